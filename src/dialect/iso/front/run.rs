//! The run: the program's lines in the order LinuxCNC runs them (O-word jumps, calls into
//! other files), its `%` and end, and what the structure check found up front.

use super::super::control;
use super::macros::{Jump, LOOP_LIMIT};
use super::{FrontEnd, Options};
use crate::diag::{Diagnostic, codes};
use crate::dialect::read::{Keep, Reader};
use crate::ir::{ItemKind, Program};
use crate::source::SourceFile;

/// [`parse`], keeping the program or only the diagnostics.
pub(crate) fn read(src: &SourceFile, options: &Options, keep: Keep) -> (Program, Vec<Diagnostic>) {
    let mut fe = FrontEnd {
        r: Reader::new(src, super::super::ID, keep),
        options,
        motion: None,
        diameter: None,
        diameter_before_line: false,
        inch: false,
        incremental: false,
        surface_speed: false,
        surface: (None, false),
        compensation: false,
        exact: (None, None),
        exact_target: (None, None),
        absolute_centres: false,
        feed: None,
        feed_mode: None,
        speed: None,
        turning: None,
        selected_tool: None,
        sync_end: None,
        in_cut: None,
        warned_rounding: false,
        warned_radius: false,
        ended: false,
        skipped_lines: 0,
        stopped: false,
        mist: false,
        flood: false,
        work_offset: 1,
        ccomp: 400.0,
        not_lathe_reported: false,
        contour: None,
        plane_xy: false,
        retract_old_z: false,
        drill: super::drilling::DrillState::default(),
        motion_before_line: None,
        z_program: None,
        cycle_call: None,
        axis_offset: (0.0, 0.0),
        offset_params: [0.0; 3],
        saved_offset: (0.0, 0.0),
        offsets_set: false,
    };
    // LinuxCNC: a program whose first non-blank line is a bare `%` ends at the next bare `%`;
    // a `%` anywhere else is refused; M2/M30 end the program. Nothing after the end runs.
    // **[evidence]** `Interp::open`, `Interp::read_text`, `convert_stop`.
    // Subroutines in files of their own (`o<name> call` → name.ngc on the subroutine path),
    // read before the run so that every file outlives the reader.
    let (externals, load_errors) = control::load_externals(src, &options.subroutine_path);
    let mut runs: Vec<control::FileRun<'_>> = Vec::with_capacity(1 + externals.len());
    runs.push(control::FileRun::new(src));
    runs.extend(externals.iter().map(control::FileRun::new));
    for (span, message) in load_errors {
        fe.r.diags.push(
            Diagnostic::new(codes::ISOR_CONTROL, message)
                .at(src, span)
                .help("check the file's permissions, or give another folder with --subroutine-path DIR"),
        );
    }
    for run in &runs {
        fe.r.src = run.src;
        for e in &run.structure.errors {
            fe.diag(
                codes::ISOR_CONTROL,
                run.lines[e.line],
                e.range.clone(),
                e.message.clone(),
                e.help,
            );
        }
    }
    fe.r.src = src;
    let broken = runs.iter().any(|r| !r.structure.errors.is_empty());
    let mut reported: Vec<Vec<bool>> = runs.iter().map(|r| vec![false; r.lines.len()]).collect();
    // An O-word line that cannot be read stops LinuxCNC wherever it stands, run or skipped
    // (it reads O-word lines while skipping), and would leave ncthread's branches to
    // guesswork: it is reported up front.
    for (f, run) in runs.iter().enumerate() {
        fe.r.src = run.src;
        for (i, line) in run.lines.iter().enumerate() {
            if run.unreadable_up_front(i) && control::looks_like_oword(line.text) {
                fe.report_unreadable(*line, &run.block(i));
                reported[f][i] = true;
            }
        }
    }
    fe.r.src = src;
    let mut params = control::Params::default();
    let mut percent = false;
    let mut first = true;
    let mut ended: Option<&'static str> = None;
    // The file running (0: the program) and its next line.
    let mut f = 0;
    let mut pc = 0;
    let mut iterations: u64 = 0;
    // An error has been reported (the program is refused).
    let mut errored = fe.r.diags.iter().any(|d| d.is_error());
    loop {
        let run = &runs[f];
        if pc >= run.lines.len() {
            if f == 0 {
                break;
            }
            // An external file ends without its `endsub`: the structure check said so.
            break;
        }
        let line = run.lines[pc];
        let here = pc;
        pc += 1;
        if run.blank[here] {
            continue;
        }
        let bare_percent = run.percent[here];
        if let Some(end) = ended {
            // A subroutine defined after the end is called from before it (LinuxCNC looks
            // ahead for it): its definition is no line after the end.
            if let Some(control::Flow::Sub { end }) = run.structure.flow.get(&here) {
                pc = end + 1;
                continue;
            }
            // A line of comments only is kept: it says something, and runs nothing.
            let block = run.block(here);
            let only_comments = matches!(&*block, Some(Ok(b)) if b.is_empty() && b.number.is_none() && !b.comments.is_empty());
            if bare_percent && percent {
                fe.push(ItemKind::Delimiter, src.line_span(line));
            } else if only_comments {
                fe.line(line, block, &mut params);
            } else {
                let span = fe.r.span(line, 0..line.text.len());
                fe.r.after_end(
                    codes::ISOR_AFTER_END,
                    span,
                    &format!("this line comes after the program's end ({end}); LinuxCNC does not run it, and neither does ncthread"),
                    "remove it, or move the program's end after it",
                );
            }
            continue;
        }
        if bare_percent && f == 0 {
            if first {
                percent = true;
                fe.push(ItemKind::Delimiter, src.line_span(line));
            } else if percent {
                fe.push(ItemKind::Delimiter, src.line_span(line));
                ended = Some("the closing `%`");
            } else {
                fe.diag(
                    codes::ISOR_SYNTAX,
                    line,
                    0..line.text.len(),
                    "LinuxCNC refuses a `%` here (\"Bad character '%' used\"): `%` is read only as the program's first line and, then, as its end".into(),
                    "remove this line, or put a `%` line first so that this one ends the program",
                );
            }
            first = false;
            continue;
        }
        first = false;
        let diags_before = fe.r.diags.len();
        // Nothing looks back past the line being read.
        fe.r.items.line_read();
        let items_before = fe.r.items.len();
        let block = run.block(here);
        let oword = match &*block {
            Some(Ok(b)) => b.oword.as_ref(),
            _ => None,
        };
        if let Some(o) = oword {
            if broken {
                // A program whose blocks do not match runs nowhere.
                fe.stopped = true;
                break;
            }
            let jump = fe.oword(here, f, o, &runs, &mut params);
            fe.name_call_chain(diags_before, &params, &runs);
            match jump {
                Ok(Jump::Next) => {}
                Ok(Jump::Here(target)) => pc = target,
                Ok(Jump::To(file, target)) => (f, pc) = (file, target),
                // LinuxCNC stops at an error. ncthread reads on to report the file's other
                // problems, but not round a loop: it would only repeat its reports, or spin
                // to the loop limit on a body an error cut short (the program is refused).
                Ok(Jump::Loop(_))
                    if errored || fe.r.diags[diags_before..].iter().any(|d| d.is_error()) =>
                {
                    fe.stopped = true;
                    break;
                }
                Ok(Jump::Loop(target)) => {
                    pc = target;
                    iterations += 1;
                    if iterations > LOOP_LIMIT {
                        fe.diag(
                            codes::ISOR_CONTROL,
                            line,
                            o.range.clone(),
                            format!("the program's loops have run {LOOP_LIMIT} times, the most ncthread follows: this loop does not end"),
                            "check the loop's condition; a program that needs more iterations must be unrolled by hand",
                        );
                        fe.name_call_chain(diags_before, &params, &runs);
                        fe.stopped = true;
                        break;
                    }
                }
                Err(e) => {
                    fe.diag(
                        codes::ISOR_CONTROL,
                        run.lines[e.line],
                        e.range,
                        e.message,
                        e.help,
                    );
                    fe.name_call_chain(diags_before, &params, &runs);
                    fe.stopped = true;
                    break;
                }
            }
            fe.r.src = runs[f].src;
            // A roughing cycle's contour subroutine has returned: the cycle runs.
            if fe
                .contour
                .as_ref()
                .is_some_and(|c| params.frames.len() <= c.level)
            {
                let before = fe.r.diags.len();
                fe.finish_contour();
                fe.name_call_chain(before, &params, &runs);
                if fe.r.diags[before..].iter().any(|d| d.is_error()) {
                    fe.stopped = true;
                    break;
                }
            }
            continue;
        }
        if !reported[f][here] {
            fe.report_unreadable(line, &block);
        }
        reported[f][here] = true;
        fe.line(line, block, &mut params);
        // A G70–G72 line calls its contour subroutine, as `o<Q> call` there would.
        if let Some(call) = fe.cycle_call.take() {
            let level = params.frames.len();
            if let Some(c) = &mut fe.contour {
                c.level = level;
            }
            match fe.oword(here, f, &call, &runs, &mut params) {
                Ok(Jump::To(file, target)) => {
                    (f, pc) = (file, target);
                    fe.r.src = runs[f].src;
                }
                Ok(_) => {}
                Err(e) => {
                    fe.contour = None;
                    fe.diag(codes::ISOR_CONTROL, line, e.range, e.message, e.help);
                    fe.name_call_chain(diags_before, &params, &runs);
                    fe.stopped = true;
                    break;
                }
            }
            continue;
        }
        fe.name_call_chain(diags_before, &params, &runs);
        errored |= fe.r.diags[diags_before..].iter().any(|d| d.is_error());
        if f != 0 {
            // The items of a subroutine in another file stand at the call in the program.
            let call = params
                .program_call_line()
                .map(|l| src.line_span(runs[0].lines[l]));
            if let Some(span) = call {
                for item in &mut fe.r.items[items_before..] {
                    item.span = span;
                }
            }
        }
        if fe.ended {
            ended = Some("M2/M30");
            if !params.frames.is_empty() {
                // M2/M30 inside a subroutine ends the whole program.
                break;
            }
        }
        if fe.stopped {
            break;
        }
    }
    fe.r.src = src;
    if let Some(c) = fe.contour.take()
        && !fe.stopped
    {
        fe.r.diags.push(
            Diagnostic::new(
                codes::ISOR_ROUGHING,
                format!("the contour subroutine {} of this cycle does not return before the program ends", c.label()),
            )
            .at(src, c.span())
            .help("end the contour's subroutine with `endsub` (or `return`)"),
        );
    }
    // A file of definitions only runs nothing, and is not refused for lacking an end.
    let library = runs[0].library().unwrap_or_default();
    // A run that an error stopped says so already.
    if ended.is_none() && !fe.stopped && !fe.r.items.is_empty() && library.is_empty() {
        let last = src.lines().filter(|l| !l.text.trim().is_empty()).last();
        if let Some(line) = last {
            fe.diag(
                codes::ISOR_NO_END,
                line,
                0..line.text.len(),
                if percent {
                    "the program starts with `%` and has no closing `%` or M2/M30: LinuxCNC runs it, then stops with \"File ended with no percent sign\"".into()
                } else {
                    "the program ends without M2/M30: LinuxCNC runs it, then stops with \"File ended with no percent sign or program end\"".into()
                },
                "end the program with M2 or M30 (or a closing `%` after a first line `%`)",
            );
        }
    }
    let (mut program, diags) = fe.r.finish();
    program.library = library;
    (program, diags)
}

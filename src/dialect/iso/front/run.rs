//! The run: the program's lines in the order LinuxCNC runs them (O-word jumps, calls into
//! other files), its `%` and end, and what the structure check found up front.
//!
//! LinuxCNC: a program whose first non-blank line is a bare `%` ends at the next bare `%`;
//! a `%` anywhere else is refused; M2/M30 end the program. Nothing after the end runs.
//! **[evidence]** `Interp::open`, `Interp::read_text`, `convert_stop`.

use std::ops::ControlFlow;

use super::super::control::{self, FileRun};
use super::super::syntax::{self, Keyword, Label, OWord};
use super::macros::{Jump, LOOP_LIMIT};
use super::{FrontEnd, Options};
use crate::diag::Diagnostic;
use crate::dialect::iso::codes;
use crate::dialect::read::{Keep, Reader};
use crate::ir::{ItemKind, Program};
use crate::source::{Line, SourceFile, Span};

/// [`parse`](super::parse), keeping the program or only the diagnostics.
pub(crate) fn read(src: &SourceFile, options: &Options, keep: Keep) -> (Program, Vec<Diagnostic>) {
    // A conversion's output read back beside its writer: read as it comes, unless a line
    // may hold an O-word (then once it has ended, as any other file).
    if matches!(keep, Keep::Diagnostics)
        && !src.text.is_complete()
        && let Some(read) = read_following(src, options)
    {
        return read;
    }
    let mut fe = FrontEnd::new(src, options, keep);
    // Subroutines in files of their own (`o<name> call` → name.ngc on the subroutine path),
    // read before the run so that every file outlives the reader.
    let (externals, load_errors) = control::load_externals(src, &options.subroutine_path);
    let mut runs: Vec<FileRun<'_>> = Vec::with_capacity(1 + externals.len());
    runs.push(FileRun::new(src));
    runs.extend(externals.iter().map(FileRun::new));
    let reported = fe.report_up_front(src, &runs, load_errors);
    let mut st = Run::new(
        reported,
        runs.iter().any(|r| !r.structure.errors.is_empty()),
    );
    st.errored = fe.r.diags.has_errors();
    fe.run(src, &runs, &mut st);
    fe.finish_run(src, &runs, &st)
}

/// [`read`] of a text still being written, its diagnostics only, each line read as it comes
/// ([`FileRun::following`]): what [`read`] finds once the text has ended, for a text in which
/// no line may hold an O-word (so no structure, no subroutine file, no look ahead). `None`
/// when a line may hold one, or a roughing cycle calls its contour subroutine (the run gives
/// up there), or the run stopped before the text's end (an error: the lines after it are
/// not looked at, and an O-word there would be reported up front): the reading is thrown
/// away.
fn read_following(src: &SourceFile, options: &Options) -> Option<(Program, Vec<Diagnostic>)> {
    let mut fe = FrontEnd::new(src, options, Keep::Diagnostics);
    let runs = [FileRun::following(src)];
    let mut st = Run::new(vec![control::LineSet::new(0)], false);
    fe.run(src, &runs, &mut st);
    if st.given_up || !runs[0].followed_to_end() {
        return None;
    }
    #[cfg(test)]
    FOLLOWED.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    Some(fe.finish_run(src, &runs, &st))
}

/// How many reads [`read_following`] answered (for the tests that it does).
#[cfg(test)]
pub(crate) static FOLLOWED: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);

/// Where the run stands.
struct Run {
    /// The file running (0: the program) and its next line.
    f: usize,
    pc: usize,
    /// The loops' iterations so far.
    iterations: u64,
    /// An error has been reported (the program is refused).
    errored: bool,
    /// The program's first line is a bare `%`.
    percent: bool,
    /// No line has run yet.
    first: bool,
    /// What ended the program.
    ended: Option<&'static str>,
    params: control::Params,
    /// The lines whose syntax errors are reported, per file.
    reported: Vec<control::LineSet>,
    /// A program whose blocks do not match runs nowhere.
    broken: bool,
    /// A run of a text still being written met what it cannot read as it comes: an O-word,
    /// or a call of a contour subroutine ([`read_following`]).
    given_up: bool,
}

impl Run {
    /// Before the program's first line: the lines `reported` up front, the structure
    /// `broken` or not.
    fn new(reported: Vec<control::LineSet>, broken: bool) -> Run {
        Run {
            f: 0,
            pc: 0,
            iterations: 0,
            errored: false,
            percent: false,
            first: true,
            ended: None,
            params: control::Params::default(),
            reported,
            broken,
            given_up: false,
        }
    }
}

impl<'a> FrontEnd<'a> {
    /// The reader before the program's first line: LinuxCNC's start-up modes.
    fn new<'k: 'a>(src: &'a SourceFile, options: &'a Options, keep: Keep<'k>) -> Self {
        FrontEnd {
            spare_words: Vec::new(),
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
            comp: Default::default(),
            exact: (None, None),
            exact_target: (None, None),
            absolute_centres: false,
            feed: None,
            feed_inch: false,
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
        }
    }

    /// Reports what is wrong before the run: the subroutine files that cannot be read, the
    /// O-word structure's errors, and an O-word line that cannot be read (it stops LinuxCNC
    /// wherever it stands, run or skipped, since it reads O-word lines while skipping, and
    /// would leave ncthread's branches to guesswork). The lines so reported, per file.
    fn report_up_front(
        &mut self,
        src: &'a SourceFile,
        runs: &[FileRun<'a>],
        load_errors: Vec<(Span, String)>,
    ) -> Vec<control::LineSet> {
        for (span, message) in load_errors {
            self.r.diags.push(
                Diagnostic::new(codes::ISOR_CONTROL, message)
                    .at(src, span)
                    .help("check the file's permissions, or give another folder with --subroutine-path DIR"),
            );
        }
        for run in runs {
            self.r.src = run.src;
            for e in &run.structure.errors {
                self.diag(
                    codes::ISOR_CONTROL,
                    run.line(e.line),
                    e.range.clone(),
                    e.message.clone(),
                    e.help,
                );
            }
        }
        self.r.src = src;
        let mut reported: Vec<control::LineSet> = runs
            .iter()
            .map(|r| control::LineSet::new(r.lines_up_front()))
            .collect();
        for (f, run) in runs.iter().enumerate() {
            self.r.src = run.src;
            for i in run.unreadable_up_front() {
                let line = run.line(i);
                if control::looks_like_oword(line.text) {
                    self.report_unreadable(line, &run.block(i));
                    reported[f].insert(i);
                }
            }
        }
        self.r.src = src;
        reported
    }

    /// Runs the lines until the program ends, an error stops it, or the lines run out.
    fn run(&mut self, src: &'a SourceFile, runs: &[FileRun<'a>], st: &mut Run) {
        loop {
            let run = &runs[st.f];
            let Some(line) = run.get_line(st.pc) else {
                // The program's last line; or an external file ends without its `endsub`:
                // the structure check said so.
                break;
            };
            if run.is_following() && control::may_hold_oword(line.text) {
                st.given_up = true;
                break;
            }
            let here = st.pc;
            st.pc += 1;
            if control::is_blank(line.text) {
                continue;
            }
            if let Some(end) = st.ended {
                self.line_after_end(src, run, st, here, end);
                continue;
            }
            if control::is_percent(line.text) && st.f == 0 {
                self.percent_line(src, line, st);
                continue;
            }
            st.first = false;
            if self.run_line(src, runs, st, here, line).is_break() {
                break;
            }
        }
    }

    /// A line after the program's end: a subroutine's definition is skipped, a closing `%`
    /// and a line of comments only are kept, any other line is reported.
    fn line_after_end(
        &mut self,
        src: &'a SourceFile,
        run: &FileRun<'a>,
        st: &mut Run,
        here: usize,
        end: &str,
    ) {
        let line = run.line(here);
        // A subroutine defined after the end is called from before it (LinuxCNC looks
        // ahead for it): its definition is no line after the end.
        if let Some(control::Flow::Sub { end }) = run.structure.flow.get(&here) {
            st.pc = end + 1;
            return;
        }
        // A line of comments only is kept: it says something, and runs nothing.
        let block = run.block(here);
        let only_comments = matches!(&*block, Some(Ok(b)) if b.is_empty() && b.number.is_none() && !b.comments.is_empty());
        if run.percent(here) && st.percent {
            self.push(ItemKind::Delimiter, src.line_span(line));
        } else if only_comments {
            self.line(line, block, &mut st.params);
        } else {
            let span = self.r.span(line, 0..line.text.len());
            self.r.after_end(
                codes::ISOR_AFTER_END,
                span,
                &format!("this line comes after the program's end ({end}); LinuxCNC does not run it, and neither does ncthread"),
                "remove it, or move the program's end after it",
            );
        }
    }

    /// A bare `%` line of the program: its first line opens it, the next one closes it.
    fn percent_line(&mut self, src: &'a SourceFile, line: Line<'_>, st: &mut Run) {
        if st.first {
            st.percent = true;
            self.push(ItemKind::Delimiter, src.line_span(line));
        } else if st.percent {
            self.push(ItemKind::Delimiter, src.line_span(line));
            st.ended = Some("the closing `%`");
        } else {
            self.diag(
                codes::ISOR_SYNTAX,
                line,
                0..line.text.len(),
                "LinuxCNC refuses a `%` here (\"Bad character '%' used\"): `%` is read only as the program's first line and, then, as its end".into(),
                "remove this line, or put a `%` line first so that this one ends the program",
            );
        }
        st.first = false;
    }

    /// Runs line `here` of the file running: an O-word, or a line of words (which may call
    /// a roughing cycle's contour). Breaks when the run stops.
    fn run_line(
        &mut self,
        src: &'a SourceFile,
        runs: &[FileRun<'a>],
        st: &mut Run,
        here: usize,
        line: Line<'a>,
    ) -> ControlFlow<()> {
        let run = &runs[st.f];
        let diags_before = self.r.diags.len();
        // Nothing looks back past the line being read.
        self.r.line_read();
        let items_before = self.r.items.len();
        let block = run.block_of(here, line, &mut self.spare_words);
        let oword = match &*block {
            Some(Ok(b)) => b.oword.as_deref(),
            _ => None,
        };
        if let Some(o) = oword {
            return self.run_oword(runs, st, here, o, diags_before);
        }
        if !st.reported[st.f].contains(here) {
            self.report_unreadable(line, &block);
        }
        st.reported[st.f].insert(here);
        self.line(line, block, &mut st.params);
        // A G70–G72 line calls its contour subroutine, as `o<Q> call` there would.
        if let Some(call) = self.cycle_call.take() {
            if run.is_following() {
                // Its subroutine may be defined further on.
                st.given_up = true;
                return ControlFlow::Break(());
            }
            if self.stop_beside_cycle(items_before) {
                self.contour = None;
                self.stopped = true;
                return ControlFlow::Break(());
            }
            return self.call_contour(runs, st, here, &call, diags_before);
        }
        self.name_call_chain(diags_before, &st.params, runs);
        st.errored |= self.r.diags[diags_before..].iter().any(|d| d.is_error());
        if st.f != 0 {
            // The items of a subroutine in another file stand at the call in the program.
            let call = st
                .params
                .program_call_line()
                .map(|l| src.line_span(runs[0].line(l)));
            if let Some(span) = call {
                for item in &mut self.r.items[items_before..] {
                    item.span = span;
                }
            }
        }
        if self.ended {
            st.ended = Some("M2/M30");
            if !st.params.frames.is_empty() {
                // M2/M30 inside a subroutine ends the whole program.
                return ControlFlow::Break(());
            }
        }
        if self.stopped {
            return ControlFlow::Break(());
        }
        ControlFlow::Continue(())
    }

    /// An O-word line: the jump it makes, then a roughing cycle whose contour subroutine has
    /// returned. Breaks when the run stops.
    fn run_oword(
        &mut self,
        runs: &[FileRun<'a>],
        st: &mut Run,
        here: usize,
        o: &OWord,
        diags_before: usize,
    ) -> ControlFlow<()> {
        let run = &runs[st.f];
        if st.broken {
            // A program whose blocks do not match runs nowhere.
            self.stopped = true;
            return ControlFlow::Break(());
        }
        let jump = self.oword(here, st.f, o, runs, &mut st.params);
        self.name_call_chain(diags_before, &st.params, runs);
        match jump {
            Ok(Jump::Next) => {}
            Ok(Jump::Here(target)) => {
                if self.read_skipped(runs, st, here + 1..target, o).is_break() {
                    self.stopped = true;
                    return ControlFlow::Break(());
                }
                st.pc = target;
            }
            Ok(Jump::To(file, target)) => (st.f, st.pc) = (file, target),
            // LinuxCNC stops at an error. ncthread reads on to report the file's other
            // problems, but not round a loop: it would only repeat its reports, or spin
            // to the loop limit on a body an error cut short (the program is refused).
            Ok(Jump::Loop(_))
                if st.errored || self.r.diags[diags_before..].iter().any(|d| d.is_error()) =>
            {
                self.stopped = true;
                return ControlFlow::Break(());
            }
            Ok(Jump::Loop(target)) => {
                st.pc = target;
                st.iterations += 1;
                if st.iterations > LOOP_LIMIT {
                    return self.endless_loop(runs, st, run.line(here), o, diags_before);
                }
            }
            Err(e) => {
                self.diag(
                    codes::ISOR_CONTROL,
                    run.line(e.line),
                    e.range,
                    e.message,
                    e.help,
                );
                self.name_call_chain(diags_before, &st.params, runs);
                self.stopped = true;
                return ControlFlow::Break(());
            }
        }
        self.r.src = runs[st.f].src;
        // A roughing cycle's contour subroutine has returned: the cycle runs.
        if self
            .contour
            .as_ref()
            .is_some_and(|c| st.params.frames.len() <= c.level)
        {
            let before = self.r.diags.len();
            self.finish_contour();
            self.name_call_chain(before, &st.params, runs);
            if self.r.diags[before..].iter().any(|d| d.is_error()) {
                self.stopped = true;
                return ControlFlow::Break(());
            }
        }
        ControlFlow::Continue(())
    }

    /// The lines control skips from an O-word line (a definition passed, a branch not
    /// taken, a loop left): LinuxCNC reads each before it skips it, so it stops at a comment
    /// it cannot read (`close_and_downcase`) and at the program's closing `%`, which ends
    /// the file while it is still looking for the label ("Failed to find sub 'O…' before
    /// EOF"). Breaks at such a line, reported. **\[evidence\]** LinuxCNC
    /// `interp_read.cc` (`read_text`), `rs274ngc_pre.cc` (`_read`).
    fn read_skipped(
        &mut self,
        runs: &[FileRun<'a>],
        st: &Run,
        lines: std::ops::Range<usize>,
        o: &OWord,
    ) -> ControlFlow<()> {
        let run = &runs[st.f];
        for i in lines {
            let Some(line) = run.get_line(i) else { break };
            if st.reported[st.f].contains(i) {
                continue;
            }
            let found = [
                (
                    syntax::too_long(line.text),
                    "split the line: LinuxCNC reads 252 bytes of it",
                ),
                (
                    syntax::comment_error(line.text),
                    "close each comment on its line, with no `(` inside it",
                ),
                (
                    syntax::skipped_label_error(line.text),
                    "give the O-word its number or <name> (a NUL byte ends the line for LinuxCNC)",
                ),
            ]
            .into_iter()
            .find_map(|(e, help)| e.map(|e| (e, help)));
            if let Some((e, help)) = found {
                self.r.syntax_error(
                    codes::ISOR_SYNTAX,
                    line,
                    e.offset,
                    format!(
                        "{}, though the line is skipped: LinuxCNC reads every line it passes",
                        e.message
                    ),
                    help,
                );
                return ControlFlow::Break(());
            }
            if st.f == 0 && st.percent && run.percent(i) {
                self.diag(
                    codes::ISOR_CONTROL,
                    line,
                    0..line.text.len(),
                    format!(
                        "the program's closing `%` while LinuxCNC skips from {} {} to the next line of {0}: it stops (\"Failed to find sub 'O{}' before EOF\")",
                        o.label,
                        o.keyword.name(),
                        linuxcnc_name(o, &st.params)
                    ),
                    "end the block (its `endsub`, `endif`, `endwhile` …) before the closing `%`",
                );
                return ControlFlow::Break(());
            }
        }
        ControlFlow::Continue(())
    }

    /// The loops have gone round [`LOOP_LIMIT`] times: the run stops at this loop.
    fn endless_loop(
        &mut self,
        runs: &[FileRun<'a>],
        st: &Run,
        line: Line<'_>,
        o: &OWord,
        diags_before: usize,
    ) -> ControlFlow<()> {
        self.diag(
            codes::ISOR_CONTROL,
            line,
            o.range.clone(),
            format!("the program's loops have run {LOOP_LIMIT} times, the most ncthread follows: this loop does not end"),
            "check the loop's condition; a program that needs more iterations must be unrolled by hand",
        );
        self.name_call_chain(diags_before, &st.params, runs);
        self.stopped = true;
        ControlFlow::Break(())
    }

    /// The call of a roughing cycle's contour subroutine that a G70–G72 line asked for.
    /// Breaks when the call fails.
    fn call_contour(
        &mut self,
        runs: &[FileRun<'a>],
        st: &mut Run,
        here: usize,
        call: &OWord,
        diags_before: usize,
    ) -> ControlFlow<()> {
        let line = runs[st.f].line(here);
        let level = st.params.frames.len();
        if let Some(c) = &mut self.contour {
            c.level = level;
        }
        match self.oword(here, st.f, call, runs, &mut st.params) {
            Ok(Jump::To(file, target)) => {
                (st.f, st.pc) = (file, target);
                self.r.src = runs[st.f].src;
            }
            Ok(_) => {}
            Err(e) => {
                self.contour = None;
                self.diag(codes::ISOR_CONTROL, line, e.range, e.message, e.help);
                self.name_call_chain(diags_before, &st.params, runs);
                self.stopped = true;
                return ControlFlow::Break(());
            }
        }
        ControlFlow::Continue(())
    }

    /// M0, M1, M2 or M30 on the line of a roughing cycle whose contour is a subroutine:
    /// LinuxCNC stops after the cycle, ncthread's items would stand before its moves; refused
    /// (a real program stops on a line of its own). `true` after the refusal.
    fn stop_beside_cycle(&mut self, items_before: usize) -> bool {
        let stop = self.r.items[items_before..]
            .iter()
            .find(|i| matches!(i.kind, ItemKind::Stop { .. } | ItemKind::ProgramEnd(_)));
        let Some(stop) = stop else {
            return false;
        };
        let span = stop.span;
        self.r.diags.push(
            Diagnostic::new(
                codes::ISOR_CONFLICT,
                "a stop or the program's end (M0, M1, M2, M30) on the line of a roughing cycle: LinuxCNC stops after the cycle's cuts, which ncthread does not read on one line",
            )
            .at(self.r.src, span)
            .help("put M0/M1/M2/M30 on a line of its own after the cycle"),
        );
        true
    }

    /// After the run: a contour subroutine that never returned, a program without its end
    /// (a file of definitions only runs nothing, and is not refused for lacking one), and
    /// the program with its library of subroutines.
    fn finish_run(
        mut self,
        src: &'a SourceFile,
        runs: &[FileRun<'a>],
        st: &Run,
    ) -> (Program, Vec<Diagnostic>) {
        self.r.src = src;
        if let Some(c) = self.contour.take()
            && !self.stopped
        {
            self.r.diags.push(
                Diagnostic::new(
                    codes::ISOR_ROUGHING,
                    format!("the contour subroutine {} of this cycle does not return before the program ends", c.label()),
                )
                .at(src, c.span())
                .help("end the contour's subroutine with `endsub` (or `return`)"),
            );
        }
        let library = runs[0].library().unwrap_or_default();
        // A run that an error stopped says so already.
        if st.ended.is_none() && !self.stopped && !self.r.items.is_empty() && library.is_empty() {
            self.no_end(src, st.percent);
        }
        let (mut program, diags) = self.r.finish();
        program.library = library;
        (program, diags)
    }

    /// The program has no end: LinuxCNC runs it, then stops with an error.
    fn no_end(&mut self, src: &'a SourceFile, percent: bool) {
        let Some(line) = src.lines().filter(|l| !l.is_blank()).last() else {
            return;
        };
        self.diag(
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

/// The name LinuxCNC's `read_o` gives an O-word's label (its `skipping_o`): a subroutine's
/// (`sub`, `endsub`, `call`, `return`) is the label itself, `100` or `name`; any other is
/// local, after the subroutine's running and a `#`.
fn linuxcnc_name(o: &OWord, params: &crate::dialect::iso::control::Params) -> String {
    let bare = |l: &Label| match l {
        Label::Number(n) | Label::Name(n) => n.clone(),
    };
    match o.keyword {
        Keyword::Sub | Keyword::EndSub | Keyword::Call | Keyword::Return => bare(&o.label),
        _ => {
            let sub = params
                .frames
                .last()
                .map(|f| bare(&f.name))
                .unwrap_or_default();
            format!("{sub}#{}", bare(&o.label))
        }
    }
}

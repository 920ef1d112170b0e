//! The iso front end: RS274/NGC lines as LinuxCNC reads them → IR items.
//!
//! It reads what ncthread writes and what a programmer writes by hand for a LinuxCNC lathe:
//! G0/G1/G33/G33.1/G76, G4, G7/G8, G18, G20/G21, G90/G91, G94/G95, S/M3/M4/M5, T/M6, G43,
//! M2/M30, comments and `%` lines; the drilling cycles G73, G81–G83, G85, G89 (with G80,
//! G98/G99) in G17 as their moves (`front/drilling.rs`). Words that change nothing ncthread models (coolant,
//! path control, the default work offset…) are kept as opaque words for ISO output.
//! Everything else — arcs, other planes and axes, work offsets, parameters, subroutines —
//! is named as unsupported. Within a line the commands run in LinuxCNC's order.

use std::ops::Range;

use super::control;
use super::gcode::*;
use super::syntax::{self, BLOCK_DELETE, Block, Word};
use crate::diag::{Code, Diagnostic, codes};
use crate::dialect::read::{Keep, Reader, UnsupportedWording};
use crate::dialect::{Letters, Unsupported, WORD_REPORTS, budget};
use crate::fixed::{Angle, Decimal, Lead, Length, div_round};
use crate::ir::{
    Compensation, Coolant, CycleChamfer, Degression, EndCode, FeedMode, Finish, IjkScale, ItemKind,
    MachineMove, ModalContext, Pos, Program, Retract, Rise, Schedule, Slope, SpindleDirection,
    SpindleMode, SyncInfeed, SyncStart, TapCycle, ThreadCycle, ThreadPass,
};
use crate::lower;
use crate::profile::BlockDelete;
use crate::source::{Line, SourceFile, Span};

/// How the ISO reader words its unsupported policy.
const UNSUPPORTED: UnsupportedWording = UnsupportedWording {
    code: codes::ISOR_UNSUPPORTED,
    more: "on this line",
    in_one: "on a line",
    many: "lines",
    own_block: "put this word on a line of its own",
    refuse_help: "ncthread reads lathe thread programs in X and Z; rewrite this line, or pass --unsupported warn to keep it opaque",
    keep_help: "kept as an opaque block: only ISO output writes it back, and positions after it are unknown",
};

#[derive(Clone, Debug, Default)]
pub struct Options {
    pub unsupported: Unsupported,
    /// Folders that hold subroutine files (`o<name> call` → `name.ngc`), LinuxCNC's
    /// `SUBROUTINE_PATH`.
    pub subroutine_path: Vec<std::path::PathBuf>,
    /// The block delete switch (profile `[iso] block_delete`, `--block-delete`).
    pub block_delete: Option<BlockDelete>,
}

/// The modal motion (LinuxCNC's group 1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Motion {
    Rapid,
    Feed,
    /// G2 (clockwise) or G3.
    Arc {
        clockwise: bool,
    },
    Thread,
    Tap,
    Cycle,
    /// G70–G72 (the code).
    Roughing(GCode),
    /// A drilling cycle: G73, G81, G82, G83, G85 or G89 (the code).
    Drill(GCode),
    /// G80: no motion mode (axis words are refused until a motion code).
    CycleOff,
}

/// A Z in the program's units and coordinates as LinuxCNC computed it, recorded with the
/// exact position in mm it stands for and the units and Z offset it was in.
#[derive(Clone, Copy, Debug)]
struct ProgramZ {
    mm: f64,
    value: f64,
    inch: bool,
    offset: f64,
}

/// The denominator of the slope that stands for tan(Q) of a G76.
const SLOPE_RUN: i64 = 1_000_000_000;

struct FrontEnd<'a> {
    r: Reader<'a>,
    options: &'a Options,
    motion: Option<Motion>,
    /// G7 (true) or G8 (false); `None` until one is programmed (LinuxCNC then reads radii).
    diameter: Option<bool>,
    /// The diameter mode before the current line's G7/G8 (a G76 scales I, J, K by both).
    diameter_before_line: bool,
    inch: bool,
    incremental: bool,
    /// G96 in force (S is a surface speed).
    surface_speed: bool,
    /// The surface speed's limit (G96's D) and whether its S is in ft/min.
    surface: (Option<Decimal>, bool),
    /// Cutter radius compensation is on (G41/G42 and their `.1`, until G40).
    compensation: bool,
    /// The position as written (mm, X a diameter), before it was rounded onto the grid:
    /// incremental moves add to it and arcs are computed from it, so that a value is rounded
    /// once, as LinuxCNC computes in doubles. An axis that does not round to the known
    /// position is stale (a move that did not set it) and not used.
    exact: (Option<f64>, Option<f64>),
    /// The exact target of the line's X and Z words, as `target` read them.
    exact_target: (Option<f64>, Option<f64>),
    /// G90.1: I and K give the arc centre itself; G91.1 (LinuxCNC's start-up mode): its
    /// offset from the arc's start.
    absolute_centres: bool,
    feed: Option<Length>,
    /// `None` until the program sets one: LinuxCNC then feeds per minute (G94).
    feed_mode: Option<FeedMode>,
    speed: Option<u32>,
    turning: Option<SpindleDirection>,
    selected_tool: Option<u32>,
    /// Where the last G33 ended, while nothing but comments followed it (a G33 there
    /// continues it).
    sync_end: Option<Pos>,
    /// Where the last synchronised move ended, while no other motion followed it.
    in_cut: Option<Pos>,
    warned_rounding: bool,
    warned_radius: bool,
    /// M2 or M30 has ended the program.
    ended: bool,
    /// Lines skipped because they start with `/` and the block delete switch is on.
    skipped_lines: usize,
    /// An error that ends the run (LinuxCNC stops there): nothing after it is read.
    stopped: bool,
    /// Coolant as M7/M8/M9 left it, and the work offset (1: G54): M72 restores them.
    mist: bool,
    flood: bool,
    work_offset: u8,
    /// `#<_ccomp>`: 400, 410 or 420.
    ccomp: f64,
    /// G17 in force (the XY plane): lines along X and Z mean what they mean in G18, but an
    /// arc, a G7x cycle and cutter compensation would work in XY.
    plane_xy: bool,
    /// G98 (true: canned cycles retract to the initial level) or G99 (to R, LinuxCNC's
    /// start-up mode).
    retract_old_z: bool,
    /// The drilling cycles' modal values.
    drill: drilling::DrillState,
    /// The motion mode before the current line's motion code.
    motion_before_line: Option<Motion>,
    /// The last Z recorded as LinuxCNC holds it.
    z_program: Option<ProgramZ>,
    /// A line was refused as not a lathe program (ISOR021): the later ones are skipped
    /// unreported, since the program is refused whole.
    not_lathe_reported: bool,
    /// A G70–G72 whose contour subroutine is running.
    contour: Option<Box<roughing::Contour>>,
    /// The call of a contour subroutine that a G70–G72 line asks the run to make.
    cycle_call: Option<syntax::OWord>,
    /// The G52/G92 offset in force (mm, X a diameter): a position the program writes is this
    /// much nearer the work zero than the IR's, which holds where the tool goes.
    axis_offset: (f64, f64),
    /// #5210, #5211, #5213 as the line before left them; the line's G52/G92 family sets
    /// #5210 again.
    offset_params: [f64; 3],
    /// The offset G92.3 restores (the last G52/G92's, until G92.1).
    saved_offset: (f64, f64),
    /// The program has set the offset (G52, G92, G92.1): #5210–#5219 are known.
    offsets_set: bool,
}

mod drilling;
mod macros;
mod offsets;
mod roughing;

use macros::{Jump, LOOP_LIMIT};

/// Reads an RS274/NGC program. The program is usable only when no diagnostic is an error.
pub fn parse(src: &SourceFile, options: &Options) -> (Program, Vec<Diagnostic>) {
    read(src, options, Keep::Program)
}

/// [`parse`], keeping the program or only the diagnostics.
pub(crate) fn read(src: &SourceFile, options: &Options, keep: Keep) -> (Program, Vec<Diagnostic>) {
    let mut fe = FrontEnd {
        r: Reader::new(src, super::ID, keep),
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
        drill: drilling::DrillState::default(),
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

/// The words of one line, sorted by what reads them.
struct Words<'b> {
    /// G codes ×10 (`G33.1` → 331) with their words.
    g: Vec<(GCode, &'b Word)>,
    /// M codes with their words.
    m: Vec<(i64, &'b Word)>,
    /// Every other word by letter (each letter once).
    other: Letters<&'b Word>,
    /// Letters a command has read.
    used: Vec<char>,
}

/// A block's copy that its words' values are evaluated into (without its expressions,
/// settings and O-word, which stay in the block read).
fn evaluated_copy(source: &Block) -> Block {
    Block {
        number: source.number,
        words: source.words.clone(),
        exprs: Vec::new(),
        settings: Vec::new(),
        oword: None,
        comments: source.comments.clone(),
        unread: source.unread.clone(),
        delimiter: source.delimiter,
    }
}

impl<'b> Words<'b> {
    fn take(&mut self, letter: char) -> Option<&'b Word> {
        let w = self.other.get(&letter).copied()?;
        self.used.push(letter);
        Some(w)
    }

    fn has_g(&self, code: GCode) -> Option<&'b Word> {
        self.g.iter().find(|(c, _)| *c == code).map(|(_, w)| *w)
    }

    fn has_m(&self, code: i64) -> Option<&'b Word> {
        self.m.iter().find(|(c, _)| *c == code).map(|(_, w)| *w)
    }
}

/// The motion codes ncthread reads (LinuxCNC's modal group 1, less the tapping and boring
/// cycles, and G80: LinuxCNC lets G80 share a line with another of them, which wins).
const MOTION: [GCode; 20] = [
    G0, G1, G2, G3, G33, G33_1, G76, G70, G71, G71_1, G71_2, G72, G72_1, G72_2, G73, G81, G82, G83,
    G85, G89,
];

/// What a G or M code is to ncthread.
enum Meaning {
    /// Read and modelled.
    Known,
    /// Changes nothing ncthread models: kept as an opaque word for ISO output.
    Kept,
    /// Not read: the reason.
    Unsupported(&'static str),
}

/// The G codes the reader reads, as written (for "did you mean").
const KNOWN_G: &[&str] = &[
    "G0", "G1", "G2", "G3", "G4", "G7", "G8", "G18", "G20", "G21", "G28", "G30", "G33", "G33.1",
    "G40", "G41", "G42", "G41.1", "G42.1", "G43", "G52", "G53", "G54", "G55", "G56", "G57", "G58",
    "G59", "G70", "G71", "G72", "G73", "G76", "G80", "G81", "G82", "G83", "G85", "G89", "G90",
    "G91", "G92", "G94", "G95", "G96", "G97", "G98", "G99",
];

fn g_meaning(code: GCode) -> Meaning {
    match code {
        G0 | G1 | G2 | G3 | G33 | G33_1 | G76 | G4 | G7 | G8 | G17 | G18 | G20 | G21 | G43
        | G90 | G91 | G90_1 | G91_1 | G94 | G95 | G96 | G97 | G40 | G41 | G42 | G41_1 | G42_1
        | G54 | G55 | G56 | G57 | G58 | G59 | G59_1 | G59_2 | G59_3 | G28 | G28_1 | G30 | G30_1
        | G53 | G52 | G92 | G92_1 | G92_2 | G92_3 | G70 | G71 | G71_1 | G71_2 | G72 | G72_1
        | G72_2 | G73 | G80 | G81 | G82 | G83 | G85 | G89 | G98 | G99 => Meaning::Known,
        // Tool length offset off, exact path / blending.
        G49 | G61 | G61_1 | G64 => Meaning::Kept,
        // Refused in every mode by `not_a_lathe_program`.
        G19 | G17_1 | G18_1 | G19_1 => {
            Meaning::Unsupported("another plane than ZX (G18) or XY (G17): not a lathe program")
        }
        G10 => Meaning::Unsupported("changes of the coordinate systems (G10)"),
        G93 => Meaning::Unsupported("inverse-time feed (G93)"),
        G74 | G84 | G86 | G87 | G88 => Meaning::Unsupported(
            "tapping and boring cycles that stop or reverse the spindle (G74, G84, G86, G87, G88)",
        ),
        _ => Meaning::Unsupported("this G code"),
    }
}

/// Whether a word changes modal state that ncthread follows (units, distance, diameter and
/// feed modes, feed, speed, tool, spindle, coolant, stops, program end): such a word cannot sit on a line
/// kept opaque.
fn changes_followed_state(w: &Word) -> bool {
    match w.letter {
        'F' | 'S' | 'T' => true,
        'G' => w.value.to_scaled(1).is_ok_and(|g| {
            matches!(
                g,
                G7 | G8
                    | G20
                    | G21
                    | G90
                    | G91
                    | G90_1
                    | G91_1
                    | G93
                    | G94
                    | G95
                    | G96
                    | G97
                    | G43
                    | G49
                    | G40..=G42_1
                    | G54..=G59_3
                    | G28..=G30_1
                    | G53
                    | G52
                    | G92..=G92_3
                    | G98
                    | G99
            )
        }),
        'M' => w
            .value
            .to_whole()
            .is_ok_and(|m| matches!(m, 0..=9 | 30 | 60)),
        _ => false,
    }
}

/// Whether a line kept opaque may move the machine: an axis word (or an expression for
/// one), a code that moves or changes the coordinates, a G or M code ncthread does not know,
/// or an O-word. A line of modes and path settings (`/G64 P0.01`) cannot.
fn may_move(line: Line<'_>, block: &Block) -> bool {
    let axis = |c: char| "XYZABCUVW".contains(c.to_ascii_uppercase());
    block.unread.iter().any(|u| match u.what {
        BLOCK_DELETE | "parameter assignment" => false,
        "parameter or expression as a value" => {
            line.text[u.range.clone()].chars().next().is_none_or(axis)
        }
        _ => true,
    }) || block.words.iter().any(|w| match w.letter {
        c if axis(c) => true,
        'G' => w.value.to_scaled(1).map_or(true, |g| {
            !matches!(
                g,
                G4 | G7
                    | G8
                    | G17
                    | G18
                    | G19
                    | G17_1
                    | G18_1
                    | G19_1
                    | G20
                    | G21
                    | G40..=G42_1
                    | G43
                    | G49
                    | G54..=G59_3
                    | G61
                    | G61_1
                    | G64
                    | G80
                    | G90
                    | G91
                    | G90_1
                    | G91_1
                    | G93
                    | G94
                    | G95
                    | G96
                    | G97
                    | G98
                    | G99
            )
        }),
        'M' => w
            .value
            .to_whole()
            .map_or(true, |m| !matches!(m, 0..=5 | 7..=9)),
        _ => false,
    })
}

fn m_meaning(code: i64) -> Meaning {
    match code {
        // Stops, program end, spindle, tool change, coolant.
        0..=9 | 30 => Meaning::Known,
        // Saving and restoring the modal state: the macro runner's (`front/macros.rs`).
        70..=73 => Meaning::Known,
        _ => Meaning::Unsupported("this M code"),
    }
}

impl FrontEnd<'_> {
    fn diag(
        &mut self,
        code: Code,
        line: Line<'_>,
        range: Range<usize>,
        message: String,
        help: &str,
    ) {
        let span = self.r.span(line, range);
        self.r.error(code, span, message, help);
    }

    fn push(&mut self, kind: ItemKind, span: Span) {
        // Anything but a comment between two G33 moves ends LinuxCNC's chain; any other
        // motion takes the tool out of the cut.
        match kind {
            ItemKind::ThreadPass(_) | ItemKind::Comment(_) | ItemKind::Delimiter => {}
            // A move to where the tool already is leaves it in the cut.
            ItemKind::Rapid { .. } | ItemKind::Feed { .. }
                if kind.end_position(self.r.pos) == self.r.pos =>
            {
                self.sync_end = None;
            }
            ItemKind::Rapid { .. }
            | ItemKind::Feed { .. }
            | ItemKind::Arc { .. }
            | ItemKind::ThreadCycle(_)
            | ItemKind::TapCycle(_)
            | ItemKind::Opaque { block: Some(_), .. } => {
                self.sync_end = None;
                self.in_cut = None;
            }
            _ => self.sync_end = None,
        }
        self.r.push(kind, span, None);
    }

    /// Reports why a line cannot be read (a NUL, a syntax error).
    fn report_unreadable(
        &mut self,
        line: Line<'_>,
        parsed: &Option<Result<Block, syntax::SyntaxError>>,
    ) {
        match parsed {
            None => {
                let at = line.text.find('\0').unwrap_or(0);
                self.r.syntax_error(
                    codes::ISOR_SYNTAX,
                    line,
                    at,
                    "a NUL character: LinuxCNC reads the line only up to it",
                    "remove the NUL byte (a damaged file?)",
                );
            }
            Some(Err(e)) => {
                self.r.syntax_error(
                    codes::ISOR_SYNTAX,
                    line,
                    e.offset,
                    e.message.clone(),
                    "a line is words (a letter and a number: `G33`, `X35.6`, `K1.5`), `( )` comments and a `;` comment to its end",
                );
            }
            Some(Ok(_)) => {}
        }
    }

    /// Runs one line that is not an O-word: its values evaluated, its parameter settings
    /// made, then its words.
    fn line(
        &mut self,
        line: Line<'_>,
        parsed: std::borrow::Cow<'_, control::ReadLine>,
        params: &mut control::Params,
    ) {
        // The line's words get their values here; its expressions stay where they were read.
        // A line read for this run alone and without expressions is taken as it is.
        let (source, mut block) = match parsed {
            std::borrow::Cow::Owned(Some(Ok(block)))
                if block.exprs.is_empty() && block.settings.is_empty() =>
            {
                (
                    None,
                    Block {
                        oword: None,
                        ..block
                    },
                )
            }
            std::borrow::Cow::Owned(Some(Ok(source))) => {
                let block = evaluated_copy(&source);
                (Some(std::borrow::Cow::Owned(source)), block)
            }
            std::borrow::Cow::Borrowed(Some(Ok(source))) => (
                Some(std::borrow::Cow::Borrowed(source)),
                evaluated_copy(source),
            ),
            _ => return,
        };
        if let Some(at) = block.unread.iter().position(|u| u.what == BLOCK_DELETE) {
            match self.options.block_delete {
                // The switch is on: LinuxCNC skips the line.
                Some(BlockDelete::On) => {
                    self.skipped_lines += 1;
                    if self.skipped_lines == 1 {
                        let span = self.r.span(line, block.unread[at].range.clone());
                        self.r.diags.push(
                            Diagnostic::new(
                                codes::ISOR_BLOCK_DELETE,
                                "a line that starts with `/` is skipped: the block delete switch is on",
                            )
                            .at(self.r.src, span)
                            .label("skipped, with every line like it")
                            .help("ncthread reads the program as the machine runs it with block delete on; give --block-delete off for the other run"),
                        );
                    }
                    return;
                }
                Some(BlockDelete::Off) => {
                    block.unread.remove(at);
                }
                None => {}
            }
        }
        if let Some(source) = source
            && (!source.exprs.is_empty() || !source.settings.is_empty())
            && let Err(e) = self.evaluate(&source, &mut block.words, params)
        {
            self.diag(codes::ISOR_EVAL, line, e.range, e.message, e.help);
            self.stopped = true;
            return;
        }
        // Messages read the parameters as the line's settings leave them.
        for c in &mut block.comments {
            if let Some(text) = self.message(c, params) {
                *c = text;
            }
        }
        self.offset_params = [
            params.numbered[5210],
            params.numbered[5211],
            params.numbered[5213],
        ];
        // A line of a roughing cycle's contour: only its shape counts.
        if self.contour.is_some() {
            self.contour_line(line, &block);
            return;
        }
        if self.modal_state(line, &block, params) {
            return;
        }
        let first = self.r.items.len();
        let span = self.r.src.line_span(line);
        if block.delimiter {
            self.push(ItemKind::Delimiter, span);
        } else if block.is_empty() {
            if !block.comments.is_empty() {
                self.push(ItemKind::Comment(block.comments.join("; ")), span);
            }
            return;
        } else {
            self.block(line, &block);
            params.numbered[5210] = self.offset_params[0];
        }
        // A line whose words made no item (G21, G90…) keeps its comment as an item.
        let comment = (!block.comments.is_empty()).then(|| block.comments.join("; "));
        if self.cycle_call.is_some() {
            // The comment stays on the cycle's rapid, if it made one.
            let pushed = self.r.items.len() > first;
            self.stamp_contour(block.number, if pushed { None } else { comment.clone() });
        }
        self.r
            .stamp_block(first, block.number, comment, span, false);
    }

    /// A plane other than ZX or an axis other than X and Z: the program is not a lathe
    /// program, and no mode may keep the line (a mill program half converted is worse than
    /// none). Reports each such word (ISOR021); true when there was one.
    fn not_a_lathe_program(&mut self, line: Line<'_>, block: &Block) -> bool {
        let roughing = block.words.iter().any(|w| {
            w.letter == 'G'
                && w.value
                    .to_scaled(1)
                    .is_ok_and(|g| matches!(g, G70 | G71 | G71_1 | G71_2 | G72 | G72_1 | G72_2))
        });
        // The first such word of the line is reported (a line may hold thousands).
        let Some((w, why)) = block.words.iter().find_map(|w| {
            let why = match w.letter {
                'U' | 'W' if roughing => None,
                'G' if w
                    .value
                    .to_scaled(1)
                    .is_ok_and(|g| matches!(g, G19 | G17_1 | G18_1 | G19_1)) =>
                {
                    Some("another plane than ZX (G18) or XY (G17)")
                }
                'Y' | 'A' | 'B' | 'C' | 'U' | 'V' | 'W' => Some("an axis other than X and Z"),
                _ => None,
            };
            Some((w, why)).filter(|_| why.is_some() || roughing && matches!(w.letter, 'U' | 'W'))
        }) else {
            return false;
        };
        let text = line.text[w.range.clone()].to_string();
        match why {
            // U and W on a G70–G72 line: the stock to leave, which this LinuxCNC refuses.
            None => self.diag(
                codes::ISOR_ROUGHING,
                line,
                w.range.clone(),
                format!(
                    "`{text}`: the stock to leave on a roughing cycle's line is read by LinuxCNC 2.9 as an axis, and a lathe has none (rs274: \"Bad character '{}' used\")",
                    w.letter.to_ascii_lowercase()
                ),
                "leave the stock with D (the distance kept along the contour), or write the contour offset by the stock",
            ),
            Some(_) if self.not_lathe_reported => {}
            Some(why) => {
                self.not_lathe_reported = true;
                self.diag(
                    codes::ISOR_NOT_LATHE,
                    line,
                    w.range.clone(),
                    format!("`{text}`: {why}: this is not a lathe program"),
                    "ncthread converts lathe programs (X and Z in the ZX plane, G18); a mill program is refused whole, in every mode, never half converted (later lines of this kind are not reported again)",
                );
            }
        }
        true
    }

    /// Reports what the line holds that ncthread does not read; true when the line must
    /// be skipped (or was kept opaque).
    fn unsupported(&mut self, line: Line<'_>, block: &Block) -> bool {
        if self.not_a_lathe_program(line, block) {
            return true;
        }
        let mut found: Vec<(Range<usize>, String)> = block
            .unread
            .iter()
            .map(|u| {
                (
                    u.range.clone(),
                    if u.what == BLOCK_DELETE {
                        "block delete `/`: whether this line runs is the operator's switch; say which with --block-delete off (it runs) or on (it is skipped), or `block_delete` in the profile's [iso] section".to_string()
                    } else {
                        format!("{} is not read by ncthread", u.what)
                    },
                )
            })
            .collect();
        for w in &block.words {
            let text = &line.text[w.range.clone()];
            let why = match w.letter {
                'G' => match w.value.to_scaled(1).map(g_meaning) {
                    Ok(Meaning::Unsupported("this G code")) => {
                        let hint = crate::dialect::read::did_you_mean(text, KNOWN_G);
                        found.push((
                            w.range.clone(),
                            format!("`{text}`: this G code — not read by ncthread{hint}"),
                        ));
                        None
                    }
                    Ok(Meaning::Unsupported(why)) => Some(why),
                    Err(_) => Some("this G code"),
                    _ => None,
                },
                'M' => match w.value.to_whole().map(m_meaning) {
                    Ok(Meaning::Unsupported(why)) => Some(why),
                    Err(_) => Some("this M code"),
                    _ => None,
                },
                _ => None,
            };
            if let Some(why) = why {
                found.push((
                    w.range.clone(),
                    format!("`{text}`: {why} — not read by ncthread"),
                ));
            }
        }
        if found.is_empty() {
            return false;
        }
        let keep = self.options.unsupported == Unsupported::Warn;
        let found = found
            .into_iter()
            .map(|(range, message)| (self.r.span(line, range), message))
            .collect();
        let thread = block.words.iter().any(|w| {
            w.letter == 'G'
                && w.value
                    .to_scaled(1)
                    .is_ok_and(|g| matches!(g, G33 | G33_1 | G76))
        });
        if self.r.unsupported(&UNSUPPORTED, found, keep, thread) {
            // A kept line must not change what ncthread follows: its modes and F, S, T or
            // spindle words would take effect in LinuxCNC and not here, and the lines after
            // it would be read wrongly. (A motion code leaves the motion mode unknown.)
            if let Some(w) = block.words.iter().find(|w| changes_followed_state(w)) {
                let span = self.r.span(line, w.range.clone());
                self.r
                    .state_in_opaque(&UNSUPPORTED, span, &line.text[w.range.clone()]);
                return true;
            }
            let context = ModalContext {
                inch: self.inch,
                diameter: self.diameter.unwrap_or(false),
                incremental: self.incremental,
                per_minute: Some(self.feed_mode != Some(FeedMode::PerRev)),
                moves: may_move(line, block),
            };
            let text = line.text.trim().to_string();
            self.r
                .keep_opaque(text, self.r.src.line_span(line), None, context);
            if block.words.iter().any(|w| {
                w.letter == 'G'
                    && w.value
                        .to_scaled(1)
                        .is_ok_and(|g| matches!(g, G0 | G1 | G2 | G3 | G33 | G33_1 | G38_1..=G38_5 | G73 | G74 | G76 | G80..=G8X_LAST))
            }) {
                self.motion = None;
            }
        }
        true
    }

    fn sort_words<'b>(&mut self, line: Line<'_>, block: &'b Block) -> Option<Words<'b>> {
        let mut words = Words {
            g: Vec::new(),
            m: Vec::new(),
            other: Letters::default(),
            used: Vec::new(),
        };
        let mut ok = true;
        let mut repeats = 0;
        for w in &block.words {
            match w.letter {
                // Checked by `unsupported` already.
                'G' => words.g.push((w.value.to_scaled(1).unwrap_or_default(), w)),
                'M' => words.m.push((w.value.to_whole().unwrap_or_default(), w)),
                letter => {
                    if words.other.contains_key(&letter) && !budget(&mut repeats) {
                        ok = false;
                    } else if let Some(first) = words.other.get(&letter) {
                        let first = line.text[first.range.clone()].to_string();
                        self.diag(
                            codes::ISOR_CONFLICT,
                            line,
                            w.range.clone(),
                            format!("a second {letter} word on the line (the first is `{first}`)"),
                            "LinuxCNC refuses a line with two words of one letter; split the line",
                        );
                        ok = false;
                    } else {
                        words.other.insert(letter, w);
                    }
                }
            }
        }
        if repeats > WORD_REPORTS {
            self.diag(
                codes::ISOR_CONFLICT,
                line,
                0..line.text.len(),
                format!("{} more repeated words on the line", repeats - WORD_REPORTS),
                "LinuxCNC refuses a line with two words of one letter; split the line",
            );
        }
        // One code of each modal group per line (LinuxCNC's read_g and read_m), even the same
        // code twice.
        let g_groups: [(&str, &[GCode], &str); 13] = [
            ("motion", &MOTION, "one motion code per line"),
            ("units", &[G20, G21], "one of G20, G21 per line"),
            ("distance", &[G90, G91], "one of G90, G91 per line"),
            (
                "arc distance",
                &[G90_1, G91_1],
                "one of G90.1, G91.1 per line",
            ),
            ("spindle mode", &[G96, G97], "one of G96, G97 per line"),
            (
                "cutter compensation",
                &[G40, G41, G42, G41_1, G42_1],
                "one of G40, G41, G42, G41.1, G42.1 per line",
            ),
            (
                "work offset",
                &[G54, G55, G56, G57, G58, G59, G59_1, G59_2, G59_3],
                "one work offset (G54 … G59.3) per line",
            ),
            (
                "non-modal",
                &[G28, G28_1, G30, G30_1, G53, G52, G92, G92_1, G92_2, G92_3],
                "one of G28, G28.1, G30, G30.1, G52, G53, G92, G92.1, G92.2, G92.3 per line",
            ),
            ("feed mode", &[G94, G95], "one of G94, G95 per line"),
            ("diameter mode", &[G7, G8], "one of G7, G8 per line"),
            ("dwell", &[G4], "one G4 per line"),
            ("tool length", &[G43, G49], "one of G43, G49 per line"),
            ("retract mode", &[G98, G99], "one of G98, G99 per line"),
        ];
        let m_groups: [(&str, &[i64], &str); 4] = [
            (
                "stopping",
                &[0, 1, 2, 30, 60],
                "one of M0, M1, M2, M30, M60 per line",
            ),
            ("tool change", &[6, 61], "one of M6, M61 per line"),
            ("spindle", &[3, 4, 5], "one of M3, M4, M5 per line"),
            (
                "coolant",
                &[7, 8, 9],
                "one of M7, M8, M9 per line (M7 and M8 on two lines)",
            ),
        ];
        for (codes_on_line, groups) in [(&words.g, &g_groups[..]), (&words.m, &m_groups[..])] {
            if codes_on_line.len() < 2 {
                continue;
            }
            for &(name, members, help) in groups {
                let mut found = codes_on_line.iter().filter(|(c, _)| members.contains(c));
                if let (Some((_, a)), Some((_, b))) = (found.next(), found.next()) {
                    self.diag(
                        codes::ISOR_CONFLICT,
                        line,
                        b.range.clone(),
                        format!(
                            "`{}` and `{}` are both {name} codes",
                            &line.text[a.range.clone()],
                            &line.text[b.range.clone()]
                        ),
                        help,
                    );
                    ok = false;
                }
            }
        }
        ok.then_some(words)
    }

    /// A length word in program units → mm on the grid; warns once when it rounds.
    fn length(&mut self, line: Line<'_>, w: &Word) -> Option<Length> {
        self.length_times(line, w, 1)
    }

    /// `times` the word's length, rounded once (an arc's I, a radius, as a diameter).
    fn length_times(&mut self, line: Line<'_>, w: &Word, times: i128) -> Option<Length> {
        let d = w.value;
        let factor: i128 = if self.inch { 254_000 } else { 10_000 } * times;
        let den = 10i128.checked_pow(d.scale);
        let num = d.mantissa.checked_mul(factor);
        let (Some(num), Some(den)) = (num, den) else {
            self.too_large(line, w);
            return None;
        };
        let v = div_round(num, den);
        if v.abs() > 1 << 50 {
            self.too_large(line, w);
            return None;
        }
        if num % den != 0 && !self.warned_rounding {
            self.warned_rounding = true;
            let exact = num as f64 / den as f64 / 10_000.0;
            self.diag(
                codes::ISOR_ROUNDED,
                line,
                w.range.clone(),
                format!(
                    "`{}` is {exact} mm{}, rounded to {} mm (ncthread computes on a 0.0001 mm grid; later values that round are not reported again)",
                    &line.text[w.range.clone()],
                    if times == 2 { " as a diameter" } else { "" },
                    Length(v as i64).mm()
                ),
                "the rounding is at most 0.00005 mm, far inside the 0.001 mm that `verify` allows",
            );
        }
        Some(Length(v as i64))
    }

    /// A lead word (K, G76's P) in program units → a [`Lead`], exact to 10⁻¹² mm.
    fn lead(&mut self, line: Line<'_>, w: &Word) -> Option<Lead> {
        let d = w.value;
        // mm: value × 10¹²; inch: value × 25.4 × 10¹² = value × 254 × 10¹¹.
        let (factor, shift) = if self.inch { (254, 11) } else { (1, 12) };
        let num = d.mantissa.checked_mul(factor);
        let scaled = match num {
            Some(num) if d.scale <= shift => 10i128
                .checked_pow(shift - d.scale)
                .and_then(|f| num.checked_mul(f)),
            Some(num) => 10i128
                .checked_pow(d.scale - shift)
                .map(|den| div_round(num, den)),
            None => None,
        };
        match scaled {
            Some(v) if v.abs() <= Lead::MAX.0 as i128 => Some(Lead(v as i64)),
            _ => {
                self.diag(
                    codes::ISOR_NUMBER,
                    line,
                    w.range.clone(),
                    format!("`{}` is too large for a lead", &line.text[w.range.clone()]),
                    "a lead is at most 1,000,000 mm",
                );
                None
            }
        }
    }

    fn too_large(&mut self, line: Line<'_>, w: &Word) {
        self.diag(
            codes::ISOR_NUMBER,
            line,
            w.range.clone(),
            format!("`{}` is too large", &line.text[w.range.clone()]),
            "lengths are at most about 10^11 mm",
        );
    }

    fn number_error(&mut self, line: Line<'_>, w: &Word, message: String, help: &str) {
        self.diag(codes::ISOR_NUMBER, line, w.range.clone(), message, help);
    }

    fn whole(&mut self, line: Line<'_>, w: &Word, what: &str) -> Option<u32> {
        match w.value.to_whole().ok().and_then(|v| u32::try_from(v).ok()) {
            Some(v) => Some(v),
            None => {
                self.number_error(
                    line,
                    w,
                    format!(
                        "{what} `{}` is not a whole number of 0 or more",
                        &line.text[w.range.clone()]
                    ),
                    "write it as a whole number",
                );
                None
            }
        }
    }

    fn missing(&mut self, line: Line<'_>, at: &Word, message: String, help: &str) {
        self.diag(codes::ISOR_WORD, line, at.range.clone(), message, help);
    }

    fn block(&mut self, line: Line<'_>, block: &Block) {
        if self.unsupported(line, block) {
            return;
        }
        let Some(mut words) = self.sort_words(line, block) else {
            return;
        };
        let span = self.r.src.line_span(line);
        // Where this line's diagnostics start (counting every error again would be
        // quadratic in a program with many warnings).
        let diags_before = self.r.diags.len();

        // LinuxCNC's order of execution within a line. A feed mode code also clears the
        // feed rate there (G1 needs a new F after it).
        if words.has_g(G94).is_some() {
            self.feed_mode = Some(FeedMode::PerMin);
            self.feed = None;
            self.push(ItemKind::FeedMode(FeedMode::PerMin), span);
        }
        if words.has_g(G95).is_some() {
            self.feed_mode = Some(FeedMode::PerRev);
            self.feed = None;
            self.push(ItemKind::FeedMode(FeedMode::PerRev), span);
        }
        // A surface speed's S is taken in the units in force before the line's G20/G21:
        // LinuxCNC sets the speed (and its task canon the ft/min or m/min factor) before it
        // changes the units.
        let inch_before = self.inch;
        // Units first: F, K and every length on the line are in the new units.
        if words.has_g(G20).is_some() {
            self.inch = true;
        }
        if words.has_g(G21).is_some() {
            self.inch = false;
        }
        let first_item = self.r.items.len();
        let mut f_word = None;
        if let Some(f) = words.take('F')
            && let Some(feed) = self.length(line, f)
        {
            if feed.0 < 0 {
                self.number_error(line, f, "the feed is negative".into(), "F is 0 or more");
            } else {
                self.feed = Some(feed);
                f_word = Some(feed);
            }
        }
        // The spindle mode comes before S in LinuxCNC's order; G96 needs S on its line. Under
        // G20 its S is in feet per minute (LinuxCNC's task canon: rpm = 12·S/(2π·r in)).
        if let Some(g96) = words.has_g(G96) {
            if !words.other.contains_key(&'S') {
                self.missing(
                    line,
                    g96,
                    "G96 without S (LinuxCNC: \"S word missing with G96\")".into(),
                    "give the surface speed on the G96 line: `G96 D2500 S200` (m/min, D the rpm limit)",
                );
                return;
            }
            let limit = words.take('D').map(|d| d.value);
            if limit.is_some_and(|d| d.is_negative() || d.mantissa == 0) {
                self.missing(
                    line,
                    g96,
                    "G96 with a D (the rpm limit) of 0 or less: LinuxCNC then turns at S rpm, not at a surface speed".into(),
                    "write G97 for a speed in rpm, or a positive D",
                );
                return;
            }
            self.surface_speed = true;
            self.surface = (limit, inch_before);
            self.push(
                ItemKind::SpindleMode(SpindleMode::SurfaceSpeed {
                    limit,
                    feet: inch_before,
                }),
                span,
            );
        } else if self.surface_speed
            && self.surface.1 != inch_before
            && words.other.contains_key(&'S')
        {
            // A new S under the surface speed, in other units than its G96's: the mode again,
            // in the S's units (the limit stands).
            self.surface.1 = inch_before;
            self.push(
                ItemKind::SpindleMode(SpindleMode::SurfaceSpeed {
                    limit: self.surface.0,
                    feet: inch_before,
                }),
                span,
            );
        }
        if words.has_g(G97).is_some() {
            self.surface_speed = false;
            self.push(ItemKind::SpindleMode(SpindleMode::Rpm), span);
        }
        let speed = match words.take('S') {
            Some(s) => self.whole(line, s, "spindle speed"),
            None => None,
        };
        if let Some(t) = words.take('T') {
            self.selected_tool = self.whole(line, t, "tool number");
        }
        let mut tool_changed = None;
        if let Some(m6) = words.has_m(6) {
            if self.compensation {
                self.comp_refusal(
                    line,
                    m6,
                    "Cannot change tools with cutter radius compensation on",
                );
            }
            match self.selected_tool {
                Some(t) => tool_changed = Some(t),
                None => self.missing(
                    line,
                    m6,
                    "M6 without a tool selected by a T word".into(),
                    "select the tool first: `T5 M6`",
                ),
            }
        }
        let offset = match words.has_g(G43) {
            Some(_) => match words.take('H') {
                Some(h) => self.whole(line, h, "tool length offset"),
                None => tool_changed.or(self.selected_tool),
            },
            None => None,
        };
        if tool_changed.is_some() || offset.is_some() {
            self.push(
                ItemKind::Tool {
                    number: tool_changed,
                    offset,
                },
                span,
            );
            // LinuxCNC's M6 stops the spindle.
            if tool_changed.is_some() && self.turning.is_some() {
                self.turning = None;
                self.push(ItemKind::SpindleStop, span);
            }
        }
        let direction = if words.has_m(3).is_some() {
            Some(SpindleDirection::Clockwise)
        } else if words.has_m(4).is_some() {
            Some(SpindleDirection::CounterClockwise)
        } else {
            None
        };
        if speed.is_some() || direction.is_some() {
            if speed.is_some() {
                self.speed = speed;
            }
            if direction.is_some() {
                self.turning = direction;
            }
            self.push(ItemKind::Spindle { speed, direction }, span);
        }
        if words.has_m(5).is_some() {
            self.turning = None;
            self.push(ItemKind::SpindleStop, span);
        }
        for &(code, w) in &words.m {
            let coolant = match code {
                7 => Coolant::Mist,
                8 => Coolant::Flood,
                9 => Coolant::Off,
                _ => continue,
            };
            let at = self.r.span(line, w.range.clone());
            match coolant {
                Coolant::Mist => self.mist = true,
                Coolant::Flood => self.flood = true,
                Coolant::Off => (self.mist, self.flood) = (false, false),
            }
            self.push(ItemKind::Coolant(coolant), at);
        }
        if let Some(g4) = words.has_g(G4) {
            match words.take('P') {
                Some(p) if !p.value.is_negative() => {
                    self.push(ItemKind::Dwell { seconds: p.value }, span)
                }
                Some(p) => self.number_error(
                    line,
                    p,
                    "the dwell time is negative".into(),
                    "G4 P is seconds, 0 or more",
                ),
                None => self.missing(
                    line,
                    g4,
                    "G4 without P (the dwell time in seconds)".into(),
                    "write `G4 P0.5`",
                ),
            }
        }
        self.diameter_before_line = self.diameter.unwrap_or(false);
        if words.has_g(G7).is_some() {
            self.diameter = Some(true);
        }
        if words.has_g(G8).is_some() {
            self.diameter = Some(false);
        }
        for i in 0..words.g.len() {
            let (code, w) = words.g[i];
            if matches!(g_meaning(code), Meaning::Kept) {
                // G64's tolerances belong to it.
                let extra: Vec<&Word> = if code == G64 {
                    ['P', 'Q'].iter().filter_map(|&l| words.take(l)).collect()
                } else {
                    Vec::new()
                };
                self.kept(line, w, &extra);
            }
        }
        // The plane (LinuxCNC selects it before compensation and motion). A lathe program
        // may select G17 to drill or tap along Z: its X and Z moves are the same in either.
        if let Some(g17) = words.has_g(G17) {
            if self.compensation {
                self.comp_refusal(
                    line,
                    g17,
                    "Cannot change planes with cutter radius compensation on",
                );
            }
            self.plane_xy = true;
        }
        if words.has_g(G18).is_some() {
            self.plane_xy = false;
        }
        // Cutter compensation, then the work offset (LinuxCNC's order).
        if let Some(&(code, w)) = words
            .g
            .iter()
            .find(|(c, _)| matches!(*c, G40 | G41 | G42 | G41_1 | G42_1))
        {
            let right = matches!(code, G42 | G42_1);
            let comp = match code {
                G40 => Some(Compensation::Off),
                G41 | G42 => match words.take('D') {
                    Some(d) => {
                        self.whole(line, d, "tool number (D)")
                            .map(|t| Compensation::FromTool {
                                right,
                                tool: Some(t),
                            })
                    }
                    None => Some(Compensation::FromTool { right, tool: None }),
                },
                _ => match words.take('D') {
                    Some(d) if !d.value.is_negative() => {
                        let orientation = match words.take('L') {
                            Some(l) => self.whole(line, l, "tool orientation (L)"),
                            None => None,
                        };
                        Some(Compensation::Dynamic {
                            right,
                            diameter: d.value,
                            orientation,
                        })
                    }
                    _ => {
                        self.missing(
                            line,
                            w,
                            format!("{} without a diameter D of 0 or more", &line.text[w.range.clone()]),
                            "G41.1/G42.1 take the tool's diameter in D (and its lathe orientation in L)",
                        );
                        None
                    }
                },
            };
            if self.plane_xy && code != G40 {
                let text = line.text[w.range.clone()].to_string();
                self.diag(
                    codes::ISOR_COMPENSATION,
                    line,
                    w.range.clone(),
                    format!("`{text}` while G17 is in force: LinuxCNC would compensate in the XY plane, which a lathe has not"),
                    "select G18 before cutter compensation",
                );
                return;
            }
            if let Some(comp) = comp {
                let on = comp != Compensation::Off;
                if on && self.compensation {
                    self.comp_refusal(line, w, "Cannot turn cutter radius comp on when on");
                }
                self.compensation = on;
                self.ccomp = match comp {
                    Compensation::FromTool { right: true, .. }
                    | Compensation::Dynamic { right: true, .. } => 420.0,
                    Compensation::Off => 400.0,
                    _ => 410.0,
                };
                self.push(ItemKind::Compensation(comp), span);
            }
        }
        if let Some(index) = words.g.iter().find_map(|(c, _)| match *c {
            G54 => Some(1),
            G55 => Some(2),
            G56 => Some(3),
            G57 => Some(4),
            G58 => Some(5),
            G59 => Some(6),
            G59_1 => Some(7),
            G59_2 => Some(8),
            G59_3 => Some(9),
            _ => None,
        }) {
            if self.compensation
                && let Some(&(_, w)) = words.g.iter().find(|(c, _)| (G54..=G59_3).contains(c))
            {
                self.comp_refusal(
                    line,
                    w,
                    "Cannot change coordinate systems with cutter radius compensation on",
                );
            }
            self.work_offset = index;
            self.push(ItemKind::WorkOffset(index), span);
        }
        if words.has_g(G90).is_some() {
            self.incremental = false;
        }
        if words.has_g(G91).is_some() {
            self.incremental = true;
        }
        if words.has_g(G90_1).is_some() {
            self.absolute_centres = true;
        }
        if words.has_g(G91_1).is_some() {
            self.absolute_centres = false;
        }
        // The retract mode of the canned cycles (after the distance modes, before the motion).
        if let Some(&(code, w)) = words.g.iter().find(|(c, _)| matches!(*c, G98 | G99)) {
            if self.compensation {
                self.comp_refusal(
                    line,
                    w,
                    "Cannot change retract mode with cutter radius compensation on",
                );
            }
            self.retract_old_z = code == G98;
        }
        let motion_code = words.g.iter().find_map(|&(c, _)| match c {
            G0 => Some(Motion::Rapid),
            G1 => Some(Motion::Feed),
            G2 => Some(Motion::Arc { clockwise: true }),
            G3 => Some(Motion::Arc { clockwise: false }),
            G33 => Some(Motion::Thread),
            G33_1 => Some(Motion::Tap),
            G76 => Some(Motion::Cycle),
            G70 | G71 | G71_1 | G71_2 | G72 | G72_1 | G72_2 => Some(Motion::Roughing(c)),
            G73 | G81 | G82 | G83 | G85 | G89 => Some(Motion::Drill(c)),
            _ => None,
        });
        // G80 with another motion code on its line is ignored. **[evidence]** `read_g`.
        let motion_code = motion_code.or(words.has_g(G80).map(|_| Motion::CycleOff));
        self.motion_before_line = self.motion;
        if let Some(m) = motion_code {
            self.motion = Some(m);
            // Any motion but a canned cycle (G80 too) forgets the cycles' initial level.
            // **[evidence]** `convert_motion`: `if (!is_a_cycle(motion)) cycle_il_flag = false`.
            if !matches!(m, Motion::Drill(_)) {
                self.drill.forget_initial_level();
            }
        }
        // G52 and G92 (the line's axes are theirs), G92.1, G92.2, G92.3.
        if let Some(&(code, w)) = words
            .g
            .iter()
            .find(|(c, _)| matches!(*c, G52 | G92 | G92_1 | G92_2 | G92_3))
        {
            self.axis_offsets(line, &mut words, code, w, motion_code.is_some());
        }
        // G28/G30 (via the line's axes to the stored position), G28.1/G30.1, and G53 with
        // G0 or G1: the line's axes are theirs, and nothing else moves.
        if let Some(&(code, w)) = words
            .g
            .iter()
            .find(|(c, _)| matches!(*c, G28 | G28_1 | G30 | G30_1 | G53))
        {
            let second = matches!(code, G30 | G30_1);
            let kind = match code {
                G28_1 | G30_1 => Some(MachineMove::StoreHome { second }),
                G28 | G30 if self.compensation => {
                    self.comp_refusal(line, w, "Cannot use g28 or g30 with cutter radius comp");
                    None
                }
                G28 | G30 => self
                    .target(line, &mut words)
                    .map(|via| MachineMove::Home { second, via }),
                _ => match self.motion {
                    Some(m @ (Motion::Rapid | Motion::Feed)) => {
                        // Machine coordinates: no G52/G92 offset.
                        let offset = std::mem::take(&mut self.axis_offset);
                        let to = self.target(line, &mut words);
                        self.axis_offset = offset;
                        let feed = if m == Motion::Feed {
                            self.feed_rate(line, Some(w), "G53 G1", span).map(Some)
                        } else {
                            Some(None)
                        };
                        match (to, feed) {
                            (Some(to), Some(feed)) if to != Pos::UNKNOWN => {
                                Some(MachineMove::Machine { to, feed })
                            }
                            (Some(_), Some(_)) => {
                                self.missing(
                                    line,
                                    w,
                                    "G53 without X or Z".into(),
                                    "G53 moves the axes it names to machine coordinates: `G53 G0 X200 Z100`",
                                );
                                None
                            }
                            _ => None,
                        }
                    }
                    _ => {
                        self.missing(
                            line,
                            w,
                            "G53 without G0 or G1 in force (LinuxCNC: \"Must use G0 or G1 with G53\")".into(),
                            "write `G53 G0 X… Z…`",
                        );
                        None
                    }
                },
            };
            if let Some(kind) = kind {
                let kind = ItemKind::MachineMove(kind);
                self.r.pos = kind.end_position(self.r.pos);
                self.push(kind, span);
            }
            self.exact = (None, None);
            words.take('X');
            words.take('Z');
        }
        let axes = ['X', 'Z']
            .iter()
            .any(|l| words.other.contains_key(l) && !words.used.contains(l));
        // A G2/G3 on the line moves even without axes (a full circle from I and K).
        if axes
            || matches!(
                motion_code,
                Some(
                    Motion::Tap
                        | Motion::Cycle
                        | Motion::Arc { .. }
                        | Motion::Roughing(_)
                        | Motion::Drill(_)
                )
            )
        {
            match self.motion {
                Some(m) => self.motion(line, &mut words, m, span),
                None => {
                    let w = words.other.get(&'X').or(words.other.get(&'Z')).copied();
                    if let Some(w) = w {
                        self.missing(
                            line,
                            w,
                            "an axis word with no motion mode (G0, G1, G33…) in force".into(),
                            "write the motion code first: `G0 X20 Z5`",
                        );
                    }
                    words.take('X');
                    words.take('Z');
                }
            }
        } else if let Some(code_word) = words
            .g
            .iter()
            .find(|(c, _)| [G1, G33].contains(c))
            .map(|(_, w)| *w)
        {
            // A motion code without axes: LinuxCNC refuses G33 ("All axes missing with motion
            // code") and checks G1's feed all the same.
            if motion_code == Some(Motion::Thread) {
                words.take('K');
                self.missing(
                    line,
                    code_word,
                    "G33 without X or Z (LinuxCNC: \"All axes missing with motion code\")".into(),
                    "give the end of the thread: `G33 Z-20 K1.5`",
                );
            } else if self.feed.is_none_or(|f| f.0 <= 0) {
                self.missing(
                    line,
                    code_word,
                    "G1 with no feed rate (F) set, or F0 (LinuxCNC refuses it even without axes)"
                        .into(),
                    "set the feed with F before or on this line",
                );
            }
        }
        // An F that no move of the line used stays where it is written (a roughing cycle's
        // moves come when its contour has run).
        if let Some(feed) = f_word
            && self.cycle_call.is_none()
            && !self.r.items[first_item..].iter().any(|i| {
                matches!(
                    i.kind,
                    ItemKind::Feed { .. }
                        | ItemKind::Arc { .. }
                        | ItemKind::MachineMove(MachineMove::Machine { feed: Some(_), .. })
                )
            })
        {
            self.push(ItemKind::FeedRate(feed), span);
        }
        for &(code, w) in &words.m {
            match code {
                0 | 1 => {
                    let at = self.r.span(line, w.range.clone());
                    self.push(
                        ItemKind::Stop {
                            optional: code == 1,
                        },
                        at,
                    );
                }
                2 => {
                    self.push(ItemKind::ProgramEnd(EndCode::M2), span);
                    self.ended = true;
                    self.compensation = false;
                }
                30 => {
                    self.push(ItemKind::ProgramEnd(EndCode::M30), span);
                    self.ended = true;
                    self.compensation = false;
                }
                _ => {}
            }
            if matches!(code, 2 | 30) {
                self.turning = None;
            }
        }
        // Words no command read (LinuxCNC refuses them too), unless an error on this line
        // already explains the line.
        if !self
            .r
            .diags
            .get(diags_before..)
            .is_some_and(|d| d.iter().any(|d| d.is_error()))
        {
            let unused: Vec<&Word> = words
                .other
                .iter()
                .filter(|(l, _)| !words.used.contains(l))
                .map(|(_, w)| *w)
                .collect();
            for w in unused {
                let text = &line.text[w.range.clone()];
                self.missing(
                    line,
                    w,
                    format!("`{text}` is not used by any command on this line"),
                    "LinuxCNC refuses words no command on the line uses (K belongs to G33/G33.1/G76, P to G4/G76, H to G43/G76…)",
                );
            }
        }
    }

    fn kept(&mut self, line: Line<'_>, w: &Word, extra: &[&Word]) {
        // A word whose value is an expression or a parameter is kept with its value: the
        // output holds no parameters (ngcgui's `g64 p#<tol>` after `#<tol> = 0.001`).
        let word = |w: &Word| {
            let text = &line.text[w.range.clone()];
            if text.contains(['#', '[']) {
                format!("{}{}", w.letter.to_ascii_uppercase(), w.value)
            } else {
                text.to_string()
            }
        };
        let mut text = word(w);
        for e in extra {
            text.push(' ');
            text.push_str(&word(e));
        }
        let span = self.r.src.span_in_line(line, w.range.clone());
        self.push(
            ItemKind::Opaque {
                dialect: super::ID,
                text,
                block: None,
            },
            span,
        );
    }

    /// X and Z of the line as an absolute target (diameter), or `None` after an error.
    /// The exact start of a move: [`FrontEnd::exact`] where it agrees with the known
    /// position, else the known position.
    fn exact_start(&self) -> (Option<f64>, Option<f64>) {
        let pick = |exact: Option<f64>, known: Option<Length>| match (exact, known) {
            (Some(e), Some(k)) if (Length::from_mm_f64(e) - k).abs() <= Length(1) => Some(e),
            (_, k) => k.map(Length::to_mm_f64),
        };
        (
            pick(self.exact.0, self.r.pos.x),
            pick(self.exact.1, self.r.pos.z),
        )
    }

    /// Where a move leaves the exact position: its target's axes, the others as they were.
    fn exact_after_move(&mut self, start: (Option<f64>, Option<f64>)) {
        self.exact = (
            self.exact_target.0.or(start.0),
            self.exact_target.1.or(start.1),
        );
    }

    fn target(&mut self, line: Line<'_>, words: &mut Words<'_>) -> Option<Pos> {
        let mut to = Pos::UNKNOWN;
        let start = self.exact_start();
        let unit = if self.inch { 25.4 } else { 1.0 };
        self.exact_target = (None, None);
        if let Some(w) = words.take('X') {
            let (v, exact) = self.x_word(line, w)?;
            // An increment is added to the exact position, then rounded: once.
            let (x, exact) = if self.incremental {
                match start.0 {
                    Some(s) => (Length::from_mm_f64(s + exact), s + exact),
                    None => return self.unknown(line, w),
                }
            } else {
                self.shifted_x(v, exact)
            };
            to.x = Some(x);
            self.exact_target.0 = Some(exact);
        }
        if let Some(w) = words.take('Z') {
            let v = self.length(line, w)?;
            let exact = w.value.to_f64() * unit;
            let (z, exact) = if self.incremental {
                match start.1 {
                    Some(s) => (Length::from_mm_f64(s + exact), s + exact),
                    None => return self.unknown(line, w),
                }
            } else {
                self.shifted_z(v, exact)
            };
            to.z = Some(z);
            self.exact_target.1 = Some(exact);
            // The Z as LinuxCNC holds it, for the drilling cycles' comparisons.
            let value = if self.incremental {
                start.1.map_or(0.0, |s| self.program_z(s)) + w.value.to_f64()
            } else {
                w.value.to_f64()
            };
            self.record_program_z(exact, value);
        }
        Some(to)
    }

    /// The Z at `mm` (exact, where the tool goes) as LinuxCNC holds it: in the program's
    /// units and coordinates, the very double it computed where ncthread saw it computed
    /// (`(mm − offset) / 25.4` need not give that double back, and the drilling cycles
    /// compare it with R).
    pub(super) fn program_z(&self, mm: f64) -> f64 {
        let offset = self.axis_offset.1;
        match self.z_program {
            Some(p) if p.mm == mm && p.inch == self.inch && p.offset == offset => p.value,
            _ => (mm - offset) / if self.inch { 25.4 } else { 1.0 },
        }
    }

    pub(super) fn record_program_z(&mut self, mm: f64, value: f64) {
        self.z_program = Some(ProgramZ {
            mm,
            value,
            inch: self.inch,
            offset: self.axis_offset.1,
        });
    }

    /// An X word as written, before any increment or offset: its value on the grid and its
    /// exact value in mm, both diameters. X is a radius until the program says G7 (with a
    /// warning, once).
    fn x_word(&mut self, line: Line<'_>, w: &Word) -> Option<(Length, f64)> {
        let unit = if self.inch { 25.4 } else { 1.0 };
        let v = self.length(line, w)?;
        let diameter = match self.diameter {
            Some(d) => d,
            None => {
                if !self.warned_radius {
                    self.warned_radius = true;
                    self.diag(
                        codes::ISOR_RADIUS_MODE,
                        line,
                        w.range.clone(),
                        "X is read as a radius: the program has not chosen G7 (diameter) or G8 (radius), and LinuxCNC starts in G8".into(),
                        "write G7 or G8 at the start so that the program does not depend on the machine's start-up codes",
                    );
                }
                false
            }
        };
        let v = if diameter { v } else { v + v };
        let exact = w.value.to_f64() * unit * if diameter { 1.0 } else { 2.0 };
        Some((v, exact))
    }

    fn unknown(&mut self, line: Line<'_>, w: &Word) -> Option<Pos> {
        self.diag(
            codes::ISOR_UNKNOWN_POSITION,
            line,
            w.range.clone(),
            format!(
                "`{}` is incremental (G91) from a position that is not known yet",
                &line.text[w.range.clone()]
            ),
            "move to an absolute position (G90) first",
        );
        None
    }

    fn spindle_turning(&mut self, line: Line<'_>, w: Option<&Word>, what: &str) -> bool {
        if self.turning.is_some() {
            return true;
        }
        let range = w.map_or(0..line.text.len(), |w| w.range.clone());
        self.diag(
            codes::ISOR_SPINDLE,
            line,
            range,
            format!("{what} while the spindle is not turning"),
            "start the spindle with S and M3/M4 before the thread; LinuxCNC refuses this line too",
        );
        false
    }

    fn motion(&mut self, line: Line<'_>, words: &mut Words<'_>, motion: Motion, span: Span) {
        let code_word = words
            .g
            .iter()
            .find(|(c, _)| MOTION.contains(c))
            .map(|(_, w)| *w);
        match motion {
            Motion::Thread | Motion::Tap if self.compensation => {
                let at = code_word.or(words.other.get(&'Z').copied());
                if let Some(at) = at {
                    self.comp_refusal(
                        line,
                        at,
                        "Bug code not g0 or g1 (a synchronised move with compensation on)",
                    );
                }
            }
            Motion::Rapid => {
                let start = self.exact_start();
                if let Some(to) = self.target(line, words) {
                    self.push(ItemKind::Rapid { to }, span);
                    self.r.pos = ItemKind::Rapid { to }.end_position(self.r.pos);
                    self.exact_after_move(start);
                }
            }
            Motion::Feed => {
                let start = self.exact_start();
                let axis = words.other.get(&'X').or(words.other.get(&'Z')).copied();
                let Some(to) = self.target(line, words) else {
                    return;
                };
                let Some(feed) = self.feed_rate(line, code_word.or(axis), "G1", span) else {
                    return;
                };
                self.push(ItemKind::Feed { to, feed }, span);
                self.r.pos = ItemKind::Feed { to, feed }.end_position(self.r.pos);
                self.exact_after_move(start);
            }
            Motion::Arc { clockwise } if self.plane_xy => {
                let g = if clockwise { "G2" } else { "G3" };
                self.arc_error(
                    line,
                    code_word,
                    format!("{g} while G17 is in force: LinuxCNC cuts the arc in the XY plane, which a lathe has not"),
                    "select G18 before the arc (a lathe's arcs are in ZX)",
                );
            }
            Motion::Arc { clockwise } => self.arc(line, words, code_word, span, clockwise),
            Motion::Roughing(code) if self.plane_xy => {
                let name = crate::ir::g_code_name(code);
                let at = code_word.or(words.other.get(&'Q').copied());
                if let Some(at) = at {
                    self.diag(
                        codes::ISOR_ROUGHING,
                        line,
                        at.range.clone(),
                        format!("{name} while G17 is in force (LinuxCNC: \"G{}.{} can only be used in XZ plane (G18)\")", code / 10, code % 10),
                        "select G18 before the cycle",
                    );
                }
            }
            Motion::Thread => self.thread(line, words, code_word, span),
            Motion::Tap => self.tap(line, words, code_word, span),
            Motion::Cycle if self.compensation => {
                let at = code_word.or(words.other.get(&'Z').copied());
                if let Some(at) = at {
                    self.comp_refusal(
                        line,
                        at,
                        "Cannot use G76 threading cycle with cutter radius compensation on",
                    );
                }
            }
            Motion::Cycle => self.cycle(line, words, code_word, span),
            Motion::Roughing(code) => self.roughing(line, words, code_word, span, code),
            Motion::Drill(code) => self.drill(line, words, code_word, span, code),
            Motion::CycleOff => {
                // Axis words after G80, or on its line. **[evidence]** `enhance_block`.
                let w = words.other.get(&'X').or(words.other.get(&'Z')).copied();
                words.take('X');
                words.take('Z');
                if let Some(w) = w {
                    let (message, help) = if words.has_g(G80).is_some() {
                        (
                            "an axis word on a G80 line (LinuxCNC: \"Cannot use axis values with g80\")",
                            "put the move on a line of its own, with its motion code",
                        )
                    } else {
                        (
                            "an axis word after G80, which leaves no motion mode in force (LinuxCNC: \"Cannot use axis values without a g code that uses them\")",
                            "write the motion code: `G0 X20 Z5`",
                        )
                    };
                    self.missing(line, w, message.into(), help);
                }
            }
        }
    }

    /// The feed rate a feed move (`code`: G1, G2, G3) uses, or `None` after reporting at `at`
    /// that none is set. The first feed move of a program that never chose a feed mode
    /// writes out LinuxCNC's start-up mode (G94) for targets that differ.
    fn feed_rate(
        &mut self,
        line: Line<'_>,
        at: Option<&Word>,
        code: &str,
        span: Span,
    ) -> Option<Length> {
        let feed = match self.feed {
            Some(f) if f.0 > 0 => f,
            _ => {
                if let Some(at) = at {
                    self.missing(
                        line,
                        at,
                        format!("{code} with no feed rate (F) set, or F0"),
                        "set the feed with F before or on this line",
                    );
                }
                return None;
            }
        };
        if self.feed_mode.is_none() {
            self.feed_mode = Some(FeedMode::PerMin);
            self.push(ItemKind::FeedMode(FeedMode::PerMin), span);
        }
        Some(feed)
    }

    /// A command LinuxCNC refuses while cutter radius compensation is on.
    fn comp_refusal(&mut self, line: Line<'_>, at: &Word, linuxcnc: &str) {
        let text = &line.text[at.range.clone()];
        self.diag(
            codes::ISOR_COMPENSATION,
            line,
            at.range.clone(),
            format!("`{text}` while cutter radius compensation is on (LinuxCNC: \"{linuxcnc}\")"),
            "turn the compensation off with G40 first",
        );
    }

    fn arc_error(&mut self, line: Line<'_>, at: Option<&Word>, message: String, help: &str) {
        let range = at.map_or(0..line.text.len(), |w| w.range.clone());
        self.diag(codes::ISOR_ARC, line, range, message, help);
    }

    /// G2/G3 in the ZX plane, as LinuxCNC reads it: the end (an axis not given stays), the
    /// centre from I and K (an offset from the start under G91.1, the centre itself under
    /// G90.1; in radius units whatever G7/G8 says, as LinuxCNC halves only X) or from R,
    /// and LinuxCNC's checks of both. The centre is rounded once onto the grid.
    /// **\[evidence\]** LinuxCNC `convert_arc`, `arc_data_ijk`, `arc_data_r` (interp_arc.cc).
    fn arc(
        &mut self,
        line: Line<'_>,
        words: &mut Words<'_>,
        code_word: Option<&Word>,
        span: Span,
        clockwise: bool,
    ) {
        let g = if clockwise { "G2" } else { "G3" };
        let axis = words.other.get(&'X').or(words.other.get(&'Z')).copied();
        let (i, k, r, p) = (
            words.take('I'),
            words.take('K'),
            words.take('R'),
            words.take('P'),
        );
        let at = code_word.or(axis).or(i).or(k).or(r);
        if let Some(g4) = words.has_g(G4) {
            return self.arc_error(
                line,
                Some(g4),
                format!("G4 on the line of a {g} (LinuxCNC: \"G4 not allowed with G2 or G3 because they both use P\")"),
                "put the dwell on a line of its own",
            );
        }
        let start_exact = self.exact_start();
        let Some(target) = self.target(line, words) else {
            return;
        };
        let Some(feed) = self.feed_rate(line, at, g, span) else {
            return;
        };
        let (Some((sx, sz)), (Some(sx_e), Some(sz_e))) = (self.r.pos.known(), start_exact) else {
            let range = at.map_or(0..line.text.len(), |w| w.range.clone());
            self.diag(
                codes::ISOR_UNKNOWN_POSITION,
                line,
                range,
                format!("{g} from a position that is not known yet: the arc's centre and path cannot be placed"),
                "move to an absolute X and Z (G0 X… Z…) before the arc",
            );
            return;
        };
        if let Some(p) = p {
            // LinuxCNC takes P within 0.001 of a whole number as that number.
            let turns = p.value.to_f64();
            let whole = turns.round();
            if (turns - whole).abs() > 0.001 || whole < 1.0 {
                return self.arc_error(
                    line,
                    Some(p),
                    format!("{g} P must be a whole number of turns, 1 or more (LinuxCNC: \"P value not an integer with M19 G2 or G3\" or \"P value should be 1 or greater with G2 or G3\")"),
                    "leave P out for an arc of less than one turn",
                );
            }
            if whole > 1.0 {
                let text = &line.text[p.range.clone()];
                self.diag(
                    codes::ISOR_UNSUPPORTED,
                    line,
                    p.range.clone(),
                    format!("`{text}`: an arc of more than one turn is not read by ncthread"),
                    "write the turns as separate arcs, or pass --unsupported warn to keep the line opaque",
                );
                return;
            }
        }
        let end = Pos::new(target.x.unwrap_or(sx), target.z.unwrap_or(sz));
        let (ex, ez) = (end.x.unwrap_or(sx), end.z.unwrap_or(sz));
        // The exact values (mm, X a diameter) that LinuxCNC computes with.
        let (s_e, e_e) = (
            (sx_e, sz_e),
            (
                self.exact_target.0.unwrap_or(sx_e),
                self.exact_target.1.unwrap_or(sz_e),
            ),
        );
        // RADIUS_TOLERANCE (0.00005 in, 0.00127 mm) and CENTER_ARC_RADIUS_TOLERANCE
        // (2·0.001·√2 in, 2·0.01·√2 mm); relative 0.001. ncthread's output is in mm: an
        // arc that only the inch tolerance lets through cannot be written, so the mm one
        // applies too.
        let radius_tolerance = 0.00127;
        let spiral_tolerance = 2.0 * 0.01 * std::f64::consts::SQRT_2;
        let spiral_tolerance_in = 2.0 * 0.001 * std::f64::consts::SQRT_2 * 25.4;
        let unit = if self.inch { 25.4 } else { 1.0 };
        let centre_exact = match (r, i.is_some() || k.is_some()) {
            (Some(_), true) => {
                return self.arc_error(
                    line,
                    r,
                    format!(
                        "{g} with both R and I/K (LinuxCNC: \"Mixed radius ijk format for arc\")"
                    ),
                    "give the arc either its radius R or its centre I K",
                );
            }
            (None, false) => {
                return self.arc_error(
                    line,
                    at,
                    format!(
                        "{g} without R, I or K (LinuxCNC: \"R i j k words all missing for arc\")"
                    ),
                    "give the arc its radius (R) or its centre (I for X, K for Z)",
                );
            }
            (Some(r), false) => {
                if target.x.is_none() && target.z.is_none() {
                    return self.arc_error(
                        line,
                        Some(r),
                        format!("{g} R without X or Z (LinuxCNC: \"X and z words missing for arc in xz plane\")"),
                        "an R arc cannot be a full circle: give its end point",
                    );
                }
                if s_e == e_e {
                    return self.arc_error(
                        line,
                        Some(r),
                        format!("{g} R ends where it starts (LinuxCNC: \"Current point same as end point of arc\")"),
                        "an R arc cannot be a full circle: write it with I and K",
                    );
                }
                if (sx, sz) == (ex, ez) {
                    return self.arc_error(
                        line,
                        Some(r),
                        format!("{g} R ends within 0.0001 mm of its start: on ncthread's grid that is a full circle, which an R arc cannot be"),
                        "write the arc with I and K, or end it on the grid",
                    );
                }
                let radius = r.value.to_f64() * unit;
                if radius.abs() < radius_tolerance {
                    let text = &line.text[r.range.clone()];
                    return self.arc_error(
                        line,
                        Some(r),
                        format!("`{text}`: a radius under 0.00127 mm, which ncthread would write as a centre arc that LinuxCNC refuses as zero-radius"),
                        "leave the arc out, or give it a real radius",
                    );
                }
                if !radius.is_finite() || radius.abs() > 1e6 {
                    return self.number_error(
                        line,
                        r,
                        format!(
                            "`{}` is too large for an arc radius",
                            &line.text[r.range.clone()]
                        ),
                        "an arc radius is at most 1,000,000 mm",
                    );
                }
                match lower::arc::centre_from_radius_mm(
                    s_e,
                    e_e,
                    radius,
                    clockwise,
                    radius_tolerance,
                ) {
                    Ok(c) => c,
                    Err(chord) => {
                        let text = &line.text[r.range.clone()];
                        return self.arc_error(
                            line,
                            Some(r),
                            format!("`{text}` is too small for the arc: its end is {chord:.5} mm from its start (LinuxCNC: \"Arc radius too small to reach end point\")"),
                            "the radius must be at least half the distance from the start to the end",
                        );
                    }
                }
            }
            (None, true) => {
                if self.absolute_centres {
                    for (word, letter) in [(i, 'I'), (k, 'K')] {
                        if word.is_none() {
                            return self.arc_error(
                                line,
                                at,
                                format!("{g} without {letter} under G90.1 (LinuxCNC: \"{letter} word missing in absolute center arc\")"),
                                "under G90.1, I and K give the arc's centre: write both",
                            );
                        }
                    }
                }
                // Range checks (and the rounding warning) as for every length word.
                for w in [i, k].into_iter().flatten() {
                    if self.length_times(line, w, 2).is_none() {
                        return;
                    }
                }
                // I is a radius: the centre's diameter is twice it.
                let value = |w: Option<&Word>| w.map_or(0.0, |w| w.value.to_f64() * unit);
                let (i_e, k_e) = (2.0 * value(i), value(k));
                if self.absolute_centres {
                    (i_e + self.axis_offset.0, k_e + self.axis_offset.1)
                } else {
                    (sx_e + i_e, sz_e + k_e)
                }
            }
        };
        if (sx, sz) == (ex, ez) && s_e != e_e {
            return self.arc_error(
                line,
                at,
                format!("{g} ends within 0.0001 mm of its start without ending there: on ncthread's grid that is a full circle"),
                "end the arc on the grid, or write the full circle with the end at the start",
            );
        }
        let (r1, r2) = lower::arc::radii_mm(s_e, e_e, centre_exact);
        let which = if self.absolute_centres {
            "G90.1"
        } else {
            "G91.1"
        };
        if r1 < radius_tolerance || r2 < radius_tolerance {
            return self.arc_error(
                line,
                at,
                format!("{g} with a zero radius: its centre is on its start or its end (LinuxCNC: \"Zero-radius arc\")"),
                &format!("check I and K: under {which} they are {}, I in radius", if self.absolute_centres { "the centre itself" } else { "the centre's offset from the start" }),
            );
        }
        let abs_err = (r1 - r2).abs();
        let rel_err = abs_err / r1.max(r2);
        let off_circle = |tolerance: f64| {
            abs_err > tolerance * 100.0 || (rel_err > 0.001 && abs_err > tolerance)
        };
        if off_circle(if self.inch {
            spiral_tolerance_in
        } else {
            spiral_tolerance
        }) {
            return self.arc_error(
                line,
                at,
                format!(
                    "{g}'s end is not on its circle: the radius is {r1:.5} mm at the start and {r2:.5} mm at the end (LinuxCNC: \"Radius to end of arc differs from radius to start\")"
                ),
                &format!("check I and K: under {which} I is a radius (not halved by G7)"),
            );
        }
        if off_circle(spiral_tolerance) {
            return self.arc_error(
                line,
                at,
                format!(
                    "{g}'s end is {abs_err:.4} mm off its circle: LinuxCNC lets that through in inches, not in millimetres, and ncthread writes millimetres"
                ),
                "put the end on the circle within 0.028 mm",
            );
        }
        if !(centre_exact.0.is_finite() && centre_exact.1.is_finite())
            || centre_exact.0.abs() > 1e9
            || centre_exact.1.abs() > 1e9
        {
            return self.arc_error(
                line,
                at,
                format!("{g}'s centre is more than 1,000 km away"),
                "check I, K or R",
            );
        }
        // The centre, computed from the values as written, rounded once onto the grid.
        let centre = Pos::new(
            Length::from_mm_f64(centre_exact.0),
            Length::from_mm_f64(centre_exact.1),
        );
        // What ncthread writes is the rounded arc: it must pass LinuxCNC's checks too (a
        // value with more than four decimals can sit right at a limit).
        let (q1, q2) = lower::arc::radii(
            (sx, sz),
            (ex, ez),
            (centre.x.unwrap_or(sx), centre.z.unwrap_or(sz)),
        );
        let q_err = (q1 - q2).abs();
        if q1 < radius_tolerance
            || q2 < radius_tolerance
            || q_err > spiral_tolerance * 100.0
            || (q_err / q1.max(q2) > 0.001 && q_err > spiral_tolerance)
        {
            return self.arc_error(
                line,
                at,
                format!("{g} is right at one of LinuxCNC's arc limits: rounded onto ncthread's 0.0001 mm grid (radius {q1:.5} mm at the start, {q2:.5} mm at the end) LinuxCNC would refuse it"),
                "write the arc's values with at most four decimals in mm, away from the limits (a radius of 0.00127 mm; an end 0.028 mm off the circle)",
            );
        }
        let kind = ItemKind::Arc {
            to: end,
            centre: Box::new(centre),
            clockwise,
            feed,
        };
        self.push(kind.clone(), span);
        self.r.pos = kind.end_position(self.r.pos);
        self.exact_after_move(start_exact);
    }

    /// The K word of G33/G33.1 (advance per revolution along the path), positive.
    fn k_word<'b>(
        &mut self,
        line: Line<'_>,
        words: &mut Words<'b>,
        at: Option<&Word>,
        what: &str,
    ) -> Option<&'b Word> {
        match words.take('K') {
            Some(k) if k.value.mantissa > 0 => Some(k),
            Some(k) => {
                self.number_error(
                    line,
                    k,
                    "the lead K is not positive".into(),
                    "K is the advance per spindle revolution, more than 0",
                );
                None
            }
            None => {
                // Point at the code, else an axis word (a modal G33 line may have only X).
                let range = at
                    .or(words.other.get(&'Z').copied())
                    .or(words.other.get(&'X').copied())
                    .map_or(0..line.text.len(), |w| w.range.clone());
                self.diag(
                    codes::ISOR_WORD,
                    line,
                    range,
                    format!("{what} without K (the lead): LinuxCNC needs K on every {what} line"),
                    "write the advance per revolution: `K1.5`",
                );
                None
            }
        }
    }

    fn thread(&mut self, line: Line<'_>, words: &mut Words<'_>, at: Option<&Word>, span: Span) {
        let k = self.k_word(line, words, at, "G33");
        let z_word = words.other.get(&'Z').copied();
        let x_word = words.other.get(&'X').copied();
        let Some(to) = self.target(line, words) else {
            return;
        };
        let Some(k) = k else {
            return;
        };
        if !self.spindle_turning(line, at.or(z_word), "G33") {
            return;
        }
        let from = self.r.pos;
        let end = ItemKind::Rapid { to }.end_position(from);
        let word = z_word.or(x_word).or(at).expect("a G33 line has X or Z");
        // LinuxCNC continues a G33 that follows another without waiting for the index pulse;
        // after anything else that empties its motion queue it would wait, in the cut.
        let start = if self.sync_end.is_some() && self.sync_end == Some(from) {
            SyncStart::Continue
        } else if self.in_cut.is_some() && self.in_cut == Some(from) {
            self.diag(
                codes::ISOR_THREAD_GEOMETRY,
                line,
                word.range.clone(),
                "this G33 starts where a thread move ended, after a line that is not a G33: whether LinuxCNC waits for the index pulse here (with the tool in the cut) depends on its motion queue".into(),
                "write the thread moves on consecutive lines (comments between them are fine), or retract before the next pass",
            );
            return;
        } else {
            SyncStart::Index(Angle::ZERO)
        };
        let dz = match (from.z, end.z) {
            (Some(a), Some(b)) => Some(b - a),
            _ => None,
        };
        let moves_x = to.x.is_some() && to.x != from.x;
        if dz == Some(Length::ZERO) || z_word.is_none() {
            // A synchronised move along X only: K is the advance along X.
            if !moves_x {
                self.diag(
                    codes::ISOR_THREAD_GEOMETRY,
                    line,
                    word.range.clone(),
                    "G33 that does not move".into(),
                    "give the end of the thread with Z (and X for a taper)",
                );
                return;
            }
            let (Some(x), Some(z)) = (end.x, from.z) else {
                self.unknown_start(line, word);
                return;
            };
            if from.x.is_none() {
                self.unknown_start(line, word);
                return;
            }
            let Some(advance) = self.lead(line, k) else {
                return;
            };
            let pass = ThreadPass {
                to: Pos::new(x, z),
                lead: advance,
                start,
                infeed: Some(SyncInfeed { x, advance }),
                entry: None,
                exit: None,
            };
            self.push(ItemKind::pass(pass), span);
            self.r.pos = Pos::new(x, z);
            self.sync_end = Some(self.r.pos);
            self.in_cut = Some(self.r.pos);
            return;
        }
        // K is along the path; the IR's lead is along Z.
        let lead = if moves_x {
            let (Some(x0), Some(dz)) = (from.x, dz) else {
                let w = x_word.expect("X moves");
                self.unknown_start(line, w);
                return;
            };
            let dx = end.x.expect("X is given") - x0;
            let k_mm = k.value.to_f64() * if self.inch { 25.4 } else { 1.0 };
            match lower::z_lead_of_k(k_mm, dz, dx) {
                Some(l) => l,
                None => {
                    self.diag(
                        codes::ISOR_NUMBER,
                        line,
                        k.range.clone(),
                        format!(
                            "`{}` gives no usable lead along Z",
                            &line.text[k.range.clone()]
                        ),
                        "a lead is more than 10⁻¹² mm and at most 1,000,000 mm",
                    );
                    return;
                }
            }
        } else {
            match self.lead(line, k) {
                Some(l) => l,
                None => return,
            }
        };
        let pass = ThreadPass {
            to,
            lead,
            start,
            infeed: None,
            entry: None,
            exit: None,
        };
        self.push(ItemKind::pass(pass), span);
        self.r.pos = pass.end_position(from);
        self.sync_end = Some(self.r.pos);
        self.in_cut = Some(self.r.pos);
    }

    fn unknown_start(&mut self, line: Line<'_>, w: &Word) {
        self.diag(
            codes::ISOR_UNKNOWN_POSITION,
            line,
            w.range.clone(),
            "the move starts from a position that is not known yet".into(),
            "move to the start with absolute X and Z first",
        );
    }

    fn tap(&mut self, line: Line<'_>, words: &mut Words<'_>, at: Option<&Word>, span: Span) {
        let k = self.k_word(line, words, at, "G33.1");
        let x_word = words.other.get(&'X').copied();
        let z_word = words.other.get(&'Z').copied();
        let Some(to) = self.target(line, words) else {
            return;
        };
        let (Some(k), Some(z_word)) = (k, z_word) else {
            if let (None, Some(at)) = (z_word, at) {
                self.missing(
                    line,
                    at,
                    "G33.1 without Z (the depth of the hole)".into(),
                    "write `G33.1 Z-20 K1.5`",
                );
            }
            return;
        };
        if let (Some(x), Some(w)) = (to.x, x_word)
            && Some(x) != self.r.pos.x
        {
            self.diag(
                codes::ISOR_THREAD_GEOMETRY,
                line,
                w.range.clone(),
                "G33.1 that also moves X".into(),
                "move to the hole's X first; the tap runs along Z only",
            );
            return;
        }
        if !self.spindle_turning(line, at, "G33.1") {
            return;
        }
        if self.r.pos.z.is_none() {
            self.unknown_start(line, z_word);
            return;
        }
        let Some(lead) = self.lead(line, k) else {
            return;
        };
        self.push(
            ItemKind::TapCycle(TapCycle {
                end_z: to.z.expect("Z is given"),
                lead,
                then_x: None,
            }),
            span,
        );
    }

    fn g76_error(&mut self, line: Line<'_>, w: &Word, message: String, help: &str) {
        self.diag(codes::ISOR_G76, line, w.range.clone(), message, help);
    }

    /// LinuxCNC's G76 (`convert_threading_cycle`) as a thread cycle.
    fn cycle(&mut self, line: Line<'_>, words: &mut Words<'_>, at: Option<&Word>, span: Span) {
        let Some(at) = at.or(words.other.get(&'Z').copied()) else {
            return;
        };
        let mut get = |l: char| words.take(l);
        let (p, i, j, k) = (get('P'), get('I'), get('J'), get('K'));
        let (r, q, h, e, l) = (get('R'), get('Q'), get('H'), get('E'), get('L'));
        let z_given = words.other.contains_key(&'Z');
        let Some(to) = self.target(line, words) else {
            return;
        };
        let (Some(p), Some(i), Some(j), Some(k), true) = (p, i, j, k, z_given) else {
            let missing: String = [
                ('P', p),
                ('Z', words.other.get(&'Z').copied()),
                ('I', i),
                ('J', j),
                ('K', k),
            ]
            .iter()
            .filter(|(_, w)| w.is_none())
            .map(|(c, _)| c.to_string())
            .collect::<Vec<_>>()
            .join(", ");
            self.missing(
                line,
                at,
                format!("G76 without {missing}"),
                "G76 needs P (pitch), Z (end), I (crest offset from the drive line), J (first depth) and K (thread depth)",
            );
            return;
        };
        // LinuxCNC's own checks, on the numbers as written.
        let (iv, jv, kv) = (i.value.to_f64(), j.value.to_f64(), k.value.to_f64());
        if iv == 0.0 {
            return self.g76_error(
                line,
                i,
                "in G76, I must not be 0".into(),
                "I is the crest's offset from the drive line: negative outside, positive in a bore",
            );
        }
        if jv <= 0.0 {
            return self.g76_error(
                line,
                j,
                "in G76, J must be greater than 0".into(),
                "J is the depth of the first pass",
            );
        }
        if kv <= jv {
            return self.g76_error(
                line,
                k,
                "in G76, K must be greater than J".into(),
                "K is the full thread depth, J the first pass's",
            );
        }
        if p.value.mantissa <= 0 {
            return self.g76_error(
                line,
                p,
                "the G76 pitch P is not positive".into(),
                "P is the advance per spindle revolution",
            );
        }
        let (Some(start_x), Some(start_z)) = (self.r.pos.x, self.r.pos.z) else {
            return self.unknown_start(line, at);
        };
        if !self.spindle_turning(line, Some(at), "G76") {
            return;
        }
        let diameter = self.diameter.unwrap_or(false);
        let Some(lead) = self.lead(line, p) else {
            return;
        };
        let (Some(i_len), Some(j_len), Some(k_len)) = (
            self.length(line, i),
            self.length(line, j),
            self.length(line, k),
        ) else {
            return;
        };
        // Per side (radius) and as a diameter, scaled as LinuxCNC scales them.
        let scale = IjkScale::of_modes(self.diameter_before_line, diameter);
        let side = |v: Length| scale.length(v);
        let i_dia = side(i_len) + side(i_len);
        let depth = side(k_len);
        let first = side(j_len);
        let height = side(i_len.abs() + k_len);
        let spring_passes = match h {
            Some(h) => match self.whole(line, h, "the number of spring passes H") {
                Some(v) => v,
                None => return,
            },
            None => 0,
        };
        let flags = match l {
            Some(l) => match l.value.to_whole() {
                Ok(v) if v >= 0 => v,
                Ok(_) => {
                    return self.number_error(
                        line,
                        l,
                        "G76 L is negative (LinuxCNC: \"Negative l word used\")".into(),
                        "L0 none, L1 entry taper, L2 exit taper, L3 both",
                    );
                }
                Err(_) => {
                    return self.number_error(
                        line,
                        l,
                        "G76 L is not a whole number".into(),
                        "L0 none, L1 entry taper, L2 exit taper, L3 both",
                    );
                }
            },
            None => 0,
        };
        let taper = match e {
            Some(e) => match self.length(line, e) {
                Some(v) => v.max(Length::ZERO),
                None => return,
            },
            None => Length::ZERO,
        };
        let chamfer = |on: bool| {
            (on && taper.0 > 0).then_some(CycleChamfer {
                length: taper,
                rise: Rise::ThreadDepth,
            })
        };
        let entry = chamfer(flags & 1 != 0);
        let runout = chamfer(flags & 2 != 0);
        // Q as LinuxCNC reads it (an unwritten Q is −1 there, and −1 means 0).
        let q_deg = q.map_or(0.0, |q| q.value.to_f64());
        let q_deg = if q_deg == -1.0 { 0.0 } else { q_deg };
        if q_deg.abs() >= 90.0
            && let Some(q) = q
        {
            return self.g76_error(
                line,
                q,
                "the compound angle Q must be less than 90°".into(),
                "Q is the infeed angle from the radial, usually 29.5",
            );
        }
        let infeed = Slope {
            rise: (q_deg.to_radians().tan() * SLOPE_RUN as f64).round() as i64,
            run: SLOPE_RUN,
        };
        let end_z = to.z.expect("Z is given");
        let cycle = ThreadCycle {
            start: (start_x, start_z),
            crest: start_x + i_dia,
            end_z,
            lead,
            depth,
            first_depth: first,
            taper: Length::ZERO,
            infeed,
            infeed_moves_end: true,
            start_angle: Angle::ZERO,
            entry,
            // With an entry taper LinuxCNC feeds in along X, synchronised, from the retract
            // height to the entry's start. **[evidence]** `threading_pass`.
            entry_infeed: entry.is_some(),
            runout,
            retract: Retract::AboveCut(height),
            spring_passes,
            finish: Finish::EndAt(to.x.unwrap_or(start_x)),
            internal: iv > 0.0,
            schedule: Schedule::Degression(Degression {
                r: r.map_or(Decimal::parse("1").expect("a number"), |r| r.value),
                i: i.value,
                j: j.value,
                k: k.value,
                scale,
                inch: self.inch,
            }),
        };
        if let Err(err) = lower::expand(&cycle) {
            return self.g76_error(
                line,
                at,
                err.message(&cycle),
                "correct the G76 words; ncthread cuts a cycle only when every pass is defined",
            );
        }
        self.r.pos = Pos::new(to.x.unwrap_or(start_x), end_z);
        self.push(ItemKind::ThreadCycle(Box::new(cycle)), span);
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::diag::Severity;

    /// The first error of `d` (read from `text`), held to its code and the text it marks.
    pub(super) fn first_error<'d>(
        d: &'d [Diagnostic],
        text: &str,
        code: Code,
        marked: &str,
    ) -> &'d Diagnostic {
        let e = d
            .iter()
            .find(|d| d.severity == Severity::Error)
            .unwrap_or_else(|| panic!("{text:?}: no error in {d:?}"));
        assert_eq!(e.code, code, "{text:?}: {e:?}");
        let loc = e.location.as_ref().unwrap();
        assert_eq!(&loc.source_line[loc.range.clone()], marked, "{text:?}");
        e
    }

    /// An error in a loop's body is reported once, and the run stops there rather than go
    /// round to the loop limit (it reported the error 200,000 times); so does a loop whose
    /// body an earlier error cut short.
    #[test]
    fn a_loop_does_not_go_round_after_an_error() {
        let endless = "G7 G18 G21 G95 F0.1\nS500 M3\nG0 X30 Z2\no1 while [1]\n  G1 X30 Z-20 X32\no1 endwhile\nM30\n";
        let (_, d) = run(endless);
        assert_eq!(d.iter().filter(|d| d.is_error()).count(), 1, "{d:?}");
        let cut_short = "G7 G18 G21 G95 F0.1\nS500 M3\n#1 = 38\no1 do\n  G0 X#1 Z2\n  #1 = [#1 - 2] =\no1 while [#1 GE 34]\nM30\n";
        let (_, d) = run(cut_short);
        let errors: Vec<_> = d.iter().filter(|d| d.is_error()).collect();
        assert_eq!(errors.len(), 1, "{d:?}");
        assert_ne!(errors[0].code, codes::ISOR_CONTROL, "{d:?}");
    }

    /// Reads a fragment: without its program end (ISOR013, tested on its own).
    pub(super) fn run(text: &str) -> (Program, Vec<Diagnostic>) {
        let (p, d) = parse(&SourceFile::new("t.ngc", text), &Options::default());
        (
            p,
            d.into_iter()
                .filter(|d| d.code != codes::ISOR_NO_END)
                .collect(),
        )
    }

    #[test]
    fn programs_end_as_linuxcnc_ends_them() {
        let codes_of = |text: &str| -> Vec<&str> {
            let (_, d) = parse(&SourceFile::new("t.ngc", text), &Options::default());
            d.iter().map(|d| d.code.id).collect()
        };
        // No end: LinuxCNC runs it and then complains; a warning here.
        assert_eq!(codes_of("G7 G0 X10 Z1\n"), ["ISOR013"]);
        assert!(codes_of("G7 G0 X10 Z1\nM2\n").is_empty());
        assert!(codes_of("%\nG7 G0 X10 Z1\n%\n").is_empty());
        // After the closing `%` or M2 nothing is read.
        let (p, d) = parse(
            &SourceFile::new("t.ngc", "%\nG7 G0 X10 Z1\n%\nG0 X5\n"),
            &Options::default(),
        );
        assert_eq!(d[0].code, codes::ISOR_AFTER_END);
        assert_eq!(p.items.len(), 3);
        // A `%` elsewhere, a NUL, and motion codes without axes are refused as LinuxCNC does.
        assert_eq!(codes_of("G7 G0 X10 Z1\n%\nM2\n"), ["ISOR001"]);
        assert_eq!(codes_of("G7 G0 X10 Z1 %\nM2\n"), ["ISOR001"]);
        assert_eq!(codes_of("(a\0b)\nM2\n"), ["ISOR001"]);
        assert_eq!(codes_of("G7 S100 M3\nG33 K1\nM2\n"), ["ISOR004"]);
        assert_eq!(codes_of("G7 G95 G1\nM2\n"), ["ISOR004"]);
    }

    fn kinds(p: &Program) -> Vec<ItemKind> {
        p.items.iter().map(|i| i.kind.clone()).collect()
    }

    fn mm(v: f64) -> Length {
        Length::from_mm_f64(v)
    }

    const HEAD: &str = "G7 G18 G21 G90 G95\nS500 M3\n";

    #[test]
    fn reads_what_ncthread_writes() {
        let text = format!(
            "%\n(a.nc, dialect nc31)\n{HEAD}G0 X35.6 Z4.5\nG33 X35.6 Z-47.5 K1.5\nG0 X37\nM30\n%\n"
        );
        let (p, d) = run(&text);
        assert!(d.is_empty(), "{d:?}");
        let k = kinds(&p);
        assert_eq!(k[0], ItemKind::Delimiter);
        assert_eq!(k[1], ItemKind::Comment("a.nc, dialect nc31".into()));
        assert_eq!(k[2], ItemKind::FeedMode(FeedMode::PerRev));
        assert_eq!(
            k[5],
            ItemKind::pass(ThreadPass {
                to: Pos::new(mm(35.6), mm(-47.5)),
                lead: crate::fixed::Lead::from_mm_f64(1.5).unwrap(),
                start: crate::ir::SyncStart::Index(Angle::ZERO),
                infeed: None,
                entry: None,
                exit: None,
            })
        );
        assert_eq!(k[7], ItemKind::ProgramEnd(EndCode::M30));
    }

    #[test]
    fn taper_k_is_along_the_path() {
        // iso.md: Ø226 → Ø246, Z3 → Z−100, K1.50705289 is a Z lead of 1.5.
        let (p, d) = run(&format!("{HEAD}G0 X226 Z3\nG33 X246 Z-100 K1.50705289\n"));
        assert!(d.is_empty(), "{d:?}");
        let ItemKind::ThreadPass(pass) = &p.items.last().unwrap().kind else {
            panic!()
        };
        // K has 8 decimals: the Z lead is 1.5 within 2·10⁻⁹ mm (a drift of 10⁻⁷ mm over the
        // thread), kept as it is rather than rounded onto a coarser grid.
        assert_eq!(pass.lead, Lead(1_500_000_001_751));
        // A tapered G33 with a round K: its Z lead is K·ΔZ/length, not K.
        let (p, _) = run(&format!("{HEAD}G0 X30 Z5\nG33 X40 Z-295 K1.5\n"));
        let ItemKind::ThreadPass(pass) = &p.items.last().unwrap().kind else {
            panic!()
        };
        assert_eq!(pass.lead, Lead(1_499_791_710_059));
    }

    #[test]
    fn radius_mode_inches_and_incremental() {
        // No G7: X is a radius (with a warning); G20 converts; G91 adds.
        let (p, d) = run("G20 G0 X1 Z0.1\nG91 G0 Z-0.5\n");
        assert_eq!(d.len(), 1);
        assert_eq!(d[0].code, codes::ISOR_RADIUS_MODE);
        let k = kinds(&p);
        assert_eq!(
            k[0],
            ItemKind::Rapid {
                to: Pos::new(mm(50.8), mm(2.54))
            }
        );
        assert_eq!(
            k[1],
            ItemKind::Rapid {
                to: Pos {
                    x: None,
                    z: Some(mm(-10.16))
                }
            }
        );
        // 0.0001 inch is 0.00254 mm: rounded once, with one warning.
        let (_, d) = run("G7 G20 G0 X0.0001\nG0 X0.0003\n");
        assert_eq!(
            d.iter().filter(|d| d.code == codes::ISOR_ROUNDED).count(),
            1
        );
    }

    #[test]
    fn feed_mode_defaults_to_per_minute() {
        let (p, d) = run("G7 G0 X10 Z0\nG1 Z-5 F100\n");
        assert!(d.is_empty(), "{d:?}");
        let k = kinds(&p);
        assert_eq!(k[1], ItemKind::FeedMode(FeedMode::PerMin));
        assert_eq!(
            k[2],
            ItemKind::Feed {
                to: Pos {
                    x: None,
                    z: Some(mm(-5.0))
                },
                feed: mm(100.0)
            }
        );
    }

    /// Arc centres as LinuxCNC places them (the R centres checked against rs274's ARC_FEED
    /// for the same lines: `tests/oracle.rs` runs the corpus part programs).
    #[test]
    fn arcs_take_their_centres_as_linuxcnc_does() {
        let arc = |text: &str| {
            let (p, d) = run(text);
            assert!(!crate::diag::has_errors(&d), "{text:?}: {d:?}");
            match kinds(&p)
                .into_iter()
                .rev()
                .find(|k| matches!(k, ItemKind::Arc { .. }))
            {
                Some(ItemKind::Arc {
                    to,
                    centre,
                    clockwise,
                    ..
                }) => (to, *centre, clockwise),
                other => panic!("{text:?}: {other:?}"),
            }
        };
        // G91.1 (the start-up mode): I and K from the start, I in radius even under G7.
        let (to, centre, cw) = arc("G7 G0 X20 Z0\nG3 X30 Z-5 I0 K-5 F1\n");
        assert_eq!(
            (to, centre, cw),
            (
                Pos::new(mm(30.0), mm(-5.0)),
                Pos::new(mm(20.0), mm(-5.0)),
                false
            )
        );
        let (_, centre, cw) = arc("G7 G0 X24 Z-20\nG3 X30 Z-23 K-3 F1\n");
        assert_eq!((centre, cw), (Pos::new(mm(24.0), mm(-23.0)), false));
        // G90.1: I and K are the centre (I a radius).
        let (_, centre, _) = arc("G7 G0 X30 Z-30\nG90.1 G2 X36 Z-33 I18 K-30 F1\n");
        assert_eq!(centre, Pos::new(mm(36.0), mm(-30.0)));
        // G8: X words are radii, I too.
        let (to, centre, _) = arc("G8 G0 X15 Z-30\nG2 X18 Z-33 I3 K0 F1\n");
        assert_eq!(
            (to, centre),
            (Pos::new(mm(36.0), mm(-33.0)), Pos::new(mm(36.0), mm(-30.0)))
        );
        // R: G2 with R > 0 turns right of its chord (the short arc), R < 0 the long one;
        // the helper's reading of `arc_data_r`: from r10 Z0 to r15 Z-5 with R5, G2's
        // centre is r15 Z0 and G3's r10 Z-5.
        let (_, centre, cw) = arc("G7 G0 X20 Z0\nG2 X30 Z-5 R5 F1\n");
        assert_eq!((centre, cw), (Pos::new(mm(30.0), mm(0.0)), true));
        let (_, centre, _) = arc("G7 G0 X20 Z0\nG2 X30 Z-5 R-5 F1\n");
        assert_eq!(centre, Pos::new(mm(20.0), mm(-5.0)));
        let (_, centre, _) = arc("G7 G0 X20 Z0\nG3 X30 Z-5 R5 F1\n");
        assert_eq!(centre, Pos::new(mm(20.0), mm(-5.0)));
        // A semicircle whose R is short by less than 0.00127 mm is one.
        let (_, centre, _) = arc("G7 G0 X0 Z0\nG2 Z-10 R4.9995 F1\n");
        assert_eq!(centre, Pos::new(mm(0.0), mm(-5.0)));
        // Inches: the centre in mm.
        let (_, centre, _) = arc("G20 G7 G0 X1 Z0\nG3 X1 Z-1 K-0.5 F1\n");
        assert_eq!(centre, Pos::new(mm(25.4), mm(-12.7)));
        // P within 0.001 of 1 is one turn, as in LinuxCNC.
        let (_, centre, _) = arc("G7 G0 X20 Z0\nG3 X30 Z-5 I0 K-5 P1.0005 F1\n");
        assert_eq!(centre, Pos::new(mm(20.0), mm(-5.0)));
        // The R centre is computed from the end as written, not from its rounding: near a
        // semicircle 0.00004 mm of X moves LinuxCNC's centre 0.007 mm along Z.
        let (_, centre, _) = arc("G8 G0 X10 Z0\nG2 X20.00004 Z0 R5.00003 F1\n");
        assert_eq!(centre, Pos::new(mm(30.0), mm(0.01)));
        // A full circle with I/K.
        let (to, centre, _) = arc("G7 G0 X20 Z0\nG2 I-5 F1\n");
        assert_eq!(
            (to, centre),
            (Pos::new(mm(20.0), mm(0.0)), Pos::new(mm(10.0), mm(0.0)))
        );
    }

    /// Increments add to the position as written and are rounded once: 50 increments of
    /// 1.00004 mm end at 50.002 mm, not 50 mm.
    #[test]
    fn increments_do_not_accumulate_rounding() {
        let text = format!("G7 G0 X10 Z0\nG91\n{}", "G1 Z-1.00004 F1\n".repeat(50));
        let (p, _) = run(&text);
        let end = p
            .items
            .iter()
            .fold(Pos::UNKNOWN, |pos, i| i.kind.end_position(pos));
        assert_eq!(end.z, Some(mm(-50.002)));
    }

    #[test]
    fn tool_change_stops_the_spindle_like_linuxcnc() {
        let (p, d) = run(&format!("{HEAD}T5 M6 G43\n"));
        assert!(d.is_empty(), "{d:?}");
        let k = kinds(&p);
        assert_eq!(
            k[2],
            ItemKind::Tool {
                number: Some(5),
                offset: Some(5)
            }
        );
        assert_eq!(k[3], ItemKind::SpindleStop);
    }

    #[test]
    fn refusals_name_the_word() {
        let cases: &[(&str, Code, &str)] = &[
            ("G7 G0 X1\nG19 G1 X2 Z0 F1\n", codes::ISOR_NOT_LATHE, "G19"),
            (
                "G7 G17 G21 G95\nS400 M3\nG0 X20 Z2\nG2 X24 Z-2 K-2 F0.1\n",
                codes::ISOR_ARC,
                "G2",
            ),
            (
                "G7 G17 G21 G95\nG0 X20 Z2\nG71 Q100 X1 Z1 D0.5 I1 R0.3\n",
                codes::ISOR_ROUGHING,
                "G71",
            ),
            (
                "G7 G17 G21 G95\nG0 X20 Z2\nG41 D1\n",
                codes::ISOR_COMPENSATION,
                "G41",
            ),
            ("G7 G0 X1 Z0\nG2 X2 Z-1 R1\n", codes::ISOR_WORD, "G2"),
            ("G7 G0 X1 Z0\nG2 X2 Z-1 R1 I1 F1\n", codes::ISOR_ARC, "R1"),
            ("G7 G0 X1 Z0\nG2 X2 Z-1 F1\n", codes::ISOR_ARC, "G2"),
            ("G7 G0 X0 Z0\nG2 X0 Z-10 R4 F1\n", codes::ISOR_ARC, "R4"),
            (
                "G7 G0 X0 Z0\nG2 Z-10 R4.998 F1\n",
                codes::ISOR_ARC,
                "R4.998",
            ),
            ("G7 G0 X0 Z0\nG3 X0 Z0 R5 F1\n", codes::ISOR_ARC, "R5"),
            ("G7 G0 X0 Z0\nG3 R5 F1\n", codes::ISOR_ARC, "R5"),
            ("G7 G0 X0 Z0\nG2 X0 Z-10 K-5.1 F1\n", codes::ISOR_ARC, "G2"),
            ("G7 G0 X0 Z0\nG2 X0 Z-10 I0 F1\n", codes::ISOR_ARC, "G2"),
            (
                "G7 G0 X0 Z0\nG90.1 G2 X0 Z-10 K-5 F1\n",
                codes::ISOR_ARC,
                "G2",
            ),
            (
                "G7 G0 X0 Z0\nG2 X0 Z-10 K-5 P2 F1\n",
                codes::ISOR_UNSUPPORTED,
                "P2",
            ),
            ("G7 G0 X0 Z0\nG2 X0 Z-10 K-5 P0 F1\n", codes::ISOR_ARC, "P0"),
            ("G2 X0 Z-10 K-5 F1\n", codes::ISOR_UNKNOWN_POSITION, "G2"),
            // Findings of the differential arc campaign against rs274.
            (
                "G7 G0 X20 Z0\nG2 X30 Z-5 R1000000000000000 F1\n",
                codes::ISOR_NUMBER,
                "R1000000000000000",
            ),
            (
                "G8 G0 X10 Z0\nG2 X10 Z-0.002 R0.001 F1\n",
                codes::ISOR_ARC,
                "R0.001",
            ),
            (
                "G7 G0 X20 Z0\nG2 G4 X30 Z-5 R5 P1 F1\n",
                codes::ISOR_ARC,
                "G4",
            ),
            (
                "G7 G0 X20 Z0\nG90.1 G91.1 G2 X30 Z-5 I0 K-5 F1\n",
                codes::ISOR_CONFLICT,
                "G91.1",
            ),
            (
                "G7 G0 X20 Z0\nG2 X30 Z-5 I0 K-5 P1.4 F1\n",
                codes::ISOR_ARC,
                "P1.4",
            ),
            (
                "G20 G8 G0 X1 Z0\nG2 X1 Z-0.202 I0 K-0.1 F1\n",
                codes::ISOR_ARC,
                "G2",
            ),
            (
                "G8 G0 X10 Z0\nG2 X17.09106 Z-17.09106 I0 K-10 F1\n",
                codes::ISOR_ARC,
                "G2",
            ),
            // An I/K arc whose end rounds onto its start would become a full circle.
            (
                "G7 G0 X20 Z0\nG2 X20 Z-0.00001 I5 K0 F1\n",
                codes::ISOR_ARC,
                "G2",
            ),
            // Whole-part codes LinuxCNC refuses.
            ("G7 S100 M3\nG96 D2500\n", codes::ISOR_WORD, "G96"),
            ("G7 S100 M3\nG96 D0 S200\n", codes::ISOR_WORD, "G96"),
            ("G7\nG53 X10\n", codes::ISOR_WORD, "G53"),
            ("G7 G0 X1 Z0\nG41.1 L3\n", codes::ISOR_WORD, "G41.1"),
            ("G7 G0 X1 Z0\nG41\nG42\n", codes::ISOR_COMPENSATION, "G42"),
            ("G7 G0 X1 Z0\nG41\nT2 M6\n", codes::ISOR_COMPENSATION, "M6"),
            ("G7 G0 X1 Z0\nG41\nG28\n", codes::ISOR_COMPENSATION, "G28"),
            ("G7 G0 X1 Z0\nG41\nG55\n", codes::ISOR_COMPENSATION, "G55"),
            (
                "G7 S100 M3\nG0 X10 Z1\nG41\nG33 Z-10 K1\n",
                codes::ISOR_COMPENSATION,
                "G33",
            ),
            (
                "G7 S100 M3\nG0 X10 Z1\nG41\nG76 P1 Z-10 I-1 J0.1 K1\n",
                codes::ISOR_COMPENSATION,
                "G76",
            ),
            ("G7 G0 X1 Z0\nG19\n", codes::ISOR_NOT_LATHE, "G19"),
            ("G0 Y1\n", codes::ISOR_NOT_LATHE, "Y1"),
            ("G0 X[1/0]\n", codes::ISOR_EVAL, "1/0"),
            ("G0 X#<nope>\n", codes::ISOR_EVAL, "#<nope>"),
            ("#1 = SQRT[-1]\n", codes::ISOR_EVAL, "SQRT[-1]"),
            ("#5221 = 1\n", codes::ISOR_EVAL, "#5221 = 1"),
            ("#<_x> = 1\n", codes::ISOR_EVAL, "#<_x> = 1"),
            ("o<nope> call\n", codes::ISOR_CONTROL, "o<nope> call"),
            ("G7 S100 M3\nM72\n", codes::ISOR_CONTROL, "M72"),
            ("G7 S100 M3\nM70 G91\n", codes::ISOR_UNSUPPORTED, "M70"),
            ("o1 while [1]\nG0 X1\n", codes::ISOR_CONTROL, "o1 while [1]"),
            (
                "o1 while [1]\no2 endwhile\n",
                codes::ISOR_CONTROL,
                "o1 while [1]",
            ),
            ("G0 X1 X2\n", codes::ISOR_CONFLICT, "X2"),
            ("G0 G1 X1\n", codes::ISOR_CONFLICT, "G1"),
            ("G7 G0 X1 Z1 K2\n", codes::ISOR_WORD, "K2"),
            ("G7 G0 X10 Z1\nG33 Z-10 K1\n", codes::ISOR_SPINDLE, "G33"),
            (
                "G7 S100 M3\nG0 X10 Z1\nG33 X10 K1\n",
                codes::ISOR_THREAD_GEOMETRY,
                "X10",
            ),
            ("G7 S100 M3\nG0 X10 Z1\nG33 Z-10\n", codes::ISOR_WORD, "G33"),
            ("G7 G1 X1 Z1\n", codes::ISOR_WORD, "G1"),
            ("G91 G7 G0 X1\n", codes::ISOR_UNKNOWN_POSITION, "X1"),
            ("X1\n", codes::ISOR_WORD, "X1"),
            (
                "G7 S100 M3\nG0 X10 Z1\nG33.1 X12 Z-5 K1\n",
                codes::ISOR_THREAD_GEOMETRY,
                "X12",
            ),
            (
                "G7 S100 M3\nG0 X10 Z1\nG76 P1 Z-10 I0 J0.1 K1\n",
                codes::ISOR_G76,
                "I0",
            ),
            (
                "G7 S100 M3\nG0 X10 Z1\nG76 P1 Z-10 I-1 J1 K1\n",
                codes::ISOR_G76,
                "K1",
            ),
            (
                "G7 S100 M3\nG0 X10 Z1\nG76 P1 Z-10 I-1 K1\n",
                codes::ISOR_WORD,
                "G76",
            ),
            ("G0 X1 (open\n", codes::ISOR_SYNTAX, "("),
            // An O-word line that cannot be read, in a branch that is not run: reported
            // all the same (its branch structure would be guessed).
            (
                "G7 G0 X1 Z0\n#1=5\no1 if [#1 LT 2]\no1 elseif [#1 LT 20] ?\no1 endif\nM2\n",
                codes::ISOR_SYNTAX,
                "?",
            ),
        ];
        for (text, code, marked) in cases {
            let src = SourceFile::new("t.ngc", *text);
            let (_, d) = parse(&src, &Options::default());
            first_error(&d, text, *code, marked);
        }
    }

    #[test]
    fn unsupported_warn_keeps_the_line_and_forgets_the_position() {
        let src = SourceFile::new("t.ngc", "G7 G0 X10 Z1\nG10 L2 P1 X0\nG0 X5\n");
        let (p, d) = parse(
            &src,
            &Options {
                unsupported: Unsupported::Warn,
                block_delete: None,
                subroutine_path: Vec::new(),
            },
        );
        let d: Vec<_> = d
            .into_iter()
            .filter(|d| d.code != codes::ISOR_NO_END)
            .collect();
        assert_eq!(d.len(), 1);
        assert_eq!(d[0].severity, Severity::Warning);
        assert!(
            matches!(&p.items[1].kind, ItemKind::Opaque { block: Some(_), text, .. } if text == "G10 L2 P1 X0")
        );
        assert!(matches!(p.items[2].kind, ItemKind::Rapid { to } if to.z.is_none()));
    }

    /// A kept line that cannot move (a block-deleted path setting) leaves the position
    /// known: the thread after it is read (issue 14, found on LinuxCNC's own g33_blend).
    #[test]
    fn a_kept_line_that_cannot_move_keeps_the_position() {
        let src = SourceFile::new(
            "t.ngc",
            "G7 G95 S300 M3\nG0 X10 Z1\n/G64 P0.002 Q0.001\nG33 Z-10 K1.5\nM30\n",
        );
        let (p, d) = parse(
            &src,
            &Options {
                unsupported: Unsupported::Warn,
                block_delete: None,
                subroutine_path: Vec::new(),
            },
        );
        assert!(!crate::diag::has_errors(&d), "{d:?}");
        let kept = p
            .items
            .iter()
            .find_map(|i| match &i.kind {
                ItemKind::Opaque { block: Some(c), .. } => Some(c.moves),
                _ => None,
            })
            .expect("the line is kept");
        assert!(!kept);
        assert!(
            p.items
                .iter()
                .any(|i| matches!(i.kind, ItemKind::ThreadPass(_)))
        );
        // With an axis word it may move: the position after it is unknown.
        let src = SourceFile::new("t.ngc", "G7 G0 X10 Z1\n/G0 X20\nG0 X5\nM30\n");
        let (p, _) = parse(
            &src,
            &Options {
                unsupported: Unsupported::Warn,
                block_delete: None,
                subroutine_path: Vec::new(),
            },
        );
        let end = p
            .items
            .iter()
            .fold(Pos::UNKNOWN, |pos, i| i.kind.end_position(pos));
        assert_eq!(end.z, None);
    }

    #[test]
    fn block_delete_follows_the_switch_or_is_refused() {
        let src = SourceFile::new(
            "t.ngc",
            "G7 G18 G21 G95\nS500 M3\nG0 X20 Z2\n/G1 Z-10 F0.1\n/ G0 X30\nG0 X40\nM30\n",
        );
        let read = |block_delete| {
            parse(
                &src,
                &Options {
                    unsupported: Unsupported::Error,
                    block_delete,
                    subroutine_path: Vec::new(),
                },
            )
        };
        let moves = |p: &Program| {
            p.items
                .iter()
                .filter(|i| matches!(i.kind, ItemKind::Rapid { .. } | ItemKind::Feed { .. }))
                .count()
        };
        // Off: the lines run (LinuxCNC's default).
        let (p, d) = read(Some(BlockDelete::Off));
        assert!(d.is_empty(), "{d:?}");
        assert_eq!(moves(&p), 4);
        // On: they are skipped, with one warning at the first.
        let (p, d) = read(Some(BlockDelete::On));
        assert_eq!(moves(&p), 2);
        assert_eq!(d.len(), 1, "{d:?}");
        assert_eq!(d[0].code, codes::ISOR_BLOCK_DELETE);
        assert_eq!(
            d[0].location.as_ref().map(|l| (l.line, l.column)),
            Some((4, 1))
        );
        // Not said: refused at the `/`.
        let (_, d) = read(None);
        let errors: Vec<_> = d.iter().filter(|d| d.is_error()).collect();
        assert_eq!(errors.len(), 2, "{d:?}");
        assert_eq!(errors[0].code, codes::ISOR_UNSUPPORTED);
        assert_eq!(
            errors[0].location.as_ref().map(|l| (l.line, l.column)),
            Some((4, 1))
        );
    }

    #[test]
    fn g76_reads_linuxcnc_words() {
        // The LinuxCNC example shape: drive line Ø20 Z5, I-1 J0.4 K1.8 (diameters, G7),
        // R2, Q29.5, H1, E2 L3.
        let text = format!("{HEAD}G0 X20 Z5\nG76 P1.5 Z-20 I-1 J0.4 K1.8 Q29.5 R2 H1 E2 L3\n");
        let (p, d) = run(&text);
        assert!(d.is_empty(), "{d:?}");
        let ItemKind::ThreadCycle(c) = &p.items.last().unwrap().kind else {
            panic!()
        };
        assert_eq!(c.crest, mm(19.0));
        assert_eq!((c.depth, c.first_depth), (mm(0.9), mm(0.2)));
        assert_eq!(c.retract, Retract::AboveCut(mm(1.4)));
        assert_eq!(c.spring_passes, 1);
        assert!(!c.internal);
        assert!(c.entry_infeed);
        assert_eq!(c.start_angle, Angle::ZERO);
        let e = lower::expand(c).unwrap();
        // 0.2·√n < 0.9 for n = 1…20, then the full depth and one spring pass.
        assert_eq!(e.passes.len(), 22);
        let p1 = e.passes[0];
        // Pass 1: line Ø18.6 from Z5 − 0.2·tan 29.5° = 4.8868 (rs274: X9.3 Z4.8868).
        assert_eq!(p1.start, Pos::new(mm(20.4), mm(4.8868)));
        assert_eq!(p1.pass.to, Pos::new(mm(18.6), mm(-19.604)));
        // rs274: a rapid back to X10.7 (Ø21.4), then in along X, synchronised at
        // K_taper = 1.5·√(2² + 0.9²)/2 = 1.644878 per rev, to X10.2 (Ø20.4).
        assert_eq!(
            e.moves[0].kind,
            lower::Move::Rapid(Pos::new(mm(21.4), mm(4.8868)))
        );
        let infeed = p1.pass.infeed.unwrap();
        assert_eq!(infeed.x, mm(20.4));
        assert_eq!(infeed.advance.mm(), "1.64487841496");
        let last = e.passes[21];
        assert_eq!(last.pass.to, Pos::new(mm(17.2), mm(-20.0)));
        assert_eq!(last.retract_x, mm(20.0));
    }
}

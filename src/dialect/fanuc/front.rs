//! The FANUC front end: blocks → IR items, with the dialect's rules as diagnostics.
//!
//! Modal state: the motion (G00, G01, G02, G03, G32 and the G92 threading cycle), inch or
//! mm (G20/G21, before the first move), feed per minute or per revolution (G98/G99), the
//! spindle's mode (G96/G97) and its limit (G50 S), and the one F register, which holds a
//! feed or a lead. X is a diameter; U and W are incremental X (diameter) and Z.
//!
//! In one block, F, S, T, M03/M04 and M07/M08 take effect before the motion; M05, M09,
//! M00/M01 and M02/M30 after it. **\[decided\]** (the order most machine builders give; a
//! program that depends on another order is rare, and the translation test encodes this
//! one.) The block is read as a block interpreter reads it (`front/block.rs`): its words
//! sorted by modal group, then one step per group in one order; `front/numbers.rs` reads
//! the words' numbers, `front/motion.rs` the dwell and the moves.

use std::ops::Range;

use super::macros;
use super::syntax::{self, Block, Word};
use crate::diag::{Code, Diagnostic};
use crate::dialect::Unsupported;
use crate::dialect::fanuc::codes;
use crate::dialect::fanuc::profile::{DecimalPoint, FanucProfile};
use crate::dialect::read::{Keep, Reader, UnsupportedWording};
use crate::fixed::{Decimal, Lead, Length};
use crate::ir::{Compensation, ItemKind, ModalContext, Pos, Program};
use crate::source::{Line, SourceFile, Span};

mod block;
mod cycles;
mod model;
mod motion;
mod numbers;

/// How the FANUC reader words its unsupported policy.
const UNSUPPORTED: UnsupportedWording = UnsupportedWording {
    code: codes::FANR_UNSUPPORTED,
    more: "unsupported words in this block",
    in_one: "in a block",
    many: "blocks",
    own_block: "write this word in a block of its own",
    refuse_help: "ncthread never guesses what a code does on a machine it cannot check; `--unsupported warn` keeps the block as written (positions after it are unknown)",
    keep_help: "the block is kept as written; only the fanuc writer can write it back, and positions after it are unknown",
};

/// The machine builder's M codes, kept as written in every mode.
const BUILDER: UnsupportedWording = UnsupportedWording {
    keep_help: "kept as written in its block: a FANUC output says it, another control's output refuses it; positions after it are unknown (it may move the machine)",
    ..UNSUPPORTED
};

/// The machine builder's M codes the profile says move no axis (`still_m_codes`).
const BUILDER_STILL: UnsupportedWording = UnsupportedWording {
    keep_help: "the profile says it moves no axis (`still_m_codes`): a FANUC output writes it back; a LinuxCNC output writes the M word the profile's `[iso] mcodes` maps it to, and every other output a comment",
    ..UNSUPPORTED
};

/// The G codes ncthread reads, for "did you mean".
const KNOWN_G: [&str; 25] = [
    "G00", "G01", "G02", "G03", "G04", "G18", "G20", "G21", "G32", "G40", "G41", "G42", "G49",
    "G50", "G54", "G55", "G56", "G57", "G58", "G59", "G80", "G92", "G96", "G97", "G99",
];

/// The largest Q: just under a whole turn, in 0.001°. **\[evidence\]**
const MAX_Q: i64 = 359_999;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Motion {
    Rapid,
    Feed,
    /// G02 (clockwise, as LinuxCNC's G2 in G18) or G03.
    Arc(bool),
    Thread,
    /// The G92 threading cycle (modal: a block with X or U repeats it).
    Cycle,
}

impl Motion {
    fn code(self) -> &'static str {
        match self {
            Motion::Rapid => "G00",
            Motion::Feed => "G01",
            Motion::Arc(true) => "G02",
            Motion::Arc(false) => "G03",
            Motion::Thread => "G32",
            Motion::Cycle => "G92",
        }
    }
}

/// The F register: a feed, or a lead when last written in a G32 or G92 block.
#[derive(Clone, Copy, Debug)]
enum FRegister {
    Feed(Length),
    Lead(Lead),
    /// Not known after this G70–G73: the contour's F words run in G70.
    AfterCycle(i64),
}

/// A G92 cycle's words, kept for its repeat blocks.
#[derive(Clone, Copy, Debug)]
struct Cycle {
    /// The diameter of the last pass (a repeat block with only Z or W keeps it).
    x: Length,
    end_z: Length,
    /// Radius at the start minus radius at the end of the cut.
    taper: Length,
}

/// How a number is read when it has no decimal point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Unit {
    /// X Z U W I K R: 0.001 mm (0.0001 in).
    Axis,
    /// F in G32/G92: its unit without a point is settled by no source, so refused.
    Lead,
    /// F elsewhere: not settled by any source, so refused without a point.
    Feed,
    /// The time of G04 X/U.
    Seconds,
}

struct FrontEnd<'a> {
    r: Reader<'a>,
    profile: &'a FanucProfile,
    unsupported: Unsupported,
    motion: Motion,
    inch: bool,
    per_minute: bool,
    surface_speed: bool,
    limit: Option<Decimal>,
    f: Option<FRegister>,
    /// Where the last G32 ended, while no other block followed it.
    sync_end: Option<Pos>,
    /// Blocks other than comments read since the last G32 block (this one included).
    blocks_since_sync: u32,
    cycle: Option<Cycle>,
    /// A G92 was refused for want of the chamfer key (said once).
    chamfer_refused: bool,
    /// The chamfer (0.1 lead) a G76's first block set with P's rr: the machine's parameter
    /// 5130, which G92 uses too. **\[decided\]** spec fanuc.md.
    g76_chamfer: Option<u32>,
    /// Any move read yet (G20/G21 must come before).
    moved: bool,
    /// The first word read without a decimal point.
    no_point: Option<(Span, String)>,
    /// The first inch value rounded onto the 0.0001 mm grid.
    inch_rounded: Option<Span>,
    /// The contour of a G71–G73 being read (`front/cycles.rs`).
    contour: Option<cycles::Contour>,
    /// A G90 or G94 cycle in force: a block with only axes repeats it.
    kept_modal: Option<i64>,
    /// A G90 or G94 written without a word of its cycle (a safe-start line's `G21 G40
    /// G80 G90`): its mode set, no cycle given, so a block with only axes is refused.
    cycle_mode_only: Option<i64>,
    /// After this cycle (G70–G76), the next move must name its G code.
    motion_after_cycle: Option<i64>,
    /// System B's G91: X and Z are increments.
    incremental: bool,
    /// Tool nose radius compensation in force (G40 off, G41/G42).
    comp: Compensation,
    /// How many blocks carry each block number.
    numbers: std::collections::HashMap<u32, u32>,
    /// The P and Q words of the cycles, checked at the end.
    references: Vec<cycles::Reference>,
    /// Under a machine model: a G71/G72's first block, read.
    setup: Option<model::Setup>,
    /// Under a machine model: a G74/G75's first block, its retract.
    peck_retract: Option<Length>,
    /// Under a machine model: a G76's first block, read.
    thread_setup: Option<model::ThreadSetup>,
    /// Under a machine model: the G71/G72 whose contour is being read.
    pending: Option<model::Pending>,
    /// Under a machine model: the contour being read, as moves.
    capturing: Option<model::Capture>,
    /// Under a machine model: the contours read as moves.
    contours: model::Contours,
    /// Under a machine model: the last G90/G94's end and taper (a repeat block keeps them).
    turning: Option<(crate::lower::fanuc::Point, Length)>,
    /// A `G97` without S that ended a surface speed, while its speed is not known
    /// (`front/block.rs`, `bare_g97`).
    bare_g97: Option<BareG97>,
    /// M03/M04 read, and no M05 since.
    spindle_on: bool,
    /// An S (a speed, not G50's limit) read: before it the speed is the control's own, as
    /// for an M03 without S.
    speed_given: bool,
    /// A `G96` without S before any S, while no S has come (`front/block.rs`, `bare_g96`):
    /// the `G96` word.
    bare_g96: Option<Span>,
}

/// A `G97` without S after G96: the rpm the control keeps is not settled by any source
/// ncthread holds. Read where that speed is never used: an S comes before any move, or the
/// spindle stops (M05) first and starts again with an S. **\[decided\]**
#[derive(Clone, Copy)]
struct BareG97 {
    /// The `G97` word.
    span: Span,
    /// M05 stopped the spindle after it (the mode is written after the stop).
    stopped: bool,
}

/// Reads a FANUC program. The program holds every item that could be read; it is usable
/// only when no diagnostic is an error.
#[cfg(test)]
pub fn parse(
    src: &SourceFile,
    profile: &FanucProfile,
    unsupported: Unsupported,
) -> (Program, Vec<Diagnostic>) {
    read(src, profile, &[], unsupported, Keep::Program)
}

/// [`parse`], keeping the program or only the diagnostics.
pub(crate) fn read(
    src: &SourceFile,
    profile: &FanucProfile,
    subroutine_path: &[std::path::PathBuf],
    unsupported: Unsupported,
    keep: Keep,
) -> (Program, Vec<Diagnostic>) {
    // A conversion's output read back beside its writer: read as it comes, unless a line
    // uses macros or subprograms (then once it has ended, as any other file).
    let follow = matches!(keep, Keep::Diagnostics) && !src.text.is_complete();
    read_with(src, profile, subroutine_path, unsupported, keep, follow)
}

/// How many reads of a text being written [`read_with`] made as the lines came (for the
/// tests that it does).
#[cfg(test)]
pub(crate) static FOLLOWED: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);

/// [`read`]; with `follow`, a text still being written (its diagnostics only) read as it
/// comes, as a program without macros or subprograms: at the first line that uses them
/// ([`macros::line_uses_macros`]) that reading is thrown away and the text read again once
/// it has ended, as [`read`] reads any other.
fn read_with(
    src: &SourceFile,
    profile: &FanucProfile,
    subroutine_path: &[std::path::PathBuf],
    unsupported: Unsupported,
    keep: Keep,
    follow: bool,
) -> (Program, Vec<Diagnostic>) {
    // A program with custom macro B or subprograms runs first (`macros.rs`); its files
    // outlive the reader.
    let loaded = (!follow && macros::uses_macros(src)).then(|| macros::load(src, subroutine_path));
    // The lines to look at before each runs (the title line, known from the first two).
    let watch = follow.then(|| macros::title_line(src));
    let mut fe = FrontEnd {
        r: Reader::new(src, super::ID, keep),
        profile,
        unsupported,
        motion: Motion::Rapid,
        inch: profile.inch,
        per_minute: false,
        surface_speed: false,
        limit: None,
        f: None,
        sync_end: None,
        blocks_since_sync: 0,
        cycle: None,
        chamfer_refused: false,
        g76_chamfer: None,
        moved: false,
        no_point: None,
        inch_rounded: None,
        contour: None,
        kept_modal: None,
        cycle_mode_only: None,
        motion_after_cycle: None,
        incremental: false,
        comp: Compensation::Off,
        numbers: std::collections::HashMap::new(),
        references: Vec::new(),
        setup: None,
        thread_setup: None,
        peck_retract: None,
        pending: None,
        capturing: None,
        contours: model::Contours::new(),
        turning: None,
        bare_g97: None,
        spindle_on: false,
        speed_given: false,
        bare_g96: None,
    };
    match &loaded {
        Some(loaded) => fe.macro_lines(src, loaded),
        None => {
            if !fe.lines(src, watch) {
                drop(fe);
                return read_with(
                    src,
                    profile,
                    subroutine_path,
                    unsupported,
                    Keep::Diagnostics,
                    false,
                );
            }
            #[cfg(test)]
            if follow {
                FOLLOWED.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            }
        }
    }
    fe.cycle_closing();
    fe.closing_notes(src);
    fe.r.finish()
}

impl<'a> FrontEnd<'a> {
    /// A line is read: its items are let go of when the program is not kept, but for a
    /// G71/G72/G73 that waits for its contour (its moves are filled in at the contour's end).
    fn line_read(&mut self) {
        let waiting = self.pending.as_ref().map(model::Pending::item);
        self.r.line_read_keeping(waiting);
    }

    /// The blocks of a program run through its macros and subprograms, each at its own line
    /// (and file); a block of another file's subprogram stands at the program's call, and
    /// a diagnostic in a subprogram names the call chain.
    fn macro_lines(&mut self, src: &'a SourceFile, loaded: &'a macros::Loaded) {
        for event in macros::run(src, loaded, self.profile) {
            self.line_read();
            match event {
                macros::Event::Diag(d) => self.r.diags.push(d),
                macros::Event::Billet(line) => {
                    self.billet(src, line);
                }
                macros::Event::Title(line) => self.title(src, line),
                macros::Event::Block {
                    file,
                    line,
                    block,
                    chain,
                    call,
                } => {
                    let (items, diags) = (self.r.items.len(), self.r.diags.len());
                    if file != 0 {
                        self.r.src = &loaded.files[file - 1].1;
                    }
                    self.block(line, &block);
                    self.r.src = src;
                    if let Some(chain) = chain {
                        for d in &mut self.r.diags[diags..] {
                            d.message = format!("{} ({chain})", d.message);
                        }
                    }
                    if let Some(call) = call {
                        let span = src.line_span(call);
                        for item in &mut self.r.items[items..] {
                            item.span = span;
                        }
                    }
                }
            }
        }
    }
}

impl FrontEnd<'_> {
    /// Every line of the program, block by block, until its end (M02/M30 or the closing `%`);
    /// a block after the end is refused, a comment after it kept. With `watch` (the title
    /// line), each line is looked at first, and at one that uses macros or subprograms the
    /// reading gives up: `false`.
    fn lines(&mut self, src: &SourceFile, watch: Option<Option<u32>>) -> bool {
        let mut ended = false;
        let mut percents = 0;
        // The first line, when it cannot be read: a title if the program starts after it.
        let mut title: Option<(Line<'_>, syntax::SyntaxError)> = None;
        let mut first = true;
        // The words of the block before, for the next block's words (no allocation a line).
        let mut room = Vec::new();
        for line in src.lines() {
            // Nothing looks back past the line being read.
            self.line_read();
            if line.is_blank() {
                continue;
            }
            if let Some(title) = watch
                && macros::line_uses_macros(line, title)
            {
                return false;
            }
            if self.billet(src, line) {
                first = false;
                continue;
            }
            let parsed = syntax::parse_line_with(line.text, std::mem::take(&mut room));
            if let Some((t, e)) = title.take() {
                match &parsed {
                    Ok(b) if b.delimiter || b.get('O').is_some() => self.title(src, t),
                    _ => self.syntax_error(t, e),
                }
            }
            if std::mem::take(&mut first)
                && let Err(e) = &parsed
                && line.text.trim_start().starts_with(char::is_alphabetic)
            {
                title = Some((line, e.clone()));
                continue;
            }
            match parsed {
                Ok(mut block) if block.delimiter => {
                    percents += 1;
                    if percents >= 2 {
                        ended = true;
                    }
                    // `%O1200 (NAME)`: the program number on the `%` line.
                    if !block.words.is_empty() || block.comment.is_some() {
                        block.delimiter = false;
                        self.line_block(src, line, &block, &mut ended);
                    }
                    room = block.words;
                }
                Ok(block) => {
                    self.line_block(src, line, &block, &mut ended);
                    room = block.words;
                }
                Err(e) => self.syntax_error(line, e),
            }
        }
        if let Some((t, e)) = title {
            self.syntax_error(t, e);
        }
        true
    }

    fn syntax_error(&mut self, line: Line<'_>, e: syntax::SyntaxError) {
        let code = if e.number_too_large {
            codes::FANR_NUMBER
        } else {
            codes::FANR_SYNTAX
        };
        self.r.syntax_error(code, line, e.offset, e.message, e.help);
    }

    /// A first line of text that is no block, before the program's start (`%` or its
    /// number): the program's title, as some editors and course books write it. A comment.
    fn title(&mut self, src: &SourceFile, line: Line<'_>) {
        let text = line.text.trim();
        self.not_run(
            src,
            line,
            text,
            format!("`{text}`: a line of text before the program's start, read as its title (a comment)"),
            "the control would refuse this line if it reached it; put the title in a comment, `(NAME)`, if the file is sent as it is",
        );
    }

    /// `[BILLET X… Z…`: Denford's stock for its simulator (VR Turning), which no control
    /// runs. A comment.
    fn billet(&mut self, src: &SourceFile, line: Line<'_>) -> bool {
        let text = line.text.trim();
        let is_billet = text
            .get(..7)
            .is_some_and(|head| head.eq_ignore_ascii_case("[BILLET"));
        if is_billet {
            self.not_run(
                src,
                line,
                text,
                format!("`{text}`: Denford's stock line for its simulator, read as a comment"),
                "a FANUC control refuses `[` outside a macro: remove the line before sending the program to a machine",
            );
        }
        is_billet
    }

    /// A line no control runs, kept as a comment with a note.
    fn not_run(
        &mut self,
        src: &SourceFile,
        line: Line<'_>,
        text: &str,
        message: String,
        help: &str,
    ) {
        let span = src.line_span(line);
        self.r.diags.push(
            Diagnostic::new(codes::FANR_NOT_RUN, message)
                .at(src, span)
                .help(help),
        );
        self.push(ItemKind::Comment(text.to_string()), span);
    }

    /// A line's block, after the program's end or before it.
    fn line_block(&mut self, src: &SourceFile, line: Line<'_>, block: &Block, ended: &mut bool) {
        match block {
                block if *ended && !block.is_empty() => self.r.after_end(
                    codes::FANR_AFTER_END,
                    src.line_span(line),
                    "this block comes after the program's end (M02/M30 or the closing %); the control does not run it, and neither does ncthread",
                    "remove it, or move the program's end after it",
                ),
                // A comment after the end stays a comment (the writers keep it).
                block if *ended => self.block(line, block),
                block => {
                    let first = self.r.items.len();
                    self.block(line, block);
                    *ended |= self.r.ends_program(first);
                }
        }
    }

    /// What the whole program is said once about: the first word without a decimal point
    /// (and how the profile reads it), the first inch value rounded onto the grid.
    fn closing_notes(&mut self, src: &SourceFile) {
        if let Some((span, word)) = self.no_point.take() {
            let (message, help) = match self.profile.decimal_point {
                DecimalPoint::Increment => (
                    format!(
                        "`{word}` and other words without a decimal point are read in least input increments (0.001 mm, or 0.0001 in under G20), the profile's `decimal_point = \"increment\"` (FANUC parameter 3401#0 = 0)"
                    ),
                    "if the machine reads such words as millimetres (3401#0 = 1), set `decimal_point = \"calculator\"` in the profile's [fanuc] section",
                ),
                DecimalPoint::Calculator => (
                    format!(
                        "`{word}` and other words without a decimal point are read as whole millimetres (or inches), the profile's `decimal_point = \"calculator\"` (FANUC parameter 3401#0 = 1)"
                    ),
                    "if the machine reads such words in least input increments (3401#0 = 0), remove `decimal_point` from the profile",
                ),
            };
            self.r.diags.push(
                Diagnostic::new(codes::FANR_DECIMAL_POINT, message)
                    .at(src, span)
                    .help(help),
            );
        }
        if let Some(span) = self.inch_rounded.take() {
            self.r.diags.push(
                Diagnostic::new(
                    codes::FANR_INCH_ROUNDED,
                    "inch values finer than 0.0001 in are rounded onto ncthread's 0.00001 mm grid (this is the first)",
                )
                .at(src, span)
                .help("0.0001 in is 0.00254 mm, held exactly; a finer value moves by at most 0.000005 mm"),
            );
        }
    }

    fn span(&self, line: Line<'_>, range: Range<usize>) -> Span {
        self.r.span(line, range)
    }

    fn error(
        &mut self,
        code: Code,
        line: Line<'_>,
        range: Range<usize>,
        message: String,
        help: &str,
    ) {
        let span = self.span(line, range);
        self.r.error(code, span, message, help);
    }

    fn push(&mut self, kind: ItemKind, span: Span) {
        self.r.pos = kind.end_position(self.r.pos);
        self.r.push(kind, span, None);
    }

    fn block(&mut self, line: Line<'_>, block: &Block) {
        let first = self.r.items.len();
        let code_span = self.span(line, block.code_range.clone());
        if let Some(n) = block.number {
            *self.numbers.entry(n).or_default() += 1;
        }
        if self.contour.is_some() && (!block.words.is_empty() || block.number.is_some()) {
            self.contour_block(line, block);
            self.r
                .stamp_block(first, block.number, block.comment.clone(), code_span, false);
            return;
        }
        if block.words.is_empty() {
            // A comment block is a block too: between two G32 blocks it is refused (whether
            // the chain waits there is documented nowhere).
            self.blocks_since_sync = self.blocks_since_sync.saturating_add(1);
            if let Some(range) = block.block_delete.clone() {
                self.skip_marked(line, block, range);
            }
            self.r
                .stamp_block(first, block.number, block.comment.clone(), code_span, false);
            return;
        }
        if let Some(range) = block.block_delete.clone() {
            self.skip_marked(line, block, range);
            return;
        }
        self.blocks_since_sync = self.blocks_since_sync.saturating_add(1);
        let _ = self.read_block(line, block, code_span);
        self.r
            .stamp_block(first, block.number, block.comment.clone(), code_span, false);
    }

    /// A block that starts with `/` (block skip): refused, or kept with `--unsupported warn`.
    fn skip_marked(&mut self, line: Line<'_>, block: &Block, range: Range<usize>) {
        let span = self.span(line, range);
        let keep = self.unsupported == Unsupported::Warn;
        let found = vec![(
            span,
            "`/`: a block skipped or run by the operator's block skip switch is not supported"
                .to_string(),
        )];
        // A thread's block (G32 or G92, as system A numbers them).
        let system = self.profile.gcode_system;
        let thread = block.words.iter().any(|w| {
            w.letter == 'G'
                && w.value
                    .to_whole()
                    .is_ok_and(|g| matches!(system.a_of(g).unwrap_or(g), 32 | 92))
        });
        if self.r.unsupported(&UNSUPPORTED, found, keep, thread) {
            self.keep(line, block, &[]);
        }
    }

    /// A block's code as written, without its block number and its comments (the item
    /// carries both).
    fn kept_text(&self, line: Line<'_>, block: &Block) -> String {
        let raw = line.text[block.code_range.clone()].trim();
        // A block run through its macros: the words with their computed values.
        if raw.contains(['#', '[']) {
            let words: Vec<String> = block
                .words
                .iter()
                .map(|w| match &line.text[w.range.clone()] {
                    t if t.contains(['#', '[']) => format!("{}{}", w.letter, w.value),
                    t => t.to_string(),
                })
                .collect();
            return words.join(" ");
        }
        let mut depth = 0usize;
        let code: String = raw
            .chars()
            .filter(|&c| {
                match c {
                    '(' => depth += 1,
                    ')' => {
                        depth = depth.saturating_sub(1);
                        return false;
                    }
                    _ => {}
                }
                depth == 0
            })
            .collect();
        let code = code.trim();
        match block.number {
            Some(_) => code
                .trim_start_matches(['N', 'n'])
                .trim_start()
                .trim_start_matches(|c: char| c.is_ascii_digit())
                .trim_start()
                .to_string(),
            None => code.to_string(),
        }
    }

    /// Keeps a block as written (`--unsupported warn`), unless it changes followed state.
    fn keep(&mut self, line: Line<'_>, block: &Block, state: &[&Word]) {
        if let Some(w) = state.first() {
            let span = self.span(line, w.range.clone());
            self.r
                .state_in_opaque(&UNSUPPORTED, span, &line.text[w.range.clone()]);
            return;
        }
        let code = self.kept_text(line, block);
        let incremental = block.words.iter().any(|w| matches!(w.letter, 'U' | 'W'));
        let span = self.span(line, block.code_range.clone());
        self.r.keep_opaque(
            code,
            span,
            None,
            ModalContext {
                inch: self.inch,
                diameter: true,
                incremental,
                per_minute: Some(self.per_minute),
                moves: true,
                cycle: false,
                compensation: false,
            },
        );
        self.sync_end = None;
        self.moved = true;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixed::Angle;
    use crate::ir::{Chamfer, Item, ItemKind, SpindleDirection, SpindleMode, SyncStart};

    fn read(text: &str, profile: &str) -> (Vec<Item>, Vec<Diagnostic>) {
        let profile = if profile.is_empty() {
            crate::profile::Profile::default()
        } else {
            crate::profile::Profile::from_toml(&SourceFile::new("p", profile)).expect("a profile")
        };
        let (p, d) = parse(
            &SourceFile::new("t", text),
            &profile.fanuc,
            Unsupported::Error,
        );
        (p.items, d)
    }

    fn codes(d: &[Diagnostic]) -> Vec<&str> {
        d.iter().map(|d| d.code.id).collect()
    }

    fn mm(v: &str) -> Length {
        Decimal::parse(v)
            .and_then(|d| d.to_length().ok())
            .expect("a length")
    }

    #[test]
    fn a_speed_with_a_point_and_no_fraction_is_that_speed() {
        let (items, d) = read("G50 S3000.\nG97 S1500.0 M03\n", "");
        assert!(d.is_empty(), "{d:?}");
        assert!(items.iter().any(|i| i.kind
            == ItemKind::Spindle {
                speed: Some(1500),
                direction: Some(SpindleDirection::Clockwise)
            }));
        let (_, d) = read("G97 S1500.5 M03\n", "");
        assert_eq!(codes(&d), ["FANR006"]);
    }

    #[test]
    fn increments_and_the_decimal_point_rule() {
        let (items, d) = read("G00 X20000 Z5.\nU-1000 W-5.\n", "");
        assert_eq!(codes(&d), ["FANR013"]);
        assert_eq!(
            items[0].kind,
            ItemKind::Rapid {
                to: Pos::new(mm("20"), mm("5"))
            }
        );
        assert_eq!(
            items[1].kind,
            ItemKind::Rapid {
                to: Pos::new(mm("19"), mm("0"))
            }
        );
        let (items, _) = read("G00 X20 Z5\n", "[fanuc]\ndecimal_point = \"calculator\"\n");
        assert_eq!(
            items[0].kind,
            ItemKind::Rapid {
                to: Pos::new(mm("20"), mm("5"))
            }
        );
        // A lead or a dwell without a point: no source settles its unit.
        for text in ["G00 X20. Z5.\nG32 Z-20. F15\n", "G04 U5\n"] {
            assert!(codes(&read(text, "").1).contains(&"FANR006"), "{text}");
        }
        // A feed without a point: 0.0001 mm/rev under G99, whole mm/min under G98 (the
        // spec's decision); in inches, not settled.
        for (text, feed) in [
            ("G00 X20. Z5.\nG01 Z-20. F2000\n", 2_000),
            ("G98\nG00 X20. Z5.\nG01 Z-20. F150\n", 1_500_000),
        ] {
            let (items, d) = read(text, "");
            assert!(!codes(&d).contains(&"FANR006"), "{text}: {d:?}");
            assert!(
                items
                    .iter()
                    .any(|i| matches!(i.kind, ItemKind::Feed { feed: f, .. } if f.0 == feed * crate::fixed::Length::STEP)),
                "{text}: {items:?}"
            );
        }
        assert!(codes(&read("G20\nG00 X2. Z1.\nG01 Z-2. F2\n", "").1).contains(&"FANR006"));
    }

    #[test]
    fn consecutive_g32_blocks_are_one_chain_and_q_starts_it() {
        let (items, d) = read(
            "G97 S500 M03\nG00 X20. Z5.\nG32 Z-18. F1.5 Q90000\nX23. Z-19.5\nG00 X30.\n",
            "",
        );
        assert!(d.is_empty(), "{d:?}");
        let passes: Vec<_> = items
            .iter()
            .filter_map(|i| match &i.kind {
                ItemKind::ThreadPass(p) => Some(**p),
                _ => None,
            })
            .collect();
        assert_eq!(passes.len(), 2);
        assert_eq!(passes[0].start, SyncStart::Index(Angle(90_000)));
        assert_eq!(passes[1].start, SyncStart::Continue);
        assert_eq!(passes[1].lead, Lead::from_length(mm("1.5")));
        // A block between two G32 blocks that meet: whether the control waits is not known.
        let (_, d) = read(
            "G97 S500 M03\nG00 X20. Z5.\nG32 Z-18. F1.5\nM08\nG32 X23. Z-19.5\n",
            "",
        );
        assert_eq!(codes(&d), ["FANR012"]);
        // Steeper than 45°, and Q on a block that continues.
        let (_, d) = read("G00 X20. Z5.\nG32 X40. Z0. F1.\n", "");
        assert_eq!(codes(&d), ["FANR005"]);
        let (_, d) = read("G00 X20. Z5.\nG32 Z-18. F1.5\nZ-19. Q1000\n", "");
        assert_eq!(codes(&d), ["FANR012"]);
    }

    #[test]
    fn g92_is_its_four_moves_with_the_machines_chamfer_and_repeats_on_x() {
        let text = "G00 X26. Z5.\nG92 X19.4 Z-20. F1.5\nX19.\nG00 X100.\n";
        let (_, d) = read(text, "");
        assert_eq!(codes(&d), ["FANR004"]);
        let (items, d) = read(text, "[fanuc]\nthread_chamfer_0p1_lead = 10\n");
        assert!(d.is_empty(), "{d:?}");
        let kinds: Vec<&ItemKind> = items.iter().map(|i| &i.kind).collect();
        assert_eq!(kinds.len(), 1 + 4 + 4 + 1);
        assert_eq!(
            *kinds[1],
            ItemKind::Rapid {
                to: Pos::new(mm("19.4"), mm("5"))
            }
        );
        let ItemKind::ThreadPass(pass) = kinds[2] else {
            panic!("{:?}", kinds[2]);
        };
        assert_eq!(pass.to, Pos::new(mm("19.4"), mm("-20")));
        // 1.0 lead = 1.5 mm along Z, at 45°: 3 mm out on the diameter, towards the start X.
        assert_eq!(
            pass.exit,
            Some(Chamfer {
                length: mm("1.5"),
                offset: mm("3")
            })
        );
        assert_eq!(
            *kinds[3],
            ItemKind::Rapid {
                to: Pos::new(mm("26"), mm("-20"))
            }
        );
        assert_eq!(
            *kinds[4],
            ItemKind::Rapid {
                to: Pos::new(mm("26"), mm("5"))
            }
        );
        // The repeat block: the same cycle at X19.
        assert_eq!(
            *kinds[5],
            ItemKind::Rapid {
                to: Pos::new(mm("19"), mm("5"))
            }
        );
        // A taper: the cut starts 2R from the end diameter, at the start Z (no chamfer: where
        // a machine's chamfer leaves a taper no source says).
        let taper = "G00 X26. Z5.\nG92 X19.4 Z-20. R-1. F1.5\n";
        let none = "[fanuc]\nthread_chamfer_0p1_lead = 0\n";
        let ten = "[fanuc]\nthread_chamfer_0p1_lead = 10\n";
        let (items, d) = read(taper, none);
        assert!(d.is_empty(), "{d:?}");
        assert_eq!(
            items[1].kind,
            ItemKind::Rapid {
                to: Pos::new(mm("17.4"), mm("5"))
            }
        );
        assert_eq!(codes(&read(taper, ten).1), ["FANR004"]);
        // A chamfer past the start X, and R against U beyond |U/2|.
        let past = "G00 X22. Z5.\nG92 X19.4 Z-20. F1.5\n";
        assert_eq!(codes(&read(past, ten).1), ["FANR004"]);
        let against = "G00 X20. Z5.\nG92 X19.4 Z-20. R2. F1.5\n";
        assert_eq!(codes(&read(against, none).1), ["FANR002"]);
    }

    #[test]
    fn stop_codes_act_after_the_motion_and_t_is_tool_and_offset() {
        let (items, d) = read("G00 X20. Z5. T0100 M03 S500\nG00 X30. M05\n", "");
        assert!(d.is_empty(), "{d:?}");
        let kinds: Vec<&ItemKind> = items.iter().map(|i| &i.kind).collect();
        assert_eq!(
            kinds,
            [
                &ItemKind::Tool {
                    number: Some(1),
                    offset: Some(0)
                },
                &ItemKind::Spindle {
                    speed: Some(500),
                    direction: Some(SpindleDirection::Clockwise)
                },
                &ItemKind::Rapid {
                    to: Pos::new(mm("20"), mm("5"))
                },
                &ItemKind::Rapid {
                    to: Pos {
                        x: Some(mm("30")),
                        z: None
                    }
                },
                &ItemKind::SpindleStop,
            ]
        );
        assert_eq!(codes(&read("S500 M03 M05\n", "").1), ["FANR008"]);
        assert_eq!(codes(&read("T12001\n", "").1), ["FANR010"]);
        assert_eq!(codes(&read("T5\n", "").1), ["FANR010"]);
    }

    #[test]
    fn every_rule_has_its_code_line_and_column() {
        let first = |text: &str| {
            let (_, d) = read(text, "");
            let d = d.into_iter().next().expect("a diagnostic");
            let at = d.location.as_ref().map(|l| (l.line, l.column));
            (d.code.id, at)
        };
        assert_eq!(first("G01 U2. F0.2\n"), ("FANR007", Some((1, 5))));
        assert_eq!(
            first("G00 X20. Z5.\nG01 Z-10.\n"),
            ("FANR009", Some((2, 1)))
        );
        assert_eq!(
            first("G00 X20. Z5.\nG02 X30. Z0. R1. F0.1\n"),
            ("FANR011", Some((2, 14)))
        );
        assert_eq!(
            first("G00 X20. Z5.\nG02 X30. Z0. F0.1\n"),
            ("FANR011", Some((2, 1)))
        );
        assert_eq!(first("M30\nG00 X20.\n"), ("FANR014", Some((2, 1))));
        assert_eq!(first("G21\nG00 X20. Z5.\nG20\n"), ("FANR015", Some((3, 1))));
        // A surface speed keeps its unit: G50 S would write it again in the other one.
        assert_eq!(
            first("G21\nG96 S200 M03\nG20\nG50 S2000\n"),
            ("FANR015", Some((3, 1)))
        );
        assert_eq!(first("G20\nG00 X0.00001 Z1.\n"), ("FANR016", Some((2, 5))));
        assert!(read("G20\nG00 X0.0001 Z1.\n", "").1.is_empty());
        assert_eq!(first("G00 X20. X30.\n"), ("FANR008", Some((1, 10))));
    }

    #[test]
    fn g96_takes_its_limit_from_g50_s() {
        let (items, _) = read("G50 S2500\nG96 S200 M03\nG50 S3000\nG97 S800\n", "");
        let limit = |n| {
            Some(Decimal {
                mantissa: n,
                scale: 0,
                has_point: false,
            })
        };
        let modes: Vec<&ItemKind> = items
            .iter()
            .map(|i| &i.kind)
            .filter(|k| matches!(k, ItemKind::SpindleMode(_)))
            .collect();
        assert_eq!(
            modes,
            [
                &ItemKind::SpindleMode(SpindleMode::SurfaceSpeed {
                    limit: limit(2500),
                    feet: false
                }),
                &ItemKind::SpindleMode(SpindleMode::SurfaceSpeed {
                    limit: limit(3000),
                    feet: false
                }),
                &ItemKind::SpindleMode(SpindleMode::Rpm),
            ]
        );
        assert_eq!(codes(&read("G50 X100. Z50.\n", "").1), ["FANR002"]);
    }

    /// A bare G97 after G96 that an S follows: its mode item stands at the S (where a FANUC
    /// output says `G97 S800`), not at the G97 (the output wrote `G97 S200`, the last surface
    /// speed as an rpm).
    #[test]
    fn a_bare_g97s_mode_comes_at_its_s() {
        let (items, diags) = read("G96 S200 M03\nG97\nS800\n", "");
        assert!(diags.is_empty(), "{diags:?}");
        let at = |kind: &ItemKind| {
            items
                .iter()
                .find(|i| &i.kind == kind)
                .map(|i| (i.span.line, i.span.column))
        };
        assert_eq!(at(&ItemKind::SpindleMode(SpindleMode::Rpm)), Some((3, 1)));
        let s800 = ItemKind::Spindle {
            speed: Some(800),
            direction: None,
        };
        assert_eq!(at(&s800), Some((3, 1)));
    }

    /// The code and place of the first error reading `text` under the profile `toml`.
    fn first_error(text: &str, toml: &str) -> (&'static str, Option<(u32, u32)>) {
        let (_, diags) = read(text, toml);
        let d = diags.iter().find(|d| d.is_error()).expect(text);
        (d.code.id, d.location.as_ref().map(|l| (l.line, l.column)))
    }

    /// A G96 without S before any S: its mode comes with the next S (at the S), unless a move
    /// or a cycle comes first (refused at the G96); a G97 before the S undoes it; after an S,
    /// a bare G96 is refused as before (what the control keeps is not settled).
    #[test]
    fn g96_without_s_before_any_s_waits_for_its_s() {
        let kinds = |text: &str| -> Vec<ItemKind> {
            let (items, diags) = read(text, "");
            assert!(diags.is_empty(), "{text}: {diags:?}");
            items
                .into_iter()
                .map(|i| i.kind)
                .filter(|k| matches!(k, ItemKind::SpindleMode(_) | ItemKind::Spindle { .. }))
                .collect()
        };
        let surface = ItemKind::SpindleMode(SpindleMode::SurfaceSpeed {
            limit: None,
            feet: false,
        });
        let speed = |s| ItemKind::Spindle {
            speed: Some(s),
            direction: None,
        };
        let started = ItemKind::Spindle {
            speed: None,
            direction: Some(crate::ir::SpindleDirection::Clockwise),
        };
        assert_eq!(
            kinds("M03 G96\nG00 X53. Z5. S200\n"),
            [started.clone(), surface.clone(), speed(200)]
        );
        // The mode item points at the S, where it takes effect.
        let (items, _) = read("G96\nG00 X53. Z5. S200\n", "");
        let mode = items
            .iter()
            .find(|i| matches!(i.kind, ItemKind::SpindleMode(_)));
        assert_eq!(mode.map(|i| (i.span.line, i.span.column)), Some((2, 14)));
        assert_eq!(
            kinds("G96 M03\nG97\nS800\n"),
            [
                started.clone(),
                ItemKind::SpindleMode(SpindleMode::Rpm),
                speed(800)
            ]
        );
        // A dwell runs at no speed.
        assert_eq!(
            kinds("G96 M03\nG04 X1.\nS200\n"),
            [started, surface.clone(), speed(200)]
        );
        // A limit after it comes with its S; a G96 S after it is the mode once.
        let limited = ItemKind::SpindleMode(SpindleMode::SurfaceSpeed {
            limit: Some(Decimal {
                mantissa: 2500,
                scale: 0,
                has_point: false,
            }),
            feet: false,
        });
        assert_eq!(
            kinds("G96\nG50 S2500\nS200\n"),
            [limited.clone(), speed(200)]
        );
        assert_eq!(kinds("G96\nG50 S2500\nG96 S200\n"), [limited, speed(200)]);
        let first = |text: &str| first_error(text, "");
        assert_eq!(
            first("G96 M03\nG00 X53. Z5.\nS200\n"),
            ("FANR002", Some((1, 1)))
        );
        // A move in the G96's own block, a thread pass repeated without axes.
        assert_eq!(
            first("M03\nG96 G01 X40. F0.2\nS200\n"),
            ("FANR002", Some((2, 1)))
        );
        let chamfer = "[fanuc]\nthread_chamfer_0p1_lead = 0\n";
        assert_eq!(
            first_error(
                "M03\nG00 X25. Z5.\nG92 X19. Z-20. F1.5\nG96\nG92\nS200\n",
                chamfer
            ),
            ("FANR002", Some((4, 1)))
        );
        // So too a bare G97's rpm (it was read).
        assert_eq!(
            first_error(
                "G96 S200 M03\nG00 X25. Z5.\nG92 X19. Z-20. F1.5\nG97\nG92\n",
                chamfer
            ),
            ("FANR002", Some((4, 1)))
        );
        // A cycle's block with S is refused too: the cycle is kept as written.
        assert_eq!(
            first("G96 M03\nG90 X40. Z-10. F0.2 S200\n"),
            ("FANR002", Some((1, 1)))
        );
        assert_eq!(
            first("G97 S800 M03\nG96\nG00 X53.\n"),
            ("FANR002", Some((2, 1)))
        );
    }

    /// System C (the profile's `gcode_system`): G70/G71 are inch and metric input, G20/G24
    /// the turning and facing cycles and G73 the turning roughing cycle (kept as written), and
    /// a code system C does not have is refused naming the system.
    #[test]
    fn system_c_reads_its_own_codes() {
        let c = "[fanuc]\ngcode_system = \"C\"\n";
        let profile = crate::profile::Profile::from_toml(&SourceFile::new("p", c)).expect("C");
        let program = |text: &str| {
            parse(
                &SourceFile::new("t", text),
                &profile.fanuc,
                Unsupported::Error,
            )
        };
        let (p, d) = program("G70 G90 G95\nG00 X1. Z0.1\n");
        assert!(d.is_empty() && p.inch, "{d:?}");
        let (p, d) =
            program("G71 G90 G95\nG00 X20. Z2.\nG20 X18. Z-10. F0.2\nX16.\nG24 X0. Z-1.\n");
        assert!(d.is_empty() && !p.inch, "{d:?}");
        let kept: Vec<&str> = p
            .items
            .iter()
            .filter_map(|i| match &i.kind {
                ItemKind::Opaque { text, .. } => Some(text.as_str()),
                _ => None,
            })
            .collect();
        assert_eq!(kept, ["G20 X18. Z-10. F0.2", "X16.", "G24 X0. Z-1."]);
        let (_, d) = program(
            "G71\nG00 X50. Z3.\nG73 U2. R1\nG73 P10 Q20 U0.5 W0.2 F0.3\nN10 G00 X18.\nN20 G01 Z-12.\nG72 P10 Q20\n",
        );
        assert!(d.is_empty(), "{d:?}");
        for (text, says) in [
            (
                "G79 X20. Z-1. F0.2\n",
                "G79 is system B's facing cycle, not a code of G-code system C, whose facing cycle is G24",
            ),
            ("G32 Z-10. F1.\n", "in G-code system C threads are G33"),
            (
                "G50 S2000\n",
                "in G-code system C the spindle limit is G92 S",
            ),
            (
                "G00 U2.\n",
                "in G-code system C an increment is G91 with X or Z",
            ),
        ] {
            let (_, d) = program(text);
            assert!(d.iter().any(|d| d.message.contains(says)), "{text}: {d:?}");
        }
        // A computed word is rounded to the unit in force: G70 inch input (not G20, the
        // turning cycle), 0.0001 in; the machine's start unit where the program says none.
        let inches = |items: &[Item]| {
            items.iter().find_map(|i| match i.kind {
                ItemKind::Rapid { to } => to.x.and_then(Length::inches_with_point),
                _ => None,
            })
        };
        let (p, d) = program("G70 G90 G95\n#1=1.23456\nG00 X#1 Z0.1\n");
        assert!(d.is_empty(), "{d:?}");
        assert_eq!(inches(&p.items).as_deref(), Some("1.2346"));
        let (p, d) = program("G71 G90 G95\nG00 X30. Z2.\nG20 X28. Z-5. F0.2\n#1=20.123\nG00 X#1\n");
        assert!(d.is_empty(), "{d:?}");
        assert!(
            p.items
                .iter()
                .any(|i| matches!(i.kind, ItemKind::Rapid { to } if to.x == Some(mm("20.123"))))
        );
        let inch = crate::profile::Profile::from_toml(&SourceFile::new(
            "p",
            "[fanuc]\nunits = \"inch\"\n",
        ))
        .unwrap();
        let (p, d) = parse(
            &SourceFile::new("t", "#1=1.23456\nG00 X#1 Z0.1\n"),
            &inch.fanuc,
            Unsupported::Error,
        );
        assert!(d.is_empty(), "{d:?}");
        assert_eq!(inches(&p.items).as_deref(), Some("1.2346"));
        // A message names a cycle by the system's code.
        let (_, d) = program("G73 P10 Q20 U0.5 W0.2 F0.3\n");
        assert!(
            d.iter().any(|d| d.message.contains("G73 turning cycle")),
            "{d:?}"
        );
    }
}

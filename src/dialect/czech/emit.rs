//! IR → the czech control's blocks.
//!
//! Block numbers are kept from a czech source and written `N10, N20, …` otherwise. Every
//! coordinate has a decimal point and at most 3 decimals, leads at most 4; a lead over 99.99
//! goes through a free R parameter (`FRnn`). Entry and runout angles come from machine
//! constant 8: in parameter mode the angle parameter is assigned in a block before the pass
//! (unless it already holds the angle); in direct mode the pass's angle must be constant 8's.
//! After a J/E pass come the empty block and a block that programs every axis. Cycles are
//! written as their passes (one comment block per pass); a tapping cycle and a dwell have no
//! documented czech form and are refused.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use crate::diag::{Code, Diagnostic};
use crate::dialect::czech::codes;
use crate::dialect::write::{self, Writer};
use crate::dialect::{DialectId, Inexact, Renumber, one_line};
use crate::fixed::{Angle, Decimal, Lead, Length};
use crate::ir::{
    Chamfer, Coolant, EndCode, FeedMode, Item, ItemKind, Pos, SpindleDirection, SpindleMode,
    SyncStart, ThreadCycle, ThreadPass,
};
use crate::lower;
use crate::profile::{AngleSource, Constant8, CzechArcs, CzechDwell, Profile};
use crate::source::SourceFile;

/// The largest lead the czech control takes directly in F. **\[seed\]**
const MAX_DIRECT_LEAD: Length = Length::from_steps(999_900);
/// Runout and entry angles are 0…60°. **\[seed\]**
const MAX_ANGLE: Angle = Angle(60_000);

#[derive(Default)]
struct Block {
    number: Option<u32>,
    words: Words,
    comment: Option<String>,
}

/// A block's words in one buffer, each after a space: no allocation per word (issue 34).
#[derive(Default)]
struct Words(String);

impl Words {
    fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// Starts a word: the buffer to write it into.
    fn next(&mut self) -> &mut String {
        if !self.0.is_empty() {
            self.0.push(' ');
        }
        &mut self.0
    }

    fn push(&mut self, word: &str) {
        self.next().push_str(word);
    }

    /// A word written from `args` (`format_args!`), without a `String` of its own.
    fn push_fmt(&mut self, args: std::fmt::Arguments<'_>) {
        let _ = self.next().write_fmt(args);
    }

    /// `word` before the others (a motion's G before its axes).
    fn push_first(&mut self, word: &str) {
        if self.0.is_empty() {
            self.0.push_str(word);
        } else {
            self.0.insert(0, ' ');
            self.0.insert_str(0, word);
        }
    }

    /// Appends `other`'s words: the buffer left over, to be cleared and used again
    /// ([`Emitter::recycle`]).
    fn extend(&mut self, other: Words) -> Words {
        if self.0.is_empty() {
            Words(std::mem::replace(&mut self.0, other.0))
        } else {
            if !other.0.is_empty() {
                self.next().push_str(&other.0);
            }
            other
        }
    }
}

struct Emitter<'a> {
    w: Writer<'a>,
    profile: &'a Profile,
    /// Keep the source's block numbers (a czech source) or number from `renumber`.
    keep_numbers: bool,
    next_number: u32,
    step: u32,
    motion: Option<&'static str>,
    /// The last F written: its value and whether it was a lead (in a G33 block).
    f: Option<(Lead, bool)>,
    /// R parameters and what they hold, as far as this program sets them.
    params: BTreeMap<u32, Decimal>,
    /// Where the last pass ended, while no other move followed: a pass that starts there
    /// waits for the index pulse with the tool in the cut.
    in_cut: Option<Pos>,
    /// After a J/E pass: the next motion must program every axis.
    all_axes: bool,
    /// After a J/E pass: the next block must be empty (a comment block serves).
    pending_empty: bool,
    /// The last block number written.
    last_number: Option<u32>,
    /// Values that need a 4th decimal.
    inexact: Inexact,
    /// `--round`: round them (a warning) instead of refusing.
    round: bool,
    /// The R parameters it chose for leads.
    chosen: Vec<u32>,
    /// Word buffers written out, to be used again (no allocation a block).
    spare: Vec<String>,
}

/// The czech writer taking a program's items one at a time (a conversion's streaming read,
/// after [`write::Facts`] gathered what it needs to know first), or a whole program
/// ([`Dialect::write`](crate::dialect::Dialect::write)).
pub(crate) struct Items<'a> {
    e: Emitter<'a>,
    /// Parameters the program assigns are not free for leads.
    reserved: Vec<u32>,
    /// The items of the block being gathered (one source line's when the source is czech).
    block: Vec<Item>,
}

impl<'a> Items<'a> {
    pub fn new(
        facts: &write::Facts,
        from: DialectId,
        src: &'a SourceFile,
        profile: &'a Profile,
        renumber: Renumber,
        round: bool,
    ) -> Self {
        Items {
            e: Emitter {
                w: Writer::new(src),
                profile,
                keep_numbers: from == super::ID,
                next_number: renumber.start,
                step: renumber.step.max(1),
                motion: None,
                f: None,
                params: BTreeMap::new(),
                in_cut: None,
                all_axes: false,
                pending_empty: false,
                last_number: None,
                inexact: Inexact::default(),
                round,
                chosen: Vec::new(),
                spare: Vec::new(),
            },
            reserved: facts.params.clone(),
            block: Vec::new(),
        }
    }

    /// Writes the block gathered so far.
    fn flush(&mut self) {
        if self.block.is_empty() {
            return;
        }
        self.e.w.spill();
        self.e.group(&self.block, &self.reserved);
        self.block.clear();
    }
}

impl write::ItemWriter for Items<'_> {
    #[cfg(unix)]
    fn follow(&mut self, follow: crate::source::Follow) {
        self.e.w.follow(follow);
    }

    fn refuses(&self) -> bool {
        self.e.inexact.refuses(self.e.round)
    }

    /// Parameters the program assigns after the first item: taken while none of them is one
    /// it chose for a lead (each choice is the lowest free number, so it is the same choice
    /// among the fewer numbers free once they are reserved).
    fn late_facts(&mut self, facts: &write::Facts) -> bool {
        if facts.params.iter().any(|n| self.e.chosen.contains(n)) {
            return false;
        }
        self.reserved.clone_from(&facts.params);
        true
    }

    fn item(&mut self, item: &Item) {
        self.take(item.clone());
    }

    fn take(&mut self, item: Item) {
        // Items of one source block stay one block when the source is czech.
        let same = self
            .block
            .first()
            .is_some_and(|first| self.e.keep_numbers && first.span.line == item.span.line);
        if !same {
            self.flush();
        }
        self.block.push(item);
    }

    fn finish(mut self: Box<Self>) -> (Option<crate::dialect::Output>, Vec<Diagnostic>) {
        self.flush();
        let Items { e, .. } = *self;
        e.end()
    }
}

impl Emitter<'_> {
    /// The program's closing diagnostics, and the text.
    fn end(mut self) -> (Option<crate::dialect::Output>, Vec<Diagnostic>) {
        let e = &mut self;
        let src = e.w.src;
        let summary = e.inexact.diagnostic(
        src,
        e.round,
        |s| {
            Diagnostic::new(
                codes::CZW_ROUNDED,
                format!("{} value(s) rounded to the czech control's grid (0.001 mm, leads 0.0001 mm), the first {}; the largest deviation is {} mm", s.count, s.what, s.largest),
            )
            .help("thread starts are rounded back along their pass, with the start angle I that keeps the helix")
        },
        |s| {
            Diagnostic::new(
                codes::CZW_PRECISION,
                format!("{} is finer than the czech control's {} mm ({} value(s) in this program are; lengths take 3 decimals, leads 4)", s.what, s.grid, s.count),
            )
            .help(format!("pass --round to round them (largest deviation {} mm, for a lead its drift at the thread's end; thread starts keep their helix through I)", s.largest))
        },
    );
        e.w.diags.extend(summary);
        self.w.finish()
    }
}

impl Emitter<'_> {
    /// Reports a problem once (a cycle's passes share the cycle's item).
    fn diag(&mut self, code: Code, item: &Item, message: String, help: &str) {
        self.w.error(code, item.span, message, help);
    }

    /// An empty word buffer: one written out before, or a new one.
    fn words(&mut self) -> Words {
        Words(self.spare.pop().unwrap_or_default())
    }

    /// Keeps `words`' buffer to be used again.
    fn recycle(&mut self, words: Words) {
        let mut buffer = words.0;
        if self.spare.len() < 4 && buffer.capacity() <= 1024 {
            buffer.clear();
            self.spare.push(buffer);
        }
    }

    fn write(&mut self, block: Block) {
        if self.pending_empty {
            self.pending_empty = false;
            if !block.words.is_empty() {
                // A blank line is not a block: the empty block carries a number.
                let number = self.last_number.map(|n| n + 1);
                self.write(Block {
                    number,
                    ..Block::default()
                });
            }
        }
        let number = if self.keep_numbers {
            block.number
        } else {
            let n = self.next_number;
            self.next_number = self.next_number.saturating_add(self.step);
            Some(n)
        };
        // Written straight into the output: `start` tells whether the line has a word yet.
        let line = &mut self.w.out;
        let start = line.len();
        if let Some(n) = number {
            line.push('N');
            crate::fixed::push_whole(line, n.into());
            self.last_number = Some(n);
        }
        if !block.words.is_empty() {
            if line.len() > start {
                line.push(' ');
            }
            line.push_str(&block.words.0);
        }
        if let Some(c) = block.comment {
            if line.len() > start {
                line.push(' ');
            }
            let _ = write!(line, "\"{}", one_line(&c));
        }
        line.push('\n');
        self.recycle(block.words);
    }

    /// `v` with a decimal point and at most 3 decimals. A value that needs a 4th is rounded
    /// (`--round`) or counted for one error; either way the text is usable.
    fn three_decimals(&mut self, item: &Item, what: &str, v: Length) -> String {
        let mut text = String::new();
        self.push_three_decimals(item, what, v, &mut text);
        text
    }

    /// [`Emitter::three_decimals`] appended to `out`.
    fn push_three_decimals(&mut self, item: &Item, what: &str, v: Length, out: &mut String) {
        if v.on_mm_decimals(3) {
            return v.push_mm_with_point(out);
        }
        let rounded = Length(crate::fixed::div_round(v.0 as i128, 100) as i64 * 100);
        self.inexact
            .note(item.span, what, v, rounded, Length::from_steps(10));
        rounded.push_mm_with_point(out);
    }

    /// `letter` and `v` as [`Emitter::push_three_decimals`] writes it, as the next word.
    fn push_word(&mut self, item: &Item, what: &str, letter: char, v: Length, words: &mut Words) {
        let out = words.next();
        out.push(letter);
        self.push_three_decimals(item, what, v, out);
    }

    /// `G04` with the time in the profile's form, in a block of no motion (the time word may
    /// be X): seconds to 0.001 s (`X0.5`), or whole milliseconds (`P500`). A time off
    /// that grid is refused, not rounded: `--round` reports lengths.
    fn dwell(&mut self, item: &Item, seconds: Decimal, block: &mut Block) {
        let ms = seconds.to_scaled(3).ok().filter(|ms| *ms >= 0);
        let Some(ms) = ms else {
            self.diag(
                codes::CZW_PRECISION,
                item,
                format!("the dwell of {seconds} s needs more than the 0.001 s this machine's dwell takes"),
                "write the dwell in the source in whole milliseconds",
            );
            return;
        };
        let word = match self.profile.czech.dwell {
            CzechDwell::PMilliseconds => format!("P{ms}"),
            form => {
                let letter = if form == CzechDwell::FSeconds {
                    'F'
                } else {
                    'X'
                };
                format!("{letter}{}", Length::from_steps(ms * 10).mm_with_point())
            }
        };
        block.words.push("G04");
        block.words.push(&word);
        self.flush(block);
    }

    /// The axis words of a move to `to` (every axis after a J/E pass).
    fn axes(&mut self, item: &Item, to: Pos) -> Words {
        let mut words = self.words();
        let full = Pos {
            x: to.x.or(if self.all_axes { self.w.pos.x } else { None }),
            z: to.z.or(if self.all_axes { self.w.pos.z } else { None }),
        };
        if let Some(x) = full.x {
            self.push_word(item, "X", 'X', x, &mut words);
        }
        if let Some(z) = full.z {
            self.push_word(item, "Z", 'Z', z, &mut words);
        }
        words
    }

    /// `G02`/`G03 X Z` with the centre in the profile's form: I and K from the start (I a
    /// radius or a diameter value), or R (negative beyond half a turn). Values off the
    /// 0.001 mm grid are refused (or rounded with `--round`) as every value is; an R is
    /// rounded onto the grid only where the centre it gives stays within 0.0005 mm.
    fn arc(
        &mut self,
        item: &Item,
        to: Pos,
        centre: Pos,
        clockwise: bool,
        feed: Length,
        block: &mut Block,
    ) {
        let (Some((sx, sz)), Some((cx, cz)), Some((ex, ez))) =
            (self.w.pos.known(), centre.known(), to.known())
        else {
            self.diag(
                codes::CZW_NO_EQUIVALENT,
                item,
                "an arc from a position that is not known: its centre cannot be written".into(),
                "move to an absolute X and Z before the arc",
            );
            return;
        };
        let mut words = self.axes(item, Pos::new(ex, ez));
        let g02 = clockwise != self.profile.czech.arcs_mirrored;
        self.motion_word(if g02 { "G02" } else { "G03" }, &mut words);
        match self.profile.czech.arcs {
            CzechArcs::Radius => {
                let Some(r) = self.radius_word(item, (sx, sz), (ex, ez), (cx, cz), clockwise)
                else {
                    return;
                };
                words.push_fmt(format_args!("R{r}"));
            }
            _ => {
                let (i, k) = self.centre_words(item, cx - sx, cz - sz);
                words.push_fmt(format_args!("I{i}"));
                words.push_fmt(format_args!("K{k}"));
            }
        }
        if self.f != Some((Lead::from_length(feed), false)) {
            self.push_word(item, "feed F", 'F', feed, &mut words);
            self.f = Some((Lead::from_length(feed), false));
        }
        let spare = block.words.extend(words);
        self.recycle(spare);
        self.all_axes = false;
    }

    /// An arc's radius as R writes it (negative over half a turn); `None` when it is
    /// refused: a full circle, or (without --round) an R whose three decimals move the
    /// centre the control finds.
    fn radius_word(
        &mut self,
        item: &Item,
        (sx, sz): (Length, Length),
        (ex, ez): (Length, Length),
        (cx, cz): (Length, Length),
        clockwise: bool,
    ) -> Option<String> {
        if (sx, sz) == (ex, ez) {
            self.diag(
                codes::CZW_NO_EQUIVALENT,
                item,
                "a full circle has no R form on this machine".into(),
                "write the circle as two arcs in the source, or declare `arcs = \"ik-radius\"` (or \"ik-diameter\") if the machine takes I and K",
            );
            return None;
        }
        let (r1, _) = lower::arc::radii((sx, sz), (ex, ez), (cx, cz));
        let long = lower::arc::over_half_turn((sx, sz), (ex, ez), (cx, cz), clockwise);
        let r = Length::from_mm_f64(if long { -r1 } else { r1 });
        let text = self.three_decimals(item, "R", r);
        // The centre the control finds from the written R.
        let written = Decimal::parse(&text).map(|d| d.to_f64()).unwrap_or(0.0);
        let off = lower::arc::centre_miss((sx, sz), (ex, ez), (cx, cz), written, clockwise);
        if off > 0.0005 {
            if !self.round {
                self.diag(
                    codes::CZW_PRECISION,
                    item,
                    format!("the arc's radius {r1:.4} mm written as R{text} moves its centre by {off:.4} mm"),
                    "pass --round to accept it, or write the arc with I and K where the machine takes them",
                );
                return None;
            }
            let moved = Length::from_mm_f64(off);
            self.inexact.note(
                item.span,
                "arc centre (from R)",
                Length::ZERO,
                moved,
                Length::from_steps(10),
            );
        }
        Some(text)
    }

    /// An arc's centre as I and K write it (offsets from the start `dx`, `dz`; I in radius
    /// or diameter as the profile says).
    fn centre_words(&mut self, item: &Item, dx: Length, dz: Length) -> (String, String) {
        let i = if self.profile.czech.arcs == CzechArcs::IkRadius {
            if dx.0 % 2 == 0 && Length(dx.0 / 2).on_mm_decimals(3) {
                Length(dx.0 / 2).mm_with_point()
            } else {
                // A radius between two 0.001 mm steps: noted as its diameter.
                let rounded = Length(crate::fixed::div_round(dx.0 as i128, 200) as i64 * 100);
                self.inexact.note(
                    item.span,
                    "I (as a diameter)",
                    dx,
                    rounded + rounded,
                    Length::from_steps(20),
                );
                rounded.mm_with_point()
            }
        } else {
            self.three_decimals(item, "I", dx)
        };
        let k = self.three_decimals(item, "K", dz);
        (i, k)
    }

    fn motion_word(&mut self, g: &'static str, words: &mut Words) {
        if self.motion != Some(g) {
            words.push_first(g);
            self.motion = Some(g);
        }
    }

    fn group(&mut self, items: &[Item], reserved: &[u32]) {
        let mut block = Block {
            number: items[0].block_number,
            words: self.words(),
            comment: items[0].comment.as_deref().map(str::to_string),
        };
        for item in items {
            self.item(item, &mut block, reserved);
        }
        // An empty numbered block of a czech source stays (it may be a J/E pass's empty
        // block).
        if !block.words.is_empty()
            || block.comment.is_some()
            || (self.keep_numbers
                && block.number.is_some()
                && !items.iter().all(|i| i.kind == ItemKind::Delimiter))
        {
            self.write(block);
        } else {
            self.recycle(block.words);
        }
    }

    /// Writes `block` now if it holds anything, and starts a fresh one.
    fn flush(&mut self, block: &mut Block) {
        if !block.words.is_empty() || block.comment.is_some() {
            let b = std::mem::take(block);
            self.write(b);
        }
    }

    fn item(&mut self, item: &Item, block: &mut Block, reserved: &[u32]) {
        if !self.kind(item, block, reserved) {
            return;
        }
        if !matches!(
            item.kind,
            ItemKind::ThreadCycle(_) | ItemKind::ThreadPass(_)
        ) {
            let before = self.w.pos;
            self.w.pos = item.kind.end_position(self.w.pos);
            if self.w.pos != before {
                self.in_cut = None;
            }
        }
    }

    /// Writes an item into `block` (or into blocks of its own): one arm per kind of item.
    /// `false` when it is refused (a diagnostic says why) and the position is not moved.
    fn kind(&mut self, item: &Item, block: &mut Block, reserved: &[u32]) -> bool {
        match &item.kind {
            ItemKind::Rapid { to } => self.rapid(item, *to, block),
            ItemKind::Feed { to, feed } => return self.feed(item, *to, *feed, block),
            ItemKind::ThreadPass(pass) => {
                self.ensure_all_axes(item, block);
                self.thread_pass(item, pass, block, reserved);
            }
            ItemKind::ThreadCycle(cycle) => {
                self.flush(block);
                self.thread_cycle(item, cycle, reserved);
            }
            ItemKind::Arc {
                to,
                centre,
                clockwise,
                feed,
            } if self.profile.czech.arcs != CzechArcs::None => {
                self.arc(item, *to, **centre, *clockwise, *feed, block)
            }
            // Refused by legalisation (the czech table has no tap, dwell or stop, and no arc
            // unless the profile declares its form).
            ItemKind::Dwell { seconds } if self.profile.czech.dwell != CzechDwell::None => {
                if !block.words.is_empty() {
                    self.flush(block);
                }
                self.dwell(item, *seconds, block);
            }
            ItemKind::TapCycle(_)
            | ItemKind::Dwell { .. }
            | ItemKind::Arc { .. }
            | ItemKind::Stop { .. } => {}
            ItemKind::FeedRate(feed) => self.feed_rate(item, *feed, block),
            ItemKind::SpindleMode(mode) => return self.spindle_mode(item, mode, block),
            // No compensation and the default work offset are this control's only state;
            // the others, and machine coordinates, are refused by legalisation.
            ItemKind::Compensation(_) | ItemKind::WorkOffset(_) | ItemKind::MachineMove(_) => {}
            // Unrolled into its moves at the top of `emit`.
            ItemKind::Roughing(_) | ItemKind::ModelCycle(_) => {}
            // Written where the profile declares the codes; legalisation refuses the rest.
            ItemKind::Coolant(c) => block.words.push(coolant_word(*c)),
            ItemKind::Spindle { speed, direction } => spindle_words(*speed, *direction, block),
            ItemKind::SpindleStop => block.words.push("M05"),
            ItemKind::Tool { number, offset } => {
                if let Some(t) = number {
                    block.words.push_fmt(format_args!("T{t}"));
                }
                if let Some(d) = offset {
                    block.words.push_fmt(format_args!("D{d}"));
                }
            }
            ItemKind::GearRange { code: m, machine } => self.gear_range(item, *m, *machine, block),
            ItemKind::MachineCode { code, machine } => {
                self.as_comment(item, block, &crate::ir::machine_code_note(*code, *machine))
            }
            ItemKind::FeedMode(FeedMode::PerRev) => block.words.push("G95"),
            ItemKind::FeedMode(FeedMode::PerMin) => block.words.push("G94"),
            ItemKind::ProgramEnd(end) => {
                self.ensure_all_axes(item, block);
                block
                    .words
                    .push(if *end == EndCode::M2 { "M02" } else { "M30" });
            }
            ItemKind::Comment(text) => self.comment_item(text, block),
            ItemKind::ParamAssign { number, value } => {
                self.params.insert(*number, *value);
                block.words.push_fmt(format_args!("R{number:02}={value}"));
            }
            ItemKind::Opaque {
                dialect: super::ID,
                text,
                ..
            } => block.words.push(text),
            ItemKind::Opaque { dialect, text, .. } => {
                self.as_comment(item, block, &format!("{dialect}: {text}"));
            }
            ItemKind::Delimiter => {
                self.flush(block);
                self.w.out.push_str("%\n");
            }
        }
        true
    }

    /// A comment: the block's own, or (when the block has words or a comment already) the
    /// next block's.
    fn comment_item(&mut self, text: &str, block: &mut Block) {
        if !(block.words.is_empty() && block.comment.is_none()) {
            self.flush(block);
        }
        block.comment = Some(text.to_string());
    }

    /// G00 with the axes (nothing when they cannot be written).
    fn rapid(&mut self, item: &Item, to: Pos, block: &mut Block) {
        let mut words = self.axes(item, to);
        self.motion_word("G00", &mut words);
        let spare = block.words.extend(words);
        self.recycle(spare);
        self.all_axes = false;
    }

    /// G01 with the axes and, when it changes, the feed; `false` when the axes cannot be
    /// written.
    fn feed(&mut self, item: &Item, to: Pos, feed: Length, block: &mut Block) -> bool {
        let mut words = self.axes(item, to);
        self.motion_word("G01", &mut words);
        if self.f != Some((Lead::from_length(feed), false)) {
            self.push_word(item, "feed F", 'F', feed, &mut words);
            self.f = Some((Lead::from_length(feed), false));
        }
        let spare = block.words.extend(words);
        self.recycle(spare);
        self.all_axes = false;
        true
    }

    /// A feed of its own: in a G01 block when the last motion was a thread (there F would
    /// be a lead).
    fn feed_rate(&mut self, item: &Item, feed: Length, block: &mut Block) {
        if self.f != Some((Lead::from_length(feed), false)) {
            if self.motion == Some("G33") {
                self.motion_word("G01", &mut block.words);
            }
            self.push_word(item, "feed F", 'F', feed, &mut block.words);
            self.f = Some((Lead::from_length(feed), false));
        }
    }

    /// G96/G97 where the profile declares them (legalisation refuses them elsewhere;
    /// without the key, rpm is this control's only mode). The machine's speed limit is its
    /// own setting: a limit in the source has no word here, and is refused (`false`), as is
    /// a surface speed in feet per minute.
    fn spindle_mode(&mut self, item: &Item, mode: &SpindleMode, block: &mut Block) -> bool {
        if !self.profile.czech.surface_speed {
            return true;
        }
        match mode {
            SpindleMode::SurfaceSpeed { feet: true, .. } => {
                self.diag(
                    codes::CZW_NO_EQUIVALENT,
                    item,
                    "a surface speed in feet per minute (G96 under G20): the czech control's G96 takes m/min".to_string(),
                    "program the surface speed in m/min (G21) in the source",
                );
                return false;
            }
            SpindleMode::SurfaceSpeed { limit: Some(d), .. } => {
                self.diag(
                    codes::CZW_NO_EQUIVALENT,
                    item,
                    format!("the surface speed's limit of {d} rpm has no word on this machine (its limit is a machine setting)"),
                    "set the machine's speed limit by hand to the source's, and remove the limit (G96's D) from the source",
                );
                return false;
            }
            SpindleMode::SurfaceSpeed { .. } => block.words.push("G96"),
            SpindleMode::Rpm => block.words.push("G97"),
        }
        true
    }

    /// A gear range's M code; an M number means a gear range only on the machine it was
    /// written for (and one the profile names): else a comment.
    fn gear_range(&mut self, item: &Item, m: u32, machine: DialectId, block: &mut Block) {
        if machine == super::ID && self.profile.czech.gear_range_mcodes.contains(&m) {
            block.words.push_fmt(format_args!("M{m}"));
        } else {
            self.as_comment(
                item,
                block,
                &format!("M{m}: gear range of the source machine"),
            );
        }
    }

    fn as_comment(&mut self, item: &Item, block: &mut Block, text: &str) {
        self.flush(block);
        self.write(Block {
            comment: Some(format!("{text} (not converted)")),
            ..Block::default()
        });
        self.diag(
            codes::CZW_COMMENT,
            item,
            format!("`{text}` has no czech equivalent; it is written as a comment"),
            "check the czech program by hand where this matters",
        );
    }

    /// A block that follows a J/E pass's empty block must program every axis: when the next
    /// item is not a move, write one that stays where the tool is.
    fn ensure_all_axes(&mut self, item: &Item, block: &mut Block) {
        if !self.all_axes {
            return;
        }
        let (Some(x), Some(z)) = (self.w.pos.x, self.w.pos.z) else {
            return;
        };
        let mut words = Words::default();
        self.push_word(item, "X", 'X', x, &mut words);
        self.push_word(item, "Z", 'Z', z, &mut words);
        self.motion_word("G00", &mut words);
        if block.words.is_empty() {
            // The block being written (its number, its comment) becomes the one that
            // programs every axis.
            block.words = words;
            self.flush(block);
        } else {
            self.flush(block);
            self.write(Block {
                words,
                ..Block::default()
            });
        }
        self.all_axes = false;
    }

    /// The R parameter that should hold `value`: one that already does, else a free one.
    fn lead_param(&mut self, lead: Lead, reserved: &[u32]) -> Option<(u32, bool)> {
        let value = Decimal::parse(&lead.mm_with_point())?;
        if let Some((&n, _)) = self
            .params
            .iter()
            .find(|(_, d)| d.to_lead().ok() == Some(lead))
        {
            return Some((n, false));
        }
        let angle_params: Vec<u32> = match self.profile.czech.constant8.map(|c| c.angle_source()) {
            Some(AngleSource::Parameters { runout, entry }) => {
                vec![runout, entry.unwrap_or(runout)]
            }
            _ => Vec::new(),
        };
        let free = (1..=99).find(|n| {
            *n != 80
                && !reserved.contains(n)
                && !angle_params.contains(n)
                && !self.params.contains_key(n)
        })?;
        self.params.insert(free, value);
        self.chosen.push(free);
        Some((free, true))
    }

    /// The angle word `sign · (100 + angle)` (axis X) that gives `chamfer`'s offset, and
    /// how far the offset it gives is from the IR's.
    fn angle_for(chamfer: &Chamfer) -> (Angle, bool, Length) {
        let ratio = chamfer.offset.abs().to_mm_f64() / (2.0 * chamfer.length.to_mm_f64());
        let angle = Angle((ratio.atan().to_degrees() * 1000.0).round() as i64);
        let offset = Length::from_mm_f64(2.0 * chamfer.length.to_mm_f64() * angle.tan());
        (
            angle,
            chamfer.offset.0 < 0,
            (offset - chamfer.offset.abs()).abs(),
        )
    }

    /// Makes the angle of `chamfer` available for `use_` (runout or entry): writes the
    /// angle parameter's assignment before the pass, or checks constant 8's direct angle.
    fn chamfer_angle(&mut self, item: &Item, chamfer: &Chamfer, what: &str) -> bool {
        let Some(c8) = self.profile.czech.constant8 else {
            self.diag(
                codes::CZW_ANGLE,
                item,
                format!("the pass has a {what}, and the czech control takes its angle from machine constant 8, which the profile does not give"),
                "give the target machine's constant 8 in a profile: [czech] constant8 = \"04000000\"",
            );
            return false;
        };
        let (angle, negative, deviation) = Self::angle_for(chamfer);
        if angle > MAX_ANGLE {
            self.diag(
                codes::CZW_ANGLE,
                item,
                format!("the {what} angle {angle}° is over the czech control's 60°"),
                "a steeper runout cannot be cut on this control",
            );
            return false;
        }
        if deviation > Length::from_steps(1) {
            self.diag(
                codes::CZW_ANGLE,
                item,
                format!(
                    "the {what} offset {} cannot be reached with an angle in 0.001° (off by {})",
                    chamfer.offset.mm(),
                    deviation.mm()
                ),
                "the angle resolution of the czech control is 0.001°",
            );
            return false;
        }
        let word = (100_000 + angle.0) * if negative { -1 } else { 1 };
        match c8.angle_source() {
            AngleSource::Direct { word: fixed } if fixed == word => true,
            AngleSource::Direct { word: fixed } => {
                self.diag(
                    codes::CZW_ANGLE,
                    item,
                    format!("the {what} needs {}{angle}° but machine constant 8 ({c8}) fixes {}°", if negative { "−" } else { "" }, Angle(fixed.abs() % 100_000)),
                    "constant 8 is in direct mode: every runout and entry has its angle; use a machine in parameter mode or change the angle",
                );
                false
            }
            AngleSource::Parameters { runout, entry } => {
                let param = if what == "entry" {
                    entry.unwrap_or(runout)
                } else {
                    runout
                };
                self.angle_parameter(item, c8, param, what, chamfer)
            }
        }
    }

    /// Sets R`param`, which constant 8 (`c8`) names for the `what` angle, to the angle of
    /// `chamfer` (in a block of its own, unless it holds it already); `false` when the
    /// parameter may not hold an angle.
    fn angle_parameter(
        &mut self,
        item: &Item,
        c8: Constant8,
        param: u32,
        what: &str,
        chamfer: &Chamfer,
    ) -> bool {
        let (angle, negative, _) = Self::angle_for(chamfer);
        let word = (100_000 + angle.0) * if negative { -1 } else { 1 };
        if param == 0 || param == 80 {
            self.diag(
                codes::CZW_ANGLE,
                item,
                format!("machine constant 8 ({c8}) names R{param:02} for the {what} angle, and R00 and R80 may not hold angles"),
                "check the target machine's constant 8 (the manual recommends R04)",
            );
            return false;
        }
        let value = Decimal {
            mantissa: word as i128,
            scale: 3,
            has_point: true,
        };
        let holds = self
            .params
            .get(&param)
            .is_some_and(|v| v.to_scaled(3).ok() == Some(word));
        if !holds {
            self.params.insert(param, value);
            let text = format_param(value);
            self.write(Block {
                words: Words(format!("R{param:02}={text}")),
                comment: Some(format!(
                    "{what} angle {}{angle}°",
                    if negative { "−" } else { "+" }
                )),
                ..Block::default()
            });
        }
        true
    }

    fn thread_pass(&mut self, item: &Item, pass: &ThreadPass, block: &mut Block, reserved: &[u32]) {
        // Refused by legalisation: no synchronised move along X on this control.
        if pass.infeed.is_some() {
            return;
        }
        if !self.chamfer_angles(item, pass, block) {
            return;
        }
        let mut start_angle = match pass.start {
            SyncStart::Index(angle) => angle,
            // Refused by legalisation: every czech G33 block waits for the index pulse.
            SyncStart::Continue => return,
        };
        if self.round {
            start_angle = self.start_on_grid(pass, start_angle, block);
        }
        // On the 0.001 grid (--round) a very short pass can lose its travel.
        let on_grid = |z: Length| crate::fixed::div_round(z.0 as i128, 100);
        if let (Some(from), Some(to)) = (self.w.pos.z, pass.to.z)
            && from != to
            && on_grid(from) == on_grid(to)
        {
            return self.diag(
                codes::CZW_PRECISION,
                item,
                format!(
                    "the thread pass's Z travel of {} mm rounds to nothing on the czech control's 0.001 mm grid",
                    (to - from).abs().mm()
                ),
                "a G33 block needs Z travel the control can measure; lengthen the pass in the source",
            );
        }
        let end_x = pass
            .to
            .x
            .map(|x| x + pass.entry.map_or(Length::ZERO, |c| c.offset));
        let mut words = self.axes(
            item,
            Pos {
                x: end_x,
                z: pass.to.z,
            },
        );
        self.motion_word("G33", &mut words);
        let Some(lead) = self.pass_lead(item, pass) else {
            return;
        };
        if self.f != Some((lead, true)) && !self.lead_word(item, lead, reserved, block, &mut words)
        {
            return;
        }
        if start_angle != Angle::ZERO {
            words.push_fmt(format_args!("I{}", start_angle.deg()));
        }
        if let Some(r) = pass.exit {
            self.push_word(item, "runout J", 'J', r.length, &mut words);
        }
        if let Some(e) = pass.entry {
            self.push_word(item, "entry E", 'E', e.length, &mut words);
        }
        let spare = block.words.extend(words);
        self.recycle(spare);
        self.w.pos = pass.end_position(self.w.pos);
        self.in_cut = Some(self.w.pos);
        if pass.entry.is_some() || pass.exit.is_some() {
            // The empty block, then a block that programs every axis. **[seed]**
            self.flush(block);
            self.pending_empty = true;
            self.all_axes = true;
        }
    }

    /// The entry's and runout's angles, in parameter blocks before the pass (the block in
    /// hand written first); `false` when they cannot be set (a diagnostic says why).
    fn chamfer_angles(&mut self, item: &Item, pass: &ThreadPass, block: &mut Block) -> bool {
        let entry_param = self.profile.czech.constant8.map(|c| c.angle_source());
        if (pass.entry.is_some() || pass.exit.is_some()) && !block.words.is_empty() {
            self.flush(block);
        }
        if let (Some(e), Some(r)) = (pass.entry, pass.exit)
            && matches!(
                entry_param,
                Some(AngleSource::Parameters { entry: None, .. })
            )
            && Self::angle_for(&e).0 != Self::angle_for(&r).0
        {
            self.diag(
                codes::CZW_ANGLE,
                item,
                "entry and runout need different angles, and constant 8 gives both from one parameter".into(),
                "use a machine whose constant 8 names an entry parameter (decades 6–5)",
            );
            return false;
        }
        if let Some(r) = pass.exit
            && !self.chamfer_angle(item, &r, "runout")
        {
            return false;
        }
        if let Some(e) = pass.entry
            && !self.chamfer_angle(item, &e, "entry")
        {
            return false;
        }
        true
    }

    /// A start that needs a 4th decimal (--round) moves along the pass onto the 0.001 grid
    /// (less than 0.001 mm, inside the tolerance), and the start angle changes by the turns
    /// that takes, so the helix stays: a start later along the travel is reached later.
    /// Of the two grid points the nearer one whose angle stays in 0…360° is taken (so that
    /// no other control starts almost a turn early), and the tool moves there; in the cut
    /// (right after another pass) the tool stays where the last block left it, and the
    /// angle wraps.
    fn start_on_grid(
        &mut self,
        pass: &ThreadPass,
        mut start_angle: Angle,
        block: &mut Block,
    ) -> Angle {
        let (Some(z), Some(end_z)) = (self.w.pos.z, pass.to.z) else {
            return start_angle;
        };
        if z.on_mm_decimals(3) {
            return start_angle;
        }
        let towards = (end_z - z).signum();
        let angle_for =
            |c: Length| start_angle.0 + pass.lead.turn_over(Length(towards * (c - z).0));
        let nearest = Length(crate::fixed::div_round(z.0 as i128, 100) as i64 * 100);
        let other = if nearest < z {
            nearest + Length::from_steps(10)
        } else {
            nearest - Length::from_steps(10)
        };
        let in_cut = self.in_cut == Some(self.w.pos);
        match [nearest, other]
            .into_iter()
            .find(|&c| (0..360_000).contains(&angle_for(c)))
        {
            Some(at) if !in_cut => {
                start_angle = Angle(angle_for(at));
                if at != nearest {
                    self.flush(block);
                    let mut words = Words::default();
                    let out = words.next();
                    out.push('Z');
                    at.push_mm_with_point(out);
                    self.motion_word("G00", &mut words);
                    self.write(Block {
                        words,
                        ..Block::default()
                    });
                }
            }
            _ => start_angle = Angle(angle_for(nearest).rem_euclid(360_000)),
        }
        start_angle
    }

    /// A pass's lead in the control's 4 decimals: another is refused (`None`), or with
    /// --round rounded with the drift at the thread's end as its deviation. A lead that
    /// rounds to nothing is refused.
    fn pass_lead(&mut self, item: &Item, pass: &ThreadPass) -> Option<Lead> {
        let (units, exact) = pass.lead.in_units(4);
        let lead = Lead::from_units(units, 4);
        if units <= 0 {
            self.diag(
                codes::CZW_PRECISION,
                item,
                format!(
                    "the lead {} mm rounds to 0 in the czech control's 0.0001 mm",
                    pass.lead
                ),
                "a thread needs a lead the control can hold",
            );
            return None;
        }
        if !exact {
            let travel = match (self.w.pos.z, pass.to.z) {
                (Some(a), Some(b)) => (b - a).abs(),
                _ => Length::ZERO,
            };
            let drift = pass.lead.drift(lead, travel);
            self.inexact
                .note_lead(item.span, "lead F", pass.lead, drift, Length::from_steps(1));
        }
        Some(lead)
    }

    /// The lead word: F, or over 99.99 FR with the R parameter that holds it (set in a
    /// block before); `false` when no parameter is free.
    fn lead_word(
        &mut self,
        item: &Item,
        lead: Lead,
        reserved: &[u32],
        block: &mut Block,
        words: &mut Words,
    ) -> bool {
        if lead > Lead::from_length(MAX_DIRECT_LEAD) {
            let Some((n, new)) = self.lead_param(lead, reserved) else {
                self.diag(
                    codes::CZW_NO_EQUIVALENT,
                    item,
                    format!(
                        "the lead {} is over 99.99 and no R parameter is free to hold it",
                        lead
                    ),
                    "free an R parameter in the program",
                );
                return false;
            };
            if new {
                self.flush(block);
                self.write(Block {
                    words: Words(format!("R{n:02}={}", lead.mm_with_point())),
                    comment: Some("lead over 99.99".into()),
                    ..Block::default()
                });
            }
            words.push_fmt(format_args!("FR{n:02}"));
        } else {
            let out = words.next();
            out.push('F');
            lead.push_mm_with_point(out);
        }
        self.f = Some((lead, true));
        true
    }

    fn thread_cycle(&mut self, item: &Item, cycle: &ThreadCycle, reserved: &[u32]) {
        let Some(steps) = self.w.cycle_steps(cycle, item.span, "D") else {
            return;
        };
        for step in steps {
            match step {
                write::CycleStep::Comment(comment) => self.write(Block {
                    comment: Some(comment),
                    ..Block::default()
                }),
                write::CycleStep::Move(moved) => {
                    let mut block = Block::default();
                    self.item(&moved, &mut block, reserved);
                    self.flush(&mut block);
                }
            }
        }
        self.w.pos = item.kind.end_position(self.w.pos);
    }
}

/// `120.0`, `-118.435`: an angle parameter's value with at least one decimal.
fn format_param(v: Decimal) -> String {
    let text = Length::from_steps(v.mantissa as i64 * 10).mm_with_point();
    if text.ends_with('.') {
        format!("{text}0")
    } else {
        text
    }
}
/// The M code of a coolant command.
fn coolant_word(c: Coolant) -> &'static str {
    match c {
        Coolant::Mist => "M07",
        Coolant::Flood => "M08",
        Coolant::Off => "M09",
    }
}

/// The spindle's speed S and direction M03/M04.
fn spindle_words(speed: Option<u32>, direction: Option<SpindleDirection>, block: &mut Block) {
    if let Some(s) = speed {
        block.words.push_fmt(format_args!("S{s}"));
    }
    match direction {
        Some(SpindleDirection::Clockwise) => block.words.push("M03"),
        Some(SpindleDirection::CounterClockwise) => block.words.push("M04"),
        None => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dialect::{ItemWriter, Unsupported};

    /// A lead over 99.99 from another dialect takes the lowest free R parameter: parameters
    /// the program assigns after the writer's first item are taken late only while that one is
    /// not among them.
    #[test]
    fn a_parameter_chosen_for_a_lead_is_not_taken_late() {
        let src = SourceFile::new(
            "t.ngc",
            "G7 G18 G21 G90 G95\nT1 M6\nS100 M3\nG0 X40 Z5\nG33 Z-30 K120\nG0 X45\nM5\nM30\n",
        );
        let profile = Profile::default();
        let iso = crate::dialect::get(crate::dialect::iso::ID);
        let (program, diags) = iso.read(&src, &profile, Unsupported::Error);
        assert!(!crate::diag::has_errors(&diags), "{diags:?}");
        let program = crate::lower::unroll(&program, Some(super::super::ID));
        let facts = write::Facts::default();
        let mut w = Items::new(
            &facts,
            program.dialect,
            &src,
            &profile,
            Renumber::default(),
            false,
        );
        for item in &program.items {
            w.item(item);
        }
        assert_eq!(w.e.chosen, [1]);
        let late = |params: Vec<u32>| write::Facts {
            params,
            arcs: false,
        };
        assert!(w.late_facts(&late(vec![2, 3])));
        assert_eq!(w.reserved, [2, 3]);
        assert!(!w.late_facts(&late(vec![1, 2])));
    }
}

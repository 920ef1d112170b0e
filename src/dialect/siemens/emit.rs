//! IR → SINUMERIK native turning (siemens.md "Writing").
//!
//! The frame: `%_N_<NAME>_MPF`, `;$PATH=/_N_MPF_DIR`, a comment saying where the program came
//! from, `N10 G18 G90 G710 G95 G40 DIAMON` (G710: lengths and feeds in millimetres whatever the
//! machine's basic system; X a diameter), the
//! program, its end (`M30`, `M2`) where the source has one: M30 stops the spindle and the
//! coolant, which a program without an end does not (siemens.md says "the end M30"; see
//! ARCHITECTURE.md). Every block is numbered
//! (`N10, N20, …`); comments are `;` to the line's end, in ASCII. X Z I K take 3 decimals (I a
//! radius value, as K, increments from the arc's start), F and K 4, `SF=` 3. A thread pass is
//! one `G33 Z… K<lead> SF=<angle>` block (X too on a taper), `SF=` on every G33 block; cycles
//! are written as their passes. What the writer does not write (chains of G33 blocks, steep
//! tapers, compensation, tapping, machine coordinates) is refused by the capability table.

use std::fmt::Write as _;

use crate::diag::{Code, Diagnostic};
use crate::dialect::siemens::codes;
use crate::dialect::write::{self, Writer};
use crate::dialect::{Inexact, Renumber};
use crate::fixed::{Angle, Decimal, Lead, Length, div_round};
use crate::ir::{
    Compensation, Coolant, EndCode, FeedMode, Item, ItemKind, Pos, Program, SpindleDirection,
    SpindleMode, SyncStart, ThreadCycle, ThreadPass,
};
use crate::lower;
use crate::source::{SourceFile, Span};

/// How the header comment of a program ncthread wrote ends.
pub(crate) const HEADER_END: &str = ", converted by ncthread";

/// The modes line every program starts with.
const MODES: &str = "G18 G90 G710 G95 G40 DIAMON";

#[derive(Default)]
struct Block {
    words: Vec<String>,
    comment: Option<String>,
    /// The block holds a motion (a second motion starts a new block).
    moves: bool,
    /// The comment is ncthread's own (a cycle's summary): not counted as transliterated.
    own_comment: bool,
}

struct Emitter<'a> {
    w: Writer<'a>,
    number: u32,
    step: u32,
    motion: Option<&'static str>,
    f: Option<Length>,
    feed_mode: FeedMode,
    compensation_off: bool,
    /// G96 in force, with the LIMS written.
    surface_speed: bool,
    limit: Option<i64>,
    /// The last S written, and a G96/G97 of this block that still needs its S.
    speed: Option<u32>,
    speed_word: Option<(Item, usize)>,
    /// The spindle turns in the output (M3/M4 written, no M5 since).
    turning: bool,
    /// A G97 was written without S while the spindle stood: the next start says its S.
    speed_unsaid: bool,
    /// The last motion was a G33 (a G33 now would continue it: refused by the table).
    after_thread: bool,
    at: Span,
    comments: write::AsciiComments,
    inexact: Inexact,
    round: bool,
    /// The tool in use (D is one of its cutting edges).
    tool: Option<u32>,
}

/// The program's name for `%_N_<NAME>_MPF`: the source's own (a SINUMERIK program's), else
/// the file's stem in upper case, letters, digits and `_` only, starting with two letters.
fn program_name(program: &Program, src: &SourceFile) -> String {
    let stem = std::path::Path::new(&src.name)
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("");
    let raw = match &program.name {
        Some(name) if program.dialect == super::ID => name.as_str(),
        _ => stem,
    };
    let mut name: String = deunicode::deunicode(raw)
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_uppercase()
            } else {
                '_'
            }
        })
        .collect();
    if !name.chars().take(2).all(|c| c.is_ascii_alphabetic()) || name.len() < 2 {
        name.insert_str(0, "NC_");
    }
    name.truncate(24);
    name.trim_end_matches('_').to_string()
}

/// The SINUMERIK writer taking a program's items one at a time (a conversion's streaming
/// read), or a whole program ([`Dialect::write`](crate::dialect::Dialect::write)).
pub(crate) struct Items<'a> {
    e: Emitter<'a>,
    /// The program's dialect.
    from: crate::ir::DialectId,
    /// Before the first item that is not a `%` line: it may be the header comment.
    header: bool,
    groups: write::Grouper,
}

impl<'a> Items<'a> {
    /// For `program`'s name and dialect (its items are not needed).
    pub fn new(program: &Program, src: &'a SourceFile, renumber: Renumber, round: bool) -> Self {
        let keep = program.dialect == super::ID;
        let mut e = Emitter {
            w: Writer::new(src),
            number: renumber.start,
            step: renumber.step.max(1),
            motion: None,
            f: None,
            feed_mode: FeedMode::PerRev,
            compensation_off: true,
            surface_speed: false,
            limit: None,
            speed: None,
            speed_word: None,
            turning: false,
            speed_unsaid: false,
            after_thread: false,
            at: Span::default(),
            comments: write::AsciiComments::default(),
            inexact: Inexact::default(),
            round,
            tool: None,
        };
        let _ = writeln!(e.w.out, "%_N_{}_MPF", program_name(program, src));
        e.w.out.push_str(";$PATH=/_N_MPF_DIR\n");
        Items {
            e,
            from: program.dialect,
            header: true,
            groups: write::Grouper::new(keep),
        }
    }

    /// The program's start, once its first item that is not a `%` line is known (`None`:
    /// the program has none): the header comment and the modes. Whether that item was the
    /// header comment.
    fn begin(&mut self, first: Option<&Item>) -> bool {
        let header = self.e.header_comment(self.from, first);
        self.e.write(Block {
            words: vec![MODES.into()],
            ..Block::default()
        });
        self.header = false;
        header
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

    fn item(&mut self, item: &Item) {
        if self.header {
            if item.kind == ItemKind::Delimiter {
                return;
            }
            if self.begin(Some(item)) {
                return;
            }
        }
        let e = &mut self.e;
        self.groups.item(item, |group| {
            e.w.spill();
            e.group(group);
        });
    }

    fn finish(mut self: Box<Self>) -> (Option<crate::dialect::Output>, Vec<Diagnostic>) {
        if self.header {
            self.begin(None);
        }
        let e = &mut self.e;
        self.groups.finish(|group| {
            e.w.spill();
            e.group(group);
        });
        let mut e = self.e;
        e.closing_diagnostics();
        e.w.finish()
    }
}

impl Emitter<'_> {
    /// The header comment: the source's own (`first`, the first item that is not a `%`
    /// line, when it is a comment ncthread wrote), or the file's name and the program's
    /// dialect `from`. Whether it was `first`.
    fn header_comment(&mut self, from: crate::ir::DialectId, first: Option<&Item>) -> bool {
        if let Some(first) = first
            && let ItemKind::Comment(c) = &first.kind
            && write::ascii_comment(c).0.ends_with(HEADER_END)
        {
            let _ = writeln!(self.w.out, "; {}", write::ascii_comment(c).0);
            return true;
        }
        let src = self.w.src;
        let file = std::path::Path::new(&src.name)
            .file_name()
            .map_or(src.name.as_str(), |n| n.to_str().unwrap_or(&src.name));
        let _ = writeln!(
            self.w.out,
            "; {}, dialect {from}{HEADER_END}",
            write::ascii_comment(file).0,
        );
        false
    }

    fn closing_diagnostics(&mut self) {
        let src = self.w.src;
        let summary = write::grid_diagnostic(
            &mut self.inexact,
            src,
            self.round,
            "SINUMERIK",
            (codes::SINW_ROUNDED, codes::SINW_PRECISION),
            "a thread's start rounded onto the grid keeps its helix: its SF= moves with it",
        );
        self.w.diags.extend(summary);
        let ascii = self
            .comments
            .diagnostic(src, codes::SINW_TRANSLITERATED, "SINUMERIK");
        self.w.diags.extend(ascii);
    }

    fn diag(&mut self, code: Code, item: &Item, message: String, help: &str) {
        self.w.error(code, item.span, message, help);
    }

    /// A comment's ASCII text, its transliteration counted.
    fn comment(&mut self, text: &str) -> String {
        self.comments.text(self.at, text)
    }

    fn write(&mut self, block: Block) {
        let comment = block
            .comment
            .map(|c| {
                if block.own_comment {
                    write::ascii_comment(&c).0
                } else {
                    self.comment(&c)
                }
            })
            .filter(|c| !c.is_empty());
        let mut line = String::new();
        if !block.words.is_empty() {
            let _ = write!(line, "N{} {}", self.number, block.words.join(" "));
            self.number = self.number.saturating_add(self.step);
        }
        if let Some(c) = comment {
            if !line.is_empty() {
                line.push(' ');
            }
            let _ = write!(line, "; {c}");
        }
        if !line.is_empty() {
            self.w.out.push_str(&line);
            self.w.out.push('\n');
        }
    }

    fn flush(&mut self, block: &mut Block) {
        if !block.words.is_empty() || block.comment.is_some() {
            let b = std::mem::take(block);
            self.write(b);
        }
    }

    fn group(&mut self, items: &[Item]) {
        self.at = items[0].span;
        let mut block = Block {
            comment: items[0].comment.as_deref().map(str::to_string),
            ..Block::default()
        };
        for item in items {
            self.at = item.span;
            if self.kind(item, &mut block) {
                self.w.pos = item.kind.end_position(self.w.pos);
            }
        }
        // A G96 or G97 says its speed: SINUMERIK's G97 without S keeps the rpm the spindle
        // turns at, where the source's S register holds the speed.
        if let Some((item, at)) = self.speed_word.take() {
            match self.speed {
                Some(s) => block.words.insert(at.min(block.words.len()), format!("S{s}")),
                None => self.diag(
                    codes::SINW_NO_EQUIVALENT,
                    &item,
                    "a change of spindle speed mode (G96/G97) before any speed is set: the SINUMERIK block says the speed with it".into(),
                    "give the speed (S) in the source before or with G96/G97",
                ),
            }
        }
        self.flush(&mut block);
    }

    /// `v` on the 0.001 mm grid (rounded with `--round`, or counted for one error).
    fn three(&mut self, item: &Item, what: &str, v: Length) -> String {
        write::on_micron_grid(&mut self.inexact, item.span, what, v).mm()
    }

    fn axes(&mut self, item: &Item, to: Pos) -> Vec<String> {
        let mut words = Vec::new();
        if let Some(x) = to.x {
            words.push(format!("X{}", self.three(item, "X", x)));
        }
        if let Some(z) = to.z {
            words.push(format!("Z{}", self.three(item, "Z", z)));
        }
        words
    }

    fn motion_block(&mut self, block: &mut Block, g: &'static str) {
        if block.moves {
            self.flush(block);
        }
        block.moves = true;
        if self.motion != Some(g) {
            block.words.push(g.to_string());
            self.motion = Some(g);
        }
    }

    /// A feed or a lead on the 0.0001 mm grid.
    fn four(&mut self, item: &Item, what: &str, lead: Lead, travel: Length) -> Option<Lead> {
        let code = codes::SINW_PRECISION;
        write::lead_on_grid(
            &mut self.w,
            &mut self.inexact,
            code,
            item.span,
            what,
            (lead, travel),
        )
    }

    fn feed_word(&mut self, item: &Item, feed: Length, block: &mut Block) {
        if self.f == Some(feed) {
            return;
        }
        // A zero feed no move runs at (the SINUMERIK reader takes `F0`, as LinuxCNC does).
        if feed == Length::ZERO {
            block.words.push("F0".to_string());
            self.f = Some(feed);
            return;
        }
        let Some(written) = self.four(item, "F", Lead::from_length(feed), Length::ZERO) else {
            return;
        };
        block.words.push(format!("F{}", written.mm()));
        self.f = Some(feed);
    }

    /// Writes an item into `block` (or into blocks of its own): one arm per kind of item.
    /// `false` when it is refused (a diagnostic says why).
    fn kind(&mut self, item: &Item, block: &mut Block) -> bool {
        match &item.kind {
            ItemKind::Rapid { to } => {
                self.after_thread = false;
                self.motion_block(block, "G0");
                let words = self.axes(item, *to);
                block.words.extend(words);
            }
            ItemKind::Feed { to, feed } => {
                self.after_thread = false;
                self.motion_block(block, "G1");
                let words = self.axes(item, *to);
                block.words.extend(words);
                self.feed_word(item, *feed, block);
            }
            ItemKind::Arc {
                to,
                centre,
                clockwise,
                feed,
            } => {
                self.after_thread = false;
                return self.arc(item, *to, **centre, *clockwise, *feed, block);
            }
            ItemKind::ThreadPass(pass) => return self.thread_pass(item, pass, block),
            ItemKind::ThreadCycle(cycle) => {
                self.flush(block);
                self.thread_cycle(item, cycle);
            }
            // Refused by legalisation (the table's rows).
            ItemKind::TapCycle(_) | ItemKind::MachineMove(_) | ItemKind::Roughing(_) => {}
            ItemKind::ModelCycle(_) => {}
            ItemKind::Comment(_)
            | ItemKind::ParamAssign { .. }
            | ItemKind::Opaque { .. }
            | ItemKind::GearRange { .. }
            | ItemKind::MachineCode { .. }
            | ItemKind::Delimiter => self.note(item, block),
            _ => return self.setting(item, block),
        }
        true
    }

    /// An item that moves nothing and is no comment: its words in `block`; `false` when
    /// refused.
    fn setting(&mut self, item: &Item, block: &mut Block) -> bool {
        match &item.kind {
            ItemKind::Spindle { speed, direction } => {
                return self.spindle(item, *speed, *direction, block);
            }
            ItemKind::SpindleStop => {
                self.turning = false;
                block.words.push("M5".into());
            }
            ItemKind::SpindleMode(mode) => return self.spindle_mode(item, mode, block),
            ItemKind::Tool { number, offset } => return self.tool(item, *number, *offset, block),
            ItemKind::FeedMode(mode) if *mode != self.feed_mode => {
                self.feed_mode = *mode;
                // G94/G95 are of G96's group: under a surface speed the feed's kind is said
                // with it (G961 is G96 with a feed per minute), and its S again.
                if self.surface_speed {
                    block.words.push(self.speed_code(true).into());
                    self.speed_word = Some((item.clone(), block.words.len()));
                } else {
                    let g = if *mode == FeedMode::PerRev {
                        "G95"
                    } else {
                        "G94"
                    };
                    block.words.push(g.into());
                }
                // F is written again after every change of mode (siemens.md).
                self.f = None;
            }
            ItemKind::ProgramEnd(end) => {
                block.words.push(
                    match end {
                        EndCode::M2 => "M2",
                        EndCode::M30 => "M30",
                    }
                    .into(),
                );
            }
            ItemKind::Coolant(Coolant::Flood) => block.words.push("M8".into()),
            ItemKind::Coolant(Coolant::Off) => block.words.push("M9".into()),
            // Refused by the table (mist is the machine builder's M code).
            ItemKind::Coolant(Coolant::Mist) => {}
            ItemKind::Stop { optional } => {
                block.words.push(if *optional { "M1" } else { "M0" }.into())
            }
            ItemKind::Dwell { seconds } => return self.dwell(item, *seconds, block),
            ItemKind::Compensation(Compensation::Off) if !self.compensation_off => {
                block.words.push("G40".into());
                self.compensation_off = true;
            }
            // Refused by the table.
            ItemKind::Compensation(_) => {}
            ItemKind::WorkOffset(n) => {
                if (1..=4).contains(n) {
                    block.words.push(format!("G{}", 53 + u32::from(*n)));
                } else {
                    self.diag(
                        codes::SINW_NO_EQUIVALENT,
                        item,
                        format!("work offset {n}: ncthread writes G54–G57, the settable offsets every SINUMERIK has (G58/G59 are programmable offsets there, not work offsets)"),
                        "use G54–G57 in the source",
                    );
                    return false;
                }
            }
            ItemKind::FeedRate(feed) if self.f != Some(*feed) => {
                self.feed_word(item, *feed, block);
            }
            _ => {}
        }
        true
    }

    /// `T<n>` and its cutting edge: `D1` for the tool's own offset, `D0` for none (D is an
    /// edge of the tool in use, so another tool's offset is refused); a T alone takes D1.
    fn tool(
        &mut self,
        item: &Item,
        number: Option<u32>,
        offset: Option<u32>,
        block: &mut Block,
    ) -> bool {
        let tool = number.or(self.tool);
        let edge = match offset {
            None if number.is_some() => None,
            None => return true,
            Some(0) => Some(0),
            // A T takes its D1 itself.
            Some(d) if Some(d) == number => None,
            Some(d) if Some(d) == tool => Some(1),
            Some(d) => {
                self.diag(
                    codes::SINW_NO_EQUIVALENT,
                    item,
                    format!("the offset {d} with tool {}: a SINUMERIK D is a cutting edge of the tool in use, not another tool's offset", tool.map_or("(none)".into(), |t| t.to_string())),
                    "use each tool with its own offset in the source",
                );
                return false;
            }
        };
        if let Some(t) = number {
            block.words.push(format!("T{t}"));
            self.tool = Some(t);
        }
        if let Some(d) = edge {
            block.words.push(format!("D{d}"));
        }
        true
    }

    /// A comment, or what is written as one (parameters, another control's words).
    fn note(&mut self, item: &Item, block: &mut Block) {
        match &item.kind {
            ItemKind::Comment(text) => {
                if !block.words.is_empty() || block.comment.is_some() {
                    self.flush(block);
                }
                block.comment = Some(text.to_string());
            }
            ItemKind::ParamAssign { number, value } => {
                self.flush(block);
                self.write(Block {
                    comment: Some(format!("parameter {number} = {value}")),
                    own_comment: true,
                    ..Block::default()
                });
            }
            ItemKind::Opaque { dialect, text, .. } => {
                self.as_comment(item, block, &format!("{dialect}: {text}"));
            }
            ItemKind::GearRange { code, machine } => self.as_comment(
                item,
                block,
                &format!("M{code}: gear range of the {machine} machine"),
            ),
            ItemKind::MachineCode { code, machine } => {
                self.as_comment(item, block, &crate::ir::machine_code_note(*code, *machine))
            }
            _ => {}
        }
    }

    fn as_comment(&mut self, item: &Item, block: &mut Block, text: &str) {
        self.flush(block);
        self.write(Block {
            comment: Some(format!("{text} (not converted)")),
            ..Block::default()
        });
        self.w.report(
            Diagnostic::new(
                codes::SINW_COMMENT,
                format!("`{text}` has no SINUMERIK equivalent; it is written as a comment"),
            )
            .at(self.w.src, item.span)
            .help("check the SINUMERIK program by hand where this matters"),
        );
    }

    /// The code of a spindle speed mode, which says the feed's kind too (one G group):
    /// G96/G97 with a feed per revolution, G961/G971 per minute.
    fn speed_code(&self, surface: bool) -> &'static str {
        match (surface, self.feed_mode) {
            (true, FeedMode::PerRev) => "G96",
            (true, FeedMode::PerMin) => "G961",
            (false, FeedMode::PerRev) => "G97",
            (false, FeedMode::PerMin) => "G971",
        }
    }

    /// The spindle's speed and direction words; `false` when refused.
    fn spindle(
        &mut self,
        item: &Item,
        speed: Option<u32>,
        direction: Option<SpindleDirection>,
        block: &mut Block,
    ) -> bool {
        // LIMS limits G97 too: a speed above it would not be the speed.
        if let (Some(s), Some(l)) = (speed, self.limit)
            && !self.surface_speed
            && i64::from(s) > l
        {
            self.diag(
                codes::SINW_NO_EQUIVALENT,
                item,
                format!("S{s} rpm above the speed limit LIMS={l} in force: on a SINUMERIK LIMS limits G97 too, where the source's limit was its surface speed's only"),
                "lower the speed to the limit in the source, or raise the surface speed's limit",
            );
            return false;
        }
        // After a bare G97 the start says the speed the program has (`speed_unsaid`).
        let speed = speed.or(self
            .speed
            .filter(|_| direction.is_some() && self.speed_unsaid));
        if let Some(s) = speed {
            block.words.push(format!("S{s}"));
            self.speed = Some(s);
            self.speed_word = None;
            self.speed_unsaid = false;
        }
        match direction {
            Some(SpindleDirection::Clockwise) => block.words.push("M3".into()),
            Some(SpindleDirection::CounterClockwise) => block.words.push("M4".into()),
            None => {}
        }
        if direction.is_some() {
            self.turning = true;
        }
        true
    }

    /// G97 S, or G96 S LIMS= (the S the spindle item's that follows in the block, or the
    /// speed the program has).
    fn spindle_mode(&mut self, item: &Item, mode: &SpindleMode, block: &mut Block) -> bool {
        match mode {
            // While the spindle stands, a G97 needs no S: the next start says its S. Under
            // G97 already, it changes nothing.
            SpindleMode::Rpm if !self.turning || !self.surface_speed => {
                let code = self.speed_code(false);
                if block.words.last().map(String::as_str) != Some(code) {
                    block.words.push(code.into());
                }
                self.speed_unsaid |= self.surface_speed;
                self.surface_speed = false;
            }
            SpindleMode::Rpm => {
                block.words.push(self.speed_code(false).into());
                self.surface_speed = false;
                self.speed_word = Some((item.clone(), block.words.len()));
            }
            SpindleMode::SurfaceSpeed { feet: true, .. } => {
                self.diag(
                    codes::SINW_NO_EQUIVALENT,
                    item,
                    "a surface speed in feet per minute (G96 under G20): the SINUMERIK program is written in millimetres (G710), where G96's S is m/min".into(),
                    "program the surface speed in m/min in the source, or cut at a speed in rpm (G97)",
                );
                return false;
            }
            SpindleMode::SurfaceSpeed { limit, .. } => {
                let limit = match limit.map(Decimal::to_whole) {
                    None => None,
                    Some(Ok(n)) if n > 0 => Some(n),
                    Some(_) => {
                        self.diag(
                            codes::SINW_PRECISION,
                            item,
                            format!("the surface speed's limit of {} rpm is not a whole number of rpm, which LIMS= takes", limit.map(|d| d.to_string()).unwrap_or_default()),
                            "write the limit in whole rpm in the source",
                        );
                        return false;
                    }
                };
                if limit.is_none() && self.limit.is_some() {
                    self.diag(
                        codes::SINW_NO_EQUIVALENT,
                        item,
                        "a surface speed without a speed limit after one with a limit: LIMS= stays in force, and the program cannot lift it".into(),
                        "give this surface speed a limit in the source (LinuxCNC's G96 … D, FANUC's G50 S)",
                    );
                    return false;
                }
                // A change of the feed's kind in the same block said it already.
                let code = self.speed_code(true);
                if block.words.last().map(String::as_str) != Some(code) {
                    block.words.push(code.into());
                }
                if let Some(n) = limit.filter(|n| self.limit != Some(*n)) {
                    block.words.push(format!("LIMS={n}"));
                    self.limit = Some(n);
                }
                self.surface_speed = true;
                self.speed_word = Some((item.clone(), block.words.len()));
            }
        }
        true
    }

    /// `G4 F<s>` in a block of its own.
    fn dwell(&mut self, item: &Item, seconds: Decimal, block: &mut Block) -> bool {
        let Ok(ms) = seconds.to_scaled(3) else {
            self.diag(
                codes::SINW_PRECISION,
                item,
                format!("the dwell of {seconds} s needs more than the 0.001 s G4 F takes"),
                "write the dwell in whole milliseconds in the source",
            );
            return false;
        };
        self.flush(block);
        let comment = block.comment.take();
        self.write(Block {
            words: vec![
                "G4".into(),
                format!("F{}", Length::from_steps(ms * 10).mm()),
            ],
            comment,
            ..Block::default()
        });
        true
    }

    /// `G2`/`G3 X Z I K F`: I and K the centre's offset from the start, I a radius value.
    fn arc(
        &mut self,
        item: &Item,
        to: Pos,
        centre: Pos,
        clockwise: bool,
        feed: Length,
        block: &mut Block,
    ) -> bool {
        let (Some((sx, sz)), Some((cx, cz)), Some((ex, ez))) =
            (self.w.pos.known(), centre.known(), to.known())
        else {
            self.diag(
                codes::SINW_NO_EQUIVALENT,
                item,
                "an arc from a position that is not known: its centre cannot be written".into(),
                "move to an absolute X and Z before the arc",
            );
            return false;
        };
        self.motion_block(block, if clockwise { "G2" } else { "G3" });
        let words = self.axes(item, Pos::new(ex, ez));
        block.words.extend(words);
        let grid = Length::from_steps(10);
        let dx = cx - sx;
        let on_grid = dx.0 % (2 * grid.0) == 0 && (cz - sz).0 % grid.0 == 0;
        // A centre off the grid (an R arc's, from the source's radius) is written as the CR=
        // the control takes, where the centre it finds from it stays within 0.0005 mm.
        if !on_grid && (sx, sz) != (ex, ez) {
            let over = lower::arc::over_half_turn((sx, sz), (ex, ez), (cx, cz), clockwise);
            let (r1, _) = lower::arc::radii((sx, sz), (ex, ez), (cx, cz));
            let r = Length(
                div_round(Length::from_mm_f64(r1).0 as i128, grid.0 as i128) as i64 * grid.0,
            );
            let signed = if over { -r.to_mm_f64() } else { r.to_mm_f64() };
            let off = lower::arc::centre_miss((sx, sz), (ex, ez), (cx, cz), signed, clockwise);
            if off <= 0.0005 && r.0 > 0 {
                let text = if over { format!("-{}", r.mm()) } else { r.mm() };
                block.words.push(format!("CR={text}"));
                self.feed_word(item, feed, block);
                return true;
            }
        }
        let half = Length(div_round(dx.0 as i128, 2 * grid.0 as i128) as i64 * grid.0);
        if half + half != dx {
            self.inexact
                .note(item.span, "I (as a diameter)", dx, half + half, grid + grid);
        }
        let k = self.three(item, "K", cz - sz);
        block.words.push(format!("I{}", half.mm()));
        block.words.push(format!("K{k}"));
        self.feed_word(item, feed, block);
        true
    }

    /// One pass: `G33 [X] Z K SF=`.
    fn thread_pass(&mut self, item: &Item, pass: &ThreadPass, block: &mut Block) -> bool {
        let end = pass.end_position(self.w.pos);
        let Ok(segments) = lower::pass_segments(self.w.pos, pass) else {
            self.diag(
                codes::SINW_NO_EQUIVALENT,
                item,
                "this thread pass needs its start point, which is not known".into(),
                "move to the start of the thread with X and Z first",
            );
            return false;
        };
        // Chains, entries, runouts and steep moves are refused by the table; the position
        // goes on, so that what follows reads right.
        let SyncStart::Index(angle) = pass.start else {
            self.w.pos = end;
            return false;
        };
        if segments.len() != 1
            || self.after_thread
            || segments.iter().any(lower::SyncSegment::is_steep)
        {
            self.w.pos = end;
            return false;
        }
        if self.surface_speed {
            self.diag(
                codes::SINW_NO_EQUIVALENT,
                item,
                "a thread cut under constant surface speed (G96): ncthread writes SINUMERIK threads under G97, at a speed in rpm".into(),
                "set the spindle speed in rpm (G97 S…) before the thread in the source",
            );
            return false;
        }
        let seg = &segments[0];
        if let (Some(a), Some(b)) = (seg.from.known(), seg.to.known())
            && near_45((b.0 - a.0).abs(), (b.1 - a.1).abs())
        {
            self.diag(
                codes::SINW_NO_EQUIVALENT,
                item,
                "a taper pass within 1° of 45°: the control takes K along Z only while Z travels farther than X (as a radius), a comparison the rounding of the written values can turn".into(),
                "cut the taper at an angle farther from 45° in the source, or convert it by hand",
            );
            return false;
        }
        let travel = match (seg.from.z, seg.to.z) {
            (Some(a), Some(b)) => (b - a).abs(),
            _ => Length::ZERO,
        };
        let Some(lead) = self.four(item, "lead K", pass.lead, travel) else {
            return false;
        };
        self.motion_block(block, "G33");
        let mut to = seg.to;
        if seg.from.x == to.x {
            to.x = None;
        }
        let words = self.axes(item, to);
        block.words.extend(words);
        block.words.push(format!("K{}", lead.mm()));
        let angle = Angle(
            write::start_on_grid(seg.from.z, seg.to.z, pass.lead, angle)
                .0
                .rem_euclid(360_000),
        );
        block.words.push(format!("SF={}", write::angle_text(angle)));
        self.after_thread = true;
        true
    }

    fn thread_cycle(&mut self, item: &Item, cycle: &ThreadCycle) {
        let Some(steps) = self.w.cycle_steps(cycle, item.span, "D") else {
            return;
        };
        for step in steps {
            match step {
                write::CycleStep::Comment(comment) => self.write(Block {
                    comment: Some(comment),
                    own_comment: true,
                    ..Block::default()
                }),
                write::CycleStep::Move(moved) => {
                    let mut block = Block::default();
                    if self.kind(&moved, &mut block) {
                        self.w.pos = moved.kind.end_position(self.w.pos);
                    }
                    self.flush(&mut block);
                }
            }
        }
    }
}

/// Whether a move of `dx` on the diameter and `dz` along Z is within 1° of 45° (the radial
/// travel at least tan 44° of the Z travel).
fn near_45(dx: Length, dz: Length) -> bool {
    let (radial, along) = (dx.to_mm_f64() / 2.0, dz.to_mm_f64());
    along > 0.0 && radial >= along * 44f64.to_radians().tan()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_the_controls_and_angles_are_short() {
        let program = Program {
            items: Vec::new(),
            dialect: crate::dialect::iso::ID,
            library: Vec::new(),
            number: None,
            name: None,
            inch: false,
        };
        let name = |file: &str| program_name(&program, &SourceFile::new(file, String::new()));
        assert_eq!(name("corpus/czech/seed-g33.nc"), "SEED_G33");
        assert_eq!(name("12-shaft.ngc"), "NC_12_SHAFT");
        assert_eq!(name("Řez závitu.nc"), "REZ_ZAVITU");
        assert_eq!(write::angle_text(Angle(0)), "0");
        assert_eq!(write::angle_text(Angle(120_500)), "120.5");
        assert_eq!(write::angle_text(Angle(90_000)), "90");
        let mm = |v: i64| Length::from_mm(v);
        assert!(near_45(mm(20), mm(10)));
        assert!(near_45(mm(19_400), mm(10_000)));
        assert!(!near_45(mm(19_300), mm(10_000)));
        assert!(!near_45(mm(2), mm(30)));
        // A start 0.0005 mm off the grid, written 0.0005 mm farther from the end: the tool
        // meets the helix 0.18° of a turn later at lead 1, so SF starts 0.18° earlier.
        let lead = Lead::from_length(Length::from_mm(1));
        let start = write::start_on_grid(Some(Length(500_050)), Some(mm(-10)), lead, Angle(0));
        assert_eq!(start, Angle(-180));
        assert_eq!(
            write::start_on_grid(Some(mm(5)), Some(mm(-10)), lead, Angle(90_000)),
            Angle(90_000)
        );
    }
}

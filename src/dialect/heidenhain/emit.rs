//! IR → HEIDENHAIN DIN (MANUALplus 620 / CNC PILOT 640; heidenhain.md "Writing").
//!
//! The frame: `%<NAME>.nc`, a `[…]` comment saying where the program came from, the section
//! `BEARBEITUNG` (`MACHINING`), the blocks `N10, N20, …`, the source's end (`M30`) where it
//! has one, and `ENDE` (`END`). The program head and the turret table are left out: the
//! vendor requires only the machining and end sections, and a program without a turret table
//! takes the machine's tool list (ARCHITECTURE.md). Lengths are millimetres: X a diameter,
//! Z, and an arc's absolute centre (`I` a radius value, `K`) with 3 decimals; F 4. `G94`/`G95`
//! stand with the first F after every change (F is their parameter). `G96 S` with its limit
//! `G26 S` in a block before it (both words are S). Comments `[…]` in ASCII.
//!
//! A thread pass is one `G33 X Z F<lead> B<lead> P<lead> C<angle> H0` block: the run-in B is
//! one lead, so that the spindle is at C one turn after the block's start, where it was at the
//! start: `C` is the IR's start angle (heidenhain.md's rule `C = φ₀ + 360°·B/F`). What the
//! unpublished points (C's sense, B's measure on a taper) change is refused unless the profile
//! declares them; chains, entries, runouts and steep passes are refused by the table.

use std::fmt::Write as _;

use super::codes;
use super::profile::{BAlong, CSense, HeidenhainArcDirection, HeidenhainProfile, SectionKeywords};
use crate::diag::{Code, Diagnostic};
use crate::dialect::write::{self, Writer};
use crate::dialect::{Inexact, Renumber};
use crate::fixed::{Angle, Decimal, Lead, Length, div_round};
use crate::ir::{
    Coolant, FeedMode, Item, ItemKind, Pos, Program, SpindleDirection, SpindleMode, SyncStart,
    ThreadCycle, ThreadPass,
};
use crate::lower;
use crate::source::{SourceFile, Span};

/// How the header comment of a program ncthread wrote ends.
pub(crate) const HEADER_END: &str = ", converted by ncthread";

/// The highest block number (`N` and up to five digits).
const LAST_NUMBER: u32 = 99_999;

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
    profile: &'a HeidenhainProfile,
    number: u32,
    step: u32,
    motion: Option<&'static str>,
    f: Option<Length>,
    feed_mode: FeedMode,
    /// G94/G95 written since the last change of mode (it stands with the next F).
    mode_said: bool,
    /// G96 in force.
    surface_speed: bool,
    /// G96 or G97 written (the reset state is not published: the first S says G97).
    speed_mode_said: bool,
    /// The G26 limit in force.
    limit: Option<i64>,
    /// The last S written, and a G96/G97 of this block that still needs its S.
    speed: Option<u32>,
    speed_word: Option<(Item, usize)>,
    /// The last motion was a G33 (a G33 now would continue it: refused by the table).
    after_thread: bool,
    at: Span,
    comments: write::AsciiComments,
    inexact: Inexact,
    round: bool,
}

/// The program's name for `%<NAME>.nc`: the source's own (a HEIDENHAIN program's), else the
/// file's stem; upper-case letters, digits and `_`, up to 40, a letter or digit first.
fn program_name(program: &Program, src: &SourceFile) -> String {
    let stem = std::path::Path::new(&src.name)
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("");
    let raw = match &program.name {
        Some(name) if program.dialect == super::ID => name.as_str(),
        _ => stem,
    };
    let name: String = deunicode::deunicode(raw)
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_uppercase()
            } else {
                '_'
            }
        })
        .collect();
    let name = name.trim_matches('_');
    let mut name: String = name.chars().take(40).collect();
    if name.is_empty() {
        name = "NC".into();
    }
    name.trim_end_matches('_').to_string()
}

/// The HEIDENHAIN writer taking a program's items one at a time (a conversion's streaming
/// read), or a whole program ([`Dialect::write`](crate::dialect::Dialect::write)).
pub(crate) struct Items<'a> {
    e: Emitter<'a>,
    /// The program's dialect.
    from: crate::ir::DialectId,
    /// Before the first item that is not a `%` line: it may be the header comment.
    header: bool,
    /// Block by block: a speed mode with its spindle start.
    groups: write::Grouper,
}

impl<'a> Items<'a> {
    /// For `program`'s name and dialect (its items are not needed).
    pub fn new(
        program: &Program,
        src: &'a SourceFile,
        profile: &'a HeidenhainProfile,
        renumber: Renumber,
        round: bool,
    ) -> Self {
        let keep = program.dialect == super::ID;
        let mut e = Emitter {
            w: Writer::new(src),
            profile,
            number: renumber.start,
            step: renumber.step.max(1),
            motion: None,
            f: None,
            feed_mode: FeedMode::PerRev,
            mode_said: false,
            surface_speed: false,
            speed_mode_said: false,
            limit: None,
            speed: None,
            speed_word: None,
            after_thread: false,
            at: Span::default(),
            comments: write::AsciiComments::default(),
            inexact: Inexact::default(),
            round,
        };
        let _ = writeln!(e.w.out, "%{}.nc", program_name(program, src));
        Items {
            e,
            from: program.dialect,
            header: true,
            groups: write::Grouper::new(keep),
        }
    }

    /// The section keywords: machining and end.
    fn keywords(&self) -> (&'static str, &'static str) {
        match self.e.profile.keywords {
            SectionKeywords::German => ("BEARBEITUNG", "ENDE"),
            SectionKeywords::English => ("MACHINING", "END"),
        }
    }

    /// The program's start, once its first item that is not a `%` line is known (`None`:
    /// the program has none): the header comment and the machining section. Whether that
    /// item was the header comment.
    fn begin(&mut self, first: Option<&Item>) -> bool {
        let header = self.e.header_comment(self.from, first);
        let (machining, _) = self.keywords();
        let _ = writeln!(self.e.w.out, "{machining}");
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
        let (_, end) = self.keywords();
        let mut e = self.e;
        let _ = writeln!(e.w.out, "{end}");
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
            && bracket_text(c).0.ends_with(HEADER_END)
        {
            let _ = writeln!(self.w.out, "[{}]", bracket_text(c).0);
            return true;
        }
        let src = self.w.src;
        let file = std::path::Path::new(&src.name)
            .file_name()
            .map_or(src.name.as_str(), |n| n.to_str().unwrap_or(&src.name));
        let _ = writeln!(
            self.w.out,
            "[{}, dialect {from}, in mm{HEADER_END}]",
            bracket_text(file).0,
        );
        false
    }

    fn closing_diagnostics(&mut self) {
        let src = self.w.src;
        let summary = write::grid_diagnostic(
            &mut self.inexact,
            src,
            self.round,
            "HEIDENHAIN",
            (codes::HEIW_ROUNDED, codes::HEIW_PRECISION),
            "a thread's start rounded onto the grid keeps its helix: its C moves with it",
        );
        self.w.diags.extend(summary);
        let ascii = self
            .comments
            .diagnostic(src, codes::HEIW_TRANSLITERATED, "HEIDENHAIN");
        self.w.diags.extend(ascii);
    }

    fn diag(&mut self, code: Code, item: &Item, message: String, help: &str) {
        self.w.error(code, item.span, message, help);
    }

    fn write(&mut self, block: Block) {
        let comment = block
            .comment
            .map(|c| {
                if block.own_comment {
                    bracket_text(&c).0
                } else {
                    let ascii = self.comments.text(self.at, &c);
                    ascii.replace('[', "(").replace(']', ")")
                }
            })
            .filter(|c| !c.is_empty());
        let mut line = String::new();
        if !block.words.is_empty() {
            if self.number > LAST_NUMBER {
                self.w.error(
                    codes::HEIW_NO_EQUIVALENT,
                    self.at,
                    format!("block number N{} is past N{LAST_NUMBER}: a HEIDENHAIN block number has up to five digits", self.number),
                    "number the blocks with a smaller start or step (--renumber)",
                );
            }
            let _ = write!(line, "N{} {}", self.number, block.words.join(" "));
            self.number = self.number.saturating_add(self.step);
        }
        if let Some(c) = comment {
            if !line.is_empty() {
                line.push(' ');
            }
            let _ = write!(line, "[{c}]");
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
        // A G96 or G97 says its speed (S is its parameter).
        if let Some((item, at)) = self.speed_word.take() {
            match self.speed {
                Some(s) => block.words.insert(at.min(block.words.len()), format!("S{s}")),
                None => self.diag(
                    codes::HEIW_NO_EQUIVALENT,
                    &item,
                    "a change of spindle speed mode (G96/G97) before any speed is set: the HEIDENHAIN block says the speed with it".into(),
                    "give the speed (S) in the source before or with G96/G97",
                ),
            }
        }
        self.flush(&mut block);
    }

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
        let code = codes::HEIW_PRECISION;
        write::lead_on_grid(
            &mut self.w,
            &mut self.inexact,
            code,
            item.span,
            what,
            (lead, travel),
        )
    }

    /// `F`, with `G94`/`G95` before it after a change of mode (F is their parameter).
    fn feed_word(&mut self, item: &Item, feed: Length, block: &mut Block) {
        if self.f == Some(feed) && self.mode_said {
            return;
        }
        let Some(written) = self.four(item, "F", Lead::from_length(feed), Length::ZERO) else {
            return;
        };
        if !self.mode_said {
            let g = match self.feed_mode {
                FeedMode::PerRev => "G95",
                FeedMode::PerMin => "G94",
            };
            // First in the block, before the motion it is the feed of.
            block.words.insert(0, g.into());
            self.mode_said = true;
        }
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
            ItemKind::ModelCycle(_) | ItemKind::Compensation(_) => {}
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
            ItemKind::SpindleStop => block.words.push("M5".into()),
            ItemKind::SpindleMode(mode) => return self.spindle_mode(item, mode, block),
            ItemKind::Tool { number, offset } => return self.tool(item, *number, *offset, block),
            ItemKind::FeedMode(mode) if *mode != self.feed_mode => {
                self.feed_mode = *mode;
                self.mode_said = false;
            }
            // M30 ends the program and stops the spindle and the coolant, as M2 does.
            ItemKind::ProgramEnd(_) => block.words.push("M30".into()),
            ItemKind::Coolant(Coolant::Flood) => block.words.push("M8".into()),
            ItemKind::Coolant(Coolant::Off) => block.words.push("M9".into()),
            // Refused by the table.
            ItemKind::Coolant(Coolant::Mist) => {}
            ItemKind::Stop { optional } => {
                block.words.push(if *optional { "M1" } else { "M0" }.into())
            }
            ItemKind::Dwell { seconds } => return self.dwell(item, *seconds, block),
            // G54 is where every program starts (the table refuses the others).
            ItemKind::WorkOffset(_) => {}
            // A zero feed no move runs at (each feed move carries its own feed).
            ItemKind::FeedRate(feed) if *feed == Length::ZERO => self.as_comment(item, block, "F0"),
            ItemKind::FeedRate(feed) if self.f != Some(*feed) => {
                self.feed_word(item, *feed, block);
            }
            _ => {}
        }
        true
    }

    /// `T<pocket>`: the turret pocket's tool with its own data.
    fn tool(
        &mut self,
        item: &Item,
        number: Option<u32>,
        offset: Option<u32>,
        block: &mut Block,
    ) -> bool {
        match (number, offset) {
            (Some(t), None) => block.words.push(format!("T{t}")),
            (Some(t), Some(d)) if d == t => block.words.push(format!("T{t}")),
            _ => {
                self.diag(
                    codes::HEIW_NO_EQUIVALENT,
                    item,
                    format!(
                        "tool {} with the offset {}: a HEIDENHAIN T calls the turret pocket's tool with its own data, and no other offset",
                        number.map_or("(none)".into(), |n| n.to_string()),
                        offset.map_or("(none)".into(), |n| n.to_string())
                    ),
                    "call each tool with its own offset in the source",
                );
                return false;
            }
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
                codes::HEIW_COMMENT,
                format!("`{text}` has no HEIDENHAIN equivalent; it is written as a comment"),
            )
            .at(self.w.src, item.span)
            .help("check the HEIDENHAIN program by hand where this matters"),
        );
    }

    /// The spindle's speed and direction words; `false` when refused.
    fn spindle(
        &mut self,
        item: &Item,
        speed: Option<u32>,
        direction: Option<SpindleDirection>,
        block: &mut Block,
    ) -> bool {
        // Whether G26 limits G97 too is not published: a speed above it is refused.
        if let (Some(s), Some(l)) = (speed, self.limit)
            && !self.surface_speed
            && i64::from(s) > l
        {
            self.diag(
                codes::HEIW_NO_EQUIVALENT,
                item,
                format!("S{s} rpm above the speed limit G26 S{l} in force: the maximum speed limits a constant speed (G97) too (MANUALplus 4110 manual), where the source's limit was its surface speed's only"),
                "lower the speed to the limit in the source, or raise the surface speed's limit",
            );
            return false;
        }
        if let Some(s) = speed {
            if !self.speed_mode_said && self.speed_word.is_none() {
                block.words.push("G97".into());
            }
            self.speed_mode_said = true;
            block.words.push(format!("S{s}"));
            self.speed = Some(s);
            self.speed_word = None;
        }
        if let Some(d) = direction {
            block.words.push(d.code().into());
        }
        true
    }

    /// `G97 S`, or `G26 S<limit>` in a block before `G96 S` (both words are S).
    fn spindle_mode(&mut self, item: &Item, mode: &SpindleMode, block: &mut Block) -> bool {
        match mode {
            // Before any speed, the first S says G97 (a program's header `G97` has no S yet).
            SpindleMode::Rpm if self.speed.is_none() && !self.surface_speed => {
                self.speed_mode_said = false;
            }
            SpindleMode::Rpm => {
                self.speed_mode_said = true;
                if !block.words.iter().any(|w| w == "G97") {
                    block.words.push("G97".into());
                    self.speed_word = Some((item.clone(), block.words.len()));
                }
                self.surface_speed = false;
            }
            SpindleMode::SurfaceSpeed { feet: true, .. } => {
                self.diag(
                    codes::HEIW_NO_EQUIVALENT,
                    item,
                    "a surface speed in feet per minute (G96 under G20): the HEIDENHAIN program is written in millimetres, where G96's S is m/min".into(),
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
                            codes::HEIW_PRECISION,
                            item,
                            format!("the surface speed's limit of {} rpm is not a whole number of rpm, which G26 S takes", limit.map(|d| d.to_string()).unwrap_or_default()),
                            "write the limit in whole rpm in the source",
                        );
                        return false;
                    }
                };
                if limit.is_none() && self.limit.is_some() {
                    self.diag(
                        codes::HEIW_NO_EQUIVALENT,
                        item,
                        "a surface speed without a speed limit after one with a limit: G26 stays in force, and the program cannot lift it".into(),
                        "give this surface speed a limit in the source (LinuxCNC's G96 … D, FANUC's G50 S)",
                    );
                    return false;
                }
                if let Some(n) = limit.filter(|n| self.limit != Some(*n)) {
                    self.flush(block);
                    self.write(Block {
                        words: vec!["G26".into(), format!("S{n}")],
                        ..Block::default()
                    });
                    self.limit = Some(n);
                }
                block.words.push("G96".into());
                self.surface_speed = true;
                self.speed_mode_said = true;
                self.speed_word = Some((item.clone(), block.words.len()));
            }
        }
        true
    }

    /// `G4 F<s>` in a block of its own (the vendor's range: 0 < F ≤ 999 s).
    fn dwell(&mut self, item: &Item, seconds: Decimal, block: &mut Block) -> bool {
        let ms = match seconds.to_scaled(3) {
            Ok(ms) if ms <= 999_000 => ms,
            Ok(_) => {
                self.diag(
                    codes::HEIW_NO_EQUIVALENT,
                    item,
                    format!("the dwell of {seconds} s is longer than G4 F takes (999 s)"),
                    "split the dwell in the source",
                );
                return false;
            }
            Err(_) => {
                self.diag(
                    codes::HEIW_PRECISION,
                    item,
                    format!("the dwell of {seconds} s needs more than the 0.001 s G4 F takes"),
                    "write the dwell in whole milliseconds in the source",
                );
                return false;
            }
        };
        if ms == 0 {
            return true;
        }
        self.flush(block);
        // Whether G4's F is the feed's F too is not published: the next feed says its F.
        self.f = None;
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

    /// `G12`/`G13 X Z I K F`: the absolute centre, I a radius value; the direction as the
    /// profile declares it (the table refuses arcs without it).
    fn arc(
        &mut self,
        item: &Item,
        to: Pos,
        centre: Pos,
        clockwise: bool,
        feed: Length,
        block: &mut Block,
    ) -> bool {
        let Some(direction) = self.profile.arc_direction else {
            return false;
        };
        let (Some((cx, cz)), Some((ex, ez))) = (centre.known(), to.known()) else {
            self.diag(
                codes::HEIW_NO_EQUIVALENT,
                item,
                "an arc whose centre is not known".into(),
                "move to an absolute X and Z before the arc",
            );
            return false;
        };
        if self.w.pos.known() == Some((ex, ez)) {
            self.diag(
                codes::HEIW_NO_EQUIVALENT,
                item,
                "a full circle: whether a G12/G13 that ends where it starts cuts a whole turn is not published".into(),
                "cut the circle as two half circles in the source",
            );
            return false;
        }
        let g12 = clockwise == (direction == HeidenhainArcDirection::Iso);
        self.motion_block(block, if g12 { "G12" } else { "G13" });
        let words = self.axes(item, Pos::new(ex, ez));
        block.words.extend(words);
        let grid = Length::from_steps(10);
        let half = Length(div_round(cx.0 as i128, 2 * grid.0 as i128) as i64 * grid.0);
        if half + half != cx {
            self.inexact
                .note(item.span, "I (as a diameter)", cx, half + half, grid + grid);
        }
        let k = self.three(item, "K", cz);
        block.words.push(format!("I{}", half.mm()));
        block.words.push(format!("K{k}"));
        self.feed_word(item, feed, block);
        true
    }

    /// One pass: `G33 X Z F B P C H0`.
    fn thread_pass(&mut self, item: &Item, pass: &ThreadPass, block: &mut Block) -> bool {
        let end = pass.end_position(self.w.pos);
        let Ok(segments) = lower::pass_segments(self.w.pos, pass) else {
            self.diag(
                codes::HEIW_NO_EQUIVALENT,
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
        let seg = &segments[0];
        let Some(travel) = self.pass_travel(item, pass, seg) else {
            return false;
        };
        // A taper without B's measure is refused by the table.
        if seg.from.x != seg.to.x && self.profile.b_along != Some(BAlong::Z) {
            return false;
        }
        let Some(lead) = self.four(item, "lead F", pass.lead, travel) else {
            return false;
        };
        let phase = Angle(
            write::start_on_grid(seg.from.z, seg.to.z, pass.lead, angle)
                .0
                .rem_euclid(360_000),
        );
        let Some(c) = self.c_word(item, phase) else {
            return false;
        };
        self.motion_block(block, "G33");
        let words = self.axes(item, seg.to);
        block.words.extend(words);
        let b = lead.mm();
        block.words.extend([
            format!("F{b}"),
            format!("B{b}"),
            format!("P{b}"),
            format!("C{}", write::angle_text(c)),
            "H0".into(),
        ]);
        self.after_thread = true;
        // Whether G33's F is the feed's F (and leaves its G94/G95) is not published: the
        // next feed says its mode and its F.
        self.f = None;
        self.mode_said = false;
        true
    }

    /// The pass's travel along Z, where it can be written as one G33: not under G96, from a
    /// known Z, two leads long (`None`: a diagnostic said why).
    fn pass_travel(
        &mut self,
        item: &Item,
        pass: &ThreadPass,
        seg: &lower::SyncSegment,
    ) -> Option<Length> {
        if self.surface_speed {
            self.diag(
                codes::HEIW_NO_EQUIVALENT,
                item,
                "a thread cut under constant surface speed (G96): ncthread writes HEIDENHAIN threads under G97, at a speed in rpm".into(),
                "set the spindle speed in rpm (G97 S…) before the thread in the source",
            );
            return None;
        }
        // X is modal (as G1's): a pass along Z from an X not known keeps it.
        let (Some(z0), Some(z1)) = (seg.from.z, seg.to.z) else {
            self.diag(
                codes::HEIW_NO_EQUIVALENT,
                item,
                "a thread pass from a Z that is not known".into(),
                "move to an absolute Z before the thread",
            );
            return None;
        };
        let travel = (z1 - z0).abs();
        if travel < pass.lead.length_times(2, 1) {
            self.diag(
                codes::HEIW_NO_EQUIVALENT,
                item,
                format!("a thread pass of {} mm along Z, shorter than two leads ({} mm): ncthread writes the run-in B and the run-out P one lead each", travel.mm(), pass.lead.mm()),
                "lengthen the pass in the source, or convert it by hand",
            );
            return None;
        }
        Some(travel)
    }

    /// `C` for a pass whose spindle angle at the start (and one lead later) is `phase`, as
    /// the profile's `c_sense` counts it; without it only 0° and 180°, which read the same
    /// both ways.
    fn c_word(&mut self, item: &Item, phase: Angle) -> Option<Angle> {
        match self.profile.c_sense {
            Some(CSense::Spindle) => Some(phase),
            Some(CSense::Against) => Some(Angle((360_000 - phase.0).rem_euclid(360_000))),
            None if phase.0 % 180_000 == 0 => Some(phase),
            None => {
                self.diag(
                    codes::HEIW_PROFILE,
                    item,
                    format!("a thread pass that starts at {}° of the spindle's turn (a multi-start thread, or a flank infeed): whether G33's start angle C counts with the spindle or against it is not published", write::angle_text(phase)),
                    "declare `c_sense = \"spindle\"` or `\"against\"` in the profile's [heidenhain] section, as a test cut on the machine shows",
                );
                None
            }
        }
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

/// A comment's text for `[…]`: ASCII ([`write::ascii_comment`]) with `[`/`]` as `(`/`)`, and
/// whether anything changed.
fn bracket_text(text: &str) -> (String, bool) {
    let (ascii, changed) = write::ascii_comment(text);
    (ascii.replace('[', "(").replace(']', ")"), changed)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_the_controls() {
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
        assert_eq!(name("12-shaft.ngc"), "12_SHAFT");
        assert_eq!(name("Řez závitu.nc"), "REZ_ZAVITU");
        assert_eq!(name("__.nc"), "NC");
        assert_eq!(bracket_text("a [b] c").0, "a (b) c");
    }
}

//! HEIDENHAIN DIN → IR: what the writer writes (so that `verify` proves a conversion), plus
//! `Xi`/`Zi` increments, `G2`/`G3` with the incremental centre, `R` arcs, `G40`, the
//! `N 13` of the manuals' examples, `G31` with its contour up to `G80` under the profile's
//! declared model (`front/g31.rs`); everything else is refused by name (heidenhain.md
//! "Reading").
//!
//! The sections: `BEARBEITUNG`/`MACHINING` (and blocks before any section) are read;
//! `ENDE`/`END` ends the program; the sections that describe (the program head, the turret
//! table, the blank and the finished part, the auxiliary contours) move nothing and are
//! passed over with a warning; subprograms are refused.
//!
//! A block runs in one order **\[decided\]**, as the other readers' blocks do: the tool, the
//! feed and speed modes, the spindle, coolant on, the motion or dwell, then coolant off, M5,
//! stops and the end. What depends on a point the vendor leaves to the machine is refused
//! unless the profile declares it: an arc's direction, G33's start angle C in any sense but
//! 0°/180°, its run-in B on a taper, a feed before G94 or G95, a G33 without B.

use std::ops::Range;

use super::codes;
use super::profile::{BAlong, CSense, HeidenhainArcDirection, HeidenhainProfile};
use super::syntax::{self, Block, Value, Word};
use crate::diag::Code;
use crate::dialect::machine::Switches;
use crate::dialect::read::{Keep, Reader};
use crate::fixed::{Angle, Decimal, Lead, Length};
use crate::ir::{
    Coolant, EndCode, FeedMode, ItemKind, Pos, Program, SpindleDirection, SpindleMode, SyncStart,
    ThreadPass,
};
use crate::source::{Line, SourceFile, Span};
use names::{KNOWN_G, LETTERS, refused_g, refused_letter};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Motion {
    Rapid,
    Feed,
    /// G2/G3 (`absolute`: G12/G13), clockwise as the vendor draws it.
    Arc {
        g2: bool,
        absolute: bool,
    },
    Thread,
}

/// Where in the program a line stands.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Section {
    /// Before any section line, or in the machining section: blocks are read.
    Machining,
    /// A section that describes (its keyword): passed over.
    Describing(&'static str),
    /// After ENDE/END.
    Ended,
}

struct FrontEnd<'a> {
    r: Reader<'a>,
    profile: &'a HeidenhainProfile,
    section: Section,
    /// G95 or G94; `None` until the program says.
    per_rev: Option<bool>,
    motion: Option<Motion>,
    f: Option<Length>,
    /// G96 is in force.
    surface: bool,
    /// The G26 limit in force.
    limit: Option<u32>,
    /// G96 or G97 said (the reset state is not published), and the last S under G97.
    speed_mode_said: bool,
    rpm: Option<u32>,
    /// The last motion was a G33.
    after_thread: bool,
    /// M30 ended the program, and no ENDE/END has followed yet.
    m30: bool,
    /// The unstated machine settings already reported (one error each is enough).
    reported: Vec<&'static str>,
    /// A G31 call whose contour (up to G80) is being read.
    g31: Option<g31::PendingG31>,
}

/// Reads a HEIDENHAIN DIN program.
pub(crate) fn read(
    src: &SourceFile,
    profile: &HeidenhainProfile,
    keep: Keep,
) -> (Program, Vec<crate::diag::Diagnostic>) {
    let mut fe = FrontEnd {
        r: Reader::new(src, super::ID, keep),
        profile,
        section: Section::Machining,
        per_rev: None,
        motion: None,
        f: None,
        surface: false,
        limit: None,
        speed_mode_said: false,
        rpm: None,
        after_thread: false,
        m30: false,
        reported: Vec::new(),
        g31: None,
    };
    let mut first = true;
    for line in src.lines() {
        fe.r.line_read();
        if line.is_blank() {
            continue;
        }
        let at_start = std::mem::take(&mut first);
        fe.line(line, at_start);
    }
    fe.g31_unended();
    fe.r.finish()
}

impl FrontEnd<'_> {
    fn span(&self, line: Line<'_>, range: Range<usize>) -> Span {
        self.r.span(line, range)
    }

    fn error(
        &mut self,
        code: Code,
        line: Line<'_>,
        range: Range<usize>,
        message: impl Into<String>,
        help: impl Into<String>,
    ) {
        let span = self.span(line, range);
        self.r.error(code, span, message, help);
    }

    /// A block with `/` (block skip) is refused, `place` naming what it stands in (` in
    /// G31's contour`): whether it runs is the operator's switch. Whether it was.
    fn block_skip(&mut self, line: Line<'_>, block: &Block, place: &str) -> bool {
        let Some(range) = block.block_delete.clone() else {
            return false;
        };
        self.error(
            codes::HEIR_UNSUPPORTED,
            line,
            range,
            format!("`/` (block skip){place}: whether the block runs is the operator's switch, which the program does not state"),
            "remove the `/`, or the block",
        );
        true
    }

    /// An error at word `w`: the word as written, then `rest` (`: …`, ` is …`).
    fn word_error(
        &mut self,
        code: Code,
        line: Line<'_>,
        w: &Word,
        rest: impl std::fmt::Display,
        help: impl Into<String>,
    ) {
        let message = format!("`{}`{rest}", &line.text[w.range.clone()]);
        self.error(code, line, w.range.clone(), message, help);
    }

    /// A point the program leaves to the machine, reported at its first use only.
    fn unknown(
        &mut self,
        what: &'static str,
        line: Line<'_>,
        range: Range<usize>,
        message: &str,
        help: &str,
    ) {
        if !self.reported.contains(&what) {
            self.reported.push(what);
            self.error(codes::HEIR_PROFILE, line, range, message, help);
        }
    }

    fn line(&mut self, line: Line<'_>, at_start: bool) {
        let whole = 0..line.text.trim_end().len();
        if super::is_name_line(line.text) {
            if at_start {
                let name = line.text.trim()[1..]
                    .rsplit_once('.')
                    .map_or("", |(n, _)| n);
                self.r.name = Some(name.to_ascii_uppercase());
            } else {
                self.error(
                    codes::HEIR_SYNTAX,
                    line,
                    whole,
                    "a program's name (`%….nc`) after its first line",
                    "a file holds one program: its name stands on the first line",
                );
            }
            return;
        }
        if let Some(section) = super::section_of(line.text) {
            self.g31_unended();
            self.section_line(line, section, whole);
            return;
        }
        if let Section::Describing(section) = self.section {
            // The program head's unit: ncthread reads and writes millimetres only.
            let up = line.text.to_ascii_uppercase();
            if matches!(section, "PROGRAMMKOPF" | "PROGRAM HEAD")
                && (up.contains("ZOLL") || up.contains("INCH"))
            {
                self.error(
                    codes::HEIR_UNSUPPORTED,
                    line,
                    whole,
                    "a program in inches (its head's unit): ncthread reads HEIDENHAIN programs in millimetres",
                    "convert the program on the control to a metric one, or convert it by hand",
                );
            }
            return;
        }
        let block = match syntax::parse_line(line.text) {
            Ok(block) => block,
            Err(e) => {
                self.r
                    .syntax_error(codes::HEIR_SYNTAX, line, e.offset, e.message, e.help);
                return;
            }
        };
        if self.section == Section::Ended {
            self.after_end(line, &block, whole);
            return;
        }
        let first = self.r.items.len();
        let span = self.span(line, block.code_range.clone());
        let g31 = block
            .words
            .iter()
            .any(|w| w.name == "G" && w.number().and_then(|d| d.to_whole().ok()) == Some(31));
        if g31 {
            // A call before the contour of the last one was ended.
            self.g31_unended();
        }
        if self.g31.is_some() {
            self.g31_contour(line, &block);
            if self.r.items.len() == first {
                self.r
                    .stamp_block(first, block.number, block.comment.clone(), span, false);
            } else if let Some(c) = block.comment.clone() {
                // G80's comment, after the cycle it ends.
                self.r.push(ItemKind::Comment(c), span, None);
            }
            return;
        }
        if g31 {
            self.g31_call(line, &block, span);
            if self.g31.is_none() {
                self.r
                    .stamp_block(first, block.number, block.comment.clone(), span, false);
            }
            return;
        }
        if !self.block_skip(line, &block, "") && !block.words.is_empty() {
            self.block(line, &block, span);
        }
        self.r
            .stamp_block(first, block.number, block.comment.clone(), span, false);
        // M30 ends the program: the blocks after it are not run (ENDE closes it).
        if self.r.ends_program(first) {
            self.section = Section::Ended;
            self.m30 = true;
        }
    }

    /// A line after the program's end: a comment is kept, a block warned of.
    fn after_end(&mut self, line: Line<'_>, block: &Block, whole: Range<usize>) {
        if block.words.is_empty() {
            if let Some(c) = block.comment.clone() {
                let span = self.span(line, whole);
                self.r.push(ItemKind::Comment(c), span, block.number);
            }
        } else {
            let span = self.span(line, block.code_range.clone());
            self.r.after_end(
                codes::HEIR_AFTER_END,
                span,
                "blocks after the program's end (M30, ENDE, END) are not run and not converted",
                "remove them, or move the end to after them",
            );
        }
    }

    fn section_line(&mut self, line: Line<'_>, section: &'static str, whole: Range<usize>) {
        if self.section == Section::Ended {
            // The end section after M30 closes the program as it should.
            if std::mem::take(&mut self.m30) && matches!(section, "ENDE" | "END") {
                return;
            }
            let span = self.span(line, whole);
            self.r.after_end(
                codes::HEIR_AFTER_END,
                span,
                "sections after the program's end (ENDE, END) are not run and not converted",
                "remove them, or move the end to after them",
            );
            return;
        }
        self.section = match section {
            "BEARBEITUNG" | "MACHINING" => Section::Machining,
            "ENDE" | "END" => Section::Ended,
            "UNTERPROGRAMM" | "SUBPROGRAM" | "RETURN" => {
                self.error(
                    codes::HEIR_UNSUPPORTED,
                    line,
                    whole,
                    format!("`{section}`: subprograms are not read"),
                    "write the subprogram's blocks into the machining section",
                );
                Section::Describing(section)
            }
            _ => {
                let span = self.span(line, whole);
                self.r.diags.push(
                    crate::diag::Diagnostic::new(
                        codes::HEIR_SECTION,
                        format!("the section `{section}` describes the program, the tools or the part and moves nothing: its lines are passed over"),
                    )
                    .at(self.r.src, span)
                    .help("the machining section's blocks are converted; check the tool pockets and the unit on the machine"),
                );
                Section::Describing(section)
            }
        };
    }
}

/// The words of one block, sorted by what they do.
#[derive(Default)]
struct Words<'b> {
    g: Vec<(u32, &'b Word)>,
    m: Vec<(u32, &'b Word)>,
    letters: Vec<&'b Word>,
}

impl<'b> Words<'b> {
    fn get(&self, name: &str) -> Option<&'b Word> {
        self.letters.iter().copied().find(|w| w.name == name)
    }
}

impl FrontEnd<'_> {
    /// `w` after `was` (the same address) in one block.
    fn repeated(&mut self, line: Line<'_>, w: &Word, was: &Word) {
        let (text, was) = (&line.text[w.range.clone()], &line.text[was.range.clone()]);
        self.error(
            codes::HEIR_CONFLICT,
            line,
            w.range.clone(),
            format!("`{text}` after `{was}` in the same block"),
            "give each address once in a block",
        );
    }

    /// Sorts the block's words; `None` when one is refused (reported).
    fn sort<'b>(&mut self, line: Line<'_>, block: &'b Block) -> Option<Words<'b>> {
        let mut words = Words::default();
        let mut ok = true;
        for w in &block.words {
            let text = &line.text[w.range.clone()];
            if w.value == Value::Unknown {
                self.error(
                    codes::HEIR_UNSUPPORTED,
                    line,
                    w.range.clone(),
                    format!(
                        "`{text}`: a value the control finds from the contour (`?`) is not read"
                    ),
                    "write the value as a number",
                );
                ok = false;
                continue;
            }
            match w.name.as_str() {
                "G" | "M" => match w.number().and_then(|d| d.to_whole().ok()) {
                    Some(n) if (0..10_000).contains(&n) => {
                        let list = if w.name == "G" {
                            &mut words.g
                        } else {
                            &mut words.m
                        };
                        list.push((n as u32, w));
                    }
                    _ => {
                        self.error(
                            codes::HEIR_NUMBER,
                            line,
                            w.range.clone(),
                            format!("`{text}`: a G or M code is a whole number"),
                            "write the code as `G1`, `M3`",
                        );
                        ok = false;
                    }
                },
                name if LETTERS.contains(&name) => {
                    let same = |n: &str| {
                        n == name
                            || n.trim_end_matches('I') == name.trim_end_matches('I')
                                && matches!(name, "X" | "XI" | "Z" | "ZI")
                    };
                    if let Some(other) = words.letters.iter().find(|o| same(&o.name)) {
                        self.repeated(line, w, other);
                        ok = false;
                    } else {
                        words.letters.push(w);
                    }
                }
                _ => {
                    self.error(
                        codes::HEIR_UNSUPPORTED,
                        line,
                        w.range.clone(),
                        refused_letter(w),
                        "write the block with the words ncthread reads (README.md, section HEIDENHAIN)",
                    );
                    ok = false;
                }
            }
        }
        ok.then_some(words)
    }

    fn block(&mut self, line: Line<'_>, block: &Block, span: Span) {
        // A cycle brings words of its own: the cycle is what is not read.
        if let Some((g, w)) = block
            .words
            .iter()
            .filter(|w| w.name == "G")
            .filter_map(|w| Some((w.number()?.to_whole().ok()?, w)))
            .find(|(g, _)| !KNOWN_G.contains(g))
        {
            self.error(
                codes::HEIR_UNSUPPORTED,
                line,
                w.range.clone(),
                format!(
                    "`G{g}`: {}",
                    refused_g(u32::try_from(g).unwrap_or(u32::MAX))
                ),
                "write the block with the G codes ncthread reads (README.md, section HEIDENHAIN)",
            );
            return;
        }
        let Some(words) = self.sort(line, block) else {
            return;
        };
        let Some(g) = self.g_codes(line, &words) else {
            return;
        };
        let mut switches = Switches::default();
        let mut stops = Vec::new();
        let Some(()) = self.machine_words(line, &words, &g, &mut switches, &mut stops, span) else {
            return;
        };
        switches.before_motion(&mut self.r, None);
        if g.dwell {
            let Some(()) = self.dwell(line, &words, span) else {
                return;
            };
        } else {
            if let Some(m) = g.motion {
                self.motion = Some(m);
            }
            let Some(()) = self.motion(line, &words, &g, block, span) else {
                return;
            };
        }
        // M5, M9, M0 and M1 act after the block's motion, as the other readers decide.
        switches.coolant_off(&mut self.r, None);
        switches.spindle_stop(&mut self.r, None);
        for (optional, at) in stops {
            self.r.push(ItemKind::Stop { optional }, at, None);
        }
        switches.program_end(&mut self.r, None);
    }
}

/// What a block's G codes say.
#[derive(Default)]
struct GCodes {
    motion: Option<Motion>,
    dwell: bool,
    /// G94 (false) or G95 (true).
    feed_mode: Option<bool>,
    /// G96 (true) or G97 (false).
    speed_mode: Option<bool>,
    limit: bool,
}

impl FrontEnd<'_> {
    /// The block's G codes; `None` when one is refused (reported).
    fn g_codes(&mut self, line: Line<'_>, words: &Words<'_>) -> Option<GCodes> {
        let mut g = GCodes::default();
        let mut ok = true;
        for &(n, w) in &words.g {
            let motion = match n {
                0 => Some(Motion::Rapid),
                1 => Some(Motion::Feed),
                2 | 3 => Some(Motion::Arc {
                    g2: n == 2,
                    absolute: false,
                }),
                12 | 13 => Some(Motion::Arc {
                    g2: n == 12,
                    absolute: true,
                }),
                33 => Some(Motion::Thread),
                _ => None,
            };
            let conflict = match n {
                _ if motion.is_some() => {
                    let was = g.motion.is_some() || g.dwell;
                    g.motion = motion;
                    was
                }
                4 => std::mem::replace(&mut g.dwell, true) || g.motion.is_some(),
                94 | 95 => g.feed_mode.replace(n == 95).is_some(),
                96 | 97 => g.speed_mode.replace(n == 96).is_some(),
                26 => std::mem::replace(&mut g.limit, true),
                40 => false,
                _ => {
                    self.error(
                        codes::HEIR_UNSUPPORTED,
                        line,
                        w.range.clone(),
                        format!("`G{n}`: {}", refused_g(n)),
                        "write the block with the G codes ncthread reads (README.md, section HEIDENHAIN)",
                    );
                    ok = false;
                    continue;
                }
            };
            if conflict {
                self.error(
                    codes::HEIR_CONFLICT,
                    line,
                    w.range.clone(),
                    format!("`G{n}` with another G code of its kind in the same block"),
                    "give one motion, one feed mode and one speed mode per block",
                );
                ok = false;
            }
        }
        // S is G26's, G96's or G97's parameter: one of them per block.
        if g.limit && g.speed_mode.is_some() {
            let at = words
                .g
                .iter()
                .find(|(n, _)| *n == 26)
                .map(|(_, w)| w.range.clone());
            self.error(
                codes::HEIR_CONFLICT,
                line,
                at.unwrap_or(0..0),
                "G26 with G96 or G97 in one block: S is the parameter of each",
                "write the speed limit G26 S in a block of its own",
            );
            ok = false;
        }
        ok.then_some(g)
    }

    /// T, the modes, S, M: what the block switches; `None` when refused (reported).
    fn machine_words(
        &mut self,
        line: Line<'_>,
        words: &Words<'_>,
        g: &GCodes,
        switches: &mut Switches,
        stops: &mut Vec<(bool, Span)>,
        span: Span,
    ) -> Option<()> {
        self.tool_and_feed_mode(line, words, g, span)?;
        let speed = self.speed_words(line, words, g, switches, span)?;
        let direction = self.m_words(line, words, switches, stops, span)?;
        if speed.is_some() || direction.is_some() {
            switches.spindle = Some((speed, direction, span));
        }
        Some(())
    }

    /// T (the pocket's tool with its own data) and G94/G95.
    fn tool_and_feed_mode(
        &mut self,
        line: Line<'_>,
        words: &Words<'_>,
        g: &GCodes,
        span: Span,
    ) -> Option<()> {
        if let Some(w) = words.get("T") {
            let t = self.whole(line, w, "a tool (turret pocket) number")?;
            // The pocket's tool with its own data: its offset too.
            self.r.push(
                ItemKind::Tool {
                    number: Some(t),
                    offset: Some(t),
                },
                span,
                None,
            );
        }
        if let Some(per_rev) = g.feed_mode {
            self.per_rev = Some(per_rev);
            let mode = if per_rev {
                FeedMode::PerRev
            } else {
                FeedMode::PerMin
            };
            self.r.push(ItemKind::FeedMode(mode), span, None);
            self.f = None;
        }
        Some(())
    }

    /// S with G26, G96 or G97 (or alone): the speed of the block's spindle item, if any.
    fn speed_words(
        &mut self,
        line: Line<'_>,
        words: &Words<'_>,
        g: &GCodes,
        switches: &mut Switches,
        span: Span,
    ) -> Option<Option<u32>> {
        let speed = match words.get("S") {
            Some(w) => Some(self.whole(line, w, "a speed")?),
            None => None,
        };
        if g.limit {
            self.limit_word(line, speed)?;
        }
        let mut speed_word = speed.filter(|_| !g.limit);
        if let Some(surface) = g.speed_mode {
            let Some(s) = speed_word else {
                self.error(
                    codes::HEIR_NUMBER,
                    line,
                    0..line.text.len(),
                    format!(
                        "G{} without S: S is its parameter",
                        if surface { 96 } else { 97 }
                    ),
                    "write the speed with it: `G96 S200`, `G97 S1000`",
                );
                return None;
            };
            self.surface = surface;
            let mode = if surface {
                SpindleMode::SurfaceSpeed {
                    limit: self.limit.map(|l| Decimal {
                        mantissa: i128::from(l),
                        scale: 0,
                        has_point: false,
                    }),
                    feet: false,
                }
            } else {
                SpindleMode::Rpm
            };
            switches.spindle_mode = Some((mode, span));
            speed_word = Some(s);
        }
        if g.speed_mode.is_some() {
            self.speed_mode_said = true;
        } else if let (Some(_), false) = (speed_word, self.speed_mode_said) {
            self.unknown(
                "speed mode",
                line,
                0..line.text.len(),
                "an S before G96 or G97: whether S is a surface speed or rpm at the start is the machine's state",
                "write the mode with the first speed: `G97 S1000` (rpm) or `G96 S200` (m/min)",
            );
            return None;
        }
        if !self.surface
            && let Some(s) = speed_word
        {
            self.rpm = Some(s);
        }
        if let (Some(s), Some(l), false) = (speed_word, self.limit, self.surface)
            && s > l
        {
            self.error(
                codes::HEIR_UNSUPPORTED,
                line,
                0..line.text.len(),
                format!("S{s} rpm above the speed limit G26 S{l}: the maximum speed limits a constant speed too (MANUALplus 4110 manual)"),
                "keep the speed within the limit, or set the limit after the speed",
            );
            return None;
        }
        Some(speed_word)
    }

    /// `G26 S`: the limit of the next G96 (and of G97's speed).
    fn limit_word(&mut self, line: Line<'_>, speed: Option<u32>) -> Option<()> {
        let Some(s) = speed else {
            self.error(
                codes::HEIR_NUMBER,
                line,
                0..line.text.len(),
                "G26 without S: the speed limit is its S",
                "write `G26 S<rpm>`",
            );
            return None;
        };
        if self.surface {
            self.error(
                codes::HEIR_UNSUPPORTED,
                line,
                0..line.text.len(),
                "G26 while G96 is in force: ncthread reads a speed limit set before the G96 it limits",
                "write G26 S before the G96 block",
            );
            return None;
        }
        if let Some(rpm) = self.rpm.filter(|r| *r > s && !self.surface) {
            self.error(
                codes::HEIR_UNSUPPORTED,
                line,
                0..line.text.len(),
                format!("G26 S{s} below the {rpm} rpm the spindle turns at under G97: the maximum speed limits a constant speed too (MANUALplus 4110 manual)"),
                "set the limit before the speed, or at least as high",
            );
            return None;
        }
        self.limit = Some(s);
        Some(())
    }

    /// M3/M4 (the direction, returned), M5, M8/M9, M0/M1, M30.
    fn m_words(
        &mut self,
        line: Line<'_>,
        words: &Words<'_>,
        switches: &mut Switches,
        stops: &mut Vec<(bool, Span)>,
        span: Span,
    ) -> Option<Option<SpindleDirection>> {
        let mut direction = None;
        for &(m, w) in &words.m {
            match m {
                3 | 4 => {
                    direction = Some(if m == 3 {
                        SpindleDirection::Clockwise
                    } else {
                        SpindleDirection::CounterClockwise
                    })
                }
                5 => switches.spindle_stop = Some(span),
                8 => switches.coolant.push((Coolant::Flood, span)),
                9 => switches.coolant.push((Coolant::Off, span)),
                0 | 1 => stops.push((m == 1, span)),
                30 => switches.end = Some((EndCode::M30, span)),
                _ => {
                    self.error(
                        codes::HEIR_UNSUPPORTED,
                        line,
                        w.range.clone(),
                        format!("`M{m}`: the machine builder's M codes are not read (ncthread reads M0, M1, M3, M4, M5, M8, M9, M30)"),
                        "remove the M code, or convert the block by hand",
                    );
                    return None;
                }
            }
        }
        Some(direction)
    }

    fn whole(&mut self, line: Line<'_>, w: &Word, what: &str) -> Option<u32> {
        let whole = w.number().and_then(|d| d.to_whole().ok());
        let n = whole.and_then(|n| u32::try_from(n).ok());
        if n.is_none() {
            // A whole number out of range is said as such, not as a fraction.
            let (why, help) = match whole {
                Some(v) if v < 0 => ("is not negative", "write it without the sign"),
                Some(_) => ("is too large", "write a smaller number"),
                None => ("is a whole number", "write it without a fraction"),
            };
            self.word_error(
                codes::HEIR_NUMBER,
                line,
                w,
                format_args!(": {what} {why}"),
                help,
            );
        }
        n
    }

    /// `G4 F<s>`.
    fn dwell(&mut self, line: Line<'_>, words: &Words<'_>, span: Span) -> Option<()> {
        let seconds = words
            .get("F")
            .and_then(|w| w.number())
            .filter(|d| !d.is_negative());
        let Some(seconds) = seconds else {
            self.error(
                codes::HEIR_NUMBER,
                line,
                0..line.text.len(),
                "G4 without its time F (seconds)",
                "write `G4 F<seconds>`",
            );
            return None;
        };
        if let Some(w) = words
            .letters
            .iter()
            .find(|w| !matches!(w.name.as_str(), "F" | "S" | "T"))
        {
            self.error(
                codes::HEIR_CONFLICT,
                line,
                w.range.clone(),
                "a dwell (G4) with an axis or arc word: ncthread reads the dwell in a block of its own",
                "move in one block and dwell in the next",
            );
            return None;
        }
        self.r.push(ItemKind::Dwell { seconds }, span, None);
        // G4's F is its time: whether it is the feed's F too is not published.
        self.f = None;
        Some(())
    }

    fn length_of(&mut self, line: Line<'_>, w: &Word) -> Option<Length> {
        let value = w
            .number()
            .and_then(|d| d.to_length().ok())
            .filter(|l| l.0.abs() < 1 << 55);
        if value.is_none() {
            self.word_error(
                codes::HEIR_NUMBER,
                line,
                w,
                " is too large or finer than 0.0001 mm",
                "write the value with at most 4 decimals",
            );
        }
        value
    }

    /// Where the block's X/Xi and Z/Zi go (Xi a diameter increment); `None` when refused.
    fn target(&mut self, line: Line<'_>, words: &Words<'_>) -> Option<Pos> {
        let from = self.r.pos;
        let mut to = Pos::UNKNOWN;
        for (abs, inc, from_axis, axis) in [
            ("X", "XI", from.x, &mut to.x),
            ("Z", "ZI", from.z, &mut to.z),
        ] {
            if let Some(w) = words.get(abs) {
                *axis = Some(self.length_of(line, w)?);
            } else if let Some(w) = words.get(inc) {
                let d = self.length_of(line, w)?;
                let Some(start) = from_axis else {
                    self.word_error(
                        codes::HEIR_UNKNOWN_POSITION,
                        line,
                        w,
                        " from a position that is not known yet",
                        "move to an absolute position first",
                    );
                    return None;
                };
                let to = start + d;
                if to.0.abs() >= 1 << 55 {
                    self.word_error(
                        codes::HEIR_NUMBER,
                        line,
                        w,
                        " moves past the largest position ncthread holds",
                        "check the increments",
                    );
                    return None;
                }
                *axis = Some(to);
            }
        }
        Some(to)
    }

    /// The feed in force: F of this block, else the last; `None` when unknown (reported).
    fn feed(&mut self, line: Line<'_>, words: &Words<'_>, block: &Block) -> Option<Length> {
        if let Some(w) = words.get("F") {
            let feed = self.length_of(line, w).filter(|f| f.0 > 0);
            if feed.is_none() {
                self.error(
                    codes::HEIR_NUMBER,
                    line,
                    w.range.clone(),
                    "a feed is positive",
                    "write the feed, `F0.2`",
                );
                return None;
            }
            if self.per_rev.is_none() {
                self.unknown(
                    "feed mode",
                    line,
                    w.range.clone(),
                    "a feed before G94 or G95: whether F is per revolution or per minute is the machine's setting",
                    "write `G95 F…` (per revolution) or `G94 F…` (per minute) with the first feed",
                );
                return None;
            }
            self.f = feed;
        }
        if self.f.is_none() {
            self.error(
                codes::HEIR_UNKNOWN_POSITION,
                line,
                block.code_range.clone(),
                "a feed move without a feed: no F since the program's start, a change of G94/G95, or a G33 (whose F is its lead)",
                "write the feed with the move, `G1 X… F0.2`",
            );
        }
        self.f
    }

    fn motion(
        &mut self,
        line: Line<'_>,
        words: &Words<'_>,
        g: &GCodes,
        block: &Block,
        span: Span,
    ) -> Option<()> {
        let axes = ["X", "XI", "Z", "ZI"]
            .iter()
            .any(|a| words.get(a).is_some());
        let motion = self.motion;
        self.stray_words(line, words, motion, axes)?;
        if !axes {
            return self.feed_alone(line, words, g, block);
        }
        let Some(motion) = motion else {
            self.unknown(
                "motion",
                line,
                block.code_range.clone(),
                "an axis move before any G0, G1, G2, G3, G12, G13 or G33: the motion in force is the machine's setting",
                "write the motion (`G0 X… Z…`)",
            );
            return None;
        };
        let from = self.r.pos;
        let written = self.target(line, words)?;
        let to = Pos {
            x: written.x.or(from.x),
            z: written.z.or(from.z),
        };
        match motion {
            Motion::Rapid => {
                if let Some(w) = words.get("F") {
                    let feed = self.feed(line, words, block)?;
                    self.r.push(
                        ItemKind::FeedRate(feed),
                        self.span(line, w.range.clone()),
                        None,
                    );
                }
                self.r.push(ItemKind::Rapid { to: written }, span, None);
            }
            Motion::Feed => {
                let feed = self.feed(line, words, block)?;
                self.r
                    .push(ItemKind::Feed { to: written, feed }, span, None);
            }
            Motion::Arc { g2, absolute } => {
                let feed = self.feed(line, words, block)?;
                let (centre, clockwise) = self.arc(line, words, from, to, g2, absolute, block)?;
                self.r.push(
                    ItemKind::Arc {
                        to,
                        centre: Box::new(centre),
                        clockwise,
                        feed,
                    },
                    span,
                    None,
                );
            }
            Motion::Thread => self.thread(line, words, from, to, block, span)?,
        }
        self.after_thread = motion == Motion::Thread;
        if self.after_thread {
            // Whether G33's F (its lead) is the feed's F too is not published.
            self.f = None;
        }
        self.r.pos = to;
        Some(())
    }

    /// An F in a block that does not move: the feed from here on (a G33's F is its lead).
    fn feed_alone(
        &mut self,
        line: Line<'_>,
        words: &Words<'_>,
        g: &GCodes,
        block: &Block,
    ) -> Option<()> {
        if let Some(w) = words.get("F") {
            if g.motion == Some(Motion::Thread) {
                return Some(());
            }
            let feed = self.feed(line, words, block)?;
            self.r.push(
                ItemKind::FeedRate(feed),
                self.span(line, w.range.clone()),
                None,
            );
        }
        Some(())
    }

    /// I, K, R belong to an arc and B, P, C, H, E to a G33 that moves: elsewhere refused.
    fn stray_words(
        &mut self,
        line: Line<'_>,
        words: &Words<'_>,
        motion: Option<Motion>,
        axes: bool,
    ) -> Option<()> {
        if let Some(w) = ["I", "K", "R", "B", "P", "C", "H", "E"]
            .iter()
            .filter_map(|a| words.get(a))
            .find(|w| !word_of(motion, &w.name) || !axes)
        {
            let text = &line.text[w.range.clone()];
            let chamfer = w.name == "B" && matches!(motion, Some(Motion::Rapid | Motion::Feed));
            let (message, help) = if chamfer {
                (
                    format!(
                        "`{text}` on a line: a chamfer (B<0) or a rounding (B>0) at its end point is not read (where the corner goes depends on the next block's path)"
                    ),
                    "write the chamfer or the rounding as its own moves",
                )
            } else {
                (
                    format!(
                        "`{text}` outside the motion it belongs to (I, K and R to an arc, B, P, C, H and E to G33)"
                    ),
                    "write the word in the arc or G33 block that moves",
                )
            };
            self.error(
                codes::HEIR_UNSUPPORTED,
                line,
                w.range.clone(),
                message,
                help,
            );
            return None;
        }
        Some(())
    }

    /// An arc's centre and its direction in LinuxCNC's sense.
    #[allow(clippy::too_many_arguments)]
    fn arc(
        &mut self,
        line: Line<'_>,
        words: &Words<'_>,
        from: Pos,
        to: Pos,
        g2: bool,
        absolute: bool,
        block: &Block,
    ) -> Option<(Pos, bool)> {
        let code = match (g2, absolute) {
            (true, false) => "G2",
            (false, false) => "G3",
            (true, true) => "G12",
            (false, true) => "G13",
        };
        let whole = block.code_range.clone();
        let Some(direction) = self.profile.arc_direction else {
            self.unknown(
                "arc direction",
                line,
                whole,
                &format!("{code}: which way it turns on the machine the vendor shows only in a help graphic"),
                "declare `arc_direction = \"iso\"` (G2/G12 as LinuxCNC's G2) or `\"front-tool\"` in the profile's [heidenhain] section",
            );
            return None;
        };
        let clockwise = g2 == (direction == HeidenhainArcDirection::Iso);
        let (Some((sx, sz)), Some((ex, ez))) = (from.known(), to.known()) else {
            self.error(
                codes::HEIR_UNKNOWN_POSITION,
                line,
                whole,
                format!("{code} from a position that is not known yet: the arc's centre cannot be placed"),
                "move to an absolute X and Z before the arc",
            );
            return None;
        };
        let (i, k, r) = (words.get("I"), words.get("K"), words.get("R"));
        let centre = match (r, i.or(k)) {
            (Some(w), Some(_)) => {
                self.error(
                    codes::HEIR_CONFLICT,
                    line,
                    w.range.clone(),
                    "R with I or K: give the centre one way",
                    "write either I and K, or R",
                );
                return None;
            }
            (None, None) => {
                self.error(
                    codes::HEIR_ARC,
                    line,
                    whole,
                    format!("{code} without I, K or R"),
                    "write the centre (I a radius value, K) or the radius R",
                );
                return None;
            }
            (Some(w), None) => self.radius_centre(line, w, code, (sx, sz), (ex, ez), clockwise)?,
            (None, Some(_)) => {
                let start = if absolute { None } else { Some((sx, sz)) };
                self.ik_centre(line, (i, k), code, start, whole.clone())?
            }
        };
        self.on_its_circle(line, code, whole, (sx, sz), (ex, ez), centre)?;
        Some((centre, clockwise))
    }

    /// Whether the arc's end is on the circle through its start (within 0.002 mm).
    fn on_its_circle(
        &mut self,
        line: Line<'_>,
        code: &str,
        whole: Range<usize>,
        (sx, sz): (Length, Length),
        (ex, ez): (Length, Length),
        centre: Pos,
    ) -> Option<()> {
        let span = self.span(line, whole);
        self.r.arc_on_circle(
            codes::HEIR_ARC,
            span,
            code,
            (sx, sz),
            (ex, ez),
            centre.known()?,
            "check I and K (I a radius value)",
        )
    }

    /// The centre of an arc of radius `R` (up to half a circle).
    #[allow(clippy::too_many_arguments)]
    fn radius_centre(
        &mut self,
        line: Line<'_>,
        w: &Word,
        code: &str,
        (sx, sz): (Length, Length),
        (ex, ez): (Length, Length),
        clockwise: bool,
    ) -> Option<Pos> {
        let radius = self.length_of(line, w)?;
        if radius.0 <= 0 || (sx, sz) == (ex, ez) {
            self.error(
                codes::HEIR_ARC,
                line,
                w.range.clone(),
                format!("{code} with R: a radius that is not positive, or an arc that ends where it starts"),
                "write the arc with I and K",
            );
            return None;
        }
        let span = self.span(line, w.range.clone());
        let text = &line.text[w.range.clone()];
        self.r.centre_of_radius(
            codes::HEIR_ARC,
            span,
            text,
            (sx, sz),
            (ex, ez),
            radius,
            clockwise,
        )
    }

    /// The centre from I (a radius value) and K: from the arc's `start` (G2/G3), or absolute
    /// (G12/G13, `start` none: both words needed).
    fn ik_centre(
        &mut self,
        line: Line<'_>,
        (i, k): (Option<&Word>, Option<&Word>),
        code: &str,
        start: Option<(Length, Length)>,
        whole: Range<usize>,
    ) -> Option<Pos> {
        let absolute = start.is_none();
        let (sx, sz) = start.unwrap_or((Length::ZERO, Length::ZERO));
        let (bx, bz) = (sx, sz);
        let (i, k) = match (i, k) {
            (Some(i), Some(k)) => (self.length_of(line, i)?, self.length_of(line, k)?),
            _ if absolute => {
                self.error(
                    codes::HEIR_ARC,
                    line,
                    whole,
                    format!("{code} with only one of I and K: the absolute centre needs both"),
                    "write I (the centre's X as a radius value) and K",
                );
                return None;
            }
            (i, k) => (
                match i {
                    Some(w) => self.length_of(line, w)?,
                    None => Length::ZERO,
                },
                match k {
                    Some(w) => self.length_of(line, w)?,
                    None => Length::ZERO,
                },
            ),
        };
        Some(Pos::new(bx + i + i, bz + k))
    }

    /// `G33 X Z F B P C H`: one pass whose spindle angle at its start follows from C at the
    /// end of the run-in B.
    fn thread(
        &mut self,
        line: Line<'_>,
        words: &Words<'_>,
        from: Pos,
        to: Pos,
        block: &Block,
        span: Span,
    ) -> Option<()> {
        let whole = block.code_range.clone();
        self.thread_not_read(line, words, whole.clone())?;
        let refuse = |fe: &mut Self, range: Range<usize>, message: &str, help: &str| {
            fe.error(codes::HEIR_THREAD, line, range, message.to_string(), help);
        };
        let lead = self.lead(
            line,
            words.get("F"),
            whole.clone(),
            codes::HEIR_THREAD,
            "G33",
        )?;
        // X is modal: a pass along Z needs only its Z; one that moves X, its start.
        let moves_x = to.x != from.x;
        let (Some(z0), Some(z1)) = (from.z, to.z) else {
            self.error(
                codes::HEIR_UNKNOWN_POSITION,
                line,
                whole,
                "G33 from a position that is not known yet",
                "move to the thread's start with X and Z first",
            );
            return None;
        };
        let dr = match (from.x, to.x) {
            (Some(x0), Some(x1)) => (x1 - x0).0.unsigned_abs(),
            _ if !moves_x => 0,
            _ => {
                self.error(
                    codes::HEIR_UNKNOWN_POSITION,
                    line,
                    whole,
                    "a taper G33 from an X that is not known yet",
                    "move to the thread's start with X and Z first",
                );
                return None;
            }
        };
        let dz = (z1 - z0).0.unsigned_abs();
        if dr > 2 * dz || dz == 0 {
            refuse(
                self,
                whole,
                "this G33 moves X (as a radius) more than Z: H0's lead along Z is for tapers up to 45°",
                "cut the thread with Z as the long axis",
            );
            return None;
        }
        let angle = self.start_angle(line, words, lead, moves_x.then_some((dr, dz)), whole)?;
        let pass = ThreadPass {
            to,
            lead,
            start: SyncStart::Index(angle),
            infeed: None,
            entry: None,
            exit: None,
        };
        self.r.push(ItemKind::pass(pass), span, None);
        Some(())
    }

    /// What makes a G33 one the reader does not read: H1/H3, E, P0, a G33 right after another,
    /// G96.
    fn thread_not_read(
        &mut self,
        line: Line<'_>,
        words: &Words<'_>,
        whole: Range<usize>,
    ) -> Option<()> {
        let refuse = |fe: &mut Self, range: Range<usize>, message: &str, help: &str| {
            fe.error(codes::HEIR_THREAD, line, range, message.to_string(), help);
        };
        for (name, what) in [
            (
                "H",
                "H1 and H3 (a lead along X or along the path) are not read",
            ),
            ("E", "a variable pitch E is not read"),
        ] {
            if let Some(w) = words.get(name)
                && w.number().is_none_or(|d| d.mantissa != 0)
            {
                refuse(
                    self,
                    w.range.clone(),
                    what,
                    "cut the thread with its lead along Z: H0",
                );
                return None;
            }
        }
        if let Some(w) = words.get("P")
            && w.number().is_some_and(|d| d.mantissa == 0)
        {
            refuse(
                self,
                w.range.clone(),
                "P0: a G33 that a successive G33 continues (a chain) is not read",
                "end each pass with a run-out P>0 and retract",
            );
            return None;
        }
        if self.after_thread {
            refuse(
                self,
                whole,
                "a G33 right after another: the vendor's successive G33 blocks are one thread run on, whose synchronisation is not published",
                "retract (G0) between two passes",
            );
            return None;
        }
        if self.surface {
            refuse(
                self,
                whole,
                "a thread under constant surface speed (G96) is not read",
                "set the speed in rpm (G97 S…) before the thread",
            );
            return None;
        }
        Some(())
    }

    /// A thread's lead F (G33's, G31's): `code` when it is missing.
    pub(super) fn lead(
        &mut self,
        line: Line<'_>,
        f: Option<&Word>,
        whole: Range<usize>,
        code: Code,
        what: &str,
    ) -> Option<Lead> {
        let Some(w) = f else {
            self.error(
                code,
                line,
                whole,
                format!("{what} without F, its lead"),
                "write the thread's lead along Z: `F1.5`",
            );
            return None;
        };
        let lead = w
            .number()
            .and_then(|d| d.to_lead().ok())
            .filter(|l| l.0 > 0 && *l <= Lead::MAX);
        if lead.is_none() {
            self.word_error(
                codes::HEIR_NUMBER,
                line,
                w,
                ": a lead is positive, at most 12 decimals of a mm",
                "write the thread's lead along Z, `F1.5`",
            );
        }
        lead
    }

    /// C as an angle of the spindle's turn: as the profile's `c_sense` counts it; without
    /// it only 0° and 180°, which read the same both ways.
    fn c_in_spindle_sense(
        &mut self,
        line: Line<'_>,
        c: Option<(Angle, Range<usize>)>,
        whole: Range<usize>,
    ) -> Option<Angle> {
        let c_angle = c.as_ref().map_or(Angle::ZERO, |(a, _)| *a);
        match self.profile.c_sense {
            Some(CSense::Against) => Some(Angle(-c_angle.0)),
            Some(CSense::Spindle) => Some(c_angle),
            None if c_angle.0 % 180_000 == 0 => Some(c_angle),
            None => {
                let range = c.map_or(whole, |(_, r)| r);
                self.unknown(
                    "c sense",
                    line,
                    range,
                    "C other than 0° or 180°: whether G33's start angle counts with the spindle or against it is not published",
                    "declare `c_sense = \"spindle\"` or `\"against\"` in the profile's [heidenhain] section, as a test cut shows",
                );
                None
            }
        }
    }

    /// The spindle's angle at the pass's start: C (as the profile's `c_sense` counts it) less
    /// the turn over the run-in B (along Z, or along the path of a taper `(dr, dz)` as
    /// `b_along` says).
    fn start_angle(
        &mut self,
        line: Line<'_>,
        words: &Words<'_>,
        lead: Lead,
        taper: Option<(u64, u64)>,
        whole: Range<usize>,
    ) -> Option<Angle> {
        let Some(b) = words.get("B") else {
            self.unknown(
                "run-in",
                line,
                whole,
                "G33 without B: the run-in, at whose end the spindle is at C, is then a machine parameter",
                "write the run-in on every G33 block: `B1.5`",
            );
            return None;
        };
        let b_len = self.length_of(line, b).filter(|l| l.0 >= 0);
        let Some(b_len) = b_len else {
            self.error(
                codes::HEIR_NUMBER,
                line,
                b.range.clone(),
                "the run-in B is not negative",
                "write `B1.5`",
            );
            return None;
        };
        let c = match words.get("C") {
            Some(w) => {
                let c = w.number().and_then(|d| d.to_angle().ok());
                let Some(c) = c else {
                    self.error(
                        codes::HEIR_NUMBER,
                        line,
                        w.range.clone(),
                        "C is an angle in degrees, at most 3 decimals",
                        "write `C90`",
                    );
                    return None;
                };
                Some((c, w.range.clone()))
            }
            None => None,
        };
        let c_spindle = self.c_in_spindle_sense(line, c, whole)?;
        let turn = match (taper, self.profile.b_along) {
            (None, _) | (Some(_), Some(BAlong::Z)) => lead.turn_over(b_len),
            (Some((dr, dz)), Some(BAlong::Path)) => {
                // B along the path: its Z share is B·dz/L (rounded once onto the grid).
                let (r, z) = (dr as f64 / 2.0, dz as f64);
                let along = b_len.to_mm_f64() * z / r.hypot(z);
                lead.turn_over(Length::from_mm_f64(along))
            }
            (Some(_), None) => {
                self.unknown(
                    "b measure",
                    line,
                    b.range.clone(),
                    "B on a taper G33: whether the run-in is measured along Z or along the path is not published, and the start angle depends on it",
                    "declare `b_along = \"z\"` or `\"path\"` in the profile's [heidenhain] section, as a test cut shows",
                );
                return None;
            }
        };
        Some(Angle((c_spindle.0 - turn).rem_euclid(360_000)))
    }
}

/// Whether the address `name` belongs to the motion `motion`.
fn word_of(motion: Option<Motion>, name: &str) -> bool {
    match motion {
        Some(Motion::Arc { .. }) => matches!(name, "I" | "K" | "R"),
        Some(Motion::Thread) => matches!(name, "B" | "P" | "C" | "H" | "E" | "I"),
        _ => false,
    }
}

mod g31;
mod names;
#[cfg(test)]
mod tests;

//! SINUMERIK native turning → IR: what the writer writes (so that `verify` proves a
//! conversion), `=AC()`/`=IC()`, `G91`, `G70` inch, `G94`, `M30`/`M2`/`M17`; everything else is
//! refused by name (siemens.md "Reading").
//!
//! A block runs in one order **\[decided\]**, as the other controls' readers do: its modes
//! (units, G90/G91, DIAMON/DIAMOF, G94/G95, G40, the work offset), the tool, the speed mode and
//! the spindle, coolant on, the motion or dwell, then coolant off, M5, stops and the end.
//! What depends on a machine setting the program has not stated is refused: X before DIAMON or
//! DIAMOF, a feed before G94 or G95, a G33 without `SF=`.

use std::ops::Range;

use super::codes;
use super::profile::SiemensProfile;
use super::syntax::{self, Block, Value, Word};
use crate::diag::{Code, Diagnostic};
use crate::dialect::machine::Switches;
use crate::dialect::read::{Keep, Reader};
use crate::fixed::{Angle, Decimal, Lead, Length};
use crate::ir::{
    Compensation, Coolant, EndCode, FeedMode, ItemKind, Pos, Program, SpindleDirection,
    SpindleMode, SyncStart, ThreadPass,
};
use crate::source::{Line, SourceFile, Span};
use names::{LETTERS, refused_g, refused_name};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Motion {
    Rapid,
    Feed,
    Arc { clockwise: bool },
    Thread,
}

struct FrontEnd<'a> {
    r: Reader<'a>,
    /// G90 (the vendor's reset state) or G91.
    absolute: bool,
    /// DIAMON (X a diameter) or DIAMOF; `None` until the program says.
    diameter: Option<bool>,
    /// G70/G700: lengths in inches.
    inch: bool,
    /// G700: feeds in inches too (G70 leaves F in the machine's basic system, which
    /// ncthread takes as metric **\[decided\]**).
    inch_feed: bool,
    /// The spindle turns (M3/M4 since the last M5).
    turning: bool,
    /// The last surface speed (S under G96/G961), which a G96 without S takes again.
    cutting: Option<u32>,
    /// LIMS in force: it limits G97 too.
    lims: Option<u32>,
    /// The profile's feed per minute at the start, pushed before the first block's items.
    start_per_minute: bool,
    /// G95 or G94; `None` until the program says.
    per_rev: Option<bool>,
    motion: Option<Motion>,
    f: Option<Length>,
    /// G96 is in force, with this LIMS.
    surface: bool,
    /// The last motion was a G33: a G33 now would continue it.
    after_thread: bool,
    ended: bool,
    warned_ramp: bool,
    /// The statements that move nothing already warned of (MSG, STOPRE).
    warned_no_motion: Vec<String>,
    /// The unstated machine settings already reported (one error each is enough: every
    /// later word that depends on it is the same mistake).
    reported_mode: Vec<&'static str>,
    /// The tool in use (its D numbers are its cutting edges).
    tool: Option<u32>,
}

/// Reads a SINUMERIK program.
pub(crate) fn read(
    src: &SourceFile,
    profile: &SiemensProfile,
    keep: Keep,
) -> (Program, Vec<Diagnostic>) {
    let mut fe = FrontEnd {
        r: Reader::new(src, super::ID, keep),
        absolute: true,
        diameter: profile.initial_diameter,
        inch: false,
        inch_feed: false,
        turning: false,
        cutting: None,
        lims: None,
        start_per_minute: profile.initial_per_rev == Some(false),
        per_rev: profile.initial_per_rev,
        motion: None,
        f: None,
        surface: false,
        after_thread: false,
        ended: false,
        warned_ramp: false,
        warned_no_motion: Vec::new(),
        reported_mode: Vec::new(),
        tool: None,
    };
    let mut first = true;
    for line in src.lines() {
        fe.r.line_read();
        if line.is_blank() {
            continue;
        }
        match syntax::parse_line(line.text) {
            Ok(block) => {
                let at_start = std::mem::take(&mut first);
                fe.line(line, &block, at_start);
            }
            Err(e) => {
                first = false;
                fe.r.syntax_error(codes::SINR_SYNTAX, line, e.offset, e.message, e.help);
            }
        }
    }
    fe.r.finish()
}

/// Whether a block's comment is the `;$PATH=…` line that stands under the program's name.
fn path_line(block: &Block) -> bool {
    block.words.is_empty()
        && block.number.is_none()
        && block
            .comment
            .as_deref()
            .is_some_and(|c| c.to_ascii_uppercase().starts_with("$PATH="))
}

impl FrontEnd<'_> {
    fn span(&self, line: Line<'_>, range: Range<usize>) -> Span {
        self.r.span(line, range)
    }

    /// An unstated machine setting `what`, reported at its first use only.
    fn mode_unknown(
        &mut self,
        what: &'static str,
        line: Line<'_>,
        range: Range<usize>,
        message: &str,
        help: &str,
    ) {
        // The program is refused at the first; the later uses are the same mistake.
        if !self.reported_mode.contains(&what) {
            self.reported_mode.push(what);
            self.error(
                codes::SINR_MODE_UNKNOWN,
                line,
                range,
                message.to_string(),
                help,
            );
        }
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

    fn line(&mut self, line: Line<'_>, block: &Block, at_start: bool) {
        if let Some((name, _)) = &block.header {
            if at_start {
                self.r.name = Some(name.clone());
            } else {
                let whole = 0..line.text.len();
                self.error(
                    codes::SINR_SYNTAX,
                    line,
                    whole,
                    "a program's name (`%_N_…_MPF`) after its first line".to_string(),
                    "a file holds one program: its name stands on the first line",
                );
            }
            return;
        }
        if path_line(block) && self.r.items.is_empty() {
            return;
        }
        if self.ended {
            // A comment after the end is kept, as every reader keeps it.
            if block.words.is_empty() {
                if let Some(c) = block.comment.clone() {
                    let span = self.span(line, 0..line.text.len());
                    self.r.push(ItemKind::Comment(c), span, block.number);
                }
            } else {
                let span = self.span(line, block.code_range.clone());
                self.r.after_end(
                    codes::SINR_AFTER_END,
                    span,
                    "blocks after the program's end (M30, M2, M17) are not run and not converted",
                    "remove them, or move the end to after them",
                );
            }
            return;
        }
        let first = self.r.items.len();
        let span = self.span(line, block.code_range.clone());
        if let Some(range) = block.block_delete.clone() {
            self.error(
                codes::SINR_UNSUPPORTED,
                line,
                range,
                "`/` (block skip): whether the block runs is the operator's switch, which the program does not state",
                "remove the `/`, or the block",
            );
        } else if !block.words.is_empty() {
            self.block(line, block, span);
        }
        self.ended = self.r.ends_program(first);
        // A block of messages alone keeps its own comment as one more comment.
        let only_comments = self.r.items.get(first..).is_some_and(|items| {
            !items.is_empty() && items.iter().all(|i| matches!(i.kind, ItemKind::Comment(_)))
        });
        match block.comment.clone() {
            Some(c) if only_comments => self.r.push(ItemKind::Comment(c), span, block.number),
            comment => self
                .r
                .stamp_block(first, block.number, comment, span, false),
        }
    }
}

/// The words of one block, sorted by what they do.
#[derive(Default)]
struct Words<'b> {
    g: Vec<(u32, &'b Word)>,
    m: Vec<(u32, &'b Word)>,
    letters: Vec<&'b Word>,
    diam: Option<(bool, &'b Word)>,
    /// MSG("…") texts, kept as comments.
    messages: Vec<(String, Span)>,
}

impl<'b> Words<'b> {
    fn get(&self, name: &str) -> Option<&'b Word> {
        self.letters.iter().copied().find(|w| w.name == name)
    }

    fn has_g(&self, g: u32) -> bool {
        self.g.iter().any(|(n, _)| *n == g)
    }
}

/// What a block's G codes say: its motion, or a dwell, and the items of its modes.
#[derive(Default)]
struct GCodes {
    motion: Option<Motion>,
    dwell: bool,
    modes: Vec<(ItemKind, Span)>,
}

impl FrontEnd<'_> {
    /// Sorts the block's words; `None` when one is refused (reported).
    fn sort<'b>(&mut self, line: Line<'_>, block: &'b Block) -> Option<Words<'b>> {
        let mut words = Words::default();
        let mut ok = true;
        let mut skip_target = false;
        for w in &block.words {
            ok &= self.sort_word(line, w, &mut words, &mut skip_target);
        }
        ok.then_some(words)
    }

    /// One word into `words`; `false` when it is refused (reported). `skip_target`: the
    /// word after a refused jump is its target, refused with it.
    fn sort_word<'b>(
        &mut self,
        line: Line<'_>,
        w: &'b Word,
        words: &mut Words<'b>,
        skip_target: &mut bool,
    ) -> bool {
        let text = &line.text[w.range.clone()];
        let refuse = |fe: &mut Self, code: Code, message: String, help: &str| {
            fe.error(code, line, w.range.clone(), message, help);
            false
        };
        match (w.name.as_str(), &w.value) {
            ("G" | "M", Value::Plain(d)) if !w.assigned => self.code(line, w, *d, words),
            ("DIAMON" | "DIAMOF", Value::None) => {
                if words.diam.replace((w.name == "DIAMON", w)).is_some() {
                    return refuse(
                        self,
                        codes::SINR_CONFLICT,
                        "DIAMON and DIAMOF twice in one block".into(),
                        "say once whether X is a diameter",
                    );
                }
                true
            }
            ("DITS" | "DITE", Value::Plain(_)) if w.assigned => {
                self.ramp(line, w);
                true
            }
            (name, Value::None) if name.len() == 1 && LETTERS.contains(&name) => refuse(
                self,
                codes::SINR_SYNTAX,
                format!("address `{name}` is not followed by a number"),
                "write the value after the address (`X26.618`, `X=AC(20)`)",
            ),
            (name, Value::Plain(_) | Value::Absolute(_) | Value::Incremental(_))
                if LETTERS.contains(&name) && (name.len() == 1 || w.assigned) =>
            {
                self.letter(line, w, words)
            }
            ("STOPRE", Value::None) => {
                self.no_motion(
                    line,
                    w,
                    "STOPRE stops the look-ahead, not the machine: left out",
                );
                true
            }
            ("MSG", Value::Call) => {
                self.message(line, w, words);
                true
            }
            // The jump's target is the jump's: one refusal.
            (_, Value::None) if *skip_target => {
                *skip_target = false;
                false
            }
            (name, value) => {
                *skip_target = *value == Value::None && name.starts_with("GOTO");
                let what = if *value == Value::Label {
                    format!("`{name}:`: labels and program jumps are not read")
                } else {
                    refused_name(name, text)
                };
                refuse(
                    self,
                    codes::SINR_UNSUPPORTED,
                    what,
                    "convert this part by hand, or remove it from the source",
                )
            }
        }
    }

    /// A G or M code, a whole number, into `words`; `false` when refused.
    fn code<'b>(&mut self, line: Line<'_>, w: &'b Word, d: Decimal, words: &mut Words<'b>) -> bool {
        match d.to_whole().ok().and_then(|n| u32::try_from(n).ok()) {
            Some(n) if !d.has_point => {
                let codes = if w.name == "G" {
                    &mut words.g
                } else {
                    &mut words.m
                };
                codes.push((n, w));
                true
            }
            _ => {
                self.error(
                    codes::SINR_NUMBER,
                    line,
                    w.range.clone(),
                    format!(
                        "`{}`: a G or M code is a whole number",
                        &line.text[w.range.clone()]
                    ),
                    "write the code without a decimal point (`G33`, `M30`)",
                );
                false
            }
        }
    }

    /// DITS/DITE: a warning, once.
    fn ramp(&mut self, line: Line<'_>, w: &Word) {
        if !std::mem::replace(&mut self.warned_ramp, true) {
            let span = self.span(line, w.range.clone());
            let text = &line.text[w.range.clone()];
            self.r.diags.push(
                Diagnostic::new(
                    codes::SINR_RAMP,
                    format!("`{text}` changes the thread's run-in or run-out ramp, not its path: it is not converted"),
                )
                .at(self.r.src, span)
                .help("check the thread's run-in and run-out on the target machine"),
            );
        }
    }

    /// `MSG("…")`: its text kept as a comment, with a warning.
    fn message<'b>(&mut self, line: Line<'_>, w: &'b Word, words: &mut Words<'b>) {
        let message = line.text[w.range.clone()]
            .split_once('(')
            .map_or("", |(_, m)| m.trim_end().trim_end_matches(')'))
            .trim()
            .trim_matches('"');
        if let Some(m) = crate::dialect::comment_text(message) {
            words.messages.push((m, self.span(line, w.range.clone())));
        }
        self.no_motion(
            line,
            w,
            "MSG shows the operator a message: kept as a comment",
        );
    }

    /// An address letter (or `SF=`, `CR=`, `LIMS=`) into `words`; `false` when refused.
    fn letter<'b>(&mut self, line: Line<'_>, w: &'b Word, words: &mut Words<'b>) -> bool {
        let name = w.name.as_str();
        if words.get(name).is_some() {
            self.error(
                codes::SINR_CONFLICT,
                line,
                w.range.clone(),
                format!("`{name}` twice in one block"),
                "give each address once per block",
            );
            return false;
        }
        if !matches!(w.value, Value::Plain(_)) && !matches!(name, "X" | "Z") {
            self.error(
                codes::SINR_UNSUPPORTED,
                line,
                w.range.clone(),
                format!(
                    "`{}`: AC(…) and IC(…) are read on X and Z only",
                    &line.text[w.range.clone()]
                ),
                "write the value as a number (an arc's I and K are increments from its start, as radius values)",
            );
            return false;
        }
        words.letters.push(w);
        true
    }

    fn block(&mut self, line: Line<'_>, block: &Block, span: Span) {
        // The profile's feed per minute at the start (the IR starts per revolution), before
        // the first block's items (the header lines stay the header's).
        if std::mem::take(&mut self.start_per_minute) {
            self.r
                .push(ItemKind::FeedMode(FeedMode::PerMin), span, None);
        }
        let Some(words) = self.sort(line, block) else {
            return;
        };
        for (text, at) in &words.messages {
            self.r.push(ItemKind::Comment(text.clone()), *at, None);
        }
        let Some(g) = self.g_codes(line, &words) else {
            return;
        };
        let Some(()) = self.modes(line, block, &words) else {
            return;
        };
        for (kind, at) in g.modes {
            self.r.push(kind, at, None);
        }
        let mut switches = Switches::default();
        let mut stops = Vec::new();
        let Some(()) = self.machine_words(line, &words, &mut switches, &mut stops, span) else {
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
            let Some(()) = self.motion(line, &words, block, span) else {
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

    /// The block's G codes: its motion or dwell, and the items of its modes; `None` when one
    /// is refused (reported).
    fn g_codes(&mut self, line: Line<'_>, words: &Words<'_>) -> Option<GCodes> {
        let mut g_codes = GCodes::default();
        for &(g, w) in &words.g {
            let at = self.span(line, w.range.clone());
            let range = w.range.clone();
            let new_motion = match g {
                0 => Some(Motion::Rapid),
                1 => Some(Motion::Feed),
                2 => Some(Motion::Arc { clockwise: true }),
                3 => Some(Motion::Arc { clockwise: false }),
                33 => Some(Motion::Thread),
                _ => None,
            };
            if new_motion.is_some() || g == 4 {
                if g_codes.motion.is_some() || g_codes.dwell {
                    self.error(
                        codes::SINR_CONFLICT,
                        line,
                        range,
                        format!("`G{g}` beside another motion or G4 in one block"),
                        "give one motion per block; G4 F… stands in a block of its own",
                    );
                    return None;
                }
                g_codes.motion = new_motion;
                g_codes.dwell = g == 4;
                continue;
            }
            let mode = match g {
                // The feed's kind and the spindle's mode (one G group): `modes`.
                18 | 90 | 91 | 70 | 71 | 700 | 710 | 94 | 95 | 96 | 97 | 961 | 971 => None,
                40 => Some(ItemKind::Compensation(Compensation::Off)),
                54..=57 => Some(ItemKind::WorkOffset((g - 53) as u8)),
                _ => {
                    self.error(
                        codes::SINR_UNSUPPORTED,
                        line,
                        range,
                        format!("`G{g}`: {}", refused_g(g)),
                        "convert this part by hand, or remove it from the source",
                    );
                    return None;
                }
            };
            g_codes.modes.extend(mode.map(|m| (m, at)));
        }
        Some(g_codes)
    }

    /// The block's modes for the whole block first: G90/G91, the units (G70/G71 lengths,
    /// G700/G710 lengths and feeds), DIAMON/DIAMOF, and the feed's kind, which G94/G95 and
    /// the spindle's modes G96/G97 (per revolution) and G961/G971 (per minute) say: one G
    /// group, one of them per block.
    fn modes(&mut self, line: Line<'_>, block: &Block, words: &Words<'_>) -> Option<()> {
        let one_of = |group: &[u32]| -> Vec<u32> {
            words
                .g
                .iter()
                .map(|(g, _)| *g)
                .filter(|g| group.contains(g))
                .collect()
        };
        let feed_kind = one_of(&[94, 95, 96, 97, 961, 971]);
        for group in [
            one_of(&[90, 91]),
            one_of(&[70, 71, 700, 710]),
            feed_kind.clone(),
        ] {
            if let [a, b, ..] = group[..] {
                self.error(
                    codes::SINR_CONFLICT,
                    line,
                    block.code_range.clone(),
                    format!("G{a} and G{b} in one block: one G group"),
                    "give one of them",
                );
                return None;
            }
        }
        if words.has_g(90) || words.has_g(91) {
            self.absolute = words.has_g(90);
        }
        if let [g] = one_of(&[70, 71, 700, 710])[..] {
            self.inch = matches!(g, 70 | 700);
            self.inch_feed = g == 700;
        }
        if let Some((on, _)) = words.diam {
            self.diameter = Some(on);
        }
        let Some(&g) = feed_kind.first() else {
            return Some(());
        };
        if self.surface && matches!(g, 94 | 95) {
            self.error(
                codes::SINR_UNSUPPORTED,
                line,
                block.code_range.clone(),
                format!("G{g} under G96: it ends the surface speed (one G group) at a spindle speed the program does not say"),
                "write G97 S… first, or G961/G96 to change the feed's kind under the surface speed",
            );
            return None;
        }
        let per_rev = matches!(g, 95..=97);
        if self.per_rev != Some(per_rev) || matches!(g, 94 | 95) {
            // What F holds across a change of kind is not stated by the sources: the feed is
            // given again (the writer does).
            if self.per_rev != Some(per_rev) {
                self.f = None;
            }
            self.per_rev = Some(per_rev);
            let at = words
                .g
                .iter()
                .find(|(c, _)| *c == g)
                .map_or(Span::default(), |(_, w)| self.span(line, w.range.clone()));
            let mode = if per_rev {
                FeedMode::PerRev
            } else {
                FeedMode::PerMin
            };
            self.r.push(ItemKind::FeedMode(mode), at, None);
        }
        Some(())
    }

    /// T, D, S, LIMS and the M codes into `switches` (and the tool item).
    fn machine_words(
        &mut self,
        line: Line<'_>,
        words: &Words<'_>,
        switches: &mut Switches,
        stops: &mut Vec<(bool, Span)>,
        span: Span,
    ) -> Option<()> {
        // One of each function per block: the spindle (M3, M4, M5) and the coolant (M8, M9).
        for group in [[3, 4, 5].as_slice(), &[8, 9]] {
            let mut found = words.m.iter().filter(|(m, _)| group.contains(m));
            if let (Some((a, _)), Some((b, w))) = (found.next(), found.next()) {
                self.error(
                    codes::SINR_CONFLICT,
                    line,
                    w.range.clone(),
                    format!("M{b} beside M{a} in one block: one of them"),
                    "write each spindle and coolant command in a block of its own",
                );
                return None;
            }
        }
        for &(m, w) in &words.m {
            let at = self.span(line, w.range.clone());
            match m {
                3 | 4 => {
                    let direction = if m == 3 {
                        SpindleDirection::Clockwise
                    } else {
                        SpindleDirection::CounterClockwise
                    };
                    switches.spindle = Some((None, Some(direction), at));
                    self.turning = true;
                }
                5 => {
                    switches.spindle_stop = Some(at);
                    self.turning = false;
                }
                8 => switches.coolant.push((Coolant::Flood, at)),
                9 => switches.coolant.push((Coolant::Off, at)),
                0 | 1 => stops.push((m == 1, at)),
                2 | 17 => switches.end = Some((EndCode::M2, at)),
                30 => switches.end = Some((EndCode::M30, at)),
                _ => {
                    self.error(
                        codes::SINR_UNSUPPORTED,
                        line,
                        w.range.clone(),
                        format!("`M{m}`: not an M code ncthread reads in a SINUMERIK program (M6, M7, gear stages and the machine builder's codes are the machine's)"),
                        "convert this part by hand, or remove it from the source",
                    );
                    return None;
                }
            }
        }
        let (t, d) = (words.get("T"), words.get("D"));
        if t.is_some() || d.is_some() {
            let number = match t {
                Some(w) => Some(self.whole(line, w, "a tool number")?),
                None => None,
            };
            let edge = match d {
                Some(w) => Some((self.whole(line, w, "a cutting edge (D) number")?, w)),
                None => None,
            };
            let offset = self.cutting_edge(line, number, edge)?;
            self.tool = number.or(self.tool);
            self.r.push(ItemKind::Tool { number, offset }, span, None);
        }
        self.spindle_words(line, words, switches, span)
    }

    /// The offset a T/D pair selects: D is a cutting edge of the tool (the SINUMERIK 808D
    /// manual: "If a D word is not written, D1 is automatically effective. If D0 is
    /// programmed, the offsets for the tool are ineffective"), so D1 (or none, after T) is
    /// the tool's own offset and D0 none; another edge has no equivalent in the IR's offsets.
    fn cutting_edge(
        &mut self,
        line: Line<'_>,
        number: Option<u32>,
        edge: Option<(u32, &Word)>,
    ) -> Option<Option<u32>> {
        let tool = number.or(self.tool);
        match (edge, tool) {
            (None, _) => Some(number),
            (Some((0, _)), _) => Some(Some(0)),
            (Some((1, _)), Some(t)) => Some(Some(t)),
            (Some((d, w)), _) => {
                let message = match tool {
                    Some(t) => format!(
                        "`D{d}`: cutting edge {d} of tool {t}; ncthread reads a tool's first edge (D1) and D0 (offsets off), as other controls' offsets hold one edge per tool"
                    ),
                    None => {
                        format!("`D{d}` before any tool: its cutting edge is of the tool in use")
                    }
                };
                self.error(
                    codes::SINR_UNSUPPORTED,
                    line,
                    w.range.clone(),
                    message,
                    "program each edge as a tool of its own (T with D1) in the source",
                );
                None
            }
        }
    }

    fn spindle_words(
        &mut self,
        line: Line<'_>,
        words: &Words<'_>,
        switches: &mut Switches,
        span: Span,
    ) -> Option<()> {
        let whole = 0..line.text.len();
        let surface = words.has_g(96) || words.has_g(961);
        let rpm = words.has_g(97) || words.has_g(971);
        let lims = match words.get("LIMS") {
            Some(w) if surface => Some(self.limit_word(line, w)?),
            Some(w) => {
                self.error(
                    codes::SINR_UNSUPPORTED,
                    line,
                    w.range.clone(),
                    "LIMS without G96 in its block is not read",
                    "write the limit beside G96: `G96 S200 LIMS=3000`",
                );
                return None;
            }
            None => None,
        };
        let s = match words.get("S") {
            Some(w) => Some((self.whole(line, w, "a spindle speed")?, w)),
            None => None,
        };
        if surface {
            self.surface_speed(line, s.map(|(v, _)| v), lims, switches, span)?;
        } else if rpm {
            if s.is_none() && self.surface && self.turning {
                self.error(
                    codes::SINR_MODE_UNKNOWN,
                    line,
                    whole,
                    "G97 without S while the spindle turns under G96: the control keeps the rpm it turns at, which depends on the diameter",
                    "write the speed with G97: `G97 S800`",
                );
                return None;
            }
            switches.spindle_mode = Some((SpindleMode::Rpm, span));
            self.surface = false;
        }
        if let Some((v, w)) = s {
            if self.surface {
                self.cutting = Some(v);
            } else if let Some(l) = self.lims.filter(|l| v > *l) {
                self.error(
                    codes::SINR_UNSUPPORTED,
                    line,
                    w.range.clone(),
                    format!("S{v} above LIMS={l}: LIMS limits G97 too, so the spindle would turn at {l} rpm"),
                    "lower the speed to the limit, or raise LIMS with a G96 block",
                );
                return None;
            }
            let direction = switches.spindle.and_then(|(_, d, _)| d);
            let at = self.span(line, w.range.clone());
            switches.spindle = Some((Some(v), direction, at));
        }
        Some(())
    }

    /// G96 (or G961): the surface speed S, else the last one; the LIMS given, else the one
    /// in force.
    fn surface_speed(
        &mut self,
        line: Line<'_>,
        s: Option<u32>,
        lims: Option<u32>,
        switches: &mut Switches,
        span: Span,
    ) -> Option<()> {
        let whole = 0..line.text.len();
        // A G96 without S takes the last surface speed again, never an rpm.
        let speed = match (s, self.cutting) {
            (Some(v), _) | (None, Some(v)) => v,
            (None, None) => {
                self.error(
                    codes::SINR_MODE_UNKNOWN,
                    line,
                    whole,
                    "G96 without S before any surface speed",
                    "write the surface speed with G96: `G96 S200 LIMS=3000`",
                );
                return None;
            }
        };
        if let Some(l) = lims {
            self.lims = Some(l);
        }
        let limit = self.lims.and_then(|l| Decimal::parse(&l.to_string()));
        switches.spindle_mode = Some((
            SpindleMode::SurfaceSpeed {
                limit,
                feet: self.inch,
            },
            span,
        ));
        let direction = switches.spindle.and_then(|(_, d, _)| d);
        switches.spindle = Some((Some(speed), direction, span));
        self.surface = true;
        self.cutting = Some(speed);
        Some(())
    }

    /// LIMS: a whole number of rpm, from 1.
    fn limit_word(&mut self, line: Line<'_>, w: &Word) -> Option<u32> {
        match w
            .plain()
            .and_then(|d| d.to_whole().ok())
            .and_then(|n| u32::try_from(n).ok())
        {
            Some(n) if n > 0 => Some(n),
            _ => {
                self.error(
                    codes::SINR_NUMBER,
                    line,
                    w.range.clone(),
                    "LIMS is a whole number of rpm, from 1",
                    "write the limit in whole rpm",
                );
                None
            }
        }
    }

    /// A whole number of at most 9 digits (S, T, D).
    fn whole(&mut self, line: Line<'_>, w: &Word, what: &str) -> Option<u32> {
        match w
            .plain()
            .and_then(|d| d.to_whole().ok())
            .and_then(|n| u32::try_from(n).ok())
            .filter(|n| *n < 1_000_000_000)
        {
            Some(n) => Some(n),
            None => {
                self.error(
                    codes::SINR_NUMBER,
                    line,
                    w.range.clone(),
                    format!(
                        "`{}`: {what} is a whole number from 0",
                        &line.text[w.range.clone()]
                    ),
                    "write it without a fraction",
                );
                None
            }
        }
    }

    /// A statement that moves nothing: its warning, once per program.
    fn no_motion(&mut self, line: Line<'_>, w: &Word, what: &str) {
        if !self.warned_no_motion.contains(&w.name) {
            self.warned_no_motion.push(w.name.clone());
            let span = self.span(line, w.range.clone());
            self.r.diags.push(
                Diagnostic::new(codes::SINR_NO_MOTION, what.to_string())
                    .at(self.r.src, span)
                    .help("it moves nothing; check the converted program where the operator relies on it"),
            );
        }
    }

    /// `G4 F<seconds>`.
    fn dwell(&mut self, line: Line<'_>, words: &Words<'_>, span: Span) -> Option<()> {
        if let Some(w) = words.letters.iter().find(|w| w.name != "F") {
            self.error(
                codes::SINR_CONFLICT,
                line,
                w.range.clone(),
                format!(
                    "`{}` beside G4: the dwell is G4 F<seconds> in a block of its own",
                    &line.text[w.range.clone()]
                ),
                "write the dwell in seconds, `G4 F2.5`, in a block of its own",
            );
            return None;
        }
        let Some(f) = words.get("F") else {
            self.error(
                codes::SINR_CONFLICT,
                line,
                0..line.text.len(),
                "G4 without F: the dwell's time in seconds",
                "write `G4 F2.5`",
            );
            return None;
        };
        let seconds = f.plain().filter(|d| !d.is_negative());
        let Some(seconds) = seconds.filter(|d| d.to_scaled(3).is_ok()) else {
            self.error(
                codes::SINR_NUMBER,
                line,
                f.range.clone(),
                "a dwell is from 0 s, to 0.001 s",
                "write the dwell in seconds with at most 3 decimals",
            );
            return None;
        };
        // G4's F is the dwell's alone: the feed stays (siemens.md).
        self.r.push(ItemKind::Dwell { seconds }, span, None);
        Some(())
    }
}

impl FrontEnd<'_> {
    /// A length word in the program's unit: mm to 0.0001, inches to 0.0001 in.
    fn length_of(&mut self, line: Line<'_>, w: &Word, d: Decimal) -> Option<Length> {
        self.r.saw_length(self.inch);
        let value = if self.inch {
            let den = 10i128.checked_pow(d.scale);
            let num = d.mantissa.checked_mul(Length::PER_INCH as i128);
            match (num, den) {
                (Some(n), Some(den)) if n % den == 0 && (n / den).abs() < 1 << 55 => {
                    Some(Length((n / den) as i64))
                }
                _ => None,
            }
        } else {
            d.to_length().ok().filter(|l| l.0.abs() < 1 << 55)
        };
        if value.is_none() {
            let unit = if self.inch { "0.0001 in" } else { "0.0001 mm" };
            self.error(
                codes::SINR_NUMBER,
                line,
                w.range.clone(),
                format!(
                    "`{}` is too large or finer than {unit}",
                    &line.text[w.range.clone()]
                ),
                "write the value with at most 4 decimals",
            );
        }
        value
    }

    /// The lead K in the program's unit, exactly.
    fn lead_of(&mut self, line: Line<'_>, w: &Word) -> Option<Lead> {
        let d = w.plain()?;
        let lead = if self.inch {
            let per = 254i128 * 10i128.pow(11);
            let den = 10i128.checked_pow(d.scale)?;
            d.mantissa
                .checked_mul(per)
                .filter(|n| n % den == 0)
                .map(|n| n / den)
                .and_then(|v| i64::try_from(v).ok())
                .map(Lead)
        } else {
            d.to_lead().ok()
        };
        match lead.filter(|l| l.0 > 0 && *l <= Lead::MAX) {
            Some(l) => Some(l),
            None => {
                self.error(
                    codes::SINR_NUMBER,
                    line,
                    w.range.clone(),
                    format!(
                        "`{}`: a lead is positive, at most 12 decimals of a mm",
                        &line.text[w.range.clone()]
                    ),
                    "write the thread's lead along Z, `K1.5`",
                );
                None
            }
        }
    }

    /// Where the block's X and Z words go: `None` when refused (reported); the axes not
    /// written stay as they are.
    fn target(&mut self, line: Line<'_>, words: &Words<'_>) -> Option<Pos> {
        let mut to = Pos::UNKNOWN;
        for name in ["X", "Z"] {
            let Some(w) = words.get(name) else { continue };
            let (d, absolute) = match w.value {
                Value::Plain(d) => (d, self.absolute),
                Value::Absolute(d) => (d, true),
                Value::Incremental(d) => (d, false),
                _ => continue,
            };
            let mut v = self.length_of(line, w, d)?;
            let current = if name == "X" {
                self.r.pos.x
            } else {
                self.r.pos.z
            };
            if name == "X" {
                match self.diameter {
                    Some(true) => {}
                    Some(false) => v = v + v,
                    None => {
                        self.mode_unknown(
                            "diameter",
                            line,
                            w.range.clone(),
                            "X before DIAMON or DIAMOF: whether X is a diameter is the machine's setting until the program says",
                            "write DIAMON (X a diameter) or DIAMOF at the program's start, or give the machine's reset state in the profile: `initial_diameter = \"DIAMON\"` (or \"DIAMOF\") in [siemens]",
                        );
                        return None;
                    }
                }
            }
            let value = if absolute {
                v
            } else {
                match current {
                    Some(c) => c + v,
                    None => {
                        self.error(
                            codes::SINR_UNKNOWN_POSITION,
                            line,
                            w.range.clone(),
                            format!("an incremental {name} from a position that is not known yet"),
                            "move to an absolute X and Z first",
                        );
                        return None;
                    }
                }
            };
            if name == "X" {
                to.x = Some(value);
            } else {
                to.z = Some(value);
            }
        }
        Some(to)
    }

    /// The block's motion (or none: a block of modes, a feed alone).
    fn motion(
        &mut self,
        line: Line<'_>,
        words: &Words<'_>,
        block: &Block,
        span: Span,
    ) -> Option<()> {
        let axes = words.get("X").is_some() || words.get("Z").is_some();
        let motion = self.motion;
        self.words_of_motion(line, words, motion, axes)?;
        if let Some(w) = words.get("F") {
            let feed = self.feed(line, w)?;
            self.f = Some(feed);
            if !axes || motion == Some(Motion::Thread) || motion == Some(Motion::Rapid) {
                self.r.push(ItemKind::FeedRate(feed), span, None);
            }
        }
        if !axes {
            return Some(());
        }
        let Some(motion) = motion else {
            self.mode_unknown(
                "motion",
                line,
                block.code_range.clone(),
                "an axis move before any G0, G1, G2, G3 or G33: the motion in force is the machine's setting",
                "write the motion (`G0 X… Z…`)",
            );
            return None;
        };
        let from = self.r.pos;
        // The axes written (a move keeps them so), and where the tool ends.
        let written = self.target(line, words)?;
        let to = Pos {
            x: written.x.or(from.x),
            z: written.z.or(from.z),
        };
        match motion {
            Motion::Rapid => {
                self.r.push(ItemKind::Rapid { to: written }, span, None);
            }
            Motion::Feed => {
                let feed = self.feed_in_force(line, block)?;
                self.r
                    .push(ItemKind::Feed { to: written, feed }, span, None);
            }
            Motion::Arc { clockwise } => {
                let feed = self.feed_in_force(line, block)?;
                let (to, centre) = self.arc(line, words, from, to, clockwise, block)?;
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
        self.r.pos = to;
        Some(())
    }

    /// SF, K, I and CR belong to a G33, G2 or G3 block that moves: elsewhere refused.
    fn words_of_motion(
        &mut self,
        line: Line<'_>,
        words: &Words<'_>,
        motion: Option<Motion>,
        axes: bool,
    ) -> Option<()> {
        let allowed: &[&str] = match motion {
            Some(Motion::Thread) if axes => &["SF", "K", "I"],
            Some(Motion::Arc { .. }) if axes => &["I", "K", "CR"],
            _ => &[],
        };
        if let Some(w) = ["SF", "K", "I", "CR"]
            .iter()
            .filter(|n| !allowed.contains(n))
            .find_map(|n| words.get(n))
        {
            self.error(
                codes::SINR_CONFLICT,
                line,
                w.range.clone(),
                format!(
                    "`{}` in a block that cuts no thread or arc",
                    &line.text[w.range.clone()]
                ),
                "write it in the G33, G2 or G3 block it belongs to",
            );
            return None;
        }
        Some(())
    }

    fn feed(&mut self, line: Line<'_>, w: &Word) -> Option<Length> {
        let d = w.plain()?;
        let feed = if d.is_negative() {
            None
        } else {
            // G70 leaves F in the basic system (metric **\[decided\]**); G700 makes it inch.
            let inch = std::mem::replace(&mut self.inch, self.inch_feed);
            let feed = self.length_of(line, w, d);
            self.inch = inch;
            feed
        };
        if feed.is_none() && !d.is_negative() {
            return None;
        }
        if feed.is_none() {
            self.error(
                codes::SINR_NUMBER,
                line,
                w.range.clone(),
                "a feed is positive",
                "write the feed per revolution (G95) or per minute (G94)",
            );
        }
        feed
    }

    fn feed_in_force(&mut self, line: Line<'_>, block: &Block) -> Option<Length> {
        if self.per_rev.is_none() {
            self.mode_unknown(
                "feed mode",
                line,
                block.code_range.clone(),
                "a feed move before G94 or G95: whether F is per revolution or per minute is the machine's setting until the program says",
                "write G95 (mm/rev) or G94 (mm/min) at the program's start, or give the machine's reset state in the profile: `initial_feed_mode = \"G95\"` (or \"G94\") in [siemens]",
            );
            return None;
        }
        match self.f {
            Some(f) if f.0 > 0 => Some(f),
            _ => {
                self.error(
                    codes::SINR_MODE_UNKNOWN,
                    line,
                    block.code_range.clone(),
                    "a feed move without a feed: F is not set since the program's start or the last G94/G95",
                    "write F in this block",
                );
                None
            }
        }
    }

    fn arc(
        &mut self,
        line: Line<'_>,
        words: &Words<'_>,
        from: Pos,
        to: Pos,
        clockwise: bool,
        block: &Block,
    ) -> Option<(Pos, Pos)> {
        let code = if clockwise { "G2" } else { "G3" };
        let whole = block.code_range.clone();
        let (Some((sx, sz)), Some((ex, ez))) = (from.known(), to.known()) else {
            self.error(
                codes::SINR_UNKNOWN_POSITION,
                line,
                whole,
                format!("{code} from a position that is not known yet: the arc's centre cannot be placed"),
                "move to an absolute X and Z before the arc",
            );
            return None;
        };
        let (i, k, cr) = (words.get("I"), words.get("K"), words.get("CR"));
        let centre = match (cr, i.or(k)) {
            (Some(w), Some(_)) => {
                self.error(
                    codes::SINR_CONFLICT,
                    line,
                    w.range.clone(),
                    "CR= with I or K: give the centre one way",
                    "write either I and K, or CR=",
                );
                return None;
            }
            (None, None) => {
                self.error(
                    codes::SINR_ARC,
                    line,
                    whole,
                    format!("{code} without I, K or CR="),
                    "write the centre (I and K from the arc's start, radius values) or the radius CR=",
                );
                return None;
            }
            (Some(w), None) => self.radius_centre(line, w, (sx, sz), (ex, ez), clockwise)?,
            (None, Some(_)) => {
                let mut offset = |w: Option<&Word>| -> Option<Length> {
                    match w {
                        Some(w) => self.length_of(line, w, w.plain()?),
                        None => Some(Length::ZERO),
                    }
                };
                let (iv, kv) = (offset(i)?, offset(k)?);
                Pos::new(sx + iv + iv, sz + kv)
            }
        };
        let span = self.span(line, whole);
        self.r.arc_on_circle(
            codes::SINR_ARC,
            span,
            code,
            (sx, sz),
            (ex, ez),
            centre.known()?,
            "check I and K (increments from the arc's start, I a radius value)",
        )?;
        Some((to, centre))
    }

    /// The centre of an arc of radius `CR=` (negative beyond half a circle).
    fn radius_centre(
        &mut self,
        line: Line<'_>,
        w: &Word,
        (sx, sz): (Length, Length),
        (ex, ez): (Length, Length),
        clockwise: bool,
    ) -> Option<Pos> {
        let code = if clockwise { "G2" } else { "G3" };
        let r = self.length_of(line, w, w.plain()?)?;
        if r.0 == 0 || (sx, sz) == (ex, ez) {
            self.error(
                codes::SINR_ARC,
                line,
                w.range.clone(),
                format!("{code} with CR=: a zero radius, or an arc that ends where it starts"),
                "write the arc with I and K",
            );
            return None;
        }
        let span = self.span(line, w.range.clone());
        let text = &line.text[w.range.clone()];
        self.r.centre_of_radius(
            codes::SINR_ARC,
            span,
            text,
            (sx, sz),
            (ex, ez),
            r,
            clockwise,
        )
    }

    /// A G33's lead K, where the block is one ncthread reads: no I, no chain, no G96.
    fn thread_lead(
        &mut self,
        line: Line<'_>,
        words: &Words<'_>,
        whole: Range<usize>,
    ) -> Option<Lead> {
        let refuse = |fe: &mut Self, range: Range<usize>, message: &str, help: &str| {
            fe.error(codes::SINR_THREAD, line, range, message.to_string(), help);
        };
        if let Some(w) = words.get("I") {
            refuse(
                self,
                w.range.clone(),
                "G33 with I: a lead along X is not read",
                "cut the thread with Z as the long axis and its lead K",
            );
            return None;
        }
        if self.after_thread {
            refuse(
                self,
                whole,
                "a G33 block that continues the G33 before it: the chain's meaning is not in the sources ncthread holds",
                "retract between the two thread moves (G0), and start each with its own SF=",
            );
            return None;
        }
        if self.surface {
            refuse(
                self,
                whole,
                "G33 under G96: the thread's lead needs the spindle at a speed in rpm",
                "write G97 S… before the thread",
            );
            return None;
        }
        let Some(k) = words.get("K") else {
            refuse(
                self,
                whole,
                "G33 without K: the thread's lead along Z",
                "write `G33 Z… K<lead> SF=<angle>`",
            );
            return None;
        };
        self.lead_of(line, k)
    }

    /// `SF=`, the start angle every G33 block states: 0 to 359.999°.
    fn start_angle(
        &mut self,
        line: Line<'_>,
        words: &Words<'_>,
        whole: Range<usize>,
    ) -> Option<Angle> {
        let Some(sf) = words.get("SF") else {
            self.error(
                codes::SINR_MODE_UNKNOWN,
                line,
                whole,
                "G33 without SF=: the start angle is then the machine's setting",
                "write the start angle on every G33 block: `SF=0`",
            );
            return None;
        };
        let angle = sf
            .plain()
            .and_then(|d| d.to_angle().ok())
            .filter(|a| (0..360_000).contains(&a.0));
        if angle.is_none() {
            self.error(
                codes::SINR_NUMBER,
                line,
                sf.range.clone(),
                format!(
                    "`{}`: SF= is from 0 to 359.999°",
                    &line.text[sf.range.clone()]
                ),
                "write the start angle in degrees, at most 3 decimals",
            );
        }
        angle
    }

    /// `G33 X Z K SF=`: one pass that waits for the index pulse, then `SF` degrees.
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
        let refuse = |fe: &mut Self, range: Range<usize>, message: &str, help: &str| {
            fe.error(codes::SINR_THREAD, line, range, message.to_string(), help);
        };
        let lead = self.thread_lead(line, words, whole.clone())?;
        let angle = self.start_angle(line, words, whole.clone())?;
        // A thread along Z needs only its end Z; one that moves X needs its start.
        let moves_x = words.get("X").is_some() && to.x != from.x;
        if to.z.is_none() || (moves_x && from.known().is_none()) {
            self.error(
                codes::SINR_UNKNOWN_POSITION,
                line,
                whole,
                "G33 from a position that is not known yet",
                "move to the thread's start with X and Z first",
            );
            return None;
        }
        let steep = match (from.known(), to.known()) {
            (Some(a), Some(b)) => (b.0 - a.0).0.unsigned_abs() >= 2 * (b.1 - a.1).0.unsigned_abs(),
            _ => from.z == to.z,
        };
        if steep {
            refuse(
                self,
                whole,
                "this G33 moves X (as a radius) as much as Z or more: its K would be along X, which is not read",
                "cut the thread with Z as the long axis",
            );
            return None;
        }
        let pass = ThreadPass {
            to,
            lead,
            start: SyncStart::Index(Angle(angle.0)),
            infeed: None,
            entry: None,
            exit: None,
        };
        self.r.push(ItemKind::pass(pass), span, None);
        Some(())
    }
}

mod names;
#[cfg(test)]
mod tests;

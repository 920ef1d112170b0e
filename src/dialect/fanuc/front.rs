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
//! one.)

use std::ops::Range;

use super::syntax::{self, Block, Word};
use crate::diag::{Code, Diagnostic, codes};
use crate::dialect::Unsupported;
use crate::dialect::read::{Keep, Reader, UnsupportedWording};
use crate::fixed::{Angle, Decimal, Lead, Length, NumberError, div_round};
use crate::ir::{
    Chamfer, Compensation, Coolant, EndCode, FeedMode, ItemKind, ModalContext, Pos, Program,
    SpindleDirection, SpindleMode, SyncStart, ThreadPass,
};
use crate::lower;
use crate::profile::{DecimalPoint, Profile};
use crate::source::{Line, SourceFile, Span};

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

/// The G codes ncthread reads, for "did you mean".
const KNOWN_G: [&str; 24] = [
    "G00", "G01", "G02", "G03", "G04", "G18", "G20", "G21", "G32", "G40", "G41", "G42", "G50",
    "G54", "G55", "G56", "G57", "G58", "G59", "G80", "G92", "G96", "G97", "G99",
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
    profile: &'a Profile,
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
    /// Any move read yet (G20/G21 must come before).
    moved: bool,
    /// The first word read without a decimal point.
    no_point: Option<(Span, String)>,
    /// The first inch value rounded onto the 0.0001 mm grid.
    inch_rounded: Option<Span>,
}

/// Reads a FANUC program. The program holds every item that could be read; it is usable
/// only when no diagnostic is an error.
pub fn parse(
    src: &SourceFile,
    profile: &Profile,
    unsupported: Unsupported,
) -> (Program, Vec<Diagnostic>) {
    read(src, profile, unsupported, Keep::Program)
}

/// [`parse`], keeping the program or only the diagnostics.
pub(crate) fn read(
    src: &SourceFile,
    profile: &Profile,
    unsupported: Unsupported,
    keep: Keep,
) -> (Program, Vec<Diagnostic>) {
    let mut fe = FrontEnd {
        r: Reader::new(src, super::ID, keep),
        profile,
        unsupported,
        motion: Motion::Rapid,
        inch: false,
        per_minute: false,
        surface_speed: false,
        limit: None,
        f: None,
        sync_end: None,
        blocks_since_sync: 0,
        cycle: None,
        chamfer_refused: false,
        moved: false,
        no_point: None,
        inch_rounded: None,
    };
    let mut ended = false;
    let mut percents = 0;
    for line in src.lines() {
        // Nothing looks back past the line being read.
        fe.r.items.line_read();
        if line.text.trim().is_empty() {
            continue;
        }
        match syntax::parse_line(line.text) {
            Ok(block) if block.delimiter => {
                percents += 1;
                if percents >= 2 {
                    ended = true;
                }
            }
            Ok(block) if ended && !block.is_empty() => fe.r.after_end(
                codes::FANR_AFTER_END,
                src.line_span(line),
                "this block comes after the program's end (M02/M30 or the closing %); the control does not run it, and neither does ncthread",
                "remove it, or move the program's end after it",
            ),
            // A comment after the end stays a comment (the writers keep it).
            Ok(block) if ended => fe.block(line, &block),
            Ok(block) => {
                let first = fe.r.items.len();
                fe.block(line, &block);
                ended |= fe.r.ends_program(first);
            }
            Err(e) => {
                let code = if e.number_too_large {
                    codes::FANR_NUMBER
                } else {
                    codes::FANR_SYNTAX
                };
                fe.r.syntax_error(code, line, e.offset, e.message, e.help);
            }
        }
    }
    if let Some((span, word)) = fe.no_point.take() {
        let (message, help) = match profile.fanuc.decimal_point {
            DecimalPoint::Increment => (
                format!(
                    "`{word}` and other words without a decimal point are read in least input increments (0.001 mm), the profile's `decimal_point = \"increment\"` (FANUC parameter 3401#0 = 0)"
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
        fe.r.diags.push(
            Diagnostic::new(codes::FANR_DECIMAL_POINT, message)
                .at(src, span)
                .help(help),
        );
    }
    if let Some(span) = fe.inch_rounded.take() {
        fe.r.diags.push(
            Diagnostic::new(
                codes::FANR_INCH_ROUNDED,
                "inch values are rounded onto ncthread's 0.0001 mm grid (this is the first)",
            )
            .at(src, span)
            .help("0.0001 in is 0.00254 mm: each value moves by at most 0.00005 mm"),
        );
    }
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

    fn number_error(&mut self, line: Line<'_>, word: &Word, e: NumberError, grid: &str) {
        let text = &line.text[word.range.clone()];
        let message = match e {
            NumberError::TooPrecise { .. } => {
                format!("`{text}` is finer than the control's {grid}")
            }
            NumberError::TooLarge => format!("`{text}` is too large"),
        };
        self.error(
            codes::FANR_NUMBER,
            line,
            word.range.clone(),
            message,
            "write the value the control takes (3 decimals for lengths in mm, 4 for leads and feeds)",
        );
    }

    /// A whole number without a decimal point (G, M, S, T, P, Q).
    fn whole(&mut self, line: Line<'_>, word: &Word) -> Option<i64> {
        let text = &line.text[word.range.clone()];
        if word.value.has_point {
            self.error(
                codes::FANR_NUMBER,
                line,
                word.range.clone(),
                format!(
                    "`{text}`: {} takes a whole number without a decimal point",
                    word.letter
                ),
                "write it without the point",
            );
            return None;
        }
        match word.value.to_whole() {
            Ok(v) => Some(v),
            Err(e) => {
                self.number_error(line, word, e, "whole number");
                None
            }
        }
    }

    /// Notes the first word read without a decimal point.
    fn note_no_point(&mut self, line: Line<'_>, word: &Word) {
        if self.no_point.is_none() {
            let span = self.span(line, word.range.clone());
            self.no_point = Some((span, line.text[word.range.clone()].to_string()));
        }
    }

    /// The value of a word in mm (the point rule and inches applied), as a decimal number
    /// of mm with at most `decimals` decimals, or `None` after a diagnostic.
    fn mm_value(&mut self, line: Line<'_>, word: &Word, unit: Unit) -> Option<Decimal> {
        let mut value = word.value;
        if !value.has_point && self.profile.fanuc.decimal_point == DecimalPoint::Increment {
            let scale = match (unit, self.inch) {
                (Unit::Axis, false) => 3,
                (Unit::Axis, true) => 4,
                _ => {
                    let text = &line.text[word.range.clone()];
                    let what = match unit {
                        Unit::Lead => "a lead F",
                        Unit::Seconds => "a dwell time",
                        _ => "a feed",
                    };
                    self.error(
                        codes::FANR_NUMBER,
                        line,
                        word.range.clone(),
                        format!("`{text}` has no decimal point, and the unit of {what} without one is not settled by any source ncthread holds"),
                        "write the value with a decimal point (`F0.2`, `G04 U1.5`, or `G04 P1500` in milliseconds)",
                    );
                    return None;
                }
            };
            value = Decimal {
                mantissa: value.mantissa,
                scale,
                has_point: true,
            };
            self.note_no_point(line, word);
        } else if !value.has_point {
            self.note_no_point(line, word);
        }
        Some(value)
    }

    /// A length word (X Z U W I K R, a feed) on the 0.0001 mm grid, from mm or inches.
    fn length(&mut self, line: Line<'_>, word: &Word, unit: Unit) -> Option<Length> {
        let value = self.mm_value(line, word, unit)?;
        if self.inch {
            // mm = in · 25.4: in 0.0001 mm units, mantissa · 254000 / 10^scale.
            let den = 10i128.checked_pow(value.scale)?;
            let Some(num) = value.mantissa.checked_mul(254_000) else {
                self.number_error(line, word, NumberError::TooLarge, "");
                return None;
            };
            let units = div_round(num, den);
            if units.abs() > 1 << 50 {
                self.number_error(line, word, NumberError::TooLarge, "");
                return None;
            }
            if num % den != 0 && self.inch_rounded.is_none() {
                self.inch_rounded = Some(self.span(line, word.range.clone()));
            }
            return Some(Length(units as i64));
        }
        let grid = if unit == Unit::Axis { 3 } else { 4 };
        match value.to_scaled(grid) {
            Ok(v) => value
                .to_length()
                .ok()
                .or(Some(Length(v * 10i64.pow(4 - grid)))),
            Err(e) => {
                let g = if grid == 3 { "0.001 mm" } else { "0.0001 mm" };
                self.number_error(line, word, e, g);
                None
            }
        }
    }

    /// A lead (F in G32/G92), exact.
    fn lead(&mut self, line: Line<'_>, word: &Word) -> Option<Lead> {
        let value = self.mm_value(line, word, Unit::Lead)?;
        let lead = if self.inch {
            // 25.4 · value, exactly on the 10⁻¹² mm grid for up to 10 decimals.
            value.mantissa.checked_mul(254).and_then(|m| {
                Decimal {
                    mantissa: m,
                    scale: value.scale + 1,
                    has_point: true,
                }
                .to_lead()
                .ok()
            })
        } else {
            match value.to_scaled(4) {
                Ok(_) => value.to_lead().ok(),
                Err(e) => {
                    self.number_error(line, word, e, "0.0001 mm");
                    return None;
                }
            }
        };
        match lead {
            Some(l) if l.0 > 0 => Some(l),
            _ => {
                let text = &line.text[word.range.clone()];
                self.error(
                    codes::FANR_NUMBER,
                    line,
                    word.range.clone(),
                    format!("`{text}` is not a lead the control can cut"),
                    "a lead is positive and has at most 4 decimals in mm",
                );
                None
            }
        }
    }

    fn block(&mut self, line: Line<'_>, block: &Block) {
        let first = self.r.items.len();
        let code_span = self.span(line, block.code_range.clone());
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
        let thread = block
            .words
            .iter()
            .any(|w| w.letter == 'G' && matches!(w.value.to_whole(), Ok(32 | 92)));
        if self.r.unsupported(&UNSUPPORTED, found, keep, thread) {
            self.keep(line, block, &[]);
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
        let code = line.text[block.code_range.clone()].trim().to_string();
        let code = match block.number {
            Some(_) => code
                .trim_start_matches(['N', 'n'])
                .trim_start()
                .trim_start_matches(|c: char| c.is_ascii_digit())
                .trim_start()
                .to_string(),
            None => code,
        };
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
            },
        );
        self.sync_end = None;
        self.moved = true;
    }

    fn read_block(&mut self, line: Line<'_>, block: &Block, code_span: Span) -> Option<()> {
        // Sort the words.
        let mut unsupported: Vec<(Span, String)> = Vec::new();
        let mut g_motion: Option<(Motion, &Word)> = None;
        let mut g_dwell: Option<&Word> = None;
        let mut g50: Option<&Word> = None;
        let mut units: Option<(bool, &Word)> = None;
        let mut feed_mode: Option<(bool, &Word)> = None;
        let mut speed_mode: Option<(bool, &Word)> = None;
        let mut comp: Option<(Compensation, &Word)> = None;
        let mut offset: Option<(u8, &Word)> = None;
        let mut m_codes: Vec<(i64, &Word)> = Vec::new();
        let mut letters: Vec<&Word> = Vec::new();
        let mut state: Vec<&Word> = Vec::new();
        let mut conflict: Option<&Word> = None;
        let mut modal_unsupported: Option<&Word> = None;
        let mut refused_by_name = false;
        for w in &block.words {
            let text = &line.text[w.range.clone()];
            match w.letter {
                'G' => {
                    let Ok(g) = w.value.to_scaled(1) else {
                        unsupported.push((self.span(line, w.range.clone()), format!("`{text}` is not a G code")));
                        continue;
                    };
                    if g % 10 != 0 {
                        unsupported.push((self.span(line, w.range.clone()), format!("`{text}` is not a G code ncthread reads")));
                        continue;
                    }
                    let g = g / 10;
                    match g {
                        0 => set(w, &mut g_motion, Motion::Rapid, &mut conflict),
                        1 => set(w, &mut g_motion, Motion::Feed, &mut conflict),
                        2 => set(w, &mut g_motion, Motion::Arc(true), &mut conflict),
                        3 => set(w, &mut g_motion, Motion::Arc(false), &mut conflict),
                        32 => set(w, &mut g_motion, Motion::Thread, &mut conflict),
                        92 => set(w, &mut g_motion, Motion::Cycle, &mut conflict),
                        4 => g_dwell = Some(w),
                        50 => g50 = Some(w),
                        20 => set(w, &mut units, true, &mut conflict),
                        21 => set(w, &mut units, false, &mut conflict),
                        98 => set(w, &mut feed_mode, true, &mut conflict),
                        99 => set(w, &mut feed_mode, false, &mut conflict),
                        96 => set(w, &mut speed_mode, true, &mut conflict),
                        97 => set(w, &mut speed_mode, false, &mut conflict),
                        40 => set(w, &mut comp, Compensation::Off, &mut conflict),
                        41 | 42 => set(
                            w,
                            &mut comp,
                            Compensation::FromTool {
                                right: g == 42,
                                tool: None,
                            },
                            &mut conflict,
                        ),
                        54..=59 => set(w, &mut offset, (g - 53) as u8, &mut conflict),
                        // The ZX plane is a lathe's only one; G80 cancels drilling cycles,
                        // which ncthread never reads.
                        18 | 80 => {}
                        76 => {
                            refused_by_name = true;
                            self.error(
                                codes::FANR_G76,
                                line,
                                w.range.clone(),
                                format!("`{text}`: the G76 threading cycle is not read"),
                                "its pass placement (and the two-block form's P, Q, R words) is not documented in any source ncthread holds, and its chamfer is a machine parameter: write the passes as G32 blocks (ncthread writes every thread that way)",
                            );
                        }
                        _ => {
                            // A cycle code is modal: the blocks after it would repeat it.
                            if matches!(g, 90 | 94 | 83..=89) {
                                modal_unsupported.get_or_insert(w);
                            }
                            let what = match g {
                                90 => "the G90 turning cycle (system A) is not read yet".to_string(),
                                94 => "the G94 facing cycle (system A) is not read yet".to_string(),
                                70..=75 => format!("the G{g} multiple repetitive cycle is not read"),
                                28 | 30 => format!("G{g} (return to the machine's reference point) is not read: the reference point is the machine's, not the program's, and LinuxCNC's G{g} goes to another place"),
                                53 => "G53 (machine coordinates) is not read".to_string(),
                                83..=89 => format!("the G{g} drilling or tapping cycle is not read"),
                                17 | 19 => format!("G{g} selects a plane other than ZX: not a lathe program"),
                                _ => format!("`{text}` is not supported{}", crate::dialect::read::did_you_mean(&format!("G{g:02}"), &KNOWN_G)),
                            };
                            unsupported.push((self.span(line, w.range.clone()), format!("`{text}`: {what}")));
                        }
                    }
                }
                'M' => match self.whole(line, w) {
                    Some(m @ (0 | 1 | 2 | 30 | 3 | 4 | 5 | 8 | 9)) => m_codes.push((m, w)),
                    Some(7) if self.profile.fanuc.mist => m_codes.push((7, w)),
                    Some(7) => unsupported.push((self.span(line, w.range.clone()), format!("`{text}`: mist coolant is not supported (set `mist = true` in the profile's [fanuc] section if the machine has it)"))),
                    Some(29) => unsupported.push((self.span(line, w.range.clone()), format!("`{text}`: rigid tapping (M29) is not read"))),
                    Some(_) => unsupported.push((self.span(line, w.range.clone()), format!("`{text}` is not supported: M codes other than M00–M05, M08, M09 and M30 are the machine builder's"))),
                    None => return None,
                },
                'X' | 'Z' | 'U' | 'W' | 'I' | 'K' | 'R' | 'F' | 'S' | 'T' | 'P' | 'Q' | 'O' => {
                    if letters.iter().any(|o| o.letter == w.letter) {
                        conflict.get_or_insert(w);
                    }
                    letters.push(w);
                }
                'E' => unsupported.push((self.span(line, w.range.clone()), format!("`{text}`: E (a lead in threads per inch) is not read"))),
                c => unsupported.push((self.span(line, w.range.clone()), format!("`{text}`: address {c} is not supported"))),
            }
        }
        if refused_by_name {
            return None;
        }
        if let Some(w) = conflict {
            let text = &line.text[w.range.clone()];
            self.error(
                codes::FANR_CONFLICT,
                line,
                w.range.clone(),
                format!("`{text}` repeats a word or a code of the same group in this block"),
                "write each word once, and one code of each group (motion, units, feed mode…)",
            );
            return None;
        }
        // M codes of one function that contradict each other: which wins is the machine
        // builder's ladder.
        let has = |m: i64| m_codes.iter().find(|(c, _)| *c == m).map(|(_, w)| *w);
        for (a, b) in [(3, 4), (3, 5), (4, 5), (8, 9), (7, 9)] {
            if let (Some(_), Some(w)) = (has(a), has(b)) {
                let text = &line.text[w.range.clone()];
                self.error(
                    codes::FANR_CONFLICT,
                    line,
                    w.range.clone(),
                    format!("`{text}` contradicts M{a:02} in the same block"),
                    "write each spindle or coolant command in a block of its own",
                );
                return None;
            }
        }
        let get = |c: char| letters.iter().copied().find(|w| w.letter == c);
        for (a, b) in [('X', 'U'), ('Z', 'W')] {
            if let (Some(_), Some(w)) = (get(a), get(b)) {
                let text = &line.text[w.range.clone()];
                self.error(
                    codes::FANR_CONFLICT,
                    line,
                    w.range.clone(),
                    format!("`{text}`: {a} and {b} both set the same axis in this block"),
                    "write the axis once, absolute or incremental",
                );
                return None;
            }
        }
        let motion_now = g_motion.map_or(self.motion, |(m, _)| m);
        let thread = matches!(motion_now, Motion::Thread | Motion::Cycle)
            && g_dwell.is_none()
            && ["X", "Z", "U", "W"]
                .iter()
                .any(|c| get(c.chars().next().unwrap_or('X')).is_some());
        if !unsupported.is_empty() {
            let keep = self.unsupported == Unsupported::Warn;
            if self.r.unsupported(&UNSUPPORTED, unsupported, keep, thread) {
                state.extend(modal_unsupported);
                state.extend(g_motion.map(|(_, w)| w));
                state.extend(units.map(|(_, w)| w));
                state.extend(feed_mode.map(|(_, w)| w));
                state.extend(speed_mode.map(|(_, w)| w));
                state.extend(g50);
                state.extend(m_codes.iter().map(|(_, w)| *w));
                state.extend(['F', 'S', 'T'].iter().filter_map(|&c| get(c)));
                self.keep(line, block, &state);
            }
            return None;
        }
        if let Some(w) = get('O') {
            // `O0001`: the program number, on a line of its own.
            if block.words.len() > 1 {
                let text = &line.text[w.range.clone()];
                self.error(
                    codes::FANR_SYNTAX,
                    line,
                    w.range.clone(),
                    format!("`{text}`: a program number stands on a line of its own"),
                    "write `O0001 (NAME)` as the program's first line",
                );
            } else if let Some(n) = self.whole(line, w)
                && !(1..=9999).contains(&n)
            {
                let text = &line.text[w.range.clone()];
                self.error(
                    codes::FANR_NUMBER,
                    line,
                    w.range.clone(),
                    format!("`{text}` is not a program number"),
                    "program numbers are O1 to O9999",
                );
            }
            return None;
        }
        // Units first: they decide what every other number means.
        if let Some((inch, w)) = units {
            if self.moved && inch != self.inch {
                let text = &line.text[w.range.clone()];
                self.error(
                    codes::FANR_INCH,
                    line,
                    w.range.clone(),
                    format!(
                        "`{text}` after the first move: the unit must be set at the program's start"
                    ),
                    "put G20 or G21 in the program's first blocks, before any move",
                );
                return None;
            }
            self.inch = inch;
        }
        if let Some((per_minute, _)) = feed_mode {
            // A feed set in the other mode is not carried over: which number F then holds
            // (mm/min or mm/rev) no source settles.
            if per_minute != self.per_minute && matches!(self.f, Some(FRegister::Feed(_))) {
                self.f = None;
            }
            self.per_minute = per_minute;
            self.push(
                ItemKind::FeedMode(if per_minute {
                    FeedMode::PerMin
                } else {
                    FeedMode::PerRev
                }),
                code_span,
            );
        }
        // F: a lead in a G32/G92 block, else a feed.
        let mut lead: Option<Lead> = None;
        let mut feed: Option<Length> = None;
        if let Some(w) = get('F') {
            if matches!(motion_now, Motion::Thread | Motion::Cycle) && g_dwell.is_none() {
                lead = Some(self.lead(line, w)?);
                self.f = Some(FRegister::Lead(lead?));
            } else {
                let f = self.length(line, w, Unit::Feed)?;
                if f.0 <= 0 {
                    let text = &line.text[w.range.clone()];
                    self.error(
                        codes::FANR_NUMBER,
                        line,
                        w.range.clone(),
                        format!("`{text}`: a feed must be positive"),
                        "write the feed",
                    );
                    return None;
                }
                feed = Some(f);
                self.f = Some(FRegister::Feed(f));
            }
        }
        // G50: the spindle's limit (S), never a coordinate setting.
        if let Some(w50) = g50 {
            if let Some((_, w)) = speed_mode {
                let text = &line.text[w.range.clone()];
                self.error(
                    codes::FANR_CONFLICT,
                    line,
                    w.range.clone(),
                    format!("`{text}` in a G50 block: its S would be the limit, not the speed"),
                    "write `G50 S<limit>` and `G96 S<speed>` in blocks of their own",
                );
                return None;
            }
            if get('X').is_some() || get('Z').is_some() || get('U').is_some() || get('W').is_some()
            {
                let text = &line.text[w50.range.clone()];
                self.error(
                    codes::FANR_UNSUPPORTED,
                    line,
                    w50.range.clone(),
                    format!("`{text}` with X or Z sets the coordinate system from where the tool stands, which ncthread cannot know"),
                    "set the work offset on the machine (G54) and remove G50 X Z from the program; `G50 S…` alone (the spindle's limit) is read",
                );
                return None;
            }
            let Some(s) = get('S') else {
                let text = &line.text[w50.range.clone()];
                self.error(
                    codes::FANR_UNSUPPORTED,
                    line,
                    w50.range.clone(),
                    format!("`{text}` without S"),
                    "write `G50 S<rpm>`, the spindle's limit under G96",
                );
                return None;
            };
            let limit = self.whole(line, s)?;
            self.limit = Some(Decimal {
                mantissa: limit as i128,
                scale: 0,
                has_point: false,
            });
            if self.surface_speed {
                self.push(
                    ItemKind::SpindleMode(SpindleMode::SurfaceSpeed {
                        limit: self.limit,
                        feet: self.inch,
                    }),
                    code_span,
                );
            }
        }
        if let Some((surface, w)) = speed_mode
            && get('S').is_none()
            && (surface || self.surface_speed)
        {
            // What G96 or G97 keeps without S (the last G96 S? the rpm the surface speed ran
            // at?) no source ncthread holds settles.
            let text = &line.text[w.range.clone()];
            self.error(
                codes::FANR_UNSUPPORTED,
                line,
                w.range.clone(),
                format!("`{text}` without S: which speed the control keeps when the mode changes is not settled by any source ncthread holds"),
                "write the speed in the same block: `G96 S200 M03`, `G97 S800`",
            );
            return None;
        }
        if let Some((surface, w)) = speed_mode {
            if surface && self.inch {
                let text = &line.text[w.range.clone()];
                self.error(
                    codes::FANR_UNSUPPORTED,
                    line,
                    w.range.clone(),
                    format!("`{text}` in inches: a surface speed in feet per minute is not read"),
                    "program the speed in rpm (G97 S…)",
                );
                return None;
            }
            self.surface_speed = surface;
            self.push(
                ItemKind::SpindleMode(if surface {
                    SpindleMode::SurfaceSpeed {
                        limit: self.limit,
                        feet: self.inch,
                    }
                } else {
                    SpindleMode::Rpm
                }),
                code_span,
            );
        }
        if let Some(w) = get('T') {
            let n = self.whole(line, w)?;
            let (tool, off) = (n / 100, n % 100);
            if !(100..=9999).contains(&n) {
                let text = &line.text[w.range.clone()];
                self.error(
                    codes::FANR_TOOL,
                    line,
                    w.range.clone(),
                    format!("`{text}` is not a tool and offset of two digits each (tool {tool}, offset {off})"),
                    "write T followed by the tool number and the offset number, two digits each: T0101 (tool 1, offset 1), T0100 (tool 1, no offset); tools over 99 are not read",
                );
                return None;
            }
            self.push(
                ItemKind::Tool {
                    number: Some(tool as u32),
                    offset: Some(off as u32),
                },
                code_span,
            );
        }
        let speed = match get('S').filter(|_| g50.is_none()) {
            Some(w) => {
                let s = self.whole(line, w)?;
                let Ok(s) = u32::try_from(s) else {
                    let text = &line.text[w.range.clone()];
                    let why = if s < 0 {
                        "a speed is not negative"
                    } else {
                        "too large for a speed"
                    };
                    self.error(
                        codes::FANR_NUMBER,
                        line,
                        w.range.clone(),
                        format!("`{text}`: {why}"),
                        "write the speed in rpm or m/min",
                    );
                    return None;
                };
                Some(s)
            }
            None => None,
        };
        let direction = m_codes.iter().find_map(|(m, _)| match m {
            3 => Some(SpindleDirection::Clockwise),
            4 => Some(SpindleDirection::CounterClockwise),
            _ => None,
        });
        if speed.is_some() || direction.is_some() {
            self.push(ItemKind::Spindle { speed, direction }, code_span);
        }
        for (m, _) in &m_codes {
            match m {
                7 => self.push(ItemKind::Coolant(Coolant::Mist), code_span),
                8 => self.push(ItemKind::Coolant(Coolant::Flood), code_span),
                _ => {}
            }
        }
        if let Some((n, _)) = offset {
            self.push(ItemKind::WorkOffset(n), code_span);
        }
        if let Some((c, _)) = comp {
            self.push(ItemKind::Compensation(c), code_span);
        }
        if let Some(g04) = g_dwell {
            // G04 is one-shot; a motion code beside it is modal and takes effect for the
            // blocks after it (a thread or a cycle there would need the axes G04 takes).
            if let Some((m, w)) = g_motion {
                if matches!(m, Motion::Thread | Motion::Cycle) {
                    let text = &line.text[w.range.clone()];
                    self.error(
                        codes::FANR_CONFLICT,
                        line,
                        w.range.clone(),
                        format!("`{text}` in a G04 block: X and U are the dwell's time there"),
                        "write the dwell and the thread in blocks of their own",
                    );
                    return None;
                }
                self.motion = m;
                self.cycle = None;
            }
            self.dwell(line, g04, &get, code_span)?;
        } else {
            if let Some((m, _)) = g_motion {
                self.motion = m;
                if m != Motion::Cycle {
                    self.cycle = None;
                }
            }
            let moves = ['X', 'Z', 'U', 'W'].iter().any(|&c| get(c).is_some());
            if moves || g_motion.is_some_and(|(m, _)| m == Motion::Cycle) {
                self.motion_block(line, &get, lead, feed, g_motion.map(|(_, w)| w), code_span)?;
            } else if let Some(f) = feed {
                // A feed of its own, for the moves after it.
                self.push(ItemKind::FeedRate(f), code_span);
            } else if let Some(w) = ['I', 'K', 'R', 'Q', 'P'].iter().find_map(|&c| get(c)) {
                let text = &line.text[w.range.clone()];
                self.error(
                    codes::FANR_UNSUPPORTED,
                    line,
                    w.range.clone(),
                    format!("`{text}` in a block that does not move"),
                    "I, K, R and Q belong to a move (an arc, a thread); P to a dwell",
                );
                return None;
            }
        }
        for (m, _) in &m_codes {
            match m {
                5 => self.push(ItemKind::SpindleStop, code_span),
                9 => self.push(ItemKind::Coolant(Coolant::Off), code_span),
                0 => self.push(ItemKind::Stop { optional: false }, code_span),
                1 => self.push(ItemKind::Stop { optional: true }, code_span),
                _ => {}
            }
        }
        for (m, _) in &m_codes {
            match m {
                2 => self.push(ItemKind::ProgramEnd(EndCode::M2), code_span),
                30 => self.push(ItemKind::ProgramEnd(EndCode::M30), code_span),
                _ => {}
            }
        }
        Some(())
    }

    /// `G04 U1.5`, `G04 X1.5` (seconds) or `G04 P1500` (milliseconds).
    fn dwell<'w>(
        &mut self,
        line: Line<'_>,
        g04: &Word,
        get: &dyn Fn(char) -> Option<&'w Word>,
        code_span: Span,
    ) -> Option<()> {
        let time = ['U', 'X', 'P']
            .iter()
            .filter_map(|&c| get(c))
            .collect::<Vec<_>>();
        let [w] = time.as_slice() else {
            let text = &line.text[g04.range.clone()];
            self.error(
                codes::FANR_UNSUPPORTED,
                line,
                g04.range.clone(),
                format!("`{text}` needs one time word: U or X in seconds, or P in milliseconds"),
                "write `G04 U1.5` or `G04 P1500`",
            );
            return None;
        };
        let seconds = if w.letter == 'P' {
            let ms = self.whole(line, w)?;
            Decimal {
                mantissa: ms as i128,
                scale: 3,
                has_point: true,
            }
        } else {
            let v = self.mm_value(line, w, Unit::Seconds)?;
            if let Err(e) = v.to_scaled(3) {
                self.number_error(line, w, e, "0.001 s");
                return None;
            }
            v
        };
        if seconds.is_negative() {
            let text = &line.text[w.range.clone()];
            self.error(
                codes::FANR_NUMBER,
                line,
                w.range.clone(),
                format!("`{text}`: a dwell is not negative"),
                "write the time",
            );
            return None;
        }
        self.push(ItemKind::Dwell { seconds }, code_span);
        Some(())
    }

    /// The end of a move: X/U and Z/W from the current position.
    fn target<'w>(
        &mut self,
        line: Line<'_>,
        get: &dyn Fn(char) -> Option<&'w Word>,
        from: Pos,
    ) -> Option<Pos> {
        let mut to = Pos::UNKNOWN;
        for (abs, inc) in [('X', 'U'), ('Z', 'W')] {
            let value = if let Some(w) = get(abs) {
                Some(self.length(line, w, Unit::Axis)?)
            } else if let Some(w) = get(inc) {
                let d = self.length(line, w, Unit::Axis)?;
                let here = if abs == 'X' { from.x } else { from.z };
                let Some(here) = here else {
                    let text = &line.text[w.range.clone()];
                    self.error(
                        codes::FANR_UNKNOWN_POSITION,
                        line,
                        w.range.clone(),
                        format!("`{text}` moves from a position that is not known yet"),
                        "move to an absolute X and Z (not U and W) first",
                    );
                    return None;
                };
                Some(here + d)
            } else {
                None
            };
            if abs == 'X' {
                to.x = value;
            } else {
                to.z = value;
            }
        }
        Some(to)
    }

    fn motion_block<'w>(
        &mut self,
        line: Line<'_>,
        get: &dyn Fn(char) -> Option<&'w Word>,
        lead: Option<Lead>,
        feed: Option<Length>,
        g: Option<&Word>,
        code_span: Span,
    ) -> Option<()> {
        let from = self.r.pos;
        let to = self.target(line, get, from)?;
        let whole = code_range_of(line, code_span);
        if !matches!(self.motion, Motion::Thread | Motion::Cycle)
            && let Some(w) = get('Q')
        {
            let text = &line.text[w.range.clone()];
            self.error(
                codes::FANR_UNSUPPORTED,
                line,
                w.range.clone(),
                format!("`{text}`: Q belongs to a thread (G32, G92)"),
                "remove it",
            );
            return None;
        }
        if !matches!(self.motion, Motion::Arc(_))
            && let Some(w) = ['I', 'K'].iter().find_map(|&c| get(c))
        {
            let text = &line.text[w.range.clone()];
            self.error(
                codes::FANR_UNSUPPORTED,
                line,
                w.range.clone(),
                format!("`{text}`: I and K belong to an arc (G02, G03)"),
                "remove it",
            );
            return None;
        }
        if !matches!(self.motion, Motion::Arc(_) | Motion::Cycle)
            && let Some(w) = get('R')
        {
            let text = &line.text[w.range.clone()];
            self.error(
                codes::FANR_UNSUPPORTED,
                line,
                w.range.clone(),
                format!("`{text}`: R belongs to an arc or to G92's taper"),
                "remove it",
            );
            return None;
        }
        if let Some(w) = get('P') {
            let text = &line.text[w.range.clone()];
            self.error(
                codes::FANR_UNSUPPORTED,
                line,
                w.range.clone(),
                format!("`{text}`: P belongs to a dwell (G04)"),
                "remove it",
            );
            return None;
        }
        self.moved = true;
        match self.motion {
            Motion::Rapid => {
                self.sync_end = None;
                self.push(ItemKind::Rapid { to }, code_span);
            }
            Motion::Feed | Motion::Arc(_) => {
                let feed = match (feed, self.f) {
                    (Some(f), _) => f,
                    (None, Some(FRegister::Feed(f))) => f,
                    (None, register) => {
                        let why = if matches!(register, Some(FRegister::Lead(_))) {
                            "F was last a thread's lead; whether this control feeds at it is not settled by any source ncthread holds"
                        } else {
                            "no feed F is set yet"
                        };
                        self.error(
                            codes::FANR_NO_FEED,
                            line,
                            whole,
                            format!("{} without F: {why}", self.motion.code()),
                            "write the feed in this block: `G01 Z-20. F0.2`",
                        );
                        return None;
                    }
                };
                self.sync_end = None;
                if let Motion::Arc(clockwise) = self.motion {
                    let (to, centre) = self.arc(line, get, from, to, clockwise, whole)?;
                    self.push(
                        ItemKind::Arc {
                            to,
                            centre: Box::new(centre),
                            clockwise,
                            feed,
                        },
                        code_span,
                    );
                } else {
                    self.push(ItemKind::Feed { to, feed }, code_span);
                }
            }
            Motion::Thread => self.thread(line, get, from, to, lead, whole, code_span)?,
            Motion::Cycle => self.cycle(line, get, from, to, lead, g, whole, code_span)?,
        }
        Some(())
    }

    /// The lead of a G32/G92 block: its F, or a lead F of an earlier thread block.
    fn block_lead(
        &mut self,
        line: Line<'_>,
        lead: Option<Lead>,
        whole: Range<usize>,
    ) -> Option<Lead> {
        match (lead, self.f) {
            (Some(l), _) => Some(l),
            (None, Some(FRegister::Lead(l))) => Some(l),
            (None, register) => {
                let why = if matches!(register, Some(FRegister::Feed(_))) {
                    "F was last a feed; whether this control threads at it is not settled by any source ncthread holds"
                } else {
                    "no lead F is set yet"
                };
                self.error(
                    codes::FANR_NO_FEED,
                    line,
                    whole,
                    format!("{} without F: {why}", self.motion.code()),
                    "write the lead in this block: `G32 Z-20. F1.5`",
                );
                None
            }
        }
    }

    /// Q: the start angle in 0.001°, a whole number.
    fn start_angle<'w>(
        &mut self,
        line: Line<'_>,
        get: &dyn Fn(char) -> Option<&'w Word>,
    ) -> Option<Angle> {
        let Some(w) = get('Q') else {
            return Some(Angle::ZERO);
        };
        let q = self.whole(line, w)?;
        if !(0..=MAX_Q).contains(&q) {
            let text = &line.text[w.range.clone()];
            self.error(
                codes::FANR_NUMBER,
                line,
                w.range.clone(),
                format!(
                    "`{text}`: the start angle Q is 0 to 359999 (0.001° without a decimal point)"
                ),
                "Q180000 is 180°",
            );
            return None;
        }
        Some(Angle(q))
    }

    /// Whether a move between two known points is steeper than 45° ([`lower::steeper_than_45`]).
    fn steep(from: Pos, to: Pos) -> bool {
        matches!((from.known(), to.known()), (Some(a), Some(b)) if lower::steeper_than_45(a, b))
    }

    #[allow(clippy::too_many_arguments)]
    fn thread<'w>(
        &mut self,
        line: Line<'_>,
        get: &dyn Fn(char) -> Option<&'w Word>,
        from: Pos,
        to: Pos,
        lead: Option<Lead>,
        whole: Range<usize>,
        code_span: Span,
    ) -> Option<()> {
        let lead = self.block_lead(line, lead, whole.clone())?;
        // A thread along Z needs only its end Z; one that moves X needs its start.
        let end = Pos {
            x: to.x.or(from.x),
            z: to.z.or(from.z),
        };
        if end.z.is_none() || (to.x.is_some() && from.known().is_none()) {
            self.error(
                codes::FANR_UNKNOWN_POSITION,
                line,
                whole,
                "G32 from a position that is not known yet".into(),
                "move to the thread's start with X and Z first",
            );
            return None;
        }
        if end.z == from.z || Self::steep(from, end) {
            self.error(
                codes::FANR_STEEP,
                line,
                whole,
                "this G32 moves X (as a radius) more than Z: steeper than 45°, its F is a lead along X, whose unit (radius or diameter) no source ncthread holds confirms".into(),
                "cut this thread with Z as the long axis, or convert it by hand",
            );
            return None;
        }
        let angle = self.start_angle(line, get)?;
        let continues = self.sync_end == Some(from) && self.blocks_since_sync == 1;
        if continues && get('Q').is_some() {
            let w = get('Q')?;
            let text = &line.text[w.range.clone()];
            self.error(
                codes::FANR_CHAIN,
                line,
                w.range.clone(),
                format!("`{text}` on a G32 block that continues the one before: the start angle counts only on the chain's first block"),
                "remove Q here, or retract and start a new pass",
            );
            return None;
        }
        if self.sync_end == Some(from) && self.blocks_since_sync > 1 {
            self.error(
                codes::FANR_CHAIN,
                line,
                whole,
                "a G32 block that starts where the last G32 ended, after a block between them: whether the control waits there for the index pulse (the tool in the cut) is not documented".into(),
                "keep the G32 blocks of one chain consecutive, or retract before the next pass",
            );
            return None;
        }
        let pass = ThreadPass {
            to: end,
            lead,
            start: if continues {
                SyncStart::Continue
            } else {
                SyncStart::Index(angle)
            },
            infeed: None,
            entry: None,
            exit: None,
        };
        self.push(ItemKind::pass(pass), code_span);
        self.sync_end = Some(end);
        self.blocks_since_sync = 0;
        Some(())
    }

    /// The G92 threading cycle: rapid to the cut's start X, thread to Z (with the machine's
    /// chamfer), rapid out to the start X, rapid back to the start Z. **\[evidence\]**
    #[allow(clippy::too_many_arguments)]
    fn cycle<'w>(
        &mut self,
        line: Line<'_>,
        get: &dyn Fn(char) -> Option<&'w Word>,
        from: Pos,
        to: Pos,
        lead: Option<Lead>,
        g: Option<&Word>,
        whole: Range<usize>,
        code_span: Span,
    ) -> Option<()> {
        let Some(chamfer) = self.profile.fanuc.thread_chamfer_0p1_lead else {
            // Said once: every G92 block of the program needs the same key.
            if std::mem::replace(&mut self.chamfer_refused, true) {
                return None;
            }
            let range = g.map_or(whole.clone(), |w| w.range.clone());
            self.error(
                codes::FANR_G92_CHAMFER,
                line,
                range,
                "G92 threading cycle: its chamfer at the thread's end is a machine parameter (5130), which the profile does not give".into(),
                "set `thread_chamfer_0p1_lead` in the profile's [fanuc] section to the machine's parameter 5130 (0 for none)",
            );
            return None;
        };
        let lead = self.block_lead(line, lead, whole.clone())?;
        let Some((sx, sz)) = from.known() else {
            self.error(
                codes::FANR_UNKNOWN_POSITION,
                line,
                whole,
                "G92 from a position that is not known yet: the cycle returns to its start point"
                    .into(),
                "move to the cycle's start point with X and Z first",
            );
            return None;
        };
        let Some(x) = to.x.or(self.cycle.map(|c| c.x)) else {
            self.error(
                codes::FANR_UNSUPPORTED,
                line,
                whole,
                "G92 without X or U: the thread's diameter".into(),
                "write the diameter of this pass: `G92 X19.4 Z-20. F1.5`",
            );
            return None;
        };
        let taper = match get('R') {
            Some(w) => self.length(line, w, Unit::Axis)?,
            None => self.cycle.map_or(Length::ZERO, |c| c.taper),
        };
        let end_z = match (to.z, self.cycle) {
            (Some(z), _) => z,
            (None, Some(c)) => c.end_z,
            (None, None) => {
                self.error(
                    codes::FANR_UNSUPPORTED,
                    line,
                    whole,
                    "G92 without Z or W: the thread's end".into(),
                    "write the end of the thread: `G92 X19.4 Z-20. F1.5`",
                );
                return None;
            }
        };
        if end_z == sz {
            self.error(
                codes::FANR_UNSUPPORTED,
                line,
                whole,
                "G92 whose Z is its start point's: the thread has no length".into(),
                "move the start point before the thread",
            );
            return None;
        }
        // R against U: with opposite signs FANUC allows only |R| ≤ |U/2| (its sign table);
        // beyond, the path is not documented. **[evidence]** GSK980TDc, HUST H6D-T.
        let u = x - sx;
        if taper.0 != 0
            && taper.signum() != u.signum()
            && 2 * taper.0.unsigned_abs() > u.0.unsigned_abs()
        {
            let w = get('R');
            let range = w.map_or(whole.clone(), |w| w.range.clone());
            self.error(
                codes::FANR_UNSUPPORTED,
                line,
                range,
                format!("G92's taper R {} against U {}: with opposite signs the cycle allows only |R| ≤ |U/2|", taper.mm(), u.mm()),
                "check R's sign: the radius at the cut's start minus the radius at its end",
            );
            return None;
        }
        // The cut starts 2R (on the diameter) from the end diameter, at the start Z.
        let cut_x = x + taper + taper;
        let angle = self.start_angle(line, get)?;
        if Self::steep(Pos::new(cut_x, sz), Pos::new(x, end_z)) {
            self.error(
                codes::FANR_STEEP,
                line,
                whole,
                "this G92's taper is steeper than 45°: its F is a lead along X, whose unit no source ncthread holds confirms".into(),
                "cut this thread with Z as the long axis",
            );
            return None;
        }
        let exit = if chamfer == 0 {
            None
        } else {
            let length = lead.length_times(i64::from(chamfer), 10);
            // On a taper the chamfer's geometry (45° from where it leaves the taper?) is in
            // no source ncthread holds.
            if taper.0 != 0 {
                self.error(
                    codes::FANR_G92_CHAMFER,
                    line,
                    whole,
                    "a tapered G92 (R) on a machine whose G92 chamfers the thread's end: where that chamfer leaves the taper and at which angle, no source ncthread holds says".into(),
                    "cut the taper thread with G32 passes, or set `thread_chamfer_0p1_lead = 0` if the machine does not chamfer",
                );
                return None;
            }
            // The chamfer is part of the retract towards the start X: past it, what the
            // control does is not documented.
            if 2 * length.0.unsigned_abs() > (sx - x).0.unsigned_abs() {
                self.error(
                    codes::FANR_G92_CHAMFER,
                    line,
                    whole,
                    format!("the machine's thread chamfer ({} mm at 45°, {} mm on the diameter) goes past the cycle's start X{}", length.mm(), (length + length).mm(), sx.mm()),
                    "start the cycle further from the thread (X at least the thread's diameter plus twice the chamfer)",
                );
                return None;
            }
            if length >= (end_z - sz).abs() {
                self.error(
                    codes::FANR_G92_CHAMFER,
                    line,
                    whole,
                    format!("the machine's thread chamfer ({} mm, {chamfer} tenths of the lead) is as long as the thread", length.mm()),
                    "check `thread_chamfer_0p1_lead` in the profile",
                );
                return None;
            }
            // At 45°, away from the thread towards the start X.
            let out = if sx >= x { 1 } else { -1 };
            Some(Chamfer {
                length,
                offset: Length(out * 2 * length.0),
            })
        };
        self.cycle = Some(Cycle { x, end_z, taper });
        self.sync_end = None;
        self.push(
            ItemKind::Rapid {
                to: Pos::new(cut_x, sz),
            },
            code_span,
        );
        self.push(
            ItemKind::pass(ThreadPass {
                to: Pos::new(x, end_z),
                lead,
                start: SyncStart::Index(angle),
                infeed: None,
                entry: None,
                exit,
            }),
            code_span,
        );
        self.push(
            ItemKind::Rapid {
                to: Pos::new(sx, end_z),
            },
            code_span,
        );
        self.push(
            ItemKind::Rapid {
                to: Pos::new(sx, sz),
            },
            code_span,
        );
        Some(())
    }

    /// An arc's end and centre: I (a radius value) and K from the start, or R (up to half a
    /// circle). The end must lie on the circle within 0.002 mm. **\[decided\]**
    fn arc<'w>(
        &mut self,
        line: Line<'_>,
        get: &dyn Fn(char) -> Option<&'w Word>,
        from: Pos,
        to: Pos,
        clockwise: bool,
        whole: Range<usize>,
    ) -> Option<(Pos, Pos)> {
        let code = if clockwise { "G02" } else { "G03" };
        let Some((sx, sz)) = from.known() else {
            self.error(
                codes::FANR_UNKNOWN_POSITION,
                line,
                whole,
                format!("{code} from a position that is not known yet: the arc's centre cannot be placed"),
                "move to an absolute X and Z before the arc",
            );
            return None;
        };
        let (ex, ez) = (to.x.unwrap_or(sx), to.z.unwrap_or(sz));
        let (i, k, r) = (get('I'), get('K'), get('R'));
        let centre = match (r, i.or(k)) {
            (Some(w), Some(_)) => {
                let text = &line.text[w.range.clone()];
                self.error(
                    codes::FANR_CONFLICT,
                    line,
                    w.range.clone(),
                    format!("`{text}` with I or K: give the centre one way"),
                    "write either I and K, or R",
                );
                return None;
            }
            (Some(w), None) => {
                let radius = self.length(line, w, Unit::Axis)?;
                let text = &line.text[w.range.clone()];
                if radius.0 <= 0 {
                    self.error(
                        codes::FANR_ARC,
                        line,
                        w.range.clone(),
                        format!("`{text}`: an arc's R is positive here (an arc over half a circle with a negative R is not confirmed for a lathe)"),
                        "write the arc with I and K",
                    );
                    return None;
                }
                if (sx, sz) == (ex, ez) {
                    self.error(
                        codes::FANR_ARC,
                        line,
                        w.range.clone(),
                        format!("{code} R ends where it starts: a full circle has no R form"),
                        "write the circle with I and K",
                    );
                    return None;
                }
                match lower::arc::centre_from_radius(
                    (sx, sz),
                    (ex, ez),
                    radius.to_mm_f64(),
                    clockwise,
                    0.001,
                ) {
                    Ok(c) => c,
                    Err(chord) => {
                        self.error(
                            codes::FANR_ARC,
                            line,
                            w.range.clone(),
                            format!("`{text}` is too small for the arc: its end is {chord:.4} mm from its start"),
                            "the radius must be at least half the distance from the start to the end",
                        );
                        return None;
                    }
                }
            }
            (None, None) => {
                self.error(
                    codes::FANR_ARC,
                    line,
                    whole,
                    format!("{code} without I, K or R"),
                    "write the centre (I as a radius value and K, from the arc's start) or the radius R",
                );
                return None;
            }
            (None, Some(_)) => {
                let iv = match i {
                    Some(w) => self.length(line, w, Unit::Axis)?,
                    None => Length::ZERO,
                };
                let kv = match k {
                    Some(w) => self.length(line, w, Unit::Axis)?,
                    None => Length::ZERO,
                };
                Pos::new(sx + iv + iv, sz + kv)
            }
        };
        let (cx, cz) = centre.known()?;
        let (r1, r2) = lower::arc::radii((sx, sz), (ex, ez), (cx, cz));
        if r1 < 0.001 || r2 < 0.001 {
            self.error(
                codes::FANR_ARC,
                line,
                whole,
                format!("{code} with a zero radius: its centre is on its start or its end"),
                "check I and K: the centre's offset from the arc's start (I as a radius)",
            );
            return None;
        }
        if (r1 - r2).abs() > 0.002 {
            self.error(
                codes::FANR_ARC,
                line,
                whole,
                format!(
                    "{code}'s end is not on its circle: the radius is {} mm at the start and {} mm at the end",
                    Length::from_mm_f64(r1).mm(),
                    Length::from_mm_f64(r2).mm()
                ),
                "check I and K (I is the centre's X offset as a radius)",
            );
            return None;
        }
        Some((Pos::new(ex, ez), centre))
    }
}

/// Puts `v` (from `w`) in its group's slot, noting a second code of the group.
fn set<'w, T>(
    w: &'w Word,
    slot: &mut Option<(T, &'w Word)>,
    v: T,
    conflict: &mut Option<&'w Word>,
) {
    if slot.is_some() {
        conflict.get_or_insert(w);
    }
    *slot = Some((v, w));
}

/// The byte range in `line` of a span on it.
fn code_range_of(line: Line<'_>, span: Span) -> Range<usize> {
    let start = span.start.saturating_sub(line.offset).min(line.text.len());
    let end = span
        .end
        .saturating_sub(line.offset)
        .min(line.text.len())
        .max(start);
    start..end
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ir::{Item, ItemKind};

    fn read(text: &str, profile: &str) -> (Vec<Item>, Vec<Diagnostic>) {
        let profile = if profile.is_empty() {
            Profile::default()
        } else {
            Profile::from_toml(&SourceFile::new("p", profile)).expect("a profile")
        };
        let (p, d) = parse(&SourceFile::new("t", text), &profile, Unsupported::Error);
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
        // A lead, a feed or a dwell without a point: no source settles its unit.
        for text in [
            "G00 X20. Z5.\nG32 Z-20. F15\n",
            "G00 X20. Z5.\nG01 Z-20. F2\n",
            "G04 U5\n",
        ] {
            assert!(codes(&read(text, "").1).contains(&"FANR006"), "{text}");
        }
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
        assert_eq!(first("G20\nG00 X0.0001 Z1.\n"), ("FANR016", Some((2, 5))));
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
}

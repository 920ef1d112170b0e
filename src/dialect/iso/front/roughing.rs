//! LinuxCNC's lathe roughing and finishing cycles in the front end: the G70–G72 line, the
//! run of its contour subroutine (only the contour's words count there), and the moves
//! [`crate::lower::g7x`] makes of it, as one [`ItemKind::Roughing`].
//! **\[evidence\]** LinuxCNC `Interp::convert_g7x` (`interp_g7x.cc`, 2.9.0~pre1).

use std::collections::BTreeMap;
use std::ops::Range;

use super::super::gcode::*;
use super::super::syntax::{Block, Keyword, Label, OWord, Word};
use super::{FrontEnd, Motion, Words};
use crate::diag::Diagnostic;
use crate::dialect::iso::codes;
use crate::fixed::Length;
use crate::ir::{ContourElement, FeedMode, ItemKind, Pos, RoughingCycle, RoughingKind};
use crate::lower::g7x::{self, C, Cycle, Element, Out};
use crate::source::{Line, Span};

/// A G70–G72 whose contour subroutine is running.
pub(super) struct Contour {
    code: GCode,
    label: String,
    /// The call level the cycle was read at: the contour ends when control is back there.
    pub(super) level: usize,
    span: Span,
    block_number: Option<u32>,
    comment: Option<String>,
    cycle: Cycle,
    kind: RoughingKind,
    /// Where the cycle starts, in program units (Z, X radius).
    start: C,
    /// The contour's current point and motion mode (0–3: G0–G3).
    at: C,
    motion: u8,
    elements: Vec<Element>,
    ir: Vec<ContourElement>,
    /// Program units per mm: 1, or 1/25.4 under G20.
    unit: f64,
    diameter: bool,
    incremental: bool,
    absolute_centres: bool,
}

impl Contour {
    /// The contour's current point in the program's coordinates (program units, X a radius,
    /// less the G52/G92 `offset` in mm, X a diameter): what `#<_x>`, `#<_z>`, #5420 and
    /// #5422 read on a contour line. LinuxCNC's cycle moves its current position to the end
    /// of each element as it reads the contour (`convert_g7x`), so a contour line may build
    /// on the one before it (LinuxCNC's `lathe_g7x_face_boring.ngc` does).
    pub(super) fn current(&self, offset: (f64, f64)) -> (f64, f64) {
        (
            self.at.im - offset.0 / 2.0 * self.unit,
            self.at.re - offset.1 * self.unit,
        )
    }
}

/// The G code's name as LinuxCNC prints it in its messages: `G71.0`.
fn dotted(code: GCode) -> String {
    format!("G{}.{}", code / 10, code % 10)
}

fn plain(code: GCode) -> String {
    crate::ir::g_code_name(code)
}

/// The most elements a contour may have (ncthread's limit, far above any real contour).
const MAX_ELEMENTS: usize = 10_000;

impl Contour {
    pub(super) fn label(&self) -> &str {
        &self.label
    }
    pub(super) fn span(&self) -> Span {
        self.span
    }
}

/// A word's value, or `default` when the line has no such word.
fn value_or(w: Option<&Word>, default: f64) -> f64 {
    w.map_or(default, |w| w.value.to_f64())
}

/// The words a G70–G72 line may use, as `convert_g7x` reads them: Q and D, then E and P
/// (G70) or I and R (G71, G72). The others are "not used by any command".
struct G7xWords<'w> {
    q: Option<&'w Word>,
    d: Option<&'w Word>,
    e: Option<&'w Word>,
    p: Option<&'w Word>,
    i: Option<&'w Word>,
    r: Option<&'w Word>,
}

impl<'w> G7xWords<'w> {
    fn take(words: &mut Words<'w>, finish: bool) -> Self {
        let q = words.take('Q');
        let d = words.take('D');
        let (e, p) = if finish {
            (words.take('E'), words.take('P'))
        } else {
            (None, None)
        };
        let (i, r) = if finish {
            (None, None)
        } else {
            (words.take('I'), words.take('R'))
        };
        G7xWords { q, d, e, p, i, r }
    }
}

/// The cycle as [`g7x`] runs it (program units) and as the IR records it (mm): G70's
/// first and last depth and passes (D, E, P), or G71's/G72's allowance D, depth of cut I
/// and retract R.
fn g7x_cycle(code: GCode, w: &G7xWords<'_>, depth: f64, unit: f64) -> (Cycle, RoughingKind) {
    let mm = |v: f64| Length::from_mm_f64(v / unit);
    if code == G70 {
        let (first, last, passes) = (value_or(w.d, 0.0), value_or(w.e, 0.0), value_or(w.p, 1.0));
        return (
            Cycle::Finish {
                first,
                last,
                passes,
            },
            RoughingKind::Finish {
                first: mm(first),
                last: mm(last),
                passes: w
                    .p
                    .map_or(crate::fixed::Decimal::parse("1").unwrap_or_default(), |w| {
                        w.value
                    }),
            },
        );
    }
    let (allowance, retract) = (value_or(w.d, 0.0), value_or(w.r, 0.5));
    let facing = matches!(code, G72 | G72_1 | G72_2);
    let variant = (code % 10) as u8;
    (
        Cycle::Rough {
            facing,
            variant,
            u: 0.0,
            w: 0.0,
            d: allowance,
            i: depth,
            r: retract,
        },
        RoughingKind::Rough {
            facing,
            variant,
            stock_x: Length(0),
            stock_z: Length(0),
            allowance: mm(allowance),
            depth: mm(depth),
            retract: mm(retract),
        },
    )
}

/// The words of one contour line as `convert_g7x` takes them.
struct ContourWords<'b> {
    /// X, Z, U, W, I, K, R, A and C, each once.
    words: BTreeMap<char, &'b Word>,
    /// G0–G3 as 0–3, when the line has one.
    motion: Option<u8>,
    /// A J (of the XY plane): an arc's line runs without it, a G0/G1 line is refused.
    j: Option<&'b Word>,
}

impl ContourWords<'_> {
    fn value(&self, letter: char) -> Option<f64> {
        self.words.get(&letter).map(|w| w.value.to_f64())
    }

    fn range(&self, letter: char) -> Option<Range<usize>> {
        self.words.get(&letter).map(|w| w.range.clone())
    }

    /// The arc word (I, J, K or R) the line has, the first of them in that order (as
    /// LinuxCNC checks a line's words).
    fn arc_word(&self) -> Option<&&Word> {
        self.words
            .get(&'I')
            .or(self.j.as_ref())
            .or(self.words.get(&'K'))
            .or(self.words.get(&'R'))
    }
}

/// The codes LinuxCNC's cycle makes no element of, which a contour line may not hold:
/// threading, the cycles, probing.
fn makes_no_element(g: GCode) -> bool {
    matches!(
        g,
        G33 | G33_1
            | G76
            | G70
            | G71
            | G71_1
            | G71_2
            | G72
            | G72_1
            | G72_2
            | G73
            | G74
            | G80..=G8X_LAST
            | G38_1..=G38_5
    )
}

/// A point of the cycle (program units, X a radius) as exact mm (X a diameter).
fn exact(p: C, unit: f64) -> (f64, f64) {
    (2.0 * p.im / unit, p.re / unit)
}

/// A point of the cycle on ncthread's grid.
fn grid(p: C, unit: f64) -> Pos {
    let (x, z) = exact(p, unit);
    Pos::new(Length::from_mm_f64(x), Length::from_mm_f64(z))
}

impl FrontEnd<'_> {
    fn roughing_error(&mut self, line: Line<'_>, range: Range<usize>, message: String, help: &str) {
        self.diag(codes::ISOR_ROUGHING, line, range, message, help);
    }

    /// A G70–G72 line: the rapid to its X and Z, then the call of its contour subroutine
    /// (`convert_g7x`'s start).
    pub(super) fn roughing(
        &mut self,
        line: Line<'_>,
        words: &mut Words<'_>,
        at: Option<&Word>,
        span: Span,
        code: GCode,
    ) {
        let range = at.map_or(0..line.text.len(), |w| w.range.clone());
        let name = plain(code);
        let w = G7xWords::take(words, code == G70);
        if at.is_none() && self.contour.is_none() && self.r.diags.has_errors() {
            return self.after_a_refused_cycle(words);
        }
        let Some((q, whole, depth)) = self.check_g7x(line, &range, code, &w) else {
            return;
        };
        let unit = if self.inch { 1.0 / 25.4 } else { 1.0 };
        let (cycle, kind) = g7x_cycle(code, &w, depth, unit);
        let Some(start) = self.g7x_start(line, words, range, span, &name, unit) else {
            return;
        };
        let label = Label::Number(
            (whole as u64)
                .to_string()
                .trim_start_matches('0')
                .to_string(),
        );
        self.contour = Some(Box::new(Contour {
            code,
            label: label.to_string(),
            level: 0,
            span,
            block_number: None,
            comment: None,
            cycle,
            kind,
            start,
            at: start,
            motion: 0,
            elements: Vec::new(),
            ir: Vec::new(),
            unit,
            diameter: self.diameter.unwrap_or(false),
            incremental: self.incremental,
            absolute_centres: self.absolute_centres,
        }));
        self.cycle_call = Some(OWord {
            label,
            keyword: Keyword::Call,
            args: Vec::new(),
            range: q.range.clone(),
        });
    }

    /// A line with axes in the motion mode a refused G70–G72 line left. LinuxCNC never keeps
    /// a cycle as the motion mode: the cycle's moves set it (`motion_machine` calls
    /// `convert_straight` and `convert_arc`), so the line continues the mode of the cycle's
    /// last move, which ncthread does not know as it refused the cycle. The line is not
    /// read (the program is refused already; "G70 without Q" there would blame a line for
    /// what the cycle's refusal left), and the position is forgotten; so is every such line
    /// up to the next motion code.
    /// **\[evidence\]** LinuxCNC `interp_g7x.cc`, `motion_machine::straight_move`.
    fn after_a_refused_cycle(&mut self, words: &mut Words<'_>) {
        for letter in ['X', 'Z', 'U', 'W'] {
            words.take(letter);
        }
        self.r.pos = Pos::UNKNOWN;
        self.exact = (None, None);
    }

    /// `convert_g7x`'s checks of the cycle's line, in its order: a Q, no cutter radius
    /// compensation, Q a whole number, the depth of cut I more than 0. The Q word, the
    /// subroutine's number and the depth of cut; `None` once refused.
    fn check_g7x<'w>(
        &mut self,
        line: Line<'_>,
        range: &Range<usize>,
        code: GCode,
        w: &G7xWords<'w>,
    ) -> Option<(&'w Word, f64, f64)> {
        let name = plain(code);
        let finish = code == G70;
        let Some(q) = w.q else {
            self.roughing_error(
                line,
                range.clone(),
                format!("{name} without Q (LinuxCNC: \"G7x.x  requires a Q word\")"),
                "name the contour's subroutine with Q: `G71 Q100 …` runs `o100 sub`",
            );
            return None;
        };
        if self.compensation && finish {
            self.roughing_error(
                line,
                range.clone(),
                format!(
                    "{name} while cutter radius compensation is on: LinuxCNC 2.9.0~pre1 takes the contour's end for the tool's position while it reads the contour, so the compensated path it cuts is not the cycle's moves (later LinuxCNC versions cut the moves; ncthread cannot write a program that both cut alike)"
                ),
                "write the finishing contour as G1/G2/G3 moves under G41.1/G42.1 (or G41/G42), or run G70 without compensation",
            );
            return None;
        }
        if self.compensation && !finish {
            self.roughing_error(
                line,
                range.clone(),
                format!(
                    "{name} while cutter radius compensation is on (LinuxCNC: \"{} cannot be used with cutter compensation enabled\")",
                    dotted(code)
                ),
                "turn the compensation off with G40 before the roughing cycle",
            );
            return None;
        }
        let number = q.value.to_f64();
        let whole = number.round();
        if (number - whole).abs() > 0.0001 || whole < 0.0 {
            let text = &line.text[q.range.clone()];
            self.roughing_error(
                line,
                q.range.clone(),
                format!("`{text}`: Q names a numbered subroutine and must be a whole number (LinuxCNC: \"Non integer value for integer\")"),
                "write the subroutine's number: `Q100` for `o100 sub`",
            );
            return None;
        }
        let depth = value_or(w.i, 1.0);
        if depth <= 0.0 {
            let at = w.i.map_or(range.clone(), |w| w.range.clone());
            self.roughing_error(
                line,
                at,
                "the depth of cut I is 0 or less (LinuxCNC: \"G7X error: I must be greater than zero.\")".into(),
                "give the depth of each roughing cut with I, more than 0",
            );
            return None;
        }
        Some((q, whole, depth))
    }

    /// LinuxCNC's G0 to the line's X and Z (the current position if none) before the
    /// cycle: where the cycle starts, in program units (Z, X a radius); `None` when that
    /// is not known (reported).
    fn g7x_start(
        &mut self,
        line: Line<'_>,
        words: &mut Words<'_>,
        range: Range<usize>,
        span: Span,
        name: &str,
        unit: f64,
    ) -> Option<C> {
        let start_exact = self.exact_start();
        let to = self.target(line, words)?;
        if to != Pos::UNKNOWN {
            self.push(ItemKind::Rapid { to }, span);
            self.r.pos = ItemKind::Rapid { to }.end_position(self.r.pos);
            self.exact_after_move(start_exact);
        }
        let (Some(_), (Some(x), Some(z))) = (self.r.pos.known(), self.exact_start()) else {
            self.diag(
                codes::ISOR_UNKNOWN_POSITION,
                line,
                range,
                format!("{name} from a position that is not known yet: the cycle starts where the tool is"),
                "move to an absolute X and Z before the cycle, or give them on its line",
            );
            return None;
        };
        Some(C::new(z * unit, x / 2.0 * unit))
    }

    /// The block number and comment of the cycle's line, for its item.
    pub(super) fn stamp_contour(&mut self, number: Option<u32>, comment: Option<String>) {
        if let Some(c) = &mut self.contour {
            c.block_number = number;
            c.comment = comment;
        }
    }

    /// One line of the contour subroutine, after its values and parameter settings: what
    /// LinuxCNC's cycle takes from it (`convert_g7x` reading the contour, in its order:
    /// the words, the motion mode, the end point, the element, its corner).
    pub(super) fn contour_line(&mut self, line: Line<'_>, block: &Block) {
        let Some(c) = self.contour.as_deref() else {
            return;
        };
        let name = plain(c.code);
        let label = c.label.clone();
        let Some(words) = self.contour_words(line, block, &name, &label) else {
            return;
        };
        let Some(c) = self.contour.as_deref_mut() else {
            return;
        };
        if let Some(m) = words.motion {
            c.motion = m;
        }
        if c.motion < 2
            && let Some(w) = words.arc_word()
        {
            let text = line.text[w.range.clone()].to_string();
            let code = if c.motion == 0 { "G0" } else { "G1" };
            return self.roughing_error(
                line,
                w.range.clone(),
                format!("`{text}` on a {code} line of a contour (LinuxCNC: \"{} word with no G2, G3… to use it\")", w.letter),
                "I, K and R belong to arcs (G2, G3), and J to none on a lathe",
            );
        }
        if let Some(j) = words.j {
            self.report_ignored_contour_words(line, &[j], &name, &label);
        }
        let Some((start, end, centre)) = self.contour_end(line, &words) else {
            return;
        };
        if start == end {
            return;
        }
        let Some(element) = self.contour_element(line, &words, start, end, centre) else {
            return;
        };
        if let (Some(a), Some(_)) = (words.range('A'), words.range('C')) {
            return self.roughing_error(
                line,
                a,
                "A and C on one corner of a contour (LinuxCNC: \"G7X error: Both A and C parameters on a corner\")".into(),
                "round the corner (A) or chamfer it (C), not both",
            );
        }
        self.add_contour_element(line, &words, element, end);
    }

    /// The words of a contour line, sorted: its motion code (G0–G3), its axis, arc and
    /// corner words (each once), and the words LinuxCNC does not run there (reported
    /// together). `None` once the line is refused.
    fn contour_words<'b>(
        &mut self,
        line: Line<'_>,
        block: &'b Block,
        name: &str,
        label: &str,
    ) -> Option<ContourWords<'b>> {
        let mut words: BTreeMap<char, &Word> = Default::default();
        let mut ignored: Vec<&Word> = Vec::new();
        let (mut motion, mut j) = (None, None);
        // G41.1/G42.1 take D and L: LinuxCNC reads them with it (and runs none of them in
        // the contour).
        let dynamic_comp = block
            .words
            .iter()
            .any(|w| w.letter == 'G' && matches!(w.value.to_scaled(1), Ok(411 | 421)));
        for w in &block.words {
            match w.letter {
                'G' => {
                    if !self.contour_g(line, w, &mut motion, &mut ignored, (name, label)) {
                        return None;
                    }
                }
                'M' if !w.value.to_whole().is_ok_and(linuxcnc_knows_m) => {
                    self.unknown_in_contour(line, w, "Unknown m code used", (name, label));
                    return None;
                }
                // J (of the XY plane) too: rs274 runs a contour's `G2 X30 J0 Z-10 R5` (and
                // refuses `J0 G0 X0 Z-10`, below).
                'J' => j = Some(w),
                'M' | 'S' | 'T' | 'F' => ignored.push(w),
                'D' | 'L' if dynamic_comp => ignored.push(w),
                'X' | 'Z' | 'U' | 'W' | 'I' | 'K' | 'R' | 'A' | 'C' => {
                    if let Some(first) = words.insert(w.letter, w) {
                        let first = line.text[first.range.clone()].to_string();
                        self.diag(
                            codes::ISOR_CONFLICT,
                            line,
                            w.range.clone(),
                            format!(
                                "a second {} word on the line (the first is `{first}`)",
                                w.letter
                            ),
                            "LinuxCNC refuses a line with two words of one letter; split the line",
                        );
                        return None;
                    }
                }
                _ => {
                    let text = &line.text[w.range.clone()];
                    self.roughing_error(
                        line,
                        w.range.clone(),
                        format!("`{text}` in the contour of a {name} ({label}): LinuxCNC refuses it there (no command on the line uses it)"),
                        "a contour line holds X, Z (or U, W), I, K or R for arcs, and A (a rounded corner) or C (a chamfer)",
                    );
                    return None;
                }
            }
        }
        self.report_ignored_contour_words(line, &ignored, name, label);
        Some(ContourWords { words, motion, j })
    }

    /// A G word of a contour line: its motion (one per line), or a code the cycle does not
    /// run (`ignored`); false when it stops the cycle (said).
    fn contour_g<'b>(
        &mut self,
        line: Line<'_>,
        w: &'b Word,
        motion: &mut Option<u8>,
        ignored: &mut Vec<&'b Word>,
        (name, label): (&str, &str),
    ) -> bool {
        let g = w.value.to_scaled(1).unwrap_or(-1);
        let refusal = match g {
            G0 | G1 | G2 | G3 if motion.is_some() => Some((
                "two motion codes on one line of a contour".to_string(),
                "one motion code per line",
            )),
            G0 | G1 | G2 | G3 => {
                *motion = Some((g / 10) as u8);
                None
            }
            // G10 (LinuxCNC reads its L and P on the line, and refuses it without them):
            // not read by ncthread anywhere, in a contour neither.
            100 => {
                let text = &line.text[w.range.clone()];
                self.diag(
                    codes::ISOR_UNSUPPORTED,
                    line,
                    w.range.clone(),
                    format!("`{text}` in the contour of a {name} ({label}): changes of the coordinate systems (G10) are not read by ncthread"),
                    "a contour is made of G0, G1, G2 and G3 moves",
                );
                return false;
            }
            g if makes_no_element(g) => {
                let text = &line.text[w.range.clone()];
                Some((
                    format!(
                        "`{text}` in the contour of a {name} ({label}): LinuxCNC's cycle makes no element of it"
                    ),
                    "a contour is made of G0, G1, G2 and G3 moves",
                ))
            }
            g => match linuxcnc_refuses(w.value.to_scaled(1).ok().filter(|_| g >= 0)) {
                Some(why) => {
                    self.unknown_in_contour(line, w, why, (name, label));
                    return false;
                }
                None => {
                    ignored.push(w);
                    None
                }
            },
        };
        match refusal {
            Some((message, help)) => {
                self.roughing_error(line, w.range.clone(), message, help);
                false
            }
            None => true,
        }
    }

    /// A code LinuxCNC does not know, in a contour: it stops where it reads it (`why`, its
    /// own words).
    fn unknown_in_contour(
        &mut self,
        line: Line<'_>,
        w: &Word,
        why: &str,
        (name, label): (&str, &str),
    ) {
        let text = &line.text[w.range.clone()];
        self.roughing_error(
            line,
            w.range.clone(),
            format!("`{text}` in the contour of a {name} ({label}): LinuxCNC stops where it reads it (\"{why}\")"),
            if w.letter == 'M' {
                "set M codes before the cycle"
            } else {
                "a contour is made of G0, G1, G2 and G3 moves"
            },
        );
    }

    /// The words of a contour line that LinuxCNC does not run there (M, S, T, F, G codes
    /// of no motion), in one warning.
    fn report_ignored_contour_words(
        &mut self,
        line: Line<'_>,
        ignored: &[&Word],
        name: &str,
        label: &str,
    ) {
        if ignored.is_empty() {
            return;
        }
        let list: Vec<&str> = ignored
            .iter()
            .map(|w| &line.text[w.range.clone()])
            .collect();
        let span = self.r.span(line, ignored[0].range.clone());
        self.r.diags.push(
            Diagnostic::new(
                codes::ISOR_CONTOUR_IGNORED,
                format!(
                    "`{}` in the contour of a {name} ({label}): LinuxCNC does not run it there, and neither does ncthread",
                    list.join(" ")
                ),
            )
            .at(self.r.src, span)
            .help("the cycle takes only the contour's shape from its subroutine: set feeds, speeds and modes before the cycle"),
        );
    }

    /// A contour line's start (the contour's current point), end and I/K centre offset, in
    /// program units (Z, X a radius): X and Z in G90 (less the G52/G92 offset), U and W
    /// increments (G90 only, and not with X or Z), every axis an increment in G91.
    fn contour_end(&mut self, line: Line<'_>, words: &ContourWords<'_>) -> Option<(C, C, C)> {
        let offset = self.axis_offset;
        let c = self.contour.as_deref()?;
        // The G52/G92 offset, in the contour's units (X a radius).
        let shift = if c.incremental {
            C::default()
        } else {
            C::new(offset.1 * c.unit, offset.0 / 2.0 * c.unit)
        };
        let v = |l: char| words.value(l);
        let mut end = if c.incremental { C::default() } else { c.at };
        let mut centre = C::default();
        for (axis, alias) in [('U', 'X'), ('W', 'Z')] {
            if let Some(w) = words.words.get(&axis) {
                let text = line.text[w.range.clone()].to_string();
                let why = if c.incremental {
                    format!(
                        "`{text}` in the contour while G91 is in force (LinuxCNC: \"G7x error: Cannot use {axis} in incremental mode (G91)\")"
                    )
                } else if words.words.contains_key(&alias) {
                    format!(
                        "`{text}` with {alias} on one line (LinuxCNC: \"G7x error: Cannot use {axis} and {alias} in the same block\")"
                    )
                } else {
                    continue;
                };
                self.roughing_error(
                    line,
                    w.range.clone(),
                    why,
                    "U and W are increments of X and Z in a contour written in G90",
                );
                return None;
            }
        }
        if let Some(u) = v('U') {
            end.im += if c.diameter { u / 2.0 } else { u };
        } else if let Some(x) = v('X') {
            end.im = if c.diameter { x / 2.0 } else { x } + shift.im;
        }
        if let Some(w) = v('W') {
            end.re += w;
        } else if let Some(z) = v('Z') {
            end.re = z + shift.re;
        }
        if let Some(i) = v('I') {
            centre.im = i;
        }
        if let Some(k) = v('K') {
            centre.re = k;
        }
        if c.incremental {
            end += c.at;
        }
        Some((c.at, end, centre))
    }

    /// The element a contour line makes in its motion mode: a line (G0, G1), or an arc
    /// (G2, G3) by its radius R or its centre I, K. `None` once refused.
    fn contour_element(
        &mut self,
        line: Line<'_>,
        words: &ContourWords<'_>,
        start: C,
        end: C,
        mut centre: C,
    ) -> Option<Element> {
        let offset = self.axis_offset;
        let c = self.contour.as_deref()?;
        let ccw = match c.motion {
            0 | 1 => return Some(Element::Line { start, end }),
            m => m == 3,
        };
        if let Some(r) = words.value('R') {
            return self.contour_arc_by_radius(line, words, start, end, ccw, r);
        }
        if words.arc_word().is_none() {
            self.roughing_error(
                line,
                0..line.text.len(),
                "an arc of the contour without I, K or R (LinuxCNC: \"G7X error: either I or K must be present for arc\")".into(),
                "give the arc its centre (I for X, K for Z) or its radius R",
            );
            return None;
        }
        if c.absolute_centres {
            centre += C::new(offset.1 * c.unit, offset.0 / 2.0 * c.unit);
        } else {
            centre += start;
        }
        Some(Element::Arc {
            ccw,
            start,
            centre,
            end,
        })
    }

    /// An arc of the contour by its radius R: its centre as LinuxCNC's cycle computes it
    /// (from the chord's midpoint, on the side the direction gives). `None` once refused.
    fn contour_arc_by_radius(
        &mut self,
        line: Line<'_>,
        words: &ContourWords<'_>,
        start: C,
        end: C,
        ccw: bool,
        r: f64,
    ) -> Option<Element> {
        if let Some(w) = words.range('I').or(words.range('K')) {
            self.roughing_error(
                line,
                w,
                "R with I or K on one arc of a contour (LinuxCNC: \"G7X error: both R and I or K flag used for arc\")".into(),
                "give the arc either its radius R or its centre I K",
            );
            return None;
        }
        let chord = (end - start).norm();
        let h = (r * r - chord / 4.0) / chord;
        if h.is_nan() || h < 0.0 {
            self.roughing_error(
                line,
                words.range('R').unwrap_or(0..line.text.len()),
                format!("R{r} is too small for the arc of the contour: LinuxCNC's cycle would compute its centre from the square root of a negative number"),
                "the radius must be at least half the distance from the arc's start to its end",
            );
            return None;
        }
        let mid = C::new((start.re + end.re) / 2.0, (start.im + end.im) / 2.0);
        let d = C::new(0.0, h.sqrt()) * (end - start);
        let centre = if ccw {
            C::new(mid.re + d.re, mid.im + d.im)
        } else {
            C::new(mid.re - d.re, mid.im - d.im)
        };
        Some(Element::Arc {
            ccw,
            start,
            centre,
            end,
        })
    }

    /// Adds the element (and its corner: A a fillet, C a chamfer) to the contour, for the
    /// cycle and for the IR, and moves the contour's current point to its end.
    fn add_contour_element(
        &mut self,
        line: Line<'_>,
        words: &ContourWords<'_>,
        element: Element,
        end: C,
    ) {
        let Some(c) = self.contour.as_deref_mut() else {
            return;
        };
        let mm = |p: C| {
            Pos::new(
                Length::from_mm_f64(2.0 * p.im / c.unit),
                Length::from_mm_f64(p.re / c.unit),
            )
        };
        c.ir.push(match element {
            Element::Arc {
                ccw, centre, end, ..
            } => ContourElement::Arc {
                to: mm(end),
                centre: mm(centre),
                clockwise: !ccw,
            },
            _ => ContourElement::Line { to: mm(end) },
        });
        c.elements.push(element);
        if let Some(a) = words.value('A') {
            c.elements.push(Element::Fillet { radius: a, at: end });
            c.ir.push(ContourElement::Round {
                radius: Length::from_mm_f64(a / c.unit),
            });
        }
        if let Some(size) = words.value('C') {
            c.elements.push(Element::Chamfer { size, at: end });
            c.ir.push(ContourElement::Chamfer {
                size: Length::from_mm_f64(size / c.unit),
            });
        }
        c.at = end;
        if c.elements.len() > MAX_ELEMENTS {
            self.roughing_error(
                line,
                0..line.text.len(),
                format!(
                    "the contour has more than {MAX_ELEMENTS} elements, more than ncthread follows"
                ),
                "check the contour's loops",
            );
            self.stopped = true;
        }
    }

    /// A refusal of the whole cycle, at its line.
    fn contour_error(&mut self, span: Span, message: String, help: &str) {
        self.r.diags.push(
            Diagnostic::new(codes::ISOR_ROUGHING, message)
                .at(self.r.src, span)
                .help(help),
        );
    }

    /// The contour is complete (its subroutine returned): the cycle's moves
    /// (`convert_g7x`'s end: the cycle run over the contour, its feed, its moves).
    pub(super) fn finish_contour(&mut self) {
        let Some(c) = self.contour.take() else {
            return;
        };
        let name = plain(c.code);
        if c.elements.len() < 2 {
            return self.contour_error(
                c.span,
                format!(
                    "the contour of this {name} ({}) has {} element(s): LinuxCNC then cuts nothing and takes the contour's end as its position, where the tool is not",
                    c.label,
                    c.elements.len()
                ),
                "give the contour at least two moves (the first from the cycle's start)",
            );
        }
        let Some(moves) = self.g7x_moves(&c, &name) else {
            return;
        };
        let feeds = moves.iter().any(|m| !matches!(m, Out::Rapid(_)));
        let Some(feed) = self.g7x_feed(&c, &name, feeds) else {
            return;
        };
        if feeds && self.feed_mode.is_none() {
            self.feed_mode = Some(FeedMode::PerMin);
            self.push(ItemKind::FeedMode(FeedMode::PerMin), c.span);
        }
        let Some((items, last, at)) = self.g7x_items(&c, &name, &moves, feed) else {
            return;
        };
        let cycle = RoughingCycle {
            code: c.code as u16,
            subroutine: c.label.clone(),
            kind: c.kind,
            start: grid(c.start, c.unit),
            contour: c.ir.clone(),
            moves: items,
        };
        let kind = ItemKind::Roughing(Box::new(cycle));
        self.push(kind.clone(), c.span);
        if let Some(item) = self.r.items.last_mut() {
            item.block_number = c.block_number;
            item.comment = c.comment.as_deref().map(Box::from);
        }
        self.r.pos = at;
        if let Some((motion, end)) = last {
            self.motion = Some(motion);
            let (x, z) = exact(end, c.unit);
            self.exact = (Some(x), Some(z));
        }
    }

    /// The cycle run over the contour ([`g7x::run`], LinuxCNC's own code): its moves, or
    /// `None` once refused (LinuxCNC's errors, and its endless loops).
    fn g7x_moves(&mut self, c: &Contour, name: &str) -> Option<Vec<Out>> {
        match g7x::run(&c.cycle, c.start, &c.elements) {
            Ok(m) => Some(m),
            Err(why) if why.starts_with(g7x::ENDLESS) => {
                self.contour_error(
                    c.span,
                    format!(
                        "{name} along {}: LinuxCNC's cycle does not end on this contour: its interpreter loops for ever (ncthread stops after {})",
                        c.label,
                        why.trim_start_matches(g7x::ENDLESS).trim()
                    ),
                    "change the contour (a tiny element, or arcs that meet at a cusp, are the usual causes); LinuxCNC fixed some of these loops after 2.9.0~pre1",
                );
                None
            }
            Err(why) => {
                self.contour_error(
                    c.span,
                    format!(
                        "{name} along {}: LinuxCNC refuses the cycle (\"G7X error: {why}\")",
                        c.label
                    ),
                    if why == "Not monotonic" {
                        "a G71.1/G72.1 contour, and the contour of a G70, must not turn back (X and Z each change one way only)"
                    } else {
                        "check the contour's subroutine"
                    },
                );
                None
            }
        }
    }

    /// The feed of the cycle's cuts: F in force, more than 0, when it has any (`feeds`).
    fn g7x_feed(&mut self, c: &Contour, name: &str, feeds: bool) -> Option<Length> {
        if feeds && let Some(why) = self.feed_in_other_units(name) {
            self.contour_error(c.span, why, super::motion::FEED_AGAIN);
            return None;
        }
        match self.feed {
            Some(f) if f.0 > 0 => Some(f),
            _ if !feeds => Some(Length(0)),
            _ => {
                self.contour_error(
                    c.span,
                    format!(
                        "{name} with no feed rate (F) set, or F0: its cuts are G1 and G2/G3 moves (LinuxCNC: \"Cannot do G1 with zero feed rate\")"
                    ),
                    "set the feed with F before or on the cycle's line",
                );
                None
            }
        }
    }

    /// The cycle's moves as items on ncthread's grid (moves to where the tool is left out),
    /// the last move's motion and exact end, and where the tool ends; `None` when an arc
    /// rounded onto the grid is one LinuxCNC refuses.
    #[allow(clippy::type_complexity)]
    fn g7x_items(
        &mut self,
        c: &Contour,
        name: &str,
        moves: &[Out],
        feed: Length,
    ) -> Option<(Vec<ItemKind>, Option<(Motion, C)>, Pos)> {
        let unit = c.unit;
        let grid = |p: C| grid(p, unit);
        let mut items = Vec::with_capacity(moves.len());
        let mut last = None;
        let mut at = self.r.pos;
        for m in moves {
            let (kind, end) = match *m {
                Out::Rapid(p) => (ItemKind::Rapid { to: grid(p) }, p),
                Out::Feed(p) => (ItemKind::Feed { to: grid(p), feed }, p),
                Out::Arc { ccw, centre, end } => {
                    let kind = ItemKind::Arc {
                        to: grid(end),
                        centre: Box::new(grid(centre)),
                        clockwise: !ccw,
                        feed,
                    };
                    if let (Some(s), Some(e), Some(k)) =
                        (at.known(), grid(end).known(), grid(centre).known())
                    {
                        let (r1, r2) = crate::lower::arc::radii(s, e, k);
                        let off = (r1 - r2).abs();
                        if r1 < 0.00127
                            || r2 < 0.00127
                            || off > 2.0 * 0.01 * std::f64::consts::SQRT_2
                        {
                            self.contour_error(
                                c.span,
                                format!(
                                    "{name} along {}: an arc of its path, rounded onto ncthread's 0.0001 mm grid, is one LinuxCNC refuses (radius {r1:.5} mm at its start, {r2:.5} mm at its end)",
                                    c.label
                                ),
                                "check the contour's arcs and corners",
                            );
                            return None;
                        }
                    }
                    (kind, end)
                }
            };
            // LinuxCNC's moves to where the tool already is move nothing.
            if matches!(kind, ItemKind::Rapid { .. } | ItemKind::Feed { .. })
                && kind.end_position(at) == at
            {
                continue;
            }
            at = kind.end_position(at);
            last = Some((
                match kind {
                    ItemKind::Rapid { .. } => Motion::Rapid,
                    ItemKind::Feed { .. } => Motion::Feed,
                    _ => Motion::Arc {
                        clockwise: !matches!(m, Out::Arc { ccw: true, .. }),
                    },
                },
                end,
            ));
            items.push(kind);
        }
        Some((items, last, at))
    }
}

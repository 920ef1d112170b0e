//! LinuxCNC's lathe roughing and finishing cycles in the front end: the G70–G72 line, the
//! run of its contour subroutine (only the contour's words count there), and the moves
//! [`crate::lower::g7x`] makes of it, as one [`ItemKind::Roughing`].
//! **\[evidence\]** LinuxCNC `Interp::convert_g7x` (`interp_g7x.cc`, 2.9.0~pre1).

use std::ops::Range;

use super::super::gcode::*;
use super::super::syntax::{Block, Keyword, Label, OWord, Word};
use super::{FrontEnd, Motion, Words};
use crate::diag::{Diagnostic, codes};
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

impl FrontEnd<'_> {
    fn roughing_error(&mut self, line: Line<'_>, range: Range<usize>, message: String, help: &str) {
        self.diag(codes::ISOR_ROUGHING, line, range, message, help);
    }

    /// A G70–G72 line: the rapid to its X and Z, then the call of its contour subroutine.
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
        let finish = code == G70;
        // Words LinuxCNC lets this cycle use; the others are "not used by any command".
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
        let Some(q) = q else {
            return self.roughing_error(
                line,
                range,
                format!("{name} without Q (LinuxCNC: \"G7x.x  requires a Q word\")"),
                "name the contour's subroutine with Q: `G71 Q100 …` runs `o100 sub`",
            );
        };
        if self.compensation && finish {
            return self.roughing_error(
                line,
                range,
                format!(
                    "{name} while cutter radius compensation is on: LinuxCNC 2.9.0~pre1 takes the contour's end for the tool's position while it reads the contour, so the compensated path it cuts is not the cycle's moves (later LinuxCNC versions cut the moves; ncthread cannot write a program that both cut alike)"
                ),
                "write the finishing contour as G1/G2/G3 moves under G41.1/G42.1 (or G41/G42), or run G70 without compensation",
            );
        }
        if self.compensation && !finish {
            return self.roughing_error(
                line,
                range,
                format!(
                    "{name} while cutter radius compensation is on (LinuxCNC: \"{} cannot be used with cutter compensation enabled\")",
                    dotted(code)
                ),
                "turn the compensation off with G40 before the roughing cycle",
            );
        }
        let value = |w: Option<&Word>, default: f64| w.map_or(default, |w| w.value.to_f64());
        let number = q.value.to_f64();
        let whole = number.round();
        if (number - whole).abs() > 0.0001 || whole < 0.0 {
            let text = &line.text[q.range.clone()];
            return self.roughing_error(
                line,
                q.range.clone(),
                format!("`{text}`: Q names a numbered subroutine and must be a whole number (LinuxCNC: \"Non integer value for integer\")"),
                "write the subroutine's number: `Q100` for `o100 sub`",
            );
        }
        let depth = value(i, 1.0);
        if depth <= 0.0 {
            let w = i.map_or(range.clone(), |w| w.range.clone());
            return self.roughing_error(
                line,
                w,
                "the depth of cut I is 0 or less (LinuxCNC: \"G7X error: I must be greater than zero.\")".into(),
                "give the depth of each roughing cut with I, more than 0",
            );
        }
        let unit = if self.inch { 1.0 / 25.4 } else { 1.0 };
        let mm = |v: f64| Length::from_mm_f64(v / unit);
        let (cycle, kind) = if finish {
            let (first, last, passes) = (value(d, 0.0), value(e, 0.0), value(p, 1.0));
            (
                Cycle::Finish {
                    first,
                    last,
                    passes,
                },
                RoughingKind::Finish {
                    first: mm(first),
                    last: mm(last),
                    passes: p.map_or(crate::fixed::Decimal::parse("1").unwrap_or_default(), |w| {
                        w.value
                    }),
                },
            )
        } else {
            let (allowance, retract) = (value(d, 0.0), value(r, 0.5));
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
        };
        // LinuxCNC first makes a G0 to the line's X and Z (the current position if none).
        let start_exact = self.exact_start();
        let Some(to) = self.target(line, words) else {
            return;
        };
        if to != Pos::UNKNOWN {
            self.push(ItemKind::Rapid { to }, span);
            self.r.pos = ItemKind::Rapid { to }.end_position(self.r.pos);
            self.exact_after_move(start_exact);
        }
        let (Some(_), (Some(x), Some(z))) = (self.r.pos.known(), self.exact_start()) else {
            return self.diag(
                codes::ISOR_UNKNOWN_POSITION,
                line,
                range,
                format!("{name} from a position that is not known yet: the cycle starts where the tool is"),
                "move to an absolute X and Z before the cycle, or give them on its line",
            );
        };
        let start = C::new(z * unit, x / 2.0 * unit);
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

    /// The block number and comment of the cycle's line, for its item.
    pub(super) fn stamp_contour(&mut self, number: Option<u32>, comment: Option<String>) {
        if let Some(c) = &mut self.contour {
            c.block_number = number;
            c.comment = comment;
        }
    }

    /// One line of the contour subroutine, after its values and parameter settings: what
    /// LinuxCNC's cycle takes from it.
    pub(super) fn contour_line(&mut self, line: Line<'_>, block: &Block) {
        let Some(c) = self.contour.as_deref() else {
            return;
        };
        let name = plain(c.code);
        let label = c.label.clone();
        let mut words: std::collections::BTreeMap<char, &Word> = Default::default();
        let mut ignored: Vec<&Word> = Vec::new();
        let mut motion = None;
        for w in &block.words {
            match w.letter {
                'G' => {
                    let g = w.value.to_scaled(1).unwrap_or(-1);
                    match g {
                        G0 | G1 | G2 | G3 => {
                            if motion.is_some() {
                                return self.roughing_error(
                                    line,
                                    w.range.clone(),
                                    "two motion codes on one line of a contour".into(),
                                    "one motion code per line",
                                );
                            }
                            motion = Some((g / 10) as u8);
                        }
                        G33
                        | G33_1
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
                        | G38_1..=G38_5 => {
                            let text = &line.text[w.range.clone()];
                            return self.roughing_error(
                                line,
                                w.range.clone(),
                                format!("`{text}` in the contour of a {name} ({label}): LinuxCNC's cycle makes no element of it"),
                                "a contour is made of G0, G1, G2 and G3 moves",
                            );
                        }
                        _ => ignored.push(w),
                    }
                }
                'M' | 'S' | 'T' | 'F' => ignored.push(w),
                'X' | 'Z' | 'U' | 'W' | 'I' | 'K' | 'R' | 'A' | 'C' => {
                    if let Some(first) = words.insert(w.letter, w) {
                        let first = line.text[first.range.clone()].to_string();
                        return self.diag(
                            codes::ISOR_CONFLICT,
                            line,
                            w.range.clone(),
                            format!(
                                "a second {} word on the line (the first is `{first}`)",
                                w.letter
                            ),
                            "LinuxCNC refuses a line with two words of one letter; split the line",
                        );
                    }
                }
                _ => {
                    let text = &line.text[w.range.clone()];
                    return self.roughing_error(
                        line,
                        w.range.clone(),
                        format!("`{text}` in the contour of a {name} ({label}): LinuxCNC refuses it there (no command on the line uses it)"),
                        "a contour line holds X, Z (or U, W), I, K or R for arcs, and A (a rounded corner) or C (a chamfer)",
                    );
                }
            }
        }
        if !ignored.is_empty() {
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
        let Some(c) = self.contour.as_deref_mut() else {
            return;
        };
        if let Some(m) = motion {
            c.motion = m;
        }
        let arc_word = words.get(&'I').or(words.get(&'K')).or(words.get(&'R'));
        if c.motion < 2
            && let Some(w) = arc_word
        {
            let text = line.text[w.range.clone()].to_string();
            let code = if c.motion == 0 { "G0" } else { "G1" };
            return self.roughing_error(
                line,
                w.range.clone(),
                format!("`{text}` on a {code} line of a contour (LinuxCNC: \"{} word with no G2, G3… to use it\")", w.letter),
                "I, K and R belong to arcs (G2, G3)",
            );
        }
        let offset = self.axis_offset;
        let Some(c) = self.contour.as_deref_mut() else {
            return;
        };
        // The G52/G92 offset, in the contour's units (X a radius).
        let shift = if c.incremental {
            C::default()
        } else {
            C::new(offset.1 * c.unit, offset.0 / 2.0 * c.unit)
        };
        let centre_shift = C::new(offset.1 * c.unit, offset.0 / 2.0 * c.unit);
        let v = |l: char| words.get(&l).map(|w| w.value.to_f64());
        let mut end = if c.incremental { C::default() } else { c.at };
        let mut centre = C::default();
        for (axis, alias) in [('U', 'X'), ('W', 'Z')] {
            if let Some(w) = words.get(&axis) {
                let text = line.text[w.range.clone()].to_string();
                let why = if c.incremental {
                    format!(
                        "`{text}` in the contour while G91 is in force (LinuxCNC: \"G7x error: Cannot use {axis} in incremental mode (G91)\")"
                    )
                } else if words.contains_key(&alias) {
                    format!(
                        "`{text}` with {alias} on one line (LinuxCNC: \"G7x error: Cannot use {axis} and {alias} in the same block\")"
                    )
                } else {
                    continue;
                };
                return self.roughing_error(
                    line,
                    w.range.clone(),
                    why,
                    "U and W are increments of X and Z in a contour written in G90",
                );
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
        let start = c.at;
        if start == end {
            return;
        }
        let range = |l: char| words.get(&l).map(|w| w.range.clone());
        let element = match c.motion {
            0 | 1 => Element::Line { start, end },
            m => {
                let ccw = m == 3;
                if let Some(r) = v('R') {
                    if let Some(w) = range('I').or(range('K')) {
                        return self.roughing_error(
                            line,
                            w,
                            "R with I or K on one arc of a contour (LinuxCNC: \"G7X error: both R and I or K flag used for arc\")".into(),
                            "give the arc either its radius R or its centre I K",
                        );
                    }
                    let chord = (end - start).norm();
                    let h = (r * r - chord / 4.0) / chord;
                    if h.is_nan() || h < 0.0 {
                        return self.roughing_error(
                            line,
                            range('R').unwrap_or(0..line.text.len()),
                            format!("R{r} is too small for the arc of the contour: LinuxCNC's cycle would compute its centre from the square root of a negative number"),
                            "the radius must be at least half the distance from the arc's start to its end",
                        );
                    }
                    let mid = C::new((start.re + end.re) / 2.0, (start.im + end.im) / 2.0);
                    let d = C::new(0.0, h.sqrt()) * (end - start);
                    let centre = if ccw {
                        C::new(mid.re + d.re, mid.im + d.im)
                    } else {
                        C::new(mid.re - d.re, mid.im - d.im)
                    };
                    Element::Arc {
                        ccw,
                        start,
                        centre,
                        end,
                    }
                } else {
                    if arc_word.is_none() {
                        return self.roughing_error(
                            line,
                            0..line.text.len(),
                            "an arc of the contour without I, K or R (LinuxCNC: \"G7X error: either I or K must be present for arc\")".into(),
                            "give the arc its centre (I for X, K for Z) or its radius R",
                        );
                    }
                    if c.absolute_centres {
                        centre += centre_shift;
                    } else {
                        centre += start;
                    }
                    Element::Arc {
                        ccw,
                        start,
                        centre,
                        end,
                    }
                }
            }
        };
        if let (Some(a), Some(_)) = (range('A'), range('C')) {
            return self.roughing_error(
                line,
                a,
                "A and C on one corner of a contour (LinuxCNC: \"G7X error: Both A and C parameters on a corner\")".into(),
                "round the corner (A) or chamfer it (C), not both",
            );
        }
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
        if let Some(a) = v('A') {
            c.elements.push(Element::Fillet { radius: a, at: end });
            c.ir.push(ContourElement::Round {
                radius: Length::from_mm_f64(a / c.unit),
            });
        }
        if let Some(size) = v('C') {
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

    /// The contour is complete (its subroutine returned): the cycle's moves.
    pub(super) fn finish_contour(&mut self) {
        let Some(c) = self.contour.take() else {
            return;
        };
        let name = plain(c.code);
        let error = |fe: &mut Self, message: String, help: &str| {
            fe.r.diags.push(
                Diagnostic::new(codes::ISOR_ROUGHING, message)
                    .at(fe.r.src, c.span)
                    .help(help),
            );
        };
        if c.elements.len() < 2 {
            return error(
                self,
                format!(
                    "the contour of this {name} ({}) has {} element(s): LinuxCNC then cuts nothing and takes the contour's end as its position, where the tool is not",
                    c.label,
                    c.elements.len()
                ),
                "give the contour at least two moves (the first from the cycle's start)",
            );
        }
        let moves = match g7x::run(&c.cycle, c.start, &c.elements) {
            Ok(m) => m,
            Err(why) if why.starts_with(g7x::ENDLESS) => {
                return error(
                    self,
                    format!(
                        "{name} along {}: LinuxCNC's cycle does not end on this contour: its interpreter loops for ever (ncthread stops after {})",
                        c.label,
                        why.trim_start_matches(g7x::ENDLESS).trim()
                    ),
                    "change the contour (a tiny element, or arcs that meet at a cusp, are the usual causes); LinuxCNC fixed some of these loops after 2.9.0~pre1",
                );
            }
            Err(why) => {
                return error(
                    self,
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
            }
        };
        let feeds = moves.iter().any(|m| !matches!(m, Out::Rapid(_)));
        let feed = match self.feed {
            Some(f) if f.0 > 0 => f,
            _ if !feeds => Length(0),
            _ => {
                return error(
                    self,
                    format!(
                        "{name} with no feed rate (F) set, or F0: its cuts are G1 and G2/G3 moves (LinuxCNC: \"Cannot do G1 with zero feed rate\")"
                    ),
                    "set the feed with F before or on the cycle's line",
                );
            }
        };
        if feeds && self.feed_mode.is_none() {
            self.feed_mode = Some(FeedMode::PerMin);
            self.push(ItemKind::FeedMode(FeedMode::PerMin), c.span);
        }
        let unit = c.unit;
        let exact = |p: C| (2.0 * p.im / unit, p.re / unit);
        let grid = |p: C| {
            let (x, z) = exact(p);
            Pos::new(Length::from_mm_f64(x), Length::from_mm_f64(z))
        };
        let mut items = Vec::with_capacity(moves.len());
        let mut last = None;
        let mut at = self.r.pos;
        for m in &moves {
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
                            return error(
                                self,
                                format!(
                                    "{name} along {}: an arc of its path, rounded onto ncthread's 0.0001 mm grid, is one LinuxCNC refuses (radius {r1:.5} mm at its start, {r2:.5} mm at its end)",
                                    c.label
                                ),
                                "check the contour's arcs and corners",
                            );
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
        let cycle = RoughingCycle {
            code: c.code as u16,
            subroutine: c.label.clone(),
            kind: c.kind,
            start: grid(c.start),
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
            let (x, z) = exact(end);
            self.exact = (Some(x), Some(z));
        }
    }
}

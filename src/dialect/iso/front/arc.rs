//! G2/G3 in the ZX plane, with LinuxCNC's checks.

use super::super::gcode::*;
use super::super::syntax::Word;
use super::{FrontEnd, Words};
use crate::dialect::iso::codes;
use crate::fixed::Length;
use crate::ir::{ItemKind, Pos};
use crate::lower;
use crate::source::{Line, Span};

/// LinuxCNC's RADIUS_TOLERANCE (0.00005 in, 0.00127 mm). ncthread's output is in mm: an arc
/// that only the inch tolerance lets through cannot be written, so the mm one applies too.
const RADIUS_TOLERANCE: f64 = 0.00127;
/// LinuxCNC's CENTER_ARC_RADIUS_TOLERANCE in mm (2·0.01·√2 mm), with a relative 0.001.
const SPIRAL_TOLERANCE: f64 = 2.0 * 0.01 * std::f64::consts::SQRT_2;
/// CENTER_ARC_RADIUS_TOLERANCE in inches (2·0.001·√2 in), in mm.
const SPIRAL_TOLERANCE_IN: f64 = 2.0 * 0.001 * std::f64::consts::SQRT_2 * 25.4;

/// An arc being read: its code, the word its errors point at, and its start and end on the
/// grid and exact (mm, X a diameter: the values LinuxCNC computes with).
struct ArcEnds<'w> {
    g: &'static str,
    at: Option<&'w Word>,
    start: (Length, Length),
    end: (Length, Length),
    start_exact: (f64, f64),
    end_exact: (f64, f64),
}

impl FrontEnd<'_> {
    pub(super) fn arc_error(
        &mut self,
        line: Line<'_>,
        at: Option<&Word>,
        message: String,
        help: &str,
    ) {
        let range = at.map_or(0..line.text.len(), |w| w.range.clone());
        self.diag(codes::ISOR_ARC, line, range, message, help);
    }

    /// G2/G3 in the ZX plane, as LinuxCNC reads it: the end (an axis not given stays), the
    /// centre from I and K (an offset from the start under G91.1, the centre itself under
    /// G90.1; in radius units whatever G7/G8 says, as LinuxCNC halves only X) or from R,
    /// and LinuxCNC's checks of both. The centre is rounded once onto the grid.
    /// **\[evidence\]** LinuxCNC `convert_arc`, `arc_data_ijk`, `arc_data_r` (interp_arc.cc).
    pub(super) fn arc(
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
        if !self.comp_arc_allowed(line, at) {
            return;
        }
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
        if let Some(p) = p
            && !self.arc_turns(line, g, p)
        {
            return;
        }
        let end = Pos::new(target.x.unwrap_or(sx), target.z.unwrap_or(sz));
        let a = ArcEnds {
            g,
            at,
            start: (sx, sz),
            end: (end.x.unwrap_or(sx), end.z.unwrap_or(sz)),
            start_exact: (sx_e, sz_e),
            end_exact: (
                self.exact_target.0.unwrap_or(sx_e),
                self.exact_target.1.unwrap_or(sz_e),
            ),
        };
        let centre_exact = self.centre_exact(line, &a, (i, k, r), target, clockwise);
        let Some(centre) = centre_exact.and_then(|c| self.arc_centre(line, &a, c)) else {
            return;
        };
        if !self.comp_arc(line, at, (a.start_exact, a.end_exact), (i, k, r), clockwise) {
            return;
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

    /// The exact centre, from R or from I and K (not both, not neither), or `None` after an
    /// error.
    fn centre_exact(
        &mut self,
        line: Line<'_>,
        a: &ArcEnds<'_>,
        (i, k, r): (Option<&Word>, Option<&Word>, Option<&Word>),
        target: Pos,
        clockwise: bool,
    ) -> Option<(f64, f64)> {
        let g = a.g;
        match (r, i.is_some() || k.is_some()) {
            (Some(_), true) => {
                self.arc_error(
                    line,
                    r,
                    format!(
                        "{g} with both R and I/K (LinuxCNC: \"Mixed radius ijk format for arc\")"
                    ),
                    "give the arc either its radius R or its centre I K",
                );
                None
            }
            (None, false) => {
                self.arc_error(
                    line,
                    a.at,
                    format!(
                        "{g} without R, I or K (LinuxCNC: \"R i j k words all missing for arc\")"
                    ),
                    "give the arc its radius (R) or its centre (I for X, K for Z)",
                );
                None
            }
            (Some(r), false) => {
                self.comp_arc_start(line, a.at, (a.start_exact, a.end_exact), Some(r), clockwise)?;
                self.centre_from_r(line, a, r, target, clockwise)
            }
            (None, true) => {
                self.comp_arc_start(line, a.at, (a.start_exact, a.end_exact), None, clockwise)?;
                self.centre_from_ik(line, a, i, k)
            }
        }
    }

    /// An arc's P: one turn (LinuxCNC takes P within 0.001 of a whole number as that
    /// number); false after an error.
    fn arc_turns(&mut self, line: Line<'_>, g: &str, p: &Word) -> bool {
        let turns = p.value.to_f64();
        let whole = turns.round();
        if (turns - whole).abs() > 0.001 || whole < 1.0 {
            self.arc_error(
                line,
                Some(p),
                format!("{g} P must be a whole number of turns, 1 or more (LinuxCNC: \"P value not an integer with M19 G2 or G3\" or \"P value should be 1 or greater with G2 or G3\")"),
                "leave P out for an arc of less than one turn",
            );
            return false;
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
            return false;
        }
        true
    }

    /// The exact centre of an R arc, after LinuxCNC's checks of R, or `None` after an error.
    fn centre_from_r(
        &mut self,
        line: Line<'_>,
        a: &ArcEnds<'_>,
        r: &Word,
        target: Pos,
        clockwise: bool,
    ) -> Option<(f64, f64)> {
        let g = a.g;
        let refusal = if target.x.is_none() && target.z.is_none() {
            Some((
                format!(
                    "{g} R without X or Z (LinuxCNC: \"X and z words missing for arc in xz plane\")"
                ),
                "an R arc cannot be a full circle: give its end point",
            ))
        } else if a.start_exact == a.end_exact {
            Some((
                format!(
                    "{g} R ends where it starts (LinuxCNC: \"Current point same as end point of arc\")"
                ),
                "an R arc cannot be a full circle: write it with I and K",
            ))
        } else if a.start == a.end {
            Some((
                format!(
                    "{g} R ends within 0.0001 mm of its start: on ncthread's grid that is a full circle, which an R arc cannot be"
                ),
                "write the arc with I and K, or end it on the grid",
            ))
        } else {
            None
        };
        if let Some((message, help)) = refusal {
            self.arc_error(line, Some(r), message, help);
            return None;
        }
        let unit = if self.inch { 25.4 } else { 1.0 };
        let radius = r.value.to_f64() * unit;
        let text = &line.text[r.range.clone()];
        if radius.abs() < RADIUS_TOLERANCE {
            self.arc_error(
                line,
                Some(r),
                format!("`{text}`: a radius under 0.00127 mm, which ncthread would write as a centre arc that LinuxCNC refuses as zero-radius"),
                "leave the arc out, or give it a real radius",
            );
            return None;
        }
        if !radius.is_finite() || radius.abs() > 1e6 {
            self.number_error(
                line,
                r,
                format!("`{text}` is too large for an arc radius"),
                "an arc radius is at most 1,000,000 mm",
            );
            return None;
        }
        let centre = lower::arc::centre_from_radius_mm(
            a.start_exact,
            a.end_exact,
            radius,
            clockwise,
            RADIUS_TOLERANCE,
        );
        if let Err(chord) = centre {
            self.arc_error(
                line,
                Some(r),
                format!("`{text}` is too small for the arc: its end is {chord:.5} mm from its start (LinuxCNC: \"Arc radius too small to reach end point\")"),
                "the radius must be at least half the distance from the start to the end",
            );
        }
        centre.ok()
    }

    /// The exact centre of an I/K arc, or `None` after an error. Under G90.1 both are
    /// required.
    fn centre_from_ik(
        &mut self,
        line: Line<'_>,
        a: &ArcEnds<'_>,
        i: Option<&Word>,
        k: Option<&Word>,
    ) -> Option<(f64, f64)> {
        if self.absolute_centres {
            for (word, letter) in [(i, 'I'), (k, 'K')] {
                if word.is_none() {
                    let g = a.g;
                    self.arc_error(
                        line,
                        a.at,
                        format!("{g} without {letter} under G90.1 (LinuxCNC: \"{letter} word missing in absolute center arc\")"),
                        "under G90.1, I and K give the arc's centre: write both",
                    );
                    return None;
                }
            }
        }
        // Range checks (and the rounding warning) as for every length word.
        for w in [i, k].into_iter().flatten() {
            self.length_times(line, w, 2)?;
        }
        // I is a radius: the centre's diameter is twice it.
        let unit = if self.inch { 25.4 } else { 1.0 };
        let value = |w: Option<&Word>| w.map_or(0.0, |w| w.value.to_f64() * unit);
        let (i_e, k_e) = (2.0 * value(i), value(k));
        Some(if self.absolute_centres {
            (i_e + self.axis_offset.0, k_e + self.axis_offset.1)
        } else {
            (a.start_exact.0 + i_e, a.start_exact.1 + k_e)
        })
    }

    /// The centre on the grid, after LinuxCNC's checks of the arc (a full circle that is
    /// none, a zero radius, an end off the circle, a centre far away), or `None` after an
    /// error.
    fn arc_centre(
        &mut self,
        line: Line<'_>,
        a: &ArcEnds<'_>,
        centre_exact: (f64, f64),
    ) -> Option<Pos> {
        if !self.arc_on_circle(line, a, centre_exact) {
            return None;
        }
        if !(centre_exact.0.is_finite() && centre_exact.1.is_finite())
            || centre_exact.0.abs() > 1e9
            || centre_exact.1.abs() > 1e9
        {
            let g = a.g;
            self.arc_error(
                line,
                a.at,
                format!("{g}'s centre is more than 1,000 km away"),
                "check I, K or R",
            );
            return None;
        }
        // The centre, computed from the values as written, rounded once onto the grid.
        let centre = Pos::new(
            Length::from_mm_f64(centre_exact.0),
            Length::from_mm_f64(centre_exact.1),
        );
        self.rounded_arc_passes(line, a, centre).then_some(centre)
    }

    /// LinuxCNC's checks of the exact arc: not a full circle on the grid that is none
    /// exactly, not of zero radius, its end on its circle; false after an error.
    fn arc_on_circle(&mut self, line: Line<'_>, a: &ArcEnds<'_>, centre_exact: (f64, f64)) -> bool {
        let g = a.g;
        if a.start == a.end && a.start_exact != a.end_exact {
            self.arc_error(
                line,
                a.at,
                format!("{g} ends within 0.0001 mm of its start without ending there: on ncthread's grid that is a full circle"),
                "end the arc on the grid, or write the full circle with the end at the start",
            );
            return false;
        }
        let (r1, r2) = lower::arc::radii_mm(a.start_exact, a.end_exact, centre_exact);
        let which = if self.absolute_centres {
            "G90.1"
        } else {
            "G91.1"
        };
        if r1 < RADIUS_TOLERANCE || r2 < RADIUS_TOLERANCE {
            self.arc_error(
                line,
                a.at,
                format!("{g} with a zero radius: its centre is on its start or its end (LinuxCNC: \"Zero-radius arc\")"),
                &format!("check I and K: under {which} they are {}, I in radius", if self.absolute_centres { "the centre itself" } else { "the centre's offset from the start" }),
            );
            return false;
        }
        let abs_err = (r1 - r2).abs();
        let rel_err = abs_err / r1.max(r2);
        let off_circle = |tolerance: f64| {
            abs_err > tolerance * 100.0 || (rel_err > 0.001 && abs_err > tolerance)
        };
        if off_circle(if self.inch {
            SPIRAL_TOLERANCE_IN
        } else {
            SPIRAL_TOLERANCE
        }) {
            self.arc_error(
                line,
                a.at,
                format!(
                    "{g}'s end is not on its circle: the radius is {r1:.5} mm at the start and {r2:.5} mm at the end (LinuxCNC: \"Radius to end of arc differs from radius to start\")"
                ),
                &format!("check I and K: under {which} I is a radius (not halved by G7)"),
            );
            return false;
        }
        if off_circle(SPIRAL_TOLERANCE) {
            self.arc_error(
                line,
                a.at,
                format!(
                    "{g}'s end is {abs_err:.4} mm off its circle: LinuxCNC lets that through in inches, not in millimetres, and ncthread writes millimetres"
                ),
                "put the end on the circle within 0.028 mm",
            );
            return false;
        }
        true
    }

    /// What ncthread writes is the rounded arc: it must pass LinuxCNC's checks too (a value
    /// with more than four decimals can sit right at a limit); false after an error.
    fn rounded_arc_passes(&mut self, line: Line<'_>, a: &ArcEnds<'_>, centre: Pos) -> bool {
        let (sx, sz) = a.start;
        let (q1, q2) = lower::arc::radii(
            a.start,
            a.end,
            (centre.x.unwrap_or(sx), centre.z.unwrap_or(sz)),
        );
        let q_err = (q1 - q2).abs();
        if q1 < RADIUS_TOLERANCE
            || q2 < RADIUS_TOLERANCE
            || q_err > SPIRAL_TOLERANCE * 100.0
            || (q_err / q1.max(q2) > 0.001 && q_err > SPIRAL_TOLERANCE)
        {
            let g = a.g;
            self.arc_error(
                line,
                a.at,
                format!("{g} is right at one of LinuxCNC's arc limits: rounded onto ncthread's 0.0001 mm grid (radius {q1:.5} mm at the start, {q2:.5} mm at the end) LinuxCNC would refuse it"),
                "write the arc's values with at most four decimals in mm, away from the limits (a radius of 0.00127 mm; an end 0.028 mm off the circle)",
            );
            return false;
        }
        true
    }
}

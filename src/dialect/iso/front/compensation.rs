//! Cutter radius compensation whose radius ncthread knows: G41.1/G42.1 with a diameter D > 0.
//! ncthread keeps the programmed path (LinuxCNC compensates what ncthread writes as it does the
//! source), but LinuxCNC refuses some compensated paths, and what it refuses the reader must
//! refuse. So the reader follows LinuxCNC 2.9.0~pre1's compensation here, as far as its
//! refusals need: the tool's compensated point, the programmed point, and the queue of
//! compensated moves that a later corner may still shorten (`interp_queue.cc`).
//!
//! G41/G42 take the radius from the machine's tool table, which ncthread does not know: they
//! are left alone (with radius 0, as in the oracle's tool table, LinuxCNC compensates nothing).
//!
//! The model works as LinuxCNC does: in the program's units (mm or inches), X a radius, in its
//! compensation plane's coordinates, which in G18 are (Z, X): Z first, X second. Its values
//! come from the reader's exact positions (mm, X a diameter, the G52/G92 offset added), turned
//! back into LinuxCNC's. The arithmetic is LinuxCNC's, in its order, with one difference:
//! LinuxCNC adds its π constants as `long double` (`M_PIl`), here they are doubles, so an
//! angle may differ in its last bit (no decision turns on that but an exact tie).
//!
//! **[evidence]** `interp_convert.cc`: `convert_straight_comp1` (LinuxCNC line 5162),
//! `convert_straight_comp2` (5291), `convert_arc_comp1` (647), `convert_arc_comp2` (797),
//! `convert_cutter_compensation_off` (1910), `convert_stop` (4554), `convert_straight`'s G53
//! check (4814) and `convert_arc`'s `arc_not_allowed` (382); `interp_arc.cc`:
//! `arc_data_comp_ijk` (78), `arc_data_comp_r` (201), `arc_data_ijk`, `arc_data_r`;
//! `interp_queue.cc`: `move_endpoint_and_flush` (571), `dequeue_canons`, `qc_scale`;
//! `interp_find.cc`: `find_turn` (687).

use std::f64::consts::{FRAC_PI_2, PI, SQRT_2};

use super::super::syntax::Word;
use super::FrontEnd;
use crate::dialect::iso::codes;
use crate::source::Line;

/// A point in the compensation plane: (Z, X radius), in the program's units.
type P = (f64, f64);

/// TOLERANCE_CONCAVE_CORNER (radians).
const CONCAVE_CORNER: f64 = 0.05;
/// TOLERANCE_EQUAL.
const TOLERANCE_EQUAL: f64 = 0.0001;
/// RADIUS_TOLERANCE_INCH, and in mm.
const RADIUS_TOLERANCE_INCH: f64 = 0.00005;
const RADIUS_TOLERANCE_MM: f64 = RADIUS_TOLERANCE_INCH * 25.4;
/// CENTER_ARC_RADIUS_TOLERANCE (LinuxCNC's defaults, which the oracle runs with).
const SPIRAL_INCH: f64 = 2.0 * 0.001 * SQRT_2;
const SPIRAL_MM: f64 = 2.0 * 0.01 * SQRT_2;
/// SPIRAL_RELATIVE_TOLERANCE.
const SPIRAL_RELATIVE: f64 = 0.001;
/// TINY (`arc_data_r`).
const TINY: f64 = 1e-12;

/// Why LinuxCNC refuses a compensated move: its message, what it means on this path, and
/// what to do.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Refusal {
    pub linuxcnc: String,
    pub what: &'static str,
    pub help: &'static str,
}

fn refusal(linuxcnc: &str, what: &'static str, help: &'static str) -> Refusal {
    Refusal {
        linuxcnc: linuxcnc.to_string(),
        what,
        help,
    }
}

const MOVE_HELP: &str = "change the path where the tool cannot follow it with this radius (D is the tool's diameter, its radius D/2), or program the tool's path without compensation";

fn too_small_for_tool() -> Refusal {
    refusal(
        "Tool radius not less than arc radius with comp",
        "the tool (radius D/2) does not fit inside the arc",
        "an arc the tool cuts from inside needs a radius greater than the tool's (D/2)",
    )
}

fn gouge(linuxcnc: &str) -> Refusal {
    refusal(
        linuxcnc,
        "the compensated tool cannot follow the path into this concave corner without cutting into the part",
        MOVE_HELP,
    )
}

/// A compensated move LinuxCNC holds back, since the next move's corner may still move its end.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Queued {
    /// STRAIGHT_TRAVERSE / STRAIGHT_FEED: the programmed direction, the compensated end.
    Straight { traverse: bool, dir: P, end: P },
    /// ARC_FEED: the sweep it was queued with, its end, centre and turn (+1 counterclockwise).
    Arc {
        original_turns: f64,
        end: P,
        centre: P,
        turn: i32,
    },
}

/// A compensation on with a known radius: LinuxCNC's `cutter_comp_*`, `program_*` and
/// `current_*` in the compensation plane.
#[derive(Clone, Copy, Debug)]
struct Session {
    left: bool,
    radius: f64,
    orientation: i64,
    /// `cutter_comp_firstmove`: no move yet.
    first: bool,
    /// The programmed point (`program_*`), set by the first move.
    program: P,
    /// The tool's compensated point (`current_*`), set by the first move.
    current: P,
}

/// An arc's centre as its words give it, in the program's units (I is a radius).
#[derive(Clone, Copy, Debug)]
pub(super) enum Centre {
    R(f64),
    Ik { i: f64, k: f64, absolute: bool },
}

/// LinuxCNC's compensation state and its queue (`interp_queue.cc`'s statics live across
/// compensation sessions: the queue's end point too).
#[derive(Clone, Debug, Default)]
pub(super) struct Model {
    session: Option<Session>,
    queue: Vec<Queued>,
    /// What `qc().front()` reads of an empty queue: the vector's first slot as it was left
    /// (LinuxCNC reads it after M0/M1 emptied the queue; `clear` leaves the memory as it was).
    slot0: Option<Queued>,
    /// `endpoint` and `endpoint_valid`.
    endpoint: P,
    endpoint_valid: bool,
    /// `arc_not_allowed`: compensation was just turned off after compensated moves.
    arc_not_allowed: bool,
    /// The units the values are in.
    inch: bool,
}

/// `v > 1.0 || v < -1.0`, as LinuxCNC tests an asin's or acos's argument: a NaN is not
/// beyond (`!(-1.0..=1.0).contains(&v)` would take it for beyond).
#[allow(clippy::manual_range_contains)]
fn beyond_one(v: f64) -> bool {
    v > 1.0 || v < -1.0
}

/// TOOL_INSIDE_ARC.
fn inside(left: bool, turn: i32) -> bool {
    (left && turn > 0) || (!left && turn < 0)
}

/// `find_turn`: the signed sweep of an arc from `a` to `b` around `c`.
fn find_turn(a: P, c: P, turn: i32, b: P) -> f64 {
    if turn == 0 {
        return 0.0;
    }
    let mut alpha = (a.1 - c.1).atan2(a.0 - c.0);
    let mut beta = (b.1 - c.1).atan2(b.0 - c.0);
    if turn > 0 {
        if beta <= alpha {
            beta += 2.0 * PI;
        }
        (beta - alpha) + f64::from(turn - 1) * (2.0 * PI)
    } else {
        if alpha <= beta {
            alpha += 2.0 * PI;
        }
        (beta - alpha) + f64::from(turn + 1) * (2.0 * PI)
    }
}

fn hypot(a: f64, b: f64) -> f64 {
    a.hypot(b)
}

impl Model {
    /// A compensation with a known radius is on.
    pub(super) fn active(&self) -> bool {
        self.session.is_some()
    }

    fn radius_tolerance(&self) -> f64 {
        if self.inch {
            RADIUS_TOLERANCE_INCH
        } else {
            RADIUS_TOLERANCE_MM
        }
    }

    fn spiral(&self) -> f64 {
        if self.inch { SPIRAL_INCH } else { SPIRAL_MM }
    }

    /// G20/G21: `convert_length_units` scales the points, the radius and the queue
    /// (`qc_scale`, which scales the end point once per queued canon and not at all when
    /// the queue is empty; here once per queued move, the only canons ncthread follows).
    pub(super) fn units(&mut self, inch: bool) {
        if inch == self.inch {
            return;
        }
        self.inch = inch;
        let s = if inch { 1.0 / 25.4 } else { 25.4 };
        let scale = |p: &mut P| *p = (p.0 * s, p.1 * s);
        if let Some(session) = &mut self.session {
            scale(&mut session.program);
            scale(&mut session.current);
            session.radius *= s;
        }
        for q in &mut self.queue {
            scale(&mut self.endpoint);
            match q {
                Queued::Straight { end, .. } => scale(end),
                Queued::Arc { end, centre, .. } => {
                    scale(end);
                    scale(centre);
                }
            }
        }
    }

    /// G41.1/G42.1 with a radius (D/2) greater than 0, in the current units.
    pub(super) fn on(&mut self, left: bool, radius: f64, orientation: i64) {
        self.session = Some(Session {
            left,
            radius,
            orientation,
            first: true,
            program: (0.0, 0.0),
            current: (0.0, 0.0),
        });
    }

    /// G41/G42 (a radius ncthread does not know), or a refusal: nothing more is followed.
    pub(super) fn forget(&mut self) {
        self.session = None;
        self.arc_not_allowed = false;
        self.queue.clear();
        self.endpoint_valid = false;
    }

    /// G40: `convert_cutter_compensation_off`.
    pub(super) fn off(&mut self) -> Result<(), Refusal> {
        let Some(s) = self.session.take() else {
            return Ok(());
        };
        if !s.first {
            self.move_endpoint_and_flush(s.current)?;
            self.dequeue();
            self.arc_not_allowed = true;
        }
        Ok(())
    }

    /// M0, M1, M2, M30: `convert_stop` flushes the queue where the tool is; M2/M30 also turn
    /// compensation off.
    pub(super) fn stop(&mut self, end: bool) -> Result<(), Refusal> {
        if let Some(s) = self.session {
            let result = self.move_endpoint_and_flush(s.current);
            self.dequeue();
            result?;
        }
        if end {
            self.session = None;
        }
        Ok(())
    }

    /// A move `convert_straight` makes that is not G0/G1 under compensation (G33, G33.1, G76,
    /// a G70–G72 cycle's): it allows an arc again.
    pub(super) fn straight_motion(&mut self) {
        self.arc_not_allowed = false;
    }

    /// `convert_arc`'s first check.
    pub(super) fn arc_allowed(&self) -> Result<(), Refusal> {
        if self.arc_not_allowed {
            return Err(refusal(
                "The move just after exiting cutter compensation mode must be straight, not an arc",
                "an arc right after G40, where LinuxCNC moves the tool back onto the programmed path",
                "put a G0 or G1 move between the G40 and the arc",
            ));
        }
        Ok(())
    }

    /// G53 under compensation with a known radius (`convert_straight`).
    pub(super) fn machine_move(&self) -> Result<(), Refusal> {
        if self.active() {
            return Err(refusal(
                "Cannot use g53 with cutter radius comp",
                "a move in machine coordinates while cutter radius compensation (D > 0) is on",
                "turn the compensation off with G40 first",
            ));
        }
        Ok(())
    }

    /// A G0/G1 (`traverse`: G0) from `start` (where the tool is, used by the first move only)
    /// to `end`: `convert_straight_comp1` or `convert_straight_comp2`.
    pub(super) fn straight(&mut self, traverse: bool, start: P, end: P) -> Result<(), Refusal> {
        self.arc_not_allowed = false;
        let Some(s) = self.session else {
            return Ok(());
        };
        let result = if s.first {
            self.straight_first(s, traverse, start, end)
        } else {
            self.straight_next(s, traverse, end)
        };
        if result.is_err() {
            self.forget();
        }
        result
    }

    fn straight_first(
        &mut self,
        mut s: Session,
        traverse: bool,
        c: P,
        p: P,
    ) -> Result<(), Refusal> {
        let radius = s.radius;
        let distance = hypot(p.0 - c.0, p.1 - c.1);
        if distance <= radius {
            return Err(refusal(
                "Length of cutter compensation entry move is not greater than the tool radius",
                "the move that starts the compensation is not longer than the tool's radius (D/2)",
                "start the compensation farther from the path: its first move must be longer than D/2",
            ));
        }
        let alpha = (p.1 - c.1).atan2(p.0 - c.0) + if s.left { PI / 2.0 } else { -PI / 2.0 };
        let end = (p.0 + radius * alpha.cos(), p.1 + radius * alpha.sin());
        self.set_endpoint(c);
        self.enqueue(Queued::Straight {
            traverse,
            dir: (alpha.cos(), alpha.sin()),
            end,
        });
        s.first = false;
        s.current = end;
        s.program = p;
        self.session = Some(s);
        Ok(())
    }

    fn straight_next(&mut self, mut s: Session, traverse: bool, p: P) -> Result<(), Refusal> {
        let (c, op) = (s.current, s.program);
        let mut end = c;
        if p.1 == op.1 && p.0 == op.0 {
            // No motion in the plane.
            self.enqueue(Queued::Straight {
                traverse,
                dir: (p.0 - op.0, p.1 - op.1),
                end: c,
            });
        } else {
            let radius = s.radius;
            let mut theta = (c.1 - op.1).atan2(c.0 - op.0);
            let mut alpha = (p.1 - op.1).atan2(p.0 - op.0);
            let (beta, gamma) = if s.left {
                if theta < alpha {
                    theta += 2.0 * PI;
                }
                ((theta - alpha) - FRAC_PI_2, FRAC_PI_2)
            } else {
                if alpha < theta {
                    alpha += 2.0 * PI;
                }
                ((alpha - theta) - FRAC_PI_2, -FRAC_PI_2)
            };
            end = (
                p.0 + radius * (alpha + gamma).cos(),
                p.1 + radius * (alpha + gamma).sin(),
            );
            let mid = (
                op.0 + radius * (alpha + gamma).cos(),
                op.1 + radius * (alpha + gamma).sin(),
            );
            let small = CONCAVE_CORNER;
            let concave = if beta < -small || beta > PI + small {
                true
            } else {
                // The "h" shape: over a round part, then along a straight one.
                beta > PI - small
                    && matches!(self.queue.first(), Some(Queued::Arc { turn, .. })
                        if (!s.left && *turn > 0) || (s.left && *turn < 0))
            };
            if !concave && beta > small {
                // A convex corner: an arc around it (G0: a traverse).
                self.move_endpoint_and_flush(c)?;
                if traverse {
                    self.enqueue(Queued::Straight {
                        traverse,
                        dir: (0.0, 0.0),
                        end: mid,
                    });
                } else {
                    self.enqueue(Queued::Arc {
                        original_turns: 0.0,
                        end: mid,
                        centre: op,
                        turn: if s.left { -1 } else { 1 },
                    });
                }
                self.dequeue();
                self.set_endpoint(mid);
            } else if concave {
                let m = self.concave_before_line(&s, (op, p, c), theta, gamma, beta)?;
                self.move_endpoint_and_flush(m)?;
            } else {
                // Straight on (collinear, or tangent from an arc).
                self.dequeue();
                self.set_endpoint(c);
            }
            self.enqueue(Queued::Straight {
                traverse,
                dir: (p.0 - op.0, p.1 - op.1),
                end,
            });
        }
        s.current = end;
        s.program = p;
        self.session = Some(s);
        Ok(())
    }

    /// Where the queued move ends at a concave corner before a line from `op` to `p` (the
    /// tool at `c`): `convert_straight_comp2`'s line→line and arc→line cases.
    fn concave_before_line(
        &self,
        s: &Session,
        (op, p, c): (P, P, P),
        theta: f64,
        gamma: f64,
        beta: f64,
    ) -> Result<P, Refusal> {
        let radius = s.radius;
        let Some(Queued::Arc {
            end: prev_end,
            centre: prev_centre,
            turn: prev_turn,
            ..
        }) = self.front()
        else {
            // line → line
            let halfcorner = (beta + PI) / 2.0;
            if halfcorner == 0.0 {
                return Err(refusal(
                    "Zero degree inside corner is invalid for cutter compensation",
                    "the path turns straight back on itself",
                    MOVE_HELP,
                ));
            }
            let retreat = radius / halfcorner.tan();
            return Ok((
                c.0 + retreat * (theta + gamma).cos(),
                c.1 + retreat * (theta + gamma).sin(),
            ));
        };
        // arc → line: the queued arc is the compensated one.
        let oldrad = hypot(prev_centre.1 - prev_end.1, prev_centre.0 - prev_end.0);
        let base_dir = (p.1 - op.1).atan2(p.0 - op.0);
        let theta = if prev_turn > 0 {
            base_dir + FRAC_PI_2
        } else {
            base_dir - FRAC_PI_2
        };
        let phi = (prev_centre.1 - op.1).atan2(prev_centre.0 - op.0);
        let tool_inside = inside(s.left, prev_turn);
        let oldrad_uncomp = if tool_inside {
            oldrad + radius
        } else {
            oldrad - radius
        };
        let alpha = theta - phi;
        let d = oldrad_uncomp * alpha.cos();
        let d2 = if tool_inside { d - radius } else { d + radius };
        let l = d2 / oldrad;
        if beyond_one(l) {
            return Err(gouge(
                "Arc to straight motion makes a corner the compensated tool can't fit in without gouging",
            ));
        }
        let angle_from_center = if tool_inside == (prev_turn > 0) {
            -l.acos() + theta + PI
        } else {
            l.acos() + theta + PI
        };
        Ok((
            prev_centre.0 + oldrad * angle_from_center.cos(),
            prev_centre.1 + oldrad * angle_from_center.sin(),
        ))
    }

    /// `convert_arc_comp1`'s first check, and `arc_data_comp_r`'s, before the arc's centre:
    /// the first compensated move is an arc from `start` to `end`.
    pub(super) fn arc_start(
        &mut self,
        start: P,
        end: P,
        r: Option<f64>,
        clockwise: bool,
    ) -> Result<(), Refusal> {
        let Some(s) = self.session.filter(|s| s.first) else {
            return Ok(());
        };
        let result = if hypot(end.0 - start.0, end.1 - start.1) <= s.radius {
            Err(refusal(
                "Radius of cutter compensation entry arc is not greater than the tool radius",
                "the arc that starts the compensation ends within the tool's radius (D/2) of where the tool is",
                "start the compensation with a G1 move longer than D/2 before the arc",
            ))
        } else if r.is_some_and(|r| r.abs() <= s.radius && inside(s.left, turn_of(clockwise))) {
            Err(too_small_for_tool())
        } else {
            Ok(())
        };
        if result.is_err() {
            self.forget();
        }
        result
    }

    /// A G2/G3 (`clockwise`: G2) from `start` (where the tool is, used by the first move
    /// only) to `end`: `convert_arc_comp1` or `convert_arc_comp2`.
    pub(super) fn arc(
        &mut self,
        start: P,
        end: P,
        centre: Centre,
        clockwise: bool,
    ) -> Result<(), Refusal> {
        let Some(s) = self.session else {
            return Ok(());
        };
        let result = if s.first {
            self.arc_first(s, start, end, centre, clockwise)
        } else {
            self.arc_next(s, end, centre, clockwise)
        };
        if result.is_err() {
            self.forget();
        }
        result
    }

    /// `arc_data_ijk` / `arc_data_r` (with `arc_data_comp_*`'s tool check when `comp`): the
    /// centre of the arc from `c` to `end`.
    fn arc_data(
        &self,
        c: P,
        end: P,
        centre: Centre,
        turn: i32,
        comp: Option<&Session>,
    ) -> Result<P, Refusal> {
        let tool_inside = comp.filter(|s| inside(s.left, turn));
        match centre {
            Centre::Ik { i, k, absolute } => {
                let centre = if absolute { (k, i) } else { (c.0 + k, c.1 + i) };
                let arc_radius = hypot(centre.0 - c.0, centre.1 - c.1);
                let radius2 = hypot(centre.0 - end.0, centre.1 - end.1);
                let tolerance = self.radius_tolerance();
                if arc_radius < tolerance || radius2 < tolerance {
                    return Err(refusal(
                        "Zero-radius arc",
                        "the arc's centre is on its start or its end",
                        "check I and K",
                    ));
                }
                let abs_err = (arc_radius - radius2).abs();
                let rel_err = abs_err / arc_radius.max(radius2);
                let spiral = self.spiral();
                if abs_err > spiral * 100.0 || (rel_err > SPIRAL_RELATIVE && abs_err > spiral) {
                    return Err(refusal(
                        "Radius to end of arc differs from radius to start",
                        "the arc's end is not on its circle",
                        "check I and K",
                    ));
                }
                if tool_inside.is_some_and(|s| arc_radius <= s.radius) {
                    return Err(too_small_for_tool());
                }
                Ok(centre)
            }
            Centre::R(radius) => {
                if end.0 == c.0 && end.1 == c.1 {
                    return Err(refusal(
                        "Current point same as end point of arc",
                        "an R arc that ends where it starts",
                        "write the arc with I and K",
                    ));
                }
                let abs_radius = radius.abs();
                let mid = ((end.0 + c.0) / 2.0, (end.1 + c.1) / 2.0);
                let mut half_length = hypot(mid.0 - end.0, mid.1 - end.1);
                if (half_length - abs_radius) > self.radius_tolerance() {
                    return Err(refusal(
                        "Arc radius too small to reach end point",
                        "R is less than half the distance from the start to the end",
                        "check R",
                    ));
                }
                if half_length / abs_radius > (1.0 - TINY) {
                    half_length = abs_radius;
                }
                let chord = (end.1 - c.1).atan2(end.0 - c.0);
                let theta = if (turn < 0 && radius > 0.0) || (turn > 0 && radius < 0.0) {
                    chord - FRAC_PI_2
                } else {
                    chord + FRAC_PI_2
                };
                let turn2 = (half_length / abs_radius).asin();
                let offset = abs_radius * turn2.cos();
                Ok((mid.0 + offset * theta.cos(), mid.1 + offset * theta.sin()))
            }
        }
    }

    fn arc_first(
        &mut self,
        mut s: Session,
        c: P,
        programmed_end: P,
        centre: Centre,
        clockwise: bool,
    ) -> Result<(), Refusal> {
        let turn = turn_of(clockwise);
        let radius = s.radius;
        let centre = self.arc_data(c, programmed_end, centre, turn, Some(&s))?;
        let (pe, ce) = (programmed_end, centre);
        let gamma = if inside(s.left, turn) {
            (ce.1 - pe.1).atan2(ce.0 - pe.0)
        } else {
            (pe.1 - ce.1).atan2(pe.0 - ce.0)
        };
        s.first = false;
        s.program = programmed_end;
        let end = (pe.0 + radius * gamma.cos(), pe.1 + radius * gamma.sin());
        // The compensated arc's centre: on the line from its end towards the programmed
        // centre, as far from its start as from its end.
        let b_len = hypot(c.1 - end.1, c.0 - end.0) / 2.0;
        let ab_ang = (ce.1 - end.1).atan2(ce.0 - end.0);
        let a_ang = (c.1 - end.1).atan2(c.0 - end.0) - ab_ang;
        if a_ang.cos().abs() < TOLERANCE_EQUAL {
            return Err(too_small_for_tool());
        }
        let c_len = b_len / a_ang.cos();
        let centre = (end.0 + c_len * ab_ang.cos(), end.1 + c_len * ab_ang.sin());
        if (hypot(centre.0 - end.0, centre.1 - end.1) - hypot(centre.0 - c.0, centre.1 - c.1)).abs()
            > self.spiral()
        {
            return Err(refusal(
                "Bug in tool radius comp",
                "LinuxCNC cannot place the compensated entry arc",
                MOVE_HELP,
            ));
        }
        if s.orientation != 0 && s.orientation != 9 {
            // A lathe tool's origin moves first: a line to where the tool is.
            self.enqueue(Queued::Straight {
                traverse: false,
                dir: (0.0, 0.0),
                end: c,
            });
            self.set_endpoint(c);
        }
        self.enqueue(Queued::Arc {
            original_turns: find_turn(c, centre, turn, end),
            end,
            centre,
            turn,
        });
        s.current = end;
        self.session = Some(s);
        Ok(())
    }

    fn arc_next(
        &mut self,
        mut s: Session,
        end: P,
        centre: Centre,
        clockwise: bool,
    ) -> Result<(), Refusal> {
        let (op, c) = (s.program, s.current);
        let turn = turn_of(clockwise);
        let ce = self.arc_data(op, end, centre, turn, None)?;
        let radius = s.radius;
        let arc_radius = hypot(ce.0 - end.0, ce.1 - end.1);
        let theta = (c.1 - op.1).atan2(c.0 - op.0);
        let theta = theta + if s.left { -FRAC_PI_2 } else { FRAC_PI_2 };
        let mut delta = (ce.1 - op.1).atan2(ce.0 - op.0);
        let alpha = delta + if clockwise { FRAC_PI_2 } else { -FRAC_PI_2 };
        let mut beta = if s.left { theta - alpha } else { alpha - theta };
        // beta from -90° to 270°
        beta = if beta > 1.5 * PI {
            beta - 2.0 * PI
        } else if beta < -FRAC_PI_2 {
            beta + 2.0 * PI
        } else {
            beta
        };
        let gamma = if inside(s.left, turn) {
            if arc_radius <= radius {
                return Err(too_small_for_tool());
            }
            (ce.1 - end.1).atan2(ce.0 - end.0)
        } else {
            delta += PI;
            (end.1 - ce.1).atan2(end.0 - ce.0)
        };
        let new_end = (end.0 + radius * gamma.cos(), end.1 + radius * gamma.sin());
        let small = CONCAVE_CORNER;
        let main = Queued::Arc {
            original_turns: find_turn(op, ce, turn, end),
            end: new_end,
            centre: ce,
            turn,
        };
        if beta < -small
            || beta > PI + small
            || ((beta - PI).abs() < small && !inside(s.left, turn))
        {
            // A concave corner.
            let m = self.concave_before_arc(&s, (ce, turn, arc_radius), theta, beta)?;
            self.move_endpoint_and_flush(m)?;
            self.enqueue(main);
        } else if beta > small {
            // A convex corner: an arc around it, then the arc.
            let mid = (op.0 + radius * delta.cos(), op.1 + radius * delta.sin());
            self.dequeue();
            self.enqueue(Queued::Arc {
                original_turns: 0.0,
                end: mid,
                centre: op,
                turn: if s.left { -1 } else { 1 },
            });
            self.dequeue();
            self.set_endpoint(mid);
            self.enqueue(main);
        } else {
            self.dequeue();
            self.set_endpoint(c);
            self.enqueue(main);
        }
        s.program = end;
        s.current = new_end;
        self.session = Some(s);
        Ok(())
    }

    /// Where the queued move ends at a concave corner before an arc around `ce`:
    /// `convert_arc_comp2`'s line→arc and arc→arc cases.
    fn concave_before_arc(
        &self,
        s: &Session,
        (ce, turn, arc_radius): (P, i32, f64),
        theta: f64,
        beta: f64,
    ) -> Result<P, Refusal> {
        let radius = s.radius;
        let tool_inside = inside(s.left, turn);
        let Some(Queued::Arc {
            end: prev_end,
            centre: prev_centre,
            turn: prev_turn,
            ..
        }) = self.front()
        else {
            // line → arc. LinuxCNC: sin(beta - M_PI_2l) in long double, -cos(beta) exactly.
            let cy = arc_radius * -beta.cos();
            let (dist_from_center, toward_nominal) = if tool_inside {
                (arc_radius - radius, cy + radius)
            } else {
                (arc_radius + radius, cy - radius)
            };
            let l = toward_nominal / dist_from_center;
            if beyond_one(l) {
                return Err(gouge(
                    "Arc move in concave corner cannot be reached by the tool without gouging",
                ));
            }
            let angle_from_center = match (tool_inside, turn > 0) {
                (true, true) => theta + l.asin(),
                (true, false) => theta - l.asin(),
                (false, true) => theta + PI - l.asin(),
                (false, false) => theta + PI + l.asin(),
            };
            return Ok((
                ce.0 + dist_from_center * angle_from_center.cos(),
                ce.1 + dist_from_center * angle_from_center.sin(),
            ));
        };
        // arc → arc
        let oldrad = hypot(prev_centre.1 - prev_end.1, prev_centre.0 - prev_end.0);
        let newrad = if tool_inside {
            arc_radius - radius
        } else {
            arc_radius + radius
        };
        let arc_cc = hypot(prev_centre.1 - ce.1, prev_centre.0 - ce.0);
        if oldrad == 0.0 || arc_cc == 0.0 {
            return Err(refusal(
                "Arc to arc motion is invalid because the arcs have the same center",
                "two arcs around one centre meet in a concave corner",
                MOVE_HELP,
            ));
        }
        let a = (oldrad * oldrad + arc_cc * arc_cc - newrad * newrad) / (2.0 * oldrad * arc_cc);
        if beyond_one(a) {
            return Err(gouge(
                "Arc to arc motion makes a corner the compensated tool can't fit in without gouging",
            ));
        }
        let pullback = a.acos();
        let cc_dir = (ce.1 - prev_centre.1).atan2(ce.0 - prev_centre.0);
        let dir = if inside(s.left, prev_turn) == (turn > 0) {
            cc_dir + pullback
        } else {
            cc_dir - pullback
        };
        Ok((
            prev_centre.0 + oldrad * dir.cos(),
            prev_centre.1 + oldrad * dir.sin(),
        ))
    }

    /// `qc().front()`, which after the queue was emptied reads its first slot as it was left.
    fn front(&self) -> Option<Queued> {
        self.queue.first().copied().or(self.slot0)
    }

    fn enqueue(&mut self, q: Queued) {
        if self.queue.is_empty() {
            self.slot0 = Some(q);
        }
        self.queue.push(q);
    }

    /// `dequeue_canons`: the queued moves go out as they are.
    fn dequeue(&mut self) {
        self.endpoint_valid = false;
        self.queue.clear();
    }

    fn set_endpoint(&mut self, p: P) {
        self.endpoint = p;
        self.endpoint_valid = true;
    }

    /// `move_endpoint_and_flush`: every queued move now ends at `p` (where a corner cut it
    /// short), then the queue goes out. A move that would have to run backwards, or an arc
    /// that would have to sweep further than it did, gouges.
    fn move_endpoint_and_flush(&mut self, p: P) -> Result<(), Refusal> {
        if self.queue.is_empty() {
            return Ok(());
        }
        let sweep_slack = if self.inch { 0.001 } else { 0.0254 };
        let (endpoint, valid) = (self.endpoint, self.endpoint_valid);
        for (n, q) in self.queue.iter_mut().enumerate() {
            match q {
                Queued::Arc {
                    original_turns,
                    end,
                    centre,
                    turn,
                } => {
                    let r1 = hypot(end.0 - centre.0, end.1 - centre.1);
                    let l1 = *original_turns;
                    *end = p;
                    let r2 = hypot(p.0 - centre.0, p.1 - centre.1);
                    let l2 = find_turn(endpoint, *centre, *turn, p);
                    if (r1 - r2).abs() > 0.01 {
                        return Err(Refusal {
                            linuxcnc: format!(
                                "BUG: cutter compensation has generated an invalid arc with mismatched radii r1 {r1:.6} r2 {r2:.6}"
                            ),
                            what: "LinuxCNC cannot end a compensated arc where the next move needs it",
                            help: MOVE_HELP,
                        });
                    }
                    if l1 != 0.0 && valid && l2.abs() > l1.abs() + sweep_slack {
                        return Err(refusal(
                            "Arc move in concave corner cannot be reached by the tool without gouging",
                            "to reach this concave corner the compensated arc before it would have to sweep further than programmed, cutting into the part",
                            MOVE_HELP,
                        ));
                    }
                }
                Queued::Straight { traverse, dir, end } => {
                    let dot = dir.0 * (p.0 - endpoint.0) + dir.1 * (p.1 - endpoint.1);
                    if valid && dot < 0.0 {
                        return Err(refusal(
                            if *traverse {
                                "Straight traverse in concave corner cannot be reached by the tool without gouging"
                            } else {
                                "Straight feed in concave corner cannot be reached by the tool without gouging"
                            },
                            "a move before this corner is shorter than the tool's way back out of a concave corner: the compensated move would run backwards, cutting into the part",
                            MOVE_HELP,
                        ));
                    }
                    *end = p;
                }
            }
            if n == 0 {
                self.slot0 = Some(*q);
            }
        }
        self.dequeue();
        self.set_endpoint(p);
        Ok(())
    }
}

/// LinuxCNC's turn of an arc of one turn or less: −1 for G2, +1 for G3.
fn turn_of(clockwise: bool) -> i32 {
    if clockwise { -1 } else { 1 }
}

impl FrontEnd<'_> {
    /// A reader's exact position (mm, X a diameter, the G52/G92 offset added) as LinuxCNC
    /// holds it in the compensation plane: (Z, X radius) in the program's units.
    fn comp_point(&self, (x, z): (f64, f64)) -> P {
        let unit = if self.inch { 25.4 } else { 1.0 };
        ((self.program_z(z)), (x - self.axis_offset.0) / 2.0 / unit)
    }

    /// The model in the current units.
    fn comp_model(&mut self) -> &mut Model {
        let inch = self.inch;
        self.comp.units(inch);
        &mut self.comp
    }

    /// Reports a refusal of a compensated move at `at` (else the whole line).
    fn comp_refused(&mut self, line: Line<'_>, at: Option<&Word>, r: Refusal) {
        let range = at.map_or(0..line.text.len(), |w| w.range.clone());
        let text = &line.text[range.clone()];
        self.diag(
            codes::ISOR_COMPENSATION,
            line,
            range.clone(),
            format!(
                "`{text}` with cutter radius compensation on: {} (LinuxCNC: \"{}\")",
                r.what, r.linuxcnc
            ),
            r.help,
        );
    }

    /// Reports `result`'s refusal; true when there is none.
    fn comp_passes(
        &mut self,
        line: Line<'_>,
        at: Option<&Word>,
        result: Result<(), Refusal>,
    ) -> bool {
        match result {
            Ok(()) => true,
            Err(r) => {
                // LinuxCNC stops here: nothing after it is followed.
                self.comp.forget();
                self.comp_refused(line, at, r);
                false
            }
        }
    }

    /// G40, G41/G42, G41.1/G42.1 as `step_compensation` read them: the model follows a
    /// compensation whose radius D/2 is known and greater than 0; G40 flushes its queue.
    pub(super) fn comp_switch(
        &mut self,
        line: Line<'_>,
        w: &Word,
        comp: crate::ir::Compensation,
        was_on: bool,
    ) {
        use crate::ir::Compensation;
        match comp {
            Compensation::Off => {
                let result = self.comp_model().off();
                self.comp_passes(line, Some(w), result);
            }
            Compensation::Dynamic {
                right,
                diameter,
                orientation,
            } if !was_on && diameter.0 > 0 => {
                // The model works in program units, as LinuxCNC.
                let unit = if self.inch { 25.4 } else { 1.0 };
                let radius = diameter.to_mm_f64() / unit / 2.0;
                let orientation = orientation.map_or(0, i64::from);
                self.comp_model().on(!right, radius, orientation);
            }
            Compensation::Dynamic { .. } | Compensation::FromTool { .. } if !was_on => {
                self.comp.forget()
            }
            _ => {}
        }
    }

    /// The start and end of a move in the model's plane, from the exact start and the line's
    /// exact target; `None` (after reporting it) when the compensated move starts where
    /// ncthread does not know the position.
    fn comp_ends(
        &mut self,
        line: Line<'_>,
        at: Option<&Word>,
        start: (Option<f64>, Option<f64>),
        target: (Option<f64>, Option<f64>),
    ) -> Option<(P, P)> {
        let end = (target.0.or(start.0), target.1.or(start.1));
        match (start, end) {
            ((Some(sx), Some(sz)), (Some(ex), Some(ez))) => {
                Some((self.comp_point((sx, sz)), self.comp_point((ex, ez))))
            }
            _ => {
                let range = at.map_or(0..line.text.len(), |w| w.range.clone());
                self.diag(
                    codes::ISOR_UNKNOWN_POSITION,
                    line,
                    range,
                    "a move under cutter radius compensation (D > 0) from a position that is not known yet: ncthread cannot tell whether LinuxCNC can compensate it".into(),
                    "move to an absolute X and Z (G0 X… Z…) before turning the compensation on",
                );
                self.comp.forget();
                None
            }
        }
    }

    /// A G0/G1 from `start` (the exact start) to the line's target (read by `target`; when
    /// not `moves`, a line without X or Z, to where it starts); false after a refusal.
    pub(super) fn comp_straight(
        &mut self,
        line: Line<'_>,
        at: Option<&Word>,
        traverse: bool,
        start: (Option<f64>, Option<f64>),
        moves: bool,
    ) -> bool {
        if !self.comp.active() {
            self.comp.straight_motion();
            return true;
        }
        let target = if moves {
            self.exact_target
        } else {
            (None, None)
        };
        let Some((start, end)) = self.comp_ends(line, at, start, target) else {
            return false;
        };
        let result = self.comp_model().straight(traverse, start, end);
        self.comp_passes(line, at, result)
    }

    /// A G0 or G1 on a line without X or Z: LinuxCNC moves to where it is, a move all the same.
    pub(super) fn comp_without_axes(&mut self, line: Line<'_>, at: Option<&Word>, traverse: bool) {
        let start = self.exact_start();
        self.comp_straight(line, at, traverse, start, false);
    }

    /// `convert_arc`'s first check: no arc right after G40; false after a refusal.
    pub(super) fn comp_arc_allowed(&mut self, line: Line<'_>, at: Option<&Word>) -> bool {
        let allowed = self.comp.arc_allowed();
        self.comp_passes(line, at, allowed)
    }

    /// An arc's checks before its centre (the entry arc's length, an R the tool cannot fit
    /// in); `None` after a refusal.
    pub(super) fn comp_arc_start(
        &mut self,
        line: Line<'_>,
        at: Option<&Word>,
        (start, end): ((f64, f64), (f64, f64)),
        r: Option<&Word>,
        clockwise: bool,
    ) -> Option<()> {
        if !self.comp.active() {
            return Some(());
        }
        let (start, end) = (self.comp_point(start), self.comp_point(end));
        let r = r.map(|r| r.value.to_f64());
        let result = self.comp_model().arc_start(start, end, r, clockwise);
        self.comp_passes(line, at, result).then_some(())
    }

    /// A G2/G3 from `start` to `end` (exact) with its centre's words; false after a refusal.
    pub(super) fn comp_arc(
        &mut self,
        line: Line<'_>,
        at: Option<&Word>,
        (start, end): ((f64, f64), (f64, f64)),
        (i, k, r): (Option<&Word>, Option<&Word>, Option<&Word>),
        clockwise: bool,
    ) -> bool {
        if !self.comp.active() {
            return true;
        }
        let value = |w: Option<&Word>| w.map_or(0.0, |w| w.value.to_f64());
        let centre = match r {
            Some(r) => Centre::R(r.value.to_f64()),
            None => Centre::Ik {
                i: value(i),
                k: value(k),
                absolute: self.absolute_centres,
            },
        };
        let (start, end) = (self.comp_point(start), self.comp_point(end));
        let result = self.comp_model().arc(start, end, centre, clockwise);
        self.comp_passes(line, at, result)
    }

    /// M0, M1 (`end`: M2, M30): LinuxCNC sends the queued moves out where the tool is.
    pub(super) fn comp_stop(&mut self, line: Line<'_>, w: &Word, end: bool) {
        let result = self.comp_model().stop(end);
        self.comp_passes(line, Some(w), result);
    }

    /// G53 with compensation on; false after a refusal.
    pub(super) fn comp_machine_move(&mut self, line: Line<'_>, w: &Word) -> bool {
        self.comp.straight_motion();
        let result = self.comp.machine_move();
        self.comp_passes(line, Some(w), result)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn model(left: bool, radius: f64) -> Model {
        let mut m = Model::default();
        m.on(left, radius, 0);
        m
    }

    #[test]
    fn an_entry_move_must_be_longer_than_the_radius() {
        let mut m = model(false, 0.4);
        let e = m.straight(false, (20.0, 30.0), (19.7, 30.0)).unwrap_err();
        assert!(
            e.linuxcnc
                .starts_with("Length of cutter compensation entry move")
        );
        assert!(!m.active(), "a refusal ends what the model follows");
        let mut m = model(false, 0.4);
        assert_eq!(m.straight(false, (20.0, 30.0), (19.5, 30.0)), Ok(()));
    }

    #[test]
    fn an_entry_arc_must_end_beyond_the_radius() {
        let mut m = model(false, 0.4);
        let e = m
            .arc_start((20.0, 30.0), (19.9986, 30.0019), None, true)
            .unwrap_err();
        assert!(
            e.linuxcnc
                .starts_with("Radius of cutter compensation entry arc")
        );
        let mut m = model(false, 0.4);
        assert_eq!(m.arc_start((20.0, 30.0), (18.0, 32.0), None, true), Ok(()));
    }

    #[test]
    fn the_tool_must_fit_inside_an_arc() {
        // G42 (right) with G2 cuts inside the arc: R0.3 < 0.4.
        let mut m = model(false, 0.4);
        let e = m
            .arc_start((20.0, 30.0), (19.0, 31.0), Some(0.3), true)
            .unwrap_err();
        assert_eq!(e.linuxcnc, "Tool radius not less than arc radius with comp");
        // G41 (left) with G2 cuts outside it: fine.
        let mut m = model(true, 0.4);
        assert_eq!(
            m.arc_start((20.0, 30.0), (19.7, 30.3), Some(0.3), true),
            Ok(())
        );
        // A later arc: I/K radius 0.3 inside, refused.
        let mut m = model(false, 0.4);
        m.straight(false, (30.0, 30.0), (20.0, 30.0)).unwrap();
        let ik = Centre::Ik {
            i: 0.0,
            k: -0.3,
            absolute: false,
        };
        let e = m.arc((20.0, 30.0), (19.4, 30.0), ik, true).unwrap_err();
        assert_eq!(e.linuxcnc, "Tool radius not less than arc radius with comp");
    }

    #[test]
    fn a_concave_corner_that_backs_up_past_a_short_move_gouges() {
        // G41 (the tool left of the path): along Z-, a step of 0.2 up in X, along Z- again:
        // with r0.4 the step is shorter than the tool's retreat out of the corner.
        let mut m = model(true, 0.4);
        m.straight(false, (10.0, 10.0), (0.0, 10.0)).unwrap();
        m.straight(false, (0.0, 10.0), (0.0, 10.2)).unwrap();
        let e = m.straight(false, (0.0, 10.2), (-10.0, 10.2)).unwrap_err();
        assert_eq!(
            e.linuxcnc,
            "Straight feed in concave corner cannot be reached by the tool without gouging"
        );
        // The same with a step of 1: fine.
        let mut m = model(true, 0.4);
        m.straight(false, (10.0, 10.0), (0.0, 10.0)).unwrap();
        m.straight(false, (0.0, 10.0), (0.0, 11.0)).unwrap();
        assert_eq!(m.straight(false, (0.0, 11.0), (-10.0, 11.0)), Ok(()));
        assert_eq!(m.stop(true), Ok(()));
    }

    #[test]
    fn an_arc_after_g40_needs_a_straight_move_first() {
        let mut m = model(false, 0.4);
        m.straight(false, (10.0, 10.0), (0.0, 10.0)).unwrap();
        m.off().unwrap();
        assert!(m.arc_allowed().is_err());
        m.straight(false, (0.0, 10.0), (0.0, 12.0)).unwrap();
        assert!(m.arc_allowed().is_ok());
        // G40 right after G41.1 (no move): no restriction.
        let mut m = model(false, 0.4);
        m.off().unwrap();
        assert!(m.arc_allowed().is_ok());
    }

    #[test]
    fn units_scale_the_model() {
        let mut m = model(false, 0.4);
        m.straight(false, (10.0, 10.0), (0.0, 10.0)).unwrap();
        m.units(true);
        let s = m.session.unwrap();
        assert!((s.radius - 0.4 / 25.4).abs() < 1e-15);
        assert!((s.program.1 - 10.0 / 25.4).abs() < 1e-15);
    }

    #[test]
    fn find_turn_sweeps_as_linuxcnc() {
        let t = find_turn((1.0, 0.0), (0.0, 0.0), 1, (0.0, 1.0));
        assert!((t - FRAC_PI_2).abs() < 1e-15);
        let t = find_turn((1.0, 0.0), (0.0, 0.0), -1, (0.0, 1.0));
        assert!((t + 1.5 * PI).abs() < 1e-15);
        assert_eq!(find_turn((1.0, 0.0), (0.0, 0.0), 0, (0.0, 1.0)), 0.0);
    }
}

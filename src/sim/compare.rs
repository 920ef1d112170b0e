//! Normalisation and comparison of two simulations ("Simulation and equivalence" in the
//! spec): collinear segments of one kind merge, rapids compare by end point only, and a
//! synchronised segment may start earlier along its own line by less than one lead.

use super::{Motion, Segment, TURN, show_pos as show};
use crate::fixed::{Angle, Lead, Length, div_round};
use crate::ir::{Pos, SpindleDirection};

/// Position tolerance: 0.001 mm.
pub const TOLERANCE: Length = Length::from_steps(10);
/// Phase tolerance: 0.01°, but never finer than the angle the spindle turns while the tool
/// advances [`PHASE_GRID`] along Z (positions live on a 0.0001 mm grid, so a thread start
/// that is rounded once on each side can differ by two grid steps).
pub const PHASE_TOLERANCE: Angle = Angle(10);
/// The axial offset of two helices that is below the grid's resolution: 0.0002 mm.
pub const PHASE_GRID: Length = Length::from_steps(2);

/// The phase tolerance for a thread of `lead`: `PHASE_TOLERANCE` or the angle of
/// `PHASE_GRID`, whichever is larger.
pub fn phase_tolerance(lead: Lead) -> Angle {
    phase_tolerance_on(lead, PHASE_GRID)
}

/// The phase tolerance for a thread of `lead` when positions are known to within `grid`.
fn phase_tolerance_on(lead: Lead, grid: Length) -> Angle {
    let grid = div_round(
        grid.0 as i128 * TURN as i128 * Lead::PER_LENGTH as i128,
        lead.0.max(1) as i128,
    ) as i64;
    Angle(PHASE_TOLERANCE.0.max(grid))
}

/// The first place where two motions differ.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Difference {
    /// Index in the normalised lists.
    pub index: usize,
    pub left: Option<Segment>,
    pub right: Option<Segment>,
    /// What differs, with both values.
    pub what: String,
}

impl std::fmt::Display for Difference {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let place = |s: &Option<Segment>| match s {
            Some(s) => match s.pass {
                Some(p) => format!("line {} (pass {p})", s.line),
                None => format!("line {}", s.line),
            },
            None => "the end".to_string(),
        };
        write!(
            f,
            "{} vs {}: {}",
            place(&self.left),
            place(&self.right),
            self.what
        )
    }
}

fn xz(p: Pos) -> Option<(f64, f64)> {
    let (x, z) = p.known()?;
    Some((x.to_mm_f64(), z.to_mm_f64()))
}

/// Whether `b` lies on the line through `a` and `c` (within the tolerance).
fn collinear(a: Pos, b: Pos, c: Pos) -> bool {
    collinear_within(a, b, c, TOLERANCE)
}

/// [`collinear`] within `tol`: rs274's inches are printed to 0.0001 in, so a point LinuxCNC
/// computed on a line is printed off it by up to 0.00127 mm (X a radius there).
fn collinear_within(a: Pos, b: Pos, c: Pos, tol: Length) -> bool {
    let (Some(a), Some(b), Some(c)) = (xz(a), xz(b), xz(c)) else {
        return false;
    };
    let (dx, dz) = (c.0 - a.0, c.1 - a.1);
    let len = dx.hypot(dz);
    if len == 0.0 {
        return false;
    }
    let cross = dx * (b.1 - a.1) - dz * (b.0 - a.0);
    (cross / len).abs() <= tol.to_mm_f64()
}

/// Whether `segments[k]` and the feed after it, of the same feed, run from where the first
/// starts to `end` along one line: their meeting point within twice `tol` of it.
fn two_feeds_as_one(segments: &[Segment], k: usize, end: Pos, tol: Length) -> bool {
    let (Some(a), Some(b)) = (segments.get(k), segments.get(k + 1)) else {
        return false;
    };
    if a.motion != b.motion || a.to != b.from || !close_pos(b.to, end, tol) {
        return false;
    }
    let (Some(p), Some(q), Some(r)) = (xz(a.from), xz(a.to), xz(end)) else {
        return false;
    };
    let (dx, dz) = (r.0 - p.0, r.1 - p.1);
    let len = dx.hypot(dz);
    len > 0.0 && ((dx * (q.1 - p.1) - dz * (q.0 - p.0)) / len).abs() <= 2.0 * tol.to_mm_f64()
}

/// Whether `p` lies within `tol` of the segment from `a` to `b`.
fn near_segment(p: Pos, a: Pos, b: Pos, tol: f64) -> bool {
    let (Some(p), Some(a), Some(b)) = (xz(p), xz(a), xz(b)) else {
        return false;
    };
    let (dx, dz) = (b.0 - a.0, b.1 - a.1);
    let len2 = dx * dx + dz * dz;
    let t = if len2 > 0.0 {
        (((p.0 - a.0) * dx + (p.1 - a.1) * dz) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p.0 - a.0 - t * dx).hypot(p.1 - a.1 - t * dz) <= tol
}

/// Whether the feeds `left[i]`, `left[i + 1]` and `right[j]`, `right[j + 1]` (all of one
/// feed) run along one path from one start to one end, their joints in different places: a
/// short feed between two others, within the tolerance of the line on one side, that
/// `normalise` merged into the feed before it on one side and into the one after it on the
/// other (rs274's printed digits). Each joint lies within twice `tol` of the other side's
/// two feeds.
fn joint_slides(left: &[Segment], i: usize, right: &[Segment], j: usize, tol: Length) -> bool {
    let (Some(l0), Some(l1), Some(r0), Some(r1)) =
        (left.get(i), left.get(i + 1), right.get(j), right.get(j + 1))
    else {
        return false;
    };
    let feed = l0.motion;
    let on = |p: Pos, a: &Segment, b: &Segment| {
        let t = 2.0 * tol.to_mm_f64();
        near_segment(p, a.from, a.to, t) || near_segment(p, b.from, b.to, t)
    };
    matches!(feed, Motion::Feed { .. })
        && [l1.motion, r0.motion, r1.motion].iter().all(|m| *m == feed)
        && l0.to == l1.from
        && r0.to == r1.from
        && close_pos(l0.from, r0.from, tol)
        && close_pos(l1.to, r1.to, tol)
        && on(l0.to, r0, r1)
        && on(r0.to, l0, l1)
}

/// Merges consecutive collinear segments of the same kind; consecutive rapids collapse to
/// their final point (and take the line and pass of the rapid that ends there).
pub fn normalise(segments: &[Segment]) -> Vec<Segment> {
    let mut out: Vec<Segment> = Vec::with_capacity(segments.len());
    // The machine state after what is out so far, and before the run of state changes
    // being read.
    let mut effective = super::MachineState::default();
    let (mut before_run, mut in_run) = (effective, false);
    for s in segments {
        if let Motion::State(state) = s.motion {
            // A run of state changes with nothing between them is the state after it (one
            // line's `S800 M3 M8` is three calls in LinuxCNC's order and one or two items
            // in ncthread's); a run that changes nothing is nothing.
            if !in_run {
                (before_run, in_run) = (effective, true);
            } else if matches!(out.last().map(|l| l.motion), Some(Motion::State(_))) {
                out.pop();
            }
            effective = state;
            if effective != before_run {
                out.push(*s);
            }
            continue;
        }
        in_run = false;
        if let Some(last) = out.last_mut()
            && arcs_continue(last, s)
        {
            last.to = s.to;
            continue;
        }
        if let Some(last) = out.last_mut() {
            let rapids = matches!((last.motion, s.motion), (Motion::Rapid, Motion::Rapid));
            let merge = rapids
                || (!matches!(s.motion, Motion::Tap { .. } | Motion::Arc { .. })
                    && last.motion == s.motion
                    && last.to == s.from
                    && collinear(last.from, last.to, s.to));
            if merge {
                last.to = s.to;
                if rapids {
                    // A rapid compares by its end point: name the move that ends there.
                    last.line = s.line;
                    last.pass = s.pass;
                }
                continue;
            }
        }
        out.push(*s);
    }
    out
}

/// Whether the arc `s` continues the arc `last` on the same circle, the same way, at the
/// same feed, together turning at most once around (a target that writes an arc a
/// quadrant at a time cuts the same arc).
fn arcs_continue(last: &Segment, s: &Segment) -> bool {
    let (
        Motion::Arc {
            centre: c,
            clockwise: cw,
            feed: f,
            per_minute: p,
        },
        Motion::Arc {
            centre: d,
            clockwise: dw,
            feed: g,
            per_minute: q,
        },
    ) = (last.motion, s.motion)
    else {
        return false;
    };
    let (Some(a), Some(b), Some(e), Some(centre)) =
        (last.from.known(), last.to.known(), s.to.known(), c.known())
    else {
        return false;
    };
    // The same circle within the grid of a printed radius (rs274 prints four decimals of a
    // radius: a centre computed two ways can differ by one step of it on the diameter).
    if (cw, f, p) != (dw, g, q) || !close_pos(c, d, Length::from_steps(2)) || last.to != s.from {
        return false;
    }
    let turned =
        crate::lower::arc::sweep(a, b, centre, cw) + crate::lower::arc::sweep(b, e, centre, cw);
    turned <= std::f64::consts::TAU + 1e-9
}

fn close(a: Option<Length>, b: Option<Length>, tol: Length) -> bool {
    match (a, b) {
        (Some(a), Some(b)) => (a - b).abs() <= tol,
        (None, None) => true,
        _ => false,
    }
}

fn close_pos(a: Pos, b: Pos, tol: Length) -> bool {
    close(a.x, b.x, tol) && close(a.z, b.z, tol)
}

fn describe(m: &Motion) -> String {
    match m {
        Motion::Rapid => "a rapid".into(),
        Motion::Feed { feed, .. } => format!("a feed at {}", feed.mm()),
        Motion::Sync { lead, .. } => format!("a thread move with lead {}", lead.mm()),
        Motion::Tap { lead, .. } => format!("a tap with lead {}", lead.mm()),
        Motion::SyncRadial { advance, .. } => {
            format!("a synchronised infeed at {} per rev", advance.mm())
        }
        Motion::Arc { clockwise, .. } => {
            format!("an arc ({})", if *clockwise { "G2" } else { "G3" })
        }
        Motion::IndexWait => "a wait in the cut for the index pulse".into(),
        Motion::State(state) => state.describe(),
        Motion::Stop { optional: true } => "an optional stop (M1)".into(),
        Motion::Stop { optional: false } => "a program stop (M0)".into(),
        Motion::Dwell { time } => format!("a dwell of {} s", Length::from_steps(*time).mm()),
        Motion::Kept { .. } => "a block kept as written".into(),
    }
}

/// Two events where the tool stands (a state, a stop, a dwell, a kept block), or two
/// motions of different kinds: equal, or what differs.
fn events(a: &Segment, b: &Segment) -> Option<String> {
    match (&a.motion, &b.motion) {
        (Motion::State(_), Motion::State(_))
        | (Motion::Stop { .. }, Motion::Stop { .. })
        | (Motion::Dwell { .. }, Motion::Dwell { .. })
        | (Motion::Kept { .. }, Motion::Kept { .. })
            if a.motion == b.motion =>
        {
            None
        }
        (Motion::Kept { .. }, Motion::Kept { .. }) => {
            Some("the blocks kept as written differ".into())
        }
        _ => Some(format!("{} ≠ {}", describe(&a.motion), describe(&b.motion))),
    }
}

/// The circular distance between two angles.
fn angle_gap(a: Angle, b: Angle) -> i64 {
    let d = (a.0 - b.0).rem_euclid(TURN);
    d.min(TURN - d)
}

/// Whether the synchronised segment `b` starts where `a` does, or earlier along `a`'s line
/// by less than one lead.
fn sync_start_ok(a: &Segment, b: &Segment, lead: Lead, tol: Length) -> bool {
    if close_pos(a.from, b.from, tol) {
        return true;
    }
    let (Some(az), Some(bz), Some(ez)) = (a.from.z, b.from.z, a.to.z) else {
        return false;
    };
    let towards = (ez - az).signum();
    let earlier = Length(towards * (az - bz).0);
    earlier.0 > 0
        && (earlier.0 as i128) * (Lead::PER_LENGTH as i128) < lead.0 as i128
        && collinear_within(b.from, a.from, a.to, tol)
}

/// The largest deviation between two equivalent normalised motions, segment by segment:
/// end points (and the starts of feeds and of thread moves that start at the same place), and
/// for thread moves the drift of their helices over the move.
pub fn largest_deviation(left: &[Segment], right: &[Segment]) -> Length {
    let gap = |a: Pos, b: Pos| {
        let axis = |p: Option<Length>, q: Option<Length>| match (p, q) {
            (Some(p), Some(q)) => (p - q).abs(),
            _ => Length::ZERO,
        };
        axis(a.x, b.x).max(axis(a.z, b.z))
    };
    let mut largest = Length::ZERO;
    let (mut i, mut j) = (0, 0);
    let judge = Judge::new(TOLERANCE, Angle(TURN), Length::ZERO);
    while let (Some(a), Some(b)) = (left.get(i), right.get(j)) {
        // Short moves on one side only, as `compare_within` passes over them.
        if judge
            .pair(a, b, (left.get(i + 1), right.get(j + 1)))
            .is_some()
            && let Some((di, dj)) = judge.short_moves_passed(left, i, right, j)
        {
            i += di;
            j += dj;
            continue;
        }
        i += 1;
        j += 1;
        // Two feeds on one side for one on the other, as `compare_within` pairs them.
        if a.motion == b.motion
            && matches!(a.motion, Motion::Feed { .. })
            && !close_pos(a.to, b.to, TOLERANCE)
        {
            if two_feeds_as_one(left, i - 1, b.to, TOLERANCE) {
                largest = largest.max(gap(left[i].to, b.to));
                i += 1;
                continue;
            }
            if two_feeds_as_one(right, j - 1, a.to, TOLERANCE) {
                largest = largest.max(gap(a.to, right[j].to));
                j += 1;
                continue;
            }
            if joint_slides(left, i - 1, right, j - 1, TOLERANCE) {
                largest = largest.max(gap(a.from, b.from));
                largest = largest.max(gap(left[i].to, right[j].to));
                i += 1;
                j += 1;
                continue;
            }
        }
        largest = largest.max(gap(a.to, b.to));
        match (a.motion, b.motion) {
            (Motion::Feed { .. }, Motion::Feed { .. }) => {
                largest = largest.max(gap(a.from, b.from))
            }
            (Motion::Arc { centre: c, .. }, Motion::Arc { centre: d, .. }) => {
                largest = largest.max(gap(a.from, b.from)).max(gap(c, d))
            }
            (Motion::Sync { lead: l, .. }, Motion::Sync { lead: m, .. }) => {
                if close_pos(a.from, b.from, TOLERANCE) {
                    largest = largest.max(gap(a.from, b.from));
                }
                if let (Some(z0), Some(z1)) = (a.from.z, a.to.z) {
                    largest = largest.max(l.drift(m, (z1 - z0).abs()));
                }
            }
            _ => {}
        }
    }
    largest
}

/// Compares two normalised motions; `None` when they are equivalent.
pub fn compare(left: &[Segment], right: &[Segment]) -> Option<Difference> {
    compare_within(left, right, TOLERANCE, Angle::ZERO)
}

/// [`compare`] with another position tolerance and a phase slack, for a reading that is
/// itself rounded (rs274 prints four decimals: of an inch, or of a chain whose helix those
/// decimals fix only to within some degrees).
pub fn compare_within(
    left: &[Segment],
    right: &[Segment],
    tol: Length,
    phase_slack: Angle,
) -> Option<Difference> {
    compare_judged(left, right, Judge::new(tol, phase_slack, Length::ZERO))
}

/// [`compare_within`] for a conversion rounded onto its target's grid (`--round`) by at most
/// `rounded`: positions within `tol`, and a thread's helix moved along Z by at most
/// `rounded` — a start rounded on a control that cannot say a start angle (the НЦ-31) moves
/// the helix with it, by no more than the deviation its writer reported.
pub fn compare_rounded(
    left: &[Segment],
    right: &[Segment],
    tol: Length,
    rounded: Length,
) -> Option<Difference> {
    compare_judged(left, right, Judge::new(tol, Angle::ZERO, rounded))
}

fn compare_judged(left: &[Segment], right: &[Segment], judge: Judge) -> Option<Difference> {
    let (mut i, mut j) = (0, 0);
    loop {
        if let (Some(a), Some(b)) = (left.get(i), right.get(j)) {
            if judge.shift_rapid(b, right.get(j + 1), a) {
                j += 1;
                continue;
            }
            if judge.shift_rapid(a, left.get(i + 1), b) {
                i += 1;
                continue;
            }
        }
        let (a, b) = match (left.get(i), right.get(j)) {
            (None, None) => return None,
            (Some(a), Some(b)) => (a, b),
            (l, r) => {
                let extra = l.or(r).expect("one side has it");
                return Some(Difference {
                    index: i,
                    left: l.copied(),
                    right: r.copied(),
                    what: format!(
                        "{} to {} on one side only",
                        describe(&extra.motion),
                        show(extra.to)
                    ),
                });
            }
        };
        if let Some((di, dj)) = feeds_joined_otherwise(left, i, right, j, judge.tol) {
            i += di;
            j += dj;
            continue;
        }
        let next = (left.get(i + 1), right.get(j + 1));
        if let Some(what) = judge.pair(a, b, next) {
            // Short moves on one side only, where the other side goes on: what a printed
            // reading drops near the tolerance (a layer's retract over the last material,
            // 0.0011 mm on one side, 0.001 mm printed on the other).
            if let Some((di, dj)) = judge.short_moves_passed(left, i, right, j) {
                i += di;
                j += dj;
                continue;
            }
            return Some(Difference {
                index: i,
                left: Some(*a),
                right: Some(*b),
                what,
            });
        }
        i += 1;
        j += 1;
    }
}

/// Two feeds on one side that the other has as one (their meeting point lies within the
/// tolerance of the line on one side and just outside it on the other: rs274's printed
/// digits, so `normalise` merged them on one side only), or a joint between two feeds in
/// different places: how many segments each side's pair takes.
fn feeds_joined_otherwise(
    left: &[Segment],
    i: usize,
    right: &[Segment],
    j: usize,
    tol: Length,
) -> Option<(usize, usize)> {
    let (a, b) = (&left[i], &right[j]);
    if !(a.motion == b.motion
        && matches!(a.motion, Motion::Feed { .. })
        && close_pos(a.from, b.from, tol)
        && !close_pos(a.to, b.to, tol))
    {
        return None;
    }
    if two_feeds_as_one(left, i, b.to, tol) {
        Some((2, 1))
    } else if two_feeds_as_one(right, j, a.to, tol) {
        Some((1, 2))
    } else if joint_slides(left, i, right, j, tol) {
        Some((2, 2))
    } else {
        None
    }
}

/// How closely [`compare_within`] holds two segments together.
/// A thread move's words as a pair's check reads them: lead, hand, phase.
type SyncWords = (Lead, Option<SpindleDirection>, Option<Angle>);
/// A synchronised infeed's words: advance per turn, hand, start angle.
type RadialWords = (Lead, Option<SpindleDirection>, Option<Angle>);
/// An arc's words: centre, clockwise, feed, per minute.
type ArcWords = (Pos, bool, Length, bool);

struct Judge {
    /// The position tolerance.
    tol: Length,
    /// The phase slack of a rounded reading.
    phase_slack: Angle,
    /// The grid a thread's phase is known to, widened by a tolerance above [`TOLERANCE`].
    phase_grid: Length,
}

/// How many short moves [`Judge::one_sided_short_moves`] passes over at most.
const SHORT_RUN: usize = 4;

impl Judge {
    /// Positions within `tol`; a helix within the grid, widened by what `tol` adds to
    /// [`TOLERANCE`] or by `helix` (a rounding that moved it), whichever is more.
    fn new(tol: Length, phase_slack: Angle, helix: Length) -> Judge {
        Judge {
            tol,
            phase_slack,
            phase_grid: PHASE_GRID + (tol - TOLERANCE).max(helix).max(Length::ZERO),
        }
    }

    /// How many segments each side passes over where `left[i]` and `right[j]` do not pair:
    /// a run of short moves on one side only ([`Judge::one_sided_short_moves`]).
    fn short_moves_passed(
        &self,
        left: &[Segment],
        i: usize,
        right: &[Segment],
        j: usize,
    ) -> Option<(usize, usize)> {
        let (a, b) = (&left[i], &right[j]);
        if let Some(n) = self.one_sided_short_moves(left, i, b, right.get(j + 1)) {
            return Some((n, 0));
        }
        self.one_sided_short_moves(right, j, a, left.get(i + 1))
            .map(|n| (0, n))
    }

    /// How many straight moves (rapids, feeds) from `side[k]` on go less than the tolerance
    /// and two grid steps along each axis, on this side only: the segment after them pairs
    /// with `other` (whose next is `other_next`). `None` when there is no such run.
    fn one_sided_short_moves(
        &self,
        side: &[Segment],
        k: usize,
        other: &Segment,
        other_next: Option<&Segment>,
    ) -> Option<usize> {
        let limit = self.tol + Length::from_steps(2);
        let short = |s: &Segment| {
            matches!(s.motion, Motion::Rapid | Motion::Feed { .. })
                && close_pos(s.from, s.to, limit)
        };
        let run = side[k..]
            .iter()
            .take(SHORT_RUN)
            .take_while(|s| short(s))
            .count();
        (1..=run).find(|&n| {
            side.get(k + n).is_some_and(|s| {
                self.pair(s, other, (side.get(k + n + 1), other_next))
                    .is_none()
            })
        })
    }

    /// A short rapid on one side only, from where the other side's thread move starts, that
    /// takes the tool back along the thread line before its own thread move starts: that is
    /// how a start angle is written where there is none (the thread starts earlier on its
    /// line, at the index pulse). It is part of the thread move's start, not a move of its own.
    fn shift_rapid(&self, r: &Segment, next: Option<&Segment>, other: &Segment) -> bool {
        let tol = self.tol;
        matches!(r.motion, Motion::Rapid)
            && close_pos(r.from, other.from, tol)
            && match (other.motion, next) {
                (
                    Motion::Sync { lead, .. },
                    Some(
                        n @ Segment {
                            motion: Motion::Sync { .. },
                            ..
                        },
                    ),
                ) => close_pos(r.to, n.from, tol) && sync_start_ok(other, n, lead, tol),
                _ => false,
            }
    }

    /// What differs between two paired segments (`next`: the segment after each), or
    /// `None` when they agree: one check per kind of motion.
    fn pair(
        &self,
        a: &Segment,
        b: &Segment,
        next: (Option<&Segment>, Option<&Segment>),
    ) -> Option<String> {
        match (a.motion, b.motion) {
            (Motion::Rapid, Motion::Rapid) => self.rapids(a, b, next),
            (
                Motion::Feed {
                    feed: f,
                    per_minute: p,
                },
                Motion::Feed {
                    feed: g,
                    per_minute: q,
                },
            ) => self.feeds(a, b, (f, p), (g, q)),
            (
                Motion::Sync {
                    lead: l,
                    direction: d,
                    phase: p,
                },
                Motion::Sync {
                    lead: m,
                    direction: e,
                    phase: q,
                },
            ) => self.threads(a, b, (l, d, p), (m, e, q)),
            (
                Motion::Tap {
                    lead: l,
                    direction: d,
                },
                Motion::Tap {
                    lead: m,
                    direction: e,
                },
            ) => self.taps(a, b, (l, d), (m, e)),
            (
                Motion::SyncRadial {
                    advance: l,
                    direction: d,
                    start_angle: p,
                },
                Motion::SyncRadial {
                    advance: m,
                    direction: e,
                    start_angle: q,
                },
            ) => self.infeeds(a, b, (l, d, p), (m, e, q)),
            (
                Motion::Arc {
                    centre: c,
                    clockwise: cw,
                    feed: f,
                    per_minute: p,
                },
                Motion::Arc {
                    centre: d,
                    clockwise: dw,
                    feed: g,
                    per_minute: q,
                },
            ) => self.arcs(a, b, (c, cw, f, p), (d, dw, g, q)),
            (Motion::IndexWait, Motion::IndexWait) => None,
            _ => events(a, b),
        }
    }

    /// Two rapids: where they end. A rapid to the start of a thread move may end earlier
    /// along the thread line: the thread move's comparison decides.
    fn rapids(
        &self,
        a: &Segment,
        b: &Segment,
        next: (Option<&Segment>, Option<&Segment>),
    ) -> Option<String> {
        let before_sync = matches!(
            next,
            (
                Some(Segment {
                    motion: Motion::Sync { .. },
                    ..
                }),
                Some(Segment {
                    motion: Motion::Sync { .. },
                    ..
                })
            )
        );
        (!before_sync && !close_pos(a.to, b.to, self.tol))
            .then(|| format!("rapid ends at {} ≠ {}", show(a.to), show(b.to)))
    }

    /// Two feed moves: the feed, then both ends.
    fn feeds(
        &self,
        a: &Segment,
        b: &Segment,
        (f, p): (Length, bool),
        (g, q): (Length, bool),
    ) -> Option<String> {
        let unit = |m: bool| if m { "mm/min" } else { "mm/rev" };
        if f != g || p != q {
            return Some(format!(
                "feed {} {} ≠ {} {}",
                f.mm(),
                unit(p),
                g.mm(),
                unit(q)
            ));
        }
        if !close_pos(a.from, b.from, self.tol) || !close_pos(a.to, b.to, self.tol) {
            return Some(format!(
                "feed move {} → {} ≠ {} → {}",
                show(a.from),
                show(a.to),
                show(b.from),
                show(b.to)
            ));
        }
        None
    }

    /// Two thread moves: the lead, the hand, both ends, then the phase.
    fn threads(
        &self,
        a: &Segment,
        b: &Segment,
        left: SyncWords,
        right: SyncWords,
    ) -> Option<String> {
        let ((l, d, _), (m, e, _)) = (left, right);
        let tol = self.tol;
        // Leads differ when the helices drift apart by more than the tolerance over the move.
        let travel = match (a.from.z, a.to.z) {
            (Some(z0), Some(z1)) => (z1 - z0).abs(),
            _ => Length::ZERO,
        };
        let drift = l.drift(m, travel);
        if drift > tol || (travel == Length::ZERO && l != m) {
            return Some(format!(
                "lead {} ≠ {} (the helices drift {} mm apart over the move)",
                l.mm(),
                m.mm(),
                drift.mm()
            ));
        }
        if d != e {
            return Some("spindle direction differs (the hand of the thread)".into());
        }
        if !close_pos(a.to, b.to, tol) {
            return Some(format!(
                "thread move ends at {} ≠ {}",
                show(a.to),
                show(b.to)
            ));
        }
        if !sync_start_ok(a, b, l, tol) {
            return Some(format!(
                "thread move starts at {} ≠ {}",
                show(a.from),
                show(b.from)
            ));
        }
        self.phases(a, b, left, right)
    }

    /// Two thread moves' phases. The two helices are compared where the cut starts (the
    /// spindle angle at the start Z on each), not extrapolated to Z0, where a lead that
    /// agrees within the tolerance over the move could still turn a distant phase.
    fn phases(
        &self,
        a: &Segment,
        b: &Segment,
        left: SyncWords,
        right: SyncWords,
    ) -> Option<String> {
        let ((l, _, p), (m, _, q)) = (left, right);
        let at_start = |phase: Angle, lead: Lead, s: &Segment| match (a.from.z, s.from.z, s.to.z) {
            (Some(z), Some(z0), Some(z1)) => super::angle_at(z, phase, lead, (z1 - z0).signum()),
            _ => phase,
        };
        match (p, q) {
            (Some(p), Some(q))
                if angle_gap(at_start(p, l, a), at_start(q, m, b))
                    <= phase_tolerance_on(l, self.phase_grid)
                        .0
                        .max(self.phase_slack.0) =>
            {
                None
            }
            (None, None) => None,
            _ => {
                let show = |p: Option<Angle>| p.map_or("unknown".into(), |p| format!("{p}°"));
                Some(format!(
                    "thread phase (spindle angle at Z0) {} ≠ {}",
                    show(p),
                    show(q)
                ))
            }
        }
    }

    /// Two tapping moves: the lead, the hand and both ends together.
    fn taps(
        &self,
        a: &Segment,
        b: &Segment,
        (l, d): (Lead, Option<SpindleDirection>),
        (m, e): (Lead, Option<SpindleDirection>),
    ) -> Option<String> {
        let tol = self.tol;
        (l != m || d != e || !close_pos(a.from, b.from, tol) || !close_pos(a.to, b.to, tol)).then(
            || {
                format!(
                    "tap {} → {} lead {} ≠ {} → {} lead {}",
                    show(a.from),
                    show(a.to),
                    l.mm(),
                    show(b.from),
                    show(b.to),
                    m.mm()
                )
            },
        )
    }

    /// Two synchronised infeeds: the advance, the hand, both ends, then how each starts.
    fn infeeds(
        &self,
        a: &Segment,
        b: &Segment,
        left: RadialWords,
        right: RadialWords,
    ) -> Option<String> {
        let ((l, d, p), (m, e, q)) = (left, right);
        let tol = self.tol;
        let travel = match (a.from.x, a.to.x) {
            (Some(x0), Some(x1)) => Length::from_steps((x1 - x0).0.abs() / Length::STEP / 2),
            _ => Length::ZERO,
        };
        if l.drift(m, travel) > tol {
            return Some(format!("infeed advance {} ≠ {}", l.mm(), m.mm()));
        }
        if d != e {
            return Some("spindle direction differs".into());
        }
        if !close_pos(a.from, b.from, tol) || !close_pos(a.to, b.to, tol) {
            return Some(format!(
                "synchronised infeed {} → {} ≠ {} → {}",
                show(a.from),
                show(a.to),
                show(b.from),
                show(b.to)
            ));
        }
        let start_ok = match (p, q) {
            (Some(p), Some(q)) => angle_gap(p, q) <= PHASE_TOLERANCE.0,
            (None, None) => true,
            _ => false,
        };
        (!start_ok).then(|| {
            "the synchronised infeed starts differently (at the index pulse or continuing)".into()
        })
    }

    /// Two arcs: the turn, arc or full circle, the feed, then the ends and the centre.
    fn arcs(&self, a: &Segment, b: &Segment, left: ArcWords, right: ArcWords) -> Option<String> {
        let ((c, cw, f, p), (d, dw, g, q)) = (left, right);
        let tol = self.tol;
        if cw != dw {
            return Some(format!("{} ≠ {}", describe(&a.motion), describe(&b.motion)));
        }
        if (a.from == a.to) != (b.from == b.to) {
            let turn = |s: &Segment| {
                if s.from == s.to {
                    "a full circle"
                } else {
                    "an arc"
                }
            };
            return Some(format!("{} ≠ {}", turn(a), turn(b)));
        }
        if f != g || p != q {
            let unit = |m: bool| if m { "mm/min" } else { "mm/rev" };
            return Some(format!(
                "arc feed {} {} ≠ {} {}",
                f.mm(),
                unit(p),
                g.mm(),
                unit(q)
            ));
        }
        if !close_pos(a.from, b.from, tol) || !close_pos(a.to, b.to, tol) || !close_pos(c, d, tol) {
            return Some(format!(
                "arc {} → {} around {} ≠ {} → {} around {}",
                show(a.from),
                show(a.to),
                show(c),
                show(b.from),
                show(b.to),
                show(d)
            ));
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_feeds_nearly_on_one_line_pair_with_one() {
        let feed = Motion::Feed {
            feed: Length::from_steps(2000),
            per_minute: false,
        };
        let seg = |from: (i64, i64), to: (i64, i64)| Segment {
            motion: feed,
            from: Pos::new(Length::from_steps(from.0), Length::from_steps(from.1)),
            to: Pos::new(Length::from_steps(to.0), Length::from_steps(to.1)),
            line: 1,
            pass: None,
        };
        // The G72 finding: (10, 2) → (10.7839, 0.0798) → (12.9181, -5.1586), the middle
        // point 0.00105 mm off the line; rs274's side has the one feed.
        let two = [
            seg((100000, 20000), (107839, 798)),
            seg((107839, 798), (129181, -51586)),
        ];
        let one = [seg((100000, 20000), (129182, -51586))];
        assert_eq!(compare(&two, &one), None);
        assert_eq!(compare(&one, &two), None);
        assert_eq!(largest_deviation(&two, &one), Length::from_steps(1));
        // A real corner is not a line.
        let corner = [
            seg((100000, 20000), (110000, 798)),
            seg((110000, 798), (129181, -51586)),
        ];
        assert!(compare(&corner, &one).is_some());
        // The G71 finding: a 0.0087 mm feed between two others, its deviation from the
        // line 0.00097 mm, merged backwards on rs274's side (its printed digits) and
        // forwards on ncthread's: one path, the joints in different places.
        let ncthread = [
            seg((106998, 3572), (204301, -44087)),
            seg((204301, -44087), (294631, -74868)),
        ];
        let rs274 = [
            seg((106998, 3572), (204436, -44142)),
            seg((204436, -44142), (294630, -74868)),
        ];
        assert_eq!(compare(&ncthread, &rs274), None);
        assert_eq!(compare(&rs274, &ncthread), None);
        assert_eq!(largest_deviation(&ncthread, &rs274), Length::from_steps(1));
        // A real corner that moved is not the same path.
        let moved = [
            seg((106998, 3572), (204301, -44087)),
            seg((204301, -44087), (294631, -74868)),
        ];
        let other = [
            seg((106998, 3572), (204436, -45142)),
            seg((204436, -45142), (294630, -74868)),
        ];
        assert!(compare(&moved, &other).is_some());
    }
    use crate::ir::SpindleDirection;

    fn mm(v: f64) -> Length {
        Length::from_mm_f64(v)
    }

    fn seg(motion: Motion, from: (f64, f64), to: (f64, f64), line: u32) -> Segment {
        Segment {
            motion,
            from: Pos::new(mm(from.0), mm(from.1)),
            to: Pos::new(mm(to.0), mm(to.1)),
            line,
            pass: None,
        }
    }

    fn sync(lead: f64, phase: i64) -> Motion {
        Motion::Sync {
            lead: Lead::from_mm_f64(lead).unwrap(),
            direction: Some(SpindleDirection::Clockwise),
            phase: Some(Angle::from_deg(phase)),
        }
    }

    #[test]
    fn normalising_merges_rapids_and_collinear_moves() {
        let segs = [
            seg(Motion::Rapid, (100.0, 50.0), (100.0, 5.0), 1),
            seg(Motion::Rapid, (100.0, 5.0), (30.0, 5.0), 2),
            seg(sync(1.5, 0), (30.0, 5.0), (30.0, -10.0), 3),
            seg(sync(1.5, 0), (30.0, -10.0), (30.0, -20.0), 4),
            seg(sync(1.5, 0), (30.0, -20.0), (32.0, -22.0), 5),
        ];
        let n = normalise(&segs);
        assert_eq!(n.len(), 3);
        assert_eq!(n[0].to, Pos::new(mm(30.0), mm(5.0)));
        assert_eq!(n[1].to, Pos::new(mm(30.0), mm(-20.0)));
        assert_eq!(n[1].line, 3);
    }

    #[test]
    fn short_moves_on_one_side_only_are_passed_over() {
        // Fuzz run 14: a G71 layer's retract over the last material, 0.0011 mm on the
        // diameter in ncthread's motion; rs274 printed it 0.001 mm, which is no move.
        let feed = Motion::Feed {
            feed: mm(0.2),
            per_minute: false,
        };
        let ours = [
            seg(Motion::Rapid, (30.0, 2.0), (10.4, 0.0), 1),
            seg(feed, (10.4, 0.0), (10.4, -1.2475), 2),
            seg(Motion::Rapid, (10.4, -1.2475), (10.4011, -1.247), 2),
            seg(feed, (10.4011, -1.247), (10.4, -1.2464), 2),
            seg(feed, (10.4, -1.2464), (60.0, -1.2464), 3),
        ];
        let theirs = [
            seg(Motion::Rapid, (30.0, 2.0), (10.4, 0.0), 0),
            seg(feed, (10.4, 0.0), (10.4, -1.2475), 0),
            seg(feed, (10.401, -1.247), (10.4, -1.2464), 0),
            seg(feed, (10.4, -1.2464), (60.0, -1.2464), 0),
        ];
        assert_eq!(compare(&ours, &theirs), None);
        assert_eq!(compare(&theirs, &ours), None);
        assert!(largest_deviation(&ours, &theirs) <= Length::from_steps(11));
        // A retract the tolerance sees is a move of its own.
        let mut longer = ours;
        longer[2].to = Pos::new(mm(10.404), mm(-1.247));
        longer[3].from = longer[2].to;
        assert!(compare(&longer, &theirs).is_some());
    }

    #[test]
    fn a_start_earlier_by_less_than_a_lead_is_the_same_helix() {
        let a = [
            seg(Motion::Rapid, (40.0, 10.0), (30.0, 5.0), 1),
            seg(sync(3.0, 180), (30.0, 5.0), (30.0, -30.0), 2),
        ];
        let b = [
            seg(Motion::Rapid, (40.0, 10.0), (30.0, 6.5), 1),
            seg(sync(3.0, 180), (30.0, 6.5), (30.0, -30.0), 3),
        ];
        assert_eq!(compare(&a, &b), None);
        // A full lead earlier is a different program (and later is never allowed).
        let c = [
            seg(Motion::Rapid, (40.0, 10.0), (30.0, 8.0), 1),
            seg(sync(3.0, 180), (30.0, 8.0), (30.0, -30.0), 3),
        ];
        assert!(compare(&a, &c).is_some());
        let d = [
            seg(Motion::Rapid, (40.0, 10.0), (30.0, 4.0), 1),
            seg(sync(3.0, 180), (30.0, 4.0), (30.0, -30.0), 3),
        ];
        assert!(compare(&a, &d).unwrap().what.contains("starts"));
    }

    #[test]
    fn machine_state_is_compared_as_the_state_after_each_run_of_commands() {
        let at = |motion| seg(motion, (10.0, 0.0), (10.0, 0.0), 1);
        let cool = |mist, flood| {
            at(Motion::State(crate::sim::MachineState {
                mist,
                flood,
                ..Default::default()
            }))
        };
        let feed = seg(
            Motion::Feed {
                feed: mm(0.1),
                per_minute: false,
            },
            (10.0, 0.0),
            (10.0, -5.0),
            2,
        );
        // ncthread's M9 against rs274's MIST_OFF, FLOOD_OFF; an M9 with nothing on is nothing.
        let ours = [
            cool(false, true),
            feed,
            cool(false, false),
            cool(false, false),
        ];
        let theirs = [
            cool(false, true),
            feed,
            cool(false, false),
            cool(false, false),
            cool(false, false),
        ];
        assert_eq!(normalise(&ours).len(), 3);
        assert_eq!(compare(&normalise(&ours), &normalise(&theirs)), None);
        assert_eq!(normalise(&[cool(false, false), feed]).len(), 1);
        // A dropped coolant command, a stop or a dwell is a difference.
        let dropped = [feed, cool(false, false)];
        assert!(compare(&normalise(&ours), &normalise(&dropped)).is_some());
        let stop = at(Motion::Stop { optional: false });
        let optional = at(Motion::Stop { optional: true });
        let d = compare(&[stop, feed], &[optional, feed]).expect("differs");
        assert_eq!(d.what, "a program stop (M0) ≠ an optional stop (M1)");
        // A surface speed turned into rpm is a difference.
        let spindle = |surface_speed| {
            at(Motion::State(crate::sim::MachineState {
                direction: Some(crate::ir::SpindleDirection::Clockwise),
                speed: Some(200),
                surface_speed,
                ..Default::default()
            }))
        };
        let d = compare(
            &[spindle(Some(Some(2_500_000))), feed],
            &[spindle(None), feed],
        )
        .expect("differs");
        assert!(d.what.contains("surface speed"), "{}", d.what);
        let dwell = |t| at(Motion::Dwell { time: t });
        assert!(compare(&[dwell(2_500)], &[dwell(2_500)]).is_none());
        assert!(compare(&[dwell(2_500)], &[dwell(5_000)]).is_some());
        assert!(compare(&[dwell(2_500), feed], &[feed]).is_some());
    }

    /// A full circle and an arc with the same ends (within the tolerance) differ.
    #[test]
    fn a_full_circle_is_not_a_tiny_arc() {
        let arc = |to: (f64, f64)| {
            seg(
                Motion::Arc {
                    centre: Pos::new(mm(30.0), mm(0.0)),
                    clockwise: true,
                    feed: mm(0.1),
                    per_minute: false,
                },
                (20.0, 0.0),
                to,
                1,
            )
        };
        let d = compare(&[arc((20.0, 0.0))], &[arc((20.0, -0.0004))]).expect("differs");
        assert_eq!(d.what, "a full circle ≠ an arc");
        assert!(compare(&[arc((20.0, 0.0))], &[arc((20.0, 0.0))]).is_none());
    }

    #[test]
    fn mutations_are_found_and_named() {
        let a = [seg(sync(1.5, 0), (35.6, 4.5), (35.6, -47.5), 9)];
        let deeper = [seg(sync(1.5, 0), (35.58, 4.5), (35.58, -47.5), 12)];
        let d = compare(&a, &deeper).unwrap();
        assert!(
            d.what.contains("ends at X35.6 Z-47.5 ≠ X35.58"),
            "{}",
            d.what
        );
        assert_eq!(
            d.to_string().split(':').next().unwrap(),
            "line 9 vs line 12"
        );
        let lead = [seg(sync(1.501, 0), (35.6, 4.5), (35.6, -47.5), 9)];
        assert!(
            compare(&a, &lead)
                .unwrap()
                .what
                .contains("lead 1.5 ≠ 1.501")
        );
        let phase = [seg(sync(1.5, 5), (35.6, 4.5), (35.6, -47.5), 9)];
        assert!(compare(&a, &phase).unwrap().what.contains("phase"));
        let missing: [Segment; 0] = [];
        assert!(
            compare(&a, &missing)
                .unwrap()
                .what
                .contains("one side only")
        );
        // Within tolerance: 0.0005 mm.
        let near = [seg(sync(1.5, 0), (35.6005, 4.5), (35.6005, -47.5), 9)];
        assert_eq!(compare(&a, &near), None);
    }
}

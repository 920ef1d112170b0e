//! FANUC's canned cycles as moves, under the machine model the profile declares (spec
//! fanuc.md, "Canned cycles under a declared machine model"): the one implementation of each
//! cycle. The reader reads a cycle's words and its contour; these functions give its moves,
//! which every target other than FANUC writes and the simulator runs.
//!
//! Positions are the IR's (X a diameter, on the 0.0001 mm grid). The turning cycles and the
//! finishing cycle move exactly; a roughing layer's end on the contour is found in floating
//! point and rounded onto the grid once.

use crate::fixed::Length;
use crate::ir::{Compensation, ItemKind, Pos};

/// A point: X (a diameter) and Z.
pub type Point = (Length, Length);

/// A move of a contour (G70's, and the shape G71/G72 rough to): to `to`, straight or around
/// `arc` (its centre, and clockwise as LinuxCNC's G2 in G18), at rapid or at `feed`; `comp`
/// the tool nose radius compensation its block switches before it (G40/G41/G42), which G70
/// runs and the roughing cycles ignore.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Element {
    pub to: Point,
    pub arc: Option<(Point, bool)>,
    pub rapid: bool,
    pub feed: Length,
    pub comp: Option<Compensation>,
}

impl Element {
    /// The element as an IR move; a rapid inside a contour runs at `feed` when `at_feed`.
    fn item(&self, shift: Point, at_feed: Option<Length>) -> ItemKind {
        let to = Pos::new(self.to.0 + shift.0, self.to.1 + shift.1);
        let feed = at_feed.unwrap_or(self.feed);
        match self.arc {
            Some((c, clockwise)) => ItemKind::Arc {
                to,
                centre: Box::new(Pos::new(c.0 + shift.0, c.1 + shift.1)),
                clockwise,
                feed,
            },
            None if self.rapid && at_feed.is_none() => ItemKind::Rapid { to },
            None => ItemKind::Feed { to, feed },
        }
    }
}

fn rapid(p: Point) -> ItemKind {
    ItemKind::Rapid {
        to: Pos::new(p.0, p.1),
    }
}

fn feed(p: Point, feed: Length) -> ItemKind {
    ItemKind::Feed {
        to: Pos::new(p.0, p.1),
        feed,
    }
}

/// A G90 turning cycle (`facing`: a G94 facing cycle) from `start` to the cut's end `(x, z)`,
/// its taper `r` (G90: the radius at the cut's start minus at its end; G94: the Z at the cut's
/// start minus at its end). Rapid in, cut, retract at feed, rapid back to the start.
/// **\[decided\]** spec fanuc.md.
pub fn turning(start: Point, end: Point, taper: Length, facing: bool, f: Length) -> Vec<ItemKind> {
    let (x0, z0) = start;
    let (x, z) = end;
    if facing {
        vec![
            rapid((x0, z + taper)),
            feed((x, z), f),
            feed((x, z0), f),
            rapid((x0, z0)),
        ]
    } else {
        vec![
            rapid((x + taper.mul_div(2, 1), z0)),
            feed((x, z), f),
            feed((x0, z), f),
            rapid((x0, z0)),
        ]
    }
}

/// A G70 finishing cycle: the contour's moves as written (the first from the start point),
/// with their own feeds and the compensation their blocks switch (`comp` in force at the
/// call: a G41/G42 already in force changes nothing), then a rapid back to the start.
pub fn finishing(start: Point, contour: &[Element], mut comp: Compensation) -> Vec<ItemKind> {
    let mut moves = Vec::with_capacity(contour.len() + 1);
    for e in contour {
        if let Some(c) = e.comp.filter(|c| c.switches(comp)) {
            comp = c;
            moves.push(ItemKind::Compensation(c));
        }
        moves.push(e.item((Length::ZERO, Length::ZERO), None));
    }
    moves.push(rapid(start));
    moves
}

/// A G28 return to the reference point: a rapid to `via` where it moves (an intermediate
/// point in the program's coordinates; `G28 U0.` has none), then the named axes (`axes`: X,
/// Z) to the reference point, a rapid in machine coordinates (X a diameter).
pub fn home(from: Pos, via: Pos, reference: Point, axes: (bool, bool)) -> Vec<ItemKind> {
    let mut moves = Vec::new();
    let to = Pos {
        x: via.x.or(from.x),
        z: via.z.or(from.z),
    };
    if to != from {
        moves.push(ItemKind::Rapid { to: via });
    }
    moves.push(ItemKind::MachineMove(crate::ir::MachineMove::Machine {
        to: Pos {
            x: axes.0.then_some(reference.0),
            z: axes.1.then_some(reference.1),
        },
        feed: None,
    }));
    moves
}

/// The words of a G73 pattern repeating cycle.
#[derive(Clone, Copy, Debug)]
pub struct Pattern {
    /// Δi, Δk: the relief of the first pass beyond the last (X as a radius, Z).
    pub relief: Point,
    /// d: the number of passes, 2 or more.
    pub passes: u32,
    /// Δu (a diameter) and Δw: the finishing allowance of the last pass.
    pub allowance: Point,
    /// The cycle's feed.
    pub feed: Length,
}

/// A G73 pattern repeating cycle from `start` along `contour` (its first element from the
/// start to the contour's first point): `passes` passes of the contour moved by the allowance
/// plus the relief spread over the passes (the first by all of it, the last by none: the
/// relief × (d − k) / (d − 1) for pass k, rounded onto the grid), each from the start moved
/// as its contour (a rapid), its first element at rapid or feed as written, the rest at feed;
/// then a rapid back to the start. **\[decided\]** spec fanuc.md (GSK's divisor, d − 1).
pub fn pattern(start: Point, contour: &[Element], p: &Pattern) -> Result<Vec<ItemKind>, Refusal> {
    let [first, profile @ ..] = contour else {
        return Err("its contour has no block".into());
    };
    if p.passes < 2 {
        return Err("one pass (R1) leaves the relief unused: whether the control cuts at the relief or the allowance is its own".into());
    }
    let d = i64::from(p.passes) - 1;
    let mut moves = Vec::new();
    for k in 1..=d + 1 {
        let left = d - (k - 1);
        let shift = (
            p.allowance.0 + p.relief.0.mul_div(2 * left, d),
            p.allowance.1 + p.relief.1.mul_div(left, d),
        );
        moves.push(rapid((start.0 + shift.0, start.1 + shift.1)));
        let infeed = if first.rapid { None } else { Some(p.feed) };
        moves.push(first.item(shift, infeed));
        moves.extend(profile.iter().map(|e| e.item(shift, Some(p.feed))));
    }
    moves.push(rapid(start));
    Ok(moves)
}

/// The words and open points of a G76 two-block threading cycle (depths as radii).
#[derive(Clone, Copy, Debug)]
pub struct Threading {
    /// X (the root's diameter) and Z at the thread's end.
    pub end: Point,
    /// R, i: the radius at the thread's start minus at its end.
    pub taper: Length,
    /// P, k: the thread's height.
    pub height: Length,
    /// Q, Δd: the first pass's depth.
    pub first: Length,
    /// The first block's Q, Δdmin: the least depth a pass adds.
    pub min_cut: Length,
    /// The first block's R, d: the depth the finishing pass removes.
    pub finish: Length,
    /// P's mm: the finishing passes, the one that removes d and the spring passes.
    pub finishing: u32,
    /// P's rr: the pull-out at the thread's end, in tenths of the lead (45°).
    pub chamfer: u32,
    /// P's aa: the tool's angle in degrees (the infeed runs along the flank at half of it).
    pub angle: u32,
    pub lead: crate::fixed::Lead,
    /// Δdmin counts from the previous pass's actual depth (else from Δd√(n − 1)).
    pub min_from_actual: bool,
    /// Each pass's end moves with its start (else it stays on the end line).
    pub end_shifts: bool,
}

/// The depths of a G76's passes: Δd√n (at least Δdmin more than the pass before, as the
/// model counts it) up to k − d, then m passes at k. **\[decided\]** spec fanuc.md.
fn thread_depths(t: &Threading) -> Result<Vec<Length>, Refusal> {
    let rough_to = t.height - t.finish;
    if t.first.0 <= 0 || rough_to.0 <= 0 || t.finishing == 0 {
        return Err("its depths do not leave a pass: Q (the first depth), P (the height) beyond the first block's R (the finishing depth) and mm (the finishing passes) must be more than 0".into());
    }
    let dd = t.first.to_mm_f64();
    let mut depths: Vec<Length> = Vec::new();
    let mut n = 1.0_f64;
    loop {
        let formula = Length::from_mm_f64(dd * n.sqrt());
        let before = if t.min_from_actual {
            depths.last().copied().unwrap_or(Length::ZERO)
        } else {
            Length::from_mm_f64(dd * (n - 1.0).sqrt())
        };
        let depth = formula.max(before + t.min_cut).min(rough_to);
        depths.push(depth);
        if depth >= rough_to {
            break;
        }
        if depths.len() > 1_000 {
            return Err("it would cut more than 1,000 passes".into());
        }
        n += 1.0;
    }
    depths.extend(std::iter::repeat_n(t.height, t.finishing as usize));
    Ok(depths)
}

/// A G76 two-block threading cycle from `start`: each pass at its depth (a line parallel to
/// the root's, k − D out from it), its start moved along the flank at a/2 by (k − D)·tan(a/2)
/// towards the thread's start (and its end too when the model says so): a rapid to the
/// pass's start, the thread with its 45° pull-out ending on the end line, a rapid out to the
/// start X, a rapid back to the start. **\[decided\]** spec fanuc.md.
pub fn threading(start: Point, t: &Threading) -> Result<Vec<ItemKind>, Refusal> {
    use crate::ir::{Chamfer, SyncStart, ThreadPass};
    let (sx, sz) = start;
    let (x, z) = t.end;
    let out = (sx - x).signum();
    let back = (sz - z).signum();
    if out == 0 || back == 0 {
        return Err("its start point must lie off the thread, before it".into());
    }
    if 2 * t.taper.0.abs() > 2 * (sz - z).0.abs() {
        return Err("its taper R is steeper than 45°: its F would be a lead along X".into());
    }
    let tan = (f64::from(t.angle) / 2.0).to_radians().tan();
    let pull = t.lead.length_times(i64::from(t.chamfer), 10);
    if 2 * pull.0.abs() > (sx - x).0.abs() || pull >= (z - sz).abs() {
        return Err(format!(
            "its pull-out ({} mm at 45°) goes past the start X or is as long as the thread",
            pull.mm()
        ));
    }
    let mut moves = Vec::new();
    for depth in thread_depths(t)? {
        let rise = t.height - depth;
        let shift = Length(back * Length::from_mm_f64(rise.to_mm_f64() * tan).0);
        let (from_z, to_z) = (sz + shift, if t.end_shifts { z + shift } else { z });
        // The pass's line: the root's moved out by k − D, through (X + 2i, sz) and (X, z).
        let at = |zz: Length| {
            x + Length(out * 2 * rise.0) + (t.taper + t.taper).mul_div((zz - z).0, (sz - z).0)
        };
        let (cut_x, end_x) = (at(from_z), at(to_z));
        // The pull-out ends 2·pull out from the pass, which must stay this side of the start.
        if out * (end_x.0 + out * 2 * pull.0 - sx.0) > 0 {
            return Err(format!(
                "its pull-out ({} mm at 45°) from the pass at X{} goes past the start X{}",
                pull.mm(),
                end_x.mm(),
                sx.mm()
            ));
        }
        moves.push(rapid((cut_x, from_z)));
        moves.push(ItemKind::pass(ThreadPass {
            to: Pos::new(end_x, to_z),
            lead: t.lead,
            start: SyncStart::Index(crate::fixed::Angle::ZERO),
            infeed: None,
            entry: None,
            exit: (pull.0 > 0).then_some(Chamfer {
                length: pull,
                offset: Length(out * 2 * pull.0),
            }),
        }));
        moves.push(rapid((sx, to_z)));
        moves.push(rapid(start));
    }
    Ok(moves)
}

/// The words of a G74 (`facing`: pecks along Z, shifts along X) or G75 (pecks along X, shifts
/// along Z) peck cycle, lengths as radii along X.
#[derive(Clone, Copy, Debug)]
pub struct Pecking {
    pub facing: bool,
    /// Where the pecks end (X a diameter) and the last shift stops.
    pub end: Point,
    /// Δk (G74) or Δi (G75): the depth of each peck.
    pub peck: Length,
    /// Δi (G74) or Δk (G75): the shift between plunges.
    pub shift: Length,
    /// Δd: the relief at the bottom of each plunge, opposite to the shift.
    pub relief: Length,
    /// e: the retract after each peck.
    pub retract: Length,
    pub feed: Length,
}

/// A G74 or G75 peck cycle from `start`: at each position (the start, then a shift towards
/// the end, the last one shortened) a plunge of pecks at feed, each but the last followed by
/// a rapid retract e; at the bottom a rapid relief Δd opposite to the shift (+Z for a G75,
/// +X for a G74, that does not shift), a rapid back to the start's level; at the end a rapid
/// to the start. **\[decided\]** spec fanuc.md, GSK 980TDi and TAC-100XT.
pub fn pecking(start: Point, p: &Pecking) -> Result<Vec<ItemKind>, Refusal> {
    // G75 plunges along X: the Axes of G71, whose layers step along X.
    let ax = Axes { facing: p.facing };
    let (a0, b0) = (ax.across(start), ax.along(start));
    let (a1, b1) = (ax.across(p.end), ax.along(p.end));
    let (sa, sb) = ((a1 - a0).signum(), (b1 - b0).signum());
    let (peck, shift) = (ax.across_units(p.peck), ax.along_units(p.shift));
    if sa == 0 || peck <= 0 || (sb != 0 && shift <= 0) {
        return Err("its pecks do not reach the end: it needs the end beyond the start, and a peck (and a shift) of more than 0".into());
    }
    let back = ax.across_units(p.retract);
    // Opposite to the shift; without one, towards + (TAC-100XT: "positive tool retraction").
    let relief = (if sb == 0 { 1 } else { -sb }) * ax.along_units(p.relief);
    let mut moves = Vec::new();
    let mut b = b0;
    loop {
        let mut a = a0;
        while a != a1 {
            a = if sa * (a1 - (a + sa * peck)) <= 0 {
                a1
            } else {
                a + sa * peck
            };
            moves.push(feed(ax.point(a, b), p.feed));
            if a != a1 && back > 0 {
                moves.push(rapid(ax.point(a - sa * back, b)));
            }
            if moves.len() > 100_000 {
                return Err("it would make more than 100,000 moves".into());
            }
        }
        if relief != 0 {
            moves.push(rapid(ax.point(a1, b + relief)));
        }
        moves.push(rapid(ax.point(a0, b + relief)));
        if b == b1 {
            break;
        }
        b = if sb * (b1 - (b + sb * shift)) <= 0 {
            b1
        } else {
            b + sb * shift
        };
        moves.push(rapid(ax.point(a0, b)));
    }
    // Back to the start, unless the last plunge's return is there (no shift, no relief).
    if ax.point(a0, b + relief) != start {
        moves.push(rapid(start));
    }
    Ok(moves)
}

/// The words and open points of a G71 (or, `facing`, a G72) type I roughing cycle.
#[derive(Clone, Copy, Debug)]
pub struct Roughing {
    /// G72: the layers are along Z and the cuts along X.
    pub facing: bool,
    /// Δd: the depth of each layer (X as a radius for G71, Z for G72).
    pub depth: Length,
    /// e: the 45° retract after each layer (a radius along X, and along Z).
    pub retract: Length,
    /// Δu (a diameter) and Δw: the finishing allowance the roughing contour is shifted by.
    pub allowance: Point,
    /// The roughing feed (the cycle's F, else the one in force).
    pub feed: Length,
    /// The retract runs at rapid (else at feed).
    pub retract_rapid: bool,
    /// The layers are counted from the start shifted by the allowance (else from the start).
    pub from_shifted: bool,
    /// The semi-finish pass along the roughing contour follows the layers (else the tool
    /// goes back to the start after the last layer).
    pub semi_finish: bool,
}

/// The axis the layers step along (`across`) and the one the cuts run along, as diameter or
/// Z grid units, for G71 (layers along X) or G72 (along Z).
#[derive(Clone, Copy)]
struct Axes {
    facing: bool,
}

impl Axes {
    fn across(self, p: Point) -> i64 {
        if self.facing { p.1.0 } else { p.0.0 }
    }
    fn along(self, p: Point) -> i64 {
        if self.facing { p.0.0 } else { p.1.0 }
    }
    fn point(self, across: i64, along: i64) -> Point {
        if self.facing {
            (Length(along), Length(across))
        } else {
            (Length(across), Length(along))
        }
    }
    /// A length along X or Z as grid units of the axis (X is a diameter: twice the radius).
    fn across_units(self, l: Length) -> i64 {
        if self.facing { l.0 } else { 2 * l.0 }
    }
    fn along_units(self, l: Length) -> i64 {
        if self.facing { 2 * l.0 } else { l.0 }
    }
}

/// Why a roughing cycle has no moves under the model.
pub type Refusal = String;

/// A G71 or G72 type I roughing cycle from `start` along `contour` (its first element the
/// block P, from the start to the contour's first point): the layers Δd apart, each infeed
/// at rapid or feed as the first element, each cut along to the roughing contour (the contour
/// shifted by the allowance), the 45° retract e, a rapid back; then the infeed to the
/// roughing contour's start, the semi-finish pass along it at the roughing feed (a rapid in
/// it at feed), and a rapid back to the start. **\[decided\]** spec fanuc.md. Without the
/// semi-finish pass (`g71_semi_finish = false`), the layers are the same and a rapid goes
/// back to the start from the last one: the steps between the layers and the last band
/// (down to the contour's start level) are G70's. **\[decided\]**
pub fn roughing(start: Point, contour: &[Element], r: &Roughing) -> Result<Vec<ItemKind>, Refusal> {
    let ax = Axes { facing: r.facing };
    let [first, profile @ ..] = contour else {
        return Err("its contour has no block".into());
    };
    let Some(last) = profile.last() else {
        return Err("its contour is only its first block".into());
    };
    let shift = r.allowance;
    let moved = |p: Point| (p.0 + shift.0, p.1 + shift.1);
    let p0 = first.to;
    // Type I: monotone in X and Z, its arcs too (an arc that bulges past its ends' box would
    // be cut through by a layer).
    let mut at = p0;
    for e in profile {
        if let Some((c, clockwise)) = e.arc
            && arc_turns(at, e.to, c, clockwise)
        {
            return Err(format!(
                "its contour's arc to X{} Z{} turns past its ends (X or Z is not monotone along it, as type I needs)",
                e.to.0.mm(),
                e.to.1.mm()
            ));
        }
        at = e.to;
    }
    let (side, way) = directions(ax, start, first, last, shift)?;
    let origin = if r.from_shifted { moved(start) } else { start };
    let step = ax.across_units(r.depth);
    // The 45° retract: e along both axes.
    let back = ax.point(
        -side * ax.across_units(r.retract),
        -way * ax.along_units(r.retract),
    );
    let p0s = moved(p0);
    let infeed = |p: Point| {
        if first.rapid {
            rapid(p)
        } else {
            feed(p, r.feed)
        }
    };
    let mut moves = Vec::new();
    if origin != start {
        moves.push(rapid(origin));
    }
    let b0 = ax.along(origin);
    let mut level = ax.across(origin);
    let mut k = 0u32;
    let mut here = origin;
    loop {
        level += side * step;
        if side * (level - ax.across(p0s)) >= 0 {
            break;
        }
        k += 1;
        if k > 10_000 {
            return Err("it would cut more than 10,000 layers".into());
        }
        let name = if r.facing {
            format!("its layer {k} at Z{}", Length(level).mm())
        } else {
            format!("its layer {k} at X{}", Length(level).mm())
        };
        let hit = layer_end(ax, level, p0s, profile, shift).ok_or_else(|| {
            format!("{name} misses the roughing contour (the contour moved by U and W)")
        })?;
        if way * (hit - b0) <= 0 {
            return Err(format!(
                "{name} meets the roughing contour before the cycle's start point"
            ));
        }
        moves.push(infeed(ax.point(level, b0)));
        moves.push(feed(ax.point(level, hit), r.feed));
        let out = (
            ax.point(level, hit).0 + back.0,
            ax.point(level, hit).1 + back.1,
        );
        moves.push(if r.retract_rapid {
            rapid(out)
        } else {
            feed(out, r.feed)
        });
        here = ax.point(ax.across(out), b0);
        moves.push(rapid(here));
    }
    if r.semi_finish {
        moves.push(infeed(p0s));
        moves.extend(profile.iter().map(|e| e.item(shift, Some(r.feed))));
        moves.push(rapid(start));
    } else if here != start {
        moves.push(rapid(start));
    }
    Ok(moves)
}

/// Which way the layers step (across) and the cuts run (along), each ±1: the contour's first
/// block moves across only, away from the start; its last point lies along the cut from its
/// first; the allowance points away from the part.
fn directions(
    ax: Axes,
    start: Point,
    first: &Element,
    last: &Element,
    shift: Point,
) -> Result<(i64, i64), Refusal> {
    let p0 = first.to;
    let (side, way) = (
        (ax.across(p0) - ax.across(start)).signum(),
        (ax.along(last.to) - ax.along(p0)).signum(),
    );
    if side == 0 || first.arc.is_some() || ax.along(p0) != ax.along(start) {
        return Err(format!(
            "its contour's first block must move {} only, away from the start point",
            if ax.facing { "along Z" } else { "along X" }
        ));
    }
    if way == 0 {
        return Err("its contour does not move along the cut".into());
    }
    let (sa, sb) = (ax.across(shift).signum(), ax.along(shift).signum());
    if sa == side || sb == way {
        return Err("its finishing allowance (U, W) points into the part".into());
    }
    Ok((side, way))
}

/// Where the layer at `level` (across, in grid units) meets the roughing contour (`profile`
/// from `from`, shifted by `shift`), along: the first element that reaches the level; where
/// the contour then runs on along the layer (straight elements parallel to it), the end of the
/// last of them, where the contour leaves the level: the band between this layer and the one
/// before lies above those elements, and the layer is there to cut it. **\[decided\]** (no
/// source says; stopping where the layer first touches would leave that band, up to Δd deep,
/// to the semi-finish pass). `None`: no element reaches it.
fn layer_end(ax: Axes, level: i64, from: Point, profile: &[Element], shift: Point) -> Option<i64> {
    let shifted = |e: &Element| (e.to.0 + shift.0, e.to.1 + shift.1);
    let mut p = from;
    for (i, e) in profile.iter().enumerate() {
        let q = shifted(e);
        let (a0, a1) = (ax.across(p), ax.across(q));
        let hit = match e.arc {
            None if a0 == level && a1 == level => Some(ax.along(q)),
            None if a0.min(a1) <= level && level <= a0.max(a1) => {
                let t = (level - a0) as f64 / (a1 - a0) as f64;
                let (b0, b1) = (ax.along(p) as f64, ax.along(q) as f64);
                Some(on_step(b0 + t * (b1 - b0)))
            }
            None => None,
            Some((c, _)) => arc_hit(ax, level, p, q, (c.0 + shift.0, c.1 + shift.1)),
        };
        if let Some(mut b) = hit {
            if a1 == level {
                for next in &profile[i + 1..] {
                    let q = shifted(next);
                    if next.arc.is_some() || ax.across(q) != level {
                        break;
                    }
                    b = ax.along(q);
                }
            }
            return Some(b);
        }
        p = q;
    }
    None
}

/// Whether the arc from `p` to `q` around `c` (clockwise as LinuxCNC's G2 in G18: Z the
/// first axis, X the second) passes, strictly between its ends, a point where X or Z turns
/// (its quarter points): then it leaves its ends' box.
fn arc_turns(p: Point, q: Point, c: Point, clockwise: bool) -> bool {
    use std::f64::consts::{FRAC_PI_2, TAU};
    // The angle in (Z, X) with X as a radius.
    let angle = |pt: Point| {
        let x = (pt.0.0 - c.0.0) as f64 / 2.0;
        let z = (pt.1.0 - c.1.0) as f64;
        x.atan2(z)
    };
    let (a0, a1) = (angle(p), angle(q));
    // The sweep from p to q, counter-clockwise positive; a whole turn when they meet.
    let mut sweep = (a1 - a0).rem_euclid(TAU);
    if clockwise {
        sweep -= TAU;
        if sweep == -TAU && p != q {
            sweep = 0.0;
        }
    } else if sweep == 0.0 {
        sweep = TAU;
    }
    const EPS: f64 = 1e-9;
    (0..4).any(|k| {
        let t = f64::from(k) * FRAC_PI_2;
        if clockwise {
            let d = (t - a0).rem_euclid(TAU) - TAU;
            d > sweep + EPS && d < -EPS
        } else {
            let d = (t - a0).rem_euclid(TAU);
            d > EPS && d < sweep - EPS
        }
    })
}

/// `v` grid units rounded onto the 0.0001 mm step, where computed values lie.
fn on_step(v: f64) -> i64 {
    (v / Length::STEP as f64).round() as i64 * Length::STEP
}

/// Where an arc from `p` to `q` around `c` meets the level, along (grid units): the crossing
/// between its ends' along coordinates, nearest `p`. Real geometry: X as a radius.
fn arc_hit(ax: Axes, level: i64, p: Point, q: Point, c: Point) -> Option<i64> {
    // A type I contour's arc lies within its ends' box (`arc_turns`, checked by `roughing`).
    let (a0, a1) = (ax.across(p), ax.across(q));
    if level < a0.min(a1) || level > a0.max(a1) {
        return None;
    }
    // Real coordinates in grid units, X halved: (across, along).
    let real = |v: i64, is_x: bool| if is_x { v as f64 / 2.0 } else { v as f64 };
    let (ax_x, al_x) = (!ax.facing, ax.facing);
    let (la, ca, cb) = (
        real(level, ax_x),
        real(ax.across(c), ax_x),
        real(ax.along(c), al_x),
    );
    let (pa, pb) = (real(ax.across(p), ax_x), real(ax.along(p), al_x));
    let radius = (pa - ca).hypot(pb - cb);
    let d = radius * radius - (la - ca) * (la - ca);
    if d < 0.0 {
        return None;
    }
    let (lo, hi) = {
        let (a, b) = (ax.along(p), ax.along(q));
        (a.min(b), a.max(b))
    };
    let back = |b: f64| {
        if al_x { on_step(b * 2.0) } else { on_step(b) }
    };
    let candidates = [cb - d.sqrt(), cb + d.sqrt()].map(back);
    candidates
        .into_iter()
        .filter(|b| (lo..=hi).contains(b))
        .min_by_key(|b| (b - ax.along(p)).abs())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mm(v: f64) -> Length {
        Length::from_mm_f64(v)
    }

    fn pt(x: f64, z: f64) -> Point {
        (mm(x), mm(z))
    }

    fn line(x: f64, z: f64, rapid: bool) -> Element {
        Element {
            comp: None,
            to: pt(x, z),
            arc: None,
            rapid,
            feed: mm(0.15),
        }
    }

    fn ends(moves: &[ItemKind]) -> Vec<(String, f64, f64)> {
        moves
            .iter()
            .map(|m| {
                let (kind, to) = match m {
                    ItemKind::Rapid { to } => ("G00", to),
                    ItemKind::Feed { to, .. } => ("G01", to),
                    ItemKind::Arc { to, .. } => ("arc", to),
                    _ => ("?", &Pos::UNKNOWN),
                };
                (
                    kind.to_string(),
                    to.x.unwrap().to_mm_f64(),
                    to.z.unwrap().to_mm_f64(),
                )
            })
            .collect()
    }

    /// G90 X38. Z-30. R-2. from X52. Z2.: rapid to Ø34 (the radius 2 smaller at the start),
    /// cut to Ø38 Z-30, out at feed to Ø52, rapid back. Derived by hand from the model.
    #[test]
    fn a_g90_taper_cuts_from_the_smaller_diameter() {
        let m = turning(pt(52.0, 2.0), pt(38.0, -30.0), mm(-2.0), false, mm(0.25));
        let e = |k: &str, x, z| (k.to_string(), x, z);
        assert_eq!(
            ends(&m),
            [
                e("G00", 34.0, 2.0),
                e("G01", 38.0, -30.0),
                e("G01", 52.0, -30.0),
                e("G00", 52.0, 2.0)
            ]
        );
        let f = turning(pt(52.0, 2.0), pt(10.0, -3.0), mm(0.0), true, mm(0.2));
        assert_eq!(
            ends(&f),
            [
                e("G00", 52.0, -3.0),
                e("G01", 10.0, -3.0),
                e("G01", 10.0, 2.0),
                e("G00", 52.0, 2.0)
            ]
        );
    }

    /// A stepped shaft roughed from X52 Z2 with Δd 2, e 0.5, U0.4 W0.1 (GSK's model: layers
    /// from the shifted start X52.4 Z2.1, retract at feed). Each layer's end derived by hand:
    /// the roughing contour is Ø20.4 Z2.1 → Z-14.9 → Ø30.4 Z-24.9 → Z-39.9 → Ø52.4.
    #[test]
    fn a_g71_roughs_in_layers_then_along_the_contour() {
        let contour = [
            line(20.0, 2.0, true),
            line(20.0, -15.0, false),
            line(30.0, -25.0, false),
            line(30.0, -40.0, false),
            line(52.0, -40.0, false),
        ];
        let r = Roughing {
            facing: false,
            depth: mm(2.0),
            retract: mm(0.5),
            allowance: (mm(0.4), mm(0.1)),
            feed: mm(0.25),
            retract_rapid: false,
            from_shifted: true,
            semi_finish: true,
        };
        let m = roughing(pt(52.0, 2.0), &contour, &r).unwrap();
        let e = |k: &str, x, z| (k.to_string(), x, z);
        let mut want = vec![e("G00", 52.4, 2.1)];
        // Layers at Ø48.4, 44.4, 40.4, 36.4, 32.4: they meet the last element (Z-39.9);
        // Ø28.4 and 24.4 meet the taper from Ø20.4 Z-14.9 to Ø30.4 Z-24.9: Z-22.9, -18.9.
        for (x, z) in [
            (48.4, -39.9),
            (44.4, -39.9),
            (40.4, -39.9),
            (36.4, -39.9),
            (32.4, -39.9),
            (28.4, -22.9),
            (24.4, -18.9),
        ] {
            want.push(e("G00", x, 2.1));
            want.push(e("G01", x, z));
            want.push(e("G01", x + 1.0, z + 0.5));
            want.push(e("G00", x + 1.0, 2.1));
        }
        want.extend([
            e("G00", 20.4, 2.1),
            e("G01", 20.4, -14.9),
            e("G01", 30.4, -24.9),
            e("G01", 30.4, -39.9),
            e("G01", 52.4, -39.9),
            e("G00", 52.0, 2.0),
        ]);
        assert_eq!(ends(&m), want);
        // Without the semi-finish pass: the same layers, then a rapid back to the start.
        let r = Roughing {
            semi_finish: false,
            ..r
        };
        let m = roughing(pt(52.0, 2.0), &contour, &r).unwrap();
        want.truncate(want.len() - 6);
        want.push(e("G00", 52.0, 2.0));
        assert_eq!(ends(&m), want);
    }

    /// G76 with Δdmin counted from the actual depths, each pass's end moved with its start,
    /// and a pull-out of 10 tenths of the 2 mm lead. By hand: depths 0.5, 0.5√2 = 0.7071,
    /// 0.5√3 = 0.866, then k − d = 0.9, then k = 1 (m = 1); pass 1 is Ø20 + 2 × 0.5 = Ø21,
    /// moved 0.5 × tan 30° = 0.2887 at both ends, its pull-out 2 mm long and 4 mm out.
    #[test]
    fn a_g76_passes_down_the_flank() {
        let t = Threading {
            end: pt(20.0, -20.0),
            taper: Length::ZERO,
            height: mm(1.0),
            first: mm(0.5),
            min_cut: mm(0.1),
            finish: mm(0.1),
            finishing: 1,
            chamfer: 10,
            angle: 60,
            lead: crate::fixed::Lead::from_length(mm(2.0)),
            min_from_actual: true,
            end_shifts: true,
        };
        let m = threading(pt(30.0, 5.0), &t).unwrap();
        assert_eq!(m.len(), 5 * 4);
        let passes: Vec<(f64, f64, f64)> = m
            .chunks(4)
            .map(|c| match (&c[0], &c[1]) {
                (ItemKind::Rapid { to: a }, ItemKind::ThreadPass(p)) => (
                    a.x.unwrap().to_mm_f64(),
                    a.z.unwrap().to_mm_f64(),
                    p.to.z.unwrap().to_mm_f64(),
                ),
                other => panic!("{other:?}"),
            })
            .collect();
        assert_eq!(
            passes,
            [
                (21.0, 5.2887, -19.7113),
                (20.5858, 5.1691, -19.8309),
                (20.268, 5.0774, -19.9226),
                (20.2, 5.0577, -19.9423),
                (20.0, 5.0, -20.0)
            ]
        );
        let ItemKind::ThreadPass(p) = &m[1] else {
            unreachable!()
        };
        assert_eq!(
            p.exit.map(|e| (
                e.length.0 / crate::fixed::Length::STEP,
                e.offset.0 / crate::fixed::Length::STEP
            )),
            Some((20_000, 40_000))
        );
        // A pull-out longer than the room to the start X is refused: from X24.5 the root
        // leaves 4.5 mm (room for 2 × 2 mm), but the first pass, at X21, only 3.5.
        let e = threading(pt(24.5, 5.0), &t).unwrap_err();
        assert!(e.contains("from the pass at X21"), "{e}");
        assert!(threading(pt(25.0, 5.0), &t).is_ok());
    }

    /// A G75 without a shift relieves towards +Z at its bottom; with one, against it.
    #[test]
    fn a_g75_relieves_against_its_shift_or_towards_plus_z() {
        let mut p = Pecking {
            facing: false,
            end: pt(30.0, -10.0),
            peck: mm(10.0),
            shift: mm(2.0),
            relief: mm(0.2),
            retract: mm(0.5),
            feed: mm(0.1),
        };
        let relief_z = |p: &Pecking| match &pecking(pt(42.0, -10.0), p).unwrap()[1] {
            ItemKind::Rapid { to } => to.z.unwrap().to_mm_f64(),
            other => panic!("{other:?}"),
        };
        assert_eq!(relief_z(&p), -9.8);
        p.end = pt(30.0, -14.0);
        assert_eq!(relief_z(&p), -9.8);
        p.end = pt(30.0, -6.0);
        assert_eq!(relief_z(&p), -10.2);
    }

    /// A layer that misses the contour, and an allowance into the part, are refused; a layer on
    /// an element parallel to it cuts along it to its end.
    #[test]
    fn what_the_model_leaves_open_is_refused() {
        let contour = [
            line(20.0, 2.0, true),
            line(20.0, -15.0, false),
            line(40.0, -15.0, false),
            line(40.4, -30.0, false),
        ];
        let mut r = Roughing {
            facing: false,
            depth: mm(2.0),
            retract: mm(0.5),
            allowance: (mm(0.0), mm(0.0)),
            feed: mm(0.25),
            retract_rapid: false,
            from_shifted: true,
            semi_finish: true,
        };
        // From Ø48 the first layer, Ø44, is beyond the contour's largest diameter, Ø40.
        let e = roughing(pt(48.0, 2.0), &contour[..3], &r).unwrap_err();
        assert!(e.contains("misses"), "{e}");
        r.allowance = (mm(-0.4), mm(0.0));
        let e = roughing(pt(44.0, 2.0), &contour, &r).unwrap_err();
        assert!(e.contains("into the part"), "{e}");
        let flat = [
            line(20.0, 2.0, true),
            line(20.0, -15.0, false),
            line(24.0, -15.0, false),
            line(24.0, -30.0, false),
            line(44.0, -30.0, false),
        ];
        r.allowance = (mm(0.0), mm(0.0));
        let moves = roughing(pt(44.0, 2.0), &flat, &r).unwrap();
        // The layers Ø40, 36, 32, 28 end on the step at Z-30 (its face); Ø24 runs along the
        // element Ø24 from Z-15 to its end, Z-30, where the contour leaves it.
        let cut_to = |x: f64| {
            moves.iter().find_map(|m| match m {
                ItemKind::Feed { to, .. } if to.x == Some(mm(x)) && to.z != Some(mm(2.0)) => to.z,
                _ => None,
            })
        };
        assert_eq!(cut_to(28.0), Some(mm(-30.0)));
        assert_eq!(cut_to(24.0), Some(mm(-30.0)));
    }

    /// An arc of a type I contour stays within its ends' box: a quarter fillet does, a half
    /// circle between two points of one diameter turns past them (either way round).
    #[test]
    fn an_arc_that_turns_past_its_ends_is_found() {
        // G03 X37. Z-38. R6. from X25. Z-32.: a quarter, its ends the quarter points.
        assert!(!arc_turns(
            pt(25.0, -32.0),
            pt(37.0, -38.0),
            pt(25.0, -38.0),
            false
        ));
        // The same quarter back, clockwise.
        assert!(!arc_turns(
            pt(37.0, -38.0),
            pt(25.0, -32.0),
            pt(25.0, -38.0),
            true
        ));
        // Half circles from X40. Z-15. to X40. Z-25. around X40. Z-20.: out to X50 (G03) or
        // in to X30 (G02).
        assert!(arc_turns(
            pt(40.0, -15.0),
            pt(40.0, -25.0),
            pt(40.0, -20.0),
            false
        ));
        assert!(arc_turns(
            pt(40.0, -15.0),
            pt(40.0, -25.0),
            pt(40.0, -20.0),
            true
        ));
        // From X30. Z0. to X34. Z-6. around X50. Z0. (radius 10): the short way (G02) stays
        // in the box, the long way (G03) turns past it.
        assert!(!arc_turns(
            pt(30.0, 0.0),
            pt(34.0, -6.0),
            pt(50.0, 0.0),
            true
        ));
        assert!(arc_turns(
            pt(30.0, 0.0),
            pt(34.0, -6.0),
            pt(50.0, 0.0),
            false
        ));
    }
}

//! Lowering: the one implementation of how thread operations become straight synchronised
//! moves. Emitters, `explain`, `plot` and the simulator all call these functions.
//! [`g7x`] is LinuxCNC's roughing and finishing cycles.

pub mod fanuc;
pub mod g7x;

use crate::fixed::{Angle, Lead, Length, div_round};
use crate::ir::{
    Chamfer, Degression, Finish, ItemKind, Pos, Retract, Rise, Schedule, SyncInfeed, SyncStart,
    ThreadCycle, ThreadPass,
};

/// One straight spindle-synchronised move.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SyncSegment {
    pub from: Pos,
    pub to: Pos,
    /// Advance along Z per spindle revolution.
    pub lead: Lead,
}

/// What a pass needs that it does not have.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LowerError {
    /// An entry, runout, taper or start shift needs the start point, which is unknown.
    UnknownStart,
}

impl SyncSegment {
    /// A move along X only (a synchronised infeed): its `lead` is the advance along X.
    pub fn is_radial(&self) -> bool {
        self.from.z.is_some() && self.from.z == self.to.z
    }

    /// X (as a radius) moves more than Z ([`steeper_than_45`]); a move along X only is, and
    /// so is one whose ends are not known to be otherwise when it runs along X.
    pub fn is_steep(&self) -> bool {
        match (self.from.known(), self.to.known()) {
            (Some(a), Some(b)) => steeper_than_45(a, b),
            _ => self.is_radial(),
        }
    }

    /// The advance per revolution along the segment's own path (LinuxCNC's G33 K): the Z
    /// lead scaled by path length / |ΔZ|, with X converted from diameter to radius.
    pub fn lead_along_path(&self) -> f64 {
        let lead = self.lead.to_mm_f64();
        let (Some(z0), Some(z1)) = (self.from.z, self.to.z) else {
            return lead;
        };
        let dr = match (self.from.x, self.to.x) {
            (Some(x0), Some(x1)) => (x1 - x0).to_mm_f64() / 2.0,
            _ => 0.0,
        };
        let dz = (z1 - z0).to_mm_f64();
        if dr == 0.0 || dz == 0.0 {
            return lead;
        }
        lead * dz.hypot(dr) / dz.abs()
    }
}

/// Whether a move from `a` to `b` ((X diameter, Z)) is steeper than 45°: X, as a radius, moves
/// more than Z (a move along X only included). The one rule for a lead given along the long
/// axis (FANUC's G32 F).
pub fn steeper_than_45(a: (Length, Length), b: (Length, Length)) -> bool {
    (b.0 - a.0).0.unsigned_abs() > 2 * (b.1 - a.1).0.unsigned_abs()
}

/// The lead along Z of a synchronised move that advances `k_mm` per revolution along its
/// path (LinuxCNC's G33 K) and travels `dz` along Z and `dx` on the diameter: K·|ΔZ|/length,
/// rounded once onto the lead grid. The one rule for the ISO reader and writer.
pub fn z_lead_of_k(k_mm: f64, dz: Length, dx: Length) -> Option<Lead> {
    let (dz, dr) = (dz.to_mm_f64(), dx.to_mm_f64() / 2.0);
    if dz == 0.0 {
        return None;
    }
    Lead::from_mm_f64(k_mm * dz.abs() / dz.hypot(dr)).filter(|l| l.0 > 0)
}

/// X on the line through `a` and `b` at `z`, rounded onto the grid.
fn x_on_line(a: (Length, Length), b: (Length, Length), z: Length) -> Length {
    let (ax, az) = a;
    let (bx, bz) = b;
    if bz == az {
        return ax;
    }
    ax + (bx - ax).mul_div((z - az).0, (bz - az).0)
}

/// The synchronised moves of `pass` starting at `start`: infeed, entry, thread, runout, in
/// order, without empty segments. An infeed segment has no Z travel; its `lead` is the
/// advance along X (per side) per revolution.
pub fn pass_segments(start: Pos, pass: &ThreadPass) -> Result<Vec<SyncSegment>, LowerError> {
    let end = Pos {
        x: pass.to.x.or(start.x),
        z: pass.to.z.or(start.z),
    };
    if pass.entry.is_none() && pass.exit.is_none() && pass.infeed.is_none() {
        return Ok(vec![SyncSegment {
            from: start,
            to: end,
            lead: pass.lead,
        }]);
    }
    let (sx, sz) = start.known().ok_or(LowerError::UnknownStart)?;
    let (ex, ez) = end.known().ok_or(LowerError::UnknownStart)?;
    let direction = (ez - sz).signum();
    let mut segments = Vec::with_capacity(4);
    // The entry (or the thread) starts where the infeed ends.
    let sx = match pass.infeed {
        Some(infeed) if infeed.x != sx => {
            segments.push(SyncSegment {
                from: Pos::new(sx, sz),
                to: Pos::new(infeed.x, sz),
                lead: infeed.advance,
            });
            infeed.x
        }
        _ => sx,
    };
    let line_from = (sx - pass.entry.map_or(Length::ZERO, |e| e.offset), sz);
    let line_to = (ex, ez);
    // The start, the entry's end, the exit's start and end: room for all four.
    let mut points = Vec::with_capacity(4);
    points.push(Pos::new(sx, sz));
    if let Some(entry) = pass.entry {
        let z = sz + Length(direction * entry.length.0);
        points.push(Pos::new(x_on_line(line_from, line_to, z), z));
    }
    if let Some(exit) = pass.exit {
        let z = ez - Length(direction * exit.length.0);
        points.push(Pos::new(x_on_line(line_from, line_to, z), z));
        points.push(Pos::new(ex + exit.offset, ez));
    } else {
        points.push(Pos::new(ex, ez));
    }
    points.dedup();
    segments.extend(points.windows(2).map(|w| SyncSegment {
        from: w[0],
        to: w[1],
        lead: pass.lead,
    }));
    Ok(segments)
}

/// Expresses a start angle without one: the first segment starts `lead·θ/360` earlier
/// along its own line, at the index pulse, and so cuts the same helix. Returns the new
/// start point (the caller moves there first). The shift is rounded once onto the grid and
/// stays under one lead (an angle just under 360° that rounds to a whole lead is no shift).
pub fn start_angle_as_shift(
    segments: &mut [SyncSegment],
    angle: Angle,
) -> Result<Option<(Pos, Length)>, LowerError> {
    if angle == Angle::ZERO {
        return Ok(None);
    }
    let Some(first) = segments.first_mut() else {
        return Ok(None);
    };
    let (Some(z0), Some(z1)) = (first.from.z, first.to.z) else {
        return Err(LowerError::UnknownStart);
    };
    let mut shift = first.lead.of_angle(angle);
    let full_turn = first.lead.length_times(1, 1);
    if shift >= full_turn {
        shift = shift - full_turn;
    }
    if shift == Length::ZERO {
        return Ok(None);
    }
    let direction = (z1 - z0).signum();
    let z = z0 - Length(direction * shift.0);
    let x = match (first.from.x, first.to.x) {
        (Some(x0), Some(x1)) if x0 != x1 => {
            Some(x0 - (x1 - x0).mul_div(shift.0, (z1 - z0).abs().0))
        }
        (Some(x0), _) => Some(x0),
        (None, Some(_)) => return Err(LowerError::UnknownStart),
        (None, None) => None,
    };
    first.from = Pos { x, z: Some(z) };
    Ok(Some((first.from, shift)))
}

/// More passes than any real thread needs: a cycle asking for more is a typing error, and
/// expanding it would only exhaust memory.
pub const MAX_PASSES: usize = 1000;

/// Why a thread cycle cannot be cut.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ExpandError {
    /// The lead is zero or negative.
    Lead,
    /// The end Z equals the start Z.
    NoTravel,
    /// The first depth is zero or negative.
    FirstDepth,
    /// The total depth is smaller than the schedule's minimum.
    DepthTooSmall { minimum: Length },
    /// The schedule needs more than [`MAX_PASSES`] passes.
    TooManyPasses,
    /// The Z travel of pass `pass` (after its infeed shift) cannot hold the runout.
    ShortPass { pass: usize, travel: Length },
}

impl ExpandError {
    /// What is wrong, for a diagnostic message.
    pub fn message(&self, cycle: &ThreadCycle) -> String {
        match self {
            ExpandError::Lead => format!("the lead {} mm is not positive", cycle.lead),
            ExpandError::NoTravel => format!(
                "the cycle ends at Z{} where it starts: there is no thread length",
                cycle.end_z.mm()
            ),
            ExpandError::FirstDepth => format!(
                "the first-pass depth {} mm is not positive",
                cycle.first_depth.mm()
            ),
            ExpandError::DepthTooSmall { minimum } => match cycle.schedule {
                Schedule::AreaInPasses(n) | Schedule::DepthInPasses(n) => format!(
                    "the thread depth {} mm is too small for {n} passes that each cut at least 0.0001 mm ({} schedule: at least {} mm)",
                    cycle.depth.mm(),
                    cycle.schedule.id(),
                    minimum.mm()
                ),
                _ => format!(
                    "the thread depth {} mm is smaller than the {} schedule needs for a first pass of {} mm (at least {} mm)",
                    cycle.depth.mm(),
                    cycle.schedule.id(),
                    cycle.first_depth.mm(),
                    minimum.mm()
                ),
            },
            ExpandError::TooManyPasses => match cycle.schedule {
                Schedule::AreaInPasses(n) | Schedule::DepthInPasses(n) => {
                    format!("{n} passes are more than the {MAX_PASSES} ncthread cuts")
                }
                _ => format!(
                    "a depth of {} mm in first passes of {} mm needs more than {MAX_PASSES} passes",
                    cycle.depth.mm(),
                    cycle.first_depth.mm()
                ),
            },
            ExpandError::ShortPass { pass, travel } => {
                let what = match (cycle.entry, cycle.runout) {
                    (Some(e), Some(r)) => {
                        format!("{} mm of entry and runout", (e.length + r.length).mm())
                    }
                    (Some(e), None) => format!("{} mm entry", e.length.mm()),
                    (None, Some(r)) => format!("{} mm runout", r.length.mm()),
                    (None, None) => "pass".to_string(),
                };
                format!(
                    "pass {pass} travels {} mm along Z, which cannot hold the {what}",
                    travel.mm()
                )
            }
        }
    }
}

/// The cumulative depth after each pass of `schedule`, ending exactly at `depth`.
pub fn pass_depths(
    schedule: Schedule,
    depth: Length,
    first: Length,
) -> Result<Vec<Length>, ExpandError> {
    let in_passes = matches!(
        schedule,
        Schedule::AreaInPasses(_) | Schedule::DepthInPasses(_)
    );
    if first.0 <= 0 && !in_passes {
        return Err(ExpandError::FirstDepth);
    }
    // In 0.0001 mm steps, where the schedules' integer rules are defined; the last pass
    // ends at `depth` itself (an inch depth lies between two steps).
    let step = |l: Length| div_round(l.0 as i128, Length::STEP as i128) as i64;
    let (p1, p2) = (step(depth), step(first).max(1));
    let mut depths = depths_in_steps(schedule, depth, p1, p2)?;
    if let Some(last) = depths.last_mut()
        && step(*last) == p1
    {
        *last = depth;
    }
    Ok(depths)
}

/// [`pass_depths`] with the depth and the first cut `p1`, `p2` in 0.0001 mm steps.
fn depths_in_steps(
    schedule: Schedule,
    depth: Length,
    p1: i64,
    p2: i64,
) -> Result<Vec<Length>, ExpandError> {
    let first = Length::from_steps(p2);
    match schedule {
        Schedule::Halving => {
            // f = P2/2, P2/4, P2/8, P2/16 (integer division); k passes of P2; a remainder.
            let last_four = [p2 / 2, p2 / 4, p2 / 8, p2 / 16];
            let tail: i64 = last_four.iter().sum();
            if p1 < p2 + tail {
                return Err(ExpandError::DepthTooSmall {
                    minimum: Length::from_steps(p2 + tail),
                });
            }
            let full = (p1 - tail) / p2;
            let rest = p1 - tail - full * p2;
            if full as usize + 5 > MAX_PASSES {
                return Err(ExpandError::TooManyPasses);
            }
            let mut cuts = vec![p2; full as usize];
            if rest > 0 {
                cuts.push(rest);
            }
            cuts.extend(last_four);
            Ok(cumulative(&cuts))
        }
        Schedule::ConstantDepth => {
            if p1 < p2 {
                return Err(ExpandError::DepthTooSmall { minimum: first });
            }
            let n = (p1 + p2 - 1) / p2;
            if n as usize > MAX_PASSES {
                return Err(ExpandError::TooManyPasses);
            }
            Ok((1..=n)
                .map(|i| Length::from_steps((i * p2).min(p1)))
                .collect())
        }
        Schedule::ConstantArea => {
            if p1 < p2 {
                return Err(ExpandError::DepthTooSmall { minimum: first });
            }
            // c_n = P2·√n reaches P1 at n = (P1/P2)².
            let (p1w, p2w) = (p1 as u128, p2 as u128);
            if p1w * p1w > p2w * p2w * (MAX_PASSES as u128 - 1) {
                return Err(ExpandError::TooManyPasses);
            }
            let mut depths = Vec::new();
            for n in 1.. {
                let c = round_sqrt(p2w * p2w * n) as i64;
                if c >= p1 {
                    depths.push(depth);
                    break;
                }
                depths.push(Length::from_steps(c));
            }
            Ok(depths)
        }
        Schedule::Degression(d) => degression_depths(&d, depth),
        Schedule::AreaInPasses(n) | Schedule::DepthInPasses(n) => {
            let n = i64::from(n);
            if n as usize > MAX_PASSES {
                return Err(ExpandError::TooManyPasses);
            }
            // Every cut at least one step: the smallest is the last, P1·(1 − √(1 − 1/N)) ≥
            // P1/(2N) for the area law, P1/N for the depth law; cuts of a step or more round
            // to different depths.
            let area = matches!(schedule, Schedule::AreaInPasses(_));
            let minimum = if area { 2 * n } else { n }.max(1);
            if n < 1 || p1 < minimum {
                return Err(ExpandError::DepthTooSmall {
                    minimum: Length::from_steps(minimum),
                });
            }
            Ok((1..=n)
                .map(|i| {
                    Length::from_steps(if area {
                        // √(P1²·i/N), the square rounded first.
                        let square = div_round(p1 as i128 * p1 as i128 * i as i128, n as i128);
                        round_sqrt(square as u128) as i64
                    } else {
                        div_round(p1 as i128 * i as i128, n as i128) as i64
                    })
                })
                .collect())
        }
        Schedule::RemainderFirst => {
            // P1 = k·P2 + r: r first (when not 0), k − 1 passes of P2, then P2 split.
            if p1 < p2 {
                return Err(ExpandError::DepthTooSmall { minimum: first });
            }
            let (k, rest) = (p1 / p2, p1 % p2);
            if k as usize + 4 > MAX_PASSES {
                return Err(ExpandError::TooManyPasses);
            }
            let split = [p2 / 2, p2 / 4, p2 / 8, p2 - p2 / 2 - p2 / 4 - p2 / 8];
            let mut cuts: Vec<i64> = (rest > 0).then_some(rest).into_iter().collect();
            cuts.extend(std::iter::repeat_n(p2, k as usize - 1));
            cuts.extend(split.into_iter().filter(|&c| c > 0));
            Ok(cumulative(&cuts))
        }
    }
}

/// LinuxCNC's G76 loop, in its own floating-point arithmetic so that the pass count is
/// the one LinuxCNC cuts: depth `|I| + |J|·n^(1/R)` (program units, scaled as LinuxCNC scales
/// words) while it is less than `|I| + |K|`, then the full depth (`depth`, exact).
fn degression_depths(d: &Degression, depth: Length) -> Result<Vec<Length>, ExpandError> {
    let unit = |v: crate::fixed::Decimal| {
        let v = v.to_f64();
        d.scale.apply(v).abs()
    };
    let (i, j, k) = (unit(d.i), unit(d.j), unit(d.k));
    if j <= 0.0 {
        return Err(ExpandError::FirstDepth);
    }
    let r = d.r.to_f64().max(1.0);
    let to_mm = if d.inch { 25.4 } else { 1.0 };
    let end = k + i;
    let mut current = i + j;
    let mut n = 1;
    let mut depths = Vec::new();
    while current < end {
        if depths.len() >= MAX_PASSES {
            return Err(ExpandError::TooManyPasses);
        }
        depths.push(Length::from_mm_f64((current - i) * to_mm).min(depth));
        n += 1;
        current = i + j * (n as f64).powf(1.0 / r);
    }
    depths.push(depth);
    Ok(depths)
}

fn cumulative(cuts: &[i64]) -> Vec<Length> {
    cuts.iter()
        .scan(0, |c, cut| {
            *c += cut;
            Some(Length::from_steps(*c))
        })
        .collect()
}

/// √v rounded to the nearest integer.
fn round_sqrt(v: u128) -> u128 {
    let r = v.isqrt();
    if v - r * r > r { r + 1 } else { r }
}

/// One pass of an expanded cycle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CyclePass {
    /// 1-based.
    pub number: usize,
    /// Cumulative depth per side after this pass.
    pub depth: Length,
    /// Depth of cut of this pass.
    pub cut: Length,
    /// Where the synchronised move starts (reached by a rapid).
    pub start: Pos,
    pub pass: ThreadPass,
    /// The diameter the tool retracts to before it returns to the start Z.
    pub retract_x: Length,
}

/// A move of an expanded cycle: a rapid, or a pass.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Move {
    Rapid(Pos),
    Pass(ThreadPass),
}

impl Move {
    /// The move as an IR item.
    pub fn item_kind(&self) -> ItemKind {
        match *self {
            Move::Rapid(to) => ItemKind::Rapid { to },
            Move::Pass(pass) => ItemKind::pass(pass),
        }
    }

    /// Where the tool is after the move, starting from `current` (as its item's
    /// [`ItemKind::end_position`], without making the item).
    pub fn end_position(&self, current: Pos) -> Pos {
        match self {
            Move::Rapid(to) => Pos {
                x: to.x.or(current.x),
                z: to.z.or(current.z),
            },
            Move::Pass(pass) => pass.end_position(current),
        }
    }
}

/// One move of an expanded cycle, with the pass it belongs to (0: the final return).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CycleMove {
    pub pass: usize,
    pub kind: Move,
}

/// A cycle as passes and as the moves that cut them, in order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Expansion {
    pub passes: Vec<CyclePass>,
    pub moves: Vec<CycleMove>,
}

/// Lowers a thread cycle to passes: the one implementation used by every emitter,
/// `explain`, `plot` and the simulator.
///
/// For cumulative depth c (external; internal mirrors X) the pass's line lies 2c inside the
/// crest line, from Z = start + c·infeed towards the end to the end Z (or, when the infeed
/// moves the end too, (depth − c)·infeed short of it). The tool comes in with a rapid (for
/// [`Retract::AboveCut`] first to the retract height over the pass start), cuts the pass with
/// its entry and runout, and leaves: out to the retract diameter and back along Z to the
/// start ([`Retract::AboveCrest`]), or out to the retract height at the pass end
/// ([`Retract::AboveCut`]). Spring passes repeat the full depth. At the end the tool
/// returns to the start point, or goes to the [`Finish::EndAt`] diameter at the end Z.
pub fn expand(cycle: &ThreadCycle) -> Result<Expansion, ExpandError> {
    let (shape, depths) = CycleShape::of(cycle)?;
    let (ax, az) = (shape.ax, shape.az);
    let mut passes = Vec::with_capacity(depths.len());
    let mut moves = Vec::with_capacity(4 * depths.len() + 1);
    let mut previous = Length::ZERO;
    for (i, &c) in depths.iter().enumerate() {
        let number = i + 1;
        let (pass, way) = shape.pass(number, c, previous)?;
        passes.push(pass);
        previous = c;
        let kinds = (way.approach.into_iter())
            .chain([Move::Pass(pass.pass)])
            .chain(way.leave);
        moves.extend(kinds.map(|kind| CycleMove { pass: number, kind }));
    }
    let last = moves
        .iter()
        .fold(Pos::new(ax, az), |p, m| m.kind.end_position(p));
    if let Some(to) = shape.home_from(last) {
        moves.push(CycleMove {
            pass: 0,
            kind: Move::Rapid(to),
        });
    }
    Ok(Expansion { passes, moves })
}

/// Whether a cycle can be cut: what [`expand`] refuses, without working out its moves (a
/// reader refuses such a cycle where it is written, and hands the cycle on).
pub fn check(cycle: &ThreadCycle) -> Result<(), ExpandError> {
    let (shape, depths) = CycleShape::of(cycle)?;
    for (i, &c) in depths.iter().enumerate() {
        shape.travel(i + 1, c)?;
    }
    Ok(())
}

/// What [`expand`] works out once for every pass of a cycle.
struct CycleShape<'c> {
    cycle: &'c ThreadCycle,
    /// The start point.
    ax: Length,
    az: Length,
    /// The sign of Z from the start towards the end.
    towards_end: i64,
    /// +1 for an external thread (the tool comes from larger diameters), −1 internal.
    outward: i64,
    /// The Z travel the entry and the runout take.
    needed: Length,
}

/// How the tool comes to a pass and leaves it.
struct PassWay {
    /// The diameter the tool retracts to.
    retract_x: Length,
    approach: Vec<Move>,
    leave: Vec<Move>,
}

impl<'c> CycleShape<'c> {
    /// The shape of `cycle` and each pass's cumulative depth (spring passes included), or
    /// why the cycle cannot be cut before any pass is worked out.
    fn of(cycle: &'c ThreadCycle) -> Result<(CycleShape<'c>, Vec<Length>), ExpandError> {
        if cycle.lead.0 <= 0 {
            return Err(ExpandError::Lead);
        }
        let (ax, az) = cycle.start;
        if cycle.end_z == az {
            return Err(ExpandError::NoTravel);
        }
        let mut depths = pass_depths(cycle.schedule, cycle.depth, cycle.first_depth)?;
        if depths.len() + cycle.spring_passes as usize > MAX_PASSES {
            return Err(ExpandError::TooManyPasses);
        }
        depths.extend((0..cycle.spring_passes).map(|_| cycle.depth));
        let shape = CycleShape {
            cycle,
            ax,
            az,
            towards_end: (cycle.end_z - az).signum(),
            // Outward: +1 for an external thread (the tool comes from larger diameters).
            outward: if cycle.internal { -1 } else { 1 },
            needed: cycle.entry.map_or(Length::ZERO, |e| e.length)
                + cycle.runout.map_or(Length::ZERO, |r| r.length),
        };
        Ok((shape, depths))
    }

    /// The Z of pass `number` at cumulative depth `c`, its end Z, and its Z travel, which
    /// must hold the entry and the runout.
    fn travel(&self, number: usize, c: Length) -> Result<(Length, Length), ExpandError> {
        let cycle = self.cycle;
        let z = self.az + Length(self.towards_end * cycle.infeed.of(c).0);
        let end_z = if cycle.infeed_moves_end {
            cycle.end_z - Length(self.towards_end * cycle.infeed.of(cycle.depth - c).0)
        } else {
            cycle.end_z
        };
        let travel = Length(self.towards_end * (end_z - z).0);
        if travel.0 <= self.needed.0 {
            return Err(ExpandError::ShortPass {
                pass: number,
                travel,
            });
        }
        Ok((z, end_z))
    }

    /// A radial length (per side) as a diameter change outwards.
    fn out(&self, l: Length) -> Length {
        Length(self.outward * l.0)
    }

    /// The crest diameter at `z`, along the taper.
    fn crest_at(&self, z: Length) -> Length {
        let cycle = self.cycle;
        cycle.crest
            + cycle
                .taper
                .mul_div((z - self.az).0, (cycle.end_z - self.az).0)
    }

    /// The retract diameter `clearance` outside the crest (the start X when that is
    /// further out).
    fn clearance_x(&self, clearance: Length) -> Length {
        let (crest_start, crest_end) = (self.cycle.crest, self.cycle.crest + self.cycle.taper);
        let x = if self.outward > 0 {
            crest_start.max(crest_end)
        } else {
            crest_start.min(crest_end)
        } + self.out(clearance + clearance);
        if (self.ax - x).signum() == self.outward {
            self.ax
        } else {
            x
        }
    }

    /// An entry's or runout's rise at cumulative depth `c`, as a diameter change.
    fn rise(&self, r: Rise, c: Length) -> Length {
        match r {
            Rise::ToCrest => self.out(c + c),
            Rise::ThreadDepth => self.out(self.cycle.depth + self.cycle.depth),
        }
    }

    /// Pass `number` at cumulative depth `c` (`previous`: the depth before it), and how
    /// the tool comes to it and leaves it.
    fn pass(
        &self,
        number: usize,
        c: Length,
        previous: Length,
    ) -> Result<(CyclePass, PassWay), ExpandError> {
        let cycle = self.cycle;
        let sink = self.out(-(c + c));
        let (z, end_z) = self.travel(number, c)?;
        let line_start = Pos::new(self.crest_at(z) + sink, z);
        let line_end = Pos::new(self.crest_at(end_z) + sink, end_z);
        let entry = cycle.entry.map(|e| Chamfer {
            length: e.length,
            offset: self.rise(e.rise, c),
        });
        let start = Pos::new(
            line_start.x.unwrap_or_default() + entry.map_or(Length::ZERO, |e| e.offset),
            z,
        );
        let infeed = self.sync_infeed(entry, start);
        let pass = ThreadPass {
            to: line_end,
            lead: cycle.lead,
            start: SyncStart::Index(cycle.start_angle),
            infeed,
            entry,
            exit: cycle.runout.map(|r| Chamfer {
                length: r.length,
                offset: self.rise(r.rise, c),
            }),
        };
        let way = self.way(line_start, line_end, start, infeed.is_some());
        let pass = CyclePass {
            number,
            depth: c,
            cut: c - previous,
            start,
            pass,
            retract_x: way.retract_x,
        };
        Ok((pass, way))
    }

    /// LinuxCNC's G76 feeds in along X, synchronised, to the entry's start at the entry's
    /// advance along its path: lead·√(E² + rise²)/E.
    fn sync_infeed(&self, entry: Option<Chamfer>, start: Pos) -> Option<SyncInfeed> {
        let cycle = self.cycle;
        match entry {
            Some(e) if cycle.entry_infeed && e.length.0 > 0 => {
                let (len, rise) = (e.length.to_mm_f64(), e.offset.abs().to_mm_f64() / 2.0);
                Lead::from_mm_f64(cycle.lead.to_mm_f64() * len.hypot(rise) / len).map(|advance| {
                    SyncInfeed {
                        x: start.x.unwrap_or_default(),
                        advance,
                    }
                })
            }
            _ => None,
        }
    }

    /// The rapids to a pass whose line runs from `line_start` to `line_end` and whose
    /// move starts at `start` (`infeed`: it feeds in synchronised), and away from it.
    fn way(&self, line_start: Pos, line_end: Pos, start: Pos, infeed: bool) -> PassWay {
        let rapid = Move::Rapid;
        let x_only = |x: Length| Pos {
            x: Some(x),
            z: None,
        };
        match self.cycle.retract {
            Retract::AboveCrest(clearance) => {
                let x = self.clearance_x(clearance);
                PassWay {
                    retract_x: x,
                    approach: vec![rapid(start)],
                    leave: vec![
                        rapid(x_only(x)),
                        rapid(Pos {
                            x: None,
                            z: Some(self.az),
                        }),
                    ],
                }
            }
            Retract::AboveCut(height) => {
                let lift = self.out(height + height);
                let back = Pos {
                    x: Some(line_start.x.unwrap_or_default() + lift),
                    z: start.z,
                };
                let x = line_end.x.unwrap_or_default() + lift;
                let approach = if back == start || infeed {
                    vec![rapid(back)]
                } else {
                    vec![rapid(back), rapid(start)]
                };
                PassWay {
                    retract_x: x,
                    approach,
                    leave: vec![rapid(x_only(x))],
                }
            }
        }
    }

    /// The rapid from `last` to where the cycle ends (the start point, or the
    /// [`Finish::EndAt`] diameter at the end Z), in the axes that change; `None` when
    /// the tool is there.
    fn home_from(&self, last: Pos) -> Option<Pos> {
        let home = match self.cycle.finish {
            Finish::Start => Pos::new(self.ax, self.az),
            Finish::EndAt(x) => Pos::new(x, self.cycle.end_z),
        };
        (last != home).then(|| Pos {
            x: (last.x != home.x).then_some(home.x).flatten(),
            z: (last.z != home.z).then_some(home.z).flatten(),
        })
    }
}

/// What a writer writes of an expansion, in order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Step<'e> {
    /// The comment that introduces a pass's moves ([`Expansion::heading`]).
    Heading(String),
    Move(&'e Move),
}

impl Expansion {
    /// The moves, each pass's introduced by its heading.
    pub fn steps(&self) -> impl Iterator<Item = Step<'_>> {
        let mut current = 0;
        self.moves.iter().flat_map(move |m| {
            let heading = (m.pass != current).then(|| {
                current = m.pass;
                Step::Heading(self.heading(m.pass))
            });
            heading.into_iter().chain([Step::Move(&m.kind)])
        })
    }

    /// The comment that introduces the moves of pass `pass` (0: the final return), or `None`
    /// when `pass` has no moves of its own.
    pub fn heading(&self, pass: usize) -> String {
        let n = self.passes.len();
        match pass.checked_sub(1).and_then(|i| self.passes.get(i)) {
            // "pass {number}/{n}: depth {depth mm}, cut {cut mm}", put together without the
            // formatter (a heading a pass).
            Some(p) => {
                let mut text = String::with_capacity(48);
                text.push_str("pass ");
                crate::fixed::push_whole(&mut text, p.number as u64);
                text.push('/');
                crate::fixed::push_whole(&mut text, n as u64);
                text.push_str(": depth ");
                p.depth.push_mm(&mut text);
                text.push_str(", cut ");
                p.cut.push_mm(&mut text);
                text
            }
            None => "back to the cycle start".to_string(),
        }
    }

    /// One line that says what the cycle cuts, for the comment before its passes. `diameter`
    /// is the sign for a diameter in the target's comments (`Ø`, or `D` where the control's
    /// character set has no `Ø`).
    pub fn summary(&self, cycle: &ThreadCycle, diameter: &str) -> String {
        use std::fmt::Write as _;
        let mut about = format!(
            "thread cycle: {} {diameter}{} to Z{}, lead {}, depth {} in {} passes, {} schedule",
            if cycle.internal {
                "internal"
            } else {
                "external"
            },
            cycle.crest.mm(),
            cycle.end_z.mm(),
            cycle.lead.mm(),
            cycle.depth.mm(),
            self.passes.len(),
            cycle.schedule.id(),
        );
        if let Schedule::Degression(d) = cycle.schedule {
            let _ = write!(about, " R{}", d.r);
        }
        if cycle.taper != Length::ZERO {
            let _ = write!(about, ", taper {} on diameter", cycle.taper.mm());
        }
        if !cycle.infeed.is_zero() {
            let _ = write!(about, ", infeed {:.3}°", cycle.infeed.degrees());
        }
        if let Some(e) = cycle.entry {
            let _ = write!(about, ", entry {}", e.length.mm());
        }
        if let Some(r) = cycle.runout {
            let _ = write!(about, ", runout {}", r.length.mm());
        }
        if cycle.spring_passes > 0 {
            let n = cycle.spring_passes;
            let _ = write!(about, ", {n} spring pass{}", if n == 1 { "" } else { "es" });
        }
        about
    }
}

/// The seed's G31 M36×1.5 as a cycle: A = Ø36 Z4.5, X3600, Z-4750, F15000, P96, P20, no
/// infeed or runout, 0.5 mm retract. A fixture for tests across the crate.
#[cfg(test)]
pub(crate) fn seed_m36_cycle(schedule: Schedule) -> ThreadCycle {
    ThreadCycle {
        start: (Length::from_steps(360_000), Length::from_steps(45_000)),
        crest: Length::from_steps(360_000),
        end_z: Length::from_steps(-475_000),
        lead: Lead::from_length(Length::from_steps(15_000)),
        depth: Length::from_steps(9_600),
        first_depth: Length::from_steps(2_000),
        taper: Length::ZERO,
        infeed: crate::ir::Slope::ZERO,
        infeed_moves_end: false,
        start_angle: Angle::ZERO,
        entry: None,
        entry_infeed: false,
        runout: None,
        retract: Retract::AboveCrest(Length::from_steps(5_000)),
        spring_passes: 0,
        finish: Finish::Start,
        internal: false,
        schedule,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ir::Chamfer;

    fn mm(v: f64) -> Length {
        Length::from_mm_f64(v)
    }

    fn lead_mm(v: f64) -> Lead {
        Lead::from_mm_f64(v).unwrap()
    }

    fn chamfer(length: f64, angle_deg: f64) -> Chamfer {
        Chamfer {
            length: mm(length),
            offset: mm(2.0 * length * angle_deg.to_radians().tan()),
        }
    }

    #[test]
    fn seed_entry_example_cuts_at_diameter_64() {
        // czech.md: start X71.798, E12., 18° → thread at Ø64 (71.798 − 2·12·tan 18°).
        let pass = ThreadPass {
            to: Pos::new(mm(71.798) - chamfer(12.0, 18.0).offset, mm(3.0)),
            lead: lead_mm(6.0),
            start: SyncStart::default(),
            infeed: None,
            entry: Some(chamfer(12.0, 18.0)),
            exit: None,
        };
        let segs = pass_segments(Pos::new(mm(71.798), mm(-100.0)), &pass).unwrap();
        assert_eq!(segs.len(), 2);
        assert_eq!(segs[0].from, Pos::new(mm(71.798), mm(-100.0)));
        let (x, z) = segs[0].to.known().unwrap();
        // 71.798 − 7.798073 = 63.999927, rounded once onto the 0.0001 grid.
        assert_eq!(x, mm(63.9999));
        assert_eq!(z, mm(-88.0));
        assert_eq!(segs[1].to, Pos::new(x, mm(3.0)));
    }

    #[test]
    fn runout_leaves_the_thread_over_the_last_j() {
        // Seed example 4: Z5 → Z-100 at Ø64, J12, 20° → ends at Ø64 + 2·12·tan 20°.
        let pass = ThreadPass {
            to: Pos::new(mm(64.0), mm(-100.0)),
            lead: lead_mm(6.0),
            start: SyncStart::default(),
            infeed: None,
            entry: None,
            exit: Some(chamfer(12.0, 20.0)),
        };
        let segs = pass_segments(Pos::new(mm(64.0), mm(5.0)), &pass).unwrap();
        assert_eq!(segs.len(), 2);
        assert_eq!(segs[0].to, Pos::new(mm(64.0), mm(-88.0)));
        assert_eq!(segs[1].to, Pos::new(mm(72.7353), mm(-100.0)));
    }

    #[test]
    fn taper_runout_follows_the_taper_line() {
        // Ø20 at Z0 to Ø30 at Z-100, runout 10 with no offset: the knee lies on the line.
        let pass = ThreadPass {
            to: Pos::new(mm(30.0), mm(-100.0)),
            lead: lead_mm(2.0),
            start: SyncStart::default(),
            infeed: None,
            entry: Some(Chamfer {
                length: mm(20.0),
                offset: mm(1.0),
            }),
            exit: Some(Chamfer {
                length: mm(10.0),
                offset: Length::ZERO,
            }),
        };
        // The line starts at Ø20 (start Ø21 minus the entry offset).
        let segs = pass_segments(Pos::new(mm(21.0), mm(0.0)), &pass).unwrap();
        let knees: Vec<_> = segs.iter().map(|s| s.to).collect();
        assert_eq!(
            knees,
            vec![
                Pos::new(mm(22.0), mm(-20.0)),
                Pos::new(mm(29.0), mm(-90.0)),
                Pos::new(mm(30.0), mm(-100.0)),
            ]
        );
    }

    #[test]
    fn seed_taper_lead_along_path() {
        // iso.md: Ø226 → Ø246, Z3 → Z-100, F1.5: K = 1.5·√(103² + 10²)/103 = 1.50705289.
        let seg = SyncSegment {
            from: Pos::new(mm(226.0), mm(3.0)),
            to: Pos::new(mm(246.0), mm(-100.0)),
            lead: lead_mm(1.5),
        };
        assert!(
            (seg.lead_along_path() - 1.507_052_89).abs() < 1e-8,
            "{}",
            seg.lead_along_path()
        );
    }

    #[test]
    fn start_angle_moves_the_start_back_along_the_pass() {
        // I180, lead 1.5, travelling towards -Z from Z3: start 0.75 earlier, at Z3.75.
        let mut segs = vec![SyncSegment {
            from: Pos::new(mm(26.618), mm(3.0)),
            to: Pos::new(mm(26.618), mm(-9.0)),
            lead: lead_mm(1.5),
        }];
        let start = start_angle_as_shift(&mut segs, Angle::from_deg(180)).unwrap();
        assert_eq!(start, Some((Pos::new(mm(26.618), mm(3.75)), mm(0.75))));
        // On a taper, X moves back along the line too.
        let mut taper = vec![SyncSegment {
            from: Pos::new(mm(20.0), mm(0.0)),
            to: Pos::new(mm(30.0), mm(-100.0)),
            lead: lead_mm(4.0),
        }];
        let start = start_angle_as_shift(&mut taper, Angle::from_deg(90)).unwrap();
        assert_eq!(start, Some((Pos::new(mm(19.9), mm(1.0)), mm(1.0))));
        // 359.999° at lead 2.5 shifts 2.499993 mm, a whole lead on the grid: no shift (the
        // phase is off by 0.001°), never a start a whole lead early.
        let mut nearly = vec![SyncSegment {
            from: Pos::new(mm(9.3), mm(10.0)),
            to: Pos::new(mm(9.3), mm(-8.047)),
            lead: lead_mm(2.5),
        }];
        assert_eq!(
            start_angle_as_shift(&mut nearly, Angle(359_999)).unwrap(),
            None
        );
        // Without a start Z there is nothing to shift from.
        let mut unknown = vec![SyncSegment {
            from: Pos::UNKNOWN,
            to: Pos {
                x: None,
                z: Some(mm(200.0)),
            },
            lead: lead_mm(1.5),
        }];
        assert_eq!(
            start_angle_as_shift(&mut unknown, Angle::from_deg(180)),
            Err(LowerError::UnknownStart)
        );
    }

    fn m36(schedule: Schedule) -> ThreadCycle {
        seed_m36_cycle(schedule)
    }

    fn lengths(v: &[f64]) -> Vec<Length> {
        v.iter().map(|&x| mm(x)).collect()
    }

    #[test]
    fn halving_schedule_of_the_seed_m36() {
        // nc31.md: 0.2, 0.2, 0.2, 0.1725, 0.1, 0.05, 0.025, 0.0125.
        let depths = pass_depths(Schedule::Halving, mm(0.96), mm(0.2)).unwrap();
        assert_eq!(
            depths,
            lengths(&[0.2, 0.4, 0.6, 0.7725, 0.8725, 0.9225, 0.9475, 0.96])
        );
        // Internal remainder case: P1 0.5, P2 0.2: f sums to 0.1875, one full pass, 0.1125.
        let depths = pass_depths(Schedule::Halving, mm(0.5), mm(0.2)).unwrap();
        assert_eq!(depths, lengths(&[0.2, 0.3125, 0.4125, 0.4625, 0.4875, 0.5]));
        // No remainder: P1 = P2 + f exactly (0.2 + 0.1875).
        let depths = pass_depths(Schedule::Halving, mm(0.3875), mm(0.2)).unwrap();
        assert_eq!(depths, lengths(&[0.2, 0.3, 0.35, 0.375, 0.3875]));
    }

    #[test]
    fn other_schedules() {
        let depths = pass_depths(Schedule::ConstantDepth, mm(0.96), mm(0.2)).unwrap();
        assert_eq!(depths, lengths(&[0.2, 0.4, 0.6, 0.8, 0.96]));
        // 0.2·√n: 0.2, 0.28284, 0.34641, 0.4, 0.44721, …; n = 23 gives 0.95917 < 0.96, n = 24
        // would pass it, so pass 24 goes to 0.96.
        let depths = pass_depths(Schedule::ConstantArea, mm(0.96), mm(0.2)).unwrap();
        assert_eq!(depths.len(), 24);
        assert_eq!(
            &depths[..5],
            &lengths(&[0.2, 0.2828, 0.3464, 0.4, 0.4472])[..]
        );
        assert_eq!(depths[22], mm(0.9592));
        assert_eq!(depths[23], mm(0.96));
    }

    #[test]
    fn heidenhain_g31_schedules() {
        // 3·√(n/4): 1.5, 2.12132, 2.59808, 3.
        let depths = pass_depths(Schedule::AreaInPasses(4), mm(3.0), Length::ZERO).unwrap();
        assert_eq!(depths, lengths(&[1.5, 2.1213, 2.5981, 3.0]));
        // 1·n/3.
        let depths = pass_depths(Schedule::DepthInPasses(3), mm(1.0), Length::ZERO).unwrap();
        assert_eq!(depths, lengths(&[0.3333, 0.6667, 1.0]));
        // 1.0 = 3·0.3 + 0.1: 0.1 first, two cuts of 0.3, then 0.3 as 0.15, 0.075, 0.0375, 0.0375.
        let depths = pass_depths(Schedule::RemainderFirst, mm(1.0), mm(0.3)).unwrap();
        assert_eq!(depths, lengths(&[0.1, 0.4, 0.7, 0.85, 0.925, 0.9625, 1.0]));
        // No remainder: 0.3, 0.6, then the split.
        let depths = pass_depths(Schedule::RemainderFirst, mm(0.9), mm(0.3)).unwrap();
        assert_eq!(depths, lengths(&[0.3, 0.6, 0.75, 0.825, 0.8625, 0.9]));
        // Odd steps: 0.0007 splits 3, 1, 0, 3 (the zero cut left out).
        let depths = pass_depths(Schedule::RemainderFirst, mm(0.0007), mm(0.0007)).unwrap();
        assert_eq!(depths, lengths(&[0.0003, 0.0004, 0.0007]));
        assert!(matches!(
            pass_depths(Schedule::RemainderFirst, mm(0.2), mm(0.3)),
            Err(ExpandError::DepthTooSmall { .. })
        ));
        assert!(matches!(
            pass_depths(Schedule::AreaInPasses(5), mm(0.0004), Length::ZERO),
            Err(ExpandError::DepthTooSmall { .. })
        ));
        // Ten area passes need 20 steps: 0.001 mm would repeat a depth (8, 8 steps).
        assert!(matches!(
            pass_depths(Schedule::AreaInPasses(10), mm(0.001), Length::ZERO),
            Err(ExpandError::DepthTooSmall { .. })
        ));
        let depths = pass_depths(Schedule::AreaInPasses(10), mm(0.002), Length::ZERO).unwrap();
        assert!(depths.windows(2).all(|w| w[0] < w[1]), "{depths:?}");
        assert!(matches!(
            pass_depths(Schedule::DepthInPasses(1001), mm(1.0), Length::ZERO),
            Err(ExpandError::TooManyPasses)
        ));
        assert!(matches!(
            pass_depths(Schedule::DepthInPasses(0), mm(1.0), Length::ZERO),
            Err(ExpandError::DepthTooSmall { .. })
        ));
    }

    #[test]
    fn impossible_depths_are_refused() {
        assert_eq!(
            pass_depths(Schedule::Halving, mm(0.3), mm(0.2)),
            Err(ExpandError::DepthTooSmall {
                minimum: mm(0.3875)
            })
        );
        assert_eq!(
            pass_depths(Schedule::Halving, mm(0.3), Length::ZERO),
            Err(ExpandError::FirstDepth)
        );
        assert_eq!(
            pass_depths(Schedule::ConstantDepth, mm(0.1), mm(0.2)),
            Err(ExpandError::DepthTooSmall { minimum: mm(0.2) })
        );
        assert_eq!(
            pass_depths(Schedule::ConstantDepth, mm(100.0), Length::from_steps(1)),
            Err(ExpandError::TooManyPasses)
        );
        assert_eq!(
            pass_depths(Schedule::ConstantArea, mm(10.0), mm(0.1)),
            Err(ExpandError::TooManyPasses)
        );
        assert_eq!(
            pass_depths(Schedule::Halving, mm(1000.0), mm(0.01)),
            Err(ExpandError::TooManyPasses)
        );
        let mut c = m36(Schedule::Halving);
        c.end_z = c.start.1;
        assert_eq!(expand(&c), Err(ExpandError::NoTravel));
        c = m36(Schedule::Halving);
        c.lead = Lead::ZERO;
        assert_eq!(expand(&c), Err(ExpandError::Lead));
        c = m36(Schedule::Halving);
        c.runout = Some(crate::ir::CycleChamfer {
            length: mm(52.0),
            rise: Rise::ToCrest,
        });
        assert_eq!(
            expand(&c),
            Err(ExpandError::ShortPass {
                pass: 1,
                travel: mm(52.0)
            })
        );
    }

    #[test]
    fn a_check_answers_as_the_expansion_does() {
        let mut cycles = Vec::new();
        for schedule in [
            Schedule::Halving,
            Schedule::ConstantDepth,
            Schedule::ConstantArea,
        ] {
            let c = m36(schedule);
            cycles.push(c);
            let mut short = c;
            short.runout = Some(crate::ir::CycleChamfer {
                length: mm(52.0),
                rise: Rise::ToCrest,
            });
            cycles.push(short);
            // A runout that only the deeper passes' infeed shift leaves no room for.
            let mut late = c;
            late.infeed = crate::ir::Slope { rise: 1, run: 1 };
            late.runout = Some(crate::ir::CycleChamfer {
                length: mm(50.8),
                rise: Rise::ToCrest,
            });
            cycles.push(late);
            let mut none = c;
            none.end_z = none.start.1;
            cycles.push(none);
            let mut lead = c;
            lead.lead = Lead::ZERO;
            cycles.push(lead);
            let mut deep = c;
            deep.depth = mm(1000.0);
            cycles.push(deep);
        }
        let mut refused = 0;
        for c in &cycles {
            let expanded = expand(c).map(|_| ());
            refused += usize::from(expanded.is_err());
            assert_eq!(check(c), expanded, "{c:?}");
        }
        assert!(
            refused >= 12 && refused < cycles.len(),
            "{refused} of {}",
            cycles.len()
        );
    }

    #[test]
    fn a_pass_heading_says_its_number_depth_and_cut() {
        {
            let e = expand(&m36(Schedule::Halving)).unwrap();
            let n = e.passes.len();
            for (i, p) in e.passes.iter().enumerate() {
                let formatted = format!(
                    "pass {}/{n}: depth {}, cut {}",
                    p.number,
                    p.depth.mm(),
                    p.cut.mm()
                );
                assert_eq!(e.heading(i + 1), formatted);
            }
            assert_eq!(e.heading(0), "back to the cycle start");
            assert_eq!(e.heading(n + 1), "back to the cycle start");
        }
    }

    #[test]
    fn seed_m36_passes_and_moves() {
        let e = expand(&m36(Schedule::Halving)).unwrap();
        let diameters: Vec<_> = e.passes.iter().map(|p| p.start.x.unwrap()).collect();
        assert_eq!(
            diameters,
            lengths(&[35.6, 35.2, 34.8, 34.455, 34.255, 34.155, 34.105, 34.08])
        );
        for p in &e.passes {
            assert_eq!(p.start.z, Some(mm(4.5)));
            assert_eq!(p.pass.to, Pos::new(p.start.x.unwrap(), mm(-47.5)));
            assert_eq!(p.pass.lead, lead_mm(1.5));
            assert_eq!(p.pass.exit, None);
            // Crest 36 + 2·0.5 = 37 is further out than the start Ø36.
            assert_eq!(p.retract_x, mm(37.0));
        }
        assert_eq!(e.passes[3].cut, mm(0.1725));
        // Four moves per pass, then the return to Ø36.
        assert_eq!(e.moves.len(), 8 * 4 + 1);
        let last = e.moves.last().unwrap();
        assert_eq!(last.pass, 0);
        assert_eq!(
            last.kind,
            Move::Rapid(Pos {
                x: Some(mm(36.0)),
                z: None
            })
        );
        assert_eq!(
            e.moves[3].kind,
            Move::Rapid(Pos {
                x: None,
                z: Some(mm(4.5))
            })
        );
    }

    #[test]
    fn a_move_ends_where_its_item_ends() {
        let e = expand(&m36(Schedule::Halving)).unwrap();
        let mut at = Pos {
            x: None,
            z: Some(mm(1.0)),
        };
        for m in &e.moves {
            let next = m.kind.end_position(at);
            assert_eq!(next, m.kind.item_kind().end_position(at));
            at = next;
        }
    }

    #[test]
    fn infeed_p6_2365_shifts_each_start_towards_the_end() {
        // shift = c·2365/4096: c 0.2 → 0.11548 → 0.1155; c 0.7725 → 0.44602 → 0.4460;
        // c 0.96 → 0.55430 → 0.5543. The thread runs towards -Z, so Z = 4.5 - shift.
        let mut c = m36(Schedule::Halving);
        c.infeed = crate::ir::Slope {
            rise: 2365,
            run: 4096,
        };
        let e = expand(&c).unwrap();
        let z: Vec<_> = e.passes.iter().map(|p| p.start.z.unwrap()).collect();
        assert_eq!(z[0], mm(4.3845));
        assert_eq!(z[3], mm(4.054));
        assert_eq!(z[7], mm(3.9457));
        // The depth is unchanged; the tool still returns to Z4.5 between passes.
        assert_eq!(e.passes[7].start.x, Some(mm(34.08)));
        assert_eq!(
            e.moves[3].kind,
            Move::Rapid(Pos {
                x: None,
                z: Some(mm(4.5))
            })
        );
    }

    #[test]
    fn runout_of_one_lead_ends_on_the_crest() {
        // P7 = 10 → 10 · 0.1 · 1.5 = 1.5 mm: pass 1 runs at Ø35.6 to Z-46, then to Ø36 Z-47.5.
        let mut c = m36(Schedule::Halving);
        c.runout = Some(crate::ir::CycleChamfer {
            length: mm(1.5),
            rise: Rise::ToCrest,
        });
        let e = expand(&c).unwrap();
        let p = e.passes[0];
        let segs = pass_segments(p.start, &p.pass).unwrap();
        assert_eq!(segs.len(), 2);
        assert_eq!(segs[0].to, Pos::new(mm(35.6), mm(-46.0)));
        assert_eq!(segs[1].to, Pos::new(mm(36.0), mm(-47.5)));
        let last = e.passes[7];
        let segs = pass_segments(last.start, &last.pass).unwrap();
        assert_eq!(segs[0].to, Pos::new(mm(34.08), mm(-46.0)));
        assert_eq!(segs[1].to, Pos::new(mm(36.0), mm(-47.5)));
    }

    #[test]
    fn internal_thread_cuts_outward_and_retracts_inward() {
        // Bore Ø22 from A = Ø20 Z5 to Z-30; depth 0.5, first 0.2.
        let c = ThreadCycle {
            start: (mm(20.0), mm(5.0)),
            crest: mm(22.0),
            end_z: mm(-30.0),
            depth: mm(0.5),
            internal: true,
            ..m36(Schedule::Halving)
        };
        let e = expand(&c).unwrap();
        let diameters: Vec<_> = e.passes.iter().map(|p| p.start.x.unwrap()).collect();
        assert_eq!(
            diameters,
            lengths(&[22.4, 22.625, 22.825, 22.925, 22.975, 23.0])
        );
        // Crest − 2·0.5 = 21 is not as far in as the start Ø20: retract to Ø20, which is
        // the start, so no final return move.
        assert!(e.passes.iter().all(|p| p.retract_x == mm(20.0)));
        assert_eq!(e.moves.len(), 6 * 4);
    }

    #[test]
    fn taper_passes_follow_the_cone() {
        // The seed's taper fragment from A = Ø25 Z0: X19.24, Z-77.8, F2, P1.08, P0.3, P6.76.
        // Halving: f = 0.15, 0.075, 0.0375, 0.0187 (sum 0.2812); two passes of 0.3, then
        // 0.1988: 0.3, 0.6, 0.7988, 0.9488, 1.0238, 1.0613, 1.08.
        let c = ThreadCycle {
            start: (mm(25.0), Length::ZERO),
            crest: mm(19.24),
            end_z: mm(-77.8),
            lead: lead_mm(2.0),
            depth: mm(1.08),
            first_depth: mm(0.3),
            taper: mm(6.76),
            ..m36(Schedule::Halving)
        };
        let e = expand(&c).unwrap();
        let depths: Vec<_> = e.passes.iter().map(|p| p.depth).collect();
        assert_eq!(
            depths,
            lengths(&[0.3, 0.6, 0.7988, 0.9488, 1.0238, 1.0613, 1.08])
        );
        let p = e.passes[0];
        assert_eq!(p.start, Pos::new(mm(18.64), Length::ZERO));
        assert_eq!(p.pass.to, Pos::new(mm(25.4), mm(-77.8)));
        // Above the larger crest Ø26: Ø27, further out than the start Ø25.
        assert_eq!(p.retract_x, mm(27.0));
        assert_eq!(e.moves.last().unwrap().pass, 0);
    }
}

/// An arc's geometry in the plane of a lathe, as LinuxCNC's `arc_data_r` and `arc_data_ijk`
/// compute it: lengths in mm, X as a radius (Z first, X second, as LinuxCNC's ZX plane).
/// The one implementation every reader and writer of arcs uses.
pub mod arc {
    use crate::fixed::Length;
    use crate::ir::Pos;

    /// (Z, X radius) in mm.
    fn plane(p: (Length, Length)) -> (f64, f64) {
        (p.1.to_mm_f64(), p.0.to_mm_f64() / 2.0)
    }

    /// The centre of the arc of signed `radius` (mm; negative: more than half a turn) from
    /// `start` to `end` ((X diameter, Z)), turning clockwise (G2) or not, rounded once onto
    /// the grid. A radius short of half the chord by at most `tolerance` makes a
    /// semicircle. `Err(chord)` when the radius is shorter still.
    pub fn centre_from_radius(
        start: (Length, Length),
        end: (Length, Length),
        radius: f64,
        clockwise: bool,
        tolerance: f64,
    ) -> Result<Pos, f64> {
        let mm = |p: (Length, Length)| (p.0.to_mm_f64(), p.1.to_mm_f64());
        centre_from_radius_mm(mm(start), mm(end), radius, clockwise, tolerance)
            .map(|(x, z)| Pos::new(Length::from_mm_f64(x), Length::from_mm_f64(z)))
    }

    /// How far from `centre` (mm) the control places the centre of an arc written with the
    /// radius `radius` (mm, negative beyond half a turn): what a writer checks before it
    /// writes an arc's centre as a rounded R. Infinite when the radius is too short.
    pub fn centre_miss(
        start: (Length, Length),
        end: (Length, Length),
        centre: (Length, Length),
        radius: f64,
        clockwise: bool,
    ) -> f64 {
        centre_from_radius(start, end, radius, clockwise, 0.001)
            .ok()
            .and_then(|c| c.known())
            .map_or(f64::INFINITY, |(x, z)| {
                ((x - centre.0).to_mm_f64() / 2.0).hypot((z - centre.1).to_mm_f64())
            })
    }

    /// [`centre_from_radius`] on exact values in mm ((X diameter, Z)), not rounded.
    pub fn centre_from_radius_mm(
        start: (f64, f64),
        end: (f64, f64),
        radius: f64,
        clockwise: bool,
        tolerance: f64,
    ) -> Result<(f64, f64), f64> {
        let (s, e) = ((start.1, start.0 / 2.0), (end.1, end.0 / 2.0));
        let abs_radius = radius.abs();
        let mid = ((s.0 + e.0) / 2.0, (s.1 + e.1) / 2.0);
        let mut half = (mid.0 - e.0).hypot(mid.1 - e.1);
        if half - abs_radius > tolerance {
            return Err(2.0 * half);
        }
        if abs_radius == 0.0 || half / abs_radius > 1.0 - 1e-12 {
            half = abs_radius;
        }
        let right = clockwise == (radius > 0.0);
        let chord = (e.1 - s.1).atan2(e.0 - s.0);
        let theta = if right {
            chord - std::f64::consts::FRAC_PI_2
        } else {
            chord + std::f64::consts::FRAC_PI_2
        };
        let offset = abs_radius * (half / abs_radius).asin().cos();
        let offset = if offset.is_finite() { offset } else { 0.0 };
        let (cz, cx) = (mid.0 + offset * theta.cos(), mid.1 + offset * theta.sin());
        Ok((2.0 * cx, cz))
    }

    /// The radius at the start and at the end (mm) of the arc around `centre`.
    pub fn radii(
        start: (Length, Length),
        end: (Length, Length),
        centre: (Length, Length),
    ) -> (f64, f64) {
        let mm = |p: (Length, Length)| (p.0.to_mm_f64(), p.1.to_mm_f64());
        radii_mm(mm(start), mm(end), mm(centre))
    }

    /// [`radii`] on exact values in mm ((X diameter, Z)).
    pub fn radii_mm(start: (f64, f64), end: (f64, f64), centre: (f64, f64)) -> (f64, f64) {
        let r = |p: (f64, f64)| ((p.0 - centre.0) / 2.0).hypot(p.1 - centre.1);
        (r(start), r(end))
    }

    /// Whether the arc from `start` to `end` around `centre` turns the given way within one
    /// quadrant of its circle (at most a quarter turn, not across the axes through the
    /// centre; ends on the axes allowed).
    pub fn within_quadrant(
        start: (Length, Length),
        end: (Length, Length),
        centre: (Length, Length),
        clockwise: bool,
    ) -> bool {
        if start == end {
            return false;
        }
        let side = |v: Length, c: Length| (v - c).0.signum();
        let (sz, sx) = (side(start.1, centre.1), side(start.0, centre.0));
        let (ez, ex) = (side(end.1, centre.1), side(end.0, centre.0));
        // The same quadrant: no axis coordinate changes sign.
        if sz * ez < 0 || sx * ex < 0 {
            return false;
        }
        let (s, e, c) = (plane(start), plane(end), plane(centre));
        let cross = (s.0 - c.0) * (e.1 - c.1) - (s.1 - c.1) * (e.0 - c.0);
        if clockwise { cross < 0.0 } else { cross > 0.0 }
    }

    /// The angle the arc turns through, in radians (a full turn when it ends where it
    /// starts).
    pub fn sweep(
        start: (Length, Length),
        end: (Length, Length),
        centre: (Length, Length),
        clockwise: bool,
    ) -> f64 {
        let (s, e, c) = (plane(start), plane(end), plane(centre));
        let a0 = (s.1 - c.1).atan2(s.0 - c.0);
        let a1 = (e.1 - c.1).atan2(e.0 - c.0);
        let turn = std::f64::consts::TAU;
        let sweep = if clockwise { a0 - a1 } else { a1 - a0 }.rem_euclid(turn);
        if start == end || sweep == 0.0 {
            turn
        } else {
            sweep
        }
    }

    /// Whether the arc turns through more than half a turn.
    pub fn over_half_turn(
        start: (Length, Length),
        end: (Length, Length),
        centre: (Length, Length),
        clockwise: bool,
    ) -> bool {
        let (s, e, c) = (plane(start), plane(end), plane(centre));
        // The cross product of centre→start and centre→end: positive when the end lies
        // counter-clockwise of the start (less than half a turn for G3).
        let cross = (s.0 - c.0) * (e.1 - c.1) - (s.1 - c.1) * (e.0 - c.0);
        if start == end {
            return true;
        }
        if clockwise { cross > 0.0 } else { cross < 0.0 }
    }
}

/// The program with every roughing or finishing cycle replaced by its moves (each stamped
/// with the cycle's line, block number and, on the first, its comment): what every writer,
/// the legalisation and the simulator see. A cycle read under a machine model stays whole
/// for its own dialect (`target`), which writes it back as written. Borrowed when there is
/// nothing to replace.
pub fn unroll(
    program: &crate::ir::Program,
    target: Option<crate::ir::DialectId>,
) -> std::borrow::Cow<'_, crate::ir::Program> {
    use crate::ir::Program;
    if !program.items.iter().any(|i| replaced(i, target)) {
        return std::borrow::Cow::Borrowed(program);
    }
    let mut items = Vec::with_capacity(program.items.len());
    for item in &program.items {
        match unrolled(item, target) {
            Some(moves) => items.extend(moves),
            None => items.push(item.clone()),
        }
    }
    std::borrow::Cow::Owned(Program {
        items,
        dialect: program.dialect,
        library: Vec::new(),
        number: program.number,
        name: program.name.clone(),
        inch: program.inch,
    })
}

/// Whether [`unroll`] replaces `item` by its moves.
fn replaced(item: &crate::ir::Item, target: Option<crate::ir::DialectId>) -> bool {
    match &item.kind {
        ItemKind::Roughing(_) => true,
        ItemKind::ModelCycle(cycle) => target != Some(cycle.dialect),
        _ => false,
    }
}

/// What [`unroll`] makes of one item: the moves that replace it, as items at its line, or
/// `None` when it stands as it is.
pub fn unrolled(
    item: &crate::ir::Item,
    target: Option<crate::ir::DialectId>,
) -> Option<impl Iterator<Item = crate::ir::Item> + '_> {
    let moves = item.kind.cycle_moves().filter(|_| replaced(item, target))?;
    Some(moves.iter().enumerate().map(|(n, kind)| crate::ir::Item {
        kind: kind.clone(),
        span: item.span,
        block_number: item.block_number,
        comment: if n == 0 { item.comment.clone() } else { None },
    }))
}

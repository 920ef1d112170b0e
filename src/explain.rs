//! `ncthread explain`: every thread operation of a program with its pass table, and every
//! roughing or finishing cycle with its cuts.
//!
//! The passes come from the one expansion ([`crate::lower::expand`]) and the phases from the
//! simulator ([`crate::sim::pass_phase`]): nothing here computes a schedule or a helix of
//! its own. A thread written as single passes (czech G33 blocks, НЦ-31 G32 frames, LinuxCNC
//! G33 lines) is recognised as one operation: consecutive passes with one lead, spindle
//! direction and cutting direction over overlapping Z, with only rapids, feeds and comments
//! between them.

use crate::fixed::{Angle, Lead, Length};
use crate::ir::{
    ItemKind, Pos, Program, RoughingCycle, RoughingKind, SpindleDirection, SyncStart, ThreadCycle,
    ThreadPass,
};
use crate::lower;
use crate::sim::{self, TURN};

/// What an operation is.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Kind {
    /// A multi-pass cycle kept whole (the НЦ-31's G31, LinuxCNC's G76).
    Cycle,
    /// Single passes that cut one thread.
    Passes,
    /// A rigid tapping cycle.
    Tap,
    /// A roughing (`G71`…) or finishing (`G70`) cycle: its G code as written.
    Roughing(String),
}

impl Kind {
    /// The id in JSON and CSV.
    pub fn id(&self) -> &'static str {
        match self {
            Kind::Cycle => "cycle",
            Kind::Passes => "passes",
            Kind::Tap => "tap",
            Kind::Roughing(code) if code == "G70" => "finishing",
            Kind::Roughing(_) => "roughing",
        }
    }

    fn title(&self) -> String {
        match self {
            Kind::Cycle => "thread cycle".into(),
            Kind::Passes => "thread written as single passes".into(),
            Kind::Tap => "tapping cycle".into(),
            Kind::Roughing(code) if code == "G70" => format!("finishing cycle {code}"),
            Kind::Roughing(code) => format!("roughing cycle {code}"),
        }
    }
}

/// Where an operation's crest diameter comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CrestSource {
    /// The program says it (a cycle's thread diameter).
    Program,
    /// `--crest` gave it.
    Given,
    /// Nobody did: depths are measured from the first pass.
    Unknown,
}

/// The hand of a thread, from the spindle direction and the direction of the cut: M3
/// cutting towards −Z (towards the chuck) cuts a right-hand thread; reversing either one
/// reverses the hand. **[decided]** after common lathe practice (M3 is the spindle's
/// forward direction).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Hand {
    Right,
    Left,
}

impl Hand {
    fn of(direction: Option<SpindleDirection>, towards: i64) -> Option<Hand> {
        let forward = direction? == SpindleDirection::Clockwise;
        match towards {
            0 => None,
            t => Some(if forward == (t < 0) {
                Hand::Right
            } else {
                Hand::Left
            }),
        }
    }

    pub fn id(self) -> &'static str {
        match self {
            Hand::Right => "right",
            Hand::Left => "left",
        }
    }
}

/// One row of a pass table.
#[derive(Clone, Debug, PartialEq)]
pub struct Pass {
    /// 1-based.
    pub number: usize,
    /// Depth of cut of this pass per side (`None` for the first pass of a thread whose crest
    /// is not known).
    pub cut: Option<Length>,
    /// Depth per side below the crest after this pass (`None` when the crest is not known).
    pub cumulative_depth: Option<Length>,
    /// Depth per side below the first pass's line.
    pub below_first: Length,
    /// The chip's cross-section relative to the first pass's (a V form:
    /// (dₙ² − dₙ₋₁²)/d₁²), when the depths are known.
    pub chip_area: Option<f64>,
    /// The thread line's start and end (X a diameter), entry and runout left out.
    pub start: (Length, Length),
    pub end: (Length, Length),
    /// Where along the cut this pass's helix lies relative to the first pass's (mm, within
    /// half a lead): the flank infeed, or another start.
    pub shift: Option<Length>,
    /// The spindle angle after the index pulse at which it starts.
    pub start_angle: Option<Angle>,
    /// A pass at the depth of the pass before (a spring pass).
    pub spring: bool,
}

/// One operation of the program.
#[derive(Clone, Debug, PartialEq)]
pub struct Operation {
    /// 1-based, in program order.
    pub number: usize,
    pub kind: Kind,
    /// The source line and block number of its first item.
    pub line: u32,
    pub block: Option<u32>,
    pub direction: Option<SpindleDirection>,
    /// The direction of the cut along Z: −1, +1 (0: none).
    pub towards: i64,
    pub hand: Option<Hand>,
    pub lead: Option<Lead>,
    /// The distinct start angles (after the index pulse) of its passes.
    pub start_angles: Vec<Angle>,
    /// An internal thread (the tool cuts outward).
    pub internal: bool,
    /// Crest diameter at the start of the thread.
    pub crest: Option<Length>,
    pub crest_source: CrestSource,
    /// The diameter of the deepest pass's line at the start of the thread.
    pub root: Option<Length>,
    /// Thread depth per side (crest to root), when the crest is known.
    pub depth: Option<Length>,
    /// Diameter change along the thread (0: straight).
    pub taper: Length,
    /// The infeed's angle to the radial (degrees), when it can be told.
    pub infeed_angle: Option<f64>,
    /// Entry and runout lengths along Z.
    pub entry: Option<Length>,
    pub runout: Option<Length>,
    pub spring_passes: usize,
    /// The pass schedule of a cycle (`halving`, `degression`…).
    pub schedule: Option<&'static str>,
    pub passes: Vec<Pass>,
    /// For a roughing cycle: the cut increment per pass, and the pass count. For a tap: its
    /// depth along Z.
    pub z_range: Option<(Length, Length)>,
}

/// Options of [`explain`].
#[derive(Clone, Copy, Debug, Default)]
pub struct Options {
    /// The crest diameter of threads written as single passes (a program of passes does not
    /// say it: the nominal diameter, e.g. 36 for M36).
    pub crest: Option<Length>,
}

/// The operations of `program` in order.
pub fn explain(program: &Program, options: &Options) -> Vec<Operation> {
    let mut ops = Vec::new();
    let mut pos = Pos::UNKNOWN;
    let mut direction = None;
    let mut run: Option<Run> = None;
    let items = &program.items;
    for item in items {
        let kind = &item.kind;
        let at = (item.span.line, item.block_number);
        match kind {
            ItemKind::ThreadPass(pass) => {
                if pass.start == SyncStart::Continue
                    && let Some(r) = run.as_mut().and_then(|r| r.chained(pos))
                {
                    r.push(*pass);
                } else {
                    let p = RunPass::new(pos, pass);
                    if !run.as_ref().is_some_and(|r| r.takes(&p, direction)) {
                        flush(&mut run, &mut ops, options);
                        run = Some(Run {
                            at,
                            direction,
                            passes: Vec::new(),
                            retract: 0,
                        });
                    }
                    if let Some(r) = run.as_mut() {
                        r.passes.push(p);
                    }
                }
            }
            // What a thread written as passes holds between its passes.
            ItemKind::Rapid { .. }
            | ItemKind::Feed { .. }
            | ItemKind::Comment(_)
            | ItemKind::FeedRate(_)
            | ItemKind::FeedMode(_)
            | ItemKind::Delimiter
            | ItemKind::ParamAssign { .. } => {
                if let Some(r) = run.as_mut() {
                    r.moved(pos, kind.end_position(pos));
                }
            }
            _ => {
                flush(&mut run, &mut ops, options);
                match kind {
                    ItemKind::ThreadCycle(cycle) => {
                        ops.push(cycle_operation(cycle, at, direction));
                    }
                    ItemKind::TapCycle(tap) => {
                        let towards = pos.z.map_or(0, |z| (tap.end_z - z).signum());
                        ops.push(Operation {
                            z_range: pos.z.map(|z| (z, tap.end_z)),
                            ..blank(Kind::Tap, at, direction, towards, Some(tap.lead))
                        });
                    }
                    ItemKind::Roughing(cycle) => ops.push(roughing_operation(cycle, at, pos)),
                    ItemKind::Spindle {
                        direction: Some(d), ..
                    } => direction = Some(*d),
                    ItemKind::SpindleStop | ItemKind::ProgramEnd(_) => direction = None,
                    _ => {}
                }
            }
        }
        pos = kind.end_position(pos);
    }
    flush(&mut run, &mut ops, options);
    for (n, op) in ops.iter_mut().enumerate() {
        op.number = n + 1;
    }
    ops
}

/// An operation with nothing known yet but its kind and where it is.
fn blank(
    kind: Kind,
    at: (u32, Option<u32>),
    direction: Option<SpindleDirection>,
    towards: i64,
    lead: Option<Lead>,
) -> Operation {
    Operation {
        number: 0,
        kind,
        line: at.0,
        block: at.1,
        direction,
        towards,
        hand: lead.and(Hand::of(direction, towards)),
        lead,
        start_angles: Vec::new(),
        internal: false,
        crest: None,
        crest_source: CrestSource::Unknown,
        root: None,
        depth: None,
        taper: Length::ZERO,
        infeed_angle: None,
        entry: None,
        runout: None,
        spring_passes: 0,
        schedule: None,
        passes: Vec::new(),
        z_range: None,
    }
}

/// One pass of a thread: its first block (which waits for the index pulse) and the blocks
/// that continue it without waiting (a chain: entry, thread, runout as blocks of their own),
/// each with where it starts.
#[derive(Clone, Debug)]
struct RunPass {
    blocks: Vec<(Pos, ThreadPass)>,
    /// Where the chain ends (the last block's end).
    end: Pos,
    phase: Option<Angle>,
}

impl RunPass {
    fn new(from: Pos, pass: &ThreadPass) -> RunPass {
        RunPass {
            blocks: vec![(from, *pass)],
            end: ItemKind::ThreadPass(*pass).end_position(from),
            phase: sim::pass_phase(from, pass),
        }
    }

    /// A block continuing the chain.
    fn push(&mut self, pass: ThreadPass) {
        self.blocks.push((self.end, pass));
        self.end = ItemKind::ThreadPass(pass).end_position(self.end);
    }

    /// The block of the chain that is its thread: the longest along Z.
    fn main(&self) -> usize {
        let travel = |(from, pass): &(Pos, ThreadPass)| match (from.z, pass.to.z) {
            (Some(a), Some(b)) => (b - a).abs().0,
            _ => 0,
        };
        let mut best = 0;
        for (i, b) in self.blocks.iter().enumerate() {
            if travel(b) > travel(&self.blocks[best]) {
                best = i;
            }
        }
        best
    }

    fn thread(&self) -> &ThreadPass {
        &self.blocks[self.main()].1
    }

    /// The thread line's start (after the infeed, before the entry) and its end.
    fn line(&self) -> Option<((Length, Length), (Length, Length))> {
        let (from, pass) = &self.blocks[self.main()];
        let (x, z) = from.known()?;
        let x = pass.infeed.map_or(x, |i| i.x);
        let x = x - pass.entry.map_or(Length::ZERO, |e| e.offset);
        // An axis the pass does not write stays where the line starts.
        let end = (pass.to.x.unwrap_or(x), pass.to.z.unwrap_or(z));
        Some(((x, z), end))
    }

    /// The entry and the runout along Z: the thread block's own, and the blocks of the chain
    /// before and after it.
    fn chamfers(&self) -> (Option<Length>, Option<Length>) {
        let main = self.main();
        let travel = |blocks: &[(Pos, ThreadPass)]| {
            blocks
                .iter()
                .filter_map(|(from, pass)| Some((pass.to.z? - from.z?).abs()))
                .fold(Length::ZERO, |a, b| a + b)
        };
        let sum = |own: Option<Length>, blocks: &[(Pos, ThreadPass)]| {
            let l = own.unwrap_or_default() + travel(blocks);
            (l.0 > 0).then_some(l)
        };
        let pass = &self.blocks[main].1;
        (
            sum(pass.entry.map(|e| e.length), &self.blocks[..main]),
            sum(pass.exit.map(|e| e.length), &self.blocks[main + 1..]),
        )
    }

    fn towards(&self) -> i64 {
        match self.line() {
            Some(((_, a), (_, b))) => (b - a).signum(),
            None => 0,
        }
    }

    /// The line's diameter at `z` (on the line extended).
    fn x_at(&self, z: Length) -> Option<Length> {
        let ((x0, z0), (x1, z1)) = self.line()?;
        Some(if z1 == z0 {
            x0
        } else {
            x0 + (x1 - x0).mul_div((z - z0).0, (z1 - z0).0)
        })
    }
}

/// Consecutive single passes being gathered into one operation.
struct Run {
    at: (u32, Option<u32>),
    direction: Option<SpindleDirection>,
    passes: Vec<RunPass>,
    /// The sign of the first move along X after a pass: +1 out to larger diameters.
    retract: i64,
}

impl Run {
    /// The last pass, when a block continuing a synchronised move at `pos` extends it.
    fn chained(&mut self, pos: Pos) -> Option<&mut Run> {
        (self.passes.last()?.end == pos).then_some(self)
    }

    fn push(&mut self, pass: ThreadPass) {
        if let Some(last) = self.passes.last_mut() {
            last.push(pass);
        }
    }

    /// Whether `p` cuts the same thread: the same lead, spindle and cutting direction, over
    /// Z that overlaps the first pass's.
    fn takes(&self, p: &RunPass, direction: Option<SpindleDirection>) -> bool {
        let Some(first) = self.passes.first() else {
            return false;
        };
        let range = |r: &RunPass| {
            let ((_, a), (_, b)) = r.line()?;
            Some((a.min(b), a.max(b)))
        };
        let overlaps = match (range(first), range(p)) {
            (Some((a0, a1)), Some((b0, b1))) => a0 < b1 && b0 < a1,
            _ => false,
        };
        first.thread().lead == p.thread().lead
            && self.direction == direction
            && first.towards() == p.towards()
            && overlaps
    }

    /// A move between passes: the first one along X after a pass tells where outside is.
    fn moved(&mut self, from: Pos, to: Pos) {
        if self.retract == 0
            && let (Some(a), Some(b)) = (from.x, to.x)
        {
            self.retract = (b - a).signum();
        }
    }
}

fn flush(run: &mut Option<Run>, ops: &mut Vec<Operation>, options: &Options) {
    if let Some(r) = run.take()
        && !r.passes.is_empty()
    {
        ops.push(passes_operation(r, options));
    }
}

/// The depth of each pass below the crest, and the rows.
struct Rows<'a> {
    outward: i64,
    crest: Option<Length>,
    reference_z: Length,
    lead: Lead,
    passes: &'a [RunPass],
}

impl Rows<'_> {
    fn rows(&self) -> Vec<Pass> {
        let below = |p: &RunPass, x0: Length| {
            p.x_at(self.reference_z)
                .map(|x| Length(self.outward * (x0 - x).0).mul_div(1, 2))
        };
        let first_x = self
            .passes
            .first()
            .and_then(|p| p.x_at(self.reference_z))
            .unwrap_or_default();
        let depths: Vec<Option<Length>> = self
            .passes
            .iter()
            .map(|p| self.crest.and_then(|c| below(p, c)))
            .collect();
        let first_depth = depths.first().copied().flatten();
        let first_phase = self.passes.first().and_then(|p| p.phase);
        let mut rows = Vec::with_capacity(self.passes.len());
        // Each start (start angle) is its own groove: a pass's cut is from the pass before
        // of the same start.
        let mut previous: Vec<(Option<Angle>, Option<Length>, Length)> = Vec::new();
        for (i, p) in self.passes.iter().enumerate() {
            let depth = depths[i];
            let below_first = below(p, first_x).unwrap_or_default();
            let angle = p.blocks[0].1.start.angle();
            let before = previous.iter().rev().find(|(a, ..)| *a == angle).copied();
            let prev_depth = match before {
                Some((_, d, _)) => d,
                None => Some(Length::ZERO).filter(|_| self.crest.is_some()),
            };
            let cut = match (depth, prev_depth) {
                (Some(d), Some(prev)) => Some(d - prev),
                _ => before.map(|(_, _, prev)| below_first - prev),
            };
            let chip_area = match (depth, prev_depth, first_depth) {
                (Some(d), Some(prev), Some(d1)) if d1.0 > 0 => {
                    let sq = |l: Length| (l.0 as f64) * (l.0 as f64);
                    Some((sq(d) - sq(prev)) / sq(d1))
                }
                _ => None,
            };
            let shift = match (p.phase, first_phase) {
                (Some(a), Some(b)) => Some(shift_of(b, a, self.lead)),
                _ => None,
            };
            let ((sx, sz), end) = p.line().unwrap_or_default();
            rows.push(Pass {
                number: i + 1,
                cut,
                cumulative_depth: depth,
                below_first,
                chip_area,
                start: (sx, sz),
                end,
                shift,
                start_angle: angle,
                spring: before.is_some_and(|(_, _, prev)| prev == below_first),
            });
            previous.push((angle, depth, below_first));
        }
        rows
    }
}

/// How far along the cut the helix of phase `other` lies from the helix of phase `first`, in
/// (−lead/2, lead/2]: the phase is the spindle angle at Z = 0, and a helix whose angle there
/// is larger is reached later along the cut.
fn shift_of(first: Angle, other: Angle, lead: Lead) -> Length {
    let mut d = (first.0 - other.0).rem_euclid(TURN);
    if d > TURN / 2 {
        d -= TURN;
    }
    lead.length_times(d, TURN)
}

fn passes_operation(run: Run, options: &Options) -> Operation {
    let first = &run.passes[0];
    let towards = first.towards();
    let lead = first.thread().lead;
    let mut op = blank(Kind::Passes, run.at, run.direction, towards, Some(lead));
    let reference_z = first.line().map_or(Length::ZERO, |((_, z), _)| z);
    // Outside is where the passes come from: a deeper pass lies further in.
    let xs: Vec<Length> = run
        .passes
        .iter()
        .filter_map(|p| p.x_at(reference_z))
        .collect();
    let spread = xs.last().copied().unwrap_or_default() - xs.first().copied().unwrap_or_default();
    // A runout or an entry rises out of the thread; else the deeper passes lie further in;
    // else the first move along X after a pass leaves the thread.
    let chamfer = first
        .thread()
        .exit
        .or(first.thread().entry)
        .map_or(0, |c| c.offset.signum());
    let outward = match (chamfer, spread.signum(), run.retract) {
        (0, 0, r) if r < 0 => -1,
        (0, 0, _) => 1,
        (0, s, _) => -s,
        (c, _, _) => c,
    };
    op.internal = outward < 0;
    op.crest = options.crest;
    op.crest_source = if options.crest.is_some() {
        CrestSource::Given
    } else {
        CrestSource::Unknown
    };
    let rows = Rows {
        outward,
        crest: options.crest,
        reference_z,
        lead,
        passes: &run.passes,
    }
    .rows();
    // The deepest pass's diameter.
    op.root = xs
        .iter()
        .copied()
        .reduce(|a, b| if (b - a).signum() == -outward { b } else { a });
    op.depth = match (op.crest, op.root) {
        (Some(c), Some(r)) => Some(Length(outward * (c - r).0).mul_div(1, 2)),
        _ => None,
    };
    if let Some(((x0, _), (x1, _))) = run.passes.last().and_then(|p| p.line()) {
        op.taper = x1 - x0;
    }
    (op.entry, op.runout) = first.chamfers();
    let mut angles: Vec<Angle> = rows.iter().filter_map(|r| r.start_angle).collect();
    angles.sort_by_key(|a| a.0);
    angles.dedup();
    op.start_angles = angles;
    // The infeed angle from the first pass to the deepest, when both shift and depth grow.
    if let Some(last) = rows.last()
        && let Some(shift) = last.shift
        && last.below_first.0 > 0
        && op.start_angles.len() <= 1
    {
        op.infeed_angle = Some(
            (shift.to_mm_f64() / last.below_first.to_mm_f64())
                .atan()
                .to_degrees(),
        );
    }
    op.spring_passes = rows.iter().filter(|r| r.spring).count();
    op.passes = rows;
    op
}

fn cycle_operation(
    cycle: &ThreadCycle,
    at: (u32, Option<u32>),
    direction: Option<SpindleDirection>,
) -> Operation {
    let towards = (cycle.end_z - cycle.start.1).signum();
    let mut op = blank(Kind::Cycle, at, direction, towards, Some(cycle.lead));
    let outward = if cycle.internal { -1 } else { 1 };
    op.internal = cycle.internal;
    op.crest = Some(cycle.crest);
    op.crest_source = CrestSource::Program;
    op.depth = Some(cycle.depth);
    op.root = Some(cycle.crest - Length(outward * 2 * cycle.depth.0));
    op.taper = cycle.taper;
    op.infeed_angle = Some(cycle.infeed.degrees());
    op.entry = cycle.entry.map(|e| e.length);
    op.runout = cycle.runout.map(|e| e.length);
    op.spring_passes = cycle.spring_passes as usize;
    op.schedule = Some(cycle.schedule.id());
    op.start_angles = vec![cycle.start_angle];
    let Ok(expansion) = lower::expand(cycle) else {
        return op;
    };
    // Each pass from where the expansion's moves leave the tool.
    let mut pos = Pos::new(cycle.start.0, cycle.start.1);
    let mut passes = Vec::with_capacity(expansion.passes.len());
    for m in &expansion.moves {
        if let lower::Move::Pass(p) = &m.kind {
            passes.push(RunPass::new(pos, p));
        }
        pos = m.kind.end_position(pos);
    }
    let mut rows = Rows {
        outward,
        crest: Some(cycle.crest),
        reference_z: cycle.start.1,
        lead: cycle.lead,
        passes: &passes,
    }
    .rows();
    // The expansion's depths are the cycle's own (the line of a taper thread is measured
    // at each pass's start, where the cycle places it).
    for (row, p) in rows.iter_mut().zip(&expansion.passes) {
        row.cumulative_depth = Some(p.depth);
        row.cut = Some(p.cut);
        row.spring = row.number > expansion.passes.len() - cycle.spring_passes as usize;
    }
    let first = rows.first().and_then(|r| r.cumulative_depth);
    let mut previous = Length::ZERO;
    for row in &mut rows {
        let d = row.cumulative_depth.unwrap_or_default();
        row.chip_area = first.filter(|f| f.0 > 0).map(|f| {
            let sq = |l: Length| (l.0 as f64) * (l.0 as f64);
            (sq(d) - sq(previous)) / sq(f)
        });
        previous = d;
    }
    op.passes = rows;
    op
}

fn roughing_operation(cycle: &RoughingCycle, at: (u32, Option<u32>), from: Pos) -> Operation {
    let code = match cycle.code {
        c if c % 10 == 0 => format!("G{}", c / 10),
        c => format!("G{}.{}", c / 10, c % 10),
    };
    let facing = matches!(cycle.kind, RoughingKind::Rough { facing: true, .. });
    let mut op = blank(Kind::Roughing(code), at, None, 0, None);
    // A cut: the feeds and arcs between two rapids.
    let mut pos = from;
    let mut rows: Vec<Pass> = Vec::new();
    let mut cutting = false;
    for m in &cycle.moves {
        let next = m.end_position(pos);
        match m {
            ItemKind::Rapid { .. } => cutting = false,
            _ => {
                if !cutting {
                    let start = pos.known().unwrap_or_default();
                    rows.push(Pass {
                        number: rows.len() + 1,
                        cut: None,
                        cumulative_depth: None,
                        below_first: Length::ZERO,
                        chip_area: None,
                        start,
                        end: start,
                        shift: None,
                        start_angle: None,
                        spring: false,
                    });
                    cutting = true;
                }
                if let Some(row) = rows.last_mut() {
                    row.end = next.known().unwrap_or_default();
                }
            }
        }
        pos = next;
    }
    // The step of each roughing cut from the one before, per side (along Z for facing).
    // (A pocket's cuts, G71.2/G72.2, start where each pocket does: no step.)
    if let RoughingKind::Rough { variant: 0 | 1, .. } = cycle.kind {
        for i in 1..rows.len() {
            let (a, b) = (rows[i - 1].start, rows[i].start);
            rows[i].cut = Some(if facing {
                (b.1 - a.1).abs()
            } else {
                (b.0 - a.0).abs().mul_div(1, 2)
            });
        }
    }
    op.passes = rows;
    op
}

// ---------------------------------------------------------------------------------------
// Output

/// How the text table is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Table {
    /// UTF-8 box drawing.
    Box,
    /// ASCII only.
    Plain,
}

fn diameter(l: Length) -> String {
    format!("Ø{}", l.mm())
}

fn hand_text(op: &Operation) -> String {
    let spindle = match op.direction {
        Some(SpindleDirection::Clockwise) => "M3",
        Some(SpindleDirection::CounterClockwise) => "M4",
        None => "spindle not turning",
    };
    let towards = match op.towards {
        t if t < 0 => "cut towards −Z",
        t if t > 0 => "cut towards +Z",
        _ => "no travel along Z",
    };
    match op.hand {
        Some(h) => format!("{}-hand ({spindle}, {towards})", h.id()),
        None => format!("hand unknown ({spindle}, {towards})"),
    }
}

/// The text form: for each operation a heading, its facts, and its pass table.
pub fn to_text(ops: &[Operation], table: Table) -> String {
    use std::fmt::Write as _;
    let mut out = String::new();
    if ops.is_empty() {
        out.push_str("no thread operation and no roughing cycle in the program\n");
    }
    for op in ops {
        if op.number > 1 {
            out.push('\n');
        }
        let block = op.block.map_or(String::new(), |n| format!(", N{n}"));
        let _ = writeln!(
            out,
            "operation {}: {} (line {}{block})",
            op.number,
            op.kind.title(),
            op.line
        );
        for fact in facts(op) {
            let _ = writeln!(out, "  {fact}");
        }
        if !op.passes.is_empty() {
            out.push_str(&pass_table(op, table));
        }
    }
    out
}

/// The lines under an operation's heading.
fn facts(op: &Operation) -> Vec<String> {
    let mut lines = Vec::new();
    match &op.kind {
        Kind::Roughing(_) => {
            let n = op.passes.len();
            lines.push(format!("{n} cut{}", if n == 1 { "" } else { "s" }));
            return lines;
        }
        Kind::Tap => {
            let mut l = format!("{}, lead {} mm", hand_text(op), lead_text(op));
            if let Some((a, b)) = op.z_range {
                let _ = std::fmt::Write::write_fmt(
                    &mut l,
                    format_args!(", Z{} to Z{}", a.mm(), b.mm()),
                );
            }
            lines.push(l);
            return lines;
        }
        _ => {}
    }
    let starts = op.start_angles.len().max(1);
    let angles = op
        .start_angles
        .iter()
        .map(|a| format!("{a}°"))
        .collect::<Vec<_>>()
        .join(", ");
    lines.push(format!(
        "{}, lead {} mm, {} start{} (start angle{} {})",
        hand_text(op),
        lead_text(op),
        starts,
        if starts == 1 { "" } else { "s" },
        if op.start_angles.len() == 1 { "" } else { "s" },
        if angles.is_empty() {
            "0°".into()
        } else {
            angles
        },
    ));
    let side = if op.internal { "internal" } else { "external" };
    let crest = match (op.crest, op.crest_source) {
        (Some(c), CrestSource::Given) => format!("crest {} (--crest)", diameter(c)),
        (Some(c), _) => format!("crest {}", diameter(c)),
        (None, _) => {
            "crest not in the program (give --crest; depths are counted from pass 1)".into()
        }
    };
    let mut l = format!("{side}, {crest}");
    if let Some(r) = op.root {
        let _ = std::fmt::Write::write_fmt(&mut l, format_args!(", root {}", diameter(r)));
    }
    if let Some(d) = op.depth {
        let _ = std::fmt::Write::write_fmt(&mut l, format_args!(", depth {} mm per side", d.mm()));
    }
    lines.push(l);
    let taper = if op.taper == Length::ZERO {
        "straight".to_string()
    } else {
        format!("taper {} mm on diameter", op.taper.mm())
    };
    let infeed = match op.infeed_angle {
        Some(a) if a.abs() < 0.0005 => "radial infeed".to_string(),
        Some(a) => format!("infeed {a:.3}° to the radial"),
        None => "infeed not told".to_string(),
    };
    let chamfer = |name: &str, l: Option<Length>| match l {
        Some(l) => format!("{name} {} mm", l.mm()),
        None => format!("no {name}"),
    };
    let mut l = format!(
        "{taper}, {infeed}, {}, {}, {} spring pass{}",
        chamfer("entry", op.entry),
        chamfer("runout", op.runout),
        op.spring_passes,
        if op.spring_passes == 1 { "" } else { "es" }
    );
    if let Some(s) = op.schedule {
        let _ = std::fmt::Write::write_fmt(&mut l, format_args!(", {s} schedule"));
    }
    lines.push(l);
    lines
}

fn lead_text(op: &Operation) -> String {
    op.lead.map_or("?".into(), |l| l.mm())
}

/// The pass table as aligned columns.
fn pass_table(op: &Operation, table: Table) -> String {
    let roughing = matches!(op.kind, Kind::Roughing(_));
    let known = op.crest.is_some();
    let mut header: Vec<&str> = vec!["pass"];
    if roughing {
        header.extend(["step", "X start", "Z start", "X end", "Z end"]);
    } else {
        header.extend([
            "cut",
            if known { "depth" } else { "below pass 1" },
            "chip area",
            "shift",
            "X start",
            "Z start",
            "X end",
            "Z end",
        ]);
    }
    let opt = |l: Option<Length>| l.map_or("—".to_string(), |l| l.mm_fixed());
    let rows: Vec<Vec<String>> = op
        .passes
        .iter()
        .map(|p| {
            let mut r = vec![format!("{}{}", p.number, if p.spring { "s" } else { "" })];
            if roughing {
                r.push(opt(p.cut));
            } else {
                r.push(opt(p.cut));
                r.push(if known {
                    opt(p.cumulative_depth)
                } else {
                    p.below_first.mm_fixed()
                });
                r.push(p.chip_area.map_or("—".into(), |a| format!("{a:.2}")));
                r.push(opt(p.shift));
            }
            r.extend([
                p.start.0.mm_fixed(),
                p.start.1.mm_fixed(),
                p.end.0.mm_fixed(),
                p.end.1.mm_fixed(),
            ]);
            r
        })
        .collect();
    let widths: Vec<usize> = (0..header.len())
        .map(|c| {
            rows.iter()
                .map(|r| r[c].chars().count())
                .chain([header[c].chars().count()])
                .max()
                .unwrap_or(0)
        })
        .collect();
    let (v, h, corners) = match table {
        Table::Box => (
            "│",
            "─",
            [["┌", "┬", "┐"], ["├", "┼", "┤"], ["└", "┴", "┘"]],
        ),
        Table::Plain => (
            "|",
            "-",
            [["+", "+", "+"], ["+", "+", "+"], ["+", "+", "+"]],
        ),
    };
    let rule = |c: [&str; 3]| {
        let inner: Vec<String> = widths.iter().map(|w| h.repeat(w + 2)).collect();
        format!("{}{}{}\n", c[0], inner.join(c[1]), c[2])
    };
    let line = |cells: &[String]| {
        let inner: Vec<String> = cells
            .iter()
            .zip(&widths)
            .map(|(c, w)| format!(" {}{c} ", " ".repeat(w - c.chars().count())))
            .collect();
        format!("{v}{}{v}\n", inner.join(v))
    };
    let mut out = String::new();
    out.push_str(&rule(corners[0]));
    out.push_str(&line(
        &header.iter().map(|s| s.to_string()).collect::<Vec<_>>(),
    ));
    out.push_str(&rule(corners[1]));
    for r in &rows {
        out.push_str(&line(r));
    }
    out.push_str(&rule(corners[2]));
    out
}

fn mm(l: Length) -> serde_json::Value {
    serde_json::json!(l.to_mm_f64())
}

fn lead_mm(l: Lead) -> serde_json::Value {
    l.mm()
        .parse::<f64>()
        .map_or(serde_json::Value::Null, |v| serde_json::json!(v))
}

/// The JSON form: `{ "operations": [ { …, "passes": [ … ] } ] }`, lengths in mm.
pub fn to_json(ops: &[Operation]) -> serde_json::Value {
    let operations: Vec<serde_json::Value> = ops
        .iter()
        .map(|op| {
            let passes: Vec<serde_json::Value> = op
                .passes
                .iter()
                .map(|p| {
                    serde_json::json!({
                        "pass": p.number,
                        "cut": p.cut.map(mm),
                        "cumulative_depth": p.cumulative_depth.map(mm),
                        "below_first": mm(p.below_first),
                        "chip_area": p.chip_area.map(|a| (a * 10_000.0).round() / 10_000.0),
                        "shift": p.shift.map(mm),
                        "start_angle": p.start_angle.map(|a| a.to_deg_f64()),
                        "spring": p.spring,
                        "x_start": mm(p.start.0),
                        "z_start": mm(p.start.1),
                        "x_end": mm(p.end.0),
                        "z_end": mm(p.end.1),
                    })
                })
                .collect();
            let code = match &op.kind {
                Kind::Roughing(code) => Some(code.clone()),
                _ => None,
            };
            serde_json::json!({
                "operation": op.number,
                "kind": op.kind.id(),
                "code": code,
                "line": op.line,
                "block": op.block,
                "spindle": match op.direction {
                    Some(SpindleDirection::Clockwise) => Some("M3"),
                    Some(SpindleDirection::CounterClockwise) => Some("M4"),
                    None => None,
                },
                "towards": op.towards,
                "hand": op.hand.map(Hand::id),
                "lead": op.lead.map(lead_mm),
                "starts": if op.lead.is_some() { Some(op.start_angles.len().max(1)) } else { None },
                "start_angles": op.start_angles.iter().map(|a| a.to_deg_f64()).collect::<Vec<_>>(),
                "internal": op.internal,
                "crest": op.crest.map(mm),
                "crest_source": match op.crest_source {
                    CrestSource::Program => "program",
                    CrestSource::Given => "given",
                    CrestSource::Unknown => "unknown",
                },
                "root": op.root.map(mm),
                "depth": op.depth.map(mm),
                "taper": mm(op.taper),
                "infeed_angle": op.infeed_angle.map(|a| (a * 1000.0).round() / 1000.0),
                "entry": op.entry.map(mm),
                "runout": op.runout.map(mm),
                "spring_passes": op.spring_passes,
                "schedule": op.schedule,
                "passes": passes,
            })
        })
        .collect();
    serde_json::json!({ "operations": operations })
}

/// The CSV form: one row per pass, the operation's facts repeated on each.
pub fn to_csv(ops: &[Operation]) -> String {
    let mut out = String::from(
        "operation,kind,line,hand,lead,crest,pass,cut,cumulative_depth,below_first,chip_area,shift,x_start,z_start,x_end,z_end\n",
    );
    let opt = |l: Option<Length>| l.map_or(String::new(), |l| l.mm());
    for op in ops {
        for p in &op.passes {
            out.push_str(&format!(
                "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n",
                op.number,
                op.kind.id(),
                op.line,
                op.hand.map_or("", Hand::id),
                op.lead.map_or(String::new(), |l| l.mm()),
                opt(op.crest),
                p.number,
                opt(p.cut),
                opt(p.cumulative_depth),
                p.below_first.mm(),
                p.chip_area.map_or(String::new(), |a| format!("{a:.4}")),
                opt(p.shift),
                p.start.0.mm(),
                p.start.1.mm(),
                p.end.0.mm(),
                p.end.1.mm(),
            ));
        }
    }
    out
}

//! `ncthread explain`: every thread operation of a program with its pass table, and every
//! roughing or finishing cycle with its cuts.
//!
//! The passes come from the one expansion ([`crate::lower::expand`]) and the phases from the
//! simulator (`sim::angle_at`, the simulator's phase rule): nothing here computes a schedule or a helix of
//! its own. A thread written as single passes (czech G33 blocks, НЦ-31 G32 frames, LinuxCNC
//! G33 lines) is recognised as one operation: consecutive passes with one lead, spindle
//! direction and cutting direction over overlapping Z, with only rapids, feeds and comments
//! between them.

use crate::fixed::{Angle, Lead, Length};
use crate::ir::{
    ItemKind, ModelCycle, Pos, Program, RoughingCycle, RoughingKind, SpindleDirection, SyncStart,
    ThreadCycle, ThreadPass,
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
    /// A roughing cycle (`G71`…): its G code as written.
    Roughing(String),
    /// A finishing cycle (`G70`; `G72` in FANUC's G-code system C): its G code as written.
    Finishing(String),
    /// A FANUC canned cycle (or a move home) kept as written, with no machine model to say
    /// its moves: its block as written.
    Kept(String),
}

impl Kind {
    /// The id in JSON and CSV.
    pub fn id(&self) -> &'static str {
        match self {
            Kind::Cycle => "cycle",
            Kind::Passes => "passes",
            Kind::Tap => "tap",
            Kind::Finishing(_) => "finishing",
            Kind::Roughing(_) => "roughing",
            Kind::Kept(_) => "kept",
        }
    }

    fn title(&self) -> String {
        match self {
            Kind::Cycle => "thread cycle".into(),
            Kind::Passes => "thread written as single passes".into(),
            Kind::Tap => "tapping cycle".into(),
            Kind::Finishing(code) => format!("finishing cycle {code}"),
            Kind::Roughing(code) => format!("roughing cycle {code}"),
            Kind::Kept(block) => format!(
                "`{block}`, kept as written: its moves are the control's, listed only under a machine model"
            ),
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
/// reverses the hand. **\[decided\]** after common lathe practice (M3 is the spindle's
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
    /// The start (groove) it cuts, 1-based: a multi-start thread's passes cut several.
    pub start_number: usize,
    /// Depth of cut of this pass per side, from the pass before on its start (`None` for
    /// the first pass of a start whose crest is not known).
    pub cut: Option<Length>,
    /// Depth per side below the crest after this pass (`None` when the crest is not known).
    pub cumulative_depth: Option<Length>,
    /// Depth per side below the first pass's line.
    pub below_first: Length,
    /// The chip's cross-section relative to the first pass's (a V form:
    /// (dₙ² − dₙ₋₁²)/d₁²), when the depths are known.
    pub chip_area: Option<f64>,
    /// The thread line's start and end (X a diameter): the part of the pass at its full
    /// depth, its entry and runout left out.
    pub start: Pos,
    pub end: Pos,
    /// Where along the cut this pass's helix lies relative to the first pass's (mm, within
    /// half a lead): the flank infeed, or another start.
    pub shift: Option<Length>,
    /// The spindle angle after the index pulse at which it starts, as written.
    pub start_angle: Option<Angle>,
    /// A pass at the depth of the pass before on its start (a spring pass).
    pub spring: bool,
}

/// One move of a roughing or finishing cycle as `lower::g7x` expanded it, for a picture of
/// its cuts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CycleMove {
    pub from: Pos,
    pub to: Pos,
    /// The cut (a pass row's number) it belongs to; `None` for a rapid.
    pub cut: Option<usize>,
    /// An arc's centre (X a diameter) and whether it turns clockwise (G2); `None` for a line.
    pub arc: Option<(Pos, bool)>,
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
    /// The direction of the cut along Z: −1, +1 (0: none, or not known).
    pub towards: i64,
    pub hand: Option<Hand>,
    pub lead: Option<Lead>,
    /// The starts (grooves) it cuts, each by its angle after the index pulse relative to
    /// the first's helix: `[0°, 180°]` for a two-start thread.
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
    /// A tap's travel along Z (from, to).
    pub z_range: Option<(Length, Length)>,
    /// A roughing or finishing cycle's moves, rapids and cuts (empty for other operations).
    pub moves: Vec<CycleMove>,
}

impl Operation {
    /// Whether it is a thread (a cycle or passes) with passes to draw.
    pub fn is_thread(&self) -> bool {
        matches!(self.kind, Kind::Cycle | Kind::Passes) && !self.passes.is_empty()
    }
}

/// The operation `plot` and the HTML report draw when none is named: the first thread, else
/// none.
pub fn default_operation(ops: &[Operation]) -> Option<&Operation> {
    ops.iter().find(|o| o.is_thread())
}

/// Options of [`explain`].
#[derive(Clone, Copy, Debug, Default)]
pub struct Options {
    /// The crest diameter of threads written as single passes, which such a program does
    /// not say: the major diameter of an external thread (36 for M36), the minor (bore)
    /// diameter of an internal one.
    pub crest: Option<Length>,
}

/// The program with each threading cycle under a machine model (G76) replaced by its
/// passes, which `explain` reads as a thread written pass by pass.
fn thread_cycles_as_passes(program: &Program) -> std::borrow::Cow<'_, Program> {
    let threads = |kind: &ItemKind| match kind {
        ItemKind::ModelCycle(c) => c.moves.iter().any(|m| matches!(m, ItemKind::ThreadPass(_))),
        _ => false,
    };
    if !program.items.iter().any(|i| threads(&i.kind)) {
        return std::borrow::Cow::Borrowed(program);
    }
    let mut items = Vec::with_capacity(program.items.len());
    for item in &program.items {
        match &item.kind {
            ItemKind::ModelCycle(c) if threads(&item.kind) => {
                items.extend(c.moves.iter().map(|m| crate::ir::Item {
                    kind: m.clone(),
                    ..item.clone()
                }));
            }
            _ => items.push(item.clone()),
        }
    }
    std::borrow::Cow::Owned(Program {
        items,
        ..program.clone()
    })
}

/// The operations of `program` in order.
pub fn explain(program: &Program, options: &Options) -> Vec<Operation> {
    let program = &*thread_cycles_as_passes(program);
    let mut ops = Vec::new();
    let mut pos = Pos::UNKNOWN;
    let mut direction = None;
    let mut run: Option<Run> = None;
    for item in &program.items {
        let kind = &item.kind;
        let at = (item.span.line, item.block_number);
        match kind {
            // A block that continues the pass before without waiting (a chain).
            ItemKind::ThreadPass(pass)
                if pass.start == SyncStart::Continue
                    && run.as_ref().is_some_and(|r| r.continues_at(pos)) =>
            {
                if let Some(r) = run.as_mut() {
                    r.chain(**pass);
                }
            }
            ItemKind::ThreadPass(pass) => {
                let p = RunPass::new(at, pos, pass);
                match run.as_mut() {
                    Some(r) if r.direction == direction => r.push(p, &mut ops, options),
                    _ => {
                        flush(&mut run, &mut ops, options);
                        run = Some(Run::new(at, direction, p));
                    }
                }
            }
            // What a thread written as passes holds between its passes.
            ItemKind::Rapid { .. }
            | ItemKind::Feed { .. }
            | ItemKind::Arc { .. }
            | ItemKind::Comment(_)
            | ItemKind::FeedRate(_)
            | ItemKind::FeedMode(_)
            | ItemKind::Delimiter
            | ItemKind::ParamAssign { .. }
            | ItemKind::Coolant(_)
            | ItemKind::Dwell { .. }
            | ItemKind::Stop { .. } => {
                if let Some(r) = run.as_mut() {
                    r.moved(pos, kind.end_position(pos));
                }
            }
            // The spindle said again, or its speed changed: the helix is the same.
            ItemKind::Spindle {
                direction: d @ (None | Some(_)),
                ..
            } if d.is_none() || *d == direction => {}
            _ => {
                flush(&mut run, &mut ops, options);
                match kind {
                    ItemKind::ThreadCycle(cycle) => {
                        ops.push(cycle_operation(cycle, at, direction));
                    }
                    ItemKind::TapCycle(tap) => ops.push(tap_operation(tap, at, direction, pos)),
                    ItemKind::Roughing(cycle) => ops.push(roughing_operation(cycle, at, pos)),
                    ItemKind::ModelCycle(cycle) => ops.extend(model_operation(cycle, at, pos)),
                    ItemKind::Opaque { .. } => ops.extend(kept_operation(kind, at, direction)),
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

/// A rigid tapping cycle from `pos`.
fn tap_operation(
    tap: &crate::ir::TapCycle,
    at: (u32, Option<u32>),
    direction: Option<SpindleDirection>,
    pos: Pos,
) -> Operation {
    let towards = pos.z.map_or(0, |z| (tap.end_z - z).signum());
    Operation {
        z_range: pos.z.map(|z| (z, tap.end_z)),
        ..blank(Kind::Tap, at, direction, towards, Some(tap.lead))
    }
}

/// A FANUC cycle kept as written, an operation of its own (not a move home: G28, G30, G53).
fn kept_operation(
    kind: &ItemKind,
    at: (u32, Option<u32>),
    direction: Option<SpindleDirection>,
) -> Option<Operation> {
    let ItemKind::Opaque {
        text,
        block: Some(c),
        ..
    } = kind
    else {
        return None;
    };
    let up = text.to_ascii_uppercase();
    let home = ["G28", "G30", "G53"].iter().any(|g| up.contains(g));
    (c.cycle && c.moves && !home).then(|| blank(Kind::Kept(text.clone()), at, direction, 0, None))
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
        moves: Vec::new(),
    }
}

/// One pass of a thread: its first block (which waits for the index pulse) and the blocks
/// that continue it without waiting (a chain: entry, thread, runout as blocks of their own).
#[derive(Clone, Debug)]
struct RunPass {
    /// Its first block's line and block number.
    at: (u32, Option<u32>),
    from: Pos,
    blocks: Vec<ThreadPass>,
    /// Where the chain ends (the last block's end).
    end: Pos,
    /// Its straight pieces (infeed, entry, thread, runout of every block) as the simulator
    /// moves them, with the helix phase of each piece along Z; made when first asked for
    /// (the chain is complete then).
    moves: std::cell::OnceCell<Vec<(Pos, Pos, Option<Angle>)>>,
}

/// A straight piece of a pass.
type Piece = (Pos, Pos);

impl RunPass {
    fn new(at: (u32, Option<u32>), from: Pos, pass: &ThreadPass) -> RunPass {
        let mut p = RunPass {
            at,
            from,
            blocks: Vec::new(),
            end: from,
            moves: std::cell::OnceCell::new(),
        };
        p.chain(*pass);
        p
    }

    /// A block continuing the chain.
    fn chain(&mut self, pass: ThreadPass) {
        self.end = pass.end_position(self.end);
        self.blocks.push(pass);
        self.moves = std::cell::OnceCell::new();
    }

    fn moves(&self) -> &[(Pos, Pos, Option<Angle>)] {
        self.moves
            .get_or_init(|| sim::chain_moves(self.from, &self.blocks))
    }

    /// The index of the thread line among the pieces: the longest along Z (along X for a
    /// face thread).
    fn main(&self) -> Option<usize> {
        let along = |&(a, b, _): &(Pos, Pos, Option<Angle>), z: bool| {
            let (p, q) = if z { (a.z, b.z) } else { (a.x, b.x) };
            p.zip(q).map_or(0, |(p, q)| (q - p).0.abs())
        };
        let moves = self.moves();
        let axial = moves.iter().any(|p| along(p, true) > 0);
        (0..moves.len()).max_by_key(|&i| (along(&moves[i], axial), usize::MAX - i))
    }

    /// The thread line, and the lengths along Z of what comes before it (the entry) and
    /// after it (the runout).
    fn line(&self) -> Option<(Piece, Length, Length)> {
        let main = self.main()?;
        let z_of = |ps: &[(Pos, Pos, Option<Angle>)]| {
            Length(
                ps.iter()
                    .map(|(a, b, _)| a.z.zip(b.z).map_or(0, |(a, b)| (b - a).0.abs()))
                    .sum(),
            )
        };
        let moves = self.moves();
        let (a, b, _) = moves[main];
        Some(((a, b), z_of(&moves[..main]), z_of(&moves[main + 1..])))
    }

    /// The phase of the thread line's helix.
    fn phase(&self) -> Option<Angle> {
        self.moves()[self.main()?].2
    }

    /// Every piece's ends.
    fn pieces(&self) -> impl Iterator<Item = Piece> + '_ {
        self.moves().iter().map(|&(a, b, _)| (a, b))
    }

    /// The thread block's lead (every block of a LinuxCNC chain has its own K: the thread's
    /// is the block that travels furthest along Z).
    fn thread_lead(&self) -> Lead {
        let mut at = self.from;
        let mut best = (0, self.blocks.first().map_or(Lead::ZERO, |p| p.lead));
        for p in &self.blocks {
            let next = p.end_position(at);
            let travel = at.z.zip(next.z).map_or(0, |(a, b)| (b - a).0.abs());
            if travel > best.0 {
                best = (travel, p.lead);
            }
            at = next;
        }
        best.1
    }

    fn towards(&self) -> i64 {
        match self.line() {
            Some(((a, b), ..)) => a.z.zip(b.z).map_or(0, |(a, b)| (b - a).signum()),
            None => 0,
        }
    }

    /// The line's diameter at `z` (on the line extended).
    fn x_at(&self, z: Length) -> Option<Length> {
        let ((a, b), ..) = self.line()?;
        let ((x0, z0), (x1, z1)) = (a.known()?, b.known()?);
        Some(if z1 == z0 {
            x0
        } else {
            x0 + (x1 - x0).mul_div((z - z0).0, (z1 - z0).0)
        })
    }

    /// The Z range of the line (a point for a face thread).
    fn z_range(&self) -> Option<(Length, Length)> {
        let ((a, b), ..) = self.line()?;
        let (za, zb) = (a.z?, b.z?);
        Some((za.min(zb), za.max(zb)))
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
    fn new(at: (u32, Option<u32>), direction: Option<SpindleDirection>, first: RunPass) -> Run {
        Run {
            at,
            direction,
            passes: vec![first],
            retract: 0,
        }
    }

    /// +1 when the thread is external (the passes come from larger diameters), −1
    /// internal (`spread`: the deepest pass's diameter less the first's). A runout or an
    /// entry rises out of the thread; else the deeper passes lie further in; else the
    /// first move along X after a pass leaves the thread.
    fn outward(&self, spread: Length) -> i64 {
        let first = &self.passes[0];
        let rise = first.line().and_then(|((a, b), ..)| {
            let pieces: Vec<Piece> = first.pieces().collect();
            let (start, end) = (pieces.first()?.0, pieces.last()?.1);
            let out = |p: Pos, q: Pos| p.x.zip(q.x).map(|(p, q)| (p - q).signum());
            out(end, b).filter(|s| *s != 0).or(out(start, a))
        });
        match (rise.unwrap_or(0), spread.signum(), self.retract) {
            (0, 0, r) if r < 0 => -1,
            (0, 0, _) => 1,
            (0, s, _) => -s,
            (c, _, _) => c,
        }
    }

    /// Whether a block continuing a synchronised move at `pos` continues the last pass.
    fn continues_at(&self, pos: Pos) -> bool {
        self.passes.last().is_some_and(|p| p.end == pos)
    }

    fn chain(&mut self, pass: ThreadPass) {
        if let Some(last) = self.passes.last_mut() {
            last.chain(pass);
        }
    }

    /// A new pass: the last one is complete now, so whether it belongs to this thread can be
    /// told; if it does not, it begins an operation of its own.
    fn push(&mut self, next: RunPass, ops: &mut Vec<Operation>, options: &Options) {
        self.settle(ops, options);
        self.passes.push(next);
    }

    /// The last pass (complete) stays when it cuts the same thread as the first, else it
    /// ends this run's operation and begins the next.
    fn settle(&mut self, ops: &mut Vec<Operation>, options: &Options) {
        if self.passes.len() < 2 {
            return;
        }
        let last = self.passes.len() - 1;
        if self.same_thread(&self.passes[last]) {
            return;
        }
        let Some(p) = self.passes.pop() else { return };
        let done = std::mem::replace(self, Run::new(p.at, self.direction, p));
        ops.push(passes_operation(done, options));
    }

    /// Whether `p` cuts the same thread as the first pass: the same lead and cutting
    /// direction, over Z that overlaps the first's, within a thread's depth of it.
    fn same_thread(&self, p: &RunPass) -> bool {
        let first = &self.passes[0];
        let overlaps = match (first.z_range(), p.z_range()) {
            (Some((a0, a1)), Some((b0, b1))) if a0 == a1 || b0 == b1 => a0 <= b1 && b0 <= a1,
            (Some((a0, a1)), Some((b0, b1))) => a0 < b1 && b0 < a1,
            _ => false,
        };
        // A thread is at most about a lead deep per side: two diameters further apart than
        // two leads are two threads.
        let reach = first.thread_lead().length_times(2, 1) + Length::from_mm(0);
        let close = match first
            .z_range()
            .and_then(|(z, _)| first.x_at(z).zip(p.x_at(z)))
        {
            Some((a, b)) => (a - b).abs() <= reach,
            None => true,
        };
        first.thread_lead() == p.thread_lead()
            && first.towards() == p.towards()
            && overlaps
            && close
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
    if let Some(mut r) = run.take() {
        r.settle(ops, options);
        ops.push(passes_operation(r, options));
    }
}

/// `v²` of a length, for chip areas.
fn square(l: Length) -> f64 {
    (l.0 as f64) * (l.0 as f64)
}

/// The rows of a thread's passes: depths below the crest (or the first pass), cuts from
/// the pass before on the same start, chip areas, shifts and spring passes.
struct Rows<'a> {
    /// +1: the passes go in from larger diameters (external).
    outward: i64,
    crest: Option<Length>,
    reference_z: Option<Length>,
    lead: Lead,
    passes: &'a [RunPass],
    /// The depth of each pass when the thread says it (a cycle's expansion).
    depths: Option<Vec<Length>>,
}

impl Rows<'_> {
    fn rows(&self) -> Vec<Pass> {
        let x_at = |p: &RunPass| self.reference_z.and_then(|z| p.x_at(z));
        let below = |x: Length, from: Length| Length(self.outward * (from - x).0).mul_div(1, 2);
        let first_x = self.passes.first().and_then(x_at);
        let first_phase = self.passes.first().and_then(|p| p.phase());
        let mut rows: Vec<Pass> = Vec::with_capacity(self.passes.len());
        // Each start: its last pass's shift, depth below the first pass, and depth.
        let mut starts: Vec<(Length, Length, Option<Length>)> = Vec::new();
        let mut previous_depth = Length::ZERO;
        for (i, p) in self.passes.iter().enumerate() {
            let x = x_at(p);
            let below_first = x.zip(first_x).map_or(Length::ZERO, |(x, f)| below(x, f));
            let depth = match &self.depths {
                Some(d) => d.get(i).copied(),
                None => self.crest.zip(x).map(|(c, x)| below(x, c)),
            };
            let shift = p
                .phase()
                .zip(first_phase)
                .map(|(a, b)| shift_of(b, a, self.lead));
            // A pass belongs to the start whose last pass's helix it follows: its shift
            // moves by no more than its depth grew (an infeed of at most 45°), give or take
            // 0.01 mm.
            let s = shift.unwrap_or_default();
            let start = starts.iter().position(|&(ss, d, _)| {
                (s - ss).abs() <= (below_first - d).abs() + Length::from_steps(100)
            });
            let before = start.map(|k| starts[k]);
            let start = start.unwrap_or_else(|| {
                starts.push((s, below_first, depth));
                starts.len() - 1
            });
            let cut = match (&self.depths, depth, before) {
                // A cycle's passes follow one another on one start.
                (Some(_), Some(d), _) => Some(d - previous_depth),
                (None, Some(d), Some((_, _, Some(b)))) => Some(d - b),
                (None, Some(d), None) => Some(d),
                (_, _, Some((_, b, _))) => Some(below_first - b),
                _ => None,
            };
            previous_depth = depth.unwrap_or_default();
            starts[start] = (s, below_first, depth);
            rows.push(Pass {
                number: i + 1,
                start_number: start + 1,
                cut,
                cumulative_depth: depth,
                below_first,
                chip_area: None,
                start: Pos::UNKNOWN,
                end: Pos::UNKNOWN,
                shift,
                start_angle: p.blocks[0].start.angle(),
                spring: before.is_some() && cut == Some(Length::ZERO),
            });
            if let Some(((a, b), ..)) = p.line() {
                let row = rows.last_mut().expect("pushed");
                row.start = a;
                row.end = b;
            }
        }
        // Chip areas relative to the first pass.
        let first = rows
            .first()
            .and_then(|r| r.cumulative_depth)
            .filter(|d| d.0 > 0);
        for row in &mut rows {
            row.chip_area = match (first, row.cumulative_depth, row.cut) {
                (Some(f), Some(d), Some(c)) => Some((square(d) - square(d - c)) / square(f)),
                _ => None,
            };
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
    let lead = first.thread_lead();
    let mut op = blank(Kind::Passes, run.at, run.direction, towards, Some(lead));
    let reference_z = first.line().and_then(|((a, _), ..)| a.z);
    let xs: Vec<Length> = run
        .passes
        .iter()
        .filter_map(|p| reference_z.and_then(|z| p.x_at(z)))
        .collect();
    let spread = xs.last().copied().unwrap_or_default() - xs.first().copied().unwrap_or_default();
    let outward = run.outward(spread);
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
        depths: None,
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
    if let Some(((a, b), ..)) = run.passes.last().and_then(|p| p.line())
        && let (Some(x0), Some(x1)) = (a.x, b.x)
    {
        op.taper = x1 - x0;
    }
    if let Some((_, entry, runout)) = first.line() {
        op.entry = Some(entry).filter(|l| l.0 > 0);
        op.runout = Some(runout).filter(|l| l.0 > 0);
    }
    op.start_angles = start_angles(&rows, lead);
    if let Some(angle) = infeed_angle(&rows) {
        op.infeed_angle = Some(angle);
    }
    op.spring_passes = rows.iter().filter(|r| r.spring).count();
    op.passes = rows;
    op
}

/// The starts: each start's angle after the index pulse relative to the first's helix.
fn start_angles(rows: &[Pass], lead: Lead) -> Vec<Angle> {
    let mut starts: Vec<(usize, Length)> = Vec::new();
    for r in rows {
        if !starts.iter().any(|(n, _)| *n == r.start_number) {
            starts.push((r.start_number, r.shift.unwrap_or_default()));
        }
    }
    let base = rows
        .first()
        .and_then(|r| r.start_angle)
        .unwrap_or(Angle::ZERO);
    starts
        .iter()
        .map(|&(_, shift)| {
            let turns = (shift.0 as i128 * TURN as i128 * Lead::PER_LENGTH as i128)
                .checked_div(lead.0.max(1) as i128)
                .unwrap_or(0);
            Angle((base.0 - turns as i64).rem_euclid(TURN))
        })
        .collect()
}

/// The infeed angle from the first pass to the deepest of its start.
fn infeed_angle(rows: &[Pass]) -> Option<f64> {
    let last = rows.iter().rev().find(|r| r.start_number == 1)?;
    let shift = last.shift?;
    (last.below_first.0 > 0).then(|| {
        (shift.to_mm_f64() / last.below_first.to_mm_f64())
            .atan()
            .to_degrees()
    })
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
            passes.push(RunPass::new(at, pos, p));
        }
        pos = m.kind.end_position(pos);
    }
    let mut rows = Rows {
        outward,
        crest: Some(cycle.crest),
        reference_z: Some(cycle.start.1),
        lead: cycle.lead,
        passes: &passes,
        // The expansion's depths are the cycle's own.
        depths: Some(expansion.passes.iter().map(|p| p.depth).collect()),
    }
    .rows();
    let spring_from = expansion.passes.len() - cycle.spring_passes as usize;
    for row in &mut rows {
        row.spring = row.number > spring_from;
        row.start_number = 1;
    }
    op.passes = rows;
    op
}

fn roughing_operation(cycle: &RoughingCycle, at: (u32, Option<u32>), from: Pos) -> Operation {
    let facing = matches!(cycle.kind, RoughingKind::Rough { facing: true, .. });
    // A pocket's cuts (G71.2/G72.2) start where each pocket does: no step.
    let steps = matches!(cycle.kind, RoughingKind::Rough { variant: 0 | 1, .. });
    let code = cycle.code_name();
    let finishing = code == "G70";
    cuts_operation(
        cuts_kind(code, finishing),
        &cycle.moves,
        facing,
        steps,
        at,
        from,
    )
}

/// A FANUC cycle under the machine model: its cuts, as a roughing cycle's (a cycle that only
/// goes home, G28, is none).
fn model_operation(cycle: &ModelCycle, at: (u32, Option<u32>), from: Pos) -> Option<Operation> {
    let cuts = !cycle.moves.is_empty() && !matches!(cycle.code.as_str(), "G28" | "G53");
    let kind = cuts_kind(cycle.code.clone(), cycle.finishing);
    cuts.then(|| cuts_operation(kind, &cycle.moves, cycle.facing, !cycle.finishing, at, from))
}

/// A cycle of cuts named by its G code: a finishing or a roughing one.
fn cuts_kind(code: String, finishing: bool) -> Kind {
    if finishing {
        Kind::Finishing(code)
    } else {
        Kind::Roughing(code)
    }
}

/// An operation of the cuts `moves` make (each cut the feeds and arcs between two rapids), and
/// with `steps` each cut's step from the one before, per side (along Z when `facing`).
fn cuts_operation(
    kind: Kind,
    moves: &[ItemKind],
    facing: bool,
    steps: bool,
    at: (u32, Option<u32>),
    from: Pos,
) -> Operation {
    let mut op = blank(kind, at, None, 0, None);
    // A cut: the feeds and arcs between two rapids.
    let mut pos = from;
    let mut rows: Vec<Pass> = Vec::new();
    let mut cutting = false;
    for m in moves {
        // A compensation switch (G70's contour) moves nothing.
        if matches!(m, ItemKind::Compensation(_)) {
            continue;
        }
        let next = m.end_position(pos);
        let arc = match m {
            ItemKind::Arc {
                centre, clockwise, ..
            } => Some((**centre, *clockwise)),
            _ => None,
        };
        match m {
            ItemKind::Rapid { .. } => cutting = false,
            _ => {
                if !cutting {
                    rows.push(Pass {
                        number: rows.len() + 1,
                        start_number: 1,
                        cut: None,
                        cumulative_depth: None,
                        below_first: Length::ZERO,
                        chip_area: None,
                        start: pos,
                        end: pos,
                        shift: None,
                        start_angle: None,
                        spring: false,
                    });
                    cutting = true;
                }
                if let Some(row) = rows.last_mut() {
                    row.end = next;
                }
            }
        }
        op.moves.push(CycleMove {
            from: pos,
            to: next,
            cut: cutting.then_some(rows.len()),
            arc,
        });
        pos = next;
    }
    // The step of each roughing cut from the one before, per side (along Z for facing).
    if steps {
        for i in 1..rows.len() {
            let (a, b) = (rows[i - 1].start, rows[i].start);
            rows[i].cut = if facing {
                a.z.zip(b.z).map(|(a, b)| (b - a).abs())
            } else {
                a.x.zip(b.x).map(|(a, b)| (b - a).abs().mul_div(1, 2))
            };
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
    /// UTF-8: box drawing, `Ø`, `°`, `−`.
    Box,
    /// ASCII only.
    Plain,
}

fn diameter(l: Length) -> String {
    format!("Ø{}", l.mm())
}

fn hand_text(op: &Operation) -> String {
    let spindle = op
        .direction
        .map_or("spindle not turning", SpindleDirection::code);
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
    match table {
        Table::Box => out,
        // What the plain table must not hold either.
        Table::Plain => out
            .replace('Ø', "D")
            .replace('°', " deg")
            .replace(['−', '—'], "-")
            .replace('²', "^2"),
    }
}

/// The lines under an operation's heading.
fn facts(op: &Operation) -> Vec<String> {
    use std::fmt::Write as _;
    let mut lines = Vec::new();
    match &op.kind {
        Kind::Kept(_) => return lines,
        Kind::Roughing(_) | Kind::Finishing(_) => {
            let n = op.passes.len();
            lines.push(format!("{n} cut{}", if n == 1 { "" } else { "s" }));
            return lines;
        }
        Kind::Tap => {
            let mut l = format!("{}, lead {} mm", hand_text(op), lead_text(op));
            if let Some((a, b)) = op.z_range {
                let _ = write!(l, ", Z{} to Z{}", a.mm(), b.mm());
            }
            lines.push(l);
            return lines;
        }
        _ => {}
    }
    lines.push(starts_line(op));
    lines.push(crest_line(op));
    if op
        .passes
        .iter()
        .any(|p| p.cumulative_depth.is_some_and(|d| d.0 < 0))
    {
        let side = if op.internal { "internal" } else { "external" };
        lines.push(format!(
            "some passes lie outside the crest: is it right? (the crest of an {side} thread is its {} diameter)",
            if op.internal { "minor (bore)" } else { "major" }
        ));
    }
    lines.push(shape_line(op));
    lines
}

/// The thread's hand, lead and starts, with each start's angle.
fn starts_line(op: &Operation) -> String {
    let starts = op.start_angles.len().max(1);
    let angles = op
        .start_angles
        .iter()
        .map(|a| format!("{a}°"))
        .collect::<Vec<_>>()
        .join(", ");
    format!(
        "{}, lead {} mm, {} start{} (start angle{} {})",
        hand_text(op),
        lead_text(op),
        starts,
        if starts == 1 { "" } else { "s" },
        if op.start_angles.len() > 1 { "s" } else { "" },
        if angles.is_empty() {
            "0°".into()
        } else {
            angles
        },
    )
}

/// External or internal, the crest and where it comes from, the root and the depth.
fn crest_line(op: &Operation) -> String {
    use std::fmt::Write as _;
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
        let _ = write!(l, ", root {}", diameter(r));
    }
    if let Some(d) = op.depth {
        let _ = write!(l, ", depth {} mm per side", d.mm());
    }
    l
}

/// The taper, the infeed, the entry and runout, the spring passes and the schedule.
fn shape_line(op: &Operation) -> String {
    use std::fmt::Write as _;
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
        let _ = write!(l, ", {s} schedule");
    }
    l
}

fn lead_text(op: &Operation) -> String {
    op.lead.map_or("?".into(), |l| l.mm())
}

/// An axis of a point in a table column (`?` when not known).
fn axis(v: Option<Length>) -> String {
    v.map_or("?".to_string(), |v| v.mm_fixed())
}

/// The pass table as aligned columns.
fn pass_table(op: &Operation, table: Table) -> String {
    let header: Vec<String> = table_header(op).iter().map(|s| s.to_string()).collect();
    let rows: Vec<Vec<String>> = op.passes.iter().map(|p| table_row(op, p)).collect();
    draw_table(&header, &rows, table)
}

/// The pass table's column names.
fn table_header(op: &Operation) -> Vec<&'static str> {
    let roughing = matches!(op.kind, Kind::Roughing(_) | Kind::Finishing(_));
    let known = op.crest.is_some();
    let many = op.start_angles.len() > 1;
    let mut header: Vec<&str> = vec!["pass"];
    if roughing {
        header.push("step");
    } else {
        if many {
            header.push("start");
        }
        header.extend([
            "cut",
            if known { "depth" } else { "below pass 1" },
            "chip area",
            "shift",
        ]);
    }
    header.extend(["X start", "Z start", "X end", "Z end"]);
    header
}

/// One pass's cells in the pass table, as [`table_header`] names them.
fn table_row(op: &Operation, p: &Pass) -> Vec<String> {
    let roughing = matches!(op.kind, Kind::Roughing(_) | Kind::Finishing(_));
    let known = op.crest.is_some();
    let many = op.start_angles.len() > 1;
    let none = "—".to_string();
    let opt = |l: Option<Length>| l.map_or(none.clone(), |l| l.mm_fixed());
    let mut r = vec![format!("{}{}", p.number, if p.spring { "s" } else { "" })];
    if !roughing && many {
        r.push(p.start_number.to_string());
    }
    r.push(opt(p.cut));
    if !roughing {
        r.push(if known {
            opt(p.cumulative_depth)
        } else {
            p.below_first.mm_fixed()
        });
        r.push(p.chip_area.map_or(none.clone(), |a| format!("{a:.2}")));
        r.push(opt(p.shift));
    }
    r.extend([
        axis(p.start.x),
        axis(p.start.z),
        axis(p.end.x),
        axis(p.end.z),
    ]);
    r
}

/// A table of `rows` under `header`, ruled with box-drawing characters or plain ASCII,
/// each column as wide as its widest cell and right-aligned.
fn draw_table(header: &[String], rows: &[Vec<String>], table: Table) -> String {
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
    out.push_str(&line(header));
    out.push_str(&rule(corners[1]));
    for r in rows {
        out.push_str(&line(r));
    }
    out.push_str(&rule(corners[2]));
    out
}

fn mm(l: Length) -> serde_json::Value {
    serde_json::json!(l.to_mm_f64())
}

fn point(p: Pos) -> (Option<serde_json::Value>, Option<serde_json::Value>) {
    (p.x.map(mm), p.z.map(mm))
}

/// The JSON form: `{ "operations": [ { …, "passes": [ … ] } ] }`, lengths in mm, `null` for
/// what the program does not say.
pub fn to_json(ops: &[Operation]) -> serde_json::Value {
    let operations: Vec<serde_json::Value> = ops
        .iter()
        .map(|op| {
            let passes: Vec<serde_json::Value> = op
                .passes
                .iter()
                .map(|p| {
                    let ((xs, zs), (xe, ze)) = (point(p.start), point(p.end));
                    serde_json::json!({
                        "pass": p.number,
                        "start": p.start_number,
                        "cut": p.cut.map(mm),
                        "cumulative_depth": p.cumulative_depth.map(mm),
                        "below_first": mm(p.below_first),
                        "chip_area": p.chip_area.map(|a| (a * 10_000.0).round() / 10_000.0),
                        "shift": p.shift.map(mm),
                        "start_angle": p.start_angle.map(|a| a.to_deg_f64()),
                        "spring": p.spring,
                        "x_start": xs,
                        "z_start": zs,
                        "x_end": xe,
                        "z_end": ze,
                    })
                })
                .collect();
            let code = match &op.kind {
                Kind::Roughing(code) | Kind::Finishing(code) | Kind::Kept(code) => {
                    Some(code.clone())
                }
                _ => None,
            };
            serde_json::json!({
                "operation": op.number,
                "kind": op.kind.id(),
                "code": code,
                "line": op.line,
                "block": op.block,
                "spindle": op.direction.map(SpindleDirection::code),
                "towards": op.towards,
                "hand": op.hand.map(Hand::id),
                "lead": op.lead.map(|l| l.to_mm_f64()),
                "starts": op.lead.map(|_| op.start_angles.len().max(1)),
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

/// The CSV form: one row per pass, the operation's facts repeated on each; empty cells for
/// what the program does not say.
pub fn to_csv(ops: &[Operation]) -> String {
    let mut out = String::from(
        "operation,kind,line,hand,lead,crest,pass,start,cut,cumulative_depth,below_first,chip_area,shift,x_start,z_start,x_end,z_end\n",
    );
    let opt = |l: Option<Length>| l.map_or(String::new(), |l| l.mm());
    for op in ops {
        for p in &op.passes {
            out.push_str(&format!(
                "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n",
                op.number,
                op.kind.id(),
                op.line,
                op.hand.map_or("", Hand::id),
                op.lead.map_or(String::new(), |l| l.mm()),
                opt(op.crest),
                p.number,
                p.start_number,
                opt(p.cut),
                opt(p.cumulative_depth),
                p.below_first.mm(),
                p.chip_area.map_or(String::new(), |a| format!("{a:.4}")),
                opt(p.shift),
                opt(p.start.x),
                opt(p.start.z),
                opt(p.end.x),
                opt(p.end.z),
            ));
        }
    }
    out
}

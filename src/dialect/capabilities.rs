//! What each dialect reads and writes: one table per dialect, declared beside it
//! ([`super::Dialect::capabilities`]), printed by `ncthread dialects`, and read by the one
//! legalisation pass ([`crate::legalise::for_target`]) that refuses, for every target, what the
//! target cannot say.

use std::fmt::Write as _;

use crate::diag::Code;
use crate::ir::{FeedMode, ItemKind, Pos, Program, SyncStart};
use crate::lower;

/// A construct a program may hold, as the capability table names it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Construct {
    /// A multi-pass thread cycle kept as one cycle.
    ThreadCycle,
    /// A pass that starts at an angle after the index pulse.
    StartAngle,
    /// An entry taper at the start of a pass.
    Entry,
    /// A runout at the end of a pass.
    Runout,
    /// A single pass along a taper.
    TaperPass,
    /// A synchronised move that continues the one before it without the index pulse.
    ContinuedChain,
    /// A pass that waits for the index pulse where another ended (the tool in the cut).
    IndexWaitInCut,
    /// A synchronised move along X (LinuxCNC's G76 infeed, a G33 along X).
    SyncInfeed,
    /// A synchronised move steeper than 45°: X (as a radius) moves more than Z.
    SteepSync,
    /// A circular feed move (G2/G3).
    Arc,
    /// A feed move at 45° in both axes (the НЦ-31's `X…±45 *` + `F…`): a linear feed move
    /// in the IR, a chamfer only where a target has a form for it.
    Chamfer45,
    /// Flood coolant on and coolant off (M8, M9).
    Coolant,
    /// Mist coolant on (M7).
    MistCoolant,
    /// A programmed or optional stop (M0, M1).
    Stop,
    /// Constant surface speed (G96).
    SurfaceSpeed,
    /// Cutter radius (tool nose) compensation on (G41, G42).
    CutterCompensation,
    /// A work offset other than the default (G55 … G59.3).
    WorkOffset,
    /// Moves and settings in machine coordinates (G53, G28, G30).
    MachineCoordinates,
    /// A rigid tapping cycle.
    Tapping,
    /// A dwell.
    Dwell,
    /// A feed in mm per minute.
    PerMinuteFeed,
    /// A tool offset number beside the tool.
    ToolOffset,
    /// Parameter assignments.
    Parameters,
    /// Frames run again (the НЦ-31's G25): read unrolled, so a program never holds one.
    Repeat,
    /// Comments.
    Comments,
}

impl Construct {
    pub const ALL: [Construct; 25] = [
        Construct::ThreadCycle,
        Construct::StartAngle,
        Construct::Entry,
        Construct::Runout,
        Construct::TaperPass,
        Construct::ContinuedChain,
        Construct::IndexWaitInCut,
        Construct::SyncInfeed,
        Construct::SteepSync,
        Construct::Arc,
        Construct::Chamfer45,
        Construct::Coolant,
        Construct::MistCoolant,
        Construct::Stop,
        Construct::SurfaceSpeed,
        Construct::CutterCompensation,
        Construct::WorkOffset,
        Construct::MachineCoordinates,
        Construct::Tapping,
        Construct::Dwell,
        Construct::PerMinuteFeed,
        Construct::ToolOffset,
        Construct::Parameters,
        Construct::Repeat,
        Construct::Comments,
    ];

    /// Its name in the table.
    pub fn name(self) -> &'static str {
        match self {
            Construct::ThreadCycle => "thread cycle kept whole",
            Construct::StartAngle => "start angle",
            Construct::Entry => "entry taper",
            Construct::Runout => "runout",
            Construct::TaperPass => "taper pass",
            Construct::ContinuedChain => "continued G33 chain",
            Construct::IndexWaitInCut => "index wait in the cut",
            Construct::SyncInfeed => "synchronised move along X",
            Construct::SteepSync => "synchronised move steeper than 45°",
            Construct::Arc => "arc (G2/G3)",
            Construct::Chamfer45 => "45° chamfer",
            Construct::Coolant => "flood coolant, coolant off",
            Construct::MistCoolant => "mist coolant",
            Construct::Stop => "program stop, optional stop",
            Construct::SurfaceSpeed => "constant surface speed (G96)",
            Construct::CutterCompensation => "cutter radius compensation (G41/G42)",
            Construct::WorkOffset => "work offsets other than the default (G55 … G59.3)",
            Construct::MachineCoordinates => "machine coordinates and homing (G53, G28, G30)",
            Construct::Tapping => "rigid tapping",
            Construct::Dwell => "dwell",
            Construct::PerMinuteFeed => "feed per minute",
            Construct::ToolOffset => "tool offset",
            Construct::Parameters => "parameters",
            Construct::Repeat => "repeat of frames (G25)",
            Construct::Comments => "comments",
        }
    }

    /// The construct a coolant command is.
    pub fn of_coolant(c: crate::ir::Coolant) -> Construct {
        match c {
            crate::ir::Coolant::Mist => Construct::MistCoolant,
            _ => Construct::Coolant,
        }
    }

    /// Whether `program` holds this construct (cycles count with their passes): one of
    /// its [`occurrences`].
    pub fn appears_in(self, program: &Program) -> bool {
        occurrences(program).iter().any(|o| o.construct == self)
    }
}

/// A use of a construct in a program: what, where, and for a pass the start angle it waits
/// for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Occurrence {
    pub construct: Construct,
    pub span: crate::source::Span,
    pub angle: Option<crate::fixed::Angle>,
}

/// Every use of a construct in program order, the one rule of where a construct occurs: what
/// the legalisation refuses ([`crate::legalise::for_target`]) and what `dialects` and the
/// tests say a program holds. A cycle's passes count as the cycle's; a pass that waits for
/// the index pulse where the pass before it ended (the tool still in the cut) is an
/// [`Construct::IndexWaitInCut`].
pub fn occurrences(program: &Program) -> Vec<Occurrence> {
    let mut finder = Occurrences::default();
    let mut out = Vec::new();
    for item in &program.items {
        finder.item(item, &mut out);
    }
    out
}

/// [`occurrences`] over a program's items one at a time, in order: the feed mode, the
/// position and whether the last pass left the tool in the cut.
#[derive(Debug)]
pub struct Occurrences {
    per_minute: bool,
    pos: Pos,
    in_cut: Option<Pos>,
}

impl Default for Occurrences {
    fn default() -> Self {
        Occurrences {
            per_minute: false,
            pos: Pos::UNKNOWN,
            in_cut: None,
        }
    }
}

impl Occurrences {
    /// The occurrences in the program's next item, added to `out`.
    pub fn item(&mut self, item: &crate::ir::Item, out: &mut Vec<Occurrence>) {
        let (pos, in_cut) = (self.pos, self.in_cut);
        let mut found: Vec<(Construct, Option<crate::fixed::Angle>)> = Vec::new();
        match &item.kind {
            ItemKind::TapCycle(_) => found.push((Construct::Tapping, None)),
            ItemKind::Arc { .. } => {
                found.push((Construct::Arc, None));
                if self.per_minute {
                    found.push((Construct::PerMinuteFeed, None));
                }
            }
            ItemKind::Coolant(c) => found.push((Construct::of_coolant(*c), None)),
            ItemKind::Stop { .. } => found.push((Construct::Stop, None)),
            ItemKind::SpindleMode(crate::ir::SpindleMode::SurfaceSpeed { .. }) => {
                found.push((Construct::SurfaceSpeed, None))
            }
            ItemKind::Compensation(c) if *c != crate::ir::Compensation::Off => {
                found.push((Construct::CutterCompensation, None))
            }
            // A G41/G42 kept as written in a cycle's contour.
            ItemKind::Opaque { block: Some(c), .. } if c.compensation => {
                found.push((Construct::CutterCompensation, None))
            }
            ItemKind::ModelCycle(m) if m.context.compensation => {
                found.push((Construct::CutterCompensation, None))
            }
            ItemKind::WorkOffset(n) if *n != 1 => found.push((Construct::WorkOffset, None)),
            ItemKind::MachineMove(_) => found.push((Construct::MachineCoordinates, None)),
            ItemKind::Dwell { .. } => found.push((Construct::Dwell, None)),
            ItemKind::FeedMode(mode) => self.per_minute = *mode == FeedMode::PerMin,
            ItemKind::Feed { to, .. } => {
                if self.per_minute {
                    found.push((Construct::PerMinuteFeed, None));
                }
                if at_45_degrees(pos, *to) {
                    found.push((Construct::Chamfer45, None));
                }
            }
            // A zero feed is no feed any move runs at (the writers leave it out or say it).
            ItemKind::FeedRate(f) if self.per_minute && *f != crate::fixed::Length::ZERO => {
                found.push((Construct::PerMinuteFeed, None))
            }
            ItemKind::ThreadCycle(c) => cycle_occurrences(c, pos, &mut found),
            ItemKind::ThreadPass(pass) => {
                pass_occurrences(pass, pos, in_cut == Some(pos), &mut found)
            }
            ItemKind::Tool {
                offset: Some(_), ..
            } => found.push((Construct::ToolOffset, None)),
            ItemKind::ParamAssign { .. } => found.push((Construct::Parameters, None)),
            ItemKind::Comment(_) => found.push((Construct::Comments, None)),
            _ => {}
        }
        if item.comment.is_some() && !matches!(item.kind, ItemKind::Comment(_)) {
            found.push((Construct::Comments, None));
        }
        out.extend(found.into_iter().map(|(construct, angle)| Occurrence {
            construct,
            span: item.span,
            angle,
        }));
        let moved = item.kind.end_position(pos);
        self.in_cut = match &item.kind {
            ItemKind::ThreadPass(_) => Some(moved),
            ItemKind::ThreadCycle(_)
            | ItemKind::TapCycle(_)
            | ItemKind::Opaque { block: Some(_), .. } => None,
            _ if moved != pos => None,
            _ => in_cut,
        };
        self.pos = moved;
    }
}

/// What a single pass from `pos` holds: a synchronised infeed, a move steeper than 45°, a
/// continued chain, an index wait with the tool in the cut (`in_cut`: the pass before it
/// ended here), and its shape.
fn pass_occurrences(
    pass: &crate::ir::ThreadPass,
    pos: Pos,
    in_cut: bool,
    found: &mut Vec<(Construct, Option<crate::fixed::Angle>)>,
) {
    if pass.infeed.is_some() {
        found.push((Construct::SyncInfeed, None));
    }
    if steep_sync(pos, pass) {
        found.push((Construct::SteepSync, None));
    }
    match pass.start {
        SyncStart::Continue => found.push((Construct::ContinuedChain, None)),
        SyncStart::Index(angle) if in_cut => found.push((Construct::IndexWaitInCut, Some(angle))),
        SyncStart::Index(_) => {}
    }
    pass_shape(pos, pass, found);
}

/// What a thread cycle from `pos` holds: itself, a synchronised infeed along its entry, a
/// pass steeper than 45°, and the shapes of its passes (each construct once).
fn cycle_occurrences(
    c: &crate::ir::ThreadCycle,
    pos: Pos,
    found: &mut Vec<(Construct, Option<crate::fixed::Angle>)>,
) {
    found.push((Construct::ThreadCycle, None));
    if c.entry_infeed && c.entry.is_some() {
        found.push((Construct::SyncInfeed, None))
    }
    let Ok(e) = lower::expand(c) else {
        return;
    };
    let mut p = pos;
    let mut steep = false;
    let mut shapes = Vec::new();
    for m in &e.moves {
        if let lower::Move::Pass(pass) = &m.kind {
            steep |= steep_sync(p, pass);
            pass_shape(p, pass, &mut shapes);
        }
        p = m.kind.end_position(p);
    }
    if steep {
        found.push((Construct::SteepSync, None));
    }
    for s in shapes {
        if !found.contains(&s) {
            found.push(s);
        }
    }
}

/// The shape of a pass from `start`, as the writers refuse it: a start angle, an entry, a
/// runout, a taper (each construct once in `found`).
fn pass_shape(
    start: Pos,
    pass: &crate::ir::ThreadPass,
    found: &mut Vec<(Construct, Option<crate::fixed::Angle>)>,
) {
    let line_start_x = pass
        .infeed
        .map(|i| i.x)
        .or(start.x)
        .map(|x| x - pass.entry.map_or(crate::fixed::Length::ZERO, |e| e.offset));
    let shapes = [
        (
            Construct::StartAngle,
            matches!(pass.start, SyncStart::Index(a) if a != crate::fixed::Angle::ZERO),
        ),
        (Construct::Entry, pass.entry.is_some()),
        (Construct::Runout, pass.exit.is_some()),
        (
            Construct::TaperPass,
            matches!((line_start_x, pass.to.x), (Some(a), Some(b)) if a != b),
        ),
    ];
    for (construct, holds) in shapes {
        if holds && !found.contains(&(construct, None)) {
            found.push((construct, None));
        }
    }
}

/// Whether a pass from `start` has a synchronised move (its entry, thread or runout) along
/// which X, as a radius, moves more than Z: steeper than 45° (a move along X only is a
/// [`Construct::SyncInfeed`]).
pub fn steep_sync(start: Pos, pass: &crate::ir::ThreadPass) -> bool {
    lower::pass_segments(start, pass)
        .is_ok_and(|segs| segs.iter().any(|s| !s.is_radial() && s.is_steep()))
}

/// Whether a move from `from` to `to` changes the diameter by twice its Z travel, and moves.
fn at_45_degrees(from: Pos, to: Pos) -> bool {
    let (Some((sx, sz)), Some(ex), Some(ez)) = (from.known(), to.x, to.z) else {
        return false;
    };
    let (dx, dz) = (ex.0.checked_sub(sx.0), ez.0.checked_sub(sz.0));
    dz.is_some_and(|d| d != 0)
        && dx.and_then(i64::checked_abs)
            == dz.and_then(i64::checked_abs).and_then(|d| d.checked_mul(2))
}

/// How a dialect reads a construct.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Read {
    /// Read, written as (`G33 … I`, `E`).
    Yes(&'static str),
    /// Not in the dialect (or not documented): refused or never there.
    No,
}

/// How a target writes a construct.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Write {
    /// Written as (`I`, `G33.1`).
    Yes(&'static str),
    /// Written in another documented form, or only under a condition, or left out where
    /// that changes no motion (said here, with its verb).
    As(&'static str),
    /// Not written: the conversion is refused with this code.
    No(Code),
}

/// One row of a dialect's table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Capability {
    pub construct: Construct,
    pub read: Read,
    pub write: Write,
}

/// A row of a table: how a dialect reads and writes `construct`.
pub const fn row(construct: Construct, read: Read, write: Write) -> Capability {
    Capability {
        construct,
        read,
        write,
    }
}

/// A dialect's table: a row per construct, and how its numbers are written.
#[derive(Clone, Debug)]
pub struct Capabilities {
    pub rows: Vec<Capability>,
    /// Lengths and leads: their grid and what `--round` does.
    pub numbers: &'static str,
    /// The machine's G codes where they differ from those the texts name (FANUC's G-code
    /// systems B and C; the texts are in system A's): (as written, the machine's).
    pub renumbered: Vec<(i64, i64)>,
}

/// `text` with each G code `renumbered` names (`G92` → `G78`), each word changed once.
fn respell(text: &str, renumbered: &[(i64, i64)]) -> String {
    if renumbered.is_empty() {
        return text.to_string();
    }
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(at) = rest.find('G') {
        let (head, tail) = rest.split_at(at);
        out.push_str(head);
        let digits = tail[1..].len()
            - tail[1..]
                .trim_start_matches(|c: char| c.is_ascii_digit())
                .len();
        let after = tail[1 + digits..].chars().next();
        let word_start = !out.chars().last().is_some_and(|c| c.is_alphanumeric());
        let code = tail[1..1 + digits].parse::<i64>().ok();
        let mapped = code
            .filter(|_| word_start && digits > 0 && !matches!(after, Some('.') | Some('0'..='9')))
            .and_then(|g| renumbered.iter().find(|(a, _)| *a == g).map(|(_, b)| *b));
        match mapped {
            Some(b) => {
                out.push_str(&format!("G{b:0width$}", width = digits));
            }
            None => out.push_str(&tail[..1 + digits]),
        }
        rest = &tail[1 + digits..];
    }
    out.push_str(rest);
    out
}

impl Capabilities {
    /// How the target writes `construct` (a construct without a row is written as it is).
    pub fn write(&self, construct: Construct) -> Write {
        self.rows
            .iter()
            .find(|r| r.construct == construct)
            .map_or(Write::Yes(""), |r| r.write)
    }

    /// Whether the target writes `construct` at all.
    pub fn writes(&self, construct: Construct) -> bool {
        !matches!(self.write(construct), Write::No(_))
    }
}

/// The table of every dialect in `dialects`, as Markdown: a row per construct, a column per
/// dialect, each cell `read / write`.
pub fn table(dialects: &[(&str, Capabilities)]) -> String {
    let mut out = String::from("| construct |");
    for (id, _) in dialects {
        let _ = write!(out, " {id} |");
    }
    out.push_str("\n| --- |");
    for _ in dialects {
        out.push_str(" --- |");
    }
    out.push('\n');
    let cell = |c: Option<&Capability>, renumbered: &[(i64, i64)]| -> String {
        let Some(c) = c else {
            return "reads; writes".into();
        };
        let read = match c.read {
            Read::Yes("") => "reads".to_string(),
            Read::Yes(how) => format!("reads ({how})"),
            Read::No => "does not read".to_string(),
        };
        let write = match c.write {
            Write::Yes("") => "writes".to_string(),
            Write::Yes(how) => format!("writes ({how})"),
            Write::As(how) => how.to_string(),
            Write::No(code) => format!("**refuses** ({})", code.id),
        };
        respell(&format!("{read}; {write}"), renumbered)
    };
    for construct in Construct::ALL {
        let _ = write!(out, "| {} |", construct.name());
        for (_, caps) in dialects {
            let row = caps.rows.iter().find(|r| r.construct == construct);
            let _ = write!(out, " {} |", cell(row, &caps.renumbered));
        }
        out.push('\n');
    }
    out.push_str("| numbers |");
    for (_, caps) in dialects {
        let _ = write!(out, " {} |", caps.numbers);
    }
    out.push('\n');
    out
}

#[cfg(test)]
mod tests {
    use super::respell;

    #[test]
    fn respelled_codes_are_whole_g_words_changed_once() {
        // FANUC system B: G32 → G33, G92 → G78, G50 → G92 (each word once: G50 is not G78).
        let b = [(32, 33), (92, 78), (50, 92)];
        assert_eq!(
            respell("reads (G32/G92 … Q, G50 S its limit, G92's chamfer)", &b),
            "reads (G33/G78 … Q, G92 S its limit, G78's chamfer)"
        );
        // Not a G word of its own, or another code: left as written.
        assert_eq!(
            respell("G92.1 G920 AG92 G G-code", &b),
            "G92.1 G920 AG92 G G-code"
        );
        assert_eq!(respell("G92", &[]), "G92");
    }
}

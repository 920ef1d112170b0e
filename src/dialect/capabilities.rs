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

    /// Whether `program` holds this construct (cycles count with their passes).
    pub fn appears_in(self, program: &Program) -> bool {
        if self == Construct::IndexWaitInCut {
            return crate::sim::simulate(program)
                .segments
                .iter()
                .any(|s| s.motion == crate::sim::Motion::IndexWait);
        }
        let mut pos = Pos::UNKNOWN;
        let mut per_minute = false;
        for item in &program.items {
            let mut passes: Vec<(Pos, crate::ir::ThreadPass)> = Vec::new();
            let found = match &item.kind {
                ItemKind::ThreadCycle(c) => {
                    if let Ok(e) = lower::expand(c) {
                        let mut p = pos;
                        for m in &e.moves {
                            if let lower::Move::Pass(pass) = m.kind {
                                passes.push((p, pass));
                            }
                            p = m.kind.end_position(p);
                        }
                    }
                    self == Construct::ThreadCycle
                }
                ItemKind::ThreadPass(pass) => {
                    passes.push((pos, **pass));
                    false
                }
                ItemKind::TapCycle(_) => self == Construct::Tapping,
                ItemKind::Arc { .. } => {
                    self == Construct::Arc || (self == Construct::PerMinuteFeed && per_minute)
                }
                ItemKind::Coolant(c) => self == Construct::of_coolant(*c),
                ItemKind::Stop { .. } => self == Construct::Stop,
                ItemKind::SpindleMode(crate::ir::SpindleMode::SurfaceSpeed { .. }) => {
                    self == Construct::SurfaceSpeed
                }
                ItemKind::Compensation(c) => {
                    self == Construct::CutterCompensation && *c != crate::ir::Compensation::Off
                }
                ItemKind::WorkOffset(n) => self == Construct::WorkOffset && *n != 1,
                ItemKind::MachineMove(_) => self == Construct::MachineCoordinates,
                ItemKind::Dwell { .. } => self == Construct::Dwell,
                ItemKind::FeedMode(mode) => {
                    per_minute = *mode == FeedMode::PerMin;
                    false
                }
                ItemKind::Feed { to, .. } => {
                    (self == Construct::PerMinuteFeed && per_minute)
                        || (self == Construct::Chamfer45 && at_45_degrees(pos, *to))
                }
                ItemKind::FeedRate(_) => self == Construct::PerMinuteFeed && per_minute,
                ItemKind::Tool {
                    offset: Some(_), ..
                } => self == Construct::ToolOffset,
                ItemKind::ParamAssign { .. } => self == Construct::Parameters,
                ItemKind::Comment(_) => self == Construct::Comments,
                _ => false,
            };
            if found || (self == Construct::Comments && item.comment.is_some()) {
                return true;
            }
            for (start, pass) in &passes {
                let line_start_x = pass
                    .infeed
                    .map(|i| i.x)
                    .or(start.x)
                    .map(|x| x - pass.entry.map_or(crate::fixed::Length::ZERO, |e| e.offset));
                let hit = match self {
                    Construct::StartAngle => {
                        matches!(pass.start, SyncStart::Index(a) if a != crate::fixed::Angle::ZERO)
                    }
                    Construct::Entry => pass.entry.is_some(),
                    Construct::Runout => pass.exit.is_some(),
                    Construct::TaperPass => {
                        matches!((line_start_x, pass.to.x), (Some(a), Some(b)) if a != b)
                    }
                    Construct::ContinuedChain => pass.start == SyncStart::Continue,
                    Construct::SyncInfeed => pass.infeed.is_some(),
                    Construct::SteepSync => steep_sync(*start, pass),
                    _ => false,
                };
                if hit {
                    return true;
                }
            }
            pos = item.kind.end_position(pos);
        }
        false
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
    let cell = |c: Option<&Capability>| -> String {
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
        format!("{read}; {write}")
    };
    for construct in Construct::ALL {
        let _ = write!(out, "| {} |", construct.name());
        for (_, caps) in dialects {
            let row = caps.rows.iter().find(|r| r.construct == construct);
            let _ = write!(out, " {} |", cell(row));
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

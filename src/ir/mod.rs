//! The thread-operation IR: one explicit, dialect-free program.
//!
//! Front ends resolve modal state, units, incremental words and parameters, so every item
//! says exactly what the machine does. Lengths are [`Length`] (0.0001 mm, X a diameter),
//! angles [`Angle`] (0.001°).

use crate::dialect::Dialect;
use crate::fixed::{Angle, Decimal, Length};
use crate::source::Span;

/// A program: items in execution order.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Program {
    pub items: Vec<Item>,
}

/// One item with where it came from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Item {
    pub kind: ItemKind,
    /// The source block (or word) this item comes from.
    pub span: Span,
    /// The source block number (`N335` → 335), if any.
    pub block_number: Option<u32>,
    /// The comment written on the item's block (attached to the block's first item).
    pub comment: Option<String>,
}

/// A point whose axes may still be unknown (before the first absolute word for that axis).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Pos {
    /// Diameter.
    pub x: Option<Length>,
    pub z: Option<Length>,
}

impl Pos {
    pub const UNKNOWN: Pos = Pos { x: None, z: None };

    pub fn new(x: Length, z: Length) -> Pos {
        Pos {
            x: Some(x),
            z: Some(z),
        }
    }

    /// Both axes, when both are known.
    pub fn known(self) -> Option<(Length, Length)> {
        Some((self.x?, self.z?))
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SpindleDirection {
    /// M03
    Clockwise,
    /// M04
    CounterClockwise,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FeedMode {
    /// G95: mm per spindle revolution.
    PerRev,
    /// G94: mm per minute.
    PerMin,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum EndCode {
    M2,
    M30,
}

/// A taper at the start (entry) or end (exit, runout) of a thread pass.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Chamfer {
    /// Length along Z (positive).
    pub length: Length,
    /// Signed X (diameter) distance of the tool from the thread line at the pass's outer end:
    /// where an entry starts, where a runout ends.
    pub offset: Length,
}

/// One spindle-synchronised move: from the current position along the thread line to `to`.
///
/// The thread line runs from the start point (shifted in X by −`entry.offset` when there is
/// an entry) to `to`. The entry leaves the start point and meets the line after
/// `entry.length` of Z travel; the exit leaves the line `exit.length` before `to.z` and ends
/// at `to.x + exit.offset`. [`crate::lower::pass_segments`] gives the moves.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ThreadPass {
    /// End of the thread line (X unknown only for a pure Z pass from an unknown X).
    pub to: Pos,
    /// Advance along Z per spindle revolution.
    pub lead: Length,
    /// Spindle angle after the index pulse at which the motion starts.
    pub start_angle: Angle,
    pub entry: Option<Chamfer>,
    pub exit: Option<Chamfer>,
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ItemKind {
    Rapid {
        to: Pos,
    },
    /// A linear feed move at `feed` (per revolution or per minute, see [`FeedMode`]).
    Feed {
        to: Pos,
        feed: Length,
    },
    ThreadPass(ThreadPass),
    /// Spindle speed (rpm) and/or direction; a direction starts the spindle.
    Spindle {
        speed: Option<u32>,
        direction: Option<SpindleDirection>,
    },
    SpindleStop,
    Tool {
        number: Option<u32>,
        offset: Option<u32>,
    },
    /// A gear/speed range selected by an M code (kept as its number).
    GearRange(u32),
    FeedMode(FeedMode),
    ProgramEnd(EndCode),
    /// A comment on a line of its own.
    Comment(String),
    /// A parameter assignment, kept for targets that can use it (its effect is already
    /// resolved into the other items).
    ParamAssign {
        number: u32,
        value: Decimal,
    },
    /// Source text whose meaning the dialect does not define; only the same dialect can
    /// write it back.
    Opaque {
        dialect: Dialect,
        text: String,
        /// The whole block was kept opaque (`--unsupported warn`): positions after it are
        /// unknown.
        block: bool,
    },
    /// A `%` program delimiter line.
    Delimiter,
}

impl ItemKind {
    /// Where the tool is after this item, starting from `current`.
    pub fn end_position(&self, current: Pos) -> Pos {
        match self {
            ItemKind::Rapid { to } | ItemKind::Feed { to, .. } => Pos {
                x: to.x.or(current.x),
                z: to.z.or(current.z),
            },
            ItemKind::ThreadPass(pass) => {
                let x = pass.to.x.or(current.x);
                Pos {
                    x: match pass.exit {
                        Some(exit) => x.map(|x| x + exit.offset),
                        None => x,
                    },
                    z: pass.to.z.or(current.z),
                }
            }
            ItemKind::Opaque { block: true, .. } => Pos::UNKNOWN,
            _ => current,
        }
    }
}

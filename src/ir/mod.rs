//! The thread-operation IR: one explicit, dialect-free program.
//!
//! Front ends resolve modal state, units, incremental words and parameters, so every item
//! says exactly what the machine does. Lengths are [`Length`] (0.0001 mm, X a diameter),
//! angles [`Angle`] (0.001°).

use crate::fixed::{Angle, Decimal, Lead, Length};
use crate::source::Span;

/// A dialect's id (`czech`, `nc31`, `iso`): what the IR records of where a word came from.
/// The dialects themselves (`crate::dialect`) give out these ids; the IR only compares them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct DialectId(&'static str);

impl DialectId {
    /// A dialect's id: each dialect declares its own (`crate::dialect::czech::ID`). Outside
    /// the crate an id comes from a dialect's `ID` or from parsing a name
    /// (`"fanuc".parse::<DialectId>()`), so that every id names a dialect.
    pub(crate) const fn new(id: &'static str) -> DialectId {
        DialectId(id)
    }

    pub fn as_str(self) -> &'static str {
        self.0
    }
}

impl std::fmt::Display for DialectId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.0)
    }
}

/// A program: items in execution order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Program {
    pub items: Vec<Item>,
    /// The dialect the program was read in: the items' block numbers, the groups of items
    /// that share a source block, and comment lines are that dialect's. A writer of the same
    /// dialect may keep them as they were.
    pub dialect: DialectId,
    /// A file of subroutine definitions and nothing else (a library, as ngcgui and
    /// LinuxCNC's lathe macros ship them): the names it defines. It runs nothing until a
    /// program calls it, so its items are empty; empty for a program. Each with the span
    /// of its definition's first line.
    pub library: Vec<(String, Span)>,
    /// The program's number as the source gives it (FANUC's `O0100`): a writer of the same
    /// dialect keeps it.
    pub number: Option<u32>,
    /// The program's name as the source gives it (SINUMERIK's `%_N_SHAFT_MPF`): a writer of
    /// the same dialect keeps it.
    pub name: Option<String>,
    /// Every length of the program was written in inches (G20): a target that can say
    /// inches writes them in inches (the items hold millimetres, as always).
    pub inch: bool,
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
    pub comment: Option<Box<str>>,
}

impl Item {
    /// An item with no block number and no comment yet.
    pub fn new(kind: ItemKind, span: Span) -> Item {
        Item {
            kind,
            span,
            block_number: None,
            comment: None,
        }
    }
}

/// The modes a kept (opaque) block was written under: they decide what its words mean, so
/// it may stand in the output only where the output is in the same modes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ModalContext {
    /// Lengths in inches (G20).
    pub inch: bool,
    /// X words are diameters (G7, the czech control, the НЦ-31).
    pub diameter: bool,
    /// Coordinates are incremental (G91).
    pub incremental: bool,
    /// Feed per minute (G94), per revolution (G95), or not known.
    pub per_minute: Option<bool>,
    /// The block may move the machine (it has axis words, or a code that moves or whose
    /// meaning is not known): positions after it are unknown. A block that cannot move
    /// (`/G64 P0.01`) leaves the position known.
    pub moves: bool,
    /// The block is a canned cycle (or a move to the machine's reference point) that the
    /// reader read and checked, kept as written because no machine model says its moves: not
    /// an unsupported block kept under `--unsupported warn`.
    pub cycle: bool,
    /// The kept block turns tool nose radius compensation on (a G41/G42 in a cycle's
    /// contour): a target must be able to say compensation to keep it.
    pub compensation: bool,
}

impl ModalContext {
    /// What the output of every writer is in: diameters, absolute coordinates, and
    /// millimetres, or inches (`inch`) for an inch program whose target can say them.
    pub fn differs_from_output(&self, inch: bool) -> Option<&'static str> {
        if self.inch && !inch {
            Some("inches (G20), and the output is in millimetres")
        } else if !self.inch && inch {
            Some("millimetres (G21), and the output is in inches")
        } else if !self.diameter {
            Some("radius mode (X as a radius), and the output writes diameters")
        } else if self.incremental {
            Some("incremental coordinates (G91), and the output's are absolute")
        } else {
            None
        }
    }
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

/// Cutter radius compensation. **\[evidence\]** LinuxCNC's G40–G42.1.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Compensation {
    /// G40
    Off,
    /// G41 / G42 (`right`), with the tool table's entry `D` (default: the tool in use).
    FromTool { right: bool, tool: Option<u32> },
    /// G41.1 / G42.1 (`right`): the tool's diameter `D` (in mm, as every length) and lathe
    /// orientation `L`.
    Dynamic {
        right: bool,
        diameter: crate::fixed::Length,
        orientation: Option<u32>,
    },
}

impl Compensation {
    /// Whether commanding `self` while `in_force` is on switches anything: a G41/G42 repeated
    /// while it is in force is modal and changes nothing (LinuxCNC refuses a second one); a
    /// G40 always counts.
    pub fn switches(self, in_force: Compensation) -> bool {
        self == Compensation::Off || self != in_force
    }
}

/// A move or a setting in machine coordinates.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MachineMove {
    /// G53 with G0 (`feed` None) or G1: to `to` in machine coordinates (X a diameter).
    Machine { to: Pos, feed: Option<Length> },
    /// G28 (or G30 when `second`): a rapid to `via` (the program's coordinates), then to
    /// the stored position, of the axes `via` names (all when it names none).
    Home { second: bool, via: Pos },
    /// G28.1 (or G30.1): store the current position.
    StoreHome { second: bool },
}

/// Spindle speed mode.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SpindleMode {
    /// G97: S is in rpm.
    Rpm,
    /// G96: S is a surface speed in m/min, or in ft/min when `feet` (G96 under G20, as
    /// LinuxCNC and FANUC read it); `limit` the highest rpm (G96's D), if any.
    SurfaceSpeed { limit: Option<Decimal>, feet: bool },
}

/// A coolant command. Mist and flood are separate circuits: M7 and M8 each turn one on,
/// M9 turns both off. **\[evidence\]** LinuxCNC `convert_m`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Coolant {
    /// M7
    Mist,
    /// M8
    Flood,
    /// M9
    Off,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SpindleDirection {
    /// M03
    Clockwise,
    /// M04
    CounterClockwise,
}

impl SpindleDirection {
    /// `M3` or `M4`: how people name it.
    pub fn code(self) -> &'static str {
        match self {
            SpindleDirection::Clockwise => "M3",
            SpindleDirection::CounterClockwise => "M4",
        }
    }
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

/// How a synchronised move starts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SyncStart {
    /// It waits for the spindle's index pulse, then for this angle more (the czech `I`). A
    /// pass that starts where another synchronised move ended waits there, in the cut.
    Index(Angle),
    /// It continues the synchronised move that ended where it starts, without waiting: the
    /// spindle angle runs on (LinuxCNC's consecutive G33 moves).
    Continue,
}

impl SyncStart {
    /// The start angle after the index pulse, or `None` for a continuation.
    pub fn angle(self) -> Option<Angle> {
        match self {
            SyncStart::Index(a) => Some(a),
            SyncStart::Continue => None,
        }
    }
}

impl Default for SyncStart {
    fn default() -> Self {
        SyncStart::Index(Angle::ZERO)
    }
}

/// A synchronised move straight along X before a pass's entry, advancing `advance` along X
/// per spindle revolution (LinuxCNC's G76 with an entry taper feeds in this way from the
/// retract height; a G33 that moves only X is one on its own).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SyncInfeed {
    /// The diameter it moves to, at the start Z.
    pub x: Length,
    /// Advance along X (per side) per spindle revolution.
    pub advance: Lead,
}

/// One spindle-synchronised move: from the current position along the thread line to `to`.
///
/// With an `infeed` the tool first moves synchronised along X to `infeed.x`; the pass's
/// start point is then there. The thread line runs from the start point (shifted in X by
/// −`entry.offset` when there is an entry) to `to`. The entry leaves the start point and
/// meets the line after `entry.length` of Z travel; the exit leaves the line `exit.length`
/// before `to.z` and ends at `to.x + exit.offset`. [`crate::lower::pass_segments`] gives the
/// moves. A pass whose `to` is its start point is only its infeed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ThreadPass {
    /// End of the thread line (X unknown only for a pure Z pass from an unknown X).
    pub to: Pos,
    /// Advance along Z per spindle revolution.
    pub lead: Lead,
    /// Whether it waits for the index pulse (and the angle after it) or continues the
    /// synchronised move before it.
    pub start: SyncStart,
    pub infeed: Option<SyncInfeed>,
    pub entry: Option<Chamfer>,
    pub exit: Option<Chamfer>,
}

impl ThreadPass {
    /// Where the tool is after this pass (its exit chamfer included), starting from `current`.
    pub fn end_position(&self, current: Pos) -> Pos {
        let x = self.to.x.or(current.x);
        Pos {
            x: match self.exit {
                Some(exit) => x.map(|x| x + exit.offset),
                None => x,
            },
            z: self.to.z.or(current.z),
        }
    }
}

/// The tangent of an angle as an exact ratio `rise / run` (e.g. the НЦ-31's parameter 6:
/// `P6 / 4096`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Slope {
    pub rise: i64,
    /// Positive.
    pub run: i64,
}

impl Slope {
    pub const ZERO: Slope = Slope { rise: 0, run: 1 };
    /// The denominator of a slope that stands for the tangent of an angle in degrees.
    const DEGREES_RUN: i64 = 1_000_000_000;

    /// tan(`degrees`) (less than 90° either way) as a ratio over 10⁹, rounded once.
    pub fn of_degrees(degrees: f64) -> Slope {
        Slope {
            rise: (degrees.to_radians().tan() * Self::DEGREES_RUN as f64).round() as i64,
            run: Self::DEGREES_RUN,
        }
    }

    /// Radial (tan 0), whatever the denominator.
    pub fn is_zero(self) -> bool {
        self.rise == 0
    }

    /// `length · rise / run`, rounded once onto the grid.
    pub fn of(self, length: Length) -> Length {
        length.mul_div(self.rise, self.run)
    }

    /// The angle in degrees (for people; the arithmetic uses the ratio).
    pub fn degrees(self) -> f64 {
        (self.rise as f64 / self.run as f64).atan().to_degrees()
    }
}

/// The rule that gives each pass of a [`ThreadCycle`] its cumulative depth.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Schedule {
    /// Passes of the first depth, a remainder pass, then four passes of 1/2, 1/4, 1/8, 1/16
    /// of the first depth (the НЦ-31's G31). **\[seed\]** + **\[decided\]** exact law.
    #[default]
    Halving,
    /// Passes of the first depth; the last pass takes what is left.
    ConstantDepth,
    /// Cumulative depth `first · √n` (equal chip area); the last pass goes to the full depth.
    ConstantArea,
    /// LinuxCNC's G76: cumulative depth `first · n^(1/R)` while it is less than the full
    /// depth, then the full depth.
    Degression(Degression),
    /// Equal chip area in a given number of passes N: cumulative depth `depth · √(n/N)`
    /// (HEIDENHAIN G31 V0 with IC). `first_depth` is the first cut, for people.
    AreaInPasses(u32),
    /// Equal cuts in a given number of passes N: cumulative depth `depth · n/N` (HEIDENHAIN
    /// G31 V1 with IC). `first_depth` is the first cut, for people.
    DepthInPasses(u32),
    /// The remainder of the depth over the first depth first, then passes of the first
    /// depth, the last of them split into 1/2, 1/4, 1/8 and 1/8 (HEIDENHAIN G31 V2).
    /// **\[seed\]** + **\[decided\]** rounding (integer halving, the last eighth takes the
    /// rest).
    RemainderFirst,
}

/// LinuxCNC's G76 depth law with the numbers as the program wrote them, so that the pass
/// count is decided exactly as LinuxCNC's floating-point loop decides it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Degression {
    /// The degression exponent R (values under 1 mean 1).
    pub r: Decimal,
    /// I, J and K as written (program units).
    pub i: Decimal,
    pub j: Decimal,
    pub k: Decimal,
    /// How LinuxCNC turns the written I, J and K into radii.
    pub scale: IjkScale,
    /// Program units are inches (G20).
    pub inch: bool,
}

/// The factor LinuxCNC applies to a G76's written I, J and K to get radii. It halves them when
/// G7 (diameter mode) is in force after the line, and when the line itself changes the mode
/// it first rescales them as it rescales X (G8 on a G7 program: ×2; G7 on a G8 program: ×½),
/// so the factors are ½ (G7), 1 (G8), 2 (G7 then G8 on the line) and ¼ (G8 then G7 on the
/// line). **\[evidence\]** LinuxCNC `convert_lathe_diameter_mode`, `convert_threading_cycle`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum IjkScale {
    Quarter,
    Half,
    One,
    Double,
}

impl IjkScale {
    /// The scale for the diameter mode before the line and after it (true: G7).
    pub fn of_modes(before: bool, after: bool) -> IjkScale {
        match (before, after) {
            (false, false) => IjkScale::One,
            (true, true) => IjkScale::Half,
            (true, false) => IjkScale::Double,
            (false, true) => IjkScale::Quarter,
        }
    }

    /// `v` scaled in floating point as LinuxCNC scales it (exact: powers of two).
    pub fn apply(self, v: f64) -> f64 {
        match self {
            IjkScale::Quarter => v / 4.0,
            IjkScale::Half => v / 2.0,
            IjkScale::One => v,
            IjkScale::Double => v * 2.0,
        }
    }

    /// A length scaled onto the grid.
    pub fn length(self, v: Length) -> Length {
        match self {
            IjkScale::Quarter => v.mul_div(1, 4),
            IjkScale::Half => v.mul_div(1, 2),
            IjkScale::One => v,
            IjkScale::Double => v + v,
        }
    }
}

impl Schedule {
    pub fn id(self) -> &'static str {
        match self {
            Schedule::Halving => "halving",
            Schedule::ConstantDepth => "constant-depth",
            Schedule::ConstantArea => "constant-area",
            Schedule::Degression(_) => "degression",
            Schedule::AreaInPasses(_) => "area-in-passes",
            Schedule::DepthInPasses(_) => "depth-in-passes",
            Schedule::RemainderFirst => "remainder-first",
        }
    }
}

/// How far the tool rises from a pass's line at an entry or runout.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Rise {
    /// To the crest line, whatever the pass's depth (the НЦ-31's runout, parameter 7).
    ToCrest,
    /// By the full thread depth at every pass, so the chamfers of all passes are parallel
    /// (LinuxCNC's G76 E/L).
    ThreadDepth,
}

/// An entry or runout of every pass of a cycle.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct CycleChamfer {
    /// Length along Z (positive).
    pub length: Length,
    pub rise: Rise,
}

/// Where the tool goes between passes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Retract {
    /// Out to a fixed diameter `clearance` per side above the crest (or the start X if that
    /// is further out), back along Z to the start, then in to the next pass (the НЦ-31).
    AboveCrest(Length),
    /// Out to `height` per side above the pass's own line, then straight to the same height
    /// above the next pass's start, then in (LinuxCNC's G76: height = I + K).
    AboveCut(Length),
}

/// Where the tool goes after the last pass.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Finish {
    /// Back to the start point A.
    Start,
    /// Retracted at the end Z, then to this diameter (LinuxCNC's G76 X).
    EndAt(Length),
}

/// A multi-pass thread cycle (the НЦ-31's G31, LinuxCNC's G76). [`crate::lower::expand`]
/// turns it into passes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ThreadCycle {
    /// Where the tool stands when the cycle starts (point A).
    pub start: (Length, Length),
    /// Crest diameter at the start Z (the smaller diameter of a taper thread).
    pub crest: Length,
    /// Z where the last pass ends.
    pub end_z: Length,
    /// Advance along Z per spindle revolution.
    pub lead: Lead,
    /// Total thread depth per side.
    pub depth: Length,
    /// Depth of the first pass per side (the schedule's parameter).
    pub first_depth: Length,
    /// Crest diameter change from the start Z to the end Z (0: a straight thread).
    pub taper: Length,
    /// Infeed direction: tan(angle to the radial). The pass start moves towards the thread
    /// end by cumulative depth · slope.
    pub infeed: Slope,
    /// The pass end moves with the infeed too, so that only the last pass ends at `end_z`
    /// and every pass is the same length (LinuxCNC's G76 Q).
    pub infeed_moves_end: bool,
    /// Spindle angle after the index pulse at which each pass starts.
    pub start_angle: Angle,
    pub entry: Option<CycleChamfer>,
    /// Each pass with an entry first feeds in synchronised along X from the retract height
    /// to the entry's start, at the entry's advance along its path (LinuxCNC's G76 L1/L3).
    pub entry_infeed: bool,
    pub runout: Option<CycleChamfer>,
    pub retract: Retract,
    /// Extra passes at the full depth (LinuxCNC's H).
    pub spring_passes: u32,
    pub finish: Finish,
    /// The tool cuts outward (a bore) instead of inward.
    pub internal: bool,
    pub schedule: Schedule,
}

/// A rigid tapping cycle: synchronised feed to `end_z`, spindle reversal, synchronised feed
/// back to the start Z with the spindle direction restored, then a rapid to `then_x`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct TapCycle {
    pub end_z: Length,
    /// Advance along Z per spindle revolution.
    pub lead: Lead,
    /// Diameter the tool moves to (rapid) after the cycle (the НЦ-31's point C).
    pub then_x: Option<Length>,
}

/// A LinuxCNC lathe roughing or finishing cycle (G70, G71, G71.1, G71.2, G72, G72.1, G72.2):
/// its words, the contour its subroutine traced, and the moves LinuxCNC makes for it.
/// **\[evidence\]** LinuxCNC `interp_g7x.cc`; the moves come from the one implementation,
/// [`crate::lower::g7x`], computed once by the reader from the values as written and rounded
/// onto the grid.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RoughingCycle {
    /// The G code ×10: 700, 710, 711, 712, 720, 721, 722.
    pub code: u16,
    /// The subroutine named by Q (`o100`).
    pub subroutine: String,
    pub kind: RoughingKind,
    /// Where the cycle starts (the block's X and Z, to which it first rapids).
    pub start: Pos,
    /// The contour as the subroutine traced it.
    pub contour: Vec<ContourElement>,
    /// The moves: [`ItemKind::Rapid`], [`ItemKind::Feed`] and [`ItemKind::Arc`] only.
    pub moves: Vec<ItemKind>,
}

impl RoughingCycle {
    /// Its G code as LinuxCNC names it: `G71.1` for 711, `G70` for 700.
    pub fn code_name(&self) -> String {
        g_code_name(i64::from(self.code))
    }
}

/// A block of a canned cycle (FANUC's G70–G76, G90/G94, G28) read under the machine model the
/// profile declares (spec fanuc.md, "Canned cycles under a declared machine model"): its text
/// as written, which its own dialect writes back, and the moves the model gives it, which every
/// other target writes and the simulator runs. A two-block form's first block and a contour's
/// blocks have no moves (the block that runs the cycle has them all).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ModelCycle {
    pub dialect: DialectId,
    /// The block's code as written, without its number and comments.
    pub text: String,
    /// The modes it was read under.
    pub context: ModalContext,
    /// The cycle's G code as written (`G71`; `G73` for the same cycle in G-code system C):
    /// `explain` names it.
    pub code: String,
    /// Its cuts run along X (a facing cycle, G72 or G94): `explain` measures steps along Z.
    pub facing: bool,
    /// The finishing cycle (G70, or G72 in G-code system C): its cuts follow the contour, no
    /// step between them.
    pub finishing: bool,
    /// The moves: [`ItemKind::Rapid`], [`ItemKind::Feed`], [`ItemKind::Arc`] and
    /// [`ItemKind::ThreadPass`] only, and G70's [`ItemKind::Compensation`] switches.
    pub moves: Vec<ItemKind>,
}

/// A G code ×10 (`711`) as it is written (`G71.1`; `G70` for 700).
pub fn g_code_name(code: i64) -> String {
    if code % 10 == 0 {
        format!("G{}", code / 10)
    } else {
        format!("G{}.{}", code / 10, code % 10)
    }
}

/// The words of a roughing or finishing cycle, in mm (LinuxCNC reads them in radius whatever
/// G7/G8 says).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RoughingKind {
    /// G70: `passes` from `first` (D) to `last` (E) distance from the contour.
    Finish {
        first: Length,
        last: Length,
        passes: Decimal,
    },
    /// G71 (along Z) or G72 (`facing`: along X); `variant` 0 cuts pockets too, 1 (`.1`) none,
    /// 2 (`.2`) only the pockets.
    Rough {
        facing: bool,
        variant: u8,
        /// U and W: the stock left in X (radius) and Z.
        stock_x: Length,
        stock_z: Length,
        /// D: the distance left along the contour.
        allowance: Length,
        /// I: the depth of each cut.
        depth: Length,
        /// R: the retract after each cut.
        retract: Length,
    },
}

/// One element of a cycle's contour (X as a diameter).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ContourElement {
    Line {
        to: Pos,
    },
    Arc {
        to: Pos,
        centre: Pos,
        clockwise: bool,
    },
    /// `A`: a rounded corner of this radius.
    Round {
        radius: Length,
    },
    /// `C`: a chamfer of this size.
    Chamfer {
        size: Length,
    },
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
    /// A circular feed move in the ZX plane from the current position to `to` (both axes
    /// known) around `centre` (X as a diameter, like every X in the IR), at `feed`.
    /// `clockwise` is LinuxCNC's G2 in G18: clockwise seen from +Y. Z × X = Y, so from +Y
    /// Z is to the right and X up (a lathe with the tool behind the spindle axis seen from
    /// above, and ncthread's pictures); a lathe with the tool in front, Z to the right and X
    /// down, is seen from −Y, where G2 looks counter-clockwise.
    Arc {
        to: Pos,
        centre: Box<Pos>,
        clockwise: bool,
        feed: Length,
    },
    ThreadPass(Box<ThreadPass>),
    ThreadCycle(Box<ThreadCycle>),
    TapCycle(TapCycle),
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
    /// A gear/speed range selected by an M code: its number, and the machine (dialect) whose
    /// range it is.
    GearRange {
        code: u32,
        machine: DialectId,
    },
    /// An M code whose action the machine's builder (or integrator) defines, and which
    /// moves no axis: a FANUC builder's code the profile names in `still_m_codes` (a chip
    /// conveyor), LinuxCNC's user M100–M199. Its number, and the machine (dialect) whose
    /// code it is.
    MachineCode {
        code: u32,
        machine: DialectId,
    },
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
        dialect: DialectId,
        text: String,
        /// The whole block was kept opaque (`--unsupported warn`), under these modes: it
        /// may move the machine, so positions after it are unknown. `None`: a single word
        /// that moves nothing (`&1100`, `M8`).
        block: Option<ModalContext>,
    },
    /// A `%` program delimiter line.
    Delimiter,
    /// A feed rate that no move of its block uses (an `F` frame of its own): the moves
    /// carry their feeds, this keeps the frame where a program writes it.
    FeedRate(Length),
    /// Coolant on or off (M7, M8, M9).
    Coolant(Coolant),
    /// What the spindle speed (S, in [`ItemKind::Spindle`]) means from here on: rpm (G97),
    /// or a surface speed in m/min that the control holds by turning faster as the tool
    /// moves in, up to a limit in rpm (G96 … D).
    SpindleMode(SpindleMode),
    /// Cutter radius (tool nose) compensation from here on (G40, G41, G42, G41.1, G42.1).
    Compensation(Compensation),
    /// The work offset in force from here on: 1 is G54 (the default), 2 G55 … 6 G59, 7–9
    /// G59.1–G59.3. Its values are the machine's.
    WorkOffset(u8),
    /// A move or a setting in machine coordinates (G53, G28, G30, G28.1, G30.1): where it
    /// leaves the tool in the program's coordinates is the machine's.
    MachineMove(MachineMove),
    /// A programmed stop (M0), or an optional stop (M1) that the operator may skip.
    Stop {
        optional: bool,
    },
    /// A pause with no motion (G4).
    Dwell {
        seconds: Decimal,
    },
    /// A roughing or finishing cycle; every target writes its moves
    /// ([`crate::lower::unroll`]).
    Roughing(Box<RoughingCycle>),
    /// A block of a canned cycle under the profile's declared machine model: kept as written
    /// for its own dialect, its moves for every other target ([`crate::lower::unroll`]).
    ModelCycle(Box<ModelCycle>),
}

/// How a target that cannot say another machine's own M code ([`ItemKind::MachineCode`])
/// names it in the comment it writes instead.
pub fn machine_code_note(code: u32, machine: DialectId) -> String {
    format!("M{code}: the {machine} machine's own M code")
}

impl ItemKind {
    /// A [`ItemKind::ThreadPass`] (the pass is boxed: it is the largest item, and most items
    /// are moves).
    pub fn pass(pass: ThreadPass) -> ItemKind {
        ItemKind::ThreadPass(Box::new(pass))
    }

    /// The moves a roughing cycle or a cycle under a machine model stands for.
    pub fn cycle_moves(&self) -> Option<&[ItemKind]> {
        match self {
            ItemKind::Roughing(cycle) => Some(&cycle.moves),
            ItemKind::ModelCycle(cycle) => Some(&cycle.moves),
            _ => None,
        }
    }

    /// Where the tool is after this item, starting from `current`.
    pub fn end_position(&self, current: Pos) -> Pos {
        if let Some(moves) = self.cycle_moves() {
            return moves.iter().fold(current, |at, m| m.end_position(at));
        }
        match self {
            ItemKind::Rapid { to } | ItemKind::Feed { to, .. } | ItemKind::Arc { to, .. } => Pos {
                x: to.x.or(current.x),
                z: to.z.or(current.z),
            },
            ItemKind::ThreadPass(pass) => pass.end_position(current),
            ItemKind::ThreadCycle(cycle) => match cycle.finish {
                Finish::Start => Pos::new(cycle.start.0, cycle.start.1),
                Finish::EndAt(x) => Pos::new(x, cycle.end_z),
            },
            ItemKind::TapCycle(tap) => Pos {
                x: tap.then_x.or(current.x),
                z: current.z,
            },
            ItemKind::Opaque { block: Some(c), .. } if c.moves => Pos::UNKNOWN,
            // What the machine's coordinates are in the program's is the machine's.
            ItemKind::MachineMove(MachineMove::Machine { to, .. }) => Pos {
                x: if to.x.is_some() { None } else { current.x },
                z: if to.z.is_some() { None } else { current.z },
            },
            ItemKind::MachineMove(MachineMove::Home { via, .. }) => {
                if via == &Pos::UNKNOWN {
                    Pos::UNKNOWN
                } else {
                    Pos {
                        x: if via.x.is_some() { None } else { current.x },
                        z: if via.z.is_some() { None } else { current.z },
                    }
                }
            }
            _ => current,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A program holds an item for about every 15–25 bytes of its text: the item's size is
    /// the reader's memory (issue 19). The large variants are boxed; this keeps them so.
    #[test]
    fn items_stay_small() {
        assert!(size_of::<ItemKind>() <= 64, "{}", size_of::<ItemKind>());
        assert!(size_of::<Item>() <= 112, "{}", size_of::<Item>());
    }
}

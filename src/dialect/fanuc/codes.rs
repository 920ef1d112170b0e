//! FANUC's diagnostic codes, beside the rules that raise them: its reader's
//! (`FANR`) and its writer's (`FANW`). The codes every dialect shares are
//! [`crate::diag::codes`]'s, re-exported here so that a rule names every code as `codes::…`.

pub use crate::diag::codes::*;
use crate::diag::codes::{error, warning};

// reader
pub const FANR_SYNTAX: Code = error("FANR001", "the block cannot be read");
pub const FANR_UNSUPPORTED: Code = error(
    "FANR002",
    "a code or word ncthread does not read in a FANUC program (drilling and tapping cycles, macro calls, the machine builder's M codes…)",
);
pub const FANR_G76: Code = error(
    "FANR003",
    "retired: G76 was refused here; it is now kept as written (FANR018 for its mistakes)",
);
pub const FANR_G92_CHAMFER: Code = error(
    "FANR004",
    "a G92 threading cycle while the profile does not give the machine's thread chamfer ([fanuc] thread_chamfer_0p1_lead)",
);
pub const FANR_STEEP: Code = error(
    "FANR005",
    "a thread move steeper than 45° (X moves more than Z): the unit of its X lead is not confirmed",
);
pub const FANR_NUMBER: Code = error(
    "FANR006",
    "a number that does not fit its word (too large, too precise, or a decimal point where the word takes none)",
);
pub const FANR_UNKNOWN_POSITION: Code =
    error("FANR007", "the move needs a position that is not known yet");
pub const FANR_CONFLICT: Code = error("FANR008", "conflicting or repeated words in one block");
pub const FANR_NO_FEED: Code = error(
    "FANR009",
    "a move without its feed, or a thread without its lead (F last set for the other kind of move)",
);
pub const FANR_TOOL: Code = error(
    "FANR010",
    "a T word that is not a tool and offset number of two digits each (T0101)",
);
pub const FANR_ARC: Code = error(
    "FANR011",
    "an arc that cannot be cut: no centre or radius, a radius too small for its chord, an end off its circle",
);
pub const FANR_CHAIN: Code = error(
    "FANR012",
    "a thread chain ncthread cannot follow: a block between two G32 blocks, or Q on a block that continues the one before",
);
pub const FANR_DECIMAL_POINT: Code = warning(
    "FANR013",
    "words without a decimal point, read as the profile's decimal_point rule says",
);
pub const FANR_AFTER_END: Code = warning(
    "FANR014",
    "blocks after the program's end (M02/M30), which the control does not run",
);
pub const FANR_INCH: Code = error(
    "FANR015",
    "G20/G21 after the first move or a G96: the unit must be set at the program's start",
);

pub const FANR_INCH_ROUNDED: Code = warning(
    "FANR016",
    "inch values finer than 0.0001 in rounded onto the 0.00001 mm grid (0.0001 in is 0.00254 mm, held exactly)",
);

pub const FANR_NOT_RUN: Code = warning(
    "FANR017",
    "a line the control does not run, read as a comment: a title before the program's start, Denford's `[BILLET` stock line",
);

pub const FANR_CYCLE: Code = error(
    "FANR018",
    "a canned cycle written wrongly: a word its form does not take, P or Q naming no block (or two), a contour that does not follow its cycle, holds other than G00–G03 or turns back (type I), a G76 P out of range",
);
pub const FANR_MACRO: Code = error(
    "FANR019",
    "a custom macro B statement or a subprogram call that cannot be run (a GOTO to a missing block, a loop that does not end, calls nested too deep, a subprogram not found, a division by zero…)",
);
pub const FANR_MACHINE_VARIABLE: Code = error(
    "FANR020",
    "a macro variable whose value lives in the machine: a system variable (#1000 and above: signals, offsets, modal information, positions), or #500 … #999 read before the program sets it",
);
pub const FANR_NOT_EXPANDED: Code = warning(
    "FANR021",
    "a canned cycle the profile's machine model covers, kept as written because the model cannot expand it (a layer that misses the contour, an allowance into the part, a type II contour…): another target refuses it",
);

// writer
pub const FANW_PRECISION: Code = error(
    "FANW001",
    "a value needs more decimals than the FANUC program takes (3 for lengths, 4 for leads and feeds)",
);
pub const FANW_NO_EQUIVALENT: Code = error(
    "FANW002",
    "an operation FANUC lathe G-code has no form for that ncthread writes (tapping, G28, cutter compensation without the profile key…)",
);
pub const FANW_STEEP: Code = error(
    "FANW003",
    "a synchronised move steeper than 45° or along X only: the unit of its X lead is not confirmed",
);
pub const FANW_COMMENT: Code = warning(
    "FANW004",
    "a source word with no FANUC equivalent is kept only as a comment",
);
pub const FANW_ROUNDED: Code = warning(
    "FANW005",
    "values rounded to 0.001 mm, leads and feeds to 0.0001 mm (--round)",
);
pub const FANW_TOOL: Code = error(
    "FANW006",
    "a tool or offset number over 99, which the four-digit T word cannot hold",
);
pub const FANW_INDEX_WAIT: Code = error(
    "FANW007",
    "a pass that waits for the index pulse where another thread move ended (consecutive G32 blocks continue)",
);
pub const FANW_TRANSLITERATED: Code = warning(
    "FANW008",
    "comment text transliterated to ASCII (a FANUC comment is upper-case ASCII): accents dropped, other scripts romanised",
);

/// The reader's codes, in the order README.md lists them.
pub const READ: &[Code] = &[
    FANR_SYNTAX,
    FANR_UNSUPPORTED,
    FANR_G76,
    FANR_G92_CHAMFER,
    FANR_STEEP,
    FANR_NUMBER,
    FANR_UNKNOWN_POSITION,
    FANR_CONFLICT,
    FANR_NO_FEED,
    FANR_TOOL,
    FANR_ARC,
    FANR_CHAIN,
    FANR_DECIMAL_POINT,
    FANR_AFTER_END,
    FANR_INCH,
    FANR_INCH_ROUNDED,
    FANR_NOT_RUN,
    FANR_CYCLE,
    FANR_MACRO,
    FANR_MACHINE_VARIABLE,
    FANR_NOT_EXPANDED,
];

/// The writer's codes, in the order README.md lists them.
pub const WRITE: &[Code] = &[
    FANW_PRECISION,
    FANW_NO_EQUIVALENT,
    FANW_STEEP,
    FANW_COMMENT,
    FANW_ROUNDED,
    FANW_TOOL,
    FANW_INDEX_WAIT,
    FANW_TRANSLITERATED,
];

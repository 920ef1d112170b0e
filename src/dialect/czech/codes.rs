//! The czech control's diagnostic codes, beside the rules that raise them: its reader's
//! (`CZR`) and its writer's (`CZW`). The codes every dialect shares are
//! [`crate::diag::codes`]'s, re-exported here so that a rule names every code as `codes::…`.

pub use crate::diag::codes::*;
use crate::diag::codes::{error, warning};

// reader
pub const CZR_SYNTAX: Code = error("CZR001", "the block cannot be read");
pub const CZR_ENTRY_WITHOUT_POINT: Code =
    error("CZR002", "E (entry) written without a decimal point");
pub const CZR_LEAD_TOO_LARGE: Code = error("CZR003", "lead over 99.99 written directly in F");
pub const CZR_NO_CONSTANT8: Code = error(
    "CZR004",
    "J/E used but the profile has no machine constant 8",
);
pub const CZR_ANGLE_PARAM_UNSET: Code = error(
    "CZR005",
    "the runout/entry angle parameter is not assigned before the block",
);
pub const CZR_ANGLE_TOO_LARGE: Code = error("CZR006", "runout/entry angle over 60°");
pub const CZR_BAD_AXIS: Code = error("CZR007", "axis decade of a runout/entry angle is not 1–3");
pub const CZR_FORBIDDEN_PARAM: Code = error("CZR008", "R00 or R80 used as an angle parameter");
pub const CZR_BLOCK_AFTER_RUNOUT: Code =
    error("CZR009", "the block after a J/E thread block is not empty");
pub const CZR_AXES_AFTER_RUNOUT: Code = error(
    "CZR010",
    "the block after the empty block does not program every axis",
);
pub const CZR_UNSUPPORTED: Code = error(
    "CZR011",
    "construct not documented for this control (unsupported)",
);
pub const CZR_NO_LEAD: Code = error(
    "CZR012",
    "G33 block without a lead, or with an ambiguous one",
);
pub const CZR_START_ANGLE_RANGE: Code = error("CZR013", "start angle I outside 0 ≤ I < 360");
pub const CZR_UNKNOWN_POSITION: Code =
    error("CZR014", "the move needs a position that is not known yet");
pub const CZR_NUMBER: Code = error(
    "CZR015",
    "number not representable (too many decimals, too large, or not whole)",
);
pub const CZR_RUNOUT_AXIS: Code = error("CZR016", "runout/entry on an axis other than X");
pub const CZR_THREAD_GEOMETRY: Code = error(
    "CZR017",
    "thread travel cannot hold the runout/entry, or has no Z travel",
);
pub const CZR_PARAM_UNSET: Code = error("CZR018", "parameter used before it is assigned");
pub const CZR_CONFLICT: Code = error("CZR019", "conflicting or repeated words in one block");
pub const CZR_NO_FEED: Code = error(
    "CZR020",
    "feed move without a feed, or with an ambiguous one",
);
pub const CZR_NEGATIVE_LENGTH: Code = error("CZR021", "J/E length must be positive");
pub const CZR_MISSING_BLOCK: Code = error(
    "CZR022",
    "the program ends before the blocks a J/E thread block requires",
);
pub const CZR_AFTER_END: Code = warning(
    "CZR023",
    "blocks after the program's end (M02/M30), which the control does not run",
);
pub const CZR_ARC: Code = error(
    "CZR024",
    "an arc that cannot be cut: no centre or radius, an unknown start, a zero radius, a radius too small for its chord, or an end off its circle",
);

pub const CZR_DWELL: Code = error(
    "CZR025",
    "a dwell (G04) without its time, with a time that is not 0 or more, or with motion in its block",
);

// writer
pub const CZW_PRECISION: Code = error(
    "CZW001",
    "a value needs more decimals than the czech control takes (3 for lengths, 4 for leads)",
);
pub const CZW_NO_EQUIVALENT: Code = error(
    "CZW002",
    "an operation the czech control has no documented form for (tapping cycle, dwell…)",
);
pub const CZW_ANGLE: Code = error(
    "CZW003",
    "an entry or runout the czech control cannot give with machine constant 8",
);
pub const CZW_COMMENT: Code = warning(
    "CZW004",
    "a source word with no czech equivalent is kept only as a comment",
);
pub const CZW_ROUNDED: Code = warning(
    "CZW005",
    "values rounded to 0.001 mm, leads to 0.0001 mm (--round)",
);
pub const CZW_CONTINUE: Code = error(
    "CZW007",
    "a thread move that continues another without the index pulse (every czech G33 block waits for it)",
);

/// The reader's codes, in the order README.md lists them.
pub const READ: &[Code] = &[
    CZR_SYNTAX,
    CZR_ENTRY_WITHOUT_POINT,
    CZR_LEAD_TOO_LARGE,
    CZR_NO_CONSTANT8,
    CZR_ANGLE_PARAM_UNSET,
    CZR_ANGLE_TOO_LARGE,
    CZR_BAD_AXIS,
    CZR_FORBIDDEN_PARAM,
    CZR_BLOCK_AFTER_RUNOUT,
    CZR_AXES_AFTER_RUNOUT,
    CZR_UNSUPPORTED,
    CZR_NO_LEAD,
    CZR_START_ANGLE_RANGE,
    CZR_UNKNOWN_POSITION,
    CZR_NUMBER,
    CZR_RUNOUT_AXIS,
    CZR_THREAD_GEOMETRY,
    CZR_PARAM_UNSET,
    CZR_CONFLICT,
    CZR_NO_FEED,
    CZR_NEGATIVE_LENGTH,
    CZR_MISSING_BLOCK,
    CZR_AFTER_END,
    CZR_ARC,
    CZR_DWELL,
];

/// The writer's codes, in the order README.md lists them.
pub const WRITE: &[Code] = &[
    CZW_PRECISION,
    CZW_NO_EQUIVALENT,
    CZW_ANGLE,
    CZW_COMMENT,
    CZW_ROUNDED,
    CZW_CONTINUE,
];

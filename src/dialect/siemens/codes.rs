//! SINUMERIK's diagnostic codes, beside the rules that raise them: its reader's (`SINR`) and
//! its writer's (`SINW`). The codes every dialect shares are [`crate::diag::codes`]'s,
//! re-exported here so that a rule names every code as `codes::…`.

pub use crate::diag::codes::*;
use crate::diag::codes::{error, warning};

// reader
pub const SINR_SYNTAX: Code = error("SINR001", "the block cannot be read");
pub const SINR_UNSUPPORTED: Code = error(
    "SINR002",
    "a code, word or statement ncthread does not read in a SINUMERIK program (cycles, R parameters and variables, jumps, subprogram calls, chamfer and rounding words, compensation, tapping…)",
);
pub const SINR_NUMBER: Code = error(
    "SINR003",
    "a number that does not fit its word (too large, too precise, or a fraction where a whole number is taken)",
);
pub const SINR_UNKNOWN_POSITION: Code =
    error("SINR004", "the move needs a position that is not known yet");
pub const SINR_CONFLICT: Code = error("SINR005", "conflicting or repeated words in one block");
pub const SINR_MODE_UNKNOWN: Code = error(
    "SINR006",
    "a word whose meaning depends on a machine setting the program has not stated yet: X before DIAMON or DIAMOF, a feed before G94 or G95, a G33 without SF=",
);
pub const SINR_ARC: Code = error(
    "SINR007",
    "an arc that cannot be cut: no centre or radius, a radius too small for its chord, an end off its circle",
);
pub const SINR_THREAD: Code = error(
    "SINR008",
    "a G33 block ncthread does not read: one that continues another G33 block, a lead along X (I), a thread under G96, a taper steeper than 45°",
);
pub const SINR_AFTER_END: Code = warning(
    "SINR009",
    "blocks after the program's end (M30, M2, M17), which the control does not run",
);
pub const SINR_RAMP: Code = warning(
    "SINR010",
    "DITS/DITE: the thread's run-in and run-out ramps change the acceleration, not the path",
);
pub const SINR_NO_MOTION: Code = warning(
    "SINR011",
    "a statement that moves nothing, kept as a comment or left out: MSG (the operator's message, kept as a comment), STOPRE (a stop of the look-ahead)",
);

// writer
pub const SINW_PRECISION: Code = error(
    "SINW001",
    "a value needs more decimals than ncthread writes in a SINUMERIK program (3 for lengths, 4 for leads and feeds, 3 for SF=)",
);
pub const SINW_NO_EQUIVALENT: Code = error(
    "SINW002",
    "an operation the SINUMERIK program ncthread writes has no form for (compensation, tapping, a thread chain, machine coordinates, work offsets past G57…)",
);
pub const SINW_COMMENT: Code = warning(
    "SINW003",
    "a source word with no SINUMERIK equivalent is kept only as a comment",
);
pub const SINW_ROUNDED: Code = warning(
    "SINW004",
    "values rounded to 0.001 mm, leads and feeds to 0.0001 mm (--round)",
);
pub const SINW_TRANSLITERATED: Code = warning(
    "SINW005",
    "comment text transliterated to ASCII: accents dropped, other scripts romanised",
);

/// The reader's codes, in the order README.md lists them.
pub const READ: &[Code] = &[
    SINR_SYNTAX,
    SINR_UNSUPPORTED,
    SINR_NUMBER,
    SINR_UNKNOWN_POSITION,
    SINR_CONFLICT,
    SINR_MODE_UNKNOWN,
    SINR_ARC,
    SINR_THREAD,
    SINR_AFTER_END,
    SINR_RAMP,
    SINR_NO_MOTION,
];

/// The writer's codes, in the order README.md lists them.
pub const WRITE: &[Code] = &[
    SINW_PRECISION,
    SINW_NO_EQUIVALENT,
    SINW_COMMENT,
    SINW_ROUNDED,
    SINW_TRANSLITERATED,
];

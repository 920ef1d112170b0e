//! HEIDENHAIN's diagnostic codes, beside the rules that raise them: its reader's (`HEIR`) and
//! its writer's (`HEIW`). The codes every dialect shares are [`crate::diag::codes`]'s,
//! re-exported here so that a rule names every code as `codes::…`.

pub use crate::diag::codes::*;
use crate::diag::codes::{error, warning};

// reader
pub const HEIR_SYNTAX: Code = error("HEIR001", "the block cannot be read");
pub const HEIR_UNSUPPORTED: Code = error(
    "HEIR002",
    "a code, word or section ncthread does not read in a HEIDENHAIN DIN program (cycles, contours and their sections, subprograms, variables, chamfer and rounding words, compensation…)",
);
pub const HEIR_NUMBER: Code = error(
    "HEIR003",
    "a number that does not fit its word (too large, too precise, or a fraction where a whole number is taken)",
);
pub const HEIR_UNKNOWN_POSITION: Code =
    error("HEIR004", "the move needs a position that is not known yet");
pub const HEIR_CONFLICT: Code = error("HEIR005", "conflicting or repeated words in one block");
pub const HEIR_PROFILE: Code = error(
    "HEIR006",
    "a word whose meaning depends on a machine fact the vendor does not publish and the profile does not declare: an arc's direction (arc_direction), a thread's start angle C (c_sense, b_along), G31's way, infeed and flank offset (g31_clearance, g31_infeed, g31_h1), a feed before G94 or G95",
);
pub const HEIR_ARC: Code = error(
    "HEIR007",
    "an arc that cannot be cut: no centre or radius, a radius too small for its chord, an end off its circle",
);
pub const HEIR_THREAD: Code = error(
    "HEIR008",
    "a G33 block ncthread does not read: one that continues another (P0), a lead along X or the path (H1, H3), a thread under G96",
);
pub const HEIR_AFTER_END: Code = warning(
    "HEIR009",
    "blocks after the program's end (M30, ENDE/END), which the control does not run",
);
pub const HEIR_SECTION: Code = warning(
    "HEIR010",
    "a section that describes and does not move (PROGRAMMKOPF, REVOLVER, ROHTEIL, FERTIGTEIL…) is passed over",
);
pub const HEIR_G31: Code = error(
    "HEIR011",
    "a G31 thread cycle outside what ncthread reads: a contour named by NS/NE or ID, more than one element, a transverse or internal thread, a word whose rule is not published (H3, D, C, K, V3–V6), a missing F, U, B or P, a thread under G96",
);

// writer
pub const HEIW_PRECISION: Code = error(
    "HEIW001",
    "a value needs more decimals than ncthread writes in a HEIDENHAIN program (3 for lengths, 4 for leads and feeds, 3 for C)",
);
pub const HEIW_NO_EQUIVALENT: Code = error(
    "HEIW002",
    "an operation the HEIDENHAIN program ncthread writes has no form for (compensation, tapping, a thread chain, machine coordinates, work offsets…)",
);
pub const HEIW_COMMENT: Code = warning(
    "HEIW003",
    "a source word with no HEIDENHAIN equivalent is kept only as a comment",
);
pub const HEIW_ROUNDED: Code = warning(
    "HEIW004",
    "values rounded to 0.001 mm, leads and feeds to 0.0001 mm (--round)",
);
pub const HEIW_TRANSLITERATED: Code = warning(
    "HEIW005",
    "comment text transliterated to ASCII: accents dropped, other scripts romanised",
);
pub const HEIW_PROFILE: Code = error(
    "HEIW006",
    "a construct whose HEIDENHAIN words depend on a machine fact the vendor does not publish: an arc's direction (`[heidenhain] arc_direction`), a thread's start angle C (`c_sense`, `b_along`)",
);

/// The reader's codes, in the order README.md lists them.
pub const READ: &[Code] = &[
    HEIR_SYNTAX,
    HEIR_UNSUPPORTED,
    HEIR_NUMBER,
    HEIR_UNKNOWN_POSITION,
    HEIR_CONFLICT,
    HEIR_PROFILE,
    HEIR_ARC,
    HEIR_THREAD,
    HEIR_AFTER_END,
    HEIR_SECTION,
    HEIR_G31,
];

/// The writer's codes, in the order README.md lists them.
pub const WRITE: &[Code] = &[
    HEIW_PRECISION,
    HEIW_NO_EQUIVALENT,
    HEIW_COMMENT,
    HEIW_ROUNDED,
    HEIW_TRANSLITERATED,
    HEIW_PROFILE,
];

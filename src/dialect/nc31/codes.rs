//! The НЦ-31's diagnostic codes, beside the rules that raise them: its reader's
//! (`NCR`) and its writer's (`NCW`). The codes every dialect shares are
//! [`crate::diag::codes`]'s, re-exported here so that a rule names every code as `codes::…`.

pub use crate::diag::codes::*;
use crate::diag::codes::{error, warning};

// reader
pub const NCR_SYNTAX: Code = error("NCR001", "the frame cannot be read");
pub const NCR_DECIMAL_POINT: Code = error(
    "NCR002",
    "a word with a decimal point (words are scaled whole numbers)",
);
pub const NCR_TWO_WORDS: Code = error("NCR003", "more than one word in a frame");
pub const NCR_MODIFIER: Code = error("NCR004", "a modifier on a word it does not apply to");
pub const NCR_UNSUPPORTED: Code = error(
    "NCR005",
    "word not documented for this control (unsupported)",
);
pub const NCR_NUMBER: Code = error("NCR006", "number out of range for its word");
pub const NCR_UNKNOWN_POSITION: Code =
    error("NCR007", "the frame needs a position that is not known yet");
pub const NCR_NO_FEED: Code = error(
    "NCR008",
    "feed move while the feed is undefined (at the start, or after a thread group)",
);
pub const NCR_OPEN_GROUP: Code = error(
    "NCR009",
    "a group (`*`) that the program or a `%` line cuts short",
);
pub const NCR_MISSING_WORD: Code = error("NCR010", "a thread group lacks a word it needs");
pub const NCR_GROUP_WORD: Code = error(
    "NCR011",
    "a word that does not belong in this group, or is repeated",
);
pub const NCR_DEPTHS: Code = error(
    "NCR012",
    "G31 depths give no valid pass schedule (P1 too small, P2 not positive, P3 negative)",
);
pub const NCR_LEAD: Code = error("NCR013", "the lead of a thread group is not positive");
pub const NCR_TRAVEL: Code = error(
    "NCR014",
    "a thread has no Z travel, or too little for its runout",
);
pub const NCR_AFTER_END: Code = warning(
    "NCR015",
    "frames after the program's end (M30), which the control does not run",
);
pub const NCR_ARC: Code = error(
    "NCR016",
    "an arc group that cannot be cut: no direction in the profile, no centre on its circle, a centre that is not one, or more than a quadrant",
);
pub const NCR_CHAMFER: Code = error(
    "NCR017",
    "a 45° chamfer group (`X…±45 *` + `F…`) that cannot be cut: not closed by its F frame, no travel, or half its X travel off the 0.0001 mm grid",
);
pub const NCR_REPEAT: Code = error(
    "NCR018",
    "a G25 repeat that cannot be unrolled: a P word missing or out of range, a range that is not whole groups before the G25, a repeat inside the range, a count under 1, or more than 10,000 repeated frames",
);

// writer
pub const NCW_PRECISION: Code = error(
    "NCW001",
    "a value is not a whole number of the НЦ-31's units (0.01 mm for X, Z and P)",
);
pub const NCW_NO_EQUIVALENT: Code = error(
    "NCW002",
    "an operation the НЦ-31 has no documented form for (dwell, feed per minute…)",
);
pub const NCW_PASS: Code = error(
    "NCW003",
    "a thread pass G32 cannot cut (start angle, entry, runout, taper)",
);
pub const NCW_DROPPED: Code = warning(
    "NCW004",
    "a source word with no НЦ-31 equivalent is left out (or kept as a comment)",
);
pub const NCW_ROUNDED: Code = warning("NCW005", "values rounded to the НЦ-31's units (--round)");
pub const NCW_COMMENTS: Code = warning(
    "NCW007",
    "comments left out: the НЦ-31 has none (--nc31-comments keeps them)",
);
pub const NCW_NOTHING: Code = error(
    "NCW008",
    "nothing in the program can be written as НЦ-31 frames (the output would be empty)",
);

/// The reader's codes, in the order README.md lists them.
pub const READ: &[Code] = &[
    NCR_SYNTAX,
    NCR_DECIMAL_POINT,
    NCR_TWO_WORDS,
    NCR_MODIFIER,
    NCR_UNSUPPORTED,
    NCR_NUMBER,
    NCR_UNKNOWN_POSITION,
    NCR_NO_FEED,
    NCR_OPEN_GROUP,
    NCR_MISSING_WORD,
    NCR_GROUP_WORD,
    NCR_DEPTHS,
    NCR_LEAD,
    NCR_TRAVEL,
    NCR_AFTER_END,
    NCR_ARC,
    NCR_CHAMFER,
    NCR_REPEAT,
];

/// The writer's codes, in the order README.md lists them.
pub const WRITE: &[Code] = &[
    NCW_PRECISION,
    NCW_NO_EQUIVALENT,
    NCW_PASS,
    NCW_DROPPED,
    NCW_ROUNDED,
    NCW_COMMENTS,
    NCW_NOTHING,
];

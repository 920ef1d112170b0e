//! LinuxCNC's (ISO) diagnostic codes, beside the rules that raise them: its reader's
//! (`ISOR`) and its writer's (`ISOW`). The codes every dialect shares are
//! [`crate::diag::codes`]'s, re-exported here so that a rule names every code as `codes::…`.

pub use crate::diag::codes::*;
use crate::diag::codes::{error, warning};

// reader
pub const ISOR_SYNTAX: Code = error("ISOR001", "the line cannot be read");
pub const ISOR_UNSUPPORTED: Code = error(
    "ISOR002",
    "construct ncthread does not read (offsets, parameters, other axes…)",
);
pub const ISOR_CONFLICT: Code = error(
    "ISOR003",
    "a word is repeated, or two codes of one modal group share a line",
);
pub const ISOR_WORD: Code = error(
    "ISOR004",
    "a command lacks a word it needs, or a word is used by no command",
);
pub const ISOR_NUMBER: Code = error("ISOR005", "number out of range for its word");
pub const ISOR_UNKNOWN_POSITION: Code =
    error("ISOR006", "the move needs a position that is not known yet");
pub const ISOR_SPINDLE: Code = error(
    "ISOR007",
    "G33, G33.1 or G76 while the spindle is not turning",
);
pub const ISOR_THREAD_GEOMETRY: Code = error(
    "ISOR008",
    "a thread move that does not move, a tap that moves X, or a G33 in the cut after another line",
);
pub const ISOR_G76: Code = error(
    "ISOR009",
    "G76 words that LinuxCNC refuses or that cannot be cut",
);
pub const ISOR_ROUNDED: Code = warning(
    "ISOR010",
    "a value is rounded onto the 0.00001 mm grid (more than five decimals of a millimetre, a computed value)",
);
pub const ISOR_RADIUS_MODE: Code = warning(
    "ISOR011",
    "X read as a radius because neither G7 nor G8 came first (LinuxCNC's default)",
);
pub const ISOR_AFTER_END: Code = warning(
    "ISOR012",
    "lines after the program's end (M2/M30 or the closing %), which LinuxCNC does not run",
);
pub const ISOR_NO_END: Code = warning(
    "ISOR013",
    "the program has no end (M2/M30, or the closing %), which LinuxCNC reports after running it",
);
pub const ISOR_ARC: Code = error(
    "ISOR014",
    "an arc LinuxCNC refuses: no radius or centre, a radius too small for its chord, a zero radius, or an end off its circle",
);
pub const ISOR_COMPENSATION: Code = error(
    "ISOR015",
    "a command LinuxCNC refuses while cutter radius compensation is on (a second G41/G42, a tool change, G28/G30, G76), or a path it cannot compensate with G41.1/G42.1's known radius (a short entry move, a tool larger than an arc, a concave corner that gouges)",
);
pub const ISOR_BLOCK_DELETE: Code = warning(
    "ISOR016",
    "lines that start with `/` are skipped: the block delete switch is on",
);
pub const ISOR_CONTROL: Code = error(
    "ISOR017",
    "O-word blocks that do not match, an unknown subroutine, calls nested too deep, or a loop that does not end",
);
pub const ISOR_EVAL: Code = error(
    "ISOR018",
    "an expression LinuxCNC refuses (division by zero, an undefined parameter, an argument out of range) or a parameter ncthread cannot know",
);
pub const ISOR_ROUGHING: Code = error(
    "ISOR019",
    "a roughing or finishing cycle (G70–G72) LinuxCNC refuses: no Q, a contour that is not monotone, a contour of one move, compensation on, or words its contour cannot hold",
);
pub const ISOR_CONTOUR_IGNORED: Code = warning(
    "ISOR020",
    "words in the contour of a G70–G72 that LinuxCNC does not run there (F, S, M, G codes other than G0–G3)",
);
pub const ISOR_NOT_LATHE: Code = error(
    "ISOR021",
    "not a lathe program: the YZ plane (G19, G17.1…) or an axis other than X and Z (Y, A, B, C, U, V, W), refused in every mode",
);

pub const ISOR_DRILLING: Code = error(
    "ISOR022",
    "a drilling cycle (G73, G81, G82, G83, G85, G89) LinuxCNC refuses (no R or Z on its first block, no P or Q, Q of 0 or less, R below the bottom, L0, no feed), or one in G18, where LinuxCNC drills along Y",
);

// writer
pub const ISOW_OPAQUE: Code = warning("ISOW001", "undocumented source word kept only as a comment");
pub const ISOW_MCODE: Code = warning(
    "ISOW002",
    "M code LinuxCNC does not define, kept only as a comment",
);
pub const ISOW_UNKNOWN_START: Code = error(
    "ISOW003",
    "a move that needs an unknown start point (a thread pass's start angle, entry or runout; an arc's centre)",
);
pub const ISOW_BAD_MAPPING: Code = error(
    "ISOW005",
    "profile M code mapping is not one of LinuxCNC's user M codes (M100–M199)",
);
pub const ISOW_INDEX_WAIT: Code = error(
    "ISOW006",
    "a pass that waits for the index pulse where another thread move ended (LinuxCNC would continue it)",
);
pub const ISOW_INCH_ROUNDED: Code = warning(
    "ISOW007",
    "an inch program's computed values written to 0.000001 in (between two 0.0001 in steps)",
);

/// The reader's codes, in the order README.md lists them.
pub const READ: &[Code] = &[
    ISOR_SYNTAX,
    ISOR_UNSUPPORTED,
    ISOR_CONFLICT,
    ISOR_WORD,
    ISOR_NUMBER,
    ISOR_UNKNOWN_POSITION,
    ISOR_SPINDLE,
    ISOR_THREAD_GEOMETRY,
    ISOR_G76,
    ISOR_ROUNDED,
    ISOR_RADIUS_MODE,
    ISOR_AFTER_END,
    ISOR_NO_END,
    ISOR_ARC,
    ISOR_COMPENSATION,
    ISOR_BLOCK_DELETE,
    ISOR_CONTROL,
    ISOR_EVAL,
    ISOR_ROUGHING,
    ISOR_CONTOUR_IGNORED,
    ISOR_NOT_LATHE,
    ISOR_DRILLING,
];

/// The writer's codes, in the order README.md lists them.
pub const WRITE: &[Code] = &[
    ISOW_OPAQUE,
    ISOW_MCODE,
    ISOW_UNKNOWN_START,
    ISOW_BAD_MAPPING,
    ISOW_INDEX_WAIT,
    ISOW_INCH_ROUNDED,
];

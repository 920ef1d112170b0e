//! Every diagnostic code, in one place so that codes stay unique and stable.
//! README.md lists them; a test checks that it does.

use super::Severity;

/// A stable diagnostic code with its default severity and a one-line summary.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Code {
    pub id: &'static str,
    pub severity: Severity,
    pub summary: &'static str,
}

const fn error(id: &'static str, summary: &'static str) -> Code {
    Code {
        id,
        severity: Severity::Error,
        summary,
    }
}

const fn warning(id: &'static str, summary: &'static str) -> Code {
    Code {
        id,
        severity: Severity::Warning,
        summary,
    }
}

// czech front end
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

// nc31 front end
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

// machine profile
pub const PF_INVALID: Code = error(
    "PF001",
    "the profile cannot be read (syntax, unknown key, wrong type)",
);
pub const PF_CONSTANT8: Code = error("PF002", "machine constant 8 is malformed");
pub const PF_VALUE: Code = error("PF003", "a profile value is out of range or malformed");

// iso front end (RS274/NGC as LinuxCNC reads it)
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
    "a value is rounded onto the 0.0001 mm grid (inches, or more decimals)",
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
pub const ISOR_COMPENSATION: Code = error(
    "ISOR015",
    "a command LinuxCNC refuses while cutter radius compensation is on (a second G41/G42, a tool change, G28/G30, G76)",
);
pub const ISOR_ARC: Code = error(
    "ISOR014",
    "an arc LinuxCNC refuses: no radius or centre, a radius too small for its chord, a zero radius, or an end off its circle",
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

// fanuc front end
pub const FANR_SYNTAX: Code = error("FANR001", "the block cannot be read");
pub const FANR_UNSUPPORTED: Code = error(
    "FANR002",
    "a code or word ncthread does not read in a FANUC program (G90/G94 cycles, G70–G75, G28, G53, tapping…)",
);
pub const FANR_G76: Code = error(
    "FANR003",
    "the G76 threading cycle: its pass placement is not documented in any source ncthread holds",
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
pub const FANR_INCH_ROUNDED: Code = warning(
    "FANR016",
    "inch values rounded onto the 0.0001 mm grid (0.0001 in is 0.00254 mm)",
);
pub const FANR_INCH: Code = error(
    "FANR015",
    "G20/G21 after the first move: the unit must be set at the program's start",
);

// czech target
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

// iso target
pub const ISOW_OPAQUE: Code = warning("ISOW001", "undocumented source word kept only as a comment");
pub const ISOW_MCODE: Code = warning(
    "ISOW002",
    "M code LinuxCNC does not define, kept only as a comment",
);
pub const ISOW_UNKNOWN_START: Code = error(
    "ISOW003",
    "a move that needs an unknown start point (a thread pass's start angle, entry or runout; an arc's centre)",
);
pub const ISOW_BAD_MAPPING: Code = error("ISOW005", "profile M code mapping is not an M word");
pub const ISOW_INDEX_WAIT: Code = error(
    "ISOW006",
    "a pass that waits for the index pulse where another thread move ended (LinuxCNC would continue it)",
);

// fanuc target
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

// nc31 target
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

// output encoding
pub const ENCODING: Code = error(
    "ENC001",
    "a character of the output that the output encoding cannot represent",
);
pub const OTHER_DIALECT: Code = warning(
    "INP002",
    "the program has errors, and reads without errors as another dialect than the one given (--from)",
);
pub const ENCODING_GUESSED: Code = warning(
    "ENC002",
    "a Czech file read as IBM852 (CP852, DOS Latin 2): its bytes are Czech letters there, not in windows-1250",
);
pub const ENCODING_UNKNOWN: Code = error(
    "ENC003",
    "a Czech file that reads cleanly neither as windows-1250 nor as IBM852: its encoding cannot be told",
);
pub const EMPTY_INPUT: Code = error(
    "INP001",
    "the input holds no program (it is empty, or only blank lines): nothing to convert; a warning in `check`",
);
pub const BINARY_INPUT: Code = error(
    "INP003",
    "the input is binary (a NUL byte, or more than 1 % control bytes), not a program's text",
);

// shared by every target (legalise, lower)
pub const SPINDLE_OFF: Code = error("LG001", "thread cut while the spindle is not turning");
pub const FEED_SPINDLE_OFF: Code = error(
    "LG002",
    "feed per revolution while the spindle is not turning (or at no speed)",
);
pub const OPAQUE_MEANING: Code = error(
    "LG003",
    "a block kept as written whose meaning the output would change (another dialect, or other modes)",
);
pub const OUTPUT_UNREADABLE: Code = error(
    "LG004",
    "the output would be refused by ncthread's own reader of the target dialect",
);
pub const LIBRARY: Code = error(
    "LG005",
    "a subroutine library (definitions only) runs nothing until a program calls it: only its own dialect keeps it",
);
pub const CYCLE_INVALID: Code = error(
    "LW001",
    "a thread cycle cannot be expanded into passes (depths, lead, travel)",
);

// simulator
pub const SIM_UNKNOWN: Code = warning(
    "SIM001",
    "the motion depends on a position or spindle state that is not known",
);
pub const SIM_INDEX_WAIT: Code = warning(
    "SIM002",
    "a pass waits for the index pulse with the tool in the cut (where the thread move before it ended)",
);

/// Every code, for documentation and uniqueness checks.
pub const ALL: &[Code] = &[
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
    PF_INVALID,
    PF_CONSTANT8,
    PF_VALUE,
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
    CZW_PRECISION,
    CZW_NO_EQUIVALENT,
    CZW_ANGLE,
    CZW_COMMENT,
    CZW_ROUNDED,
    CZW_CONTINUE,
    ISOW_OPAQUE,
    ISOW_MCODE,
    ISOW_UNKNOWN_START,
    ISOW_BAD_MAPPING,
    ISOW_INDEX_WAIT,
    NCW_PRECISION,
    NCW_NO_EQUIVALENT,
    NCW_PASS,
    NCW_DROPPED,
    NCW_ROUNDED,
    NCW_COMMENTS,
    FANW_PRECISION,
    FANW_NO_EQUIVALENT,
    FANW_STEEP,
    FANW_COMMENT,
    FANW_ROUNDED,
    FANW_TOOL,
    FANW_INDEX_WAIT,
    FANW_TRANSLITERATED,
    NCW_NOTHING,
    ENCODING,
    ENCODING_GUESSED,
    ENCODING_UNKNOWN,
    EMPTY_INPUT,
    BINARY_INPUT,
    OTHER_DIALECT,
    SPINDLE_OFF,
    FEED_SPINDLE_OFF,
    OPAQUE_MEANING,
    OUTPUT_UNREADABLE,
    LIBRARY,
    CYCLE_INVALID,
    SIM_UNKNOWN,
    SIM_INDEX_WAIT,
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_are_unique() {
        let mut ids: Vec<_> = ALL.iter().map(|c| c.id).collect();
        ids.sort();
        let n = ids.len();
        ids.dedup();
        assert_eq!(ids.len(), n);
    }
}

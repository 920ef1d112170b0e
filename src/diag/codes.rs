//! Every diagnostic code, in one place so that codes stay unique and stable.
//! README.md lists them; a test checks that it does.

use super::Severity;

/// A stable diagnostic code with its default severity and a one-line summary.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
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
pub const CZ_SYNTAX: Code = error("CZ001", "the block cannot be read");
pub const CZ_ENTRY_WITHOUT_POINT: Code =
    error("CZ002", "E (entry) written without a decimal point");
pub const CZ_LEAD_TOO_LARGE: Code = error("CZ003", "lead over 99.99 written directly in F");
pub const CZ_NO_CONSTANT8: Code = error(
    "CZ004",
    "J/E used but the profile has no machine constant 8",
);
pub const CZ_ANGLE_PARAM_UNSET: Code = error(
    "CZ005",
    "the runout/entry angle parameter is not assigned before the block",
);
pub const CZ_ANGLE_TOO_LARGE: Code = error("CZ006", "runout/entry angle over 60°");
pub const CZ_BAD_AXIS: Code = error("CZ007", "axis decade of a runout/entry angle is not 1–3");
pub const CZ_FORBIDDEN_PARAM: Code = error("CZ008", "R00 or R80 used as an angle parameter");
pub const CZ_BLOCK_AFTER_RUNOUT: Code =
    error("CZ009", "the block after a J/E thread block is not empty");
pub const CZ_AXES_AFTER_RUNOUT: Code = error(
    "CZ010",
    "the block after the empty block does not program every axis",
);
pub const CZ_UNSUPPORTED: Code = error(
    "CZ011",
    "construct not documented for this control (unsupported)",
);
pub const CZ_NO_LEAD: Code = error(
    "CZ012",
    "G33 block without a lead, or with an ambiguous one",
);
pub const CZ_START_ANGLE_RANGE: Code = error("CZ013", "start angle I outside 0 ≤ I < 360");
pub const CZ_UNKNOWN_POSITION: Code =
    error("CZ014", "the move needs a position that is not known yet");
pub const CZ_NUMBER: Code = error(
    "CZ015",
    "number not representable (too many decimals, too large, or not whole)",
);
pub const CZ_RUNOUT_AXIS: Code = error("CZ016", "runout/entry on an axis other than X");
pub const CZ_THREAD_GEOMETRY: Code = error(
    "CZ017",
    "thread travel cannot hold the runout/entry, or has no Z travel",
);
pub const CZ_PARAM_UNSET: Code = error("CZ018", "parameter used before it is assigned");
pub const CZ_CONFLICT: Code = error("CZ019", "conflicting or repeated words in one block");
pub const CZ_NO_FEED: Code = error(
    "CZ020",
    "feed move without a feed, or with an ambiguous one",
);
pub const CZ_NEGATIVE_LENGTH: Code = error("CZ021", "J/E length must be positive");
pub const CZ_MISSING_BLOCK: Code = error(
    "CZ022",
    "the program ends before the blocks a J/E thread block requires",
);
pub const CZ_AFTER_END: Code = warning(
    "CZ023",
    "blocks after the program's end (M02/M30), which the control does not run",
);

// nc31 front end
pub const NC_SYNTAX: Code = error("NC001", "the frame cannot be read");
pub const NC_DECIMAL_POINT: Code = error(
    "NC002",
    "a word with a decimal point (words are scaled whole numbers)",
);
pub const NC_TWO_WORDS: Code = error("NC003", "more than one word in a frame");
pub const NC_MODIFIER: Code = error("NC004", "a modifier on a word it does not apply to");
pub const NC_UNSUPPORTED: Code = error(
    "NC005",
    "word not documented for this control (unsupported)",
);
pub const NC_NUMBER: Code = error("NC006", "number out of range for its word");
pub const NC_UNKNOWN_POSITION: Code =
    error("NC007", "the frame needs a position that is not known yet");
pub const NC_NO_FEED: Code = error(
    "NC008",
    "feed move while the feed is undefined (at the start, or after a thread group)",
);
pub const NC_OPEN_GROUP: Code = error(
    "NC009",
    "a group (`*`) that the program or a `%` line cuts short",
);
pub const NC_MISSING_WORD: Code = error("NC010", "a thread group lacks a word it needs");
pub const NC_GROUP_WORD: Code = error(
    "NC011",
    "a word that does not belong in this group, or is repeated",
);
pub const NC_DEPTHS: Code = error(
    "NC012",
    "G31 depths give no valid pass schedule (P1 too small, P2 not positive, P3 negative)",
);
pub const NC_LEAD: Code = error("NC013", "the lead of a thread group is not positive");
pub const NC_TRAVEL: Code = error(
    "NC014",
    "a thread has no Z travel, or too little for its runout",
);
pub const NC_AFTER_END: Code = warning(
    "NC015",
    "frames after the program's end (M30), which the control does not run",
);

// machine profile
pub const PF_INVALID: Code = error(
    "PF001",
    "the profile cannot be read (syntax, unknown key, wrong type)",
);
pub const PF_CONSTANT8: Code = error("PF002", "machine constant 8 is malformed");
pub const PF_VALUE: Code = error("PF003", "a profile value is out of range or malformed");

// iso front end (RS274/NGC as LinuxCNC reads it)
pub const NGC_SYNTAX: Code = error("NGC001", "the line cannot be read");
pub const NGC_UNSUPPORTED: Code = error(
    "NGC002",
    "construct ncthread does not read (arcs, offsets, parameters, other axes…)",
);
pub const NGC_CONFLICT: Code = error(
    "NGC003",
    "a word is repeated, or two codes of one modal group share a line",
);
pub const NGC_WORD: Code = error(
    "NGC004",
    "a command lacks a word it needs, or a word is used by no command",
);
pub const NGC_NUMBER: Code = error("NGC005", "number out of range for its word");
pub const NGC_UNKNOWN_POSITION: Code =
    error("NGC006", "the move needs a position that is not known yet");
pub const NGC_SPINDLE: Code = error(
    "NGC007",
    "G33, G33.1 or G76 while the spindle is not turning",
);
pub const NGC_THREAD_GEOMETRY: Code = error(
    "NGC008",
    "a thread move that does not move, a tap that moves X, or a G33 in the cut after another line",
);
pub const NGC_G76: Code = error(
    "NGC009",
    "G76 words that LinuxCNC refuses or that cannot be cut",
);
pub const NGC_ROUNDED: Code = warning(
    "NGC010",
    "a value is rounded onto the 0.0001 mm grid (inches, or more decimals)",
);
pub const NGC_RADIUS_MODE: Code = warning(
    "NGC011",
    "X read as a radius because neither G7 nor G8 came first (LinuxCNC's default)",
);
pub const NGC_AFTER_END: Code = warning(
    "NGC012",
    "lines after the program's end (M2/M30 or the closing %), which LinuxCNC does not run",
);
pub const NGC_NO_END: Code = warning(
    "NGC013",
    "the program has no end (M2/M30, or the closing %), which LinuxCNC reports after running it",
);

// czech target
pub const CZT_PRECISION: Code = error(
    "CZT001",
    "a value needs more decimals than the czech control takes (3 for lengths, 4 for leads)",
);
pub const CZT_NO_EQUIVALENT: Code = error(
    "CZT002",
    "an operation the czech control has no documented form for (tapping cycle, dwell…)",
);
pub const CZT_ANGLE: Code = error(
    "CZT003",
    "an entry or runout the czech control cannot give with machine constant 8",
);
pub const CZT_COMMENT: Code = warning(
    "CZT004",
    "a source word with no czech equivalent is kept only as a comment",
);
pub const CZT_ROUNDED: Code = warning(
    "CZT005",
    "values rounded to 0.001 mm, leads to 0.0001 mm (--round)",
);
pub const CZT_CONTINUE: Code = error(
    "CZT007",
    "a thread move that continues another without the index pulse (every czech G33 block waits for it)",
);

// iso target
pub const ISO_OPAQUE: Code = warning("ISO001", "undocumented source word kept only as a comment");
pub const ISO_MCODE: Code = warning(
    "ISO002",
    "M code LinuxCNC does not define, kept only as a comment",
);
pub const ISO_START_ANGLE: Code = error(
    "ISO003",
    "thread pass whose start angle, entry or runout needs an unknown start point",
);
pub const ISO_BAD_MAPPING: Code = error("ISO005", "profile M code mapping is not an M word");
pub const ISO_INDEX_WAIT: Code = error(
    "ISO006",
    "a pass that waits for the index pulse where another thread move ended (LinuxCNC would continue it)",
);

// nc31 target
pub const NCT_PRECISION: Code = error(
    "NCT001",
    "a value is not a whole number of the НЦ-31's units (0.01 mm for X, Z and P)",
);
pub const NCT_NO_EQUIVALENT: Code = error(
    "NCT002",
    "an operation the НЦ-31 has no documented form for (dwell, feed per minute…)",
);
pub const NCT_PASS: Code = error(
    "NCT003",
    "a thread pass G32 cannot cut (start angle, entry, runout, taper)",
);
pub const NCT_DROPPED: Code = warning(
    "NCT004",
    "a source word with no НЦ-31 equivalent is left out (or kept as a comment)",
);
pub const NCT_ROUNDED: Code = warning("NCT005", "values rounded to the НЦ-31's units (--round)");
pub const NCT_COMMENTS: Code = warning(
    "NCT007",
    "comments left out: the НЦ-31 has none (--nc31-comments keeps them)",
);
pub const NCT_NOTHING: Code = error(
    "NCT008",
    "nothing in the program can be written as НЦ-31 frames (the output would be empty)",
);

// output encoding
pub const ENCODING: Code = error(
    "ENC001",
    "a character of the output that the output encoding cannot represent",
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
    CZ_SYNTAX,
    CZ_ENTRY_WITHOUT_POINT,
    CZ_LEAD_TOO_LARGE,
    CZ_NO_CONSTANT8,
    CZ_ANGLE_PARAM_UNSET,
    CZ_ANGLE_TOO_LARGE,
    CZ_BAD_AXIS,
    CZ_FORBIDDEN_PARAM,
    CZ_BLOCK_AFTER_RUNOUT,
    CZ_AXES_AFTER_RUNOUT,
    CZ_UNSUPPORTED,
    CZ_NO_LEAD,
    CZ_START_ANGLE_RANGE,
    CZ_UNKNOWN_POSITION,
    CZ_NUMBER,
    CZ_RUNOUT_AXIS,
    CZ_THREAD_GEOMETRY,
    CZ_PARAM_UNSET,
    CZ_CONFLICT,
    CZ_NO_FEED,
    CZ_NEGATIVE_LENGTH,
    CZ_MISSING_BLOCK,
    CZ_AFTER_END,
    NC_SYNTAX,
    NC_DECIMAL_POINT,
    NC_TWO_WORDS,
    NC_MODIFIER,
    NC_UNSUPPORTED,
    NC_NUMBER,
    NC_UNKNOWN_POSITION,
    NC_NO_FEED,
    NC_OPEN_GROUP,
    NC_MISSING_WORD,
    NC_GROUP_WORD,
    NC_DEPTHS,
    NC_LEAD,
    NC_TRAVEL,
    NC_AFTER_END,
    PF_INVALID,
    PF_CONSTANT8,
    PF_VALUE,
    NGC_SYNTAX,
    NGC_UNSUPPORTED,
    NGC_CONFLICT,
    NGC_WORD,
    NGC_NUMBER,
    NGC_UNKNOWN_POSITION,
    NGC_SPINDLE,
    NGC_THREAD_GEOMETRY,
    NGC_G76,
    NGC_ROUNDED,
    NGC_RADIUS_MODE,
    NGC_AFTER_END,
    NGC_NO_END,
    CZT_PRECISION,
    CZT_NO_EQUIVALENT,
    CZT_ANGLE,
    CZT_COMMENT,
    CZT_ROUNDED,
    CZT_CONTINUE,
    ISO_OPAQUE,
    ISO_MCODE,
    ISO_START_ANGLE,
    ISO_BAD_MAPPING,
    ISO_INDEX_WAIT,
    NCT_PRECISION,
    NCT_NO_EQUIVALENT,
    NCT_PASS,
    NCT_DROPPED,
    NCT_ROUNDED,
    NCT_COMMENTS,
    NCT_NOTHING,
    ENCODING,
    SPINDLE_OFF,
    FEED_SPINDLE_OFF,
    OPAQUE_MEANING,
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

//! The diagnostic codes every dialect shares (profiles, input and output encoding,
//! legalisation, the simulator), and what a code is. Each dialect's own codes are in its folder
//! (`dialect/<id>/codes.rs`); `dialect::all_codes` lists every code, README.md's table in
//! its order, and a test checks that ids stay unique.

use super::Severity;

/// A stable diagnostic code with its default severity and a one-line summary.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Code {
    pub id: &'static str,
    pub severity: Severity,
    pub summary: &'static str,
}

pub(crate) const fn error(id: &'static str, summary: &'static str) -> Code {
    Code {
        id,
        severity: Severity::Error,
        summary,
    }
}

pub(crate) const fn warning(id: &'static str, summary: &'static str) -> Code {
    Code {
        id,
        severity: Severity::Warning,
        summary,
    }
}

pub const PF_INVALID: Code = error(
    "PF001",
    "the profile cannot be read (syntax, unknown key, wrong type)",
);
pub const PF_CONSTANT8: Code = error("PF002", "machine constant 8 is malformed");
pub const PF_VALUE: Code = error("PF003", "a profile value is out of range or malformed");

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

pub const SIM_UNKNOWN: Code = warning(
    "SIM001",
    "the motion depends on a position or spindle state that is not known",
);
pub const SIM_INDEX_WAIT: Code = warning(
    "SIM002",
    "a pass waits for the index pulse with the tool in the cut (where the thread move before it ended)",
);

/// The profile's codes, in the order README.md lists them.
pub const PROFILE: &[Code] = &[PF_INVALID, PF_CONSTANT8, PF_VALUE];

/// The other shared codes (encodings, input, legalisation, the simulator), in README.md's order.
pub const SHARED: &[Code] = &[
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
    #[test]
    fn codes_are_unique() {
        let mut ids: Vec<_> = crate::dialect::all_codes().iter().map(|c| c.id).collect();
        ids.sort();
        let n = ids.len();
        ids.dedup();
        assert_eq!(ids.len(), n);
    }
}

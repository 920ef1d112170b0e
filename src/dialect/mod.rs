//! The dialects. Each lives in its own folder (front end and/or emitter plus its rules) and
//! meets the others only in the IR.

pub mod czech;
pub mod detect;
pub mod iso;
pub mod nc31;

use std::fmt;

use crate::fixed::{Lead, Length};
use crate::source::Span;

/// A program dialect.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Dialect {
    /// The Czech lathe control (manual chapter 5).
    Czech,
    /// The Электроника НЦ-31 (scaled integer words, `*` groups, G31/G32/G33).
    Nc31,
    /// ISO/RS274-NGC as LinuxCNC reads it.
    Iso,
}

impl Dialect {
    pub const ALL: [Dialect; 3] = [Dialect::Czech, Dialect::Nc31, Dialect::Iso];

    pub fn id(self) -> &'static str {
        match self {
            Dialect::Czech => "czech",
            Dialect::Nc31 => "nc31",
            Dialect::Iso => "iso",
        }
    }
}

impl fmt::Display for Dialect {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.id())
    }
}

/// Where a pest parse of `line` failed, as a byte offset: at the letter when pest stopped
/// after an address letter that has no number (shared by every dialect's syntax layer).
pub(crate) fn pest_error_offset<R: pest::RuleType>(line: &str, e: &pest::error::Error<R>) -> usize {
    let offset = match e.location {
        pest::error::InputLocation::Pos(p) => p,
        pest::error::InputLocation::Span((s, _)) => s,
    };
    let offset = offset.min(line.len());
    if line[..offset]
        .chars()
        .next_back()
        .is_some_and(|c| c.is_ascii_alphabetic())
    {
        offset - 1
    } else {
        offset
    }
}

/// How many problems of one kind a reader reports for one line before it only counts them:
/// a hostile line of 50,000 repeated words gets a few diagnostics and a count.
pub(crate) const WORD_REPORTS: usize = 5;

/// Counts one more problem on the line; true while it should still be reported.
pub(crate) fn budget(count: &mut usize) -> bool {
    *count += 1;
    *count <= WORD_REPORTS
}

/// What a front end does with constructs its dialect's documentation does not define.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Unsupported {
    /// Refuse the program (default).
    #[default]
    Error,
    /// Warn and keep the block as an opaque item (only the same dialect writes it back).
    Warn,
}

/// Values a target cannot hold on its grid, gathered for one diagnostic per program (an
/// error, or with `--round` a warning): how many, the largest deviation, and the first.
#[derive(Debug, Default)]
pub(crate) struct Inexact {
    pub count: usize,
    /// The largest deviation: of a length, its rounding; of a lead, the drift it causes at
    /// the thread's end.
    pub largest: Length,
    /// Where the first is, what it is (`X 26.618 mm`) and the grid it misses (`0.001 mm`).
    pub first: Option<(Span, String, String)>,
}

impl Inexact {
    /// Notes that `what` = `value` at `span` is written as `rounded` on `grid`.
    pub fn note(&mut self, span: Span, what: &str, value: Length, rounded: Length, grid: Length) {
        self.count += 1;
        self.largest = self.largest.max((rounded - value).abs());
        if self.first.is_none() {
            self.first = Some((span, format!("{what} {} mm", value.mm()), grid.mm()));
        }
    }

    /// Notes that the lead `what` = `lead` at `span` is written rounded onto `grid`, so that
    /// the thread drifts by `drift` at its end: that is its deviation.
    pub fn note_lead(&mut self, span: Span, what: &str, lead: Lead, drift: Length, grid: Length) {
        self.count += 1;
        self.largest = self.largest.max(drift);
        if self.first.is_none() {
            self.first = Some((span, format!("{what} {} mm", lead.mm()), grid.mm()));
        }
    }
}

/// A comment's text on one line: control characters (a stray CR, a tab) become spaces.
pub(crate) fn one_line(text: &str) -> String {
    let line: String = text
        .chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect();
    // Readers trim comments: so do the writers, so that an output reads back as it is.
    line.trim().to_string()
}

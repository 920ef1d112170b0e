//! Diagnostics: a stable code, a severity, where (file, line, column, the source line) and a
//! help text. Rendered like rustc's (`error[CZR003]: …`) or as one JSON object per line.

pub mod codes;
pub mod io;

use std::ops::Range;

use annotate_snippets::{AnnotationKind, Group, Level, Renderer, Snippet};
use serde::Serialize;

pub use codes::Code;
pub use io::io_error;

use crate::source::{SourceFile, Span};

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Severity {
    Warning,
    Error,
}

/// Where a diagnostic points: the file, the 1-based line and column, and a copy of the line
/// so that the diagnostic can be printed without the source at hand.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Location {
    pub file: String,
    pub line: u32,
    pub column: u32,
    pub source_line: String,
    /// Byte range of the marked text inside `source_line`.
    pub range: Range<usize>,
}

#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Diagnostic {
    pub code: Code,
    pub severity: Severity,
    pub message: String,
    pub location: Option<Location>,
    /// A short text printed beside the caret.
    pub label: Option<String>,
    pub help: Option<String>,
    /// How far the output may move from the source because of what this reports (the
    /// largest rounding of `--round`): what `verify` then allows.
    pub deviation: Option<crate::fixed::Length>,
    /// How many more diagnostics like this one it stands for: repeats counted and not
    /// listed ([`Fold`]); 0 for one that stands for itself alone.
    pub more: usize,
}

/// The diagnostics reported so far, each once: a repeated one is found by its hash, not by
/// comparing it with every other (a program with 100,000 warnings stays linear).
#[derive(Debug, Default)]
pub(crate) struct Seen(std::collections::HashMap<u64, Vec<usize>>);

impl Seen {
    fn key(d: &Diagnostic) -> u64 {
        use std::hash::{Hash, Hasher};
        let mut h = std::collections::hash_map::DefaultHasher::new();
        d.hash(&mut h);
        h.finish()
    }

    /// Whether `d` is already in `diags`; if not, remembers that it will be at `diags.len()`.
    pub(crate) fn first_time(&mut self, diags: &[Diagnostic], d: &Diagnostic) -> bool {
        if self.has(diags, d) {
            return false;
        }
        self.0.entry(Self::key(d)).or_default().push(diags.len());
        true
    }

    /// Whether `d` is already in `diags`.
    pub(crate) fn has(&self, diags: &[Diagnostic], d: &Diagnostic) -> bool {
        self.0
            .get(&Self::key(d))
            .is_some_and(|at| at.iter().any(|&i| diags.get(i) == Some(d)))
    }
}

/// How many diagnostics of one message a stage lists ([`Fold`]).
pub const LISTED_PER_MESSAGE: u32 = 10;
/// How many diagnostics of one code a stage lists ([`Fold`]).
pub const LISTED_PER_CODE: u32 = 100;

/// The diagnostics a stage lists, and the repeats it counts instead (issue 34: a program of a
/// million lines that changes tools 40,000 times gave 86,000 warnings that two messages say,
/// and held them all). Past [`LISTED_PER_MESSAGE`] of one code and message, or
/// [`LISTED_PER_CODE`] of one code, a diagnostic is counted, and the last one counted is
/// listed at the end, labelled with how many it stands for ([`Fold::finish`]). Nothing is
/// dropped unsaid: every repeat is in a count, and a count's deviation is the largest of
/// those it stands for. What it holds is bounded: a hundred diagnostics' keys per code.
#[derive(Debug, Default)]
pub(crate) struct Fold {
    /// The listed ones, to list each once ([`Fold::admit_once`]).
    seen: Seen,
    per_message: std::collections::HashMap<(&'static str, u64), u32>,
    per_code: std::collections::HashMap<&'static str, u32>,
    /// By code and whether they are errors (a counted error is never stood for by a
    /// warning), in the order first counted.
    counted: indexmap::IndexMap<(&'static str, bool), Counted>,
    errors: usize,
}

/// The repeats of one code a [`Fold`] counted: how many, the first one's line, the last one,
/// and the largest deviation.
#[derive(Debug)]
struct Counted {
    count: usize,
    first_line: Option<u32>,
    last: Diagnostic,
    deviation: Option<crate::fixed::Length>,
}

impl Fold {
    /// Whether `d` is listed; if not, it is counted.
    pub(crate) fn admit(&mut self, d: &Diagnostic) -> bool {
        if self.listed(d) {
            return true;
        }
        self.count(d);
        false
    }

    /// Whether `d` is listed in `listed` (what this fold admitted so far), unless it is
    /// there already; if not, it is counted, unless it is the one counted last.
    pub(crate) fn admit_once(&mut self, listed: &[Diagnostic], d: &Diagnostic) -> bool {
        if !self.under_limits(d) {
            let again = self.seen.has(listed, d)
                || self
                    .counted
                    .get(&(d.code.id, d.is_error()))
                    .is_some_and(|c| c.last == *d);
            if !again {
                self.count(d);
            }
            return false;
        }
        self.seen.first_time(listed, d) && self.listed(d)
    }

    /// The key of `d`'s code and message.
    fn message_key(d: &Diagnostic) -> (&'static str, u64) {
        use std::hash::{Hash, Hasher};
        let mut h = std::collections::hash_map::DefaultHasher::new();
        d.message.hash(&mut h);
        (d.code.id, h.finish())
    }

    /// Whether one more diagnostic like `d` is listed.
    fn under_limits(&self, d: &Diagnostic) -> bool {
        self.per_code.get(d.code.id).copied().unwrap_or(0) < LISTED_PER_CODE
            && self
                .per_message
                .get(&Self::message_key(d))
                .copied()
                .unwrap_or(0)
                < LISTED_PER_MESSAGE
    }

    /// Whether `d` is listed (it is then counted against the limits). Past a code's limit
    /// nothing more of it is remembered, so that what a fold holds is bounded.
    fn listed(&mut self, d: &Diagnostic) -> bool {
        if !self.under_limits(d) {
            return false;
        }
        *self.per_code.entry(d.code.id).or_default() += 1;
        *self.per_message.entry(Self::message_key(d)).or_default() += 1;
        true
    }

    /// Counts `d`, not listed.
    fn count(&mut self, d: &Diagnostic) {
        self.errors += usize::from(d.is_error());
        let key = (d.code.id, d.is_error());
        match self.counted.get_mut(&key) {
            Some(c) => {
                c.count += 1;
                c.last = d.clone();
                c.deviation = c.deviation.max(d.deviation);
            }
            None => {
                self.counted.insert(
                    key,
                    Counted {
                        count: 1,
                        first_line: d.location.as_ref().map(|l| l.line),
                        last: d.clone(),
                        deviation: d.deviation,
                    },
                );
            }
        }
    }

    /// How many errors were counted, not listed.
    pub(crate) fn errors(&self) -> usize {
        self.errors
    }

    /// For each code counted, its last diagnostic, labelled with how many it stands for.
    pub(crate) fn finish(self) -> impl Iterator<Item = Diagnostic> {
        self.counted.into_values().map(|c| {
            let Counted {
                count,
                first_line,
                mut last,
                deviation,
            } = c;
            if count == 1 {
                // Listed as it is: the one it would stand for is itself.
                return last;
            }
            let kind = if last.is_error() { "error" } else { "warning" };
            let from = match (first_line, last.location.as_ref()) {
                (Some(first), Some(l)) if first != l.line => format!(" (from line {first})"),
                _ => String::new(),
            };
            last.label = Some(format!(
                "the last of {count} more {} {kind}s{from}, not listed one by one",
                last.code.id
            ));
            last.deviation = deviation;
            last.more = count - 1;
            last
        })
    }
}

impl Diagnostic {
    pub fn new(code: Code, message: impl Into<String>) -> Diagnostic {
        Diagnostic {
            code,
            severity: code.severity,
            message: message.into(),
            location: None,
            label: None,
            help: None,
            deviation: None,
            more: 0,
        }
    }

    /// How many diagnostics this one stands for: itself and [`Diagnostic::more`].
    pub fn count(&self) -> usize {
        1 + self.more
    }

    /// Points the diagnostic at `span` of `src`. A span running past its line is cut at the
    /// line's end.
    pub fn at(mut self, src: &SourceFile, span: Span) -> Diagnostic {
        let line = src.line(span.line);
        let text = line.text;
        let range = span.range();
        let start =
            text.floor_char_boundary(range.start.saturating_sub(line.offset).min(text.len()));
        let end = text.ceil_char_boundary(
            range
                .end
                .saturating_sub(line.offset)
                .clamp(start, text.len()),
        );
        self.location = Some(Location {
            file: src.name.clone(),
            line: span.line,
            column: span.column,
            source_line: line.text.to_string(),
            range: start..end,
        });
        self
    }

    pub fn label(mut self, label: impl Into<String>) -> Diagnostic {
        self.label = Some(label.into());
        self
    }

    pub fn help(mut self, help: impl Into<String>) -> Diagnostic {
        self.help = Some(help.into());
        self
    }

    /// Lowers an error to a warning (e.g. `--unsupported warn`).
    pub fn as_warning(mut self) -> Diagnostic {
        self.severity = Severity::Warning;
        self
    }

    pub fn is_error(&self) -> bool {
        self.severity == Severity::Error
    }

    /// The rustc-like text form; `color` adds ANSI styles.
    pub fn render(&self, color: bool) -> String {
        let level = match self.severity {
            Severity::Error => Level::ERROR,
            Severity::Warning => Level::WARNING,
        };
        let title = level.primary_title(self.message.as_str()).id(self.code.id);
        let mut group = match &self.location {
            Some(loc) => {
                let mut annotation = AnnotationKind::Primary.span(loc.range.clone());
                if let Some(label) = &self.label {
                    annotation = annotation.label(label.as_str());
                }
                title.element(
                    Snippet::source(loc.source_line.as_str())
                        .line_start(loc.line as usize)
                        .path(loc.file.as_str())
                        .annotation(annotation),
                )
            }
            None => Group::with_title(title),
        };
        if let Some(help) = &self.help {
            group = group.element(Level::HELP.message(help.as_str()));
        }
        let renderer = if color {
            Renderer::styled()
        } else {
            Renderer::plain()
        };
        renderer.render(&[group])
    }

    /// One JSON object (no trailing newline).
    pub fn to_json(&self) -> String {
        self.to_json_value().to_string()
    }

    /// The JSON object of [`Diagnostic::to_json`] as a value (for reports that hold many).
    pub fn to_json_value(&self) -> serde_json::Value {
        #[derive(Serialize)]
        struct Json<'a> {
            code: &'a str,
            severity: Severity,
            message: &'a str,
            file: Option<&'a str>,
            line: Option<u32>,
            column: Option<u32>,
            end_column: Option<u32>,
            source_line: Option<&'a str>,
            label: Option<&'a str>,
            help: Option<&'a str>,
            #[serde(skip_serializing_if = "is_zero")]
            more: usize,
        }
        fn is_zero(n: &usize) -> bool {
            *n == 0
        }
        let loc = self.location.as_ref();
        let end_column =
            loc.map(|l| l.column + l.source_line[l.range.clone()].chars().count() as u32);
        let json = Json {
            code: self.code.id,
            severity: self.severity,
            message: &self.message,
            file: loc.map(|l| l.file.as_str()),
            line: loc.map(|l| l.line),
            column: loc.map(|l| l.column),
            end_column,
            source_line: loc.map(|l| l.source_line.as_str()),
            label: self.label.as_deref(),
            help: self.help.as_deref(),
            more: self.more,
        };
        serde_json::to_value(&json).unwrap_or_default()
    }
}

impl Diagnostic {
    /// The diagnostic [`Diagnostic::to_json_value`] wrote (a report read back by a later
    /// run), or `None` when it is not one: an unknown code, a location that does not fit its
    /// line, a code not in `known` (`dialect::all_codes`). The range is found from the columns
    /// (characters) in the line.
    pub fn from_json_value(v: &serde_json::Value, known: &[Code]) -> Option<Diagnostic> {
        let id = v.get("code")?.as_str()?;
        let code = *known.iter().find(|c| c.id == id)?;
        let severity = match v.get("severity")?.as_str()? {
            "error" => Severity::Error,
            "warning" => Severity::Warning,
            _ => return None,
        };
        let text = |key: &str| v.get(key).and_then(|t| t.as_str()).map(str::to_string);
        let number = |key: &str| {
            v.get(key)
                .and_then(|n| n.as_u64())
                .and_then(|n| u32::try_from(n).ok())
        };
        let location = match (text("file"), number("line"), number("column")) {
            (Some(file), Some(line), Some(column)) => {
                let source_line = text("source_line")?;
                let byte = |column: u32| {
                    let chars = (column as usize).checked_sub(1)?;
                    match source_line.char_indices().nth(chars) {
                        Some((at, _)) => Some(at),
                        None if source_line.chars().count() == chars => Some(source_line.len()),
                        None => None,
                    }
                };
                let start = byte(column)?;
                let end = byte(number("end_column").unwrap_or(column))?.max(start);
                Some(Location {
                    file,
                    line,
                    column,
                    source_line,
                    range: start..end,
                })
            }
            _ => None,
        };
        Some(Diagnostic {
            code,
            severity,
            message: text("message")?,
            location,
            label: text("label"),
            help: text("help"),
            deviation: None,
            more: number("more").map_or(0, |n| n as usize),
        })
    }
}

/// How diagnostics are printed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Format {
    #[default]
    Human,
    Json,
}

/// All diagnostics in one text: human ones separated by blank lines, JSON one per line.
pub fn render_all(diags: &[Diagnostic], format: Format, color: bool) -> String {
    let mut out = String::new();
    for d in diags {
        match format {
            Format::Human => {
                out.push_str(&d.render(color));
                out.push_str("\n\n");
            }
            Format::Json => {
                out.push_str(&d.to_json());
                out.push('\n');
            }
        }
    }
    out
}

/// The diagnostics to print when at most `max_errors` errors of each file are printed (0:
/// every one), as clang's `-ferror-limit`: every warning and the first `max_errors` errors of
/// each file, in their order; and per file (in order of appearance) how many errors were left
/// out.
pub fn cap(diags: &[Diagnostic], max_errors: usize) -> (Vec<&Diagnostic>, Vec<(String, usize)>) {
    fn file(d: &Diagnostic) -> &str {
        d.location.as_ref().map_or("", |l| l.file.as_str())
    }
    let mut shown: std::collections::HashMap<&str, usize> = Default::default();
    let mut hidden: Vec<(String, usize)> = Vec::new();
    let mut kept = Vec::new();
    for d in diags {
        if !d.is_error() || max_errors == 0 {
            kept.push(d);
            continue;
        }
        let count = shown.entry(file(d)).or_default();
        *count += 1;
        if *count <= max_errors {
            kept.push(d);
        } else if let Some((_, n)) = hidden.iter_mut().find(|(f, _)| f == file(d)) {
            *n += d.count();
        } else {
            hidden.push((file(d).to_string(), d.count()));
        }
    }
    (kept, hidden)
}

/// The line that says how many errors of `file` [`cap`] left out.
pub fn more_errors(file: &str, count: usize) -> String {
    let file = if file.is_empty() { "the input" } else { file };
    format!(
        "note: {count} more error{} in {file} not shown (--max-errors 0 shows every one)",
        if count == 1 { "" } else { "s" }
    )
}

/// Orders diagnostics by file position (those without one first); stable otherwise.
pub fn sort(diags: &mut [Diagnostic]) {
    diags.sort_by_key(|d| d.location.as_ref().map(|l| (l.line, l.column)));
}

pub fn has_errors(diags: &[Diagnostic]) -> bool {
    diags.iter().any(Diagnostic::is_error)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A code both kept (a warning) and refused (an error) with one message: past the
    /// limits, the errors counted stay an error of their own, whatever is counted after.
    #[test]
    fn a_counted_error_is_never_stood_for_by_a_warning() {
        let one = |error: bool| {
            let d = Diagnostic::new(codes::ENCODING, "`W1`: not supported");
            if error { d } else { d.as_warning() }
        };
        let mut fold = Fold::default();
        for _ in 0..LISTED_PER_MESSAGE {
            assert!(fold.admit(&one(false)));
        }
        assert!(!fold.admit(&one(true)));
        assert!(!fold.admit(&one(false)));
        assert_eq!(fold.errors(), 1);
        let counted: Vec<Diagnostic> = fold.finish().collect();
        assert_eq!(counted.len(), 2, "{counted:#?}");
        assert!(counted.iter().any(Diagnostic::is_error), "{counted:#?}");
    }

    #[test]
    fn repeats_past_what_is_listed_are_counted_in_the_last_one() {
        let src = SourceFile::new("t", "X\n".repeat(300));
        let at = |line: u32| src.span_in_line(src.line(line), 0..1);
        let mut fold = Fold::default();
        let mut listed = Vec::new();
        // One message 150 times, then 120 distinct messages of the same code.
        for line in 1..=150 {
            let d = Diagnostic::new(codes::SIM_UNKNOWN, "same").at(&src, at(line));
            if fold.admit(&d) {
                listed.push(line);
            }
        }
        assert_eq!(listed, (1..=LISTED_PER_MESSAGE).collect::<Vec<_>>());
        for n in 0..120u32 {
            let mut d =
                Diagnostic::new(codes::SIM_UNKNOWN, format!("other {n}")).at(&src, at(151 + n));
            d.deviation = Some(crate::fixed::Length(i64::from(n % 7)));
            if fold.admit(&d) {
                listed.push(151 + n);
            }
        }
        let per_code = LISTED_PER_CODE - LISTED_PER_MESSAGE;
        assert_eq!(listed.len() as u32, LISTED_PER_CODE);
        assert_eq!(listed.last(), Some(&(150 + per_code)));
        assert_eq!(fold.errors(), 0);
        let counted: Vec<Diagnostic> = fold.finish().collect();
        assert_eq!(counted.len(), 1);
        let total = 150 + 120 - LISTED_PER_CODE as usize;
        assert_eq!(counted[0].message, "other 119");
        assert_eq!(counted[0].location.as_ref().map(|l| l.line), Some(270));
        assert_eq!(
            counted[0].label.as_deref(),
            Some(
                format!(
                    "the last of {total} more SIM001 warnings (from line {}), not listed one by one",
                    LISTED_PER_MESSAGE + 1
                )
                .as_str()
            )
        );
        // The largest deviation of those counted, for `verify`.
        assert_eq!(counted[0].deviation, Some(crate::fixed::Length(6)));
        // Counts (check's, batch's) count every one; JSON says how many more.
        assert_eq!(counted[0].count(), total);
        let json = counted[0].to_json_value();
        assert_eq!(json["more"], total - 1);
        let back = Diagnostic::from_json_value(&json, &[codes::SIM_UNKNOWN]).unwrap();
        assert_eq!(back.more, total - 1);
        assert!(
            Diagnostic::new(codes::SIM_UNKNOWN, "x").to_json_value()["more"].is_null(),
            "a diagnostic that stands for itself alone does not say it"
        );
    }

    #[test]
    fn a_fold_lists_each_once_counts_each_once_and_holds_a_bounded_table() {
        let src = SourceFile::new("t", "X\n".repeat(3));
        let at = src.span_in_line(src.line(2), 0..1);
        let mut fold = Fold::default();
        let mut listed: Vec<Diagnostic> = Vec::new();
        // Every diagnostic twice in a row (a cycle's passes share its span): once each.
        for n in 0..10_000 {
            let d = Diagnostic::new(codes::PF_VALUE, format!("block {n}")).at(&src, at);
            for _ in 0..2 {
                if fold.admit_once(&listed, &d) {
                    listed.push(d.clone());
                }
            }
        }
        assert_eq!(listed.len(), LISTED_PER_CODE as usize);
        assert_eq!(fold.errors(), 10_000 - LISTED_PER_CODE as usize);
        // Distinct messages past the code's limit leave nothing behind.
        assert_eq!(fold.per_message.len(), LISTED_PER_CODE as usize);
        let counted: Vec<Diagnostic> = fold.finish().collect();
        assert_eq!(counted[0].count(), 10_000 - LISTED_PER_CODE as usize);
        assert_eq!(counted[0].message, "block 9999");
    }

    #[test]
    fn one_repeat_past_the_list_is_listed_as_it_is_and_errors_are_counted() {
        let mut fold = Fold::default();
        let d = Diagnostic::new(codes::PF_VALUE, "bad").label("here");
        for _ in 0..=LISTED_PER_MESSAGE {
            fold.admit(&d);
        }
        assert_eq!(fold.errors(), 1);
        let counted: Vec<Diagnostic> = fold.finish().collect();
        assert_eq!(counted, [d]);
    }

    #[test]
    fn renders_like_rustc() {
        let src = SourceFile::new("ex6.nc", "N10 M04\nN30 Z3 F6.0 E12 G33\n");
        let line = src.line(2);
        let span = src.span_in_line(line, 12..15);
        let d = Diagnostic::new(
            crate::dialect::czech::codes::CZR_ENTRY_WITHOUT_POINT,
            "entry length written without a decimal point",
        )
        .at(&src, span)
        .label("needs a decimal point")
        .help("write `E12.`");
        let text = d.render(false);
        assert!(
            text.starts_with("error[CZR002]: entry length written without a decimal point"),
            "{text}"
        );
        assert!(text.contains("--> ex6.nc:2:13"), "{text}");
        assert!(text.contains("2 | N30 Z3 F6.0 E12 G33"), "{text}");
        assert!(text.contains("^^^ needs a decimal point"), "{text}");
        assert!(text.contains("help: write `E12.`"), "{text}");
    }

    #[test]
    fn errors_are_capped_per_file_and_counted() {
        let at = |file: &str, line: u32, code| {
            let src = SourceFile::new(file, "N10\nN20\nN30\nN40\n");
            let span = src.span_in_line(src.line(line), 0..3);
            Diagnostic::new(code, "x").at(&src, span)
        };
        let diags = vec![
            at("a.nc", 1, crate::dialect::czech::codes::CZR_SYNTAX),
            at("a.nc", 2, crate::dialect::czech::codes::CZR_AFTER_END),
            at("a.nc", 3, crate::dialect::czech::codes::CZR_SYNTAX),
            at("b.nc", 1, crate::dialect::czech::codes::CZR_SYNTAX),
            at("a.nc", 4, crate::dialect::czech::codes::CZR_SYNTAX),
        ];
        let (kept, hidden) = cap(&diags, 1);
        let lines: Vec<(&str, u32)> = kept
            .iter()
            .map(|d| {
                let l = d.location.as_ref().unwrap();
                (l.file.as_str(), l.line)
            })
            .collect();
        // The warning stays; one error per file.
        assert_eq!(lines, [("a.nc", 1), ("a.nc", 2), ("b.nc", 1)]);
        assert_eq!(hidden, [("a.nc".to_string(), 2)]);
        assert_eq!(
            more_errors("a.nc", 2),
            "note: 2 more errors in a.nc not shown (--max-errors 0 shows every one)"
        );
        let (kept, hidden) = cap(&diags, 0);
        assert_eq!((kept.len(), hidden.len()), (5, 0));
    }

    #[test]
    fn json_reads_back_as_it_was_written() {
        let src = SourceFile::new("č.nc", "N10 \"Č\" F120.\n");
        let span = src.span_in_line(src.line(1), 10..15);
        let d = Diagnostic::new(
            crate::dialect::czech::codes::CZR_LEAD_TOO_LARGE,
            "lead too large",
        )
        .at(&src, span)
        .label("here")
        .help("write FR")
        .as_warning();
        let back =
            Diagnostic::from_json_value(&d.to_json_value(), crate::dialect::all_codes()).unwrap();
        assert_eq!(back, d);
        assert_eq!(back.render(false), d.render(false));
        let plain = Diagnostic::new(codes::EMPTY_INPUT, "empty");
        assert_eq!(
            Diagnostic::from_json_value(&plain.to_json_value(), crate::dialect::all_codes()),
            Some(plain)
        );
        let unknown = serde_json::json!({"code": "XX999", "severity": "error", "message": "?"});
        assert_eq!(
            Diagnostic::from_json_value(&unknown, crate::dialect::all_codes()),
            None
        );
    }

    #[test]
    fn json_names_every_field() {
        let src = SourceFile::new("a.nc", "N10 F120.\n");
        let span = src.span_in_line(src.line(1), 4..9);
        let d = Diagnostic::new(
            crate::dialect::czech::codes::CZR_LEAD_TOO_LARGE,
            "lead too large",
        )
        .at(&src, span);
        let v: serde_json::Value = serde_json::from_str(&d.to_json()).unwrap();
        assert_eq!(v["code"], "CZR003");
        assert_eq!(v["severity"], "error");
        assert_eq!(v["line"], 1);
        assert_eq!(v["column"], 5);
        assert_eq!(v["end_column"], 10);
        assert_eq!(v["source_line"], "N10 F120.");
    }
}

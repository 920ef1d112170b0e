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
}

/// The diagnostics reported so far, each once: a repeated one is found by its hash, not by
/// comparing it with every other (a program with 100,000 warnings stays linear).
#[derive(Debug, Default)]
pub(crate) struct Seen(std::collections::HashMap<u64, Vec<usize>>);

impl Seen {
    /// Whether `d` is already in `diags`; if not, remembers that it will be at `diags.len()`.
    pub(crate) fn first_time(&mut self, diags: &[Diagnostic], d: &Diagnostic) -> bool {
        use std::hash::{Hash, Hasher};
        let mut h = std::collections::hash_map::DefaultHasher::new();
        d.hash(&mut h);
        let at = self.0.entry(h.finish()).or_default();
        if at.iter().any(|&i| diags.get(i) == Some(d)) {
            return false;
        }
        at.push(diags.len());
        true
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
        }
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
            *n += 1;
        } else {
            hidden.push((file(d).to_string(), 1));
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

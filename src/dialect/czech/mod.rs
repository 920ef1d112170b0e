//! Dialect `czech`: the Czech lathe control of manual chapter 5 (G33 with F, I, J, E,
//! R-parameter angles, `FRnn`).

mod emit;
mod front;
pub mod syntax;

pub use front::Options;

use super::{Dialect, DialectId, LineClaim, LineMark, Unsupported, WriteOptions, detect};
use crate::diag::Diagnostic;
use crate::ir::Program;
use crate::profile::Profile;
use crate::source::SourceFile;
use crate::text::TextEncoding;

/// The czech control's id.
pub const ID: DialectId = DialectId::new("czech");

/// The czech control.
pub struct Czech;

impl Dialect for Czech {
    fn id(&self) -> DialectId {
        ID
    }

    fn title(&self) -> &'static str {
        "the czech control"
    }

    fn extension(&self) -> &'static str {
        "ncp"
    }

    fn legacy_encoding(&self) -> TextEncoding {
        TextEncoding::Standard(encoding_rs::WINDOWS_1250)
    }

    fn claim_line(&self, line: &str) -> Option<LineClaim> {
        // A `"` comment, and R<nn>= assignments, FRnn and & words.
        if line.contains(['"', '“', '„']) {
            return Some(LineClaim {
                priority: 100,
                mark: LineMark::Mark,
            });
        }
        detect::code_words(line)
            .iter()
            .any(|w| {
                (w.starts_with('R') && w.contains('=')) || w.starts_with('&') || w.starts_with("FR")
            })
            .then_some(LineClaim {
                priority: 70,
                mark: LineMark::Mark,
            })
    }

    fn mark_description(&self) -> &'static str {
        "a czech mark (a `\"` comment, `R<nn>=`, `FR<nn>` or `&`)"
    }

    fn fallback_reason(&self) -> Option<&'static str> {
        Some(
            "no dialect's marks (НЦ-31 `*`/`~`/`@`, czech `\"` comments or R/FR/& words, ISO `( )` comments or G33 … K); decimal words read as czech",
        )
    }

    fn tie_rank(&self) -> u8 {
        2
    }

    fn read(
        &self,
        src: &SourceFile,
        profile: &Profile,
        unsupported: Unsupported,
    ) -> (Program, Vec<Diagnostic>) {
        front::parse(src, profile, &Options { unsupported })
    }

    fn write(
        &self,
        program: &Program,
        src: &SourceFile,
        profile: &Profile,
        options: &WriteOptions,
    ) -> (Option<String>, Vec<Diagnostic>) {
        emit::emit(program, src, profile, options.renumber, options.round)
    }
}

//! Dialect `iso`: RS274/NGC as LinuxCNC reads it. A target checked against LinuxCNC's
//! `rs274`, and a source (hand conversions to check, CAM programs to move to old machines).

mod emit;
mod front;
mod syntax;

pub use front::Options;

use super::{Dialect, DialectId, LineClaim, LineMark, Unsupported, WriteOptions, detect};
use crate::diag::Diagnostic;
use crate::ir::Program;
use crate::profile::Profile;
use crate::source::SourceFile;
use crate::text::TextEncoding;

/// ISO G-code's id.
pub const ID: DialectId = DialectId::new("iso");

/// RS274/NGC as LinuxCNC reads it.
pub struct Iso;

impl Dialect for Iso {
    fn id(&self) -> DialectId {
        ID
    }

    fn title(&self) -> &'static str {
        "LinuxCNC (RS274/NGC)"
    }

    fn extension(&self) -> &'static str {
        "ngc"
    }

    fn legacy_encoding(&self) -> TextEncoding {
        TextEncoding::Standard(encoding_rs::WINDOWS_1252)
    }

    fn claim_line(&self, line: &str) -> Option<LineClaim> {
        if line.starts_with('(') {
            return Some(LineClaim {
                priority: 95,
                mark: LineMark::Neutral,
            });
        }
        // A `( )` or `;` comment after code.
        if detect::code_part(line).len() < line.len() {
            return Some(LineClaim {
                priority: 90,
                mark: LineMark::Mark,
            });
        }
        let words = detect::code_words(line);
        let g33_with_k =
            words.iter().any(|w| w == "G33") && words.iter().any(|w| w.starts_with('K'));
        let iso_word = g33_with_k
            || words.iter().any(|w| {
                matches!(
                    w.as_str(),
                    "G7" | "G8" | "G18" | "G21" | "G20" | "G33.1" | "G76" | "G64" | "M6" | "G43"
                )
            });
        iso_word.then_some(LineClaim {
            priority: 60,
            mark: LineMark::Mark,
        })
    }

    fn mark_description(&self) -> &'static str {
        "an ISO mark (a `( )` or `;` comment after code, G33 with K, or a G7/G18/G21/G33.1/G76 word)"
    }

    fn tie_rank(&self) -> u8 {
        1
    }

    fn linuxcnc_reads(&self) -> bool {
        true
    }

    fn output_feed_mode(&self) -> Option<crate::ir::FeedMode> {
        // The header: `G7 G18 G21 G90 G95`.
        Some(crate::ir::FeedMode::PerRev)
    }

    fn read(
        &self,
        src: &SourceFile,
        _profile: &Profile,
        unsupported: Unsupported,
    ) -> (Program, Vec<Diagnostic>) {
        front::parse(src, &Options { unsupported })
    }

    fn write(
        &self,
        program: &Program,
        src: &SourceFile,
        profile: &Profile,
        _options: &WriteOptions,
    ) -> (Option<String>, Vec<Diagnostic>) {
        emit::emit(program, src, profile)
    }
}

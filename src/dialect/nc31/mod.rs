//! Dialect `nc31`: the Электроника НЦ-31 (scaled integer words, one word per frame, `*`
//! groups, `~` rapid, `@` incremental, G31 multi-pass cycle, G32 single pass, G33 tapping).

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

/// The НЦ-31's id.
pub const ID: DialectId = DialectId::new("nc31");

/// The Электроника НЦ-31.
pub struct Nc31;

impl Dialect for Nc31 {
    fn id(&self) -> DialectId {
        ID
    }

    fn title(&self) -> &'static str {
        "the НЦ-31"
    }

    fn extension(&self) -> &'static str {
        "nc31"
    }

    fn legacy_encoding(&self) -> TextEncoding {
        TextEncoding::Standard(encoding_rs::IBM866)
    }

    fn claim_line(&self, line: &str) -> Option<LineClaim> {
        // A comment line: PC archives of the НЦ-31 and ISO programs both have them.
        if line.starts_with('(') {
            return Some(LineClaim {
                priority: 95,
                mark: LineMark::Neutral,
            });
        }
        let words = detect::code_words(line);
        let modifiers = detect::code_part(line)
            .chars()
            .any(detect::is_nc31_modifier);
        let integer = |w: &String| {
            w.len() > 1
                && w[1..]
                    .trim_start_matches(['+', '-'])
                    .bytes()
                    .all(|b| b.is_ascii_digit())
        };
        if words.len() == 1 && integer(&words[0]) {
            return Some(LineClaim {
                priority: 80,
                mark: if modifiers {
                    LineMark::Mark
                } else {
                    LineMark::Weak
                },
            });
        }
        modifiers.then_some(LineClaim {
            priority: 50,
            mark: LineMark::Mark,
        })
    }

    fn mark_description(&self) -> &'static str {
        "a frame with the НЦ-31's `*`/`~`/`@` modifiers"
    }

    fn weak_reason(&self) -> Option<&'static str> {
        Some(
            "every frame is one whole-number word, as on the НЦ-31, but no `*`, `~` or `@` confirms it",
        )
    }

    fn plain_lines_contradict(&self) -> bool {
        true
    }

    fn tie_rank(&self) -> u8 {
        3
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
        emit::emit(program, src, profile, options)
    }
}

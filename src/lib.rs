//! ncthread: lathe thread-cutting programs between the czech control, the НЦ-31 and ISO
//! G-code, through one thread-operation IR. Exact or refused.
//!
//! The stages are public functions: [`parse`] (text → [`ir::Program`]), [`emit`]
//! (program → text), and [`convert`] (both). Every problem is a [`diag::Diagnostic`].

pub mod diag;
pub mod dialect;
pub mod fixed;
pub mod ir;
pub mod lower;
pub mod profile;
pub mod sim;
pub mod source;
pub mod text;

use diag::{Diagnostic, codes};
pub use dialect::{Dialect, Unsupported};
use ir::Program;
use profile::Profile;
use source::SourceFile;

/// Everything a conversion needs besides the source.
#[derive(Clone, Debug)]
pub struct ConvertOptions {
    pub from: Dialect,
    pub to: Dialect,
    pub profile: Profile,
    pub unsupported: Unsupported,
}

/// The result of a conversion: the program text when there was no error, and every
/// diagnostic (warnings too).
#[derive(Clone, Debug)]
pub struct Conversion {
    pub output: Option<String>,
    pub diagnostics: Vec<Diagnostic>,
}

/// Reads `src` in dialect `from`. The program is usable only when no diagnostic is an error.
pub fn parse(
    src: &SourceFile,
    from: Dialect,
    profile: &Profile,
    unsupported: Unsupported,
) -> (Program, Vec<Diagnostic>) {
    match from {
        Dialect::Czech => {
            dialect::czech::parse(src, profile, &dialect::czech::Options { unsupported })
        }
        Dialect::Nc31 => {
            dialect::nc31::parse(src, profile, &dialect::nc31::Options { unsupported })
        }
        Dialect::Iso => (
            Program::default(),
            vec![not_yet(&format!("reading dialect {from}"))],
        ),
    }
}

/// Writes `program` (read from `src` in dialect `from`) in dialect `to`.
pub fn emit(
    program: &Program,
    src: &SourceFile,
    from: Dialect,
    to: Dialect,
    profile: &Profile,
) -> (Option<String>, Vec<Diagnostic>) {
    match to {
        Dialect::Iso => dialect::iso::emit(program, src, from, profile),
        Dialect::Czech | Dialect::Nc31 => (None, vec![not_yet(&format!("writing dialect {to}"))]),
    }
}

fn not_yet(what: &str) -> Diagnostic {
    Diagnostic::new(
        codes::NOT_IMPLEMENTED,
        format!("{what} is not implemented in this version"),
    )
}

/// Parses and emits. Refuses (no output) when any error remains.
pub fn convert(src: &SourceFile, options: &ConvertOptions) -> Conversion {
    let (program, mut diagnostics) =
        parse(src, options.from, &options.profile, options.unsupported);
    if diag::has_errors(&diagnostics) {
        diag::sort(&mut diagnostics);
        return Conversion {
            output: None,
            diagnostics,
        };
    }
    let (output, more) = emit(&program, src, options.from, options.to, &options.profile);
    diagnostics.extend(more);
    diag::sort(&mut diagnostics);
    Conversion {
        output,
        diagnostics,
    }
}

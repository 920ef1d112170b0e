//! What a dialect's profile section reads its values with: numbers as TOML gives them, and
//! the one wording of a bad value. (A leaf: the sections live in `dialect/<id>/profile.rs`,
//! and [`super::Profile`] gathers them.)

use serde::Deserialize;

use crate::diag::{Diagnostic, codes};
use crate::fixed::Length;
use crate::source::{SourceFile, Span};

/// A number as TOML writes it.
#[derive(Deserialize, Clone, Copy)]
#[serde(untagged)]
pub(crate) enum RawNumber {
    Int(i64),
    Float(f64),
}

impl RawNumber {
    /// The value as a length on the 0.0001 mm grid, if it lies on it.
    pub(crate) fn length(self) -> Option<Length> {
        match self {
            RawNumber::Int(i) => i.checked_mul(Length::PER_MM).map(Length),
            RawNumber::Float(f) => {
                let steps = f * 10_000.0;
                (steps.is_finite() && steps.abs() < 1e15 && (steps - steps.round()).abs() < 1e-6)
                    .then(|| Length::from_steps(steps.round() as i64))
            }
        }
    }
}

/// A value of `key` the section cannot use: PF… with the key, at its place.
pub(crate) fn bad_value(
    src: &SourceFile,
    span: Span,
    key: &str,
    message: String,
    help: &str,
) -> Diagnostic {
    Diagnostic::new(codes::PF_VALUE, format!("profile key `{key}`: {message}"))
        .at(src, span)
        .help(help.to_string())
}

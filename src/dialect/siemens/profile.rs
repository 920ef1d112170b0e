//! SINUMERIK's section of the machine profile (`[siemens]`): the states a program may rely
//! on without stating them, which the machine data sets at reset (`$MC_GCODE_RESET_VALUES`,
//! `$MC_DIAMETER_AX_DEF`) and no manual can know for a given machine.
//!
//! ```toml
//! [siemens]
//! initial_diameter = "DIAMOF"   # X is a radius until the program says DIAMON ("DIAMON": a diameter)
//! initial_feed_mode = "G95"     # F is per revolution until the program says G94 ("G94": per minute)
//! ```

use serde::Deserialize;

use crate::diag::Diagnostic;
use crate::profile::value::bad_value;
use crate::source::SourceFile;

/// What the machine is in at a program's start, where the program does not say; `None` until
/// the profile says (the reader then refuses what depends on it).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct SiemensProfile {
    /// X is a diameter (DIAMON) at the start.
    pub initial_diameter: Option<bool>,
    /// F is per revolution (G95) at the start.
    pub initial_per_rev: Option<bool>,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(crate) struct Raw {
    initial_diameter: Option<toml::Spanned<String>>,
    initial_feed_mode: Option<toml::Spanned<String>>,
}

/// Reads the `[siemens]` section into `p`, reporting each bad value with its key.
pub(crate) fn read(
    src: &SourceFile,
    raw: Raw,
    p: &mut SiemensProfile,
    diags: &mut Vec<Diagnostic>,
) {
    let mut keyword = |value: Option<toml::Spanned<String>>, key: &str, names: [&str; 2], help| {
        let value = value?;
        let found = names
            .iter()
            .position(|n| value.get_ref().eq_ignore_ascii_case(n));
        if found.is_none() {
            let message = format!("unknown value \"{}\"", value.get_ref());
            diags.push(bad_value(
                src,
                src.span_of(value.span()),
                &format!("siemens.{key}"),
                message,
                help,
            ));
        }
        found
    };
    if let Some(i) = keyword(
        raw.initial_diameter,
        "initial_diameter",
        ["DIAMON", "DIAMOF"],
        "\"DIAMON\" (X a diameter) or \"DIAMOF\" (X a radius), as the machine is at reset: its machine data, or a program that moves X by a known amount",
    ) {
        p.initial_diameter = Some(i == 0);
    }
    if let Some(i) = keyword(
        raw.initial_feed_mode,
        "initial_feed_mode",
        ["G95", "G94"],
        "\"G95\" (F per revolution) or \"G94\" (F per minute), as the machine is at reset",
    ) {
        p.initial_per_rev = Some(i == 0);
    }
}

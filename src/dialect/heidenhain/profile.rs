//! HEIDENHAIN's section of the machine profile (`[heidenhain]`): the points the vendor's
//! manuals do not publish, which the machine's documentation (or a test cut) settles.
//!
//! ```toml
//! [heidenhain]
//! keywords = "de"           # the section keywords on disk: "de" (BEARBEITUNG, ENDE) or "en" (MACHINING, END)
//! arc_direction = "iso"     # G12/G2 clockwise as LinuxCNC's G2, or "front-tool"
//! c_sense = "spindle"       # G33's C counts with the spindle's turn, or "against"
//! b_along = "z"             # G33's run-in B is measured along Z, or "path"
//! g31_clearance = 1.0       # G31 read under ncthread's model: the retract per side above the crest
//! g31_infeed = "first"      # G31 V0/V1 with I: I is the first cut ("first"), or the cuts are spread ("spread")
//! g31_h1 = "towards-end"    # G31 H1's offsets move each pass's start towards the thread's end, or "towards-start"
//! ```

use serde::Deserialize;

use crate::diag::Diagnostic;
use crate::fixed::Length;
use crate::profile::value::{RawNumber, bad_value};
use crate::source::SourceFile;

/// The language of the section keywords a program is written with.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SectionKeywords {
    /// `PROGRAMMKOPF`, `REVOLVER`, `BEARBEITUNG`, `ENDE`.
    #[default]
    German,
    /// `PROGRAM HEAD`, `TURRET`, `MACHINING`, `END`.
    English,
}

/// Which way G12 (and G2) turns.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HeidenhainArcDirection {
    /// G12 is LinuxCNC's G2.
    Iso,
    /// G12 is clockwise with Z to the right and X pointing down (a front-tool-post lathe seen
    /// from above): LinuxCNC's G3 for the same path.
    FrontTool,
}

/// In which sense G33's start angle C counts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CSense {
    /// With the spindle's turn: C is the IR's start angle.
    Spindle,
    /// Against it: C is 360° less the IR's start angle.
    Against,
}

/// Along what G33's run-in length B is measured.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BAlong {
    /// B is a distance along Z.
    Z,
    /// B is a distance along the thread's path.
    Path,
}

/// How G31's cuts follow from I under the infeed types V0 and V1.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum G31Infeed {
    /// I is the first cut: V0 cuts to `I·√n`, V1 to `I·n`, the last pass to the depth U.
    First,
    /// I bounds the cuts: the fewest passes N whose cuts stay within I (V0: N = ⌈(U/I)²⌉,
    /// V1: N = ⌈U/I⌉), the depth spread over them as IC spreads it.
    Spread,
}

/// Which way along Z G31's H1 ("offset from the left") moves each pass's start, the cut's
/// depth · tan A further for every cut; H2 moves it the other way.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum G31Offset {
    /// Towards the thread's end (the way the tool cuts).
    TowardsEnd,
    /// Towards the thread's start.
    TowardsStart,
}

/// The HEIDENHAIN machine's unpublished points; `None` until the profile says.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct HeidenhainProfile {
    pub keywords: SectionKeywords,
    pub arc_direction: Option<HeidenhainArcDirection>,
    pub c_sense: Option<CSense>,
    pub b_along: Option<BAlong>,
    /// G31 is read under ncthread's model of its way (README, "HEIDENHAIN G31"): the tool
    /// goes to this height per side above the crest between passes.
    pub g31_clearance: Option<Length>,
    pub g31_infeed: Option<G31Infeed>,
    pub g31_h1: Option<G31Offset>,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(crate) struct Raw {
    keywords: Option<toml::Spanned<String>>,
    arc_direction: Option<toml::Spanned<String>>,
    c_sense: Option<toml::Spanned<String>>,
    b_along: Option<toml::Spanned<String>>,
    g31_clearance: Option<toml::Spanned<RawNumber>>,
    g31_infeed: Option<toml::Spanned<String>>,
    g31_h1: Option<toml::Spanned<String>>,
}

/// Reads the `[heidenhain]` section into `p`, reporting each bad value with its key.
pub(crate) fn read(
    src: &SourceFile,
    raw: Raw,
    p: &mut HeidenhainProfile,
    diags: &mut Vec<Diagnostic>,
) {
    let mut keyword = |value: Option<toml::Spanned<String>>, key: &str, names: &[&str], help| {
        let value = value?;
        let found = names.iter().position(|n| value.get_ref() == n);
        if found.is_none() {
            let message = format!("unknown value \"{}\"", value.get_ref());
            diags.push(bad_value(
                src,
                src.span_of(value.span()),
                &format!("heidenhain.{key}"),
                message,
                help,
            ));
        }
        found
    };
    if let Some(i) = keyword(
        raw.keywords,
        "keywords",
        &["de", "en"],
        "\"de\" (BEARBEITUNG, ENDE) or \"en\" (MACHINING, END), as the control's editor shows them",
    ) {
        p.keywords = [SectionKeywords::German, SectionKeywords::English][i];
    }
    if let Some(i) = keyword(
        raw.arc_direction,
        "arc_direction",
        &["iso", "front-tool"],
        "\"iso\" (G12 as LinuxCNC's G2) or \"front-tool\" (G12 clockwise seen with X pointing down), as the machine's documentation shows it",
    ) {
        p.arc_direction = Some(
            [
                HeidenhainArcDirection::Iso,
                HeidenhainArcDirection::FrontTool,
            ][i],
        );
    }
    if let Some(i) = keyword(
        raw.c_sense,
        "c_sense",
        &["spindle", "against"],
        "\"spindle\" (C counts with the spindle's turn) or \"against\", as a test cut shows",
    ) {
        p.c_sense = Some([CSense::Spindle, CSense::Against][i]);
    }
    if let Some(i) = keyword(
        raw.b_along,
        "b_along",
        &["z", "path"],
        "\"z\" (B measured along Z) or \"path\" (along the thread's path), as a test cut shows",
    ) {
        p.b_along = Some([BAlong::Z, BAlong::Path][i]);
    }
    if let Some(i) = keyword(
        raw.g31_infeed,
        "g31_infeed",
        &["first", "spread"],
        "\"first\" (I is G31's first cut) or \"spread\" (the fewest passes whose cuts stay within I), as the machine's cycle cuts",
    ) {
        p.g31_infeed = Some([G31Infeed::First, G31Infeed::Spread][i]);
    }
    if let Some(i) = keyword(
        raw.g31_h1,
        "g31_h1",
        &["towards-end", "towards-start"],
        "\"towards-end\" (G31 H1 moves each pass's start towards the thread's end) or \"towards-start\", as a test cut shows",
    ) {
        p.g31_h1 = Some([G31Offset::TowardsEnd, G31Offset::TowardsStart][i]);
    }
    if let Some(v) = raw.g31_clearance {
        let clearance = v
            .get_ref()
            .length()
            .filter(|l| l.0 > 0 && l.0 <= 1000 * Length::PER_MM);
        if clearance.is_none() {
            diags.push(bad_value(
                src,
                src.span_of(v.span()),
                "heidenhain.g31_clearance",
                "not a length in millimetres from 0.0001 to 1000".into(),
                "the height per side above the thread's crest the machine's G31 retracts to between passes, `g31_clearance = 1.0`",
            ));
        }
        p.g31_clearance = clearance;
    }
}

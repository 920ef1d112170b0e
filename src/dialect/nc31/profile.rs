//! The НЦ-31's section of the machine profile (`[nc31]`).

use serde::Deserialize;

use crate::diag::Diagnostic;
use crate::fixed::{Lead, Length};
use crate::ir::{Schedule, Slope};
use crate::profile::value::{RawNumber, bad_value};
use crate::source::SourceFile;

/// The НЦ-31's units and machine parameters. Defaults: the seed's units, radial infeed, no
/// runout, 0.5 mm retract, halving schedule.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Nc31Profile {
    /// One unit of X (diameter), Z and P words.
    pub linear_unit: Length,
    /// One unit of F inside a G31/G32/G33 group (lead).
    pub lead_unit: Length,
    /// One unit of F elsewhere (feed per revolution).
    pub feed_unit: Length,
    /// Machine parameter 6: 4096·tan(infeed angle); 0 is radial infeed.
    pub infeed_p6: u32,
    /// Machine parameter 7: runout length in units of 0.1·lead; 0 is none.
    pub runout_p7: u32,
    /// Radial clearance above the crest when a G31 pass returns. **\[decided\]** 0.5 mm.
    pub retract: Length,
    pub schedule: Schedule,
    /// M codes that select a spindle speed range. **\[seed\]** M38…M41.
    pub gear_range_mcodes: Vec<u32>,
    /// The machine switches coolant with M8/M9 (key `coolant = "m8-m9"`). **\[evidence\]**
    /// one shop's program checker only, so off unless the profile says. **\[decided\]**
    pub coolant: bool,
    /// Arcs as `G2`/`G3` groups with two unsigned P offsets, and `G12`/`G13` quarter arcs
    /// (key `arcs = "g2-g3-p"`). **\[evidence\]** one shop's generator; off by default.
    pub arcs: bool,
    /// Which way G2 turns (key `arc_direction`); no default: a profile that enables arcs
    /// must say, and arcs are refused until it does. **\[decided\]**
    pub arc_direction: Option<Nc31ArcDirection>,
    /// The machine takes 45° chamfers `X<end>±45 *` + `F<feed>` (key `chamfer45`): the
    /// writer writes a 45° feed move so. **\[evidence\]** one shop's generator; the reader
    /// reads them whatever the key says (nc31.md: "Read it; write it only when the profile
    /// says the machine takes it").
    pub chamfer45: bool,
    /// The machine repeats frames with `G25 *`, `P<from><to> *`, `P<count>` (key
    /// `repeat_g25`): the reader unrolls it; no writer writes it. **\[evidence\]** one shop's
    /// checker; off by default (refused by name).
    pub repeat_g25: bool,
}

/// Which way the НЦ-31's G2 turns.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Nc31ArcDirection {
    /// G2 is clockwise with Z to the right and X pointing down (a front-tool-post lathe
    /// seen from above): LinuxCNC's G3 for the same path.
    FrontTool,
    /// G2 is LinuxCNC's G2.
    Iso,
}

impl Default for Nc31Profile {
    fn default() -> Self {
        Nc31Profile {
            linear_unit: Length::from_steps(100),
            lead_unit: Length::from_steps(1),
            feed_unit: Length::from_steps(100),
            infeed_p6: 0,
            runout_p7: 0,
            retract: Length::from_steps(5_000),
            schedule: Schedule::Halving,
            gear_range_mcodes: vec![38, 39, 40, 41],
            coolant: false,
            arcs: false,
            arc_direction: None,
            chamfer45: false,
            repeat_g25: false,
        }
    }
}

impl Nc31Profile {
    /// The denominator of parameter 6. **\[seed\]** P = 4096·tan α.
    pub const P6_RUN: i64 = 4096;
    /// The largest parameter 6 accepted: 45° (flank infeed is at most half a thread angle).
    pub const P6_MAX: u32 = 4096;
    /// The largest parameter 7: the seed gives runouts of 0.1…3.1 leads.
    pub const P7_MAX: u32 = 31;

    pub fn infeed(&self) -> Slope {
        Slope {
            rise: self.infeed_p6 as i64,
            run: Self::P6_RUN,
        }
    }

    /// The runout length along Z for `lead`: P7 · 0.1 · lead, rounded once onto the grid.
    pub fn runout(&self, lead: Lead) -> Length {
        lead.length_times(self.runout_p7 as i64, 10)
    }
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(crate) struct Raw {
    linear_unit_mm: Option<toml::Spanned<RawNumber>>,
    lead_unit_mm: Option<toml::Spanned<RawNumber>>,
    feed_unit_mm: Option<toml::Spanned<RawNumber>>,
    infeed_p6: Option<toml::Spanned<i64>>,
    runout_p7: Option<toml::Spanned<i64>>,
    retract_mm: Option<toml::Spanned<RawNumber>>,
    schedule: Option<toml::Spanned<String>>,
    gear_range_mcodes: Option<Vec<u32>>,
    coolant: Option<toml::Spanned<String>>,
    arcs: Option<toml::Spanned<String>>,
    arc_direction: Option<toml::Spanned<String>>,
    chamfer45: Option<bool>,
    repeat_g25: Option<bool>,
}

/// Reads the `[nc31]` section into `p`, reporting each bad value with its key.
pub(crate) fn read(src: &SourceFile, raw: Raw, p: &mut Nc31Profile, diags: &mut Vec<Diagnostic>) {
    use Nc31ArcDirection::{FrontTool, Iso};
    use Schedule::{ConstantArea, ConstantDepth, Halving};
    const UNIT: &str = "a unit must be a positive multiple of 0.0001 mm";
    const UNIT_HELP: &str = "e.g. 0.01 for words in hundredths of a millimetre, 0.0001 for leads";
    const RETRACT: &str = "the retract must be zero or positive, a multiple of 0.0001 mm";
    const RETRACT_HELP: &str = "the built-in value is 0.5";
    const P6_HELP: &str =
        "parameter 6 is 4096·tan(infeed angle): 0 radial, 2365 for 30°, 1491 for 20°";
    const P7_HELP: &str = "parameter 7 is the runout in tenths of the lead (1…31), 0 for none";
    const SCHEDULE_HELP: &str =
        "one of \"halving\" (the control's G31), \"constant-depth\", \"constant-area\"";
    const ARCS_HELP: &str = "\"none\" (the default), or \"g2-g3-p\" (G2/G3 groups with X, Z and two unsigned P offsets of the centre; G12/G13 quarter arcs)";
    const DIR_HELP: &str = "\"front-tool\" (G2 clockwise seen with X pointing down, as the one public НЦ-31 source writes it) or \"iso\" (G2 as LinuxCNC's), as the machine's documentation says";
    const COOLANT_HELP: &str = "\"none\" (the default), or \"m8-m9\" when the machine takes M8/M9";
    let mut bad = |span, key: &str, message: String, help: &str| {
        diags.push(bad_value(src, src.span_of(span), key, message, help));
    };
    let lengths = [
        (raw.linear_unit_mm, &mut p.linear_unit, "linear_unit_mm"),
        (raw.lead_unit_mm, &mut p.lead_unit, "lead_unit_mm"),
        (raw.feed_unit_mm, &mut p.feed_unit, "feed_unit_mm"),
        (raw.retract_mm, &mut p.retract, "retract_mm"),
    ];
    for (value, slot, key) in lengths {
        let Some(value) = value else { continue };
        let (span, retract) = (value.span(), key == "retract_mm");
        match value.into_inner().length() {
            // The units are positive; the retract is zero or more.
            Some(l) if l.0 > 0 || (retract && l.0 == 0) => *slot = l,
            _ if retract => bad(span, &format!("nc31.{key}"), RETRACT.into(), RETRACT_HELP),
            _ => bad(span, &format!("nc31.{key}"), UNIT.into(), UNIT_HELP),
        }
    }
    let parameters = [
        (raw.infeed_p6, &mut p.infeed_p6, "infeed_p6", P6_HELP),
        (raw.runout_p7, &mut p.runout_p7, "runout_p7", P7_HELP),
    ];
    let maxima = [Nc31Profile::P6_MAX, Nc31Profile::P7_MAX];
    for ((value, slot, key, help), max) in parameters.into_iter().zip(maxima) {
        let Some(value) = value else { continue };
        match u32::try_from(*value.get_ref()) {
            Ok(v) if v <= max => *slot = v,
            _ => {
                let message = format!("{} is outside 0…{max}", value.get_ref());
                bad(value.span(), &format!("nc31.{key}"), message, help);
            }
        }
    }
    if let Some(g) = raw.gear_range_mcodes {
        p.gear_range_mcodes = g;
    }
    p.chamfer45 = raw.chamfer45.unwrap_or(p.chamfer45);
    p.repeat_g25 = raw.repeat_g25.unwrap_or(p.repeat_g25);
    // A keyword's value: its index among `names`, or a diagnostic.
    let mut keyword = |value: Option<toml::Spanned<String>>, key: &str, names: &[&str], help| {
        let value = value?;
        let found = names.iter().position(|n| value.get_ref() == n);
        if found.is_none() {
            let what = if key == "schedule" { key } else { "value" };
            let message = format!("unknown {what} \"{}\"", value.get_ref());
            bad(value.span(), &format!("nc31.{key}"), message, help);
        }
        found
    };
    let schedules = ["halving", "constant-depth", "constant-area"];
    if let Some(i) = keyword(raw.schedule, "schedule", &schedules, SCHEDULE_HELP) {
        p.schedule = [Halving, ConstantDepth, ConstantArea][i];
    }
    if let Some(i) = keyword(raw.arcs, "arcs", &["none", "g2-g3-p"], ARCS_HELP) {
        p.arcs = i == 1;
    }
    let directions = ["front-tool", "iso"];
    if let Some(i) = keyword(raw.arc_direction, "arc_direction", &directions, DIR_HELP) {
        p.arc_direction = Some([FrontTool, Iso][i]);
    }
    if let Some(i) = keyword(raw.coolant, "coolant", &["none", "m8-m9"], COOLANT_HELP) {
        p.coolant = i == 1;
    }
}

//! The machine profile: a TOML file with the constants that differ per machine.
//!
//! ```toml
//! [czech]
//! constant8 = "15160000"        # TAB0.REK machine constant No. 8
//! initial_motion = "G00"        # motion mode in force at program start
//! gear_range_mcodes = [41, 42, 43, 44]
//!
//! [nc31]
//! linear_unit_mm = 0.01         # X (diameter), Z and P words
//! lead_unit_mm = 0.0001         # F inside G31/G32/G33 groups
//! feed_unit_mm = 0.01           # F elsewhere (mm/rev)
//! infeed_p6 = 0                 # machine parameter 6: 4096·tan(infeed angle)
//! runout_p7 = 0                 # machine parameter 7: runout in 0.1·lead
//! retract_mm = 0.5              # radial clearance above the crest between G31 passes
//! schedule = "halving"          # G31 pass law: halving, constant-depth, constant-area
//! gear_range_mcodes = [38, 39, 40, 41]
//!
//! [iso]
//! mcodes = { 42 = "M142" }      # legacy M codes → LinuxCNC M words
//! tool_change = "m6"            # "m6" writes `T9 M6`, "t" writes `T9` alone
//! ```

use indexmap::IndexMap;
use serde::Deserialize;

use crate::diag::{Diagnostic, codes};
use crate::fixed::{Lead, Length};
use crate::ir::{Schedule, Slope};
use crate::source::{SourceFile, Span};

/// Machine constants. `Profile::default()` holds the seeds' values.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Profile {
    /// The profile file's name, for diagnostics that mention it.
    pub name: Option<String>,
    pub czech: CzechProfile,
    pub nc31: Nc31Profile,
    pub iso: IsoProfile,
}

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
    /// Radial clearance above the crest when a G31 pass returns. **[decided]** 0.5 mm.
    pub retract: Length,
    pub schedule: Schedule,
    /// M codes that select a spindle speed range. **[seed]** M38…M41.
    pub gear_range_mcodes: Vec<u32>,
}

impl Default for Nc31Profile {
    fn default() -> Self {
        Nc31Profile {
            linear_unit: Length(100),
            lead_unit: Length(1),
            feed_unit: Length(100),
            infeed_p6: 0,
            runout_p7: 0,
            retract: Length(5_000),
            schedule: Schedule::Halving,
            gear_range_mcodes: vec![38, 39, 40, 41],
        }
    }
}

impl Nc31Profile {
    /// The denominator of parameter 6. **[seed]** P = 4096·tan α.
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

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CzechProfile {
    /// Machine constant No. 8 (runout/entry angle); `None` when the profile does not give it.
    pub constant8: Option<Constant8>,
    /// Motion mode at program start. **[decided]** G00.
    pub initial_motion: InitialMotion,
    /// M codes that select a gear range. **[decided]** M41–M44 (the seed shows M42).
    pub gear_range_mcodes: Vec<u32>,
}

impl Default for CzechProfile {
    fn default() -> Self {
        CzechProfile {
            constant8: None,
            initial_motion: InitialMotion::Rapid,
            gear_range_mcodes: vec![41, 42, 43, 44],
        }
    }
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
pub enum InitialMotion {
    #[default]
    #[serde(rename = "G00", alias = "G0")]
    Rapid,
    #[serde(rename = "G01", alias = "G1")]
    Feed,
}

#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct IsoProfile {
    /// Source M code → the M word LinuxCNC should get instead (e.g. a user M code).
    pub mcodes: IndexMap<u32, String>,
    pub tool_change: ToolChange,
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ToolChange {
    /// `T9 M6` (LinuxCNC's tool change).
    #[default]
    M6,
    /// `T9` alone (a lathe turret configured to index on T).
    T,
}

/// Machine constant No. 8 as written: a sign and 8 decades, decade 8 first.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Constant8 {
    pub negative: bool,
    /// `decades[0]` is decade 8, `decades[7]` decade 1.
    pub decades: [u8; 8],
}

/// What constant 8 says about the runout/entry angle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AngleSource {
    /// Direct mode: the angle word `sign · (axis·100 + angle)` in 0.001° (decades 6…1).
    Direct { word: i64 },
    /// Parameter mode: R parameter numbers for the runout angle and the entry angle.
    Parameters { runout: u32, entry: Option<u32> },
}

impl Constant8 {
    /// Parses `[+|-]dddddddd`.
    pub fn parse(text: &str) -> Option<Constant8> {
        let (negative, digits) = crate::fixed::split_sign(text)?;
        if digits.len() != 8 || !digits.bytes().all(|b| b.is_ascii_digit()) {
            return None;
        }
        let mut decades = [0u8; 8];
        for (d, b) in decades.iter_mut().zip(digits.bytes()) {
            *d = b - b'0';
        }
        Some(Constant8 { negative, decades })
    }

    fn number(&self, from: usize, to: usize) -> u32 {
        self.decades[from..to]
            .iter()
            .fold(0, |n, &d| n * 10 + d as u32)
    }

    /// Direct mode when decades 8 and 7 are 0, else parameter mode. **[seed]**
    pub fn angle_source(&self) -> AngleSource {
        let runout = self.number(0, 2);
        if runout == 0 {
            // decade 6 = axis, decades 5…1 = angle in 0.001°: together axis·100 000 + angle.
            let magnitude = self.number(2, 8) as i64;
            let word = if self.negative { -magnitude } else { magnitude };
            AngleSource::Direct { word }
        } else {
            let entry = self.number(2, 4);
            AngleSource::Parameters {
                runout,
                entry: (entry != 0).then_some(entry),
            }
        }
    }
}

impl std::fmt::Display for Constant8 {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.negative {
            f.write_str("-")?;
        }
        for d in self.decades {
            write!(f, "{d}")?;
        }
        Ok(())
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawProfile {
    #[serde(default)]
    czech: RawCzech,
    #[serde(default)]
    nc31: RawNc31,
    #[serde(default)]
    iso: RawIso,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawNc31 {
    linear_unit_mm: Option<toml::Spanned<RawNumber>>,
    lead_unit_mm: Option<toml::Spanned<RawNumber>>,
    feed_unit_mm: Option<toml::Spanned<RawNumber>>,
    infeed_p6: Option<toml::Spanned<i64>>,
    runout_p7: Option<toml::Spanned<i64>>,
    retract_mm: Option<toml::Spanned<RawNumber>>,
    schedule: Option<toml::Spanned<String>>,
    gear_range_mcodes: Option<Vec<u32>>,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(untagged)]
enum RawNumber {
    Int(i64),
    Float(f64),
}

impl RawNumber {
    /// The value as a length on the 0.0001 mm grid, if it lies on it.
    fn length(self) -> Option<Length> {
        match self {
            RawNumber::Int(i) => i.checked_mul(10_000).map(Length),
            RawNumber::Float(f) => {
                let units = f * 10_000.0;
                (units.is_finite() && units.abs() < 1e15 && (units - units.round()).abs() < 1e-6)
                    .then(|| Length(units.round() as i64))
            }
        }
    }
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawCzech {
    constant8: Option<toml::Spanned<RawConstant>>,
    initial_motion: Option<InitialMotion>,
    gear_range_mcodes: Option<Vec<u32>>,
}

#[derive(Deserialize)]
#[serde(untagged)]
enum RawConstant {
    Text(String),
    Number(i64),
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawIso {
    mcodes: Option<IndexMap<String, toml::Spanned<String>>>,
    tool_change: Option<ToolChange>,
}

impl Profile {
    /// Reads a profile from its text; every problem is a diagnostic pointing into the file.
    pub fn from_toml(src: &SourceFile) -> Result<Profile, Vec<Diagnostic>> {
        let raw: RawProfile = toml::from_str(&src.text).map_err(|e| {
            let mut message = format!("profile: {}", e.message().trim());
            let span = e.span().map(|range| src.span_of(range));
            // Serde's type errors do not name the key: take it from the marked line.
            if let Some(key) = span.and_then(|s| key_on_line(src, s))
                && !message.contains(&key)
            {
                message.push_str(&format!(" (key `{key}`)"));
            }
            let mut d = Diagnostic::new(codes::PF_INVALID, message);
            if let Some(span) = span {
                d = d.at(src, span);
            }
            vec![
                d.help("see README.md, section \"Machine profile\", for the keys and their values"),
            ]
        })?;
        let mut diags = Vec::new();
        let mut profile = Profile {
            name: Some(src.name.clone()),
            ..Profile::default()
        };
        if let Some(c8) = raw.czech.constant8 {
            let span = src.span_of(c8.span());
            let text = match c8.get_ref() {
                RawConstant::Text(t) => Some(t.clone()),
                RawConstant::Number(n) if n.unsigned_abs() < 100_000_000 => Some(format!(
                    "{}{:08}",
                    if *n < 0 { "-" } else { "" },
                    n.unsigned_abs()
                )),
                RawConstant::Number(_) => None,
            };
            match text.as_deref().and_then(Constant8::parse) {
                Some(c) => profile.czech.constant8 = Some(c),
                None => diags.push(
                    Diagnostic::new(codes::PF_CONSTANT8, "machine constant 8 must be a sign and 8 decades")
                        .at(src, span)
                        .label("not 8 decimal digits")
                        .help("write it as in TAB0.REK, e.g. \"+00112500\" (direct: axis X, 12.500°) or \"04000000\" (angle in R04)"),
                ),
            }
        }
        if let Some(m) = raw.czech.initial_motion {
            profile.czech.initial_motion = m;
        }
        if let Some(g) = raw.czech.gear_range_mcodes {
            profile.czech.gear_range_mcodes = g;
        }
        nc31(src, raw.nc31, &mut profile.nc31, &mut diags);
        if let Some(t) = raw.iso.tool_change {
            profile.iso.tool_change = t;
        }
        for (key, value) in raw.iso.mcodes.unwrap_or_default() {
            let span = src.span_of(value.span());
            let word = value.into_inner();
            let valid_word = word
                .strip_prefix(['M', 'm'])
                .is_some_and(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()));
            match key.trim_start_matches(['M', 'm']).parse::<u32>() {
                Ok(code) if valid_word => {
                    profile.iso.mcodes.insert(code, word.to_ascii_uppercase());
                }
                _ => diags.push(
                    Diagnostic::new(codes::ISOW_BAD_MAPPING, format!("`{key} = \"{word}\"` is not an M code mapping"))
                        .at(src, span)
                        .help("write the source M number as the key and one LinuxCNC M word as the value, e.g. `42 = \"M142\"`"),
                ),
            }
        }
        if diags.is_empty() {
            Ok(profile)
        } else {
            Err(diags)
        }
    }
}

/// `key` of a `key = value` line, when the span lies after the `=`.
fn key_on_line(src: &SourceFile, span: Span) -> Option<String> {
    let line = src.line(span.line);
    let (key, _) = line.text.split_once('=')?;
    let key = key.trim();
    (span.start >= line.offset + key.len() && !key.is_empty() && !key.starts_with('['))
        .then(|| key.to_string())
}

fn bad_value(src: &SourceFile, span: Span, key: &str, message: String, help: &str) -> Diagnostic {
    Diagnostic::new(codes::PF_VALUE, format!("profile key `{key}`: {message}"))
        .at(src, span)
        .help(help.to_string())
}

/// Reads the `[nc31]` section into `p`, reporting each bad value with its key.
fn nc31(src: &SourceFile, raw: RawNc31, p: &mut Nc31Profile, diags: &mut Vec<Diagnostic>) {
    let units = [
        (
            "nc31.linear_unit_mm",
            raw.linear_unit_mm,
            &mut p.linear_unit,
        ),
        ("nc31.lead_unit_mm", raw.lead_unit_mm, &mut p.lead_unit),
        ("nc31.feed_unit_mm", raw.feed_unit_mm, &mut p.feed_unit),
    ];
    for (key, value, slot) in units {
        let Some(value) = value else { continue };
        let span = src.span_of(value.span());
        match value.into_inner().length() {
            Some(l) if l.0 > 0 => *slot = l,
            _ => diags.push(bad_value(
                src,
                span,
                key,
                "a unit must be a positive multiple of 0.0001 mm".into(),
                "e.g. 0.01 for words in hundredths of a millimetre, 0.0001 for leads",
            )),
        }
    }
    if let Some(value) = raw.retract_mm {
        let span = src.span_of(value.span());
        match value.into_inner().length() {
            Some(l) if l.0 >= 0 => p.retract = l,
            _ => diags.push(bad_value(
                src,
                span,
                "nc31.retract_mm",
                "the retract must be zero or positive, a multiple of 0.0001 mm".into(),
                "the built-in value is 0.5",
            )),
        }
    }
    let parameters = [
        (
            "nc31.infeed_p6",
            raw.infeed_p6,
            Nc31Profile::P6_MAX,
            &mut p.infeed_p6,
            "parameter 6 is 4096·tan(infeed angle): 0 radial, 2365 for 30°, 1491 for 20°",
        ),
        (
            "nc31.runout_p7",
            raw.runout_p7,
            Nc31Profile::P7_MAX,
            &mut p.runout_p7,
            "parameter 7 is the runout in tenths of the lead (1…31), 0 for none",
        ),
    ];
    for (key, value, max, slot, help) in parameters {
        let Some(value) = value else { continue };
        let span = src.span_of(value.span());
        match u32::try_from(*value.get_ref()) {
            Ok(v) if v <= max => *slot = v,
            _ => diags.push(bad_value(
                src,
                span,
                key,
                format!("{} is outside 0…{max}", value.get_ref()),
                help,
            )),
        }
    }
    if let Some(value) = raw.schedule {
        let span = src.span_of(value.span());
        match value.get_ref().as_str() {
            "halving" => p.schedule = Schedule::Halving,
            "constant-depth" => p.schedule = Schedule::ConstantDepth,
            "constant-area" => p.schedule = Schedule::ConstantArea,
            other => diags.push(bad_value(
                src,
                span,
                "nc31.schedule",
                format!("unknown schedule \"{other}\""),
                "one of \"halving\" (the control's G31), \"constant-depth\", \"constant-area\"",
            )),
        }
    }
    if let Some(g) = raw.gear_range_mcodes {
        p.gear_range_mcodes = g;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn load(text: &str) -> Result<Profile, Vec<Diagnostic>> {
        Profile::from_toml(&SourceFile::new("p.toml", text))
    }

    #[test]
    fn decodes_the_seed_constants() {
        let direct = Constant8::parse("00112500").unwrap();
        assert_eq!(direct.angle_source(), AngleSource::Direct { word: 112_500 });
        let negative = Constant8::parse("-00120000").unwrap();
        assert_eq!(
            negative.angle_source(),
            AngleSource::Direct { word: -120_000 }
        );
        let r04 = Constant8::parse("04000000").unwrap();
        assert_eq!(
            r04.angle_source(),
            AngleSource::Parameters {
                runout: 4,
                entry: None
            }
        );
        let two = Constant8::parse("15160000").unwrap();
        assert_eq!(
            two.angle_source(),
            AngleSource::Parameters {
                runout: 15,
                entry: Some(16)
            }
        );
        assert_eq!(two.to_string(), "15160000");
        assert!(Constant8::parse("1516000").is_none());
        assert!(Constant8::parse("1516000x").is_none());
    }

    #[test]
    fn reads_a_profile() {
        let p = load("[czech]\nconstant8 = \"15160000\"\ninitial_motion = \"G01\"\n[iso]\nmcodes = { 42 = \"M142\" }\ntool_change = \"t\"\n").unwrap();
        assert_eq!(p.czech.constant8, Constant8::parse("15160000"));
        assert_eq!(p.czech.initial_motion, InitialMotion::Feed);
        assert_eq!(p.iso.mcodes.get(&42).map(String::as_str), Some("M142"));
        assert_eq!(p.iso.tool_change, ToolChange::T);
        // An integer keeps its leading zeros as decades.
        let p = load("[czech]\nconstant8 = 4000000\n").unwrap();
        assert_eq!(p.czech.constant8, Constant8::parse("04000000"));
    }

    #[test]
    fn reports_unknown_keys_and_bad_values_with_their_line() {
        let e = load("[czech]\nconstant_8 = \"1\"\n").unwrap_err();
        assert_eq!(e[0].code, codes::PF_INVALID);
        assert_eq!(e[0].location.as_ref().unwrap().line, 2);
        assert!(e[0].message.contains("constant_8"), "{}", e[0].message);
        let e = load("[czech]\n\nconstant8 = \"12\"\n").unwrap_err();
        assert_eq!(e[0].code, codes::PF_CONSTANT8);
        assert_eq!(e[0].location.as_ref().unwrap().line, 3);
        let e = load("[iso]\nmcodes = { 42 = \"G1\" }\n").unwrap_err();
        assert_eq!(e[0].code, codes::ISOW_BAD_MAPPING);
    }

    #[test]
    fn reads_the_nc31_section() {
        let p = Profile::default();
        assert_eq!(p.nc31.linear_unit, Length(100));
        assert_eq!(p.nc31.lead_unit, Length(1));
        assert_eq!(p.nc31.retract, Length(5000));
        let p = load("[nc31]\nlinear_unit_mm = 0.001\nlead_unit_mm = 0.001\nfeed_unit_mm = 0.001\ninfeed_p6 = 2365\nruntout_p7 = 1\n").unwrap_err();
        assert!(p[0].message.contains("runtout_p7"), "{}", p[0].message);
        let p = load("[nc31]\nlinear_unit_mm = 0.001\nfeed_unit_mm = 1\ninfeed_p6 = 2365\nrunout_p7 = 10\nretract_mm = 1\nschedule = \"constant-area\"\n").unwrap();
        assert_eq!(p.nc31.linear_unit, Length(10));
        assert_eq!(p.nc31.feed_unit, Length(10_000));
        assert_eq!(p.nc31.infeed().of(Length(9600)), Length(5543));
        assert_eq!(
            p.nc31.runout(Lead::from_length(Length(15_000))),
            Length(15_000)
        );
        assert_eq!(p.nc31.schedule, Schedule::ConstantArea);
    }

    #[test]
    fn reports_bad_nc31_values_with_file_line_and_key() {
        for (text, line, key) in [
            (
                "[nc31]\nlinear_unit_mm = 0.00001\n",
                2,
                "nc31.linear_unit_mm",
            ),
            ("[nc31]\n\nlead_unit_mm = -1\n", 3, "nc31.lead_unit_mm"),
            ("[nc31]\ninfeed_p6 = 5000\n", 2, "nc31.infeed_p6"),
            ("[nc31]\nrunout_p7 = 40\n", 2, "nc31.runout_p7"),
            ("[nc31]\nschedule = \"fast\"\n", 2, "nc31.schedule"),
            ("[nc31]\nretract_mm = -0.5\n", 2, "nc31.retract_mm"),
        ] {
            let e = load(text).unwrap_err();
            assert_eq!(e[0].code, codes::PF_VALUE, "{text}");
            let loc = e[0].location.as_ref().unwrap();
            assert_eq!((loc.file.as_str(), loc.line), ("p.toml", line), "{text}");
            assert!(e[0].message.contains(key), "{}", e[0].message);
        }
        // A wrong type names the key too.
        let e = load("[nc31]\ninfeed_p6 = \"30deg\"\n").unwrap_err();
        assert_eq!(e[0].code, codes::PF_INVALID);
        assert!(e[0].message.contains("infeed_p6"), "{}", e[0].message);
    }
}

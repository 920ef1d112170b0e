//! The machine profile: a TOML file with the constants that differ per machine.
//!
//! ```toml
//! [czech]
//! constant8 = "15160000"        # TAB0.REK machine constant No. 8
//! initial_motion = "G00"        # motion mode in force at program start
//! gear_range_mcodes = [41, 42, 43, 44]
//!
//! [iso]
//! mcodes = { 42 = "M142" }      # legacy M codes → LinuxCNC M words
//! tool_change = "m6"            # "m6" writes `T9 M6`, "t" writes `T9` alone
//! ```

use indexmap::IndexMap;
use serde::Deserialize;

use crate::diag::{Diagnostic, codes};
use crate::source::SourceFile;

/// Machine constants. `Profile::default()` holds the seeds' values.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Profile {
    /// The profile file's name, for diagnostics that mention it.
    pub name: Option<String>,
    pub czech: CzechProfile,
    pub iso: IsoProfile,
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
    iso: RawIso,
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
            let mut d = Diagnostic::new(
                codes::PF_INVALID,
                format!("profile: {}", e.message().trim()),
            );
            if let Some(range) = e.span() {
                d = d.at(src, src.span_of(range));
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
                    Diagnostic::new(codes::ISO_BAD_MAPPING, format!("`{key} = \"{word}\"` is not an M code mapping"))
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
        assert_eq!(e[0].code, codes::ISO_BAD_MAPPING);
    }
}

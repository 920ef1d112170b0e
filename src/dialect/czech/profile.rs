//! The czech control's section of the machine profile (`[czech]`).

use serde::Deserialize;

use crate::diag::Diagnostic;
use crate::dialect::czech::codes;
use crate::profile::value::bad_value;
use crate::source::SourceFile;

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CzechProfile {
    /// Machine constant No. 8 (runout/entry angle); `None` when the profile does not give it.
    pub constant8: Option<Constant8>,
    /// Motion mode at program start. **\[decided\]** G00.
    pub initial_motion: InitialMotion,
    /// M codes that select a gear range. **\[decided\]** M41–M44 (the seed shows M42).
    pub gear_range_mcodes: Vec<u32>,
    /// The machine switches flood coolant with M08/M09 (key `coolant = "m08-m09"`). The
    /// seed does not document coolant: off until the shop's manual says. **\[decided\]**
    pub coolant: bool,
    /// Mist coolant is M07 (key `mist = "m07"`, with `coolant`).
    pub mist: bool,
    /// How the machine writes arcs (key `arcs`): none until the shop's manual says.
    pub arcs: CzechArcs,
    /// G02 is clockwise seen as on a front-tool lathe (key `arc_direction = "mirrored"`),
    /// the opposite letter of LinuxCNC's G2 for the same path. **\[decided\]** default "iso".
    pub arcs_mirrored: bool,
    /// How the machine writes a dwell (key `dwell`): none until the shop's manual says.
    pub dwell: CzechDwell,
    /// The machine holds a constant surface speed with `G96 S…` (m/min) and returns to rpm
    /// with `G97 S…` (key `surface_speed = "g96-g97"`); its speed limit is the machine's
    /// setting, not a word of the program. **\[decided\]**
    pub surface_speed: bool,
}

/// The dwell forms the czech profile can declare. **\[decided\]** (czech.md, "Forms the machine
/// profile declares")
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum CzechDwell {
    /// Dwells are refused.
    #[default]
    None,
    /// `G04 X<seconds>` (X is then the time, not an axis).
    XSeconds,
    /// `G04 F<seconds>`.
    FSeconds,
    /// `G04 P<milliseconds>`, a whole number.
    PMilliseconds,
}

impl CzechDwell {
    /// The address that carries the time.
    pub fn letter(self) -> Option<char> {
        match self {
            CzechDwell::None => None,
            CzechDwell::XSeconds => Some('X'),
            CzechDwell::FSeconds => Some('F'),
            CzechDwell::PMilliseconds => Some('P'),
        }
    }
}

/// The arc forms the czech profile can declare. **\[decided\]** (czech.md, "Forms the machine
/// profile declares")
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum CzechArcs {
    /// Arcs are refused.
    #[default]
    None,
    /// `G02`/`G03 X Z I K`: I and K the centre's offset from the start, I a radius.
    IkRadius,
    /// The same, I a diameter value.
    IkDiameter,
    /// `G02`/`G03 X Z R`: R the radius, negative for more than half a turn.
    Radius,
}

impl Default for CzechProfile {
    fn default() -> Self {
        CzechProfile {
            constant8: None,
            initial_motion: InitialMotion::Rapid,
            gear_range_mcodes: vec![41, 42, 43, 44],
            coolant: false,
            mist: false,
            arcs: CzechArcs::None,
            arcs_mirrored: false,
            dwell: CzechDwell::None,
            surface_speed: false,
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

    /// Direct mode when decades 8 and 7 are 0, else parameter mode. **\[seed\]**
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

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(crate) struct Raw {
    constant8: Option<toml::Spanned<RawConstant>>,
    initial_motion: Option<InitialMotion>,
    gear_range_mcodes: Option<Vec<u32>>,
    coolant: Option<toml::Spanned<String>>,
    mist: Option<toml::Spanned<String>>,
    arcs: Option<toml::Spanned<String>>,
    arc_direction: Option<toml::Spanned<String>>,
    dwell: Option<toml::Spanned<String>>,
    surface_speed: Option<toml::Spanned<String>>,
}

#[derive(Deserialize)]
#[serde(untagged)]
enum RawConstant {
    Text(String),
    Number(i64),
}

/// Reads the `[czech]` section into `p`, reporting each bad value with its line.
pub(crate) fn read(src: &SourceFile, raw: Raw, p: &mut CzechProfile, diags: &mut Vec<Diagnostic>) {
    if let Some(c8) = raw.constant8 {
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
            Some(c) => p.constant8 = Some(c),
            None => diags.push(
                Diagnostic::new(codes::PF_CONSTANT8, "machine constant 8 must be a sign and 8 decades")
                    .at(src, span)
                    .label("not 8 decimal digits")
                    .help("write it as in TAB0.REK, e.g. \"+00112500\" (direct: axis X, 12.500°) or \"04000000\" (angle in R04)"),
            ),
        }
    }
    p.initial_motion = raw.initial_motion.unwrap_or(p.initial_motion);
    if let Some(g) = raw.gear_range_mcodes {
        p.gear_range_mcodes = g;
    }
    let mist_span = raw.mist.as_ref().map(|m| src.span_of(m.span()));
    // The keys that choose one of a few values, in the order they are checked: each value's
    // place among its key's names, or a diagnostic and the setting left as it is.
    #[rustfmt::skip]
    let choices = [
        ("czech.arcs", raw.arcs, &["none", "ik-radius", "ik-diameter", "r"][..], "\"none\" (the default), \"ik-radius\" or \"ik-diameter\" (G02/G03 X Z I K, I a radius or a diameter value), \"r\" (G02/G03 X Z R), as the machine's manual gives it"),
        ("czech.arc_direction", raw.arc_direction, &["iso", "mirrored"][..], "\"iso\" (the default: G02 as LinuxCNC's G2 for the same path) or \"mirrored\" (a front-tool machine whose manual says G02 turns the other way)"),
        ("czech.dwell", raw.dwell, &["none", "g04-x-seconds", "g04-f-seconds", "g04-p-milliseconds"][..], "\"none\" (the default), \"g04-x-seconds\", \"g04-f-seconds\" or \"g04-p-milliseconds\", as the machine's manual gives it"),
        ("czech.surface_speed", raw.surface_speed, &["none", "g96-g97"][..], "\"none\" (the default), or \"g96-g97\" (G96 S in m/min, G97 S in rpm) when the machine's manual says so"),
        ("czech.coolant", raw.coolant, &["none", "m08-m09"][..], "\"none\" (the default), or \"m08-m09\" when the machine's manual says so"),
        ("czech.mist", raw.mist, &["none", "m07"][..], "\"none\" (the default), or \"m07\" when the machine's manual says so"),
    ];
    let [arcs, direction, dwell, speed, coolant, mist] =
        choices.map(|(key, value, names, help)| {
            let value = value?;
            let name = value.get_ref().as_str();
            let found = names.iter().position(|n| *n == name);
            if found.is_none() {
                let message = format!("unknown value \"{name}\"");
                let span = src.span_of(value.span());
                diags.push(bad_value(src, span, key, message, help));
            }
            found
        });
    use {CzechArcs as A, CzechDwell as D};
    p.arcs = arcs.map_or(p.arcs, |i| {
        [A::None, A::IkRadius, A::IkDiameter, A::Radius][i]
    });
    p.arcs_mirrored = direction.map_or(p.arcs_mirrored, |i| i == 1);
    p.dwell = dwell.map_or(p.dwell, |i| {
        [D::None, D::XSeconds, D::FSeconds, D::PMilliseconds][i]
    });
    p.surface_speed = speed.map_or(p.surface_speed, |i| i == 1);
    p.coolant = coolant.map_or(p.coolant, |i| i == 1);
    p.mist = mist.map_or(p.mist, |i| i == 1);
    if let Some(span) = mist_span
        && p.mist
        && !p.coolant
    {
        p.mist = false;
        diags.push(bad_value(
            src,
            span,
            "czech.mist",
            "`mist` is set but `coolant` is not".into(),
            "set `coolant = \"m08-m09\"` too: M09 turns mist off as well",
        ));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
}

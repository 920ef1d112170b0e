//! The machine profile: a TOML file with the constants that differ per machine. Each
//! dialect declares and reads its own section (`dialect/<id>/profile.rs`); this module reads
//! the file and hands each section to its dialect.
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
//! chamfer45 = false             # write 45° feed moves as `X<end>±45 *` + `F<feed>`
//! repeat_g25 = false            # read (unroll) `G25 *`, `P<from><to> *`, `P<count>`
//!
//! [iso]
//! mcodes = { 42 = "M142" }      # other machines' M codes → LinuxCNC user M words
//! tool_change = "m6"            # "m6" writes `T9 M6`, "t" writes `T9` alone
//!
//! [fanuc]
//! decimal_point = "increment"   # a word without a point: 0.001 mm (or "calculator": mm)
//! thread_chamfer_0p1_lead = 10  # G92's chamfer (parameter 5130); needed to read G92
//! tool_offset = "same"          # T0303 for tool 3 without an offset; "none": T0300
//! program_number = 1            # O0001
//!
//! [siemens]
//! initial_diameter = "DIAMON"   # X a diameter until the program says (or "DIAMOF")
//! initial_feed_mode = "G95"     # F per revolution until the program says (or "G94")
//!
//! [heidenhain]
//! keywords = "de"               # section keywords on disk: BEARBEITUNG/ENDE ("en": MACHINING/END)
//! arc_direction = "iso"         # G2/G12 as LinuxCNC's G2 ("front-tool": as its G3)
//! c_sense = "spindle"           # G33's C counts with the spindle's turn ("against")
//! b_along = "z"                 # G33's run-in B is measured along Z ("path")
//! ```

use serde::Deserialize;

use crate::diag::{Diagnostic, codes};
use crate::dialect::czech::profile as czech;
use crate::dialect::fanuc::profile as fanuc;
use crate::dialect::heidenhain::profile as heidenhain;
use crate::dialect::iso::profile as iso;
use crate::dialect::nc31::profile as nc31;
use crate::dialect::siemens::profile as siemens;
use crate::source::{SourceFile, Span};

pub(crate) mod value;

/// Every key of a profile with its values and defaults, as a commented TOML file (README's
/// "Machine profile" block, which a test keeps equal to it): the help of the browser page's
/// profile editor.
pub const KEYS: &str = include_str!("keys.toml");

pub use crate::dialect::czech::profile::{
    AngleSource, Constant8, CzechArcs, CzechDwell, CzechProfile, InitialMotion,
};
pub use crate::dialect::fanuc::profile::{DecimalPoint, FanucProfile, GcodeSystem, ToolOffset};
pub use crate::dialect::heidenhain::profile::{
    BAlong, CSense, G31Infeed, G31Offset, HeidenhainArcDirection, HeidenhainProfile,
    SectionKeywords,
};
pub use crate::dialect::iso::profile::{BlockDelete, IsoProfile, ToolChange};
pub use crate::dialect::nc31::profile::{Nc31ArcDirection, Nc31Profile};
pub use crate::dialect::siemens::profile::SiemensProfile;

/// Machine constants. `Profile::default()` holds the seeds' values.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Profile {
    /// The profile file's name, for diagnostics that mention it.
    pub name: Option<String>,
    pub czech: CzechProfile,
    pub nc31: Nc31Profile,
    pub iso: IsoProfile,
    pub fanuc: FanucProfile,
    pub siemens: SiemensProfile,
    pub heidenhain: HeidenhainProfile,
}

/// Why a profile file cannot be used.
#[derive(Clone, Debug)]
pub enum LoadError {
    Io(String),
    Invalid(Vec<Diagnostic>),
}

impl LoadError {
    /// One line for a report: the I/O error, or the first error with its place.
    pub fn summary(&self, path: &std::path::Path) -> String {
        match self {
            LoadError::Io(why) => why.clone(),
            LoadError::Invalid(diags) => {
                let first = diags
                    .iter()
                    .find(|d| d.is_error())
                    .map_or(String::new(), |d| {
                        let at = d
                            .location
                            .as_ref()
                            .map_or(String::new(), |l| format!(" at {}:{}", l.line, l.column));
                        format!(": {}{at} ({})", d.message, d.code.id)
                    });
                format!("the profile {} has errors{first}", path.display())
            }
        }
    }
}

/// What the command line says of the machine on top of any profile.
#[derive(Clone, Debug, Default)]
pub struct Overrides {
    pub block_delete: Option<BlockDelete>,
    /// More folders of subroutine files (after the profile's).
    pub subroutine_path: Vec<std::path::PathBuf>,
}

impl Overrides {
    pub fn apply(&self, profile: &mut Profile) {
        if let Some(b) = self.block_delete {
            profile.iso.block_delete = Some(b);
        }
        profile
            .iso
            .subroutine_path
            .extend(self.subroutine_path.iter().cloned());
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawProfile {
    #[serde(default)]
    czech: czech::Raw,
    #[serde(default)]
    nc31: nc31::Raw,
    #[serde(default)]
    iso: iso::Raw,
    #[serde(default)]
    fanuc: fanuc::Raw,
    #[serde(default)]
    siemens: siemens::Raw,
    #[serde(default)]
    heidenhain: heidenhain::Raw,
}

impl Profile {
    /// Reads the profile file at `path`: an I/O error as text, or the profile's diagnostics
    /// (each with its file, line and key).
    pub fn load(path: &std::path::Path) -> Result<Profile, LoadError> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| LoadError::Io(crate::diag::io_error("read", path.display(), &e)))?;
        Profile::from_toml(&SourceFile::new(path.display().to_string(), text))
            .map_err(LoadError::Invalid)
    }

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
        czech::read(src, raw.czech, &mut profile.czech, &mut diags);
        nc31::read(src, raw.nc31, &mut profile.nc31, &mut diags);
        iso::read(src, raw.iso, &mut profile.iso, &mut diags);
        fanuc::read(src, raw.fanuc, &mut profile.fanuc, &mut diags);
        siemens::read(src, raw.siemens, &mut profile.siemens, &mut diags);
        heidenhain::read(src, raw.heidenhain, &mut profile.heidenhain, &mut diags);
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
    (span.range().start >= line.offset + key.len() && !key.is_empty() && !key.starts_with('['))
        .then(|| key.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixed::{Lead, Length};
    use crate::ir::Schedule;

    fn load(text: &str) -> Result<Profile, Vec<Diagnostic>> {
        Profile::from_toml(&SourceFile::new("p.toml", text))
    }

    #[test]
    fn the_keys_help_is_readmes_block_and_a_profile() {
        let readme = include_str!("../../README.md");
        assert!(
            readme.contains("## Machine profile") && readme.contains(KEYS),
            "README's profile block and src/profile/keys.toml differ"
        );
        // Every key it shows reads (a key it names but the reader refuses would mislead).
        let src = SourceFile::new("keys.toml", KEYS);
        if let Err(diags) = Profile::from_toml(&src) {
            panic!(
                "{}",
                crate::diag::render_all(&diags, crate::diag::Format::Human, false)
            );
        }
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
        assert_eq!(e[0].code, crate::dialect::iso::codes::ISOW_BAD_MAPPING);
        // Only a user M code: M3 would start the spindle.
        let e = load("[iso]\nmcodes = { 42 = \"M3\" }\n").unwrap_err();
        assert_eq!(e[0].code, crate::dialect::iso::codes::ISOW_BAD_MAPPING);
    }

    #[test]
    fn reads_the_nc31_section() {
        let p = Profile::default();
        assert_eq!(p.nc31.linear_unit, Length::from_steps(100));
        assert_eq!(p.nc31.lead_unit, Length::from_steps(1));
        assert_eq!(p.nc31.retract, Length::from_steps(5000));
        let p = load("[nc31]\nlinear_unit_mm = 0.001\nlead_unit_mm = 0.001\nfeed_unit_mm = 0.001\ninfeed_p6 = 2365\nruntout_p7 = 1\n").unwrap_err();
        assert!(p[0].message.contains("runtout_p7"), "{}", p[0].message);
        let p = load("[nc31]\nlinear_unit_mm = 0.001\nfeed_unit_mm = 1\ninfeed_p6 = 2365\nrunout_p7 = 10\nretract_mm = 1\nschedule = \"constant-area\"\n").unwrap();
        assert_eq!(p.nc31.linear_unit, Length::from_steps(10));
        assert_eq!(p.nc31.feed_unit, Length::from_steps(10_000));
        assert_eq!(
            p.nc31.infeed().of(Length::from_steps(9600)),
            Length::from_steps(5543)
        );
        assert_eq!(
            p.nc31.runout(Lead::from_length(Length::from_steps(15_000))),
            Length::from_steps(15_000)
        );
        assert_eq!(p.nc31.schedule, Schedule::ConstantArea);
        // Chamfers and G25 repeats: off by default, booleans.
        assert!(!Profile::default().nc31.chamfer45 && !Profile::default().nc31.repeat_g25);
        let p = load("[nc31]\nchamfer45 = true\nrepeat_g25 = true\n").unwrap();
        assert!(p.nc31.chamfer45 && p.nc31.repeat_g25);
        let e = load("[nc31]\nrepeat_g25 = \"yes\"\n").unwrap_err();
        assert_eq!(e[0].code, codes::PF_INVALID);
        assert!(e[0].message.contains("repeat_g25"), "{}", e[0].message);
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

    #[test]
    fn reads_heidenhain_g31_keys_and_reports_bad_values() {
        let p = load("[heidenhain]\ng31_clearance = 0.5\ng31_infeed = \"spread\"\ng31_h1 = \"towards-start\"\n")
            .unwrap();
        assert_eq!(p.heidenhain.g31_clearance, Some(Length::from_steps(5_000)));
        assert_eq!(p.heidenhain.g31_infeed, Some(G31Infeed::Spread));
        assert_eq!(p.heidenhain.g31_h1, Some(G31Offset::TowardsStart));
        for (text, key) in [
            (
                "[heidenhain]\ng31_clearance = 0\n",
                "heidenhain.g31_clearance",
            ),
            (
                "[heidenhain]\ng31_clearance = 0.00001\n",
                "heidenhain.g31_clearance",
            ),
            (
                "[heidenhain]\ng31_infeed = \"half\"\n",
                "heidenhain.g31_infeed",
            ),
            ("[heidenhain]\ng31_h1 = \"left\"\n", "heidenhain.g31_h1"),
        ] {
            let e = load(text).unwrap_err();
            assert_eq!(e[0].code, codes::PF_VALUE, "{text}");
            assert!(e[0].message.contains(key), "{}", e[0].message);
        }
    }
}

//! The FANUC section of the machine profile (`[fanuc]`).
//!
//! ```toml
//! [fanuc]
//! decimal_point = "increment"     # a word without a point: "increment" (X10 = 0.010 mm) or "calculator" (X10 = 10 mm)
//! thread_chamfer_0p1_lead = 10    # G92's chamfer (parameter 5130) in 0.1 lead; needed to read G92
//! tool_offset = "same"            # T0303 for tool 3 without an offset number; "none" writes T0300
//! program_number = 1              # O0001 (default: a FANUC source's own number, else 1)
//! nose_radius_in_offsets = false  # the offset page holds nose radius and tip: G41/G42 may be written
//! mist = false                    # the machine has M07
//! gcode_system = "A"              # "A", or "B" (G33 threads, G90/G91, G94/G95, G92 S, G77–G79)
//! ```

use serde::Deserialize;

use crate::diag::Diagnostic;
use crate::profile::value::bad_value;
use crate::source::SourceFile;

/// How a word without a decimal point is read: FANUC parameter 3401#0 (DPI). **\[evidence\]**
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DecimalPoint {
    /// In least input increments: 0.001 mm for X Z U W I K R, 0.0001 mm for a lead F (the
    /// control's default, DPI = 0).
    #[default]
    Increment,
    /// As millimetres, like a pocket calculator (DPI = 1).
    Calculator,
}

/// Which offset a tool gets when the program names none.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ToolOffset {
    /// The offset of the same number: `T0303`.
    #[default]
    Same,
    /// No offset: `T0300`.
    None,
}

/// FANUC's lathe G-code systems (parameter 3401#6, #7). **\[evidence\]** spec fanuc.md.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum GcodeSystem {
    /// System A: G32 threads, G50 S the spindle limit, G98/G99 the feed mode, U/W
    /// incremental, G90/G92/G94 the turning, threading and facing cycles.
    #[default]
    A,
    /// System B: G33 threads, G92 S the spindle limit, G94/G95 the feed mode, G90/G91
    /// absolute and incremental, G77/G78/G79 the turning, threading and facing cycles.
    B,
}

/// The functions whose G code differs between systems A and B: (system A's, system B's).
/// The reader maps B onto A, the writer A onto B: one table for both.
const SYSTEM_B_CODES: [(i64, i64); 7] = [
    (32, 33), // thread
    (90, 77), // turning cycle
    (92, 78), // threading cycle
    (94, 79), // facing cycle
    (50, 92), // spindle limit (S)
    (98, 94), // feed per minute
    (99, 95), // feed per revolution
];

impl GcodeSystem {
    /// System B's code for system A's `a`, where they differ.
    pub(crate) fn b_of(a: i64) -> Option<i64> {
        SYSTEM_B_CODES.iter().find(|p| p.0 == a).map(|p| p.1)
    }

    /// System A's code for system B's `b`, where they differ.
    pub(crate) fn a_of(b: i64) -> Option<i64> {
        SYSTEM_B_CODES.iter().find(|p| p.1 == b).map(|p| p.0)
    }
}

/// What ncthread knows of a FANUC lathe.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FanucProfile {
    pub decimal_point: DecimalPoint,
    /// G92's thread chamfer (pull-out) in 0.1 lead (FANUC parameter 5130), at 45°. `None`:
    /// not said, so a G92 is refused. **\[decided\]**
    pub thread_chamfer_0p1_lead: Option<u32>,
    pub tool_offset: ToolOffset,
    /// The `O` number of a program ncthread writes (1–9999). `None`: a FANUC source's own
    /// number, else 1.
    pub program_number: Option<u32>,
    /// The offset page holds the nose radius and tip direction, so `G41`/`G42` may be
    /// written. **\[decided\]** off: the program cannot state them.
    pub nose_radius_in_offsets: bool,
    /// The machine has mist coolant on `M07`.
    pub mist: bool,
    /// The G-code system the machine reads and ncthread writes.
    pub gcode_system: GcodeSystem,
}

impl Default for FanucProfile {
    fn default() -> Self {
        FanucProfile {
            decimal_point: DecimalPoint::Increment,
            thread_chamfer_0p1_lead: None,
            tool_offset: ToolOffset::Same,
            program_number: None,
            nose_radius_in_offsets: false,
            mist: false,
            gcode_system: GcodeSystem::A,
        }
    }
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(crate) struct Raw {
    decimal_point: Option<toml::Spanned<String>>,
    thread_chamfer_0p1_lead: Option<toml::Spanned<i64>>,
    tool_offset: Option<toml::Spanned<String>>,
    program_number: Option<toml::Spanned<i64>>,
    nose_radius_in_offsets: Option<bool>,
    mist: Option<bool>,
    gcode_system: Option<toml::Spanned<String>>,
}

/// Reads the `[fanuc]` section into `p`, reporting each bad value with its line.
pub(crate) fn read(src: &SourceFile, raw: Raw, p: &mut FanucProfile, diags: &mut Vec<Diagnostic>) {
    if let Some(v) = raw.decimal_point {
        let span = src.span_of(v.span());
        match v.into_inner().as_str() {
            "increment" => p.decimal_point = DecimalPoint::Increment,
            "calculator" => p.decimal_point = DecimalPoint::Calculator,
            other => diags.push(bad_value(
                src,
                span,
                "decimal_point",
                format!("`{other}` is not a decimal point rule"),
                "\"increment\" (X10 is 0.010 mm: FANUC parameter 3401#0 = 0) or \"calculator\" (X10 is 10 mm: 3401#0 = 1)",
            )),
        }
    }
    if let Some(v) = raw.thread_chamfer_0p1_lead {
        let span = src.span_of(v.span());
        match u32::try_from(v.into_inner()) {
            Ok(n) if n <= 127 => p.thread_chamfer_0p1_lead = Some(n),
            _ => diags.push(bad_value(
                src,
                span,
                "thread_chamfer_0p1_lead",
                "the thread chamfer is 0 to 127 tenths of the lead".into(),
                "copy the machine's parameter 5130 (0 is no chamfer)",
            )),
        }
    }
    if let Some(v) = raw.tool_offset {
        let span = src.span_of(v.span());
        match v.into_inner().as_str() {
            "same" => p.tool_offset = ToolOffset::Same,
            "none" => p.tool_offset = ToolOffset::None,
            other => diags.push(bad_value(
                src,
                span,
                "tool_offset",
                format!("`{other}` is not a tool offset rule"),
                "\"same\" (T0303 for tool 3) or \"none\" (T0300)",
            )),
        }
    }
    if let Some(v) = raw.program_number {
        let span = src.span_of(v.span());
        match u32::try_from(v.into_inner()) {
            Ok(n) if (1..=9999).contains(&n) => p.program_number = Some(n),
            _ => diags.push(bad_value(
                src,
                span,
                "program_number",
                "a program number is 1 to 9999".into(),
                "O0001 is program_number = 1",
            )),
        }
    }
    if let Some(b) = raw.nose_radius_in_offsets {
        p.nose_radius_in_offsets = b;
    }
    if let Some(b) = raw.mist {
        p.mist = b;
    }
    if let Some(v) = raw.gcode_system {
        gcode_system(src, v, p, diags);
    }
}

/// `gcode_system`: "A" or "B"; "C" is refused with its reason.
fn gcode_system(
    src: &SourceFile,
    v: toml::Spanned<String>,
    p: &mut FanucProfile,
    diags: &mut Vec<Diagnostic>,
) {
    let span = src.span_of(v.span());
    match v.into_inner().as_str() {
        "A" | "a" => p.gcode_system = GcodeSystem::A,
        "B" | "b" => p.gcode_system = GcodeSystem::B,
        "C" | "c" => diags.push(bad_value(
            src,
            span,
            "gcode_system",
            "G-code system C is not read yet: the sources ncthread holds disagree on its codes for the turning, threading and facing cycles".into(),
            "\"A\" or \"B\"",
        )),
        other => diags.push(bad_value(
            src,
            span,
            "gcode_system",
            format!("`{other}` is not a FANUC G-code system"),
            "\"A\" (G32, G50 S, G98/G99) or \"B\" (G33, G92 S, G94/G95, G90/G91)",
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::GcodeSystem;
    use crate::profile::Profile;
    use crate::source::SourceFile;

    fn system(value: &str) -> Result<GcodeSystem, Vec<crate::diag::Diagnostic>> {
        let text = format!("[fanuc]\ngcode_system = \"{value}\"\n");
        Profile::from_toml(&SourceFile::new("p.toml", text)).map(|p| p.fanuc.gcode_system)
    }

    /// A and B are read; C is refused with its reason, and so is anything else.
    #[test]
    fn the_gcode_system_is_a_or_b() {
        assert_eq!(system("A").unwrap(), GcodeSystem::A);
        assert_eq!(system("B").unwrap(), GcodeSystem::B);
        let c = system("C").unwrap_err();
        assert!(c[0].message.contains("system C is not read yet"), "{c:?}");
        assert!(system("D").is_err());
        assert_eq!(Profile::default().fanuc.gcode_system, GcodeSystem::A);
    }
}

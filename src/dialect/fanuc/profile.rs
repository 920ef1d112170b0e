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
//! still_m_codes = [31, 33]        # the builder's M codes that move no axis (a chip conveyor): the position stays known
//! gcode_system = "A"              # "A", "B" (G33 threads, G90/G91, G94/G95, G92 S, G77–G79) or "C" (as B; G70/G71 units, G20/G21/G24, G72–G78)
//! units = "mm"                    # the unit the machine starts in (a program without G20/G21): "mm" or "inch"
//! cycle_model = "gsk-980tdi"      # expand the canned cycles into moves as this control makes them
//! g71_retract = "feed"            # or one open point at a time: the 45° retract after a G71 layer
//! g71_layers_from = "shifted-start" # layers counted from the start shifted by the allowance, or "start"
//! g71_semi_finish = true          # the pass along the roughing contour after the layers
//! g73_divisor = "passes-minus-one" # how G73 spreads its relief: by passes − 1, or "passes"
//! g76_min_cut = "formula"         # G76's Δdmin counts from Δd√(n−1), or "accumulated"
//! g76_pass_end = "end-line"       # G76's passes end on the end line, or "shifted"
//! reference_point = { x = 250.0, z = 300.0 }  # G28's point in machine coordinates (X a diameter)
//! haas_setting_73 = 0.05          # Haas's one-block G71/G72: the retract after a layer (Setting 73, 287 on the NGC), in the machine's unit
//! haas_dwell_p = true             # G04 P with a decimal point is seconds, as on a Haas (`G04 P3.` 3 s; `G04 P3` 3 ms), and written so
//! ```

use serde::Deserialize;

use crate::diag::Diagnostic;
use crate::fixed::Length;
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

/// FANUC's lathe G-code systems (parameter 3401#6, #7). **\[evidence\]** spec fanuc.md; system
/// C's codes from FANUC's "G code list" table (README, the decisions).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum GcodeSystem {
    /// System A: G32 threads, G50 S the spindle limit, G98/G99 the feed mode, U/W
    /// incremental, G90/G92/G94 the turning, threading and facing cycles.
    #[default]
    A,
    /// System B: G33 threads, G92 S the spindle limit, G94/G95 the feed mode, G90/G91
    /// absolute and incremental, G77/G78/G79 the turning, threading and facing cycles.
    B,
    /// System C: as B, but G70/G71 inch and metric input, G20/G21/G24 the turning, threading
    /// and facing cycles, and the multiple repetitive cycles renumbered G72–G78.
    C,
}

/// The functions whose G code differs between the systems: (system A's, B's, C's). The
/// reader maps B and C onto A, the writer A onto B or C: one table for both.
const SYSTEM_CODES: [(i64, i64, i64); 16] = [
    (32, 33, 33), // thread
    (90, 77, 20), // turning cycle
    (92, 78, 21), // threading cycle
    (94, 79, 24), // facing cycle
    (50, 92, 92), // spindle limit (S)
    (98, 94, 94), // feed per minute
    (99, 95, 95), // feed per revolution
    (20, 20, 70), // inch input
    (21, 21, 71), // metric input
    (70, 70, 72), // finishing cycle
    (71, 71, 73), // stock removal in turning
    (72, 72, 74), // stock removal in facing
    (73, 73, 75), // pattern repeating
    (74, 74, 76), // end face peck drilling
    (75, 75, 77), // grooving
    (76, 76, 78), // multiple threading
];

impl GcodeSystem {
    /// This system's code in a row of [`SYSTEM_CODES`].
    fn column(self, row: &(i64, i64, i64)) -> i64 {
        match self {
            GcodeSystem::A => row.0,
            GcodeSystem::B => row.1,
            GcodeSystem::C => row.2,
        }
    }

    /// This system's code for system A's `a` (itself where no system differs).
    pub(crate) fn code(self, a: i64) -> i64 {
        SYSTEM_CODES
            .iter()
            .find(|r| r.0 == a)
            .map_or(a, |r| self.column(r))
    }

    /// System A's code for this system's `g`, where the table has it.
    pub(crate) fn a_of(self, g: i64) -> Option<i64> {
        SYSTEM_CODES
            .iter()
            .find(|r| self.column(r) == g)
            .map(|r| r.0)
    }

    /// System A's codes this system numbers otherwise: (A's, this system's).
    pub(crate) fn renumbered(self) -> Vec<(i64, i64)> {
        SYSTEM_CODES
            .iter()
            .map(|r| (r.0, self.column(r)))
            .filter(|(a, own)| a != own)
            .collect()
    }

    /// The system's name in a message: "G-code system B".
    pub(crate) fn name(self) -> &'static str {
        match self {
            GcodeSystem::A => "G-code system A",
            GcodeSystem::B => "G-code system B",
            GcodeSystem::C => "G-code system C",
        }
    }
}

/// How the 45° retract after each G71/G72 layer moves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Retract {
    Feed,
    Rapid,
}

/// Where the G71/G72 layers are counted from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LayersFrom {
    /// The start point shifted by the finishing allowance (Δu/2, Δw).
    ShiftedStart,
    /// The start point itself.
    Start,
}

/// How G73 spreads its relief over its passes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum G73Divisor {
    /// By passes − 1: the first pass at the whole relief, the last at none.
    PassesMinusOne,
    /// By the passes.
    Passes,
}

/// Where G76's least depth per pass (Δdmin) counts from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MinCut {
    /// From Δd√(n − 1), the formula's depth of the pass before.
    Formula,
    /// From the pass before's actual depth.
    Accumulated,
}

/// Where each G76 pass ends.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PassEnd {
    /// On the thread's end line: only its start moves along the flank.
    EndLine,
    /// Moved with its start.
    Shifted,
}

/// The machine model under which the FANUC reader expands canned cycles into moves (spec
/// fanuc.md, "Canned cycles under a declared machine model"): each open point the sources
/// leave to the control. `None` in a point: not said. **\[decided\]**
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct CycleModel {
    /// The profile declares a model: `cycle_model` names the control, or the points are
    /// given one by one (`"the profile's keys"`). `None`: cycles are kept as written.
    pub declared: Option<&'static str>,
    pub g71_retract: Option<Retract>,
    pub g71_layers_from: Option<LayersFrom>,
    pub g71_semi_finish: Option<bool>,
    pub g73_divisor: Option<G73Divisor>,
    pub g76_min_cut: Option<MinCut>,
    pub g76_pass_end: Option<PassEnd>,
    /// The reference point G28 returns to, in machine coordinates (X a diameter).
    pub reference_point: Option<(Length, Length)>,
    /// Haas's one-block G71/G72 (`G71 P Q U W D F`): the retract after each layer, the
    /// machine's Setting 73 (287 on Haas's Next Generation Control). `None`: not said, so
    /// such a cycle is kept as written.
    pub haas_setting_73: Option<Length>,
}

impl CycleModel {
    /// The GSK 980TDi's answer to each open point, as its manual states it.
    fn gsk_980tdi() -> CycleModel {
        CycleModel {
            declared: Some("gsk-980tdi"),
            g71_retract: Some(Retract::Feed),
            g71_layers_from: Some(LayersFrom::ShiftedStart),
            g71_semi_finish: Some(true),
            g73_divisor: Some(G73Divisor::PassesMinusOne),
            g76_min_cut: Some(MinCut::Formula),
            g76_pass_end: Some(PassEnd::EndLine),
            reference_point: None,
            haas_setting_73: None,
        }
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
    /// The machine builder's M codes that move no axis (a chip conveyor, a door): the
    /// machine's own codes (`ItemKind::MachineCode`), the position known after them, written
    /// back for FANUC and as a comment (or `[iso] mcodes`'s word) elsewhere.
    /// **\[decided\]** none: an M code can call a macro.
    pub still_m_codes: Vec<u32>,
    /// The G-code system the machine reads and ncthread writes.
    pub gcode_system: GcodeSystem,
    /// How the machine runs its canned cycles, where the profile says.
    pub cycle_model: CycleModel,
    /// The machine starts in inches (a Haas lathe's Setting 9, FANUC parameter 0#2): a
    /// program that says neither G20 nor G21 is read in inches. **\[decided\]** millimetres.
    pub inch: bool,
    /// G04's P with a decimal point is seconds, as Haas's controls read it ("G04 P10. is a
    /// dwell of 10 seconds; G04 P10 is a dwell of 10 milliseconds", Haas's operator's
    /// manual, G04). **\[evidence\]** Off: FANUC's P takes no decimal point (refused).
    pub haas_dwell_p: bool,
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
            still_m_codes: Vec::new(),
            gcode_system: GcodeSystem::A,
            cycle_model: CycleModel::default(),
            inch: false,
            haas_dwell_p: false,
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
    still_m_codes: Option<Vec<u32>>,
    gcode_system: Option<toml::Spanned<String>>,
    units: Option<toml::Spanned<String>>,
    cycle_model: Option<toml::Spanned<String>>,
    g71_retract: Option<toml::Spanned<String>>,
    g71_layers_from: Option<toml::Spanned<String>>,
    g71_semi_finish: Option<bool>,
    g73_divisor: Option<toml::Spanned<String>>,
    g76_min_cut: Option<toml::Spanned<String>>,
    g76_pass_end: Option<toml::Spanned<String>>,
    reference_point: Option<toml::Spanned<RawPoint>>,
    haas_setting_73: Option<toml::Spanned<f64>>,
    haas_dwell_p: Option<bool>,
}

/// `reference_point = { x = 250.0, z = 300.0 }`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawPoint {
    x: f64,
    z: f64,
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
    flags(raw.nose_radius_in_offsets, raw.mist, raw.still_m_codes, p);
    if let Some(b) = raw.haas_dwell_p {
        p.haas_dwell_p = b;
    }
    if let Some(v) = raw.gcode_system {
        gcode_system(src, v, p, diags);
    }
    if let Some(v) = raw.units {
        units(src, v, p, diags);
    }
    let keys = ModelKeys {
        cycle_model: raw.cycle_model,
        g71_retract: raw.g71_retract,
        g71_layers_from: raw.g71_layers_from,
        g71_semi_finish: raw.g71_semi_finish,
        g73_divisor: raw.g73_divisor,
        g76_min_cut: raw.g76_min_cut,
        g76_pass_end: raw.g76_pass_end,
        reference_point: raw.reference_point,
        haas_setting_73: raw.haas_setting_73,
    };
    model_keys(src, keys, p, diags);
}

/// The keys that take any value of their type.
fn flags(
    nose_radius_in_offsets: Option<bool>,
    mist: Option<bool>,
    still_m_codes: Option<Vec<u32>>,
    p: &mut FanucProfile,
) {
    if let Some(b) = nose_radius_in_offsets {
        p.nose_radius_in_offsets = b;
    }
    if let Some(b) = mist {
        p.mist = b;
    }
    if let Some(codes) = still_m_codes {
        p.still_m_codes = codes;
    }
}

/// The keys of the machine model of the canned cycles.
struct ModelKeys {
    cycle_model: Option<toml::Spanned<String>>,
    g71_retract: Option<toml::Spanned<String>>,
    g71_layers_from: Option<toml::Spanned<String>>,
    g71_semi_finish: Option<bool>,
    g73_divisor: Option<toml::Spanned<String>>,
    g76_min_cut: Option<toml::Spanned<String>>,
    g76_pass_end: Option<toml::Spanned<String>>,
    reference_point: Option<toml::Spanned<RawPoint>>,
    haas_setting_73: Option<toml::Spanned<f64>>,
}

/// The machine model: `cycle_model` first, each open point's own key over it, and the
/// reference point; a key alone declares a model.
fn model_keys(
    src: &SourceFile,
    keys: ModelKeys,
    p: &mut FanucProfile,
    diags: &mut Vec<Diagnostic>,
) {
    cycle_model(src, keys.cycle_model, p, diags);
    if let Some(v) = keys.reference_point {
        p.cycle_model.reference_point = reference_point(src, v, diags);
    }
    if let Some(v) = keys.haas_setting_73 {
        p.cycle_model.haas_setting_73 = haas_length(src, v, p.inch, "haas_setting_73", diags);
    }
    let m = &mut p.cycle_model;
    let own = keys.g71_retract.is_some()
        || keys.g71_layers_from.is_some()
        || keys.g71_semi_finish.is_some()
        || keys.g73_divisor.is_some()
        || keys.g76_min_cut.is_some()
        || keys.g76_pass_end.is_some()
        || m.reference_point.is_some();
    if own && m.declared.is_none() {
        m.declared = Some("the profile's keys");
    }
    m.g71_retract = choice(
        src,
        keys.g71_retract,
        "g71_retract",
        &[("feed", Retract::Feed), ("rapid", Retract::Rapid)],
        diags,
        m.g71_retract,
    );
    m.g71_layers_from = choice(
        src,
        keys.g71_layers_from,
        "g71_layers_from",
        &[
            ("shifted-start", LayersFrom::ShiftedStart),
            ("start", LayersFrom::Start),
        ],
        diags,
        m.g71_layers_from,
    );
    if let Some(b) = keys.g71_semi_finish {
        m.g71_semi_finish = Some(b);
    }
    m.g76_min_cut = choice(
        src,
        keys.g76_min_cut,
        "g76_min_cut",
        &[
            ("formula", MinCut::Formula),
            ("accumulated", MinCut::Accumulated),
        ],
        diags,
        m.g76_min_cut,
    );
    m.g76_pass_end = choice(
        src,
        keys.g76_pass_end,
        "g76_pass_end",
        &[
            ("end-line", PassEnd::EndLine),
            ("shifted", PassEnd::Shifted),
        ],
        diags,
        m.g76_pass_end,
    );
    m.g73_divisor = choice(
        src,
        keys.g73_divisor,
        "g73_divisor",
        &[
            ("passes-minus-one", G73Divisor::PassesMinusOne),
            ("passes", G73Divisor::Passes),
        ],
        diags,
        m.g73_divisor,
    );
}

/// A Haas Setting's length, in the machine's unit (`units`): 0 or more, below 1 m; on the
/// grid of that unit (0.0001 in is exact).
fn haas_length(
    src: &SourceFile,
    v: toml::Spanned<f64>,
    inch: bool,
    key: &str,
    diags: &mut Vec<Diagnostic>,
) -> Option<Length> {
    let span = src.span_of(v.span());
    let x = v.into_inner();
    let mm = if inch { x * 25.4 } else { x };
    if x.is_finite() && (0.0..1000.0).contains(&mm) {
        return Some(if inch {
            Length((x * 10_000.0).round() as i64 * Length::INCH_STEP)
        } else {
            Length::from_mm_f64(x)
        });
    }
    diags.push(bad_value(
        src,
        span,
        key,
        format!("`{x}` is not a retract"),
        "copy the machine's Setting, in the machine's unit (`units`): 0.05 is 0.05 in on an inch machine",
    ));
    None
}

/// `reference_point = { x = …, z = … }`: millimetres, x a diameter.
fn reference_point(
    src: &SourceFile,
    v: toml::Spanned<RawPoint>,
    diags: &mut Vec<Diagnostic>,
) -> Option<(Length, Length)> {
    let span = src.span_of(v.span());
    let v = v.into_inner();
    if v.x.is_finite() && v.z.is_finite() && v.x.abs() < 1e5 && v.z.abs() < 1e5 {
        return Some((Length::from_mm_f64(v.x), Length::from_mm_f64(v.z)));
    }
    diags.push(bad_value(
        src,
        span,
        "reference_point",
        "the reference point's x and z are millimetres under 100,000".into(),
        "copy the machine's reference point in machine coordinates: `reference_point = { x = 250.0, z = 300.0 }` (x a diameter)",
    ));
    None
}

/// `cycle_model`: the control whose every open point the profile takes.
fn cycle_model(
    src: &SourceFile,
    v: Option<toml::Spanned<String>>,
    p: &mut FanucProfile,
    diags: &mut Vec<Diagnostic>,
) {
    let Some(v) = v else { return };
    let span = src.span_of(v.span());
    match v.into_inner().to_ascii_lowercase().as_str() {
        "gsk-980tdi" => p.cycle_model = CycleModel::gsk_980tdi(),
        other => diags.push(bad_value(
            src,
            span,
            "cycle_model",
            format!("`{other}` is not a machine model ncthread knows"),
            "\"gsk-980tdi\" (every open point as the GSK 980TDi manual states it), or give the open points one by one: g71_retract, g71_layers_from, g71_semi_finish, g73_divisor, g76_min_cut, g76_pass_end, reference_point",
        )),
    }
}

/// A key whose value is one of `options` (its name in the profile, and the value); without
/// the key, `current`.
fn choice<T: Copy>(
    src: &SourceFile,
    v: Option<toml::Spanned<String>>,
    key: &str,
    options: &[(&str, T)],
    diags: &mut Vec<Diagnostic>,
    current: Option<T>,
) -> Option<T> {
    let Some(v) = v else {
        return current;
    };
    let span = src.span_of(v.span());
    let value = v.into_inner();
    let found = options.iter().find(|(name, _)| *name == value).map(|o| o.1);
    if found.is_none() {
        let names: Vec<String> = options.iter().map(|(n, _)| format!("\"{n}\"")).collect();
        diags.push(bad_value(
            src,
            span,
            key,
            format!("`{value}` is not a value of {key}"),
            &format!("one of {}", names.join(", ")),
        ));
    }
    found
}

/// `units`: the unit the machine starts in, "mm" or "inch".
fn units(
    src: &SourceFile,
    v: toml::Spanned<String>,
    p: &mut FanucProfile,
    diags: &mut Vec<Diagnostic>,
) {
    let span = src.span_of(v.span());
    match v.into_inner().as_str() {
        "mm" => p.inch = false,
        "inch" => p.inch = true,
        other => diags.push(bad_value(
            src,
            span,
            "units",
            format!("`{other}` is not a unit the machine starts in"),
            "\"mm\" (G21 at power-on) or \"inch\" (G20 at power-on: a Haas lathe's Setting 9 = INCH)",
        )),
    }
}

/// `gcode_system`: "A", "B" or "C".
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
        "C" | "c" => p.gcode_system = GcodeSystem::C,
        other => diags.push(bad_value(
            src,
            span,
            "gcode_system",
            format!("`{other}` is not a FANUC G-code system"),
            "\"A\" (G32, G50 S, G98/G99), \"B\" (G33, G92 S, G94/G95, G90/G91) or \"C\" (as B, with G70/G71 inch and metric and the cycles renumbered)",
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

    /// A, B and C are read; anything else is refused.
    #[test]
    fn the_gcode_system_is_a_b_or_c() {
        assert_eq!(system("A").unwrap(), GcodeSystem::A);
        assert_eq!(system("B").unwrap(), GcodeSystem::B);
        assert_eq!(system("C").unwrap(), GcodeSystem::C);
        let d = system("D").unwrap_err();
        assert!(d[0].message.contains("not a FANUC G-code system"), "{d:?}");
        assert_eq!(Profile::default().fanuc.gcode_system, GcodeSystem::A);
    }

    /// Within one system no code means two things: each column of the table holds a code
    /// once, and the reader's and the writer's mappings undo each other.
    #[test]
    fn each_system_spells_each_function_once() {
        for s in [GcodeSystem::A, GcodeSystem::B, GcodeSystem::C] {
            let mut seen = std::collections::HashSet::new();
            for row in super::SYSTEM_CODES {
                assert!(seen.insert(s.column(&row)), "{s:?} {row:?}");
                assert_eq!(s.a_of(s.code(row.0)), Some(row.0), "{s:?} {row:?}");
            }
        }
        // System C, FANUC's table: inch and metric input G70/G71, the finishing cycle G72,
        // the turning cycle G20, the threading cycle G21.
        let c = GcodeSystem::C;
        assert_eq!((c.code(20), c.code(21)), (70, 71));
        assert_eq!((c.code(70), c.code(76)), (72, 78));
        assert_eq!((c.code(90), c.code(92), c.code(94)), (20, 21, 24));
        assert_eq!(
            (c.a_of(70), c.a_of(20), c.a_of(90)),
            (Some(20), Some(90), None)
        );
        assert_eq!(GcodeSystem::B.code(20), 20);
    }

    /// The unit the machine starts in: millimetres unless the profile says inches.
    #[test]
    fn the_machine_starts_in_mm_or_inches() {
        let units = |v: &str| {
            Profile::from_toml(&SourceFile::new(
                "p.toml",
                format!("[fanuc]\nunits = \"{v}\"\n"),
            ))
            .map(|p| p.fanuc.inch)
        };
        assert!(units("inch").unwrap());
        assert!(!units("mm").unwrap());
        assert!(units("feet").is_err());
        assert!(!Profile::default().fanuc.inch);
        // A program without G20 or G21 is then read in inches and written in inches.
        let profile =
            Profile::from_toml(&SourceFile::new("p.toml", "[fanuc]\nunits = \"inch\"\n")).unwrap();
        let (p, d) = crate::dialect::fanuc::front::parse(
            &SourceFile::new("t", "G99\nG00 X1. Z0.1\nM30\n"),
            &profile.fanuc,
            crate::dialect::Unsupported::Error,
        );
        assert!(d.iter().all(|d| !d.is_error()), "{d:?}");
        assert!(p.inch);
        assert!(
            p.items
                .iter()
                .any(|i| matches!(&i.kind, crate::ir::ItemKind::Rapid { to }
            if to.x == Some(crate::fixed::Length::from_mm_f64(25.4))))
        );
    }

    #[test]
    fn haas_setting_73_is_in_the_machines_unit() {
        let read = |text: &str| {
            Profile::from_toml(&SourceFile::new("p.toml", text))
                .map(|p| p.fanuc.cycle_model.haas_setting_73)
        };
        // 0.05 in is 1.27 mm, exactly (0.0001 in is 254 grid units).
        assert_eq!(
            read("[fanuc]\nunits = \"inch\"\nhaas_setting_73 = 0.05\n").unwrap(),
            Some(crate::fixed::Length(500 * crate::fixed::Length::INCH_STEP))
        );
        assert_eq!(
            read("[fanuc]\nhaas_setting_73 = 1.0\n").unwrap(),
            Some(crate::fixed::Length::from_mm(1))
        );
        assert!(read("[fanuc]\nhaas_setting_73 = -1.0\n").is_err());
        assert_eq!(read("[fanuc]\n").unwrap(), None);
    }
}

//! Dialect `heidenhain`: HEIDENHAIN MANUALplus 620 / CNC PILOT 640 DIN programs. See
//! ../shared/spec/heidenhain.md. No HEIDENHAIN control runs here, so the writer uses only
//! words whose meaning the vendor's manuals give; what depends on the two points they leave
//! to a help graphic or do not state (an arc's direction; the sense of G33's start angle C and
//! the measure of its run-in B) is written only where the profile declares it, and refused by
//! name otherwise. The reader reads what the writer writes and a little more (`Xi`/`Zi`,
//! `G2`/`G3`, `R`, the `N 13` of the manuals' examples, the `G31` cycle under the profile's
//! declared model).

pub mod codes;
mod emit;
mod front;
pub mod profile;
pub mod syntax;

use super::capabilities::{Capabilities, Capability, Construct, Read, Write, row};
use super::{Dialect, DialectId, Keep, LineClaim, LineMark, Unsupported, WriteOptions, detect};
use crate::diag::Diagnostic;
use crate::dialect::capabilities::Occurrence;
use crate::encoding::TextEncoding;
use crate::ir::Program;
use crate::profile::Profile;
use crate::source::SourceFile;
use profile::BAlong;

/// The HEIDENHAIN dialect's id.
pub const ID: DialectId = DialectId::new("heidenhain");

/// HEIDENHAIN DIN turning.
pub struct Heidenhain;

/// The section keywords a DIN program's lines may be (German and English).
pub(crate) const SECTIONS: &[&str] = &[
    "PROGRAMMKOPF",
    "PROGRAM HEAD",
    "REVOLVER",
    "TURRET",
    "MAGAZINE",
    "SPANNMITTEL",
    "CHUCKING EQUIPMENT",
    "ROHTEIL",
    "BLANK",
    "HILFSROHTEIL",
    "AUXIL_BLANK",
    "FERTIGTEIL",
    "FINISHED",
    "FINISHED PART",
    "HILFSKONTUR",
    "AUXIL_CONTOUR",
    "BEARBEITUNG",
    "MACHINING",
    "ENDE",
    "END",
    "UNTERPROGRAMM",
    "SUBPROGRAM",
    "RETURN",
];

/// Whether `line` is a section keyword line (`BEARBEITUNG`, `FINISHED PART`), a comment
/// after it allowed.
pub(crate) fn section_of(line: &str) -> Option<&'static str> {
    let code = line.split('[').next().unwrap_or("").trim();
    // `UNTERPROGRAMM "NAME"`: a subprogram's section names it.
    let code = match code.split_once('"') {
        Some((head, _)) => head.trim(),
        None => code,
    };
    let code = code.split_whitespace().collect::<Vec<_>>().join(" ");
    SECTIONS
        .iter()
        .find(|s| s.eq_ignore_ascii_case(&code))
        .copied()
}

/// `%352.nc`, `%SHAFT_1.ncs`: a DIN program's name line.
pub(crate) fn is_name_line(line: &str) -> bool {
    let t = line.trim();
    let Some(rest) = t.strip_prefix('%') else {
        return false;
    };
    let lower = rest.to_ascii_lowercase();
    let stem = lower
        .strip_suffix(".nc")
        .or_else(|| lower.strip_suffix(".ncs"));
    stem.is_some_and(|s| !s.is_empty() && s.chars().all(|c| c.is_ascii_alphanumeric() || c == '_'))
}

impl Dialect for Heidenhain {
    fn id(&self) -> DialectId {
        ID
    }

    fn title(&self) -> &'static str {
        "HEIDENHAIN DIN turning (MANUALplus 620, CNC PILOT 640)"
    }

    fn extension(&self) -> &'static str {
        "nc"
    }

    fn extensions(&self) -> &'static [&'static str] {
        &["nc", "ncs"]
    }

    fn legacy_encoding(&self) -> TextEncoding {
        TextEncoding::Standard(encoding_rs::WINDOWS_1252)
    }

    fn claim_line(&self, line: &str) -> Option<LineClaim> {
        let code = detect::code_part(line).to_ascii_uppercase();
        let incremental = code
            .split_whitespace()
            .any(|w| (w.starts_with("XI") || w.starts_with("ZI")) && w.len() > 2);
        // `MACHINING` and `END` alone are English words another dialect never writes as a line.
        let section = section_of(line).is_some() && !line.trim().is_empty();
        (is_name_line(line) || section || incremental).then_some(LineClaim {
            priority: 97,
            mark: LineMark::Mark,
        })
    }

    fn mark_description(&self) -> &'static str {
        "a HEIDENHAIN mark (a `%NAME.nc` name, a section line such as BEARBEITUNG/MACHINING or ENDE/END, Xi/Zi)"
    }

    fn tie_rank(&self) -> u8 {
        0
    }

    fn read_keeping(
        &self,
        src: &SourceFile,
        profile: &Profile,
        unsupported: Unsupported,
        keep: Keep<'_>,
    ) -> (Program, Vec<Diagnostic>) {
        let _ = unsupported;
        front::read(src, &profile.heidenhain, keep)
    }

    fn capabilities(&self, profile: &Profile) -> Capabilities {
        Capabilities {
            rows: [thread_rows(profile), machine_rows(profile)].concat(),
            numbers: "lengths to 0.001 mm (X a diameter, I a radius value), leads and feeds to 0.0001 mm, C to 0.001°; always in millimetres; `--round` rounds, reporting the largest deviation",
            renumbered: Vec::new(),
        }
    }

    fn refusal(&self, at: Occurrence, src: &SourceFile) -> Option<Diagnostic> {
        let (code, message, help) = match at.construct {
            Construct::Arc => (
                codes::HEIW_PROFILE,
                "an arc: which way G12/G13 turn on the machine the vendor shows only in a help graphic",
                "declare `arc_direction = \"iso\"` (G12 as LinuxCNC's G2) or `\"front-tool\"` in the profile's [heidenhain] section, as the machine's manual shows it",
            ),
            Construct::TaperPass => (
                codes::HEIW_PROFILE,
                "a taper thread pass: whether G33's run-in B is measured along Z or along the path is not published, and on a taper the start angle C depends on it",
                "declare `b_along = \"z\"` in the profile's [heidenhain] section if the machine measures B along Z (a test cut shows it), or convert the taper by hand",
            ),
            Construct::Entry | Construct::Runout | Construct::ContinuedChain => (
                codes::HEIW_NO_EQUIVALENT,
                "a thread pass of several synchronised moves (an entry, a runout, or a move that continues another): the vendor does not say whether a successive G33 (after P0) takes its own C and B",
                "cut this thread without the entry or runout in the source, or convert it by hand",
            ),
            Construct::IndexWaitInCut => (
                codes::HEIW_NO_EQUIVALENT,
                "a pass that waits for the index pulse where another thread move ended: consecutive G33 blocks would continue without waiting",
                "retract between the two moves in the source",
            ),
            Construct::SyncInfeed | Construct::SteepSync => (
                codes::HEIW_NO_EQUIVALENT,
                "a synchronised move along X or steeper than 45°: its lead would be along X (H1), where the measure of the run-in B is not published",
                "cut this thread with Z as the long axis, or convert it by hand",
            ),
            Construct::MistCoolant => (
                codes::HEIW_NO_EQUIVALENT,
                "mist coolant (M7): no HEIDENHAIN text ncthread holds gives its M code",
                "use flood coolant (M8) in the source, or add the machine's code by hand",
            ),
            Construct::CutterCompensation => (
                codes::HEIW_NO_EQUIVALENT,
                "cutter radius (tool nose) compensation: its radius and tip position are in the tool's data, which the program cannot state",
                "program the tool's path without compensation, or add G41/G42 by hand with the tool data checked",
            ),
            Construct::MachineCoordinates => (
                codes::HEIW_NO_EQUIVALENT,
                "a move in machine coordinates or to a stored position (G53, G28, G30): HEIDENHAIN's G53 is a zero point shift",
                "program the tool change position in the part's coordinates",
            ),
            Construct::WorkOffset => (
                codes::HEIW_NO_EQUIVALENT,
                "a work offset other than the default: HEIDENHAIN's zero point shifts (G51, G53–G56, G59) take their values in the program or the machine's tables, which ncthread cannot match to G55 … G59.3",
                "program in one work offset (G54) in the source",
            ),
            Construct::Tapping => (
                codes::HEIW_NO_EQUIVALENT,
                "rigid tapping depends on the machine's spindle settings",
                "tap this hole by hand on the HEIDENHAIN machine, or cut the thread with G33 passes",
            ),
            _ => return None,
        };
        Some(Diagnostic::new(code, message).at(src, at.span).help(help))
    }

    /// Its writer reads the program's name (kept from a HEIDENHAIN source).
    fn writer_reads(&self) -> crate::dialect::WriterReads {
        use crate::dialect::WriterReads;
        WriterReads {
            name: true,
            ..WriterReads::NOTHING
        }
    }

    fn item_writer<'a>(
        &self,
        _facts: &crate::dialect::Facts,
        program: &Program,
        src: &'a SourceFile,
        profile: &'a Profile,
        options: &WriteOptions,
    ) -> Box<dyn crate::dialect::ItemWriter + Send + 'a> {
        Box::new(emit::Items::new(
            program,
            src,
            &profile.heidenhain,
            options.renumber,
            options.round,
        ))
    }
}

/// The table's rows for the thread's forms.
fn thread_rows(profile: &Profile) -> Vec<Capability> {
    use Construct::*;

    let taper = if profile.heidenhain.b_along == Some(BAlong::Z) {
        Write::Yes("G33 X Z F B P C H0, F the lead along Z")
    } else {
        Write::No(codes::HEIW_PROFILE)
    };
    vec![
        row(
            ThreadCycle,
            Read::Yes("G31 F U B P, I or IC, V0–V2, one element … G80 (g31_clearance)"),
            Write::As("writes its passes as G33 blocks (G31 never)"),
        ),
        row(
            StartAngle,
            Read::Yes("G33 … B C"),
            Write::As("C after a run-in B of one lead (0°/180° unless c_sense)"),
        ),
        row(Entry, Read::No, Write::No(codes::HEIW_NO_EQUIVALENT)),
        row(Runout, Read::No, Write::No(codes::HEIW_NO_EQUIVALENT)),
        row(TaperPass, Read::Yes("G33 X Z F B C H0 (b_along)"), taper),
        row(
            ContinuedChain,
            Read::No,
            Write::No(codes::HEIW_NO_EQUIVALENT),
        ),
        row(
            IndexWaitInCut,
            Read::No,
            Write::No(codes::HEIW_NO_EQUIVALENT),
        ),
        row(SyncInfeed, Read::No, Write::No(codes::HEIW_NO_EQUIVALENT)),
        row(SteepSync, Read::No, Write::No(codes::HEIW_NO_EQUIVALENT)),
    ]
}

/// The table's rows for the rest of a part program.
fn machine_rows(profile: &Profile) -> Vec<Capability> {
    use Construct::*;

    let arc = if profile.heidenhain.arc_direction.is_some() {
        Write::Yes("G12/G13 X Z I K (absolute centre, I a radius value)")
    } else {
        Write::No(codes::HEIW_PROFILE)
    };
    vec![
        row(
            Arc,
            Read::Yes("G2/G3, G12/G13 with I K or R (arc_direction)"),
            arc,
        ),
        row(
            Chamfer45,
            Read::No,
            Write::As("writes it as a feed move (G1 X Z)"),
        ),
        row(Coolant, Read::Yes("M8/M9"), Write::Yes("M8/M9")),
        row(MistCoolant, Read::No, Write::No(codes::HEIW_NO_EQUIVALENT)),
        row(Stop, Read::Yes("M0/M1"), Write::Yes("M0/M1")),
        row(
            SurfaceSpeed,
            Read::Yes("G96 S, G26 S, G97 S"),
            Write::Yes("G26 S, G96 S, G97 S"),
        ),
        row(
            CutterCompensation,
            Read::No,
            Write::No(codes::HEIW_NO_EQUIVALENT),
        ),
        row(WorkOffset, Read::No, Write::No(codes::HEIW_NO_EQUIVALENT)),
        row(
            MachineCoordinates,
            Read::No,
            Write::No(codes::HEIW_NO_EQUIVALENT),
        ),
        row(Tapping, Read::No, Write::No(codes::HEIW_NO_EQUIVALENT)),
        row(Dwell, Read::Yes("G4 F (s)"), Write::Yes("G4 F (s)")),
        row(PerMinuteFeed, Read::Yes("G94"), Write::Yes("G94 F")),
        row(
            ToolOffset,
            Read::No,
            Write::As("T<pocket>: the tool's own offset only (HEIW002)"),
        ),
        row(Parameters, Read::No, Write::As("writes them as comments")),
        row(Repeat, Read::No, Write::As("writes the repeated moves out")),
        row(Comments, Read::Yes("`[…]`"), Write::As("`[…]`, ASCII")),
    ]
}

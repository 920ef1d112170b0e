//! Dialect `siemens`: SINUMERIK native turning (808D, 828D, 840D sl), ISO mode (`G291`) out
//! of scope. See ../shared/spec/siemens.md. No Siemens interpreter runs here, so the writer
//! uses only words whose meaning the vendor's text gives, writes every modal state it relies
//! on, and refuses the rest by name; the reader reads what the writer writes and a little
//! more (`=AC()`/`=IC()`, G91, G70, G94, M2/M17).

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

/// The SINUMERIK dialect's id.
pub const ID: DialectId = DialectId::new("siemens");

/// SINUMERIK native turning.
pub struct Siemens;

/// Words only a SINUMERIK program writes: `SF=`, `CR=`, `LIMS=`, `DIAMON`/`DIAMOF`,
/// `=AC(`/`=IC(`, `DITS=`/`DITE=`, its cycles.
fn siemens_word(code: &str) -> bool {
    let up = code.to_ascii_uppercase();
    [
        "SF=", "CR=", "LIMS=", "DIAMON", "DIAMOF", "=AC(", "=IC(", "DITS=", "DITE=", "CYCLE9",
    ]
    .iter()
    .any(|w| up.contains(w))
}

impl Dialect for Siemens {
    fn id(&self) -> DialectId {
        ID
    }

    fn title(&self) -> &'static str {
        "SINUMERIK native turning (808D, 828D, 840D sl)"
    }

    fn extension(&self) -> &'static str {
        "mpf"
    }

    fn extensions(&self) -> &'static [&'static str] {
        &["mpf", "spf"]
    }

    fn legacy_encoding(&self) -> TextEncoding {
        TextEncoding::Standard(encoding_rs::WINDOWS_1252)
    }

    fn claim_line(&self, line: &str) -> Option<LineClaim> {
        let up = line.trim_start().to_ascii_uppercase();
        let code = detect::code_part(line);
        if up.starts_with("%_N_") || up.starts_with(";$PATH=") || siemens_word(code) {
            return Some(LineClaim {
                priority: 97,
                mark: LineMark::Mark,
            });
        }
        // A `;` comment after code: LinuxCNC's as much (a shared mark).
        (code.len() < line.trim().len() && line.contains(';') && !line.contains('(')).then_some(
            LineClaim {
                priority: 90,
                mark: LineMark::Mark,
            },
        )
    }

    fn mark_description(&self) -> &'static str {
        "a SINUMERIK mark (a `%_N_…_MPF` name, `;$PATH=`, SF=, CR=, LIMS=, DIAMON/DIAMOF, =AC()/=IC())"
    }

    fn tie_rank(&self) -> u8 {
        0
    }

    fn output_feed_mode(&self) -> Option<crate::ir::FeedMode> {
        // The header: `G95`.
        Some(crate::ir::FeedMode::PerRev)
    }

    fn read_keeping(
        &self,
        src: &SourceFile,
        profile: &Profile,
        unsupported: Unsupported,
        keep: Keep<'_>,
    ) -> (Program, Vec<Diagnostic>) {
        let _ = unsupported;
        front::read(src, &profile.siemens, keep)
    }

    fn capabilities(&self, _profile: &Profile) -> Capabilities {
        Capabilities {
            rows: [thread_rows(), machine_rows()].concat(),
            numbers: "lengths to 0.001 mm (X a diameter under DIAMON, I a radius value), leads and feeds to 0.0001 mm, SF= to 0.001°; always in millimetres (G71); `--round` rounds, reporting the largest deviation",
            renumbered: Vec::new(),
        }
    }

    fn refusal(&self, at: Occurrence, src: &SourceFile) -> Option<Diagnostic> {
        let (message, help) = match at.construct {
            Construct::Entry | Construct::Runout | Construct::ContinuedChain => (
                "a thread pass of several synchronised moves (an entry, a runout, or a move that continues another): SINUMERIK would cut it as consecutive G33 blocks, whose chaining the sources ncthread holds do not define",
                "cut this thread without the entry or runout in the source, or convert it by hand",
            ),
            Construct::IndexWaitInCut => (
                "a pass that waits for the index pulse where another thread move ended: consecutive G33 blocks would continue without waiting",
                "retract between the two moves in the source",
            ),
            Construct::SyncInfeed | Construct::SteepSync => (
                "a synchronised move along X or steeper than 45°: its lead would be I, along X, which ncthread does not write",
                "cut this thread with Z as the long axis, or convert it by hand",
            ),
            Construct::MistCoolant => (
                "mist coolant (M7) is the machine builder's M code on a SINUMERIK lathe",
                "use flood coolant (M8) in the source, or add the machine's code by hand",
            ),
            Construct::CutterCompensation => (
                "cutter radius (tool nose) compensation: its radius and tip position are in the tool's data, which the program cannot state",
                "program the tool's path without compensation, or add G41/G42 by hand with the tool data checked",
            ),
            Construct::MachineCoordinates => (
                "a move in machine coordinates or to a stored position (G53, G28, G30): SINUMERIK's G53 and G74 have other meanings",
                "program the tool change position in the part's coordinates",
            ),
            Construct::Tapping => (
                "rigid tapping (SINUMERIK's G331/G332) depends on the machine's spindle settings",
                "tap this hole by hand on the SINUMERIK machine, or cut the thread with G33 passes",
            ),
            _ => return None,
        };
        Some(
            Diagnostic::new(codes::SINW_NO_EQUIVALENT, message)
                .at(src, at.span)
                .help(help),
        )
    }

    /// Its writer reads the program's name (kept from a SINUMERIK source).
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
        _profile: &'a Profile,
        options: &WriteOptions,
    ) -> Box<dyn crate::dialect::ItemWriter + Send + 'a> {
        Box::new(emit::Items::new(
            program,
            src,
            options.renumber,
            options.round,
        ))
    }
}

/// The table's rows for the thread's forms.
fn thread_rows() -> Vec<Capability> {
    use Construct::*;

    vec![
        row(
            ThreadCycle,
            Read::No,
            Write::As("writes its passes as G33 blocks (CYCLE97/CYCLE99 never)"),
        ),
        row(
            StartAngle,
            Read::Yes("G33 … SF="),
            Write::Yes("SF= on every G33"),
        ),
        row(Entry, Read::No, Write::No(codes::SINW_NO_EQUIVALENT)),
        row(Runout, Read::No, Write::No(codes::SINW_NO_EQUIVALENT)),
        row(
            TaperPass,
            Read::Yes("G33 X Z K (Z the long axis)"),
            Write::Yes("G33 X Z K, K the lead along Z"),
        ),
        row(
            ContinuedChain,
            Read::No,
            Write::No(codes::SINW_NO_EQUIVALENT),
        ),
        row(
            IndexWaitInCut,
            Read::No,
            Write::No(codes::SINW_NO_EQUIVALENT),
        ),
        row(SyncInfeed, Read::No, Write::No(codes::SINW_NO_EQUIVALENT)),
        row(SteepSync, Read::No, Write::No(codes::SINW_NO_EQUIVALENT)),
    ]
}

/// The table's rows for the rest of a part program.
fn machine_rows() -> Vec<Capability> {
    use Construct::*;

    vec![
        row(
            Arc,
            Read::Yes("G2/G3 X Z I K (I a radius value) or CR="),
            Write::Yes("G2/G3 X Z I K, I a radius value (CR= for a centre off the grid)"),
        ),
        row(
            Chamfer45,
            Read::No,
            Write::As("writes it as a feed move (G1 X Z)"),
        ),
        row(Coolant, Read::Yes("M8/M9"), Write::Yes("M8/M9")),
        row(MistCoolant, Read::No, Write::No(codes::SINW_NO_EQUIVALENT)),
        row(Stop, Read::Yes("M0/M1"), Write::Yes("M0/M1")),
        row(
            SurfaceSpeed,
            Read::Yes("G96 S LIMS=, G97 S"),
            Write::Yes("G96 S LIMS=, G97 S"),
        ),
        row(
            CutterCompensation,
            Read::No,
            Write::No(codes::SINW_NO_EQUIVALENT),
        ),
        row(
            WorkOffset,
            Read::Yes("G54–G57"),
            Write::As("G54–G57 (G58 and after: SINW002)"),
        ),
        row(
            MachineCoordinates,
            Read::No,
            Write::No(codes::SINW_NO_EQUIVALENT),
        ),
        row(Tapping, Read::No, Write::No(codes::SINW_NO_EQUIVALENT)),
        row(Dwell, Read::Yes("G4 F (s)"), Write::Yes("G4 F (s)")),
        row(PerMinuteFeed, Read::Yes("G94"), Write::Yes("G94")),
        row(ToolOffset, Read::Yes("T D"), Write::Yes("T D")),
        row(Parameters, Read::No, Write::As("writes them as comments")),
        row(Repeat, Read::No, Write::As("writes the repeated moves out")),
        row(Comments, Read::Yes("`;`"), Write::As("`;`, ASCII")),
    ]
}

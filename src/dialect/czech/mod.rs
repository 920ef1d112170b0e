//! Dialect `czech`: the Czech lathe control of manual chapter 5 (G33 with F, I, J, E,
//! R-parameter angles, `FRnn`).

pub mod codes;
mod emit;
mod front;
pub mod profile;
pub mod syntax;

pub use front::Options;

use super::capabilities::{Capabilities, Capability, Construct, Read, Write, row};
use super::{Dialect, DialectId, Keep, LineClaim, LineMark, Unsupported, WriteOptions, detect};
use crate::diag::Diagnostic;
use crate::dialect::capabilities::Occurrence;
use crate::encoding::TextEncoding;
use crate::ir::Program;
use crate::profile::{CzechArcs, CzechDwell, Profile};
use crate::source::SourceFile;

/// The czech control's id.
pub const ID: DialectId = DialectId::new("czech");

/// The czech control.
pub struct Czech;

impl Dialect for Czech {
    fn id(&self) -> DialectId {
        ID
    }

    fn title(&self) -> &'static str {
        "the czech control"
    }

    fn extension(&self) -> &'static str {
        "ncp"
    }

    fn extensions(&self) -> &'static [&'static str] {
        &["nc", "ncp", "cnc"]
    }

    fn legacy_encoding(&self) -> TextEncoding {
        TextEncoding::Standard(encoding_rs::WINDOWS_1250)
    }

    fn claim_line(&self, line: &str) -> Option<LineClaim> {
        // A `"` comment (not a `"` inside another dialect's `( )` or `;` comment: `(1/2"
        // BORING BAR)`), and R<nn>= assignments, FRnn and & words.
        let quote = line.find(['"', '“', '„']);
        let other = line.find(['(', ';']);
        if quote.is_some_and(|q| other.is_none_or(|o| q < o)) {
            return Some(LineClaim {
                priority: 100,
                mark: LineMark::Mark,
            });
        }
        detect::code_words(line)
            .iter()
            .any(|w| {
                (w.starts_with('R') && w.contains('=')) || w.starts_with('&') || w.starts_with("FR")
            })
            .then_some(LineClaim {
                priority: 70,
                mark: LineMark::Mark,
            })
    }

    fn mark_description(&self) -> &'static str {
        "a czech mark (a `\"` comment, `R<nn>=`, `FR<nn>` or `&`)"
    }

    fn fallback_reason(&self) -> Option<&'static str> {
        Some(
            "no dialect's marks (НЦ-31 `*`/`~`/`@`, czech `\"` comments or R/FR/& words, ISO `( )` comments or G33 … K); decimal words read as czech",
        )
    }

    fn tie_rank(&self) -> u8 {
        2
    }

    fn read_keeping(
        &self,
        src: &SourceFile,
        profile: &Profile,
        unsupported: Unsupported,
        keep: Keep<'_>,
    ) -> (Program, Vec<Diagnostic>) {
        front::read(
            src,
            &profile.czech,
            &Options {
                unsupported,
                profile_name: profile.name.clone(),
            },
            keep,
        )
    }

    fn capabilities(&self, profile: &Profile) -> Capabilities {
        Capabilities {
            rows: [thread_rows(), machine_rows(profile)].concat(),
            numbers: "lengths to 0.001 mm, leads to 0.0001 mm (over 99.99 through FRnn); `--round` rounds, reporting the largest deviation",
            renumbered: Vec::new(),
        }
    }

    fn refusal(&self, at: Occurrence, src: &SourceFile) -> Option<Diagnostic> {
        let (code, message, help) = match at.construct {
            Construct::Arc => (
                codes::CZW_NO_EQUIVALENT,
                "an arc (G2/G3) has no form that the czech seed documents",
                "arc forms differ between controls of that era: if the machine's manual gives one, set `arcs` (\"ik-radius\", \"ik-diameter\" or \"r\") in the profile's [czech] section",
            ),
            Construct::Coolant => (
                codes::CZW_NO_EQUIVALENT,
                "coolant (M8/M9) has no form that the czech seed documents",
                "if the machine's manual gives M08/M09, set `coolant = \"m08-m09\"` in the profile's [czech] section",
            ),
            Construct::MistCoolant => (
                codes::CZW_NO_EQUIVALENT,
                "mist coolant (M7) has no form that the czech seed documents",
                "if the machine's manual gives M07, set `mist = \"m07\"` (with `coolant = \"m08-m09\"`) in the profile's [czech] section",
            ),
            Construct::CutterCompensation => (
                codes::CZW_NO_EQUIVALENT,
                "cutter radius compensation (G41/G42) has no form that the czech seed documents",
                "program the tool nose's path in the source (compensated by the CAM system), or add the compensation by hand in this machine's form",
            ),
            Construct::WorkOffset => (
                codes::CZW_NO_EQUIVALENT,
                "a work offset other than the default (G55 … G59.3) has no form that the czech seed documents",
                "program the part in the default coordinate system (G54), or add the offset by hand in this machine's form",
            ),
            Construct::MachineCoordinates => (
                codes::CZW_NO_EQUIVALENT,
                "a move in machine coordinates or to a reference point (G53, G28, G30) has no form that the czech seed documents",
                "program the tool change position in the part's coordinates, or add the reference move by hand in this machine's form",
            ),
            Construct::SurfaceSpeed => (
                codes::CZW_NO_EQUIVALENT,
                "a constant surface speed (G96) has no form that the czech seed documents",
                "if the machine's manual gives G96/G97, set `surface_speed = \"g96-g97\"` in the profile's [czech] section (else program the speed in rpm, G97 S…, in the source)",
            ),
            Construct::Stop => (
                codes::CZW_NO_EQUIVALENT,
                "a program stop (M0/M1) has no form that the czech seed documents",
                "the czech manual's chapter documents thread cutting only; add the stop by hand in this machine's form",
            ),
            Construct::Tapping => (
                codes::CZW_NO_EQUIVALENT,
                "a rigid tapping cycle has no documented form on the czech control",
                "the czech manual's chapter documents thread cutting with G33 only (its G84 cycle is undocumented); tap this hole another way",
            ),
            Construct::Dwell => (
                codes::CZW_NO_EQUIVALENT,
                "a dwell (G4) has no form that the czech seed documents",
                "if the machine's manual gives one, set `dwell` (\"g04-x-seconds\", \"g04-f-seconds\" or \"g04-p-milliseconds\") in the profile's [czech] section",
            ),
            Construct::SyncInfeed => (
                codes::CZW_NO_EQUIVALENT,
                "the pass starts with a synchronised move along X (LinuxCNC's G76 infeed before an entry taper, or a G33 along X), which the czech control has no documented form for",
                "the czech G33 synchronises the thread's own travel; cut this thread without the synchronised infeed (a G76 without L1/L3) or by hand",
            ),
            Construct::ContinuedChain => (
                codes::CZW_CONTINUE,
                "this thread move continues the one before it without waiting for the index pulse; every czech G33 block waits for the pulse, so the tool would stand in the cut",
                "the czech control cuts one synchronised motion per block: a thread with its entry (E) and runout (J); write the source's thread that way, or retract between the moves",
            ),
            _ => return None,
        };
        Some(Diagnostic::new(code, message).at(src, at.span).help(help))
    }

    /// Its writer reads the parameters a program assigns (not free for its leads).
    fn writer_reads(&self) -> crate::dialect::WriterReads {
        use crate::dialect::WriterReads;
        WriterReads {
            params: true,
            ..WriterReads::NOTHING
        }
    }

    fn item_writer<'a>(
        &self,
        facts: &crate::dialect::Facts,
        program: &Program,
        src: &'a SourceFile,
        profile: &'a Profile,
        options: &WriteOptions,
    ) -> Box<dyn crate::dialect::ItemWriter + Send + 'a> {
        Box::new(emit::Items::new(
            facts,
            program.dialect,
            src,
            profile,
            options.renumber,
            options.round,
        ))
    }
}

/// The table's rows for the thread's forms (cycles, passes, their tapers and chains).
fn thread_rows() -> Vec<Capability> {
    use Construct::*;
    vec![
        row(
            ThreadCycle,
            Read::No,
            Write::As("writes its passes, a comment block each"),
        ),
        row(StartAngle, Read::Yes("I"), Write::Yes("I")),
        row(
            Entry,
            Read::Yes("E, its angle from machine constant 8"),
            Write::As("writes E when the profile's constant 8 gives its angle (else CZW003)"),
        ),
        row(
            Runout,
            Read::Yes("J, its angle from machine constant 8"),
            Write::As("writes J when the profile's constant 8 gives its angle (else CZW003)"),
        ),
        row(TaperPass, Read::Yes("G33 X Z"), Write::Yes("G33 X Z")),
        row(ContinuedChain, Read::No, Write::No(codes::CZW_CONTINUE)),
        row(
            IndexWaitInCut,
            Read::Yes("a G33 block right after another"),
            Write::Yes("G33 … I"),
        ),
        row(SyncInfeed, Read::No, Write::No(codes::CZW_NO_EQUIVALENT)),
    ]
}

/// The table's rows for the rest of a part program, as far as the profile gives their forms.
fn machine_rows(profile: &Profile) -> Vec<Capability> {
    use Construct::*;

    vec![
        match profile.czech.arcs {
            CzechArcs::None => row(Arc, Read::No, Write::No(codes::CZW_NO_EQUIVALENT)),
            CzechArcs::IkRadius => row(
                Arc,
                Read::Yes("G02/G03 X Z I K, I a radius"),
                Write::Yes("G02/G03 X Z I K, I a radius"),
            ),
            CzechArcs::IkDiameter => row(
                Arc,
                Read::Yes("G02/G03 X Z I K, I a diameter"),
                Write::Yes("G02/G03 X Z I K, I a diameter"),
            ),
            CzechArcs::Radius => row(
                Arc,
                Read::Yes("G02/G03 X Z R"),
                Write::As("G02/G03 X Z R (not a full circle)"),
            ),
        },
        row(
            Chamfer45,
            Read::No,
            Write::As("writes it as a feed move (G01 X Z)"),
        ),
        if profile.czech.coolant {
            row(Coolant, Read::Yes("M08/M09"), Write::Yes("M08/M09"))
        } else {
            row(Coolant, Read::No, Write::No(codes::CZW_NO_EQUIVALENT))
        },
        if profile.czech.mist {
            row(MistCoolant, Read::Yes("M07"), Write::Yes("M07"))
        } else {
            row(MistCoolant, Read::No, Write::No(codes::CZW_NO_EQUIVALENT))
        },
        row(Stop, Read::No, Write::No(codes::CZW_NO_EQUIVALENT)),
        if profile.czech.surface_speed {
            row(
                SurfaceSpeed,
                Read::Yes("G96 S (m/min), G97 S"),
                Write::As("G96 S (m/min), G97 S; no speed limit word (a G96 with one: CZW002)"),
            )
        } else {
            row(SurfaceSpeed, Read::No, Write::No(codes::CZW_NO_EQUIVALENT))
        },
        row(
            CutterCompensation,
            Read::No,
            Write::No(codes::CZW_NO_EQUIVALENT),
        ),
        row(WorkOffset, Read::No, Write::No(codes::CZW_NO_EQUIVALENT)),
        row(
            MachineCoordinates,
            Read::No,
            Write::No(codes::CZW_NO_EQUIVALENT),
        ),
        row(Tapping, Read::No, Write::No(codes::CZW_NO_EQUIVALENT)),
        match profile.czech.dwell {
            CzechDwell::None => row(Dwell, Read::No, Write::No(codes::CZW_NO_EQUIVALENT)),
            CzechDwell::XSeconds => row(Dwell, Read::Yes("G04 X (s)"), Write::Yes("G04 X (s)")),
            CzechDwell::FSeconds => row(Dwell, Read::Yes("G04 F (s)"), Write::Yes("G04 F (s)")),
            CzechDwell::PMilliseconds => row(
                Dwell,
                Read::Yes("G04 P (ms)"),
                Write::As("G04 P (ms; a time off the millisecond: CZW001)"),
            ),
        },
        row(PerMinuteFeed, Read::Yes("G94"), Write::Yes("G94")),
        row(ToolOffset, Read::Yes("D"), Write::Yes("D")),
        row(Parameters, Read::Yes("R<nn>="), Write::Yes("R<nn>=")),
        row(Repeat, Read::No, Write::As("writes the repeated moves out")),
        row(Comments, Read::Yes("\""), Write::Yes("\"")),
    ]
}

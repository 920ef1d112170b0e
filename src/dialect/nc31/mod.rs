//! Dialect `nc31`: the Электроника НЦ-31 (scaled integer words, one word per frame, `*`
//! groups, `~` rapid, `@` incremental, G31 multi-pass cycle, G32 single pass, G33 tapping).

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
use crate::profile::Profile;
use crate::source::SourceFile;

/// The НЦ-31's id.
pub const ID: DialectId = DialectId::new("nc31");

/// The Электроника НЦ-31.
pub struct Nc31;

impl Dialect for Nc31 {
    fn id(&self) -> DialectId {
        ID
    }

    fn title(&self) -> &'static str {
        "the НЦ-31"
    }

    fn extension(&self) -> &'static str {
        "nc31"
    }

    fn extensions(&self) -> &'static [&'static str] {
        &["nc", "nc31"]
    }

    fn legacy_encoding(&self) -> TextEncoding {
        TextEncoding::Standard(encoding_rs::IBM866)
    }

    fn claim_line(&self, line: &str) -> Option<LineClaim> {
        // A comment line: PC archives of the НЦ-31 and ISO programs both have them.
        if line.starts_with('(') {
            return Some(LineClaim {
                priority: 95,
                mark: LineMark::Neutral,
            });
        }
        let words = detect::code_words(line);
        let modifiers = detect::code_part(line)
            .chars()
            .any(detect::is_nc31_modifier);
        let integer = |w: &String| {
            w.len() > 1
                && w[1..]
                    .trim_start_matches(['+', '-'])
                    .bytes()
                    .all(|b| b.is_ascii_digit())
        };
        if words.len() == 1 && integer(&words[0]) {
            return Some(LineClaim {
                priority: 80,
                mark: if modifiers {
                    LineMark::Mark
                } else {
                    LineMark::Weak
                },
            });
        }
        modifiers.then_some(LineClaim {
            priority: 50,
            mark: LineMark::Mark,
        })
    }

    fn mark_description(&self) -> &'static str {
        "a frame with the НЦ-31's `*`/`~`/`@` modifiers"
    }

    fn weak_reason(&self) -> Option<&'static str> {
        Some(
            "every frame is one whole-number word, as on the НЦ-31, but no `*`, `~` or `@` confirms it",
        )
    }

    fn plain_lines_contradict(&self) -> bool {
        true
    }

    fn tie_rank(&self) -> u8 {
        3
    }

    fn read_keeping(
        &self,
        src: &SourceFile,
        profile: &Profile,
        unsupported: Unsupported,
        keep: Keep<'_>,
    ) -> (Program, Vec<Diagnostic>) {
        front::read(src, &profile.nc31, &Options { unsupported }, keep)
    }

    fn capabilities(&self, profile: &Profile) -> Capabilities {
        Capabilities {
            rows: [thread_rows(), machine_rows(profile)].concat(),
            numbers: "whole units of the profile (X, Z, P 0.01 mm; leads 0.0001 mm; feeds 0.01 mm/rev); `--round` rounds, reporting the largest deviation",
            renumbered: Vec::new(),
        }
    }

    fn refusal(&self, at: Occurrence, src: &SourceFile) -> Option<Diagnostic> {
        let (message, help) = match at.construct {
            Construct::Coolant => (
                "coolant (M8/M9) has no form that the НЦ-31 guide documents",
                "if the machine takes M8/M9 (one shop's programs use them), set `coolant = \"m8-m9\"` in the profile's [nc31] section",
            ),
            Construct::MistCoolant => (
                "mist coolant (M7) has no documented form on the НЦ-31",
                "the НЦ-31 switches one coolant circuit (M8/M9 where the profile enables it); program flood coolant in the source",
            ),
            Construct::CutterCompensation => (
                "cutter radius compensation (G41/G42) has no documented form on the НЦ-31",
                "program the tool nose's path in the source (compensated by the CAM system)",
            ),
            Construct::WorkOffset => (
                "a work offset other than the default (G55 … G59.3) has no documented form on the НЦ-31",
                "program the part in the default coordinate system (G54)",
            ),
            Construct::MachineCoordinates => (
                "a move in machine coordinates or to a reference point (G53, G28, G30) has no documented form on the НЦ-31",
                "program the tool change position in the part's coordinates",
            ),
            Construct::SurfaceSpeed => (
                "a constant surface speed (G96) has no documented form on the НЦ-31",
                "the НЦ-31 turns at S rpm in a speed range; program the speed in rpm (G97 S…) in the source",
            ),
            Construct::Stop => (
                "a program stop (M0/M1) has no documented form on the НЦ-31",
                "the guide documents G31, G32 and G33 only; add the stop by hand where the control takes one",
            ),
            Construct::Arc => (
                "an arc (G2/G3) has no form that the НЦ-31 guide documents",
                "if the machine takes G2/G3 groups with two P offsets (one shop's programs do), set `arcs = \"g2-g3-p\"` and `arc_direction` (\"front-tool\" or \"iso\") in the profile's [nc31] section",
            ),
            Construct::Dwell => (
                "a dwell (G4) has no documented form on the НЦ-31",
                "the guide documents G31, G32 and G33 only; remove the dwell or add it by hand",
            ),
            Construct::PerMinuteFeed => (
                "a feed in mm per minute; the НЦ-31 feeds in mm per revolution",
                "program the feed per revolution (G95) in the source",
            ),
            // What G32 cannot cut is refused pass by pass while writing (NCW003).
            _ => return None,
        };
        Some(
            Diagnostic::new(codes::NCW_NO_EQUIVALENT, message)
                .at(src, at.span)
                .help(help),
        )
    }

    /// Its writer reads only the program's dialect.
    fn writer_reads(&self) -> crate::dialect::WriterReads {
        use crate::dialect::WriterReads;
        WriterReads::NOTHING
    }

    fn item_writer<'a>(
        &self,
        _facts: &crate::dialect::Facts,
        program: &Program,
        src: &'a SourceFile,
        profile: &'a Profile,
        options: &WriteOptions,
    ) -> Box<dyn crate::dialect::ItemWriter + Send + 'a> {
        Box::new(emit::Items::new(program.dialect, src, profile, options))
    }
}

/// The table's rows for the thread's forms (cycles, passes, their tapers and chains).
fn thread_rows() -> Vec<Capability> {
    use Construct::*;

    vec![
        row(
            ThreadCycle,
            Read::Yes("G31"),
            Write::As(
                "writes G31 when the profile's parameters 6 and 7, retract and schedule reproduce it, else G32 passes",
            ),
        ),
        row(StartAngle, Read::No, Write::No(codes::NCW_PASS)),
        row(Entry, Read::No, Write::No(codes::NCW_PASS)),
        row(
            Runout,
            Read::Yes("in G31: parameter 7"),
            Write::As(
                "writes it only inside a G31 kept whole (parameter 7); refuses it on a pass (NCW003)",
            ),
        ),
        row(
            TaperPass,
            Read::Yes("in G31: the third P"),
            Write::As(
                "writes it only inside a G31 kept whole (the third P); refuses it on a pass (NCW003)",
            ),
        ),
        row(ContinuedChain, Read::No, Write::No(codes::NCW_PASS)),
        row(
            IndexWaitInCut,
            Read::Yes("a G32 group right after another"),
            Write::Yes("G32"),
        ),
        row(SyncInfeed, Read::No, Write::No(codes::NCW_PASS)),
        row(
            Tapping,
            Read::Yes("G33"),
            Write::Yes("G33, `G33 @` for point C"),
        ),
        row(Dwell, Read::No, Write::No(codes::NCW_NO_EQUIVALENT)),
    ]
}

/// The table's rows for the rest of a part program, as far as the profile gives their forms.
fn machine_rows(profile: &Profile) -> Vec<Capability> {
    use Construct::*;

    vec![
        if profile.nc31.arcs && profile.nc31.arc_direction.is_some() {
            row(
                Arc,
                Read::Yes("G2/G3 X Z P P, G12/G13 X Z"),
                Write::As("G2/G3 X Z P P, a group per quadrant"),
            )
        } else {
            row(Arc, Read::No, Write::No(codes::NCW_NO_EQUIVALENT))
        },
        row(
            Chamfer45,
            Read::Yes("X or Z with `+45`/`-45`, closed by F"),
            if profile.nc31.chamfer45 {
                Write::As(
                    "writes `X…±45 *` + `F…` where start, end and feed are whole units, else X and Z frames",
                )
            } else {
                Write::As(
                    "writes X and Z frames (`X…±45 *` + `F…` with the profile's chamfer45 = true)",
                )
            },
        ),
        if profile.nc31.coolant {
            row(Coolant, Read::Yes("M8/M9"), Write::Yes("M8/M9"))
        } else {
            row(Coolant, Read::No, Write::No(codes::NCW_NO_EQUIVALENT))
        },
        row(MistCoolant, Read::No, Write::No(codes::NCW_NO_EQUIVALENT)),
        row(Stop, Read::No, Write::No(codes::NCW_NO_EQUIVALENT)),
        row(SurfaceSpeed, Read::No, Write::No(codes::NCW_NO_EQUIVALENT)),
        row(
            CutterCompensation,
            Read::No,
            Write::No(codes::NCW_NO_EQUIVALENT),
        ),
        row(WorkOffset, Read::No, Write::No(codes::NCW_NO_EQUIVALENT)),
        row(
            MachineCoordinates,
            Read::No,
            Write::No(codes::NCW_NO_EQUIVALENT),
        ),
        row(PerMinuteFeed, Read::No, Write::No(codes::NCW_NO_EQUIVALENT)),
        row(
            ToolOffset,
            Read::No,
            Write::As("leaves it out with NCW004 (the T word's turret position carries it)"),
        ),
        row(
            Parameters,
            Read::No,
            Write::As("leaves them out with NCW004 (their values are written where used)"),
        ),
        row(
            Repeat,
            if profile.nc31.repeat_g25 {
                Read::Yes("G25 P P, unrolled")
            } else {
                Read::No
            },
            Write::As("writes the repeated frames out, never G25"),
        ),
        row(
            Comments,
            Read::Yes("`(` lines"),
            Write::As("leaves them out with NCW007, or writes `(` lines with --nc31-comments"),
        ),
    ]
}

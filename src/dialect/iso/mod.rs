//! Dialect `iso`: RS274/NGC as LinuxCNC reads it. A target checked against LinuxCNC's
//! `rs274`, and a source (hand conversions to check, CAM programs to move to old machines).

pub mod codes;
mod control;
mod emit;
pub(crate) mod expr;
mod front;
#[cfg(test)]
pub(crate) use front::FOLLOWED;
mod gcode;
mod long_double;
pub mod profile;
mod syntax;

pub use front::Options;

use super::capabilities::{Capabilities, Construct, Read, Write, row};
use super::{Dialect, DialectId, Keep, LineClaim, LineMark, Unsupported, WriteOptions, detect};
use crate::diag::Diagnostic;
use crate::dialect::capabilities::Occurrence;
use crate::encoding::TextEncoding;
use crate::ir::Program;
use crate::profile::Profile;
use crate::source::SourceFile;

/// ISO G-code's id.
pub const ID: DialectId = DialectId::new("iso");

/// RS274/NGC as LinuxCNC reads it.
pub struct Iso;

/// The reader's options from the machine profile.
fn options(profile: &Profile, unsupported: Unsupported) -> Options {
    Options {
        unsupported,
        block_delete: profile.iso.block_delete,
        subroutine_path: profile.iso.subroutine_path.clone(),
    }
}

impl Dialect for Iso {
    fn id(&self) -> DialectId {
        ID
    }

    fn title(&self) -> &'static str {
        "LinuxCNC (RS274/NGC)"
    }

    fn extension(&self) -> &'static str {
        "ngc"
    }

    fn extensions(&self) -> &'static [&'static str] {
        &["ngc", "nc", "tap"]
    }

    fn legacy_encoding(&self) -> TextEncoding {
        TextEncoding::Standard(encoding_rs::WINDOWS_1252)
    }

    fn claim_line(&self, line: &str) -> Option<LineClaim> {
        if line.starts_with('(') {
            return Some(LineClaim {
                priority: 95,
                mark: LineMark::Neutral,
            });
        }
        // A `( )` or `;` comment after code.
        if detect::code_part(line).len() < line.len() {
            return Some(LineClaim {
                priority: 90,
                mark: LineMark::Mark,
            });
        }
        // LinuxCNC's macro language: a parameter (`#1`, `#<name>`), an expression (`[`) or
        // an O-word (`o<name> …`, `o100 while …`); no other dialect writes these.
        let code = detect::code_part(line).trim_start().to_ascii_lowercase();
        let macro_mark = code.contains('[')
            || code
                .as_bytes()
                .windows(2)
                .any(|w| w[0] == b'#' && (w[1].is_ascii_digit() || w[1] == b'<' || w[1] == b'['))
            || code.starts_with("o<")
            || (code.starts_with('o')
                && code[1..]
                    .trim_start()
                    .starts_with(|c: char| c.is_ascii_digit())
                && [
                    "sub", "endsub", "call", "return", "if", "else", "while", "do", "repeat",
                    "break", "continue",
                ]
                .iter()
                .any(|k| code.contains(k)));
        if macro_mark {
            return Some(LineClaim {
                priority: 90,
                mark: LineMark::Mark,
            });
        }
        let words = detect::code_words(line);
        // A drilling cycle with G98/G99: LinuxCNC's retract mode, or FANUC's feed mode before
        // its face drilling cycles (G83, G85, G89). A shared mark: FANUC's claim on G98/G99
        // alone does not decide the line.
        let drilling = words
            .iter()
            .any(|w| matches!(w.as_str(), "G73" | "G81" | "G82" | "G83" | "G85" | "G89"));
        if drilling && words.iter().any(|w| w == "G98" || w == "G99") {
            return Some(LineClaim {
                priority: 96,
                mark: LineMark::Mark,
            });
        }
        // Its own words, and those it shares with FANUC (a mark FANUC claims too).
        let iso_word = detect::iso_only(&words) || detect::iso_fanuc_shared(&words);
        iso_word.then_some(LineClaim {
            priority: 60,
            mark: LineMark::Mark,
        })
    }

    fn mark_description(&self) -> &'static str {
        "an ISO mark (a `( )` or `;` comment after code, a parameter, an expression or an O-word, G33 with K, or a G7/G33.1/G76/G81/G82 word)"
    }

    fn tie_rank(&self) -> u8 {
        1
    }

    fn linuxcnc_reads(&self) -> bool {
        true
    }

    fn says_inches(&self) -> bool {
        true
    }

    fn output_feed_mode(&self) -> Option<crate::ir::FeedMode> {
        // The header: `G7 G18 G21 G90 G95`.
        Some(crate::ir::FeedMode::PerRev)
    }

    fn read_keeping(
        &self,
        src: &SourceFile,
        profile: &Profile,
        unsupported: Unsupported,
        keep: Keep<'_>,
    ) -> (Program, Vec<Diagnostic>) {
        front::read(src, &options(profile, unsupported), keep)
    }

    fn capabilities(&self, _profile: &Profile) -> Capabilities {
        use Construct::*;
        Capabilities {
            rows: vec![
                row(
                    ThreadCycle,
                    Read::Yes("G76"),
                    Write::As("writes its passes"),
                ),
                row(
                    StartAngle,
                    Read::No,
                    Write::As("writes an earlier start on the same helix"),
                ),
                row(
                    Entry,
                    Read::Yes("G76 E L1, chained G33"),
                    Write::As("writes a chained G33"),
                ),
                row(
                    Runout,
                    Read::Yes("G76 E L2, chained G33"),
                    Write::As("writes a chained G33"),
                ),
                row(TaperPass, Read::Yes("G33 X Z K"), Write::Yes("G33 X Z K")),
                row(
                    ContinuedChain,
                    Read::Yes("consecutive G33"),
                    Write::Yes("consecutive G33"),
                ),
                row(IndexWaitInCut, Read::No, Write::No(codes::ISOW_INDEX_WAIT)),
                row(
                    SyncInfeed,
                    Read::Yes("G33 along X, G76 L1/L3"),
                    Write::Yes("G33 along X"),
                ),
                row(Tapping, Read::Yes("G33.1"), Write::Yes("G33.1")),
                row(Dwell, Read::Yes("G4"), Write::Yes("G4")),
                row(
                    Arc,
                    Read::Yes("G2/G3 with I K or R"),
                    Write::Yes("G2/G3 X Z I K"),
                ),
                row(
                    Chamfer45,
                    Read::No,
                    Write::As("writes it as a feed move (G1 X Z)"),
                ),
                row(Coolant, Read::Yes("M8/M9"), Write::Yes("M8/M9")),
                row(MistCoolant, Read::Yes("M7"), Write::Yes("M7")),
                row(Stop, Read::Yes("M0/M1"), Write::Yes("M0/M1")),
                row(
                    SurfaceSpeed,
                    Read::Yes("G96 D S, G97"),
                    Write::Yes("G96 D S, G97"),
                ),
                row(
                    CutterCompensation,
                    Read::Yes("G40, G41/G42 D, G41.1/G42.1 D L"),
                    Write::Yes("G40, G41/G42 D, G41.1/G42.1 D L"),
                ),
                row(
                    WorkOffset,
                    Read::Yes("G54 … G59.3"),
                    Write::Yes("G54 … G59.3"),
                ),
                row(
                    MachineCoordinates,
                    Read::Yes("G53 G0/G1, G28/G30 (.1)"),
                    Write::Yes("G53 G0/G1, G28/G30 (.1)"),
                ),
                row(PerMinuteFeed, Read::Yes("G94"), Write::Yes("G94")),
                row(ToolOffset, Read::Yes("G43 H"), Write::Yes("G43 H")),
                row(Parameters, Read::No, Write::As("writes them as comments")),
                row(Repeat, Read::No, Write::As("writes the repeated moves out")),
                row(Comments, Read::Yes("`( )`, `;`"), Write::Yes("`( )`")),
            ],
            numbers: "lengths to 0.00001 mm, an inch program's in inches (0.0001 in; a computed point to 0.000001 in, ISOW007), leads exact (a taper's K with the digits that read back to 10⁻¹² mm)",
            renumbered: Vec::new(),
        }
    }

    fn refusal(&self, at: Occurrence, src: &SourceFile) -> Option<Diagnostic> {
        if at.construct != Construct::IndexWaitInCut {
            return None;
        }
        let angle = at
            .angle
            .filter(|a| *a != crate::fixed::Angle::ZERO)
            .map_or(String::new(), |a| format!(" and {a}°"));
        Some(
            Diagnostic::new(
                codes::ISOW_INDEX_WAIT,
                format!("this pass waits for the index pulse{angle} where the thread move before it ended, with the tool in the cut; LinuxCNC continues consecutive G33 moves without waiting"),
            )
            .at(src, at.span)
            .help("retract and return between the two moves in the source, or make the second continue the first (the same helix)"),
        )
    }

    /// Its writer reads whether the program has an arc (its header's `G91.1`) and its unit.
    fn writer_reads(&self) -> crate::dialect::WriterReads {
        use crate::dialect::WriterReads;
        WriterReads {
            arcs: true,
            inch: true,
            ..WriterReads::NOTHING
        }
    }

    fn item_writer<'a>(
        &self,
        facts: &crate::dialect::Facts,
        program: &Program,
        src: &'a SourceFile,
        profile: &'a Profile,
        _options: &WriteOptions,
    ) -> Box<dyn crate::dialect::ItemWriter + Send + 'a> {
        Box::new(emit::Items::new(facts, program, src, profile))
    }
}

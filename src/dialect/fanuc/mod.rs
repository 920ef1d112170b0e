//! Dialect `fanuc`: FANUC lathe G-code, system A (Series 0i-TF and the controls that copy
//! it: Haas, Mitsubishi and many others). See ../shared/spec/fanuc.md.

pub mod codes;
mod emit;
mod front;
#[cfg(test)]
pub(crate) use front::FOLLOWED;
mod macros;
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

/// The FANUC dialect's id.
pub const ID: DialectId = DialectId::new("fanuc");

/// FANUC lathe G-code.
pub struct Fanuc;

/// Whether a line's words are FANUC's alone: G32, G50, G98/G99, G77–G79, a G92 with F, a
/// four-digit T, U or W words.
fn fanuc_word(words: &[String]) -> bool {
    let g92_with_f = words.iter().any(|w| w == "G92") && words.iter().any(|w| w.starts_with('F'));
    let has = |g: &str| words.iter().any(|w| w == g);
    let p = words.iter().find(|w| w.starts_with('P'));
    // G76 P010060 (mm rr aa) and G76 X… F… are FANUC's two-block G76 (LinuxCNC's has P with a
    // point, and no F); G70–G73 with P name a contour's first block (LinuxCNC's, only Q).
    let g76 = has("G76")
        && (words.iter().any(|w| w.starts_with('F'))
            || p.is_some_and(|p| p.len() == 7 && p[1..].bytes().all(|b| b.is_ascii_digit())));
    // G74/G75 with P are the peck cycles' second block; G72–G75 with P are system C's
    // multiple repetitive cycles too (LinuxCNC has no G74/G75).
    let g7x_p = ["G70", "G71", "G72", "G73", "G74", "G75"]
        .iter()
        .any(|g| has(g))
        && p.is_some();
    // System B: G92 S, the spindle limit.
    let g92_s = has("G92") && words.iter().any(|w| w.starts_with('S'));
    // System C's single cycles: G20/G21/G24 with an end and F, no motion code (LinuxCNC's
    // units switch stands in a header, or beside the move's G code).
    let c_cycle = ["G20", "G21", "G24"].iter().any(|g| has(g))
        && words.iter().any(|w| w.starts_with('F'))
        && words.iter().any(|w| w.starts_with(['X', 'Z', 'U', 'W']))
        && !words.iter().any(|w| {
            matches!(
                w.as_str(),
                "G0" | "G00" | "G1" | "G01" | "G2" | "G02" | "G3" | "G03" | "G33"
            )
        });
    g92_with_f
        || g92_s
        || c_cycle
        || g76
        || g7x_p
        || words.iter().any(|w| {
            // G77–G79: systems B's and C's cycles, no LinuxCNC code.
            matches!(
                w.as_str(),
                "G32" | "G50" | "G98" | "G99" | "G77" | "G78" | "G79"
            ) || (w.len() == 5 && w.starts_with('T') && w[1..].bytes().all(|b| b.is_ascii_digit()))
                || ((w.starts_with('U') || w.starts_with('W')) && w.contains('.'))
        })
}

/// Custom macro B: an `IF`, `WHILE`, `GOTO`, `DO` or `END` statement, `G65` and `M98` are
/// FANUC's alone (LinuxCNC writes its control flow after an O-word and has no G65); a
/// variable (`#1`, `#[…]`) or an expression (`[`) is LinuxCNC's as much (a shared mark).
fn macro_claim(code: &str, words: &[String]) -> Option<LineClaim> {
    let up = code.to_ascii_uppercase();
    let statement = up
        .trim_start_matches(|c: char| c == 'N' || c.is_ascii_digit() || c == ' ')
        .split(|c: char| !c.is_ascii_alphabetic())
        .next()
        .is_some_and(|k| matches!(k, "IF" | "WHILE" | "GOTO" | "DO" | "END"));
    if statement || words.iter().any(|w| w == "G65" || w == "M98") {
        return Some(LineClaim {
            priority: 96,
            mark: LineMark::Mark,
        });
    }
    let variable = up.contains('[')
        || up
            .as_bytes()
            .windows(2)
            .any(|w| w[0] == b'#' && (w[1].is_ascii_digit() || w[1] == b'['));
    (variable && !up.contains("#<") && !up.starts_with('O')).then_some(LineClaim {
        priority: 90,
        mark: LineMark::Mark,
    })
}

impl Dialect for Fanuc {
    fn id(&self) -> DialectId {
        ID
    }

    fn title(&self) -> &'static str {
        "FANUC lathe G-code (system A)"
    }

    fn extension(&self) -> &'static str {
        "nc"
    }

    fn extensions(&self) -> &'static [&'static str] {
        &["nc", "tap"]
    }

    fn legacy_encoding(&self) -> TextEncoding {
        TextEncoding::Standard(encoding_rs::WINDOWS_1252)
    }

    fn claim_line(&self, line: &str) -> Option<LineClaim> {
        // `O0001` (a program number, perhaps with its name).
        let code = detect::code_part(line).trim();
        let program_number = code.len() > 1
            && code.starts_with(['O', 'o'])
            && code[1..].bytes().all(|b| b.is_ascii_digit());
        let words = detect::code_words(line);
        // A single whole-number word alone on its line may be the НЦ-31's: FANUC's mark needs
        // a second word, a decimal point or a comment beside it.
        let beside = words.len() > 1
            || words.iter().any(|w| w.contains('.'))
            || code.len() < line.trim().len();
        if program_number || (beside && fanuc_word(&words)) {
            return Some(LineClaim {
                priority: 96,
                mark: LineMark::Mark,
            });
        }
        if let Some(claim) = macro_claim(code, &words) {
            return Some(claim);
        }
        // A `( )` comment after code: FANUC's as much as LinuxCNC's (a shared mark).
        // So is a `;` at the end: FANUC's end of block, LinuxCNC's empty comment.
        let eob = line.trim_end().ends_with(';') && code.len() + 1 == line.trim().len();
        if (code.len() < line.trim().len() && line.contains('(')) || eob {
            return Some(LineClaim {
                priority: 90,
                mark: LineMark::Mark,
            });
        }
        // G18, G20, G21 are FANUC's as much as LinuxCNC's (a shared mark), where the line
        // has no word only LinuxCNC writes (`G7 G18 G21` is LinuxCNC's).
        (detect::iso_fanuc_shared(&words) && !detect::iso_only(&words)).then_some(LineClaim {
            priority: 60,
            mark: LineMark::Mark,
        })
    }

    fn mark_description(&self) -> &'static str {
        "a FANUC mark (an `O0001` program number, G32, G50, G98/G99, G77–G79, G92 with F, G20/G21/G24 with an end and F, G76 with F or P010060, G70–G75 with P, G92 with S, T0101, or U/W words)"
    }

    fn tie_rank(&self) -> u8 {
        0
    }

    fn auto_note(&self, profile: &Profile) -> Option<String> {
        Some(match profile.fanuc.gcode_system {
            profile::GcodeSystem::A => "G-code system A (the default; a machine that reads G33 threads, G90/G91, G94/G95, G92 S and G77–G79 needs `[fanuc] gcode_system = \"B\"`, one with G70/G71 inch and metric and G72–G78 cycles \"C\")".into(),
            s => format!("{} (the profile's `gcode_system`)", s.name()),
        })
    }

    fn says_inches(&self) -> bool {
        true
    }

    fn output_feed_mode(&self) -> Option<crate::ir::FeedMode> {
        // The header: `G21 G99`.
        Some(crate::ir::FeedMode::PerRev)
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
            &profile.fanuc,
            &profile.iso.subroutine_path,
            unsupported,
            keep,
        )
    }

    fn capabilities(&self, profile: &Profile) -> Capabilities {
        Capabilities {
            rows: [thread_rows(), machine_rows(profile)].concat(),
            numbers: "lengths to 0.001 mm (X a diameter, I a radius), leads and feeds to 0.0001 mm, an inch program's in inches (0.0001 in, leads and feeds 0.000001 in), a decimal point on every length; `--round` rounds, reporting the largest deviation",
            // The texts name system A's codes; a machine on B or C reads its own.
            renumbered: profile.fanuc.gcode_system.renumbered(),
        }
    }

    fn refusal(&self, at: Occurrence, src: &SourceFile) -> Option<Diagnostic> {
        let (code, message, help) = match at.construct {
            Construct::SyncInfeed => (
                codes::FANW_STEEP,
                "the pass starts with a synchronised move along X (LinuxCNC's G76 infeed before an entry taper, or a G33 along X): its F would be a lead along X, whose unit no source ncthread holds confirms",
                "cut this thread without the synchronised infeed (a G76 without L1/L3), or convert it by hand",
            ),
            Construct::SteepSync => (
                codes::FANW_STEEP,
                "a synchronised move steeper than 45° (a runout, an entry or a taper where X, as a radius, moves more than Z): its F would be a lead along X, whose unit no source ncthread holds confirms",
                "give the thread a runout or entry under 45° in the source, or convert this pass by hand",
            ),
            Construct::IndexWaitInCut => (
                codes::FANW_INDEX_WAIT,
                "a pass waits for the index pulse where the thread move before it ended; consecutive G32 blocks continue without waiting, so FANUC would cut another helix",
                "retract between the two moves in the source",
            ),
            Construct::MistCoolant => (
                codes::FANW_NO_EQUIVALENT,
                "mist coolant (M7) is the machine builder's option on a FANUC lathe",
                "if the machine has M07, set `mist = true` in the profile's [fanuc] section",
            ),
            Construct::CutterCompensation => (
                codes::FANW_NO_EQUIVALENT,
                "cutter radius (tool nose) compensation: on a FANUC lathe its radius and tip direction are in the offset page, which the program cannot state",
                "if the machine's offsets hold the nose radius and tip of every tool, set `nose_radius_in_offsets = true` in the profile's [fanuc] section",
            ),
            Construct::MachineCoordinates => (
                codes::FANW_NO_EQUIVALENT,
                "a move in machine coordinates or to a stored position (G53, G28, G30): FANUC's G28 goes to the machine's reference point, not to LinuxCNC's stored position",
                "program the tool change position in the part's coordinates, or add the reference return by hand",
            ),
            Construct::Tapping => (
                codes::FANW_NO_EQUIVALENT,
                "rigid tapping: on a FANUC lathe it needs an option and parameters (M29 S… G84) that the program cannot state",
                "tap this hole by hand on the FANUC machine, or cut the thread with G32 passes",
            ),
            _ => return None,
        };
        Some(Diagnostic::new(code, message).at(src, at.span).help(help))
    }

    /// Its writer reads the program's number (kept from a FANUC source) and its unit.
    fn writer_reads(&self) -> crate::dialect::WriterReads {
        use crate::dialect::WriterReads;
        WriterReads {
            number: true,
            inch: true,
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
        Box::new(emit::Items::new(program, src, profile, options.round))
    }
}

/// The table's rows for the thread's forms (cycles, passes, their tapers and chains).
fn thread_rows() -> Vec<Capability> {
    use Construct::*;

    vec![
        row(
            ThreadCycle,
            Read::No,
            Write::As("writes its passes as G32 blocks (G92 and G76 never)"),
        ),
        row(
            StartAngle,
            Read::Yes("G32/G92 … Q (0.001°)"),
            Write::Yes("Q on a chain's first G32"),
        ),
        row(
            Entry,
            Read::No,
            Write::As("writes it as a G32 block of the pass's chain"),
        ),
        row(
            Runout,
            Read::Yes("G92's chamfer, from the profile's `thread_chamfer_0p1_lead`"),
            Write::As("writes it as a G32 block of the pass's chain"),
        ),
        row(
            TaperPass,
            Read::Yes("G32 X Z, G92 R"),
            Write::Yes("G32 X Z, F the lead along Z"),
        ),
        row(
            ContinuedChain,
            Read::Yes("consecutive G32 blocks"),
            Write::Yes("consecutive G32 blocks"),
        ),
        row(IndexWaitInCut, Read::No, Write::No(codes::FANW_INDEX_WAIT)),
        row(SyncInfeed, Read::No, Write::No(codes::FANW_STEEP)),
        row(SteepSync, Read::No, Write::No(codes::FANW_STEEP)),
    ]
}

/// The table's rows for the rest of a part program, as far as the profile gives their forms.
fn machine_rows(profile: &Profile) -> Vec<Capability> {
    use Construct::*;
    let f = &profile.fanuc;

    vec![
        row(
            Arc,
            Read::Yes("G02/G03 X Z I K, I a radius; R up to half a circle"),
            Write::Yes("G02/G03 X Z I K, I a radius"),
        ),
        row(
            Chamfer45,
            Read::No,
            Write::As("writes it as a feed move (G01 X Z)"),
        ),
        row(Coolant, Read::Yes("M08/M09"), Write::Yes("M08/M09")),
        if f.mist {
            row(MistCoolant, Read::Yes("M07"), Write::Yes("M07"))
        } else {
            row(MistCoolant, Read::No, Write::No(codes::FANW_NO_EQUIVALENT))
        },
        row(Stop, Read::Yes("M00/M01"), Write::Yes("M00/M01")),
        row(
            SurfaceSpeed,
            Read::Yes("G96 S (m/min), G50 S its limit, G97 S"),
            Write::Yes("G50 S, G96 S, G97 S"),
        ),
        if f.nose_radius_in_offsets {
            row(
                CutterCompensation,
                Read::Yes("G41/G42, the nose radius in the offset page"),
                Write::As("G41/G42 (the nose radius in the offset page; G41.1/G42.1: FANW002)"),
            )
        } else {
            row(
                CutterCompensation,
                Read::Yes("G41/G42, the nose radius in the offset page"),
                Write::No(codes::FANW_NO_EQUIVALENT),
            )
        },
        row(
            WorkOffset,
            Read::Yes("G54–G59"),
            Write::As("G54–G59 (G59.1–G59.3: FANW002)"),
        ),
        row(
            MachineCoordinates,
            Read::No,
            Write::No(codes::FANW_NO_EQUIVALENT),
        ),
        row(Tapping, Read::No, Write::No(codes::FANW_NO_EQUIVALENT)),
        // As the reader reads it (U is an increment's word in systems B and C) and the
        // writer writes it (`emit.rs`, `dwell`).
        row(
            Dwell,
            Read::Yes(
                match (f.gcode_system == profile::GcodeSystem::A, f.haas_dwell_p) {
                    (true, false) => "G04 U/X (s), G04 P (ms)",
                    (true, true) => "G04 U/X (s), G04 P (ms; with a point, s)",
                    (false, false) => "G04 X (s), G04 P (ms)",
                    (false, true) => "G04 X (s), G04 P (ms; with a point, s)",
                },
            ),
            Write::Yes(match f.gcode_system {
                _ if f.haas_dwell_p => "G04 P (s, with a point)",
                profile::GcodeSystem::A => "G04 U (s)",
                profile::GcodeSystem::B | profile::GcodeSystem::C => "G04 X (s)",
            }),
        ),
        row(PerMinuteFeed, Read::Yes("G98"), Write::Yes("G98")),
        row(ToolOffset, Read::Yes("T0101"), Write::Yes("T0101")),
        row(Parameters, Read::No, Write::As("writes them as comments")),
        row(Repeat, Read::No, Write::As("writes the repeated moves out")),
        row(
            Comments,
            Read::Yes("`( )`"),
            Write::As("`( )`, upper-case ASCII"),
        ),
    ]
}

//! The iso front end: RS274/NGC lines as LinuxCNC reads them → IR items.
//!
//! It reads what ncthread writes and what a programmer writes by hand for a LinuxCNC lathe:
//! G0/G1/G33/G33.1/G76, G4, G7/G8, G18, G20/G21, G90/G91, G94/G95, S/M3/M4/M5, T/M6, G43,
//! M2/M30, comments and `%` lines; the drilling cycles G73, G81–G83, G85, G89 (with G80,
//! G98/G99) in G17 as their moves (`front/drilling.rs`). Words that change nothing ncthread models (coolant,
//! path control, the default work offset…) are kept as opaque words for ISO output.
//! Everything else — arcs, other planes and axes, work offsets, parameters, subroutines —
//! is named as unsupported. Within a line the commands run in LinuxCNC's order.
//!
//! The parts: `run` runs the lines in the order LinuxCNC runs them (O-word jumps and calls,
//! `%`, the end); `line` reads one line (block delete, its values evaluated); `unsupported`
//! names what is not read; `words` sorts a line's words by letter and its codes by modal
//! group; `block` is the block interpreter, one step per modal group in LinuxCNC's order;
//! `values` and `position` read lengths, leads and targets; `motion`, `arc`, `thread` and
//! `g76` are the moves; `drilling`, `roughing`, `offsets` and `macros` the canned cycles, the
//! G52/G92 offsets and the parameters, O-words and modal state.

use std::ops::Range;

use super::gcode::*;
use super::syntax::{self, Block, Word};
use crate::diag::Code;
use crate::dialect::Unsupported;
use crate::dialect::iso::codes;
use crate::dialect::read::{Reader, UnsupportedWording};
use crate::fixed::{Decimal, Length};
use crate::ir::{FeedMode, ItemKind, Pos, SpindleDirection};
use crate::profile::BlockDelete;
use crate::source::{Line, Span};
#[cfg(test)]
use crate::{diag::Diagnostic, dialect::read::Keep, ir::Program, source::SourceFile};

/// How the ISO reader words its unsupported policy.
const UNSUPPORTED: UnsupportedWording = UnsupportedWording {
    code: codes::ISOR_UNSUPPORTED,
    more: "on this line",
    in_one: "on a line",
    many: "lines",
    own_block: "put this word on a line of its own",
    refuse_help: "ncthread reads lathe thread programs in X and Z; rewrite this line, or pass --unsupported warn to keep it opaque",
    keep_help: "kept as an opaque block: only ISO output writes it back, and positions after it are unknown",
};

#[derive(Clone, Debug, Default)]
pub struct Options {
    pub unsupported: Unsupported,
    /// Folders that hold subroutine files (`o<name> call` → `name.ngc`), LinuxCNC's
    /// `SUBROUTINE_PATH`.
    pub subroutine_path: Vec<std::path::PathBuf>,
    /// The block delete switch (profile `[iso] block_delete`, `--block-delete`).
    pub block_delete: Option<BlockDelete>,
}

/// The modal motion (LinuxCNC's group 1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Motion {
    Rapid,
    Feed,
    /// G2 (clockwise) or G3.
    Arc {
        clockwise: bool,
    },
    Thread,
    Tap,
    Cycle,
    /// G70–G72 (the code).
    Roughing(GCode),
    /// A drilling cycle: G73, G81, G82, G83, G85 or G89 (the code).
    Drill(GCode),
    /// G80: no motion mode (axis words are refused until a motion code).
    CycleOff,
}

/// A Z in the program's units and coordinates as LinuxCNC computed it, recorded with the
/// exact position in mm it stands for and the units and Z offset it was in.
#[derive(Clone, Copy, Debug)]
struct ProgramZ {
    mm: f64,
    value: f64,
    inch: bool,
    offset: f64,
}

struct FrontEnd<'a> {
    /// The room of the last line's words, for the next line read ([`FrontEnd::line`]).
    spare_words: Vec<syntax::Word>,
    r: Reader<'a>,
    options: &'a Options,
    motion: Option<Motion>,
    /// G7 (true) or G8 (false); `None` until one is programmed (LinuxCNC then reads radii).
    diameter: Option<bool>,
    /// The diameter mode before the current line's G7/G8 (a G76 scales I, J, K by both).
    diameter_before_line: bool,
    inch: bool,
    incremental: bool,
    /// G96 in force (S is a surface speed).
    surface_speed: bool,
    /// The surface speed's limit (G96's D) and whether its S is in ft/min.
    surface: (Option<Decimal>, bool),
    /// Cutter radius compensation is on (G41/G42 and their `.1`, until G40).
    compensation: bool,
    /// LinuxCNC's compensated path, followed while the radius is known (G41.1/G42.1 D > 0).
    comp: compensation::Model,
    /// The position as written (mm, X a diameter), before it was rounded onto the grid:
    /// incremental moves add to it and arcs are computed from it, so that a value is rounded
    /// once, as LinuxCNC computes in doubles. An axis that does not round to the known
    /// position is stale (a move that did not set it) and not used.
    exact: (Option<f64>, Option<f64>),
    /// The exact target of the line's X and Z words, as `target` read them.
    exact_target: (Option<f64>, Option<f64>),
    /// G90.1: I and K give the arc centre itself; G91.1 (LinuxCNC's start-up mode): its
    /// offset from the arc's start.
    absolute_centres: bool,
    feed: Option<Length>,
    /// The feed rate was given in inches (under G20).
    feed_inch: bool,
    /// `None` until the program sets one: LinuxCNC then feeds per minute (G94).
    feed_mode: Option<FeedMode>,
    speed: Option<u32>,
    turning: Option<SpindleDirection>,
    selected_tool: Option<u32>,
    /// Where the last G33 ended, while nothing but comments followed it (a G33 there
    /// continues it).
    sync_end: Option<Pos>,
    /// Where the last synchronised move ended, while no other motion followed it.
    in_cut: Option<Pos>,
    warned_rounding: bool,
    warned_radius: bool,
    /// M2 or M30 has ended the program.
    ended: bool,
    /// Lines skipped because they start with `/` and the block delete switch is on.
    skipped_lines: usize,
    /// An error that ends the run (LinuxCNC stops there): nothing after it is read.
    stopped: bool,
    /// Coolant as M7/M8/M9 left it, and the work offset (1: G54): M72 restores them.
    mist: bool,
    flood: bool,
    work_offset: u8,
    /// `#<_ccomp>`: 400, 410 or 420.
    ccomp: f64,
    /// G17 in force (the XY plane): lines along X and Z mean what they mean in G18, but an
    /// arc, a G7x cycle and cutter compensation would work in XY.
    plane_xy: bool,
    /// G98 (true: canned cycles retract to the initial level) or G99 (to R, LinuxCNC's
    /// start-up mode).
    retract_old_z: bool,
    /// The drilling cycles' modal values.
    drill: drilling::DrillState,
    /// The motion mode before the current line's motion code.
    motion_before_line: Option<Motion>,
    /// The last Z recorded as LinuxCNC holds it.
    z_program: Option<ProgramZ>,
    /// A line was refused as not a lathe program (ISOR021): the later ones are skipped
    /// unreported, since the program is refused whole.
    not_lathe_reported: bool,
    /// A G70–G72 whose contour subroutine is running.
    contour: Option<Box<roughing::Contour>>,
    /// The call of a contour subroutine that a G70–G72 line asks the run to make.
    cycle_call: Option<syntax::OWord>,
    /// The G52/G92 offset in force (mm, X a diameter): a position the program writes is this
    /// much nearer the work zero than the IR's, which holds where the tool goes.
    axis_offset: (f64, f64),
    /// #5210, #5211, #5213 as the line before left them; the line's G52/G92 family sets
    /// #5210 again.
    offset_params: [f64; 3],
    /// The offset G92.3 restores (the last G52/G92's, until G92.1).
    saved_offset: (f64, f64),
    /// The program has set the offset (G52, G92, G92.1): #5210–#5219 are known.
    offsets_set: bool,
}

mod arc;
mod block;
mod compensation;
mod drilling;
mod g76;
mod line;
mod macros;
mod motion;
mod offsets;
mod position;
mod roughing;
mod run;
#[cfg(test)]
pub(crate) use run::FOLLOWED;
mod thread;
mod unsupported;
mod values;
mod words;

pub(crate) use run::read;
use words::Words;

/// Reads an RS274/NGC program. The program is usable only when no diagnostic is an error.
#[cfg(test)]
pub fn parse(src: &SourceFile, options: &Options) -> (Program, Vec<Diagnostic>) {
    read(src, options, Keep::Program)
}

impl FrontEnd<'_> {
    fn diag(
        &mut self,
        code: Code,
        line: Line<'_>,
        range: Range<usize>,
        message: String,
        help: &str,
    ) {
        let span = self.r.span(line, range);
        self.r.error(code, span, message, help);
    }

    fn push(&mut self, kind: ItemKind, span: Span) {
        // Anything but a comment between two G33 moves ends LinuxCNC's chain; any other
        // motion takes the tool out of the cut.
        match kind {
            ItemKind::ThreadPass(_) | ItemKind::Comment(_) | ItemKind::Delimiter => {}
            // A move to where the tool already is leaves it in the cut.
            ItemKind::Rapid { .. } | ItemKind::Feed { .. }
                if kind.end_position(self.r.pos) == self.r.pos =>
            {
                self.sync_end = None;
            }
            ItemKind::Rapid { .. }
            | ItemKind::Feed { .. }
            | ItemKind::Arc { .. }
            | ItemKind::ThreadCycle(_)
            | ItemKind::TapCycle(_)
            | ItemKind::Opaque { block: Some(_), .. } => {
                self.sync_end = None;
                self.in_cut = None;
            }
            _ => self.sync_end = None,
        }
        self.r.push(kind, span, None);
    }

    /// Reports why a line cannot be read (a NUL, a syntax error).
    fn report_unreadable(
        &mut self,
        line: Line<'_>,
        parsed: &Option<Result<Block, syntax::SyntaxError>>,
    ) {
        match parsed {
            None => {
                let at = line.text.find('\0').unwrap_or(0);
                self.r.syntax_error(
                    codes::ISOR_SYNTAX,
                    line,
                    at,
                    "a NUL character: LinuxCNC reads the line only up to it",
                    "remove the NUL byte (a damaged file?)",
                );
            }
            Some(Err(e)) => {
                self.r.syntax_error(
                    codes::ISOR_SYNTAX,
                    line,
                    e.offset,
                    e.message.clone(),
                    "a line is words (a letter and a number: `G33`, `X35.6`, `K1.5`), `( )` comments and a `;` comment to its end",
                );
            }
            Some(Ok(_)) => {}
        }
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::diag::Severity;
    use crate::fixed::{Angle, Lead, Length};
    use crate::ir::{EndCode, FeedMode, ItemKind, Pos, Program, Retract, ThreadPass};
    use crate::lower;

    /// The first error of `d` (read from `text`), held to its code and the text it marks.
    pub(super) fn first_error<'d>(
        d: &'d [Diagnostic],
        text: &str,
        code: Code,
        marked: &str,
    ) -> &'d Diagnostic {
        let e = d
            .iter()
            .find(|d| d.severity == Severity::Error)
            .unwrap_or_else(|| panic!("{text:?}: no error in {d:?}"));
        assert_eq!(e.code, code, "{text:?}: {e:?}");
        let loc = e.location.as_ref().unwrap();
        assert_eq!(&loc.source_line[loc.range.clone()], marked, "{text:?}");
        e
    }

    /// An error in a loop's body is reported once, and the run stops there rather than go
    /// round to the loop limit (it reported the error 200,000 times); so does a loop whose
    /// body an earlier error cut short.
    #[test]
    fn a_loop_does_not_go_round_after_an_error() {
        let endless = "G7 G18 G21 G95 F0.1\nS500 M3\nG0 X30 Z2\no1 while [1]\n  G1 X30 Z-20 X32\no1 endwhile\nM30\n";
        let (_, d) = run(endless);
        assert_eq!(d.iter().filter(|d| d.is_error()).count(), 1, "{d:?}");
        let cut_short = "G7 G18 G21 G95 F0.1\nS500 M3\n#1 = 38\no1 do\n  G0 X#1 Z2\n  #1 = [#1 - 2] =\no1 while [#1 GE 34]\nM30\n";
        let (_, d) = run(cut_short);
        let errors: Vec<_> = d.iter().filter(|d| d.is_error()).collect();
        assert_eq!(errors.len(), 1, "{d:?}");
        assert_ne!(errors[0].code, codes::ISOR_CONTROL, "{d:?}");
    }

    /// A feed rate given before a G20/G21 that changed the units is not known: a feed move
    /// under it and `#<_feed>` are refused at their word, and an F after the change, or a
    /// G20 that changes nothing, lets the program go on.
    #[test]
    fn a_feed_across_a_change_of_units_is_not_known() {
        let head = "G8 G18 G21 G94\nG0 X0 Z0\nF100\n";
        for (body, marked) in [
            ("G20\nG1 X1\n", "G1"),
            ("G1 X0\nG20\nZ-1 X1\n", "X1"),
            ("G20\nG2 X0 Z-1 K-0.5\n", "G2"),
            ("G20\n#1 = #<_feed>\n", "#<_feed>"),
            ("G20\nG21\nG20\nG1 X1\n", "G1"),
        ] {
            let text = format!("{head}{body}");
            let (_, d) = run(&text);
            if marked == "#<_feed>" {
                first_error(&d, &text, codes::ISOR_EVAL, marked);
            } else {
                let e = first_error(&d, &text, codes::ISOR_WORD, marked);
                assert!(e.message.contains("given in mm before the G20"), "{e:?}");
            }
        }
        for fine in [
            "G20 F4\nG1 X1\n",
            "G21\nG1 X1\n",
            "G20\nG21\nG1 X1\n",
            "G20\nG0 X1\n",
        ] {
            let text = format!("{head}{fine}");
            let (_, d) = run(&text);
            assert!(!d.iter().any(|d| d.is_error()), "{text:?}: {d:?}");
        }
    }

    /// Reads a fragment: without its program end (ISOR013, tested on its own).
    pub(super) fn run(text: &str) -> (Program, Vec<Diagnostic>) {
        let (p, d) = parse(&SourceFile::new("t.ngc", text), &Options::default());
        (
            p,
            d.into_iter()
                .filter(|d| d.code != codes::ISOR_NO_END)
                .collect(),
        )
    }

    #[test]
    fn programs_end_as_linuxcnc_ends_them() {
        let codes_of = |text: &str| -> Vec<&str> {
            let (_, d) = parse(&SourceFile::new("t.ngc", text), &Options::default());
            d.iter().map(|d| d.code.id).collect()
        };
        // No end: LinuxCNC runs it and then complains; a warning here.
        assert_eq!(codes_of("G7 G0 X10 Z1\n"), ["ISOR013"]);
        assert!(codes_of("G7 G0 X10 Z1\nM2\n").is_empty());
        assert!(codes_of("%\nG7 G0 X10 Z1\n%\n").is_empty());
        // After the closing `%` or M2 nothing is read.
        let (p, d) = parse(
            &SourceFile::new("t.ngc", "%\nG7 G0 X10 Z1\n%\nG0 X5\n"),
            &Options::default(),
        );
        assert_eq!(d[0].code, codes::ISOR_AFTER_END);
        assert_eq!(p.items.len(), 3);
        // A `%` elsewhere, a NUL, and motion codes without axes are refused as LinuxCNC does.
        assert_eq!(codes_of("G7 G0 X10 Z1\n%\nM2\n"), ["ISOR001"]);
        assert_eq!(codes_of("G7 G0 X10 Z1 %\nM2\n"), ["ISOR001"]);
        assert_eq!(codes_of("(a\0b)\nM2\n"), ["ISOR001"]);
        assert_eq!(codes_of("G7 S100 M3\nG33 K1\nM2\n"), ["ISOR004"]);
        assert_eq!(codes_of("G7 G95 G1\nM2\n"), ["ISOR004"]);
    }

    fn kinds(p: &Program) -> Vec<ItemKind> {
        p.items.iter().map(|i| i.kind.clone()).collect()
    }

    fn mm(v: f64) -> Length {
        Length::from_mm_f64(v)
    }

    const HEAD: &str = "G7 G18 G21 G90 G95\nS500 M3\n";

    #[test]
    fn reads_what_ncthread_writes() {
        let text = format!(
            "%\n(a.nc, dialect nc31)\n{HEAD}G0 X35.6 Z4.5\nG33 X35.6 Z-47.5 K1.5\nG0 X37\nM30\n%\n"
        );
        let (p, d) = run(&text);
        assert!(d.is_empty(), "{d:?}");
        let k = kinds(&p);
        assert_eq!(k[0], ItemKind::Delimiter);
        assert_eq!(k[1], ItemKind::Comment("a.nc, dialect nc31".into()));
        assert_eq!(k[2], ItemKind::FeedMode(FeedMode::PerRev));
        assert_eq!(
            k[5],
            ItemKind::pass(ThreadPass {
                to: Pos::new(mm(35.6), mm(-47.5)),
                lead: crate::fixed::Lead::from_mm_f64(1.5).unwrap(),
                start: crate::ir::SyncStart::Index(Angle::ZERO),
                infeed: None,
                entry: None,
                exit: None,
            })
        );
        assert_eq!(k[7], ItemKind::ProgramEnd(EndCode::M30));
    }

    #[test]
    fn taper_k_is_along_the_path() {
        // iso.md: Ø226 → Ø246, Z3 → Z−100, K1.50705289 is a Z lead of 1.5.
        let (p, d) = run(&format!("{HEAD}G0 X226 Z3\nG33 X246 Z-100 K1.50705289\n"));
        assert!(d.is_empty(), "{d:?}");
        let ItemKind::ThreadPass(pass) = &p.items.last().unwrap().kind else {
            panic!()
        };
        // K has 8 decimals: the Z lead is 1.5 within 2·10⁻⁹ mm (a drift of 10⁻⁷ mm over the
        // thread), kept as it is rather than rounded onto a coarser grid.
        assert_eq!(pass.lead, Lead(1_500_000_001_751));
        // A tapered G33 with a round K: its Z lead is K·ΔZ/length, not K.
        let (p, _) = run(&format!("{HEAD}G0 X30 Z5\nG33 X40 Z-295 K1.5\n"));
        let ItemKind::ThreadPass(pass) = &p.items.last().unwrap().kind else {
            panic!()
        };
        assert_eq!(pass.lead, Lead(1_499_791_710_059));
    }

    #[test]
    fn radius_mode_inches_and_incremental() {
        // No G7: X is a radius (with a warning); G20 converts; G91 adds.
        let (p, d) = run("G20 G0 X1 Z0.1\nG91 G0 Z-0.5\n");
        assert_eq!(d.len(), 1);
        assert_eq!(d[0].code, codes::ISOR_RADIUS_MODE);
        let k = kinds(&p);
        assert_eq!(
            k[0],
            ItemKind::Rapid {
                to: Pos::new(mm(50.8), mm(2.54))
            }
        );
        assert_eq!(
            k[1],
            ItemKind::Rapid {
                to: Pos {
                    x: None,
                    z: Some(mm(-10.16))
                }
            }
        );
        // 0.0001 inch is 0.00254 mm: on the grid, exactly; a fifth decimal rounds, with
        // one warning.
        let (p, d) = run("G7 G20 G0 X0.0001\nG0 X0.0003\n");
        assert!(d.is_empty(), "{d:?}");
        assert_eq!(
            kinds(&p)[0],
            ItemKind::Rapid {
                to: Pos {
                    x: Some(Length(254)),
                    z: None
                }
            }
        );
        let (_, d) = run("G7 G20 G0 X0.00001\nG0 X0.00003\n");
        assert_eq!(
            d.iter().filter(|d| d.code == codes::ISOR_ROUNDED).count(),
            1
        );
    }

    #[test]
    fn feed_mode_defaults_to_per_minute() {
        let (p, d) = run("G7 G0 X10 Z0\nG1 Z-5 F100\n");
        assert!(d.is_empty(), "{d:?}");
        let k = kinds(&p);
        assert_eq!(k[1], ItemKind::FeedMode(FeedMode::PerMin));
        assert_eq!(
            k[2],
            ItemKind::Feed {
                to: Pos {
                    x: None,
                    z: Some(mm(-5.0))
                },
                feed: mm(100.0)
            }
        );
    }

    /// Arc centres as LinuxCNC places them (the R centres checked against rs274's ARC_FEED
    /// for the same lines: `tests/oracle.rs` runs the corpus part programs).
    #[test]
    fn arcs_take_their_centres_as_linuxcnc_does() {
        let arc = |text: &str| {
            let (p, d) = run(text);
            assert!(!crate::diag::has_errors(&d), "{text:?}: {d:?}");
            match kinds(&p)
                .into_iter()
                .rev()
                .find(|k| matches!(k, ItemKind::Arc { .. }))
            {
                Some(ItemKind::Arc {
                    to,
                    centre,
                    clockwise,
                    ..
                }) => (to, *centre, clockwise),
                other => panic!("{text:?}: {other:?}"),
            }
        };
        // G91.1 (the start-up mode): I and K from the start, I in radius even under G7.
        let (to, centre, cw) = arc("G18 G7 G0 X20 Z0\nG3 X30 Z-5 I0 K-5 F1\n");
        assert_eq!(
            (to, centre, cw),
            (
                Pos::new(mm(30.0), mm(-5.0)),
                Pos::new(mm(20.0), mm(-5.0)),
                false
            )
        );
        let (_, centre, cw) = arc("G18 G7 G0 X24 Z-20\nG3 X30 Z-23 K-3 F1\n");
        assert_eq!((centre, cw), (Pos::new(mm(24.0), mm(-23.0)), false));
        // G90.1: I and K are the centre (I a radius).
        let (_, centre, _) = arc("G18 G7 G0 X30 Z-30\nG90.1 G2 X36 Z-33 I18 K-30 F1\n");
        assert_eq!(centre, Pos::new(mm(36.0), mm(-30.0)));
        // G8: X words are radii, I too.
        let (to, centre, _) = arc("G18 G8 G0 X15 Z-30\nG2 X18 Z-33 I3 K0 F1\n");
        assert_eq!(
            (to, centre),
            (Pos::new(mm(36.0), mm(-33.0)), Pos::new(mm(36.0), mm(-30.0)))
        );
        // R: G2 with R > 0 turns right of its chord (the short arc), R < 0 the long one;
        // the helper's reading of `arc_data_r`: from r10 Z0 to r15 Z-5 with R5, G2's
        // centre is r15 Z0 and G3's r10 Z-5.
        let (_, centre, cw) = arc("G18 G7 G0 X20 Z0\nG2 X30 Z-5 R5 F1\n");
        assert_eq!((centre, cw), (Pos::new(mm(30.0), mm(0.0)), true));
        let (_, centre, _) = arc("G18 G7 G0 X20 Z0\nG2 X30 Z-5 R-5 F1\n");
        assert_eq!(centre, Pos::new(mm(20.0), mm(-5.0)));
        let (_, centre, _) = arc("G18 G7 G0 X20 Z0\nG3 X30 Z-5 R5 F1\n");
        assert_eq!(centre, Pos::new(mm(20.0), mm(-5.0)));
        // A semicircle whose R is short by less than 0.00127 mm is one.
        let (_, centre, _) = arc("G18 G7 G0 X0 Z0\nG2 Z-10 R4.9995 F1\n");
        assert_eq!(centre, Pos::new(mm(0.0), mm(-5.0)));
        // Inches: the centre in mm.
        let (_, centre, _) = arc("G18 G20 G7 G0 X1 Z0\nG3 X1 Z-1 K-0.5 F1\n");
        assert_eq!(centre, Pos::new(mm(25.4), mm(-12.7)));
        // P within 0.001 of 1 is one turn, as in LinuxCNC.
        let (_, centre, _) = arc("G18 G7 G0 X20 Z0\nG3 X30 Z-5 I0 K-5 P1.0005 F1\n");
        assert_eq!(centre, Pos::new(mm(20.0), mm(-5.0)));
        // The R centre is computed from the end as written, not from its rounding: near a
        // semicircle 0.00004 mm of X moves LinuxCNC's centre 0.007 mm along Z.
        let (_, centre, _) = arc("G18 G8 G0 X10 Z0\nG2 X20.00004 Z0 R5.00003 F1\n");
        assert_eq!(centre, Pos::new(mm(30.0), mm(0.01)));
        // A full circle with I/K.
        let (to, centre, _) = arc("G18 G7 G0 X20 Z0\nG2 I-5 F1\n");
        assert_eq!(
            (to, centre),
            (Pos::new(mm(20.0), mm(0.0)), Pos::new(mm(10.0), mm(0.0)))
        );
    }

    /// Increments add to the position as written and are rounded once: 50 increments of
    /// 1.00004 mm end at 50.002 mm, not 50 mm.
    #[test]
    fn increments_do_not_accumulate_rounding() {
        let text = format!("G18 G7 G0 X10 Z0\nG91\n{}", "G1 Z-1.00004 F1\n".repeat(50));
        let (p, _) = run(&text);
        let end = p
            .items
            .iter()
            .fold(Pos::UNKNOWN, |pos, i| i.kind.end_position(pos));
        assert_eq!(end.z, Some(mm(-50.002)));
    }

    #[test]
    fn tool_change_stops_the_spindle_like_linuxcnc() {
        let (p, d) = run(&format!("{HEAD}T5 M6 G43\n"));
        assert!(d.is_empty(), "{d:?}");
        let k = kinds(&p);
        assert_eq!(
            k[2],
            ItemKind::Tool {
                number: Some(5),
                offset: Some(5)
            }
        );
        assert_eq!(k[3], ItemKind::SpindleStop);
    }

    #[test]
    fn refusals_name_the_word() {
        let cases: &[(&str, Code, &str)] = &[
            (
                "G18 G7 G0 X1\nG19 G1 X2 Z0 F1\n",
                codes::ISOR_NOT_LATHE,
                "G19",
            ),
            (
                "G7 G17 G21 G95\nS400 M3\nG0 X20 Z2\nG2 X24 Z-2 K-2 F0.1\n",
                codes::ISOR_ARC,
                "G2",
            ),
            (
                "G7 G17 G21 G95\nG0 X20 Z2\nG71 Q100 X1 Z1 D0.5 I1 R0.3\n",
                codes::ISOR_ROUGHING,
                "G71",
            ),
            (
                "G7 G17 G21 G95\nG0 X20 Z2\nG41 D1\n",
                codes::ISOR_COMPENSATION,
                "G41",
            ),
            ("G18 G7 G0 X1 Z0\nG2 X2 Z-1 R1\n", codes::ISOR_WORD, "G2"),
            (
                "G18 G7 G0 X1 Z0\nG2 X2 Z-1 R1 I1 F1\n",
                codes::ISOR_ARC,
                "R1",
            ),
            ("G18 G7 G0 X1 Z0\nG2 X2 Z-1 F1\n", codes::ISOR_ARC, "G2"),
            ("G18 G7 G0 X0 Z0\nG2 X0 Z-10 R4 F1\n", codes::ISOR_ARC, "R4"),
            (
                "G18 G7 G0 X0 Z0\nG2 Z-10 R4.998 F1\n",
                codes::ISOR_ARC,
                "R4.998",
            ),
            ("G18 G7 G0 X0 Z0\nG3 X0 Z0 R5 F1\n", codes::ISOR_ARC, "R5"),
            ("G18 G7 G0 X0 Z0\nG3 R5 F1\n", codes::ISOR_ARC, "R5"),
            (
                "G18 G7 G0 X0 Z0\nG2 X0 Z-10 K-5.1 F1\n",
                codes::ISOR_ARC,
                "G2",
            ),
            ("G18 G7 G0 X0 Z0\nG2 X0 Z-10 I0 F1\n", codes::ISOR_ARC, "G2"),
            (
                "G18 G7 G0 X0 Z0\nG90.1 G2 X0 Z-10 K-5 F1\n",
                codes::ISOR_ARC,
                "G2",
            ),
            (
                "G18 G7 G0 X0 Z0\nG2 X0 Z-10 K-5 P2 F1\n",
                codes::ISOR_UNSUPPORTED,
                "P2",
            ),
            (
                "G18 G7 G0 X0 Z0\nG2 X0 Z-10 K-5 P0 F1\n",
                codes::ISOR_ARC,
                "P0",
            ),
            (
                "G18\nG2 X0 Z-10 K-5 F1\n",
                codes::ISOR_UNKNOWN_POSITION,
                "G2",
            ),
            // Findings of the differential arc campaign against rs274.
            (
                "G18 G7 G0 X20 Z0\nG2 X30 Z-5 R1000000000000000 F1\n",
                codes::ISOR_NUMBER,
                "R1000000000000000",
            ),
            (
                "G18 G8 G0 X10 Z0\nG2 X10 Z-0.002 R0.001 F1\n",
                codes::ISOR_ARC,
                "R0.001",
            ),
            (
                "G18 G7 G0 X20 Z0\nG2 G4 X30 Z-5 R5 P1 F1\n",
                codes::ISOR_ARC,
                "G4",
            ),
            (
                "G18 G7 G0 X20 Z0\nG90.1 G91.1 G2 X30 Z-5 I0 K-5 F1\n",
                codes::ISOR_CONFLICT,
                "G91.1",
            ),
            (
                "G18 G7 G0 X20 Z0\nG2 X30 Z-5 I0 K-5 P1.4 F1\n",
                codes::ISOR_ARC,
                "P1.4",
            ),
            (
                "G20 G8 G0 X1 Z0\nG2 X1 Z-0.202 I0 K-0.1 F1\n",
                codes::ISOR_ARC,
                "G2",
            ),
            // An I/K arc whose end rounds onto its start would become a full circle.
            (
                "G18 G7 G0 X20 Z0\nG2 X20 Z-0.000001 I5 K0 F1\n",
                codes::ISOR_ARC,
                "G2",
            ),
            // Whole-part codes LinuxCNC refuses.
            ("G7 S100 M3\nG96 D2500\n", codes::ISOR_WORD, "G96"),
            ("G7 S100 M3\nG96 D0 S200\n", codes::ISOR_WORD, "G96"),
            ("G7\nG53 X10\n", codes::ISOR_WORD, "G53"),
            ("G18 G7 G0 X1 Z0\nG41.1 L3\n", codes::ISOR_WORD, "G41.1"),
            (
                "G18 G7 G0 X1 Z0\nG41\nG42\n",
                codes::ISOR_COMPENSATION,
                "G42",
            ),
            (
                "G18 G7 G0 X1 Z0\nG41\nT2 M6\n",
                codes::ISOR_COMPENSATION,
                "M6",
            ),
            (
                "G18 G7 G0 X1 Z0\nG41\nG28\n",
                codes::ISOR_COMPENSATION,
                "G28",
            ),
            (
                "G18 G7 G0 X1 Z0\nG41\nG55\n",
                codes::ISOR_COMPENSATION,
                "G55",
            ),
            (
                "G18 G7 S100 M3\nG0 X10 Z1\nG41\nG33 Z-10 K1\n",
                codes::ISOR_COMPENSATION,
                "G33",
            ),
            (
                "G18 G7 S100 M3\nG0 X10 Z1\nG41\nG76 P1 Z-10 I-1 J0.1 K1\n",
                codes::ISOR_COMPENSATION,
                "G76",
            ),
            ("G18 G7 G0 X1 Z0\nG19\n", codes::ISOR_NOT_LATHE, "G19"),
            ("G0 Y1\n", codes::ISOR_NOT_LATHE, "Y1"),
            ("G0 X[1/0]\n", codes::ISOR_EVAL, "1/0"),
            ("G0 X#<nope>\n", codes::ISOR_EVAL, "#<nope>"),
            ("#1 = SQRT[-1]\n", codes::ISOR_EVAL, "SQRT[-1]"),
            ("#5221 = 1\n", codes::ISOR_EVAL, "#5221 = 1"),
            ("#<_x> = 1\n", codes::ISOR_EVAL, "#<_x> = 1"),
            ("o<nope> call\n", codes::ISOR_CONTROL, "o<nope> call"),
            ("G7 S100 M3\nM72\n", codes::ISOR_CONTROL, "M72"),
            ("G7 S100 M3\nM70 G91\n", codes::ISOR_UNSUPPORTED, "M70"),
            ("o1 while [1]\nG0 X1\n", codes::ISOR_CONTROL, "o1 while [1]"),
            (
                "o1 while [1]\no2 endwhile\n",
                codes::ISOR_CONTROL,
                "o1 while [1]",
            ),
            ("G0 X1 X2\n", codes::ISOR_CONFLICT, "X2"),
            ("G0 G1 X1\n", codes::ISOR_CONFLICT, "G1"),
            ("G7 G0 X1 Z1 K2\n", codes::ISOR_WORD, "K2"),
            ("G7 G0 X10 Z1\nG33 Z-10 K1\n", codes::ISOR_SPINDLE, "G33"),
            (
                "G7 S100 M3\nG0 X10 Z1\nG33 X10 K1\n",
                codes::ISOR_THREAD_GEOMETRY,
                "X10",
            ),
            ("G7 S100 M3\nG0 X10 Z1\nG33 Z-10\n", codes::ISOR_WORD, "G33"),
            ("G7 G1 X1 Z1\n", codes::ISOR_WORD, "G1"),
            ("G91 G7 G0 X1\n", codes::ISOR_UNKNOWN_POSITION, "X1"),
            ("X1\n", codes::ISOR_WORD, "X1"),
            (
                "G7 S100 M3\nG0 X10 Z1\nG33.1 X12 Z-5 K1\n",
                codes::ISOR_THREAD_GEOMETRY,
                "X12",
            ),
            (
                "G7 S100 M3\nG0 X10 Z1\nG76 P1 Z-10 I0 J0.1 K1\n",
                codes::ISOR_G76,
                "I0",
            ),
            (
                "G7 S100 M3\nG0 X10 Z1\nG76 P1 Z-10 I-1 J1 K1\n",
                codes::ISOR_G76,
                "K1",
            ),
            (
                "G7 S100 M3\nG0 X10 Z1\nG76 P1 Z-10 I-1 K1\n",
                codes::ISOR_WORD,
                "G76",
            ),
            ("G0 X1 (open\n", codes::ISOR_SYNTAX, "("),
            // An O-word line that cannot be read, in a branch that is not run: reported
            // all the same (its branch structure would be guessed).
            (
                "G7 G0 X1 Z0\n#1=5\no1 if [#1 LT 2]\no1 elseif [#1 LT 20] ?\no1 endif\nM2\n",
                codes::ISOR_SYNTAX,
                "?",
            ),
        ];
        for (text, code, marked) in cases {
            let src = SourceFile::new("t.ngc", *text);
            let (_, d) = parse(&src, &Options::default());
            first_error(&d, text, *code, marked);
        }
    }

    #[test]
    fn unsupported_warn_keeps_the_line_and_forgets_the_position() {
        let src = SourceFile::new("t.ngc", "G7 G0 X10 Z1\nG10 L2 P1 X0\nG0 X5\n");
        let (p, d) = parse(
            &src,
            &Options {
                unsupported: Unsupported::Warn,
                block_delete: None,
                subroutine_path: Vec::new(),
            },
        );
        let d: Vec<_> = d
            .into_iter()
            .filter(|d| d.code != codes::ISOR_NO_END)
            .collect();
        assert_eq!(d.len(), 1);
        assert_eq!(d[0].severity, Severity::Warning);
        assert!(
            matches!(&p.items[1].kind, ItemKind::Opaque { block: Some(_), text, .. } if text == "G10 L2 P1 X0")
        );
        assert!(matches!(p.items[2].kind, ItemKind::Rapid { to } if to.z.is_none()));
    }

    /// A kept line that cannot move (a block-deleted path setting) leaves the position
    /// known: the thread after it is read (issue 14, found on LinuxCNC's own g33_blend).
    #[test]
    fn a_kept_line_that_cannot_move_keeps_the_position() {
        let src = SourceFile::new(
            "t.ngc",
            "G7 G95 S300 M3\nG0 X10 Z1\n/G64 P0.002 Q0.001\nG33 Z-10 K1.5\nM30\n",
        );
        let (p, d) = parse(
            &src,
            &Options {
                unsupported: Unsupported::Warn,
                block_delete: None,
                subroutine_path: Vec::new(),
            },
        );
        assert!(!crate::diag::has_errors(&d), "{d:?}");
        let kept = p
            .items
            .iter()
            .find_map(|i| match &i.kind {
                ItemKind::Opaque { block: Some(c), .. } => Some(c.moves),
                _ => None,
            })
            .expect("the line is kept");
        assert!(!kept);
        assert!(
            p.items
                .iter()
                .any(|i| matches!(i.kind, ItemKind::ThreadPass(_)))
        );
        // With an axis word it may move: the position after it is unknown.
        let src = SourceFile::new("t.ngc", "G7 G0 X10 Z1\n/G0 X20\nG0 X5\nM30\n");
        let (p, _) = parse(
            &src,
            &Options {
                unsupported: Unsupported::Warn,
                block_delete: None,
                subroutine_path: Vec::new(),
            },
        );
        let end = p
            .items
            .iter()
            .fold(Pos::UNKNOWN, |pos, i| i.kind.end_position(pos));
        assert_eq!(end.z, None);
    }

    /// LinuxCNC reads the lines it skips: a comment it cannot read there, or the closing
    /// `%`, stops it.
    #[test]
    fn skipped_lines_are_read_as_linuxcnc_reads_them() {
        let head = "%\nG7 G18 G21 G90 G95\n";
        let nested = format!("{head}o1 sub\n(a (b)\no1 endsub\nM2\n%\n");
        let (_, d) = run(&nested);
        let e = first_error(&d, &nested, codes::ISOR_SYNTAX, "(");
        assert!(e.message.contains("Nested comment found"), "{e:?}");
        let unclosed = format!("{head}o1 if [0]\n  (a\no1 endif\nM2\n%\n");
        let (_, d) = run(&unclosed);
        let e = first_error(&d, &unclosed, codes::ISOR_SYNTAX, "(");
        assert!(e.message.contains("Unclosed comment found"), "{e:?}");
        let percent = format!("{head}o<turn> sub\n%\no<turn> endsub\nM2\n");
        let (_, d) = run(&percent);
        let e = first_error(&d, &percent, codes::ISOR_CONTROL, "%");
        assert!(e.message.contains("'Oturn' before EOF"), "{e:?}");
        // Lines not run are not read: after the end.
        for ok in [
            format!("{head}M2\n(a (b)\n%\n"),
            format!("{head}o1 sub\n(a) ; (b\no1 endsub\nM2\n%\n"),
        ] {
            let (_, d) = run(&ok);
            assert!(!d.iter().any(|d| d.is_error()), "{ok:?}: {d:?}");
        }
    }

    /// A value after an O-word's keyword on a line LinuxCNC runs stops it ("Unexpected
    /// character after O-word"); on a line it reaches by skipping, it does not look.
    #[test]
    fn an_oword_takes_only_its_arguments() {
        let head = "%\nG7 G18 G21 G90 G95\n";
        for (text, marked) in [
            (format!("{head}o100 sub [1]\no100 endsub\nM2\n%\n"), "[1]"),
            (
                format!("{head}o2 if [1]\no2 else [3]\no2 endif\nM2\n%\n"),
                "[3]",
            ),
        ] {
            let (_, d) = run(&text);
            let e = first_error(&d, &text, codes::ISOR_CONTROL, marked);
            assert!(e.message.contains("Unexpected character"), "{e:?}");
        }
        let skipped = format!("{head}o1 if [0]\no1 elseif [1] [2]\no1 endif\nM2\n%\n");
        let (_, d) = run(&skipped);
        assert!(!d.iter().any(|d| d.is_error()), "{d:?}");
    }

    /// A refused G70 leaves ncthread not knowing the motion mode LinuxCNC has after it (its
    /// last move's): the axis lines after it are not blamed as a G70 without Q.
    #[test]
    fn no_follow_on_report_after_a_refused_cycle() {
        let text = "%\nG7 G18 G21 G90 G95\nS500 M3\nG0 X34 Z-30\nG42.1 D0.8 L2\nG70 Q100 X32 Z-30 F0.08\nG40 X34\nZ5\nM2\no100 sub\nG1 X12 Z1\nG1 X18 Z-2\nG1 Z-30\no100 endsub\n%\n";
        let (_, d) = run(text);
        let errors: Vec<_> = d.iter().filter(|d| d.is_error()).collect();
        assert_eq!(errors.len(), 1, "{errors:?}");
        first_error(&d, text, codes::ISOR_ROUGHING, "G70");
    }

    #[test]
    fn block_delete_follows_the_switch_or_is_refused() {
        let src = SourceFile::new(
            "t.ngc",
            "G7 G18 G21 G95\nS500 M3\nG0 X20 Z2\n/G1 Z-10 F0.1\n/ G0 X30\nG0 X40\nM30\n",
        );
        let read = |block_delete| {
            parse(
                &src,
                &Options {
                    unsupported: Unsupported::Error,
                    block_delete,
                    subroutine_path: Vec::new(),
                },
            )
        };
        let moves = |p: &Program| {
            p.items
                .iter()
                .filter(|i| matches!(i.kind, ItemKind::Rapid { .. } | ItemKind::Feed { .. }))
                .count()
        };
        // Off: the lines run (LinuxCNC's default).
        let (p, d) = read(Some(BlockDelete::Off));
        assert!(d.is_empty(), "{d:?}");
        assert_eq!(moves(&p), 4);
        // On: they are skipped, with one warning at the first.
        let (p, d) = read(Some(BlockDelete::On));
        assert_eq!(moves(&p), 2);
        assert_eq!(d.len(), 1, "{d:?}");
        assert_eq!(d[0].code, codes::ISOR_BLOCK_DELETE);
        assert_eq!(
            d[0].location.as_ref().map(|l| (l.line, l.column)),
            Some((4, 1))
        );
        // Not said: refused at the `/`.
        let (_, d) = read(None);
        let errors: Vec<_> = d.iter().filter(|d| d.is_error()).collect();
        assert_eq!(errors.len(), 2, "{d:?}");
        assert_eq!(errors[0].code, codes::ISOR_UNSUPPORTED);
        assert_eq!(
            errors[0].location.as_ref().map(|l| (l.line, l.column)),
            Some((4, 1))
        );
    }

    #[test]
    fn g76_reads_linuxcnc_words() {
        // The LinuxCNC example shape: drive line Ø20 Z5, I-1 J0.4 K1.8 (diameters, G7),
        // R2, Q29.5, H1, E2 L3.
        let text = format!("{HEAD}G0 X20 Z5\nG76 P1.5 Z-20 I-1 J0.4 K1.8 Q29.5 R2 H1 E2 L3\n");
        let (p, d) = run(&text);
        assert!(d.is_empty(), "{d:?}");
        let ItemKind::ThreadCycle(c) = &p.items.last().unwrap().kind else {
            panic!()
        };
        assert_eq!(c.crest, mm(19.0));
        assert_eq!((c.depth, c.first_depth), (mm(0.9), mm(0.2)));
        assert_eq!(c.retract, Retract::AboveCut(mm(1.4)));
        assert_eq!(c.spring_passes, 1);
        assert!(!c.internal);
        assert!(c.entry_infeed);
        assert_eq!(c.start_angle, Angle::ZERO);
        let e = lower::expand(c).unwrap();
        // 0.2·√n < 0.9 for n = 1…20, then the full depth and one spring pass.
        assert_eq!(e.passes.len(), 22);
        let p1 = e.passes[0];
        // Pass 1: line Ø18.6 from Z5 − 0.2·tan 29.5° = 4.8868 (rs274: X9.3 Z4.8868).
        assert_eq!(p1.start, Pos::new(mm(20.4), mm(4.8868)));
        assert_eq!(p1.pass.to, Pos::new(mm(18.6), mm(-19.604)));
        // rs274: a rapid back to X10.7 (Ø21.4), then in along X, synchronised at
        // K_taper = 1.5·√(2² + 0.9²)/2 = 1.644878 per rev, to X10.2 (Ø20.4).
        assert_eq!(
            e.moves[0].kind,
            lower::Move::Rapid(Pos::new(mm(21.4), mm(4.8868)))
        );
        let infeed = p1.pass.infeed.unwrap();
        assert_eq!(infeed.x, mm(20.4));
        assert_eq!(infeed.advance.mm(), "1.64487841496");
        let last = e.passes[21];
        assert_eq!(last.pass.to, Pos::new(mm(17.2), mm(-20.0)));
        assert_eq!(last.retract_x, mm(20.0));
    }
}

//! The czech front end: blocks → IR items, with the dialect's rules as diagnostics.
//!
//! A block is read as LinuxCNC's interpreter reads one (`interp_convert.cc`): its words are
//! first sorted by modal group into a [`Words`] (`words.rs`, which reports repeated and
//! conflicting words), then [`FrontEnd::execute`] carries them out, one step per group in one
//! documented order. The switching steps (spindle, coolant, program end) are the ones every
//! front end shares ([`Switches`]); the motion steps are in `motion.rs`, the G33 thread pass
//! in `thread.rs`.

mod motion;
mod thread;
mod words;

use std::collections::HashMap;
use std::ops::Range;

use super::syntax::{self, Block, Value};
use crate::diag::{Code, Diagnostic};
use crate::dialect::Unsupported;
use crate::dialect::czech::codes;
use crate::dialect::czech::profile::{CzechProfile, InitialMotion};
use crate::dialect::machine::Switches;
use crate::dialect::read::{Keep, Reader, UnsupportedWording};
use crate::fixed::{Decimal, Length, NumberError};
use crate::ir::{ItemKind, ModalContext, Program, SpindleMode};
use crate::source::{Line, SourceFile, Span};
use syntax::Word;
use words::Words;

/// How the czech reader words its unsupported policy.
const UNSUPPORTED: UnsupportedWording = UnsupportedWording {
    code: codes::CZR_UNSUPPORTED,
    more: "unsupported words in this block",
    in_one: "in a block",
    many: "blocks",
    own_block: "write this word in a block of its own",
    refuse_help: "ncthread never guesses the meaning of undocumented constructs; `--unsupported warn` keeps the block as an opaque item",
    keep_help: "the block is kept as written; only the czech emitter can write it back, and positions after it are unknown",
};

#[derive(Clone, Debug, Default)]
pub struct Options {
    pub unsupported: Unsupported,
    /// The profile file's name, for the messages that cite its constant 8.
    pub profile_name: Option<String>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Motion {
    Rapid,
    Feed,
    Thread,
    /// G02 (true) or G03, as written: the profile says which way G02 turns.
    Arc(bool),
}

/// The F register: its value and whether it was last written as a lead (in a G33 block).
#[derive(Clone, Copy, Debug)]
struct FRegister {
    value: Length,
    is_lead: bool,
}

/// What the blocks after a J/E thread block must be. **\[seed\]**
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum AfterRunout {
    Nothing,
    EmptyBlock { thread: Span },
    AllAxes { thread: Span },
}

struct FrontEnd<'a> {
    r: Reader<'a>,
    profile: &'a CzechProfile,
    options: &'a Options,
    motion: Motion,
    incremental: bool,
    f: Option<FRegister>,
    params: HashMap<u32, Decimal>,
    after_runout: AfterRunout,
}

/// Reads a czech program. The program holds every item that could be read; the program is
/// usable only when no diagnostic is an error.
#[cfg(test)]
pub fn parse(
    src: &SourceFile,
    profile: &CzechProfile,
    options: &Options,
) -> (Program, Vec<Diagnostic>) {
    read(src, profile, options, Keep::Program)
}

/// [`parse`], keeping the program or only the diagnostics.
pub(crate) fn read(
    src: &SourceFile,
    profile: &CzechProfile,
    options: &Options,
    keep: Keep,
) -> (Program, Vec<Diagnostic>) {
    let mut fe = FrontEnd {
        r: Reader::new(src, super::ID, keep),
        profile,
        options,
        motion: match profile.initial_motion {
            InitialMotion::Rapid => Motion::Rapid,
            InitialMotion::Feed => Motion::Feed,
        },
        incremental: false,
        f: None,
        params: HashMap::new(),
        after_runout: AfterRunout::Nothing,
    };
    // M02/M30 end the program: blocks after it never run. **[decided]** (as LinuxCNC)
    let mut ended = false;
    let mut block = Block::default();
    for line in src.lines() {
        // Nothing looks back past the line being read.
        fe.r.line_read();
        if line.is_blank() {
            continue;
        }
        match syntax::parse_line_into(line.text, &mut block) {
            Ok(()) if ended && !block.is_empty() && !block.delimiter => fe.r.after_end(
                codes::CZR_AFTER_END,
                src.line_span(line),
                "this block comes after the program's end (M02/M30); the control does not run it, and neither does ncthread",
                "remove it, or move the program's end after it",
            ),
            Ok(()) => {
                let first = fe.r.items.len();
                fe.block(line, &block);
                ended |= fe.r.ends_program(first);
            }
            Err(e) => {
                let code = if e.number_too_large {
                    codes::CZR_NUMBER
                } else {
                    codes::CZR_SYNTAX
                };
                fe.r.syntax_error(code, line, e.offset, e.message, e.help);
            }
        }
    }
    if let AfterRunout::EmptyBlock { thread } | AfterRunout::AllAxes { thread } = fe.after_runout {
        fe.r.error(
            codes::CZR_MISSING_BLOCK,
            thread,
            "the program ends before the blocks this J/E thread block requires",
            "after a thread block with J or E write an empty block, then a block that programs X and Z",
        );
    }
    fe.r.finish()
}

impl<'a> FrontEnd<'a> {
    fn span(&self, line: Line<'_>, range: Range<usize>) -> Span {
        self.r.src.span_in_line(line, range)
    }

    fn error(
        &self,
        code: Code,
        line: Line<'_>,
        range: Range<usize>,
        message: impl Into<String>,
    ) -> Diagnostic {
        Diagnostic::new(code, message).at(self.r.src, self.span(line, range))
    }

    fn report(&mut self, d: Diagnostic) {
        self.r.diags.push(d);
    }

    fn push(&mut self, kind: ItemKind, span: Span, number: Option<u32>) {
        self.r.push(kind, span, number);
    }

    fn block(&mut self, line: Line<'_>, block: &Block) {
        let first_item = self.r.items.len();
        let code_span = self.span(line, block.code_range.clone());
        self.check_after_runout(line, block, code_span);
        if block.delimiter {
            self.push(ItemKind::Delimiter, code_span, None);
        } else {
            let mut words = Words::default();
            if self.classify(line, block, &mut words) {
                if words.unsupported.is_empty() {
                    self.execute(line, block, &words, code_span);
                } else {
                    self.unsupported(line, block, &words, code_span);
                }
            }
        }
        // Assignments take effect after the block's motion. **[decided]**
        for a in &block.assignments {
            self.params.insert(a.param, a.value);
        }
        let span = self.r.src.line_span(line);
        self.r
            .stamp_block(first_item, block.number, block.comment.clone(), span, true);
    }

    /// The empty block and the all-axes block that must follow a J/E thread block.
    fn check_after_runout(&mut self, line: Line<'_>, block: &Block, code_span: Span) {
        match self.after_runout {
            AfterRunout::Nothing => {}
            AfterRunout::EmptyBlock { thread } => {
                if block.is_empty() {
                    self.after_runout = AfterRunout::AllAxes { thread };
                } else {
                    let range = block
                        .words
                        .first()
                        .map(|w| w.range.clone())
                        .or_else(|| block.assignments.first().map(|a| a.range.clone()))
                        .unwrap_or(block.code_range.clone());
                    self.report(self.error(codes::CZR_BLOCK_AFTER_RUNOUT, line, range, "the block after a thread block with J or E must be empty")
                        .label("expected an empty block")
                        .help(format!(
                            "insert an empty block (only a block number and/or a comment) after line {}",
                            thread.line
                        )));
                    self.after_runout = AfterRunout::Nothing;
                }
            }
            AfterRunout::AllAxes { thread } => {
                let has = |c| block.words.iter().any(|w| w.letter == c);
                let missing: Vec<&str> = [("X", has('X')), ("Z", has('Z'))]
                    .into_iter()
                    .filter(|(_, h)| !h)
                    .map(|(n, _)| n)
                    .collect();
                if !missing.is_empty() {
                    let d = Diagnostic::new(
                        codes::CZR_AXES_AFTER_RUNOUT,
                        format!("this block must program every axis after the J/E thread block on line {}", thread.line),
                    )
                    .at(self.r.src, code_span)
                    .label(format!("missing {}", missing.join(" and ")))
                    .help("write X and Z here; if the tool should not move, repeat the end position of the thread block");
                    self.r.diags.push(d);
                }
                self.after_runout = AfterRunout::Nothing;
            }
        }
    }

    fn unsupported(&mut self, line: Line<'_>, block: &Block, words: &Words<'_>, code_span: Span) {
        let keep = self.options.unsupported == Unsupported::Warn;
        let found = words
            .unsupported
            .iter()
            .map(|(word, what)| {
                let text = &line.text[word.range.clone()];
                (
                    self.span(line, word.range.clone()),
                    format!("`{text}`: {what} is not supported"),
                )
            })
            .collect();
        let thread = words.motion.is_some_and(|(m, _)| m == Motion::Thread);
        if !self.r.unsupported(&UNSUPPORTED, found, keep, thread) {
            return;
        }
        // A kept block must not change what ncthread follows: its motion, distance or
        // feed mode, F, S, T, D or spindle words would take effect on the control and not
        // here, and the blocks after it would be read wrongly.
        let state = words
            .motion
            .map(|(_, w)| w)
            .or(words.distance.map(|(_, w)| w))
            .or(words.feed_mode.map(|(_, w)| w))
            .or(words.spindle.map(|(_, w)| w))
            .or(words.end.map(|(_, w)| w))
            .or(words.gears.first().map(|(_, w)| *w))
            .or(words.coolant.first().map(|(_, w)| *w))
            .or(['F', 'S', 'T', 'D'].iter().find_map(|&c| words.get(c)));
        if let Some(w) = state {
            let span = self.span(line, w.range.clone());
            self.r
                .state_in_opaque(&UNSUPPORTED, span, &line.text[w.range.clone()]);
            return;
        }
        // The block number is the writer's to give.
        let code = line.text[block.code_range.clone()].trim_start();
        let code = match code.strip_prefix(['N', 'n']) {
            Some(rest) if block.number.is_some() => rest
                .trim_start_matches(|c: char| c.is_ascii_digit())
                .trim_start(),
            _ => code,
        };
        let context = ModalContext {
            inch: false,
            diameter: true,
            incremental: self.incremental,
            per_minute: None,
            // The reader cannot tell: positions after the block are unknown.
            moves: true,
            cycle: false,
            compensation: false,
        };
        self.r
            .keep_opaque(code.to_string(), code_span, None, context);
    }

    /// A number on the 0.0001 mm grid, or a diagnostic.
    fn length(&mut self, line: Line<'_>, word: &Word, value: Decimal) -> Option<Length> {
        match value.to_length() {
            Ok(v) => Some(v),
            Err(e) => {
                self.number_error(line, word.range.clone(), e, "0.0001 mm");
                None
            }
        }
    }

    fn number_error(&mut self, line: Line<'_>, range: Range<usize>, e: NumberError, grid: &str) {
        let text = line.text[range.clone()].to_string();
        let (message, help) = match e {
            NumberError::TooPrecise { .. } if grid == "whole" => (
                format!("`{text}` must be a whole number"),
                "write it without a fraction".to_string(),
            ),
            NumberError::TooPrecise { .. } => (
                format!("`{text}` is finer than {grid}"),
                format!(
                    "ncthread keeps numbers exact on a {grid} grid; round the value in the source"
                ),
            ),
            NumberError::TooLarge => (
                format!("`{text}` is too large"),
                "check the value".to_string(),
            ),
        };
        self.report(
            self.error(codes::CZR_NUMBER, line, range, message)
                .help(help),
        );
    }

    fn whole(&mut self, line: Line<'_>, word: &Word) -> Option<u32> {
        let Value::Number(d) = word.value else {
            return None;
        };
        if d.is_negative() {
            let text = line.text[word.range.clone()].to_string();
            self.report(
                self.error(
                    codes::CZR_NUMBER,
                    line,
                    word.range.clone(),
                    format!("`{text}` must not be negative"),
                )
                .help("write a positive whole number"),
            );
            return None;
        }
        match d.to_whole() {
            Ok(v) if v <= u32::MAX as i64 => Some(v as u32),
            Ok(_) => {
                self.number_error(line, word.range.clone(), NumberError::TooLarge, "whole");
                None
            }
            Err(e) => {
                self.number_error(line, word.range.clone(), e, "whole");
                None
            }
        }
    }

    /// Resolves an axis word to an absolute coordinate.
    fn axis(
        &mut self,
        line: Line<'_>,
        word: Option<&Word>,
        current: Option<Length>,
    ) -> Option<Option<Length>> {
        let Some(word) = word else { return Some(None) };
        let Value::Number(d) = word.value else {
            return None;
        };
        let v = self.length(line, word, d)?;
        if !self.incremental {
            return Some(Some(v));
        }
        match current {
            Some(c) => Some(Some(c + v)),
            None => {
                self.report(
                    self.error(
                        codes::CZR_UNKNOWN_POSITION,
                        line,
                        word.range.clone(),
                        "incremental move from an unknown position",
                    )
                    .label("G91 adds this to a position not programmed yet")
                    .help("program an absolute position (G90) for this axis first"),
                );
                None
            }
        }
    }

    /// Carries out one block whose words [`Self::classify`] sorted: one step per modal group,
    /// in the czech control's order, which is LinuxCNC's (`interp_convert.cc`) adapted to
    /// what the dialect has (no plane, units, compensation, tool length or coordinate system
    /// words; F is read with the motion, as it is a lead in a G33 block):
    ///
    /// 1. feed mode: G94 / G95 ([`Self::feed_mode`]);
    /// 2. R parameter assignments, as items ([`Self::assignments`]; their values take
    ///    effect after the block);
    /// 3. tool: T and D ([`Self::tool`]);
    /// 4. gear range: the profile's M codes ([`Self::gear_range`]);
    /// 5. `&` words, kept opaque ([`Self::opaque_words`]);
    /// 6. speed mode (G96 / G97), spindle (S, M03 / M04) and coolant on (M07 / M08):
    ///    [`Switches::before_motion`];
    /// 7. distance mode G90 / G91 and motion mode ([`Self::modes`]);
    /// 8. dwell (G04, [`Self::dwell`]) or motion with its F ([`Self::motion_item`]);
    /// 9. coolant off (M09), spindle stop (M05) and program end (M02 / M30):
    ///    [`Switches::after_motion`]. The czech control switches off after the block's own
    ///    cut, which still has coolant and a turning spindle. **\[decided\]**
    fn execute(&mut self, line: Line<'_>, block: &Block, words: &Words<'_>, code_span: Span) {
        let number = block.number;
        self.feed_mode(line, words, number);
        self.assignments(line, block);
        self.tool(line, words, number);
        self.gear_range(line, words, number);
        self.opaque_words(line, block);
        let switches = self.switches(line, words);
        switches.before_motion(&mut self.r, number);
        self.modes(words);
        match words.dwell {
            Some((g04, time)) => self.dwell(line, g04, time, number),
            None => self.motion_item(line, words, code_span, number),
        }
        switches.after_motion(&mut self.r, number);
    }

    /// Step 1, feed mode: G94 (per minute) or G95 (per revolution), an item of its own.
    fn feed_mode(&mut self, line: Line<'_>, words: &Words<'_>, number: Option<u32>) {
        if let Some((mode, w)) = words.feed_mode {
            let span = self.span(line, w.range.clone());
            self.push(ItemKind::FeedMode(mode), span, number);
        }
    }

    /// Step 2, R parameter assignments: one item each, in the block's order. The reader
    /// takes their values after the block (see [`Self::block`]).
    fn assignments(&mut self, line: Line<'_>, block: &Block) {
        for a in &block.assignments {
            let span = self.span(line, a.range.clone());
            self.push(
                ItemKind::ParamAssign {
                    number: a.param,
                    value: a.value,
                },
                span,
                block.number,
            );
        }
    }

    /// Step 3, tool: T (the tool) and D (its offset), one item stamped with T's span, or D's
    /// when T is not written.
    fn tool(&mut self, line: Line<'_>, words: &Words<'_>, number: Option<u32>) {
        let tool = words.get('T').and_then(|w| self.whole(line, w));
        let offset = words.get('D').and_then(|w| self.whole(line, w));
        if tool.is_some() || offset.is_some() {
            let w = words
                .get('T')
                .or(words.get('D'))
                .expect("T or D is present");
            let span = self.span(line, w.range.clone());
            self.push(
                ItemKind::Tool {
                    number: tool,
                    offset,
                },
                span,
                number,
            );
        }
    }

    /// Step 4, gear range: each of the profile's gear range M codes, in the block's order.
    fn gear_range(&mut self, line: Line<'_>, words: &Words<'_>, number: Option<u32>) {
        for (gear, w) in &words.gears {
            let span = self.span(line, w.range.clone());
            self.push(
                ItemKind::GearRange {
                    code: *gear,
                    machine: super::ID,
                },
                span,
                number,
            );
        }
    }

    /// Step 5, `&` words (`&1100`): kept as written, for the czech emitter only.
    fn opaque_words(&mut self, line: Line<'_>, block: &Block) {
        for (text, range) in &block.opaque {
            let span = self.span(line, range.clone());
            self.push(
                ItemKind::Opaque {
                    dialect: super::ID,
                    text: text.clone(),
                    block: None,
                },
                span,
                block.number,
            );
        }
    }

    /// Step 6 and 9's words, for the steps the front ends share: G96 / G97, S with M03 /
    /// M04 (stamped with S's span, or the M code's), M07 / M08 / M09, M05 and the end code.
    /// S is checked here, after the tool's T and D.
    fn switches(&mut self, line: Line<'_>, words: &Words<'_>) -> Switches {
        let speed = words.get('S').and_then(|w| self.whole(line, w));
        let direction = words.spindle.and_then(|(d, _)| d);
        let span = |fe: &Self, w: &Word| fe.span(line, w.range.clone());
        let spindle_word = words.get('S').or(words.spindle.map(|(_, w)| w));
        Switches {
            spindle_mode: words.speed_mode.map(|(g96, w)| {
                let mode = if g96 {
                    SpindleMode::SurfaceSpeed {
                        limit: None,
                        feet: false,
                    }
                } else {
                    SpindleMode::Rpm
                };
                (mode, span(self, w))
            }),
            spindle: spindle_word.map(|w| (speed, direction, span(self, w))),
            coolant: words
                .coolant
                .iter()
                .map(|&(c, w)| (c, span(self, w)))
                .collect(),
            spindle_stop: match words.spindle {
                Some((None, w)) => Some(span(self, w)),
                _ => None,
            },
            end: words.end.map(|(end, w)| (end, span(self, w))),
        }
    }

    /// Step 7, distance mode (G90 / G91) and motion mode (G00, G01, G02, G03, G33): modal
    /// state the block's motion and the blocks after it use; no items.
    fn modes(&mut self, words: &Words<'_>) {
        if let Some((incremental, _)) = words.distance {
            self.incremental = incremental;
        }
        if let Some((motion, _)) = words.motion {
            self.motion = motion;
        }
    }
}

fn code_span_range(line: Line<'_>, span: Span) -> Range<usize> {
    let range = span.range();
    range.start.saturating_sub(line.offset)..range.end.saturating_sub(line.offset)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dialect::czech::profile::{Constant8, CzechArcs, CzechDwell};
    use crate::fixed::Lead;
    use crate::ir::{Chamfer, Pos, ThreadPass};

    fn run(text: &str, constant8: Option<&str>) -> (Program, Vec<Diagnostic>) {
        let profile = CzechProfile {
            constant8: constant8.map(|c| Constant8::parse(c).unwrap()),
            ..Default::default()
        };
        parse(
            &SourceFile::new("t.nc", text),
            &profile,
            &Options::default(),
        )
    }

    /// Dwells and surface speed as the profile declares them, and their refusals.
    /// An M number past u32 is no gear range that wraps onto a small one (M4294967338 was
    /// read as M42).
    #[test]
    fn a_huge_m_number_is_no_gear_range() {
        let (_, diags) = run("N10 M03 S500\nN20 M4294967338\n", None);
        assert_eq!(diags[0].code, codes::CZR_UNSUPPORTED, "{diags:?}");
    }

    #[test]
    fn dwell_and_surface_speed_follow_the_profile_form() {
        let read = |dwell: CzechDwell, css: bool, text: &str| {
            let profile = CzechProfile {
                dwell,
                surface_speed: css,
                ..Default::default()
            };
            let head = "N10 M03 S500 G95\nN20 G00 X20. Z0.\nN30 ";
            let src = SourceFile::new("t.nc", format!("{head}{text}\nN40 Z-5.\n"));
            let (p, d) = parse(&src, &profile, &Options::default());
            let kinds: Vec<ItemKind> = p.items[3..].iter().map(|i| i.kind.clone()).collect();
            let first = d
                .iter()
                .find(|d| d.is_error())
                .map(|d| (d.code.id, d.location.as_ref().map(|l| l.column)));
            (kinds, first)
        };
        let secs = |text: &str| ItemKind::Dwell {
            seconds: Decimal::parse(text).unwrap(),
        };
        let z5 = ItemKind::Rapid {
            to: Pos {
                x: None,
                z: Some(Length::from_mm(-5)),
            },
        };
        // Each form: the time word is the time (X is no axis in a G04 block).
        assert_eq!(
            read(CzechDwell::XSeconds, false, "G04 X0.5"),
            (vec![secs("0.5"), z5.clone()], None)
        );
        assert_eq!(
            read(CzechDwell::FSeconds, false, "G04 F2."),
            (vec![secs("2."), z5.clone()], None)
        );
        assert_eq!(
            read(CzechDwell::PMilliseconds, false, "G04 P500"),
            (vec![secs("0.500"), z5.clone()], None)
        );
        // G04 is not modal: the next block moves again.
        // Refusals: no time, a negative time, motion in the block, P outside G04, no form.
        let refused = |dwell, text| read(dwell, false, text).1;
        assert_eq!(
            refused(CzechDwell::PMilliseconds, "G04"),
            Some(("CZR025", Some(5)))
        );
        assert_eq!(
            refused(CzechDwell::PMilliseconds, "G04 P-5"),
            Some(("CZR025", Some(9)))
        );
        assert_eq!(
            refused(CzechDwell::PMilliseconds, "G04 P1.5"),
            Some(("CZR025", Some(9)))
        );
        assert_eq!(
            refused(CzechDwell::FSeconds, "G04 F1. X30."),
            Some(("CZR025", Some(13)))
        );
        assert_eq!(
            refused(CzechDwell::PMilliseconds, "G01 Z-3. P5 F0.1"),
            Some(("CZR011", Some(14)))
        );
        assert_eq!(
            refused(CzechDwell::None, "G04 X1."),
            Some(("CZR011", Some(5)))
        );
        // G96 S is a surface speed; G97 S rpm; refused without the key.
        let surface =
            |limit| ItemKind::SpindleMode(SpindleMode::SurfaceSpeed { limit, feet: false });
        assert_eq!(
            read(CzechDwell::None, true, "G96 S180").0[..2],
            [
                surface(None),
                ItemKind::Spindle {
                    speed: Some(180),
                    direction: None
                }
            ]
        );
        assert_eq!(
            read(CzechDwell::None, true, "G97 S600").0[0],
            ItemKind::SpindleMode(SpindleMode::Rpm)
        );
        assert_eq!(
            read(CzechDwell::None, true, "G96 G97 S600").1,
            Some(("CZR019", Some(9)))
        );
        assert_eq!(
            read(CzechDwell::None, false, "G96 S180").1,
            Some(("CZR011", Some(5)))
        );
    }

    /// Arcs as the profile declares them: the centre, the direction, and the refusals.
    #[test]
    fn arcs_follow_the_profile_form() {
        let arc = |form: CzechArcs, mirrored: bool, text: &str| {
            let profile = CzechProfile {
                arcs: form,
                arcs_mirrored: mirrored,
                ..Default::default()
            };
            let head = "N10 M03 S500 G95\nN20 G00 X20. Z0.\nN30 G01 F0.1\nN40 ";
            let src = SourceFile::new("t.nc", format!("{head}{text}\n"));
            let (p, d) = parse(&src, &profile, &Options::default());
            let arc = p.items.iter().find_map(|i| match &i.kind {
                ItemKind::Arc {
                    to,
                    centre,
                    clockwise,
                    ..
                } => Some((*to, **centre, *clockwise)),
                _ => None,
            });
            let first = d.iter().find(|d| d.is_error()).map(|d| d.code.id);
            (arc, first)
        };
        let mm = |v: i64| Length::from_mm(v);
        let end = Pos::new(mm(30), mm(-5));
        // I a radius; the same arc with I a diameter value; with R.
        assert_eq!(
            arc(CzechArcs::IkRadius, false, "G03 X30. Z-5. I0. K-5."),
            (Some((end, Pos::new(mm(20), mm(-5)), false)), None)
        );
        assert_eq!(
            arc(CzechArcs::IkDiameter, false, "G02 X30. Z-5. I10. K0."),
            (Some((end, Pos::new(mm(30), mm(0)), true)), None)
        );
        assert_eq!(
            arc(CzechArcs::Radius, false, "G02 X30. Z-5. R5."),
            (Some((end, Pos::new(mm(30), mm(0)), true)), None)
        );
        // A mirrored machine's G02 is LinuxCNC's G3 for the same path.
        assert_eq!(
            arc(CzechArcs::IkRadius, true, "G02 X30. Z-5. I0. K-5."),
            (Some((end, Pos::new(mm(20), mm(-5)), false)), None)
        );
        // Refusals: no centre, an end off the circle, a radius too small, words of the
        // other form, no arcs declared.
        let refused = |form, text| arc(form, false, text).1;
        assert_eq!(
            refused(CzechArcs::IkRadius, "G02 X30. Z-5."),
            Some("CZR024")
        );
        assert_eq!(
            refused(CzechArcs::IkRadius, "G02 X30. Z-5. I5. K1."),
            Some("CZR024")
        );
        assert_eq!(
            refused(CzechArcs::Radius, "G02 X30. Z-10. R2."),
            Some("CZR024")
        );
        assert_eq!(
            refused(CzechArcs::Radius, "G02 X20. Z0. R2."),
            Some("CZR024")
        );
        assert_eq!(
            refused(CzechArcs::Radius, "G02 X30. Z-5. I5. K0."),
            Some("CZR011")
        );
        assert_eq!(
            refused(CzechArcs::IkRadius, "G02 X30. Z-5. R5."),
            Some("CZR011")
        );
        assert_eq!(
            refused(CzechArcs::None, "G02 X30. Z-5. I5. K0."),
            Some("CZR011")
        );
        assert_eq!(refused(CzechArcs::IkRadius, "G02 I5. K0."), Some("CZR024"));
    }

    /// The first error's code, line and column.
    fn first_error(text: &str, constant8: Option<&str>) -> (&'static str, u32, u32) {
        let (_, diags) = run(text, constant8);
        let d = diags
            .iter()
            .find(|d| d.is_error())
            .unwrap_or_else(|| panic!("no error for {text:?}"));
        let loc = d.location.as_ref().expect("located");
        (d.code.id, loc.line, loc.column)
    }

    fn passes(text: &str, constant8: Option<&str>) -> Vec<ThreadPass> {
        let (program, diags) = run(text, constant8);
        assert!(!diag::has_errors(&diags), "{diags:?}");
        program
            .items
            .iter()
            .filter_map(|i| match &i.kind {
                ItemKind::ThreadPass(p) => Some(**p),
                _ => None,
            })
            .collect()
    }

    use crate::diag;

    const RUNOUT: &str =
        "N10 M03 S50\nN20 G00 X64. Z5.\nN30 G33 Z-100. F6. J12\nN40\nN50 G00 X70. Z-100.\n";

    #[test]
    fn every_rule_has_its_code_line_and_column() {
        type Case<'a> = (&'a str, Option<&'a str>, (&'a str, u32, u32));
        let cases: &[Case] = &[
            ("N10 G00 X30. Z", None, ("CZR001", 1, 14)),
            (
                "N10 M03 S1\nN20 G00 X1. Z1.\nN30 G33 Z-5. F1. E2",
                Some("+00120000"),
                ("CZR002", 3, 18),
            ),
            (
                "N10 M03 S1\nN20 G00 X1. Z1.\nN30 G33 Z-50. F120.",
                None,
                ("CZR003", 3, 15),
            ),
            (RUNOUT, None, ("CZR004", 3, 20)),
            (RUNOUT, Some("04000000"), ("CZR005", 3, 20)),
            (
                &format!("N5 R04=161.0\n{RUNOUT}"),
                Some("04000000"),
                ("CZR006", 4, 20),
            ),
            (
                &format!("N5 R04=20.0\n{RUNOUT}"),
                Some("04000000"),
                ("CZR007", 4, 20),
            ),
            (
                &format!("N5 R04=420.0\n{RUNOUT}"),
                Some("04000000"),
                ("CZR007", 4, 20),
            ),
            (RUNOUT, Some("80000000"), ("CZR008", 3, 20)),
            (
                "N10 M03 S50\nN20 G00 X64. Z5.\nN30 G33 Z-100. F6. J12\nN40 X70.\n",
                Some("+00120000"),
                ("CZR009", 4, 5),
            ),
            (
                "N10 M03 S50\nN20 G00 X64. Z5.\nN30 G33 Z-100. F6. J12\nN40\nN50 Z-100.\n",
                Some("+00120000"),
                ("CZR010", 5, 1),
            ),
            ("N10 G84 X1.", None, ("CZR011", 1, 5)),
            ("N10 G02 X1. Z1.", None, ("CZR011", 1, 5)),
            ("N10 G00 X1. P5", None, ("CZR011", 1, 13)),
            ("N10 G00 X1. Z1.\nN20 G33 Z-5.", None, ("CZR012", 2, 1)),
            (
                "N10 G00 X1. Z1.\nN20 G33 Z-5. F1. I400",
                None,
                ("CZR013", 2, 18),
            ),
            ("N10 G91 X1.", None, ("CZR014", 1, 9)),
            ("N10 G33 X5. Z-5. F1.", None, ("CZR014", 1, 1)),
            ("N10 X1.000001", None, ("CZR015", 1, 5)),
            ("N10 S12.5", None, ("CZR015", 1, 5)),
            (RUNOUT, Some("+00320000"), ("CZR016", 3, 20)),
            (
                "N10 G00 X1. Z1.\nN20 G33 Z-5. F1. J7",
                Some("+00120000"),
                ("CZR017", 2, 1),
            ),
            ("N10 G00 X1. Z1.\nN20 G33 X9. F1.", None, ("CZR017", 2, 1)),
            ("N10 G33 Z1. FR3", None, ("CZR018", 1, 13)),
            ("N10 G00 G01 X1.", None, ("CZR019", 1, 9)),
            ("N10 X1. N20", None, ("CZR019", 1, 9)),
            ("N10 M03 M04", None, ("CZR019", 1, 9)),
            ("N10 G00 X1. Z1.\nN20 G01 Z-5.", None, ("CZR020", 2, 1)),
            (
                "N10 G00 X1. Z1.\nN20 G33 Z-5. F1. J0",
                Some("+00120000"),
                ("CZR021", 2, 18),
            ),
            (
                "N10 G00 X1. Z1.\nN20 G33 Z-5. F1. J1",
                Some("+00120000"),
                ("CZR022", 2, 1),
            ),
        ];
        for (text, c8, expected) in cases {
            assert_eq!(
                first_error(text, *c8),
                *expected,
                "{text:?} with constant 8 {c8:?}"
            );
        }
    }

    #[test]
    fn runout_and_entry_angles_come_from_constant_8_or_parameters() {
        // Direct mode, axis X, +12.5°: offset 2·12·tan 12.5° = 24·0.2216947 = 5.3207.
        let p = passes(RUNOUT, Some("+00112500"))[0];
        assert_eq!(
            p.exit,
            Some(Chamfer {
                length: Length::from_mm(12),
                offset: Length::from_steps(53_207)
            })
        );
        // Negative sign: towards −X.
        let p = passes(RUNOUT, Some("-00112500"))[0];
        assert_eq!(p.exit.unwrap().offset, Length::from_steps(-53_207));
        // Parameter mode R04 = -120.000: axis X, 20° towards −X: 2·12·tan 20° = 8.7353.
        let p = passes(&format!("N5 R04= -00120.000\n{RUNOUT}"), Some("04000000"))[0];
        assert_eq!(p.exit.unwrap().offset, Length::from_steps(-87_353));
        // Entry without its own parameter uses the runout parameter. **[decided]**
        let entry = "N5 R04=118.0\nN10 M04 S50\nN20 X71.798 Z-100.\nN30 Z3 F6.0 E12. G33\nN40\nN50 X64. Z3 G0\n";
        let p = passes(entry, Some("04000000"))[0];
        assert_eq!(p.entry.unwrap().offset, Length::from_steps(77_981));
    }

    #[test]
    fn seed_entry_check_thread_at_diameter_64() {
        // czech.md: start X71.798, E12., 18° → the thread is cut at Ø64.000.
        let text = "N10 M04 S50\nN20 X71.798 Z-100. R16=118.0\nN30 Z3 F6.0 E12. G33\nN40\nN50 X64. Z3 G0\n";
        let p = passes(text, Some("15160000"))[0];
        let line_x = p.to.x.unwrap();
        assert!(
            (line_x - Length::from_mm(64)).abs() <= Length::from_steps(1),
            "{line_x}"
        );
        assert_eq!(p.to.z, Some(Length::from_mm(3)));
        assert_eq!(p.lead, Lead::from_length(Length::from_mm(6)));
    }

    #[test]
    fn modal_state_and_parameters_resolve_into_items() {
        // Modal G00 from the profile, modal G33 lead from the previous G33, FRnn.
        let text = "N5 R10=250.0\nN10 M03 S100\nN20 X30. Z5.\nN30 G33 Z-20. F2.\nN40 G00 X32.\nN50 Z5.\nN60 X29.8\nN70 G33 Z-20.\nN80 G00 X40. Z300.\nN90 G33 Z0. FR10\n";
        let leads: Vec<_> = passes(text, None).iter().map(|p| p.lead).collect();
        assert_eq!(
            leads,
            [2, 2, 250].map(|mm| Lead::from_length(Length::from_mm(mm)))
        );
        // G91 adds to the position; G90 restores absolute words.
        let (program, _) = run("N10 G00 X10. Z10.\nN20 G91 X-2. Z-3.\nN30 G90 X5.\n", None);
        let ends: Vec<_> = program
            .items
            .iter()
            .map(|i| i.kind.end_position(Pos::UNKNOWN))
            .collect();
        assert_eq!(ends[1], Pos::new(Length::from_mm(8), Length::from_mm(7)));
        assert_eq!(ends[2].x, Some(Length::from_mm(5)));
    }

    #[test]
    fn comments_attach_to_the_first_item_of_their_block() {
        let (program, _) = run("N10 M03 S50 \"START\nN20 \"ONLY A COMMENT\n", None);
        assert_eq!(program.items[0].comment.as_deref(), Some("START"));
        assert_eq!(program.items[0].block_number, Some(10));
        assert_eq!(
            program.items[1].kind,
            ItemKind::Comment("ONLY A COMMENT".into())
        );
    }

    #[test]
    fn unsupported_warn_keeps_the_block_opaque_and_forgets_the_position() {
        let src = SourceFile::new("t.nc", "N10 G00 X1. Z1.\nN20 G84 X2. Z-5.\nN30 G91 X1.\n");
        let options = Options {
            unsupported: Unsupported::Warn,
            profile_name: None,
        };
        let (program, diags) = parse(&src, &CzechProfile::default(), &options);
        assert_eq!(diags[0].severity, diag::Severity::Warning);
        // Kept without its block number (the writer gives one), with the modes it was
        // written under.
        assert!(
            matches!(&program.items[1].kind, ItemKind::Opaque { block: Some(c), text, .. } if text == "G84 X2. Z-5." && !c.incremental)
        );
        // The incremental move after it has no known position to add to.
        assert_eq!(diags[1].code, codes::CZR_UNKNOWN_POSITION);
        // A kept block may not change what later blocks depend on (here the F register).
        let src = SourceFile::new("t.nc", "N10 G00 X1. Z1.\nN20 G84 X2. Z-5. F1.\n");
        let (_, diags) = parse(&src, &CzechProfile::default(), &options);
        let e = diags.iter().find(|d| d.is_error()).unwrap();
        assert_eq!(e.code, codes::CZR_UNSUPPORTED);
        assert!(
            e.message.contains("`F1.` in a block kept opaque"),
            "{}",
            e.message
        );
    }
}

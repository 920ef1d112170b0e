//! The czech front end: blocks → IR items, with the dialect's rules as diagnostics.

use std::collections::HashMap;
use std::ops::Range;

use super::syntax::{self, Block, Value, Word};
use crate::diag::{Code, Diagnostic, codes};
use crate::dialect::read::{Keep, Reader, UnsupportedWording};
use crate::dialect::{Letters, Unsupported, WORD_REPORTS, budget};
use crate::fixed::{Angle, Decimal, Lead, Length, NumberError};
use crate::ir::{
    Chamfer, Coolant, EndCode, FeedMode, ItemKind, ModalContext, Pos, Program, SpindleDirection,
    SpindleMode, SyncStart, ThreadPass,
};
use crate::lower;
use crate::profile::{AngleSource, CzechArcs, CzechDwell, InitialMotion, Profile};
use crate::source::{Line, SourceFile, Span};

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
}

/// The largest lead `F` may give directly. **\[seed\]** 99.99 mm.
const MAX_DIRECT_LEAD: Length = Length(999_900);
/// The largest runout/entry angle. **\[seed\]** 60°.
const MAX_ANGLE: Angle = Angle(60_000);

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
    profile: &'a Profile,
    options: &'a Options,
    motion: Motion,
    incremental: bool,
    f: Option<FRegister>,
    params: HashMap<u32, Decimal>,
    after_runout: AfterRunout,
}

/// Reads a czech program. The program holds every item that could be read; the program is
/// usable only when no diagnostic is an error.
pub fn parse(src: &SourceFile, profile: &Profile, options: &Options) -> (Program, Vec<Diagnostic>) {
    read(src, profile, options, Keep::Program)
}

/// [`parse`], keeping the program or only the diagnostics.
pub(crate) fn read(
    src: &SourceFile,
    profile: &Profile,
    options: &Options,
    keep: Keep,
) -> (Program, Vec<Diagnostic>) {
    let mut fe = FrontEnd {
        r: Reader::new(src, super::ID, keep),
        profile,
        options,
        motion: match profile.czech.initial_motion {
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
    for line in src.lines() {
        // Nothing looks back past the line being read.
        fe.r.items.line_read();
        if line.text.trim().is_empty() {
            continue;
        }
        match syntax::parse_line(line.text) {
            Ok(block) if ended && !block.is_empty() && !block.delimiter => fe.r.after_end(
                codes::CZR_AFTER_END,
                src.line_span(line),
                "this block comes after the program's end (M02/M30); the control does not run it, and neither does ncthread",
                "remove it, or move the program's end after it",
            ),
            Ok(block) => {
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

/// The words of one block, sorted by meaning.
#[derive(Default)]
struct Words<'b> {
    motion: Option<(Motion, &'b Word)>,
    distance: Option<(bool, &'b Word)>,
    feed_mode: Option<(FeedMode, &'b Word)>,
    spindle: Option<(Option<SpindleDirection>, &'b Word)>,
    end: Option<(EndCode, &'b Word)>,
    gears: Vec<(u32, &'b Word)>,
    coolant: Vec<(Coolant, &'b Word)>,
    /// G04 and the word that gives its time (the profile's `dwell` form).
    dwell: Option<(&'b Word, Option<&'b Word>)>,
    /// G96 (true) or G97 (the profile's `surface_speed`).
    speed_mode: Option<(bool, &'b Word)>,
    by_letter: Letters<&'b Word>,
    unsupported: Vec<(&'b Word, String)>,
}

impl<'b> Words<'b> {
    fn get(&self, letter: char) -> Option<&'b Word> {
        self.by_letter.get(&letter).copied()
    }
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
        } else if let Some(words) = self.classify(line, block) {
            if words.unsupported.is_empty() {
                self.meaning(line, block, &words, code_span);
            } else {
                self.unsupported(line, block, &words, code_span);
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

    /// Sorts the words by meaning; reports repeated and conflicting words.
    fn classify<'b>(&mut self, line: Line<'_>, block: &'b Block) -> Option<Words<'b>> {
        let mut words = Words::default();
        let mut ok = true;
        // Problems reported for this block: a hostile line of thousands of repeated words
        // gets a few diagnostics and a count, not one per word.
        let mut conflicts = 0;
        for word in &block.words {
            let whole = |w: &Word| match w.value {
                Value::Number(d) => d.to_whole().ok().filter(|v| *v >= 0),
                Value::Param(_) => None,
            };
            match word.letter {
                'G' => {
                    let Some(g) = whole(word) else {
                        words
                            .unsupported
                            .push((word, "a G code that is not a whole number".into()));
                        continue;
                    };
                    let conflict = match g {
                        0 | 1 | 33 => {
                            let m = match g {
                                0 => Motion::Rapid,
                                1 => Motion::Feed,
                                _ => Motion::Thread,
                            };
                            words.motion.replace((m, word)).map(|(_, w)| w)
                        }
                        90 | 91 => words.distance.replace((g == 91, word)).map(|(_, w)| w),
                        94 | 95 => {
                            let mode = if g == 95 {
                                FeedMode::PerRev
                            } else {
                                FeedMode::PerMin
                            };
                            words.feed_mode.replace((mode, word)).map(|(_, w)| w)
                        }
                        4 if self.profile.czech.dwell != CzechDwell::None => {
                            words.dwell.replace((word, None)).map(|(w, _)| w)
                        }
                        4 => {
                            words.unsupported.push((
                                word,
                                "G04 (a dwell, whose form the czech seed does not document: if the machine's manual gives it, set `dwell` in the profile's [czech] section)".into(),
                            ));
                            None
                        }
                        96 | 97 if self.profile.czech.surface_speed => {
                            words.speed_mode.replace((g == 96, word)).map(|(_, w)| w)
                        }
                        96 | 97 => {
                            words.unsupported.push((
                                word,
                                format!("G{g} (surface speed, whose form the czech seed does not document: if the machine's manual gives G96/G97, set `surface_speed = \"g96-g97\"` in the profile's [czech] section)"),
                            ));
                            None
                        }
                        84 => {
                            words.unsupported.push((
                                word,
                                "the G84 thread cycle (its parameters are not in the manual)"
                                    .into(),
                            ));
                            None
                        }
                        2 | 3 if self.profile.czech.arcs != CzechArcs::None => words
                            .motion
                            .replace((Motion::Arc(g == 2), word))
                            .map(|(_, w)| w),
                        2 | 3 => {
                            words.unsupported.push((
                                word,
                                format!("G0{g} arcs (their form is not in the seed: if the machine's manual gives it, set `arcs` in the profile's [czech] section)"),
                            ));
                            None
                        }
                        _ => {
                            let known = [
                                "G00", "G01", "G02", "G03", "G33", "G90", "G91", "G94", "G95",
                            ];
                            let text = format!("G{g:02}");
                            let hint = crate::dialect::read::did_you_mean(&text, &known);
                            words.unsupported.push((word, format!("G{g}{hint}")));
                            None
                        }
                    };
                    if let Some(previous) = conflict
                        && budget(&mut conflicts)
                    {
                        ok = false;
                        let range = word.range.clone();
                        let prev = &line.text[previous.range.clone()];
                        self.report(self.error(codes::CZR_CONFLICT, line, range, format!("this G code conflicts with `{prev}` in the same block"))
                            .label("same group as an earlier G code")
                            .help("write one G code of each group (motion, G90/G91, G94/G95, G96/G97, G04) per block"));
                    }
                }
                'M' => {
                    let Some(m) = whole(word) else {
                        words
                            .unsupported
                            .push((word, "an M code that is not a whole number".into()));
                        continue;
                    };
                    let conflict = match m {
                        3 => words
                            .spindle
                            .replace((Some(SpindleDirection::Clockwise), word)),
                        4 => words
                            .spindle
                            .replace((Some(SpindleDirection::CounterClockwise), word)),
                        5 => words.spindle.replace((None, word)),
                        2 => words
                            .end
                            .replace((EndCode::M2, word))
                            .map(|(_, w)| (None, w)),
                        30 => words
                            .end
                            .replace((EndCode::M30, word))
                            .map(|(_, w)| (None, w)),
                        8 | 9 if self.profile.czech.coolant => {
                            let c = if m == 8 { Coolant::Flood } else { Coolant::Off };
                            words.coolant.push((c, word));
                            None
                        }
                        7 if self.profile.czech.mist => {
                            words.coolant.push((Coolant::Mist, word));
                            None
                        }
                        7..=9 => {
                            let key = if m == 7 {
                                "mist = \"m07\""
                            } else {
                                "coolant = \"m08-m09\""
                            };
                            words.unsupported.push((
                                word,
                                format!("M{m:02} (coolant, whose form the czech seed does not document: if the machine's manual gives it, set `{key}` in the profile's [czech] section)"),
                            ));
                            None
                        }
                        _ if self.profile.czech.gear_range_mcodes.contains(&(m as u32)) => {
                            words.gears.push((m as u32, word));
                            None
                        }
                        _ => {
                            words.unsupported.push((word, format!("M{m:02}")));
                            None
                        }
                    };
                    if let Some((_, previous)) = conflict
                        && budget(&mut conflicts)
                    {
                        ok = false;
                        let prev = &line.text[previous.range.clone()];
                        self.report(self.error(codes::CZR_CONFLICT, line, word.range.clone(), format!("this M code conflicts with `{prev}` in the same block"))
                            .help("write one spindle M code (M03, M04, M05) and one end code per block"));
                    }
                }
                // K and R are arc words where the profile declares arcs.
                'X' | 'Z' | 'F' | 'S' | 'T' | 'D' | 'I' | 'J' | 'E' | 'K' | 'R' | 'P'
                    if match word.letter {
                        'K' | 'R' => self.profile.czech.arcs != CzechArcs::None,
                        'P' => self.profile.czech.dwell == CzechDwell::PMilliseconds,
                        _ => true,
                    } =>
                {
                    if let Some(previous) = words.by_letter.insert(word.letter, word)
                        && budget(&mut conflicts)
                    {
                        ok = false;
                        let prev = &line.text[previous.range.clone()];
                        self.report(
                            self.error(
                                codes::CZR_CONFLICT,
                                line,
                                word.range.clone(),
                                format!("address {} is written twice in this block", word.letter),
                            )
                            .label(format!("`{prev}` came earlier"))
                            .help("write each address once per block"),
                        );
                    }
                    if matches!(word.value, Value::Param(_)) && word.letter != 'F' {
                        words.unsupported.push((
                            word,
                            format!(
                                "a parameter as the value of {} (only FRnn is documented)",
                                word.letter
                            ),
                        ));
                    }
                }
                'N' if budget(&mut conflicts) => {
                    ok = false;
                    self.report(
                        self.error(
                            codes::CZR_CONFLICT,
                            line,
                            word.range.clone(),
                            "a block number must come first in the block",
                        )
                        .help("write `N<number>` at the start of the block, once"),
                    );
                }
                'Y' => words
                    .unsupported
                    .push((word, "the Y axis (ncthread models ZX lathes)".into())),
                'R' => words.unsupported.push((
                    word,
                    "an R word without `=` (R-parameter arithmetic is not documented)".into(),
                )),
                'N' => {}
                c => words.unsupported.push((word, format!("address {c}"))),
            }
        }
        if conflicts > WORD_REPORTS {
            ok = false;
            let more = conflicts - WORD_REPORTS;
            self.report(
                self.error(
                    codes::CZR_CONFLICT,
                    line,
                    block.code_range.clone(),
                    format!("{more} more repeated or conflicting words in this block"),
                )
                .help("write each address once per block, and one G code of each group"),
            );
        }
        // In a G04 block the profile's time word is the dwell's time, not an axis or a feed;
        // the block moves nothing. P means something only there.
        if let Some((g04, _)) = words.dwell {
            let letter = self.profile.czech.dwell.letter().unwrap_or('P');
            let time = words.by_letter.remove(&letter);
            words.dwell = Some((g04, time));
            for w in [words.motion.map(|(_, w)| w), words.get('X'), words.get('Z')]
                .into_iter()
                .flatten()
            {
                ok = false;
                let g = &line.text[g04.range.clone()];
                self.report(
                    self.error(
                        codes::CZR_DWELL,
                        line,
                        w.range.clone(),
                        format!("`{g}` dwells: a block with a dwell moves nothing"),
                    )
                    .help("write the dwell in a block of its own, before or after the move"),
                );
            }
        } else if let Some(p) = words.by_letter.remove(&'P') {
            words
                .unsupported
                .push((p, "P outside a G04 block".to_string()));
        }
        // I, J and E mean something only in a G33 block; I, K and R in an arc block as the
        // profile's arc form says.
        let motion = words.motion.map_or(self.motion, |(m, _)| m);
        let arc_words: &[char] = match (motion, self.profile.czech.arcs) {
            (Motion::Arc(_), CzechArcs::IkRadius | CzechArcs::IkDiameter) => &['I', 'K'],
            (Motion::Arc(_), CzechArcs::Radius) => &['R'],
            _ => &[],
        };
        for letter in ['I', 'J', 'E', 'K', 'R'] {
            if (motion == Motion::Thread && matches!(letter, 'I' | 'J' | 'E'))
                || arc_words.contains(&letter)
            {
                continue;
            }
            if let Some(w) = words.get(letter) {
                let what = match letter {
                    'K' | 'R' if matches!(motion, Motion::Arc(_)) => format!(
                        "{letter} in an arc block of a machine whose arcs take {}",
                        if arc_words == ['R'] { "R" } else { "I and K" }
                    ),
                    'K' => "address K".to_string(),
                    'R' => "an R word without `=` (R-parameter arithmetic is not documented)"
                        .to_string(),
                    _ if matches!(motion, Motion::Arc(_)) => format!(
                        "{letter} in an arc block of a machine whose arcs take {}",
                        if arc_words == ['R'] { "R" } else { "I and K" }
                    ),
                    _ => format!(
                        "{letter} outside a G33 block (arc and cycle words are not documented)"
                    ),
                };
                words.unsupported.push((w, what));
            }
        }
        ok.then_some(words)
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

    fn meaning(&mut self, line: Line<'_>, block: &Block, words: &Words<'_>, code_span: Span) {
        let number = block.number;
        let word_span = |fe: &Self, w: &Word| fe.span(line, w.range.clone());
        if let Some((incremental, _)) = words.distance {
            self.incremental = incremental;
        }
        if let Some((motion, _)) = words.motion {
            self.motion = motion;
        }
        if let Some((mode, w)) = words.feed_mode {
            let span = word_span(self, w);
            self.push(ItemKind::FeedMode(mode), span, number);
        }
        for a in &block.assignments {
            let span = self.span(line, a.range.clone());
            self.push(
                ItemKind::ParamAssign {
                    number: a.param,
                    value: a.value,
                },
                span,
                number,
            );
        }
        let tool = words.get('T').and_then(|w| self.whole(line, w));
        let offset = words.get('D').and_then(|w| self.whole(line, w));
        if tool.is_some() || offset.is_some() {
            let w = words
                .get('T')
                .or(words.get('D'))
                .expect("T or D is present");
            let span = word_span(self, w);
            self.push(
                ItemKind::Tool {
                    number: tool,
                    offset,
                },
                span,
                number,
            );
        }
        for (gear, w) in &words.gears {
            let span = word_span(self, w);
            self.push(
                ItemKind::GearRange {
                    code: *gear,
                    machine: super::ID,
                },
                span,
                number,
            );
        }
        for (text, range) in &block.opaque {
            let span = self.span(line, range.clone());
            self.push(
                ItemKind::Opaque {
                    dialect: super::ID,
                    text: text.clone(),
                    block: None,
                },
                span,
                number,
            );
        }
        // The speed mode first: the block's S is then in its unit.
        if let Some((g96, w)) = words.speed_mode {
            let span = word_span(self, w);
            let mode = if g96 {
                SpindleMode::SurfaceSpeed {
                    limit: None,
                    feet: false,
                }
            } else {
                SpindleMode::Rpm
            };
            self.push(ItemKind::SpindleMode(mode), span, number);
        }
        let speed = words.get('S').and_then(|w| self.whole(line, w));
        let direction = words.spindle.and_then(|(d, _)| d);
        if speed.is_some() || direction.is_some() {
            let w = words
                .get('S')
                .or(words.spindle.map(|(_, w)| w))
                .expect("S or M03/M04 is present");
            let span = word_span(self, w);
            self.push(ItemKind::Spindle { speed, direction }, span, number);
        }
        // Coolant on before the block's motion, off after it, as the spindle. **[decided]**
        for &(c, w) in words.coolant.iter().filter(|(c, _)| *c != Coolant::Off) {
            let span = word_span(self, w);
            self.push(ItemKind::Coolant(c), span, number);
        }
        match words.dwell {
            Some((g04, time)) => self.dwell(line, g04, time, number),
            None => self.motion_item(line, words, code_span, number),
        }
        for &(c, w) in words.coolant.iter().filter(|(c, _)| *c == Coolant::Off) {
            let span = word_span(self, w);
            self.push(ItemKind::Coolant(c), span, number);
        }
        if let Some((None, w)) = words.spindle {
            let span = word_span(self, w);
            self.push(ItemKind::SpindleStop, span, number);
        }
        if let Some((end, w)) = words.end {
            let span = word_span(self, w);
            self.push(ItemKind::ProgramEnd(end), span, number);
        }
    }

    /// A G04 block: its time in the profile's form.
    fn dwell(&mut self, line: Line<'_>, g04: &Word, time: Option<&Word>, number: Option<u32>) {
        let form = self.profile.czech.dwell;
        let letter = form.letter().unwrap_or('P');
        let Some(time) = time else {
            let g = &line.text[g04.range.clone()];
            self.report(
                self.error(
                    codes::CZR_DWELL,
                    line,
                    g04.range.clone(),
                    format!("`{g}` without its time ({letter})"),
                )
                .help(match form {
                    CzechDwell::PMilliseconds => "write the time in milliseconds: `G04 P500`",
                    CzechDwell::FSeconds => "write the time in seconds: `G04 F0.5`",
                    _ => "write the time in seconds: `G04 X0.5`",
                }),
            );
            return;
        };
        let seconds = match (time.value, form) {
            (Value::Number(d), CzechDwell::PMilliseconds) => match d.to_whole() {
                Ok(ms) if ms >= 0 => Some(Decimal {
                    mantissa: ms as i128,
                    scale: 3,
                    has_point: true,
                }),
                _ => None,
            },
            (Value::Number(d), _) if !d.is_negative() && d.scale <= 4 => Some(d),
            _ => None,
        };
        let Some(seconds) = seconds else {
            self.report(
                self.error(
                    codes::CZR_DWELL,
                    line,
                    time.range.clone(),
                    "the dwell time must be a number of 0 or more",
                )
                .label(if form == CzechDwell::PMilliseconds {
                    "whole milliseconds"
                } else {
                    "seconds, to 0.0001 s"
                })
                .help("write the time as a plain number, e.g. `G04 P500` (ms) or `G04 X0.5` (s), as the profile's form says"),
            );
            return;
        };
        let span = self.span(line, g04.range.start..time.range.end.max(g04.range.end));
        self.push(ItemKind::Dwell { seconds }, span, number);
    }

    /// The F word's value: a number, or the value of the parameter in `FRnn`.
    fn f_value(&mut self, line: Line<'_>, word: &Word) -> Option<Length> {
        let d = match word.value {
            Value::Number(d) => d,
            Value::Param(p) => match self.params.get(&p) {
                Some(d) => *d,
                None => {
                    self.report(
                        self.error(
                            codes::CZR_PARAM_UNSET,
                            line,
                            word.range.clone(),
                            format!("R{p:02} is used before it is assigned"),
                        )
                        .label("no earlier block assigns it")
                        .help(format!(
                            "assign it in an earlier block, e.g. `R{p:02}=250.0`"
                        )),
                    );
                    return None;
                }
            },
        };
        self.length(line, word, d)
    }

    fn motion_item(
        &mut self,
        line: Line<'_>,
        words: &Words<'_>,
        code_span: Span,
        number: Option<u32>,
    ) {
        let f_word = words.get('F');
        let f = match f_word {
            Some(w) => match self.f_value(line, w) {
                Some(v) => Some((v, w)),
                None => return,
            },
            None => None,
        };
        let thread = self.motion == Motion::Thread;
        if let Some((value, _)) = f {
            self.f = Some(FRegister {
                value,
                is_lead: thread,
            });
        }
        let (x_word, z_word) = (words.get('X'), words.get('Z'));
        let has_thread_words = ['I', 'J', 'E'].iter().any(|&c| words.get(c).is_some());
        // A feed that no move of the block uses stays where it is written.
        let unused_feed = match f {
            Some((value, w)) if !thread => {
                let moves = x_word.is_some() || z_word.is_some();
                (!moves || self.motion == Motion::Rapid)
                    .then(|| (value, self.span(line, w.range.clone())))
            }
            _ => None,
        };
        if let Some((value, span)) = unused_feed {
            self.push(ItemKind::FeedRate(value), span, number);
        }
        if x_word.is_none() && z_word.is_none() {
            let arc_words = ['I', 'K', 'R'].iter().any(|&c| words.get(c).is_some());
            if let (Motion::Arc(g02), true) = (self.motion, arc_words) {
                let code = if g02 { "G02" } else { "G03" };
                self.arc_error(
                    line,
                    code_span_range(line, code_span),
                    format!("a {code} block with a centre or radius but no end point"),
                    "program the arc's end with X and Z (a full circle is two arcs)",
                );
            }
            if thread && has_thread_words {
                self.report(
                    self.error(
                        codes::CZR_THREAD_GEOMETRY,
                        line,
                        code_span_range(line, code_span),
                        "a G33 block with I, J or E but no end point",
                    )
                    .help("program the end of the thread with Z (and X for a taper)"),
                );
            }
            return;
        }
        let start = self.r.pos;
        let Some(x) = self.axis(line, x_word, start.x) else {
            return;
        };
        let Some(z) = self.axis(line, z_word, start.z) else {
            return;
        };
        let to = Pos { x, z };
        let kind = match self.motion {
            Motion::Rapid => ItemKind::Rapid { to },
            Motion::Feed => match self.feed_rate(line, code_span, "G01") {
                Some(feed) => ItemKind::Feed { to, feed },
                None => return,
            },
            Motion::Arc(g02) => {
                let code = if g02 { "G02" } else { "G03" };
                let Some(feed) = self.feed_rate(line, code_span, code) else {
                    return;
                };
                match self.arc(line, words, start, to, g02, code_span) {
                    Some((to, centre, clockwise)) => ItemKind::Arc {
                        to,
                        centre: Box::new(centre),
                        clockwise,
                        feed,
                    },
                    None => return,
                }
            }
            Motion::Thread => match self.thread_pass(line, words, f, start, to, code_span) {
                Some(pass) => ItemKind::pass(pass),
                None => return,
            },
        };
        self.r.pos = kind.end_position(self.r.pos);
        self.push(kind, code_span, number);
    }

    /// The feed a feed move (`code`: G01, G02, G03) uses, or `None` after reporting why
    /// there is none.
    fn feed_rate(&mut self, line: Line<'_>, code_span: Span, code: &str) -> Option<Length> {
        match self.f {
            Some(FRegister {
                value,
                is_lead: false,
            }) if value <= Length::ZERO => {
                self.report(
                    self.error(
                        codes::CZR_NO_FEED,
                        line,
                        code_span_range(line, code_span),
                        format!(
                            "{code} move at feed F{}: the axis would not move",
                            value.mm()
                        ),
                    )
                    .help("program a feed greater than 0 with F"),
                );
                None
            }
            Some(FRegister {
                value,
                is_lead: false,
            }) => Some(value),
            other => {
                let message = if other.is_some() {
                    format!("{code} move whose F was last programmed as a thread lead")
                } else {
                    format!("{code} move without a feed")
                };
                self.report(
                    self.error(
                        codes::CZR_NO_FEED,
                        line,
                        code_span_range(line, code_span),
                        message,
                    )
                    .help("program the feed with F in this block or an earlier G01 block"),
                );
                None
            }
        }
    }

    fn arc_error(&mut self, line: Line<'_>, range: Range<usize>, message: String, help: &str) {
        self.report(self.error(codes::CZR_ARC, line, range, message).help(help));
    }

    /// An arc block in the profile's form: its end (both axes), its centre and whether it
    /// turns clockwise as LinuxCNC's G2 does (G02, or G03 on a mirrored machine). The
    /// geometry is `lower::arc`'s, as for ISO; the end must lie on the circle within
    /// 0.002 mm, two steps of the control's 0.001 mm. **\[decided\]**
    fn arc(
        &mut self,
        line: Line<'_>,
        words: &Words<'_>,
        start: Pos,
        to: Pos,
        g02: bool,
        code_span: Span,
    ) -> Option<(Pos, Pos, bool)> {
        let code = if g02 { "G02" } else { "G03" };
        let whole = code_span_range(line, code_span);
        let Some((sx, sz)) = start.known() else {
            self.report(
                self.error(
                    codes::CZR_UNKNOWN_POSITION,
                    line,
                    whole,
                    format!("{code} from a position that is not known yet: the arc's centre cannot be placed"),
                )
                .help("move to an absolute X and Z before the arc"),
            );
            return None;
        };
        let (ex, ez) = (to.x.unwrap_or(sx), to.z.unwrap_or(sz));
        let clockwise = g02 != self.profile.czech.arcs_mirrored;
        let value = |fe: &mut Self, w: Option<&Word>| match w.map(|w| (w, w.value)) {
            Some((w, Value::Number(d))) => fe.length(line, w, d).map(Some),
            Some(_) => None,
            None => Some(None),
        };
        let centre = if self.profile.czech.arcs == CzechArcs::Radius {
            let Some(r) = words.get('R') else {
                self.arc_error(
                    line,
                    whole,
                    format!("{code} without R (this machine's arcs take their radius in R)"),
                    "write the radius: `G02 X… Z… R5.`; a negative R turns more than half a circle",
                );
                return None;
            };
            let Value::Number(radius) = r.value else {
                return None;
            };
            if (sx, sz) == (ex, ez) {
                self.arc_error(
                    line,
                    r.range.clone(),
                    format!("{code} R ends where it starts: a full circle has no R form"),
                    "write the circle as two arcs",
                );
                return None;
            }
            match lower::arc::centre_from_radius(
                (sx, sz),
                (ex, ez),
                radius.to_f64(),
                clockwise,
                0.001,
            ) {
                Ok(c) => c,
                Err(chord) => {
                    let text = &line.text[r.range.clone()];
                    self.arc_error(line, r.range.clone(), format!("`{text}` is too small for the arc: its end is {chord} mm from its start"), "the radius must be at least half the distance from the start to the end");
                    return None;
                }
            }
        } else {
            let (i, k) = (words.get('I'), words.get('K'));
            if i.is_none() && k.is_none() {
                self.arc_error(line, whole, format!("{code} without I or K (this machine's arcs take their centre's offset from the start in I and K)"), "write the centre: I for X, K for Z, from the arc's start");
                return None;
            }
            let iv = value(self, i)?.unwrap_or(Length::ZERO);
            let kv = value(self, k)?.unwrap_or(Length::ZERO);
            let dx = if self.profile.czech.arcs == CzechArcs::IkRadius {
                iv + iv
            } else {
                iv
            };
            Pos::new(sx + dx, sz + kv)
        };
        let (cx, cz) = centre.known()?;
        let (r1, r2) = lower::arc::radii((sx, sz), (ex, ez), (cx, cz));
        if r1 < 0.001 || r2 < 0.001 {
            self.arc_error(
                line,
                whole,
                format!("{code} with a zero radius: its centre is on its start or its end"),
                "check I and K: the centre's offset from the arc's start",
            );
            return None;
        }
        if (r1 - r2).abs() > 0.002 {
            self.arc_error(
                line,
                whole,
                format!(
                    "{code}'s end is not on its circle: the radius is {} mm at the start and {} mm at the end",
                    Length::from_mm_f64(r1).mm(),
                    Length::from_mm_f64(r2).mm()
                ),
                "check I and K (and whether the profile's `arcs` reads I as a radius or a diameter)",
            );
            return None;
        }
        Some((Pos::new(ex, ez), centre, clockwise))
    }

    fn thread_pass(
        &mut self,
        line: Line<'_>,
        words: &Words<'_>,
        f: Option<(Length, &Word)>,
        start: Pos,
        to: Pos,
        code_span: Span,
    ) -> Option<ThreadPass> {
        let block_range = code_span_range(line, code_span);
        let lead = match (f, self.f) {
            (Some((lead, word)), _) => {
                if matches!(word.value, Value::Number(_)) && lead > MAX_DIRECT_LEAD {
                    let text = line.text[word.range.clone()].to_string();
                    self.report(self.error(codes::CZR_LEAD_TOO_LARGE, line, word.range.clone(), format!("lead `{text}` is over 99.99 mm, the most F can give directly"))
                        .label("over 99.99")
                        .help(format!("assign the lead to a parameter in an earlier block and use it: `R10={}` … `FR10`", lead.mm_with_point())));
                    return None;
                }
                if lead <= Length::ZERO {
                    self.report(
                        self.error(
                            codes::CZR_NO_LEAD,
                            line,
                            word.range.clone(),
                            "the lead must be positive",
                        )
                        .help("F in a G33 block is the lead in mm per spindle revolution"),
                    );
                    return None;
                }
                lead
            }
            (
                None,
                Some(FRegister {
                    value,
                    is_lead: true,
                }),
            ) => value,
            (None, other) => {
                let message = if other.is_some() {
                    "G33 block without F, and the last F was a feed, not a lead"
                } else {
                    "G33 block without a lead"
                };
                self.report(
                    self.error(codes::CZR_NO_LEAD, line, block_range, message)
                        .help("write the lead in the G33 block: F<mm per revolution> or FR<nn>"),
                );
                return None;
            }
        };
        let start_angle = match words.get('I') {
            Some(w) => {
                let Value::Number(d) = w.value else {
                    return None;
                };
                let angle = match d.to_angle() {
                    Ok(a) => a,
                    Err(e) => {
                        self.number_error(line, w.range.clone(), e, "0.001°");
                        return None;
                    }
                };
                if !(Angle::ZERO..Angle::from_deg(360)).contains(&angle) {
                    self.report(self.error(codes::CZR_START_ANGLE_RANGE, line, w.range.clone(), "the start angle must be at least 0° and less than 360°")
                        .help("I is the spindle angle after the index pulse at which the thread starts"));
                    return None;
                }
                angle
            }
            None => Angle::ZERO,
        };
        let (j, e) = (words.get('J'), words.get('E'));
        let end = Pos {
            x: to.x.or(start.x),
            z: to.z.or(start.z),
        };
        let changes_x = to.x.is_some() && to.x != start.x;
        if (changes_x || j.is_some() || e.is_some()) && start.known().is_none() {
            let why = if changes_x {
                "a taper thread"
            } else {
                "a thread with runout or entry"
            };
            self.report(
                self.error(
                    codes::CZR_UNKNOWN_POSITION,
                    line,
                    block_range.clone(),
                    format!("{why} needs its start point, which is not known here"),
                )
                .label("start point unknown")
                .help("move to the start of the thread with X and Z before this block"),
            );
            return None;
        }
        let travel = match (start.z, end.z) {
            (Some(a), Some(b)) => Some((b - a).abs()),
            _ => None,
        };
        if travel == Some(Length::ZERO) {
            self.report(
                self.error(
                    codes::CZR_THREAD_GEOMETRY,
                    line,
                    block_range,
                    "this G33 block has no Z travel",
                )
                .help("ncthread measures the lead along Z; face threads are not supported"),
            );
            return None;
        }
        let mut entry = None;
        let mut exit = None;
        if let Some(w) = e {
            if let Value::Number(d) = w.value
                && !d.has_point
            {
                let text = line.text[w.range.clone()].to_string();
                self.report(self.error(codes::CZR_ENTRY_WITHOUT_POINT, line, w.range.clone(), format!("entry length `{text}` is written without a decimal point"))
                    .label("E needs a decimal point")
                    .help(format!("write `{text}.`: the manual requires E with a decimal point (E10. or E10.0)")));
                return None;
            }
            entry = Some(self.chamfer(line, w, AngleUse::Entry)?);
        }
        if let Some(w) = j {
            exit = Some(self.chamfer(line, w, AngleUse::Runout)?);
        }
        let used =
            entry.map_or(Length::ZERO, |c| c.length) + exit.map_or(Length::ZERO, |c| c.length);
        if let Some(travel) = travel
            && used > travel
        {
            self.report(self.error(codes::CZR_THREAD_GEOMETRY, line, block_range, format!("entry and runout ({} mm) are longer than the thread's Z travel ({} mm)", used, travel))
                .help("the programmed end point includes the runout: J and E must fit inside the travel"));
            return None;
        }
        if entry.is_some() || exit.is_some() {
            self.after_runout = AfterRunout::EmptyBlock { thread: code_span };
        }
        // The thread line is the programmed line shifted by −(entry offset). **[decided]**
        // A block without X keeps the diameter: the pass says so too (X stays unwritten).
        let line_end_x = match entry {
            Some(c) => end.x.map(|x| x - c.offset),
            None => to.x,
        };
        Some(ThreadPass {
            to: Pos {
                x: line_end_x,
                z: end.z,
            },
            lead: Lead::from_length(lead),
            // Every G33 block waits for the index pulse. **[seed]**
            start: SyncStart::Index(start_angle),
            infeed: None,
            entry,
            exit,
        })
    }

    /// J or E: its length, and its offset from the angle that machine constant 8 selects.
    fn chamfer(&mut self, line: Line<'_>, word: &Word, usage: AngleUse) -> Option<Chamfer> {
        let Value::Number(d) = word.value else {
            return None;
        };
        let length = self.length(line, word, d)?;
        let letter = word.letter;
        if length <= Length::ZERO {
            self.report(self.error(codes::CZR_NEGATIVE_LENGTH, line, word.range.clone(), format!("{letter} must be a positive length"))
                .help(format!("{letter} is a length along the thread axis, always positive whatever the direction of travel")));
            return None;
        }
        let profile_name = self
            .profile
            .name
            .clone()
            .unwrap_or_else(|| "the built-in profile".into());
        let Some(c8) = self.profile.czech.constant8 else {
            self.report(self.error(codes::CZR_NO_CONSTANT8, line, word.range.clone(), format!("{} needs the {} angle from machine constant 8, which the profile does not give", letter, usage.name()))
                .label("angle unknown")
                .help("give the machine's TAB0.REK constant 8 in a profile (`--profile FILE`): [czech] constant8 = \"04000000\""));
            return None;
        };
        let (angle_word, source) = match c8.angle_source() {
            AngleSource::Direct { word } => {
                (word, format!("machine constant 8 ({c8}, {profile_name})"))
            }
            AngleSource::Parameters { runout, entry } => {
                let param = match usage {
                    AngleUse::Runout => runout,
                    AngleUse::Entry => entry.unwrap_or(runout),
                };
                if param == 0 || param == 80 {
                    self.report(self.error(codes::CZR_FORBIDDEN_PARAM, line, word.range.clone(), format!("machine constant 8 ({c8}, {profile_name}) names R{param:02} for the {} angle; R00 and R80 may not hold angles", usage.name()))
                        .help("choose another parameter in constant 8 (the manual recommends R04)"));
                    return None;
                }
                let Some(value) = self.params.get(&param).copied() else {
                    self.report(self.error(codes::CZR_ANGLE_PARAM_UNSET, line, word.range.clone(), format!("the {} angle parameter R{param:02} is not assigned before this block", usage.name()))
                        .label(format!("needs R{param:02}"))
                        .help(format!("assign it in an earlier block: `R{param:02}=120.0` is axis X, +20° (machine constant 8 = {c8})")));
                    return None;
                };
                match value.to_scaled(Angle::DECIMALS) {
                    Ok(w) => (w, format!("R{param:02}")),
                    Err(e) => {
                        self.number_error(line, word.range.clone(), e, "0.001°");
                        return None;
                    }
                }
            }
        };
        // sign · (axis·100 + angle) in 0.001°. **[seed]**
        let magnitude = angle_word.abs();
        let axis = magnitude / 100_000;
        let angle = Angle(magnitude % 100_000);
        if !(1..=3).contains(&axis) {
            self.report(self.error(codes::CZR_BAD_AXIS, line, word.range.clone(), format!("the {} angle in {source} names axis {axis}; the axis decade must be 1 (X), 2 (Y) or 3 (Z)", usage.name()))
                .help("write the axis in the hundreds: `R04=120.0` is axis X, 20°"));
            return None;
        }
        if axis != 1 {
            self.report(self.error(codes::CZR_RUNOUT_AXIS, line, word.range.clone(), format!("the {} angle in {source} moves axis {}; only X runout is supported on a ZX lathe", usage.name(), if axis == 2 { "Y" } else { "Z" }))
                .help("use axis 1 (X): `R04=120.0`"));
            return None;
        }
        if angle > MAX_ANGLE {
            self.report(
                self.error(
                    codes::CZR_ANGLE_TOO_LARGE,
                    line,
                    word.range.clone(),
                    format!(
                        "the {} angle {}° in {source} is over 60°",
                        usage.name(),
                        angle
                    ),
                )
                .help("runout and entry angles are 0 to 60°"),
            );
            return None;
        }
        let offset = Length::from_mm_f64(2.0 * length.to_mm_f64() * angle.tan());
        Some(Chamfer {
            length,
            offset: if angle_word < 0 { -offset } else { offset },
        })
    }
}

#[derive(Clone, Copy)]
enum AngleUse {
    Runout,
    Entry,
}

impl AngleUse {
    fn name(self) -> &'static str {
        match self {
            AngleUse::Runout => "runout",
            AngleUse::Entry => "entry",
        }
    }
}

fn code_span_range(line: Line<'_>, span: Span) -> Range<usize> {
    (span.start - line.offset)..(span.end - line.offset)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::profile::Constant8;

    fn run(text: &str, constant8: Option<&str>) -> (Program, Vec<Diagnostic>) {
        let mut profile = Profile::default();
        profile.czech.constant8 = constant8.map(|c| Constant8::parse(c).unwrap());
        parse(
            &SourceFile::new("t.nc", text),
            &profile,
            &Options::default(),
        )
    }

    /// Dwells and surface speed as the profile declares them, and their refusals.
    #[test]
    fn dwell_and_surface_speed_follow_the_profile_form() {
        let read = |dwell: CzechDwell, css: bool, text: &str| {
            let mut profile = Profile::default();
            profile.czech.dwell = dwell;
            profile.czech.surface_speed = css;
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
            let mut profile = Profile::default();
            profile.czech.arcs = form;
            profile.czech.arcs_mirrored = mirrored;
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
                offset: Length(53_207)
            })
        );
        // Negative sign: towards −X.
        let p = passes(RUNOUT, Some("-00112500"))[0];
        assert_eq!(p.exit.unwrap().offset, Length(-53_207));
        // Parameter mode R04 = -120.000: axis X, 20° towards −X: 2·12·tan 20° = 8.7353.
        let p = passes(&format!("N5 R04= -00120.000\n{RUNOUT}"), Some("04000000"))[0];
        assert_eq!(p.exit.unwrap().offset, Length(-87_353));
        // Entry without its own parameter uses the runout parameter. **[decided]**
        let entry = "N5 R04=118.0\nN10 M04 S50\nN20 X71.798 Z-100.\nN30 Z3 F6.0 E12. G33\nN40\nN50 X64. Z3 G0\n";
        let p = passes(entry, Some("04000000"))[0];
        assert_eq!(p.entry.unwrap().offset, Length(77_981));
    }

    #[test]
    fn seed_entry_check_thread_at_diameter_64() {
        // czech.md: start X71.798, E12., 18° → the thread is cut at Ø64.000.
        let text = "N10 M04 S50\nN20 X71.798 Z-100. R16=118.0\nN30 Z3 F6.0 E12. G33\nN40\nN50 X64. Z3 G0\n";
        let p = passes(text, Some("15160000"))[0];
        let line_x = p.to.x.unwrap();
        assert!(
            (line_x - Length::from_mm(64)).abs() <= Length(1),
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
        };
        let (program, diags) = parse(&src, &Profile::default(), &options);
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
        let (_, diags) = parse(&src, &Profile::default(), &options);
        let e = diags.iter().find(|d| d.is_error()).unwrap();
        assert_eq!(e.code, codes::CZR_UNSUPPORTED);
        assert!(
            e.message.contains("`F1.` in a block kept opaque"),
            "{}",
            e.message
        );
    }
}

//! The block interpreter: a block's words sorted by modal group into [`Words`] (what the
//! block asks), then one short step per group, in one order, as LinuxCNC's
//! `interp_convert.cc` reads a block (`read_…` into `block_struct`, then `execute_block`).
//!
//! The steps, LinuxCNC's order adapted to what a FANUC lathe program holds:
//!
//! | step | group | words |
//! |------|-------|-------|
//! | [`FrontEnd::sort_words`] | (every word) | G, M and the address letters; G76 refused by name |
//! | [`FrontEnd::check_words`] | (the block) | a group or a letter twice, M codes that contradict, X with U, Z with W |
//! | [`FrontEnd::refuse_unsupported`] | (the block) | what ncthread does not read: refused, or the block kept as written |
//! | [`FrontEnd::program_number`] | program number | O |
//! | [`FrontEnd::units`] | units | G20 / G21 (first: they decide what every other number means) |
//! | [`FrontEnd::feed_mode`] | feed mode | G98 / G99 |
//! | [`FrontEnd::feed`] | feed | F (a lead in a G32 / G92 block) |
//! | [`FrontEnd::spindle_mode`] | speed mode | G50 S (the limit), G96 / G97 — [`Switches::spindle_mode`] |
//! | [`FrontEnd::tool`] | tool | T |
//! | [`FrontEnd::speed`] | spindle | S, M03 / M04 — [`Switches::spindle`] |
//! | (coolant) | coolant | M07 / M08 — [`Switches::coolant_on`] |
//! | [`FrontEnd::coordinate_system`] | coordinate system | G54 – G59 |
//! | [`FrontEnd::compensation`] | compensation | G40 / G41 / G42 |
//! | [`FrontEnd::dwell_step`] or [`FrontEnd::motion_step`] | dwell or motion | G04; G00 G01 G02 G03 G32 G92 |
//! | [`FrontEnd::stops`] | stop | M05, M09, M00, M01 |
//! | [`FrontEnd::program_end`] | end | M02 / M30 |
//!
//! G18 (the ZX plane, a lathe's only one), G49 (cancelling a tool length compensation,
//! G43/G44, which ncthread never reads: a safe-start line's `G40 G49 G80`) and G80
//! (cancelling drilling cycles ncthread never reads) are read and do nothing. A step that refuses the block says why and returns
//! `None`: the steps after it do not run.
//!
//! The stop step is not [`Switches::after_motion`]: M05, M09, M00 and M01 act in the
//! block's order (`M05 M09` stops the spindle first), and each M code written acts (`M05
//! M05` stops twice, `M02 M30` ends twice), where `Switches` holds one of each.

use super::{BUILDER, FRegister, FrontEnd, KNOWN_G, Motion, UNSUPPORTED, Unit};
use crate::dialect::Unsupported;
use crate::dialect::fanuc::codes;
use crate::dialect::fanuc::profile::GcodeSystem;
use crate::dialect::fanuc::syntax::{Block, Word};
use crate::dialect::machine::Switches;
use crate::dialect::read::letter_bit;
use crate::fixed::{Decimal, Lead, Length};
use crate::ir::{
    Compensation, Coolant, EndCode, FeedMode, ItemKind, SpindleDirection, SpindleMode,
};
use crate::source::{Line, Span};

/// What one block asks, its words sorted by modal group (LinuxCNC's `block_struct`).
#[derive(Default)]
pub(super) struct Words<'w> {
    /// What ncthread does not read, each with what to say about it, in the block's order.
    unsupported: Vec<(Span, String)>,
    /// The machine builder's M codes among `unsupported`: when they are all the block has
    /// that ncthread does not read, the block is read and they are kept as written, in
    /// every mode.
    builder: Vec<&'w Word>,
    /// The first modal code ncthread does not read (a cycle: the blocks after it repeat it).
    modal_unsupported: Option<&'w Word>,
    /// A code refused by name, its diagnostic said.
    refused_by_name: bool,
    /// A cycle ncthread keeps as written (`front/cycles.rs`).
    pub(super) cycle: Option<(i64, &'w Word)>,
    /// The first word that repeats a letter or a code of its group.
    conflict: Option<&'w Word>,
    /// G00 G01 G02 G03 G32 G92.
    pub(super) motion: Option<(Motion, &'w Word)>,
    /// G04 (one-shot).
    pub(super) dwell: Option<&'w Word>,
    /// G50: the spindle's limit, its S.
    pub(super) limit: Option<&'w Word>,
    /// G20 (true) or G21.
    pub(super) units: Option<(bool, &'w Word)>,
    /// G98 (true: per minute) or G99.
    pub(super) feed_mode: Option<(bool, &'w Word)>,
    /// G96 (true: a surface speed) or G97.
    pub(super) speed_mode: Option<(bool, &'w Word)>,
    /// G40 G41 G42.
    pub(super) comp: Option<(Compensation, &'w Word)>,
    /// G54 – G59, as 1 – 6.
    pub(super) offset: Option<(u8, &'w Word)>,
    /// G90 / G91 of system B or C (true: incremental).
    pub(super) distance: Option<(bool, &'w Word)>,
    /// The M codes read, in the block's order.
    pub(super) m_codes: smallvec::SmallVec<[(i64, &'w Word); 4]>,
    /// X Z U W I K R F S T P Q O, in the block's order.
    /// Held in place for up to eight (a block rarely has more).
    pub(super) letters: smallvec::SmallVec<[&'w Word; 8]>,
    /// [`letter_bit`] of each letter in `letters` (all `A`–`Z`): most questions (is there an
    /// R?) are answered without a look at the list.
    present: u32,
}

impl<'w> Words<'w> {
    /// The word of this letter.
    pub(super) fn get(&self, c: char) -> Option<&'w Word> {
        if self.present & letter_bit(c) == 0 {
            return None;
        }
        self.letters.iter().copied().find(|w| w.letter == c)
    }

    /// The first M code `m`.
    pub(super) fn m(&self, m: i64) -> Option<&'w Word> {
        self.m_codes.iter().find(|(c, _)| *c == m).map(|(_, w)| *w)
    }

    /// Whether the block has X, Z, U or W.
    pub(super) fn moves(&self) -> bool {
        ['X', 'Z', 'U', 'W'].iter().any(|&c| self.get(c).is_some())
    }

    /// The block runs something at the spindle's speed: a move (not a dwell's X or U), a
    /// thread cycle repeated without axes (`G92`), or a cycle kept as written.
    pub(super) fn runs(&self) -> bool {
        (self.dwell.is_none()
            && (self.moves() || self.motion.is_some_and(|(m, _)| m == Motion::Cycle)))
            || (self.cycle.is_some() && !self.gives_no_cycle())
    }

    /// A G90 or G94 (as system A numbers them) written with no word of its cycle and no
    /// address but S and T: its mode set, no cycle given (`G21 G40 G80 G90`).
    /// **\[decided\]**
    pub(super) fn gives_no_cycle(&self) -> bool {
        matches!(self.cycle, Some((90 | 94, _)))
            && self.letters.iter().all(|w| matches!(w.letter, 'S' | 'T'))
    }

    /// The words that change state the reader follows, for a block kept as written.
    fn state(&self) -> Vec<&'w Word> {
        let mut state: Vec<&'w Word> = Vec::new();
        state.extend(self.modal_unsupported);
        state.extend(self.motion.map(|(_, w)| w));
        state.extend(self.units.map(|(_, w)| w));
        state.extend(self.feed_mode.map(|(_, w)| w));
        state.extend(self.speed_mode.map(|(_, w)| w));
        state.extend(self.limit);
        state.extend(self.m_codes.iter().map(|(_, w)| *w));
        state.extend(['F', 'S', 'T'].iter().filter_map(|&c| self.get(c)));
        state
    }
}

/// Puts `v` (from `w`) in its group's slot, noting a second code of the group.
fn set<'w, T>(
    w: &'w Word,
    slot: &mut Option<(T, &'w Word)>,
    v: T,
    conflict: &mut Option<&'w Word>,
) {
    if slot.is_some() {
        conflict.get_or_insert(w);
    }
    *slot = Some((v, w));
}

/// Whether ncthread keeps G code `g` as written (`front/cycles.rs`): G70–G76, G90 and G94
/// (the turning and facing cycles, modal), G28 and G30 (to the reference point) and G53
/// (machine coordinates).
fn is_kept(g: i64) -> bool {
    matches!(g, 28 | 30 | 53 | 70..=76 | 90 | 94)
}

/// A G code of system B or C as the reader numbers it (system A's code for the same
/// function; G90/G91 as 900/910), or why it is none.
fn from_system(system: GcodeSystem, g: i64) -> Result<i64, String> {
    if let Some(a) = system.a_of(g) {
        return Ok(a);
    }
    let name = system.name();
    match g {
        90 => Ok(900),
        91 => Ok(910),
        32 => Err(format!("in {name} threads are G33")),
        50 => Err(format!("in {name} the spindle limit is G92 S")),
        98 | 99 => Err(format!(
            "in {name}, G98/G99 set a drilling cycle's return level, which ncthread does not read"
        )),
        79 => Err(format!(
            "G79 is system B's facing cycle, not a code of {name}, whose facing cycle is G24"
        )),
        g => Ok(g),
    }
}

/// What to say about a G code ncthread does not read (`text` as written; `g` as system A
/// numbers it).
fn unsupported_g(g: i64, text: &str, system: GcodeSystem) -> String {
    match g {
        28 | 30 => format!(
            "G{g} (return to the machine's reference point) is not read: the reference point is the machine's, not the program's, and LinuxCNC's G{g} goes to another place"
        ),
        53 => "G53 (machine coordinates) is not read".to_string(),
        83..=89 => format!("the G{g} drilling or tapping cycle is not read"),
        17 | 19 => format!("G{g} selects a plane other than ZX: not a lathe program"),
        77..=79 if system == GcodeSystem::A => format!(
            "G{g} is a code of FANUC's G-code system B (its {} cycle), not of system A (the default): if the machine reads system B, set `gcode_system = \"B\"` in the profile's [fanuc] section",
            ["turning", "threading", "facing"][(g - 77) as usize]
        ),
        33 | 91 | 95 if system == GcodeSystem::A => format!(
            "G{g} is a code of FANUC's G-code systems B and C, not of system A (the default): if the machine reads system B or C, set `gcode_system = \"B\"` (or \"C\") in the profile's [fanuc] section"
        ),
        24 if system == GcodeSystem::A => "G24 is a code of FANUC's G-code system C (its facing cycle), not of system A (the default): if the machine reads system C, set `gcode_system = \"C\"` in the profile's [fanuc] section".to_string(),
        _ => format!(
            "`{text}` is not supported{}",
            crate::dialect::read::did_you_mean(&format!("G{g:02}"), &KNOWN_G)
        ),
    }
}

impl FrontEnd<'_> {
    /// One block with words: its words sorted, then the steps in the module's order. `None`
    /// once a step has refused the block (its diagnostic said).
    pub(super) fn read_block(
        &mut self,
        line: Line<'_>,
        block: &Block,
        code_span: Span,
    ) -> Option<()> {
        let read_as_a;
        let block = if self.profile.gcode_system != GcodeSystem::A {
            read_as_a = self.system_b_block(line, block)?;
            &*read_as_a
        } else {
            block
        };
        // Filled in place: returned, the struct (some 400 bytes) was copied twice a line.
        let mut words = Words::default();
        self.sort_words(line, block, &mut words)?;
        if words.refused_by_name {
            return None;
        }
        self.check_words(line, &words)?;
        let motion = words.motion.map_or(self.motion, |(m, _)| m);
        // F is a lead, and X / U the thread's, in a G32 or G92 block (not beside G04).
        let threads = matches!(motion, Motion::Thread | Motion::Cycle) && words.dwell.is_none();
        let thread = threads && words.moves();
        let builder = std::mem::take(&mut words.builder);
        if !words.unsupported.is_empty() {
            // A builder's M code (a chip conveyor, a door, a tailstock…) alone, outside a
            // thread's block, is read in every mode (the machine's own code when it moves
            // nothing, else kept as written), and the block read.
            if thread || builder.len() < words.unsupported.len() {
                self.refuse_unsupported(line, block, words, thread);
                return None;
            }
            let found = std::mem::take(&mut words.unsupported);
            self.builder_warnings(found, &builder);
        }
        self.bare_g97_used(&words, code_span)?;
        if self.cycle_step(line, block, &words) {
            if let Some(w) = builder.first() {
                let text = &line.text[w.range.clone()];
                self.error(
                    codes::FANR_CYCLE,
                    line,
                    w.range.clone(),
                    format!("`{text}` in the block of a cycle, which ncthread keeps as written"),
                    "write the machine builder's M code in a block of its own, before or after the cycle",
                );
            }
            return None;
        }
        if let Some(w) = words.get('O') {
            self.program_number(line, block, w);
            return None;
        }
        self.units(line, &words)?;
        self.feed_mode(&words, code_span);
        let (lead, feed) = self.feed(line, &words, threads)?;
        let mut sw = Switches {
            spindle_mode: self.spindle_mode(line, &words)?.map(|m| (m, code_span)),
            ..Switches::default()
        };
        sw.spindle_mode(&mut self.r, None);
        self.tool(line, &words, code_span)?;
        self.gear_ranges(&words, code_span);
        sw.spindle = Some((self.speed(line, &words)?, words.direction(), code_span));
        if words.direction().is_some() {
            self.spindle_on = true;
        }
        sw.spindle(&mut self.r, None);
        sw.coolant = words.coolant_on(code_span);
        sw.coolant_on(&mut self.r, None);
        self.coordinate_system(&words, code_span);
        self.compensation(&words, code_span);
        match words.dwell {
            Some(g04) => self.dwell_step(line, &words, g04, code_span)?,
            None => self.motion_step(line, &words, lead, feed, code_span)?,
        }
        self.stops(&words, code_span);
        self.builder_codes(line, &builder);
        self.program_end(&words, code_span);
        Some(())
    }

    /// M41–M44, the gear (speed) range, before the spindle turns in it.
    fn gear_ranges(&mut self, words: &Words<'_>, code_span: Span) {
        for (m, _) in &words.m_codes {
            if (41..=44).contains(m) {
                self.push(
                    ItemKind::GearRange {
                        code: *m as u32,
                        machine: crate::dialect::fanuc::ID,
                    },
                    code_span,
                );
            }
        }
    }

    /// A G96 without S before any S (`bare_g96`) used: a move, a cycle or a thread before
    /// the S that gives its surface speed. Refused at the G96. **\[decided\]**
    fn bare_g96_used(&mut self, words: &Words<'_>) -> Option<()> {
        let Some(span) = self.bare_g96 else {
            return Some(());
        };
        let speed = words.get('S').is_some() && words.limit.is_none();
        let cycle = words.cycle.is_some() && !words.gives_no_cycle();
        // A move with its S runs at that S (it acts before the move); a G97 in the block
        // undoes the G96 before it.
        let g97 = words.speed_mode.is_some_and(|(surface, _)| !surface);
        let used = cycle || (!speed && !g97 && words.runs());
        if !used {
            return Some(());
        }
        self.bare_g96_refused(span, cycle && speed);
        None
    }

    /// The refusal of a G96 without S whose surface speed a move, a thread or a cycle would
    /// run at (`in_cycle`: the S is in a kept cycle's block).
    fn bare_g96_refused(&mut self, span: Span, in_cycle: bool) {
        self.bare_g96 = None;
        let message = if in_cycle {
            "`G96` without S, and a cycle's block gives its S: the cycle is kept as written, and its S cannot be the G96's"
        } else {
            "`G96` without S, and the tool moves before any S: the surface speed it moves at is the control's own, which no output can say"
        };
        self.r.error(
            codes::FANR_UNSUPPORTED,
            span,
            message,
            "write the surface speed with the G96: `G96 S200 M03`",
        );
    }

    /// A bare G97's speed used (`bare_g97`): a move, a cycle or a thread while the spindle
    /// turns at it, or M03/M04 without S after M05 stopped it. Refused at the G97 (or the M
    /// code), which is then done with.
    fn bare_g97_used(&mut self, words: &Words<'_>, code_span: Span) -> Option<()> {
        self.bare_g96_used(words)?;
        let Some(bare) = self.bare_g97 else {
            return Some(());
        };
        let speed = words.get('S').is_some() && words.limit.is_none();
        let used = !speed
            && if bare.stopped {
                words.direction().is_some()
            } else {
                words.runs()
            };
        if !used {
            return Some(());
        }
        self.bare_g97 = None;
        let (message, help) = if bare.stopped {
            (
                "the spindle starts again without S after a `G97` without S: which rpm the control keeps is not settled by any source ncthread holds",
                "write the speed with the M03/M04: `S800 M03`",
            )
        } else {
            (
                "`G97` without S, and the spindle turns on at the rpm it keeps: which speed the control keeps when the mode changes is not settled by any source ncthread holds",
                "write the speed in the same block: `G97 S800`, or stop the spindle (M05) before the next move",
            )
        };
        let at = if bare.stopped { code_span } else { bare.span };
        self.r.error(codes::FANR_UNSUPPORTED, at, message, help);
        None
    }

    /// The warnings of a block's builder M codes (`found`, one per code of `builder`): kept
    /// as written, and whether the profile says each moves no axis.
    fn builder_warnings(&mut self, found: Vec<(Span, String)>, builder: &[&Word]) {
        let (still, moving): (Vec<_>, Vec<_>) = found
            .into_iter()
            .zip(builder)
            .partition(|(_, w)| self.still(w).is_some());
        let strip = |v: Vec<((Span, String), &&Word)>| v.into_iter().map(|(f, _)| f).collect();
        self.r.unsupported(&BUILDER, strip(moving), true, false);
        self.r
            .unsupported(&super::BUILDER_STILL, strip(still), true, false);
    }

    /// The number of a builder's M code the profile says moves no axis (`still_m_codes`).
    fn still(&self, w: &Word) -> Option<u32> {
        let m = u32::try_from(w.value.to_whole().ok()?).ok()?;
        self.profile.still_m_codes.contains(&m).then_some(m)
    }

    /// The machine builder's M codes of a block, after its other items (the FANUC writer
    /// puts them back in its block). One the profile says moves no axis is the machine's
    /// own code ([`ItemKind::MachineCode`]); any other is kept as written, and what it does
    /// is the machine's, so that positions after it are unknown.
    fn builder_codes(&mut self, line: Line<'_>, codes: &[&Word]) {
        for w in codes {
            let span = self.span(line, w.range.clone());
            if let Some(code) = self.still(w) {
                self.push(
                    ItemKind::MachineCode {
                        code,
                        machine: crate::dialect::fanuc::ID,
                    },
                    span,
                );
                // It moves nothing: a G32 chain across it is refused as across any other
                // block between (FANR012), and a G20/G21 may still follow.
                continue;
            }
            self.r.keep_opaque(
                line.text[w.range.clone()].to_string(),
                span,
                None,
                crate::ir::ModalContext {
                    inch: self.inch,
                    diameter: true,
                    incremental: false,
                    per_minute: Some(self.per_minute),
                    moves: true,
                    cycle: false,
                    compensation: false,
                },
            );
            self.sync_end = None;
            self.moved = true;
        }
    }

    /// What a block means beside FANUC's cycles: a cycle kept as written (`front/cycles.rs`),
    /// the repeat of a G90/G94 in force, a move without its G code right after a cycle
    /// (refused: which of G00–G03 is in force is the control's), D, A or C outside a cycle.
    /// True when the block is done with (kept, or refused and said).
    fn cycle_step(&mut self, line: Line<'_>, block: &Block, words: &Words<'_>) -> bool {
        if let Some((g, w)) = words.cycle {
            // A G90 or G94 without a word of its cycle (`G21 G40 G49 G54 G80 G90`, the
            // safe-start line of programs written for mills and lathes alike) cuts nothing:
            // the group's mode is set, and the block's other codes act as in any block.
            // **[decided]**
            if words.gives_no_cycle() {
                self.kept_modal = None;
                self.cycle_mode_only = Some(g);
                return false;
            }
            self.kept_cycle(line, block, words, g, Some(w));
            return true;
        }
        let moves = words.dwell.is_none() && words.moves();
        let (pending, refused) = self.motion_named(line, block, words, self.cycle_mode_only, |g| {
            format!("after a G{g:02} that gave no cycle: the control would repeat a cycle nothing describes")
        });
        self.cycle_mode_only = pending;
        if refused {
            return true;
        }
        let (pending, refused) = self.motion_named(line, block, words, self.motion_after_cycle, |g| {
            format!("after the G{g:02} cycle: which of G00–G03 is in force after a cycle is the control's")
        });
        self.motion_after_cycle = pending;
        if refused {
            return true;
        }
        if let Some(g) = self.kept_modal {
            if words.motion.is_some() {
                self.kept_modal = None;
            } else if moves {
                // A block with only axes repeats the G90/G94 cycle.
                self.kept_cycle(line, block, words, g, None);
                return true;
            }
        }
        if let Some(w) = ['D', 'A', 'C'].iter().find_map(|&c| words.get(c)) {
            let text = &line.text[w.range.clone()];
            self.error(
                codes::FANR_UNSUPPORTED,
                line,
                w.range.clone(),
                format!("`{text}`: D, A and C belong to a canned cycle or its contour"),
                "remove it",
            );
            return true;
        }
        false
    }

    /// While `pending` (a cycle, or a G90/G94 that gave none, as its code), the next move
    /// must name its G code: a motion code ends it; a move without one is refused, `after`
    /// saying why (from the code as the machine's system spells it). The state left, and
    /// whether the block was refused.
    fn motion_named(
        &mut self,
        line: Line<'_>,
        block: &Block,
        words: &Words<'_>,
        pending: Option<i64>,
        after: impl Fn(i64) -> String,
    ) -> (Option<i64>, bool) {
        let Some(g) = pending else {
            return (None, false);
        };
        if words.motion.is_some() {
            return (None, false);
        }
        if words.dwell.is_some() || !words.moves() {
            return (pending, false);
        }
        let text = &line.text[block.code_range.clone()];
        self.error(
            codes::FANR_CYCLE,
            line,
            block.code_range.clone(),
            format!(
                "`{text}` moves without a G code {}",
                after(self.profile.gcode_system.code(g))
            ),
            "name the motion: `G00 X100. Z100.` or `G01 X50. F0.2`",
        );
        (pending, true)
    }

    /// A block of system B or C as the reader reads system A: G90 / G91 set the distance mode
    /// (`self.incremental`) first, under G91 X and Z are increments (read as U and W; a
    /// cycle's too, G53's not), and U and W are words of the cycles only. `None` when a block
    /// moves with U or W (said).
    fn system_b_block<'b>(
        &mut self,
        line: Line<'_>,
        block: &'b Block,
    ) -> Option<std::borrow::Cow<'b, Block>> {
        for w in &block.words {
            if w.letter == 'G' {
                match w.value.to_whole() {
                    Ok(90) => self.incremental = false,
                    Ok(91) => self.incremental = true,
                    _ => {}
                }
            }
        }
        // A cycle kept as written (system B's G77/G79, system C's G20/G24 are system A's
        // G90/G94).
        let cycle = block.words.iter().any(|w| {
            w.letter == 'G'
                && w.value
                    .to_whole()
                    .is_ok_and(|g| from_system(self.profile.gcode_system, g).is_ok_and(is_kept))
        });
        if !cycle && let Some(w) = block.words.iter().find(|w| matches!(w.letter, 'U' | 'W')) {
            let text = &line.text[w.range.clone()];
            self.error(
                codes::FANR_UNSUPPORTED,
                line,
                w.range.clone(),
                format!(
                    "`{text}`: in {} an increment is G91 with X or Z",
                    self.profile.gcode_system.name()
                ),
                "write `G91 X… Z…` (or the absolute X, Z)",
            );
            return None;
        }
        // Under G91 a cycle's X and Z are increments too (`G91 G28 X0. Z0.`, a turning
        // cycle's end), read as system A's U and W; G53's are machine coordinates.
        let g53 = block
            .words
            .iter()
            .any(|w| w.letter == 'G' && w.value.to_whole() == Ok(53));
        if !self.incremental || g53 {
            return Some(std::borrow::Cow::Borrowed(block));
        }
        let mut b = block.clone();
        for w in &mut b.words {
            w.letter = match w.letter {
                'X' => 'U',
                'Z' => 'W',
                c => c,
            };
        }
        Some(std::borrow::Cow::Owned(b))
    }

    /// Sorts the block's words by group: G and M codes into their groups (or among the
    /// unsupported), the address letters kept in order. G76 is refused here, by name. `None`
    /// when an M code is not a whole number (said).
    fn sort_words<'w>(
        &mut self,
        line: Line<'_>,
        block: &'w Block,
        words: &mut Words<'w>,
    ) -> Option<()> {
        for w in &block.words {
            let text = &line.text[w.range.clone()];
            match w.letter {
                'G' => self.sort_g(line, w, words),
                'M' => self.sort_m(line, w, words)?,
                'X' | 'Z' | 'U' | 'W' | 'I' | 'K' | 'R' | 'F' | 'S' | 'T' | 'P' | 'Q' | 'O'
                | 'D' | 'A' | 'C' => {
                    if words.present & letter_bit(w.letter) != 0 {
                        words.conflict.get_or_insert(w);
                    }
                    words.present |= letter_bit(w.letter);
                    words.letters.push(w);
                }
                'E' => words.unsupported.push((
                    self.span(line, w.range.clone()),
                    format!("`{text}`: E (a lead in threads per inch) is not read"),
                )),
                c => words.unsupported.push((
                    self.span(line, w.range.clone()),
                    format!("`{text}`: address {c} is not supported"),
                )),
            }
        }
        Some(())
    }

    /// A G word into its modal group, or among the unsupported; G76 refused by name.
    fn sort_g<'w>(&mut self, line: Line<'_>, w: &'w Word, words: &mut Words<'w>) {
        let text = &line.text[w.range.clone()];
        let Ok(g) = w.value.to_scaled(1) else {
            words.unsupported.push((
                self.span(line, w.range.clone()),
                format!("`{text}` is not a G code"),
            ));
            return;
        };
        if g % 10 != 0 {
            words.unsupported.push((
                self.span(line, w.range.clone()),
                format!("`{text}` is not a G code ncthread reads"),
            ));
            return;
        }
        let mut g = g / 10;
        if self.profile.gcode_system != GcodeSystem::A {
            match from_system(self.profile.gcode_system, g) {
                Ok(a) => g = a,
                Err(why) => {
                    words
                        .unsupported
                        .push((self.span(line, w.range.clone()), format!("`{text}`: {why}")));
                    return;
                }
            }
        }
        let conflict = &mut words.conflict;
        match g {
            // System B's G90 / G91, absolute and incremental (read as 900 / 910).
            900 | 910 => set(w, &mut words.distance, g == 910, conflict),
            0 => set(w, &mut words.motion, Motion::Rapid, conflict),
            1 => set(w, &mut words.motion, Motion::Feed, conflict),
            2 => set(w, &mut words.motion, Motion::Arc(true), conflict),
            3 => set(w, &mut words.motion, Motion::Arc(false), conflict),
            32 => set(w, &mut words.motion, Motion::Thread, conflict),
            92 => set(w, &mut words.motion, Motion::Cycle, conflict),
            4 => words.dwell = Some(w),
            50 => words.limit = Some(w),
            20 => set(w, &mut words.units, true, conflict),
            21 => set(w, &mut words.units, false, conflict),
            98 => set(w, &mut words.feed_mode, true, conflict),
            99 => set(w, &mut words.feed_mode, false, conflict),
            96 => set(w, &mut words.speed_mode, true, conflict),
            97 => set(w, &mut words.speed_mode, false, conflict),
            40 => set(w, &mut words.comp, Compensation::Off, conflict),
            41 | 42 => set(
                w,
                &mut words.comp,
                Compensation::FromTool {
                    right: g == 42,
                    tool: None,
                },
                conflict,
            ),
            54..=59 => set(w, &mut words.offset, (g - 53) as u8, conflict),
            // The ZX plane is a lathe's only one; G49 cancels a tool length compensation
            // and G80 drilling cycles, neither of which ncthread reads (so neither is in
            // force).
            18 | 49 | 80 => {}
            g if is_kept(g) => set(w, &mut words.cycle, g, conflict),
            _ => {
                // A cycle code is modal: the blocks after it would repeat it.
                if matches!(g, 90 | 94 | 83..=89) {
                    words.modal_unsupported.get_or_insert(w);
                }
                let what = unsupported_g(g, text, self.profile.gcode_system);
                words.unsupported.push((
                    self.span(line, w.range.clone()),
                    format!("`{text}`: {what}"),
                ));
            }
        }
    }

    /// An M word among the block's M codes, or among the unsupported. `None` when it is not
    /// a whole number (said).
    fn sort_m<'w>(&mut self, line: Line<'_>, w: &'w Word, words: &mut Words<'w>) -> Option<()> {
        let text = &line.text[w.range.clone()];
        let why = match self.whole(line, w)? {
            // The same code twice (`M30 M30`) is a slip whose count the control does not
            // define: refused, as a letter written twice is.
            m @ (0 | 1 | 2 | 30 | 3 | 4 | 5 | 8 | 9 | 41..=44) => {
                if words.m(m).is_some() {
                    words.conflict.get_or_insert(w);
                }
                words.m_codes.push((m, w));
                return Some(());
            }
            7 if self.profile.mist => {
                words.m_codes.push((7, w));
                return Some(());
            }
            7 => format!(
                "`{text}`: mist coolant is not supported (set `mist = true` in the profile's [fanuc] section if the machine has it)"
            ),
            29 => format!("`{text}`: rigid tapping (M29) is not read"),
            98 | 99 => format!("`{text}`: a subprogram call or return is not read here"),
            _ => {
                words.builder.push(w);
                format!(
                    "`{text}` is the machine builder's M code (FANUC's own are M00–M05, M08, M09, M30 and the gear ranges M41–M44): what it does is the machine's"
                )
            }
        };
        words
            .unsupported
            .push((self.span(line, w.range.clone()), why));
        Some(())
    }
}

impl<'w> Words<'w> {
    /// M03 or M04: the direction the block starts the spindle in.
    fn direction(&self) -> Option<SpindleDirection> {
        self.m_codes.iter().find_map(|(m, _)| match m {
            3 => Some(SpindleDirection::Clockwise),
            4 => Some(SpindleDirection::CounterClockwise),
            _ => None,
        })
    }

    /// M07 and M08, in the block's order.
    pub(super) fn coolant_on(&self, span: Span) -> Vec<(Coolant, Span)> {
        self.m_codes
            .iter()
            .filter_map(|(m, _)| match m {
                7 => Some((Coolant::Mist, span)),
                8 => Some((Coolant::Flood, span)),
                _ => None,
            })
            .collect()
    }
}

impl FrontEnd<'_> {
    /// The block as a whole: a letter or a group written twice, M codes of one function
    /// that contradict each other (which wins is the machine builder's ladder), an axis
    /// written both absolute and incremental.
    fn check_words(&mut self, line: Line<'_>, words: &Words<'_>) -> Option<()> {
        if let Some(w) = words.conflict {
            let text = &line.text[w.range.clone()];
            self.error(
                codes::FANR_CONFLICT,
                line,
                w.range.clone(),
                format!("`{text}` repeats a word or a code of the same group in this block"),
                "write each word once, and one code of each group (motion, units, feed mode…)",
            );
            return None;
        }
        for (a, b) in [(3, 4), (3, 5), (4, 5), (8, 9), (7, 9), (2, 30)] {
            if let (Some(_), Some(w)) = (words.m(a), words.m(b)) {
                let text = &line.text[w.range.clone()];
                self.error(
                    codes::FANR_CONFLICT,
                    line,
                    w.range.clone(),
                    format!("`{text}` contradicts M{a:02} in the same block"),
                    "write each spindle or coolant command, and the program's end, in a block of its own",
                );
                return None;
            }
        }
        for (a, b) in [('X', 'U'), ('Z', 'W')] {
            if let (Some(_), Some(w)) = (words.get(a), words.get(b)) {
                let text = &line.text[w.range.clone()];
                self.error(
                    codes::FANR_CONFLICT,
                    line,
                    w.range.clone(),
                    format!("`{text}`: {a} and {b} both set the same axis in this block"),
                    "write the axis once, absolute or incremental",
                );
                return None;
            }
        }
        Some(())
    }

    /// A block with words ncthread does not read: refused, or kept as written with
    /// `--unsupported warn` (unless it changes state the reader follows).
    fn refuse_unsupported(
        &mut self,
        line: Line<'_>,
        block: &Block,
        words: Words<'_>,
        thread: bool,
    ) {
        let keep = self.unsupported == Unsupported::Warn;
        let state = words.state();
        if self
            .r
            .unsupported(&UNSUPPORTED, words.unsupported, keep, thread)
        {
            self.keep(line, block, &state);
        }
    }

    /// Program number: `O0001`, on a line of its own.
    fn program_number(&mut self, line: Line<'_>, block: &Block, w: &Word) {
        if block.words.len() > 1 {
            let text = &line.text[w.range.clone()];
            self.error(
                codes::FANR_SYNTAX,
                line,
                w.range.clone(),
                format!("`{text}`: a program number stands on a line of its own"),
                "write `O0001 (NAME)` as the program's first line",
            );
        } else if let Some(n) = self.whole(line, w) {
            match u32::try_from(n) {
                // The first program number is the program's (a second one would start a
                // subprogram, which ncthread does not read yet).
                Ok(number) if (1..=99_999_999).contains(&number) => {
                    self.r.number.get_or_insert(number);
                }
                _ => {
                    let text = &line.text[w.range.clone()];
                    self.error(
                        codes::FANR_NUMBER,
                        line,
                        w.range.clone(),
                        format!("`{text}` is not a program number"),
                        "program numbers are O1 to O9999 (O99999999 on controls with eight digits, and Haas's five)",
                    );
                }
            }
        }
    }

    /// Units: G20 / G21, first, as they decide what every other number means; only before
    /// the first move.
    fn units(&mut self, line: Line<'_>, words: &Words<'_>) -> Option<()> {
        if let Some((inch, w)) = words.units {
            if (self.moved || self.surface_speed) && inch != self.inch {
                // A surface speed keeps the unit it was set in (m/min or ft/min): a G50 S or
                // an S after the change would be read in the other one.
                let after = if self.moved {
                    "after the first move"
                } else {
                    "after G96 set a surface speed"
                };
                let text = &line.text[w.range.clone()];
                self.error(
                    codes::FANR_INCH,
                    line,
                    w.range.clone(),
                    format!("`{text}` {after}: the unit must be set at the program's start"),
                    match self.profile.gcode_system {
                        GcodeSystem::C => {
                            "put G70 or G71 in the program's first blocks, before any move or G96"
                        }
                        _ => "put G20 or G21 in the program's first blocks, before any move or G96",
                    },
                );
                return None;
            }
            self.inch = inch;
        }
        Some(())
    }

    /// Feed mode: G98 (per minute) / G99 (per revolution).
    fn feed_mode(&mut self, words: &Words<'_>, code_span: Span) {
        if let Some((per_minute, _)) = words.feed_mode {
            // A feed set in the other mode is not carried over: which number F then holds
            // (mm/min or mm/rev) no source settles.
            if per_minute != self.per_minute && matches!(self.f, Some(FRegister::Feed(_))) {
                self.f = None;
            }
            self.per_minute = per_minute;
            self.push(
                ItemKind::FeedMode(if per_minute {
                    FeedMode::PerMin
                } else {
                    FeedMode::PerRev
                }),
                code_span,
            );
        }
    }

    /// Feed: F, a lead in a G32 / G92 block (`threads`), else a feed; kept in the one F
    /// register. The block's lead and feed.
    fn feed(
        &mut self,
        line: Line<'_>,
        words: &Words<'_>,
        threads: bool,
    ) -> Option<(Option<Lead>, Option<Length>)> {
        let mut lead: Option<Lead> = None;
        let mut feed: Option<Length> = None;
        if let Some(w) = words.get('F') {
            if threads {
                lead = Some(self.lead(line, w)?);
                self.f = Some(FRegister::Lead(lead?));
            } else {
                let f = self.length(line, w, Unit::Feed)?;
                if f.0 <= 0 {
                    let text = &line.text[w.range.clone()];
                    self.error(
                        codes::FANR_NUMBER,
                        line,
                        w.range.clone(),
                        format!("`{text}`: a feed must be positive"),
                        "write the feed",
                    );
                    return None;
                }
                feed = Some(f);
                self.f = Some(FRegister::Feed(f));
            }
        }
        Some((lead, feed))
    }

    /// Speed mode: G50 S (the spindle's limit, never a coordinate setting) or G96 / G97
    /// (the two never share a block). The mode to switch to, if any.
    fn spindle_mode(&mut self, line: Line<'_>, words: &Words<'_>) -> Option<Option<SpindleMode>> {
        match words.limit {
            Some(w50) => self.spindle_limit(line, words, w50),
            None => self.speed_mode(line, words),
        }
    }

    /// `G50 S<rpm>`: the limit, and under G96 the surface speed again with it.
    fn spindle_limit(
        &mut self,
        line: Line<'_>,
        words: &Words<'_>,
        w50: &Word,
    ) -> Option<Option<SpindleMode>> {
        if let Some((_, w)) = words.speed_mode {
            let text = &line.text[w.range.clone()];
            self.error(
                codes::FANR_CONFLICT,
                line,
                w.range.clone(),
                format!("`{text}` in a G50 block: its S would be the limit, not the speed"),
                "write `G50 S<limit>` and `G96 S<speed>` in blocks of their own",
            );
            return None;
        }
        if words.moves() {
            let text = &line.text[w50.range.clone()];
            self.error(
                codes::FANR_UNSUPPORTED,
                line,
                w50.range.clone(),
                format!("`{text}` with X or Z sets the coordinate system from where the tool stands, which ncthread cannot know"),
                "set the work offset on the machine (G54) and remove G50 X Z from the program; `G50 S…` alone (the spindle's limit) is read",
            );
            return None;
        }
        let Some(s) = words.get('S') else {
            let text = &line.text[w50.range.clone()];
            self.error(
                codes::FANR_UNSUPPORTED,
                line,
                w50.range.clone(),
                format!("`{text}` without S"),
                "write `G50 S<rpm>`, the spindle's limit under G96",
            );
            return None;
        };
        let limit = self.whole(line, s)?;
        self.limit = Some(Decimal {
            mantissa: limit as i128,
            scale: 0,
            has_point: false,
        });
        // After a G96 without S the limit comes with its S (`bare_g96`).
        Some(
            (self.surface_speed && self.bare_g96.is_none()).then_some(SpindleMode::SurfaceSpeed {
                limit: self.limit,
                feet: self.inch,
            }),
        )
    }

    /// G96 (a surface speed, with the limit G50 set) or G97 (rpm), each with its S.
    fn speed_mode(&mut self, line: Line<'_>, words: &Words<'_>) -> Option<Option<SpindleMode>> {
        let Some((surface, w)) = words.speed_mode else {
            // An S after a bare G97: the rpm from here on, the mode with it, at the S (a
            // FANUC output writes `G97 S800` there, not a G97 with the last speed it knows).
            if let Some(s) = words.get('S')
                && let Some(bare) = self.bare_g97.take()
                && !bare.stopped
            {
                let span = self.span(line, s.range.clone());
                self.push(ItemKind::SpindleMode(SpindleMode::Rpm), span);
            }
            return Some(None);
        };
        // A G96 or G97 with S after a bare one: the bare one's speed was never used.
        if words.get('S').is_some() {
            self.bare_g97 = None;
            self.bare_g96 = None;
        }
        if words.get('S').is_none() && !self.speed_given && (surface || self.bare_g96.is_some()) {
            // Before any S the speed is the control's own (as for an M03 without S): a G96
            // waits for the S that gives its surface speed (`bare_g96`), unless its own block
            // runs at it; a G97 after it undoes it, and is read as any G97 before an S.
            self.surface_speed = surface;
            if !surface {
                self.bare_g96 = None;
            } else {
                let span = self.span(line, w.range.clone());
                if words.runs() {
                    self.bare_g96_refused(span, false);
                    return None;
                }
                self.bare_g96 = Some(span);
                return Some(None);
            }
        }
        if words.get('S').is_none()
            && !surface
            && self.surface_speed
            && self.spindle_on
            && words.moves()
        {
            // The block's own move runs at the rpm the control keeps.
            let text = &line.text[w.range.clone()];
            self.error(
                codes::FANR_UNSUPPORTED,
                line,
                w.range.clone(),
                format!("`{text}` without S, and the block moves at the rpm it keeps: which speed the control keeps when the mode changes is not settled by any source ncthread holds"),
                "write the speed in the same block: `G97 S800`",
            );
            return None;
        }
        if words.get('S').is_none() && !surface && self.surface_speed {
            // Read where its speed is never used (`bare_g97`); while the spindle stands, the
            // mode is here and the next start must say its S.
            self.surface_speed = false;
            self.bare_g97 = Some(super::BareG97 {
                span: self.span(line, w.range.clone()),
                stopped: !self.spindle_on,
            });
            return Some((!self.spindle_on).then_some(SpindleMode::Rpm));
        }
        if words.get('S').is_none() && (surface || self.surface_speed) {
            // What G96 or G97 keeps without S (the last G96 S? the rpm the surface speed ran
            // at?) no source ncthread holds settles.
            let text = &line.text[w.range.clone()];
            self.error(
                codes::FANR_UNSUPPORTED,
                line,
                w.range.clone(),
                format!("`{text}` without S: which speed the control keeps when the mode changes is not settled by any source ncthread holds"),
                "write the speed in the same block: `G96 S200 M03`, `G97 S800`",
            );
            return None;
        }
        // Under G20 the surface speed is in feet per minute, as in LinuxCNC.
        self.surface_speed = surface;
        Some(Some(if surface {
            SpindleMode::SurfaceSpeed {
                limit: self.limit,
                feet: self.inch,
            }
        } else {
            SpindleMode::Rpm
        }))
    }

    /// Tool: T, the tool and its offset, two digits each.
    fn tool(&mut self, line: Line<'_>, words: &Words<'_>, code_span: Span) -> Option<()> {
        if let Some(w) = words.get('T') {
            let n = self.whole(line, w)?;
            let (tool, off) = (n / 100, n % 100);
            if !(100..=9999).contains(&n) {
                let text = &line.text[w.range.clone()];
                self.error(
                    codes::FANR_TOOL,
                    line,
                    w.range.clone(),
                    format!("`{text}` is not a tool and offset of two digits each (tool {tool}, offset {off})"),
                    "write T followed by the tool number and the offset number, two digits each: T0101 (tool 1, offset 1), T0100 (tool 1, no offset); tools over 99 are not read",
                );
                return None;
            }
            self.push(
                ItemKind::Tool {
                    number: Some(tool as u32),
                    offset: Some(off as u32),
                },
                code_span,
            );
        }
        Some(())
    }

    /// Spindle: the speed S (not G50's, which is the limit). The block's speed, if any.
    pub(super) fn speed(&mut self, line: Line<'_>, words: &Words<'_>) -> Option<Option<u32>> {
        let Some(w) = words.get('S').filter(|_| words.limit.is_none()) else {
            return Some(None);
        };
        let s = self.whole(line, w)?;
        self.speed_given = true;
        // A G96 without S before it: its mode from here on, with this S (where a block
        // that changes the mode says its speed).
        if self.bare_g96.take().is_some() {
            let span = self.span(line, w.range.clone());
            self.push(
                ItemKind::SpindleMode(SpindleMode::SurfaceSpeed {
                    limit: self.limit,
                    feet: self.inch,
                }),
                span,
            );
        }
        let Ok(s) = u32::try_from(s) else {
            let text = &line.text[w.range.clone()];
            let why = if s < 0 {
                "a speed is not negative"
            } else {
                "too large for a speed"
            };
            self.error(
                codes::FANR_NUMBER,
                line,
                w.range.clone(),
                format!("`{text}`: {why}"),
                "write the speed in rpm or m/min",
            );
            return None;
        };
        Some(Some(s))
    }

    /// Coordinate system: G54 – G59.
    fn coordinate_system(&mut self, words: &Words<'_>, code_span: Span) {
        if let Some((n, _)) = words.offset {
            self.push(ItemKind::WorkOffset(n), code_span);
        }
    }

    /// Compensation: G40, G41, G42.
    fn compensation(&mut self, words: &Words<'_>, code_span: Span) {
        if let Some((c, _)) = words.comp {
            // G41/G42 again while it is in force is not handed on.
            if !c.switches(self.comp) {
                return;
            }
            self.comp = c;
            self.push(ItemKind::Compensation(c), code_span);
        }
    }

    /// Dwell: G04 is one-shot; a motion code beside it is modal and takes effect for the
    /// blocks after it (a thread or a cycle there would need the axes G04 takes).
    fn dwell_step(
        &mut self,
        line: Line<'_>,
        words: &Words<'_>,
        g04: &Word,
        code_span: Span,
    ) -> Option<()> {
        if let Some((m, w)) = words.motion {
            if matches!(m, Motion::Thread | Motion::Cycle) {
                let text = &line.text[w.range.clone()];
                self.error(
                    codes::FANR_CONFLICT,
                    line,
                    w.range.clone(),
                    format!("`{text}` in a G04 block: X and U are the dwell's time there"),
                    "write the dwell and the thread in blocks of their own",
                );
                return None;
            }
            self.motion = m;
            self.cycle = None;
        }
        self.dwell(line, g04, &|c| words.get(c), code_span)
    }

    /// Motion: the modal motion set, then the block's move (a G92 block moves without X or
    /// Z: it repeats the cycle); a feed F of its own is for the moves after it.
    fn motion_step(
        &mut self,
        line: Line<'_>,
        words: &Words<'_>,
        lead: Option<Lead>,
        feed: Option<Length>,
        code_span: Span,
    ) -> Option<()> {
        if let Some((m, _)) = words.motion {
            self.motion = m;
            if m != Motion::Cycle {
                self.cycle = None;
            }
        }
        if words.moves() || words.motion.is_some_and(|(m, _)| m == Motion::Cycle) {
            let g = words.motion.map(|(_, w)| w);
            self.motion_block(line, &|c| words.get(c), lead, feed, g, code_span)?;
            // A rapid's F is for the moves after it (a cycle kept as written without F cuts
            // at it): an item of its own, so that a writer says it.
            if let (Motion::Rapid, Some(f)) = (self.motion, feed) {
                self.push(ItemKind::FeedRate(f), code_span);
            }
        } else if let Some(f) = feed {
            self.push(ItemKind::FeedRate(f), code_span);
        } else if let Some(w) = ['I', 'K', 'R', 'Q', 'P'].iter().find_map(|&c| words.get(c)) {
            let text = &line.text[w.range.clone()];
            self.error(
                codes::FANR_UNSUPPORTED,
                line,
                w.range.clone(),
                format!("`{text}` in a block that does not move"),
                "I, K, R and Q belong to a move (an arc, a thread); P to a dwell",
            );
            return None;
        }
        Some(())
    }

    /// Stop: M05, M09, M00 and M01, after the motion, in the block's order.
    pub(super) fn stops(&mut self, words: &Words<'_>, code_span: Span) {
        for (m, _) in &words.m_codes {
            match m {
                5 => {
                    self.spindle_on = false;
                    self.push(ItemKind::SpindleStop, code_span);
                    // A bare G97's mode, once the spindle stands (`bare_g97`).
                    if let Some(bare) = self.bare_g97.as_mut().filter(|b| !b.stopped) {
                        bare.stopped = true;
                        let span = bare.span;
                        self.push(ItemKind::SpindleMode(SpindleMode::Rpm), span);
                    }
                }
                9 => self.push(ItemKind::Coolant(Coolant::Off), code_span),
                0 => self.push(ItemKind::Stop { optional: false }, code_span),
                1 => self.push(ItemKind::Stop { optional: true }, code_span),
                _ => {}
            }
        }
    }

    /// End: M02 and M30, last.
    fn program_end(&mut self, words: &Words<'_>, code_span: Span) {
        for (m, _) in &words.m_codes {
            match m {
                2 => self.push(ItemKind::ProgramEnd(EndCode::M2), code_span),
                30 => self.push(ItemKind::ProgramEnd(EndCode::M30), code_span),
                _ => {}
            }
        }
    }
}

//! Sorting one block's words by modal group ([`Words`]): what the block asks, before any of
//! it is carried out. Repeated and conflicting words are reported here.

use super::{FrontEnd, Motion};
use crate::dialect::czech::codes;
use crate::dialect::czech::profile::{CzechArcs, CzechDwell};
use crate::dialect::czech::syntax::{Block, Value, Word};
use crate::dialect::{Letters, WORD_REPORTS, budget};
use crate::ir::{Coolant, EndCode, FeedMode, SpindleDirection};
use crate::source::Line;

/// The words of one block, sorted by modal group: what the block asks.
#[derive(Default)]
pub(super) struct Words<'b> {
    /// G00, G01, G02, G03, G33.
    pub(super) motion: Option<(Motion, &'b Word)>,
    /// G90 (false) or G91.
    pub(super) distance: Option<(bool, &'b Word)>,
    /// G94 or G95.
    pub(super) feed_mode: Option<(FeedMode, &'b Word)>,
    /// M03, M04 (a direction) or M05 (none).
    pub(super) spindle: Option<(Option<SpindleDirection>, &'b Word)>,
    /// M02 or M30.
    pub(super) end: Option<(EndCode, &'b Word)>,
    /// The profile's gear range M codes.
    pub(super) gears: Vec<(u32, &'b Word)>,
    /// M07, M08, M09, in the block's order.
    pub(super) coolant: Vec<(Coolant, &'b Word)>,
    /// G04 and the word that gives its time (the profile's `dwell` form).
    pub(super) dwell: Option<(&'b Word, Option<&'b Word>)>,
    /// G96 (true) or G97 (the profile's `surface_speed`).
    pub(super) speed_mode: Option<(bool, &'b Word)>,
    /// The address words (X, Z, F, S, T, D, I, J, E, K, R, P).
    pub(super) by_letter: Letters<&'b Word>,
    /// Each word the reader does not support, and what it is.
    pub(super) unsupported: Vec<(&'b Word, String)>,
}

impl<'b> Words<'b> {
    pub(super) fn get(&self, letter: char) -> Option<&'b Word> {
        self.by_letter.get(&letter).copied()
    }
}

/// The problems reported for one block: a hostile line of thousands of repeated words gets a
/// few diagnostics and a count, not one per word.
struct Tally {
    /// No word conflicts with another: the block can be carried out.
    ok: bool,
    /// Repeated or conflicting words so far.
    conflicts: usize,
}

const R_WITHOUT_EQUALS: &str = "an R word without `=` (R-parameter arithmetic is not documented)";

/// A G or M code's number: a whole number of 0 or more.
fn code_number(w: &Word) -> Option<i64> {
    match w.value {
        Value::Number(d) => d.to_whole().ok().filter(|v| *v >= 0),
        Value::Param(_) => None,
    }
}

impl<'a> FrontEnd<'a> {
    /// Sorts the words by modal group into `words` (empty); reports repeated and conflicting
    /// words. `false` when a conflict keeps the block from being carried out. After the words
    /// one by one: the count of conflicts not reported, the dwell's words, the thread and arc
    /// words.
    pub(super) fn classify<'b>(
        &mut self,
        line: Line<'_>,
        block: &'b Block,
        words: &mut Words<'b>,
    ) -> bool {
        let mut tally = Tally {
            ok: true,
            conflicts: 0,
        };
        for word in &block.words {
            match word.letter {
                'G' => self.g_word(line, word, words, &mut tally),
                'M' => self.m_word(line, word, words, &mut tally),
                c if self.is_address(c) => self.address_word(line, word, words, &mut tally),
                'N' => self.misplaced_number(line, word, &mut tally),
                'Y' => words
                    .unsupported
                    .push((word, "the Y axis (ncthread models ZX lathes)".into())),
                'R' => words.unsupported.push((word, R_WITHOUT_EQUALS.into())),
                c => words.unsupported.push((word, format!("address {c}"))),
            }
        }
        if tally.conflicts > WORD_REPORTS {
            tally.ok = false;
            let more = tally.conflicts - WORD_REPORTS;
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
        self.dwell_words(line, words, &mut tally);
        self.thread_and_arc_words(words);
        tally.ok
    }

    /// A G code: its group (motion, G90/G91, G94/G95, G04, G96/G97), or why it is not
    /// supported; a second code of a group conflicts.
    fn g_word<'b>(
        &mut self,
        line: Line<'_>,
        word: &'b Word,
        words: &mut Words<'b>,
        tally: &mut Tally,
    ) {
        let Some(g) = code_number(word) else {
            words
                .unsupported
                .push((word, "a G code that is not a whole number".into()));
            return;
        };
        if let Some(previous) = self.g_group(g, word, words)
            && budget(&mut tally.conflicts)
        {
            tally.ok = false;
            let range = word.range.clone();
            let prev = &line.text[previous.range.clone()];
            self.report(self.error(codes::CZR_CONFLICT, line, range, format!("this G code conflicts with `{prev}` in the same block"))
                .label("same group as an earlier G code")
                .help("write one G code of each group (motion, G90/G91, G94/G95, G96/G97, G04) per block"));
        }
    }

    /// Files G code `g` in its group; the group's earlier word, if any.
    fn g_group<'b>(&self, g: i64, word: &'b Word, words: &mut Words<'b>) -> Option<&'b Word> {
        let czech = self.profile;
        match g {
            0 | 1 | 33 => {
                let m = match g {
                    0 => Motion::Rapid,
                    1 => Motion::Feed,
                    _ => Motion::Thread,
                };
                words.motion.replace((m, word)).map(|(_, w)| w)
            }
            2 | 3 if czech.arcs != CzechArcs::None => words
                .motion
                .replace((Motion::Arc(g == 2), word))
                .map(|(_, w)| w),
            90 | 91 => words.distance.replace((g == 91, word)).map(|(_, w)| w),
            94 | 95 => {
                let mode = if g == 95 {
                    FeedMode::PerRev
                } else {
                    FeedMode::PerMin
                };
                words.feed_mode.replace((mode, word)).map(|(_, w)| w)
            }
            4 if czech.dwell != CzechDwell::None => {
                words.dwell.replace((word, None)).map(|(w, _)| w)
            }
            96 | 97 if czech.surface_speed => {
                words.speed_mode.replace((g == 96, word)).map(|(_, w)| w)
            }
            _ => {
                words.unsupported.push((word, unsupported_g(g)));
                None
            }
        }
    }

    /// An M code: spindle, end, coolant or gear range, or why it is not supported; a second
    /// spindle or end code conflicts.
    fn m_word<'b>(
        &mut self,
        line: Line<'_>,
        word: &'b Word,
        words: &mut Words<'b>,
        tally: &mut Tally,
    ) {
        let Some(m) = code_number(word) else {
            words
                .unsupported
                .push((word, "an M code that is not a whole number".into()));
            return;
        };
        if let Some(previous) = self.m_group(m, word, words)
            && budget(&mut tally.conflicts)
        {
            tally.ok = false;
            let prev = &line.text[previous.range.clone()];
            self.report(
                self.error(
                    codes::CZR_CONFLICT,
                    line,
                    word.range.clone(),
                    format!("this M code conflicts with `{prev}` in the same block"),
                )
                .help("write one spindle M code (M03, M04, M05) and one end code per block"),
            );
        }
    }

    /// Files M code `m` in its group; the group's earlier word, if any.
    fn m_group<'b>(&self, m: i64, word: &'b Word, words: &mut Words<'b>) -> Option<&'b Word> {
        let czech = self.profile;
        let gear = u32::try_from(m)
            .ok()
            .filter(|g| czech.gear_range_mcodes.contains(g));
        let previous = match m {
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
            8 | 9 if czech.coolant => {
                let c = if m == 8 { Coolant::Flood } else { Coolant::Off };
                words.coolant.push((c, word));
                None
            }
            7 if czech.mist => {
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
            _ if gear.is_some() => {
                words.gears.extend(gear.map(|g| (g, word)));
                None
            }
            _ => {
                words.unsupported.push((word, format!("M{m:02}")));
                None
            }
        };
        previous.map(|(_, w)| w)
    }

    /// The letters that are address words here: K and R where the profile declares arcs, P
    /// where a dwell's time is in P.
    fn is_address(&self, letter: char) -> bool {
        match letter {
            'X' | 'Z' | 'F' | 'S' | 'T' | 'D' | 'I' | 'J' | 'E' => true,
            'K' | 'R' => self.profile.arcs != CzechArcs::None,
            'P' => self.profile.dwell == CzechDwell::PMilliseconds,
            _ => false,
        }
    }

    /// An address word: each address once per block; only F takes a parameter (`FRnn`).
    fn address_word<'b>(
        &mut self,
        line: Line<'_>,
        word: &'b Word,
        words: &mut Words<'b>,
        tally: &mut Tally,
    ) {
        if let Some(previous) = words.by_letter.insert(word.letter, word)
            && budget(&mut tally.conflicts)
        {
            tally.ok = false;
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

    /// An N word after the block's start.
    fn misplaced_number(&mut self, line: Line<'_>, word: &Word, tally: &mut Tally) {
        if budget(&mut tally.conflicts) {
            tally.ok = false;
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
    }

    /// The G04 block's words: the profile's time word is the dwell's time; no motion word.
    fn dwell_words(&mut self, line: Line<'_>, words: &mut Words<'_>, tally: &mut Tally) {
        // In a G04 block the profile's time word is the dwell's time, not an axis or a feed;
        // the block moves nothing. P means something only there.
        if let Some((g04, _)) = words.dwell {
            let letter = self.profile.dwell.letter().unwrap_or('P');
            let time = words.by_letter.remove(&letter);
            words.dwell = Some((g04, time));
            for w in [words.motion.map(|(_, w)| w), words.get('X'), words.get('Z')]
                .into_iter()
                .flatten()
            {
                tally.ok = false;
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
    }

    /// The words that belong to one motion mode: I, J and E to G33; I and K, or R, to arcs.
    fn thread_and_arc_words(&self, words: &mut Words<'_>) {
        // I, J and E mean something only in a G33 block; I, K and R in an arc block as the
        // profile's arc form says.
        let motion = words.motion.map_or(self.motion, |(m, _)| m);
        let arc_words: &[char] = match (motion, self.profile.arcs) {
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
                    'R' => R_WITHOUT_EQUALS.to_string(),
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
    }
}

/// Why G code `g` is not supported (by this profile or at all).
fn unsupported_g(g: i64) -> String {
    match g {
        4 => "G04 (a dwell, whose form the czech seed does not document: if the machine's manual gives it, set `dwell` in the profile's [czech] section)".into(),
        96 | 97 => format!("G{g} (surface speed, whose form the czech seed does not document: if the machine's manual gives G96/G97, set `surface_speed = \"g96-g97\"` in the profile's [czech] section)"),
        84 => "the G84 thread cycle (its parameters are not in the manual)".into(),
        2 | 3 => format!("G0{g} arcs (their form is not in the seed: if the machine's manual gives it, set `arcs` in the profile's [czech] section)"),
        _ => {
            let known = [
                "G00", "G01", "G02", "G03", "G33", "G90", "G91", "G94", "G95",
            ];
            let text = format!("G{g:02}");
            let hint = crate::dialect::read::did_you_mean(&text, &known);
            format!("G{g}{hint}")
        }
    }
}

//! A line's words sorted by what reads them: by letter, then the G and M codes by modal group
//! into what the block asks ([`Asks`]), after LinuxCNC's one-code-per-group check.

use super::super::gcode::*;
use super::super::syntax::{Block, Word};
use super::unsupported::{USER_M_FIRST, USER_M_LAST};
use super::{FrontEnd, Motion};
use crate::dialect::iso::codes;
use crate::dialect::{Letters, WORD_REPORTS, budget};
use crate::ir::{Coolant, FeedMode, SpindleDirection};
use crate::source::Line;

use super::unsupported::{Meaning, g_meaning};

/// The words of one line, sorted by what reads them.
pub(super) struct Words<'b> {
    /// G codes ×10 (`G33.1` → 331) with their words.
    pub(super) g: smallvec::SmallVec<[(GCode, &'b Word); 4]>,
    /// M codes with their words.
    pub(super) m: smallvec::SmallVec<[(i64, &'b Word); 4]>,
    /// Every other word by letter (each letter once).
    pub(super) other: Letters<&'b Word>,
    /// Letters a command has read.
    pub(super) used: smallvec::SmallVec<[char; 8]>,
}

impl<'b> Words<'b> {
    pub(super) fn new() -> Self {
        Words {
            g: smallvec::SmallVec::new(),
            m: smallvec::SmallVec::new(),
            other: Letters::default(),
            used: smallvec::SmallVec::new(),
        }
    }

    pub(super) fn take(&mut self, letter: char) -> Option<&'b Word> {
        let w = self.other.get(&letter).copied()?;
        self.used.push(letter);
        Some(w)
    }

    pub(super) fn has_g(&self, code: GCode) -> Option<&'b Word> {
        self.g.iter().find(|(c, _)| *c == code).map(|(_, w)| *w)
    }

    #[cfg(test)]
    pub(super) fn has_m(&self, code: i64) -> Option<&'b Word> {
        self.m.iter().find(|(c, _)| *c == code).map(|(_, w)| *w)
    }
}

/// The motion codes ncthread reads (LinuxCNC's modal group 1, less the tapping and boring
/// cycles, and G80: LinuxCNC lets G80 share a line with another of them, which wins).
pub(super) const MOTION: [GCode; 20] = [
    G0, G1, G2, G3, G33, G33_1, G76, G70, G71, G71_1, G71_2, G72, G72_1, G72_2, G73, G81, G82, G83,
    G85, G89,
];

/// LinuxCNC's G code groups (`read_g`): one code of each per line, even the same code twice.
const G_GROUPS: [(&str, &[GCode], &str); 13] = [
    ("motion", &MOTION, "one motion code per line"),
    ("units", &[G20, G21], "one of G20, G21 per line"),
    ("distance", &[G90, G91], "one of G90, G91 per line"),
    (
        "arc distance",
        &[G90_1, G91_1],
        "one of G90.1, G91.1 per line",
    ),
    ("spindle mode", &[G96, G97], "one of G96, G97 per line"),
    (
        "cutter compensation",
        &[G40, G41, G42, G41_1, G42_1],
        "one of G40, G41, G42, G41.1, G42.1 per line",
    ),
    (
        "work offset",
        &[G54, G55, G56, G57, G58, G59, G59_1, G59_2, G59_3],
        "one work offset (G54 … G59.3) per line",
    ),
    (
        "non-modal",
        &[G28, G28_1, G30, G30_1, G53, G52, G92, G92_1, G92_2, G92_3],
        "one of G28, G28.1, G30, G30.1, G52, G53, G92, G92.1, G92.2, G92.3 per line",
    ),
    ("feed mode", &[G94, G95], "one of G94, G95 per line"),
    ("diameter mode", &[G7, G8], "one of G7, G8 per line"),
    ("dwell", &[G4], "one G4 per line"),
    ("tool length", &[G43, G49], "one of G43, G49 per line"),
    ("retract mode", &[G98, G99], "one of G98, G99 per line"),
];

/// LinuxCNC's M code groups (`read_m`), one code of each per line.
const M_GROUPS: [(&str, &[i64], &str); 5] = [
    (
        "stopping",
        &[0, 1, 2, 30, 60],
        "one of M0, M1, M2, M30, M60 per line",
    ),
    ("tool change", &[6, 61], "one of M6, M61 per line"),
    ("spindle", &[3, 4, 5], "one of M3, M4, M5 per line"),
    (
        "coolant",
        &[7, 8, 9],
        "one of M7, M8, M9 per line (M7 and M8 on two lines)",
    ),
    ("user", &USER_CODES, "one of M100–M199 per line"),
];

/// The user M codes ([`USER_M_FIRST`] to [`USER_M_LAST`]), for [`M_GROUPS`].
const USER_CODES: [i64; (USER_M_LAST - USER_M_FIRST + 1) as usize] = {
    let mut codes = [0; (USER_M_LAST - USER_M_FIRST + 1) as usize];
    let mut i = 0;
    while i < codes.len() {
        codes[i] = USER_M_FIRST + i as i64;
        i += 1;
    }
    codes
};

/// What one block asks, one entry per modal group (LinuxCNC's `block_struct`): the group's
/// code on the line, with its word where a step reports at it. [`FrontEnd::sort_words`] has
/// refused a line with two codes of one group, so each group holds one code at most; the
/// plane (G17 and G18 may share a line, G18 winning) and the codes kept opaque are not a
/// group here.
#[cfg_attr(test, derive(Debug, PartialEq))]
pub(super) struct Asks<'b> {
    /// G94 / G95.
    pub(super) feed_mode: Option<FeedMode>,
    /// G20 (true) / G21 (false).
    pub(super) inch: Option<bool>,
    /// G96.
    pub(super) surface_speed: Option<&'b Word>,
    /// G97.
    pub(super) rpm: bool,
    /// M6.
    pub(super) tool_change: Option<&'b Word>,
    /// G43.
    pub(super) tool_length: bool,
    /// M3 / M4.
    pub(super) direction: Option<SpindleDirection>,
    /// M5.
    pub(super) spindle_stop: bool,
    /// M7 / M8 / M9.
    pub(super) coolant: Option<(Coolant, &'b Word)>,
    /// G4.
    pub(super) dwell: Option<&'b Word>,
    /// G7 (true) / G8 (false).
    pub(super) diameter: Option<bool>,
    /// The codes kept as opaque words (G49, G61, G61.1, G64), in the line's order.
    pub(super) kept: Vec<(GCode, &'b Word)>,
    /// G17.
    pub(super) plane_xy: Option<&'b Word>,
    /// G18.
    pub(super) plane_zx: bool,
    /// G40, G41, G42, G41.1, G42.1.
    pub(super) compensation: Option<(GCode, &'b Word)>,
    /// G54 … G59.3 as the work offset's number (1: G54).
    pub(super) work_offset: Option<(u8, &'b Word)>,
    /// G90 (false) / G91 (true).
    pub(super) incremental: Option<bool>,
    /// G90.1 (true) / G91.1 (false).
    pub(super) absolute_centres: Option<bool>,
    /// G98 / G99.
    pub(super) retract: Option<(GCode, &'b Word)>,
    /// The motion code, or G80 when the line has no other.
    pub(super) motion: Option<Motion>,
    /// G52, G92, G92.1, G92.2, G92.3.
    pub(super) offsets: Option<(GCode, &'b Word)>,
    /// G28, G28.1, G30, G30.1, G53.
    pub(super) machine: Option<(GCode, &'b Word)>,
    /// M0, M1, M2, M30.
    pub(super) stop: Option<(i64, &'b Word)>,
    /// M100–M199.
    pub(super) user: Option<(u32, &'b Word)>,
}

impl<'b> Asks<'b> {
    /// What the line's sorted words ask ([`Asks::fill`] of [`Asks::none`]).
    #[cfg(test)]
    pub(super) fn of(words: &Words<'b>) -> Self {
        let mut a = Asks::none();
        a.fill(words);
        a
    }

    /// A block that asks nothing.
    pub(super) fn none() -> Self {
        Asks {
            feed_mode: None,
            inch: None,
            surface_speed: None,
            rpm: false,
            tool_change: None,
            tool_length: false,
            direction: None,
            spindle_stop: false,
            coolant: None,
            dwell: None,
            diameter: None,
            kept: Vec::new(),
            plane_xy: None,
            plane_zx: false,
            compensation: None,
            work_offset: None,
            incremental: None,
            absolute_centres: None,
            retract: None,
            motion: None,
            offsets: None,
            machine: None,
            stop: None,
            user: None,
        }
    }

    /// Sorts the line's G and M codes by modal group into `self`, which asks nothing yet
    /// ([`Asks::none`]), in one pass over them: a group's code is the first of the line's
    /// codes in it, and of a pair (G94 / G95, …) the first named wins wherever it stands (the
    /// line has one code of a group at most, [`FrontEnd::sort_words`]). Filled where it
    /// stands: a block's asks and words were moved a few hundred bytes each, a line.
    pub(super) fn fill(&mut self, words: &Words<'b>) {
        fn first<T>(slot: &mut Option<T>, value: T) {
            if slot.is_none() {
                *slot = Some(value);
            }
        }
        let a = self;
        let mut cycle_off = false;
        for &(code, w) in &words.g {
            match code {
                // Of a pair, the first named wins wherever it stands.
                G94 => a.feed_mode = Some(FeedMode::PerMin),
                G95 => first(&mut a.feed_mode, FeedMode::PerRev),
                G20 => a.inch = Some(true),
                G21 => first(&mut a.inch, false),
                G7 => a.diameter = Some(true),
                G8 => first(&mut a.diameter, false),
                G91 => a.incremental = Some(true),
                G90 => first(&mut a.incremental, false),
                G90_1 => a.absolute_centres = Some(true),
                G91_1 => first(&mut a.absolute_centres, false),
                G96 => first(&mut a.surface_speed, w),
                G97 => a.rpm = true,
                G43 => a.tool_length = true,
                G4 => first(&mut a.dwell, w),
                G17 => first(&mut a.plane_xy, w),
                G18 => a.plane_zx = true,
                G40 | G41 | G42 | G41_1 | G42_1 => first(&mut a.compensation, (code, w)),
                G54 | G55 | G56 | G57 | G58 | G59 | G59_1 | G59_2 | G59_3 => {
                    first(&mut a.work_offset, (work_offset(code), w));
                }
                G98 | G99 => first(&mut a.retract, (code, w)),
                G52 | G92 | G92_1 | G92_2 | G92_3 => first(&mut a.offsets, (code, w)),
                G28 | G28_1 | G30 | G30_1 | G53 => first(&mut a.machine, (code, w)),
                G80 => cycle_off = true,
                _ => {}
            }
            if let Some(motion) = Self::motion_of(code) {
                first(&mut a.motion, motion);
            }
            if matches!(g_meaning(code), Meaning::Kept) {
                a.kept.push((code, w));
            }
        }
        if cycle_off {
            first(&mut a.motion, Motion::CycleOff);
        }
        for &(code, w) in &words.m {
            match code {
                3 => a.direction = Some(SpindleDirection::Clockwise),
                4 => first(&mut a.direction, SpindleDirection::CounterClockwise),
                5 => a.spindle_stop = true,
                6 => first(&mut a.tool_change, w),
                7 => first(&mut a.coolant, (Coolant::Mist, w)),
                8 => first(&mut a.coolant, (Coolant::Flood, w)),
                9 => first(&mut a.coolant, (Coolant::Off, w)),
                0 | 1 | 2 | 30 => first(&mut a.stop, (code, w)),
                USER_M_FIRST..=USER_M_LAST => {
                    if let Ok(c) = u32::try_from(code) {
                        first(&mut a.user, (c, w));
                    }
                }
                _ => {}
            }
        }
    }

    /// The motion a motion code asks for. G80 counts only when the line has no other: LinuxCNC
    /// ignores a G80 beside another motion code. **[evidence]** `read_g`.
    fn motion_of(code: GCode) -> Option<Motion> {
        Some(match code {
            G0 => Motion::Rapid,
            G1 => Motion::Feed,
            G2 => Motion::Arc { clockwise: true },
            G3 => Motion::Arc { clockwise: false },
            G33 => Motion::Thread,
            G33_1 => Motion::Tap,
            G76 => Motion::Cycle,
            G70 | G71 | G71_1 | G71_2 | G72 | G72_1 | G72_2 => Motion::Roughing(code),
            G73 | G81 | G82 | G83 | G85 | G89 => Motion::Drill(code),
            _ => return None,
        })
    }
}

/// The number of a work offset code (1: G54 … 9: G59.3).
fn work_offset(code: GCode) -> u8 {
    match code {
        G54 => 1,
        G55 => 2,
        G56 => 3,
        G57 => 4,
        G58 => 5,
        G59 => 6,
        G59_1 => 7,
        G59_2 => 8,
        _ => 9,
    }
}

impl FrontEnd<'_> {
    /// Sorts the line's words into `words` (empty): the G and M codes in the line's order,
    /// every other word by its letter. Reports a letter given twice and two codes of one
    /// modal group; false when the line has either (LinuxCNC refuses it).
    pub(super) fn sort_words<'b>(
        &mut self,
        line: Line<'_>,
        block: &'b Block,
        words: &mut Words<'b>,
    ) -> bool {
        let mut ok = self.sort_letters(line, block, words);
        ok &= self.one_code_per_group(line, words);
        ok
    }

    /// Each word into `words` by its letter; false when a letter is given twice.
    fn sort_letters<'b>(
        &mut self,
        line: Line<'_>,
        block: &'b Block,
        words: &mut Words<'b>,
    ) -> bool {
        let mut ok = true;
        let mut repeats = 0;
        for w in &block.words {
            match w.letter {
                // Checked by `unsupported` already.
                'G' => words.g.push((w.value.to_scaled(1).unwrap_or_default(), w)),
                'M' => words.m.push((w.value.to_whole().unwrap_or_default(), w)),
                letter => {
                    if words.other.contains_key(&letter) && !budget(&mut repeats) {
                        ok = false;
                    } else if let Some(first) = words.other.get(&letter) {
                        let first = line.text[first.range.clone()].to_string();
                        self.diag(
                            codes::ISOR_CONFLICT,
                            line,
                            w.range.clone(),
                            format!("a second {letter} word on the line (the first is `{first}`)"),
                            "LinuxCNC refuses a line with two words of one letter; split the line",
                        );
                        ok = false;
                    } else {
                        words.other.insert(letter, w);
                    }
                }
            }
        }
        if repeats > WORD_REPORTS {
            self.diag(
                codes::ISOR_CONFLICT,
                line,
                0..line.text.len(),
                format!("{} more repeated words on the line", repeats - WORD_REPORTS),
                "LinuxCNC refuses a line with two words of one letter; split the line",
            );
        }
        ok
    }

    /// One code of each modal group per line (LinuxCNC's `read_g` and `read_m`), even the
    /// same code twice; false when a group has two.
    fn one_code_per_group(&mut self, line: Line<'_>, words: &Words<'_>) -> bool {
        let mut ok = true;
        for (codes_on_line, groups) in [(&words.g, &G_GROUPS[..]), (&words.m, &M_GROUPS[..])] {
            if codes_on_line.len() < 2 {
                continue;
            }
            for &(name, members, help) in groups {
                let mut found = codes_on_line.iter().filter(|(c, _)| members.contains(c));
                if let (Some((_, a)), Some((_, b))) = (found.next(), found.next()) {
                    self.diag(
                        codes::ISOR_CONFLICT,
                        line,
                        b.range.clone(),
                        format!(
                            "`{}` and `{}` are both {name} codes",
                            &line.text[a.range.clone()],
                            &line.text[b.range.clone()]
                        ),
                        help,
                    );
                    ok = false;
                }
            }
        }
        ok
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `Asks::of` as it was, a look over the codes for each group.
    /// Sorts the line's G and M codes by modal group.
    fn of_by_groups<'b>(words: &Words<'b>) -> Asks<'b> {
        let g = |codes: &[GCode]| words.g.iter().find(|(c, _)| codes.contains(c)).copied();
        let either = |a: GCode, b: GCode| match (words.has_g(a), words.has_g(b)) {
            (Some(_), _) => Some(true),
            (None, Some(_)) => Some(false),
            (None, None) => None,
        };
        Asks {
            feed_mode: either(G94, G95).map(|min| {
                if min {
                    FeedMode::PerMin
                } else {
                    FeedMode::PerRev
                }
            }),
            inch: either(G20, G21),
            surface_speed: words.has_g(G96),
            rpm: words.has_g(G97).is_some(),
            tool_change: words.has_m(6),
            tool_length: words.has_g(G43).is_some(),
            direction: if words.has_m(3).is_some() {
                Some(SpindleDirection::Clockwise)
            } else if words.has_m(4).is_some() {
                Some(SpindleDirection::CounterClockwise)
            } else {
                None
            },
            spindle_stop: words.has_m(5).is_some(),
            coolant: words.m.iter().find_map(|&(code, w)| match code {
                7 => Some((Coolant::Mist, w)),
                8 => Some((Coolant::Flood, w)),
                9 => Some((Coolant::Off, w)),
                _ => None,
            }),
            dwell: words.has_g(G4),
            diameter: either(G7, G8),
            kept: words
                .g
                .iter()
                .filter(|(c, _)| matches!(g_meaning(*c), Meaning::Kept))
                .copied()
                .collect(),
            plane_xy: words.has_g(G17),
            plane_zx: words.has_g(G18).is_some(),
            compensation: g(&[G40, G41, G42, G41_1, G42_1]),
            work_offset: g(&[G54, G55, G56, G57, G58, G59, G59_1, G59_2, G59_3])
                .map(|(c, w)| (work_offset(c), w)),
            incremental: either(G91, G90),
            absolute_centres: either(G90_1, G91_1),
            retract: g(&[G98, G99]),
            motion: motion(words),
            offsets: g(&[G52, G92, G92_1, G92_2, G92_3]),
            machine: g(&[G28, G28_1, G30, G30_1, G53]),
            stop: words
                .m
                .iter()
                .find(|(c, _)| matches!(c, 0 | 1 | 2 | 30))
                .copied(),
            user: words
                .m
                .iter()
                .filter(|(c, _)| (USER_M_FIRST..=USER_M_LAST).contains(c))
                .find_map(|&(c, w)| Some((u32::try_from(c).ok()?, w))),
        }
    }

    /// The line's motion code; G80 only when the line has no other (LinuxCNC ignores a G80
    /// beside another motion code). **[evidence]** `read_g`.
    fn motion<'b>(words: &Words<'b>) -> Option<Motion> {
        let code = words.g.iter().find_map(|&(c, _)| match c {
            G0 => Some(Motion::Rapid),
            G1 => Some(Motion::Feed),
            G2 => Some(Motion::Arc { clockwise: true }),
            G3 => Some(Motion::Arc { clockwise: false }),
            G33 => Some(Motion::Thread),
            G33_1 => Some(Motion::Tap),
            G76 => Some(Motion::Cycle),
            G70 | G71 | G71_1 | G71_2 | G72 | G72_1 | G72_2 => Some(Motion::Roughing(c)),
            G73 | G81 | G82 | G83 | G85 | G89 => Some(Motion::Drill(c)),
            _ => None,
        });
        code.or(words.has_g(G80).map(|_| Motion::CycleOff))
    }

    #[test]
    fn a_block_asks_what_a_look_per_group_finds() {
        let mut codes: Vec<(char, i64)> = [
            G0, G1, G2, G3, G4, G7, G8, G17, G18, G20, G21, G28, G28_1, G30, G30_1, G33, G33_1,
            G40, G41, G42, G41_1, G42_1, G43, G49, G52, G53, G54, G55, G56, G57, G58, G59, G59_1,
            G59_2, G59_3, G61, G61_1, G64, G70, G71, G71_1, G71_2, G72, G72_1, G72_2, G73, G76,
            G80, G81, G82, G83, G85, G89, G90, G91, G90_1, G91_1, G92, G92_1, G92_2, G92_3, G94,
            G95, G96, G97, G98, G99,
        ]
        .into_iter()
        .map(|g| ('G', g))
        .collect();
        codes.extend([0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 30, 60, 61, 100, 150, 199].map(|m| ('M', m)));
        let word = |i: usize| Word {
            letter: 'G',
            value: crate::fixed::Decimal::default(),
            range: i..i + 1,
            expr: None,
        };
        let words: Vec<Word> = (0..3).map(word).collect();
        let n = codes.len();
        // Every code alone, every pair in both orders, and each pair with a third code from
        // across the list before, between and after it.
        let mut lines: Vec<Vec<(char, i64)>> = codes.iter().map(|&c| vec![c]).collect();
        for a in 0..n {
            for b in 0..n {
                lines.push(vec![codes[a], codes[b]]);
                for c in [0, n / 5, n / 3, n / 2, 2 * n / 3, n - 1] {
                    lines.push(vec![codes[c], codes[a], codes[b]]);
                    lines.push(vec![codes[a], codes[c], codes[b]]);
                    lines.push(vec![codes[a], codes[b], codes[c]]);
                }
            }
        }
        for line in &lines {
            let mut sorted = Words::new();
            for (i, &(letter, code)) in line.iter().enumerate() {
                match letter {
                    'G' => sorted.g.push((code, &words[i])),
                    _ => sorted.m.push((code, &words[i])),
                }
            }
            assert_eq!(Asks::of(&sorted), of_by_groups(&sorted), "{line:?}");
        }
        assert!(lines.len() > 100_000, "{}", lines.len());
    }
}

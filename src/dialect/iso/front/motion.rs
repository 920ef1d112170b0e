//! The motion modes: rapid, feed, and the dispatch to arcs, threads, taps and cycles.

use super::super::gcode::*;
use super::super::syntax::Word;
use super::words::MOTION;
use super::{FrontEnd, Motion, Words};
use crate::dialect::iso::codes;
use crate::fixed::Length;
use crate::ir::{FeedMode, ItemKind};
use crate::source::{Line, Span};

impl FrontEnd<'_> {
    pub(super) fn spindle_turning(&mut self, line: Line<'_>, w: Option<&Word>, what: &str) -> bool {
        if self.turning.is_some() {
            return true;
        }
        let range = w.map_or(0..line.text.len(), |w| w.range.clone());
        self.diag(
            codes::ISOR_SPINDLE,
            line,
            range,
            format!("{what} while the spindle is not turning"),
            "start the spindle with S and M3/M4 before the thread; LinuxCNC refuses this line too",
        );
        false
    }

    /// The line's move in the motion mode in force: the code's own reader, or LinuxCNC's
    /// refusal of the mode here (a synchronised move or G76 with compensation on; an arc or
    /// a roughing cycle in G17; axis words under G80).
    pub(super) fn motion(
        &mut self,
        line: Line<'_>,
        words: &mut Words<'_>,
        motion: Motion,
        span: Span,
    ) {
        let code_word = words
            .g
            .iter()
            .find(|(c, _)| MOTION.contains(c))
            .map(|(_, w)| *w);
        if !matches!(
            motion,
            Motion::Rapid | Motion::Feed | Motion::Arc { .. } | Motion::Drill(_) | Motion::CycleOff
        ) {
            // A move `convert_straight` makes, which allows an arc after G40 again.
            self.comp.straight_motion();
        }
        match motion {
            Motion::Thread | Motion::Tap if self.compensation => {
                let at = code_word.or(words.other.get(&'Z').copied());
                if let Some(at) = at {
                    self.comp_refusal(
                        line,
                        at,
                        "Bug code not g0 or g1 (a synchronised move with compensation on)",
                    );
                }
            }
            Motion::Rapid => self.rapid(line, words, code_word, span),
            Motion::Feed => self.feed_move(line, words, code_word, span),
            Motion::Arc { clockwise } if self.plane_xy => {
                let g = if clockwise { "G2" } else { "G3" };
                self.arc_error(
                    line,
                    code_word,
                    format!("{g} while G17 is in force: LinuxCNC cuts the arc in the XY plane, which a lathe has not"),
                    "select G18 before the arc (a lathe's arcs are in ZX)",
                );
            }
            Motion::Arc { clockwise } => self.arc(line, words, code_word, span, clockwise),
            Motion::Roughing(code) if self.plane_xy => {
                self.roughing_in_xy(line, words, code_word, code)
            }
            Motion::Thread => self.thread(line, words, code_word, span),
            Motion::Tap => self.tap(line, words, code_word, span),
            Motion::Cycle if self.compensation => {
                let at = code_word.or(words.other.get(&'Z').copied());
                if let Some(at) = at {
                    self.comp_refusal(
                        line,
                        at,
                        "Cannot use G76 threading cycle with cutter radius compensation on",
                    );
                }
            }
            Motion::Cycle => self.cycle(line, words, code_word, span),
            Motion::Roughing(code) => self.roughing(line, words, code_word, span, code),
            Motion::Drill(code) => self.drill(line, words, code_word, span, code),
            Motion::CycleOff => self.axes_after_g80(line, words),
        }
    }

    /// G0 to the line's target.
    fn rapid(
        &mut self,
        line: Line<'_>,
        words: &mut Words<'_>,
        code_word: Option<&Word>,
        span: Span,
    ) {
        let start = self.exact_start();
        let at = code_word.or(words.other.get(&'X').or(words.other.get(&'Z')).copied());
        if let Some(to) = self.target(line, words) {
            if !self.comp_straight(line, at, true, start, true) {
                return;
            }
            self.push(ItemKind::Rapid { to }, span);
            self.r.pos = ItemKind::Rapid { to }.end_position(self.r.pos);
            self.exact_after_move(start);
        }
    }

    /// G1 to the line's target at the feed in force.
    fn feed_move(
        &mut self,
        line: Line<'_>,
        words: &mut Words<'_>,
        code_word: Option<&Word>,
        span: Span,
    ) {
        let start = self.exact_start();
        let axis = words.other.get(&'X').or(words.other.get(&'Z')).copied();
        let Some(to) = self.target(line, words) else {
            return;
        };
        let Some(feed) = self.feed_rate(line, code_word.or(axis), "G1", span) else {
            return;
        };
        if !self.comp_straight(line, code_word.or(axis), false, start, true) {
            return;
        }
        self.push(ItemKind::Feed { to, feed }, span);
        self.r.pos = ItemKind::Feed { to, feed }.end_position(self.r.pos);
        self.exact_after_move(start);
    }

    /// A roughing cycle in G17, which LinuxCNC refuses.
    fn roughing_in_xy(
        &mut self,
        line: Line<'_>,
        words: &Words<'_>,
        code_word: Option<&Word>,
        code: GCode,
    ) {
        let name = crate::ir::g_code_name(code);
        let at = code_word.or(words.other.get(&'Q').copied());
        if let Some(at) = at {
            self.diag(
                codes::ISOR_ROUGHING,
                line,
                at.range.clone(),
                format!("{name} while G17 is in force (LinuxCNC: \"G{}.{} can only be used in XZ plane (G18)\")", code / 10, code % 10),
                "select G18 before the cycle",
            );
        }
    }

    /// Axis words after G80, or on its line. **[evidence]** `enhance_block`.
    fn axes_after_g80(&mut self, line: Line<'_>, words: &mut Words<'_>) {
        let w = words.other.get(&'X').or(words.other.get(&'Z')).copied();
        words.take('X');
        words.take('Z');
        if let Some(w) = w {
            let (message, help) = if words.has_g(G80).is_some() {
                (
                    "an axis word on a G80 line (LinuxCNC: \"Cannot use axis values with g80\")",
                    "put the move on a line of its own, with its motion code",
                )
            } else {
                (
                    "an axis word after G80, which leaves no motion mode in force (LinuxCNC: \"Cannot use axis values without a g code that uses them\")",
                    "write the motion code: `G0 X20 Z5`",
                )
            };
            self.missing(line, w, message.into(), help);
        }
    }

    /// The feed rate a feed move (`code`: G1, G2, G3) uses, or `None` after reporting at `at`
    /// that none is set. The first feed move of a program that never chose a feed mode
    /// writes out LinuxCNC's start-up mode (G94) for targets that differ.
    pub(super) fn feed_rate(
        &mut self,
        line: Line<'_>,
        at: Option<&Word>,
        code: &str,
        span: Span,
    ) -> Option<Length> {
        let feed = match self.feed {
            Some(f) if f.0 > 0 => f,
            _ => {
                if let Some(at) = at {
                    self.missing(
                        line,
                        at,
                        format!("{code} with no feed rate (F) set, or F0"),
                        "set the feed with F before or on this line",
                    );
                }
                return None;
            }
        };
        if let Some(why) = self.feed_in_other_units(code) {
            if let Some(at) = at {
                self.missing(line, at, why, FEED_AGAIN);
            }
            return None;
        }
        if self.feed_mode.is_none() {
            self.feed_mode = Some(FeedMode::PerMin);
            self.push(ItemKind::FeedMode(FeedMode::PerMin), span);
        }
        Some(feed)
    }

    /// Why a feed move (`code`) cannot use the feed rate in force: it was given in the other
    /// units, before a G20/G21. LinuxCNC's machine and its standalone interpreter go on at
    /// different feeds then: the task canon converts a feed per minute into the new units
    /// (`GET_EXTERNAL_FEED_RATE` in emccanon.cc), rs274 keeps the number (saicanon.cc), so no
    /// conversion can say which the program meant.
    pub(super) fn feed_in_other_units(&self, code: &str) -> Option<String> {
        (self.feed.is_some() && self.feed_inch != self.inch).then(|| {
            let (was, change) = if self.feed_inch {
                ("inches", "G21")
            } else {
                ("mm", "G20")
            };
            format!(
                "{code} under a feed rate (F) given in {was} before the {change}: LinuxCNC's standalone interpreter keeps F's number in the new units, a LinuxCNC machine feeding per minute keeps its speed, so the feed is not known"
            )
        })
    }
}

/// The help of a feed move under a feed rate given in the other units.
pub(super) const FEED_AGAIN: &str = "give F again after a G20/G21 that changes the units";

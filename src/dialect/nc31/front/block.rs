//! The block interpreter of a group without a G word, shaped as LinuxCNC's
//! `interp_convert.cc`: the group's words are first sorted by modal group into a
//! [`PlainWords`] (reporting the words that do not belong and the repeats, in the frames'
//! order), their values then read into a [`PlainBlock`] (reporting bad values, and a feed
//! move without a feed), and the block then runs as one step per modal group, in one order:
//!
//! | step | group | words |
//! |------|-------|-------|
//! | [`FrontEnd::tool_step`] | tool | T |
//! | [`FrontEnd::gear_step`] | spindle speed range | the profile's M codes (M38 … M41) |
//! | [`Switches::before_motion`] | spindle speed and direction, coolant on | S, M3 / M4, M8 |
//! | [`FrontEnd::motion_step`] | motion | X, Z (rapid when either has `~`) |
//! | [`Switches::coolant_off`] | coolant off | M9 |
//! | [`FrontEnd::unused_feed_step`] | feed | F that no move of the group uses |
//! | [`Switches::spindle_stop`] | spindle stop | M5 |
//! | [`Switches::program_end`] | stopping | M30 |
//!
//! LinuxCNC sets the feed first; so does this reader (the F of a group sets the feed
//! register before the group's move, which is then cut at it), but a feed that no move of
//! the group uses stays an item where the control shows it, after the motion. The НЦ-31 has
//! no feed mode, speed mode, dwell, plane, units, compensation, tool length, coordinate
//! systems, distance mode or homing: `@` (incremental) and `~` (rapid) are marks on the
//! coordinates, read with them. Coolant goes on before the group's motion and off after it,
//! as the spindle does **\[decided\]**: the steps of [`crate::dialect::machine`] that all
//! front ends share, in the order of the controls that switch off after the motion.

use super::super::syntax::Modifier;
use super::{Feed, FrontEnd, GroupFrame};
use crate::dialect::machine::Switches;
use crate::dialect::nc31::codes;
use crate::fixed::Length;
use crate::ir::{Coolant, EndCode, ItemKind, Pos, SpindleDirection};
use crate::source::Span;

/// What a group without a G word asks, sorted by modal group: the frame of each word.
#[derive(Default)]
struct PlainWords<'g> {
    /// Motion: the X frame.
    x: Option<&'g GroupFrame>,
    /// Motion: the Z frame.
    z: Option<&'g GroupFrame>,
    /// Feed: the F frame.
    f: Option<&'g GroupFrame>,
    /// Spindle speed: the S frame.
    s: Option<&'g GroupFrame>,
    /// Tool: the T frame.
    t: Option<&'g GroupFrame>,
    /// Spindle direction: M3 / M4 (the last one written) and its frame.
    direction: Option<(SpindleDirection, &'g GroupFrame)>,
    /// Spindle stop: the first M5 frame.
    stop: Option<&'g GroupFrame>,
    /// Program end: M30.
    end: bool,
    /// Spindle speed ranges: the profile's M codes, in the group's order.
    gears: Vec<u32>,
    /// Coolant: M8 / M9, in the group's order.
    coolant: Vec<Coolant>,
}

/// A group without a G word, its values read: what its steps do.
struct PlainBlock {
    /// T: the turret position.
    tool: Option<u32>,
    /// The speed range M codes.
    gears: Vec<u32>,
    /// S, M3 / M4, M8 / M9, M5, M30: the switching steps all front ends share.
    switches: Switches,
    /// The group's move: a rapid, or a feed move at the feed.
    motion: Option<ItemKind>,
    /// The group's F when no move of the group uses it.
    unused_feed: Option<Length>,
}

impl FrontEnd<'_> {
    /// A group without a G word: its words sorted, their values read, then one step per
    /// modal group in the order of the module's table. A group with an error adds no item.
    pub(super) fn plain_group(&mut self, frames: &[GroupFrame], span: Span) {
        let Some(block) = self.plain_block(frames, span) else {
            return;
        };
        self.tool_step(block.tool, span);
        self.gear_step(&block.gears, span);
        block.switches.before_motion(&mut self.r, None);
        self.motion_step(block.motion, span);
        block.switches.coolant_off(&mut self.r, None);
        self.unused_feed_step(block.unused_feed, span);
        block.switches.spindle_stop(&mut self.r, None);
        block.switches.program_end(&mut self.r, None);
    }

    /// Sorts the group's words into [`PlainWords`], reporting (frame by frame) marks a word
    /// does not take, repeated words and P outside G31. Returns whether all is well.
    fn plain_words<'g>(&mut self, frames: &'g [GroupFrame], words: &mut PlainWords<'g>) -> bool {
        let mut ok = true;
        for fr in frames {
            let w = fr.word();
            let axis = matches!(w.letter, 'X' | 'Z');
            ok &= self.check_modifiers(fr, axis, axis, false);
            let slot = match w.letter {
                'X' => Some(&mut words.x),
                'Z' => Some(&mut words.z),
                'F' => Some(&mut words.f),
                'S' => Some(&mut words.s),
                'T' => Some(&mut words.t),
                _ => None,
            };
            if let Some(slot) = slot {
                if let Some(first) = *slot {
                    self.repeated(fr, first);
                    ok = false;
                } else {
                    *slot = Some(fr);
                }
                continue;
            }
            match (w.letter, w.value) {
                ('M', 3 | 4) => {
                    let d = if w.value == 3 {
                        SpindleDirection::Clockwise
                    } else {
                        SpindleDirection::CounterClockwise
                    };
                    if let Some((_, first)) = words.direction {
                        self.repeated(fr, first);
                        ok = false;
                    }
                    words.direction = Some((d, fr));
                }
                ('M', 5) => {
                    words.stop.get_or_insert(fr);
                }
                ('M', 30) => words.end = true,
                ('M', 8) => words.coolant.push(Coolant::Flood),
                ('M', 9) => words.coolant.push(Coolant::Off),
                ('M', m) => words.gears.extend(u32::try_from(m).ok()),
                _ => {
                    // P outside G31.
                    self.word_error(
                        codes::NCR_GROUP_WORD,
                        fr,
                        format!("`{}` outside a G31 group", fr.text(self.r.src)),
                        "P words give the depths of a G31 cycle: `G31 *`, X, Z, F, then P (depth), P (first pass), optional P (taper)",
                    );
                    ok = false;
                }
            }
        }
        ok
    }

    /// Reads the sorted words' values: M5 beside a spindle start, F, S, T, X, Z, then the
    /// feed a feed move needs. F sets the feed register even when the group has an error.
    /// `None` when the group has an error.
    fn plain_block(&mut self, frames: &[GroupFrame], span: Span) -> Option<PlainBlock> {
        let mut words = PlainWords::default();
        let mut ok = self.plain_words(frames, &mut words);
        if let (Some(_), Some(fr)) = (words.direction, words.stop) {
            self.word_error(
                codes::NCR_GROUP_WORD,
                fr,
                "M5 in the same group as a spindle start",
                "start and stop the spindle in different groups",
            );
            ok = false;
        }
        let feed = words.f.and_then(|fr| self.feed_rate(fr));
        ok &= words.f.is_none() || feed.is_some();
        let speed = words.s.and_then(|fr| self.whole(fr));
        let tool = words.t.and_then(|fr| self.whole(fr));
        ok &= words.s.is_none() || speed.is_some();
        ok &= words.t.is_none() || tool.is_some();
        let to_x = words.x.map(|fr| self.coordinate(fr, self.r.pos.x));
        let to_z = words.z.map(|fr| self.coordinate(fr, self.r.pos.z));
        if matches!(to_x, Some(None)) || matches!(to_z, Some(None)) {
            ok = false;
        }
        if let Some(feed) = feed {
            self.feed = Feed::Set(feed);
        }
        let moves = words.x.is_some() || words.z.is_some();
        let rapid = [words.x, words.z]
            .into_iter()
            .flatten()
            .any(|fr| fr.frame.has(Modifier::Rapid));
        ok &= self.feed_for_move(&words, moves && !rapid);
        if !ok {
            return None;
        }
        let to = Pos {
            x: to_x.flatten(),
            z: to_z.flatten(),
        };
        let motion = match (rapid, self.feed) {
            (false, Feed::Set(feed)) => ItemKind::Feed { to, feed },
            _ => ItemKind::Rapid { to },
        };
        let switches = Switches {
            spindle_mode: None,
            spindle: Some((speed, words.direction.map(|(d, _)| d), span)),
            coolant: words.coolant.iter().map(|&c| (c, span)).collect(),
            spindle_stop: words.stop.map(|_| span),
            end: words.end.then_some((EndCode::M30, span)),
        };
        Some(PlainBlock {
            tool,
            gears: words.gears,
            switches,
            motion: moves.then_some(motion),
            unused_feed: feed.filter(|_| !moves || rapid),
        })
    }

    /// Reports a feed move (`feeds`) when no feed is set. Returns whether all is well.
    fn feed_for_move(&mut self, words: &PlainWords, feeds: bool) -> bool {
        if !feeds || matches!(self.feed, Feed::Set(_)) {
            return true;
        }
        let fr = words.x.or(words.z).expect("the group moves");
        let why = self.why_no_feed();
        self.word_error(
            codes::NCR_NO_FEED,
            fr,
            format!("feed move `{}` but {why}", fr.text(self.r.src)),
            "program the feed in a frame of its own (e.g. `F60` = 0.6 mm/rev) before this move, or mark the move rapid with `~`",
        );
        false
    }

    /// The tool step (T): the turret turns to the tool before the group's motion.
    fn tool_step(&mut self, tool: Option<u32>, span: Span) {
        if let Some(number) = tool {
            self.push(
                ItemKind::Tool {
                    number: Some(number),
                    offset: None,
                },
                span,
                None,
            );
        }
    }

    /// The speed range step (the profile's M codes), in the group's order, before the
    /// spindle's speed.
    fn gear_step(&mut self, gears: &[u32], span: Span) {
        for &g in gears {
            self.push(
                ItemKind::GearRange {
                    code: g,
                    machine: super::super::ID,
                },
                span,
                None,
            );
        }
    }

    /// The motion step (X, Z): the group's move, both axes at once, from where the tool
    /// stands.
    fn motion_step(&mut self, motion: Option<ItemKind>, span: Span) {
        if let Some(kind) = motion {
            self.r.pos = kind.end_position(self.r.pos);
            self.push(kind, span, None);
        }
    }

    /// The feed step (F) of a group whose F no move uses: the feed stays an item where it is
    /// written, after the motion and coolant off. (A feed move's F is in its item.)
    fn unused_feed_step(&mut self, feed: Option<Length>, span: Span) {
        if let Some(feed) = feed {
            self.push(ItemKind::FeedRate(feed), span, None);
        }
    }
}

//! Thread groups: G31 (the multi-pass cycle), G32 (one pass), G33 (tapping).

use super::super::syntax::Modifier;
use super::{Feed, FrontEnd, GroupFrame};
use crate::dialect::nc31::codes;
use crate::fixed::{Angle, Lead, Length};
use crate::ir::{
    CycleChamfer, Finish, ItemKind, Pos, Retract, Rise, SyncStart, TapCycle, ThreadCycle,
    ThreadPass,
};
use crate::lower::{self, ExpandError};
use crate::source::Span;

/// What a thread group's words are, by letter.
#[derive(Default)]
pub(super) struct ThreadWords<'g> {
    pub(super) x: Option<&'g GroupFrame>,
    pub(super) z: Option<&'g GroupFrame>,
    pub(super) f: Option<&'g GroupFrame>,
    pub(super) p: Vec<&'g GroupFrame>,
}

const G31_ABOUT: &str = "G31 takes X (thread diameter), Z (end), F (lead), P (thread depth per side), P (first-pass depth) and an optional P (taper on diameter)";

impl FrontEnd<'_> {
    /// Sorts a thread group's words; reports words that do not belong and repeats.
    pub(super) fn thread_words<'g>(
        &mut self,
        frames: &'g [GroupFrame],
        allowed: &[char],
        max_p: usize,
        about: &str,
    ) -> Option<ThreadWords<'g>> {
        let mut words = ThreadWords::default();
        let mut ok = true;
        let g = &frames[0];
        let g33 = g.word().value == 33;
        ok &= self.check_modifiers(g, false, g33, false);
        for fr in &frames[1..] {
            let letter = fr.word().letter;
            let coordinate = matches!(letter, 'X' | 'Z');
            ok &= self.check_modifiers(fr, false, coordinate, false);
            if !allowed.contains(&letter) {
                let help = if g.word().value == 32 && letter == 'X' {
                    "G32 cuts along Z at the current diameter; move to the pass diameter in a group before `G32 *`".to_string()
                } else {
                    format!("{about}; other words go in groups of their own")
                };
                self.word_error(
                    codes::NCR_GROUP_WORD,
                    fr,
                    format!(
                        "`{}` does not belong in a {} group",
                        fr.text(self.r.src),
                        g.text(self.r.src)
                    ),
                    help,
                );
                ok = false;
                continue;
            }
            let slot = match letter {
                'X' => &mut words.x,
                'Z' => &mut words.z,
                'F' => &mut words.f,
                _ => {
                    if words.p.len() == max_p {
                        self.word_error(
                            codes::NCR_GROUP_WORD,
                            fr,
                            format!("`{}` is a P word too many", fr.text(self.r.src)),
                            "G31 takes P (thread depth), P (first-pass depth) and an optional third P (taper)",
                        );
                        ok = false;
                    } else {
                        words.p.push(fr);
                    }
                    continue;
                }
            };
            if let Some(first) = *slot {
                self.repeated(fr, first);
                ok = false;
            } else {
                *slot = Some(fr);
            }
        }
        ok.then_some(words)
    }

    pub(super) fn missing(&mut self, g: &GroupFrame, missing: &[&str], about: &str) -> bool {
        if missing.is_empty() {
            return false;
        }
        self.word_error(
            codes::NCR_MISSING_WORD,
            g,
            format!(
                "the {} group has no {}",
                g.text(self.r.src),
                missing.join(", no ")
            ),
            about.to_string(),
        );
        true
    }

    pub(super) fn lead(&mut self, f: &GroupFrame) -> Option<Lead> {
        let lead = self.scaled(f, self.profile.lead_unit)?;
        if lead.0 <= 0 {
            self.word_error(
                codes::NCR_LEAD,
                f,
                format!("lead `{}` is not positive", f.text(self.r.src)),
                "F in a thread group is the lead in 0.0001 mm: F15000 = 1.5 mm",
            );
            return None;
        }
        let lead = Lead::from_length(lead);
        if lead > Lead::MAX {
            self.word_error(
                codes::NCR_NUMBER,
                f,
                format!("`{}` is too large for a lead", f.text(self.r.src)),
                "a lead is at most 1,000,000 mm",
            );
            return None;
        }
        Some(lead)
    }

    pub(super) fn start_unknown(&mut self, g: &GroupFrame, what: &str) {
        self.word_error(
            codes::NCR_UNKNOWN_POSITION,
            g,
            format!("{} starts from the tool position, and the {what} is not known", g.text(self.r.src)),
            "move to the start point with X and Z (e.g. `X3600 ~ *` then `Z450 ~`) before the cycle",
        );
    }

    /// `G31 *` X Z F P P [P]: the multi-pass cycle, from where the tool stands.
    pub(super) fn g31(&mut self, frames: &[GroupFrame], span: Span) {
        let g = &frames[0];
        let Some(w) = self.g31_words(frames) else {
            return;
        };
        let Some(start) = self.r.pos.known() else {
            self.start_unknown(g, "start point");
            return;
        };
        let Some(cycle) = self.g31_cycle(&w, start) else {
            return;
        };
        if let Err(e) = lower::check(&cycle) {
            return self.g31_refused(e, &cycle, &w);
        }
        self.push(ItemKind::ThreadCycle(Box::new(cycle)), span, None);
        self.r.pos = Pos::new(start.0, start.1);
        self.feed = Feed::AfterThread(g.place.number);
    }

    /// A G31 group's words, sorted; reports those that do not belong and those missing.
    /// `Some` only with X, Z, F and at least two P.
    fn g31_words<'g>(&mut self, frames: &'g [GroupFrame]) -> Option<ThreadWords<'g>> {
        let g = &frames[0];
        let w = self.thread_words(frames, &['X', 'Z', 'F', 'P'], 3, G31_ABOUT)?;
        let mut missing = Vec::new();
        for (present, name) in [
            (w.x.is_some(), "X (thread diameter)"),
            (w.z.is_some(), "Z (end)"),
            (w.f.is_some(), "F (lead)"),
            (!w.p.is_empty(), "P (thread depth)"),
            (w.p.len() >= 2, "P (first-pass depth)"),
        ] {
            if !present {
                missing.push(name);
            }
        }
        if self.missing(g, &missing, G31_ABOUT) {
            return None;
        }
        Some(w)
    }

    /// The G31 cycle from `start` (X, Z): its words' values, checked.
    fn g31_cycle(&mut self, w: &ThreadWords, (ax, az): (Length, Length)) -> Option<ThreadCycle> {
        let (Some(xf), Some(zf), Some(ff)) = (w.x, w.z, w.f) else {
            return None;
        };
        let unit = self.profile.linear_unit;
        let crest = self.coordinate(xf, Some(ax));
        let end_z = self.coordinate(zf, Some(az));
        let lead = self.lead(ff);
        let depth = self.scaled(w.p[0], unit);
        let first = self.scaled(w.p[1], unit);
        let taper = match w.p.get(2) {
            Some(pf) => self.scaled(pf, unit),
            None => Some(Length::ZERO),
        };
        let (Some(crest), Some(end_z), Some(lead), Some(depth), Some(first), Some(taper)) =
            (crest, end_z, lead, depth, first, taper)
        else {
            return None;
        };
        if crest.0 <= 0 {
            self.word_error(
                codes::NCR_NUMBER,
                xf,
                format!("thread diameter `{}` is not positive", xf.text(self.r.src)),
                "X in G31 is the thread's crest diameter in 0.01 mm (X3600 = Ø36)",
            );
            return None;
        }
        if taper.0 < 0 {
            self.word_error(
                codes::NCR_DEPTHS,
                w.p[2],
                format!("taper `{}` is negative", w.p[2].text(self.r.src)),
                "the third P is the difference of the larger and the smaller diameter; X is the smaller one at the start",
            );
            return None;
        }
        Some(ThreadCycle {
            start: (ax, az),
            crest,
            end_z,
            lead,
            depth,
            first_depth: first,
            taper,
            infeed: self.profile.infeed(),
            infeed_moves_end: false,
            start_angle: Angle::ZERO,
            entry: None,
            entry_infeed: false,
            runout: Some(self.profile.runout(lead))
                .filter(|r| r.0 > 0)
                .map(|length| CycleChamfer {
                    length,
                    rise: Rise::ToCrest,
                }),
            retract: Retract::AboveCrest(self.profile.retract),
            spring_passes: 0,
            finish: Finish::Start,
            internal: ax < crest,
            schedule: self.profile.schedule,
        })
    }

    /// Reports why the G31 `cycle` cannot be expanded, at the word that decides it.
    fn g31_refused(&mut self, e: ExpandError, cycle: &ThreadCycle, w: &ThreadWords) {
        let (Some(zf), Some(ff)) = (w.z, w.f) else {
            return;
        };
        let (code, frame, help) = match e {
            ExpandError::Lead => (codes::NCR_LEAD, ff, "the lead must be positive".to_string()),
            ExpandError::NoTravel => (
                codes::NCR_TRAVEL,
                zf,
                "Z is where every pass ends; it must differ from the start Z".to_string(),
            ),
            ExpandError::FirstDepth | ExpandError::TooManyPasses => (
                codes::NCR_DEPTHS,
                w.p[1],
                "the second P is the first pass's depth per side in 0.01 mm (P20 = 0.2 mm)".to_string(),
            ),
            ExpandError::DepthTooSmall { .. } => (
                codes::NCR_DEPTHS,
                w.p[0],
                format!(
                    "with the {} schedule the thread depth (first P) must be at least the first-pass depth (second P){}",
                    cycle.schedule.id(),
                    if cycle.schedule == crate::ir::Schedule::Halving {
                        " plus the four halving passes P/2 + P/4 + P/8 + P/16"
                    } else {
                        ""
                    }
                ),
            ),
            ExpandError::ShortPass { .. } => (
                codes::NCR_TRAVEL,
                zf,
                "the runout (machine parameter 7) and the infeed shift (parameter 6) must fit inside the pass; move the start point further out or shorten the runout".to_string(),
            ),
        };
        let message = e.message(cycle);
        self.word_error(code, frame, message, help);
    }

    /// `G32 *` F Z: one synchronised pass along Z at the current diameter.
    pub(super) fn g32(&mut self, frames: &[GroupFrame], span: Span) {
        const ABOUT: &str = "G32 takes F (lead) and Z (end)";
        let g = &frames[0];
        let Some(w) = self.thread_words(frames, &['Z', 'F'], 0, ABOUT) else {
            return;
        };
        let mut missing = Vec::new();
        if w.f.is_none() {
            missing.push("F (lead)");
        }
        if w.z.is_none() {
            missing.push("Z (end)");
        }
        if self.missing(g, &missing, ABOUT) {
            return;
        }
        let (Some(zf), Some(ff)) = (w.z, w.f) else {
            return;
        };
        let lead = self.lead(ff);
        let end_z = self.coordinate(zf, self.r.pos.z);
        let (Some(lead), Some(end_z)) = (lead, end_z) else {
            return;
        };
        if self.r.pos.z == Some(end_z) {
            self.word_error(
                codes::NCR_TRAVEL,
                zf,
                format!("the pass ends at Z{} where it starts", end_z.mm()),
                "Z is the end of the pass; it must differ from the current Z",
            );
            return;
        }
        let pass = ThreadPass {
            to: Pos {
                x: self.r.pos.x,
                z: Some(end_z),
            },
            lead,
            // G32 starts from the index pulse. **[seed]**
            start: SyncStart::Index(Angle::ZERO),
            infeed: None,
            entry: None,
            exit: None,
        };
        let kind = ItemKind::pass(pass);
        self.r.pos = kind.end_position(self.r.pos);
        self.push(kind, span, None);
        self.feed = Feed::AfterThread(g.place.number);
    }

    /// `G33 [@] *` X Z F: tapping; with `@` the tool then moves to X (point C).
    pub(super) fn g33(&mut self, frames: &[GroupFrame], span: Span) {
        const ABOUT: &str = "G33 takes X (point C, with `@` on G33), Z (end) and F (lead)";
        let g = &frames[0];
        let offset = g.frame.has(Modifier::Incremental);
        let Some(w) = self.thread_words(frames, &['X', 'Z', 'F'], 0, ABOUT) else {
            return;
        };
        let mut missing = Vec::new();
        if offset && w.x.is_none() {
            missing.push("X (point C after `@`)");
        }
        if w.z.is_none() {
            missing.push("Z (end)");
        }
        if w.f.is_none() {
            missing.push("F (lead)");
        }
        if self.missing(g, &missing, ABOUT) {
            return;
        }
        let (Some(zf), Some(ff)) = (w.z, w.f) else {
            return;
        };
        let Some(start_z) = self.r.pos.z else {
            self.start_unknown(g, "Z position");
            return;
        };
        let lead = self.lead(ff);
        let end_z = self.coordinate(zf, Some(start_z));
        let x = match w.x {
            Some(xf) => match self.coordinate(xf, self.r.pos.x) {
                Some(x) => Some((x, xf)),
                None => return,
            },
            None => None,
        };
        let (Some(lead), Some(end_z)) = (lead, end_z) else {
            return;
        };
        if end_z == start_z {
            self.word_error(
                codes::NCR_TRAVEL,
                zf,
                format!("the tap ends at Z{} where it starts", end_z.mm()),
                "Z is the bottom of the tapped hole; it must differ from the start Z",
            );
            return;
        }
        let then_x = match x {
            Some((x, _)) if offset => Some(x),
            Some((x, xf)) if self.r.pos.x != Some(x) => {
                let current = self
                    .r
                    .pos
                    .x
                    .map_or("not known".to_string(), |c| format!("Ø{}", c.mm()));
                self.word_error(
                    codes::NCR_GROUP_WORD,
                    xf,
                    format!("`{}` in a G33 group without `@`, but the tool stands at {current}", xf.text(self.r.src)),
                    "without `@` on G33 the tap does not move in X; write `G33 @ *` to move to X (point C) after the cycle",
                );
                return;
            }
            _ => None,
        };
        let kind = ItemKind::TapCycle(TapCycle {
            end_z,
            lead,
            then_x,
        });
        self.r.pos = kind.end_position(self.r.pos);
        self.push(kind, span, None);
        self.feed = Feed::AfterThread(g.place.number);
    }
}

//! The words the guide documents, and the policy for the others.

use super::super::syntax::Word;
use super::{FrontEnd, GroupFrame, UNSUPPORTED};
use crate::dialect::Unsupported;
use crate::dialect::nc31::codes;
use crate::ir::ModalContext;

impl FrontEnd<'_> {
    /// Reports words the guide does not document; with `--unsupported warn` the group is kept
    /// as one opaque item. Returns whether the group can be read.
    pub(super) fn check_supported(&mut self, frames: &[GroupFrame]) -> bool {
        if self.g25_refused(frames) {
            return false;
        }
        let mut found = Vec::new();
        for f in frames {
            if let Some(reason) = self.unsupported_reason(f.word()) {
                found.push((f, reason));
            }
        }
        if found.is_empty() {
            return true;
        }
        self.report_unsupported(frames, found);
        false
    }

    /// G25 without the profile's key, reported. Returns whether the group has one.
    fn g25_refused(&mut self, frames: &[GroupFrame]) -> bool {
        // G25 without the profile's key: never kept as written, since it repeats frames by
        // their numbers and an output numbers its frames anew.
        if !self.profile.repeat_g25
            && let Some(f) = frames
                .iter()
                .find(|f| f.word().letter == 'G' && f.word().value == 25)
        {
            self.word_error(
                codes::NCR_UNSUPPORTED,
                f,
                format!(
                    "`{}`: G25 (a repeat of frames) is not in the guide",
                    f.text(self.r.src)
                ),
                "if the machine repeats frames with `G25 *`, `P<from><to> *`, `P<count>`, set `repeat_g25 = true` in the profile's [nc31] section (ncthread then writes the repeated frames out); `--unsupported warn` cannot keep it as written, since the output numbers its frames anew",
            );
            return true;
        }
        false
    }

    /// Why the guide does not document `w`, or `None` when it does.
    fn unsupported_reason(&self, w: &Word) -> Option<String> {
        match w.letter {
            'X' | 'Z' | 'F' | 'P' | 'S' | 'T' => None,
            'G' if matches!(w.value, 31..=33) => None,
            'G' if matches!(w.value, 2 | 3 | 12 | 13) && self.profile.arcs => None,
            'G' if w.value == 25 && self.profile.repeat_g25 => None,
            // Refused below, also under `--unsupported warn`.
            'G' if w.value == 25 => None,
            'G' if matches!(w.value, 2 | 3 | 12 | 13) => Some(format!(
                "G{} (an arc) is not in the guide: if the machine takes G2/G3 groups with P offsets, set `arcs = \"g2-g3-p\"` and `arc_direction` in the profile's [nc31] section",
                w.value
            )),
            'G' => Some(format!(
                "G{} is not among the documented G words (G31, G32, G33)",
                w.value
            )),
            'M' if matches!(w.value, 3 | 4 | 5 | 30)
                || (self.profile.coolant && matches!(w.value, 8 | 9))
                || u32::try_from(w.value)
                    .is_ok_and(|m| self.profile.gear_range_mcodes.contains(&m)) =>
            {
                None
            }
            'M' if matches!(w.value, 8 | 9) => Some(format!(
                "M{} (coolant) is not in the guide: if the machine takes M8/M9, set `coolant = \"m8-m9\"` in the profile's [nc31] section",
                w.value
            )),
            'M' => Some(format!(
                "M{} is not among the documented M words (M3, M4, M5, M30, speed ranges {})",
                w.value,
                self.profile
                    .gear_range_mcodes
                    .iter()
                    .map(|m| format!("M{m}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            )),
            other => Some(format!("address {other} is not documented for the НЦ-31")),
        }
    }

    /// Reports the group's undocumented words (`found`, each with its reason): an error, or
    /// with `--unsupported warn` a warning and the group kept as one opaque item, unless it
    /// holds a word that changes what ncthread follows.
    fn report_unsupported(&mut self, frames: &[GroupFrame], found: Vec<(&GroupFrame, String)>) {
        let keep = self.options.unsupported == Unsupported::Warn;
        let found = found
            .into_iter()
            .map(|(f, reason)| {
                (
                    self.word_span(f),
                    format!("`{}`: {reason}", f.text(self.r.src)),
                )
            })
            .collect();
        let thread = frames
            .iter()
            .any(|f| f.word().letter == 'G' && matches!(f.word().value, 31..=33));
        if !self.r.unsupported(&UNSUPPORTED, found, keep, thread) {
            return;
        }
        // A kept group must not change what ncthread follows (the feed, the spindle, a
        // thread group's words), or the groups after it would be read wrongly.
        if let Some(f) = frames.iter().find(|f| self.changes_state(f.word())) {
            let span = self.word_span(f);
            self.r
                .state_in_opaque(&UNSUPPORTED, span, f.text(self.r.src));
            return;
        }
        let text = frames
            .iter()
            .map(|f| &self.r.src.line_of(f.place).text[f.frame.code_range.clone()])
            .collect::<Vec<_>>()
            .join("\n");
        let span = self.group_span(frames);
        let context = ModalContext {
            inch: false,
            diameter: true,
            incremental: false,
            per_minute: None,
            // The reader cannot tell: positions after the block are unknown.
            moves: true,
            cycle: false,
            compensation: false,
        };
        self.r
            .keep_opaque(text, span, frames[0].frame.number, context);
    }

    /// Whether `w` changes what ncthread follows: the feed, the spindle, the tool, a thread
    /// or arc group's words, a repeat (G25 runs frames again, which its P words name by
    /// numbers the writer may give to other frames), the program's end.
    fn changes_state(&self, w: &Word) -> bool {
        matches!(w.letter, 'F' | 'S' | 'T')
            || (w.letter == 'G' && matches!(w.value, 2 | 3 | 12 | 13 | 25 | 31..=33))
            || (w.letter == 'M'
                && (matches!(w.value, 3 | 4 | 5 | 30)
                    || (self.profile.coolant && matches!(w.value, 8 | 9))
                    || u32::try_from(w.value)
                        .is_ok_and(|m| self.profile.gear_range_mcodes.contains(&m))))
    }
}

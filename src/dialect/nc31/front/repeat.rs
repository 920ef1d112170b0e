//! G25 groups: frames repeated by their numbers.

use super::{FrontEnd, GroupFrame, REPEAT_LIMIT};
use crate::diag::Diagnostic;
use crate::dialect::nc31::codes;

/// What a G25 group holds (the help of its errors).
const ABOUT: &str = "G25 takes P (the first frame's number followed by the last frame's number in three digits: P5009 repeats N5 to N9) and P (how many times)";

/// A diagnostic as a repeat compares it with those reported before: code, line and
/// column, message.
pub(super) type Reported = (&'static str, Option<(u32, u32)>, String);

pub(super) fn reported(d: &Diagnostic) -> Reported {
    (
        d.code.id,
        d.location.as_ref().map(|l| (l.line, l.column)),
        d.message.clone(),
    )
}

/// A G25 group's words, read: the range's P frame and numbers, the count's P frame and value.
struct Repeat<'g> {
    range: &'g GroupFrame,
    from: u32,
    to: u32,
    count: &'g GroupFrame,
    times: i64,
}

impl FrontEnd<'_> {
    /// `G25 *`, `P<from><to> *`, `P<count>`: the groups from frame N<from> to frame N<to>
    /// (the last three digits of the first P are <to>) are read again `count` times here,
    /// from where the tool stands, as the control runs them (incremental frames cut further
    /// each time; absolute ones go to the same place again). The range must be whole groups
    /// before the G25 and hold no G25. **\[evidence\]** one shop's checker (nc31.md, "General
    /// motion"); the count of repetitions after the frames' own run and the limits are
    /// **\[decided\]**.
    pub(super) fn g25(&mut self, frames: &[GroupFrame]) {
        let Some(rep) = self.repeat_words(frames) else {
            return;
        };
        let Some((first, last)) = self.repeat_groups(&rep) else {
            return;
        };
        let (count, times) = (rep.count, rep.times);
        let per_run = self.frames_before[last + 1] - self.frames_before[first];
        let total = usize::try_from(times)
            .ok()
            .and_then(|t| t.checked_mul(per_run))
            .and_then(|n| n.checked_add(self.unrolled))
            .filter(|&n| n <= REPEAT_LIMIT);
        let Some(total) = total else {
            return self.repeat_error(
                count,
                format!(
                    "`{}` repeats {per_run} frame(s) {times} times: this program's repeats would unroll more than {REPEAT_LIMIT} frames",
                    count.text(self.r.src)
                ),
                "ncthread reads at most 10,000 repeated frames in a program; split the program",
            );
        };
        self.unrolled = total;
        let replay: Vec<Vec<GroupFrame>> = self.groups[first..=last]
            .iter()
            .filter(|(_, readable)| *readable)
            .map(|(frames, _)| frames.clone())
            .collect();
        self.replay(&replay, times, frames[0].place.number);
    }

    /// A G25 group's error (NCR_REPEAT) at the frame `at`.
    fn repeat_error(&mut self, at: &GroupFrame, message: String, help: &str) {
        self.word_error(codes::NCR_REPEAT, at, message, help.to_string());
    }

    /// Reads a G25 group's words: the two P, the range's numbers (forwards), the count (at
    /// least one), and a range that holds none of the G25's own frames.
    fn repeat_words<'g>(&mut self, frames: &'g [GroupFrame]) -> Option<Repeat<'g>> {
        let g = &frames[0];
        let w = self.thread_words(frames, &['P'], 2, ABOUT)?;
        let [range, count] = w.p[..] else {
            let missing = if w.p.is_empty() {
                "no P (range), no P (count)"
            } else {
                "no P (count)"
            };
            self.repeat_error(g, format!("the G25 group has {missing}"), ABOUT);
            return None;
        };
        let value = range.word().value;
        let (from, to) = (value / 1000, value % 1000);
        let (Ok(from), Ok(to)) = (u32::try_from(from), u32::try_from(to)) else {
            self.repeat_error(
                range,
                format!(
                    "`{}` is not a pair of frame numbers",
                    range.text(self.r.src)
                ),
                ABOUT,
            );
            return None;
        };
        if from > to {
            self.repeat_error(
                range,
                format!(
                    "`{}` repeats N{from} to N{to}: the range runs backwards",
                    range.text(self.r.src)
                ),
                ABOUT,
            );
            return None;
        }
        let times = count.word().value;
        if times < 1 {
            self.repeat_error(
                count,
                format!("`{}`: a G25 repeats at least once", count.text(self.r.src)),
                "the second P is how many times the frames run again (P1 once)",
            );
            return None;
        }
        let own = frames
            .iter()
            .filter_map(|f| f.frame.number)
            .find(|n| (from..=to).contains(n));
        if let Some(n) = own {
            self.repeat_error(
                range,
                format!(
                    "`{}` repeats N{from} to N{to}, which holds this G25's own frame N{n}",
                    range.text(self.r.src)
                ),
                "a G25 repeats frames before it; end the range before the G25 group",
            );
            return None;
        }
        Some(Repeat {
            range,
            from,
            to,
            count,
            times,
        })
    }

    /// The first and last of the groups read so far that the range names: whole groups,
    /// in order, holding no G25.
    fn repeat_groups(&mut self, rep: &Repeat) -> Option<(usize, usize)> {
        let Repeat {
            range, from, to, ..
        } = *rep;
        let mut ends =
            [(from, "first"), (to, "last")].map(|(n, which)| match self.numbers.get(&n) {
                None => Err(format!("there is no frame N{n} before this G25")),
                Some((_, _, true)) => Err(format!(
                    "more than one frame before this G25 is numbered N{n}"
                )),
                Some(&(group, frame, false)) => {
                    let len = self.groups.get(group).map_or(0, |(f, _)| f.len());
                    let whole = if which == "first" {
                        frame == 0
                    } else {
                        frame + 1 == len
                    };
                    if whole {
                        Ok(group)
                    } else {
                        Err(format!(
                            "N{n} is not the {which} frame of its group: a repeat runs whole groups"
                        ))
                    }
                }
            });
        let first = std::mem::replace(&mut ends[0], Ok(0));
        let last = std::mem::replace(&mut ends[1], Ok(0));
        let (first, last) = match (first, last) {
            (Ok(a), Ok(b)) if a <= b => (a, b),
            (Ok(_), Ok(_)) => {
                self.repeat_error(
                    range,
                    format!(
                        "`{}`: frame N{from} comes after frame N{to} in the program",
                        range.text(self.r.src)
                    ),
                    "the range runs from an earlier frame to a later one",
                );
                return None;
            }
            (Err(why), _) | (_, Err(why)) => {
                self.repeat_error(
                    range,
                    format!("`{}`: {why}", range.text(self.r.src)),
                    "the first P names frames of this program before the G25: N<from> starts a group and N<to> ends one",
                );
                return None;
            }
        };
        let nested = self.repeats.partition_point(|&i| i < first);
        if let Some(&inner) = self.repeats.get(nested).filter(|&&i| i <= last) {
            let line = self.groups[inner].0[0].place.number;
            self.repeat_error(
                range,
                format!(
                    "`{}` holds the G25 on line {line}: a repeat cannot repeat a repeat",
                    range.text(self.r.src)
                ),
                "write the inner repeat's frames out, or repeat a range without a G25",
            );
            return None;
        }
        Some((first, last))
    }

    /// Reads the `replay` groups again `times` times. A diagnostic already reported is not
    /// reported again; a new one names the G25 (on `line`), and an error stops the repeats.
    fn replay(&mut self, replay: &[Vec<GroupFrame>], times: i64, line: u32) {
        for _ in 0..times {
            let mark = self.r.diags.len();
            for frames in replay {
                self.read_group(frames);
            }
            if self.r.diags.len() == mark {
                continue;
            }
            // What the frames already said when they were read is not said again; what is
            // new (a feed or a position that differs here) names the G25.
            let new: Vec<Diagnostic> = self.r.diags.drain(mark..).collect();
            for d in &self.r.diags[self.reported.1.min(mark)..] {
                self.reported.0.insert(reported(d));
            }
            let mut failed = false;
            for mut d in new {
                if !self.reported.0.insert(reported(&d)) {
                    continue;
                }
                d.message
                    .push_str(&format!(" (repeated by the G25 on line {line})"));
                failed |= d.is_error();
                self.r.diags.push(d);
            }
            self.reported.1 = self.r.diags.len();
            if failed {
                break;
            }
        }
    }
}

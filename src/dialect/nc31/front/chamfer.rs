//! Chamfer groups: `X<end>±45 *` closed by `F<feed>`.

use super::super::syntax::Modifier;
use super::{Feed, FrontEnd, GroupFrame};
use crate::dialect::nc31::codes;
use crate::fixed::Length;
use crate::ir::{ItemKind, Pos};
use crate::source::Span;

/// What a chamfer group holds (the help of its errors).
const ABOUT: &str = "a chamfer group is `X<end>+45 *` or `X<end>-45 *` (likewise Z) closed by `F<feed>`: the other axis moves by the same radial amount, towards plus for `+45` and minus for `-45`";

impl FrontEnd<'_> {
    /// A chamfer group: `X<end>+45 *` or `X<end>-45 *` (likewise Z, `@` allowed) closed by
    /// `F<feed>`. The named axis goes to its end; the other moves by the same radial amount
    /// (X by twice it: X is a diameter), up for `+45` and down for `-45`: a 45° feed move.
    /// The F frame sets the feed, as every F frame outside a thread group does.
    /// **\[evidence\]** one shop's generator and checker (nc31.md, "General motion").
    pub(super) fn chamfer(&mut self, frames: &[GroupFrame], span: Span) {
        let Some((af, feed)) = self.chamfer_words(frames) else {
            return;
        };
        // `X3000+45`
        let shown = format!(
            "{}{}",
            af.text(self.r.src),
            af.frame
                .chamfer()
                .map_or("", |(up, _)| Modifier::Chamfer { up }.ascii())
        );
        let Some(ff) = feed else {
            return self.word_error(
                codes::NCR_CHAMFER,
                af,
                format!("the chamfer `{shown}` is not closed by an F frame"),
                ABOUT,
            );
        };
        if frames.last().is_some_and(|last| !std::ptr::eq(last, ff)) {
            return self.word_error(
                codes::NCR_CHAMFER,
                ff,
                format!(
                    "`{}` does not close the chamfer group: its F frame comes last",
                    ff.text(self.r.src)
                ),
                ABOUT,
            );
        }
        let Some(rate) = self.feed_rate(ff) else {
            return;
        };
        let Some((sx, sz)) = self.r.pos.known() else {
            return self.word_error(
                codes::NCR_UNKNOWN_POSITION,
                af,
                format!(
                    "the chamfer `{shown}` starts where the tool stands, and that is not known yet"
                ),
                "move to an absolute X and Z before the chamfer",
            );
        };
        let Some((ex, ez)) = self.chamfer_end(af, &shown, (sx, sz)) else {
            return;
        };
        if (ex, ez) == (sx, sz) {
            return self.word_error(
                codes::NCR_CHAMFER,
                af,
                format!(
                    "the chamfer `{shown}` does not move: the tool already stands at its {}",
                    af.word().letter
                ),
                ABOUT,
            );
        }
        self.feed = Feed::Set(rate);
        let kind = ItemKind::Feed {
            to: Pos::new(ex, ez),
            feed: rate,
        };
        self.r.pos = kind.end_position(self.r.pos);
        self.push(kind, span, None);
    }

    /// Sorts a chamfer group's words: its chamfered X or Z and its F. Reports words that do
    /// not belong, repeats and marks a word does not take; `None` after any of them or
    /// without a chamfered word.
    fn chamfer_words<'g>(
        &mut self,
        frames: &'g [GroupFrame],
    ) -> Option<(&'g GroupFrame, Option<&'g GroupFrame>)> {
        let mut ok = true;
        let (mut axis, mut feed): (Option<&GroupFrame>, Option<&GroupFrame>) = (None, None);
        for fr in frames {
            let w = fr.word();
            let chamfered = fr.frame.chamfer().is_some();
            match w.letter {
                'X' | 'Z' if chamfered => {
                    if let Some(first) = axis {
                        let line = first.place.number;
                        self.word_error(
                            codes::NCR_GROUP_WORD,
                            fr,
                            format!(
                                "a second chamfer `{}` in the group of `{}` (line {line})",
                                fr.text(self.r.src),
                                first.text(self.r.src)
                            ),
                            ABOUT,
                        );
                        ok = false;
                    } else {
                        axis = Some(fr);
                    }
                    if let Some(range) = fr.frame.modifier_range(Modifier::Rapid) {
                        let span = self.span(fr, range);
                        self.error(
                            codes::NCR_MODIFIER,
                            span,
                            format!("`~` on the chamfer `{}`", fr.text(self.r.src)),
                            "a chamfer is a feed move at the F that closes its group; a rapid is written without `+45`/`-45`",
                        );
                        ok = false;
                    }
                    ok &= self.check_modifiers(fr, true, true, true);
                }
                'F' => {
                    if let Some(first) = feed {
                        self.repeated(fr, first);
                        ok = false;
                    } else {
                        feed = Some(fr);
                    }
                    ok &= self.check_modifiers(fr, false, false, false);
                }
                // The mark on a word that takes none.
                _ if chamfered => ok &= self.check_modifiers(fr, false, false, false),
                _ => {
                    self.word_error(
                        codes::NCR_GROUP_WORD,
                        fr,
                        format!(
                            "`{}` does not belong in a chamfer group",
                            fr.text(self.r.src)
                        ),
                        format!("{ABOUT}; other words go in groups of their own"),
                    );
                    ok = false;
                }
            }
        }
        Some((axis.filter(|_| ok)?, feed))
    }

    /// The chamfer's end from `(sx, sz)`: the named axis's coordinate, the other axis moved
    /// by the same radial amount in the sign's direction. Reports an X whose Z travel is off
    /// the grid, and a move too far.
    fn chamfer_end(
        &mut self,
        af: &GroupFrame,
        shown: &str,
        (sx, sz): (Length, Length),
    ) -> Option<(Length, Length)> {
        let up = af.frame.chamfer().is_some_and(|(up, _)| up);
        let sign = if up { 1 } else { -1 };
        let end = if af.word().letter == 'X' {
            let ex = self.coordinate(af, Some(sx))?;
            let travel = ex.0.checked_sub(sx.0);
            if travel.is_some_and(|d| d % (2 * Length::STEP) != 0) {
                self.word_error(
                    codes::NCR_CHAMFER,
                    af,
                    format!(
                        "the chamfer `{shown}` changes the diameter by {} mm: half of it, the Z travel, is off the 0.0001 mm grid",
                        (ex - sx).mm()
                    ),
                    "a 45° chamfer moves Z by half the diameter change; with the profile's linear unit this X cannot be reached at 45°",
                );
                return None;
            }
            travel
                .and_then(|d| (d / 2).checked_abs())
                .and_then(|r| sz.0.checked_add(sign * r))
                .map(|ez| (ex, Length(ez)))
        } else {
            let ez = self.coordinate(af, Some(sz))?;
            ez.0.checked_sub(sz.0)
                .and_then(i64::checked_abs)
                .and_then(|r| r.checked_mul(2))
                .and_then(|d| sx.0.checked_add(sign * d))
                .map(|ex| (Length(ex), ez))
        };
        let Some((ex, ez)) = end else {
            self.word_error(
                codes::NCR_NUMBER,
                af,
                format!("the chamfer `{shown}` moves the tool too far"),
                "check the word's digits and the profile's units",
            );
            return None;
        };
        Some((ex, ez))
    }
}

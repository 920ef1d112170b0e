//! The dwell and motion step of a block: G04, or the block's F and its G00, G01, G02, G03 or
//! G33 move.

use std::ops::Range;

use super::{FRegister, FrontEnd, Motion, Words, code_span_range};
use crate::dialect::czech::codes;
use crate::dialect::czech::profile::{CzechArcs, CzechDwell};
use crate::dialect::czech::syntax::{Value, Word};
use crate::fixed::{Decimal, Length};
use crate::ir::{ItemKind, Pos};
use crate::lower;
use crate::source::{Line, Span};

impl<'a> FrontEnd<'a> {
    /// Step 8, dwell: a G04 block, its time in the profile's form.
    pub(super) fn dwell(
        &mut self,
        line: Line<'_>,
        g04: &Word,
        time: Option<&Word>,
        number: Option<u32>,
    ) {
        let form = self.profile.dwell;
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

    /// Step 8, motion: the block's F ([`Self::feed`]), then its move in the modal motion
    /// mode, which also moves the reader's position. A block without X or Z moves nothing.
    pub(super) fn motion_item(
        &mut self,
        line: Line<'_>,
        words: &Words<'_>,
        code_span: Span,
        number: Option<u32>,
    ) {
        let Some(f) = self.feed(line, words, number) else {
            return;
        };
        let (x_word, z_word) = (words.get('X'), words.get('Z'));
        if x_word.is_none() && z_word.is_none() {
            self.no_end_point(line, words, code_span);
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
        let Some(kind) = self.move_item(line, words, f, start, to, code_span) else {
            return;
        };
        self.r.pos = kind.end_position(self.r.pos);
        self.push(kind, code_span, number);
    }

    /// The block's F: its value goes to the F register (a lead in a G33 block, else a feed),
    /// and a feed that no move of the block uses is an item where it is written. `None`
    /// when F cannot be read (the block then does nothing more); else F and its word, if
    /// written.
    fn feed<'w>(
        &mut self,
        line: Line<'_>,
        words: &Words<'w>,
        number: Option<u32>,
    ) -> Option<Option<(Length, &'w Word)>> {
        let f = match words.get('F') {
            Some(w) => Some((self.f_value(line, w)?, w)),
            None => None,
        };
        let thread = self.motion == Motion::Thread;
        if let Some((value, _)) = f {
            self.f = Some(FRegister {
                value,
                is_lead: thread,
            });
        }
        // A feed that no move of the block uses stays where it is written.
        let unused_feed = match f {
            Some((value, w)) if !thread => {
                let moves = words.get('X').is_some() || words.get('Z').is_some();
                (!moves || self.motion == Motion::Rapid)
                    .then(|| (value, self.span(line, w.range.clone())))
            }
            _ => None,
        };
        if let Some((value, span)) = unused_feed {
            self.push(ItemKind::FeedRate(value), span, number);
        }
        Some(f)
    }

    /// A block without an end point: an error when it holds an arc's centre or radius, or a
    /// thread's I, J or E.
    fn no_end_point(&mut self, line: Line<'_>, words: &Words<'_>, code_span: Span) {
        let has_thread_words = ['I', 'J', 'E'].iter().any(|&c| words.get(c).is_some());
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
        if self.motion == Motion::Thread && has_thread_words {
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
    }

    /// The move from `start` to `to` in the modal motion mode, or `None` after reporting why
    /// there is none.
    fn move_item(
        &mut self,
        line: Line<'_>,
        words: &Words<'_>,
        f: Option<(Length, &Word)>,
        start: Pos,
        to: Pos,
        code_span: Span,
    ) -> Option<ItemKind> {
        Some(match self.motion {
            Motion::Rapid => ItemKind::Rapid { to },
            Motion::Feed => ItemKind::Feed {
                to,
                feed: self.feed_rate(line, code_span, "G01")?,
            },
            Motion::Arc(g02) => {
                let code = if g02 { "G02" } else { "G03" };
                let feed = self.feed_rate(line, code_span, code)?;
                let (to, centre, clockwise) = self.arc(line, words, start, to, g02, code_span)?;
                ItemKind::Arc {
                    to,
                    centre: Box::new(centre),
                    clockwise,
                    feed,
                }
            }
            Motion::Thread => {
                ItemKind::pass(self.thread_pass(line, words, f, start, to, code_span)?)
            }
        })
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
        let clockwise = g02 != self.profile.arcs_mirrored;
        let arc = Arc {
            code,
            whole,
            start: (sx, sz),
            end: (ex, ez),
        };
        let centre = if self.profile.arcs == CzechArcs::Radius {
            self.radius_centre(line, words, &arc, clockwise)?
        } else {
            self.ik_centre(line, words, &arc)?
        };
        self.check_radii(line, &arc, centre)?;
        Some((Pos::new(ex, ez), centre, clockwise))
    }

    /// The centre of an arc written with R (negative for more than half a turn).
    fn radius_centre(
        &mut self,
        line: Line<'_>,
        words: &Words<'_>,
        arc: &Arc,
        clockwise: bool,
    ) -> Option<Pos> {
        let code = arc.code;
        let Some(r) = words.get('R') else {
            self.arc_error(
                line,
                arc.whole.clone(),
                format!("{code} without R (this machine's arcs take their radius in R)"),
                "write the radius: `G02 X… Z… R5.`; a negative R turns more than half a circle",
            );
            return None;
        };
        let Value::Number(radius) = r.value else {
            return None;
        };
        if arc.start == arc.end {
            self.arc_error(
                line,
                r.range.clone(),
                format!("{code} R ends where it starts: a full circle has no R form"),
                "write the circle as two arcs",
            );
            return None;
        }
        match lower::arc::centre_from_radius(arc.start, arc.end, radius.to_f64(), clockwise, 0.001)
        {
            Ok(c) => Some(c),
            Err(chord) => {
                let text = &line.text[r.range.clone()];
                self.arc_error(
                    line,
                    r.range.clone(),
                    format!(
                        "`{text}` is too small for the arc: its end is {chord} mm from its start"
                    ),
                    "the radius must be at least half the distance from the start to the end",
                );
                None
            }
        }
    }

    /// The centre of an arc written with I and K, its offset from the start (I a radius or a
    /// diameter value, as the profile says).
    fn ik_centre(&mut self, line: Line<'_>, words: &Words<'_>, arc: &Arc) -> Option<Pos> {
        let value = |fe: &mut Self, w: Option<&Word>| match w.map(|w| (w, w.value)) {
            Some((w, Value::Number(d))) => fe.length(line, w, d).map(Some),
            Some(_) => None,
            None => Some(None),
        };
        let (i, k) = (words.get('I'), words.get('K'));
        if i.is_none() && k.is_none() {
            let code = arc.code;
            self.arc_error(line, arc.whole.clone(), format!("{code} without I or K (this machine's arcs take their centre's offset from the start in I and K)"), "write the centre: I for X, K for Z, from the arc's start");
            return None;
        }
        let iv = value(self, i)?.unwrap_or(Length::ZERO);
        let kv = value(self, k)?.unwrap_or(Length::ZERO);
        let dx = if self.profile.arcs == CzechArcs::IkRadius {
            iv + iv
        } else {
            iv
        };
        let (sx, sz) = arc.start;
        Some(Pos::new(sx + dx, sz + kv))
    }

    /// The arc's radius is not zero, and the same at its start and its end (within 0.002 mm).
    fn check_radii(&mut self, line: Line<'_>, arc: &Arc, centre: Pos) -> Option<()> {
        let code = arc.code;
        let (cx, cz) = centre.known()?;
        let (r1, r2) = lower::arc::radii(arc.start, arc.end, (cx, cz));
        if r1 < 0.001 || r2 < 0.001 {
            self.arc_error(
                line,
                arc.whole.clone(),
                format!("{code} with a zero radius: its centre is on its start or its end"),
                "check I and K: the centre's offset from the arc's start",
            );
            return None;
        }
        if (r1 - r2).abs() > 0.002 {
            self.arc_error(
                line,
                arc.whole.clone(),
                format!(
                    "{code}'s end is not on its circle: the radius is {} mm at the start and {} mm at the end",
                    Length::from_mm_f64(r1).mm(),
                    Length::from_mm_f64(r2).mm()
                ),
                "check I and K (and whether the profile's `arcs` reads I as a radius or a diameter)",
            );
            return None;
        }
        Some(())
    }
}

/// An arc block's code (G02 or G03), its range in the line, and its start and end.
struct Arc {
    code: &'static str,
    whole: Range<usize>,
    start: (Length, Length),
    end: (Length, Length),
}

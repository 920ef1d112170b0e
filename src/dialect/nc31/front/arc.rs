//! Arc groups: `G2`/`G3` with the centre's unsigned offsets, `G12`/`G13` quarter circles.

use super::thread::ThreadWords;
use super::{Feed, FrontEnd, GroupFrame};
use crate::dialect::nc31::codes;
use crate::dialect::nc31::profile::Nc31ArcDirection;
use crate::fixed::Length;
use crate::ir::{ItemKind, Pos};
use crate::lower;
use crate::source::Span;

impl FrontEnd<'_> {
    /// An arc group: `G2 *`/`G3 *` X, Z, P (the centre's radial offset from the start,
    /// unsigned, in radius units), P (its axial offset), within one quadrant; or `G12 *`/
    /// `G13 *` X, Z, a quarter circle. **\[evidence\]** one shop's generator (nc31.md,
    /// "General motion"). The signs of the offsets come from the quadrant: of the centres
    /// they allow, the one on whose circle the end lies (within one linear unit) and around
    /// which the arc turns the profile's way within one quadrant. **\[decided\]**
    pub(super) fn arc(&mut self, frames: &[GroupFrame], span: Span) {
        let g = &frames[0];
        let code = g.word().value;
        let quarter = code >= 12;
        let about = if quarter {
            "G12/G13 take X and Z (the end of a quarter circle)"
        } else {
            "G2/G3 take X, Z and two P (the centre's unsigned offsets from the start: radial, then axial)"
        };
        let (allowed, max_p): (&[char], usize) = if quarter {
            (&['X', 'Z'], 0)
        } else {
            (&['X', 'Z', 'P'], 2)
        };
        let Some(w) = self.thread_words(frames, allowed, max_p, about) else {
            return;
        };
        let Some((direction, feed, start)) = self.arc_ready(g, &w, about) else {
            return;
        };
        let Some(end) = self.arc_end(&w, start) else {
            return;
        };
        let g2_type = matches!(code, 2 | 12);
        let clockwise = g2_type != (direction == Nc31ArcDirection::FrontTool);
        let Some(centre) = self.arc_centre(g, &w, (start, end), clockwise) else {
            return;
        };
        let kind = ItemKind::Arc {
            to: Pos::new(end.0, end.1),
            centre: Box::new(centre),
            clockwise,
            feed,
        };
        self.r.pos = kind.end_position(self.r.pos);
        self.push(kind, span, None);
    }

    /// An arc group's error (NCR_ARC) at the frame `at`.
    fn arc_error(&mut self, at: &GroupFrame, message: String, help: &str) {
        self.word_error(codes::NCR_ARC, at, message, help.to_string());
    }

    /// What an arc needs before its words are read: the profile's direction of G2, the
    /// words (two P unless a quarter arc, X or Z), the feed and the start (X, Z).
    fn arc_ready(
        &mut self,
        g: &GroupFrame,
        w: &ThreadWords,
        about: &str,
    ) -> Option<(Nc31ArcDirection, Length, (Length, Length))> {
        let code = g.word().value;
        let Some(direction) = self.profile.arc_direction else {
            self.arc_error(
                g,
                format!("G{code}: the profile enables arcs but does not say which way G2 turns"),
                "set `arc_direction = \"front-tool\"` or `\"iso\"` in the profile's [nc31] section, as the machine's documentation says",
            );
            return None;
        };
        if code < 12 && w.p.len() < 2 {
            let message = format!("G{code} without its two P words (the centre's offsets)");
            self.arc_error(g, message, about);
            return None;
        }
        if w.x.is_none() && w.z.is_none() {
            self.arc_error(g, format!("G{code} without X or Z"), about);
            return None;
        }
        let Feed::Set(feed) = self.feed else {
            let why = self.why_no_feed();
            self.word_error(
                codes::NCR_NO_FEED,
                g,
                format!("arc `G{code}` but {why}"),
                "program the feed in a frame of its own (e.g. `F20` = 0.2 mm/rev) before the arc",
            );
            return None;
        };
        let Some(start) = self.r.pos.known() else {
            self.word_error(
                codes::NCR_UNKNOWN_POSITION,
                g,
                format!("arc `G{code}` from a position that is not known yet"),
                "move to an absolute X and Z before the arc",
            );
            return None;
        };
        Some((direction, feed, start))
    }

    /// The arc's end (X, Z): its coordinates from `start`, an axis not written staying.
    fn arc_end(&mut self, w: &ThreadWords, (sx, sz): (Length, Length)) -> Option<(Length, Length)> {
        let ex = match w.x {
            Some(fr) => self.coordinate(fr, Some(sx)),
            None => Some(sx),
        };
        let ez = match w.z {
            Some(fr) => self.coordinate(fr, Some(sz)),
            None => Some(sz),
        };
        Some((ex?, ez?))
    }

    /// The centres an arc's words allow: a quarter arc's two corners, or the four signs of
    /// the two unsigned P offsets (the radial one doubled on the diameter).
    fn arc_candidates(
        &mut self,
        w: &ThreadWords,
        quarter: bool,
        ((sx, sz), (ex, ez)): ((Length, Length), (Length, Length)),
    ) -> Option<Vec<Pos>> {
        if quarter {
            return Some(vec![Pos::new(ex, sz), Pos::new(sx, ez)]);
        }
        let unit = self.profile.linear_unit;
        let (Some(a), Some(b)) = (self.scaled(w.p[0], unit), self.scaled(w.p[1], unit)) else {
            return None;
        };
        if a.0 < 0 || b.0 < 0 {
            self.arc_error(
                if a.0 < 0 { w.p[0] } else { w.p[1] },
                "a negative P in an arc group: its offsets are unsigned".into(),
                "the signs come from the quadrant the arc turns in; write the offsets without a sign",
            );
            return None;
        }
        let mut out = Vec::new();
        for (dx, dz) in [(a, b), (-a, b), (a, -b), (-a, -b)] {
            let c = Pos::new(sx + dx + dx, sz + dz);
            if !out.contains(&c) {
                out.push(c);
            }
        }
        Some(out)
    }

    /// The one centre the arc's words allow whose circle holds the end (within one linear
    /// unit) and around which the arc turns the profile's way within one quadrant.
    fn arc_centre(
        &mut self,
        g: &GroupFrame,
        w: &ThreadWords,
        ends: ((Length, Length), (Length, Length)),
        clockwise: bool,
    ) -> Option<Pos> {
        let code = g.word().value;
        let candidates = self.arc_candidates(w, code >= 12, ends)?;
        let ((sx, sz), (ex, ez)) = ends;
        let tolerance = self.profile.linear_unit.to_mm_f64();
        let fits: Vec<Pos> = candidates
            .into_iter()
            .filter(|c| {
                let Some((cx, cz)) = c.known() else {
                    return false;
                };
                let (r1, r2) = lower::arc::radii((sx, sz), (ex, ez), (cx, cz));
                r1 > 0.0
                    && (r1 - r2).abs() <= tolerance
                    && lower::arc::within_quadrant((sx, sz), (ex, ez), (cx, cz), clockwise)
            })
            .collect();
        match fits.as_slice() {
            [c] => return Some(*c),
            [] => self.arc_error(
                g,
                format!(
                    "G{code} to X{} Z{}: no centre its offsets allow has the end on its circle with the arc turning {} within one quadrant",
                    ex.mm(),
                    ez.mm(),
                    if clockwise {
                        "clockwise (G2 seen as LinuxCNC sees it)"
                    } else {
                        "counter-clockwise (G3 seen as LinuxCNC sees it)"
                    }
                ),
                "check the P offsets (radial first, in radius units) and the profile's arc_direction; an arc over a quadrant boundary is written as two groups",
            ),
            _ => self.arc_error(
                g,
                format!("G{code}: more than one centre fits its offsets"),
                "a zero offset leaves the side open; write the arc so that its centre is one",
            ),
        }
        None
    }
}

//! G76: LinuxCNC's threading cycle.

use super::super::syntax::Word;
use super::{FrontEnd, Words};
use crate::dialect::iso::codes;
use crate::fixed::{Angle, Decimal, Length};
use crate::ir::{
    CycleChamfer, Degression, Finish, IjkScale, ItemKind, Pos, Retract, Rise, Schedule, Slope,
    ThreadCycle,
};
use crate::lower;
use crate::source::{Line, Span};

/// The words of a G76 line: P, I, J, K are required, the others optional.
struct G76Words<'b> {
    p: &'b Word,
    i: &'b Word,
    j: &'b Word,
    k: &'b Word,
    r: Option<&'b Word>,
    q: Option<&'b Word>,
    h: Option<&'b Word>,
    e: Option<&'b Word>,
    l: Option<&'b Word>,
}

impl FrontEnd<'_> {
    pub(super) fn g76_error(&mut self, line: Line<'_>, w: &Word, message: String, help: &str) {
        self.diag(codes::ISOR_G76, line, w.range.clone(), message, help);
    }

    /// LinuxCNC's G76 (`convert_threading_cycle`) as a thread cycle.
    pub(super) fn cycle(
        &mut self,
        line: Line<'_>,
        words: &mut Words<'_>,
        at: Option<&Word>,
        span: Span,
    ) {
        let Some(at) = at.or(words.other.get(&'Z').copied()) else {
            return;
        };
        let mut get = |l: char| words.take(l);
        let (p, i, j, k) = (get('P'), get('I'), get('J'), get('K'));
        let (r, q, h, e, l) = (get('R'), get('Q'), get('H'), get('E'), get('L'));
        let z_given = words.other.contains_key(&'Z');
        let Some(to) = self.target(line, words) else {
            return;
        };
        let (Some(p), Some(i), Some(j), Some(k), true) = (p, i, j, k, z_given) else {
            let missing: String = [
                ('P', p),
                ('Z', words.other.get(&'Z').copied()),
                ('I', i),
                ('J', j),
                ('K', k),
            ]
            .iter()
            .filter(|(_, w)| w.is_none())
            .map(|(c, _)| c.to_string())
            .collect::<Vec<_>>()
            .join(", ");
            self.missing(
                line,
                at,
                format!("G76 without {missing}"),
                "G76 needs P (pitch), Z (end), I (crest offset from the drive line), J (first depth) and K (thread depth)",
            );
            return;
        };
        let g = G76Words {
            p,
            i,
            j,
            k,
            r,
            q,
            h,
            e,
            l,
        };
        if !self.g76_checks(line, &g) {
            return;
        }
        let (Some(start_x), Some(start_z)) = (self.r.pos.x, self.r.pos.z) else {
            return self.unknown_start(line, at);
        };
        if !self.spindle_turning(line, Some(at), "G76") {
            return;
        }
        let Some(cycle) = self.g76_cycle(line, &g, (start_x, start_z), to) else {
            return;
        };
        if let Err(err) = lower::check(&cycle) {
            return self.g76_error(
                line,
                at,
                err.message(&cycle),
                "correct the G76 words; ncthread cuts a cycle only when every pass is defined",
            );
        }
        self.r.pos = Pos::new(to.x.unwrap_or(start_x), cycle.end_z);
        self.push(ItemKind::ThreadCycle(Box::new(cycle)), span);
    }

    /// LinuxCNC's own checks of I, J, K and P, on the numbers as written; false after an
    /// error.
    fn g76_checks(&mut self, line: Line<'_>, g: &G76Words<'_>) -> bool {
        let (iv, jv, kv) = (g.i.value.to_f64(), g.j.value.to_f64(), g.k.value.to_f64());
        let (w, message, help) = if iv == 0.0 {
            (
                g.i,
                "in G76, I must not be 0",
                "I is the crest's offset from the drive line: negative outside, positive in a bore",
            )
        } else if jv <= 0.0 {
            (
                g.j,
                "in G76, J must be greater than 0",
                "J is the depth of the first pass",
            )
        } else if kv <= jv {
            (
                g.k,
                "in G76, K must be greater than J",
                "K is the full thread depth, J the first pass's",
            )
        } else if g.p.value.mantissa <= 0 {
            (
                g.p,
                "the G76 pitch P is not positive",
                "P is the advance per spindle revolution",
            )
        } else {
            return true;
        };
        self.g76_error(line, w, message.into(), help);
        false
    }

    /// The cycle a checked G76 cuts from `start` to `to`, or `None` after an error.
    fn g76_cycle(
        &mut self,
        line: Line<'_>,
        g: &G76Words<'_>,
        start: (Length, Length),
        to: Pos,
    ) -> Option<ThreadCycle> {
        let (start_x, start_z) = start;
        let diameter = self.diameter.unwrap_or(false);
        let lead = self.lead(line, g.p)?;
        let (Some(i_len), Some(j_len), Some(k_len)) = (
            self.length(line, g.i),
            self.length(line, g.j),
            self.length(line, g.k),
        ) else {
            return None;
        };
        // Per side (radius) and as a diameter, scaled as LinuxCNC scales them.
        let scale = IjkScale::of_modes(self.diameter_before_line, diameter);
        let side = |v: Length| scale.length(v);
        let i_dia = side(i_len) + side(i_len);
        let height = side(i_len.abs() + k_len);
        let spring_passes = match g.h {
            Some(h) => self.whole(line, h, "the number of spring passes H")?,
            None => 0,
        };
        let (entry, runout) = self.g76_tapers(line, g)?;
        let infeed = self.g76_infeed(line, g.q)?;
        Some(ThreadCycle {
            start: (start_x, start_z),
            crest: start_x + i_dia,
            end_z: to.z.expect("Z is given"),
            lead,
            depth: side(k_len),
            first_depth: side(j_len),
            taper: Length::ZERO,
            infeed,
            infeed_moves_end: true,
            start_angle: Angle::ZERO,
            entry,
            // With an entry taper LinuxCNC feeds in along X, synchronised, from the retract
            // height to the entry's start. **[evidence]** `threading_pass`.
            entry_infeed: entry.is_some(),
            runout,
            retract: Retract::AboveCut(height),
            spring_passes,
            finish: Finish::EndAt(to.x.unwrap_or(start_x)),
            internal: g.i.value.to_f64() > 0.0,
            schedule: Schedule::Degression(Degression {
                r: g.r
                    .map_or(Decimal::parse("1").expect("a number"), |r| r.value),
                i: g.i.value,
                j: g.j.value,
                k: g.k.value,
                scale,
                inch: self.inch,
            }),
        })
    }

    /// The entry and exit tapers: L (1 entry, 2 exit, 3 both) of length E.
    #[allow(clippy::type_complexity)]
    fn g76_tapers(
        &mut self,
        line: Line<'_>,
        g: &G76Words<'_>,
    ) -> Option<(Option<CycleChamfer>, Option<CycleChamfer>)> {
        let flags = match g.l {
            Some(l) => match l.value.to_whole() {
                Ok(v) if v >= 0 => v,
                Ok(_) => {
                    self.number_error(
                        line,
                        l,
                        "G76 L is negative (LinuxCNC: \"Negative l word used\")".into(),
                        "L0 none, L1 entry taper, L2 exit taper, L3 both",
                    );
                    return None;
                }
                Err(_) => {
                    self.number_error(
                        line,
                        l,
                        "G76 L is not a whole number".into(),
                        "L0 none, L1 entry taper, L2 exit taper, L3 both",
                    );
                    return None;
                }
            },
            None => 0,
        };
        let taper = match g.e {
            Some(e) => self.length(line, e)?.max(Length::ZERO),
            None => Length::ZERO,
        };
        let chamfer = |on: bool| {
            (on && taper.0 > 0).then_some(CycleChamfer {
                length: taper,
                rise: Rise::ThreadDepth,
            })
        };
        Some((chamfer(flags & 1 != 0), chamfer(flags & 2 != 0)))
    }

    /// The infeed's slope: tan(Q), Q as LinuxCNC reads it (an unwritten Q is −1 there, and
    /// −1 means 0), less than 90°.
    fn g76_infeed(&mut self, line: Line<'_>, q: Option<&Word>) -> Option<Slope> {
        let q_deg = q.map_or(0.0, |q| q.value.to_f64());
        let q_deg = if q_deg == -1.0 { 0.0 } else { q_deg };
        if q_deg.abs() >= 90.0
            && let Some(q) = q
        {
            self.g76_error(
                line,
                q,
                "the compound angle Q must be less than 90°".into(),
                "Q is the infeed angle from the radial, usually 29.5",
            );
            return None;
        }
        Some(Slope::of_degrees(q_deg))
    }
}

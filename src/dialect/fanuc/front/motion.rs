//! The block's dwell or motion: G04, and the moves G00 G01 G02 G03 G32 G92.

use std::ops::Range;

use super::{Cycle, FRegister, FrontEnd, MAX_Q, Motion, Unit};
use crate::dialect::fanuc::codes;
use crate::dialect::fanuc::syntax::Word;
use crate::fixed::{Angle, Decimal, Lead, Length};
use crate::ir::{Chamfer, ItemKind, Pos, SyncStart, ThreadPass};
use crate::lower;
use crate::source::{Line, Span};

/// Where a G92 pass runs: its start point, the diameter and Z of its end, its taper R.
#[derive(Clone, Copy, Debug)]
struct CyclePass {
    sx: Length,
    sz: Length,
    x: Length,
    end_z: Length,
    /// Radius at the start minus radius at the end of the cut.
    taper: Length,
}

impl FrontEnd<'_> {
    /// `G04 U1.5`, `G04 X1.5` (seconds) or `G04 P1500` (milliseconds).
    pub(super) fn dwell<'w>(
        &mut self,
        line: Line<'_>,
        g04: &Word,
        get: &dyn Fn(char) -> Option<&'w Word>,
        code_span: Span,
    ) -> Option<()> {
        let time = ['U', 'X', 'P']
            .iter()
            .filter_map(|&c| get(c))
            .collect::<Vec<_>>();
        let [w] = time.as_slice() else {
            let text = &line.text[g04.range.clone()];
            self.error(
                codes::FANR_UNSUPPORTED,
                line,
                g04.range.clone(),
                format!("`{text}` needs one time word: U or X in seconds, or P in milliseconds"),
                "write `G04 U1.5` or `G04 P1500`",
            );
            return None;
        };
        // A Haas reads `P3.` as seconds (the profile's `haas_dwell_p`).
        if w.letter == 'P' && w.value.has_point && !self.profile.haas_dwell_p {
            let text = &line.text[w.range.clone()];
            self.error(
                codes::FANR_NUMBER,
                line,
                w.range.clone(),
                format!("`{text}`: G04's P takes whole milliseconds without a decimal point"),
                "write `G04 P3000` (or `G04 U3.`) for 3 s; on a Haas, where `P3.` is 3 seconds, set `haas_dwell_p = true` in the profile's [fanuc] section",
            );
            return None;
        }
        let seconds = if w.letter == 'P' && !w.value.has_point {
            let ms = self.whole(line, w)?;
            Decimal {
                mantissa: ms as i128,
                scale: 3,
                has_point: true,
            }
        } else {
            let v = self.mm_value(line, w, Unit::Seconds)?;
            if let Err(e) = v.to_scaled(3) {
                self.number_error(line, w, e, "0.001 s");
                return None;
            }
            v
        };
        if seconds.is_negative() {
            let text = &line.text[w.range.clone()];
            self.error(
                codes::FANR_NUMBER,
                line,
                w.range.clone(),
                format!("`{text}`: a dwell is not negative"),
                "write the time",
            );
            return None;
        }
        self.push(ItemKind::Dwell { seconds }, code_span);
        Some(())
    }

    /// The end of a move: X/U and Z/W from the current position.
    pub(super) fn target<'w>(
        &mut self,
        line: Line<'_>,
        get: &dyn Fn(char) -> Option<&'w Word>,
        from: Pos,
    ) -> Option<Pos> {
        let mut to = Pos::UNKNOWN;
        for (abs, inc) in [('X', 'U'), ('Z', 'W')] {
            let value = if let Some(w) = get(abs) {
                Some(self.length(line, w, Unit::Axis)?)
            } else if let Some(w) = get(inc) {
                let d = self.length(line, w, Unit::Axis)?;
                let here = if abs == 'X' { from.x } else { from.z };
                let Some(here) = here else {
                    let text = &line.text[w.range.clone()];
                    self.error(
                        codes::FANR_UNKNOWN_POSITION,
                        line,
                        w.range.clone(),
                        format!("`{text}` moves from a position that is not known yet"),
                        "move to an absolute X and Z (not U and W) first",
                    );
                    return None;
                };
                Some(here + d)
            } else {
                None
            };
            if abs == 'X' {
                to.x = value;
            } else {
                to.z = value;
            }
        }
        Some(to)
    }

    /// The block's move in the modal motion, from where the tool stands to X/U and Z/W.
    pub(super) fn motion_block<'w>(
        &mut self,
        line: Line<'_>,
        get: &dyn Fn(char) -> Option<&'w Word>,
        lead: Option<Lead>,
        feed: Option<Length>,
        g: Option<&Word>,
        code_span: Span,
    ) -> Option<()> {
        let from = self.r.pos;
        let to = self.target(line, get, from)?;
        let whole = code_range_of(line, code_span);
        self.foreign_words(line, get)?;
        self.moved = true;
        match self.motion {
            Motion::Rapid => {
                self.sync_end = None;
                self.push(ItemKind::Rapid { to }, code_span);
            }
            Motion::Feed | Motion::Arc(_) => {
                self.feed_move(line, get, from, to, feed, whole, code_span)?;
            }
            Motion::Thread => self.thread(line, get, from, to, lead, whole, code_span)?,
            Motion::Cycle => self.cycle(line, get, from, to, lead, g, whole, code_span)?,
        }
        Some(())
    }

    /// Words that belong to another motion than the block's: Q to a thread, I and K to an
    /// arc, R to an arc or G92, P to a dwell.
    fn foreign_words<'w>(
        &mut self,
        line: Line<'_>,
        get: &dyn Fn(char) -> Option<&'w Word>,
    ) -> Option<()> {
        let rules: [(bool, &[char], &str); 4] = [
            (
                !matches!(self.motion, Motion::Thread | Motion::Cycle),
                &['Q'],
                "Q belongs to a thread (G32, G92)",
            ),
            (
                !matches!(self.motion, Motion::Arc(_)),
                &['I', 'K'],
                "I and K belong to an arc (G02, G03)",
            ),
            (
                !matches!(self.motion, Motion::Arc(_) | Motion::Cycle),
                &['R'],
                "R belongs to an arc or to G92's taper",
            ),
            (true, &['P'], "P belongs to a dwell (G04)"),
        ];
        for (foreign, letters, why) in rules {
            if foreign && let Some(w) = letters.iter().find_map(|&c| get(c)) {
                let text = &line.text[w.range.clone()];
                self.error(
                    codes::FANR_UNSUPPORTED,
                    line,
                    w.range.clone(),
                    format!("`{text}`: {why}"),
                    "remove it",
                );
                return None;
            }
        }
        Some(())
    }

    /// G01, G02, G03: a straight or circular feed move, at the block's F or the feed the F
    /// register holds.
    #[allow(clippy::too_many_arguments)]
    fn feed_move<'w>(
        &mut self,
        line: Line<'_>,
        get: &dyn Fn(char) -> Option<&'w Word>,
        from: Pos,
        to: Pos,
        feed: Option<Length>,
        whole: Range<usize>,
        code_span: Span,
    ) -> Option<()> {
        let feed = match (feed, self.f) {
            (Some(f), _) => f,
            (None, Some(FRegister::Feed(f))) => f,
            (None, register) => {
                let why = match register {
                    Some(FRegister::Lead(_)) => "F was last a thread's lead; whether this control feeds at it is not settled by any source ncthread holds".to_string(),
                    Some(FRegister::AfterCycle(g)) => {
                        let s = self.profile.gcode_system;
                        format!("the feed after the G{:02} cycle is the control's (its F, or its contour's, which G{:02} runs)", s.code(g), s.code(70))
                    }
                    _ => "no feed F is set yet".to_string(),
                };
                self.error(
                    codes::FANR_NO_FEED,
                    line,
                    whole,
                    format!("{} without F: {why}", self.motion.code()),
                    "write the feed in this block: `G01 Z-20. F0.2`",
                );
                return None;
            }
        };
        self.sync_end = None;
        if let Motion::Arc(clockwise) = self.motion {
            let (to, centre) = self.arc(line, get, from, to, clockwise, whole)?;
            self.push(
                ItemKind::Arc {
                    to,
                    centre: Box::new(centre),
                    clockwise,
                    feed,
                },
                code_span,
            );
        } else {
            self.push(ItemKind::Feed { to, feed }, code_span);
        }
        Some(())
    }

    /// The lead of a G32/G92 block: its F, or a lead F of an earlier thread block.
    fn block_lead(
        &mut self,
        line: Line<'_>,
        lead: Option<Lead>,
        whole: Range<usize>,
    ) -> Option<Lead> {
        match (lead, self.f) {
            (Some(l), _) => Some(l),
            (None, Some(FRegister::Lead(l))) => Some(l),
            (None, register) => {
                let why = if matches!(register, Some(FRegister::Feed(_))) {
                    "F was last a feed; whether this control threads at it is not settled by any source ncthread holds"
                } else {
                    "no lead F is set yet"
                };
                self.error(
                    codes::FANR_NO_FEED,
                    line,
                    whole,
                    format!("{} without F: {why}", self.motion.code()),
                    "write the lead in this block: `G32 Z-20. F1.5`",
                );
                None
            }
        }
    }

    /// Q: the start angle in 0.001°, a whole number.
    fn start_angle<'w>(
        &mut self,
        line: Line<'_>,
        get: &dyn Fn(char) -> Option<&'w Word>,
    ) -> Option<Angle> {
        let Some(w) = get('Q') else {
            return Some(Angle::ZERO);
        };
        let q = self.whole(line, w)?;
        if !(0..=MAX_Q).contains(&q) {
            let text = &line.text[w.range.clone()];
            self.error(
                codes::FANR_NUMBER,
                line,
                w.range.clone(),
                format!(
                    "`{text}`: the start angle Q is 0 to 359999 (0.001° without a decimal point)"
                ),
                "Q180000 is 180°",
            );
            return None;
        }
        Some(Angle(q))
    }

    /// Whether a move between two known points is steeper than 45° ([`lower::steeper_than_45`]).
    fn steep(from: Pos, to: Pos) -> bool {
        matches!((from.known(), to.known()), (Some(a), Some(b)) if lower::steeper_than_45(a, b))
    }

    #[allow(clippy::too_many_arguments)]
    fn thread<'w>(
        &mut self,
        line: Line<'_>,
        get: &dyn Fn(char) -> Option<&'w Word>,
        from: Pos,
        to: Pos,
        lead: Option<Lead>,
        whole: Range<usize>,
        code_span: Span,
    ) -> Option<()> {
        let lead = self.block_lead(line, lead, whole.clone())?;
        // A thread along Z needs only its end Z; one that moves X needs its start.
        let end = Pos {
            x: to.x.or(from.x),
            z: to.z.or(from.z),
        };
        if end.z.is_none() || (to.x.is_some() && from.known().is_none()) {
            self.error(
                codes::FANR_UNKNOWN_POSITION,
                line,
                whole,
                "G32 from a position that is not known yet".into(),
                "move to the thread's start with X and Z first",
            );
            return None;
        }
        if end.z == from.z || Self::steep(from, end) {
            self.error(
                codes::FANR_STEEP,
                line,
                whole,
                "this G32 moves X (as a radius) more than Z: steeper than 45°, its F is a lead along X, whose unit (radius or diameter) no source ncthread holds confirms".into(),
                "cut this thread with Z as the long axis, or convert it by hand",
            );
            return None;
        }
        let angle = self.start_angle(line, get)?;
        let continues = self.sync_end == Some(from) && self.blocks_since_sync == 1;
        if continues && get('Q').is_some() {
            let w = get('Q')?;
            let text = &line.text[w.range.clone()];
            self.error(
                codes::FANR_CHAIN,
                line,
                w.range.clone(),
                format!("`{text}` on a G32 block that continues the one before: the start angle counts only on the chain's first block"),
                "remove Q here, or retract and start a new pass",
            );
            return None;
        }
        if self.sync_end == Some(from) && self.blocks_since_sync > 1 {
            self.error(
                codes::FANR_CHAIN,
                line,
                whole,
                "a G32 block that starts where the last G32 ended, after a block between them: whether the control waits there for the index pulse (the tool in the cut) is not documented".into(),
                "keep the G32 blocks of one chain consecutive, or retract before the next pass",
            );
            return None;
        }
        let pass = ThreadPass {
            to: end,
            lead,
            start: if continues {
                SyncStart::Continue
            } else {
                SyncStart::Index(angle)
            },
            infeed: None,
            entry: None,
            exit: None,
        };
        self.push(ItemKind::pass(pass), code_span);
        self.sync_end = Some(end);
        self.blocks_since_sync = 0;
        Some(())
    }

    /// The G92 threading cycle: rapid to the cut's start X, thread to Z (with the machine's
    /// chamfer), rapid out to the start X, rapid back to the start Z. **\[evidence\]**
    #[allow(clippy::too_many_arguments)]
    fn cycle<'w>(
        &mut self,
        line: Line<'_>,
        get: &dyn Fn(char) -> Option<&'w Word>,
        from: Pos,
        to: Pos,
        lead: Option<Lead>,
        g: Option<&Word>,
        whole: Range<usize>,
        code_span: Span,
    ) -> Option<()> {
        let chamfer = self.chamfer_key(line, g, whole.clone())?;
        let lead = self.block_lead(line, lead, whole.clone())?;
        let p = self.cycle_pass(line, get, from, to, whole.clone())?;
        self.taper_fits(line, get, p, whole.clone())?;
        // The cut starts 2R (on the diameter) from the end diameter, at the start Z.
        let cut_x = p.x + p.taper + p.taper;
        let angle = self.start_angle(line, get)?;
        if Self::steep(Pos::new(cut_x, p.sz), Pos::new(p.x, p.end_z)) {
            self.error(
                codes::FANR_STEEP,
                line,
                whole,
                "this G92's taper is steeper than 45°: its F is a lead along X, whose unit no source ncthread holds confirms".into(),
                "cut this thread with Z as the long axis",
            );
            return None;
        }
        let exit = self.cycle_exit(line, chamfer, lead, p, whole)?;
        self.cycle = Some(Cycle {
            x: p.x,
            end_z: p.end_z,
            taper: p.taper,
        });
        self.sync_end = None;
        self.push(
            ItemKind::Rapid {
                to: Pos::new(cut_x, p.sz),
            },
            code_span,
        );
        self.push(
            ItemKind::pass(ThreadPass {
                to: Pos::new(p.x, p.end_z),
                lead,
                start: SyncStart::Index(angle),
                infeed: None,
                entry: None,
                exit,
            }),
            code_span,
        );
        self.push(
            ItemKind::Rapid {
                to: Pos::new(p.sx, p.end_z),
            },
            code_span,
        );
        self.push(
            ItemKind::Rapid {
                to: Pos::new(p.sx, p.sz),
            },
            code_span,
        );
        Some(())
    }

    /// The machine's G92 chamfer from the profile (in 0.1 lead), which G92 needs; its
    /// absence is said once, as every G92 block of the program needs the same key.
    fn chamfer_key(
        &mut self,
        line: Line<'_>,
        g: Option<&Word>,
        whole: Range<usize>,
    ) -> Option<u32> {
        // A G76's rr before it sets the machine's chamfer (parameter 5130) for G92 too.
        let Some(chamfer) = self.g76_chamfer.or(self.profile.thread_chamfer_0p1_lead) else {
            // Said once: every G92 block of the program needs the same key.
            if std::mem::replace(&mut self.chamfer_refused, true) {
                return None;
            }
            let range = g.map_or(whole.clone(), |w| w.range.clone());
            self.error(
                codes::FANR_G92_CHAMFER,
                line,
                range,
                "G92 threading cycle: its chamfer at the thread's end is a machine parameter (5130), which the profile does not give".into(),
                "set `thread_chamfer_0p1_lead` in the profile's [fanuc] section to the machine's parameter 5130 (0 for none)",
            );
            return None;
        };
        Some(chamfer)
    }

    /// A G92 pass: its start point (known), its diameter, end and taper, each written or
    /// kept from the cycle's last block.
    fn cycle_pass<'w>(
        &mut self,
        line: Line<'_>,
        get: &dyn Fn(char) -> Option<&'w Word>,
        from: Pos,
        to: Pos,
        whole: Range<usize>,
    ) -> Option<CyclePass> {
        let Some((sx, sz)) = from.known() else {
            self.error(
                codes::FANR_UNKNOWN_POSITION,
                line,
                whole,
                "G92 from a position that is not known yet: the cycle returns to its start point"
                    .into(),
                "move to the cycle's start point with X and Z first",
            );
            return None;
        };
        let Some(x) = to.x.or(self.cycle.map(|c| c.x)) else {
            self.error(
                codes::FANR_UNSUPPORTED,
                line,
                whole,
                "G92 without X or U: the thread's diameter".into(),
                "write the diameter of this pass: `G92 X19.4 Z-20. F1.5`",
            );
            return None;
        };
        let taper = match get('R') {
            Some(w) => self.length(line, w, Unit::Axis)?,
            None => self.cycle.map_or(Length::ZERO, |c| c.taper),
        };
        let end_z = match (to.z, self.cycle) {
            (Some(z), _) => z,
            (None, Some(c)) => c.end_z,
            (None, None) => {
                self.error(
                    codes::FANR_UNSUPPORTED,
                    line,
                    whole,
                    "G92 without Z or W: the thread's end".into(),
                    "write the end of the thread: `G92 X19.4 Z-20. F1.5`",
                );
                return None;
            }
        };
        if end_z == sz {
            self.error(
                codes::FANR_UNSUPPORTED,
                line,
                whole,
                "G92 whose Z is its start point's: the thread has no length".into(),
                "move the start point before the thread",
            );
            return None;
        }
        Some(CyclePass {
            sx,
            sz,
            x,
            end_z,
            taper,
        })
    }

    /// R against U: with opposite signs FANUC allows only |R| ≤ |U/2| (its sign table);
    /// beyond, the path is not documented. **\[evidence\]** GSK980TDc, HUST H6D-T.
    fn taper_fits<'w>(
        &mut self,
        line: Line<'_>,
        get: &dyn Fn(char) -> Option<&'w Word>,
        p: CyclePass,
        whole: Range<usize>,
    ) -> Option<()> {
        let (taper, u) = (p.taper, p.x - p.sx);
        if taper.0 != 0
            && taper.signum() != u.signum()
            && 2 * taper.0.unsigned_abs() > u.0.unsigned_abs()
        {
            let w = get('R');
            let range = w.map_or(whole.clone(), |w| w.range.clone());
            self.error(
                codes::FANR_UNSUPPORTED,
                line,
                range,
                format!("G92's taper R {} against U {}: with opposite signs the cycle allows only |R| ≤ |U/2|", taper.mm(), u.mm()),
                "check R's sign: the radius at the cut's start minus the radius at its end",
            );
            return None;
        }
        Some(())
    }

    /// The machine's chamfer at the thread's end (`chamfer` tenths of the lead, at 45°
    /// towards the start X), which must fit between the thread and the start point.
    fn cycle_exit(
        &mut self,
        line: Line<'_>,
        chamfer: u32,
        lead: Lead,
        p: CyclePass,
        whole: Range<usize>,
    ) -> Option<Option<Chamfer>> {
        if chamfer == 0 {
            return Some(None);
        }
        let CyclePass {
            sx,
            sz,
            x,
            end_z,
            taper,
        } = p;
        let length = lead.length_times(i64::from(chamfer), 10);
        // On a taper the chamfer's geometry (45° from where it leaves the taper?) is in
        // no source ncthread holds.
        if taper.0 != 0 {
            self.error(
                codes::FANR_G92_CHAMFER,
                line,
                whole,
                "a tapered G92 (R) on a machine whose G92 chamfers the thread's end: where that chamfer leaves the taper and at which angle, no source ncthread holds says".into(),
                "cut the taper thread with G32 passes, or set `thread_chamfer_0p1_lead = 0` if the machine does not chamfer",
            );
            return None;
        }
        // The chamfer is part of the retract towards the start X: past it, what the
        // control does is not documented.
        if 2 * length.0.unsigned_abs() > (sx - x).0.unsigned_abs() {
            self.error(
                codes::FANR_G92_CHAMFER,
                line,
                whole,
                format!("the machine's thread chamfer ({} mm at 45°, {} mm on the diameter) goes past the cycle's start X{}", length.mm(), (length + length).mm(), sx.mm()),
                "start the cycle further from the thread (X at least the thread's diameter plus twice the chamfer)",
            );
            return None;
        }
        if length >= (end_z - sz).abs() {
            self.error(
                codes::FANR_G92_CHAMFER,
                line,
                whole,
                format!("the machine's thread chamfer ({} mm, {chamfer} tenths of the lead) is as long as the thread", length.mm()),
                "check `thread_chamfer_0p1_lead` in the profile",
            );
            return None;
        }
        // At 45°, away from the thread towards the start X.
        let out = if sx >= x { 1 } else { -1 };
        Some(Some(Chamfer {
            length,
            offset: Length(out * 2 * length.0),
        }))
    }

    /// An arc's end and centre: I (a radius value) and K from the start, or R (up to half a
    /// circle). The end must lie on the circle within 0.002 mm. **\[decided\]**
    fn arc<'w>(
        &mut self,
        line: Line<'_>,
        get: &dyn Fn(char) -> Option<&'w Word>,
        from: Pos,
        to: Pos,
        clockwise: bool,
        whole: Range<usize>,
    ) -> Option<(Pos, Pos)> {
        let code = if clockwise { "G02" } else { "G03" };
        let Some((sx, sz)) = from.known() else {
            self.error(
                codes::FANR_UNKNOWN_POSITION,
                line,
                whole,
                format!("{code} from a position that is not known yet: the arc's centre cannot be placed"),
                "move to an absolute X and Z before the arc",
            );
            return None;
        };
        let (ex, ez) = (to.x.unwrap_or(sx), to.z.unwrap_or(sz));
        let centre = self.arc_centre(line, get, (sx, sz), (ex, ez), clockwise, whole.clone())?;
        let (cx, cz) = centre.known()?;
        let (r1, r2) = lower::arc::radii((sx, sz), (ex, ez), (cx, cz));
        if r1 < 0.001 || r2 < 0.001 {
            self.error(
                codes::FANR_ARC,
                line,
                whole,
                format!("{code} with a zero radius: its centre is on its start or its end"),
                "check I and K: the centre's offset from the arc's start (I as a radius)",
            );
            return None;
        }
        if (r1 - r2).abs() > 0.002 {
            self.error(
                codes::FANR_ARC,
                line,
                whole,
                format!(
                    "{code}'s end is not on its circle: the radius is {} mm at the start and {} mm at the end",
                    Length::from_mm_f64(r1).mm(),
                    Length::from_mm_f64(r2).mm()
                ),
                "check I and K (I is the centre's X offset as a radius)",
            );
            return None;
        }
        Some((Pos::new(ex, ez), centre))
    }

    /// The arc's centre, given one way: I and K (I a radius value, both from the start), or R.
    fn arc_centre<'w>(
        &mut self,
        line: Line<'_>,
        get: &dyn Fn(char) -> Option<&'w Word>,
        (sx, sz): (Length, Length),
        (ex, ez): (Length, Length),
        clockwise: bool,
        whole: Range<usize>,
    ) -> Option<Pos> {
        let code = if clockwise { "G02" } else { "G03" };
        let (i, k, r) = (get('I'), get('K'), get('R'));
        let centre = match (r, i.or(k)) {
            (Some(w), Some(_)) => {
                let text = &line.text[w.range.clone()];
                self.error(
                    codes::FANR_CONFLICT,
                    line,
                    w.range.clone(),
                    format!("`{text}` with I or K: give the centre one way"),
                    "write either I and K, or R",
                );
                return None;
            }
            (Some(w), None) => self.radius_centre(line, w, (sx, sz), (ex, ez), clockwise)?,
            (None, None) => {
                self.error(
                    codes::FANR_ARC,
                    line,
                    whole,
                    format!("{code} without I, K or R"),
                    "write the centre (I as a radius value and K, from the arc's start) or the radius R",
                );
                return None;
            }
            (None, Some(_)) => {
                let iv = match i {
                    Some(w) => self.length(line, w, Unit::Axis)?,
                    None => Length::ZERO,
                };
                let kv = match k {
                    Some(w) => self.length(line, w, Unit::Axis)?,
                    None => Length::ZERO,
                };
                Pos::new(sx + iv + iv, sz + kv)
            }
        };
        Some(centre)
    }

    /// The centre of an arc of radius R (`w`), positive and up to half a circle.
    fn radius_centre(
        &mut self,
        line: Line<'_>,
        w: &Word,
        (sx, sz): (Length, Length),
        (ex, ez): (Length, Length),
        clockwise: bool,
    ) -> Option<Pos> {
        let code = if clockwise { "G02" } else { "G03" };
        let radius = self.length(line, w, Unit::Axis)?;
        let text = &line.text[w.range.clone()];
        if radius.0 <= 0 {
            self.error(
                codes::FANR_ARC,
                line,
                w.range.clone(),
                format!("`{text}`: an arc's R is positive here (an arc over half a circle with a negative R is not confirmed for a lathe)"),
                "write the arc with I and K",
            );
            return None;
        }
        if (sx, sz) == (ex, ez) {
            self.error(
                codes::FANR_ARC,
                line,
                w.range.clone(),
                format!("{code} R ends where it starts: a full circle has no R form"),
                "write the circle with I and K",
            );
            return None;
        }
        let span = self.span(line, w.range.clone());
        self.r.centre_of_radius(
            codes::FANR_ARC,
            span,
            text,
            (sx, sz),
            (ex, ez),
            radius,
            clockwise,
        )
    }
}

/// The byte range in `line` of a span on it.
fn code_range_of(line: Line<'_>, span: Span) -> Range<usize> {
    let range = span.range();
    let start = range.start.saturating_sub(line.offset).min(line.text.len());
    let end = range
        .end
        .saturating_sub(line.offset)
        .min(line.text.len())
        .max(start);
    start..end
}

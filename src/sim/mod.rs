//! The motion simulator: what the machine does with a program, as straight segments in
//! fixed-point X (diameter) and Z. It is the arbiter of "exact or refuse": it reads only the
//! IR, shares the cycle and pass geometry with the emitters through [`crate::lower`], and
//! knows nothing of any dialect's text.

mod compare;
pub mod rs274;

pub use compare::{
    Difference, TOLERANCE, compare, compare_rounded, compare_within, largest_deviation, normalise,
    phase_tolerance,
};

use crate::diag::{Diagnostic, codes};
use crate::fixed::{Angle, Lead, Length, div_round};
use crate::ir::{ItemKind, Pos, Program, SpindleDirection, SyncStart, ThreadPass};
use crate::lower;
use crate::source::{SourceFile, Span};

/// A full spindle turn in [`Angle`] units.
pub const TURN: i64 = 360_000;

/// What a segment does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Motion {
    Rapid,
    /// A linear feed at `feed`: mm per revolution, or mm per minute when `per_minute`.
    Feed {
        feed: Length,
        per_minute: bool,
    },
    /// A spindle-synchronised move: `lead` along Z per revolution, the spindle `direction`,
    /// and the `phase`: the spindle angle at which the tool is (or would be, on the line
    /// extended) at Z = 0. Two passes with equal lead, direction and phase cut the same helix.
    /// `None` when the start Z is unknown.
    Sync {
        lead: Lead,
        direction: Option<SpindleDirection>,
        phase: Option<Angle>,
    },
    /// A rigid tap to `to.z` and back to `from.z`, the spindle reversing at the bottom.
    Tap {
        lead: Lead,
        direction: Option<SpindleDirection>,
    },
    /// A spindle-synchronised move along X only (G76's infeed before an entry taper, a G33
    /// that moves only X): `advance` along X (per side) per revolution; `start_angle` the
    /// spindle angle after the index pulse at which it starts, `None` when it continues a
    /// synchronised move.
    SyncRadial {
        advance: Lead,
        direction: Option<SpindleDirection>,
        start_angle: Option<Angle>,
    },
    /// A circular feed around `centre` (X a diameter): G2 (`clockwise`) or G3 in the ZX
    /// plane, at `feed` as for [`Motion::Feed`]. `from` = `to` is a full circle.
    Arc {
        centre: Pos,
        clockwise: bool,
        feed: Length,
        per_minute: bool,
    },
    /// The machine state changed where the tool stands (`from` = `to`): coolant, spindle
    /// direction, speed and speed mode, after the command.
    State(MachineState),
    /// A programmed stop (M0) or an optional stop (M1).
    Stop {
        optional: bool,
    },
    /// A dwell, in 0.0001 s.
    Dwell {
        time: i64,
    },
    /// A block kept as written that the control runs by its own rules (a FANUC canned
    /// cycle): `text` is a hash of its words, so that two programs agree only where they keep
    /// the same block. The position after it is unknown.
    Kept {
        text: u64,
    },
    /// The tool stands where a synchronised move ended, in the cut, while the spindle turns
    /// until the index pulse (and the start angle after it): a pass that waits for the
    /// index right where another ended (`from` = `to`).
    IndexWait,
}

/// What the machine is doing besides moving: compared, in order with the motion, so that a
/// conversion that drops coolant or turns a surface speed into rpm is not equivalent.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MachineState {
    pub mist: bool,
    pub flood: bool,
    pub direction: Option<SpindleDirection>,
    /// The last S: rpm, or under a surface speed m/min.
    pub speed: Option<u32>,
    /// A surface speed (G96) is in force, with its rpm limit in 0.001 rpm (`None`: none).
    pub surface_speed: Option<Option<i64>>,
    /// The surface speed's S is in feet per minute (G96 under G20), else m/min.
    pub surface_feet: bool,
    /// The work offset in force: 0 for the default (G54), 1 … 8 for G55 … G59.3.
    pub work_offset: u8,
    /// Cutter radius compensation in force. The path compared stays the programmed one
    /// (the tool's radius is the machine's), so both sides must compensate alike.
    pub compensation: Option<crate::ir::Compensation>,
    /// The tool the last tool change put in the spindle or turret (`None`: none yet). Its
    /// offsets are the machine's.
    pub tool: Option<u32>,
}

impl MachineState {
    /// `coolant off, spindle M3 at S800 rpm`.
    pub fn describe(&self) -> String {
        let coolant = match (self.mist, self.flood) {
            (false, false) => "coolant off",
            (true, false) => "mist on",
            (false, true) => "flood on",
            (true, true) => "mist and flood on",
        };
        let spindle = match self.direction {
            Some(SpindleDirection::Clockwise) => "spindle M3",
            Some(SpindleDirection::CounterClockwise) => "spindle M4",
            None => "spindle stopped",
        };
        let speed = match (self.speed, self.surface_speed) {
            (None, None) => String::new(),
            (Some(s), None) => format!(" at S{s} rpm"),
            (s, Some(limit)) => format!(
                " at a surface speed of {} {}{}",
                s.map_or("?".into(), |s| s.to_string()),
                if self.surface_feet { "ft/min" } else { "m/min" },
                limit.map_or(String::new(), |l| format!(
                    " up to {} rpm",
                    Length::from_steps(l * 10).mm()
                ))
            ),
        };
        let offset = match self.work_offset {
            0 => String::new(),
            n @ 1..=5 => format!(", work offset G{}", 54 + n),
            n => format!(", work offset G59.{}", n - 5),
        };
        let compensation = match self.compensation {
            None => "",
            Some(crate::ir::Compensation::FromTool { right: false, .. })
            | Some(crate::ir::Compensation::Dynamic { right: false, .. }) => ", compensation left",
            Some(_) => ", compensation right",
        };
        let tool = self.tool.map_or(String::new(), |t| format!(", tool T{t}"));
        format!("{coolant}, {spindle}{speed}{offset}{compensation}{tool}")
    }
}

impl Motion {
    /// The JSON of an event that happens where the tool stands: a stop, a dwell, a kept block.
    fn event_json(&self) -> serde_json::Value {
        match *self {
            Motion::Stop { optional } => serde_json::json!({
                "motion": if optional { "optional-stop" } else { "stop" },
            }),
            Motion::Dwell { time } => serde_json::json!({
                "motion": "dwell",
                "seconds": time as f64 / 10_000.0,
            }),
            Motion::Kept { text } => serde_json::json!({
                "motion": "kept",
                "block": format!("{text:016x}"),
            }),
            _ => serde_json::Value::Null,
        }
    }

    /// Whether the tool moves (a coolant command, a stop or a dwell happens where it
    /// stands, wherever that is).
    pub fn moves(&self) -> bool {
        !matches!(
            self,
            Motion::State(_) | Motion::Stop { .. } | Motion::Dwell { .. } | Motion::Kept { .. }
        )
    }
}

/// One move: straight, or an arc (its centre in the motion).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Segment {
    pub motion: Motion,
    pub from: Pos,
    pub to: Pos,
    /// The source line of the item it comes from.
    pub line: u32,
    /// The pass number inside a thread cycle.
    pub pass: Option<usize>,
}

/// Something the simulator could not know.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Problem {
    /// The item it concerns.
    pub span: Span,
    pub message: String,
    /// The tool stands in the cut waiting for the index pulse (not a missing position).
    pub index_wait: bool,
}

impl Problem {
    /// As a warning diagnostic pointing into `src` (the program the simulation came from).
    pub fn diagnostic(&self, src: &SourceFile) -> Diagnostic {
        if self.index_wait {
            return Diagnostic::new(codes::SIM_INDEX_WAIT, self.message.clone())
                .at(src, self.span)
                .help("the pass waits for the spindle's index pulse where the thread move before it ended, so the tool stands in the cut for up to a turn; retract and return between the moves, or write them as one block (entry E, runout J)");
        }
        Diagnostic::new(codes::SIM_UNKNOWN, self.message.clone())
            .at(src, self.span)
            .help("move to a known position with absolute X and Z before this, so that the motion can be checked")
    }
}

/// The motion of a program, and what could not be determined.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Simulation {
    pub segments: Vec<Segment>,
    pub problems: Vec<Problem>,
}

struct Machine {
    pos: Pos,
    /// G94 in force (feeds per revolution until a program says otherwise).
    per_minute: bool,
    direction: Option<SpindleDirection>,
    /// Where the last synchronised segment ended and the spindle angle there, while the
    /// next one may continue it without waiting for the index pulse.
    sync_end: Option<(Pos, Angle)>,
    /// Coolant and spindle.
    state: MachineState,
    out: Simulation,
    /// Keep the segments (`false`: only the problems, for `check`).
    record: bool,
}

/// The spindle angle at Z = 0 of a synchronised move through `z` at spindle angle `angle`,
/// travelling towards `towards` (the sign of its Z travel).
fn phase_at_zero(z: Length, angle: Angle, lead: Lead, towards: i64) -> Angle {
    // Travelling towards -Z the spindle turns 360° per lead from z down to 0, so the angle
    // at 0 is angle + 360·z/lead; travelling towards +Z it is angle − 360·z/lead.
    Angle((angle.0 - towards * turned(z, lead)).rem_euclid(TURN))
}

/// The spindle angle (0.001° units, not reduced) that `z` of travel takes at `lead`.
fn turned(z: Length, lead: Lead) -> i64 {
    let num = z.0 as i128 * TURN as i128 * Lead::PER_LENGTH as i128;
    (div_round(num, lead.0.max(1) as i128) % TURN as i128) as i64
}

/// The spindle angle at `z` on a helix with phase `phase` (the inverse of
/// [`phase_at_zero`]).
pub(crate) fn angle_at(z: Length, phase: Angle, lead: Lead, towards: i64) -> Angle {
    Angle((phase.0 + towards * turned(z, lead)).rem_euclid(TURN))
}

impl Machine {
    fn new(pos: Pos) -> Machine {
        Machine {
            pos,
            per_minute: false,
            direction: None,
            sync_end: None,
            state: MachineState::default(),
            out: Simulation::default(),
            record: true,
        }
    }

    /// Records a segment (unless only the problems are wanted).
    fn keep(&mut self, segment: Segment) {
        if self.record {
            self.out.segments.push(segment);
        }
    }

    /// A change of the machine state, as an event where the tool stands (none when nothing
    /// changes).
    fn change(&mut self, state: MachineState, span: Span) {
        if state != self.state {
            self.state = state;
            self.event(Motion::State(state), span);
        }
    }

    /// Something the machine does where the tool stands.
    fn event(&mut self, motion: Motion, span: Span) {
        self.keep(Segment {
            motion,
            from: self.pos,
            to: self.pos,
            line: span.line,
            pass: None,
        });
    }

    fn problem(&mut self, span: Span, message: impl Into<String>) {
        self.out.problems.push(Problem {
            span,
            message: message.into(),
            index_wait: false,
        });
    }

    fn segment(&mut self, motion: Motion, to: Pos, span: Span, pass: Option<usize>) {
        let to = Pos {
            x: to.x.or(self.pos.x),
            z: to.z.or(self.pos.z),
        };
        if to == self.pos && !matches!(motion, Motion::Tap { .. } | Motion::Arc { .. }) {
            return;
        }
        let from = self.pos;
        if !matches!(motion, Motion::Rapid) && from.known().is_none() {
            self.problem(
                span,
                "the move starts from a position that is not known: its path cannot be compared",
            );
        }
        self.keep(Segment {
            motion,
            from,
            to,
            line: span.line,
            pass,
        });
        if !matches!(motion, Motion::Tap { .. }) {
            self.pos = to;
        }
        if !matches!(motion, Motion::Sync { .. }) {
            self.sync_end = None;
        }
    }

    fn thread_pass(&mut self, pass: &ThreadPass, span: Span, number: Option<usize>) {
        if self.direction.is_none() {
            self.problem(span, "a thread pass while the spindle is not turning");
        }
        let segments = match lower::pass_segments(self.pos, pass) {
            Ok(s) => s,
            Err(_) => {
                self.problem(
                    span,
                    "the thread pass needs its start point, which is not known",
                );
                self.pos = pass.end_position(self.pos);
                self.sync_end = None;
                return;
            }
        };
        for (i, seg) in segments.into_iter().enumerate() {
            // The pass's first move starts as the pass says; the rest of the pass (entry,
            // thread, runout) is one synchronised motion.
            let start = if i == 0 {
                pass.start
            } else {
                SyncStart::Continue
            };
            let start_angle = self.start_angle(start, &seg, span, number);
            if seg.is_radial() {
                let continues = matches!(start, SyncStart::Continue);
                self.sync_radial(&seg, start_angle, continues, span, number);
            } else {
                self.sync_along(&seg, start_angle, span, number);
            }
        }
    }

    /// The spindle angle a synchronised move starts at: where the last one ended (it
    /// continues it), or the index pulse's angle (after the tool stood in the cut waiting
    /// for it, if a thread move ended there).
    fn start_angle(
        &mut self,
        start: SyncStart,
        seg: &lower::SyncSegment,
        span: Span,
        number: Option<usize>,
    ) -> Option<Angle> {
        let continued = self.sync_end.filter(|(end, _)| *end == seg.from);
        match start {
            SyncStart::Continue => match continued {
                Some((_, angle)) => Some(angle),
                None => {
                    self.problem(
                        span,
                        "the thread move continues a synchronised move, but none ended where it starts",
                    );
                    None
                }
            },
            SyncStart::Index(angle) => {
                if continued.is_some() {
                    // It waits for the index pulse where the last synchronised move
                    // ended: the tool stands in the cut while the spindle turns.
                    self.out.problems.push(Problem {
                        span,
                        message: "the tool stands in the cut until the index pulse: this pass starts where the thread move before it ended".into(),
                        index_wait: true,
                    });
                    self.keep(Segment {
                        motion: Motion::IndexWait,
                        from: seg.from,
                        to: seg.from,
                        line: span.line,
                        pass: number,
                    });
                }
                Some(angle)
            }
        }
    }

    /// A synchronised infeed (along X); the spindle turns (|ΔX|/2) / advance revolutions
    /// on the way.
    fn sync_radial(
        &mut self,
        seg: &lower::SyncSegment,
        start_angle: Option<Angle>,
        continues: bool,
        span: Span,
        number: Option<usize>,
    ) {
        self.segment(
            Motion::SyncRadial {
                advance: seg.lead,
                direction: self.direction,
                start_angle: if continues { None } else { start_angle },
            },
            seg.to,
            span,
            number,
        );
        self.sync_end = match (start_angle, seg.from.x, seg.to.x) {
            (Some(angle), Some(x0), Some(x1)) => {
                let side = Length::from_steps((x1 - x0).0.abs() / Length::STEP / 2);
                Some((
                    self.pos,
                    Angle((angle.0 + turned(side, seg.lead)).rem_euclid(TURN)),
                ))
            }
            _ => None,
        };
    }

    /// A thread move along the helix: its phase is the spindle angle at Z0.
    fn sync_along(
        &mut self,
        seg: &lower::SyncSegment,
        start_angle: Option<Angle>,
        span: Span,
        number: Option<usize>,
    ) {
        let towards = match (seg.from.z, seg.to.z) {
            (Some(a), Some(b)) => (b - a).signum(),
            _ => 0,
        };
        let phase = match (seg.from.z, start_angle) {
            (Some(z), Some(angle)) if towards != 0 => {
                Some(phase_at_zero(z, angle, seg.lead, towards))
            }
            _ => None,
        };
        self.segment(
            Motion::Sync {
                lead: seg.lead,
                direction: self.direction,
                phase,
            },
            seg.to,
            span,
            number,
        );
        self.sync_end = match (phase, seg.to.z) {
            (Some(phase), Some(z)) => Some((self.pos, angle_at(z, phase, seg.lead, towards))),
            _ => None,
        };
    }

    fn item(&mut self, kind: &ItemKind, span: Span) {
        if let Some(moves) = kind.cycle_moves() {
            for m in moves {
                self.item(m, span);
            }
            return;
        }
        match kind {
            ItemKind::Rapid { to } => self.segment(Motion::Rapid, *to, span, None),
            ItemKind::Feed { to, feed } => {
                let per_minute = self.per_minute;
                self.segment(
                    Motion::Feed {
                        feed: *feed,
                        per_minute,
                    },
                    *to,
                    span,
                    None,
                )
            }
            ItemKind::Arc {
                to,
                centre,
                clockwise,
                feed,
            } => {
                let motion = Motion::Arc {
                    centre: **centre,
                    clockwise: *clockwise,
                    feed: *feed,
                    per_minute: self.per_minute,
                };
                self.segment(motion, *to, span, None)
            }
            ItemKind::ThreadPass(pass) => self.thread_pass(pass, span, None),
            ItemKind::ThreadCycle(cycle) => self.thread_cycle(cycle, kind, span),
            ItemKind::TapCycle(tap) => self.tap_cycle(tap, span),
            ItemKind::Spindle { speed, direction } => self.spindle(*speed, *direction, span),
            ItemKind::SpindleStop => {
                self.direction = None;
                let state = MachineState {
                    direction: None,
                    ..self.state
                };
                self.change(state, span);
            }
            ItemKind::ProgramEnd(_) => self.program_end(span),
            ItemKind::Coolant(c) => self.coolant(*c, span),
            ItemKind::Tool {
                number: Some(n), ..
            } => self.change_state(span, |s| s.tool = Some(*n)),
            ItemKind::Compensation(c) => self.change_state(span, |s| {
                s.compensation = (*c != crate::ir::Compensation::Off).then_some(*c)
            }),
            ItemKind::WorkOffset(n) => {
                self.change_state(span, |s| s.work_offset = n.saturating_sub(1))
            }
            ItemKind::MachineMove(crate::ir::MachineMove::StoreHome { .. }) => {}
            ItemKind::MachineMove(m) => self.machine_move(m, kind, span),
            ItemKind::SpindleMode(mode) => self.spindle_mode(mode, span),
            ItemKind::Stop { optional } => self.event(
                Motion::Stop {
                    optional: *optional,
                },
                span,
            ),
            ItemKind::Dwell { seconds } => {
                let time = (seconds.to_f64() * 10_000.0).round() as i64;
                self.event(Motion::Dwell { time }, span);
            }
            ItemKind::FeedMode(mode) => self.per_minute = *mode == crate::ir::FeedMode::PerMin,
            ItemKind::Opaque {
                block: Some(c),
                text,
                ..
            } => self.kept(text, c, span),
            _ => {}
        }
    }

    /// A block kept as written: a cycle is recorded (its words, so that two programs agree
    /// only where they keep the same block); one that may move leaves the position unknown.
    fn kept(&mut self, text: &str, c: &crate::ir::ModalContext, span: Span) {
        if c.cycle {
            self.event(
                Motion::Kept {
                    text: kept_hash(text),
                },
                span,
            );
        }
        if c.moves {
            self.pos = Pos::UNKNOWN;
        }
        self.sync_end = None;
    }

    /// The machine's state as `edit` changes it.
    fn change_state(&mut self, span: Span, edit: impl FnOnce(&mut MachineState)) {
        let mut state = self.state;
        edit(&mut state);
        self.change(state, span);
    }

    /// A threading cycle, as the passes and rapids it expands to (`kind`: the item, for
    /// where it ends when it cannot be expanded).
    fn thread_cycle(&mut self, cycle: &crate::ir::ThreadCycle, kind: &ItemKind, span: Span) {
        match lower::expand(cycle) {
            Ok(expansion) => {
                for m in &expansion.moves {
                    let pass = (m.pass > 0).then_some(m.pass);
                    match &m.kind {
                        lower::Move::Pass(p) => self.thread_pass(p, span, pass),
                        lower::Move::Rapid(to) => self.segment(Motion::Rapid, *to, span, pass),
                    }
                }
            }
            Err(e) => {
                let message = e.message(cycle);
                self.problem(span, message);
                self.pos = kind.end_position(self.pos);
            }
        }
    }

    /// A tapping cycle: the tap to its end Z, then the rapid out in X if it has one.
    fn tap_cycle(&mut self, tap: &crate::ir::TapCycle, span: Span) {
        if self.pos.z.is_none() {
            self.problem(span, "the tapping cycle starts from a Z that is not known");
        }
        if self.direction.is_none() {
            self.problem(span, "a tapping cycle while the spindle is not turning");
        }
        self.segment(
            Motion::Tap {
                lead: tap.lead,
                direction: self.direction,
            },
            Pos {
                x: None,
                z: Some(tap.end_z),
            },
            span,
            None,
        );
        if let Some(x) = tap.then_x {
            self.segment(
                Motion::Rapid,
                Pos {
                    x: Some(x),
                    z: None,
                },
                span,
                None,
            );
        }
    }

    /// The spindle started, or its speed or direction changed.
    fn spindle(&mut self, speed: Option<u32>, direction: Option<SpindleDirection>, span: Span) {
        if direction.is_some() {
            self.direction = direction;
        }
        let mut state = self.state;
        state.direction = self.direction;
        if speed.is_some() {
            state.speed = speed;
        }
        self.change(state, span);
    }

    /// LinuxCNC's program end stops the spindle, turns the coolant off and goes back to
    /// rpm; so does every control here.
    fn program_end(&mut self, span: Span) {
        self.direction = None;
        let state = MachineState {
            mist: false,
            flood: false,
            direction: None,
            surface_speed: None,
            surface_feet: false,
            work_offset: 0,
            compensation: None,
            ..self.state
        };
        self.change(state, span);
    }

    /// Mist or flood on, or both off.
    fn coolant(&mut self, c: crate::ir::Coolant, span: Span) {
        let mut state = self.state;
        match c {
            crate::ir::Coolant::Mist => state.mist = true,
            crate::ir::Coolant::Flood => state.flood = true,
            crate::ir::Coolant::Off => (state.mist, state.flood) = (false, false),
        }
        self.change(state, span);
    }

    /// A move in the machine's coordinates: the rapid via its intermediate point, if it
    /// has one, then a rapid to where the machine's coordinates put the tool (unknown here).
    fn machine_move(&mut self, m: &crate::ir::MachineMove, kind: &ItemKind, span: Span) {
        if let crate::ir::MachineMove::Home { via, .. } = m
            && *via != Pos::UNKNOWN
        {
            self.segment(Motion::Rapid, *via, span, None);
        }
        let to = kind.end_position(self.pos);
        self.keep(Segment {
            motion: Motion::Rapid,
            from: self.pos,
            to,
            line: span.line,
            pass: None,
        });
        self.pos = to;
        self.sync_end = None;
    }

    /// Constant surface speed (its spindle limit kept in thousandths) or back to rpm.
    fn spindle_mode(&mut self, mode: &crate::ir::SpindleMode, span: Span) {
        let (surface_speed, surface_feet) = match mode {
            crate::ir::SpindleMode::Rpm => (None, false),
            crate::ir::SpindleMode::SurfaceSpeed { limit, feet } => (
                Some(limit.map(|d| (d.to_f64() * 1000.0).round() as i64)),
                *feet,
            ),
        };
        let state = MachineState {
            surface_speed,
            surface_feet,
            ..self.state
        };
        self.change(state, span);
    }
}

/// `X35.6 Z-47.5`, with `?` for an unknown axis.
pub fn show_pos(p: Pos) -> String {
    let axis = |v: Option<Length>| v.map_or("?".to_string(), |v| v.mm());
    format!("X{} Z{}", axis(p.x), axis(p.z))
}

impl Segment {
    /// The spindle angle at `z` on the helix of a thread move (`None` for other moves, or
    /// when its phase is unknown).
    pub fn spindle_angle_at(&self, z: Length) -> Option<Angle> {
        let Motion::Sync {
            lead,
            phase: Some(phase),
            ..
        } = self.motion
        else {
            return None;
        };
        let towards = match (self.from.z, self.to.z) {
            (Some(a), Some(b)) => (b - a).signum(),
            _ => return None,
        };
        Some(angle_at(z, phase, lead, towards))
    }

    /// One line of text: `line 14 pass 1  thread  X35.6 Z4.5 → X35.6 Z-47.5  lead 1.5 M3 phase 0°`.
    pub fn to_text(&self) -> String {
        let pos = show_pos;
        let dir = |d: Option<SpindleDirection>| d.map_or("spindle stopped", SpindleDirection::code);
        let (name, extra) = match self.motion {
            Motion::Rapid => ("rapid", String::new()),
            Motion::Feed { feed, per_minute } => (
                "feed",
                format!(
                    "  feed {} {}",
                    feed.mm(),
                    if per_minute { "mm/min" } else { "mm/rev" }
                ),
            ),
            Motion::Sync {
                lead,
                direction,
                phase,
            } => (
                "thread",
                format!(
                    "  lead {} {} phase {}",
                    lead.mm(),
                    dir(direction),
                    phase.map_or("unknown".to_string(), |p| format!("{p}°"))
                ),
            ),
            Motion::Tap { lead, direction } => (
                "tap",
                format!("  lead {} {} and back", lead.mm(), dir(direction)),
            ),
            Motion::SyncRadial {
                advance,
                direction,
                start_angle,
            } => (
                "infeed",
                format!(
                    "  synchronised, {} per rev along X {}{}",
                    advance.mm(),
                    dir(direction),
                    start_angle.map_or(String::new(), |a| format!(" from the index pulse + {a}°"))
                ),
            ),
            Motion::Arc {
                centre,
                clockwise,
                feed,
                per_minute,
            } => (
                if clockwise { "arc G2" } else { "arc G3" },
                format!(
                    "  centre {}  feed {} {}",
                    pos(centre),
                    feed.mm(),
                    if per_minute { "mm/min" } else { "mm/rev" }
                ),
            ),
            Motion::IndexWait => ("wait", "  in the cut for the index pulse".to_string()),
            Motion::State(state) => ("state", format!("  {}", state.describe())),
            Motion::Stop { optional } => (
                if optional { "optional stop" } else { "stop" },
                String::new(),
            ),
            Motion::Dwell { time } => ("dwell", format!("  {} s", Length::from_steps(time).mm())),
            Motion::Kept { text } => (
                "kept",
                format!("  a block the control runs by its own rules (#{text:016x})"),
            ),
        };
        let pass = self.pass.map_or(String::new(), |p| format!(" pass {p}"));
        format!(
            "line {}{pass}  {name}  {} → {}{extra}",
            self.line,
            pos(self.from),
            pos(self.to)
        )
    }

    /// One JSON object: line, pass, motion, from, to (mm, X a diameter), and lead, feed,
    /// spindle direction and phase (degrees) where they apply.
    pub fn to_json(&self) -> serde_json::Value {
        let num = |v: Length| serde_json::json!(v.to_mm_f64());
        let pos = |p: Pos| serde_json::json!({ "x": p.x.map(num), "z": p.z.map(num) });
        let dir = |d: Option<SpindleDirection>| d.map(SpindleDirection::code);
        let mut v = serde_json::json!({
            "line": self.line,
            "pass": self.pass,
            "from": pos(self.from),
            "to": pos(self.to),
        });
        let extra = match self.motion {
            Motion::Rapid => serde_json::json!({ "motion": "rapid" }),
            Motion::Feed { feed, per_minute } => serde_json::json!({
                "motion": "feed",
                "feed": num(feed),
                "feed_unit": if per_minute { "mm/min" } else { "mm/rev" },
            }),
            Motion::Sync {
                lead,
                direction,
                phase,
            } => serde_json::json!({
                "motion": "thread",
                "lead": lead.to_mm_f64(),
                "spindle": dir(direction),
                "phase": phase.map(|p| p.to_deg_f64()),
            }),
            Motion::Tap { lead, direction } => serde_json::json!({
                "motion": "tap",
                "lead": lead.to_mm_f64(),
                "spindle": dir(direction),
            }),
            Motion::SyncRadial {
                advance,
                direction,
                start_angle,
            } => serde_json::json!({
                "motion": "infeed",
                "advance": advance.to_mm_f64(),
                "spindle": dir(direction),
                "start_angle": start_angle.map(|a| a.to_deg_f64()),
            }),
            Motion::Arc {
                centre,
                clockwise,
                feed,
                per_minute,
            } => serde_json::json!({
                "motion": if clockwise { "arc-cw" } else { "arc-ccw" },
                "centre": pos(centre),
                "feed": num(feed),
                "feed_unit": if per_minute { "mm/min" } else { "mm/rev" },
            }),
            Motion::IndexWait => serde_json::json!({ "motion": "index-wait" }),
            Motion::State(state) => serde_json::json!({
                "motion": "state",
                "mist": state.mist,
                "flood": state.flood,
                "spindle": dir(state.direction),
                "speed": state.speed,
                "surface_speed": state.surface_speed.is_some(),
                "rpm_limit": state.surface_speed.flatten().map(|l| l as f64 / 1000.0),
                "work_offset": state.work_offset + 1,
            }),
            Motion::Stop { .. } | Motion::Dwell { .. } | Motion::Kept { .. } => {
                self.motion.event_json()
            }
        };
        if let (Some(v), serde_json::Value::Object(extra)) = (v.as_object_mut(), extra) {
            v.extend(extra);
        }
        v
    }
}

/// Runs `program` from an unknown position with the spindle stopped.
pub fn simulate(program: &Program) -> Simulation {
    let mut m = Machine::new(Pos::UNKNOWN);
    for item in &program.items {
        m.item(&item.kind, item.span);
    }
    m.out
}

/// What [`simulate`] finds it cannot know, without keeping the motion (`check`: memory stays
/// small for a large program).
pub fn problems(program: &Program) -> Vec<Problem> {
    let mut finder = Problems::new();
    for item in &program.items {
        finder.item(item);
    }
    finder.finish()
}

/// [`problems`] over a program's items one at a time, in order (`check`'s streaming read).
pub struct Problems(Machine);

impl Problems {
    pub fn new() -> Problems {
        let mut m = Machine::new(Pos::UNKNOWN);
        m.record = false;
        Problems(m)
    }

    /// The program's next item.
    pub fn item(&mut self, item: &crate::ir::Item) {
        self.0.item(&item.kind, item.span);
    }

    /// The problems found since the last take, taken out.
    pub fn take(&mut self) -> std::vec::Drain<'_, Problem> {
        self.0.out.problems.drain(..)
    }

    pub fn finish(self) -> Vec<Problem> {
        self.0.out.problems
    }
}

impl Default for Problems {
    fn default() -> Self {
        Problems::new()
    }
}

/// The synchronised moves of a pass written as a chain of blocks (the first waits for the
/// index pulse, the others continue it), started at `from`, as [`simulate`] moves them: each
/// move's ends and, for a move along Z, the phase of its helix (see [`Motion::Sync`]).
pub fn chain_moves(from: Pos, chain: &[ThreadPass]) -> Vec<(Pos, Pos, Option<Angle>)> {
    let mut m = Machine::new(from);
    m.direction = Some(SpindleDirection::Clockwise);
    for pass in chain {
        m.thread_pass(pass, Span::default(), None);
    }
    m.out
        .segments
        .iter()
        .filter_map(|s| match s.motion {
            Motion::Sync { phase, .. } => Some((s.from, s.to, phase)),
            Motion::SyncRadial { .. } => Some((s.from, s.to, None)),
            _ => None,
        })
        .collect()
}

/// A kept block's words as a hash (FNV-1a), blanks and case left out: the same block
/// written `G71 P80 Q130` or `g71p80q130` is the same.
fn kept_hash(text: &str) -> u64 {
    text.bytes()
        .filter(|b| !b.is_ascii_whitespace())
        .map(|b| b.to_ascii_uppercase())
        .fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
            (h ^ u64::from(b)).wrapping_mul(0x100_0000_01b3)
        })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ir::{Item, Schedule, TapCycle};
    use crate::source::Span;

    fn mm(v: f64) -> Length {
        Length::from_mm_f64(v)
    }

    fn program(kinds: Vec<ItemKind>) -> Program {
        Program {
            dialect: crate::dialect::iso::ID,
            library: Vec::new(),
            number: None,
            inch: false,
            name: None,
            items: kinds
                .into_iter()
                .enumerate()
                .map(|(i, kind)| {
                    let span = Span {
                        line: i as u32 + 1,
                        ..Span::default()
                    };
                    Item::new(kind, span)
                })
                .collect(),
        }
    }

    fn spindle() -> ItemKind {
        ItemKind::Spindle {
            speed: Some(100),
            direction: Some(SpindleDirection::Clockwise),
        }
    }

    fn pass(x: f64, z: f64, lead: f64, angle: i64) -> ItemKind {
        ItemKind::pass(ThreadPass {
            to: Pos::new(mm(x), mm(z)),
            lead: Lead::from_mm_f64(lead).unwrap(),
            start: SyncStart::Index(Angle::from_deg(angle)),
            infeed: None,
            entry: None,
            exit: None,
        })
    }

    fn rapid(x: f64, z: f64) -> ItemKind {
        ItemKind::Rapid {
            to: Pos::new(mm(x), mm(z)),
        }
    }

    fn phase(s: &Segment) -> Option<Angle> {
        match s.motion {
            Motion::Sync { phase, .. } => phase,
            _ => None,
        }
    }

    #[test]
    fn phase_is_the_spindle_angle_at_z0() {
        // From Z3 towards -Z, lead 1.5, at the index pulse: at Z0 the spindle has turned
        // 2 revolutions → phase 0. From Z3.75: 2.5 revolutions → 180°.
        let sim = simulate(&program(vec![
            spindle(),
            rapid(26.0, 3.0),
            pass(26.0, -9.0, 1.5, 0),
            rapid(26.0, 3.75),
            pass(26.0, -9.0, 1.5, 0),
            rapid(26.0, 3.0),
            pass(26.0, -9.0, 1.5, 180),
        ]));
        assert!(sim.problems.is_empty(), "{:?}", sim.problems);
        let phases: Vec<_> = sim.segments.iter().filter_map(phase).collect();
        assert_eq!(
            phases,
            vec![Angle::ZERO, Angle::from_deg(180), Angle::from_deg(180)]
        );
    }

    #[test]
    fn consecutive_sync_segments_keep_the_spindle_turning() {
        // A runout: the second segment continues the first, so its phase is the same helix.
        let sim = simulate(&program(vec![
            spindle(),
            rapid(64.0, 5.0),
            ItemKind::pass(ThreadPass {
                to: Pos::new(mm(64.0), mm(-100.0)),
                lead: Lead::from_mm_f64(6.0).unwrap(),
                start: SyncStart::default(),
                infeed: None,
                entry: None,
                exit: Some(crate::ir::Chamfer {
                    length: mm(12.0),
                    offset: mm(8.0),
                }),
            }),
        ]));
        let phases: Vec<_> = sim.segments.iter().filter_map(phase).collect();
        // 5 / 6 of a turn before Z0 → 300°.
        assert_eq!(phases, vec![Angle::from_deg(300), Angle::from_deg(300)]);
    }

    #[test]
    fn cycles_run_through_expand_with_pass_numbers_and_taps_return() {
        let cycle = crate::lower::seed_m36_cycle(Schedule::Halving);
        let sim = simulate(&program(vec![
            spindle(),
            rapid(36.0, 4.5),
            ItemKind::ThreadCycle(Box::new(cycle)),
            rapid(0.0, 6.0),
            ItemKind::TapCycle(TapCycle {
                end_z: mm(-100.0),
                lead: Lead::from_mm_f64(1.5).unwrap(),
                then_x: Some(mm(20.0)),
            }),
        ]));
        assert!(sim.problems.is_empty(), "{:?}", sim.problems);
        let passes: Vec<_> = sim
            .segments
            .iter()
            .filter(|s| matches!(s.motion, Motion::Sync { .. }))
            .map(|s| (s.pass, s.from.x))
            .collect();
        assert_eq!(passes.len(), 8);
        assert_eq!(passes[7], (Some(8), Some(mm(34.08))));
        let tap = sim
            .segments
            .iter()
            .find(|s| matches!(s.motion, Motion::Tap { .. }))
            .unwrap();
        assert_eq!(
            (tap.from, tap.to),
            (Pos::new(mm(0.0), mm(6.0)), Pos::new(mm(0.0), mm(-100.0)))
        );
        // After the tap the tool is back at Z6 and moves to Ø20.
        assert_eq!(sim.segments.last().unwrap().to, Pos::new(mm(20.0), mm(6.0)));
    }

    #[test]
    fn unknown_positions_are_reported() {
        let sim = simulate(&program(vec![spindle(), pass(30.0, -20.0, 1.5, 0)]));
        assert_eq!(sim.problems.len(), 1);
        assert_eq!(sim.problems[0].span.line, 2);
        assert_eq!(phase(&sim.segments[0]), None);
    }
}

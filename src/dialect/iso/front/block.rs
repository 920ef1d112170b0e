//! The block interpreter, shaped as LinuxCNC's (`interp_convert.cc`: `execute_block`, then
//! `convert_m` and `convert_g`): the line's words are sorted first ([`FrontEnd::sort_words`],
//! then [`Asks::fill`]: what the block asks of each modal group), then one step per group
//! runs, in one order. A step reads what the groups before it left: the units are set
//! before every length, the spindle mode before S, the plane before compensation and motion.
//!
//! | step | group | words |
//! |------|-------|-------|
//! | [`FrontEnd::step_feed_mode`] | feed mode | G94 / G95 |
//! | [`FrontEnd::step_units`] | units | G20 / G21 |
//! | [`FrontEnd::step_feed`] | feed rate | F |
//! | [`FrontEnd::step_spindle_mode`] | spindle speed mode | G96 / G97 ([`Switches::spindle_mode`]) |
//! | [`FrontEnd::step_speed`] | spindle speed | S |
//! | [`FrontEnd::step_tool`] | tool | T, M6, G43 |
//! | [`FrontEnd::step_spindle`] | spindle | M3 / M4 ([`Switches::spindle`]), M5 ([`Switches::spindle_stop`]) |
//! | [`FrontEnd::step_coolant`] | coolant | M7 / M8 / M9 ([`Switches::coolant_on`], [`Switches::coolant_off`]) |
//! | [`FrontEnd::step_dwell`] | dwell | G4 |
//! | [`FrontEnd::step_diameter_mode`] | lathe diameter mode | G7 / G8 |
//! | [`FrontEnd::step_kept`] | path control, tool length off | G49, G61, G61.1, G64 (kept opaque) |
//! | [`FrontEnd::step_plane`] | plane | G17 / G18 |
//! | [`FrontEnd::step_compensation`] | cutter compensation | G40, G41, G42, G41.1, G42.1 |
//! | [`FrontEnd::step_coordinate_system`] | coordinate system | G54 … G59.3 |
//! | [`FrontEnd::step_distance_modes`] | distance modes | G90 / G91, G90.1 / G91.1 |
//! | [`FrontEnd::step_retract_mode`] | canned cycle return | G98 / G99 |
//! | [`FrontEnd::step_motion_mode`] | motion mode | G0 … G89, G80 |
//! | [`FrontEnd::step_offsets`] | axis offsets | G52, G92, G92.1, G92.2, G92.3 |
//! | [`FrontEnd::step_machine_move`] | home, machine coordinates | G28, G28.1, G30, G30.1, G53 |
//! | [`FrontEnd::step_motion`] | motion | X, Z and the motion's words |
//! | [`FrontEnd::step_unused_feed`] | feed rate | an F no move used |
//! | [`FrontEnd::step_stop`] | stopping | M0 / M1, M2 / M30 ([`Switches::program_end`]) |
//! | [`FrontEnd::step_unused_words`] | — | words no step read |
//!
//! LinuxCNC switches M5 and M9 before the motion, so this reader calls the shared
//! [`Switches`] steps one by one, each where LinuxCNC takes it, not
//! [`Switches::before_motion`] / [`Switches::after_motion`].

use std::ops::ControlFlow;

use super::super::gcode::*;
use super::super::syntax::{Block, Word};
use super::words::{Asks, Words};
use super::{FrontEnd, Motion};
use crate::dialect::iso::codes;
use crate::dialect::machine::Switches;
use crate::dialect::read::Reader;
use crate::fixed::Length;
use crate::ir::{
    Compensation, Coolant, EndCode, FeedMode, ItemKind, MachineMove, Pos, SpindleMode,
};
use crate::source::{Line, Span};

/// One block as the interpreter runs it: its words, what it asks of each modal group, and
/// what the earlier steps read for the later ones.
struct Interp<'l, 'b> {
    line: Line<'l>,
    words: Words<'b>,
    asks: Asks<'b>,
    /// The line's span, which most of its items are stamped with.
    span: Span,
    /// Where this line's diagnostics start (counting every error again would be quadratic
    /// in a program with many warnings).
    diags_before: usize,
    /// The units before the line's G20/G21: a surface speed's S is in them (LinuxCNC sets
    /// the speed, and its task canon the ft/min or m/min factor, before it changes units).
    inch_before: bool,
    /// The first item after the line's feed mode.
    first_item: usize,
    /// The line's F, when it was a feed.
    f_word: Option<Length>,
    /// The line's S, when it was a speed.
    speed: Option<u32>,
}

impl FrontEnd<'_> {
    /// Runs one block: reports what ncthread does not read, sorts the words, then runs the
    /// steps in LinuxCNC's order (see the module's table).
    pub(super) fn block(&mut self, line: Line<'_>, block: &Block) {
        if self.unsupported(line, block) {
            return;
        }
        // Made where they stand: the words and what the block asks are a few hundred bytes
        // each, and were moved into the interpreter's block.
        let mut b = Interp {
            line,
            words: Words::new(),
            asks: Asks::none(),
            span: self.r.src.line_span(line),
            diags_before: self.r.diags.len(),
            inch_before: self.inch,
            first_item: 0,
            f_word: None,
            speed: None,
        };
        if !self.sort_words(line, block, &mut b.words) {
            return;
        }
        b.diags_before = self.r.diags.len();
        b.asks.fill(&b.words);
        let _ = self.interpret(&mut b);
    }

    /// The steps, in LinuxCNC's order; a step that breaks ends the block there.
    fn interpret(&mut self, b: &mut Interp<'_, '_>) -> ControlFlow<()> {
        self.step_feed_mode(b);
        self.step_units(b);
        self.step_feed(b);
        self.step_spindle_mode(b)?;
        self.step_speed(b);
        self.step_tool(b);
        self.step_spindle(b);
        self.step_coolant(b);
        self.step_user_m(b);
        self.step_dwell(b);
        self.step_diameter_mode(b);
        self.step_kept(b);
        self.step_plane(b);
        self.step_compensation(b)?;
        self.step_coordinate_system(b);
        self.step_distance_modes(b);
        self.step_retract_mode(b);
        self.step_motion_mode(b);
        self.step_offsets(b);
        self.step_machine_move(b);
        self.step_motion(b);
        self.step_unused_feed(b);
        self.step_stop(b);
        self.step_unused_words(b);
        ControlFlow::Continue(())
    }

    /// Makes one of the switching steps every front end shares ([`Switches`]) with this
    /// reader's bookkeeping: an item it pushes ends a G33 chain, as [`FrontEnd::push`]'s do.
    fn switch(&mut self, step: fn(&Switches, &mut Reader<'_>, Option<u32>), switches: &Switches) {
        let before = self.r.items.len();
        step(switches, &mut self.r, None);
        if self.r.items.len() > before {
            self.sync_end = None;
        }
    }

    /// G94 / G95: the feed mode. A feed mode code also clears the feed rate, as in LinuxCNC
    /// (G1 needs a new F after it).
    fn step_feed_mode(&mut self, b: &mut Interp<'_, '_>) {
        if let Some(mode) = b.asks.feed_mode {
            self.feed_mode = Some(mode);
            self.feed = None;
            self.push(ItemKind::FeedMode(mode), b.span);
        }
    }

    /// G20 / G21, first: F, K and every length on the line are in the new units.
    fn step_units(&mut self, b: &mut Interp<'_, '_>) {
        if let Some(inch) = b.asks.inch {
            self.inch = inch;
        }
    }

    /// F: the feed rate, 0 or more.
    fn step_feed(&mut self, b: &mut Interp<'_, '_>) {
        b.first_item = self.r.items.len();
        if let Some(f) = b.words.take('F')
            && let Some(feed) = self.length(b.line, f)
        {
            if feed.0 < 0 {
                self.number_error(b.line, f, "the feed is negative".into(), "F is 0 or more");
            } else {
                self.feed = Some(feed);
                self.feed_inch = self.inch;
                b.f_word = Some(feed);
            }
        }
    }

    /// G96 / G97, before S in LinuxCNC's order. G96 needs S on its line; under G20 its S is
    /// in feet per minute (LinuxCNC's task canon: rpm = 12·S/(2π·r in)). Breaks on a G96
    /// LinuxCNC refuses.
    fn step_spindle_mode(&mut self, b: &mut Interp<'_, '_>) -> ControlFlow<()> {
        let (line, span, inch_before) = (b.line, b.span, b.inch_before);
        let has_s = b.words.other.contains_key(&'S');
        if let Some(g96) = b.asks.surface_speed {
            if !has_s {
                self.missing(
                    line,
                    g96,
                    "G96 without S (LinuxCNC: \"S word missing with G96\")".into(),
                    "give the surface speed on the G96 line: `G96 D2500 S200` (m/min, D the rpm limit)",
                );
                return ControlFlow::Break(());
            }
            let limit = b.words.take('D').map(|d| d.value);
            if limit.is_some_and(|d| d.is_negative() || d.mantissa == 0) {
                self.missing(
                    line,
                    g96,
                    "G96 with a D (the rpm limit) of 0 or less: LinuxCNC then turns at S rpm, not at a surface speed".into(),
                    "write G97 for a speed in rpm, or a positive D",
                );
                return ControlFlow::Break(());
            }
            self.surface_speed = true;
            self.surface = (limit, inch_before);
            let mode = SpindleMode::SurfaceSpeed {
                limit,
                feet: inch_before,
            };
            self.spindle_mode_item(mode, span);
        } else if self.surface_speed && self.surface.1 != inch_before && has_s && !b.asks.rpm {
            // A new S under the surface speed, in other units than its G96's: the mode again,
            // in the S's units (the limit stands). Not beside a G97: LinuxCNC sets the mode
            // before the speed (`convert_spindle_mode`, then `convert_speed`), so that the S
            // is rpm.
            self.surface.1 = inch_before;
            let mode = SpindleMode::SurfaceSpeed {
                limit: self.surface.0,
                feet: inch_before,
            };
            self.spindle_mode_item(mode, span);
        }
        if b.asks.rpm {
            self.surface_speed = false;
            self.spindle_mode_item(SpindleMode::Rpm, span);
        }
        ControlFlow::Continue(())
    }

    /// The spindle mode's item, by the shared step.
    fn spindle_mode_item(&mut self, mode: SpindleMode, span: Span) {
        let switches = Switches {
            spindle_mode: Some((mode, span)),
            ..Switches::default()
        };
        self.switch(Switches::spindle_mode, &switches);
    }

    /// S: the spindle speed, read here and switched with the direction by
    /// [`FrontEnd::step_spindle`].
    fn step_speed(&mut self, b: &mut Interp<'_, '_>) {
        b.speed = match b.words.take('S') {
            Some(s) => self.whole(b.line, s, "spindle speed"),
            None => None,
        };
    }

    /// T (the tool selected), M6 (the tool change, which stops the spindle in LinuxCNC) and
    /// G43 (the tool length offset, H or the tool's own): one tool item.
    fn step_tool(&mut self, b: &mut Interp<'_, '_>) {
        let line = b.line;
        if let Some(t) = b.words.take('T') {
            self.selected_tool = self.whole(line, t, "tool number");
        }
        let mut tool_changed = None;
        if let Some(m6) = b.asks.tool_change {
            if self.compensation {
                self.comp_refusal(
                    line,
                    m6,
                    "Cannot change tools with cutter radius compensation on",
                );
            }
            match self.selected_tool {
                Some(t) => tool_changed = Some(t),
                None => self.missing(
                    line,
                    m6,
                    "M6 without a tool selected by a T word".into(),
                    "select the tool first: `T5 M6`",
                ),
            }
        }
        let offset = if b.asks.tool_length {
            match b.words.take('H') {
                Some(h) => self.whole(line, h, "tool length offset"),
                None => tool_changed.or(self.selected_tool),
            }
        } else {
            None
        };
        if tool_changed.is_some() || offset.is_some() {
            self.push(
                ItemKind::Tool {
                    number: tool_changed,
                    offset,
                },
                b.span,
            );
            // LinuxCNC's M6 stops the spindle.
            if tool_changed.is_some() && self.turning.is_some() {
                self.turning = None;
                self.push(ItemKind::SpindleStop, b.span);
            }
        }
    }

    /// M3 / M4 with S: one spindle item; then M5.
    fn step_spindle(&mut self, b: &mut Interp<'_, '_>) {
        let (speed, direction) = (b.speed, b.asks.direction);
        if speed.is_some() || direction.is_some() {
            if speed.is_some() {
                self.speed = speed;
            }
            if direction.is_some() {
                self.turning = direction;
            }
            let switches = Switches {
                spindle: Some((speed, direction, b.span)),
                ..Switches::default()
            };
            self.switch(Switches::spindle, &switches);
        }
        if b.asks.spindle_stop {
            self.turning = None;
            let switches = Switches {
                spindle_stop: Some(b.span),
                ..Switches::default()
            };
            self.switch(Switches::spindle_stop, &switches);
        }
    }

    /// M7 / M8 / M9, stamped with the code's own word (M72 restores what they leave).
    fn step_coolant(&mut self, b: &mut Interp<'_, '_>) {
        let Some((coolant, w)) = b.asks.coolant else {
            return;
        };
        let at = self.r.span(b.line, w.range.clone());
        match coolant {
            Coolant::Mist => self.mist = true,
            Coolant::Flood => self.flood = true,
            Coolant::Off => (self.mist, self.flood) = (false, false),
        }
        let switches = Switches {
            coolant: vec![(coolant, at)],
            ..Switches::default()
        };
        self.switch(Switches::coolant_on, &switches);
        self.switch(Switches::coolant_off, &switches);
    }

    /// M100–M199: the machine's own code, which moves no axis. Its P and Q go to the
    /// machine's program: not read.
    fn step_user_m(&mut self, b: &mut Interp<'_, '_>) {
        let Some((code, w)) = b.asks.user else {
            return;
        };
        for letter in ['P', 'Q'] {
            if let Some(arg) = b.words.take(letter) {
                let text = &b.line.text[w.range.clone()];
                self.diag(
                    codes::ISOR_UNSUPPORTED,
                    b.line,
                    arg.range.clone(),
                    format!("`{letter}` beside the user M code `{text}`: its value goes to the machine's program — not read by ncthread"),
                    "write the user M code without P and Q, or keep the line out of the program ncthread converts",
                );
            }
        }
        let at = self.r.span(b.line, w.range.clone());
        self.push(
            ItemKind::MachineCode {
                code,
                machine: crate::dialect::iso::ID,
            },
            at,
        );
    }

    /// G4 P: a dwell of P seconds, 0 or more.
    fn step_dwell(&mut self, b: &mut Interp<'_, '_>) {
        let Some(g4) = b.asks.dwell else {
            return;
        };
        match b.words.take('P') {
            Some(p) if !p.value.is_negative() => {
                self.push(ItemKind::Dwell { seconds: p.value }, b.span)
            }
            Some(p) => self.number_error(
                b.line,
                p,
                "the dwell time is negative".into(),
                "G4 P is seconds, 0 or more",
            ),
            None => self.missing(
                b.line,
                g4,
                "G4 without P (the dwell time in seconds)".into(),
                "write `G4 P0.5`",
            ),
        }
    }

    /// G7 / G8: X a diameter or a radius from here on (the mode before the line is kept for
    /// a G76's I, J and K).
    fn step_diameter_mode(&mut self, b: &mut Interp<'_, '_>) {
        self.diameter_before_line = self.diameter.unwrap_or(false);
        if let Some(diameter) = b.asks.diameter {
            self.diameter = Some(diameter);
        }
    }

    /// G49, G61, G61.1, G64: changes nothing ncthread models, kept as opaque words in the
    /// line's order (G64's tolerances P and Q with it).
    fn step_kept(&mut self, b: &mut Interp<'_, '_>) {
        for &(code, w) in &b.asks.kept {
            let extra: Vec<&Word> = if code == G64 {
                ['P', 'Q'].iter().filter_map(|&l| b.words.take(l)).collect()
            } else {
                Vec::new()
            };
            self.kept(b.line, w, &extra);
        }
    }

    /// G17 / G18, before compensation and motion. A lathe program may select G17 to drill or
    /// tap along Z: its X and Z moves are the same in either.
    fn step_plane(&mut self, b: &mut Interp<'_, '_>) {
        if let Some(g17) = b.asks.plane_xy {
            if self.compensation {
                self.comp_refusal(
                    b.line,
                    g17,
                    "Cannot change planes with cutter radius compensation on",
                );
            }
            self.plane_xy = true;
        }
        if b.asks.plane_zx {
            self.plane_xy = false;
        }
    }

    /// G40 / G41 / G42 (D a tool number) / G41.1 / G42.1 (D a diameter, L the orientation).
    /// Breaks on compensation asked for in G17.
    fn step_compensation(&mut self, b: &mut Interp<'_, '_>) -> ControlFlow<()> {
        let Some((code, w)) = b.asks.compensation else {
            return ControlFlow::Continue(());
        };
        let line = b.line;
        let comp = self.compensation_asked(b, code, w);
        if self.plane_xy && code != G40 {
            let text = line.text[w.range.clone()].to_string();
            self.diag(
                codes::ISOR_COMPENSATION,
                line,
                w.range.clone(),
                format!("`{text}` while G17 is in force: LinuxCNC would compensate in the XY plane, which a lathe has not"),
                "select G18 before cutter compensation",
            );
            return ControlFlow::Break(());
        }
        if let Some(comp) = comp {
            let on = comp != Compensation::Off;
            if on && self.compensation {
                self.comp_refusal(line, w, "Cannot turn cutter radius comp on when on");
            }
            self.comp_switch(line, w, comp, self.compensation);
            self.compensation = on;
            self.ccomp = match comp {
                Compensation::FromTool { right: true, .. }
                | Compensation::Dynamic { right: true, .. } => 420.0,
                Compensation::Off => 400.0,
                _ => 410.0,
            };
            self.push(ItemKind::Compensation(comp), b.span);
        }
        ControlFlow::Continue(())
    }

    /// The compensation a G40–G42.1 asks for with its D (and L), or `None` after an error.
    fn compensation_asked(
        &mut self,
        b: &mut Interp<'_, '_>,
        code: GCode,
        w: &Word,
    ) -> Option<Compensation> {
        let (line, right) = (b.line, matches!(code, G42 | G42_1));
        match code {
            G40 => Some(Compensation::Off),
            G41 | G42 => match b.words.take('D') {
                Some(d) => self
                    .whole(line, d, "tool number (D)")
                    .map(|t| Compensation::FromTool {
                        right,
                        tool: Some(t),
                    }),
                None => Some(Compensation::FromTool { right, tool: None }),
            },
            _ => match b.words.take('D') {
                Some(d) if !d.value.is_negative() => {
                    let orientation = match b.words.take('L') {
                        Some(l) => self.whole(line, l, "tool orientation (L)"),
                        None => None,
                    };
                    // In the units in force, as every length.
                    let diameter = self.length(line, d)?;
                    Some(Compensation::Dynamic {
                        right,
                        diameter,
                        orientation,
                    })
                }
                _ => {
                    self.missing(
                        line,
                        w,
                        format!("{} without a diameter D of 0 or more", &line.text[w.range.clone()]),
                        "G41.1/G42.1 take the tool's diameter in D (and its lathe orientation in L)",
                    );
                    None
                }
            },
        }
    }

    /// G54 … G59.3: the work offset (after compensation, as in LinuxCNC).
    fn step_coordinate_system(&mut self, b: &mut Interp<'_, '_>) {
        let Some((index, w)) = b.asks.work_offset else {
            return;
        };
        if self.compensation {
            self.comp_refusal(
                b.line,
                w,
                "Cannot change coordinate systems with cutter radius compensation on",
            );
        }
        self.work_offset = index;
        self.push(ItemKind::WorkOffset(index), b.span);
    }

    /// G90 / G91 (the axes) and G90.1 / G91.1 (an arc's I and K).
    fn step_distance_modes(&mut self, b: &mut Interp<'_, '_>) {
        if let Some(incremental) = b.asks.incremental {
            self.incremental = incremental;
        }
        if let Some(absolute) = b.asks.absolute_centres {
            self.absolute_centres = absolute;
        }
    }

    /// G98 / G99: the canned cycles' retract mode (after the distance modes, before the
    /// motion).
    fn step_retract_mode(&mut self, b: &mut Interp<'_, '_>) {
        if let Some((code, w)) = b.asks.retract {
            if self.compensation {
                self.comp_refusal(
                    b.line,
                    w,
                    "Cannot change retract mode with cutter radius compensation on",
                );
            }
            self.retract_old_z = code == G98;
        }
    }

    /// The motion mode the line's code sets (the mode before it is kept). Any motion but a
    /// canned cycle (G80 too) forgets the cycles' initial level.
    /// **[evidence]** `convert_motion`: `if (!is_a_cycle(motion)) cycle_il_flag = false`.
    fn step_motion_mode(&mut self, b: &mut Interp<'_, '_>) {
        self.motion_before_line = self.motion;
        if let Some(m) = b.asks.motion {
            self.motion = Some(m);
            if !matches!(m, Motion::Drill(_)) {
                self.drill.forget_initial_level();
            }
        }
    }

    /// G52 and G92 (the line's axes are theirs), G92.1, G92.2, G92.3.
    fn step_offsets(&mut self, b: &mut Interp<'_, '_>) {
        if let Some((code, w)) = b.asks.offsets {
            let with_motion = b.asks.motion.is_some();
            self.axis_offsets(b.line, &mut b.words, code, w, with_motion);
        }
    }

    /// G28/G30 (via the line's axes to the stored position), G28.1/G30.1, and G53 with G0 or
    /// G1: the line's axes are theirs, and nothing else moves.
    fn step_machine_move(&mut self, b: &mut Interp<'_, '_>) {
        let Some((code, w)) = b.asks.machine else {
            return;
        };
        let second = matches!(code, G30 | G30_1);
        let kind = match code {
            G28_1 | G30_1 => Some(MachineMove::StoreHome { second }),
            G28 | G30 if b.asks.motion.is_some_and(|m| m != Motion::CycleOff) => {
                self.missing(
                    b.line,
                    w,
                    format!("{} with a motion code on its line (LinuxCNC: \"Cannot use two G codes that both use axis values\")", if second { "G30" } else { "G28" }),
                    "put the move on a line of its own",
                );
                None
            }
            G28 | G30 if self.compensation => {
                self.comp_refusal(b.line, w, "Cannot use g28 or g30 with cutter radius comp");
                None
            }
            G28 | G30 => self
                .target(b.line, &mut b.words)
                .map(|via| MachineMove::Home { second, via }),
            _ => self.g53(b, w),
        };
        if let Some(kind) = kind {
            let kind = ItemKind::MachineMove(kind);
            self.r.pos = kind.end_position(self.r.pos);
            self.push(kind, b.span);
        }
        self.exact = (None, None);
        b.words.take('X');
        b.words.take('Z');
    }

    /// G53 with G0 or G1 in force: a move in machine coordinates, or `None` after an error.
    fn g53(&mut self, b: &mut Interp<'_, '_>, w: &Word) -> Option<MachineMove> {
        let line = b.line;
        let Some(m @ (Motion::Rapid | Motion::Feed)) = self.motion else {
            self.missing(
                line,
                w,
                "G53 without G0 or G1 in force (LinuxCNC: \"Must use G0 or G1 with G53\")".into(),
                "write `G53 G0 X… Z…`",
            );
            return None;
        };
        // G91 on the line, or in force: LinuxCNC refuses (`check_g_codes`).
        if self.incremental {
            self.missing(
                line,
                w,
                "G53 under G91 (LinuxCNC: \"Cannot use g53 incremental\")".into(),
                "G53's X and Z are machine coordinates: write G90 before the G53 line",
            );
            return None;
        }
        // Machine coordinates: no G52/G92 offset.
        let offset = std::mem::take(&mut self.axis_offset);
        let to = self.target(line, &mut b.words);
        self.axis_offset = offset;
        let feed = if m == Motion::Feed {
            self.feed_rate(line, Some(w), "G53 G1", b.span).map(Some)
        } else {
            Some(None)
        };
        if to.is_some() && feed.is_some() && !self.comp_machine_move(line, w) {
            return None;
        }
        match (to, feed) {
            (Some(to), Some(feed)) if to != Pos::UNKNOWN => Some(MachineMove::Machine { to, feed }),
            (Some(_), Some(_)) => {
                self.missing(
                    line,
                    w,
                    "G53 without X or Z".into(),
                    "G53 moves the axes it names to machine coordinates: `G53 G0 X200 Z100`",
                );
                None
            }
            _ => None,
        }
    }

    /// The motion: the line's X and Z (those no step took) in the motion mode in force. A
    /// G2/G3, G33.1, G76, roughing or drilling code on the line moves even without axes (a
    /// full circle from I and K, a cycle's own words).
    fn step_motion(&mut self, b: &mut Interp<'_, '_>) {
        let axes = ['X', 'Z']
            .iter()
            .any(|l| b.words.other.contains_key(l) && !b.words.used.contains(l));
        let moves_without_axes = matches!(
            b.asks.motion,
            Some(
                Motion::Tap
                    | Motion::Cycle
                    | Motion::Arc { .. }
                    | Motion::Roughing(_)
                    | Motion::Drill(_)
            )
        );
        if !(axes || moves_without_axes) {
            self.motion_code_without_axes(b);
            // LinuxCNC moves a G0/G1 line without axes to where it is, compensated or not.
            if let Some(m @ (Motion::Rapid | Motion::Feed)) = b.asks.motion
                && (m == Motion::Rapid || self.feed.is_some_and(|f| f.0 > 0))
            {
                let at = b.words.g.iter().find(|(c, _)| [G0, G1].contains(c));
                self.comp_without_axes(b.line, at.map(|(_, w)| *w), m == Motion::Rapid);
            }
            return;
        }
        match self.motion {
            Some(m) => self.motion(b.line, &mut b.words, m, b.span),
            None => {
                let w = b.words.other.get(&'X').or(b.words.other.get(&'Z')).copied();
                if let Some(w) = w {
                    self.missing(
                        b.line,
                        w,
                        "an axis word with no motion mode (G0, G1, G33…) in force".into(),
                        "write the motion code first: `G0 X20 Z5`",
                    );
                }
                b.words.take('X');
                b.words.take('Z');
            }
        }
    }

    /// A G1 or G33 without axes: LinuxCNC refuses G33 ("All axes missing with motion code")
    /// and checks G1's feed all the same.
    fn motion_code_without_axes(&mut self, b: &mut Interp<'_, '_>) {
        let Some(code_word) = b
            .words
            .g
            .iter()
            .find(|(c, _)| [G1, G33].contains(c))
            .map(|(_, w)| *w)
        else {
            return;
        };
        if b.asks.motion == Some(Motion::Thread) {
            b.words.take('K');
            self.missing(
                b.line,
                code_word,
                "G33 without X or Z (LinuxCNC: \"All axes missing with motion code\")".into(),
                "give the end of the thread: `G33 Z-20 K1.5`",
            );
        } else if self.feed.is_none_or(|f| f.0 <= 0) {
            self.missing(
                b.line,
                code_word,
                "G1 with no feed rate (F) set, or F0 (LinuxCNC refuses it even without axes)"
                    .into(),
                "set the feed with F before or on this line",
            );
        } else if self.feed_mode == Some(FeedMode::PerRev) && self.speed.unwrap_or(0) == 0 {
            self.missing(
                b.line,
                code_word,
                "G1 under feed per revolution (G95) with no spindle speed (S) set, or S0 (LinuxCNC: \"Cannot feed with zero spindle speed in feed per rev mode\", even without axes)"
                    .into(),
                "set the spindle speed with S before or on this line",
            );
        }
    }

    /// An F that no move of the line used stays where it is written (a roughing cycle's
    /// moves come when its contour has run).
    fn step_unused_feed(&mut self, b: &mut Interp<'_, '_>) {
        if let Some(feed) = b.f_word
            && self.cycle_call.is_none()
            && !self.r.items[b.first_item..].iter().any(|i| {
                matches!(
                    i.kind,
                    ItemKind::Feed { .. }
                        | ItemKind::Arc { .. }
                        | ItemKind::MachineMove(MachineMove::Machine { feed: Some(_), .. })
                )
            })
        {
            self.push(ItemKind::FeedRate(feed), b.span);
        }
    }

    /// M0 / M1 (stamped with their word), M2 / M30: the program's end, which also turns
    /// cutter compensation off and stops the spindle.
    fn step_stop(&mut self, b: &mut Interp<'_, '_>) {
        let Some((code, w)) = b.asks.stop else {
            return;
        };
        self.comp_stop(b.line, w, code >= 2);
        let end = match code {
            0 | 1 => {
                let at = self.r.span(b.line, w.range.clone());
                let optional = code == 1;
                return self.push(ItemKind::Stop { optional }, at);
            }
            2 => EndCode::M2,
            _ => EndCode::M30,
        };
        let switches = Switches {
            end: Some((end, b.span)),
            ..Switches::default()
        };
        self.switch(Switches::program_end, &switches);
        self.ended = true;
        self.compensation = false;
        self.turning = None;
    }

    /// Words no step read (LinuxCNC refuses them too), unless an error on this line already
    /// explains the line.
    fn step_unused_words(&mut self, b: &mut Interp<'_, '_>) {
        if self
            .r
            .diags
            .get(b.diags_before..)
            .is_some_and(|d| d.iter().any(|d| d.is_error()))
        {
            return;
        }
        let unused: Vec<&Word> = b
            .words
            .other
            .iter()
            .filter(|(l, _)| !b.words.used.contains(l))
            .map(|(_, w)| *w)
            .collect();
        for w in unused {
            let text = &b.line.text[w.range.clone()];
            self.missing(
                b.line,
                w,
                format!("`{text}` is not used by any command on this line"),
                "LinuxCNC refuses words no command on the line uses (K belongs to G33/G33.1/G76, P to G4/G76, H to G43/G76…)",
            );
        }
    }

    /// A code kept as an opaque word (with `extra`, its own words), stamped with its word.
    pub(super) fn kept(&mut self, line: Line<'_>, w: &Word, extra: &[&Word]) {
        // A word whose value is an expression or a parameter is kept with its value: the
        // output holds no parameters (ngcgui's `g64 p#<tol>` after `#<tol> = 0.001`).
        let word = |w: &Word| {
            let text = &line.text[w.range.clone()];
            if text.contains(['#', '[']) {
                format!("{}{}", w.letter.to_ascii_uppercase(), w.value)
            } else {
                text.to_string()
            }
        };
        let mut text = word(w);
        for e in extra {
            text.push(' ');
            text.push_str(&word(e));
        }
        let span = self.r.src.span_in_line(line, w.range.clone());
        self.push(
            ItemKind::Opaque {
                dialect: super::super::ID,
                text,
                block: None,
            },
            span,
        );
    }

    /// A command LinuxCNC refuses while cutter radius compensation is on.
    pub(super) fn comp_refusal(&mut self, line: Line<'_>, at: &Word, linuxcnc: &str) {
        let text = &line.text[at.range.clone()];
        self.diag(
            codes::ISOR_COMPENSATION,
            line,
            at.range.clone(),
            format!("`{text}` while cutter radius compensation is on (LinuxCNC: \"{linuxcnc}\")"),
            "turn the compensation off with G40 first",
        );
    }
}

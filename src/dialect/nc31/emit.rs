//! IR → the НЦ-31's frames.
//!
//! Frames are numbered `N0, N1, …`, one word each; `*` continues a group, `~` marks a rapid
//! coordinate, `@` the G33 offset. Values are whole numbers in the profile's units: a value
//! off that grid is refused, or rounded with `--round` (never a lead: its error grows with
//! every turn). A thread cycle stays one `G31` group when the profile's machine parameters
//! (6, 7), retract and schedule reproduce it exactly; otherwise it is written as its passes.
//! A pass is a `G32` group: along Z at the current diameter, from the index pulse, no entry
//! or runout. Taps are `G33` groups. The control has no comments: they are dropped with one
//! warning, or written as `(` lines (`--nc31-comments`, or when the source is an nc31 file
//! that already holds such lines).

use crate::diag::{Code, Diagnostic};
use crate::dialect::nc31::codes;
use crate::dialect::write::{self, Writer};
use crate::dialect::{DialectId, Inexact, WriteOptions, one_line};
use crate::fixed::{Angle, Lead, Length};
use crate::ir::{
    Coolant, CycleChamfer, EndCode, FeedMode, Finish, Item, ItemKind, Pos, Retract, Rise,
    SpindleDirection, SyncStart, TapCycle, ThreadCycle, ThreadPass,
};
use crate::lower;
use crate::profile::{Nc31ArcDirection, Nc31Profile, Profile};
use crate::source::{SourceFile, Span};

struct Emitter<'a> {
    w: Writer<'a>,
    profile: &'a Nc31Profile,
    /// `round`: values off the unit grid are rounded (a warning) instead of refused;
    /// `comments`: comments are written as `(` lines (for PC-side archives).
    options: WriteOptions,
    /// Comments are written (asked for, or the source is an nc31 file with `(` lines).
    comments: bool,
    next_frame: u64,
    /// The feed register: `None` at the start and after every thread group. **\[decided\]**
    feed: Option<Length>,
    per_minute: bool,
    inexact: Inexact,
    /// Comments dropped: how many, and the first.
    dropped: (usize, Option<Span>),
}

/// The НЦ-31 writer taking a program's items one at a time (a conversion's streaming read),
/// or a whole program ([`Dialect::write`](crate::dialect::Dialect::write)).
pub(crate) struct Items<'a> {
    e: Emitter<'a>,
    /// An nc31 program's own groups and `(` comment lines are kept as they were.
    own: bool,
    /// The items of the source line being gathered (each item alone from another dialect).
    block: Vec<Item>,
    /// Where the program's first item stands (the empty output's refusal points there).
    first: Option<Span>,
}

impl<'a> Items<'a> {
    pub fn new(
        from: crate::ir::DialectId,
        src: &'a SourceFile,
        profile: &'a Profile,
        options: &WriteOptions,
    ) -> Self {
        let own = from == super::ID;
        Items {
            e: Emitter {
                w: Writer::new(src),
                profile: &profile.nc31,
                options: *options,
                comments: options.comments || own,
                next_frame: 0,
                feed: None,
                per_minute: false,
                inexact: Inexact::default(),
                dropped: (0, None),
            },
            own,
            block: Vec::new(),
            first: None,
        }
    }

    /// Writes the block gathered so far. The items of one nc31 group stay one group. A G25
    /// reads a group again right after itself (its items then share the source line): where
    /// the items start over (the group's first item again, or a second move) a new group
    /// begins.
    fn flush(&mut self) {
        if self.block.is_empty() {
            return;
        }
        let block = std::mem::take(&mut self.block);
        let e = &mut self.e;
        e.w.spill();
        let mut group = Vec::new();
        let mut moved = false;
        for (i, item) in block.iter().enumerate() {
            let motion = matches!(
                item.kind,
                ItemKind::Rapid { .. } | ItemKind::Feed { .. } | ItemKind::Arc { .. }
            );
            if i > 0 && ((motion && moved) || item.kind == block[0].kind) {
                e.write(&mut group);
                moved = false;
            }
            moved |= motion;
            e.item(item, &mut group);
        }
        e.write(&mut group);
    }
}

impl write::ItemWriter for Items<'_> {
    #[cfg(unix)]
    fn follow(&mut self, follow: crate::source::Follow) {
        self.e.w.follow(follow);
    }

    fn refuses(&self) -> bool {
        self.e.inexact.refuses(self.e.options.round)
    }

    fn item(&mut self, item: &Item) {
        self.take(item.clone());
    }

    fn take(&mut self, item: Item) {
        self.first.get_or_insert(item.span);
        let same = self.own
            && self
                .block
                .first()
                .is_some_and(|first| first.span.line == item.span.line);
        if !same {
            self.flush();
        }
        self.block.push(item);
    }

    fn finish(mut self: Box<Self>) -> (Option<crate::dialect::Output>, Vec<Diagnostic>) {
        self.flush();
        let Items { mut e, first, .. } = *self;
        e.finish();
        if e.w.is_blank() && !e.w.diags.iter().any(Diagnostic::is_error) {
            let mut d = Diagnostic::new(
                codes::NCW_NOTHING,
                "nothing in this program is written as НЦ-31 frames: the output would be empty",
            )
            .help("the warnings above say what was left out; an empty program is not a conversion");
            if let Some(span) = first {
                d = d.at(e.w.src, span);
            }
            e.w.diags.push(d);
        }
        e.w.finish()
    }
}

/// A frame's text without its number: one word and its modifiers.
fn frame(word: String, rapid: bool) -> String {
    if rapid { format!("{word} ~") } else { word }
}

/// Why a cycle is not the profile's G31, or `None` when it is.
fn g31_mismatch(cycle: &ThreadCycle, p: &Nc31Profile) -> Option<String> {
    g31_start_mismatch(cycle, p)
        .or_else(|| g31_runout_mismatch(cycle, p))
        .or_else(|| g31_path_mismatch(cycle, p))
        .or_else(|| g31_units_mismatch(cycle, p))
}

/// How a cycle's infeed and start differ from G31's (machine parameter 6, the index
/// pulse, no entry).
fn g31_start_mismatch(cycle: &ThreadCycle, p: &Nc31Profile) -> Option<String> {
    let infeed = p.infeed();
    if cycle.infeed.rise as i128 * infeed.run as i128
        != infeed.rise as i128 * cycle.infeed.run as i128
    {
        return Some(format!(
            "its infeed angle ({:.3}°) is not machine parameter 6's ({:.3}°, P6 = {})",
            cycle.infeed.degrees(),
            infeed.degrees(),
            p.infeed_p6
        ));
    }
    if cycle.infeed_moves_end {
        return Some("its infeed shifts the end of every pass".into());
    }
    if cycle.start_angle != Angle::ZERO {
        return Some(format!(
            "it starts {}° after the index pulse",
            cycle.start_angle.deg()
        ));
    }
    if cycle.entry.is_some() {
        return Some("it has an entry taper".into());
    }
    None
}

/// How a cycle's runout differs from G31's (machine parameter 7).
fn g31_runout_mismatch(cycle: &ThreadCycle, p: &Nc31Profile) -> Option<String> {
    let runout = Some(p.runout(cycle.lead))
        .filter(|r| r.0 > 0)
        .map(|length| CycleChamfer {
            length,
            rise: Rise::ToCrest,
        });
    if cycle.runout != runout {
        let what = |r: Option<CycleChamfer>| match r {
            None => "none".to_string(),
            Some(c) => format!(
                "{} mm{}",
                c.length.mm(),
                if c.rise == Rise::ToCrest {
                    ""
                } else {
                    " rising by the thread depth"
                }
            ),
        };
        return Some(format!(
            "its runout ({}) is not machine parameter 7's ({}, P7 = {})",
            what(cycle.runout),
            what(runout),
            p.runout_p7
        ));
    }
    None
}

/// How a cycle's retract, passes, finish and side differ from the profile's G31.
fn g31_path_mismatch(cycle: &ThreadCycle, p: &Nc31Profile) -> Option<String> {
    if cycle.retract != Retract::AboveCrest(p.retract) {
        return Some(format!(
            "it retracts differently from the profile's G31 ({} mm above the crest)",
            p.retract.mm()
        ));
    }
    if cycle.spring_passes != 0 {
        return Some(format!("it has {} spring pass(es)", cycle.spring_passes));
    }
    if cycle.finish != Finish::Start {
        return Some("it does not return to its start point".into());
    }
    if cycle.schedule != p.schedule {
        return Some(format!(
            "its pass schedule ({}) is not the profile's ({})",
            cycle.schedule.id(),
            p.schedule.id()
        ));
    }
    if cycle.internal != (cycle.start.0 < cycle.crest) {
        return Some("its start point is on the wrong side of the thread".into());
    }
    if cycle.taper.0 < 0 {
        return Some("its thread narrows towards the end (G31 tapers widen)".into());
    }
    None
}

/// Which of a cycle's lead and words is not a whole number of the profile's units.
fn g31_units_mismatch(cycle: &ThreadCycle, p: &Nc31Profile) -> Option<String> {
    let lead_unit = Lead::from_length(p.lead_unit);
    if lead_unit.0 > 0 && cycle.lead.0 % lead_unit.0 != 0 {
        return Some(format!(
            "its lead {} mm is not a whole number of {} mm units",
            cycle.lead,
            p.lead_unit.mm()
        ));
    }
    let words = [
        ("X", cycle.crest, p.linear_unit),
        ("Z", cycle.end_z, p.linear_unit),
        ("P (depth)", cycle.depth, p.linear_unit),
        ("P (first pass)", cycle.first_depth, p.linear_unit),
        ("P (taper)", cycle.taper, p.linear_unit),
    ];
    for (what, v, unit) in words {
        if v.0 % unit.0 != 0 {
            return Some(format!(
                "its {what} {} mm is not a whole number of {} mm units",
                v.mm(),
                unit.mm()
            ));
        }
    }
    None
}

/// Where an arc from `(sx, sz)` to `(ex, ez)` around `(cx, cz)` (X diameters) crosses the
/// axes through its centre, in order, on the circle of `radius`: the angles (Z first, X as
/// a radius), and the axis crossings between them.
fn quadrant_crossings(
    (sx, sz): (Length, Length),
    (ex, ez): (Length, Length),
    (cx, cz): (Length, Length),
    radius: Length,
    clockwise: bool,
) -> Vec<Pos> {
    let angle = |x: Length, z: Length| ((x - cx).to_mm_f64() / 2.0).atan2((z - cz).to_mm_f64());
    let quarter = std::f64::consts::FRAC_PI_2;
    let (a0, a1) = (angle(sx, sz), angle(ex, ez));
    let turn = std::f64::consts::TAU;
    let mut sweep = if clockwise { a0 - a1 } else { a1 - a0 }.rem_euclid(turn);
    if (sx, sz) == (ex, ez) || sweep < 1e-12 {
        sweep = turn;
    }
    let mut points = Vec::new();
    let step = if clockwise { -1.0 } else { 1.0 };
    let mut k = if clockwise {
        (a0 / quarter - 1e-9).floor()
    } else {
        (a0 / quarter + 1e-9).ceil()
    };
    loop {
        let crossing = k * quarter;
        let travelled = (crossing - a0) * step;
        if travelled >= sweep - 1e-9 {
            break;
        }
        if travelled > 1e-9 {
            let (x, z) = match (k as i64).rem_euclid(4) {
                0 => (cx, cz + radius),
                1 => (cx + radius + radius, cz),
                2 => (cx, cz - radius),
                _ => (cx - radius - radius, cz),
            };
            points.push(Pos::new(x, z));
        }
        k += step;
    }
    points
}

impl Emitter<'_> {
    fn diag(&mut self, code: Code, span: Span, message: String, help: impl Into<String>) {
        self.w.error(code, span, message, help);
    }

    /// Writes a group: numbered frames, `*` on all but the last.
    fn write(&mut self, group: &mut Vec<String>) {
        let n = group.len();
        for (i, f) in group.drain(..).enumerate() {
            let more = if i + 1 < n { " *" } else { "" };
            self.w
                .out
                .push_str(&format!("N{} {f}{more}\n", self.next_frame));
            self.next_frame += 1;
        }
    }

    fn comment(&mut self, span: Span, text: &str, group: &mut Vec<String>) {
        if self.comments {
            self.write(group);
            self.w.out.push_str(&format!("({})\n", one_line(text)));
        } else {
            self.dropped.0 += 1;
            self.dropped.1.get_or_insert(span);
        }
    }

    /// `v` in whole `unit`s. Off the grid: rounded (counted for one diagnostic).
    fn units(&mut self, span: Span, what: &str, v: Length, unit: Length) -> i64 {
        if v.0 % unit.0 == 0 {
            return v.0 / unit.0;
        }
        let n = crate::fixed::div_round(v.0 as i128, unit.0 as i128) as i64;
        self.inexact.note(span, what, v, Length(n * unit.0), unit);
        n
    }

    /// A lead in whole lead units over `travel` along Z. Off the grid: rounded, with the
    /// drift at the thread's end as its deviation (counted for one diagnostic); a lead that
    /// rounds to nothing is refused.
    fn lead(&mut self, span: Span, lead: Lead, travel: Length) -> Option<i64> {
        let unit = Lead::from_length(self.profile.lead_unit);
        if unit.0 <= 0 {
            return None;
        }
        if lead.0 % unit.0 == 0 {
            return Some(lead.0 / unit.0);
        }
        let n = crate::fixed::div_round(lead.0 as i128, unit.0 as i128) as i64;
        if n <= 0 {
            self.diag(
                codes::NCW_PRECISION,
                span,
                format!(
                    "the lead {lead} mm rounds to 0 in the НЦ-31's {} mm lead units",
                    self.profile.lead_unit.mm()
                ),
                "a thread needs a lead the control can hold; check the profile's nc31.lead_unit_mm",
            );
            return None;
        }
        let drift = lead.drift(Lead(n * unit.0), travel);
        self.inexact
            .note_lead(span, "lead F", lead, drift, self.profile.lead_unit);
        Some(n)
    }

    /// Something the НЦ-31 has no word for, but that does not move the tool: a comment line
    /// when comments are written, and a warning either way.
    fn not_written(&mut self, item: &Item, text: &str, why: &str, group: &mut Vec<String>) {
        let kept = self.comments;
        if kept {
            self.write(group);
            self.w
                .out
                .push_str(&format!("({} (not converted))\n", one_line(text)));
        }
        self.diag(
            codes::NCW_DROPPED,
            item.span,
            format!(
                "`{text}` has no НЦ-31 equivalent; it is {}",
                if kept {
                    "written as a comment"
                } else {
                    "left out"
                }
            ),
            why,
        );
    }

    fn coordinate_frames(&mut self, span: Span, to: Pos, rapid: bool) -> Vec<String> {
        let unit = self.profile.linear_unit;
        let mut frames = Vec::new();
        if let Some(x) = to.x {
            let n = self.units(span, "X", x, unit);
            frames.push(frame(format!("X{n}"), rapid));
        }
        if let Some(z) = to.z {
            let n = self.units(span, "Z", z, unit);
            frames.push(frame(format!("Z{n}"), rapid));
        }
        frames
    }

    fn item(&mut self, item: &Item, group: &mut Vec<String>) {
        if let Some(c) = &item.comment {
            self.comment(item.span, c, group);
        }
        if !self.motion(item, group) {
            self.words(item, group);
        }
        if !matches!(
            item.kind,
            ItemKind::ThreadCycle(_) | ItemKind::ThreadPass(_) | ItemKind::TapCycle(_)
        ) {
            self.w.pos = item.kind.end_position(self.w.pos);
        }
    }

    /// Writes a move: one arm per kind of motion. `false` when the item is not a move the
    /// НЦ-31 makes (see [`Self::words`]).
    fn motion(&mut self, item: &Item, group: &mut Vec<String>) -> bool {
        match &item.kind {
            ItemKind::Rapid { to } => {
                let frames = self.coordinate_frames(item.span, *to, true);
                group.extend(frames);
            }
            // A 45° chamfer where the profile has it.
            ItemKind::Feed { to, feed } if self.chamfer_fits(*to, *feed) => {
                self.chamfer(item.span, *to, *feed, group);
            }
            ItemKind::Feed { to, feed } => {
                // A feed per minute is refused by legalisation (the НЦ-31 feeds per rev).
                if !self.per_minute {
                    self.feed_frame(item.span, *feed, group);
                }
                let frames = self.coordinate_frames(item.span, *to, false);
                group.extend(frames);
            }
            ItemKind::ThreadPass(pass) => {
                self.write(group);
                self.thread_pass(item.span, pass, None);
            }
            ItemKind::ThreadCycle(cycle) => {
                self.write(group);
                self.thread_cycle(item, cycle);
            }
            ItemKind::TapCycle(tap) => {
                self.write(group);
                self.tap(item.span, tap);
            }
            ItemKind::Arc {
                to,
                centre,
                clockwise,
                feed,
            } if self.profile.arcs && !self.per_minute => {
                if let Some(direction) = self.profile.arc_direction {
                    self.write(group);
                    self.feed_frame(item.span, *feed, group);
                    self.arc(item.span, *to, **centre, *clockwise, direction);
                }
            }
            _ => return false,
        }
        true
    }

    /// Writes an item that is not a move: one arm per kind of item.
    fn words(&mut self, item: &Item, group: &mut Vec<String>) {
        match &item.kind {
            // Written by `motion`.
            ItemKind::Rapid { .. }
            | ItemKind::Feed { .. }
            | ItemKind::ThreadPass(_)
            | ItemKind::ThreadCycle(_)
            | ItemKind::TapCycle(_) => {}
            // Refused by legalisation (no dwell, arc, stop or mist on the НЦ-31).
            ItemKind::Dwell { .. }
            | ItemKind::Arc { .. }
            | ItemKind::Stop { .. }
            | ItemKind::Coolant(Coolant::Mist) => {}
            // A zero feed no move runs at (the НЦ-31 reader refuses `F0`).
            ItemKind::FeedRate(feed) if *feed == Length::ZERO => self.not_written(
                item,
                "F0",
                "no move runs at it: each feed move carries its own feed",
                group,
            ),
            // A feed frame of its own (a feed per minute is refused by legalisation).
            ItemKind::FeedRate(feed) => {
                if !self.per_minute {
                    self.feed_frame(item.span, *feed, group);
                }
            }
            // Speeds in rpm are this control's only mode; a surface speed is refused by
            // legalisation.
            ItemKind::SpindleMode(_) => {}
            // No compensation and the default work offset are this control's only state;
            // the others, and machine coordinates, are refused by legalisation.
            ItemKind::Compensation(_) | ItemKind::WorkOffset(_) | ItemKind::MachineMove(_) => {}
            // Unrolled into its moves at the top of `emit`.
            ItemKind::Roughing(_) | ItemKind::ModelCycle(_) => {}
            // M8/M9 where the profile declares them; legalisation refuses them otherwise.
            ItemKind::Coolant(c) => group.push(
                if *c == Coolant::Flood { "M8" } else { "M9" }.to_string(),
            ),
            ItemKind::Spindle { speed, direction } => {
                group.extend(speed.map(|s| format!("S{s}")));
                match direction {
                    Some(SpindleDirection::Clockwise) => group.push("M3".into()),
                    Some(SpindleDirection::CounterClockwise) => group.push("M4".into()),
                    None => {}
                }
            }
            ItemKind::SpindleStop => group.push("M5".into()),
            ItemKind::Tool { number, offset } => self.tool(item, *number, *offset, group),
            ItemKind::GearRange { code, machine } => self.gear_range(item, *code, *machine, group),
            ItemKind::MachineCode { code, machine } => self.own_m(item, *code, *machine, group),
            ItemKind::FeedMode(mode) => {
                self.per_minute = *mode == FeedMode::PerMin;
            }
            ItemKind::ProgramEnd(EndCode::M2 | EndCode::M30) => {
                // The guide documents M30 as the end of a program. **[decided]** M2 → M30.
                group.push("M30".into());
            }
            ItemKind::Comment(text) => self.comment(item.span, text, group),
            ItemKind::ParamAssign { number, value } => self.not_written(
                item,
                &format!("R{number:02}={value}"),
                "the НЦ-31 has no parameters; the values this program takes from it are written where they are used",
                group,
            ),
            ItemKind::Opaque {
                dialect: super::ID,
                text,
                ..
            } => {
                self.write(group);
                self.own_frames(text);
            }
            ItemKind::Opaque { dialect, text, .. } => self.not_written(
                item,
                &format!("{dialect}: {text}"),
                "check the НЦ-31 program by hand where this matters",
                group,
            ),
            ItemKind::Delimiter => {
                self.write(group);
                self.w.out.push_str("%\n");
            }
        }
    }

    /// The feed in a frame of its own, as in the seed programs, when it changes.
    fn feed_frame(&mut self, span: Span, feed: Length, group: &mut Vec<String>) {
        if self.feed != Some(feed) {
            self.write(group);
            let n = self.units(span, "feed F", feed, self.profile.feed_unit);
            group.push(format!("F{n}"));
            self.write(group);
            self.feed = Some(feed);
        }
    }

    /// The turret position T; a tool offset has no word (the position carries its own).
    fn tool(
        &mut self,
        item: &Item,
        number: Option<u32>,
        offset: Option<u32>,
        group: &mut Vec<String>,
    ) {
        if let Some(t) = number {
            group.push(format!("T{t}"));
        }
        if let Some(d) = offset {
            self.diag(
                codes::NCW_DROPPED,
                item.span,
                format!("tool offset {d} is left out: the НЦ-31's T word selects a turret position and its offset"),
                "check that the turret position carries the offset this program needs",
            );
        }
    }

    /// A gear range's M code when it is the НЦ-31's own (and the profile names it); else
    /// not written, and why.
    fn gear_range(&mut self, item: &Item, m: u32, machine: DialectId, group: &mut Vec<String>) {
        if machine == super::ID && self.profile.gear_range_mcodes.contains(&m) {
            group.push(format!("M{m}"));
        } else {
            self.not_written(
                item,
                &format!("M{m}: gear range of the source machine"),
                "the НЦ-31's speed ranges (M38–M41) are not the source machine's gear ranges; add the range by hand",
                group,
            );
        }
    }

    /// Another machine's own M code: left out, and said.
    fn own_m(&mut self, item: &Item, m: u32, machine: DialectId, group: &mut Vec<String>) {
        self.not_written(
            item,
            &crate::ir::machine_code_note(m, machine),
            "what it does is the source machine's; add the НЦ-31's own code by hand if the machine needs it",
            group,
        );
    }

    /// Frames kept from an НЦ-31 source as they were, renumbered: the source's frame
    /// number is dropped.
    fn own_frames(&mut self, text: &str) {
        for line in text.lines() {
            let rest = line.trim_start();
            let rest = rest
                .strip_prefix('N')
                .map(|r| r.trim_start_matches(|c: char| c.is_ascii_digit()))
                .unwrap_or(rest)
                .trim();
            self.w
                .out
                .push_str(&format!("N{} {rest}\n", self.next_frame));
            self.next_frame += 1;
        }
    }

    /// Whether a feed move to `to` is written as a 45° chamfer: the profile says the
    /// machine takes them (`chamfer45`), the move is at 45° (X, a diameter, changes by twice
    /// the Z travel), and its start, end and feed are whole units (the control computes
    /// the other axis from them: nothing may be rounded).
    fn chamfer_fits(&self, to: Pos, feed: Length) -> bool {
        let unit = self.profile.linear_unit;
        let (Some((sx, sz)), Some((ex, ez))) = (self.w.pos.known(), to.known()) else {
            return false;
        };
        let (dx, dz) = (ex.0.checked_sub(sx.0), ez.0.checked_sub(sz.0));
        self.profile.chamfer45
            && !self.per_minute
            && [sx, sz, ex, ez].iter().all(|v| v.0 % unit.0 == 0)
            && feed.0 % self.profile.feed_unit.0 == 0
            && dz.is_some_and(|d| d != 0)
            && dx.and_then(i64::checked_abs)
                == dz.and_then(i64::checked_abs).and_then(|d| d.checked_mul(2))
    }

    /// `X<end>+45 *` (Z grows) or `X<end>-45 *` (Z falls), then `F<feed>`: a group of its
    /// own, the F frame closing it.
    fn chamfer(&mut self, span: Span, to: Pos, feed: Length, group: &mut Vec<String>) {
        let (Some((_, sz)), Some((ex, ez))) = (self.w.pos.known(), to.known()) else {
            return;
        };
        self.write(group);
        let sign = if ez > sz { "+" } else { "-" };
        let x = self.units(span, "X", ex, self.profile.linear_unit);
        let f = self.units(span, "feed F", feed, self.profile.feed_unit);
        let mut chamfer = vec![format!("X{x}{sign}45"), format!("F{f}")];
        self.write(&mut chamfer);
        self.feed = Some(feed);
    }

    /// `G32 *` F Z. `cycle`: why the cycle this pass belongs to is not a G31.
    fn thread_pass(&mut self, span: Span, pass: &ThreadPass, cycle: Option<&str>) {
        let cannot = self.g32_obstacles(pass);
        if !cannot.is_empty() {
            let context = match cycle {
                Some(why) => {
                    format!("; it is a pass of a cycle that is not this machine's G31 ({why})")
                }
                None => String::new(),
            };
            return self.diag(
                codes::NCW_PASS,
                span,
                format!(
                    "the thread pass has {}, which G32 cannot cut{context}",
                    cannot.join(" and ")
                ),
                "G32 cuts one pass along Z at the current diameter, from the index pulse, without entry or runout; a start angle can be written as a pass that starts earlier by the Z shift (as the guide writes multi-start threads), by hand in the source",
            );
        }
        let Some(to_z) = pass.to.z else {
            return;
        };
        let travel = self.w.pos.z.map_or(Length::ZERO, |z| (to_z - z).abs());
        let Some(lead) = self.lead(span, pass.lead, travel) else {
            return;
        };
        let unit = self.profile.linear_unit;
        if let Some(from) = self.w.pos.z
            && unit.0 > 0
            && crate::fixed::div_round(from.0 as i128, unit.0 as i128)
                == crate::fixed::div_round(to_z.0 as i128, unit.0 as i128)
        {
            return self.diag(
                codes::NCW_PRECISION,
                span,
                format!(
                    "the thread pass's Z travel of {} mm rounds to nothing in the НЦ-31's {} mm units",
                    travel.mm(),
                    unit.mm()
                ),
                "G32 needs a pass the control can measure; lengthen the pass in the source",
            );
        }
        let z = self.units(span, "Z", to_z, unit);
        let mut group = vec!["G32".to_string(), format!("F{lead}"), format!("Z{z}")];
        self.write(&mut group);
        self.w.pos.z = Some(to_z);
        self.feed = None;
    }

    /// What a thread pass has that G32 cannot cut: a start angle, no index pulse, a
    /// synchronised infeed, an entry or runout, a taper (or a start diameter not known).
    fn g32_obstacles(&self, pass: &ThreadPass) -> Vec<String> {
        let mut cannot = Vec::new();
        match pass.start {
            SyncStart::Index(Angle::ZERO) => {}
            SyncStart::Index(angle) => cannot.push(format!(
                "a start angle of {}° (a Z shift of {} mm)",
                angle.deg(),
                pass.lead.of_angle(angle).mm()
            )),
            SyncStart::Continue => {
                cannot.push("no index pulse: it continues the thread move before it".to_string())
            }
        }
        if pass.infeed.is_some() {
            cannot.push("a synchronised infeed along X".to_string());
        }
        if let Some(e) = pass.entry {
            cannot.push(format!("an entry ({} mm)", e.length.mm()));
        }
        if let Some(r) = pass.exit {
            cannot.push(format!("a runout ({} mm)", r.length.mm()));
        }
        // The thread line starts where the entry meets it.
        let line_start = pass
            .infeed
            .map(|i| i.x)
            .or(self.w.pos.x)
            .map(|x| x - pass.entry.map_or(Length::ZERO, |e| e.offset));
        match (line_start, pass.to.x) {
            (_, None) => {}
            (Some(from), Some(to)) if from == to => {}
            (Some(from), Some(to)) => {
                cannot.push(format!("a taper (Ø{} to Ø{})", from.mm(), to.mm()));
            }
            (None, Some(_)) => cannot.push("a start diameter that is not known".into()),
        }
        cannot
    }

    fn thread_cycle(&mut self, item: &Item, cycle: &ThreadCycle) {
        let Some(expansion) = self.w.expand(cycle, item.span) else {
            return;
        };
        let start = Pos::new(cycle.start.0, cycle.start.1);
        let Some(why) = g31_mismatch(cycle, self.profile) else {
            if self.w.pos != start {
                let mut group = self.coordinate_frames(item.span, start, true);
                self.write(&mut group);
            }
            let unit = self.profile.linear_unit;
            let travel = (cycle.end_z - cycle.start.1).abs();
            let Some(lead) = self.lead(item.span, cycle.lead, travel) else {
                return;
            };
            let mut group = vec![
                "G31".to_string(),
                format!("X{}", cycle.crest.0 / unit.0),
                format!("Z{}", cycle.end_z.0 / unit.0),
                format!("F{lead}"),
                format!("P{}", cycle.depth.0 / unit.0),
                format!("P{}", cycle.first_depth.0 / unit.0),
            ];
            if cycle.taper != Length::ZERO {
                group.push(format!("P{}", cycle.taper.0 / unit.0));
            }
            self.write(&mut group);
            self.w.pos = start;
            self.feed = None;
            return;
        };
        // Not this machine's G31: its passes, each a G32 group.
        if self.comments {
            self.w
                .out
                .push_str(&format!("({})\n", expansion.summary(cycle, "D")));
        }
        let errors = self.w.errors();
        for m in &expansion.moves {
            match &m.kind {
                lower::Move::Pass(pass) => self.thread_pass(item.span, pass, Some(&why)),
                rapid => {
                    let moved = Item {
                        kind: rapid.item_kind(),
                        comment: None,
                        block_number: None,
                        span: item.span,
                    };
                    let mut group = Vec::new();
                    self.item(&moved, &mut group);
                    self.write(&mut group);
                }
            }
            if self.w.errors() > errors {
                return;
            }
        }
        self.w.pos = item.kind.end_position(self.w.pos);
    }

    /// A radius from a difference of diameters, in linear units (noted when off the grid).
    fn radius_units(&mut self, span: Span, what: &str, diameter: Length) -> i64 {
        let unit = self.profile.linear_unit;
        let d = diameter.0.abs();
        if d % (2 * unit.0) == 0 {
            return d / (2 * unit.0);
        }
        let n = crate::fixed::div_round(d as i128, 2 * unit.0 as i128) as i64;
        self.inexact.note(
            span,
            what,
            Length(d),
            Length(2 * n * unit.0),
            Length(2 * unit.0),
        );
        n
    }

    /// An arc as `G2`/`G3` groups of at most a quadrant each: X, Z and the centre's
    /// unsigned offsets from each group's start (radial in radius units, then axial). An
    /// arc over the axes through its centre is split where it crosses them; those points
    /// are on the grid only when its radius is (else rounded with `--round`, or refused).
    fn arc(
        &mut self,
        span: Span,
        to: Pos,
        centre: Pos,
        clockwise: bool,
        direction: Nc31ArcDirection,
    ) {
        let (Some((sx, sz)), Some((cx, cz)), Some((ex, ez))) =
            (self.w.pos.known(), centre.known(), to.known())
        else {
            self.diag(
                codes::NCW_NO_EQUIVALENT,
                span,
                "an arc from a position that is not known: its centre offsets cannot be written"
                    .into(),
                "move to an absolute X and Z before the arc",
            );
            return;
        };
        let (r, _) = lower::arc::radii((sx, sz), (ex, ez), (cx, cz));
        let radius = Length::from_mm_f64(r);
        let mut points = quadrant_crossings((sx, sz), (ex, ez), (cx, cz), radius, clockwise);
        if !points.is_empty() && (r - radius.to_mm_f64()).abs() > 1e-7 {
            self.inexact.note(
                span,
                "arc radius (where it crosses a quadrant)",
                Length::ZERO,
                Length::from_mm_f64((r - radius.to_mm_f64()).abs()).max(Length::from_steps(1)),
                self.profile.linear_unit,
            );
        }
        points.push(Pos::new(ex, ez));
        let g2 = clockwise != (direction == Nc31ArcDirection::FrontTool);
        let unit = self.profile.linear_unit;
        let mut from = (sx, sz);
        for p in points {
            let Some((px, pz)) = p.known() else { continue };
            let x = self.units(span, "X", px, unit);
            let z = self.units(span, "Z", pz, unit);
            let a = self.radius_units(span, "P (radial offset)", cx - from.0);
            let b = self.units(span, "P (axial offset)", (cz - from.1).abs(), unit);
            let mut group = vec![
                if g2 { "G2" } else { "G3" }.to_string(),
                format!("X{x}"),
                format!("Z{z}"),
                format!("P{a}"),
                format!("P{b}"),
            ];
            self.write(&mut group);
            from = (px, pz);
        }
        self.w.pos = to;
    }

    /// `G33 [@] *` X Z F.
    fn tap(&mut self, span: Span, tap: &TapCycle) {
        let travel = self.w.pos.z.map_or(Length::ZERO, |z| (tap.end_z - z).abs());
        let Some(lead) = self.lead(span, tap.lead, travel) else {
            return;
        };
        let unit = self.profile.linear_unit;
        let mut group = vec![if tap.then_x.is_some() { "G33 @" } else { "G33" }.to_string()];
        // Without `@` the X word names the diameter the tool stands at (the seed writes it).
        if let Some(x) = tap.then_x.or(self.w.pos.x) {
            let n = self.units(span, "X", x, unit);
            group.push(format!("X{n}"));
        }
        let z = self.units(span, "Z", tap.end_z, unit);
        group.push(format!("Z{z}"));
        group.push(format!("F{lead}"));
        self.write(&mut group);
        self.w.pos = ItemKind::TapCycle(*tap).end_position(self.w.pos);
        self.feed = None;
    }

    fn finish(&mut self) {
        if let Some(span) = self.dropped.1 {
            let n = self.dropped.0;
            self.diag(
                codes::NCW_COMMENTS,
                span,
                format!("{n} comment(s) left out: the НЦ-31 has no comments"),
                "pass --nc31-comments to write them as `(` lines for a PC-side archive",
            );
        }
        let summary = self.inexact.diagnostic(
            self.w.src,
            self.options.round,
            |s| {
                Diagnostic::new(
                    codes::NCW_ROUNDED,
                    format!("{} value(s) rounded to the НЦ-31's units, the first {}; the largest deviation is {} mm", s.count, s.what, s.largest),
                )
                .help("the rounded program cuts within that deviation of the source")
            },
            |s| {
                Diagnostic::new(
                    codes::NCW_PRECISION,
                    format!("{} is not a whole number of the НЦ-31's {} mm units ({} value(s) in this program are not)", s.what, s.grid, s.count),
                )
                .help(format!("pass --round to round them (largest deviation {} mm)", s.largest))
            },
        );
        self.w.diags.extend(summary);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ir::Program;

    /// The writer's text as a string, as the tests read it.
    fn emit(
        program: &Program,
        src: &SourceFile,
        profile: &Profile,
        options: &WriteOptions,
    ) -> (Option<String>, Vec<Diagnostic>) {
        let (out, diags) =
            crate::dialect::Dialect::write(&super::super::Nc31, program, src, profile, options);
        (out.map(|o| o.into_string().expect("in memory")), diags)
    }
    use crate::diag::Severity;
    use crate::ir::{Chamfer, Schedule};

    /// nc31 → nc31 with `profile`.
    fn again(
        text: &str,
        profile: &Profile,
        options: WriteOptions,
    ) -> (Option<String>, Vec<Diagnostic>) {
        let src = SourceFile::new("t.nc", text);
        let (program, diags) = super::super::front::parse(&src, &profile.nc31, &Default::default());
        assert!(!crate::diag::has_errors(&diags), "{diags:?}");
        emit(&program, &src, profile, &options)
    }

    fn write(items: Vec<ItemKind>, options: WriteOptions) -> (Option<String>, Vec<Diagnostic>) {
        let src = SourceFile::new("t", "");
        let program = Program {
            items: items
                .into_iter()
                .map(|k| Item::new(k, Span::default()))
                .collect(),
            dialect: crate::dialect::iso::ID,
            library: Vec::new(),
            number: None,
            inch: false,
            name: None,
        };
        // As a conversion does: legalisation for the НЦ-31, then the writer.
        let mut diags =
            crate::legalise::for_target(&program, &src, &super::super::Nc31, &Profile::default());
        let (out, more) = emit(&program, &src, &Profile::default(), &options);
        diags.extend(more);
        (out.filter(|_| !crate::diag::has_errors(&diags)), diags)
    }

    fn codes_of(diags: &[Diagnostic]) -> Vec<&'static str> {
        diags.iter().map(|d| d.code.id).collect()
    }

    fn mm(v: i64) -> Length {
        Length::from_mm(v)
    }

    fn turning() -> ItemKind {
        ItemKind::Spindle {
            speed: Some(500),
            direction: Some(SpindleDirection::Clockwise),
        }
    }

    fn at(x: Length, z: Length) -> ItemKind {
        ItemKind::Rapid { to: Pos::new(x, z) }
    }

    fn pass(z: Length) -> ThreadPass {
        ThreadPass {
            to: Pos {
                x: None,
                z: Some(z),
            },
            lead: crate::fixed::Lead::from_length(Length::from_steps(15_000)),
            start: crate::ir::SyncStart::Index(Angle::ZERO),
            infeed: None,
            entry: None,
            exit: None,
        }
    }

    const SEED_G31: &str = "N0 M3\nN1 S700\nN2 X3600 ~ *\nN3 Z450 ~\nN4 G31 *\nN5 X3600 *\nN6 Z-4750 *\nN7 F15000 *\nN8 P96 *\nN9 P20\nN10 M5\nN11 M30\n";

    #[test]
    fn a_cycle_of_this_machine_stays_one_g31_group() {
        let (out, diags) = again(SEED_G31, &Profile::default(), WriteOptions::default());
        assert!(diags.is_empty(), "{diags:?}");
        assert_eq!(
            out.unwrap(),
            "N0 M3\nN1 S700\nN2 X3600 ~ *\nN3 Z450 ~\nN4 G31 *\nN5 X3600 *\nN6 Z-4750 *\nN7 F15000 *\nN8 P96 *\nN9 P20\nN10 M5\nN11 M30\n"
        );
        // With parameter 7 in the profile the cycle is still the machine's G31.
        let mut p7 = Profile::default();
        p7.nc31.runout_p7 = 10;
        let (out, _) = again(SEED_G31, &p7, WriteOptions::default());
        assert!(out.unwrap().contains("N4 G31 *"));
    }

    #[test]
    fn another_machines_cycle_becomes_g32_passes_that_cut_the_same() {
        let src = SourceFile::new("t.nc", SEED_G31);
        let profile = Profile::default();
        let (program, _) = super::super::front::parse(&src, &profile.nc31, &Default::default());
        // The same cycle with a schedule this machine's G31 does not use.
        let mut other = program.clone();
        for item in &mut other.items {
            if let ItemKind::ThreadCycle(c) = &mut item.kind {
                c.schedule = Schedule::ConstantDepth;
            }
        }
        let (out, diags) = emit(&other, &src, &profile, &WriteOptions::default());
        assert!(!crate::diag::has_errors(&diags), "{diags:?}");
        let out = out.unwrap();
        assert!(
            !out.contains("G31") && out.matches("G32").count() == 5,
            "{out}"
        );
        let back = SourceFile::new("back.nc", out);
        let (read, diags) = super::super::front::parse(&back, &profile.nc31, &Default::default());
        assert!(!crate::diag::has_errors(&diags), "{diags:?}");
        let a = crate::sim::normalise(&crate::sim::simulate(&other).segments);
        let b = crate::sim::normalise(&crate::sim::simulate(&read).segments);
        assert_eq!(crate::sim::compare(&a, &b), None);
    }

    #[test]
    fn a_cycle_with_a_runout_the_profile_lacks_is_refused_naming_why() {
        let mut p7 = Profile::default();
        p7.nc31.runout_p7 = 10;
        let src = SourceFile::new("t.nc", SEED_G31);
        let (program, _) = super::super::front::parse(&src, &p7.nc31, &Default::default());
        let (out, diags) = emit(
            &program,
            &src,
            &Profile::default(),
            &WriteOptions::default(),
        );
        assert!(out.is_none());
        let d = diags.iter().find(|d| d.code.id == "NCW003").unwrap();
        assert!(d.message.contains("a runout (1.5 mm)"), "{}", d.message);
        assert!(
            d.message.contains("machine parameter 7's (none, P7 = 0)"),
            "{}",
            d.message
        );
    }

    #[test]
    fn g32_refuses_start_angle_entry_runout_and_taper() {
        let runout = Chamfer {
            length: mm(2),
            offset: mm(2),
        };
        let cases: [(ThreadPass, &str); 4] = [
            (
                ThreadPass {
                    start: crate::ir::SyncStart::Index(Angle(180_000)),
                    ..pass(mm(-20))
                },
                "a start angle of 180° (a Z shift of 0.75 mm)",
            ),
            (
                ThreadPass {
                    exit: Some(runout),
                    ..pass(mm(-20))
                },
                "a runout (2 mm)",
            ),
            (
                ThreadPass {
                    entry: Some(runout),
                    ..pass(mm(-20))
                },
                "an entry (2 mm)",
            ),
            (
                ThreadPass {
                    to: Pos::new(mm(22), mm(-20)),
                    ..pass(mm(-20))
                },
                "a taper (Ø20 to Ø22)",
            ),
        ];
        for (p, what) in cases {
            let (out, diags) = write(
                vec![turning(), at(mm(20), mm(5)), ItemKind::pass(p)],
                WriteOptions::default(),
            );
            assert!(out.is_none(), "{what}");
            assert_eq!(codes_of(&diags), ["NCW003"]);
            assert!(diags[0].message.contains(what), "{}", diags[0].message);
        }
        // A pass at the current diameter is a G32 group; the feed is programmed again after it.
        let (out, diags) = write(
            vec![
                turning(),
                at(mm(20), mm(5)),
                ItemKind::pass(ThreadPass {
                    to: Pos::new(mm(20), mm(-20)),
                    ..pass(mm(-20))
                }),
                ItemKind::Feed {
                    to: Pos {
                        x: Some(mm(30)),
                        z: None,
                    },
                    feed: Length::from_steps(3_000),
                },
            ],
            WriteOptions::default(),
        );
        assert!(diags.is_empty(), "{diags:?}");
        assert_eq!(
            out.unwrap(),
            "N0 S500 *\nN1 M3\nN2 X2000 ~ *\nN3 Z500 ~\nN4 G32 *\nN5 F15000 *\nN6 Z-2000\nN7 F30\nN8 X3000\n"
        );
    }

    #[test]
    fn values_off_the_grid_are_refused_or_rounded_and_leads_by_their_drift() {
        let items = || {
            vec![
                turning(),
                at(Length::from_steps(266_180), mm(3)),
                ItemKind::pass(pass(mm(-9))),
                at(Length::from_steps(264_180), mm(3)),
            ]
        };
        let (out, diags) = write(items(), WriteOptions::default());
        assert!(out.is_none());
        assert_eq!(codes_of(&diags), ["NCW001"]);
        assert!(
            diags[0].message.starts_with("X 26.618 mm"),
            "{}",
            diags[0].message
        );
        assert!(
            diags[0].message.contains("(2 value(s)"),
            "{}",
            diags[0].message
        );
        let (out, diags) = write(
            items(),
            WriteOptions {
                round: true,
                ..WriteOptions::default()
            },
        );
        assert!(out.unwrap().contains("N2 X2662 ~ *"));
        assert_eq!(diags[0].severity, Severity::Warning);
        assert!(
            diags[0].message.contains("largest deviation is 0.002 mm"),
            "{}",
            diags[0].message
        );
        // A lead off the lead unit is refused, or with --round rounded with its drift at the
        // thread's end: 1.5005 → F1501 (0.001 mm units), 0.0005·14/1.5005 = 0.00467 mm.
        let src = SourceFile::new("t", "");
        let mut profile = Profile::default();
        profile.nc31.lead_unit = Length::from_steps(10);
        let program = Program {
            items: vec![turning(), at(mm(20), mm(5)), ItemKind::pass(pass(mm(-9)))]
                .into_iter()
                .map(|mut k| {
                    if let ItemKind::ThreadPass(p) = &mut k {
                        p.lead = crate::fixed::Lead::from_length(Length::from_steps(15_005));
                    }
                    Item::new(k, Span::default())
                })
                .collect(),
            dialect: crate::dialect::iso::ID,
            library: Vec::new(),
            number: None,
            inch: false,
            name: None,
        };
        let (out, diags) = emit(
            &program,
            &src,
            &profile,
            &WriteOptions {
                round: true,
                ..WriteOptions::default()
            },
        );
        assert!(out.unwrap().contains("F1501"));
        assert_eq!(codes_of(&diags), ["NCW005"]);
        assert!(
            diags[0].message.contains("largest deviation is 0.0047 mm"),
            "{}",
            diags[0].message
        );
        let (out, diags) = emit(&program, &src, &profile, &WriteOptions::default());
        assert!(out.is_none());
        assert_eq!(codes_of(&diags), ["NCW001"]);
        assert!(
            diags[0].message.contains("lead F 1.5005 mm"),
            "{}",
            diags[0].message
        );
    }

    #[test]
    fn comments_are_dropped_with_one_warning_or_written() {
        let items = || {
            vec![
                ItemKind::Comment("ONE".into()),
                at(mm(20), mm(5)),
                ItemKind::Comment("TWO".into()),
            ]
        };
        let (out, diags) = write(items(), WriteOptions::default());
        assert_eq!(out.unwrap(), "N0 X2000 ~ *\nN1 Z500 ~\n");
        assert_eq!(codes_of(&diags), ["NCW007"]);
        assert!(diags[0].message.starts_with("2 comment(s)"));
        let (out, diags) = write(
            items(),
            WriteOptions {
                comments: true,
                ..WriteOptions::default()
            },
        );
        assert!(diags.is_empty());
        assert_eq!(out.unwrap(), "(ONE)\nN0 X2000 ~ *\nN1 Z500 ~\n(TWO)\n");
    }

    #[test]
    fn taps_are_g33_groups_with_and_without_point_c() {
        let tap = |then_x| {
            ItemKind::TapCycle(TapCycle {
                end_z: mm(-25),
                lead: crate::fixed::Lead::from_length(Length::from_steps(17_500)),
                then_x,
            })
        };
        let (out, _) = write(
            vec![turning(), at(mm(0), mm(5)), tap(None)],
            WriteOptions::default(),
        );
        assert!(
            out.unwrap()
                .ends_with("N4 G33 *\nN5 X0 *\nN6 Z-2500 *\nN7 F17500\n")
        );
        let (out, _) = write(
            vec![turning(), at(mm(0), mm(5)), tap(Some(mm(20)))],
            WriteOptions::default(),
        );
        assert!(
            out.unwrap()
                .ends_with("N4 G33 @ *\nN5 X2000 *\nN6 Z-2500 *\nN7 F17500\n")
        );
    }

    /// nc31 → nc31, read with `read` and written with `write`.
    fn rewrite(text: &str, read: &Profile, write: &Profile) -> String {
        let src = SourceFile::new("t.nc", text);
        let (program, diags) = super::super::front::parse(&src, &read.nc31, &Default::default());
        assert!(!crate::diag::has_errors(&diags), "{diags:?}");
        let (out, diags) = emit(&program, &src, write, &WriteOptions::default());
        assert!(diags.is_empty(), "{diags:?}");
        out.unwrap()
    }

    const CHAMFERS: &str = "N0 M3\nN1 S500\nN2 X2000 ~ *\nN3 Z0 ~\nN4 X3000+45 *\nN5 F20\nN6 Z-1000\nN7 Z-1500-45 *\nN8 F20\nN9 X3000 *\nN10 Z-2000\nN11 X3000 *\nN12 Z-2500\n";

    /// With `chamfer45` a 45° feed move is an `X<end>±45 *` + `F` group, whatever form the
    /// source gave it; without, its X and Z frames.
    #[test]
    fn a_45_degree_feed_move_is_a_chamfer_where_the_profile_says() {
        let mut chamfers = Profile::default();
        chamfers.nc31.chamfer45 = true;
        assert_eq!(
            rewrite(CHAMFERS, &Profile::default(), &chamfers),
            "N0 M3\nN1 S500\nN2 X2000 ~ *\nN3 Z0 ~\nN4 X3000+45 *\nN5 F20\nN6 Z-1000\nN7 X2000-45 *\nN8 F20\nN9 X3000-45 *\nN10 F20\nN11 X3000 *\nN12 Z-2500\n"
        );
        assert_eq!(
            rewrite(CHAMFERS, &Profile::default(), &Profile::default()),
            "N0 M3\nN1 S500\nN2 X2000 ~ *\nN3 Z0 ~\nN4 F20\nN5 X3000 *\nN6 Z500\nN7 Z-1000\nN8 X2000 *\nN9 Z-1500\nN10 X3000 *\nN11 Z-2000\nN12 X3000 *\nN13 Z-2500\n"
        );
        // A 45° move whose start is off the unit grid is written as its frames (the control
        // would compute Z from a rounded start), and so is one whose end is.
        let (out, _) = write(
            vec![
                turning(),
                at(Length::from_steps(200_050), mm(0)),
                ItemKind::Feed {
                    to: Pos::new(Length::from_steps(300_050), mm(5)),
                    feed: Length::from_steps(2_000),
                },
            ],
            WriteOptions {
                round: true,
                ..WriteOptions::default()
            },
        );
        assert!(!out.unwrap().contains("45"));
        let src = SourceFile::new("t", "");
        let program = Program {
            items: [
                turning(),
                at(mm(20), mm(0)),
                ItemKind::Feed {
                    to: Pos::new(mm(30), mm(5)),
                    feed: Length::from_steps(2_000),
                },
                ItemKind::Feed {
                    to: Pos::new(Length::from_steps(300_100), Length::from_steps(50_050)),
                    feed: Length::from_steps(2_000),
                },
            ]
            .into_iter()
            .map(|k| Item::new(k, Span::default()))
            .collect(),
            dialect: crate::dialect::iso::ID,
            library: Vec::new(),
            number: None,
            inch: false,
            name: None,
        };
        let (out, _) = emit(
            &program,
            &src,
            &chamfers,
            &WriteOptions {
                round: true,
                ..WriteOptions::default()
            },
        );
        assert!(
            out.as_deref()
                .is_some_and(|o| o.ends_with("N4 X3000+45 *\nN5 F20\nN6 X3001 *\nN7 Z501\n")),
            "{out:?}"
        );
    }

    /// A G25 is written out: its frames again, each group as read, never `G25`.
    #[test]
    fn a_repeat_is_written_out_group_by_group() {
        let mut repeat = Profile::default();
        repeat.nc31.repeat_g25 = true;
        let grooves = "N0 M3\nN1 S500\nN2 X2000 ~ *\nN3 Z0 ~\nN4 F10\nN5 Z-500 @ ~\nN6 X-400 @\nN7 X400 @ ~\nN8 G25 *\nN9 P5007 *\nN10 P2\nN11 X5000 ~\n";
        assert_eq!(
            rewrite(grooves, &repeat, &Profile::default()),
            "N0 M3\nN1 S500\nN2 X2000 ~ *\nN3 Z0 ~\nN4 F10\nN5 Z-500 ~\nN6 X1600\nN7 X2000 ~\nN8 Z-1000 ~\nN9 X1600\nN10 X2000 ~\nN11 Z-1500 ~\nN12 X1600\nN13 X2000 ~\nN14 X5000 ~\n"
        );
        // One group repeated right after itself: its items start over, a group each time.
        let one = "N0 M3\nN1 S500\nN2 X2000 ~ *\nN3 Z0 ~\nN4 F10\nN5 Z-100 @\nN6 G25 *\nN7 P5005 *\nN8 P2\n";
        assert_eq!(
            rewrite(one, &repeat, &Profile::default()),
            "N0 M3\nN1 S500\nN2 X2000 ~ *\nN3 Z0 ~\nN4 F10\nN5 Z-100\nN6 Z-200\nN7 Z-300\n"
        );
        let two = "N0 M3\nN1 S500\nN2 X2000 ~ *\nN3 Z0 ~\nN4 F10\nN5 S600 *\nN6 Z-100 @\nN7 G25 *\nN8 P5006 *\nN9 P1\n";
        assert_eq!(
            rewrite(two, &repeat, &Profile::default()),
            "N0 M3\nN1 S500\nN2 X2000 ~ *\nN3 Z0 ~\nN4 F10\nN5 S600 *\nN6 Z-100\nN7 S600 *\nN8 Z-200\n"
        );
    }

    #[test]
    fn what_the_control_cannot_do_is_refused() {
        let (_, diags) = write(
            vec![
                ItemKind::FeedMode(FeedMode::PerMin),
                ItemKind::Feed {
                    to: Pos::new(mm(20), mm(5)),
                    feed: mm(100),
                },
            ],
            WriteOptions::default(),
        );
        assert_eq!(codes_of(&diags), ["NCW002"]);
        // Nothing left to write is refused, not an empty program with exit 0.
        let (out, diags) = write(
            vec![ItemKind::GearRange {
                code: 42,
                machine: crate::dialect::iso::ID,
            }],
            WriteOptions::default(),
        );
        assert_eq!(out, None);
        assert_eq!(codes_of(&diags), ["NCW004", "NCW008"]);
    }
}

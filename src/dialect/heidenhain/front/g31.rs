//! HEIDENHAIN's thread cycle `G31`, read under ncthread's model of it (README, "HEIDENHAIN
//! G31"; spec heidenhain.md, "Reading").
//!
//! **\[evidence\]** MANUALplus 620 / CNC PILOT 640 DIN manual p.272 and the seed's p.303: G31
//! cuts a thread on a contour, here the one written after the call and ended by `G80`; B and
//! P extend the thread contour (run-in, run-out); I is the maximum infeed (`F/3` when not
//! written under V0); IC the number of cuts, the infeed "calculated from IC and U" (V0, V1);
//! V0 keeps the chip cross-section constant, V1 the infeed, V2 cuts the remainder of U over I
//! first and splits the last cut into 1/2, 1/4, 1/8 and 1/8; Q idle passes after the last.
//!
//! **\[decided\]** What the manuals leave open is ncthread's model, read only where the profile
//! declares the machine cuts that way (`g31_clearance`, and `g31_infeed` where V0/V1 take I):
//! the tool rapids to the start point, `g31_clearance` per side above the crest at the start
//! of the run-in; each pass starts at the index pulse (a one-start thread's phase is no
//! property of the part unless C ties it to the contour), the tool coming in along X (H0) or
//! to a start moved along Z by the depth · tan A (H1, H2, the way `g31_h1` says), cuts to the
//! run-out's end, leaves to the start point's diameter and returns along Z; the cycle ends at
//! the start point. One straight or tapered element (`G0 X Z`, `G1 X Z`, `G80`), external;
//! what else G31 says (H3, starts D, C, K, transverse J1, BD1, V3–V6, contours named by NS/NE
//! or ID) is refused by name.

use std::ops::Range;

use super::super::profile::{G31Infeed, G31Offset};
use super::{FrontEnd, codes};
use crate::dialect::heidenhain::syntax::{Block, Value, Word};
use crate::fixed::{Angle, Lead, Length};
use crate::ir::{Finish, ItemKind, Pos, Retract, Schedule, Slope, ThreadCycle};
use crate::lower;
use crate::source::{Line, Span};

/// The words a G31 block may hold.
const G31_WORDS: &[&str] = &[
    "I", "IC", "B", "P", "A", "V", "H", "C", "BD", "F", "U", "K", "D", "E", "Q", "J", "O", "R",
    "ID", "NS", "NE", "X", "Z",
];

const ABOUT: &str = "ncthread reads `G31 F U B P [I|IC] [V0|V1|V2] [Q]` with one contour element after it (`G0 X Z`, `G1 X Z`, `G80`), under the profile's g31_clearance (README, section HEIDENHAIN)";

/// A G31 call whose contour is being read.
pub(super) struct PendingG31 {
    /// The cycle's values; `None` when the call was refused (its contour is still passed
    /// over up to G80).
    call: Option<Call>,
    /// The contour so far: its start, then the end of its element.
    contour: Vec<Pos>,
    /// The call's code, for errors found at G80.
    span: Span,
    number: Option<u32>,
    comment: Option<String>,
}

/// What a G31 call says.
struct Call {
    lead: Lead,
    /// H1/H2's shift of each pass's start towards the thread's end per unit of depth.
    infeed: Slope,
    depth: Length,
    run_in: Length,
    run_out: Length,
    first_depth: Length,
    schedule: Schedule,
    idle: u32,
    clearance: Length,
}

impl FrontEnd<'_> {
    /// A block with `G31`: the call is read (or refused) and its contour awaited.
    pub(super) fn g31_call(&mut self, line: Line<'_>, block: &Block, span: Span) {
        let call = self.g31_words(line, block);
        let named = block
            .words
            .iter()
            .any(|w| matches!(w.name.as_str(), "ID" | "NS" | "NE" | "X" | "Z"));
        if named {
            // The contour is elsewhere (or the cycle is another control's form): no G80 follows.
            return;
        }
        self.g31 = Some(PendingG31 {
            call,
            contour: Vec::new(),
            span,
            number: block.number,
            comment: block.comment.clone(),
        });
    }

    /// The call's words, or `None` after reporting why it is not read.
    fn g31_words(&mut self, line: Line<'_>, block: &Block) -> Option<Call> {
        let whole = block.code_range.clone();
        if self.block_skip(line, block, "") {
            return None;
        }
        let mut words: Vec<&Word> = Vec::new();
        let mut ok = true;
        for w in &block.words {
            let text = &line.text[w.range.clone()];
            let known = G31_WORDS.contains(&w.name.as_str())
                || w.name == "G" && w.number().is_some_and(|n| n.to_whole() == Ok(31));
            if !known {
                self.error(
                    codes::HEIR_G31,
                    line,
                    w.range.clone(),
                    format!("`{text}` in a G31 block"),
                    ABOUT,
                );
                ok = false;
            } else if w.value == Value::Unknown
                || matches!(w.value, Value::Text(_)) && w.name != "ID"
            {
                self.error(
                    codes::HEIR_UNSUPPORTED,
                    line,
                    w.range.clone(),
                    format!("`{text}`: a value the control finds itself is not read"),
                    "write the value as a number",
                );
                ok = false;
            } else if let Some(was) = words.iter().find(|o| o.name == w.name) {
                self.repeated(line, w, was);
                ok = false;
            } else if w.name != "G" {
                words.push(w);
            }
        }
        let get = |name: &str| words.iter().copied().find(|w| w.name == name);
        // Forms other than a contour after the call.
        const NAMED: &str = "a thread on contour blocks named by NS/NE (the finished part's, or an auxiliary contour's) is not read: ncthread reads the contour written after the call";
        const END_POINT: &str =
            "G31 with its end point in the block (X, Z: the MANUALplus 4110's form) is not read";
        for (name, why) in [
            ("NS", NAMED),
            ("NE", NAMED),
            (
                "ID",
                "a thread on an auxiliary contour named by ID is not read: ncthread reads the contour written after the call",
            ),
            ("X", END_POINT),
            ("Z", END_POINT),
        ] {
            if let Some(w) = get(name) {
                self.word_error(codes::HEIR_G31, line, w, format_args!(": {why}"), "write the thread's contour after the call: `G31 F… U… B… P… IC…`, `G0 X… Z…`, `G1 Z…`, `G80`");
                return None;
            }
        }
        // Words whose rule the manuals do not give, or that ask for more than one element.
        for (name, allowed, why) in [
            (
                "D",
                1,
                "a multi-start thread: the order in which G31 cuts the starts is not published; ncthread reads D1",
            ),
            (
                "C",
                0,
                "the start angle C ties the thread to a contour feature; how G31 counts it is not published; ncthread reads C0",
            ),
            (
                "K",
                0,
                "the thread depth's run-out over K: its shape is not published; ncthread reads K0",
            ),
            (
                "J",
                0,
                "a transverse thread (J1) is not read; ncthread reads longitudinal threads (J0)",
            ),
            (
                "O",
                0,
                "chamfers and roundings machined with the thread (O) are not read; a contour after the call has none",
            ),
            (
                "BD",
                0,
                "BD1 on a contour written after the call: the manual's example says the thread stays external whatever BD says; ncthread reads BD0",
            ),
            ("E", 0, "a variable pitch (E) is not read"),
            (
                "R",
                0,
                "the remaining cut depth R belongs to V4 (as the MANUALplus 4110), which is not read",
            ),
        ] {
            if let Some(w) = get(name)
                && w.number().and_then(|d| d.to_whole().ok()) != Some(allowed)
            {
                self.word_error(codes::HEIR_G31, line, w, format_args!(": {why}"), ABOUT);
                ok = false;
            }
        }
        let v = match get("V") {
            None => 0,
            Some(w) => {
                let v = self.whole(line, w, "the infeed type V")?;
                if v > 2 {
                    let what = match v {
                        3 => {
                            "V3 takes its infeeds from the lead and the spindle speed by a rule not published"
                        }
                        4 => "V4 cuts as the MANUALplus 4110, whose rule is not published",
                        5 | 6 => "V5 and V6 cut as the CNC PILOT 4290, whose rule is not published",
                        _ => "the infeed types are V0 to V6",
                    };
                    self.word_error(codes::HEIR_G31, line, w, format_args!(": {what}"), "ncthread reads V0 (constant chip cross-section), V1 (constant infeed) and V2 (the remainder first, the last cut split)");
                    return None;
                }
                v
            }
        };
        let infeed = self.g31_offset(line, get("H"), get("A"))?;
        let lead = self.lead(line, get("F"), whole.clone(), codes::HEIR_G31, "G31")?;
        let Some(u) = get("U") else {
            self.error(
                codes::HEIR_G31,
                line,
                whole,
                "G31 without U, the thread depth",
                "write the depth per side: `U0.92`",
            );
            return None;
        };
        let depth = self.length_of(line, u)?;
        if depth.0 <= 0 {
            self.error(
                codes::HEIR_G31,
                line,
                u.range.clone(),
                "the thread depth U is positive (ncthread reads external threads)",
                "write the depth per side: `U0.92`",
            );
            return None;
        }
        let mut run = |name: &str, what: &str| -> Option<Length> {
            let Some(w) = get(name) else {
                self.error(
                    codes::HEIR_G31,
                    line,
                    whole.clone(),
                    format!("G31 without {name}: the {what} the control then takes from the contour or its machine parameters"),
                    format!("write the {what}: `{name}3`"),
                );
                return None;
            };
            let l = self.length_of(line, w)?;
            if l.0 < 0 {
                self.error(
                    codes::HEIR_G31,
                    line,
                    w.range.clone(),
                    format!("the {what} {name} is not negative"),
                    format!("write the {what}: `{name}3`"),
                );
                return None;
            }
            Some(l)
        };
        let run_in = run("B", "run-in length");
        let run_out = run("P", "run-out length");
        let (run_in, run_out) = (run_in?, run_out?);
        let idle = match get("Q") {
            Some(w) => self.whole(line, w, "the number of idle passes Q")?,
            None => 0,
        };
        let (schedule, first_depth) = self.g31_schedule(line, &get, v, lead, depth, whole)?;
        if !ok {
            return None;
        }
        if self.surface {
            self.error(
                codes::HEIR_G31,
                line,
                block.code_range.clone(),
                "G31 under constant surface speed (G96): a thread under G96 is not read",
                "write `G97 S…` before the cycle",
            );
            return None;
        }
        let Some(clearance) = self.profile.g31_clearance else {
            self.unknown(
                "g31",
                line,
                block.code_range.clone(),
                "G31: where the tool goes between passes, and where the cycle starts and ends, is not published",
                "if the machine's G31 cuts as ncthread's model (README, \"HEIDENHAIN G31\"), declare its retract height per side above the crest, `g31_clearance = 1.0`, in the profile's [heidenhain] section",
            );
            return None;
        };
        Some(Call {
            lead,
            infeed,
            depth,
            run_in,
            run_out,
            first_depth,
            schedule,
            idle,
            clearance,
        })
    }

    /// H and A: radial (H0), or each pass's start moved along Z by its depth · tan A (H1,
    /// H2) the way the profile's `g31_h1` says; `None` when refused (reported).
    fn g31_offset(&mut self, line: Line<'_>, h: Option<&Word>, a: Option<&Word>) -> Option<Slope> {
        let h_value = match h {
            Some(w) => self.whole(line, w, "the offset type H")?,
            None => 0,
        };
        // **[evidence]** p.272: A, the approach angle (angle of infeed), 30° when not written.
        let degrees = match a {
            Some(w) => {
                let d = w
                    .number()
                    .map(|d| d.to_f64())
                    .filter(|d| (-60.0..=60.0).contains(d));
                if d.is_none() {
                    self.word_error(
                        codes::HEIR_G31,
                        line,
                        w,
                        ": the approach angle A is −60° to 60°",
                        "write the infeed angle from the X axis, `A30`",
                    );
                    return None;
                }
                d?
            }
            None => 30.0,
        };
        let Some(h) = h.filter(|_| h_value != 0) else {
            // H0: without offset; A moves nothing.
            return Some(Slope::ZERO);
        };
        if h_value > 2 {
            let why = if h_value == 3 {
                "the offsets alternating right and left (H3): their pattern is published only as prose"
            } else {
                "the offset types are H0 to H3"
            };
            self.word_error(
                codes::HEIR_G31,
                line,
                h,
                format_args!(": {why}"),
                "ncthread reads H0 (no offset), and H1/H2 under the profile's g31_h1",
            );
            return None;
        }
        let Some(way) = self.profile.g31_h1 else {
            self.unknown(
                "g31_h1",
                line,
                h.range.clone(),
                "G31 H1/H2: which way along Z the offset \"from the left\" moves each cut is not published",
                "declare `g31_h1 = \"towards-end\"` or `\"towards-start\"` in the profile's [heidenhain] section, as a test cut shows",
            );
            return None;
        };
        let slope = Slope::of_degrees(degrees);
        let towards_end = (way == G31Offset::TowardsEnd) == (h_value == 1);
        Some(if towards_end {
            slope
        } else {
            Slope {
                rise: -slope.rise,
                ..slope
            }
        })
    }

    /// The depth law of infeed type `v` with I or IC, and the first cut it names.
    fn g31_schedule<'w>(
        &mut self,
        line: Line<'_>,
        get: &dyn Fn(&str) -> Option<&'w Word>,
        v: u32,
        lead: Lead,
        depth: Length,
        whole: Range<usize>,
    ) -> Option<(Schedule, Length)> {
        if let (Some(_), Some(ic)) = (get("I"), get("IC")) {
            self.error(
                codes::HEIR_CONFLICT,
                line,
                ic.range.clone(),
                "G31 with both I (the maximum infeed) and IC (the number of cuts)",
                "give the infeed I or the number of cuts IC",
            );
            return None;
        }
        if let Some(w) = get("IC") {
            let n = self.whole(line, w, "the number of cuts IC")?;
            if v == 2 || n == 0 {
                let (message, help) = if n == 0 {
                    (
                        "IC, the number of cuts, is at least 1",
                        "write the number of cuts: `IC6`",
                    )
                } else {
                    (
                        "IC, the number of cuts, works with V0 and V1",
                        "give V2 its infeed I",
                    )
                };
                self.error(codes::HEIR_G31, line, w.range.clone(), message, help);
                return None;
            }
            let schedule = if v == 0 {
                Schedule::AreaInPasses(n)
            } else {
                Schedule::DepthInPasses(n)
            };
            return Some((schedule, first_cut(schedule, depth)));
        }
        let written = get("I");
        let i = match written {
            Some(w) => {
                let i = self.length_of(line, w)?;
                if i.0 <= 0 {
                    self.error(
                        codes::HEIR_G31,
                        line,
                        w.range.clone(),
                        "the maximum infeed I is positive",
                        "write the infeed per side: `I0.3`",
                    );
                    return None;
                }
                i
            }
            // **[evidence]** p.272: "No input and V=0: I = 1/3 * F".
            None if v == 0 => lead.length_times(1, 3),
            None => {
                self.error(
                    codes::HEIR_G31,
                    line,
                    whole,
                    format!("G31 V{v} without I (the maximum infeed) or IC (the number of cuts)"),
                    "write the infeed per side `I0.3` (or, for V1, the number of cuts `IC6`)",
                );
                return None;
            }
        };
        if v == 2 {
            return Some((Schedule::RemainderFirst, i));
        }
        let Some(infeed) = self.profile.g31_infeed else {
            self.unknown(
                "g31_infeed",
                line,
                whole,
                "G31 V0 or V1 with the infeed I: whether I is the first cut or only bounds cuts spread evenly over the depth is not published",
                "declare `g31_infeed = \"first\"` or `\"spread\"` in the profile's [heidenhain] section, as the machine's cycle cuts, or give the number of cuts IC",
            );
            return None;
        };
        Some(match (infeed, v) {
            // I bounds the first cut: a depth under it is one pass.
            (G31Infeed::First, 0) => (Schedule::ConstantArea, i.min(depth)),
            (G31Infeed::First, _) => (Schedule::ConstantDepth, i.min(depth)),
            (G31Infeed::Spread, _) => {
                // U/I exactly (I = F/3 from the lead itself when not written), in lengths'
                // grid units: U/I = u/i.
                let (u, i) = match written {
                    Some(_) => (depth.0 as u128, i.0 as u128),
                    None => (
                        3 * depth.0 as u128 * Lead::PER_LENGTH as u128,
                        lead.0 as u128,
                    ),
                };
                let n = spread_passes(u, i, v == 0);
                let schedule = if v == 0 {
                    Schedule::AreaInPasses(n)
                } else {
                    Schedule::DepthInPasses(n)
                };
                (schedule, first_cut(schedule, depth))
            }
        })
    }

    /// A block of the contour after a G31 call: `G0 X Z` first, one `G1`, then `G80`.
    pub(super) fn g31_contour(&mut self, line: Line<'_>, block: &Block) {
        let Some(mut pending) = self.g31.take() else {
            return;
        };
        if block.words.is_empty() {
            self.g31 = Some(pending);
            return;
        }
        if self.block_skip(line, block, " in G31's contour") {
            pending.call = None;
        }
        let g: Vec<i64> = block
            .words
            .iter()
            .filter(|w| w.name == "G")
            .filter_map(|w| w.number()?.to_whole().ok())
            .collect();
        if g.contains(&80) {
            if block.words.len() > 1 {
                self.error(
                    codes::HEIR_G31,
                    line,
                    block.code_range.clone(),
                    "G80 with other words: it ends G31's contour in a block of its own",
                    "write `G80` alone, and the other words in the next block",
                );
            } else if let Some(call) = pending.call.take() {
                self.g31_cycle(line, &pending, call);
            }
            return;
        }
        if pending.call.is_some() {
            let element = self.g31_element(line, block, &g, &pending.contour);
            match element {
                Some(p) => pending.contour.push(p),
                None => pending.call = None,
            }
        }
        self.g31 = Some(pending);
    }

    /// One contour block's end point, or `None` after reporting why it is not read.
    fn g31_element(
        &mut self,
        line: Line<'_>,
        block: &Block,
        g: &[i64],
        contour: &[Pos],
    ) -> Option<Pos> {
        let whole = block.code_range.clone();
        let first = contour.is_empty();
        let expected = if first { 0 } else { 1 };
        let mut to = Pos::UNKNOWN;
        let mut ok = g == [expected];
        for w in &block.words {
            let slot = match w.name.as_str() {
                "G" => continue,
                "X" => &mut to.x,
                "Z" => &mut to.z,
                _ => {
                    ok = false;
                    continue;
                }
            };
            match slot {
                Some(_) => ok = false,
                None => *slot = Some(self.length_of(line, w)?),
            }
        }
        let from = contour.last().copied().unwrap_or(Pos::UNKNOWN);
        let to = Pos {
            x: to.x.or(from.x),
            z: to.z.or(from.z),
        };
        if !ok || to.x.is_none() || to.z.is_none() {
            let help = if first {
                "G31's contour starts with `G0 X… Z…` (its start point), then one `G1 X… Z…` and `G80`"
            } else {
                "G31's contour element is `G1 X… Z…` (absolute), then `G80`"
            };
            self.error(
                codes::HEIR_G31,
                line,
                whole,
                "a block of G31's contour ncthread does not read",
                help,
            );
            return None;
        }
        if contour.len() >= 2 {
            self.error(
                codes::HEIR_G31,
                line,
                whole,
                "a second element in G31's contour: a succession of threads is not read",
                "ncthread reads one straight or tapered element: `G0 X… Z…`, `G1 X… Z…`, `G80`; cut each thread with its own G31",
            );
            return None;
        }
        Some(to)
    }

    /// At G80: the cycle on the contour read, pushed at the call.
    fn g31_cycle(&mut self, g80: Line<'_>, pending: &PendingG31, call: Call) {
        let here = |fe: &mut Self, message: String, help: &str| {
            let at = pending.span;
            fe.r.error(codes::HEIR_G31, at, message, help);
        };
        let [start, end] = pending.contour[..] else {
            self.error(
                codes::HEIR_G31,
                g80,
                0..g80.text.trim_end().len(),
                "G80 ends a G31 contour that has no element",
                "write the contour: `G0 X… Z…` (its start), `G1 X… Z…`, then `G80`",
            );
            return;
        };
        let (Some(xs), Some(zs), Some(xe), Some(ze)) = (start.x, start.z, end.x, end.z) else {
            return;
        };
        let dz = ze - zs;
        let dx = xe - xs;
        if dz.0 == 0 && dx.0 == 0 {
            here(
                self,
                "G31's contour element has no length".into(),
                "write the element from the thread's start to its end: `G0 X… Z…`, `G1 Z…`",
            );
            return;
        }
        // Longitudinal: the element runs further along Z than its radius changes.
        if dz.0 == 0 || dx.0.abs() >= 2 * dz.0.abs() {
            here(
                self,
                "G31's contour element runs along X as far as along Z or further: a transverse thread is not read".into(),
                "ncthread reads longitudinal threads on G31",
            );
            return;
        }
        if dx.0 != 0 && (call.run_in.0 != 0 || call.run_out.0 != 0) {
            here(
                self,
                "a taper G31 with a run-in or run-out: whether B and P extend the cone along Z or along its line is not published".into(),
                "write B0 P0 and the taper's contour from where the thread's passes start to where they end",
            );
            return;
        }
        // A start moved towards the end by more than the run-in would rapid into the stock.
        let reach = call.infeed.of(call.depth);
        if reach > call.run_in {
            here(
                self,
                format!(
                    "the last pass's start moves {} mm towards the thread's end (U · tan A), further than the run-in B{}: the tool would rapid into the stock",
                    reach.mm(),
                    call.run_in.mm()
                ),
                "lengthen the run-in B to at least the offset, or cut with H0",
            );
            return;
        }
        let towards_end = dz.0.signum();
        let az = zs - Length(towards_end * call.run_in.0);
        let end_z = ze + Length(towards_end * call.run_out.0);
        let root = xs.min(xe) - call.depth - call.depth;
        if root.0 <= 0 {
            here(
                self,
                format!(
                    "the thread depth U{} reaches the spindle axis from the diameter {}",
                    call.depth.mm(),
                    xs.min(xe).mm()
                ),
                "check U (the depth per side) and the contour's X (a diameter)",
            );
            return;
        }
        let ax = xs.max(xe) + call.clearance + call.clearance;
        let cycle = ThreadCycle {
            start: (ax, az),
            crest: xs,
            end_z,
            lead: call.lead,
            depth: call.depth,
            first_depth: call.first_depth,
            taper: dx,
            infeed: call.infeed,
            infeed_moves_end: false,
            start_angle: Angle::ZERO,
            entry: None,
            entry_infeed: false,
            runout: None,
            retract: Retract::AboveCrest(call.clearance),
            spring_passes: call.idle,
            finish: Finish::Start,
            internal: false,
            schedule: call.schedule,
        };
        if let Err(e) = lower::check(&cycle) {
            here(
                self,
                format!("G31 cannot be cut: {}", e.message(&cycle)),
                "check U, I or IC, F and the contour",
            );
            return;
        }
        let a = Pos::new(ax, az);
        let first = self.r.items.len();
        self.r
            .push(ItemKind::Rapid { to: a }, pending.span, pending.number);
        self.r.push(
            ItemKind::ThreadCycle(Box::new(cycle)),
            pending.span,
            pending.number,
        );
        if let Some(comment) = pending.comment.clone()
            && let Some(item) = self.r.items.held_mut(first)
        {
            item.comment = Some(comment.into());
        }
        self.r.pos = a;
        // G31's F is its lead: whether it is the feed's F too is not published (as G33's).
        // The cycle ends with a rapid back to its start point, so a G33 after it waits for
        // the index pulse as after any rapid.
        self.f = None;
        self.after_thread = false;
        self.motion = None;
    }

    /// A program that ends (or a section that starts) while a G31 contour is being read.
    pub(super) fn g31_unended(&mut self) {
        if let Some(pending) = self.g31.take() {
            self.r.error(
                codes::HEIR_G31,
                pending.span,
                "G31's contour is not ended by G80: the blocks after the call were read as its contour",
                "end the contour after the call with `G80`",
            );
        }
    }
}

/// The first cut of a schedule that spreads `depth` over its passes (for people: the law
/// does not use it); zero when the depth cannot be spread (refused where the cycle is checked).
fn first_cut(schedule: Schedule, depth: Length) -> Length {
    lower::pass_depths(schedule, depth, Length::ZERO)
        .ok()
        .and_then(|d| d.first().copied())
        .unwrap_or(Length::ZERO)
}

/// The fewest passes whose cuts stay within I, for U/I = `u`/`i`: ⌈(U/I)²⌉ for equal areas,
/// ⌈U/I⌉ for equal cuts (at least 1; `u32::MAX` when too many to count).
fn spread_passes(u: u128, i: u128, area: bool) -> u32 {
    let g = gcd(u, i.max(1));
    let (u, i) = (u / g, i.max(1) / g);
    let n = if area {
        match (u.checked_mul(u), i.checked_mul(i)) {
            (Some(uu), Some(ii)) => uu.div_ceil(ii),
            _ => u128::MAX,
        }
    } else {
        u.div_ceil(i)
    };
    u32::try_from(n).unwrap_or(u32::MAX).max(1)
}

fn gcd(mut a: u128, mut b: u128) -> u128 {
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a.max(1)
}

#[cfg(test)]
mod tests {
    use super::spread_passes;

    #[test]
    fn spread_passes_count_exactly() {
        // U1, I = F/3 with F1: (3·1/1)² = 9 exactly (I rounded to 0.3333 would give 10).
        assert_eq!(spread_passes(3, 1, true), 9);
        // U0.92, I0.5: ⌈3.3856⌉ = 4; ⌈1.84⌉ = 2.
        assert_eq!(spread_passes(92, 50, true), 4);
        assert_eq!(spread_passes(92, 50, false), 2);
        // U2.0001, I = 2/3: (3·2.0001/2)² = 9.0009 → 10.
        assert_eq!(spread_passes(3 * 20_001, 20_000, true), 10);
        assert_eq!(spread_passes(1, 0, true), 1);
        assert_eq!(spread_passes(u128::MAX / 2, 1, true), u32::MAX);
    }
}

//! LinuxCNC's drilling cycles in the front end: G73, G81, G82, G83, G85 and G89 in G17, along
//! Z at the hole's X (a lathe has no Y). Each block becomes the rapids, feeds and dwells rs274
//! makes of it, so that every target writes them and `simulate`, `verify` and `explain` see
//! them; what rs274 refuses is refused in its words (ISOR022).
//! **\[evidence\]** LinuxCNC 2.9.0~pre1 `interp_cycles.cc` (`convert_cycle`, `convert_cycle_xy`,
//! `convert_cycle_g81`, `_g82`, `_g83`, `_g73`, `_g85`, `_g89`), `interp_internal.hh`
//! (`CYCLE_MACRO`, `G83_RAPID_DELTA`), `interp_convert.cc` (`convert_motion` forgets the
//! initial level at any other motion), `interp_read.cc` (`read_integer_value` for L).

use super::super::gcode::*;
use super::super::syntax::Word;
use super::{FrontEnd, Motion, Words};
use crate::dialect::iso::codes;
use crate::fixed::{Decimal, Length};
use crate::ir::{ItemKind, Pos};
use crate::source::{Line, Span};

/// The cycles' modal values as LinuxCNC keeps them (`cycle_il`, `cycle_r`, `cycle_cc`,
/// `cycle_q`, `cycle_p`): numbers in the program's units when they were set (LinuxCNC
/// converts none of them when the units change).
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct DrillState {
    /// The initial level: the Z where the first cycle block found the tool, kept until a
    /// motion that is not a cycle (G80 included).
    initial: Option<f64>,
    /// R as written (under G91 an increment from the initial level).
    r: f64,
    /// Z as written (under G91 an increment from R).
    z: f64,
    /// G73's and G83's peck.
    q: f64,
    /// G82's and G89's dwell.
    p: Option<Decimal>,
}

impl DrillState {
    pub(super) fn forget_initial_level(&mut self) {
        self.initial = None;
    }
}

/// G83's clearance above the last peck's depth before it feeds again, and G73's
/// chip-breaking retract: 0.010 in the program's units under G20, times 25.4 under G21
/// (LinuxCNC 2.9.0~pre1; later versions take it from a D word or the INI).
const RAPID_DELTA: f64 = 0.010;

/// The most moves one cycle block may make: ncthread's limit (an L or a Q could ask for
/// billions), far above any real hole.
pub(super) const MAX_STEPS: usize = 100_000;

/// One move of a cycle: Z in the program's units; X exact in mm (a diameter, where the tool
/// goes), `None` where it stays.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Step {
    Rapid(Option<f64>, f64),
    Feed(Option<f64>, f64),
    /// The cycle's P.
    Dwell,
}

/// A cycle block as `convert_cycle_xy` has set it up (Z values in the program's units).
#[derive(Clone, Copy, Debug)]
pub(super) struct Plan {
    code: GCode,
    /// The Z where the tool is.
    current: f64,
    /// The initial level.
    initial: f64,
    r: f64,
    bottom: f64,
    /// G99: the tool retracts to R; G98: to the initial level (or R, if that is higher).
    to_r_plane: bool,
    /// G73's and G83's peck, and their δ.
    q: f64,
    delta: f64,
    /// X (mm, a diameter) before the first hole and the step added before each hole (0
    /// under G90), or `None`: X stays where it is.
    x: Option<(f64, f64)>,
    repeats: u32,
}

/// A cycle block's moves, and where it leaves the tool.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Expanded {
    pub(super) steps: Vec<Step>,
    pub(super) x: Option<f64>,
    pub(super) z: f64,
}

/// The moves of a cycle block, as rs274 computes them (in doubles, with its loop for the
/// pecks); `Err` when there would be more than `limit`.
pub(super) fn expand(p: &Plan, limit: usize) -> Result<Expanded, ()> {
    let mut steps = Vec::new();
    let (mut old, mut current) = (p.initial, p.current);
    // Below R: first straight up to R, which becomes the initial level of this block.
    if old < p.r {
        steps.push(Step::Rapid(None, p.r));
        old = p.r;
        current = p.r;
    }
    let clear = if p.to_r_plane { p.r } else { old };
    let mut x = p.x.map(|(x, _)| x);
    let step = p.x.map_or(0.0, |(_, s)| s);
    let over = |steps: &Vec<Step>| steps.len() > limit;
    for repeat in 0..p.repeats {
        x = x.map(|x| x + step);
        // CYCLE_MACRO: the first hole from above R along X at the current level, then down
        // to R; every other from the clear level, down to R if that is above it.
        if repeat == 0 && current > p.r {
            steps.push(Step::Rapid(x, current));
            steps.push(Step::Rapid(None, p.r));
        } else {
            steps.push(Step::Rapid(x, clear));
            if clear > p.r {
                steps.push(Step::Rapid(None, p.r));
            }
        }
        match p.code {
            G73 | G83 => {
                let mut depth = p.r - p.q;
                while depth > p.bottom {
                    steps.push(Step::Feed(None, depth));
                    if p.code == G83 {
                        steps.push(Step::Rapid(None, p.r));
                    }
                    steps.push(Step::Rapid(None, depth + p.delta));
                    depth -= p.q;
                    if over(&steps) {
                        return Err(());
                    }
                }
                steps.push(Step::Feed(None, p.bottom));
                steps.push(Step::Rapid(None, clear));
            }
            G82 => {
                steps.push(Step::Feed(None, p.bottom));
                steps.push(Step::Dwell);
                steps.push(Step::Rapid(None, clear));
            }
            G85 => {
                steps.push(Step::Feed(None, p.bottom));
                steps.push(Step::Feed(None, p.r));
                steps.push(Step::Rapid(None, clear));
            }
            G89 => {
                steps.push(Step::Feed(None, p.bottom));
                steps.push(Step::Dwell);
                steps.push(Step::Feed(None, clear));
            }
            _ => {
                steps.push(Step::Feed(None, p.bottom));
                steps.push(Step::Rapid(None, clear));
            }
        }
        if over(&steps) {
            return Err(());
        }
    }
    Ok(Expanded { steps, x, z: clear })
}

/// L as LinuxCNC reads an integer: within 0.0001 of a whole number (above it by up to
/// 0.0001, or below the next by less than 0.0001).
fn integer(v: f64) -> Option<f64> {
    let floor = v.floor();
    let frac = v - floor;
    if frac > 0.9999 {
        Some(floor + 1.0)
    } else if frac > 0.0001 {
        None
    } else {
        Some(floor)
    }
}

/// The words a drilling block may use, taken as `convert_cycle` reads them: X, Z, R, L,
/// and Q (G73, G83) or P (G82, G89).
struct DrillWords<'w> {
    x: Option<&'w Word>,
    z: Option<&'w Word>,
    r: Option<&'w Word>,
    l: Option<&'w Word>,
    q: Option<&'w Word>,
    p: Option<&'w Word>,
}

impl<'w> DrillWords<'w> {
    fn take(words: &mut Words<'w>, code: GCode) -> Self {
        let x = words.take('X');
        let z = words.take('Z');
        let r = words.take('R');
        let l = words.take('L');
        let q = if pecks(code) { words.take('Q') } else { None };
        let p = if dwells(code) { words.take('P') } else { None };
        DrillWords { x, z, r, l, q, p }
    }
}

/// G73 and G83 peck (Q).
fn pecks(code: GCode) -> bool {
    matches!(code, G73 | G83)
}

/// G82 and G89 dwell at the bottom (P).
fn dwells(code: GCode) -> bool {
    matches!(code, G82 | G89)
}

/// A cycle block's levels as written: R and Z in the program's units (carried from the
/// block before when the same cycle runs again), and whether it does.
struct Levels {
    same: bool,
    r: f64,
    z: f64,
}

/// A cycle block's place as `convert_cycle_xy` sets it up.
struct Place {
    /// The tool's X (exact mm, a diameter) before the block, if known.
    start_x: Option<f64>,
    /// The Z where the tool is, and the initial level (program units).
    current: f64,
    initial: f64,
    /// R and the bottom of the hole (program units, absolute).
    r: f64,
    bottom: f64,
    /// X (mm, a diameter) before the first hole and the step added before each, or `None`.
    x: Option<(f64, f64)>,
}

impl FrontEnd<'_> {
    fn drill_error(&mut self, line: Line<'_>, at: &Word, message: String, help: &str) {
        self.diag(codes::ISOR_DRILLING, line, at.range.clone(), message, help);
    }

    /// A cycle word's value in the program's units: as written (read as a length), else
    /// `carried` (the block before's, when the same cycle runs again), else refused at `at`
    /// with `missing`'s message and help. `None` once a diagnostic is reported.
    fn cycle_length(
        &mut self,
        line: Line<'_>,
        word: Option<&Word>,
        carried: Option<f64>,
        at: &Word,
        missing: impl FnOnce() -> (String, &'static str),
    ) -> Option<f64> {
        match (word, carried) {
            (Some(w), _) => {
                self.length(line, w)?;
                Some(w.value.to_f64())
            }
            (None, Some(v)) => Some(v),
            (None, None) => {
                let (message, help) = missing();
                self.drill_error(line, at, message, help);
                None
            }
        }
    }

    /// A block of a drilling cycle (`code`), written on the line (`at`) or modal, in
    /// `convert_cycle`'s order: its words and checks, its levels, the hole's X, P and Q,
    /// then the moves `convert_cycle_g8x` makes, and the modal values kept.
    pub(super) fn drill(
        &mut self,
        line: Line<'_>,
        words: &mut Words<'_>,
        at: Option<&Word>,
        span: Span,
        code: GCode,
    ) {
        let name = crate::ir::g_code_name(code);
        let w = DrillWords::take(words, code);
        // The line has the code, or an axis word: there is a word to point at.
        let Some(at) = at.or(w.x).or(w.z) else {
            return;
        };
        if w.x.is_none() && w.z.is_none() {
            return self.missing(
                line,
                at,
                format!("{name} without X or Z (LinuxCNC: \"All axes missing with motion code\")"),
                &format!("give the hole's X or the cycle's Z: `{name} X0 R1 Z-10`"),
            );
        }
        let Some(repeats) = self.read_l(line, w.l) else {
            return;
        };
        let Some(levels) = self.convert_cycle(line, at, code, &w, repeats) else {
            return;
        };
        let Some(place) = self.cycle_xy(line, at, &name, &w, &levels) else {
            return;
        };
        let Some(dwell) = self.cycle_dwell(line, at, code, &w, levels.same) else {
            return;
        };
        let Some(q) = self.cycle_peck(line, at, code, &w, levels.same) else {
            return;
        };
        let plan = Plan {
            code,
            current: place.current,
            initial: place.initial,
            r: place.r,
            bottom: place.bottom,
            to_r_plane: !self.retract_old_z,
            q,
            delta: if self.inch {
                RAPID_DELTA
            } else {
                RAPID_DELTA * 25.4
            },
            x: place.x,
            repeats: repeats.min(f64::from(u32::MAX)) as u32,
        };
        let Some(expanded) = self.expand_cycle(line, at, &name, &w, &plan) else {
            return;
        };
        let Some(feed) = self.feed_rate(line, Some(at), &name, span) else {
            return;
        };
        self.cycle_steps(&expanded.steps, dwell, feed, span);
        let unit = if self.inch { 25.4 } else { 1.0 };
        let end_z = expanded.z * unit + self.axis_offset.1;
        self.exact = (expanded.x.or(place.start_x), Some(end_z));
        self.record_program_z(end_z, expanded.z);
        self.drill = DrillState {
            initial: Some(place.initial),
            r: levels.r,
            z: levels.z,
            q,
            p: if dwells(code) { dwell } else { self.drill.p },
        };
    }

    /// L as `read_l` reads it: an integer, not negative; 1 when not written. `None` once
    /// refused.
    fn read_l(&mut self, line: Line<'_>, l_word: Option<&Word>) -> Option<f64> {
        let Some(l) = l_word else {
            return Some(1.0);
        };
        match integer(l.value.to_f64()) {
            None => {
                self.number_error(
                    line,
                    l,
                    format!(
                        "`{}` is not a whole number (LinuxCNC: \"Non integer value for integer\")",
                        &line.text[l.range.clone()]
                    ),
                    "L is the number of times the cycle runs",
                );
                None
            }
            Some(n) if n < 0.0 => {
                self.number_error(
                    line,
                    l,
                    "L is negative (LinuxCNC: \"Negative L word used\")".into(),
                    "L is the number of times the cycle runs",
                );
                None
            }
            Some(n) => Some(n),
        }
    }

    /// `convert_cycle`'s checks, in its order: a feed rate, no cutter radius compensation,
    /// R (or the block before's), L not 0, the plane G17, Z (or the block before's). R and Z
    /// may be left out when the same cycle ran on the block before. `None` once refused.
    fn convert_cycle(
        &mut self,
        line: Line<'_>,
        at: &Word,
        code: GCode,
        w: &DrillWords<'_>,
        repeats: f64,
    ) -> Option<Levels> {
        let name = crate::ir::g_code_name(code);
        if self.feed.is_none_or(|f| f.0 <= 0) {
            self.drill_error(
                line,
                at,
                format!("{name} with no feed rate (F) set, or F0 (LinuxCNC: \"Cannot feed with zero feed rate\")"),
                "set the feed with F before or on the cycle's line",
            );
            return None;
        }
        if self.compensation {
            self.comp_refusal(
                line,
                at,
                "Cannot use canned cycles with cutter compensation on",
            );
            return None;
        }
        let same = self.motion_before_line == Some(Motion::Drill(code));
        let r = self.cycle_length(line, w.r, same.then_some(self.drill.r), at, || {
            (
                format!("{name} without R (LinuxCNC: \"R clearance plane unspecified in cycle\")"),
                "give R, the level the cycle feeds from, on the cycle's first block",
            )
        })?;
        if repeats == 0.0 {
            let l = w.l.unwrap_or(at);
            self.drill_error(
                line,
                l,
                "L0 (LinuxCNC: \"Cannot do zero repeats of cycle\")".into(),
                "L is the number of times the cycle runs, 1 or more; leave it out for once",
            );
            return None;
        }
        if !self.plane_xy {
            self.refuse_drill_plane(line, at, &name, same);
            return None;
        }
        let z = self.cycle_length(line, w.z, same.then_some(self.drill.z), at, || {
            (
                format!(
                    "{name} without Z (LinuxCNC: \"Z value unspecified in xy plane canned cycle\")"
                ),
                "give Z, the bottom of the hole, on the cycle's first block",
            )
        })?;
        Some(Levels { same, r, z })
    }

    /// A cycle in G18: LinuxCNC drills along Y there, which a lathe does not have.
    fn refuse_drill_plane(&mut self, line: Line<'_>, at: &Word, name: &str, same: bool) {
        let (message, help) = if same {
            (
                format!(
                    "{name} repeated in G18: LinuxCNC drills along Y in the ZX plane (the cycle's Z taken for Y), and a lathe has no Y"
                ),
                "select G17 before the cycle: a lathe drills along Z in G17 (X the hole, Z the depth)",
            )
        } else {
            (
                format!(
                    "{name} in G18 (LinuxCNC: \"Y value unspecified in xz plane canned cycle\"): in the ZX plane LinuxCNC drills along Y, and a lathe has no Y"
                ),
                "select G17 before the cycle: a lathe drills along Z in G17 (X the hole, Z the depth)",
            )
        };
        self.drill_error(line, at, message, help);
    }

    /// `convert_cycle_xy`'s set-up: where the tool is (its Z must be known), the initial
    /// level, R and the bottom (program units) and the hole's X (mm, a diameter) with its
    /// step; R may not be below the bottom. Under G91 R is measured from the initial level,
    /// Z from R, and X added before every hole. `None` once refused.
    fn cycle_xy(
        &mut self,
        line: Line<'_>,
        at: &Word,
        name: &str,
        w: &DrillWords<'_>,
        levels: &Levels,
    ) -> Option<Place> {
        let (start_x, Some(start_z)) = self.exact_start() else {
            self.drill_error_unknown(line, at, name);
            return None;
        };
        // LinuxCNC's numbers: the program's units and coordinates.
        let current = self.program_z(start_z);
        let initial = self.drill.initial.unwrap_or(current);
        let (r, bottom, x) = if self.incremental {
            let x = match w.x {
                Some(w) => {
                    let (_, step) = self.x_word(line, w)?;
                    match start_x {
                        Some(s) => Some((s, step)),
                        None => {
                            self.unknown(line, w);
                            return None;
                        }
                    }
                }
                None => None,
            };
            let r = levels.r + initial;
            (r, r + levels.z, x)
        } else {
            let x = match w.x {
                Some(w) => {
                    let (v, exact) = self.x_word(line, w)?;
                    Some((self.shifted_x(v, exact).1, 0.0))
                }
                None => None,
            };
            (levels.r, levels.z, x)
        };
        if r < bottom {
            let at = w.r.or(w.z).unwrap_or(at);
            self.drill_error(
                line,
                at,
                format!("{name}'s R is below the bottom of the hole (LinuxCNC: \"R less than z in cycle in xy plane\")"),
                if self.incremental {
                    "under G91, R is measured from the initial level and Z from R: a hole's Z is negative"
                } else {
                    "R is the level the cycle feeds from, above Z"
                },
            );
            return None;
        }
        Some(Place {
            start_x,
            current,
            initial,
            r,
            bottom,
            x,
        })
    }

    /// G82's and G89's dwell P (the block before's when the same cycle runs again; −1 is
    /// no word for LinuxCNC, which marks an unwritten one so); `Some(None)` for the other
    /// cycles, `None` once refused.
    fn cycle_dwell(
        &mut self,
        line: Line<'_>,
        at: &Word,
        code: GCode,
        w: &DrillWords<'_>,
        same: bool,
    ) -> Option<Option<Decimal>> {
        if !dwells(code) {
            return Some(None);
        }
        let name = crate::ir::g_code_name(code);
        let lower = name.to_ascii_lowercase();
        match w.p.filter(|w| w.value.to_f64() != -1.0) {
            Some(p) if p.value.is_negative() => {
                self.number_error(
                    line,
                    p,
                    "the dwell time is negative".into(),
                    "P is the dwell at the bottom in seconds, 0 or more",
                );
                None
            }
            Some(p) => Some(Some(p.value)),
            None if same => Some(self.drill.p),
            None => {
                self.drill_error(
                    line,
                    at,
                    format!(
                        "{name} without P (LinuxCNC: \"Dwell time p word missing with {lower}\")"
                    ),
                    "give P, the dwell at the bottom in seconds",
                );
                None
            }
        }
    }

    /// G73's and G83's peck Q (the block before's when the same cycle runs again; −1 is no
    /// word), more than 0; the value kept for the other cycles. `None` once refused.
    fn cycle_peck(
        &mut self,
        line: Line<'_>,
        at: &Word,
        code: GCode,
        w: &DrillWords<'_>,
        same: bool,
    ) -> Option<f64> {
        let q = self.drill.q;
        if !pecks(code) {
            return Some(q);
        }
        let name = crate::ir::g_code_name(code);
        let lower = name.to_ascii_lowercase();
        let written = w.q.filter(|w| w.value.to_f64() != -1.0);
        let q = self.cycle_length(line, written, same.then_some(q), at, || {
            (
                format!("{name} without Q (LinuxCNC: \"Q word missing with {lower}\")"),
                "give Q, the depth of each peck",
            )
        })?;
        if q <= 0.0 {
            let at = w.q.unwrap_or(at);
            self.drill_error(
                line,
                at,
                format!("{name}'s Q is not positive (LinuxCNC: \"Negative or zero q value used\")"),
                "Q is the depth of each peck, more than 0",
            );
            return None;
        }
        Some(q)
    }

    /// The block's moves ([`expand`]), or `None` when there would be more than
    /// [`MAX_STEPS`] (reported at Q or L).
    fn expand_cycle(
        &mut self,
        line: Line<'_>,
        at: &Word,
        name: &str,
        w: &DrillWords<'_>,
        plan: &Plan,
    ) -> Option<Expanded> {
        let Ok(expanded) = expand(plan, MAX_STEPS) else {
            let word = if pecks(plan.code) { w.q } else { None };
            let word = word.or(w.l).unwrap_or(at);
            self.drill_error(
                line,
                word,
                format!("{name} would make more than {MAX_STEPS} moves, ncthread's limit for one cycle block"),
                "check L (the repeats) and Q (the peck)",
            );
            return None;
        };
        Some(expanded)
    }

    /// The block's moves as items: Z from the program's units to mm with the G52/G92
    /// offset, the dwell P where the cycle dwells.
    fn cycle_steps(&mut self, steps: &[Step], dwell: Option<Decimal>, feed: Length, span: Span) {
        let unit = if self.inch { 25.4 } else { 1.0 };
        let off_z = self.axis_offset.1;
        let to = |x: Option<f64>, z: f64| Pos {
            x: x.map(Length::from_mm_f64),
            z: Some(Length::from_mm_f64(z * unit + off_z)),
        };
        for step in steps {
            let kind = match *step {
                Step::Rapid(x, z) => ItemKind::Rapid { to: to(x, z) },
                Step::Feed(x, z) => ItemKind::Feed { to: to(x, z), feed },
                Step::Dwell => match dwell {
                    Some(seconds) => ItemKind::Dwell { seconds },
                    None => continue,
                },
            };
            // A move to where the tool is (rs274 makes them: the move along X to the hole
            // where it stands, the retract to R where it already is) moves nothing.
            let end = kind.end_position(self.r.pos);
            if end == self.r.pos && !matches!(kind, ItemKind::Dwell { .. }) {
                continue;
            }
            self.r.pos = end;
            self.push(kind, span);
        }
    }

    fn drill_error_unknown(&mut self, line: Line<'_>, at: &Word, name: &str) {
        self.diag(
            codes::ISOR_UNKNOWN_POSITION,
            line,
            at.range.clone(),
            format!(
                "{name} from a Z that is not known yet: the cycle starts from where the tool is"
            ),
            "move to an absolute Z (G0 Z…) before the cycle",
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diag::Code;
    use crate::ir::Program;

    use super::super::tests::{first_error, run as read};

    const HEAD: &str = "G7 G17 G21 G90 F100\nG0 X0 Z5\n";

    /// Every refusal rs274 makes of a drilling block (its words in the message, checked
    /// against rs274 2.9.0~pre1), at the word it names.
    #[test]
    fn refuses_what_rs274_refuses() {
        let cases: &[(&str, Code, &str, &str)] = &[
            (
                "G81 R1\n",
                codes::ISOR_WORD,
                "G81",
                "All axes missing with motion code",
            ),
            (
                "G81 X0 R1 Z-10 L1.5\n",
                codes::ISOR_NUMBER,
                "L1.5",
                "Non integer value for integer",
            ),
            (
                "G81 X0 R1 Z-10 L-2\n",
                codes::ISOR_NUMBER,
                "L-2",
                "Negative L word used",
            ),
            (
                "G81 X0 R1 Z-10 F0\n",
                codes::ISOR_DRILLING,
                "G81",
                "Cannot feed with zero feed rate",
            ),
            (
                "G81 X0 Z-10\n",
                codes::ISOR_DRILLING,
                "G81",
                "R clearance plane unspecified in cycle",
            ),
            (
                "G81 X0 R1 Z-10 L0\n",
                codes::ISOR_DRILLING,
                "L0",
                "Cannot do zero repeats of cycle",
            ),
            (
                "G81 X0 R1\n",
                codes::ISOR_DRILLING,
                "G81",
                "Z value unspecified in xy plane canned cycle",
            ),
            (
                "G81 X0 R-11 Z-10\n",
                codes::ISOR_DRILLING,
                "R-11",
                "R less than z in cycle in xy plane",
            ),
            (
                "G91 G81 X0 R-1 Z1\n",
                codes::ISOR_DRILLING,
                "R-1",
                "R less than z in cycle in xy plane",
            ),
            (
                "G82 X0 R1 Z-10\n",
                codes::ISOR_DRILLING,
                "G82",
                "Dwell time p word missing with g82",
            ),
            // P-1 and Q-1 are how LinuxCNC marks a word not written.
            (
                "G89 X0 R1 Z-10 P-1\n",
                codes::ISOR_DRILLING,
                "G89",
                "Dwell time p word missing with g89",
            ),
            (
                "G83 X0 R1 Z-10\n",
                codes::ISOR_DRILLING,
                "G83",
                "Q word missing with g83",
            ),
            (
                "G73 X0 R1 Z-10 Q-1\n",
                codes::ISOR_DRILLING,
                "G73",
                "Q word missing with g73",
            ),
            (
                "G83 X0 R1 Z-10 Q0\n",
                codes::ISOR_DRILLING,
                "Q0",
                "Negative or zero q value used",
            ),
            (
                "G73 X0 R1 Z-10 Q-2\n",
                codes::ISOR_DRILLING,
                "Q-2",
                "Negative or zero q value used",
            ),
            // R, Z, P and Q carry over to the same cycle only.
            (
                "G81 X0 R1 Z-10\nG83 X0 Z-5 Q2\n",
                codes::ISOR_DRILLING,
                "G83",
                "R clearance plane unspecified in cycle",
            ),
            (
                "G83 X0 R1 Z-10 Q2\nG73 X0 R1 Z-5\n",
                codes::ISOR_DRILLING,
                "G73",
                "Q word missing with g73",
            ),
            (
                "G82 X0 R1 Z-10 P1\nG80\nG82 X0 R1 Z-10\n",
                codes::ISOR_DRILLING,
                "G82",
                "Dwell time p word missing with g82",
            ),
            // G80, and the words no command uses.
            (
                "G81 X0 R1 Z-10\nG80 X1\n",
                codes::ISOR_WORD,
                "X1",
                "Cannot use axis values with g80",
            ),
            (
                "G81 X0 R1 Z-10\nG80\nX1\n",
                codes::ISOR_WORD,
                "X1",
                "Cannot use axis values without a g code that uses them",
            ),
            ("G81 X0 R1 Z-10\nR2\n", codes::ISOR_WORD, "R2", "not used"),
            ("G81 X0 R1 Z-10 Q2\n", codes::ISOR_WORD, "Q2", "not used"),
            ("G81 X0 R1 Z-10 P2\n", codes::ISOR_WORD, "P2", "not used"),
            ("G98 G99\n", codes::ISOR_CONFLICT, "G99", "retract mode"),
            // G18: LinuxCNC drills along Y.
            (
                "G18 G81 X0 R1 Z-10\n",
                codes::ISOR_DRILLING,
                "G81",
                "Y value unspecified in xz plane canned cycle",
            ),
            (
                "G81 X0 R1 Z-10\nG18\nX0\n",
                codes::ISOR_DRILLING,
                "X0",
                "drills along Y",
            ),
            // Compensation: under G18 LinuxCNC says so before the plane.
            (
                "G18 T1 M6\nG41 G1 X1 Z4\nG81 X0 R1 Z-10\n",
                codes::ISOR_COMPENSATION,
                "G81",
                "Cannot use canned cycles with cutter compensation on",
            ),
            (
                "G18 T1 M6\nG41 G1 X1 Z4\nG98\n",
                codes::ISOR_COMPENSATION,
                "G98",
                "Cannot change retract mode with cutter radius compensation on",
            ),
            // ncthread's own: a negative dwell (as for G4), too many moves, an unknown Z.
            (
                "G82 X0 R1 Z-10 P-2\n",
                codes::ISOR_NUMBER,
                "P-2",
                "negative",
            ),
            (
                "G81 X0 R1 Z-10 L1000000\n",
                codes::ISOR_DRILLING,
                "L1000000",
                "100000 moves",
            ),
            (
                "G83 X0 R1 Z-10 Q0.0001\n",
                codes::ISOR_DRILLING,
                "Q0.0001",
                "100000 moves",
            ),
            (
                "G84 X0 R1 Z-10\n",
                codes::ISOR_UNSUPPORTED,
                "G84",
                "tapping and boring",
            ),
            (
                "G86 X0 R1 Z-10 P1\n",
                codes::ISOR_UNSUPPORTED,
                "G86",
                "tapping and boring",
            ),
        ];
        for (body, code, marked, words) in cases {
            let text = format!("{HEAD}{body}");
            let (_, d) = read(&text);
            let e = first_error(&d, &text, *code, marked);
            assert!(e.message.contains(words), "{text:?}: {}", e.message);
        }
        // A cycle from an unknown Z.
        let (_, d) = read("G7 G17 G21 F100\nG81 X0 R1 Z-10\n");
        assert_eq!(d[0].code, codes::ISOR_UNKNOWN_POSITION, "{d:?}");
    }

    /// The moves of a program as (kind, X, Z) in mm: `T` rapid, `F` feed, `D` dwell.
    fn moves(p: &Program) -> Vec<(char, Option<f64>, Option<f64>)> {
        let mm = |l: Option<Length>| l.map(Length::to_mm_f64);
        p.items
            .iter()
            .filter_map(|i| match &i.kind {
                ItemKind::Rapid { to } => Some(('T', mm(to.x), mm(to.z))),
                ItemKind::Feed { to, .. } => Some(('F', mm(to.x), mm(to.z))),
                ItemKind::Dwell { .. } => Some(('D', None, None)),
                _ => None,
            })
            .collect()
    }

    /// The modal rules between blocks, each as rs274 runs them (research programs
    /// q3_modal_repeat, q3_below_r, q3_g91_L, q3_g83_inch).
    #[test]
    fn blocks_follow_rs274s_modal_rules() {
        let t = |x: Option<f64>, z: f64| ('T', x, Some(z));
        let f = |z: f64| ('F', None, Some(z));
        let x = Some;
        // The initial level Z5 stays through the repeats; G99 then G98 at the next hole: a
        // diagonal from R up to the initial level. (Moves to where the tool is, which rs274
        // makes too, are left out: here the first, to X0 at Z5.)
        let (p, d) = read(&format!(
            "{HEAD}G98 G81 X0 R1 Z-10\nX3\nG99 X6\nG98 X9\nG80\n"
        ));
        assert!(d.is_empty(), "{d:?}");
        assert_eq!(
            moves(&p)[1..],
            [
                t(None, 1.0),
                f(-10.0),
                t(None, 5.0),
                t(x(3.0), 5.0),
                t(None, 1.0),
                f(-10.0),
                t(None, 5.0),
                t(x(6.0), 5.0),
                t(None, 1.0),
                f(-10.0),
                t(None, 1.0),
                t(x(9.0), 5.0),
                t(None, 1.0),
                f(-10.0),
                t(None, 5.0),
            ]
        );
        // Below R: straight up to R first, and G98 then retracts to R. A line with only Z
        // repeats the cycle there. (rs274 then moves to X0 at Z1, where the tool is; the next
        // block's initial level is still Z-2, so it goes up to R again, and along X to X0 at
        // R: all where the tool is.)
        let (p, d) = read("G7 G17 G21 G90 F100\nG0 X0 Z-2\nG98 G81 X0 R1 Z-10\nZ-12\n");
        assert!(d.is_empty(), "{d:?}");
        assert_eq!(
            moves(&p)[1..],
            [t(None, 1.0), f(-10.0), t(None, 1.0), f(-12.0), t(None, 1.0)]
        );
        // G91: R from the initial level, Z from R, X added before each of the L holes (in
        // G7 X is a diameter).
        let (p, d) = read(&format!("{HEAD}G91 G98 G81 X2 R-4 Z-11 L3\n"));
        assert!(d.is_empty(), "{d:?}");
        assert_eq!(
            moves(&p)[1..5],
            [t(x(2.0), 5.0), t(None, 1.0), f(-10.0), t(None, 5.0)]
        );
        assert_eq!(moves(&p)[9], t(x(6.0), 5.0));
        // G20: δ is 0.010 inch (0.254 mm).
        let (p, d) = read(
            "G7 G17 G20 G90 F10\nG0 X0 Z0.5\nG98 G73 X0 R0.1 Z-0.5 Q0.2\nG91 G83 Z-0.6 R-0.4 Q0.2\n",
        );
        assert!(d.is_empty(), "{d:?}");
        let m = moves(&p);
        assert_eq!(
            m[1..8],
            [
                t(None, 2.54),
                f(-2.54),
                t(None, -2.286),
                f(-7.62),
                t(None, -7.366),
                f(-12.7),
                t(None, 12.7)
            ]
        );
        // The G91 G83: R at 0.5 - 0.4 = Z0.1 in, Z-0.5 in; it keeps the initial level.
        assert_eq!(
            m[8..12],
            [t(None, 2.54), f(-2.54), t(None, 2.54), t(None, -2.286)]
        );
    }

    /// The tool left at R by a G99 block, in inches: rs274 holds Z0.68 as the double 0.68,
    /// while 0.68 × 25.4 / 25.4 is above it. The next block (G98) is then not above R, and
    /// its first hole is reached at the initial level, diagonally, as rs274 moves.
    #[test]
    fn the_tool_at_r_is_at_r_in_inches_too() {
        let (p, d) =
            read("G8 G17 G20 G90 G94 F100\nG0 X0 Z1.03\nG85 X1.86 R0.68 Z-0.21\nG98 X3.51\n");
        assert!(d.is_empty(), "{d:?}");
        let m = moves(&p);
        assert_eq!(m[m.len() - 5], ('T', Some(178.308), Some(26.162)));
        assert_eq!(m[m.len() - 4], ('T', None, Some(17.272)));
    }

    /// A G80 beside another motion code gives way to it (rs274's `read_g`).
    #[test]
    fn g80_gives_way_to_another_motion_code() {
        let (p, d) = read(&format!("{HEAD}G81 X0 R1 Z-10\nG0 G80 X4\nX6\n"));
        assert!(d.is_empty(), "{d:?}");
        let m = moves(&p);
        assert_eq!(
            m[m.len() - 2..],
            [('T', Some(4.0), None), ('T', Some(6.0), None)]
        );
    }

    /// `#<_motion_mode>`, `#<_retract_old_z>` and `#<_retract_r_plane>` follow the cycles.
    #[test]
    fn parameters_follow_the_cycle() {
        let (p, d) = read(&format!(
            "{HEAD}(debug,#<_retract_old_z> #<_retract_r_plane>)\nG98 G83 X0 R1 Z-10 Q4\n(debug,#<_motion_mode> #<_retract_old_z> #<_retract_r_plane>)\nG80\n(debug,#<_motion_mode>)\n"
        ));
        assert!(d.is_empty(), "{d:?}");
        let comments: Vec<&str> = p
            .items
            .iter()
            .filter_map(|i| match &i.kind {
                ItemKind::Comment(c) => Some(c.as_str()),
                _ => None,
            })
            .collect();
        assert_eq!(
            comments,
            [
                "debug,0.000000 1.000000",
                "debug,830.000000 1.000000 0.000000",
                "debug,800.000000"
            ]
        );
    }

    fn plan(code: GCode) -> Plan {
        Plan {
            code,
            current: 5.0,
            initial: 5.0,
            r: 1.0,
            bottom: -10.0,
            to_r_plane: true,
            q: 3.0,
            delta: RAPID_DELTA * 25.4,
            x: Some((0.0, 0.0)),
            repeats: 1,
        }
    }

    fn zs(e: &Expanded) -> Vec<(char, f64)> {
        e.steps
            .iter()
            .map(|s| match *s {
                Step::Rapid(_, z) => ('T', (z * 10_000.0).round() / 10_000.0),
                Step::Feed(_, z) => ('F', (z * 10_000.0).round() / 10_000.0),
                Step::Dwell => ('D', 0.0),
            })
            .collect()
    }

    /// rs274's canon for the research programs q3_g81, q3_g82_g85_g89, q3_g83, q3_g73.
    #[test]
    fn cycles_move_as_rs274_moves() {
        let t = 'T';
        let f = 'F';
        let g81 = expand(&plan(G81), MAX_STEPS).unwrap();
        assert_eq!(zs(&g81), [(t, 5.0), (t, 1.0), (f, -10.0), (t, 1.0)]);
        assert_eq!(g81.z, 1.0);
        let g98 = expand(
            &Plan {
                to_r_plane: false,
                ..plan(G81)
            },
            MAX_STEPS,
        )
        .unwrap();
        assert_eq!(zs(&g98).last(), Some(&(t, 5.0)));
        let g85 = expand(
            &Plan {
                to_r_plane: false,
                ..plan(G85)
            },
            MAX_STEPS,
        )
        .unwrap();
        assert_eq!(
            zs(&g85),
            [(t, 5.0), (t, 1.0), (f, -10.0), (f, 1.0), (t, 5.0)]
        );
        let g89 = expand(
            &Plan {
                to_r_plane: false,
                ..plan(G89)
            },
            MAX_STEPS,
        )
        .unwrap();
        assert_eq!(
            zs(&g89),
            [(t, 5.0), (t, 1.0), (f, -10.0), ('D', 0.0), (f, 5.0)]
        );
        let g83 = expand(
            &Plan {
                to_r_plane: false,
                ..plan(G83)
            },
            MAX_STEPS,
        )
        .unwrap();
        assert_eq!(
            zs(&g83),
            [
                (t, 5.0),
                (t, 1.0),
                (f, -2.0),
                (t, 1.0),
                (t, -1.746),
                (f, -5.0),
                (t, 1.0),
                (t, -4.746),
                (f, -8.0),
                (t, 1.0),
                (t, -7.746),
                (f, -10.0),
                (t, 5.0)
            ]
        );
        let g73 = expand(&plan(G73), MAX_STEPS).unwrap();
        assert_eq!(
            zs(&g73),
            [
                (t, 5.0),
                (t, 1.0),
                (f, -2.0),
                (t, -1.746),
                (f, -5.0),
                (t, -4.746),
                (f, -8.0),
                (t, -7.746),
                (f, -10.0),
                (t, 1.0)
            ]
        );
    }
}

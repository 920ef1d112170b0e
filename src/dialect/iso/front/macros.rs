//! Running LinuxCNC's macro language inside the front end: a line's values evaluated from
//! the parameters and the machine state the program has reached, its parameter settings,
//! and the O-word lines that move control (`interp_o_word.cc`, `interp_read.cc`,
//! `interp_namedparams.cc`).

use std::ops::Range;

use super::super::control::{self, FileRun, Flow, Frame, ModalState, Params, StructureError};
use super::super::expr::{self, Env, EvalError, Param};
use super::super::syntax::{Block, Keyword, OWord, Setting};
use super::{FrontEnd, Motion};
use crate::diag::Diagnostic;
use crate::dialect::iso::codes;
use crate::ir::{FeedMode, SpindleDirection};
use crate::source::Line;

/// The most loop iterations (back jumps of `endwhile`, `do … while`, `endrepeat` and
/// `continue`) ncthread follows in one program: an endless loop ends with an error well
/// within a second. **\[decided\]**
pub(super) const LOOP_LIMIT: u64 = 200_000;

/// LinuxCNC's deepest subroutine nesting below the main program (`INTERP_SUB_ROUTINE_LEVELS`
/// is 10 and counts the main program).
const MAX_CALL_DEPTH: usize = 9;

/// A computed value as a word's decimal: G codes within 0.0001 of a tenth and M, T, H, L
/// within 0.0001 of a whole number are that number, as LinuxCNC reads them.
fn word_value(letter: char, v: f64) -> Option<crate::fixed::Decimal> {
    let snapped = match letter {
        'G' if ((v * 10.0).round() - v * 10.0).abs() < 0.001 => (v * 10.0).round() / 10.0,
        'M' | 'T' | 'H' | 'L' if (v.round() - v).abs() < 0.0001 => v.round(),
        _ => v,
    };
    expr::to_decimal(snapped)
}

/// The parameter a setting sets, its number (`Ok`) or its name (`Err`): a numbered one
/// #1 … #5000, or a named one, which the setting creates for the rest of its line when it
/// is new (LinuxCNC creates it when it reads the setting's left side). A parameter of the
/// machine, or a read-only system parameter, is refused.
fn setting_target(scope: &Scope<'_>, s: &Setting) -> Result<Result<usize, String>, EvalError> {
    let params = scope.params;
    Ok(match &s.param {
        Param::Numbered(e) => {
            let n = expr::parameter_number(e.eval(scope)?, &s.range)?;
            if n > 5000 {
                return Err(EvalError {
                    message: format!(
                        "#{n} is a parameter of the machine, which ncthread does not follow"
                    ),
                    help: "the numbered parameters a program sets are #1 … #5000",
                    range: s.range.clone(),
                });
            }
            Ok(n)
        }
        Param::Named(name) => {
            if scope.system(name, &s.range).is_some() && params.named(name).is_none() {
                return Err(EvalError {
                    message: format!("Cannot assign to read-only parameter #<{name}>"),
                    help: "LinuxCNC's system parameters are read only",
                    range: s.range.clone(),
                });
            }
            if params.named(name).is_none() {
                scope.created.borrow_mut().push(name.clone());
            }
            Err(name.clone())
        }
    })
}

/// The lines LinuxCNC's `restore_settings` reads to bring `saved` back from `now`: the
/// units first (a line of their own), then one line of F (one decimal) and S (whole) where
/// they differ, the G codes that differ and the first M code that differs, then the other
/// M codes a line each.
fn gen_settings(saved: &ModalState, now: &ModalState) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    if saved.inch != now.inch {
        lines.push(if saved.inch { "G20" } else { "G21" }.into());
    }
    // Only what differs is said again (LinuxCNC's `gen_settings` compares the values as
    // held): an F the subroutine left alone is not rounded to one decimal.
    let mut text = String::new();
    if saved.feed != now.feed {
        text.push_str(&format!("F{:.1}", saved.feed));
    }
    if saved.speed != now.speed {
        text.push_str(&format!(" S{:.0}", saved.speed));
    }
    gen_g_codes(saved, now, &mut text);
    let mut m_codes = gen_m_codes(saved, now).into_iter();
    if let Some(first) = m_codes.next() {
        text.push(' ');
        text.push_str(&first);
    }
    if !text.trim().is_empty() {
        lines.push(text.trim_start().to_string());
    }
    lines.extend(m_codes);
    lines
}

/// LinuxCNC's `gen_g_codes`: the modal G codes of `saved` that differ from `now`, each
/// after a blank: distance, feed mode, spindle speed mode, arc centres, retract, plane,
/// diameter mode.
fn gen_g_codes(saved: &ModalState, now: &ModalState, text: &mut String) {
    let mut g = |differs: bool, code: &str| {
        if differs {
            text.push(' ');
            text.push_str(code);
        }
    };
    g(
        saved.incremental != now.incremental,
        if saved.incremental { "G91" } else { "G90" },
    );
    if let Some(mode) = saved.feed_mode {
        g(
            Some(mode) != now.feed_mode,
            if mode == 950 { "G95" } else { "G94" },
        );
    }
    g(
        saved.surface_speed != now.surface_speed,
        if saved.surface_speed { "G96" } else { "G97" },
    );
    g(
        saved.absolute_centres != now.absolute_centres,
        if saved.absolute_centres {
            "G90.1"
        } else {
            "G91.1"
        },
    );
    g(
        saved.retract_old_z != now.retract_old_z,
        if saved.retract_old_z { "G98" } else { "G99" },
    );
    g(
        saved.plane_xy != now.plane_xy,
        if saved.plane_xy { "G17" } else { "G18" },
    );
    if let Some(d) = saved.diameter {
        g(Some(d) != now.diameter, if d { "G7" } else { "G8" });
    }
}

/// LinuxCNC's `gen_m_codes`: the M codes of `saved` that differ from `now`: the spindle,
/// then the mist slot (M7, or M9 when no coolant was on; nothing when only flood was),
/// then the flood slot (M8 or nothing).
fn gen_m_codes(saved: &ModalState, now: &ModalState) -> Vec<String> {
    // The mist slot holds M7, or M9 when no coolant was on (nothing when only flood
    // was); the flood slot M8 or nothing.
    let slot = |s: &ModalState| match (s.mist, s.flood) {
        (true, _) => Some("M7"),
        (false, false) => Some("M9"),
        (false, true) => None,
    };
    let mut m_codes: Vec<String> = Vec::new();
    if saved.spindle != now.spindle {
        m_codes.push(format!("M{}", saved.spindle));
    }
    if let Some(m) = slot(saved)
        && slot(saved) != slot(now)
    {
        m_codes.push(m.into());
    }
    if saved.flood && !now.flood {
        m_codes.push("M8".into());
    }
    m_codes
}

/// Where control goes after an O-word line.
pub(super) enum Jump {
    Next,
    /// To a line of this file.
    Here(usize),
    /// To a line of a file (a call, a return).
    To(usize, usize),
    /// Back to the start of a loop (counted against [`LOOP_LIMIT`]).
    Loop(usize),
}

/// An O-word line being run: where it stands (line `at` of file `file`) and what it says.
struct OLine<'a, 'r> {
    at: usize,
    file: usize,
    o: &'a OWord,
    runs: &'a [FileRun<'r>],
}

impl OLine<'_, '_> {
    fn error(&self, range: Range<usize>, message: String, help: &'static str) -> StructureError {
        StructureError {
            line: self.at,
            range,
            message,
            help,
        }
    }

    /// Skips on to the next line of this label (LinuxCNC's `skipping_o`).
    fn skip(&self, params: &mut Params) -> Result<Jump, StructureError> {
        match self.runs[self.file].structure.next_same.get(&self.at) {
            Some(&next) => {
                params.skipping = true;
                Ok(Jump::Here(next))
            }
            None => Err(self.error(
                self.o.range.clone(),
                format!(
                    "File ended with no percent sign or program end: LinuxCNC skips from {} {} to the next line of {0}, and there is none",
                    self.o.label,
                    self.o.keyword.name()
                ),
                "close the loop with its end of the same label",
            )),
        }
    }

    /// What follows the keyword and its arguments: LinuxCNC's `read_items` allows comments
    /// only, on a line it reads while not skipping (a `sub` takes no argument, an `if` one,
    /// a `call` up to 30). **\[evidence\]** LinuxCNC `interp_read.cc`, `read_items` and
    /// `read_o`.
    fn tail(&self) -> Result<(), StructureError> {
        let most = match self.o.keyword {
            Keyword::Call => return Ok(()),
            Keyword::EndSub
            | Keyword::Return
            | Keyword::If
            | Keyword::ElseIf
            | Keyword::While
            | Keyword::Repeat => 1,
            Keyword::Sub
            | Keyword::Do
            | Keyword::Else
            | Keyword::EndIf
            | Keyword::Break
            | Keyword::Continue
            | Keyword::EndWhile
            | Keyword::EndRepeat => 0,
        };
        let Some(extra) = self.o.args.get(most) else {
            return Ok(());
        };
        // The argument with its brackets.
        let text = self.runs[self.file]
            .get_line(self.at)
            .map_or("", |l| l.text);
        let (start, end) = (extra.range.start, extra.range.end);
        let start = text
            .get(..start)
            .and_then(|t| t.rfind('['))
            .unwrap_or(start);
        let end = text
            .get(end..)
            .and_then(|t| t.find(']'))
            .map_or(end, |i| end + i + 1);
        let (range, written) = match text.get(start..end) {
            Some(w) => (start..end, w),
            None => (extra.range.clone(), "[…]"),
        };
        Err(self.error(
            range,
                format!(
                    "`{written}` after {} {}: LinuxCNC allows only a comment there (\"Unexpected character after O-word\")",
                    self.o.label,
                    self.o.keyword.name()
                ),
                match most {
                    0 => "this O-word takes no value: remove the bracket (a subroutine's arguments go on its `call`)",
                    _ => "this O-word takes one value in brackets: remove the others",
                },
        ))
    }

    /// A `break` or `continue` of a `repeat` (the loop starting at line `start`), which
    /// LinuxCNC refuses when it reaches it.
    fn not_a_loop(&self, start: usize) -> StructureError {
        let line = self.runs[self.file].line(start).number;
        self.error(
            self.o.range.clone(),
            format!(
                "no matching while/do label: '{} {}' (found 'repeat' in line {line}): LinuxCNC has no `{1}` for a `repeat`",
                self.o.label,
                self.o.keyword.name()
            ),
            "leave a `repeat` by a `while` loop with the count in a parameter, or by an `if` around its body",
        )
    }

    /// The checks of a line reached: what follows its words, and its label's place.
    /// Whether it was reached by skipping to its label (LinuxCNC's `skipping_o`).
    fn enter(&self, flow: Option<&Flow>, params: &mut Params) -> Result<bool, StructureError> {
        let skipped = std::mem::take(&mut params.skipping);
        if !skipped && params.testing != Some(self.at) {
            self.tail()?;
        }
        self.opened(flow, params)?;
        Ok(skipped)
    }

    /// An `if`, `do`, `repeat` or opening `while` reached (`flow` says whether a `while`
    /// opens a loop): its label takes this place in
    /// the subroutine running (or the program) for the rest of the run, as in LinuxCNC's
    /// `offset_map`. A label that already has another place there is refused: LinuxCNC
    /// stops at an `if`, `while` or `repeat` ("duplicate O-word label"), and sends the
    /// `while` of a `do` back to the earlier place.
    fn opened(&self, flow: Option<&Flow>, params: &mut Params) -> Result<(), StructureError> {
        let opens = matches!(
            (self.o.keyword, flow),
            (Keyword::If | Keyword::Do | Keyword::Repeat, _)
                | (Keyword::While, Some(Flow::While { .. }))
        );
        if !opens {
            return Ok(());
        }
        let scope = params.frames.last().map(|f| f.name.clone());
        let here = (self.file, self.at);
        let place = *params
            .opened
            .entry((scope, self.o.label.clone()))
            .or_insert(here);
        if place == here {
            return Ok(());
        }
        let line = self.runs[place.0].get_line(place.1).map_or(0, |l| l.number);
        Err(self.error(
            self.o.range.clone(),
            format!(
                "duplicate O-word label - already defined in line {line}: LinuxCNC keeps one place per label in a subroutine (or the program), and {} {} is a second",
                self.o.label,
                self.o.keyword.name()
            ),
            "give each `if`, `do`, `while` and `repeat` of a subroutine (or of the program) a label of its own",
        ))
    }

    /// `sub` (LinuxCNC's `O_sub`): a definition is passed once; reaching it again (a
    /// loop, or after a call that found it further down) is LinuxCNC's "found in illegal
    /// location".
    fn o_sub(&self, end: usize, params: &mut Params) -> Result<Jump, StructureError> {
        if !params.passed.insert((self.file, self.at)) {
            return Err(self.error(
                self.o.range.clone(),
                format!(
                    "sub: {} found in illegal location (a definition reached again, or after it was called)",
                    self.o.label
                ),
                "define subroutines before the program calls them, outside loops",
            ));
        }
        Ok(Jump::Here(end + 1))
    }
}

/// A definition of the called subroutine that LinuxCNC does not find (`found`: its file and
/// line): after the program's closing `%`, where the file ends; or earlier in the calling
/// file where the run never passed (inside an `if` not taken), as LinuxCNC knows the
/// definitions it has passed and seeks any other from the call on.
fn unreachable_definition(
    l: &OLine<'_, '_>,
    params: &Params,
    found: Option<(usize, usize)>,
) -> Option<StructureError> {
    let (o, runs, file) = (l.o, l.runs, l.file);
    let (k, start) = found?;
    let (why, help) = if runs[k].closing_percent().is_some_and(|c| start > c) {
        // A definition after the program's closing `%` is never read: the file ends there.
        (
            "after the program's closing `%`, where LinuxCNC's file ends",
            "define the subroutine before the closing `%`",
        )
    } else if k == file && start < l.at && !params.passed.contains(&(k, start)) {
        // LinuxCNC knows a definition it has passed; any other it seeks from the call on,
        // so that one earlier in the file that the run skipped is not found.
        (
            "before this call where the run never passed it (an `if` or a loop skipped it): LinuxCNC seeks it from the call on",
            "define the subroutine at the program's top level, before the program calls it",
        )
    } else {
        return None;
    };
    Some(l.error(
        o.range.clone(),
        format!(
            "{} is defined {why} (\"Failed to find sub '{}' before EOF\")",
            o.label,
            o.label.to_string().to_uppercase()
        ),
        help,
    ))
}

/// `endwhile` and `endrepeat` (LinuxCNC's `O_endwhile`/`O_endrepeat`): reached by
/// skipping, the loop ends, unless a `continue` is pending (then the loop goes round, and
/// the flag is cleared); reached in sequence, back to the loop's first line.
fn o_endwhile(params: &mut Params, skipped: bool, start: usize) -> Jump {
    if skipped && !std::mem::take(&mut params.doing_continue) {
        Jump::Next
    } else {
        Jump::Loop(start)
    }
}

/// The machine state a line's expressions may read, as LinuxCNC's system parameters
/// give it: lengths in the program's units, X a radius (LinuxCNC keeps radii inside).
struct System {
    plane_xy: bool,
    /// G98 in force (G99 is LinuxCNC's start-up mode).
    retract_old_z: bool,
    x: Option<f64>,
    z: Option<f64>,
    inch: bool,
    incremental: bool,
    feed: Option<f64>,
    /// The feed rate was given in the other units, before a G20/G21: LinuxCNC's task and its
    /// standalone interpreter give different numbers for it.
    feed_in_other_units: bool,
    rpm: Option<f64>,
    tool: f64,
    motion: Option<f64>,
    spindle: Option<SpindleDirection>,
    diameter: bool,
    per_rev: bool,
    work_offset: u8,
    /// 400, 410 or 420 (G40, G41, G42).
    ccomp: f64,
    absolute_centres: bool,
    surface_speed: bool,
    mist: bool,
    flood: bool,
    /// The program has set the G52/G92 offset (#5210–#5219 are then its values).
    offsets_set: bool,
}

struct Scope<'p> {
    params: &'p Params,
    system: System,
    /// Named parameters a setting earlier on the line creates: they exist (as 0) for the
    /// rest of the line, as LinuxCNC creates them when it reads the setting's left side.
    created: std::cell::RefCell<Vec<String>>,
}

fn unknown(what: &str, range: &Range<usize>) -> EvalError {
    EvalError {
        message: format!("{what} is not known here"),
        help: "LinuxCNC gives the machine's value, which ncthread cannot know: program an absolute position (or the value) before reading it",
        range: range.clone(),
    }
}

impl Scope<'_> {
    fn system(&self, name: &str, range: &Range<usize>) -> Option<Result<f64, EvalError>> {
        let s = &self.system;
        let flag = |b: bool| Ok(f64::from(u8::from(b)));
        Some(match name {
            "_x" => s.x.ok_or_else(|| unknown("the X position", range)),
            "_z" => s.z.ok_or_else(|| unknown("the Z position", range)),
            "_y" | "_a" | "_b" | "_c" | "_u" | "_v" | "_w" => Ok(0.0),
            "_metric" => flag(!s.inch),
            "_imperial" => flag(s.inch),
            "_absolute" => flag(!s.incremental),
            "_incremental" => flag(s.incremental),
            "_feed" if s.feed_in_other_units => Err(EvalError {
                message: "the feed rate (F) given before the G20/G21 that changed the units is not known here: LinuxCNC's standalone interpreter gives its number, a LinuxCNC machine feeding per minute its speed in the new units".into(),
                help: "give F again after the G20/G21",
                range: range.clone(),
            }),
            "_feed" => Ok(s.feed.unwrap_or(0.0)),
            "_rpm" => Ok(s.rpm.unwrap_or(0.0)),
            "_current_tool" => Ok(s.tool),
            "_motion_mode" => s.motion.ok_or_else(|| unknown("the motion mode", range)),
            "_plane" => Ok(if s.plane_xy { 170.0 } else { 180.0 }),
            // The LinuxCNC ncthread follows (and checks with): 2.9.0.
            "_vmajor" => Ok(2.9),
            "_vminor" => Ok(0.0),
            // 1 under G98 and G99 respectively (LinuxCNC's comments swap them; its values
            // do not). **[evidence]** `interp_namedparams.cc`, NP_RETRACT_OLD_Z/R_PLANE.
            "_retract_old_z" => flag(s.retract_old_z),
            "_retract_r_plane" => flag(!s.retract_old_z),
            "_coord_system" => Ok(match self.system.work_offset {
                n @ 1..=6 => 530.0 + 10.0 * f64::from(n),
                n => 584.0 + f64::from(n),
            }),
            "_ccomp" => Ok(self.system.ccomp),
            "_ijk_absolute_mode" => flag(s.absolute_centres),
            "_spindle_css_mode" => flag(s.surface_speed),
            "_spindle_rpm_mode" => flag(!s.surface_speed),
            "_mist" => flag(s.mist),
            "_flood" => flag(s.flood),
            "_call_level" => Ok(self.params.frames.len() as f64),
            "_lathe_diameter_mode" => flag(s.diameter),
            "_lathe_radius_mode" => flag(!s.diameter),
            "_spindle_on" => flag(s.spindle.is_some()),
            "_spindle_cw" => flag(s.spindle == Some(SpindleDirection::Clockwise)),
            "_units_per_rev" => flag(s.per_rev),
            "_units_per_minute" => flag(!s.per_rev),
            "_selected_tool" => Ok(s.tool),
            "_tool_offset" | "_current_pocket" | "_selected_pocket" | "_abs_x" | "_abs_z"
            | "_metric_machine" | "_task" | "_remap_level" | "_line" => Err(EvalError {
                message: format!(
                    "#<{name}> holds a value of the machine or of its interpreter (tool table, offsets, configuration) that ncthread does not know"
                ),
                help: "compute the value in the program instead of reading it from the machine",
                range: range.clone(),
            }),
            "_value" => Ok(self.params.value),
            "_value_returned" => flag(self.params.value_returned),
            _ => return None,
        })
    }
}

impl Env for Scope<'_> {
    fn numbered(&self, n: usize, range: &Range<usize>) -> Result<f64, EvalError> {
        let s = &self.system;
        match n {
            1..=5000 => Ok(self.params.numbered[n]),
            5400 => Ok(s.tool),
            // Whether a G52/G92 offset is applied; the offsets themselves (#5211–#5219) are
            // kept in the machine's own units, which the program does not say.
            5210 if s.offsets_set => Ok(self.params.numbered[n]),
            5420 => s.x.ok_or_else(|| unknown("the X position (#5420)", range)),
            5421 | 5423..=5428 => Ok(0.0),
            5422 => s.z.ok_or_else(|| unknown("the Z position (#5422)", range)),
            _ => Err(EvalError {
                message: format!(
                    "#{n} holds a value of the machine (an offset, a stored position, a tool table entry) that ncthread does not know"
                ),
                help: "compute the value in the program instead of reading it from the machine",
                range: range.clone(),
            }),
        }
    }

    fn named(&self, name: &str, range: &Range<usize>) -> Result<f64, EvalError> {
        if let Some(v) = self.params.named(name) {
            return Ok(v);
        }
        if self.created.borrow().iter().any(|c| c == name) {
            return Ok(0.0);
        }
        if let Some(v) = self.system(name, range) {
            return v;
        }
        Err(EvalError {
            message: format!("Named parameter #<{name}> not defined"),
            help: "set it before it is read (`#<name> = …`); a subroutine's named parameters are its own",
            range: range.clone(),
        })
    }

    fn exists(&self, name: &str) -> bool {
        self.params.named(name).is_some()
            || self.created.borrow().iter().any(|c| c == name)
            || self.system(name, &(0..0)).is_some()
    }
}

impl FrontEnd<'_> {
    fn scope<'p>(&self, params: &'p Params) -> Scope<'p> {
        let unit = if self.inch { 25.4 } else { 1.0 };
        let (x, z) = self.exact_start();
        // In the program's coordinates: less the G52/G92 offset.
        let (dx, dz) = self.axis_offset;
        let (x, z) = match self.contour.as_deref() {
            // Inside a G7x contour: the contour's current point.
            Some(c) => {
                let (x, z) = c.current(self.axis_offset);
                (Some(x), Some(z))
            }
            None => (x.map(|x| (x - dx) / 2.0 / unit), z.map(|z| (z - dz) / unit)),
        };
        Scope {
            params,
            system: System {
                plane_xy: self.plane_xy,
                retract_old_z: self.retract_old_z,
                x,
                z,
                inch: self.inch,
                incremental: self.incremental,
                feed: self.feed.map(|f| f.to_mm_f64() / unit),
                feed_in_other_units: self.feed.is_some() && self.feed_inch != self.inch,
                rpm: self.speed.map(f64::from),
                tool: self.selected_tool.map_or(0.0, f64::from),
                motion: self.motion.map(|m| match m {
                    Motion::Rapid => 0.0,
                    Motion::Feed => 10.0,
                    Motion::Arc { clockwise: true } => 20.0,
                    Motion::Arc { clockwise: false } => 30.0,
                    Motion::Thread => 330.0,
                    Motion::Tap => 331.0,
                    Motion::Cycle => 760.0,
                    Motion::Roughing(code) | Motion::Drill(code) => code as f64,
                    Motion::CycleOff => 800.0,
                }),
                spindle: self.turning,
                diameter: self.diameter == Some(true),
                per_rev: self.feed_mode == Some(FeedMode::PerRev),
                work_offset: self.work_offset,
                offsets_set: self.offsets_set,
                ccomp: if self.compensation { self.ccomp } else { 400.0 },
                absolute_centres: self.absolute_centres,
                surface_speed: self.surface_speed,
                mist: self.mist,
                flood: self.flood,
            },
            created: Default::default(),
        }
    }

    fn eval(&self, e: &expr::Expr, params: &Params) -> Result<f64, EvalError> {
        e.eval(&self.scope(params))
    }

    /// Evaluates the line's computed values (into their words) and makes its parameter
    /// settings: every value is read before any setting takes effect, as in LinuxCNC.
    pub(super) fn evaluate(
        &self,
        block: &Block,
        words: &mut [super::Word],
        params: &mut Params,
    ) -> Result<(), EvalError> {
        let scope = self.scope(params);
        // Left to right, as LinuxCNC reads the line: words' values and settings.
        enum Part {
            Word(usize),
            Setting(usize),
        }
        let mut parts: Vec<(usize, Part)> = block
            .words
            .iter()
            .enumerate()
            .filter(|(_, w)| w.expr.is_some())
            .map(|(i, w)| (w.range.start, Part::Word(i)))
            .chain(
                block
                    .settings
                    .iter()
                    .enumerate()
                    .map(|(i, s)| (s.range.start, Part::Setting(i))),
            )
            .collect();
        parts.sort_by_key(|(at, _)| *at);
        let mut settings = Vec::with_capacity(block.settings.len());
        for (_, part) in parts {
            match part {
                Part::Word(i) => {
                    let w = &block.words[i];
                    let e = &block.exprs[w.expr.expect("a computed word")];
                    let v = e.eval(&scope)?;
                    let value = word_value(w.letter, v).ok_or_else(|| EvalError {
                        message: format!("the value {v} is too large for a word"),
                        help: "check the expression",
                        range: w.range.clone(),
                    })?;
                    words[i].value = value;
                }
                Part::Setting(i) => {
                    let s = &block.settings[i];
                    let target = setting_target(&scope, s)?;
                    settings.push((target, s.value.eval(&scope)?));
                }
            }
        }
        drop(scope);
        for (target, v) in settings {
            match target {
                Ok(n) => params.numbered[n] = v,
                Err(name) if name.starts_with('_') => {
                    params.globals.insert(name, v);
                }
                Err(name) => {
                    params.locals_mut().insert(name, v);
                }
            }
        }
        Ok(())
    }

    /// A `(debug,…)` or `(print,…)` comment with its parameters' values put in, as
    /// LinuxCNC prints it (`%lf`; `######` for a parameter that has none), so that the
    /// unrolled program says what the macro said. Other comments as they are.
    pub(super) fn message(&self, text: &str, params: &Params) -> Option<String> {
        let tagged = text.get(..6).is_some_and(|tag| {
            tag.eq_ignore_ascii_case("debug,") || tag.eq_ignore_ascii_case("print,")
        });
        if !tagged || !text.contains('#') {
            return None;
        }
        let scope = self.scope(params);
        let mut out = String::with_capacity(text.len());
        let mut rest = text;
        while let Some(at) = rest.find('#') {
            out.push_str(&rest[..at]);
            let after = &rest[at + 1..];
            let (value, used) = if let Some(name) = after.strip_prefix('<') {
                match name.find('>') {
                    Some(end) => {
                        let key: String = name[..end]
                            .chars()
                            .filter(|c| !c.is_whitespace())
                            .flat_map(char::to_lowercase)
                            .collect();
                        (scope.named(&key, &(0..0)).ok(), end + 2)
                    }
                    None => (None, 0),
                }
            } else {
                let digits = after.bytes().take_while(u8::is_ascii_digit).count();
                let n = after[..digits].parse::<usize>().ok();
                (
                    n.and_then(|n| expr::parameter_number(n as f64, &(0..0)).ok())
                        .and_then(|n| scope.numbered(n, &(0..0)).ok()),
                    digits,
                )
            };
            if used == 0 {
                out.push('#');
                rest = after;
                continue;
            }
            match value {
                Some(v) => out.push_str(&format!("{v:.6}")),
                None => out.push_str("######"),
            }
            rest = &after[used..];
        }
        out.push_str(rest);
        Some(out)
    }

    fn modal(&self) -> ModalState {
        let unit = if self.inch { 25.4 } else { 1.0 };
        ModalState {
            inch: self.inch,
            incremental: self.incremental,
            feed_mode: self.feed_mode.map(|m| match m {
                FeedMode::PerMin => 940,
                FeedMode::PerRev => 950,
            }),
            surface_speed: self.surface_speed,
            absolute_centres: self.absolute_centres,
            diameter: self.diameter,
            spindle: match self.turning {
                Some(SpindleDirection::Clockwise) => 3,
                Some(SpindleDirection::CounterClockwise) => 4,
                None => 5,
            },
            mist: self.mist,
            flood: self.flood,
            feed: self.feed.map_or(0.0, |f| f.to_mm_f64() / unit),
            speed: self.speed.map_or(0.0, f64::from),
            work_offset: self.work_offset,
            compensation: self.compensation,
            retract_old_z: self.retract_old_z,
            plane_xy: self.plane_xy,
        }
    }

    /// M70 (save the modal state), M71 (forget it), M72 (restore it), M73 (save it, and
    /// restore it when the subroutine returns) on a line of their own: true when the line
    /// was one.
    pub(super) fn modal_state(
        &mut self,
        line: Line<'_>,
        block: &Block,
        params: &mut Params,
    ) -> bool {
        let code = |w: &super::Word| w.value.to_whole().ok().filter(|m| (70..=73).contains(m));
        let Some((m, word)) = block
            .words
            .iter()
            .find_map(|w| (w.letter == 'M').then(|| code(w)).flatten().map(|m| (m, w)))
        else {
            return false;
        };
        if block.words.len() > 1 {
            self.diag(
                codes::ISOR_UNSUPPORTED,
                line,
                word.range.clone(),
                format!("M{m} with other words on its line, whose order against it ncthread does not follow"),
                "write M70–M73 on a line of their own",
            );
            return true;
        }
        let level = params.frames.len();
        match m {
            70 | 73 => {
                params
                    .contexts
                    .insert(level, (self.modal(), m == 73 && level > 0));
            }
            71 => {
                params.contexts.remove(&level);
            }
            _ => match params.contexts.get(&level).map(|(s, _)| s.clone()) {
                Some(saved) => self.restore(line, word.range.clone(), &saved),
                None => {
                    self.diag(
                        codes::ISOR_CONTROL,
                        line,
                        word.range.clone(),
                        "Cannot restore context from invalid stack frame - missing M70/M73?".into(),
                        "save the modal state with M70 (or M73) at this call level before M72",
                    );
                    self.stopped = true;
                }
            },
        }
        true
    }

    /// Restores `saved` as LinuxCNC's `restore_settings` does: the units first, then one line
    /// of F (one decimal) and S (whole) where they differ, the G codes that differ and the first M code that
    /// differs, then the other M codes a line each, read here as if the program held them.
    /// The motion mode is not restored (LinuxCNC does not), nor G64's tolerances (a path
    /// setting ncthread keeps as written).
    pub(super) fn restore(&mut self, line: Line<'_>, range: Range<usize>, saved: &ModalState) {
        let now = self.modal();
        if saved.work_offset != now.work_offset || saved.compensation != now.compensation {
            self.diag(
                codes::ISOR_UNSUPPORTED,
                line,
                range,
                "restoring a saved work offset or cutter compensation (M72/M73), which ncthread does not follow".into(),
                "restore them in the program with G54…G59.3 and G40/G41/G42",
            );
            return;
        }
        let lines = gen_settings(saved, &now);
        let first_item = self.r.items.len();
        for text in &lines {
            let synthetic = Line {
                number: line.number,
                offset: line.offset,
                text,
            };
            // ncthread's own words: they always read.
            if let Ok(block) = super::syntax::parse_line(text) {
                self.block(synthetic, &block);
            }
        }
        // The restored state stands at the M72 (or the return) in the program.
        let span = self.r.src.line_span(line);
        for item in &mut self.r.items[first_item..] {
            item.span = span;
        }
    }

    /// Runs an O-word line at `at`: where control goes next (LinuxCNC's
    /// `convert_control_functions`, one step per keyword).
    pub(super) fn oword(
        &mut self,
        at: usize,
        file: usize,
        o: &OWord,
        runs: &[FileRun<'_>],
        params: &mut Params,
    ) -> Result<Jump, StructureError> {
        let l = OLine { at, file, o, runs };
        let flow = runs[file].structure.flow.get(&at);
        let skipped = l.enter(flow, params)?;
        match (o.keyword, flow) {
            (Keyword::Sub, Some(Flow::Sub { end })) => l.o_sub(*end, params),
            (Keyword::EndSub | Keyword::Return, _) => self.o_endsub(&l, params),
            (Keyword::Call, _) => self.o_call(&l, params),
            (Keyword::If, Some(Flow::If { branches, end })) => {
                self.o_if(&l, params, branches.first().copied(), *end)
            }
            (Keyword::ElseIf | Keyword::Else, Some(Flow::Branch { next, end })) => {
                self.o_else(&l, params, *next, *end)
            }
            (Keyword::EndIf, _) => Ok(Jump::Next),
            (Keyword::While, Some(Flow::While { .. })) => {
                if self.o_condition(&l, params)? {
                    Ok(Jump::Next)
                } else {
                    l.skip(params)
                }
            }
            (
                Keyword::EndWhile | Keyword::EndRepeat,
                Some(Flow::EndWhile { start } | Flow::EndRepeat { start }),
            ) => Ok(o_endwhile(params, skipped, *start)),
            (Keyword::Do, _) => Ok(Jump::Next),
            (Keyword::While, Some(Flow::DoWhile { start })) => {
                if self.o_condition(&l, params)? && !params.doing_break {
                    Ok(Jump::Loop(start + 1))
                } else {
                    params.doing_break = false;
                    Ok(Jump::Next)
                }
            }
            (Keyword::Repeat, Some(Flow::Repeat { .. })) => self.o_repeat(&l, params),
            (
                Keyword::Break | Keyword::Continue,
                Some(
                    Flow::Break {
                        start,
                        repeat: true,
                        ..
                    }
                    | Flow::Continue {
                        start,
                        repeat: true,
                        ..
                    },
                ),
            ) => Err(l.not_a_loop(*start)),
            (Keyword::Break, Some(Flow::Break { .. })) => {
                params.doing_break = true;
                l.skip(params)
            }
            // Already skipping to this label, a `continue` does nothing.
            (Keyword::Continue, Some(Flow::Continue { .. })) => {
                if !skipped {
                    params.doing_continue = true;
                }
                l.skip(params)
            }
            _ => Err(l.error(
                o.range.clone(),
                format!("{} {} out of place", o.label, o.keyword.name()),
                "check the program's O-word blocks",
            )),
        }
    }

    /// The O-word's `i`th argument evaluated, if it has one.
    fn o_arg(
        &self,
        l: &OLine<'_, '_>,
        params: &Params,
        i: usize,
    ) -> Result<Option<f64>, StructureError> {
        match l.o.args.get(i) {
            Some(e) => self
                .eval(e, params)
                .map(Some)
                .map_err(|e| control::eval_error(l.at, e)),
            None => Ok(None),
        }
    }

    /// The condition of an `if`, `elseif` or `while`: its first argument, not 0.
    fn o_condition(&self, l: &OLine<'_, '_>, params: &Params) -> Result<bool, StructureError> {
        match self.o_arg(l, params, 0)? {
            Some(v) => Ok(v != 0.0),
            None => Err(l.error(
                l.o.range.clone(),
                format!("{} {} without its condition", l.o.label, l.o.keyword.name()),
                "write the condition in brackets: `o100 while [#1 LT 5]`",
            )),
        }
    }

    /// `endsub` and `return` (LinuxCNC's `O_endsub`/`O_return`): the caller's #1 … #30
    /// back, the state an M73 saved restored, the value returned (`#<_value>`), and
    /// control back after the call.
    fn o_endsub(&mut self, l: &OLine<'_, '_>, params: &mut Params) -> Result<Jump, StructureError> {
        let o = l.o;
        let value = self.o_arg(l, params, 0)?;
        let level = params.frames.len();
        let Some(frame) = params.frames.pop() else {
            return Err(l.error(
                o.range.clone(),
                format!("{} {} outside a call of it", o.label, o.keyword.name()),
                "a subroutine runs only when it is called",
            ));
        };
        params.numbered[1..=30].copy_from_slice(&frame.saved);
        // M73 in the subroutine: its saved state comes back with the return.
        if let Some((saved, true)) = params.contexts.remove(&level) {
            let line = l.runs[l.file].line(l.at);
            self.restore(line, o.range.clone(), &saved);
        }
        params.contexts.remove(&level);
        match value {
            Some(v) => {
                params.value = v;
                params.value_returned = true;
            }
            None => params.value_returned = false,
        }
        Ok(Jump::To(frame.file, frame.call_line + 1))
    }

    /// `call` (LinuxCNC's `O_call`): the subroutine found (this file's definition, else the
    /// program's, else a subroutine file's), the nesting limit, its arguments into #1 …
    /// #30 (the caller's saved), a new frame, and control to the definition's first line.
    fn o_call(&mut self, l: &OLine<'_, '_>, params: &mut Params) -> Result<Jump, StructureError> {
        let (o, runs, file) = (l.o, l.runs, l.file);
        let found = std::iter::once(file)
            .chain(0..runs.len())
            .find_map(|k| runs[k].structure.subs.get(&o.label).map(|&l| (k, l)));
        if let Some(e) = unreachable_definition(l, params, found) {
            return Err(e);
        }
        let Some((sub_file, start)) = found else {
            return Err(l.error(
                o.range.clone(),
                format!("Unable to open file or find subroutine {}", o.label),
                "define the subroutine in the program (`o<name> sub` … `o<name> endsub`), or give the folder of name.ngc with --subroutine-path",
            ));
        };
        if params.frames.len() >= MAX_CALL_DEPTH {
            return Err(l.error(
                o.range.clone(),
                format!(
                    "Too many nested levels of subroutines: {} would be call {} deep, LinuxCNC's limit is {MAX_CALL_DEPTH}",
                    o.label,
                    params.frames.len() + 1
                ),
                "a subroutine that calls itself needs a condition that ends the recursion",
            ));
        }
        let mut args = [0.0; 30];
        for (i, slot) in args.iter_mut().enumerate() {
            if let Some(v) = self.o_arg(l, params, i)? {
                *slot = v;
            }
        }
        if o.args.len() > 30 {
            return Err(l.error(
                o.args[30].range.clone(),
                format!("{} call with more than 30 arguments", o.label),
                "a subroutine takes at most 30 arguments (#1 … #30)",
            ));
        }
        let mut saved = [0.0; 30];
        saved.copy_from_slice(&params.numbered[1..=30]);
        params.numbered[1..=30].copy_from_slice(&args);
        params.passed.insert((sub_file, start));
        // A call starts its level with no saved state.
        params.contexts.remove(&(params.frames.len() + 1));
        params.frames.push(Frame {
            name: o.label.clone(),
            file,
            call_line: l.at,
            sub_file,
            saved,
            locals: Default::default(),
        });
        Ok(Jump::To(sub_file, start + 1))
    }

    /// `if` (LinuxCNC's `O_if`): on when its condition holds, else to its first `elseif`
    /// or `else` (which then tests), else past its `endif`.
    fn o_if(
        &self,
        l: &OLine<'_, '_>,
        params: &mut Params,
        first_branch: Option<usize>,
        end: usize,
    ) -> Result<Jump, StructureError> {
        Ok(if self.o_condition(l, params)? {
            Jump::Next
        } else if let Some(b) = first_branch {
            params.testing = Some(b);
            Jump::Here(b)
        } else {
            Jump::Here(end + 1)
        })
    }

    /// `elseif` and `else` (LinuxCNC's `O_elseif`/`O_else`): reached from a failed test, an
    /// `elseif` tests and an `else` runs; reached after a branch ran, past the `endif`.
    fn o_else(
        &self,
        l: &OLine<'_, '_>,
        params: &mut Params,
        next: Option<usize>,
        end: usize,
    ) -> Result<Jump, StructureError> {
        let o = l.o;
        Ok(if params.testing == Some(l.at) {
            params.testing = None;
            if o.keyword == Keyword::Else || self.o_condition(l, params)? {
                Jump::Next
            } else if let Some(b) = next {
                params.testing = Some(b);
                Jump::Here(b)
            } else {
                Jump::Here(end + 1)
            }
        } else {
            // After a branch ran, LinuxCNC still reads an `elseif`'s condition (its
            // errors stand), then goes past the `endif`.
            if o.keyword == Keyword::ElseIf {
                self.o_condition(l, params)?;
            }
            Jump::Here(end + 1)
        })
    }

    /// `repeat` (LinuxCNC's `O_repeat`): the count is taken when the loop starts (and
    /// again once it has run out), and counted down at its first line, as LinuxCNC's
    /// `repeat_count`; when it has run out, on to the `endrepeat`.
    fn o_repeat(&self, l: &OLine<'_, '_>, params: &mut Params) -> Result<Jump, StructureError> {
        let (o, file, at) = (l.o, l.file, l.at);
        let count = self.o_arg(l, params, 0)?.ok_or_else(|| {
            l.error(
                o.range.clone(),
                format!("{} repeat without its count", o.label),
                "write the count in brackets: `o100 repeat [3]`",
            )
        })?;
        let left = match params.repeats.get(&(file, at)) {
            Some(&left) => left,
            None => count.round() as i64,
        };
        if left > 0 {
            params.repeats.insert((file, at), left - 1);
            Ok(Jump::Next)
        } else {
            params.repeats.remove(&(file, at));
            l.skip(params)
        }
    }

    /// Names the call chain in the diagnostics made since `from` while a subroutine runs.
    pub(super) fn name_call_chain(&mut self, from: usize, params: &Params, runs: &[FileRun<'_>]) {
        let Some(chain) = params.chain(|file, line| {
            let number = runs[file].line(line).number;
            if file == 0 {
                format!("line {number}")
            } else {
                format!("{} line {number}", runs[file].src.name)
            }
        }) else {
            return;
        };
        for d in &mut self.r.diags[from..] {
            if !d.message.contains(" called from line ") {
                let message = format!("{} ({chain})", d.message);
                *d = Diagnostic {
                    message,
                    ..d.clone()
                };
            }
        }
    }
}

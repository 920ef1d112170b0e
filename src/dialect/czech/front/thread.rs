//! The G33 thread pass: its lead, start angle and travel, and the entry (E) and runout (J)
//! chamfers whose angle machine constant 8 selects.

use std::ops::Range;

use super::{AfterRunout, FRegister, FrontEnd, Words, code_span_range};
use crate::dialect::czech::codes;
use crate::dialect::czech::profile::AngleSource;
use crate::dialect::czech::syntax::{Value, Word};
use crate::fixed::{Angle, Lead, Length};
use crate::ir::{Chamfer, Pos, SyncStart, ThreadPass};
use crate::source::{Line, Span};

/// The largest lead `F` may give directly. **\[seed\]** 99.99 mm.
const MAX_DIRECT_LEAD: Length = Length::from_steps(999_900);
/// The largest runout/entry angle. **\[seed\]** 60°.
const MAX_ANGLE: Angle = Angle(60_000);

impl<'a> FrontEnd<'a> {
    /// A G33 block's pass from `start` to `to`: its lead, start angle (I), travel, entry (E)
    /// and runout (J), in that order; `None` after reporting why there is none. A pass with
    /// entry or runout asks for an empty block and an all-axes block after it.
    pub(super) fn thread_pass(
        &mut self,
        line: Line<'_>,
        words: &Words<'_>,
        f: Option<(Length, &Word)>,
        start: Pos,
        to: Pos,
        code_span: Span,
    ) -> Option<ThreadPass> {
        let block_range = code_span_range(line, code_span);
        let lead = self.lead(line, f, block_range.clone())?;
        let start_angle = self.start_angle(line, words.get('I'))?;
        let (j, e) = (words.get('J'), words.get('E'));
        let end = Pos {
            x: to.x.or(start.x),
            z: to.z.or(start.z),
        };
        let chamfers = j.is_some() || e.is_some();
        let travel = self.thread_travel(line, start, to, end, chamfers, block_range.clone())?;
        let (entry, exit) = self.entry_and_runout(line, e, j)?;
        let used =
            entry.map_or(Length::ZERO, |c| c.length) + exit.map_or(Length::ZERO, |c| c.length);
        if let Some(travel) = travel
            && used > travel
        {
            self.report(self.error(codes::CZR_THREAD_GEOMETRY, line, block_range, format!("entry and runout ({} mm) are longer than the thread's Z travel ({} mm)", used, travel))
                .help("the programmed end point includes the runout: J and E must fit inside the travel"));
            return None;
        }
        if entry.is_some() || exit.is_some() {
            self.after_runout = AfterRunout::EmptyBlock { thread: code_span };
        }
        // The thread line is the programmed line shifted by −(entry offset). **[decided]**
        // A block without X keeps the diameter: the pass says so too (X stays unwritten).
        let line_end_x = match entry {
            Some(c) => end.x.map(|x| x - c.offset),
            None => to.x,
        };
        Some(ThreadPass {
            to: Pos {
                x: line_end_x,
                z: end.z,
            },
            lead: Lead::from_length(lead),
            // Every G33 block waits for the index pulse. **[seed]**
            start: SyncStart::Index(start_angle),
            infeed: None,
            entry,
            exit,
        })
    }

    /// The lead: the block's F, or the F register when it was last written as a lead.
    fn lead(
        &mut self,
        line: Line<'_>,
        f: Option<(Length, &Word)>,
        block_range: Range<usize>,
    ) -> Option<Length> {
        Some(match (f, self.f) {
            (Some((lead, word)), _) => {
                if matches!(word.value, Value::Number(_)) && lead > MAX_DIRECT_LEAD {
                    let text = line.text[word.range.clone()].to_string();
                    self.report(self.error(codes::CZR_LEAD_TOO_LARGE, line, word.range.clone(), format!("lead `{text}` is over 99.99 mm, the most F can give directly"))
                    .label("over 99.99")
                    .help(format!("assign the lead to a parameter in an earlier block and use it: `R10={}` … `FR10`", lead.mm_with_point())));
                    return None;
                }
                if lead <= Length::ZERO {
                    self.report(
                        self.error(
                            codes::CZR_NO_LEAD,
                            line,
                            word.range.clone(),
                            "the lead must be positive",
                        )
                        .help("F in a G33 block is the lead in mm per spindle revolution"),
                    );
                    return None;
                }
                lead
            }
            (
                None,
                Some(FRegister {
                    value,
                    is_lead: true,
                }),
            ) => value,
            (None, other) => {
                let message = if other.is_some() {
                    "G33 block without F, and the last F was a feed, not a lead"
                } else {
                    "G33 block without a lead"
                };
                self.report(
                    self.error(codes::CZR_NO_LEAD, line, block_range, message)
                        .help("write the lead in the G33 block: F<mm per revolution> or FR<nn>"),
                );
                return None;
            }
        })
    }

    /// The start angle: I, from 0° to under 360°, or 0°.
    fn start_angle(&mut self, line: Line<'_>, word: Option<&Word>) -> Option<Angle> {
        Some(match word {
            Some(w) => {
                let Value::Number(d) = w.value else {
                    return None;
                };
                let angle = match d.to_angle() {
                    Ok(a) => a,
                    Err(e) => {
                        self.number_error(line, w.range.clone(), e, "0.001°");
                        return None;
                    }
                };
                if !(Angle::ZERO..Angle::from_deg(360)).contains(&angle) {
                    self.report(self.error(codes::CZR_START_ANGLE_RANGE, line, w.range.clone(), "the start angle must be at least 0° and less than 360°")
                    .help("I is the spindle angle after the index pulse at which the thread starts"));
                    return None;
                }
                angle
            }
            None => Angle::ZERO,
        })
    }

    /// The pass's Z travel, when its start is known. A taper or a pass with entry or runout
    /// needs its start point; a pass without Z travel is refused.
    fn thread_travel(
        &mut self,
        line: Line<'_>,
        start: Pos,
        to: Pos,
        end: Pos,
        chamfers: bool,
        block_range: Range<usize>,
    ) -> Option<Option<Length>> {
        let changes_x = to.x.is_some() && to.x != start.x;
        if (changes_x || chamfers) && start.known().is_none() {
            let why = if changes_x {
                "a taper thread"
            } else {
                "a thread with runout or entry"
            };
            self.report(
                self.error(
                    codes::CZR_UNKNOWN_POSITION,
                    line,
                    block_range.clone(),
                    format!("{why} needs its start point, which is not known here"),
                )
                .label("start point unknown")
                .help("move to the start of the thread with X and Z before this block"),
            );
            return None;
        }
        let travel = match (start.z, end.z) {
            (Some(a), Some(b)) => Some((b - a).abs()),
            _ => None,
        };
        if travel == Some(Length::ZERO) {
            self.report(
                self.error(
                    codes::CZR_THREAD_GEOMETRY,
                    line,
                    block_range,
                    "this G33 block has no Z travel",
                )
                .help("ncthread measures the lead along Z; face threads are not supported"),
            );
            return None;
        }
        Some(travel)
    }

    /// The entry (E, written with a decimal point) and the runout (J) chamfers.
    fn entry_and_runout(
        &mut self,
        line: Line<'_>,
        e: Option<&Word>,
        j: Option<&Word>,
    ) -> Option<(Option<Chamfer>, Option<Chamfer>)> {
        let mut entry = None;
        let mut exit = None;
        if let Some(w) = e {
            if let Value::Number(d) = w.value
                && !d.has_point
            {
                let text = line.text[w.range.clone()].to_string();
                self.report(self.error(codes::CZR_ENTRY_WITHOUT_POINT, line, w.range.clone(), format!("entry length `{text}` is written without a decimal point"))
                    .label("E needs a decimal point")
                    .help(format!("write `{text}.`: the manual requires E with a decimal point (E10. or E10.0)")));
                return None;
            }
            entry = Some(self.chamfer(line, w, AngleUse::Entry)?);
        }
        if let Some(w) = j {
            exit = Some(self.chamfer(line, w, AngleUse::Runout)?);
        }
        Some((entry, exit))
    }

    /// J or E: its length, and its offset from the angle that machine constant 8 selects.
    fn chamfer(&mut self, line: Line<'_>, word: &Word, usage: AngleUse) -> Option<Chamfer> {
        let Value::Number(d) = word.value else {
            return None;
        };
        let length = self.length(line, word, d)?;
        let letter = word.letter;
        if length <= Length::ZERO {
            self.report(self.error(codes::CZR_NEGATIVE_LENGTH, line, word.range.clone(), format!("{letter} must be a positive length"))
                .help(format!("{letter} is a length along the thread axis, always positive whatever the direction of travel")));
            return None;
        }
        let (angle_word, source) = self.chamfer_angle(line, word, usage)?;
        // sign · (axis·100 + angle) in 0.001°. **[seed]**
        let magnitude = angle_word.abs();
        let axis = magnitude / 100_000;
        let angle = Angle(magnitude % 100_000);
        if !(1..=3).contains(&axis) {
            self.report(self.error(codes::CZR_BAD_AXIS, line, word.range.clone(), format!("the {} angle in {source} names axis {axis}; the axis decade must be 1 (X), 2 (Y) or 3 (Z)", usage.name()))
                .help("write the axis in the hundreds: `R04=120.0` is axis X, 20°"));
            return None;
        }
        if axis != 1 {
            self.report(self.error(codes::CZR_RUNOUT_AXIS, line, word.range.clone(), format!("the {} angle in {source} moves axis {}; only X runout is supported on a ZX lathe", usage.name(), if axis == 2 { "Y" } else { "Z" }))
                .help("use axis 1 (X): `R04=120.0`"));
            return None;
        }
        if angle > MAX_ANGLE {
            self.report(
                self.error(
                    codes::CZR_ANGLE_TOO_LARGE,
                    line,
                    word.range.clone(),
                    format!(
                        "the {} angle {}° in {source} is over 60°",
                        usage.name(),
                        angle
                    ),
                )
                .help("runout and entry angles are 0 to 60°"),
            );
            return None;
        }
        let offset = Length::from_mm_f64(2.0 * length.to_mm_f64() * angle.tan());
        Some(Chamfer {
            length,
            offset: if angle_word < 0 { -offset } else { offset },
        })
    }

    /// The angle word `sign · (axis·100 + angle)` in 0.001° that machine constant 8 selects
    /// for `usage`, directly or through an R parameter, and where it comes from.
    fn chamfer_angle(
        &mut self,
        line: Line<'_>,
        word: &Word,
        usage: AngleUse,
    ) -> Option<(i64, String)> {
        let letter = word.letter;
        let profile_name = self
            .options
            .profile_name
            .clone()
            .unwrap_or_else(|| "the built-in profile".into());
        let Some(c8) = self.profile.constant8 else {
            self.report(self.error(codes::CZR_NO_CONSTANT8, line, word.range.clone(), format!("{} needs the {} angle from machine constant 8, which the profile does not give", letter, usage.name()))
                .label("angle unknown")
                .help("give the machine's TAB0.REK constant 8 in a profile (`--profile FILE`): [czech] constant8 = \"04000000\""));
            return None;
        };
        Some(match c8.angle_source() {
            AngleSource::Direct { word } => {
                (word, format!("machine constant 8 ({c8}, {profile_name})"))
            }
            AngleSource::Parameters { runout, entry } => {
                let param = match usage {
                    AngleUse::Runout => runout,
                    AngleUse::Entry => entry.unwrap_or(runout),
                };
                if param == 0 || param == 80 {
                    self.report(self.error(codes::CZR_FORBIDDEN_PARAM, line, word.range.clone(), format!("machine constant 8 ({c8}, {profile_name}) names R{param:02} for the {} angle; R00 and R80 may not hold angles", usage.name()))
                        .help("choose another parameter in constant 8 (the manual recommends R04)"));
                    return None;
                }
                let Some(value) = self.params.get(&param).copied() else {
                    self.report(self.error(codes::CZR_ANGLE_PARAM_UNSET, line, word.range.clone(), format!("the {} angle parameter R{param:02} is not assigned before this block", usage.name()))
                        .label(format!("needs R{param:02}"))
                        .help(format!("assign it in an earlier block: `R{param:02}=120.0` is axis X, +20° (machine constant 8 = {c8})")));
                    return None;
                };
                match value.to_scaled(Angle::DECIMALS) {
                    Ok(w) => (w, format!("R{param:02}")),
                    Err(e) => {
                        self.number_error(line, word.range.clone(), e, "0.001°");
                        return None;
                    }
                }
            }
        })
    }
}

#[derive(Clone, Copy)]
enum AngleUse {
    Runout,
    Entry,
}

impl AngleUse {
    fn name(self) -> &'static str {
        match self {
            AngleUse::Runout => "runout",
            AngleUse::Entry => "entry",
        }
    }
}

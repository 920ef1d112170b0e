//! G52 and the G92 family as LinuxCNC keeps them: an offset of the program's coordinates
//! that the reader resolves, so that the IR holds where the tool goes and every target moves
//! the same without saying the offset. **\[evidence\]** LinuxCNC `convert_axis_offsets`
//! (`interp_convert.cc`), parameters #5210 (applied), #5211 (X, a radius) and #5213 (Z) in
//! the program's units.

use super::super::gcode::*;
use super::{FrontEnd, Words};
use crate::dialect::iso::codes;
use crate::fixed::Length;
use crate::source::Line;

impl FrontEnd<'_> {
    /// An absolute X as the program writes it (grid value and exact mm, both diameters) →
    /// where the tool goes.
    pub(super) fn shifted_x(&self, v: Length, exact: f64) -> (Length, f64) {
        let off = self.axis_offset.0;
        if off == 0.0 {
            (v, exact)
        } else {
            (Length::from_mm_f64(exact + off), exact + off)
        }
    }

    pub(super) fn shifted_z(&self, v: Length, exact: f64) -> (Length, f64) {
        let off = self.axis_offset.1;
        if off == 0.0 {
            (v, exact)
        } else {
            (Length::from_mm_f64(exact + off), exact + off)
        }
    }

    /// G52, G92, G92.1, G92.2 or G92.3 (`code`, written as `w`) on `line`
    /// (`convert_axis_offsets`: refused under cutter radius compensation, then its case).
    pub(super) fn axis_offsets(
        &mut self,
        line: Line<'_>,
        words: &mut Words<'_>,
        code: GCode,
        w: &super::Word,
        with_motion: bool,
    ) {
        let x = words.take('X');
        let z = words.take('Z');
        if self.compensation {
            return self.comp_refusal(
                line,
                w,
                "Cannot change axis offsets with cutter radius comp",
            );
        }
        match code {
            G52 | G92 => self.set_axis_offsets(line, code, w, [x, z], with_motion),
            _ => self.reset_axis_offsets(line, code, w, [x, z]),
        }
    }

    /// G52 (the offset is the values) and G92 (the current point gets the values: the
    /// offset is where the tool is, less the values), for the axes they name.
    fn set_axis_offsets(
        &mut self,
        line: Line<'_>,
        code: GCode,
        w: &super::Word,
        axes: [Option<&super::Word>; 2],
        with_motion: bool,
    ) {
        let name = offset_name(code);
        if axes.iter().all(Option::is_none) {
            return self.missing(
                line,
                w,
                format!("{name} without X or Z (LinuxCNC: \"All axes missing with G52 or G92\")"),
                &format!("{name} sets the axes it names: `{name} X0 Z0`"),
            );
        }
        if with_motion {
            return self.missing(
                line,
                w,
                format!("{name} with a motion code on its line (LinuxCNC: \"Cannot use two G codes that both use axis values\")"),
                "put the move on a line of its own",
            );
        }
        let Some(off) = self.new_axis_offsets(line, code, axes) else {
            return;
        };
        if [off.0, off.1]
            .iter()
            .any(|v| !v.is_finite() || v.abs() > 1e9)
        {
            return self.missing(
                line,
                w,
                format!("{name} sets an offset of more than 1,000 km"),
                "check the values",
            );
        }
        self.axis_offset = off;
        self.saved_offset = off;
        self.offset_params[0] = 1.0;
        self.offsets_set = true;
    }

    /// The offsets (mm, X a diameter) G52 or G92 sets with the values of `axes` (X, Z);
    /// `None` when G92 names an axis whose position is not known (reported).
    fn new_axis_offsets(
        &mut self,
        line: Line<'_>,
        code: GCode,
        axes: [Option<&super::Word>; 2],
    ) -> Option<(f64, f64)> {
        let name = offset_name(code);
        let unit = if self.inch { 25.4 } else { 1.0 };
        let diameter = self.diameter.unwrap_or(false);
        let value_x = |w: &super::Word| w.value.to_f64() * unit * if diameter { 1.0 } else { 2.0 };
        let value_z = |w: &super::Word| w.value.to_f64() * unit;
        let (ex, ez) = self.exact_start();
        let mut off = self.axis_offset;
        for (word, here, slot) in [(axes[0], ex, 0usize), (axes[1], ez, 1)] {
            let Some(word) = word else { continue };
            let v = if slot == 0 {
                value_x(word)
            } else {
                value_z(word)
            };
            let target = if slot == 0 { &mut off.0 } else { &mut off.1 };
            if code == G52 {
                *target = v;
            } else {
                // The current point gets the value: the offset is where the tool
                // is, less the value.
                let Some(here) = here else {
                    let text = &line.text[word.range.clone()];
                    self.diag(
                        codes::ISOR_UNKNOWN_POSITION,
                        line,
                        word.range.clone(),
                        format!("`{name} {text}` from a position that is not known yet: the offset is where the tool is, less the value"),
                        "move to an absolute X and Z before G92",
                    );
                    return None;
                };
                *target = here - v;
            }
        }
        Some(off)
    }

    /// G92.1 (clear the offset and its parameters), G92.2 (clear the offset, keep the
    /// parameters) and G92.3 (apply the parameters' offset again): they take no axes.
    fn reset_axis_offsets(
        &mut self,
        line: Line<'_>,
        code: GCode,
        w: &super::Word,
        axes: [Option<&super::Word>; 2],
    ) {
        let name = offset_name(code);
        for word in axes.into_iter().flatten() {
            let text = &line.text[word.range.clone()];
            self.missing(
                line,
                word,
                format!("`{text}` on a {name} line, which takes no axes"),
                &format!("put {name} on a line of its own"),
            );
        }
        match code {
            G92_1 => {
                self.axis_offset = (0.0, 0.0);
                self.saved_offset = (0.0, 0.0);
                self.offset_params[0] = 0.0;
                self.offsets_set = true;
            }
            G92_2 => {
                self.axis_offset = (0.0, 0.0);
                self.offset_params[0] = 0.0;
            }
            _ if !self.offsets_set => {
                self.diag(
                    codes::ISOR_UNSUPPORTED,
                    line,
                    w.range.clone(),
                    "G92.3 before the program sets an offset: it restores the offset the machine kept from before the program (#5211–#5219), which ncthread does not know".into(),
                    "set the offset in the program (G92 X… Z…) or clear it (G92.1) first",
                );
            }
            // #5211–#5219 are in the machine's own units: a program that set them
            // restores what only the machine knows.
            _ if self.offset_params[1] != 0.0 || self.offset_params[2] != 0.0 => {
                self.diag(
                    codes::ISOR_UNSUPPORTED,
                    line,
                    w.range.clone(),
                    "G92.3 after the program set #5211–#5219: LinuxCNC restores them in the machine's own length units (its INI's LINEAR_UNITS), which the program does not say".into(),
                    "set the offset with G92 X… Z… instead of through the parameters",
                );
            }
            _ => {
                self.axis_offset = self.saved_offset;
                self.offset_params[0] = 1.0;
            }
        }
    }
}

/// The code's name as the messages write it.
fn offset_name(code: GCode) -> &'static str {
    match code {
        G52 => "G52",
        G92 => "G92",
        G92_1 => "G92.1",
        G92_2 => "G92.2",
        _ => "G92.3",
    }
}

//! A line's target: X and Z as written, increments, offsets, the exact position.

use super::super::syntax::Word;
use super::{FrontEnd, ProgramZ, Words};
use crate::dialect::iso::codes;
use crate::fixed::Length;
use crate::ir::Pos;
use crate::source::Line;

impl FrontEnd<'_> {
    /// The exact start of a move: [`FrontEnd::exact`] where it agrees with the known
    /// position, else the known position.
    pub(super) fn exact_start(&self) -> (Option<f64>, Option<f64>) {
        let pick = |exact: Option<f64>, known: Option<Length>| match (exact, known) {
            (Some(e), Some(k)) if (Length::from_mm_f64(e) - k).abs() <= Length::from_steps(1) => {
                Some(e)
            }
            (_, k) => k.map(Length::to_mm_f64),
        };
        (
            pick(self.exact.0, self.r.pos.x),
            pick(self.exact.1, self.r.pos.z),
        )
    }

    /// Where a move leaves the exact position: its target's axes, the others as they were.
    pub(super) fn exact_after_move(&mut self, start: (Option<f64>, Option<f64>)) {
        self.exact = (
            self.exact_target.0.or(start.0),
            self.exact_target.1.or(start.1),
        );
    }

    /// X and Z of the line as an absolute target (diameter), or `None` after an error.
    pub(super) fn target(&mut self, line: Line<'_>, words: &mut Words<'_>) -> Option<Pos> {
        let mut to = Pos::UNKNOWN;
        let start = self.exact_start();
        let unit = if self.inch { 25.4 } else { 1.0 };
        self.exact_target = (None, None);
        if let Some(w) = words.take('X') {
            let (v, exact) = self.x_word(line, w)?;
            // An increment is added to the exact position, then rounded: once.
            let (x, exact) = if self.incremental {
                match start.0 {
                    Some(s) => (Length::from_mm_f64(s + exact), s + exact),
                    None => return self.unknown(line, w),
                }
            } else {
                self.shifted_x(v, exact)
            };
            to.x = Some(x);
            self.exact_target.0 = Some(exact);
        }
        if let Some(w) = words.take('Z') {
            let v = self.length(line, w)?;
            let exact = w.value.to_f64() * unit;
            let (z, exact) = if self.incremental {
                match start.1 {
                    Some(s) => (Length::from_mm_f64(s + exact), s + exact),
                    None => return self.unknown(line, w),
                }
            } else {
                self.shifted_z(v, exact)
            };
            to.z = Some(z);
            self.exact_target.1 = Some(exact);
            // The Z as LinuxCNC holds it, for the drilling cycles' comparisons.
            let value = if self.incremental {
                start.1.map_or(0.0, |s| self.program_z(s)) + w.value.to_f64()
            } else {
                w.value.to_f64()
            };
            self.record_program_z(exact, value);
        }
        Some(to)
    }

    /// The Z at `mm` (exact, where the tool goes) as LinuxCNC holds it: in the program's
    /// units and coordinates, the very double it computed where ncthread saw it computed
    /// (`(mm − offset) / 25.4` need not give that double back, and the drilling cycles
    /// compare it with R).
    pub(super) fn program_z(&self, mm: f64) -> f64 {
        let offset = self.axis_offset.1;
        match self.z_program {
            Some(p) if p.mm == mm && p.inch == self.inch && p.offset == offset => p.value,
            _ => (mm - offset) / if self.inch { 25.4 } else { 1.0 },
        }
    }

    pub(super) fn record_program_z(&mut self, mm: f64, value: f64) {
        self.z_program = Some(ProgramZ {
            mm,
            value,
            inch: self.inch,
            offset: self.axis_offset.1,
        });
    }

    /// An X word as written, before any increment or offset: its value on the grid and its
    /// exact value in mm, both diameters. X is a radius until the program says G7 (with a
    /// warning, once).
    pub(super) fn x_word(&mut self, line: Line<'_>, w: &Word) -> Option<(Length, f64)> {
        let unit = if self.inch { 25.4 } else { 1.0 };
        let v = self.length(line, w)?;
        let diameter = match self.diameter {
            Some(d) => d,
            None => {
                if !self.warned_radius {
                    self.warned_radius = true;
                    self.diag(
                        codes::ISOR_RADIUS_MODE,
                        line,
                        w.range.clone(),
                        "X is read as a radius: the program has not chosen G7 (diameter) or G8 (radius), and LinuxCNC starts in G8".into(),
                        "write G7 or G8 at the start so that the program does not depend on the machine's start-up codes",
                    );
                }
                false
            }
        };
        let v = if diameter { v } else { v + v };
        let exact = w.value.to_f64() * unit * if diameter { 1.0 } else { 2.0 };
        Some((v, exact))
    }

    pub(super) fn unknown(&mut self, line: Line<'_>, w: &Word) -> Option<Pos> {
        self.diag(
            codes::ISOR_UNKNOWN_POSITION,
            line,
            w.range.clone(),
            format!(
                "`{}` is incremental (G91) from a position that is not known yet",
                &line.text[w.range.clone()]
            ),
            "move to an absolute position (G90) first",
        );
        None
    }
}

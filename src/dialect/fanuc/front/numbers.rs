//! The numbers of a block's words: whole numbers, lengths on the grid (the decimal point
//! rule and inches applied) and leads.

use super::{FrontEnd, Unit};
use crate::dialect::fanuc::codes;
use crate::dialect::fanuc::profile::DecimalPoint;
use crate::dialect::fanuc::syntax::Word;
use crate::fixed::{Decimal, Lead, Length, NumberError, div_round};
use crate::source::Line;

impl FrontEnd<'_> {
    pub(super) fn number_error(&mut self, line: Line<'_>, word: &Word, e: NumberError, grid: &str) {
        let text = &line.text[word.range.clone()];
        let message = match e {
            NumberError::TooPrecise { .. } => {
                format!("`{text}` is finer than the control's {grid}")
            }
            NumberError::TooLarge => format!("`{text}` is too large"),
        };
        self.error(
            codes::FANR_NUMBER,
            line,
            word.range.clone(),
            message,
            "write the value the control takes (3 decimals for lengths in mm, 4 for leads and feeds)",
        );
    }

    /// A whole number without a decimal point (G, M, S, T, P, Q). An S may have one where
    /// nothing follows it but zeros (`S3000.`, as Haas programs write it): the speed is the
    /// same whole number. **\[decided\]**
    pub(super) fn whole(&mut self, line: Line<'_>, word: &Word) -> Option<i64> {
        let text = &line.text[word.range.clone()];
        let whole_speed = word.letter == 'S' && word.value.to_whole().is_ok();
        if word.value.has_point && !whole_speed {
            self.error(
                codes::FANR_NUMBER,
                line,
                word.range.clone(),
                format!(
                    "`{text}`: {} takes a whole number without a decimal point",
                    word.letter
                ),
                "write it without the point",
            );
            return None;
        }
        match word.value.to_whole() {
            Ok(v) => Some(v),
            Err(e) => {
                self.number_error(line, word, e, "whole number");
                None
            }
        }
    }

    /// Notes the first word read without a decimal point.
    fn note_no_point(&mut self, line: Line<'_>, word: &Word) {
        if self.no_point.is_none() {
            let span = self.span(line, word.range.clone());
            self.no_point = Some((span, line.text[word.range.clone()].to_string()));
        }
    }

    /// The value of a word in mm (the point rule and inches applied), as a decimal number
    /// of mm with at most `decimals` decimals, or `None` after a diagnostic.
    pub(super) fn mm_value(&mut self, line: Line<'_>, word: &Word, unit: Unit) -> Option<Decimal> {
        let mut value = word.value;
        if !value.has_point && self.profile.decimal_point == DecimalPoint::Increment {
            let scale = match (unit, self.inch) {
                (Unit::Axis, false) => 3,
                (Unit::Axis, true) => 4,
                // A feed without a point, in mm: whole mm/min under G98, 0.0001 mm/rev under
                // G99. **[decided]** (spec fanuc.md)
                (Unit::Feed, false) if self.per_minute => 0,
                (Unit::Feed, false) => 4,
                _ => {
                    let text = &line.text[word.range.clone()];
                    let what = match unit {
                        Unit::Lead => "a lead F",
                        Unit::Seconds => "a dwell time",
                        _ => "a feed",
                    };
                    self.error(
                        codes::FANR_NUMBER,
                        line,
                        word.range.clone(),
                        format!("`{text}` has no decimal point, and the unit of {what} without one is not settled by any source ncthread holds"),
                        "write the value with a decimal point (`F0.2`, `G04 U1.5`, or `G04 P1500` in milliseconds)",
                    );
                    return None;
                }
            };
            value = Decimal {
                mantissa: value.mantissa,
                scale,
                has_point: true,
            };
            self.note_no_point(line, word);
        } else if !value.has_point {
            self.note_no_point(line, word);
        }
        Some(value)
    }

    /// A length word (X Z U W I K R, a feed): millimetres on the 0.0001 mm step, inches exact
    /// to 0.0001 in.
    pub(super) fn length(&mut self, line: Line<'_>, word: &Word, unit: Unit) -> Option<Length> {
        let value = self.mm_value(line, word, unit)?;
        self.r.saw_length(self.inch);
        if self.inch {
            // mm = in · 25.4: in grid units, mantissa · 2,540,000 / 10^scale (exact to
            // 0.0001 in).
            let den = 10i128.checked_pow(value.scale)?;
            let Some(num) = value.mantissa.checked_mul(2_540_000) else {
                self.number_error(line, word, NumberError::TooLarge, "");
                return None;
            };
            let units = div_round(num, den);
            if units.abs() > (1 << 50) * Length::STEP as i128 {
                self.number_error(line, word, NumberError::TooLarge, "");
                return None;
            }
            if num % den != 0 && self.inch_rounded.is_none() {
                self.inch_rounded = Some(self.span(line, word.range.clone()));
            }
            return Some(Length(units as i64));
        }
        let grid = if unit == Unit::Axis { 3 } else { 4 };
        match value.to_scaled(grid) {
            Ok(v) => value
                .to_length()
                .ok()
                .or(Some(Length::from_steps(v * 10i64.pow(4 - grid)))),
            Err(e) => {
                let g = if grid == 3 { "0.001 mm" } else { "0.0001 mm" };
                self.number_error(line, word, e, g);
                None
            }
        }
    }

    /// A lead (F in G32/G92), exact.
    pub(super) fn lead(&mut self, line: Line<'_>, word: &Word) -> Option<Lead> {
        let value = self.mm_value(line, word, Unit::Lead)?;
        let lead = if self.inch {
            // 25.4 · value, exactly on the 10⁻¹² mm grid for up to 10 decimals.
            value.mantissa.checked_mul(254).and_then(|m| {
                Decimal {
                    mantissa: m,
                    scale: value.scale + 1,
                    has_point: true,
                }
                .to_lead()
                .ok()
            })
        } else {
            match value.to_scaled(4) {
                Ok(_) => value.to_lead().ok(),
                Err(e) => {
                    self.number_error(line, word, e, "0.0001 mm");
                    return None;
                }
            }
        };
        match lead {
            Some(l) if l.0 > 0 => Some(l),
            _ => {
                let text = &line.text[word.range.clone()];
                self.error(
                    codes::FANR_NUMBER,
                    line,
                    word.range.clone(),
                    format!("`{text}` is not a lead the control can cut"),
                    "a lead is positive and has at most 4 decimals in mm",
                );
                None
            }
        }
    }
}

//! Word values: lengths on the grid, leads, whole numbers, and their diagnostics.

use super::super::syntax::Word;
use super::FrontEnd;
use crate::dialect::iso::codes;
use crate::fixed::{Lead, Length, POWERS_OF_TEN, div_round};
use crate::source::Line;

impl FrontEnd<'_> {
    /// A length word in program units → a length on the grid: millimetres exact to 0.00001
    /// mm, inches to 0.0001 in; warns once when it rounds.
    pub(super) fn length(&mut self, line: Line<'_>, w: &Word) -> Option<Length> {
        self.length_times(line, w, 1)
    }

    /// `times` the word's length, rounded once (an arc's I, a radius, as a diameter).
    pub(super) fn length_times(&mut self, line: Line<'_>, w: &Word, times: i128) -> Option<Length> {
        let d = w.value;
        self.r.saw_length(self.inch);
        // Grid units per program unit (1 in = 2,540,000).
        let per_unit = if self.inch {
            Length::PER_INCH
        } else {
            Length::PER_MM
        } as i128;
        // A word's few digits in i64, where the product cannot overflow (|num| < 2⁶³): i128's
        // remainder is a library call, for every length read.
        let small = i64::try_from(d.mantissa)
            .ok()
            .filter(|m| m.unsigned_abs() < 1 << 40 && (-2..=2).contains(&times))
            .zip(POWERS_OF_TEN.get(d.scale as usize))
            .map(|(m, &den)| (m * per_unit as i64 * times as i64, den));
        let (num, den) = match small {
            Some((num, den)) => (i128::from(num), i128::from(den)),
            None => {
                let den = 10i128.checked_pow(d.scale);
                let num = d.mantissa.checked_mul(per_unit * times);
                let (Some(num), Some(den)) = (num, den) else {
                    self.too_large(line, w);
                    return None;
                };
                (num, den)
            }
        };
        let v = div_round(num, den);
        if v.abs() > (1 << 50) * Length::STEP as i128 {
            self.too_large(line, w);
            return None;
        }
        let length = Length(v as i64);
        let rounds = match small {
            Some((num, den)) => num % den != 0,
            None => num % den != 0,
        };
        if rounds && !self.warned_rounding {
            self.warned_rounding = true;
            let exact = num as f64 / den as f64 / Length::PER_MM as f64;
            self.diag(
                codes::ISOR_ROUNDED,
                line,
                w.range.clone(),
                format!(
                    "`{}` is {exact} mm{}, rounded to {} mm (ncthread holds lengths to 0.00001 mm; later values that round are not reported again)",
                    &line.text[w.range.clone()],
                    if times == 2 { " as a diameter" } else { "" },
                    length.mm(),
                ),
                "the rounding is at most 0.000005 mm, far inside the 0.001 mm that `verify` allows",
            );
        }
        Some(length)
    }

    /// A lead word (K, G76's P) in program units → a [`Lead`], exact to 10⁻¹² mm.
    pub(super) fn lead(&mut self, line: Line<'_>, w: &Word) -> Option<Lead> {
        let d = w.value;
        // mm: value × 10¹²; inch: value × 25.4 × 10¹² = value × 254 × 10¹¹.
        let (factor, shift) = if self.inch { (254, 11) } else { (1, 12) };
        let num = d.mantissa.checked_mul(factor);
        let scaled = match num {
            Some(num) if d.scale <= shift => 10i128
                .checked_pow(shift - d.scale)
                .and_then(|f| num.checked_mul(f)),
            Some(num) => 10i128
                .checked_pow(d.scale - shift)
                .map(|den| div_round(num, den)),
            None => None,
        };
        match scaled {
            Some(v) if v.abs() <= Lead::MAX.0 as i128 => Some(Lead(v as i64)),
            _ => {
                self.diag(
                    codes::ISOR_NUMBER,
                    line,
                    w.range.clone(),
                    format!("`{}` is too large for a lead", &line.text[w.range.clone()]),
                    "a lead is at most 1,000,000 mm",
                );
                None
            }
        }
    }

    pub(super) fn too_large(&mut self, line: Line<'_>, w: &Word) {
        self.diag(
            codes::ISOR_NUMBER,
            line,
            w.range.clone(),
            format!("`{}` is too large", &line.text[w.range.clone()]),
            "lengths are at most about 10^11 mm",
        );
    }

    pub(super) fn number_error(&mut self, line: Line<'_>, w: &Word, message: String, help: &str) {
        self.diag(codes::ISOR_NUMBER, line, w.range.clone(), message, help);
    }

    pub(super) fn whole(&mut self, line: Line<'_>, w: &Word, what: &str) -> Option<u32> {
        match w.value.to_whole().ok().and_then(|v| u32::try_from(v).ok()) {
            Some(v) => Some(v),
            None => {
                self.number_error(
                    line,
                    w,
                    format!(
                        "{what} `{}` is not a whole number of 0 or more",
                        &line.text[w.range.clone()]
                    ),
                    "write it as a whole number",
                );
                None
            }
        }
    }

    pub(super) fn missing(&mut self, line: Line<'_>, at: &Word, message: String, help: &str) {
        self.diag(codes::ISOR_WORD, line, at.range.clone(), message, help);
    }
}

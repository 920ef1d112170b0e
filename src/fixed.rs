//! Exact numbers: fixed-point lengths and angles, and the decimal literals they come from.
//!
//! Lengths are integers of 0.0001 mm, angles integers of 0.001°. Floats appear only inside
//! trigonometry and are rounded once onto these grids ([`Length::from_mm_f64`],
//! [`Angle::tan`] callers).

use std::fmt;

/// A length in units of 0.0001 mm (X is a diameter wherever it appears).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Length(pub i64);

/// An angle in units of 0.001°.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Angle(pub i64);

impl Length {
    /// Decimal places of the grid.
    pub const DECIMALS: u32 = 4;
    pub const ZERO: Length = Length(0);

    pub fn from_mm(mm: i64) -> Length {
        Length(mm * 10_000)
    }

    /// Rounds a float (the result of trigonometry) onto the grid, half away from zero.
    pub fn from_mm_f64(mm: f64) -> Length {
        Length((mm * 10_000.0).round() as i64)
    }

    pub fn to_mm_f64(self) -> f64 {
        self.0 as f64 / 10_000.0
    }

    pub fn abs(self) -> Length {
        Length(self.0.abs())
    }

    pub fn signum(self) -> i64 {
        self.0.signum()
    }

    /// `self · num / den`, rounded half away from zero onto the grid (exact integer arithmetic).
    pub fn mul_div(self, num: i64, den: i64) -> Length {
        Length(div_round(self.0 as i128 * num as i128, den as i128) as i64)
    }

    /// The value in millimetres with as few decimals as needed (`-100`, `71.798`).
    pub fn mm(self) -> String {
        format_scaled(self.0, Self::DECIMALS, Trailing::None)
    }

    /// The value in millimetres, always with a decimal point (`3.`, `26.618`).
    pub fn mm_with_point(self) -> String {
        format_scaled(self.0, Self::DECIMALS, Trailing::Point)
    }
}

impl std::ops::Add for Length {
    type Output = Length;
    fn add(self, o: Length) -> Length {
        Length(self.0 + o.0)
    }
}

impl std::ops::Sub for Length {
    type Output = Length;
    fn sub(self, o: Length) -> Length {
        Length(self.0 - o.0)
    }
}

impl std::ops::Neg for Length {
    type Output = Length;
    fn neg(self) -> Length {
        Length(-self.0)
    }
}

impl fmt::Display for Length {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.mm())
    }
}

impl Angle {
    pub const DECIMALS: u32 = 3;
    pub const ZERO: Angle = Angle(0);

    pub fn from_deg(deg: i64) -> Angle {
        Angle(deg * 1000)
    }

    pub fn to_deg_f64(self) -> f64 {
        self.0 as f64 / 1000.0
    }

    pub fn tan(self) -> f64 {
        self.to_deg_f64().to_radians().tan()
    }

    /// Degrees with as few decimals as needed (`18`, `12.5`).
    pub fn deg(self) -> String {
        format_scaled(self.0, Self::DECIMALS, Trailing::None)
    }
}

impl fmt::Display for Angle {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.deg())
    }
}

/// Integer division rounding half away from zero.
pub fn div_round(num: i128, den: i128) -> i128 {
    debug_assert!(den != 0);
    let (num, den) = if den < 0 { (-num, -den) } else { (num, den) };
    if num >= 0 {
        (num + den / 2) / den
    } else {
        -((-num + den / 2) / den)
    }
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Trailing {
    None,
    Point,
}

fn format_scaled(value: i64, decimals: u32, trailing: Trailing) -> String {
    let scale = 10i64.pow(decimals);
    let sign = if value < 0 { "-" } else { "" };
    let abs = value.unsigned_abs();
    let whole = abs / scale as u64;
    let frac = abs % scale as u64;
    if frac == 0 {
        return match trailing {
            Trailing::None => format!("{sign}{whole}"),
            Trailing::Point => format!("{sign}{whole}."),
        };
    }
    let frac = format!("{frac:0width$}", width = decimals as usize);
    format!("{sign}{whole}.{}", frac.trim_end_matches('0'))
}

/// Splits an optional leading `+`/`-` from `text`: (negative, the rest). `None` for "".
pub fn split_sign(text: &str) -> Option<(bool, &str)> {
    Some(match text.as_bytes().first()? {
        b'-' => (true, &text[1..]),
        b'+' => (false, &text[1..]),
        _ => (false, text),
    })
}

/// A number exactly as written in a program: `-00120.000`, `26.618`, `12`, `.5`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Decimal {
    /// All digits as one integer, sign included (`-00120.000` → -120000).
    pub mantissa: i128,
    /// Digits after the decimal point (`-00120.000` → 3).
    pub scale: u32,
    /// Whether a decimal point was written (`E12.` vs `E12`).
    pub has_point: bool,
}

/// Why a decimal literal does not fit where it is used.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NumberError {
    /// More decimals than the grid holds (e.g. 0.00001 mm).
    TooPrecise { decimals: u32 },
    /// Outside the range of the representation.
    TooLarge,
}

impl Decimal {
    /// Parses `[+-]digits[.digits]` or `[+-].digits`; `None` when the text is not such a number.
    pub fn parse(text: &str) -> Option<Decimal> {
        let (negative, rest) = split_sign(text)?;
        let (int, frac, has_point) = match rest.split_once('.') {
            Some((i, f)) => (i, f, true),
            None => (rest, "", false),
        };
        if int.is_empty() && frac.is_empty() {
            return None;
        }
        if !int.bytes().chain(frac.bytes()).all(|b| b.is_ascii_digit()) {
            return None;
        }
        let mut mantissa: i128 = 0;
        for b in int.bytes().chain(frac.bytes()) {
            mantissa = mantissa.checked_mul(10)?.checked_add((b - b'0') as i128)?;
        }
        if negative {
            mantissa = -mantissa;
        }
        Some(Decimal {
            mantissa,
            scale: frac.len() as u32,
            has_point,
        })
    }

    /// The value as an integer of `10^-decimals` units, exactly, or why not.
    pub fn to_scaled(self, decimals: u32) -> Result<i64, NumberError> {
        let value = if self.scale <= decimals {
            let factor = 10i128
                .checked_pow(decimals - self.scale)
                .ok_or(NumberError::TooLarge)?;
            self.mantissa
                .checked_mul(factor)
                .ok_or(NumberError::TooLarge)?
        } else {
            let factor = 10i128
                .checked_pow(self.scale - decimals)
                .ok_or(NumberError::TooLarge)?;
            if self.mantissa % factor != 0 {
                return Err(NumberError::TooPrecise { decimals });
            }
            self.mantissa / factor
        };
        // Keep well inside i64 so later products (lead · length) cannot overflow.
        const LIMIT: i128 = 1 << 50;
        if value.abs() > LIMIT {
            return Err(NumberError::TooLarge);
        }
        Ok(value as i64)
    }

    pub fn to_length(self) -> Result<Length, NumberError> {
        self.to_scaled(Length::DECIMALS).map(Length)
    }

    pub fn to_angle(self) -> Result<Angle, NumberError> {
        self.to_scaled(Angle::DECIMALS).map(Angle)
    }

    /// A whole number (a G, M, S, T or D value); `12.` and `12.0` count as whole.
    pub fn to_whole(self) -> Result<i64, NumberError> {
        self.to_scaled(0)
    }

    pub fn is_negative(self) -> bool {
        self.mantissa < 0
    }

    /// The nearest `f64` (what a C program's `strtod` reads from the same text).
    pub fn to_f64(self) -> f64 {
        // The mantissa and the power of ten are exact in f64 for the numbers programs
        // hold (up to 15 digits), so one correctly rounded division gives strtod's value.
        self.mantissa as f64 / 10f64.powi(self.scale as i32)
    }
}

impl fmt::Display for Decimal {
    /// The number with its written decimals (leading zeros are not kept): `-120.000`, `12.`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let digits = self.mantissa.unsigned_abs().to_string();
        let scale = self.scale as usize;
        let digits = format!("{digits:0>width$}", width = scale + 1);
        let (int, frac) = digits.split_at(digits.len() - scale);
        let sign = if self.mantissa < 0 { "-" } else { "" };
        let point = if self.has_point { "." } else { "" };
        write!(f, "{sign}{int}{point}{frac}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_the_seed_spellings() {
        let d = Decimal::parse("-00120.000").unwrap();
        assert_eq!((d.mantissa, d.scale, d.has_point), (-120000, 3, true));
        assert_eq!(d.to_length(), Ok(Length(-1_200_000)));
        assert_eq!(Decimal::parse("Z").map(|d| d.mantissa), None);
        assert!(!Decimal::parse("12").unwrap().has_point);
        assert_eq!(
            Decimal::parse("12.").unwrap().to_length(),
            Ok(Length::from_mm(12))
        );
        assert_eq!(Decimal::parse(".5").unwrap().to_length(), Ok(Length(5000)));
        assert_eq!(
            Decimal::parse("+3").unwrap().to_length(),
            Ok(Length::from_mm(3))
        );
        assert_eq!(Decimal::parse("-"), None);
        assert_eq!(Decimal::parse("."), None);
        assert_eq!(Decimal::parse("1.2.3"), None);
    }

    #[test]
    fn decimals_print_as_written() {
        for (text, shown) in [
            ("-00120.000", "-120.000"),
            ("12.", "12."),
            ("250.0", "250.0"),
            (".5", "0.5"),
            ("7", "7"),
        ] {
            assert_eq!(Decimal::parse(text).unwrap().to_string(), shown);
        }
    }

    #[test]
    fn refuses_values_off_the_grid() {
        let d = Decimal::parse("1.00005").unwrap();
        assert_eq!(d.to_length(), Err(NumberError::TooPrecise { decimals: 4 }));
        // Trailing zeros beyond the grid are exact.
        assert_eq!(
            Decimal::parse("1.000000").unwrap().to_length(),
            Ok(Length(10_000))
        );
        assert_eq!(
            Decimal::parse("12.5").unwrap().to_whole(),
            Err(NumberError::TooPrecise { decimals: 0 })
        );
        assert_eq!(
            Decimal::parse("99999999999999999999999")
                .unwrap()
                .to_length(),
            Err(NumberError::TooLarge)
        );
    }

    #[test]
    fn formats_without_noise() {
        assert_eq!(Length(-1_000_000).mm(), "-100");
        assert_eq!(Length(717_980).mm(), "71.798");
        assert_eq!(Length(30_000).mm_with_point(), "3.");
        assert_eq!(Length(-5).mm(), "-0.0005");
        assert_eq!(Angle(12_500).deg(), "12.5");
    }

    #[test]
    fn rounds_half_away_from_zero() {
        assert_eq!(div_round(5, 2), 3);
        assert_eq!(div_round(-5, 2), -3);
        assert_eq!(div_round(4, 3), 1);
        assert_eq!(Length(10).mul_div(1, 4), Length(3));
        assert_eq!(Length::from_mm_f64(7.798_072_7), Length(77_981));
    }
}

//! Exact numbers: fixed-point lengths and angles, and the decimal literals they come from.
//!
//! Lengths are integers of 0.00001 mm, a grid that holds 0.0001 mm and 0.0001 in (2.54 µm,
//! 254 units) alike. A value written in millimetres, and every computed value, lies on the
//! 0.0001 mm step ([`Length::STEP`]); a value written in inches on the 0.0001 in step.
//! Angles are integers of 0.001°. Floats appear only inside trigonometry and are rounded once
//! onto these grids ([`Length::from_mm_f64`], [`Angle::tan`] callers).

use std::fmt;

/// A length in units of 0.00001 mm (X is a diameter wherever it appears).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Length(pub i64);

/// An angle in units of 0.001°.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Angle(pub i64);

impl Length {
    /// Decimal places of the grid (0.00001 mm).
    pub const DECIMALS: u32 = 5;
    /// Grid units per millimetre.
    pub const PER_MM: i64 = 100_000;
    /// Decimal places of the millimetre step: a millimetre program's values, and computed ones.
    pub const MM_DECIMALS: u32 = 4;
    /// The millimetre step, 0.0001 mm, in grid units.
    pub const STEP: i64 = 10;
    /// The inch step, 0.0001 in, in grid units.
    pub const INCH_STEP: i64 = 254;
    pub const ZERO: Length = Length(0);

    pub fn from_mm(mm: i64) -> Length {
        Length(mm * Self::PER_MM)
    }

    /// `steps` of 0.0001 mm.
    pub const fn from_steps(steps: i64) -> Length {
        Length(steps * Self::STEP)
    }

    /// Rounds a float (the result of trigonometry) onto the 0.0001 mm step, half away from
    /// zero.
    pub fn from_mm_f64(mm: f64) -> Length {
        Length(round_half_away(mm * 10_000.0) as i64 * Self::STEP)
    }

    pub fn to_mm_f64(self) -> f64 {
        self.0 as f64 / Self::PER_MM as f64
    }

    /// Whether the value is a whole number of `10^-decimals` mm (`decimals` at most 5).
    pub fn on_mm_decimals(self, decimals: u32) -> bool {
        self.0 % 10i64.pow(Self::DECIMALS.saturating_sub(decimals)) == 0
    }

    pub fn abs(self) -> Length {
        Length(self.0.abs())
    }

    pub fn signum(self) -> i64 {
        self.0.signum()
    }

    /// `self · num / den`, rounded half away from zero onto the 0.0001 mm step (exact
    /// integer arithmetic).
    pub fn mul_div(self, num: i64, den: i64) -> Length {
        Length(
            div_round(
                self.0 as i128 * num as i128,
                den as i128 * Self::STEP as i128,
            ) as i64
                * Self::STEP,
        )
    }

    /// The value in millimetres with as few decimals as needed (`-100`, `71.798`).
    pub fn mm(self) -> String {
        format_scaled(self.0, Self::DECIMALS, Trailing::None)
    }

    /// [`Self::mm`] appended to `out`.
    pub fn push_mm(self, out: &mut String) {
        format_scaled_into(out, self.0, Self::DECIMALS, Trailing::None);
    }

    /// The value in millimetres, always with a decimal point (`3.`, `26.618`).
    pub fn mm_with_point(self) -> String {
        format_scaled(self.0, Self::DECIMALS, Trailing::Point)
    }

    /// [`Length::mm_with_point`] appended to `out`.
    pub fn push_mm_with_point(self, out: &mut String) {
        format_scaled_into(out, self.0, Self::DECIMALS, Trailing::Point);
    }

    /// The value in millimetres with all four decimals (`0.2000`, `-47.5000`): a table's
    /// column; five where the value lies between two 0.0001 mm steps (an inch value).
    pub fn mm_fixed(self) -> String {
        if self.0 % Self::STEP == 0 {
            format_scaled(self.0 / Self::STEP, Self::MM_DECIMALS, Trailing::All)
        } else {
            format_scaled(self.0, Self::DECIMALS, Trailing::All)
        }
    }

    /// Half of this length in mm, exactly (a diameter's radius: one more decimal when it
    /// falls between two grid steps): `Length::from_steps(30)` → `0.00015`.
    pub fn half_mm(self) -> String {
        // Lengths are at most about 10^11 mm (10^16 units): five times that fits.
        format_scaled(self.0.saturating_mul(5), Self::DECIMALS + 1, Trailing::None)
    }
}

/// `num / den` as a decimal with the fewest decimals from `min` to `max` that hold it
/// exactly, else rounded half away from zero at `max`: the text, and the rounded value times
/// `den / 10^max` (compare it with `num · 10^max / 10^max` for the deviation), and whether it
/// is exact.
pub fn decimal_of(num: i128, den: i128, min: u32, max: u32) -> (String, bool) {
    for decimals in min..=max {
        let Some(scaled) = 10i128
            .checked_pow(decimals)
            .and_then(|p| num.checked_mul(p))
        else {
            break;
        };
        if scaled % den == 0 {
            return (format_wide(scaled / den, decimals), true);
        }
    }
    let scaled = 10i128
        .checked_pow(max)
        .and_then(|p| num.checked_mul(p))
        .unwrap_or(num);
    (format_wide(div_round(scaled, den), max), false)
}

/// An i128 of `10^-decimals` units, as few decimals as needed.
fn format_wide(value: i128, decimals: u32) -> String {
    match i64::try_from(value) {
        Ok(v) => format_scaled(v, decimals, Trailing::None),
        Err(_) => value.to_string(),
    }
}

impl Length {
    /// Grid units per inch.
    pub const PER_INCH: i64 = 2_540_000;

    /// The value in inches: exact with up to four decimals (0.0001 in, 254 units), else to
    /// 0.000001 in; `false` when rounded.
    pub fn inches(self) -> (String, bool) {
        decimal_of(self.0 as i128, Self::PER_INCH as i128, 0, 6)
    }

    /// The value in inches with a decimal point (`1.`, `0.0625`), when it lies on the
    /// 0.0001 in step.
    pub fn inches_with_point(self) -> Option<String> {
        (self.0 % Self::INCH_STEP == 0)
            .then(|| format_scaled(self.0 / Self::INCH_STEP, 4, Trailing::Point))
    }

    /// The length that [`Length::inches`]'s text reads back as, on the grid: itself on the
    /// 0.0001 in step, else the 0.000001 in value rounded to the grid unit (as a reader
    /// rounds it).
    pub fn inch_read_back(self) -> Length {
        if self.0 % Self::INCH_STEP == 0 {
            return self;
        }
        let n = div_round(self.0 as i128 * 100, Self::INCH_STEP as i128);
        Length(div_round(n * Self::INCH_STEP as i128, 100) as i64)
    }

    /// Half of this length in inches (a diameter's radius), as [`Length::inches`].
    pub fn half_inches(self) -> (String, bool) {
        decimal_of(self.0 as i128, 2 * Self::PER_INCH as i128, 0, 6)
    }

    /// How far `text`, a value in inches, lies from this length (on the grid, rounded up).
    pub fn inch_deviation(self, text: &str, half: bool) -> Length {
        let Some(d) = Decimal::parse(text) else {
            return Length::ZERO;
        };
        let per = if half { 2 } else { 1 } * Self::PER_INCH as i128;
        let Some(den) = 10i128.checked_pow(d.scale) else {
            return Length::ZERO;
        };
        let diff = (d.mantissa * per - self.0 as i128 * den).abs();
        Length(((diff + den - 1) / den).min(i64::MAX as i128) as i64)
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

/// A lead: the advance per spindle revolution, in units of 10⁻¹² mm.
///
/// Leads are kept far finer than lengths because their error grows with every turn: a lead
/// computed from LinuxCNC's K along a taper is irrational, and on the 0.0001 mm grid it
/// would drift past the tolerance over a long thread. At 10⁻¹² mm a thread drifts by less
/// than 10⁻⁶ mm over a million turns. A lead written in a program with up to 12 decimals is
/// held exactly.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Lead(pub i64);

impl Lead {
    pub const DECIMALS: u32 = 12;
    pub const ZERO: Lead = Lead(0);
    /// Lead units per [`Length`] unit.
    pub const PER_LENGTH: i64 = 10_000_000;
    /// The largest lead ncthread holds: 1,000,000 mm (i64 holds more, but products with
    /// lengths must stay inside i128).
    pub const MAX: Lead = Lead(1_000_000 * 1_000_000_000_000);

    pub fn from_length(l: Length) -> Lead {
        Lead(l.0.saturating_mul(Self::PER_LENGTH))
    }

    /// Rounds a float (the result of trigonometry or of LinuxCNC's arithmetic) onto the
    /// grid; `None` when it is not finite or over [`Lead::MAX`].
    pub fn from_mm_f64(mm: f64) -> Option<Lead> {
        let v = (mm * 1e12).round();
        (v.is_finite() && v.abs() <= Self::MAX.0 as f64).then_some(Lead(v as i64))
    }

    pub fn to_mm_f64(self) -> f64 {
        self.0 as f64 / 1e12
    }

    /// The lead as a length, when it lies on the 0.0001 mm step.
    pub fn exact_length(self) -> Option<Length> {
        (self.0 % (Self::PER_LENGTH * Length::STEP) == 0)
            .then_some(Length(self.0 / Self::PER_LENGTH))
    }

    /// The lead in units of `10^-decimals` mm: exactly, or rounded half away from zero with
    /// `false`.
    pub fn in_units(self, decimals: u32) -> (i64, bool) {
        let den = 10i128.pow(Self::DECIMALS.saturating_sub(decimals));
        let v = div_round(self.0 as i128, den);
        (v as i64, self.0 as i128 % den == 0)
    }

    /// The lead of `units` of `10^-decimals` mm.
    pub fn from_units(units: i64, decimals: u32) -> Lead {
        Lead(units.saturating_mul(10i64.pow(Self::DECIMALS.saturating_sub(decimals))))
    }

    /// `self · num / den` as a length, rounded once onto the 0.0001 mm step (exact integer
    /// arithmetic): a runout of P7 tenths of the lead, the Z shift of a start angle.
    pub fn length_times(self, num: i64, den: i64) -> Length {
        Length::from_steps(div_round(
            self.0 as i128 * num as i128,
            den as i128 * Self::PER_LENGTH as i128 * Length::STEP as i128,
        ) as i64)
    }

    /// The spindle's turn, in 0.001°, while a thread of this lead advances `travel` along Z
    /// (the inverse of [`Lead::of_angle`]), rounded once.
    pub fn turn_over(self, travel: Length) -> i64 {
        div_round(
            travel.0 as i128 * 360_000 * Self::PER_LENGTH as i128,
            self.0.max(1) as i128,
        ) as i64
    }

    /// The axial shift that stands for a start angle: `lead · angle / 360°`, on the grid.
    pub fn of_angle(self, angle: Angle) -> Length {
        self.length_times(angle.0, 360_000)
    }

    /// How far a helix of this lead drifts from one of `other` over `travel` along Z:
    /// `|self − other| · travel / self`, on the length grid (rounded up, so that any drift
    /// shows).
    pub fn drift(self, other: Lead, travel: Length) -> Length {
        if self.0 <= 0 {
            return Length(i64::MAX);
        }
        let num = (self.0 as i128 - other.0 as i128).abs() * travel.0.unsigned_abs() as i128;
        let den = self.0 as i128 * Length::STEP as i128;
        let steps = ((num + den - 1) / den).min(i64::MAX as i128 / Length::STEP as i128);
        Length::from_steps(steps as i64)
    }

    /// The lead in inches with at most `decimals` decimals and a decimal point, and the lead
    /// that text is (rounded half away from zero where it is not exact).
    pub fn inches_to(self, decimals: u32) -> (String, Lead) {
        // Inch · 25.4 · 10¹² = units: an inch decimal of `decimals` places is
        // n · 254 · 10^(11 − decimals) units.
        let per = 254 * 10i128.pow(11u32.saturating_sub(decimals));
        let n = div_round(self.0 as i128, per);
        let text = format_wide(n, decimals);
        let text = if text.contains('.') { text } else { text + "." };
        (text, Lead((n * per).clamp(0, Self::MAX.0 as i128) as i64))
    }

    /// The lead in inches, exact to 11 decimals (what a reader of inch leads holds), else
    /// rounded there; `false` when rounded.
    pub fn inches(self) -> (String, bool) {
        decimal_of(self.0 as i128 * 10, 254 * 10i128.pow(12), 0, 11)
    }

    /// The lead in millimetres with as few decimals as needed (`1.5`, `1.49979167`).
    pub fn mm(self) -> String {
        format_scaled(self.0, Self::DECIMALS, Trailing::None)
    }

    /// The lead in millimetres, always with a decimal point (`6.`, `1.5`).
    pub fn mm_with_point(self) -> String {
        format_scaled(self.0, Self::DECIMALS, Trailing::Point)
    }

    /// [`Lead::mm_with_point`] appended to `out`.
    pub fn push_mm_with_point(self, out: &mut String) {
        format_scaled_into(out, self.0, Self::DECIMALS, Trailing::Point);
    }
}

impl fmt::Display for Lead {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.mm())
    }
}

/// `x.round()` (half away from zero), without the library call it is on x86-64: below 2⁵²
/// the part cut off by truncating is exact, and compared with ½.
#[inline]
pub fn round_half_away(x: f64) -> f64 {
    if x.abs() < 4_503_599_627_370_496.0 {
        let t = x as i64 as f64;
        let cut = x - t;
        if cut >= 0.5 {
            t + 1.0
        } else if cut <= -0.5 {
            t - 1.0
        } else {
            t.copysign(x)
        }
    } else {
        x.round()
    }
}

/// Integer division rounding half away from zero.
pub fn div_round(num: i128, den: i128) -> i128 {
    debug_assert!(den != 0);
    // i128 division is a library call: numbers well inside i64 (every word of a program)
    // take the machine's, which rounds the same.
    const SMALL: i128 = 1 << 61;
    if num.abs() < SMALL && den.abs() < SMALL {
        let (num, den) = (num as i64, den as i64);
        let (num, den) = if den < 0 { (-num, -den) } else { (num, den) };
        return if num >= 0 {
            (num + den / 2) / den
        } else {
            -((-num + den / 2) / den)
        } as i128;
    }
    let (num, den) = if den < 0 { (-num, -den) } else { (num, den) };
    if num >= 0 {
        (num + den / 2) / den
    } else {
        -((-num + den / 2) / den)
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Trailing {
    None,
    Point,
    /// Every decimal, zeros too (`0.2000`): columns of a table.
    All,
}

fn format_scaled(value: i64, decimals: u32, trailing: Trailing) -> String {
    let mut out = String::with_capacity(24);
    format_scaled_into(&mut out, value, decimals, trailing);
    out
}

/// 10⁰ to 10¹⁸ (the powers an i64 holds), looked up rather than raised (a loop) for every
/// word read and written.
pub(crate) const POWERS_OF_TEN: [i64; 19] = {
    let mut p = [1; 19];
    let mut i = 1;
    while i < p.len() {
        p[i] = p[i - 1] * 10;
        i += 1;
    }
    p
};

/// The largest magnitude [`Decimal::to_scaled`] gives: well inside i64, so that later
/// products (lead · length) cannot overflow.
const SCALED_LIMIT: i128 = 1 << 50;

/// 10⁰ to 10²², each exact in f64.
const EXACT_POWERS_OF_TEN: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

/// [`format_scaled`] appended to `out`.
fn format_scaled_into(out: &mut String, value: i64, decimals: u32, trailing: Trailing) {
    // Written digit by digit (no `format!`), into one buffer appended once: the writers
    // format every coordinate.
    let abs = value.unsigned_abs();
    let scale = POWERS_OF_TEN
        .get(decimals as usize)
        .map_or_else(|| 10u64.pow(decimals), |&p| p as u64);
    let (whole, frac) = (abs / scale, abs % scale);
    let mut buf = [0u8; 64];
    let mut len = usize::from(value < 0);
    buf[0] = b'-';
    len = digits_into(&mut buf, len, whole, 1, false);
    if frac == 0 {
        match trailing {
            Trailing::None => {}
            Trailing::Point => {
                buf[len] = b'.';
                len += 1;
            }
            Trailing::All => {
                let zeros = (decimals as usize).max(1);
                buf[len] = b'.';
                buf[len + 1..len + 1 + zeros].fill(b'0');
                len += 1 + zeros;
            }
        }
    } else {
        buf[len] = b'.';
        len = digits_into(
            &mut buf,
            len + 1,
            frac,
            decimals as usize,
            trailing != Trailing::All,
        );
    }
    push_ascii(out, &buf[..len]);
}

/// Writes `n` in decimal into `buf` at `at`, with at least `width` digits (leading zeros),
/// without its trailing zeros when `trim` is set; where it ends.
fn digits_into(buf: &mut [u8; 64], at: usize, mut n: u64, width: usize, trim: bool) -> usize {
    let mut digits = [b'0'; 20];
    let mut start = digits.len();
    while n > 0 || digits.len() - start < width {
        start -= 1;
        digits[start] = b'0' + (n % 10) as u8;
        n /= 10;
    }
    let mut end = digits.len();
    while trim && end > start + 1 && digits[end - 1] == b'0' {
        end -= 1;
    }
    let len = end - start;
    buf[at..at + len].copy_from_slice(&digits[start..end]);
    at + len
}

/// Appends ASCII bytes (digits, a sign, a point) to `out`.
fn push_ascii(out: &mut String, bytes: &[u8]) {
    // The check cannot fail, and is quicker than a char at a time.
    if let Ok(text) = std::str::from_utf8(bytes) {
        out.push_str(text);
    }
}

/// Appends `n` in decimal with at least `width` digits (leading zeros), without its trailing
/// zeros when `trim` is set.
fn push_digits(out: &mut String, n: u64, width: usize, trim: bool) {
    let mut buf = [0u8; 64];
    let len = digits_into(&mut buf, 0, n, width, trim);
    push_ascii(out, &buf[..len]);
}

/// `n` in decimal appended to `out` (as `write!(out, "{n}")` writes it, without the
/// formatter).
pub(crate) fn push_whole(out: &mut String, n: u64) {
    push_digits(out, n, 1, false);
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
///
/// Packed to 8-byte alignment: an `i128` would align every IR item that holds one to 16
/// bytes, and [`crate::ir::Item`] with it (112 bytes instead of 96).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[repr(C, packed(8))]
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
        // One pass; the digits add up in a u64 while they fit (every word of a real program),
        // then in an i128.
        let (negative, rest) = split_sign(text)?;
        let (mut narrow, mut wide) = (0u64, None::<i128>);
        let (mut digits, mut scale, mut has_point) = (0usize, 0u32, false);
        for b in rest.bytes() {
            match b {
                b'0'..=b'9' => {
                    let d = b - b'0';
                    digits += 1;
                    if has_point {
                        scale = scale.checked_add(1)?;
                    }
                    match wide.as_mut() {
                        None if narrow < 1_000_000_000_000_000_000 => {
                            narrow = narrow * 10 + d as u64
                        }
                        None => wide = Some(narrow as i128 * 10 + d as i128),
                        Some(w) => *w = w.checked_mul(10)?.checked_add(d as i128)?,
                    }
                }
                b'.' if !has_point => has_point = true,
                _ => return None,
            }
        }
        if digits == 0 {
            return None;
        }
        let mantissa = wide.unwrap_or(narrow as i128);
        Some(Decimal {
            mantissa: if negative { -mantissa } else { mantissa },
            scale,
            has_point,
        })
    }

    /// The value as an integer of `10^-decimals` units, exactly, or why not.
    // Inlined: the readers ask it of every G code a few times.
    #[inline]
    pub fn to_scaled(self, decimals: u32) -> Result<i64, NumberError> {
        // The common case in i64: a few digits scaled up by at most 10^9.
        if self.scale <= decimals
            && decimals - self.scale <= 9
            && let Ok(m) = i32::try_from(self.mantissa)
        {
            let value = i64::from(m) * POWERS_OF_TEN[(decimals - self.scale) as usize];
            return if i128::from(value).abs() > SCALED_LIMIT {
                Err(NumberError::TooLarge)
            } else {
                Ok(value)
            };
        }
        self.to_scaled_wide(decimals)
    }

    /// [`Self::to_scaled`] of a value that needs more than an i32's digits or a factor over
    /// 10⁹, or has more decimals than `decimals` (rounding is refused: too precise).
    #[inline(never)]
    fn to_scaled_wide(self, decimals: u32) -> Result<i64, NumberError> {
        const LIMIT: i128 = SCALED_LIMIT;
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
            // As in `div_round`: the machine's division where both fit in an i64.
            let (rem, quot) = match (i64::try_from(self.mantissa), i64::try_from(factor)) {
                (Ok(m), Ok(f)) => ((m % f) as i128, (m / f) as i128),
                _ => (self.mantissa % factor, self.mantissa / factor),
            };
            if rem != 0 {
                return Err(NumberError::TooPrecise { decimals });
            }
            quot
        };
        if value.abs() > LIMIT {
            return Err(NumberError::TooLarge);
        }
        Ok(value as i64)
    }

    /// The value as a length in millimetres: at most four decimals (the 0.0001 mm step).
    pub fn to_length(self) -> Result<Length, NumberError> {
        self.to_scaled(Length::MM_DECIMALS).map(Length::from_steps)
    }

    /// The value as a lead (10⁻¹² mm units), exactly, or why not.
    pub fn to_lead(self) -> Result<Lead, NumberError> {
        let lead = if self.scale <= Lead::DECIMALS {
            10i128
                .checked_pow(Lead::DECIMALS - self.scale)
                .and_then(|f| self.mantissa.checked_mul(f))
                .ok_or(NumberError::TooLarge)?
        } else {
            let factor =
                10i128
                    .checked_pow(self.scale - Lead::DECIMALS)
                    .ok_or(NumberError::TooPrecise {
                        decimals: Lead::DECIMALS,
                    })?;
            if self.mantissa % factor != 0 {
                return Err(NumberError::TooPrecise {
                    decimals: Lead::DECIMALS,
                });
            }
            self.mantissa / factor
        };
        if lead.abs() > Lead::MAX.0 as i128 {
            return Err(NumberError::TooLarge);
        }
        Ok(Lead(lead as i64))
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
        // A mantissa in i64 converts alike without the library call an i128 takes, and the
        // powers of ten to 10²² are exact (as `powi` gives them).
        if let (Ok(m), Some(&p)) = (
            i64::try_from(self.mantissa),
            EXACT_POWERS_OF_TEN.get(self.scale as usize),
        ) {
            return m as f64 / p;
        }
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

    #[test]
    fn rounding_half_away_is_f64_round() {
        let mut values = vec![
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.5,
            2.5,
            -2.5,
            0.49999999999999994,
            -0.49999999999999994,
            0.5000000000000001,
            1.4999999999999998,
            4_503_599_627_370_495.5,
            -4_503_599_627_370_495.5,
            4_503_599_627_370_496.0,
            9.3e18,
            -9.3e18,
            1e300,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::MIN_POSITIVE,
            -f64::MIN_POSITIVE,
            f64::EPSILON,
        ];
        // Every quarter step around the grid's values, and values from a walk over the range.
        values.extend((-40..=40).map(|i| i as f64 * 0.25));
        let mut x = 1e-9f64;
        while x < 1e17 {
            values.extend([x, -x, x + 0.5, -x - 0.5, (x * 10_000.0).floor() + 0.5]);
            x *= 1.37;
        }
        for v in values {
            assert_eq!(
                super::round_half_away(v).to_bits(),
                v.round().to_bits(),
                "{v:e}"
            );
        }
        assert!(super::round_half_away(f64::NAN).is_nan());
    }

    #[test]
    fn a_decimal_as_f64_is_the_mantissa_over_the_power_of_ten() {
        for (i, &p) in super::EXACT_POWERS_OF_TEN.iter().enumerate() {
            assert_eq!(p, 10f64.powi(i as i32), "10^{i}");
        }
        let mantissas = [
            0,
            1,
            -1,
            15,
            -1_651_090_548_698,
            123_456_789_012_345_678,
            i128::from(i64::MAX),
            i128::from(i64::MIN),
            i128::from(i64::MAX) + 1,
            (1 << 70) + 12_345,
            -(1 << 90),
        ];
        for mantissa in mantissas {
            for scale in 0..30 {
                let d = super::Decimal {
                    mantissa,
                    scale,
                    has_point: true,
                };
                let by_powi = mantissa as f64 / 10f64.powi(scale as i32);
                assert_eq!(
                    d.to_f64().to_bits(),
                    by_powi.to_bits(),
                    "{mantissa} e-{scale}"
                );
            }
        }
    }

    /// The formatting as `format!` writes it: what `format_scaled` must equal.
    fn format_reference(value: i64, decimals: u32, trailing: Trailing) -> String {
        let scale = 10i64.pow(decimals);
        let sign = if value < 0 { "-" } else { "" };
        let (whole, frac) = (
            value.unsigned_abs() / scale as u64,
            value.unsigned_abs() % scale as u64,
        );
        if frac == 0 {
            return match trailing {
                Trailing::None => format!("{sign}{whole}"),
                Trailing::Point => format!("{sign}{whole}."),
                Trailing::All => format!("{sign}{whole}.{:0width$}", 0, width = decimals as usize),
            };
        }
        let frac = format!("{frac:0width$}", width = decimals as usize);
        if trailing == Trailing::All {
            return format!("{sign}{whole}.{frac}");
        }
        format!("{sign}{whole}.{}", frac.trim_end_matches('0'))
    }

    /// Decimal::parse as it was written first (split at the point, i128 throughout): what
    /// the one-pass form must equal.
    fn parse_reference(text: &str) -> Option<Decimal> {
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
        Some(Decimal {
            mantissa: if negative { -mantissa } else { mantissa },
            scale: frac.len() as u32,
            has_point,
        })
    }

    #[test]
    fn scaling_agrees_with_exact_arithmetic() {
        // The reference: the value times 10^decimals in i128, exact or refused.
        fn reference(d: Decimal, decimals: u32) -> Result<i64, NumberError> {
            let (m, scale) = (d.mantissa, d.scale as i64 - decimals as i64);
            let value = if scale <= 0 {
                10i128
                    .checked_pow((-scale) as u32)
                    .and_then(|f| m.checked_mul(f))
                    .ok_or(NumberError::TooLarge)?
            } else {
                let f = 10i128
                    .checked_pow(scale as u32)
                    .ok_or(NumberError::TooLarge)?;
                if m % f != 0 {
                    return Err(NumberError::TooPrecise { decimals });
                }
                m / f
            };
            if value.abs() > 1 << 50 {
                return Err(NumberError::TooLarge);
            }
            Ok(value as i64)
        }
        for text in [
            "0",
            "-0",
            "1",
            "-1.5",
            "26.618",
            "2147483647",
            "-2147483648",
            "2147483648",
            "1125899906842624",
            "112589990684.2624",
            "112589990684.2625",
            "0.00001",
            "12.34567",
            "999999999999999999.9",
            "-.0001",
            "1e",
            "123456789012345678901234567890",
        ] {
            let Some(d) = Decimal::parse(text) else {
                continue;
            };
            for decimals in [0, 3, 4, 6, 9, 12, 20, 40] {
                assert_eq!(
                    d.to_scaled(decimals),
                    reference(d, decimals),
                    "{text} at {decimals}"
                );
            }
        }
    }

    #[test]
    fn numbers_are_read_as_the_first_form_read_them() {
        let long = "9".repeat(38);
        let longer = "9".repeat(39);
        let fixed = [
            "",
            "-",
            "+",
            ".",
            "-.",
            "5",
            "-5",
            "+5",
            "5.",
            ".5",
            "-.5",
            "00120.000",
            "-00120.000",
            "1.2.3",
            "1..",
            "..1",
            "1-",
            "12a",
            "a",
            " 1",
            "1 ",
            "999999999999999999",
            "1000000000000000000",
            "9999999999999999999",
            "18446744073709551616",
            "-18446744073709551617.5",
            long.as_str(),
            longer.as_str(),
            "0.0000000000000000000001",
        ];
        for text in fixed {
            assert_eq!(Decimal::parse(text), parse_reference(text), "{text:?}");
        }
        // Every string of up to 4 characters from the number alphabet.
        let alphabet = ['0', '1', '9', '.', '-', '+', 'x'];
        let mut texts = vec![String::new()];
        for _ in 0..4 {
            let next: Vec<String> = texts
                .iter()
                .flat_map(|t| alphabet.iter().map(move |c| format!("{t}{c}")))
                .collect();
            for text in &next {
                assert_eq!(Decimal::parse(text), parse_reference(text), "{text:?}");
            }
            texts = next;
        }
    }

    #[test]
    fn rounded_division_is_the_same_in_i64_and_i128() {
        let reference = |num: i128, den: i128| {
            let (num, den) = if den < 0 { (-num, -den) } else { (num, den) };
            if num >= 0 {
                (num + den / 2) / den
            } else {
                -((-num + den / 2) / den)
            }
        };
        let values: [i128; 14] = [
            0,
            1,
            -1,
            2,
            -2,
            3,
            5,
            -5,
            7,
            10_000,
            -254_000,
            1 << 40,
            (1 << 61) - 1,
            -(1 << 61) + 1,
        ];
        for num in values.iter().chain(&[1 << 61, 1 << 62, -(1 << 70)]) {
            for den in [
                1,
                -1,
                2,
                -2,
                3,
                7,
                -10,
                10_000,
                254_000,
                (1 << 61) - 1,
                1 << 61,
                1 << 65,
            ] {
                assert_eq!(div_round(*num, den), reference(*num, den), "{num} / {den}");
            }
        }
    }

    #[test]
    fn numbers_are_written_as_format_writes_them() {
        let values = [
            0,
            1,
            -1,
            5,
            10,
            100,
            1000,
            10000,
            12345,
            -12345,
            120000,
            -5000,
            99999,
            100001,
            i64::MAX,
            i64::MIN,
            i64::MIN + 1,
            7,
            70,
            700,
            1_000_000_007,
        ];
        for value in values {
            for decimals in [0, 1, 3, 4, 5, 6] {
                for trailing in [Trailing::None, Trailing::Point, Trailing::All] {
                    assert_eq!(
                        format_scaled(value, decimals, trailing),
                        format_reference(value, decimals, trailing),
                        "{value} {decimals} {trailing:?}"
                    );
                }
            }
        }
    }
    use super::*;

    #[test]
    fn parses_the_seed_spellings() {
        let d = Decimal::parse("-00120.000").unwrap();
        assert_eq!((d.mantissa, d.scale, d.has_point), (-120000, 3, true));
        assert_eq!(d.to_length(), Ok(Length::from_steps(-1_200_000)));
        assert_eq!(Decimal::parse("Z").map(|d| d.mantissa), None);
        assert!(!Decimal::parse("12").unwrap().has_point);
        assert_eq!(
            Decimal::parse("12.").unwrap().to_length(),
            Ok(Length::from_mm(12))
        );
        assert_eq!(
            Decimal::parse(".5").unwrap().to_length(),
            Ok(Length::from_steps(5000))
        );
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
            Ok(Length::from_steps(10_000))
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
        assert_eq!(Length::from_steps(-1_000_000).mm(), "-100");
        assert_eq!(Length::from_steps(717_980).mm(), "71.798");
        assert_eq!(Length::from_steps(30_000).mm_with_point(), "3.");
        assert_eq!(Length::from_steps(-5).mm(), "-0.0005");
        assert_eq!(Angle(12_500).deg(), "12.5");
    }

    #[test]
    fn leads_are_exact_to_twelve_decimals() {
        let k = Decimal::parse("1.23456").unwrap().to_lead().unwrap();
        assert_eq!(k, Lead(1_234_560_000_000));
        assert_eq!(k.mm(), "1.23456");
        assert_eq!(k.exact_length(), None);
        assert_eq!(k.in_units(4), (12_346, false));
        assert_eq!(
            Lead::from_length(Length::from_steps(15_000)).in_units(4),
            (15_000, true)
        );
        assert_eq!(
            Lead::from_length(Length::from_steps(15_000)).mm_with_point(),
            "1.5"
        );
        assert_eq!(
            Lead::from_length(Length::from_steps(60_000)).mm_with_point(),
            "6."
        );
        assert_eq!(
            Decimal::parse("0.0000000000001").unwrap().to_lead(),
            Err(NumberError::TooPrecise { decimals: 12 })
        );
        assert_eq!(
            Decimal::parse("2000000").unwrap().to_lead(),
            Err(NumberError::TooLarge)
        );
        // K1.5 along Ø30 → Ø40 over 300 mm of Z: the Z lead 1.5·300/√(300² + 5²).
        let z = Lead::from_mm_f64(1.5 * 300.0 / 300f64.hypot(5.0)).unwrap();
        assert_eq!(z.mm(), "1.499791710059");
        // On the 0.0001 grid (1.4998) it would drift 0.0017 mm over the thread; here it does
        // not drift at all at that resolution.
        let grid = Lead::from_length(Length::from_steps(14_998));
        assert_eq!(z.drift(grid, Length::from_mm(300)), Length::from_steps(17));
        // A start angle of 180° at lead 1.5 is 0.75 mm; a runout of 7 tenths of 1.5 is 1.05.
        let l = Lead::from_length(Length::from_steps(15_000));
        assert_eq!(l.of_angle(Angle::from_deg(180)), Length::from_steps(7_500));
        assert_eq!(l.length_times(7, 10), Length::from_steps(10_500));
    }

    #[test]
    fn rounds_half_away_from_zero() {
        assert_eq!(div_round(5, 2), 3);
        assert_eq!(div_round(-5, 2), -3);
        assert_eq!(div_round(4, 3), 1);
        assert_eq!(Length::from_steps(10).mul_div(1, 4), Length::from_steps(3));
        assert_eq!(Length::from_mm_f64(7.798_072_7), Length::from_steps(77_981));
    }
}

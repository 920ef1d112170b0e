//! LinuxCNC's angle conversions, bit for bit: `interp_execute.cc` turns degrees into
//! radians as `(x * M_PIl) / 180.0` and back as `(a * 180.0) / M_PIl`, in `long double`
//! (x86's 80-bit format: a 64-bit mantissa, each operation rounded to it, half to even),
//! and stores a degree result in a `double`; the two operations are done here on integers,
//! rounded as the x87 rounds them. (Its COS, SIN and TAN then take the `long double`
//! argument, `cosl`: for an angle under [`TRIG_LIMIT`] the nearest `double` gives the same
//! value to far below the grid; a larger one is refused.)

/// The largest angle (degrees) whose COS, SIN or TAN ncthread computes as LinuxCNC does:
/// there, the radians' rounding to a `double` (LinuxCNC keeps 11 more bits) moves the result
/// by less than 10⁻⁷ of it. `COS[1E22]` is another number in the two precisions.
pub const TRIG_LIMIT: f64 = 1e9;

/// `M_PIl`: π rounded to 64 bits, as `PI_MANTISSA · 2^-62`.
const PI_MANTISSA: u128 = 0xC90F_DAA2_2168_C235;
const PI_EXP: i32 = -62;

/// A finite positive number `m · 2^e`.
#[derive(Clone, Copy, Debug)]
struct Num {
    m: u128,
    e: i32,
}

/// `m` (with `sticky`: more bits below it that are not all zero) rounded to `bits`
/// significant bits, half to even.
fn round(n: Num, sticky: bool, bits: u32) -> Num {
    let width = 128 - n.m.leading_zeros();
    if width <= bits {
        return n;
    }
    let cut = width - bits;
    let kept = n.m >> cut;
    let rest = n.m & ((1u128 << cut) - 1);
    let half = 1u128 << (cut - 1);
    let up = rest > half || (rest == half && (sticky || kept & 1 == 1));
    let m = kept + u128::from(up);
    Num {
        m,
        e: n.e + cut as i32,
    }
}

/// `a / b` to 64 significant bits (x87 division), `a` and `b` positive.
fn divide(a: Num, b: Num) -> Num {
    // The divisor widened to 64 bits, the dividend to 126: the quotient has at least 62
    // bits from the first step of long division and 64 more from the second (each
    // remainder stays below the divisor, under 2^64).
    let b_shift = 64 - (128 - b.m.leading_zeros()) as i32;
    let b = Num {
        m: b.m << b_shift,
        e: b.e - b_shift,
    };
    let a_width = 128 - a.m.leading_zeros();
    let shift = 126 - a_width as i32;
    let num = a.m << shift;
    let q_hi = num / b.m;
    let r = num % b.m;
    let q_lo = (r << 64) / b.m;
    let sticky = !(r << 64).is_multiple_of(b.m);
    let q = Num {
        m: (q_hi << 64) | q_lo,
        e: a.e - shift - b.e - 64,
    };
    round(q, sticky, 64)
}

fn to_num(x: f64) -> Num {
    let bits = x.abs().to_bits();
    let exp = ((bits >> 52) & 0x7ff) as i32;
    let frac = u128::from(bits & ((1 << 52) - 1));
    if exp == 0 {
        Num { m: frac, e: -1074 }
    } else {
        Num {
            m: frac | (1 << 52),
            e: exp - 1075,
        }
    }
}

/// The `double` nearest `n` (rounded to 53 bits, half to even), or `None` outside the range
/// of normal doubles (the caller falls back on `f64`).
fn to_f64(n: Num) -> Option<f64> {
    let r = round(n, false, 53);
    let width = 128 - r.m.leading_zeros() as i32;
    let exp = r.e + width - 1;
    if !(-1022..=1023).contains(&exp) {
        return None;
    }
    // m < 2^53 exactly: the conversion and the power of two are exact.
    Some(r.m as f64 * 2f64.powi(r.e))
}

fn signed(x: f64, v: Option<f64>) -> Option<f64> {
    v.map(|v| if x < 0.0 { -v } else { v })
}

/// `(x * M_PIl) / 180.0` stored in a `double`: degrees to radians as LinuxCNC turns them.
pub fn radians(x: f64) -> f64 {
    if x == 0.0 || !x.is_finite() {
        return x.to_radians();
    }
    let n = to_num(x);
    let product = round(
        Num {
            m: n.m * PI_MANTISSA,
            e: n.e + PI_EXP,
        },
        false,
        64,
    );
    let q = divide(product, Num { m: 180, e: 0 });
    signed(x, to_f64(q)).unwrap_or_else(|| x.to_radians())
}

/// `(a * 180.0) / M_PIl` stored in a `double`: radians to degrees as LinuxCNC turns them.
pub fn degrees(a: f64) -> f64 {
    if a == 0.0 || !a.is_finite() {
        return a.to_degrees();
    }
    let n = to_num(a);
    // 53 bits times 180 (8 bits): exact in 64.
    let product = round(
        Num {
            m: n.m * 180,
            e: n.e,
        },
        false,
        64,
    );
    let q = divide(
        product,
        Num {
            m: PI_MANTISSA,
            e: PI_EXP,
        },
    );
    signed(a, to_f64(q)).unwrap_or_else(|| a.to_degrees())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Bits printed by a C program on x86-64 (gcc, glibc): `(x*M_PIl)/180.0` and
    /// `(x*180.0)/M_PIl` stored in doubles.
    #[test]
    fn as_the_x87_computes_them() {
        let cases: [(f64, u64, u64); 4] = [
            (1e22, 0x4422ec430581f40c, 0x44de5506ad08bee2),
            (60.0, 0x3ff0c152382d7366, 0x40aadb7e58bd85d8),
            (0.5, 0x3f81df46a2529d39, 0x403ca5dc1a63c1f8),
            (1.2345678901234567, 0x3f96107d1d8f84ef, 0x4051af12eadab474),
        ];
        for (x, r, d) in cases {
            assert_eq!(radians(x).to_bits(), r, "radians({x})");
            assert_eq!(degrees(x).to_bits(), d, "degrees({x})");
            assert_eq!(radians(-x).to_bits(), r | 1 << 63, "radians(-{x})");
        }
    }
}

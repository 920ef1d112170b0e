//! LinuxCNC's expressions (`interp_read.cc`: `read_real_expression`, `read_real_value`,
//! `execute_binary`, `execute_unary`): parameters, bracketed expressions with LinuxCNC's
//! precedence, and its functions. Values are f64 as in LinuxCNC; a value that becomes a
//! coordinate is rounded once onto the IR's grid by the front end.

use super::long_double;

use std::ops::Range;

/// A binary operator, in LinuxCNC's precedence classes (`precedence()`): `**` 6; `*`, `/`,
/// `MOD` 5; `+`, `-` 4; comparisons 3; `AND`, `OR`, `XOR` 2. All associate to the left.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Op {
    Power,
    Times,
    Divide,
    Modulo,
    Plus,
    Minus,
    Eq,
    Ne,
    Gt,
    Ge,
    Lt,
    Le,
    And,
    Or,
    Xor,
}

impl Op {
    pub fn parse(text: &str) -> Option<Op> {
        Some(match text.to_ascii_lowercase().as_str() {
            "**" => Op::Power,
            "*" => Op::Times,
            "/" => Op::Divide,
            "mod" => Op::Modulo,
            "+" => Op::Plus,
            "-" => Op::Minus,
            "eq" => Op::Eq,
            "ne" => Op::Ne,
            "gt" => Op::Gt,
            "ge" => Op::Ge,
            "lt" => Op::Lt,
            "le" => Op::Le,
            "and" => Op::And,
            "or" => Op::Or,
            "xor" => Op::Xor,
            _ => return None,
        })
    }

    pub fn precedence(self) -> u8 {
        match self {
            Op::Power => 6,
            Op::Times | Op::Divide | Op::Modulo => 5,
            Op::Plus | Op::Minus => 4,
            Op::Eq | Op::Ne | Op::Gt | Op::Ge | Op::Lt | Op::Le => 3,
            Op::And | Op::Or | Op::Xor => 2,
        }
    }
}

/// A one-argument function.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Func {
    Abs,
    Acos,
    Asin,
    Cos,
    Exp,
    Fix,
    Fup,
    Ln,
    Round,
    Sin,
    Sqrt,
    Tan,
}

impl Func {
    pub fn parse(text: &str) -> Option<Func> {
        Some(match text.to_ascii_lowercase().as_str() {
            "abs" => Func::Abs,
            "acos" => Func::Acos,
            "asin" => Func::Asin,
            "cos" => Func::Cos,
            "exp" => Func::Exp,
            "fix" => Func::Fix,
            "fup" => Func::Fup,
            "ln" => Func::Ln,
            "round" => Func::Round,
            "sin" => Func::Sin,
            "sqrt" => Func::Sqrt,
            "tan" => Func::Tan,
            _ => return None,
        })
    }
}

/// Which parameter: a number (computed: `#5`, `##1`, `#[1 + 2]`) or a name (lower case,
/// blanks removed, as LinuxCNC keeps it).
#[derive(Clone, Debug, PartialEq)]
pub enum Param {
    Numbered(Box<Expr>),
    Named(String),
}

/// An expression node with the byte range it was read from (for the caret of an error).
#[derive(Clone, Debug, PartialEq)]
pub struct Expr {
    pub kind: ExprKind,
    pub range: Range<usize>,
}

#[derive(Clone, Debug, PartialEq)]
pub enum ExprKind {
    Number(f64),
    Param(Param),
    Negate(Box<Expr>),
    Unary(Func, Box<Expr>),
    /// `ATAN[y]/[x]`: degrees.
    Atan(Box<Expr>, Box<Expr>),
    /// `EXISTS[#<name>]`
    Exists(String),
    Binary(Op, Box<Expr>, Box<Expr>),
}

/// Why an expression has no value, in LinuxCNC's words where it has them, and where.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct EvalError {
    pub message: String,
    pub help: &'static str,
    pub range: Range<usize>,
}

/// What an expression reads: parameters, by the rules of the program's state.
pub trait Env {
    /// `#n`. `n` is whole and checked by the caller to be LinuxCNC's range.
    fn numbered(&self, n: usize, range: &Range<usize>) -> Result<f64, EvalError>;
    /// `#<name>` (lower case).
    fn named(&self, name: &str, range: &Range<usize>) -> Result<f64, EvalError>;
    /// `EXISTS[#<name>]`
    fn exists(&self, name: &str) -> bool;
}

/// The highest parameter number LinuxCNC has (`RS274NGC_MAX_PARAMETERS` − 1).
pub const MAX_PARAMETER: usize = 5601;

/// LinuxCNC's tolerance for EQ and NE (`TOLERANCE_EQUAL`); LT, LE, GT and GE are exact.
/// **\[evidence\]** the rs274 ncthread is checked with (2.9.0~pre1): `[1 EQ 1.00009]` is 1,
/// `[1.0000001 LE 1]` is 0. (Later LinuxCNC sources have 1e-6 and a tolerant LE/GE.)
const TOLERANCE_EQUAL: f64 = 0.0001;

/// The parameter number a value names: whole within 0.0001 (LinuxCNC rounds), 1 … 5601.
pub fn parameter_number(value: f64, range: &Range<usize>) -> Result<usize, EvalError> {
    let n = value.round();
    if (value - n).abs() > 0.0001 {
        return Err(EvalError {
            message: format!("parameter number {value} is not a whole number"),
            help: "a numbered parameter is #1 … #5601",
            range: range.clone(),
        });
    }
    if !(1.0..=MAX_PARAMETER as f64).contains(&n) {
        return Err(EvalError {
            message: format!("Parameter number out of range: #{n}"),
            help: "a numbered parameter is #1 … #5601",
            range: range.clone(),
        });
    }
    Ok(n as usize)
}

impl Expr {
    fn fail(&self, message: String, help: &'static str) -> EvalError {
        EvalError {
            message,
            help,
            range: self.range.clone(),
        }
    }

    /// The expression's value (LinuxCNC's `read_real_expression`): operands first, left
    /// to right, then the function or operation; a value that is not finite is refused.
    pub fn eval(&self, env: &dyn Env) -> Result<f64, EvalError> {
        let value = match &self.kind {
            ExprKind::Number(v) => *v,
            ExprKind::Param(Param::Numbered(index)) => {
                let n = parameter_number(index.eval(env)?, &self.range)?;
                env.numbered(n, &self.range)?
            }
            ExprKind::Param(Param::Named(name)) => env.named(name, &self.range)?,
            ExprKind::Negate(e) => -e.eval(env)?,
            ExprKind::Exists(name) => f64::from(u8::from(env.exists(name))),
            ExprKind::Atan(y, x) => {
                let (y, x) = (y.eval(env)?, x.eval(env)?);
                long_double::degrees(y.atan2(x))
            }
            ExprKind::Unary(f, e) => {
                let v = e.eval(env)?;
                self.unary(*f, v)?
            }
            ExprKind::Binary(op, a, b) => {
                let (a, b) = (a.eval(env)?, b.eval(env)?);
                self.binary_value(*op, a, b)?
            }
        };
        if value.is_finite() {
            Ok(value)
        } else {
            Err(self.fail(
                format!("the value is not a finite number ({value})"),
                "check the expression's operands",
            ))
        }
    }

    /// A function of one argument (LinuxCNC's `execute_unary`), refusing what it refuses:
    /// ACOS and ASIN outside −1 … 1, LN of 0 or less, SQRT of less than 0.
    pub(crate) fn unary(&self, f: Func, v: f64) -> Result<f64, EvalError> {
        Ok(match f {
            Func::Abs => v.abs(),
            Func::Acos | Func::Asin if !(-1.0..=1.0).contains(&v) => {
                let name = if f == Func::Acos { "ACOS" } else { "ASIN" };
                return Err(self.fail(
                    format!(
                        "Argument to {} out of range ({v})",
                        name.to_ascii_lowercase()
                    ),
                    "the argument of ACOS and ASIN is −1 … 1",
                ));
            }
            Func::Acos => long_double::degrees(v.acos()),
            Func::Asin => long_double::degrees(v.asin()),
            Func::Cos | Func::Sin | Func::Tan if v.abs() >= long_double::TRIG_LIMIT => {
                return Err(self.fail(
                    format!("an angle of {v}° for {}: LinuxCNC computes its radians in 80-bit precision, which a 64-bit float does not reproduce past 1e9°", format!("{f:?}").to_ascii_uppercase()),
                    "reduce the angle below 1e9° (a turn is 360°)",
                ));
            }
            Func::Cos => long_double::radians(v).cos(),
            Func::Sin => long_double::radians(v).sin(),
            Func::Tan => long_double::radians(v).tan(),
            Func::Exp => v.exp(),
            Func::Fix => v.floor(),
            Func::Fup => v.ceil(),
            Func::Ln if v <= 0.0 => {
                return Err(self.fail(
                    format!("Zero or negative argument to ln ({v})"),
                    "LN takes a positive number",
                ));
            }
            Func::Ln => v.ln(),
            // `(double)(int)(v ± 0.5)`: half away from zero, the sum rounded first.
            Func::Round => {
                let t = if v < 0.0 { v - 0.5 } else { v + 0.5 };
                if t.abs() >= 2_147_483_648.0 {
                    -2_147_483_648.0
                } else {
                    t.trunc()
                }
            }
            Func::Sqrt if v < 0.0 => {
                return Err(self.fail(
                    format!("Negative argument to sqrt ({v})"),
                    "SQRT takes 0 or more",
                ));
            }
            Func::Sqrt => v.sqrt(),
        })
    }

    /// An operation of two operands (LinuxCNC's `execute_binary1` and `execute_binary2`),
    /// refusing what it refuses: a negative base to a fractional power, a division by 0,
    /// MOD 0.
    pub(crate) fn binary_value(&self, op: Op, a: f64, b: f64) -> Result<f64, EvalError> {
        let truth = |t: bool| f64::from(u8::from(t));
        Ok(match op {
            Op::Power => {
                if a < 0.0 && b.floor() != b {
                    return Err(self.fail(
                        format!("Attempt to raise negative to non integer power ({a} ** {b})"),
                        "a negative base takes only a whole exponent",
                    ));
                }
                a.powf(b)
            }
            Op::Times => a * b,
            Op::Modulo if b == 0.0 => {
                return Err(self.fail(
                    "Calculation resulted in 'not a number' (MOD 0)".into(),
                    "check the divisor's parameters: it is 0 here",
                ));
            }
            Op::Divide if b == 0.0 => {
                return Err(self.fail(
                    "Attempt to divide by zero".into(),
                    "check the divisor's parameters: it is 0 here",
                ));
            }
            Op::Divide => a / b,
            // fmod, made positive as LinuxCNC does.
            Op::Modulo => {
                let r = a % b;
                if r < 0.0 { r + b.abs() } else { r }
            }
            Op::Plus => a + b,
            Op::Minus => a - b,
            Op::Eq => truth((a - b).abs() < TOLERANCE_EQUAL),
            Op::Ne => truth((a - b).abs() >= TOLERANCE_EQUAL),
            Op::Gt => truth(a > b),
            Op::Ge => truth(a >= b),
            Op::Lt => truth(a < b),
            Op::Le => truth(a <= b),
            Op::And => truth(a != 0.0 && b != 0.0),
            Op::Or => truth(a != 0.0 || b != 0.0),
            Op::Xor => truth((a != 0.0) != (b != 0.0)),
        })
    }

    /// Builds `operands[0] op[0] operands[1] …` by LinuxCNC's precedence, left to right.
    pub fn binary(operands: Vec<Expr>, ops: Vec<Op>) -> Expr {
        let mut values: Vec<Expr> = Vec::new();
        let mut pending: Vec<Op> = Vec::new();
        let reduce = |values: &mut Vec<Expr>, op: Op| {
            let b = values.pop().expect("two operands");
            let a = values.pop().expect("two operands");
            let range = a.range.start..b.range.end;
            values.push(Expr {
                kind: ExprKind::Binary(op, Box::new(a), Box::new(b)),
                range,
            });
        };
        let mut operands = operands.into_iter();
        if let Some(first) = operands.next() {
            values.push(first);
        }
        for (op, operand) in ops.into_iter().zip(operands) {
            while let Some(&top) = pending.last() {
                if top.precedence() >= op.precedence() {
                    pending.pop();
                    reduce(&mut values, top);
                } else {
                    break;
                }
            }
            pending.push(op);
            values.push(operand);
        }
        while let Some(op) = pending.pop() {
            reduce(&mut values, op);
        }
        values.pop().expect("an expression has an operand")
    }
}

/// A number as a word's decimal value: up to 12 decimals (enough to keep a lead exact to
/// the IR's 10⁻¹² mm), trailing zeros removed.
pub fn to_decimal(v: f64) -> Option<crate::fixed::Decimal> {
    if !v.is_finite() || v.abs() >= 1e15 {
        return None;
    }
    // The common value (a computed coordinate, `30 - 2 · 0.25`) is the double nearest a
    // number of four decimals: below 1024 it lies within half an ulp (< 10⁻¹³) of it, so
    // that `{v:.12}` writes that number's digits; made without formatting and parsing.
    if v.abs() < 1024.0 {
        let m = crate::fixed::round_half_away(v * 1e4);
        if m / 1e4 == v {
            let (mut mantissa, mut scale) = (m as i128, 4);
            while scale > 0 && mantissa % 10 == 0 {
                mantissa /= 10;
                scale -= 1;
            }
            return Some(crate::fixed::Decimal {
                mantissa,
                scale,
                has_point: true,
            });
        }
    }
    let text = format!("{v:.12}");
    let text = text.trim_end_matches('0');
    crate::fixed::Decimal::parse(text)
}

#[cfg(test)]
mod tests {
    use super::*;

    struct NoParams;
    impl Env for NoParams {
        fn numbered(&self, n: usize, _: &Range<usize>) -> Result<f64, EvalError> {
            Ok(n as f64 * 10.0)
        }
        fn named(&self, name: &str, range: &Range<usize>) -> Result<f64, EvalError> {
            match name {
                "a" => Ok(2.0),
                _ => Err(EvalError {
                    message: format!("Named parameter #<{name}> not defined"),
                    help: "",
                    range: range.clone(),
                }),
            }
        }
        fn exists(&self, name: &str) -> bool {
            name == "a"
        }
    }

    fn num(v: f64) -> Expr {
        Expr {
            kind: ExprKind::Number(v),
            range: 0..1,
        }
    }

    #[test]
    fn precedence_and_left_association_are_linuxcnc_s() {
        let e = |vals: &[f64], ops: &[Op]| {
            Expr::binary(vals.iter().map(|&v| num(v)).collect(), ops.to_vec())
                .eval(&NoParams)
                .unwrap()
        };
        assert_eq!(
            e(&[2.0, 3.0, 4.0, 2.0], &[Op::Plus, Op::Times, Op::Power]),
            50.0
        );
        assert_eq!(e(&[10.0, 4.0, 3.0], &[Op::Minus, Op::Minus]), 3.0);
        assert_eq!(e(&[2.0, 3.0, 2.0], &[Op::Power, Op::Power]), 64.0);
        assert_eq!(e(&[1.0, 2.0, 3.0], &[Op::Plus, Op::Eq]), 1.0);
        assert_eq!(e(&[-7.0, 3.0], &[Op::Modulo]), 2.0);
        assert_eq!(e(&[1.0, 0.0], &[Op::Xor]), 1.0);
        assert_eq!(e(&[1.00009, 1.0], &[Op::Eq]), 1.0);
        assert_eq!(e(&[1.00011, 1.0], &[Op::Eq]), 0.0);
        assert_eq!(e(&[1.0, 1.0000001], &[Op::Lt]), 1.0);
        assert_eq!(e(&[1.0000001, 1.0], &[Op::Le]), 0.0);
        assert_eq!(e(&[1.0, 1.0, 0.0], &[Op::Or, Op::And]), 0.0);
    }

    #[test]
    fn refuses_what_linuxcnc_refuses() {
        let bin = |a, op, b| Expr::binary(vec![num(a), num(b)], vec![op]).eval(&NoParams);
        assert!(
            bin(1.0, Op::Divide, 0.0)
                .unwrap_err()
                .message
                .contains("divide by zero")
        );
        assert!(
            bin(-8.0, Op::Power, 0.5)
                .unwrap_err()
                .message
                .contains("negative")
        );
        let f = |f, v| {
            Expr {
                kind: ExprKind::Unary(f, Box::new(num(v))),
                range: 0..1,
            }
            .eval(&NoParams)
        };
        assert!(f(Func::Sqrt, -1.0).is_err());
        assert!(f(Func::Ln, 0.0).is_err());
        assert!(f(Func::Acos, 1.5).is_err());
        assert_eq!(f(Func::Round, -2.5).unwrap(), -3.0);
        assert_eq!(f(Func::Fix, -2.5).unwrap(), -3.0);
        assert_eq!(f(Func::Fup, 2.1).unwrap(), 3.0);
        assert!((f(Func::Sin, 30.0).unwrap() - 0.5).abs() < 1e-12);
    }

    #[test]
    fn decimals_of_computed_values() {
        assert_eq!(to_decimal(0.1 + 0.2).unwrap().to_string(), "0.3");
        assert_eq!(to_decimal(2.0).unwrap().to_string(), "2.");
        assert_eq!(
            to_decimal(-1.0 / 3.0).unwrap().to_string(),
            "-0.333333333333"
        );
        assert!(to_decimal(f64::NAN).is_none());
        // Formatted and read back, as the values a program computes, in and out of the
        // quick path.
        let by_text = |v: f64| {
            let text = format!("{v:.12}");
            crate::fixed::Decimal::parse(text.trim_end_matches('0'))
        };
        let mut values: Vec<f64> = (-20_000..=20_000).map(|k| f64::from(k) * 0.0125).collect();
        values.extend((0..2_000).map(|k| 30.0 - f64::from(k) * 0.25));
        values.extend((-300..=300).map(|k| f64::from(k) / 3.0));
        values.extend([
            0.0,
            -0.0,
            1e-13,
            -1e-13,
            0.00005,
            1023.9999,
            1024.0,
            1024.0001,
            999.99995,
            0.1 + 0.2,
            -1023.99995,
            5e-5,
            4.99999e-5,
            1e14,
            -1e14,
        ]);
        for v in values {
            assert_eq!(to_decimal(v), by_text(v), "{v:e}");
        }
    }
}

//! A FANUC custom macro B line: its statement (an assignment, `IF`, `GOTO`, `WHILE … DO`,
//! `END`) or its words with values that are numbers, variables or `[ ]` expressions; and
//! the expressions' values by FANUC's rules for a vacant variable.
//!
//! The expression tree and the operators' arithmetic are LinuxCNC's (`iso/expr.rs`) where
//! the rules agree; FANUC differs in precedence (`*` `/` `AND` `MOD` above `+` `-` `OR`
//! `XOR`, comparisons only at the top), in FIX and FUP (towards and away from zero), in
//! ATAN's range (0 … 360°) and in the vacant value (`#0`).

use std::ops::Range;

pub use crate::dialect::iso::expr::Expr;
use crate::dialect::iso::expr::{ExprKind, Func, Op, Param};

/// A word's value: as written, or computed.
#[derive(Clone, Debug)]
pub enum Value {
    Number(crate::fixed::Decimal),
    Expr(Expr),
}

#[derive(Clone, Debug)]
pub struct MWord {
    pub letter: char,
    pub value: Value,
    pub range: Range<usize>,
}

/// The variable an assignment sets: `#5` or `#[#1+1]`.
#[derive(Clone, Debug)]
pub struct Target {
    pub index: Expr,
    pub range: Range<usize>,
}

#[derive(Clone, Debug)]
pub enum Stmt {
    /// A block of words (possibly none: a comment or a block number).
    Words(Vec<MWord>),
    Assign(Target, Expr),
    IfGoto(Expr, Expr),
    IfThen(Expr, Target, Expr),
    Goto(Expr),
    /// `WHILE [c] DO m`, or a bare `DO m` (an endless loop: no condition).
    While(Option<Expr>, u8),
    End(u8),
}

/// One line of a macro program.
#[derive(Clone, Debug)]
pub struct MLine {
    pub number: Option<u32>,
    pub block_delete: Option<Range<usize>>,
    pub comment: Option<String>,
    pub delimiter: bool,
    pub code_range: Range<usize>,
    pub stmt: Stmt,
    /// Where the statement's keyword stands (for the caret of a control-flow error).
    pub stmt_range: Range<usize>,
}

impl MLine {
    pub fn word(&self, letter: char) -> Option<&MWord> {
        match &self.stmt {
            Stmt::Words(w) => w.iter().find(|w| w.letter == letter),
            _ => None,
        }
    }
}

/// Why a line cannot be read: where and what.
#[derive(Clone, Debug)]
pub struct Error {
    pub offset: usize,
    pub message: String,
}

struct Lexer<'a> {
    text: &'a str,
    b: &'a [u8],
    pos: usize,
    /// Operators and nested brackets so far: an expression beyond [`MAX_NODES`] is refused
    /// (FANUC nests brackets 5 deep; the bound keeps the recursion's stack small).
    nodes: usize,
}

const MAX_NODES: usize = 400;

type Res<T> = Result<T, Error>;

impl<'a> Lexer<'a> {
    fn blanks(&mut self) {
        while self.pos < self.b.len() && matches!(self.b[self.pos], b' ' | b'\t' | b'\r') {
            self.pos += 1;
        }
    }

    fn peek(&mut self) -> Option<u8> {
        self.blanks();
        self.b.get(self.pos).copied()
    }

    fn fail<T>(&self, message: impl Into<String>) -> Res<T> {
        Err(Error {
            offset: self.pos.min(self.text.len()),
            message: message.into(),
        })
    }

    /// The character here (whole, when it is not ASCII).
    fn here(&self) -> char {
        self.text[self.pos..].chars().next().unwrap_or(' ')
    }

    fn eat(&mut self, c: u8) -> bool {
        if self.peek() == Some(c) {
            self.pos += 1;
            true
        } else {
            false
        }
    }

    fn expect(&mut self, c: u8) -> Res<()> {
        if self.eat(c) {
            Ok(())
        } else {
            self.fail(format!("`{}` expected here", c as char))
        }
    }

    /// A run of letters (upper case), without moving when there is none.
    fn word(&mut self) -> String {
        self.blanks();
        let start = self.pos;
        while self.pos < self.b.len() && self.b[self.pos].is_ascii_alphabetic() {
            self.pos += 1;
        }
        self.text[start..self.pos].to_ascii_uppercase()
    }

    /// The keyword `k` next, or stay.
    fn keyword(&mut self, k: &str) -> bool {
        let save = self.pos;
        if self.word() == k {
            true
        } else {
            self.pos = save;
            false
        }
    }

    /// An unsigned number's text (`12`, `1.5`, `.5`, `2.`).
    fn number_text(&mut self) -> Option<Range<usize>> {
        self.blanks();
        let start = self.pos;
        let mut digits = 0;
        while self.pos < self.b.len()
            && (self.b[self.pos].is_ascii_digit() || self.b[self.pos] == b'.')
        {
            digits += usize::from(self.b[self.pos].is_ascii_digit());
            self.pos += 1;
        }
        if digits == 0 || self.text[start..self.pos].matches('.').count() > 1 {
            self.pos = start;
            return None;
        }
        Some(start..self.pos)
    }

    fn small(&mut self, what: &str) -> Res<u8> {
        match self.number_text() {
            Some(r) => match self.text[r].parse::<u8>() {
                Ok(m @ 1..=3) => Ok(m),
                _ => self.fail(format!("{what} takes 1, 2 or 3")),
            },
            None => self.fail(format!("{what} takes 1, 2 or 3")),
        }
    }

    // Expressions: FANUC's precedence.

    fn expr(&mut self) -> Res<Expr> {
        let a = self.sum()?;
        let save = self.pos;
        let w = self.word();
        let op = match w.as_str() {
            "EQ" => Op::Eq,
            "NE" => Op::Ne,
            "GT" => Op::Gt,
            "GE" => Op::Ge,
            "LT" => Op::Lt,
            "LE" => Op::Le,
            _ => {
                self.pos = save;
                return Ok(a);
            }
        };
        let b = self.sum()?;
        Ok(binary(op, a, b))
    }

    fn sum(&mut self) -> Res<Expr> {
        let mut a = self.product()?;
        loop {
            let save = self.pos;
            let op = match self.peek() {
                Some(b'+') => Op::Plus,
                Some(b'-') => Op::Minus,
                _ => match self.word().as_str() {
                    "OR" => Op::Or,
                    "XOR" => Op::Xor,
                    _ => {
                        self.pos = save;
                        return Ok(a);
                    }
                },
            };
            if matches!(op, Op::Plus | Op::Minus) {
                self.pos += 1;
            }
            let b = self.product()?;
            a = binary(op, a, b);
        }
    }

    fn product(&mut self) -> Res<Expr> {
        let mut a = self.unary()?;
        loop {
            let save = self.pos;
            let op = match self.peek() {
                Some(b'*') => Op::Times,
                // `ATAN[a]/[b]` is read by `function`; here `/` divides.
                Some(b'/') => Op::Divide,
                _ => match self.word().as_str() {
                    "AND" => Op::And,
                    "MOD" => Op::Modulo,
                    _ => {
                        self.pos = save;
                        return Ok(a);
                    }
                },
            };
            if matches!(op, Op::Times | Op::Divide) {
                self.pos += 1;
            }
            let b = self.unary()?;
            a = binary(op, a, b);
        }
    }

    fn unary(&mut self) -> Res<Expr> {
        self.nodes += 1;
        if self.nodes > MAX_NODES {
            return self.fail("the expression is too long or nests too deep");
        }
        let start = {
            self.blanks();
            self.pos
        };
        if self.eat(b'-') {
            let e = self.unary()?;
            return Ok(Expr {
                range: start..e.range.end,
                kind: ExprKind::Negate(Box::new(e)),
            });
        }
        if self.eat(b'+') {
            return self.unary();
        }
        self.primary()
    }

    fn primary(&mut self) -> Res<Expr> {
        self.blanks();
        let start = self.pos;
        match self.peek() {
            Some(b'[') => {
                self.pos += 1;
                let e = self.expr()?;
                self.expect(b']')?;
                Ok(Expr {
                    kind: e.kind,
                    range: start..self.pos,
                })
            }
            Some(b'#') => self.variable(),
            Some(c) if c.is_ascii_digit() || c == b'.' => {
                let r = self.number_text().ok_or(Error {
                    offset: start,
                    message: "a number expected here".into(),
                })?;
                let v: f64 = self.text[r.clone()].parse().map_err(|_| Error {
                    offset: start,
                    message: format!("`{}` is not a number", &self.text[r.clone()]),
                })?;
                Ok(Expr {
                    kind: ExprKind::Number(v),
                    range: r,
                })
            }
            Some(c) if c.is_ascii_alphabetic() => self.function(start),
            None => self.fail("the block ends where a value was expected"),
            Some(c) => self.fail(format!(
                "unexpected character `{}` in an expression",
                c as char
            )),
        }
    }

    /// `#5`, `#[#1+1]`.
    fn variable(&mut self) -> Res<Expr> {
        self.blanks();
        let start = self.pos;
        self.expect(b'#')?;
        let index = if self.peek() == Some(b'[') {
            self.primary()?
        } else {
            let Some(r) = self.number_text() else {
                return self.fail("`#` is followed by a variable number or `[expression]`");
            };
            let v: f64 = self.text[r.clone()].parse().unwrap_or(f64::NAN);
            Expr {
                kind: ExprKind::Number(v),
                range: r,
            }
        };
        Ok(Expr {
            kind: ExprKind::Param(Param::Numbered(Box::new(index))),
            range: start..self.pos,
        })
    }

    fn function(&mut self, start: usize) -> Res<Expr> {
        let name = self.word();
        let f = match name.as_str() {
            "ATAN" => None,
            "FIX" => Some(Func::Fix),
            "FUP" => Some(Func::Fup),
            "ROUND" | "RND" => Some(Func::Round),
            n => match Func::parse(n) {
                Some(f) => Some(f),
                None => {
                    self.pos = start;
                    return self.fail(format!(
                        "`{name}` is not a function ncthread reads in an expression (SIN COS TAN ASIN ACOS ATAN SQRT ABS ROUND FIX FUP LN EXP)"
                    ));
                }
            },
        };
        if self.peek() != Some(b'[') {
            return self.fail(format!("`{name}` takes its argument in `[ ]`"));
        }
        let a = self.primary()?;
        let kind = match f {
            Some(f) => ExprKind::Unary(f, Box::new(a)),
            None => {
                // `ATAN[a]/[b]`, or `ATAN[a,b]` as later controls write it.
                let save = self.pos;
                if self.eat(b'/') && self.peek() == Some(b'[') {
                    let b = self.primary()?;
                    ExprKind::Atan(Box::new(a), Box::new(b))
                } else {
                    self.pos = save;
                    return self.fail("ATAN takes two arguments: `ATAN[a]/[b]`");
                }
            }
        };
        Ok(Expr {
            kind,
            range: start..self.pos,
        })
    }
}

fn binary(op: Op, a: Expr, b: Expr) -> Expr {
    let range = a.range.start..b.range.end;
    Expr {
        kind: ExprKind::Binary(op, Box::new(a), Box::new(b)),
        range,
    }
}

/// Reads one line as custom macro B.
pub fn parse_line(text: &str) -> Result<MLine, Error> {
    let mut l = Lexer {
        text,
        b: text.as_bytes(),
        pos: 0,
        nodes: 0,
    };
    let first = {
        l.blanks();
        l.pos
    };
    let mut line = MLine {
        number: None,
        block_delete: None,
        comment: None,
        delimiter: false,
        code_range: first..first,
        stmt: Stmt::Words(Vec::new()),
        stmt_range: first..first,
    };
    if l.peek() == Some(b'/') {
        l.pos += 1;
        line.block_delete = Some(first..l.pos);
    }
    let save = l.pos;
    if matches!(l.peek(), Some(b'N' | b'n')) {
        l.pos += 1;
        match l.number_text() {
            Some(r) if !text[r.clone()].contains('.') => {
                line.number = Some(text[r].parse().ok().filter(|n| *n <= 99_999).ok_or(Error {
                    offset: save,
                    message: "a block number is N1 to N99999".into(),
                })?);
            }
            _ => l.pos = save,
        }
    }
    l.blanks();
    let stmt_start = l.pos;
    line.stmt = statement(&mut l)?;
    line.stmt_range = stmt_start..l.pos;
    line.code_range = first..l.pos;
    let mut comments = Vec::new();
    loop {
        match l.peek() {
            None => break,
            Some(b'(') => {
                let start = l.pos;
                let Some(end) = text[start..].find(')') else {
                    return l.fail("a comment that is not closed");
                };
                comments.extend(crate::dialect::comment_text(&text[start + 1..start + end]));
                l.pos = start + end + 1;
            }
            Some(b';') => {
                l.pos += 1;
                if !matches!(l.peek(), None | Some(b'(')) {
                    return l.fail("text after the end-of-block mark `;` is not a comment");
                }
            }
            Some(_) => return l.fail(format!("unexpected character `{}`", l.here())),
        }
    }
    if !comments.is_empty() {
        line.comment = Some(comments.join(" "));
    }
    Ok(line)
}

fn statement(l: &mut Lexer<'_>) -> Res<Stmt> {
    match l.peek() {
        Some(b'#') => return assignment(l).map(|(t, e)| Stmt::Assign(t, e)),
        Some(b'%') => {
            l.pos += 1;
            return Ok(Stmt::Words(Vec::new()));
        }
        _ => {}
    }
    let save = l.pos;
    let w = l.word();
    match w.as_str() {
        "IF" => {
            if l.peek() != Some(b'[') {
                return l.fail("IF takes its condition in `[ ]`");
            }
            let cond = l.primary()?;
            if l.keyword("GOTO") {
                Ok(Stmt::IfGoto(cond, l.expr()?))
            } else if l.keyword("THEN") {
                let (t, e) = assignment(l)?;
                Ok(Stmt::IfThen(cond, t, e))
            } else if l.peek() == Some(b'#') {
                l.fail("IF […] #i=… without THEN: FANUC writes IF […] THEN #i=…")
            } else {
                l.fail("IF […] is followed by GOTO n or THEN #i=…")
            }
        }
        "GOTO" => Ok(Stmt::Goto(l.expr()?)),
        "WHILE" => {
            if l.peek() != Some(b'[') {
                return l.fail("WHILE takes its condition in `[ ]`");
            }
            let cond = l.primary()?;
            if !l.keyword("DO") {
                return l.fail("WHILE […] is followed by DO m");
            }
            Ok(Stmt::While(Some(cond), l.small("DO")?))
        }
        "DO" => Ok(Stmt::While(None, l.small("DO")?)),
        "END" => Ok(Stmt::End(l.small("END")?)),
        _ => {
            l.pos = save;
            words(l).map(Stmt::Words)
        }
    }
}

fn assignment(l: &mut Lexer<'_>) -> Res<(Target, Expr)> {
    let start = l.pos;
    let v = l.variable()?;
    let ExprKind::Param(Param::Numbered(index)) = v.kind else {
        return l.fail("a variable expected here");
    };
    let target = Target {
        index: *index,
        range: start..l.pos,
    };
    l.expect(b'=')?;
    Ok((target, l.expr()?))
}

/// Words: an address letter and a number, `#n`, `[expression]`, each with a sign or not.
fn words(l: &mut Lexer<'_>) -> Res<Vec<MWord>> {
    let mut out = Vec::new();
    while let Some(c) = l.peek() {
        if !c.is_ascii_alphabetic() && c != b':' {
            break;
        }
        let start = l.pos;
        l.pos += 1;
        let letter = if c == b':' {
            'O'
        } else {
            c.to_ascii_uppercase() as char
        };
        let vstart = {
            l.blanks();
            l.pos
        };
        let negative = l.eat(b'-');
        if !negative {
            l.eat(b'+');
        }
        let value = match l.peek() {
            Some(b'#' | b'[') => {
                let e = l.primary()?;
                Value::Expr(if negative {
                    Expr {
                        range: vstart..e.range.end,
                        kind: ExprKind::Negate(Box::new(e)),
                    }
                } else {
                    e
                })
            }
            _ => {
                let Some(r) = l.number_text() else {
                    l.pos = start;
                    return l.fail(format!("address `{letter}` is not followed by a number"));
                };
                let text = &l.text[vstart..r.end];
                let Some(d) = crate::fixed::Decimal::parse(text) else {
                    return l.fail(format!("`{text}` has too many digits"));
                };
                Value::Number(d)
            }
        };
        out.push(MWord {
            letter,
            value,
            range: start..l.pos,
        });
    }
    Ok(out)
}

/// What an expression reads: a variable's value, vacant (`None`), or why it has none.
pub trait Vars {
    fn get(&self, n: i64, range: &Range<usize>) -> Result<Option<f64>, EvalError>;
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct EvalError {
    pub message: String,
    pub help: String,
    pub range: Range<usize>,
    /// A value the machine holds (FANR020) rather than a mistake in the program.
    pub machine: bool,
}

impl EvalError {
    pub fn new(range: &Range<usize>, message: String, help: &str) -> EvalError {
        EvalError {
            message,
            help: help.into(),
            range: range.clone(),
            machine: false,
        }
    }
}

/// A variable number: whole.
pub fn index(e: &Expr, vars: &dyn Vars) -> Result<i64, EvalError> {
    let v = eval(e, vars)?.unwrap_or(0.0);
    let n = v.round();
    if (v - n).abs() > 1e-6 || n.abs() > 1e9 {
        return Err(EvalError::new(
            &e.range,
            format!("variable number {v} is not a whole number"),
            "a variable is #0, #1 … #33, #100 … #199 or #500 … #999",
        ));
    }
    Ok(n as i64)
}

/// An expression's value, `None` when vacant. FANUC's rules for a vacant variable (the
/// 0i-TF operator's manual, "Custom macro", "Undefined variable"): `#1=#0` leaves #1 vacant;
/// in arithmetic and functions a vacant value is 0 (`#0*5` is 0, `#0+#0` is 0); `EQ` and
/// `NE` tell vacant from 0 (`#0 EQ 0` is false, `#0 EQ #0` true); `GT` `GE` `LT` `LE` read it
/// as 0. A negated vacant value stays vacant **\[decided\]** (no case in the manual; a vacant
/// word is left out, which is safer than `-0`).
pub fn eval(e: &Expr, vars: &dyn Vars) -> Result<Option<f64>, EvalError> {
    let fail = |m: String, help: &str| EvalError::new(&e.range, m, help);
    let v = match &e.kind {
        ExprKind::Number(v) => *v,
        ExprKind::Param(Param::Numbered(i)) => {
            let n = index(i, vars)?;
            return vars.get(n, &e.range);
        }
        ExprKind::Param(Param::Named(_)) | ExprKind::Exists(_) => {
            return Err(fail("not a FANUC expression".into(), ""));
        }
        ExprKind::Negate(a) => match eval(a, vars)? {
            None => return Ok(None),
            Some(v) => -v,
        },
        ExprKind::Atan(a, b) => {
            let (a, b) = (zero(eval(a, vars)?), zero(eval(b, vars)?));
            // 0 … 360° (parameter 6004#0 = 0, the default).
            let d = a.atan2(b).to_degrees();
            if d < 0.0 { d + 360.0 } else { d }
        }
        ExprKind::Unary(f, a) => {
            let v = zero(eval(a, vars)?);
            match f {
                // FANUC: FIX[-1.2] is -1, FUP[-1.2] is -2 (towards and away from zero).
                Func::Fix => v.trunc(),
                Func::Fup => {
                    if v < 0.0 {
                        v.floor()
                    } else {
                        v.ceil()
                    }
                }
                f => e.unary(*f, v).map_err(|x| fail(x.message, x.help))?,
            }
        }
        ExprKind::Binary(op, a, b) => {
            let (a, b) = (eval(a, vars)?, eval(b, vars)?);
            match (op, a, b) {
                (Op::Eq, None, None) | (Op::Ne, Some(_), None) | (Op::Ne, None, Some(_)) => 1.0,
                (Op::Ne, None, None) | (Op::Eq, Some(_), None) | (Op::Eq, None, Some(_)) => 0.0,
                (Op::Divide, _, b) if zero(b) == 0.0 => {
                    return Err(fail(
                        "division by zero (FANUC alarm 112)".into(),
                        "check the divisor's variables: it is 0 (or vacant) here",
                    ));
                }
                _ => e
                    .binary_value(*op, zero(a), zero(b))
                    .map_err(|x| fail(x.message, x.help))?,
            }
        }
    };
    if v.is_finite() {
        Ok(Some(v))
    } else {
        Err(fail(
            format!("the value is not a finite number ({v})"),
            "check the expression's operands",
        ))
    }
}

fn zero(v: Option<f64>) -> f64 {
    v.unwrap_or(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Fixed;
    impl Vars for Fixed {
        fn get(&self, n: i64, _: &Range<usize>) -> Result<Option<f64>, EvalError> {
            Ok(match n {
                1 => Some(2.0),
                2 => Some(0.0),
                _ => None,
            })
        }
    }

    fn value(text: &str) -> Option<f64> {
        let mut l = Lexer {
            text,
            b: text.as_bytes(),
            pos: 0,
            nodes: 0,
        };
        let e = l.expr().unwrap_or_else(|e| panic!("{text}: {e:?}"));
        assert_eq!(l.pos, text.len(), "{text}");
        eval(&e, &Fixed).unwrap()
    }

    #[test]
    fn fanuc_precedence_and_functions() {
        assert_eq!(value("[1+2*3]"), Some(7.0));
        assert_eq!(value("[8/2/2]"), Some(2.0));
        assert_eq!(value("[1 OR 0 AND 0]"), Some(1.0));
        assert_eq!(value("[#1+1 GT 2]"), Some(1.0));
        assert_eq!(value("FIX[-1.2]"), Some(-1.0));
        assert_eq!(value("FUP[-1.2]"), Some(-2.0));
        assert_eq!(value("FUP[1.2]"), Some(2.0));
        assert_eq!(value("ROUND[-1.5]"), Some(-2.0));
        assert_eq!(value("ATAN[-1]/[0]"), Some(270.0));
        assert_eq!(value("SQRT[16]+ABS[-1]"), Some(5.0));
        assert_eq!(value("[7 MOD 3]"), Some(1.0));
        assert_eq!(value("#[#1-1]"), Some(2.0));
    }

    #[test]
    fn vacant_values_by_fanuc_s_table() {
        assert_eq!(value("#0"), None);
        assert_eq!(value("#5"), None);
        assert_eq!(value("-#5"), None);
        assert_eq!(value("[#0*5]"), Some(0.0));
        assert_eq!(value("[#0+#0]"), Some(0.0));
        assert_eq!(value("[#5 EQ #0]"), Some(1.0));
        assert_eq!(value("[#5 EQ 0]"), Some(0.0));
        assert_eq!(value("[#2 EQ #0]"), Some(0.0));
        assert_eq!(value("[#5 NE 0]"), Some(1.0));
        assert_eq!(value("[#5 GE #0]"), Some(1.0));
        assert_eq!(value("[#5 GT 0]"), Some(0.0));
    }

    #[test]
    fn statements_and_words() {
        let l = parse_line("N10 IF [#1 GT 2] GOTO 20 (X)").unwrap();
        assert_eq!(l.number, Some(10));
        assert!(matches!(l.stmt, Stmt::IfGoto(..)));
        assert_eq!(l.comment.as_deref(), Some("X"));
        assert!(matches!(
            parse_line("WHILE[#1LE3]DO1").unwrap().stmt,
            Stmt::While(Some(_), 1)
        ));
        assert!(matches!(parse_line("END 2;").unwrap().stmt, Stmt::End(2)));
        assert!(matches!(
            parse_line("#[#1+100]=#1*2").unwrap().stmt,
            Stmt::Assign(..)
        ));
        let l = parse_line("G01 X[#1+2.] Z-#2 F0.2").unwrap();
        let Stmt::Words(w) = &l.stmt else { panic!() };
        assert_eq!(w.len(), 4);
        assert_eq!(w[1].range, 4..12);
        assert!(parse_line("END 4").is_err());
        assert!(parse_line("X[1+").is_err());
        assert!(parse_line("#1=BIN[3]").is_err());
        assert!(parse_line("G00 X(OPEN").is_err());
        // Deep or long expressions are refused, not a stack overflow.
        assert!(parse_line(&format!("#1={}1{}", "[".repeat(5000), "]".repeat(5000))).is_err());
        assert!(parse_line(&format!("#1={}", "-".repeat(5000))).is_err());
        assert!(parse_line(&format!("#1=1{}", "+1".repeat(5000))).is_err());
    }
}

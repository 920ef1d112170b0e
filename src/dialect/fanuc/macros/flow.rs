//! The jumps (`GOTO`, `WHILE … DO` / `END`), the calls (`M98`, `G65`), the return (`M99`)
//! and the blocks the run gives the interpreter.

use super::parse::{self, EvalError, MLine, MWord, Stmt, Value};
use super::{Event, Flow, Frame, LOOP_LIMIT, MAX_DEPTH, MAX_MACRO_LEVELS, Runner, packed};

/// A program's block numbers (each with its lines, in order) and its `DO m` … `END m` pairs.
#[derive(Debug, Default)]
pub(super) struct Index {
    numbers: std::collections::HashMap<u32, Vec<usize>>,
    loops: Vec<(usize, usize)>,
}
use crate::dialect::fanuc::codes;
use crate::dialect::fanuc::syntax::{Block, Word};
use crate::fixed::Decimal;

/// FANUC's argument specification I: the local each address of a `G65` sets.
fn argument(letter: char) -> Option<usize> {
    Some(match letter {
        'A' => 1,
        'B' => 2,
        'C' => 3,
        'I' => 4,
        'J' => 5,
        'K' => 6,
        'D' => 7,
        'E' => 8,
        'F' => 9,
        'H' => 11,
        'M' => 13,
        'Q' => 17,
        'R' => 18,
        'S' => 19,
        'T' => 20,
        'U' => 21,
        'V' => 22,
        'W' => 23,
        'X' => 24,
        'Y' => 25,
        'Z' => 26,
        _ => return None,
    })
}

/// A computed value as a word's decimal. A variable's value in an address is rounded to
/// the address's least input increment (FANUC, "Custom macro", "Variables": "rounded off"):
/// 0.001 mm (0.0001 in) for the axes and arc words, 0.0001 mm (0.000001 in) for F; a whole
/// value of any other address is that number without a point.
fn word_value(letter: char, v: f64, inch: bool) -> Option<Decimal> {
    let decimals = match letter {
        'X' | 'Z' | 'U' | 'W' | 'I' | 'K' | 'R' | 'Y' | 'C' => {
            if inch {
                4
            } else {
                3
            }
        }
        'F' | 'E' => {
            if inch {
                6
            } else {
                4
            }
        }
        _ if (v - v.round()).abs() < 1e-9 && v.abs() < 1e12 => {
            return Some(Decimal {
                mantissa: v.round() as i128,
                scale: 0,
                has_point: false,
            });
        }
        _ => return crate::dialect::iso::expr::to_decimal(v),
    };
    if !v.is_finite() || v.abs() >= 1e12 {
        return None;
    }
    Some(Decimal {
        mantissa: (v * 10f64.powi(decimals)).round() as i128,
        scale: decimals as u32,
        has_point: true,
    })
}

impl Runner<'_> {
    /// The line index of `N n` in the running program: forward from here, then from its
    /// start (as FANUC searches).
    fn find_block(&mut self, n: u32) -> Option<usize> {
        let (pc, index) = (self.cur.pc, self.index());
        let at = index.numbers.get(&n)?;
        at.iter().find(|i| **i >= pc).or(at.first()).copied()
    }

    /// The running program's block numbers and loops, found once per program.
    fn index(&mut self) -> std::rc::Rc<Index> {
        let p = self.cur.prog;
        if let Some(index) = self.indexes.get(&(p.file, p.start)) {
            return index.clone();
        }
        let stmt = |i: usize| self.lines[p.file][i].1.as_ref().ok();
        let mut index = Index::default();
        for i in p.start..p.end {
            let Some(l) = stmt(i) else { continue };
            if let Some(n) = l.number {
                index.numbers.entry(n).or_default().push(i);
            }
            if let Stmt::While(_, m) = &l.stmt
                && let Some(j) = (i + 1..p.end)
                    .find(|j| matches!(stmt(*j).map(|l| &l.stmt), Some(Stmt::End(e)) if e == m))
            {
                index.loops.push((i, j));
            }
        }
        let index = std::rc::Rc::new(index);
        self.indexes.insert((p.file, p.start), index.clone());
        index
    }

    fn back(&mut self, to: usize, l: &MLine) -> Flow {
        self.iterations += 1;
        if self.iterations > LOOP_LIMIT {
            return self.refuse(
                codes::FANR_MACRO,
                l.stmt_range.clone(),
                format!("the program jumps back more than {LOOP_LIMIT} times: ncthread stops an endless loop here"),
                "check the loop's condition: it never becomes false",
            );
        }
        self.cur.pc = to;
        Flow::Next
    }

    pub(super) fn goto(&mut self, n: &parse::Expr, l: &MLine) -> Result<Flow, EvalError> {
        let v = parse::eval(n, &self.vars)?.unwrap_or(0.0);
        let here = self.cur.pc - 1;
        if v.fract() != 0.0 || !(1.0..=99_999.0).contains(&v) {
            return Ok(self.refuse(
                codes::FANR_MACRO,
                n.range.clone(),
                format!("GOTO {v}: a block number is 1 … 99999"),
                "GOTO names a block number (N) of the same program",
            ));
        }
        let Some(to) = self.find_block(v as u32) else {
            return Ok(self.refuse(
                codes::FANR_MACRO,
                n.range.clone(),
                format!("GOTO {v}: there is no block N{v} in this program"),
                "GOTO jumps to a block number (N) of the program or subprogram it stands in",
            ));
        };
        let into = self
            .index()
            .loops
            .iter()
            .copied()
            .any(|(d, e)| d < to && to <= e && !(d..=e).contains(&here));
        if into {
            return Ok(self.refuse(
                codes::FANR_MACRO,
                n.range.clone(),
                format!(
                    "GOTO {v} jumps into a WHILE … DO loop from outside it, which FANUC refuses"
                ),
                "jump to the WHILE block or to a block outside the loop",
            ));
        }
        Ok(if to <= here {
            self.back(to, l)
        } else {
            self.cur.pc = to;
            Flow::Next
        })
    }

    /// `WHILE` false: on after its `END m`.
    pub(super) fn past_end(&mut self, m: u8, l: &MLine) -> Flow {
        let here = self.cur.pc - 1;
        match self.index().loops.iter().copied().find(|(d, _)| *d == here) {
            Some((_, e)) => {
                self.cur.pc = e + 1;
                Flow::Next
            }
            None => self.refuse(
                codes::FANR_MACRO,
                l.stmt_range.clone(),
                format!("DO {m} has no END {m} after it in this program"),
                "close each WHILE … DO m with END m",
            ),
        }
    }

    /// `END m`: back to its `DO m`.
    pub(super) fn back_to_do(&mut self, m: u8, l: &MLine) -> Flow {
        let here = self.cur.pc - 1;
        match self
            .index()
            .loops
            .iter()
            .copied()
            .filter(|(_, e)| *e == here)
            .map(|(d, _)| d)
            .max()
        {
            Some(d) => self.back(d, l),
            None => self.refuse(
                codes::FANR_MACRO,
                l.stmt_range.clone(),
                format!("END {m} has no WHILE … DO {m} before it in this program"),
                "close each WHILE … DO m with END m",
            ),
        }
    }

    /// A block of words: computed, then run (a call, a return) or given to the interpreter.
    pub(super) fn words(&mut self, l: &MLine, words: &[MWord]) -> Result<Flow, EvalError> {
        let mut out: Vec<Word> = Vec::new();
        for w in words {
            let value = match &w.value {
                Value::Number(d) => *d,
                Value::Expr(e) => match parse::eval(e, &self.vars)? {
                    // A vacant value: the address is as if not written (FANUC, "Undefined
                    // variable": `G90 X#1` with #1 vacant is `G90`).
                    None => continue,
                    Some(v) => match word_value(w.letter, v, self.inch) {
                        Some(d) => d,
                        None => {
                            return Err(EvalError::new(
                                &w.range,
                                format!("{}{v} is too large for a word", w.letter),
                                "check the expression",
                            ));
                        }
                    },
                },
            };
            out.push(Word {
                letter: w.letter,
                value,
                range: w.range.clone(),
            });
        }
        let code = |letter: char, n: i64| {
            out.iter()
                .position(|w| w.letter == letter && w.value.to_whole() == Ok(n))
        };
        if let Some(g) = [66, 67].into_iter().find_map(|n| code('G', n)) {
            return Ok(self.refuse(
                codes::FANR_UNSUPPORTED,
                out[g].range.clone(),
                format!(
                    "`{}`: the modal macro call (G66/G67) is not read",
                    &self.line_text(out[g].range.clone())
                ),
                "call the macro with G65 at each block where it should run",
            ));
        }
        if code('G', 65).is_some() {
            return Ok(self.g65(l, &out));
        }
        if let Some(m) = code('M', 98) {
            return Ok(self.m98(l, out, m));
        }
        if let Some(m) = code('M', 99) {
            return Ok(self.m99(l, out, m));
        }
        self.emit(l, out);
        Ok(Flow::Next)
    }

    fn line_text(&self, range: std::ops::Range<usize>) -> String {
        let line = self.lines[self.cur.prog.file][self.cur.pc - 1].0;
        line.text.get(range).unwrap_or("").to_string()
    }

    /// Gives a block to the interpreter; M02 and M30 end the run there.
    fn emit(&mut self, l: &MLine, words: Vec<Word>) {
        for w in words.iter().filter(|w| w.letter == 'G') {
            match w.value.to_whole().map(|g| self.system.a_of(g).unwrap_or(g)) {
                Ok(20) => self.inch = true,
                Ok(21) => self.inch = false,
                _ => {}
            }
        }
        let end = words
            .iter()
            .any(|w| w.letter == 'M' && matches!(w.value.to_whole(), Ok(2 | 30)));
        let file = self.cur.prog.file;
        let line = self.lines[file][self.cur.pc - 1].0;
        let call = if file == 0 {
            None
        } else {
            self.program_call().map(|i| self.lines[0][i].0)
        };
        let block = Block {
            number: l.number,
            words,
            comment: l.comment.clone(),
            delimiter: false,
            block_delete: l.block_delete.clone(),
            code_range: l.code_range.clone(),
        };
        let chain = self.chain();
        self.events.push(Event::Block {
            file,
            line,
            block,
            chain,
            call,
        });
        if end {
            // M02/M30 end the program, in a subprogram too.
            self.cur.pc = self.cur.prog.end;
            self.frames.clear();
        }
    }

    /// The line of the program (file 0) whose call leads into another file.
    fn program_call(&self) -> Option<usize> {
        let mut frames: Vec<&Frame> = self.frames.iter().collect();
        frames.push(&self.cur);
        frames
            .iter()
            .find(|f| f.prog.file != 0)
            .map(|f| f.call)
            .filter(|(file, _)| *file == 0)
            .map(|(_, i)| i)
    }

    fn g65(&mut self, l: &MLine, out: &[Word]) -> Flow {
        let mut args = [None; 33];
        let (mut p, mut repeats) = (None, 1);
        for w in out {
            let v = w.value.to_f64();
            match w.letter {
                'G' if w.value.to_whole() == Ok(65) => {}
                'P' => p = Some((v as u32, w.range.clone())),
                'L' => repeats = v as u32,
                // FANUC reads an argument without a point in the address's least input
                // increment on some addresses and as written on others: not guessed.
                letter if !w.value.has_point && "XYZUVWIJKRF".contains(letter) => {
                    return self.refuse(
                        codes::FANR_NUMBER,
                        w.range.clone(),
                        format!("`{}`: a G65 argument on {letter} without a decimal point, whose unit (whole or least input increment) depends on the machine", self.line_text(w.range.clone())),
                        "write the argument with a decimal point (`X20.`)",
                    );
                }
                letter => match argument(letter) {
                    Some(n) if args[n - 1].is_none() => args[n - 1] = Some(v),
                    _ => {
                        return self.refuse(
                            codes::FANR_MACRO,
                            w.range.clone(),
                            format!("`{letter}` is not an argument of G65 here (argument specification I: A B C D E F H I J K M Q R S T U V W X Y Z, each once)"),
                            "G65 P… takes each argument letter once; G, L, N, O and P are not arguments",
                        );
                    }
                },
            }
        }
        let Some((p, range)) = p else {
            return self.refuse(
                codes::FANR_MACRO,
                l.stmt_range.clone(),
                "G65 without P (the program it calls)".into(),
                "write G65 P<program number> and the arguments",
            );
        };
        self.call(p, repeats, Some(args), range)
    }

    fn m98(&mut self, l: &MLine, mut out: Vec<Word>, m: usize) -> Flow {
        let m98 = out.remove(m);
        let take = |out: &mut Vec<Word>, letter: char| {
            out.iter()
                .position(|w| w.letter == letter)
                .map(|i| out.remove(i))
        };
        let p = take(&mut out, 'P');
        let l_word = take(&mut out, 'L');
        if !out.is_empty() {
            self.emit(l, out);
        }
        let Some(p) = p else {
            return self.refuse(
                codes::FANR_MACRO,
                m98.range,
                "M98 without P (the subprogram it calls)".into(),
                "write M98 P<program number>",
            );
        };
        let (number, packed_repeats) = match p.value.to_whole() {
            Ok(n) if (1..=99_999_999).contains(&n) => packed(n as u32),
            _ => return self.refuse(codes::FANR_MACRO, p.range, "M98's P is a program number (1 … 9999, or a repeat count of up to four digits in front of it)".into(), "write M98 P1234 or M98 P1234 L3"),
        };
        let repeats = match l_word.map(|w| w.value.to_whole()) {
            Some(Ok(n)) if (0..=9999).contains(&n) => n as u32,
            Some(_) => {
                return self.refuse(
                    codes::FANR_MACRO,
                    p.range,
                    "M98's L is a repeat count, 0 … 9999".into(),
                    "write M98 P1234 L3",
                );
            }
            None => packed_repeats,
        };
        self.call(number, repeats, None, p.range)
    }

    fn call(
        &mut self,
        n: u32,
        repeats: u32,
        args: Option<[Option<f64>; 33]>,
        range: std::ops::Range<usize>,
    ) -> Flow {
        let Some(prog) = self.programs.get(&n).copied() else {
            return self.refuse(
                codes::FANR_MACRO,
                range,
                format!("O{n:04} is neither in this file nor a file O{n:04} or O{n:04}.nc in the subroutine path"),
                "put the subprogram after the program's M30, or its file in a folder given by --subroutine-path (the profile's [iso] subroutine_path)",
            );
        };
        if repeats == 0 {
            return Flow::Next;
        }
        let levels = self
            .frames
            .iter()
            .chain(std::iter::once(&self.cur))
            .filter(|f| f.macro_call)
            .count();
        if self.frames.len() + 1 > MAX_DEPTH || (args.is_some() && levels >= MAX_MACRO_LEVELS) {
            return self.refuse(
                codes::FANR_MACRO,
                range,
                format!("calling O{n:04} here nests calls deeper than FANUC allows (at most {MAX_DEPTH} nested calls, at most {MAX_MACRO_LEVELS} of them G65 calls)"),
                "a subprogram that calls itself needs a condition that ends the calls",
            );
        }
        let frame = Frame {
            prog,
            pc: prog.start,
            name: format!("O{n:04}"),
            repeats: repeats - 1,
            macro_call: args.is_some(),
            call: (self.cur.prog.file, self.cur.pc - 1),
        };
        if let Some(args) = args {
            self.vars.push(args);
        }
        self.frames.push(std::mem::replace(&mut self.cur, frame));
        Flow::Next
    }

    fn m99(&mut self, l: &MLine, mut out: Vec<Word>, m: usize) -> Flow {
        let m99 = out.remove(m);
        if let Some(p) = out.iter().find(|w| w.letter == 'P') {
            return self.refuse(
                codes::FANR_UNSUPPORTED,
                p.range.clone(),
                "M99 P…: a return to a block number of the caller is not read".into(),
                "return with M99 alone and jump with GOTO in the caller",
            );
        }
        if !out.is_empty() {
            self.emit(l, out);
        }
        if self.frames.is_empty() {
            return self.refuse(
                codes::FANR_MACRO,
                m99.range,
                "M99 in the main program runs it again from its start, endlessly".into(),
                "end the program with M30 (M99 ends a subprogram)",
            );
        }
        if self.cur.repeats > 0 {
            self.cur.repeats -= 1;
            let start = self.cur.prog.start;
            return self.back(start, l);
        }
        if self.cur.macro_call {
            self.vars.pop();
        }
        if let Some(caller) = self.frames.pop() {
            self.cur = caller;
        }
        Flow::Next
    }
}

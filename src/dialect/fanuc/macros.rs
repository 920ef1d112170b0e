//! FANUC custom macro B and subprograms, run before the block interpreter: the program's
//! variables, `IF`/`GOTO`/`WHILE` control flow, `M98`/`M99` subprograms and `G65` macro
//! calls are run here, and what comes out is the explicit program, block by block, each
//! block still at its own line (and file) with its words' values computed. The block
//! interpreter (`front/block.rs`) then reads those blocks as it reads any others.
//!
//! Only a program that uses these (a `#`, `[`, `IF`, `WHILE`, `GOTO`, `G65`, `G66`, `M98`
//! or `M99`) comes here ([`uses_macros`]); every other program is read line by line as
//! before.
//!
//! Bounds, as the ISO reader's: at most [`LOOP_LIMIT`] backward jumps, at most
//! [`MAX_DEPTH`] nested calls (FANUC's subprogram nesting) of which [`MAX_MACRO_LEVELS`]
//! `G65` calls (FANUC's local variable levels). Each refusal names its call chain.

use std::collections::HashMap;
use std::ops::Range;
use std::path::PathBuf;

use super::codes;
use super::syntax::{self, Block};
use crate::diag::{Code, Diagnostic};
use crate::source::{Line, SourceFile};

mod parse;
mod vars;

use parse::{EvalError, MLine, Stmt, Value};

/// The most backward jumps (`END`, a `GOTO` back, a repeat of `M98 … L`) one program
/// runs: an endless loop ends with an error within a second. **\[decided\]** (as the ISO
/// reader's limit.)
pub(super) const LOOP_LIMIT: u64 = 200_000;

/// The most lines one program runs: a long loop of many blocks ends with an error within
/// seconds as well. **\[decided\]**
const STEP_LIMIT: u64 = 2_000_000;

/// FANUC's deepest nesting of subprogram and macro calls (0i-F: 10 levels in all).
const MAX_DEPTH: usize = 10;

/// FANUC's local variable levels below the main program (0i-F: 4 nested macro calls;
/// level 0 is the main program's).
const MAX_MACRO_LEVELS: usize = 4;

/// Whether a program uses custom macro B or subprograms (see the module's comment).
pub(super) fn uses_macros(src: &SourceFile) -> bool {
    let title = title_line(src);
    src.lines().any(|line| line_uses_macros(line, title))
}

/// Whether `line` makes its program one that [`uses_macros`] (`title`: the program's title
/// line, [`title_line`]).
pub(super) fn line_uses_macros(line: Line<'_>, title: Option<u32>) -> bool {
    if Some(line.number) == title || is_billet(line.text) {
        return false;
    }
    let code = without_comments(line.text);
    // Lines are short: a plain look at each byte beats a vector search's set-up.
    if code.bytes().any(|b| b == b'#' || b == b'[') || starts_with_statement(&code) {
        return true;
    }
    may_call(&code)
        && syntax::parse_line(line.text).is_ok_and(|b| {
            b.words.iter().any(|w| {
                matches!(
                    (w.letter, w.value.to_whole()),
                    ('G', Ok(65..=67)) | ('M', Ok(98 | 99))
                )
            })
        })
}

/// `IF`, `WHILE`, `GOTO`, `DO` or `END` first in a block's code (after `/` and its N).
fn starts_with_statement(code: &str) -> bool {
    // Each keyword is two letters or more in a row, which a block of words never has.
    if !code
        .as_bytes()
        .windows(2)
        .any(|w| w[0].is_ascii_alphabetic() && w[1].is_ascii_alphabetic())
    {
        return false;
    }
    let code = code.trim_start().trim_start_matches('/').trim_start();
    let code = match code.strip_prefix(['N', 'n']) {
        Some(rest) if rest.starts_with(|c: char| c.is_ascii_digit()) => {
            rest.trim_start_matches(|c: char| c.is_ascii_digit())
        }
        _ => code,
    };
    let code = code.trim_start();
    let end = code
        .find(|c: char| !c.is_ascii_alphabetic())
        .unwrap_or(code.len());
    ["IF", "WHILE", "GOTO", "DO", "END"]
        .iter()
        .any(|w| w.eq_ignore_ascii_case(&code[..end]))
}

/// Whether `code` may hold `G65`–`G67`, `M98` or `M99`: a G or M, then (as the grammar reads
/// a word's value) blanks, a sign and zeros, then a 6 or a 9. Lines without one need not be
/// parsed to know they call nothing.
fn may_call(code: &str) -> bool {
    let b = code.as_bytes();
    b.iter().enumerate().any(|(i, c)| {
        matches!(c, b'G' | b'g' | b'M' | b'm')
            && b[i + 1..]
                .iter()
                .find(|&&d| !matches!(d, b' ' | b'\t' | b'\r' | b'+' | b'-' | b'0'))
                .is_some_and(|&d| d == b'6' || d == b'9')
    })
}

/// The line of a title before the program's start (see `front.rs`): a first line that is
/// no block and starts with a letter, followed by a `%` or the program number.
pub(super) fn title_line(src: &SourceFile) -> Option<u32> {
    let mut lines = src.lines().filter(|l| !l.is_blank());
    let first = lines.next()?;
    let next = lines.next()?;
    let starts = syntax::parse_line(next.text).is_ok_and(|b| b.delimiter || b.get('O').is_some());
    (syntax::parse_line(first.text).is_err()
        && first.text.trim_start().starts_with(char::is_alphabetic)
        && starts)
        .then_some(first.number)
}

/// Denford's `[BILLET X… Z…` stock line (a comment, see `front.rs`).
fn is_billet(text: &str) -> bool {
    text.trim_start()
        .get(..7)
        .is_some_and(|h| h.eq_ignore_ascii_case("[BILLET"))
}

/// `text` without its `( )` comments (borrowed when it has none).
fn without_comments(text: &str) -> std::borrow::Cow<'_, str> {
    if !text.bytes().any(|b| b == b'(' || b == b')') {
        return std::borrow::Cow::Borrowed(text);
    }
    let mut out = String::new();
    let mut depth = false;
    for c in text.chars() {
        match c {
            '(' => depth = true,
            ')' => depth = false,
            _ if !depth => out.push(c),
            _ => {}
        }
    }
    std::borrow::Cow::Owned(out)
}

/// The files a program's subprograms come from: `O1234` or `O1234.nc` in the subroutine
/// path, for each `M98 P…` or `G65 P…` the program calls but does not hold.
pub(super) struct Loaded {
    /// Each file with the program number it was found for.
    pub files: Vec<(u32, SourceFile)>,
}

/// A line and what it reads as (or where and why it cannot be read, with a help).
type ReadLine<'a> = (Line<'a>, Result<MLine, (usize, String, String)>);

pub(super) fn load(src: &SourceFile, path: &[PathBuf]) -> Loaded {
    let mut files: Vec<(u32, SourceFile)> = Vec::new();
    let mut known: Vec<u32> = Vec::new();
    let mut k = 0;
    loop {
        let file = if k == 0 { src } else { &files[k - 1].1 };
        let lines: Vec<_> = file.lines().map(|l| read_line(l.text)).collect();
        let defined: Vec<u32> = lines
            .iter()
            .filter_map(|l| o_number(l.as_ref().ok()?))
            .collect();
        let mut wanted = Vec::new();
        for l in lines.iter().flatten() {
            if let Some(n) = called(l)
                && !defined.contains(&n)
                && !known.contains(&n)
            {
                known.push(n);
                wanted.push(n);
            }
        }
        for n in wanted {
            if let Some(f) = find_file(path, n) {
                files.push((n, f));
            }
        }
        k += 1;
        if k > files.len() {
            break;
        }
    }
    Loaded { files }
}

fn find_file(path: &[PathBuf], n: u32) -> Option<SourceFile> {
    for dir in path {
        for name in [
            format!("O{n:04}"),
            format!("O{n:04}.nc"),
            format!("O{n}"),
            format!("O{n}.nc"),
        ] {
            let p = dir.join(&name);
            if let Ok(text) = std::fs::read_to_string(&p) {
                return Some(SourceFile::new(p.display().to_string(), text));
            }
        }
    }
    None
}

/// The program a line's `M98 P…` or `G65 P…` calls, when written as a number.
fn called(l: &MLine) -> Option<u32> {
    let g65 = l.word('G').is_some_and(|w| number(w) == Some(65.0));
    let m98 = l.word('M').is_some_and(|w| number(w) == Some(98.0));
    let p = number(l.word('P')?)?;
    match (g65, m98) {
        (true, _) => Some(p as u32),
        (_, true) => Some(packed(p as u32).0),
        _ => None,
    }
}

/// `M98 P30001234`: three times O1234 (a P of more than four digits holds the repeat
/// count in front of the program number).
fn packed(p: u32) -> (u32, u32) {
    if p > 9999 {
        (p % 10_000, p / 10_000)
    } else {
        (p, 1)
    }
}

fn number(w: &parse::MWord) -> Option<f64> {
    match &w.value {
        Value::Number(d) => Some(d.to_f64()),
        Value::Expr(_) => None,
    }
}

fn o_number(l: &MLine) -> Option<u32> {
    let Stmt::Words(w) = &l.stmt else { return None };
    let o = w.first().filter(|w| w.letter == 'O')?;
    number(o).map(|n| n as u32)
}

/// A line as the macro runner reads it: as the FANUC syntax reads it when it can (so that
/// every form it takes reads the same), else as custom macro B.
fn read_line(text: &str) -> Result<MLine, (usize, String, String)> {
    match syntax::parse_line(text) {
        Ok(b) => Ok(MLine {
            number: b.number,
            block_delete: b.block_delete,
            comment: b.comment,
            delimiter: b.delimiter && b.words.is_empty(),
            stmt_range: b.code_range.clone(),
            code_range: b.code_range,
            stmt: Stmt::Words(
                b.words
                    .into_iter()
                    .map(|w| parse::MWord {
                        letter: w.letter,
                        value: Value::Number(w.value),
                        range: w.range,
                    })
                    .collect(),
            ),
        }),
        Err(plain) => parse::parse_line(text).map_err(|e| {
            let code = without_comments(text);
            let macro_line = code.contains(['#', '[']) || starts_with_statement(&code);
            if macro_line {
                (e.offset, e.message, "custom macro B: `#1=[#2+1.]`, `IF [#1 GT 2] GOTO 10`, `WHILE [#1 LE 3] DO 1` … `END 1`, words with `#n` or `[expression]` values".into())
            } else {
                (plain.offset, plain.message, plain.help)
            }
        }),
    }
}

/// What the run gives the block interpreter.
pub(super) enum Event<'a> {
    Block {
        /// 0: the program; else `loaded.files[file - 1]`.
        file: usize,
        line: Line<'a>,
        block: Block,
        /// `in O2000 called from line 12`, innermost first.
        chain: Option<String>,
        /// The program's line whose call runs a block of another file.
        call: Option<Line<'a>>,
    },
    /// A `[BILLET` line (a comment, see `front.rs`).
    Billet(Line<'a>),
    /// A title before the program's start (a comment, see `front.rs`).
    Title(Line<'a>),
    Diag(Diagnostic),
}

/// A program in a file: its O line (if any), its first line and the line after its last.
#[derive(Clone, Copy, Debug)]
struct Prog {
    file: usize,
    start: usize,
    end: usize,
}

#[derive(Clone, Debug)]
struct Frame {
    prog: Prog,
    pc: usize,
    name: String,
    /// Runs left after this one (`M98 P… L3`).
    repeats: u32,
    /// A `G65` call: a level of locals of its own.
    macro_call: bool,
    /// The caller's file and line index.
    call: (usize, usize),
}

struct Runner<'a> {
    files: Vec<&'a SourceFile>,
    lines: Vec<Vec<ReadLine<'a>>>,
    programs: HashMap<u32, Prog>,
    frames: Vec<Frame>,
    cur: Frame,
    vars: vars::Variables,
    iterations: u64,
    /// Lines run so far.
    steps: u64,
    /// Inch or metric input, which a computed word is rounded to: the machine's start unit,
    /// then G20/G21 (G70/G71 in G-code system C).
    inch: bool,
    /// The machine's G-code system: which codes are G20/G21 (G70/G71 in system C).
    system: super::profile::GcodeSystem,
    percents: u32,
    events: Vec<Event<'a>>,
    /// The program's title line (see [`title_line`]).
    title: Option<u32>,
    /// Each program's block numbers and loops, by (file, first line).
    indexes: HashMap<(usize, usize), std::rc::Rc<flow::Index>>,
}

enum Flow {
    Next,
    Stop,
}

/// Runs the program: its explicit blocks, its refusals, in order.
pub(super) fn run<'a>(
    src: &'a SourceFile,
    loaded: &'a Loaded,
    profile: &super::profile::FanucProfile,
) -> Vec<Event<'a>> {
    let files: Vec<&SourceFile> = std::iter::once(src)
        .chain(loaded.files.iter().map(|(_, f)| f))
        .collect();
    let numbers: Vec<u32> = loaded.files.iter().map(|(n, _)| *n).collect();
    let lines: Vec<Vec<_>> = files
        .iter()
        .map(|f| f.lines().map(|l| (l, read_line(l.text))).collect())
        .collect();
    let (main, programs) = programs(&lines, &numbers);
    let mut r = Runner {
        files,
        lines,
        programs,
        frames: Vec::new(),
        cur: Frame {
            prog: main,
            pc: 0,
            name: String::new(),
            repeats: 0,
            macro_call: false,
            call: (0, 0),
        },
        vars: vars::Variables::default(),
        iterations: 0,
        steps: 0,
        inch: profile.inch,
        system: profile.gcode_system,
        percents: 0,
        events: Vec::new(),
        title: title_line(src),
        indexes: HashMap::new(),
    };
    r.syntax_errors();
    while let Flow::Next = r.step() {}
    r.events
}

/// The main program's lines and every numbered program's.
fn programs(lines: &[Vec<ReadLine<'_>>], numbers: &[u32]) -> (Prog, HashMap<u32, Prog>) {
    let mut programs = HashMap::new();
    let mut main = None;
    for (f, file) in lines.iter().enumerate() {
        let o_lines: Vec<(usize, u32)> = file
            .iter()
            .enumerate()
            .filter_map(|(i, (_, l))| Some((i, o_number(l.as_ref().ok()?)?)))
            .collect();
        // A program's own number: an O line before any other block.
        let first_block = file.iter().position(|(_, l)| {
            l.as_ref()
                .map_or(true, |l| !matches!(&l.stmt, Stmt::Words(w) if w.is_empty()))
        });
        let own = o_lines
            .first()
            .filter(|(i, _)| Some(*i) == first_block)
            .copied();
        for (k, &(i, n)) in o_lines.iter().enumerate() {
            let end = o_lines.get(k + 1).map_or(file.len(), |(j, _)| *j);
            programs.entry(n).or_insert(Prog {
                file: f,
                start: i + 1,
                end,
            });
        }
        if f == 0 {
            let end = o_lines
                .iter()
                .find(|(i, _)| own.is_none_or(|(o, _)| *i > o))
                .map_or(file.len(), |(i, _)| *i);
            main = Some(Prog {
                file: 0,
                start: 0,
                end,
            });
        } else if own.is_none() {
            // A file without an O line is one subprogram; it takes its number from its name.
            programs.entry(numbers[f - 1]).or_insert(Prog {
                file: f,
                start: 0,
                end: file.len(),
            });
        }
    }
    let main = main.unwrap_or(Prog {
        file: 0,
        start: 0,
        end: 0,
    });
    (main, programs)
}

impl<'a> Runner<'a> {
    /// Every line that cannot be read, said up front (a program with one runs nowhere).
    fn syntax_errors(&mut self) {
        for f in 0..self.files.len() {
            for i in 0..self.lines[f].len() {
                let (line, Err((offset, message, help))) = &self.lines[f][i] else {
                    continue;
                };
                if f == 0 && (is_billet(line.text) || Some(line.number) == self.title) {
                    continue;
                }
                let src = self.files[f];
                let span = src.span_in_line(*line, *offset..offset + 1);
                self.events.push(Event::Diag(
                    Diagnostic::new(codes::FANR_SYNTAX, message.clone())
                        .at(src, span)
                        .help(help.clone()),
                ));
            }
        }
    }

    /// The call chain: `in O2000 called from line 12, in O3000 called from line 4`.
    fn chain(&self) -> Option<String> {
        if self.frames.is_empty() {
            return None;
        }
        let mut parts: Vec<(String, usize)> = Vec::new();
        let mut inner = &self.cur;
        for outer in self.frames.iter().rev() {
            let (f, i) = inner.call;
            let number = self.lines[f][i].0.number;
            let at = if f == 0 {
                format!("line {number}")
            } else {
                format!("{} line {number}", self.files[f].name)
            };
            let part = format!("in {} called from {at}", inner.name);
            // A recursion's repeated calls are counted, not listed (as the ISO reader does).
            match parts.last_mut() {
                Some((last, n)) if *last == part => *n += 1,
                _ => parts.push((part, 1)),
            }
            inner = outer;
        }
        let parts: Vec<String> = parts
            .into_iter()
            .map(|(p, n)| if n > 1 { format!("{p} ({n} times)") } else { p })
            .collect();
        Some(parts.join(", "))
    }

    /// A refusal at `range` of the line just run; the run stops.
    fn refuse(&mut self, code: Code, range: Range<usize>, message: String, help: &str) -> Flow {
        let (mut f, mut i) = (self.cur.prog.file, self.cur.pc.saturating_sub(1));
        if i >= self.lines[f].len() {
            // An empty subprogram file: at its call.
            (f, i) = self.cur.call;
        }
        let line = self.lines[f][i].0;
        let src = self.files[f];
        let message = match self.chain() {
            Some(c) => format!("{message} ({c})"),
            None => message,
        };
        let d = Diagnostic::new(code, message)
            .at(src, src.span_in_line(line, range))
            .help(help);
        self.events.push(Event::Diag(d));
        Flow::Stop
    }

    fn eval_error(&mut self, e: EvalError) -> Flow {
        let code = if e.machine {
            codes::FANR_MACHINE_VARIABLE
        } else {
            codes::FANR_MACRO
        };
        self.refuse(code, e.range, e.message, &e.help)
    }

    fn step(&mut self) -> Flow {
        if self.cur.pc >= self.cur.prog.end {
            if self.frames.is_empty() {
                return Flow::Stop;
            }
            let range = 0..0;
            let name = self.cur.name.clone();
            self.cur.pc = self.cur.prog.end.max(1);
            return self.refuse(
                codes::FANR_MACRO,
                range,
                format!("{name} ends without M99"),
                "end a subprogram with M99",
            );
        }
        let (f, i) = (self.cur.prog.file, self.cur.pc);
        self.cur.pc += 1;
        self.steps += 1;
        if self.steps > STEP_LIMIT {
            return self.refuse(
                codes::FANR_MACRO,
                0..0,
                format!("the program runs more than {STEP_LIMIT} lines: ncthread stops it here"),
                "a loop this long is not a part program ncthread can convert; check its condition",
            );
        }
        // A blank line is no block (as in the line-by-line reader).
        if self.lines[f][i].0.text.trim().is_empty() {
            return Flow::Next;
        }
        let Ok(l) = &self.lines[f][i].1 else {
            // Said up front; the run goes on past it, as the line-by-line reader does, so
            // that the rest of the program is checked too.
            let line = self.lines[f][i].0;
            if f == 0 && is_billet(line.text) {
                self.events.push(Event::Billet(line));
                return Flow::Next;
            }
            if f == 0 && Some(line.number) == self.title {
                self.events.push(Event::Title(line));
                return Flow::Next;
            }
            return Flow::Next;
        };
        let l = l.clone();
        if l.delimiter {
            // The main program's closing `%` ends it; a subprogram file's `%` is its frame.
            if self.frames.is_empty() {
                self.percents += 1;
            }
            return if self.percents >= 2 && self.frames.is_empty() {
                Flow::Stop
            } else {
                Flow::Next
            };
        }
        if let Some(range) = l.block_delete.clone()
            && !matches!(l.stmt, Stmt::Words(_))
        {
            return self.refuse(
                codes::FANR_UNSUPPORTED,
                range,
                "`/` before a macro statement: whether the operator's block skip switch skips it is not known".into(),
                "remove the `/`, or the statement",
            );
        }
        match self.statement(&l) {
            Ok(flow) => flow,
            Err(e) => self.eval_error(e),
        }
    }

    fn statement(&mut self, l: &MLine) -> Result<Flow, EvalError> {
        let truth = |r: &mut Self, c: &parse::Expr| -> Result<bool, EvalError> {
            Ok(parse::eval(c, &r.vars)?.is_some_and(|v| v != 0.0))
        };
        Ok(match &l.stmt {
            Stmt::Assign(t, e) => {
                self.assign(t, e)?;
                Flow::Next
            }
            Stmt::IfThen(c, t, e) => {
                if truth(self, c)? {
                    self.assign(t, e)?;
                }
                Flow::Next
            }
            Stmt::IfGoto(c, n) => {
                if truth(self, c)? {
                    return self.goto(n, l);
                }
                Flow::Next
            }
            Stmt::Goto(n) => return self.goto(n, l),
            Stmt::While(c, m) => {
                let go = match c {
                    Some(c) => truth(self, c)?,
                    None => true,
                };
                if go { Flow::Next } else { self.past_end(*m, l) }
            }
            Stmt::End(m) => self.back_to_do(*m, l),
            Stmt::Words(w) => return self.words(l, w),
        })
    }

    fn assign(&mut self, t: &parse::Target, e: &parse::Expr) -> Result<(), EvalError> {
        let v = parse::eval(e, &self.vars)?;
        let n = parse::index(&t.index, &self.vars)?;
        self.vars.set(n, v, &t.range)
    }
}

mod flow;

#[cfg(test)]
mod tests;

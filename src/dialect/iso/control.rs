//! LinuxCNC's O-words (`interp_o_word.cc`): where each `sub`, `if`, `while`, `do`,
//! `repeat`, `break`, `continue` and `return` sends control, found once per file, and the
//! parameters a running program reads and sets (numbered, named local and global, the
//! subroutine frames).

use std::collections::HashMap;
use std::ops::Range;

use super::expr::{EvalError, MAX_PARAMETER};
use super::syntax::{self, Block, Keyword, Label, OWord, SyntaxError};
use crate::source::{Line, SourceFile, Span};

/// Where an O-word line sends control.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Flow {
    /// `sub`: a definition, skipped when reached in sequence (to after `end`).
    Sub {
        end: usize,
    },
    /// `endsub` of the definition that starts at `start`.
    EndSub {
        start: usize,
    },
    /// `return` inside the definition that starts at `start`.
    Return {
        start: usize,
    },
    Call,
    /// `if`: its `elseif`/`else` lines in order, and its `endif`.
    If {
        branches: Vec<usize>,
        end: usize,
    },
    /// `elseif`/`else`: tested when a failed test before it sends control here (the next
    /// branch, if any, after it), else reached after a branch ran: on past the `endif`.
    Branch {
        next: Option<usize>,
        end: usize,
    },
    EndIf,
    While {
        end: usize,
    },
    EndWhile {
        start: usize,
    },
    /// `do`; its closing `while` is `close`.
    Do {
        close: usize,
    },
    /// The `while` that closes the `do` at `start`.
    DoWhile {
        start: usize,
    },
    Repeat {
        end: usize,
    },
    EndRepeat {
        start: usize,
    },
    /// `break`/`continue` of the loop that starts at `start` and ends at `end` (its
    /// `endwhile`, closing `while` or `endrepeat`).
    Break {
        start: usize,
        end: usize,
        /// The loop is a `repeat` (LinuxCNC refuses the line when it reaches it).
        repeat: bool,
    },
    Continue {
        start: usize,
        end: usize,
        repeat: bool,
    },
}

/// A structure error: the line and what is wrong (LinuxCNC refuses such a program).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct StructureError {
    pub line: usize,
    pub range: Range<usize>,
    pub message: String,
    pub help: &'static str,
}

/// The control flow of one file's O-word lines.
#[derive(Debug, Default)]
pub struct Structure {
    pub flow: HashMap<usize, Flow>,
    /// `o<name> sub` / `o100 sub`: the definition's first line.
    pub subs: HashMap<Label, usize>,
    /// For each O-word line, the next O-word line of the same label in the file: where
    /// LinuxCNC's skipping to a label stops (`break`, `continue`, a false `while`, a
    /// `repeat` that has run its count).
    pub next_same: HashMap<usize, usize>,
    pub errors: Vec<StructureError>,
}

struct Open {
    label: Label,
    keyword: Keyword,
    line: usize,
    range: Range<usize>,
    branches: Vec<usize>,
    /// Whether the last of `branches` is an `else`.
    after_else: bool,
    /// `break`/`continue` lines inside this loop, resolved at its end.
    exits: Vec<(usize, bool)>,
}

impl Open {
    fn new(i: usize, o: &OWord, keyword: Keyword) -> Open {
        Open {
            label: o.label.clone(),
            keyword,
            line: i,
            range: o.range.clone(),
            branches: Vec::new(),
            after_else: false,
            exits: Vec::new(),
        }
    }
}

/// Whether the innermost open block is a `k` of this label.
fn top_is(stack: &[Open], k: Keyword, label: &Label) -> bool {
    stack
        .last()
        .is_some_and(|t| t.keyword == k && t.label == *label)
}

impl Structure {
    /// The structure of a file's `blocks` (with their 0-based line numbers, in order; lines
    /// without an O-word may be left out).
    pub fn of<'b>(blocks: impl IntoIterator<Item = (usize, &'b Block)>) -> Structure {
        let mut s = Structure::default();
        let mut stack: Vec<Open> = Vec::new();
        let mut last: HashMap<Label, usize> = HashMap::new();
        for (i, block) in blocks {
            let Some(o) = block.oword.as_deref() else {
                continue;
            };
            if let Some(before) = last.insert(o.label.clone(), i) {
                s.next_same.insert(before, i);
            }
            s.line(&mut stack, i, o);
        }
        for t in stack {
            s.errors.push(StructureError {
                line: t.line,
                range: t.range,
                message: format!("{} {} is never closed", t.label, t.keyword.name()),
                help: "close it with its end (`endsub`, `endif`, `endwhile`, `while`, `endrepeat`) of the same label",
            });
        }
        s.errors.sort_by_key(|e| e.line);
        s
    }

    /// The O-word line `o` at line `i`, against the blocks open before it (`stack`): one
    /// step per keyword, each pairing the line with the open block it closes or belongs to.
    fn line(&mut self, stack: &mut Vec<Open>, i: usize, o: &OWord) {
        let label = &o.label;
        match o.keyword {
            Keyword::Sub => self.sub(stack, i, o),
            Keyword::EndSub => {
                if top_is(stack, Keyword::Sub, label) {
                    let t = stack.pop().expect("top");
                    self.flow.insert(t.line, Flow::Sub { end: i });
                    self.flow.insert(i, Flow::EndSub { start: t.line });
                } else {
                    self.error(
                        i,
                        o,
                        format!("{label} endsub does not close a {label} sub"),
                        "every `endsub` closes the `sub` of the same label, after every block inside it is closed",
                    );
                }
            }
            // LinuxCNC returns from the subroutine running, whatever the label (real
            // programs write the label of the `if` around it).
            Keyword::Return => match stack.iter().find(|t| t.keyword == Keyword::Sub) {
                Some(t) => {
                    self.flow.insert(i, Flow::Return { start: t.line });
                }
                None => self.error(
                    i,
                    o,
                    format!("{label} return is not inside a subroutine"),
                    "`return` ends the subroutine it stands in",
                ),
            },
            Keyword::Call => {
                self.flow.insert(i, Flow::Call);
            }
            Keyword::If | Keyword::Do | Keyword::Repeat => self.open(stack, i, o),
            Keyword::While if !top_is(stack, Keyword::Do, label) => self.open(stack, i, o),
            Keyword::ElseIf | Keyword::Else => self.branch(stack, i, o),
            Keyword::EndIf => self.endif(stack, i, o),
            // The `while` that closes a `do` of the same label.
            Keyword::While => {
                let t = stack.pop().expect("a do on top");
                self.flow.insert(t.line, Flow::Do { close: i });
                self.flow.insert(i, Flow::DoWhile { start: t.line });
                self.resolve_exits(&t, i);
            }
            Keyword::EndWhile | Keyword::EndRepeat => self.end_loop(stack, i, o),
            Keyword::Break | Keyword::Continue => self.exit(stack, i, o),
        }
    }

    fn error(&mut self, i: usize, o: &OWord, message: String, help: &'static str) {
        self.errors.push(StructureError {
            line: i,
            range: o.range.clone(),
            message,
            help,
        });
    }

    /// `if`, `do`, `repeat` and a `while` that opens a loop: not inside an open block of
    /// the same label in the same subroutine (or the program). LinuxCNC keeps one place per
    /// label there (`offset_map`): the inner line is reached, run or skipped to, and
    /// refused ("duplicate O-word label"), or, for a `do`, its `while` goes back to the
    /// outer one. **\[evidence\]** LinuxCNC 2.9 `interp_o_word.cc`,
    /// `convert_control_functions`.
    fn open(&mut self, stack: &mut Vec<Open>, i: usize, o: &OWord) {
        let label = &o.label;
        let inner = stack
            .iter()
            .rev()
            .take_while(|t| t.keyword != Keyword::Sub)
            .find(|t| t.label == *label);
        if let Some(outer) = inner {
            let outer = outer.keyword.name();
            self.error(
                i,
                o,
                format!(
                    "duplicate O-word label: {label} {} inside the {label} {outer} it would close or skip to",
                    o.keyword.name()
                ),
                "give the inner block a label of its own (LinuxCNC keeps one place per label in a subroutine)",
            );
        }
        stack.push(Open::new(i, o, o.keyword));
    }

    /// `sub`: a definition, not inside another, each name once.
    fn sub(&mut self, stack: &mut Vec<Open>, i: usize, o: &OWord) {
        let label = &o.label;
        if stack.iter().any(|t| t.keyword == Keyword::Sub) {
            self.error(
                i,
                o,
                format!("{label} sub inside another subroutine's definition"),
                "define each subroutine on its own, outside every other",
            );
        }
        if self.subs.insert(label.clone(), i).is_some() {
            self.error(
                i,
                o,
                format!("{label} is defined twice"),
                "give each subroutine its own name",
            );
        }
        stack.push(Open::new(i, o, Keyword::Sub));
    }

    /// `elseif` and `else`: a branch of the open `if` of the same label, none after its
    /// `else`.
    fn branch(&mut self, stack: &mut [Open], i: usize, o: &OWord) {
        let label = &o.label;
        if top_is(stack, Keyword::If, label) {
            let t = stack.last_mut().expect("top");
            let after_else = t.after_else;
            t.after_else = o.keyword == Keyword::Else;
            if after_else {
                self.error(
                    i,
                    o,
                    format!("{label} {} after {label} else", o.keyword.name()),
                    "`else` is the last branch of an `if`",
                );
            }
            t.branches.push(i);
        } else {
            self.error(
                i,
                o,
                format!("{label} {} without an open {label} if", o.keyword.name()),
                "`elseif` and `else` belong to the `if` of the same label",
            );
        }
    }

    /// `endif`: closes the open `if` of the same label and its branches.
    fn endif(&mut self, stack: &mut Vec<Open>, i: usize, o: &OWord) {
        let label = &o.label;
        if top_is(stack, Keyword::If, label) {
            let t = stack.pop().expect("top");
            for (k, &b) in t.branches.iter().enumerate() {
                let next = t.branches.get(k + 1).copied();
                self.flow.insert(b, Flow::Branch { next, end: i });
            }
            self.flow.insert(
                t.line,
                Flow::If {
                    branches: t.branches,
                    end: i,
                },
            );
            self.flow.insert(i, Flow::EndIf);
        } else {
            self.error(
                i,
                o,
                format!("{label} endif without an open {label} if"),
                "every `endif` closes the `if` of the same label",
            );
        }
    }

    /// `endwhile` and `endrepeat`: close the open `while` or `repeat` of the same label,
    /// and its `break`s and `continue`s.
    fn end_loop(&mut self, stack: &mut Vec<Open>, i: usize, o: &OWord) {
        let label = &o.label;
        let opener = if o.keyword == Keyword::EndWhile {
            Keyword::While
        } else {
            Keyword::Repeat
        };
        if top_is(stack, opener, label) {
            let t = stack.pop().expect("top");
            if opener == Keyword::While {
                self.flow.insert(t.line, Flow::While { end: i });
                self.flow.insert(i, Flow::EndWhile { start: t.line });
            } else {
                self.flow.insert(t.line, Flow::Repeat { end: i });
                self.flow.insert(i, Flow::EndRepeat { start: t.line });
            }
            self.resolve_exits(&t, i);
        } else {
            self.error(
                i,
                o,
                format!(
                    "{label} {} without an open {label} {}",
                    o.keyword.name(),
                    opener.name()
                ),
                "a loop's end closes the loop of the same label",
            );
        }
    }

    /// `break` and `continue`: of the innermost open loop of the same label, resolved at
    /// its end.
    fn exit(&mut self, stack: &mut [Open], i: usize, o: &OWord) {
        let label = &o.label;
        let is_loop = |k| matches!(k, Keyword::While | Keyword::Do | Keyword::Repeat);
        match stack
            .iter_mut()
            .rev()
            .find(|t| is_loop(t.keyword) && t.label == *label)
        {
            Some(t) => t.exits.push((i, o.keyword == Keyword::Break)),
            None => self.error(
                i,
                o,
                format!("{label} {} is not inside a {label} loop", o.keyword.name()),
                "`break` and `continue` belong to the `while`, `do` or `repeat` of the same label",
            ),
        }
    }

    fn resolve_exits(&mut self, t: &Open, end: usize) {
        let repeat = t.keyword == Keyword::Repeat;
        for &(line, brk) in &t.exits {
            let (start, end) = (t.line, end);
            self.flow.insert(
                line,
                if brk {
                    Flow::Break { start, end, repeat }
                } else {
                    Flow::Continue { start, end, repeat }
                },
            );
        }
    }
}

/// Whether a line is an O-word line to LinuxCNC: its first character that is not a blank is
/// an `o` (LinuxCNC reads such lines even in a branch it skips, and stops at one it cannot
/// read), whether or not ncthread can read the rest.
pub fn looks_like_oword(text: &str) -> bool {
    text.trim_start_matches([' ', '\t', '\r'])
        .starts_with(['o', 'O'])
}

/// Whether a line may hold an O-word: an `o` outside its comments (`( )`, and `;` to the
/// line's end). A comment line (a converted program's pass headings) is not read up front.
pub fn may_hold_oword(text: &str) -> bool {
    // Most lines hold no `o` at all: told eight bytes at a time (the run asks it of every
    // line of a text read as it comes).
    if !has_byte(text, |word| word | 0x2020_2020_2020_2020, b'o') {
        return false;
    }
    let mut in_comment = false;
    for b in text.bytes() {
        match b {
            b'(' => in_comment = true,
            b')' => in_comment = false,
            b';' if !in_comment => return false,
            b'o' | b'O' if !in_comment => return true,
            _ => {}
        }
    }
    false
}

/// The bytes of a line that are not blanks.
fn code(text: &str) -> impl Iterator<Item = u8> + '_ {
    text.bytes().filter(|b| !matches!(b, b' ' | b'\t' | b'\r'))
}

/// Whether a line is of blanks only (skipped).
pub fn is_blank(text: &str) -> bool {
    code(text).next().is_none()
}

/// Whether a line is a bare `%`.
pub fn is_percent(text: &str) -> bool {
    let mut c = code(text);
    c.next() == Some(b'%') && c.next().is_none()
}

/// A set of a file's lines (0-based), a bit each.
#[derive(Clone, Debug, Default)]
pub struct LineSet(Vec<u64>);

impl LineSet {
    /// Empty, for a file of `lines` lines.
    pub fn new(lines: usize) -> LineSet {
        LineSet(vec![0; lines.div_ceil(64)])
    }

    pub fn contains(&self, i: usize) -> bool {
        self.0.get(i / 64).is_some_and(|w| w >> (i % 64) & 1 == 1)
    }

    /// Adds line `i` (one past the words sized for the file is not kept).
    pub fn insert(&mut self, i: usize) {
        if let Some(w) = self.0.get_mut(i / 64) {
            *w |= 1 << (i % 64);
        }
    }
}

/// A line read into a block: `None` when it holds a NUL.
pub type ReadLine = Option<Result<Block, SyntaxError>>;

/// A line read ([`FileRun::block`]): one read up front, one of a body kept (shared, not
/// copied, each time it runs again), or one read for this run alone (the caller's to take).
// A line read for this run alone is moved on as it is: boxing it would cost an allocation
// a line, what sharing the kept lines saves.
#[allow(clippy::large_enum_variant)]
pub enum Got<'a> {
    Borrowed(&'a ReadLine),
    Shared(std::rc::Rc<ReadLine>),
    Owned(ReadLine),
}

impl std::ops::Deref for Got<'_> {
    type Target = ReadLine;

    fn deref(&self) -> &ReadLine {
        match self {
            Got::Borrowed(line) => line,
            Got::Shared(line) => line,
            Got::Owned(line) => line,
        }
    }
}

/// A file the run reads: the program, or a subroutine's file.
///
/// The lines that may hold an O-word (an `o` outside comments: the structure needs them
/// before the run, [`may_hold_oword`]) are read once, up front; every other line is read when it runs, and a line inside
/// a subroutine or a loop (it may run again) is kept once read, up to [`BODY_LINES_KEPT`]
/// of them, so that neither a long straight program nor one with many loops is held as
/// parsed blocks (issues 19 and 34).
pub struct FileRun<'s> {
    pub src: &'s SourceFile,
    /// How many lines the file has (each taken from `src` when asked: a table of them
    /// would take four times the text's line index).
    line_count: usize,
    /// The lines read up front (the O-word lines), by 0-based line, in order; `None`: the line holds a NUL. A long
    /// straight program has few: a table of every line would cost 8 bytes a line.
    read: Vec<(usize, Box<ReadLine>)>,
    pub structure: Structure,
    /// Where subroutines and loops start (0-based, in order), each with the last line that
    /// a body starting there or before reaches.
    bodies: Vec<(usize, usize)>,
    /// Body lines read so far ([`BODY_LINES_KEPT`] at most: forgotten all at once when full).
    kept: std::cell::RefCell<std::collections::HashMap<usize, std::rc::Rc<ReadLine>>>,
    /// Where the last look-ups in `read` and `bodies` ended: lines are mostly asked for in
    /// order, so the next answer is usually there or one further.
    hints: std::cell::Cell<(usize, usize)>,
    /// A text still being written, read as it comes ([`FileRun::following`]).
    follow: Option<Follow<'s>>,
}

/// The lines of a text still being written, taken in order as they come: the line last
/// taken is at hand, and the next one is taken when asked for.
struct Follow<'s> {
    lines: std::cell::RefCell<Box<dyn Iterator<Item = Line<'s>> + 's>>,
    /// The 0-based number of the line last taken, and that line (`None`: the text ended
    /// before it). `None` before the first.
    at: std::cell::Cell<Option<(usize, Option<Line<'s>>)>>,
}

impl<'s> Follow<'s> {
    /// Line `i`: `Some(None)` past the text's end; `None` when it is neither the line last
    /// taken nor the next one (the whole text's index must answer).
    fn get(&self, i: usize) -> Option<Option<Line<'s>>> {
        match self.at.get() {
            Some((j, line)) if j == i => Some(line),
            Some((j, None)) if i > j => Some(None),
            Some((j, Some(_))) if i == j + 1 => Some(self.take(i)),
            None if i == 0 => Some(self.take(0)),
            _ => None,
        }
    }

    fn take(&self, i: usize) -> Option<Line<'s>> {
        let line = self.lines.borrow_mut().next();
        self.at.set(Some((i, line)));
        line
    }
}

/// A line read into a block (an empty one past the file's end).
fn parse(line: Option<Line<'_>>) -> ReadLine {
    parse_into(line, Vec::new())
}

/// [`parse`], the words put into `words` (an earlier line's room, emptied first).
// Inlined: its answer, a block, is then made where the run holds it, not moved there.
#[inline]
fn parse_into(line: Option<Line<'_>>, words: Vec<syntax::Word>) -> ReadLine {
    let text = line.map_or("", |l| l.text);
    (!has_nul(text)).then(|| syntax::parse_line_into(text, words))
}

/// Whether a line holds a NUL: a short line looked at eight bytes at a time (a vector
/// search's setup is most of its cost on a line of a program), a long one searched.
fn has_nul(text: &str) -> bool {
    if text.len() > 64 {
        return memchr::memchr(0, text.as_bytes()).is_some();
    }
    has_byte(text, |word| word, 0)
}

/// Whether a byte of `text` is `byte` once `fold` has made it (`fold` maps each byte of an
/// eight-byte word alone, as `| 0x20` folds case): eight bytes at a time.
fn has_byte(text: &str, fold: impl Fn(u64) -> u64, byte: u8) -> bool {
    let bytes = text.as_bytes();
    let pattern = u64::from_le_bytes([byte; 8]);
    // A zero byte where the folded word has `byte`.
    let found = |word: u64| crate::source::zero_bytes(fold(word) ^ pattern) != 0;
    let mut words = bytes.chunks_exact(8);
    words.by_ref().any(|w| {
        let mut word = [0; 8];
        word.copy_from_slice(w);
        found(u64::from_le_bytes(word))
    }) || {
        let mut last = [0xff; 8];
        let rest = words.remainder();
        last[..rest.len()].copy_from_slice(rest);
        // The padding (0xff, folded 0xff) is never `byte`: both callers look for ASCII.
        found(u64::from_le_bytes(last))
    }
}

/// `v.partition_point(below)` for a `v` sorted by it, tried first at `hint` and one past it.
fn partition_from<T>(v: &[T], hint: usize, below: impl Fn(&T) -> bool) -> usize {
    for at in [hint, hint + 1] {
        let left_ok = at == 0 || v.get(at - 1).is_some_and(&below);
        let right_ok = v.get(at).is_none_or(|x| !below(x));
        if at <= v.len() && left_ok && right_ok {
            return at;
        }
    }
    v.partition_point(below)
}

/// How many lines of subroutine and loop bodies a [`FileRun`] keeps read: a loop this long
/// or shorter is read once, however often it runs; a longer one is read on each pass, as
/// LinuxCNC reads it.
pub const BODY_LINES_KEPT: usize = 4096;

impl<'s> FileRun<'s> {
    /// Line `i` (0-based) of the file.
    pub fn line(&self, i: usize) -> Line<'s> {
        if let Some(Some(line)) = self.follow.as_ref().and_then(|f| f.get(i)) {
            return line;
        }
        self.src.line(u32::try_from(i + 1).unwrap_or(u32::MAX))
    }

    /// Whether line `i` is of blanks only (skipped).
    pub fn blank(&self, i: usize) -> bool {
        is_blank(self.get_line(i).map_or("", |l| l.text))
    }

    /// Whether line `i` is a bare `%`.
    pub fn percent(&self, i: usize) -> bool {
        is_percent(self.get_line(i).map_or("", |l| l.text))
    }

    /// Line `i` (0-based), when the file has it.
    pub fn get_line(&self, i: usize) -> Option<Line<'s>> {
        if let Some(line) = self.follow.as_ref().and_then(|f| f.get(i)) {
            return line;
        }
        (i < self.line_count()).then(|| self.line(i))
    }

    /// How many lines the file has (a text still being written: once it has ended).
    pub fn line_count(&self) -> usize {
        if self.follow.is_some() {
            return self.src.line_count();
        }
        self.line_count
    }

    /// How many lines were looked at before the run: none for a text still being written.
    pub fn lines_up_front(&self) -> usize {
        if self.follow.is_some() {
            0
        } else {
            self.line_count
        }
    }

    /// Whether the file is a text still being written, read as it comes
    /// ([`FileRun::following`]).
    pub fn is_following(&self) -> bool {
        self.follow.is_some()
    }

    /// Whether a text read as it came was taken to its end (every line looked at).
    pub fn followed_to_end(&self) -> bool {
        self.follow
            .as_ref()
            .is_some_and(|f| matches!(f.at.get(), Some((_, None))))
    }

    /// The program's closing `%` line, when its first line (not blank) is a `%`: LinuxCNC's
    /// file ends there, so nothing after it is ever read, a definition included.
    /// **\[evidence\]** LinuxCNC `interp_read.cc` (`read_text`: a `%` line under the
    /// percent flag is the end of the file).
    pub fn closing_percent(&self) -> Option<usize> {
        let mut lines = (0..self.line_count()).filter(|&i| !self.blank(i) || self.percent(i));
        let first = lines.next()?;
        if !self.percent(first) {
            return None;
        }
        lines.find(|&i| self.percent(i))
    }

    pub fn new(src: &'s SourceFile) -> FileRun<'s> {
        let line_count = src.line_count();
        // One pass over the lines: what is read up front.
        let mut read: Vec<(usize, Box<ReadLine>)> = Vec::new();
        for (i, l) in src.lines().enumerate() {
            if may_hold_oword(l.text) {
                read.push((i, Box::new(parse(Some(l)))));
            }
        }
        let structure = Structure::of(read.iter().filter_map(|(i, line)| {
            let block = line.as_ref().as_ref()?.as_ref().ok()?;
            Some((*i, block))
        }));
        // Subroutine and loop bodies may run again: kept once read. Each start with the
        // last line any body starting there or before reaches.
        let mut bodies: Vec<(usize, usize)> = structure
            .flow
            .iter()
            .filter_map(|(&start, flow)| match *flow {
                Flow::Sub { end } | Flow::While { end } | Flow::Repeat { end } => {
                    Some((start, end))
                }
                Flow::Do { close } => Some((start, close)),
                _ => None,
            })
            .collect();
        bodies.sort_unstable();
        let mut reach = 0;
        for body in &mut bodies {
            reach = reach.max(body.1);
            body.1 = reach;
        }
        read.shrink_to_fit();
        FileRun {
            src,
            line_count,
            read,
            structure,
            bodies,
            kept: Default::default(),
            hints: Default::default(),
            follow: None,
        }
    }

    /// The run of a text still being written (a conversion's output, read back beside its
    /// writer), its lines read as they come with nothing read up front: no structure, no
    /// bodies. It holds only for a text in which no line may hold an O-word
    /// ([`may_hold_oword`]) — the run looks at each line before it runs it, and gives up at
    /// the first that may, to be read again by [`FileRun::new`] once the text has ended.
    pub fn following(src: &'s SourceFile) -> FileRun<'s> {
        FileRun {
            src,
            line_count: 0,
            read: Vec::new(),
            structure: Structure::default(),
            bodies: Vec::new(),
            kept: Default::default(),
            hints: Default::default(),
            follow: Some(Follow {
                lines: std::cell::RefCell::new(Box::new(src.lines())),
                at: std::cell::Cell::new(None),
            }),
        }
    }

    /// Line `i` read into a block; `None` when it holds a NUL.
    pub fn block(&self, i: usize) -> Got<'_> {
        self.block_with(i, || self.get_line(i), &mut Vec::new())
    }

    /// [`Self::block`] of line `i`, which is `line` (the run has it at hand: finding it
    /// again costs a search of the text's line index); a line read for this run alone takes
    /// its words' room from `spare` (an earlier line's: no allocation a line).
    pub fn block_of(&self, i: usize, line: Line<'s>, spare: &mut Vec<syntax::Word>) -> Got<'_> {
        self.block_with(i, || Some(line), spare)
    }

    /// Line `i` read into a block, its text from `line` when it must be read.
    fn block_with(
        &self,
        i: usize,
        line: impl FnOnce() -> Option<Line<'s>>,
        spare: &mut Vec<syntax::Word>,
    ) -> Got<'_> {
        let (hint, body_hint) = self.hints.get();
        let at = partition_from(&self.read, hint, |r| r.0 < i);
        self.hints.set((at, body_hint));
        match self.read.get(at).filter(|r| r.0 == i) {
            Some(r) => Got::Borrowed(&r.1),
            None if self.in_body(i) => {
                let mut kept = self.kept.borrow_mut();
                if let Some(line) = kept.get(&i) {
                    return Got::Shared(line.clone());
                }
                let read = std::rc::Rc::new(parse(line()));
                if kept.len() >= BODY_LINES_KEPT {
                    kept.clear();
                }
                kept.insert(i, read.clone());
                Got::Shared(read)
            }
            None => Got::Owned(parse_into(line(), std::mem::take(spare))),
        }
    }

    /// Whether line `i` is inside a subroutine or a loop.
    fn in_body(&self, i: usize) -> bool {
        let (hint, body_hint) = self.hints.get();
        let starts = partition_from(&self.bodies, body_hint, |&(start, _)| start <= i);
        self.hints.set((hint, starts));
        starts > 0 && i <= self.bodies[starts - 1].1
    }

    /// The subroutines of a file that holds definitions and nothing else (a library): every
    /// line outside `sub` … `endsub` is blank, a `%` or comments only. `None` for a program
    /// (or a file whose structure is broken).
    pub fn library(&self) -> Option<Vec<(String, crate::source::Span)>> {
        if self.structure.subs.is_empty() || !self.structure.errors.is_empty() {
            return None;
        }
        let mut i = 0;
        while i < self.line_count() {
            if let Some(Flow::Sub { end }) = self.structure.flow.get(&i) {
                i = end + 1;
                continue;
            }
            let only_comments =
                matches!(&*self.block(i), Some(Ok(b)) if b.is_empty() && b.number.is_none());
            if !(self.blank(i) || self.percent(i) || only_comments) {
                return None;
            }
            i += 1;
        }
        let mut subs: Vec<(usize, String)> = self
            .structure
            .subs
            .iter()
            .map(|(label, &line)| (line, label.to_string()))
            .collect();
        subs.sort();
        Some(
            subs.into_iter()
                .map(|(line, name)| (name, self.src.line_span(self.line(line))))
                .collect(),
        )
    }

    /// The lines read up front that cannot be read (0-based, in order).
    pub fn unreadable_up_front(&self) -> impl Iterator<Item = usize> + '_ {
        self.read
            .iter()
            .filter(|(_, line)| matches!(**line, Some(Err(_))))
            .map(|(i, _)| *i)
    }
}

/// The subroutines `src` calls that it does not define, read from `name.ngc` in the first
/// folder of `path` that has it (LinuxCNC's `SUBROUTINE_PATH`), and theirs in turn; and
/// for each name found nowhere, the call and why. At most [`MAX_FILES`] files.
pub fn load_externals(
    src: &SourceFile,
    path: &[std::path::PathBuf],
) -> (Vec<SourceFile>, Vec<(Span, String)>) {
    let mut files: Vec<SourceFile> = Vec::new();
    let mut errors = Vec::new();
    let mut known: std::collections::HashSet<String> = std::collections::HashSet::new();
    // (file index: 0 the program, else files[i - 1]) to scan.
    let mut queue = vec![0usize];
    while let Some(k) = queue.pop() {
        let file = if k == 0 { src } else { &files[k - 1] };
        let mut defined = std::collections::HashSet::new();
        let mut calls = Vec::new();
        for line in file.lines() {
            // An O-word line first (few are), then without a NUL.
            if !matches!(line.text.trim_start().as_bytes().first(), Some(b'o' | b'O'))
                || has_nul(line.text)
            {
                continue;
            }
            let Ok(b) = syntax::parse_line(line.text) else {
                continue;
            };
            let Some(o) = b.oword else { continue };
            let Label::Name(name) = &o.label else {
                continue;
            };
            match o.keyword {
                Keyword::Sub => {
                    defined.insert(name.clone());
                }
                Keyword::Call => {
                    calls.push((name.clone(), file.span_in_line(line, o.range.clone())))
                }
                _ => {}
            }
        }
        let mut found = Vec::new();
        for (name, span) in calls {
            if defined.contains(&name) || !known.insert(name.clone()) {
                continue;
            }
            if files.len() >= MAX_FILES {
                break;
            }
            let candidate = path
                .iter()
                .map(|dir| dir.join(format!("{name}.ngc")))
                .find(|p| p.is_file());
            let Some(candidate) = candidate else {
                // Not found: the call reports it when it runs, if it runs.
                continue;
            };
            match std::fs::read(&candidate) {
                Ok(bytes) => {
                    let legacy = crate::dialect::Dialect::legacy_encoding(&super::Iso);
                    let (text, _) = crate::encoding::decode_or(&bytes, legacy);
                    found.push(SourceFile::new(candidate.display().to_string(), text));
                }
                Err(e) if k == 0 => {
                    errors.push((span, format!("cannot read {}: {e}", candidate.display())))
                }
                Err(_) => {}
            }
        }
        for f in found {
            files.push(f);
            queue.push(files.len());
        }
    }
    (files, errors)
}

/// The most subroutine files one program reads.
pub const MAX_FILES: usize = 256;

/// A subroutine call in progress.
#[derive(Debug)]
pub struct Frame {
    pub name: Label,
    /// The file and line of the `call` (control comes back after it).
    pub file: usize,
    pub call_line: usize,
    /// The file the subroutine runs in.
    pub sub_file: usize,
    /// The caller's #1 … #30, restored at the return.
    pub saved: [f64; 30],
    /// Named local parameters.
    pub locals: HashMap<String, f64>,
}

/// Every parameter a program has set.
#[derive(Debug)]
pub struct Params {
    pub numbered: Vec<f64>,
    /// Named parameters of the main program (locals there live as long as the program).
    pub top: HashMap<String, f64>,
    /// Global named parameters (`#<_name>`).
    pub globals: HashMap<String, f64>,
    pub frames: Vec<Frame>,
    /// The count left of each `repeat` that has started and not run out, by its file and
    /// line. One table for the whole run, as LinuxCNC's `offset_map` holds one count per
    /// label: a subroutine that returns from inside a `repeat` leaves its count, and the
    /// next call of it goes on from there.
    pub repeats: HashMap<(usize, usize), i64>,
    /// `#<_value>` and whether the last subroutine returned one.
    pub value: f64,
    pub value_returned: bool,
    /// The `elseif`/`else` line a failed test sent control to: it tests (or runs).
    pub testing: Option<usize>,
    /// Control skipped to the O-word line it reaches next (LinuxCNC's `skipping_o`: a
    /// `break`, a `continue`, a false `while`, a `repeat` that has run its count).
    pub skipping: bool,
    /// LinuxCNC's `doing_break` and `doing_continue`: set by `break` and `continue`, and
    /// cleared only where 2.9's interpreter clears them (the end of a `do` loop that does
    /// not go round again; an `endwhile`/`endrepeat` reached by skipping), so that a flag
    /// left set changes a later loop exactly as it does in LinuxCNC.
    pub doing_break: bool,
    pub doing_continue: bool,
    /// Subroutine definitions (file, line) passed in sequence or called.
    pub passed: std::collections::HashSet<(usize, usize)>,
    /// The `if`, `do`, `repeat` and opening `while` lines run so far, by the subroutine
    /// they ran in (`None`: the program) and their label, with their file and line
    /// (LinuxCNC's `offset_map`, where a label has one place for the whole run).
    pub opened: HashMap<(Option<Label>, Label), (usize, usize)>,
    /// The modal state M70/M73 saved at each call level (0: the program), and whether the
    /// return from that level restores it (M73).
    pub contexts: HashMap<usize, (ModalState, bool)>,
}

/// What M70 and M73 save of the modal state that ncthread follows (LinuxCNC's
/// `save_settings`): modes, spindle, coolant, feed and speed. **\[evidence\]** rules of
/// `interp_convert.cc` (`gen_settings`, `gen_m_codes`).
#[derive(Clone, Debug, PartialEq)]
pub struct ModalState {
    pub inch: bool,
    pub incremental: bool,
    /// G93/G94/G95 as 930/940/950, `None` before any.
    pub feed_mode: Option<u32>,
    pub surface_speed: bool,
    pub absolute_centres: bool,
    pub diameter: Option<bool>,
    /// 3, 4 or 5.
    pub spindle: u8,
    pub mist: bool,
    pub flood: bool,
    /// In the units in force when saved.
    pub feed: f64,
    pub speed: f64,
    pub work_offset: u8,
    pub compensation: bool,
    /// G98 (true) or G99.
    pub retract_old_z: bool,
    /// G17 (true) or G18: LinuxCNC's `gen_settings` restores the plane (slot 3).
    pub plane_xy: bool,
}

impl Default for Params {
    fn default() -> Self {
        Params {
            numbered: vec![0.0; MAX_PARAMETER + 1],
            top: HashMap::new(),
            globals: HashMap::new(),
            frames: Vec::new(),
            repeats: HashMap::new(),
            value: 0.0,
            value_returned: false,
            testing: None,
            skipping: false,
            doing_break: false,
            doing_continue: false,
            passed: Default::default(),
            opened: HashMap::new(),
            contexts: HashMap::new(),
        }
    }
}

impl Params {
    pub fn locals(&self) -> &HashMap<String, f64> {
        self.frames.last().map_or(&self.top, |f| &f.locals)
    }

    pub fn locals_mut(&mut self) -> &mut HashMap<String, f64> {
        match self.frames.last_mut() {
            Some(f) => &mut f.locals,
            None => &mut self.top,
        }
    }

    /// A named parameter the program set (global or local), if any.
    pub fn named(&self, name: &str) -> Option<f64> {
        if name.starts_with('_') {
            self.globals.get(name).copied()
        } else {
            self.locals().get(name).copied()
        }
    }

    /// The line of the program (file 0) whose call runs the code in another file now.
    pub fn program_call_line(&self) -> Option<usize> {
        self.frames
            .iter()
            .find(|f| f.sub_file != 0)
            .filter(|f| f.file == 0)
            .map(|f| f.call_line)
    }

    /// The call chain for a diagnostic: `in o<thread> (called from line 12)`, innermost
    /// first.
    pub fn chain(&self, line_of: impl Fn(usize, usize) -> String) -> Option<String> {
        if self.frames.is_empty() {
            return None;
        }
        // A recursion's repeated calls are counted, not listed.
        let mut parts: Vec<(String, usize)> = Vec::new();
        for f in self.frames.iter().rev() {
            let part = format!("in {} called from {}", f.name, line_of(f.file, f.call_line));
            match parts.last_mut() {
                Some((last, n)) if *last == part => *n += 1,
                _ => parts.push((part, 1)),
            }
        }
        let parts: Vec<String> = parts
            .into_iter()
            .map(|(p, n)| if n > 1 { format!("{p} ({n} times)") } else { p })
            .collect();
        Some(parts.join(", "))
    }
}

/// An error of evaluation, as a structure-like error on its line.
pub fn eval_error(line: usize, e: EvalError) -> StructureError {
    StructureError {
        line,
        range: e.range,
        message: e.message,
        help: e.help,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dialect::iso::syntax::parse_line;

    #[test]
    fn a_nul_is_found_wherever_it_stands() {
        for len in 0..80 {
            for filler in ['a', '\u{1}', '\u{80}', 'ÿ'] {
                let text: String = std::iter::repeat_n(filler, len).collect();
                assert!(!has_nul(&text), "{len} {filler:?}");
                for at in 0..text.chars().count() {
                    let with: String = text
                        .chars()
                        .enumerate()
                        .map(|(i, c)| if i == at { '\0' } else { c })
                        .collect();
                    assert!(has_nul(&with), "{len} {filler:?} @{at}");
                    for o in ['o', 'O'] {
                        let with: String = text
                            .chars()
                            .enumerate()
                            .map(|(i, c)| if i == at { o } else { c })
                            .collect();
                        assert!(may_hold_oword(&with), "{len} {filler:?} {o} @{at}");
                        let in_comment = format!("({with})");
                        assert!(!may_hold_oword(&in_comment), "{in_comment:?}");
                    }
                }
                // Bytes that fold near an `o` are not one.
                for near in [
                    'n',
                    'p',
                    'N',
                    'P',
                    '/',
                    '\u{ef}',
                    '\u{4f}'.to_ascii_lowercase(),
                ] {
                    let with = format!("{text}{near}");
                    let expected = near.eq_ignore_ascii_case(&'o');
                    assert_eq!(may_hold_oword(&with), expected, "{with:?}");
                }
            }
        }
    }

    #[test]
    fn a_hinted_partition_point_is_the_partition_point() {
        let v = [1, 3, 3, 7, 9];
        for x in 0..11 {
            for hint in 0..8 {
                assert_eq!(
                    super::partition_from(&v, hint, |&e| e < x),
                    v.partition_point(|&e| e < x),
                    "{x} from {hint}"
                );
            }
        }
        assert_eq!(super::partition_from(&[] as &[i32], 3, |&e| e < 1), 0);
    }

    fn structure(text: &str) -> Structure {
        let blocks: Vec<Block> = text.lines().map(|l| parse_line(l).unwrap()).collect();
        Structure::of(blocks.iter().enumerate())
    }

    #[test]
    fn only_an_o_outside_comments_may_be_an_oword() {
        for (text, may) in [
            ("o100 sub", true),
            ("N10 O100 call", true),
            ("#<pos> = 1", true),
            ("(pass 1 of 5) G0 X1", false),
            ("G0 X1 ; to the corner", false),
            ("(a) o1 endsub (b)", true),
            ("G1 X[COS[1]]", true),
            ("(unclosed o", false),
        ] {
            assert_eq!(may_hold_oword(text), may, "{text}");
        }
    }

    #[test]
    fn a_line_set_holds_its_lines() {
        let mut set = LineSet::new(130);
        for i in [0, 63, 64, 129] {
            assert!(!set.contains(i));
            set.insert(i);
            assert!(set.contains(i));
        }
        set.insert(192);
        assert!(!set.contains(192) && !set.contains(1) && !set.contains(128));
        let src = SourceFile::new("t", "  \t\n %\r\n%%\nX1\n");
        let run = FileRun::new(&src);
        let flags: Vec<(bool, bool)> = (0..4).map(|i| (run.blank(i), run.percent(i))).collect();
        assert_eq!(
            flags,
            [(true, false), (false, true), (false, false), (false, false)]
        );
    }

    #[test]
    fn body_lines_are_kept_read_and_read_alike() {
        let text = "G0 X1\no1 sub\nG1 X[1+1]\no2 while [1 LT 0]\nG1 X3\no2 endwhile\nG1 X4\no1 endsub\nG0 X5\no3 repeat [2]\nG1 X6\no3 endrepeat\nG0 X7\n";
        let src = SourceFile::new("t", text);
        let run = FileRun::new(&src);
        let inside: Vec<usize> = (0..run.line_count()).filter(|&i| run.in_body(i)).collect();
        // The nested loop's end does not end the subroutine around it.
        assert_eq!(inside, [1, 2, 3, 4, 5, 6, 7, 9, 10, 11]);
        for i in 0..run.line_count() {
            let line = src.line(i as u32 + 1).text;
            let fresh = Some(parse_line(line));
            assert_eq!(*run.block(i), fresh, "{line}");
            assert_eq!(*run.block(i), fresh, "{line} again");
        }
        // Only the body lines that are not O-word lines are kept.
        assert_eq!(run.kept.borrow().len(), 4);
    }

    #[test]
    fn matches_every_block_by_its_label() {
        let s = structure(
            "o<t> sub\no1 while [1]\no1 break\no1 endwhile\no<t> return\no<t> endsub\no2 do\no2 continue\no2 while [0]\no3 if [1]\no3 elseif [2]\no3 else\no3 endif\no4 repeat [2]\no4 endrepeat\n",
        );
        assert!(s.errors.is_empty(), "{:?}", s.errors);
        assert_eq!(s.flow[&0], Flow::Sub { end: 5 });
        assert_eq!(s.flow[&1], Flow::While { end: 3 });
        assert_eq!(
            s.flow[&2],
            Flow::Break {
                start: 1,
                end: 3,
                repeat: false
            }
        );
        assert_eq!(s.flow[&4], Flow::Return { start: 0 });
        assert_eq!(s.flow[&6], Flow::Do { close: 8 });
        assert_eq!(
            s.flow[&7],
            Flow::Continue {
                start: 6,
                end: 8,
                repeat: false
            }
        );
        assert_eq!(
            s.flow[&9],
            Flow::If {
                branches: vec![10, 11],
                end: 12
            }
        );
        assert_eq!(s.flow[&13], Flow::Repeat { end: 14 });
        assert_eq!(s.subs[&Label::Name("t".into())], 0);
    }

    #[test]
    fn names_what_does_not_match() {
        let lines =
            |text: &str| -> Vec<usize> { structure(text).errors.iter().map(|e| e.line).collect() };
        assert_eq!(lines("o1 while [1]\no2 endwhile\n"), [0, 1]);
        assert_eq!(lines("o1 if [1]\no1 else\no1 elseif [1]\no1 endif\n"), [2]);
        assert_eq!(lines("o1 break\n"), [0]);
        assert_eq!(lines("o<a> sub\no<b> sub\no<b> endsub\no<a> endsub\n"), [1]);
        assert_eq!(lines("o<a> return\n"), [0]);
        // An opener inside an open block of its label, in the same subroutine.
        assert_eq!(lines("o1 if [1]\no1 if [1]\no1 endif\no1 endif\n"), [1]);
        assert!(lines("o1 do\no2 if [1]\no1 while [1]\no2 endif\n").contains(&2));
        // A subroutine's labels are its own.
        assert!(
            lines("o1 if [1]\no<s> sub\no1 if [1]\no1 endif\no<s> endsub\no1 endif\n").is_empty()
        );
        // One after the other is LinuxCNC's run to judge, not the structure's.
        assert!(lines("o1 if [1]\no1 endif\no1 if [1]\no1 endif\n").is_empty());
    }
}

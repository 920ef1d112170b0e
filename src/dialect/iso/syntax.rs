//! The RS274/NGC line syntax (`grammar/iso.pest`): one line in, one [`Block`] out.

use std::ops::Range;

use pest::Parser;
use pest_derive::Parser;

use super::expr::{Expr, ExprKind, Func, Op, Param};
use crate::fixed::Decimal;

mod fast;
#[cfg(test)]
use fast::fast_line;
use fast::fast_line_into;

#[derive(Parser)]
#[grammar = "../grammar/iso.pest"]
struct IsoParser;

/// `X26.618`: the address letter (upper case), the value, and the byte range in the line.
/// A value computed from parameters or an expression (`X#1`, `Z[#2 - 1]`) names its
/// expression in [`Block::exprs`]; its `value` is set when the front end evaluates it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Word {
    pub letter: char,
    pub value: Decimal,
    pub range: Range<usize>,
    pub expr: Option<usize>,
}

/// What [`Unread`] says of a line's leading `/`.
pub const BLOCK_DELETE: &str = "block delete `/`";

/// Something the line holds that ncthread does not read (block delete), with its range.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Unread {
    pub what: &'static str,
    pub range: Range<usize>,
}

/// A line's [`Unread`] parts: rare (a block delete), so held apart, that a block, which is
/// moved a few times a line, fits in 128 bytes (moved without a `memcpy` call).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
// The box is the point: one pointer in the block, the vector (three words) apart.
#[allow(clippy::box_collection)]
pub struct Unreads(Option<Box<Vec<Unread>>>);

impl Unreads {
    pub fn push(&mut self, unread: Unread) {
        self.0.get_or_insert_default().push(unread);
    }

    /// Takes out the part at `at` (when there is one).
    pub fn remove(&mut self, at: usize) -> Option<Unread> {
        let parts = self.0.as_mut()?;
        let part = (at < parts.len()).then(|| parts.remove(at));
        if parts.is_empty() {
            self.0 = None;
        }
        part
    }
}

impl std::ops::Deref for Unreads {
    type Target = [Unread];

    fn deref(&self) -> &[Unread] {
        self.0.as_deref().map_or(&[], Vec::as_slice)
    }
}

/// `#1 = 5`, `#<depth> = [#1 * 2]`
#[derive(Clone, Debug, PartialEq)]
pub struct Setting {
    pub param: Param,
    pub value: Expr,
    pub range: Range<usize>,
}

/// An O-word's label: `o100` (a number, without leading zeros) or `o<name>` (lower case,
/// blanks removed).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum Label {
    Number(String),
    Name(String),
}

impl std::fmt::Display for Label {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Label::Number(n) => write!(f, "o{n}"),
            Label::Name(n) => write!(f, "o<{n}>"),
        }
    }
}

/// The keyword of an O-word line.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Keyword {
    Sub,
    EndSub,
    Call,
    Return,
    If,
    ElseIf,
    Else,
    EndIf,
    While,
    EndWhile,
    Do,
    Repeat,
    EndRepeat,
    Break,
    Continue,
}

impl Keyword {
    fn parse(text: &str) -> Option<Keyword> {
        Some(match text.to_ascii_lowercase().as_str() {
            "sub" => Keyword::Sub,
            "endsub" => Keyword::EndSub,
            "call" => Keyword::Call,
            "return" => Keyword::Return,
            "if" => Keyword::If,
            "elseif" => Keyword::ElseIf,
            "else" => Keyword::Else,
            "endif" => Keyword::EndIf,
            "while" => Keyword::While,
            "endwhile" => Keyword::EndWhile,
            "do" => Keyword::Do,
            "repeat" => Keyword::Repeat,
            "endrepeat" => Keyword::EndRepeat,
            "break" => Keyword::Break,
            "continue" => Keyword::Continue,
            _ => return None,
        })
    }

    pub fn name(self) -> &'static str {
        match self {
            Keyword::Sub => "sub",
            Keyword::EndSub => "endsub",
            Keyword::Call => "call",
            Keyword::Return => "return",
            Keyword::If => "if",
            Keyword::ElseIf => "elseif",
            Keyword::Else => "else",
            Keyword::EndIf => "endif",
            Keyword::While => "while",
            Keyword::EndWhile => "endwhile",
            Keyword::Do => "do",
            Keyword::Repeat => "repeat",
            Keyword::EndRepeat => "endrepeat",
            Keyword::Break => "break",
            Keyword::Continue => "continue",
        }
    }
}

/// `o<name> call [1] [2]`: the label, the keyword, its bracketed arguments.
#[derive(Clone, Debug, PartialEq)]
pub struct OWord {
    pub label: Label,
    pub keyword: Keyword,
    pub args: Vec<Expr>,
    pub range: Range<usize>,
}

/// Everything a line holds, in the order written.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Block {
    pub number: Option<u32>,
    pub words: Vec<Word>,
    /// The expressions of computed word values ([`Word::expr`]).
    pub exprs: Vec<Expr>,
    /// Parameter settings: they take effect after the line is read.
    pub settings: Vec<Setting>,
    /// Boxed: few lines hold one, and every line's block is moved a few times as it is read.
    pub oword: Option<Box<OWord>>,
    /// Every `( )` and `;` comment, trimmed.
    pub comments: Vec<String>,
    pub unread: Unreads,
    /// A `%` line.
    pub delimiter: bool,
}

impl Block {
    /// Only a block number and/or comments.
    pub fn is_empty(&self) -> bool {
        self.words.is_empty()
            && self.unread.is_empty()
            && !self.delimiter
            && self.settings.is_empty()
            && self.oword.is_none()
    }
}

/// Why a line could not be read: the byte offset and what was found there.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SyntaxError {
    pub offset: usize,
    pub message: String,
}

/// The longest line LinuxCNC reads, in bytes (a CR included): its buffer is `LINELEN` = 255
/// bytes with the newline and the C string's end; a longer line stops it. **\[evidence\]**
/// LinuxCNC `rs274ngc_pre.cc` (`_read`: "Command too long"); rs274 refuses a line of 253.
pub const LINE_MAX: usize = 252;

/// A line longer than LinuxCNC reads ([`LINE_MAX`]), also one it skips.
pub fn too_long(line: &str) -> Option<SyntaxError> {
    (line.len() > LINE_MAX).then(|| SyntaxError {
        offset: line.floor_char_boundary(LINE_MAX),
        message: format!(
            "a line of {} bytes: LinuxCNC reads lines of up to {LINE_MAX} (\"Command too long\")",
            line.len()
        ),
    })
}

/// [`comment_error`]'s sibling for an O-word: LinuxCNC reads the label of every O-word line
/// it passes, also one it skips (`read_o`), up to a NUL: an `o` with no number or `<name>`
/// after it stops it. **\[evidence\]** LinuxCNC `interp_read.cc` (`read_items`, `read_o`).
pub fn skipped_label_error(line: &str) -> Option<SyntaxError> {
    let text = line.split('\0').next().unwrap_or("");
    // Blanks go (`close_and_downcase`); a block delete and a line number come first.
    let chars: Vec<(usize, char)> = text
        .char_indices()
        .filter(|(_, c)| !c.is_whitespace())
        .collect();
    let mut i = 0;
    if chars.get(i).is_some_and(|c| c.1 == '/') {
        i += 1;
    }
    if chars.get(i).is_some_and(|c| c.1.eq_ignore_ascii_case(&'n')) {
        i += 1;
        while chars
            .get(i)
            .is_some_and(|c| c.1.is_ascii_digit() || c.1 == '.')
        {
            i += 1;
        }
    }
    let (at, o) = *chars.get(i)?;
    if !o.eq_ignore_ascii_case(&'o') {
        return None;
    }
    match chars.get(i + 1) {
        Some((_, c)) if c.is_ascii_digit() || "+-.[#<".contains(*c) => None,
        next => Some(SyntaxError {
            offset: next
                .map_or(line.find('\0').unwrap_or(line.len()), |n| n.0)
                .max(at),
            message: if next.is_none() && line.contains('\0') {
                "an O-word cut short by a NUL character: LinuxCNC reads the line only up to it, and finds no number after the `o` (\"No characters found in reading real value\")".to_string()
            } else {
                "an `o` with no number or name after it: LinuxCNC cannot read the O-word's label"
                    .to_string()
            },
        }),
    }
}

/// What LinuxCNC's `close_and_downcase` refuses in a line: a `(` inside a comment ("Nested
/// comment found", at that `(`) or a comment the line does not close ("Unclosed comment
/// found", at its `(`); a `;` outside a comment makes the rest of the line a comment. It
/// reads every line it meets, also one it then skips (a subroutine's definition, a branch
/// not taken), and up to a NUL only (the line is a C string). **\[evidence\]** LinuxCNC
/// `interp_internal.cc`, `close_and_downcase`.
pub fn comment_error(line: &str) -> Option<SyntaxError> {
    let text = line.split('\0').next().unwrap_or("");
    let mut open: Option<usize> = None;
    for (i, c) in text.char_indices() {
        match (open, c) {
            (None, ';') => return None,
            (None, '(') => open = Some(i),
            (Some(_), ')') => open = None,
            (Some(_), '(') => {
                return Some(SyntaxError {
                    offset: i,
                    message:
                        "a comment inside a comment: LinuxCNC refuses it (\"Nested comment found\")"
                            .into(),
                });
            }
            _ => {}
        }
    }
    open.map(|offset| SyntaxError {
        offset,
        message:
            "the comment is not closed with `)`: LinuxCNC refuses it (\"Unclosed comment found\")"
                .into(),
    })
}

/// Parses one line (without its line ending).
pub fn parse_line(line: &str) -> Result<Block, SyntaxError> {
    parse_line_into(line, Vec::new())
}

/// [`parse_line`], its words put into `words` (the room of a line read before; what it
/// still holds is dropped).
pub fn parse_line_into(line: &str, words: Vec<Word>) -> Result<Block, SyntaxError> {
    if let Some(e) = too_long(line) {
        return Err(e);
    }
    match fast_line_into(line, words) {
        Some(block) => Ok(block),
        None => parse_with_grammar(line),
    }
}

/// Parses one line with the grammar: the reading of every line the fast path declines, and
/// the source of every syntax error.
fn parse_with_grammar(line: &str) -> Result<Block, SyntaxError> {
    check_expression_size(line)?;
    let mut pairs = IsoParser::parse(Rule::line, line).map_err(|e| syntax_error(line, &e))?;
    let line_pair = pairs
        .next()
        .expect("the grammar's `line` rule always yields one pair");
    let mut block = Block::default();
    for pair in line_pair.into_inner() {
        match pair.as_rule() {
            Rule::delimiter => block.delimiter = true,
            Rule::block => {}
            _ => continue,
        }
        for part in pair.into_inner() {
            let span = part.as_span();
            let range = span.start()..span.end();
            match part.as_rule() {
                Rule::block_number => {
                    let digits = part.into_inner().next().expect("block_number has digits");
                    block.number = digits.as_str().parse().ok();
                }
                Rule::block_delete => block.unread.push(Unread {
                    what: BLOCK_DELETE,
                    range,
                }),
                Rule::parameter_setting => {
                    let mut inner = part.into_inner();
                    let target = inner.next().expect("a setting names a parameter");
                    let value = inner.next().expect("a setting has a value");
                    block.settings.push(Setting {
                        param: param_of(target, range.start..range.start + 1)?,
                        value: real_value(value)?,
                        range,
                    });
                }
                Rule::oword => block.oword = Some(Box::new(oword_of(part, range, &mut block)?)),
                Rule::word => word_of(part, range, &mut block)?,
                Rule::comment | Rule::semicolon_comment => {
                    let text = part.into_inner().next().map_or("", |t| t.as_str());
                    block.comments.extend(crate::dialect::comment_text(text));
                }
                _ => {}
            }
        }
    }
    Ok(block)
}

/// An O-word (`o100 while [#1 LT 5]`): its label, keyword and arguments; its comments go
/// to the block's.
fn oword_of(part: Pair<'_>, range: Range<usize>, block: &mut Block) -> Result<OWord, SyntaxError> {
    let mut inner = part.into_inner();
    let label = inner.next().expect("an O-word has a label");
    let label = match label.as_rule() {
        Rule::name => Label::Name(name_of(label)),
        _ => Label::Number(label.as_str().trim_start_matches('0').to_string()),
    };
    let keyword = inner.next().expect("an O-word has a keyword");
    let text: String = keyword
        .as_str()
        .chars()
        .filter(|c| !c.is_whitespace())
        .collect();
    let Some(keyword) = Keyword::parse(&text) else {
        return Err(SyntaxError {
            offset: keyword.as_span().start(),
            message: format!(
                "`{}` is not an O-word keyword (sub, endsub, call, return, if, elseif, else, endif, while, endwhile, do, repeat, endrepeat, break, continue)",
                keyword.as_str()
            ),
        });
    };
    let mut args = Vec::new();
    for arg in inner {
        match arg.as_rule() {
            Rule::bracket => args.push(bracket(arg)?),
            Rule::comment | Rule::semicolon_comment => {
                let text = arg.into_inner().next().map_or("", |t| t.as_str());
                block.comments.extend(crate::dialect::comment_text(text));
            }
            _ => {}
        }
    }
    Ok(OWord {
        label,
        keyword,
        args,
        range,
    })
}

/// A word (`X26.618`, `Z#1`, `X[#2 - 1]`) into the block: a number as its decimal, a
/// computed value as its expression (in [`Block::exprs`]).
fn word_of(part: Pair<'_>, range: Range<usize>, block: &mut Block) -> Result<(), SyntaxError> {
    let mut inner = part.into_inner();
    let letter = inner.next().expect("word has an address").as_str();
    let letter = letter.chars().next().unwrap_or('?').to_ascii_uppercase();
    let value = inner.next().expect("word has a value");
    if value.as_rule() == Rule::real_value {
        block.exprs.push(real_value(value)?);
        block.words.push(Word {
            letter,
            value: Decimal::default(),
            range,
            expr: Some(block.exprs.len() - 1),
        });
        return Ok(());
    }
    match Decimal::parse(value.as_str()) {
        Some(value) => {
            block.words.push(Word {
                letter,
                value,
                range,
                expr: None,
            });
            Ok(())
        }
        None => Err(SyntaxError {
            offset: range.start,
            message: format!("`{}` has too many digits", value.as_str()),
        }),
    }
}

/// The deepest nesting of brackets and parameters (`[[…]]`, `##1`) a line may hold, and
/// the most of them: LinuxCNC reads lines of at most 256 characters, so no program it runs
/// comes near; a hostile line must not exhaust the stack of the recursive reader.
const MAX_NESTING: usize = 64;
const MAX_EXPRESSION_PARTS: usize = 1024;

fn check_expression_size(line: &str) -> Result<(), SyntaxError> {
    let (mut depth, mut hashes, mut parts) = (0usize, 0usize, 0usize);
    let mut in_comment = false;
    for (i, c) in line.char_indices() {
        match c {
            '(' => in_comment = true,
            ')' => in_comment = false,
            ';' if !in_comment => break,
            _ if in_comment => {}
            '[' => {
                depth += 1;
                parts += 1;
            }
            ']' => depth = depth.saturating_sub(1),
            '#' => {
                hashes += 1;
                parts += 1;
            }
            ' ' | '\t' => {}
            _ => {
                hashes = 0;
                if depth > 0 {
                    parts += 1;
                }
            }
        }
        if depth + hashes > MAX_NESTING || parts > MAX_EXPRESSION_PARTS {
            return Err(SyntaxError {
                offset: i,
                message: format!(
                    "an expression nested deeper than {MAX_NESTING} levels or longer than {MAX_EXPRESSION_PARTS} characters: ncthread does not read it (LinuxCNC reads lines of at most 256 characters)"
                ),
            });
        }
    }
    Ok(())
}

type Pair<'i> = pest::iterators::Pair<'i, Rule>;

fn range_of(pair: &Pair<'_>) -> Range<usize> {
    pair.as_span().start()..pair.as_span().end()
}

/// `<My Name>` → `myname`: LinuxCNC removes blanks and lowers the case.
fn name_of(pair: Pair<'_>) -> String {
    name_text(pair.as_str())
}

/// A name's text as written (`<My Name>`) as LinuxCNC keeps it (`myname`).
fn name_text(text: &str) -> String {
    text.trim_start_matches('<')
        .trim_end_matches('>')
        .chars()
        .filter(|c| !c.is_whitespace())
        .flat_map(char::to_lowercase)
        .collect()
}

fn number_of(pair: &Pair<'_>) -> Result<f64, SyntaxError> {
    pair.as_str().parse().map_err(|_| SyntaxError {
        offset: pair.as_span().start(),
        message: format!("`{}` is not a number", pair.as_str()),
    })
}

/// The parameter after `#`: a name, a number, a bracket or another parameter.
fn param_of(pair: Pair<'_>, hash: Range<usize>) -> Result<Param, SyntaxError> {
    let range = hash.start..pair.as_span().end();
    Ok(match pair.as_rule() {
        Rule::name => Param::Named(name_of(pair)),
        Rule::unsigned => Param::Numbered(Box::new(Expr {
            kind: ExprKind::Number(number_of(&pair)?),
            range,
        })),
        Rule::bracket => Param::Numbered(Box::new(bracket(pair)?)),
        _ => Param::Numbered(Box::new(parameter(pair)?)),
    })
}

/// `#…`
fn parameter(pair: Pair<'_>) -> Result<Expr, SyntaxError> {
    let range = range_of(&pair);
    let inner = pair.into_inner().next().expect("# names a parameter");
    Ok(Expr {
        kind: ExprKind::Param(param_of(inner, range.start..range.start + 1)?),
        range,
    })
}

/// `[…]`
fn bracket(pair: Pair<'_>) -> Result<Expr, SyntaxError> {
    let expression = pair
        .into_inner()
        .next()
        .expect("a bracket holds an expression");
    let mut operands = Vec::new();
    let mut ops = Vec::new();
    for part in expression.into_inner() {
        match part.as_rule() {
            Rule::operator => ops.push(Op::parse(part.as_str()).expect("the grammar's operators")),
            _ => operands.push(real_value(part)?),
        }
    }
    Ok(Expr::binary(operands, ops))
}

/// A value: an optional sign and a number, parameter, bracket or function.
fn real_value(pair: Pair<'_>) -> Result<Expr, SyntaxError> {
    let range = range_of(&pair);
    let mut negative = false;
    let mut value = None;
    for part in pair.into_inner() {
        match part.as_rule() {
            Rule::sign => negative = part.as_str() == "-",
            Rule::unsigned => {
                value = Some(Expr {
                    kind: ExprKind::Number(number_of(&part)?),
                    range: range_of(&part),
                })
            }
            Rule::bracket => value = Some(bracket(part)?),
            Rule::parameter => value = Some(parameter(part)?),
            Rule::function => value = Some(function(part)?),
            _ => {}
        }
    }
    let value = value.expect("a value has a body");
    Ok(if negative {
        Expr {
            kind: ExprKind::Negate(Box::new(value)),
            range,
        }
    } else {
        value
    })
}

fn function(pair: Pair<'_>) -> Result<Expr, SyntaxError> {
    let range = range_of(&pair);
    let mut inner = pair.into_inner();
    let first = inner.next().expect("a function has a body");
    let kind = match first.as_rule() {
        Rule::atan => {
            let mut args = first.into_inner();
            let y = bracket(args.next().expect("ATAN's [y]"))?;
            let x = bracket(args.next().expect("ATAN's [x]"))?;
            ExprKind::Atan(Box::new(y), Box::new(x))
        }
        Rule::exists => {
            let name = first.into_inner().next().expect("EXISTS names a parameter");
            ExprKind::Exists(name_of(name))
        }
        _ => {
            let f = Func::parse(first.as_str()).expect("the grammar's functions");
            let arg = bracket(inner.next().expect("a function's argument"))?;
            ExprKind::Unary(f, Box::new(arg))
        }
    };
    Ok(Expr { kind, range })
}

fn syntax_error(line: &str, e: &pest::error::Error<Rule>) -> SyntaxError {
    let offset = crate::dialect::pest_error_offset(line, e);
    let rest = &line[offset..];
    let message = match rest.chars().next() {
        None => "the line ends where a value was expected".to_string(),
        Some('(') => match rest[1..].find(['(', ')']).map(|i| &rest[1 + i..1 + i + 1]) {
            Some("(") => {
                "a comment inside a comment: LinuxCNC refuses it (\"Nested comment found\")"
                    .to_string()
            }
            _ => "the comment is not closed with `)`".to_string(),
        },
        Some(c) if c.is_ascii_alphabetic() => {
            format!("address `{c}` is not followed by a number")
        }
        Some(c) if c.is_ascii_digit() || c == '.' || c == '-' || c == '+' => format!(
            "number `{}` does not belong to an address",
            rest.split([' ', '\t']).next().unwrap_or(rest)
        ),
        Some(c) => format!("unexpected character `{c}`"),
    };
    SyntaxError { offset, message }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn letters(b: &Block) -> String {
        b.words.iter().map(|w| w.letter).collect()
    }

    #[test]
    fn reads_words_comments_and_numbers() {
        let b = parse_line("N20 g33 X35.6 z-47.5 K1.5 (pass 1) ; rest").unwrap();
        assert_eq!(b.number, Some(20));
        assert_eq!(letters(&b), "GXZK");
        assert_eq!(b.words[0].value, Decimal::parse("33").unwrap());
        assert_eq!(b.words[1].range, 8..13);
        assert_eq!(b.comments, ["pass 1", "rest"]);
        let b = parse_line("G33.1Z-10K1.25").unwrap();
        assert_eq!(letters(&b), "GZK");
        assert_eq!(b.words[0].value, Decimal::parse("33.1").unwrap());
        let b = parse_line("G0 X 10 Z.5").unwrap();
        assert_eq!(letters(&b), "GXZ");
    }

    #[test]
    fn finds_the_comments_linuxcnc_refuses() {
        assert_eq!(comment_error("G0 X1 (a) ; (b"), None);
        assert_eq!(comment_error("(a ; b)"), None);
        let e = comment_error("  (  (#1 the groove)").unwrap();
        assert_eq!(e.offset, 5);
        assert!(e.message.contains("Nested comment found"), "{}", e.message);
        let e = comment_error("G0 (  G0 X1 Z1").unwrap();
        assert_eq!(e.offset, 3);
        assert!(
            e.message.contains("Unclosed comment found"),
            "{}",
            e.message
        );
        // A NUL ends the line for LinuxCNC.
        assert!(comment_error("(a\0)").is_some());
        assert_eq!(comment_error("G0\0("), None);
    }

    #[test]
    fn reads_delimiters_and_comment_lines() {
        assert!(parse_line("%").unwrap().delimiter);
        let b = parse_line("  (only a comment)").unwrap();
        assert!(b.is_empty());
        assert_eq!(b.comments, ["only a comment"]);
        assert!(parse_line("").unwrap().is_empty());
    }

    #[test]
    fn reads_parameters_expressions_and_o_words() {
        let b = parse_line("#1 = 5 #<My Depth> = [#1 * 2]").unwrap();
        assert_eq!(b.settings.len(), 2);
        assert_eq!(b.settings[1].param, Param::Named("mydepth".into()));
        let b = parse_line("G0 X#1 Z[2*3] K-#<p>").unwrap();
        assert_eq!(b.exprs.len(), 3);
        assert_eq!(b.words[1].expr, Some(0));
        assert_eq!(b.words[2].range, 7..13);
        assert!(b.unread.is_empty());
        let b = parse_line("o<Thread> call [1] [2 + #3] (comment)").unwrap();
        let o = b.oword.unwrap();
        assert_eq!(o.label, Label::Name("thread".into()));
        assert_eq!(o.keyword, Keyword::Call);
        assert_eq!(o.args.len(), 2);
        assert_eq!(b.comments, ["comment"]);
        let b = parse_line("o100 end sub").unwrap();
        assert_eq!(b.oword.as_ref().unwrap().keyword, Keyword::EndSub);
        assert!(
            parse_line("o100 endsubb")
                .unwrap_err()
                .message
                .contains("not an O-word keyword")
        );
        let b = parse_line("O0100 while [#1 LT 3]").unwrap();
        assert_eq!(b.oword.unwrap().label, Label::Number("100".into()));
        let b = parse_line("G0 X[ATAN[1]/[1] + ABS[-2] ** 2 MOD 3]").unwrap();
        assert_eq!(b.exprs.len(), 1);
        let mut b = parse_line("/G0 X1").unwrap();
        assert_eq!(b.unread[0].what, "block delete `/`");
        assert_eq!(b.unread.remove(1), None);
        assert_eq!(b.unread.remove(0).map(|u| u.range), Some(0..1));
        assert!(b.unread.is_empty() && b.unread == Unreads::default());
        // A block is moved a few times a line: in 128 bytes, without a `memcpy` call.
        assert!(std::mem::size_of::<Block>() <= 128);
        // O-words take nothing but brackets and a comment.
        assert!(parse_line("o100 call G0").is_err());
        // A hostile nesting is refused, not a stack overflow.
        // (Past LinuxCNC's line length, which the grammar never sees.)
        let deep = format!("G0 X{}1{}", "[".repeat(100_000), "]".repeat(100_000));
        assert!(
            parse_line(&deep)
                .unwrap_err()
                .message
                .contains("Command too long")
        );
        assert!(
            parse_with_grammar(&deep)
                .unwrap_err()
                .message
                .contains("nested deeper")
        );
        let hashes = format!("G0 X{}1", "#".repeat(100_000));
        assert!(parse_line(&hashes).is_err());
        let long = format!("G0 X[{}1]", "1+".repeat(100_000));
        assert!(parse_line(&long).is_err());
    }

    #[test]
    fn points_at_the_bad_character() {
        let e = parse_line("G0 X").unwrap_err();
        assert_eq!(e.offset, 3);
        assert!(e.message.contains("`X`"), "{}", e.message);
        let e = parse_line("G0 X1 (open").unwrap_err();
        assert_eq!(e.offset, 6);
        assert!(e.message.contains("not closed"), "{}", e.message);
        let e = parse_line("((nested)").unwrap_err();
        assert_eq!(e.offset, 0);
        assert!(e.message.contains("Nested comment"), "{}", e.message);
        let e = parse_line("G0 12").unwrap_err();
        assert_eq!(e.offset, 3);
    }

    const TOKENS: &[&str] = &[
        " ",
        "\t",
        "\r",
        "/",
        "N",
        "n",
        "10",
        "0",
        "99999999999",
        ".5",
        "G",
        "x",
        "Z",
        "F",
        "-",
        "+",
        ".",
        "5",
        "26.618",
        "(",
        ")",
        "(AB)",
        ";",
        "%",
        "é",
        "#",
        "O",
        "o",
        "[",
        "]",
        "#1",
        "=",
        "sub",
        "<",
        ">",
        "<a b>",
        "#<P>",
        "##",
        "*",
        "**",
        "/",
        "mod",
        "LE",
        "gt",
        "and",
        "Or",
        "xor",
        "while",
        "end while",
        "if",
        "call",
        "abs",
        "atan",
        "[1]",
        "[#<x> + 1]",
        "x[",
        "o1 ",
        "O100 while ",
        "endwhile",
        "#1=",
        "#<a>=",
        "X[",
        "[#1",
        "+1]",
        " LE ",
        "-[",
        "]]",
    ];

    /// Lines of the macro language as programs write them, and near misses: where the fast
    /// path reads one, it reads what the grammar does (ranges included).
    #[test]
    fn the_fast_path_reads_expressions_as_the_grammar_does() {
        let lines = [
            "#<pass> = 1",
            "#<pass> = [#<pass> + 1]",
            "o100 while [#<pass> LE 4]",
            "O100 ENDWHILE",
            "G0 X[30 - #<pass> * 0.25] Z5",
            "N10 #1=5 G1 X#1 Z-#<z> F[#2/2]",
            "/ o<my sub> call [1] [-2.5] [#3] (args)",
            "o0100 if [#1 EQ 2 AND #2 GT 3] ; why",
            "#[1 + 2] = ##1",
            "# 5 = - [ 2 ** 3 mod 5 ]",
            "X - #1",
            "X-[1]",
            "X+#1",
            "o 1 2 sub",
            "#<a> = [1 - -2]",
            "#<a> = [1 --2]",
            "#1 = [2 * 3 + 4 / 5 - 6]",
            "o100 sub [1",
            "o100 sub X5",
            "o100",
            "G0 o100 sub",
            "#<> = 1",
            "#<a<b> = 1",
            "X[1 2]",
            "X[abs[-1]]",
            "X[1.2.3]",
            "#1 = 5.",
            "#1 = .5",
            "#1 = .",
            "X[#1]]",
            "o100 while [1] (a) (b)",
            "o100 while [1];(a)",
            "o<A\u{e9}> call",
            "#1 = 1e5",
            "X [1]",
            "X - [1]",
            "X#1=5",
            "G0 O5",
            "o1.5 sub",
            "o0 sub",
            "N10.5 /o1 sub",
            "X[1\r+\r2]",
            "#<a(b> = [[1]]",
            "[5mod3]",
            "#1=[#1and#2]",
        ];
        for line in lines {
            let grammar = parse_with_grammar(line);
            if let Some(fast) = fast_line(line) {
                assert_eq!(Ok(fast), grammar, "{line:?}");
            }
            // Into the room an earlier line's words left, even with those words still in it:
            // the same block.
            let room = parse_line("G1 X1 Z2 F3 K4 I5").map_or_else(|_| Vec::new(), |b| b.words);
            assert_eq!(room.len(), 6);
            assert_eq!(
                parse_line_into(line, room),
                parse_line(line),
                "{line:?} (into room)"
            );
        }
        for line in &lines[..13] {
            assert!(fast_line(line).is_some(), "the fast path declines {line:?}");
        }
    }

    crate::dialect::lex::agreement_tests!(fast_line, parse_with_grammar, TOKENS);
}

//! The НЦ-31 frame syntax (`grammar/nc31.pest`): one line in, one [`Line`] out.

use std::ops::Range;

use pest::Parser;
use pest_derive::Parser;

use crate::diag::Code;
use crate::dialect::lex::{Cursor, blank_or_tab};
use crate::dialect::nc31::codes;

#[derive(Parser)]
#[grammar = "../grammar/nc31.pest"]
struct Nc31Parser;

/// The most digits a word may have: more than any НЦ-31 word, few enough that scaling by
/// any unit stays exact in 64 bits.
const MAX_DIGITS: usize = 12;

/// `X3600`: the address letter (upper case), the integer value, and its byte range.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Word {
    pub letter: char,
    pub value: i64,
    pub range: Range<usize>,
}

/// A frame modifier.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Modifier {
    /// `~`: the move is a rapid.
    Rapid,
    /// `*`: the next frame belongs to the same group.
    Group,
    /// `@`: the coordinate is incremental (on G33: move to X afterwards).
    Incremental,
    /// `+45` / `-45` (`up`: `+45`): a 45° chamfer to this X or Z, the other axis moving
    /// the same radial amount in the sign's direction. **\[evidence\]** nc31.md, "General
    /// motion".
    Chamfer { up: bool },
}

impl Modifier {
    pub fn ascii(self) -> &'static str {
        match self {
            Modifier::Rapid => "~",
            Modifier::Group => "*",
            Modifier::Incremental => "@",
            Modifier::Chamfer { up: true } => "+45",
            Modifier::Chamfer { up: false } => "-45",
        }
    }

    /// Whether `self` and `other` are the same mark (both chamfer signs are one mark).
    fn same_kind(self, other: Modifier) -> bool {
        std::mem::discriminant(&self) == std::mem::discriminant(&other)
    }
}

/// One frame: optional number, at most one word, its modifiers.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Frame {
    pub number: Option<u32>,
    pub word: Option<Word>,
    /// In the order written, with their byte ranges.
    pub modifiers: smallvec::SmallVec<[(Modifier, Range<usize>); 2]>,
    /// The frame without leading and trailing blanks.
    pub code_range: Range<usize>,
}

impl Frame {
    pub fn has(&self, m: Modifier) -> bool {
        self.modifiers.iter().any(|(x, _)| *x == m)
    }

    pub fn modifier_range(&self, m: Modifier) -> Option<Range<usize>> {
        self.modifiers
            .iter()
            .find(|(x, _)| *x == m)
            .map(|(_, r)| r.clone())
    }

    /// The chamfer mark (`+45`: true), and where it is.
    pub fn chamfer(&self) -> Option<(bool, Range<usize>)> {
        self.modifiers.iter().find_map(|(m, r)| match m {
            Modifier::Chamfer { up } => Some((*up, r.clone())),
            _ => None,
        })
    }
}

/// What one line holds.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Line {
    /// Blank.
    Empty,
    /// `(` comment line: the text after `(` (a closing `)` removed).
    Comment(String),
    /// `%`
    Delimiter,
    Frame(Frame),
}

/// Why a line cannot be read: the code, where (bytes in the line), what and how to fix it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SyntaxError {
    pub code: Code,
    pub range: Range<usize>,
    pub message: String,
    pub help: String,
}

const FRAME_HELP: &str = "a frame is `N<number>`, one word (a letter and a whole number: `X3600`, `Z-4750`), then modifiers `~` (rapid), `*` (group continues), `@` (incremental)";

/// Parses one line (without its line ending).
pub fn parse_line(line: &str) -> Result<Line, SyntaxError> {
    match fast_line(line) {
        Some(parsed) => Ok(parsed),
        None => parse_with_grammar(line),
    }
}

/// The grammar's reading of a well-formed line without pest (see `dialect::lex`), or `None`.
fn fast_line(line: &str) -> Option<Line> {
    let mut c = Cursor::new(line);
    c.skip(blank_or_tab);
    match c.peek() {
        None => return Some(Line::Empty),
        Some(b'(') => {
            let text = c.rest()[1..].trim();
            let text = text.strip_suffix(')').unwrap_or(text).trim_end();
            return Some(crate::dialect::comment_text(text).map_or(Line::Empty, Line::Comment));
        }
        Some(b'%') => return c.delimiter(blank_or_tab)?.then_some(Line::Delimiter),
        _ => {}
    }
    let first = c.pos;
    let mut frame = Frame::default();
    if matches!(c.peek(), Some(b'N' | b'n')) && c.peek_at(1).is_some_and(|b| b.is_ascii_digit()) {
        c.pos += 1;
        let digits = c.digits()?;
        frame.number = Some(crate::dialect::lex::whole(&line[digits])?);
    }
    let mut last = c.pos;
    c.skip(blank_or_tab);
    while !c.at_end() {
        let start = c.pos;
        let b = c.peek()?;
        if b.is_ascii_alphabetic() {
            c.pos += 1;
            let negative = match c.peek() {
                Some(sign @ (b'+' | b'-')) => {
                    c.pos += 1;
                    sign == b'-'
                }
                _ => false,
            };
            let digits = c.digits()?;
            if frame.word.is_some()
                || !frame.modifiers.is_empty()
                || digits.len() > MAX_DIGITS
                || c.peek() == Some(b'.')
            {
                return None;
            }
            let value = line.as_bytes()[digits]
                .iter()
                .fold(0i64, |v, d| v * 10 + i64::from(d - b'0'));
            frame.word = Some(Word {
                letter: b.to_ascii_uppercase() as char,
                value: if negative { -value } else { value },
                range: start..c.pos,
            });
        } else {
            let rest = c.rest();
            let (m, len) = match b {
                b'~' => (Modifier::Rapid, 1),
                b'*' => (Modifier::Group, 1),
                b'@' => (Modifier::Incremental, 1),
                b'+' | b'-'
                    if rest[1..].starts_with("45")
                        && !rest.as_bytes().get(3).is_some_and(u8::is_ascii_digit) =>
                {
                    (Modifier::Chamfer { up: b == b'+' }, 3)
                }
                _ if rest.starts_with('↷') || rest.starts_with('⌒') => (Modifier::Rapid, 3),
                _ if rest.starts_with('⇄') || rest.starts_with('⇆') => {
                    (Modifier::Incremental, 3)
                }
                _ => return None,
            };
            if frame.modifiers.iter().any(|(x, _)| x.same_kind(m)) {
                return None;
            }
            c.pos += len;
            frame.modifiers.push((m, start..c.pos));
        }
        last = c.pos;
        c.skip(blank_or_tab);
    }
    if frame.word.is_none() && !frame.modifiers.is_empty() {
        return None;
    }
    if frame.number.is_none() && frame.word.is_none() {
        return Some(Line::Empty);
    }
    frame.code_range = first..last;
    Some(Line::Frame(frame))
}

/// Parses one line with the grammar: the reading of every line the fast path declines, and
/// the source of every syntax error.
fn parse_with_grammar(line: &str) -> Result<Line, SyntaxError> {
    let mut pairs = Nc31Parser::parse(Rule::line, line).map_err(|e| syntax_error(line, &e))?;
    let line_pair = pairs
        .next()
        .expect("the grammar's `line` rule always yields one pair");
    let Some(content) = line_pair.into_inner().find(|p| p.as_rule() != Rule::EOI) else {
        return Ok(Line::Empty);
    };
    match content.as_rule() {
        Rule::comment_line => {
            let text = content.into_inner().next().map_or("", |t| t.as_str());
            let text = text.trim();
            let text = text.strip_suffix(')').unwrap_or(text).trim_end();
            Ok(crate::dialect::comment_text(text).map_or(Line::Empty, Line::Comment))
        }
        Rule::delimiter => Ok(Line::Delimiter),
        _ => frame(line, content),
    }
}

/// A frame from the grammar's `frame` pair: its number, word and modifiers in order, each
/// part checked as it comes.
fn frame(line: &str, pair: pest::iterators::Pair<'_, Rule>) -> Result<Line, SyntaxError> {
    let mut frame = Frame::default();
    let (mut first, mut last) = (None, 0);
    for part in pair.into_inner() {
        let span = part.as_span();
        let range = span.start()..span.end();
        first.get_or_insert(range.start);
        last = range.end;
        match part.as_rule() {
            Rule::frame_number => frame.number = Some(frame_number(span.as_str(), range)?),
            Rule::word => frame.word = Some(frame_word(line, &frame, span.as_str(), range)?),
            rule @ (Rule::rapid | Rule::group | Rule::incremental | Rule::chamfer) => {
                frame_modifier(&mut frame, rule, span.as_str(), range)?;
            }
            _ => {}
        }
    }
    if frame.word.is_none()
        && let Some((_, range)) = frame.modifiers.first()
    {
        return Err(SyntaxError {
            code: codes::NCR_SYNTAX,
            range: range.clone(),
            message: "a modifier without a word".into(),
            help: FRAME_HELP.into(),
        });
    }
    let Some(first) = first else {
        return Ok(Line::Empty);
    };
    frame.code_range = first..last.max(first);
    Ok(Line::Frame(frame))
}

/// `N<digits>`: the frame's number, small enough.
fn frame_number(text: &str, range: Range<usize>) -> Result<u32, SyntaxError> {
    let digits = &text[1..];
    digits.parse().map_err(|_| SyntaxError {
        code: codes::NCR_NUMBER,
        range,
        message: format!("frame number `{text}` is too large"),
        help: "frame numbers are small whole numbers (N0, N1, …)".into(),
    })
}

/// The frame's word `text`: the first of the frame, before its modifiers, a whole number
/// without a decimal point and with at most [`MAX_DIGITS`] digits.
fn frame_word(
    line: &str,
    frame: &Frame,
    text: &str,
    range: Range<usize>,
) -> Result<Word, SyntaxError> {
    let letter = text.chars().next().unwrap_or('?').to_ascii_uppercase();
    let number = &text[1..];
    if let Some(previous) = &frame.word {
        return Err(SyntaxError {
            code: codes::NCR_TWO_WORDS,
            range,
            message: format!(
                "a second word `{text}` in the frame of `{}`",
                &line[previous.range.clone()]
            ),
            help: "the НЦ-31 takes one word per frame; put this word in a frame of its own and join the frames with `*` to make one group".into(),
        });
    }
    if !frame.modifiers.is_empty() {
        return Err(SyntaxError {
            code: codes::NCR_SYNTAX,
            range: frame.modifiers[0].1.clone(),
            message: "a modifier before the frame's word".into(),
            help: FRAME_HELP.into(),
        });
    }
    if let Some(dot) = number.find('.') {
        let at = range.start + 1 + dot;
        return Err(SyntaxError {
            code: codes::NCR_DECIMAL_POINT,
            range: at..at + 1,
            message: format!("`{text}` has a decimal point"),
            help: "НЦ-31 words are scaled whole numbers: X and Z in 0.01 mm (X3600 = Ø36), F in 0.0001 mm inside G31/G32/G33 (F15000 = lead 1.5) and 0.01 mm/rev elsewhere, P in 0.01 mm (the built-in units; the profile's [nc31] section can change them)".into(),
        });
    }
    let digits = number.trim_start_matches(['+', '-']);
    let value = if digits.len() > MAX_DIGITS {
        None
    } else {
        number.parse::<i64>().ok()
    };
    let Some(value) = value else {
        return Err(SyntaxError {
            code: codes::NCR_NUMBER,
            range,
            message: format!("`{text}` has too many digits"),
            help: format!("a word has at most {MAX_DIGITS} digits"),
        });
    };
    Ok(Word {
        letter,
        value,
        range,
    })
}

/// Adds the modifier of `rule` (`text`) to the frame: each kind of mark once.
fn frame_modifier(
    frame: &mut Frame,
    rule: Rule,
    text: &str,
    range: Range<usize>,
) -> Result<(), SyntaxError> {
    let m = match rule {
        Rule::rapid => Modifier::Rapid,
        Rule::group => Modifier::Group,
        Rule::incremental => Modifier::Incremental,
        _ => Modifier::Chamfer {
            up: text.starts_with('+'),
        },
    };
    if let Some((previous, _)) = frame.modifiers.iter().find(|(x, _)| x.same_kind(m)) {
        return Err(SyntaxError {
            code: codes::NCR_SYNTAX,
            range,
            message: if *previous == m {
                format!("modifier `{}` written twice", m.ascii())
            } else {
                format!(
                    "`{}` after `{}`: a frame has one chamfer sign",
                    m.ascii(),
                    previous.ascii()
                )
            },
            help: "write each modifier once".into(),
        });
    }
    frame.modifiers.push((m, range));
    Ok(())
}

fn syntax_error(line: &str, e: &pest::error::Error<Rule>) -> SyntaxError {
    let offset = crate::dialect::pest_error_offset(line, e);
    let rest = &line[offset..];
    let found = rest.chars().next();
    let end = offset + found.map_or(0, char::len_utf8);
    let (message, help) = match found {
        None => (
            "the frame ends where a value was expected".to_string(),
            FRAME_HELP.to_string(),
        ),
        Some('(') => (
            "a comment after a frame".to_string(),
            "the НЦ-31 has no comments; ncthread reads a line that starts with `(` as a comment line: move the comment to a line of its own".to_string(),
        ),
        Some('%') => (
            "`%` inside a frame".to_string(),
            "`%` stands alone on its line".to_string(),
        ),
        Some(c) if c.is_ascii_alphabetic() => (
            format!("address `{c}` is not followed by a whole number"),
            FRAME_HELP.to_string(),
        ),
        Some(c) if c.is_ascii_digit() || c == '.' || c == '-' || c == '+' => (
            format!(
                "number `{}` does not belong to an address",
                rest.split([' ', '\t']).next().unwrap_or(rest)
            ),
            FRAME_HELP.to_string(),
        ),
        Some(c) => (format!("unexpected character `{c}`"), FRAME_HELP.to_string()),
    };
    SyntaxError {
        code: codes::NCR_SYNTAX,
        range: offset..end,
        message,
        help,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(line: &str) -> Frame {
        match parse_line(line).unwrap() {
            Line::Frame(f) => f,
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn reads_the_seed_frames() {
        let f = frame("N4 X10000 ~ *");
        assert_eq!(f.number, Some(4));
        assert_eq!(
            f.word,
            Some(Word {
                letter: 'X',
                value: 10000,
                range: 3..9
            })
        );
        assert!(f.has(Modifier::Rapid) && f.has(Modifier::Group));
        assert!(!f.has(Modifier::Incremental));
        assert_eq!(f.code_range, 0..13);
        let f = frame("N11 Z-5200 @ *");
        assert_eq!(f.word.as_ref().unwrap().value, -5200);
        assert!(f.has(Modifier::Incremental));
        // Modifiers in any order, with or without spaces, panel symbols too.
        let f = frame("N9 G33*⇄");
        assert!(f.has(Modifier::Group) && f.has(Modifier::Incremental));
        let f = frame("X3600↷*");
        assert!(f.has(Modifier::Rapid));
        assert_eq!(frame("N5 Z5000 ⌒").modifiers[0].0, Modifier::Rapid);
        assert_eq!(frame("z+450").word.unwrap().letter, 'Z');
        // A frame with only its number.
        assert_eq!(frame("N7").word, None);
    }

    #[test]
    fn reads_the_chamfer_marks() {
        let f = frame("N7 X3000+45*");
        assert_eq!(
            f.word.as_ref().map(|w| (w.letter, w.value)),
            Some(('X', 3000))
        );
        assert_eq!(f.chamfer(), Some((true, 8..11)));
        assert!(f.has(Modifier::Group));
        let f = frame("Z-200-45 @ *");
        assert_eq!(f.word.as_ref().map(|w| w.value), Some(-200));
        assert_eq!(f.chamfer(), Some((false, 5..8)));
        assert!(f.has(Modifier::Incremental));
        assert_eq!(frame("X-45").chamfer(), None);
        assert_eq!(frame("X3000").chamfer(), None);
        let e = parse_line("X3000+45-45").unwrap_err();
        assert_eq!((e.code, e.range), (codes::NCR_SYNTAX, 8..11));
        assert!(e.message.contains("one chamfer sign"), "{}", e.message);
        let e = parse_line("X3000+45+45").unwrap_err();
        assert!(e.message.contains("written twice"), "{}", e.message);
        // `+450` is not a chamfer, and a chamfer needs a word before it.
        let e = parse_line("X3000+450").unwrap_err();
        assert_eq!((e.code, e.range), (codes::NCR_SYNTAX, 5..6));
        let e = parse_line("+45 X3000").unwrap_err();
        assert_eq!((e.code, e.range), (codes::NCR_SYNTAX, 0..3));
        let e = parse_line("N5 +45").unwrap_err();
        assert_eq!((e.code, e.range), (codes::NCR_SYNTAX, 3..6));
    }

    #[test]
    fn reads_comment_and_delimiter_lines() {
        assert_eq!(
            parse_line("(M36X1.5 THREAD)").unwrap(),
            Line::Comment("M36X1.5 THREAD".into())
        );
        assert_eq!(
            parse_line("  (Резьба").unwrap(),
            Line::Comment("Резьба".into())
        );
        assert_eq!(parse_line("%").unwrap(), Line::Delimiter);
        assert_eq!(parse_line("  ").unwrap(), Line::Empty);
    }

    #[test]
    fn explains_the_rules_it_refuses() {
        let e = parse_line("N10 X36.00 *").unwrap_err();
        assert_eq!(e.code, codes::NCR_DECIMAL_POINT);
        assert_eq!(e.range, 7..8);
        assert!(e.help.contains("0.01 mm"), "{}", e.help);
        let e = parse_line("N10 X3600 Z450").unwrap_err();
        assert_eq!(e.code, codes::NCR_TWO_WORDS);
        assert_eq!(e.range, 10..14);
        assert!(e.help.contains("`*`"), "{}", e.help);
        let e = parse_line("N10 X3600 ~ ~").unwrap_err();
        assert_eq!(e.code, codes::NCR_SYNTAX);
        let e = parse_line("N10 ~ X3600").unwrap_err();
        assert_eq!((e.code, e.range), (codes::NCR_SYNTAX, 4..5));
        let e = parse_line("N10 X3600 (diameter").unwrap_err();
        assert_eq!(e.range, 10..11);
        assert!(e.message.contains("comment"), "{}", e.message);
        let e = parse_line("N10 X").unwrap_err();
        assert_eq!(e.range, 4..5);
        let e = parse_line("N10 X1234567890123").unwrap_err();
        assert_eq!(e.code, codes::NCR_NUMBER);
        let e = parse_line("N10 X100 ;").unwrap_err();
        assert!(e.message.contains("`;`"), "{}", e.message);
    }

    const TOKENS: &[&str] = &[
        " ",
        "\t",
        "N",
        "n",
        "10",
        "0",
        "99999999999",
        "9999999999999",
        "G",
        "x",
        "Z",
        "F",
        "-",
        "+",
        ".",
        "5",
        "45",
        "+45",
        "-45",
        "~",
        "*",
        "@",
        "↷",
        "⌒",
        "⇄",
        "⇆",
        "(",
        ")",
        "%",
        "é",
        "\r",
        "3600",
    ];

    crate::dialect::lex::agreement_tests!(fast_line, parse_with_grammar, TOKENS);
}

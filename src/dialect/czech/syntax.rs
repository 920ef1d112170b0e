//! The czech block syntax (`grammar/czech.pest`): one line in, one [`Block`] out.

use std::ops::Range;

use pest::Parser;
use pest::iterators::Pair;
use pest_derive::Parser;

use crate::dialect::lex::{Cursor, blank_or_tab};
use crate::fixed::Decimal;

#[derive(Parser)]
#[grammar = "../grammar/czech.pest"]
struct CzechParser;

/// A word's value: a number, or an R parameter (`FR10`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Value {
    Number(Decimal),
    Param(u32),
}

/// `X26.618`: the address letter (upper case), the value, and byte ranges in the line.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Word {
    pub letter: char,
    pub value: Value,
    pub range: Range<usize>,
}

/// `R04=120.0`
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Assignment {
    pub param: u32,
    pub value: Decimal,
    pub range: Range<usize>,
}

/// Everything a block holds, in the order written.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Block {
    pub number: Option<u32>,
    pub words: Vec<Word>,
    pub assignments: Vec<Assignment>,
    /// `&1100` words: (text, range).
    pub opaque: Vec<(String, Range<usize>)>,
    pub comment: Option<String>,
    /// A `%` line.
    pub delimiter: bool,
    /// The range of the block without its comment and trailing blanks.
    pub code_range: Range<usize>,
}

impl Block {
    /// Only a block number and/or a comment.
    pub fn is_empty(&self) -> bool {
        self.words.is_empty()
            && self.assignments.is_empty()
            && self.opaque.is_empty()
            && !self.delimiter
    }
}

/// Why a line could not be read: the byte offset and what was found there.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SyntaxError {
    pub offset: usize,
    pub message: String,
    pub help: String,
    /// A number that is too large for its place (block or parameter number).
    pub number_too_large: bool,
}

fn int(pair: &Pair<'_, Rule>, line: &str) -> Result<u32, SyntaxError> {
    pair.as_str().parse().map_err(|_| SyntaxError {
        offset: pair.as_span().start(),
        message: format!(
            "`{}` is too large for a block or parameter number",
            &line[pair.as_span().start()..pair.as_span().end()]
        ),
        help: "block and parameter numbers are small whole numbers".into(),
        number_too_large: true,
    })
}

fn decimal(pair: &Pair<'_, Rule>) -> Result<Decimal, SyntaxError> {
    Decimal::parse(pair.as_str()).ok_or_else(|| SyntaxError {
        offset: pair.as_span().start(),
        message: format!("`{}` has too many digits", pair.as_str()),
        help: "numbers are at most 30 digits long".into(),
        number_too_large: true,
    })
}

/// Parses one line (without its line ending).
pub fn parse_line(line: &str) -> Result<Block, SyntaxError> {
    let mut block = Block::default();
    parse_line_into(line, &mut block).map(|()| block)
}

/// [`parse_line`] into a block reused from line to line (its lists keep their room).
/// After an error the block may hold part of a reading: use it only after `Ok`.
pub fn parse_line_into(line: &str, block: &mut Block) -> Result<(), SyntaxError> {
    block.number = None;
    block.words.clear();
    block.assignments.clear();
    block.opaque.clear();
    block.comment = None;
    block.delimiter = false;
    block.code_range = 0..0;
    if read_fast(line, block).is_none() {
        *block = parse_with_grammar(line)?;
    }
    Ok(())
}

/// The typographic quotes that open a comment as `"` does.
const QUOTES: [&str; 3] = ["“", "”", "„"];

/// The grammar's reading of a well-formed line without pest (see `dialect::lex`), or `None`.
#[cfg(test)]
fn fast_line(line: &str) -> Option<Block> {
    let mut block = Block::default();
    read_fast(line, &mut block).map(|()| block)
}

/// [`fast_line`] into `block` (empty); `None` leaves it partly filled.
fn read_fast(line: &str, block: &mut Block) -> Option<()> {
    let mut c = Cursor::new(line);
    c.skip(blank_or_tab);
    let first = c.pos;
    if c.peek() == Some(b'%') {
        return fast_delimiter(&mut c, first, block);
    }
    let mut code_end = 0;
    if matches!(c.peek(), Some(b'N' | b'n')) && c.peek_at(1).is_some_and(|b| b.is_ascii_digit()) {
        c.pos += 1;
        let digits = c.digits()?;
        block.number = Some(crate::dialect::lex::whole(&line[digits])?);
        code_end = c.pos;
        c.skip(blank_or_tab);
    }
    while !c.at_end() {
        if let Some(quote) = comment_quote(&c) {
            block.comment = crate::dialect::comment_text(&c.rest()[quote..]);
            break;
        }
        fast_item(&mut c, line, block)?;
        code_end = c.pos;
        c.skip(blank_or_tab);
    }
    block.code_range = first..code_end.max(first);
    Some(())
}

/// The length of the quote that opens a comment at the cursor, if one does.
#[inline(always)]
fn comment_quote(c: &Cursor<'_>) -> Option<usize> {
    let rest = c.rest();
    // Each typographic quote starts with the byte 0xE2: most words need one look.
    match rest.as_bytes().first() {
        Some(b'"') => return Some(1),
        Some(0xE2) => {}
        _ => return None,
    }
    QUOTES
        .iter()
        .find(|q| rest.starts_with(**q))
        .map(|q| q.len())
}

/// A `%` line (the cursor on the `%`): a delimiter and an optional comment.
fn fast_delimiter(c: &mut Cursor<'_>, first: usize, block: &mut Block) -> Option<()> {
    c.pos += 1;
    c.skip(blank_or_tab);
    block.delimiter = true;
    if !c.at_end() {
        let quote = comment_quote(c)?;
        block.comment = crate::dialect::comment_text(&c.rest()[quote..]);
    }
    block.code_range = first..first;
    Some(())
}

/// The `&` word, assignment or word at the cursor, into `block`; `None` when the line is not
/// for the fast path.
fn fast_item(c: &mut Cursor<'_>, line: &str, block: &mut Block) -> Option<()> {
    let start = c.pos;
    let b = c.peek()?;
    if b == b'&' {
        c.pos += 1;
        c.digits()?;
        block
            .opaque
            .push((line[start..c.pos].to_string(), start..c.pos));
    } else if b.is_ascii_alphabetic() {
        c.pos += 1;
        let assigned = if matches!(b, b'R' | b'r') {
            assignment(c, line)
        } else {
            None
        };
        if let Some((param, value)) = assigned {
            block.assignments.push(Assignment {
                param,
                value,
                range: start..c.pos,
            });
        } else {
            c.pos = start + 1;
            block.words.push(fast_word(c, line, start, b)?);
        }
    } else {
        return None;
    }
    Some(())
}

/// After a word's letter `letter` (written from `start`): its value, a number or `Rnn`.
fn fast_word(c: &mut Cursor<'_>, line: &str, start: usize, letter: u8) -> Option<Word> {
    c.skip(blank_or_tab);
    let value = if matches!(c.peek(), Some(b'R' | b'r'))
        && c.peek_at(1).is_some_and(|b| b.is_ascii_digit())
    {
        c.pos += 1;
        let digits = c.digits()?;
        Value::Param(crate::dialect::lex::whole(&line[digits])?)
    } else {
        Value::Number(c.value(blank_or_tab)?)
    };
    Some(Word {
        letter: letter.to_ascii_uppercase() as char,
        value,
        range: start..c.pos,
    })
}

/// After `R`: `04 = 120.0`, when the line holds an assignment there (else the cursor is left
/// anywhere and the caller reads a word).
fn assignment(c: &mut Cursor<'_>, line: &str) -> Option<(u32, Decimal)> {
    let digits = c.digits()?;
    c.skip(blank_or_tab);
    if c.peek() != Some(b'=') {
        return None;
    }
    c.pos += 1;
    let param = crate::dialect::lex::whole(&line[digits])?;
    let value = c.value(blank_or_tab)?;
    Some((param, value))
}

/// Parses one line with the grammar: the reading of every line the fast path declines, and
/// the source of every syntax error.
fn parse_with_grammar(line: &str) -> Result<Block, SyntaxError> {
    let mut pairs = CzechParser::parse(Rule::line, line).map_err(|e| syntax_error(line, &e))?;
    let line_pair = pairs
        .next()
        .expect("the grammar's `line` rule always yields one pair");
    let mut block = Block::default();
    let mut code_end = 0;
    for pair in line_pair.into_inner() {
        let rule = pair.as_rule();
        if rule == Rule::delimiter {
            block.delimiter = true;
        }
        if rule != Rule::delimiter && rule != Rule::block {
            continue;
        }
        for part in pair.into_inner() {
            let span = part.as_span();
            if part.as_rule() != Rule::comment {
                code_end = span.end();
            }
            match part.as_rule() {
                Rule::block_number => {
                    let digits = part.into_inner().next().expect("block_number has digits");
                    block.number = Some(int(&digits, line)?);
                }
                Rule::assignment => {
                    let mut inner = part.into_inner();
                    let param = int(&inner.next().expect("assignment has digits"), line)?;
                    let value = decimal(&inner.next().expect("assignment has a number"))?;
                    block.assignments.push(Assignment {
                        param,
                        value,
                        range: span.start()..span.end(),
                    });
                }
                Rule::opaque => block
                    .opaque
                    .push((span.as_str().to_string(), span.start()..span.end())),
                Rule::word => {
                    let mut inner = part.into_inner();
                    let letter = inner.next().expect("word has an address").as_str();
                    let letter = letter.chars().next().unwrap_or('?').to_ascii_uppercase();
                    let value_pair = inner.next().expect("word has a value");
                    let value = match value_pair.as_rule() {
                        Rule::param_ref => {
                            let digits = value_pair
                                .into_inner()
                                .next()
                                .expect("param_ref has digits");
                            Value::Param(int(&digits, line)?)
                        }
                        _ => Value::Number(decimal(&value_pair)?),
                    };
                    block.words.push(Word {
                        letter,
                        value,
                        range: span.start()..span.end(),
                    });
                }
                Rule::comment => {
                    let text = part.into_inner().next().map_or("", |t| t.as_str());
                    block.comment = crate::dialect::comment_text(text);
                }
                _ => {}
            }
        }
    }
    let first = line.len() - line.trim_start_matches([' ', '\t']).len();
    block.code_range = first..code_end.max(first);
    Ok(block)
}

fn syntax_error(line: &str, e: &pest::error::Error<Rule>) -> SyntaxError {
    let offset = crate::dialect::pest_error_offset(line, e);
    let rest = &line[offset..];
    let found = rest.chars().next();
    let help =
        "a block is `N<number>`, then words (a letter and a number: `X26.618`, `Z-9.`, `FR10`), \
                `R<nn>=<number>` assignments and `&<digits>`, then an optional comment from `\"`"
            .to_string();
    let message = match found {
        None => "the block ends where a value was expected".to_string(),
        Some(c) if c.is_ascii_alphabetic() => {
            format!("address `{c}` is not followed by a number")
        }
        Some(c) if c.is_ascii_digit() || c == '.' || c == '-' || c == '+' => {
            format!(
                "number `{}` does not belong to an address",
                rest.split([' ', '\t']).next().unwrap_or(rest)
            )
        }
        Some(c) => format!("unexpected character `{c}`"),
    };
    SyntaxError {
        offset,
        message,
        help,
        number_too_large: false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn letters(b: &Block) -> String {
        b.words.iter().map(|w| w.letter).collect()
    }

    #[test]
    fn reads_the_seed_blocks() {
        let b = parse_line("N325 G00 G95 T9 &1100 D9 S1000 M03 M42 \"HLAVNI VETA").unwrap();
        assert_eq!(b.number, Some(325));
        assert_eq!(letters(&b), "GGTDSMM");
        assert_eq!(b.opaque[0].0, "&1100");
        assert_eq!(b.comment.as_deref(), Some("HLAVNI VETA"));
        assert_eq!(
            &"N325 G00 G95 T9 &1100 D9 S1000 M03 M42 \"HLAVNI VETA"[b.code_range.clone()],
            "N325 G00 G95 T9 &1100 D9 S1000 M03 M42"
        );

        let b = parse_line("N10 R15= -00120.000 R16= -00118.000").unwrap();
        assert_eq!(b.assignments.len(), 2);
        assert_eq!(b.assignments[1].param, 16);
        assert_eq!(
            b.assignments[1].value,
            Decimal::parse("-00118.000").unwrap()
        );

        let b = parse_line("N70 Z200.0 FR10 I0 G33 \"stoupání").unwrap();
        assert_eq!(b.words[1].value, Value::Param(10));

        let b = parse_line("N40\t“PRÁZDNÝ BLOK").unwrap();
        assert!(b.is_empty());
        assert_eq!(b.comment.as_deref(), Some("PRÁZDNÝ BLOK"));
    }

    #[test]
    fn reads_words_written_together() {
        let b = parse_line("G00X26.618Z3.").unwrap();
        assert_eq!(letters(&b), "GXZ");
        assert_eq!(b.words[1].range, 3..10);
        let b = parse_line("n10 g33 z-9. f1.5").unwrap();
        assert_eq!(letters(&b), "GZF");
    }

    #[test]
    fn reads_delimiters_and_blank_lines() {
        assert!(parse_line("%").unwrap().delimiter);
        assert_eq!(
            parse_line("   ").unwrap(),
            Block {
                code_range: 3..3,
                ..Block::default()
            }
        );
    }

    #[test]
    fn points_at_the_bad_character() {
        let e = parse_line("N10 X26.618 Z").unwrap_err();
        assert_eq!(e.offset, 12);
        assert!(e.message.contains("`Z`"), "{}", e.message);
        let e = parse_line("N10 X1 ; comment").unwrap_err();
        assert_eq!(e.offset, 7);
        assert!(e.message.contains("`;`"), "{}", e.message);
        let e = parse_line("N10 12").unwrap_err();
        assert_eq!(e.offset, 4);
    }

    const TOKENS: &[&str] = &[
        " ",
        "\t",
        "N",
        "n",
        "10",
        "0",
        "99999999999",
        "G",
        "x",
        "Z",
        "R",
        "r",
        "F",
        "04",
        "=",
        " = ",
        "-",
        "+",
        ".",
        "5",
        "26.618",
        "&",
        "&1100",
        "\"",
        "“",
        "„",
        "%",
        "C",
        ";",
        "(",
        "é",
        "\r",
        "1.2.3",
    ];

    crate::dialect::lex::agreement_tests!(fast_line, parse_with_grammar, TOKENS);
}

//! The FANUC block syntax (`grammar/fanuc.pest`): one line in, one [`Block`] out.

use std::ops::Range;

use pest::Parser;
use pest_derive::Parser;

use crate::dialect::lex::{Cursor, blank_tab_or_cr};
use crate::fixed::Decimal;

#[derive(Parser)]
#[grammar = "../grammar/fanuc.pest"]
struct FanucParser;

/// `X26.618`: the address letter (upper case), the value as written, and its byte range.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Word {
    pub letter: char,
    pub value: Decimal,
    pub range: Range<usize>,
}

/// Everything a line holds, in the order written.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Block {
    pub number: Option<u32>,
    pub words: Vec<Word>,
    /// The comments, joined by a blank.
    pub comment: Option<String>,
    /// A `%` line.
    pub delimiter: bool,
    /// A `/` (block skip) in front.
    pub block_delete: Option<Range<usize>>,
    /// The range of the block without its comments and trailing blanks.
    pub code_range: Range<usize>,
}

impl Block {
    /// Only a block number and/or a comment.
    pub fn is_empty(&self) -> bool {
        self.words.is_empty() && !self.delimiter
    }

    /// The first word with this letter.
    pub fn get(&self, letter: char) -> Option<&Word> {
        self.words.iter().find(|w| w.letter == letter)
    }
}

/// Why a line could not be read: the byte offset and what was found there.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SyntaxError {
    pub offset: usize,
    pub message: String,
    pub help: String,
    /// A number too large for its place.
    pub number_too_large: bool,
}

/// Parses one line (without its line ending).
pub fn parse_line(line: &str) -> Result<Block, SyntaxError> {
    parse_line_with(line, Vec::new())
}

/// [`parse_line`] into the room of an earlier block's words (`words`, cleared here), so that
/// a reader going line by line allocates none.
pub fn parse_line_with(line: &str, mut words: Vec<Word>) -> Result<Block, SyntaxError> {
    words.clear();
    match fast_line_with(line, words) {
        Some(block) => Ok(block),
        None => parse_with_grammar(line),
    }
}

/// The grammar's reading of a well-formed line without pest (see `dialect::lex`), or `None`.
#[cfg(test)]
fn fast_line(line: &str) -> Option<Block> {
    fast_line_with(line, Vec::new())
}

/// [`fast_line`] into `words` (empty).
fn fast_line_with(line: &str, words: Vec<Word>) -> Option<Block> {
    let mut c = Cursor::new(line);
    c.skip(blank_tab_or_cr);
    let first = c.pos;
    let mut block = Block {
        words,
        ..Block::default()
    };
    if c.delimiter(blank_tab_or_cr)? {
        block.delimiter = true;
        block.code_range = c.pos..c.pos;
        return Some(block);
    }
    let mut code_end = first;
    if c.peek() == Some(b'/') {
        c.pos += 1;
        block.block_delete = Some(first..c.pos);
        code_end = c.pos;
        c.skip(blank_tab_or_cr);
    }
    if let Some(digits) = c.block_number(blank_tab_or_cr) {
        block.number = Some(crate::dialect::lex::whole(&line[digits]).filter(|n| *n <= 99_999)?);
        code_end = c.pos;
        c.skip(blank_tab_or_cr);
    }
    let mut comments: Vec<String> = Vec::new();
    while !c.at_end() {
        let start = c.pos;
        match c.peek()? {
            b'(' => comments.extend(crate::dialect::comment_text(c.paren_comment()?)),
            b';' => {
                c.pos += 1;
                c.skip(blank_tab_or_cr);
                if !c.at_end() {
                    return None;
                }
                break;
            }
            b if b.is_ascii_alphabetic() => {
                c.pos += 1;
                let value = c.value(blank_tab_or_cr)?;
                block.words.push(Word {
                    letter: b.to_ascii_uppercase() as char,
                    value,
                    range: start..c.pos,
                });
                code_end = c.pos;
            }
            _ => return None,
        }
        c.skip(blank_tab_or_cr);
    }
    if !comments.is_empty() {
        block.comment = Some(comments.join(" "));
    }
    block.code_range = first..code_end;
    Some(block)
}

/// Parses one line with the grammar: the reading of every line the fast path declines, and
/// the source of every syntax error.
fn parse_with_grammar(line: &str) -> Result<Block, SyntaxError> {
    let mut pairs = FanucParser::parse(Rule::line, line).map_err(|e| syntax_error(line, &e))?;
    let Some(line_pair) = pairs.next() else {
        return Ok(Block::default());
    };
    let mut block = Block::default();
    let mut comments: Vec<String> = Vec::new();
    let mut first = line.len() - line.trim_start_matches([' ', '\t', '\r']).len();
    let mut code_end = first;
    for pair in line_pair.into_inner() {
        match pair.as_rule() {
            // The block on a `%` line (`%O1200 (NAME)`) starts after the `%`: a block kept
            // as written is its words, never the tape's delimiter.
            Rule::delimiter => {
                block.delimiter = true;
                first = pair.as_span().end();
                code_end = first;
            }
            Rule::block => {
                for part in pair.into_inner() {
                    let span = part.as_span();
                    match part.as_rule() {
                        Rule::block_delete => {
                            block.block_delete = Some(span.start()..span.end());
                            code_end = span.end();
                        }
                        Rule::block_number => {
                            code_end = span.end();
                            let digits = part.into_inner().next().map_or("", |d| d.as_str());
                            block.number =
                                Some(digits.parse().ok().filter(|n| *n <= 99_999).ok_or_else(
                                    || SyntaxError {
                                        offset: span.start(),
                                        message: format!(
                                            "`{}` is too large for a block number",
                                            span.as_str()
                                        ),
                                        help: "block numbers are N1 to N99999".into(),
                                        number_too_large: true,
                                    },
                                )?);
                        }
                        Rule::word => {
                            code_end = span.end();
                            block.words.push(grammar_word(part)?);
                        }
                        Rule::comment => {
                            let text = part.into_inner().next().map_or("", |t| t.as_str());
                            if let Some(t) = crate::dialect::comment_text(text) {
                                comments.push(t);
                            }
                        }
                        _ => {}
                    }
                }
            }
            _ => {}
        }
    }
    if !comments.is_empty() {
        block.comment = Some(comments.join(" "));
    }
    block.code_range = first..code_end.max(first);
    Ok(block)
}

/// A word the grammar read: its letter (`:0100`, ISO code's program number, is `O0100`) and
/// its number.
fn grammar_word(part: pest::iterators::Pair<'_, Rule>) -> Result<Word, SyntaxError> {
    let span = part.as_span();
    let mut inner = part.into_inner();
    let letter = match inner.next().and_then(|a| a.as_str().chars().next()) {
        Some(':') => 'O',
        c => c.unwrap_or('?').to_ascii_uppercase(),
    };
    let text = inner.next().map_or("", |n| n.as_str());
    let value = Decimal::parse(text).ok_or_else(|| SyntaxError {
        offset: span.start(),
        message: format!("`{}` has too many digits", span.as_str()),
        help: "numbers are at most 30 digits long".into(),
        number_too_large: true,
    })?;
    Ok(Word {
        letter,
        value,
        range: span.start()..span.end(),
    })
}

/// Where the word that `before` ends in starts, when its number already has a decimal
/// point (`X-12.8` before a second `.`).
fn second_point(before: &str) -> Option<usize> {
    let number = before.trim_end_matches(|c: char| c.is_ascii_digit());
    let number = number.strip_suffix('.')?;
    let start = number.trim_end_matches(|c: char| c.is_ascii_digit());
    let start = start.strip_suffix(['-', '+']).unwrap_or(start);
    let letter = start
        .chars()
        .next_back()
        .filter(char::is_ascii_alphabetic)?;
    Some(start.len() - letter.len_utf8())
}

fn syntax_error(line: &str, e: &pest::error::Error<Rule>) -> SyntaxError {
    let offset = crate::dialect::pest_error_offset(line, e);
    let rest = &line[offset..];
    let found = rest.chars().next();
    let help = "a FANUC block is `N<number>`, then words (a letter and a number: `X26.618`, `Z-9.`, `T0101`), with `( )` comments".to_string();
    // `X#1`: pest stops at the letter whose number is a macro variable or expression.
    let after = rest
        .get(found.map_or(0, char::len_utf8)..)
        .unwrap_or("")
        .trim_start();
    let found = if found.is_some_and(|c| c.is_ascii_alphabetic()) && after.starts_with(['#', '[']) {
        after.chars().next()
    } else {
        found
    };
    let (message, help) = match found {
        None => ("the block ends where a value was expected".to_string(), help),
        Some('#' | '[') => (
            format!("`{}`: custom macro variables and expressions are not read", found.unwrap_or('#')),
            "ncthread reads FANUC programs without custom macros (macro B): write the values the macro computes".to_string(),
        ),
        Some('(') => (
            "a comment that is not closed, or a `(` inside a comment".to_string(),
            "close the comment with `)` on the same line; comments do not nest".to_string(),
        ),
        // `TO303`: the letter O typed for a zero.
        Some(c)
            if c.is_ascii_alphabetic()
                && rest[1..].starts_with(['O', 'o'])
                && rest[2..].starts_with(|d: char| d.is_ascii_digit()) =>
        {
            let word = rest
                .char_indices()
                .skip(2)
                .find(|(_, d)| !d.is_ascii_digit() && *d != 'O' && *d != 'o' && *d != '.')
                .map_or(rest, |(i, _)| &rest[..i]);
            (
                format!("`{word}`: address `{c}` is followed by the letter O, not a number"),
                format!("a zero typed as the letter O? Write `{c}{}`", word[1..].replace(['O', 'o'], "0")),
            )
        }
        Some(c) if c.is_ascii_alphabetic() => {
            (format!("address `{c}` is not followed by a number"), help)
        }
        // `X-12.8.`: a second decimal point after a number that has one.
        Some('.') if let Some(start) = second_point(&line[..offset]) => {
            let end = rest[1..]
                .find(|d: char| !d.is_ascii_digit())
                .map_or(line.len(), |i| offset + 1 + i);
            (
                format!("`{}`: a number with two decimal points", &line[start..end]),
                format!("write the number with one decimal point: `{}`?", &line[start..offset]),
            )
        }
        Some(c) if c.is_ascii_digit() || c == '.' || c == '-' || c == '+' => (
            format!(
                "number `{}` does not belong to an address",
                rest.split([' ', '\t']).next().unwrap_or(rest)
            ),
            help,
        ),
        // `X-21.75,A30`: a direct drawing dimension (FANUC's `,A` angle, `,C` chamfer, `,R`
        // corner radius after a move).
        Some(',') if rest[1..].starts_with(['A', 'C', 'R', 'a', 'c', 'r']) => (
            format!(
                "`{}`: FANUC's direct drawing dimensions (`,A` an angle, `,C` a chamfer, `,R` a corner radius) are not read",
                rest.split([' ', '\t', '(']).next().unwrap_or(rest)
            ),
            "write the points the angle, chamfer or corner gives as moves of their own (`G01 X… Z…`, an arc for a corner radius)".to_string(),
        ),
        Some(c) => (format!("unexpected character `{c}`"), help),
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

    #[test]
    fn words_comments_and_marks() {
        let b = parse_line("N10 g32 x19.4 Z-20. F1.5 Q180000 (PASS 1);").unwrap();
        assert_eq!(b.number, Some(10));
        let letters: String = b.words.iter().map(|w| w.letter).collect();
        assert_eq!(letters, "GXZFQ");
        assert!(b.words[2].value.has_point);
        assert!(!b.words[4].value.has_point);
        assert_eq!(b.comment.as_deref(), Some("PASS 1"));
        assert!(parse_line("%").unwrap().delimiter);
        assert!(parse_line("O0001 (SHAFT)").unwrap().get('O').is_some());
        assert!(parse_line("/ G00 X1.").unwrap().block_delete.is_some());
    }

    /// The forms real files take: `:0100` is a program number, `%` may stand before one on
    /// its line, and a full-width `％` is a `%`.
    #[test]
    fn program_numbers_and_delimiters_as_files_carry_them() {
        let b = parse_line(":0100").unwrap();
        assert_eq!(b.get('O').map(|w| w.value.to_whole()), Some(Ok(100)));
        let b = parse_line("%O1200(TOKARKA)").unwrap();
        assert!(b.delimiter);
        assert_eq!(b.code_range, 1..6);
        assert_eq!(b.get('O').map(|w| w.value.to_whole()), Some(Ok(1200)));
        assert_eq!(b.comment.as_deref(), Some("TOKARKA"));
        let b = parse_line(" ％ ").unwrap();
        assert!(b.delimiter && b.words.is_empty());
        assert!(parse_line("G00 X1. %").is_err());
        // A comment after the end-of-block mark, as some editors save it.
        let b = parse_line("N60 T0202; (DESBASTE)").unwrap();
        assert_eq!(b.comment.as_deref(), Some("DESBASTE"));
        assert!(parse_line("N60 T0202; X1.").is_err());
        assert!(parse_line("G00 :1").is_ok());
    }

    #[test]
    fn what_cannot_be_read_is_said_at_its_character() {
        let e = parse_line("G00 X#1").unwrap_err();
        assert_eq!(e.offset, 4);
        assert!(e.message.contains("macro"), "{}", e.message);
        let e = parse_line("G00 X").unwrap_err();
        assert_eq!(e.offset, 4);
        let e = parse_line("G00 (OPEN").unwrap_err();
        assert!(e.message.contains("comment"), "{}", e.message);
        // Multi-byte text never splits a character.
        assert!(parse_line("G00 Ž").is_err());
        let e = parse_line("X-21.75,A30 F0.1").unwrap_err();
        assert_eq!(e.offset, 7);
        assert!(
            e.message.starts_with("`,A30`: FANUC's direct drawing"),
            "{}",
            e.message
        );
        assert!(
            parse_line("X1.,")
                .unwrap_err()
                .message
                .contains("unexpected character")
        );
    }

    /// Typos found in public shop programs are named as what they are.
    #[test]
    fn a_second_decimal_point_and_an_o_for_a_zero_are_named() {
        let e = parse_line("Z-0.1 X-12.8.").unwrap_err();
        assert_eq!(e.offset, 12);
        assert_eq!(e.message, "`X-12.8.`: a number with two decimal points");
        assert!(e.help.contains("`X-12.8`"), "{}", e.help);
        let e = parse_line("G0X-4.5.Z0.").unwrap_err();
        assert_eq!(e.message, "`X-4.5.`: a number with two decimal points");
        let e = parse_line("TO303").unwrap_err();
        assert_eq!(e.offset, 0);
        assert_eq!(
            e.message,
            "`TO303`: address `T` is followed by the letter O, not a number"
        );
        assert!(e.help.contains("`T0303`"), "{}", e.help);
        // Not every stray point is a second one, nor every O after a letter a zero.
        assert!(
            parse_line("G00 X1 .5")
                .unwrap_err()
                .message
                .starts_with("number")
        );
        assert!(
            parse_line("TOP")
                .unwrap_err()
                .message
                .starts_with("address `T`")
        );
    }

    const TOKENS: &[&str] = &[
        " ", "\t", "\r", "/", "N", "n", "10", "0", "99999", "100000", "G", "x", "Z", "F", "-", "+",
        ".", "5", "26.618", "(", ")", "(AB)", ";", "%", "é", "#", "O",
    ];

    crate::dialect::lex::agreement_tests!(fast_line, parse_with_grammar, TOKENS);
}

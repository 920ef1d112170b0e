//! The HEIDENHAIN DIN block syntax (`grammar/heidenhain.pest`): one block line in, one
//! [`Block`] out. The `%NAME.nc` line and the section lines are the front end's.

use std::ops::Range;

use pest::Parser;
use pest_derive::Parser;

use crate::fixed::Decimal;

#[derive(Parser)]
#[grammar = "../grammar/heidenhain.pest"]
struct HeidenhainParser;

/// What follows a word's address.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Value {
    /// `X20`.
    Number(Decimal),
    /// `X?`: a value the control finds from the contour.
    Unknown,
    /// `ID"342-300.1"`.
    Text(String),
}

/// One word: its address in upper case (`X`, `XI`, `BR`), its value and byte range.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Word {
    pub name: String,
    pub value: Value,
    pub range: Range<usize>,
}

impl Word {
    /// The number of a word (`X20`).
    pub fn number(&self) -> Option<Decimal> {
        match self.value {
            Value::Number(d) => Some(d),
            _ => None,
        }
    }
}

/// Everything a block line holds, in the order written.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Block {
    pub number: Option<u32>,
    pub words: Vec<Word>,
    pub comment: Option<String>,
    /// A `/` (block skip) in front.
    pub block_delete: Option<Range<usize>>,
    /// The range of the block without its comment and trailing blanks.
    pub code_range: Range<usize>,
}

/// Why a line could not be read: the byte offset and what was found there.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SyntaxError {
    pub offset: usize,
    pub message: String,
    pub help: String,
}

const HELP: &str = "a HEIDENHAIN DIN block is `N<number>`, then words (`G1`, `X26.618`, `Zi-2`), with a `[…]` comment at its end";

/// Parses one block line (without its line ending).
pub fn parse_line(line: &str) -> Result<Block, SyntaxError> {
    let mut pairs =
        HeidenhainParser::parse(Rule::line, line).map_err(|e| syntax_error(line, &e))?;
    let mut block = Block::default();
    let Some(block_pair) = pairs.next().and_then(|l| l.into_inner().next()) else {
        return Ok(block);
    };
    let first = line.len() - line.trim_start_matches([' ', '\t', '\r']).len();
    let mut code_end = first;
    for part in block_pair.into_inner() {
        let span = part.as_span();
        let range = span.start()..span.end();
        match part.as_rule() {
            Rule::block_delete => {
                block.block_delete = Some(range);
                code_end = span.end();
            }
            Rule::block_number => {
                code_end = span.end();
                let digits = part.into_inner().next().map_or("", |d| d.as_str());
                block.number = Some(digits.parse().ok().filter(|n| *n <= 99_999).ok_or_else(
                    || SyntaxError {
                        offset: span.start(),
                        message: format!("`{}` is too large for a block number", span.as_str()),
                        help: "block numbers are N1 to N99999".into(),
                    },
                )?);
            }
            Rule::word | Rule::named => {
                code_end = span.end();
                block.words.push(word(part, range)?);
            }
            Rule::comment => {
                let text = part.into_inner().next().map_or("", |t| t.as_str());
                block.comment = crate::dialect::comment_text(text);
            }
            _ => {}
        }
    }
    block.code_range = first..code_end.max(first);
    Ok(block)
}

fn word(part: pest::iterators::Pair<'_, Rule>, range: Range<usize>) -> Result<Word, SyntaxError> {
    let start = range.start;
    let mut inner = part.into_inner();
    let name = inner.next().map_or("", |p| p.as_str()).to_ascii_uppercase();
    let value = match inner.next() {
        Some(v) if v.as_rule() == Rule::number => {
            Value::Number(Decimal::parse(v.as_str()).ok_or_else(|| SyntaxError {
                offset: start,
                message: format!("`{}` has too many digits", v.as_str()),
                help: "numbers are at most 30 digits long".into(),
            })?)
        }
        Some(v) if v.as_rule() == Rule::text => Value::Text(v.as_str().trim_matches('"').into()),
        _ => Value::Unknown,
    };
    Ok(Word { name, value, range })
}

fn syntax_error(line: &str, e: &pest::error::Error<Rule>) -> SyntaxError {
    let offset = crate::dialect::pest_error_offset(line, e);
    let rest = &line[offset..];
    // After an address, what stands where its number should.
    let value = rest.trim_start_matches(|c: char| c.is_ascii_alphabetic() || c == ' ');
    let first = match value.chars().next() {
        Some(c @ ('#' | '{' | '=' | '(')) => Some(c),
        _ => rest.chars().next(),
    };
    let (message, help) = match first {
        None => (
            "the block ends where a value was expected".to_string(),
            HELP.to_string(),
        ),
        Some(c) if c.is_ascii_digit() || c == '.' || c == '-' || c == '+' => (
            format!(
                "number `{}` does not belong to an address",
                rest.split([' ', '\t']).next().unwrap_or(rest)
            ),
            HELP.to_string(),
        ),
        Some('#' | '{' | '=' | '(') => (
            "a variable, an expression or a structure command (`#1`, `{…}`, `=`): DIN PLUS variables and program structures are not read".to_string(),
            "write the value as a number".to_string(),
        ),
        Some('[') => (
            "a comment `[…]` that does not close on its line".to_string(),
            "close the comment with `]`".to_string(),
        ),
        Some(c) => (format!("unexpected character `{c}`"), HELP.to_string()),
    };
    SyntaxError {
        offset,
        message,
        help,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words_increments_unknowns_names_and_comments() {
        let b =
            parse_line("N 13 G33 Xi-2 Z-20 F1.5 B1.5 C90 X? T5 ID\"342-300.1\" [pass 1]").unwrap();
        assert_eq!(b.number, Some(13));
        let names: Vec<&str> = b.words.iter().map(|w| w.name.as_str()).collect();
        assert_eq!(names, ["G", "XI", "Z", "F", "B", "C", "X", "T", "ID"]);
        assert_eq!(b.words[1].number(), Decimal::parse("-2"));
        assert_eq!(b.words[6].value, Value::Unknown);
        assert_eq!(b.words[8].value, Value::Text("342-300.1".into()));
        assert_eq!(b.comment.as_deref(), Some("pass 1"));
        let b = parse_line("N2 G1 X20 BR-0.5").unwrap();
        assert_eq!(b.words[2].name, "BR");
        assert_eq!(parse_line("[a comment alone]").unwrap().words.len(), 0);
    }

    #[test]
    fn what_is_not_a_block_is_a_syntax_error() {
        assert!(
            parse_line("N10 G0 X#1")
                .unwrap_err()
                .message
                .contains("variable")
        );
        assert!(parse_line("N10 G0 X").is_err());
        assert!(
            parse_line("N10 [open")
                .unwrap_err()
                .message
                .contains("close")
        );
        assert!(parse_line("N10 G0 X1 Ž").is_err());
        assert!(parse_line("N123456 G0").is_err());
    }
}

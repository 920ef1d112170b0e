//! The SINUMERIK block syntax (`grammar/siemens.pest`): one line in, one [`Block`] out.

use std::ops::Range;

use pest::Parser;
use pest_derive::Parser;

use crate::fixed::Decimal;

#[derive(Parser)]
#[grammar = "../grammar/siemens.pest"]
struct SiemensParser;

/// What follows a word's name.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Value {
    /// `X20`, `X=20`, `SF=90`.
    Plain(Decimal),
    /// `X=AC(20)`: absolute whatever G90/G91 say.
    Absolute(Decimal),
    /// `X=IC(-2)`: incremental whatever G90/G91 say.
    Incremental(Decimal),
    /// A name alone: `DIAMON`, `GOTOF`.
    None,
    /// A name with an argument list: `CYCLE97(…)`, `MSG("…")`.
    Call,
    /// A jump's target: `SKOK1:`.
    Label,
}

/// One element of a block: its name in upper case (`X`, `SF`, `DIAMON`), what follows it,
/// whether it was written `name=value`, and its byte range.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Word {
    pub name: String,
    pub value: Value,
    pub assigned: bool,
    pub range: Range<usize>,
}

impl Word {
    /// The number of a plain word (`X20`, `SF=90`).
    pub fn plain(&self) -> Option<Decimal> {
        match self.value {
            Value::Plain(d) => Some(d),
            _ => None,
        }
    }
}

/// Everything a line holds, in the order written.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Block {
    /// `%_N_NAME_MPF`: the name and whether it is a subprogram (`_SPF`).
    pub header: Option<(String, bool)>,
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

const HELP: &str = "a SINUMERIK block is `N<number>`, then words (`X26.618`, `G33`, `X=AC(20)`, `SF=90`), with a `;` comment to the line's end";

/// Parses one line (without its line ending): the common lines by hand
/// ([`crate::dialect::lex`]), any other with the grammar.
pub fn parse_line(line: &str) -> Result<Block, SyntaxError> {
    match fast_line(line) {
        Some(block) => Ok(block),
        None => parse_with_grammar(line),
    }
}

/// The grammar's reading of a line of `N` and words (`X26.618`, `SF=90`, `DIAMON`) with a
/// `;` comment, read by hand; `None` at anything else (a header, `/`, a label, a call,
/// `AC(…)`/`IC(…)`, a number too long, any error), which the grammar reads.
fn fast_line(line: &str) -> Option<Block> {
    use crate::dialect::lex::{Cursor, blank_tab_or_cr as sep};
    let mut c = Cursor::new(line);
    c.skip(sep);
    let first = c.pos;
    if c.at_end() {
        return None;
    }
    let mut block = Block::default();
    let mut code_end = first;
    if matches!(c.peek(), Some(b'N' | b'n')) && c.peek_at(1).is_some_and(|b| b.is_ascii_digit()) {
        c.pos += 1;
        let digits = c.digits()?;
        block.number =
            Some(crate::dialect::lex::whole(&line[digits]).filter(|n| *n <= 999_999_999)?);
        code_end = c.pos;
        c.skip(sep);
    }
    while let Some(b) = c.peek() {
        if b == b';' {
            block.comment = crate::dialect::comment_text(&line[c.pos + 1..]);
            break;
        }
        if !b.is_ascii_alphabetic() {
            return None;
        }
        let start = c.pos;
        // The grammar's `ident`, to see what follows it.
        let ident_end = start
            + line[start..]
                .bytes()
                .take_while(|b| b.is_ascii_alphanumeric() || *b == b'_')
                .count();
        let mut after = Cursor::new(line);
        after.pos = ident_end;
        after.skip(sep);
        let word = if after.peek() == Some(b'=') {
            // `assignment`: a plain number only (AC/IC to the grammar).
            after.pos += 1;
            after.skip(sep);
            let value = Decimal::parse(after.number()?)?;
            c.pos = after.pos;
            Word {
                name: line[start..ident_end].to_ascii_uppercase(),
                value: Value::Plain(value),
                assigned: true,
                range: start..c.pos,
            }
        } else {
            c.pos = start + 1;
            match c.number() {
                // `word`: a letter and its number.
                Some(n) => Word {
                    name: line[start..start + 1].to_ascii_uppercase(),
                    value: Value::Plain(Decimal::parse(n)?),
                    assigned: false,
                    range: start..c.pos,
                },
                // A call or a label to the grammar; else a `keyword`.
                None if matches!(after.peek(), Some(b'(' | b':')) => return None,
                None => {
                    c.pos = ident_end;
                    Word {
                        name: line[start..ident_end].to_ascii_uppercase(),
                        value: Value::None,
                        assigned: false,
                        range: start..ident_end,
                    }
                }
            }
        };
        block.words.push(word);
        code_end = c.pos;
        c.skip(sep);
    }
    block.code_range = first..code_end;
    Some(block)
}

/// Parses one line with the grammar: the reading of every line the fast path declines, and
/// the source of every syntax error.
fn parse_with_grammar(line: &str) -> Result<Block, SyntaxError> {
    let mut pairs = SiemensParser::parse(Rule::line, line).map_err(|e| syntax_error(line, &e))?;
    let mut block = Block::default();
    let Some(line_pair) = pairs.next() else {
        return Ok(block);
    };
    let first = line.len() - line.trim_start_matches([' ', '\t', '\r']).len();
    let mut code_end = first;
    for pair in line_pair.into_inner() {
        match pair.as_rule() {
            Rule::header => {
                let mut inner = pair.into_inner();
                let name = inner.next().map_or("", |p| p.as_str()).to_ascii_uppercase();
                let sub = inner
                    .next()
                    .is_some_and(|k| k.as_str().eq_ignore_ascii_case("SPF"));
                block.header = Some((name, sub));
            }
            Rule::block => {
                for part in pair.into_inner() {
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
                            block.number = Some(
                                digits
                                    .parse()
                                    .ok()
                                    .filter(|n| *n <= 999_999_999)
                                    .ok_or_else(|| SyntaxError {
                                        offset: span.start(),
                                        message: format!(
                                            "`{}` is too large for a block number",
                                            span.as_str()
                                        ),
                                        help: "block numbers are N1 to N999999999".into(),
                                    })?,
                            );
                        }
                        Rule::word
                        | Rule::assignment
                        | Rule::call
                        | Rule::keyword
                        | Rule::label => {
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
            }
            _ => {}
        }
    }
    block.code_range = first..code_end.max(first);
    Ok(block)
}

fn number(text: &str, offset: usize) -> Result<Decimal, SyntaxError> {
    Decimal::parse(text).ok_or_else(|| SyntaxError {
        offset,
        message: format!("`{text}` has too many digits"),
        help: "numbers are at most 30 digits long".into(),
    })
}

fn word(part: pest::iterators::Pair<'_, Rule>, range: Range<usize>) -> Result<Word, SyntaxError> {
    let rule = part.as_rule();
    let start = range.start;
    let whole = part.as_str();
    let mut inner = part.into_inner();
    let (name, value) = match rule {
        Rule::keyword => (whole.to_string(), Value::None),
        Rule::label => (
            inner.next().map_or("", |p| p.as_str()).to_string(),
            Value::Label,
        ),
        Rule::call => (
            inner.next().map_or("", |p| p.as_str()).to_string(),
            Value::Call,
        ),
        Rule::word => {
            let name = inner.next().map_or("", |p| p.as_str()).to_string();
            let text = inner.next().map_or("", |p| p.as_str());
            (name, Value::Plain(number(text, start)?))
        }
        _ => {
            let name = inner.next().map_or("", |p| p.as_str()).to_string();
            let value = match inner.next() {
                Some(v) if v.as_rule() == Rule::number => Value::Plain(number(v.as_str(), start)?),
                Some(v) => {
                    let absolute = v.as_rule() == Rule::absolute;
                    let text = v.into_inner().next().map_or("", |n| n.as_str());
                    let d = number(text, start)?;
                    if absolute {
                        Value::Absolute(d)
                    } else {
                        Value::Incremental(d)
                    }
                }
                None => Value::None,
            };
            (name, value)
        }
    };
    Ok(Word {
        name: name.to_ascii_uppercase(),
        value,
        assigned: rule == Rule::assignment,
        range,
    })
}

fn syntax_error(line: &str, e: &pest::error::Error<Rule>) -> SyntaxError {
    let offset = crate::dialect::pest_error_offset(line, e);
    let rest = &line[offset..];
    let before = line[..offset].trim_end();
    if before.ends_with(['=', '(', '+', '-', '*', '/']) && !rest.is_empty() {
        return SyntaxError {
            offset,
            message: "a value that is not a number, AC(…) or IC(…): expressions, R parameters and variables are not read".into(),
            help: "write the value as a number (`X=20.5`, `X=AC(20.5)`)".into(),
        };
    }
    let (message, help) = match rest.chars().next() {
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
        Some('=') => (
            "a value that is not a number, AC(…) or IC(…): expressions and variables are not read"
                .to_string(),
            "write the value as a number (`X=20.5`, `X=AC(20.5)`)".to_string(),
        ),
        Some(':') => (
            "a label or a main block number (`:10`): jumps and labels are not read".to_string(),
            HELP.to_string(),
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

    const TOKENS: &[&str] = &[
        " ",
        "\t",
        "\r",
        "/",
        "N",
        "n",
        "10",
        "0",
        "9999999999",
        ".5",
        "-",
        "+",
        ".",
        "G",
        "g",
        "X",
        "Z",
        "SF",
        "LIMS",
        "DIAMON",
        "GOTOF",
        "R1",
        "_",
        "=",
        "AC(",
        "IC(",
        "(",
        ")",
        "\"",
        ":",
        ";",
        "; c",
        "%",
        "%_N_A_MPF",
        "Ž",
        "1234567890123456789012345678901",
    ];

    crate::dialect::lex::agreement_tests!(fast_line, parse_with_grammar, TOKENS);

    #[test]
    fn words_assignments_keywords_and_comments() {
        let b = parse_line("N20 g33 Z-20 K1.5 SF=90 X=AC(20) Z=IC(-2.5) DIAMON ; pass 1").unwrap();
        assert_eq!(b.number, Some(20));
        let names: Vec<&str> = b.words.iter().map(|w| w.name.as_str()).collect();
        assert_eq!(names, ["G", "Z", "K", "SF", "X", "Z", "DIAMON"]);
        assert_eq!(b.words[3].plain(), Decimal::parse("90"));
        assert!(matches!(b.words[4].value, Value::Absolute(_)));
        assert!(matches!(b.words[5].value, Value::Incremental(_)));
        assert_eq!(b.words[6].value, Value::None);
        assert_eq!(b.comment.as_deref(), Some("pass 1"));
        assert_eq!(&"N20 g33"[b.code_range.start..7], "N20 g33");
    }

    #[test]
    fn the_header_names_the_program() {
        let b = parse_line("%_N_SHAFT_2_MPF").unwrap();
        assert_eq!(b.header, Some(("SHAFT_2".into(), false)));
        let b = parse_line("%_N_THREAD_spf").unwrap();
        assert_eq!(b.header, Some(("THREAD".into(), true)));
        assert!(parse_line("%").is_err());
    }

    #[test]
    fn what_the_front_end_names_is_read_and_the_rest_is_a_syntax_error() {
        let b = parse_line("CYCLE97(1.5,,0,-20) R1=2 GOTOF END L10").unwrap();
        let names: Vec<&str> = b.words.iter().map(|w| w.name.as_str()).collect();
        assert_eq!(names, ["CYCLE97", "R1", "GOTOF", "END", "L"]);
        assert_eq!(b.words[0].value, Value::Call);
        assert!(b.words[1].assigned);
        assert!(parse_line("X=R1+2").is_err());
        // An address without its number is a name here; the front end says what is missing.
        assert_eq!(parse_line("G0 X").unwrap().words[1].value, Value::None);
        assert!(parse_line("G0 Ž").is_err());
        let b = parse_line("MSG(\"A;B (C)\") ; note").unwrap();
        assert_eq!(b.words[0].name, "MSG");
        assert_eq!(b.comment.as_deref(), Some("note"));
        let b = parse_line("PROGR: G0 X1").unwrap();
        assert_eq!(b.words[0].value, Value::Label);
        let e = parse_line("N10 G0 X=R04+20").unwrap_err();
        assert!(e.message.contains("expressions"), "{}", e.message);
    }
}

//! The RS274/NGC line syntax (`grammar/iso.pest`): one line in, one [`Block`] out.

use std::ops::Range;

use pest::Parser;
use pest_derive::Parser;

use crate::fixed::Decimal;

#[derive(Parser)]
#[grammar = "../grammar/iso.pest"]
struct IsoParser;

/// `X26.618`: the address letter (upper case), the value, and the byte range in the line.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Word {
    pub letter: char,
    pub value: Decimal,
    pub range: Range<usize>,
}

/// What [`Unread`] says of a line's leading `/`.
pub const BLOCK_DELETE: &str = "block delete `/`";

/// Something the line holds that ncthread does not read (a parameter, an expression, an
/// O-word, block delete), with its range.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Unread {
    pub what: &'static str,
    pub range: Range<usize>,
}

/// Everything a line holds, in the order written.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Block {
    pub number: Option<u32>,
    pub words: Vec<Word>,
    /// Every `( )` and `;` comment, trimmed.
    pub comments: Vec<String>,
    pub unread: Vec<Unread>,
    /// A `%` line.
    pub delimiter: bool,
}

impl Block {
    /// Only a block number and/or comments.
    pub fn is_empty(&self) -> bool {
        self.words.is_empty() && self.unread.is_empty() && !self.delimiter
    }
}

/// Why a line could not be read: the byte offset and what was found there.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SyntaxError {
    pub offset: usize,
    pub message: String,
}

/// Parses one line (without its line ending).
pub fn parse_line(line: &str) -> Result<Block, SyntaxError> {
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
                Rule::parameter => block.unread.push(Unread {
                    what: "parameter assignment",
                    range,
                }),
                Rule::oword => block.unread.push(Unread {
                    what: "O-word (subroutine or control flow)",
                    range,
                }),
                Rule::word => {
                    let mut inner = part.into_inner();
                    let letter = inner.next().expect("word has an address").as_str();
                    let letter = letter.chars().next().unwrap_or('?').to_ascii_uppercase();
                    let value = inner.next().expect("word has a value");
                    if value.as_rule() == Rule::expression {
                        block.unread.push(Unread {
                            what: "parameter or expression as a value",
                            range,
                        });
                        continue;
                    }
                    match Decimal::parse(value.as_str()) {
                        Some(value) => block.words.push(Word {
                            letter,
                            value,
                            range,
                        }),
                        None => {
                            return Err(SyntaxError {
                                offset: span.start(),
                                message: format!("`{}` has too many digits", value.as_str()),
                            });
                        }
                    }
                }
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
    fn reads_delimiters_and_comment_lines() {
        assert!(parse_line("%").unwrap().delimiter);
        let b = parse_line("  (only a comment)").unwrap();
        assert!(b.is_empty());
        assert_eq!(b.comments, ["only a comment"]);
        assert!(parse_line("").unwrap().is_empty());
    }

    #[test]
    fn names_what_it_does_not_read() {
        let b = parse_line("#1 = 5").unwrap();
        assert_eq!(b.unread[0].what, "parameter assignment");
        let b = parse_line("G0 X#1 Z[2*3]").unwrap();
        assert_eq!(b.unread.len(), 2);
        assert_eq!(b.unread[1].range, 7..13);
        let b = parse_line("o100 sub").unwrap();
        assert!(b.unread[0].what.starts_with("O-word"));
        let b = parse_line("/G0 X1").unwrap();
        assert_eq!(b.unread[0].what, "block delete `/`");
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
}

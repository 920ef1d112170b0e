//! The grammar's reading of the common, well-formed lines without pest (see `dialect::lex`):
//! plain words and comments, and LinuxCNC's macro language as programs write it — parameter
//! settings (`#<pass> = [#<pass> + 1]`), computed words (`X[30 - #<pass> * 0.25]`, `Z#1`) and
//! O-words (`o100 while [#<pass> LE 4]`). `None` at anything else (a function, an error, a rare
//! form): the grammar reads that line. Each reading here is the grammar's, range for range
//! (the agreement tests in `syntax`'s tests hold it to `parse_with_grammar`).

use super::{
    BLOCK_DELETE, Block, Keyword, Label, OWord, Setting, Unread, Word, check_expression_size,
    name_text,
};
use crate::dialect::iso::expr::{Expr, ExprKind, Op, Param};
use crate::dialect::lex::{Cursor, blank_tab_or_cr};
use crate::fixed::Decimal;

/// [`fast_line_into`] into a new block.
#[cfg(test)]
pub(super) fn fast_line(line: &str) -> Option<Block> {
    fast_line_into(line, Vec::new())
}

/// A line of words, comments, settings or one O-word, as the grammar reads it; `None` when
/// the grammar may read it otherwise. Its words go into `words` (the room of a line read
/// before; emptied first).
pub(super) fn fast_line_into(line: &str, mut words: Vec<Word>) -> Option<Block> {
    words.clear();
    let mut c = Cursor::new(line);
    c.skip(blank_tab_or_cr);
    let mut block = Block {
        words,
        ..Block::default()
    };
    if c.delimiter(blank_tab_or_cr)? {
        block.delimiter = true;
        return Some(block);
    }
    if c.peek() == Some(b'/') {
        block.unread.push(Unread {
            what: BLOCK_DELETE,
            range: c.pos..c.pos + 1,
        });
        c.pos += 1;
        c.skip(blank_tab_or_cr);
    }
    if let Some(digits) = c.block_number(blank_tab_or_cr) {
        block.number = Some(crate::dialect::lex::whole(&line[digits])?);
        if c.peek() == Some(b'.') {
            c.pos += 1;
            c.digits()?;
        }
        c.skip(blank_tab_or_cr);
    }
    // Expressions are read only once the line is known to be of a size the grammar reads.
    let mut sized = false;
    let mut sized_ok = || {
        if !sized {
            check_expression_size(line).ok()?;
            sized = true;
        }
        Some(())
    };
    if matches!(c.peek(), Some(b'O' | b'o')) {
        sized_ok()?;
        block.oword = Some(Box::new(oword(&mut c, &mut block.comments)?));
        return Some(block);
    }
    while !c.at_end() {
        let start = c.pos;
        match c.peek()? {
            b'(' => block
                .comments
                .extend(crate::dialect::comment_text(c.paren_comment()?)),
            b';' => {
                block
                    .comments
                    .extend(crate::dialect::comment_text(&c.rest()[1..]));
                break;
            }
            b'#' => {
                sized_ok()?;
                block.settings.push(setting(&mut c)?);
            }
            // An O-word stands first on its line; an `o` later (`G0 O5`, a word O) is left to
            // the grammar.
            b'O' | b'o' => return None,
            b if b.is_ascii_alphabetic() => {
                c.pos += 1;
                let letter = b.to_ascii_uppercase() as char;
                let after_letter = c.pos;
                if let Some(value) = c.value(blank_tab_or_cr) {
                    block.words.push(Word {
                        letter,
                        value,
                        range: start..c.pos,
                        expr: None,
                    });
                } else {
                    // Not a number: a computed value (`X#1`, `Z-[#2 - 1]`), or the grammar's.
                    c.pos = after_letter;
                    c.skip(blank_tab_or_cr);
                    if !computed_value_follows(&c) {
                        return None;
                    }
                    sized_ok()?;
                    block.exprs.push(real_value(&mut c)?);
                    block.words.push(Word {
                        letter,
                        value: Decimal::default(),
                        range: start..c.pos,
                        expr: Some(block.exprs.len() - 1),
                    });
                }
            }
            _ => return None,
        }
        c.skip(blank_tab_or_cr);
    }
    Some(block)
}

/// Whether a sign (and blanks), then `[` or `#` follow: a value only `real_value` reads.
fn computed_value_follows(c: &Cursor<'_>) -> bool {
    let bytes = c.text.as_bytes();
    let mut at = c.pos;
    if matches!(bytes.get(at), Some(b'+' | b'-')) {
        at += 1;
        while bytes.get(at).is_some_and(|&b| blank_tab_or_cr(b)) {
            at += 1;
        }
    }
    matches!(bytes.get(at), Some(b'[' | b'#'))
}

/// The grammar's `real_value` (never at a blank): `sign? ~ sep* ~ (bracket | parameter |
/// unsigned)`; a function is the grammar's.
fn real_value(c: &mut Cursor<'_>) -> Option<Expr> {
    let start = c.pos;
    let negative = match c.peek()? {
        b'-' => true,
        b'+' => false,
        _ => return value_body(c),
    };
    c.pos += 1;
    c.skip(blank_tab_or_cr);
    let value = value_body(c)?;
    Some(if negative {
        Expr {
            kind: ExprKind::Negate(Box::new(value)),
            range: start..c.pos,
        }
    } else {
        value
    })
}

fn value_body(c: &mut Cursor<'_>) -> Option<Expr> {
    match c.peek()? {
        b'[' => bracket(c),
        b'#' => parameter(c),
        b'0'..=b'9' | b'.' => {
            let start = c.pos;
            let number = unsigned(c)?;
            Some(Expr {
                kind: ExprKind::Number(number),
                range: start..c.pos,
            })
        }
        _ => None,
    }
}

/// The grammar's `unsigned` (the cursor at a digit or a point), as `number_of` reads it.
fn unsigned(c: &mut Cursor<'_>) -> Option<f64> {
    c.number()?.parse().ok()
}

/// `[` expression `]`: operands and operators, combined by precedence as the grammar's
/// reading does ([`Expr::binary`]).
fn bracket(c: &mut Cursor<'_>) -> Option<Expr> {
    c.pos += 1;
    c.skip(blank_tab_or_cr);
    let mut operands = vec![real_value(c)?];
    let mut ops = Vec::new();
    loop {
        let before = c.pos;
        c.skip(blank_tab_or_cr);
        let Some(op) = operator(c) else {
            c.pos = before;
            break;
        };
        c.skip(blank_tab_or_cr);
        ops.push(op);
        operands.push(real_value(c)?);
    }
    c.skip(blank_tab_or_cr);
    if c.peek()? != b']' {
        return None;
    }
    c.pos += 1;
    Some(Expr::binary(operands, ops))
}

/// The grammar's `operator`, its alternatives tried in its order.
fn operator(c: &mut Cursor<'_>) -> Option<Op> {
    const OPERATORS: [&str; 15] = [
        "**", "*", "/", "mod", "+", "-", "eq", "ne", "gt", "ge", "lt", "le", "and", "xor", "or",
    ];
    let rest = c.rest().as_bytes();
    let text = OPERATORS.into_iter().find(|op| {
        rest.get(..op.len())
            .is_some_and(|r| r.eq_ignore_ascii_case(op.as_bytes()))
    })?;
    c.pos += text.len();
    Op::parse(text)
}

/// `#…` (the cursor at `#`).
fn parameter(c: &mut Cursor<'_>) -> Option<Expr> {
    let hash = c.pos;
    c.pos += 1;
    let param = parameter_body(c, hash)?;
    Some(Expr {
        kind: ExprKind::Param(param),
        range: hash..c.pos,
    })
}

/// What follows a `#` (at `hash`) and blanks: a name, a parameter, a bracket or a number.
fn parameter_body(c: &mut Cursor<'_>, hash: usize) -> Option<Param> {
    c.skip(blank_tab_or_cr);
    Some(match c.peek()? {
        b'<' => Param::Named(name_text(name(c)?)),
        b'#' => Param::Numbered(Box::new(parameter(c)?)),
        b'[' => Param::Numbered(Box::new(bracket(c)?)),
        b'0'..=b'9' | b'.' => {
            let number = unsigned(c)?;
            Param::Numbered(Box::new(Expr {
                kind: ExprKind::Number(number),
                range: hash..c.pos,
            }))
        }
        _ => return None,
    })
}

/// The grammar's `name` (the cursor at `<`): `<`, at least one character that is neither `<`
/// nor `>`, `>`.
fn name<'a>(c: &mut Cursor<'a>) -> Option<&'a str> {
    let rest = c.rest();
    let end = rest[1..].find(['<', '>'])? + 1;
    if end == 1 || rest.as_bytes()[end] != b'>' {
        return None;
    }
    c.pos += end + 1;
    Some(&rest[..=end])
}

/// `#1 = 5`, `#<x> = [#<x> + 1]` (the cursor at `#`).
fn setting(c: &mut Cursor<'_>) -> Option<Setting> {
    let start = c.pos;
    c.pos += 1;
    let param = parameter_body(c, start)?;
    c.skip(blank_tab_or_cr);
    if c.peek()? != b'=' {
        return None;
    }
    c.pos += 1;
    c.skip(blank_tab_or_cr);
    let value = real_value(c)?;
    Some(Setting {
        param,
        value,
        range: start..c.pos,
    })
}

/// An O-word line from its `o` to the line's end: label, keyword, bracketed arguments and a
/// comment (into `comments`).
fn oword(c: &mut Cursor<'_>, comments: &mut Vec<String>) -> Option<OWord> {
    let start = c.pos;
    c.pos += 1;
    c.skip(blank_tab_or_cr);
    let label = match c.peek()? {
        b'<' => Label::Name(name_text(name(c)?)),
        b'0'..=b'9' | b'.' => {
            let number = c.number()?;
            Label::Number(number.trim_start_matches('0').to_string())
        }
        _ => return None,
    };
    c.skip(blank_tab_or_cr);
    // `ASCII_ALPHA ~ (sep* ~ ASCII_ALPHA)*`, its blanks left out.
    if !c.peek()?.is_ascii_alphabetic() {
        return None;
    }
    let mut keyword = String::new();
    loop {
        keyword.push(char::from(c.peek()?));
        c.pos += 1;
        let before = c.pos;
        c.skip(blank_tab_or_cr);
        if !c.peek().is_some_and(|b| b.is_ascii_alphabetic()) {
            c.pos = before;
            break;
        }
    }
    let keyword = Keyword::parse(&keyword)?;
    let mut args = Vec::new();
    loop {
        let before = c.pos;
        c.skip(blank_tab_or_cr);
        if c.peek() != Some(b'[') {
            c.pos = before;
            break;
        }
        args.push(bracket(c)?);
    }
    c.skip(blank_tab_or_cr);
    match c.peek() {
        Some(b'(') => comments.extend(crate::dialect::comment_text(c.paren_comment()?)),
        Some(b';') => {
            comments.extend(crate::dialect::comment_text(&c.rest()[1..]));
            c.pos = c.text.len();
        }
        _ => {}
    }
    c.skip(blank_tab_or_cr);
    if !c.at_end() {
        return None;
    }
    Some(OWord {
        label,
        keyword,
        args,
        range: start..c.pos,
    })
}

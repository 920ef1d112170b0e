//! A byte cursor for the syntax layers' fast paths.
//!
//! Every dialect's grammar (`grammar/*.pest`) is the definition of its line syntax and the
//! source of its syntax errors. Parsing each line with pest costs most of a reader's time
//! (its call tracker, stack checks and pair tree), so each syntax layer first tries a
//! hand-written reading of the common, well-formed lines: it returns `None` at anything it is
//! not sure of (an error, a rare form; an expression but in ISO's), and pest reads that line. Each fast path
//! is tested against its grammar line by line (the corpus, generated programs and random
//! lines): where it answers, it answers exactly what the grammar's reading does.

use crate::fixed::Decimal;

/// A position in a line's bytes.
pub(crate) struct Cursor<'a> {
    pub text: &'a str,
    pub pos: usize,
}

impl<'a> Cursor<'a> {
    pub fn new(text: &'a str) -> Self {
        Cursor { text, pos: 0 }
    }

    pub fn peek(&self) -> Option<u8> {
        self.text.as_bytes().get(self.pos).copied()
    }

    pub fn peek_at(&self, ahead: usize) -> Option<u8> {
        self.text.as_bytes().get(self.pos + ahead).copied()
    }

    pub fn at_end(&self) -> bool {
        self.pos >= self.text.len()
    }

    pub fn rest(&self) -> &'a str {
        &self.text[self.pos..]
    }

    /// Skips the bytes `sep` accepts (the grammar's `sep*`).
    pub fn skip(&mut self, sep: impl Fn(u8) -> bool) {
        while self.peek().is_some_and(&sep) {
            self.pos += 1;
        }
    }

    /// `ASCII_DIGIT+`: the digits' range, or `None` (nothing taken).
    pub fn digits(&mut self) -> Option<std::ops::Range<usize>> {
        let start = self.pos;
        while self.peek().is_some_and(|b| b.is_ascii_digit()) {
            self.pos += 1;
        }
        (self.pos > start).then_some(start..self.pos)
    }

    /// `%` and blanks to the line's end (a delimiter line of the ISO, FANUC and НЦ-31
    /// grammars): whether the line is one. `None` when it starts with `%` and goes on (the
    /// grammar reads that).
    pub fn delimiter(&mut self, sep: impl Fn(u8) -> bool) -> Option<bool> {
        if self.peek() != Some(b'%') {
            return Some(false);
        }
        self.pos += 1;
        self.skip(sep);
        self.at_end().then_some(true)
    }

    /// The ISO and FANUC grammars' `N` `sep*` `digits`: the digits' range. At an `N` without
    /// digits (`N-5`, a word N) or at no `N`, nothing is taken.
    pub fn block_number(&mut self, sep: impl Fn(u8) -> bool) -> Option<std::ops::Range<usize>> {
        if !matches!(self.peek(), Some(b'N' | b'n')) {
            return None;
        }
        let start = self.pos;
        self.pos += 1;
        self.skip(sep);
        let digits = self.digits();
        if digits.is_none() {
            self.pos = start;
        }
        digits
    }

    /// The ISO and FANUC grammars' `( )` comment at `(`: its text, without a `(` inside.
    /// `None` (the grammar's) when it is not closed or holds a `(`.
    pub fn paren_comment(&mut self) -> Option<&'a str> {
        let text = &self.rest()[1..];
        let end = text.find([')', '('])?;
        if text.as_bytes()[end] != b')' {
            return None;
        }
        self.pos += end + 2;
        Some(&text[..end])
    }

    /// A word's value after its letter, as the ISO, FANUC and czech grammars read it: blanks
    /// allowed, then a number. `None` may leave the cursor past the blanks (or past a number
    /// too long to read): a caller that tries another reading puts it back first.
    ///
    /// Inlined on purpose: returned from a call, the `Decimal` goes through memory and the
    /// store-forwarding stall its parts' merge below avoids comes back (BENCHMARKS.md,
    /// twelfth round).
    #[inline(always)]
    pub fn value(&mut self, sep: impl Fn(u8) -> bool) -> Option<Decimal> {
        self.skip(sep);
        let start = self.pos;
        // One pass over the digits while they fit in a u64 (every word of a real program);
        // a longer number is read by `Decimal::parse`, which knows what fits.
        let bytes = self.text.as_bytes();
        let mut at = start;
        let negative = match bytes.get(at) {
            Some(b'-') => {
                at += 1;
                true
            }
            Some(b'+') => {
                at += 1;
                false
            }
            _ => false,
        };
        let (mut mantissa, mut digits, mut scale, mut has_point) = (0u64, 0u32, 0u32, false);
        let mut long = false;
        while let Some(&b) = bytes.get(at) {
            if b.is_ascii_digit() {
                if digits == 18 {
                    long = true;
                    break;
                }
                mantissa = mantissa * 10 + u64::from(b - b'0');
                digits += 1;
                scale += u32::from(has_point);
            } else if b == b'.' && !has_point {
                has_point = true;
            } else {
                break;
            }
            at += 1;
        }
        // The parts as plain integers on both paths, put together once: a `Decimal` made on
        // each path and merged is copied through memory, and stalls the store that follows.
        let (mantissa, scale, has_point) = if long || digits == 0 {
            // More digits than fit in a u64 (`Decimal::parse` knows what fits), or none
            // (`number` takes nothing).
            let d = Decimal::parse(self.number()?)?;
            (d.mantissa, d.scale, d.has_point)
        } else {
            self.pos = at;
            let mantissa = i128::from(mantissa);
            (
                if negative { -mantissa } else { mantissa },
                scale,
                has_point,
            )
        };
        Some(Decimal {
            mantissa,
            scale,
            has_point,
        })
    }

    /// The grammars' `number`: `("+" | "-")? ~ (ASCII_DIGIT+ ~ ("." ~ ASCII_DIGIT*)? | "." ~
    /// ASCII_DIGIT+)`, greedy as pest reads it; `None` takes nothing.
    pub fn number(&mut self) -> Option<&'a str> {
        let start = self.pos;
        if matches!(self.peek(), Some(b'+' | b'-')) {
            self.pos += 1;
        }
        if self.digits().is_some() {
            if self.peek() == Some(b'.') {
                self.pos += 1;
                self.digits();
            }
        } else if self.peek() == Some(b'.') && self.peek_at(1).is_some_and(|b| b.is_ascii_digit()) {
            self.pos += 1;
            self.digits();
        } else {
            self.pos = start;
            return None;
        }
        Some(&self.text[start..self.pos])
    }
}

/// The value of `digits` (as [`Cursor::digits`] takes them), as `str::parse::<u32>` reads
/// ASCII digits: `None` when empty, not all digits, or too large.
pub(crate) fn whole(digits: &str) -> Option<u32> {
    if digits.is_empty() {
        return None;
    }
    digits.bytes().try_fold(0u32, |v, d| {
        let d = d.is_ascii_digit().then(|| u32::from(d - b'0'))?;
        v.checked_mul(10)?.checked_add(d)
    })
}

/// The grammars' `sep` of czech and НЦ-31 lines: a blank or a tab.
pub(crate) fn blank_or_tab(b: u8) -> bool {
    b == b' ' || b == b'\t'
}

/// The grammars' `sep` of ISO and FANUC lines: a blank, a tab or a carriage return.
pub(crate) fn blank_tab_or_cr(b: u8) -> bool {
    b == b' ' || b == b'\t' || b == b'\r'
}

#[cfg(test)]
mod tests {
    use super::*;

    fn number(text: &str) -> Option<(&str, usize)> {
        let mut c = Cursor::new(text);
        c.number().map(|n| (n, c.pos))
    }

    #[test]
    fn reads_numbers_as_the_grammar_does() {
        assert_eq!(number("26.618Z"), Some(("26.618", 6)));
        assert_eq!(number("-9."), Some(("-9.", 3)));
        assert_eq!(number("+.5"), Some(("+.5", 3)));
        assert_eq!(number("1.2.3"), Some(("1.2", 3)));
        assert_eq!(number("-."), None);
        assert_eq!(number("."), None);
        assert_eq!(number("- 5"), None);
        assert_eq!(number(""), None);
    }

    #[test]
    fn a_whole_number_is_what_parse_reads() {
        for digits in [
            "",
            "1a",
            "0",
            "7",
            "0042",
            "4294967295",
            "4294967296",
            "99999999999",
            "1",
        ] {
            assert_eq!(whole(digits), digits.parse::<u32>().ok(), "{digits}");
        }
    }

    #[test]
    fn a_value_is_the_number_read_then_parsed() {
        let long = "1234567890123456789012345678901234567890";
        for text in [
            "26.618Z",
            "-9.",
            "+.5",
            "1.2.3",
            "-.",
            ".",
            "- 5",
            "",
            "-00120.000",
            "-0",
            "5.X",
            "..5",
            "999999999999999999",
            "9999999999999999999",
            "-1234567890.12345678",
            "0.0000000000000000001",
            long,
            "12 34",
            "  7",
            "+",
            "x5",
        ] {
            let mut fast = Cursor::new(text);
            let mut slow = Cursor::new(text);
            let read = fast.value(|b| b == b' ');
            slow.skip(|b| b == b' ');
            let expected = slow.number().and_then(Decimal::parse);
            assert_eq!(read, expected, "{text:?}");
            if read.is_some() {
                assert_eq!(fast.pos, slow.pos, "{text:?}");
            }
        }
    }
}

/// What the fast paths' tests share: every line of the corpus, and random lines made of a
/// dialect's tokens.
#[cfg(test)]
pub(crate) mod agreement {
    use proptest::prelude::*;

    /// Every line of every program in `corpus/` (of any dialect: another dialect's lines are
    /// hostile input too), decoded lossily.
    pub fn corpus_lines() -> Vec<String> {
        let mut lines = Vec::new();
        let mut dirs = vec![std::path::PathBuf::from(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/corpus"
        ))];
        while let Some(dir) = dirs.pop() {
            for entry in std::fs::read_dir(&dir).expect("corpus/ is readable") {
                let path = entry.expect("a corpus entry").path();
                if path.is_dir() {
                    dirs.push(path);
                } else if path.extension().is_some_and(|e| e == "nc" || e == "ngc") {
                    let bytes = std::fs::read(&path).expect("a corpus file");
                    let text = String::from_utf8_lossy(&bytes);
                    lines.extend(
                        text.split('\n')
                            .map(|l| l.trim_end_matches('\r').to_string()),
                    );
                }
            }
        }
        lines
    }

    /// Checks the fast path against the grammar on every corpus line, and that it reads at
    /// least 90 % of the lines the grammar reads (a fast path that declines everything is
    /// correct and useless).
    pub fn on_corpus<B: PartialEq + std::fmt::Debug, E: std::fmt::Debug>(
        fast: impl Fn(&str) -> Option<B>,
        grammar: impl Fn(&str) -> Result<B, E>,
    ) {
        let (mut fast_read, mut read) = (0, 0);
        for line in corpus_lines() {
            let slow = grammar(&line);
            if slow.is_ok() {
                read += 1;
            }
            if let Some(b) = fast(&line) {
                fast_read += 1;
                match slow {
                    Ok(s) => assert_eq!(b, s, "the fast path differs on {line:?}"),
                    Err(e) => panic!("the fast path reads {line:?}, the grammar does not: {e:?}"),
                }
            }
        }
        assert!(
            fast_read * 10 >= read * 9,
            "the fast path reads {fast_read} of {read} lines"
        );
    }

    /// Lines of 0 to 14 tokens from `tokens`, joined without blanks.
    pub fn lines(tokens: &'static [&'static str]) -> impl Strategy<Value = String> {
        prop::collection::vec(prop::sample::select(tokens), 0..14).prop_map(|t| t.concat())
    }
}

/// The two tests of a syntax layer's fast path against its grammar (in its `tests` module):
/// `agreement_tests!(fast_line, parse_with_grammar, TOKENS)`.
#[cfg(test)]
macro_rules! agreement_tests {
    ($fast:ident, $grammar:ident, $tokens:expr) => {
        #[test]
        fn the_fast_path_reads_as_the_grammar_does_on_the_corpus() {
            crate::dialect::lex::agreement::on_corpus($fast, $grammar);
        }

        proptest::proptest! {
            #![proptest_config(proptest::prelude::ProptestConfig::with_cases(4000))]
            #[test]
            fn the_fast_path_reads_as_the_grammar_does(
                line in crate::dialect::lex::agreement::lines($tokens)
            ) {
                if let Some(parsed) = $fast(&line) {
                    proptest::prop_assert_eq!(Ok(parsed), $grammar(&line));
                }
            }
        }
    };
}
#[cfg(test)]
pub(crate) use agreement_tests;

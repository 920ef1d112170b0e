//! Source text, lines and spans.

use std::ops::Range;

/// Where something stands in a source file: 1-based line and column (in characters) and the
/// byte range in the whole text. The offsets are 32-bit (every IR item holds a span; a text
/// past 4 GiB has its spans there cut at its 4 GiB mark, which no program reaches).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Span {
    pub line: u32,
    pub column: u32,
    pub start: u32,
    pub end: u32,
}

impl Span {
    /// The byte range in the whole text.
    pub fn range(&self) -> Range<usize> {
        self.start as usize..self.end as usize
    }
}

/// A byte offset of a text as a span holds it.
pub fn offset32(offset: usize) -> u32 {
    u32::try_from(offset).unwrap_or(u32::MAX)
}

/// One program text with its name (a path, or `<stdin>`).
#[derive(Clone, Debug)]
pub struct SourceFile {
    pub name: String,
    pub text: String,
    line_starts: LineStarts,
}

/// How many lines one entry of a [`LineStarts`] stands for.
const STRIDE: usize = 16;

/// Where every [`STRIDE`]th line of a text starts (a line between is found from there: a
/// table of every line took 4 bytes a line, as much as a short line's text), in 32-bit
/// offsets for a text under 4 GiB, else full-width; and how many lines there are. The last
/// line asked for is remembered, so that reading the lines in order finds each from the one
/// before.
#[derive(Clone, Debug)]
struct LineStarts {
    count: usize,
    every: Starts,
    /// The last line found (0-based), where it starts and where it ends with its line end
    /// (0: not found yet).
    last: std::cell::Cell<(usize, usize, usize)>,
}

#[derive(Clone, Debug)]
enum Starts {
    Narrow(Vec<u32>),
    Wide(Vec<usize>),
}

impl LineStarts {
    fn of(text: &str) -> LineStarts {
        let ends = memchr::memchr_iter(b'\n', text.as_bytes()).count();
        // A text ending in a line end has no line after it.
        let count = 1 + ends - usize::from(text.ends_with('\n'));
        let starts = std::iter::once(0)
            .chain(
                memchr::memchr_iter(b'\n', text.as_bytes())
                    .map(|i| i + 1)
                    .filter(|&i| i < text.len()),
            )
            .step_by(STRIDE);
        let entries = count.div_ceil(STRIDE);
        let every = match u32::try_from(text.len()) {
            Ok(_) => {
                let mut v = Vec::with_capacity(entries);
                v.extend(starts.map(|i| i as u32));
                Starts::Narrow(v)
            }
            Err(_) => {
                let mut v = Vec::with_capacity(entries);
                v.extend(starts);
                Starts::Wide(v)
            }
        };
        LineStarts {
            count,
            every,
            last: std::cell::Cell::new((0, 0, 0)),
        }
    }

    fn len(&self) -> usize {
        self.count
    }

    /// Where the `k`th entry's line (line `k · STRIDE`) starts.
    fn entry(&self, k: usize) -> Option<usize> {
        match &self.every {
            Starts::Narrow(v) => v.get(k).map(|&s| s as usize),
            Starts::Wide(v) => v.get(k).copied(),
        }
    }

    /// Where line `i` (0-based) of `text` starts, and where it ends with its line end.
    fn get(&self, text: &str, i: usize) -> Option<(usize, usize)> {
        if i >= self.count {
            return None;
        }
        let (last, at, end) = self.last.get();
        if last == i && end > 0 {
            return Some((at, end));
        }
        // From the last line found when it is before `i` in the same stretch, else from
        // the entry before `i`.
        let (mut line, mut start) = if last <= i && i - last <= i % STRIDE {
            (last, at)
        } else {
            let k = i / STRIDE;
            (k * STRIDE, self.entry(k)?)
        };
        while line < i {
            start += memchr::memchr(b'\n', text.as_bytes().get(start..)?)? + 1;
            line += 1;
        }
        let end = start + line_end(text.get(start..)?);
        self.last.set((i, start, end));
        Some((start, end))
    }

    /// How many lines start at or before `offset` of `text`.
    fn up_to(&self, text: &str, offset: usize) -> usize {
        let k = match &self.every {
            Starts::Narrow(v) => v.partition_point(|&s| s as usize <= offset),
            Starts::Wide(v) => v.partition_point(|&s| s <= offset),
        };
        let Some(from) = k.checked_sub(1).and_then(|k| self.entry(k)) else {
            return 0;
        };
        let to = offset.min(text.len());
        let ends = text
            .get(from..to)
            .map_or(0, |t| t.bytes().filter(|&b| b == b'\n').count());
        // A line end at `offset` (or the text's last one) starts no line there.
        let past_end = usize::from(to == text.len() && text.ends_with('\n') && to > from);
        ((k - 1) * STRIDE + 1 + ends - past_end).min(self.count)
    }
}

/// Where the first line of `text` ends, its line end included.
fn line_end(text: &str) -> usize {
    memchr::memchr(b'\n', text.as_bytes()).map_or(text.len(), |e| e + 1)
}

/// Line `number` at `offset`, its text `with_end` without its line ending.
fn line_at(number: u32, offset: usize, with_end: &str) -> Line<'_> {
    let text = with_end.strip_suffix('\n').unwrap_or(with_end);
    let text = text.strip_suffix('\r').unwrap_or(text);
    Line {
        number,
        offset,
        text,
    }
}

/// One line of a source file, without its line ending.
#[derive(Clone, Copy, Debug)]
pub struct Line<'a> {
    /// 1-based line number.
    pub number: u32,
    /// Byte offset of the line's first character in the whole text.
    pub offset: usize,
    pub text: &'a str,
}

impl SourceFile {
    pub fn new(name: impl Into<String>, text: impl Into<String>) -> SourceFile {
        let text = text.into();
        let line_starts = LineStarts::of(&text);
        SourceFile {
            name: name.into(),
            text,
            line_starts,
        }
    }

    /// How many lines the text has.
    pub fn line_count(&self) -> usize {
        self.line_starts.len()
    }

    /// Every line, LF or CRLF endings removed.
    pub fn lines(&self) -> impl Iterator<Item = Line<'_>> {
        let mut offset = 0;
        (0..self.line_starts.len()).map(move |i| {
            let rest = &self.text[offset..];
            let end = line_end(rest);
            let line = line_at(i as u32 + 1, offset, &rest[..end]);
            offset += end;
            line
        })
    }

    /// Line `number` (1-based). Out-of-range numbers give an empty line at the end.
    pub fn line(&self, number: u32) -> Line<'_> {
        let i = (number.max(1) - 1) as usize;
        let Some((start, end)) = self.line_starts.get(&self.text, i) else {
            return Line {
                number,
                offset: self.text.len(),
                text: "",
            };
        };
        line_at(number, start, &self.text[start..end])
    }

    /// The span of `range` (bytes within `line`'s text). A range that does not fall on
    /// character boundaries is widened to the characters it touches, and one that runs past
    /// the line is cut at its end.
    pub fn span_in_line(&self, line: Line<'_>, range: Range<usize>) -> Span {
        let text = line.text;
        let start = text.floor_char_boundary(range.start.min(text.len()));
        let end = text.ceil_char_boundary(range.end.clamp(start, text.len()));
        let column = text[..start].chars().count() as u32 + 1;
        Span {
            line: line.number,
            column,
            start: offset32(line.offset + start),
            end: offset32(line.offset + end),
        }
    }

    /// The span of the one character at byte `offset` of `line` (empty at the line's end):
    /// where a syntax error points.
    pub fn char_span(&self, line: Line<'_>, offset: usize) -> Span {
        let start = line.text.floor_char_boundary(offset.min(line.text.len()));
        let end = line.text[start..]
            .chars()
            .next()
            .map_or(start, |c| start + c.len_utf8());
        self.span_in_line(line, start..end)
    }

    /// The span of a byte range of the whole text (it should not cross a line end).
    pub fn span_of(&self, range: Range<usize>) -> Span {
        let index = self.line_starts.up_to(&self.text, range.start).max(1);
        let line = self.line(index as u32);
        let start = range.start.saturating_sub(line.offset);
        let end = range.end.saturating_sub(line.offset).max(start);
        self.span_in_line(line, start..end)
    }

    /// The span of a whole line.
    pub fn line_span(&self, line: Line<'_>) -> Span {
        self.span_in_line(line, 0..line.text.len())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_start_where_the_text_says_and_the_index_is_sized_to_them() {
        let long: String = (0..40).map(|i| format!("N{i} X{i}\r\n")).collect();
        let long_open = format!("{long}é\n\nlast");
        for text in [
            "",
            "\n",
            "a",
            "a\n",
            "a\nb",
            "a\n\n",
            "\r\nx\r\n",
            "é\nü\n\nz",
            &long,
            &long_open,
            &"\n".repeat(33),
        ] {
            let naive: Vec<&str> = if text.is_empty() {
                vec![""]
            } else {
                text.split_inclusive('\n')
                    .map(|l| l.trim_end_matches('\n').trim_end_matches('\r'))
                    .collect()
            };
            let src = SourceFile::new("t", text);
            let lines: Vec<&str> = src.lines().map(|l| l.text).collect();
            assert_eq!(lines, naive, "{text:?}");
            assert_eq!(src.line_count(), naive.len());
            // Each line asked for alone, backwards, then forwards (the remembered line).
            let n = naive.len() as u32;
            for number in (1..=n).rev().chain(1..=n) {
                let line = src.line(number);
                assert_eq!(line.text, naive[number as usize - 1], "{text:?} {number}");
                assert_eq!(&text[line.offset..line.offset + line.text.len()], line.text);
            }
            assert_eq!(src.line(n + 1).text, "");
            // The line of every offset, as counting the line ends before it says.
            for offset in (0..=text.len()).filter(|&o| text.is_char_boundary(o)) {
                let ends = text[..offset].matches('\n').count();
                let expected = (ends + 1).min(naive.len()) as u32;
                assert_eq!(
                    src.span_of(offset..offset).line,
                    expected,
                    "{text:?} @{offset}"
                );
            }
            let Starts::Narrow(v) = &src.line_starts.every else {
                panic!("a short text has 32-bit line starts");
            };
            assert_eq!(v.len(), naive.len().div_ceil(STRIDE), "{text:?}");
            assert_eq!(v.capacity(), v.len(), "{text:?}");
        }
    }

    #[test]
    fn splits_lf_and_crlf_lines() {
        let src = SourceFile::new("t", "N10 X1\r\nN20 Z2\nN30");
        let lines: Vec<_> = src.lines().map(|l| (l.number, l.offset, l.text)).collect();
        assert_eq!(
            lines,
            vec![(1, 0, "N10 X1"), (2, 8, "N20 Z2"), (3, 15, "N30")]
        );
        assert_eq!(SourceFile::new("t", "A\n").lines().count(), 1);
        assert_eq!(SourceFile::new("t", "").lines().count(), 1);
    }

    #[test]
    fn columns_count_characters() {
        let src = SourceFile::new("t", "“ŘÍ X1");
        let line = src.line(1);
        let x = line.text.find('X').unwrap();
        let span = src.span_in_line(line, x..x + 2);
        assert_eq!((span.line, span.column), (1, 5));
        assert_eq!(span.range().start, x);
        assert_eq!(src.span_of(x..x + 2), span);
        // A range inside a multi-byte character widens to the whole character.
        let accented = SourceFile::new("t", "é X");
        let span = accented.span_in_line(accented.line(1), 1..2);
        assert_eq!((span.start, span.end, span.column), (0, 2, 1));
        let span = accented.char_span(accented.line(1), 0);
        assert_eq!((span.start, span.end), (0, 2));
        let span = accented.char_span(accented.line(1), 99);
        assert_eq!((span.start, span.end, span.column), (4, 4, 4));
        let two = SourceFile::new("t", "ab\ncd");
        assert_eq!(two.span_of(4..5).line, 2);
        assert_eq!(two.span_of(4..5).column, 2);
    }
}

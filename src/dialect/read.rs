//! What every reader shares. A dialect's front end owns a [`Reader`] and adds only its own
//! rules: the reader holds the items read so far, the diagnostics and the known position,
//! stamps block numbers, reports what comes after the program's end once, and applies the
//! unsupported policy (refuse, or keep the block as an opaque item) in one way for every
//! dialect.

use std::ops::Range;

use crate::diag::{Code, Diagnostic};
use crate::fixed::Length;
use crate::ir::{DialectId, Item, ItemKind, ModalContext, Pos, Program};
use crate::source::{Line, SourceFile, Span};

/// ` (did you mean G33?)` when `code` (`G32`) is one edit away from a code the dialect reads
/// (a digit changed, added or left out), else nothing.
pub fn did_you_mean(code: &str, known: &[&str]) -> String {
    fn distance(a: &str, b: &str) -> usize {
        let (a, b): (Vec<char>, Vec<char>) = (a.chars().collect(), b.chars().collect());
        let mut row: Vec<usize> = (0..=b.len()).collect();
        for (i, ca) in a.iter().enumerate() {
            let mut previous = row[0];
            row[0] = i + 1;
            for (j, cb) in b.iter().enumerate() {
                let here = row[j + 1];
                row[j + 1] = (previous + usize::from(ca != cb))
                    .min(row[j] + 1)
                    .min(here + 1);
                previous = here;
            }
        }
        row[b.len()]
    }
    known
        .iter()
        .filter(|k| **k != code && distance(code, k) == 1)
        // A digit changed before one added or left out; then the nearest number (G32 → G33,
        // not G30 or G02).
        .min_by_key(|k| {
            let number = |c: &str| c[1..].parse::<f64>().unwrap_or(0.0);
            (
                k.len().abs_diff(code.len()),
                ((number(k) - number(code)).abs() * 10.0) as u64,
            )
        })
        .map(|k| format!(" (did you mean {k}?)"))
        .unwrap_or_default()
}

/// The help of an unsupported word in a block that cuts a thread.
pub const THREAD_HELP: &str = "this block cuts a thread, which ncthread converts only when it reads every word of the block: rewrite or remove this word (`--unsupported warn` cannot keep a thread block: the thread would not be checked)";

/// How many problems of one kind a reader reports for one line before it only counts them:
/// a hostile line of 50,000 repeated words gets a few diagnostics and a count.
pub(crate) const WORD_REPORTS: usize = 5;

/// Counts one more problem on the line; true while it should still be reported.
pub(crate) fn budget(count: &mut usize) -> bool {
    *count += 1;
    *count <= WORD_REPORTS
}

/// What a front end does with constructs its dialect's documentation does not define.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Unsupported {
    /// Refuse the program (default).
    #[default]
    Error,
    /// Warn and keep the block as an opaque item (only the same dialect writes it back).
    Warn,
}

/// How a dialect words its unsupported policy: its code, what it calls a block, and the
/// help texts of a refusal and of a block kept as written.
pub(crate) struct UnsupportedWording {
    pub code: Code,
    /// Appended to the last reported word when more were left out: `on this line`.
    pub more: &'static str,
    /// `in a block`, `on a line`, `in a group`.
    pub in_one: &'static str,
    /// `blocks`, `lines`, `groups`.
    pub many: &'static str,
    /// How to split off a word that changes followed state.
    pub own_block: &'static str,
    /// The help of a refusal (`--unsupported error`).
    pub refuse_help: &'static str,
    /// The help of a block kept as written (`--unsupported warn`).
    pub keep_help: &'static str,
}

/// A comment as every reader keeps it: control characters as blanks, trimmed; an empty
/// comment is none.
pub(crate) fn comment_text(raw: &str) -> Option<String> {
    Some(one_line(raw)).filter(|t| !t.is_empty())
}

/// A comment's text on one line: control characters (a stray CR, a tab) become spaces.
pub(crate) fn one_line(text: &str) -> String {
    // Most comments are printable ASCII: nothing to replace, one allocation (collecting the
    // characters grew the string two or three times a comment).
    if text.bytes().all(|b| (0x20..0x7f).contains(&b)) {
        return text.trim().to_string();
    }
    let line: String = text
        .chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect();
    // Readers trim comments: so do the writers, so that an output reads back as it is.
    line.trim().to_string()
}

/// A block's words by letter, in the order written: a block holds a handful, so a list
/// beats a hash map (which took a tenth of a reader's time hashing), and a list held in place
/// for up to eight beats one allocated for every block. A mask of the letters held answers
/// most questions (is there an I?) without looking at the list.
#[derive(Clone, Debug)]
pub(crate) struct Letters<W> {
    list: smallvec::SmallVec<[(char, W); 8]>,
    /// Bit `c - 'A'` for each letter `A`–`Z` held; bit 31 for any other character.
    present: u32,
}

impl<W> Default for Letters<W> {
    fn default() -> Self {
        Letters {
            list: smallvec::SmallVec::new(),
            present: 0,
        }
    }
}

/// A letter's bit in a mask of the letters a block holds ([`Letters`], FANUC's words):
/// `A`–`Z` one each, any other character bit 31.
pub(crate) fn letter_bit(letter: char) -> u32 {
    if letter.is_ascii_uppercase() {
        1 << (letter as u32 - 'A' as u32)
    } else {
        1 << 31
    }
}

impl<W: Copy> Letters<W> {
    pub fn get(&self, letter: &char) -> Option<&W> {
        if self.present & letter_bit(*letter) == 0 {
            return None;
        }
        self.list.iter().find(|(l, _)| l == letter).map(|(_, w)| w)
    }

    pub fn contains_key(&self, letter: &char) -> bool {
        self.get(letter).is_some()
    }

    /// Sets the word of `letter`; the word it had before.
    pub fn insert(&mut self, letter: char, word: W) -> Option<W> {
        if self.present & letter_bit(letter) != 0
            && let Some((_, w)) = self.list.iter_mut().find(|(l, _)| *l == letter)
        {
            return Some(std::mem::replace(w, word));
        }
        self.present |= letter_bit(letter);
        self.list.push((letter, word));
        None
    }

    pub fn remove(&mut self, letter: &char) -> Option<W> {
        let at = self.list.iter().position(|(l, _)| l == letter)?;
        let (_, word) = self.list.remove(at);
        self.present = self.list.iter().fold(0, |m, (l, _)| m | letter_bit(*l));
        Some(word)
    }

    pub fn iter(&self) -> impl Iterator<Item = (&char, &W)> {
        self.list.iter().map(|(l, w)| (l, w))
    }
}

/// Where a pest parse of `line` failed, as a byte offset: at the letter when pest stopped
/// after an address letter that has no number (shared by every dialect's syntax layer).
pub(crate) fn pest_error_offset<R: pest::RuleType>(line: &str, e: &pest::error::Error<R>) -> usize {
    let offset = match e.location {
        pest::error::InputLocation::Pos(p) => p,
        pest::error::InputLocation::Span((s, _)) => s,
    };
    let offset = offset.min(line.len());
    if line[..offset]
        .chars()
        .next_back()
        .is_some_and(|c| c.is_ascii_alphabetic())
    {
        offset - 1
    } else {
        offset
    }
}

/// Where a streaming read hands the items of the lines it is done with, in order
/// ([`crate::dialect::Dialect::stream`]).
pub trait ItemSink {
    fn item(&mut self, item: Item);
    /// The read so far, said before each line's items are handed on (a sink that writes
    /// may need the program's number or name before the first item, and may stop at the
    /// first error).
    fn so_far(&mut self, _read: SoFar<'_>) {}
}

/// What a read has found so far ([`ItemSink::so_far`]).
#[derive(Clone, Copy, Debug)]
pub struct SoFar<'a> {
    /// The program's number (FANUC's `O0100`) and name, when read.
    pub number: Option<u32>,
    pub name: Option<&'a str>,
    /// Whether any diagnostic so far is an error.
    pub errors: bool,
}

/// What a read keeps: the program, only its diagnostics, or nothing, handing each line's
/// items on.
pub enum Keep<'s> {
    Program,
    /// A conversion's read-back of its output needs only the diagnostics: the reader lets go
    /// of each line's items once the line is read ([`Items::line_read`]).
    Diagnostics,
    /// As [`Keep::Diagnostics`], each item handed to the sink as it is let go of: the items
    /// and diagnostics are those of [`Keep::Program`], without the program in memory.
    Stream(&'s mut dyn ItemSink),
}

impl<'s> Keep<'s> {
    /// The same, for as long as a reader that lives shorter than the sink.
    pub fn shorten<'t>(self) -> Keep<'t>
    where
        's: 't,
    {
        match self {
            Keep::Program => Keep::Program,
            Keep::Diagnostics => Keep::Diagnostics,
            Keep::Stream(sink) => Keep::Stream(sink),
        }
    }
}

/// The items a reader has made. Front ends use them as a vector indexed from 0 (`len()`
/// before a line, then `items[first..]`); under [`Keep::Diagnostics`] and [`Keep::Stream`]
/// the items of the lines read are let go of and only counted, so that no front end may look
/// back past the line it is reading, except at an item it holds on to
/// ([`Items::line_read_keeping`]).
pub(crate) struct Items<'s> {
    held: Vec<Item>,
    dropped: usize,
    keep: Keep<'s>,
}

impl Items<'_> {
    pub fn len(&self) -> usize {
        self.dropped + self.held.len()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    pub fn last_mut(&mut self) -> Option<&mut Item> {
        self.held.last_mut()
    }

    /// The items from index `first` on.
    pub fn get(&self, first: std::ops::RangeFrom<usize>) -> Option<&[Item]> {
        self.held.get(self.held_index(first.start)..)
    }

    /// Item `i`, while it is held (`None` once its line was let go of).
    pub fn held_mut(&mut self, i: usize) -> Option<&mut Item> {
        let at = i.checked_sub(self.dropped)?;
        self.held.get_mut(at)
    }

    /// Takes the items from index `first` on out of the program.
    pub fn split_off(&mut self, first: usize) -> Vec<Item> {
        let at = self.held_index(first).min(self.held.len());
        self.held.split_off(at)
    }

    /// Where item `i` stands in `held`.
    fn held_index(&self, i: usize) -> usize {
        debug_assert!(i >= self.dropped, "an item of a line already let go of");
        i.saturating_sub(self.dropped)
    }

    /// [`Items::line_read`], holding on to item `kept` and those after it (a cycle whose
    /// moves are filled in when its contour has been read).
    pub fn line_read_keeping(&mut self, kept: Option<usize>) {
        let n = kept.map_or(self.held.len(), |k| {
            k.saturating_sub(self.dropped).min(self.held.len())
        });
        self.let_go(n);
    }

    /// Says the read so far to a sink ([`ItemSink::so_far`]).
    fn so_far(&mut self, read: SoFar<'_>) {
        if let Keep::Stream(sink) = &mut self.keep {
            sink.so_far(read);
        }
    }

    /// Lets go of the first `n` items held.
    fn let_go(&mut self, n: usize) {
        match &mut self.keep {
            Keep::Program => return,
            Keep::Diagnostics => {
                self.held.drain(..n);
            }
            Keep::Stream(sink) => {
                for item in self.held.drain(..n) {
                    sink.item(item);
                }
            }
        }
        self.dropped += n;
    }

    /// The items still held when the read ends: the program's, or (streaming) none, each
    /// handed on.
    fn finish(mut self) -> Vec<Item> {
        self.let_go(self.held.len());
        self.held
    }
}

impl std::ops::Index<std::ops::RangeFrom<usize>> for Items<'_> {
    type Output = [Item];

    fn index(&self, range: std::ops::RangeFrom<usize>) -> &[Item] {
        self.get(range).unwrap_or(&[])
    }
}

#[cfg(test)]
impl std::ops::Index<usize> for Items<'_> {
    type Output = Item;

    fn index(&self, i: usize) -> &Item {
        &self[i..][0]
    }
}

impl std::ops::IndexMut<std::ops::RangeFrom<usize>> for Items<'_> {
    fn index_mut(&mut self, range: std::ops::RangeFrom<usize>) -> &mut [Item] {
        let start = self.held_index(range.start);
        self.held.get_mut(start..).unwrap_or(&mut [])
    }
}

/// The diagnostics a reader has made. Front ends use them as a vector indexed from 0 (`len()`
/// before a line, then `diags[mark..]`), as [`Items`]; once a line is read
/// ([`Reader::line_read`]) its diagnostics are settled: listed, or past
/// [`crate::diag::LISTED_PER_MESSAGE`] of one message and [`crate::diag::LISTED_PER_CODE`] of
/// one code, counted ([`crate::diag::Fold`]), so that a program that repeats one problem on a
/// million lines (a 20 MB program read with the wrong `--from`) holds a few hundred, not a
/// million. No front end may look at a settled one by its index.
#[derive(Default)]
pub(crate) struct Diags {
    /// Settled and listed.
    listed: Vec<Diagnostic>,
    /// How many were settled (listed or counted).
    settled: usize,
    /// Whether a settled one was an error.
    settled_error: bool,
    fold: crate::diag::Fold,
    /// Not settled yet: the line's.
    held: Vec<Diagnostic>,
}

impl Diags {
    pub fn push(&mut self, d: Diagnostic) {
        self.held.push(d);
    }

    pub fn len(&self) -> usize {
        self.settled + self.held.len()
    }

    /// Whether any so far is an error.
    pub fn has_errors(&self) -> bool {
        self.settled_error || self.held.iter().any(Diagnostic::is_error)
    }

    /// Those from index `first` on (only those not settled).
    pub fn get(&self, first: std::ops::RangeFrom<usize>) -> Option<&[Diagnostic]> {
        self.held.get(self.held_index(first.start)..)
    }

    /// Takes those from index `first` on out.
    pub fn split_off(&mut self, first: usize) -> Vec<Diagnostic> {
        let at = self.held_index(first).min(self.held.len());
        self.held.split_off(at)
    }

    /// Takes those from index `first` on out, in order.
    pub fn drain(&mut self, first: std::ops::RangeFrom<usize>) -> std::vec::Drain<'_, Diagnostic> {
        let at = self.held_index(first.start).min(self.held.len());
        self.held.drain(at..)
    }

    /// Every one listed so far, in order (not those counted).
    #[cfg(test)]
    pub fn iter(&self) -> impl Iterator<Item = &Diagnostic> {
        self.listed.iter().chain(&self.held)
    }

    fn held_index(&self, i: usize) -> usize {
        debug_assert!(i >= self.settled, "a diagnostic of a line already settled");
        i.saturating_sub(self.settled)
    }

    /// The line is read: its diagnostics are listed or counted; `listed` sees each one
    /// listed.
    pub fn settle(&mut self, mut listed: impl FnMut(&Diagnostic)) {
        for d in self.held.drain(..) {
            self.settled += 1;
            self.settled_error |= d.is_error();
            if self.fold.admit(&d) {
                listed(&d);
                self.listed.push(d);
            }
        }
    }

    /// Every diagnostic: those listed, then for each code counted the last one, labelled
    /// with how many it stands for.
    fn finish(mut self) -> Vec<Diagnostic> {
        self.settle(|_| {});
        let mut all = self.listed;
        all.extend(self.fold.finish());
        all
    }
}

impl Extend<Diagnostic> for Diags {
    fn extend<T: IntoIterator<Item = Diagnostic>>(&mut self, iter: T) {
        self.held.extend(iter);
    }
}

impl std::ops::Index<std::ops::RangeFrom<usize>> for Diags {
    type Output = [Diagnostic];

    fn index(&self, range: std::ops::RangeFrom<usize>) -> &[Diagnostic] {
        self.get(range).unwrap_or(&[])
    }
}

impl std::ops::IndexMut<std::ops::RangeFrom<usize>> for Diags {
    fn index_mut(&mut self, range: std::ops::RangeFrom<usize>) -> &mut [Diagnostic] {
        let start = self.held_index(range.start).min(self.held.len());
        &mut self.held[start..]
    }
}

#[cfg(test)]
impl std::ops::Index<usize> for Diags {
    type Output = Diagnostic;

    fn index(&self, i: usize) -> &Diagnostic {
        &self[i..][0]
    }
}

/// The state every reader keeps: the source, the items and diagnostics so far, and the
/// tool's position as far as it is known.
pub(crate) struct Reader<'a> {
    pub src: &'a SourceFile,
    pub items: Items<'a>,
    pub diags: Diags,
    pub pos: Pos,
    dialect: DialectId,
    warned_after_end: bool,
    /// The program's number (FANUC's `O0100`), when the source gives one.
    pub number: Option<u32>,
    /// The program's name (SINUMERIK's `%_N_SHAFT_MPF`), when the source gives one.
    pub name: Option<String>,
    /// The units the program's length words were written in: `None` before any, then
    /// `Some(true)` for inches throughout, `Some(false)` for millimetres or both.
    units: Option<bool>,
}

impl<'a> Reader<'a> {
    pub fn new<'k: 'a>(src: &'a SourceFile, dialect: DialectId, keep: Keep<'k>) -> Self {
        Reader {
            src,
            items: Items {
                held: Vec::new(),
                dropped: 0,
                keep: keep.shorten(),
            },
            diags: Diags::default(),
            pos: Pos::UNKNOWN,
            dialect,
            warned_after_end: false,
            number: None,
            name: None,
            units: None,
        }
    }

    /// Notes that a length word was read in inches (`true`) or millimetres.
    pub fn saw_length(&mut self, inch: bool) {
        self.units = Some(self.units.map_or(inch, |was| was && inch));
    }

    /// The program read (without the items let go of under [`Keep::Diagnostics`]), and
    /// every diagnostic.
    pub fn finish(mut self) -> (Program, Vec<Diagnostic>) {
        self.say_so_far();
        (
            Program {
                items: self.items.finish(),
                dialect: self.dialect,
                library: Vec::new(),
                number: self.number,
                name: self.name,
                inch: self.units == Some(true),
            },
            self.diags.finish(),
        )
    }

    /// Says the read so far to a streaming read's sink.
    fn say_so_far(&mut self) {
        if matches!(self.items.keep, Keep::Stream(_)) {
            let read = SoFar {
                number: self.number,
                name: self.name.as_deref(),
                errors: self.diags.has_errors(),
            };
            self.items.so_far(read);
        }
    }

    /// A line is read, and nothing will look back at its items or diagnostics again: its
    /// items are let go of when the program is not kept, and its diagnostics settled.
    pub fn line_read(&mut self) {
        self.line_read_keeping(None);
    }

    /// [`Reader::line_read`], holding on to item `kept` and those after it
    /// ([`Items::line_read_keeping`]).
    pub fn line_read_keeping(&mut self, kept: Option<usize>) {
        self.say_so_far();
        self.items.line_read_keeping(kept);
        self.diags.settle(|_| {});
    }

    pub fn push(&mut self, kind: ItemKind, span: Span, number: Option<u32>) {
        self.items.held.push(Item {
            block_number: number,
            ..Item::new(kind, span)
        });
    }

    /// The span of `range` (bytes) of `line`.
    pub fn span(&self, line: Line<'_>, range: Range<usize>) -> Span {
        self.src.span_in_line(line, range)
    }

    /// An error at `span` with its help.
    pub fn error(
        &mut self,
        code: Code,
        span: Span,
        message: impl Into<String>,
        help: impl Into<String>,
    ) {
        self.diags
            .push(Diagnostic::new(code, message).at(self.src, span).help(help));
    }

    /// Whether an arc `name` (`G2`) from `start` to `end` ((X diameter, Z)) around `centre`
    /// ends on its circle (within 0.002 mm) with a radius; else the error `code` at `span`.
    #[allow(clippy::too_many_arguments)]
    pub fn arc_on_circle(
        &mut self,
        code: Code,
        span: Span,
        name: &str,
        start: (Length, Length),
        end: (Length, Length),
        centre: (Length, Length),
        help: &str,
    ) -> Option<()> {
        let (r1, r2) = crate::lower::arc::radii(start, end, centre);
        if r1 < 0.001 || r2 < 0.001 || (r1 - r2).abs() > 0.002 {
            self.error(
                code,
                span,
                format!(
                    "{name}'s end is not on its circle, or its radius is zero: {} mm at the start, {} mm at the end",
                    Length::from_mm_f64(r1).mm(),
                    Length::from_mm_f64(r2).mm()
                ),
                help,
            );
            return None;
        }
        Some(())
    }

    /// The centre of the arc of signed `radius` (negative beyond half a circle) from `start`
    /// to `end`; when the radius is too short for the chord, the error `code` at `span`, the
    /// radius word `text`'s.
    #[allow(clippy::too_many_arguments)]
    pub fn centre_of_radius(
        &mut self,
        code: Code,
        span: Span,
        text: &str,
        start: (Length, Length),
        end: (Length, Length),
        radius: Length,
        clockwise: bool,
    ) -> Option<Pos> {
        match crate::lower::arc::centre_from_radius(
            start,
            end,
            radius.to_mm_f64(),
            clockwise,
            0.001,
        ) {
            Ok(c) => Some(c),
            Err(chord) => {
                self.error(
                    code,
                    span,
                    format!(
                        "`{text}` is too small for the arc: its end is {chord:.4} mm from its start"
                    ),
                    "the radius must be at least half the distance from the start to the end",
                );
                None
            }
        }
    }

    /// A syntax error at the character that starts at byte `offset` of `line`.
    pub fn syntax_error(
        &mut self,
        code: Code,
        line: Line<'_>,
        offset: usize,
        message: impl Into<String>,
        help: impl Into<String>,
    ) {
        let span = self.src.char_span(line, offset);
        self.error(code, span, message, help);
    }

    /// Stamps the items read from one source block (those from `first` on): the block's
    /// number goes to its first item (to each of them when `every`), its comment to its
    /// first item that is not a comment. A block that made no item but has a comment
    /// becomes a comment item at `span`.
    pub fn stamp_block(
        &mut self,
        first: usize,
        number: Option<u32>,
        comment: Option<String>,
        span: Span,
        every: bool,
    ) {
        if first >= self.items.len() {
            if let Some(comment) = comment {
                self.push(ItemKind::Comment(comment), span, number);
            }
            return;
        }
        let items = &mut self.items[first..];
        if let Some(comment) = comment
            && !matches!(items[0].kind, ItemKind::Comment(_))
        {
            items[0].comment = Some(comment.into());
        }
        let stamped = if every { items.len() } else { 1 };
        for item in &mut items[..stamped] {
            item.block_number = number;
        }
    }

    /// Whether an item from `first` on ends the program.
    pub fn ends_program(&self, first: usize) -> bool {
        self.items.get(first..).is_some_and(|items| {
            items
                .iter()
                .any(|i| matches!(i.kind, ItemKind::ProgramEnd(_)))
        })
    }

    /// Reports the first block after the program's end (the others are not reported).
    pub fn after_end(&mut self, code: Code, span: Span, message: &str, help: &str) {
        if !std::mem::replace(&mut self.warned_after_end, true) {
            self.error(code, span, message, help);
        }
    }

    /// Reports the unsupported words `found` (span, message): at most [`WORD_REPORTS`],
    /// the last saying how many more there are. Errors, or warnings when `keep`.
    /// A block that may cut a thread (`thread`) is never kept, in any mode, and its help
    /// never suggests `--unsupported warn` (a thread is converted only when every word of its
    /// block is read). Returns whether the block was kept.
    pub fn unsupported(
        &mut self,
        wording: &UnsupportedWording,
        mut found: Vec<(Span, String)>,
        keep: bool,
        thread: bool,
    ) -> bool {
        let keep = keep && !thread;
        let more = found.len().saturating_sub(WORD_REPORTS);
        found.truncate(WORD_REPORTS);
        if more > 0
            && let Some((_, message)) = found.last_mut()
        {
            message.push_str(&format!(" (and {more} more {})", wording.more));
        }
        for (span, message) in found {
            let d = Diagnostic::new(wording.code, message).at(self.src, span);
            self.diags.push(if keep {
                d.help(wording.keep_help).as_warning()
            } else if thread {
                d.help(THREAD_HELP)
            } else {
                d.help(wording.refuse_help)
            });
        }
        keep
    }

    /// Refuses to keep a block opaque because its word `text` at `span` changes state the
    /// reader follows: the blocks after it would be read wrongly.
    pub fn state_in_opaque(&mut self, wording: &UnsupportedWording, span: Span, text: &str) {
        self.error(
            wording.code,
            span,
            format!(
                "`{text}` {} kept opaque: it changes state that the {} after it depend on, which ncthread would not follow",
                wording.in_one, wording.many
            ),
            format!(
                "{}, so that ncthread reads it and keeps only the unsupported words",
                wording.own_block
            ),
        );
    }

    /// Keeps a block as written (`--unsupported warn`): an opaque item in this dialect,
    /// after which the position is unknown.
    pub fn keep_opaque(
        &mut self,
        text: String,
        span: Span,
        number: Option<u32>,
        context: ModalContext,
    ) {
        let kind = ItemKind::Opaque {
            dialect: self.dialect,
            text,
            block: Some(context),
        };
        self.pos = kind.end_position(self.pos);
        self.push(kind, span, number);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_comment_on_one_line_is_its_characters_controls_as_blanks_trimmed() {
        let by_characters = |text: &str| -> String {
            let line: String = text
                .chars()
                .map(|c| if c.is_control() { ' ' } else { c })
                .collect();
            line.trim().to_string()
        };
        for text in [
            "",
            " ",
            "pass 1/5: depth 0.2",
            "  face  ",
            "a\tb",
            "\ttab first",
            "cr last\r",
            "del \u{7f} here",
            "\u{85}next line\u{85}",
            "\u{a0}no-break blank\u{a0}",
            "Ø33 závit",
            "\u{2003}em space",
            "~ tilde and } brace",
        ] {
            assert_eq!(one_line(text), by_characters(text), "{text:?}");
        }
    }

    #[test]
    fn letters_answer_as_a_list_does() {
        let mut l = Letters::default();
        assert_eq!(l.get(&'X'), None);
        assert_eq!(l.insert('X', 1), None);
        assert_eq!(l.insert('z', 2), None);
        assert_eq!(l.insert('#', 3), None);
        assert_eq!(l.insert('X', 4), Some(1));
        assert_eq!(
            (l.get(&'X'), l.get(&'z'), l.get(&'#'), l.get(&'Z')),
            (Some(&4), Some(&2), Some(&3), None)
        );
        assert_eq!(l.remove(&'z'), Some(2));
        assert_eq!((l.get(&'z'), l.get(&'#')), (None, Some(&3)));
        assert_eq!(l.remove(&'#'), Some(3));
        assert!(!l.contains_key(&'#') && l.contains_key(&'X'));
        for c in 'A'..='J' {
            l.insert(c, c as i32);
        }
        let order: String = l.iter().map(|(c, _)| *c).collect();
        assert_eq!(order, "XABCDEFGHIJ");
        assert_eq!(l.get(&'J'), Some(&('J' as i32)));
    }
    use crate::diag::Severity;

    const WORDING: UnsupportedWording = UnsupportedWording {
        code: crate::dialect::iso::codes::ISOR_UNSUPPORTED,
        more: "on this line",
        in_one: "on a line",
        many: "lines",
        own_block: "put this word on a line of its own",
        refuse_help: "refused",
        keep_help: "kept",
    };

    /// A line's diagnostics are settled once it is read: a mark taken in the line still
    /// indexes them, the repeats past the limits are counted in the last one, and an error
    /// settled is still known.
    #[test]
    fn a_readers_diagnostics_are_listed_or_counted_once_each_line_is_read() {
        let src = SourceFile::new("t", "Q7\n".repeat(30));
        let warning = |line: u32| {
            Diagnostic::new(WORDING.code, "`Q7`: not supported")
                .as_warning()
                .at(&src, src.line_span(src.line(line)))
        };
        let mut d = Diags::default();
        let mut marks = Vec::new();
        for line in 1..=25 {
            let mark = d.len();
            d.push(warning(line));
            assert_eq!(d[mark..].len(), 1);
            assert_eq!(d[mark].location.as_ref().map(|l| l.line), Some(line));
            marks.push(mark);
            d.settle(|_| {});
        }
        assert_eq!(
            marks,
            (0..25).collect::<Vec<_>>(),
            "indexed as if all were held"
        );
        assert!(!d.has_errors());
        let mark = d.len();
        d.push(Diagnostic::new(WORDING.code, "`Q8`: not supported"));
        d.push(warning(26));
        let taken = d.split_off(mark + 1);
        assert_eq!(taken.len(), 1);
        d.settle(|_| {});
        assert!(d.has_errors(), "an error settled is still known");
        let all = d.finish();
        // Ten warnings listed, the error, and the last warning counting the other 15.
        assert_eq!(all.len(), 12, "{all:#?}");
        assert_eq!(all.iter().map(Diagnostic::count).sum::<usize>(), 26);
        assert_eq!(all[11].more, 14);
        assert_eq!(all[11].location.as_ref().map(|l| l.line), Some(25));
    }

    #[test]
    fn a_code_one_edit_away_is_suggested() {
        let known = ["G0", "G1", "G33", "G33.1", "G76"];
        assert_eq!(did_you_mean("G32", &known), " (did you mean G33?)");
        assert_eq!(did_you_mean("G34", &known), " (did you mean G33?)");
        assert_eq!(did_you_mean("G133", &known), " (did you mean G33?)");
        assert_eq!(did_you_mean("G2", &known), " (did you mean G1?)");
        assert_eq!(did_you_mean("G92", &known), "");
        assert_eq!(did_you_mean("G33", &known), "");
    }

    #[test]
    fn unsupported_words_are_counted_past_the_limit_and_warn_only_when_kept() {
        let src = SourceFile::new("t", "A1 A2 A3 A4 A5 A6 A7\n");
        let found: Vec<(Span, String)> = (1..=7)
            .map(|i| (Span::default(), format!("`A{i}`")))
            .collect();
        let mut r = Reader::new(&src, crate::dialect::iso::ID, Keep::Program);
        r.unsupported(&WORDING, found.clone(), false, false);
        assert_eq!(r.diags.len(), WORD_REPORTS);
        assert_eq!(r.diags[4].message, "`A5` (and 2 more on this line)");
        assert!(r.diags.iter().all(|d| d.severity == Severity::Error));
        let mut r = Reader::new(&src, crate::dialect::iso::ID, Keep::Program);
        r.unsupported(&WORDING, found.clone(), true, false);
        assert!(r.diags.iter().all(|d| d.severity == Severity::Warning));
        // A thread block: refused under `keep` too, and no advice to keep it.
        let mut r = Reader::new(&src, crate::dialect::iso::ID, Keep::Program);
        assert!(!r.unsupported(&WORDING, found, true, true));
        assert!(r.diags.iter().all(|d| d.severity == Severity::Error));
        assert!(
            r.diags
                .iter()
                .all(|d| d.help.as_deref() == Some(THREAD_HELP))
        );
    }

    #[test]
    fn a_block_stamps_its_number_and_comment_on_its_items() {
        let src = SourceFile::new("t", "N10 M5 (stop)\n");
        let mut r = Reader::new(&src, crate::dialect::iso::ID, Keep::Program);
        r.stamp_block(0, Some(5), Some("alone".into()), Span::default(), false);
        assert_eq!(r.items[0].kind, ItemKind::Comment("alone".into()));
        assert_eq!(r.items[0].block_number, Some(5));
        r.push(ItemKind::SpindleStop, Span::default(), None);
        r.push(ItemKind::SpindleStop, Span::default(), None);
        r.stamp_block(1, Some(10), Some("stop".into()), Span::default(), false);
        assert_eq!(r.items[1].comment.as_deref(), Some("stop"));
        assert_eq!(
            (r.items[1].block_number, r.items[2].block_number),
            (Some(10), None)
        );
        r.stamp_block(1, Some(20), None, Span::default(), true);
        assert_eq!(
            (r.items[1].block_number, r.items[2].block_number),
            (Some(20), Some(20))
        );
        assert_eq!(r.items.len(), 3);
    }

    #[test]
    fn only_the_first_block_after_the_end_is_reported() {
        let src = SourceFile::new("t", "M30\nX1\nX2\n");
        let mut r = Reader::new(&src, crate::dialect::iso::ID, Keep::Program);
        r.push(
            ItemKind::ProgramEnd(crate::ir::EndCode::M30),
            Span::default(),
            None,
        );
        assert!(r.ends_program(0) && !r.ends_program(1));
        r.after_end(
            crate::dialect::iso::codes::ISOR_AFTER_END,
            Span::default(),
            "after",
            "help",
        );
        r.after_end(
            crate::dialect::iso::codes::ISOR_AFTER_END,
            Span::default(),
            "after",
            "help",
        );
        assert_eq!(r.diags.len(), 1);
    }
}

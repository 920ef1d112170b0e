//! Source text, lines and spans.

use std::ops::Range;
use std::sync::atomic::AtomicU64;
use std::sync::atomic::Ordering::Relaxed;

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
    pub text: Text,
    /// Made when the text is given, or (a text still being written, [`Following`]) once
    /// its end is known, when first asked for.
    line_starts: std::sync::OnceLock<LineStarts>,
}

/// A program's text: in memory, or (a conversion's output, written to a temporary file as it
/// was made) mapped from its file, so that a text many times the memory a conversion may take
/// is read without being held (issue 34). It reads as a `str` either way. A mapped text lets
/// go of the pages it has been read past ([`Text::read_to`]): they stay in the file, and a
/// look back reads them again.
pub struct Text(Repr);

enum Repr {
    Owned(String),
    #[cfg(unix)]
    Mapped(Mapped),
    /// A writer's output read as it is written ([`Following`]).
    #[cfg(unix)]
    Growing(Growing),
}

#[cfg(unix)]
struct Mapped {
    map: memmap2::Mmap,
    /// The file mapped, whole ([`Text::file`]).
    file: std::fs::File,
    /// The pages before this offset have been let go of (a multiple of [`RELEASE_ALIGN`]).
    released: std::sync::atomic::AtomicUsize,
}

/// A writer's output that a reader reads as it is written (issue 34: a conversion's
/// read-back beside its writer). The writer publishes whole lines as they reach its
/// temporary file ([`Follow`]); the reader's text ([`Following::text`]) holds what has been
/// published, and its [`SourceFile`] hands its lines as they come and waits for the end only
/// where it needs the whole text (the line count, a line by number).
#[cfg(unix)]
pub fn follow() -> (Follow, Following) {
    let shared = std::sync::Arc::new(Shared {
        state: std::sync::Mutex::new(Published::default()),
        changed: std::sync::Condvar::new(),
        cancelled: std::sync::atomic::AtomicBool::new(false),
    });
    (Follow(shared.clone()), Following(shared))
}

#[cfg(unix)]
struct Shared {
    state: std::sync::Mutex<Published>,
    changed: std::sync::Condvar,
    /// The reading is not wanted any more ([`Following::cancel`]): looked at line by line,
    /// also once the whole text is published.
    cancelled: std::sync::atomic::AtomicBool,
}

#[cfg(unix)]
#[derive(Default)]
struct Published {
    /// The writer's temporary file, once it has one.
    file: Option<std::fs::File>,
    /// How many of its bytes are written (whole lines, but at the end).
    len: usize,
    /// The writer has written its last line.
    done: bool,
    /// The text will not be finished (the writer was let go of, or failed), or its reading
    /// is not wanted any more.
    abandoned: bool,
}

#[cfg(unix)]
impl Shared {
    fn change(&self, f: impl FnOnce(&mut Published)) {
        if let Ok(mut state) = self.state.lock() {
            f(&mut state);
        }
        self.changed.notify_all();
    }
}

/// The writer's end of a [`follow`]: dropped before [`Follow::finish`], the text is abandoned.
#[cfg(unix)]
pub struct Follow(std::sync::Arc<Shared>);

#[cfg(unix)]
impl std::fmt::Debug for Follow {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Follow")
    }
}

#[cfg(unix)]
impl Follow {
    /// The first `len` bytes of `file` are written: whole lines, the last one included.
    pub(crate) fn publish(&self, file: &std::fs::File, len: u64) {
        let len = usize::try_from(len).unwrap_or(usize::MAX);
        self.0.change(|state| {
            // The reader's own handle on the file, at the first spill.
            if state.file.is_none() {
                match file.try_clone() {
                    Ok(copy) => state.file = Some(copy),
                    Err(_) => {
                        state.abandoned = true;
                        return;
                    }
                }
            }
            state.len = len;
        });
    }

    /// Every line is published.
    pub(crate) fn finish(self) {
        self.0.change(|state| state.done = true);
    }
}

#[cfg(unix)]
impl Drop for Follow {
    fn drop(&mut self) {
        self.0.change(|state| {
            if !state.done {
                state.abandoned = true;
            }
        });
    }
}

/// The reader's end of a [`follow`].
#[cfg(unix)]
pub struct Following(std::sync::Arc<Shared>);

/// How much of the address space a followed text reserves (64 GiB; a quarter of it on a
/// 32-bit system): a longer output is read after its writer, as any other.
#[cfg(unix)]
const FOLLOW_RESERVE: usize = if usize::BITS >= 64 {
    (1u64 << 36) as usize
} else {
    usize::MAX / 4
};

#[cfg(unix)]
impl Following {
    /// Says that the text is not wanted any more: its reading ends at the next line.
    pub fn cancel(&self) {
        self.0.cancelled.store(true, Relaxed);
        self.0.change(|state| state.abandoned = true);
    }

    /// A handle that can [`Following::cancel`] from elsewhere.
    pub fn canceller(&self) -> Following {
        Following(self.0.clone())
    }

    /// The text, once the writer has a file; `None` when it ends without one (a short
    /// output, held in memory) or is abandoned first, or the file cannot be mapped.
    pub fn text(self) -> Option<Text> {
        let file = {
            let guard = self.0.state.lock().ok()?;
            let state = self
                .0
                .changed
                .wait_while(guard, |s| s.file.is_none() && !s.done && !s.abandoned)
                .ok()?;
            if state.abandoned {
                return None;
            }
            state.file.as_ref()?.try_clone().ok()?
        };
        // SAFETY: the file is the writer's unnamed temporary file, to which it only appends
        // (past the published length); only the published bytes are ever read, and the map
        // is read-only. The map may reach past the file's end: those pages are never touched.
        let map = unsafe {
            memmap2::MmapOptions::new()
                .len(FOLLOW_RESERVE)
                .map(&file)
                .ok()?
        };
        Some(Text(Repr::Growing(Growing {
            map,
            shared: self.0,
            seen: std::sync::atomic::AtomicUsize::new(0),
            ended: std::sync::atomic::AtomicBool::new(false),
            complete: std::sync::atomic::AtomicBool::new(false),
            released: std::sync::atomic::AtomicUsize::new(0),
        })))
    }
}

/// A [`Following`] text: what of the map has been published and checked to be UTF-8.
#[cfg(unix)]
struct Growing {
    map: memmap2::Mmap,
    shared: std::sync::Arc<Shared>,
    /// The bytes published, checked and readable.
    seen: std::sync::atomic::AtomicUsize,
    /// Nothing more will come: the writer finished, or the text was abandoned.
    ended: std::sync::atomic::AtomicBool,
    /// The writer finished and every byte it wrote is seen.
    complete: std::sync::atomic::AtomicBool,
    released: std::sync::atomic::AtomicUsize,
}

#[cfg(unix)]
impl Growing {
    /// The map's bytes `from..to` (published: within the file). Not through the map's whole
    /// slice, which reaches past the file's end.
    fn bytes(&self, from: usize, to: usize) -> &[u8] {
        let to = to.min(self.map.len());
        let from = from.min(to);
        // SAFETY: `from..to` is within the map, and (published) within the file, whose
        // bytes there are written and no longer change.
        unsafe { std::slice::from_raw_parts(self.map.as_ptr().add(from), to - from) }
    }

    /// The bytes seen.
    fn seen_bytes(&self) -> &[u8] {
        self.bytes(0, self.seen.load(Relaxed))
    }

    /// Whether the reading was cancelled.
    fn cancelled(&self) -> bool {
        self.shared.cancelled.load(Relaxed)
    }

    /// Waits for more of the text: whether some came (false once nothing more will).
    fn more(&self) -> bool {
        if self.ended.load(Relaxed) {
            return false;
        }
        let seen = self.seen.load(Relaxed);
        let Ok(guard) = self.shared.state.lock() else {
            self.ended.store(true, Relaxed);
            return false;
        };
        let Ok(state) = self
            .shared
            .changed
            .wait_while(guard, |s| s.len <= seen && !s.done && !s.abandoned)
        else {
            self.ended.store(true, Relaxed);
            return false;
        };
        let (len, done, abandoned) = (state.len, state.done, state.abandoned);
        drop(state);
        if abandoned || len > self.map.len() {
            self.ended.store(true, Relaxed);
            return false;
        }
        // Checked a stretch at a time: a reader far behind its writer does not touch the
        // pages ahead of it (which it would hold until it passes them).
        let mut checked = seen;
        if len > seen {
            let to = len.min(seen.saturating_add(READ_LAG));
            checked = match std::str::from_utf8(self.bytes(seen, to)) {
                Ok(_) => to,
                // A character cut by the stretch's end: checked from its start with the next.
                Err(e) if e.error_len().is_none() && to < len && e.valid_up_to() > 0 => {
                    seen + e.valid_up_to()
                }
                Err(_) => {
                    self.ended.store(true, Relaxed);
                    return false;
                }
            };
            self.seen.fetch_max(checked, Relaxed);
        }
        if done && checked >= len {
            self.ended.store(true, Relaxed);
            self.complete.store(true, Relaxed);
        }
        checked > seen
    }
}

/// How far behind the furthest point read a mapped text keeps its pages, and how far that
/// point moves before more are let go of.
#[cfg(unix)]
const READ_LAG: usize = 1 << 20;
/// What a page boundary is a multiple of on every system (4 KiB, 16 KiB and 64 KiB pages).
#[cfg(unix)]
const RELEASE_ALIGN: usize = 1 << 16;

impl Text {
    /// The text of a file, mapped: an error when it cannot be mapped or is not UTF-8. The
    /// file must be one no one else writes (a conversion's own temporary file, which has no
    /// name): it is taken, so that the caller cannot write it while it is mapped.
    #[cfg(unix)]
    pub(crate) fn mapped(file: std::fs::File) -> std::io::Result<Text> {
        if file.metadata()?.len() == 0 {
            return Ok(Text(Repr::Owned(String::new())));
        }
        // SAFETY: the file is an unnamed temporary file taken from its caller, which
        // nothing writes while it is mapped (the map is read-only; the file is let go of).
        let map = unsafe { memmap2::Mmap::map(&file)? };
        let text = Text(Repr::Mapped(Mapped {
            map,
            file,
            released: std::sync::atomic::AtomicUsize::new(0),
        }));
        // Checked a stretch at a time, each let go of once checked.
        let bytes = text.bytes_of();
        let mut at = 0;
        while at < bytes.len() {
            let end = (at + READ_LAG).min(bytes.len());
            match std::str::from_utf8(&bytes[at..end]) {
                Ok(_) => at = end,
                // A character cut by the stretch's end: checked from its start with the next.
                Err(e) if e.error_len().is_none() && end < bytes.len() && e.valid_up_to() > 0 => {
                    at += e.valid_up_to()
                }
                Err(e) => return Err(invalid(e)),
            }
            text.read_to(at);
        }
        text.release(0);
        Ok(text)
    }

    #[cfg(unix)]
    fn bytes_of(&self) -> &[u8] {
        match &self.0 {
            Repr::Owned(s) => s.as_bytes(),
            Repr::Mapped(m) => &m.map,
            Repr::Growing(g) => g.seen_bytes(),
        }
    }

    /// A mapped text's map, how much of it is the text (for a growing one, what is seen),
    /// and where its pages are let go of.
    #[cfg(unix)]
    fn pages(&self) -> Option<(&memmap2::Mmap, usize, &std::sync::atomic::AtomicUsize)> {
        match &self.0 {
            Repr::Owned(_) => None,
            Repr::Mapped(m) => Some((&m.map, m.map.len(), &m.released)),
            Repr::Growing(g) => Some((&g.map, g.seen.load(Relaxed), &g.released)),
        }
    }

    /// A text still being written ([`follow`]): waits for more of it; whether some came
    /// (false once nothing more will, and for any other text).
    pub fn grow(&self) -> bool {
        #[cfg(unix)]
        if let Repr::Growing(g) = &self.0 {
            return g.more();
        }
        false
    }

    /// A text still being written whose reading was cancelled ([`Following::cancel`]).
    fn cancelled(&self) -> bool {
        #[cfg(unix)]
        if let Repr::Growing(g) = &self.0 {
            return g.cancelled();
        }
        false
    }

    /// Waits until nothing more of the text will come ([`Text::grow`]).
    fn wait_end(&self) {
        while self.grow() {}
    }

    /// The file a mapped text is read from, when the text is every byte of it (a
    /// conversion's own unnamed temporary file, for [`crate::files::link_into_place`]): a
    /// second handle to it, which never leaves the library (a write through it would change
    /// the `str` the map is read as). `None` for a text in memory, or one not wholly written.
    #[cfg(unix)]
    pub(crate) fn file(&self) -> Option<std::fs::File> {
        let file = match &self.0 {
            Repr::Owned(_) => return None,
            Repr::Mapped(m) => m.file.try_clone().ok()?,
            Repr::Growing(g) => {
                if !self.is_complete() {
                    return None;
                }
                let state = g.shared.state.lock().ok()?;
                state.file.as_ref()?.try_clone().ok()?
            }
        };
        let whole = file.metadata().is_ok_and(|m| m.len() == self.len() as u64);
        whole.then_some(file)
    }

    /// Whether the text is whole: true but for a text still being written whose writer has
    /// not finished (or which was abandoned before its end).
    pub fn is_complete(&self) -> bool {
        #[cfg(unix)]
        if let Repr::Growing(g) = &self.0 {
            return g.complete.load(Relaxed) && !g.cancelled();
        }
        true
    }

    /// Says that the text has been read to `offset` and will be read on from there: a
    /// mapped text lets go of the pages more than [`READ_LAG`] behind it (a look back reads
    /// them from the file again). Does nothing to a text in memory.
    #[inline]
    pub fn read_to(&self, offset: usize) {
        #[cfg(unix)]
        if let Some((_, _, released_at)) = self.pages() {
            let released = released_at.load(Relaxed);
            if offset >= released + 2 * READ_LAG {
                self.release(offset - READ_LAG);
            } else if offset < released {
                // Read again from further back (a loop's body, a second pass): the pages
                // from there on are let go of as the reading passes them again.
                released_at.store(offset / RELEASE_ALIGN * RELEASE_ALIGN, Relaxed);
            }
        }
        #[cfg(not(unix))]
        let _ = offset;
    }

    /// Lets go of the pages before `offset`, or (0) of every page, to be read from the
    /// start again.
    fn release(&self, offset: usize) {
        #[cfg(unix)]
        if let Some((map, len, released)) = self.pages() {
            let (from, to) = if offset == 0 {
                (0, len)
            } else {
                let to = offset.min(len) / RELEASE_ALIGN * RELEASE_ALIGN;
                (released.load(Relaxed), to)
            };
            if to > from {
                // SAFETY: the map is read-only and its file unchanged where it was read (a
                // growing text's file is only appended to), so that a page let go of reads
                // the same bytes when it is read again: nothing that points into it sees a
                // change.
                let _ = unsafe {
                    map.unchecked_advise_range(memmap2::UncheckedAdvice::DontNeed, from, to - from)
                };
            }
            released.store(if offset == 0 { 0 } else { to.max(from) }, Relaxed);
        }
        #[cfg(not(unix))]
        let _ = offset;
    }

    /// The text in memory (a mapped text is read whole).
    pub fn into_string(self) -> String {
        match self.0 {
            Repr::Owned(s) => s,
            #[cfg(unix)]
            Repr::Mapped(_) | Repr::Growing(_) => self.to_string(),
        }
    }

    /// Whether the text is mapped from a file rather than held in memory.
    pub fn is_mapped(&self) -> bool {
        !matches!(self.0, Repr::Owned(_))
    }

    /// The text as stretches of whole lines of about `size` bytes (the last may end without
    /// a line end), each said to be read ([`Text::read_to`]) once the next is asked for:
    /// what writes a mapped text out a stretch at a time.
    pub fn stretches(&self, size: usize) -> impl Iterator<Item = &str> {
        let text: &str = self;
        let mut at = 0;
        std::iter::from_fn(move || {
            if at >= text.len() {
                return None;
            }
            self.read_to(at);
            let rest = &text[at..];
            let cut = if rest.len() <= size {
                rest.len()
            } else {
                memchr::memchr(b'\n', &rest.as_bytes()[size..]).map_or(rest.len(), |e| size + e + 1)
            };
            at += cut;
            Some(&rest[..cut])
        })
    }
}

#[cfg(unix)]
fn invalid(e: std::str::Utf8Error) -> std::io::Error {
    std::io::Error::new(std::io::ErrorKind::InvalidData, e)
}

impl std::ops::Deref for Text {
    type Target = str;

    fn deref(&self) -> &str {
        match &self.0 {
            Repr::Owned(s) => s,
            // SAFETY: checked to be UTF-8 when mapped, and the file is not changed.
            #[cfg(unix)]
            Repr::Mapped(m) => unsafe { std::str::from_utf8_unchecked(&m.map) },
            // SAFETY: what is seen was checked to be UTF-8 after it was published (to a
            // character's end: a stretch that cuts one stops before it), and the file is only
            // appended to past it.
            #[cfg(unix)]
            Repr::Growing(g) => unsafe { std::str::from_utf8_unchecked(g.seen_bytes()) },
        }
    }
}

impl serde::Serialize for Text {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(self)
    }
}

impl AsRef<str> for Text {
    fn as_ref(&self) -> &str {
        self
    }
}

impl From<String> for Text {
    fn from(s: String) -> Text {
        Text(Repr::Owned(s))
    }
}

impl From<Text> for String {
    fn from(text: Text) -> String {
        text.into_string()
    }
}

impl From<&str> for Text {
    fn from(s: &str) -> Text {
        Text(Repr::Owned(s.to_string()))
    }
}

impl Clone for Text {
    /// A copy in memory.
    fn clone(&self) -> Text {
        Text(Repr::Owned(self.to_string()))
    }
}

impl std::fmt::Debug for Text {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        std::fmt::Debug::fmt(&**self, f)
    }
}

impl std::fmt::Display for Text {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self)
    }
}

impl PartialEq for Text {
    fn eq(&self, other: &Text) -> bool {
        **self == **other
    }
}

impl Eq for Text {}

impl PartialEq<str> for Text {
    fn eq(&self, other: &str) -> bool {
        &**self == other
    }
}

impl PartialEq<&str> for Text {
    fn eq(&self, other: &&str) -> bool {
        &**self == *other
    }
}

impl PartialEq<String> for Text {
    fn eq(&self, other: &String) -> bool {
        **self == **other
    }
}

/// The numbers of the line indexes made (0: none).
static NEXT_ID: AtomicU64 = AtomicU64::new(1);

thread_local! {
    /// The last line a thread found: the index's number, the line (0-based), where it
    /// starts and where it ends with its line end (0: not found yet).
    static LAST: std::cell::Cell<(u64, usize, usize, usize)> =
        const { std::cell::Cell::new((0, 0, 0, 0)) };
}

/// How many lines one entry of a [`LineStarts`] stands for.
const STRIDE: usize = 16;

/// Where every [`STRIDE`]th line of a text starts (a line between is found from there: a
/// table of every line took 4 bytes a line, as much as a short line's text), in 32-bit
/// offsets for a text under 4 GiB, else full-width; and how many lines there are. The last
/// line asked for is remembered (by each thread, [`LAST`]), so that reading the lines in
/// order finds each from the one before.
#[derive(Clone, Debug)]
struct LineStarts {
    count: usize,
    every: Starts,
    /// This index's own number: the key of the last line found, which each thread keeps
    /// for itself ([`LAST`]: a conversion's reader and writer read one text at once).
    id: u64,
}

#[derive(Clone, Debug)]
enum Starts {
    Narrow(Vec<u32>),
    Wide(Vec<usize>),
}

impl LineStarts {
    /// The index of `text`, found a stretch at a time (a mapped text lets go of each once
    /// indexed).
    fn of(text: &Text) -> LineStarts {
        fn index<T>(text: &Text, wrap: impl Fn(usize) -> T) -> (usize, Vec<T>) {
            let bytes = text.as_bytes();
            let mut starts = Vec::new();
            // Line 0 starts at 0; line `count` at the byte after each line end but the last
            // byte's.
            let mut count = 0;
            let mut at = 0;
            loop {
                if count % STRIDE == 0 {
                    starts.push(wrap(at));
                }
                count += 1;
                let Some(end) = memchr::memchr(b'\n', &bytes[at..]) else {
                    break;
                };
                at += end + 1;
                if at == bytes.len() {
                    break;
                }
                text.read_to(at);
            }
            starts.shrink_to_fit();
            (count, starts)
        }
        let (count, every) = match u32::try_from(text.len()) {
            Ok(_) => {
                let (count, starts) = index(text, |i| i as u32);
                (count, Starts::Narrow(starts))
            }
            Err(_) => {
                let (count, starts) = index(text, |i| i);
                (count, Starts::Wide(starts))
            }
        };
        LineStarts {
            count,
            every,
            id: NEXT_ID.fetch_add(1, Relaxed),
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
        let (id, last, at, end) = LAST.with(std::cell::Cell::get);
        let found = id == self.id && end > 0;
        if found && last == i {
            return Some((at, end));
        }
        // From the line after the last one found (it starts where that one ends) when that
        // is before `i` in the same stretch, else from the entry before `i`.
        let (mut line, mut start) = if found && last < i && i - last <= i % STRIDE {
            (last + 1, end)
        } else {
            let k = i / STRIDE;
            (k * STRIDE, self.entry(k)?)
        };
        while line < i {
            start += memchr::memchr(b'\n', text.as_bytes().get(start..)?)? + 1;
            line += 1;
        }
        let end = start + line_end(text.get(start..)?);
        LAST.with(|last| last.set((self.id, i, start, end)));
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

/// The high bit of each zero byte of `x` (eight bytes at a time): none when it has none, and
/// the lowest set bit marks the first (a bit above a true one may be false, none below it).
pub(crate) fn zero_bytes(x: u64) -> u64 {
    x.wrapping_sub(0x0101_0101_0101_0101) & !x & 0x8080_8080_8080_8080
}

/// Where the first line of `text` ends, its line end included.
fn line_end(text: &str) -> usize {
    // Most program lines are short: a look at their first bytes, eight at a time, is quicker
    // than setting up a vector search.
    let bytes = text.as_bytes();
    let head = &bytes[..bytes.len().min(32)];
    let mut words = head.chunks_exact(8);
    for (i, chunk) in words.by_ref().enumerate() {
        let mut word = [0; 8];
        word.copy_from_slice(chunk);
        // A zero byte where the word has a line feed: the lowest flagged byte is the first
        // line feed (a flag above a true one may be false; none below it is).
        let found = zero_bytes(u64::from_le_bytes(word) ^ 0x0A0A_0A0A_0A0A_0A0A);
        if found != 0 {
            return i * 8 + (found.trailing_zeros() / 8) as usize + 1;
        }
    }
    let rest = words.remainder();
    let checked = head.len() - rest.len();
    if let Some(e) = rest.iter().position(|&b| b == b'\n') {
        return checked + e + 1;
    }
    memchr::memchr(b'\n', &bytes[head.len()..]).map_or(text.len(), |e| head.len() + e + 1)
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

/// Where a line stands in its text: enough to take it again without looking for it (a
/// reader that keeps what it read of a line, such as an НЦ-31 group's frames).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LinePlace {
    /// 1-based line number.
    pub number: u32,
    offset: usize,
    len: usize,
}

impl Line<'_> {
    /// Where the line stands ([`SourceFile::line_of`] takes it again).
    pub fn place(&self) -> LinePlace {
        LinePlace {
            number: self.number,
            offset: self.offset,
            len: self.text.len(),
        }
    }

    /// Whether the line holds only white space (`str::trim`'s), at the cost of a byte or two
    /// for a line that starts with a visible ASCII character.
    pub fn is_blank(&self) -> bool {
        match self
            .text
            .bytes()
            .find(|b| !matches!(b, b' ' | b'\t' | b'\r'))
        {
            None => true,
            Some(b) if b.is_ascii_graphic() => false,
            Some(_) => self.text.trim().is_empty(),
        }
    }
}

impl SourceFile {
    pub fn new(name: impl Into<String>, text: impl Into<String>) -> SourceFile {
        SourceFile::of_text(name, Text::from(text.into()))
    }

    /// The source of a text, in memory or mapped. Its lines are indexed only when one is
    /// asked for by number or their count is (a text still being written: once its end is
    /// known), a stretch at a time, each let go of once indexed (a mapped text); a reader that
    /// reads forward never waits for the index ([`SourceFile::lines`]).
    pub fn of_text(name: impl Into<String>, text: Text) -> SourceFile {
        SourceFile {
            name: name.into(),
            text,
            line_starts: std::sync::OnceLock::new(),
        }
    }

    /// The line index (of a text still being written: once its end is known).
    fn index(&self) -> &LineStarts {
        self.line_starts.get_or_init(|| {
            self.text.wait_end();
            LineStarts::of(&self.text)
        })
    }

    /// How many lines the text has.
    pub fn line_count(&self) -> usize {
        self.index().len()
    }

    /// Every line, LF or CRLF endings removed.
    pub fn lines(&self) -> impl Iterator<Item = Line<'_>> {
        let mut offset = 0;
        let mut number = 0u32;
        let mut count = self.line_starts.get().map(LineStarts::len);
        std::iter::from_fn(move || {
            let i = number as usize;
            // Where the line ends (its line end included), once a search has found it.
            let mut found = None;
            match count {
                Some(count) if i >= count => return None,
                Some(_) => {}
                // Not indexed (a text still being written, or not indexed yet): up to the
                // next line end, waiting for it; its last line (which may have none) once the
                // text has ended. Counted as
                // `LineStarts::of` counts: an empty text has one empty line, and a line end
                // at the very end starts none.
                None => loop {
                    if self.text.cancelled() {
                        return None;
                    }
                    let rest = &self.text[offset..];
                    let end = line_end(rest);
                    if rest.as_bytes().get(end.wrapping_sub(1)) == Some(&b'\n') {
                        found = Some(end);
                        break;
                    }
                    if !self.text.grow() {
                        if offset == self.text.len() && (offset > 0 || number > 0) {
                            return None;
                        }
                        count = Some(i + 1);
                        break;
                    }
                },
            }
            self.text.read_to(offset);
            let rest = &self.text[offset..];
            let end = found.unwrap_or_else(|| line_end(rest));
            number += 1;
            let line = line_at(number, offset, &rest[..end]);
            offset += end;
            Some(line)
        })
    }

    /// Line `number` (1-based). Out-of-range numbers give an empty line at the end.
    pub fn line(&self, number: u32) -> Line<'_> {
        let i = (number.max(1) - 1) as usize;
        let Some((start, end)) = self.index().get(&self.text, i) else {
            return Line {
                number,
                offset: self.text.len(),
                text: "",
            };
        };
        self.text.read_to(start);
        line_at(number, start, &self.text[start..end])
    }

    /// The line at `place` (of one of this file's lines): [`Self::line`] without a search.
    pub fn line_of(&self, place: LinePlace) -> Line<'_> {
        let text = self.text.get(place.offset..place.offset + place.len);
        let Some(text) = text else {
            return self.line(place.number);
        };
        self.text.read_to(place.offset);
        Line {
            number: place.number,
            offset: place.offset,
            text,
        }
    }

    /// The span of `range` (bytes within `line`'s text). A range that does not fall on
    /// character boundaries is widened to the characters it touches, and one that runs past
    /// the line is cut at its end.
    pub fn span_in_line(&self, line: Line<'_>, range: Range<usize>) -> Span {
        let text = line.text;
        let start = text.floor_char_boundary(range.start.min(text.len()));
        let end = text.ceil_char_boundary(range.end.clamp(start, text.len()));
        let before = &text[..start];
        let column = if before.is_ascii() {
            before.len()
        } else {
            before.chars().count()
        } as u32
            + 1;
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
        let index = self.index().up_to(&self.text, range.start).max(1);
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
    fn a_blank_line_is_one_trim_empties() {
        for text in [
            "",
            " ",
            "\t\r",
            "\u{0B}",
            "\u{0C} ",
            "\u{A0}",
            " \u{3000}",
            "N10",
            " X",
            " é",
            "\u{0B}X",
            "\u{A0}N1",
            "\u{1F}",
        ] {
            let line = Line {
                number: 1,
                offset: 0,
                text,
            };
            assert_eq!(line.is_blank(), text.trim().is_empty(), "{text:?}");
        }
    }

    /// The first line end at every byte of the eight-byte words and of the bytes after
    /// them (texts of 0 to 79 characters), among bytes one borrow or one bit away from a line
    /// feed before and after it (`\x0b`, a second `\n`, a character whose last byte is 0x8A).
    #[test]
    fn a_line_ends_at_its_first_line_feed() {
        for len in 0..80 {
            for at in 0..=len {
                for before in ["a", "\x0b", "\n", "\u{28a}", "\u{10a0a}"] {
                    for after in ["a", "\x0b", "\n", "\u{28a}"] {
                        // `len` characters, the line feed the character at `at` (none when
                        // `at` is `len`).
                        let mut text = before.repeat(at);
                        if at < len {
                            text.push('\n');
                            text.push_str(&after.repeat(len - at - 1));
                        }
                        let expected = text.find('\n').map_or(text.len(), |e| e + 1);
                        assert_eq!(line_end(&text), expected, "{text:?}");
                    }
                }
            }
        }
    }

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
            // Lines either side of the 32 bytes looked at before a vector search.
            &format!(
                "{}\n{}\n{}\r\nx",
                "a".repeat(31),
                "b".repeat(32),
                "c".repeat(100)
            ),
            &"d".repeat(33),
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
            // Read again once indexed: the lines counted by the index, the same.
            let lines: Vec<&str> = src.lines().map(|l| l.text).collect();
            assert_eq!(lines, naive, "{text:?} (indexed)");
            // Each line asked for alone, backwards, then forwards (from the remembered line),
            // then every third.
            let n = naive.len() as u32;
            for number in (1..=n).rev().chain(1..=n).chain((1..=n).step_by(3)) {
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
            let Starts::Narrow(v) = &src.index().every else {
                panic!("a short text has 32-bit line starts");
            };
            assert_eq!(v.len(), naive.len().div_ceil(STRIDE), "{text:?}");
            assert_eq!(v.capacity(), v.len(), "{text:?}");
        }
    }

    /// A text mapped from a file, read past its pages' release and back: what the same
    /// text in memory reads, line by line, spans included.
    #[cfg(unix)]
    #[test]
    fn a_mapped_text_reads_as_the_same_text_in_memory() {
        use std::io::Write as _;
        fn mapped(text: &str) -> std::io::Result<Text> {
            let mut file = tempfile::tempfile()?;
            file.write_all(text.as_bytes())?;
            Text::mapped(file)
        }
        // Over 2 × READ_LAG, so that pages are let go of, with a character cut by the first
        // stretch's end.
        let mut long = "N1 X1\r\n".repeat(READ_LAG / 7 - 1);
        long.push_str(&"é".repeat(8));
        long.push_str(&"\nN2 Z-1. (a comment)\n".repeat(READ_LAG / 10));
        for text in ["", "a", "a\nb\n", "é\r\n\nü", &long] {
            let src = SourceFile::of_text("m", mapped(text).expect("mapped"));
            let held = SourceFile::new("m", text);
            assert_eq!(src.text.is_mapped(), !text.is_empty());
            assert_eq!(&*src.text, text);
            assert_eq!(src.line_count(), held.line_count());
            let lines = |s: &SourceFile| -> Vec<(u32, usize, String)> {
                s.lines()
                    .map(|l| (l.number, l.offset, l.text.to_string()))
                    .collect()
            };
            assert_eq!(lines(&src), lines(&held));
            // Back to the start, then on: the lines as before.
            let n = held.line_count() as u32;
            for number in [n, 1, n / 2 + 1, n] {
                assert_eq!(src.line(number).text, held.line(number).text);
                assert_eq!(src.line(number).offset, held.line(number).offset);
            }
            let end = text.len();
            assert_eq!(src.span_of(end..end), held.span_of(end..end));
            assert_eq!(lines(&src), lines(&held), "read a second time");
            let stretches: String = src.text.stretches(100).collect();
            assert_eq!(stretches, text);
        }
        // Not UTF-8, even where a stretch ends: refused.
        let mut bad = "a".repeat(READ_LAG - 1).into_bytes();
        bad.extend_from_slice(&[0xC3, b'x']);
        assert!(mapped(std::str::from_utf8(&bad[..READ_LAG - 1]).unwrap()).is_ok());
        for bad in [bad.clone(), [&bad[..], &[0xC3]].concat()] {
            let mut file = tempfile::tempfile().expect("a temporary file");
            file.write_all(&bad).expect("written");
            assert!(Text::mapped(file).is_err());
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

    /// Writes `text` into a temporary file a piece of whole lines at a time from another
    /// thread, publishing each, and `finish`es (or, with `abandon`, lets go after its first
    /// half); the reader's source over the followed text.
    #[cfg(unix)]
    fn followed(text: &str, abandon: bool) -> SourceFile {
        use std::io::Write as _;
        let (follow, following) = follow();
        let owned = text.to_string();
        let writer = std::thread::spawn(move || {
            let mut file = tempfile::tempfile().unwrap();
            let pieces: Vec<&str> = owned.split_inclusive('\n').collect();
            let mut len = 0u64;
            for (i, piece) in pieces.chunks(3).enumerate() {
                if abandon && i * 6 >= pieces.len() {
                    return;
                }
                let piece = piece.concat();
                file.write_all(piece.as_bytes()).unwrap();
                len += piece.len() as u64;
                follow.publish(&file, len);
                std::thread::sleep(std::time::Duration::from_millis(1));
            }
            follow.publish(&file, len);
            follow.finish();
        });
        let src = SourceFile::of_text("followed", following.text().expect("a file"));
        let lines: Vec<(u32, usize, String)> = src
            .lines()
            .map(|l| (l.number, l.offset, l.text.to_string()))
            .collect();
        writer.join().unwrap();
        let whole = SourceFile::new("whole", src.text.to_string());
        let expected: Vec<(u32, usize, String)> = whole
            .lines()
            .map(|l| (l.number, l.offset, l.text.to_string()))
            .collect();
        assert_eq!(lines, expected, "{text:?}");
        src
    }

    /// A text read as it is written (a conversion's read-back beside its writer) has the
    /// lines, line count and lines by number of the whole text, its end counted alike.
    #[cfg(unix)]
    #[test]
    fn a_followed_text_reads_as_the_whole_text() {
        let long: String = (0..100).map(|i| format!("N{i} X{i} (ü)\r\n")).collect();
        for text in [
            "",
            "a",
            "a\n",
            "a\n\nb",
            "a\n\n",
            "\n",
            long.as_str(),
            &format!("{long}last"),
        ] {
            let src = followed(text, false);
            assert!(src.text.is_complete(), "{text:?}");
            assert_eq!(src.text, text);
            let whole = SourceFile::new("whole", text);
            assert_eq!(src.line_count(), whole.line_count(), "{text:?}");
            for n in 0..=whole.line_count() as u32 + 1 {
                let (a, b) = (src.line(n), whole.line(n));
                assert_eq!(
                    (a.number, a.offset, a.text),
                    (b.number, b.offset, b.text),
                    "{text:?} {n}"
                );
            }
        }
    }

    /// A writer that lets go before its end leaves an incomplete text, whose lines end where
    /// it stopped.
    #[cfg(unix)]
    #[test]
    fn an_abandoned_text_is_incomplete() {
        let long: String = (0..100).map(|i| format!("N{i} X{i}\n")).collect();
        let src = followed(&long, true);
        assert!(!src.text.is_complete());
        assert!(src.text.len() < long.len() && long.starts_with(&*src.text));
    }

    /// The czech reader over a followed text reports what it reports over the whole text,
    /// a line by number (for a diagnostic's source line) waiting for the end.
    #[cfg(unix)]
    #[test]
    fn a_reader_over_a_followed_text_reports_as_over_the_whole() {
        let mut text: String = (0..200)
            .map(|i| format!("N{} G00 X{}. Z2.\n", 10 + i * 10, 30 + i % 5))
            .collect();
        text.push_str("N9990 G00 X40. Q7\nN9999 M30\n");
        let src = followed(&text, false);
        let whole = SourceFile::new("followed", text.as_str());
        let czech = crate::dialect::get(crate::dialect::czech::ID);
        let profile = crate::profile::Profile::default();
        let a = czech.diagnostics(&src, &profile, Default::default());
        let b = czech.diagnostics(&whole, &profile, Default::default());
        assert!(!a.is_empty());
        assert_eq!(a, b);
    }

    /// The ISO reader over a text still being written (read as it comes while no line may
    /// hold an O-word; else again once the text has ended) reports what it reports over the
    /// whole text: an error in a straight program, the `%`s and the end, a loop (the run
    /// gives up at it), a contour subroutine called before its definition, an error that
    /// stops the run before an O-word.
    #[cfg(unix)]
    #[test]
    fn the_iso_reader_over_a_text_being_written_reports_as_over_the_whole() {
        let straight: String = (0..300)
            .map(|i| {
                format!(
                    "G0 X{} Z2\nG1 Z-{} F0.2 (pass {i})\n",
                    30 + i % 5,
                    10 + i % 7
                )
            })
            .collect();
        let head = "G7 G18 G21 G90 G95\n";
        let texts = [
            format!("{head}{straight}G1 X20 Z-40 Q7\n{straight}M30\n"),
            format!("%\n{head}{straight}%\nG0 X1\n"),
            format!("{head}{straight}"),
            format!(
                "{head}{straight}#1 = 0\no100 while [#1 LT 2]\nG0 X40\n#1 = [#1 + 1]\no100 endwhile\n{straight}M30\n"
            ),
            format!(
                "{head}G0 X40 Z2\n{straight}G71 Q100 D1 I0.2 K0.1\nG0 X50\nM30\no100 sub\nG1 X20 Z0\nG1 Z-10\nG1 X40\no100 endsub\n"
            ),
            // An error that stops the run, an O-word after it (reported up front).
            format!("{head}M72\n{straight}o1 endif\nM30\n"),
        ];
        reads_as_the_whole_while_written(crate::dialect::iso::ID, &texts);
        let followed = crate::dialect::iso::FOLLOWED.load(std::sync::atomic::Ordering::Relaxed);
        // The straight programs are read as they come (the others give up): unless this
        // thread was kept waiting for a whole text's writing.
        assert!(followed > 0, "no text was read as it came");
    }

    /// The FANUC reader over a text still being written (read as it comes while no line uses
    /// macros or subprograms; else again once the text has ended) reports what it reports
    /// over the whole text: an error, a title line and the `%`s, a line after the end, a
    /// macro variable, a subprogram call.
    #[cfg(unix)]
    #[test]
    fn the_fanuc_reader_over_a_text_being_written_reports_as_over_the_whole() {
        let straight: String = (0..300)
            .map(|i| {
                format!(
                    "G00 X{}. Z2.\nG01 Z-{}. F0.2 (PASS {i})\n",
                    30 + i % 5,
                    10 + i % 7
                )
            })
            .collect();
        let head = "%\nO0100\nG21 G99\nT0101\nG97 S500 M03\n";
        let texts = [
            format!("{head}{straight}G01 X20. Z-40. Q7\n{straight}M30\n%\n"),
            format!("SHAFT ONE\n{head}{straight}M30\nG00 X1.\n%\n"),
            format!("{head}{straight}"),
            format!("{head}{straight}#100=2.\nG00 X#100\n{straight}M30\n%\n"),
            format!("{head}{straight}M98 P1234\n{straight}M30\n%\n"),
        ];
        reads_as_the_whole_while_written(crate::dialect::fanuc::ID, &texts);
        let followed = crate::dialect::fanuc::FOLLOWED.load(std::sync::atomic::Ordering::Relaxed);
        assert!(followed > 0, "no text was read as it came");
    }

    /// Each of `texts`, written 40 lines at a time in another thread while `dialect`'s
    /// reader reads it for its diagnostics, gives the diagnostics of the whole text.
    #[cfg(unix)]
    fn reads_as_the_whole_while_written(dialect: crate::dialect::DialectId, texts: &[String]) {
        use std::io::Write as _;
        let reader = crate::dialect::get(dialect);
        let profile = crate::profile::Profile::default();
        for text in texts {
            let (follow, following) = follow();
            let owned = text.clone();
            let writer = std::thread::spawn(move || {
                let mut file = tempfile::tempfile().unwrap();
                let mut len = 0u64;
                for piece in owned.split_inclusive('\n').collect::<Vec<_>>().chunks(40) {
                    let piece = piece.concat();
                    file.write_all(piece.as_bytes()).unwrap();
                    len += piece.len() as u64;
                    follow.publish(&file, len);
                    std::thread::sleep(std::time::Duration::from_millis(2));
                }
                follow.finish();
            });
            let src = SourceFile::of_text("followed", following.text().expect("a file"));
            let a = reader.diagnostics(&src, &profile, Default::default());
            writer.join().unwrap();
            assert!(src.text.is_complete());
            let whole = SourceFile::new("followed", text.as_str());
            let b = reader.diagnostics(&whole, &profile, Default::default());
            assert_eq!(a, b, "{dialect}: {}", &text[text.len() - 120..]);
        }
    }

    /// A reading cancelled (its output refused) ends at once, even with every line
    /// published, and is not complete: its answer never stands for the read-back's.
    #[cfg(unix)]
    #[test]
    fn a_cancelled_reading_ends_and_is_incomplete() {
        use std::io::Write as _;
        let (follow, following) = follow();
        let cancel = following.canceller();
        let mut file = tempfile::tempfile().unwrap();
        file.write_all(b"N10 X1\nN20 X2\n").unwrap();
        follow.publish(&file, 14);
        follow.finish();
        let src = SourceFile::of_text("followed", following.text().unwrap());
        let mut lines = src.lines();
        assert_eq!(lines.next().map(|l| l.text), Some("N10 X1"));
        cancel.cancel();
        assert_eq!(lines.next().map(|l| l.text), None);
        assert!(!src.text.is_complete());
    }

    /// A text published in one step of more than the stretch checked at a time (with a
    /// character cut at the stretch's end) is seen whole and complete, a megabyte at a time;
    /// one with a byte that is no UTF-8 further on ends before the stretch that holds it,
    /// incomplete.
    #[cfg(unix)]
    #[test]
    fn a_text_published_at_once_is_checked_a_stretch_at_a_time() {
        use std::io::Write as _;
        let mut text = "a".repeat(READ_LAG - 1);
        text.push('é');
        text.push_str(&"N10 X1\n".repeat(READ_LAG / 7));
        let mut bad = text.clone().into_bytes();
        bad.extend_from_slice(b"N20 \xFF\n");
        for (bytes, good) in [(text.as_bytes(), true), (&bad[..], false)] {
            let (follow, following) = follow();
            let mut file = tempfile::tempfile().unwrap();
            file.write_all(bytes).unwrap();
            follow.publish(&file, bytes.len() as u64);
            follow.finish();
            let text = following.text().unwrap();
            assert!(text.grow());
            assert_eq!(
                text.len(),
                READ_LAG - 1,
                "the stretch stops before the cut é"
            );
            text.wait_end();
            assert_eq!(text.is_complete(), good);
            if good {
                assert_eq!(text.as_bytes(), bytes);
            } else {
                assert_eq!(text.len(), 2 * READ_LAG - 1);
            }
        }
    }
}

//! What every writer shares: the items of one source block, a cycle's expansion with its
//! refusal, and the one summary of the values a target's grid cannot hold.

use crate::diag::{Code, Diagnostic, codes};
use crate::fixed::{Angle, Lead, Length, div_round};
use crate::ir::{Item, Pos, ThreadCycle};
use crate::lower::{self, Expansion};
use crate::source::{SourceFile, Span};

/// The program's items a block at a time, one item at a time: the items read from one source
/// line stay together when the writer keeps the source's blocks (`keep`: the program is in
/// the writer's own dialect), else each item is a block of its own, and a speed mode and the
/// spindle item after it are one block (`G96 S200 M3`: the mode says its speed). Each group is
/// handed out once complete.
#[derive(Debug, Default)]
pub(crate) struct Grouper {
    keep: bool,
    /// The items of the source line being gathered.
    line: Vec<Item>,
    /// A complete group, held while the next may join it.
    ready: Option<Vec<Item>>,
}

impl Grouper {
    pub fn new(keep: bool) -> Self {
        Grouper {
            keep,
            ..Grouper::default()
        }
    }

    /// The program's next item; `out` takes each group it completes.
    pub fn item(&mut self, item: &Item, mut out: impl FnMut(&[Item])) {
        let same_line = self.keep
            && self
                .line
                .first()
                .is_some_and(|first| first.span.line == item.span.line);
        if !same_line && !self.line.is_empty() {
            let group = std::mem::take(&mut self.line);
            self.complete(group, &mut out);
        }
        self.line.push(item.clone());
    }

    /// The program has ended: the groups still held.
    pub fn finish(&mut self, mut out: impl FnMut(&[Item])) {
        if !self.line.is_empty() {
            let group = std::mem::take(&mut self.line);
            self.complete(group, &mut out);
        }
        if let Some(group) = self.ready.take() {
            out(&group);
        }
    }

    fn complete(&mut self, group: Vec<Item>, out: &mut impl FnMut(&[Item])) {
        if let Some(before) = self.ready.take() {
            if !self.keep
                && matches!(before[0].kind, crate::ir::ItemKind::SpindleMode(_))
                && matches!(group[0].kind, crate::ir::ItemKind::Spindle { .. })
                && group[0].comment.is_none()
            {
                out(&[before[0].clone(), group[0].clone()]);
                return;
            }
            out(&before);
        }
        self.ready = Some(group);
    }
}

/// Values a target cannot hold on its grid, gathered for one diagnostic per program (an
/// error, or with `--round` a warning): how many, the largest deviation, and the first.
#[derive(Debug, Default)]
pub(crate) struct Inexact {
    pub count: usize,
    /// The largest deviation: of a length, its rounding; of a lead, the drift it causes at
    /// the thread's end.
    pub largest: Length,
    /// Where the first is, what it is (`X 26.618 mm`) and the grid it misses (`0.001 mm`).
    pub first: Option<(Span, String, String)>,
}

/// What [`Inexact`] gathered, for the target's one diagnostic.
pub(crate) struct InexactSummary {
    pub count: usize,
    /// The first value (`X 26.618 mm`) and the grid it misses (`0.001`).
    pub what: String,
    pub grid: String,
    /// The largest deviation, in mm.
    pub largest: String,
}

impl Inexact {
    /// Whether a value off the grid has been found: refused at the end without `round`.
    pub fn refuses(&self, round: bool) -> bool {
        !round && self.count > 0
    }

    /// The one diagnostic of a program's values off the grid (none when all are on it):
    /// `rounded` words the warning of `--round`, `refused` the error without it.
    pub fn diagnostic(
        &mut self,
        src: &SourceFile,
        round: bool,
        rounded: impl FnOnce(&InexactSummary) -> Diagnostic,
        refused: impl FnOnce(&InexactSummary) -> Diagnostic,
    ) -> Option<Diagnostic> {
        let (span, what, grid) = self.first.take()?;
        let summary = InexactSummary {
            count: self.count,
            what,
            grid,
            largest: self.largest.mm(),
        };
        let mut d = if round {
            rounded(&summary)
        } else {
            refused(&summary)
        };
        if round {
            d.deviation = Some(self.largest);
        }
        Some(d.at(src, span))
    }

    /// Notes that `what` = `value` at `span` is written as `rounded` on `grid`.
    pub fn note(&mut self, span: Span, what: &str, value: Length, rounded: Length, grid: Length) {
        self.count += 1;
        self.largest = self.largest.max((rounded - value).abs());
        if self.first.is_none() {
            self.first = Some((span, format!("{what} {} mm", value.mm()), grid.mm()));
        }
    }

    /// Notes that the lead `what` = `lead` at `span` is written rounded onto `grid`, so that
    /// the thread drifts by `drift` at its end: that is its deviation.
    pub fn note_lead(&mut self, span: Span, what: &str, lead: Lead, drift: Length, grid: Length) {
        self.count += 1;
        self.largest = self.largest.max(drift);
        if self.first.is_none() {
            self.first = Some((span, format!("{what} {} mm", lead.mm()), grid.mm()));
        }
    }
}

/// A comment's text in ASCII on one line (deunicode's transliteration, `?` where it has
/// none; the diameter sign `D`), and whether anything changed.
pub(crate) fn ascii_comment(text: &str) -> (String, bool) {
    let mut changed = false;
    let mut ascii = String::new();
    for c in crate::dialect::one_line(text).chars() {
        if c.is_ascii() && !c.is_ascii_control() {
            ascii.push(c);
        } else if c.is_ascii_control() {
            ascii.push(' ');
        } else if matches!(c, 'Ø' | 'ø' | '⌀' | '∅') {
            ascii.push('D');
        } else {
            changed = true;
            ascii.push_str(
                deunicode::deunicode_char(c)
                    .filter(|t| t.is_ascii())
                    .unwrap_or("?"),
            );
        }
    }
    (ascii.trim().to_string(), changed)
}

/// The start angle of a pass that starts where the output's move before it left the tool:
/// its start Z on the 0.001 mm grid (rounded with `--round`). The helix is the same: the
/// angle runs on by the turns between the exact start and the written one.
pub(crate) fn start_on_grid(
    from: Option<Length>,
    to: Option<Length>,
    lead: Lead,
    angle: Angle,
) -> Angle {
    start_on(100, from, to, lead, angle)
}

/// [`start_on_grid`] on a grid of `grid` length units (100: 0.001 mm; 254: 0.0001 in).
pub(crate) fn start_on(
    grid: i64,
    from: Option<Length>,
    to: Option<Length>,
    lead: Lead,
    angle: Angle,
) -> Angle {
    let (Some(z), Some(end)) = (from, to) else {
        return angle;
    };
    let written = Length(div_round(z.0 as i128, grid as i128) as i64 * grid);
    Angle(angle.0 + lead.turn_over(Length((end - z).signum() * (written - z).0)))
}

/// An angle in degrees with as few decimals as needed (`0`, `90`, `120.5`).
pub(crate) fn angle_text(a: Angle) -> String {
    let (whole, frac) = (a.0 / 1000, a.0 % 1000);
    if frac == 0 {
        whole.to_string()
    } else {
        format!("{whole}.{frac:03}")
            .trim_end_matches('0')
            .to_string()
    }
}

/// The comments a writer transliterated to ASCII ([`ascii_comment`]): how many, and the first
/// with its place, for one warning per program.
#[derive(Debug, Default)]
pub(crate) struct AsciiComments {
    first: Option<(Span, String, String)>,
    count: usize,
}

impl AsciiComments {
    /// The ASCII text of the comment `text` of the item at `at`, its transliteration counted.
    pub fn text(&mut self, at: Span, text: &str) -> String {
        let (ascii, changed) = ascii_comment(text);
        if changed {
            self.count += 1;
            if self.first.is_none() {
                self.first = Some((at, crate::dialect::one_line(text), ascii.clone()));
            }
        }
        ascii
    }

    /// The one warning (`code`) of the comments transliterated, for a `control`'s program.
    pub fn diagnostic(
        &mut self,
        src: &SourceFile,
        code: Code,
        control: &str,
    ) -> Option<Diagnostic> {
        let (at, text, ascii) = self.first.take()?;
        let many = match self.count {
            1 => String::new(),
            n => format!(" ({n} comments, the first shown)"),
        };
        Some(
            Diagnostic::new(
                code,
                format!("comment text transliterated to ASCII: `{text}` → `{ascii}`{many}"),
            )
            .at(src, at)
            .help(format!("ncthread writes {control} comments in ASCII, which every control version shows: a letter loses its accent, other scripts are romanised, the diameter sign is `D`")),
        )
    }
}

/// `v` on the 0.001 mm grid, its rounding noted in `inexact` at `span` as `what`.
pub(crate) fn on_micron_grid(inexact: &mut Inexact, span: Span, what: &str, v: Length) -> Length {
    let grid = Length::from_steps(10);
    let rounded = Length(crate::fixed::div_round(v.0 as i128, grid.0 as i128) as i64 * grid.0);
    if rounded != v {
        inexact.note(span, what, v, rounded, grid);
    }
    rounded
}

/// A feed or a lead on the 0.0001 mm grid (its rounding noted in `inexact`, as the drift it
/// causes over `travel`); `None` after the error `code` when it rounds to nothing.
pub(crate) fn lead_on_grid(
    w: &mut Writer<'_>,
    inexact: &mut Inexact,
    code: Code,
    span: Span,
    what: &str,
    (lead, travel): (Lead, Length),
) -> Option<Lead> {
    let (units, exact) = lead.in_units(4);
    let written = Lead::from_units(units, 4);
    if written.0 <= 0 {
        w.error(
            code,
            span,
            format!(
                "{what} {} mm rounds to 0 in the program's 0.0001 mm",
                lead.mm()
            ),
            "a feed or a lead needs a value the control can hold",
        );
        return None;
    }
    if !exact {
        let drift = lead.drift(written, travel);
        inexact.note_lead(span, what, lead, drift, Length::from_steps(1));
    }
    Some(written)
}

/// The one diagnostic of a program's values off a `control`'s grid of 0.001 mm (leads and
/// feeds 0.0001 mm): the warning `rounded` (its help `rounded_help`) with `--round`, else the
/// error `refused`.
pub(crate) fn grid_diagnostic(
    inexact: &mut Inexact,
    src: &SourceFile,
    round: bool,
    control: &str,
    (rounded, refused): (Code, Code),
    rounded_help: &str,
) -> Option<Diagnostic> {
    inexact.diagnostic(
        src,
        round,
        |s| {
            Diagnostic::new(
                rounded,
                format!("{} value(s) rounded to the {control} program's grid (0.001 mm, leads and feeds 0.0001 mm), the first {}; the largest deviation is {} mm", s.count, s.what, s.largest),
            )
            .help(rounded_help)
        },
        |s| {
            Diagnostic::new(
                refused,
                format!("{} is finer than the {control} program's {} mm ({} value(s) in this program are; lengths take 3 decimals, leads and feeds 4)", s.what, s.grid, s.count),
            )
            .help(format!("pass --round to round them (largest deviation {} mm, for a lead its drift at the thread's end)", s.largest))
        },
    )
}

/// A line of a cycle written out ([`Writer::cycle_steps`]).
pub(crate) enum CycleStep {
    Comment(String),
    Move(Item),
}

/// What a writer needs to know of the whole program before its first line, gathered by a
/// first streaming read of the program (a conversion that does not hold the program) or
/// from the program's items: so far the R parameters a program assigns (not free for the
/// czech writer's leads). Over the items as [`crate::lower::unroll`] gives them.
#[derive(Clone, Debug, Default)]
pub struct Facts {
    /// The parameters assigned, in order, each once.
    pub params: Vec<u32>,
    /// Whether the program has an arc (the ISO header says `G91.1`).
    pub arcs: bool,
}

impl Facts {
    /// The program's next item (after unrolling). Whether the facts changed.
    pub fn item(&mut self, item: &Item) -> bool {
        let mut changed = false;
        if !self.arcs && matches!(item.kind, crate::ir::ItemKind::Arc { .. }) {
            self.arcs = true;
            changed = true;
        }
        if let crate::ir::ItemKind::ParamAssign { number, .. } = item.kind
            && let Err(at) = self.params.binary_search(&number)
        {
            self.params.insert(at, number);
            changed = true;
        }
        changed
    }
}

/// What a dialect's writer reads of the [`Facts`] and of the program's header (the program
/// as read without its items: its dialect, always, and its number, name and unit). A
/// conversion reads its source once when nothing its writer reads changes after the
/// writer's first item (or the writer takes it late, [`ItemWriter::late_facts`]), and twice
/// otherwise (the first read gathering them): so a writer
/// that reads something it does not declare here would write differently in the two cases
/// (`tests/read_back.rs` holds every corpus file's conversion to every target to the
/// conversion of the whole program).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct WriterReads {
    pub params: bool,
    pub arcs: bool,
    pub number: bool,
    pub name: bool,
    pub inch: bool,
}

impl WriterReads {
    /// Everything: the default of a dialect that does not say.
    pub const ALL: WriterReads = WriterReads {
        params: true,
        arcs: true,
        number: true,
        name: true,
        inch: true,
    };
    /// Nothing but the program's dialect.
    pub const NOTHING: WriterReads = WriterReads {
        params: false,
        arcs: false,
        number: false,
        name: false,
        inch: false,
    };

    /// What a writer made from `facts` and `program` reads of them: two writers whose views
    /// are equal write the same items alike.
    pub fn view(&self, facts: &Facts, program: &crate::ir::Program) -> WriterView {
        WriterView {
            params: if self.params {
                facts.params.clone()
            } else {
                Vec::new()
            },
            arcs: self.arcs && facts.arcs,
            number: program.number.filter(|_| self.number),
            name: program.name.clone().filter(|_| self.name),
            inch: self.inch && program.inch,
        }
    }
}

/// What a writer read of the facts and the header ([`WriterReads::view`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct WriterView {
    params: Vec<u32>,
    arcs: bool,
    number: Option<u32>,
    name: Option<String>,
    inch: bool,
}

/// A writer that takes a program one item at a time, in order (issue 34: a conversion that
/// does not hold the program). Items come unrolled ([`crate::lower::unrolled`]).
pub trait ItemWriter {
    fn item(&mut self, item: &Item);
    /// [`Self::item`] for an item the writer may keep (a writer that gathers a block's items
    /// overrides it to keep them without a copy).
    fn take(&mut self, item: Item) {
        self.item(&item);
    }
    /// The facts it was made with changed after its first item (a conversion that reads its
    /// program once): whether it took them, so that it now writes what a writer made with
    /// them would have written (by default not: the conversion lets it go and reads again).
    fn late_facts(&mut self, _facts: &Facts) -> bool {
        false
    }
    /// Has a reader read the text as it is written ([`Writer::follow`]); by default the
    /// writer does not say it, and the reader is told so at once.
    #[cfg(unix)]
    fn follow(&mut self, _follow: crate::source::Follow) {}
    /// Whether the output is refused already by what the writer has found so far and says
    /// only at its finish (a value off its grid without `--round`): a reader following it
    /// can stop.
    fn refuses(&self) -> bool {
        false
    }
    /// The text (none after an error) and the writer's diagnostics.
    fn finish(self: Box<Self>) -> (Option<Output>, Vec<Diagnostic>);
}

/// How much finished text a writer holds before it moves it to its spool ([`Writer::spill`]).
const SPILL_AT: usize = 1 << 20;

/// The text a writer has finished with, moved out of memory into an unnamed temporary file
/// (gone when closed, whatever happens) once it passes [`SPILL_AT`] bytes: a program's
/// items and its whole output are then never in memory together (issue 34). Where no
/// temporary file can be made (the browser's WebAssembly) the text stays in memory.
#[derive(Debug, Default)]
struct Spool {
    file: Option<std::fs::File>,
    /// The bytes written to `file` whole.
    len: u64,
    /// Whether any of them is not a blank.
    non_blank: bool,
    /// No (more) spilling: no temporary file could be made, or a write to it failed.
    off: bool,
    /// A reader that reads the text as it is spooled ([`crate::source::follow`]).
    #[cfg(unix)]
    follow: Option<crate::source::Follow>,
}

impl Spool {
    /// Appends `text` to the file (made on first use); false when it cannot, and from then
    /// on the text stays in memory.
    fn write(&mut self, text: &str) -> bool {
        use std::io::Write as _;
        if self.off {
            return false;
        }
        if self.file.is_none() {
            match crate::files::spool_file() {
                Ok(f) => self.file = Some(f),
                Err(_) => {
                    self.off = true;
                    return false;
                }
            }
        }
        let written = self
            .file
            .as_mut()
            .is_some_and(|f| f.write_all(text.as_bytes()).is_ok());
        if written {
            self.len += text.len() as u64;
            self.non_blank |= !text.trim().is_empty();
            #[cfg(unix)]
            if let (Some(follow), Some(file)) = (&self.follow, &self.file) {
                follow.publish(file, self.len);
            }
        } else {
            // The file keeps its first `len` bytes, which are whole; a part written after
            // them is never read.
            self.off = true;
            #[cfg(unix)]
            {
                self.follow = None;
            }
        }
        written
    }
}

#[cfg(unix)]
impl Spool {
    /// A text followed as it is spooled ([`Writer::follow`]): its last lines `held` go to
    /// the spool too (published as a spill is), which is then its end; what stays held.
    /// A spool that took nothing before (a short output), or fails now, lets its reader go.
    fn end_followed(&mut self, held: String) -> String {
        if self.follow.is_none() {
            return held;
        }
        if self.file.is_none() {
            self.follow = None;
            return held;
        }
        // A failed write lets the reader go itself.
        if !held.is_empty() && !self.write(&held) {
            return held;
        }
        if let Some(follow) = self.follow.take() {
            follow.finish();
        }
        String::new()
    }
}

/// A writer's text: what it spooled (in order) and what it still held at the end.
#[derive(Debug)]
pub struct Output {
    spooled: Option<(std::fs::File, u64)>,
    held: String,
}

impl Output {
    /// The whole text: what was spooled, mapped from its file (the rest written to it
    /// first), else the text held. Fails only when the spool cannot be read back.
    pub fn into_text(self) -> std::io::Result<crate::source::Text> {
        #[cfg(unix)]
        if let Some((mut file, len)) = self.spooled {
            use std::io::{Seek as _, Write as _};
            file.seek(std::io::SeekFrom::Start(len))?;
            file.write_all(self.held.as_bytes())?;
            file.set_len(len + self.held.len() as u64)?;
            return crate::source::Text::mapped(file);
        }
        self.into_string().map(Into::into)
    }

    /// The whole text in memory. Fails only when the spool cannot be read back.
    pub fn into_string(self) -> std::io::Result<String> {
        use std::io::{Read as _, Seek as _};
        let Some((mut file, len)) = self.spooled else {
            return Ok(self.held);
        };
        let capacity = usize::try_from(len).unwrap_or(usize::MAX);
        let mut bytes = Vec::with_capacity(capacity.saturating_add(self.held.len()));
        file.rewind()?;
        file.take(len).read_to_end(&mut bytes)?;
        if bytes.len() as u64 != len {
            return Err(std::io::Error::new(
                std::io::ErrorKind::UnexpectedEof,
                "the temporary file is shorter than what was written to it",
            ));
        }
        bytes.extend_from_slice(self.held.as_bytes());
        String::from_utf8(bytes)
            .map_err(|e| std::io::Error::new(std::io::ErrorKind::InvalidData, e))
    }
}

/// The state every writer keeps: the source (for diagnostics), the text written so far,
/// the diagnostics, and the tool's position as the output leaves it.
pub(crate) struct Writer<'a> {
    pub src: &'a SourceFile,
    /// The text written and not yet spilled ([`Writer::spill`]).
    pub out: String,
    pub diags: Vec<Diagnostic>,
    pub pos: Pos,
    fold: crate::diag::Fold,
    spool: Spool,
    /// What the target does to its finished lines before they leave (LinuxCNC's long lines
    /// split): applied to whole lines, a part at a time, so it must give the same text
    /// over a text's lines one part at a time as over the whole, and change nothing it gave.
    pub post: Option<fn(String) -> String>,
    /// [`SPILL_AT`], lower in tests.
    spill_at: usize,
    /// A spill took lines out of `out` (even if the spool then failed and they came back).
    spilled: bool,
}

impl<'a> Writer<'a> {
    pub fn new(src: &'a SourceFile) -> Self {
        Writer {
            src,
            out: String::new(),
            diags: Vec::new(),
            pos: Pos::UNKNOWN,
            fold: Default::default(),
            spool: Spool::default(),
            post: None,
            spill_at: SPILL_AT,
            spilled: false,
        }
    }

    /// Called between items, where nothing written will be changed again: once the text
    /// held passes [`SPILL_AT`] bytes, its whole lines go to the spool.
    pub fn spill(&mut self) {
        if self.out.len() < self.spill_at || self.spool.off {
            return;
        }
        let Some(end) = self.out.rfind('\n').map(|i| i + 1) else {
            return;
        };
        self.spilled = true;
        let rest = self.out.split_off(end);
        let lines = std::mem::replace(&mut self.out, rest);
        let lines = match self.post {
            Some(post) => post(lines),
            None => lines,
        };
        if !self.spool.write(&lines) {
            // Held again, before the rest (`post` changes nothing it gave).
            self.out.insert_str(0, &lines);
        }
    }

    /// Has `follow` read the text as it goes to the spool: every spill is published to it,
    /// and [`Writer::finish`] spools the rest and says it is done. A writer that spills
    /// nothing (a short output), fails, or is let go of, abandons it.
    #[cfg(unix)]
    pub fn follow(&mut self, follow: crate::source::Follow) {
        self.spool.follow = Some(follow);
    }

    /// Whether every line written is still held (none moved to the spool): an offset into
    /// `out` taken earlier still points where it did.
    pub fn holds_all(&self) -> bool {
        !self.spilled
    }

    /// Whether nothing but blanks was written.
    pub fn is_blank(&self) -> bool {
        !self.spool.non_blank && self.out.trim().is_empty()
    }

    /// Reports a problem at `span` once (a cycle's passes share the cycle's span).
    pub fn error(
        &mut self,
        code: Code,
        span: Span,
        message: impl Into<String>,
        help: impl Into<String>,
    ) {
        self.report(Diagnostic::new(code, message).at(self.src, span).help(help));
    }

    /// A cycle's passes ([`lower::expand`]), or `None` after refusing a cycle that does not
    /// define every pass (the same words for every target).
    pub fn expand(&mut self, cycle: &ThreadCycle, span: Span) -> Option<Expansion> {
        match lower::expand(cycle) {
            Ok(e) => Some(e),
            Err(e) => {
                self.error(
                    codes::CYCLE_INVALID,
                    span,
                    e.message(cycle),
                    "correct the cycle's words; ncthread cuts a cycle only when every pass is defined",
                );
                None
            }
        }
    }

    /// A cycle written out as its passes, for a writer with one kind of comment line: its
    /// summary (with `diameter`, `D` or `Ø`) and each pass's heading as comments, and each
    /// move as an item at the cycle's span. `None` after refusing a cycle that cannot be
    /// expanded.
    pub fn cycle_steps(
        &mut self,
        cycle: &ThreadCycle,
        span: Span,
        diameter: &str,
    ) -> Option<Vec<CycleStep>> {
        let expansion = self.expand(cycle, span)?;
        let mut steps = vec![CycleStep::Comment(expansion.summary(cycle, diameter))];
        steps.extend(expansion.steps().map(|step| match step {
            lower::Step::Heading(heading) => CycleStep::Comment(heading),
            lower::Step::Move(m) => CycleStep::Move(Item::new(m.item_kind(), span)),
        }));
        Some(steps)
    }

    /// Adds `d` unless the same diagnostic was reported already; a repeat past what is
    /// listed is counted ([`crate::diag::Fold`]).
    pub fn report(&mut self, d: Diagnostic) {
        // The output will be refused: a reader following it is let go.
        #[cfg(unix)]
        if d.is_error() {
            self.spool.follow = None;
        }
        if self.fold.admit_once(&self.diags, &d) {
            self.diags.push(d);
        }
    }

    /// How many errors so far, listed or counted.
    pub fn errors(&self) -> usize {
        self.diags.iter().filter(|d| d.is_error()).count() + self.fold.errors()
    }

    /// The text, when no diagnostic is an error, and the diagnostics.
    pub fn finish(mut self) -> (Option<Output>, Vec<Diagnostic>) {
        self.diags.extend(std::mem::take(&mut self.fold).finish());
        if self.diags.iter().any(Diagnostic::is_error) {
            return (None, self.diags);
        }
        let out = std::mem::take(&mut self.out);
        let held = match self.post {
            Some(post) => post(out),
            None => out,
        };
        #[cfg(unix)]
        let held = self.spool.end_followed(held);
        let spooled = self
            .spool
            .file
            .filter(|_| self.spool.len > 0)
            .map(|f| (f, self.spool.len));
        (Some(Output { spooled, held }), self.diags)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ir::ItemKind;

    /// Lines written past the spill size go to the spool whole, the post-pass sees each part,
    /// and the text read back is the text written, in order.
    #[test]
    fn a_spilled_output_reads_back_as_written() {
        fn shout(text: String) -> String {
            text.to_uppercase()
        }
        let src = SourceFile::new("t", "");
        let mut w = Writer::new(&src);
        w.spill_at = 10;
        w.post = Some(shout);
        let mut whole = String::new();
        for n in 0..50 {
            let line = format!("line {n} ü\n");
            w.out.push_str(&line);
            whole.push_str(&line);
            if n % 3 == 0 {
                // A part of a line: it stays held until its line ends.
                w.out.push_str("part ");
                whole.push_str("part ");
            }
            w.spill();
        }
        assert!(w.spool.len > 0, "spilled");
        assert!(!w.is_blank());
        let (out, diags) = w.finish();
        assert!(diags.is_empty());
        assert_eq!(out.unwrap().into_string().unwrap(), whole.to_uppercase());
    }

    #[test]
    fn blanks_spilled_are_still_blank() {
        let src = SourceFile::new("t", "");
        let mut w = Writer::new(&src);
        w.spill_at = 1;
        w.out.push_str("  \n\n");
        w.spill();
        assert!(w.spool.len > 0 && w.is_blank());
        w.out.push_str("N1\n");
        assert!(!w.is_blank());
    }

    #[test]
    fn blocks_keep_the_items_of_one_source_line_together_only_when_asked() {
        let on = |line| {
            let mut item = Item::new(ItemKind::SpindleStop, Span::default());
            item.span.line = line;
            item
        };
        let items = [on(1), on(1), on(2), on(3), on(3)];
        let sizes = |keep| {
            let mut grouper = Grouper::new(keep);
            let mut sizes = Vec::new();
            for item in &items {
                grouper.item(item, |g| sizes.push(g.len()));
            }
            grouper.finish(|g| sizes.push(g.len()));
            sizes
        };
        assert_eq!(sizes(true), [2, 1, 2]);
        assert_eq!(sizes(false), [1; 5]);
        // A speed mode and the spindle start after it are one block, unless the start has a comment.
        let mode = Item::new(
            ItemKind::SpindleMode(crate::ir::SpindleMode::Rpm),
            Span::default(),
        );
        let start = Item::new(
            ItemKind::Spindle {
                speed: Some(800),
                direction: Some(crate::ir::SpindleDirection::Clockwise),
            },
            Span::default(),
        );
        let mut commented = start.clone();
        commented.comment = Some("START".into());
        for (second, expected) in [(start, vec![2]), (commented, vec![1, 1])] {
            let mut grouper = Grouper::new(false);
            let mut sizes = Vec::new();
            grouper.item(&mode, |g| sizes.push(g.len()));
            grouper.item(&second, |g| sizes.push(g.len()));
            grouper.finish(|g| sizes.push(g.len()));
            assert_eq!(sizes, expected);
        }
    }

    #[test]
    fn an_expansion_introduces_each_pass_once() {
        let cycle = lower::seed_m36_cycle(crate::ir::Schedule::Halving);
        let e = lower::expand(&cycle).expect("the seed cycle expands");
        let headings: Vec<String> = e
            .steps()
            .filter_map(|s| match s {
                lower::Step::Heading(h) => Some(h),
                lower::Step::Move(_) => None,
            })
            .collect();
        let passes = e.passes.len() + usize::from(e.moves.iter().any(|m| m.pass == 0));
        assert_eq!(headings.len(), passes);
        assert_eq!(e.steps().count(), e.moves.len() + headings.len());
    }
}

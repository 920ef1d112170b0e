//! ncthread: lathe thread-cutting programs between the czech control, the НЦ-31, LinuxCNC's
//! ISO G-code and FANUC lathe G-code, through one thread-operation IR. Exact or refused.
//!
//! The stages are public functions: [`parse`] (text → [`ir::Program`]), [`emit`]
//! (program → text), [`convert`] (both, and the output read back), [`check`] (every
//! diagnostic without writing) and [`verify`] (both programs simulated and compared). Every
//! problem is a [`diag::Diagnostic`] with a code, a place and a help text.
//!
//! Convert a program:
//!
//! ```
//! use ncthread::{ConvertOptions, DialectId, convert, source::SourceFile};
//!
//! let text = "N10 G00 G95 S1000 M03\nN20 G00 X26.618 Z3.\nN30 G33 Z-9. I0. F1.5\nN40 G00 X29.\n";
//! let src = SourceFile::new("part.nc", text.to_string());
//! // Dialect names parse in any case; a name that is no dialect's is an error.
//! let options = ConvertOptions::new("czech".parse()?, "ISO".parse()?);
//! let conversion = convert(&src, &options);
//! let output = conversion.output.expect("converted");
//! assert!(output.contains("G33 X26.618 Z-9 K1.5"));
//! assert!("FANUX".parse::<DialectId>().is_err());
//! # Ok::<(), ncthread::dialect::UnknownDialect>(())
//! ```
//!
//! A refusal names the block and why, and writes nothing:
//!
//! ```
//! use ncthread::{ConvertOptions, convert, dialect, source::SourceFile};
//!
//! // An НЦ-31 frame with a decimal point: the НЦ-31 writes whole units.
//! let src = SourceFile::new("p.txt", "N1 X36.5\n".to_string());
//! let c = convert(&src, &ConvertOptions::new(dialect::nc31::ID, dialect::iso::ID));
//! assert!(c.output.is_none());
//! let first = c.diagnostics.iter().find(|d| d.is_error()).unwrap();
//! assert_eq!(first.code.id, "NCR002");
//! assert_eq!(first.location.as_ref().unwrap().line, 1);
//! ```
//!
//! Prove a conversion by simulating both programs:
//!
//! ```
//! use ncthread::{ConvertOptions, Outcome, dialect, source::SourceFile, verify};
//!
//! let text = "N10 G00 G95 S1000 M03\nN20 G00 X26.618 Z3.\nN30 G33 Z-9. I0. F1.5\nN40 G00 X29.\n";
//! let src = SourceFile::new("part.nc", text.to_string());
//! let v = verify(&src, &ConvertOptions::new(dialect::czech::ID, dialect::fanuc::ID), None, None);
//! assert!(matches!(v.outcome, Outcome::Equivalent { .. }));
//! ```
//!
//! The modules a user needs are [`diag`], [`dialect`] (ids and the capability tables),
//! [`ir`], [`profile`], [`source`], [`sim`], [`explain`], [`plot`], [`batch`],
//! [`text`] (decoding legacy encodings) and [`frontend`] (a program's bytes read as the CLI
//! reads them, and its diagnostics and verdict as the CLI prints them). `fixed`, `files`, `legalise` and `lower` are the
//! implementation, public only for the crate's own tests, benchmarks and binary: they are
//! hidden from the documentation and may change without notice.

pub mod batch;
pub mod diag;
pub mod dialect;
pub mod encoding;
pub mod explain;
#[doc(hidden)]
pub mod files;
#[doc(hidden)]
pub mod fixed;
pub mod frontend;
pub mod ir;
#[doc(hidden)]
pub mod legalise;
#[doc(hidden)]
pub mod lower;
pub mod plot;
pub mod profile;
pub mod sim;
pub mod source;
pub mod text;

/// The crate's version, as Cargo.toml gives it.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");

use diag::Diagnostic;
pub use dialect::{DialectId, Unsupported};
use ir::Program;
use profile::Profile;
use source::SourceFile;

/// Everything a conversion needs besides the source.
#[derive(Clone, Debug)]
pub struct ConvertOptions {
    pub from: DialectId,
    pub to: DialectId,
    pub profile: Profile,
    pub unsupported: Unsupported,
    /// Block numbering for a target that numbers its blocks, from another dialect.
    pub renumber: dialect::Renumber,
    /// Round values a target cannot hold to its grid (with a warning) instead of refusing.
    pub round: bool,
    /// nc31 output: write comments as `(` lines instead of dropping them.
    pub nc31_comments: bool,
}

impl ConvertOptions {
    /// Options for converting `from` → `to` with the built-in defaults: no machine profile,
    /// undocumented constructs refused, czech/nc31 block numbers from 10 by 10, no rounding.
    pub fn new(from: DialectId, to: DialectId) -> ConvertOptions {
        ConvertOptions {
            from,
            to,
            profile: Profile::default(),
            unsupported: Unsupported::Error,
            renumber: Default::default(),
            round: false,
            nc31_comments: false,
        }
    }
}

/// The result of a conversion: the program text when there was no error, and every
/// diagnostic (warnings too). A large output is not held in memory: it is mapped from the
/// temporary file it was written to ([`source::Text`]), and reads as a `str` all the same.
#[derive(Clone, Debug)]
pub struct Conversion {
    pub output: Option<source::Text>,
    pub diagnostics: Vec<Diagnostic>,
}

/// Reads `src` in dialect `from`. The program is usable only when no diagnostic is an error.
/// A program with errors whose text reads like another dialect says so (INP002): the
/// `--from` may be wrong.
pub fn parse(
    src: &SourceFile,
    from: DialectId,
    profile: &Profile,
    unsupported: Unsupported,
) -> (Program, Vec<Diagnostic>) {
    read(src, from, profile, unsupported, dialect::Keep::Program)
}

/// [`parse`], keeping what `keep` says (a streaming read hands each item on).
fn read(
    src: &SourceFile,
    from: DialectId,
    profile: &Profile,
    unsupported: Unsupported,
    keep: dialect::Keep<'_>,
) -> (Program, Vec<Diagnostic>) {
    let (program, mut diags) = dialect::get(from).read_keeping(src, profile, unsupported, keep);
    if diag::has_errors(&diags) {
        let detection = dialect::detect::detect(&src.text);
        let other = detection.dialect;
        if detection.certain
            && other != from
            && !diag::has_errors(&dialect::get(other).diagnostics(src, profile, unsupported))
        {
            diags.push(
                Diagnostic::new(
                    diag::codes::OTHER_DIALECT,
                    format!(
                        "{} was read as {from}, and it reads without errors as {other} ({})",
                        src.name, detection.reason
                    ),
                )
                .help(format!(
                    "if it is written in {0}, give --from {0} (or --from auto)",
                    detection.dialect
                )),
            );
        }
    }
    (program, diags)
}

/// Writes `program` (read from `src`) in dialect `options.to`, after the rules every target
/// shares.
pub fn emit(
    program: &Program,
    src: &SourceFile,
    options: &ConvertOptions,
) -> (Option<String>, Vec<Diagnostic>) {
    let (output, mut diags) = emit_output(program, src, options);
    let output = output.and_then(|o| held(o, options, &mut diags));
    (output.map(source::Text::into_string), diags)
}

/// The whole text of a writer's `output`, or `None` with the error in `diags` when its
/// temporary file could not be read back.
fn held(
    output: dialect::Output,
    options: &ConvertOptions,
    diags: &mut Vec<Diagnostic>,
) -> Option<source::Text> {
    output
        .into_text()
        .map_err(|e| {
            diags.push(
                Diagnostic::new(
                    diag::codes::OUTPUT_UNREADABLE,
                    format!(
                        "the {} output could not be kept while it was written: its temporary file failed ({e})",
                        options.to
                    ),
                )
                .help(crate::files::MAKE_ROOM),
            )
        })
        .ok()
}

/// What a writer is told of the conversion.
fn write_options(options: &ConvertOptions) -> dialect::WriteOptions {
    dialect::WriteOptions {
        renumber: options.renumber,
        round: options.round,
        comments: options.nc31_comments,
    }
}

/// [`emit`], with a large output left in the writer's temporary file until the caller has
/// let go of the program.
fn emit_output(
    program: &Program,
    src: &SourceFile,
    options: &ConvertOptions,
) -> (Option<dialect::Output>, Vec<Diagnostic>) {
    // Roughing cycles are legalised and written as their moves.
    let program = &*lower::unroll(program, Some(options.to));
    let shared = legalise::check(program, src, Some(options.to));
    if diag::has_errors(&shared) {
        return (None, shared);
    }
    let target = dialect::get(options.to);
    // What the target's table refuses; the writer then spells what remains.
    let mut diags = legalise::for_target(program, src, target, &options.profile);
    let (output, more) = target.write(program, src, &options.profile, &write_options(options));
    diags.extend(more);
    let output = output.filter(|_| !diag::has_errors(&diags));
    (output, diags)
}

/// INP001 when `src` holds no program: its reading made nothing (blank lines, an empty
/// comment); `items`: how many items it made (a streaming read keeps none).
fn empty_read(src: &SourceFile, items: usize, program: &Program) -> Option<Diagnostic> {
    (items == 0 && program.library.is_empty()).then(|| {
        let what = if src.text.trim().is_empty() {
            "it is empty"
        } else {
            "nothing in it is a block or a comment"
        };
        Diagnostic::new(
            diag::codes::EMPTY_INPUT,
            format!("{} holds no program: {what}", src.name),
        )
        .help("there is nothing to convert; check that the right file (or stdin) was given")
    })
}

/// Parses and emits. Refuses (no output) when any error remains. The program is never held
/// (issue 34): it is read once, straight into the writer, or twice when what the writer must
/// know first changed after its first item (the first read gathering it).
pub fn convert(src: &SourceFile, options: &ConvertOptions) -> Conversion {
    convert_streaming(src, options)
}

/// [`convert`] holding the program and writing it whole ([`emit`]): public for the test
/// that holds the streaming conversion to it.
#[doc(hidden)]
pub fn convert_whole(src: &SourceFile, options: &ConvertOptions) -> Conversion {
    let (program, mut diagnostics) =
        parse(src, options.from, &options.profile, options.unsupported);
    if let Some(stop) = before_writing(
        src,
        &program,
        program.items.len(),
        options,
        &mut diagnostics,
    ) {
        return stop;
    }
    let (output, more) = emit_output(&program, src, options);
    diagnostics.extend(more);
    // The source's program is not needed again: the whole output and the read-back's
    // need not stand beside it.
    drop(program);
    finish_conversion(output, options, diagnostics)
}

/// What stops a conversion before its writer: a subroutine library, an empty program, or
/// an error in the read (`items`: how many items the read made).
fn before_writing(
    src: &SourceFile,
    program: &Program,
    items: usize,
    options: &ConvertOptions,
    diagnostics: &mut Vec<Diagnostic>,
) -> Option<Conversion> {
    if !diag::has_errors(diagnostics) && !program.library.is_empty() {
        return Some(library(src, program, options, std::mem::take(diagnostics)));
    }
    if !diag::has_errors(diagnostics)
        && let Some(empty) = empty_read(src, items, program)
    {
        diagnostics.push(empty);
    }
    if diag::has_errors(diagnostics) {
        let mut diagnostics = std::mem::take(diagnostics);
        diag::sort(&mut diagnostics);
        return Some(Conversion {
            output: None,
            diagnostics,
        });
    }
    None
}

/// The writer's output, once the program is let go of, read back by the target's reader.
fn finish_conversion(
    output: Option<dialect::Output>,
    options: &ConvertOptions,
    diagnostics: Vec<Diagnostic>,
) -> Conversion {
    finish_followed(output, options, diagnostics, None)
}

/// [`finish_conversion`], the read-back made already beside the writer when `followed`
/// read the whole of this output ([`ReadBack`]), else made here.
fn finish_followed(
    output: Option<dialect::Output>,
    options: &ConvertOptions,
    mut diagnostics: Vec<Diagnostic>,
    followed: Option<ReadBack<'_>>,
) -> Conversion {
    if output.is_some()
        && !diag::has_errors(&diagnostics)
        && let Some((text, diags)) = followed.and_then(ReadBack::join)
    {
        // The writer's output is the text read: its file, mapped once already.
        drop(output);
        let mut output = None;
        match refusal(diags, options) {
            Some(refusal) => diagnostics.push(refusal),
            None => output = Some(text),
        }
        diag::sort(&mut diagnostics);
        return Conversion {
            output,
            diagnostics,
        };
    }
    let mut output = output.and_then(|o| held(o, options, &mut diagnostics));
    // Never write what the target's reader refuses: a last check, which finds what the
    // writers' own checks miss (it names the output line).
    if !diag::has_errors(&diagnostics)
        && let Some(text) = output.take()
    {
        let (text, refusal) = read_back(text, options);
        match refusal {
            Some(refusal) => diagnostics.push(refusal),
            None => output = Some(text),
        }
    }
    diag::sort(&mut diagnostics);
    Conversion {
        output,
        diagnostics,
    }
}

/// [`convert`]: one streaming read hands each item, unrolled, through the shared rules,
/// the target's table and the writer, made at the first item from what has been read so far
/// ([`dialect::Facts`] and the program's header). When something the writer reads of them
/// ([`dialect::Dialect::writer_reads`]) changes after that and the writer cannot take it late
/// ([`dialect::ItemWriter::late_facts`]: a FANUC program's number read after its first item,
/// an ISO output's first arc after its first megabyte, an inch program), or the read finds an
/// error, the writer is let go of, and (without an error) a second read writes the program
/// with what the first gathered. Nothing holds the program; the output spills to the
/// writer's temporary file.
///
/// A large source (and a machine with a second core) has its writer side — the shared
/// rules, the target's table and the writer — in a thread of its own, fed the items in
/// batches ([`WriterSide::Worker`]), while the reading thread reads on: the same work in the same
/// order, so the same output and diagnostics.
fn convert_streaming(src: &SourceFile, options: &ConvertOptions) -> Conversion {
    // In `batch`'s pool every core has a file already.
    #[cfg(not(target_arch = "wasm32"))]
    if src.text.len() >= WORKER_FROM
        && rayon::current_thread_index().is_none()
        && std::thread::available_parallelism().is_ok_and(|n| n.get() > 1)
    {
        return std::thread::scope(|scope| stream(src, options, Some(scope)));
    }
    stream(src, options, None)
}

/// A source this large, on a machine with a second core, has its writer side in a thread of
/// its own (issue 34: below it a thread costs more than it saves).
#[cfg(not(target_arch = "wasm32"))]
const WORKER_FROM: usize = 1 << 20;

/// [`convert_streaming`], the writer side in a thread of `scope` when there is one.
fn stream<'s, 'scope, 'env>(
    src: &'s SourceFile,
    options: &'s ConvertOptions,
    scope: Option<&'scope std::thread::Scope<'scope, 'env>>,
) -> Conversion
where
    's: 'scope,
{
    let target = dialect::get(options.to);
    let write = write_options(options);
    let mut once = Once {
        facts: Default::default(),
        items: 0,
        header: Default::default(),
        errors: false,
        emit: None,
        stopped: false,
        src,
        options,
        target,
        write: &write,
        scope,
        read_back: None,
    };
    let (program, mut diagnostics) = read(
        src,
        options.from,
        &options.profile,
        options.unsupported,
        dialect::Keep::Stream(&mut once),
    );
    if let Some(stop) = before_writing(src, &program, once.items, options, &mut diagnostics) {
        return stop;
    }
    let Once {
        facts,
        emit,
        read_back,
        ..
    } = once;
    let emit = emit.and_then(|(side, made_with)| Some((side.finish()?, made_with)));
    let view = target.writer_reads().view(&facts, &program);
    let inch = legalise::output_in_inches(&program, Some(options.to));
    let (emit, read_back) = match emit {
        Some((emit, written)) if written == (view, inch) => (emit, read_back),
        first => {
            // What the writer reads changed after its first item (or no item made one): the
            // same read again (its diagnostics are the first's), with what the first gathered.
            // The first writer is let go of first, and with it the reading of its output
            // beside it (which would otherwise wait for that writer's end).
            drop(first);
            drop(read_back);
            let mut emit = Emit::new(src, options, target, &facts, &program, &write);
            let _ = dialect::get(options.from).read_keeping(
                src,
                &options.profile,
                options.unsupported,
                dialect::Keep::Stream(&mut emit),
            );
            (emit, None)
        }
    };
    let Emit {
        rules,
        table,
        writer,
        ..
    } = emit;
    // As `emit`: the shared rules first; the table's refusals and the writer's after.
    let shared = rules.finish();
    if diag::has_errors(&shared) {
        diagnostics.extend(shared);
        return finish_conversion(None, options, diagnostics);
    }
    let mut diags = table.finish();
    let (output, more) = writer.finish();
    diags.extend(more);
    let output = output.filter(|_| !diag::has_errors(&diags));
    diagnostics.extend(diags);
    finish_followed(output, options, diagnostics, read_back)
}

/// What a read-back beside the writer answers: the output and its reading's diagnostics,
/// when it read the whole output.
type Answer = Option<(source::Text, Vec<Diagnostic>)>;

/// The read-back of a large conversion's output in a thread of its own, reading the output
/// as the writer spools it ([`source::follow`]): the czech, НЦ-31, SINUMERIK and HEIDENHAIN
/// readers read forward and keep up with the writer, and so do the ISO reader while no line
/// may hold an O-word and the FANUC reader while no line uses macros or subprograms (which
/// a converted program's output never holds); at such a line they wait for the end and read the whole
/// output up front. Its answer counts only when it read the whole output
/// of the writer the conversion kept; otherwise (the writer let go of, or failing, or a short
/// output held in memory) the read-back is made after the writer, as for a small conversion.
/// Dropped, it is told to stop.
#[cfg(unix)]
struct ReadBack<'scope> {
    done: Option<std::thread::ScopedJoinHandle<'scope, Answer>>,
    cancel: source::Following,
}

#[cfg(not(unix))]
struct ReadBack<'scope>(std::marker::PhantomData<&'scope ()>);

#[cfg(unix)]
impl<'scope> ReadBack<'scope> {
    /// Starts the read-back of the output of `emit`'s writer in a thread of `scope`, and
    /// has `emit` cancel it once the output is refused; `None` when no thread can be had
    /// (the writer then is not followed).
    fn start<'s, 'env>(
        emit: &mut Emit<'s>,
        options: &'s ConvertOptions,
        scope: &'scope std::thread::Scope<'scope, 'env>,
    ) -> Option<ReadBack<'scope>>
    where
        's: 'scope,
    {
        let (follow, following) = source::follow();
        let cancel = following.canceller();
        let done = std::thread::Builder::new()
            .name("ncthread-read-back".into())
            .spawn_scoped(scope, move || {
                let text = following.text()?;
                let out = SourceFile::of_text(output_name(options), text);
                let diags = dialect::get(options.to).diagnostics(
                    &out,
                    &options.profile,
                    options.unsupported,
                );
                out.text.is_complete().then_some((out.text, diags))
            })
            .ok()?;
        emit.writer.follow(follow);
        emit.cancel = Some(cancel.canceller());
        Some(ReadBack {
            done: Some(done),
            cancel,
        })
    }

    /// The output and the read-back's diagnostics, when it read the whole output.
    fn join(mut self) -> Answer {
        match self.done.take()?.join() {
            Ok(answer) => answer,
            Err(panic) => std::panic::resume_unwind(panic),
        }
    }
}

#[cfg(not(unix))]
impl ReadBack<'_> {
    fn join(self) -> Answer {
        None
    }
}

#[cfg(unix)]
impl Drop for ReadBack<'_> {
    fn drop(&mut self) {
        if self.done.is_some() {
            self.cancel.cancel();
        }
    }
}

/// The program's header as a read has found it so far.
#[derive(Default)]
struct Header {
    number: Option<u32>,
    name: Option<String>,
}

/// The one read of a streaming conversion: what the writer must know (gathered over every
/// item), and the writer, made at the first item with what was known then, while nothing
/// it reads of that has changed and the read has found no error.
struct Once<'s, 'w, 'scope, 'env> {
    facts: dialect::Facts,
    items: usize,
    header: Header,
    errors: bool,
    /// The writer and what it was made with (its view, and whether the output is in inches).
    emit: Option<(WriterSide<'s, 'scope>, (dialect::WriterView, bool))>,
    /// The writer was let go of (or never made): a second read writes.
    stopped: bool,
    src: &'s SourceFile,
    options: &'s ConvertOptions,
    target: &'static dyn dialect::Dialect,
    write: &'w dialect::WriteOptions,
    /// Where the writer side gets a thread of its own, if it does.
    scope: Option<&'scope std::thread::Scope<'scope, 'env>>,
    /// The read-back of the first writer's output, beside it (with a thread of its own).
    read_back: Option<ReadBack<'scope>>,
}

impl<'s, 'scope, 'env> Once<'s, '_, 'scope, 'env>
where
    's: 'scope,
{
    /// The program as read so far, without its items and in millimetres (whether every
    /// length is in inches is known only at the end).
    fn program(&self) -> Program {
        Program {
            items: Vec::new(),
            dialect: self.options.from,
            library: Vec::new(),
            number: self.header.number,
            name: self.header.name.clone(),
            inch: false,
        }
    }

    /// What the writer reads of what is known now.
    fn view(&self, program: &Program) -> dialect::WriterView {
        self.target.writer_reads().view(&self.facts, program)
    }

    /// An item the writer side takes by reference (one of a cycle's unrolled moves).
    fn one(&mut self, item: &ir::Item) {
        if self.admit(item)
            && let Some((side, _)) = &mut self.emit
        {
            side.item(item);
        }
    }

    /// An item the writer side takes whole (no copy for its thread).
    fn one_owned(&mut self, item: ir::Item) {
        if self.admit(&item)
            && let Some((side, _)) = &mut self.emit
        {
            side.take(item);
        }
    }

    /// The facts gathered over `item`, and the writer made, kept or let go of: whether the
    /// writer side takes the item.
    fn admit(&mut self, item: &ir::Item) -> bool {
        let changed = self.facts.item(item);
        if self.stopped || self.errors {
            self.stop();
            return false;
        }
        match &self.emit {
            None => {
                let program = self.program();
                let made_with = (
                    self.view(&program),
                    legalise::output_in_inches(&program, Some(self.options.to)),
                );
                let emit = Emit::new(
                    self.src,
                    self.options,
                    self.target,
                    &self.facts,
                    &program,
                    self.write,
                );
                #[cfg(unix)]
                let emit = self.read_back_beside(emit);
                self.emit = Some((WriterSide::new(emit, self.scope), made_with));
            }
            Some(_) if changed => {
                let view = self.view(&self.program());
                if let Some((side, (written, _))) = &mut self.emit
                    && *written != view
                {
                    if !side.late_facts(&self.facts) {
                        self.stop();
                        return false;
                    }
                    *written = view;
                }
            }
            Some(_) => {}
        }
        true
    }

    fn stop(&mut self) {
        self.stopped = true;
        self.emit = None;
    }

    /// The first writer's output read back beside it, when the writer side has a thread of
    /// its own ([`ReadBack`]).
    #[cfg(unix)]
    fn read_back_beside(&mut self, mut emit: Emit<'s>) -> Emit<'s> {
        // Where reading a file through a map while it is written sees what was written (a
        // unified buffer cache): not on every Unix.
        let coherent = cfg!(any(target_os = "linux", target_os = "macos"));
        if coherent && let Some(scope) = self.scope {
            self.read_back = ReadBack::start(&mut emit, self.options, scope);
        }
        emit
    }
}

impl<'s, 'scope, 'env> dialect::ItemSink for Once<'s, '_, 'scope, 'env>
where
    's: 'scope,
{
    fn item(&mut self, item: ir::Item) {
        self.items += 1;
        if let Some(moves) = lower::unrolled(&item, Some(self.options.to)) {
            moves.for_each(|m| self.one(&m));
            return;
        }
        self.one_owned(item);
    }

    fn so_far(&mut self, read: dialect::SoFar<'_>) {
        self.errors |= read.errors;
        if self.header.number != read.number || self.header.name.as_deref() != read.name {
            self.header = Header {
                number: read.number,
                name: read.name.map(str::to_string),
            };
            // The header changed since the writer was made: let it go if it read that.
            if let Some((_, (written, _))) = &self.emit
                && *written != self.view(&self.program())
            {
                self.stop();
            }
        }
    }
}

/// Where a streaming conversion's writer side runs.
enum WriterSide<'s, 'scope> {
    /// In the reading thread (boxed: an `Emit` is large, the worker's handle small).
    Here(Box<Emit<'s>>),
    /// In a thread of its own.
    Worker(Worker<'s, 'scope>),
}

/// A writer side in a thread of its own, handed the items in batches through a bounded
/// queue (so that the items waiting for it stay few: issue 34's memory bound).
struct Worker<'s, 'scope> {
    batch: Vec<ir::Item>,
    jobs: std::sync::mpsc::SyncSender<Job>,
    /// The batches the writer's thread has emptied, to be filled again (no allocation and
    /// no fresh pages a batch).
    emptied: std::sync::mpsc::Receiver<Vec<ir::Item>>,
    done: std::thread::ScopedJoinHandle<'scope, Option<Emit<'s>>>,
}

/// What the reading thread hands the writer's (after the writer side itself).
enum Job {
    Items(Vec<ir::Item>),
    /// The facts changed after the first item: whether the writer takes them late (the
    /// answer is awaited).
    LateFacts(dialect::Facts, std::sync::mpsc::SyncSender<bool>),
}

/// How many items a batch holds, and how many batches wait at most.
const BATCH: usize = 4096;
const QUEUED: usize = 2;

impl<'s, 'scope> WriterSide<'s, 'scope> {
    fn new<'env>(emit: Emit<'s>, scope: Option<&'scope std::thread::Scope<'scope, 'env>>) -> Self
    where
        's: 'scope,
    {
        let emit = Box::new(emit);
        let Some(scope) = scope else {
            return WriterSide::Here(emit);
        };
        let (jobs, queue) = std::sync::mpsc::sync_channel::<Job>(QUEUED);
        let (give_back, emptied) = std::sync::mpsc::sync_channel::<Vec<ir::Item>>(QUEUED + 1);
        // The writer side is handed over once the thread runs, so that it stays here when
        // no thread can be had.
        let (start, started) = std::sync::mpsc::sync_channel::<Box<Emit<'s>>>(1);
        let spawned = std::thread::Builder::new()
            .name("ncthread-writer".into())
            .spawn_scoped(scope, move || {
                let mut emit = *started.recv().ok()?;
                for job in queue {
                    match job {
                        Job::Items(mut items) => {
                            // Taken by reference and let go of together: items the
                            // reading thread allocated, freed one at a time between the
                            // writer's own allocations, kept the two threads waiting on
                            // the allocator's lock (iso → siemens 1.7 → 2.6 s at 20 MB).
                            items.iter().for_each(|item| emit.one(item));
                            items.clear();
                            // Dropped instead when the reading thread has enough.
                            let _ = give_back.try_send(items);
                        }
                        Job::LateFacts(facts, answer) => {
                            let _ = answer.send(emit.writer.late_facts(&facts));
                        }
                    }
                }
                Some(emit)
            });
        // No thread to be had (a process limit): the writer stays in this one.
        let Ok(done) = spawned else {
            return WriterSide::Here(emit);
        };
        match start.send(emit) {
            Ok(()) => WriterSide::Worker(Worker {
                batch: Vec::with_capacity(BATCH),
                jobs,
                emptied,
                done,
            }),
            // The thread has ended already: the writer side stays here.
            Err(std::sync::mpsc::SendError(emit)) => WriterSide::Here(emit),
        }
    }

    fn item(&mut self, item: &ir::Item) {
        match self {
            WriterSide::Here(emit) => emit.one(item),
            WriterSide::Worker(w) => w.push(item.clone()),
        }
    }

    fn take(&mut self, item: ir::Item) {
        match self {
            WriterSide::Here(emit) => emit.one_owned(item),
            WriterSide::Worker(w) => w.push(item),
        }
    }

    /// [`dialect::ItemWriter::late_facts`], once the writer has taken every item before.
    fn late_facts(&mut self, facts: &dialect::Facts) -> bool {
        match self {
            WriterSide::Here(emit) => emit.writer.late_facts(facts),
            WriterSide::Worker(w) => {
                w.flush();
                let (answer, answered) = std::sync::mpsc::sync_channel(1);
                // A writer's thread that has ended (it panicked: `finish` says so) takes
                // nothing.
                w.jobs.send(Job::LateFacts(facts.clone(), answer)).is_ok()
                    && answered.recv().unwrap_or(false)
            }
        }
    }

    /// The writer side, every item taken; `None` when its thread never got it (the
    /// conversion then reads again, the writer in the reading thread).
    fn finish(self) -> Option<Emit<'s>> {
        match self {
            WriterSide::Here(emit) => Some(*emit),
            WriterSide::Worker(mut w) => {
                w.flush();
                drop(w.jobs);
                match w.done.join() {
                    Ok(emit) => emit,
                    Err(panic) => std::panic::resume_unwind(panic),
                }
            }
        }
    }
}

impl Worker<'_, '_> {
    fn push(&mut self, item: ir::Item) {
        self.batch.push(item);
        if self.batch.len() >= BATCH {
            self.flush();
        }
    }

    fn flush(&mut self) {
        if !self.batch.is_empty() {
            let next = self
                .emptied
                .try_recv()
                .unwrap_or_else(|_| Vec::with_capacity(BATCH));
            let items = std::mem::replace(&mut self.batch, next);
            // A writer's thread that has ended takes nothing (`finish` says why).
            let _ = self.jobs.send(Job::Items(items));
        }
    }
}

/// The shared rules, the target's table and its writer, taking each item unrolled.
struct Emit<'s> {
    rules: legalise::Shared<'s>,
    table: legalise::ForTarget<'s>,
    writer: Box<dyn dialect::ItemWriter + Send + 's>,
    to: DialectId,
    /// Stops the read-back beside the writer ([`ReadBack`]) once the output is refused.
    #[cfg(unix)]
    cancel: Option<source::Following>,
}

impl<'s> Emit<'s> {
    fn new(
        src: &'s SourceFile,
        options: &'s ConvertOptions,
        target: &'static dyn dialect::Dialect,
        facts: &dialect::Facts,
        program: &Program,
        write: &dialect::WriteOptions,
    ) -> Emit<'s> {
        Emit {
            rules: legalise::Shared::new(
                src,
                Some(options.to),
                legalise::output_in_inches(program, Some(options.to)),
            ),
            table: legalise::ForTarget::new(src, target, &options.profile),
            writer: target.item_writer(facts, program, src, &options.profile, write),
            to: options.to,
            #[cfg(unix)]
            cancel: None,
        }
    }

    fn one(&mut self, item: &ir::Item) {
        self.rules.item(item);
        self.table.item(item);
        self.writer.item(item);
        self.cancel_if_refused();
    }

    /// [`Self::one`] for an item the writer may keep.
    fn one_owned(&mut self, item: ir::Item) {
        self.rules.item(&item);
        self.table.item(&item);
        self.writer.take(item);
        self.cancel_if_refused();
    }

    /// Stops the read-back beside the writer once the output is refused.
    fn cancel_if_refused(&mut self) {
        #[cfg(unix)]
        if self.cancel.is_some()
            && (self.rules.errored() || self.table.errored() || self.writer.refuses())
            && let Some(cancel) = self.cancel.take()
        {
            cancel.cancel();
        }
    }
}

impl dialect::ItemSink for Emit<'_> {
    fn item(&mut self, item: ir::Item) {
        if let Some(moves) = lower::unrolled(&item, Some(self.to)) {
            moves.for_each(|m| self.one(&m));
            return;
        }
        self.one_owned(item);
    }
}

/// A subroutine library (`Program::library`): nothing in it runs until a program calls it,
/// so there is no motion to convert. Its own dialect keeps it as it is, byte for byte; any
/// other target refuses it by name (LG005): the caller is what converts, with the library on
/// its subroutine path, and the subroutines it calls are then unrolled into its output.
fn library(
    src: &SourceFile,
    program: &Program,
    options: &ConvertOptions,
    mut diagnostics: Vec<Diagnostic>,
) -> Conversion {
    let names: Vec<&str> = program.library.iter().map(|(n, _)| n.as_str()).collect();
    let names = names.join(", ");
    if options.to == program.dialect {
        diag::sort(&mut diagnostics);
        return Conversion {
            output: Some(src.text.to_string().into()),
            diagnostics,
        };
    }
    diagnostics.push(
        Diagnostic::new(
            diag::codes::LIBRARY,
            format!(
                "{} is a subroutine library ({names}): it runs nothing until a program calls it, and a {} program cannot hold {} subroutines",
                src.name, options.to, program.dialect
            ),
        )
        .at(src, program.library[0].1)
        .label("the first definition")
        .help(format!(
            "convert the program that calls it, with this file's folder on --subroutine-path: its calls are unrolled into that output; --to {} keeps the library as it is",
            program.dialect
        )),
    );
    diag::sort(&mut diagnostics);
    Conversion {
        output: None,
        diagnostics,
    }
}

/// The first error of reading `output` back as the target dialect, as an LG004 that points
/// into the output; the output is handed back (it is not copied to be read).
fn read_back(output: source::Text, options: &ConvertOptions) -> (source::Text, Option<Diagnostic>) {
    let out = SourceFile::of_text(output_name(options), output);
    let diags = dialect::get(options.to).diagnostics(&out, &options.profile, options.unsupported);
    let refusal = refusal(diags, options);
    (out.text, refusal)
}

/// What a diagnostic of the read-back calls the output.
fn output_name(options: &ConvertOptions) -> String {
    format!("({} output)", options.to)
}

/// The read-back's first error as an LG004 refusal that points into the output.
fn refusal(diags: Vec<Diagnostic>, options: &ConvertOptions) -> Option<Diagnostic> {
    let first = diags.into_iter().find(|d| d.is_error())?;
    let mut refusal = Diagnostic::new(
        diag::codes::OUTPUT_UNREADABLE,
        format!(
            "the {} output would not read back: {} ({})",
            options.to, first.message, first.code.id
        ),
    )
    .help("nothing is written; a value rounded with --round may leave a move the control cannot make. Otherwise this is a bug in ncthread: please report it with the program");
    refusal.location = first.location;
    refusal.label = first.label;
    Some(refusal)
}

/// Every diagnostic of a program without writing it (`ncthread check`): the front end's,
/// the shared legalisation's, and the simulator's (unknown positions).
pub fn check(
    src: &SourceFile,
    from: DialectId,
    profile: &Profile,
    unsupported: Unsupported,
) -> Vec<Diagnostic> {
    // The program is not kept: the shared rules and the simulator take each item as the
    // reader lets go of it (their findings are used only if the read has no error).
    let mut checker = Checker {
        src,
        rules: legalise::Shared::new(src, None, false),
        problems: sim::Problems::new(),
        found: Default::default(),
        items: 0,
    };
    let (program, mut diagnostics) = read(
        src,
        from,
        profile,
        unsupported,
        dialect::Keep::Stream(&mut checker),
    );
    if !diag::has_errors(&diagnostics)
        && let Some(empty) = empty_read(src, checker.items, &program)
    {
        diagnostics.push(empty.as_warning());
    }
    if !diag::has_errors(&diagnostics) {
        diagnostics.extend(checker.rules.finish());
        let (mut listed, fold) = checker.found;
        listed.extend(checker.problems.finish().iter().map(|p| p.diagnostic(src)));
        diagnostics.extend(listed);
        diagnostics.extend(fold.finish());
    }
    diag::sort(&mut diagnostics);
    diagnostics
}

/// What `check` runs over each item of a streaming read: the shared rules over its moves
/// (a cycle unrolled, as for any target) and the simulator over the item.
struct Checker<'s> {
    src: &'s SourceFile,
    rules: legalise::Shared<'s>,
    problems: sim::Problems,
    /// The simulator's findings so far as diagnostics: those listed, and the fold that
    /// counts the repeats (a program that makes the same one on every pass).
    found: (Vec<Diagnostic>, diag::Fold),
    items: usize,
}

impl dialect::ItemSink for Checker<'_> {
    fn item(&mut self, item: ir::Item) {
        self.items += 1;
        self.problems.item(&item);
        let (listed, fold) = &mut self.found;
        for p in self.problems.take() {
            let d = p.diagnostic(self.src);
            if fold.admit(&d) {
                listed.push(d);
            }
        }
        match lower::unrolled(&item, None) {
            Some(moves) => moves.for_each(|m| self.rules.item(&m)),
            None => self.rules.item(&item),
        }
    }
}

/// What `verify` found.
#[derive(Clone, Debug)]
pub enum Outcome {
    /// The normalised motions agree; `segments` were compared, and they differ by at most
    /// `deviation` (positions, and the drift of each thread's helix over its move).
    Equivalent {
        segments: usize,
        deviation: fixed::Length,
        /// The position tolerance they were compared with.
        tolerance: fixed::Length,
    },
    /// The first place where they differ.
    Different(Box<sim::Difference>),
    /// A program could not be read or converted (the diagnostics say why).
    Refused,
}

/// The result of [`verify`]: the outcome, every diagnostic, and the two motions compared.
#[derive(Clone, Debug)]
pub struct Verification {
    pub outcome: Outcome,
    pub diagnostics: Vec<Diagnostic>,
    /// The source's normalised motion and the other program's.
    pub left: Vec<sim::Segment>,
    pub right: Vec<sim::Segment>,
    /// The same motions as simulated, before normalising: what `verify --plot` draws
    /// (normalising merges consecutive rapids into one straight move, which is not the path
    /// the machine takes).
    pub left_moves: Vec<sim::Segment>,
    pub right_moves: Vec<sim::Segment>,
    /// The second judge's findings (`verify --rs274`): LinuxCNC's own run of each ISO
    /// program held against ncthread's simulation of the other side.
    pub oracle: Vec<OracleCheck>,
}

/// One comparison by LinuxCNC's interpreter.
#[derive(Clone, Debug)]
pub struct OracleCheck {
    /// What was compared, for people: `LinuxCNC's run of the ISO output vs the source`.
    pub what: String,
    pub outcome: OracleOutcome,
}

#[derive(Clone, Debug)]
pub enum OracleOutcome {
    /// `partial`: compared only up to where ncthread stops knowing the position.
    Equivalent {
        segments: usize,
        deviation: fixed::Length,
        partial: bool,
    },
    Different(Box<sim::Difference>),
    /// rs274 refused the program, could not be run, or crashed on every try
    /// ([`sim::rs274::RunError::is_crash`]).
    Failed(sim::rs274::RunError),
    /// The comparison cannot decide (why).
    CannotJudge(String),
}

/// Runs `program` (ISO text) through LinuxCNC's interpreter and compares its motion with
/// `expected` (a normalised simulation).
fn oracle_check(
    interpreter: &sim::rs274::Interpreter,
    what: String,
    program: &str,
    settings: &sim::rs274::Settings,
    turret: bool,
    expected: &[sim::Segment],
) -> OracleCheck {
    let outcome = match interpreter.run_with(program, settings) {
        Err(e) => OracleOutcome::Failed(e),
        Ok(mut canon) => match sim::rs274::judge(expected, {
            // A turret that indexes on T (`[iso] tool_change = "t"`) changes the tool where
            // LinuxCNC only selects it.
            if turret {
                for c in &mut canon {
                    if let sim::rs274::Canon::SelectTool(t) = *c {
                        *c = sim::rs274::Canon::ChangeTool(t);
                    }
                }
            }
            &canon
        }) {
            sim::rs274::Judgement::Agrees {
                segments,
                deviation,
                partial,
            } => OracleOutcome::Equivalent {
                segments,
                deviation,
                partial,
            },
            sim::rs274::Judgement::Differs(d) => OracleOutcome::Different(d),
            sim::rs274::Judgement::CannotJudge(why) => OracleOutcome::CannotJudge(why),
        },
    };
    OracleCheck { what, outcome }
}

/// Proves a conversion: simulates `src` (dialect `options.from`) and the program in
/// `options.to` — `against` when given (a hand conversion), else ncthread's own conversion
/// read back — and compares the normalised motions.
///
/// With `rs274` (LinuxCNC's interpreter), each ISO program on either side is also run by
/// LinuxCNC and its motion compared with ncthread's simulation of the other side: a judge
/// that shares no code with ncthread's readers.
pub fn verify(
    src: &SourceFile,
    options: &ConvertOptions,
    against: Option<&SourceFile>,
    rs274: Option<&sim::rs274::Interpreter>,
) -> Verification {
    verify_within(src, options, against, rs274, sim::TOLERANCE)
}

/// [`verify`] with positions allowed to differ by `tolerance` (at least
/// [`sim::TOLERANCE`]); a conversion made with `--round` is allowed the deviation its
/// rounding reported, when that is larger.
pub fn verify_within(
    src: &SourceFile,
    options: &ConvertOptions,
    against: Option<&SourceFile>,
    rs274: Option<&sim::rs274::Interpreter>,
    tolerance: fixed::Length,
) -> Verification {
    let (program, mut diagnostics) =
        parse(src, options.from, &options.profile, options.unsupported);
    if diag::has_errors(&diagnostics) {
        return refused(diagnostics);
    }
    let converted;
    let other = match against {
        Some(other) => other,
        None => {
            let (output, more) = emit(&program, src, options);
            diagnostics.extend(more);
            let Some(output) = output else {
                return refused(diagnostics);
            };
            converted = SourceFile::new(
                format!("{} (converted to {})", src.name, options.to),
                output,
            );
            &converted
        }
    };
    let (other_program, more) = parse(other, options.to, &options.profile, options.unsupported);
    let other_failed = diag::has_errors(&more);
    diagnostics.extend(more);
    if other_failed {
        return refused(diagnostics);
    }
    let left = sim::simulate(&program);
    let right = sim::simulate(&other_program);
    // Where ncthread does not know a position, LinuxCNC does (it starts at X0 Z0): there
    // its run cannot judge ncthread's simulation.
    // The judge compares up to the first position ncthread does not know; a program it
    // knows no position of cannot be judged.
    let unknown = |s: &sim::Simulation| {
        let segments = sim::normalise(&s.segments);
        sim::rs274::known_prefix(&segments) == 0 && !segments.is_empty()
    };
    let (left_unknown, right_unknown) = (unknown(&left), unknown(&right));
    diagnostics.extend(left.problems.iter().map(|p| p.diagnostic(src)));
    diagnostics.extend(right.problems.iter().map(|p| p.diagnostic(other)));
    diag::sort(&mut diagnostics);
    let (left_moves, right_moves) = (left.segments, right.segments);
    let left = sim::normalise(&left_moves);
    let right = sim::normalise(&right_moves);
    let outcome = compare_sides(&left, &right, tolerance, &diagnostics);
    let oracle = match rs274 {
        Some(interpreter) => oracle_checks(
            interpreter,
            options,
            &Side {
                program: src,
                segments: &left,
                unknown: left_unknown,
            },
            &Side {
                program: other,
                segments: &right,
                unknown: right_unknown,
            },
        ),
        None => Vec::new(),
    };
    Verification {
        outcome,
        diagnostics,
        left,
        right,
        left_moves,
        right_moves,
        oracle,
    }
}

/// A verification that stopped at a program that could not be read or converted.
fn refused(mut diagnostics: Vec<Diagnostic>) -> Verification {
    diag::sort(&mut diagnostics);
    Verification {
        outcome: Outcome::Refused,
        diagnostics,
        left: Vec::new(),
        right: Vec::new(),
        left_moves: Vec::new(),
        right_moves: Vec::new(),
        oracle: Vec::new(),
    }
}

/// Compares the two normalised motions. The rounding a `--round` conversion reported (in
/// `diagnostics`: half a step of the target's grid, or a lead's drift over its thread) is
/// allowed, to positions and to a helix's place along Z, and the tolerance asked for.
fn compare_sides(
    left: &[sim::Segment],
    right: &[sim::Segment],
    tolerance: fixed::Length,
    diagnostics: &[Diagnostic],
) -> Outcome {
    let rounded = diagnostics
        .iter()
        .filter_map(|d| d.deviation)
        .max()
        .unwrap_or(fixed::Length::ZERO);
    let tolerance = tolerance.max(sim::TOLERANCE).max(rounded);
    match sim::compare_rounded(left, right, tolerance, rounded) {
        None => Outcome::Equivalent {
            segments: left.len(),
            deviation: sim::largest_deviation(left, right),
            tolerance,
        },
        Some(d) => Outcome::Different(Box::new(d)),
    }
}

/// One side of a verification, as the second judge sees it.
struct Side<'a> {
    program: &'a SourceFile,
    /// ncthread's normalised motion of it.
    segments: &'a [sim::Segment],
    /// ncthread knows no position of it: the judge cannot compare.
    unknown: bool,
}

/// The second judge (`verify --rs274`): LinuxCNC's own run of each program it reads held
/// against ncthread's simulation of the other side.
fn oracle_checks(
    interpreter: &sim::rs274::Interpreter,
    options: &ConvertOptions,
    source: &Side,
    other: &Side,
) -> Vec<OracleCheck> {
    // The block delete switch is the machine's: both runs use it.
    let settings = sim::rs274::Settings {
        block_delete: options.profile.iso.block_delete == Some(profile::BlockDelete::On),
        subroutine_path: options.profile.iso.subroutine_path.clone(),
    };
    let turret = options.profile.iso.tool_change == profile::ToolChange::T;
    let judge = |program: &SourceFile, model: &Side| {
        let what = format!(
            "LinuxCNC's run of {} vs ncthread's simulation of {}",
            program.name, model.program.name
        );
        if model.unknown {
            OracleCheck {
                what,
                outcome: OracleOutcome::CannotJudge(
                    "ncthread's simulation has positions it does not know (SIM001), which LinuxCNC's has".into(),
                ),
            }
        } else {
            oracle_check(
                interpreter,
                what,
                &program.text,
                &settings,
                turret,
                model.segments,
            )
        }
    };
    let mut oracle = Vec::new();
    if dialect::get(options.to).linuxcnc_reads() {
        oracle.push(judge(other.program, source));
    }
    if dialect::get(options.from).linuxcnc_reads() {
        oracle.push(judge(source.program, other));
    }
    oracle
}

#[cfg(test)]
mod tests {
    use super::*;

    fn options(to: DialectId) -> ConvertOptions {
        ConvertOptions::new(dialect::iso::ID, to)
    }

    #[test]
    fn an_output_the_target_refuses_is_not_written() {
        // A G33 block without Z travel, as a writer could have rounded it.
        let text = "N10 S500 M03\nN20 G00 X20. Z0.\nN30 G33 Z0. F1.\nN40 M02\n";
        let (back, refusal) = read_back(text.into(), &options(dialect::czech::ID));
        assert_eq!(back, text, "the output is handed back as it was");
        let refusal = refusal.expect("refused");
        assert_eq!(refusal.code, diag::codes::OUTPUT_UNREADABLE);
        assert!(refusal.message.contains("CZR017"), "{}", refusal.message);
        let at = refusal.location.expect("located");
        assert_eq!((at.file.as_str(), at.line), ("(czech output)", 3));
        let text = "N10 S500 M03\nN20 M02\n";
        assert!(
            read_back(text.into(), &options(dialect::czech::ID))
                .1
                .is_none()
        );
    }

    /// A library whose first line is its first definition (no comment, no `%`): iso → iso
    /// keeps it as it is (it was INP001 "holds no program"); another target refuses it by
    /// name at that line.
    #[test]
    fn a_subroutine_library_is_kept_or_refused_by_name() {
        let text = "o<x> sub\n  G1 X#1 F0.1\no<x> endsub\n\no<y> sub\n  G0 Z#1\no<y> endsub\n";
        let src = SourceFile::new("lib.ngc", text.to_string());
        let kept = convert(&src, &options(dialect::iso::ID));
        assert_eq!(kept.output.as_deref(), Some(text), "{:?}", kept.diagnostics);
        assert!(kept.diagnostics.is_empty(), "{:?}", kept.diagnostics);
        for to in [dialect::fanuc::ID, dialect::czech::ID, dialect::nc31::ID] {
            let refused = convert(&src, &options(to));
            assert!(refused.output.is_none());
            let first = &refused.diagnostics[0];
            assert_eq!(first.code.id, "LG005", "{first:?}");
            assert!(first.message.contains("o<x>, o<y>"), "{}", first.message);
            assert_eq!(first.location.as_ref().map(|l| l.line), Some(1));
        }
        // A program that defines a subroutine and calls it is no library.
        let program = format!("{text}G7 G18 G21 G95\no<y> call [5]\nM2\n");
        let src = SourceFile::new("p.ngc", program);
        let c = convert(&src, &options(dialect::fanuc::ID));
        assert!(c.diagnostics.iter().all(|d| d.code.id != "LG005"));
    }
}

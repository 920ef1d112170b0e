//! Converting a whole tree of programs (`ncthread batch`).
//!
//! The source tree is walked ([`crate::files::walk`]: hidden entries and what
//! `.ncthreadignore` names left out, program files chosen by extension or `--glob`), each
//! program is converted on its own, in parallel, with its own profile
//! ([`crate::files::discover_profile`]), and its output is written into the mirrored place of
//! the output tree with the target's extension. A bad file is reported and the rest go on. An
//! output is written to a temporary file beside it and renamed into place, so a reader never
//! sees half a program; an existing output is kept unless `force`. Nothing is ever written
//! inside the source tree. An interrupt stops the workers between files.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use rayon::prelude::*;
use serde_json::json;

use crate::diag::Diagnostic;
use crate::dialect::{self, DialectId};
use crate::files::{self, Selection, Verdict};
use crate::profile::Profile;
use crate::source::SourceFile;
use crate::text::{self, OutputOptions, TextEncoding};
use crate::{ConvertOptions, convert};

/// Which profile the programs use.
#[derive(Clone, Debug)]
pub enum ProfileChoice {
    /// The one the command line names, for every program.
    Given(PathBuf, Box<Profile>),
    /// Each program's own: a sidecar, or the nearest `ncthread.toml` (else the built-in
    /// defaults).
    Discover,
    /// The built-in defaults for every program (`--no-profile`).
    Defaults,
}

/// What a batch run does.
#[derive(Clone, Debug)]
pub struct BatchOptions {
    pub src_dir: PathBuf,
    pub out_dir: PathBuf,
    /// The source dialect, or `None` to choose it per file from the text.
    pub from: Option<DialectId>,
    /// The conversion (its `from` and `profile` are set per file).
    pub conversion: ConvertOptions,
    pub profile: ProfileChoice,
    /// What the command line says on top of every profile.
    pub overrides: crate::profile::Overrides,
    /// Worker threads; 0 lets rayon choose (one per core).
    pub jobs: usize,
    /// Overwrite existing outputs.
    pub force: bool,
    /// Convert, but write nothing: say what would be written.
    pub dry_run: bool,
    /// The outputs' extension, without the dot.
    pub extension: String,
    /// Which files of the tree are programs.
    pub selection: Selection,
    /// The input encoding, or `None` for UTF-8 when valid, else the dialect's legacy one.
    pub input_encoding: Option<TextEncoding>,
    pub output: OutputOptions,
    /// Write a static HTML report into this folder: `index.html` and the plots.
    pub html: Option<PathBuf>,
}

/// The default extension of a target's files.
pub fn default_extension(to: DialectId) -> &'static str {
    dialect::get(to).extension()
}

/// The extensions of the program files of `from` (every dialect's for `auto`).
pub fn program_extensions(from: Option<DialectId>) -> Vec<&'static str> {
    let mut all: Vec<&'static str> = match from {
        Some(d) => dialect::get(d).extensions().to_vec(),
        None => dialect::ALL
            .iter()
            .flat_map(|d| d.extensions())
            .copied()
            .collect(),
    };
    all.sort_unstable();
    all.dedup();
    all
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Status {
    Converted,
    /// The program has errors, or it could not be read or written.
    Failed,
    /// The output exists and `force` was not given.
    Skipped,
    /// Not a program (its name or its bytes say so): left out, with the reason.
    LeftOut,
    /// The run was interrupted before the file's turn.
    NotDone,
}

impl Status {
    pub fn name(self) -> &'static str {
        match self {
            Status::Converted => "converted",
            Status::Failed => "failed",
            Status::Skipped => "skipped",
            Status::LeftOut => "left out",
            Status::NotDone => "not done",
        }
    }
}

/// What happened to one input.
#[derive(Clone, Debug)]
pub struct FileReport {
    /// The input, as `src_dir` joined with its path below it.
    pub input: PathBuf,
    pub status: Status,
    /// Where the output goes (whether or not it was written: see [`FileReport::written`]).
    pub output: PathBuf,
    /// The dialect the file was read as.
    pub dialect: Option<DialectId>,
    /// The encoding the file was read in, and the one its output was written in.
    pub encoding: Option<TextEncoding>,
    pub output_encoding: Option<TextEncoding>,
    /// The profile used (`None`: the built-in defaults).
    pub profile: Option<PathBuf>,
    /// How `--from auto` chose the dialect when the text did not say it for certain.
    pub dialect_note: Option<String>,
    pub diagnostics: Vec<Diagnostic>,
    /// Why the file failed or was skipped when it is not a diagnostic (I/O, an existing output).
    pub reason: Option<String>,
    /// With an HTML report: the converted program's `explain` text and its plot's file
    /// (relative to the report's folder).
    pub explained: Option<(String, Option<PathBuf>)>,
}

impl FileReport {
    fn new(input: PathBuf, output: PathBuf, status: Status) -> FileReport {
        FileReport {
            input,
            status,
            output,
            dialect: None,
            encoding: None,
            output_encoding: None,
            profile: None,
            dialect_note: None,
            diagnostics: Vec::new(),
            reason: None,
            explained: None,
        }
    }

    /// The output, when there is one: written by this run (not `dry_run`), or kept from
    /// before (skipped because it exists). A file that failed or was left out has none.
    pub fn written(&self, dry_run: bool) -> Option<&Path> {
        match self.status {
            Status::Converted if !dry_run => Some(&self.output),
            Status::Skipped => Some(&self.output),
            _ => None,
        }
    }

    /// The profile used, for people.
    pub fn profile_name(&self) -> String {
        self.profile
            .as_ref()
            .map_or("built-in defaults".into(), |p| p.display().to_string())
    }

    /// The report's object of this file: `output` only when there is one
    /// ([`FileReport::written`]); under `--dry-run`, `would_write` where it would be.
    pub fn to_json(&self, dry_run: bool) -> serde_json::Value {
        let would_write = (dry_run && self.status == Status::Converted)
            .then(|| self.output.display().to_string());
        json!({
            "path": self.input.display().to_string(),
            "status": self.status.name(),
            "output": self.written(dry_run).map(|p| p.display().to_string()),
            "would_write": would_write,
            "dialect": self.dialect.map(|d| d.to_string()),
            "encoding": self.encoding.map(|e| e.name()),
            "output_encoding": self.output_encoding.map(|e| e.name()),
            "profile": self.profile.as_ref().map(|p| p.display().to_string()),
            "dialect_note": self.dialect_note,
            "reason": self.reason,
            "diagnostics": self.diagnostics.iter().map(|d| {
                let loc = d.location.as_ref();
                json!({
                    "code": d.code.id,
                    "severity": d.severity,
                    "line": loc.map(|l| l.line),
                    "column": loc.map(|l| l.column),
                    "message": d.message,
                })
            }).collect::<Vec<_>>(),
        })
    }
}

/// Every file's report, in the order of the walk.
#[derive(Clone, Debug)]
pub struct BatchReport {
    pub files: Vec<FileReport>,
    pub elapsed: Duration,
    /// Nothing was written (`--dry-run`).
    pub dry_run: bool,
    /// The run was interrupted.
    pub interrupted: bool,
    /// Why the run stopped before its end: a write that no later write would survive (a
    /// full disk), in [`files::io_error`]'s words.
    pub fatal: Option<String>,
}

impl BatchReport {
    pub fn count(&self, status: Status) -> usize {
        self.files.iter().filter(|f| f.status == status).count()
    }

    /// The files this run converted whose conversion has warnings (values rounded, blocks
    /// written as comments, an encoding guessed…).
    pub fn with_warnings(&self) -> usize {
        self.files
            .iter()
            .filter(|f| f.status == Status::Converted && !f.diagnostics.is_empty())
            .count()
    }

    /// The codes of the diagnostics of the files this run read (converted or failed), each
    /// with the number of files it appears in: the commonest first, then by code.
    pub fn codes(&self) -> Vec<(&'static str, usize)> {
        let mut files: HashMap<&'static str, usize> = HashMap::new();
        for f in &self.files {
            if !matches!(f.status, Status::Converted | Status::Failed) {
                continue;
            }
            let mut codes: Vec<&'static str> = f.diagnostics.iter().map(|d| d.code.id).collect();
            codes.sort_unstable();
            codes.dedup();
            for code in codes {
                *files.entry(code).or_default() += 1;
            }
        }
        let mut codes: Vec<(&'static str, usize)> = files.into_iter().collect();
        codes.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(b.0)));
        codes
    }

    /// `commonest codes: NCW005 in 10 files, NCW007 in 4 files, CZR001 in 1 file`: the five
    /// commonest ([`BatchReport::codes`]), or `None` when no file has a diagnostic.
    pub fn codes_summary(&self) -> Option<String> {
        let codes = self.codes();
        if codes.is_empty() {
            return None;
        }
        let each: Vec<String> = codes
            .iter()
            .take(5)
            .map(|(code, n)| format!("{code} in {n} file{}", if *n == 1 { "" } else { "s" }))
            .collect();
        Some(format!(
            "commonest codes: {}{}",
            each.join(", "),
            if codes.len() > 5 { ", …" } else { "" }
        ))
    }

    /// `converted 151 (12 with warnings), failed 3, skipped 2 (exist; --force to overwrite),
    /// left out 4 (not programs) in 0.4 s`
    pub fn summary(&self) -> String {
        let warned = self.with_warnings();
        let mut text = format!(
            "{} {}{}, failed {}",
            if self.dry_run {
                "would convert"
            } else {
                "converted"
            },
            self.count(Status::Converted),
            if warned > 0 {
                format!(" ({warned} with warnings)")
            } else {
                String::new()
            },
            self.count(Status::Failed),
        );
        let skipped = self.count(Status::Skipped);
        if skipped > 0 {
            text.push_str(&format!(
                ", skipped {skipped} (exist; --force to overwrite)"
            ));
        } else {
            text.push_str(", skipped 0");
        }
        let left = self.count(Status::LeftOut);
        if left > 0 {
            text.push_str(&format!(", left out {left} (not programs)"));
        }
        let not_done = self.count(Status::NotDone);
        if self.interrupted {
            text.push_str(&format!(", interrupted: {not_done} not done"));
        } else if self.fatal.is_some() {
            text.push_str(&format!(", stopped: {not_done} not done"));
        }
        text.push_str(&format!(" in {:.1} s", self.elapsed.as_secs_f64()));
        text
    }

    /// Whether the run succeeded: nothing failed and nothing was left undone (skipped
    /// outputs and files that are not programs are no failure).
    pub fn succeeded(&self) -> bool {
        !self.interrupted && self.fatal.is_none() && self.count(Status::Failed) == 0
    }

    pub fn to_json(&self, options: &BatchOptions) -> serde_json::Value {
        json!({
            "source": options.src_dir.display().to_string(),
            "output": options.out_dir.display().to_string(),
            "from": options.from.map_or("auto".to_string(), |d| d.to_string()),
            "to": options.conversion.to.to_string(),
            "dry_run": self.dry_run,
            "interrupted": self.interrupted,
            "stopped": self.fatal,
            "converted": self.count(Status::Converted),
            "with_warnings": self.with_warnings(),
            "failed": self.count(Status::Failed),
            "skipped": self.count(Status::Skipped),
            "left_out": self.count(Status::LeftOut),
            "not_done": self.count(Status::NotDone),
            "seconds": self.elapsed.as_secs_f64(),
            "codes": self
                .codes()
                .into_iter()
                .map(|(code, n)| (code.to_string(), json!(n)))
                .collect::<serde_json::Map<String, serde_json::Value>>(),
            "files": self.files.iter().map(|f| f.to_json(self.dry_run)).collect::<Vec<_>>(),
        })
    }
}

/// What a run will do, decided before any work: the files, each program's profile, and the
/// trees checked.
#[derive(Clone, Debug)]
pub struct Plan {
    src_root: PathBuf,
    walk: files::Walk,
    /// Per file of the walk: the profile's path (`None`: the built-in defaults).
    profiles: Vec<Option<PathBuf>>,
    /// Each profile read once: its path → the profile, or why it cannot be used.
    loaded: HashMap<PathBuf, Result<Profile, String>>,
}

impl Plan {
    /// The programs the run will convert.
    pub fn programs(&self) -> usize {
        self.walk.programs().count()
    }

    /// The positive globs that matched no file.
    pub fn unmatched_globs(&self) -> &[String] {
        &self.walk.unmatched
    }
}

/// Walks the source tree and finds each program's profile; checks that the output tree is
/// outside it and can be written. `Err` is a usage or I/O problem with the trees themselves.
pub fn plan(options: &BatchOptions) -> Result<Plan, String> {
    let src_root = std::fs::canonicalize(&options.src_dir)
        .map_err(|e| files::io_error("read", options.src_dir.display(), &e))?;
    if !src_root.is_dir() {
        return Err(format!("{} is not a folder", options.src_dir.display()));
    }
    let inside = |dir: &Path, what: &str| -> Result<(), String> {
        let resolved =
            files::resolve(dir).map_err(|e| files::io_error("read", dir.display(), &e))?;
        if resolved.starts_with(&src_root) {
            return Err(format!(
                "the {what} {} is inside the source folder {}; ncthread never writes into the source tree",
                dir.display(),
                options.src_dir.display()
            ));
        }
        Ok(())
    };
    inside(&options.out_dir, "output folder")?;
    let out_root = files::resolve(&options.out_dir)
        .map_err(|e| files::io_error("read", options.out_dir.display(), &e))?;
    if src_root.starts_with(&out_root) {
        return Err(format!(
            "the output folder {} holds the source folder {}: outputs could land in the source tree",
            options.out_dir.display(),
            options.src_dir.display()
        ));
    }
    if let Some(dir) = &options.html {
        inside(dir, "report folder")?;
    }
    let walk = files::walk(&options.src_dir, &options.selection)?;
    let mut loaded = HashMap::new();
    let profiles: Vec<Option<PathBuf>> = walk
        .files
        .iter()
        .map(|f| match &options.profile {
            ProfileChoice::Given(path, _) => Some(path.clone()),
            ProfileChoice::Defaults => None,
            ProfileChoice::Discover if f.verdict == Verdict::Program => {
                files::discover_profile(&options.src_dir.join(&f.rel))
            }
            ProfileChoice::Discover => None,
        })
        .collect();
    for path in profiles.iter().flatten() {
        if loaded.contains_key(path) {
            continue;
        }
        let profile = match &options.profile {
            ProfileChoice::Given(_, p) => Ok((**p).clone()),
            _ => read_profile(path).map(|mut p| {
                options.overrides.apply(&mut p);
                p
            }),
        };
        loaded.insert(path.clone(), profile);
    }
    Ok(Plan {
        src_root,
        walk,
        profiles,
        loaded,
    })
}

/// Reads a discovered profile; its errors become one reason.
fn read_profile(path: &Path) -> Result<Profile, String> {
    Profile::load(path).map_err(|e| e.summary(path))
}

/// How an output is written: [`files::write_atomically`]'s arguments and result (path,
/// bytes, force, the source tree's guard).
pub type Writer<'a> =
    dyn Fn(&Path, &[u8], bool, Option<&Path>) -> Result<(), files::WriteError> + Sync + 'a;

/// Runs a batch as planned. `progress` is called once per file as it finishes (from worker
/// threads); `stop` ends the run between files (an interrupt). A write that no later write
/// would survive (a full disk: [`files::WriteError::Fatal`]) stops the run too, and the
/// report says why. `Err` is a usage or I/O problem with the trees themselves (nothing was
/// converted).
pub fn run(
    options: &BatchOptions,
    plan: &Plan,
    progress: &(dyn Fn(&FileReport) + Sync),
    stop: &AtomicBool,
) -> Result<BatchReport, String> {
    run_with(options, plan, progress, stop, &files::write_atomically)
}

/// [`run`], writing each output with `write` (the tests' seam for a disk that fills up).
pub fn run_with(
    options: &BatchOptions,
    plan: &Plan,
    progress: &(dyn Fn(&FileReport) + Sync),
    stop: &AtomicBool,
    write: &Writer<'_>,
) -> Result<BatchReport, String> {
    let started = Instant::now();
    // The first write that stops every write, and the flag the workers read.
    let fatal: std::sync::Mutex<Option<String>> = Default::default();
    let halted = AtomicBool::new(false);
    if !options.dry_run {
        std::fs::create_dir_all(&options.out_dir)
            .map_err(|e| files::io_error("create", options.out_dir.display(), &e))?;
        // A folder that cannot be written is the user's problem, named as they wrote it.
        tempfile::Builder::new()
            .prefix(".ncthread-")
            .tempfile_in(&options.out_dir)
            .map_err(|e| files::io_error("write into", options.out_dir.display(), &e))?;
        if let Some(dir) = &options.html {
            std::fs::create_dir_all(dir.join("plots"))
                .map_err(|e| files::io_error("create", dir.display(), &e))?;
        }
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(options.jobs)
        .build()
        .map_err(|e| format!("cannot start the worker threads: {e}"))?;
    // Two inputs that differ only in their extension would write one output; two whose
    // outputs differ only in case would on a case-insensitive file system (Windows, macOS,
    // the FAT of a USB stick that takes the programs to the machine).
    let mut first_of: HashMap<String, &Path> = Default::default();
    let clashes: Vec<Option<Clash>> = plan
        .walk
        .files
        .iter()
        .map(|f| {
            if f.verdict != Verdict::Program {
                return None;
            }
            let out = f.rel.with_extension(&options.extension);
            let key = out.to_string_lossy().to_lowercase();
            match first_of.get(&key) {
                Some(first) if first.with_extension(&options.extension) == out => {
                    Some(Clash::Same(first))
                }
                Some(first) => Some(Clash::Case(first)),
                None => {
                    first_of.insert(key, &f.rel);
                    None
                }
            }
        })
        .collect();
    let files = pool.install(|| {
        plan.walk
            .files
            .par_iter()
            .zip(clashes.par_iter())
            .zip(plan.profiles.par_iter())
            .map(|((found, clash), profile)| {
                let input = options.src_dir.join(&found.rel);
                let output = output_path(options, &found.rel);
                let report = match &found.verdict {
                    Verdict::Skip(why) => {
                        let mut r = FileReport::new(input, output, Status::LeftOut);
                        r.reason = Some(why.clone());
                        r
                    }
                    Verdict::Program if stop.load(Ordering::Relaxed) => {
                        let mut r = FileReport::new(input, output, Status::NotDone);
                        r.reason = Some("interrupted before its turn".into());
                        r
                    }
                    Verdict::Program if halted.load(Ordering::Relaxed) => {
                        let mut r = FileReport::new(input, output, Status::NotDone);
                        r.reason = Some("the run stopped before its turn".into());
                        r
                    }
                    Verdict::Program => {
                        let profile = profile
                            .as_ref()
                            .map(|p| (p.clone(), plan.loaded.get(p).cloned()));
                        let (report, stops) =
                            one(options, plan, &found.rel, *clash, profile, write);
                        if let Some(why) = stops {
                            halted.store(true, Ordering::Relaxed);
                            if let Ok(mut first) = fatal.lock() {
                                first.get_or_insert(why);
                            }
                        }
                        report
                    }
                };
                progress(&report);
                report
            })
            .collect::<Vec<_>>()
    });
    Ok(BatchReport {
        files,
        elapsed: started.elapsed(),
        dry_run: options.dry_run,
        interrupted: stop.load(Ordering::Relaxed),
        fatal: fatal.into_inner().unwrap_or_else(|e| e.into_inner()),
    })
}

/// An input whose output would land on an earlier input's.
#[derive(Clone, Copy, Debug)]
enum Clash<'a> {
    /// The same output (the names differ only in their extension).
    Same(&'a Path),
    /// Outputs whose names differ only in case.
    Case(&'a Path),
}

/// Why an output that exists is not written.
const OUTPUT_EXISTS: &str = "the output exists (--force overwrites it)";

/// Where the output of the program at `rel` (below the source folder) goes.
fn output_path(options: &BatchOptions, rel: &Path) -> PathBuf {
    options.out_dir.join(rel).with_extension(&options.extension)
}

/// Converts one program with its profile (`None`: the built-in defaults; else its path and
/// the profile read, or why it could not be), and writes its output with `write`. Also
/// returns why the run must stop when the write failed so that no later one would succeed.
fn one(
    options: &BatchOptions,
    plan: &Plan,
    rel: &Path,
    clash: Option<Clash>,
    profile: Option<(PathBuf, Option<Result<Profile, String>>)>,
    write: &Writer<'_>,
) -> (FileReport, Option<String>) {
    let (mut report, bytes) = convert_one(options, rel, clash, profile);
    let Some(bytes) = bytes else {
        return (report, None);
    };
    match write(&report.output, &bytes, options.force, Some(&plan.src_root)) {
        Ok(()) => report.status = Status::Converted,
        Err(files::WriteError::Exists) => {
            report.status = Status::Skipped;
            report.reason = Some(OUTPUT_EXISTS.into());
        }
        Err(files::WriteError::Failed(e)) => report.reason = Some(e),
        Err(files::WriteError::Fatal(e)) => {
            report.reason = Some(e.clone());
            return (report, Some(e));
        }
    }
    (report, None)
}

/// Converts one program: its report and the output's bytes to write, or no bytes when the
/// report is final (failed, skipped, or converted under `--dry-run`).
fn convert_one(
    options: &BatchOptions,
    rel: &Path,
    clash: Option<Clash>,
    profile: Option<(PathBuf, Option<Result<Profile, String>>)>,
) -> (FileReport, Option<Vec<u8>>) {
    let input = options.src_dir.join(rel);
    let output = output_path(options, rel);
    let mut report = FileReport::new(input.clone(), output.clone(), Status::Failed);
    match clash {
        Some(Clash::Same(first)) => {
            report.reason = Some(format!(
                "{} is written to the same output; give the files different names",
                options.src_dir.join(first).display()
            ));
            return (report, None);
        }
        Some(Clash::Case(first)) => {
            report.reason = Some(format!(
                "its output {} and the output {} of {} differ only in case: on a case-insensitive file system (Windows, macOS, a USB stick) one would replace the other; rename one of the programs",
                output.display(),
                output_path(options, first).display(),
                options.src_dir.join(first).display()
            ));
            return (report, None);
        }
        None => {}
    }
    let defaults = || {
        let mut p = Profile::default();
        options.overrides.apply(&mut p);
        p
    };
    let profile = match profile {
        None => defaults(),
        Some((path, found)) => {
            report.profile = Some(path);
            match found {
                Some(Ok(p)) => p,
                Some(Err(why)) => {
                    report.reason = Some(why);
                    return (report, None);
                }
                None => defaults(),
            }
        }
    };
    if !options.force && output.exists() {
        report.status = Status::Skipped;
        report.reason = Some(OUTPUT_EXISTS.into());
        return (report, None);
    }
    let bytes = match std::fs::read(&input) {
        Ok(b) => b,
        Err(e) => {
            report.reason = Some(files::io_error("read", input.display(), &e));
            return (report, None);
        }
    };
    let decoded = text::decode_program(&bytes, options.from, options.input_encoding, Some(rel));
    report.dialect_note = decoded.detection.as_ref().filter(|d| !d.certain).map(|d| {
        format!(
            "--from auto: read as {} ({}); give --from to be sure",
            d.dialect, d.reason
        )
    });
    let note = decoded.encoding_diagnostic(&input.display().to_string());
    let text::Decoded {
        text,
        encoding,
        dialect: from,
        eof_mark,
        ..
    } = decoded;
    report.dialect = Some(from);
    report.encoding = Some(encoding);
    if let Some(d) = note {
        let refused = d.is_error();
        report.diagnostics.push(d);
        if refused {
            return (report, None);
        }
    }
    let kept = text::Input::of(&text, encoding, &eof_mark, from == options.conversion.to);
    let src = SourceFile::new(input.display().to_string(), text);
    let conversion = ConvertOptions {
        from,
        profile,
        ..options.conversion.clone()
    };
    let converted = convert(&src, &conversion);
    report.diagnostics.extend(converted.diagnostics);
    let Some(program) = converted.output else {
        return (report, None);
    };
    report.output_encoding = Some(options.output.encoding_for(&kept));
    let bytes = match text::encode_output(
        &program,
        &output.display().to_string(),
        &options.output,
        &kept,
    ) {
        Ok(b) => b,
        Err(d) => {
            report.diagnostics.push(*d);
            return (report, None);
        }
    };
    if let Some(dir) = options.html.as_ref().filter(|_| !options.dry_run) {
        report.explained = Some(explain_output(&program, &conversion, rel, dir));
    }
    if options.dry_run {
        report.status = Status::Converted;
        return (report, None);
    }
    (report, Some(bytes))
}

/// The converted program as the target reads it: its `explain` text, and its plot written
/// into the report's `plots/` folder (`None` when it could not be written).
fn explain_output(
    program: &str,
    conversion: &ConvertOptions,
    rel: &Path,
    dir: &Path,
) -> (String, Option<PathBuf>) {
    let name = rel.display().to_string();
    let src = SourceFile::new(name.clone(), program);
    let (ir, _) = crate::parse(
        &src,
        conversion.to,
        &conversion.profile,
        conversion.unsupported,
    );
    let ops = crate::explain::explain(&ir, &Default::default());
    let table = crate::explain::to_text(&ops, crate::explain::Table::Box);
    let operation = crate::explain::default_operation(&ops);
    let svg = crate::plot::plot(
        &format!("{name} ({})", conversion.to),
        &crate::sim::simulate(&ir).segments,
        operation,
    );
    let plot = PathBuf::from("plots").join(rel).with_extension("svg");
    let written = dir
        .join(&plot)
        .parent()
        .map_or(Ok(()), std::fs::create_dir_all)
        .and_then(|()| std::fs::write(dir.join(&plot), svg));
    (table, written.ok().map(|()| plot))
}

/// A path as a relative URL: each segment percent-encoded.
fn url(path: &Path) -> String {
    let mut out = String::new();
    for (i, part) in path.components().enumerate() {
        if i > 0 {
            out.push('/');
        }
        for b in part.as_os_str().to_string_lossy().bytes() {
            if b.is_ascii_alphanumeric() || b"-_.~".contains(&b) {
                out.push(b as char);
            } else {
                out.push_str(&format!("%{b:02X}"));
            }
        }
    }
    out
}

impl BatchReport {
    /// The static HTML report (`index.html` in `options.html`, beside the `plots/` the run
    /// wrote): a summary on top, a table of every file, and per file its status, encoding,
    /// profile, diagnostics with their source lines, and for a converted program its
    /// `explain` table and plot. One page, no script, no outside resource.
    pub fn write_html(&self, options: &BatchOptions) -> Result<(), String> {
        let Some(dir) = &options.html else {
            return Ok(());
        };
        let esc = crate::plot::escape;
        let mut page = String::new();
        let title = format!(
            "ncthread batch: {} → {}",
            options.src_dir.display(),
            options.out_dir.display()
        );
        page.push_str(&format!(
            "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>{}</title>\n<style>\n{}\n</style>\n</head>\n<body>\n<h1>{}</h1>\n",
            esc(&title),
            HTML_STYLE,
            esc(&title)
        ));
        page.push_str(&format!(
            "<p class=\"summary\">{}{} · from {} to {} · profile: {}</p>\n",
            esc(&self.summary()),
            self.codes_summary()
                .map_or(String::new(), |c| format!("<br>{}", esc(&c))),
            options.from.map_or("auto".to_string(), |d| d.to_string()),
            options.conversion.to,
            esc(&match &options.profile {
                ProfileChoice::Given(p, _) => p.display().to_string(),
                ProfileChoice::Discover => "each program's own (sidecar or ncthread.toml)".into(),
                ProfileChoice::Defaults => "built-in defaults".into(),
            })
        ));
        page.push_str("<table>\n<tr><th>file</th><th>status</th><th>dialect</th><th>encoding</th><th>errors</th><th>warnings</th><th>output</th></tr>\n");
        for (i, f) in self.files.iter().enumerate() {
            let errors = f.diagnostics.iter().filter(|d| d.is_error()).count();
            page.push_str(&format!(
                "<tr><td><a href=\"#f{i}\">{}</a></td><td class=\"{}\">{}</td><td>{}</td><td>{}</td><td>{errors}</td><td>{}</td><td>{}</td></tr>\n",
                esc(&f.input.display().to_string()),
                f.status.name(),
                f.status.name(),
                f.dialect.map_or("—".to_string(), |d| d.to_string()),
                f.encoding.map_or("—", |e| e.name()),
                f.diagnostics.len() - errors,
                f.written(self.dry_run)
                    .map_or("—".to_string(), |p| esc(&p.display().to_string())),
            ));
        }
        page.push_str("</table>\n");
        for (i, f) in self.files.iter().enumerate() {
            page.push_str(&format!(
                "<section id=\"f{i}\">\n<h2>{} <span class=\"{}\">{}</span></h2>\n<p>read as {} in {}; profile: {}; {}</p>\n",
                esc(&f.input.display().to_string()),
                f.status.name(),
                f.status.name(),
                f.dialect.map_or("—".to_string(), |d| d.to_string()),
                f.encoding.map_or("—", |e| e.name()),
                esc(&f.profile_name()),
                f.written(self.dry_run).map_or("no output".to_string(), |p| format!(
                    "output {}",
                    esc(&p.display().to_string())
                )),
            ));
            if let Some(reason) = &f.reason {
                page.push_str(&format!("<p class=\"reason\">{}</p>\n", esc(reason)));
            }
            if !f.diagnostics.is_empty() {
                let text =
                    crate::diag::render_all(&f.diagnostics, crate::diag::Format::Human, false);
                page.push_str(&format!(
                    "<h3>diagnostics</h3>\n<pre>{}</pre>\n",
                    esc(&text)
                ));
            }
            if let Some((table, plot)) = &f.explained {
                page.push_str(&format!(
                    "<h3>explain (the {} output)</h3>\n<pre>{}</pre>\n",
                    options.conversion.to,
                    esc(table)
                ));
                if let Some(plot) = plot {
                    page.push_str(&format!(
                        "<h3>plot</h3>\n<img src=\"{}\" alt=\"plot of {}\" width=\"1100\">\n",
                        url(plot),
                        esc(&f.input.display().to_string())
                    ));
                }
            }
            page.push_str("</section>\n");
        }
        page.push_str("</body>\n</html>\n");
        let path = dir.join("index.html");
        std::fs::write(&path, page).map_err(|e| files::io_error("write", path.display(), &e))
    }
}

const HTML_STYLE: &str = "body { font-family: DejaVu Sans, Arial, sans-serif; margin: 2em; color: #222; }
table { border-collapse: collapse; }
td, th { border: 1px solid #ccc; padding: 0.2em 0.6em; text-align: left; }
pre { background: #f6f6f6; padding: 0.6em; overflow-x: auto; font-family: DejaVu Sans Mono, monospace; }
.converted { color: #1b6b1b; } .failed { color: #c00000; } .skipped { color: #806000; }
section { border-top: 1px solid #ccc; margin-top: 2em; }
.summary { font-size: 1.1em; }";

#[cfg(test)]
mod tests {
    use super::*;

    /// A tree of `n` czech programs and the options of a czech → iso run into `out`.
    fn tree(dir: &Path, n: usize) -> BatchOptions {
        let src = dir.join("src");
        std::fs::create_dir_all(&src).unwrap();
        for i in 0..n {
            std::fs::write(
                src.join(format!("p{i:02}.nc")),
                format!(
                    "N10 G95 M03 S500\nN20 G00 X{}. Z5.\nN30 G33 Z-20. F1.5\nN40 G00 X40.\nN50 M30\n",
                    30 + i
                ),
            )
            .unwrap();
        }
        BatchOptions {
            src_dir: src,
            out_dir: dir.join("out"),
            from: Some(dialect::czech::ID),
            conversion: ConvertOptions {
                from: dialect::czech::ID,
                to: dialect::iso::ID,
                profile: Profile::default(),
                unsupported: crate::Unsupported::Error,
                renumber: Default::default(),
                round: false,
                nc31_comments: false,
            },
            profile: ProfileChoice::Defaults,
            overrides: Default::default(),
            jobs: 1,
            force: false,
            dry_run: false,
            extension: "ngc".into(),
            selection: Selection {
                extensions: program_extensions(Some(dialect::czech::ID)),
                ..Default::default()
            },
            input_encoding: None,
            output: Default::default(),
            html: None,
        }
    }

    /// A disk that fills up after two outputs: the third write fails with ENOSPC, the run
    /// stops there (no file after it is tried), and the report names the path.
    #[test]
    fn a_full_disk_stops_the_run() {
        let dir = tempfile::tempdir().unwrap();
        let options = tree(dir.path(), 12);
        let planned = super::plan(&options).unwrap();
        let writes = std::sync::atomic::AtomicUsize::new(0);
        let full = |path: &Path, bytes: &[u8], force: bool, guard: Option<&Path>| {
            if writes.fetch_add(1, Ordering::SeqCst) < 2 {
                return files::write_atomically(path, bytes, force, guard);
            }
            let enospc = std::io::Error::from(std::io::ErrorKind::StorageFull);
            Err(files::WriteError::of("write", path.display(), &enospc))
        };
        let report = run_with(&options, &planned, &|_| {}, &AtomicBool::new(false), &full).unwrap();
        assert_eq!(
            writes.load(Ordering::SeqCst),
            3,
            "no write after the full one"
        );
        assert_eq!(report.count(Status::Converted), 2);
        assert_eq!(report.count(Status::Failed), 1);
        assert_eq!(report.count(Status::NotDone), 9);
        let failed = report
            .files
            .iter()
            .find(|f| f.status == Status::Failed)
            .unwrap();
        let why = format!(
            "cannot write {}: {}",
            failed.output.display(),
            files::io_reason(&std::io::Error::from(std::io::ErrorKind::StorageFull))
        );
        assert_eq!(report.fatal.as_deref(), Some(why.as_str()));
        assert_eq!(failed.reason.as_deref(), Some(why.as_str()));
        assert!(!report.succeeded());
        assert!(
            report.summary().contains("stopped: 9 not done"),
            "{}",
            report.summary()
        );
        // Another write error fails its file only.
        let dir = tempfile::tempdir().unwrap();
        let options = tree(dir.path(), 4);
        let planned = super::plan(&options).unwrap();
        let denied = |path: &Path, _: &[u8], _: bool, _: Option<&Path>| {
            let e = std::io::Error::from(std::io::ErrorKind::PermissionDenied);
            Err(files::WriteError::of("write", path.display(), &e))
        };
        let report = run_with(
            &options,
            &planned,
            &|_| {},
            &AtomicBool::new(false),
            &denied,
        )
        .unwrap();
        assert_eq!(report.count(Status::Failed), 4);
        assert_eq!(report.fatal, None);
    }
}

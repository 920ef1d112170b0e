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
    /// Write a static HTML report into this folder: `index.html`, the plots, and the data
    /// of the page (`report.json`, [`STATE_FILE`]), which the next run reads back.
    pub html: Option<PathBuf>,
    /// The JSON report the caller writes. A previous run's report there (or the HTML
    /// report's data, which wins) tells which skipped outputs are up to date, and gives
    /// their rows back.
    pub report: Option<PathBuf>,
}

/// The data of the HTML report, beside `index.html`: the JSON report with each converted
/// file's `explain` table and plot, read back by the next run.
pub const STATE_FILE: &str = "report.json";

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
    /// What the output was made from: the input's bytes and the profile
    /// ([`fingerprint`]); and the output's bytes as written.
    pub input_hash: Option<u64>,
    pub output_hash: Option<u64>,
    /// For a skipped file whose output a previous run's report knows: whether it is what
    /// this run would write (`true`: the row is that run's), or older than its program or
    /// the settings (`false`).
    pub up_to_date: Option<bool>,
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
            input_hash: None,
            output_hash: None,
            up_to_date: None,
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
    /// ([`FileReport::written`]); under `--dry-run`, `would_write` where it would be; with
    /// `explain`, the `explain` table and the plot of a converted file (the HTML report's
    /// data).
    pub fn to_json(&self, dry_run: bool, explain: bool) -> serde_json::Value {
        let would_write = (dry_run && self.status == Status::Converted)
            .then(|| self.output.display().to_string());
        let hex = |h: Option<u64>| h.map(|h| format!("{h:016x}"));
        let mut value = json!({
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
            "up_to_date": self.up_to_date,
            "input_hash": hex(self.input_hash),
            "output_hash": hex(self.output_hash),
            "diagnostics": self.diagnostics.iter().map(Diagnostic::to_json_value).collect::<Vec<_>>(),
        });
        if explain && let Some((table, plot)) = &self.explained {
            value["explain"] = json!(table);
            value["plot"] = json!(plot.as_ref().map(|p| p.display().to_string()));
        }
        value
    }

    /// The row a previous run's report (`v`) holds for the input `input`, with `output`:
    /// what that run found (read as, in, with, its diagnostics, its `explain`), or `None`
    /// when `v` is not such a row.
    fn from_json(v: &serde_json::Value, input: PathBuf, output: PathBuf) -> Option<FileReport> {
        let text = |key: &str| v.get(key).and_then(|t| t.as_str());
        let hash = |key: &str| text(key).and_then(|h| u64::from_str_radix(h, 16).ok());
        let status = match text("status")? {
            "converted" => Status::Converted,
            "skipped" => Status::Skipped,
            _ => return None,
        };
        let mut f = FileReport::new(input, output, status);
        f.dialect = text("dialect").and_then(dialect::by_id).map(|d| d.id());
        f.encoding = text("encoding").and_then(TextEncoding::for_label);
        f.output_encoding = text("output_encoding").and_then(TextEncoding::for_label);
        f.profile = text("profile").map(PathBuf::from);
        f.dialect_note = text("dialect_note").map(str::to_string);
        f.diagnostics = v
            .get("diagnostics")?
            .as_array()?
            .iter()
            .map(|v| Diagnostic::from_json_value(v, crate::dialect::all_codes()))
            .collect::<Option<Vec<_>>>()?;
        f.explained = text("explain").map(|t| (t.to_string(), text("plot").map(PathBuf::from)));
        f.input_hash = hash("input_hash");
        f.output_hash = hash("output_hash");
        Some(f)
    }
}

/// FNV-1a over `parts` (each ended by a 0xFF byte, which no part's UTF-8 holds): a stable
/// fingerprint of what an output is made from (the same in every build, unlike std's
/// hasher), for telling an output that is up to date.
pub fn fingerprint(parts: &[&[u8]]) -> u64 {
    let mut h = Fnv::default();
    for part in parts {
        h.add(part);
        h.end_part();
    }
    h.0
}

/// [`fingerprint`] taken a piece of a part at a time.
struct Fnv(u64);

impl Default for Fnv {
    fn default() -> Self {
        Fnv(0xcbf2_9ce4_8422_2325)
    }
}

impl Fnv {
    fn add(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 ^= u64::from(b);
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }

    fn end_part(&mut self) {
        self.add(&[0xFF]);
    }
}

/// The [`fingerprint`] of an encoded output's bytes (one part), read a buffer at a time.
fn output_fingerprint(encoded: &mut text::Encoded) -> std::io::Result<u64> {
    let mut h = Fnv::default();
    encoded.each_chunk(&mut |bytes| h.add(bytes))?;
    h.end_part();
    Ok(h.0)
}

/// The fingerprint of the settings an output depends on besides its program and profile:
/// the dialects, the conversion's options, the encodings and line endings, the extension,
/// the profile choice, and ncthread's version.
fn settings_fingerprint(options: &BatchOptions) -> u64 {
    let c = &options.conversion;
    let profile = match &options.profile {
        ProfileChoice::Given(path, _) => format!("given {}", path.display()),
        ProfileChoice::Discover => "discover".into(),
        ProfileChoice::Defaults => "defaults".into(),
    };
    let text = format!(
        "{} {:?} {} {:?} {:?} {} {} {:?} {:?} {:?} {} {profile}",
        env!("CARGO_PKG_VERSION"),
        options.from.map(|d| d.to_string()),
        c.to,
        c.unsupported,
        c.renumber,
        c.round,
        c.nc31_comments,
        options.input_encoding.map(TextEncoding::name),
        options.output,
        options.overrides,
        options.extension,
    );
    fingerprint(&[text.as_bytes()])
}

/// The input fingerprint of a program's `bytes` read with `profile`.
fn input_fingerprint(bytes: &[u8], profile: &Profile) -> u64 {
    fingerprint(&[bytes, format!("{profile:?}").as_bytes()])
}

/// What a previous run's report says of the outputs it wrote.
#[derive(Clone, Debug, Default)]
struct Previous {
    /// That run's settings were this run's.
    same_settings: bool,
    /// Its rows of converted (or, in turn, restored) files, by their path below the source.
    files: HashMap<PathBuf, FileReport>,
}

impl Previous {
    /// The previous report at `path` (the HTML report's data, or the JSON report), when it
    /// is one ncthread wrote; a missing or unreadable one is no previous run.
    fn load(path: &Path, options: &BatchOptions) -> Option<Previous> {
        let text = std::fs::read_to_string(path).ok()?;
        let json: serde_json::Value = serde_json::from_str(&text).ok()?;
        let source = PathBuf::from(json.get("source")?.as_str()?);
        // A report of another tree (the same --report file given to another run) says
        // nothing of these outputs.
        let same = |a: &Path, b: &Path| match (files::resolve(a), files::resolve(b)) {
            (Ok(a), Ok(b)) => a == b,
            _ => a == b,
        };
        let output = PathBuf::from(json.get("output")?.as_str()?);
        if !same(&source, &options.src_dir) || !same(&output, &options.out_dir) {
            return None;
        }
        let settings = json
            .get("settings")
            .and_then(|s| s.as_str())
            .and_then(|h| u64::from_str_radix(h, 16).ok());
        let mut files = HashMap::new();
        for f in json.get("files")?.as_array()? {
            let Some(rel) = f
                .get("path")
                .and_then(|p| p.as_str())
                .and_then(|p| Path::new(p).strip_prefix(&source).ok())
            else {
                continue;
            };
            let input = options.src_dir.join(rel);
            let output = output_path(options, rel);
            if let Some(row) = FileReport::from_json(f, input, output) {
                files.insert(rel.to_path_buf(), row);
            }
        }
        Some(Previous {
            same_settings: settings == Some(settings_fingerprint(options)),
            files,
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

    /// The skipped files whose output is older than its program or the settings (a previous
    /// run's report tells).
    pub fn out_of_date(&self) -> usize {
        self.files
            .iter()
            .filter(|f| f.up_to_date == Some(false))
            .count()
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
        let stale = self.out_of_date();
        if skipped > 0 && stale > 0 {
            text.push_str(&format!(
                ", skipped {skipped} (exist, {stale} of them out of date; --force to convert again)"
            ));
        } else if skipped > 0 {
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

    /// The JSON report.
    pub fn to_json(&self, options: &BatchOptions) -> serde_json::Value {
        self.json(options, false)
    }

    /// The JSON report; with `explain`, each converted file's `explain` table and plot too
    /// (the HTML report's data).
    fn json(&self, options: &BatchOptions, explain: bool) -> serde_json::Value {
        json!({
            "ncthread": env!("CARGO_PKG_VERSION"),
            "settings": format!("{:016x}", settings_fingerprint(options)),
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
            "out_of_date": self.out_of_date(),
            "left_out": self.count(Status::LeftOut),
            "not_done": self.count(Status::NotDone),
            "seconds": self.elapsed.as_secs_f64(),
            "codes": self
                .codes()
                .into_iter()
                .map(|(code, n)| (code.to_string(), json!(n)))
                .collect::<serde_json::Map<String, serde_json::Value>>(),
            "files": self.files.iter().map(|f| f.to_json(self.dry_run, explain)).collect::<Vec<_>>(),
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
    /// What the previous run's report says of the outputs it wrote.
    previous: Previous,
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
    // The HTML report's data, else the JSON report: what a previous run wrote.
    let previous = options
        .html
        .as_ref()
        .map(|dir| dir.join(STATE_FILE))
        .iter()
        .chain(options.report.iter())
        .find_map(|path| Previous::load(path, options))
        .unwrap_or_default();
    Ok(Plan {
        src_root,
        walk,
        profiles,
        loaded,
        previous,
    })
}

/// Reads a discovered profile; its errors become one reason.
fn read_profile(path: &Path) -> Result<Profile, String> {
    Profile::load(path).map_err(|e| e.summary(path))
}

/// How an output is written: [`write_encoded`]'s arguments and result (path, the encoded
/// output, force, the source tree's guard).
pub type Writer<'a> = dyn Fn(&Path, &mut text::Encoded, bool, Option<&Path>) -> Result<(), files::WriteError>
    + Sync
    + 'a;

/// Writes an encoded output with [`files::write_atomically_with`] (a large one copied from its
/// temporary file).
pub fn write_encoded(
    path: &Path,
    encoded: &mut text::Encoded,
    force: bool,
    guard: Option<&Path>,
) -> Result<(), files::WriteError> {
    files::write_atomically_with(path, force, guard, |to| encoded.write_to(to))
}

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
    run_with(options, plan, progress, stop, &write_encoded)
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
        prepare_folders(options)?;
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(options.jobs)
        .build()
        .map_err(|e| format!("cannot start the worker threads: {e}"))?;
    let clashes = clashes(plan, options);
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

/// Makes the output folder (and the HTML report's), and tries a write into it: a folder
/// that cannot be written is the user's problem, named as they wrote it.
fn prepare_folders(options: &BatchOptions) -> Result<(), String> {
    std::fs::create_dir_all(&options.out_dir)
        .map_err(|e| files::io_error("create", options.out_dir.display(), &e))?;
    tempfile::Builder::new()
        .prefix(".ncthread-")
        .tempfile_in(&options.out_dir)
        .map_err(|e| files::io_error("write into", options.out_dir.display(), &e))?;
    if let Some(dir) = &options.html {
        std::fs::create_dir_all(dir.join("plots"))
            .map_err(|e| files::io_error("create", dir.display(), &e))?;
    }
    Ok(())
}

/// Each file's clash with an earlier one (`None`: its output is its own). Two inputs that
/// differ only in their extension would write one output; two whose outputs differ only in
/// case would on a case-insensitive file system (Windows, macOS, the FAT of a USB stick
/// that takes the programs to the machine).
fn clashes<'p>(plan: &'p Plan, options: &BatchOptions) -> Vec<Option<Clash<'p>>> {
    let mut first_of: HashMap<String, &Path> = Default::default();
    plan.walk
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
        .collect()
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
    let (mut report, bytes) = convert_one(options, plan, rel, clash, profile);
    let Some(mut bytes) = bytes else {
        return (report, None);
    };
    match write(
        &report.output,
        &mut bytes,
        options.force,
        Some(&plan.src_root),
    ) {
        Ok(()) => {
            report.status = Status::Converted;
            // Written, so readable: a read that fails leaves the output without a
            // fingerprint (a later run converts it again).
            report.output_hash = output_fingerprint(&mut bytes).ok();
        }
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
    plan: &Plan,
    rel: &Path,
    clash: Option<Clash>,
    profile: Option<(PathBuf, Option<Result<Profile, String>>)>,
) -> (FileReport, Option<text::Encoded>) {
    let input = options.src_dir.join(rel);
    let output = output_path(options, rel);
    let mut report = FileReport::new(input.clone(), output.clone(), Status::Failed);
    if let Some(clash) = clash {
        report.reason = Some(clash_reason(options, clash, &output));
        return (report, None);
    }
    let Some(profile) = file_profile(options, profile, &mut report) else {
        return (report, None);
    };
    if !options.force && output.exists() {
        report.status = Status::Skipped;
        report.reason = Some(OUTPUT_EXISTS.into());
        if let Some(before) = plan.previous.files.get(rel) {
            report = kept(report, before, &profile, plan.previous.same_settings);
        }
        return (report, None);
    }
    let bytes = match std::fs::read(&input) {
        Ok(b) => b,
        Err(e) => {
            report.reason = Some(files::io_error("read", input.display(), &e));
            return (report, None);
        }
    };
    report.input_hash = Some(input_fingerprint(&bytes, &profile));
    let Some(decoded) = decode_input(options, rel, &bytes, &mut report) else {
        return (report, None);
    };
    let bytes = convert_decoded(options, rel, decoded, profile, &mut report);
    if options.dry_run && bytes.is_some() {
        report.status = Status::Converted;
        return (report, None);
    }
    (report, bytes)
}

/// Why a file whose output would land on an earlier file's is not converted.
fn clash_reason(options: &BatchOptions, clash: Clash, output: &Path) -> String {
    match clash {
        Clash::Same(first) => format!(
            "{} is written to the same output; give the files different names",
            options.src_dir.join(first).display()
        ),
        Clash::Case(first) => format!(
            "its output {} and the output {} of {} differ only in case: on a case-insensitive file system (Windows, macOS, a USB stick) one would replace the other; rename one of the programs",
            output.display(),
            output_path(options, first).display(),
            options.src_dir.join(first).display()
        ),
    }
}

/// A file's profile (`profile`: the one found for it, and it loaded or why not), with
/// the overrides; the defaults when none was found. `None` when it could not be loaded
/// (the report says why).
fn file_profile(
    options: &BatchOptions,
    profile: Option<(PathBuf, Option<Result<Profile, String>>)>,
    report: &mut FileReport,
) -> Option<Profile> {
    let defaults = || {
        let mut p = Profile::default();
        options.overrides.apply(&mut p);
        p
    };
    match profile {
        None => Some(defaults()),
        Some((path, found)) => {
            report.profile = Some(path);
            match found {
                Some(Ok(p)) => Some(p),
                Some(Err(why)) => {
                    report.reason = Some(why);
                    None
                }
                None => Some(defaults()),
            }
        }
    }
}

/// A program's bytes decoded, its dialect and encoding (and how sure) in the report;
/// `None` when its encoding is refused.
fn decode_input(
    options: &BatchOptions,
    rel: &Path,
    bytes: &[u8],
    report: &mut FileReport,
) -> Option<text::Decoded> {
    let decoded = text::decode_program(bytes, options.from, options.input_encoding, Some(rel));
    report.dialect_note = decoded.detection.as_ref().filter(|d| !d.certain).map(|d| {
        format!(
            "--from auto: read as {} ({}); give --from to be sure",
            d.dialect, d.reason
        )
    });
    let note = decoded.encoding_diagnostic(&report.input.display().to_string());
    report.dialect = Some(decoded.dialect);
    report.encoding = Some(decoded.encoding);
    if let Some(d) = note {
        let refused = d.is_error();
        report.diagnostics.push(d);
        if refused {
            return None;
        }
    }
    Some(decoded)
}

/// Converts a decoded program with its `profile`: the output's bytes (and its
/// explanation for the HTML report), or `None` when it is refused (the report says why).
fn convert_decoded(
    options: &BatchOptions,
    rel: &Path,
    decoded: text::Decoded,
    profile: Profile,
    report: &mut FileReport,
) -> Option<text::Encoded> {
    let text::Decoded {
        text,
        encoding,
        dialect: from,
        eof_mark,
        ..
    } = decoded;
    let kept = text::Input::of(&text, encoding, &eof_mark, from == options.conversion.to);
    let src = SourceFile::new(report.input.display().to_string(), text);
    let conversion = ConvertOptions {
        from,
        profile,
        ..options.conversion.clone()
    };
    let converted = convert(&src, &conversion);
    report.diagnostics.extend(converted.diagnostics);
    let program = converted.output?;
    report.output_encoding = Some(options.output.encoding_for(&kept));
    let html = options.html.as_ref().filter(|_| !options.dry_run);
    let name = report.output.display().to_string();
    // The text is kept only for the HTML report's explanation.
    let (bytes, program) = if html.is_some() {
        let encoded = text::encode_output_text(&program, &name, &options.output, &kept);
        (encoded, Some(program))
    } else {
        let encoded = text::encode_output_owned(program, &name, &options.output, &kept);
        (encoded, None)
    };
    let bytes = match bytes {
        Ok(b) => b,
        Err(d) => {
            report.diagnostics.push(*d);
            return None;
        }
    };
    if let (Some(dir), Some(program)) = (html, program) {
        report.explained = Some(explain_output(&program, &conversion, rel, dir));
    }
    Some(bytes)
}

/// A file skipped because its output exists, which a previous run's report (`before`)
/// knows: that run's row when the output is what this run would write (its program,
/// profile and settings as then, the output as that run wrote it), else the skip with why it
/// is not. The fingerprints stay, so that a later run still tells.
fn kept(
    mut report: FileReport,
    before: &FileReport,
    profile: &Profile,
    same_settings: bool,
) -> FileReport {
    let input = std::fs::read(&report.input)
        .ok()
        .map(|b| input_fingerprint(&b, profile));
    let output = std::fs::read(&report.output)
        .ok()
        .map(|b| fingerprint(&[&b]));
    report.input_hash = before.input_hash;
    report.output_hash = before.output_hash;
    let why = if output.is_none() || output != before.output_hash {
        "the output exists and was changed after ncthread wrote it (--force overwrites it)"
    } else if input.is_none() || input != before.input_hash {
        report.up_to_date = Some(false);
        "the output exists, but its program has changed since it was converted (--force converts it again)"
    } else if !same_settings {
        report.up_to_date = Some(false);
        "the output exists, but it was converted with other settings (--force converts it again)"
    } else {
        return FileReport {
            input: report.input,
            output: report.output,
            status: Status::Skipped,
            reason: Some(UP_TO_DATE.into()),
            up_to_date: Some(true),
            ..before.clone()
        };
    };
    report.reason = Some(why.into());
    report
}

/// Why an output that is what this run would write is not written again.
const UP_TO_DATE: &str = "up to date: converted by an earlier run (--force converts it again)";

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
        let mut page = self.html_head(options);
        page.push_str("<table>\n<tr><th>file</th><th>status</th><th>dialect</th><th>encoding</th><th>errors</th><th>warnings</th><th>output</th></tr>\n");
        for (i, f) in self.files.iter().enumerate() {
            page.push_str(&self.html_row(i, f));
        }
        page.push_str("</table>\n");
        for (i, f) in self.files.iter().enumerate() {
            page.push_str(&self.html_section(i, f, options));
        }
        page.push_str("</body>\n</html>\n");
        let path = dir.join("index.html");
        std::fs::write(&path, page).map_err(|e| files::io_error("write", path.display(), &e))?;
        // The page's data, which the next run reads back.
        let path = dir.join(STATE_FILE);
        let json = serde_json::to_string_pretty(&self.json(options, true))
            .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        std::fs::write(&path, json + "\n").map_err(|e| files::io_error("write", path.display(), &e))
    }

    /// The HTML report's head, title and summary line.
    fn html_head(&self, options: &BatchOptions) -> String {
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
        page
    }

    /// File `i`'s row in the HTML report's table, linking to its section.
    fn html_row(&self, i: usize, f: &FileReport) -> String {
        let esc = crate::plot::escape;
        let errors: usize = f
            .diagnostics
            .iter()
            .filter(|d| d.is_error())
            .map(Diagnostic::count)
            .sum();
        format!(
            "<tr><td><a href=\"#f{i}\">{}</a></td><td class=\"{}\">{}</td><td>{}</td><td>{}</td><td>{errors}</td><td>{}</td><td>{}</td></tr>\n",
            esc(&f.input.display().to_string()),
            f.status.name(),
            f.status.name(),
            f.dialect.map_or("—".to_string(), |d| d.to_string()),
            f.encoding.map_or("—", |e| e.name()),
            f.diagnostics.len() - errors,
            f.written(self.dry_run)
                .map_or("—".to_string(), |p| esc(&p.display().to_string())),
        )
    }

    /// File `i`'s section in the HTML report: how it was read, why it failed, its
    /// diagnostics, and its output explained and plotted.
    fn html_section(&self, i: usize, f: &FileReport, options: &BatchOptions) -> String {
        let esc = crate::plot::escape;
        let mut page = String::new();
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
            let text = crate::diag::render_all(&f.diagnostics, crate::diag::Format::Human, false);
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
        page
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
            report: None,
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
        let full = |path: &Path, bytes: &mut text::Encoded, force: bool, guard: Option<&Path>| {
            if writes.fetch_add(1, Ordering::SeqCst) < 2 {
                return write_encoded(path, bytes, force, guard);
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
        let denied = |path: &Path, _: &mut text::Encoded, _: bool, _: Option<&Path>| {
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

//! Converting a whole tree of programs (`ncthread batch`).
//!
//! The source tree is walked (hidden files and folders left out, files sorted), each file is
//! converted in parallel on its own, and its output is written into the mirrored place of
//! the output tree with the target's extension. A bad file is reported and the rest go on. An
//! output is written to a temporary file beside it and renamed into place, so a reader never
//! sees half a program; an existing output is kept unless `force`. Nothing is ever written
//! inside the source tree.

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use rayon::prelude::*;
use serde_json::json;

use crate::diag::Diagnostic;
use crate::dialect::{self, DialectId};
use crate::source::SourceFile;
use crate::text::{self, OutputOptions, TextEncoding};
use crate::{ConvertOptions, convert};

/// What a batch run does.
#[derive(Clone, Debug)]
pub struct BatchOptions {
    pub src_dir: PathBuf,
    pub out_dir: PathBuf,
    /// The source dialect, or `None` to choose it per file from the text.
    pub from: Option<DialectId>,
    /// The conversion (its `from` is set per file).
    pub conversion: ConvertOptions,
    /// Worker threads; 0 lets rayon choose (one per core).
    pub jobs: usize,
    /// Overwrite existing outputs.
    pub force: bool,
    /// The outputs' extension, without the dot.
    pub extension: String,
    /// Only the files whose path below `src_dir` matches.
    pub glob: Option<globset::GlobMatcher>,
    /// The input encoding, or `None` for UTF-8 when valid, else the dialect's legacy one.
    pub input_encoding: Option<TextEncoding>,
    pub output: OutputOptions,
    /// Write a static HTML report into this folder: `index.html` and the plots.
    pub html: Option<PathBuf>,
    /// The profile the conversions use, for people (`built-in defaults` or its path).
    pub profile_name: String,
}

/// The default extension of a target's files.
pub fn default_extension(to: DialectId) -> &'static str {
    dialect::get(to).extension()
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Status {
    Converted,
    /// The program has errors, or it could not be read or written.
    Failed,
    /// The output exists and `force` was not given.
    Skipped,
}

impl Status {
    pub fn name(self) -> &'static str {
        match self {
            Status::Converted => "converted",
            Status::Failed => "failed",
            Status::Skipped => "skipped",
        }
    }
}

/// What happened to one input.
#[derive(Clone, Debug)]
pub struct FileReport {
    /// The input, as `src_dir` joined with its path below it.
    pub input: PathBuf,
    pub status: Status,
    /// Where the output is (or would have been) written.
    pub output: PathBuf,
    /// The dialect the file was read as.
    pub dialect: Option<DialectId>,
    /// The encoding the file was read in.
    pub encoding: Option<TextEncoding>,
    pub diagnostics: Vec<Diagnostic>,
    /// Why the file failed or was skipped when it is not a diagnostic (I/O, an existing output).
    pub reason: Option<String>,
    /// With an HTML report: the converted program's `explain` text and its plot's file
    /// (relative to the report's folder).
    pub explained: Option<(String, Option<PathBuf>)>,
}

impl FileReport {
    pub fn to_json(&self) -> serde_json::Value {
        json!({
            "path": self.input.display().to_string(),
            "status": self.status.name(),
            "output": self.output.display().to_string(),
            "dialect": self.dialect.map(|d| d.to_string()),
            "encoding": self.encoding.map(|e| e.name()),
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
}

impl BatchReport {
    pub fn count(&self, status: Status) -> usize {
        self.files.iter().filter(|f| f.status == status).count()
    }

    /// `converted 151, failed 3, skipped 0 in 0.4 s`
    pub fn summary(&self) -> String {
        format!(
            "converted {}, failed {}, skipped {} in {:.1} s",
            self.count(Status::Converted),
            self.count(Status::Failed),
            self.count(Status::Skipped),
            self.elapsed.as_secs_f64()
        )
    }

    pub fn all_converted(&self) -> bool {
        self.files.iter().all(|f| f.status == Status::Converted)
    }

    pub fn to_json(&self, options: &BatchOptions) -> serde_json::Value {
        json!({
            "source": options.src_dir.display().to_string(),
            "output": options.out_dir.display().to_string(),
            "from": options.from.map_or("auto".to_string(), |d| d.to_string()),
            "to": options.conversion.to.to_string(),
            "converted": self.count(Status::Converted),
            "failed": self.count(Status::Failed),
            "skipped": self.count(Status::Skipped),
            "seconds": self.elapsed.as_secs_f64(),
            "files": self.files.iter().map(FileReport::to_json).collect::<Vec<_>>(),
        })
    }
}

/// The files below `dir` (paths relative to it), sorted, hidden entries left out. Symbolic
/// links to files are followed, links to folders are not (no cycles).
pub fn inputs(dir: &Path, glob: Option<&globset::GlobMatcher>) -> std::io::Result<Vec<PathBuf>> {
    fn walk(root: &Path, rel: &Path, out: &mut Vec<PathBuf>) -> std::io::Result<()> {
        let mut entries: Vec<_> =
            std::fs::read_dir(root.join(rel))?.collect::<Result<Vec<_>, _>>()?;
        entries.sort_by_key(|e| e.file_name());
        for entry in entries {
            let name = entry.file_name();
            if name.to_string_lossy().starts_with('.') {
                continue;
            }
            let path = rel.join(&name);
            let kind = entry.file_type()?;
            if kind.is_dir() {
                walk(root, &path, out)?;
            } else if kind.is_file() || (kind.is_symlink() && root.join(&path).is_file()) {
                out.push(path);
            }
        }
        Ok(())
    }
    let mut out = Vec::new();
    walk(dir, Path::new(""), &mut out)?;
    if let Some(glob) = glob {
        out.retain(|p| glob.is_match(p));
    }
    Ok(out)
}

/// Runs a batch. `progress` is called once per file as it finishes (from worker threads).
/// `Err` is a usage or I/O problem with the trees themselves (nothing was converted).
pub fn run(
    options: &BatchOptions,
    progress: &(dyn Fn(&FileReport) + Sync),
) -> Result<BatchReport, String> {
    let started = Instant::now();
    let src_root = std::fs::canonicalize(&options.src_dir)
        .map_err(|e| format!("cannot read {}: {e}", options.src_dir.display()))?;
    if !src_root.is_dir() {
        return Err(format!("{} is not a folder", options.src_dir.display()));
    }
    let out_root = resolve(&options.out_dir)
        .map_err(|e| format!("cannot read {}: {e}", options.out_dir.display()))?;
    if out_root.starts_with(&src_root) {
        return Err(format!(
            "the output folder {} is inside the source folder {}; ncthread never writes into the source tree",
            options.out_dir.display(),
            options.src_dir.display()
        ));
    }
    std::fs::create_dir_all(&options.out_dir)
        .map_err(|e| format!("cannot create {}: {e}", options.out_dir.display()))?;
    if let Some(dir) = &options.html {
        let resolved = resolve(dir).map_err(|e| format!("cannot read {}: {e}", dir.display()))?;
        if resolved.starts_with(&src_root) {
            return Err(format!(
                "the report folder {} is inside the source folder {}; ncthread never writes into the source tree",
                dir.display(),
                options.src_dir.display()
            ));
        }
        std::fs::create_dir_all(dir.join("plots"))
            .map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    }
    let files = inputs(&options.src_dir, options.glob.as_ref())
        .map_err(|e| format!("cannot walk {}: {e}", options.src_dir.display()))?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(options.jobs)
        .build()
        .map_err(|e| format!("cannot start the worker threads: {e}"))?;
    // Two inputs that differ only in their extension would write one output.
    let mut first_of: std::collections::HashMap<PathBuf, &Path> = Default::default();
    let clashes: Vec<Option<&Path>> = files
        .iter()
        .map(|rel| {
            let out = rel.with_extension(&options.extension);
            match first_of.get(&out) {
                Some(first) => Some(*first),
                None => {
                    first_of.insert(out, rel);
                    None
                }
            }
        })
        .collect();
    let files = pool.install(|| {
        files
            .par_iter()
            .zip(clashes.par_iter())
            .map(|(rel, clash)| {
                let report = one(options, &src_root, rel, *clash);
                progress(&report);
                report
            })
            .collect::<Vec<_>>()
    });
    Ok(BatchReport {
        files,
        elapsed: started.elapsed(),
    })
}

/// The absolute, symlink-free form of `path`, which need not exist yet: its deepest existing
/// ancestor canonicalised, then the rest.
fn resolve(path: &Path) -> std::io::Result<PathBuf> {
    let absolute = std::path::absolute(path)?;
    let mut existing = absolute.as_path();
    let mut rest = Vec::new();
    while !existing.exists() {
        match (existing.parent(), existing.file_name()) {
            (Some(parent), Some(name)) => {
                rest.push(name.to_owned());
                existing = parent;
            }
            _ => break,
        }
    }
    let mut resolved = std::fs::canonicalize(existing)?;
    resolved.extend(rest.iter().rev());
    Ok(resolved)
}

/// Converts one file.
fn one(options: &BatchOptions, src_root: &Path, rel: &Path, clash: Option<&Path>) -> FileReport {
    let input = options.src_dir.join(rel);
    let output = options.out_dir.join(rel).with_extension(&options.extension);
    let mut report = FileReport {
        input: input.clone(),
        status: Status::Failed,
        output: output.clone(),
        dialect: None,
        encoding: None,
        diagnostics: Vec::new(),
        reason: None,
        explained: None,
    };
    if let Some(first) = clash {
        report.reason = Some(format!(
            "{} is written to the same output; give the files different names",
            options.src_dir.join(first).display()
        ));
        return report;
    }
    if !options.force && output.exists() {
        report.status = Status::Skipped;
        report.reason = Some("the output exists (--force overwrites it)".into());
        return report;
    }
    let bytes = match std::fs::read(&input) {
        Ok(b) => b,
        Err(e) => {
            report.reason = Some(format!("cannot read: {e}"));
            return report;
        }
    };
    let text::Decoded {
        text,
        encoding,
        dialect: from,
        ..
    } = text::decode_program(&bytes, options.from, options.input_encoding);
    report.dialect = Some(from);
    report.encoding = Some(encoding);
    let crlf = text::uses_crlf(&text);
    let src = SourceFile::new(input.display().to_string(), text);
    let conversion = convert(
        &src,
        &ConvertOptions {
            from,
            ..options.conversion.clone()
        },
    );
    report.diagnostics = conversion.diagnostics;
    let Some(program) = conversion.output else {
        return report;
    };
    let bytes = match text::encode_output(
        &program,
        &output.display().to_string(),
        &options.output,
        crlf,
    ) {
        Ok(b) => b,
        Err(d) => {
            report.diagnostics.push(*d);
            return report;
        }
    };
    if let Some(dir) = &options.html {
        report.explained = Some(explain_output(&program, &options.conversion, rel, dir));
    }
    match write_atomically(&output, &bytes, options.force, src_root) {
        Ok(()) => report.status = Status::Converted,
        Err(Write::Exists) => {
            report.status = Status::Skipped;
            report.reason = Some("the output exists (--force overwrites it)".into());
        }
        Err(Write::Failed(e)) => report.reason = Some(e),
    }
    report
}

enum Write {
    Exists,
    Failed(String),
}

/// Writes `bytes` to a temporary file beside `path` and renames it into place (without
/// replacing an existing file unless `force`).
fn write_atomically(path: &Path, bytes: &[u8], force: bool, src_root: &Path) -> Result<(), Write> {
    let parent = path.parent().unwrap_or(Path::new("."));
    std::fs::create_dir_all(parent)
        .map_err(|e| Write::Failed(format!("cannot create {}: {e}", parent.display())))?;
    match std::fs::canonicalize(parent) {
        Ok(p) if p.starts_with(src_root) => {
            return Err(Write::Failed(format!(
                "{} is inside the source tree; ncthread never writes there",
                parent.display()
            )));
        }
        Ok(_) => {}
        Err(e) => {
            return Err(Write::Failed(format!(
                "cannot read {}: {e}",
                parent.display()
            )));
        }
    }
    let failed = |e: std::io::Error| Write::Failed(format!("cannot write {}: {e}", path.display()));
    let mut tmp = tempfile::Builder::new()
        .prefix(".ncthread-")
        .tempfile_in(parent)
        .map_err(failed)?;
    tmp.write_all(bytes)
        .and_then(|()| tmp.flush())
        .map_err(failed)?;
    let persisted = if force {
        tmp.persist(path).map(drop)
    } else {
        tmp.persist_noclobber(path).map(drop)
    };
    match persisted {
        Ok(()) => Ok(()),
        Err(e) if e.error.kind() == std::io::ErrorKind::AlreadyExists => Err(Write::Exists),
        Err(e) => Err(failed(e.error)),
    }
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
    let operation = ops
        .iter()
        .find(|o| o.lead.is_some() && !o.passes.is_empty())
        .or(ops.first());
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
            "<p class=\"summary\">{} · from {} to {} · profile: {}</p>\n",
            esc(&self.summary()),
            options.from.map_or("auto".to_string(), |d| d.to_string()),
            options.conversion.to,
            esc(&options.profile_name)
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
                esc(&f.output.display().to_string()),
            ));
        }
        page.push_str("</table>\n");
        for (i, f) in self.files.iter().enumerate() {
            page.push_str(&format!(
                "<section id=\"f{i}\">\n<h2>{} <span class=\"{}\">{}</span></h2>\n<p>read as {} in {}; profile: {}; output {}</p>\n",
                esc(&f.input.display().to_string()),
                f.status.name(),
                f.status.name(),
                f.dialect.map_or("—".to_string(), |d| d.to_string()),
                f.encoding.map_or("—", |e| e.name()),
                esc(&options.profile_name),
                esc(&f.output.display().to_string()),
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
        std::fs::write(dir.join("index.html"), page)
            .map_err(|e| format!("cannot write {}: {e}", dir.join("index.html").display()))
    }
}

const HTML_STYLE: &str = "body { font-family: DejaVu Sans, Arial, sans-serif; margin: 2em; color: #222; }
table { border-collapse: collapse; }
td, th { border: 1px solid #ccc; padding: 0.2em 0.6em; text-align: left; }
pre { background: #f6f6f6; padding: 0.6em; overflow-x: auto; font-family: DejaVu Sans Mono, monospace; }
.converted { color: #1b6b1b; } .failed { color: #c00000; } .skipped { color: #806000; }
section { border-top: 1px solid #ccc; margin-top: 2em; }
.summary { font-size: 1.1em; }";

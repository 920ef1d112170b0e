//! `ncthread batch`: a folder of programs converted into another, with a progress bar.

use std::io::{self, IsTerminal, Write};
use std::path::Path;
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use ncthread::DialectId;
use ncthread::diag;
use ncthread::files::io_error;
use ncthread::profile::Profile;

use super::Fatal;
use super::args::{BatchArgs, DiagnosticsFormat};
use super::colour::colour;
use super::io::{load_profile, note};

pub(crate) fn batch(args: BatchArgs) -> Result<ExitCode, Fatal> {
    let to: DialectId = args.to.into();
    let from = args.from.known();
    let extension = extension(&args, to)?;
    let options = ncthread::batch::BatchOptions {
        src_dir: args.src_dir.clone(),
        out_dir: args.out_dir.clone(),
        from,
        conversion: args.common.options(
            from.unwrap_or(ncthread::dialect::ALL[0].id()),
            to,
            Profile::default(),
            &args.target,
        ),
        profile: profile_choice(&args)?,
        overrides: args.common.overrides(),
        jobs: args.jobs.unwrap_or(0),
        force: args.force,
        dry_run: args.dry_run,
        extension,
        selection: args.selection.selection(from),
        input_encoding: args.common.encoding,
        output: args.output.options(),
        html: args.html.clone(),
        report: args.report.clone(),
    };
    // The report must be writable, and outside the source tree, before any work is done.
    if let Some(path) = &args.report {
        report_writable(path, &args.src_dir)?;
    }
    let plan = ncthread::batch::plan(&options).map_err(Fatal::Usage)?;
    for glob in plan.unmatched_globs() {
        note(format!("ncthread: warning: --glob {glob} matched no file"));
    }
    let bar = progress_bar(plan.programs(), args.quiet);
    let stop = stop_on_ctrl_c();
    let lines = Progress {
        verbose: args.common.verbose,
        dry_run: args.dry_run,
        quiet: args.quiet,
        format: args.common.diagnostics,
        max_errors: args.common.max_errors,
        color: colour(true),
    };
    let progress = |f: &ncthread::batch::FileReport| {
        let text = lines.of(f);
        if !text.is_empty() {
            bar.suspend(|| {
                let _ = io::stderr().write_all(text.as_bytes());
            });
        }
        if f.status != ncthread::batch::Status::LeftOut {
            bar.inc(1);
        }
    };
    let report = ncthread::batch::run(&options, &plan, &progress, &stop).map_err(Fatal::Usage)?;
    bar.finish_and_clear();
    let unwritten = write_reports(&args, &report, &options);
    if !args.quiet {
        note(format!("ncthread: {}", report.summary()));
        if let Some(codes) = report.codes_summary() {
            note(format!("ncthread: {codes}"));
        }
    }
    for why in &unwritten {
        note(format!("error: {why}"));
    }
    // A full disk stopped the run: exit 2, naming the path.
    if let Some(why) = &report.fatal {
        return Err(Fatal::Usage(format!("the run stopped: {why}")));
    }
    Ok(exit_code(
        &report,
        !plan.unmatched_globs().is_empty() || !unwritten.is_empty(),
    ))
}

/// A run's exit code: 130 interrupted, 2 when a glob matched nothing or a report was not
/// written (`incomplete`), 1 when a file failed.
fn exit_code(report: &ncthread::batch::BatchReport, incomplete: bool) -> ExitCode {
    if report.interrupted {
        ExitCode::from(130)
    } else if incomplete {
        ExitCode::from(2)
    } else if report.succeeded() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}

/// The outputs' extension: `--ext` (without its dot), else the target's.
fn extension(args: &BatchArgs, to: DialectId) -> Result<String, Fatal> {
    let extension = args
        .ext
        .clone()
        .unwrap_or_else(|| ncthread::batch::default_extension(to).to_string());
    let extension = extension.trim_start_matches('.').to_string();
    if extension.is_empty() || extension.contains(['/', '\\']) || extension == ".." {
        return Err(Fatal::Usage(format!(
            "--ext {extension:?}: an extension is a name without a folder (ngc, nc, ncp)"
        )));
    }
    Ok(extension)
}

/// The profile of every file: `--profile`'s (loaded now, with the overrides), the defaults
/// (`--no-profile`), or each file's own.
fn profile_choice(args: &BatchArgs) -> Result<ncthread::batch::ProfileChoice, Fatal> {
    Ok(match (&args.common.profile, args.common.no_profile) {
        (Some(path), _) => {
            let mut p = load_profile(&Some(path.clone()), args.common.diagnostics)?;
            args.common.overrides().apply(&mut p);
            ncthread::batch::ProfileChoice::Given(path.clone(), Box::new(p))
        }
        (None, true) => ncthread::batch::ProfileChoice::Defaults,
        (None, false) => ncthread::batch::ProfileChoice::Discover,
    })
}

/// Refuses a report inside the source tree, or one that cannot be written (tried by
/// opening it, and removed again if it did not exist).
fn report_writable(path: &Path, src_dir: &Path) -> Result<(), Fatal> {
    let inside = ncthread::files::resolve(path)
        .ok()
        .zip(std::fs::canonicalize(src_dir).ok());
    if inside.is_some_and(|(r, s)| r.starts_with(s)) {
        return Err(Fatal::Usage(format!(
            "the report {} is inside the source folder {}; ncthread never writes into the source tree",
            path.display(),
            src_dir.display()
        )));
    }
    let existed = path.exists();
    std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(path)
        .map_err(|e| Fatal::Usage(io_error("write", path.display(), &e)))?;
    if !existed {
        let _ = std::fs::remove_file(path);
    }
    Ok(())
}

/// The progress bar on a terminal (hidden elsewhere, and with `--quiet`).
fn progress_bar(programs: usize, quiet: bool) -> indicatif::ProgressBar {
    if io::stderr().is_terminal() && !quiet {
        let bar = indicatif::ProgressBar::new(programs as u64);
        bar.set_style(
            indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} {wide_msg}")
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        bar
    } else {
        indicatif::ProgressBar::hidden()
    }
}

/// Ctrl-C: the workers finish the file in hand, the rest is not done, and the summary and
/// the report say what was. The flag the handler sets.
fn stop_on_ctrl_c() -> Arc<AtomicBool> {
    let stop = Arc::new(AtomicBool::new(false));
    {
        let stop = stop.clone();
        let _ = ctrlc::set_handler(move || stop.store(true, Ordering::Relaxed));
    }
    stop
}

/// What is said on stderr about each file as the run goes.
struct Progress {
    verbose: bool,
    dry_run: bool,
    quiet: bool,
    format: DiagnosticsFormat,
    max_errors: usize,
    color: bool,
}

impl Progress {
    /// The lines about one file done (empty: nothing to say).
    fn of(&self, f: &ncthread::batch::FileReport) -> String {
        use ncthread::batch::Status;
        let mut text = String::new();
        if self.verbose || (self.dry_run && !self.quiet && f.status == Status::Converted) {
            text.push_str(&file_line(f, self.dry_run));
        }
        if let Some(note) = f.dialect_note.as_ref().filter(|_| !self.quiet) {
            text.push_str(&format!("{}: {note}\n", f.input.display()));
        }
        // What failed, and an output older than its program; why any other output was
        // skipped only when asked (--verbose).
        if f.status == Status::Failed
            || (self.verbose && f.status == Status::Skipped)
            || (!self.quiet && f.up_to_date == Some(false))
        {
            text.push_str(&file_problem(f, self.format, self.max_errors, self.color));
        }
        text
    }
}

/// Writes the JSON report and the HTML one (not on a dry run), even when the run stopped;
/// what could not be written.
fn write_reports(
    args: &BatchArgs,
    report: &ncthread::batch::BatchReport,
    options: &ncthread::batch::BatchOptions,
) -> Vec<String> {
    let mut unwritten = Vec::new();
    if let Some(path) = &args.report {
        let written = serde_json::to_string_pretty(&report.to_json(options))
            .map_err(|e| format!("cannot write the report: {e}"))
            .and_then(|json| {
                std::fs::write(path, json + "\n").map_err(|e| io_error("write", path.display(), &e))
            });
        unwritten.extend(written.err());
    }
    if !args.dry_run {
        unwritten.extend(report.write_html(options).err());
    }
    unwritten
}

/// One file's line under --verbose or --dry-run: what it was read as, its profile, and
/// what is (or would be) written.
pub(crate) fn file_line(f: &ncthread::batch::FileReport, dry_run: bool) -> String {
    use ncthread::batch::Status;
    let path = f.input.display();
    match f.status {
        Status::LeftOut => format!(
            "{path}: left out: {}\n",
            f.reason.as_deref().unwrap_or("not a program")
        ),
        _ => format!(
            "{path}: {} as {} in {}, profile {}{}\n",
            if dry_run && f.status == Status::Converted {
                "would convert"
            } else {
                f.status.name()
            },
            f.dialect.map_or("?".to_string(), |d| d.to_string()),
            f.encoding.map_or("?", |e| e.name()),
            f.profile_name(),
            // Where the output is, or would be: none for a file that failed.
            match f.status {
                Status::Failed | Status::NotDone => String::new(),
                _ => format!(
                    " → {}{}",
                    f.output.display(),
                    f.output_encoding
                        .map_or(String::new(), |e| format!(" in {e}"))
                ),
            },
        ),
    }
}

/// What went wrong with one batch file: its errors (human: `path:line:col: error[CODE]
/// message`, the level coloured as the full diagnostics colour it with `color`, at most
/// `max_errors` of them (0: every one) and then how many more; JSON: one object per line),
/// or the reason it failed or was skipped.
pub(crate) fn file_problem(
    f: &ncthread::batch::FileReport,
    format: DiagnosticsFormat,
    max_errors: usize,
    color: bool,
) -> String {
    let mut text = String::new();
    let path = f.input.display();
    if let Some(reason) = &f.reason {
        text.push_str(&format!("{path}: {}: {reason}\n", f.status.name()));
    }
    // Its errors, and the warnings that say why (another dialect, an encoding guessed).
    let why = |d: &&diag::Diagnostic| {
        d.is_error()
            || d.code == diag::codes::OTHER_DIALECT
            || d.code == diag::codes::ENCODING_GUESSED
    };
    // Errors shown, and those not shown (a folded one counts every repeat it stands for).
    let (mut shown, mut hidden) = (0, 0);
    for d in f.diagnostics.iter().filter(why) {
        if d.is_error() {
            if format == DiagnosticsFormat::Human && max_errors > 0 && shown >= max_errors {
                hidden += d.count();
                continue;
            }
            shown += 1;
        }
        match format {
            DiagnosticsFormat::Json => {
                text.push_str(&d.to_json());
                text.push('\n');
            }
            DiagnosticsFormat::Human => {
                let at = d.location.as_ref().map_or(format!("{path}"), |l| {
                    format!("{}:{}:{}", l.file, l.line, l.column)
                });
                let (level, style) = if d.is_error() {
                    ("error", "\x1b[1m\x1b[91m")
                } else {
                    ("warning", "\x1b[1m\x1b[93m")
                };
                let level = format!("{level}[{}]", d.code.id);
                let level = if color {
                    format!("{style}{level}\x1b[0m")
                } else {
                    level
                };
                let more = match (&d.label, d.more) {
                    (Some(label), 1..) => format!(" ({label})"),
                    _ => String::new(),
                };
                text.push_str(&format!("{at}: {level}: {}{more}\n", d.message));
            }
        }
    }
    if hidden > 0 {
        text.push_str(&diag::more_errors(&path.to_string(), hidden));
        text.push('\n');
    }
    text
}

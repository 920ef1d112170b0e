//! `ncthread check`: programs read and their diagnostics printed, nothing written.

use std::path::PathBuf;
use std::process::ExitCode;

use ncthread::DialectId;
use ncthread::diag::Diagnostic;
use ncthread::files::io_error;
use ncthread::source::SourceFile;

use super::Fatal;
use super::args::{CheckArgs, DiagnosticsFormat};
use super::colour::colour;
use super::io::{note, read_input, render, unsupported, write_output};

/// The programs a check reads, and what could not be read or chosen on the way.
#[derive(Default)]
struct Programs {
    /// Every program to check (`None`: stdin), each once.
    programs: Vec<Option<PathBuf>>,
    /// How many files could not be read (each said on stderr).
    unreadable: usize,
    /// The globs that matched no file.
    unmatched: Vec<String>,
}

/// What the checked programs came to.
#[derive(Default)]
struct Tally {
    errors: usize,
    warnings: usize,
    failed_files: usize,
    checked: usize,
    /// The programs read without a certain dialect (`NAME as DIALECT`).
    uncertain: Vec<String>,
    /// The diagnostics, rendered for stdout.
    out: String,
}

pub(crate) fn check(args: CheckArgs) -> Result<ExitCode, Fatal> {
    let from = args.from.known();
    let mut found = programs(&args, from)?;
    let mut tally = Tally::default();
    for file in &found.programs {
        // An unreadable file is reported and the others are still checked.
        if let Err(e) = check_one(file, &args, from, &mut tally) {
            if let Fatal::Usage(message) = e {
                note(format!("error: {message}"));
            }
            found.unreadable += 1;
        }
    }
    write_output(&None, tally.out.as_bytes())?;
    summarise(&args, &tally, &found.unmatched);
    Ok(if found.unreadable > 0 || !found.unmatched.is_empty() {
        ExitCode::from(2)
    } else if tally.errors > 0 {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    })
}

/// Every program named, and every program of every folder named, each once.
fn programs(args: &CheckArgs, from: Option<DialectId>) -> Result<Programs, Fatal> {
    let selection = args.selection.selection(from);
    let mut found = Programs::default();
    // Globs choose files of folders: without a path they walk the current folder.
    let globbed = !args.selection.glob.is_empty() || !args.selection.iglob.is_empty();
    let files = match (args.files.is_empty(), globbed) {
        (true, true) => vec![PathBuf::from(".")],
        _ => args.files.clone(),
    };
    if files.is_empty() {
        found.programs.push(None);
    }
    for file in &files {
        if file.as_os_str() == "-" {
            found.programs.push(None);
        } else if file.is_dir() {
            let walk = ncthread::files::walk(file, &selection).map_err(Fatal::Usage)?;
            for f in &walk.files {
                if let ncthread::files::Verdict::Skip(why) = &f.verdict
                    && args.common.verbose
                {
                    note(format!(
                        "ncthread: {}: left out: {why}",
                        file.join(&f.rel).display()
                    ));
                }
            }
            found
                .programs
                .extend(walk.programs().map(|rel| Some(file.join(rel))));
            found.unmatched.extend(walk.unmatched);
        } else {
            match std::fs::metadata(file) {
                Ok(_) => found.programs.push(Some(file.clone())),
                Err(e) => {
                    note(format!("error: {}", io_error("read", file.display(), &e)));
                    found.unreadable += 1;
                }
            }
        }
    }
    // A file named twice (or inside a folder named too) is checked once.
    let mut seen = std::collections::HashSet::new();
    found.programs.retain(|p| match p {
        Some(path) => seen.insert(std::fs::canonicalize(path).unwrap_or_else(|_| path.clone())),
        None => true,
    });
    Ok(found)
}

/// Checks one program into `tally`; an error when it (or its profile) cannot be read.
fn check_one(
    file: &Option<PathBuf>,
    args: &CheckArgs,
    from: Option<DialectId>,
    tally: &mut Tally,
) -> Result<(), Fatal> {
    let (name, bytes) = read_input(file, args.stdin.stdin_filename.as_deref())?;
    // A profile with errors fails its program, not the run.
    let profile = args.common.profile_for(&args.stdin.named(file))?;
    let decoded = ncthread::text::decode_program_owned(
        bytes,
        from,
        args.common.encoding,
        Some(std::path::Path::new(&name)),
    );
    if let Some(d) = decoded.detection.as_ref().filter(|d| !d.certain) {
        tally.uncertain.push(format!("{name} as {}", d.dialect));
    }
    if args.common.verbose {
        note(format!(
            "ncthread: {name}: read as {} in {}",
            decoded.dialect, decoded.encoding
        ));
    }
    let encoding_note = decoded.encoding_diagnostic(&name);
    let src = SourceFile::new(name, decoded.text);
    let diags = match encoding_note {
        Some(d) if d.is_error() => vec![d],
        note => {
            let mut diags = ncthread::check(
                &src,
                decoded.dialect,
                &profile,
                unsupported(args.common.unsupported),
            );
            diags.extend(note);
            diags
        }
    };
    tally.add(&diags, args);
    Ok(())
}

impl Tally {
    /// Counts one checked program's diagnostics and renders them.
    fn add(&mut self, diags: &[Diagnostic], args: &CheckArgs) {
        self.checked += 1;
        // A diagnostic that stands for repeats counts each.
        let e: usize = diags
            .iter()
            .filter(|d| d.is_error())
            .map(Diagnostic::count)
            .sum();
        self.errors += e;
        self.warnings += diags.iter().map(Diagnostic::count).sum::<usize>() - e;
        self.failed_files += usize::from(e > 0);
        self.out.push_str(&render(
            diags,
            args.common.diagnostics,
            args.common.max_errors,
            colour(false),
        ));
    }
}

/// The notes on stderr after the diagnostics: the dialects guessed, the globs that matched
/// nothing, and (for people) the totals.
fn summarise(args: &CheckArgs, tally: &Tally, unmatched: &[String]) {
    let human = args.common.diagnostics == DiagnosticsFormat::Human && !args.quiet;
    let uncertain = &tally.uncertain;
    if human && !uncertain.is_empty() {
        note(format!(
            "ncthread: --from auto: {} file(s) read without a certain dialect ({}{}); give --from to be sure",
            uncertain.len(),
            uncertain[..uncertain.len().min(3)].join(", "),
            if uncertain.len() > 3 { ", …" } else { "" }
        ));
    }
    for glob in unmatched {
        note(format!("ncthread: warning: --glob {glob} matched no file"));
    }
    if human {
        note(format!(
            "ncthread: checked {} file(s): {} error(s) in {} file(s), {} warning(s)",
            tally.checked, tally.errors, tally.failed_files, tally.warnings
        ));
    }
}

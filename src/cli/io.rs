//! Reading programs and profiles, printing diagnostics, writing outputs, and what the
//! common arguments come to (a program's profile, the conversion options).

use std::io::{self, IsTerminal, Read, Write};
use std::path::PathBuf;

use ncthread::diag::{self, Format};
use ncthread::files::io_error;
use ncthread::profile::{BlockDelete, Profile};
use ncthread::source::SourceFile;
use ncthread::text::TextEncoding;
use ncthread::{ConvertOptions, DialectId, Unsupported};

use super::Fatal;
use super::args::{
    BlockDeleteArg, CommonArgs, DiagnosticsFormat, SourceDialect, StdinArgs, TargetArgs,
    UnsupportedArg,
};
use super::colour::colour;

/// One line on stderr. Never panics: a closed or broken stderr loses the line, nothing more.
pub(crate) fn note(message: String) {
    let _ = writeln!(io::stderr(), "{message}");
}

pub(crate) fn is_stdio(path: &Option<PathBuf>) -> bool {
    path.as_ref().is_none_or(|p| p.as_os_str() == "-")
}

/// The bytes of the program `path` (stdin: `None` or `-`) and the name it goes by
/// (`stdin_name`, else `<stdin>`, for a program read from stdin).
pub(crate) fn read_input(
    path: &Option<PathBuf>,
    stdin_name: Option<&std::path::Path>,
) -> Result<(String, Vec<u8>), Fatal> {
    if is_stdio(path) {
        if io::stdin().is_terminal() {
            note("ncthread: reading the program from the terminal: type it and end with Ctrl-D, or give a FILE".into());
        }
        let mut bytes = Vec::new();
        io::stdin()
            .read_to_end(&mut bytes)
            .map_err(|e| Fatal::Usage(io_error("read", "stdin", &e)))?;
        let name = stdin_name.map_or("<stdin>".into(), |n| n.display().to_string());
        return Ok((name, bytes));
    }
    let path = path.as_ref().expect("not stdio");
    let bytes =
        std::fs::read(path).map_err(|e| Fatal::Usage(io_error("read", path.display(), &e)))?;
    Ok((path.display().to_string(), bytes))
}

/// Diagnostics as text: JSON every one; human at most `max_errors` errors per file (0: every
/// one), then how many more there are.
pub(crate) fn render(
    diags: &[diag::Diagnostic],
    format: DiagnosticsFormat,
    max_errors: usize,
    color: bool,
) -> String {
    if format == DiagnosticsFormat::Json {
        return diag::render_all(diags, Format::Json, false);
    }
    ncthread::frontend::render_diagnostics(diags, max_errors, color)
}

/// Diagnostics on stderr (see [`render`]).
pub(crate) fn print_diagnostics(
    diags: &[diag::Diagnostic],
    format: DiagnosticsFormat,
    max_errors: usize,
) {
    let text = render(diags, format, max_errors, colour(true));
    let _ = io::stderr().write_all(text.as_bytes());
}

pub(crate) fn load_profile(
    path: &Option<PathBuf>,
    format: DiagnosticsFormat,
) -> Result<Profile, Fatal> {
    let Some(path) = path else {
        return Ok(Profile::default());
    };
    Profile::load(path).map_err(|e| match e {
        ncthread::profile::LoadError::Io(why) => Fatal::Usage(why),
        ncthread::profile::LoadError::Invalid(diags) => {
            print_diagnostics(&diags, format, 0);
            Fatal::Usage(format!("the profile {} has errors", path.display()))
        }
    })
}

/// Reads the input and decodes it in the given dialect, or chooses the dialect (`auto`).
pub(crate) fn read_source(
    input: &Option<PathBuf>,
    stdin: &StdinArgs,
    from: SourceDialect,
    common: &CommonArgs,
    profile: &Profile,
) -> Result<(SourceFile, DialectId), Fatal> {
    let (name, bytes) = read_input(input, stdin.stdin_filename.as_deref())?;
    let (src, from, decoded) = decode_source(name, bytes, from, common.encoding, profile);
    encoding_checked(&src, &decoded, common.diagnostics)?;
    Ok((src, from))
}

/// [`read_source`], with what the output keeps of the input for a conversion to `to`.
pub(crate) fn read_source_for(
    input: &Option<PathBuf>,
    stdin: &StdinArgs,
    from: SourceDialect,
    common: &CommonArgs,
    to: DialectId,
    profile: &Profile,
) -> Result<(SourceFile, DialectId, ncthread::text::Input), Fatal> {
    let (name, bytes) = read_input(input, stdin.stdin_filename.as_deref())?;
    let (src, from, decoded) = decode_source(name, bytes, from, common.encoding, profile);
    encoding_checked(&src, &decoded, common.diagnostics)?;
    let kept =
        ncthread::text::Input::of(&src.text, decoded.encoding, &decoded.eof_mark, from == to);
    Ok((src, from, kept))
}

/// Decodes a program in the given dialect, or chooses the dialect (`auto`, saying so on
/// stderr when unsure). Also returns the encoding used.
pub(crate) fn decode_source(
    name: String,
    bytes: Vec<u8>,
    from: SourceDialect,
    encoding: Option<TextEncoding>,
    profile: &Profile,
) -> (SourceFile, DialectId, ncthread::text::Decoded) {
    let read = ncthread::frontend::read(name, bytes, from.known(), encoding);
    if let Some(text) = read.auto_note(profile, false) {
        note(format!("ncthread: {text}"));
    }
    (read.src, read.from, read.decoded)
}

/// The note of a legacy encoding chosen from a file's bytes (printed), or its refusal.
pub(crate) fn encoding_checked(
    src: &SourceFile,
    decoded: &ncthread::text::Decoded,
    format: DiagnosticsFormat,
) -> Result<(), Fatal> {
    let Some(d) = decoded.encoding_diagnostic(&src.name) else {
        return Ok(());
    };
    let refused = d.is_error();
    print_diagnostics(&[d], format, 0);
    if refused { Err(Fatal::Refused) } else { Ok(()) }
}

pub(crate) fn unsupported(arg: UnsupportedArg) -> Unsupported {
    match arg {
        UnsupportedArg::Error => Unsupported::Error,
        UnsupportedArg::Warn => Unsupported::Warn,
    }
}

/// Reads a program for a command that looks at it (explain, plot): its diagnostics are
/// printed, and `None` when it has errors.
pub(crate) fn read_program(
    input: &Option<PathBuf>,
    stdin: &StdinArgs,
    from: SourceDialect,
    common: &CommonArgs,
) -> Result<Option<(SourceFile, ncthread::ir::Program)>, Fatal> {
    let profile = common.profile_for(&stdin.named(input))?;
    let (src, from) = read_source(input, stdin, from, common, &profile)?;
    let (program, mut diags) =
        ncthread::parse(&src, from, &profile, unsupported(common.unsupported));
    diag::sort(&mut diags);
    print_diagnostics(&diags, common.diagnostics, common.max_errors);
    Ok((!diag::has_errors(&diags)).then_some((src, program)))
}

pub(crate) fn write_output(path: &Option<PathBuf>, bytes: &[u8]) -> Result<(), Fatal> {
    write_with(path, |to| to.write_all(bytes))
}

/// [`write_output`] of an encoded output, which a large output holds in a temporary file:
/// made in the output's folder ([`ncthread::files::spool_beside`]), that file is linked
/// into place rather than copied where it can be.
pub(crate) fn write_encoded(
    path: &Option<PathBuf>,
    mut encoded: ncthread::text::Encoded,
) -> Result<(), Fatal> {
    if let Some(to) = path.as_ref().filter(|_| !is_stdio(path))
        && encoded
            .link_into_place(to)
            .map_err(|e| not_written(e, to))?
    {
        return Ok(());
    }
    write_with(path, |to| encoded.write_to(to))
}

/// Writes what `fill` writes to `path` (stdout for `-` or none); a file whole or not at all.
fn write_with(
    path: &Option<PathBuf>,
    fill: impl FnOnce(&mut dyn io::Write) -> io::Result<()>,
) -> Result<(), Fatal> {
    if is_stdio(path) {
        let mut out = io::stdout().lock();
        return match fill(&mut out).and_then(|()| out.flush()) {
            // The reader (e.g. `head`) has what it wanted.
            Err(e) if e.kind() == io::ErrorKind::BrokenPipe => Ok(()),
            Err(e) => Err(Fatal::Usage(io_error("write", "stdout", &e))),
            Ok(()) => Ok(()),
        };
    }
    // Whole or not at all: a temporary file beside it, renamed into place.
    let path = path.as_ref().expect("not stdio");
    if let Some(parent) = path.parent().filter(|p| !p.as_os_str().is_empty())
        && !parent.is_dir()
    {
        return Err(Fatal::Usage(format!(
            "cannot write {}: the folder {} does not exist",
            path.display(),
            parent.display()
        )));
    }
    ncthread::files::write_atomically_with(path, true, None, fill).map_err(|e| not_written(e, path))
}

/// Why `path` was not written, as the command's usage error.
fn not_written(e: ncthread::files::WriteError, path: &std::path::Path) -> Fatal {
    match e {
        ncthread::files::WriteError::Failed(why) | ncthread::files::WriteError::Fatal(why) => {
            Fatal::Usage(why)
        }
        ncthread::files::WriteError::Exists => Fatal::Usage(format!("{} exists", path.display())),
    }
}

impl StdinArgs {
    /// The path the program `input` goes by: the file, or the name given to stdin.
    pub(crate) fn named(&self, input: &Option<PathBuf>) -> Option<PathBuf> {
        if is_stdio(input) {
            self.stdin_filename.clone()
        } else {
            input.clone()
        }
    }
}

impl CommonArgs {
    /// What the command line says of the machine on top of any profile.
    pub(crate) fn overrides(&self) -> ncthread::profile::Overrides {
        ncthread::profile::Overrides {
            block_delete: self.block_delete.map(|b| match b {
                BlockDeleteArg::Off => BlockDelete::Off,
                BlockDeleteArg::On => BlockDelete::On,
            }),
            subroutine_path: self.subroutine_path.clone(),
        }
    }

    /// The profile of the program `input` (stdin without `--stdin-filename`: `None`):
    /// `--profile`, else (unless `--no-profile`) its sidecar `STEM.profile.toml` or the
    /// nearest `ncthread.toml`, else the built-in defaults; with the command line's settings
    /// on top. Loaded before the program is read, so that a bad profile stops early.
    pub(crate) fn profile_for(&self, input: &Option<PathBuf>) -> Result<Profile, Fatal> {
        let path = match (&self.profile, input) {
            (Some(p), _) => Some(p.clone()),
            (None, _) if self.no_profile => None,
            (None, Some(file)) if !is_stdio(input) => ncthread::files::discover_profile(file),
            (None, _) => None,
        };
        if self.verbose {
            note(format!(
                "ncthread: profile: {}",
                path.as_ref()
                    .map_or("built-in defaults".into(), |p| p.display().to_string())
            ));
        }
        let mut profile = load_profile(&path, self.diagnostics)?;
        self.overrides().apply(&mut profile);
        Ok(profile)
    }

    /// The options of a conversion from `from` to `to`.
    pub(crate) fn options(
        &self,
        from: DialectId,
        to: DialectId,
        profile: Profile,
        target: &TargetArgs,
    ) -> ConvertOptions {
        ConvertOptions {
            from,
            to,
            profile,
            unsupported: unsupported(self.unsupported),
            renumber: target.renumber.unwrap_or_default(),
            round: target.round,
            nc31_comments: target.nc31_comments,
        }
    }
}

//! The `ncthread` command line: argument parsing and exit codes only.
//! Exit codes: 0 success, 1 the input has errors (nothing written), 2 usage or I/O error.

use std::io::{self, IsTerminal, Read, Write};
use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand, ValueEnum};

use ncthread::diag::{self, Format};
use ncthread::profile::Profile;
use ncthread::source::SourceFile;
use ncthread::{ConvertOptions, Dialect, Unsupported};

#[derive(Parser)]
#[command(
    name = "ncthread",
    version,
    about = "Lathe thread-cutting programs between the czech control, the НЦ-31 and ISO G-code: exact or refused."
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Convert one program (stdin to stdout by default).
    Convert(ConvertArgs),
    /// Print the machine motion of a program: every rapid, feed, thread and tap segment.
    Simulate(SimulateArgs),
    /// Prove a conversion (or check a hand conversion with --against): the two programs'
    /// simulated motions must agree within 0.001 mm and 0.01°.
    Verify(VerifyArgs),
}

#[derive(clap::Args)]
struct VerifyArgs {
    /// The source program; `-` or nothing reads stdin.
    input: Option<PathBuf>,
    /// The source dialect; `auto` chooses from the text.
    #[arg(long, value_enum)]
    from: SourceDialect,
    /// The target dialect.
    #[arg(long, value_enum)]
    to: TargetDialect,
    /// An existing program in the target dialect (e.g. the shop's hand conversion) to check
    /// instead of ncthread's own conversion.
    #[arg(long)]
    against: Option<PathBuf>,
    #[command(flatten)]
    target: TargetArgs,
    #[command(flatten)]
    common: CommonArgs,
}

#[derive(clap::Args)]
struct SimulateArgs {
    /// The program to read; `-` or nothing reads stdin.
    input: Option<PathBuf>,
    /// The dialect of the program; `auto` chooses from the text.
    #[arg(long, value_enum)]
    from: SourceDialect,
    /// `text`: one segment per line; `json`: one JSON object per segment.
    #[arg(long, value_enum, default_value_t = OutputFormat::Text)]
    format: OutputFormat,
    #[command(flatten)]
    common: CommonArgs,
}

/// Options every subcommand takes.
#[derive(clap::Args)]
struct CommonArgs {
    /// Machine profile (TOML) with the machine's constants: czech constant 8, nc31 units
    /// and parameters 6/7, ISO M code mappings.
    #[arg(long)]
    profile: Option<PathBuf>,
    /// How to print diagnostics on stderr.
    #[arg(long, value_enum, default_value_t = DiagnosticsFormat::Human)]
    diagnostics: DiagnosticsFormat,
    /// Undocumented constructs: refuse the program, or warn and keep them as opaque items.
    #[arg(long, value_enum, default_value_t = UnsupportedArg::Error)]
    unsupported: UnsupportedArg,
}

/// Options of the subcommands that write a program.
#[derive(clap::Args)]
struct TargetArgs {
    /// Block numbers for czech output from another dialect: START,STEP (default 10,10).
    #[arg(long, value_parser = parse_renumber)]
    renumber: Option<ncthread::dialect::czech::Renumber>,
    /// Round values the target cannot hold (czech: 0.001 mm; nc31: its units) with a
    /// warning instead of refusing.
    #[arg(long)]
    round: bool,
    /// nc31 output: write comments as `(` lines (for PC-side archives) instead of dropping
    /// them with a warning.
    #[arg(long)]
    nc31_comments: bool,
}

impl CommonArgs {
    /// The profile, loaded (before the input is read, so a bad profile stops early).
    fn profile(&self) -> Result<Profile, Fatal> {
        load_profile(&self.profile, self.diagnostics)
    }

    /// The options of a conversion from `from` to `to`.
    fn options(
        &self,
        from: Dialect,
        to: Dialect,
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

#[derive(Clone, Copy, ValueEnum)]
enum OutputFormat {
    Text,
    Json,
}

#[derive(clap::Args)]
struct ConvertArgs {
    /// The program to read; `-` or nothing reads stdin.
    input: Option<PathBuf>,
    /// The source dialect; `auto` chooses from the text (and says so on stderr when unsure).
    #[arg(long, value_enum)]
    from: SourceDialect,
    /// The target dialect.
    #[arg(long, value_enum)]
    to: TargetDialect,
    /// Where to write the program; `-` or nothing writes stdout.
    #[arg(short, long)]
    output: Option<PathBuf>,
    #[command(flatten)]
    target: TargetArgs,
    #[command(flatten)]
    common: CommonArgs,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum SourceDialect {
    Czech,
    Nc31,
    Iso,
    Auto,
}

#[derive(Clone, Copy, ValueEnum)]
enum TargetDialect {
    Czech,
    Nc31,
    Iso,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum DiagnosticsFormat {
    Human,
    Json,
}

#[derive(Clone, Copy, ValueEnum)]
enum UnsupportedArg {
    Error,
    Warn,
}

impl From<TargetDialect> for Dialect {
    fn from(d: TargetDialect) -> Dialect {
        match d {
            TargetDialect::Czech => Dialect::Czech,
            TargetDialect::Nc31 => Dialect::Nc31,
            TargetDialect::Iso => Dialect::Iso,
        }
    }
}

fn parse_renumber(text: &str) -> Result<ncthread::dialect::czech::Renumber, String> {
    let (start, step) = text
        .split_once(',')
        .ok_or("expected START,STEP, e.g. 10,10")?;
    let number = |t: &str| {
        t.trim()
            .parse::<u32>()
            .map_err(|_| format!("`{t}` is not a whole number"))
    };
    Ok(ncthread::dialect::czech::Renumber {
        start: number(start)?,
        step: number(step)?,
    })
}

/// A failure that is the user's invocation or the file system, not the program's content.
struct Fatal(String);

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Convert(args) => convert(args),
        Command::Simulate(args) => simulate(args),
        Command::Verify(args) => verify(args),
    };
    match result {
        Ok(code) => code,
        Err(Fatal(message)) => {
            eprintln!("ncthread: {message}");
            ExitCode::from(2)
        }
    }
}

fn is_stdio(path: &Option<PathBuf>) -> bool {
    path.as_ref().is_none_or(|p| p.as_os_str() == "-")
}

fn read_input(path: &Option<PathBuf>) -> Result<(String, Vec<u8>), Fatal> {
    if is_stdio(path) {
        let mut bytes = Vec::new();
        io::stdin()
            .read_to_end(&mut bytes)
            .map_err(|e| Fatal(format!("cannot read stdin: {e}")))?;
        return Ok(("<stdin>".into(), bytes));
    }
    let path = path.as_ref().expect("not stdio");
    let bytes =
        std::fs::read(path).map_err(|e| Fatal(format!("cannot read {}: {e}", path.display())))?;
    Ok((path.display().to_string(), bytes))
}

fn print_diagnostics(diags: &[diag::Diagnostic], format: DiagnosticsFormat) {
    let format = match format {
        DiagnosticsFormat::Human => Format::Human,
        DiagnosticsFormat::Json => Format::Json,
    };
    let color = format == Format::Human
        && io::stderr().is_terminal()
        && std::env::var_os("NO_COLOR").is_none();
    let text = diag::render_all(diags, format, color);
    let _ = io::stderr().write_all(text.as_bytes());
}

fn load_profile(path: &Option<PathBuf>, format: DiagnosticsFormat) -> Result<Profile, Fatal> {
    let Some(path) = path else {
        return Ok(Profile::default());
    };
    let text = std::fs::read_to_string(path)
        .map_err(|e| Fatal(format!("cannot read profile {}: {e}", path.display())))?;
    Profile::from_toml(&SourceFile::new(path.display().to_string(), text)).map_err(|diags| {
        print_diagnostics(&diags, format);
        Fatal(format!("the profile {} has errors", path.display()))
    })
}

/// Reads the input and decodes it in the given dialect, or chooses the dialect (`auto`).
fn read_source(
    input: &Option<PathBuf>,
    from: SourceDialect,
) -> Result<(SourceFile, Dialect), Fatal> {
    let (name, bytes) = read_input(input)?;
    let (text, from) = match from {
        SourceDialect::Czech => (
            ncthread::text::decode(&bytes, Dialect::Czech).0,
            Dialect::Czech,
        ),
        SourceDialect::Nc31 => (
            ncthread::text::decode(&bytes, Dialect::Nc31).0,
            Dialect::Nc31,
        ),
        SourceDialect::Iso => (ncthread::text::decode(&bytes, Dialect::Iso).0, Dialect::Iso),
        SourceDialect::Auto => {
            let (text, _, detection) = ncthread::text::decode_detect(&bytes);
            if !detection.certain {
                eprintln!(
                    "ncthread: --from auto: reading {name} as {} ({}); give --from to be sure",
                    detection.dialect, detection.reason
                );
            }
            (text, detection.dialect)
        }
    };
    Ok((SourceFile::new(name, text), from))
}

fn unsupported(arg: UnsupportedArg) -> Unsupported {
    match arg {
        UnsupportedArg::Error => Unsupported::Error,
        UnsupportedArg::Warn => Unsupported::Warn,
    }
}

fn convert(args: ConvertArgs) -> Result<ExitCode, Fatal> {
    let profile = args.common.profile()?;
    let (src, from) = read_source(&args.input, args.from)?;
    let options = args
        .common
        .options(from, args.to.into(), profile, &args.target);
    let conversion = ncthread::convert(&src, &options);
    print_diagnostics(&conversion.diagnostics, args.common.diagnostics);
    let Some(output) = conversion.output else {
        return Ok(ExitCode::from(1));
    };
    write_output(&args.output, output.as_bytes())?;
    Ok(ExitCode::SUCCESS)
}

fn simulate(args: SimulateArgs) -> Result<ExitCode, Fatal> {
    let profile = args.common.profile()?;
    let (src, from) = read_source(&args.input, args.from)?;
    let (program, mut diags) =
        ncthread::parse(&src, from, &profile, unsupported(args.common.unsupported));
    if diag::has_errors(&diags) {
        diag::sort(&mut diags);
        print_diagnostics(&diags, args.common.diagnostics);
        return Ok(ExitCode::from(1));
    }
    let simulation = ncthread::sim::simulate(&program);
    diags.extend(simulation.problems.iter().map(|p| p.diagnostic(&src)));
    diag::sort(&mut diags);
    print_diagnostics(&diags, args.common.diagnostics);
    let mut out = String::new();
    for segment in &simulation.segments {
        match args.format {
            OutputFormat::Text => out.push_str(&segment.to_text()),
            OutputFormat::Json => out.push_str(&segment.to_json().to_string()),
        }
        out.push('\n');
    }
    write_output(&None, out.as_bytes())?;
    Ok(ExitCode::SUCCESS)
}

fn verify(args: VerifyArgs) -> Result<ExitCode, Fatal> {
    let profile = args.common.profile()?;
    let (src, from) = read_source(&args.input, args.from)?;
    let to: Dialect = args.to.into();
    let against = match &args.against {
        Some(path) => {
            let bytes = std::fs::read(path)
                .map_err(|e| Fatal(format!("cannot read {}: {e}", path.display())))?;
            let text = ncthread::text::decode(&bytes, to).0;
            Some(SourceFile::new(path.display().to_string(), text))
        }
        None => None,
    };
    let options = args.common.options(from, to, profile, &args.target);
    let v = ncthread::verify(&src, &options, against.as_ref());
    print_diagnostics(&v.diagnostics, args.common.diagnostics);
    let other = against
        .as_ref()
        .map_or(format!("ncthread's {to} conversion"), |a| a.name.clone());
    let (text, code) = match &v.outcome {
        ncthread::Outcome::Equivalent { segments } => (
            format!(
                "equivalent: {} ({from}) and {other} ({to}) make the same motion ({segments} segments after normalising; 0.001 mm, 0.01°)\n",
                src.name
            ),
            ExitCode::SUCCESS,
        ),
        ncthread::Outcome::Different(d) => {
            let seg = |s: &Option<ncthread::sim::Segment>| {
                s.map_or("(nothing: the program has ended)".to_string(), |s| {
                    s.to_text()
                })
            };
            (
                format!(
                    "DIFFERENT: {}\n  {} ({from}): {}\n  {other} ({to}): {}\n  first difference: {d}\n",
                    d.what,
                    src.name,
                    seg(&d.left),
                    seg(&d.right),
                ),
                ExitCode::from(1),
            )
        }
        ncthread::Outcome::Refused => (
            "not verified: a program could not be read or converted (see the errors above)\n"
                .to_string(),
            ExitCode::from(1),
        ),
    };
    write_output(&None, text.as_bytes())?;
    Ok(code)
}

fn write_output(path: &Option<PathBuf>, bytes: &[u8]) -> Result<(), Fatal> {
    if is_stdio(path) {
        let mut out = io::stdout().lock();
        return match out.write_all(bytes).and_then(|()| out.flush()) {
            // The reader (e.g. `head`) has what it wanted.
            Err(e) if e.kind() == io::ErrorKind::BrokenPipe => Ok(()),
            Err(e) => Err(Fatal(format!("cannot write stdout: {e}"))),
            Ok(()) => Ok(()),
        };
    }
    let path = path.as_ref().expect("not stdio");
    std::fs::write(path, bytes).map_err(|e| Fatal(format!("cannot write {}: {e}", path.display())))
}

//! The `ncthread` command line: argument parsing and exit codes only.
//! Exit codes: 0 success, 1 the input has errors (nothing written), 2 usage or I/O error.

use std::io::{self, IsTerminal, Read, Write};
use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand, ValueEnum};

use clap::builder::TypedValueParser as _;
use ncthread::diag::{self, Format};
use ncthread::files::io_error;
use ncthread::profile::{BlockDelete, Profile};
use ncthread::source::SourceFile;
use ncthread::text::{Eol, OutputOptions, TextEncoding};
use ncthread::{ConvertOptions, DialectId, Unsupported};

/// The first line of `ncthread -h`, and (lower case) of the manual page's NAME.
const ABOUT: &str = "Convert lathe thread-cutting programs between the czech control, the НЦ-31, FANUC and ISO G-code (LinuxCNC): exact or refused";

const LONG_ABOUT: &str = "Convert lathe thread-cutting programs between the czech control, the НЦ-31, FANUC and ISO G-code (LinuxCNC): exact or refused.

Every conversion is exactly equivalent or refused with a diagnostic that names the block, the construct and why. `verify` proves a conversion by simulating both programs; `check`, `explain` and `plot` look at one; `batch` converts a whole archive. README.md is the manual: every option, every profile key and every diagnostic code.";

/// An example of a command line, for `-h` (the `short` ones), `--help` and the manual page.
struct Example {
    command: &'static str,
    what: &'static str,
    short: bool,
}

const fn ex(command: &'static str, what: &'static str, short: bool) -> Example {
    Example {
        command,
        what,
        short,
    }
}

const TOP_EXAMPLES: &[Example] = &[
    ex(
        "ncthread convert P0001.NC --from czech --to iso -o P0001.ngc",
        "one program",
        true,
    ),
    ex(
        "ncthread verify P0001.NC --from czech --to fanuc",
        "prove the conversion: both programs make the same motion",
        true,
    ),
    ex(
        "ncthread batch archive/ converted/ --from auto --to fanuc --html report/",
        "a whole archive, with a report to read in a browser",
        true,
    ),
    ex(
        "ncthread check programs/",
        "lint a folder of programs",
        false,
    ),
    ex(
        "ncthread explain O1002 --from fanuc",
        "the passes of every thread",
        false,
    ),
    ex(
        "ncthread man --dir ~/.local/share/man/man1",
        "install the manual pages",
        false,
    ),
];

const CONVERT_EXAMPLES: &[Example] = &[
    ex(
        "ncthread convert P0001.NC --from czech --to iso -o P0001.ngc",
        "write a file",
        true,
    ),
    ex(
        "ncthread convert --from auto --to fanuc < P0001.NC > O0001.nc",
        "a pipe filter: stdin to stdout",
        true,
    ),
    ex(
        "ncthread convert P0001.NC --from czech --to nc31 --round",
        "round what the НЦ-31's 0.01 mm cannot hold, with one warning",
        false,
    ),
    ex(
        "ncthread convert P0001.NC --from czech --to czech --output-encoding cp852 --eol crlf",
        "for a DOS PC",
        false,
    ),
    ex(
        "ncthread convert --from auto --to iso --stdin-filename lathe2/P0001.NC",
        "a program on stdin, named to find its profile beside it",
        false,
    ),
];

const SIMULATE_EXAMPLES: &[Example] = &[
    ex(
        "ncthread simulate G31.NC --from nc31",
        "every rapid, feed, thread and tap segment",
        true,
    ),
    ex(
        "ncthread simulate P0001.NC --from auto --format json",
        "one JSON object per segment",
        false,
    ),
];

const VERIFY_EXAMPLES: &[Example] = &[
    ex(
        "ncthread verify P0001.NC --from czech --to iso",
        "prove ncthread's conversion",
        true,
    ),
    ex(
        "ncthread verify P0001.NC --from czech --to iso --against P0001.ngc",
        "check the shop's hand conversion",
        true,
    ),
    ex(
        "ncthread verify P0001.NC --from czech --to iso --against P0001.ngc --plot diff.svg",
        "draw the first difference",
        false,
    ),
    ex(
        "ncthread verify P0001.NC --from czech --to iso --rs274",
        "LinuxCNC's interpreter as a second judge",
        false,
    ),
];

const CHECK_EXAMPLES: &[Example] = &[
    ex(
        "ncthread check programs/",
        "every program of a folder",
        true,
    ),
    ex(
        "ncthread check P0001.NC --from czech --diagnostics json",
        "one JSON object per diagnostic, for an editor or CI",
        true,
    ),
    ex(
        "ncthread check --glob '**/O*' archive/",
        "the files a glob chooses",
        false,
    ),
];

const EXPLAIN_EXAMPLES: &[Example] = &[
    ex(
        "ncthread explain G31.NC --from nc31",
        "the pass table of every thread",
        true,
    ),
    ex(
        "ncthread explain P0001.NC --from czech --crest 36",
        "depths from the crest of an M36 thread written as passes",
        true,
    ),
    ex(
        "ncthread explain P0001.NC --from czech --format csv",
        "one row per pass",
        false,
    ),
];

const PLOT_EXAMPLES: &[Example] = &[
    ex(
        "ncthread plot G31.NC --from nc31 -o g31.svg",
        "the toolpath, the passes and their cross-section",
        true,
    ),
    ex(
        "ncthread plot P0001.NC --from czech --operation 2 -o p2.svg",
        "the second operation in detail",
        false,
    ),
];

const BATCH_EXAMPLES: &[Example] = &[
    ex(
        "ncthread batch archive/ converted/ --from auto --to iso",
        "every program of a tree, in parallel",
        true,
    ),
    ex(
        "ncthread batch archive/ converted/ --from czech --to fanuc --report report.json --html report/",
        "with a JSON and an HTML report",
        true,
    ),
    ex(
        "ncthread batch archive/ converted/ --from auto --to iso --dry-run --verbose",
        "say what would be written, and write nothing",
        false,
    ),
    ex(
        "ncthread batch archive/ converted/ --from fanuc --to iso --glob 'O*'",
        "take the files a glob chooses",
        false,
    ),
];

/// The examples as `-h` (`long`: `--help`) prints them after the options.
fn examples(list: &[Example], long: bool) -> String {
    let chosen: Vec<&Example> = list.iter().filter(|e| long || e.short).collect();
    let mut text = String::from("\x1b[1m\x1b[4mExamples:\x1b[0m\n");
    for e in chosen {
        if long {
            text.push_str(&format!("  {}\n          {}\n", e.command, e.what));
        } else {
            text.push_str(&format!("  {}\n", e.command));
        }
    }
    if !long {
        text.push_str(
            "\n--help for every option's details and more examples; README.md is the manual.",
        );
    }
    text.trim_end().to_string()
}

/// The examples of a command, by its name (`ncthread` for the top).
fn examples_of(name: &str) -> &'static [Example] {
    match name {
        "convert" => CONVERT_EXAMPLES,
        "simulate" => SIMULATE_EXAMPLES,
        "verify" => VERIFY_EXAMPLES,
        "check" => CHECK_EXAMPLES,
        "explain" => EXPLAIN_EXAMPLES,
        "plot" => PLOT_EXAMPLES,
        "batch" => BATCH_EXAMPLES,
        "ncthread" => TOP_EXAMPLES,
        _ => &[],
    }
}

#[derive(Parser)]
#[command(
    name = "ncthread",
    version,
    about = ABOUT,
    long_about = LONG_ABOUT,
    after_help = examples(TOP_EXAMPLES, false),
    after_long_help = examples(TOP_EXAMPLES, true),
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
    /// When to colour diagnostics: `auto` on a terminal unless NO_COLOR is set (CLICOLOR_FORCE
    /// colours a pipe too), `always`, or `never`.
    #[arg(long, value_enum, global = true, default_value_t = ColorArg::Auto, value_name = "WHEN")]
    color: ColorArg,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum ColorArg {
    Auto,
    Always,
    Never,
}

/// The `--color` of this run, set once in `main`.
static COLOR: std::sync::OnceLock<ColorArg> = std::sync::OnceLock::new();

/// Whether to colour what goes to a stream that is (`terminal`) a terminal: `--color always`
/// or `never` as said; `auto` as <https://no-color.org> and <https://bixense.com/clicolors/>
/// say, in anstream's order: NO_COLOR (set, not empty) never, CLICOLOR_FORCE (set, not `0`)
/// always, CLICOLOR=0 or TERM=dumb never, else a terminal.
fn colour_wanted(
    choice: ColorArg,
    terminal: bool,
    env: impl Fn(&str) -> Option<std::ffi::OsString>,
) -> bool {
    let set = |name: &str| env(name).filter(|v| !v.is_empty());
    match choice {
        ColorArg::Always => true,
        ColorArg::Never => false,
        ColorArg::Auto => {
            if set("NO_COLOR").is_some() {
                false
            } else if set("CLICOLOR_FORCE").is_some_and(|v| v != "0") {
                true
            } else if env("CLICOLOR").is_some_and(|v| v == "0")
                || env("TERM").is_some_and(|v| v == "dumb")
            {
                false
            } else {
                terminal
            }
        }
    }
}

/// Whether to colour stderr (`false`: stdout).
fn colour(stderr: bool) -> bool {
    let terminal = if stderr {
        io::stderr().is_terminal()
    } else {
        io::stdout().is_terminal()
    };
    colour_wanted(
        COLOR.get().copied().unwrap_or(ColorArg::Auto),
        terminal,
        |name| std::env::var_os(name),
    )
}

/// `--color WHEN` from the raw arguments, for clap's own help and errors (printed before
/// the arguments are parsed).
fn colour_argument(args: &[std::ffi::OsString]) -> Option<ColorArg> {
    let mut args = args.iter().map(|a| a.to_string_lossy());
    while let Some(arg) = args.next() {
        if arg == "--" {
            break;
        }
        let value = match arg.strip_prefix("--color") {
            Some("") => args.next().map(|v| v.into_owned()),
            Some(rest) => rest.strip_prefix('=').map(str::to_string),
            None => continue,
        };
        return value.and_then(|v| ColorArg::from_str(&v, true).ok());
    }
    None
}

#[derive(Subcommand)]
enum Command {
    /// Convert one program (stdin to stdout by default).
    #[command(after_help = examples(CONVERT_EXAMPLES, false), after_long_help = examples(CONVERT_EXAMPLES, true))]
    Convert(ConvertArgs),
    /// Print the machine motion of a program: every rapid, feed, thread and tap segment.
    #[command(after_help = examples(SIMULATE_EXAMPLES, false), after_long_help = examples(SIMULATE_EXAMPLES, true))]
    Simulate(SimulateArgs),
    /// Prove a conversion (or check a hand conversion with --against): the two programs'
    /// simulated motions must agree within 0.001 mm and 0.01°.
    #[command(after_help = examples(VERIFY_EXAMPLES, false), after_long_help = examples(VERIFY_EXAMPLES, true))]
    Verify(VerifyArgs),
    /// Lint programs and folders of programs: every diagnostic of each file on stdout (the
    /// count on stderr), no output program.
    #[command(after_help = examples(CHECK_EXAMPLES, false), after_long_help = examples(CHECK_EXAMPLES, true))]
    Check(CheckArgs),
    /// Print every thread operation (a cycle, a tap, a thread written as single passes) with
    /// its pass table, and every roughing cycle with its cuts.
    #[command(after_help = examples(EXPLAIN_EXAMPLES, false), after_long_help = examples(EXPLAIN_EXAMPLES, true))]
    Explain(ExplainArgs),
    /// Draw a program as an SVG: the toolpath, and a thread operation's passes in XZ and in
    /// cross-section with a legend.
    #[command(after_help = examples(PLOT_EXAMPLES, false), after_long_help = examples(PLOT_EXAMPLES, true))]
    Plot(PlotArgs),
    /// Convert a whole tree of programs into a mirrored tree, in parallel.
    #[command(after_help = examples(BATCH_EXAMPLES, false), after_long_help = examples(BATCH_EXAMPLES, true))]
    Batch(BatchArgs),
    /// Print what each dialect reads and writes (the capability table, Markdown): what a
    /// target refuses, and under which code.
    Dialects {
        /// A machine profile: a row may depend on the machine (czech constant 8).
        #[arg(long)]
        profile: Option<PathBuf>,
    },
    /// Print a shell completion script (bash, zsh, fish, elvish, powershell).
    Completions {
        #[arg(value_enum)]
        shell: clap_complete::Shell,
    },
    /// Print a manual page (roff): ncthread(1), or a subcommand's (`ncthread man convert`);
    /// `--dir DIR` writes every page there (ncthread.1, ncthread-convert.1, …).
    Man {
        /// The subcommand whose page to print.
        subcommand: Option<String>,
        /// Write every page into this folder instead.
        #[arg(long, value_name = "DIR", conflicts_with = "subcommand")]
        dir: Option<PathBuf>,
    },
}

#[derive(clap::Args)]
struct CheckArgs {
    /// The programs to check, and folders of programs (walked as `batch` walks them); `-` or
    /// nothing reads stdin.
    files: Vec<PathBuf>,
    /// The dialect of the programs; `auto` chooses per file from the text.
    #[arg(long, alias = "dialect", ignore_case = true, value_parser = source_dialect(), default_value = "auto")]
    from: SourceDialect,
    /// Print the diagnostics only: no summary line, no notes.
    #[arg(long, short = 'q')]
    quiet: bool,
    #[command(flatten)]
    stdin: StdinArgs,
    #[command(flatten)]
    selection: SelectionArgs,
    #[command(flatten)]
    common: CommonArgs,
}

/// The name of a program that comes on stdin.
#[derive(clap::Args)]
struct StdinArgs {
    /// The name of the program read from stdin (as ruff's): the file its diagnostics name,
    /// where its sidecar profile or `ncthread.toml` is looked for, and its extension for
    /// `--from auto`. Ignored for a program read from a file.
    #[arg(long, value_name = "NAME")]
    stdin_filename: Option<PathBuf>,
}

impl StdinArgs {
    /// The path the program `input` goes by: the file, or the name given to stdin.
    fn named(&self, input: &Option<PathBuf>) -> Option<PathBuf> {
        if is_stdio(input) {
            self.stdin_filename.clone()
        } else {
            input.clone()
        }
    }
}

/// Which files of a folder are programs.
#[derive(clap::Args)]
struct SelectionArgs {
    /// Take the files whose path below the folder matches this glob (gitignore syntax, e.g.
    /// `**/*.NC`) instead of the dialect's extensions; `!GLOB` leaves files out. Repeatable.
    #[arg(long, value_name = "GLOB")]
    glob: Vec<String>,
    /// As --glob, matched without regard to case.
    #[arg(long, value_name = "GLOB")]
    iglob: Vec<String>,
}

impl SelectionArgs {
    fn selection(&self, from: Option<DialectId>) -> ncthread::files::Selection {
        ncthread::files::Selection {
            globs: self.glob.clone(),
            iglobs: self.iglob.clone(),
            extensions: ncthread::batch::program_extensions(from),
        }
    }
}

#[derive(clap::Args)]
struct BatchArgs {
    /// The folder of programs to convert (walked recursively; never written to).
    src_dir: PathBuf,
    /// The folder the converted tree is written to (created when missing).
    out_dir: PathBuf,
    /// The source dialect; `auto` chooses per file from the text.
    #[arg(long, ignore_case = true, value_parser = source_dialect())]
    from: SourceDialect,
    /// The target dialect.
    #[arg(long, ignore_case = true, value_parser = target_dialect())]
    to: TargetDialect,
    /// Worker threads (default: one per core).
    #[arg(long, short = 'j')]
    jobs: Option<usize>,
    /// Write a JSON report of every file here. A re-run reads it back: a skipped file whose
    /// output is up to date keeps its row.
    #[arg(long, value_name = "FILE")]
    report: Option<PathBuf>,
    /// Overwrite outputs that exist.
    #[arg(long)]
    force: bool,
    #[arg(long, value_name = "EXT", help = ext_help())]
    ext: Option<String>,
    /// Convert, but write nothing: list what would be written.
    #[arg(long)]
    dry_run: bool,
    /// Print only what failed (each failed file's errors or reason): no progress bar, no
    /// notes, no summary. The exit code says the rest.
    #[arg(long, short = 'q', conflicts_with = "verbose")]
    quiet: bool,
    #[command(flatten)]
    selection: SelectionArgs,
    /// Also write a static HTML report into this folder (`index.html`, the plots and the
    /// page's data `report.json`): each file's status, encoding, profile and diagnostics, and
    /// each converted program's `explain` table and plot. A re-run reads the data back: a
    /// skipped file whose output is up to date keeps its row.
    #[arg(long, value_name = "DIR")]
    html: Option<PathBuf>,
    #[command(flatten)]
    target: TargetArgs,
    #[command(flatten)]
    output: OutputArgs,
    #[command(flatten)]
    common: CommonArgs,
}

/// How output programs become bytes.
#[derive(clap::Args)]
struct OutputArgs {
    /// The output's encoding (an encoding_rs/WHATWG label, or IBM852); default UTF-8.
    #[arg(long, value_parser = parse_output_encoding)]
    output_encoding: Option<TextEncoding>,
    /// Write a character the output encoding lacks as its ASCII transliteration (Č → C)
    /// instead of refusing.
    #[arg(long)]
    transliterate: bool,
    /// Line endings: `keep` the input's, or `lf`, `crlf`.
    #[arg(long, value_enum, default_value_t = EolArg::Keep)]
    eol: EolArg,
}

#[derive(Clone, Copy, ValueEnum)]
enum EolArg {
    Keep,
    Lf,
    Crlf,
}

impl OutputArgs {
    fn options(&self) -> OutputOptions {
        OutputOptions {
            encoding: self.output_encoding,
            transliterate: self.transliterate,
            eol: match self.eol {
                EolArg::Keep => Eol::Keep,
                EolArg::Lf => Eol::Lf,
                EolArg::Crlf => Eol::CrLf,
            },
        }
    }
}

fn parse_encoding(label: &str) -> Result<TextEncoding, String> {
    TextEncoding::for_label(label).ok_or_else(|| {
        format!("`{label}` is not an encoding label (e.g. utf-8, windows-1250, ibm866, ibm852)")
    })
}

fn parse_output_encoding(label: &str) -> Result<TextEncoding, String> {
    let e = parse_encoding(label)?;
    if !e.can_encode() {
        return Err(format!(
            "ncthread cannot write {e}; choose utf-8 or a single-byte encoding"
        ));
    }
    Ok(e)
}

#[derive(clap::Args)]
struct VerifyArgs {
    /// The source program; `-` or nothing reads stdin.
    input: Option<PathBuf>,
    /// The source dialect; `auto` chooses from the text.
    #[arg(long, ignore_case = true, value_parser = source_dialect())]
    from: SourceDialect,
    /// The target dialect.
    #[arg(long, ignore_case = true, value_parser = target_dialect())]
    to: TargetDialect,
    /// An existing program in the target dialect (e.g. the shop's hand conversion) to check
    /// instead of ncthread's own conversion.
    #[arg(long)]
    against: Option<PathBuf>,
    /// Also run every ISO program of the comparison through LinuxCNC's interpreter (`rs274`
    /// on the PATH, or the command in $NCTHREAD_RS274) and hold its motion against
    /// ncthread's simulation of the other program: a second, independent judge.
    #[arg(long)]
    rs274: bool,
    /// Also write an SVG of both motions overlaid, the first difference marked (a file: the
    /// verdict goes to stdout).
    #[arg(long, value_name = "FILE.svg", value_parser = not_stdout)]
    plot: Option<PathBuf>,
    /// How far positions may differ, in mm (default 0.001). A conversion with --round is
    /// allowed the deviation its rounding reported.
    #[arg(long, value_name = "MM", value_parser = parse_length)]
    tolerance: Option<ncthread::fixed::Length>,
    #[command(flatten)]
    target: TargetArgs,
    #[command(flatten)]
    stdin: StdinArgs,
    #[command(flatten)]
    common: CommonArgs,
}

#[derive(clap::Args)]
struct ExplainArgs {
    /// The program to read; `-` or nothing reads stdin.
    input: Option<PathBuf>,
    /// The dialect of the program; `auto` chooses from the text.
    #[arg(long, ignore_case = true, value_parser = source_dialect())]
    from: SourceDialect,
    /// `text`: a heading and a table per operation; `json`: `{ "operations": [ … ] }`;
    /// `csv`: one row per pass.
    #[arg(long, value_enum, default_value_t = ExplainFormat::Text)]
    format: ExplainFormat,
    /// Draw the text tables in ASCII instead of UTF-8 box drawing.
    #[arg(long)]
    plain: bool,
    /// The crest diameter of a thread written as single passes, in mm, which such a program
    /// does not say: the major diameter of an external thread (36 for M36), the minor (bore)
    /// diameter of an internal one. Without it, depths are counted from the first pass.
    #[arg(long, value_name = "MM", value_parser = parse_length)]
    crest: Option<ncthread::fixed::Length>,
    #[command(flatten)]
    stdin: StdinArgs,
    #[command(flatten)]
    common: CommonArgs,
}

#[derive(clap::Args)]
struct PlotArgs {
    /// The program to read; `-` or nothing reads stdin.
    input: Option<PathBuf>,
    /// The dialect of the program; `auto` chooses from the text.
    #[arg(long, ignore_case = true, value_parser = source_dialect())]
    from: SourceDialect,
    /// Where to write the SVG; `-` or nothing writes stdout.
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// The operation (as `explain` numbers them) drawn in detail; default the first thread.
    #[arg(long, value_name = "N")]
    operation: Option<usize>,
    /// The crest diameter of a thread written as single passes (see `explain --crest`).
    #[arg(long, value_name = "MM", value_parser = parse_length)]
    crest: Option<ncthread::fixed::Length>,
    #[command(flatten)]
    stdin: StdinArgs,
    #[command(flatten)]
    common: CommonArgs,
}

#[derive(Clone, Copy, ValueEnum)]
enum ExplainFormat {
    Text,
    Json,
    Csv,
}

fn not_stdout(text: &str) -> Result<PathBuf, String> {
    if text == "-" {
        return Err("give a file: the verdict is written on stdout".into());
    }
    Ok(PathBuf::from(text))
}

fn parse_length(text: &str) -> Result<ncthread::fixed::Length, String> {
    ncthread::fixed::Decimal::parse(text)
        .and_then(|d| d.to_length().ok())
        .filter(|l| l.0 > 0)
        .ok_or_else(|| format!("`{text}` is not a positive length in mm (at most 4 decimals)"))
}

#[derive(clap::Args)]
struct SimulateArgs {
    /// The program to read; `-` or nothing reads stdin.
    input: Option<PathBuf>,
    /// The dialect of the program; `auto` chooses from the text.
    #[arg(long, ignore_case = true, value_parser = source_dialect())]
    from: SourceDialect,
    /// `text`: one segment per line; `json`: one JSON object per segment.
    #[arg(long, value_enum, default_value_t = OutputFormat::Text)]
    format: OutputFormat,
    #[command(flatten)]
    stdin: StdinArgs,
    #[command(flatten)]
    common: CommonArgs,
}

/// Options every subcommand takes.
#[derive(clap::Args)]
struct CommonArgs {
    /// Machine profile (TOML): what differs per machine, in [czech], [nc31], [iso] and
    /// [fanuc] sections. Without it, a program's sidecar `STEM.profile.toml`, else the
    /// nearest `ncthread.toml` in its folder or above, else the built-in defaults.
    ///
    /// [czech]: machine constant 8 (runout and entry angles), the first motion mode, gear
    /// range M codes, and the machine's forms of coolant, arcs, dwell and surface speed.
    /// [nc31]: the units of X Z P and F, machine parameters 6 and 7 (infeed angle, runout),
    /// the G31 retract and pass schedule, gear range M codes, coolant, arcs, 45° chamfers,
    /// G25 repeats. [iso]: M code mappings, the tool change, the block delete switch,
    /// subroutine folders. [fanuc]: words without a decimal point, G92's thread chamfer, the
    /// tool offset number, the program number, nose radius compensation, mist coolant.
    /// Without a key, what needs it is refused by name. README.md lists every key.
    #[arg(long, value_name = "FILE")]
    profile: Option<PathBuf>,
    /// Use the built-in defaults: no sidecar or `ncthread.toml` is looked for.
    #[arg(long, conflicts_with = "profile")]
    no_profile: bool,
    /// Say which profile (and, in batch and check, which encoding) each program used; batch
    /// lists every file, with its output or why it was skipped or left out.
    #[arg(long, short = 'v')]
    verbose: bool,
    /// How to print diagnostics (on stderr; `check` prints them on stdout).
    #[arg(long, value_enum, default_value_t = DiagnosticsFormat::Human)]
    diagnostics: DiagnosticsFormat,
    /// Print at most N errors of each file, then how many more there are (0: every one).
    /// Warnings and `--diagnostics json` are not limited.
    #[arg(long, value_name = "N", default_value_t = 50)]
    max_errors: usize,
    /// Undocumented constructs: refuse the program, or warn and keep them as opaque items.
    #[arg(long, value_enum, default_value_t = UnsupportedArg::Error)]
    unsupported: UnsupportedArg,
    #[arg(long, value_name = "LABEL", value_parser = parse_encoding, help = encoding_help())]
    encoding: Option<TextEncoding>,
    /// ISO input: the block delete switch the program runs with. Lines that start with `/`
    /// run when it is off and are skipped when it is on; without it (or the profile's
    /// `[iso] block_delete`) such a line is refused.
    #[arg(long, value_enum)]
    block_delete: Option<BlockDeleteArg>,
    /// ISO input: a folder that holds subroutine files (`o<name> call` reads `name.ngc`
    /// from the first folder that has it), as LinuxCNC's SUBROUTINE_PATH; repeatable.
    #[arg(long, value_name = "DIR")]
    subroutine_path: Vec<PathBuf>,
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum BlockDeleteArg {
    Off,
    On,
}

/// Options of the subcommands that write a program.
#[derive(clap::Args)]
struct TargetArgs {
    /// Block numbers for czech output from another dialect: START,STEP (default 10,10).
    #[arg(long, value_parser = parse_renumber)]
    renumber: Option<ncthread::dialect::Renumber>,
    /// Round values the target cannot hold onto its grid, with one warning giving the
    /// largest deviation, instead of refusing them.
    ///
    /// czech and fanuc: lengths to 0.001 mm, leads and feeds to 0.0001 mm; nc31: whole units
    /// of the profile (0.01 mm, leads 0.0001 mm); iso holds every value and never rounds. A
    /// rounded lead's deviation is its drift at the thread's end; a czech thread start moved
    /// onto the grid changes its start angle I so that the pass cuts the same helix; an arc
    /// whose written R would move its centre is rounded too. `verify --round` allows the
    /// deviation the rounding reported.
    #[arg(long)]
    round: bool,
    /// nc31 output: write comments as `(` lines (for PC-side archives) instead of dropping
    /// them with a warning.
    #[arg(long)]
    nc31_comments: bool,
}

impl CommonArgs {
    /// What the command line says of the machine on top of any profile.
    fn overrides(&self) -> ncthread::profile::Overrides {
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
    fn profile_for(&self, input: &Option<PathBuf>) -> Result<Profile, Fatal> {
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
    fn options(
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
    #[arg(long, ignore_case = true, value_parser = source_dialect())]
    from: SourceDialect,
    /// The target dialect.
    #[arg(long, ignore_case = true, value_parser = target_dialect())]
    to: TargetDialect,
    /// Where to write the program; `-` or nothing writes stdout.
    #[arg(short, long)]
    output: Option<PathBuf>,
    #[command(flatten)]
    target: TargetArgs,
    #[command(flatten)]
    output_format: OutputArgs,
    #[command(flatten)]
    stdin: StdinArgs,
    #[command(flatten)]
    common: CommonArgs,
}

/// A source dialect (`--from`, `--dialect`): one of the registry's, or `auto` (`None`).
#[derive(Clone, Copy, PartialEq, Eq)]
struct SourceDialect(Option<DialectId>);

/// A target dialect (`--to`).
#[derive(Clone, Copy, PartialEq, Eq)]
struct TargetDialect(DialectId);

/// `--ext`'s help: each target's own extension, from the registry.
fn ext_help() -> String {
    let each: Vec<String> = ncthread::dialect::ALL
        .iter()
        .map(|d| format!("{} for {}", d.extension(), d.id()))
        .collect();
    format!(
        "The outputs' extension (default: the target's, {})",
        each.join(", ")
    )
}

/// `--encoding`'s help: each dialect's legacy encoding, from the registry.
fn encoding_help() -> String {
    let each: Vec<String> = ncthread::dialect::ALL
        .iter()
        .map(|d| format!("{} {}", d.id(), d.legacy_encoding()))
        .collect();
    format!(
        "The input's encoding (an encoding_rs/WHATWG label, or IBM852); default: UTF-8 when the bytes are valid UTF-8, else the dialect's legacy one ({})",
        each.join(", ")
    )
}

/// The ids of every dialect in the registry, for clap.
fn dialect_ids() -> Vec<&'static str> {
    ncthread::dialect::ALL
        .iter()
        .map(|d| d.id().as_str())
        .collect()
}

fn source_dialect() -> impl clap::builder::TypedValueParser<Value = SourceDialect> {
    let mut ids = dialect_ids();
    ids.push("auto");
    clap::builder::PossibleValuesParser::new(ids).map(|id: String| {
        SourceDialect(ncthread::dialect::by_id(&id.to_ascii_lowercase()).map(|d| d.id()))
    })
}

fn target_dialect() -> impl clap::builder::TypedValueParser<Value = TargetDialect> {
    clap::builder::PossibleValuesParser::new(dialect_ids()).map(|id: String| {
        TargetDialect(
            ncthread::dialect::by_id(&id.to_ascii_lowercase())
                .map_or(ncthread::dialect::ALL[0].id(), |d| d.id()),
        )
    })
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

impl SourceDialect {
    /// The dialect given, or `None` for `auto`.
    fn known(self) -> Option<DialectId> {
        self.0
    }
}

impl From<TargetDialect> for DialectId {
    fn from(d: TargetDialect) -> DialectId {
        d.0
    }
}

fn parse_renumber(text: &str) -> Result<ncthread::dialect::Renumber, String> {
    let (start, step) = text
        .split_once(',')
        .ok_or("expected START,STEP, e.g. 10,10")?;
    let number = |t: &str| {
        t.trim()
            .parse::<u32>()
            .map_err(|_| format!("`{t}` is not a whole number"))
    };
    let (start, step) = (number(start)?, number(step)?);
    if step == 0 {
        return Err("STEP must be at least 1: blocks need numbers that grow".into());
    }
    // Block numbers are written as N and up to 9 digits (the czech control's N words are
    // read as whole numbers; larger ones would not read back).
    if start > 999_999_999 {
        return Err(format!("START {start} has more than 9 digits"));
    }
    Ok(ncthread::dialect::Renumber { start, step })
}

/// A failure that is the user's invocation or the file system, not the program's content.
enum Fatal {
    /// A usage or I/O problem (exit 2), said on stderr.
    Usage(String),
    /// The input was refused and its diagnostics printed (exit 1).
    Refused,
}

fn main() -> ExitCode {
    let args: Vec<std::ffi::OsString> = std::env::args_os().collect();
    let mut command = <Cli as clap::CommandFactory>::command();
    command = match colour_argument(&args) {
        Some(ColorArg::Always) => command.color(clap::ColorChoice::Always),
        Some(ColorArg::Never) => command.color(clap::ColorChoice::Never),
        _ => command,
    };
    let cli = command
        .try_get_matches_from(&args)
        .and_then(|m| <Cli as clap::FromArgMatches>::from_arg_matches(&m))
        .unwrap_or_else(|e| e.exit());
    let _ = COLOR.set(cli.color);
    let result = match cli.command {
        Command::Convert(args) => convert(args),
        Command::Simulate(args) => simulate(args),
        Command::Verify(args) => verify(args),
        Command::Check(args) => check(args),
        Command::Explain(args) => explain(args),
        Command::Plot(args) => plot(args),
        Command::Batch(args) => batch(args),
        Command::Completions { shell } => {
            let mut cmd = <Cli as clap::CommandFactory>::command();
            let mut out = Vec::new();
            clap_complete::generate(shell, &mut cmd, "ncthread", &mut out);
            write_output(&None, &out).map(|()| ExitCode::SUCCESS)
        }
        Command::Dialects { profile } => load_profile(&profile, DiagnosticsFormat::Human)
            .and_then(|profile| {
                write_output(
                    &None,
                    ncthread::dialect::capability_table(&profile).as_bytes(),
                )
            })
            .map(|()| ExitCode::SUCCESS),
        Command::Man { subcommand, dir } => man(subcommand, dir),
    };
    match result {
        Ok(code) => code,
        Err(Fatal::Usage(message)) => {
            note(format!("error: {message}"));
            ExitCode::from(2)
        }
        Err(Fatal::Refused) => ExitCode::from(1),
    }
}

/// The sections every manual page ends with: exit status, the profile, the diagnostic codes.
fn man_sections() -> String {
    use clap_mangen::roff::{Roff, bold, roman};
    let mut roff = Roff::new();
    roff.control("SH", ["EXIT STATUS"]);
    for (code, what) in [
        (
            "0",
            "success (converted, equivalent, or no error found; warnings may have been printed)",
        ),
        (
            "1",
            "the input has errors (nothing written for that file), or verify found a difference",
        ),
        (
            "2",
            "usage or I/O error (also a profile with errors, a --glob that matched nothing)",
        ),
        (
            "130",
            "batch was interrupted (Ctrl-C): the summary and the report say what was done",
        ),
    ] {
        roff.control("TP", [])
            .text([bold(code)])
            .text([roman(what)]);
    }
    roff.control("SH", ["FILES"]);
    roff.text([roman(
        "A machine profile (TOML) gives the constants that differ per machine: sections [czech] (constant8, coolant, arcs, dwell, surface_speed…), [nc31] (units, infeed_p6, runout_p7, retract_mm, schedule, arcs, chamfer45, repeat_g25…) and [iso] (mcodes, tool_change, block_delete, subroutine_path). Without --profile a program uses its sidecar STEM.profile.toml, else the nearest ncthread.toml in its folder or above, else the built-in defaults (--no-profile). An .ncthreadignore file (gitignore syntax) leaves files out of batch and check. README.md lists every key.",
    )]);
    roff.control("SH", ["DIAGNOSTICS"]);
    roff.text([roman(
        "Every diagnostic has a stable code, a severity, the file, line and column, the source line with a caret, and a help text; --diagnostics json prints one JSON object per diagnostic.",
    )]);
    for code in ncthread::diag::codes::ALL {
        let severity = if code.severity == diag::Severity::Error {
            "error"
        } else {
            "warning"
        };
        roff.control("TP", [])
            .text([bold(code.id)])
            .text([roman(format!("{severity}: {}", code.summary))]);
    }
    roff.render()
}

/// A manual page: clap_mangen's title, NAME ("ncthread \\- convert …", "ncthread\\-convert \\-
/// convert one program …"), SYNOPSIS (`ncthread convert …`, as it is typed), DESCRIPTION,
/// OPTIONS and SUBCOMMANDS, then the examples as EXAMPLES, and [`man_sections`].
fn man_page(cmd: clap::Command, examples: &[Example]) -> Result<Vec<u8>, Fatal> {
    use clap_mangen::roff::{Roff, bold, roman};
    let failed = |e: io::Error| Fatal::Usage(format!("cannot render the manual page: {e}"));
    // NAME is a phrase in lower case without a full stop ("ls - list directory contents").
    let about = cmd.get_about().map(|a| a.to_string()).unwrap_or_default();
    let mut chars = about.trim_end_matches('.').chars();
    let name_line: String = match chars.next() {
        Some(c) if !chars.clone().next().is_some_and(char::is_uppercase) => {
            c.to_lowercase().chain(chars).collect()
        }
        Some(c) => std::iter::once(c).chain(chars).collect(),
        None => String::new(),
    };
    let long = cmd
        .get_long_about()
        .map(|a| a.to_string())
        .unwrap_or_else(|| about.clone());
    let cmd = cmd.about(name_line).long_about(long);
    let man = clap_mangen::Man::new(cmd.clone())
        .source(format!("ncthread {}", env!("CARGO_PKG_VERSION")));
    let mut out = Vec::new();
    man.render_title(&mut out).map_err(failed)?;
    man.render_name_section(&mut out).map_err(failed)?;
    man.render_synopsis_section(&mut out).map_err(failed)?;
    man.render_description_section(&mut out).map_err(failed)?;
    if cmd.get_arguments().any(|a| !a.is_hide_set()) {
        man.render_options_section(&mut out).map_err(failed)?;
    }
    if cmd.has_subcommands() {
        man.render_subcommands_section(&mut out).map_err(failed)?;
    }
    if !examples.is_empty() {
        let mut roff = Roff::new();
        roff.control("SH", ["EXAMPLES"]);
        for e in examples {
            roff.control("TP", [])
                .text([bold(e.command)])
                .text([roman(e.what)]);
        }
        out.extend_from_slice(roff.render().as_bytes());
    }
    out.extend_from_slice(man_sections().as_bytes());
    Ok(out)
}

/// `ncthread man`: ncthread(1) or a subcommand's page on stdout, or every page into a folder.
fn man(subcommand: Option<String>, dir: Option<PathBuf>) -> Result<ExitCode, Fatal> {
    let cmd = <Cli as clap::CommandFactory>::command();
    // A subcommand's page is ncthread-NAME(1); its synopsis is typed `ncthread NAME`.
    let sub = |c: &clap::Command| {
        c.clone()
            .display_name(format!("ncthread-{}", c.get_name()))
            .bin_name(format!("ncthread {}", c.get_name()))
    };
    let pages: Vec<(String, clap::Command, &[Example])> =
        std::iter::once(("ncthread".to_string(), cmd.clone(), TOP_EXAMPLES))
            .chain(
                cmd.get_subcommands()
                    .filter(|c| c.get_name() != "help")
                    .map(|c| {
                        (
                            format!("ncthread-{}", c.get_name()),
                            sub(c),
                            examples_of(c.get_name()),
                        )
                    }),
            )
            .collect();
    match (subcommand, dir) {
        (None, None) => write_output(&None, &man_page(cmd, TOP_EXAMPLES)?)?,
        (Some(name), _) => {
            let Some((_, c, examples)) = pages
                .iter()
                .find(|(n, _, _)| *n == format!("ncthread-{name}"))
            else {
                return Err(Fatal::Usage(format!(
                    "`{name}` is not a subcommand of ncthread"
                )));
            };
            write_output(&None, &man_page(c.clone(), examples)?)?;
        }
        (None, Some(dir)) => {
            std::fs::create_dir_all(&dir)
                .map_err(|e| Fatal::Usage(io_error("create", dir.display(), &e)))?;
            for (name, c, examples) in pages {
                write_output(
                    &Some(dir.join(format!("{name}.1"))),
                    &man_page(c, examples)?,
                )?;
            }
        }
    }
    Ok(ExitCode::SUCCESS)
}

/// One line on stderr. Never panics: a closed or broken stderr loses the line, nothing more.
fn note(message: String) {
    let _ = writeln!(io::stderr(), "{message}");
}

fn is_stdio(path: &Option<PathBuf>) -> bool {
    path.as_ref().is_none_or(|p| p.as_os_str() == "-")
}

/// The bytes of the program `path` (stdin: `None` or `-`) and the name it goes by
/// (`stdin_name`, else `<stdin>`, for a program read from stdin).
fn read_input(
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
fn render(
    diags: &[diag::Diagnostic],
    format: DiagnosticsFormat,
    max_errors: usize,
    color: bool,
) -> String {
    if format == DiagnosticsFormat::Json {
        return diag::render_all(diags, Format::Json, false);
    }
    let (kept, hidden) = diag::cap(diags, max_errors);
    let mut text = String::new();
    for d in kept {
        text.push_str(&d.render(color));
        text.push_str("\n\n");
    }
    for (file, count) in hidden {
        text.push_str(&diag::more_errors(&file, count));
        text.push('\n');
    }
    text
}

/// Diagnostics on stderr (see [`render`]).
fn print_diagnostics(diags: &[diag::Diagnostic], format: DiagnosticsFormat, max_errors: usize) {
    let text = render(diags, format, max_errors, colour(true));
    let _ = io::stderr().write_all(text.as_bytes());
}

fn load_profile(path: &Option<PathBuf>, format: DiagnosticsFormat) -> Result<Profile, Fatal> {
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
fn read_source(
    input: &Option<PathBuf>,
    stdin: &StdinArgs,
    from: SourceDialect,
    common: &CommonArgs,
) -> Result<(SourceFile, DialectId), Fatal> {
    let (name, bytes) = read_input(input, stdin.stdin_filename.as_deref())?;
    let (src, from, decoded) = decode_source(name, &bytes, from, common.encoding);
    encoding_checked(&src, &decoded, common.diagnostics)?;
    Ok((src, from))
}

/// [`read_source`], with what the output keeps of the input for a conversion to `to`.
fn read_source_for(
    input: &Option<PathBuf>,
    stdin: &StdinArgs,
    from: SourceDialect,
    common: &CommonArgs,
    to: DialectId,
) -> Result<(SourceFile, DialectId, ncthread::text::Input), Fatal> {
    let (name, bytes) = read_input(input, stdin.stdin_filename.as_deref())?;
    let (src, from, decoded) = decode_source(name, &bytes, from, common.encoding);
    encoding_checked(&src, &decoded, common.diagnostics)?;
    let kept =
        ncthread::text::Input::of(&src.text, decoded.encoding, &decoded.eof_mark, from == to);
    Ok((src, from, kept))
}

/// Decodes a program in the given dialect, or chooses the dialect (`auto`, saying so on
/// stderr when unsure). Also returns the encoding used.
fn decode_source(
    name: String,
    bytes: &[u8],
    from: SourceDialect,
    encoding: Option<TextEncoding>,
) -> (SourceFile, DialectId, ncthread::text::Decoded) {
    let mut decoded = ncthread::text::decode_program(
        bytes,
        from.known(),
        encoding,
        Some(std::path::Path::new(&name)),
    );
    if let Some(detection) = decoded.detection.as_ref().filter(|d| !d.certain) {
        note(format!(
            "ncthread: --from auto: reading {name} as {} ({}); give --from to be sure",
            detection.dialect, detection.reason
        ));
    }
    let text = std::mem::take(&mut decoded.text);
    (SourceFile::new(name, text), decoded.dialect, decoded)
}

/// The note of a legacy encoding chosen from a file's bytes (printed), or its refusal.
fn encoding_checked(
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

fn unsupported(arg: UnsupportedArg) -> Unsupported {
    match arg {
        UnsupportedArg::Error => Unsupported::Error,
        UnsupportedArg::Warn => Unsupported::Warn,
    }
}

fn convert(args: ConvertArgs) -> Result<ExitCode, Fatal> {
    let profile = args.common.profile_for(&args.stdin.named(&args.input))?;
    let (src, from, input) = read_source_for(
        &args.input,
        &args.stdin,
        args.from,
        &args.common,
        args.to.into(),
    )?;
    let options = args
        .common
        .options(from, args.to.into(), profile, &args.target);
    let mut conversion = ncthread::convert(&src, &options);
    let bytes = conversion.output.as_ref().map(|output| {
        let name = args
            .output
            .as_ref()
            .filter(|_| !is_stdio(&args.output))
            .map_or("<stdout>".to_string(), |p| p.display().to_string());
        ncthread::text::encode_output(output, &name, &args.output_format.options(), &input)
    });
    let bytes = match bytes {
        Some(Ok(b)) => Some(b),
        Some(Err(d)) => {
            conversion.diagnostics.push(*d);
            None
        }
        None => None,
    };
    print_diagnostics(
        &conversion.diagnostics,
        args.common.diagnostics,
        args.common.max_errors,
    );
    let Some(bytes) = bytes else {
        return Ok(ExitCode::from(1));
    };
    write_output(&args.output, &bytes)?;
    Ok(ExitCode::SUCCESS)
}

fn simulate(args: SimulateArgs) -> Result<ExitCode, Fatal> {
    let profile = args.common.profile_for(&args.stdin.named(&args.input))?;
    let (src, from) = read_source(&args.input, &args.stdin, args.from, &args.common)?;
    let (program, mut diags) =
        ncthread::parse(&src, from, &profile, unsupported(args.common.unsupported));
    if diag::has_errors(&diags) {
        diag::sort(&mut diags);
        print_diagnostics(&diags, args.common.diagnostics, args.common.max_errors);
        return Ok(ExitCode::from(1));
    }
    let simulation = ncthread::sim::simulate(&program);
    diags.extend(simulation.problems.iter().map(|p| p.diagnostic(&src)));
    diag::sort(&mut diags);
    print_diagnostics(&diags, args.common.diagnostics, args.common.max_errors);
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

/// Reads a program for a command that looks at it (explain, plot): its diagnostics are
/// printed, and `None` when it has errors.
fn read_program(
    input: &Option<PathBuf>,
    stdin: &StdinArgs,
    from: SourceDialect,
    common: &CommonArgs,
) -> Result<Option<(SourceFile, ncthread::ir::Program)>, Fatal> {
    let profile = common.profile_for(&stdin.named(input))?;
    let (src, from) = read_source(input, stdin, from, common)?;
    let (program, mut diags) =
        ncthread::parse(&src, from, &profile, unsupported(common.unsupported));
    diag::sort(&mut diags);
    print_diagnostics(&diags, common.diagnostics, common.max_errors);
    Ok((!diag::has_errors(&diags)).then_some((src, program)))
}

fn explain(args: ExplainArgs) -> Result<ExitCode, Fatal> {
    let Some((_, program)) = read_program(&args.input, &args.stdin, args.from, &args.common)?
    else {
        return Ok(ExitCode::from(1));
    };
    let options = ncthread::explain::Options { crest: args.crest };
    let ops = ncthread::explain::explain(&program, &options);
    let out = match args.format {
        ExplainFormat::Text => ncthread::explain::to_text(
            &ops,
            if args.plain {
                ncthread::explain::Table::Plain
            } else {
                ncthread::explain::Table::Box
            },
        ),
        ExplainFormat::Json => {
            let mut text = serde_json::to_string_pretty(&ncthread::explain::to_json(&ops))
                .map_err(|e| Fatal::Usage(format!("cannot write JSON: {e}")))?;
            text.push('\n');
            text
        }
        ExplainFormat::Csv => ncthread::explain::to_csv(&ops),
    };
    write_output(&None, out.as_bytes())?;
    Ok(ExitCode::SUCCESS)
}

fn plot(args: PlotArgs) -> Result<ExitCode, Fatal> {
    let Some((src, program)) = read_program(&args.input, &args.stdin, args.from, &args.common)?
    else {
        return Ok(ExitCode::from(1));
    };
    let ops =
        ncthread::explain::explain(&program, &ncthread::explain::Options { crest: args.crest });
    let operation = match args.operation {
        Some(n) => Some(ops.get(n.wrapping_sub(1)).ok_or_else(|| {
            Fatal::Usage(format!(
                "--operation {n}: the program has {} operation(s) (see `ncthread explain`)",
                ops.len()
            ))
        })?),
        None => ncthread::explain::default_operation(&ops),
    };
    let simulation = ncthread::sim::simulate(&program);
    let svg = ncthread::plot::plot(&src.name, &simulation.segments, operation);
    write_output(&args.output, svg.as_bytes())?;
    Ok(ExitCode::SUCCESS)
}

fn verify(args: VerifyArgs) -> Result<ExitCode, Fatal> {
    let profile = args.common.profile_for(&args.stdin.named(&args.input))?;
    let (src, from) = read_source(&args.input, &args.stdin, args.from, &args.common)?;
    let to: DialectId = args.to.into();
    let against = match &args.against {
        Some(path) => {
            let bytes = std::fs::read(path)
                .map_err(|e| Fatal::Usage(io_error("read", path.display(), &e)))?;
            let text = ncthread::text::decode_as(&bytes, args.common.encoding, to).0;
            Some(SourceFile::new(path.display().to_string(), text))
        }
        None => None,
    };
    let options = args.common.options(from, to, profile, &args.target);
    let interpreter = if args.rs274 {
        match ncthread::sim::rs274::Interpreter::find() {
            Some(i) => Some(i),
            None => {
                return Err(Fatal::Usage(
                    "--rs274: LinuxCNC's interpreter was not found: put `rs274` on the PATH or name a command in NCTHREAD_RS274 (the project's scripts/rs274 fetches one)".into(),
                ));
            }
        }
    } else {
        None
    };
    let v = ncthread::verify_within(
        &src,
        &options,
        against.as_ref(),
        interpreter.as_ref(),
        args.tolerance.unwrap_or(ncthread::sim::TOLERANCE),
    );
    print_diagnostics(
        &v.diagnostics,
        args.common.diagnostics,
        args.common.max_errors,
    );
    let other = against
        .as_ref()
        .map_or(format!("ncthread's {to} conversion"), |a| a.name.clone());
    let seg = |s: &Option<ncthread::sim::Segment>| {
        s.map_or("(nothing: the program has ended)".to_string(), |s| {
            s.to_text()
        })
    };
    let (mut text, mut code) = match &v.outcome {
        ncthread::Outcome::Equivalent {
            segments,
            deviation,
            tolerance,
        } => (
            format!(
                "equivalent: {} ({from}) and {other} ({to}) make the same motion ({segments} segments after normalising; largest deviation {} mm; tolerance {} mm, 0.01°)\n",
                src.name,
                deviation.mm(),
                tolerance.mm()
            ),
            ExitCode::SUCCESS,
        ),
        ncthread::Outcome::Different(d) => (
            format!(
                "DIFFERENT: {}\n  {} ({from}): {}\n  {other} ({to}): {}\n  first difference: {d}\n",
                d.what,
                src.name,
                seg(&d.left),
                seg(&d.right),
            ),
            ExitCode::from(1),
        ),
        ncthread::Outcome::Refused => (
            "not verified: a program could not be read or converted (see the errors above)\n"
                .to_string(),
            ExitCode::from(1),
        ),
    };
    let mut plot = None;
    if let Some(path) = &args.plot {
        let difference = match &v.outcome {
            ncthread::Outcome::Different(d) => Some(&**d),
            _ => None,
        };
        let svg = ncthread::plot::verify_plot(
            &format!("verify: {} ({from}) against {other} ({to})", src.name),
            &format!("{} ({from})", src.name),
            &v.left_moves,
            &format!("{other} ({to})"),
            &v.right_moves,
            difference,
        );
        plot = Some((path, svg));
    }
    for check in &v.oracle {
        match &check.outcome {
            ncthread::OracleOutcome::Equivalent {
                segments,
                deviation,
                partial,
            } => text.push_str(&format!(
                "rs274 agrees: {} ({segments} segments{}; largest deviation {} mm)\n",
                check.what,
                if *partial {
                    ", up to where ncthread stops knowing the tool's path"
                } else {
                    ""
                },
                deviation.mm()
            )),
            ncthread::OracleOutcome::Different(d) => {
                code = ExitCode::from(1);
                text.push_str(&format!(
                    "rs274 DISAGREES: {}: {}\n  ncthread: {}\n  LinuxCNC: {}\n",
                    check.what,
                    d.what,
                    seg(&d.left),
                    seg(&d.right)
                ));
            }
            ncthread::OracleOutcome::Failed(e) => {
                code = ExitCode::from(1);
                text.push_str(&format!("rs274 could not check {}: {e}\n", check.what));
            }
            ncthread::OracleOutcome::CannotJudge(why) => {
                text.push_str(&format!("rs274 cannot judge {}: {why}\n", check.what));
            }
        }
    }
    write_output(&None, text.as_bytes())?;
    // The verdict first: a plot that cannot be written does not hide it.
    if let Some((path, svg)) = plot {
        write_output(&Some(path.clone()), svg.as_bytes())?;
    }
    Ok(code)
}

fn write_output(path: &Option<PathBuf>, bytes: &[u8]) -> Result<(), Fatal> {
    if is_stdio(path) {
        let mut out = io::stdout().lock();
        return match out.write_all(bytes).and_then(|()| out.flush()) {
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
    ncthread::files::write_atomically(path, bytes, true, None).map_err(|e| match e {
        ncthread::files::WriteError::Failed(why) | ncthread::files::WriteError::Fatal(why) => {
            Fatal::Usage(why)
        }
        ncthread::files::WriteError::Exists => Fatal::Usage(format!("{} exists", path.display())),
    })
}

fn check(args: CheckArgs) -> Result<ExitCode, Fatal> {
    let from = args.from.known();
    let selection = args.selection.selection(from);
    // Every program named, and every program of every folder named.
    let mut programs: Vec<Option<PathBuf>> = Vec::new();
    let mut unreadable = 0;
    let mut unmatched = Vec::new();
    // Globs choose files of folders: without a path they walk the current folder.
    let globbed = !args.selection.glob.is_empty() || !args.selection.iglob.is_empty();
    let files = match (args.files.is_empty(), globbed) {
        (true, true) => vec![PathBuf::from(".")],
        _ => args.files.clone(),
    };
    if files.is_empty() {
        programs.push(None);
    }
    for file in &files {
        if file.as_os_str() == "-" {
            programs.push(None);
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
            programs.extend(walk.programs().map(|rel| Some(file.join(rel))));
            unmatched.extend(walk.unmatched);
        } else {
            match std::fs::metadata(file) {
                Ok(_) => programs.push(Some(file.clone())),
                Err(e) => {
                    note(format!("error: {}", io_error("read", file.display(), &e)));
                    unreadable += 1;
                }
            }
        }
    }
    // A file named twice (or inside a folder named too) is checked once.
    let mut seen = std::collections::HashSet::new();
    programs.retain(|p| match p {
        Some(path) => seen.insert(std::fs::canonicalize(path).unwrap_or_else(|_| path.clone())),
        None => true,
    });
    let (mut errors, mut warnings, mut failed_files, mut checked) = (0, 0, 0, 0);
    let mut uncertain: Vec<String> = Vec::new();
    let mut out = String::new();
    for file in &programs {
        // An unreadable file is reported and the others are still checked.
        let (name, bytes) = match read_input(file, args.stdin.stdin_filename.as_deref()) {
            Ok(input) => input,
            Err(e) => {
                if let Fatal::Usage(message) = e {
                    note(format!("error: {message}"));
                }
                unreadable += 1;
                continue;
            }
        };
        let named = args.stdin.named(file);
        // A profile with errors fails its program, not the run.
        let profile = match args.common.profile_for(&named) {
            Ok(p) => p,
            Err(e) => {
                if let Fatal::Usage(message) = e {
                    note(format!("error: {message}"));
                }
                unreadable += 1;
                continue;
            }
        };
        let decoded = ncthread::text::decode_program(
            &bytes,
            from,
            args.common.encoding,
            Some(std::path::Path::new(&name)),
        );
        if let Some(d) = decoded.detection.as_ref().filter(|d| !d.certain) {
            uncertain.push(format!("{name} as {}", d.dialect));
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
        checked += 1;
        let e = diags.iter().filter(|d| d.is_error()).count();
        errors += e;
        warnings += diags.len() - e;
        failed_files += usize::from(e > 0);
        out.push_str(&render(
            &diags,
            args.common.diagnostics,
            args.common.max_errors,
            colour(false),
        ));
    }
    write_output(&None, out.as_bytes())?;
    let human = args.common.diagnostics == DiagnosticsFormat::Human && !args.quiet;
    if human && !uncertain.is_empty() {
        note(format!(
            "ncthread: --from auto: {} file(s) read without a certain dialect ({}{}); give --from to be sure",
            uncertain.len(),
            uncertain[..uncertain.len().min(3)].join(", "),
            if uncertain.len() > 3 { ", …" } else { "" }
        ));
    }
    for glob in &unmatched {
        note(format!("ncthread: warning: --glob {glob} matched no file"));
    }
    if human {
        note(format!(
            "ncthread: checked {checked} file(s): {errors} error(s) in {failed_files} file(s), {warnings} warning(s)"
        ));
    }
    Ok(if unreadable > 0 || !unmatched.is_empty() {
        ExitCode::from(2)
    } else if errors > 0 {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    })
}

fn batch(args: BatchArgs) -> Result<ExitCode, Fatal> {
    let to: DialectId = args.to.into();
    let from = args.from.known();
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
    let profile = match (&args.common.profile, args.common.no_profile) {
        (Some(path), _) => {
            let mut p = load_profile(&Some(path.clone()), args.common.diagnostics)?;
            args.common.overrides().apply(&mut p);
            ncthread::batch::ProfileChoice::Given(path.clone(), Box::new(p))
        }
        (None, true) => ncthread::batch::ProfileChoice::Defaults,
        (None, false) => ncthread::batch::ProfileChoice::Discover,
    };
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
        profile,
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
        let inside = ncthread::files::resolve(path)
            .ok()
            .zip(std::fs::canonicalize(&args.src_dir).ok());
        if inside.is_some_and(|(r, s)| r.starts_with(s)) {
            return Err(Fatal::Usage(format!(
                "the report {} is inside the source folder {}; ncthread never writes into the source tree",
                path.display(),
                args.src_dir.display()
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
    }
    let plan = ncthread::batch::plan(&options).map_err(Fatal::Usage)?;
    for glob in plan.unmatched_globs() {
        note(format!("ncthread: warning: --glob {glob} matched no file"));
    }
    let quiet = args.quiet;
    let bar = if io::stderr().is_terminal() && !quiet {
        let bar = indicatif::ProgressBar::new(plan.programs() as u64);
        bar.set_style(
            indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} {wide_msg}")
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        bar
    } else {
        indicatif::ProgressBar::hidden()
    };
    // Ctrl-C: the workers finish the file in hand, the rest is not done, and the summary and
    // the report say what was.
    let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    {
        let stop = stop.clone();
        let _ = ctrlc::set_handler(move || stop.store(true, std::sync::atomic::Ordering::Relaxed));
    }
    let format = args.common.diagnostics;
    let verbose = args.common.verbose;
    let dry_run = args.dry_run;
    let color = colour(true);
    let max_errors = args.common.max_errors;
    let progress = |f: &ncthread::batch::FileReport| {
        use ncthread::batch::Status;
        let mut text = String::new();
        if verbose || (dry_run && !quiet && f.status == Status::Converted) {
            text.push_str(&file_line(f, dry_run));
        }
        if let Some(note) = f.dialect_note.as_ref().filter(|_| !quiet) {
            text.push_str(&format!("{}: {note}\n", f.input.display()));
        }
        // What failed, and an output older than its program; why any other output was
        // skipped only when asked (--verbose).
        if f.status == Status::Failed
            || (verbose && f.status == Status::Skipped)
            || (!quiet && f.up_to_date == Some(false))
        {
            text.push_str(&file_problem(f, format, max_errors, color));
        }
        if !text.is_empty() {
            bar.suspend(|| {
                let _ = io::stderr().write_all(text.as_bytes());
            });
        }
        if f.status != Status::LeftOut {
            bar.inc(1);
        }
    };
    let report = ncthread::batch::run(&options, &plan, &progress, &stop).map_err(Fatal::Usage)?;
    bar.finish_and_clear();
    // The reports are written even when the run stopped; what cannot be written is said.
    let mut unwritten = Vec::new();
    if let Some(path) = &args.report {
        let written = serde_json::to_string_pretty(&report.to_json(&options))
            .map_err(|e| format!("cannot write the report: {e}"))
            .and_then(|json| {
                std::fs::write(path, json + "\n").map_err(|e| io_error("write", path.display(), &e))
            });
        unwritten.extend(written.err());
    }
    if !dry_run {
        unwritten.extend(report.write_html(&options).err());
    }
    if !quiet {
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
    Ok(if report.interrupted {
        ExitCode::from(130)
    } else if !plan.unmatched_globs().is_empty() || !unwritten.is_empty() {
        ExitCode::from(2)
    } else if report.succeeded() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}

/// One file's line under --verbose or --dry-run: what it was read as, its profile, and
/// what is (or would be) written.
fn file_line(f: &ncthread::batch::FileReport, dry_run: bool) -> String {
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
fn file_problem(
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
    let mut errors = 0;
    for d in f.diagnostics.iter().filter(why) {
        errors += usize::from(d.is_error());
        if format == DiagnosticsFormat::Human && max_errors > 0 && errors > max_errors {
            continue;
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
                text.push_str(&format!("{at}: {level}: {}\n", d.message));
            }
        }
    }
    if format == DiagnosticsFormat::Human && max_errors > 0 && errors > max_errors {
        text.push_str(&diag::more_errors(&path.to_string(), errors - max_errors));
        text.push('\n');
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn colour_follows_the_flag_then_no_color_then_clicolor_force_then_the_terminal() {
        let env = |vars: &'static [(&'static str, &'static str)]| {
            move |name: &str| {
                vars.iter()
                    .find(|(n, _)| *n == name)
                    .map(|(_, v)| std::ffi::OsString::from(v))
            }
        };
        use ColorArg::{Always, Auto, Never};
        assert!(colour_wanted(Auto, true, env(&[])));
        assert!(!colour_wanted(Auto, false, env(&[])));
        assert!(!colour_wanted(Auto, true, env(&[("NO_COLOR", "1")])));
        // An empty NO_COLOR is no request.
        assert!(colour_wanted(Auto, true, env(&[("NO_COLOR", "")])));
        assert!(colour_wanted(Auto, false, env(&[("CLICOLOR_FORCE", "1")])));
        assert!(!colour_wanted(Auto, false, env(&[("CLICOLOR_FORCE", "0")])));
        assert!(!colour_wanted(
            Auto,
            false,
            env(&[("CLICOLOR_FORCE", "1"), ("NO_COLOR", "1")])
        ));
        assert!(!colour_wanted(Auto, true, env(&[("CLICOLOR", "0")])));
        assert!(!colour_wanted(Auto, true, env(&[("TERM", "dumb")])));
        assert!(colour_wanted(Always, false, env(&[("NO_COLOR", "1")])));
        assert!(!colour_wanted(Never, true, env(&[("CLICOLOR_FORCE", "1")])));
    }

    /// Every example `-h`, `--help` and the manual pages print is a command line ncthread
    /// takes.
    #[test]
    fn every_example_parses() {
        let cmd = <Cli as clap::CommandFactory>::command();
        let names = std::iter::once("ncthread")
            .chain(cmd.get_subcommands().map(|c| c.get_name()))
            .collect::<Vec<_>>();
        let mut seen = 0;
        for name in names {
            for e in examples_of(name) {
                // The ncthread command of a line that may feed it (`<`) or pipe it on.
                let line = e.command.split(['<', '>', '|']).next().unwrap_or_default();
                let words: Vec<String> = line
                    .split_whitespace()
                    .map(|w| w.trim_matches('\'').to_string())
                    .collect();
                assert_eq!(words[0], "ncthread", "{}", e.command);
                if name != "ncthread" {
                    assert_eq!(words[1], name, "{}", e.command);
                }
                if let Err(err) = Cli::try_parse_from(&words) {
                    panic!("{}: {err}", e.command);
                }
                seen += 1;
            }
        }
        assert!(seen > 20, "{seen}");
    }

    #[test]
    fn colour_is_found_in_the_raw_arguments() {
        let args = |a: &[&str]| a.iter().map(std::ffi::OsString::from).collect::<Vec<_>>();
        assert_eq!(
            colour_argument(&args(&["ncthread", "--color", "never", "-h"])),
            Some(ColorArg::Never)
        );
        assert_eq!(
            colour_argument(&args(&["ncthread", "check", "--color=ALWAYS"])),
            Some(ColorArg::Always)
        );
        assert_eq!(
            colour_argument(&args(&["ncthread", "--", "--color=always"])),
            None
        );
        assert_eq!(colour_argument(&args(&["ncthread", "-h"])), None);
    }
}

//! The command line's arguments, as clap parses them.

use std::path::PathBuf;

use clap::builder::TypedValueParser as _;
use clap::{Parser, Subcommand, ValueEnum};
use ncthread::DialectId;
use ncthread::text::{Eol, OutputOptions, TextEncoding};

use super::colour::ColorArg;
use super::examples::{
    ABOUT, BATCH_EXAMPLES, CHECK_EXAMPLES, CONVERT_EXAMPLES, EXPLAIN_EXAMPLES, LONG_ABOUT,
    PLOT_EXAMPLES, SIMULATE_EXAMPLES, TOP_EXAMPLES, VERIFY_EXAMPLES, examples,
};

#[derive(Parser)]
#[command(
    name = "ncthread",
    version,
    about = ABOUT,
    long_about = LONG_ABOUT,
    after_help = examples(TOP_EXAMPLES, false),
    after_long_help = examples(TOP_EXAMPLES, true),
)]
pub(crate) struct Cli {
    #[command(subcommand)]
    pub(crate) command: Command,
    /// When to colour diagnostics: `auto` on a terminal unless NO_COLOR is set (CLICOLOR_FORCE
    /// colours a pipe too), `always`, or `never`.
    #[arg(long, value_enum, global = true, default_value_t = ColorArg::Auto, value_name = "WHEN")]
    pub(crate) color: ColorArg,
}

#[derive(Subcommand)]
pub(crate) enum Command {
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
pub(crate) struct CheckArgs {
    /// The programs to check, and folders of programs (walked as `batch` walks them); `-` or
    /// nothing reads stdin.
    pub(crate) files: Vec<PathBuf>,
    /// The dialect of the programs; `auto` chooses per file from the text.
    #[arg(long, alias = "dialect", ignore_case = true, value_parser = source_dialect(), default_value = "auto")]
    pub(crate) from: SourceDialect,
    /// Print the diagnostics only: no summary line, no notes.
    #[arg(long, short = 'q')]
    pub(crate) quiet: bool,
    #[command(flatten)]
    pub(crate) stdin: StdinArgs,
    #[command(flatten)]
    pub(crate) selection: SelectionArgs,
    #[command(flatten)]
    pub(crate) common: CommonArgs,
}

/// The name of a program that comes on stdin.
#[derive(clap::Args)]
pub(crate) struct StdinArgs {
    /// The name of the program read from stdin (as ruff's): the file its diagnostics name,
    /// where its sidecar profile or `ncthread.toml` is looked for, and its extension for
    /// `--from auto`. Ignored for a program read from a file.
    #[arg(long, value_name = "NAME")]
    pub(crate) stdin_filename: Option<PathBuf>,
}

/// Which files of a folder are programs.
#[derive(clap::Args)]
pub(crate) struct SelectionArgs {
    /// Take the files whose path below the folder matches this glob (gitignore syntax, e.g.
    /// `**/*.NC`) instead of the dialect's extensions; `!GLOB` leaves files out. Repeatable.
    #[arg(long, value_name = "GLOB")]
    pub(crate) glob: Vec<String>,
    /// As --glob, matched without regard to case.
    #[arg(long, value_name = "GLOB")]
    pub(crate) iglob: Vec<String>,
}

impl SelectionArgs {
    pub(crate) fn selection(&self, from: Option<DialectId>) -> ncthread::files::Selection {
        ncthread::files::Selection {
            globs: self.glob.clone(),
            iglobs: self.iglob.clone(),
            extensions: ncthread::batch::program_extensions(from),
        }
    }
}

#[derive(clap::Args)]
pub(crate) struct BatchArgs {
    /// The folder of programs to convert (walked recursively; never written to).
    pub(crate) src_dir: PathBuf,
    /// The folder the converted tree is written to (created when missing).
    pub(crate) out_dir: PathBuf,
    /// The source dialect; `auto` chooses per file from the text.
    #[arg(long, ignore_case = true, value_parser = source_dialect())]
    pub(crate) from: SourceDialect,
    /// The target dialect.
    #[arg(long, ignore_case = true, value_parser = target_dialect())]
    pub(crate) to: TargetDialect,
    /// Worker threads (default: one per core).
    #[arg(long, short = 'j')]
    pub(crate) jobs: Option<usize>,
    /// Write a JSON report of every file here. A re-run reads it back: a skipped file whose
    /// output is up to date keeps its row.
    #[arg(long, value_name = "FILE")]
    pub(crate) report: Option<PathBuf>,
    /// Overwrite outputs that exist.
    #[arg(long)]
    pub(crate) force: bool,
    #[arg(long, value_name = "EXT", help = ext_help())]
    pub(crate) ext: Option<String>,
    /// Convert, but write nothing: list what would be written.
    #[arg(long)]
    pub(crate) dry_run: bool,
    /// Print only what failed (each failed file's errors or reason): no progress bar, no
    /// notes, no summary. The exit code says the rest.
    #[arg(long, short = 'q', conflicts_with = "verbose")]
    pub(crate) quiet: bool,
    #[command(flatten)]
    pub(crate) selection: SelectionArgs,
    /// Also write a static HTML report into this folder (`index.html`, the plots and the
    /// page's data `report.json`): each file's status, encoding, profile and diagnostics, and
    /// each converted program's `explain` table and plot. A re-run reads the data back: a
    /// skipped file whose output is up to date keeps its row.
    #[arg(long, value_name = "DIR")]
    pub(crate) html: Option<PathBuf>,
    #[command(flatten)]
    pub(crate) target: TargetArgs,
    #[command(flatten)]
    pub(crate) output: OutputArgs,
    #[command(flatten)]
    pub(crate) common: CommonArgs,
}

/// How output programs become bytes.
#[derive(clap::Args)]
pub(crate) struct OutputArgs {
    /// The output's encoding (an encoding_rs/WHATWG label, or IBM852); default UTF-8.
    #[arg(long, value_parser = parse_output_encoding)]
    pub(crate) output_encoding: Option<TextEncoding>,
    /// Write a character the output encoding lacks as its ASCII transliteration (Č → C)
    /// instead of refusing.
    #[arg(long)]
    pub(crate) transliterate: bool,
    /// Line endings: `keep` the input's, or `lf`, `crlf`.
    #[arg(long, value_enum, default_value_t = EolArg::Keep)]
    pub(crate) eol: EolArg,
}

#[derive(Clone, Copy, ValueEnum)]
pub(crate) enum EolArg {
    Keep,
    Lf,
    Crlf,
}

impl OutputArgs {
    pub(crate) fn options(&self) -> OutputOptions {
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

pub(crate) fn parse_encoding(label: &str) -> Result<TextEncoding, String> {
    TextEncoding::for_label(label).ok_or_else(|| {
        format!("`{label}` is not an encoding label (e.g. utf-8, windows-1250, ibm866, ibm852)")
    })
}

pub(crate) fn parse_output_encoding(label: &str) -> Result<TextEncoding, String> {
    let e = parse_encoding(label)?;
    if !e.can_encode() {
        return Err(format!(
            "ncthread cannot write {e}; choose utf-8 or a single-byte encoding"
        ));
    }
    Ok(e)
}

#[derive(clap::Args)]
pub(crate) struct VerifyArgs {
    /// The source program; `-` or nothing reads stdin.
    pub(crate) input: Option<PathBuf>,
    /// The source dialect; `auto` chooses from the text.
    #[arg(long, ignore_case = true, value_parser = source_dialect())]
    pub(crate) from: SourceDialect,
    /// The target dialect.
    #[arg(long, ignore_case = true, value_parser = target_dialect())]
    pub(crate) to: TargetDialect,
    /// An existing program in the target dialect (e.g. the shop's hand conversion) to check
    /// instead of ncthread's own conversion.
    #[arg(long)]
    pub(crate) against: Option<PathBuf>,
    /// Also run every ISO program of the comparison through LinuxCNC's interpreter (`rs274`
    /// on the PATH, or the command in $NCTHREAD_RS274) and hold its motion against
    /// ncthread's simulation of the other program: a second, independent judge.
    #[arg(long)]
    pub(crate) rs274: bool,
    /// Also write an SVG of both motions overlaid, the first difference marked (a file: the
    /// verdict goes to stdout).
    #[arg(long, value_name = "FILE.svg", value_parser = not_stdout)]
    pub(crate) plot: Option<PathBuf>,
    /// How far positions may differ, in mm (default 0.001). A conversion with --round is
    /// allowed the deviation its rounding reported.
    #[arg(long, value_name = "MM", value_parser = parse_length)]
    pub(crate) tolerance: Option<ncthread::fixed::Length>,
    #[command(flatten)]
    pub(crate) target: TargetArgs,
    #[command(flatten)]
    pub(crate) stdin: StdinArgs,
    #[command(flatten)]
    pub(crate) common: CommonArgs,
}

#[derive(clap::Args)]
pub(crate) struct ExplainArgs {
    /// The program to read; `-` or nothing reads stdin.
    pub(crate) input: Option<PathBuf>,
    /// The dialect of the program; `auto` chooses from the text.
    #[arg(long, ignore_case = true, value_parser = source_dialect())]
    pub(crate) from: SourceDialect,
    /// `text`: a heading and a table per operation; `json`: `{ "operations": [ … ] }`;
    /// `csv`: one row per pass.
    #[arg(long, value_enum, default_value_t = ExplainFormat::Text)]
    pub(crate) format: ExplainFormat,
    /// Draw the text tables in ASCII instead of UTF-8 box drawing.
    #[arg(long)]
    pub(crate) plain: bool,
    /// The crest diameter of a thread written as single passes, in mm, which such a program
    /// does not say: the major diameter of an external thread (36 for M36), the minor (bore)
    /// diameter of an internal one. Without it, depths are counted from the first pass.
    #[arg(long, value_name = "MM", value_parser = parse_length)]
    pub(crate) crest: Option<ncthread::fixed::Length>,
    #[command(flatten)]
    pub(crate) stdin: StdinArgs,
    #[command(flatten)]
    pub(crate) common: CommonArgs,
}

#[derive(clap::Args)]
pub(crate) struct PlotArgs {
    /// The program to read; `-` or nothing reads stdin.
    pub(crate) input: Option<PathBuf>,
    /// The dialect of the program; `auto` chooses from the text.
    #[arg(long, ignore_case = true, value_parser = source_dialect())]
    pub(crate) from: SourceDialect,
    /// Where to write the SVG; `-` or nothing writes stdout.
    #[arg(short, long)]
    pub(crate) output: Option<PathBuf>,
    /// The operation (as `explain` numbers them) drawn in detail; default the first thread.
    #[arg(long, value_name = "N")]
    pub(crate) operation: Option<usize>,
    /// The crest diameter of a thread written as single passes (see `explain --crest`).
    #[arg(long, value_name = "MM", value_parser = parse_length)]
    pub(crate) crest: Option<ncthread::fixed::Length>,
    #[command(flatten)]
    pub(crate) stdin: StdinArgs,
    #[command(flatten)]
    pub(crate) common: CommonArgs,
}

#[derive(Clone, Copy, ValueEnum)]
pub(crate) enum ExplainFormat {
    Text,
    Json,
    Csv,
}

pub(crate) fn not_stdout(text: &str) -> Result<PathBuf, String> {
    if text == "-" {
        return Err("give a file: the verdict is written on stdout".into());
    }
    Ok(PathBuf::from(text))
}

pub(crate) fn parse_length(text: &str) -> Result<ncthread::fixed::Length, String> {
    ncthread::fixed::Decimal::parse(text)
        .and_then(|d| d.to_length().ok())
        .filter(|l| l.0 > 0)
        .ok_or_else(|| format!("`{text}` is not a positive length in mm (at most 4 decimals)"))
}

#[derive(clap::Args)]
pub(crate) struct SimulateArgs {
    /// The program to read; `-` or nothing reads stdin.
    pub(crate) input: Option<PathBuf>,
    /// The dialect of the program; `auto` chooses from the text.
    #[arg(long, ignore_case = true, value_parser = source_dialect())]
    pub(crate) from: SourceDialect,
    /// `text`: one segment per line; `json`: one JSON object per segment.
    #[arg(long, value_enum, default_value_t = OutputFormat::Text)]
    pub(crate) format: OutputFormat,
    #[command(flatten)]
    pub(crate) stdin: StdinArgs,
    #[command(flatten)]
    pub(crate) common: CommonArgs,
}

/// Options every subcommand takes.
#[derive(clap::Args)]
pub(crate) struct CommonArgs {
    /// Machine profile (TOML): what differs per machine, in [czech], [nc31], [iso], [fanuc],
    /// [siemens] and [heidenhain] sections. Without it, a program's sidecar `STEM.profile.toml`, else the
    /// nearest `ncthread.toml` in its folder or above, else the built-in defaults.
    ///
    /// [czech]: machine constant 8 (runout and entry angles), the first motion mode, gear
    /// range M codes, and the machine's forms of coolant, arcs, dwell and surface speed.
    /// [nc31]: the units of X Z P and F, machine parameters 6 and 7 (infeed angle, runout),
    /// the G31 retract and pass schedule, gear range M codes, coolant, arcs, 45° chamfers,
    /// G25 repeats. [iso]: M code mappings, the tool change, the block delete switch,
    /// subroutine folders. [fanuc]: words without a decimal point, G92's thread chamfer, the
    /// tool offset number, the program number, nose radius compensation, mist coolant, the
    /// G-code system, the machine model of the canned cycles. [siemens]: X and F before the
    /// program says. [heidenhain]: the section keywords, the arc direction, G33's C and B,
    /// G31's model. Without a key, what needs it is refused by name. README.md lists every key.
    #[arg(long, value_name = "FILE")]
    pub(crate) profile: Option<PathBuf>,
    /// Use the built-in defaults: no sidecar or `ncthread.toml` is looked for.
    #[arg(long, conflicts_with = "profile")]
    pub(crate) no_profile: bool,
    /// Say which profile (and, in batch and check, which encoding) each program used; batch
    /// lists every file, with its output or why it was skipped or left out.
    #[arg(long, short = 'v')]
    pub(crate) verbose: bool,
    /// How to print diagnostics (on stderr; `check` prints them on stdout).
    #[arg(long, value_enum, default_value_t = DiagnosticsFormat::Human)]
    pub(crate) diagnostics: DiagnosticsFormat,
    /// Print at most N errors of each file, then how many more there are (0: every one).
    /// Warnings and `--diagnostics json` are not limited.
    #[arg(long, value_name = "N", default_value_t = 50)]
    pub(crate) max_errors: usize,
    /// Undocumented constructs: refuse the program, or warn and keep them as opaque items.
    #[arg(long, value_enum, default_value_t = UnsupportedArg::Error)]
    pub(crate) unsupported: UnsupportedArg,
    #[arg(long, value_name = "LABEL", value_parser = parse_encoding, help = encoding_help())]
    pub(crate) encoding: Option<TextEncoding>,
    /// ISO input: the block delete switch the program runs with. Lines that start with `/`
    /// run when it is off and are skipped when it is on; without it (or the profile's
    /// `[iso] block_delete`) such a line is refused.
    #[arg(long, value_enum)]
    pub(crate) block_delete: Option<BlockDeleteArg>,
    /// ISO input: a folder that holds subroutine files (`o<name> call` reads `name.ngc`
    /// from the first folder that has it), as LinuxCNC's SUBROUTINE_PATH; repeatable.
    #[arg(long, value_name = "DIR")]
    pub(crate) subroutine_path: Vec<PathBuf>,
}

#[derive(Clone, Copy, clap::ValueEnum)]
pub(crate) enum BlockDeleteArg {
    Off,
    On,
}

/// Options of the subcommands that write a program.
#[derive(clap::Args)]
pub(crate) struct TargetArgs {
    /// Block numbers for czech output from another dialect: START,STEP (default 10,10).
    #[arg(long, value_parser = parse_renumber)]
    pub(crate) renumber: Option<ncthread::dialect::Renumber>,
    /// Round values the target cannot hold onto its grid, with one warning giving the
    /// largest deviation, instead of refusing them.
    ///
    /// czech, fanuc, siemens and heidenhain: lengths to 0.001 mm, leads and feeds to 0.0001 mm; nc31: whole units
    /// of the profile (0.01 mm, leads 0.0001 mm); iso holds every value and never rounds. A
    /// rounded lead's deviation is its drift at the thread's end; a czech thread start moved
    /// onto the grid changes its start angle I so that the pass cuts the same helix; an arc
    /// whose written R would move its centre is rounded too. `verify --round` allows the
    /// deviation the rounding reported.
    #[arg(long)]
    pub(crate) round: bool,
    /// nc31 output: write comments as `(` lines (for PC-side archives) instead of dropping
    /// them with a warning.
    #[arg(long)]
    pub(crate) nc31_comments: bool,
}

#[derive(Clone, Copy, ValueEnum)]
pub(crate) enum OutputFormat {
    Text,
    Json,
}

#[derive(clap::Args)]
pub(crate) struct ConvertArgs {
    /// The program to read; `-` or nothing reads stdin.
    pub(crate) input: Option<PathBuf>,
    /// The source dialect; `auto` chooses from the text (and says so on stderr when unsure).
    #[arg(long, ignore_case = true, value_parser = source_dialect())]
    pub(crate) from: SourceDialect,
    /// The target dialect.
    #[arg(long, ignore_case = true, value_parser = target_dialect())]
    pub(crate) to: TargetDialect,
    /// Where to write the program; `-` or nothing writes stdout.
    #[arg(short, long)]
    pub(crate) output: Option<PathBuf>,
    #[command(flatten)]
    pub(crate) target: TargetArgs,
    #[command(flatten)]
    pub(crate) output_format: OutputArgs,
    #[command(flatten)]
    pub(crate) stdin: StdinArgs,
    #[command(flatten)]
    pub(crate) common: CommonArgs,
}

/// A source dialect (`--from`, `--dialect`): one of the registry's, or `auto` (`None`).
#[derive(Clone, Copy, PartialEq, Eq)]
pub(crate) struct SourceDialect(Option<DialectId>);

/// A target dialect (`--to`).
#[derive(Clone, Copy, PartialEq, Eq)]
pub(crate) struct TargetDialect(DialectId);

/// `--ext`'s help: each target's own extension, from the registry.
pub(crate) fn ext_help() -> String {
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
pub(crate) fn encoding_help() -> String {
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
pub(crate) fn dialect_ids() -> Vec<&'static str> {
    ncthread::dialect::ALL
        .iter()
        .map(|d| d.id().as_str())
        .collect()
}

pub(crate) fn source_dialect() -> impl clap::builder::TypedValueParser<Value = SourceDialect> {
    let mut ids = dialect_ids();
    ids.push("auto");
    clap::builder::PossibleValuesParser::new(ids).map(|id: String| {
        SourceDialect(ncthread::dialect::by_id(&id.to_ascii_lowercase()).map(|d| d.id()))
    })
}

pub(crate) fn target_dialect() -> impl clap::builder::TypedValueParser<Value = TargetDialect> {
    clap::builder::PossibleValuesParser::new(dialect_ids()).map(|id: String| {
        TargetDialect(
            ncthread::dialect::by_id(&id.to_ascii_lowercase())
                .map_or(ncthread::dialect::ALL[0].id(), |d| d.id()),
        )
    })
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum DiagnosticsFormat {
    Human,
    Json,
}

#[derive(Clone, Copy, ValueEnum)]
pub(crate) enum UnsupportedArg {
    Error,
    Warn,
}

impl SourceDialect {
    /// The dialect given, or `None` for `auto`.
    pub(crate) fn known(self) -> Option<DialectId> {
        self.0
    }
}

impl From<TargetDialect> for DialectId {
    fn from(d: TargetDialect) -> DialectId {
        d.0
    }
}

pub(crate) fn parse_renumber(text: &str) -> Result<ncthread::dialect::Renumber, String> {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cli::examples::examples_of;

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
}

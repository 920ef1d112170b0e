//! The `ncthread` command line: argument parsing and exit codes only.
//! Exit codes: 0 success, 1 the input has errors (nothing written), 2 usage or I/O error.

mod cli;

#[cfg(all(any(target_os = "linux", target_os = "macos"), target_arch = "x86_64"))]
#[global_allocator]
static GLOBAL: tikv_jemallocator::Jemalloc = tikv_jemallocator::Jemalloc;

use std::process::ExitCode;

use cli::Fatal;
use cli::args::{Cli, Command, DiagnosticsFormat};
use cli::colour::{COLOR, ColorArg, colour_argument};
use cli::io::{load_profile, note, write_output};
use cli::{batch, check, commands, man, verify};

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
        Command::Convert(args) => commands::convert(args),
        Command::Simulate(args) => commands::simulate(args),
        Command::Verify(args) => verify::verify(args),
        Command::Check(args) => check::check(args),
        Command::Explain(args) => commands::explain(args),
        Command::Plot(args) => commands::plot(args),
        Command::Batch(args) => batch::batch(args),
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
        Command::Man { subcommand, dir } => man::man(subcommand, dir),
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

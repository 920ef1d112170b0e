//! `ncthread man`: the manual pages.

use std::io;
use std::path::PathBuf;
use std::process::ExitCode;

use ncthread::diag;
use ncthread::files::io_error;

use super::Fatal;
use super::args::Cli;
use super::examples::{Example, TOP_EXAMPLES, examples_of};
use super::io::write_output;

/// The sections every manual page ends with: exit status, the profile, the diagnostic codes.
pub(crate) fn man_sections() -> String {
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
    for code in ncthread::dialect::all_codes() {
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
pub(crate) fn man_page(cmd: clap::Command, examples: &[Example]) -> Result<Vec<u8>, Fatal> {
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
pub(crate) fn man(subcommand: Option<String>, dir: Option<PathBuf>) -> Result<ExitCode, Fatal> {
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

//! `ncthread verify`: a conversion proved by simulating both programs.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use ncthread::files::io_error;
use ncthread::source::SourceFile;
use ncthread::text::TextEncoding;
use ncthread::{DialectId, OracleCheck, OracleOutcome, Outcome, Verification};

use super::Fatal;
use super::args::VerifyArgs;
use super::io::{print_diagnostics, read_source, write_output};

/// The two sides of a verification as the verdict names them.
struct Sides<'a> {
    /// The source program's name and dialect.
    src: &'a SourceFile,
    from: DialectId,
    /// The other program (`--against`'s name, or ncthread's conversion) and its dialect.
    other: String,
    to: DialectId,
}

pub(crate) fn verify(args: VerifyArgs) -> Result<ExitCode, Fatal> {
    let profile = args.common.profile_for(&args.stdin.named(&args.input))?;
    let (src, from) = read_source(&args.input, &args.stdin, args.from, &args.common, &profile)?;
    let to: DialectId = args.to.into();
    let against = match &args.against {
        Some(path) => Some(read_against(path, args.common.encoding, to)?),
        None => None,
    };
    let options = args.common.options(from, to, profile, &args.target);
    let interpreter = if args.rs274 {
        Some(find_interpreter()?)
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
    let sides = Sides {
        src: &src,
        from,
        other,
        to,
    };
    let (mut text, mut code) = verdict(&v.outcome, &sides);
    let plot = args.plot.as_ref().map(|path| (path, plot(&v, &sides)));
    for check in &v.oracle {
        if !oracle_line(check, &mut text) {
            code = ExitCode::from(1);
        }
    }
    write_output(&None, text.as_bytes())?;
    // The verdict first: a plot that cannot be written does not hide it.
    if let Some((path, svg)) = plot {
        write_output(&Some(PathBuf::clone(path)), svg.as_bytes())?;
    }
    Ok(code)
}

/// The program of `--against`, decoded as a `to` program.
fn read_against(
    path: &Path,
    encoding: Option<TextEncoding>,
    to: DialectId,
) -> Result<SourceFile, Fatal> {
    let bytes =
        std::fs::read(path).map_err(|e| Fatal::Usage(io_error("read", path.display(), &e)))?;
    let text = ncthread::text::decode_as(&bytes, encoding, to).0;
    Ok(SourceFile::new(path.display().to_string(), text))
}

/// LinuxCNC's interpreter for `--rs274`, or why there is none.
fn find_interpreter() -> Result<ncthread::sim::rs274::Interpreter, Fatal> {
    ncthread::sim::rs274::Interpreter::find().ok_or_else(|| {
        Fatal::Usage(
            "--rs274: LinuxCNC's interpreter was not found: put `rs274` on the PATH or name a command in NCTHREAD_RS274 (the project's scripts/rs274 fetches one)".into(),
        )
    })
}

/// The verdict's first lines and the exit code it gives.
fn verdict(outcome: &Outcome, sides: &Sides) -> (String, ExitCode) {
    let (text, passes) =
        ncthread::frontend::verdict(outcome, sides.src, sides.from, &sides.other, sides.to);
    (
        text,
        if passes {
            ExitCode::SUCCESS
        } else {
            ExitCode::from(1)
        },
    )
}

/// The SVG of `--plot`: both motions, and the first difference marked.
fn plot(v: &Verification, sides: &Sides) -> String {
    let Sides {
        src,
        from,
        other,
        to,
    } = sides;
    let difference = match &v.outcome {
        Outcome::Different(d) => Some(&**d),
        _ => None,
    };
    ncthread::plot::verify_plot(
        &format!("verify: {} ({from}) against {other} ({to})", src.name),
        &format!("{} ({from})", src.name),
        &v.left_moves,
        &format!("{other} ({to})"),
        &v.right_moves,
        difference,
    )
}

/// One rs274 check's line, added to `text`; `false` when it fails the verification.
fn oracle_line(check: &OracleCheck, text: &mut String) -> bool {
    match &check.outcome {
        OracleOutcome::Equivalent {
            segments,
            deviation,
            partial,
        } => {
            text.push_str(&format!(
                "rs274 agrees: {} ({segments} segments{}; largest deviation {} mm)\n",
                check.what,
                if *partial {
                    ", up to where ncthread stops knowing the tool's path"
                } else {
                    ""
                },
                deviation.mm()
            ));
            true
        }
        OracleOutcome::Different(d) => {
            text.push_str(&format!(
                "rs274 DISAGREES: {}: {}\n  ncthread: {}\n  LinuxCNC: {}\n",
                check.what,
                d.what,
                ncthread::frontend::segment_text(&d.left),
                ncthread::frontend::segment_text(&d.right)
            ));
            false
        }
        OracleOutcome::Failed(e) => {
            text.push_str(&format!("rs274 could not check {}: {e}\n", check.what));
            false
        }
        OracleOutcome::CannotJudge(why) => {
            text.push_str(&format!("rs274 cannot judge {}: {why}\n", check.what));
            true
        }
    }
}

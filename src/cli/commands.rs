//! The commands that read one program: convert, simulate, explain and plot.

use std::process::ExitCode;

use ncthread::diag;

use super::Fatal;
use super::args::{ConvertArgs, ExplainArgs, ExplainFormat, OutputFormat, PlotArgs, SimulateArgs};
use super::io::{
    is_stdio, print_diagnostics, read_program, read_source, read_source_for, unsupported,
    write_encoded, write_output,
};

pub(crate) fn convert(args: ConvertArgs) -> Result<ExitCode, Fatal> {
    let profile = args.common.profile_for(&args.stdin.named(&args.input))?;
    let (src, from, input) = read_source_for(
        &args.input,
        &args.stdin,
        args.from,
        &args.common,
        args.to.into(),
        &profile,
    )?;
    let options = args
        .common
        .options(from, args.to.into(), profile, &args.target);
    // A large output's temporary file beside the file it becomes, which it then becomes.
    ncthread::files::spool_beside(args.output.as_deref().filter(|_| !is_stdio(&args.output)));
    let mut conversion = ncthread::convert(&src, &options);
    let bytes = conversion.output.take().map(|output| {
        let name = args
            .output
            .as_ref()
            .filter(|_| !is_stdio(&args.output))
            .map_or("<stdout>".to_string(), |p| p.display().to_string());
        ncthread::text::encode_output_owned(output, &name, &args.output_format.options(), &input)
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
    write_encoded(&args.output, bytes)?;
    Ok(ExitCode::SUCCESS)
}

pub(crate) fn simulate(args: SimulateArgs) -> Result<ExitCode, Fatal> {
    let profile = args.common.profile_for(&args.stdin.named(&args.input))?;
    let (src, from) = read_source(&args.input, &args.stdin, args.from, &args.common, &profile)?;
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

pub(crate) fn explain(args: ExplainArgs) -> Result<ExitCode, Fatal> {
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

pub(crate) fn plot(args: PlotArgs) -> Result<ExitCode, Fatal> {
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

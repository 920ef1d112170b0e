//! The help texts: the about lines and every command's examples, for `-h`, `--help` and
//! the manual pages.

/// The first line of `ncthread -h`, and (lower case) of the manual page's NAME.
pub(crate) const ABOUT: &str = "Convert lathe thread-cutting programs between the czech control, the НЦ-31, FANUC and ISO G-code (LinuxCNC): exact or refused";

pub(crate) const LONG_ABOUT: &str = "Convert lathe thread-cutting programs between the czech control, the НЦ-31, FANUC and ISO G-code (LinuxCNC): exact or refused.

Every conversion is exactly equivalent or refused with a diagnostic that names the block, the construct and why. `verify` proves a conversion by simulating both programs; `check`, `explain` and `plot` look at one; `batch` converts a whole archive. README.md is the manual: every option, every profile key and every diagnostic code.";

/// An example of a command line, for `-h` (the `short` ones), `--help` and the manual page.
pub(crate) struct Example {
    pub(crate) command: &'static str,
    pub(crate) what: &'static str,
    pub(crate) short: bool,
}

pub(crate) const fn ex(command: &'static str, what: &'static str, short: bool) -> Example {
    Example {
        command,
        what,
        short,
    }
}

pub(crate) const TOP_EXAMPLES: &[Example] = &[
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

pub(crate) const CONVERT_EXAMPLES: &[Example] = &[
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
        "ncthread convert P0001.NC --from czech --to siemens -o SHAFT.MPF",
        "a SINUMERIK main program, named after the source (`%_N_NC_P0001_MPF`)",
        false,
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

pub(crate) const SIMULATE_EXAMPLES: &[Example] = &[
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

pub(crate) const VERIFY_EXAMPLES: &[Example] = &[
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

pub(crate) const CHECK_EXAMPLES: &[Example] = &[
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

pub(crate) const EXPLAIN_EXAMPLES: &[Example] = &[
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

pub(crate) const PLOT_EXAMPLES: &[Example] = &[
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

pub(crate) const BATCH_EXAMPLES: &[Example] = &[
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
pub(crate) fn examples(list: &[Example], long: bool) -> String {
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
pub(crate) fn examples_of(name: &str) -> &'static [Example] {
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

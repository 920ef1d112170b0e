//! The command line: exit codes, stdin/stdout, files, and diagnostics on stderr.
mod common;

use std::process::Output;

use common::{ncthread, text};

/// `ncthread convert ARGS… --from czech --to iso`.
fn czech_to_iso(args: &[&str], stdin: Option<&[u8]>) -> Output {
    let all: Vec<&str> = ["convert"]
        .iter()
        .chain(args)
        .chain(&["--from", "czech", "--to", "iso"])
        .copied()
        .collect();
    ncthread(&all, stdin)
}

#[test]
fn converts_a_file_to_stdout() {
    let out = czech_to_iso(&["corpus/czech/ex3-taper.nc"], None);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(text(&out.stdout).contains("G33 X246 Z-100 K1.507052888241"));
    // Warnings go to stderr and do not fail the conversion.
    assert!(text(&out.stderr).contains("warning[ISOW002]"));
}

#[test]
fn is_a_pipe_filter() {
    let program = b"N10 M03 S100\nN20 G00 X30. Z5.\nN30 G33 Z-20. F1.5\n";
    let out = czech_to_iso(&[], Some(program));
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(text(&out.stdout).contains("G33 X30 Z-20 K1.5"));
    let out = czech_to_iso(&["-", "-o", "-"], Some(program));
    assert_eq!(out.status.code(), Some(0));
    assert!(text(&out.stdout).starts_with("%\n(<stdin>, dialect czech"));
}

#[test]
fn input_errors_exit_1_and_write_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let target = dir.path().join("out.ngc");
    let out = czech_to_iso(
        &[
            "corpus/bad/czech/lead-over-99.99.nc",
            "-o",
            target.to_str().unwrap(),
        ],
        None,
    );
    assert_eq!(out.status.code(), Some(1));
    assert!(
        !target.exists(),
        "an output was written for a refused program"
    );
    let err = text(&out.stderr);
    assert!(err.contains("error[CZR003]"), "{err}");
    assert!(
        err.contains("--> corpus/bad/czech/lead-over-99.99.nc:3:15"),
        "{err}"
    );
    assert!(err.contains("3 | N30 G33 Z-50. F120."), "{err}");
    assert!(err.contains("^^^^^"), "{err}");
    assert!(err.contains("help:"), "{err}");
}

#[test]
fn writes_the_output_file() {
    let dir = tempfile::tempdir().unwrap();
    let target = dir.path().join("out.ngc");
    let out = czech_to_iso(
        &[
            "corpus/czech/ex6b-entry-param-with-point.nc",
            "--profile",
            "corpus/czech/ex6b-entry-param-with-point.profile.toml",
            "-o",
            target.to_str().unwrap(),
        ],
        None,
    );
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(out.stdout.is_empty());
    assert!(
        std::fs::read_to_string(&target)
            .unwrap()
            .contains("G33 X63.9999 Z-88")
    );
}

#[test]
fn json_diagnostics_are_one_object_per_line() {
    let out = czech_to_iso(
        &["corpus/bad/czech/syntax-error.nc", "--diagnostics", "json"],
        None,
    );
    assert_eq!(out.status.code(), Some(1));
    let lines: Vec<serde_json::Value> = text(&out.stderr)
        .lines()
        .map(|l| serde_json::from_str(l).expect("a JSON object"))
        .collect();
    assert_eq!(lines.len(), 2);
    assert_eq!(lines[0]["code"], "CZR001");
    assert_eq!(
        (lines[0]["line"].as_u64(), lines[0]["column"].as_u64()),
        (Some(2), Some(14))
    );
}

#[test]
fn repeated_warnings_are_listed_a_few_times_and_the_rest_counted() {
    // 150 tool changes, each with an offset the НЦ-31 leaves out (NCW004).
    let mut program = String::from("N1 G95 M03 S800\n");
    for n in 2..=151 {
        program.push_str(&format!("N{n} T1 D1\n"));
    }
    program.push_str("N999 M30\n");
    let args = [
        "convert",
        "--from",
        "czech",
        "--to",
        "nc31",
        "--diagnostics",
        "json",
    ];
    let out = ncthread(&args, Some(program.as_bytes()));
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let lines: Vec<serde_json::Value> = text(&out.stderr)
        .lines()
        .map(|l| serde_json::from_str(l).expect("a JSON object"))
        .filter(|d: &serde_json::Value| d["code"] == "NCW004")
        .collect();
    // Ten listed, and the last standing for itself and the 139 others before it.
    assert_eq!(lines.len(), 11);
    let lines_of: Vec<u64> = lines.iter().filter_map(|d| d["line"].as_u64()).collect();
    assert_eq!(lines_of, [2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 151]);
    assert_eq!(lines[10]["more"], 139);
    assert_eq!(
        lines[10]["label"],
        "the last of 140 more NCW004 warnings (from line 12), not listed one by one"
    );
    assert!(lines[..10].iter().all(|d| d["more"].is_null()));
}

#[test]
fn check_counts_every_repeat_a_listed_diagnostic_stands_for() {
    // 150 thread passes and no spindle: LG001 on each, from the shared rules.
    let mut program = String::from("N1 G00 X30 Z5\n");
    for n in 2..=151 {
        program.push_str(&format!("N{n} G33 Z-{} F1.5\n", n - 1));
    }
    program.push_str("N999 M30\n");
    let out = ncthread(
        &["check", "--from", "czech", "-", "--diagnostics", "json"],
        Some(program.as_bytes()),
    );
    assert_eq!(out.status.code(), Some(1), "{}", text(&out.stderr));
    // The diagnostics on stdout.
    let lg001: Vec<serde_json::Value> = text(&out.stdout)
        .lines()
        .filter_map(|l| serde_json::from_str(l).ok())
        .filter(|d: &serde_json::Value| d["code"] == "LG001")
        .collect();
    assert_eq!(lg001.len(), 11);
    assert_eq!(lg001[10]["more"], 139);
    // The count (said with human diagnostics) counts the 139 the last one stands for.
    let human = ncthread(&["check", "--from", "czech", "-"], Some(program.as_bytes()));
    let stderr = text(&human.stderr);
    assert!(stderr.contains("150 error(s) in 1 file(s)"), "{stderr}");
}

/// The simulator's findings and a reader's are folded as the writers' are: listed ten times,
/// the rest counted in the last one, and every one counted.
#[test]
fn check_folds_the_simulators_and_the_readers_repeats() {
    // 30 moves from an X that is not known (SIM001 each), then 30 incremental ones from it
    // (ISOR006 each).
    let mut program = String::from("G21 G18 G7 G90\nS500 M3\n");
    for n in 1..=30 {
        program.push_str(&format!("G1 Z-{n} F0.2\n"));
    }
    let warnings = program.clone() + "M2\n";
    program.push_str("G91\n");
    for _ in 1..=30 {
        program.push_str("G1 X1\n");
    }
    program.push_str("M2\n");
    let codes = |input: &str| {
        let out = ncthread(
            &["check", "--from", "iso", "-", "--diagnostics", "json"],
            Some(input.as_bytes()),
        );
        let all: Vec<serde_json::Value> = text(&out.stdout)
            .lines()
            .filter_map(|l| serde_json::from_str(l).ok())
            .collect();
        let of = |code: &str| -> (usize, u64) {
            let mine: Vec<&serde_json::Value> = all.iter().filter(|d| d["code"] == code).collect();
            let more = mine.iter().map(|d| d["more"].as_u64().unwrap_or(0)).sum();
            (mine.len(), more)
        };
        // The count is said with human diagnostics.
        let human = ncthread(&["check", "--from", "iso", "-"], Some(input.as_bytes()));
        (of("SIM001"), of("ISOR006"), text(&human.stderr))
    };
    let (sim, reader, stderr) = codes(&warnings);
    assert_eq!(sim, (11, 19), "{stderr}");
    assert_eq!(reader, (0, 0));
    assert!(stderr.contains("30 warning(s)"), "{stderr}");
    // With an error in the read, the simulator's findings are not said.
    let (sim, reader, stderr) = codes(&program);
    assert_eq!(reader, (11, 19), "{stderr}");
    assert_eq!(sim, (0, 0));
    assert!(stderr.contains("30 error(s) in 1 file(s)"), "{stderr}");
}

#[test]
fn usage_and_io_errors_exit_2() {
    let out = ncthread(&["convert", "--from", "klingon", "--to", "iso"], None);
    assert_eq!(out.status.code(), Some(2));
    let out = czech_to_iso(&["no/such/file.nc"], None);
    assert_eq!(out.status.code(), Some(2));
    assert!(text(&out.stderr).contains("cannot read no/such/file.nc"));
    let dir = tempfile::tempdir().unwrap();
    let profile = dir.path().join("p.toml");
    std::fs::write(&profile, "[czech]\nconstant8 = \"12\"\n").unwrap();
    let out = czech_to_iso(
        &[
            "corpus/czech/ex3-taper.nc",
            "--profile",
            profile.to_str().unwrap(),
        ],
        None,
    );
    assert_eq!(out.status.code(), Some(2));
    assert!(
        text(&out.stderr).contains("error[PF002]"),
        "{}",
        text(&out.stderr)
    );
}

/// `--unsupported warn` keeps a block only where it means the same: in its own dialect and
/// modes. Across dialects it is refused in every mode, and a kept block may not carry words
/// whose effect later blocks depend on.
#[test]
fn unsupported_warn_keeps_a_block_only_where_it_means_the_same() {
    let program = b"N10 M03 S100\nN20 G00 X30. Z5.\nN30 G84 X26. Z-20.\nN40 G00 X40.\n";
    let out = czech_to_iso(&[], Some(program));
    assert_eq!(out.status.code(), Some(1));
    let out = czech_to_iso(&["--unsupported", "warn"], Some(program));
    assert_eq!(out.status.code(), Some(1), "{}", text(&out.stderr));
    let err = text(&out.stderr);
    assert!(
        err.contains("warning[CZR011]") && err.contains("error[LG003]"),
        "{err}"
    );
    let czech = |program: &[u8]| {
        ncthread(
            &[
                "convert",
                "-",
                "--from",
                "czech",
                "--to",
                "czech",
                "--unsupported",
                "warn",
            ],
            Some(program),
        )
    };
    let out = czech(program);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(
        text(&out.stdout).contains("N30 G84 X26. Z-20.\n"),
        "{}",
        text(&out.stdout)
    );
    // Under G91 the kept block would read absolute in the output.
    let out = czech(b"N10 M03 S100\nN20 G00 X30. Z5.\nN25 G91\nN30 G84 Z-20.\nN35 G90\n");
    assert_eq!(out.status.code(), Some(1));
    assert!(
        text(&out.stderr).contains("incremental coordinates (G91)"),
        "{}",
        text(&out.stderr)
    );
    // F on the kept block would change the F register the next G33 may use.
    let out = czech(b"N10 M03 S100\nN20 G00 X30. Z5.\nN30 G84 X26. Z-20. F1.5\n");
    assert_eq!(out.status.code(), Some(1));
    assert!(
        text(&out.stderr).contains("`F1.5` in a block kept opaque"),
        "{}",
        text(&out.stderr)
    );
}

#[test]
fn reads_nc31_and_refuses_its_faults_with_line_and_column() {
    let out = ncthread(
        &[
            "convert",
            "corpus/nc31/g31-m36x1.5.nc",
            "--from",
            "nc31",
            "--to",
            "iso",
        ],
        None,
    );
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert_eq!(text(&out.stdout).matches("G33 X").count(), 8);
    let out = ncthread(
        &[
            "convert",
            "corpus/bad/nc31/decimal-point.nc",
            "--from",
            "nc31",
            "--to",
            "iso",
        ],
        None,
    );
    assert_eq!(out.status.code(), Some(1));
    assert!(out.stdout.is_empty());
    let err = text(&out.stderr);
    assert!(
        err.contains("error[NCR002]") && err.contains("--> corpus/bad/nc31/decimal-point.nc:8:7"),
        "{err}"
    );
}

#[test]
fn from_auto_chooses_the_dialect_and_says_so_when_unsure() {
    // Certain: `*`/`~` frames. Nothing said.
    let program = std::fs::read("corpus/nc31/g33-tap-m20x1.5.nc").unwrap();
    let out = ncthread(
        &["convert", "--from", "auto", "--to", "iso"],
        Some(&program),
    );
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(text(&out.stdout).contains("G33.1 Z-100 K1.5"));
    assert!(
        !text(&out.stderr).contains("--from auto"),
        "{}",
        text(&out.stderr)
    );
    // Czech marks: `"` comments.
    let out = ncthread(
        &[
            "convert",
            "corpus/czech/ex3-taper.nc",
            "--from",
            "auto",
            "--to",
            "iso",
        ],
        None,
    );
    assert!(
        text(&out.stdout).contains("dialect czech"),
        "{}",
        text(&out.stderr)
    );
    // Unsure: decimal words without any mark are read as czech, and it says so.
    let out = ncthread(
        &["convert", "--from", "auto", "--to", "iso"],
        Some(b"N10 M03 S100\nN20 G00 X30. Z5.\nN30 G33 Z-20. F1.5\n"),
    );
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let err = text(&out.stderr);
    assert!(
        err.contains("--from auto: reading <stdin> as czech"),
        "{err}"
    );
}

/// `--from auto` names the FANUC G-code system it reads a program in, and why (issue 32).
#[test]
fn from_auto_names_the_fanuc_gcode_system() {
    let run = |file: &str| {
        let out = ncthread(&["convert", file, "--from", "auto", "--to", "iso"], None);
        assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
        text(&out.stderr)
    };
    let a = run("corpus/fanuc/g32-taper.nc");
    assert!(a.contains("as fanuc, G-code system A (the default"), "{a}");
    // The sidecar profile says B.
    let b = run("corpus/fanuc/system-b.nc");
    assert!(
        b.contains("G-code system B (the profile's `gcode_system`)"),
        "{b}"
    );
    let c = run("corpus/fanuc/system-c.nc");
    assert!(
        c.contains("G-code system C (the profile's `gcode_system`)"),
        "{c}"
    );
    // Another dialect has no variant to name.
    let czech = run("corpus/czech/ex3-taper.nc");
    assert!(!czech.contains("G-code system"), "{czech}");
}

#[test]
fn simulate_prints_the_motion_as_text_or_json() {
    let out = ncthread(
        &["simulate", "corpus/nc31/g31-m36x1.5.nc", "--from", "nc31"],
        None,
    );
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    assert!(
        stdout
            .contains("line 10 pass 8  thread  X34.08 Z4.5 → X34.08 Z-47.5  lead 1.5 M3 phase 0°"),
        "{stdout}"
    );
    let out = ncthread(
        &[
            "simulate",
            "corpus/czech/ex7-large-pitch.nc",
            "--from",
            "czech",
            "--format",
            "json",
        ],
        None,
    );
    assert_eq!(out.status.code(), Some(0));
    let lines: Vec<serde_json::Value> = text(&out.stdout)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    // The spindle start is a change of the machine state, then the thread.
    assert_eq!(lines[0]["motion"], "state");
    assert_eq!(lines[0]["spindle"], "M3");
    let first = &lines[1];
    assert_eq!(first["motion"], "thread");
    assert_eq!(first["lead"], 250.0);
    // The pass starts from an unknown position: a warning says so.
    assert!(
        text(&out.stderr).contains("warning[SIM001]"),
        "{}",
        text(&out.stderr)
    );
    let out = ncthread(
        &[
            "simulate",
            "corpus/bad/nc31/decimal-point.nc",
            "--from",
            "nc31",
        ],
        None,
    );
    assert_eq!(out.status.code(), Some(1));
    assert!(out.stdout.is_empty());
}

#[test]
fn verify_proves_a_conversion_and_checks_a_hand_conversion() {
    // Acceptance: the seed G31 M36×1.5 against a hand-written ISO program with its 8 passes.
    let seed = "corpus/nc31/g31-m36x1.5.nc";
    let out = ncthread(&["verify", seed, "--from", "nc31", "--to", "iso"], None);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stdout));
    assert!(text(&out.stdout).starts_with("equivalent:"));
    let against = |file: &str| {
        ncthread(
            &[
                "verify",
                seed,
                "--from",
                "nc31",
                "--to",
                "iso",
                "--against",
                file,
            ],
            None,
        )
    };
    let out = against("corpus/iso/m36x1.5-by-hand.ngc");
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stdout));
    // One pass 0.02 mm off: exit 1, and the report names the pass and both lines.
    let out = against("corpus/iso/m36x1.5-by-hand-pass5-off.ngc");
    assert_eq!(out.status.code(), Some(1), "{}", text(&out.stdout));
    let report = text(&out.stdout);
    assert!(report.starts_with("DIFFERENT:"), "{report}");
    assert!(report.contains("line 10 (pass 5) vs line 31"), "{report}");
    assert!(
        report.contains("X34.255") && report.contains("X34.275"),
        "{report}"
    );
    // A source that cannot be read: refused, exit 1; a missing file: exit 2.
    let out = ncthread(
        &[
            "verify",
            "corpus/bad/nc31/lead-zero.nc",
            "--from",
            "nc31",
            "--to",
            "iso",
        ],
        None,
    );
    assert_eq!(out.status.code(), Some(1));
    assert!(text(&out.stdout).starts_with("not verified"));
    let out = against("corpus/iso/no-such-file.ngc");
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn reads_iso_and_linuxcnc_g76() {
    let out = ncthread(
        &[
            "convert",
            "corpus/iso/g76-external.ngc",
            "--from",
            "iso",
            "--to",
            "iso",
        ],
        None,
    );
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let ngc = text(&out.stdout);
    assert!(ngc.contains("(pass 45/45: depth 1.2267, cut 0)"), "{ngc}");
    assert!(!ngc.lines().any(|l| l.starts_with("G76")));
    let out = ncthread(
        &["simulate", "corpus/iso/g76-external.ngc", "--from", "auto"],
        None,
    );
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(text(&out.stdout).contains("line 7 pass 45  thread"));
    // Arcs are read and written back; a target without arcs refuses them by name.
    let out = ncthread(
        &[
            "convert",
            "corpus/iso/part-shaft-m20.ngc",
            "--from",
            "iso",
            "--to",
            "iso",
        ],
        None,
    );
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(text(&out.stdout).contains("G2 X38 Z-48 I4.47215 K-4 F0.1"));
    let out = ncthread(
        &[
            "convert",
            "corpus/iso/part-shaft-m20.ngc",
            "--from",
            "iso",
            "--to",
            "czech",
        ],
        None,
    );
    assert_eq!(out.status.code(), Some(1));
    assert!(
        text(&out.stderr)
            .contains("error[CZW002]: an arc (G2/G3) has no form that the czech seed documents")
    );
    let out = ncthread(
        &[
            "convert",
            "corpus/bad/iso/arc-without-feed.ngc",
            "--from",
            "iso",
            "--to",
            "iso",
        ],
        None,
    );
    assert_eq!(out.status.code(), Some(1));
    assert!(text(&out.stderr).contains("error[ISOR004]: G2 with no feed rate (F) set, or F0"));
}

#[test]
fn czech_to_czech_keeps_start_angles_parameters_opaque_words_and_comments() {
    let convert = |file: &str| {
        let out = ncthread(&["convert", file, "--from", "czech", "--to", "czech"], None);
        assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
        text(&out.stdout)
    };
    let ex1 = convert("corpus/czech/ex1-multipass.nc");
    assert!(
        ex1.contains("&1100") && ex1.contains("\"HLAVNI VETA"),
        "{ex1}"
    );
    assert!(ex1.contains("N335 G33 Z-9. F1.5"), "{ex1}");
    let ex7 = convert("corpus/czech/ex7-large-pitch.nc");
    assert!(ex7.contains("R10=250.0") && ex7.contains("FR10"), "{ex7}");
    let i180 = convert("corpus/czech/multistart-i180.nc");
    assert!(i180.contains("I180"), "{i180}");
    // A lead over 99.99 from another dialect goes through a free parameter.
    let out = ncthread(
        &["convert", "-", "--from", "iso", "--to", "czech"],
        Some(b"G7 G18 G21 G90 G95\nS100 M3\nG0 X40 Z5\nG33 Z-200 K250\nM30\n"),
    );
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let czech = text(&out.stdout);
    assert!(
        czech.contains("R01=250.") && czech.contains("G33 Z-200. FR01"),
        "{czech}"
    );
    // Values that need a 4th decimal: refused, or rounded with --round.
    let fine = b"G7 G18 G21 G90 G95\nS100 M3\nG0 X26.6185 Z5\nM30\n";
    let out = ncthread(
        &["convert", "-", "--from", "iso", "--to", "czech"],
        Some(fine),
    );
    assert_eq!(out.status.code(), Some(1));
    assert!(text(&out.stderr).contains("error[CZW001]"));
    let out = ncthread(
        &["convert", "-", "--from", "iso", "--to", "czech", "--round"],
        Some(fine),
    );
    assert_eq!(out.status.code(), Some(0));
    assert!(text(&out.stderr).contains("warning[CZW005]"));
    assert!(
        text(&out.stdout).contains("X26.619"),
        "{}",
        text(&out.stdout)
    );
}

/// Issue 5's acceptance for nc31 output.
#[test]
fn writes_nc31_exactly_or_refuses_with_the_reason() {
    let to_nc31 = |args: &[&str]| {
        let all: Vec<&str> = ["convert"]
            .iter()
            .chain(args)
            .chain(&["--to", "nc31"])
            .copied()
            .collect();
        ncthread(&all, None)
    };
    // czech X26.618 is not representable at 0.01 mm: refused with its line.
    let out = to_nc31(&["corpus/czech/ex1-multipass.nc", "--from", "czech"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(out.stdout.is_empty());
    let err = text(&out.stderr);
    assert!(
        err.contains("error[NCW001]: X 26.618 mm is not a whole number")
            && err.contains("--> corpus/czech/ex1-multipass.nc:2:1"),
        "{err}"
    );
    // With --round it converts and warns with the largest deviation.
    let out = to_nc31(&[
        "corpus/czech/ex1-multipass.nc",
        "--from",
        "czech",
        "--round",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let err = text(&out.stderr);
    assert!(
        err.contains("warning[NCW005]: 3 value(s) rounded") && err.contains("0.003 mm"),
        "{err}"
    );
    let nc31 = text(&out.stdout);
    assert!(
        nc31.contains("X2662 ~ *") && nc31.contains("G32 *\nN6 F15000 *\nN7 Z-900"),
        "{nc31}"
    );
    // A czech J runout: refused, naming the runout.
    let out = to_nc31(&[
        "corpus/czech/ex4-runout-constant.nc",
        "--from",
        "czech",
        "--profile",
        "corpus/czech/ex4-runout-constant.profile.toml",
    ]);
    assert_eq!(out.status.code(), Some(1));
    let err = text(&out.stderr);
    assert!(
        err.contains("error[NCW003]: the thread pass has a runout (12 mm), which G32 cannot cut"),
        "{err}"
    );
    // nc31 → nc31 keeps G31 as a cycle, and the `(` comments of a PC-side file.
    let out = to_nc31(&["corpus/nc31/pc-archive-cp866-crlf.nc", "--from", "nc31"]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    // The file's CRLF line endings and its encoding (IBM866) are kept.
    assert!(out.stdout.ends_with(b"M30\r\n%\r\n"));
    let (decoded, _, errors) = encoding_rs::IBM866.decode(&out.stdout);
    assert!(!errors);
    let nc31 = decoded.replace("\r\n", "\n");
    assert!(
        nc31.contains("N9 G31 *\nN10 X3600 *\nN11 Z-4750 *\nN12 F15000 *\nN13 P96 *\nN14 P20\n"),
        "{nc31}"
    );
    assert!(nc31.contains("(ПОДВОД В НАЧАЛЬНУЮ ТОЧКУ ЦИКЛА)"), "{nc31}");
    // Comments from another dialect: dropped with one warning, or kept on request.
    let out = to_nc31(&["corpus/czech/windows-1250.nc", "--from", "czech"]);
    assert_eq!(out.status.code(), Some(0));
    assert!(text(&out.stderr).contains("warning[NCW007]: 3 comment(s) left out"));
    assert!(!text(&out.stdout).contains('('));
    let out = to_nc31(&[
        "corpus/czech/windows-1250.nc",
        "--from",
        "czech",
        "--nc31-comments",
    ]);
    assert_eq!(out.status.code(), Some(0));
    assert!(!text(&out.stderr).contains("NCW007"));
    assert!(
        text(&out.stdout).contains("(ROZTOČENÍ"),
        "{}",
        text(&out.stdout)
    );
}

/// `verify --round` reports the largest deviation that `convert --round` reports.
#[test]
fn verify_and_convert_agree_on_the_rounding_deviation() {
    let program =
        b"G7 G18 G21 G90 G95\nS800 M3\nG0 X36.0004 Z3.0003\nG33 Z-20.0004 K1.5\nG0 X38\nM30\n";
    let args = ["-", "--from", "iso", "--to", "czech", "--round"];
    let convert = ncthread(&[&["convert"][..], &args].concat(), Some(program));
    assert_eq!(convert.status.code(), Some(0));
    assert!(
        text(&convert.stderr).contains("the largest deviation is 0.0004 mm"),
        "{}",
        text(&convert.stderr)
    );
    let verify = ncthread(&[&["verify"][..], &args].concat(), Some(program));
    assert_eq!(verify.status.code(), Some(0));
    assert!(
        text(&verify.stdout).contains("largest deviation 0.0004 mm"),
        "{}",
        text(&verify.stdout)
    );
}

/// `verify --rs274` holds LinuxCNC's run of each ISO side against ncthread's simulation of the
/// other (the taper whose lead once drifted), and a missing interpreter is an error, not a pass.
#[test]
fn verify_rs274_is_a_second_judge() {
    let run = |rs274: &std::path::Path| {
        std::process::Command::new(env!("CARGO_BIN_EXE_ncthread"))
            .args([
                "verify",
                "corpus/fidelity/taper-lead-quantised.ngc",
                "--from",
                "iso",
                "--to",
                "iso",
                "--rs274",
            ])
            .env("NCTHREAD_RS274", rs274)
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .output()
            .unwrap()
    };
    let missing = run(std::path::Path::new("/nonexistent/rs274"));
    assert_eq!(missing.status.code(), Some(1));
    assert!(text(&missing.stdout).contains("rs274 could not check"));
    let Some(rs274) = common::rs274() else { return };
    let out = run(rs274);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stdout));
    assert_eq!(
        text(&out.stdout).matches("rs274 agrees").count(),
        2,
        "{}",
        text(&out.stdout)
    );
}

#[test]
fn a_mill_program_is_refused_in_every_mode() {
    for mode in ["error", "warn"] {
        let out = ncthread(
            &[
                "convert",
                "corpus/bad/iso/mill-program-xy-plane.ngc",
                "--from",
                "iso",
                "--to",
                "iso",
                "--unsupported",
                mode,
            ],
            None,
        );
        assert_eq!(out.status.code(), Some(1), "--unsupported {mode}");
        assert!(text(&out.stdout).is_empty(), "--unsupported {mode}");
        let err = text(&out.stderr);
        assert!(
            err.contains(
                "error[ISOR021]: `Y0`: an axis other than X and Z: this is not a lathe program"
            ),
            "--unsupported {mode}: {err}"
        );
        // Reported at its first line only: the program is refused whole.
        assert_eq!(err.matches("ISOR021").count(), 1, "{err}");
    }
}

/// Every subcommand says an I/O error in one form, `error: cannot ACTION PATH: reason`, the
/// reason without Rust's `(os error N)`.
#[test]
fn io_errors_are_worded_alike_in_every_subcommand() {
    let missing = "error: cannot read no/such/file.nc: no such file or directory\n";
    for args in [
        &[
            "convert",
            "no/such/file.nc",
            "--from",
            "czech",
            "--to",
            "iso",
        ][..],
        &["simulate", "no/such/file.nc", "--from", "czech"],
        &["explain", "no/such/file.nc", "--from", "czech"],
        &["plot", "no/such/file.nc", "--from", "czech"],
        &[
            "verify",
            "no/such/file.nc",
            "--from",
            "czech",
            "--to",
            "iso",
        ],
        &["check", "no/such/file.nc", "--from", "czech", "--quiet"],
    ] {
        let out = ncthread(args, None);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert_eq!(text(&out.stderr), missing, "{args:?}");
    }
    let out = ncthread(
        &[
            "verify",
            "corpus/czech/ex3-taper.nc",
            "--from",
            "czech",
            "--to",
            "iso",
            "--against",
            "no/such/file.nc",
        ],
        None,
    );
    assert_eq!(text(&out.stderr), missing);
    let out = czech_to_iso(
        &["corpus/czech/ex3-taper.nc", "--profile", "no/such/file.nc"],
        None,
    );
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(text(&out.stderr), missing);
    let dir = tempfile::tempdir().unwrap();
    let out = ncthread(
        &[
            "batch",
            "no/such/file.nc",
            dir.path().to_str().unwrap(),
            "--from",
            "czech",
            "--to",
            "iso",
        ],
        None,
    );
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(text(&out.stderr), missing);
    let report = dir.path().join("no/report.json");
    let out = ncthread(
        &[
            "batch",
            "corpus/czech",
            dir.path().join("out").to_str().unwrap(),
            "--from",
            "czech",
            "--to",
            "iso",
            "--report",
            report.to_str().unwrap(),
        ],
        None,
    );
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        text(&out.stderr),
        format!(
            "error: cannot write {}: no such file or directory\n",
            report.display()
        )
    );
    let output = dir.path().join("no/p.ngc");
    let out = czech_to_iso(
        &["corpus/czech/ex3-taper.nc", "-o", output.to_str().unwrap()],
        None,
    );
    // After the conversion's warnings.
    assert!(
        text(&out.stderr).ends_with(&format!(
            "\n\nerror: cannot write {}: the folder {} does not exist\n",
            output.display(),
            dir.path().join("no").display()
        )),
        "{}",
        text(&out.stderr)
    );
}

/// `--stdin-filename NAME` names a program that comes on stdin in every subcommand that reads
/// one: its diagnostics say NAME, and its sidecar profile is found beside NAME (ex4's runout
/// needs the machine's constant 8 from it).
#[test]
fn stdin_filename_names_the_program_and_finds_its_profile() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(
        "corpus/czech/ex4-runout-constant.profile.toml",
        dir.path().join("P4.profile.toml"),
    )
    .unwrap();
    let name = dir.path().join("P4.nc");
    let name = name.to_str().unwrap();
    let program = std::fs::read("corpus/czech/ex4-runout-constant.nc").unwrap();
    let bad = b"N10 M03 S500\nN20 G00 X30. Z\n";
    for args in [
        &["convert", "--from", "czech", "--to", "iso"][..],
        &["simulate", "--from", "czech"],
        &["explain", "--from", "czech"],
        &["plot", "--from", "czech"],
        &["verify", "--from", "czech", "--to", "iso"],
        &["check", "--from", "czech"],
    ] {
        let named: Vec<&str> = args
            .iter()
            .copied()
            .chain(["--stdin-filename", name])
            .collect();
        let out = ncthread(&named, Some(&program));
        assert_eq!(
            out.status.code(),
            Some(0),
            "{args:?}: {}",
            text(&out.stderr)
        );
        let unnamed = ncthread(args, Some(&program));
        assert_eq!(unnamed.status.code(), Some(1), "{args:?}: no profile");
        let out = ncthread(&named, Some(bad));
        assert_eq!(out.status.code(), Some(1), "{args:?}");
        let said = text(&out.stderr) + &text(&out.stdout);
        assert!(said.contains(&format!("--> {name}:2:")), "{args:?}: {said}");
    }
}

/// `--color auto|always|never` colours the diagnostics (ANSI escapes); `auto` colours a pipe
/// only under CLICOLOR_FORCE, and never under NO_COLOR. Batch's one-line errors too.
#[test]
fn color_is_asked_for_or_follows_no_color_and_clicolor_force() {
    let bad: &[u8] = b"N10 M03 S500\nN20 G00 X30. Z\n";
    let run = |args: &[&str], env: &[(&str, &str)]| {
        use std::io::Write as _;
        let mut command = std::process::Command::new(env!("CARGO_BIN_EXE_ncthread"));
        command
            .args(["convert", "--from", "czech", "--to", "iso"])
            .args(args)
            .env_remove("NO_COLOR")
            .env_remove("CLICOLOR_FORCE")
            .env_remove("CLICOLOR")
            .stdin(std::process::Stdio::piped())
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped());
        for (k, v) in env {
            command.env(k, v);
        }
        let mut child = command.spawn().unwrap();
        child.stdin.take().unwrap().write_all(bad).unwrap();
        let out = child.wait_with_output().unwrap();
        assert_eq!(out.status.code(), Some(1));
        text(&out.stderr).contains("\x1b[")
    };
    assert!(!run(&[], &[]), "a pipe: no colour");
    assert!(run(&["--color", "always"], &[]));
    assert!(
        run(&["--color=always"], &[("NO_COLOR", "1")]),
        "the flag wins"
    );
    assert!(!run(&["--color", "never"], &[("CLICOLOR_FORCE", "1")]));
    assert!(run(&[], &[("CLICOLOR_FORCE", "1")]));
    assert!(!run(&[], &[("CLICOLOR_FORCE", "1"), ("NO_COLOR", "1")]));
    // Before the subcommand too.
    let out = ncthread(
        &["--color", "always", "check", "--from", "czech", "-"],
        Some(bad),
    );
    assert!(text(&out.stdout).contains("\x1b["), "{}", text(&out.stdout));
    // batch's one-line errors.
    let dir = tempfile::tempdir().unwrap();
    let src = dir.path().join("src");
    std::fs::create_dir(&src).unwrap();
    std::fs::write(src.join("bad.nc"), bad).unwrap();
    let out = ncthread(
        &[
            "batch",
            src.to_str().unwrap(),
            dir.path().join("out").to_str().unwrap(),
            "--from",
            "czech",
            "--to",
            "iso",
            "--color",
            "always",
        ],
        None,
    );
    assert!(
        text(&out.stderr).contains("\x1b[1m\x1b[91merror[CZR001]\x1b[0m"),
        "{}",
        text(&out.stderr)
    );
}

/// `-h` is the short help with a few examples, `--help` the long one with more; the first
/// line names every dialect; `--round`, `--profile`, `--ext` say what they do for each target;
/// the manual pages' NAME reads "ncthread - convert …", a subcommand's synopsis is typed as
/// `ncthread convert`, and its examples are an EXAMPLES section.
#[test]
fn help_is_short_or_long_with_examples_and_the_man_pages_read_as_man_pages() {
    let short = text(&ncthread(&["-h"], None).stdout);
    let long = text(&ncthread(&["--help"], None).stdout);
    let first = short.lines().next().unwrap();
    for dialect in ["czech", "НЦ-31", "FANUC", "ISO"] {
        assert!(first.contains(dialect), "{first}");
    }
    assert!(
        short.contains("\nExamples:\n  ncthread convert "),
        "{short}"
    );
    assert!(long.contains("\nExamples:\n"), "{long}");
    assert!(long.lines().count() > short.lines().count());
    assert!(long.contains("ncthread man --dir") && !short.contains("ncthread man --dir"));
    for sub in [
        "convert", "simulate", "verify", "check", "explain", "plot", "batch",
    ] {
        let short = text(&ncthread(&[sub, "-h"], None).stdout);
        assert!(
            short.contains(&format!("\nExamples:\n  ncthread {sub} ")),
            "{sub}: {short}"
        );
    }
    let convert = text(&ncthread(&["convert", "--help"], None).stdout);
    let round = convert.split("--round").nth(1).unwrap();
    assert!(
        round.contains("czech, fanuc, siemens and heidenhain: lengths to 0.001 mm")
            && round.contains("nc31: whole units"),
        "{round}"
    );
    let profile = convert.split("--profile <FILE>").nth(1).unwrap();
    for section in ["[czech]", "[nc31]", "[iso]", "[fanuc]"] {
        assert!(profile.contains(section), "{section}: {profile}");
    }
    let batch = text(&ncthread(&["batch", "--help"], None).stdout);
    assert!(
        batch.contains("ngc for iso") && batch.contains("nc for fanuc"),
        "{batch}"
    );
    let page = text(&ncthread(&["man"], None).stdout);
    assert!(
        page.contains(".SH NAME\nncthread \\- convert lathe thread\\-cutting programs between the czech control, the НЦ\\-31, FANUC and ISO G\\-code"),
        "{page}"
    );
    let page = text(&ncthread(&["man", "convert"], None).stdout);
    assert!(
        page.contains(".TH ncthread-convert 1  \"ncthread "),
        "{page}"
    );
    assert!(
        page.contains(".SH NAME\nncthread\\-convert \\- convert one program"),
        "{page}"
    );
    assert!(page.contains("\\fBncthread convert\\fR ["), "{page}");
    assert!(
        page.contains(".SH EXAMPLES\n.TP\n\\fBncthread convert "),
        "{page}"
    );
    assert!(!page.contains(".SH EXTRA"), "{page}");
}

/// Random bytes are refused as binary (INP003) whatever `--from` says, in one short error:
/// not ENC003's "give --encoding", not a syntax error per line.
#[test]
fn binary_input_is_refused_as_binary() {
    let random: Vec<u8> = (0u64..200_000)
        .map(|i| (i.wrapping_mul(6_364_136_223_846_793_005) >> 29) as u8)
        .collect();
    for from in ["auto", "czech", "nc31", "iso", "fanuc"] {
        for command in ["convert", "check"] {
            let mut args = vec![command, "--from", from];
            if command == "convert" {
                args.extend(["--to", "iso"]);
            }
            let out = ncthread(&args, Some(&random));
            assert_eq!(out.status.code(), Some(1), "{args:?}");
            let said = text(&out.stderr) + &text(&out.stdout);
            assert!(
                said.contains("error[INP003]: <stdin> is binary"),
                "{args:?}: {said}"
            );
            assert!(!said.contains("ENC003"), "{args:?}: {said}");
            assert!(said.len() < 1000, "{args:?}: {} bytes", said.len());
        }
    }
}

/// Text that is no program has an error on nearly every line: at most `--max-errors N` (50 by
/// default, 0 every one) are printed per file, then how many more there are; JSON prints
/// every one.
#[test]
fn errors_stop_at_a_cap_with_a_count() {
    // 500 lines of letters and digits: one НЦ-31 error each.
    let mut seed = 7u64;
    let mut junk = String::new();
    for _ in 0..500 {
        for _ in 0..30 {
            seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            junk.push(b"ABCXYZ0123456789.;#%"[(seed >> 33) as usize % 20] as char);
        }
        junk.push('\n');
    }
    let errors = |s: &str| s.matches("error[").count();
    let convert = |extra: &[&str]| {
        let mut args = vec!["convert", "--from", "nc31", "--to", "iso"];
        args.extend(extra);
        let out = ncthread(&args, Some(junk.as_bytes()));
        assert_eq!(out.status.code(), Some(1));
        text(&out.stderr)
    };
    // A reader lists a hundred errors of one code and counts the rest in the last
    // (diag::Fold): every one is in the count the note gives.
    let listed = errors(&convert(&["--max-errors", "0"]));
    let json = convert(&["--diagnostics", "json"]);
    assert_eq!(json.lines().count(), listed, "JSON is not capped");
    let all: usize = json
        .lines()
        .map(|l| {
            let d: serde_json::Value = serde_json::from_str(l).unwrap();
            1 + d["more"].as_u64().unwrap_or(0) as usize
        })
        .sum();
    assert!(all >= 400 && listed < all, "{listed} listed of {all}");
    let capped = convert(&[]);
    assert_eq!(errors(&capped), 50, "{capped}");
    assert!(
        capped.ends_with(&format!(
            "note: {} more errors in <stdin> not shown (--max-errors 0 shows every one)\n",
            all - 50
        )),
        "{capped}"
    );
    assert_eq!(errors(&convert(&["--max-errors", "3"])), 3);
    let out = ncthread(&["check", "--from", "nc31"], Some(junk.as_bytes()));
    assert_eq!(errors(&text(&out.stdout)), 50);
    assert!(text(&out.stdout).contains("more errors in <stdin> not shown"));
    // batch's one-line errors.
    let dir = tempfile::tempdir().unwrap();
    let src = dir.path().join("src");
    std::fs::create_dir(&src).unwrap();
    std::fs::write(src.join("junk.nc31"), &junk).unwrap();
    let out = ncthread(
        &[
            "batch",
            src.to_str().unwrap(),
            dir.path().join("out").to_str().unwrap(),
            "--from",
            "nc31",
            "--to",
            "iso",
            "--max-errors",
            "10",
        ],
        None,
    );
    let err = text(&out.stderr);
    assert_eq!(errors(&err), 10, "{err}");
    assert!(
        err.contains(&format!(
            "note: {} more errors in {} not shown",
            all - 10,
            src.join("junk.nc31").display()
        )),
        "{err}"
    );
}

/// A full disk on stdout (Linux's /dev/full): exit 2, in the one wording.
#[cfg(target_os = "linux")]
#[test]
fn a_full_stdout_is_exit_2() {
    let full = std::fs::OpenOptions::new()
        .write(true)
        .open("/dev/full")
        .unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_ncthread"))
        .args([
            "convert",
            "corpus/czech/ex3-taper.nc",
            "--from",
            "czech",
            "--to",
            "czech",
        ])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stdout(full)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(
        text(&out.stderr).ends_with("error: cannot write stdout: no space left on device\n"),
        "{}",
        text(&out.stderr)
    );
}

/// A large output (past the writer's 1 MiB in memory) is written in a temporary file beside
/// the file it goes to, which becomes that file by a link and a rename: the same bytes as on
/// stdout, the same mode as a small output's file (written as a copy), nothing else left in
/// the folder, and an existing file replaced; through an encoding that changes the text
/// (CRLF) too. Linux only (elsewhere the output is copied, as a small one is).
#[cfg(target_os = "linux")]
#[test]
fn a_large_output_becomes_its_file_without_a_copy() {
    use std::os::unix::fs::PermissionsExt as _;
    let dir = tempfile::tempdir().unwrap();
    let source = dir.path().join("big.nc");
    std::fs::write(&source, common::large_czech_program(3 << 20)).unwrap();
    let source = source.to_str().unwrap();
    let out = dir.path().join("out");
    std::fs::create_dir(&out).unwrap();
    let stdout = czech_to_iso(&[source], None);
    assert_eq!(stdout.status.code(), Some(0), "{}", text(&stdout.stderr));
    assert!(stdout.stdout.len() > 1 << 20);
    let small = out.join("small.ngc");
    let small_run = czech_to_iso(
        &["corpus/czech/ex3-taper.nc", "-o", small.to_str().unwrap()],
        None,
    );
    assert_eq!(
        small_run.status.code(),
        Some(0),
        "{}",
        text(&small_run.stderr)
    );
    let mode = |p: &std::path::Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
    let big = out.join("big.ngc");
    std::fs::write(&big, "an older file\n").unwrap();
    let crlf = stdout.stdout.iter().fold(Vec::new(), |mut v, &b| {
        if b == b'\n' {
            v.push(b'\r');
        }
        v.push(b);
        v
    });
    for (eol, expected) in [("keep", stdout.stdout.clone()), ("crlf", crlf)] {
        let args = [source, "-o", big.to_str().unwrap(), "--eol", eol];
        let run = czech_to_iso(&args, None);
        assert_eq!(run.status.code(), Some(0), "{}", text(&run.stderr));
        assert!(std::fs::read(&big).unwrap() == expected, "{eol}");
        assert_eq!(mode(&big), mode(&small));
        let mut names: Vec<_> = std::fs::read_dir(&out)
            .unwrap()
            .map(|e| e.unwrap().file_name().into_string().unwrap())
            .collect();
        names.sort();
        assert_eq!(names, ["big.ngc", "small.ngc"]);
    }
}

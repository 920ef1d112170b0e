//! The command line: exit codes, stdin/stdout, files, and diagnostics on stderr.
use std::io::Write;
use std::process::{Command, Output, Stdio};

fn ncthread(args: &[&str], stdin: Option<&[u8]>) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_ncthread"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("ncthread runs");
    let mut pipe = child.stdin.take().unwrap();
    pipe.write_all(stdin.unwrap_or_default()).unwrap();
    drop(pipe);
    child.wait_with_output().unwrap()
}

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

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

#[test]
fn converts_a_file_to_stdout() {
    let out = czech_to_iso(&["corpus/czech/ex3-taper.nc"], None);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(text(&out.stdout).contains("G33 X246 Z-100 K1.50705289"));
    // Warnings go to stderr and do not fail the conversion.
    assert!(text(&out.stderr).contains("warning[ISO002]"));
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
            "corpus/bad/lead-over-99.99.nc",
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
    assert!(err.contains("error[CZ003]"), "{err}");
    assert!(
        err.contains("--> corpus/bad/lead-over-99.99.nc:3:15"),
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
        &["corpus/bad/syntax-error.nc", "--diagnostics", "json"],
        None,
    );
    assert_eq!(out.status.code(), Some(1));
    let lines: Vec<serde_json::Value> = text(&out.stderr)
        .lines()
        .map(|l| serde_json::from_str(l).expect("a JSON object"))
        .collect();
    assert_eq!(lines.len(), 2);
    assert_eq!(lines[0]["code"], "CZ001");
    assert_eq!(
        (lines[0]["line"].as_u64(), lines[0]["column"].as_u64()),
        (Some(2), Some(14))
    );
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

#[test]
fn unsupported_warn_keeps_the_block_as_a_comment() {
    let program = b"N10 M03 S100\nN20 G00 X30. Z5.\nN30 G84 X26. Z-20. F1.5\n";
    let out = czech_to_iso(&[], Some(program));
    assert_eq!(out.status.code(), Some(1));
    let out = czech_to_iso(&["--unsupported", "warn"], Some(program));
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(text(&out.stdout).contains("(czech: N30 G84 X26. Z-20. F1.5)"));
    let err = text(&out.stderr);
    assert!(
        err.contains("warning[CZ011]") && err.contains("warning[ISO001]"),
        "{err}"
    );
}

//! `ncthread batch`, `check`, encodings and the pipe (issue 6's acceptance).
use std::collections::BTreeMap;
mod common;

use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use common::{ncthread, text};

/// Every file below `dir`: path → (bytes, modification time).
fn snapshot(dir: &Path) -> BTreeMap<PathBuf, (Vec<u8>, std::time::SystemTime)> {
    fn walk(dir: &Path, out: &mut BTreeMap<PathBuf, (Vec<u8>, std::time::SystemTime)>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                walk(&path, out);
            } else {
                let modified = std::fs::metadata(&path).unwrap().modified().unwrap();
                out.insert(path.clone(), (std::fs::read(&path).unwrap(), modified));
            }
        }
    }
    let mut out = BTreeMap::new();
    walk(dir, &mut out);
    out
}

/// A valid czech program that differs with `i`.
fn program(i: usize) -> String {
    format!(
        "N10 G95 M03 S500 \"PROGRAM {i}\nN20 G00 X{}. Z5.\nN30 G33 Z-{}. F1.5\nN40 G00 X40.\nN50 Z5.\nN60 M30\n",
        30 + i % 7,
        20 + i % 5
    )
}

/// The acceptance tree: 150 valid czech programs in nested folders, 3 invalid ones, one
/// windows-1250 file.
fn acceptance_tree(src: &Path) {
    for i in 0..150 {
        let dir = src.join(format!("shop{}/machine{}", i % 5, i % 3));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join(format!("p{i:03}.nc")), program(i)).unwrap();
    }
    let bad = src.join("bad");
    std::fs::create_dir_all(&bad).unwrap();
    std::fs::write(bad.join("syntax.nc"), "N10 M03 S500\nN20 G00 X30. Z\n").unwrap();
    std::fs::write(
        bad.join("no-feed.nc"),
        "N10 M03 S500\nN20 G00 X30. Z5.\nN30 G01 Z-10.\n",
    )
    .unwrap();
    std::fs::write(
        bad.join("arc.nc"),
        "N10 M03 S500\nN20 G00 X30. Z5.\nN30 G02 X40. Z-5. I5. K0.\n",
    )
    .unwrap();
    let cp1250 =
        std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("corpus/czech/windows-1250.nc"))
            .unwrap();
    std::fs::write(src.join("shop0/windows-1250.nc"), cp1250).unwrap();
}

#[test]
fn batch_converts_a_tree_keeps_going_and_reports_every_file() {
    let dir = tempfile::tempdir().unwrap();
    let (src, out) = (dir.path().join("src"), dir.path().join("out"));
    acceptance_tree(&src);
    let before = snapshot(&src);
    let report_path = dir.path().join("report.json");
    let (s, o, r) = (
        src.to_str().unwrap(),
        out.to_str().unwrap(),
        report_path.to_str().unwrap(),
    );
    let run = |extra: &[&str]| {
        let mut args = vec![
            "batch", s, o, "--from", "czech", "--to", "iso", "--report", r,
        ];
        args.extend(extra);
        ncthread(&args, None)
    };

    let first = run(&["--jobs", "2"]);
    assert_eq!(first.status.code(), Some(1), "{}", text(&first.stderr));
    let err = text(&first.stderr);
    assert!(
        err.contains("ncthread: converted 151, failed 3, skipped 0 in "),
        "{err}"
    );
    // Each failure is named with its line on stderr.
    assert!(err.contains("bad/syntax.nc:2:14: error[CZR001]"), "{err}");
    assert!(err.contains("bad/no-feed.nc:3:1: error[CZR020]"), "{err}");
    // No progress bar on a pipe.
    assert!(!err.contains('█') && !err.contains("151/154"), "{err}");

    let outputs = snapshot(&out);
    assert_eq!(outputs.len(), 151);
    assert!(outputs.contains_key(&out.join("shop2/machine2/p047.ngc")));
    assert!(outputs.keys().all(|p| p.extension().unwrap() == "ngc"));
    let converted = text(&outputs[&out.join("shop0/windows-1250.ngc")].0);
    assert!(
        converted.contains("S50 M3 (ROZTOČENÍ VŘETENE)\n"),
        "{converted}"
    );

    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&report_path).unwrap()).unwrap();
    let files = report["files"].as_array().unwrap();
    assert_eq!(files.len(), 154);
    let failed: Vec<&serde_json::Value> =
        files.iter().filter(|f| f["status"] == "failed").collect();
    assert_eq!(failed.len(), 3);
    for f in &failed {
        let d = &f["diagnostics"][0];
        assert!(d["line"].as_u64().unwrap() >= 2, "{f}");
        assert!(d["code"].as_str().unwrap().starts_with("CZ"), "{f}");
    }
    let cp = files
        .iter()
        .find(|f| f["path"].as_str().unwrap().ends_with("windows-1250.nc"))
        .unwrap();
    assert_eq!(cp["encoding"], "windows-1250");
    assert_eq!(cp["status"], "converted");
    assert!(
        cp["output"]
            .as_str()
            .unwrap()
            .ends_with("shop0/windows-1250.ngc")
    );
    let utf8 = files
        .iter()
        .find(|f| f["path"].as_str().unwrap().ends_with("p000.nc"))
        .unwrap();
    assert_eq!(utf8["encoding"], "UTF-8");
    assert_eq!(report["converted"], 151);

    // The source tree is untouched.
    assert_eq!(snapshot(&src), before);

    // Again without --force: nothing is overwritten, and the run fails.
    let again = run(&[]);
    assert_eq!(again.status.code(), Some(1));
    assert!(
        text(&again.stderr).contains("converted 0, failed 3, skipped 151"),
        "{}",
        text(&again.stderr)
    );
    // The skipped files are counted, not listed, unless --verbose (the report of the first
    // run says they are up to date).
    assert!(!text(&again.stderr).contains("skipped: "));
    let verbose = run(&["--verbose"]);
    assert!(
        text(&verbose.stderr).contains(
            "skipped: up to date: converted by an earlier run (--force converts it again)"
        ),
        "{}",
        text(&verbose.stderr)
    );
    // --quiet: what failed, and nothing else.
    let quiet = run(&["--quiet"]);
    assert_eq!(quiet.status.code(), Some(1));
    let said = text(&quiet.stderr);
    assert!(said.contains("bad/syntax.nc:2:14: error[CZR001]"), "{said}");
    assert!(
        said.lines()
            .all(|l| l.contains("/bad/") && l.contains("error[")),
        "{said}"
    );
    assert_eq!(snapshot(&out), outputs);

    // With --force it converts again (new files, same content).
    let forced = run(&["--force", "--jobs", "1"]);
    assert_eq!(forced.status.code(), Some(1));
    assert!(text(&forced.stderr).contains("converted 151, failed 3, skipped 0"));
    let rewritten = snapshot(&out);
    assert_eq!(rewritten.len(), 151);
    for (path, (bytes, modified)) in &rewritten {
        assert_eq!(bytes, &outputs[path].0);
        assert!(modified >= &outputs[path].1);
    }
    assert_eq!(snapshot(&src), before);
}

#[test]
fn batch_never_writes_into_the_source_tree_and_checks_its_arguments() {
    let dir = tempfile::tempdir().unwrap();
    let src = dir.path().join("src");
    acceptance_tree(&src);
    let inside = src.join("converted");
    let out = ncthread(
        &[
            "batch",
            src.to_str().unwrap(),
            inside.to_str().unwrap(),
            "--from",
            "czech",
            "--to",
            "iso",
        ],
        None,
    );
    assert_eq!(out.status.code(), Some(2));
    assert!(text(&out.stderr).contains("is inside the source folder"));
    assert!(!inside.exists());
    // All valid: exit 0; --glob chooses files, --ext names the outputs, --from auto per file.
    let out_dir = dir.path().join("out");
    let out = ncthread(
        &[
            "batch",
            src.to_str().unwrap(),
            out_dir.to_str().unwrap(),
            "--from",
            "auto",
            "--to",
            "nc31",
            "--glob",
            "shop1/**/*.nc",
            "--ext",
            "nc",
        ],
        None,
    );
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    // Every one with a comment the НЦ-31 drops (NCW007).
    assert!(text(&out.stderr).contains("converted 30 (30 with warnings), failed 0, skipped 0"));
    assert!(out_dir.join("shop1/machine0/p006.nc").exists());
}

#[test]
fn encodings_line_endings_and_transliteration() {
    // `ncthread convert` of the windows-1250 seed file to `to`, with `extra` options.
    let cp1250_to = |to: &str, extra: &[&str]| {
        let mut args = vec![
            "convert",
            "corpus/czech/windows-1250.nc",
            "--from",
            "czech",
            "--to",
            to,
        ];
        args.extend(extra);
        ncthread(&args, None)
    };
    // windows-1250 in, windows-1250 out, byte for byte for the comment.
    let out = cp1250_to("czech", &["--output-encoding", "windows-1250"]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(out.stdout.windows(9).any(|w| w == b"ROZTO\xC8EN\xCD"));
    // IBM852 (not in encoding_rs).
    let out = cp1250_to("czech", &["--output-encoding", "cp852", "--eol", "crlf"]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(out.stdout.windows(9).any(|w| w == b"ROZTO\xACEN\xD6"));
    assert!(out.stdout.ends_with(b"\r\n"));
    let back = ncthread(
        &[
            "convert",
            "-",
            "--from",
            "czech",
            "--to",
            "iso",
            "--encoding",
            "ibm852",
        ],
        Some(&out.stdout),
    );
    assert_eq!(back.status.code(), Some(0));
    assert!(
        text(&back.stdout).contains("(ROZTOČENÍ VŘETENE)"),
        "{}",
        text(&back.stdout)
    );
    // CRLF in keeps CRLF out.
    assert!(text(&back.stdout).contains("G7 G18 G21 G90 G95\r\n"));
    // An output encoding without the character: refused with the output line, or
    // transliterated.
    let out = cp1250_to("iso", &["--output-encoding", "ibm866"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(out.stdout.is_empty());
    let err = text(&out.stderr);
    assert!(
        err.contains("error[ENC001]: `Č` (U+010C) in output line 4 cannot be written in IBM866"),
        "{err}"
    );
    let out = cp1250_to("iso", &["--output-encoding", "ibm866", "--transliterate"]);
    assert_eq!(out.status.code(), Some(0));
    assert!(
        text(&out.stdout).contains("(ROZTOCENI VRETENE)"),
        "{}",
        text(&out.stdout)
    );
    // Bad labels are usage errors.
    let out = cp1250_to("iso", &["--encoding", "klingon"]);
    assert_eq!(out.status.code(), Some(2));
    let out = cp1250_to("iso", &["--output-encoding", "utf-16le"]);
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn check_lints_files_and_exits_1_on_errors() {
    let ok = ncthread(
        &[
            "check",
            "corpus/czech/ex1-multipass.nc",
            "corpus/nc31/g31-m36x1.5.nc",
        ],
        None,
    );
    assert_eq!(ok.status.code(), Some(0), "{}", text(&ok.stdout));
    assert!(text(&ok.stderr).contains("checked 2 file(s): 0 error(s)"));
    let bad = ncthread(
        &[
            "check",
            "corpus/czech/ex1-multipass.nc",
            "corpus/bad/nc31/decimal-point.nc",
            "--diagnostics",
            "json",
        ],
        None,
    );
    assert_eq!(bad.status.code(), Some(1));
    let lines: Vec<serde_json::Value> = text(&bad.stdout)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines.len(), 2);
    assert_eq!(lines[0]["code"], "NCR002");
    assert_eq!(lines[0]["file"], "corpus/bad/nc31/decimal-point.nc");
    assert_eq!(lines[0]["line"], 8);
    // An unreadable file is an I/O error (exit 2), and the others are still checked.
    let out = ncthread(
        &[
            "check",
            "no/such/file.nc",
            "corpus/bad/nc31/decimal-point.nc",
        ],
        None,
    );
    assert_eq!(out.status.code(), Some(2));
    assert!(text(&out.stderr).contains("cannot read no/such/file.nc"));
    assert!(text(&out.stdout).contains("error[NCR002]"));
    // stdin, with the dialect given.
    let out = ncthread(
        &["check", "-", "--dialect", "czech"],
        Some(b"N10 G00 X30. Z5.\nN20 G33 Z-20. F1.5\n"),
    );
    assert_eq!(out.status.code(), Some(1));
    assert!(
        text(&out.stdout).contains("error[LG001]"),
        "{}",
        text(&out.stdout)
    );
}

#[test]
fn convert_is_a_pipe_filter_that_survives_a_closed_pipe() {
    let program = std::fs::read("corpus/nc31/g31-m36x1.5.nc").unwrap();
    // `cat prog.nc | ncthread convert --from auto --to iso | head -1`
    let spawn = || {
        Command::new(env!("CARGO_BIN_EXE_ncthread"))
            .args(["convert", "--from", "auto", "--to", "iso"])
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap()
    };
    let mut child = spawn();
    // The reader goes away before ncthread writes anything.
    drop(child.stdout.take());
    child.stdin.take().unwrap().write_all(&program).unwrap();
    let out = child.wait_with_output().unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(!text(&out.stderr).contains("panicked"));
    // And read as a normal pipe, the first line is the program's.
    let mut child = spawn();
    child.stdin.take().unwrap().write_all(&program).unwrap();
    let mut first = String::new();
    BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut first)
        .unwrap();
    assert_eq!(first, "%\n");
    assert_eq!(child.wait().unwrap().code(), Some(0));
}

#[test]
fn completions_and_man_page_come_from_the_clap_definitions() {
    for shell in ["bash", "zsh", "fish"] {
        let out = ncthread(&["completions", shell], None);
        assert_eq!(out.status.code(), Some(0));
        assert!(text(&out.stdout).contains("batch"), "{shell}");
    }
    let man = ncthread(&["man"], None);
    assert_eq!(man.status.code(), Some(0));
    let man = text(&man.stdout);
    assert!(
        man.starts_with(".ie") || man.contains(".TH ncthread 1"),
        "{man}"
    );
    assert!(man.contains("batch"));
}

/// `batch --html DIR`: one page with a summary on top, every file's status, encoding, profile
/// and diagnostics with their source lines, and each converted program's `explain` table and
/// plot, the plots beside it; nothing loaded from elsewhere.
#[test]
fn html_report_shows_every_file() {
    let dir = tempfile::tempdir().unwrap();
    let (src, out, html) = (
        dir.path().join("src"),
        dir.path().join("out"),
        dir.path().join("report"),
    );
    std::fs::create_dir_all(src.join("shop a")).unwrap();
    let corpus = Path::new(env!("CARGO_MANIFEST_DIR")).join("corpus/nc31");
    std::fs::copy(corpus.join("g31-m36x1.5.nc"), src.join("shop a/m36.nc")).unwrap();
    std::fs::copy(corpus.join("g32-three-passes.nc"), src.join("g32.nc")).unwrap();
    std::fs::write(src.join("bad.nc"), "N0 M3\nN1 X36.00 ~\n").unwrap();
    let run = ncthread(
        &[
            "batch",
            src.to_str().unwrap(),
            out.to_str().unwrap(),
            "--from",
            "nc31",
            "--to",
            "iso",
            "--html",
            html.to_str().unwrap(),
        ],
        None,
    );
    assert_eq!(run.status.code(), Some(1), "{}", text(&run.stderr));
    let page = std::fs::read_to_string(html.join("index.html")).unwrap();
    assert!(page.starts_with("<!DOCTYPE html>"));
    assert!(
        page.contains("converted 2 (2 with warnings), failed 1, skipped 0"),
        "{page}"
    );
    assert!(page.contains("profile: built-in defaults"));
    // The failed file: its error with the source line and the caret.
    assert!(page.contains("error[NCR002]"), "{page}");
    assert!(page.contains("2 | N1 X36.00 ~"), "{page}");
    // The converted ones: the explain table of the output, and the plot beside the page.
    assert_eq!(page.matches("<h3>explain (the iso output)</h3>").count(), 2);
    assert!(
        page.contains("│    8 │"),
        "the eight passes of the G31: {page}"
    );
    assert!(
        page.contains("<img src=\"plots/shop%20a/m36.svg\""),
        "{page}"
    );
    let svg = std::fs::read_to_string(html.join("plots/shop a/m36.svg")).unwrap();
    assert!(svg.starts_with("<svg ") && svg.contains("<title>pass 8: depth"));
    assert!(html.join("plots/g32.svg").is_file());
    assert!(!html.join("plots/bad.svg").exists());
    // One page, no script, nothing from elsewhere.
    for outside in [
        "<script",
        "src=\"http",
        "href=\"http",
        "url(http",
        "@import",
    ] {
        assert!(!page.contains(outside), "{outside}");
    }
    // The report never goes into the source tree.
    let inside = ncthread(
        &[
            "batch",
            src.to_str().unwrap(),
            out.to_str().unwrap(),
            "--from",
            "nc31",
            "--to",
            "iso",
            "--force",
            "--html",
            src.join("report").to_str().unwrap(),
        ],
        None,
    );
    assert_eq!(inside.status.code(), Some(2));
    assert!(text(&inside.stderr).contains("never writes into the source tree"));
    assert!(!src.join("report").exists());
}

/// The summary counts the converted files with warnings and names the commonest codes (by
/// the number of files they appear in); the report has both.
#[test]
fn the_summary_counts_warnings_and_names_the_commonest_codes() {
    let dir = tempfile::tempdir().unwrap();
    let (src, out) = (dir.path().join("src"), dir.path().join("out"));
    std::fs::create_dir_all(&src).unwrap();
    let body = "N30 G33 Z-20. F1.5\nN40 G00 X40.\nN50 Z5.\nN60 M30\n";
    // A value the НЦ-31 rounds (NCW005) and a comment it drops (NCW007); a comment; nothing;
    // an error.
    std::fs::write(
        src.join("a.nc"),
        format!("N10 G95 M03 S500 \"A\nN20 G00 X30.005 Z5.\n{body}"),
    )
    .unwrap();
    std::fs::write(
        src.join("b.nc"),
        format!("N10 G95 M03 S500 \"B\nN20 G00 X30. Z5.\n{body}"),
    )
    .unwrap();
    std::fs::write(
        src.join("c.nc"),
        format!("N10 G95 M03 S500\nN20 G00 X30. Z5.\n{body}"),
    )
    .unwrap();
    std::fs::write(src.join("bad.nc"), "N10 M03 S500\nN20 G00 X30. Z\n").unwrap();
    let report = dir.path().join("report.json");
    let run = ncthread(
        &[
            "batch",
            src.to_str().unwrap(),
            out.to_str().unwrap(),
            "--from",
            "czech",
            "--to",
            "nc31",
            "--round",
            "--report",
            report.to_str().unwrap(),
        ],
        None,
    );
    let err = text(&run.stderr);
    assert!(
        err.contains("ncthread: converted 3 (2 with warnings), failed 1, skipped 0 in "),
        "{err}"
    );
    assert!(
        err.contains(
            "ncthread: commonest codes: NCW007 in 2 files, CZR001 in 1 file, NCW005 in 1 file\n"
        ),
        "{err}"
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    assert_eq!(json["with_warnings"], 2);
    assert_eq!(
        json["codes"],
        serde_json::json!({"NCW007": 2, "CZR001": 1, "NCW005": 1})
    );
}

/// The reports name an output only where one was written (or kept from before): none for a
/// file that failed or was left out, and under `--dry-run` only where it would be.
/// `ncthread batch SRC OUT --from czech --to iso --report REPORT` with `extra`: the run and
/// the report it wrote.
fn batch_czech_to_iso(
    src: &std::path::Path,
    out: &std::path::Path,
    report: &std::path::Path,
    extra: &[&str],
) -> (std::process::Output, serde_json::Value) {
    let mut args = vec![
        "batch",
        src.to_str().unwrap(),
        out.to_str().unwrap(),
        "--from",
        "czech",
        "--to",
        "iso",
        "--report",
        report.to_str().unwrap(),
    ];
    args.extend(extra);
    let run = ncthread(&args, None);
    let json = serde_json::from_str(&std::fs::read_to_string(report).unwrap()).unwrap();
    (run, json)
}

/// The report's row of the file whose path ends with `name`.
fn report_row(json: &serde_json::Value, name: &str) -> serde_json::Value {
    json["files"]
        .as_array()
        .unwrap()
        .iter()
        .find(|f| f["path"].as_str().unwrap().ends_with(name))
        .unwrap()
        .clone()
}

#[test]
fn the_report_names_an_output_only_where_one_was_written() {
    let dir = tempfile::tempdir().unwrap();
    let (src, out) = (dir.path().join("src"), dir.path().join("out"));
    std::fs::create_dir_all(&src).unwrap();
    std::fs::write(src.join("good.nc"), program(1)).unwrap();
    std::fs::write(src.join("bad.nc"), "N10 M03 S500\nN20 G00 X30. Z\n").unwrap();
    std::fs::write(src.join("notes.txt"), "not a program\n").unwrap();
    let report = dir.path().join("report.json");
    let html = dir.path().join("html");
    let run = |extra: &[&str]| {
        let (run, json) = batch_czech_to_iso(&src, &out, &report, extra);
        (
            text(&run.stderr),
            report_row(&json, "good.nc"),
            report_row(&json, "bad.nc"),
            report_row(&json, "notes.txt"),
        )
    };
    let (said, _, _, _) = run(&["--dry-run", "--verbose"]);
    let (_, good, bad, notes) = run(&["--dry-run"]);
    assert_eq!(good["output"], serde_json::Value::Null, "{good}");
    assert!(
        good["would_write"].as_str().unwrap().ends_with("good.ngc"),
        "{good}"
    );
    assert_eq!(bad["would_write"], serde_json::Value::Null, "{bad}");
    assert!(
        said.contains("good.nc: would convert as czech in UTF-8, profile built-in defaults → ")
    );
    assert!(
        said.lines()
            .any(|l| l.contains("bad.nc: failed as czech") && !l.contains('→')),
        "{said}"
    );
    let (_, good, bad, notes2) = run(&["--html", html.to_str().unwrap()]);
    assert!(
        good["output"].as_str().unwrap().ends_with("good.ngc"),
        "{good}"
    );
    assert_eq!(bad["output"], serde_json::Value::Null, "{bad}");
    for n in [&notes, &notes2] {
        assert_eq!(n["output"], serde_json::Value::Null, "{n}");
    }
    let page = std::fs::read_to_string(html.join("index.html")).unwrap();
    let row = page
        .lines()
        .find(|l| l.starts_with("<tr>") && l.contains("bad.nc"))
        .unwrap();
    assert!(row.ends_with("<td>—</td></tr>"), "{row}");
    assert!(!page.contains("bad.ngc"), "{page}");
}

/// Two programs whose outputs differ only in case would overwrite each other on a
/// case-insensitive file system (Windows, macOS, a USB stick): the second fails, named.
#[test]
fn outputs_that_differ_only_in_case_are_flagged() {
    let dir = tempfile::tempdir().unwrap();
    let (src, out) = (dir.path().join("src"), dir.path().join("out"));
    for rel in ["P1.nc", "p1.NC", "Lathe/x.nc", "lathe/X.nc", "P2.nc"] {
        let path = src.join(rel);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(path, program(2)).unwrap();
    }
    let report = dir.path().join("report.json");
    let run = ncthread(
        &[
            "batch",
            src.to_str().unwrap(),
            out.to_str().unwrap(),
            "--from",
            "czech",
            "--to",
            "iso",
            "--report",
            report.to_str().unwrap(),
        ],
        None,
    );
    assert_eq!(run.status.code(), Some(1), "{}", text(&run.stderr));
    let err = text(&run.stderr);
    assert!(err.contains("converted 3, failed 2"), "{err}");
    for (second, first) in [("p1.NC", "P1.nc"), ("lathe/X.nc", "Lathe/x.nc")] {
        let line = err
            .lines()
            .find(|l| l.starts_with(&format!("{}: failed: ", src.join(second).display())))
            .unwrap_or_else(|| panic!("{second}: {err}"));
        assert!(line.contains("differ only in case"), "{line}");
        assert!(
            line.contains(&src.join(first).display().to_string()),
            "{line}"
        );
    }
    assert!(out.join("P1.ngc").is_file() && !out.join("p1.ngc").exists());
}

/// A FANUC control names its programs `O1002`, without an extension: such a file is taken
/// when its text is a program; a README, a script or a binary file without one is not.
#[test]
fn programs_without_an_extension_are_taken_by_their_text() {
    let dir = tempfile::tempdir().unwrap();
    let (src, out) = (dir.path().join("src"), dir.path().join("out"));
    std::fs::create_dir_all(src.join("lathe")).unwrap();
    let fanuc = std::fs::read("corpus/fanuc/g32-m20x1.5-multipass.nc").unwrap();
    std::fs::write(src.join("lathe/O1002"), &fanuc).unwrap();
    std::fs::write(
        src.join("README"),
        "Programs of lathe 2 (the old one)\nG32 cuts a thread (see the manual)\nAsk Jan first.\n",
    )
    .unwrap();
    std::fs::write(src.join("run"), "#!/bin/sh\nncthread batch a b\n").unwrap();
    std::fs::write(src.join("DATA"), b"\0\x01\x02O1002\nG32\0").unwrap();
    let report = dir.path().join("report.json");
    for from in ["auto", "fanuc"] {
        let run = ncthread(
            &[
                "batch",
                src.to_str().unwrap(),
                out.to_str().unwrap(),
                "--from",
                from,
                "--to",
                "iso",
                "--force",
                "--report",
                report.to_str().unwrap(),
            ],
            None,
        );
        assert_eq!(run.status.code(), Some(0), "{}", text(&run.stderr));
        assert!(
            text(&run.stderr).contains("converted 1, failed 0, skipped 0, left out 3"),
            "{}",
            text(&run.stderr)
        );
        assert!(out.join("lathe/O1002.ngc").is_file());
        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
        let reason = |name: &str| {
            json["files"]
                .as_array()
                .unwrap()
                .iter()
                .find(|f| f["path"].as_str().unwrap().ends_with(name))
                .unwrap()["reason"]
                .as_str()
                .unwrap()
                .to_string()
        };
        for name in ["README", "run"] {
            assert!(
                reason(name).contains("no extension, and its text is not a program"),
                "{name}: {}",
                reason(name)
            );
        }
        assert!(reason("DATA").starts_with("binary"), "{}", reason("DATA"));
    }
    // check walks folders alike.
    let check = ncthread(&["check", src.to_str().unwrap(), "--from", "fanuc"], None);
    assert!(
        text(&check.stderr).contains("checked 1 file(s)"),
        "{}",
        text(&check.stderr)
    );
}

/// A re-run skips the outputs that exist, and keeps what the previous run found for them:
/// the HTML report's rows (read back from its `report.json`), or the JSON report's, when the
/// program, its profile, the settings and the output are as they were; an output older than
/// its program is said on every run until `--force`.
#[test]
fn a_rerun_keeps_the_rows_of_the_outputs_it_skips() {
    let dir = tempfile::tempdir().unwrap();
    let (src, out, html) = (
        dir.path().join("src"),
        dir.path().join("out"),
        dir.path().join("html"),
    );
    std::fs::create_dir_all(&src).unwrap();
    std::fs::write(src.join("a.nc"), program(1)).unwrap();
    // M42: a gear range ISO has no word for, written as a comment (ISOW002).
    std::fs::write(
        src.join("b.nc"),
        program(2).replace("M03 S500", "M03 S500 M42"),
    )
    .unwrap();
    std::fs::write(src.join("bad.nc"), "N10 M03 S500\nN20 G00 X30. Z\n").unwrap();
    let report = dir.path().join("report.json");
    let run = |extra: &[&str]| {
        let (run, json) = batch_czech_to_iso(&src, &out, &report, extra);
        assert_eq!(run.status.code(), Some(1), "{}", text(&run.stderr));
        (text(&run.stderr), json)
    };
    let row = report_row;
    let page = || std::fs::read_to_string(html.join("index.html")).unwrap();
    let h = html.to_str().unwrap();
    let (_, first) = run(&["--html", h]);
    let first_page = page();
    assert_eq!(
        first_page
            .matches("<h3>explain (the iso output)</h3>")
            .count(),
        2
    );
    assert!(first_page.contains("warning[ISOW002]"), "{first_page}");

    // Again: nothing is converted, and the report is the first one's.
    let (said, again) = run(&["--html", h]);
    assert!(
        said.contains("converted 0, failed 1, skipped 2 (exist; --force to overwrite)"),
        "{said}"
    );
    assert!(!said.contains("skipped:"), "{said}");
    let again_page = page();
    assert_eq!(
        again_page
            .matches("<h3>explain (the iso output)</h3>")
            .count(),
        2
    );
    assert!(again_page.contains("warning[ISOW002]"), "{again_page}");
    assert!(again_page.contains("up to date: converted by an earlier run"));
    for name in ["a.nc", "b.nc"] {
        let (was, is) = (row(&first, name), row(&again, name));
        assert_eq!(is["status"], "skipped");
        assert_eq!(is["up_to_date"], true);
        for key in [
            "dialect",
            "encoding",
            "output_encoding",
            "output",
            "diagnostics",
        ] {
            assert_eq!(is[key], was[key], "{name}: {key}");
        }
    }
    assert_eq!(row(&again, "b.nc")["diagnostics"][0]["code"], "ISOW002");

    // A program changed since: out of date, said on every run (without --verbose).
    std::fs::write(src.join("a.nc"), program(3)).unwrap();
    for _ in 0..2 {
        let (said, json) = run(&["--html", h]);
        assert!(
            said.contains("skipped 2 (exist, 1 of them out of date; --force to convert again)"),
            "{said}"
        );
        assert!(
            said.contains(&format!(
                "{}: skipped: the output exists, but its program has changed since it was converted",
                src.join("a.nc").display()
            )),
            "{said}"
        );
        assert_eq!(row(&json, "a.nc")["up_to_date"], false);
        assert_eq!(row(&json, "b.nc")["up_to_date"], true);
        assert_eq!(
            page().matches("<h3>explain (the iso output)</h3>").count(),
            1
        );
    }
    // An output changed by hand is kept, and said to be.
    std::fs::write(out.join("b.ngc"), "M2\n").unwrap();
    let (_, json) = run(&["--html", h, "--verbose"]);
    assert!(
        row(&json, "b.nc")["reason"]
            .as_str()
            .unwrap()
            .starts_with("the output exists and was changed after ncthread wrote it"),
        "{}",
        row(&json, "b.nc")
    );
    // --force converts them again; then the JSON report alone keeps the rows.
    let (said, _) = run(&["--force"]);
    assert!(
        said.contains("converted 2 (1 with warnings), failed 1"),
        "{said}"
    );
    let (_, json) = run(&[]);
    assert_eq!(row(&json, "b.nc")["up_to_date"], true);
    assert_eq!(row(&json, "b.nc")["diagnostics"][0]["code"], "ISOW002");
    assert_eq!(row(&json, "a.nc")["dialect"], "czech");
    // The same report given to a run into another tree says nothing of its outputs.
    let other = dir.path().join("other");
    std::fs::create_dir_all(&other).unwrap();
    std::fs::write(other.join("b.ngc"), "M2\n").unwrap();
    let run = ncthread(
        &[
            "batch",
            src.to_str().unwrap(),
            other.to_str().unwrap(),
            "--from",
            "czech",
            "--to",
            "iso",
            "--report",
            report.to_str().unwrap(),
            "--verbose",
        ],
        None,
    );
    assert!(
        text(&run.stderr).contains("b.nc: skipped: the output exists (--force overwrites it)"),
        "{}",
        text(&run.stderr)
    );
}

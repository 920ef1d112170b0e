//! A shop's archive as it is (issue 17): programs of every dialect with sidecar profiles and
//! an `ncthread.toml`, upper-case names, a README, a binary file, an empty file, a DOS file
//! ending in `^Z`, nested folders. `batch` and `check` must take the programs, leave out the
//! rest with a reason, use each program's profile, and leave the source tree as it was.
mod common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use common::{ncthread, text};

fn corpus(path: &str) -> Vec<u8> {
    std::fs::read(common::root().join("corpus").join(path)).unwrap()
}

/// Every file below `dir` with its bytes.
fn tree(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut out = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else {
                out.insert(
                    p.strip_prefix(dir).unwrap().to_path_buf(),
                    std::fs::read(&p).unwrap(),
                );
            }
        }
    }
    out
}

/// The archive: what each file is expected to become.
fn archive(src: &Path) {
    let put = |rel: &str, bytes: &[u8]| {
        let p = src.join(rel);
        std::fs::create_dir_all(p.parent().unwrap()).unwrap();
        std::fs::write(p, bytes).unwrap();
    };
    // czech: a program with its sidecar profile (constant 8 for its J runout: refused
    // without it), an upper-case name, a DOS file ending in ^Z.
    put("czech/ex4.nc", &corpus("czech/ex4-runout-constant.nc"));
    put(
        "czech/ex4.profile.toml",
        &corpus("czech/ex4-runout-constant.profile.toml"),
    );
    put("czech/P0001.NC", &corpus("czech/ex1-multipass.nc"));
    let mut dos = corpus("czech/feed-incremental-crlf.nc");
    dos.push(0x1A);
    put("czech/DOS.NC", &dos);
    // A file padded with NULs to its block size.
    let mut padded = corpus("czech/ex3-taper.nc");
    padded.extend([0u8; 100]);
    put("czech/PADDED.NC", &padded);
    // A file from a DOS PC: CP852.
    put(
        "czech/DOSPC.NC",
        &encoding_rs_cp852(
            "N10 G00 G95 S500 M03 \"ŘEZÁNÍ ZÁVITU\r\nN20 X30. Z5.\r\nN30 G33 Z-20. F1.5\r\nN40 M30\r\n",
        ),
    );
    // nc31: an ncthread.toml for the folder (parameter 7: a runout), a program below it in a
    // nested folder that finds it.
    put(
        "nc31/ncthread.toml",
        &corpus("nc31/g31-runout-p7.profile.toml"),
    );
    put("nc31/lathe 2/G31.NC", &corpus("nc31/g31-runout-p7.nc"));
    // iso, and a program with an error.
    put("iso/shaft.ngc", &corpus("iso/part-shaft-m20.ngc"));
    put("iso/bad.ngc", b"G7 G21 G95\nG33 Z-10\nM2\n");
    // What is not a program.
    put("README.md", b"# Programs of lathe 2\n");
    put("notes.txt", b"N10 is the first block\n");
    put("czech/OLD.BAK", b"MZ\x90\0\x03\0\0\0\x04\0\0\0\xff\xff");
    put("czech/EMPTY.NC", b"");
    put(
        "czech/binary.nc",
        b"\0\x01\x02\x03\x04\x05\x06\x07\x08N10\0\0\x10\x11",
    );
}

fn report(path: &Path) -> BTreeMap<String, serde_json::Value> {
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    json["files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| {
            let path = f["path"].as_str().unwrap().replace('\\', "/");
            let rel = path.split("/src/").nth(1).unwrap().to_string();
            (rel, f.clone())
        })
        .collect()
}

#[test]
fn batch_converts_an_archive_as_it_is() {
    let dir = tempfile::tempdir().unwrap();
    let (src, out) = (dir.path().join("src"), dir.path().join("out"));
    archive(&src);
    let before = tree(&src);
    let report_path = dir.path().join("report.json");
    let run = |extra: &[&str]| {
        let mut args = vec![
            "batch",
            src.to_str().unwrap(),
            out.to_str().unwrap(),
            "--from",
            "auto",
            "--to",
            "iso",
            "--report",
            report_path.to_str().unwrap(),
        ];
        args.extend(extra);
        ncthread(&args, None)
    };
    let first = run(&[]);
    assert_eq!(first.status.code(), Some(1), "{}", text(&first.stderr));
    let files = report(&report_path);
    let status = |rel: &str| files[rel]["status"].as_str().unwrap().to_string();
    let reason = |rel: &str| files[rel]["reason"].as_str().unwrap_or("").to_string();
    for rel in [
        "czech/ex4.nc",
        "czech/P0001.NC",
        "czech/DOS.NC",
        "czech/DOSPC.NC",
        "czech/PADDED.NC",
        "nc31/lathe 2/G31.NC",
        "iso/shaft.ngc",
    ] {
        assert_eq!(status(rel), "converted", "{rel}: {:#}", files[rel]);
    }
    // The encodings read and written: the DOS PC's file is CP852, with a note.
    assert_eq!(files["czech/DOSPC.NC"]["encoding"], "IBM852");
    assert_eq!(files["czech/DOSPC.NC"]["diagnostics"][0]["code"], "ENC002");
    assert_eq!(files["czech/P0001.NC"]["encoding"], "UTF-8");
    assert_eq!(files["czech/P0001.NC"]["output_encoding"], "UTF-8");
    // The profiles each program used.
    assert!(
        files["czech/ex4.nc"]["profile"]
            .as_str()
            .unwrap()
            .ends_with("czech/ex4.profile.toml")
    );
    assert!(
        files["nc31/lathe 2/G31.NC"]["profile"]
            .as_str()
            .unwrap()
            .ends_with("nc31/ncthread.toml")
    );
    assert_eq!(files["czech/P0001.NC"]["profile"], serde_json::Value::Null);
    // The G31's runout of parameter 7 reached the output: its passes end on a taper.
    let g31 = std::fs::read_to_string(out.join("nc31/lathe 2/G31.ngc")).unwrap();
    assert!(g31.contains("runout"), "{g31}");
    // The failure, with its code.
    assert_eq!(status("iso/bad.ngc"), "failed");
    assert_eq!(files["iso/bad.ngc"]["diagnostics"][0]["code"], "ISOR004");
    // What is not a program, each with its reason.
    for (rel, why) in [
        ("README.md", "not a program file (.md"),
        ("notes.txt", "not a program file (.txt"),
        ("czech/OLD.BAK", "not a program file (.bak"),
        ("czech/ex4.profile.toml", "a machine profile"),
        ("nc31/ncthread.toml", "a machine profile"),
        ("czech/EMPTY.NC", "empty"),
        ("czech/binary.nc", "binary"),
    ] {
        assert_eq!(status(rel), "left out", "{rel}");
        assert!(reason(rel).starts_with(why), "{rel}: {}", reason(rel));
    }
    // The source tree as it was; outputs with the mode a new file gets (0644 under umask 022).
    assert_eq!(tree(&src), before);
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt as _;
        let probe = dir.path().join("probe");
        std::fs::File::create(&probe).unwrap();
        let expected = std::fs::metadata(&probe).unwrap().permissions().mode() & 0o777;
        for (rel, _) in tree(&out) {
            let mode = std::fs::metadata(out.join(&rel))
                .unwrap()
                .permissions()
                .mode()
                & 0o777;
            assert_eq!(mode, expected, "{}", rel.display());
        }
    }
    assert!(
        !tree(&out)
            .keys()
            .any(|p| p.to_string_lossy().contains(".ncthread-"))
    );
    let summary = text(&first.stderr);
    assert!(
        summary.contains(
            "converted 7 (4 with warnings), failed 1, skipped 0, left out 7 (not programs)"
        ),
        "{summary}"
    );
    // A re-run: everything there is skipped, exit 0 … but the failure fails again.
    std::fs::remove_file(src.join("iso/bad.ngc")).unwrap();
    let again = run(&[]);
    assert_eq!(again.status.code(), Some(0), "{}", text(&again.stderr));
    assert!(
        text(&again.stderr)
            .contains("converted 0, failed 0, skipped 7 (exist; --force to overwrite)"),
        "{}",
        text(&again.stderr)
    );
    // --force converts again; --dry-run writes nothing and says what it would write.
    let forced = run(&["--force"]);
    assert_eq!(forced.status.code(), Some(0));
    assert!(text(&forced.stderr).contains("converted 7 (4 with warnings), failed 0"));
    let dry_out = dir.path().join("dry");
    let dry = ncthread(
        &[
            "batch",
            src.to_str().unwrap(),
            dry_out.to_str().unwrap(),
            "--from",
            "auto",
            "--to",
            "iso",
            "--dry-run",
        ],
        None,
    );
    assert_eq!(dry.status.code(), Some(0));
    assert!(!dry_out.exists());
    let said = text(&dry.stderr);
    assert!(said.contains("would convert 7"), "{said}");
    assert!(
        said.contains("czech/P0001.NC: would convert as czech in UTF-8"),
        "{said}"
    );
}

#[test]
fn a_same_dialect_run_keeps_each_file_as_it_was_written() {
    let dir = tempfile::tempdir().unwrap();
    let (src, out) = (dir.path().join("src"), dir.path().join("out"));
    std::fs::create_dir_all(&src).unwrap();
    // A windows-1250 file with CRLF and a ^Z: converted to czech, it stays all three.
    let cp1250 = corpus("czech/windows-1250.nc");
    // (the corpus file is windows-1250: only its line ends change)
    let mut dos: Vec<u8> = cp1250
        .iter()
        .flat_map(|&b| {
            if b == b'\n' {
                vec![b'\r', b'\n']
            } else {
                vec![b]
            }
        })
        .collect();
    dos.push(0x1A);
    std::fs::write(src.join("w.nc"), &dos).unwrap();
    let run = ncthread(
        &[
            "batch",
            src.to_str().unwrap(),
            out.to_str().unwrap(),
            "--from",
            "czech",
            "--to",
            "czech",
            "--ext",
            "nc",
        ],
        None,
    );
    assert_eq!(run.status.code(), Some(0), "{}", text(&run.stderr));
    let written = std::fs::read(out.join("w.nc")).unwrap();
    assert!(written.ends_with(b"\r\n\x1a"), "{written:?}");
    let (decoded, _, bad) = encoding_rs::WINDOWS_1250.decode(&written);
    assert!(!bad && decoded.contains("ROZTOČENÍ"), "{decoded}");
    // The same through convert, as an editor's filter.
    let piped = ncthread(&["convert", "--from", "czech", "--to", "czech"], Some(&dos));
    assert_eq!(piped.status.code(), Some(0));
    assert_eq!(piped.stdout, written);
}

#[test]
fn check_takes_folders_and_finds_profiles() {
    let dir = tempfile::tempdir().unwrap();
    let src = dir.path().join("src");
    archive(&src);
    let out = ncthread(&["check", src.to_str().unwrap()], None);
    let err = text(&out.stderr);
    // Seven programs checked (the bad one fails), nothing else counted; one note for the
    // programs whose dialect is not certain.
    assert!(
        err.contains("checked 8 file(s): 1 error(s) in 1 file(s)"),
        "{err}"
    );
    assert_eq!(err.matches("--from auto").count(), 1, "{err}");
    assert_eq!(out.status.code(), Some(1));
    // The sidecar profile is found: without it the czech J runout is refused.
    let one = ncthread(
        &[
            "check",
            src.join("czech/ex4.nc").to_str().unwrap(),
            "--from",
            "czech",
        ],
        None,
    );
    assert_eq!(one.status.code(), Some(0), "{}", text(&one.stdout));
    let none = ncthread(
        &[
            "check",
            src.join("czech/ex4.nc").to_str().unwrap(),
            "--from",
            "czech",
            "--no-profile",
        ],
        None,
    );
    assert_eq!(none.status.code(), Some(1));
    assert!(text(&none.stdout).contains("CZR004"));
    // --stdin-filename finds it for stdin too, and names the diagnostics.
    let bytes = std::fs::read(src.join("czech/ex4.nc")).unwrap();
    let piped = ncthread(
        &[
            "check",
            "--from",
            "czech",
            "--stdin-filename",
            src.join("czech/ex4.nc").to_str().unwrap(),
        ],
        Some(&bytes),
    );
    assert_eq!(piped.status.code(), Some(0), "{}", text(&piped.stdout));
    // --dialect is still understood; a missing file is not counted as checked (exit 2);
    // --quiet prints no summary.
    let missing = ncthread(
        &[
            "check",
            "--dialect",
            "czech",
            "--quiet",
            src.join("czech/P0001.NC").to_str().unwrap(),
            "/no/such/file.nc",
        ],
        None,
    );
    assert_eq!(missing.status.code(), Some(2));
    let err = text(&missing.stderr);
    assert!(err.contains("cannot read /no/such/file.nc"), "{err}");
    assert!(!err.contains("checked"), "{err}");
    // A glob that matches nothing: a warning, and exit 2.
    let glob = ncthread(
        &["check", src.to_str().unwrap(), "--glob", "**/*.ncx"],
        None,
    );
    assert_eq!(glob.status.code(), Some(2));
    assert!(text(&glob.stderr).contains("--glob **/*.ncx matched no file"));
    // --iglob and `!`: the czech programs in any case but DOS.NC (and the binary one).
    let chosen = ncthread(
        &[
            "check",
            src.to_str().unwrap(),
            "--iglob",
            "czech/*.nc",
            "--glob",
            "!**/DOS.NC",
            "--glob",
            "!**/binary.nc",
        ],
        None,
    );
    let err = text(&chosen.stderr);
    assert!(err.contains("checked 4 file(s)"), "{err}");
    // An .ncthreadignore leaves a folder out.
    std::fs::write(src.join(".ncthreadignore"), "iso/\n").unwrap();
    let ignored = ncthread(&["check", src.to_str().unwrap()], None);
    assert_eq!(ignored.status.code(), Some(0), "{}", text(&ignored.stdout));
    assert!(text(&ignored.stderr).contains("checked 6 file(s): 0 error(s)"));
}

#[test]
fn empty_input_is_a_warning_for_check_and_an_error_for_convert() {
    let out = ncthread(
        &["convert", "--from", "czech", "--to", "iso"],
        Some(b"\r\n\x1a"),
    );
    assert_eq!(out.status.code(), Some(1));
    assert!(out.stdout.is_empty());
    assert!(text(&out.stderr).contains("error[INP001]"));
    let out = ncthread(&["check", "--from", "czech"], Some(b""));
    assert_eq!(out.status.code(), Some(0));
    assert!(text(&out.stdout).contains("warning[INP001]"));
}

#[test]
fn a_report_or_an_output_folder_that_cannot_be_written_stops_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let src = dir.path().join("src");
    archive(&src);
    let out = dir.path().join("out");
    let report = dir.path().join("no/such/folder/report.json");
    let run = ncthread(
        &[
            "batch",
            src.to_str().unwrap(),
            out.to_str().unwrap(),
            "--from",
            "auto",
            "--to",
            "iso",
            "--report",
            report.to_str().unwrap(),
        ],
        None,
    );
    assert_eq!(run.status.code(), Some(2));
    assert!(text(&run.stderr).contains(&format!("cannot write {}", report.display())));
    assert!(
        !out.exists(),
        "nothing was written before the report was found unwritable"
    );
    // An output path that is a file, not a folder: exit 2 naming it.
    let file = dir.path().join("a-file");
    std::fs::write(&file, b"x").unwrap();
    let run = ncthread(
        &[
            "batch",
            src.to_str().unwrap(),
            file.to_str().unwrap(),
            "--from",
            "auto",
            "--to",
            "iso",
        ],
        None,
    );
    assert_eq!(run.status.code(), Some(2));
    assert!(
        text(&run.stderr).contains(file.to_str().unwrap()),
        "{}",
        text(&run.stderr)
    );
}

/// Ctrl-C: the workers stop between files, no temporary file is left, the summary and the
/// report say what was done, exit 130. The batch runs on a pseudo-terminal (util-linux's
/// `script`), and Ctrl-C is typed into it: the terminal's line discipline interrupts the
/// batch as it would a user's (where `script` is missing, SIGINT is sent instead).
#[cfg(unix)]
#[test]
fn an_interrupt_leaves_no_temporary_file_and_a_report() {
    use std::io::{Read as _, Write as _};
    let dir = tempfile::tempdir().unwrap();
    let (src, out) = (dir.path().join("src"), dir.path().join("out"));
    std::fs::create_dir_all(&src).unwrap();
    let program = corpus("nc31/g31-m36x1.5.nc");
    for i in 0..3000 {
        std::fs::write(src.join(format!("p{i:04}.nc")), &program).unwrap();
    }
    let report = dir.path().join("report.json");
    let args = [
        env!("CARGO_BIN_EXE_ncthread"),
        "batch",
        src.to_str().unwrap(),
        out.to_str().unwrap(),
        "--from",
        "nc31",
        "--to",
        "iso",
        "-j",
        "1",
        "--report",
        report.to_str().unwrap(),
    ];
    let pty = std::process::Command::new("script")
        .arg("--version")
        .output()
        .is_ok();
    let mut child = if pty {
        let line = args
            .iter()
            .map(|a| format!("'{a}'"))
            .collect::<Vec<_>>()
            .join(" ");
        std::process::Command::new("script")
            .args(["-qfec", &line, "/dev/null"])
            .stdin(std::process::Stdio::piped())
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap()
    } else {
        std::process::Command::new(args[0])
            .args(&args[1..])
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap()
    };
    // Once the work has begun (the first outputs are there), the interrupt.
    let started = std::time::Instant::now();
    while tree_len(&out) < 5 && started.elapsed().as_secs() < 30 {
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    if pty {
        let mut stdin = child.stdin.take().unwrap();
        stdin.write_all(b"\x03").unwrap();
        stdin.flush().unwrap();
        // (kept open until the batch ends: script would end the session on EOF)
        std::mem::forget(stdin);
    } else {
        let kill = std::process::Command::new("kill")
            .args(["-INT", &child.id().to_string()])
            .status()
            .unwrap();
        assert!(kill.success());
    }
    let status = child.wait().unwrap();
    let mut said = String::new();
    if let Some(mut o) = child.stdout.take() {
        o.read_to_string(&mut said).unwrap();
    }
    child
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut said)
        .unwrap();
    if tree_len(&out) == 3000 {
        // It finished before the interrupt arrived: nothing to judge.
        eprintln!("the batch ended before the interrupt");
        return;
    }
    assert_eq!(status.code(), Some(130), "{said}");
    assert!(said.contains("interrupted:"), "{said}");
    assert!(
        !tree(&out)
            .keys()
            .any(|p| p.to_string_lossy().contains(".ncthread-"))
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    assert_eq!(json["interrupted"], true);
    let done = json["converted"].as_u64().unwrap();
    assert_eq!(
        done as usize,
        tree_len(&out),
        "the report counts what was written"
    );
    assert!(json["not_done"].as_u64().unwrap() > 0);
}

fn tree_len(dir: &Path) -> usize {
    std::fs::read_dir(dir).map_or(0, |d| d.count())
}

/// Messages that lead somewhere: a code one digit off is named; a thread block's refusal
/// does not advise keeping it; a wrong --from is pointed out; dialect names in any case;
/// --renumber checked.
#[test]
fn messages_lead_somewhere() {
    let iso = b"G7 G21 G95\nS300 M3\nG0 X30 Z5\nG32 Z-20 F1.5\nM2\n";
    let out = ncthread(&["convert", "--from", "iso", "--to", "iso"], Some(iso));
    assert!(
        text(&out.stderr).contains("`G32`: this G code — not read by ncthread (did you mean G33?)"),
        "{}",
        text(&out.stderr)
    );
    let czech = b"N10 G95 M03 S500\nN20 G00 X30. Z5.\nN30 G32 Z-20. F1.5\nN40 M30\n";
    let out = ncthread(&["convert", "--from", "czech", "--to", "iso"], Some(czech));
    assert!(
        text(&out.stderr).contains("G32 (did you mean G33?)"),
        "{}",
        text(&out.stderr)
    );
    // A thread block with an unsupported word: refused in every mode, no advice to keep it.
    let thread = b"N10 G95 M03 S500\nN20 G00 X30. Z5.\nN30 G33 Z-20. F1.5 Y3.\nN40 M30\n";
    for mode in ["error", "warn"] {
        let out = ncthread(
            &[
                "convert",
                "--from",
                "czech",
                "--to",
                "czech",
                "--unsupported",
                mode,
            ],
            Some(thread),
        );
        assert_eq!(out.status.code(), Some(1));
        let err = text(&out.stderr);
        assert!(err.contains("this block cuts a thread"), "{err}");
        assert!(!err.contains("`--unsupported warn` keeps"), "{err}");
    }
    // An НЦ-31 program read as czech.
    let out = ncthread(
        &[
            "convert",
            "corpus/nc31/g31-m36x1.5.nc",
            "--from",
            "czech",
            "--to",
            "iso",
        ],
        None,
    );
    assert_eq!(out.status.code(), Some(1));
    assert!(
        text(&out.stderr).contains("warning[INP002]"),
        "{}",
        text(&out.stderr)
    );
    assert!(text(&out.stderr).contains("give --from nc31"));
    // Dialect names in any case.
    let out = ncthread(
        &[
            "convert",
            "corpus/czech/ex3-taper.nc",
            "--from",
            "Czech",
            "--to",
            "ISO",
        ],
        None,
    );
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    // --renumber with a step of 0 would number every block alike.
    let out = ncthread(
        &[
            "convert",
            "corpus/iso/g76-external.ngc",
            "--from",
            "iso",
            "--to",
            "czech",
            "--renumber",
            "10,0",
        ],
        None,
    );
    assert_eq!(out.status.code(), Some(2));
    assert!(text(&out.stderr).contains("STEP must be at least 1"));
}

/// A czech file written on a DOS PC (CP852) is read as such, with a note; one that reads
/// cleanly in neither encoding is refused, never garbled.
#[test]
fn a_cp852_file_is_told_from_windows_1250() {
    let cp852 = encoding_rs_cp852(
        "N10 G00 G95 S500 M03 \"ROZTOČENÍ VŘETENE, ŘEZÁNÍ ZÁVITU\r\nN20 X30. Z5.\r\nN30 G33 Z-20. F1.5\r\nN40 M30\r\n",
    );
    let out = ncthread(
        &["convert", "--from", "czech", "--to", "czech"],
        Some(&cp852),
    );
    assert_eq!(out.status.code(), Some(0));
    assert!(
        text(&out.stderr).contains("warning[ENC002]"),
        "{}",
        text(&out.stderr)
    );
    // Kept in CP852 (Č is 0xAC there).
    assert!(
        out.stdout.windows(2).any(|w| w == b"O\xAC"),
        "{:?}",
        out.stdout
    );
    let out = ncthread(&["convert", "--from", "czech", "--to", "iso"], Some(&cp852));
    assert!(
        text(&out.stdout).contains("ROZTOČENÍ VŘETENE"),
        "{}",
        text(&out.stdout)
    );
    let garbled = b"N10 G00 G95 S500 M03 \"\x80\x81\x83\x88\x90\r\nN20 M30\r\n";
    let out = ncthread(
        &["convert", "--from", "czech", "--to", "iso"],
        Some(garbled),
    );
    assert_eq!(out.status.code(), Some(1));
    assert!(text(&out.stderr).contains("error[ENC003]"));
    // The windows-1250 corpus file stays windows-1250, without a note.
    let out = ncthread(
        &[
            "convert",
            "corpus/czech/windows-1250.nc",
            "--from",
            "czech",
            "--to",
            "iso",
        ],
        None,
    );
    assert!(
        !text(&out.stderr).contains("ENC00"),
        "{}",
        text(&out.stderr)
    );
}

/// CP852 bytes of `text` (the few Czech letters the tests use).
fn encoding_rs_cp852(text: &str) -> Vec<u8> {
    text.chars()
        .map(|c| match c {
            'Č' => 0xAC,
            'Í' => 0xD6,
            'Ř' => 0xFC,
            'Á' => 0xB5,
            c if c.is_ascii() => c as u8,
            c => panic!("no CP852 byte for {c}"),
        })
        .collect()
}

#[test]
fn man_pages_for_every_subcommand() {
    let out = ncthread(&["man", "convert"], None);
    assert_eq!(out.status.code(), Some(0));
    let page = text(&out.stdout);
    assert!(page.contains(".TH ncthread-convert 1"), "{page}");
    for section in [
        "EXIT STATUS",
        "FILES",
        "DIAGNOSTICS",
        "ISOR021",
        "ncthread.toml",
    ] {
        assert!(page.contains(section), "{section}");
    }
    let dir = tempfile::tempdir().unwrap();
    let out = ncthread(&["man", "--dir", dir.path().to_str().unwrap()], None);
    assert_eq!(out.status.code(), Some(0));
    for name in [
        "ncthread",
        "ncthread-convert",
        "ncthread-batch",
        "ncthread-check",
        "ncthread-explain",
        "ncthread-plot",
        "ncthread-verify",
    ] {
        assert!(dir.path().join(format!("{name}.1")).is_file(), "{name}");
    }
    let help = text(&ncthread(&["check", "--help"], None).stdout);
    assert!(help.contains("on stdout"), "{help}");
}

/// `verify --round` proves a conversion within the deviation its rounding reported;
/// `--tolerance` allows what it is told.
#[test]
fn verify_allows_the_reported_rounding() {
    let out = ncthread(
        &[
            "verify",
            "corpus/czech/ex1-multipass.nc",
            "--from",
            "czech",
            "--to",
            "nc31",
            "--round",
        ],
        None,
    );
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stdout));
    assert!(text(&out.stdout).contains("largest deviation 0.003 mm; tolerance 0.003 mm"));
    let hand =
        std::fs::read_to_string(common::root().join("corpus/iso/m36x1.5-by-hand.ngc")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let off = dir.path().join("off.ngc");
    std::fs::write(&off, hand.replace("G0 X34.255\n", "G0 X34.259\n")).unwrap();
    let verify = |tolerance: &str| {
        ncthread(
            &[
                "verify",
                "corpus/nc31/g31-m36x1.5.nc",
                "--from",
                "nc31",
                "--to",
                "iso",
                "--against",
                off.to_str().unwrap(),
                "--tolerance",
                tolerance,
            ],
            None,
        )
    };
    assert_eq!(verify("0.001").status.code(), Some(1));
    assert_eq!(verify("0.005").status.code(), Some(0));
}

/// `convert -o` writes whole or not at all, with the mode a new file gets; a folder that is
/// not there is exit 2, naming the path given.
#[test]
fn convert_writes_its_output_atomically() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("p.ngc");
    let run = ncthread(
        &[
            "convert",
            "corpus/czech/ex3-taper.nc",
            "--from",
            "czech",
            "--to",
            "iso",
            "-o",
            out.to_str().unwrap(),
        ],
        None,
    );
    assert_eq!(run.status.code(), Some(0));
    assert!(std::fs::read_to_string(&out).unwrap().contains("G33"));
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        1,
        "no temporary file is left"
    );
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt as _;
        let probe = dir.path().join("probe");
        std::fs::File::create(&probe).unwrap();
        let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode(&out), mode(&probe));
    }
    for bad in [
        dir.path().join("no/such/p.ngc"),
        dir.path().join("p.ngc/x.ngc"),
    ] {
        let run = ncthread(
            &[
                "convert",
                "corpus/czech/ex3-taper.nc",
                "--from",
                "czech",
                "--to",
                "iso",
                "-o",
                bad.to_str().unwrap(),
            ],
            None,
        );
        assert_eq!(run.status.code(), Some(2));
        let err = text(&run.stderr);
        assert!(
            err.contains(&format!("cannot write {}", bad.display())),
            "{err}"
        );
        assert!(!dir.path().join("no").exists(), "no folder is made");
    }
}

/// Found in review: the profile of `p.nc31` and of `../A/p.nc31` is the same one; the report,
/// an extension with a folder or an output folder holding the source are refused before any
/// work; a `.ngc` file without dialect marks is read as iso (said); links are listed; a file
/// named twice is checked once; a `!` glob wins over an
/// `--iglob`; `--dry-run` writes no plot.
#[test]
fn review_findings_stay_fixed() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path();
    let (a, b) = (root.join("Y/A"), root.join("Y/B"));
    std::fs::create_dir_all(&a).unwrap();
    std::fs::create_dir_all(&b).unwrap();
    std::fs::write(a.join("p.nc31"), corpus("nc31/g31-m36x1.5.nc")).unwrap();
    std::fs::write(a.join("ncthread.toml"), "[nc31]\nlinear_unit_mm = 0.001\n").unwrap();
    std::fs::write(b.join("ncthread.toml"), "[nc31]\nlinear_unit_mm = 0.1\n").unwrap();
    let run_in = |cwd: &Path, args: &[&str]| {
        std::process::Command::new(env!("CARGO_BIN_EXE_ncthread"))
            .current_dir(cwd)
            .args(args)
            .output()
            .unwrap()
    };
    for (cwd, file) in [(&a, "p.nc31"), (&b, "../A/p.nc31")] {
        let out = run_in(cwd, &["convert", file, "--from", "nc31", "--to", "iso"]);
        assert!(
            text(&out.stdout).contains("G0 X10 Z5"),
            "{file}: {}",
            text(&out.stdout)
        );
    }
    let src = a.to_str().unwrap();
    let refused = |args: &[&str], says: &str| {
        let out = ncthread(args, None);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(text(&out.stderr).contains(says), "{}", text(&out.stderr));
    };
    let report = a.join("p.nc31");
    refused(
        &[
            "batch",
            src,
            root.join("o").to_str().unwrap(),
            "--from",
            "nc31",
            "--to",
            "iso",
            "--report",
            report.to_str().unwrap(),
        ],
        "is inside the source folder",
    );
    assert_eq!(
        std::fs::read(&report).unwrap(),
        corpus("nc31/g31-m36x1.5.nc")
    );
    refused(
        &[
            "batch",
            src,
            root.join("o").to_str().unwrap(),
            "--from",
            "nc31",
            "--to",
            "iso",
            "--ext",
            "a/b",
        ],
        "an extension is a name without a folder",
    );
    refused(
        &[
            "batch",
            src,
            root.join("Y").to_str().unwrap(),
            "--from",
            "nc31",
            "--to",
            "iso",
        ],
        "holds the source folder",
    );
    assert!(!root.join("o").exists());
    // A .ngc file without any dialect's marks.
    let g = root.join("G");
    std::fs::create_dir_all(&g).unwrap();
    std::fs::write(
        g.join("plain.ngc"),
        "G95\nS500 M3\nG0 X20 Z5\nG1 Z-10 F0.2\nM30\n",
    )
    .unwrap();
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink(&a, g.join("lathe-a")).unwrap();
        std::os::unix::fs::symlink(root.join("nowhere.nc"), g.join("dangling.nc")).unwrap();
    }
    let go = root.join("GO");
    let report = root.join("g.json");
    let out = ncthread(
        &[
            "batch",
            g.to_str().unwrap(),
            go.to_str().unwrap(),
            "--from",
            "auto",
            "--to",
            "iso",
            "--report",
            report.to_str().unwrap(),
            "--dry-run",
            "--html",
            root.join("h").to_str().unwrap(),
        ],
        None,
    );
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(text(&out.stderr).contains(
        "read as iso (the text has no dialect's marks, and only iso's files are called .ngc)"
    ));
    assert!(
        !go.exists() && !root.join("h").exists(),
        "--dry-run writes nothing"
    );
    #[cfg(unix)]
    {
        let json = std::fs::read_to_string(&report).unwrap();
        assert!(json.contains("a link to a folder (not followed)"), "{json}");
        assert!(json.contains("a link to nothing"), "{json}");
    }
    // Checked once though named twice.
    let twice = ncthread(
        &[
            "check",
            g.to_str().unwrap(),
            g.join("plain.ngc").to_str().unwrap(),
        ],
        None,
    );
    assert!(
        text(&twice.stderr).contains("checked 1 file(s)"),
        "{}",
        text(&twice.stderr)
    );
    // `check --glob` without a path walks the current folder (it read stdin).
    let here = run_in(&g, &["check", "--glob", "*.ngc"]);
    assert!(
        text(&here.stderr).contains("checked 1 file(s)"),
        "{}",
        text(&here.stderr)
    );
    // A `!` glob wins over an --iglob given after it.
    std::fs::write(g.join("README.NGC"), "G95\nM30\n").unwrap();
    let chosen = ncthread(
        &[
            "check",
            g.to_str().unwrap(),
            "--glob",
            "!README.NGC",
            "--iglob",
            "*.ngc",
        ],
        None,
    );
    assert!(
        text(&chosen.stderr).contains("checked 1 file(s)"),
        "{}",
        text(&chosen.stderr)
    );
}

//! Helpers shared by the integration tests: corpus cases, conversions, and LinuxCNC's rs274
//! as the oracle for ISO output.
#![allow(dead_code)]

pub mod fanuc;
pub mod heidenhain;
pub mod siemens;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

use ncthread::profile::Profile;
use ncthread::source::SourceFile;
use ncthread::{Conversion, ConvertOptions, DialectId, Unsupported};

/// Every target dialect ncthread writes; each corpus file is snapshotted for each.
pub const TARGETS: &[DialectId] = &[
    ncthread::dialect::iso::ID,
    ncthread::dialect::czech::ID,
    ncthread::dialect::nc31::ID,
    ncthread::dialect::fanuc::ID,
    ncthread::dialect::siemens::ID,
    ncthread::dialect::heidenhain::ID,
];

pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// One corpus file, with or without the profile beside it (`NAME.profile.toml`).
#[derive(Clone, Debug)]
pub struct Case {
    /// `czech/ex4-runout-constant`, `czech/ex4-runout-constant+profile`, `bad/nc31/…`.
    pub name: String,
    /// Relative to the repository root, with `/`.
    pub path: String,
    pub profile: Option<String>,
    pub from: DialectId,
}

/// Every corpus file × {no profile, its profile}, sorted by name.
pub fn corpus_cases() -> Vec<Case> {
    let mut cases = Vec::new();
    for (folder, from) in [
        ("czech", ncthread::dialect::czech::ID),
        ("nc31", ncthread::dialect::nc31::ID),
        ("iso", ncthread::dialect::iso::ID),
        ("bad/czech", ncthread::dialect::czech::ID),
        ("bad/nc31", ncthread::dialect::nc31::ID),
        ("bad/iso", ncthread::dialect::iso::ID),
        ("fanuc", ncthread::dialect::fanuc::ID),
        ("bad/fanuc", ncthread::dialect::fanuc::ID),
        ("fidelity", ncthread::dialect::czech::ID),
        ("fidelity", ncthread::dialect::iso::ID),
        ("fuzz/czech", ncthread::dialect::czech::ID),
        ("fuzz/nc31", ncthread::dialect::nc31::ID),
        ("fuzz/iso", ncthread::dialect::iso::ID),
        ("fuzz/fanuc", ncthread::dialect::fanuc::ID),
        ("fuzz/heidenhain", ncthread::dialect::heidenhain::ID),
        ("siemens", ncthread::dialect::siemens::ID),
        ("bad/siemens", ncthread::dialect::siemens::ID),
        ("heidenhain", ncthread::dialect::heidenhain::ID),
        ("bad/heidenhain", ncthread::dialect::heidenhain::ID),
    ] {
        let ext = extension(from);
        let dir = root().join("corpus").join(folder);
        let mut files: Vec<_> = std::fs::read_dir(&dir)
            .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
            .map(|e| e.expect("dir entry").path())
            .filter(|p| p.extension().is_some_and(|e| e == ext))
            .collect();
        files.sort();
        for file in files {
            let stem = file.file_stem().unwrap().to_string_lossy().to_string();
            let path = format!("corpus/{folder}/{stem}.{ext}");
            cases.push(Case {
                name: format!("{folder}/{stem}"),
                path: path.clone(),
                profile: None,
                from,
            });
            let profile = format!("corpus/{folder}/{stem}.profile.toml");
            if root().join(&profile).exists() {
                cases.push(Case {
                    name: format!("{folder}/{stem}+profile"),
                    path,
                    profile: Some(profile),
                    from,
                });
            }
        }
    }
    cases
}

/// The corpus files' extension for a dialect.
pub fn extension(d: DialectId) -> &'static str {
    match d {
        ncthread::dialect::iso::ID => "ngc",
        ncthread::dialect::siemens::ID => "mpf",
        _ => "nc",
    }
}

pub fn load_profile(path: &str) -> Profile {
    let text = std::fs::read_to_string(root().join(path)).unwrap();
    Profile::from_toml(&SourceFile::new(path, text)).unwrap_or_else(|d| panic!("{path}: {d:?}"))
}

pub fn convert_case(case: &Case, to: DialectId) -> Conversion {
    let src = case_source(case);
    let options = ConvertOptions {
        from: case.from,
        to,
        profile: case
            .profile
            .as_deref()
            .map(load_profile)
            .unwrap_or_default(),
        unsupported: Unsupported::Error,
        renumber: Default::default(),
        round: false,
        nc31_comments: false,
    };
    ncthread::convert(&src, &options)
}

/// A corpus file's text, decoded as `convert` decodes it.
pub fn case_source(case: &Case) -> SourceFile {
    let bytes = std::fs::read(root().join(&case.path)).unwrap();
    let (text, _) = ncthread::text::decode(&bytes, case.from);
    SourceFile::new(case.path.clone(), text)
}

/// The case read with its profile (diagnostics dropped: for cases the reader accepts).
pub fn parse_case(case: &Case) -> ncthread::ir::Program {
    let profile = case
        .profile
        .as_deref()
        .map(load_profile)
        .unwrap_or_default();
    ncthread::parse(&case_source(case), case.from, &profile, Unsupported::Error).0
}

/// Whether the reader alone refuses the case (so that every target refuses it alike).
pub fn reader_refuses(case: &Case) -> bool {
    let profile = case
        .profile
        .as_deref()
        .map(load_profile)
        .unwrap_or_default();
    let (_, diags) = ncthread::parse(&case_source(case), case.from, &profile, Unsupported::Error);
    ncthread::diag::has_errors(&diags)
}

/// A conversion as one text: diagnostics, then the program (or that it was refused).
pub fn render_body(conversion: &Conversion) -> String {
    let diags = ncthread::diag::render_all(
        &conversion.diagnostics,
        ncthread::diag::Format::Human,
        false,
    );
    format!(
        "--- diagnostics\n{}--- output\n{}",
        diags,
        conversion
            .output
            .as_deref()
            .unwrap_or("(refused: nothing written)\n"),
    )
}

pub use ncthread::sim::rs274::Canon;

/// The command that runs rs274. `$NCTHREAD_RS274` names a command run as `CMD FILE.ngc`;
/// otherwise `scripts/rs274` provides the interpreter (it fetches the Debian package on first
/// use). Without an interpreter the oracle tests fail, unless `NCTHREAD_SKIP_RS274=1` says to
/// skip them: then this is `None`, and the test output says so loudly.
pub fn rs274() -> Option<&'static Path> {
    static FOUND: OnceLock<Option<PathBuf>> = OnceLock::new();
    FOUND
        .get_or_init(|| {
            if std::env::var_os("NCTHREAD_SKIP_RS274").is_some_and(|v| v == "1") {
                // Straight to stderr: the test harness captures eprintln!, and a skip must show.
                let _ = std::io::Write::write_all(
                    &mut std::io::stderr(),
                    b"\n!!!!! SKIPPING the rs274 oracle checks (NCTHREAD_SKIP_RS274=1) !!!!!\n\n",
                );
                return None;
            }
            if let Some(cmd) = std::env::var_os("NCTHREAD_RS274") {
                return Some(PathBuf::from(cmd));
            }
            let script = root().join("scripts/rs274");
            let out = Command::new(&script).arg("--install").output();
            match out {
                Ok(o) if o.status.success() => Some(script),
                Ok(o) => panic!(
                    "no LinuxCNC interpreter for the oracle tests: `scripts/rs274 --install` failed:\n{}\n\
                     install it, set NCTHREAD_RS274=CMD, or set NCTHREAD_SKIP_RS274=1 to skip these checks",
                    String::from_utf8_lossy(&o.stderr)
                ),
                Err(e) => panic!(
                    "no LinuxCNC interpreter for the oracle tests: {}: {e}; set NCTHREAD_SKIP_RS274=1 to skip these checks",
                    script.display()
                ),
            }
        })
        .as_deref()
}

/// Runs rs274 on `ngc`; Err with rs274's complaint when it refuses the program.
pub fn run_rs274(cmd: &Path, ngc: &str) -> Result<Vec<Canon>, ncthread::sim::rs274::RunError> {
    ncthread::sim::rs274::Interpreter::Wrapper(cmd.to_path_buf()).run(ngc)
}

/// A synchronised move as rs274 runs it: start, end and the lead along Z derived from K.
#[derive(Clone, Debug)]
pub struct SyncMove {
    pub from: (f64, f64),
    pub to: (f64, f64),
    pub k: f64,
    pub z_lead: f64,
}

/// The synchronised feed moves of a canonical call list (positions start at X0 Z0).
pub fn sync_moves(canon: &[Canon]) -> Vec<SyncMove> {
    let (mut pos, mut k) = ((0.0, 0.0), None);
    let mut moves = Vec::new();
    for c in canon {
        match *c {
            Canon::Traverse { x, z } => pos = (x, z),
            // A rigid tap returns to where it started.
            Canon::RigidTap { .. } => {}
            Canon::Feed { x, z } => {
                if let Some(k) = k {
                    let (dx, dz): (f64, f64) = ((x - pos.0) / 2.0, z - pos.1);
                    let z_lead = k * dz.abs() / dx.hypot(dz);
                    moves.push(SyncMove {
                        from: pos,
                        to: (x, z),
                        k,
                        z_lead,
                    });
                }
                pos = (x, z);
            }
            Canon::SyncStart { k: new } => k = Some(new),
            Canon::SyncStop => k = None,
            _ => {}
        }
    }
    moves
}

pub fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

/// The simulation of a corpus case's source program (parsed with its profile).
pub fn simulate_case(case: &Case) -> ncthread::sim::Simulation {
    let bytes = std::fs::read(root().join(&case.path)).unwrap();
    let (text, _) = ncthread::text::decode(&bytes, case.from);
    let src = SourceFile::new(case.path.clone(), text);
    let profile = case
        .profile
        .as_deref()
        .map(load_profile)
        .unwrap_or_default();
    let (program, diags) = ncthread::parse(&src, case.from, &profile, Unsupported::Error);
    assert!(
        !ncthread::diag::has_errors(&diags),
        "{}: {diags:?}",
        case.name
    );
    ncthread::sim::simulate(&program)
}

/// LinuxCNC's motion as ncthread's simulator describes motion (the library's reading).
pub fn rs274_segments(canon: &[Canon]) -> Vec<ncthread::sim::Segment> {
    ncthread::sim::rs274::segments(canon)
}

/// Our own simulation of an ISO program text (the iso front end, default profile).
pub fn simulate_iso(name: &str, text: &str) -> ncthread::sim::Simulation {
    let src = SourceFile::new(name, text);
    let (program, diags) = ncthread::parse(
        &src,
        ncthread::dialect::iso::ID,
        &Profile::default(),
        Unsupported::Error,
    );
    assert!(!ncthread::diag::has_errors(&diags), "{name}: {diags:?}");
    ncthread::sim::simulate(&program)
}

/// Runs the `ncthread` binary in the crate folder with `args` and `stdin`.
pub fn ncthread(args: &[&str], stdin: Option<&[u8]>) -> std::process::Output {
    use std::io::Write;
    use std::process::Stdio;
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

/// A czech program of at least `bytes` bytes (a rapid, a cut and a retract over and over):
/// past the 1 MiB where a conversion spools its output and runs its writer in a thread.
pub fn large_czech_program(bytes: usize) -> String {
    let mut program = String::from("N10 G95 M03 S800 T1 D1\n");
    let mut n = 20;
    while program.len() < bytes {
        for line in ["G00 X34. Z2.", "G01 Z-40. F0.25", "G00 X40."] {
            program.push_str(&format!("N{n} {line}\n"));
            n += 10;
        }
    }
    program.push_str(&format!("N{n} M30\n"));
    program
}

pub fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// Runs `f` on a thread of its own and waits at most `seconds`: its result, or why there is
/// none (a panic and its message, or a hang). The fuzz and hostile-input tests run every
/// input this way.
pub fn watchdog<T: Send + 'static>(
    seconds: u64,
    f: impl FnOnce() -> T + Send + 'static,
) -> Result<T, String> {
    use std::sync::mpsc;
    let (tx, rx) = mpsc::channel();
    let handle = std::thread::spawn(move || {
        let _ = tx.send(f());
    });
    match rx.recv_timeout(std::time::Duration::from_secs(seconds)) {
        Ok(result) => {
            let _ = handle.join();
            Ok(result)
        }
        Err(mpsc::RecvTimeoutError::Timeout) => Err(format!("hang: no result within {seconds} s")),
        Err(mpsc::RecvTimeoutError::Disconnected) => {
            let message = handle
                .join()
                .err()
                .and_then(|p| {
                    p.downcast_ref::<String>()
                        .cloned()
                        .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                })
                .unwrap_or_default();
            Err(format!("panic: {message}"))
        }
    }
}

/// A `verify` with an interpreter at hand: rs274 judged (at least one ISO side) and agreed
/// with ncthread's reading of every side it judged.
pub fn assert_rs274_agrees(v: &ncthread::Verification, with_rs274: bool, here: &str) {
    if with_rs274 {
        assert!(!v.oracle.is_empty(), "{here}: rs274 did not judge");
    }
    for check in &v.oracle {
        assert!(
            matches!(check.outcome, ncthread::OracleOutcome::Equivalent { .. }),
            "{here}: {}: {:?}",
            check.what,
            check.outcome
        );
    }
}

/// Renders an SVG with resvg (the tests' renderer; ncthread itself writes SVG text only, and
/// the tests look at its pixels, not its text, which resvg without fonts does not draw).
pub fn render_svg(svg: &str) -> resvg::tiny_skia::Pixmap {
    let tree = resvg::usvg::Tree::from_str(svg, &resvg::usvg::Options::default())
        .unwrap_or_else(|e| panic!("not a valid SVG: {e}\n{svg}"));
    let size = tree.size().to_int_size();
    let mut pixmap = resvg::tiny_skia::Pixmap::new(size.width(), size.height()).unwrap();
    resvg::render(&tree, Default::default(), &mut pixmap.as_mut());
    pixmap
}

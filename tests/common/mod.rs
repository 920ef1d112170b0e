//! Helpers shared by the integration tests: corpus cases, conversions, and LinuxCNC's rs274
//! as the oracle for ISO output.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

use ncthread::profile::Profile;
use ncthread::source::SourceFile;
use ncthread::{Conversion, ConvertOptions, Dialect, Unsupported};

/// Every target dialect ncthread writes; each corpus file is snapshotted for each.
pub const TARGETS: &[Dialect] = &[Dialect::Iso, Dialect::Czech, Dialect::Nc31];

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
    pub from: Dialect,
}

/// Every corpus file × {no profile, its profile}, sorted by name.
pub fn corpus_cases() -> Vec<Case> {
    let mut cases = Vec::new();
    for (folder, from) in [
        ("czech", Dialect::Czech),
        ("nc31", Dialect::Nc31),
        ("iso", Dialect::Iso),
        ("bad/czech", Dialect::Czech),
        ("bad/nc31", Dialect::Nc31),
        ("bad/iso", Dialect::Iso),
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
pub fn extension(d: Dialect) -> &'static str {
    match d {
        Dialect::Iso => "ngc",
        _ => "nc",
    }
}

pub fn load_profile(path: &str) -> Profile {
    let text = std::fs::read_to_string(root().join(path)).unwrap();
    Profile::from_toml(&SourceFile::new(path, text)).unwrap_or_else(|d| panic!("{path}: {d:?}"))
}

pub fn convert_case(case: &Case, to: Dialect) -> Conversion {
    let bytes = std::fs::read(root().join(&case.path)).unwrap();
    let (text, _) = ncthread::text::decode(&bytes, case.from);
    let src = SourceFile::new(case.path.clone(), text);
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

/// A conversion as one text: diagnostics, then the program (or that it was refused).
pub fn render(case: &Case, to: Dialect, conversion: &Conversion) -> String {
    let diags = ncthread::diag::render_all(
        &conversion.diagnostics,
        ncthread::diag::Format::Human,
        false,
    );
    format!(
        "source: {}\nprofile: {}\ntarget: {to}\n--- diagnostics\n{}--- output\n{}",
        case.path,
        case.profile
            .as_deref()
            .unwrap_or("none (built-in defaults)"),
        diags,
        conversion
            .output
            .as_deref()
            .unwrap_or("(refused: nothing written)\n"),
    )
}

/// One canonical machine call of rs274 that moves the tool. X is a diameter here.
#[derive(Clone, Debug, PartialEq)]
pub enum Canon {
    Traverse {
        x: f64,
        z: f64,
    },
    Feed {
        x: f64,
        z: f64,
    },
    /// START_SPEED_FEED_SYNC: K, the advance per revolution along the path.
    SyncStart {
        k: f64,
    },
    SyncStop,
    RigidTap {
        x: f64,
        z: f64,
    },
    SpindleClockwise,
    SpindleCounterClockwise,
    SpindleStop,
    /// SET_FEED_RATE
    FeedRate(f64),
    /// SET_FEED_MODE: per revolution when true.
    FeedPerRev(bool),
    /// USE_LENGTH_UNITS: inches when true (the calls' lengths are then in inches).
    Inches(bool),
}

/// The command that runs rs274, or `None` (with a loud message) when there is none.
/// `$NCTHREAD_RS274` names a command run as `CMD FILE.ngc`; otherwise `scripts/rs274`
/// provides the interpreter (it fetches the Debian package on first use).
pub fn rs274() -> Option<&'static Path> {
    static FOUND: OnceLock<Option<PathBuf>> = OnceLock::new();
    FOUND
        .get_or_init(|| {
            if let Some(cmd) = std::env::var_os("NCTHREAD_RS274") {
                return Some(PathBuf::from(cmd));
            }
            let script = root().join("scripts/rs274");
            let ok = Command::new(&script).arg("--install").output().map(|o| o.status.success()).unwrap_or(false);
            if ok {
                return Some(script);
            }
            if std::env::var_os("CI").is_some() {
                panic!("rs274 is not available in CI: run `scripts/rs274 --install` before the tests");
            }
            eprintln!("\n!!!!! SKIPPING the rs274 oracle checks: no LinuxCNC interpreter could be had !!!!!");
            eprintln!("!!!!! run `scripts/rs274 --install` or set NCTHREAD_RS274 to run them       !!!!!\n");
            None
        })
        .as_deref()
}

/// Runs rs274 on `ngc`; Err with rs274's complaint when it refuses the program.
pub fn run_rs274(cmd: &Path, ngc: &str) -> Result<Vec<Canon>, String> {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("program.ngc");
    std::fs::write(&file, ngc).unwrap();
    let out = Command::new(cmd).arg(&file).output().expect("rs274 runs");
    let stderr = String::from_utf8_lossy(&out.stderr);
    let stdout = String::from_utf8_lossy(&out.stdout);
    let complaint = stderr
        .lines()
        .filter(|l| l.trim() != "executing" && !l.trim().is_empty())
        .collect::<Vec<_>>();
    if !out.status.success() || !complaint.is_empty() {
        return Err(format!(
            "rs274 exit {:?}: {}",
            out.status.code(),
            complaint.join("\n")
        ));
    }
    if !stdout.contains("FINISH()") && !stdout.contains("PROGRAM_END()") {
        return Err("rs274 did not reach the end of the program".into());
    }
    Ok(stdout.lines().filter_map(parse_canon).collect())
}

fn numbers(args: &str) -> Vec<f64> {
    args.split([',', ' '])
        .filter_map(|a| a.trim().parse().ok())
        .collect()
}

fn parse_canon(line: &str) -> Option<Canon> {
    // `   12 N.....  CALL(…)` or `   27 N50    CALL(…)` (the source line's N number).
    let (_, rest) = line.trim_start().split_once(' ')?;
    let (n, call) = rest.trim_start().split_once(' ')?;
    if !n.starts_with('N') {
        return None;
    }
    let call = call.trim_start();
    let (name, rest) = call.split_once('(')?;
    let args = numbers(rest.trim_end_matches(')'));
    Some(match name {
        "STRAIGHT_TRAVERSE" => Canon::Traverse {
            x: 2.0 * args[0],
            z: args[2],
        },
        "STRAIGHT_FEED" => Canon::Feed {
            x: 2.0 * args[0],
            z: args[2],
        },
        "RIGID_TAP" => Canon::RigidTap {
            x: 2.0 * args[0],
            z: args[2],
        },
        "START_SPEED_FEED_SYNC" => Canon::SyncStart { k: args[0] },
        "STOP_SPEED_FEED_SYNCH" => Canon::SyncStop,
        "START_SPINDLE_CLOCKWISE" => Canon::SpindleClockwise,
        "START_SPINDLE_COUNTERCLOCKWISE" => Canon::SpindleCounterClockwise,
        "STOP_SPINDLE_TURNING" => Canon::SpindleStop,
        "SET_FEED_RATE" => Canon::FeedRate(args[0]),
        "SET_FEED_MODE" => Canon::FeedPerRev(args.get(1).is_some_and(|&m| m == 1.0)),
        "USE_LENGTH_UNITS" => Canon::Inches(rest.contains("INCHES")),
        _ => return None,
    })
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

/// The spindle phase (angle at Z0, degrees) of each synchronised move as LinuxCNC runs it:
/// a chain of moves starts at the index pulse, and a move that continues the previous one
/// where it ended stays on its helix.
pub fn sync_phases(moves: &[SyncMove]) -> Vec<f64> {
    let mut phases: Vec<f64> = Vec::new();
    for (i, m) in moves.iter().enumerate() {
        let towards = (m.to.1 - m.from.1).signum();
        let continues = i > 0 && {
            let p = &moves[i - 1];
            close(p.to.0, m.from.0, 1e-9) && close(p.to.1, m.from.1, 1e-9)
        };
        let phase = if continues {
            phases[i - 1]
        } else {
            (-towards * 360.0 * m.from.1 / m.z_lead).rem_euclid(360.0)
        };
        phases.push(phase);
    }
    phases
}

/// LinuxCNC's motion as ncthread's simulator describes motion, so that `sim::compare` can
/// judge the two readings of one program. A chain of synchronised moves (one after another
/// in the motion queue: LinuxCNC waits for the index pulse only when a synchronised move
/// follows an unsynchronised one) starts at the index pulse, and the spindle angle runs on
/// through the chain at path length / K turns per move; a synchronised move without Z travel (G76's
/// radial feed in above the crest) cuts nothing and counts as a rapid, but its turns still
/// pass. Positions are unknown until the first move, as in the simulator.
pub fn rs274_segments(canon: &[Canon]) -> Vec<ncthread::sim::Segment> {
    use ncthread::fixed::{Angle, Length};
    use ncthread::ir::{Pos, SpindleDirection};
    use ncthread::sim::{Motion, Segment};
    let mm = Length::from_mm_f64;
    let mut pos = Pos::UNKNOWN;
    let (mut k, mut chain_turns): (Option<f64>, Option<f64>) = (None, None);
    let mut direction = None;
    let (mut feed, mut per_rev) = (0.0, false);
    let mut out = Vec::new();
    let mut scale = 1.0;
    let push = |out: &mut Vec<Segment>, motion, from: Pos, to: Pos| {
        if from != to || matches!(motion, Motion::Tap { .. }) {
            out.push(Segment {
                motion,
                from,
                to,
                line: 0,
                pass: None,
            });
        }
    };
    for c in canon {
        match *c {
            Canon::Traverse { x, z } => {
                let to = Pos::new(mm(x * scale), mm(z * scale));
                push(&mut out, Motion::Rapid, pos, to);
                pos = to;
                chain_turns = None;
            }
            Canon::Feed { x, z } => {
                let (x, z) = (x * scale, z * scale);
                let to = Pos::new(mm(x), mm(z));
                match k.map(|k| k * scale) {
                    Some(k) => {
                        let (x0, z0) = pos
                            .known()
                            .map(|(x, z)| (x.to_mm_f64(), z.to_mm_f64()))
                            .unwrap_or((0.0, 0.0));
                        let (dr, dz) = ((x - x0) / 2.0, z - z0);
                        let length = dr.hypot(dz);
                        let turns = chain_turns.get_or_insert(0.0);
                        if dz == 0.0 {
                            push(&mut out, Motion::Rapid, pos, to);
                        } else {
                            let z_lead = k * dz.abs() / length;
                            // The spindle angle at Z0 on this helix.
                            let towards = dz.signum();
                            let at_zero = (*turns - towards * z0 / z_lead) * 360.0;
                            let phase = Angle(
                                (at_zero.rem_euclid(360.0) * 1000.0).round() as i64 % 360_000,
                            );
                            push(
                                &mut out,
                                Motion::Sync {
                                    lead: mm(z_lead),
                                    direction,
                                    phase: Some(phase),
                                },
                                pos,
                                to,
                            );
                        }
                        *turns += length / k;
                    }
                    None => {
                        push(
                            &mut out,
                            Motion::Feed {
                                feed: mm(feed * scale),
                                per_minute: !per_rev,
                            },
                            pos,
                            to,
                        );
                        chain_turns = None;
                    }
                }
                pos = to;
            }
            Canon::RigidTap { z, .. } => {
                let to = Pos {
                    x: pos.x,
                    z: Some(mm(z * scale)),
                };
                let lead = mm(k.unwrap_or(0.0) * scale);
                push(&mut out, Motion::Tap { lead, direction }, pos, to);
                chain_turns = None;
            }
            Canon::SyncStart { k: new } => k = Some(new),
            Canon::SyncStop => k = None,
            Canon::SpindleClockwise => direction = Some(SpindleDirection::Clockwise),
            Canon::SpindleCounterClockwise => direction = Some(SpindleDirection::CounterClockwise),
            Canon::SpindleStop => direction = None,
            Canon::FeedRate(f) => feed = f,
            Canon::FeedPerRev(p) => per_rev = p,
            Canon::Inches(inch) => scale = if inch { 25.4 } else { 1.0 },
        }
    }
    out
}

/// Our own simulation of an ISO program text (the iso front end, default profile).
pub fn simulate_iso(name: &str, text: &str) -> ncthread::sim::Simulation {
    let src = SourceFile::new(name, text);
    let (program, diags) =
        ncthread::parse(&src, Dialect::Iso, &Profile::default(), Unsupported::Error);
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

pub fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

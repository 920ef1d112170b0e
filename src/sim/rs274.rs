//! LinuxCNC's `rs274` as a second judge: its canonical machine calls for an ISO program,
//! read back into the simulator's [`Segment`]s so that [`super::compare`] can hold them
//! against ncthread's own simulation. The tests use it as the oracle for every ISO output, and
//! `ncthread verify --rs274` runs it on a conversion.

use std::path::{Path, PathBuf};
use std::process::Command;

use super::{Motion, Segment};
use crate::fixed::{Angle, Lead, Length};
use crate::ir::{Pos, SpindleDirection};

/// One canonical machine call that moves the tool or changes what a move means. X is a
/// diameter here (rs274 prints radii in the XZ plane of a lathe).
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
    /// ARC_FEED in the XZ plane: the end, the centre, and the rotation (negative: G2;
    /// its size the turns).
    Arc {
        x: f64,
        z: f64,
        cx: f64,
        cz: f64,
        rotation: i32,
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
    /// SET_SPINDLE_SPEED: rpm, or m/min under a surface speed.
    SpindleSpeed(f64),
    /// SET_SPINDLE_MODE: 0 for rpm, else a surface speed with this rpm limit (1e30: none).
    SpindleMode(f64),
    /// SET_G5X_OFFSET: the work offset's index (1: G54).
    WorkOffset(u8),
    /// MIST_ON / MIST_OFF
    Mist(bool),
    /// FLOOD_ON / FLOOD_OFF
    Flood(bool),
    /// PROGRAM_STOP, or OPTIONAL_PROGRAM_STOP when true.
    Stop(bool),
    /// DWELL: seconds.
    Dwell(f64),
    /// CHANGE_TOOL: the tool now in the spindle.
    ChangeTool(u32),
    /// SELECT_TOOL: the tool the next change takes (a turret that indexes on T changes to it).
    SelectTool(u32),
    /// SET_G92_OFFSET: the G52/G92 offset (X a diameter) that the calls after it leave out of
    /// their coordinates. [`Interpreter::run`] adds it back and drops this call.
    AxisOffset {
        x: f64,
        z: f64,
    },
}

/// The calls with every G52/G92 offset added back into the coordinates: what the tool does in
/// the work coordinates, whatever offsets the program set.
///
/// The machine holds an offset in its own units from the moment it is set (LinuxCNC's canon
/// layer converts it then): after a change of units the calls' coordinates are in the new
/// unit, the offset is not, so it is held in millimetres here and added in the unit in force.
pub fn without_axis_offsets(canon: impl IntoIterator<Item = Canon>) -> Vec<Canon> {
    let (mut x_mm, mut z_mm) = (0.0, 0.0);
    let mut scale = 1.0;
    let (mut dx, mut dz) = (0.0, 0.0);
    let mut out = Vec::new();
    for c in canon {
        out.push(match c {
            Canon::AxisOffset { x, z } => {
                (x_mm, z_mm) = (x * scale, z * scale);
                (dx, dz) = (x, z);
                continue;
            }
            Canon::Inches(inch) => {
                scale = if inch { 25.4 } else { 1.0 };
                (dx, dz) = (x_mm / scale, z_mm / scale);
                Canon::Inches(inch)
            }
            Canon::Traverse { x, z } => Canon::Traverse {
                x: x + dx,
                z: z + dz,
            },
            Canon::Feed { x, z } => Canon::Feed {
                x: x + dx,
                z: z + dz,
            },
            Canon::RigidTap { x, z } => Canon::RigidTap {
                x: x + dx,
                z: z + dz,
            },
            Canon::Arc {
                x,
                z,
                cx,
                cz,
                rotation,
            } => Canon::Arc {
                x: x + dx,
                z: z + dz,
                cx: cx + dx,
                cz: cz + dz,
                rotation,
            },
            other => other,
        });
    }
    out
}

fn numbers(args: &str) -> Vec<f64> {
    args.split([',', ' '])
        .filter_map(|a| a.trim().parse().ok())
        .collect()
}

/// One line of rs274's output (`   12 N.....  CALL(…)`), when it is a call that matters.
pub fn parse_canon(line: &str) -> Option<Canon> {
    // `   42 N30    NAME(…)`: the call counter, the block number in a six-wide column (a
    // longer one runs into the name), the call.
    let (_, rest) = line.trim_start().split_once(' ')?;
    let call = rest
        .trim_start()
        .strip_prefix('N')?
        .trim_start_matches(|c: char| c.is_ascii_digit() || c == '.')
        .trim_start();
    let (name, rest) = call.split_once('(')?;
    let args = numbers(rest.trim_end_matches(')'));
    let arg = |i: usize| args.get(i).copied();
    Some(match name {
        "STRAIGHT_TRAVERSE" => Canon::Traverse {
            x: 2.0 * arg(0)?,
            z: arg(2)?,
        },
        "STRAIGHT_FEED" => Canon::Feed {
            x: 2.0 * arg(0)?,
            z: arg(2)?,
        },
        // ARC_FEED(first_end, second_end, first_axis, second_axis, rotation, …): in the XZ
        // plane Z first, X second (a radius).
        "ARC_FEED" => Canon::Arc {
            z: arg(0)?,
            x: 2.0 * arg(1)?,
            cz: arg(2)?,
            cx: 2.0 * arg(3)?,
            rotation: arg(4)? as i32,
        },
        "RIGID_TAP" => Canon::RigidTap {
            x: 2.0 * arg(0)?,
            z: arg(2)?,
        },
        "START_SPEED_FEED_SYNC" => Canon::SyncStart { k: arg(0)? },
        "STOP_SPEED_FEED_SYNCH" => Canon::SyncStop,
        "START_SPINDLE_CLOCKWISE" => Canon::SpindleClockwise,
        "START_SPINDLE_COUNTERCLOCKWISE" => Canon::SpindleCounterClockwise,
        "STOP_SPINDLE_TURNING" => Canon::SpindleStop,
        "SET_FEED_RATE" => Canon::FeedRate(arg(0)?),
        "SET_FEED_MODE" => Canon::FeedPerRev(arg(1).is_some_and(|m| m == 1.0)),
        "USE_LENGTH_UNITS" => Canon::Inches(rest.contains("INCHES")),
        "SET_SPINDLE_SPEED" => Canon::SpindleSpeed(arg(1)?),
        // `SET_SPINDLE_MODE(0 2500.0000)`: the spindle, then the mode (no comma).
        "SET_SPINDLE_MODE" => Canon::SpindleMode(arg(1)?),
        "SET_G5X_OFFSET" => Canon::WorkOffset(arg(0)? as u8),
        "MIST_ON" => Canon::Mist(true),
        "MIST_OFF" => Canon::Mist(false),
        "FLOOD_ON" => Canon::Flood(true),
        "FLOOD_OFF" => Canon::Flood(false),
        "PROGRAM_STOP" => Canon::Stop(false),
        "OPTIONAL_PROGRAM_STOP" => Canon::Stop(true),
        "DWELL" => Canon::Dwell(arg(0)?),
        "CHANGE_TOOL" => Canon::ChangeTool(arg(0)? as u32),
        "SELECT_TOOL" => Canon::SelectTool(arg(0)? as u32),
        "SET_G92_OFFSET" => Canon::AxisOffset {
            x: 2.0 * arg(0)?,
            z: arg(2)?,
        },
        _ => return None,
    })
}

/// How long one run of LinuxCNC's interpreter may take: some of its cycles never end on
/// some contours (its G71 before 2.9.1), and a judge must not hang.
const RUN_LIMIT: std::time::Duration = std::time::Duration::from_secs(60);

/// Runs `command` with its output captured; kills it (and says so) after `limit`.
fn run_bounded(
    mut command: Command,
    limit: std::time::Duration,
) -> Result<std::process::Output, String> {
    use std::io::Read;
    use std::process::Stdio;
    // Its own process group, so that a run killed at the limit takes its children with it
    // (a wrapper such as scripts/rs274 cannot pass a SIGKILL on to the rs274 under it).
    #[cfg(unix)]
    std::os::unix::process::CommandExt::process_group(&mut command, 0);
    let mut child = command
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| e.to_string())?;
    // The pipes are drained on threads so that a full pipe never stalls the child.
    let drain = |pipe: Option<Box<dyn Read + Send>>| {
        std::thread::spawn(move || {
            let mut bytes = Vec::new();
            if let Some(mut p) = pipe {
                let _ = p.read_to_end(&mut bytes);
            }
            bytes
        })
    };
    let stdout = drain(
        child
            .stdout
            .take()
            .map(|p| Box::new(p) as Box<dyn Read + Send>),
    );
    let stderr = drain(
        child
            .stderr
            .take()
            .map(|p| Box::new(p) as Box<dyn Read + Send>),
    );
    let started = std::time::Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().map_err(|e| e.to_string())? {
            break status;
        }
        if started.elapsed() > limit {
            kill_group(child.id());
            let _ = child.kill();
            let _ = child.wait();
            return Err(format!(
                "it did not finish within {} s (LinuxCNC's interpreter loops for ever on this program)",
                limit.as_secs()
            ));
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    };
    Ok(std::process::Output {
        status,
        stdout: stdout.join().unwrap_or_default(),
        stderr: stderr.join().unwrap_or_default(),
    })
}

/// Kills the process group `pid` leads (see [`run_bounded`]), through `kill(1)`.
fn kill_group(pid: u32) {
    #[cfg(unix)]
    let _ = Command::new("kill")
        .args(["-s", "KILL", "--", &format!("-{pid}")])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .status();
    #[cfg(not(unix))]
    let _ = pid;
}

/// How many runs [`Interpreter::run_with`] makes of a program while rs274 is killed by a
/// signal. A crash says nothing of the program: LinuxCNC's rs274 dies of SIGBUS when another
/// rs274 in the same HOME truncates the tool table file they both map (`$HOME/.tool.mmap`).
pub const TRIES: u32 = 3;

/// Why a run of LinuxCNC's interpreter gave no canonical calls.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum RunError {
    /// rs274 refused the program (its exit code and complaint), or stopped before its end.
    Refused(String),
    /// rs274 was killed by `signal` on each of `tries` runs: the interpreter crashed, which
    /// says nothing of the program.
    Killed { signal: i32, tries: u32 },
    /// The interpreter could not be run, or did not finish in time.
    CannotRun(String),
}

impl RunError {
    /// The interpreter crashed: no judgement of the program.
    pub fn is_crash(&self) -> bool {
        matches!(self, RunError::Killed { .. })
    }
}

impl std::fmt::Display for RunError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            RunError::Refused(why) | RunError::CannotRun(why) => f.write_str(why),
            RunError::Killed { signal, tries } => {
                write!(f, "rs274 was killed by signal {signal}")?;
                if let Some(name) = signal_name(*signal) {
                    write!(f, " ({name})")?;
                }
                if *tries > 1 {
                    write!(f, " on each of {tries} runs")?;
                }
                f.write_str(": LinuxCNC's interpreter crashed, which says nothing of the program")
            }
        }
    }
}

/// The signal that killed a process, if one did.
#[cfg(unix)]
fn killed_by(status: &std::process::ExitStatus) -> Option<i32> {
    std::os::unix::process::ExitStatusExt::signal(status)
}

#[cfg(not(unix))]
fn killed_by(_: &std::process::ExitStatus) -> Option<i32> {
    None
}

/// A signal's name (`SIGBUS`), for the signals a crashed or stopped process dies of.
#[cfg(unix)]
fn signal_name(signal: i32) -> Option<&'static str> {
    Some(match signal {
        libc::SIGHUP => "SIGHUP",
        libc::SIGINT => "SIGINT",
        libc::SIGQUIT => "SIGQUIT",
        libc::SIGILL => "SIGILL",
        libc::SIGTRAP => "SIGTRAP",
        libc::SIGABRT => "SIGABRT",
        libc::SIGBUS => "SIGBUS",
        libc::SIGFPE => "SIGFPE",
        libc::SIGKILL => "SIGKILL",
        libc::SIGSEGV => "SIGSEGV",
        libc::SIGPIPE => "SIGPIPE",
        libc::SIGALRM => "SIGALRM",
        libc::SIGTERM => "SIGTERM",
        libc::SIGXCPU => "SIGXCPU",
        libc::SIGXFSZ => "SIGXFSZ",
        libc::SIGSYS => "SIGSYS",
        _ => return None,
    })
}

#[cfg(not(unix))]
fn signal_name(_: i32) -> Option<&'static str> {
    None
}

/// The machine's settings a run of LinuxCNC's interpreter follows.
#[derive(Clone, Debug, Default)]
pub struct Settings {
    /// The block delete switch is on: lines that start with `/` are skipped.
    pub block_delete: bool,
    /// Folders that hold subroutine files.
    pub subroutine_path: Vec<std::path::PathBuf>,
}

/// How to run LinuxCNC's interpreter.
#[derive(Clone, Debug)]
pub enum Interpreter {
    /// A command run as `CMD FILE` that prints the canonical calls (the project's
    /// `scripts/rs274`, or `$NCTHREAD_RS274`).
    Wrapper(PathBuf),
    /// LinuxCNC's `rs274` itself, run as `rs274 -t TOOLS -g FILE` with a tool table of
    /// tools 1–999 at zero offsets (rs274 refuses tools it does not know), in a HOME of its
    /// own (a temporary folder).
    Binary(PathBuf),
}

impl Interpreter {
    /// `$NCTHREAD_RS274` when set, else `rs274` on the PATH.
    pub fn find() -> Option<Interpreter> {
        if let Some(cmd) = std::env::var_os("NCTHREAD_RS274") {
            return Some(Interpreter::Wrapper(PathBuf::from(cmd)));
        }
        let path = std::env::var_os("PATH")?;
        std::env::split_paths(&path)
            .map(|dir| dir.join("rs274"))
            .find(|p| p.is_file())
            .map(Interpreter::Binary)
    }

    /// Runs the interpreter on `program`: its canonical calls, or its complaint when it
    /// refuses the program (or cannot be run).
    pub fn run(&self, program: &str) -> Result<Vec<Canon>, RunError> {
        self.run_with(program, &Settings::default())
    }

    /// [`Interpreter::run`] with the machine's settings: the block delete switch (`rs274
    /// -b`) and the folders of subroutine files (an INI file's `SUBROUTINE_PATH`). A run
    /// killed by a signal is tried again, up to [`TRIES`] runs in all.
    pub fn run_with(&self, program: &str, settings: &Settings) -> Result<Vec<Canon>, RunError> {
        let cannot = RunError::CannotRun;
        let dir = tempfile::tempdir()
            .map_err(|e| cannot(format!("cannot make a temporary folder: {e}")))?;
        let switch = switches(settings, dir.path())?;
        let file = dir.path().join("program.ngc");
        std::fs::write(&file, as_lathe_starts(&without_user_m_codes(program)))
            .map_err(|e| cannot(format!("cannot write {}: {e}", file.display())))?;
        let tools = dir.path().join("tools.tbl");
        if let Interpreter::Binary(_) = self {
            let table: String = (1..=999)
                .map(|i| format!("T{i} P{i} X0 Z0 D0 ;\n"))
                .collect();
            std::fs::write(&tools, table)
                .map_err(|e| cannot(format!("cannot write {}: {e}", tools.display())))?;
        }
        let command = || match self {
            Interpreter::Wrapper(cmd) => {
                let mut c = Command::new(cmd);
                c.args(&switch).arg(&file);
                c
            }
            Interpreter::Binary(bin) => {
                let mut c = Command::new(bin);
                // rs274 maps its tool table from `$HOME/.tool.mmap` and truncates the file at
                // every start: a run sharing a HOME with another rs274 dies of SIGBUS.
                c.env("HOME", dir.path());
                c.arg("-t").arg(&tools).arg("-g").args(&switch).arg(&file);
                c
            }
        };
        let out = self.run_retrying(command)?;
        calls_of(&out)
    }

    /// Runs the command `command` makes, again while it is killed by a signal, up to
    /// [`TRIES`] runs in all.
    fn run_retrying(
        &self,
        command: impl Fn() -> Command,
    ) -> Result<std::process::Output, RunError> {
        let mut tries = 0;
        loop {
            tries += 1;
            let out = run_bounded(command(), RUN_LIMIT).map_err(|e| {
                RunError::CannotRun(format!("cannot run {}: {e}", self.path().display()))
            })?;
            match killed_by(&out.status) {
                // A crash of the interpreter, not a judgement of the program: once more.
                Some(_) if tries < TRIES => {}
                Some(signal) => return Err(RunError::Killed { signal, tries }),
                None => return Ok(out),
            }
        }
    }

    fn path(&self) -> &Path {
        match self {
            Interpreter::Wrapper(p) | Interpreter::Binary(p) => p,
        }
    }
}

/// `program` as a LinuxCNC lathe runs it: after its start-up code, `G18`. LinuxCNC's lathe
/// configuration sets `RS274NGC_STARTUP_CODE = G18` (its manual's "Lathe Configuration"
/// chapter: the interpreter was written for mills and starts in G17), and ncthread reads an ISO
/// program as on a lathe; the standalone rs274 runs no start-up code, so the line goes first
/// — after the opening `%` when the program has one, which must stay its first line.
fn as_lathe_starts(program: &str) -> String {
    let mut out = String::with_capacity(program.len() + 5);
    let mut rest = program;
    // rs274 skips blank lines before the `%` line (`Interp::open`).
    while let Some(end) = rest.find('\n') {
        let line = &rest[..end];
        if !line.trim().is_empty() {
            if line.trim() == "%" {
                out.push_str(&rest[..=end]);
                rest = &rest[end + 1..];
            }
            break;
        }
        out.push_str(&rest[..=end]);
        rest = &rest[end + 1..];
    }
    out.push_str("G18\n");
    out.push_str(rest);
    out
}

/// `program` without its user M codes (M100–M199), each word blanked out where it stands.
/// On a machine LinuxCNC runs each as a program of its configuration (`USER_M_PATH`), which
/// moves no axis; the standalone rs274 has no configuration and refuses them ("Unknown m
/// code used"), and cannot take them as remaps either. Comments and `<…>` names are left as
/// they are.
fn without_user_m_codes(program: &str) -> std::borrow::Cow<'_, str> {
    let bytes = program.as_bytes();
    let mut blank: Vec<std::ops::Range<usize>> = Vec::new();
    let (mut i, mut comment, mut name, mut line_comment) = (0, false, false, false);
    while i < bytes.len() {
        let b = bytes[i];
        match b {
            b'\n' => (comment, name, line_comment) = (false, false, false),
            _ if line_comment => {}
            b'(' if !name => comment = true,
            b')' if comment => comment = false,
            b';' if !comment && !name => line_comment = true,
            b'<' if !comment => name = true,
            b'>' if name => name = false,
            b'M' | b'm' if !comment && !name => {
                let mut end = i + 1;
                while end < bytes.len() && matches!(bytes[end], b' ' | b'\t') {
                    end += 1;
                }
                let digits = end;
                while end < bytes.len() && bytes[end].is_ascii_digit() {
                    end += 1;
                }
                let value: Option<u32> = program[digits..end].parse().ok();
                let fraction = bytes.get(end) == Some(&b'.');
                if value.is_some_and(|v| (100..=199).contains(&v)) && !fraction {
                    blank.push(i..end);
                }
                i = end.max(i + 1);
                continue;
            }
            _ => {}
        }
        i += 1;
    }
    if blank.is_empty() {
        return std::borrow::Cow::Borrowed(program);
    }
    let mut out = program.as_bytes().to_vec();
    for range in blank {
        out[range].fill(b' ');
    }
    std::borrow::Cow::Owned(String::from_utf8(out).unwrap_or_else(|_| program.to_string()))
}

/// The switches of an rs274 run with `settings`: `-b` for the block delete switch, and
/// `-i` with an INI file (written into `dir`) for the folders of subroutine files.
fn switches(settings: &Settings, dir: &Path) -> Result<Vec<std::ffi::OsString>, RunError> {
    let mut switch: Vec<std::ffi::OsString> = Vec::new();
    if settings.block_delete {
        switch.push("-b".into());
    }
    if !settings.subroutine_path.is_empty() {
        let folders: Vec<String> = settings
            .subroutine_path
            .iter()
            .map(|p| {
                std::path::absolute(p)
                    .unwrap_or_else(|_| p.clone())
                    .display()
                    .to_string()
            })
            .collect();
        let ini = dir.join("ncthread.ini");
        std::fs::write(
            &ini,
            format!("[RS274NGC]\nSUBROUTINE_PATH = {}\n", folders.join(":")),
        )
        .map_err(|e| RunError::CannotRun(format!("cannot write {}: {e}", ini.display())))?;
        switch.push("-i".into());
        switch.push(ini.into_os_string());
    }
    Ok(switch)
}

/// The canonical calls of a finished rs274 run, or its complaint: a run must end without
/// one (but for the complaint of a program without an end, which runs to its last line)
/// and reach the program's end.
fn calls_of(out: &std::process::Output) -> Result<Vec<Canon>, RunError> {
    let stderr = String::from_utf8_lossy(&out.stderr);
    let stdout = String::from_utf8_lossy(&out.stdout);
    let complaint: Vec<&str> = stderr
        .lines()
        .filter(|l| l.trim() != "executing" && !l.trim().is_empty())
        .collect();
    // A program without an end runs to its last line; then rs274 complains.
    let ran_to_the_end = complaint
        .first()
        .is_some_and(|c| c.starts_with("File ended with no percent sign"));
    if (!out.status.success() || !complaint.is_empty()) && !ran_to_the_end {
        return Err(RunError::Refused(format!(
            "rs274 exit {:?}: {}",
            out.status.code(),
            complaint.join("\n")
        )));
    }
    if !ran_to_the_end && !stdout.contains("FINISH()") && !stdout.contains("PROGRAM_END()") {
        return Err(RunError::Refused(
            "rs274 did not reach the end of the program".into(),
        ));
    }
    Ok(without_axis_offsets(stdout.lines().filter_map(parse_canon)))
}

/// LinuxCNC's motion as ncthread's simulator describes motion. A chain of synchronised moves
/// (one after another in the motion queue: LinuxCNC waits for the index pulse only when a
/// synchronised move follows an unsynchronised one) starts at the index pulse, and the
/// spindle angle runs on through the chain at path length / K turns per move, whatever K
/// each move has. A synchronised move without Z travel (G76's radial feed in before an entry
/// taper) is reported as [`Motion::SyncRadial`]. Positions are unknown until the first move,
/// as in the simulator.
pub fn segments(canon: &[Canon]) -> Vec<Segment> {
    let mut reader = CanonReader {
        pos: Pos::UNKNOWN,
        exact: None,
        snapped: None,
        k: None,
        chain_turns: None,
        direction: None,
        feed: 0.0,
        per_rev: false,
        out: Vec::new(),
        scale: 1.0,
        state: super::MachineState::default(),
    };
    for c in canon {
        reader.call(c);
    }
    reader.out
}

/// [`segments`]' reading of the calls, one at a time.
struct CanonReader {
    pos: Pos,
    /// The position as rs274 printed it, in mm, before rounding onto the grid.
    exact: Option<(f64, f64)>,
    /// After a synchronised move whose printed Z [`Self::feed_to`] took for the one it did
    /// not leave: that printed position (mm), where a traverse to it goes nowhere.
    snapped: Option<(f64, f64)>,
    /// The K of the synchronised motion in force (in the program's units).
    k: Option<f64>,
    /// The spindle turns so far in the chain of synchronised moves (`None`: no chain).
    chain_turns: Option<f64>,
    direction: Option<SpindleDirection>,
    feed: f64,
    per_rev: bool,
    out: Vec<Segment>,
    /// mm per program unit.
    scale: f64,
    state: super::MachineState,
}

impl CanonReader {
    /// One canonical call.
    fn call(&mut self, c: &Canon) {
        let mm = Length::from_mm_f64;
        let scale = self.scale;
        // Calls that do not move (a synchronisation's end, a comment) keep it.
        let snapped = match c {
            Canon::Traverse { .. }
            | Canon::Feed { .. }
            | Canon::Arc { .. }
            | Canon::RigidTap { .. } => self.snapped.take(),
            _ => self.snapped,
        };
        match *c {
            // Added back into the coordinates when the calls were read.
            Canon::AxisOffset { .. } => {}
            // A traverse to the printed end of a snapped synchronised move stays there.
            Canon::Traverse { x, z } if snapped == Some((x * scale, z * scale)) => {
                self.push(Motion::Rapid, self.pos);
                self.chain_turns = None;
            }
            Canon::Traverse { x, z } => {
                let to = Pos::new(mm(x * scale), mm(z * scale));
                self.push(Motion::Rapid, to);
                self.pos = to;
                self.exact = Some((x * scale, z * scale));
                self.chain_turns = None;
            }
            Canon::Feed { x, z } => self.feed_to(x, z),
            Canon::Arc {
                x,
                z,
                cx,
                cz,
                rotation,
            } => {
                let to = Pos::new(mm(x * scale), mm(z * scale));
                let motion = Motion::Arc {
                    centre: Pos::new(mm(cx * scale), mm(cz * scale)),
                    clockwise: rotation < 0,
                    feed: mm(self.feed * scale),
                    per_minute: !self.per_rev,
                };
                self.push(motion, to);
                self.pos = to;
                self.exact = Some((x * scale, z * scale));
                self.chain_turns = None;
            }
            Canon::RigidTap { z, .. } => {
                let to = Pos {
                    x: self.pos.x,
                    z: Some(mm(z * scale)),
                };
                let lead = Lead::from_mm_f64(self.k.unwrap_or(0.0) * scale).unwrap_or(Lead::MAX);
                let direction = self.direction;
                self.push(Motion::Tap { lead, direction }, to);
                self.chain_turns = None;
            }
            Canon::SyncStart { k: new } => self.k = Some(new),
            Canon::SyncStop => self.k = None,
            Canon::SpindleClockwise
            | Canon::SpindleCounterClockwise
            | Canon::SpindleStop
            | Canon::SpindleSpeed(_)
            | Canon::SpindleMode(_)
            | Canon::WorkOffset(_)
            | Canon::Mist(_)
            | Canon::Flood(_)
            | Canon::ChangeTool(_) => self.machine_state(c),
            // Only a change puts the tool in the spindle.
            Canon::SelectTool(_) => {}
            Canon::FeedRate(f) => self.feed = f,
            Canon::FeedPerRev(p) => self.per_rev = p,
            Canon::Inches(inch) => self.scale = if inch { 25.4 } else { 1.0 },
            Canon::Stop(optional) => self.event(Motion::Stop { optional }),
            Canon::Dwell(seconds) => {
                let time = (seconds * 10_000.0).round() as i64;
                self.event(Motion::Dwell { time });
            }
        }
    }

    /// A move from the position to `to`, kept unless it goes nowhere (a tap or an arc, a
    /// full circle, is always kept).
    fn push(&mut self, motion: Motion, to: Pos) {
        if self.pos != to || matches!(motion, Motion::Tap { .. } | Motion::Arc { .. }) {
            self.out.push(Segment {
                motion,
                from: self.pos,
                to,
                line: 0,
                pass: None,
            });
        }
    }

    /// An event where the tool stands.
    fn event(&mut self, motion: Motion) {
        self.out.push(Segment {
            motion,
            from: self.pos,
            to: self.pos,
            line: 0,
            pass: None,
        });
    }

    /// A straight feed move: synchronised while a K is in force, else at the feed rate.
    fn feed_to(&mut self, x: f64, z: f64) {
        let scale = self.scale;
        let (x, mut z) = (x * scale, z * scale);
        // In inches rs274 prints a Z it did not move to four decimals of an inch: a
        // synchronised move along X alone can seem to move Z by up to 0.0001 inch.
        if let (Some((_, z0)), Some(_)) = (self.exact, self.k)
            && scale != 1.0
            && (z - z0).abs() <= 1.0001e-4 * scale
        {
            self.snapped = Some((x, z));
            z = z0;
        }
        let to = Pos::new(Length::from_mm_f64(x), Length::from_mm_f64(z));
        match self.k.map(|k| k * scale) {
            Some(k) => self.synchronised(k, x, z, to),
            None => {
                let motion = Motion::Feed {
                    feed: Length::from_mm_f64(self.feed * scale),
                    per_minute: !self.per_rev,
                };
                self.push(motion, to);
                self.chain_turns = None;
            }
        }
        self.pos = to;
        self.exact = Some((x, z));
    }

    /// A synchronised move to (`x`, `z`) in mm, K `k` mm per turn along its path: an
    /// infeed without Z travel, else a thread move with its phase; the chain's spindle
    /// angle runs on.
    fn synchronised(&mut self, k: f64, x: f64, z: f64, to: Pos) {
        let (x0, z0) = self.exact.unwrap_or((0.0, 0.0));
        let (dr, dz) = ((x - x0) / 2.0, z - z0);
        let length = dr.hypot(dz);
        let turns = *self.chain_turns.get_or_insert(0.0);
        let index_start = turns == 0.0;
        let motion = if dz == 0.0 {
            Motion::SyncRadial {
                advance: Lead::from_mm_f64(k).unwrap_or(Lead::MAX),
                direction: self.direction,
                start_angle: index_start.then_some(Angle::ZERO),
            }
        } else {
            let z_lead = k * dz.abs() / length;
            // The spindle angle at Z0 on this helix.
            let towards = dz.signum();
            let at_zero = (turns - towards * z0 / z_lead) * 360.0;
            let phase = Angle((at_zero.rem_euclid(360.0) * 1000.0).round() as i64 % 360_000);
            Motion::Sync {
                lead: Lead::from_mm_f64(z_lead).unwrap_or(Lead::MAX),
                direction: self.direction,
                phase: Some(phase),
            }
        };
        self.push(motion, to);
        self.chain_turns = Some(turns + length / k);
    }

    /// A call that changes the machine's state: an event when it does.
    fn machine_state(&mut self, c: &Canon) {
        let mut next = self.state;
        let inches = self.scale != 1.0;
        match *c {
            Canon::SpindleClockwise => {
                self.direction = Some(SpindleDirection::Clockwise);
            }
            Canon::SpindleCounterClockwise => {
                self.direction = Some(SpindleDirection::CounterClockwise);
            }
            Canon::SpindleStop => self.direction = None,
            // Under a surface speed, LinuxCNC's task canon takes S in ft/min or m/min by
            // the units in force when S is set.
            Canon::SpindleSpeed(v) => {
                next.speed = Some(v.round() as u32);
                next.surface_feet = next.surface_speed.is_some() && inches;
            }
            Canon::SpindleMode(v) => {
                next.surface_speed =
                    (v != 0.0).then(|| (v < 1e29).then(|| (v * 1000.0).round() as i64));
                next.surface_feet = next.surface_speed.is_some() && inches;
            }
            Canon::WorkOffset(n) => next.work_offset = n.saturating_sub(1),
            Canon::Mist(on) => next.mist = on,
            Canon::Flood(on) => next.flood = on,
            Canon::ChangeTool(t) => next.tool = Some(t),
            _ => {}
        }
        next.direction = self.direction;
        if next != self.state {
            self.state = next;
            self.event(Motion::State(next));
        }
    }
}

/// How far (in degrees) rs274's printed numbers leave the helix of its synchronised chains
/// uncertain: positions have four decimals and K six, and a chain's spindle angle is the sum
/// of path length / K over its moves, so a small K over a long path multiplies those last
/// digits. The largest over the program's chains.
pub fn phase_uncertainty(canon: &[Canon]) -> f64 {
    let mut prev: Option<(f64, f64)> = None;
    let mut k: Option<f64> = None;
    let (mut chain, mut worst) = (0.0f64, 0.0f64);
    for c in canon {
        match *c {
            Canon::Traverse { x, z } => {
                prev = Some((x, z));
                chain = 0.0;
            }
            Canon::Feed { x, z } => {
                if let (Some(k), Some((x0, z0))) = (k, prev)
                    && k > 0.0
                {
                    let length = ((x - x0) / 2.0).hypot(z - z0);
                    // Both ends off by half a digit on each axis; K off by half of its last.
                    chain += 1.5e-4 / k + length * 5e-7 / (k * k);
                    worst = worst.max(chain * 360.0);
                } else {
                    chain = 0.0;
                }
                prev = Some((x, z));
            }
            Canon::Arc { x, z, .. } => {
                prev = Some((x, z));
                chain = 0.0;
            }
            Canon::RigidTap { .. } => chain = 0.0,
            Canon::SyncStart { k: new } => k = Some(new),
            Canon::SyncStop => k = None,
            _ => {}
        }
    }
    worst
}

/// What LinuxCNC's run says of a simulation.
#[derive(Clone, Debug)]
pub enum Judgement {
    /// The motions agree; `segments` were compared, within `deviation`; `partial`: only up
    /// to where ncthread stops knowing the position (a move in machine coordinates).
    Agrees {
        segments: usize,
        deviation: Length,
        partial: bool,
    },
    Differs(Box<super::Difference>),
    /// rs274's printed digits cannot decide (why).
    CannotJudge(String),
}

/// Holds rs274's canonical calls against `expected` (a normalised simulation), allowing for
/// what rs274's printing loses: four decimals of an inch (0.00254 mm on the diameter), and the
/// digits that fix a synchronised chain's helix (a small K over a long path); beyond half a
/// turn of that, it cannot judge.
///
/// rs274 starts at X0 Z0, and prints a G0 without axes as a traverse to where it is: at the
/// start that reads like a rapid from an unknown place to X0 Z0. A first rapid to X0 Z0 is
/// therefore left out on both sides: rs274's output cannot tell it from no move.
pub fn judge(expected: &[Segment], canon: &[Canon]) -> Judgement {
    let inch = canon.iter().any(|c| matches!(c, Canon::Inches(true)));
    let tolerance = if inch {
        super::TOLERANCE + Length::from_steps(26)
    } else {
        super::TOLERANCE
    };
    let mut theirs = without_rapid_to_rs274_start(as_printed(&segments(canon), tolerance));
    // rs274 prints nothing for cutter compensation: ncthread's record of it is compared
    // between conversions, not here. With a tool radius the judge's tool table does not
    // have (G41.1/G42.1 D), LinuxCNC cuts the compensated path, which ncthread does not
    // compute: the judgement stops there.
    let compensated = expected.iter().position(|s| {
        matches!(
            s.motion,
            Motion::State(super::MachineState {
                compensation: Some(crate::ir::Compensation::Dynamic { diameter, .. }),
                ..
            }) if diameter.0 != 0
        )
    });
    let stripped: Vec<Segment> = expected[..compensated.unwrap_or(expected.len())]
        .iter()
        .map(|s| match s.motion {
            Motion::State(state) => Segment {
                motion: Motion::State(super::MachineState {
                    compensation: None,
                    ..state
                }),
                ..*s
            },
            _ => *s,
        })
        .collect();
    let cut = compensated.is_some();
    let expected = &without_rapid_to_rs274_start(as_printed(&stripped, tolerance));
    // Where ncthread stops knowing the position (a move in machine coordinates, to the
    // reference point), LinuxCNC's run is judged up to there.
    let mut known = known_prefix(expected);
    // Where the judgement is cut, rs274's last move may run on into what follows (rapids
    // merge; nothing of the compensation is printed): the last move is left out too.
    if cut {
        known = known.saturating_sub(1);
        if known == 0 {
            return Judgement::CannotJudge(
                "LinuxCNC cuts a compensated path from the start (G41.1/G42.1 with a diameter), which ncthread does not compute".into(),
            );
        }
    }
    if known == 0 && !expected.is_empty() {
        return Judgement::CannotJudge(
            "ncthread's simulation has positions it does not know (SIM001), which LinuxCNC's has"
                .into(),
        );
    }
    let partial = known < expected.len() || cut;
    if partial {
        theirs.truncate(known);
    }
    let expected = &expected[..known];
    let slack = phase_uncertainty(canon);
    if slack >= 180.0 {
        return Judgement::CannotJudge(format!(
            "rs274 prints four decimals, which leave the helix of a synchronised chain uncertain by {slack:.0}° (a small K over a long path)"
        ));
    }
    let slack = Angle((slack * 1000.0).ceil() as i64);
    match super::compare_within(expected, &theirs, tolerance, slack) {
        None => Judgement::Agrees {
            partial,
            segments: theirs.len(),
            deviation: super::largest_deviation(expected, &theirs),
        },
        Some(d) => Judgement::Differs(Box::new(d)),
    }
}

/// How many leading segments ncthread knows the positions of: up to the first move that
/// starts or ends where ncthread does not know (after a move in machine coordinates).
pub fn known_prefix(segments: &[Segment]) -> usize {
    segments
        .iter()
        .position(|s| {
            s.motion.moves()
                && (s.to.known().is_none()
                    || (s.from.known().is_none() && s.motion != Motion::Rapid))
        })
        .unwrap_or(segments.len())
}

/// `segments` normalised without the straight moves (rapids and feeds, after rapids merged)
/// that go no more than `tol` along each axis: rs274 prints four decimals of a radius, so
/// that a move shorter than a printed step is nothing on its side (a G71 layer's retract
/// over the last 0.00005 mm of material), and at the judge's tolerance such a move is
/// nothing on either side. So is a run of rapids that ends where it began (to the
/// reference point and back), which LinuxCNC prints and ncthread may not know.
pub fn as_printed(segments: &[Segment], tol: Length) -> Vec<Segment> {
    let mut out = super::normalise(segments);
    out.retain(|s| {
        let short = |a: Option<Length>, b: Option<Length>| match (a, b) {
            (Some(a), Some(b)) => (a - b).abs() <= tol,
            _ => false,
        };
        !(matches!(s.motion, Motion::Rapid | Motion::Feed { .. })
            && short(s.from.x, s.to.x)
            && short(s.from.z, s.to.z))
    });
    super::normalise(&out)
}

/// `segments` without a first rapid from an unknown place to X0 Z0 (see `judge`).
///
/// The first move, after the events before it: a G0 or a G1 from nowhere to rs274's start
/// point, X0 Z0, is also what rs274 prints for a `G1` without axes before any move (LinuxCNC
/// moves to where it stands, which it takes for X0 Z0), where ncthread, not knowing the
/// place, moves nowhere. Left out on both sides, like the rapid; after such a feed, the state
/// changes either side of it are one run (normalised again), as on ncthread's side, which
/// never had it. (Not after a rapid: rs274's first rapid may be two merged, the second a
/// `G28` that ncthread's side holds as a move to a place it does not know.)
fn without_rapid_to_rs274_start(mut segments: Vec<Segment>) -> Vec<Segment> {
    if let Some(i) = segments.iter().position(|s| s.motion.moves())
        && matches!(segments[i].motion, Motion::Rapid | Motion::Feed { .. })
        && segments[i].from == Pos::UNKNOWN
        && segments[i].to == Pos::new(Length::ZERO, Length::ZERO)
    {
        let feed = matches!(segments.remove(i).motion, Motion::Feed { .. });
        if feed {
            return super::normalise(&segments);
        }
    }
    segments
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The judge runs a program without its user M codes (the standalone rs274 has no
    /// configuration to run them), and leaves every other M code, comment and name alone.
    #[test]
    fn user_m_codes_are_blanked_for_the_judge() {
        let program = "M131\nG0 X1 m 142 (M150)\nM3 M99 M200 M131.5 ; M110\no<m120> call\n";
        assert_eq!(
            without_user_m_codes(program),
            "    \nG0 X1       (M150)\nM3 M99 M200 M131.5 ; M110\no<m120> call\n"
        );
        assert!(matches!(
            without_user_m_codes("G0 X1\n"),
            std::borrow::Cow::Borrowed(_)
        ));
    }

    /// A G92 offset set in millimetres stays those millimetres after G20: LinuxCNC's canon
    /// layer holds it in the machine's units, and rs274 prints the later moves in inches
    /// without it (found by the fuzz harness, `corpus/fuzz/iso/g20-after-a-g92-offset.ngc`).
    #[test]
    fn an_axis_offset_keeps_the_unit_it_was_set_in() {
        let canon = without_axis_offsets([
            Canon::AxisOffset { x: 40.0, z: 10.0 },
            Canon::Inches(true),
            Canon::Feed { x: -12.0, z: -20.0 },
        ]);
        match canon[1] {
            Canon::Feed { x, z } => {
                assert!((x - (-12.0 + 40.0 / 25.4)).abs() < 1e-9, "{x}");
                assert!((z - (-20.0 + 10.0 / 25.4)).abs() < 1e-9, "{z}");
            }
            ref other => panic!("{other:?}"),
        }
    }

    /// G18 goes first, or after the `%` that opens a program (blank lines before it kept), so
    /// that rs274 still takes the `%` for the program's opening.
    #[test]
    fn a_lathe_starts_in_g18() {
        assert_eq!(as_lathe_starts("G0 X1\nM2\n"), "G18\nG0 X1\nM2\n");
        assert_eq!(as_lathe_starts("%\nG0 X1\n%\n"), "%\nG18\nG0 X1\n%\n");
        assert_eq!(
            as_lathe_starts("\n  \r\n % \r\nG0 X1\r\n%\r\n"),
            "\n  \r\n % \r\nG18\nG0 X1\r\n%\r\n"
        );
        assert_eq!(as_lathe_starts("\nG0 X1\n"), "\nG18\nG0 X1\n");
        assert_eq!(as_lathe_starts("M2"), "G18\nM2");
    }

    /// A run killed at its limit takes its children with it: a wrapper's rs274 that loops
    /// for ever does not live on (SIGKILL does not pass through a shell).
    #[cfg(target_os = "linux")]
    #[test]
    fn a_run_killed_at_the_limit_kills_its_children() {
        let dir = tempfile::tempdir().unwrap();
        let pid_file = dir.path().join("pid");
        let mut command = Command::new("sh");
        command
            .arg("-c")
            .arg(format!("sleep 30 & echo $! > {}; wait", pid_file.display()));
        let ran = run_bounded(command, std::time::Duration::from_millis(500));
        assert!(ran.is_err(), "{ran:?}");
        let pid = std::fs::read_to_string(&pid_file).unwrap();
        // Gone, or a zombie waiting to be reaped: no longer running.
        std::thread::sleep(std::time::Duration::from_millis(100));
        let stat =
            std::fs::read_to_string(format!("/proc/{}/stat", pid.trim())).unwrap_or_default();
        let state = stat
            .rsplit(')')
            .next()
            .unwrap_or("")
            .trim_start()
            .chars()
            .next();
        assert!(matches!(state, None | Some('Z') | Some('X')), "{stat}");
    }

    /// A stand-in for rs274 in `dir`: a shell script, copied into place by another process so
    /// that no file this process has open for writing is executed ("text file busy").
    #[cfg(unix)]
    fn fake_rs274(dir: &Path, script: &str) -> PathBuf {
        let text = dir.join("fake.sh");
        std::fs::write(&text, script).unwrap();
        let bin = dir.join("rs274");
        let status = Command::new("sh")
            .arg("-c")
            .arg("cp \"$0\" \"$1\" && chmod +x \"$1\"")
            .arg(&text)
            .arg(&bin)
            .status()
            .unwrap();
        assert!(status.success());
        bin
    }

    #[cfg(unix)]
    #[test]
    fn the_binary_runs_in_a_home_of_its_own() {
        let dir = tempfile::tempdir().unwrap();
        // Called as `rs274 -t TOOLS -g FILE`: HOME must be the run's own folder, FILE's.
        let bin = fake_rs274(
            dir.path(),
            "#!/bin/sh\n\
             [ \"$HOME\" = \"$(dirname \"$4\")\" ] || { echo \"HOME is $HOME\" >&2; exit 1; }\n\
             echo '    1 N..... PROGRAM_END()'\n",
        );
        assert_eq!(Interpreter::Binary(bin).run("M2\n"), Ok(Vec::new()));
    }

    /// A stand-in that dies of SIGBUS on its first `crashes` runs (counted in a file beside it).
    #[cfg(unix)]
    fn crashing_rs274(dir: &Path, crashes: u32) -> PathBuf {
        fake_rs274(
            dir,
            &format!(
                "#!/bin/sh\n\
                 n=$(cat \"$0.runs\" 2>/dev/null || echo 0); n=$((n + 1)); echo $n >\"$0.runs\"\n\
                 if [ $n -le {crashes} ]; then ulimit -c 0; kill -s BUS $$; fi\n\
                 echo '    1 N..... STRAIGHT_TRAVERSE(9.0000, 0.0000, 4.5000, 0.0000, 0.0000, 0.0000)'\n\
                 echo '    2 N..... PROGRAM_END()'\n"
            ),
        )
    }

    #[cfg(unix)]
    fn runs(bin: &Path) -> String {
        std::fs::read_to_string(bin.with_extension("runs")).unwrap_or_default()
    }

    #[cfg(unix)]
    #[test]
    fn a_run_killed_by_a_signal_is_run_again() {
        let dir = tempfile::tempdir().unwrap();
        let bin = crashing_rs274(dir.path(), TRIES - 1);
        assert_eq!(
            Interpreter::Wrapper(bin.clone()).run("M2\n"),
            Ok(vec![Canon::Traverse { x: 18.0, z: 4.5 }])
        );
        assert_eq!(runs(&bin).trim(), TRIES.to_string());
    }

    #[cfg(unix)]
    #[test]
    fn a_run_killed_every_time_names_the_signal() {
        let dir = tempfile::tempdir().unwrap();
        let bin = crashing_rs274(dir.path(), u32::MAX);
        let e = Interpreter::Wrapper(bin.clone()).run("M2\n").unwrap_err();
        assert_eq!(
            e,
            RunError::Killed {
                signal: libc::SIGBUS,
                tries: TRIES
            }
        );
        assert!(e.is_crash());
        assert!(
            e.to_string().starts_with(&format!(
                "rs274 was killed by signal {} (SIGBUS) on each of 3 runs",
                libc::SIGBUS
            )),
            "{e}"
        );
        assert_eq!(runs(&bin).trim(), TRIES.to_string());
        // A refusal is no crash, and is not run again.
        let dir = tempfile::tempdir().unwrap();
        let bin = fake_rs274(
            dir.path(),
            "#!/bin/sh\necho run >>\"$0.runs\"\necho 'Unknown g code' >&2\nexit 1\n",
        );
        let e = Interpreter::Wrapper(bin.clone()).run("G999\n").unwrap_err();
        assert_eq!(
            e,
            RunError::Refused("rs274 exit Some(1): Unknown g code".into())
        );
        assert!(!e.is_crash());
        assert_eq!(runs(&bin), "run\n");
    }

    #[test]
    fn reads_rs274_lines() {
        assert_eq!(
            parse_canon(
                "   15 N..... STRAIGHT_TRAVERSE(9.0000, 0.0000, 4.5000, 0.0000, 0.0000, 0.0000)"
            ),
            Some(Canon::Traverse { x: 18.0, z: 4.5 })
        );
        assert_eq!(
            parse_canon("   20 N..... START_SPEED_FEED_SYNC(3.000000,0)"),
            Some(Canon::SyncStart { k: 3.0 })
        );
        assert_eq!(parse_canon("   16 N..... COMMENT(\"x\")"), None);
        // A block number longer than its column runs into the call's name.
        assert_eq!(
            parse_canon("   42 N19999999999999999999930START_SPEED_FEED_SYNC(1.250000,0)"),
            Some(Canon::SyncStart { k: 1.25 })
        );
        assert_eq!(parse_canon("   16 N..... STRAIGHT_FEED()"), None);
    }

    #[test]
    fn a_retract_shorter_than_a_printed_step_is_no_move() {
        // Fuzz run 13: ncthread's G71 layer retracts 0.0001 mm on the diameter where rs274
        // prints a traverse to where the tool stands, then both feed on.
        let feed = Motion::Feed {
            feed: Length::from_mm_f64(0.2),
            per_minute: false,
        };
        let at = |x: f64, z: f64| Pos::new(Length::from_mm_f64(x), Length::from_mm_f64(z));
        let seg = |motion, from, to| Segment {
            motion,
            from,
            to,
            line: 1,
            pass: None,
        };
        let ours = [
            seg(Motion::Rapid, Pos::UNKNOWN, at(17.0, -5.0)),
            seg(feed, at(17.0, -5.0), at(17.0, -5.0273)),
            seg(Motion::Rapid, at(17.0, -5.0273), at(17.0001, -5.0273)),
            seg(feed, at(17.0001, -5.0273), at(25.9235, -8.0341)),
        ];
        let canon = [
            Canon::FeedPerRev(true),
            Canon::FeedRate(0.2),
            Canon::Traverse { x: 17.0, z: -5.0 },
            Canon::Feed {
                x: 17.0,
                z: -5.0273,
            },
            Canon::Traverse {
                x: 17.0,
                z: -5.0273,
            },
            Canon::Feed {
                x: 25.9236,
                z: -8.0341,
            },
        ];
        assert!(
            matches!(judge(&ours, &canon), Judgement::Agrees { .. }),
            "{:?}",
            judge(&ours, &canon)
        );
        // A retract the tolerance sees is a move.
        let mut longer = ours;
        longer[2].to = at(17.0011, -5.0273);
        longer[3].from = longer[2].to;
        assert!(matches!(judge(&longer, &canon), Judgement::Differs(_)));
    }

    #[test]
    fn a_chain_keeps_its_phase_and_a_radial_move_is_named() {
        // G76's entry: radial in at K 1.644878 from the index pulse, then the taper and the
        // thread at K 1.5 without a new index wait.
        let canon = [
            Canon::SpindleClockwise,
            Canon::Traverse { x: 21.4, z: 4.8868 },
            Canon::SyncStart { k: 1.644878 },
            Canon::Feed { x: 20.4, z: 4.8868 },
            Canon::Feed { x: 18.6, z: 2.8868 },
            Canon::SyncStart { k: 1.5 },
            Canon::Feed {
                x: 18.6,
                z: -17.604,
            },
            Canon::SyncStop,
        ];
        let s: Vec<Segment> = segments(&canon)
            .into_iter()
            .filter(|s| s.motion.moves())
            .collect();
        assert!(matches!(
            s[1].motion,
            Motion::SyncRadial {
                start_angle: Some(Angle::ZERO),
                ..
            }
        ));
        let phase = |seg: &Segment| match seg.motion {
            Motion::Sync { phase, .. } => phase,
            _ => None,
        };
        // Both synchronised moves lie on one helix.
        assert_eq!(phase(&s[2]), phase(&s[3]));
    }
}

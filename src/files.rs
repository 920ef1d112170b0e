//! A shop's archive: which files of a folder are programs, and which machine profile each
//! program uses.
//!
//! Folders are walked as ripgrep walks them (the `ignore` crate): hidden entries are left out,
//! an `.ncthreadignore` (gitignore syntax) in a folder leaves out what it names below it,
//! `--glob`/`--iglob` choose files by their path below the folder (`!` leaves out). Without a
//! positive glob, a file is a program when its extension is one its dialect's files have
//! (case-insensitive); what is not a program is listed with the reason, never failed.
//!
//! The profile of a program is the first of: the one the command line names; a sidecar
//! `STEM.profile.toml` beside the program (`STEM` its file name without the extension); the
//! nearest `ncthread.toml` in its folder or a folder above it (as `rustfmt.toml` is found).

use std::path::{Path, PathBuf};

pub use crate::diag::io::{io_error, io_reason};

/// What a walk takes.
#[derive(Clone, Debug, Default)]
pub struct Selection {
    /// Globs on the path below the folder; `!GLOB` leaves out what it matches.
    pub globs: Vec<String>,
    /// The same, matched case-insensitively.
    pub iglobs: Vec<String>,
    /// The extensions of program files (without the dot), when no positive glob is given.
    pub extensions: Vec<&'static str>,
}

impl Selection {
    /// The positive globs, each with whether it ignores case.
    fn positive(&self) -> impl Iterator<Item = (&str, bool)> {
        let globs = self.globs.iter().map(|g| (g.as_str(), false));
        let iglobs = self.iglobs.iter().map(|g| (g.as_str(), true));
        globs.chain(iglobs).filter(|(g, _)| !g.starts_with('!'))
    }
}

/// What a walk found: a program to read, or a file left out and why.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Verdict {
    Program,
    Skip(String),
}

/// A file below the walked folder.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Found {
    /// Relative to the folder.
    pub rel: PathBuf,
    pub verdict: Verdict,
}

/// A walk's files (sorted by path) and the positive globs that matched no file.
#[derive(Clone, Debug, Default)]
pub struct Walk {
    pub files: Vec<Found>,
    pub unmatched: Vec<String>,
}

impl Walk {
    pub fn programs(&self) -> impl Iterator<Item = &Path> {
        self.files
            .iter()
            .filter(|f| f.verdict == Verdict::Program)
            .map(|f| f.rel.as_path())
    }
}

fn overrides(root: &Path, globs: &[(&str, bool)]) -> Result<ignore::overrides::Override, String> {
    let mut builder = ignore::overrides::OverrideBuilder::new(root);
    for &(glob, nocase) in globs {
        builder
            .case_insensitive(nocase)
            .and_then(|b| b.add(glob))
            .map_err(|e| format!("--glob {glob}: {e}"))?;
    }
    builder.build().map_err(|e| format!("--glob: {e}"))
}

/// Walks `root`: every file, sorted by path, each a program or left out with a reason.
pub fn walk(root: &Path, selection: &Selection) -> Result<Walk, String> {
    // Every glob, the `!` ones last: a file left out stays out, whatever chose it.
    let mut all: Vec<(&str, bool)> = selection
        .globs
        .iter()
        .map(|g| (g.as_str(), false))
        .chain(selection.iglobs.iter().map(|g| (g.as_str(), true)))
        .collect();
    all.sort_by_key(|(g, _)| g.starts_with('!'));
    let chosen = overrides(root, &all)?;
    let by_extension = selection.positive().next().is_none();
    let mut builder = ignore::WalkBuilder::new(root);
    builder
        .standard_filters(false)
        .hidden(true)
        .follow_links(false)
        .add_custom_ignore_filename(".ncthreadignore")
        .overrides(chosen)
        .sort_by_file_name(|a, b| a.cmp(b));
    let mut files = Vec::new();
    for entry in builder.build() {
        let entry = entry.map_err(|e| match e.io_error() {
            Some(io) => io_error("read", root.display(), io),
            None => format!("cannot read {}: {e}", root.display()),
        })?;
        let path = entry.path();
        // A link to a file is followed; a link to a folder is not (no cycles), and is said.
        let is_file = entry.file_type().is_some_and(|t| t.is_file())
            || entry.path_is_symlink() && path.is_file();
        let rel = path.strip_prefix(root).unwrap_or(path).to_path_buf();
        if !is_file {
            if entry.path_is_symlink() {
                let why = if path.exists() {
                    "a link to a folder (not followed)"
                } else {
                    "a link to nothing"
                };
                files.push(Found {
                    rel,
                    verdict: Verdict::Skip(why.into()),
                });
            }
            continue;
        }
        let verdict = if by_extension {
            by_name(&rel, &selection.extensions)
        } else {
            Verdict::Program
        };
        let verdict = match verdict {
            Verdict::Program => by_content(path, false),
            // A FANUC control names its programs `O1002`: a file without an extension is taken
            // when its text is a program.
            Verdict::Skip(why) if by_extension && rel.extension().is_none() => {
                match by_content(path, true) {
                    Verdict::Program => Verdict::Program,
                    Verdict::Skip(not) if not == NOT_PROGRAM_TEXT => Verdict::Skip(why),
                    skip => skip,
                }
            }
            skip => skip,
        };
        files.push(Found { rel, verdict });
    }
    // A glob that matched no file is worth saying: a typo chooses nothing.
    let mut unmatched = Vec::new();
    for (glob, nocase) in selection.positive() {
        let one = overrides(root, &[(glob, nocase)])?;
        if !files
            .iter()
            .any(|f| one.matched(root.join(&f.rel), false).is_whitelist())
        {
            unmatched.push(glob.to_string());
        }
    }
    Ok(Walk { files, unmatched })
}

/// Whether a file's name says it is a program.
fn by_name(rel: &Path, extensions: &[&str]) -> Verdict {
    let name = rel
        .file_name()
        .map(|n| n.to_string_lossy().to_lowercase())
        .unwrap_or_default();
    if name == "ncthread.toml" || name.ends_with(".profile.toml") {
        return Verdict::Skip("a machine profile".into());
    }
    match rel.extension().map(|e| e.to_string_lossy().to_lowercase()) {
        Some(e) if extensions.contains(&e.as_str()) => Verdict::Program,
        Some(e) => Verdict::Skip(format!(
            "not a program file (.{e}; programs are {}; --glob takes others)",
            list(extensions)
        )),
        None => Verdict::Skip(format!(
            "not a program file (no extension, and its text is not a program; programs are {}; --glob takes others)",
            list(extensions)
        )),
    }
}

fn list(extensions: &[&str]) -> String {
    extensions
        .iter()
        .map(|e| format!(".{e}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Why [`by_content`] did not take a file's text as a program.
const NOT_PROGRAM_TEXT: &str = "its text is not a program";

/// Whether a file's bytes are a program's: not empty, not binary; and with `as_text` (a file
/// whose name does not say it), text whose lines are a program's ([`looks_like_program`]).
fn by_content(path: &Path, as_text: bool) -> Verdict {
    use std::io::Read as _;
    let mut head = Vec::with_capacity(8192);
    let read = std::fs::File::open(path).and_then(|f| f.take(8192).read_to_end(&mut head));
    if let Err(e) = read {
        return Verdict::Skip(io_error("read", path.display(), &e));
    }
    match content_verdict(&head) {
        Verdict::Program if as_text => {
            // The ASCII of it: every dialect's words and marks are ASCII.
            let text: String = head
                .iter()
                .map(|&b| if b.is_ascii() { b as char } else { '?' })
                .collect();
            if looks_like_program(&text) {
                Verdict::Program
            } else {
                Verdict::Skip(NOT_PROGRAM_TEXT.into())
            }
        }
        verdict => verdict,
    }
}

/// Whether a text (a file's first 8 KB) is a program: at least three of its lines are blocks
/// (a word's letter and its number first: `N10`, `G0`, `X1.`, `O1002`, `#1=`, `o<sub>`), no
/// more than one line in ten is something else (comment lines, `%` and blank lines aside),
/// and a line carries a dialect's mark (what `--from auto` tells dialects by). Prose, a
/// list of numbers or a script is none.
pub fn looks_like_program(text: &str) -> bool {
    let (mut blocks, mut other) = (0usize, 0usize);
    let lines: Vec<&str> = text.lines().collect();
    // The last line of a head cut at 8 KB may be cut short.
    let whole = if text.len() >= 8192 {
        &lines[..lines.len().saturating_sub(1)]
    } else {
        &lines[..]
    };
    for line in whole {
        let line = line.trim();
        let line = line.strip_prefix('/').unwrap_or(line).trim_start();
        if line.is_empty() || line.starts_with(['%', '(', ';', '"']) {
            continue;
        }
        let bytes = line.as_bytes();
        let mut rest = bytes.iter().skip(1).skip_while(|b| **b == b' ');
        let block = match bytes[0] {
            b'#' => matches!(bytes.get(1), Some(b'0'..=b'9' | b'<' | b'[')),
            b'o' | b'O' if bytes.get(1) == Some(&b'<') => true,
            c if c.is_ascii_alphabetic() => matches!(
                rest.next(),
                Some(b'0'..=b'9' | b'.' | b'-' | b'+' | b'#' | b'[')
            ),
            _ => false,
        };
        if block {
            blocks += 1;
        } else {
            other += 1;
        }
    }
    blocks >= 3 && other * 10 <= blocks + other && crate::dialect::detect::has_marks(text)
}

/// The verdict on a file's first bytes (at most 8 KB).
pub fn content_verdict(head: &[u8]) -> Verdict {
    let (body, _) = crate::text::split_eof_mark(head);
    if body.iter().all(|b| b.is_ascii_whitespace()) {
        return Verdict::Skip("empty".into());
    }
    if crate::text::binary_evidence(body).is_some() {
        return Verdict::Skip("binary (NUL or control bytes): not a program".into());
    }
    Verdict::Program
}

/// The profile a program uses when the command line names none: a sidecar
/// `STEM.profile.toml`, else the nearest `ncthread.toml` in its folder or above.
pub fn discover_profile(program: &Path) -> Option<PathBuf> {
    let stem = program.file_stem()?;
    let folder = program.parent().unwrap_or(Path::new(""));
    let mut sidecar = stem.to_os_string();
    sidecar.push(".profile.toml");
    let sidecar = folder.join(sidecar);
    if sidecar.is_file() {
        return Some(sidecar);
    }
    // The folders really above the program: `..` resolved, a bare file name in `.`.
    let folder = if folder.as_os_str().is_empty() {
        Path::new(".")
    } else {
        folder
    };
    let start = std::fs::canonicalize(folder).ok()?;
    start
        .ancestors()
        .map(|dir| dir.join("ncthread.toml"))
        .find(|p| p.is_file())
}

/// The absolute, symlink-free form of `path`, which need not exist yet: its deepest existing
/// ancestor canonicalised, then the rest.
pub fn resolve(path: &Path) -> std::io::Result<PathBuf> {
    let absolute = std::path::absolute(path)?;
    let mut existing = absolute.as_path();
    let mut rest = Vec::new();
    while !existing.exists() {
        match (existing.parent(), existing.file_name()) {
            (Some(parent), Some(name)) => {
                rest.push(name.to_owned());
                existing = parent;
            }
            _ => break,
        }
    }
    let mut resolved = std::fs::canonicalize(existing)?;
    resolved.extend(rest.iter().rev());
    Ok(resolved)
}

/// Why [`write_atomically`] wrote nothing.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum WriteError {
    /// The file exists and `force` was not given.
    Exists,
    /// This file could not be written (why, in [`io_error`]'s words).
    Failed(String),
    /// Nothing more can be written there: the disk is full, the quota used up, the file
    /// system read-only ([`stops_every_write`]). A batch stops rather than fail every file.
    Fatal(String),
}

impl WriteError {
    /// The error of `action` on `path`: [`WriteError::Fatal`] when it stops every write.
    pub fn of(action: &str, path: impl std::fmt::Display, e: &std::io::Error) -> WriteError {
        let why = io_error(action, path, e);
        if stops_every_write(e) {
            WriteError::Fatal(why)
        } else {
            WriteError::Failed(why)
        }
    }
}

/// Whether an I/O error will recur for every file written to the same place: no space left
/// on the device (ENOSPC), the disk quota exceeded (EDQUOT), a read-only file system (EROFS).
pub fn stops_every_write(e: &std::io::Error) -> bool {
    use std::io::ErrorKind;
    matches!(
        e.kind(),
        ErrorKind::StorageFull | ErrorKind::QuotaExceeded | ErrorKind::ReadOnlyFilesystem
    )
}

/// Writes `bytes` to a temporary file beside `path` and renames it into place, so that no
/// reader sees half a file (without replacing an existing file unless `force`). The file
/// gets the mode a new file gets (0666 less the umask), as `File::create` would give it.
/// With `guard`, a folder inside it is refused (a source tree).
pub fn write_atomically(
    path: &Path,
    bytes: &[u8],
    force: bool,
    guard: Option<&Path>,
) -> Result<(), WriteError> {
    write_atomically_with(path, force, guard, |file| file.write_all(bytes))
}

/// [`write_atomically`] of what `fill` writes (a large output copied from its temporary
/// file).
pub fn write_atomically_with(
    path: &Path,
    force: bool,
    guard: Option<&Path>,
    fill: impl FnOnce(&mut dyn std::io::Write) -> std::io::Result<()>,
) -> Result<(), WriteError> {
    use std::io::Write as _;
    let parent = folder_of(path);
    // The source tree is checked before any folder is made.
    if let Some(guard) = guard {
        match resolve(parent) {
            Ok(p) if p.starts_with(guard) => {
                return Err(WriteError::Failed(format!(
                    "{} is inside the source tree; ncthread never writes there",
                    parent.display()
                )));
            }
            Ok(_) => {}
            Err(e) => {
                return Err(WriteError::Failed(io_error("read", parent.display(), &e)));
            }
        }
    }
    std::fs::create_dir_all(parent).map_err(|e| WriteError::of("create", parent.display(), &e))?;
    let failed = |e: std::io::Error| WriteError::of("write", path.display(), &e);
    let mut builder = tempfile::Builder::new();
    builder.prefix(".ncthread-");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt as _;
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    let mut tmp = builder.tempfile_in(parent).map_err(failed)?;
    fill(&mut tmp).and_then(|()| tmp.flush()).map_err(failed)?;
    let persisted = if force {
        tmp.persist(path).map(drop)
    } else {
        tmp.persist_noclobber(path).map(drop)
    };
    match persisted {
        Ok(()) => Ok(()),
        Err(e) if e.error.kind() == std::io::ErrorKind::AlreadyExists => Err(WriteError::Exists),
        Err(e) => Err(failed(e.error)),
    }
}

/// The folder in which a large output's temporary file (its spool) is made, when set: the
/// folder of the file the output goes to ([`spool_beside`]).
static SPOOL_FOLDER: std::sync::Mutex<Option<PathBuf>> = std::sync::Mutex::new(None);

/// The spools [`spool_file`] made beside a file, by device and inode, with their folder:
/// only these are linked into place ([`link_into_place`]).
#[cfg(target_os = "linux")]
static BESIDE: std::sync::Mutex<Vec<(u64, u64, PathBuf)>> = std::sync::Mutex::new(Vec::new());

/// The folder of `file` (`.` for a bare name).
fn folder_of(file: &Path) -> &Path {
    match file.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// The help of a refusal for a temporary file that failed (a full disk): where room is
/// needed.
pub(crate) const MAKE_ROOM: &str = "nothing is written; make room in the output's folder and the temporary folder (TMPDIR), and convert again";

/// Has the temporary files of the outputs made from now on in this process (until it is
/// called again) made beside `file` (`None`: in the system's temporary folder, the default),
/// so that an output becomes `file` by a link and a rename rather than a copy
/// ([`crate::text::Encoded::link_into_place`], issue 34): on Linux, where the folder's
/// filesystem makes unnamed files (`O_TMPFILE`; a network share does not); elsewhere, and
/// where it cannot, in the system's temporary folder as before. The file is unnamed either
/// way: nothing is left if the process stops. The CLI's `convert -o FILE` sets it; `batch`,
/// whose outputs go to many folders at once, does not.
pub fn spool_beside(file: Option<&Path>) {
    if let Ok(mut set) = SPOOL_FOLDER.lock() {
        *set = file.map(|f| folder_of(f).to_path_buf());
    }
}

/// An unnamed temporary file for a writer's text: in the folder [`spool_beside`] set (Linux,
/// `O_TMPFILE` with mode 0o666, so that the umask or the folder's default ACL gives it the
/// mode, group and label a file written there gets), else in the system's temporary folder.
pub(crate) fn spool_file() -> std::io::Result<std::fs::File> {
    #[cfg(target_os = "linux")]
    {
        use std::os::unix::fs::{MetadataExt as _, OpenOptionsExt as _};
        let folder = SPOOL_FOLDER.lock().ok().and_then(|f| f.clone());
        if let Some(folder) = folder
            && let Ok(file) = std::fs::OpenOptions::new()
                .read(true)
                .write(true)
                .mode(0o666)
                .custom_flags(libc::O_TMPFILE)
                .open(&folder)
            && let Ok(meta) = file.metadata()
            && let Ok(mut beside) = BESIDE.lock()
        {
            beside.push((meta.dev(), meta.ino(), folder));
            return Ok(file);
        }
    }
    tempfile::tempfile()
}

/// Makes `file` — a whole spool that [`spool_file`] made in `path`'s folder, still unnamed —
/// the file at `path`, replacing it: linked under a temporary name beside it (`linkat`
/// through `/proc/self/fd`, the `open(2)` recipe for `O_TMPFILE`) and renamed into place, as
/// [`write_atomically_with`] renames the copy it writes. `Ok(false)`, and nothing done, for
/// any other file (made elsewhere, or with a name) or where it cannot be linked (no `/proc`,
/// not Linux): the caller copies it then. A failed rename is an error, as it is for a copy.
#[cfg(target_os = "linux")]
pub(crate) fn link_into_place(file: &std::fs::File, path: &Path) -> Result<bool, WriteError> {
    use std::os::unix::ffi::OsStrExt as _;
    use std::os::unix::fs::MetadataExt as _;
    use std::os::unix::io::AsRawFd as _;
    let folder = folder_of(path);
    let Ok(meta) = file.metadata() else {
        return Ok(false);
    };
    // Only an unnamed spool made in this folder: a named file would get a second name, and
    // one made elsewhere (the system's temporary folder) has that folder's mode and group.
    let made_here = BESIDE.lock().is_ok_and(|beside| {
        beside
            .iter()
            .any(|(dev, ino, f)| (*dev, *ino) == (meta.dev(), meta.ino()) && f == folder)
    });
    if !made_here || meta.nlink() != 0 {
        return Ok(false);
    }
    let Ok(from) = std::ffi::CString::new(format!("/proc/self/fd/{}", file.as_raw_fd())) else {
        return Ok(false);
    };
    let linked = tempfile::Builder::new()
        .prefix(".ncthread-")
        .make_in(folder, |name| {
            let to = std::ffi::CString::new(name.as_os_str().as_bytes())
                .map_err(|_| std::io::Error::from(std::io::ErrorKind::InvalidInput))?;
            // SAFETY: two NUL-terminated paths that live through the call.
            let done = unsafe {
                libc::linkat(
                    libc::AT_FDCWD,
                    from.as_ptr(),
                    libc::AT_FDCWD,
                    to.as_ptr(),
                    libc::AT_SYMLINK_FOLLOW,
                )
            };
            if done == 0 {
                Ok(())
            } else {
                Err(std::io::Error::last_os_error())
            }
        });
    let Ok(linked) = linked else {
        return Ok(false);
    };
    if let Ok(mut beside) = BESIDE.lock() {
        beside.retain(|(dev, ino, _)| (*dev, *ino) != (meta.dev(), meta.ino()));
    }
    linked
        .persist(path)
        .map(|_| true)
        .map_err(|e| WriteError::of("write", path.display(), &e.error))
}

/// [`link_into_place`] where there is no `O_TMPFILE`: never (the caller copies).
#[cfg(not(target_os = "linux"))]
pub(crate) fn link_into_place(_file: &std::fs::File, _path: &Path) -> Result<bool, WriteError> {
    Ok(false)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A spool made beside a file becomes that file by [`link_into_place`], replacing it,
    /// with the mode a written file gets there; no other file is linked (one made in another
    /// folder, or not by [`spool_file`], or with a name), and nothing else is left in the
    /// folder.
    #[cfg(target_os = "linux")]
    #[test]
    fn a_spool_is_linked_into_place() {
        use std::io::Write as _;
        use std::os::unix::fs::PermissionsExt as _;
        let dir = tempfile::tempdir().unwrap();
        let written = dir.path().join("written.ngc");
        write_atomically_with(&written, true, None, |to| to.write_all(b"x")).unwrap();
        let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
        let target = dir.path().join("out.ngc");
        std::fs::write(&target, "older").unwrap();
        let elsewhere = tempfile::tempdir().unwrap();
        spool_beside(Some(&elsewhere.path().join("x.ngc")));
        let mut made_elsewhere = spool_file().unwrap();
        spool_beside(Some(&target));
        let mut beside = spool_file().unwrap();
        spool_beside(None);
        let mut not_a_spool = tempfile::tempfile_in(dir.path()).unwrap();
        for other in [&mut made_elsewhere, &mut not_a_spool] {
            other.write_all(b"G0 X2\n").unwrap();
            assert!(!link_into_place(other, &target).unwrap());
        }
        let named = std::fs::File::open(&written).unwrap();
        assert!(!link_into_place(&named, &target).unwrap());
        assert_eq!(std::fs::read_to_string(&target).unwrap(), "older");
        beside.write_all(b"G0 X1\n").unwrap();
        assert!(link_into_place(&beside, &target).unwrap());
        assert_eq!(std::fs::read_to_string(&target).unwrap(), "G0 X1\n");
        assert_eq!(mode(&target), mode(&written));
        let mut names: Vec<_> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().into_string().unwrap())
            .collect();
        names.sort();
        assert_eq!(names, ["out.ngc", "written.ngc"]);
    }

    #[test]
    fn content_tells_programs_from_empty_and_binary_files() {
        assert_eq!(content_verdict(b"N10 G00 X1.\r\n\x1a"), Verdict::Program);
        assert_eq!(content_verdict(b"G0 X1\n\0\0\0"), Verdict::Program);
        assert!(matches!(content_verdict(b"  \r\n"), Verdict::Skip(r) if r == "empty"));
        assert!(matches!(content_verdict(b"\x1a"), Verdict::Skip(r) if r == "empty"));
        assert!(
            matches!(content_verdict(b"MZ\x90\0\x03\0\0\0"), Verdict::Skip(r) if r.starts_with("binary"))
        );
        // Legacy encodings' high bytes are text.
        assert_eq!(content_verdict(b"\"ROZTO\xC8EN\xCD\n"), Verdict::Program);
    }

    #[test]
    fn a_full_disk_stops_every_write() {
        use std::io::ErrorKind;
        for kind in [
            ErrorKind::StorageFull,
            ErrorKind::QuotaExceeded,
            ErrorKind::ReadOnlyFilesystem,
        ] {
            assert!(stops_every_write(&std::io::Error::from(kind)), "{kind:?}");
        }
        for kind in [ErrorKind::PermissionDenied, ErrorKind::NotFound] {
            assert!(!stops_every_write(&std::io::Error::from(kind)), "{kind:?}");
        }
        #[cfg(target_os = "linux")]
        {
            // ENOSPC, EDQUOT and EROFS as the kernel gives them.
            for errno in [28, 122, 30] {
                let e = std::io::Error::from_raw_os_error(errno);
                assert!(stops_every_write(&e), "{errno}: {e}");
            }
            // A real write to a full device.
            use std::io::Write as _;
            let e = std::fs::OpenOptions::new()
                .write(true)
                .open("/dev/full")
                .and_then(|mut f| f.write_all(b"N10 G00 X1.\n").and_then(|()| f.flush()))
                .expect_err("/dev/full is full");
            assert_eq!(
                WriteError::of("write", "out/P1.ngc", &e),
                WriteError::Fatal("cannot write out/P1.ngc: no space left on device".to_string())
            );
        }
    }

    #[test]
    fn io_errors_read_as_one_sentence() {
        let e = std::io::Error::from_raw_os_error(2);
        assert_eq!(
            io_error("read", "P1.NC", &e),
            "cannot read P1.NC: no such file or directory"
        );
        let e = std::io::Error::other("UTF-8 expected");
        assert_eq!(io_reason(&e), "UTF-8 expected");
    }

    #[test]
    fn a_text_without_an_extension_is_a_program_when_its_lines_are() {
        let fanuc = "%\nO1002 (THREAD M20X1.5)\nG21 G99\nG97 S500 M03\nG00 X22. Z5.\nG32 Z-20. F1.5\nG00 X30.\nM30\n%\n";
        assert!(looks_like_program(fanuc));
        let nc31 = "N0 M40\nN4 X10000 ~ *\nN5 Z5000 ~\nN11 Z-5200 ~ *\n";
        assert!(looks_like_program(nc31));
        let czech = "N10 G00 X26.618 Z3. \"ROZTOCENI\nN20 R04=120.0\nN30 G33 Z-9. FR10\nN40 M30\n";
        assert!(looks_like_program(czech));
        let iso = "o<thread> sub\n#1 = 5\nG33 Z-10 K1.5\no<thread> endsub\nM2\n";
        assert!(looks_like_program(iso));
        // Prose, even about G-code and with ( ) in it; a script; numbers; too little.
        let readme = "Programs of lathe 2 (the old one)\nG33 cuts a thread (see the manual)\nX is a diameter.\nAsk Jan before you run P0001.\n";
        assert!(!looks_like_program(readme));
        assert!(!looks_like_program(
            "#!/bin/sh\nrm -rf out\nncthread batch a b\n"
        ));
        assert!(!looks_like_program("1,2,3\n4,5,6\n7,8,9\n"));
        assert!(!looks_like_program("G0 X1 (A)\nM30\n"));
        // Blocks without any dialect's mark: no telling it from a list of codes.
        assert!(!looks_like_program("G0 X1\nG1 Z2\nG0 X3\n"));
    }

    #[test]
    fn names_tell_programs_profiles_and_other_files() {
        let ext = ["nc", "ngc"];
        assert_eq!(by_name(Path::new("a/P1.NC"), &ext), Verdict::Program);
        assert_eq!(by_name(Path::new("p.ngc"), &ext), Verdict::Program);
        assert!(
            matches!(by_name(Path::new("p.profile.toml"), &ext), Verdict::Skip(r) if r == "a machine profile")
        );
        assert!(
            matches!(by_name(Path::new("NCTHREAD.TOML"), &ext), Verdict::Skip(r) if r == "a machine profile")
        );
        assert!(
            matches!(by_name(Path::new("README"), &ext), Verdict::Skip(r) if r.contains("no extension"))
        );
        assert!(
            matches!(by_name(Path::new("p.BAK"), &ext), Verdict::Skip(r) if r.contains(".bak"))
        );
    }
}

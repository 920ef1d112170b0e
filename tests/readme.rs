//! README.md's examples run as printed. Every command line of a ```sh block, and every
//! `$ ` line of any block, runs in `sh` with the built `ncthread` first on the PATH, in a
//! temporary folder of its own that holds the repository's `corpus`, `docs` and `scripts`
//! (so an example that writes a file writes it there, and `~` is that folder too). A line
//! the README shows with output must print that output: its lines in order, `…` standing
//! for lines left out. A line whose shown output holds an error (`error[`) or a verdict of
//! `DIFFERENT` must exit 1; every other line must exit 0.
//!
//! Not run: `cargo` lines (the set-up commands; `cargo test` is this run), synopses (lines of
//! a plain ``` block without `$`), ```text blocks (an illustration, such as a batch run over
//! a shop's archive), and a line that needs a program this machine lacks (`rsvg-convert`,
//! `man`, `jq`), which is reported.

use std::path::{Path, PathBuf};
use std::process::Command;

/// One example: its command, the output the README shows (if any), its README line.
#[derive(Debug)]
struct Example {
    /// The code block it stands in: the examples of one block share their folder.
    block: usize,
    line: usize,
    command: String,
    shown: Vec<String>,
}

fn examples(readme: &str) -> Vec<Example> {
    // The code blocks: their info string and numbered lines.
    let mut blocks: Vec<(String, Vec<(usize, &str)>)> = Vec::new();
    let mut open: Option<(String, Vec<(usize, &str)>)> = None;
    for (i, text) in readme.lines().enumerate() {
        if let Some(info) = text.strip_prefix("```") {
            match open.take() {
                Some(b) => blocks.push(b),
                None => open = Some((info.trim().to_string(), Vec::new())),
            }
        } else if let Some((_, lines)) = &mut open {
            lines.push((i + 1, text));
        }
    }
    let mut out: Vec<Example> = Vec::new();
    for (block, (info, lines)) in blocks.into_iter().enumerate() {
        if !matches!(info.as_str(), "" | "sh" | "console") {
            continue;
        }
        // In a block with `$ ` lines only those are commands, and the lines under one are
        // its output; in a ```sh block without them every line is a command.
        let prompts = lines.iter().any(|(_, l)| l.starts_with("$ "));
        if !prompts && info != "sh" {
            continue;
        }
        let mut pending: Option<(usize, String)> = None;
        let mut last_prompt = false;
        for (n, text) in lines {
            if let Some((start, mut command)) = pending.take() {
                command.push('\n');
                command.push_str(text);
                if text.ends_with('\\') {
                    pending = Some((start, command));
                } else {
                    out.push(Example {
                        block,
                        line: start,
                        command,
                        shown: Vec::new(),
                    });
                }
                continue;
            }
            let command = if prompts {
                text.strip_prefix("$ ")
            } else {
                Some(text)
            };
            match command {
                Some(c) if c.ends_with('\\') => pending = Some((n, c.to_string())),
                Some(c) if !c.trim().is_empty() => {
                    out.push(Example {
                        block,
                        line: n,
                        command: c.to_string(),
                        shown: Vec::new(),
                    });
                    last_prompt = prompts;
                }
                Some(_) => {}
                None => {
                    if last_prompt && let Some(e) = out.last_mut() {
                        e.shown.push(text.to_string());
                    }
                }
            }
        }
    }
    out.retain(|e| !e.command.trim_start().starts_with("cargo "));
    out
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A folder for the examples: the repository's inputs linked in, outputs written here.
fn sandbox() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    for name in ["corpus", "docs", "scripts"] {
        std::os::unix::fs::symlink(root().join(name), dir.path().join(name)).unwrap();
    }
    dir
}

fn has_program(name: &str) -> bool {
    Command::new("sh")
        .arg("-c")
        .arg(format!("command -v {name}"))
        .output()
        .is_ok_and(|o| o.status.success())
}

/// Whether `shown` (with `…` for lines left out) appears in `printed`, line by line in order.
fn shows(printed: &str, shown: &[String]) -> Result<(), String> {
    let printed: Vec<&str> = printed.lines().map(str::trim_end).collect();
    let mut at = 0;
    let mut gap = false;
    for want in shown {
        let want = want.trim_end();
        if want == "…" {
            gap = true;
            continue;
        }
        let found = if gap {
            printed[at..]
                .iter()
                .position(|p| line_matches(p, want))
                .map(|k| at + k)
        } else {
            printed
                .get(at)
                .is_some_and(|p| line_matches(p, want))
                .then_some(at)
        };
        match found {
            Some(k) => at = k + 1,
            None => {
                return Err(format!(
                    "the line `{want}` is not printed where the README shows it"
                ));
            }
        }
        gap = false;
    }
    Ok(())
}

/// Whether a printed line is the line shown, a `…` inside it standing for any text.
fn line_matches(printed: &str, shown: &str) -> bool {
    let parts: Vec<&str> = shown.split('…').collect();
    let [first, middle @ .., last] = parts.as_slice() else {
        return printed == shown;
    };
    if !printed.starts_with(first) || printed.len() < first.len() + last.len() {
        return false;
    }
    let mut rest = &printed[first.len()..];
    for part in middle {
        match rest.find(part) {
            Some(k) => rest = &rest[k + part.len()..],
            None => return false,
        }
    }
    rest.ends_with(last)
}

#[test]
fn every_readme_example_runs_as_printed() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let all = examples(&readme);
    assert!(all.len() >= 30, "only {} examples found", all.len());
    let bin = PathBuf::from(env!("CARGO_BIN_EXE_ncthread"));
    let path = format!(
        "{}:{}",
        bin.parent().unwrap().display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let skip_rs274 = std::env::var_os("NCTHREAD_SKIP_RS274").is_some();
    let (mut ran, mut failures, mut skipped) = (0, Vec::new(), Vec::new());
    let mut folders: std::collections::HashMap<usize, tempfile::TempDir> = Default::default();
    for e in &all {
        let needs: Vec<&str> = ["rsvg-convert", "man -l", "jq"]
            .into_iter()
            .filter(|p| e.command.contains(p))
            .filter(|p| !has_program(p.split(' ').next().unwrap()))
            .collect();
        if !needs.is_empty() || (skip_rs274 && e.command.contains("--rs274")) {
            skipped.push(format!("README.md:{}: {}", e.line, e.command));
            continue;
        }
        let dir = folders.entry(e.block).or_insert_with(|| {
            let dir = sandbox();
            // The folders an example writes into under `~`, as a user's home has them.
            for sub in [
                ".local/share/bash-completion/completions",
                ".local/share/man",
            ] {
                std::fs::create_dir_all(dir.path().join(sub)).unwrap();
            }
            dir
        });
        let out = Command::new("sh")
            .arg("-c")
            .arg(&e.command)
            .current_dir(dir.path())
            .env("PATH", &path)
            .env("HOME", dir.path())
            .env("NO_COLOR", "1")
            // As a user types it: an example that needs rs274 names it.
            .env_remove("NCTHREAD_RS274")
            .env_remove("CLICOLOR_FORCE")
            .output()
            .unwrap();
        ran += 1;
        let printed = format!(
            "{}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
        let fails = e
            .shown
            .iter()
            .any(|l| l.contains("error[") || l.starts_with("DIFFERENT"));
        let want = if fails { 1 } else { 0 };
        let code = out.status.code();
        if code != Some(want) {
            failures.push(format!(
                "README.md:{}: `{}` exited {code:?}, not {want}:\n{printed}",
                e.line, e.command
            ));
            continue;
        }
        if let Err(why) = shows(&printed, &e.shown) {
            failures.push(format!(
                "README.md:{}: `{}`: {why}:\n{printed}",
                e.line, e.command
            ));
        }
    }
    for s in &skipped {
        eprintln!("not run (a program it needs is not installed): {s}");
    }
    eprintln!("{ran} README examples ran, {} skipped", skipped.len());
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

#[test]
fn the_example_reader_finds_commands_and_their_output() {
    let md = "x\n```sh\nncthread a \\\n    --b\n```\n```sh\n$ ncthread c\nerror[X]: y\n…\n```\n```\nncthread synopsis [FILE]\n```\n```text\n$ ncthread d\n```\n";
    let e = examples(md);
    let commands: Vec<&str> = e.iter().map(|e| e.command.as_str()).collect();
    assert_eq!(commands, ["ncthread a \\\n    --b", "ncthread c"]);
    assert_eq!(e[1].shown, ["error[X]: y", "…"]);
    assert!(shows("a\nb\nc\n", &["a".into(), "…".into(), "c".into()]).is_ok());
    assert!(shows("a\nb\nc\n", &["a".into(), "c".into()]).is_err());
    assert!(line_matches("converted 3 in 0.1 s", "converted 3 in …"));
    assert!(!line_matches("converted 4 in 0.1 s", "converted 3 in …"));
    assert!(Path::new(env!("CARGO_BIN_EXE_ncthread")).exists());
}

//! One snapshot per corpus file, holding every route of it: what `explain` says of it and its
//! conversion to every target (diagnostics and output); a file with a profile beside it then
//! shows what the profile changes. The programs of a folder that the reader refuses (no target
//! sees them) share one snapshot, each refusal once, so that a folder's refusals are read in
//! one go. Every test runs and reports on its
//! own, so the first failing file does not hide the rest: `cargo test --test corpus czech/ex4`
//! runs the cases whose name contains `czech/ex4`.
mod common;

use common::Case;
use libtest_mimic::{Arguments, Failed, Trial};

fn main() {
    let args = Arguments::from_args();
    let cases = common::corpus_cases();
    let mut trials = vec![Trial::test("corpus_is_there", {
        let n = cases.len();
        move || {
            if n > 40 {
                Ok(())
            } else {
                Err(format!("the corpus went missing: {n} cases").into())
            }
        }
    })];
    let profiled: Vec<Case> = cases
        .iter()
        .filter(|c| c.profile.is_some())
        .cloned()
        .collect();
    let with_profile: Vec<String> = profiled.iter().map(|c| c.path.clone()).collect();
    trials.push(Trial::test("no_stale_snapshots", {
        let cases = cases.clone();
        move || no_stale_snapshots(&cases)
    }));
    let mut grouped: std::collections::BTreeMap<String, Vec<Case>> = Default::default();
    for case in &cases {
        if refused_alone(case, &with_profile) {
            grouped.entry(folder(case)).or_default().push(case.clone());
        }
    }
    for (folder, members) in &grouped {
        let members = members.clone();
        trials.push(Trial::test(
            format!("snapshot::{folder} (refused by the reader)"),
            move || refused_snapshot(&members),
        ));
    }
    for case in cases {
        // A bad file with a profile is judged with it: its fault may lie in the machine's
        // constants, and be fine on another machine.
        let judged_bad = case.path.starts_with("corpus/bad/")
            && (case.profile.is_some() || !with_profile.contains(&case.path));
        let detected = !case.path.starts_with("corpus/bad/")
            && !case.path.starts_with("corpus/fuzz/")
            && case.profile.is_none();
        let name = case.name.clone();
        if case.profile.is_none() && !refused_alone(&case, &with_profile) {
            let plain = case.clone();
            let profiled = profiled.iter().find(|c| c.path == case.path).cloned();
            trials.push(Trial::test(format!("snapshot::{name}"), move || {
                snapshot(&plain, profiled.as_ref())
            }));
        }
        if judged_bad {
            trials.push(Trial::test(format!("refused::{name}"), {
                let case = case.clone();
                move || refused(&case)
            }));
        }
        if detected {
            trials.push(Trial::test(format!("detected::{name}"), move || {
                detected_as_its_folder(&case)
            }));
        }
    }
    libtest_mimic::run(&args, trials).exit();
}

/// Every route of one corpus file, as one text a person can read in one go: what `explain`
/// says of it and its conversion to every target; or, when the reader refuses it, the refusal
/// once (after checking that every target says the same). A file with a profile beside it
/// shows the profile's effect after that: each route again, or that it is the same.
fn routes(case: &Case) -> Result<String, Failed> {
    let conversions: Vec<_> = common::TARGETS
        .iter()
        .map(|&to| (to, common::convert_case(case, to)))
        .collect();
    let mut text = String::new();
    if common::reader_refuses(case) {
        let first = common::render_body(&conversions[0].1);
        for (to, c) in &conversions[1..] {
            if common::render_body(c) != first {
                return Err(format!(
                    "{}: the reader refuses it, yet --to {to} differs",
                    case.name
                )
                .into());
            }
        }
        text.push_str("=== every target (the reader refuses the program)\n");
        text.push_str(&first);
    } else {
        text.push_str("=== explain\n");
        text.push_str(&explain(case));
        for (to, c) in &conversions {
            text.push_str(&format!("=== --to {to}\n"));
            text.push_str(&common::render_body(c));
        }
    }
    Ok(text)
}

/// The one snapshot of a corpus file: its routes, then (with a profile beside it) the
/// routes with the profile, each section that the profile leaves alone said to be the same.
fn snapshot(plain: &Case, with_profile: Option<&Case>) -> Result<(), Failed> {
    let base = plain.name.replace('/', "__");
    let without = routes(plain)?;
    let mut text = format!("source: {}\n{without}", plain.path);
    if let Some(case) = with_profile {
        let profile = case.profile.as_deref().unwrap_or_default();
        text.push_str(&format!(
            "\n##### with the profile {profile}: each route the profile changes\n"
        ));
        let before = sections(&without);
        for (head, body) in sections(&routes(case)?) {
            match before.iter().find(|(h, _)| *h == head) {
                Some((_, b)) if *b == body => text.push_str(&format!("{head} (as without)\n")),
                _ => text.push_str(&format!("{head}\n{body}")),
            }
        }
    }
    insta::with_settings!({ prepend_module_to_snapshot => false, omit_expression => true }, {
        insta::assert_snapshot!(base, text);
    });
    Ok(())
}

/// A program the reader refuses, with no profile beside it: its snapshot is its folder's.
fn refused_alone(case: &Case, with_profile: &[String]) -> bool {
    case.profile.is_none() && !with_profile.contains(&case.path) && common::reader_refuses(case)
}

/// `bad/iso` for `corpus/bad/iso/x.ngc`.
fn folder(case: &Case) -> String {
    let path = case.path.trim_start_matches("corpus/");
    path.rsplit_once('/').map_or(path, |(f, _)| f).to_string()
}

/// The name of a folder's snapshot of the programs the reader refuses.
fn refused_name(folder: &str) -> String {
    format!("{}__refused-by-the-reader", folder.replace('/', "__"))
}

/// The one snapshot of a folder's programs that the reader refuses: each refusal, in order.
fn refused_snapshot(members: &[Case]) -> Result<(), Failed> {
    let mut text = String::new();
    for case in members {
        text.push_str(&format!(
            "##### {}
{}
",
            case.path,
            routes(case)?
        ));
    }
    let name = refused_name(&folder(&members[0]));
    insta::with_settings!({ prepend_module_to_snapshot => false, omit_expression => true }, {
        insta::assert_snapshot!(name, text);
    });
    Ok(())
}

/// A routes text cut at its `=== ` headings: (heading, body) in order.
fn sections(text: &str) -> Vec<(&str, String)> {
    let mut out: Vec<(&str, String)> = Vec::new();
    for line in text.split_inclusive('\n') {
        match line.strip_prefix("=== ") {
            Some(_) => out.push((line.trim_end(), String::new())),
            None => {
                if let Some(last) = out.last_mut() {
                    last.1.push_str(line)
                }
            }
        }
    }
    out
}

/// A file in corpus/bad/ is refused, each error with a location and a help text.
fn refused(case: &Case) -> Result<(), Failed> {
    let conversion = common::convert_case(case, ncthread::dialect::iso::ID);
    if conversion.output.is_some() {
        return Err(format!("{} converted", case.name).into());
    }
    for d in conversion.diagnostics.iter().filter(|d| d.is_error()) {
        let Some(loc) = d.location.as_ref() else {
            return Err(format!("{}: {} has no location", case.name, d.code.id).into());
        };
        if loc.line < 1 || loc.column < 1 {
            return Err(format!("{}: {} at {loc:?}", case.name, d.code.id).into());
        }
        if d.help.is_none() {
            return Err(format!("{}: {} has no help", case.name, d.code.id).into());
        }
    }
    Ok(())
}

/// `--from auto` reads a valid corpus program as the dialect of its folder (bad files are
/// left out: some mix dialects on purpose; so are the fuzz findings, machine-made).
fn detected_as_its_folder(case: &Case) -> Result<(), Failed> {
    let bytes = std::fs::read(common::root().join(&case.path)).unwrap();
    let (_, _, detection) = ncthread::text::decode_detect(&bytes);
    if detection.dialect == case.from {
        Ok(())
    } else {
        Err(format!("{}: {detection:?}", case.name).into())
    }
}

/// Every snapshot file belongs to a case of today's corpus (a renamed or deleted corpus file
/// takes its snapshots with it).
fn no_stale_snapshots(cases: &[Case]) -> Result<(), Failed> {
    let with_profile: Vec<String> = cases
        .iter()
        .filter(|c| c.profile.is_some())
        .map(|c| c.path.clone())
        .collect();
    let expected: std::collections::HashSet<String> = cases
        .iter()
        .map(|case| match refused_alone(case, &with_profile) {
            true => format!("{}.snap", refused_name(&folder(case))),
            false => format!(
                "{}.snap",
                case.name.replace('/', "__").replace("+profile", "")
            ),
        })
        .collect();
    let dir = common::root().join("tests/snapshots");
    let stale: Vec<String> = std::fs::read_dir(&dir)?
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".snap") && !expected.contains(n))
        .collect();
    if stale.is_empty() {
        Ok(())
    } else {
        Err(format!("snapshots of no corpus case (delete them): {stale:?}").into())
    }
}

/// `ncthread explain` of the case: the text table, then the JSON.
fn explain(case: &Case) -> String {
    let program = common::parse_case(case);
    let ops = ncthread::explain::explain(&program, &Default::default());
    format!(
        "--- text\n{}--- json\n{}\n",
        ncthread::explain::to_text(&ops, ncthread::explain::Table::Box),
        serde_json::to_string_pretty(&ncthread::explain::to_json(&ops)).unwrap()
    )
}

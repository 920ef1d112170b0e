//! One test per corpus case (each file, and each file with its profile): its conversions to
//! every target as insta snapshots (diagnostics and output), and what `explain` says of it. A program the reader refuses is
//! snapshotted once (`…__read`), since no target sees it. Every test runs and reports on its
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
    let with_profile: Vec<String> = cases
        .iter()
        .filter(|c| c.profile.is_some())
        .map(|c| c.path.clone())
        .collect();
    trials.push(Trial::test("no_stale_snapshots", {
        let cases = cases.clone();
        move || no_stale_snapshots(&cases)
    }));
    for case in cases {
        // A bad file with a profile is judged with it: its fault may lie in the machine's
        // constants, and be fine on another machine.
        let judged_bad = case.path.starts_with("corpus/bad/")
            && (case.profile.is_some() || !with_profile.contains(&case.path));
        let detected = !case.path.starts_with("corpus/bad/")
            && !case.path.starts_with("corpus/fuzz/")
            && case.profile.is_none();
        let name = case.name.clone();
        trials.push(Trial::test(format!("snapshot::{name}"), {
            let case = case.clone();
            move || snapshots(&case)
        }));
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

/// The case converted to every target, each conversion a snapshot; or, when the reader
/// refuses it, one snapshot of the refusal (after checking that every target says the same).
fn snapshots(case: &Case) -> Result<(), Failed> {
    let base = case.name.replace('/', "__");
    let conversions: Vec<_> = common::TARGETS
        .iter()
        .map(|&to| (to, common::convert_case(case, to)))
        .collect();
    let mut snaps = Vec::new();
    if common::reader_refuses(case) {
        let label = "every (the reader refuses the program)";
        let first = common::render(case, label, &conversions[0].1);
        for (to, c) in &conversions[1..] {
            if common::render(case, label, c) != first {
                return Err(format!(
                    "{}: the reader refuses it, yet --to {to} differs",
                    case.name
                )
                .into());
            }
        }
        snaps.push((format!("{base}__read"), first));
    } else {
        snaps.push((format!("{base}__explain"), explain(case)));
        for (to, c) in &conversions {
            snaps.push((
                format!("{base}__to_{to}"),
                common::render(case, &to.to_string(), c),
            ));
        }
    }
    for (name, text) in snaps {
        insta::with_settings!({ prepend_module_to_snapshot => false, omit_expression => true }, {
            insta::assert_snapshot!(name, text);
        });
    }
    Ok(())
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
    let mut expected = std::collections::HashSet::new();
    for case in cases {
        // A program the reader refuses has one snapshot; any other one per target.
        let base = case.name.replace('/', "__");
        if common::reader_refuses(case) {
            expected.insert(format!("{base}__read.snap"));
        } else {
            expected.insert(format!("{base}__explain.snap"));
            for to in common::TARGETS {
                expected.insert(format!("{base}__to_{to}.snap"));
            }
        }
    }
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
        "source: {}\nprofile: {}\n--- text\n{}--- json\n{}\n",
        case.path,
        case.profile
            .as_deref()
            .unwrap_or("none (built-in defaults)"),
        ncthread::explain::to_text(&ops, ncthread::explain::Table::Box),
        serde_json::to_string_pretty(&ncthread::explain::to_json(&ops)).unwrap()
    )
}

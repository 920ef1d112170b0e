//! Issue 15: LinuxCNC's macro language. Every macro program of the corpus (parameters,
//! expressions, O-word subroutines and control flow, a subroutine file on the subroutine
//! path) is run by ncthread and by LinuxCNC's rs274, which runs the macro itself: both
//! readings agree move for move, and the unrolled ISO output makes the same motion in rs274.
//! Every refusal names its code.
mod common;

use ncthread::source::SourceFile;
use ncthread::{ConvertOptions, Outcome, Unsupported};

fn cases(folder: &str) -> Vec<(String, Option<String>)> {
    let dir = common::root().join(folder);
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().to_string())
        .filter(|n| n.starts_with("macro-") && n.ends_with(".ngc"))
        .collect();
    files.sort();
    files
        .into_iter()
        .map(|n| {
            let stem = n.trim_end_matches(".ngc");
            let profile = format!("{folder}/{stem}.profile.toml");
            let profile = common::root().join(&profile).exists().then_some(profile);
            (format!("{folder}/{n}"), profile)
        })
        .collect()
}

fn options(profile: &Option<String>) -> ConvertOptions {
    ConvertOptions {
        from: ncthread::dialect::iso::ID,
        to: ncthread::dialect::iso::ID,
        profile: profile
            .as_deref()
            .map(common::load_profile)
            .unwrap_or_default(),
        unsupported: Unsupported::Error,
        renumber: Default::default(),
        round: false,
        nc31_comments: false,
    }
}

#[test]
fn every_macro_program_runs_as_rs274_runs_it() {
    let rs274 = common::rs274().map(|p| ncthread::sim::rs274::Interpreter::Wrapper(p.into()));
    let programs = cases("corpus/iso");
    assert!(programs.len() >= 12, "{programs:?}");
    for (path, profile) in programs {
        let text = std::fs::read_to_string(common::root().join(&path)).unwrap();
        // The subroutine folder of a profile is relative to the profile.
        let mut options = options(&profile);
        options.profile.iso.subroutine_path = options
            .profile
            .iso
            .subroutine_path
            .iter()
            .map(|p| common::root().join(p))
            .collect();
        let src = SourceFile::new(path.clone(), text);
        let v = ncthread::verify(&src, &options, None, rs274.as_ref());
        assert!(
            matches!(v.outcome, Outcome::Equivalent { .. }),
            "{path}: {:?} {:?}",
            v.outcome,
            v.diagnostics
        );
        if rs274.is_some() {
            // LinuxCNC's run of the macro source and of the unrolled output.
            assert_eq!(v.oracle.len(), 2, "{path}");
        }
        for check in &v.oracle {
            assert!(
                matches!(
                    check.outcome,
                    ncthread::OracleOutcome::Equivalent { partial: false, .. }
                ),
                "{path}: {}: {:?}",
                check.what,
                check.outcome
            );
        }
    }
}

#[test]
fn macro_refusals_name_their_code() {
    let expected = [
        ("corpus/bad/iso/macro-continue-in-repeat.ngc", "ISOR017"),
        ("corpus/bad/iso/macro-div-zero.ngc", "ISOR018"),
        ("corpus/bad/iso/macro-endless-recursion.ngc", "ISOR017"),
        ("corpus/bad/iso/macro-endless-while.ngc", "ISOR017"),
        ("corpus/bad/iso/macro-undefined-named.ngc", "ISOR018"),
        ("corpus/bad/iso/macro-unknown-sub.ngc", "ISOR017"),
    ];
    assert_eq!(cases("corpus/bad/iso").len(), expected.len());
    for (path, code) in expected {
        let text = std::fs::read_to_string(common::root().join(path)).unwrap();
        let src = SourceFile::new(path, text);
        let c = ncthread::convert(&src, &options(&None));
        assert!(c.output.is_none(), "{path}");
        let first = c.diagnostics.iter().find(|d| d.is_error()).unwrap();
        assert_eq!(first.code.id, code, "{path}: {first:?}");
    }
}

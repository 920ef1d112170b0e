//! Converting a program to a dialect and converting the result to the same dialect again
//! changes nothing: for every corpus program and every target, `T → T` of `X → T` is the
//! same text as `X → T` (issue 12). An ncthread output is a fixed point of ncthread.
mod common;

use ncthread::source::SourceFile;
use ncthread::{ConvertOptions, Unsupported};

#[test]
fn converting_twice_gives_the_same_text() {
    let mut checked = 0;
    for case in common::corpus_cases() {
        for &to in common::TARGETS {
            let Some(first) = common::convert_case(&case, to).output else {
                continue;
            };
            let profile = case
                .profile
                .as_deref()
                .map(common::load_profile)
                .unwrap_or_default();
            let options = ConvertOptions {
                from: to,
                to,
                profile,
                unsupported: Unsupported::Error,
                renumber: Default::default(),
                round: false,
                nc31_comments: false,
            };
            let again =
                ncthread::convert(&SourceFile::new(case.path.clone(), first.clone()), &options);
            let second = again.output.unwrap_or_else(|| {
                panic!(
                    "{} → {to}: ncthread refuses its own output: {:?}\n{first}",
                    case.name, again.diagnostics
                )
            });
            assert_eq!(second, first, "{} → {to} → {to}", case.name);
            checked += 1;
        }
    }
    assert!(checked > 60, "only {checked} conversions checked");
}

/// A program ncthread wrote (its header says so) converts to its own dialect byte for byte:
/// the inch ISO program stays `G20` with every value as it was (issue 32).
#[test]
fn a_program_ncthread_wrote_converts_to_itself() {
    let mut checked = 0;
    for case in common::corpus_cases() {
        // Programs in a legacy encoding are not ncthread's ISO or FANUC output.
        let Ok(text) = std::fs::read_to_string(&case.path) else {
            continue;
        };
        let header = text.lines().nth(1).unwrap_or("");
        if case.profile.is_some() || !header.ends_with(", converted by ncthread)") {
            continue;
        }
        let out = common::convert_case(&case, case.from).output;
        assert_eq!(out.as_deref(), Some(text.as_str()), "{}", case.name);
        checked += 1;
    }
    assert!(checked >= 1, "no program ncthread wrote in the corpus");
}

/// A program whose every length is in inches is written in inches by ISO and FANUC (`G20`
/// in the modes line, no `G21`), and in millimetres by the targets that cannot say inches.
#[test]
fn an_inch_program_stays_in_inches() {
    let mut checked = 0;
    for name in [
        "iso/inch-canonical.ngc",
        "iso/inch-radius-mode.ngc",
        "iso/drill-g83-inch.ngc",
        "fanuc/inch-g20.nc",
        "fanuc/haas-inch-part.nc",
    ] {
        let case = common::corpus_cases()
            .into_iter()
            .find(|c| c.path.ends_with(name) && c.profile.is_none())
            .unwrap_or_else(|| panic!("{name} not in the corpus"));
        for to in [ncthread::dialect::iso::ID, ncthread::dialect::fanuc::ID] {
            let out = common::convert_case(&case, to)
                .output
                .unwrap_or_else(|| panic!("{name} → {to} refused"));
            let modes = out.lines().find(|l| l.starts_with('G')).unwrap_or("");
            assert!(modes.contains("G20"), "{name} → {to}: {modes}");
            let code = |l: &&str| !l.starts_with('(');
            assert!(
                !out.lines().filter(code).any(|l| l.contains("G21")),
                "{name} → {to}:\n{out}"
            );
            checked += 1;
        }
        for to in [ncthread::dialect::czech::ID, ncthread::dialect::nc31::ID] {
            if let Some(out) = common::convert_case(&case, to).output {
                assert!(!out.contains("G20"), "{name} → {to}:\n{out}");
            }
        }
    }
    assert_eq!(checked, 10);
}

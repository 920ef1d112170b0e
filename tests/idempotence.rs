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

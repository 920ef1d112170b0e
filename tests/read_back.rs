//! A conversion reads its output back keeping only the diagnostics (each reader lets go of a
//! line's items once the line is read): those diagnostics must be the full read's, for every
//! corpus file, read as every dialect (another dialect's text is hostile input too), with
//! and without `--unsupported warn`.

mod common;

use ncthread::Unsupported;
use ncthread::dialect;

#[test]
fn reading_for_the_diagnostics_alone_reports_what_a_full_read_reports() {
    let mut compared = 0;
    for case in common::corpus_cases() {
        let src = common::case_source(&case);
        let profile = case
            .profile
            .as_deref()
            .map(common::load_profile)
            .unwrap_or_default();
        for d in dialect::ALL {
            for unsupported in [Unsupported::Error, Unsupported::Warn] {
                let (_, full) = d.read(&src, &profile, unsupported);
                let alone = d.diagnostics(&src, &profile, unsupported);
                assert_eq!(alone, full, "{} read as {}", case.name, d.id());
                compared += 1;
            }
        }
    }
    assert!(compared > 1000, "only {compared} reads compared");
}

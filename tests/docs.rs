//! The user's manual stays true: README.md lists every diagnostic code with its summary.

#[test]
fn readme_lists_every_diagnostic_code() {
    let readme =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/README.md")).unwrap();
    for code in ncthread::dialect::all_codes() {
        let row = format!(
            "| `{}` | {} |",
            code.id,
            if code.severity == ncthread::diag::Severity::Error {
                "error"
            } else {
                "warning"
            }
        );
        assert!(
            readme.contains(&row),
            "README.md lacks the row for {}",
            code.id
        );
        assert!(
            readme.contains(code.summary),
            "README.md lacks the summary of {}",
            code.id
        );
    }
}

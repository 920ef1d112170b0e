//! Every corpus file × every target as an insta snapshot (diagnostics and output).
mod common;

#[test]
fn corpus_snapshots() {
    let cases = common::corpus_cases();
    assert!(
        cases.len() > 40,
        "the corpus went missing: {} cases",
        cases.len()
    );
    for case in &cases {
        for &to in common::TARGETS {
            let conversion = common::convert_case(case, to);
            let text = common::render(case, to, &conversion);
            let name = format!("{}__to_{to}", case.name.replace('/', "__"));
            insta::with_settings!({ prepend_module_to_snapshot => false, omit_expression => true }, {
                insta::assert_snapshot!(name, text);
            });
        }
    }
}

/// Every file in corpus/bad/ is refused (with its profile when it has one: a file whose
/// fault lies in the machine's constants may be fine on another machine).
#[test]
fn bad_programs_are_refused() {
    let cases = common::corpus_cases();
    let with_profile: Vec<&str> = cases
        .iter()
        .filter(|c| c.profile.is_some())
        .map(|c| c.path.as_str())
        .collect();
    for case in cases.iter().filter(|c| {
        c.path.starts_with("corpus/bad/")
            && (c.profile.is_some() || !with_profile.contains(&c.path.as_str()))
    }) {
        let conversion = common::convert_case(case, ncthread::dialect::iso::ID);
        assert!(conversion.output.is_none(), "{} converted", case.name);
        for d in conversion.diagnostics.iter().filter(|d| d.is_error()) {
            let loc = d
                .location
                .as_ref()
                .unwrap_or_else(|| panic!("{}: {} has no location", case.name, d.code.id));
            assert!(loc.line >= 1 && loc.column >= 1, "{}", case.name);
            assert!(d.help.is_some(), "{}: {} has no help", case.name, d.code.id);
        }
    }
}

/// `--from auto` reads every valid corpus program as the dialect of its folder (bad files
/// are left out: some mix dialects on purpose; so are the fuzz findings, machine-made).
#[test]
fn auto_detection_agrees_with_every_corpus_folder() {
    for case in common::corpus_cases()
        .iter()
        .filter(|c| !c.path.starts_with("corpus/bad/") && !c.path.starts_with("corpus/fuzz/"))
    {
        let bytes = std::fs::read(common::root().join(&case.path)).unwrap();
        let (_, _, detection) = ncthread::text::decode_detect(&bytes);
        assert_eq!(detection.dialect, case.from, "{}: {detection:?}", case.name);
    }
}

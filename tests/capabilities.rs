//! The capability table (`ncthread dialects`) says what each target refuses; real conversions
//! must agree. For every cell that says a target refuses a construct, the corpus programs
//! that hold the construct are converted to that target and refused with the cell's code, and
//! at least one corpus program holds it. README.md prints the table as ncthread does.
mod common;

use ncthread::dialect::capabilities::{Construct, Write};
use ncthread::source::SourceFile;

#[test]
fn every_refusal_in_the_table_is_a_refusal_in_practice() {
    let mut programs = Vec::new();
    for case in common::corpus_cases()
        .into_iter()
        .filter(|c| !c.path.starts_with("corpus/bad/"))
    {
        let bytes = std::fs::read(common::root().join(&case.path)).unwrap();
        let (text, _) = ncthread::text::decode(&bytes, case.from);
        let src = SourceFile::new(case.path.clone(), text);
        let profile = case
            .profile
            .as_deref()
            .map(common::load_profile)
            .unwrap_or_default();
        let (program, diags) =
            ncthread::parse(&src, case.from, &profile, ncthread::Unsupported::Error);
        if !ncthread::diag::has_errors(&diags) {
            programs.push((case, profile, program));
        }
    }
    let mut cells = 0;
    for target in ncthread::dialect::ALL {
        for construct in Construct::ALL {
            // A "no" cell of the built-in table needs a corpus program that holds it.
            if let Write::No(_) = target.capabilities(&Default::default()).write(construct) {
                cells += 1;
                assert!(
                    programs.iter().any(|(_, _, p)| construct.appears_in(p)),
                    "no corpus program holds `{}`, which {} refuses",
                    construct.name(),
                    target.id()
                );
            }
            // Every program is refused for what the table of its own profile refuses.
            for (case, profile, program) in &programs {
                let Write::No(code) = target.capabilities(profile).write(construct) else {
                    continue;
                };
                if !construct.appears_in(program) {
                    continue;
                }
                let conversion = common::convert_case(case, target.id());
                // A FANUC cycle kept as written is refused by the shared legalisation (LG003),
                // which stops before the target's table is asked.
                if conversion
                    .diagnostics
                    .iter()
                    .any(|d| d.is_error() && d.code.id == "LG003")
                {
                    continue;
                }
                assert!(
                    conversion.output.is_none()
                        && conversion
                            .diagnostics
                            .iter()
                            .any(|d| d.is_error() && d.code == code),
                    "{} holds `{}`: {} should refuse it with {}, and says {:?}",
                    case.name,
                    construct.name(),
                    target.id(),
                    code.id,
                    conversion
                        .diagnostics
                        .iter()
                        .map(|d| d.code.id)
                        .collect::<Vec<_>>()
                );
            }
        }
    }
    assert!(cells >= 10, "only {cells} refusing cells");
}

#[test]
fn readme_prints_the_table_ncthread_prints() {
    let readme = std::fs::read_to_string(common::root().join("README.md")).unwrap();
    let table = ncthread::dialect::capability_table(&Default::default());
    assert!(
        readme.contains(&table),
        "README.md lacks the table `ncthread dialects` prints:\n{table}"
    );
}

/// The FANUC dwell row says the word the writer writes on that machine: `G04 U` (system A),
/// `G04 X` (systems B and C), `G04 P` in seconds (a Haas, `haas_dwell_p`).
#[test]
fn the_fanuc_dwell_row_names_the_word_the_writer_writes() {
    let src = SourceFile::new(
        "dwell.ngc",
        "G7 G18 G21 G90 G95\nG0 X20 Z5\nG4 P0.5\nM2\n".to_string(),
    );
    for toml in [
        "",
        "[fanuc]\ngcode_system = \"B\"\n",
        "[fanuc]\ngcode_system = \"C\"\n",
        "[fanuc]\nhaas_dwell_p = true\n",
    ] {
        let profile =
            ncthread::profile::Profile::from_toml(&SourceFile::new("p", toml.to_string())).unwrap();
        let fanuc = ncthread::dialect::get(ncthread::dialect::fanuc::ID);
        let Write::Yes(written) = fanuc.capabilities(&profile).write(Construct::Dwell) else {
            panic!("{toml}: the dwell row does not say it writes dwells");
        };
        let word = &written[..5];
        let options = ncthread::ConvertOptions {
            profile,
            ..ncthread::ConvertOptions::new(
                ncthread::dialect::iso::ID,
                ncthread::dialect::fanuc::ID,
            )
        };
        let out = ncthread::convert(&src, &options);
        let text = out
            .output
            .unwrap_or_else(|| panic!("{toml}: {:?}", out.diagnostics));
        let line = text
            .lines()
            .find(|l| l.starts_with("G04"))
            .expect("a dwell");
        assert!(
            line.starts_with(word),
            "{toml}: the row says {written}, the writer {line}"
        );
    }
}

//! What a downstream project does with the library: convert programs through the public API
//! only (no module the crate hides) and hold the results in insta snapshots, each reviewed
//! once. A shop that keeps its own programs under version control can test its conversions
//! the same way: a changed conversion shows as a snapshot diff.

use ncthread::diag::{Format, render_all};
use ncthread::source::SourceFile;
use ncthread::{ConvertOptions, DialectId, convert};

fn program(path: &str) -> SourceFile {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join(path)).unwrap();
    SourceFile::new(path, text)
}

/// The conversion as a reviewer reads it: the diagnostics as the CLI prints them, then the
/// output (or that nothing was written).
fn shown(src: &SourceFile, from: &str, to: &str) -> String {
    let options = ConvertOptions::new(from.parse().unwrap(), to.parse().unwrap());
    let c = convert(src, &options);
    format!(
        "{}--- output\n{}",
        render_all(&c.diagnostics, Format::Human, false),
        c.output
            .as_deref()
            .unwrap_or("(refused: nothing written)\n")
    )
}

#[test]
fn the_seed_taper_thread_to_fanuc() {
    let src = program("corpus/czech/ex3-taper.nc");
    insta::with_settings!({ snapshot_path => "downstream_snapshots" }, {
        insta::assert_snapshot!(shown(&src, "czech", "FANUC"));
    });
}

#[test]
fn a_refusal_names_its_block() {
    let src = program("corpus/bad/iso/spindle-off-g33.ngc");
    insta::with_settings!({ snapshot_path => "downstream_snapshots" }, {
        insta::assert_snapshot!(shown(&src, "iso", "czech"));
    });
}

/// A typo in a dialect's name is an error that lists the dialects, never another dialect
/// (`ConvertOptions { to: DialectId::new("FANUC") }` converted to czech before).
#[test]
fn a_dialect_name_in_any_case_is_that_dialect_and_a_typo_is_an_error() {
    for (name, id) in [
        ("FANUC", ncthread::dialect::fanuc::ID),
        ("Iso", ncthread::dialect::iso::ID),
        (" nc31 ", ncthread::dialect::nc31::ID),
        ("czech", ncthread::dialect::czech::ID),
    ] {
        assert_eq!(name.parse::<DialectId>(), Ok(id));
    }
    let err = "fanuk".parse::<DialectId>().unwrap_err();
    assert_eq!(
        err.to_string(),
        "unknown dialect `fanuk`: the dialects are czech, nc31, iso, fanuc, siemens, heidenhain"
    );
    let src = program("corpus/czech/ex3-taper.nc");
    let c = convert(
        &src,
        &ConvertOptions::new("czech".parse().unwrap(), "FANUC".parse().unwrap()),
    );
    let out = c.output.unwrap();
    assert!(out.starts_with("%\nO"), "not a FANUC program:\n{out}");
}

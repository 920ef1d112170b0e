//! Issue 14: the forms a czech machine profile declares besides arcs — dwell (`G04 X|F|P`)
//! and constant surface speed (`G96`/`G97`). An ISO program with both converts to czech
//! under each form exactly (`verify` equivalent, rs274 agreeing with ncthread's reading of
//! the ISO side), back again, and is refused by name where the profile lacks the form or
//! the value has none.
mod common;

use ncthread::profile::Profile;
use ncthread::source::SourceFile;
use ncthread::{ConvertOptions, DialectId, Outcome, Unsupported};

const PROGRAM: &str = "\
G7 G18 G21 G90 G95
G96 S180 M3
G0 X40 Z2
G1 Z-20 F0.2
G1 X30 F0.05
G4 P0.5
G0 X42
G97 S600
G0 Z50
M5
M30
";

fn profile(toml: &str) -> Profile {
    Profile::from_toml(&SourceFile::new("test.toml", toml)).expect("a valid profile")
}

fn options(from: DialectId, to: DialectId, profile: Profile) -> ConvertOptions {
    ConvertOptions {
        from,
        to,
        profile,
        unsupported: Unsupported::Error,
        renumber: Default::default(),
        round: false,
        nc31_comments: false,
    }
}

fn refused_with(conversion: &ncthread::Conversion, code: &str) -> bool {
    conversion.output.is_none()
        && conversion
            .diagnostics
            .iter()
            .any(|d| d.is_error() && d.code.id == code)
}

#[test]
fn czech_dwell_and_surface_speed_convert_exactly_or_are_refused_by_name() {
    let rs274 = common::rs274().map(|p| ncthread::sim::rs274::Interpreter::Wrapper(p.into()));
    let iso = ncthread::dialect::iso::ID;
    let czech = ncthread::dialect::czech::ID;
    let src = SourceFile::new("dwell-css.ngc", PROGRAM);
    let css = "surface_speed = \"g96-g97\"\n";
    for (form, word) in [
        ("g04-x-seconds", "G04 X0.5"),
        ("g04-f-seconds", "G04 F0.5"),
        ("g04-p-milliseconds", "G04 P500"),
    ] {
        let toml = format!("[czech]\ndwell = \"{form}\"\n{css}");
        let here = format!("iso → czech with {form}");
        let to_czech = options(iso, czech, profile(&toml));
        let conversion = ncthread::convert(&src, &to_czech);
        let output = conversion
            .output
            .unwrap_or_else(|| panic!("{here}: refused: {:?}", conversion.diagnostics));
        assert!(
            output.lines().any(|l| l.contains(word)),
            "{here}:\n{output}"
        );
        assert!(
            output.contains("G96\n") && output.contains("S180 M03"),
            "{here}:\n{output}"
        );
        assert!(output.contains("G97"), "{here}:\n{output}");
        let v = ncthread::verify(&src, &to_czech, None, rs274.as_ref());
        assert!(
            matches!(v.outcome, Outcome::Equivalent { .. }),
            "{here}: {:?}\n{output}",
            v.outcome
        );
        common::assert_rs274_agrees(&v, rs274.is_some(), &here);
        // And back: the czech program to ISO cuts what the ISO source cuts.
        let back_src = SourceFile::new("dwell-css.nc", output.clone());
        let back = options(czech, iso, profile(&toml));
        let v = ncthread::verify(&back_src, &back, None, rs274.as_ref());
        assert!(
            matches!(v.outcome, Outcome::Equivalent { .. }),
            "czech → iso with {form}: {:?}\n{output}",
            v.outcome
        );
    }
    // Without the keys: refused by name, for the dwell and for G96.
    let only_css = options(iso, czech, profile(&format!("[czech]\n{css}")));
    assert!(refused_with(&ncthread::convert(&src, &only_css), "CZW002"));
    let only_dwell = options(
        iso,
        czech,
        profile("[czech]\ndwell = \"g04-p-milliseconds\"\n"),
    );
    assert!(refused_with(
        &ncthread::convert(&src, &only_dwell),
        "CZW002"
    ));
    // A G96 speed limit has no czech word; a dwell off the millisecond has no czech value.
    let both = profile(&format!("[czech]\ndwell = \"g04-p-milliseconds\"\n{css}"));
    let limited = SourceFile::new("limit.ngc", PROGRAM.replace("G96 S180", "G96 D2500 S180"));
    assert!(refused_with(
        &ncthread::convert(&limited, &options(iso, czech, both.clone())),
        "CZW002"
    ));
    let fine = SourceFile::new("fine.ngc", PROGRAM.replace("G4 P0.5", "G4 P0.0005"));
    assert!(refused_with(
        &ncthread::convert(&fine, &options(iso, czech, both)),
        "CZW001"
    ));
}

/// Block delete: with the switch on, the `/` lines are skipped, off they run; each reading
/// converts exactly and LinuxCNC (run with `-b` when on) agrees with it.
#[test]
fn block_delete_is_read_as_the_switch_says_and_rs274_agrees() {
    let rs274 = common::rs274().map(|p| ncthread::sim::rs274::Interpreter::Wrapper(p.into()));
    let path = "corpus/iso/block-delete.ngc";
    let text = std::fs::read_to_string(common::root().join(path)).unwrap();
    let src = SourceFile::new(path, text);
    let iso = ncthread::dialect::iso::ID;
    let mut segments = Vec::new();
    for switch in ["on", "off"] {
        for to in [iso, ncthread::dialect::czech::ID] {
            let toml = format!("[iso]\nblock_delete = \"{switch}\"\n");
            let v = ncthread::verify(
                &src,
                &options(iso, to, profile(&toml)),
                None,
                rs274.as_ref(),
            );
            // With the switch off the `/M1` stop runs too, which czech has no form for.
            if switch == "off" && to != iso {
                assert!(matches!(v.outcome, Outcome::Refused));
                assert!(v.diagnostics.iter().any(|d| d.code.id == "CZW002"));
                continue;
            }
            let Outcome::Equivalent { segments: n, .. } = v.outcome else {
                panic!("block delete {switch} → {to}: {:?}", v.outcome);
            };
            segments.push(n);
            common::assert_rs274_agrees(
                &v,
                rs274.is_some(),
                &format!("block delete {switch} → {to}"),
            );
        }
    }
    // The skim cut (three moves) and the stop run only with the switch off.
    assert_eq!(segments, [11, 11, 15]);
}

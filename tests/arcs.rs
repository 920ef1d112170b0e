//! Issue 14: arcs between dialects. One ISO program with every arc form LinuxCNC reads is
//! converted to czech and nc31 under each arc form their profiles can declare; each route
//! is exact (`verify` equivalent, rs274 agreeing with ncthread's reading of the ISO side)
//! or refused with the code that names the reason.
mod common;

use ncthread::profile::Profile;
use ncthread::source::SourceFile;
use ncthread::{ConvertOptions, DialectId, Outcome, Unsupported};

const FILE: &str = "corpus/iso/arcs-every-form.ngc";

fn profile(toml: &str) -> Profile {
    Profile::from_toml(&SourceFile::new("test.toml", toml)).expect("a valid profile")
}

fn options(to: DialectId, profile: Profile) -> ConvertOptions {
    ConvertOptions {
        from: ncthread::dialect::iso::ID,
        to,
        profile,
        unsupported: Unsupported::Error,
        renumber: Default::default(),
        round: false,
        nc31_comments: false,
    }
}

#[test]
fn every_arc_form_converts_exactly_or_is_refused_by_name() {
    let rs274 = common::rs274().map(|p| ncthread::sim::rs274::Interpreter::Wrapper(p.into()));
    let text = std::fs::read_to_string(common::root().join(FILE)).unwrap();
    let src = SourceFile::new(FILE, text);
    let czech = ncthread::dialect::czech::ID;
    let nc31 = ncthread::dialect::nc31::ID;
    let routes: [(DialectId, &str, Option<&str>); 8] = [
        (czech, "[czech]\narcs = \"ik-radius\"\n", None),
        (czech, "[czech]\narcs = \"ik-diameter\"\n", None),
        (
            czech,
            "[czech]\narcs = \"ik-radius\"\narc_direction = \"mirrored\"\n",
            None,
        ),
        // A full circle has no R form.
        (czech, "[czech]\narcs = \"r\"\n", Some("CZW002")),
        (czech, "", Some("CZW002")),
        (
            nc31,
            "[nc31]\narcs = \"g2-g3-p\"\narc_direction = \"iso\"\n",
            None,
        ),
        (
            nc31,
            "[nc31]\narcs = \"g2-g3-p\"\narc_direction = \"front-tool\"\n",
            None,
        ),
        // Arcs declared, their direction not: refused until the profile says.
        (nc31, "[nc31]\narcs = \"g2-g3-p\"\n", Some("NCW002")),
    ];
    for (to, toml, refused) in routes {
        let here = format!("{FILE} → {to} with {toml:?}");
        let options = options(to, profile(toml));
        let conversion = ncthread::convert(&src, &options);
        if let Some(code) = refused {
            assert!(conversion.output.is_none(), "{here}: converted");
            assert!(
                conversion
                    .diagnostics
                    .iter()
                    .any(|d| d.is_error() && d.code.id == code),
                "{here}: no {code} in {:?}",
                conversion.diagnostics
            );
            continue;
        }
        let output = conversion
            .output
            .unwrap_or_else(|| panic!("{here}: refused: {:?}", conversion.diagnostics));
        let v = ncthread::verify(&src, &options, None, rs274.as_ref());
        assert!(
            matches!(v.outcome, Outcome::Equivalent { .. }),
            "{here}: {:?}\n{output}",
            v.outcome
        );
        common::assert_rs274_agrees(&v, rs274.is_some(), &here);
        // The nc31 output writes the full circle and the semicircle a quadrant a group.
        if to == nc31 {
            let groups = output
                .lines()
                .filter(|l| l.contains(" G2 ") || l.contains(" G3 "))
                .count();
            assert_eq!(groups, 1 + 2 + 4 + 1, "{here}:\n{output}");
        }
    }
}

/// An arc at a feed per minute: the НЦ-31 feeds per revolution, so it is refused by name
/// (it was once written as mm/rev), while ISO keeps it.
#[test]
fn a_per_minute_arc_is_refused_for_the_nc31() {
    let text = "G7 G18 G21 G90 G94\nS800 M3\nG0 X20 Z0\nG2 X30 Z-5 I5 K0 F100\nG0 X40\nM5\nM30\n";
    let src = SourceFile::new("per-minute.ngc", text);
    let nc31 = profile("[nc31]\narcs = \"g2-g3-p\"\narc_direction = \"iso\"\n");
    let conversion = ncthread::convert(&src, &options(ncthread::dialect::nc31::ID, nc31));
    assert!(conversion.output.is_none());
    assert!(
        conversion.diagnostics.iter().any(|d| d.is_error()
            && d.code.id == "NCW002"
            && d.location.as_ref().is_some_and(|l| l.line == 4)),
        "{:?}",
        conversion.diagnostics
    );
    let iso = ncthread::convert(
        &src,
        &options(ncthread::dialect::iso::ID, Profile::default()),
    );
    assert!(iso.output.is_some(), "{:?}", iso.diagnostics);
}

//! `verify` over the corpus: every conversion ncthread writes proves equivalent to its
//! source, and hand conversions with a typical mistake are caught.
mod common;

use ncthread::source::SourceFile;
use ncthread::{ConvertOptions, DialectId, Outcome, Unsupported};

fn options(from: DialectId, to: DialectId) -> ConvertOptions {
    ConvertOptions {
        from,
        to,
        profile: Default::default(),
        unsupported: Unsupported::Error,
        renumber: Default::default(),
        round: false,
        nc31_comments: false,
    }
}

fn read(path: &str) -> SourceFile {
    let text = std::fs::read_to_string(common::root().join(path)).unwrap();
    SourceFile::new(path, text)
}

#[test]
fn every_corpus_conversion_verifies() {
    let mut verified = 0;
    for case in common::corpus_cases() {
        for &to in common::TARGETS {
            if common::convert_case(&case, to).output.is_none() {
                continue;
            }
            let bytes = std::fs::read(common::root().join(&case.path)).unwrap();
            let (text, _) = ncthread::text::decode(&bytes, case.from);
            let src = SourceFile::new(case.path.clone(), text);
            let options = ConvertOptions {
                profile: case
                    .profile
                    .as_deref()
                    .map(common::load_profile)
                    .unwrap_or_default(),
                ..options(case.from, to)
            };
            let v = ncthread::verify(&src, &options, None, None);
            match v.outcome {
                Outcome::Equivalent { .. } => {}
                other => panic!("{} → {to}: {other:?}\n{:?}", case.name, v.diagnostics),
            }
            verified += 1;
        }
    }
    assert!(verified >= 40, "only {verified} conversions verified");
}

/// The hand-written M36×1.5 with one change, checked against the seed program.
fn mutant(change: impl Fn(&str) -> String) -> Outcome {
    let hand = read("corpus/iso/m36x1.5-by-hand.ngc");
    let mutated = SourceFile::new("mutant.ngc", change(&hand.text));
    assert_ne!(mutated.text, hand.text, "the mutation changed nothing");
    let seed = read("corpus/nc31/g31-m36x1.5.nc");
    ncthread::verify(
        &seed,
        &options(ncthread::dialect::nc31::ID, ncthread::dialect::iso::ID),
        Some(&mutated),
        None,
    )
    .outcome
}

fn difference(outcome: Outcome) -> String {
    match outcome {
        Outcome::Different(d) => d.to_string(),
        other => panic!("the mutation was not caught: {other:?}"),
    }
}

#[test]
fn the_unchanged_hand_conversion_verifies() {
    assert!(matches!(
        mutant(|t| t.replace("(pass 1)", "(pass one)")),
        Outcome::Equivalent { .. }
    ));
}

#[test]
fn a_pass_0_01_deeper_is_caught() {
    // 0.01 mm per side deeper on pass 3: Ø34.8 → Ø34.78.
    let d = difference(mutant(|t| t.replace("G0 X34.8\n", "G0 X34.78\n")));
    assert!(d.contains("(pass 3)") && d.contains("X34.78"), "{d}");
}

#[test]
fn a_lead_0_001_off_is_caught() {
    let d = difference(mutant(|t| {
        t.replacen("G33 Z-47.5 K1.5", "G33 Z-47.5 K1.501", 1)
    }));
    assert!(d.contains("lead 1.5 ≠ 1.501"), "{d}");
}

#[test]
fn a_start_angle_5_degrees_off_is_caught() {
    // Pass 4 started 1.5·5/360 = 0.0208 mm earlier from the index pulse: a helix 5° away.
    let d = difference(mutant(|t| {
        t.replace(
            "(pass 4)\nG0 X34.455\nG33 Z-47.5 K1.5",
            "(pass 4)\nG0 X34.455 Z4.5208\nG33 Z-47.5 K1.5",
        )
    }));
    assert!(d.contains("(pass 4)") && d.contains("phase"), "{d}");
}

#[test]
fn a_missing_pass_is_caught() {
    let d = difference(mutant(|t| {
        t.replace(
            "(pass 8)\nG0 X34.08\nG33 Z-47.5 K1.5\n",
            "(pass 8 left out)\n",
        )
    }));
    assert!(d.contains("(pass 8)"), "{d}");
}

#[test]
fn another_tool_or_a_tool_change_elsewhere_is_caught() {
    // Tool 6 instead of the seed's turret position 5.
    let d = difference(mutant(|t| t.replace("T5 M6", "T6 M6")));
    assert!(d.contains("tool T6") && d.contains("tool T5"), "{d}");
    // The change before the rapid to the change position instead of after it.
    let d = difference(mutant(|t| {
        let t = t.replace(
            "T5 M6 (threading tool, at the change position as the NC-31 indexes it)\n",
            "",
        );
        t.replace("S700 M3\nG0 X100 Z50\n", "T5 M6\nS700 M3\nG0 X100 Z50\n")
    }));
    assert!(d.contains("tool T5"), "{d}");
}

#[test]
fn a_missing_spring_pass_is_caught() {
    // The G76 with H2 against its own expansion without the last (spring) pass.
    let src = read("corpus/iso/g76-external.ngc");
    let v = ncthread::convert(
        &src,
        &options(ncthread::dialect::iso::ID, ncthread::dialect::iso::ID),
    );
    let full = v.output.unwrap();
    let cut = full.find("(pass 45/45").expect("45 passes");
    let end = cut + full[cut..].find("G0 X50 Z50").unwrap();
    let without = format!("{}{}", &full[..cut], &full[end..]);
    let against = SourceFile::new("without-spring.ngc", without);
    let outcome = ncthread::verify(
        &src,
        &options(ncthread::dialect::iso::ID, ncthread::dialect::iso::ID),
        Some(&against),
        None,
    )
    .outcome;
    let d = difference(outcome);
    assert!(d.contains("(pass 45)"), "{d}");
    // With the pass, it verifies.
    let against = SourceFile::new("full.ngc", full);
    let outcome = ncthread::verify(
        &src,
        &options(ncthread::dialect::iso::ID, ncthread::dialect::iso::ID),
        Some(&against),
        None,
    )
    .outcome;
    assert!(matches!(outcome, Outcome::Equivalent { .. }), "{outcome:?}");
}

/// A start rounded onto a target's grid (`--round`) keeps its helix where the target can
/// say a start angle (FANUC's Q, the czech I): LinuxCNC's G76 with a compound angle starts
/// its passes off the 0.001 mm grid. (SINUMERIK and HEIDENHAIN refuse this program's
/// runouts; their rounded starts are their writers' unit tests'.)
#[test]
fn rounded_thread_starts_keep_their_helix() {
    let src = read("corpus/iso/g76-external.ngc");
    for to in [ncthread::dialect::fanuc::ID, ncthread::dialect::czech::ID] {
        let options = ConvertOptions {
            round: true,
            // Its sidecar: the czech machine constant 8 for the runout.
            profile: common::load_profile("corpus/iso/g76-external.profile.toml"),
            ..options(ncthread::dialect::iso::ID, to)
        };
        let v = ncthread::verify(&src, &options, None, None);
        assert!(
            matches!(v.outcome, Outcome::Equivalent { .. }),
            "iso → {to} --round: {:?}",
            v.outcome
        );
    }
}

/// Where the target cannot say a start angle (the НЦ-31), a start rounded onto its grid moves
/// the helix with it, by no more than the deviation its writer reports: `verify --round`
/// allows the helix that deviation, as it allows positions. (A G31 with flank offsets H1
/// starts its passes off the 0.01 mm grid.)
#[test]
fn a_rounded_start_moves_the_helix_within_the_reported_deviation() {
    let src = SourceFile::new(
        "h1.nc",
        "%G.nc\nBEARBEITUNG\nN1 T1 G97 S500 M3\nN2 G0 X30 Z15\nN3 G31 F3.175 U1.8 B4 P0 I0.4 V0 H1\n\
         N4 G0 X10 Z0\nN5 G1 X10 Z-10\nN6 G80\nN7 G0 X40 Z20\nN8 M30\nENDE\n"
            .to_string(),
    );
    let profile = ncthread::profile::Profile::from_toml(&SourceFile::new(
        "p.toml",
        "[heidenhain]\ng31_clearance = 2.5\ng31_infeed = \"first\"\ng31_h1 = \"towards-start\"\n"
            .to_string(),
    ))
    .unwrap();
    let options = ConvertOptions {
        round: true,
        profile,
        ..options(
            ncthread::dialect::heidenhain::ID,
            ncthread::dialect::nc31::ID,
        )
    };
    let v = ncthread::verify(&src, &options, None, None);
    let Outcome::Equivalent { tolerance, .. } = v.outcome else {
        panic!("{:?}\n{:?}", v.outcome, v.diagnostics)
    };
    // The НЦ-31's 0.01 mm units: at most half a unit.
    assert!(tolerance.0 <= 500, "{tolerance:?}");
}

//! The SINUMERIK reader's unit tests.

use super::*;
use crate::fixed::Decimal;

fn read_text(text: &str) -> (Vec<ItemKind>, Vec<&'static str>) {
    read_with(text, &SiemensProfile::default())
}

fn read_with(text: &str, profile: &SiemensProfile) -> (Vec<ItemKind>, Vec<&'static str>) {
    let (p, d) = read(&SourceFile::new("t.mpf", text), profile, Keep::Program);
    (
        p.items.into_iter().map(|i| i.kind).collect(),
        d.iter().map(|d| d.code.id).collect(),
    )
}

fn mm(v: &str) -> Length {
    Decimal::parse(v)
        .and_then(|d| d.to_length().ok())
        .expect("a length")
}

const HEAD: &str = "%_N_T_MPF\n;$PATH=/_N_MPF_DIR\nN10 G18 G90 G71 G95 G40 DIAMON\n";

#[test]
fn a_pass_waits_for_the_index_pulse_and_sf_degrees() {
    let (items, codes) = read_text(&format!(
        "{HEAD}N20 S800 M3\nN30 G0 X29.2 Z5\nN40 G33 Z-30 K3 SF=180\n"
    ));
    assert!(codes.is_empty(), "{codes:?}");
    let pass = items.iter().find_map(|k| match k {
        ItemKind::ThreadPass(p) => Some(p),
        _ => None,
    });
    let pass = pass.expect("a pass");
    assert_eq!(pass.to, Pos::new(mm("29.2"), mm("-30")));
    assert_eq!(pass.start, SyncStart::Index(Angle(180_000)));
    assert_eq!(pass.lead, Decimal::parse("3").unwrap().to_lead().unwrap());
}

#[test]
fn absolute_and_incremental_words_and_radius_x() {
    let (items, codes) = read_text(&format!(
        "{HEAD}N20 G0 X40 Z5\nN30 G91 X-2 Z=AC(1)\nN40 X=AC(30) Z-1\nN50 DIAMOF G90 X10\n"
    ));
    assert!(codes.is_empty(), "{codes:?}");
    let rapids: Vec<Pos> = items
        .iter()
        .filter_map(|k| match k {
            ItemKind::Rapid { to } => Some(*to),
            _ => None,
        })
        .collect();
    assert_eq!(
        rapids,
        [
            Pos::new(mm("40"), mm("5")),
            Pos::new(mm("38"), mm("1")),
            Pos::new(mm("30"), mm("0")),
            Pos {
                x: Some(mm("20")),
                z: None
            },
        ]
    );
}

#[test]
fn what_a_machine_setting_decides_is_refused_until_the_program_says() {
    let (_, codes) = read_text("N10 G90 G95\nN20 G0 X20 Z5\n");
    assert_eq!(codes, ["SINR006"]);
    let (_, codes) = read_text("N10 DIAMON\nN20 G0 X20 Z5\nN30 G1 Z-5 F0.2\n");
    assert_eq!(codes, ["SINR006"]);
    let (_, codes) = read_text(&format!("{HEAD}N20 G0 X20 Z5\nN30 G33 Z-5 K1\n"));
    assert_eq!(codes, ["SINR006"]);
    // A feed after a change of mode is given again; the same mode restated keeps it.
    let (_, codes) = read_text(&format!(
        "{HEAD}N20 G0 X20 Z5\nN30 G1 Z-5 F0.2\nN40 G95\nN50 Z-6\nN60 G94\nN70 Z-7\n"
    ));
    assert_eq!(codes, ["SINR006"]);
}

#[test]
fn what_is_not_read_is_named() {
    for (text, code) in [
        ("N20 CYCLE97(1,2)\n", "SINR002"),
        ("N20 R1=2\n", "SINR002"),
        ("N20 GOTOF END\n", "SINR002"),
        ("N20 G64\n", "SINR002"),
        ("N20 M6\n", "SINR002"),
        (
            "N20 G0 X20 Z5\nN30 G33 Z-5 K1 SF=0\nN40 Z-8 K1 SF=0\n",
            "SINR008",
        ),
        ("N20 G0 X20 Z5\nN30 G1 X30 F0.1 SF=5\n", "SINR005"),
        ("N20 G0 X20 Z5\nN30 G2 X30 Z0 CR=1 F0.1\n", "SINR007"),
    ] {
        let (_, codes) = read_text(&format!("{HEAD}{text}"));
        assert_eq!(codes.first(), Some(&code), "{text}: {codes:?}");
    }
}

#[test]
fn the_profile_gives_the_reset_state_and_each_unstated_one_is_said_once() {
    let text = "G0 X10 Z5\nG1 X12 F0.2\nX14\nG1 Z-5\n";
    let (_, codes) = read_text(text);
    assert_eq!(codes, ["SINR006", "SINR006"]);
    let profile = SiemensProfile {
        initial_diameter: Some(false),
        initial_per_rev: Some(false),
    };
    let (items, codes) = read_with(text, &profile);
    assert!(codes.is_empty(), "{codes:?}");
    assert_eq!(items[0], ItemKind::FeedMode(FeedMode::PerMin));
    assert_eq!(
        items[1],
        ItemKind::Rapid {
            to: Pos::new(mm("20"), mm("5"))
        }
    );
}

#[test]
fn messages_are_comments_and_stopre_is_nothing() {
    let (items, codes) = read_text(&format!(
        "{HEAD}MSG(\"ROUGH\") ; first\nSTOPRE\nN20 G0 X20 Z5\nSKOK1: G0 X30\n"
    ));
    assert_eq!(codes, ["SINR011", "SINR011", "SINR002"]);
    assert!(items.contains(&ItemKind::Comment("ROUGH".into())));
    assert!(items.contains(&ItemKind::Comment("first".into())));
}

#[test]
fn an_inch_program_is_held_exactly() {
    let (items, codes) =
        read_text("N10 G18 G90 G70 G95 DIAMON\nN20 G0 X0.6 Z0.2\nN30 G33 Z-0.75 K0.0769 SF=0\n");
    assert!(codes.is_empty(), "{codes:?}");
    assert_eq!(
        items[1],
        ItemKind::Rapid {
            to: Pos::new(mm("15.24"), mm("5.08"))
        }
    );
    match &items[2] {
        ItemKind::ThreadPass(p) => assert_eq!(p.lead.mm(), "1.95326"),
        other => panic!("{other:?}"),
    }
}

#[test]
fn g94_to_g97_are_one_group_and_lims_limits_g97() {
    let base = "N10 G18 G90 G710 G94 G40 DIAMON\nN20 G0 X20 Z5\n";
    // G97 says a feed per revolution: F is given again after it.
    let (items, codes) = read_text(&format!("{base}N30 G97 S800 M3\nN40 G1 Z-5 F0.2\n"));
    assert!(codes.is_empty(), "{codes:?}");
    assert!(items.contains(&ItemKind::FeedMode(FeedMode::PerRev)));
    let (_, codes) = read_text(&format!(
        "{base}N25 G1 Z0 F100\nN30 G97 S800 M3\nN40 G1 Z-5\n"
    ));
    assert_eq!(codes, ["SINR006"]);
    // G971 keeps the feed per minute.
    let (_, codes) = read_text(&format!(
        "{base}N25 G1 Z0 F100\nN30 G971 S800 M3\nN40 G1 Z-5\n"
    ));
    assert!(codes.is_empty(), "{codes:?}");
    for (text, code) in [
        ("N30 G96 S200 LIMS=2000 M3\nN40 G95\n", "SINR002"),
        ("N30 G96 S200 LIMS=2000 M3\nN40 G97\n", "SINR006"),
        ("N30 G96 S200 LIMS=2000 M3\nN40 G97 S2500\n", "SINR002"),
        ("N30 G96 M3\n", "SINR006"),
        ("N30 S500 M3 M4\n", "SINR005"),
    ] {
        let (_, codes) = read_text(&format!("{base}{text}"));
        assert_eq!(codes.first(), Some(&code), "{text}: {codes:?}");
    }
    // A G96 without S takes the last surface speed again.
    let (items, codes) = read_text(&format!(
        "{base}N30 G96 S200 LIMS=2000 M3\nN40 G97 S800\nN50 G96\n"
    ));
    assert!(codes.is_empty(), "{codes:?}");
    let speeds: Vec<Option<u32>> = items
        .iter()
        .filter_map(|k| match k {
            ItemKind::Spindle { speed, .. } => Some(*speed),
            _ => None,
        })
        .collect();
    assert_eq!(speeds, [Some(200), Some(800), Some(200)]);
}

#[test]
fn g70_leaves_the_feed_metric_and_g700_makes_it_inch() {
    let feed_of = |units: &str| {
        let (items, codes) = read_text(&format!(
            "N10 G18 G90 {units} G95 DIAMON\nN20 G0 X1 Z1\nN30 G1 Z0 F0.01\n"
        ));
        assert!(codes.is_empty(), "{codes:?}");
        items.iter().find_map(|k| match k {
            ItemKind::Feed { feed, .. } => Some(*feed),
            _ => None,
        })
    };
    assert_eq!(feed_of("G70"), Some(mm("0.01")));
    assert_eq!(feed_of("G700"), Some(mm("0.254")));
    assert_eq!(feed_of("G710"), Some(mm("0.01")));
}

use super::*;
use crate::profile::Profile;

fn read_with(text: &str, profile: &HeidenhainProfile) -> (Program, Vec<crate::diag::Diagnostic>) {
    read(&SourceFile::new("t.nc", text), profile, Keep::Program)
}

fn full() -> HeidenhainProfile {
    HeidenhainProfile {
        arc_direction: Some(HeidenhainArcDirection::Iso),
        c_sense: Some(CSense::Spindle),
        b_along: Some(BAlong::Z),
        ..Default::default()
    }
}

fn codes_of(diags: &[crate::diag::Diagnostic]) -> Vec<&str> {
    diags.iter().map(|d| d.code.id).collect()
}

#[test]
fn c_at_the_end_of_the_run_in_gives_the_start_angle() {
    // B = one lead: the spindle is at C one turn after the start, so at C at the start.
    let (p, d) = read_with(
        "%T.nc\nBEARBEITUNG\nN1 G0 X20 Z5\nN2 G33 X20 Z-20 F1.5 B1.5 P1.5 C90 H0\nENDE\n",
        &full(),
    );
    assert!(d.is_empty(), "{d:?}");
    let ItemKind::ThreadPass(pass) = &p.items[1].kind else {
        panic!("{:?}", p.items)
    };
    assert_eq!(pass.start, SyncStart::Index(Angle(90_000)));
    // A quarter lead of run-in: a quarter turn before C.
    let (p, _) = read_with("G0 X20 Z5\nG33 X20 Z-20 F2 B0.5 C90\n", &full());
    let ItemKind::ThreadPass(pass) = &p.items[1].kind else {
        panic!()
    };
    assert_eq!(pass.start, SyncStart::Index(Angle(0)));
    // Counted against the spindle: C90 is 270° of its turn.
    let against = HeidenhainProfile {
        c_sense: Some(CSense::Against),
        ..full()
    };
    let (p, _) = read_with("G0 X20 Z5\nG33 X20 Z-20 F2 B2 C90\n", &against);
    let ItemKind::ThreadPass(pass) = &p.items[1].kind else {
        panic!()
    };
    assert_eq!(pass.start, SyncStart::Index(Angle(270_000)));
    assert_eq!(p.name, None);
}

#[test]
fn what_the_vendor_leaves_to_the_machine_is_refused_without_the_profile() {
    let none = HeidenhainProfile::default();
    let (_, d) = read_with("G0 X20 Z5\nG33 X20 Z-20 F2 B2 C90\n", &none);
    assert_eq!(codes_of(&d), ["HEIR006"]);
    let (_, d) = read_with("G0 X20 Z5\nG33 X20 Z-20 F2 B2 C180\n", &none);
    assert!(d.is_empty(), "{d:?}");
    let (_, d) = read_with("G0 X20 Z5\nG33 X20 Z-20 F2\n", &full());
    assert_eq!(codes_of(&d), ["HEIR006"]);
    let (_, d) = read_with("G0 X20 Z5\nG33 X24 Z-20 F2 B2\n", &none);
    assert_eq!(codes_of(&d), ["HEIR006"]);
    let (_, d) = read_with("G0 X20 Z5\nG95 G2 X30 Z0 I5 K0 F0.1\n", &none);
    assert_eq!(codes_of(&d), ["HEIR006"]);
    let (_, d) = read_with("G0 X20 Z5\nG1 X30 F0.1\n", &full());
    assert_eq!(codes_of(&d), ["HEIR006"]);
}

#[test]
fn increments_arcs_sections_and_the_end() {
    let text = "%SHAFT.nc\nPROGRAMMKOPF\n#EINHEIT METRISCH\nREVOLVER\nT1 ID\"342-300.1\"\nBEARBEITUNG\nN 1 T1 G97 S1000 M3\nN2 G0 X20 Z2\nN3 G95 G1 Zi-7 F0.2\nN4 G2 Xi10 Z-10 I5 K0 [arc]\nN5 G13 X20 Z-15 I15 K-15\nN6 M30\nENDE\n";
    let (p, d) = read_with(text, &full());
    assert_eq!(codes_of(&d), ["HEIR010", "HEIR010"]);
    assert_eq!(p.name.as_deref(), Some("SHAFT"));
    let arcs: Vec<(Pos, Pos, bool)> = p
        .items
        .iter()
        .filter_map(|i| match &i.kind {
            ItemKind::Arc {
                to,
                centre,
                clockwise,
                ..
            } => Some((*to, **centre, *clockwise)),
            _ => None,
        })
        .collect();
    let at = |x: i64, z: i64| Pos::new(Length::from_mm(x), Length::from_mm(z));
    assert_eq!(
        arcs,
        [
            (at(30, -10), at(30, -5), true),
            (at(20, -15), at(30, -15), false)
        ]
    );
    assert!(
        p.items
            .iter()
            .any(|i| i.kind == ItemKind::ProgramEnd(EndCode::M30))
    );
    let (_, d) = read_with("G0 X1 Z1\nENDE\nG0 X2\n", &full());
    assert_eq!(codes_of(&d), ["HEIR009"]);
    // M30 ends the program: a block after it is not run; the ENDE after it is its close.
    let (p, d) = read_with("G0 X1 Z1\nM30\nM30\nENDE\n", &full());
    assert_eq!(codes_of(&d), ["HEIR009"]);
    let ends = p
        .items
        .iter()
        .filter(|i| matches!(i.kind, ItemKind::ProgramEnd(_)));
    assert_eq!(ends.count(), 1);
    let (_, d) = read_with("G0 X1 Z1\nM30\nENDE\n", &full());
    assert!(d.is_empty(), "{d:?}");
    let _ = Profile::default();
}

#[test]
fn refusals_name_what_is_not_read() {
    for (text, code) in [
        ("G0 X20 Z2\nG31 X20 Z-20 F1.5\n", "HEIR011"),
        ("G0 X20 Z2\nG1 X30 BR1 F0.2\n", "HEIR002"),
        ("G0 X? Z2\n", "HEIR002"),
        ("G0 X20 Z2\nG33 X20 Z-20 F1.5 B1.5 P0\n", "HEIR008"),
        ("G0 X20 Z2\nG33 X20 Z-20 F1.5 B1.5 H1\n", "HEIR008"),
        ("M13\n", "HEIR002"),
        ("G0 X1 Xi2\n", "HEIR005"),
        ("UNTERPROGRAMM\n", "HEIR002"),
    ] {
        let (_, d) = read_with(text, &full());
        assert_eq!(codes_of(&d), [code], "{text}");
    }
}

#[test]
fn g31_is_read_under_the_declared_model_only() {
    let text = "G0 X40 Z10\nG31 F2 U1.2 B4 P2 IC4 [M20]\nG0 X20 Z0\nG1 Z-30\nG80\nG0 X50\n";
    // Without the model: refused, its contour passed over (G0 X50 is read).
    let (p, d) = read_with(text, &full());
    assert_eq!(codes_of(&d), ["HEIR006"]);
    assert!(matches!(
        p.items.last().map(|i| &i.kind),
        Some(ItemKind::Rapid { .. })
    ));
    let model = HeidenhainProfile {
        g31_clearance: Some(Length::from_mm(1)),
        ..full()
    };
    let (p, d) = read_with(text, &model);
    assert!(d.is_empty(), "{d:?}");
    let kinds: Vec<&ItemKind> = p.items.iter().map(|i| &i.kind).collect();
    // The start point: 1 mm per side above the crest, at the start of the run-in B4.
    let a = Pos::new(Length::from_mm(22), Length::from_mm(4));
    assert_eq!(*kinds[1], ItemKind::Rapid { to: a });
    assert_eq!(p.items[1].comment.as_deref(), Some("M20"));
    let ItemKind::ThreadCycle(c) = kinds[2] else {
        panic!("{kinds:?}")
    };
    assert_eq!(c.start, (Length::from_mm(22), Length::from_mm(4)));
    assert_eq!(c.end_z, Length::from_mm(-32));
    assert_eq!(
        (c.crest, c.depth),
        (Length::from_mm(20), Length::from_steps(12_000))
    );
    assert_eq!(c.schedule, crate::ir::Schedule::AreaInPasses(4));
    assert_eq!(
        c.retract,
        crate::ir::Retract::AboveCrest(Length::from_mm(1))
    );
    // After the cycle the motion is not known: the next move must say it.
    assert!(matches!(kinds[3], ItemKind::Rapid { .. }));
    let (_, d) = read_with(&text.replace("G0 X50", "X50"), &model);
    assert_eq!(codes_of(&d), ["HEIR006"]);
    // Read line by line, the diagnostics are the same.
    let src = SourceFile::new("t.nc", text);
    let (_, streamed) = read(&src, &model, Keep::Diagnostics);
    assert!(streamed.is_empty());
}

/// A count that is a whole number out of range is said as such: too large, or negative;
/// only a fraction is "a whole number".
#[test]
fn a_whole_number_out_of_range_is_said_as_such() {
    let message = |text: &str| {
        let (_, d) = read_with(text, &full());
        d.into_iter()
            .find(|d| d.is_error())
            .map(|d| d.message)
            .unwrap_or_default()
    };
    assert!(message("T99999999999\n").ends_with("is too large"));
    assert!(message("T-1\n").ends_with("is not negative"));
    assert!(message("T1.5\n").ends_with("is a whole number"));
}

/// A `/` (block skip) is refused at the slash, in a block and in a G31 call alike (in a
/// G31's contour: `corpus/bad/heidenhain/g31-model-limits.nc`).
#[test]
fn a_block_skip_is_refused_where_it_stands() {
    let refusal = |text: &str| {
        let (_, d) = read_with(text, &full());
        d.into_iter()
            .find(|d| d.is_error())
            .map(|d| (d.code.id, d.location.map_or(0, |l| l.column), d.message))
            .unwrap_or_default()
    };
    let (code, column, message) = refusal("/N10 G0 X20 Z5\n");
    assert_eq!((code, column), ("HEIR002", 1));
    assert!(message.starts_with("`/` (block skip): "), "{message}");
    let (code, _, message) = refusal("/N10 G31 F1.5 U0.92 B2 P2 IC4\n");
    assert_eq!(code, "HEIR002");
    assert!(message.starts_with("`/` (block skip): "), "{message}");
}

use super::*;
use crate::diag::Severity;
use crate::dialect::nc31::profile::Nc31ArcDirection;
use crate::ir::{EndCode, Pos, Schedule, SpindleDirection, TapCycle, ThreadPass};

fn run(text: &str) -> (Program, Vec<Diagnostic>) {
    run_with(text, &Nc31Profile::default(), Unsupported::Error)
}

fn run_with(
    text: &str,
    profile: &Nc31Profile,
    unsupported: Unsupported,
) -> (Program, Vec<Diagnostic>) {
    parse(
        &SourceFile::new("t.nc", text),
        profile,
        &Options { unsupported },
    )
}

fn kinds(text: &str) -> Vec<ItemKind> {
    let (program, diags) = run(text);
    assert!(diags.is_empty(), "{text:?}: {diags:?}");
    program.items.into_iter().map(|i| i.kind).collect()
}

fn mm(v: f64) -> Length {
    Length::from_mm_f64(v)
}

/// (code, line, column) of the first error.
fn first_error(text: &str) -> (&'static str, u32, u32) {
    let (_, diags) = run(text);
    let d = diags
        .iter()
        .find(|d| d.is_error())
        .unwrap_or_else(|| panic!("no error for {text:?}"));
    let loc = d.location.as_ref().expect("located");
    assert!(d.help.is_some(), "{text:?}: no help");
    (d.code.id, loc.line, loc.column)
}

const START: &str = "N0 M3\nN1 S700\nN2 X3600 ~ *\nN3 Z450 ~\n";

#[test]
fn groups_move_both_axes_at_once_rapid_if_any_frame_says_so() {
    let k = kinds("N3 F30\nN4 X10000 ~ *\nN5 Z5000\nN6 X3600\nN7 Z-100 @\n");
    assert_eq!(
        k,
        vec![
            // The F frame of its own stays (no move of its group uses it).
            ItemKind::FeedRate(mm(0.3)),
            ItemKind::Rapid {
                to: Pos::new(mm(100.0), mm(50.0))
            },
            ItemKind::Feed {
                to: Pos {
                    x: Some(mm(36.0)),
                    z: None
                },
                feed: mm(0.3)
            },
            ItemKind::Feed {
                to: Pos {
                    x: None,
                    z: Some(mm(49.0))
                },
                feed: mm(0.3)
            },
        ]
    );
}

#[test]
fn spindle_tool_and_speed_range_words() {
    let k = kinds("N0 M40\nN1 M3\nN2 S700\nN6 T5\nN17 M5\nN18 M30\n");
    assert_eq!(
        k,
        vec![
            ItemKind::GearRange {
                code: 40,
                machine: super::super::ID,
            },
            ItemKind::Spindle {
                speed: None,
                direction: Some(SpindleDirection::Clockwise)
            },
            ItemKind::Spindle {
                speed: Some(700),
                direction: None
            },
            ItemKind::Tool {
                number: Some(5),
                offset: None
            },
            ItemKind::SpindleStop,
            ItemKind::ProgramEnd(EndCode::M30),
        ]
    );
    // One group: S and M4 become one spindle item.
    let k = kinds("M4 *\nS150\n");
    assert_eq!(
        k,
        vec![ItemKind::Spindle {
            speed: Some(150),
            direction: Some(SpindleDirection::CounterClockwise)
        }]
    );
}

#[test]
fn g31_becomes_one_cycle_from_the_start_point() {
    let text =
        format!("{START}N9 G31 *\nN10 X3600 *\nN11 Z-4750 *\nN12 F15000 *\nN13 P96 *\nN14 P20\n");
    let (program, diags) = run(&text);
    assert!(diags.is_empty(), "{diags:?}");
    let item = program.items.last().unwrap();
    assert_eq!(item.block_number, Some(9));
    assert_eq!((item.span.line, item.span.column), (5, 1));
    let ItemKind::ThreadCycle(c) = &item.kind else {
        panic!("{:?}", item.kind)
    };
    assert_eq!(c.start, (mm(36.0), mm(4.5)));
    assert_eq!(c.crest, mm(36.0));
    assert_eq!(c.end_z, mm(-47.5));
    assert_eq!(c.lead, crate::fixed::Lead::from_mm_f64(1.5).unwrap());
    assert_eq!(
        (c.depth, c.first_depth, c.taper),
        (mm(0.96), mm(0.2), Length::ZERO)
    );
    assert!(!c.internal);
    assert_eq!(c.retract, crate::ir::Retract::AboveCrest(mm(0.5)));
    assert_eq!(c.schedule, Schedule::Halving);
    // `Z-5200 @` from Z4.5 is the same end.
    let inc = text.replace("Z-4750 *", "Z-5200 @ *");
    let (program, _) = run(&inc);
    assert_eq!(program.items.last().unwrap().kind, item.kind);
}

#[test]
fn g31_takes_parameters_6_and_7_and_the_taper() {
    let profile = Nc31Profile {
        infeed_p6: 2365,
        runout_p7: 10,
        ..Default::default()
    };
    let text = format!("{START}G31 *\nX3600 *\nZ-4750 *\nF15000 *\nP96 *\nP20 *\nP676\n");
    let (program, diags) = run_with(&text, &profile, Unsupported::Error);
    assert!(diags.is_empty(), "{diags:?}");
    let ItemKind::ThreadCycle(c) = &program.items.last().unwrap().kind else {
        panic!()
    };
    assert_eq!(c.infeed.of(mm(0.96)), mm(0.5543));
    assert_eq!(c.runout.map(|r| r.length), Some(mm(1.5)));
    assert_eq!(c.taper, mm(6.76));
    // A start inside the thread diameter: internal.
    let text = "M3\nS100\nX2000 ~ *\nZ500 ~\nG31 *\nX2200 *\nZ-3000 *\nF15000 *\nP50 *\nP20\n";
    let (program, diags) = run(text);
    assert!(diags.is_empty(), "{diags:?}");
    assert!(matches!(&program.items.last().unwrap().kind, ItemKind::ThreadCycle(c) if c.internal));
}

/// Arc groups where the profile declares them: the centre from unsigned offsets and
/// the quadrant, quarter arcs, and the refusals.
#[test]
fn arc_groups_take_their_centre_from_the_quadrant() {
    let profile = |direction| Nc31Profile {
        arcs: true,
        arc_direction: direction,
        ..Default::default()
    };
    let arc = |direction, text: &str| {
        let head = "M3\nS500\nX2000 ~ *\nZ0 ~\nF10\n";
        let (p, d) = run_with(
            &format!("{head}{text}"),
            &profile(direction),
            Unsupported::Error,
        );
        let arc = p.items.iter().find_map(|i| match &i.kind {
            ItemKind::Arc {
                centre, clockwise, ..
            } => Some((**centre, *clockwise)),
            _ => None,
        });
        (arc, d.iter().find(|d| d.is_error()).map(|d| d.code.id))
    };
    let iso = Some(Nc31ArcDirection::Iso);
    let front = Some(Nc31ArcDirection::FrontTool);
    // From Ø20 Z0 to Ø30 Z-5 around r10 Z-5 (ISO G3) or r15 Z0 (ISO G2).
    let g = |code: &str| format!("{code} *\nX3000 *\nZ-500 *\nP0 *\nP500\n");
    assert_eq!(
        arc(iso, &g("G3")),
        (Some((Pos::new(mm(20.0), mm(-5.0)), false)), None)
    );
    assert_eq!(
        arc(front, &g("G2")),
        (Some((Pos::new(mm(20.0), mm(-5.0)), false)), None)
    );
    let g = |code: &str| format!("{code} *\nX3000 *\nZ-500 *\nP500 *\nP0\n");
    assert_eq!(
        arc(iso, &g("G2")),
        (Some((Pos::new(mm(30.0), mm(0.0)), true)), None)
    );
    // Quarter arcs.
    let q = |code: &str| format!("{code} *\nX3000 *\nZ-500\n");
    assert_eq!(
        arc(iso, &q("G13")),
        (Some((Pos::new(mm(20.0), mm(-5.0)), false)), None)
    );
    assert_eq!(
        arc(iso, &q("G12")),
        (Some((Pos::new(mm(30.0), mm(0.0)), true)), None)
    );
    // Refused: no direction declared, offsets that fit no centre, a quarter that is
    // not one, a missing P, arcs not declared at all.
    assert_eq!(arc(None, &q("G13")).1, Some("NCR016"));
    assert_eq!(
        arc(iso, "G3 *\nX3000 *\nZ-500 *\nP100 *\nP500\n").1,
        Some("NCR016")
    );
    assert_eq!(arc(iso, "G13 *\nX3000 *\nZ-700\n").1, Some("NCR016"));
    assert_eq!(arc(iso, "G3 *\nX3000 *\nZ-500 *\nP0\n").1, Some("NCR016"));
    let (_, d) = run("M3\nS500\nX2000 ~ *\nZ0 ~\nF10\nG13 *\nX3000 *\nZ-500\n");
    assert_eq!(
        d.iter().find(|d| d.is_error()).map(|d| d.code.id),
        Some("NCR005")
    );
}

#[test]
fn g32_is_one_pass_at_the_current_diameter() {
    let k = kinds(&format!("{START}N9 G32 *\nN10 F15000 *\nN11 Z-4700\n"));
    assert_eq!(
        k.last(),
        Some(&ItemKind::pass(ThreadPass {
            to: Pos::new(mm(36.0), mm(-47.0)),
            lead: crate::fixed::Lead::from_mm_f64(1.5).unwrap(),
            start: crate::ir::SyncStart::default(),
            infeed: None,
            entry: None,
            exit: None
        }))
    );
}

#[test]
fn g33_taps_and_moves_to_point_c_with_the_offset() {
    let text =
        "M3\nS150\nX0 ~ *\nZ600 ~\nN9 G33 @ *\nN10 X2000 *\nN11 Z-10000 *\nN12 F15000\nX10000 ~\n";
    let k = kinds(text);
    assert_eq!(
        k[3],
        ItemKind::TapCycle(TapCycle {
            end_z: mm(-100.0),
            lead: crate::fixed::Lead::from_mm_f64(1.5).unwrap(),
            then_x: Some(mm(20.0))
        })
    );
    // Without `@`, X must be where the tool is.
    let k = kinds("M3\nS150\nX0 ~ *\nZ600 ~\nG33 *\nX0 *\nZ-10000 *\nF15000\n");
    assert!(matches!(
        k[3],
        ItemKind::TapCycle(TapCycle { then_x: None, .. })
    ));
}

#[test]
fn feed_is_undefined_after_a_thread_group() {
    let text = format!("N3 F30\n{START}N9 G32 *\nN10 F15000 *\nN11 Z-4700\nN12 X4000\n");
    assert_eq!(first_error(&text), ("NCR008", 9, 5));
    let (_, diags) = run(&text);
    assert!(diags[0].message.contains("line 6"), "{}", diags[0].message);
    // F60 after the pass defines it again (the seed's program).
    let ok = format!("N3 F30\n{START}N9 G32 *\nN10 F15000 *\nN11 Z-4700\nN12 F60\nN13 X4000\n");
    assert!(run(&ok).1.is_empty());
}

#[test]
fn every_rule_has_its_code_and_place() {
    let g31 =
        |p1: &str, p2: &str| format!("{START}G31 *\nX3600 *\nZ-4750 *\nF15000 *\n{p1} *\n{p2}\n");
    let cases: Vec<(String, (&str, u32, u32))> = vec![
        ("X36.00".into(), ("NCR002", 1, 4)),
        ("N4 X3600 Z450".into(), ("NCR003", 1, 10)),
        ("N4 F30 ~".into(), ("NCR004", 1, 8)),
        ("N4 S700 @".into(), ("NCR004", 1, 9)),
        ("N4 G1 *\nX100".into(), ("NCR005", 1, 4)),
        ("N4 M8".into(), ("NCR005", 1, 4)),
        ("N4 H5".into(), ("NCR005", 1, 4)),
        ("N4 F0".into(), ("NCR006", 1, 4)),
        ("N4 S-5".into(), ("NCR006", 1, 4)),
        ("N4 X100 @".into(), ("NCR007", 1, 9)),
        (
            "N4 G31 *\nX3600 *\nZ-4750 *\nF15000 *\nP96 *\nP20".into(),
            ("NCR007", 1, 4),
        ),
        ("N4 X3600".into(), ("NCR008", 1, 4)),
        ("N4 X3600 ~ *".into(), ("NCR009", 1, 4)),
        ("N4 X3600 ~ *\n%".into(), ("NCR009", 2, 1)),
        (
            format!("{START}G31 *\nX3600 *\nZ-4750 *\nP96 *\nP20\n"),
            ("NCR010", 5, 1),
        ),
        (format!("{START}G32 *\nF15000\n"), ("NCR010", 5, 1)),
        (
            format!("{START}G33 @ *\nZ-100 *\nF15000\n"),
            ("NCR010", 5, 1),
        ),
        (
            format!("{START}G32 *\nX3500 *\nF15000 *\nZ-4700\n"),
            ("NCR011", 6, 1),
        ),
        (
            format!("{START}G31 *\nX3600 *\nZ-4750 *\nF15000 *\nS700 *\nP96 *\nP20\n"),
            ("NCR011", 9, 1),
        ),
        (
            format!("{START}G31 *\nX3600 *\nX3600 *\nZ-4750 *\nF15000 *\nP96 *\nP20\n"),
            ("NCR011", 7, 1),
        ),
        (
            format!("{START}X3600 *\nG32 *\nF15000 *\nZ-4700\n"),
            ("NCR011", 6, 1),
        ),
        (format!("{START}P20\n"), ("NCR011", 5, 1)),
        (
            format!("{START}G33 *\nX2000 *\nZ-100 *\nF15000\n"),
            ("NCR011", 6, 1),
        ),
        (g31("P30", "P20"), ("NCR012", 9, 1)),
        (g31("P96", "P0"), ("NCR012", 10, 1)),
        (
            format!("{START}G31 *\nX3600 *\nZ-4750 *\nF15000 *\nP96 *\nP20 *\nP-10\n"),
            ("NCR012", 11, 1),
        ),
        (format!("{START}G32 *\nF0 *\nZ-4700\n"), ("NCR013", 6, 1)),
        (
            format!("{START}G31 *\nX3600 *\nZ450 *\nF15000 *\nP96 *\nP20\n"),
            ("NCR014", 7, 1),
        ),
        (format!("{START}G32 *\nF15000 *\nZ0 @\n"), ("NCR014", 7, 1)),
        ("N4 G31 ~ *\nX1".into(), ("NCR004", 1, 8)),
        ("N4 X100 (comment".into(), ("NCR001", 1, 9)),
    ];
    for (text, expected) in &cases {
        assert_eq!(first_error(text), *expected, "{text:?}");
    }
}

#[test]
fn runout_that_does_not_fit_is_refused_at_z() {
    let profile = Nc31Profile {
        runout_p7: 31,
        ..Default::default()
    };
    // 3.1 leads of 2 = 6.2 mm; the pass is 5 mm long.
    let text = "M3\nS100\nX3600 ~ *\nZ0 ~\nG31 *\nX3600 *\nZ-500 *\nF20000 *\nP96 *\nP20\n";
    let (_, diags) = run_with(text, &profile, Unsupported::Error);
    assert_eq!(diags[0].code, codes::NCR_TRAVEL);
    assert_eq!(diags[0].location.as_ref().unwrap().line, 7);
}

#[test]
fn a_bad_frame_inside_a_group_does_not_cascade() {
    let (_, diags) = run("X36.00 ~ *\nZ450 ~\nF30\n");
    assert_eq!(diags.len(), 1, "{diags:?}");
    assert_eq!(diags[0].code, codes::NCR_DECIMAL_POINT);
}

#[test]
fn unsupported_warn_keeps_the_group_opaque_and_forgets_the_position() {
    let (program, diags) = run_with(
        "X100 ~ *\nZ100 ~\nN5 G4 *\nP100\nX10 @ ~\n",
        &Nc31Profile::default(),
        Unsupported::Warn,
    );
    assert_eq!(diags[0].severity, Severity::Warning);
    assert!(
        matches!(&program.items[1].kind, ItemKind::Opaque { block: Some(_), text, .. } if text == "N5 G4 *\nP100")
    );
    assert_eq!(program.items[1].block_number, Some(5));
    assert_eq!(diags[1].code, codes::NCR_UNKNOWN_POSITION);
}

#[test]
fn comments_and_delimiters_are_items() {
    let k = kinds("%\n(M36X1.5)\nM30\n%\n");
    assert_eq!(
        k,
        vec![
            ItemKind::Delimiter,
            ItemKind::Comment("M36X1.5".into()),
            ItemKind::ProgramEnd(EndCode::M30),
            ItemKind::Delimiter
        ]
    );
}

/// The items a chamfer group `text` makes from Ø20 Z0 at F20 (0.2 mm/rev).
fn chamfer(text: &str) -> Vec<ItemKind> {
    let k = kinds(&format!("M3\nS500\nX2000 ~ *\nZ0 ~\n{text}"));
    k[3..].to_vec()
}

fn feed(x: f64, z: f64, f: f64) -> ItemKind {
    ItemKind::Feed {
        to: Pos::new(mm(x), mm(z)),
        feed: mm(f),
    }
}

/// `X<end>±45 *` + `F`: X to its end, Z by half the diameter change, the sign giving
/// Z's direction; `Z<end>±45 *` + `F`: Z to its end, the diameter by twice the Z travel.
/// Read whatever the profile says (nc31.md: "Read it").
#[test]
fn chamfers_move_the_other_axis_by_the_same_radial_amount() {
    // X grows by 10 (radius 5): Z +5 or -5.
    assert_eq!(chamfer("X3000+45 *\nF20\n"), [feed(30.0, 5.0, 0.2)]);
    assert_eq!(chamfer("X3000-45 *\nF20\n"), [feed(30.0, -5.0, 0.2)]);
    // X shrinks: the sign still gives Z's direction.
    assert_eq!(chamfer("X1000+45 *\nF20\n"), [feed(10.0, 5.0, 0.2)]);
    assert_eq!(chamfer("X1000-45 *\nF20\n"), [feed(10.0, -5.0, 0.2)]);
    // Z travels 5: the diameter grows or shrinks by 10.
    assert_eq!(chamfer("Z-500+45 *\nF20\n"), [feed(30.0, -5.0, 0.2)]);
    assert_eq!(chamfer("Z-500-45 *\nF20\n"), [feed(10.0, -5.0, 0.2)]);
    assert_eq!(chamfer("Z300+45 *\nF20\n"), [feed(26.0, 3.0, 0.2)]);
    assert_eq!(chamfer("Z300-45 *\nF20\n"), [feed(14.0, 3.0, 0.2)]);
    // Incremental, and the F frame sets the feed for the moves after it.
    assert_eq!(
        chamfer("X1000 @ +45 *\nF15\nZ-2000\n"),
        [
            feed(30.0, 5.0, 0.15),
            ItemKind::Feed {
                to: Pos {
                    x: None,
                    z: Some(mm(-20.0))
                },
                feed: mm(0.15)
            }
        ]
    );
    assert_eq!(chamfer("Z-200@-45*\nF20\n"), [feed(16.0, -2.0, 0.2)]);
    // With a unit of 0.0001 mm half a diameter change can be off the grid: refused.
    let fine = Nc31Profile {
        linear_unit: Length::from_steps(1),
        ..Default::default()
    };
    let text = "M3\nS500\nX200000 ~ *\nZ0 ~\nN7 X200001+45 *\nF20\n";
    let (_, diags) = run_with(text, &fine, Unsupported::Error);
    assert_eq!(
        diags.iter().map(|d| d.code.id).collect::<Vec<_>>(),
        ["NCR017"]
    );
    let text = text.replace("X200001", "X200002");
    let (program, diags) = run_with(&text, &fine, Unsupported::Error);
    assert!(diags.is_empty(), "{diags:?}");
    assert_eq!(
        program.items.last().map(|i| &i.kind),
        Some(&ItemKind::Feed {
            to: Pos::new(Length::from_steps(200_002), Length::from_steps(1)),
            feed: mm(0.2)
        })
    );
}

#[test]
fn chamfer_rules_have_their_code_and_place() {
    let head = "M3\nS500\nX2000 ~ *\nZ0 ~\n";
    let cases: Vec<(String, (&str, u32, u32))> = vec![
        // Not closed by F, or F not last.
        (format!("{head}X3000+45\n"), ("NCR017", 5, 1)),
        (format!("{head}F20 *\nX3000+45\n"), ("NCR017", 5, 1)),
        // No travel.
        (format!("{head}X2000+45 *\nF20\n"), ("NCR017", 5, 1)),
        (format!("{head}Z0-45 *\nF20\n"), ("NCR017", 5, 1)),
        // A rapid mark, a word that does not belong, a second chamfer, a second F.
        (format!("{head}X3000+45 ~ *\nF20\n"), ("NCR004", 5, 10)),
        (format!("{head}X3000+45 *\nS700 *\nF20\n"), ("NCR011", 6, 1)),
        (format!("{head}X3000+45 *\nZ100 *\nF20\n"), ("NCR011", 6, 1)),
        (
            format!("{head}X3000+45 *\nZ100-45 *\nF20\n"),
            ("NCR011", 6, 1),
        ),
        (format!("{head}X3000+45 *\nF20 *\nF30\n"), ("NCR011", 7, 1)),
        // The mark on a word that is not the chamfer's X or Z.
        (format!("{head}X3000+45 *\nF20+45\n"), ("NCR004", 6, 4)),
        (
            format!("{head}G32 *\nF15000 *\nZ-100+45\n"),
            ("NCR004", 7, 6),
        ),
        (format!("{head}S700-45\n"), ("NCR004", 5, 5)),
        // A feed that is not positive, a start that is not known.
        (format!("{head}X3000+45 *\nF0\n"), ("NCR006", 6, 1)),
        ("X3000+45 *\nF20\n".into(), ("NCR007", 1, 1)),
    ];
    for (text, expected) in &cases {
        assert_eq!(first_error(text), *expected, "{text:?}");
    }
}

fn repeating() -> Nc31Profile {
    Nc31Profile {
        repeat_g25: true,
        ..Default::default()
    }
}

/// Grooves 5 mm apart: the frames N5 to N7 (incremental) run again twice at the G25.
const GROOVES: &str = "N0 M3\nN1 S500\nN2 X2000 ~ *\nN3 Z0 ~\nN4 F10\nN5 Z-500 @ ~\nN6 X-400 @\nN7 X400 @ ~\nN8 G25 *\nN9 P5007 *\nN10 P2\nN11 X5000 ~\n";

#[test]
fn g25_reads_the_frames_again_count_times() {
    let (program, diags) = run_with(GROOVES, &repeating(), Unsupported::Error);
    assert!(diags.is_empty(), "{diags:?}");
    let moves: Vec<(ItemKind, u32)> = program
        .items
        .iter()
        .skip(4)
        .map(|i| (i.kind.clone(), i.span.line))
        .collect();
    let z = |z: f64| ItemKind::Rapid {
        to: Pos {
            x: None,
            z: Some(mm(z)),
        },
    };
    let x = |x: f64, rapid: bool| {
        let to = Pos {
            x: Some(mm(x)),
            z: None,
        };
        if rapid {
            ItemKind::Rapid { to }
        } else {
            ItemKind::Feed { to, feed: mm(0.1) }
        }
    };
    let mut expected = Vec::new();
    for groove in 1..=3 {
        expected.extend([
            (z(-5.0 * groove as f64), 6),
            (x(16.0, false), 7),
            (x(20.0, true), 8),
        ]);
    }
    expected.push((x(50.0, true), 12));
    assert_eq!(moves, expected);
    // The repeated items keep their frames' numbers.
    assert_eq!(program.items[7].block_number, Some(5));
    // Without the profile's key G25 is refused by name (the help names the key), also
    // when kept as written: one error, at the G25.
    for unsupported in [Unsupported::Error, Unsupported::Warn] {
        let (_, diags) = run_with(GROOVES, &Nc31Profile::default(), unsupported);
        assert_eq!(diags.len(), 1, "{diags:?}");
        let d = &diags[0];
        assert_eq!(
            (
                d.code,
                d.severity,
                d.location.as_ref().map(|l| (l.line, l.column))
            ),
            (codes::NCR_UNSUPPORTED, Severity::Error, Some((9, 4)))
        );
        let help = d.help.as_deref().unwrap_or_default();
        assert!(help.contains("repeat_g25 = true"), "{help}");
    }
    // With the key, a G25 group that also holds a word ncthread does not read is not kept as
    // written under warn either: the repeat would not run in ncthread's reading, and its P
    // names frames by numbers the writer may give to other frames.
    let kept = GROOVES.replace("N8 G25 *\n", "N8 G25 *\nM7 *\n");
    let (_, diags) = run_with(&kept, &repeating(), Unsupported::Warn);
    assert!(
        diags.iter().any(|d| d.is_error()
            && d.code == codes::NCR_UNSUPPORTED
            && d.message.starts_with("`G25` in a group kept opaque")),
        "{diags:?}"
    );
}

#[test]
fn g25_repeats_absolute_frames_as_the_control_does() {
    // An absolute move repeated goes to the same place again.
    let text =
        "N0 M3\nN1 S500\nN2 X2000 ~ *\nN3 Z0 ~\nN4 F10\nN5 Z-100\nN6 G25 *\nN7 P5005 *\nN8 P3\n";
    let (program, diags) = run_with(text, &repeating(), Unsupported::Error);
    assert!(diags.is_empty(), "{diags:?}");
    let feeds = program
        .items
        .iter()
        .filter(|i| matches!(i.kind, ItemKind::Feed { .. }))
        .count();
    assert_eq!(feeds, 4);
}

#[test]
fn g25_rules_have_their_code_and_place() {
    let head =
        "N0 M3\nN1 S500\nN2 X2000 ~ *\nN3 Z0 ~\nN4 F10\nN5 Z-500 @ ~\nN6 X-400 @\nN7 X400 @ ~\n";
    let g25 = |range: &str, count: &str| format!("{head}N8 G25 *\nN9 {range} *\nN10 {count}\n");
    let cases: Vec<(String, (&str, u32, u32))> = vec![
        // The range: backwards, not in the program, holding the G25, negative.
        (g25("P7005", "P2"), ("NCR018", 10, 4)),
        (g25("P20021", "P2"), ("NCR018", 10, 4)),
        (g25("P5008", "P2"), ("NCR018", 10, 4)),
        (g25("P5009", "P2"), ("NCR018", 10, 4)),
        (g25("P-5007", "P2"), ("NCR018", 10, 4)),
        // Inside a group: N3 ends the group N2–N3, N2 starts it.
        (g25("P3007", "P2"), ("NCR018", 10, 4)),
        (g25("P2002", "P2"), ("NCR018", 10, 4)),
        // The count: under 1, or too many frames in all.
        (g25("P5007", "P0"), ("NCR018", 11, 5)),
        (g25("P5007", "P-1"), ("NCR018", 11, 5)),
        (g25("P5007", "P3334"), ("NCR018", 11, 5)),
        // Missing P words, another word.
        (format!("{head}N8 G25 *\nN9 P5007\n"), ("NCR018", 9, 4)),
        (format!("{head}N8 G25\n"), ("NCR018", 9, 4)),
        (
            format!("{head}N8 G25 *\nN9 X100 *\nN10 P5007 *\nN11 P2\n"),
            ("NCR011", 10, 4),
        ),
        (
            format!("{head}N8 G25 ~ *\nN9 P5007 *\nN10 P2\n"),
            ("NCR004", 9, 8),
        ),
        // A repeat of a repeat.
        (
            format!("{head}N8 G25 *\nN9 P5007 *\nN10 P1\nN11 G25 *\nN12 P5010 *\nN13 P1\n"),
            ("NCR018", 13, 5),
        ),
        // Two frames numbered N5, frame numbers out of order.
        (
            format!("{head}N5 X2000 ~\nN8 G25 *\nN9 P5007 *\nN10 P2\n"),
            ("NCR018", 11, 4),
        ),
        (
            format!("{head}N1 X2000 ~\nN8 G25 *\nN9 P7001 *\nN10 P2\n"),
            ("NCR018", 11, 4),
        ),
    ];
    for (text, expected) in &cases {
        let (_, diags) = run_with(text, &repeating(), Unsupported::Error);
        let d = diags
            .iter()
            .find(|d| d.is_error())
            .unwrap_or_else(|| panic!("no error for {text:?}"));
        let loc = d.location.as_ref().expect("located");
        assert!(d.help.is_some(), "{text:?}: no help");
        assert_eq!(
            (d.code.id, loc.line, loc.column),
            *expected,
            "{text:?}: {}",
            d.message
        );
    }
    // The limit is over the whole program: 3334 × 3 frames is too many, and so are two
    // repeats of 1700 × 3.
    let text =
        format!("{head}N8 G25 *\nN9 P5007 *\nN10 P1700\nN11 G25 *\nN12 P5007 *\nN13 P1700\n");
    let (_, diags) = run_with(&text, &repeating(), Unsupported::Error);
    assert_eq!(
        diags
            .iter()
            .map(|d| (d.code.id, d.location.as_ref().unwrap().line))
            .collect::<Vec<_>>(),
        [("NCR018", 14)]
    );
}

/// A repeat that fails where its frames did not (the feed is undefined after a thread)
/// says so once, naming the G25; what the frames already said is not said again.
#[test]
fn a_repeat_reports_what_is_new_once() {
    let text = "N0 M3\nN1 S500\nN2 X2000 ~ *\nN3 Z0 ~\nN4 F10\nN5 Z-100\nN6 G32 *\nN7 F15000 *\nN8 Z-200\nN9 G25 *\nN10 P5005 *\nN11 P3\n";
    let (_, diags) = run_with(text, &repeating(), Unsupported::Error);
    assert_eq!(diags.len(), 1, "{diags:?}");
    assert_eq!(diags[0].code, codes::NCR_NO_FEED);
    assert_eq!(diags[0].location.as_ref().unwrap().line, 6);
    assert!(
        diags[0]
            .message
            .ends_with("(repeated by the G25 on line 10)"),
        "{}",
        diags[0].message
    );
    let text = "N0 M3\nN1 S500\nN2 X2000 ~ *\nN3 Z0 ~\nN5 Z-100\nN6 G25 *\nN7 P5005 *\nN8 P3\n";
    let (_, diags) = run_with(text, &repeating(), Unsupported::Error);
    assert_eq!(diags.len(), 1, "{diags:?}");
    assert!(!diags[0].message.contains("G25"), "{}", diags[0].message);
    // Many repeats of frames that failed add nothing (and stay quick: the diagnostics
    // reported are gathered once, not at every repeat), until the limit: 1666 repeats of
    // 6 frames fit in 10,000, the 334 after them are refused at their count.
    let mut text = String::from("N0 M3\nN1 S500\nN2 X2000 ~ *\nN3 Z0 ~\nN5 Z-100\n");
    for n in 0..2000 {
        text.push_str(&format!("N{} G25 *\nP5005 *\nP6\n", 6 + n));
    }
    let (_, diags) = run_with(&text, &repeating(), Unsupported::Error);
    // The 334 refusals: ten listed, the rest counted in the last (diag::Fold).
    assert_eq!(diags.len(), 1 + 10 + 1);
    assert_eq!(diags.iter().map(|d| d.count()).sum::<usize>(), 1 + 334);
    assert_eq!(diags[11].more, 334 - 11);
    assert_eq!(
        (diags[1].code, diags[1].location.as_ref().map(|l| l.line)),
        (codes::NCR_REPEAT, Some(8 + 3 * 1666))
    );
}

#[test]
fn units_come_from_the_profile() {
    let profile = Nc31Profile {
        linear_unit: Length::from_steps(10),
        feed_unit: Length::from_steps(10),
        ..Default::default()
    };
    let (program, diags) = run_with("F300\nX36000 *\nZ4500\n", &profile, Unsupported::Error);
    assert!(diags.is_empty());
    assert_eq!(program.items[0].kind, ItemKind::FeedRate(mm(0.3)));
    assert_eq!(
        program.items[1].kind,
        ItemKind::Feed {
            to: Pos::new(mm(36.0), mm(4.5)),
            feed: mm(0.3)
        }
    );
}

/// An M number past u32 is no speed range that wraps onto a small one (M4294967337 was M41).
#[test]
fn a_huge_m_number_is_no_speed_range() {
    let (_, diags) = run("M4294967337\n");
    assert_eq!(diags[0].code, codes::NCR_UNSUPPORTED, "{diags:?}");
}

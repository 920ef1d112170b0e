//! Property tests: random valid programs survive emit → parse unchanged, for each dialect
//! that can express them (issue 5). The generated programs hold what both the czech control
//! and LinuxCNC can say: spindle start, rapids, feeds and thread passes along Z or tapers,
//! on the 0.001 mm grid (czech's), leads on the 0.0001 mm grid.
use ncthread::dialect::Dialect;
use ncthread::fixed::{Angle, Length};
use ncthread::ir::{FeedMode, Item, ItemKind, Pos, Program, SpindleDirection, ThreadPass};
use ncthread::source::{SourceFile, Span};
use ncthread::{ConvertOptions, Unsupported};
use proptest::prelude::*;

fn on_grid(range: std::ops::Range<i64>) -> impl Strategy<Value = Length> + Clone {
    // Whole thousandths of a millimetre.
    range.prop_map(|v| Length(v * 10))
}

#[derive(Clone, Debug)]
enum Step {
    Rapid(Length, Length),
    Feed(Length, Length, Length),
    Pass(Option<Length>, Length, Length, Angle),
}

fn step(with_angles: bool) -> impl Strategy<Value = Step> {
    let x = on_grid(1_000..200_000);
    let z = on_grid(-300_000..50_000);
    let angle = if with_angles {
        (0i64..360_000).boxed()
    } else {
        Just(0i64).boxed()
    };
    prop_oneof![
        (x.clone(), z.clone()).prop_map(|(x, z)| Step::Rapid(x, z)),
        (x.clone(), z.clone(), on_grid(1..2_000)).prop_map(|(x, z, f)| Step::Feed(x, z, f)),
        (proptest::option::of(x), z, (1i64..2_000_000), angle)
            .prop_map(|(x, z, lead, a)| Step::Pass(x, z, Length(lead), Angle(a))),
    ]
}

/// A program from the steps; a pass that would not move along Z is left out.
fn program(steps: &[Step]) -> Program {
    let item = |kind| Item::new(kind, Span::default());
    let mut items = vec![
        item(ItemKind::FeedMode(FeedMode::PerRev)),
        item(ItemKind::Spindle {
            speed: Some(500),
            direction: Some(SpindleDirection::Clockwise),
        }),
        item(ItemKind::Rapid {
            to: Pos::new(Length::from_mm(100), Length::from_mm(60)),
        }),
    ];
    let mut z_now = Length::from_mm(60);
    for s in steps {
        match *s {
            Step::Rapid(x, z) => {
                items.push(item(ItemKind::Rapid { to: Pos::new(x, z) }));
                z_now = z;
            }
            Step::Feed(x, z, feed) => {
                items.push(item(ItemKind::Feed {
                    to: Pos::new(x, z),
                    feed,
                }));
                z_now = z;
            }
            Step::Pass(x, z, lead, start_angle) if z != z_now => {
                items.push(item(ItemKind::ThreadPass(ThreadPass {
                    to: Pos { x, z: Some(z) },
                    lead,
                    start_angle,
                    entry: None,
                    exit: None,
                })));
                z_now = z;
            }
            Step::Pass(..) => {}
        }
    }
    Program { items }
}

/// The items that move the tool or the spindle, with positions made absolute.
fn motion(p: &Program) -> Vec<ItemKind> {
    let mut pos = Pos::UNKNOWN;
    let mut out = Vec::new();
    for i in &p.items {
        let kind = match &i.kind {
            ItemKind::Rapid { .. } | ItemKind::Feed { .. } => {
                let end = i.kind.end_position(pos);
                match &i.kind {
                    ItemKind::Rapid { .. } => ItemKind::Rapid { to: end },
                    ItemKind::Feed { feed, .. } => ItemKind::Feed {
                        to: end,
                        feed: *feed,
                    },
                    _ => unreachable!(),
                }
            }
            ItemKind::ThreadPass(pass) => {
                let end = i.kind.end_position(pos);
                ItemKind::ThreadPass(ThreadPass { to: end, ..*pass })
            }
            ItemKind::Spindle {
                direction: Some(_), ..
            }
            | ItemKind::SpindleStop => i.kind.clone(),
            _ => {
                pos = i.kind.end_position(pos);
                continue;
            }
        };
        pos = i.kind.end_position(pos);
        out.push(kind);
    }
    out
}

fn round_trip(program: &Program, to: Dialect) -> Program {
    let src = SourceFile::new("generated", "");
    let options = ConvertOptions {
        from: Dialect::Iso,
        to,
        profile: Default::default(),
        unsupported: Unsupported::Error,
        renumber: Default::default(),
        round: false,
    };
    let (text, diags) = ncthread::emit(program, &src, &options);
    let text = text.unwrap_or_else(|| panic!("not written as {to}: {diags:?}"));
    let back = SourceFile::new("emitted", text.clone());
    let (parsed, diags) = ncthread::parse(&back, to, &Default::default(), Unsupported::Error);
    assert!(
        !ncthread::diag::has_errors(&diags),
        "{to} output not read back: {diags:?}\n{text}"
    );
    parsed
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn czech_emit_then_parse_keeps_the_program(steps in proptest::collection::vec(step(true), 1..12)) {
        let p = program(&steps);
        prop_assert_eq!(motion(&round_trip(&p, Dialect::Czech)), motion(&p));
    }

    #[test]
    fn iso_emit_then_parse_keeps_the_program(steps in proptest::collection::vec(step(false), 1..12)) {
        let p = program(&steps);
        prop_assert_eq!(motion(&round_trip(&p, Dialect::Iso)), motion(&p));
    }
}

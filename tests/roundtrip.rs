//! Property tests: random valid programs survive emit → parse unchanged, for each dialect
//! that can express them (issue 5). The generated programs hold what both the czech control
//! and LinuxCNC can say: spindle start, rapids, feeds and thread passes along Z or tapers,
//! on the 0.001 mm grid (czech's), leads on the 0.0001 mm grid. For the НЦ-31: passes along
//! Z only, G31 cycles, values on its 0.01 mm grid.
use ncthread::DialectId;
use ncthread::fixed::{Angle, Lead, Length};
use ncthread::ir::{
    CycleChamfer, FeedMode, Finish, Item, ItemKind, Pos, Program, Retract, Rise, Schedule, Slope,
    SpindleDirection, SyncStart, ThreadCycle, ThreadPass,
};
use ncthread::source::{SourceFile, Span};
use ncthread::{ConvertOptions, Unsupported};
use proptest::prelude::*;

fn on_grid(range: std::ops::Range<i64>) -> impl Strategy<Value = Length> + Clone {
    // Whole thousandths of a millimetre.
    range.prop_map(|v| Length::from_steps(v * 10))
}

/// Whole hundredths of a millimetre (the НЦ-31's unit).
fn on_nc31_grid(range: std::ops::Range<i64>) -> impl Strategy<Value = Length> + Clone {
    range.prop_map(|v| Length::from_steps(v * 100))
}

#[derive(Clone, Debug)]
enum Step {
    Rapid(Length, Length),
    Feed(Length, Length, Length),
    Pass(Option<Length>, Length, Length, Angle),
    /// An arc from the current position around the centre at this offset (X as a radius,
    /// Z), to the point of its circle at this angle (0.001°), G2 when true.
    Arc(Length, Length, i64, bool, Length),
    /// A G31-style cycle from the current position: crest, end Z, lead, depth, first depth,
    /// runout (in tenths of the lead).
    Cycle(Length, Length, Length, Length, Length, i64),
}

fn nc31_step() -> impl Strategy<Value = Step> {
    let x = on_nc31_grid(100..20_000);
    let z = on_nc31_grid(-30_000..5_000);
    prop_oneof![
        (x.clone(), z.clone()).prop_map(|(x, z)| Step::Rapid(x, z)),
        (x.clone(), z.clone(), on_nc31_grid(1..200)).prop_map(|(x, z, f)| Step::Feed(x, z, f)),
        (z.clone(), 1i64..2_000_000).prop_map(|(z, lead)| Step::Pass(
            None,
            z,
            Length::from_steps(lead),
            Angle::ZERO
        )),
        (
            x,
            z,
            1i64..100_000,
            on_nc31_grid(1..300),
            on_nc31_grid(1..60),
            0i64..4
        )
            .prop_map(|(crest, z, lead, depth, first, p7)| Step::Cycle(
                crest,
                z,
                Length::from_steps(lead),
                depth,
                first,
                p7
            )),
    ]
}

fn step(with_angles: bool) -> BoxedStrategy<Step> {
    let x = on_grid(1_000..200_000);
    let z = on_grid(-300_000..50_000);
    let angle = if with_angles {
        (0i64..360_000).boxed()
    } else {
        Just(0i64).boxed()
    };
    let rapid = (x.clone(), z.clone()).prop_map(|(x, z)| Step::Rapid(x, z));
    let feed = (x.clone(), z.clone(), on_grid(1..2_000)).prop_map(|(x, z, f)| Step::Feed(x, z, f));
    let pass = (proptest::option::of(x), z, (1i64..2_000_000), angle)
        .prop_map(|(x, z, lead, a)| Step::Pass(x, z, Length::from_steps(lead), Angle(a)));
    if with_angles {
        // The czech control: no arcs.
        return prop_oneof![rapid, feed, pass].boxed();
    }
    let arc = (
        -300_000i64..300_000,
        -300_000i64..300_000,
        0i64..360_000,
        any::<bool>(),
        on_grid(1..2_000),
    )
        .prop_map(|(di, dk, a, cw, f)| {
            Step::Arc(Length::from_steps(di), Length::from_steps(dk), a, cw, f)
        });
    prop_oneof![rapid, feed, pass, arc].boxed()
}

/// A program from the steps; a pass that would not move along Z is left out. A pass right
/// after another continues it when `chains` (LinuxCNC's consecutive G33) and otherwise waits
/// for the index pulse there (the czech control, the НЦ-31).
fn program(steps: &[Step], chains: bool) -> Program {
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
    let mut x_now = Length::from_mm(100);
    for s in steps {
        let after_pass = matches!(items.last().map(|i| &i.kind), Some(ItemKind::ThreadPass(_)));
        match *s {
            Step::Rapid(x, z) => {
                items.push(item(ItemKind::Rapid { to: Pos::new(x, z) }));
                (x_now, z_now) = (x, z);
            }
            Step::Feed(x, z, feed) => {
                items.push(item(ItemKind::Feed {
                    to: Pos::new(x, z),
                    feed,
                }));
                (x_now, z_now) = (x, z);
            }
            Step::Cycle(crest, end_z, lead, depth, first_depth, p7) => {
                let cycle = ThreadCycle {
                    start: (x_now, z_now),
                    crest,
                    end_z,
                    lead: Lead::from_length(lead),
                    depth,
                    first_depth,
                    taper: Length::ZERO,
                    infeed: Slope { rise: 0, run: 4096 },
                    infeed_moves_end: false,
                    start_angle: Angle::ZERO,
                    entry: None,
                    entry_infeed: false,
                    runout: (p7 > 0).then(|| CycleChamfer {
                        length: lead.mul_div(p7, 10),
                        rise: Rise::ToCrest,
                    }),
                    retract: Retract::AboveCrest(Length::from_steps(5_000)),
                    spring_passes: 0,
                    finish: Finish::Start,
                    internal: x_now < crest,
                    schedule: Schedule::Halving,
                };
                // Only cycles that can be cut (depths, travel) and whose start is not on
                // the crest line.
                if x_now != crest && ncthread::lower::expand(&cycle).is_ok() {
                    items.push(item(ItemKind::ThreadCycle(Box::new(cycle))));
                }
            }
            Step::Pass(x, z, lead, start_angle) if z != z_now => {
                let start = if chains && after_pass {
                    SyncStart::Continue
                } else {
                    SyncStart::Index(start_angle)
                };
                items.push(item(ItemKind::pass(ThreadPass {
                    to: Pos { x, z: Some(z) },
                    lead: Lead::from_length(lead),
                    start,
                    infeed: None,
                    entry: None,
                    exit: None,
                })));
                if let Some(x) = x {
                    x_now = x;
                }
                z_now = z;
            }
            Step::Pass(..) => {}
            Step::Arc(di, dk, angle, clockwise, feed) => {
                // The centre on the diameter grid; the end on the circle, rounded onto it.
                let (cx, cz) = (x_now + di + di, z_now + dk);
                let radius = (di.to_mm_f64()).hypot(dk.to_mm_f64());
                let a = (angle as f64 / 1000.0).to_radians();
                let (ex, ez) = (
                    Length::from_mm_f64(cx.to_mm_f64() + 2.0 * radius * a.sin()),
                    Length::from_mm_f64(cz.to_mm_f64() + radius * a.cos()),
                );
                if radius >= 0.01 {
                    items.push(item(ItemKind::Arc {
                        to: Pos::new(ex, ez),
                        centre: Box::new(Pos::new(cx, cz)),
                        clockwise,
                        feed,
                    }));
                    (x_now, z_now) = (ex, ez);
                }
            }
        }
    }
    Program {
        items,
        dialect: ncthread::dialect::iso::ID,
        library: Vec::new(),
        number: None,
        name: None,
        inch: false,
    }
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
                ItemKind::pass(ThreadPass { to: end, ..**pass })
            }
            ItemKind::ThreadCycle(_)
            | ItemKind::Arc { .. }
            | ItemKind::Spindle {
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

fn round_trip(program: &Program, to: DialectId) -> Program {
    round_trip_with(program, to, &Default::default())
}

fn round_trip_with(
    program: &Program,
    to: DialectId,
    profile: &ncthread::profile::Profile,
) -> Program {
    let src = SourceFile::new("generated", "");
    let options = ConvertOptions {
        from: ncthread::dialect::iso::ID,
        to,
        profile: profile.clone(),
        unsupported: Unsupported::Error,
        renumber: Default::default(),
        round: false,
        nc31_comments: false,
    };
    let (text, diags) = ncthread::emit(program, &src, &options);
    let text = text.unwrap_or_else(|| panic!("not written as {to}: {diags:?}"));
    let back = SourceFile::new("emitted", text.clone());
    let (parsed, diags) = ncthread::parse(&back, to, profile, Unsupported::Error);
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
        let p = program(&steps, false);
        prop_assert_eq!(motion(&round_trip(&p, ncthread::dialect::czech::ID)), motion(&p));
    }

    #[test]
    fn iso_emit_then_parse_keeps_the_program(steps in proptest::collection::vec(step(false), 1..12)) {
        let p = program(&steps, true);
        prop_assert_eq!(motion(&round_trip(&p, ncthread::dialect::iso::ID)), motion(&p));
    }

    #[test]
    fn nc31_emit_then_parse_keeps_the_program(
        steps in proptest::collection::vec(nc31_step(), 1..12),
        p7 in 0u32..4,
    ) {
        // The cycles' runout is the profile's parameter 7, so that they stay G31 groups;
        // the others become G32 passes or are refused.
        let mut profile = ncthread::profile::Profile::default();
        profile.nc31.runout_p7 = p7;
        let p = program(&steps, false);
        let p = Program {
            dialect: p.dialect,
            library: Vec::new(),
            number: None,
            name: None,
            inch: false,
            items: p
                .items
                .into_iter()
                .filter(|i| match &i.kind {
                    ItemKind::ThreadCycle(c) => {
                        c.runout.map_or(0, |r| r.length.0) == profile.nc31.runout(c.lead).0
                    }
                    _ => true,
                })
                .collect(),
        };
        prop_assert_eq!(motion(&round_trip_with(&p, ncthread::dialect::nc31::ID, &profile)), motion(&p));
    }
}

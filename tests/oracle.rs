//! LinuxCNC's rs274 as the oracle: every ISO conversion of the corpus must run in the real
//! interpreter, and the seed acceptance figures are read back from its canonical calls.
mod common;

use common::{Case, close, convert_case, corpus_cases, rs274, run_rs274, sync_moves};

fn case(name: &str) -> Case {
    corpus_cases()
        .into_iter()
        .find(|c| c.name == name)
        .unwrap_or_else(|| panic!("no corpus case {name}"))
}

fn iso(name: &str) -> String {
    let conversion = convert_case(&case(name), ncthread::dialect::iso::ID);
    conversion
        .output
        .unwrap_or_else(|| panic!("{name} was refused: {:?}", conversion.diagnostics))
        .into()
}

#[test]
fn every_iso_conversion_runs_in_rs274() {
    let Some(cmd) = rs274() else { return };
    let mut checked = 0;
    for case in corpus_cases() {
        if let Some(ngc) = convert_case(&case, ncthread::dialect::iso::ID).output {
            run_rs274(cmd, &ngc).unwrap_or_else(|e| panic!("{}: {e}\n{ngc}", case.name));
            checked += 1;
        }
    }
    assert!(checked >= 12, "only {checked} conversions reached rs274");
}

#[test]
fn seed_entry_example_runs_from_71_798_to_64_then_to_z3() {
    let Some(cmd) = rs274() else { return };
    let moves =
        sync_moves(&run_rs274(cmd, &iso("czech/ex6b-entry-param-with-point+profile")).unwrap());
    assert_eq!(moves.len(), 2, "{moves:?}");
    let (entry, thread) = (&moves[0], &moves[1]);
    assert!(
        close(entry.from.0, 71.798, 1e-3) && close(entry.from.1, -100.0, 1e-4),
        "{entry:?}"
    );
    assert!(
        close(entry.to.0, 64.0, 1e-3) && close(entry.to.1, -88.0, 1e-4),
        "{entry:?}"
    );
    assert!(
        close(thread.to.0, 64.0, 1e-3) && close(thread.to.1, 3.0, 1e-4),
        "{thread:?}"
    );
    for m in &moves {
        assert!(close(m.z_lead, 6.0, 1e-5), "lead along Z {m:?}");
    }
}

#[test]
fn seed_taper_is_one_g33_with_z_lead_1_5() {
    let Some(cmd) = rs274() else { return };
    let moves = sync_moves(&run_rs274(cmd, &iso("czech/ex3-taper")).unwrap());
    assert_eq!(moves.len(), 1, "{moves:?}");
    let m = &moves[0];
    assert!(
        close(m.from.0, 226.0, 1e-4) && close(m.from.1, 3.0, 1e-4),
        "{m:?}"
    );
    assert!(
        close(m.to.0, 246.0, 1e-4) && close(m.to.1, -100.0, 1e-4),
        "{m:?}"
    );
    assert!(close(m.k, 1.50705, 1e-5), "{m:?}");
    assert!(close(m.z_lead, 1.5, 1e-5), "{m:?}");
}

#[test]
fn lead_250_through_a_parameter_converts() {
    let Some(cmd) = rs274() else { return };
    let moves = sync_moves(&run_rs274(cmd, &iso("czech/ex7-large-pitch")).unwrap());
    assert_eq!(moves.len(), 1);
    assert!(
        close(moves[0].k, 250.0, 1e-9) && close(moves[0].to.1, 200.0, 1e-4),
        "{moves:?}"
    );
}

#[test]
fn start_angle_becomes_the_same_helix_one_half_lead_earlier() {
    let Some(cmd) = rs274() else { return };
    let moves = sync_moves(&run_rs274(cmd, &iso("czech/multistart-i180")).unwrap());
    assert_eq!(moves.len(), 2);
    // Second start: lead 3, 180° → starts 1.5 mm before Z5, at the index pulse.
    assert!(
        close(moves[1].from.1, 6.5, 1e-4) && close(moves[1].to.1, -30.0, 1e-4),
        "{moves:?}"
    );
    assert!(close(moves[1].z_lead, 3.0, 1e-6));
}

/// The traverses rs274 runs after the last synchronised move, as (diameter, Z).
fn traverses_after_last_sync(canon: &[common::Canon]) -> Vec<(f64, f64)> {
    let last = canon
        .iter()
        .rposition(|c| matches!(c, common::Canon::SyncStop))
        .expect("a synchronised move");
    canon[last..]
        .iter()
        .filter_map(|c| match *c {
            common::Canon::Traverse { x, z } => Some((x, z)),
            _ => None,
        })
        .collect()
}

fn assert_points(actual: &[(f64, f64)], expected: &[(f64, f64)]) {
    assert_eq!(actual.len(), expected.len(), "{actual:?}");
    for (a, e) in actual.iter().zip(expected) {
        assert!(
            close(a.0, e.0, 1e-4) && close(a.1, e.1, 1e-4),
            "{actual:?} vs {expected:?}"
        );
    }
}

#[test]
fn seed_g31_m36_cuts_eight_passes_then_returns_to_the_start() {
    let Some(cmd) = rs274() else { return };
    // nc31.md: cumulative depths 0.2, 0.4, 0.6, 0.7725, 0.8725, 0.9225, 0.9475, 0.96 on Ø36.
    let diameters = [35.6, 35.2, 34.8, 34.455, 34.255, 34.155, 34.105, 34.08];
    for name in ["nc31/g31-m36x1.5", "nc31/g31-m36x1.5-incremental-z"] {
        let canon = run_rs274(cmd, &iso(name)).unwrap();
        let moves = sync_moves(&canon);
        assert_eq!(moves.len(), 8, "{name}: {moves:?}");
        for (m, d) in moves.iter().zip(diameters) {
            assert_points(&[m.from, m.to], &[(d, 4.5), (d, -47.5)]);
            assert!(close(m.z_lead, 1.5, 1e-9), "{name}: {m:?}");
        }
        // Retract above the crest (Ø36 + 2·0.5), back to Z4.5, back to the start Ø36; then
        // the program's own N15/N16 return to Ø100 Z50.
        assert_points(
            &traverses_after_last_sync(&canon),
            &[(37.0, -47.5), (37.0, 4.5), (36.0, 4.5), (100.0, 50.0)],
        );
    }
}

#[test]
fn seed_g32_cuts_three_passes() {
    let Some(cmd) = rs274() else { return };
    let moves = sync_moves(&run_rs274(cmd, &iso("nc31/g32-three-passes")).unwrap());
    assert_eq!(moves.len(), 3, "{moves:?}");
    for (m, d) in moves.iter().zip([35.0, 34.4, 34.08]) {
        assert_points(&[m.from, m.to], &[(d, 4.5), (d, -47.0)]);
        assert!(close(m.z_lead, 1.5, 1e-9), "{m:?}");
    }
}

#[test]
fn seed_g33_taps_to_z_minus_100_then_moves_to_diameter_20() {
    let Some(cmd) = rs274() else { return };
    let canon = run_rs274(cmd, &iso("nc31/g33-tap-m20x1.5")).unwrap();
    let tap = canon
        .iter()
        .position(|c| matches!(c, common::Canon::RigidTap { .. }))
        .expect("a rigid tap");
    assert_eq!(canon[tap - 1], common::Canon::SyncStart { k: 1.5 });
    assert_eq!(canon[tap], common::Canon::RigidTap { x: 0.0, z: -100.0 });
    // The tap returns to Z6; then point C at Ø20.
    assert_eq!(canon[tap + 2], common::Canon::Traverse { x: 20.0, z: 6.0 });
}

#[test]
fn g31_runout_of_one_lead_ends_every_pass_on_the_crest() {
    let Some(cmd) = rs274() else { return };
    let moves = sync_moves(&run_rs274(cmd, &iso("nc31/g31-runout-p7+profile")).unwrap());
    assert_eq!(moves.len(), 16, "{moves:?}");
    for pair in moves.chunks(2) {
        assert!(close(pair[0].to.1, -46.0, 1e-4), "{pair:?}");
        assert_points(&[pair[1].to], &[(36.0, -47.5)]);
        for m in pair {
            assert!(close(m.z_lead, 1.5, 1e-6), "{m:?}");
        }
    }
}

/// Two independent readings of every conversion agree: the synchronised moves LinuxCNC runs
/// for the ISO output are the simulator's thread segments of the source program — same end
/// points, lead and helix phase; the start may be earlier along the line by less than a lead
/// (a start angle written as a shift).
#[test]
fn rs274_cuts_what_the_simulator_says_the_source_cuts() {
    use ncthread::sim::{Motion, Segment, normalise};
    let Some(cmd) = rs274() else { return };
    let synchronised =
        |s: &&Segment| matches!(s.motion, Motion::Sync { .. } | Motion::SyncRadial { .. });
    let mut checked = 0;
    for case in corpus_cases() {
        let Some(ngc) = convert_case(&case, ncthread::dialect::iso::ID).output else {
            continue;
        };
        let canon = run_rs274(cmd, &ngc).unwrap();
        // How far rs274's printed digits fix its helices (a small K over a long path).
        let slack = ncthread::sim::rs274::phase_uncertainty(&canon);
        let theirs = common::rs274_segments(&canon);
        let moves: Vec<_> = theirs.iter().filter(synchronised).collect();
        let sim = normalise(&common::simulate_case(&case).segments);
        let threads: Vec<_> = sim.iter().filter(synchronised).collect();
        // rs274's chain of collinear moves is normalised the same way.
        let moves_n = normalise(&moves.iter().map(|s| **s).collect::<Vec<_>>());
        assert_eq!(
            threads.len(),
            moves_n.len(),
            "{}: {threads:?}\n{moves_n:?}",
            case.name
        );
        for (s, m) in threads.iter().zip(&moves_n) {
            let mm = |v: Option<ncthread::fixed::Length>| v.map(|v| v.to_mm_f64());
            let here = format!("{} line {}: {s:?} vs {m:?}", case.name, s.line);
            let (tx, tz) = (mm(s.to.x), mm(s.to.z));
            let (mx, mz) = (mm(m.to.x).unwrap(), mm(m.to.z).unwrap());
            assert!(tz.is_some_and(|z| close(z, mz, 1e-3)), "end Z {here}");
            assert!(tx.is_none_or(|x| close(x, mx, 1e-3)), "end X {here}");
            match (s.motion, m.motion) {
                (
                    Motion::Sync { lead, phase: p, .. },
                    Motion::Sync {
                        lead: l, phase: q, ..
                    },
                ) => {
                    // rs274 prints radii to 0.0001 and K to 1e-6: the Z lead read back is
                    // that exact.
                    assert!(close(l.to_mm_f64(), lead.to_mm_f64(), 1e-4), "lead {here}");
                    if let (Some(z), Some(mz0)) = (mm(s.from.z), mm(m.from.z)) {
                        let towards = (mz - mz0).signum();
                        let earlier = towards * (z - mz0);
                        assert!(
                            earlier > -1e-3 && earlier < l.to_mm_f64() + 1e-3,
                            "start {here}"
                        );
                    }
                    // The helices where the cut starts (rs274 prints radii to 0.0001: the
                    // phase tolerance of `compare`).
                    if let (Some(_), Some(_), Some(z)) = (p, q, s.from.z) {
                        let (p, q) = (
                            s.spindle_angle_at(z).unwrap(),
                            m.spindle_angle_at(z).unwrap(),
                        );
                        let tolerance =
                            ncthread::sim::phase_tolerance(lead).to_deg_f64().max(slack);
                        let gap = (p.to_deg_f64() - q.to_deg_f64()).rem_euclid(360.0);
                        assert!(
                            gap.min(360.0 - gap) <= tolerance,
                            "phase {p} vs {q}: {here}"
                        );
                    }
                }
                (Motion::SyncRadial { advance, .. }, Motion::SyncRadial { advance: a, .. }) => {
                    assert!(
                        close(a.to_mm_f64(), advance.to_mm_f64(), 1e-5),
                        "advance {here}"
                    );
                }
                _ => panic!("different kinds of move: {here}"),
            }
            checked += 1;
        }
    }
    eprintln!("{checked} synchronised moves compared with rs274");
    assert!(checked > 100, "only {checked} synchronised moves compared");
}

/// Two independent readings of one ISO program must agree: LinuxCNC's canonical motion and
/// ncthread's iso front end + simulator, compared by `sim::compare`. Run over every ISO
/// snapshot (every conversion ncthread writes) and every ISO source in the corpus.
#[test]
fn rs274_motion_equals_the_iso_front_end_simulation() {
    let Some(cmd) = rs274() else { return };
    let mut programs: Vec<(String, String)> = Vec::new();
    for case in corpus_cases() {
        if let Some(ngc) = convert_case(&case, ncthread::dialect::iso::ID).output {
            programs.push((format!("{} → iso", case.name), ngc.into()));
        }
        if case.from == ncthread::dialect::iso::ID && !case.path.starts_with("corpus/bad/") {
            let text = std::fs::read_to_string(common::root().join(&case.path)).unwrap();
            // Fidelity cases that ncthread refuses to read (kept blocks) are judged in
            // tests/fidelity.rs.
            let src = ncthread::source::SourceFile::new(case.path.clone(), text.clone());
            let (_, diags) = ncthread::parse(
                &src,
                ncthread::dialect::iso::ID,
                &Default::default(),
                ncthread::Unsupported::Error,
            );
            if !ncthread::diag::has_errors(&diags) {
                programs.push((case.path.clone(), text));
            }
        }
    }
    let (mut threads, mut agreed, mut abstained) = (0, 0, 0);
    for (name, text) in &mut programs {
        // rs274 starts at X0 Z0; a program that moves before it states a position leaves
        // ncthread's reading unknown there (SIM001): tell it where rs274 starts.
        let sim = common::simulate_iso(name, text);
        if !sim.problems.is_empty()
            || sim
                .segments
                .iter()
                .any(|s| s.motion.moves() && s.to.known().is_none())
        {
            let body = text.strip_prefix("%\n").unwrap_or(text);
            *text = format!("%\nG0 X0 Z0 (rs274 starts here)\n{body}");
        }
        let (name, text) = (&*name, &*text);
        let canon = run_rs274(cmd, text).unwrap_or_else(|e| panic!("{name}: {e}"));
        let ours = ncthread::sim::normalise(&common::simulate_iso(name, text).segments);
        match ncthread::sim::rs274::judge(&ours, &canon) {
            ncthread::sim::rs274::Judgement::Differs(d) => panic!(
                "{name}: ncthread's reading differs from rs274's: {d}\n  ours:   {:?}\n  rs274:  {:?}",
                d.left, d.right
            ),
            ncthread::sim::rs274::Judgement::CannotJudge(why) => {
                eprintln!("{name}: rs274 cannot judge: {why}");
                abstained += 1;
                continue;
            }
            ncthread::sim::rs274::Judgement::Agrees { .. } => agreed += 1,
        }
        threads += ours
            .iter()
            .filter(|s| matches!(s.motion, ncthread::sim::Motion::Sync { .. }))
            .count();
    }
    eprintln!(
        "rs274 agrees on {agreed} of {} programs ({abstained} it cannot judge), {threads} thread moves",
        programs.len()
    );
    assert!(
        programs.len() >= 40 && threads >= 100,
        "{} programs, {threads} thread moves",
        programs.len()
    );
}

/// G76 acceptance: a LinuxCNC G76 program (external; internal with an exit taper) converted
/// to ISO (expanded passes) cuts, per rs274, exactly what rs274 cuts for the G76 itself.
#[test]
fn g76_expanded_cuts_what_linuxcnc_cuts_for_the_g76() {
    let Some(cmd) = rs274() else { return };
    for (name, passes) in [
        ("iso/g76-external", 45),
        ("iso/g76-internal-exit-taper", 31),
        ("iso/g76-entry-and-exit-taper", 22),
    ] {
        let c = case(name);
        let source = std::fs::read_to_string(common::root().join(&c.path)).unwrap();
        let g76 =
            ncthread::sim::normalise(&common::rs274_segments(&run_rs274(cmd, &source).unwrap()));
        let expanded_text = iso(name);
        assert!(
            !expanded_text.lines().any(|l| l.starts_with("G76")),
            "{name}: the output still holds G76"
        );
        let expanded = ncthread::sim::normalise(&common::rs274_segments(
            &run_rs274(cmd, &expanded_text).unwrap(),
        ));
        if let Some(d) = ncthread::sim::compare(&g76, &expanded) {
            panic!(
                "{name}: {d}\n  G76: {:?}\n  expanded: {:?}",
                d.left, d.right
            );
        }
        // Every pass starts a new synchronised chain: count the chains rs274 runs.
        let chains = run_rs274(cmd, &source)
            .unwrap()
            .windows(2)
            .filter(|w| matches!(w[0], common::Canon::SyncStop))
            .count();
        assert_eq!(chains, passes, "{name}");
    }
}

/// G76 acceptance, czech: the G76 programs converted `--to czech --round` (a machine whose
/// constant 8 is in parameter mode), then read back as czech and written as ISO, cut in rs274
/// what rs274 cuts for the G76 itself. (A G76 with an entry taper feeds in synchronised along
/// X before each entry, which the czech control cannot say: that one is refused.)
#[test]
fn g76_through_czech_cuts_what_linuxcnc_cuts_for_the_g76() {
    let Some(cmd) = rs274() else { return };
    let refused = common::convert_case(
        &case("iso/g76-entry-and-exit-taper+profile"),
        ncthread::dialect::czech::ID,
    );
    assert!(refused.output.is_none());
    assert!(
        refused
            .diagnostics
            .iter()
            .any(|d| d.code.id == "CZW002" && d.message.contains("synchronised move along X")),
        "{:?}",
        refused.diagnostics
    );
    for name in [
        "iso/g76-external+profile",
        "iso/g76-internal-exit-taper+profile",
    ] {
        let c = case(name);
        let source = std::fs::read_to_string(common::root().join(&c.path)).unwrap();
        let profile = common::load_profile(c.profile.as_deref().unwrap());
        let options = |from, to| ncthread::ConvertOptions {
            from,
            to,
            profile: profile.clone(),
            unsupported: ncthread::Unsupported::Error,
            renumber: Default::default(),
            round: true,
            nc31_comments: false,
        };
        let src = ncthread::source::SourceFile::new(c.path.clone(), source.clone());
        let czech = ncthread::convert(
            &src,
            &options(ncthread::dialect::iso::ID, ncthread::dialect::czech::ID),
        )
        .output
        .unwrap_or_else(|| panic!("{name}: not converted to czech"));
        let czech_src = ncthread::source::SourceFile::new("czech.ncp", czech);
        let back = ncthread::convert(
            &czech_src,
            &options(ncthread::dialect::czech::ID, ncthread::dialect::iso::ID),
        );
        let ngc = back
            .output
            .unwrap_or_else(|| panic!("{name}: czech not read back: {:?}", back.diagnostics));
        let g76 =
            ncthread::sim::normalise(&common::rs274_segments(&run_rs274(cmd, &source).unwrap()));
        let through =
            ncthread::sim::normalise(&common::rs274_segments(&run_rs274(cmd, &ngc).unwrap()));
        if let Some(d) = ncthread::sim::compare(&g76, &through) {
            panic!(
                "{name}: {d}\n  G76: {:?}\n  via czech: {:?}",
                d.left, d.right
            );
        }
    }
}

/// Issue 5's acceptance: for every corpus program X that converts to a middle dialect Y
/// (czech, nc31), X → Y → ISO cuts in rs274 what X → ISO cuts.
#[test]
fn every_program_through_czech_or_nc31_cuts_what_it_cuts_directly() {
    let Some(cmd) = rs274() else { return };
    for (middle, at_least) in [
        (ncthread::dialect::czech::ID, 25),
        (ncthread::dialect::nc31::ID, 20),
    ] {
        let mut checked = 0;
        for c in corpus_cases()
            .into_iter()
            .filter(|c| !c.path.starts_with("corpus/bad/"))
        {
            let Some(direct) = convert_case(&c, ncthread::dialect::iso::ID).output else {
                continue;
            };
            let Some(text) = convert_case(&c, middle).output else {
                continue;
            };
            let options = ncthread::ConvertOptions {
                from: middle,
                to: ncthread::dialect::iso::ID,
                profile: c
                    .profile
                    .as_deref()
                    .map(common::load_profile)
                    .unwrap_or_default(),
                unsupported: ncthread::Unsupported::Error,
                renumber: Default::default(),
                round: false,
                nc31_comments: false,
            };
            let back = ncthread::convert(
                &ncthread::source::SourceFile::new(format!("middle.{middle}"), text),
                &options,
            );
            let through = back.output.unwrap_or_else(|| {
                panic!(
                    "{}: the {middle} output is not read back: {:?}",
                    c.name, back.diagnostics
                )
            });
            let (direct_canon, through_canon) = (
                run_rs274(cmd, &direct).unwrap(),
                run_rs274(cmd, &through).unwrap(),
            );
            let a = ncthread::sim::normalise(&common::rs274_segments(&direct_canon));
            let b = ncthread::sim::normalise(&common::rs274_segments(&through_canon));
            // rs274 prints four decimals of an inch under G20 (the direct output of an inch
            // program is in inches, the one through czech or nc31 in mm).
            use ncthread::sim::rs274::Canon;
            let inch = direct_canon
                .iter()
                .any(|c| matches!(c, Canon::Inches(true)));
            let tolerance = ncthread::sim::TOLERANCE
                + ncthread::fixed::Length::from_steps(if inch { 26 } else { 0 });
            let slack = match inch {
                true => ncthread::sim::rs274::phase_uncertainty(&direct_canon),
                false => 0.0,
            };
            let slack = ncthread::fixed::Angle((slack * 1000.0).ceil() as i64);
            if let Some(d) = ncthread::sim::compare_within(&a, &b, tolerance, slack) {
                panic!(
                    "{}: {d}\n  direct: {:?}\n  via {middle}: {:?}",
                    c.name, d.left, d.right
                );
            }
            checked += 1;
        }
        assert!(
            checked >= at_least,
            "only {checked} programs went through {middle}"
        );
    }
}

/// LinuxCNC runs each ISO source of the corpus and ncthread's ISO conversion of it alike:
/// rs274's own motion of the one equals its motion of the other. Cutter compensation, which
/// ncthread does not simulate, is judged here: rs274 compensates both programs.
#[test]
fn rs274_runs_the_iso_output_as_it_runs_the_iso_source() {
    use ncthread::sim::compare_within;
    let Some(cmd) = rs274() else { return };
    let (mut programs, mut segments, mut compensated, mut abstained) = (0, 0, 0, 0);
    for case in corpus_cases() {
        if case.from != ncthread::dialect::iso::ID || case.path.starts_with("corpus/bad/") {
            continue;
        }
        let Some(ngc) = convert_case(&case, ncthread::dialect::iso::ID).output else {
            continue;
        };
        let source = std::fs::read_to_string(common::root().join(&case.path)).unwrap();
        // The machine's settings, as the case's profile says (block delete, subroutines).
        let profile = case
            .profile
            .as_deref()
            .map(common::load_profile)
            .unwrap_or_default();
        let settings = ncthread::sim::rs274::Settings {
            block_delete: profile.iso.block_delete == Some(ncthread::profile::BlockDelete::On),
            subroutine_path: profile.iso.subroutine_path.clone(),
        };
        let rs274 = ncthread::sim::rs274::Interpreter::Wrapper(cmd.to_path_buf());
        let run = |text: &str| {
            rs274
                .run_with(text, &settings)
                .unwrap_or_else(|e| panic!("{}: {e}", case.name))
        };
        let (theirs, ours) = (run(&source), run(&ngc));
        // rs274 prints four decimals: of an inch under G20, and of a chain's K.
        use ncthread::sim::rs274::{Canon, as_printed, phase_uncertainty};
        let inch = theirs.iter().any(|c| matches!(c, Canon::Inches(true)));
        let tolerance = ncthread::sim::TOLERANCE
            + ncthread::fixed::Length::from_steps(if inch { 26 } else { 0 });
        // rs274 starts at X0 Z0: a rapid or a feed there before any other move (a `G0` or
        // `G1` without axes) moves nothing.
        let moves = |canon: &[common::Canon]| {
            use ncthread::sim::Motion;
            let origin = ncthread::ir::Pos::new(Default::default(), Default::default());
            let mut segments = common::rs274_segments(canon);
            while let Some(i) = segments.iter().position(|s| s.motion.moves())
                && matches!(segments[i].motion, Motion::Rapid | Motion::Feed { .. })
                && segments[i].to == origin
            {
                segments.remove(i);
            }
            // A move shorter than the tolerance may print as none on one side.
            as_printed(&segments, tolerance)
        };
        let (a, b) = (moves(&theirs), moves(&ours));
        let slack = phase_uncertainty(&theirs).max(phase_uncertainty(&ours));
        if slack >= 180.0 {
            eprintln!(
                "{}: rs274's four decimals leave a helix uncertain by {slack:.0}°",
                case.name
            );
            abstained += 1;
            continue;
        }
        let slack = ncthread::fixed::Angle((slack * 1000.0).ceil() as i64);
        if let Some(d) = compare_within(&a, &b, tolerance, slack) {
            panic!(
                "{}: rs274 runs the source and the output differently: {d}",
                case.name
            );
        }
        programs += 1;
        segments += a.len();
        compensated += usize::from(source.contains("G41") || source.contains("G42"));
    }
    eprintln!(
        "rs274 runs {programs} ISO sources and their ISO outputs alike ({segments} segments, {compensated} programs with cutter compensation); {abstained} it cannot judge"
    );
    assert!(
        programs >= 30 && compensated >= 1,
        "{programs} programs, {compensated} compensated"
    );
}

/// `scripts/rs274` runs beside any other rs274 on the machine. LinuxCNC's rs274 maps its tool
/// table from `$HOME/.tool.mmap` and truncates that file at every start, so two runs that share
/// a HOME kill each other with SIGBUS (issue 30: `cargo test` failed while another rs274 ran);
/// the script gives each run a HOME of its own. The script and the other rs274 here share a
/// HOME made for the test, so that the other rs274 crashes no one else's run on the machine.
#[cfg(unix)]
#[test]
fn scripts_rs274_runs_beside_another_rs274() {
    use std::os::unix::process::ExitStatusExt;
    use std::process::{Command, Stdio};
    use std::sync::atomic::{AtomicBool, Ordering};
    if rs274().is_none() {
        return;
    }
    let script = common::root().join("scripts/rs274");
    let install = Command::new(&script).arg("--install").output().unwrap();
    if !install.status.success() && std::env::var_os("NCTHREAD_RS274").is_some() {
        eprintln!("scripts/rs274 cannot install an interpreter here: not checked");
        return;
    }
    assert!(install.status.success(), "{install:?}");
    let bin = std::path::PathBuf::from(String::from_utf8(install.stdout).unwrap().trim());
    let program = common::root().join("corpus/iso/part-shaft-m20.ngc");
    let dir = tempfile::tempdir().unwrap();
    let home = dir.path().join("home");
    std::fs::create_dir(&home).unwrap();
    // The script's cache (HOME would move it): the one that holds `root/usr/bin/rs274`, else
    // (an rs274 on the PATH) one for the tool table alone.
    let cache = match bin.ancestors().nth(4) {
        Some(cache) if bin.ends_with("root/usr/bin/rs274") => cache.to_path_buf(),
        _ => dir.path().join("cache"),
    };
    let tools = dir.path().join("tools.tbl");
    std::fs::write(
        &tools,
        (1..=999)
            .map(|i| format!("T{i} P{i} X0 Z0 D0 ;\n"))
            .collect::<String>(),
    )
    .unwrap();
    // The other rs274 runs as LinuxCNC's users run it: in its HOME, which the script shares.
    let usr = bin.parent().and_then(|p| p.parent()).unwrap().to_path_buf();
    let stop = AtomicBool::new(false);
    let failures = std::thread::scope(|s| {
        s.spawn(|| {
            while !stop.load(Ordering::Relaxed) {
                let _ = Command::new(&bin)
                    .env("HOME", &home)
                    .env(
                        "LD_LIBRARY_PATH",
                        format!(
                            "{}:{}",
                            usr.join("lib").display(),
                            usr.join("lib/x86_64-linux-gnu").display()
                        ),
                    )
                    .arg("-t")
                    .arg(&tools)
                    .arg("-g")
                    .arg(&program)
                    .stdout(Stdio::null())
                    .stderr(Stdio::null())
                    .status();
            }
        });
        let failures: Vec<String> = (0..100)
            .filter_map(|_| {
                let out = Command::new(&script)
                    .env("HOME", &home)
                    .env("NCTHREAD_RS274_CACHE", &cache)
                    .arg(&program)
                    .output()
                    .unwrap();
                (!out.status.success()).then(|| {
                    format!(
                        "exit {:?}, signal {:?}: {}",
                        out.status.code(),
                        out.status.signal(),
                        String::from_utf8_lossy(&out.stderr)
                    )
                })
            })
            .collect();
        stop.store(true, Ordering::Relaxed);
        failures
    });
    assert!(
        failures.is_empty(),
        "{} of 100 runs failed beside another rs274:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// How ncthread's reading of an ISO program compares with rs274's run of it.
enum Agreement {
    /// The same rapids, feeds and dwells, in order.
    Moves,
    /// Both refuse it, ncthread quoting rs274's reason.
    Refused,
}

/// Whether ncthread's reading of an ISO program moves as rs274 runs it, move for move: every
/// rapid, feed and dwell in order (zero-length moves left out on both sides), or both refuse
/// it for rs274's reason; `Err` says how they differ.
fn moves_differ(cmd: &std::path::Path, name: &str, text: &str) -> Result<Agreement, String> {
    use ncthread::sim::Motion;
    let theirs = run_rs274(cmd, text);
    let src = ncthread::source::SourceFile::new(name, text);
    let (program, diags) = ncthread::parse(
        &src,
        ncthread::dialect::iso::ID,
        &Default::default(),
        ncthread::Unsupported::Error,
    );
    let ours_error = diags.iter().find(|d| d.is_error());
    let canon = match (theirs, ours_error) {
        (Ok(canon), None) => canon,
        (Err(ncthread::sim::rs274::RunError::Refused(theirs)), Some(ours)) => {
            // `rs274 exit Some(1): <its message>`, then the line it stopped at.
            let first = theirs.lines().next().unwrap_or("");
            let reason = first.split_once("): ").map_or(first, |(_, r)| r).trim();
            let quoted =
                !reason.is_empty() && ours.message.to_lowercase().contains(&reason.to_lowercase());
            return if quoted {
                Ok(Agreement::Refused)
            } else {
                Err(format!(
                    "{name}: rs274 says {reason:?}, ncthread {:?}",
                    ours.message
                ))
            };
        }
        (Ok(_), Some(ours)) => {
            return Err(format!(
                "{name}: ncthread refuses it ({}), rs274 runs it",
                ours.message
            ));
        }
        (Err(theirs), None) => {
            return Err(format!(
                "{name}: rs274 refuses it ({theirs}), ncthread reads it"
            ));
        }
        // The interpreter crashed or could not run: no judgement.
        (Err(theirs), Some(_)) => return Err(format!("{name}: {theirs}")),
    };
    let inch = canon
        .iter()
        .any(|c| matches!(c, common::Canon::Inches(true)));
    // rs274 prints four decimals: of an inch under G20 (X a radius).
    let tolerance = if inch { 0.0052 } else { 0.001 };
    let keep = |s: &ncthread::sim::Segment| {
        matches!(
            s.motion,
            Motion::Rapid | Motion::Feed { .. } | Motion::Dwell { .. }
        )
    };
    let near = |p: Option<ncthread::fixed::Length>, q: Option<ncthread::fixed::Length>| match (p, q)
    {
        (Some(p), Some(q)) => (p.to_mm_f64() - q.to_mm_f64()).abs() <= tolerance,
        (p, q) => p == q,
    };
    // Zero-length moves (after rs274's rounding to four decimals) left out.
    let moving = |segments: Vec<ncthread::sim::Segment>| -> Vec<ncthread::sim::Segment> {
        segments
            .into_iter()
            .filter(|s| {
                keep(s) && !(s.motion.moves() && near(s.from.x, s.to.x) && near(s.from.z, s.to.z))
            })
            .collect()
    };
    let theirs = moving(common::rs274_segments(&canon));
    let ours = moving(ncthread::sim::simulate(&program).segments);
    let describe = |s: &ncthread::sim::Segment| format!("{:?} to {:?}", s.motion, s.to);
    for (i, (a, b)) in ours.iter().zip(&theirs).enumerate() {
        let same_kind = std::mem::discriminant(&a.motion) == std::mem::discriminant(&b.motion)
            && (!matches!(a.motion, Motion::Dwell { .. }) || a.motion == b.motion);
        if !(same_kind && near(a.to.x, b.to.x) && near(a.to.z, b.to.z)) {
            return Err(format!(
                "{name}: move {i} (line {}): ncthread {} but rs274 {}",
                a.line,
                describe(a),
                describe(b)
            ));
        }
    }
    if ours.len() != theirs.len() {
        return Err(format!(
            "{name}: ncthread makes {} moves, rs274 {}",
            ours.len(),
            theirs.len()
        ));
    }
    Ok(Agreement::Moves)
}

/// The drilling cycles move for move: the comparisons above normalise the motion (a run of
/// rapids compares by its end), which would not see a G83 that leaves out its rapid back to
/// R, or a retract to the wrong level before the next rapid. Here every rapid, feed and dwell
/// rs274 makes of the corpus's drilling programs must be ncthread's, in order.
#[test]
fn drilling_cycles_move_as_rs274_moves_one_by_one() {
    let Some(cmd) = rs274() else { return };
    let mut checked = 0;
    for case in corpus_cases() {
        if !case.path.starts_with("corpus/iso/drill-") {
            continue;
        }
        let text = std::fs::read_to_string(common::root().join(&case.path)).unwrap();
        match moves_differ(cmd, &case.path, &text) {
            Ok(Agreement::Moves) => checked += 1,
            Ok(Agreement::Refused) => panic!("{}: refused", case.path),
            Err(e) => panic!("{e}"),
        }
    }
    assert!(checked >= 5, "{checked} drilling programs");
}

/// Drilling programs made up from the cycles' words (G73, G81–G83, G85, G89 with R, Z, Q, P,
/// L; modal repeats with X or Z alone; G90/G91, G98/G99, G7/G8, G20/G21 switched between
/// blocks; G52/G92 offsets; G80 and G0/G1 between them): rs274 and ncthread move alike, or
/// refuse alike with rs274's words.
#[test]
fn made_up_drilling_programs_move_as_rs274_moves() {
    let Some(cmd) = rs274() else { return };
    /// A small deterministic generator (xorshift): the same programs on every run.
    struct Rng(u64, bool);
    impl Rng {
        fn next(&mut self, n: u64) -> u64 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            self.0 % n
        }
        /// A value from lo to hi mm in steps of 0.5, or under G20 from lo/5 to hi/5 inch in
        /// steps of 0.01.
        fn v(&mut self, lo: i64, hi: i64) -> String {
            if self.1 {
                let hundredths = lo * 20 + self.next((hi - lo) as u64 * 20 + 1) as i64;
                format!("{}", hundredths as f64 / 100.0)
            } else {
                let halves = lo * 2 + self.next((hi - lo) as u64 * 2 + 1) as i64;
                format!("{}", halves as f64 / 2.0)
            }
        }
        fn pick<'a>(&mut self, of: &[&'a str]) -> &'a str {
            of[self.next(of.len() as u64) as usize]
        }
    }
    let mut g = Rng(0x9E37_79B9_7F4A_7C15, false);
    let (mut compared, mut refused) = (0, 0);
    for k in 0..150 {
        g.1 = g.next(5) == 0;
        let inch = g.1;
        let mut lines = vec![
            format!(
                "{} G17 {} G90 G94 F100",
                if g.next(2) == 0 { "G7" } else { "G8" },
                if inch { "G20" } else { "G21" }
            ),
            format!("G0 X0 Z{}", g.v(2, 10)),
        ];
        let codes = ["G81", "G82", "G83", "G73", "G85", "G89"];
        let mut in_cycle = false;
        for _ in 0..1 + g.next(8) {
            let r = g.next(100);
            if r < 35 || !in_cycle {
                let code = codes[g.next(6) as usize];
                let mut words = Vec::new();
                if g.next(10) < 3 {
                    words.push(g.pick(&["G98", "G99"]).to_string());
                }
                let incremental = g.next(10) < 2;
                if incremental {
                    words.push("G91".into());
                } else if g.next(10) < 2 {
                    words.push("G90".into());
                }
                words.push(code.into());
                if g.next(10) < 7 {
                    words.push(format!(
                        "X{}",
                        if incremental { g.v(-4, 4) } else { g.v(0, 20) }
                    ));
                }
                if incremental {
                    words.push(format!("R{}", g.v(-6, 2)));
                } else {
                    words.push(format!("R{}", g.v(-3, 4)));
                }
                words.push(format!("Z{}", g.v(-15, -1)));
                if matches!(code, "G83" | "G73") {
                    words.push(format!("Q{}", g.v(1, 6)));
                }
                if matches!(code, "G82" | "G89") {
                    words.push(g.pick(&["P0.5", "P1", "P0.25"]).into());
                }
                if g.next(10) < 2 {
                    words.push(format!("L{}", 1 + g.next(3)));
                }
                lines.push(words.join(" "));
                in_cycle = true;
            } else if r < 60 {
                let mut words = Vec::new();
                if g.next(10) < 3 {
                    words.push(g.pick(&["G98", "G99"]).to_string());
                }
                if g.next(10) < 2 {
                    words.push(g.pick(&["G90", "G91"]).to_string());
                }
                if g.next(2) == 0 {
                    words.push(format!("X{}", g.v(-4, 20)));
                } else {
                    words.push(format!("Z{}", g.v(-15, -1)));
                }
                if g.next(10) < 2 {
                    words.push(format!("L{}", 1 + g.next(3)));
                }
                lines.push(words.join(" "));
            } else if r < 85 {
                lines.push("G80".into());
                lines.push(format!("G90 {} Z{}", g.pick(&["G0", "G1"]), g.v(-3, 10)));
                in_cycle = false;
            } else if r < 92 {
                lines.push(g.pick(&["G98", "G99", "G91", "G90"]).into());
            } else if r < 96 {
                lines.push(match g.next(4) {
                    0 => format!("G92 Z{}", g.v(-2, 2)),
                    1 => format!("G52 Z{}", g.v(-2, 2)),
                    2 => format!("G52 X{}", g.v(-2, 2)),
                    _ => "G92.1".into(),
                });
            } else {
                // F again with the units: a feed carried across them is refused (ISOR004).
                lines.push(format!("{} F100", g.pick(&["G20", "G21"])));
            }
        }
        lines.push("G90 G80".into());
        lines.push("M2".into());
        let text = lines.join("\n") + "\n";
        match moves_differ(cmd, &format!("made-up program {k}"), &text) {
            Ok(Agreement::Moves) => compared += 1,
            Ok(Agreement::Refused) => refused += 1,
            Err(e) => panic!("{e}\n{text}"),
        }
    }
    eprintln!("made-up drilling programs: {compared} move as rs274 moves, {refused} refused alike");
    assert!(compared >= 100, "{compared} programs compared");
}

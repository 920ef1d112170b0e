//! `explain`, `plot` and `verify --plot`: the seed programs' pass tables (figures from the
//! seeds and the spec), and the SVGs rendered with resvg and looked at pixel by pixel.
mod common;

use common::{ncthread, render_svg as render, text};

/// `ncthread explain FILE --from D --format json`, parsed.
fn explain_json(file: &str, from: &str, more: &[&str]) -> serde_json::Value {
    let mut args = vec!["explain", file, "--from", from, "--format", "json"];
    args.extend(more);
    let out = ncthread(&args, None);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    serde_json::from_slice(&out.stdout).expect("explain --format json prints JSON")
}

fn numbers(v: &serde_json::Value, key: &str) -> Vec<f64> {
    v["passes"]
        .as_array()
        .expect("passes")
        .iter()
        .map(|p| p[key].as_f64().unwrap_or(f64::NAN))
        .collect()
}

/// The seed's G31 M36×1.5 (depth P96, first depth P20, the halving law of nc31.md): eight
/// passes, four of the first depth's multiples, then a remainder and halvings.
#[test]
fn seed_g31_is_eight_passes_with_the_halving_depths() {
    let v = explain_json("corpus/nc31/g31-m36x1.5.nc", "nc31", &[]);
    let ops = v["operations"].as_array().unwrap();
    assert_eq!(ops.len(), 1, "{v:#}");
    let op = &ops[0];
    assert_eq!(op["kind"], "cycle");
    assert_eq!(op["lead"], 1.5);
    assert_eq!(op["crest"], 36.0);
    assert_eq!(op["root"], 34.08);
    assert_eq!(op["hand"], "right");
    assert_eq!(
        numbers(op, "cumulative_depth"),
        [0.2, 0.4, 0.6, 0.7725, 0.8725, 0.9225, 0.9475, 0.96]
    );
    assert_eq!(
        numbers(op, "x_start"),
        [35.6, 35.2, 34.8, 34.455, 34.255, 34.155, 34.105, 34.08]
    );
}

/// The seed's G32 program: three passes on Ø35, Ø34.4 and Ø34.08 of an M36×1.5 are one
/// thread; with the crest the seed names, the cuts are its t₁ = 0.5, t₂ = 0.3, t₃ = 0.16.
#[test]
fn seed_g32_passes_are_one_thread() {
    let v = explain_json("corpus/nc31/g32-three-passes.nc", "nc31", &[]);
    let ops = v["operations"].as_array().unwrap();
    assert_eq!(ops.len(), 1, "{v:#}");
    assert_eq!(ops[0]["kind"], "passes");
    assert_eq!(numbers(&ops[0], "x_start"), [35.0, 34.4, 34.08]);
    assert_eq!(ops[0]["crest"], serde_json::Value::Null);
    assert_eq!(numbers(&ops[0], "below_first"), [0.0, 0.3, 0.46]);
    let v = explain_json(
        "corpus/nc31/g32-three-passes.nc",
        "nc31",
        &["--crest", "36"],
    );
    let op = &v["operations"][0];
    assert_eq!(numbers(op, "cut"), [0.5, 0.3, 0.16]);
    assert_eq!(numbers(op, "cumulative_depth"), [0.5, 0.8, 0.96]);
    assert_eq!(op["depth"], 0.96);
}

/// The czech manual's multi-pass example: three G33 blocks, one thread.
#[test]
fn czech_multipass_example_is_one_thread() {
    let v = explain_json("corpus/czech/ex1-multipass.nc", "czech", &[]);
    let ops = v["operations"].as_array().unwrap();
    assert_eq!(ops.len(), 1, "{v:#}");
    assert_eq!(numbers(&ops[0], "x_start"), [26.618, 26.418, 26.177]);
    assert_eq!(numbers(&ops[0], "z_end"), [-9.0, -9.0, -9.0]);
    assert_eq!(ops[0]["line"], 3);
}

/// A two-start thread (I0 and I180) is one operation with two starts, the second start's
/// helix half a lead along; its pass is not a spring pass of the first.
#[test]
fn two_starts_are_one_thread_with_two_start_angles() {
    let v = explain_json(
        "corpus/czech/multistart-i180.nc",
        "czech",
        &["--crest", "30"],
    );
    let op = &v["operations"][0];
    assert_eq!(op["starts"], 2);
    assert_eq!(op["start_angles"], serde_json::json!([0.0, 180.0]));
    assert_eq!(numbers(op, "shift"), [0.0, 1.5]);
    assert_eq!(numbers(op, "cut"), [0.4, 0.4]);
    assert_eq!(op["spring_passes"], 0);
}

/// A G76 with Q29.5: the tool moves along the flank, so each pass's helix lies further along
/// by its depth below the first pass · tan 29.5°.
#[test]
fn flank_infeed_shifts_each_pass() {
    let v = explain_json(
        "corpus/iso/g76-external.ngc",
        "iso",
        &["--profile", "corpus/iso/g76-external.profile.toml"],
    );
    let op = &v["operations"][0];
    assert_eq!(op["infeed_angle"], 29.5);
    let tan = 29.5f64.to_radians().tan();
    for p in op["passes"].as_array().unwrap() {
        let below = p["below_first"].as_f64().unwrap();
        let shift = p["shift"].as_f64().unwrap();
        assert!((shift - below * tan).abs() <= 0.0002, "{p}");
    }
}

#[test]
fn csv_has_a_row_per_pass() {
    let out = ncthread(
        &[
            "explain",
            "corpus/nc31/g31-m36x1.5.nc",
            "--from",
            "nc31",
            "--format",
            "csv",
        ],
        None,
    );
    assert_eq!(out.status.code(), Some(0));
    let csv = text(&out.stdout);
    let rows: Vec<&str> = csv.lines().collect();
    assert_eq!(rows.len(), 9, "{csv}");
    assert!(rows[0].starts_with("operation,kind,line,hand,lead,crest,pass,start,cut"));
    assert!(
        rows[8].starts_with("1,cycle,10,right,1.5,36,8,1,0.0125,0.96,"),
        "{csv}"
    );
}

#[test]
fn a_program_with_errors_explains_nothing() {
    let out = ncthread(
        &[
            "explain",
            "corpus/bad/czech/lead-over-99.99.nc",
            "--from",
            "czech",
        ],
        None,
    );
    assert_eq!(out.status.code(), Some(1));
    assert!(text(&out.stdout).is_empty());
    assert!(text(&out.stderr).contains("error[CZR003]"));
}

/// The pixels of `rect` (x, y, width, height) that are strongly coloured (not grey, not
/// white): the passes, which are drawn in colours by pass order.
fn coloured(p: &resvg::tiny_skia::Pixmap, (x0, y0, w, h): (u32, u32, u32, u32)) -> usize {
    let mut n = 0;
    for y in y0..(y0 + h).min(p.height()) {
        for x in x0..(x0 + w).min(p.width()) {
            let c = p.pixel(x, y).unwrap();
            let (r, g, b) = (c.red() as i32, c.green() as i32, c.blue() as i32);
            if (r - g).abs().max((g - b).abs()).max((r - b).abs()) > 60 {
                n += 1;
            }
        }
    }
    n
}

fn plot(file: &str, from: &str) -> String {
    let out = ncthread(&["plot", file, "--from", from], None);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    text(&out.stdout)
}

/// The G31 M36×1.5: eight passes between Ø36 and Ø34.08 in the pass view, the cross-section
/// and the toolpath, each drawn (coloured pixels where the passes are).
#[test]
fn plot_of_the_seed_g31_shows_its_eight_passes() {
    let svg = plot("corpus/nc31/g31-m36x1.5.nc", "nc31");
    assert!(
        svg.contains("crest Ø36") && svg.contains("root Ø34.08"),
        "{svg}"
    );
    for n in 1..=8 {
        assert!(
            svg.contains(&format!("<title>pass {n}: depth ")),
            "cross-section pass {n}"
        );
        assert!(
            svg.contains(&format!("<title>pass {n}: X")),
            "pass view pass {n}"
        );
    }
    assert!(!svg.contains("<title>pass 9:"));
    // Eight thread moves in the toolpath, each a pass of the cycle.
    assert_eq!(svg.matches("thread  X").count(), 8, "{svg}");
    let pixmap = render(&svg);
    // The toolpath (top), the pass view (lower left) and the cross-section (lower middle).
    assert!(coloured(&pixmap, (70, 60, 990, 400)) > 500, "toolpath");
    assert!(coloured(&pixmap, (70, 520, 470, 320)) > 1000, "pass view");
    assert!(
        coloured(&pixmap, (600, 520, 300, 320)) > 1000,
        "cross-section"
    );
    // Nothing coloured where nothing is drawn: right of the toolpath's start point.
    assert_eq!(coloured(&pixmap, (1020, 480, 80, 20)), 0);
}

/// A hand conversion with pass 5 cut 0.02 mm deeper (per side): `verify --plot` marks that
/// pass, in the whole view and in the view around it.
#[test]
fn verify_plot_marks_the_pass_that_differs() {
    let hand =
        std::fs::read_to_string(common::root().join("corpus/iso/m36x1.5-by-hand.ngc")).unwrap();
    assert!(hand.contains("G0 X34.255\n"));
    let mutated = hand.replace("G0 X34.255\n", "G0 X34.215\n");
    let dir = tempfile::tempdir().unwrap();
    let against = dir.path().join("deeper.ngc");
    let svg_path = dir.path().join("verify.svg");
    std::fs::write(&against, mutated).unwrap();
    let out = ncthread(
        &[
            "verify",
            "corpus/nc31/g31-m36x1.5.nc",
            "--from",
            "nc31",
            "--to",
            "iso",
            "--against",
            against.to_str().unwrap(),
            "--plot",
            svg_path.to_str().unwrap(),
        ],
        None,
    );
    assert_eq!(out.status.code(), Some(1), "{}", text(&out.stdout));
    let svg = std::fs::read_to_string(&svg_path).unwrap();
    assert!(
        svg.contains("first difference: line 10 (pass 5)"),
        "the label names the pass: {svg}"
    );
    assert!(
        svg.contains("X34.255 Z-47.5 ≠ X34.215 Z-47.5"),
        "and its numbers"
    );
    // The marked segments are the two pass-5 moves, in red.
    let marked: Vec<&str> = svg
        .lines()
        .filter(|l| l.contains("stroke=\"#d00000\" stroke-width=\"3.5\""))
        .collect();
    assert_eq!(marked.len(), 4, "two segments in each view: {marked:?}");
    assert!(marked.iter().any(|l| l.contains("X34.215 Z4.5")));
    assert!(marked.iter().any(|l| l.contains("X34.255 Z4.5")));
    let pixmap = render(&svg);
    let red = |rect: (u32, u32, u32, u32)| {
        let mut n = 0;
        for y in rect.1..rect.1 + rect.3 {
            for x in rect.0..rect.0 + rect.2 {
                let c = pixmap.pixel(x, y).unwrap();
                if c.red() > 180 && c.green() < 60 && c.blue() < 60 {
                    n += 1;
                }
            }
        }
        n
    };
    assert!(
        red((70, 640, 990, 300)) > 500,
        "the difference in the detail view"
    );
    // An equivalent conversion: no mark.
    let out = ncthread(
        &[
            "verify",
            "corpus/nc31/g31-m36x1.5.nc",
            "--from",
            "nc31",
            "--to",
            "iso",
            "--plot",
            svg_path.to_str().unwrap(),
        ],
        None,
    );
    assert_eq!(out.status.code(), Some(0));
    let svg = std::fs::read_to_string(&svg_path).unwrap();
    assert!(svg.contains("equivalent: the motions agree"));
    assert!(!svg.contains("#d00000\" stroke-width=\"3.5\""));
    render(&svg);
}

#[test]
fn plot_refuses_an_operation_it_does_not_have() {
    let out = ncthread(
        &[
            "plot",
            "corpus/nc31/g31-m36x1.5.nc",
            "--from",
            "nc31",
            "--operation",
            "2",
        ],
        None,
    );
    assert_eq!(out.status.code(), Some(2));
    assert!(text(&out.stderr).contains("--operation 2: the program has 1 operation(s)"));
}

/// Every corpus program that reads plots to a valid SVG (arcs, roughing cycles, taps, and
/// programs without a thread).
#[test]
fn every_corpus_program_plots() {
    let mut plotted = 0;
    for case in common::corpus_cases() {
        if common::reader_refuses(&case) {
            continue;
        }
        let program = common::parse_case(&case);
        let ops = ncthread::explain::explain(&program, &Default::default());
        let segments = ncthread::sim::simulate(&program).segments;
        for op in ops.iter().map(Some).chain([None]) {
            let svg = ncthread::plot::plot(&case.name, &segments, op);
            resvg::usvg::Tree::from_str(&svg, &resvg::usvg::Options::default())
                .unwrap_or_else(|e| panic!("{}: {e}", case.name));
            assert!(
                !svg.contains("NaN") && !svg.contains("=\"inf") && !svg.contains("=\"-inf"),
                "{}",
                case.name
            );
            plotted += 1;
        }
    }
    assert!(plotted > 100, "{plotted}");
}

/// README.md's `explain` examples print what the command prints, and its plot is the one the
/// command writes today.
#[test]
fn readme_examples_are_current() {
    let readme = std::fs::read_to_string(common::root().join("README.md")).unwrap();
    let examples = [
        (
            "$ ncthread explain corpus/nc31/g31-m36x1.5.nc --from nc31\n",
            vec!["explain", "corpus/nc31/g31-m36x1.5.nc", "--from", "nc31"],
        ),
        (
            "$ ncthread explain corpus/nc31/g32-three-passes.nc --from nc31 --crest 36 --plain\n",
            vec![
                "explain",
                "corpus/nc31/g32-three-passes.nc",
                "--from",
                "nc31",
                "--crest",
                "36",
                "--plain",
            ],
        ),
    ];
    for (prompt, args) in examples {
        let at = readme
            .find(prompt)
            .unwrap_or_else(|| panic!("README lacks {prompt}"))
            + prompt.len();
        let out = text(&ncthread(&args, None).stdout);
        assert!(
            readme[at..].starts_with(&out),
            "README's example of {prompt} is stale; today it prints:\n{out}"
        );
    }
    let svg = plot("corpus/nc31/g31-m36x1.5.nc", "nc31");
    let kept = std::fs::read_to_string(common::root().join("docs/plot-g31-m36x1.5.svg")).unwrap();
    assert!(
        svg == kept,
        "docs/plot-g31-m36x1.5.svg is stale: ncthread plot corpus/nc31/g31-m36x1.5.nc --from nc31 -o docs/plot-g31-m36x1.5.svg"
    );
}

/// `explain --format json` of a program given on stdin.
fn explain_stdin(program: &str, from: &str, more: &[&str]) -> serde_json::Value {
    let mut args = vec!["explain", "--from", from, "--format", "json"];
    args.extend(more);
    let out = ncthread(&args, Some(program.as_bytes()));
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    serde_json::from_slice(&out.stdout).unwrap()
}

/// How passes are gathered into threads (found in review): the whole chain decides, not its
/// first block; another diameter is another thread; a spindle said again, coolant or a dwell
/// between passes do not end a thread; starts are told by the helix, not the angle written.
#[test]
fn passes_are_gathered_into_the_threads_they_cut() {
    let pass = |x: &str, z: &str, k: &str| format!("G0 X{x} Z{z}\nG33 Z-20 K{k}\nG0 X40\nG0 Z5\n");
    // Two threads of one lead over one length: Ø15.4/14.8 outside, Ø9/9.6 inside.
    let two = format!(
        "G7 G21 G95\nS300 M3\nG0 X40 Z5\n{}{}G0 X8\n{}{}M2\n",
        pass("15.4", "4", "2"),
        pass("14.8", "4", "2"),
        pass("9", "4", "2").replace("G0 X40", "G0 X8"),
        pass("9.6", "4", "2").replace("G0 X40", "G0 X8"),
    );
    let v = explain_stdin(&two, "iso", &[]);
    let ops = v["operations"].as_array().unwrap();
    assert_eq!(ops.len(), 2, "{v:#}");
    assert_eq!(
        (ops[0]["internal"].clone(), ops[1]["internal"].clone()),
        (false.into(), true.into())
    );
    // A spindle said again, coolant and a dwell between the passes: one thread.
    let restated = format!(
        "G7 G21 G95\nS300 M3\nG0 X40 Z5\n{}S300 M3\n{}M8\n{}G4 P0.5\n{}M2\n",
        pass("15.4", "4", "2"),
        pass("14.8", "4", "2"),
        pass("14.4", "4", "2"),
        pass("14.2", "4", "2")
    );
    let v = explain_stdin(&restated, "iso", &[]);
    assert_eq!(v["operations"].as_array().unwrap().len(), 1, "{v:#}");
    assert_eq!(v["operations"][0]["passes"].as_array().unwrap().len(), 4);
    // A two-start thread written by moving Z half a lead: two starts, each pass cuts its own.
    let twostart = format!(
        "G7 G21 G95\nS300 M3\nG0 X40 Z6\n{}{}{}{}M2\n",
        pass("29.4", "6", "3"),
        pass("29", "6", "3"),
        pass("29.4", "7.5", "3"),
        pass("29", "7.5", "3")
    );
    let v = explain_stdin(&twostart, "iso", &["--crest", "30"]);
    let op = &v["operations"][0];
    assert_eq!(
        op["start_angles"],
        serde_json::json!([0.0, 180.0]),
        "{op:#}"
    );
    assert_eq!(numbers(op, "start"), [1.0, 1.0, 2.0, 2.0]);
    assert_eq!(numbers(op, "cut"), [0.3, 0.2, 0.3, 0.2]);
    // A czech flank infeed by the start angle (I0, I6, I12 on a 3 mm lead): one start, each
    // pass 0.05 mm back along the helix, an infeed of atan(0.05 / 0.2) = 14.036°.
    let flank = "N10 G00 G95 S800 M03\nN20 X29.6 Z5.\nN30 G33 Z-30. I0. F3.\nN40 G00 X32.\nN50 Z5.\nN60 X29.2\nN70 G33 Z-30. I6. F3.\nN80 G00 X32.\nN90 Z5.\nN100 X28.8\nN110 G33 Z-30. I12. F3.\nN120 G00 X32.\nN130 M30\n";
    let v = explain_stdin(flank, "czech", &["--crest", "30"]);
    let op = &v["operations"][0];
    assert_eq!(op["starts"], 1, "{op:#}");
    assert_eq!(numbers(op, "cut"), [0.2, 0.2, 0.2]);
    assert_eq!(numbers(op, "shift"), [0.0, -0.05, -0.1]);
    assert_eq!(op["infeed_angle"], -14.036);
    // A chain (entry, thread, runout as three G33 lines) is one pass; two such passes are
    // one thread, its line the full-depth part.
    let chain = "G7 G21 G95\nS500 M3\nG0 X44 Z5\nG33 X40 Z-1 K2.10818511\nG33 Z-40 K2\nG33 X44 Z-44 K2.23606798\nG0 X50\nG0 Z5\nG0 X44\nG33 X39.4 Z-1 K2.10818511\nG33 Z-40 K2\nG33 X44 Z-44 K2.23606798\nG0 X50\nG0 Z5\nM2\n";
    let v = explain_stdin(chain, "iso", &[]);
    let op = &v["operations"][0];
    assert_eq!(v["operations"].as_array().unwrap().len(), 1, "{v:#}");
    assert_eq!(op["lead"], 2.0);
    assert_eq!(numbers(op, "z_start"), [-1.0, -1.0]);
    assert_eq!(numbers(op, "z_end"), [-40.0, -40.0]);
    assert_eq!(
        (op["entry"].clone(), op["runout"].clone()),
        (6.0.into(), 4.0.into())
    );
}

/// A pass's start and end are its full-depth line: a czech J runout and a G76's tapers are
/// left out; a position the program never gave is `null`, not 0.
#[test]
fn the_pass_line_leaves_out_entry_and_runout_and_unknowns_are_null() {
    let v = explain_json(
        "corpus/czech/ex4-runout-constant.nc",
        "czech",
        &["--profile", "corpus/czech/ex4-runout-constant.profile.toml"],
    );
    let op = &v["operations"][0];
    assert_eq!(numbers(op, "z_end"), [-88.0]);
    assert_eq!(op["runout"], 12.0);
    let v = explain_json("corpus/czech/ex2-start-angle.nc", "czech", &[]);
    let p = &v["operations"][0]["passes"][0];
    assert_eq!(
        (p["x_start"].clone(), p["z_start"].clone()),
        (serde_json::Value::Null, serde_json::Value::Null)
    );
}

#[test]
fn plain_tables_are_ascii() {
    let out = ncthread(
        &[
            "explain",
            "corpus/iso/g76-external.ngc",
            "--from",
            "iso",
            "--plain",
        ],
        None,
    );
    assert_eq!(out.status.code(), Some(0));
    assert!(out.stdout.is_ascii(), "{}", text(&out.stdout));
    assert!(text(&out.stdout).contains("crest D16, root D13.5466"));
}

/// A roughing cycle is drawn as its cuts, never as a thread's cross-section; `verify --plot`
/// writes a file, never stdout.
#[test]
fn plot_draws_threads_as_threads_only() {
    let svg = plot("corpus/iso/roughing-g71-bore.ngc", "iso");
    assert!(
        !svg.contains("cross-section"),
        "no thread: no cross-section"
    );
    let out = ncthread(
        &[
            "plot",
            "corpus/iso/roughing-g71-bore.ngc",
            "--from",
            "iso",
            "--operation",
            "1",
        ],
        None,
    );
    let svg = text(&out.stdout);
    assert!(svg.contains("operation 1: G71's cuts") && !svg.contains("cross-section"));
    let out = ncthread(
        &[
            "verify",
            "corpus/nc31/g31-m36x1.5.nc",
            "--from",
            "nc31",
            "--to",
            "iso",
            "--plot",
            "-",
        ],
        None,
    );
    assert_eq!(out.status.code(), Some(2));
}

//! Issue 12's acceptance: no panic and no hang on 400 hostile inputs and on every corpus
//! file, through `check`, `convert` (every target, also with `--unsupported warn` and
//! `--round`), `verify`, `explain` and `plot`. The inputs are made here, deterministically: hand-written ones
//! (multi-byte text at every place an error can point, a BOM, NUL, ^Z, CR-only lines, a
//! line of 50,000 words, a 1 MB line, absurd numbers) and seeded mutations of corpus files.
//! Each input runs on a watchdog thread; a panic or a run over 20 s fails the test.
mod common;

use ncthread::profile::Profile;
use ncthread::source::SourceFile;
use ncthread::{ConvertOptions, DialectId, Unsupported};

const DIALECTS: [DialectId; 4] = [
    ncthread::dialect::czech::ID,
    ncthread::dialect::nc31::ID,
    ncthread::dialect::iso::ID,
    ncthread::dialect::fanuc::ID,
];

/// A small deterministic generator (64-bit LCG, Knuth's constants).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        self.0 >> 33
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

/// Hand-written hostile inputs, for every dialect.
fn hand_written() -> Vec<Vec<u8>> {
    let mut v: Vec<Vec<u8>> = [
        "é\n",
        "é",
        "",
        "\u{feff}",
        "\u{feff}\u{feff}G0 X1\n",
        "%",
        "%\n%\n%\n",
        "\0\0\0",
        "G0 X1\x1a\x1a\0\0",
        "N10 G00 X1.\rN20 Z2.\r",
        "N10 G33 Z-9. F1.5 I359.999\n",
        "N10 G33 Z-9. F1.5 I-0.001\n",
        "N10 G33 Z-9. F0.00001\n",
        "G33 Z-9 K0.0000000000001\n",
        "X99999999999999999999999999999999999999\n",
        "X1e400\n",
        "X-0 Z-0.\n",
        "N10 Xé\n",
        "N10 X1.é\n",
        "G0 X(é\n",
        "(é\n",
        "\"ŘÍŠE\n",
        "N0 X3600 ~ *\nN1 Z450 ~ *\n",
        "N0 G31 *\nN1 X3600 *\nN2 Z-4750 *\nN3 F0 *\nN4 P96 *\nN5 P20\n",
        "N0 G31 *\nN1 X3600 *\nN2 Z-4750 *\nN3 F15000 *\nN4 P999999999 *\nN5 P1\n",
        "G7 S1 M3\nG0 X10 Z1\nG76 P1 Z-10 I-1 J0.0000001 K100000\n",
        "G7 S1 M3\nG0 X10 Z1\nG76 P0.0001 Z-100000 I-1 J0.1 K0.2\n",
        "中文标题\nG0 X1 Z1\n",
        "🛠🛠🛠\n",
        "e\u{301}\u{301}\u{301}\n",
        "N10 G33 Z-9. F1.5 J5 E5. \"Ä\n\n\n",
        "N10 R04=99999999999999.999\nN20 G33 Z1 F1 J1\n",
        "G0 X1 %\n",
        "% (c)\n",
        "o100 sub\n#1=[1+\n",
    ]
    .iter()
    .map(|s| s.as_bytes().to_vec())
    .collect();
    // Invalid UTF-8 and every byte.
    v.push(vec![0xff, 0xfe, 0x80, b'G', b'0', 0xc3]);
    v.push((0..=255u8).collect());
    // Lines of 20,000 repeated words and of 200 KB (the release CLI's times for 50,000
    // words and 1 MB are in the closing note of issue 12; here a debug build must end).
    v.push(format!("N10 {}\n", "X1 ".repeat(20_000)).into_bytes());
    v.push(format!("G0 {}\n", "Y1 ".repeat(20_000)).into_bytes());
    v.push(format!("({})\n", "é".repeat(100_000)).into_bytes());
    v.push(format!("N1 X{}\n", "1".repeat(200_000)).into_bytes());
    v
}

/// Inserts, deletes and replaces bytes of `bytes` (multi-byte characters most of all).
fn mutate(rng: &mut Lcg, bytes: &[u8]) -> Vec<u8> {
    const PIECES: [&str; 14] = [
        "é", "Č", "中", "🛠", "\u{301}", "\r", "\0", "\x1a", "%", "(", "\"", "*", "~", "\u{feff}",
    ];
    let mut b = bytes.to_vec();
    for _ in 0..1 + rng.below(6) {
        let at = rng.below(b.len() + 1);
        match rng.below(4) {
            0 | 1 => {
                let piece = PIECES[rng.below(PIECES.len())].as_bytes();
                b.splice(at..at, piece.iter().copied());
            }
            2 if !b.is_empty() => {
                let end = (at + 1 + rng.below(4)).min(b.len());
                b.drain(at.min(b.len())..end);
            }
            _ if !b.is_empty() => {
                let i = at.min(b.len() - 1);
                b[i] = rng.next() as u8;
            }
            _ => {}
        }
    }
    b
}

/// check, explain and plot, convert to every target (plain, `--unsupported warn`,
/// `--round`) and verify.
fn exercise(from: DialectId, bytes: &[u8], profile: &Profile) {
    let (text, _) = ncthread::text::decode(bytes, from);
    let src = SourceFile::new("hostile", text);
    for unsupported in [Unsupported::Error, Unsupported::Warn] {
        let _ = ncthread::check(&src, from, profile, unsupported);
        // What reads (warnings allowed) is explained and plotted, with and without a crest.
        let (program, _) = ncthread::parse(&src, from, profile, unsupported);
        let segments = ncthread::sim::simulate(&program).segments;
        for crest in [None, Some(ncthread::fixed::Length::from_mm(30))] {
            let options = ncthread::explain::Options { crest };
            let ops = ncthread::explain::explain(&program, &options);
            for table in [
                ncthread::explain::Table::Box,
                ncthread::explain::Table::Plain,
            ] {
                let _ = ncthread::explain::to_text(&ops, table);
            }
            let _ = ncthread::explain::to_json(&ops);
            let _ = ncthread::explain::to_csv(&ops);
            for op in ops.iter().map(Some).chain([None]) {
                let _ = ncthread::plot::plot("hostile", &segments, op);
            }
        }
    }
    for to in DIALECTS {
        for (unsupported, round) in [
            (Unsupported::Error, false),
            (Unsupported::Warn, false),
            (Unsupported::Error, true),
        ] {
            let options = ConvertOptions {
                from,
                to,
                profile: profile.clone(),
                unsupported,
                renumber: Default::default(),
                round,
                nc31_comments: round,
            };
            let conversion = ncthread::convert(&src, &options);
            for d in &conversion.diagnostics {
                let _ = d.render(false);
                let _ = d.to_json();
            }
            if !round {
                let _ = ncthread::verify(&src, &options, None, None);
            }
        }
    }
}

/// Runs `exercise` on a watchdog thread; the failure names the input. The bound catches a hang,
/// not a slow input: the slowest corpus input (`bad/iso/macro-endless-while.ngc`, whose loop runs
/// to ncthread's cap in each of its ~20 parses) takes about 15 s under the test profile on a busy
/// 2-core machine, which once tripped a 20 s bound in CI.
fn guarded(name: &str, from: DialectId, bytes: Vec<u8>, profile: Profile) -> Result<(), String> {
    common::watchdog(60, move || exercise(from, &bytes, &profile))
        .map_err(|why| format!("{name} ({from}): {why}"))
}

#[test]
fn no_panic_and_no_hang_on_400_hostile_inputs_and_the_corpus() {
    use rayon::prelude::*;
    let corpus: Vec<_> = common::corpus_cases()
        .into_iter()
        .map(|c| {
            let bytes = std::fs::read(common::root().join(&c.path)).unwrap();
            let profile = c
                .profile
                .as_deref()
                .map(common::load_profile)
                .unwrap_or_default();
            (c.name, c.from, bytes, profile)
        })
        .collect();
    // Every corpus file as it is, the hand-written inputs in every dialect, and seeded
    // mutations of the corpus up to 400 hostile inputs.
    let mut inputs: Vec<(String, DialectId, Vec<u8>, Profile)> = corpus.clone();
    let mut hostile = 0;
    for (i, bytes) in hand_written().into_iter().enumerate() {
        for from in DIALECTS {
            hostile += 1;
            inputs.push((
                format!("hand-written #{i}"),
                from,
                bytes.clone(),
                Profile::default(),
            ));
        }
    }
    let mut rng = Lcg(12);
    while hostile < 400 {
        let (name, from, bytes, profile) = &corpus[rng.below(corpus.len())];
        let mutated = mutate(&mut rng, bytes);
        hostile += 1;
        inputs.push((
            format!("{name} mutated #{hostile}"),
            *from,
            mutated,
            profile.clone(),
        ));
    }
    // The largest first, so that the threads share the work evenly.
    inputs.sort_by_key(|(_, _, bytes, _)| std::cmp::Reverse(bytes.len()));
    let failures: Vec<String> = inputs
        .into_par_iter()
        .filter_map(|(name, from, bytes, profile)| guarded(&name, from, bytes, profile).err())
        .collect();
    assert!(
        failures.is_empty(),
        "{} of {} inputs failed:\n{}",
        failures.len(),
        corpus.len() + hostile,
        failures.join("\n")
    );
    assert!(hostile >= 400);
}

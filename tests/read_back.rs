//! A conversion reads its output back keeping only the diagnostics (each reader lets go of a
//! line's items once the line is read): those diagnostics must be the full read's, for every
//! corpus file, read as every dialect (another dialect's text is hostile input too), with
//! and without `--unsupported warn`. The same for a streaming read's items, and for a
//! conversion that streams.

mod common;

use ncthread::Unsupported;
use ncthread::dialect;
use ncthread::profile::Profile;
use ncthread::source::SourceFile;

/// Every corpus file with its profile (or none).
fn each_case(mut f: impl FnMut(&common::Case, &SourceFile, &Profile)) {
    for case in common::corpus_cases() {
        let src = common::case_source(&case);
        let profile = case
            .profile
            .as_deref()
            .map(common::load_profile)
            .unwrap_or_default();
        f(&case, &src, &profile);
    }
}

#[test]
fn reading_for_the_diagnostics_alone_reports_what_a_full_read_reports() {
    let mut compared = 0;
    each_case(|case, src, profile| {
        for d in dialect::ALL {
            for unsupported in [Unsupported::Error, Unsupported::Warn] {
                let (_, full) = d.read(src, profile, unsupported);
                let alone = d.diagnostics(src, profile, unsupported);
                assert_eq!(alone, full, "{} read as {}", case.name, d.id());
                compared += 1;
            }
        }
    });
    assert!(compared > 1000, "only {compared} reads compared");
}

/// Collects what a streaming read hands on.
#[derive(Default)]
struct Collect(Vec<ncthread::ir::Item>);

impl dialect::ItemSink for Collect {
    fn item(&mut self, item: ncthread::ir::Item) {
        self.0.push(item);
    }
}

/// A streaming read (`check`, issue 34) hands on each line's items once the line is read:
/// in order they must be the full read's items, its diagnostics the full read's, and the
/// program it returns the full read's but for the items — for every corpus file read as every
/// dialect, with and without `--unsupported warn`. (A FANUC G71 holds on to its item until
/// its contour has been read: its moves are filled in then.)
#[test]
fn a_streaming_read_hands_on_the_full_reads_items_in_order() {
    let mut compared = 0;
    each_case(|case, src, profile| {
        for d in dialect::ALL {
            for unsupported in [Unsupported::Error, Unsupported::Warn] {
                let (full, full_diags) = d.read(src, profile, unsupported);
                let mut sink = Collect::default();
                let (mut streamed, diags) = d.stream(src, profile, unsupported, &mut sink);
                let what = format!("{} read as {}", case.name, d.id());
                assert_eq!(diags, full_diags, "{what}");
                assert!(streamed.items.is_empty(), "{what}: items kept");
                streamed.items = sink.0;
                assert_eq!(streamed, full, "{what}");
                compared += 1;
            }
        }
    });
    assert!(compared > 1000, "only {compared} reads compared");
}

/// A conversion to a target whose writer takes one item at a time reads the program once or twice
/// and never holds it (issue 34): its output and diagnostics must be those of the conversion
/// that holds the program, for every corpus file and every such target.
#[test]
fn a_streaming_conversion_writes_what_the_whole_program_writes() {
    let mut compared = 0;
    each_case(|case, src, profile| {
        for to in dialect::ALL.iter() {
            for (unsupported, round) in [(Unsupported::Error, false), (Unsupported::Warn, true)] {
                let mut options = ncthread::ConvertOptions::new(case.from, to.id());
                options.profile = profile.clone();
                options.unsupported = unsupported;
                options.round = round;
                let streamed = ncthread::convert(src, &options);
                let whole = ncthread::convert_whole(src, &options);
                let what = format!(
                    "{} to {} ({unsupported:?}, round {round})",
                    case.name,
                    to.id()
                );
                assert_eq!(streamed.output, whole.output, "{what}");
                assert_eq!(streamed.diagnostics, whole.diagnostics, "{what}");
                compared += 1;
            }
        }
    });
    assert!(compared > 600, "only {compared} conversions compared");
}

/// A conversion reads its source once while nothing its writer reads of the program (the
/// facts it gathers, the header) changes after the writer's first item, and again when
/// something does: each such program converts as the whole program does — a FANUC number
/// after a comment, an arc after the ISO header, an inch program, an R parameter after the
/// first block, an error after the first moves.
#[test]
fn a_writer_made_before_what_it_reads_changed_is_let_go_of() {
    let cases = [
        (
            "fanuc",
            "%\n(SHAFT)\nO0100\nG21 G99\nT0101\nG97 S500 M03\nG00 X40. Z5.\nG01 Z-20. F0.2\nG00 X45.\nM30\n%\n",
        ),
        (
            "iso",
            "G7 G18 G21 G90 G95\nT1 M6\nS500 M3\nG0 X40 Z5\nG1 Z-10 F0.2\nG2 X44 Z-12 I2 K0\nG0 X50\nM5\nM30\n",
        ),
        (
            "iso",
            "G7 G18 G20 G90 G95\nT1 M6\nS500 M3\nG0 X1.5 Z0.2\nG1 Z-1 F0.008\nG0 X2\nM5\nM30\n",
        ),
        (
            "czech",
            "N10 G95 M03 S800 T1 D1\nN20 G00 X34. Z2.\nN30 R07=30.\nN40 G01 Z-40. F0.25\nN50 G00 X40.\nN60 M30\n",
        ),
        (
            "czech",
            "N10 G95 M03 S800 T1 D1\nN20 G00 X34. Z2.\nN40 G01 Z-40. F0.25\nN50 G00 X40. Q7\nN60 M30\n",
        ),
        // A lead over 99.99 no parameter holds when it is written (the block's own assignment
        // takes effect after it), then R01 assigned: the lead must not go through R01.
        (
            "czech",
            "N10 G95 M03 S800 T1 D1\nN20 R10=250.\nN30 G00 X34. Z2.\nN40 R10=300. G33 Z-40. FR10\nN50 G00 X40.\nN60 R01=5.\nN70 M30\n",
        ),
    ];
    // An arc after the ISO writer's first megabyte: its header's modes line is no longer
    // held, so the writer cannot take the arc late.
    let mut long = String::from("G7 G18 G21 G90 G95\nT1 M6\nS500 M3\nG0 X40 Z5\n");
    for i in 0..150_000 {
        long.push_str(if i % 2 == 0 {
            "G1 X40 Z-10 F0.2\n"
        } else {
            "G1 X41 Z-1 F0.2\n"
        });
    }
    long.push_str("G1 X40 Z-10\nG2 X44 Z-12 I2 K0\nG0 X50\nM5\nM30\n");
    let cases = cases.iter().map(|&(from, text)| (from, text.to_string()));
    for (from, text) in cases.chain([("iso", long)]) {
        let src = SourceFile::new(format!("program.{from}"), text.as_str());
        let from = dialect::by_id(from).unwrap().id();
        for to in dialect::ALL.iter() {
            let options = ncthread::ConvertOptions::new(from, to.id());
            let streamed = ncthread::convert(&src, &options);
            if from.as_str() == "iso" && to.id().as_str() == "iso" {
                let out = streamed.output.as_deref();
                assert!(out.is_some(), "{:?}", streamed.diagnostics);
            }
            let whole = ncthread::convert_whole(&src, &options);
            let what = format!("{from} to {}: {}", to.id(), &text[..text.len().min(300)]);
            assert_eq!(streamed.output, whole.output, "{what}");
            assert_eq!(streamed.diagnostics, whole.diagnostics, "{what}");
        }
    }
}

/// A source of a megabyte or more has its writer side in a thread of its own (on a machine
/// with a second core), fed the items in batches: each such program converts as the whole
/// program does — an R parameter assigned after many items (the writer takes it late, across
/// the threads), an error after many items (the writer's thread let go of), every dialect to
/// every target.
#[test]
fn a_large_program_converts_with_its_writer_in_a_thread_as_the_whole_program_does() {
    let programs = [
        (
            "czech",
            "N10 G95 M03 S800 T1 D1\n",
            "N20 G00 X34. Z2.\nN30 G01 Z-40. F0.25\nN40 G00 X40.\n",
            "N50 R07=30.\nN60 G00 X50.\nN70 M30\n",
        ),
        (
            "czech",
            "N10 G95 M03 S800 T1 D1\n",
            "N20 G00 X34. Z2.\nN30 G01 Z-40. F0.25\nN40 G00 X40.\n",
            "N50 G00 X40. Q7\nN60 M30\n",
        ),
        (
            "iso",
            "G7 G18 G21 G90 G95\nT1 M6\nS500 M3\n",
            "G0 X40 Z5\nG1 Z-10 F0.2\nG0 X50\n",
            "M5\nM30\n",
        ),
        // An inch program: whether the output is in inches is known only at the end, so the
        // writer made at its first item is let go of and the program read again (the reading
        // of the first writer's output beside it must not wait for that writer).
        (
            "iso",
            "G7 G18 G20 G90 G95\nT1 M6\nS500 M3\n",
            "G0 X1.5 Z0.2\nG1 Z-0.4 F0.008\nG0 X2\n",
            "M5\nM30\n",
        ),
        (
            "fanuc",
            "%\nO0100\nG21 G99\nT0101\nG97 S500 M03\n",
            "G00 X40. Z5.\nG01 Z-20. F0.2\nG00 X45.\n",
            "M05\nM30\n%\n",
        ),
    ];
    for (from, head, body, tail) in programs {
        let mut text = String::from(head);
        while text.len() < 3 << 19 {
            text.push_str(body);
        }
        text.push_str(tail);
        let src = SourceFile::new(format!("program.{from}"), text.as_str());
        let from = dialect::by_id(from).unwrap().id();
        for to in dialect::ALL.iter() {
            let options = ncthread::ConvertOptions::new(from, to.id());
            let streamed = ncthread::convert(&src, &options);
            let whole = ncthread::convert_whole(&src, &options);
            let what = format!("{from} to {}: …{tail}", to.id());
            assert_eq!(streamed.output, whole.output, "{what}");
            assert_eq!(streamed.diagnostics, whole.diagnostics, "{what}");
        }
    }
}

/// With the outputs' temporary files made beside the destination (`files::spool_beside`, as
/// `convert -o` has it), a large conversion's output, encoded as it is (LF) or changed (CRLF),
/// becomes the destination by a link (`Encoded::link_into_place` answers true) with the bytes
/// a copy writes; made in the system's temporary folder, it is not linked. Linux only.
#[cfg(target_os = "linux")]
#[test]
fn a_large_output_made_beside_its_destination_is_linked_into_place() {
    use ncthread::text::{Encoded, Eol, Input, OutputOptions, encode_output_owned};
    let program = common::large_czech_program(3 << 20);
    let src = SourceFile::new("big.nc", program.as_str());
    let czech = dialect::by_id("czech").unwrap().id();
    let options = ncthread::ConvertOptions::new(czech, dialect::by_id("iso").unwrap().id());
    let input = Input::default();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("big.ngc");
    let encoded = |eol: Eol| -> Encoded {
        let output = ncthread::convert(&src, &options).output.expect("converts");
        let form = OutputOptions {
            eol,
            ..OutputOptions::default()
        };
        encode_output_owned(output, "big.ngc", &form, &input).expect("encodes")
    };
    for eol in [Eol::Lf, Eol::CrLf] {
        let mut copy = Vec::new();
        encoded(eol).write_to(&mut copy).unwrap();
        assert!(copy.len() > 1 << 20);
        assert!(
            !encoded(eol).link_into_place(&path).unwrap(),
            "made in TMPDIR"
        );
        ncthread::files::spool_beside(Some(&path));
        let beside = encoded(eol);
        ncthread::files::spool_beside(None);
        assert!(beside.link_into_place(&path).unwrap(), "{eol:?}");
        assert!(std::fs::read(&path).unwrap() == copy, "{eol:?}");
    }
}

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

/// A conversion to a target whose writer takes one item at a time reads the program twice
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

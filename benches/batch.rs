//! Batch throughput: 10,000 small czech programs converted to ISO with 1 and 2 worker
//! threads. Prints the wall time of each run (`cargo bench --bench batch`); nothing is
//! asserted about time.
//!
//! `NCTHREAD_BENCH_FILES` changes the number of files.

use std::path::Path;
use std::time::Instant;

use ncthread::batch::{BatchOptions, ProfileChoice, plan, run};
use ncthread::{ConvertOptions, Unsupported};

fn program(i: usize) -> String {
    format!(
        "N10 G95 M03 S500 \"PROGRAM {i}\nN20 G00 X{}. Z5.\nN30 G33 Z-{}. F1.5\nN40 G00 X40.\nN50 Z5.\nN60 M30\n",
        30 + i % 7,
        20 + i % 5
    )
}

fn main() {
    let files: usize = std::env::var("NCTHREAD_BENCH_FILES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(10_000);
    let dir = tempfile::tempdir().expect("a temporary folder");
    let src = dir.path().join("src");
    for i in 0..files {
        let folder = src.join(format!("d{}", i % 100));
        std::fs::create_dir_all(&folder).unwrap();
        std::fs::write(folder.join(format!("p{i}.nc")), program(i)).unwrap();
    }
    println!(
        "batch: {files} czech programs → iso on {} core(s)",
        std::thread::available_parallelism().map_or(1, |n| n.get())
    );
    for jobs in [1, 2] {
        let out = dir.path().join(format!("out{jobs}"));
        let options = options(&src, &out, jobs);
        let started = Instant::now();
        let plan = plan(&options).expect("the trees can be used");
        let stop = std::sync::atomic::AtomicBool::new(false);
        let report = run(&options, &plan, &|_| {}, &stop).expect("the batch runs");
        let elapsed = started.elapsed();
        assert!(report.succeeded(), "{}", report.summary());
        println!(
            "  --jobs {jobs}: {:.2} s wall ({:.0} files/s) — {}",
            elapsed.as_secs_f64(),
            files as f64 / elapsed.as_secs_f64(),
            report.summary()
        );
    }
}

fn options(src: &Path, out: &Path, jobs: usize) -> BatchOptions {
    BatchOptions {
        src_dir: src.to_path_buf(),
        out_dir: out.to_path_buf(),
        from: Some(ncthread::dialect::czech::ID),
        conversion: ConvertOptions {
            from: ncthread::dialect::czech::ID,
            to: ncthread::dialect::iso::ID,
            profile: Default::default(),
            unsupported: Unsupported::Error,
            renumber: Default::default(),
            round: false,
            nc31_comments: false,
        },
        jobs,
        force: false,
        extension: "ngc".into(),
        selection: ncthread::files::Selection {
            extensions: ncthread::batch::program_extensions(Some(ncthread::dialect::czech::ID)),
            ..Default::default()
        },
        profile: ProfileChoice::Defaults,
        overrides: Default::default(),
        dry_run: false,
        input_encoding: None,
        output: Default::default(),
        html: None,
        report: None,
    }
}

//! The stages and the routes, measured with criterion on generated programs (issue 19): read
//! (LinuxCNC's macros evaluated in the ISO reader, and a 100,000-iteration loop on its own),
//! lower and simulate, emit, and end to end (`convert` with its read-back, and `check`), for
//! every dialect, on programs of 1 KB and 1 MB (`benches/support/programs.rs`). The 20 MB
//! figures are measured through the CLI (BENCHMARKS.md): criterion's repeated runs of them
//! would take minutes.
//!
//! `cargo bench --bench stages`; `NCTHREAD_BENCH_SIZES=1000` for the small programs only.
//! `cargo test --benches` runs each once (CI's smoke test). Nothing is asserted about time.

#[path = "support/programs.rs"]
mod programs;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use ncthread::profile::Profile;
use ncthread::source::SourceFile;
use ncthread::{ConvertOptions, DialectId, Unsupported};

const DIALECTS: [DialectId; 4] = [
    ncthread::dialect::czech::ID,
    ncthread::dialect::nc31::ID,
    ncthread::dialect::iso::ID,
    ncthread::dialect::fanuc::ID,
];

fn sizes() -> Vec<usize> {
    std::env::var("NCTHREAD_BENCH_SIZES")
        .ok()
        .map(|v| v.split(',').filter_map(|s| s.trim().parse().ok()).collect())
        .unwrap_or_else(|| vec![1_000, 1_000_000])
}

fn options(from: DialectId, to: DialectId) -> ConvertOptions {
    ConvertOptions::new(from, to)
}

fn stages(c: &mut Criterion) {
    let profile = Profile::default();
    for bytes in sizes() {
        for from in DIALECTS {
            let text = programs::program(from.as_str(), bytes).expect("a dialect");
            let src = SourceFile::new(format!("generated.{from}"), text);
            let (program, diags) = ncthread::parse(&src, from, &profile, Unsupported::Error);
            assert!(
                !ncthread::diag::has_errors(&diags),
                "the generated {from} program reads: {diags:?}"
            );
            let mut group = c.benchmark_group(format!("{from} {bytes} B"));
            group.sample_size(10);
            group.throughput(Throughput::Bytes(src.text.len() as u64));
            group.bench_function("read", |b| {
                b.iter(|| ncthread::parse(&src, from, &profile, Unsupported::Error))
            });
            group.bench_function("lower and simulate", |b| {
                b.iter(|| ncthread::sim::simulate(&program))
            });
            let mut targets = vec![ncthread::dialect::iso::ID];
            if from != ncthread::dialect::iso::ID {
                targets.push(from);
            }
            for to in targets {
                group.bench_function(BenchmarkId::new("emit", to), |b| {
                    b.iter(|| ncthread::emit(&program, &src, &options(from, to)))
                });
                group.bench_function(BenchmarkId::new("convert", to), |b| {
                    b.iter(|| ncthread::convert(&src, &options(from, to)))
                });
            }
            group.bench_function("check", |b| {
                b.iter(|| ncthread::check(&src, from, &profile, Unsupported::Error))
            });
            group.finish();
        }
    }
    // LinuxCNC's macro language on its own: a while loop of 100,000 iterations whose body
    // sets parameters from expressions.
    let looped = SourceFile::new(
        "loop.ngc",
        "G7 G18 G21 G90 G95\n#1=0\n#3=0\no100 while [#1 LT 100000]\n#2 = [#1 * 0.001 + SIN[#1]]\n#3 = [#3 + #2 / 2]\n#1 = [#1 + 1]\no100 endwhile\nG0 X20 Z5\nM2\n",
    );
    let mut group = c.benchmark_group("iso macros");
    group.sample_size(10);
    group.bench_function("while loop of 100,000 iterations", |b| {
        b.iter(|| {
            ncthread::parse(
                &looped,
                ncthread::dialect::iso::ID,
                &profile,
                Unsupported::Error,
            )
        })
    });
    group.finish();
}

criterion_group!(benches, stages);
criterion_main!(benches);

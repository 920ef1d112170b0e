//! Writes a realistic program of a dialect, of about a given size, for benchmarks (issue 19):
//! whole parts one after another (facing and turning moves, arcs, coolant, a tool change, a
//! thread: a czech multi-pass G33 thread, an НЦ-31 G31 cycle, a LinuxCNC G76 and a macro loop
//! of G33 passes with parameters, expressions and an O-word `while`), each part at other
//! diameters so that no two are alike.
//!
//! `cargo run --release --example generate -- czech|nc31|iso|fanuc BYTES > FILE`

#[path = "../benches/support/programs.rs"]
mod programs;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let program = match (args.first(), args.get(1).and_then(|b| b.parse().ok())) {
        (Some(dialect), Some(bytes)) => programs::program(dialect, bytes),
        _ => None,
    };
    let Some(program) = program else {
        eprintln!("usage: generate czech|nc31|iso|fanuc BYTES");
        std::process::exit(2);
    };
    print!("{program}");
}

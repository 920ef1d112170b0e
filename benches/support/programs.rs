//! Realistic programs of every dialect, of about a given size (issue 19): whole parts one after
//! another, each at other diameters. Used by `examples/generate.rs` and `benches/stages.rs`.

use std::fmt::Write as _;

fn czech(part: usize, out: &mut String) {
    let d = 30 + part % 20;
    let _ = write!(
        out,
        "N10 G95 M03 S800 T1 D1 \"PART {part}\n\
         N20 G00 X{x}. Z2.\n\
         N30 G01 X-1. Z0. F0.15 \"FACE\n\
         N40 G00 X{x}. Z2.\n\
         N50 G01 Z-40. F0.25\n\
         N60 G00 X{x2}. Z2.\n\
         N70 X{d}.\n\
         N80 G01 Z-30. F0.1\n\
         N90 G00 X{x}. Z50. M05\n\
         N100 T2 D2 M03 S400\n\
         N110 X{d}. Z5.\n",
        x = d + 4,
        x2 = d + 6,
    );
    for (n, depth) in [0.4, 0.7, 0.9, 1.0].iter().enumerate() {
        let _ = write!(
            out,
            "N{a} X{dx:.3}\nN{b} G33 Z-27. F1.5\nN{c} G00 X{e}.\nN{f} Z5.\n",
            a = 120 + n * 40,
            dx = d as f64 - depth,
            b = 130 + n * 40,
            c = 140 + n * 40,
            e = d + 4,
            f = 150 + n * 40,
        );
    }
    out.push_str("N300 G00 X60. Z50. M05\n");
}

fn nc31(part: usize, out: &mut String, n: &mut usize) {
    let d = 3000 + (part % 20) * 100;
    let mut frame = |text: String, out: &mut String| {
        let _ = writeln!(out, "N{} {text}", *n);
        *n += 1;
    };
    frame("M3".into(), out);
    frame("S700".into(), out);
    frame("F30".into(), out);
    frame(format!("X{} ~ *", d + 400), out);
    frame("Z200 ~".into(), out);
    frame("X-100 *".into(), out);
    frame("Z0".into(), out);
    frame(format!("X{} ~ *", d + 400), out);
    frame("Z450 ~".into(), out);
    frame(format!("X{d} *"), out);
    frame("Z-4750".into(), out);
    frame(format!("X{} ~ *", d + 400), out);
    frame("Z450 ~".into(), out);
    frame("G31 *".into(), out);
    frame(format!("X{d} *"), out);
    frame("Z-4750 *".into(), out);
    frame("F15000 *".into(), out);
    frame("P96 *".into(), out);
    frame("P20".into(), out);
    frame("X10000 ~ *".into(), out);
    frame("Z5000 ~".into(), out);
    frame("M5".into(), out);
}

fn iso(part: usize, out: &mut String) {
    let d = 30 + part % 20;
    let _ = write!(
        out,
        "(part {part})\n\
         T1 M6 G43\n\
         G96 D2500 S200 M3\n\
         M8\n\
         G0 X{x} Z2\n\
         G1 X-1 Z0 F0.15 (face)\n\
         G0 X{x} Z2\n\
         G1 Z-40 F0.25\n\
         G0 X{d} Z2\n\
         G1 Z-20 F0.1\n\
         G2 X{x} Z-22 I2 K0\n\
         G1 Z-40\n\
         G0 X60 Z50\n\
         M9\n\
         T2 M6 G43\n\
         G97 S600 M3\n\
         G0 X{x} Z5\n\
         G76 P1.5 Z-17 I-1 J0.4 K0.92 Q29.5 R1.5 H1 E1 L2\n",
        x = d + 4,
    );
    // A macro loop of G33 passes in every fourth part (LinuxCNC's loops are counted: a
    // program's loops run at most 200,000 times in ncthread), up to 25,000 loops (about
    // 200 MB of program).
    if !part.is_multiple_of(4) || part >= 100_000 {
        out.push_str("G0 X60 Z50\n");
        return;
    }
    let _ = write!(
        out,
        "#<pass> = 1\n\
         o{o} while [#<pass> LE 4]\n\
         G0 X[{d} - #<pass> * 0.25] Z5\n\
         G33 Z-17 K1.5\n\
         G0 X{x}\n\
         G0 Z5\n\
         #<pass> = [#<pass> + 1]\n\
         o{o} endwhile\n\
         G0 X60 Z50\n",
        x = d + 4,
        o = 100 + part,
    );
}

fn fanuc(part: usize, out: &mut String) {
    let d = 30 + part % 20;
    let _ = write!(
        out,
        "(PART {part})\n\
         T0101\n\
         G50 S2500\n\
         G96 S200 M03\n\
         M08\n\
         G00 X{x}. Z2.\n\
         G01 X-1. F0.15\n\
         G00 X{x}. Z2.\n\
         G01 Z-40. F0.25\n\
         G00 X{d}. Z2.\n\
         G01 Z-20. F0.1\n\
         G02 X{x}. Z-22. I2. K0.\n\
         G01 Z-40.\n\
         G00 X60. Z50.\n\
         M09\n\
         T0202\n\
         G97 S600 M03\n",
        x = d + 4,
    );
    for depth in [0.4, 0.7, 0.9, 1.0] {
        let _ = write!(
            out,
            "G00 X{dx:.3} Z5.\nG32 Z-27. F1.5\nG00 X{e}.\nZ5.\n",
            dx = d as f64 - depth,
            e = d + 4
        );
    }
    out.push_str("G00 X60. Z50.\nM05\n");
}

/// A program of `dialect` (`czech`, `nc31`, `iso`, `fanuc`) of at least `bytes` bytes.
pub fn program(dialect: &str, bytes: usize) -> Option<String> {
    let mut out = String::new();
    match dialect {
        "iso" => out.push_str("%\nG7 G18 G21 G90 G95\n"),
        "fanuc" => out.push_str("%\nO0001 (GENERATED)\nG21 G99\n"),
        "czech" | "nc31" => {}
        _ => return None,
    }
    let (mut part, mut n) = (0, 0);
    while out.len() < bytes {
        match dialect {
            "czech" => czech(part, &mut out),
            "nc31" => nc31(part, &mut out, &mut n),
            "iso" => iso(part, &mut out),
            _ => fanuc(part, &mut out),
        }
        part += 1;
    }
    match dialect {
        "czech" => out.push_str("N999 M30\n"),
        "nc31" => {
            let _ = writeln!(out, "N{n} M30");
        }
        "iso" => out.push_str("M2\n%\n"),
        _ => out.push_str("M30\n%\n"),
    }
    Some(out)
}

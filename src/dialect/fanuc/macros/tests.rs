//! The run of macro programs: jumps, loops, calls and their refusals.

use crate::diag::Diagnostic;
use crate::dialect::Unsupported;
use crate::dialect::fanuc::front;
use crate::dialect::read::Keep;
use crate::ir::ItemKind;
use crate::source::SourceFile;

const HEAD: &str = "G21 G99\nG97 S500 M03\nG00 X50. Z5.\n";

fn read_with(text: &str, path: &[std::path::PathBuf]) -> (Vec<(f64, f64)>, Vec<Diagnostic>) {
    let profile = crate::profile::Profile::default();
    let src = SourceFile::new("t.nc", format!("%\nO0001\n{HEAD}{text}M30\n%\n"));
    let (p, d) = front::read(
        &src,
        &profile.fanuc,
        path,
        Unsupported::Error,
        Keep::Program,
    );
    // Where each move ends (an axis not written stays where it was).
    let mut at = (f64::NAN, f64::NAN);
    let mut moves = Vec::new();
    for i in &p.items {
        if let ItemKind::Rapid { to } | ItemKind::Feed { to, .. } = &i.kind {
            at = (
                to.x.map_or(at.0, |l| l.to_mm_f64()),
                to.z.map_or(at.1, |l| l.to_mm_f64()),
            );
            moves.push(at);
        }
    }
    moves.remove(0);
    (moves, d)
}

fn read(text: &str) -> (Vec<(f64, f64)>, Vec<Diagnostic>) {
    read_with(text, &[])
}

fn xs(text: &str) -> Vec<f64> {
    let (moves, d) = read(text);
    assert!(d.is_empty(), "{text}: {d:?}");
    moves.iter().map(|m| m.0).collect()
}

fn refusal(text: &str) -> (String, String, u32) {
    let (_, d) = read(text);
    let d = d
        .into_iter()
        .next()
        .unwrap_or_else(|| panic!("{text}: no diagnostic"));
    let line = d.location.as_ref().map_or(0, |l| l.line);
    (d.code.id.to_string(), d.message, line)
}

#[test]
fn plain_programs_do_not_run_through_macros() {
    assert!(!super::uses_macros(&SourceFile::new(
        "t",
        "O0001\nG00 X20. Z5.\nM30\n"
    )));
    assert!(!super::uses_macros(&SourceFile::new(
        "t",
        "[BILLET X33 Z65\n(IF #1 GOTO)\n"
    )));
    assert!(super::uses_macros(&SourceFile::new("t", "M98 P100\n")));
    // A title with a keyword in it is a title; a keyword inside a word is no statement.
    let title = "SHAFT END DOOR\n%\nO0001\nG00 X1. Z1.\nM30\n%\n";
    assert!(!super::uses_macros(&SourceFile::new("t", title)));
    assert!(super::uses_macros(&SourceFile::new("t", "N10 GOTO 20\n")));
    assert!(super::uses_macros(&SourceFile::new("t", "G00 X#1\n")));
    // Every way a word may write a call (blanks, a sign, zeros, a point, lower case).
    for call in [
        "G65 P9010",
        "g 065 p9010",
        "G+66P1",
        "G67.",
        "M98P100",
        "m 99",
        "N5 M098 P1",
        "M99.0",
        "G0 (M98) M98 P2",
        "\tM\t99",
    ] {
        assert!(super::uses_macros(&SourceFile::new("t", call)), "{call}");
    }
    for plain in [
        "G96 S200",
        "M09",
        "G01 X65. Z-98.",
        "M9",
        "(M98 P1) G00",
        "G6.5",
    ] {
        assert!(!super::uses_macros(&SourceFile::new("t", plain)), "{plain}");
    }
}

#[test]
fn nested_loops_and_goto_out_of_a_loop() {
    let nested = "#1=0\nWHILE [#1 LT 2] DO 1\n#2=0\nWHILE [#2 LT 2] DO 2\nG00 X[10.+#1*10.+#2]\n#2=#2+1\nEND 2\n#1=#1+1\nEND 1\n";
    assert_eq!(xs(nested), [10.0, 11.0, 20.0, 21.0]);
    // Out of a loop: allowed.
    let out = "#1=0\nWHILE [#1 LT 9] DO 1\nG00 X[10.+#1]\nIF [#1 EQ 1] GOTO 50\n#1=#1+1\nEND 1\nN50 G00 X40.\n";
    assert_eq!(xs(out), [10.0, 11.0, 40.0]);
    // Into a loop from outside it: refused.
    let into = "#1=0\nGOTO 20\nWHILE [#1 LT 2] DO 1\nN20 G00 X10.\n#1=#1+1\nEND 1\n";
    let (code, message, line) = refusal(into);
    assert_eq!((code.as_str(), line), ("FANR019", 7), "{message}");
    assert!(message.contains("into a WHILE"), "{message}");
    // A bare DO is an endless loop, ended by GOTO.
    let bare = "#1=0\nDO 1\n#1=#1+1\nIF [#1 GT 3] GOTO 9\nEND 1\nN9 G00 X[#1]\n";
    assert_eq!(xs(bare), [4.0]);
    let (code, _, _) = refusal("END 1\n");
    assert_eq!(code, "FANR019");
    let (code, _, _) = refusal("WHILE [1 EQ 0] DO 2\n");
    assert_eq!(code, "FANR019");
}

#[test]
fn indirect_variables_and_commons() {
    assert_eq!(xs("#1=100\n#[#1+5]=7.\nG00 X#105\n"), [7.0]);
    assert_eq!(xs("#500=3.\nG00 X[#500*2]\n"), [6.0]);
    // A common variable outlives a G65 level, a local does not.
    let text = "#1=5.\nG65 P100 A1.\nG00 X[#1+#100]\nM30\nO100\n#100=#1*10\nM99\n";
    assert_eq!(xs(text), [15.0]);
    let (code, message, _) = refusal("#0=1\n");
    assert_eq!(code, "FANR019", "{message}");
    let (code, message, _) = refusal("#40=1\n");
    assert!(message.contains("#40"), "{code} {message}");
    let (code, _, _) = refusal("G00 X#4001\n");
    assert_eq!(code, "FANR020");
    let (code, message, _) = refusal("#3000=1\n");
    assert!(code == "FANR019" && message.contains("alarm"), "{message}");
    let (code, _, _) = refusal("#1=1/#0\n");
    assert_eq!(code, "FANR019");
    let (code, message, _) = refusal("/#1=1\n");
    assert!(
        code == "FANR002" && message.contains("block skip"),
        "{message}"
    );
}

#[test]
fn subprograms_calls_and_returns() {
    // M98 shares the caller's locals; L and the packed P repeat.
    let body = "M30\nO200\nG00 X[#1] W-1.\n#1=#1+1\nM99\n";
    let text = format!("#1=10.\nM98 P200 L2\nM98 P20200\nM98 P200 L0\n{body}");
    assert_eq!(xs(&text), [10.0, 11.0, 12.0, 13.0]);
    // G65: arguments to their locals, nested levels.
    let text = "G65 P300 X20. Z-3. I4.\nM30\nO300\nG01 X[#24+#4] Z#26 F0.1\nG65 P301 A1.\nG00 X#24\nM99\nO301\nG00 X#1\nM99\n";
    let (moves, d) = read(text);
    assert!(d.is_empty(), "{d:?}");
    assert_eq!(moves, [(24.0, -3.0), (1.0, -3.0), (20.0, -3.0)]);
    let (code, message, _) = refusal("G65 P300 X20\nM30\nO300\nM99\n");
    assert!(
        code == "FANR006" && message.contains("decimal point"),
        "{message}"
    );
    let (code, _, _) = refusal("G65 P300 G01\nM30\nO300\nM99\n");
    assert_eq!(code, "FANR019");
    let (code, message, _) = refusal("M99\n");
    assert!(
        code == "FANR019" && message.contains("main program"),
        "{message}"
    );
    let (code, message, _) = refusal("G66 P300 X1.\n");
    assert!(code == "FANR002" && message.contains("G66"), "{message}");
    let (code, message, _) = refusal("M98 P400\n");
    assert!(code == "FANR019" && message.contains("O0400"), "{message}");
    // A call without end: the depth limit, with its chain.
    let (code, message, line) = refusal("M98 P500\nM30\nO500\nM98 P500\nM99\n");
    assert_eq!((code.as_str(), line), ("FANR019", 9), "{message}");
    assert!(
        message.contains("(in O0500 called from line 9 (9 times), in O0500 called from line 6)"),
        "{message}"
    );
    // M30 in a subprogram ends the program.
    assert_eq!(xs("M98 P600\nG00 X20.\nM30\nO600\nG00 X10.\nM30\n"), [10.0]);
}

#[test]
fn a_diagnostic_in_a_subprogram_is_at_its_line_with_the_chain() {
    let (_, d) = read("M98 P700\nM30\nO700\nG01 Z-10.\nM99\n");
    let d = &d[0];
    assert_eq!(d.code.id, "FANR009");
    assert_eq!(d.location.as_ref().map(|l| l.line), Some(9));
    assert!(
        d.message.ends_with("(in O0700 called from line 6)"),
        "{}",
        d.message
    );
}

#[test]
fn a_subprogram_from_a_file_in_the_subroutine_path() {
    let dir = std::env::temp_dir().join(format!("ncthread-fanuc-subs-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("O0800.nc"), "O0800\nG00 X#1\nG01 Z-4.\nM99\n").unwrap();
    let (moves, d) = read_with("#1=12.\nM98 P800\n", std::slice::from_ref(&dir));
    std::fs::remove_dir_all(&dir).ok();
    assert_eq!(moves, [(12.0, 5.0)]);
    // The feed has no F: said at the file's line, with the chain.
    let d = &d[0];
    assert_eq!(d.code.id, "FANR009");
    assert!(
        d.location
            .as_ref()
            .is_some_and(|l| l.file.ends_with("O0800.nc") && l.line == 3)
    );
    assert!(
        d.message.contains("in O0800 called from line 7"),
        "{}",
        d.message
    );
}

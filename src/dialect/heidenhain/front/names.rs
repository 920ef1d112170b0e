//! The names of what the HEIDENHAIN reader does not read, for its refusals.

use super::syntax::Word;

/// The addresses a block may hold besides G and M.
pub(super) const LETTERS: &[&str] = &[
    "X", "XI", "Z", "ZI", "I", "K", "R", "F", "B", "P", "C", "H", "E", "S", "T",
];

/// The G codes the reader reads.
pub(super) const KNOWN_G: &[i64] = &[0, 1, 2, 3, 4, 12, 13, 26, 33, 40, 94, 95, 96, 97];

/// Why a G code is not read.
pub(super) fn refused_g(g: u32) -> &'static str {
    match g {
        32 | 35 => "thread cycles are not read; write the passes as G33 blocks",
        36 | 37 => "tapping is not read",
        41 | 42 => {
            "cutter radius compensation is not read (its radius and tip are in the tool's data, which the program does not state)"
        }
        14 => {
            "the tool change point (G14) is the machine's position, which the program does not state"
        }
        51 | 53..=56 | 59 => "zero point shifts are not read",
        701 => "moves in machine coordinates are not read",
        800..=899 => "contour cycles are not read (their passes follow the contour sections)",
        352 => "the API thread cycle (G352) is not read",
        _ => "it is not a G code ncthread reads in a HEIDENHAIN DIN program",
    }
}

/// What an address the reader does not read is, for its refusal.
pub(super) fn refused_letter(w: &Word) -> String {
    match w.name.as_str() {
        "BR" | "BE" | "RB" => format!(
            "`{}`: chamfer and rounding words are not read (where the corner goes depends on the next block's path)",
            w.name
        ),
        "AN" | "Q" | "A" => format!(
            "`{}`: a move given by its angle or intersection is not read",
            w.name
        ),
        "ID" => "`ID`: a tool's name belongs in the turret table".into(),
        "L" => "`L`: subprogram calls are not read".into(),
        "D" => "`D`: a dwell in revolutions (G4 D) is not read".into(),
        name => format!("address `{name}` is not read"),
    }
}

//! The names of what the SINUMERIK reader does not read, for its refusals.

/// Why a G code is not read.
pub(super) fn refused_g(g: u32) -> &'static str {
    match g {
        17 | 19 => "the plane of a lathe program is G18",
        41 | 42 => {
            "cutter radius compensation is not read (its radius and tip are in the tool's data, which the program does not state)"
        }
        53 | 153 | 500 | 74 | 75 => "machine coordinates, frames and reference moves are not read",
        331 | 332 | 63 => "tapping is not read",
        34 | 35 => "threads of increasing or decreasing lead are not read",
        9 | 60 | 64 | 641 | 642 | 645 => {
            "exact stop and continuous-path modes are not read (G64 rounds corners)"
        }
        _ => "it is not a G code ncthread reads in a SINUMERIK program",
    }
}

/// The letters and names a block may hold (besides G, M and DIAMON/DIAMOF).
pub(super) const LETTERS: &[&str] = &["X", "Z", "I", "K", "F", "S", "T", "D", "SF", "CR", "LIMS"];

/// What a name the reader does not read is, for its refusal.
pub(super) fn refused_name(name: &str, text: &str) -> String {
    let digits_after = |p: &str| {
        name.strip_prefix(p)
            .is_some_and(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()))
    };
    if name.starts_with("CYCLE") {
        format!(
            "`{name}`: SINUMERIK's cycles are not read (no pass or infeed law of theirs is published); write the passes as G33 blocks"
        )
    } else if digits_after("R") {
        format!("`{name}`: R parameters are not read")
    } else if matches!(name, "DEF" | "DEFINE") {
        format!("`{name}`: variables are not read")
    } else if matches!(
        name,
        "GOTO"
            | "GOTOF"
            | "GOTOB"
            | "GOTOC"
            | "IF"
            | "ELSE"
            | "ENDIF"
            | "WHILE"
            | "ENDWHILE"
            | "LOOP"
            | "ENDLOOP"
            | "FOR"
            | "ENDFOR"
            | "REPEAT"
            | "UNTIL"
            | "CASE"
    ) {
        format!("`{name}`: program jumps and loops are not read")
    } else if name == "L" || digits_after("L") {
        format!("`{text}`: subprogram calls are not read")
    } else if matches!(name, "CHF" | "CHR" | "RND" | "RNDM") {
        format!(
            "`{name}`: chamfer and rounding words are not read (where the corner goes depends on the next block's path)"
        )
    } else if matches!(name, "DIAM90" | "DIAMCYCOF") {
        format!("`{name}`: only DIAMON and DIAMOF are read")
    } else if name.len() == 1 {
        format!("address `{name}` is not read (`{text}`)")
    } else {
        format!("`{name}` is not read")
    }
}

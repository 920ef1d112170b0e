//! What ncthread does not read: the codes it refuses or keeps, a mill program, and a line
//! kept opaque under `--unsupported warn`.

use std::ops::Range;

use super::super::gcode::*;
use super::super::syntax::{BLOCK_DELETE, Block, Word};
use super::{FrontEnd, UNSUPPORTED};
use crate::dialect::Unsupported;
use crate::dialect::iso::codes;
use crate::ir::{FeedMode, ModalContext};
use crate::source::Line;

/// What a G or M code is to ncthread.
pub(super) enum Meaning {
    /// Read and modelled.
    Known,
    /// Changes nothing ncthread models: kept as an opaque word for ISO output.
    Kept,
    /// Not read: the reason.
    Unsupported(&'static str),
}

/// The G codes the reader reads, as written (for "did you mean").
pub(super) const KNOWN_G: &[&str] = &[
    "G0", "G1", "G2", "G3", "G4", "G7", "G8", "G18", "G20", "G21", "G28", "G30", "G33", "G33.1",
    "G40", "G41", "G42", "G41.1", "G42.1", "G43", "G52", "G53", "G54", "G55", "G56", "G57", "G58",
    "G59", "G70", "G71", "G72", "G73", "G76", "G80", "G81", "G82", "G83", "G85", "G89", "G90",
    "G91", "G92", "G94", "G95", "G96", "G97", "G98", "G99",
];

pub(super) fn g_meaning(code: GCode) -> Meaning {
    match code {
        G0 | G1 | G2 | G3 | G33 | G33_1 | G76 | G4 | G7 | G8 | G17 | G18 | G20 | G21 | G43
        | G90 | G91 | G90_1 | G91_1 | G94 | G95 | G96 | G97 | G40 | G41 | G42 | G41_1 | G42_1
        | G54 | G55 | G56 | G57 | G58 | G59 | G59_1 | G59_2 | G59_3 | G28 | G28_1 | G30 | G30_1
        | G53 | G52 | G92 | G92_1 | G92_2 | G92_3 | G70 | G71 | G71_1 | G71_2 | G72 | G72_1
        | G72_2 | G73 | G80 | G81 | G82 | G83 | G85 | G89 | G98 | G99 => Meaning::Known,
        // Tool length offset off, exact path / blending.
        G49 | G61 | G61_1 | G64 => Meaning::Kept,
        // Refused in every mode by `not_a_lathe_program`.
        G19 | G17_1 | G18_1 | G19_1 => {
            Meaning::Unsupported("another plane than ZX (G18) or XY (G17): not a lathe program")
        }
        G10 => Meaning::Unsupported("changes of the coordinate systems (G10)"),
        G93 => Meaning::Unsupported("inverse-time feed (G93)"),
        G74 | G84 | G86 | G87 | G88 => Meaning::Unsupported(
            "tapping and boring cycles that stop or reverse the spindle (G74, G84, G86, G87, G88)",
        ),
        _ => Meaning::Unsupported("this G code"),
    }
}

/// Whether a word changes modal state that ncthread follows (units, distance, diameter and
/// feed modes, feed, speed, tool, spindle, coolant, stops, program end): such a word cannot sit on a line
/// kept opaque.
pub(super) fn changes_followed_state(w: &Word) -> bool {
    match w.letter {
        'F' | 'S' | 'T' => true,
        'G' => w.value.to_scaled(1).is_ok_and(|g| {
            matches!(
                g,
                G7 | G8
                    | G20
                    | G21
                    | G90
                    | G91
                    | G90_1
                    | G91_1
                    | G93
                    | G94
                    | G95
                    | G96
                    | G97
                    | G43
                    | G49
                    | G40..=G42_1
                    | G54..=G59_3
                    | G28..=G30_1
                    | G53
                    | G52
                    | G92..=G92_3
                    | G98
                    | G99
            )
        }),
        'M' => w
            .value
            .to_whole()
            .is_ok_and(|m| matches!(m, 0..=9 | 30 | 60)),
        _ => false,
    }
}

/// LinuxCNC's user M codes, M100–M199: each runs the program of that name in the
/// configuration's USER_M_PATH and waits for it; none moves an axis (LinuxCNC G-code
/// documentation, "M100 to M199 User Defined Commands"). **\[evidence\]**
pub(super) const USER_M_FIRST: i64 = 100;
/// The last of LinuxCNC's user M codes.
pub(super) const USER_M_LAST: i64 = 199;

/// Whether a line kept opaque may move the machine: an axis word (or an expression for
/// one), a code that moves or changes the coordinates, a G or M code ncthread does not know,
/// or an O-word. A line of modes and path settings (`/G64 P0.01`) cannot.
pub(super) fn may_move(line: Line<'_>, block: &Block) -> bool {
    let axis = |c: char| "XYZABCUVW".contains(c.to_ascii_uppercase());
    block.unread.iter().any(|u| match u.what {
        BLOCK_DELETE | "parameter assignment" => false,
        "parameter or expression as a value" => {
            line.text[u.range.clone()].chars().next().is_none_or(axis)
        }
        _ => true,
    }) || block.words.iter().any(|w| match w.letter {
        c if axis(c) => true,
        'G' => w.value.to_scaled(1).map_or(true, |g| {
            !matches!(
                g,
                G4 | G7
                    | G8
                    | G17
                    | G18
                    | G19
                    | G17_1
                    | G18_1
                    | G19_1
                    | G20
                    | G21
                    | G40..=G42_1
                    | G43
                    | G49
                    | G54..=G59_3
                    | G61
                    | G61_1
                    | G64
                    | G80
                    | G90
                    | G91
                    | G90_1
                    | G91_1
                    | G93
                    | G94
                    | G95
                    | G96
                    | G97
                    | G98
                    | G99
            )
        }),
        'M' => w.value.to_whole().map_or(
            true,
            |m| !matches!(m, 0..=5 | 7..=9 | USER_M_FIRST..=USER_M_LAST),
        ),
        _ => false,
    })
}

pub(super) fn m_meaning(code: i64) -> Meaning {
    match code {
        // Stops, program end, spindle, tool change, coolant.
        0..=9 | 30 => Meaning::Known,
        // Saving and restoring the modal state: the macro runner's (`front/macros.rs`).
        70..=73 => Meaning::Known,
        // The user's M codes: programs of the machine's configuration (USER_M_PATH).
        USER_M_FIRST..=USER_M_LAST => Meaning::Known,
        _ => Meaning::Unsupported("this M code"),
    }
}

/// Whether ncthread reads all the line holds: nothing unread, no axis but X and Z, and only G
/// and M codes it reads or keeps — the lines [`FrontEnd::unsupported`] neither reports nor
/// skips (it returns false), told in one look at each word (most lines; the look of each of
/// its checks took three).
fn reads_every_word(block: &Block) -> bool {
    block.unread.is_empty()
        && block.words.iter().all(|w| match w.letter {
            'Y' | 'A' | 'B' | 'C' | 'U' | 'V' | 'W' => false,
            'G' => w
                .value
                .to_scaled(1)
                .is_ok_and(|g| !matches!(g_meaning(g), Meaning::Unsupported(_))),
            'M' => w
                .value
                .to_whole()
                .is_ok_and(|m| !matches!(m_meaning(m), Meaning::Unsupported(_))),
            _ => true,
        })
}

/// What a line holds that ncthread does not read: its unread parts, then its G and M codes
/// that are not read, each with its message.
fn unread_words(line: Line<'_>, block: &Block) -> Vec<(Range<usize>, String)> {
    let mut found: Vec<(Range<usize>, String)> = block
        .unread
        .iter()
        .map(|u| {
            (
                u.range.clone(),
                if u.what == BLOCK_DELETE {
                    "block delete `/`: whether this line runs is the operator's switch; say which with --block-delete off (it runs) or on (it is skipped), or `block_delete` in the profile's [iso] section".to_string()
                } else {
                    format!("{} is not read by ncthread", u.what)
                },
            )
        })
        .collect();
    for w in &block.words {
        let text = &line.text[w.range.clone()];
        let why = match w.letter {
            'G' => match w.value.to_scaled(1).map(g_meaning) {
                Ok(Meaning::Unsupported("this G code")) => {
                    let hint = crate::dialect::read::did_you_mean(text, KNOWN_G);
                    found.push((
                        w.range.clone(),
                        format!("`{text}`: this G code — not read by ncthread{hint}"),
                    ));
                    None
                }
                Ok(Meaning::Unsupported(why)) => Some(why),
                Err(_) => Some("this G code"),
                _ => None,
            },
            'M' => match w.value.to_whole().map(m_meaning) {
                Ok(Meaning::Unsupported(why)) => Some(why),
                Err(_) => Some("this M code"),
                _ => None,
            },
            _ => None,
        };
        if let Some(why) = why {
            found.push((
                w.range.clone(),
                format!("`{text}`: {why} — not read by ncthread"),
            ));
        }
    }
    found
}

impl FrontEnd<'_> {
    /// A plane other than ZX or an axis other than X and Z: the program is not a lathe
    /// program, and no mode may keep the line (a mill program half converted is worse than
    /// none). Reports each such word (ISOR021); true when there was one.
    pub(super) fn not_a_lathe_program(&mut self, line: Line<'_>, block: &Block) -> bool {
        let roughing = block.words.iter().any(|w| {
            w.letter == 'G'
                && w.value
                    .to_scaled(1)
                    .is_ok_and(|g| matches!(g, G70 | G71 | G71_1 | G71_2 | G72 | G72_1 | G72_2))
        });
        // The first such word of the line is reported (a line may hold thousands).
        let Some((w, why)) = block.words.iter().find_map(|w| {
            let why = match w.letter {
                'U' | 'W' if roughing => None,
                'G' if w
                    .value
                    .to_scaled(1)
                    .is_ok_and(|g| matches!(g, G19 | G17_1 | G18_1 | G19_1)) =>
                {
                    Some("another plane than ZX (G18) or XY (G17)")
                }
                'Y' | 'A' | 'B' | 'C' | 'U' | 'V' | 'W' => Some("an axis other than X and Z"),
                _ => None,
            };
            Some((w, why)).filter(|_| why.is_some() || roughing && matches!(w.letter, 'U' | 'W'))
        }) else {
            return false;
        };
        let text = line.text[w.range.clone()].to_string();
        match why {
            // U and W on a G70–G72 line: the stock to leave, which this LinuxCNC refuses.
            None => self.diag(
                codes::ISOR_ROUGHING,
                line,
                w.range.clone(),
                format!(
                    "`{text}`: the stock to leave on a roughing cycle's line is read by LinuxCNC 2.9 as an axis, and a lathe has none (rs274: \"Bad character '{}' used\")",
                    w.letter.to_ascii_lowercase()
                ),
                "leave the stock with D (the distance kept along the contour), or write the contour offset by the stock",
            ),
            Some(_) if self.not_lathe_reported => {}
            Some(why) => {
                self.not_lathe_reported = true;
                self.diag(
                    codes::ISOR_NOT_LATHE,
                    line,
                    w.range.clone(),
                    format!("`{text}`: {why}: this is not a lathe program"),
                    "ncthread converts lathe programs (X and Z in the ZX plane, G18); a mill program is refused whole, in every mode, never half converted (later lines of this kind are not reported again)",
                );
            }
        }
        true
    }

    /// Reports what the line holds that ncthread does not read; true when the line must
    /// be skipped (or was kept opaque).
    pub(super) fn unsupported(&mut self, line: Line<'_>, block: &Block) -> bool {
        if reads_every_word(block) {
            return false;
        }
        if self.not_a_lathe_program(line, block) {
            return true;
        }
        let found = unread_words(line, block);
        if found.is_empty() {
            return false;
        }
        let keep = self.options.unsupported == Unsupported::Warn;
        let found = found
            .into_iter()
            .map(|(range, message)| (self.r.span(line, range), message))
            .collect();
        let thread = block.words.iter().any(|w| {
            w.letter == 'G'
                && w.value
                    .to_scaled(1)
                    .is_ok_and(|g| matches!(g, G33 | G33_1 | G76))
        });
        if self.r.unsupported(&UNSUPPORTED, found, keep, thread) {
            self.keep_line_opaque(line, block);
        }
        true
    }

    /// Keeps a line with unsupported words as an opaque block (`--unsupported warn`), unless
    /// it changes state ncthread follows (reported).
    fn keep_line_opaque(&mut self, line: Line<'_>, block: &Block) {
        // A kept line must not change what ncthread follows: its modes and F, S, T or
        // spindle words would take effect in LinuxCNC and not here, and the lines after
        // it would be read wrongly. (A motion code leaves the motion mode unknown.)
        if let Some(w) = block.words.iter().find(|w| changes_followed_state(w)) {
            let span = self.r.span(line, w.range.clone());
            self.r
                .state_in_opaque(&UNSUPPORTED, span, &line.text[w.range.clone()]);
            return;
        }
        let context = ModalContext {
            inch: self.inch,
            diameter: self.diameter.unwrap_or(false),
            incremental: self.incremental,
            per_minute: Some(self.feed_mode != Some(FeedMode::PerRev)),
            moves: may_move(line, block),
            cycle: false,
            compensation: false,
        };
        let text = line.text.trim().to_string();
        self.r
            .keep_opaque(text, self.r.src.line_span(line), None, context);
        if block.words.iter().any(|w| {
            w.letter == 'G'
                && w.value
                    .to_scaled(1)
                    .is_ok_and(|g| matches!(g, G0 | G1 | G2 | G3 | G33 | G33_1 | G38_1..=G38_5 | G73 | G74 | G76 | G80..=G8X_LAST))
        }) {
            self.motion = None;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::source::SourceFile;

    /// A line read in whole is one the checks report nothing of: nothing unread, no G or M
    /// code not read, no axis or plane of a mill (and a line they would report is not one).
    #[test]
    fn a_line_read_in_whole_is_one_nothing_is_reported_of() {
        let mut lines = vec![];
        for g in [
            "", "G0", "G1", "G17", "G18", "G19", "G17.1", "G18.1", "G10", "G33", "G38.2", "G49",
            "G64", "G70", "G71", "G84", "G93", "G95", "G5.3",
        ] {
            for m in ["", "M3", "M6", "M19", "M62", "M70", "M150", "M250", "M1.5"] {
                for axes in ["X1 Z2", "Y1", "A5", "U1 W2", "K1.5 F0.1", "X#1", "/X1"] {
                    lines.push(format!("{g} {m} {axes}"));
                }
            }
        }
        let src = SourceFile::new("t", lines.join("\n"));
        let mut whole = 0;
        for line in src.lines() {
            let Ok(block) = crate::dialect::iso::syntax::parse_line(line.text) else {
                continue;
            };
            let mill = block.words.iter().any(|w| {
                matches!(w.letter, 'Y' | 'A' | 'B' | 'C' | 'U' | 'V' | 'W')
                    || w.letter == 'G'
                        && w.value
                            .to_scaled(1)
                            .is_ok_and(|g| matches!(g, G19 | G17_1 | G18_1 | G19_1))
            });
            let reported = !unread_words(line, &block).is_empty() || mill;
            assert_eq!(reads_every_word(&block), !reported, "{}", line.text);
            whole += usize::from(!reported);
        }
        assert!(whole > 50, "{whole}");
    }
}

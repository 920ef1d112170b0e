//! `--from auto`: which dialect a program text is written in.
//!
//! Each dialect claims the lines that carry its marks ([`super::Dialect::claim_line`]): the НЦ-31
//! writes one scaled integer word per frame with `*`, `~`, `@` modifiers; the czech control
//! writes decimal words several to a block, `"` comments, `R<nn>=` assignments, `FRnn` and `&`
//! words; ISO G-code writes `( )` or `;` comments after words, G33 with a K lead, G7 and
//! the like (G18/G20/G21 it shares with FANUC). The claim with the highest priority decides
//! a line. The choice is certain when one dialect has marks and no other has any.

use super::{ALL, DialectId, LineClaim, LineMark};

/// The chosen dialect, whether the text left any doubt, and why it was chosen.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Detection {
    pub dialect: DialectId,
    pub certain: bool,
    pub reason: String,
}

/// The words of a line's code, upper case, with their numbers (`G33`, `R04=120.0`, `&1100`).
pub(crate) fn words(code: &str) -> Vec<String> {
    let mut words = Vec::new();
    let mut current = String::new();
    for c in code.chars() {
        if c.is_ascii_alphabetic() && !current.ends_with(|p: char| p.is_ascii_alphabetic()) {
            if !current.is_empty() {
                words.push(std::mem::take(&mut current));
            }
            current.push(c.to_ascii_uppercase());
        } else if c.is_ascii_alphanumeric() || matches!(c, '.' | '-' | '+' | '=' | '&') {
            current.push(c.to_ascii_uppercase());
        } else if !current.is_empty() {
            words.push(std::mem::take(&mut current));
        }
    }
    if !current.is_empty() {
        words.push(current);
    }
    words
}

/// A line's code: what stands before a `(` or `;` comment.
pub(crate) fn code_part(line: &str) -> &str {
    line.split(['(', ';']).next().unwrap_or("")
}

/// A word ISO G-code (LinuxCNC) and FANUC's system A both write to the same effect: the ZX
/// plane and the units (`G18`, `G20`, `G21`; CAM posts for FANUC lathes write them). A line
/// whose only ISO word is one of these is a mark the two share.
pub(crate) fn iso_fanuc_shared(words: &[String]) -> bool {
    words
        .iter()
        .any(|w| matches!(w.as_str(), "G18" | "G20" | "G21"))
}

/// The words of ISO's mark that a FANUC lathe program (system A) does not write so: G7/G8
/// (diameter and radius mode), G33 with K, G33.1, LinuxCNC's one-block G76, G64, M6, G43,
/// the drilling cycles G81/G82.
pub(crate) fn iso_only(words: &[String]) -> bool {
    let g33_with_k = words.iter().any(|w| w == "G33") && words.iter().any(|w| w.starts_with('K'));
    g33_with_k
        || words.iter().any(|w| {
            matches!(
                w.as_str(),
                "G7" | "G8" | "G33.1" | "G76" | "G64" | "M6" | "G43" | "G81" | "G82"
            )
        })
}

/// The НЦ-31's modifiers (`*`, `~`, `@` and the panel's symbols).
pub(crate) fn is_nc31_modifier(c: char) -> bool {
    matches!(c, '*' | '~' | '@' | '⇄' | '⇆' | '↷' | '⌒')
}

/// The words of a line's code without its modifiers and its block number.
pub(crate) fn code_words(line: &str) -> Vec<String> {
    let code = code_part(line);
    words(code.trim_matches(|c: char| is_nc31_modifier(c) || c.is_whitespace()))
        .into_iter()
        .filter(|w| !w.starts_with('N'))
        .collect()
}

/// Whether a line of `text` carries a dialect's mark (one that only it writes, or that two
/// share, such as a `( )` comment after code): the text is written in some dialect.
pub fn has_marks(text: &str) -> bool {
    text.lines().map(str::trim).any(|line| {
        !line.is_empty()
            && line != "%"
            && ALL
                .iter()
                .any(|d| d.claim_line(line).is_some_and(|c| c.mark == LineMark::Mark))
    })
}

/// Chooses the dialect of `text`.
pub fn detect(text: &str) -> Detection {
    let mut tally = Tally::new(ALL.len());
    for (i, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line == "%" {
            continue;
        }
        tally.add(i + 1, line);
    }
    let marked = tally.marks.iter().filter(|&&m| m > 0).count();
    match (marked, tally.first_shared) {
        // Only marks that several dialects share: the likeliest of them, never certain.
        (0, Some(line)) => tally.shared_guess(line),
        (0, None) => tally.weak_guess(),
        _ => tally.choice(marked),
    }
}

/// What [`detect`] counts over a program's lines, per dialect (indices into [`ALL`]).
struct Tally {
    /// Lines that only the dialect marks.
    marks: Vec<usize>,
    /// Lines that weakly suggest the dialect.
    weak: Vec<usize>,
    /// The first line the dialect marks.
    first: Vec<Option<usize>>,
    /// Lines that two dialects mark alike (a `( )` comment after code: ISO's and FANUC's).
    shared: Vec<usize>,
    first_shared: Option<usize>,
    /// Lines that no dialect claims.
    plain: usize,
}

impl Tally {
    fn new(n: usize) -> Tally {
        Tally {
            marks: vec![0; n],
            weak: vec![0; n],
            first: vec![None; n],
            shared: vec![0; n],
            first_shared: None,
            plain: 0,
        }
    }

    /// Counts line `number`, `line` (trimmed, not empty): the claims of highest priority.
    fn add(&mut self, number: usize, line: &str) {
        let claims: Vec<(usize, LineClaim)> = (0..ALL.len())
            .filter_map(|k| ALL[k].claim_line(line).map(|c| (k, c)))
            .collect();
        let top = claims.iter().map(|(_, c)| c.priority).max();
        let marking: Vec<usize> = claims
            .iter()
            .filter(|(_, c)| Some(c.priority) == top && c.mark == LineMark::Mark)
            .map(|(k, _)| *k)
            .collect();
        if marking.len() > 1 {
            for k in marking {
                self.shared[k] += 1;
            }
            self.first_shared.get_or_insert(number);
            return;
        }
        let claim = claims
            .into_iter()
            .max_by_key(|(k, c)| (c.priority, std::cmp::Reverse(*k)));
        match claim {
            None => self.plain += 1,
            Some((_, c)) if c.mark == LineMark::Neutral => {}
            Some((k, c)) if c.mark == LineMark::Weak => self.weak[k] += 1,
            Some((k, _)) => {
                self.marks[k] += 1;
                self.first[k].get_or_insert(number);
            }
        }
    }

    /// The likeliest of the dialects that share the marks (the first on `line`).
    fn shared_guess(&self, line: usize) -> Detection {
        let n = ALL.len();
        let shared = &self.shared;
        let k = (0..n)
            .filter(|&k| shared[k] > 0)
            .max_by_key(|&k| (shared[k], ALL[k].tie_rank()))
            .unwrap_or(0);
        let others: Vec<&str> = (0..n)
            .filter(|&j| j != k && shared[j] > 0)
            .map(|j| ALL[j].id().as_str())
            .collect();
        Detection {
            dialect: ALL[k].id(),
            certain: false,
            reason: format!(
                "line {line} has a mark that {} and {} share (a comment after code, G98/G99 beside a drilling cycle, or the plane and units G18/G20/G21)",
                ALL[k].id(),
                others.join(" and "),
            ),
        }
    }

    /// No marks: the dialect of the weak hints when every line has one, else the fallback.
    fn weak_guess(&self) -> Detection {
        let weak = &self.weak;
        let weakest = (0..ALL.len())
            .filter(|&k| weak[k] > 0 && ALL[k].weak_reason().is_some())
            .max_by_key(|&k| (weak[k], ALL[k].tie_rank()));
        let fallback = ALL.iter().position(|d| d.is_fallback()).unwrap_or(0);
        let (k, reason) = match weakest {
            Some(k) if self.plain == 0 => (k, ALL[k].weak_reason().unwrap_or_default().to_string()),
            _ => (
                fallback,
                ALL[fallback]
                    .fallback_reason()
                    .unwrap_or_default()
                    .to_string(),
            ),
        };
        Detection {
            dialect: ALL[k].id(),
            certain: false,
            reason,
        }
    }

    /// The dialect with the most marked lines wins; certain when it is the only one of the
    /// `marked` dialects.
    fn choice(&self, marked: usize) -> Detection {
        let n = ALL.len();
        let marks = &self.marks;
        let best = (0..n)
            .max_by_key(|&k| (marks[k], ALL[k].tie_rank()))
            .unwrap_or(0);
        let said = |k: usize| {
            format!(
                "line {} has {}",
                self.first[k].unwrap_or(0),
                ALL[k].mark_description()
            )
        };
        let mut reason = said(best);
        let certain = marked == 1 && !(ALL[best].plain_lines_contradict() && self.plain > 0);
        if !certain {
            let others: Vec<String> = (0..n)
                .filter(|&k| k != best && marks[k] > 0)
                .map(said)
                .collect();
            if !others.is_empty() {
                reason.push_str(&format!(", but {}", others.join(" and ")));
            } else {
                reason.push_str(", but other lines hold several or decimal words");
            }
        }
        Detection {
            dialect: ALL[best].id(),
            certain,
            reason,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recognises_each_dialect() {
        let nc31 = "N0 M40\nN4 X10000 ~ *\nN5 Z5000 ~\nN11 Z-5200 ⇄ *\n";
        let d = detect(nc31);
        assert_eq!((d.dialect.as_str(), d.certain), ("nc31", true), "{d:?}");
        let czech = "N10 G00 X26.618 Z3. \"ROZTOČENÍ\nN20 R04=120.0\nN30 G33 Z-9. FR10\n";
        let d = detect(czech);
        assert_eq!((d.dialect.as_str(), d.certain), ("czech", true), "{d:?}");
        let iso = "%\n(ncthread)\nG7 G18 G21 G90 G95\nG33 Z-9 K1.5\n%\n";
        let d = detect(iso);
        assert_eq!((d.dialect.as_str(), d.certain), ("iso", true), "{d:?}");
    }

    /// LinuxCNC's G98/G99 before a drilling cycle is no FANUC feed mode mark.
    #[test]
    fn a_linuxcnc_drilling_program_is_iso() {
        let text = "G7 G17 G20 G90 G95\nG0 X0 Z0.5\nF0.003\nG98 G83 X0 R0.1 Z-0.5 Q0.2\nG80\nG99 G73 X0 R0.1 Z-0.5 Q0.2\nM2\n";
        let d = detect(text);
        assert_eq!(d.dialect.as_str(), "iso", "{d:?}");
        let text =
            "G7 G17 G21 G90 G94\nG0 X10 Z5\nG91 G98 G81 X10 R-4 Z-3 L3\nG99 X-5 L2\nG90 G80\nM2\n";
        let d = detect(text);
        assert_eq!(d.dialect.as_str(), "iso", "{d:?}");
    }

    #[test]
    fn a_mark_two_dialects_share_leaves_a_doubt() {
        // A `( )` comment after code: LinuxCNC's and FANUC's.
        let text = "G21 G97 S500 M03 (SPINDLE)\nG00 X40. Z2. (APPROACH)\nG01 Z-10. F0.2\n";
        let d = detect(text);
        assert!(!d.certain, "{d:?}");
        assert!(d.reason.contains("share"), "{}", d.reason);
        // A mark of one of them decides.
        let d = detect(&format!("{text}G99\nG32 Z-20. F1.5 (THREAD)\n"));
        assert_eq!((d.dialect.as_str(), d.certain), ("fanuc", true), "{d:?}");
    }

    /// G18, G20 and G21 are FANUC's too: a CAM post's FANUC lathe program that writes them
    /// is FANUC beyond doubt (it read as FANUC "but line 567 has an ISO mark"), and a line
    /// with them and a word only LinuxCNC writes stays LinuxCNC's.
    #[test]
    fn the_plane_and_the_units_are_marks_iso_and_fanuc_share() {
        let fusion = "%\nO0001\nN10G98G18\nN11G21\nN12G50S6000\nN14T0100\nN16G96S91M3\nN18G0X60.Z5.\nN20G18G2X0.Z0.83I-18.5F0.1\nN22G28U0.W0.\nN24M30\n%\n";
        let d = detect(fusion);
        assert_eq!((d.dialect.as_str(), d.certain), ("fanuc", true), "{d:?}");
        let d = detect("G7 G18 G21 G90 G95\nG0 X10 Z2\nG1 Z-10 F0.2\nM2\n");
        assert_eq!((d.dialect.as_str(), d.certain), ("iso", true), "{d:?}");
        // A `"` inside a `( )` comment is no czech mark (a review's finding: with the shared
        // lines, `(1/2" BORING BAR)` read as czech for certain).
        let d = detect("G18 G20 G90 G95\n(1/2\" BORING BAR)\nG0 X0.5 Z0.1\nG1 Z-1. F0.004\nM2\n");
        assert_ne!(d.dialect.as_str(), "czech", "{d:?}");
        // Nothing but them: ISO's, in doubt.
        let d = detect("G18 G21 G90\nG0 X10 Z2\nG1 Z-10 F0.2\nM2\n");
        assert_eq!((d.dialect.as_str(), d.certain), ("iso", false), "{d:?}");
        assert!(d.reason.contains("share"), "{}", d.reason);
    }

    #[test]
    fn says_when_it_is_not_sure() {
        let d = detect("N10 G00 X26.618 Z3.\nN20 G33 Z-9. F1.5\n");
        assert_eq!((d.dialect.as_str(), d.certain), ("czech", false), "{d:?}");
        let d = detect("N0 M3\nN1 S700\nN2 X3600\n");
        assert_eq!((d.dialect.as_str(), d.certain), ("nc31", false), "{d:?}");
        let d = detect("N0 X3600 ~ *\nN1 Z450 ~\nN2 G33 Z-9. F1.5 \"X\n");
        assert!(!d.certain, "{d:?}");
        assert!(d.reason.contains("line 3"), "{}", d.reason);
    }
}

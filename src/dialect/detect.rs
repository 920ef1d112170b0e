//! `--from auto`: which dialect a program text is written in.
//!
//! Each dialect has marks no other one uses: the НЦ-31 writes one scaled integer word per
//! frame with `*`, `~`, `@` modifiers; the czech control writes decimal words several to a
//! block, `"` comments, `R<nn>=` assignments, `FRnn` and `&` words; ISO G-code writes `( )`
//! or `;` comments after words, G33 with a K lead, G7/G18/G21 and the like. The choice is certain when
//! one dialect has marks and no other has any.

use super::Dialect;

/// The chosen dialect, whether the text left any doubt, and why it was chosen.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Detection {
    pub dialect: Dialect,
    pub certain: bool,
    pub reason: String,
}

#[derive(Default)]
struct Marks {
    /// Lines that are one integer word with `*`/`~`/`@`.
    nc31_modifiers: usize,
    /// Lines that are one integer word (and perhaps a frame number), no modifiers.
    single_integer_words: usize,
    /// Lines with a `"` comment, `R<nn>=`, `FR<nn>` or `&<digits>`.
    czech: usize,
    /// Lines with `;`, a `( )` comment after code, or an ISO-only word.
    iso: usize,
    /// Lines with several words or a decimal word, and no mark.
    plain_decimal: usize,
    /// First line of each kind, for the reason.
    first: [Option<usize>; 3],
}

fn words(code: &str) -> Vec<String> {
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

fn is_nc31_modifier(c: char) -> bool {
    matches!(c, '*' | '~' | '@' | '⇄' | '⇆' | '↷' | '⌒')
}

/// Chooses the dialect of `text`.
pub fn detect(text: &str) -> Detection {
    let mut m = Marks::default();
    for (i, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line == "%" {
            continue;
        }
        let n = i + 1;
        let note = |m: &mut Marks, k: usize| {
            m.first[k].get_or_insert(n);
        };
        // czech comments start at a quote; ISO's at `(` or `;`.
        if line.contains(['"', '“', '„']) {
            m.czech += 1;
            note(&mut m, 1);
            continue;
        }
        if line.starts_with('(') {
            // A comment line: the НЦ-31 (PC archives) and ISO both have them.
            continue;
        }
        let code = line.split(['(', ';']).next().unwrap_or("");
        if code.len() < line.len() {
            m.iso += 1;
            note(&mut m, 2);
            continue;
        }
        let ws = words(code.trim_matches(|c: char| is_nc31_modifier(c) || c.is_whitespace()));
        let ws: Vec<_> = ws.into_iter().filter(|w| !w.starts_with('N')).collect();
        let modifiers = code.chars().any(is_nc31_modifier);
        let integer = |w: &String| {
            w.len() > 1
                && w[1..]
                    .trim_start_matches(['+', '-'])
                    .bytes()
                    .all(|b| b.is_ascii_digit())
        };
        if ws.len() == 1 && integer(&ws[0]) {
            if modifiers {
                m.nc31_modifiers += 1;
                note(&mut m, 0);
            } else {
                m.single_integer_words += 1;
            }
            continue;
        }
        let czech_word = ws.iter().any(|w| {
            (w.starts_with('R') && w.contains('=')) || w.starts_with('&') || w.starts_with("FR")
        });
        let g33_with_k = ws.iter().any(|w| w == "G33") && ws.iter().any(|w| w.starts_with('K'));
        let iso_word = g33_with_k
            || ws.iter().any(|w| {
                matches!(
                    w.as_str(),
                    "G7" | "G8" | "G18" | "G21" | "G20" | "G33.1" | "G76" | "G64" | "M6" | "G43"
                )
            });
        if czech_word {
            m.czech += 1;
            note(&mut m, 1);
        } else if iso_word {
            m.iso += 1;
            note(&mut m, 2);
        } else if modifiers {
            m.nc31_modifiers += 1;
            note(&mut m, 0);
        } else {
            m.plain_decimal += 1;
        }
    }
    let kinds = [m.nc31_modifiers, m.czech, m.iso];
    let marked = kinds.iter().filter(|&&k| k > 0).count();
    let line = |k: usize| m.first[k].unwrap_or(0);
    if marked == 0 {
        return if m.single_integer_words > 0 && m.plain_decimal == 0 {
            Detection {
                dialect: Dialect::Nc31,
                certain: false,
                reason: "every frame is one whole-number word, as on the НЦ-31, but no `*`, `~` or `@` confirms it".into(),
            }
        } else {
            Detection {
                dialect: Dialect::Czech,
                certain: false,
                reason: "no dialect's marks (НЦ-31 `*`/`~`/`@`, czech `\"` comments or R/FR/& words, ISO `( )` comments or G33 … K); decimal words read as czech".into(),
            }
        };
    }
    // The dialect with the most marked lines wins; certain when it is the only one.
    let best = (0..3)
        .max_by_key(|&k| (kinds[k], std::cmp::Reverse(k)))
        .unwrap_or(0);
    let dialect = [Dialect::Nc31, Dialect::Czech, Dialect::Iso][best];
    let what = [
        "a frame with the НЦ-31's `*`/`~`/`@` modifiers",
        "a czech mark (a `\"` comment, `R<nn>=`, `FR<nn>` or `&`)",
        "an ISO mark (a `( )` or `;` comment after code, G33 with K, or a G7/G18/G21/G33.1/G76 word)",
    ];
    let mut reason = format!("line {} has {}", line(best), what[best]);
    let certain = marked == 1 && !(best == 0 && m.plain_decimal > 0);
    if !certain {
        let others: Vec<String> = (0..3)
            .filter(|&k| k != best && kinds[k] > 0)
            .map(|k| format!("line {} has {}", line(k), what[k]))
            .collect();
        if !others.is_empty() {
            reason.push_str(&format!(", but {}", others.join(" and ")));
        } else {
            reason.push_str(", but other lines hold several or decimal words");
        }
    }
    Detection {
        dialect,
        certain,
        reason,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recognises_each_dialect() {
        let nc31 = "N0 M40\nN4 X10000 ~ *\nN5 Z5000 ~\nN11 Z-5200 ⇄ *\n";
        let d = detect(nc31);
        assert_eq!((d.dialect, d.certain), (Dialect::Nc31, true), "{d:?}");
        let czech = "N10 G00 X26.618 Z3. \"ROZTOČENÍ\nN20 R04=120.0\nN30 G33 Z-9. FR10\n";
        let d = detect(czech);
        assert_eq!((d.dialect, d.certain), (Dialect::Czech, true), "{d:?}");
        let iso = "%\n(ncthread)\nG7 G18 G21 G90 G95\nG33 Z-9 K1.5\n%\n";
        let d = detect(iso);
        assert_eq!((d.dialect, d.certain), (Dialect::Iso, true), "{d:?}");
    }

    #[test]
    fn says_when_it_is_not_sure() {
        let d = detect("N10 G00 X26.618 Z3.\nN20 G33 Z-9. F1.5\n");
        assert_eq!((d.dialect, d.certain), (Dialect::Czech, false), "{d:?}");
        let d = detect("N0 M3\nN1 S700\nN2 X3600\n");
        assert_eq!((d.dialect, d.certain), (Dialect::Nc31, false), "{d:?}");
        let d = detect("N0 X3600 ~ *\nN1 Z450 ~\nN2 G33 Z-9. F1.5 \"X\n");
        assert!(!d.certain, "{d:?}");
        assert!(d.reason.contains("line 3"), "{}", d.reason);
    }
}

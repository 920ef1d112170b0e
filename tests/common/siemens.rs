//! The test side's translation of a SINUMERIK program of ncthread's subset into LinuxCNC ISO
//! (siemens.md "Checked by"), independent of ncthread's SINUMERIK reader: `tests/siemens.rs`
//! runs it through rs274.
//!
//! The translation: `%_N_…` and `;` comments dropped, block numbers dropped; `DIAMON` → `G7`,
//! `G71` → `G21`, `G18 G90 G40 G54…G57` as they are; `G0`–`G3` as they are, `I K` increments
//! from the arc's start (radius values) under `G91.1`, `CR=` → `R`; `G33 [X] Z K SF=` → `G33 …
//! K` with K along the path (K is the lead along Z), the pass started `K·SF/360°` earlier along
//! its line (a `G0` there first); `G4 F<s>` → `G4 P<s>`; `G96 S LIMS=` → `G96 D S`; `T<n>` →
//! `T<n> M6 G43` (M6 stops LinuxCNC's spindle, a turret does not: the spindle is started
//! again), `D1` its own offset (G43), `D0` none (G49); M5, M9, M0, M1, M2 and M30 after the block's motion (ncthread's
//! decision), on the next line.

fn n(v: f64) -> String {
    let s = format!("{v:.6}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" { "0".into() } else { s.into() }
}

/// A block's words: `(name, value)`, `X20` and `X=20` alike; a keyword has an empty value.
fn words(code: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    for token in code.split_whitespace() {
        let up = token.to_ascii_uppercase();
        if let Some((name, value)) = up.split_once('=') {
            out.push((name.to_string(), value.to_string()));
        } else {
            let split = up
                .find(|c: char| !c.is_ascii_alphabetic())
                .unwrap_or(up.len());
            out.push((up[..split].to_string(), up[split..].to_string()));
        }
    }
    out
}

/// The code without its `MSG("…")` statements (an operator's message moves nothing).
fn without_messages(code: &str) -> String {
    let up = code.to_ascii_uppercase();
    match up.find("MSG(") {
        Some(i) => {
            let end = code[i..].find(')').map_or(code.len(), |j| i + j + 1);
            format!("{}{}", &code[..i], without_messages(&code[end..]))
        }
        None => code.to_string(),
    }
}

/// The translation of a SINUMERIK program of ncthread's subset into LinuxCNC ISO, or why not.
pub fn translate(text: &str) -> Result<String, String> {
    translate_from(text, &Default::default())
}

/// [`translate`] for a machine whose reset state the profile gives (X a radius or a diameter,
/// F per revolution or per minute, until the program says).
pub fn translate_from(
    text: &str,
    start: &ncthread::profile::SiemensProfile,
) -> Result<String, String> {
    let mut out = vec!["G18 G91.1".to_string()];
    if start.initial_diameter.is_some() {
        out.push("G7".into());
    }
    match start.initial_per_rev {
        Some(true) => out.push("G95".into()),
        Some(false) => out.push("G94".into()),
        None => {}
    }
    let (mut x, mut z): (Option<f64>, Option<f64>) = (None, None);
    let mut motion = 0u32;
    let mut feed: Option<f64> = None;
    let mut turning: Option<&str> = None;
    let mut per_minute: Option<bool> = start.initial_per_rev.map(|r| !r);
    let mut speed: Option<String> = None;
    let mut lims: Option<String> = None;
    // DIAMOF: X (not I) a radius, written here as a diameter under G7; G91 increments.
    let mut radius = start.initial_diameter == Some(false);
    let mut incremental = false;
    for line in text.lines() {
        let code = without_messages(line.split(';').next().unwrap_or(""))
            .trim()
            .to_string();
        let code = code.as_str();
        if code.is_empty() || code.starts_with('%') {
            continue;
        }
        let ws: Vec<(String, String)> = words(code)
            .into_iter()
            .filter(|(name, _)| name != "N")
            .collect();
        let get = |name: &str| ws.iter().find(|(l, _)| l == name).map(|(_, v)| v.clone());
        let num = |name: &str| -> Result<Option<f64>, String> {
            get(name)
                .map(|v| v.parse::<f64>().map_err(|_| format!("{name}={v}")))
                .transpose()
        };
        let mut now: Vec<String> = Vec::new();
        let mut after: Vec<String> = Vec::new();
        let mut dwell = false;
        for (name, value) in &ws {
            match (name.as_str(), value.as_str()) {
                ("G", g) => match g.parse::<u32>().map_err(|_| format!("G{g}"))? {
                    g @ (0 | 1 | 2 | 3 | 33) => motion = g,
                    4 => dwell = true,
                    18 => now.push("G18".into()),
                    90 => incremental = false,
                    91 => incremental = true,
                    71 | 710 => now.push("G21".into()),
                    70 | 700 => now.push("G20".into()),
                    40 => now.push("G40".into()),
                    g @ 54..=57 => now.push(format!("G{g}")),
                    // LinuxCNC sets F to 0 on every G94/G95: said only where the mode changes.
                    g @ (94 | 95) => {
                        if per_minute != Some(g == 94) {
                            per_minute = Some(g == 94);
                            now.push(format!("G{g}"));
                        }
                    }
                    // G96/G97 say a feed per revolution, G961/G971 per minute; LinuxCNC's
                    // G96 says its S on its line.
                    g @ (96 | 97 | 961 | 971) => {
                        let per_rev = g < 100;
                        if per_minute != Some(!per_rev) {
                            per_minute = Some(!per_rev);
                            now.push(if per_rev { "G95" } else { "G94" }.into());
                        }
                        if matches!(g, 96 | 961) {
                            // LIMS stays in force until another is written.
                            if let Some(l) = get("LIMS") {
                                lims = Some(l);
                            }
                            let d = lims.as_ref().map(|l| format!(" D{l}")).unwrap_or_default();
                            let s = get("S").or(speed.clone()).ok_or("G96 before any S")?;
                            now.push(format!("G96{d} S{s}"));
                        } else {
                            now.push("G97".into());
                        }
                    }
                    g => return Err(format!("G{g} is not in the subset")),
                },
                ("DIAMON", "") => {
                    radius = false;
                    now.push("G7".into())
                }
                ("DIAMOF", "") => {
                    radius = true;
                    now.push("G7".into())
                }
                // They move nothing: a comment, a stop of the look-ahead.
                ("DITS" | "DITE" | "STOPRE", _) => {}
                ("M", m) => match m {
                    "3" => {
                        turning = Some("M3");
                        now.push("M3".into())
                    }
                    "4" => {
                        turning = Some("M4");
                        now.push("M4".into())
                    }
                    "8" => now.push("M8".into()),
                    "5" => {
                        turning = None;
                        after.push("M5".into())
                    }
                    "9" | "0" | "1" | "2" | "30" => after.push(format!("M{m}")),
                    "17" => after.push("M2".into()),
                    m => return Err(format!("M{m} is not in the subset")),
                },
                ("S", s) => {
                    speed = Some(s.to_string());
                    if !ws
                        .iter()
                        .any(|(l, v)| l == "G" && (v == "96" || v == "961"))
                    {
                        now.push(format!("S{s}"));
                    }
                }
                ("T", t) => {
                    now.push(format!("T{t} M6 G43"));
                    if let Some(dir) = turning {
                        now.push(dir.to_string());
                    }
                }
                // D is a cutting edge of the tool in use: D1 its own offset, D0 none.
                ("D", "0") => now.push("G49".into()),
                ("D", "1") => {
                    if get("T").is_none() {
                        now.push("G43".into());
                    }
                }
                ("X" | "Z" | "I" | "K" | "F" | "SF" | "CR" | "LIMS", _) => {}
                (name, value) => return Err(format!("{name}{value} is not in the subset")),
            }
        }
        let moves = get("X").is_some() || get("Z").is_some();
        if dwell {
            let s = num("F")?.ok_or("G4 without F")?;
            now.push(format!("G4 P{}", n(s)));
        } else {
            if let Some(f) = num("F")? {
                feed = Some(f);
                if !moves || motion == 33 || motion == 0 {
                    now.push(format!("F{}", n(f)));
                }
            }
            if moves {
                // `X=AC(…)`, `X=IC(…)`, G90/G91: every axis value made absolute here.
                let axis =
                    |name: &str, current: Option<f64>, scale: f64| -> Result<Option<f64>, String> {
                        let Some(v) = get(name) else {
                            return Ok(current);
                        };
                        let (text, inc) = if let Some(t) = v.strip_prefix("AC(") {
                            (t.trim_end_matches(')').to_string(), false)
                        } else if let Some(t) = v.strip_prefix("IC(") {
                            (t.trim_end_matches(')').to_string(), true)
                        } else {
                            (v.clone(), incremental)
                        };
                        let value = text.parse::<f64>().map_err(|_| format!("{name}={v}"))? * scale;
                        if inc {
                            Ok(Some(
                                current.ok_or(format!(
                                    "incremental {name} from an unknown position"
                                ))? + value,
                            ))
                        } else {
                            Ok(Some(value))
                        }
                    };
                let nx = axis("X", x, if radius { 2.0 } else { 1.0 })?;
                let nz = axis("Z", z, 1.0)?;
                let axes = |x: Option<f64>, z: Option<f64>| {
                    let mut s = String::new();
                    if let Some(x) = x {
                        s.push_str(&format!(" X{}", n(x)));
                    }
                    if let Some(z) = z {
                        s.push_str(&format!(" Z{}", n(z)));
                    }
                    s
                };
                let f = |feed: Option<f64>| feed.map(|f| format!(" F{}", n(f))).unwrap_or_default();
                match motion {
                    0 => now.push(format!("G0{}", axes(nx, nz))),
                    1 => now.push(format!("G1{}{}", axes(nx, nz), f(feed))),
                    2 | 3 => {
                        let centre = match num("CR")? {
                            Some(r) => format!(" R{}", n(r)),
                            None => format!(
                                " I{} K{}",
                                n(num("I")?.unwrap_or(0.0)),
                                n(num("K")?.unwrap_or(0.0))
                            ),
                        };
                        now.push(format!("G{motion}{}{centre}{}", axes(nx, nz), f(feed)));
                    }
                    33 => {
                        let lead = num("K")?.ok_or("G33 without K")?;
                        let sf = num("SF")?.ok_or("G33 without SF=")?;
                        let z0 = z.ok_or("skip: G33 from an unknown Z")?;
                        let (x0, x1) = match (x, nx) {
                            (Some(a), b) => (a, b.unwrap_or(a)),
                            (None, None) => (0.0, 0.0),
                            (None, Some(_)) => return Err("G33 with X from an unknown X".into()),
                        };
                        let z1 = nz.unwrap_or(z0);
                        let (dz, dr) = (z1 - z0, (x1 - x0) / 2.0);
                        if dz == 0.0 || dr.abs() >= dz.abs() {
                            return Err("a G33 steeper than 45°".into());
                        }
                        let k = lead * dz.hypot(dr) / dz.abs();
                        let shift = lead * sf / 360.0;
                        // rs274 prints four decimals: a shift that prints as none, or as a
                        // whole lead, is the same helix started at the index pulse.
                        if (shift * 10_000.0).round() != 0.0
                            && ((lead - shift) * 10_000.0).round() != 0.0
                        {
                            let (sx, sz) =
                                (x0 - (x1 - x0) * shift / dz.abs(), z0 - dz.signum() * shift);
                            let sx = if x.is_some() {
                                format!(" X{}", n(sx))
                            } else {
                                String::new()
                            };
                            now.push(format!("G0{sx} Z{}", n(sz)));
                        }
                        let xw = if x.is_some() || nx.is_some() {
                            Some(x1)
                        } else {
                            None
                        };
                        now.push(format!("G33{} K{}", axes(xw, Some(z1)), n(k)));
                    }
                    m => return Err(format!("motion G{m}")),
                }
                x = nx;
                z = nz;
            }
        }
        out.extend(now);
        out.extend(after);
    }
    Ok(out.join("\n") + "\n")
}

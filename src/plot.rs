//! `ncthread plot` and `verify --plot`: SVG pictures of a program's motion and of its
//! threads, written directly (no renderer at run time).
//!
//! Every picture is drawn from what the simulator ([`crate::sim::simulate`]) and `explain`
//! ([`crate::explain`]) computed: nothing here knows a cycle or a schedule. The XZ views put
//! Z to the right and X (as a radius, so that angles are true; the labels give diameters) up.

use std::fmt::Write as _;

use crate::explain::{CycleMove, Kind, Operation};
use crate::fixed::Length;
use crate::ir::Pos;
use crate::sim::{Difference, Motion, Segment};

use self::escape as esc;

const WIDTH: f64 = 1100.0;
const FONT: &str = "font-family=\"DejaVu Sans, Arial, sans-serif\"";
const RAPID: &str = "#888888";
const FEED: &str = "#1b6b1b";
const LEFT: &str = "#1f5fbf";
const RIGHT: &str = "#e07b00";
const MARK: &str = "#d00000";
const TAP: &str = "#7a3db8";

/// A rectangle of the picture and the mm window it shows (equal scale on both axes unless
/// `stretch` says how much more X is magnified).
#[derive(Clone, Copy)]
struct View {
    /// Pixels: left, top, width, height.
    left: f64,
    top: f64,
    width: f64,
    height: f64,
    /// mm: Z from, radius from, pixels per mm along Z, along X.
    z0: f64,
    r0: f64,
    sz: f64,
    sr: f64,
}

impl View {
    /// A view of `box` (z min, z max, r min, r max in mm) inside the pixel rectangle, with
    /// a margin, equal scales when `equal`.
    fn fit(rect: (f64, f64, f64, f64), bounds: (f64, f64, f64, f64), equal: bool) -> View {
        let (left, top, width, height) = rect;
        let (mut zmin, mut zmax, mut rmin, mut rmax) = bounds;
        if zmax - zmin < 1e-6 {
            zmin -= 1.0;
            zmax += 1.0;
        }
        if rmax - rmin < 1e-6 {
            rmin -= 1.0;
            rmax += 1.0;
        }
        let (pad_z, pad_r) = ((zmax - zmin) * 0.06, (rmax - rmin) * 0.08);
        let (zmin, zmax, rmin, rmax) = (zmin - pad_z, zmax + pad_z, rmin - pad_r, rmax + pad_r);
        let mut sz = width / (zmax - zmin);
        let mut sr = height / (rmax - rmin);
        if equal {
            sz = sz.min(sr);
            sr = sz;
        }
        // Centred in the rectangle.
        let z0 = zmin - (width / sz - (zmax - zmin)) / 2.0;
        let r0 = rmin - (height / sr - (rmax - rmin)) / 2.0;
        View {
            left,
            top,
            width,
            height,
            z0,
            r0,
            sz,
            sr,
        }
    }

    fn px(&self, z: f64, r: f64) -> (f64, f64) {
        (
            self.left + (z - self.z0) * self.sz,
            self.top + self.height - (r - self.r0) * self.sr,
        )
    }

    /// A program point (X a diameter).
    fn at(&self, p: (Length, Length)) -> (f64, f64) {
        self.px(p.1.to_mm_f64(), p.0.to_mm_f64() / 2.0)
    }

    fn z_range(&self) -> (f64, f64) {
        (self.z0, self.z0 + self.width / self.sz)
    }

    fn r_range(&self) -> (f64, f64) {
        (self.r0, self.r0 + self.height / self.sr)
    }
}

/// Text for SVG and HTML: `&`, `<`, `>` and quotes escaped, control characters as spaces.
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            c if (c as u32) < 0x20 && c != '\n' && c != '\t' => out.push(' '),
            c => out.push(c),
        }
    }
    out
}

fn text(out: &mut String, x: f64, y: f64, size: f64, anchor: &str, fill: &str, s: &str) {
    let _ = writeln!(
        out,
        r#"<text x="{x:.1}" y="{y:.1}" font-size="{size}" text-anchor="{anchor}" fill="{fill}" {FONT}>{}</text>"#,
        esc(s)
    );
}

/// A "nice" tick step for a span of `span` mm shown in about `n` ticks.
fn tick_step(span: f64, n: f64) -> f64 {
    let raw = (span / n).max(1e-4);
    let mag = 10f64.powf(raw.log10().floor());
    let f = raw / mag;
    mag * if f < 1.5 {
        1.0
    } else if f < 3.5 {
        2.0
    } else if f < 7.5 {
        5.0
    } else {
        10.0
    }
}

fn number(v: f64) -> String {
    let s = format!("{v:.4}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" { "0".into() } else { s.into() }
}

/// The frame, a grid with mm ticks, and the axis names. `diameter`: the vertical ticks are
/// labelled as diameters (the view holds radii).
fn axes(out: &mut String, v: &View, z_name: &str, r_name: &str, diameter: bool) {
    let _ = writeln!(
        out,
        "<rect x=\"{:.1}\" y=\"{:.1}\" width=\"{:.1}\" height=\"{:.1}\" fill=\"#ffffff\" stroke=\"#444444\" stroke-width=\"1\"/>",
        v.left, v.top, v.width, v.height
    );
    let (z0, z1) = v.z_range();
    let step = tick_step(z1 - z0, v.width / 90.0);
    let mut z = (z0 / step).ceil() * step;
    while z <= z1 + 1e-9 {
        let (x, _) = v.px(z, 0.0);
        let _ = writeln!(
            out,
            "<line x1=\"{x:.1}\" y1=\"{:.1}\" x2=\"{x:.1}\" y2=\"{:.1}\" stroke=\"#e6e6e6\" stroke-width=\"1\"/>",
            v.top,
            v.top + v.height
        );
        text(
            out,
            x,
            v.top + v.height + 14.0,
            10.0,
            "middle",
            "#444444",
            &number(z),
        );
        z += step;
    }
    let (r0, r1) = v.r_range();
    let step = tick_step(r1 - r0, v.height / 45.0);
    let mut r = (r0 / step).ceil() * step;
    while r <= r1 + 1e-9 {
        let (_, y) = v.px(0.0, r);
        let _ = writeln!(
            out,
            "<line x1=\"{:.1}\" y1=\"{y:.1}\" x2=\"{:.1}\" y2=\"{y:.1}\" stroke=\"#e6e6e6\" stroke-width=\"1\"/>",
            v.left,
            v.left + v.width
        );
        let label = if diameter { r * 2.0 } else { r };
        text(
            out,
            v.left - 4.0,
            y + 3.5,
            10.0,
            "end",
            "#444444",
            &number(label),
        );
        r += step;
    }
    text(
        out,
        v.left + v.width / 2.0,
        v.top + v.height + 28.0,
        11.0,
        "middle",
        "#222222",
        z_name,
    );
    let _ = writeln!(
        out,
        r##"<text x="{:.1}" y="{:.1}" font-size="11" text-anchor="middle" fill="#222222" transform="rotate(-90 {:.1} {:.1})" {FONT}>{}</text>"##,
        v.left - 40.0,
        v.top + v.height / 2.0,
        v.left - 40.0,
        v.top + v.height / 2.0,
        esc(r_name)
    );
}

/// The colour of pass `i` of `n` (blue for the first, red for the last).
fn pass_colour(i: usize, n: usize) -> String {
    let t = if n <= 1 {
        0.0
    } else {
        i as f64 / (n - 1) as f64
    };
    format!("hsl({:.0},80%,42%)", 220.0 - 220.0 * t)
}

/// The mm bounds (z min, z max, r min, r max) of segments with known ends.
fn bounds<'a>(segments: impl Iterator<Item = &'a Segment>) -> Option<(f64, f64, f64, f64)> {
    moves_bounds(segments.map(|s| {
        let centre = match s.motion {
            Motion::Arc { centre, .. } => Some(centre),
            _ => None,
        };
        (s.from, s.to, centre)
    }))
}

/// The mm bounds of moves (from, to, an arc's centre) with known ends: an arc's whole circle,
/// since it may bulge past its ends.
fn moves_bounds(
    moves: impl Iterator<Item = (Pos, Pos, Option<Pos>)>,
) -> Option<(f64, f64, f64, f64)> {
    let mut b: Option<(f64, f64, f64, f64)> = None;
    for (from, to, centre) in moves {
        for p in [from, to] {
            let Some((x, z)) = p.known() else { continue };
            let (z, r) = (z.to_mm_f64(), x.to_mm_f64() / 2.0);
            b = Some(match b {
                None => (z, z, r, r),
                Some((a, bz, c, d)) => (a.min(z), bz.max(z), c.min(r), d.max(r)),
            });
        }
        if let (Some((cx, cz)), Some((fx, fz))) = (centre.and_then(Pos::known), from.known()) {
            let (cz, cr) = (cz.to_mm_f64(), cx.to_mm_f64() / 2.0);
            let rad = (fz.to_mm_f64() - cz).hypot(fx.to_mm_f64() / 2.0 - cr);
            if let Some((a, bz, c, d)) = b {
                b = Some((
                    a.min(cz - rad),
                    bz.max(cz + rad),
                    c.min(cr - rad),
                    d.max(cr + rad),
                ));
            }
        }
    }
    b
}

/// How a segment is stroked.
struct Stroke<'a> {
    colour: String,
    width: f64,
    dash: Option<&'a str>,
}

/// The SVG path of one segment (`None` when an end is unknown or it does not move).
fn segment_path(v: &View, s: &Segment) -> Option<String> {
    let arc = match s.motion {
        Motion::Arc {
            centre, clockwise, ..
        } => Some((centre, clockwise)),
        _ => None,
    };
    path_of(v, s.from, s.to, arc)
}

/// The SVG path of a move from `from` to `to`: a line, or an arc around a centre (X a
/// diameter) when `arc` gives it and whether it turns clockwise (G2).
fn path_of(v: &View, from: Pos, to: Pos, arc: Option<(Pos, bool)>) -> Option<String> {
    let (from, to) = (from.known()?, to.known()?);
    let (x0, y0) = v.at(from);
    let (x1, y1) = v.at(to);
    let Some((centre, clockwise)) = arc else {
        if from == to {
            return None;
        }
        return Some(format!("M{x0:.2},{y0:.2} L{x1:.2},{y1:.2}"));
    };
    // In mm, X as a radius: Z to the right, X up, as drawn.
    let mm = |(x, z): (Length, Length)| (z.to_mm_f64(), x.to_mm_f64() / 2.0);
    let ((z0, r0), (z1, r1), (cz, cr)) = (mm(from), mm(to), mm(centre.known()?));
    let rad = (z0 - cz).hypot(r0 - cr);
    // The circle as drawn: an ellipse when X is magnified.
    let (rx, ry) = (rad * v.sz, rad * v.sr);
    // G18: G2 turns clockwise seen from +Y. With Z to the right and X up, +Y points at the
    // viewer, so G2 is clockwise on the screen too: SVG's positive-angle sweep (y down).
    let sweep = u8::from(clockwise);
    if from == to {
        // A full circle: two halves.
        let (ox, oy) = v.px(2.0 * cz - z0, 2.0 * cr - r0);
        return Some(format!(
            "M{x0:.2},{y0:.2} A{rx:.2},{ry:.2} 0 0 {sweep} {ox:.2},{oy:.2} A{rx:.2},{ry:.2} 0 0 {sweep} {x0:.2},{y0:.2}"
        ));
    }
    // The angle it turns, in the motion's sense: over half a turn is SVG's large arc.
    let (a0, a1) = ((r0 - cr).atan2(z0 - cz), (r1 - cr).atan2(z1 - cz));
    let turned = if clockwise { a0 - a1 } else { a1 - a0 }.rem_euclid(std::f64::consts::TAU);
    let large = u8::from(turned > std::f64::consts::PI);
    Some(format!(
        "M{x0:.2},{y0:.2} A{rx:.2},{ry:.2} 0 {large} {sweep} {x1:.2},{y1:.2}"
    ))
}

fn stroke_path(out: &mut String, d: &str, s: &Stroke<'_>, title: Option<&str>) {
    let dash = s
        .dash
        .map_or(String::new(), |d| format!(" stroke-dasharray=\"{d}\""));
    match title {
        Some(t) => {
            let _ = writeln!(
                out,
                "<path d=\"{d}\" fill=\"none\" stroke=\"{}\" stroke-width=\"{}\"{dash}><title>{}</title></path>",
                s.colour,
                s.width,
                esc(t)
            );
        }
        None => {
            let _ = writeln!(
                out,
                "<path d=\"{d}\" fill=\"none\" stroke=\"{}\" stroke-width=\"{}\"{dash}/>",
                s.colour, s.width
            );
        }
    }
}

/// The moves of a program in `v`: rapids dashed grey, feeds and arcs green, threads
/// coloured by pass order (or all in `colour` when given: an overlay).
fn draw_motion(out: &mut String, v: &View, segments: &[Segment], colour: Option<&str>) {
    let threads = segments
        .iter()
        .filter(|s| matches!(s.motion, Motion::Sync { .. } | Motion::SyncRadial { .. }))
        .count();
    let mut nth = 0;
    for s in segments {
        let Some(d) = segment_path(v, s) else {
            continue;
        };
        let title = s.to_text();
        let stroke = match s.motion {
            Motion::Rapid => Stroke {
                colour: colour.unwrap_or(RAPID).to_string(),
                width: 1.0,
                dash: Some("5,4"),
            },
            Motion::Sync { .. } | Motion::SyncRadial { .. } => {
                nth += 1;
                Stroke {
                    colour: colour.map_or_else(|| pass_colour(nth - 1, threads), str::to_string),
                    width: 2.0,
                    dash: None,
                }
            }
            Motion::Tap { .. } => Stroke {
                colour: colour.unwrap_or(TAP).to_string(),
                width: 2.5,
                dash: None,
            },
            _ => Stroke {
                colour: colour.unwrap_or(FEED).to_string(),
                width: 1.5,
                dash: None,
            },
        };
        stroke_path(out, &d, &stroke, Some(title.trim()));
    }
}

fn dot(out: &mut String, (x, y): (f64, f64), r: f64, fill: &str, title: &str) {
    let _ = writeln!(
        out,
        "<circle cx=\"{x:.1}\" cy=\"{y:.1}\" r=\"{r}\" fill=\"{fill}\"><title>{}</title></circle>",
        esc(title)
    );
}

fn svg_open(height: f64, title: &str) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{WIDTH}\" height=\"{height}\" viewBox=\"0 0 {WIDTH} {height}\">"
    );
    let _ = writeln!(out, "<title>{}</title>", esc(title));
    let _ = writeln!(
        out,
        "<rect width=\"{WIDTH}\" height=\"{height}\" fill=\"#fafafa\"/>"
    );
    text(&mut out, 20.0, 26.0, 16.0, "start", "#111111", title);
    out
}

/// `ncthread plot`: the whole program's toolpath, the chosen thread operation's passes in XZ
/// (X magnified), its cross-section, and a legend. `operation` is the one drawn in detail.
pub fn plot(title: &str, segments: &[Segment], operation: Option<&Operation>) -> String {
    let operation = operation.filter(|o| !o.passes.is_empty());
    let height = if operation.is_some() { 900.0 } else { 520.0 };
    let mut out = svg_open(height, title);
    // 1. The toolpath.
    let rect = (70.0, 60.0, WIDTH - 110.0, 400.0);
    // Blocks kept as written (a FANUC cycle without a machine model): their moves are the
    // control's, so the picture says they are missing.
    let kept = segments
        .iter()
        .filter(|s| matches!(s.motion, crate::sim::Motion::Kept { .. }))
        .count();
    let heading = if kept == 0 {
        "toolpath (XZ; rapids dashed, feeds green, threads coloured by pass: first blue, last red)"
            .to_string()
    } else {
        format!(
            "toolpath (XZ; rapids dashed, feeds green); not drawn: {kept} block{} kept as written, whose moves are the control's",
            if kept == 1 { "" } else { "s" }
        )
    };
    text(&mut out, 70.0, 52.0, 13.0, "start", "#222222", &heading);
    match bounds(segments.iter()) {
        Some(b) => {
            let v = View::fit(rect, b, true);
            axes(&mut out, &v, "Z (mm)", "X (diameter, mm)", true);
            draw_motion(&mut out, &v, segments, None);
            if let Some(start) = segments
                .iter()
                .find_map(|s| s.from.known().or(s.to.known()))
            {
                dot(&mut out, v.at(start), 4.0, "#111111", "start point");
            }
        }
        None => text(
            &mut out,
            rect.0 + 10.0,
            rect.1 + 30.0,
            13.0,
            "start",
            "#444444",
            "no move with a known position",
        ),
    }
    if let Some(op) = operation {
        if op.is_thread() {
            thread_detail(&mut out, op, (70.0, 520.0, 470.0, 320.0));
            cross_section(&mut out, op, (600.0, 520.0, 300.0, 320.0));
            legend(&mut out, op, (920.0, 520.0));
        } else {
            // A roughing cycle's cuts: the whole width.
            thread_detail(&mut out, op, (70.0, 520.0, WIDTH - 110.0, 320.0));
        }
    }
    out.push_str("</svg>\n");
    out
}

/// A view's title above its rectangle.
fn heading(out: &mut String, rect: (f64, f64, f64, f64), title: &str) {
    text(out, rect.0, rect.1 - 8.0, 13.0, "start", "#222222", title);
}

/// The operation's passes along Z, X magnified so that each pass is apart; a roughing or
/// finishing cycle's cuts as it moves them, rapids dashed.
fn thread_detail(out: &mut String, op: &Operation, rect: (f64, f64, f64, f64)) {
    let cuts = detail_cuts(op);
    let Some(b) = detail_bounds(op, cuts) else {
        return;
    };
    let v = View::fit(rect, b, false);
    heading(out, rect, &detail_heading(op, cuts, &scale_note(&v)));
    axes(out, &v, "Z (mm)", "X (diameter, mm)", true);
    let n = op.passes.len();
    // Lines along a taper leave the frame: they are cut at it.
    let _ = writeln!(
        out,
        "<clipPath id=\"passes\"><rect x=\"{:.1}\" y=\"{:.1}\" width=\"{:.1}\" height=\"{:.1}\"/></clipPath>\n<g clip-path=\"url(#passes)\">",
        v.left, v.top, v.width, v.height
    );
    if op.is_thread() {
        guide_lines(out, &v, op);
    }
    for m in cuts {
        draw_cut(out, &v, m, n);
    }
    if cuts.is_empty() {
        for (i, p) in op.passes.iter().enumerate() {
            let (Some(start), Some(end)) = (p.start.known(), p.end.known()) else {
                continue;
            };
            let (a, c) = (v.at(start), v.at(end));
            let _ = writeln!(
                out,
                "<line x1=\"{:.1}\" y1=\"{:.1}\" x2=\"{:.1}\" y2=\"{:.1}\" stroke=\"{}\" stroke-width=\"2\"><title>pass {}: {} to {}</title></line>",
                a.0,
                a.1,
                c.0,
                c.1,
                pass_colour(i, n),
                p.number,
                crate::sim::show_pos(p.start),
                crate::sim::show_pos(p.end)
            );
        }
    }
    out.push_str("</g>\n");
    pass_labels(out, &v, op);
}

/// A cycle's moves from its first cut to its last (the approach and the way back are in
/// the toolpath).
fn detail_cuts(op: &Operation) -> &[CycleMove] {
    match (
        op.moves.iter().position(|m| m.cut.is_some()),
        op.moves.iter().rposition(|m| m.cut.is_some()),
    ) {
        (Some(a), Some(b)) => &op.moves[a..=b],
        _ => &[],
    }
}

/// The detail's bounds (Z, Z, radius, radius): the passes, the cuts and the crest line,
/// with room for the pass numbers past the passes' starts.
fn detail_bounds(op: &Operation, cuts: &[CycleMove]) -> Option<(f64, f64, f64, f64)> {
    let mut b: Option<(f64, f64, f64, f64)> = None;
    let mut add = |p: Pos| {
        let Some((x, z)) = p.known() else { return };
        let (z, r) = (z.to_mm_f64(), x.to_mm_f64() / 2.0);
        b = Some(match b {
            None => (z, z, r, r),
            Some((a, c, d, e)) => (a.min(z), c.max(z), d.min(r), e.max(r)),
        });
    };
    for p in &op.passes {
        add(p.start);
        add(p.end);
    }
    if let Some((z0, z1, r0, r1)) =
        moves_bounds(cuts.iter().map(|m| (m.from, m.to, m.arc.map(|a| a.0))))
    {
        add(Pos::new(
            Length::from_mm_f64(r0 * 2.0),
            Length::from_mm_f64(z0),
        ));
        add(Pos::new(
            Length::from_mm_f64(r1 * 2.0),
            Length::from_mm_f64(z1),
        ));
    }
    // The crest line, parallel to the root (the deepest pass's line).
    if let (Some(c), Some(((x0, z0), (x1, z1)))) = (op.crest, root_line(op)) {
        let offset = c.to_mm_f64() - op.root.map_or(x0, |r| r.to_mm_f64());
        for (x, z) in [(x0, z0), (x1, z1)] {
            b = b.map(|(a, c, d, e)| {
                let r = (x + offset) / 2.0;
                (a.min(z), c.max(z), d.min(r), e.max(r))
            });
        }
    }
    let mut b = b?;
    let room = (b.1 - b.0).max(1.0) * 0.08;
    if labels_right(op) {
        b.1 += room;
    } else {
        b.0 -= room;
    }
    Some(b)
}

/// How a view's axes are scaled: `to scale`, or which one is magnified and how much.
fn scale_note(v: &View) -> String {
    if v.sr > v.sz * 1.05 {
        format!(
            "X magnified ×{}",
            number((v.sr / v.sz * 10.0).round() / 10.0)
        )
    } else if v.sz > v.sr * 1.05 {
        format!(
            "Z magnified ×{}",
            number((v.sz / v.sr * 10.0).round() / 10.0)
        )
    } else {
        "to scale".into()
    }
}

/// The detail's heading: the operation, what is drawn, and the `scale`.
fn detail_heading(op: &Operation, cuts: &[CycleMove], scale: &str) -> String {
    match &op.kind {
        Kind::Roughing(code) | Kind::Finishing(code) if cuts.iter().any(|m| m.cut.is_none()) => {
            format!(
                "operation {}: {code}'s cuts ({scale}; rapids dashed)",
                op.number
            )
        }
        Kind::Roughing(code) | Kind::Finishing(code) => {
            format!("operation {}: {code}'s cuts ({scale})", op.number)
        }
        _ => format!("operation {}: passes along Z ({scale})", op.number),
    }
}

/// One move of a cycle's cuts (of `n` passes): a rapid dashed, a cut in its pass's colour.
fn draw_cut(out: &mut String, v: &View, m: &CycleMove, n: usize) {
    let Some(d) = path_of(v, m.from, m.to, m.arc) else {
        return;
    };
    let (from, to) = (crate::sim::show_pos(m.from), crate::sim::show_pos(m.to));
    let (stroke, title) = match (m.cut, m.arc) {
        (None, _) => (
            Stroke {
                colour: RAPID.to_string(),
                width: 1.0,
                dash: Some("5,4"),
            },
            format!("rapid  {from} → {to}"),
        ),
        (Some(c), arc) => (
            Stroke {
                colour: pass_colour(c - 1, n),
                width: 2.0,
                dash: None,
            },
            match arc {
                Some((centre, clockwise)) => format!(
                    "cut {c}  arc {}  {from} → {to}  centre {}",
                    if clockwise { "G2" } else { "G3" },
                    crate::sim::show_pos(centre)
                ),
                None => format!("cut {c}  feed  {from} → {to}"),
            },
        ),
    };
    stroke_path(out, &d, &stroke, Some(&title));
}

/// Each pass's (or cut's) number beside its start, past the end of its line (beside it, or
/// above or below a cut along X), in its colour on a white ground. Passes that start at one
/// point (a spring pass) share a label (`10, 11`); a label that would overlap one already
/// placed is left out (the first and the last pass are placed first, then the others in
/// order).
fn pass_labels(out: &mut String, v: &View, op: &Operation) {
    /// A label: where (x, baseline, anchor), the start it labels (px), its pass numbers, and
    /// the first's index (its colour).
    struct Label {
        at: (f64, f64, &'static str),
        start: (f64, f64),
        numbers: Vec<usize>,
        first: usize,
    }
    let mut labels: Vec<Label> = Vec::new();
    let n = op.passes.len();
    for (i, p) in op.passes.iter().enumerate() {
        let (Some(start), Some(end)) = (p.start.known(), p.end.known()) else {
            continue;
        };
        let (a, c) = (v.at(start), v.at(end));
        let (dx, dy) = (a.0 - c.0, a.1 - c.1);
        let place = if dy.abs() > dx.abs() && dy.abs() >= 1.0 {
            // Along X: above a start above its end, else below.
            if dy < 0.0 {
                (a.0, a.1 - 5.0, "middle")
            } else {
                (a.0, a.1 + 13.0, "middle")
            }
        } else if dx.abs() >= 1.0 && dx > 0.0 || dx.abs() < 1.0 && labels_right(op) {
            (a.0 + 4.0, a.1 + 3.5, "start")
        } else {
            (a.0 - 4.0, a.1 + 3.5, "end")
        };
        match labels
            .iter_mut()
            .find(|l| (l.start.0 - a.0).abs() < 1.0 && (l.start.1 - a.1).abs() < 1.0)
        {
            Some(l) => l.numbers.push(p.number),
            None => labels.push(Label {
                at: place,
                start: a,
                numbers: vec![p.number],
                first: i,
            }),
        }
    }
    let last = labels.len().saturating_sub(1);
    let order = (0..labels.len())
        .filter(|&i| i == 0 || i == last)
        .chain(1..last);
    // Placed labels: left, right, baseline (px).
    let mut placed: Vec<(f64, f64, f64)> = Vec::new();
    for i in order {
        let Label {
            at: (x, y, anchor),
            numbers,
            first,
            ..
        } = &labels[i];
        let label = numbers
            .iter()
            .map(usize::to_string)
            .collect::<Vec<_>>()
            .join(", ");
        // 10 px digits are about 6.4 px wide, a comma and space 5.
        let width = 6.5 * label.len() as f64;
        let left = match *anchor {
            "start" => *x,
            "end" => x - width,
            _ => x - width / 2.0,
        };
        let overlaps = placed
            .iter()
            .any(|&(l, r, b)| (b - y).abs() < 10.0 && left < r + 2.0 && l < left + width + 2.0);
        if overlaps {
            continue;
        }
        placed.push((left, left + width, *y));
        halo_text(out, *x, *y, 10.0, anchor, &pass_colour(*first, n), &label);
    }
}

/// Whether the passes start on the right of their lines (towards +Z), so that their numbers
/// go on the right (the first pass's way; true when not known).
fn labels_right(op: &Operation) -> bool {
    op.passes
        .iter()
        .find_map(|p| Some(p.start.z? >= p.end.z?))
        .unwrap_or(true)
}

/// [`text`] on a white ground (the text's width estimated), legible over the lines it
/// crosses.
fn halo_text(out: &mut String, x: f64, y: f64, size: f64, anchor: &str, fill: &str, s: &str) {
    // DejaVu Sans is about 0.6 em a character.
    let width = 0.6 * size * s.chars().count() as f64 + 2.0;
    let left = match anchor {
        "end" => x - width + 1.0,
        "middle" => x - width / 2.0,
        _ => x - 1.0,
    };
    let _ = writeln!(
        out,
        "<rect x=\"{left:.1}\" y=\"{:.1}\" width=\"{width:.1}\" height=\"{:.1}\" fill=\"#ffffff\" fill-opacity=\"0.85\"/>",
        y - size * 0.9,
        size * 1.15
    );
    text(out, x, y, size, anchor, fill, s);
}

/// The crest and root lines along the passes: the root is the deepest pass's line (along a
/// taper, the taper) and the crest parallel to it, `crest − root` apart on the diameter. They
/// run from the view's far edge to where the passes start, so that the pass numbers past the
/// starts stand clear, and are labelled where the passes start (where their diameters are
/// measured: a taper's label says the Z), each on its side away from the other.
fn guide_lines(out: &mut String, v: &View, op: &Operation) {
    let Some(((x0, z0), (x1, z1))) = root_line(op) else {
        return;
    };
    let slope = if (z1 - z0).abs() > 1e-9 {
        (x1 - x0) / (z1 - z0)
    } else {
        0.0
    };
    let right = labels_right(op);
    let (e0, e1) = v.z_range();
    let starts = op
        .passes
        .iter()
        .filter_map(|p| p.start.z)
        .map(|z| z.to_mm_f64());
    let (from, to) = if right {
        (e0, starts.fold(f64::MIN, f64::max))
    } else {
        (starts.fold(f64::MAX, f64::min), e1)
    };
    let near = if right { to } else { from };
    // A taper's diameters are those where the deepest pass starts.
    let at = if slope == 0.0 {
        String::new()
    } else {
        format!(" at Z{}", number(z0))
    };
    // Diameters: the root line's at z, and the crest's offset from it.
    let root_at = |z: f64| x0 + slope * (z - z0);
    let offset = match (op.crest, op.root) {
        (Some(c), Some(r)) => Some(c.to_mm_f64() - r.to_mm_f64()),
        (Some(c), None) => Some(c.to_mm_f64() - x0),
        _ => None,
    };
    // The crest (or, not known, the first pass) is above the root on the screen when the
    // thread is external.
    let outward = match (offset, op.passes.first().and_then(|p| p.start.x)) {
        (Some(o), _) => o >= 0.0,
        (None, Some(x)) => x.to_mm_f64() >= x0,
        _ => true,
    };
    let span = GuideSpan {
        from,
        to,
        near,
        right,
    };
    if let (Some(offset), Some(crest)) = (offset, op.crest) {
        guide_line(
            out,
            v,
            &span,
            &|z| root_at(z) + offset,
            outward,
            &format!("crest Ø{}{at}", crest.mm()),
        );
    }
    let root = op.root.map_or("deepest pass".to_string(), |r| {
        format!("root Ø{}{at}", r.mm())
    });
    guide_line(out, v, &span, &root_at, !outward, &root);
}

/// Where the guide lines run along Z (`from` to `to`) and where their labels stand
/// (`near`, on the `right` side or the left).
struct GuideSpan {
    from: f64,
    to: f64,
    near: f64,
    right: bool,
}

/// One guide line, at the diameter `diameter_at` each Z, labelled `label` `above` it (or
/// below).
fn guide_line(
    out: &mut String,
    v: &View,
    span: &GuideSpan,
    diameter_at: &dyn Fn(f64) -> f64,
    above: bool,
    label: &str,
) {
    let GuideSpan {
        from,
        to,
        near,
        right,
    } = *span;
    let (a, b) = (
        v.px(from, diameter_at(from) / 2.0),
        v.px(to, diameter_at(to) / 2.0),
    );
    let _ = writeln!(
        out,
        "<line x1=\"{:.1}\" y1=\"{:.1}\" x2=\"{:.1}\" y2=\"{:.1}\" stroke=\"#555555\" stroke-width=\"1\" stroke-dasharray=\"2,3\"/>",
        a.0, a.1, b.0, b.1
    );
    // Clear of the line over the label's width (about 6 px a character at 10 px).
    let width = 6.0 * label.chars().count() as f64 / v.sz;
    let other = if right { near - width } else { near + width };
    let (x, ya) = v.px(near, diameter_at(near) / 2.0);
    let yb = v.px(other, diameter_at(other) / 2.0).1;
    let y = if above {
        ya.min(yb) - 4.0
    } else {
        ya.max(yb) + 12.0
    };
    let y = y.clamp(v.top + 12.0, v.top + v.height - 4.0);
    let (x, anchor) = if right {
        (x - 4.0, "end")
    } else {
        (x + 4.0, "start")
    };
    halo_text(out, x, y, 10.0, anchor, "#555555", label);
}

/// The deepest pass's line, (X diameter, Z) at its start and end in mm: the thread's root.
fn root_line(op: &Operation) -> Option<((f64, f64), (f64, f64))> {
    let depth = |p: &crate::explain::Pass| p.cumulative_depth.unwrap_or(p.below_first);
    let deepest = op
        .passes
        .iter()
        .filter(|p| p.start.known().is_some() && p.end.known().is_some())
        .max_by_key(|p| depth(p))?;
    let mm = |p: Pos| p.known().map(|(x, z)| (x.to_mm_f64(), z.to_mm_f64()));
    Some((mm(deepest.start)?, mm(deepest.end)?))
}

/// The thread's cross-section: the form (60° flanks from the crest to the deepest pass) and
/// the tool's tip at every pass (its depth, and its shift along the cut).
fn cross_section(out: &mut String, op: &Operation, rect: (f64, f64, f64, f64)) {
    heading(
        out,
        rect,
        &format!("operation {}: cross-section (tool at each pass)", op.number),
    );
    let deepest = op.passes.iter().map(pass_depth).fold(0.0f64, f64::max);
    let lead = op.lead.map_or(1.0, |l| l.to_mm_f64());
    let tan30 = (30f64).to_radians().tan();
    // Horizontal: along the cut (mm), the first pass's tip at 0; vertical: depth (down).
    let shifts: Vec<f64> = op
        .passes
        .iter()
        .map(|p| p.shift.map_or(0.0, |s| s.to_mm_f64()))
        .collect();
    let (smin, smax) = shifts
        .iter()
        .fold((0.0f64, 0.0f64), |(a, b), &s| (a.min(s), b.max(s)));
    let half = (deepest * tan30 + lead * 0.15).max(lead * 0.3);
    let v = View::fit(
        rect,
        (smin - half, smax + half, -deepest * 1.15, deepest * 0.25),
        true,
    );
    let _ = writeln!(
        out,
        "<rect x=\"{:.1}\" y=\"{:.1}\" width=\"{:.1}\" height=\"{:.1}\" fill=\"#ffffff\" stroke=\"#444444\"/>",
        v.left, v.top, v.width, v.height
    );
    // The part: the crest line, and the groove the deepest passes leave.
    let crest_y = v.px(0.0, 0.0).1;
    section_line(out, &v, crest_y);
    // The root, the deepest pass's depth, drawn as the crest is.
    let root_y = v.px(0.0, -deepest).1;
    section_line(out, &v, root_y);
    // The tools reach above the crest: they are cut at the frame.
    let _ = writeln!(
        out,
        "<clipPath id=\"section\"><rect x=\"{:.1}\" y=\"{:.1}\" width=\"{:.1}\" height=\"{:.1}\"/></clipPath>\n<g clip-path=\"url(#section)\">",
        v.left, v.top, v.width, v.height
    );
    let height = deepest * 1.1 + lead * 0.05;
    for (i, &shift) in shifts.iter().enumerate() {
        section_tool(out, &v, op, i, shift, height);
    }
    out.push_str("</g>\n");
    // The lines' labels over the tools: the crest above its line, the root below.
    let crest = match op.crest {
        Some(c) => format!("crest Ø{}", c.mm()),
        None => "pass 1 (the crest is not in the program)".into(),
    };
    let root = op
        .root
        .map_or("deepest pass".to_string(), |r| format!("root Ø{}", r.mm()));
    for (y, label) in [(crest_y - 4.0, crest), (root_y + 12.0, root)] {
        halo_text(out, v.left + 4.0, y, 10.0, "start", "#555555", &label);
    }
    scale_bar(out, &v);
}

/// A pass's cumulative depth in mm (below the first pass when the crest is not known).
fn pass_depth(p: &crate::explain::Pass) -> f64 {
    p.cumulative_depth.unwrap_or(p.below_first).to_mm_f64()
}

/// A dotted line across the cross-section at height `y` (px): the crest or the root.
fn section_line(out: &mut String, v: &View, y: f64) {
    let _ = writeln!(
        out,
        "<line x1=\"{:.1}\" y1=\"{y:.1}\" x2=\"{:.1}\" y2=\"{y:.1}\" stroke=\"#555555\" stroke-dasharray=\"2,3\"/>",
        v.left,
        v.left + v.width
    );
}

/// The tool of pass `i` in the cross-section, `shift` mm along the cut, its flanks
/// `height` mm tall, its tip marked.
fn section_tool(out: &mut String, v: &View, op: &Operation, i: usize, shift: f64, height: f64) {
    let tan30 = (30f64).to_radians().tan();
    let p = &op.passes[i];
    let (s, d) = (shift, pass_depth(p));
    let top = d - height;
    let points = [
        v.px(s - (d - top) * tan30, -top),
        v.px(s, -d),
        v.px(s + (d - top) * tan30, -top),
    ];
    let colour = pass_colour(i, op.passes.len());
    let _ = writeln!(
        out,
        "<polyline points=\"{:.1},{:.1} {:.1},{:.1} {:.1},{:.1}\" fill=\"none\" stroke=\"{colour}\" stroke-width=\"1.5\"><title>pass {}: depth {} mm, shift {} mm</title></polyline>",
        points[0].0,
        points[0].1,
        points[1].0,
        points[1].1,
        points[2].0,
        points[2].1,
        p.number,
        number(d),
        number(s)
    );
    dot(out, points[1], 2.5, &colour, &format!("pass {}", p.number));
}

/// A scale bar of one tick step in the view's lower left corner.
fn scale_bar(out: &mut String, v: &View) {
    let (z0, z1) = v.z_range();
    let step = tick_step(z1 - z0, 4.0);
    let (a, y) = (v.left + 10.0, v.top + v.height - 10.0);
    let b = a + step * v.sz;
    let _ = writeln!(
        out,
        "<line x1=\"{a:.1}\" y1=\"{y:.1}\" x2=\"{b:.1}\" y2=\"{y:.1}\" stroke=\"#222222\" stroke-width=\"2\"/>"
    );
    text(
        out,
        (a + b) / 2.0,
        y - 4.0,
        10.0,
        "middle",
        "#222222",
        &format!("{} mm", number(step)),
    );
}

fn legend(out: &mut String, op: &Operation, (x, y): (f64, f64)) {
    let mut lines = vec![format!("operation {} (line {})", op.number, op.line)];
    if let Some(l) = op.lead {
        lines.push(format!("lead {} mm", l.mm()));
    }
    if let Some(c) = op.crest {
        lines.push(format!("crest Ø{}", c.mm()));
    }
    if let Some(r) = op.root {
        lines.push(format!("root Ø{}", r.mm()));
    }
    match op.depth {
        Some(d) => lines.push(format!("depth {} mm", d.mm())),
        None => lines.push("depth: crest not known".into()),
    }
    let n = op.passes.len();
    lines.push(format!("{n} pass{}", if n == 1 { "" } else { "es" }));
    if op.spring_passes > 0 {
        lines.push(format!("({} spring)", op.spring_passes));
    }
    if let Some(s) = op.schedule {
        lines.push(format!("{s} schedule"));
    }
    if let Some(a) = op.infeed_angle {
        lines.push(format!("infeed {a:.1}°"));
    }
    if let Some(h) = op.hand {
        lines.push(format!("{}-hand", h.id()));
    }
    for (i, l) in lines.iter().enumerate() {
        text(out, x, y + 14.0 * i as f64, 12.0, "start", "#222222", l);
    }
    // The colour ramp of the passes.
    let top = y + 14.0 * lines.len() as f64 + 6.0;
    for i in 0..n.min(40) {
        let _ = writeln!(
            out,
            "<rect x=\"{:.1}\" y=\"{top:.1}\" width=\"{:.1}\" height=\"10\" fill=\"{}\"/>",
            x + i as f64 * 150.0 / n.min(40) as f64,
            150.0 / n.min(40) as f64,
            pass_colour(i, n)
        );
    }
    text(
        out,
        x,
        top + 22.0,
        10.0,
        "start",
        "#444444",
        "first pass → last pass",
    );
}

/// `verify --plot`: both programs' motions overlaid (as simulated: `left` and `right` are not
/// normalised, so that rapids are drawn as the machine moves), and the first difference (of
/// the normalised motions) marked and labelled.
pub fn verify_plot(
    title: &str,
    left_name: &str,
    left: &[Segment],
    right_name: &str,
    right: &[Segment],
    difference: Option<&Difference>,
) -> String {
    // The difference's segments as the machine moves them.
    let marked: Vec<Segment> = difference
        .map(|d| {
            let mut m = d.left.map_or(Vec::new(), |s| as_moved(left, &s));
            m.extend(d.right.map_or(Vec::new(), |s| as_moved(right, &s)));
            m
        })
        .unwrap_or_default();
    let detail = bounds(marked.iter());
    let height = if detail.is_some() { 1000.0 } else { 640.0 };
    let mut out = svg_open(height, title);
    let Some(b) = bounds(left.iter().chain(right)) else {
        text(
            &mut out,
            80.0,
            120.0,
            13.0,
            "start",
            "#444444",
            "no move with a known position",
        );
        out.push_str("</svg>\n");
        return out;
    };
    verify_key(&mut out, left_name, right_name);
    let whole = View::fit((70.0, 80.0, WIDTH - 110.0, 440.0), b, true);
    axes(&mut out, &whole, "Z (mm)", "X (diameter, mm)", true);
    overlay(&mut out, &whole, left, right, &marked, difference);
    let Some(d) = difference else {
        text(
            &mut out,
            70.0,
            575.0,
            12.0,
            "start",
            "#1b6b1b",
            "equivalent: the motions agree within the tolerance",
        );
        out.push_str("</svg>\n");
        return out;
    };
    let label = format!("first difference: {d}");
    for (i, l) in wrap(&label, 150).iter().enumerate() {
        text(
            &mut out,
            70.0,
            570.0 + 15.0 * i as f64,
            12.0,
            "start",
            MARK,
            l,
        );
    }
    if let Some(detail) = detail {
        difference_detail(&mut out, detail, left, right, &marked, difference);
    }
    out.push_str("</svg>\n");
    out
}

/// The key of a verify plot: each program's line as it is drawn, and their rapids.
fn verify_key(out: &mut String, left_name: &str, right_name: &str) {
    let line = |out: &mut String, (x, y): (f64, f64), colour: &str, width: f64, dash: &str| {
        let _ = writeln!(
            out,
            "<line x1=\"{x}\" y1=\"{y}\" x2=\"{}\" y2=\"{y}\" stroke=\"{colour}\" stroke-width=\"{width}\" stroke-dasharray=\"{dash}\"/>",
            x + 30.0
        );
    };
    line(out, (70.0, 50.0), LEFT, 2.5, "none");
    text(out, 106.0, 54.0, 12.0, "start", "#222222", left_name);
    line(out, (70.0, 66.0), RIGHT, 1.2, "6,3");
    text(out, 106.0, 70.0, 12.0, "start", "#222222", right_name);
    line(out, (WIDTH - 380.0, 50.0), LEFT, 2.5, "2,4");
    line(out, (WIDTH - 380.0, 66.0), RIGHT, 1.2, "2,4");
    text(
        out,
        WIDTH - 344.0,
        62.0,
        12.0,
        "start",
        "#222222",
        "rapids (dotted, each in its program's colour)",
    );
}

/// The view around the first difference (`detail`: the bounds of its segments), X
/// magnified so that a small step is seen. (Twice the step around a small one; a large
/// one, such as a rapid to another place, is not magnified past the whole view.)
fn difference_detail(
    out: &mut String,
    (z0, z1, r0, r1): (f64, f64, f64, f64),
    left: &[Segment],
    right: &[Segment],
    marked: &[Segment],
    difference: Option<&Difference>,
) {
    let (dz, dr) = ((z1 - z0).max(1.0), (r1 - r0).max(0.05));
    let pad = (dr * 2.0).min(dr * 0.1 + 0.1);
    let bounds = (z0 - dz * 0.1, z1 + dz * 0.1, r0 - pad, r1 + pad);
    let rect = (70.0, 640.0, WIDTH - 110.0, 300.0);
    text(
        out,
        70.0,
        630.0,
        13.0,
        "start",
        "#222222",
        "around the first difference (X magnified)",
    );
    let v = View::fit(rect, bounds, false);
    axes(out, &v, "Z (mm)", "X (diameter, mm)", true);
    let _ = writeln!(
        out,
        "<clipPath id=\"detail\"><rect x=\"{:.1}\" y=\"{:.1}\" width=\"{:.1}\" height=\"{:.1}\"/></clipPath>\n<g clip-path=\"url(#detail)\">",
        v.left, v.top, v.width, v.height
    );
    overlay(out, &v, left, right, marked, difference);
    out.push_str("</g>\n");
}

/// Both motions in `v`, the difference's segments (`marked`, as moved) in red and circled.
fn overlay(
    out: &mut String,
    v: &View,
    left: &[Segment],
    right: &[Segment],
    marked: &[Segment],
    difference: Option<&Difference>,
) {
    draw_overlay(out, v, left, LEFT, 2.5, None);
    draw_overlay(out, v, right, RIGHT, 1.2, Some("6,3"));
    let Some(d) = difference else { return };
    let label = format!("first difference: {d}");
    for s in marked {
        if let Some(path) = segment_path(v, s) {
            stroke_path(
                out,
                &path,
                &Stroke {
                    colour: MARK.to_string(),
                    width: 3.5,
                    dash: None,
                },
                Some(&s.to_text()),
            );
        }
    }
    if let Some(p) = [d.left, d.right]
        .iter()
        .flatten()
        .find_map(|s| s.to.known().or(s.from.known()))
    {
        let (x, y) = v.at(p);
        let _ = writeln!(
            out,
            "<circle cx=\"{x:.1}\" cy=\"{y:.1}\" r=\"12\" fill=\"none\" stroke=\"{MARK}\" stroke-width=\"2.5\"><title>{}</title></circle>",
            esc(&label)
        );
    }
}

/// A segment of a normalised motion as the machine moves it: normalising merges consecutive
/// rapids into one from the first's start to the last's end (it takes the last's line and
/// pass); that rapid is those rapids of `moves` (the motion as simulated) again. Anything else
/// is drawn as it is: merged feeds are collinear, merged arcs one arc.
fn as_moved(moves: &[Segment], s: &Segment) -> Vec<Segment> {
    if !matches!(s.motion, Motion::Rapid) {
        return vec![*s];
    }
    let rapid = |m: &Segment| matches!(m.motion, Motion::Rapid);
    for (i, last) in moves.iter().enumerate() {
        if !(rapid(last) && last.to == s.to && last.line == s.line && last.pass == s.pass) {
            continue;
        }
        // The run of rapids that ends here (events where the tool stands do not break it),
        // from the first that starts where the merged one does.
        let mut first = i;
        while first > 0
            && (rapid(&moves[first - 1]) || moves[first - 1].from == moves[first - 1].to)
        {
            first -= 1;
        }
        if let Some(k) = (first..=i).find(|&k| rapid(&moves[k]) && moves[k].from == s.from) {
            return moves[k..=i].iter().filter(|m| rapid(m)).copied().collect();
        }
    }
    vec![*s]
}

fn draw_overlay(
    out: &mut String,
    v: &View,
    segments: &[Segment],
    colour: &str,
    width: f64,
    dash: Option<&str>,
) {
    for s in segments {
        let Some(d) = segment_path(v, s) else {
            continue;
        };
        let dash = match s.motion {
            Motion::Rapid => Some("2,4"),
            _ => dash,
        };
        stroke_path(
            out,
            &d,
            &Stroke {
                colour: colour.to_string(),
                width,
                dash,
            },
            Some(s.to_text().trim()),
        );
    }
}

/// `text` in lines of at most `width` characters, broken at spaces.
fn wrap(text: &str, width: usize) -> Vec<String> {
    let mut lines = vec![String::new()];
    for word in text.split(' ') {
        let last = lines.last_mut().expect("one line");
        if !last.is_empty() && last.chars().count() + 1 + word.chars().count() > width {
            lines.push(word.to_string());
        } else {
            if !last.is_empty() {
                last.push(' ');
            }
            last.push_str(word);
        }
    }
    lines
}

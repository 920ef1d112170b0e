//! The pictures against the motion they draw (issue 30): every arc of every corpus program is
//! read back out of the SVG with the SVG specification's own endpoint-to-centre conversion
//! and held against the simulated arc; and the pictures, rendered with resvg, have ink where
//! the program moves and none where it does not.
mod common;
use common::render_svg as render;

use ncthread::explain::CycleMove;
use ncthread::ir::Pos;
use ncthread::sim::{Motion, Segment};

/// Text as the SVG writes it, unescaped.
fn unescape(s: &str) -> String {
    s.replace("&quot;", "\"")
        .replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&amp;", "&")
}

/// Every `<path>` of an SVG in order: its `d` and its tooltip.
fn paths(svg: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let mut rest = svg;
    while let Some(at) = rest.find("<path d=\"") {
        rest = &rest[at + 9..];
        let end = rest.find('"').expect("d ends");
        let d = rest[..end].to_string();
        let element_end = rest.find("</path>").unwrap_or(rest.len());
        let close = rest.find("/>").unwrap_or(rest.len());
        let title = if element_end < close || close == rest.len() {
            let t = rest.find("<title>").expect("a title") + 7;
            let e = rest[t..].find("</title>").expect("title ends") + t;
            unescape(&rest[t..e])
        } else {
            String::new()
        };
        out.push((d, title));
    }
    out
}

/// A path's commands: each letter with its numbers (`M`, `L`, `A`).
fn commands(d: &str) -> Vec<(char, Vec<f64>)> {
    let mut out: Vec<(char, Vec<f64>)> = Vec::new();
    let mut number = String::new();
    let flush = |number: &mut String, out: &mut Vec<(char, Vec<f64>)>| {
        if !number.is_empty() {
            let v = number
                .parse()
                .unwrap_or_else(|_| panic!("{number:?} in {d}"));
            out.last_mut().expect("a command first").1.push(v);
            number.clear();
        }
    };
    for c in d.chars() {
        if c.is_ascii_alphabetic() {
            flush(&mut number, &mut out);
            out.push((c, Vec::new()));
        } else if c == ',' || c.is_whitespace() {
            flush(&mut number, &mut out);
        } else {
            number.push(c);
        }
    }
    flush(&mut number, &mut out);
    out
}

/// An SVG elliptical arc in centre form.
#[derive(Debug)]
struct Centred {
    cx: f64,
    cy: f64,
    rx: f64,
    ry: f64,
    /// Degrees, in the SVG's user space (y down): positive turns from +x towards +y.
    sweep: f64,
    /// The arc commands it was drawn with.
    pieces: usize,
}

/// SVG 1.1, implementation notes F.6.5 (with F.6.6's correction of radii too small): the
/// arc from (x1, y1) to (x2, y2) with radii `rx`, `ry`, x-axis rotation `phi` (degrees) and
/// the large-arc and sweep flags, in centre form.
#[allow(clippy::too_many_arguments)]
fn endpoint_to_centre(
    (x1, y1): (f64, f64),
    (x2, y2): (f64, f64),
    mut rx: f64,
    mut ry: f64,
    phi: f64,
    large: bool,
    sweep: bool,
) -> Centred {
    let (sin, cos) = phi.to_radians().sin_cos();
    // Step 1: (x1', y1').
    let (dx, dy) = ((x1 - x2) / 2.0, (y1 - y2) / 2.0);
    let (x1p, y1p) = (cos * dx + sin * dy, -sin * dx + cos * dy);
    // F.6.6: radii too small to reach are scaled up.
    (rx, ry) = (rx.abs(), ry.abs());
    let lambda = x1p * x1p / (rx * rx) + y1p * y1p / (ry * ry);
    if lambda > 1.0 {
        (rx, ry) = (rx * lambda.sqrt(), ry * lambda.sqrt());
    }
    // Step 2: (cx', cy'), the sign + when the flags differ.
    let num = rx * rx * ry * ry - rx * rx * y1p * y1p - ry * ry * x1p * x1p;
    let den = rx * rx * y1p * y1p + ry * ry * x1p * x1p;
    let mut k = (num / den).max(0.0).sqrt();
    if large == sweep {
        k = -k;
    }
    let (cxp, cyp) = (k * rx * y1p / ry, -k * ry * x1p / rx);
    // Step 3: (cx, cy).
    let (cx, cy) = (
        cos * cxp - sin * cyp + (x1 + x2) / 2.0,
        sin * cxp + cos * cyp + (y1 + y2) / 2.0,
    );
    // Step 4: θ1 and Δθ.
    let angle = |(ux, uy): (f64, f64), (vx, vy): (f64, f64)| {
        let a = ((ux * vx + uy * vy) / (ux.hypot(uy) * vx.hypot(vy)))
            .clamp(-1.0, 1.0)
            .acos()
            .to_degrees();
        if ux * vy - uy * vx < 0.0 { -a } else { a }
    };
    let u = ((x1p - cxp) / rx, (y1p - cyp) / ry);
    let v = ((-x1p - cxp) / rx, (-y1p - cyp) / ry);
    let mut delta = angle(u, v) % 360.0;
    if !sweep && delta > 0.0 {
        delta -= 360.0;
    } else if sweep && delta < 0.0 {
        delta += 360.0;
    }
    Centred {
        cx,
        cy,
        rx,
        ry,
        sweep: delta,
        pieces: 1,
    }
}

/// An arc drawn as one or more SVG arc commands, in centre form (the radii of the first, the
/// centres' mean, the sweeps added).
fn drawn_arc(d: &str) -> Centred {
    let cmds = commands(d);
    let (m, rest) = cmds.split_first().expect("a command");
    assert_eq!(m.0, 'M', "{d}");
    let mut at = (m.1[0], m.1[1]);
    let mut whole: Option<Centred> = None;
    for (c, v) in rest {
        assert_eq!(*c, 'A', "an arc is drawn with A only: {d}");
        assert_eq!(v.len(), 7, "{d}");
        let to = (v[5], v[6]);
        let part = endpoint_to_centre(at, to, v[0], v[1], v[2], v[3] != 0.0, v[4] != 0.0);
        match &mut whole {
            None => whole = Some(part),
            Some(w) => {
                // Two halves of a circle: each centre is found from a chord that is a
                // diameter to two decimals, which moves it by about √(0.01·r) px either
                // way; their mean is the centre.
                assert!(
                    (w.cx - part.cx).hypot(w.cy - part.cy) < 0.2 + (0.05 * w.rx.max(w.ry)).sqrt(),
                    "the pieces of one arc share a centre: {d}"
                );
                (w.cx, w.cy) = ((w.cx + part.cx) / 2.0, (w.cy + part.cy) / 2.0);
                w.sweep += part.sweep;
                w.pieces += 1;
            }
        }
        at = to;
    }
    whole.unwrap_or_else(|| panic!("no arc in {d}"))
}

/// How a view maps program mm (Z, X as a radius) to pixels: `x = ax + kx·z`,
/// `y = ay + ky·r`. Found from the drawn ends of the moves (the test does not ask the plot).
#[derive(Debug)]
struct Mapping {
    ax: f64,
    kx: f64,
    ay: f64,
    ky: f64,
}

/// A program point in mm (Z, X as a radius) and where a view draws it (px).
type Pair = ((f64, f64), (f64, f64));

impl Mapping {
    /// From pairs of (program point in mm, pixel point): the two furthest apart along each
    /// axis fix it; every pair must then agree to the SVG's two decimals.
    fn fit(pairs: &[Pair], here: &str) -> Option<Mapping> {
        let axis = |get: fn(&Pair) -> (f64, f64)| {
            let lo = pairs.iter().map(get).min_by(|a, b| a.0.total_cmp(&b.0))?;
            let hi = pairs.iter().map(get).max_by(|a, b| a.0.total_cmp(&b.0))?;
            if hi.0 - lo.0 < 1e-3 {
                return None;
            }
            let k = (hi.1 - lo.1) / (hi.0 - lo.0);
            Some((lo.1 - k * lo.0, k))
        };
        let (ax, kx) = axis(|((z, _), (x, _))| (*z, *x))?;
        let (ay, ky) = axis(|((_, r), (_, y))| (*r, *y))?;
        let m = Mapping { ax, kx, ay, ky };
        for ((z, r), (x, y)) in pairs {
            let (px, py) = m.px(*z, *r);
            assert!(
                (px - x).abs() < 0.02 && (py - y).abs() < 0.02,
                "{here}: the view is not one linear map: ({z}, {r}) → ({x}, {y}), expected ({px}, {py})"
            );
        }
        Some(m)
    }

    fn px(&self, z: f64, r: f64) -> (f64, f64) {
        (self.ax + self.kx * z, self.ay + self.ky * r)
    }
}

/// A program point in mm: (Z, X as a radius), as the pictures draw it.
fn mm(p: Pos) -> Option<(f64, f64)> {
    let (x, z) = p.known()?;
    Some((z.to_mm_f64(), x.to_mm_f64() / 2.0))
}

/// A move as a picture draws it: its ends, an arc's centre and sense, and the tooltip the
/// picture gives it (`None`: not checked).
#[derive(Clone, Debug)]
struct Move {
    from: Pos,
    to: Pos,
    /// Centre (X a diameter) and clockwise (G2).
    arc: Option<(Pos, bool)>,
    title: Option<String>,
}

impl Move {
    fn of(s: &Segment) -> Move {
        let arc = match s.motion {
            Motion::Arc {
                centre, clockwise, ..
            } => Some((centre, clockwise)),
            _ => None,
        };
        Move {
            from: s.from,
            to: s.to,
            arc,
            title: Some(s.to_text().trim().to_string()),
        }
    }

    fn of_cycle(m: &CycleMove) -> Move {
        Move {
            from: m.from,
            to: m.to,
            arc: m.arc,
            title: None,
        }
    }

    /// Whether a picture draws it: both ends known, and it moves (an arc that ends where it
    /// starts is a full circle).
    fn drawn(&self) -> bool {
        self.from.known().is_some()
            && self.to.known().is_some()
            && (self.from != self.to || self.arc.is_some())
    }
}

/// The drawable moves paired with a view's paths (the moves drawn first, in order), and the
/// view's map found from their ends.
fn view_map<'a>(
    drawn_paths: &'a [(String, String)],
    moves: &'a [Move],
    here: &str,
) -> (Vec<(&'a Move, &'a str)>, Option<Mapping>) {
    let moves: Vec<&Move> = moves.iter().filter(|m| m.drawn()).collect();
    assert!(
        drawn_paths.len() >= moves.len(),
        "{here}: {} paths for {} moves",
        drawn_paths.len(),
        moves.len()
    );
    let mut pairs = Vec::new();
    let mut paired = Vec::new();
    for (m, (d, title)) in moves.into_iter().zip(drawn_paths) {
        if let Some(t) = &m.title {
            assert_eq!(title, t, "{here}: the paths follow the moves");
        }
        let cmds = commands(d);
        let first = &cmds[0].1;
        let last = &cmds.last().unwrap().1;
        let end = (last[last.len() - 2], last[last.len() - 1]);
        pairs.push((mm(m.from).unwrap(), (first[0], first[1])));
        pairs.push((mm(m.to).unwrap(), end));
        paired.push((m, d.as_str()));
    }
    (paired, Mapping::fit(&pairs, here))
}

/// Holds each arc of `moves` drawn among `drawn_paths` (the paths of one view, the drawable
/// moves first and in order) to the arc the program moves: centre, radius, direction and
/// the angle it turns. Returns how many arcs were checked.
fn check_arcs(drawn_paths: &[(String, String)], moves: &[Move], here: &str) -> usize {
    let (paired, map) = view_map(drawn_paths, moves, here);
    let arcs: Vec<_> = paired.iter().filter(|(m, _)| m.arc.is_some()).collect();
    if arcs.is_empty() {
        return 0;
    }
    let map = map.unwrap_or_else(|| panic!("{here}: the moves do not span the view"));
    for (m, d) in &arcs {
        let (centre, clockwise) = m.arc.unwrap();
        let here = format!("{here}: {m:?}");
        let ((z0, r0), (z1, r1), (cz, cr)) = (
            mm(m.from).unwrap(),
            mm(m.to).unwrap(),
            mm(centre).expect("a known centre"),
        );
        let radius = (z0 - cz).hypot(r0 - cr);
        // The program's arc: G3 turns counter-clockwise seen from +Y, and Z × X = Y, so it
        // turns from +Z towards +X: a positive angle in (Z, X); G2 a negative one.
        let (a0, a1) = ((r0 - cr).atan2(z0 - cz), (r1 - cr).atan2(z1 - cz));
        let turned = if m.from == m.to {
            360.0
        } else if clockwise {
            (a0 - a1).to_degrees().rem_euclid(360.0)
        } else {
            (a1 - a0).to_degrees().rem_euclid(360.0)
        };
        // The drawing's arc, back in program mm: the map's signs say whether the picture
        // mirrors an axis (X up is y down: it does), which reverses the sense of turning.
        let svg = drawn_arc(d);
        let (dz, dr) = ((svg.cx - map.ax) / map.kx, (svg.cy - map.ay) / map.ky);
        let (rz, rr) = (svg.rx / map.kx.abs(), svg.ry / map.ky.abs());
        let turned_drawn = svg.sweep * (map.kx * map.ky).signum();
        let clockwise_drawn = turned_drawn < 0.0;
        // Tolerances from the SVG's two decimals: a point is good to 0.005 px, and a centre
        // found from a chord near a diameter moves by about √(0.01·r) px along it, which
        // turns each piece's angle by twice that over r.
        let scale = map.kx.abs().min(map.ky.abs());
        let r_px = radius * scale;
        let centre_tol = (0.05 + (0.02 * r_px).sqrt()) / scale;
        let angle_tol =
            svg.pieces as f64 * (0.5 + (2.0 * (0.02 / r_px.max(0.01)).sqrt()).to_degrees());
        assert_eq!(
            clockwise_drawn,
            clockwise,
            "{here}: drawn {} ({d})",
            if clockwise_drawn { "G2" } else { "G3" }
        );
        // An arc whose ends lie within a pixel of each other (a fuzz finding's 0.004 mm
        // chord) keeps only its sense in two decimals: its centre cannot be read back.
        if m.from != m.to && (z1 - z0).hypot(r1 - r0) * scale < 1.0 {
            continue;
        }
        assert!(
            (turned_drawn.abs() - turned).abs() <= angle_tol,
            "{here}: turns {turned:.3}° but is drawn turning {:.3}° ({d})",
            turned_drawn.abs()
        );
        assert!(
            (dz - cz).hypot(dr - cr) <= centre_tol,
            "{here}: centre Z{cz} r{cr} drawn at Z{dz} r{dr} ({d})"
        );
        assert!(
            (rz - radius).abs() <= centre_tol && (rr - radius).abs() <= centre_tol,
            "{here}: radius {radius} drawn {rz} × {rr} ({d})"
        );
    }
    arcs.len()
}

/// Every arc of every corpus program, in `plot`'s toolpath (one scale on both axes), in
/// `verify --plot`'s view around a difference on that arc (X magnified: an ellipse), and in
/// a roughing cycle's view of its cuts, sweeps the arc the program cuts.
#[test]
fn every_corpus_arc_is_drawn_as_the_program_turns_it() {
    let (mut arcs, mut magnified, mut cycles) = (0, 0, 0);
    for case in common::corpus_cases() {
        if common::reader_refuses(&case) {
            continue;
        }
        let program = common::parse_case(&case);
        let segments = ncthread::sim::simulate(&program).segments;
        let moves: Vec<Move> = segments.iter().map(Move::of).collect();
        let svg = ncthread::plot::plot(&case.name, &segments, None);
        arcs += check_arcs(&paths(&svg), &moves, &case.name);
        // A difference on each arc: `verify --plot` draws the view around it with X
        // magnified; the paths after its clip are that view's (the source's moves first).
        for s in segments
            .iter()
            .filter(|s| Move::of(s).drawn() && matches!(s.motion, Motion::Arc { .. }))
        {
            let d = ncthread::sim::Difference {
                index: 0,
                left: Some(*s),
                right: Some(*s),
                what: "a test".into(),
            };
            let svg = ncthread::plot::verify_plot(
                &case.name,
                "left",
                &segments,
                "right",
                &segments,
                Some(&d),
            );
            let detail = svg
                .split("<clipPath id=\"detail\">")
                .nth(1)
                .expect("a view around the difference");
            let here = format!("{} (verify, around {})", case.name, s.to_text());
            check_arcs(&paths(detail), &moves, &here);
            magnified += 1;
        }
        // A roughing cycle's view: its moves from the first cut to the last, X or Z
        // magnified.
        for op in ncthread::explain::explain(&program, &Default::default()) {
            let (Some(a), Some(b)) = (
                op.moves.iter().position(|m| m.cut.is_some()),
                op.moves.iter().rposition(|m| m.cut.is_some()),
            ) else {
                continue;
            };
            let svg = ncthread::plot::plot(&case.name, &segments, Some(&op));
            let detail = svg
                .split("<clipPath id=\"passes\">")
                .nth(1)
                .expect("a view of the cuts");
            let cuts: Vec<Move> = op.moves[a..=b].iter().map(Move::of_cycle).collect();
            let here = format!("{} (operation {})", case.name, op.number);
            cycles += check_arcs(&paths(detail), &cuts, &here);
        }
    }
    assert!(
        arcs >= 30 && magnified == arcs && cycles >= 5,
        "{arcs} arcs, {magnified} magnified, {cycles} in cycles"
    );
    println!("{arcs} arcs checked, in cycles' views {cycles}");
}

#[test]
fn the_endpoint_to_centre_conversion_is_the_specification_s() {
    // A quarter of the unit circle around the origin, from (1, 0) to (0, 1): the short way
    // turns +90° (sweep 1), the long way −270° (sweep 0).
    let short = endpoint_to_centre((1.0, 0.0), (0.0, 1.0), 1.0, 1.0, 0.0, false, true);
    assert!(short.cx.abs() < 1e-9 && short.cy.abs() < 1e-9, "{short:?}");
    assert!((short.sweep - 90.0).abs() < 1e-9, "{short:?}");
    let long = endpoint_to_centre((1.0, 0.0), (0.0, 1.0), 1.0, 1.0, 0.0, true, false);
    assert!(long.cx.abs() < 1e-9 && long.cy.abs() < 1e-9, "{long:?}");
    assert!((long.sweep + 270.0).abs() < 1e-9, "{long:?}");
    // The other centre: the short way with sweep 0 goes around (1, 1).
    let other = endpoint_to_centre((1.0, 0.0), (0.0, 1.0), 1.0, 1.0, 0.0, false, false);
    assert!((other.cx - 1.0).abs() < 1e-9 && (other.cy - 1.0).abs() < 1e-9);
    assert!((other.sweep + 90.0).abs() < 1e-9, "{other:?}");
    // An ellipse twice as wide: its radii are kept, its centre found.
    let e = endpoint_to_centre((2.0, 0.0), (0.0, 1.0), 2.0, 1.0, 0.0, false, true);
    assert!(e.cx.abs() < 1e-9 && e.cy.abs() < 1e-9 && (e.sweep - 90.0).abs() < 1e-9);
    // Radii too small are scaled up (F.6.6): a half circle.
    let h = endpoint_to_centre((-2.0, 0.0), (2.0, 0.0), 1.0, 1.0, 0.0, false, true);
    assert!((h.rx - 2.0).abs() < 1e-9 && h.cx.abs() < 1e-9 && (h.sweep.abs() - 180.0).abs() < 1e-9);
}

/// Whether anything darker than the grid (#e6e6e6) is drawn within `r` px of `(x, y)`.
fn ink(p: &resvg::tiny_skia::Pixmap, (x, y): (f64, f64), r: f64) -> bool {
    let (x0, x1) = ((x - r).floor() as i64, (x + r).ceil() as i64);
    let (y0, y1) = ((y - r).floor() as i64, (y + r).ceil() as i64);
    (y0..=y1).any(|py| {
        (x0..=x1).any(|px| {
            px >= 0
                && py >= 0
                && p.pixel(px as u32, py as u32)
                    .is_some_and(|c| c.alpha() > 0 && c.red().min(c.green()).min(c.blue()) < 170)
        })
    })
}

/// A program point (Z, X as a diameter) in a view's pixels.
fn at(map: &Mapping, z: f64, x: f64) -> (f64, f64) {
    map.px(z, x / 2.0)
}

/// The distance in px from `p` to what a move draws (an arc: its whole circle, which is
/// nearer than or as near as its arc).
fn distance(map: &Mapping, m: &Move, p: (f64, f64)) -> f64 {
    let (a, b) = (mm(m.from).unwrap(), mm(m.to).unwrap());
    let (a, b) = (map.px(a.0, a.1), map.px(b.0, b.1));
    match m.arc {
        Some((centre, _)) => {
            // The circle is an ellipse where the axes' scales differ: measured in mm.
            let (cz, cr) = mm(centre).unwrap();
            let (z0, r0) = mm(m.from).unwrap();
            let radius = (z0 - cz).hypot(r0 - cr);
            let (pz, pr) = ((p.0 - map.ax) / map.kx, (p.1 - map.ay) / map.ky);
            ((pz - cz).hypot(pr - cr) - radius).abs() * map.kx.abs().min(map.ky.abs())
        }
        None => {
            let (dx, dy) = (b.0 - a.0, b.1 - a.1);
            let len2 = dx * dx + dy * dy;
            let t = if len2 == 0.0 {
                0.0
            } else {
                (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / len2).clamp(0.0, 1.0)
            };
            (p.0 - a.0 - t * dx).hypot(p.1 - a.1 - t * dy)
        }
    }
}

/// The point of an arc halfway along it, and five points of its circle off the arc (a sixth,
/// two sixths … five sixths of the way round the other way), in mm (Z, X as a radius).
fn arc_points(m: &Move) -> ((f64, f64), [(f64, f64); 5]) {
    let (centre, clockwise) = m.arc.expect("an arc");
    let ((z0, r0), (z1, r1), (cz, cr)) =
        (mm(m.from).unwrap(), mm(m.to).unwrap(), mm(centre).unwrap());
    let radius = (z0 - cz).hypot(r0 - cr);
    let (a0, a1) = ((r0 - cr).atan2(z0 - cz), (r1 - cr).atan2(z1 - cz));
    // G3 turns from +Z towards +X (a positive angle), G2 the other way.
    let tau = std::f64::consts::TAU;
    let turned = match (m.from == m.to, clockwise) {
        (true, true) => -tau,
        (true, false) => tau,
        (false, true) => -(a0 - a1).rem_euclid(tau),
        (false, false) => (a1 - a0).rem_euclid(tau),
    };
    let mid = a0 + turned / 2.0;
    let point = |a: f64| (cz + radius * a.cos(), cr + radius * a.sin());
    // The rest of the circle, from the arc's end on round to its start.
    let rest = tau - turned.abs();
    let off = |f: f64| point(a1 + turned.signum() * rest * f);
    (point(mid), [1.0, 2.0, 3.0, 4.0, 5.0].map(|k| off(k / 6.0)))
}

/// The whole part of `corpus/iso/part-shaft-m20.ngc` (its header describes each arc: a
/// convex round, a concave fillet, an R6 cove, an R5 bead), rendered: each arc's middle is
/// drawn and the rest of its circle is not. Drawn the long way round, it was the other way
/// about.
#[test]
fn the_shaft_s_arcs_are_drawn_the_short_way_in_the_picture() {
    let case = common::corpus_cases()
        .into_iter()
        .find(|c| c.name == "iso/part-shaft-m20")
        .unwrap();
    let program = common::parse_case(&case);
    let segments = ncthread::sim::simulate(&program).segments;
    let moves: Vec<Move> = segments.iter().map(Move::of).collect();
    let svg = ncthread::plot::plot(&case.name, &segments, None);
    let (_, map) = view_map(&paths(&svg), &moves, &case.name);
    let map = map.unwrap();
    let pixmap = render(&svg);
    let arcs: Vec<&Move> = moves.iter().filter(|m| m.arc.is_some()).collect();
    assert_eq!(arcs.len(), 4, "the header's four arcs");
    for m in arcs {
        let ((mz, mr), off) = arc_points(m);
        assert!(
            ink(&pixmap, map.px(mz, mr), 1.5),
            "{m:?}: its middle is not drawn"
        );
        // The rest of its circle is not drawn, except where another move passes.
        let mut looked = 0;
        for (z, r) in off {
            let p = map.px(z, r);
            if moves
                .iter()
                .filter(|o| o.drawn() && !std::ptr::eq(*o, m))
                .any(|o| distance(&map, o, p) < 6.0)
            {
                continue;
            }
            assert!(
                !ink(&pixmap, p, 2.0),
                "{m:?}: its circle is drawn at Z{z} r{r}"
            );
            looked += 1;
        }
        assert!(
            looked >= 2,
            "{m:?}: the rest of its circle is too busy to look at"
        );
    }
    // The cove's bottom (Ø38 − 2·(6 − 4.4721) = Ø34.944 at Z-44) and the bead's top (Ø40 at
    // Z-53, on the rough turned Ø40) are drawn; the cove's circle's top (Ø58.944) is not.
    assert!(ink(&pixmap, at(&map, -44.0, 34.9443), 1.5));
    assert!(ink(&pixmap, at(&map, -53.0, 40.0), 1.5));
    assert!(!ink(&pixmap, at(&map, -44.0, 58.9443), 2.0));
}

/// `verify --plot` of the hand conversion with pass 5 off: in the view around the difference,
/// nothing crosses the band between pass 4 and pass 5 along the thread. The rapids between
/// passes (out to Ø37, back to Z4.5, in to the next pass) were merged by normalising into one
/// diagonal across it.
#[test]
fn verify_plot_draws_rapids_as_the_machine_moves() {
    let read = |path: &str| {
        let text = std::fs::read_to_string(common::root().join(path)).unwrap();
        ncthread::source::SourceFile::new(path, text)
    };
    let src = read("corpus/nc31/g31-m36x1.5.nc");
    let hand = read("corpus/iso/m36x1.5-by-hand-pass5-off.ngc");
    let options = ncthread::ConvertOptions {
        from: ncthread::dialect::nc31::ID,
        to: ncthread::dialect::iso::ID,
        profile: Default::default(),
        unsupported: ncthread::Unsupported::Error,
        renumber: Default::default(),
        round: false,
        nc31_comments: false,
    };
    let v = ncthread::verify(&src, &options, Some(&hand), None);
    let ncthread::Outcome::Different(d) = &v.outcome else {
        panic!("pass 5 is off: {:?}", v.outcome)
    };
    let svg = ncthread::plot::verify_plot("t", "a", &v.left_moves, "b", &v.right_moves, Some(d));
    let detail = svg.split("<clipPath id=\"detail\">").nth(1).unwrap();
    let moves: Vec<Move> = v.left_moves.iter().map(Move::of).collect();
    let (_, map) = view_map(&paths(detail), &moves, "the view around the difference");
    let map = map.unwrap();
    let pixmap = render(&svg);
    // Pass 5 (Ø34.255 here, Ø34.275 there) and pass 4 (Ø34.455) are drawn at Z-20 …
    for x in [34.455, 34.275, 34.255] {
        assert!(ink(&pixmap, at(&map, -20.0, x), 1.5), "a pass at Ø{x}");
    }
    // … and nothing between them, anywhere along the thread.
    let (top, bottom) = (
        at(&map, -20.0, 34.455).1 + 3.0,
        at(&map, -20.0, 34.275).1 - 3.0,
    );
    assert!(bottom - top > 10.0, "the band is {} px", bottom - top);
    for z in [-40.0, -30.0, -20.0, -10.0, 0.0] {
        let mut y = top;
        while y <= bottom {
            let x = at(&map, z, 34.0).0;
            assert!(
                !ink(&pixmap, (x, y), 0.5),
                "something crosses at Z{z}, y {y}"
            );
            y += 1.0;
        }
    }
}

/// A roughing cycle's view of its cuts (`plot --operation 1` of G71 with G70): the last cut
/// follows the contour (its arc is drawn), not a diagonal from its start to its end.
#[test]
fn a_roughing_cut_is_drawn_along_its_moves() {
    let case = common::corpus_cases()
        .into_iter()
        .find(|c| c.name == "iso/roughing-g71-g70-shaft")
        .unwrap();
    let program = common::parse_case(&case);
    let segments = ncthread::sim::simulate(&program).segments;
    let ops = ncthread::explain::explain(&program, &Default::default());
    let op = &ops[0];
    let (a, b) = (
        op.moves.iter().position(|m| m.cut.is_some()).unwrap(),
        op.moves.iter().rposition(|m| m.cut.is_some()).unwrap(),
    );
    let cuts: Vec<Move> = op.moves[a..=b].iter().map(Move::of_cycle).collect();
    let svg = ncthread::plot::plot(&case.name, &segments, Some(op));
    let detail = svg.split("<clipPath id=\"passes\">").nth(1).unwrap();
    let (_, map) = view_map(&paths(detail), &cuts, "the view of the cuts");
    let map = map.unwrap();
    let pixmap = render(&svg);
    let last = op.passes.last().unwrap();
    let (Some((x0, z0)), Some((x1, z1))) = (last.start.known(), last.end.known()) else {
        panic!("the last cut's ends")
    };
    let (x0, z0, x1, z1) = (
        x0.to_mm_f64(),
        z0.to_mm_f64(),
        x1.to_mm_f64(),
        z1.to_mm_f64(),
    );
    // The straight line from the last cut's start to its end is not drawn …
    for t in [0.4, 0.5, 0.6] {
        let (z, x) = (z0 + (z1 - z0) * t, x0 + (x1 - x0) * t);
        assert!(
            !ink(&pixmap, at(&map, z, x), 2.0),
            "a diagonal at Z{z} Ø{x}"
        );
    }
    // … its arc is.
    let arc = cuts
        .iter()
        .rev()
        .find(|m| m.arc.is_some())
        .expect("the contour's arc");
    let ((mz, mr), _) = arc_points(arc);
    assert!(ink(&pixmap, map.px(mz, mr), 1.5), "the arc's middle");
}

/// README's pictures of a whole part and of a roughing cycle: their commands, as printed,
/// write the SVGs kept in docs/, and the PNGs beside them are those SVGs at 1.5 times their
/// size (`rsvg-convert -z 1.5`, as README says).
#[test]
fn readme_pictures_are_current() {
    let readme = std::fs::read_to_string(common::root().join("README.md")).unwrap();
    for (command, svg, png) in [
        (
            "ncthread plot corpus/iso/part-shaft-m20.ngc --from iso -o shaft.svg",
            "docs/plot-part-shaft-m20.svg",
            "docs/plot-part-shaft-m20.png",
        ),
        (
            "ncthread plot corpus/iso/roughing-g71-g70-shaft.ngc --from iso --operation 1 -o g71.svg",
            "docs/plot-roughing-g71-g70-shaft.svg",
            "docs/plot-roughing-g71-g70-shaft.png",
        ),
    ] {
        assert!(
            readme.contains(&format!("\n{command}\n")),
            "README lacks `{command}`"
        );
        assert!(readme.contains(&format!("]({png})")), "README shows {png}");
        let dir = tempfile::tempdir().unwrap();
        let written = dir.path().join("out.svg");
        let mut args: Vec<&str> = command.split(' ').skip(1).collect();
        let o = args.iter().position(|a| *a == "-o").unwrap();
        args[o + 1] = written.to_str().unwrap();
        let out = common::ncthread(&args, None);
        assert_eq!(out.status.code(), Some(0), "{}", common::text(&out.stderr));
        let kept = std::fs::read_to_string(common::root().join(svg)).unwrap();
        assert!(
            std::fs::read_to_string(&written).unwrap() == kept,
            "{svg} is stale: ncthread {} -o {svg}, then rsvg-convert -z 1.5 -b white {svg} -o {png}",
            args[..o].join(" ")
        );
        // The PNG's size (its IHDR) is the SVG's × 1.5.
        let size = |attr: &str| -> f64 {
            let at = kept.find(&format!(" {attr}=\"")).unwrap() + attr.len() + 3;
            kept[at..at + kept[at..].find('"').unwrap()]
                .parse()
                .unwrap()
        };
        let bytes = std::fs::read(common::root().join(png)).unwrap();
        assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "{png} is a PNG");
        let be = |i: usize| u32::from_be_bytes(bytes[i..i + 4].try_into().unwrap()) as f64;
        assert_eq!(
            (be(16), be(20)),
            (size("width") * 1.5, size("height") * 1.5),
            "{png}: rsvg-convert -z 1.5 -b white {svg} -o {png}"
        );
    }
}

/// A program with blocks kept as written (a FANUC cycle, no machine model) says in its
/// heading how many it does not draw; a program without them keeps the usual heading.
#[test]
fn a_plot_says_how_many_kept_blocks_it_does_not_draw() {
    let heading = |path: &str| {
        let text = std::fs::read_to_string(common::root().join(path)).unwrap();
        let src = ncthread::source::SourceFile::new(path, text);
        let (program, _) = ncthread::parse(
            &src,
            ncthread::dialect::fanuc::ID,
            &Default::default(),
            ncthread::Unsupported::Error,
        );
        let sim = ncthread::sim::simulate(&program);
        ncthread::plot::plot(path, &sim.segments, None)
    };
    // G71 U R, G71 P Q, the contour's 6 blocks, G70 and G28.
    let kept = heading("corpus/fanuc/kept-g71-g70-g28-part.nc");
    assert!(
        kept.contains("not drawn: 10 blocks kept as written"),
        "{kept}"
    );
    let plain = heading("corpus/fanuc/part-shaft-two-tools.nc");
    assert!(!plain.contains("not drawn"), "{plain}");
    assert!(plain.contains("threads coloured by pass"));
}

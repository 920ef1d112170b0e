//! The pictures against the motion they draw (issue 30): every arc of every corpus program is
//! read back out of the SVG with the SVG specification's own endpoint-to-centre conversion
//! and held against the simulated arc; and the pictures, rendered with resvg, have ink where
//! the program moves and none where it does not.
mod common;

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

impl Mapping {
    /// From pairs of (program point in mm, pixel point): the two furthest apart along each
    /// axis fix it; every pair must then agree to the SVG's two decimals.
    fn fit(pairs: &[((f64, f64), (f64, f64))], here: &str) -> Option<Mapping> {
        let axis = |get: fn(&((f64, f64), (f64, f64))) -> (f64, f64)| {
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
fn mm(p: ncthread::ir::Pos) -> Option<(f64, f64)> {
    let (x, z) = p.known()?;
    Some((z.to_mm_f64(), x.to_mm_f64() / 2.0))
}

/// Whether the picture draws `s`: a move with both ends known, an arc even when it ends
/// where it starts (a full circle).
fn drawn(s: &Segment) -> bool {
    s.from.known().is_some()
        && s.to.known().is_some()
        && (s.from != s.to || matches!(s.motion, Motion::Arc { .. }))
}

/// Holds each arc of `segments` drawn among `drawn_paths` (the paths of one view, the
/// drawable segments first and in order) to the arc the program moves: centre, radius,
/// direction and the angle it turns. Returns how many arcs were checked.
fn check_arcs(drawn_paths: &[(String, String)], segments: &[Segment], here: &str) -> usize {
    let moves: Vec<&Segment> = segments.iter().filter(|s| drawn(s)).collect();
    assert!(
        drawn_paths.len() >= moves.len(),
        "{here}: {} paths for {} moves",
        drawn_paths.len(),
        moves.len()
    );
    let mut pairs = Vec::new();
    for (s, (d, title)) in moves.iter().zip(drawn_paths) {
        assert_eq!(
            title,
            s.to_text().trim(),
            "{here}: the paths follow the moves"
        );
        let cmds = commands(d);
        let first = &cmds[0].1;
        let last = &cmds.last().unwrap().1;
        let end = (last[last.len() - 2], last[last.len() - 1]);
        pairs.push((mm(s.from).unwrap(), (first[0], first[1])));
        pairs.push((mm(s.to).unwrap(), end));
    }
    let arcs: Vec<_> = moves
        .iter()
        .zip(drawn_paths)
        .filter(|(s, _)| matches!(s.motion, Motion::Arc { .. }))
        .collect();
    if arcs.is_empty() {
        return 0;
    }
    let map = Mapping::fit(&pairs, here)
        .unwrap_or_else(|| panic!("{here}: the moves do not span the view"));
    for (s, (d, _)) in arcs {
        let Motion::Arc {
            centre, clockwise, ..
        } = s.motion
        else {
            unreachable!()
        };
        let here = format!("{here}: {}", s.to_text());
        let ((z0, r0), (z1, r1), (cz, cr)) = (
            mm(s.from).unwrap(),
            mm(s.to).unwrap(),
            mm(centre).expect("a known centre"),
        );
        let radius = (z0 - cz).hypot(r0 - cr);
        // The program's arc: G3 turns counter-clockwise seen from +Y, and Z × X = Y, so it
        // turns from +Z towards +X: a positive angle in (Z, X); G2 a negative one.
        let (a0, a1) = ((r0 - cr).atan2(z0 - cz), (r1 - cr).atan2(z1 - cz));
        let turned = if s.from == s.to {
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
        let r_px = radius * map.kx.abs().min(map.ky.abs());
        let centre_tol = (0.05 + (0.02 * r_px).sqrt()) / map.kx.abs().min(map.ky.abs());
        let angle_tol =
            svg.pieces as f64 * (0.5 + (2.0 * (0.02 / r_px.max(0.01)).sqrt()).to_degrees());
        assert_eq!(
            clockwise_drawn,
            clockwise,
            "{here}: drawn {} ({d})",
            if clockwise_drawn { "G2" } else { "G3" }
        );
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
    moves
        .iter()
        .filter(|s| matches!(s.motion, Motion::Arc { .. }))
        .count()
}

/// Every arc of every corpus program, in `plot`'s toolpath (one scale on both axes) and in
/// `verify --plot`'s view around a difference on that arc (X magnified: an ellipse), sweeps
/// the arc the program cuts.
#[test]
fn every_corpus_arc_is_drawn_as_the_program_turns_it() {
    let (mut arcs, mut magnified) = (0, 0);
    for case in common::corpus_cases() {
        if common::reader_refuses(&case) {
            continue;
        }
        let program = common::parse_case(&case);
        let segments = ncthread::sim::simulate(&program).segments;
        let svg = ncthread::plot::plot(&case.name, &segments, None);
        arcs += check_arcs(&paths(&svg), &segments, &case.name);
        // A difference on each arc: `verify --plot` draws the view around it with X
        // magnified; the paths after its clip are that view's (the source's moves first).
        for s in segments
            .iter()
            .filter(|s| drawn(s) && matches!(s.motion, Motion::Arc { .. }))
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
            check_arcs(&paths(detail), &segments, &here);
            magnified += 1;
        }
    }
    assert!(arcs >= 30 && magnified == arcs, "{arcs} arcs, {magnified}");
    println!("{arcs} arcs checked");
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

//! LinuxCNC's lathe roughing and finishing cycles (G70, G71, G71.1, G71.2, G72, G72.1,
//! G72.2): the contour of the cycle's subroutine becomes the moves LinuxCNC makes.
//!
//! A port of `interp_g7x.cc` as the rs274 that ncthread checks with builds it (LinuxCNC
//! 2.9.0~pre1, git f1270d6ed7): the same geometry in the same order of floating-point
//! operations, in program units with X a radius and Z the real part of a complex number,
//! so that its tolerances (1e-6, 1e-3, 1e-2) mean what they mean there. The moves are
//! rounded onto ncthread's grid once, by the reader. Where the C++ has undefined behaviour
//! (an element before the first) or can loop without end, the port refuses with a message
//! instead. **\[evidence\]** LinuxCNC `src/emc/rs274ngc/interp_g7x.cc`.

use std::ops::{Add, AddAssign, Div, Mul, Neg, Sub};

/// A point of the XZ plane: `re` is Z, `im` is X (a radius), in program units.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct C {
    pub re: f64,
    pub im: f64,
}

const I: C = C { re: 0.0, im: 1.0 };

impl C {
    pub const fn new(re: f64, im: f64) -> C {
        C { re, im }
    }
    fn conj(self) -> C {
        C::new(self.re, -self.im)
    }
    /// `std::abs`: the modulus (hypot).
    fn abs(self) -> f64 {
        self.re.hypot(self.im)
    }
    /// `std::norm`: the squared modulus.
    pub fn norm(self) -> f64 {
        self.re * self.re + self.im * self.im
    }
    fn scale(self, s: f64) -> C {
        C::new(s * self.re, s * self.im)
    }
    fn over(self, s: f64) -> C {
        C::new(self.re / s, self.im / s)
    }
}

impl Add for C {
    type Output = C;
    fn add(self, o: C) -> C {
        C::new(self.re + o.re, self.im + o.im)
    }
}
impl AddAssign for C {
    fn add_assign(&mut self, o: C) {
        *self = *self + o;
    }
}
impl Sub for C {
    type Output = C;
    fn sub(self, o: C) -> C {
        C::new(self.re - o.re, self.im - o.im)
    }
}
impl Neg for C {
    type Output = C;
    fn neg(self) -> C {
        C::new(-self.re, -self.im)
    }
}
impl Mul for C {
    type Output = C;
    fn mul(self, o: C) -> C {
        C::new(
            self.re * o.re - self.im * o.im,
            self.re * o.im + self.im * o.re,
        )
    }
}
impl Div for C {
    type Output = C;
    /// Smith's division, as libgcc's `__divdc3` computes it for finite values.
    fn div(self, o: C) -> C {
        let (a, b, c, d) = (self.re, self.im, o.re, o.im);
        if c.abs() < d.abs() {
            let ratio = c / d;
            let denom = c * ratio + d;
            C::new((a * ratio + b) / denom, (b * ratio - a) / denom)
        } else {
            let ratio = d / c;
            let denom = d * ratio + c;
            C::new((b * ratio + a) / denom, (b - a * ratio) / denom)
        }
    }
}

const TOLERANCE: f64 = 1e-6;

/// The most steps (passes, offsets, pocket moves) one cycle may take before ncthread calls
/// it endless: LinuxCNC's own loops can spin for ever on some contours.
const STEP_LIMIT: u64 = 2_000_000;

/// How a refusal begins when the cycle would not end (LinuxCNC's interpreter loops for ever
/// on such a contour; LinuxCNC fixed some of these loops after 2.9.0~pre1).
pub const ENDLESS: &str = "the cycle does not end on this contour";

/// A move the cycle makes, in program units (Z, X radius).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Out {
    Rapid(C),
    Feed(C),
    Arc { ccw: bool, centre: C, end: C },
}

/// One element of the contour as LinuxCNC's cycle reads it from the subroutine.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Element {
    Line {
        start: C,
        end: C,
    },
    Arc {
        ccw: bool,
        start: C,
        centre: C,
        end: C,
    },
    /// `A`: a rounded corner of this radius at the point.
    Fillet {
        radius: f64,
        at: C,
    },
    /// `C`: a chamfer of this size at the point.
    Chamfer {
        size: f64,
        at: C,
    },
}

/// The cycle and its words (LinuxCNC's defaults where a word is not written).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Cycle {
    /// G70: `passes` (P) from `first` (D) to `last` (E) distance from the contour.
    Finish { first: f64, last: f64, passes: f64 },
    /// G71 (`facing` false) or G72: `variant` 0 (pockets too), 1 (no pockets), 2 (pockets
    /// only); `u`, `w` the stock left in X and Z, `d` the distance left, `i` the depth of
    /// cut, `r` the retract.
    Rough {
        facing: bool,
        variant: u8,
        u: f64,
        w: f64,
        d: f64,
        i: f64,
        r: f64,
    },
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    Straight,
    Round { ccw: bool, centre: C },
}

/// What a corner element does when the contour is finished (LinuxCNC's `fillet_segment`
/// and `chamfer_segment`; a copy loses it, as `dup()` slices them into plain segments).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Corner {
    None,
    Fillet,
    Chamfer,
}

#[derive(Clone, Copy, Debug, PartialEq)]
struct Seg {
    kind: Kind,
    start: C,
    end: C,
    finish: f64,
    corner: Corner,
}

type Fail = String;

fn fail<T>(message: impl Into<String>) -> Result<T, Fail> {
    Err(message.into())
}

/// The step budget shared by every loop of one cycle.
struct Budget(u64);

impl Budget {
    fn spend(&mut self) -> Result<(), Fail> {
        self.0 += 1;
        if self.0 > STEP_LIMIT {
            return fail(format!("{ENDLESS} {STEP_LIMIT} steps"));
        }
        Ok(())
    }
}

impl Seg {
    fn straight(start: C, end: C) -> Seg {
        Seg {
            kind: Kind::Straight,
            start,
            end,
            finish: 0.0,
            corner: Corner::None,
        }
    }

    fn round(ccw: bool, start: C, centre: C, end: C) -> Seg {
        Seg {
            kind: Kind::Round { ccw, centre },
            start,
            end,
            finish: 0.0,
            corner: Corner::None,
        }
    }

    /// `dup()`: the copy is a plain segment.
    fn dup(&self) -> Seg {
        Seg {
            corner: Corner::None,
            ..*self
        }
    }

    fn radius(&self) -> f64 {
        match self.kind {
            Kind::Straight => (self.start - self.end).abs(),
            Kind::Round { centre, .. } => (self.start - self.end)
                .abs()
                .min((self.start - centre).abs()),
        }
    }

    fn monotonic(&self) -> bool {
        match self.kind {
            Kind::Straight => (self.end - self.start).re <= 1e-3,
            Kind::Round { ccw, centre } => {
                if self.finish != 0.0 {
                    return true;
                }
                let entry = (self.start - centre).im;
                let exit = (self.end - centre).im;
                let dz = (self.end - self.start).re;
                if ccw {
                    entry >= -1e-3 && exit >= -1e-3 && dz <= -1e-3
                } else {
                    entry <= 1e-3 && exit <= 1e-3 && dz <= -1e-3
                }
            }
        }
    }

    fn offset(&mut self, distance: f64) {
        match self.kind {
            Kind::Straight => {
                let d = (I.scale(distance) * (self.start - self.end))
                    .over((self.start - self.end).abs());
                self.start += d;
                self.end += d;
            }
            Kind::Round { ccw, centre } => {
                let r = (self.start - centre).abs();
                let factor = (r + if ccw { 1.0 } else { -1.0 } * distance) / r;
                self.start = (self.start - centre).scale(factor) + centre;
                self.end = (self.end - centre).scale(factor) + centre;
            }
        }
    }

    fn flip_imag(&mut self) {
        if let Kind::Round { ccw, centre } = self.kind {
            self.kind = Kind::Round {
                ccw: !ccw,
                centre: centre.conj(),
            };
        }
        self.start = self.start.conj();
        self.end = self.end.conj();
    }

    fn flip_real(&mut self) {
        if let Kind::Round { ccw, centre } = self.kind {
            self.kind = Kind::Round {
                ccw: !ccw,
                centre: -centre.conj(),
            };
        }
        self.start = -self.start.conj();
        self.end = -self.end.conj();
    }

    fn rotate(&mut self) {
        if let Kind::Round { ccw, centre } = self.kind {
            self.kind = Kind::Round {
                ccw,
                centre: -centre * I,
            };
        }
        self.start = -self.start * I;
        self.end = -self.end * I;
    }

    fn moved(&mut self, d: C) {
        self.start += d;
        self.end += d;
        if let Kind::Round { ccw, centre } = self.kind {
            self.kind = Kind::Round {
                ccw,
                centre: centre + d,
            };
        }
    }

    fn on_segment(&self, ccw: bool, centre: C, p: C) -> bool {
        let a = ((self.start - centre).conj() * (p - centre)).im;
        let b = ((self.end - centre).conj() * (p - centre)).im;
        if ccw {
            a >= -TOLERANCE && b <= TOLERANCE
        } else {
            a <= TOLERANCE && b >= -TOLERANCE
        }
    }

    fn intersection_z(&self, x: f64, is: &mut Vec<f64>) {
        match self.kind {
            Kind::Straight => {
                let (s, e) = (self.start, self.end);
                if s.im.min(e.im) > x + TOLERANCE || s.im.max(e.im) < x - TOLERANCE {
                    return;
                }
                if (s - e).im.abs() < TOLERANCE {
                    is.push(s.re);
                    is.push(e.re);
                } else {
                    is.push((x - s.im) / (e.im - s.im) * (e.re - s.re) + s.re);
                }
            }
            Kind::Round { ccw, centre } => {
                let r = self.start - centre;
                let mut s = -(x - r.abs() - centre.im) * (x + r.abs() - centre.im);
                if s < -TOLERANCE {
                    return;
                }
                if s < 0.0 {
                    s = 0.0;
                }
                s = s.sqrt();
                // `real(center+s)`: s adds to the real part.
                let p1 = C::new(centre.re + s, x);
                if self.on_segment(ccw, centre, p1) {
                    is.push(p1.re);
                }
                let p2 = C::new(centre.re - s, x);
                if self.on_segment(ccw, centre, p2) {
                    is.push(p2.re);
                }
            }
        }
    }

    /// True: not climbing (LinuxCNC's `return 1`).
    fn climb(&self, location: &mut C, out: &mut Sink) -> Result<bool, Fail> {
        match self.kind {
            Kind::Straight => {
                if self.end.im + TOLERANCE < self.start.im {
                    return Ok(true);
                }
                if (*location - self.start).abs() > TOLERANCE {
                    return fail("How did we get here?");
                }
                out.straight_move(self.end);
                *location = self.end;
                Ok(false)
            }
            Kind::Round { ccw: false, centre } => {
                if location.re > centre.re {
                    return Ok(true);
                }
                if (*location - self.end).abs() > 1e-3 {
                    out.circular_move(false, centre, self.end);
                }
                *location = self.end;
                Ok(false)
            }
            Kind::Round { ccw: true, centre } => {
                if location.re < centre.re {
                    return Ok(true);
                }
                let mut ep = self.end;
                if self.end.re < centre.re {
                    ep.re = centre.re;
                    ep.im = centre.im + (self.start - centre).abs();
                }
                if (*location - ep).abs() > 1e-3 {
                    out.circular_move(true, centre, ep);
                }
                *location = ep;
                Ok(true)
            }
        }
    }

    fn climb_only(&self, location: &mut C, out: &mut Sink) {
        match self.kind {
            Kind::Straight => {
                if self.end.im < self.start.im {
                    return;
                }
                let mut is = Vec::new();
                self.intersection_z(location.im, &mut is);
                let Some(&first) = is.first() else {
                    return;
                };
                location.re = first;
                out.straight_move(*location);
                out.straight_move(self.end);
                *location = self.end;
            }
            Kind::Round { ccw, centre } => {
                let mut is = Vec::new();
                self.intersection_z(location.im, &mut is);
                let (Some(&front), Some(&back)) = (is.first(), is.last()) else {
                    return;
                };
                if !ccw {
                    if back > centre.re {
                        return;
                    }
                    location.re = back;
                    out.straight_move(*location);
                    if (*location - self.end).abs() > 1e-3 {
                        out.circular_move(false, centre, self.end);
                    }
                    *location = self.end;
                } else {
                    if front < centre.re {
                        return;
                    }
                    location.re = front;
                    out.straight_move(*location);
                    let mut ep = self.end;
                    if self.end.re < centre.re {
                        ep.re = centre.re;
                        ep.im = centre.im + (self.start - centre).abs();
                    }
                    if (*location - ep).abs() > 1e-3 {
                        out.circular_move(true, centre, ep);
                    }
                    *location = ep;
                }
            }
        }
    }

    /// True: not diving (LinuxCNC's `return 1`).
    fn dive(&self, location: &mut C, x: f64, out: &mut Sink, fast: bool) -> Result<bool, Fail> {
        match self.kind {
            Kind::Straight => {
                if self.start.im <= self.end.im + TOLERANCE {
                    return Ok(true);
                }
                if x < self.end.im {
                    if fast {
                        out.straight_rapid(self.end);
                    } else {
                        out.straight_move(self.end);
                    }
                    *location = self.end;
                    return Ok(false);
                }
                let mut is = Vec::new();
                self.intersection_z(x, &mut is);
                let Some(&front) = is.first() else {
                    return fail("x too large in straight dive");
                };
                let ep = C::new(front, x);
                if fast {
                    out.straight_rapid(ep);
                } else {
                    out.straight_move(ep);
                }
                *location = ep;
                Ok(false)
            }
            Kind::Round { ccw, centre } => {
                if (*location - self.end).abs() < TOLERANCE
                    || (*location - self.end).re <= TOLERANCE
                {
                    *location = self.end;
                    return Ok(false);
                }
                let mut is = Vec::new();
                self.intersection_z(x, &mut is);
                if is.is_empty() {
                    self.intersection_z(x - TOLERANCE, &mut is);
                }
                if ccw {
                    if location.re - TOLERANCE > centre.re {
                        return Ok(true);
                    }
                    match is.last() {
                        Some(&back) if back <= centre.re => {
                            let ep = C::new(back, x);
                            out.circular_move(true, centre, ep);
                            *location = ep;
                        }
                        _ => {
                            out.circular_move(true, centre, self.end);
                            *location = self.end;
                        }
                    }
                    Ok(false)
                } else {
                    if location.re <= centre.re {
                        return Ok(true);
                    }
                    match is.first() {
                        None => {
                            out.circular_move(false, centre, self.end);
                            *location = self.end;
                        }
                        // Hit at the back side only: the pocket lowers x.
                        Some(&front) if front < centre.re => {}
                        Some(&front) => {
                            let ep = C::new(front, x);
                            out.circular_move(false, centre, ep);
                            *location = ep;
                        }
                    }
                    Ok(false)
                }
            }
        }
    }

    /// `corner_finish`: fits this corner between `prev` and `next`, moving their ends;
    /// returns the corner's centre.
    fn corner_finish(&mut self, prev: &mut Seg, next: &mut Seg) -> Result<C, Fail> {
        let mut p = prev.dup();
        let mut n = next.dup();
        p.offset(self.finish);
        n.offset(self.finish);
        if (p.end - n.start).re > 1e-2 {
            self.finish = -self.finish;
            p = prev.dup();
            n = next.dup();
            p.offset(self.finish);
            n.offset(self.finish);
        }
        if (p.end - n.start).re > 1e-2 {
            return fail(format!(
                "Corner finish failed at ({},{})",
                prev.end.re, prev.end.im
            ));
        }
        intersect(&mut p, &mut n)?;
        let centre = (p.end + n.start).over(2.0);
        p.offset(-self.finish);
        n.offset(-self.finish);
        prev.end = p.end;
        self.start = p.end;
        next.start = n.start;
        self.end = n.start;
        Ok(centre)
    }

    fn do_finish(&mut self, prev: &mut Seg, next: &mut Seg) -> Result<(), Fail> {
        match self.corner {
            Corner::None => {}
            Corner::Chamfer => {
                self.corner_finish(prev, next)?;
            }
            Corner::Fillet => {
                let centre = self.corner_finish(prev, next)?;
                let ccw = (self.start - centre).im > 0.0 || (self.end - centre).im > 0.0;
                self.kind = Kind::Round { ccw, centre };
                self.finish = 0.0;
            }
        }
        Ok(())
    }
}

/// `p->intersect(n)`: corrects the end of `p` and the start of `n` to where they meet.
fn intersect(p: &mut Seg, n: &mut Seg) -> Result<(), Fail> {
    match (p.kind, n.kind) {
        (Kind::Straight, Kind::Straight) => {
            let rot = (n.start - n.end).conj().over((n.start - n.end).abs());
            let ps = (p.start - n.end) * rot;
            let pe = (p.end - n.end) * rot;
            if (ps - pe).im == 0.0 {
                return fail("Cannot intersect parallel lines");
            }
            let f = ps.im / (ps - pe).im;
            let is = (ps + (pe - ps).scale(f)) / rot + n.end;
            n.start = is;
            p.end = is;
        }
        // An arc followed by a straight.
        (Kind::Round { centre, .. }, Kind::Straight) => {
            if (n.start - p.end).abs() < TOLERANCE {
                return Ok(());
            }
            let rot = (n.start - n.end).conj().over((n.start - n.end).abs());
            let pe = (p.end - n.end) * rot;
            let pc = (centre - n.end) * rot;
            let (s1, s2) = line_circle(pc, pe, rot, n.end);
            let pick = if (n.start - s1).abs() < (n.start - s2).abs() {
                s1
            } else {
                s2
            };
            n.start = pick;
            p.end = pick;
        }
        // A straight followed by an arc.
        (Kind::Straight, Kind::Round { centre, .. }) => {
            if (n.start - p.end).abs() < TOLERANCE {
                return Ok(());
            }
            let rot = (p.start - p.end).conj().over((p.start - p.end).abs());
            let pe = (n.end - p.end) * rot;
            let pc = (centre - p.end) * rot;
            let (s1, s2) = line_circle(pc, pe, rot, p.end);
            let pick = if (n.start - s1).abs() < (n.start - s2).abs() {
                s1
            } else {
                s2
            };
            n.start = pick;
            p.end = pick;
        }
        (Kind::Round { centre: pc, .. }, Kind::Round { centre, .. }) => {
            let a = (n.start - centre).abs();
            let b = (p.start - pc).abs();
            let c = (centre - pc).abs();
            let cos_b = (c * c + a * a - b * b) / 2.0 / a / c;
            let cos_b2 = (cos_b * cos_b).min(1.0);
            let rot = C::new(cos_b, (1.0 - cos_b2).sqrt());
            let is = (rot * (pc - centre)).over(c).scale(a) + centre;
            p.end = is;
            n.start = is;
        }
    }
    Ok(())
}

/// The two points where the rotated line meets the rotated circle, back in place.
fn line_circle(pc: C, pe: C, rot: C, origin: C) -> (C, C) {
    let mut b = (pc - pe).norm() - pc.im * pc.im;
    if b < 0.0 {
        b = 0.0;
    } else {
        b = b.sqrt();
    }
    let s1 = C::new(pc.re + b, 0.0) / rot + origin;
    let s2 = C::new(pc.re - b, 0.0) / rot + origin;
    (s1, s2)
}

/// The moves made, through the flip of the profile (`swapped_motion`) and LinuxCNC's
/// `motion_machine` (an arc to where the tool already is, within 0.0001, is not made).
struct Sink {
    flip: u8,
    moves: Vec<Out>,
    current: C,
}

impl Sink {
    fn map(&self, p: C) -> C {
        match self.flip {
            0 => p,
            1 => -p.conj(),
            2 => p.conj(),
            3 => -p,
            4 => I * p,
            5 => (I * p).conj(),
            6 => -(I * p).conj(),
            _ => -I * p,
        }
    }
    fn mirrored(&self) -> bool {
        matches!(self.flip, 1 | 2 | 5 | 6)
    }
    fn straight_move(&mut self, end: C) {
        let end = self.map(end);
        self.moves.push(Out::Feed(end));
        self.current = end;
    }
    fn straight_rapid(&mut self, end: C) {
        let end = self.map(end);
        self.moves.push(Out::Rapid(end));
        self.current = end;
    }
    fn circular_move(&mut self, ccw: bool, centre: C, end: C) {
        let ccw = ccw != self.mirrored();
        let (centre, end) = (self.map(centre), self.map(end));
        // TOLERANCE_EQUAL of `equal()`.
        if (self.current.re - end.re).abs() < 0.0001 && (self.current.im - end.im).abs() < 0.0001 {
            return;
        }
        self.moves.push(Out::Arc { ccw, centre, end });
        self.current = end;
    }
}

#[derive(Clone)]
struct Path {
    segs: Vec<Seg>,
    flip: u8,
}

impl Path {
    fn rotate(&mut self) {
        for s in &mut self.segs {
            s.rotate();
        }
        self.flip ^= 4;
    }

    /// Turns the profile so that Z and X decrease along it.
    fn swap(&mut self) -> Result<(), Fail> {
        let (Some(front), Some(back)) = (self.segs.first(), self.segs.last()) else {
            return fail("the contour is empty");
        };
        let d = front.end - back.end;
        if d.im > 0.0 {
            for s in &mut self.segs {
                s.flip_imag();
            }
            self.flip ^= 2;
        }
        if d.re < 0.0 {
            for s in &mut self.segs {
                s.flip_real();
            }
            self.flip ^= 1;
        }
        Ok(())
    }

    fn monotonic(&mut self) -> Result<(), Fail> {
        let Some(front) = self.segs.first_mut() else {
            return fail("the contour is empty");
        };
        if (front.end - front.start).re > 0.0 {
            front.start.re = front.end.re;
        }
        if self.segs.iter().any(|s| !s.monotonic()) {
            return fail("Not monotonic");
        }
        Ok(())
    }

    fn do_finish(&mut self) -> Result<(), Fail> {
        let n = self.segs.len();
        for h in 1..n.saturating_sub(1) {
            let (before, rest) = self.segs.split_at_mut(h);
            let (here, after) = rest.split_at_mut(1);
            here[0].do_finish(&mut before[h - 1], &mut after[0])?;
        }
        self.segs.retain(|s| s.radius() >= 1e-3);
        Ok(())
    }

    fn add_distance(&mut self, distance: f64, budget: &mut Budget) -> Result<(), Fail> {
        if self.segs.len() < 2 {
            return fail("the contour has no element left to offset");
        }
        let v1 = self.segs[0].end - self.segs[0].start;
        let v2 = self.segs[self.segs.len() - 1].start - self.segs[0].start;
        let angle = v1 / v2;
        let distance = if angle.im < 0.0 { -distance } else { distance };
        let of = self.segs.remove(0);
        let mut current_distance = 0.0;
        while current_distance != distance {
            budget.spend()?;
            let mut max_distance: f64 = 1e9;
            for s in &self.segs {
                max_distance = max_distance.min(s.radius() / 2.0);
            }
            max_distance = max_distance.min((distance - current_distance).abs());
            if distance < 0.0 {
                max_distance = -max_distance;
            }
            for s in &mut self.segs {
                s.offset(max_distance);
            }
            self.segs.retain(|s| s.radius() >= 1e-3);
            if self.segs.is_empty() {
                return fail("the contour vanishes when it is offset");
            }
            self.connect(distance, max_distance, budget)?;
            self.repair(budget)?;
            current_distance += max_distance;
        }
        for p in 0..self.segs.len().saturating_sub(1) {
            let mid = (self.segs[p].end + self.segs[p + 1].start).over(2.0);
            self.segs[p].end = mid;
            self.segs[p + 1].start = mid;
        }
        let mut of = of;
        of.end = self.segs[0].start;
        self.segs.insert(0, of);
        Ok(())
    }

    /// Connecting arcs where the segments, just offset by `max_distance` on the way to
    /// `distance`, no longer meet.
    fn connect(
        &mut self,
        distance: f64,
        max_distance: f64,
        budget: &mut Budget,
    ) -> Result<(), Fail> {
        let mut p = 0;
        while p + 1 < self.segs.len() {
            budget.spend()?;
            let n = p + 1;
            if (self.segs[p].end - self.segs[n].start).re > 1e-2 {
                let mut s = self.segs[p].dup();
                let mut e = self.segs[n].dup();
                s.offset(-max_distance);
                e.offset(-max_distance);
                let centre = (s.end + e.start).over(2.0);
                let arc = Seg::round(distance > 0.0, self.segs[p].end, centre, self.segs[n].start);
                self.segs.insert(n, arc);
                p += 1;
            }
            p += 1;
        }
        Ok(())
    }

    /// Removes what the offset left not monotonic or vanishing, and joins the rest where
    /// neighbours cross.
    fn repair(&mut self, budget: &mut Budget) -> Result<(), Fail> {
        let mut p = 0;
        while p + 1 < self.segs.len() {
            budget.spend()?;
            if !self.segs[p].monotonic() {
                // LinuxCNC removes the shorter of this and the one before, from the
                // start again ("Oops"); before the first there is nothing.
                if p == 0 {
                    return fail("Not monotonic after the offset of the first element");
                }
                if self.segs[p].radius() < self.segs[p - 1].radius() {
                    self.segs.remove(p);
                } else {
                    self.segs.remove(p - 1);
                }
                p = 0;
                if self.segs.len() < 2 {
                    return fail("the contour vanishes when it is offset");
                }
            }
            if self.segs[p].radius() < 1e-3 {
                self.segs.remove(p);
                p = 0;
                if self.segs.len() < 2 {
                    return fail("the contour vanishes when it is offset");
                }
            } else {
                let (a, b) = self.segs.split_at_mut(p + 1);
                intersect(&mut a[p], &mut b[0])?;
            }
            p += 1;
        }
        Ok(())
    }
}

/// The moves of one cycle: `start` is where the cycle starts (after its rapid to the
/// block's X and Z), `contour` the elements its subroutine made.
pub fn run(cycle: &Cycle, start: C, contour: &[Element]) -> Result<Vec<Out>, Fail> {
    let segs = segments_of(contour);
    if segs.len() < 2 {
        return fail("the contour has fewer than two elements");
    }
    let mut path = Path { segs, flip: 0 };
    let mut budget = Budget(0);
    let mut out = Sink {
        flip: 0,
        moves: Vec::new(),
        current: start,
    };
    match *cycle {
        Cycle::Finish {
            first,
            last,
            passes,
        } => {
            path.finish_passes(start, (first, last, passes), &mut out, &mut budget)?;
        }
        Cycle::Rough {
            facing,
            variant,
            u,
            w,
            d,
            i,
            r,
        } => {
            path.rough_contour(start, facing, d, C::new(w, u), &mut budget)?;
            out.flip = path.flip;
            let delta = i.max(2.0 * TOLERANCE);
            let escape = C::new(1.0, 1.0).scale(r);
            let first = path.segs[0].start;
            out.straight_rapid(first);
            let back = path.segs[path.segs.len() - 1].end;
            if back.im < first.im {
                let ep = C::new(back.re, first.im);
                path.segs.push(Seg::straight(back, ep));
            }
            let mut pocket_starts = vec![first];
            pocket(
                &path.segs,
                variant,
                first,
                0,
                &mut out,
                &mut pocket_starts,
                delta,
                escape,
                &mut budget,
            )?;
        }
    }
    Ok(out.moves)
}

/// The contour's elements as segments: a fillet or a chamfer as a corner to be made.
fn segments_of(contour: &[Element]) -> Vec<Seg> {
    contour
        .iter()
        .map(|e| match *e {
            Element::Line { start, end } => Seg::straight(start, end),
            Element::Arc {
                ccw,
                start,
                centre,
                end,
            } => Seg::round(ccw, start, centre, end),
            Element::Fillet { radius, at } => Seg {
                finish: radius,
                corner: Corner::Fillet,
                ..Seg::round(false, at, at, at)
            },
            Element::Chamfer { size, at } => Seg {
                finish: size,
                corner: Corner::Chamfer,
                ..Seg::straight(at, at)
            },
        })
        .collect()
}

impl Path {
    /// G70's passes (`first`, `last`: the distances of the first and last from the
    /// contour; `passes`: how many), from `start`.
    fn finish_passes(
        &mut self,
        start: C,
        (first, last, passes): (f64, f64, f64),
        out: &mut Sink,
        budget: &mut Budget,
    ) -> Result<(), Fail> {
        self.segs[0].start = start;
        let mut probe = self.clone();
        probe.segs.remove(0);
        probe.swap()?;
        if probe.segs.iter().any(|s| !s.monotonic()) {
            probe.rotate();
            probe.swap()?;
        }
        probe.monotonic()?;
        if probe.flip & 4 != 0 {
            self.rotate();
        }
        self.swap()?;
        self.do_finish()?;
        self.monotonic()?;
        out.flip = self.flip;
        // `for(int pass=p; …)`: P truncated to a whole number.
        let mut pass = passes as i64;
        while pass > 0 {
            budget.spend()?;
            let distance = (pass - 1) as f64 * (first - last) / passes + last;
            let mut offset = self.clone();
            offset.add_distance(distance, budget)?;
            let front = offset.segs[0];
            out.straight_rapid(front.start);
            out.straight_rapid(front.end);
            for s in &offset.segs[1..] {
                draw(s, out);
            }
            pass -= 1;
        }
        Ok(())
    }

    /// G71/G72's contour from `start` (`facing`: along X), offset by `d` and moved by
    /// `displacement` (the finishing allowances W and U).
    fn rough_contour(
        &mut self,
        start: C,
        facing: bool,
        d: f64,
        displacement: C,
        budget: &mut Budget,
    ) -> Result<(), Fail> {
        self.segs[0].start = start;
        if facing {
            self.rotate();
        }
        self.swap()?;
        self.do_finish()?;
        self.monotonic()?;
        self.add_distance(d, budget)?;
        for s in &mut self.segs {
            s.moved(displacement);
        }
        Ok(())
    }
}

fn draw(s: &Seg, out: &mut Sink) {
    match s.kind {
        Kind::Straight => out.straight_move(s.end),
        Kind::Round { ccw, centre } => out.circular_move(ccw, centre, s.end),
    }
}

/// `g7x::pocket`: roughs from `location`, element `p` on; a pocket found on the way is
/// roughed the same way (LinuxCNC recurses; this loops).
#[allow(clippy::too_many_arguments)]
fn pocket(
    segs: &[Seg],
    mut cycle: u8,
    mut location: C,
    mut p: usize,
    out: &mut Sink,
    pocket_starts: &mut Vec<C>,
    delta: f64,
    escape: C,
    budget: &mut Budget,
) -> Result<(), Fail> {
    'pocket: loop {
        let Some(&top) = pocket_starts.last() else {
            return fail("This can't happen");
        };
        let mut x = top.im;
        if cycle == 2 {
            // Skips the first roughing pass.
            while p < segs.len() {
                budget.spend()?;
                if segs[p].dive(&mut location, -1e9, out, p == 0)? {
                    break;
                }
                p += 1;
            }
            cycle = 3;
        }
        while p < segs.len() {
            budget.spend()?;
            while x - TOLERANCE > location.im {
                budget.spend()?;
                x -= delta;
            }
            if segs[p].dive(&mut location, x, out, p == 0)? {
                if cycle == 1 {
                    // After the first roughing pass, along the final contour, and done.
                    while p < segs.len() {
                        segs[p].climb_only(&mut location, out);
                        p += 1;
                    }
                } else {
                    // Along the final contour until a pocket, then that pocket.
                    while p < segs.len() {
                        budget.spend()?;
                        if segs[p].climb(&mut location, out)? {
                            if cycle == 3 {
                                if let Some(&last) = pocket_starts.last()
                                    && location.im > last.im
                                    && pocket_starts.len() > 1
                                {
                                    pocket_starts.pop();
                                }
                                if pocket_starts.len() == 1 {
                                    pocket_starts.push(location);
                                }
                            }
                            continue 'pocket;
                        }
                        p += 1;
                    }
                }
                return Ok(());
            }
            if (location.im - x).abs() > TOLERANCE {
                // x is beyond the current element: on to the next.
                p += 1;
                continue;
            }
            match cross(segs, p, location, out, escape, budget)? {
                Crossed::Onto(ip) => p = ip,
                Crossed::Lower => x -= delta,
                Crossed::Nothing => {}
            }
        }
        return Ok(());
    }
}

/// What [`cross`] did, for [`pocket`] to go on with.
enum Crossed {
    /// Moved onto element `ip` at its entry.
    Onto(usize),
    /// Crossed (or found a zero-length element): the next pass is one step lower.
    Lower,
    /// Found nothing to cross to.
    Nothing,
}

/// From `location`, on element `p` at the pass's height, across to the first element
/// the pass meets, and back out along `escape` to the start of the next pass.
fn cross(
    segs: &[Seg],
    p: usize,
    location: C,
    out: &mut Sink,
    escape: C,
    budget: &mut Budget,
) -> Result<Crossed, Fail> {
    let mut ip = p;
    while ip < segs.len() {
        budget.spend()?;
        let mut is = Vec::new();
        segs[ip].intersection_z(location.im, &mut is);
        let (Some(&front), Some(&back)) = (is.first(), is.last()) else {
            ip += 1;
            continue;
        };
        // The diving element itself can be hit if it is an arc.
        let destination_z = if ip != p { front } else { back };
        let distance = (destination_z - location.re).abs();
        if destination_z - TOLERANCE > location.re {
            // The diving element, at its start only.
            ip += 1;
            continue;
        }
        if distance < TOLERANCE {
            if p == ip {
                ip += 1;
                continue;
            } else if (location - segs[ip].start).abs() < TOLERANCE {
                // Another element, at its entry: move onto it.
                return Ok(Crossed::Onto(ip));
            } else {
                // A zero-length element: done with it.
                return Ok(Crossed::Lower);
            }
        }
        let mut dest = location;
        dest.re = destination_z;
        out.straight_move(dest);
        // A travel too short for the whole escape.
        let escape_scale = (distance / 2.0 / escape.re).min(1.0);
        dest += escape.scale(escape_scale);
        out.straight_rapid(dest);
        let dest = location - escape.scale(escape_scale).conj();
        out.straight_rapid(dest);
        if p == 0 {
            out.straight_rapid(location);
        } else {
            out.straight_move(location);
        }
        return Ok(Crossed::Lower);
    }
    Ok(Crossed::Nothing)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn division_is_the_complex_quotient() {
        let q = C::new(3.0, 4.0) / C::new(1.0, 2.0);
        assert!((q.re - 2.2).abs() < 1e-15 && (q.im + 0.4).abs() < 1e-15);
        let q = C::new(3.0, 4.0) / C::new(2.0, 1.0);
        assert!((q.re - 2.0).abs() < 1e-15 && (q.im - 1.0).abs() < 1e-15);
    }

    #[test]
    fn a_contour_of_one_element_is_refused() {
        let r = run(
            &Cycle::Rough {
                facing: false,
                variant: 0,
                u: 0.0,
                w: 0.0,
                d: 0.0,
                i: 1.0,
                r: 0.5,
            },
            C::new(2.0, 10.0),
            &[Element::Line {
                start: C::new(2.0, 10.0),
                end: C::new(0.0, 2.0),
            }],
        );
        assert!(r.is_err());
    }
}

//! Lowering: the one implementation of how thread operations become straight synchronised
//! moves. Emitters, `explain`, `plot` and the simulator all call these functions.

use crate::fixed::{Angle, Length};
use crate::ir::{Pos, ThreadPass};

/// One straight spindle-synchronised move.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SyncSegment {
    pub from: Pos,
    pub to: Pos,
    /// Advance along Z per spindle revolution.
    pub lead: Length,
}

/// What a pass needs that it does not have.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LowerError {
    /// An entry, runout, taper or start shift needs the start point, which is unknown.
    UnknownStart,
}

impl SyncSegment {
    /// The advance per revolution along the segment's own path (LinuxCNC's G33 K): the Z
    /// lead scaled by path length / |ΔZ|, with X converted from diameter to radius.
    pub fn lead_along_path(&self) -> f64 {
        let lead = self.lead.to_mm_f64();
        let (Some(z0), Some(z1)) = (self.from.z, self.to.z) else {
            return lead;
        };
        let dr = match (self.from.x, self.to.x) {
            (Some(x0), Some(x1)) => (x1 - x0).to_mm_f64() / 2.0,
            _ => 0.0,
        };
        let dz = (z1 - z0).to_mm_f64();
        if dr == 0.0 || dz == 0.0 {
            return lead;
        }
        lead * dz.hypot(dr) / dz.abs()
    }
}

/// X on the line through `a` and `b` at `z`, rounded onto the grid.
fn x_on_line(a: (Length, Length), b: (Length, Length), z: Length) -> Length {
    let (ax, az) = a;
    let (bx, bz) = b;
    if bz == az {
        return ax;
    }
    ax + (bx - ax).mul_div((z - az).0, (bz - az).0)
}

/// The synchronised moves of `pass` starting at `start`: entry, thread, runout, in order,
/// without empty segments.
pub fn pass_segments(start: Pos, pass: &ThreadPass) -> Result<Vec<SyncSegment>, LowerError> {
    let end = Pos {
        x: pass.to.x.or(start.x),
        z: pass.to.z.or(start.z),
    };
    if pass.entry.is_none() && pass.exit.is_none() {
        return Ok(vec![SyncSegment {
            from: start,
            to: end,
            lead: pass.lead,
        }]);
    }
    let (sx, sz) = start.known().ok_or(LowerError::UnknownStart)?;
    let (ex, ez) = end.known().ok_or(LowerError::UnknownStart)?;
    let direction = (ez - sz).signum();
    let line_from = (sx - pass.entry.map_or(Length::ZERO, |e| e.offset), sz);
    let line_to = (ex, ez);
    let mut points = vec![Pos::new(sx, sz)];
    if let Some(entry) = pass.entry {
        let z = sz + Length(direction * entry.length.0);
        points.push(Pos::new(x_on_line(line_from, line_to, z), z));
    }
    if let Some(exit) = pass.exit {
        let z = ez - Length(direction * exit.length.0);
        points.push(Pos::new(x_on_line(line_from, line_to, z), z));
        points.push(Pos::new(ex + exit.offset, ez));
    } else {
        points.push(Pos::new(ex, ez));
    }
    points.dedup();
    Ok(points
        .windows(2)
        .map(|w| SyncSegment {
            from: w[0],
            to: w[1],
            lead: pass.lead,
        })
        .collect())
}

/// Expresses a start angle without one: the first segment starts `lead·θ/360` earlier
/// along its own line, at the index pulse, and so cuts the same helix. Returns the new
/// start point (the caller moves there first).
pub fn start_angle_as_shift(
    segments: &mut [SyncSegment],
    angle: Angle,
) -> Result<Option<Pos>, LowerError> {
    if angle == Angle::ZERO {
        return Ok(None);
    }
    let Some(first) = segments.first_mut() else {
        return Ok(None);
    };
    let (Some(z0), Some(z1)) = (first.from.z, first.to.z) else {
        return Err(LowerError::UnknownStart);
    };
    let shift = first.lead.mul_div(angle.0, 360_000);
    let direction = (z1 - z0).signum();
    let z = z0 - Length(direction * shift.0);
    let x = match (first.from.x, first.to.x) {
        (Some(x0), Some(x1)) if x0 != x1 => {
            Some(x0 - (x1 - x0).mul_div(shift.0, (z1 - z0).abs().0))
        }
        (Some(x0), _) => Some(x0),
        (None, Some(_)) => return Err(LowerError::UnknownStart),
        (None, None) => None,
    };
    first.from = Pos { x, z: Some(z) };
    Ok(Some(first.from))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ir::Chamfer;

    fn mm(v: f64) -> Length {
        Length::from_mm_f64(v)
    }

    fn chamfer(length: f64, angle_deg: f64) -> Chamfer {
        Chamfer {
            length: mm(length),
            offset: mm(2.0 * length * angle_deg.to_radians().tan()),
        }
    }

    #[test]
    fn seed_entry_example_cuts_at_diameter_64() {
        // czech.md: start X71.798, E12., 18° → thread at Ø64 (71.798 − 2·12·tan 18°).
        let pass = ThreadPass {
            to: Pos::new(mm(71.798) - chamfer(12.0, 18.0).offset, mm(3.0)),
            lead: mm(6.0),
            start_angle: Angle::ZERO,
            entry: Some(chamfer(12.0, 18.0)),
            exit: None,
        };
        let segs = pass_segments(Pos::new(mm(71.798), mm(-100.0)), &pass).unwrap();
        assert_eq!(segs.len(), 2);
        assert_eq!(segs[0].from, Pos::new(mm(71.798), mm(-100.0)));
        let (x, z) = segs[0].to.known().unwrap();
        // 71.798 − 7.798073 = 63.999927, rounded once onto the 0.0001 grid.
        assert_eq!(x, mm(63.9999));
        assert_eq!(z, mm(-88.0));
        assert_eq!(segs[1].to, Pos::new(x, mm(3.0)));
    }

    #[test]
    fn runout_leaves_the_thread_over_the_last_j() {
        // Seed example 4: Z5 → Z-100 at Ø64, J12, 20° → ends at Ø64 + 2·12·tan 20°.
        let pass = ThreadPass {
            to: Pos::new(mm(64.0), mm(-100.0)),
            lead: mm(6.0),
            start_angle: Angle::ZERO,
            entry: None,
            exit: Some(chamfer(12.0, 20.0)),
        };
        let segs = pass_segments(Pos::new(mm(64.0), mm(5.0)), &pass).unwrap();
        assert_eq!(segs.len(), 2);
        assert_eq!(segs[0].to, Pos::new(mm(64.0), mm(-88.0)));
        assert_eq!(segs[1].to, Pos::new(mm(72.7353), mm(-100.0)));
    }

    #[test]
    fn taper_runout_follows_the_taper_line() {
        // Ø20 at Z0 to Ø30 at Z-100, runout 10 with no offset: the knee lies on the line.
        let pass = ThreadPass {
            to: Pos::new(mm(30.0), mm(-100.0)),
            lead: mm(2.0),
            start_angle: Angle::ZERO,
            entry: Some(Chamfer {
                length: mm(20.0),
                offset: mm(1.0),
            }),
            exit: Some(Chamfer {
                length: mm(10.0),
                offset: Length::ZERO,
            }),
        };
        // The line starts at Ø20 (start Ø21 minus the entry offset).
        let segs = pass_segments(Pos::new(mm(21.0), mm(0.0)), &pass).unwrap();
        let knees: Vec<_> = segs.iter().map(|s| s.to).collect();
        assert_eq!(
            knees,
            vec![
                Pos::new(mm(22.0), mm(-20.0)),
                Pos::new(mm(29.0), mm(-90.0)),
                Pos::new(mm(30.0), mm(-100.0)),
            ]
        );
    }

    #[test]
    fn seed_taper_lead_along_path() {
        // iso.md: Ø226 → Ø246, Z3 → Z-100, F1.5: K = 1.5·√(103² + 10²)/103 = 1.50705289.
        let seg = SyncSegment {
            from: Pos::new(mm(226.0), mm(3.0)),
            to: Pos::new(mm(246.0), mm(-100.0)),
            lead: mm(1.5),
        };
        assert!(
            (seg.lead_along_path() - 1.507_052_89).abs() < 1e-8,
            "{}",
            seg.lead_along_path()
        );
    }

    #[test]
    fn start_angle_moves_the_start_back_along_the_pass() {
        // I180, lead 1.5, travelling towards -Z from Z3: start 0.75 earlier, at Z3.75.
        let mut segs = vec![SyncSegment {
            from: Pos::new(mm(26.618), mm(3.0)),
            to: Pos::new(mm(26.618), mm(-9.0)),
            lead: mm(1.5),
        }];
        let start = start_angle_as_shift(&mut segs, Angle::from_deg(180)).unwrap();
        assert_eq!(start, Some(Pos::new(mm(26.618), mm(3.75))));
        // On a taper, X moves back along the line too.
        let mut taper = vec![SyncSegment {
            from: Pos::new(mm(20.0), mm(0.0)),
            to: Pos::new(mm(30.0), mm(-100.0)),
            lead: mm(4.0),
        }];
        let start = start_angle_as_shift(&mut taper, Angle::from_deg(90)).unwrap();
        assert_eq!(start, Some(Pos::new(mm(19.9), mm(1.0))));
        // Without a start Z there is nothing to shift from.
        let mut unknown = vec![SyncSegment {
            from: Pos::UNKNOWN,
            to: Pos {
                x: None,
                z: Some(mm(200.0)),
            },
            lead: mm(1.5),
        }];
        assert_eq!(
            start_angle_as_shift(&mut unknown, Angle::from_deg(180)),
            Err(LowerError::UnknownStart)
        );
    }
}

//! The plane geometry of VECTO's shift lines: points, the section of a line a speed falls in, the
//! crossing of two segments, and which side of a line a point lies (VECTO's `GetSection`,
//! `VectoMath.Intersect`, `ShiftPolygon.IsLeftOf` and `IsRightOf`).

/// A point (engine speed [rad/s], torque [Nm]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pt {
    pub x: f64,
    pub y: f64,
}

/// VECTO's `GetSection(skip)`: the pair of neighbouring points from the one before the first
/// point not skipped (the last point never is), clamped to the first pair.
///
/// # Panics
/// With fewer than two points.
pub fn section(points: &[Pt], skip: impl Fn(&Pt) -> bool) -> (Pt, Pt) {
    let last = points.len() - 1;
    let first_kept = points.iter().enumerate().position(|(i, p)| !(skip(p) && i < last)).unwrap_or(last);
    let i = first_kept.saturating_sub(1).min(last - 1);
    (points[i], points[i + 1])
}

/// Where the segments `a` and `b` cross, if they do (VECTO's `VectoMath.Intersect`: none where
/// they are parallel).
pub fn intersect(a: (Pt, Pt), b: (Pt, Pt)) -> Option<Pt> {
    let (s10x, s10y) = (a.1.x - a.0.x, a.1.y - a.0.y);
    let (s32x, s32y) = (b.1.x - b.0.x, b.1.y - b.0.y);
    let denom = s10x * s32y - s32x * s10y;
    if denom == 0.0 {
        return None;
    }
    let positive = denom > 0.0;
    let (s02x, s02y) = (a.0.x - b.0.x, a.0.y - b.0.y);
    let s_numer = s10x * s02y - s10y * s02x;
    if (s_numer < 0.0) == positive {
        return None;
    }
    let t_numer = s32x * s02y - s32y * s02x;
    if (t_numer < 0.0) == positive {
        return None;
    }
    if ((s_numer > denom) == positive) || ((t_numer > denom) == positive) {
        return None;
    }
    let t = t_numer / denom;
    Some(Pt { x: a.0.x + t * s10x, y: a.0.y + t * s10y })
}

/// The cross product of (segment start → end) and (segment start → point).
fn cross(p: Pt, (a, b): (Pt, Pt)) -> f64 {
    (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x)
}

/// Whether `p` lies left of (above, for a rising line) the segment; never where the segment lies
/// wholly at lower speeds (VECTO's `IsLeftOf`).
pub fn is_left_of(p: Pt, seg: (Pt, Pt)) -> bool {
    if seg.0.x < p.x && seg.1.x < p.x {
        return false;
    }
    cross(p, seg) > 1e-6
}

/// Whether `p` lies right of the segment; never where the segment lies wholly at higher speeds
/// (VECTO's `IsRightOf`).
pub fn is_right_of(p: Pt, seg: (Pt, Pt)) -> bool {
    if seg.0.x > p.x && seg.1.x > p.x {
        return false;
    }
    cross(p, seg) < -1e-6
}

/// VECTO's `IsBelowDownshiftCurve` (and `IsBelowUpshiftCurve`): left of the line's section at the
/// point's speed, never beyond the line's last speed. False for an empty line.
pub fn is_below(line: &[Pt], p: Pt) -> bool {
    if line.len() < 2 {
        return false;
    }
    let seg = section(line, |e| e.x < p.x);
    if seg.1.x < p.x {
        return false;
    }
    is_left_of(p, seg)
}

/// VECTO's `IsAboveDownshiftCurve` (and `IsAboveUpshiftCurve`): right of the line's section at the
/// point's speed, always beyond the line's last speed. False for an empty line.
pub fn is_above(line: &[Pt], p: Pt) -> bool {
    if line.len() < 2 {
        return false;
    }
    let seg = section(line, |e| e.x < p.x);
    if seg.1.x < p.x {
        return true;
    }
    is_right_of(p, seg)
}

/// VECTO's `InterpolateDownshift`: the line's torque at speed `x` (linear in its section,
/// extrapolated), infinite on a vertical section or for an empty line.
pub fn torque_on(line: &[Pt], x: f64) -> f64 {
    if line.len() < 2 {
        return f64::INFINITY;
    }
    let (a, b) = section(line, |e| e.x < x);
    if (a.x - b.x).abs() < 1e-6 {
        return f64::INFINITY;
    }
    a.y + (b.y - a.y) * (x - a.x) / (b.x - a.x)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pts(xy: &[(f64, f64)]) -> Vec<Pt> {
        xy.iter().map(|&(x, y)| Pt { x, y }).collect()
    }

    #[test]
    fn get_section_picks_the_pair_around_the_speed_clamped_at_both_ends() {
        let line = pts(&[(0.0, 0.0), (10.0, 1.0), (20.0, 2.0)]);
        assert_eq!(section(&line, |p| p.x < 15.0), (line[1], line[2]));
        assert_eq!(section(&line, |p| p.x < -5.0), (line[0], line[1]));
        assert_eq!(section(&line, |p| p.x < 99.0), (line[1], line[2]));
    }

    #[test]
    fn vecto_math_intersect_finds_crossings_within_both_segments_only() {
        let a = (Pt { x: 0.0, y: 0.0 }, Pt { x: 2.0, y: 2.0 });
        let b = (Pt { x: 0.0, y: 2.0 }, Pt { x: 2.0, y: 0.0 });
        assert_eq!(intersect(a, b), Some(Pt { x: 1.0, y: 1.0 }));
        let short = (Pt { x: 0.0, y: 2.0 }, Pt { x: 0.5, y: 1.5 });
        assert_eq!(intersect(a, short), None);
        assert_eq!(intersect(a, (Pt { x: 0.0, y: 1.0 }, Pt { x: 1.0, y: 2.0 })), None);
    }

    #[test]
    fn shift_polygon_is_below_and_is_above_a_rising_line() {
        // A downshift line rising from (100, -200) to (200, 1000) to (250, 3000).
        let line = pts(&[(100.0, -200.0), (200.0, 1000.0), (250.0, 3000.0)]);
        assert!(is_below(&line, Pt { x: 150.0, y: 800.0 }));
        assert!(!is_below(&line, Pt { x: 150.0, y: 0.0 }));
        assert!(is_above(&line, Pt { x: 150.0, y: 0.0 }));
        // Beyond the line's last speed a point is above it, never below.
        assert!(is_above(&line, Pt { x: 300.0, y: 5000.0 }) && !is_below(&line, Pt { x: 300.0, y: 5000.0 }));
        assert!((torque_on(&line, 225.0) - 2000.0).abs() < 1e-9);
    }
}

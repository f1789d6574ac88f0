//! The engine's fuel map: fuel rate [g/h] at scattered (engine speed [rpm], torque [Nm]) points,
//! interpolated linearly on the Delaunay triangulation of the points, as VECTO does.
//!
//! Like VECTO, the triangulation is made after scaling torque and speed each to [0, 1] over the
//! map's range (a Delaunay triangulation depends on the scales of its axes), and built the way
//! VECTO builds it ([`super::delaunay`]), so that where a cell's diagonal is a tie the same one is
//! chosen. Outside the map's convex hull, [`FuelMap::extrapolate`] takes the value at the nearest
//! point of the hull's boundary (VECTO starts from the nearest hull vertex and projects onto an edge
//! next to it; the two agree wherever the nearest boundary point lies on one of those edges).

use super::delaunay::Triangulation;
use crate::{CoreError, CoreResult};

/// A fuel map, ready to interpolate.
#[derive(Debug, Clone)]
pub struct FuelMap {
    /// Over (torque, speed) scaled to [0, 1], carrying the fuel rate [g/h].
    triangulation: Triangulation,
    torque_nm: (f64, f64),
    speed_rpm: (f64, f64),
}

impl FuelMap {
    /// A map from `(engine speed [rpm], torque [Nm], fuel rate [g/h])` points; `key` names it in
    /// errors. At least three points not on one line, finite values, fuel rate ≥ 0, no (speed, torque)
    /// twice.
    pub fn new(key: &str, points: &[(f64, f64, f64)]) -> CoreResult<Self> {
        Self::build(key, points, true)
    }

    /// [`FuelMap::new`] for a value of either sign (an electric machine's loss, which its maps
    /// give slightly negative at standstill).
    pub fn signed(key: &str, points: &[(f64, f64, f64)]) -> CoreResult<Self> {
        Self::build(key, points, false)
    }

    fn build(key: &str, points: &[(f64, f64, f64)], nonnegative: bool) -> CoreResult<Self> {
        check_points(key, points, nonnegative)?;
        let range = |f: fn(&(f64, f64, f64)) -> f64| {
            points.iter().map(f).fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)))
        };
        let (speed_rpm, torque_nm) = (range(|p| p.0), range(|p| p.1));
        if speed_rpm.1 <= speed_rpm.0 || torque_nm.1 <= torque_nm.0 {
            return Err(CoreError::invalid(key, "points spanning a range of engine speeds and of torques"));
        }
        let scaled: Vec<[f64; 3]> =
            points.iter().map(|&(n, t, f)| [scale(t, torque_nm), scale(n, speed_rpm), f]).collect();
        let triangulation =
            Triangulation::new(&scaled).ok_or_else(|| CoreError::invalid(key, "points not all on one line"))?;
        Ok(FuelMap { triangulation, torque_nm, speed_rpm })
    }

    /// Fuel rate [g/h] at `speed_rpm` and `torque_nm`, or `None` outside the map's convex hull (and
    /// for a speed or torque that is not finite).
    pub fn interpolate(&self, speed_rpm: f64, torque_nm: f64) -> Option<f64> {
        // Outside the unit square (or not a number) no triangle holds the point: no lookup needed.
        const EDGE: f64 = 1e-9;
        let (x, y) = (scale(torque_nm, self.torque_nm), scale(speed_rpm, self.speed_rpm));
        let inside = -EDGE..=1.0 + EDGE;
        if !(inside.contains(&x) && inside.contains(&y)) {
            return None;
        }
        self.triangulation.interpolate(x, y)
    }

    /// Fuel rate [g/h] at `speed_rpm` and `torque_nm`: interpolated inside the map, else the
    /// value at the nearest point of its boundary (in scaled coordinates).
    pub fn extrapolate(&self, speed_rpm: f64, torque_nm: f64) -> f64 {
        if !(speed_rpm.is_finite() && torque_nm.is_finite()) {
            return f64::NAN;
        }
        if let Some(fuel) = self.interpolate(speed_rpm, torque_nm) {
            return fuel;
        }
        // Far outside, squared distances would overflow; the nearest boundary point is the same.
        let clamp = |v: f64| v.clamp(-1e6, 1e6);
        let (x, y) = (clamp(scale(torque_nm, self.torque_nm)), clamp(scale(speed_rpm, self.speed_rpm)));
        let mut best = (f64::INFINITY, 0.0);
        for [[x0, y0, z0], [x1, y1, z1]] in self.triangulation.hull() {
            let (dx, dy) = (x1 - x0, y1 - y0);
            let t = (((x - x0) * dx + (y - y0) * dy) / (dx * dx + dy * dy)).clamp(0.0, 1.0);
            let d2 = (x0 + t * dx - x).powi(2) + (y0 + t * dy - y).powi(2);
            if d2 < best.0 {
                best = (d2, z0 + t * (z1 - z0));
            }
        }
        best.1
    }

    /// The map's range of engine speeds [rpm].
    pub fn speed_range_rpm(&self) -> (f64, f64) {
        self.speed_rpm
    }

    /// The map's range of torques [Nm].
    pub fn torque_range_nm(&self) -> (f64, f64) {
        self.torque_nm
    }

    /// Number of points of the map.
    pub fn len(&self) -> usize {
        self.triangulation.len()
    }

    /// Whether the map has no points (never: a map has at least three).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

fn scale(value: f64, (lo, hi): (f64, f64)) -> f64 {
    (value - lo) / (hi - lo)
}

fn check_points(key: &str, points: &[(f64, f64, f64)], nonnegative: bool) -> CoreResult<()> {
    if points.len() < 3 {
        return Err(CoreError::invalid(key, "at least three points").got(points.len()));
    }
    let mut seen = std::collections::HashSet::new();
    for (i, &(n, t, f)) in points.iter().enumerate() {
        let row = i + 1;
        if !(n.is_finite() && t.is_finite() && f.is_finite()) {
            return Err(CoreError::invalid(key, format!("finite numbers at point {row}")).got(format!("{n}, {t}, {f}")));
        }
        if nonnegative && f < 0.0 {
            return Err(CoreError::invalid(key, format!("a fuel rate >= 0 at point {row}")).got(f));
        }
        if !seen.insert((n.to_bits(), t.to_bits())) {
            return Err(CoreError::invalid(key, format!("each (speed, torque) once; point {row} repeats"))
                .got(format!("{n} rpm, {t} Nm")));
        }
    }
    Ok(())
}

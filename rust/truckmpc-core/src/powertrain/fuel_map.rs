//! The engine's fuel map: fuel rate [g/h] at scattered (engine speed [rpm], torque [Nm]) points,
//! interpolated linearly on the Delaunay triangulation of the points, as VECTO does.
//!
//! Like VECTO, the triangulation is made after scaling torque and speed each to [0, 1] over the
//! map's range: a Delaunay triangulation depends on the scales of its axes, and the scaled one is
//! the one VECTO's results come from. Where four points lie on one circle (the rectangular cells of
//! a map measured on a grid) either diagonal is a Delaunay triangulation; this one and VECTO's may
//! pick different ones there, and differ by a few per cent inside such a cell away from its edges.
//! Outside the map's convex hull, [`FuelMap::extrapolate`] takes the value at the nearest point of
//! the hull's boundary (VECTO starts from the nearest hull vertex and projects onto an edge next to
//! it; the two agree wherever the nearest boundary point lies on one of those edges).

use spade::{DelaunayTriangulation, FloatTriangulation, HasPosition, Point2, Triangulation};

use crate::{CoreError, CoreResult};

/// One point of the map, in scaled coordinates, with its fuel rate.
#[derive(Debug, Clone, Copy)]
struct MapPoint {
    torque: f64,
    speed: f64,
    fuel_g_per_h: f64,
}

impl HasPosition for MapPoint {
    type Scalar = f64;
    fn position(&self) -> Point2<f64> {
        Point2::new(self.torque, self.speed)
    }
}

/// A fuel map, ready to interpolate.
#[derive(Debug, Clone)]
pub struct FuelMap {
    triangulation: DelaunayTriangulation<MapPoint>,
    torque_nm: (f64, f64),
    speed_rpm: (f64, f64),
    /// The hull's boundary as segments of (torque, speed, fuel) in scaled coordinates.
    hull: Vec<[(f64, f64, f64); 2]>,
}

impl FuelMap {
    /// A map from `(engine speed [rpm], torque [Nm], fuel rate [g/h])` points; `key` names it in
    /// errors. At least three points not on one line, finite values, fuel rate ≥ 0, no (speed, torque)
    /// twice.
    pub fn new(key: &str, points: &[(f64, f64, f64)]) -> CoreResult<Self> {
        check_points(key, points)?;
        let range = |f: fn(&(f64, f64, f64)) -> f64| {
            points.iter().map(f).fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)))
        };
        let (speed_rpm, torque_nm) = (range(|p| p.0), range(|p| p.1));
        if speed_rpm.1 <= speed_rpm.0 || torque_nm.1 <= torque_nm.0 {
            return Err(CoreError::invalid(key, "points spanning a range of engine speeds and of torques"));
        }
        let scaled: Vec<MapPoint> = points
            .iter()
            .map(|&(n, t, f)| MapPoint { torque: scale(t, torque_nm), speed: scale(n, speed_rpm), fuel_g_per_h: f })
            .collect();
        let triangulation = DelaunayTriangulation::<MapPoint>::bulk_load(scaled)
            .map_err(|e| CoreError::invalid(key, "points a triangulation accepts").got(format!("{e:?}")))?;
        if triangulation.num_inner_faces() == 0 {
            return Err(CoreError::invalid(key, "points not all on one line"));
        }
        let hull = triangulation
            .convex_hull()
            .map(|edge| {
                let [a, b] = edge.vertices().map(|v| *v.data());
                [(a.torque, a.speed, a.fuel_g_per_h), (b.torque, b.speed, b.fuel_g_per_h)]
            })
            .collect();
        Ok(FuelMap { triangulation, torque_nm, speed_rpm, hull })
    }

    /// Fuel rate [g/h] at `speed_rpm` and `torque_nm`, or `None` outside the map's convex hull (and
    /// for a speed or torque that is not finite).
    pub fn interpolate(&self, speed_rpm: f64, torque_nm: f64) -> Option<f64> {
        // Checked here: the triangulation's point location must never see a point far outside it.
        const EDGE: f64 = 1e-9;
        let (x, y) = (scale(torque_nm, self.torque_nm), scale(speed_rpm, self.speed_rpm));
        let inside = -EDGE..=1.0 + EDGE;
        if !(inside.contains(&x) && inside.contains(&y)) {
            return None;
        }
        self.triangulation.barycentric().interpolate(|v| v.data().fuel_g_per_h, Point2::new(x, y))
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
        for [(x0, y0, z0), (x1, y1, z1)] in &self.hull {
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
        self.triangulation.num_vertices()
    }

    /// Whether the map has no points (never: a map has at least three).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

fn scale(value: f64, (lo, hi): (f64, f64)) -> f64 {
    (value - lo) / (hi - lo)
}

fn check_points(key: &str, points: &[(f64, f64, f64)]) -> CoreResult<()> {
    if points.len() < 3 {
        return Err(CoreError::invalid(key, "at least three points").got(points.len()));
    }
    let mut seen = std::collections::HashSet::new();
    for (i, &(n, t, f)) in points.iter().enumerate() {
        let row = i + 1;
        if !(n.is_finite() && t.is_finite() && f.is_finite()) {
            return Err(CoreError::invalid(key, format!("finite numbers at point {row}")).got(format!("{n}, {t}, {f}")));
        }
        if f < 0.0 {
            return Err(CoreError::invalid(key, format!("a fuel rate >= 0 at point {row}")).got(f));
        }
        if !seen.insert((n.to_bits(), t.to_bits())) {
            return Err(CoreError::invalid(key, format!("each (speed, torque) once; point {row} repeats"))
                .got(format!("{n} rpm, {t} Nm")));
        }
    }
    Ok(())
}

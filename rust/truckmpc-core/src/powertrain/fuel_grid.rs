//! The fuel map resampled on a regular grid of engine speed and torque, for the closed loop and the
//! look-ahead controller, which evaluate the fuel rate millions of times per run.
//!
//! Looking a point up on the triangulation scans its triangles; the grid answers in a few
//! operations, bilinear between its nodes. Each node holds the triangulated (or, outside the map,
//! extrapolated) value, so the grid reproduces any map that is linear over each cell exactly, and
//! elsewhere differs only in cells a triangle edge crosses (the test bounds how much, on VECTO's
//! generic engine). The cut at the drag curve is not resampled: the caller applies it exactly.

use super::FuelMap;

/// Nodes along each axis of a fuel map's grid.
const NODES: usize = 401;

/// A map sampled on `nodes × nodes` points over a speed and torque range.
#[derive(Debug, Clone)]
pub struct FuelGrid {
    nodes: usize,
    speed_rpm: (f64, f64),
    torque_nm: (f64, f64),
    /// The map's value (fuel rate [g/h], or a torque loss [Nm]), row-major by speed.
    values: Vec<f64>,
}

impl FuelGrid {
    /// `map` sampled over `speed_rpm` × `torque_nm` (each (lowest, highest), highest > lowest).
    pub fn new(map: &FuelMap, speed_rpm: (f64, f64), torque_nm: (f64, f64)) -> Self {
        Self::with_nodes(map, speed_rpm, torque_nm, NODES)
    }

    /// [`FuelGrid::new`] with `nodes` (≥ 2) along each axis.
    pub fn with_nodes(map: &FuelMap, speed_rpm: (f64, f64), torque_nm: (f64, f64), nodes: usize) -> Self {
        Self::from_fn(speed_rpm, torque_nm, nodes, |n, t| map.extrapolate(n, t).max(0.0))
    }

    /// Any function `value(speed [rpm], torque [Nm])` sampled on `nodes` (≥ 2) along each axis
    /// over `speed_rpm` × `torque_nm`.
    pub fn from_fn(
        speed_rpm: (f64, f64),
        torque_nm: (f64, f64),
        nodes: usize,
        value: impl Fn(f64, f64) -> f64,
    ) -> Self {
        let nodes = nodes.max(2);
        let node = |(lo, hi): (f64, f64), i: usize| lo + (hi - lo) * i as f64 / (nodes - 1) as f64;
        let mut values = Vec::with_capacity(nodes * nodes);
        for i in 0..nodes {
            let n = node(speed_rpm, i);
            values.extend((0..nodes).map(|j| value(n, node(torque_nm, j))));
        }
        FuelGrid { nodes, speed_rpm, torque_nm, values }
    }

    /// Fuel rate [g/h] at `speed_rpm` and `torque_nm`, bilinear between the nodes; outside the
    /// grid's range the nearest edge's value (NaN for a speed or torque that is not a number).
    #[inline]
    pub fn at(&self, speed_rpm: f64, torque_nm: f64) -> f64 {
        let (i, fi) = cell(speed_rpm, self.speed_rpm, self.nodes);
        let (j, fj) = cell(torque_nm, self.torque_nm, self.nodes);
        if fi.is_nan() || fj.is_nan() {
            return f64::NAN;
        }
        let at = |a: usize, b: usize| self.values[a * self.nodes + b];
        let low = at(i, j) + fj * (at(i, j + 1) - at(i, j));
        let high = at(i + 1, j) + fj * (at(i + 1, j + 1) - at(i + 1, j));
        low + fi * (high - low)
    }
}

/// The cell of `x` on an axis over `(lo, hi)`: its lower node and the fraction across it, clamped
/// to the axis.
#[inline]
fn cell(x: f64, (lo, hi): (f64, f64), nodes: usize) -> (usize, f64) {
    let steps = (nodes - 1) as f64;
    let t = ((x - lo) / (hi - lo) * steps).clamp(0.0, steps);
    if t.is_nan() {
        return (0, f64::NAN);
    }
    let i = (t as usize).min(nodes - 2);
    (i, t - i as f64)
}

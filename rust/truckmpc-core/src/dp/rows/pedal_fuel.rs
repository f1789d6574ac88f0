//! The fuel rate of a map-based truck over the pedal at the speeds of a fixed grid, tabulated once
//! per speed and gear and interpolated per transition.
//!
//! A trapezoid row of a map-based truck evaluates the fuel map twice per transition (at its start
//! and end speeds, each at the transition's own pedal): the wheel-torque range, two loss maps and
//! the fuel grid. At a fixed engine speed all of these are piecewise linear in the pedal, so the
//! fuel rate is too, and nearly affine (a Willans line): a table of [`STRIDE`] values over the
//! pedal, exact at fuel cut, at its nodes and at full pedal, gives it to within 0.1 % of the
//! full-pedal rate between them, on a map with a strong curvature and a kink where its fuel reaches
//! zero (`tests::the_table_is_close_to_the_map`; the error halves as the nodes double). Trapezoid
//! rows use it (Euler rows read the map). On a fixed grid the
//! speeds are the same at every stage and in every solve, so each speed and gear is tabulated once
//! per run; a moving grid's speeds change with each stage, and its rows evaluate the map instead.

use crate::vehicle::Vehicle;

/// Pedal intervals of the table: the value at pedal P is interpolated between P·NODES's neighbours.
pub const NODES: usize = 128;

/// Values per entry: the nodes 0, 1/NODES, …, 1.
pub const STRIDE: usize = NODES + 1;

/// The fuel per metre [g/m] over the pedal at node k/NODES, k = 0..=NODES, for the fixed grid's
/// speeds and each forward gear, filled on demand. Keyed on the grid's step: another grid starts
/// afresh. Like the row cache, one table serves one vehicle.
#[derive(Debug, Clone, Default)]
pub struct PedalFuel {
    /// The grid step δ [m/s] (bits) the values are for.
    delta_bits: u64,
    /// Per gear (index 0 unused).
    gears: Vec<GearTable>,
}

/// One gear's entries for a contiguous range of grid indices.
#[derive(Debug, Clone, Default)]
struct GearTable {
    /// Grid index of the first entry.
    first: i64,
    /// Entry i (grid index first + i) at `values[i·STRIDE..(i + 1)·STRIDE]`.
    values: Vec<f64>,
}

impl PedalFuel {
    /// Make sure the entries of grid indices `lo..=hi` (origin 0, step `delta_mps`) in forward
    /// `gear` exist, computing the missing ones from the vehicle's map.
    pub fn fill(&mut self, vehicle: &Vehicle, (lo, hi): (i64, i64), delta_mps: f64, gear: usize) {
        if delta_mps.to_bits() != self.delta_bits {
            self.gears.clear();
            self.delta_bits = delta_mps.to_bits();
        }
        if self.gears.len() <= gear {
            self.gears.resize_with(gear + 1, GearTable::default);
        }
        let table = &mut self.gears[gear];
        let entry = |index: i64| {
            let v_mps = index as f64 * delta_mps;
            (0..STRIDE).map(move |k| vehicle.fuel_rate_gps(v_mps, k as f64 / NODES as f64, gear) / v_mps)
        };
        if table.values.is_empty() {
            table.first = lo;
            table.values.extend((lo..=hi).flat_map(entry));
            return;
        }
        let last = table.first + (table.values.len() / STRIDE) as i64 - 1;
        if lo < table.first {
            let below: Vec<f64> = (lo..table.first).flat_map(entry).collect();
            table.values.splice(0..0, below);
            table.first = lo;
        }
        if hi > last {
            table.values.extend((last + 1..=hi).flat_map(entry));
        }
    }

    /// The entries of grid indices `lo..=hi` in `gear`, end to end ([`PedalFuel::fill`]ed before).
    #[inline]
    pub fn entries(&self, (lo, hi): (i64, i64), gear: usize) -> &[f64] {
        let table = &self.gears[gear];
        &table.values[(lo - table.first) as usize * STRIDE..(hi + 1 - table.first) as usize * STRIDE]
    }
}

/// The fuel per metre [g/m] at `pedal` from an entry of [`PedalFuel`]: its value at zero pedal
/// for pedal ≤ 0 (zero at a diesel's fuel cut, the auxiliaries' draw for a battery-electric
/// truck), else interpolated between the two nodes around it.
#[inline]
pub fn interpolate(entry: &[f64], pedal: f64) -> f64 {
    if pedal <= 0.0 {
        return entry[0];
    }
    let t = (pedal * NODES as f64).min(NODES as f64);
    let k = (t as usize).min(NODES - 1);
    let f = t - k as f64;
    entry[k] + f * (entry[k + 1] - entry[k])
}

/// The grid index whose speed (origin 0, step `delta_mps`) is exactly `v_mps`, if there is one.
#[inline]
pub fn grid_index_of(v_mps: f64, delta_mps: f64) -> Option<i64> {
    let index = (v_mps / delta_mps).round() as i64;
    (index as f64 * delta_mps == v_mps).then_some(index)
}

#[cfg(test)]
mod tests {
    use super::super::tests::curved_map_truck;
    use super::*;

    /// Against the map itself, at pedals between the nodes over speeds 43–97 km/h in every gear
    /// that turns the engine in its range: exact at fuel cut, at the nodes and at full pedal, and
    /// within 0.1 % of the full-pedal rate between them.
    #[test]
    fn the_table_is_close_to_the_map() {
        let vehicle = curved_map_truck();
        let mut table = PedalFuel::default();
        let delta = 0.05 / 3.6;
        let (mut worst, mut rows): (f64, usize) = (0.0, 0);
        for index in (860..1940).step_by(7) {
            for gear in 1..=4 {
                let v = index as f64 * delta;
                let full = vehicle.fuel_rate_gps(v, 1.0, gear);
                if full <= 0.0 {
                    continue;
                }
                rows += 1;
                table.fill(&vehicle, (index, index), delta, gear);
                let entry = table.entries((index, index), gear);
                let rate = |pedal: f64| interpolate(entry, pedal) * v;
                assert_eq!(interpolate(entry, 1.0), full / v);
                assert_eq!(interpolate(entry, 0.0), 0.0);
                assert_eq!(interpolate(entry, 0.5), vehicle.fuel_rate_gps(v, 0.5, gear) / v);
                for step in 1..1000 {
                    let pedal = step as f64 / 1000.0;
                    let err = (rate(pedal) - vehicle.fuel_rate_gps(v, pedal, gear)).abs() / full;
                    worst = worst.max(err);
                }
            }
        }
        assert!(rows > 200, "{rows} rows");
        assert!(worst < 1e-3, "worst error {worst:.2e} of the full-pedal rate");
    }

    #[test]
    fn only_grid_speeds_have_an_index() {
        let delta = 0.05 / 3.6;
        assert_eq!(grid_index_of(1700.0 * delta, delta), Some(1700));
        assert_eq!(grid_index_of(1700.5 * delta, delta), None);
    }
}

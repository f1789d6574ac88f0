//! Rows of the trapezoid stage: the inputs joining two speeds [m/s] from the maps at both ends,
//! the fuel from the fuel per metre at both ends; the pedal band stops at full pedal (the
//! full-pedal end is an exact arc of the solver's), and from zero where fuel cut is one too. Costs
//! in the units of (5.9).

use super::pedal_fuel::{grid_index_of, interpolate, STRIDE};
use super::{change_cost, clamp_span, maps, trim, EndMaps, GridIndex, Inputs, RowMaps, RowMemo, RowSpan, BRAKE_WINDOW};
use crate::dp::params::{DpSettings, GridAnchor, StageModel};
use crate::dp::stage::{self, Branch};
use crate::levels::{brake_accel_on, pedal_accel_on, AffineAccel};
use crate::powertrain::{Powertrain, RateForm};
use crate::vehicle::Vehicle;

/// What a trapezoid pair evaluates at its end speed in the row's gear on the stage's slope: the
/// pedal's affine map and the half-stage fuel at full pedal [g] (the fuel per unit of pedal; NaN
/// for a map-based truck, whose fuel is evaluated at each pair's own pedal instead).
#[derive(Debug, Clone, Copy)]
pub struct AtEnd {
    accel: AffineAccel,
    full_half_fuel_g: f64,
}

impl AtEnd {
    /// The values at end speed `v_j` [m/s] for the rows of `end` (stages of `h_m`).
    #[inline]
    pub(super) fn at(end: &EndMaps, v_j: f64, h_m: f64) -> Self {
        let linear_fuel = end.vehicle.rate_form() == RateForm::ProportionalToPedal;
        AtEnd {
            accel: pedal_accel_on(end.vehicle, v_j, end.gear, end.slope_torque),
            full_half_fuel_g: match linear_fuel {
                true => stage::half_stage_fuel_g(end.vehicle, v_j, 1.0, end.gear, h_m),
                false => f64::NAN,
            },
        }
    }
}

/// The [`AtEnd`] values of one stage and gear by grid index of the next stage, each computed once
/// for all the rows that reach it (a row's pairs share their end speeds with its neighbours').
/// Values are those [`AtEnd::at`] gives, bit for bit: a row of another gear, slope, next grid or
/// stage length starts the memo afresh. Like the row cache, one memo serves one vehicle.
#[derive(Debug, Clone, Default)]
pub struct EndMemo {
    /// Gear, slope torque, next grid's origin and step, and stage length (bits).
    key: [u64; 5],
    first: i64,
    values: Vec<Option<AtEnd>>,
}

impl EndMemo {
    /// Keep the values while `key` is the one they were computed for, else forget them.
    #[inline]
    fn keyed(&mut self, key: [u64; 5]) {
        if key != self.key {
            self.values.clear();
            self.key = key;
        }
    }

    /// The values at grid index `index` of speed `v_j` [m/s].
    #[inline]
    fn get(&mut self, index: i64, compute: impl FnOnce() -> AtEnd) -> AtEnd {
        if self.values.is_empty() {
            self.first = index;
        } else if index < self.first {
            let missing = (self.first - index) as usize;
            self.values.splice(0..0, std::iter::repeat_n(None, missing));
            self.first = index;
        }
        let at = (index - self.first) as usize;
        if at >= self.values.len() {
            self.values.resize(at + 1, None);
        }
        *self.values[at].get_or_insert_with(compute)
    }
}

/// The fuel [g] of a trapezoid stage of a map-based truck from `v_i` to `v_j` [m/s] at `pedal`,
/// from the map at both ends.
#[inline]
pub(super) fn map_stage_fuel_g(end: &EndMaps, (v_i, v_j): (f64, f64), pedal: f64, h_m: f64) -> f64 {
    let half = |v: f64| stage::half_stage_fuel_g(end.vehicle, v, pedal, end.gear, h_m);
    half(v_i) + half(v_j)
}

/// [`pair`](super::pair) on a trapezoid stage: the inputs from the maps at both ends, the fuel from
/// the fuel per metre at both ends; `at_j` gives the values at the end speed when they are needed,
/// and `map_fuel_g` a map-based truck's stage fuel [g] at a pedal level.
#[inline]
pub(super) fn pair_trapezoid(
    p: &DpSettings,
    (m, end): (&RowMaps, &EndMaps),
    (v_i, v_j, v_max): (f64, f64, f64),
    at_j: impl FnOnce() -> AtEnd,
    map_fuel_g: impl FnOnce(f64) -> f64,
) -> Option<(Inputs, f64)> {
    let h = p.mpc.stage_m;
    let change = change_cost(p.mpc.q_speed_change, p.q_speed_change_sq, v_i - v_j);
    let model = StageModel::Trapezoid;
    if m.pedal.gain > 0.0 {
        let AtEnd { accel: at_j, full_half_fuel_g } = at_j();
        let pedal = stage::input_for(model, &m.pedal, &at_j, (v_i, v_j), h);
        let (pedal_lo, pedal_hi) = end.pedal_band;
        if pedal >= pedal_lo && pedal <= pedal_hi {
            let clipped = pedal.clamp(0.0, 1.0);
            let fuel = if m.map_fuel.is_some() {
                p.mpc.q_fuel * map_fuel_g(clipped)
            } else {
                let fuel_per_pedal = m.full_fuel_g + full_half_fuel_g;
                p.mpc.q_fuel * fuel_per_pedal * clipped
            };
            return Some((Inputs { pedal: clipped, brake: 0.0 }, fuel + change));
        }
        if pedal > pedal_hi {
            return None;
        }
    }
    if (v_j - v_max).abs() < p.delta_mps() * BRAKE_WINDOW {
        let at_j = brake_accel_on(end.vehicle, v_j, end.gear, end.slope_torque);
        let at_i = brake_accel_on(end.vehicle, v_i, end.gear, end.slope_torque);
        let brake = stage::input_for(model, &at_i, &at_j, (v_i, v_j), h);
        if (0.0..=1.0).contains(&brake) {
            let cost = p.q_brake * brake + change;
            if !end.vehicle.brake_draws_energy() {
                return Some((Inputs { pedal: 0.0, brake }, cost));
            }
            let energy = stage::brake_energy(model, end.vehicle, (v_i, v_j), brake, end.gear, h);
            return Some((Inputs { pedal: 0.0, brake }, cost + p.mpc.q_fuel * energy));
        }
    }
    None
}

/// The pedal levels a trapezoid row accepts from `v_i`: never above full pedal (a level clipped to
/// full pedal would reach the grid point past the full-pedal end for nothing: a path pulsing
/// between full pedal and a glide gained half a grid step a stage), the full-pedal end being an
/// exact arc of the solver's instead; and from zero when fuel cut is an exact arc too (a level
/// below zero, clipped to zero, is fuel cut in the plant, whose engine drag brakes much harder
/// than the map at zero pedal the row assumed), else from −ε as the Euler rows.
/// On the moving grid, whose top bound is the continuous full-pedal speed, the top would be out of
/// reach at full pedal and its solves infeasible: there the band is the Euler rows' [−ε, 1 + ε].
#[inline]
pub(super) fn trapezoid_pedal_band(p: &DpSettings, v_i: f64, gain: f64) -> (f64, f64) {
    let (lo, hi) = p.pedal_band(v_i, gain);
    match p.mpc.grid {
        GridAnchor::Fixed => (if p.mpc.fuel_cut_arcs { 0.0 } else { lo }, 1.0),
        GridAnchor::Moving => (lo, hi),
    }
}

/// [`forward_row`](super::forward_row) on a trapezoid stage: the span from the end speeds of the
/// pedal band's ends (one index wider each way, the implicit step being solved to rounding), each
/// cost from [`pair_trapezoid`]. A map-based truck's fuel comes from the memo's pedal table when
/// both speeds are on a fixed grid, else from the map.
pub(super) fn forward_row_trapezoid(
    (vehicle, p): (&Vehicle, &DpSettings),
    (v_i, gear, slope_torque): (f64, usize, f64),
    known_ends: [Option<f64>; 2],
    (grid, v_max): (GridIndex, f64),
    (out, memo): (&mut Vec<f64>, &mut RowMemo),
) -> (RowSpan, usize) {
    let start = out.len();
    let m = maps(vehicle, p, v_i, gear, slope_torque);
    let end = m.trapezoid.expect("a trapezoid row");
    let h = p.mpc.stage_m;
    let RowMemo { ends: memo, fuel: table } = memo;
    memo.keyed([gear as u64, slope_torque.to_bits(), grid.origin_mps.to_bits(), grid.delta_mps.to_bits(), h.to_bits()]);
    let (mut first, mut last) = (i64::MAX, i64::MIN);
    let pedal_on = m.pedal.gain > 0.0;
    let mut band_lo = f64::INFINITY;
    if pedal_on {
        let (pedal_lo, pedal_hi) = end.pedal_band;
        // The span only needs its ends to within a grid step (it is one index wider each way and
        // every pair is checked on its own), so the implicit end speed stops at a tenth of one.
        let tol_mps = 0.1 * grid.delta_mps;
        let at = |u: f64| {
            stage::end_speed_within(
                StageModel::Trapezoid,
                vehicle,
                (v_i, h),
                gear,
                slope_torque,
                (Branch::Pedal, u),
                tol_mps,
            )
        };
        // Where the caller knows the band's ends exactly (its arcs), they serve as well.
        let end = |pedal: f64, e: usize| known_ends[e].filter(|_| pedal == e as f64).unwrap_or_else(|| at(pedal));
        band_lo = end(pedal_lo, 0);
        first = grid.ceil(band_lo) - 1;
        last = grid.floor(end(pedal_hi, 1)) + 1;
    }
    if band_lo > v_max - p.delta_mps() {
        first = first.min(grid.floor(v_max - p.delta_mps()));
        last = last.max(grid.ceil(v_max + p.delta_mps()));
    }
    (first, last) = clamp_span((first, last), grid, v_max, p.delta_mps());
    if last < first {
        return (RowSpan { first: 0, len: 0 }, start);
    }
    // One loop per source of fuel (the pedal table, or the maps and closed forms), so that neither
    // branches on it per transition.
    let tabled = m.map_fuel.is_some() && p.mpc.grid == GridAnchor::Fixed && grid.origin_mps == 0.0;
    match tabled.then(|| grid_index_of(v_i, grid.delta_mps)).flatten().filter(|&index| index > 0) {
        Some(index_i) => {
            table.fill(vehicle, (index_i.min(first), index_i.max(last)), grid.delta_mps, gear);
            let entry_i = table.entries((index_i, index_i), gear);
            let ends = table.entries((first, last), gear).chunks_exact(STRIDE);
            out.extend((first..=last).zip(ends).map(|(index, entry_j)| {
                let v_j = grid.speed(index);
                let at_j = || memo.get(index, || AtEnd::at(&end, v_j, h));
                let fuel = |pedal: f64| 0.5 * h * (interpolate(entry_i, pedal) + interpolate(entry_j, pedal));
                pair_trapezoid(p, (&m, &end), (v_i, v_j, v_max), at_j, fuel).map_or(f64::INFINITY, |(_, cost)| cost)
            }));
        }
        None => out.extend((first..=last).map(|index| {
            let v_j = grid.speed(index);
            let at_j = || memo.get(index, || AtEnd::at(&end, v_j, h));
            let fuel = |pedal: f64| map_stage_fuel_g(&end, (v_i, v_j), pedal, h);
            pair_trapezoid(p, (&m, &end), (v_i, v_j, v_max), at_j, fuel).map_or(f64::INFINITY, |(_, cost)| cost)
        })),
    }
    trim(out, start, first)
}

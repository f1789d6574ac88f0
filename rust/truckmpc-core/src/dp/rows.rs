//! Transition costs of one DP state towards one target gear: a "row" over the next stage's grid.
//!
//! The part of the stage cost (5.9) that depends only on the two speeds, the gear and the slope —
//! fuel (Q1), speed change (Q3) and brake (Q5) — is computed here; the speed deviation (Q2) and the
//! shift (Q4) terms depend on the state alone and are added by the solver. A row covers the
//! contiguous band of grid indices reached with a pedal level in [−ε, 1 + ε] (B.5 is affine in the
//! end speed), extended down to the brake points next to v_max; indices in between that no input
//! reaches hold +∞. Speeds of grid indices come from [`GridIndex`], so a row computed for an
//! absolute grid is the same whichever solve asks for it (what makes caching exact).
//!
//! This file holds the grid's indices, the row types and the dispatch by stage model; the rows of
//! the explicit Euler stage are in `rows/euler.rs`, those of the trapezoid stage in
//! `rows/trapezoid.rs`.

mod euler;
mod pedal_fuel;
#[cfg(test)]
mod tests;
mod trapezoid;

use self::euler::{forward_row_euler, pair_euler};
use self::pedal_fuel::PedalFuel;
use self::trapezoid::EndMemo;
use self::trapezoid::{forward_row_trapezoid, map_stage_fuel_g, pair_trapezoid, trapezoid_pedal_band, AtEnd};
use super::params::{DpSettings, StageModel};
use super::stage;
use crate::levels::{brake_accel_on, pedal_accel_on, stage_fuel_g, AffineAccel};
use crate::powertrain::{Powertrain, RateForm};
use crate::vehicle::Vehicle;

/// Speed of a grid index: v = origin + index·δ [m/s]. A moving grid has its origin at the stage's
/// lower bound; a fixed grid has origin 0, so an index names the same speed at every stage.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridIndex {
    /// Speed of index 0 [m/s].
    pub origin_mps: f64,
    /// Grid step δ [m/s].
    pub delta_mps: f64,
}

impl GridIndex {
    /// Speed of `index` [m/s].
    #[inline]
    pub fn speed(&self, index: i64) -> f64 {
        self.origin_mps + index as f64 * self.delta_mps
    }

    /// Smallest index whose speed is at least `v_mps` (to rounding).
    #[inline]
    pub fn ceil(&self, v_mps: f64) -> i64 {
        ceil_i64((v_mps - self.origin_mps) / self.delta_mps - 1e-9)
    }

    /// Largest index whose speed is at most `v_mps` (to rounding).
    #[inline]
    pub fn floor(&self, v_mps: f64) -> i64 {
        floor_i64((v_mps - self.origin_mps) / self.delta_mps + 1e-9)
    }
}

/// `x.ceil() as i64` without the libm call that `ceil` is on x86-64 without SSE4.1: truncate, and
/// step up where that lost a positive fraction. The same integer for every x (saturating at the
/// ends of i64, 0 for NaN, as `as` does).
#[inline]
pub fn ceil_i64(x: f64) -> i64 {
    let t = x as i64;
    if (t as f64) < x {
        t.saturating_add(1)
    } else {
        t
    }
}

/// `x.floor() as i64` without the libm call, as [`ceil_i64`].
#[inline]
pub fn floor_i64(x: f64) -> i64 {
    let t = x as i64;
    if (t as f64) > x {
        t.saturating_sub(1)
    } else {
        t
    }
}

/// |v_j − v_max| must be below δ times this for a brake transition (5.4.3).
pub const BRAKE_WINDOW: f64 = 1.0 - 1e-9;

/// What rows keep between calls to [`forward_row`]: the values at the end speeds of one stage and
/// gear, and a map-based truck's fuel over the pedal at the fixed grid's speeds.
#[derive(Debug, Clone, Default)]
pub struct RowMemo {
    ends: EndMemo,
    fuel: PedalFuel,
}

/// Where a row's costs start on the next grid, and how many there are.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct RowSpan {
    /// Grid index of the first cost.
    pub first: i64,
    /// Number of costs (0: no admissible target).
    pub len: usize,
}

/// The inputs joining v_i to v_j in forward gear g: the pedal when some P ∈ [−ε, 1 + ε] does
/// (clipped to [0, 1]), else the brake at fuel cut when v_j is next to v_max and B ∈ [0, 1].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Inputs {
    pub pedal: f64,
    pub brake: f64,
}

/// The per-state constants of a row: the affine maps of (B.1) at v_i and the full-pedal fuel
/// (Euler: the whole stage's; trapezoid: the half at v_i; NaN for a map-based truck, whose fuel is
/// evaluated at each pedal level), and with the trapezoid stage what the maps at the end speed
/// need.
#[derive(Debug, Clone, Copy)]
struct RowMaps<'a> {
    pedal: AffineAccel,
    /// The brake's map, for Euler rows (a trapezoid row evaluates it at its few brake pairs).
    brake: Option<AffineAccel>,
    full_fuel_g: f64,
    trapezoid: Option<EndMaps<'a>>,
    /// For a map-based truck, whose fuel is not proportional to the pedal: the vehicle and gear to
    /// evaluate the fuel of each pedal level with (None: fuel = full-pedal fuel × pedal).
    map_fuel: Option<(&'a Vehicle, usize)>,
}

impl RowMaps<'_> {
    /// Fuel [g] of an Euler stage from `v_i` with `pedal` ∈ [0, 1] (length `h_m`).
    #[inline]
    fn euler_fuel_g(&self, v_i: f64, pedal: f64, h_m: f64) -> f64 {
        match self.map_fuel {
            None => self.full_fuel_g * pedal,
            Some((vehicle, gear)) => stage_fuel_g(vehicle, v_i, pedal, gear, h_m),
        }
    }
}

/// What a trapezoid stage evaluates at its end speed (the vehicle, the gear and the slope), and the
/// pedal levels its row accepts ([`trapezoid_pedal_band`], a function of v_i alone).
#[derive(Debug, Clone, Copy)]
struct EndMaps<'a> {
    vehicle: &'a Vehicle,
    gear: usize,
    slope_torque: f64,
    pedal_band: (f64, f64),
}

fn maps<'a>(vehicle: &'a Vehicle, p: &DpSettings, v_i: f64, gear: usize, slope_torque: f64) -> RowMaps<'a> {
    let trapezoid = p.mpc.stage_model == StageModel::Trapezoid;
    let pedal = pedal_accel_on(vehicle, v_i, gear, slope_torque);
    let map_fuel = (vehicle.rate_form() == RateForm::Map).then_some((vehicle, gear));
    RowMaps {
        pedal,
        brake: (!trapezoid).then(|| brake_accel_on(vehicle, v_i, gear, slope_torque)),
        full_fuel_g: match (map_fuel, trapezoid) {
            (Some(_), _) => f64::NAN,
            (None, true) => stage::half_stage_fuel_g(vehicle, v_i, 1.0, gear, p.mpc.stage_m),
            (None, false) => stage_fuel_g(vehicle, v_i, 1.0, gear, p.mpc.stage_m),
        },
        trapezoid: trapezoid.then(|| {
            let pedal_band = if pedal.gain > 0.0 { trapezoid_pedal_band(p, v_i, pedal.gain) } else { (0.0, 0.0) };
            EndMaps { vehicle, gear, slope_torque, pedal_band }
        }),
        map_fuel,
    }
}

/// A row's span `(first, last)` of grid indices limited to the targets [`pair`] admits: speeds
/// above standstill and at most [`REACH_BEYOND_V_MAX`] grid steps beyond `v_max` [m/s], the top of
/// the next stage's band (`delta_mps` the grid step). No target outside reaches the next stage's
/// grid; the ends are found on the grid's own speeds, so a row and `pair` agree at every index.
#[inline]
fn clamp_span((first, last): (i64, i64), grid: GridIndex, v_max: f64, delta_mps: f64) -> (i64, i64) {
    let top = v_max + REACH_BEYOND_V_MAX * delta_mps;
    if !(top.is_finite() && grid.delta_mps > 0.0 && grid.origin_mps.is_finite()) {
        return (first, last);
    }
    let mut lowest = grid.floor(0.0);
    while grid.speed(lowest) > 0.0 {
        lowest -= 1;
    }
    while !(grid.speed(lowest) > 0.0) {
        lowest += 1;
    }
    let mut highest = grid.floor(top);
    while grid.speed(highest) > top {
        highest -= 1;
    }
    while grid.speed(highest + 1) <= top {
        highest += 1;
    }
    (first.max(lowest), last.min(highest))
}

/// Grid steps beyond v_max that a row covers and [`pair`] admits (the brake points lie within one).
const REACH_BEYOND_V_MAX: f64 = 2.0;

/// Trim a row's unreachable ends (appended to `out` from `start`, its first index `first`) so the
/// min-plus loop never scans them.
fn trim(out: &mut Vec<f64>, start: usize, first: i64) -> (RowSpan, usize) {
    let row = &out[start..];
    let Some(lead) = row.iter().position(|c| c.is_finite()) else {
        out.truncate(start);
        return (RowSpan { first: 0, len: 0 }, start);
    };
    let trail = row.iter().rev().take_while(|c| !c.is_finite()).count();
    let len = row.len() - lead - trail;
    out.truncate(start + lead + len);
    (RowSpan { first: first + lead as i64, len }, start + lead)
}

/// The cost of a speed change `dv` [m/s] over a stage: Q3·|Δv| plus, with the fuel_time cost,
/// the Euler stage's energy error priced in fuel ([`DpSettings::q_speed_change_sq`]).
#[inline]
pub fn change_cost(q_change: f64, q_change_sq: f64, dv: f64) -> f64 {
    q_change * dv.abs() + q_change_sq * (dv * dv)
}

/// Inputs and their stage cost (Q1·fuel + Q3·|Δv| (+ Euler correction) + Q5·B) for one pair,
/// None if inadmissible; `v_max` [m/s] is the top of the next stage's band.
#[inline]
fn pair(p: &DpSettings, m: &RowMaps, v_i: f64, v_j: f64, v_max: f64) -> Option<(Inputs, f64)> {
    if !(v_j > 0.0 && v_j <= v_max + REACH_BEYOND_V_MAX * p.delta_mps()) {
        return None;
    }
    if let Some(end) = &m.trapezoid {
        let fuel = |pedal: f64| map_stage_fuel_g(end, (v_i, v_j), pedal, p.mpc.stage_m);
        return pair_trapezoid(p, (m, end), (v_i, v_j, v_max), || AtEnd::at(end, v_j, p.mpc.stage_m), fuel);
    }
    pair_euler(p, m, v_i, v_j, v_max)
}

/// Append to `out` the costs of joining `v_i` in forward `gear` to the grid indices of the next
/// stage; return their span and where its first cost is in `out`. `known_ends`: the end speeds
/// [m/s] at zero and at full pedal (the pedal branch's) where the caller has them exactly, which a
/// trapezoid row then takes for the ends of its span instead of iterating for them. Indices no
/// input reaches inside the span hold +∞; a row with no admissible target appends nothing (len 0). Each cost is
/// [`pair`]'s, bit for bit, but for a map-based truck's fuel on a fixed grid, which is interpolated
/// over the pedal (within 0.1 % of the full-pedal fuel). `v_max_mps` is the top of the next
/// stage's band. `memo` keeps what trapezoid rows evaluate at each end speed.
#[allow(clippy::too_many_arguments)]
pub fn forward_row(
    vehicle: &Vehicle,
    p: &DpSettings,
    (v_i, known_ends): (f64, [Option<f64>; 2]),
    gear: usize,
    slope_torque: f64,
    grid: GridIndex,
    v_max_mps: f64,
    (out, memo): (&mut Vec<f64>, &mut RowMemo),
) -> (RowSpan, usize) {
    let (from, target) = ((v_i, gear, slope_torque), (grid, v_max_mps));
    match p.mpc.stage_model {
        StageModel::Trapezoid => forward_row_trapezoid((vehicle, p), from, known_ends, target, (out, memo)),
        StageModel::Euler => forward_row_euler((vehicle, p), from, target, out),
    }
}

/// The inputs of one admissible pair (the solver recomputes them for the path it keeps); `v_max`
/// [m/s] is the top of the next stage's band.
pub fn inputs(
    vehicle: &Vehicle,
    p: &DpSettings,
    (v_i, v_j, v_max): (f64, f64, f64),
    gear: usize,
    slope_torque: f64,
) -> Option<Inputs> {
    pair(p, &maps(vehicle, p, v_i, gear, slope_torque), v_i, v_j, v_max).map(|(inputs, _)| inputs)
}

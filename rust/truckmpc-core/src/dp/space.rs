//! The search space of section 5.4: usable gears per speed (5.7), the reachable speed interval
//! per stage cut to the allowed band, the backward pass from the final stage's v_ref bound, and
//! the velocity grid of each stage (5.8). Speeds in m/s.

use super::params::{DpSettings, GridAnchor};
use super::rows::GridIndex;
use super::shift;
use super::stage::{self, Branch};
use crate::band::BandAt;
use crate::vehicle::{Vehicle, NEUTRAL};

/// Forward gears whose engine speed at `v_mps` lies in [n_min, n_max], as an inclusive range of
/// gear numbers (engine speed falls with the gear number, so the set is contiguous); None if empty.
pub fn usable_gears(vehicle: &Vehicle, v_mps: f64, n_min_rpm: f64, n_max_rpm: f64) -> Option<(usize, usize)> {
    let mut range: Option<(usize, usize)> = None;
    for g in 1..=vehicle.forward_gears() {
        let n = vehicle.gear(g).c4 * v_mps;
        if n >= n_min_rpm && n <= n_max_rpm {
            range = Some(match range {
                None => (g, g),
                Some((lo, _)) => (lo, g),
            });
        }
    }
    range
}

/// Gears used to bound reachability from `v_mps`: the usable ones, or if none, the forward gear
/// whose engine speed is closest to the window (so a truck outside the window still has a bound).
fn reach_gears(vehicle: &Vehicle, params: &DpSettings, v_mps: f64) -> (usize, usize) {
    usable_gears(vehicle, v_mps, params.mpc.n_min_rpm, params.mpc.n_max_rpm).unwrap_or_else(|| {
        let distance = |g: usize| {
            let n = vehicle.gear(g).c4 * v_mps;
            (params.mpc.n_min_rpm - n).max(n - params.mpc.n_max_rpm)
        };
        let best = (1..=vehicle.forward_gears()).min_by(|&a, &b| distance(a).total_cmp(&distance(b))).unwrap();
        (best, best)
    })
}

/// Speeds after one stage at full pedal, over the reachability gears: (max, min) [m/s].
/// Neutral counts towards the maximum when allowed: on a steep descent it can beat a gear. For a
/// truck whose shifts interrupt traction the minimum counts a stage that shifts into the gear
/// (the roll, then full pedal over the rest): on a climb the band a path must keep to is then wide
/// enough for a shift's lost speed.
fn full_pedal_speeds(vehicle: &Vehicle, params: &DpSettings, v_mps: f64, slope: f64) -> (f64, f64) {
    let (lo, hi) = reach_gears(vehicle, params, v_mps);
    let torque = vehicle.slope_torque_nm(slope);
    let mut best = f64::NEG_INFINITY;
    let mut worst = f64::INFINITY;
    let roll = shift::planned(params, vehicle)
        .then(|| shift::interruption(vehicle, v_mps, torque, params.mpc.stage_m))
        .flatten();
    for g in lo..=hi {
        let v1 = end_of_stage(vehicle, params, v_mps, g, torque, (Branch::Pedal, 1.0));
        best = best.max(v1);
        worst = worst.min(v1);
        if let Some(roll) = &roll {
            let rest = params.mpc.stage_m - roll.d_m;
            let model = params.mpc.stage_model;
            let shifted = stage::end_speed(model, vehicle, (roll.v_mps, rest), g, torque, (Branch::Pedal, 1.0));
            worst = worst.min(shifted);
        }
    }
    if params.mpc.allow_neutral {
        best = best.max(end_of_stage(vehicle, params, v_mps, NEUTRAL, torque, (Branch::Brake, 0.0)));
    }
    (best, worst)
}

/// Lowest speed after one stage without brakes: fuel cut in the gear with the most engine drag.
fn lowest_speed(vehicle: &Vehicle, params: &DpSettings, v_mps: f64, slope: f64) -> f64 {
    let (lo, hi) = reach_gears(vehicle, params, v_mps);
    let torque = vehicle.slope_torque_nm(slope);
    let mut v_min = f64::INFINITY;
    for g in lo..=hi {
        v_min = v_min.min(end_of_stage(vehicle, params, v_mps, g, torque, (Branch::Brake, 0.0)));
    }
    if params.mpc.allow_neutral {
        v_min = v_min.min(end_of_stage(vehicle, params, v_mps, NEUTRAL, torque, (Branch::Brake, 0.0)));
    }
    v_min
}

/// End speed of one stage from `v_mps` in `gear` by the settings' stage model.
fn end_of_stage(
    vehicle: &Vehicle,
    params: &DpSettings,
    v_mps: f64,
    gear: usize,
    torque: f64,
    input: (Branch, f64),
) -> f64 {
    stage::end_speed(params.mpc.stage_model, vehicle, (v_mps, params.mpc.stage_m), gear, torque, input)
}

/// One stage's velocity grid: v(j) = first_mps + j·δ for j in 0..count.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Grid {
    /// Speed of the first grid point [m/s].
    pub first_mps: f64,
    /// Number of grid points.
    pub count: usize,
}

impl Grid {
    /// Speed of grid point `j` [m/s].
    #[inline]
    pub fn speed(&self, j: usize, delta_mps: f64) -> f64 {
        self.first_mps + j as f64 * delta_mps
    }
}

/// Considered speed intervals [lo, hi] of stages 0..=N [m/s]; stage 0 is the initial speed.
#[derive(Debug, Clone, Default)]
pub struct Intervals {
    pub lo: Vec<f64>,
    pub hi: Vec<f64>,
}

/// Forward reachability from `v0_mps` cut to each stage's [v_min, v_max] (5.4.2; `bands` holds
/// the band of stages 0..=N), then the final stage's lower bound raised to its v_ref and the
/// backward pass removing speeds that cannot reach it. On a fixed grid the bounds are grid speeds
/// found from grid speeds ([`grid_forward`], [`grid_backward`]).
pub fn intervals(
    vehicle: &Vehicle,
    params: &DpSettings,
    v0_mps: f64,
    slopes: &[f64],
    bands: &[BandAt],
    out: &mut Intervals,
) {
    intervals_from_stage(vehicle, params, v0_mps, slopes, bands, None, true, out)
}

/// As [`intervals`], with the final stage's lower bound raised to its v_ref only when `raise_end`,
/// and with the absolute index of the first stage and a memo kept across solves:
/// each step of the forward and backward passes is a function of its stage's slope and its input
/// bounds only, and successive receding horizons mostly repeat the same steps at the same road
/// stages (the chains of bounds meet). A step whose stage, slope and inputs (bit for bit) are
/// those of the memo returns the memo's output, which is what computing it would give (a stage's
/// band is a function of its position, so of its absolute index, too).
pub fn intervals_from_stage(
    vehicle: &Vehicle,
    params: &DpSettings,
    v0_mps: f64,
    slopes: &[f64],
    bands: &[BandAt],
    memo: Option<(u64, &mut IntervalMemo)>,
    raise_end: bool,
    out: &mut Intervals,
) {
    debug_assert_eq!(bands.len(), slopes.len() + 1);
    let (forward, backward): (StepFn<2>, StepFn<1>) = match params.mpc.grid {
        GridAnchor::Moving => (continuous_forward, continuous_backward),
        GridAnchor::Fixed => (grid_forward, grid_backward),
    };
    let mut memo = memo.map(|(stage, memo)| {
        memo.prepare(slopes.len());
        (stage, memo)
    });
    out.lo.clear();
    out.hi.clear();
    out.lo.push(v0_mps);
    out.hi.push(v0_mps);
    for (k, &slope) in slopes.iter().enumerate() {
        let input = [out.lo[k], out.hi[k], 0.0];
        let band = &bands[k + 1];
        let [lo, hi] = match &mut memo {
            Some((stage, memo)) => {
                memo.forward.get(*stage + k as u64, slope, input, |x| forward(vehicle, params, band, x, slope))
            }
            None => forward(vehicle, params, band, input, slope),
        };
        out.lo.push(lo);
        out.hi.push(hi);
    }
    let n = slopes.len();
    // Without the raise the final stage keeps its reachable speeds: the terminal cost prices them.
    let v_ref_end = if raise_end { bands[n].v_ref_mps() } else { out.lo[n] };
    out.lo[n] = match params.mpc.grid {
        GridAnchor::Moving => v_ref_end.min(out.hi[n]),
        GridAnchor::Fixed => {
            let grid = GridIndex { origin_mps: 0.0, delta_mps: params.delta_mps() };
            grid.speed(grid.ceil(v_ref_end).min(index_of(params, out.hi[n])))
        }
    };
    for k in (1..n).rev() {
        let input = [out.lo[k], out.hi[k], out.lo[k + 1]];
        let band = &bands[k];
        let [lo] = match &mut memo {
            Some((stage, memo)) => memo
                .backward
                .get(*stage + k as u64, slopes[k], input, |x| backward(vehicle, params, band, x, slopes[k])),
            None => backward(vehicle, params, band, input, slopes[k]),
        };
        out.lo[k] = lo;
    }
}

/// One step of a pass: (band, inputs, slope) to outputs. Forward: [lo, hi, _] of stage k to
/// [lo, hi] of stage k + 1 in that stage's band; backward: [lo, hi, lo of stage k + 1] of stage k
/// to its new lo.
type StepFn<const N: usize> = fn(&Vehicle, &DpSettings, &BandAt, [f64; 3], f64) -> [f64; N];

/// Steps of one pass remembered per absolute stage (a ring over the horizon's stages).
#[derive(Debug, Clone, Default)]
pub struct StepMemo<const N: usize> {
    entries: Vec<MemoEntry<N>>,
}

#[derive(Debug, Clone, Copy)]
struct MemoEntry<const N: usize> {
    stage: u64,
    slope: u64,
    input: [u64; 3],
    output: [f64; N],
}

impl<const N: usize> MemoEntry<N> {
    /// No step (no stage has this index).
    const EMPTY: Self = MemoEntry { stage: u64::MAX, slope: 0, input: [0; 3], output: [0.0; N] };
}

impl<const N: usize> StepMemo<N> {
    fn get(&mut self, stage: u64, slope: f64, input: [f64; 3], step: impl FnOnce([f64; 3]) -> [f64; N]) -> [f64; N] {
        let len = self.entries.len() as u64;
        let entry = &mut self.entries[(stage % len) as usize];
        let key = (stage, slope.to_bits(), input.map(f64::to_bits));
        if (entry.stage, entry.slope, entry.input) == key {
            return entry.output;
        }
        let output = step(input);
        *entry = MemoEntry { stage: key.0, slope: key.1, input: key.2, output };
        output
    }
}

/// The memo of both passes, kept by the solver across solves.
#[derive(Debug, Clone, Default)]
pub struct IntervalMemo {
    forward: StepMemo<2>,
    backward: StepMemo<1>,
}

impl IntervalMemo {
    /// Room for horizons of `stages` stages (one entry per stage and pass).
    fn prepare(&mut self, stages: usize) {
        let size = stages + 1;
        if self.forward.entries.len() != size {
            self.forward.entries = vec![MemoEntry::EMPTY; size];
            self.backward.entries = vec![MemoEntry::EMPTY; size];
        }
    }
}

/// How far below fuel cut a stage's end speeds count as reached on a fixed grid [m/s]: a grid step
/// with fuel-cut arcs, so that the grid points around any arc's end are states; half a step when
/// the pedal tolerance is half a grid step (ε without a value), where a row admits the grid point
/// within that distance below fuel cut; 0 with a fixed ε, as in the thesis.
fn band_slack_mps(params: &DpSettings) -> f64 {
    if params.mpc.fuel_cut_arcs {
        params.delta_mps()
    } else if params.mpc.epsilon.is_none() {
        0.5 * params.delta_mps()
    } else {
        0.0
    }
}

/// The thesis's forward step (5.4.2), bounds as continuous speeds [m/s].
fn continuous_forward(
    vehicle: &Vehicle,
    params: &DpSettings,
    band: &BandAt,
    [prev_lo, hi, _]: [f64; 3],
    slope: f64,
) -> [f64; 2] {
    let (v_min, v_max) = (band.v_min_mps(), band.v_max_mps());
    let (v_plus, v_plus_low) = full_pedal_speeds(vehicle, params, hi, slope);
    let v_minus = lowest_speed(vehicle, params, prev_lo, slope);
    let hi = v_plus.min(v_max);
    let lo = if v_plus >= v_min { v_minus.max(v_min).min(v_max) } else { v_plus_low.min(hi) };
    let lo = lagging_low(vehicle, params, (lo, hi), (prev_lo, v_plus >= v_min), slope).unwrap_or(lo);
    [lo.min(hi), hi]
}

/// Shifts' lost speed a path may lag the free-shift chain by before the band cuts it.
const LAGGED_SHIFTS: f64 = 3.0;

/// The bottom `lo` of a stage whose band is `[lo, hi]` [m/s], lowered for a truck whose planned
/// shifts interrupt traction. The band's top is the chain of full pedal in the best gear at every
/// stage, as if shifts were free, and its bottom is v_min wherever that chain reaches v_min
/// (`holds`): on a climb and after it a path that shifts lags that chain by each shift's roll
/// (downshifts on the way up, upshifts where the grade eases), and would find no state left. On a
/// climb the bottom may lie [`LAGGED_SHIFTS`] rolls below the top (a roll's loss: a stage of full
/// pedal in the best gear from the top's speed against one that shifts into it, on this stage's
/// grade). Where the top holds v_min the bottom stays below v_min only as far as a lag carries
/// on: no higher than full pedal takes the previous bottom `prev_lo`, nor than the rolls' room
/// below the top, so a truck that could hold v_min is not planned below it. None where the plan
/// does not model the interruption or no shift can start.
fn lagging_low(
    vehicle: &Vehicle,
    params: &DpSettings,
    (lo, hi): (f64, f64),
    (prev_lo, holds): (f64, bool),
    slope: f64,
) -> Option<f64> {
    let lagged = hi - LAGGED_SHIFTS * roll_loss(vehicle, params, hi, slope)?;
    let floor = if holds { lagged.max(full_pedal_speeds(vehicle, params, prev_lo, slope).0) } else { lagged };
    Some(lo.min(floor).min(hi))
}

/// Speed one shift's roll costs over a stage from `v_mps` [m/s]: full pedal in the best gear
/// against a stage that shifts into it (None where the plan does not model the interruption or no
/// shift can start).
fn roll_loss(vehicle: &Vehicle, params: &DpSettings, v_mps: f64, slope: f64) -> Option<f64> {
    if !shift::planned(params, vehicle) {
        return None;
    }
    let torque = vehicle.slope_torque_nm(slope);
    let roll = shift::interruption(vehicle, v_mps, torque, params.mpc.stage_m)?;
    let (lo, hi) = reach_gears(vehicle, params, v_mps);
    let model = params.mpc.stage_model;
    let rest = (roll.v_mps, params.mpc.stage_m - roll.d_m);
    let pedal = (Branch::Pedal, 1.0);
    let free = (lo..=hi).map(|g| end_of_stage(vehicle, params, v_mps, g, torque, pedal)).fold(f64::MIN, f64::max);
    let shifted = (lo..=hi).map(|g| stage::end_speed(model, vehicle, rest, g, torque, pedal)).fold(f64::MIN, f64::max);
    Some((free - shifted).max(0.0))
}

/// The thesis's backward step: raise lo to the lowest speed that reaches the next stage's lo.
fn continuous_backward(
    vehicle: &Vehicle,
    params: &DpSettings,
    _band: &BandAt,
    [lo, hi, target]: [f64; 3],
    slope: f64,
) -> [f64; 1] {
    let needed = min_speed_reaching(vehicle, params, lo, hi, slope, target);
    [lo.max(needed)]
}

/// Index of a bound already on the fixed grid (multiples of δ).
fn index_of(params: &DpSettings, v_mps: f64) -> i64 {
    (v_mps / params.delta_mps()).round() as i64
}

/// The forward step of 5.4.2 on a fixed grid: every bound is a multiple of δ, and each stage's
/// bounds are found from the previous stage's grid bounds, not from continuous speeds. The top of
/// stage k + 1 is the highest grid speed that full pedal reaches from the top of stage k. Rounding
/// continuous bounds instead breaks the chain on long climbs: the last stage's bound (the end of
/// the continuous full-pedal chain) then lies above what any grid path can reach.
fn grid_forward(
    vehicle: &Vehicle,
    params: &DpSettings,
    band: &BandAt,
    [prev_lo, hi, _]: [f64; 3],
    slope: f64,
) -> [f64; 2] {
    let (v_min_mps, v_max_mps) = (band.v_min_mps(), band.v_max_mps());
    // Multiples of δ: index i is the speed i·δ [m/s].
    let grid = GridIndex { origin_mps: 0.0, delta_mps: params.delta_mps() };
    let top = grid.floor(v_max_mps);
    let (v_plus, v_plus_low) = full_pedal_speeds(vehicle, params, hi, slope);
    // Only below: above, slack would compound along the full-pedal chain over the horizon, and a
    // final bound raised to v_ref on a climb would then lie beyond every grid path. Below it
    // compounds too, which keeps every state's fuel-cut arc bracketed; the band's v_min cuts it.
    let v_minus = lowest_speed(vehicle, params, prev_lo, slope) - band_slack_mps(params);
    let hi = grid.floor(v_plus).min(top);
    let lo = if v_plus >= v_min_mps { grid.ceil(v_minus.max(v_min_mps)) } else { grid.floor(v_plus_low) };
    let holds = v_plus >= v_min_mps;
    let lo = match lagging_low(vehicle, params, (grid.speed(lo), grid.speed(hi)), (prev_lo, holds), slope) {
        Some(lagging) => lo.min(grid.floor(lagging)),
        None => lo,
    };
    [grid.speed(lo.min(hi)), grid.speed(hi)]
}

/// The backward step on a fixed grid: the lowest grid speed of the stage from which full pedal
/// reaches the next stage's lowest one.
fn grid_backward(
    vehicle: &Vehicle,
    params: &DpSettings,
    _band: &BandAt,
    [lo, hi, target]: [f64; 3],
    slope: f64,
) -> [f64; 1] {
    let grid = GridIndex { origin_mps: 0.0, delta_mps: params.delta_mps() };
    let (lo, hi) = (index_of(params, lo), index_of(params, hi));
    let target = index_of(params, target);
    let reaches = |index: i64| grid.floor(full_pedal_speeds(vehicle, params, grid.speed(index), slope).0) >= target;
    // Full-pedal end speed grows with the start speed: bisect for the lowest index that reaches.
    let needed = if reaches(lo) {
        lo
    } else if !reaches(hi) {
        hi
    } else {
        let (mut a, mut b) = (lo, hi);
        while b - a > 1 {
            let mid = a + (b - a) / 2;
            if reaches(mid) {
                b = mid;
            } else {
                a = mid;
            }
        }
        b
    };
    [grid.speed(needed)]
}

/// Smallest speed in [lo, hi] from which full pedal reaches `target` in one stage (bisection to a
/// hundredth of δ; full-pedal end speed grows with the start speed). Returns `hi` if none does.
fn min_speed_reaching(vehicle: &Vehicle, params: &DpSettings, lo: f64, hi: f64, slope: f64, target: f64) -> f64 {
    let reaches = |v: f64| full_pedal_speeds(vehicle, params, v, slope).0 >= target;
    if reaches(lo) {
        return lo;
    }
    if !reaches(hi) {
        return hi;
    }
    let (mut a, mut b) = (lo, hi);
    let tolerance = 0.01 * params.delta_mps();
    while b - a > tolerance {
        let mid = 0.5 * (a + b);
        if reaches(mid) {
            b = mid;
        } else {
            a = mid;
        }
    }
    b
}

/// The velocity grid of an interval (5.8), moving (anchored at lo) or fixed (multiples of δ).
pub fn grid(params: &DpSettings, lo: f64, hi: f64) -> Grid {
    let delta = params.delta_mps();
    // Absorbs rounding so that an interval exactly k·δ wide keeps its last point.
    const SLACK: f64 = 1e-9;
    match params.mpc.grid {
        GridAnchor::Moving => {
            Grid { first_mps: lo, count: super::rows::floor_i64((hi - lo) / delta + SLACK).max(0) as usize + 1 }
        }
        GridAnchor::Fixed => {
            // The bounds are multiples of δ already ([`grid_intervals`]).
            let first = (lo / delta).round();
            let last = (hi / delta).round().max(first);
            Grid { first_mps: first * delta, count: (last - first) as usize + 1 }
        }
    }
}

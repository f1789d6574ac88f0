//! The receding-horizon step of section 5.6 on a road: the slopes the DP sees ahead of a position,
//! and the prediction of the speed one stage ahead under the inputs being applied now.

use super::solver::{InitialState, Solution, Solver};
use super::stage::{self, StageModel};
use super::values::ValueTable;
use crate::band::{BandAt, SpeedBand};
use crate::levels::euler_step;
use crate::plant::Control;
use crate::road::Road;
use crate::vehicle::Vehicle;

/// Mean grade of each of the `stages` stages of length `stage_m` starting at `s0_m` (the road is
/// flat beyond its end), written into `out`.
pub fn stage_slopes(road: &Road, s0_m: f64, stage_m: f64, stages: usize, out: &mut Vec<f64>) {
    out.clear();
    let mut hint = usize::MAX;
    out.extend((0..stages).map(|k| {
        let a = s0_m + k as f64 * stage_m;
        road.mean_slope_from(a, a + stage_m, &mut hint)
    }));
}

/// The band at each of the `stages + 1` stage boundaries from `s0_m`, written into `out`. The DP
/// bounds speeds at the boundaries only, so a boundary where a higher stretch begins keeps the
/// band of the stage before it (the lower of the two tops): the truck enters the faster stretch at
/// the slower one's speed rather than speeding up ahead of it.
pub fn stage_bands(band: &SpeedBand, s0_m: f64, stage_m: f64, stages: usize, out: &mut Vec<BandAt>) {
    bands_at(band, (0..=stages).map(|k| s0_m + k as f64 * stage_m), out);
}

/// The bands of [`stage_bands`] at the given boundary positions [m], in order.
pub fn bands_at(band: &SpeedBand, positions: impl Iterator<Item = f64>, out: &mut Vec<BandAt>) {
    out.clear();
    let mut hint = 0;
    let mut positions = positions;
    let Some(first_m) = positions.next() else { return };
    let mut before = band.at(first_m, &mut hint);
    out.push(before);
    for s_m in positions {
        let here = band.at(s_m, &mut hint);
        out.push(if before.v_max_kmh < here.v_max_kmh { before } else { here });
        before = here;
    }
}

/// Speed [m/s] one stage ahead of `s_m` with `u` held, by the controller's own stage model on the
/// stage's mean slope (the thesis's Euler stage (5.4) is kept bit for bit).
pub fn predict_speed(
    (vehicle, model): (&Vehicle, StageModel),
    road: &Road,
    s_m: f64,
    v_mps: f64,
    u: Control,
    stage_m: f64,
) -> f64 {
    let slope = road.mean_slope(s_m, s_m + stage_m);
    match model {
        StageModel::Euler => euler_step(vehicle, v_mps, u.pedal, u.brake, u.gear, slope, stage_m),
        StageModel::Trapezoid => {
            let torque = vehicle.slope_torque_nm(slope);
            stage::end_speed_with(model, vehicle, (v_mps, stage_m), (u.pedal, u.brake, u.gear), torque)
        }
    }
}

/// The slopes and bands of a horizon: scratch for [`solve_at`], and what a recorded solve's stages
/// saw ([`solve_recording_at`]).
#[derive(Debug, Clone, Default)]
pub struct HorizonScratch {
    pub slopes: Vec<f64>,
    pub bands: Vec<BandAt>,
}

/// Solve the DP for the horizon starting at `s_m` from `start` in `band` (which varies along a
/// road with target speeds). A horizon that starts on a stage boundary counted from the road's
/// start gets its absolute stage index, so a fixed-grid solver can reuse transition costs from
/// the solves before.
pub fn solve_at(
    solver: &mut Solver,
    vehicle: &Vehicle,
    (road, band): (&Road, &SpeedBand),
    s_m: f64,
    start: InitialState,
    scratch: &mut HorizonScratch,
) -> Solution {
    let stages = solver.params().stages();
    let first_stage = ahead(solver, (road, band), s_m, stages, scratch);
    if !band.varies() {
        return solver.solve_from_stage(vehicle, start, &scratch.slopes, first_stage);
    }
    solver.solve_in_bands(vehicle, start, &scratch.slopes, &scratch.bands, first_stage)
}

/// As [`solve_at`] over `stages` stages (the horizon and the stages to be decided from it), every
/// stage's cost-to-go kept in `table`; the slopes and bands stay in `scratch` (bands empty on a
/// road without target speeds).
pub fn solve_recording_at(
    solver: &mut Solver,
    vehicle: &Vehicle,
    (road, band): (&Road, &SpeedBand),
    (s_m, stages): (f64, usize),
    start: InitialState,
    scratch: &mut HorizonScratch,
    table: &mut ValueTable,
) -> Solution {
    let first_stage = ahead(solver, (road, band), s_m, stages, scratch);
    let bands = band.varies().then_some(&scratch.bands[..]);
    solver.solve_horizon_recording(vehicle, start, (&scratch.slopes, bands), first_stage, table)
}

/// The slopes (and, where the band varies, the bands) of `stages` stages from `s_m` into
/// `scratch`; the absolute index of the first stage when `s_m` is a stage boundary of the road.
fn ahead(
    solver: &Solver,
    (road, band): (&Road, &SpeedBand),
    s_m: f64,
    stages: usize,
    scratch: &mut HorizonScratch,
) -> Option<u64> {
    let stage_m = solver.params().mpc.stage_m;
    stage_slopes(road, s_m, stage_m, stages, &mut scratch.slopes);
    let first_stage = boundary_stage(road.start_m(), s_m, stage_m).map(|k| k as u64);
    scratch.bands.clear();
    if !band.varies() {
        return first_stage;
    }
    // On a boundary, positions come from the absolute index (as the cache's key does), so a
    // stage's band cannot differ between solves by a rounding at a stretch's start.
    match first_stage {
        Some(first) => {
            let positions = (first..=first + stages as u64).map(|j| road.start_m() + j as f64 * stage_m);
            bands_at(band, positions, &mut scratch.bands);
        }
        None => stage_bands(band, s_m, stage_m, stages, &mut scratch.bands),
    }
    first_stage
}

/// The index of the stage boundary at `s_m` [m], stages of `stage_m` [m] counted from `origin_m`;
/// None when `s_m` lies before `origin_m` or more than a micrometre off every boundary.
pub fn boundary_stage(origin_m: f64, s_m: f64, stage_m: f64) -> Option<usize> {
    let stages_in = (s_m - origin_m) / stage_m;
    let on_boundary = stages_in >= 0.0 && (stages_in - stages_in.round()).abs() * stage_m < 1e-6;
    on_boundary.then(|| stages_in.round() as usize)
}

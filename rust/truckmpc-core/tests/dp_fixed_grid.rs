//! The fixed grid's search space: when a horizon ends on a long climb, the considered speeds of the
//! last stages shrink to the full-pedal chain. On a fixed grid that chain must be followed on grid
//! speeds, or its end lies above what any grid path reaches and every solve there is infeasible.

mod common;

use truckmpc_core::dp::space::{intervals, Intervals};
use truckmpc_core::dp::{DpSettings, GridAnchor, InitialState, Solver};
use truckmpc_core::{Vehicle, VehicleParams};

/// Slopes of a horizon of `stages` stages: flat, then a climb of `grade` from stage `climb_from`.
fn climb(stages: usize, climb_from: usize, grade: f64) -> Vec<f64> {
    (0..stages).map(|k| if k >= climb_from { grade } else { 0.0 }).collect()
}

fn params(delta_kmh: f64) -> DpSettings {
    DpSettings::thesis()
        .with_mpc(|m| (m.grid, m.delta_kmh, m.horizon_m, m.stage_m) = (GridAnchor::Fixed, delta_kmh, 3000.0, 25.0))
}

#[test]
fn horizons_ending_on_a_climb_are_feasible_on_the_fixed_grid() {
    let vehicle = Vehicle::new(VehicleParams::default()).unwrap();
    let mut checked = 0;
    for delta_kmh in [0.1, 0.2, 0.5] {
        let p = params(delta_kmh);
        let mut solver = Solver::new(p.clone());
        for grade in [0.015, 0.025, 0.032, 0.045] {
            for climb_from in [20, 60, 100, 115] {
                for v0_kmh in [80.3, 84.17, 85.0, 88.91] {
                    let slopes = climb(p.stages(), climb_from, grade);
                    let start = InitialState { v_mps: v0_kmh / 3.6, gear: 12, stages_since_shift: p.k_lim };
                    let sol = solver.solve(&vehicle, start, &slopes);
                    assert!(
                        sol.feasible,
                        "infeasible: δ {delta_kmh} km/h, {grade} grade from stage {climb_from}, start {v0_kmh} km/h"
                    );
                    checked += 1;
                }
            }
        }
    }
    assert_eq!(checked, 3 * 4 * 4 * 4);
}

#[test]
fn fixed_grid_bounds_are_grid_speeds_below_v_max() {
    let vehicle = Vehicle::new(VehicleParams::default()).unwrap();
    let p = params(0.2);
    let delta = p.delta_mps();
    let slopes = climb(p.stages(), 70, 0.03);
    let mut iv = Intervals::default();
    intervals(&vehicle, &p, 84.17 / 3.6, &slopes, &vec![p.band(); slopes.len() + 1], &mut iv);
    let on_grid = |v: f64| ((v / delta) - (v / delta).round()).abs() < 1e-9;
    for k in 1..=slopes.len() {
        assert!(on_grid(iv.lo[k]) && on_grid(iv.hi[k]), "stage {k}: bounds off the grid");
        assert!(iv.lo[k] <= iv.hi[k] + 1e-12, "stage {k}: empty interval");
        assert!(iv.hi[k] <= p.v_max_mps() + 1e-9, "stage {k}: above v_max");
    }
    // The climb outlasts the horizon's end: the final bound falls below v_ref (the chain case).
    assert!(iv.lo[slopes.len()] < p.v_ref_mps());
}

/// With the pedal tolerance of half a grid step (ε without a value), the grid point nearest to the
/// fuel-cut end speed is a state of stage 1 even when it lies below that speed: a row reaches it
/// (clipped to zero pedal), so the search space must hold it. With the thesis's fixed ε the lower
/// bound stays at the first grid speed at or above fuel cut.
#[test]
fn half_step_tolerance_keeps_the_grid_point_nearest_to_fuel_cut() {
    use truckmpc_core::levels::brake_accel;
    let vehicle = Vehicle::new(VehicleParams::default()).unwrap();
    let mut below = 0;
    for epsilon in [None, Some(0.1)] {
        for delta_kmh in [0.1, 0.4] {
            let p = params(delta_kmh).with_mpc(|m| (m.epsilon, m.allow_neutral) = (epsilon, false));
            let delta = p.delta_mps();
            for step in 0..40 {
                let v0 = (82.0 + 0.137 * step as f64) / 3.6;
                let slope = -0.005;
                let slopes = vec![slope; p.stages()];
                let mut iv = Intervals::default();
                intervals(&vehicle, &p, v0, &slopes, &vec![p.band(); slopes.len() + 1], &mut iv);
                // Fuel cut in the gear with the most engine drag among those usable at v0.
                let (lo, hi) =
                    truckmpc_core::dp::space::usable_gears(&vehicle, v0, p.mpc.n_min_rpm, p.mpc.n_max_rpm).unwrap();
                let cut = (lo..=hi)
                    .map(|g| brake_accel(&vehicle, v0, g, slope).step(v0, p.mpc.stage_m, 0.0))
                    .fold(f64::INFINITY, f64::min);
                let nearest = (cut / delta).round() * delta;
                if epsilon.is_none() {
                    assert!(iv.lo[1] <= nearest + 1e-9, "v0 {v0}: lower bound {} above {nearest}", iv.lo[1]);
                    below += usize::from(nearest < cut);
                } else {
                    assert!(iv.lo[1] >= cut - 1e-9, "v0 {v0}: thesis bound {} below fuel cut {cut}", iv.lo[1]);
                }
            }
        }
    }
    assert!(below > 10, "too few cases with the nearest point below fuel cut: {below}");
}

/// A whole-road solve keeps every stage's cost-to-go; a one-stage solve from the start against
/// the stored stage 1 gives the whole solve's cost and first control (Bellman's principle), and so
/// does one from each state on the optimal path against the stage after it.
#[test]
fn one_stage_solves_against_the_stored_values_follow_the_whole_road_optimum() {
    use truckmpc_core::dp::ValueTable;
    let vehicle = Vehicle::new(VehicleParams::default()).unwrap();
    for p in [DpSettings::default(), DpSettings::thesis()] {
        let p = p.with_mpc(|m| m.horizon_m = 3000.0);
        let slopes: Vec<f64> = (0..p.stages()).map(|k| 0.03 * ((k as f64) * 0.09).sin()).collect();
        let start = InitialState { v_mps: 84.3 / 3.6, gear: 12, stages_since_shift: p.k_lim };
        let mut solver = Solver::new(p.clone());
        let mut table = ValueTable::default();
        let whole = solver.solve_recording(&vehicle, start, &slopes, None, &mut table);
        assert!(whole.feasible);
        assert_eq!(table.stages.len(), slopes.len() + 1);
        let mut one = Solver::new(p.clone());
        let first = one.solve_to_values(&vehicle, start, slopes[0], None, &table.stages[1]);
        assert_eq!(first.cost.to_bits(), whole.cost.to_bits());
        assert_eq!((first.pedal, first.brake, first.gear), (whole.pedal, whole.brake, whole.gear));
        let mut since = if whole.gear != start.gear { 1 } else { (start.stages_since_shift + 1).min(p.k_lim) };
        for (k, &slope) in slopes.iter().enumerate().skip(1) {
            let point = whole.trajectory[k];
            let state =
                InitialState { v_mps: point.v_grid_mps, gear: whole.trajectory[k - 1].gear, stages_since_shift: since };
            let step = one.solve_to_values(&vehicle, state, slope, None, &table.stages[k + 1]);
            assert!(step.feasible, "stage {k}");
            assert_eq!(step.gear, point.gear, "stage {k}");
            // The trajectory's inputs aim from its own speed (off the grid after an arc on
            // trapezoid stages); the one-stage solve's from the grid state.
            let on_grid = point.v_mps == point.v_grid_mps;
            let same = (step.pedal - point.pedal).abs() < 1e-12 && (step.brake - point.brake).abs() < 1e-12;
            assert!(same || !on_grid, "stage {k}");
            since = if point.gear != state.gear { 1 } else { (since + 1).min(p.k_lim) };
        }
    }
}

/// A truck whose gearbox interrupts traction, with the plan modelling the interruption, over a
/// road of `grade` for 3 km between flats (500 m before, 1.5 km after) in stages of `stage_m`: the
/// whole road solved at once, on either grid.
fn climb_plan(vehicle: &Vehicle, grade: f64, grid: GridAnchor, stage_m: f64) -> truckmpc_core::dp::Solution {
    let p = DpSettings::default()
        .with_mpc(|m| (m.plan_interruption, m.grid, m.stage_m) = (true, grid, stage_m))
        .for_vehicle(vehicle)
        .bound();
    let stages = (5000.0 / stage_m) as usize;
    let climb = (500.0 / stage_m) as usize..(3500.0 / stage_m) as usize;
    let slopes: Vec<f64> = (0..stages).map(|k| if climb.contains(&k) { grade } else { 0.0 }).collect();
    let start = InitialState { v_mps: 85.0 / 3.6, gear: 12, stages_since_shift: p.k_lim };
    Solver::new(p).solve(vehicle, start, &slopes)
}

/// Shifts between forward gears of a plan.
fn forward_shifts(plan: &truckmpc_core::dp::Solution) -> usize {
    let gears: Vec<usize> = plan.trajectory.iter().map(|point| point.gear).collect();
    gears.windows(2).filter(|pair| pair[0] != pair[1] && pair[0] != 0 && pair[1] != 0).count()
}

#[test]
fn a_plan_whose_shifts_interrupt_traction_finds_a_path_over_a_long_climb() {
    // Full pedal cannot hold v_min up these grades: the truck slows and shifts down on the way up,
    // and up again after the top, losing a roll's speed at each shift. A band whose bottom follows
    // the free-shift full-pedal chain within one roll leaves such a path no state (the plan then
    // found none on the VECTO long-haul cycle's 4.5 % climb).
    let vehicle = common::map_vehicle();
    for grid in [GridAnchor::Fixed, GridAnchor::Moving] {
        for grade in [0.03, 0.045, 0.06] {
            let plan = climb_plan(&vehicle, grade, grid, 25.0);
            assert!(plan.feasible, "{grid:?}, {grade}: no plan");
            let shifts = forward_shifts(&plan);
            let slowest = plan.trajectory.iter().map(|point| point.v_mps).fold(f64::INFINITY, f64::min);
            assert!(shifts >= 2, "{grid:?}, {grade}: {shifts} shifts between forward gears");
            assert!(slowest * 3.6 < 77.0, "{grid:?}, {grade}: the climb never slows the truck below v_min");
        }
    }
}

#[test]
fn where_a_shifts_roll_outlasts_the_stage_the_plan_still_shifts() {
    // Stages of 12.5 m (the convergence check's S/2) are shorter than a second's roll at cruising
    // speed: such a shift is planned as an ordinary stage. Without it the plan could not change
    // gear there at all and found no path up the climb.
    let vehicle = common::map_vehicle();
    let plan = climb_plan(&vehicle, 0.045, GridAnchor::Fixed, 12.5);
    assert!(plan.feasible, "no plan");
    assert!(forward_shifts(&plan) >= 2, "{} shifts between forward gears", forward_shifts(&plan));
}

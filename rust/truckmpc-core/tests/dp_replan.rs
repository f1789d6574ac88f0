//! Deciding later stages from one horizon solve's stored cost-to-go (`replan_m`): by Bellman's
//! principle, the one-stage solve at stage i against the stored values of stage i + 1 decides as a
//! fresh solve over the stages left would (same terminal pricing, same grid), from any state the
//! stored solve reaches.

use truckmpc_core::dp::{DpSettings, InitialState, Solver, ValueTable};
use truckmpc_core::{Vehicle, VehicleParams};

/// A rolling road of `stages` stages, grades within ±3 %.
fn rolling(stages: usize) -> Vec<f64> {
    (0..stages).map(|k| 0.03 * ((k as f64) * 0.07).sin()).collect()
}

#[test]
fn a_recording_horizon_solve_decides_as_the_plain_one() {
    let vehicle = Vehicle::new(VehicleParams::default()).unwrap();
    let p = DpSettings::default().with_mpc(|m| m.horizon_m = 1500.0);
    let slopes = rolling(p.stages());
    let start = InitialState { v_mps: 83.7 / 3.6, gear: 12, stages_since_shift: p.k_lim };
    let plain = Solver::new(p.clone()).solve(&vehicle, start, &slopes);
    let mut table = ValueTable::default();
    let recorded = Solver::new(p.clone()).solve_horizon_recording(&vehicle, start, (&slopes, None), None, &mut table);
    assert!(plain.feasible);
    assert_eq!(recorded.cost.to_bits(), plain.cost.to_bits());
    assert_eq!((recorded.pedal, recorded.brake, recorded.gear), (plain.pedal, plain.brake, plain.gear));
    assert_eq!(table.stages.len(), slopes.len() + 1);
}

#[test]
fn stages_decided_from_stored_values_match_fresh_solves_of_the_stages_left() {
    for mass_kg in [40_000.0, 20_000.0] {
        let vehicle = Vehicle::new(VehicleParams { mass_kg, ..VehicleParams::default() }).unwrap();
        let p = DpSettings::default().with_mpc(|m| m.horizon_m = 1000.0);
        let span = 20;
        let slopes = rolling(p.stages() + span - 1);
        let start = InitialState { v_mps: 86.1 / 3.6, gear: 12, stages_since_shift: p.k_lim };
        let mut table = ValueTable::default();
        let mut solver = Solver::new(p.clone());
        let block = solver.solve_horizon_recording(&vehicle, start, (&slopes, None), None, &mut table);
        assert!(block.feasible);
        let mut since = if block.gear != start.gear { 1 } else { p.k_lim };
        let (mut compared, mut same) = (0, 0);
        for i in 1..span {
            let point = block.trajectory[i];
            let gear_before = block.trajectory[i - 1].gear;
            let state = InitialState { v_mps: point.v_grid_mps, gear: gear_before, stages_since_shift: since };
            let stored = Solver::new(p.clone()).solve_to_values(&vehicle, state, slopes[i], None, &table.stages[i + 1]);
            let fresh = Solver::new(p.clone()).solve(&vehicle, state, &slopes[i..]);
            assert!(stored.feasible && fresh.feasible, "stage {i}");
            let scale = fresh.cost.abs().max(1.0);
            assert_eq!(stored.gear, fresh.gear, "stage {i}");
            assert!((stored.pedal - fresh.pedal).abs() < 1e-12, "stage {i}: pedal");
            assert!((stored.brake - fresh.brake).abs() < 1e-12, "stage {i}: brake");
            // The stored solve searched from the block's start, a wider space than the fresh one
            // bounds from this state (at full pedal on a climb its grid chain may stop lower):
            // never dearer, and most often the same to rounding.
            let gap = (stored.cost - fresh.cost) / scale;
            assert!(gap <= 1e-9, "stage {i}: stored {} above fresh {}", stored.cost, fresh.cost);
            same += usize::from(gap.abs() <= 1e-9);
            since = if point.gear != gear_before { 1 } else { (since + 1).min(p.k_lim) };
            compared += 1;
        }
        assert_eq!(compared, span - 1);
        assert!(same * 5 >= compared * 4, "{same} of {compared} stages the same cost");
    }
}

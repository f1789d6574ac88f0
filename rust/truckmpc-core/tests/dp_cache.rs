//! The row cache changes nothing but speed: along a receding sequence of solves on a road, a
//! fixed-grid solver with the cache returns bit-identical solutions to one without it.

use truckmpc_core::band::SpeedBand;
use truckmpc_core::control::ShiftCounter;
use truckmpc_core::dp::{horizon, DpSettings, GridAnchor, InitialState, NeutralRule, Solver};
use truckmpc_core::{Road, Vehicle, VehicleParams};

fn hilly_road() -> Road {
    // Deterministic hills and dips of up to ±4 % over 20 km, 25 m segments.
    let n = 800;
    let distance: Vec<f64> = (0..=n).map(|i| 25.0 * i as f64).collect();
    let slopes: Vec<f64> = (0..n).map(|i| 0.04 * ((i as f64) * 0.021).sin() * ((i as f64) * 0.0037).cos()).collect();
    Road::new(distance, slopes).unwrap()
}

fn run(params: &DpSettings, caching: bool, road: &Road, vehicle: &Vehicle) -> Vec<(bool, u64, u64, u64, usize, usize)> {
    let mut solver = Solver::new(params.clone());
    solver.set_caching(caching);
    let mut scratch = horizon::HorizonScratch::default();
    let band = SpeedBand::uniform(&params.cruise());
    let (mut v, mut gear, mut shifts) = (85.0 / 3.6, 12usize, ShiftCounter::new(params.k_lim));
    let mut out = Vec::new();
    for stage in 0..400 {
        let s = road.start_m() + stage as f64 * params.mpc.stage_m;
        let start = InitialState { v_mps: v, gear, stages_since_shift: shifts.stages() };
        let sol = horizon::solve_at(&mut solver, vehicle, (road, &band), s, start, &mut scratch);
        out.push((
            sol.feasible,
            sol.cost.to_bits(),
            sol.pedal.to_bits(),
            sol.brake.to_bits(),
            sol.gear,
            sol.transitions,
        ));
        if sol.feasible {
            shifts.record(gear, sol.gear);
            gear = sol.gear;
            v = sol.trajectory[1].v_mps + 0.013 * ((stage as f64) * 0.7).sin(); // model error
        }
    }
    out
}

#[test]
fn cached_and_uncached_solves_are_bit_identical() {
    let vehicle = Vehicle::new(VehicleParams::default()).unwrap();
    let road = hilly_road();
    for rule in [NeutralRule::Nearest, NeutralRule::Interpolate, NeutralRule::Quadratic] {
        let params = DpSettings::thesis().with_mpc(|m| {
            (m.grid, m.neutral_rule, m.horizon_m, m.delta_kmh) = (GridAnchor::Fixed, rule, 1500.0, 0.2);
        });
        let with = run(&params, true, &road, &vehicle);
        let without = run(&params, false, &road, &vehicle);
        let feasible = with.iter().filter(|s| s.0).count();
        assert!(feasible > 250, "too few feasible solves: {feasible} of {}", with.len());
        for (k, (a, b)) in with.iter().zip(&without).enumerate() {
            assert_eq!(a, b, "solve {k} differs with the cache ({rule:?})");
        }
    }
}

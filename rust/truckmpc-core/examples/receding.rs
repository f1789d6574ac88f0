//! Receding-horizon solves along a road profile CSV (distance_m, altitude_m, ...), the speed
//! advanced by the predicted trajectory: the closed loop without Python and without the plant.
//! Usage: receding ROAD.csv [moving|fixed] [delta_kmh] [horizon_m] [stage_m] [distance_m]
//! (`distance_m` drives only that far from the road's start, e.g. 10000 for a short profiling run.)
use std::sync::Arc;
use std::time::Instant;
use truckmpc_core::band::SpeedBand;
use truckmpc_core::control::ShiftCounter;
use truckmpc_core::dp::{horizon, DpSettings, GridAnchor, InitialState, Solver};
use truckmpc_core::{Road, Vehicle, VehicleParams};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let text = std::fs::read_to_string(&args[1]).unwrap();
    let (mut d, mut h) = (vec![], vec![]);
    for line in text.lines().filter(|l| !l.starts_with('#')).skip(1) {
        let f: Vec<f64> = line.split(',').take(2).map(|x| x.parse().unwrap()).collect();
        d.push(f[0]);
        h.push(f[1]);
    }
    let slopes: Vec<f64> = (0..d.len() - 1).map(|i| (h[i + 1] - h[i]) / (d[i + 1] - d[i])).collect();
    let road = Arc::new(Road::new(d, slopes).unwrap());
    let vehicle = Vehicle::new(VehicleParams::default()).unwrap();
    let grid = if args.get(2).map(|s| s.as_str()) == Some("fixed") { GridAnchor::Fixed } else { GridAnchor::Moving };
    let num = |i: usize, dflt: f64| args.get(i).map(|s| s.parse().unwrap()).unwrap_or(dflt);
    let mut p = DpSettings::thesis().with_mpc(|m| {
        (m.grid, m.delta_kmh, m.horizon_m, m.stage_m) = (grid, num(3, 0.1), num(4, 3000.0), num(5, 25.0));
    });
    p.q_speed_below = 5.0;
    let mut solver = Solver::new(p.clone());
    let mut scratch = horizon::HorizonScratch::default();
    let band = SpeedBand::uniform(&p.cruise());
    let (mut v, mut gear, mut shifts) = (85.0 / 3.6, 12usize, ShiftCounter::new(p.k_lim));
    let (mut solves, mut transitions, mut infeasible, mut states) = (0u64, 0u64, 0u64, 0u64);
    // FNV-1a over every solve's first control and next speed: equal digests mean bit-identical traces.
    let mut digest = 0xcbf29ce484222325u64;
    let mut mix = |x: u64| digest = (digest ^ x).wrapping_mul(0x100000001b3);
    let t0 = Instant::now();
    let mut s = road.start_m();
    let end_m = road.end_m().min(road.start_m() + num(6, f64::INFINITY));
    while s + p.mpc.stage_m <= end_m {
        let sol = horizon::solve_at(
            &mut solver,
            &vehicle,
            (&road, &band),
            s,
            InitialState { v_mps: v, gear, stages_since_shift: shifts.stages() },
            &mut scratch,
        );
        solves += 1;
        transitions += sol.transitions as u64;
        states += sol.states as u64;
        mix(sol.cost.to_bits());
        if sol.feasible {
            mix(sol.pedal.to_bits());
            mix(sol.brake.to_bits());
            mix(sol.gear as u64);
            mix(sol.trajectory[1].v_mps.to_bits());
            shifts.record(gear, sol.gear);
            gear = sol.gear;
            v = sol.trajectory[1].v_mps;
        } else {
            infeasible += 1;
        }
        s += p.mpc.stage_m;
    }
    let secs = t0.elapsed().as_secs_f64();
    println!("{grid:?}: {solves} solves, {:.3} ms/solve, {:.0} transitions/solve, {:.2} ns/transition, {infeasible} infeasible, rows computed {}, {:.0} states/solve, trace digest {digest:016x}",
        1e3 * secs / solves as f64, transitions as f64 / solves as f64, 1e9 * secs / transitions as f64, solver.rows_computed(), states as f64 / solves as f64);
}

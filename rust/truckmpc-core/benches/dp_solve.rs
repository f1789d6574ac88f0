//! One DP solve of the look-ahead controller, at the two settings of `truckmpc bench`:
//! (S 25 m, δ 0.1 km/h, 3000 m horizon) — the thesis's worst case — and (S 50 m, δ 0.2 km/h, 2000 m),
//! neutral allowed, from 85 km/h in gear 12 on a fixed synthetic road of ±3 % hills.
//!
//! Per setting:
//! - `fresh`: a new solver per solve (buffers allocated), as for the first solve of a run;
//! - `same_solver`: the same solve repeated on one solver, whose buffers have grown;
//! - `rolling/<grid>`: one solver stepping one stage along the road per solve, as the closed loop
//!   does (successive horizons share all but one stage), for the moving and the fixed grid.
//!
//! Throughput is in transitions (the solver's own count; for `rolling`, the mean over its positions),
//! so criterion's elem/s is transitions per second: 1e9 / (elem/s) is ns per transition.
//!
//! ```sh
//! cargo bench -p truckmpc-core --bench dp_solve              # full measurement
//! cargo bench -p truckmpc-core --bench dp_solve -- --quick   # a quick look
//! ```

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, BatchSize, Criterion, Throughput};
use truckmpc_core::band::SpeedBand;
use truckmpc_core::dp::horizon::{self, solve_at, stage_slopes};
use truckmpc_core::dp::{DpSettings, GridAnchor, InitialState, Solver};
use truckmpc_core::{CruiseParams, MpcParams};
use truckmpc_core::{Road, Vehicle, VehicleParams};

/// Length of the synthetic road [m]; the rolling benchmark wraps around before its end.
const ROAD_M: f64 = 40_000.0;
/// Profile point spacing of the synthetic road [m].
const POINT_M: f64 = 25.0;
/// Stages the rolling benchmark advances before starting over at the road's start.
const ROLLING_STAGES: usize = 120;

/// A deterministic hilly road: the sum of three sines (periods 3.1, 1.3 and 0.7 km), scaled so the
/// grade spans ±3 %, one constant grade per 25 m segment.
fn hilly_road() -> Road {
    let points = (ROAD_M / POINT_M) as usize + 1;
    let distance: Vec<f64> = (0..points).map(|i| i as f64 * POINT_M).collect();
    let tau = std::f64::consts::TAU;
    let raw = |s: f64| {
        0.6 * (tau * s / 3100.0).sin() + 0.3 * (tau * s / 1300.0 + 1.0).sin() + 0.1 * (tau * s / 700.0 + 2.0).sin()
    };
    let slope: Vec<f64> = distance[..points - 1].iter().map(|&s| 0.03 * raw(s + 0.5 * POINT_M)).collect();
    Road::new(distance, slope).expect("synthetic road is valid")
}

/// The thesis's controller at one setting (k_lim and Q2 resolved by their table 6.1/6.2 rules).
fn params(stage_m: f64, delta_kmh: f64, horizon_m: f64, grid: GridAnchor) -> DpSettings {
    let mpc = MpcParams { stage_m, horizon_m, delta_kmh, allow_neutral: true, grid, ..MpcParams::thesis() };
    DpSettings::new(&mpc, &CruiseParams::default()).expect("benchmark parameters are valid")
}

fn start(p: &DpSettings) -> InitialState {
    InitialState { v_mps: 85.0 / 3.6, gear: 12, stages_since_shift: p.k_lim }
}

fn dp_solve(c: &mut Criterion) {
    let vehicle = Vehicle::new(VehicleParams::default()).expect("default vehicle is valid");
    let road = hilly_road();
    for (stage_m, delta_kmh, horizon_m) in [(25.0, 0.1, 3000.0), (50.0, 0.2, 2000.0)] {
        let name = format!("dp_solve/S{stage_m}_d{delta_kmh}_{horizon_m}m");
        let p = params(stage_m, delta_kmh, horizon_m, GridAnchor::Moving);
        let x0 = start(&p);
        let mut slopes = Vec::new();
        stage_slopes(&road, 0.0, p.mpc.stage_m, p.stages(), &mut slopes);
        let probe = Solver::new(p.clone()).solve(&vehicle, x0, &slopes);
        assert!(probe.feasible, "{name}: the benchmark solve must be feasible");

        let mut group = c.benchmark_group(&name);
        group.throughput(Throughput::Elements(probe.transitions as u64));
        group.bench_function("fresh", |b| {
            b.iter_batched(
                || Solver::new(p.clone()),
                |mut solver| black_box(solver.solve(&vehicle, x0, black_box(&slopes))),
                BatchSize::SmallInput,
            )
        });
        let mut solver = Solver::new(p.clone());
        group.bench_function("same_solver", |b| b.iter(|| black_box(solver.solve(&vehicle, x0, black_box(&slopes)))));
        for (label, grid) in [("rolling/moving", GridAnchor::Moving), ("rolling/fixed", GridAnchor::Fixed)] {
            let p = params(stage_m, delta_kmh, horizon_m, grid);
            let mut solver = Solver::new(p.clone());
            let mut scratch = horizon::HorizonScratch::default();
            let band = SpeedBand::uniform(&p.cruise());
            let total: usize = (0..ROLLING_STAGES)
                .map(|k| {
                    solve_at(&mut solver, &vehicle, (&road, &band), k as f64 * p.mpc.stage_m, x0, &mut scratch)
                        .transitions
                })
                .sum();
            group.throughput(Throughput::Elements((total / ROLLING_STAGES) as u64));
            let mut solver = Solver::new(p.clone());
            let mut stage = 0usize;
            group.bench_function(label, |b| {
                b.iter(|| {
                    let s_m = (stage % ROLLING_STAGES) as f64 * p.mpc.stage_m;
                    stage += 1;
                    black_box(solve_at(&mut solver, &vehicle, (&road, &band), s_m, x0, &mut scratch))
                })
            });
        }
        group.finish();
    }
}

criterion_group!(benches, dp_solve);
criterion_main!(benches);

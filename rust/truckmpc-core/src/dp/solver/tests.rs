//! The solver's tests: the AVX2 passes against their scalar loops, the neutral joins, the min-plus
//! block pass, and cached rows against computed ones on a moving grid.

#[cfg(target_arch = "x86_64")]
use super::arcs::{join_nearest_avx2, NeutralOut};
use super::arcs::{quadratic_to_go, ArcJoin};
use super::choices::{level_flag, level_of, Decision, ARC, FLAGS, FULL, GLIDE, NO_GEAR};
use super::first_pass::block_mins;
#[cfg(target_arch = "x86_64")]
use super::second_pass::rank_avx2;
use super::second_pass::{decide_states, StateIn, StateOut};
use super::*;
use crate::dp::cache::{Block, CoastArc, LANES, PAD};
use crate::dp::params::{GridAnchor, NeutralRule};
use crate::dp::simd::{self, LaneOut};
use crate::params::MAX_PEDAL_LEVELS;
use crate::road::Road;
use crate::vehicle::{VehicleParams, NEUTRAL};

/// A receding sequence of solves on a hilly road (with a model error, so that start speeds
/// are off any grid), each solve's outputs as bits.
fn receding(params: &DpSettings, caching: bool) -> Vec<(bool, u64, u64, u64, usize, usize, u64)> {
    let vehicle = Vehicle::new(VehicleParams::default()).unwrap();
    let n = 600;
    let distance: Vec<f64> = (0..=n).map(|i| 25.0 * i as f64).collect();
    let slopes: Vec<f64> = (0..n).map(|i| 0.04 * ((i as f64) * 0.021).sin() * ((i as f64) * 0.0037).cos()).collect();
    let road = Road::new(distance, slopes).unwrap();
    let mut solver = Solver::new(params.clone());
    solver.set_caching(caching);
    let mut scratch = crate::dp::horizon::HorizonScratch::default();
    let band = crate::band::SpeedBand::uniform(&params.cruise());
    let (mut v, mut gear, mut since) = (85.0 / 3.6, 12usize, params.k_lim);
    let mut out = Vec::new();
    for stage in 0..300 {
        let s = road.start_m() + stage as f64 * params.mpc.stage_m;
        let start = InitialState { v_mps: v, gear, stages_since_shift: since };
        let sol = crate::dp::horizon::solve_at(&mut solver, &vehicle, (&road, &band), s, start, &mut scratch);
        let next_v = sol.trajectory.get(1).map_or(0, |p| p.v_mps.to_bits());
        out.push((
            sol.feasible,
            sol.cost.to_bits(),
            sol.pedal.to_bits(),
            sol.brake.to_bits(),
            sol.gear,
            sol.transitions,
            next_v,
        ));
        if sol.feasible {
            since = if sol.gear != gear { 1 } else { (since + 1).min(params.k_lim) };
            gear = sol.gear;
            v = sol.trajectory[1].v_mps + if stage % 3 == 0 { 0.013 * ((stage as f64) * 0.7).sin() } else { 0.0 };
        }
    }
    out
}

#[test]
fn second_pass_in_avx2_equals_the_scalar_loop() {
    let Some(avx2) = Avx2Token::detect() else { return };
    let mut seed = 13u64;
    let mut next = move |n: u64| {
        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (seed >> 33) % n
    };
    let (width, gears) = (24usize, 6usize);
    for case in 0..400 {
        let m = 1 + next(21) as usize;
        let slot0 = next((width - m + 1) as u64) as usize;
        let gear = 1 + next(gears as u64 - 1) as u32;
        let k_lim = [0, 1, 3, 8, u32::MAX][case % 5];
        let mut cost = |inf_one_in: u64| if next(inf_one_in) == 0 { INF } else { next(7) as f64 * 0.5 };
        let all_cost: Vec<f64> = (0..m).map(|_| cost(4)).collect();
        let first_cost: Vec<f64> = (0..m).map(|_| cost(3)).collect();
        let second_cost: Vec<f64> = first_cost.iter().map(|&c| if c == INF { INF } else { c + cost(3) }).collect();
        // As the first pass leaves them: no gear exactly where the cost is +∞.
        let mut gear_of = |c: f64| if c == INF { NO_GEAR } else { next(gears as u64) as u32 };
        let first_gear: Vec<u32> = first_cost.iter().map(|&c| gear_of(c)).collect();
        let second_gear: Vec<u32> = second_cost.iter().map(|&c| gear_of(c)).collect();
        let counter_next: Vec<u32> =
            (0..40).map(|_| [0, 1, 2, 7, 8, 9, u32::MAX / 2, u32::MAX - 1, u32::MAX][next(9) as usize]).collect();
        // Some choices are exact arcs, flagged on their index's top byte: fuel cut, full pedal or
        // a pedal level (any byte up to that of the most levels).
        let mut index = |n: u64| next(n) as u32 | if next(3) == 0 { (next(243) as u32) << 24 } else { 0 };
        let all_j: Vec<u32> = (0..m).map(|_| index(40)).collect();
        let shift_j: Vec<u32> = (0..width * gears).map(|_| index(1000)).collect();
        let penalty: Vec<f64> = (0..m).map(|_| next(5) as f64 * 0.25).collect();
        // Even cases decide a forward gear's states; odd ones neutral's, whose staying
        // carries the counter of its own choice.
        let neutral = case % 2 == 1;
        let gear = if neutral { NEUTRAL as u32 } else { gear };
        let neutral_counter: Vec<u32> = if neutral {
            (0..m).map(|_| [0, 1, 7, 8, 9, u32::MAX / 2, u32::MAX - 1, u32::MAX][next(8) as usize]).collect()
        } else {
            vec![0; m]
        };
        let run = |avx2: Option<Avx2Token>| {
            let (mut c, mut n, mut sh, mut d) = (vec![0.0; m], vec![0; m], vec![0.0; m], vec![Decision::default(); m]);
            let input = StateIn {
                gear,
                slot0,
                all_cost: &all_cost,
                all_j: &all_j,
                first_cost: &first_cost,
                first_gear: &first_gear,
                second_cost: &second_cost,
                second_gear: &second_gear,
                neutral_counter: &neutral_counter,
                penalty: &penalty,
                shift_j: &shift_j,
                width,
                counter_next: &counter_next,
                q4: 0.5,
                k_lim,
            };
            let out = StateOut { cost: &mut c, counter: &mut n, shift: &mut sh, decision: &mut d };
            let same = if neutral {
                decide_states::<true, true>(input, out, avx2)
            } else {
                decide_states::<true, false>(input, out, avx2)
            };
            (
                c.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
                n,
                sh.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
                d,
                same,
            )
        };
        assert_eq!(run(Some(avx2)), run(None), "case {case}");
    }
}

/// The quadratic rule is exact on a quadratic cost-to-go wherever three states surround the
/// end speed; its error on a smooth cost-to-go is third order in the grid step (an eighth when
/// it halves, where linear interpolation's, second order, is a quarter); at the ends and next
/// to a state with no finite cost it interpolates between the two bracketing states; outside
/// it finds none.
#[test]
fn quadratic_neutral_join_is_exact_on_quadratics_and_third_order() {
    let quad = |x: f64| 3.0 + 0.7 * x - 0.04 * x * x;
    let cost: Vec<f64> = (0..40).map(|j| quad(j as f64)).collect();
    let counter = vec![9u32; 40];
    for t in 0..=200 {
        let x = 2.0 + t as f64 * 0.17;
        let (to_go, j, _) = quadratic_to_go(x, (0, 39), &cost, &counter).unwrap();
        assert!((to_go - quad(x)).abs() < 1e-12, "x {x}: {to_go} vs {}", quad(x));
        assert_eq!(j, (x + 0.5) as usize);
    }
    // A smooth non-quadratic on grids of step h: error at mid-cells shrinks with h³.
    let error = |h: f64| {
        let f = |v: f64| (0.3 * v).sin() + 0.02 * v * v * v;
        let values: Vec<f64> = (0..400).map(|j| f(j as f64 * h)).collect();
        let x = 5.0 / h + 0.37; // the same speed region at every h
        (quadratic_to_go(x, (0, 399), &values, &vec![0; 400]).unwrap().0 - f(x * h)).abs()
    };
    let ratio = error(0.1) / error(0.05);
    assert!(ratio > 6.0 && ratio < 10.0, "error ratio at half the step: {ratio}");
    // Bracketing fallback: next to +∞, and at the ends of the states.
    let mut holes = cost.clone();
    holes[21] = INF;
    let (to_go, _, _) = quadratic_to_go(19.8, (0, 39), &holes, &counter).unwrap();
    assert!((to_go - (0.2 * cost[19] + 0.8 * cost[20])).abs() < 1e-12);
    let (to_go, _, _) = quadratic_to_go(0.3, (0, 39), &cost, &counter).unwrap();
    assert!((to_go - (0.7 * cost[0] + 0.3 * cost[1])).abs() < 1e-12);
    assert!(quadratic_to_go(20.6, (0, 39), &holes, &counter).is_none());
    assert!(quadratic_to_go(39.2, (0, 39), &cost, &counter).is_none());
    assert!(quadratic_to_go(-0.2, (0, 39), &cost, &counter).is_none());
    // The counter is the smallest among the points used.
    let mut counters = counter.clone();
    counters[11] = 2;
    assert_eq!(quadratic_to_go(10.2, (0, 39), &cost, &counters).unwrap().2, 2);
}

#[test]
fn neutral_join_in_avx2_equals_the_scalar_join() {
    if Avx2Token::detect().is_none() {
        return;
    }
    let mut seed = 17u64;
    let mut next = move |n: u64| {
        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (seed >> 33) % n
    };
    for case in 0..300 {
        let (lo, hi) = (next(6) as u32, 6 + next(20) as u32);
        let join = ArcJoin {
            extrapolate_top: false,
            rule: NeutralRule::Nearest,
            origin_mps: 20.0 + next(100) as f64 * 0.01,
            delta_mps: 0.1 / 3.6,
            lo,
            hi,
        };
        let n = next(23) as usize;
        let arcs: Vec<CoastArc> = (0..n)
            .map(|_| CoastArc {
                // From well below to well above the states, with exact half steps.
                v_end_mps: join.origin_mps + (next(64) as f64 * 0.5 - 4.0) * join.delta_mps + next(3) as f64 * 1e-12,
                cost: next(9) as f64 * 0.25,
            })
            .collect();
        let cost_next: Vec<f64> = (0..40).map(|_| if next(4) == 0 { INF } else { next(11) as f64 }).collect();
        let counter_next: Vec<u32> = (0..40).map(|_| next(12) as u32).collect();
        let k_lim = [0, 4, 8, u32::MAX][case % 4];
        let scalar: Vec<_> = arcs
            .iter()
            .map(|arc| {
                let (cost, j, counter) = join.join(arc, &cost_next, &counter_next);
                (cost.to_bits(), j, counter, if counter >= k_lim { cost } else { INF }.to_bits(), j)
            })
            .collect();
        let (mut a, mut b, mut c, mut d, mut e) = (vec![0.0; n], vec![0; n], vec![0; n], vec![0.0; n], vec![0; n]);
        let out = NeutralOut { all_cost: &mut a, all_j: &mut b, counters: &mut c, shift_cost: &mut d, shift_j: &mut e };
        // SAFETY: AVX2 was detected above.
        let done = unsafe { join_nearest_avx2(&join, &arcs, (&cost_next, &counter_next), k_lim, out) };
        assert_eq!(done, n / 4 * 4);
        for t in 0..done {
            assert_eq!((a[t].to_bits(), b[t], c[t], d[t].to_bits(), e[t]), scalar[t], "case {case} arc {t}");
        }
    }
}

#[test]
fn shift_ranking_in_avx2_equals_the_scalar_loop() {
    if Avx2Token::detect().is_none() {
        return;
    }
    let mut seed = 19u64;
    let mut next = move |n: u64| {
        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (seed >> 33) % n
    };
    for case in 0..200 {
        let m = next(19) as usize;
        let (mut f, mut fg, mut s, mut sg) = (vec![INF; m], vec![NO_GEAR; m], vec![INF; m], vec![NO_GEAR; m]);
        let (mut f2, mut fg2, mut s2, mut sg2) = (f.clone(), fg.clone(), s.clone(), sg.clone());
        for g in 0..6u32 {
            // Few distinct values: many ties.
            let costs: Vec<f64> = (0..m).map(|_| if next(3) == 0 { INF } else { next(4) as f64 }).collect();
            for t in 0..m {
                let c = costs[t];
                if c < f[t] {
                    (s[t], sg[t]) = (f[t], fg[t]);
                    (f[t], fg[t]) = (c, g);
                } else if c < s[t] {
                    (s[t], sg[t]) = (c, g);
                }
            }
            // SAFETY: AVX2 was detected above; equal lengths.
            let done = unsafe { rank_avx2(&costs, g, (&mut f2, &mut fg2), (&mut s2, &mut sg2)) };
            for t in done..m {
                let c = costs[t];
                if c < f2[t] {
                    (s2[t], sg2[t]) = (f2[t], fg2[t]);
                    (f2[t], fg2[t]) = (c, g);
                } else if c < s2[t] {
                    (s2[t], sg2[t]) = (c, g);
                }
            }
        }
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!((bits(&f), fg, bits(&s), sg), (bits(&f2), fg2, bits(&s2), sg2), "case {case}");
    }
}

#[test]
fn moving_grid_rows_from_the_cache_give_the_same_bits() {
    for rule in [NeutralRule::Nearest, NeutralRule::Interpolate, NeutralRule::Quadratic] {
        let params = DpSettings::thesis().with_mpc(|m| {
            (m.grid, m.neutral_rule, m.horizon_m, m.delta_kmh) = (GridAnchor::Moving, rule, 1500.0, 0.2);
        });
        let with = receding(&params, true);
        let without = receding(&params, false);
        assert!(with.iter().filter(|s| s.0).count() > 200);
        for (k, (a, b)) in with.iter().zip(&without).enumerate() {
            assert_eq!(a, b, "solve {k} differs with the cache ({rule:?})");
        }
    }
}

/// A whole-road solve (off the cache's window) on a road whose grades come back: the rows kept by
/// key give the same cost, trajectory and stored values, bit for bit, as rows computed at every
/// stage, and are computed for a tenth of the stages or fewer where a road of distinct grades
/// computes them at every stage.
#[test]
fn a_whole_road_solve_with_rows_kept_by_key_gives_the_same_bits() {
    let vehicle = Vehicle::new(VehicleParams::default()).unwrap();
    // Nine grades, on every other stretch of 40 stages; flat between.
    let slopes: Vec<f64> = (0..400).map(|i| 0.01 * ((i * 7 % 9) as f64 - 4.0) * ((i / 40) % 2) as f64).collect();
    let distinct: Vec<f64> = slopes.iter().enumerate().map(|(i, a)| a + 1e-7 * i as f64).collect();
    let start = InitialState { v_mps: 85.0 / 3.6, gear: 12, stages_since_shift: 100 };
    // The thesis's settings (Euler stages, moving grid) and the declared defaults (trapezoid stages,
    // fixed grid, fuel-cut arcs), each as the whole-road optimum prices it.
    for params in [DpSettings::thesis().bound(), DpSettings::default().bound()] {
        let solve = |slopes: &[f64], caching: bool| {
            let mut solver = Solver::new(params.clone());
            solver.set_caching(caching);
            let mut table = crate::dp::ValueTable::default();
            let sol = solver.solve_recording(&vehicle, start, slopes, None, &mut table);
            let path: Vec<(u64, usize)> = sol.trajectory.iter().map(|p| (p.v_mps.to_bits(), p.gear)).collect();
            let gears = vehicle.forward_gears() + 1;
            let values: Vec<Option<(u64, u32)>> = (table.stages.iter())
                .flat_map(|st| (0..gears).flat_map(move |g| (0..st.count).map(move |j| st.get(g, j))))
                .map(|value| value.map(|(cost, counter)| (cost.to_bits(), counter)))
                .collect();
            ((sol.feasible, sol.cost.to_bits(), path, values), solver.rows_computed())
        };
        let ((with, kept_rows), (without, _)) = (solve(&slopes, true), solve(&slopes, false));
        assert!(with.0, "feasible ({:?})", params.mpc.stage_model);
        assert_eq!(with, without, "{:?}", params.mpc.stage_model);
        let (_, every_stage_rows) = solve(&distinct, true);
        assert!(kept_rows > 0 && kept_rows * 10 < every_stage_rows, "{kept_rows} rows against {every_stage_rows}");
    }
}

/// Per lane, the first strict improvement over the targets that are states (`lo..=hi`).
fn scalar_lane(costs: &[f64], steps: usize, base: i64, (lo, hi): (u32, u32), values: &[f64], l: usize) -> (f64, u32) {
    let mut best = (INF, 0);
    for d in 0..steps {
        let j = base + (l + d) as i64;
        if j >= lo as i64 && j <= hi as i64 {
            let x = costs[d * LANES + l] + values[PAD + j as usize];
            if x < best.0 {
                best = (x, d as u32);
            }
        }
    }
    best
}

/// What [`block_mins`] with `kernels` writes: minima and next-grid indices of the four lanes.
fn written<K: simd::Kernels>(
    kernels: K,
    block: &Block,
    costs: &[f64],
    base: i64,
    range: (u32, u32),
    values: (&[f64], &[f64]),
    same: bool,
) -> ([f64; LANES], [u32; LANES], [f64; LANES], [u32; LANES]) {
    let mut lanes = ([0.0; LANES], [0; LANES], [0.0; LANES], [0; LANES]);
    let (all, all_j, shift, shift_j) = (&mut lanes.0, &mut lanes.1, &mut lanes.2, &mut lanes.3);
    block_mins(kernels, block, costs, base, range, values, same, LaneOut { all, all_j, shift, shift_j });
    lanes
}

#[test]
fn block_pass_inside_and_beyond_the_margins_matches_a_scalar_scan() {
    let (count, steps) = (30usize, 20usize);
    let (lo, hi) = (3u32, 25u32);
    let mut seed = 5u64;
    let mut next = || {
        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (seed >> 35) % 9
    };
    for _ in 0..50 {
        let costs: Vec<f64> = (0..steps * LANES).map(|_| if next() == 0 { INF } else { next() as f64 * 0.5 }).collect();
        // Values as the solver keeps them: +∞ outside the states and in the margins.
        let mut to_go = vec![INF; stride(count)];
        let mut shiftable = vec![INF; stride(count)];
        for j in lo..=hi {
            to_go[PAD + j as usize] = next() as f64;
            shiftable[PAD + j as usize] = if next() < 3 { INF } else { to_go[PAD + j as usize] };
        }
        let block = Block { first: 0, steps: steps as u32, offset: 0, spans: [(0, 0); LANES], reach: 0 };
        // Inside the margins (packed pass) and reaching below them (clipped pass).
        for base in [-4i64, 10, -(PAD as i64) - 3, count as i64 - 5] {
            let (all, all_j, shift, shift_j) =
                written(simd::Portable, &block, &costs, base, (lo, hi), (&to_go, &shiftable), false);
            // The AVX2 kernels (minima written from registers) write the same.
            #[cfg(target_arch = "x86_64")]
            if let Some(avx2) = simd::Avx2::detect() {
                for same in [false, true] {
                    let values = (&to_go[..], if same { &to_go[..] } else { &shiftable[..] });
                    let got = written(avx2, &block, &costs, base, (lo, hi), values, same);
                    let want = written(simd::Portable, &block, &costs, base, (lo, hi), values, same);
                    let bits = |x: [f64; LANES]| x.map(f64::to_bits);
                    assert_eq!((bits(got.0), got.1, bits(got.2), got.3), (bits(want.0), want.1, bits(want.2), want.3));
                }
            }
            // The index of lane l at step d is base + l + d.
            let step = |j: u32, l: usize| (j as i64 - base - l as i64) as u32;
            for l in 0..LANES {
                let want = scalar_lane(&costs, steps, base, (lo, hi), &to_go, l);
                assert_eq!((all[l], step(all_j[l], l)), want, "base {base} lane {l}");
                let want = scalar_lane(&costs, steps, base, (lo, hi), &shiftable, l);
                assert_eq!((shift[l], step(shift_j[l], l)), want, "base {base} lane {l}");
            }
        }
    }
}

#[test]
fn a_pedal_levels_flag_gives_its_level_back_and_reads_as_no_other_arc() {
    for l in 1..MAX_PEDAL_LEVELS {
        let flagged = 1234 | level_flag(l);
        let d = Decision::new(flagged, 3);
        assert_eq!((d.j, d.gear, level_of(d.arc)), (1234, 3, Some(l)));
        assert!(u32::from(d.arc) != ARC >> 24 && u32::from(d.arc) != FULL >> 24);
        assert_eq!(flagged & !FLAGS, 1234);
    }
    for other in [0, ARC >> 24, FULL >> 24] {
        assert_eq!(level_of(other as u8), None);
    }
}

#[test]
fn the_glide_flag_reads_as_no_pedal_level() {
    let d = Decision::new(1234 | GLIDE, 3);
    assert_eq!((d.j, d.gear, u32::from(d.arc), level_of(d.arc)), (1234, 3, GLIDE >> 24, None));
    for l in 1..MAX_PEDAL_LEVELS {
        assert_ne!(level_flag(l), GLIDE);
    }
}

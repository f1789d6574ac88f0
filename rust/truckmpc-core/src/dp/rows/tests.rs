//! Rows against `pair`'s costs bit for bit, and the integer ceil and floor against libm's.

use std::sync::Arc;

use super::*;
use crate::dp::stage::Branch;
use crate::params::GridAnchor;
use crate::powertrain::tests::body;
use crate::powertrain::{Driveline, Engine, MapModel, MapTruck};
use crate::vehicle::VehicleParams;

/// Every cost of a row is `pair`'s, bit for bit (whichever path computed it), and the row is
/// trimmed to its finite ends: over speeds, gears and slopes, with brake points next to v_max.
#[test]
fn rows_hold_the_costs_of_pair() {
    let thesis = DpSettings::thesis();
    rows_hold_the_costs_of_pair_in(&thesis);
    rows_hold_the_costs_of_pair_in(&thesis.with_mpc(|m| m.stage_model = StageModel::Trapezoid));
    rows_hold_the_costs_of_pair_in(&DpSettings::default());
}

fn rows_hold_the_costs_of_pair_in(p: &DpSettings) {
    let vehicle = Vehicle::new(VehicleParams::default()).unwrap();
    let p = p.clone();
    let mut out = vec![1.0; 3];
    let mut memo = RowMemo::default();
    for (s, slope) in [-0.06, -0.03, -0.01, 0.0, 0.01, 0.03, 0.06].into_iter().enumerate() {
        let torque = vehicle.slope_torque_nm(slope);
        for gear in 1..=vehicle.forward_gears() {
            // One memo for every row, as the solver keeps it: it starts afresh per gear and slope.
            for step in 0..60 {
                let v_i = p.v_max_mps() - 0.37 * step as f64 / 3.6;
                let grid = GridIndex { origin_mps: 15.0 + 0.013 * s as f64, delta_mps: p.delta_mps() };
                let before = out.len();
                let (span, at) = row_of(&vehicle, &p, (v_i, gear, torque), grid, (&mut out, &mut memo));
                assert_eq!(out.len(), at + span.len);
                assert!(at >= before);
                let m = maps(&vehicle, &p, v_i, gear, torque);
                let reference =
                    |index: i64| pair(&p, &m, v_i, grid.speed(index), p.v_max_mps()).map_or(f64::INFINITY, |(_, c)| c);
                for (t, &c) in out[at..].iter().enumerate() {
                    assert_eq!(c.to_bits(), reference(span.first + t as i64).to_bits(), "v {v_i} gear {gear}");
                }
                if span.len > 0 {
                    assert!(out[at].is_finite() && out[at + span.len - 1].is_finite());
                    // Just outside the span nothing is admissible.
                    assert!(
                        !reference(span.first - 1).is_finite() && !reference(span.first + span.len as i64).is_finite()
                    );
                }
                out.truncate(3);
            }
        }
    }
}

/// A map-based truck's rows on the fixed grid read its fuel from the pedal table: every cost is
/// `pair`'s (which reads the map) to within 0.1 % of the stage's full-pedal fuel, and the same
/// targets are admissible. Speeds are visited downwards and then upwards past the first ones, so
/// the table grows below and above what it holds.
#[test]
fn a_map_trucks_rows_on_the_fixed_grid_are_pairs_costs_to_within_the_tables_error() {
    let vehicle = curved_map_truck();
    let p = DpSettings::default().with_mpc(|m| m.grid = GridAnchor::Fixed);
    assert_eq!(p.mpc.stage_model, StageModel::Trapezoid);
    let grid = GridIndex { origin_mps: 0.0, delta_mps: p.delta_mps() };
    let mut memo = RowMemo::default();
    let mut out = Vec::new();
    let mut rows = 0;
    let indices = (1500..1700).rev().step_by(3).chain((1690..1900).step_by(5));
    for index in indices {
        let v_i = grid.speed(index);
        for gear in 2..=4 {
            for slope in [-0.02, 0.0, 0.015] {
                let torque = vehicle.slope_torque_nm(slope);
                out.clear();
                let (span, at) = row_of(&vehicle, &p, (v_i, gear, torque), grid, (&mut out, &mut memo));
                let m = maps(&vehicle, &p, v_i, gear, torque);
                for (t, &cost) in out[at..at + span.len].iter().enumerate() {
                    let v_j = grid.speed(span.first + t as i64);
                    let exact = pair(&p, &m, v_i, v_j, p.v_max_mps()).map_or(f64::INFINITY, |(_, c)| c);
                    assert_eq!(cost.is_finite(), exact.is_finite(), "v {v_i} gear {gear} slope {slope}");
                    let full = stage::half_stage_fuel_g(&vehicle, v_i, 1.0, gear, p.mpc.stage_m)
                        + stage::half_stage_fuel_g(&vehicle, v_j, 1.0, gear, p.mpc.stage_m);
                    if exact.is_finite() {
                        assert!((cost - exact).abs() <= 1e-3 * p.mpc.q_fuel * full + 1e-12, "{cost} vs {exact}");
                    }
                }
                rows += usize::from(span.len > 0);
            }
        }
    }
    assert!(rows > 300, "{rows} rows with targets");
}

/// A trapezoid row given the exact end speeds of its band (the solver's fuel-cut and full-pedal
/// arcs) is the row it finds by iterating for them, span and costs bit for bit: with the thesis's
/// truck (full pedal only: its fuel cut is the drag curve, not the map at zero pedal) and a map
/// truck (both ends), over speeds, gears and slopes on the fixed grid.
#[test]
fn a_row_given_its_ends_by_the_arcs_is_the_row_it_finds_itself() {
    let p = DpSettings::default();
    assert!(p.mpc.stage_model == StageModel::Trapezoid && p.mpc.grid == GridAnchor::Fixed && p.mpc.fuel_cut_arcs);
    let grid = GridIndex { origin_mps: 0.0, delta_mps: p.delta_mps() };
    let trucks = [(Vehicle::new(VehicleParams::default()).unwrap(), false), (curved_map_truck(), true)];
    let (mut compared, mut differ, mut out) = (0, 0, Vec::<f64>::new());
    for (vehicle, map) in &trucks {
        let mut memo = RowMemo::default();
        for index in (1300..1850).step_by(7) {
            let v_i = grid.speed(index);
            for gear in 1..=vehicle.forward_gears() {
                for slope in [-0.04, -0.01, 0.0, 0.02, 0.05] {
                    let torque = vehicle.slope_torque_nm(slope);
                    let arc = |input| {
                        stage::end_speed(StageModel::Trapezoid, vehicle, (v_i, p.mpc.stage_m), gear, torque, input)
                    };
                    let known = [map.then(|| arc((Branch::Brake, 0.0))), Some(arc((Branch::Pedal, 1.0)))];
                    // The top given a grid step short: the check can fail.
                    let short = [known[0], known[1].map(|v| v - 1.5 * grid.delta_mps)];
                    let [found, given, shortened] = [[None; 2], known, short].map(|ends| {
                        out.clear();
                        let row = (&mut out, &mut memo);
                        let (span, at) = forward_row(vehicle, &p, (v_i, ends), gear, torque, grid, p.v_max_mps(), row);
                        (span, out[at..].iter().map(|c| c.to_bits()).collect::<Vec<u64>>())
                    });
                    assert_eq!(found, given, "v {v_i} gear {gear} slope {slope}");
                    compared += usize::from(found.0.len > 0);
                    differ += usize::from(found != shortened);
                }
            }
        }
    }
    assert!(compared > 500 && differ > 500, "{compared} rows with targets, {differ} changed by a short top");
}

/// [`forward_row`] from `v_i` [m/s] in `gear` on a slope of wheel torque `torque` [Nm] to `grid`
/// below the settings' v_max, the row finding its band's ends itself.
fn row_of(
    vehicle: &Vehicle,
    p: &DpSettings,
    (v_i, gear, torque): (f64, usize, f64),
    grid: GridIndex,
    buffers: (&mut Vec<f64>, &mut RowMemo),
) -> (RowSpan, usize) {
    forward_row(vehicle, p, (v_i, [None; 2]), gear, torque, grid, p.v_max_mps(), buffers)
}

/// A truck whose fuel map curves in torque (z = n/1000 · (1500 + 40 T + 0.004 T²) g/h), so
/// the rate is not affine in the pedal and interpolating it has an error to bound.
pub(in crate::dp::rows) fn curved_map_truck() -> Vehicle {
    let mut points = Vec::new();
    for n in (6..=20).map(|k| 100.0 * k as f64) {
        for t in (-3..=25).map(|k| 100.0 * k as f64) {
            points.push((n, t, n / 1000.0 * (1500.0 + 40.0 * t + 0.004 * t * t).max(0.0)));
        }
    }
    let full_load = [(600.0, 1200.0, -150.0), (1200.0, 2400.0, -200.0), (2000.0, 1800.0, -280.0)];
    let engine = Engine::new(600.0, 4.0, &full_load, &points).unwrap();
    let driveline = Driveline::new((&[3.0, 2.0, 1.4, 1.0], 2.6), (0.98, 0.97, 20.0), 0.5).unwrap();
    let truck = MapTruck::new(engine, driveline, body()).unwrap();
    let model = MapModel::new(truck, 1.0e5, 0.0);
    Vehicle::from_map(Arc::new(model), &VehicleParams::default()).unwrap()
}

#[test]
fn integer_ceil_and_floor_equal_the_libm_ones() {
    let mut values = vec![
        0.0,
        -0.0,
        0.5,
        -0.5,
        1.0,
        -1.0,
        1e-300,
        -1e-300,
        2.5,
        -2.5,
        4503599627370495.5,
        -4503599627370495.5,
        9007199254740993.0,
        9.3e18,
        -9.3e18,
        9_223_372_036_854_775_808.0, // 2^63
        -9_223_372_036_854_775_808.0,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NAN,
        f64::MAX,
        f64::MIN,
    ];
    let mut seed = 11u64;
    for _ in 0..100_000 {
        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        let x = f64::from_bits(seed);
        values.push(x);
        values.push((seed >> 11) as f64 * 1e-6 - 4e6);
    }
    for x in values {
        assert_eq!(ceil_i64(x), x.ceil() as i64, "ceil {x:e}");
        assert_eq!(floor_i64(x), x.floor() as i64, "floor {x:e}");
    }
}

//! Rows against `pair`'s costs bit for bit, and the integer ceil and floor against libm's.

use super::*;
use crate::vehicle::VehicleParams;

/// Every cost of a row is `pair`'s, bit for bit (whichever path computed it), and the row is
/// trimmed to its finite ends: over speeds, gears and slopes, with brake points next to v_max.
#[test]
fn rows_hold_the_costs_of_pair() {
    let thesis = DpSettings::thesis();
    rows_hold_the_costs_of_pair_in(&thesis);
    rows_hold_the_costs_of_pair_in(&DpSettings { stage_model: StageModel::Trapezoid, ..thesis });
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
                let (span, at) =
                    forward_row(&vehicle, &p, v_i, gear, torque, grid, p.v_max_mps(), (&mut out, &mut memo));
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

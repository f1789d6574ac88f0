//! Tests of the map-based truck against truths constructed by hand: planes a linear interpolation
//! must reproduce, boundaries, and the energy balance.

use super::*;
use crate::CoreError;

/// z = 5000 + 2·n + 30·T [g/h], positive over the map: linear interpolation on any triangulation reproduces a plane.
pub(super) fn plane(n: f64, t: f64) -> f64 {
    5000.0 + 2.0 * n + 30.0 * t
}

/// Scattered points of the plane: a grid of speeds with torques that differ from speed to speed.
pub(super) fn plane_points() -> Vec<(f64, f64, f64)> {
    let mut pts = Vec::new();
    for (k, n) in [600.0, 900.0, 1200.0, 1500.0, 1800.0].into_iter().enumerate() {
        for j in 0..6 {
            let t = -100.0 + j as f64 * (300.0 + 17.0 * k as f64);
            pts.push((n, t, plane(n, t)));
        }
    }
    pts
}

#[test]
fn a_curve_is_linear_between_its_points_and_holds_its_end_values() {
    let c = Curve::new("c", &[(600.0, 1000.0), (1000.0, 2000.0), (2000.0, 1500.0)]).unwrap();
    assert_eq!(c.at(800.0), 1500.0);
    assert_eq!(c.at(1500.0), 1750.0);
    assert_eq!(c.at(2200.0), 1500.0);
    assert_eq!(c.at(500.0), 1000.0);
    assert!(c.covers(600.0) && c.covers(2000.0) && !c.covers(2000.1));
}

/// The bucketed look-up finds the segment a binary search finds, on curves with very uneven
/// spacing (points 1e-3 apart next to gaps of hundreds), at the points themselves, between them
/// and outside the range.
#[test]
fn a_curve_finds_the_same_segment_as_a_search_however_its_points_are_spaced() {
    let mut seed: u64 = 12345;
    let mut next = move || {
        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    for _ in 0..200 {
        let mut x = -50.0 + 100.0 * next();
        let mut points = Vec::new();
        for _ in 0..2 + (next() * 40.0) as usize {
            points.push((x, next() * 10.0));
            x += if next() < 0.3 { 1e-3 * next() + 1e-9 } else { 300.0 * next() + 1e-6 };
        }
        let c = Curve::new("c", &points).unwrap();
        let (xs, ys): (Vec<f64>, Vec<f64>) = points.iter().copied().unzip();
        let search = |x: f64| {
            let n = xs.len();
            let x = x.clamp(xs[0], xs[n - 1]);
            let i = xs.partition_point(|&xi| xi <= x).clamp(1, n - 1);
            ys[i - 1] + (ys[i] - ys[i - 1]) * (x - xs[i - 1]) / (xs[i] - xs[i - 1])
        };
        let (lo, hi) = c.x_range();
        let probes = xs.iter().copied().chain((0..300).map(|_| lo - 10.0 + (hi - lo + 20.0) * next()));
        for x in probes {
            assert_eq!(c.at(x).to_bits(), search(x).to_bits(), "x {x} on {points:?}");
        }
    }
}

#[test]
fn a_curve_refuses_x_that_does_not_increase() {
    let err = Curve::new("full_load_curve", &[(600.0, 1.0), (600.0, 2.0)]).unwrap_err();
    assert_eq!(err.key(), "full_load_curve");
    assert!(err.to_string().contains("increasing x at point 2"), "{err}");
}

#[test]
fn the_fuel_map_reproduces_a_plane_anywhere_inside_it() {
    let map = FuelMap::new("fuel_map", &plane_points()).unwrap();
    for (n, t) in [(700.0, 0.0), (1000.0, 600.0), (1333.0, 1111.0), (1799.0, 1300.0), (600.0, -100.0)] {
        let got = map.interpolate(n, t).expect("inside the map");
        assert!((got - plane(n, t)).abs() < 1e-6 * plane(n, t).abs().max(1.0), "({n}, {t}): {got}");
    }
}

#[test]
fn outside_the_map_the_fuel_rate_is_the_boundary_value_nearest_to_it() {
    // The unit square in scaled coordinates: speeds 1000–2000 rpm, torques 0–1000 Nm.
    let pts = [(1000.0, 0.0, 0.0), (2000.0, 0.0, 100.0), (1000.0, 1000.0, 10.0), (2000.0, 1000.0, 110.0)];
    let map = FuelMap::new("fuel_map", &pts).unwrap();
    assert_eq!(map.interpolate(1500.0, 1200.0), None);
    // Above the top edge (torque 1000 Nm) at 1500 rpm: the top edge's value there, 60 g/h.
    assert!((map.extrapolate(1500.0, 1200.0) - 60.0).abs() < 1e-9);
    // Beyond the corner (2000 rpm, 1000 Nm): the corner's value.
    assert!((map.extrapolate(2500.0, 1500.0) - 110.0).abs() < 1e-9);
}

#[test]
fn the_fuel_map_answers_nan_and_huge_inputs_without_panicking() {
    let map = FuelMap::new("fuel_map", &plane_points()).unwrap();
    for (n, t) in [(f64::NAN, 0.0), (f64::INFINITY, 0.0), (1000.0, f64::INFINITY), (1e300, 1e300), (-1e300, 5.0)] {
        assert_eq!(map.interpolate(n, t), None);
        let x = map.extrapolate(n, t);
        assert_eq!(x.is_nan(), !(n.is_finite() && t.is_finite()), "({n}, {t}) -> {x}");
    }
    // Far beyond the top right corner: the corner's value.
    assert!((map.extrapolate(1e300, 1e300) - plane(1800.0, -100.0 + 5.0 * 368.0)).abs() < 1e-6);
}

#[test]
fn the_fuel_map_refuses_a_repeated_point_and_points_on_a_line() {
    let mut pts = plane_points();
    pts.push(pts[3]);
    let err = FuelMap::new("fuel_map", &pts).unwrap_err();
    assert!(err.to_string().contains("point 31 repeats"), "{err}");
    let line = [(600.0, 0.0, 1.0), (700.0, 100.0, 2.0), (800.0, 200.0, 3.0)];
    assert!(matches!(FuelMap::new("fuel_map", &line), Err(CoreError::Invalid { .. })));
}

pub(crate) fn engine() -> Engine {
    let full_load = [(600.0, 1000.0, -100.0), (1200.0, 2000.0, -150.0), (1800.0, 1600.0, -200.0)];
    Engine::new(600.0, 4.0, &full_load, &plane_points()).unwrap()
}

#[test]
fn the_engine_cuts_fuel_at_or_below_its_drag_torque_and_reads_its_map_above() {
    let e = engine();
    assert_eq!(e.drag_torque_nm(900.0), -125.0);
    assert_eq!(e.fuel_rate_g_per_h(900.0, -125.0), 0.0);
    assert!((e.fuel_rate_g_per_h(900.0, 500.0) - plane(900.0, 500.0)).abs() < 1e-6);
    let (power_w, at_rpm) = e.rated_power();
    assert_eq!(at_rpm, 1800.0);
    assert!((power_w - 1600.0 * 1800.0 * 2.0 * std::f64::consts::PI / 60.0).abs() < 1e-6);
}

/// The body of the test trucks: 40 t, 6 m² drag area, 4 kW of auxiliaries.
pub(crate) fn body() -> Body {
    Body {
        mass_kg: 40_000.0,
        wheels_inertia_kgm2: 60.0,
        cda_m2: 6.0,
        air_density_kgpm3: 1.2,
        rolling_resistance: 0.006,
        aux_power_w: 4_000.0,
    }
}

pub(crate) fn truck() -> MapTruck {
    let driveline = Driveline::new((&[3.0, 2.0, 1.0], 3.0), (0.98, 0.97, 20.0), 0.5).unwrap();
    MapTruck::new(engine(), driveline, body()).unwrap()
}

#[test]
fn engine_speed_follows_from_road_speed_ratio_and_tyre_radius() {
    let t = truck();
    // 20 m/s on a 0.5 m radius is 40 rad/s at the wheel; gear 2 and axle 3 make 240 rad/s.
    let expected = 240.0 * 60.0 / (2.0 * std::f64::consts::PI);
    assert!((t.driveline().engine_speed_rpm(20.0, 2) - expected).abs() < 1e-9);
}

#[test]
fn at_steady_speed_the_engine_delivers_the_road_load_the_driveline_losses_and_the_auxiliaries() {
    let t = truck();
    let (v, slope) = (22.0, 0.01_f64.atan());
    let loads = t.road_loads(v, 0.0, slope);
    let expected_air = 0.5 * 1.2 * 6.0 * v.powi(3);
    assert!((loads.air_w - expected_air).abs() < 1e-6);
    assert!((loads.slope_w - 40_000.0 * G_MPS2 * slope.sin() * v).abs() < 1e-6);
    let op = t.operating_point(v, 0.0, slope, 3).unwrap();
    let omega = op.engine_speed_rpm / RPM_PER_RAD_S;
    let engine_w = op.engine_torque_nm * omega;
    let balance = (engine_w - 4_000.0 - 20.0 * omega) * 0.98 * 0.97 - loads.wheel_w();
    assert!(balance.abs() < 1e-6 * engine_w, "engine {engine_w} W, wheels {} W", loads.wheel_w());
    assert!(op.feasible);
}

#[test]
fn a_driveline_refuses_ratios_that_do_not_fall_and_efficiencies_outside_0_1() {
    let err = Driveline::new((&[3.0, 3.0], 3.0), (0.98, 0.97, 0.0), 0.5).unwrap_err();
    assert!(err.to_string().contains("gear 2 below gear 1"), "{err}");
    assert_eq!(Driveline::new((&[3.0], 3.0), (1.2, 0.97, 0.0), 0.5).unwrap_err().key(), "gear_efficiency");
}

#[test]
fn a_drag_area_curve_replaces_the_constant_and_is_linear_in_speed() {
    let t = truck().with_cda_curve(&[(10.0, 7.0), (30.0, 6.0)]).unwrap();
    assert_eq!(t.cda_m2(20.0), 6.5);
    let expected = 0.5 * 1.2 * 6.5 * 20.0_f64.powi(3);
    assert!((t.road_loads(20.0, 0.0, 0.0).air_w - expected).abs() < 1e-9);
    assert_eq!(truck().with_cda_curve(&[(10.0, -1.0), (30.0, 6.0)]).unwrap_err().key(), "cda_curve");
}

#[test]
fn on_a_descent_the_wheels_drive_the_engine_and_the_brakes_take_the_rest() {
    let t = truck();
    let (v, gear) = (22.0, 3);
    // Gentle: the engine's drag is enough; the power from the wheels, less the driveline's share,
    // turns the engine against its torque, the auxiliaries and the driveline's drag.
    let slope = (-0.013_f64).atan();
    let op = t.operating_point(v, 0.0, slope, gear).unwrap();
    let omega = op.engine_speed_rpm / RPM_PER_RAD_S;
    let wheel_w = t.road_loads(v, 0.0, slope).wheel_w();
    assert!(wheel_w < 0.0 && op.engine_torque_nm < 0.0 && op.brake_power_w == 0.0, "{op:?}");
    let engine_side_w = (op.engine_torque_nm - 4_000.0 / omega - 20.0) * omega;
    assert!((engine_side_w - wheel_w * 0.98 * 0.97).abs() < 1e-6 * wheel_w.abs());
    // Above its drag torque the engine is fuelled, less than at zero torque.
    assert!(op.fuel_g_per_h > 0.0 && op.fuel_g_per_h < plane(op.engine_speed_rpm, 0.0));
    // Steep: below the drag torque; the brakes take what the drag does not, at the wheels.
    let slope = (-0.08_f64).atan();
    let op = t.operating_point(v, 0.0, slope, gear).unwrap();
    let drag = t.engine().drag_torque_nm(op.engine_speed_rpm);
    let held_w = ((drag - 4_000.0 / omega - 20.0) / (0.98 * 0.97)) * omega;
    let expected = held_w - t.road_loads(v, 0.0, slope).wheel_w();
    assert!(op.brake_power_w > 0.0 && (op.brake_power_w - expected).abs() < 1e-6 * expected);
    assert_eq!(op.fuel_g_per_h, 0.0);
}

#[test]
fn beyond_the_full_load_curve_there_is_no_fuel_rate_and_no_point_without_a_speed() {
    let t = truck();
    let op = t.operating_point(60.0, 0.0, 0.0, 1).unwrap(); // 60 m/s in gear 1: far above 1800 rpm
    assert!(!op.feasible && op.fuel_g_per_h.is_nan());
    let bad = [(0.0, 0.0, 0.0, 1), (f64::NAN, 0.0, 0.0, 1), (20.0, f64::NAN, 0.0, 1), (20.0, 0.0, f64::INFINITY, 1)];
    for (v, a, s, g) in bad.into_iter().chain([(20.0, 0.0, 0.0, 0), (20.0, 0.0, 0.0, 4)]) {
        assert!(t.operating_point(v, a, s, g).is_none());
    }
}

#[test]
fn in_a_square_cell_the_insertion_order_picks_the_diagonal_as_vectos_map_does() {
    // Four corners on one circle, not on one plane: the diagonal decides the value inside. Inserted
    // (0,0), (1,0), (0,1), (1,1), the last corner finds the first triangle's circumcircle only
    // touching it, so that triangle stays and the diagonal is (1,0)–(0,1).
    let z = |n: f64, t: f64| if (n, t) == (1.0, 1.0) { 10.0 } else { 0.0 };
    let corners = [(0.0, 0.0), (0.0, 1.0), (1.0, 0.0), (1.0, 1.0)]; // (speed, torque): torque is x
    let map = FuelMap::new("fuel_map", &corners.map(|(n, t)| (n, t, z(n, t)))).unwrap();
    // Beyond the diagonal (1,0)–(0,1), in the triangle holding the raised corner: linear towards it.
    assert!((map.interpolate(0.75, 0.75).unwrap() - 5.0).abs() < 1e-12);
    // On the near side, in the flat triangle: zero (the other diagonal would give 2.5 at (0.25, 0.75)).
    assert!(map.interpolate(0.25, 0.25).unwrap().abs() < 1e-12);
    assert!(map.interpolate(0.25, 0.75).unwrap().abs() < 1e-12);
}

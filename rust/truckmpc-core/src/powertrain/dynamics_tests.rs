//! Tests of the map-based truck as the plant and the controllers drive it, against truths built
//! from the truck's own components: its operating points, the energy balance, a plane fuel map
//! (where the price of kinetic energy has a closed form), and a shift's traction interruption.

use std::sync::Arc;

use super::tests::{body, engine, plane, plane_points, truck};
use super::*;
use crate::dp::fuel_time::kinetic_fuel_g;
use crate::levels::{pedal_accel, stationary};
use crate::plant::{Control, Plant};
use crate::road::Road;
use crate::vehicle::{Vehicle, VehicleParams, NEUTRAL};

fn vehicle(interruption_s: f64) -> Vehicle {
    Vehicle::from_map(Arc::new(MapModel::new(truck(), 1.0e5, interruption_s)), &VehicleParams::default()).unwrap()
}

#[test]
fn holding_a_speed_on_a_grade_takes_the_trucks_own_operating_point() {
    let v = vehicle(0.0);
    let truck = truck();
    for (speed, grade, gear) in [(22.0, 0.01, 3), (15.0, 0.02, 2), (20.0, -0.002, 3)] {
        let point = stationary(&v, speed, grade, gear);
        assert!(point.feasible && point.pedal > 0.0, "{speed} m/s on {grade}: {point:?}");
        let op = truck.operating_point(speed, 0.0, f64::atan(grade), gear).unwrap();
        let n = v.engine_speed_rpm(speed, gear);
        assert!((n - op.engine_speed_rpm).abs() < 1e-9);
        let torque = v.engine_torque_nm(n, point.pedal, gear);
        assert!((torque - op.engine_torque_nm).abs() < 1e-6 * op.engine_torque_nm.abs(), "{torque} vs {op:?}");
        // The map is a plane, which the resampled grid reproduces exactly.
        let fuel_g_per_h = v.fuel_rate_gps(speed, point.pedal, gear) * 3600.0;
        assert!((fuel_g_per_h - op.fuel_g_per_h).abs() < 1e-6 * op.fuel_g_per_h, "{fuel_g_per_h} vs {op:?}");
        // The model alone, through the interface: the same operating point, all braking by friction.
        let model = MapModel::new(truck.clone(), 1.0e5, 0.0);
        let u = Control { pedal: point.pedal, brake: 0.0, gear };
        let rate_g_per_h = Powertrain::energy_rate(&model, speed, u) * 3600.0;
        assert!((rate_g_per_h - op.fuel_g_per_h).abs() < 1e-6 * op.fuel_g_per_h, "{rate_g_per_h} vs {op:?}");
        let held = Powertrain::accel_on(&model, speed, point.pedal, 0.0, gear, model.slope_torque_nm(grade));
        assert!(held.abs() < 1e-9, "{held}");
        let braking = Control { brake: 0.5, ..u };
        assert_eq!(model.friction_brake_force_n(speed, braking), 0.5e5 / truck.driveline().wheel_radius_m());
    }
}

#[test]
fn acceleration_is_the_wheel_force_left_over_by_the_road_loads_on_the_effective_mass() {
    let v = vehicle(0.0);
    let t = truck();
    let (speed, gear) = (15.0, 2);
    let (r, ratio) = (t.driveline().wheel_radius_m(), t.driveline().ratio(gear));
    let n = t.driveline().engine_speed_rpm(speed, gear);
    let aux_nm = t.body().aux_power_w / (n / RPM_PER_RAD_S);
    let wheel_nm = t.driveline().wheel_torque_nm(t.engine().max_torque_nm(n) - aux_nm, gear, n);
    let loads = t.road_loads(speed, 0.0, 0.0);
    let mass = 40_000.0 + 60.0 / (r * r) + 4.0 * ratio * ratio / (r * r);
    let expected = (wheel_nm / r * speed - loads.wheel_w()) / (mass * speed);
    let got = v.accel_mps2(speed, 1.0, 0.0, gear, 0.0);
    assert!((got - expected).abs() < 1e-9, "{got} vs {expected}");
    // Fuel cut: the engine's drag (and the auxiliaries) brake the truck, and no fuel flows.
    let cut_nm = t.driveline().wheel_torque_nm(t.engine().drag_torque_nm(n) - aux_nm, gear, n);
    let expected_cut = (cut_nm / r * speed - loads.wheel_w()) / (mass * speed);
    assert!((v.accel_mps2(speed, 0.0, 0.0, gear, 0.0) - expected_cut).abs() < 1e-9);
    assert_eq!(v.fuel_rate_gps(speed, 0.0, gear), 0.0);
}

#[test]
fn kinetic_energy_costs_the_maps_marginal_fuel_through_the_driveline() {
    // On a plane map ṁ = (5000 + 2n + 30T)/3600 g/s, so at a fixed speed the fuel per unit of
    // wheel torque is 30/(3600·ratio·η) while driving, and ½v² per metre is c1·(W − load).
    let v = vehicle(0.0);
    let t = truck();
    for (speed, gear) in [(22.0, 3), (12.0, 2)] {
        let c1 = v.gear(gear).c1;
        let per_wheel_nm = 30.0 / 3600.0 / (t.driveline().ratio(gear) * t.driveline().efficiency());
        let expected = per_wheel_nm / (c1 * speed);
        let got = kinetic_fuel_g(&v, speed, gear);
        assert!((got / expected - 1.0).abs() < 1e-9, "{speed} m/s gear {gear}: {got} vs {expected}");
        assert!(pedal_accel(&v, speed, gear, 0.0).gain > 0.0);
    }
}

#[test]
fn the_resampled_fuel_map_stays_within_a_small_share_of_the_triangulated_one() {
    // A curved surface, triangulated from scattered points: the grid differs only where a
    // triangle's edge crosses one of its cells.
    let curved = |n: f64, t: f64| 2000.0 + 1.5 * n + 18.0 * t + 0.004 * t * t + 1e-3 * n * t;
    let mut points = Vec::new();
    for i in 0..9 {
        for j in 0..8 {
            let (n, t) = (600.0 + 200.0 * i as f64, -150.0 + 300.0 * j as f64 + 13.0 * i as f64);
            points.push((n, t, curved(n, t)));
        }
    }
    let map = FuelMap::new("fuel_map", &points).unwrap();
    let grid = FuelGrid::new(&map, (600.0, 2200.0), (-150.0, 2200.0));
    let top = points.iter().map(|p| p.2).fold(0.0, f64::max);
    let mut worst: f64 = 0.0;
    for k in 0..2000 {
        let (n, t) = (600.0 + (k * 37 % 1600) as f64, -150.0 + (k * 53 % 2350) as f64);
        worst = worst.max((grid.at(n, t) - map.extrapolate(n, t)).abs());
    }
    assert!(worst < 1e-3 * top, "worst {worst} g/h of {top}");
    // A plane is reproduced exactly.
    let flat = FuelMap::new("fuel_map", &plane_points()).unwrap();
    let grid = FuelGrid::new(&flat, (600.0, 1800.0), (-100.0, 1500.0));
    assert!((grid.at(1111.0, 777.0) - plane(1111.0, 777.0)).abs() < 1e-6);
}

#[test]
fn a_shift_rolls_in_neutral_at_fuel_cut_for_the_gearboxs_interruption_time() {
    let road = Arc::new(Road::new(vec![0.0, 10_000.0], vec![0.0]).unwrap());
    // 12 m/s: 688 rpm in gear 3, 1375 rpm in gear 2, both on the full-load curve.
    let (start, dt) = (12.0, 0.05);
    let drive = |interruption_s: f64, second_gear: usize| {
        let mut plant = Plant::new(Arc::new(vehicle(interruption_s)), road.clone(), 0.0, start);
        plant.step(Control { pedal: 0.5, brake: 0.0, gear: 3 }, dt);
        let before = plant.state();
        // 0.95 s, inside the 1 s interruption (whose end 20 steps of 0.05 s reach only to rounding).
        for _ in 0..19 {
            plant.step(Control { pedal: 0.5, brake: 0.0, gear: second_gear }, dt);
        }
        (before, plant.state())
    };
    let (before, after) = drive(1.0, 2);
    assert_eq!(after.fuel_g, before.fuel_g, "no fuel while traction is interrupted");
    // Exactly as rolling in neutral with no fuel: the neutral plant's speed.
    let (_, rolled) = drive(0.0, NEUTRAL);
    assert!((after.v_mps - rolled.v_mps).abs() < 1e-12 && (after.s_m - rolled.s_m).abs() < 1e-9);
    // Instant shifts (the thesis's truck's way): fuel flows at once.
    let (before, after) = drive(0.0, 2);
    assert!(after.fuel_g > before.fuel_g);
    assert_eq!(Vehicle::new(VehicleParams::default()).unwrap().traction_interruption_s(), 0.0);
}

/// Points of a loss map that follow the affine law of a stage of efficiency `eta` and drag
/// `drag_nm` (at its input): loss = T − passed, passed = (T − drag)·η driving, (T − drag)/η driven.
fn affine_points(eta: f64, drag_nm: f64) -> Vec<(f64, f64, f64)> {
    let mut points = Vec::new();
    for n in [0.0, 500.0, 1000.0, 1500.0, 2000.0, 2500.0, 3000.0] {
        let mut torques = vec![-20000.0, -3000.0, -1000.0, -300.0, 0.0, drag_nm, 300.0, 1000.0, 3000.0, 20000.0];
        torques.dedup();
        for t in torques {
            let passed = if t >= drag_nm { (t - drag_nm) * eta } else { (t - drag_nm) / eta };
            points.push((n, t, t - passed));
        }
    }
    points
}

#[test]
fn loss_maps_that_follow_the_affine_law_give_the_affine_drivelines_torques() {
    let ratios = [3.0, 2.0, 1.0];
    let affine = Driveline::new((&ratios, 3.0), (0.97, 0.98, 25.0), 0.5).unwrap();
    let gear_maps: Vec<Vec<(f64, f64, f64)>> = (0..3).map(|_| affine_points(0.97, 25.0)).collect();
    let mapped = affine.clone().with_loss_maps(Some(&gear_maps), Some(&affine_points(0.98, 0.0))).unwrap();
    assert_eq!(mapped.has_loss_maps(), (true, true));
    for gear in 1..=3 {
        for n in [700.0, 1234.0, 1900.0] {
            for engine_nm in [-250.0, -40.0, 10.0, 400.0, 1500.0, 2400.0] {
                let want = affine.wheel_torque_nm(engine_nm, gear, n);
                let got = mapped.wheel_torque_nm(engine_nm, gear, n);
                // Within half a newton-metre at the gearbox input: the resampled map rounds the
                // kink where the torque passed on changes sign over one cell of its grid.
                let at_input = (got - want).abs() / (ratios[gear - 1] * 3.0);
                assert!(at_input < 0.5, "gear {gear} {n} rpm {engine_nm} Nm: {got} vs {want}");
                let back = mapped.engine_torque_nm(got, gear, n);
                assert!((back - engine_nm).abs() < 1e-6 * engine_nm.abs().max(1.0), "round trip {back} vs {engine_nm}");
            }
        }
    }
}

#[test]
fn a_loss_map_for_every_gear_or_none() {
    let d = Driveline::new((&[3.0, 2.0], 3.0), (0.97, 0.98, 25.0), 0.5).unwrap();
    let err = d.with_loss_maps(Some(&[affine_points(0.97, 25.0)]), None).unwrap_err();
    assert_eq!(err.key(), "gear_loss_maps");
}

/// A retarder losing 10 Nm at standstill and 1 Nm more per 100 rpm of its own speed.
fn retarder(position: RetarderPosition, ratio: f64) -> Retarder {
    Retarder::new(position, ratio, &[(0.0, 10.0), (3000.0, 40.0)]).unwrap()
}

#[test]
fn an_output_retarder_drags_on_the_gearbox_output_in_gear_and_in_neutral() {
    let plain = Driveline::new((&[3.0, 2.0, 1.0], 3.0), (0.97, 0.98, 25.0), 0.5).unwrap();
    let with = plain.clone().with_retarder(retarder(RetarderPosition::GearboxOutput, 1.0));
    let (gear, n_rpm) = (2, 1200.0);
    // At 1200 rpm in gear 2 the gearbox output turns at 600 rpm: 16 Nm taken there, before the axle.
    let engine_nm = 800.0;
    let drop = plain.wheel_torque_nm(engine_nm, gear, n_rpm) - with.wheel_torque_nm(engine_nm, gear, n_rpm);
    assert!((drop - 16.0 * 0.98 * 3.0).abs() < 1e-9, "{drop}");
    let back = with.engine_torque_nm(with.wheel_torque_nm(engine_nm, gear, n_rpm), gear, n_rpm);
    assert!((back - engine_nm).abs() < 1e-9);
    let losses = with.stage_losses_w(engine_nm, gear, n_rpm);
    assert!((losses.retarder_w - 16.0 * 600.0 / RPM_PER_RAD_S).abs() < 1e-9);
    // In neutral at 10 m/s the axle's input turns at 10/0.5·3 rad/s = 573 rpm: the retarder's
    // 15.73 Nm there, through the driven axle (efficiency 0.98 against the wheels), at the wheels.
    let shaft_rpm = 10.0 / 0.5 * 3.0 * RPM_PER_RAD_S;
    let expected = -(10.0 + shaft_rpm / 100.0) / 0.98 * 3.0;
    assert!((with.neutral_wheel_torque_nm(10.0) - expected).abs() < 1e-9);
    assert_eq!(plain.neutral_wheel_torque_nm(10.0), 0.0);
}

#[test]
fn an_input_retarder_drags_at_engine_speed_through_its_ratio_and_not_in_neutral() {
    let plain = Driveline::new((&[3.0, 2.0, 1.0], 3.0), (0.97, 0.98, 25.0), 0.5).unwrap();
    let with = plain.clone().with_retarder(retarder(RetarderPosition::GearboxInput, 2.0));
    // At 900 rpm the retarder turns at 1800 rpm (28 Nm), twice that seen at its shaft.
    let extra = with.engine_torque_nm(5000.0, 1, 900.0) - plain.engine_torque_nm(5000.0, 1, 900.0);
    assert!((extra - 56.0).abs() < 1e-9, "{extra}");
    assert_eq!(with.neutral_wheel_torque_nm(10.0), 0.0);
}

#[test]
fn in_neutral_a_truck_with_an_axle_loss_map_decelerates_by_the_axles_drag() {
    let ratios = [3.0, 2.0, 1.0];
    let affine = Driveline::new((&ratios, 3.0), (0.97, 0.98, 25.0), 0.5).unwrap();
    // An axle map losing 30 Nm at its input whatever the torque.
    let axle: Vec<(f64, f64, f64)> =
        [0.0, 3000.0].iter().flat_map(|&n| [-5000.0, 0.0, 5000.0].map(|t| (n, t, 30.0))).collect();
    let mapped = affine.clone().with_loss_maps(None, Some(&axle)).unwrap();
    let plain = MapModel::new(MapTruck::new(engine(), affine, body()).unwrap(), 30_000.0, 1.0);
    let dragged = MapModel::new(MapTruck::new(engine(), mapped, body()).unwrap(), 30_000.0, 1.0);
    let (v, slope) = (20.0, 0.0);
    let dv = plain.accel_on(v, 0.0, 0.0, NEUTRAL, slope) - dragged.accel_on(v, 0.0, 0.0, NEUTRAL, slope);
    // 30 Nm at the axle's input is 90 Nm at the wheels, over the rolling mass's r / inertia.
    assert!((dv - 90.0 * plain.c1(NEUTRAL)).abs() < 1e-6, "{dv}");
}

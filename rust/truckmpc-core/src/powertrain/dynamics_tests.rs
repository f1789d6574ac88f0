//! Tests of the map-based truck as the plant and the controllers drive it, against truths built
//! from the truck's own components: its operating points, the energy balance, a plane fuel map
//! (where the price of kinetic energy has a closed form), and a shift's traction interruption.

use std::sync::Arc;

use super::tests::{plane, plane_points, truck};
use super::*;
use crate::dp::fuel_time::kinetic_fuel_g;
use crate::levels::{pedal_accel, stationary};
use crate::plant::{Control, Plant};
use crate::road::Road;
use crate::vehicle::{Vehicle, VehicleParams, NEUTRAL};

fn vehicle(interruption_s: f64) -> Vehicle {
    Vehicle::from_map(MapModel::new(truck(), 1.0e5, interruption_s), &VehicleParams::default()).unwrap()
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
    let wheel_nm = t.driveline().wheel_torque_nm(t.engine().max_torque_nm(n) - aux_nm, gear);
    let loads = t.road_loads(speed, 0.0, 0.0);
    let mass = 40_000.0 + 60.0 / (r * r) + 4.0 * ratio * ratio / (r * r);
    let expected = (wheel_nm / r * speed - loads.wheel_w()) / (mass * speed);
    let got = v.accel_mps2(speed, 1.0, 0.0, gear, 0.0);
    assert!((got - expected).abs() < 1e-9, "{got} vs {expected}");
    // Fuel cut: the engine's drag (and the auxiliaries) brake the truck, and no fuel flows.
    let cut_nm = t.driveline().wheel_torque_nm(t.engine().drag_torque_nm(n) - aux_nm, gear);
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
        let c1 = v.map_model().unwrap().c1(gear);
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
    let (start, dt) = (20.0, 0.05);
    let drive = |interruption_s: f64, second_gear: usize| {
        let mut plant = Plant::new(Arc::new(vehicle(interruption_s)), road.clone(), 0.0, start);
        plant.step(Control { pedal: 0.5, brake: 0.0, gear: 3 }, dt);
        let before = plant.state();
        for _ in 0..20 {
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

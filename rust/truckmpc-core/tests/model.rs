//! The model's equations against values computed by hand from table A.1/A.2 (40 t, 85 km/h,
//! gear 12), the pedal/brake levels against the Euler stage they invert, and the plant's energy
//! balance.

use std::sync::Arc;

use truckmpc_core::levels::{brake_for_step, euler_step, pedal_for_step, stage_fuel_g};
use truckmpc_core::powertrain::{Control as U, Powertrain, ThesisModel};
use truckmpc_core::{Control, Plant, Road, Vehicle, VehicleParams, NEUTRAL};

const V85: f64 = 85.0 / 3.6;

fn truck() -> Vehicle {
    Vehicle::new(VehicleParams::default()).unwrap()
}

fn close(got: f64, want: f64) {
    assert!((got - want).abs() <= 1e-9 * want.abs().max(1.0), "got {got}, want {want}");
}

#[test]
fn engine_speed_fueling_torque_and_fuel_by_hand() {
    let v = truck();
    // N = 30 i_t i_f v / (π r_w), δ_max = a N² + b N + c, T = a_e N + b_e P δ_max + c_e.
    let n = v.engine_speed_rpm(V85, 12);
    close(n, 1417.8562959100097);
    let thesis = ThesisModel::new(VehicleParams::default()).unwrap();
    close(thesis.fueling_max_mg(n), 218.80932462179118);
    close(v.engine_torque_nm(n, 0.5, 12), 914.9377809913007);
    close(v.engine_torque_nm(n, 0.0, 12), -176.28135404008086); // fuel cut: drag torque (2.4)
    close(v.fuel_rate_gps(V85, 0.5, 12), 7.756004462970594); // (B.2): c5 N P δ_max
    close(v.fuel_rate_gps(V85, 0.0, 12), 0.0);
    close(v.fuel_rate_gps(V85, 0.7, NEUTRAL), 0.3132); // idle: c5 N_idle δ_idle
    close(v.engine_speed_rpm(V85, NEUTRAL), 600.0);
    // The same through the interface, on the thesis's model alone.
    close(Powertrain::engine_speed_rpm(&thesis, V85, 12), 1417.8562959100097);
    close(thesis.energy_rate(V85, U { pedal: 0.5, brake: 0.3, gear: 12 }), 7.756004462970594);
    close(thesis.energy_rate(V85, U { pedal: 0.7, brake: 0.0, gear: NEUTRAL }), 0.3132);
}

#[test]
fn acceleration_matches_the_uncompacted_driveline_model() {
    // Section 2.4 with c_r cos α + sin α, written out, at P = 0.5, B = 0.1, 2 % uphill.
    close(truck().accel_mps2(V85, 0.5, 0.1, 12, 0.02), -0.6572376267327567);
    let thesis = ThesisModel::new(VehicleParams::default()).unwrap();
    close(thesis.accel_on(V85, 0.5, 0.1, 12, thesis.slope_torque_nm(0.02)), -0.6572376267327567);
}

#[test]
fn neutral_has_no_engine_and_coasts_further_than_fuel_cut() {
    let v = truck();
    let coast = v.accel_mps2(V85, 0.0, 0.0, NEUTRAL, 0.0);
    let cut = v.accel_mps2(V85, 0.0, 0.0, 12, 0.0);
    assert!(coast < 0.0 && cut < coast, "neutral {coast}, fuel cut {cut}");
    // Pedal is meaningless in neutral.
    close(v.accel_mps2(V85, 1.0, 0.0, NEUTRAL, 0.0), coast);
}

#[test]
fn acceleration_falls_with_slope_brake_and_speed_and_rises_with_pedal() {
    let v = truck();
    let a = |speed: f64, pedal: f64, brake: f64, slope: f64| v.accel_mps2(speed, pedal, brake, 12, slope);
    assert!(a(V85, 0.5, 0.0, 0.01) < a(V85, 0.5, 0.0, 0.0));
    assert!(a(V85, 0.5, 0.2, 0.0) < a(V85, 0.5, 0.0, 0.0));
    assert!(a(V85, 0.6, 0.0, 0.0) > a(V85, 0.5, 0.0, 0.0));
    assert!(a(25.0, 0.5, 0.0, 0.0) < a(V85, 0.5, 0.0, 0.0));
}

#[test]
fn pedal_and_brake_levels_invert_the_euler_stage() {
    let v = truck();
    for (v0, v1, slope) in [(V85, V85 + 0.05, 0.0), (V85, V85 - 0.05, -0.005), (22.0, 22.1, 0.005)] {
        let pedal = pedal_for_step(&v, v0, v1, 12, slope, 25.0);
        assert!((0.0..=1.0).contains(&pedal), "pedal {pedal}");
        close(euler_step(&v, v0, pedal, 0.0, 12, slope, 25.0), v1);
    }
    let brake = brake_for_step(&v, 25.0, 25.0, 12, -0.04, 25.0);
    assert!((0.0..=1.0).contains(&brake), "brake {brake}");
    close(euler_step(&v, 25.0, 0.0, brake, 12, -0.04, 25.0), 25.0);
    close(stage_fuel_g(&v, V85, 0.5, 12, 25.0), 25.0 / V85 * 7.756004462970594);
}

#[test]
fn plant_energy_balance_on_a_hill() {
    // Over a run at constant inputs, engine work at the wheel equals the change of kinetic and
    // potential energy plus the losses to air, rolling and brakes (up to the rotating inertia).
    let vehicle = Arc::new(truck());
    let road = Arc::new(Road::new(vec![0.0, 500.0, 1000.0], vec![0.0, -0.03]).unwrap());
    let mut plant = Plant::new(vehicle.clone(), road.clone(), 0.0, V85);
    let u = Control { pedal: 0.0, brake: 0.05, gear: NEUTRAL };
    plant.advance_to(u, 0.05, 1000.0);
    let s = plant.state();
    let p = vehicle.params();
    let m = p.mass_kg;
    let wheels = p.wheel_inertia_kgm2 / (p.wheel_radius_m * p.wheel_radius_m);
    let kinetic = 0.5 * (m + wheels) * (s.v_mps * s.v_mps - V85 * V85);
    let potential = m * p.gravity_mps2 * (-0.03f64).sin() * 500.0;
    // Air and rolling losses by integrating along the way is what the plant does; here the
    // balance is checked for the brake term: with rolling and air drag switched off, all of the
    // potential energy goes into motion or the brake.
    assert!(s.brake_energy_j > 0.0 && s.fuel_g > 0.0);
    let frictionless = Arc::new(
        Vehicle::new(VehicleParams { rolling_resistance: 0.0, air_drag_coefficient: 0.0, ..VehicleParams::default() })
            .unwrap(),
    );
    let mut ideal = Plant::new(frictionless, road, 0.0, V85);
    ideal.advance_to(u, 0.05, 1000.0);
    let t = ideal.state();
    let kinetic_ideal = 0.5 * (m + wheels) * (t.v_mps * t.v_mps - V85 * V85);
    let balance = kinetic_ideal + potential + t.brake_energy_j;
    assert!(balance.abs() < 1e-7 * potential.abs(), "energy not conserved: {balance} J");
    assert!(kinetic < kinetic_ideal, "drag must cost energy");
}

#[test]
fn plant_stops_at_the_target_and_reports_a_stall() {
    let vehicle = Arc::new(truck());
    let steep = Arc::new(Road::new(vec![0.0, 3000.0], vec![0.35]).unwrap());
    let mut plant = Plant::new(vehicle.clone(), steep, 0.0, 10.0);
    plant.advance_to(Control { pedal: 1.0, brake: 0.0, gear: 1 }, 0.05, 3000.0);
    let s = plant.state();
    assert!(s.stalled && s.s_m < 3000.0, "{s:?}");
    assert!(s.v_mps < vehicle.stall_speed_mps());

    let flat = Arc::new(Road::new(vec![0.0, 1000.0], vec![0.0]).unwrap());
    let mut plant = Plant::new(vehicle, flat, 0.0, V85);
    plant.advance_to(Control { pedal: 0.45, brake: 0.0, gear: 12 }, 0.05, 777.7);
    assert!((plant.state().s_m - 777.7).abs() < 1e-6);
}

#[test]
fn road_slopes_altitude_and_flat_continuation() {
    let road = Road::new(vec![0.0, 100.0, 300.0], vec![0.02, -0.01]).unwrap();
    close(road.altitude_at(100.0), 2.0);
    close(road.altitude_at(300.0), 0.0);
    close(road.mean_slope(50.0, 150.0), (2.0 - 1.0 - 0.5) / 100.0);
    close(road.mean_slope(300.0, 400.0), 0.0); // flat beyond the end
    let mut hint = 0;
    close(road.slope_at(150.0, &mut hint), -0.01);
    close(road.slope_at(50.0, &mut hint), 0.02); // moving back works too
    assert!(Road::new(vec![0.0, 0.0], vec![0.0]).is_err());
    assert!(Road::new(vec![0.0], vec![]).is_err());
}

/// The hinted altitude search gives the same bits as a whole-profile search, whatever the hint:
/// on and between profile points, at both ends, beyond them, and moving backwards.
#[test]
fn altitude_with_any_hint_equals_the_whole_profile_search() {
    let distance_m: Vec<f64> = (0..40).map(|i| 25.0 * i as f64 + if i % 3 == 0 { 0.0 } else { 7.3 }).collect();
    let slopes: Vec<f64> = (0..39).map(|i| 0.001 * ((i * 7) % 11) as f64 - 0.004).collect();
    let road = Road::new(distance_m.clone(), slopes.clone()).unwrap();
    // The reference: altitudes summed segment by segment, the segment found by bisection.
    let mut altitude_m = vec![0.0];
    for i in 0..slopes.len() {
        altitude_m.push(altitude_m[i] + slopes[i] * (distance_m[i + 1] - distance_m[i]));
    }
    let last = slopes.len() - 1;
    let reference = |s: f64| {
        if s >= distance_m[last + 1] {
            return altitude_m[last + 1];
        }
        if s <= distance_m[0] {
            return slopes[0] * (s - distance_m[0]);
        }
        let i = distance_m.partition_point(|&d| d <= s).saturating_sub(1).min(last);
        altitude_m[i] + slopes[i] * (s - distance_m[i])
    };
    let mut positions: Vec<f64> = distance_m.clone();
    positions.extend(distance_m.windows(2).map(|w| 0.5 * (w[0] + w[1])));
    positions.extend([-5.0, 1e4, distance_m[last + 1] - 1e-9]);
    let backwards: Vec<f64> = positions.iter().rev().copied().collect();
    for order in [positions, backwards] {
        for start_hint in [0, 17, usize::MAX] {
            let mut hint = start_hint;
            for &s in &order {
                let got = road.altitude_from(s, &mut hint);
                assert_eq!(got.to_bits(), reference(s).to_bits(), "s {s}, hint from {start_hint}");
                assert_eq!(road.altitude_at(s).to_bits(), got.to_bits(), "s {s}");
            }
        }
    }
}

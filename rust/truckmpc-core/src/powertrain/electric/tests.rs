//! Tests of the battery-electric truck against truths built by hand: a power map whose loss torque
//! is linear on each side of zero torque (so VECTO's triangulation reproduces it exactly), a
//! battery whose current follows from the quadratic of its terminal power, and the energy balance
//! of a drive over hills.

use std::f64::consts::PI;
use std::sync::Arc;

use super::*;
use crate::plant::{Control, Plant};
use crate::powertrain::tests::body;
use crate::powertrain::{OverloadRating, Powertrain, Thermal, ThermalState, RPM_PER_RAD_S};
use crate::road::Road;

const COUNT: usize = 2;
/// Rated power of one machine [W]: 800 Nm up to 2000 rpm.
const RATED_W: f64 = 800.0 * 2000.0 * PI / 30.0;

/// One machine's loss torque [Nm] at `n_rpm` and `t_nm`, scaled by `k` for a second voltage level.
fn loss_torque(n_rpm: f64, t_nm: f64, k: f64) -> f64 {
    k * (5.0 + 0.04 * t_nm.abs() + 0.001 * n_rpm)
}

fn level(voltage_v: f64, k: f64) -> LevelData {
    let speeds: Vec<f64> = (0..=18).map(|i| 500.0 * i as f64).collect();
    let torque_limits = speeds
        .iter()
        .map(|&n| {
            let t = if n <= 2000.0 { 800.0 } else { RATED_W / (n / RPM_PER_RAD_S) };
            (n, k.sqrt() * t, -k.sqrt() * t)
        })
        .collect();
    let mut power_map = Vec::new();
    for &n in &speeds {
        for j in -8..=8 {
            let t = 100.0 * j as f64;
            let p = if n == 0.0 { 0.0 } else { n / RPM_PER_RAD_S * (t + loss_torque(n, t, k)) };
            power_map.push((n, t, p));
        }
    }
    LevelData { voltage_v, torque_limits, power_map, rating: None }
}

fn battery(discharge_a: f64) -> BatteryData {
    BatteryData {
        capacity_ah: 1000.0,
        ocv: vec![(0.0, 700.0), (100.0, 800.0)],
        resistance_mohm: vec![(0.0, 50.0), (100.0, 30.0)],
        current_limits: vec![(0.0, 800.0, discharge_a), (100.0, 800.0, discharge_a)],
        soc_window_pct: (8.0, 92.0),
    }
}

fn parts(discharge_a: f64, soc_start_pct: f64) -> ElectricParts {
    let soc_start_pct = Some(soc_start_pct);
    ElectricParts {
        machine: MachineData {
            count: COUNT,
            inertia_kgm2: 0.25,
            levels: vec![level(600.0, 1.0)],
            drag_curve: vec![(0.0, -2.0), (9000.0, -20.0)],
        },
        reduction: ReductionData {
            ratio: 12.0,
            loss_map: Some(vec![
                (0.0, -10000.0, 300.0),
                (0.0, 0.0, 0.0),
                (0.0, 10000.0, 300.0),
                (20000.0, -10000.0, 300.0),
                (20000.0, 0.0, 0.0),
                (20000.0, 10000.0, 300.0),
            ]),
            wheel_radius_m: 0.5,
        },
        battery: battery(discharge_a),
        body: body(),
        conditioning_w: 600.0,
        cda_curve: None,
        soc_start_pct,
    }
}

fn model(discharge_a: f64) -> ElectricModel {
    ElectricModel::new(parts(discharge_a, 50.0).build().unwrap(), 60_000.0)
}

/// VECTO's `ElectricMotorMapReader` scales the map by the count and `LookupElectricPower` gives
/// ω·(torque + loss torque): with a loss torque linear on each triangle, exact.
#[test]
fn electric_power_is_omega_times_torque_plus_the_interpolated_loss_torque_of_count_machines() {
    let truck = parts(2000.0, 50.0).build().unwrap();
    let m = truck.machines();
    for (n, total) in [(1234.0, 2.0 * 345.6), (4321.0, -2.0 * 123.4), (777.0, 0.0)] {
        let omega = n / RPM_PER_RAD_S;
        let expected = omega * (total + COUNT as f64 * loss_torque(n, total / COUNT as f64, 1.0));
        let got = m.electric_power_w(n, total);
        assert!((got - expected).abs() < 1e-9 * expected.abs().max(1.0), "{n} rpm {total} Nm: {got} vs {expected}");
    }
    assert_eq!(m.max_drive_nm(1000.0), 1600.0);
    assert!((m.max_brake_nm(4000.0) + 2.0 * RATED_W / (4000.0 / RPM_PER_RAD_S)).abs() < 1e-9);
    assert_eq!(m.max_drive_nm(9001.0), 0.0, "no torque above the limits' top speed");
    assert_eq!(m.drag_nm(4500.0), -22.0);
    assert_eq!(m.inertia_kgm2(), 0.5);
}

/// VECTO's `VoltageLevelData` interpolates linearly between the levels around the voltage, and
/// holds the nearer one outside them.
#[test]
fn voltage_levels_are_interpolated_at_the_battery_voltage_and_held_outside_them() {
    let levels = || {
        vec![
            VoltageLevel::new("a", 600.0, &level(600.0, 1.0).torque_limits, &level(600.0, 1.0).power_map).unwrap(),
            VoltageLevel::new("b", 800.0, &level(800.0, 4.0).torque_limits, &level(800.0, 4.0).power_map).unwrap(),
        ]
    };
    let drag = [(0.0, -2.0), (9000.0, -20.0)];
    let (n, t) = (3000.0, 2.0 * 200.0);
    let omega = n / RPM_PER_RAD_S;
    for (volts, k) in [(700.0, 2.5), (500.0, 1.0), (900.0, 4.0)] {
        let m = Machines::new(2, 0.25, levels(), &drag, volts).unwrap();
        let expected = omega * (t + 2.0 * loss_torque(n, t / 2.0, k));
        assert!((m.electric_power_w(n, t) - expected).abs() < 1e-6, "{volts} V");
        // The limits scale by √k at each level: 1 and 2, blended.
        let w = ((volts - 600.0) / 200.0_f64).clamp(0.0, 1.0);
        assert!((m.max_drive_nm(1000.0) - 2.0 * 800.0 * (1.0 + w)).abs() < 1e-9, "{volts} V");
    }
}

/// The current solves R·I² − U·I + P = 0 (VECTO's `Battery` solves the same quadratic), the store
/// gives U·I, and the limits are the powers at the current limits.
#[test]
fn battery_power_follows_from_the_open_circuit_voltage_and_the_internal_resistance() {
    let b = battery(1000.0).at(0.5).unwrap();
    assert_eq!((b.ocv_v, b.resistance_ohm), (750.0, 0.040));
    for terminal_w in [150_000.0, -80_000.0, 1.0e-3] {
        let i = b.current_a(terminal_w);
        assert!((750.0 * i - 0.04 * i * i - terminal_w).abs() < 1e-9 * terminal_w.abs().max(1.0));
        assert!((b.internal_power_w(terminal_w) - 750.0 * i).abs() < 1e-9);
    }
    assert!((b.max_discharge_w() - (750.0 * 1000.0 - 0.04 * 1.0e6)).abs() < 1e-6);
    assert!((b.max_charge_w() - (750.0 * 800.0 + 0.04 * 640_000.0)).abs() < 1e-6);
    assert!(b.current_a(b.max_discharge_w() * 1.0e3).is_nan(), "beyond the most the battery gives");
}

/// Declaration mode narrows 8–92 % by 5 % of its width (VECTO's `CreateBatteryData`) and starts
/// in the middle; a start outside the window is refused by name.
#[test]
fn the_usable_window_is_narrowed_for_ageing_and_a_run_starts_in_its_middle() {
    let data = battery(1000.0);
    let (lo, hi) = data.usable_window_pct();
    assert!((lo - 10.1).abs() < 1e-12 && (hi - 89.9).abs() < 1e-12, "{lo}–{hi}");
    assert!((data.declared_start_pct() - 50.0).abs() < 1e-12);
    let wide = BatteryData { soc_window_pct: (0.0, 100.0), ..battery(1000.0) };
    let (lo, hi) = wide.usable_window_pct();
    assert!((lo - 7.25).abs() < 1e-12 && (hi - 92.75).abs() < 1e-12, "kept within 5–95 first: {lo}–{hi}");
    let error = parts(1000.0, 9.0).build().unwrap_err().to_string();
    assert!(error.contains("soc_start_pct") && error.contains("10.1–89.9"), "{error}");
}

/// Where the battery's current limit binds, full pedal draws exactly the battery's most power.
#[test]
fn full_pedal_draws_at_most_what_the_battery_gives() {
    let m = model(300.0);
    let b = *m.truck().battery();
    let v = 20.0; // 4584 rpm: the machines could give 2 × 333 Nm ≈ 320 kW electric
    let full = Control { pedal: 1.0, brake: 0.0, gear: 1 };
    let flows = m.power_flows(v, full);
    let terminal_w = flows.battery_w - flows.battery_loss_w;
    assert!((terminal_w - b.max_discharge_w()).abs() < 1e-3 * b.max_discharge_w(), "{terminal_w} W");
    let unlimited = model(2000.0);
    assert!(unlimited.power_flows(v, full).battery_w > 1.2 * flows.battery_w);
}

/// Braking above 10 km/h returns energy and leaves the friction brakes what the machines cannot
/// take; below 10 km/h nothing is recovered (VECTO's lowest recuperation speed).
#[test]
fn braking_recovers_above_ten_km_per_h_and_the_friction_brakes_take_the_rest() {
    let m = model(2000.0);
    let soft = Control { pedal: 0.0, brake: 0.02, gear: 1 }; // 1.2 kNm asked at the wheels
    let (drag, _, regen) = m.wheel_torques_nm(20.0);
    assert!(drag - regen > 1200.0, "the machines take all of it");
    assert_eq!(m.friction_brake_force_n(20.0, soft), 0.0);
    assert!(m.energy_rate(20.0, soft) < 0.0);
    let hard = Control { brake: 0.5, ..soft };
    let friction_n = m.friction_brake_force_n(20.0, hard);
    assert!((friction_n - (30_000.0 - (drag - regen)) / 0.5).abs() < 1e-6, "{friction_n}");
    let slow = 2.0;
    assert_eq!(m.friction_brake_force_n(slow, soft), 1200.0 / 0.5);
    let aux_only = m.energy_rate(slow, Control { brake: 0.0, ..soft });
    assert_eq!(m.energy_rate(slow, soft), aux_only);
    assert!(aux_only > body().aux_power_w, "the auxiliaries' draw and its loss");
    let running = m.power_flows(20.0, Control { pedal: 0.1, brake: 0.0, gear: 1 });
    let off = m.power_flows(20.0, Control { pedal: 0.0, brake: 0.0, gear: 1 });
    assert_eq!(
        (running.aux_w, off.aux_w),
        (body().aux_power_w + 600.0, body().aux_power_w),
        "conditioning while they run"
    );
}

/// A hilly drive under pedal, coasting and braking: the energy drawn from the battery equals the
/// air drag, rolling resistance, the machines', reduction's and battery's losses, the
/// auxiliaries, the friction brakes and the change of kinetic and potential energy.
#[test]
fn the_energy_drawn_balances_the_loads_losses_and_stored_energy() {
    let m = Arc::new(model(2000.0));
    let road = Arc::new(Road::new(vec![0.0, 1500.0, 3000.0, 4500.0, 20_000.0], vec![0.02, -0.03, 0.0, 0.01]).unwrap());
    let mut plant = Plant::new(m.clone(), road.clone(), 0.0, 22.0);
    let body = *m.truck().body();
    let r = m.truck().wheel_radius_m();
    let (mut sum, dt) = ([0.0_f64; 6], 0.01);
    let controls = [(0.8, 0.0, 60.0), (0.0, 0.0, 20.0), (0.0, 0.15, 15.0), (0.3, 0.0, 40.0), (0.0, 0.5, 6.0)];
    for (pedal, brake, seconds) in controls {
        let u = Control { pedal, brake, gear: 1 };
        for _ in 0..(seconds / dt) as usize {
            let x0 = plant.state();
            plant.step(u, dt);
            let x1 = plant.state();
            // Trapezoid over the step of each loss, air drag and rolling resistance [J].
            for (x, w) in [(x0, 0.5 * dt), (x1, 0.5 * dt)] {
                let f = m.power_flows(x.v_mps, u);
                let alpha = road.slope_at(x.s_m + 1e-6, &mut 0).atan();
                let air = m.air_torque_nm(x.v_mps) / r * x.v_mps;
                let rolling =
                    body.mass_kg * crate::powertrain::G_MPS2 * alpha.cos() * body.rolling_resistance * x.v_mps;
                let losses = [f.machine_loss_w, f.reduction_loss_w, f.battery_loss_w, f.aux_w, air, rolling];
                for (s, p) in sum.iter_mut().zip(losses) {
                    *s += w * p;
                }
            }
        }
    }
    let x = plant.state();
    assert!(!x.stalled && x.s_m > 3000.0, "{x:?}");
    let m_eff = 1.0 / (m.c1() * r);
    let kinetic = 0.5 * m_eff * (x.v_mps.powi(2) - 22.0_f64.powi(2));
    let height = |s: f64| {
        let (d, g) = (road.distance_m(), road.slopes());
        (0..g.len()).map(|i| (s.min(d[i + 1]) - d[i]).max(0.0) * g[i].atan().sin()).sum::<f64>()
    };
    let potential = body.mass_kg * crate::powertrain::G_MPS2 * height(x.s_m);
    let balance = sum.iter().sum::<f64>() + x.brake_energy_j + kinetic + potential;
    let drawn = x.fuel_g;
    assert!(
        (balance - drawn).abs() < 1e-3 * sum[..4].iter().sum::<f64>(),
        "drawn {drawn} J, balance {balance} J, {sum:?}"
    );
    assert!(x.brake_energy_j > 0.0 && sum[0] > 0.0 && sum[2] > 0.0);
}

/// A run started just above the window's floor ends where the usable charge ends.
#[test]
fn a_battery_near_its_floor_ends_the_drive_where_the_usable_charge_ends() {
    let m = Arc::new(ElectricModel::new(parts(2000.0, 10.2).build().unwrap(), 60_000.0));
    let road = Arc::new(Road::new(vec![0.0, 100_000.0], vec![0.01]).unwrap());
    let mut plant = Plant::new(m.clone(), road, 0.0, 22.0);
    for _ in 0..20_000 {
        plant.step(Control { pedal: 0.7, brake: 0.0, gear: 1 }, 0.05);
    }
    let x = plant.state();
    assert!(x.stalled && x.s_m < 100_000.0, "{x:?}");
    let soc = plant.state_of_charge().unwrap();
    assert!(soc <= 0.101 && soc > 0.1005, "stopped at {soc}");
    let usable_j = m.truck().battery().energy_per_soc_j() * (0.102 - 0.101);
    assert!((x.fuel_g - usable_j).abs() < 0.01 * usable_j, "drew {} J of {usable_j} J", x.fuel_g);
}

/// At the glide pedal the machines draw no electric power: each gives t with t + (5 + 0.04|t| +
/// 0.001 n) = 0 (the loss torque cancels the torque), t = -(5 + 0.001 n) / 0.96, between its drag
/// and zero. The truck then loses less speed than with them switched off, and the battery gives
/// the auxiliaries and the conditioning only.
#[test]
fn at_the_glide_pedal_the_machines_draw_no_electric_power() {
    let m = model(2000.0);
    let v = 22.0;
    let n = m.rpm_per_mps() * v;
    let pedal = m.glide_pedal(v, 1).expect("the machines recover at 79 km/h");
    let expected_nm = -(COUNT as f64) * (5.0 + 0.001 * n) / 0.96;
    let torque_nm = |pedal: f64| m.machine_torque_nm(v, Control { pedal, brake: 0.0, gear: 1 });
    let got_nm = torque_nm(pedal);
    assert!((got_nm - expected_nm).abs() < 1e-3 * expected_nm.abs(), "{got_nm} vs {expected_nm} Nm");
    let drag_nm = torque_nm(0.0);
    assert!(drag_nm < got_nm && got_nm < 0.0, "{drag_nm} < {got_nm} < 0");
    let accel = |p: f64| m.accel_on(v, p, 0.0, 1, 0.0);
    assert!(accel(pedal) > accel(0.0), "the glide loses less speed than coasting");
    let flows = m.power_flows(v, Control { pedal, brake: 0.0, gear: 1 });
    let electric_w = flows.battery_w - flows.battery_loss_w - flows.aux_w;
    assert!(electric_w.abs() < 1e-3 * flows.aux_w, "{flows:?}");
    assert!(m.glides() && m.glide_pedal(2.0, 1).is_none(), "no glide below 10 km/h");
}

/// Machines rated 300 Nm each continuously and 500 Nm for 30 s, both at 1500 rpm.
fn rated(overload_s: f64) -> ElectricParts {
    let mut parts = parts(2000.0, 50.0);
    let rating = OverloadRating {
        continuous_torque_nm: 300.0,
        continuous_speed_rpm: 1500.0,
        overload_torque_nm: 500.0,
        overload_speed_rpm: 1500.0,
        overload_duration_s: overload_s,
    };
    parts.machine.levels[0].rating = Some(rating);
    parts
}

/// VECTO's overload data: the continuous loss is the machines' loss at the continuous torque and
/// speed, the buffer the loss at the overload point above it times the overload time.
#[test]
fn the_thermal_buffer_is_the_overload_points_extra_loss_over_its_time() {
    let thermal = rated(30.0).build().unwrap().thermal().unwrap();
    let omega = 1500.0 / RPM_PER_RAD_S;
    let continuous_w = 2.0 * omega * loss_torque(1500.0, 300.0, 1.0);
    let peak_w = 2.0 * omega * loss_torque(1500.0, 500.0, 1.0);
    assert!((thermal.continuous_loss_w - continuous_w).abs() < 1e-9 * continuous_w);
    assert!((thermal.buffer_j - 30.0 * (peak_w - continuous_w)).abs() < 1e-6);
    assert_eq!(thermal.continuous_nm, 600.0);
    assert!(parts(2000.0, 50.0).build().unwrap().thermal().is_none(), "unrated machines never derate");
}

/// The machines derate once the content exceeds the buffer and recover at 90 % of it; the
/// content never falls below zero.
#[test]
fn the_machines_derate_above_the_buffer_and_recover_at_nine_tenths_of_it() {
    let limits = Thermal { buffer_j: 100.0, continuous_loss_w: 10.0, continuous_nm: 600.0 };
    let mut state = ThermalState::new(limits);
    state.commit(0.0, 5.0, true);
    assert_eq!(state.content_j, 0.0);
    state.commit(110.0, 1.0, true); // +100 J: at the buffer, not above it
    assert!(!state.derated && state.content_j == 100.0);
    state.commit(11.0, 1.0, true);
    assert!(state.derated && state.derated_s == 0.0);
    state.commit(0.0, 1.0, true); // 91 J: still above 90 %
    assert!(state.derated && state.derated_s == 1.0);
    state.commit(0.0, 1.0, false); // 81 J: recovered; this second did not bind
    assert!(!state.derated && state.derated_s == 1.0);
}

/// Climbing 8 % at full pedal from 18 km/h (about 1 000 rpm, where the machines give 1 600 Nm
/// against a continuous 600 Nm), rated machines fill their buffer and drive at their derated
/// limits, which lose less than the continuous loss, until the buffer has cooled: they climb
/// slower than unrated machines. A buffer the climb never fills changes nothing, bit for bit.
#[test]
fn a_long_climb_at_full_pedal_derates_the_machines() {
    let road = Arc::new(Road::new(vec![0.0, 5_000.0], vec![0.08]).unwrap());
    let climb = |parts: ElectricParts| {
        let mut plant =
            Plant::new(Arc::new(ElectricModel::new(parts.build().unwrap(), 60_000.0)), road.clone(), 0.0, 5.0);
        for _ in 0..1_200 {
            plant.step(Control { pedal: 1.0, brake: 0.0, gear: 1 }, 0.05);
        }
        (plant.state(), plant.thermal())
    };
    let (free, none) = climb(parts(2000.0, 50.0));
    let (hot, thermal) = climb(rated(30.0));
    let (cool, never) = climb(rated(1.0e9));
    assert!(none.is_none() && cool == free && never.unwrap().derated_s == 0.0);
    let thermal = thermal.unwrap();
    assert!(thermal.derated_s > 5.0, "{thermal:?}");
    assert!(hot.s_m < free.s_m - 10.0, "derated {} m, free {} m", hot.s_m, free.s_m);
    let derated = rated(30.0).build().unwrap().derated().unwrap();
    let m = ElectricModel::new(derated, 60_000.0);
    let slope_nm = m.slope_torque_nm(0.08);
    let expected = m.accel_on(hot.v_mps, 1.0, 0.0, 1, slope_nm);
    let full = ElectricModel::new(rated(30.0).build().unwrap(), 60_000.0).accel_on(hot.v_mps, 1.0, 0.0, 1, slope_nm);
    assert!(expected < full, "derated {expected} vs rated {full} m/s²");
}

//! A new kind of truck plugs into the plant through the `Powertrain` trait alone: a battery truck
//! whose motor pushes with a constant force and whose brakes recover up to a fixed force, on a flat
//! road without air drag or rolling resistance, where speed, distance and energy have closed forms.

use std::sync::Arc;

use truckmpc_core::powertrain::{AffineAccel, Control, EnergyStore, Powertrain, RateForm, NEUTRAL};
use truckmpc_core::{Plant, Road};

/// A truck of `mass_kg` whose pedal P gives the force P·`drive_n` [N] at the wheels (drawing
/// exactly that power from its battery), whose brake B asks for B·`brake_n` [N], of which up to
/// `recover_n` goes back into the battery and the rest to the friction brakes.
#[derive(Debug, Clone)]
struct ConstantForceTruck {
    mass_kg: f64,
    drive_n: f64,
    brake_n: f64,
    recover_n: f64,
    battery: EnergyStore,
}

impl ConstantForceTruck {
    fn recovered_n(&self, brake: f64) -> f64 {
        (brake * self.brake_n).min(self.recover_n)
    }
}

impl Powertrain for ConstantForceTruck {
    fn forward_gears(&self) -> usize {
        1
    }
    fn engine_speed_rpm(&self, v_mps: f64, _gear: usize) -> f64 {
        100.0 * v_mps
    }
    fn stall_speed_mps(&self) -> f64 {
        0.5
    }
    fn traction_interruption_s(&self) -> f64 {
        0.0
    }
    fn interrupted_energy_rate(&self, _v_mps: f64) -> f64 {
        0.0
    }
    /// A wheel radius of 1 m: the torque is the force.
    fn slope_torque_nm(&self, grade: f64) -> f64 {
        self.mass_kg * 9.81 * grade
    }
    fn pedal_affine(&self, _v_mps: f64, _gear: usize, slope_torque_nm: f64) -> AffineAccel {
        AffineAccel { accel_at_zero: -slope_torque_nm / self.mass_kg, gain: self.drive_n / self.mass_kg }
    }
    fn brake_affine(&self, _v_mps: f64, _gear: usize, slope_torque_nm: f64) -> AffineAccel {
        AffineAccel { accel_at_zero: -slope_torque_nm / self.mass_kg, gain: -self.brake_n / self.mass_kg }
    }
    fn accel_on(&self, _v_mps: f64, pedal: f64, brake: f64, gear: usize, slope_torque_nm: f64) -> f64 {
        let drive = if gear == NEUTRAL { 0.0 } else { pedal.max(0.0) * self.drive_n };
        (drive - brake * self.brake_n - slope_torque_nm) / self.mass_kg
    }
    fn accel_derivative_per_s(&self, _v_mps: f64, _pedal: f64, _gear: usize) -> f64 {
        0.0
    }
    /// The motor's power less what the brakes recover [W].
    fn energy_rate(&self, v_mps: f64, u: Control) -> f64 {
        let drive = if u.gear == NEUTRAL { 0.0 } else { u.pedal.max(0.0) * self.drive_n };
        (drive - self.recovered_n(u.brake)) * v_mps
    }
    fn friction_brake_force_n(&self, _v_mps: f64, u: Control) -> f64 {
        u.brake * self.brake_n - self.recovered_n(u.brake)
    }
    fn rate_form(&self) -> RateForm {
        RateForm::ProportionalToPedal
    }
    fn zero_pedal_is_cut(&self) -> bool {
        true
    }
    fn store(&self) -> EnergyStore {
        self.battery
    }
}

const CAPACITY_J: f64 = 1.0e9;

fn truck(capacity_j: f64) -> Arc<ConstantForceTruck> {
    let battery = EnergyStore::Battery { capacity_j, soc_start: 0.9, soc_min: 0.1 };
    Arc::new(ConstantForceTruck {
        mass_kg: 20_000.0,
        drive_n: 10_000.0,
        brake_n: 40_000.0,
        recover_n: 15_000.0,
        battery,
    })
}

fn flat() -> Arc<Road> {
    Arc::new(Road::new(vec![0.0, 100_000.0], vec![0.0]).unwrap())
}

fn drive(plant: &mut Plant<ConstantForceTruck>, u: Control, seconds: f64) {
    let dt_s = 0.05;
    for _ in 0..(seconds / dt_s).round() as usize {
        plant.step(u, dt_s);
    }
}

/// Full pedal: v = v0 + (F/m)·t and s = v0·t + ½(F/m)·t², and the battery gives the work F·s.
#[test]
fn constant_force_gives_the_closed_form_speed_distance_and_energy() {
    let (v0, t) = (10.0, 20.0);
    let mut plant = Plant::new(truck(CAPACITY_J), flat(), 0.0, v0);
    drive(&mut plant, Control { pedal: 1.0, brake: 0.0, gear: 1 }, t);
    let a = 10_000.0 / 20_000.0;
    let x = plant.state();
    let s = v0 * t + 0.5 * a * t * t;
    assert!((x.t_s - t).abs() < 1e-9 && (x.v_mps - (v0 + a * t)).abs() < 1e-9, "{x:?}");
    assert!((x.s_m - s).abs() < 1e-6, "{} vs {s}", x.s_m);
    assert!((x.fuel_g - 10_000.0 * s).abs() < 1e-6 * 10_000.0 * s, "drew {} J", x.fuel_g);
    let soc = plant.state_of_charge().unwrap();
    assert!((soc - (0.9 - 10_000.0 * s / CAPACITY_J)).abs() < 1e-12, "{soc}");
    assert_eq!(x.brake_energy_j, 0.0);
}

/// Braking harder than the motor can take: the battery gets back what it recovers, the friction
/// brakes dissipate the rest, and the two add up to the kinetic energy lost.
#[test]
fn braking_splits_between_recuperation_and_the_friction_brakes() {
    let (v0, brake) = (25.0, 0.5); // asks 20 kN, of which 15 kN is recovered
    let mut plant = Plant::new(truck(CAPACITY_J), flat(), 0.0, v0);
    drive(&mut plant, Control { pedal: 0.0, brake, gear: 1 }, 10.0);
    let x = plant.state();
    assert!((x.v_mps - (v0 - 1.0 * 10.0)).abs() < 1e-9, "{x:?}");
    let recovered_j = 15_000.0 * x.s_m;
    assert!((x.fuel_g + recovered_j).abs() < 1e-6 * recovered_j, "drew {} J", x.fuel_g);
    assert!((x.brake_energy_j - 5_000.0 * x.s_m).abs() < 1e-6 * x.brake_energy_j);
    let kinetic_j = 0.5 * 20_000.0 * (v0 * v0 - x.v_mps * x.v_mps);
    assert!((kinetic_j - recovered_j - x.brake_energy_j).abs() < 1e-6 * kinetic_j);
    assert!(plant.state_of_charge().unwrap() > 0.9);
}

/// A battery that holds less than the trip ends it where its usable charge ends: the truck stops
/// moving within one step of the distance whose work empties it.
#[test]
fn an_empty_battery_stops_the_truck_where_its_usable_charge_ends() {
    let capacity_j = 5.0e7; // 0.8 · 5e7 J = 4e7 J usable: 4 km at 10 kN
    let mut plant = Plant::new(truck(capacity_j), flat(), 0.0, 20.0);
    drive(&mut plant, Control { pedal: 1.0, brake: 0.0, gear: 1 }, 400.0);
    let x = plant.state();
    assert!(x.stalled);
    let usable_m = 0.8 * capacity_j / 10_000.0;
    assert!(x.s_m >= usable_m && x.s_m < usable_m + x.v_mps * 0.05 + 1e-6, "stopped at {} m", x.s_m);
    assert!(plant.state_of_charge().unwrap() <= 0.1);
}

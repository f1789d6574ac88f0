//! A stage that shifts between two forward gears, for a truck whose gearbox interrupts traction
//! ([`Powertrain::shift_interruption_s`]): the DP models it as the plant drives it. The truck
//! first rolls in neutral for the interruption (no pedal, at the powertrain's interrupted energy
//! rate; without the brake, which the plant would keep applied: a stage that shifts and brakes is
//! rare), covering a distance d and reaching a speed v'; then it drives the new gear with the
//! stage's input over the rest of the stage, h − d, from v'. The stage's energy and time are the
//! two parts' sums.
//!
//! The DP prices the second part with its ordinary stage model over h − d, and adds the first
//! part's energy and the time the shift costs against an ordinary stage's (the DP charges an
//! ordinary stage's time by its source speed alone: [`extra_cost`]).

use super::params::{DpSettings, StageModel};
use super::stage;
use crate::plant::Control;
use crate::powertrain::Powertrain;
use crate::vehicle::{Vehicle, NEUTRAL};

/// RK4 steps over the interruption (a second's roll in neutral; the error is far below the grid's).
const STEPS: usize = 16;

/// The roll in neutral that starts a shifting stage.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Interruption {
    /// Speed at its end [m/s].
    pub v_mps: f64,
    /// Distance covered [m].
    pub d_m: f64,
    /// Its duration [s].
    pub t_s: f64,
    /// Energy drawn meanwhile, in the store's unit (the engine at fuel cut: none).
    pub energy: f64,
}

/// The interruption of a shift at `v_mps` on a slope of wheel torque `slope_torque_nm` [Nm], on a
/// stage of `h_m`: None where the truck does not interrupt traction, where it would stop, or where
/// the roll would outlast the stage (a stage shorter than the roll: the plan then shifts there as
/// in an ordinary stage).
pub fn interruption(vehicle: &Vehicle, v_mps: f64, slope_torque_nm: f64, h_m: f64) -> Option<Interruption> {
    let t_s = vehicle.traction_interruption_s();
    if !(t_s > 0.0 && v_mps > 0.0) {
        return None;
    }
    let dt = t_s / STEPS as f64;
    let accel = |v: f64| vehicle.accel_on(v, 0.0, 0.0, NEUTRAL, slope_torque_nm);
    let rate = |v: f64| vehicle.interrupted_energy_rate(v);
    let (mut v, mut d, mut energy) = (v_mps, 0.0, 0.0);
    for _ in 0..STEPS {
        let k1 = accel(v);
        let k2 = accel(v + 0.5 * dt * k1);
        let k3 = accel(v + 0.5 * dt * k2);
        let k4 = accel(v + dt * k3);
        // Distance: ∫v dt with v's own RK4 stages; energy likewise at the stage speeds.
        let (v2, v3, v4) = (v + 0.5 * dt * k1, v + 0.5 * dt * k2, v + dt * k3);
        d += dt / 6.0 * (v + 2.0 * v2 + 2.0 * v3 + v4);
        energy += dt / 6.0 * (rate(v) + 2.0 * rate(v2) + 2.0 * rate(v3) + rate(v4));
        v += dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
        if !(v > 0.0) {
            return None;
        }
    }
    (d < h_m).then_some(Interruption { v_mps: v, d_m: d, t_s, energy })
}

/// Whether the plan of `p` models the interruption of `vehicle`'s shifts (`plan_interruption`, and
/// a gearbox that interrupts traction).
#[inline]
pub fn planned(p: &DpSettings, vehicle: &Vehicle) -> bool {
    p.mpc.plan_interruption && vehicle.traction_interruption_s() > 0.0
}

/// Whether the plan of `p` drives a change from `from` to `to` with an interruption on `vehicle`.
#[inline]
pub fn interrupts(p: &DpSettings, vehicle: &Vehicle, from: usize, to: usize) -> bool {
    p.mpc.plan_interruption && vehicle.shift_interruption_s(from, to) > 0.0
}

/// The settings for the part of a shifting stage after its interruption: those of `p` over the
/// `h_m − d` left.
pub fn after(p: &DpSettings, roll: &Interruption) -> DpSettings {
    let mut rest = p.clone();
    rest.mpc.stage_m = p.mpc.stage_m - roll.d_m;
    rest
}

/// What a shifting stage from `v_i` to `v_j` [m/s] costs on top of its drive after the roll
/// (priced over h − d by the ordinary stage model): the roll's energy, its speed change (Q3), and
/// the time the stage takes beyond an ordinary stage between the same speeds, at the fuel_time
/// cost's price per second.
#[inline]
pub fn extra_cost(p: &DpSettings, roll: &Interruption, (v_i, v_j): (f64, f64)) -> f64 {
    let h = p.mpc.stage_m;
    let model = p.mpc.stage_model;
    let shifting = roll.t_s + stage::time_s(model, (roll.v_mps, v_j), h - roll.d_m);
    let ordinary = stage::time_s(model, (v_i, v_j), h);
    let change = p.mpc.q_speed_change * (v_i - roll.v_mps).abs();
    p.mpc.q_fuel * roll.energy + change + p.q_time_per_s * (shifting - ordinary)
}

/// A stage of `h_m` from `v_mps` under `u` on a slope of wheel torque `slope_torque_nm`, shifting
/// from `from_gear`: (end speed [m/s], energy in the store's unit, time [s]) as the DP's stage
/// model gives them, the interruption first where the change has one (an ordinary stage where the
/// roll would outlast it, a short last stage). The end speed is 0 where the truck stops.
pub fn drive_stage(
    (vehicle, model): (&Vehicle, StageModel),
    (v_mps, h_m): (f64, f64),
    from_gear: usize,
    u: Control,
    slope_torque_nm: f64,
) -> (f64, f64, f64) {
    let shifts = vehicle.shift_interruption_s(from_gear, u.gear) > 0.0;
    let roll = shifts.then(|| interruption(vehicle, v_mps, slope_torque_nm, h_m));
    let (v0, h, energy0, time0) = match roll.flatten() {
        Some(r) => (r.v_mps, h_m - r.d_m, r.energy, r.t_s),
        None => (v_mps, h_m, 0.0, 0.0),
    };
    let v_end = stage::end_speed_with(model, vehicle, (v0, h), (u.pedal, u.brake, u.gear), slope_torque_nm);
    if !(v_end > 0.0) {
        return (0.0, 0.0, 0.0);
    }
    let energy = energy0 + stage::energy_of(model, vehicle, (v0, v_end), u, h);
    (v_end, energy, time0 + stage::time_s(model, (v0, v_end), h))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::powertrain::tests::truck;
    use crate::powertrain::MapModel;
    use crate::vehicle::VehicleParams;
    use std::sync::Arc;

    fn vehicle(interruption_s: f64) -> Vehicle {
        Vehicle::from_map(Arc::new(MapModel::new(truck(), 1.0e5, interruption_s)), &VehicleParams::default()).unwrap()
    }

    #[test]
    fn the_roll_is_the_neutral_coast_of_the_interruption() {
        let v = vehicle(1.0);
        let torque = v.slope_torque_nm(0.02);
        let roll = interruption(&v, 22.0, torque, 50.0).unwrap();
        // A fine explicit integration of the same coast, as the plant rolls it.
        let (mut speed, mut d) = (22.0, 0.0);
        let dt = 1e-5;
        for _ in 0..100_000 {
            d += speed * dt;
            speed += v.accel_on(speed, 0.0, 0.0, NEUTRAL, torque) * dt;
        }
        assert!((roll.v_mps - speed).abs() < 1e-5 && (roll.d_m - d).abs() < 1e-4, "{roll:?} vs {speed} {d}");
        assert_eq!((roll.t_s, roll.energy), (1.0, 0.0));
        // A roll longer than the stage, or a truck without interruption: no shifting stage.
        assert!(interruption(&v, 22.0, torque, 20.0).is_none());
        assert!(interruption(&vehicle(0.0), 22.0, torque, 50.0).is_none());
    }

    #[test]
    fn a_shifting_stage_rolls_then_drives_the_new_gear_over_the_rest() {
        let v = vehicle(1.0);
        let (torque, u) = (v.slope_torque_nm(0.01), Control { pedal: 0.6, brake: 0.0, gear: 3 });
        let model = StageModel::Trapezoid;
        let (end, fuel, time) = drive_stage((&v, model), (20.0, 50.0), 2, u, torque);
        let roll = interruption(&v, 20.0, torque, 50.0).unwrap();
        let rest = 50.0 - roll.d_m;
        let expected = stage::end_speed_with(model, &v, (roll.v_mps, rest), (0.6, 0.0, 3), torque);
        assert_eq!(end, expected);
        assert_eq!(fuel, stage::fuel_g(model, &v, (roll.v_mps, expected), 0.6, 3, rest));
        assert_eq!(time, 1.0 + stage::time_s(model, (roll.v_mps, expected), rest));
        // Staying in gear, or leaving neutral, is an ordinary stage.
        let plain = stage::end_speed_with(model, &v, (20.0, 50.0), (0.6, 0.0, 3), torque);
        assert_eq!(drive_stage((&v, model), (20.0, 50.0), 3, u, torque).0, plain);
        assert_eq!(drive_stage((&v, model), (20.0, 50.0), NEUTRAL, u, torque).0, plain);
    }
}

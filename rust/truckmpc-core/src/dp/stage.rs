//! The DP's model of one stage of length h [m] with constant inputs: where it ends, the input that
//! joins two speeds, and its fuel and time.
//!
//! Along the road, kinetic energy per unit mass E = ½v² [m²/s²] changes as dE/ds = a(v, u), the
//! acceleration of (B.1). With the gear and slope fixed, a is affine in one input u (the pedal
//! for P > 0, or the brake at fuel cut): a(v, u) = a0(v) + gain(v)·u ([`AffineAccel`]).
//!
//! - **Euler** (the thesis's (5.4)): v_j = v_i + (h/v_i)·a(v_i, u), fuel (h/v_i)·ṁ_f(v_i, u),
//!   time h/v_i. First order in h: along a path its ½v² grows by h·a + ½(v_j − v_i)² a stage, so
//!   a path that speeds up and slows down in turn gains kinetic energy the plant does not give.
//! - **Trapezoid**: E_j − E_i = (h/2)·(a(v_i, u) + a(v_j, u)), fuel (h/2)·(ṁ_f(v_i, u)/v_i +
//!   ṁ_f(v_j, u)/v_j), time (h/2)·(1/v_i + 1/v_j). Second order in h, and energy is conserved:
//!   a closed speed cycle gains nothing. The input joining two speeds stays a closed form,
//!   u = ((v_j² − v_i²)/h − a0(v_i) − a0(v_j)) / (gain(v_i) + gain(v_j)); the end speed of a
//!   given input is implicit and found by fixed-point iteration (each iteration shrinks the error
//!   by about (h/2)·|∂a/∂v|/v², under 1 % at any stage length the settings allow for a truck).

pub use crate::params::StageModel;

use crate::levels::{brake_accel_on, pedal_accel_on, AffineAccel};
use crate::powertrain::{Control, Powertrain};
use crate::vehicle::{Vehicle, NEUTRAL};

/// Fixed-point iterations of the trapezoid's implicit end speed, after an Euler first guess.
const ITERATIONS: usize = 4;

/// Which affine branch of (B.1) an input drives: the pedal (P > 0, brake off) in a forward gear,
/// or the brake at fuel cut (engine drag in a forward gear, none in neutral).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Branch {
    Pedal,
    Brake,
}

/// The affine acceleration of `branch` at `v_mps` in `gear` on a slope of wheel torque
/// `slope_torque_nm` [Nm].
#[inline]
pub fn accel_map(vehicle: &Vehicle, v_mps: f64, gear: usize, slope_torque_nm: f64, branch: Branch) -> AffineAccel {
    match branch {
        Branch::Pedal => pedal_accel_on(vehicle, v_mps, gear, slope_torque_nm),
        Branch::Brake => brake_accel_on(vehicle, v_mps, gear, slope_torque_nm),
    }
}

/// Speed [m/s] at the end of a stage of `h_m` from `v_mps` with input `u` of `branch` held; 0 when
/// the truck would stop within the stage (a speed no grid holds).
pub fn end_speed(
    model: StageModel,
    vehicle: &Vehicle,
    (v_mps, h_m): (f64, f64),
    gear: usize,
    slope_torque_nm: f64,
    (branch, u): (Branch, f64),
) -> f64 {
    end_speed_within(model, vehicle, (v_mps, h_m), gear, slope_torque_nm, (branch, u), 0.0)
}

/// [`end_speed`], with the trapezoid's iteration stopped once a step moves the speed by less than
/// `tol_mps` [m/s] (the error left is then about a hundredth of that); `tol_mps` 0 iterates fully.
pub fn end_speed_within(
    model: StageModel,
    vehicle: &Vehicle,
    (v_mps, h_m): (f64, f64),
    gear: usize,
    slope_torque_nm: f64,
    (branch, u): (Branch, f64),
    tol_mps: f64,
) -> f64 {
    let at_start = accel_map(vehicle, v_mps, gear, slope_torque_nm, branch);
    let euler = at_start.step(v_mps, h_m, u);
    match model {
        StageModel::Euler => euler,
        StageModel::Trapezoid => {
            let a_i = at_start.accel_at_zero + at_start.gain * u;
            let e_i = 0.5 * v_mps * v_mps;
            let mut v_j = euler.max(0.5 * v_mps);
            for _ in 0..ITERATIONS {
                let at_end = accel_map(vehicle, v_j, gear, slope_torque_nm, branch);
                let e_j = e_i + 0.5 * h_m * (a_i + at_end.accel_at_zero + at_end.gain * u);
                if e_j <= 0.0 {
                    return 0.0;
                }
                let next = (2.0 * e_j).sqrt();
                let step = (next - v_j).abs();
                v_j = next;
                if step < tol_mps {
                    break;
                }
            }
            v_j
        }
    }
}

/// Speed [m/s] at the end of a stage of `h_m` from `v_mps` with the plant's inputs held: the pedal
/// branch when the pedal is above zero, otherwise the brake branch (fuel cut in a gear).
pub fn end_speed_with(
    model: StageModel,
    vehicle: &Vehicle,
    (v_mps, h_m): (f64, f64),
    (pedal, brake, gear): (f64, f64, usize),
    slope_torque_nm: f64,
) -> f64 {
    let input = if pedal > 0.0 && gear != NEUTRAL { (Branch::Pedal, pedal) } else { (Branch::Brake, brake) };
    end_speed(model, vehicle, (v_mps, h_m), gear, slope_torque_nm, input)
}

/// The input of the branch whose maps at the stage's ends are `at_i` (at `v_i`) and `at_j` (at
/// `v_j`) that joins `v_i` to `v_j` [m/s] over `h_m`, unclipped (Euler reads only `at_i`).
#[inline]
pub fn input_for(model: StageModel, at_i: &AffineAccel, at_j: &AffineAccel, (v_i, v_j): (f64, f64), h_m: f64) -> f64 {
    match model {
        StageModel::Euler => at_i.input_for(v_i, v_j, h_m),
        StageModel::Trapezoid => {
            ((v_j * v_j - v_i * v_i) / h_m - at_i.accel_at_zero - at_j.accel_at_zero) / (at_i.gain + at_j.gain)
        }
    }
}

/// Fuel [g] of a stage from `v_i` to `v_j` [m/s] over `h_m` at `pedal` in `gear` (idle fuelling in
/// neutral, none at fuel cut).
#[inline]
pub fn fuel_g(model: StageModel, vehicle: &Vehicle, (v_i, v_j): (f64, f64), pedal: f64, gear: usize, h_m: f64) -> f64 {
    match model {
        StageModel::Euler => h_m / v_i * vehicle.fuel_rate_gps(v_i, pedal, gear),
        StageModel::Trapezoid => {
            half_stage_fuel_g(vehicle, v_i, pedal, gear, h_m) + half_stage_fuel_g(vehicle, v_j, pedal, gear, h_m)
        }
    }
}

/// The trapezoid's share of a stage's fuel [g] at one end, at speed `v_mps`: (h/2)·ṁ_f/v, half
/// the stage length at that end's fuel per metre. Fuel is linear in the pedal at a fixed engine
/// speed (B.2), so at `pedal` 1 this is the fuel per unit of pedal.
#[inline]
pub fn half_stage_fuel_g(vehicle: &Vehicle, v_mps: f64, pedal: f64, gear: usize, h_m: f64) -> f64 {
    0.5 * h_m * vehicle.fuel_rate_gps(v_mps, pedal, gear) / v_mps
}

/// Energy of a braking stage from `v_i` to `v_j` [m/s] over `h_m` at `brake` in `gear`, in the
/// store's unit (negative where braking returns more than the truck draws meanwhile); zero for a
/// truck whose braking draws nothing ([`Powertrain::brake_draws_energy`]), as at a diesel's fuel
/// cut, so its brake arcs keep their cost.
#[inline]
pub fn brake_energy(
    model: StageModel,
    vehicle: &Vehicle,
    (v_i, v_j): (f64, f64),
    brake: f64,
    gear: usize,
    h_m: f64,
) -> f64 {
    if !vehicle.brake_draws_energy() {
        return 0.0;
    }
    let per_m = |v: f64| vehicle.energy_rate(v, Control { pedal: 0.0, brake, gear }) / v;
    match model {
        StageModel::Euler => h_m * per_m(v_i),
        StageModel::Trapezoid => 0.5 * h_m * (per_m(v_i) + per_m(v_j)),
    }
}

/// Energy of a stage from `v_i` to `v_j` [m/s] over `h_m` under control `u`, in the store's unit:
/// [`brake_energy`] where the brake is on and braking draws energy, else [`fuel_g`] at the pedal.
#[inline]
pub fn energy_of(model: StageModel, vehicle: &Vehicle, v: (f64, f64), u: Control, h_m: f64) -> f64 {
    if u.brake > 0.0 && vehicle.brake_draws_energy() {
        brake_energy(model, vehicle, v, u.brake, u.gear, h_m)
    } else {
        fuel_g(model, vehicle, v, u.pedal, u.gear, h_m)
    }
}

/// Time [s] of a stage from `v_i` to `v_j` [m/s] over `h_m`.
#[inline]
pub fn time_s(model: StageModel, (v_i, v_j): (f64, f64), h_m: f64) -> f64 {
    match model {
        StageModel::Euler => h_m / v_i,
        StageModel::Trapezoid => 0.5 * h_m * (1.0 / v_i + 1.0 / v_j),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::VehicleParams;

    /// The plant's own integration over a stage (fine RK4 in distance on dE/ds = a), the reference
    /// both models approximate.
    fn exact_end(vehicle: &Vehicle, v0: f64, h: f64, gear: usize, torque: f64, (branch, u): (Branch, f64)) -> f64 {
        let accel = |v: f64| {
            let m = accel_map(vehicle, v, gear, torque, branch);
            m.accel_at_zero + m.gain * u
        };
        let steps = 2000;
        let ds = h / steps as f64;
        let mut e = 0.5 * v0 * v0;
        let de = |e: f64| accel((2.0 * e).sqrt());
        for _ in 0..steps {
            let k1 = de(e);
            let k2 = de(e + 0.5 * ds * k1);
            let k3 = de(e + 0.5 * ds * k2);
            let k4 = de(e + ds * k3);
            e += ds / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
        }
        (2.0 * e).sqrt()
    }

    /// The trapezoid's end speed is second order in h (halving h divides the error by about 8 per
    /// stage), Euler's first order (about 4), and the trapezoid is the closer one at S = 25 m.
    #[test]
    fn the_trapezoid_is_second_order_and_euler_first() {
        let vehicle = Vehicle::new(VehicleParams::default()).unwrap();
        for (gear, slope, branch, u) in
            [(12, 0.0, Branch::Pedal, 1.0), (10, 0.03, Branch::Pedal, 0.8), (12, -0.03, Branch::Brake, 0.0)]
        {
            let torque = vehicle.slope_torque_nm(slope);
            let v0 = 22.0;
            let err = |model, h| {
                (end_speed(model, &vehicle, (v0, h), gear, torque, (branch, u))
                    - exact_end(&vehicle, v0, h, gear, torque, (branch, u)))
                .abs()
            };
            let (t50, t25) = (err(StageModel::Trapezoid, 100.0), err(StageModel::Trapezoid, 50.0));
            let (e50, e25) = (err(StageModel::Euler, 100.0), err(StageModel::Euler, 50.0));
            assert!(t50 / t25 > 6.0, "trapezoid order: {t50:e} / {t25:e}");
            assert!(e50 / e25 > 3.0 && e50 / e25 < 5.0, "euler order: {e50:e} / {e25:e}");
            let (t, e) = (err(StageModel::Trapezoid, 25.0), err(StageModel::Euler, 25.0));
            assert!(t < 0.1 * e, "at 25 m: trapezoid {t:e}, euler {e:e}");
        }
    }

    /// The closed-form input lands the implicit step on the wanted end speed, in both branches.
    #[test]
    fn the_input_for_two_speeds_drives_the_step_between_them() {
        let vehicle = Vehicle::new(VehicleParams::default()).unwrap();
        for model in [StageModel::Euler, StageModel::Trapezoid] {
            let cases = [
                (Branch::Pedal, 0.0, 23.0, 23.1),
                (Branch::Pedal, 0.01, 24.0, 23.8),
                (Branch::Brake, -0.04, 25.0, 25.0),
            ];
            for (branch, slope, v_i, v_j) in cases {
                let torque = vehicle.slope_torque_nm(slope);
                let gear = 12;
                let at_i = accel_map(&vehicle, v_i, gear, torque, branch);
                let at_j = accel_map(&vehicle, v_j, gear, torque, branch);
                let u = input_for(model, &at_i, &at_j, (v_i, v_j), 25.0);
                assert!((0.0..=1.0).contains(&u), "{model:?} {branch:?}: {u}");
                let end = end_speed(model, &vehicle, (v_i, 25.0), gear, torque, (branch, u));
                assert!((end - v_j).abs() < 1e-10, "{model:?} {branch:?}: {end} vs {v_j}");
            }
        }
    }

    /// Holding a speed in gear costs the same fuel per metre in both models, and a closed cycle
    /// (up from v to w, down from w to v at fuel cut) gains no kinetic energy in the trapezoid: the
    /// pedal fuel of going up equals what holding the average force would cost, to rounding.
    #[test]
    fn fuel_and_time_follow_the_rule_of_their_model() {
        let vehicle = Vehicle::new(VehicleParams::default()).unwrap();
        let (v_i, v_j, h) = (23.0, 24.0, 25.0);
        assert_eq!(time_s(StageModel::Euler, (v_i, v_j), h), h / v_i);
        assert!((time_s(StageModel::Trapezoid, (v_i, v_j), h) - 0.5 * h * (1.0 / v_i + 1.0 / v_j)).abs() < 1e-15);
        let per_m = |v: f64| vehicle.fuel_rate_gps(v, 1.0, 12) / v;
        let trapezoid = fuel_g(StageModel::Trapezoid, &vehicle, (v_i, v_j), 1.0, 12, h);
        assert!((trapezoid - 0.5 * h * (per_m(v_i) + per_m(v_j))).abs() < 1e-12);
        assert_eq!(
            fuel_g(StageModel::Euler, &vehicle, (v_i, v_j), 0.5, 12, h),
            h / v_i * vehicle.fuel_rate_gps(v_i, 0.5, 12)
        );
        // Neutral: idle fuel over the stage's time.
        let idle = fuel_g(StageModel::Trapezoid, &vehicle, (v_i, v_j), 0.0, NEUTRAL, h);
        assert!(
            (idle - vehicle.fuel_rate_gps(v_i, 0.0, NEUTRAL) * time_s(StageModel::Trapezoid, (v_i, v_j), h)).abs()
                < 1e-12
        );
    }
}

//! Pedal and brake levels of appendix B.2 and the stationary points of B.3.
//!
//! One Euler stage of length h [m] (5.4 with M = 1) maps v0 to v1 = v0 + (h/v0)·a(v0, u).
//! With the gear and slope fixed, a(v0, u) is affine in the pedal (for P > 0) and in the brake
//! (at fuel cut), so the level joining two speeds is a closed form: (B.5) and (B.7).

pub use crate::powertrain::AffineAccel;
use crate::powertrain::Powertrain;
use crate::vehicle::{Vehicle, NEUTRAL};

/// Acceleration as an affine function of the pedal P > 0 (brake off) in a forward gear (for the
/// thesis's truck the fuelled branch of (2.8)). `gain` is zero where no fuel can be injected.
#[inline]
pub fn pedal_accel(vehicle: &Vehicle, v0_mps: f64, gear: usize, slope: f64) -> AffineAccel {
    pedal_accel_on(vehicle, v0_mps, gear, vehicle.slope_torque_nm(slope))
}

/// [`pedal_accel`] with the slope given as its wheel torque [Nm], precomputed by callers that
/// evaluate many speeds on one slope.
#[inline]
pub fn pedal_accel_on(vehicle: &Vehicle, v0_mps: f64, gear: usize, slope_torque_nm: f64) -> AffineAccel {
    debug_assert!(gear != NEUTRAL);
    vehicle.pedal_affine(v0_mps, gear, slope_torque_nm)
}

/// Acceleration as an affine function of the brake B at fuel cut (drag torque) in a gear, or
/// coasting in neutral.
#[inline]
pub fn brake_accel(vehicle: &Vehicle, v0_mps: f64, gear: usize, slope: f64) -> AffineAccel {
    brake_accel_on(vehicle, v0_mps, gear, vehicle.slope_torque_nm(slope))
}

/// [`brake_accel`] with the slope given as its wheel torque [Nm].
#[inline]
pub fn brake_accel_on(vehicle: &Vehicle, v0_mps: f64, gear: usize, slope_torque_nm: f64) -> AffineAccel {
    vehicle.brake_affine(v0_mps, gear, slope_torque_nm)
}

/// Pedal level (B.5) that joins v0 to v1 in one Euler stage of length h in a forward gear,
/// unclipped. NaN where the engine can inject no fuel at that speed.
pub fn pedal_for_step(vehicle: &Vehicle, v0_mps: f64, v1_mps: f64, gear: usize, slope: f64, h_m: f64) -> f64 {
    let map = pedal_accel(vehicle, v0_mps, gear, slope);
    if map.gain <= 0.0 {
        return f64::NAN;
    }
    map.input_for(v0_mps, v1_mps, h_m)
}

/// Brake level (B.7) that joins v0 to v1 in one Euler stage of length h at fuel cut, unclipped.
pub fn brake_for_step(vehicle: &Vehicle, v0_mps: f64, v1_mps: f64, gear: usize, slope: f64, h_m: f64) -> f64 {
    brake_accel(vehicle, v0_mps, gear, slope).input_for(v0_mps, v1_mps, h_m)
}

/// One explicit Euler stage (5.4) of length h [m] with constant inputs; returns the end speed [m/s].
pub fn euler_step(vehicle: &Vehicle, v0_mps: f64, pedal: f64, brake: f64, gear: usize, slope: f64, h_m: f64) -> f64 {
    v0_mps + h_m / v0_mps * vehicle.accel_mps2(v0_mps, pedal, brake, gear, slope)
}

/// Fuel [g] of one Euler stage (5.5) of length h [m]: (h/v0)·ṁ_f(v0, P, gear).
#[inline]
pub fn stage_fuel_g(vehicle: &Vehicle, v0_mps: f64, pedal: f64, gear: usize, h_m: f64) -> f64 {
    h_m / v0_mps * vehicle.fuel_rate_gps(v0_mps, pedal, gear)
}

/// A stationary point of (B.1): the levels that hold a speed on a slope in a gear.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stationary {
    /// Pedal level [0, 1]; at the bound when infeasible.
    pub pedal: f64,
    /// Brake level [0, 1]; at the bound when infeasible.
    pub brake: f64,
    /// Whether levels within [0, 1] hold the speed exactly.
    pub feasible: bool,
    /// ∂(dv/ds)/∂v at the point [1/m] (v in m/s), the eigenvalue λ of tables B.1/B.2.
    pub eigenvalue_per_m: f64,
}

/// Levels that hold `v_mps` on `slope` in `gear` (table B.1/B.2): the pedal when the engine must
/// push, otherwise the brake at fuel cut; in neutral only the brake.
pub fn stationary(vehicle: &Vehicle, v_mps: f64, slope: f64, gear: usize) -> Stationary {
    // A tiny negative brake level is the rounding of a printed slope, not a real infeasibility.
    const TOLERANCE: f64 = 1e-6;
    let (pedal, brake, feasible) = if gear == NEUTRAL {
        let b = brake_accel(vehicle, v_mps, gear, slope);
        let brake = -b.accel_at_zero / b.gain;
        (0.0, brake.clamp(0.0, 1.0), (-TOLERANCE..=1.0).contains(&brake))
    } else {
        let p = pedal_accel(vehicle, v_mps, gear, slope);
        let pedal = if p.gain > 0.0 { -p.accel_at_zero / p.gain } else { f64::INFINITY };
        if pedal > 0.0 {
            (pedal.min(1.0), 0.0, pedal <= 1.0)
        } else {
            let b = brake_accel(vehicle, v_mps, gear, slope);
            let brake = -b.accel_at_zero / b.gain;
            (0.0, brake.clamp(0.0, 1.0), (-TOLERANCE..=1.0).contains(&brake))
        }
    };
    // At a stationary point a = 0, so ∂(a/v)/∂v = (∂a/∂v)/v.
    let eigenvalue_per_m = vehicle.accel_derivative_per_s(v_mps, pedal, gear) / v_mps;
    Stationary { pedal, brake, feasible, eigenvalue_per_m }
}

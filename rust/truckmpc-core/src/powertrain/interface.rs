//! What the plant, the DP's stage models and the controllers need of a truck, whatever drives it:
//! the [`Powertrain`] trait, with the control it is driven by ([`Control`]), the affine form of its
//! acceleration in one input ([`AffineAccel`]) and the store it draws its energy from
//! ([`EnergyStore`]).
//!
//! Conventions: speeds in m/s, torques at the wheel in Nm, the slope as its wheel torque (from
//! [`Powertrain::slope_torque_nm`]), pedal and brake levels in [0, 1], gear 0 is neutral (coasting:
//! nothing drives the wheels) and forward gears are 1..=n. The energy rate is in the store's unit per
//! second (fuel [g/s] for a fuel tank, power [W] for a battery) and may be negative where the
//! powertrain takes energy back while braking.

use crate::powertrain::thermal::Thermal;

/// Gear number of neutral. Forward gears are numbered 1..=n.
pub const NEUTRAL: usize = 0;

/// Constant inputs over one integration step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Control {
    /// Pedal level P ∈ [0, 1].
    pub pedal: f64,
    /// Brake level B ∈ [0, 1].
    pub brake: f64,
    /// Gear number, 0 = neutral.
    pub gear: usize,
}

/// Acceleration as an affine function of one input at a fixed speed, gear and slope:
/// a(u) = accel_at_zero + gain·u [m/s²].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AffineAccel {
    /// Acceleration with the input at zero [m/s²].
    pub accel_at_zero: f64,
    /// Change of acceleration per unit of input [m/s²].
    pub gain: f64,
}

impl AffineAccel {
    /// Speed after one Euler stage of length `h_m` from `v0_mps` with input `u` [m/s].
    #[inline]
    pub fn step(&self, v0_mps: f64, h_m: f64, u: f64) -> f64 {
        v0_mps + h_m / v0_mps * (self.accel_at_zero + self.gain * u)
    }

    /// The input that makes one Euler stage of length `h_m` end at `v1_mps` (unclipped).
    #[inline]
    pub fn input_for(&self, v0_mps: f64, v1_mps: f64, h_m: f64) -> f64 {
        (v0_mps * (v1_mps - v0_mps) / h_m - self.accel_at_zero) / self.gain
    }
}

/// How the energy rate depends on the pedal at a fixed speed and gear, which decides the forms the
/// DP may use for it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RateForm {
    /// Proportional to the pedal (zero at P ≤ 0) and smooth in speed: a stage's energy at any
    /// pedal is the pedal times its energy at full pedal, and speed derivatives may be local.
    ProportionalToPedal,
    /// Read from a map, piecewise linear: evaluated at each pedal, and differenced over speeds a
    /// cruise moves through.
    Map,
}

/// The store a powertrain draws its energy from. Its state is a function of what has been drawn
/// since the start (the energy rate's integral, in the rate's unit).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum EnergyStore {
    /// A fuel tank that never runs dry; the rate is fuel [g/s].
    FuelTank,
    /// A battery holding `capacity_j` [J] when full, charged to the fraction `soc_start` at the
    /// start and empty (for driving) at `soc_min`; the rate is its power [W], negative when charging.
    Battery { capacity_j: f64, soc_start: f64, soc_min: f64 },
}

impl EnergyStore {
    /// State of charge [0–1] after `drawn` (in the rate's unit) since the start; None for a tank.
    pub fn state_of_charge(&self, drawn: f64) -> Option<f64> {
        match *self {
            EnergyStore::FuelTank => None,
            EnergyStore::Battery { capacity_j, soc_start, .. } => Some(soc_start - drawn / capacity_j),
        }
    }

    /// Whether the store can give no more after `drawn` since the start.
    #[inline]
    pub fn is_empty(&self, drawn: f64) -> bool {
        match *self {
            EnergyStore::FuelTank => false,
            EnergyStore::Battery { soc_min, .. } => self.state_of_charge(drawn).is_some_and(|soc| soc <= soc_min),
        }
    }
}

/// A truck as the plant integrates it and the DP and the controllers plan with it.
///
/// The acceleration is affine in the pedal at a fixed speed, gear and slope (brake off), and
/// affine in the brake with the pedal at zero: [`Powertrain::pedal_affine`] and
/// [`Powertrain::brake_affine`] give those forms, which are also the tractive and braking limits
/// (pedal and brake 0 and 1), and [`Powertrain::accel_on`] evaluates any control.
pub trait Powertrain {
    /// Number of forward gears (1..=n; 0 is neutral).
    fn forward_gears(&self) -> usize;

    /// Engine (or motor) speed [rpm] at `v_mps` in `gear`; its idle speed in neutral.
    fn engine_speed_rpm(&self, v_mps: f64, gear: usize) -> f64;

    /// Lowest speed [m/s] the lowest gear drives; a truck slower than this has stalled.
    fn stall_speed_mps(&self) -> f64;

    /// How long a shift from one forward gear to another interrupts traction [s] (0: instant).
    fn traction_interruption_s(&self) -> f64;

    /// How long a change from `from_gear` to `to_gear` interrupts traction [s]: the interruption
    /// for a change between two different forward gears, none to or from neutral.
    #[inline]
    fn shift_interruption_s(&self, from_gear: usize, to_gear: usize) -> f64 {
        let shifts = from_gear != to_gear && from_gear != NEUTRAL && to_gear != NEUTRAL;
        if shifts {
            self.traction_interruption_s()
        } else {
            0.0
        }
    }

    /// Energy rate while a shift interrupts traction and the truck rolls in neutral, at `v_mps`.
    fn interrupted_energy_rate(&self, v_mps: f64) -> f64;

    /// Gravity and rolling resistance as a torque at the wheel [Nm] on `grade` (Δh/ΔL).
    fn slope_torque_nm(&self, grade: f64) -> f64;

    /// Acceleration as an affine function of the pedal (brake off) at `v_mps` in forward `gear`.
    fn pedal_affine(&self, v_mps: f64, gear: usize, slope_torque_nm: f64) -> AffineAccel;

    /// Acceleration as an affine function of the brake with the pedal at zero at `v_mps` in
    /// `gear` (in neutral: coasting).
    fn brake_affine(&self, v_mps: f64, gear: usize, slope_torque_nm: f64) -> AffineAccel;

    /// Acceleration [m/s²] at `v_mps` with pedal, brake and gear.
    fn accel_on(&self, v_mps: f64, pedal: f64, brake: f64, gear: usize, slope_torque_nm: f64) -> f64;

    /// ∂(dv/dt)/∂v [1/s] at `v_mps`, `pedal`, brake off, `gear`, on a flat road.
    fn accel_derivative_per_s(&self, v_mps: f64, pedal: f64, gear: usize) -> f64;

    /// Energy rate of control `u` at `v_mps` [the store's unit per s]; negative where braking
    /// returns energy to the store.
    fn energy_rate(&self, v_mps: f64, u: Control) -> f64;

    /// The share of control `u`'s brake force the friction brakes carry at `v_mps` [N]: all of it
    /// for a powertrain that takes none back, what it cannot take for one that does.
    fn friction_brake_force_n(&self, v_mps: f64, u: Control) -> f64;

    /// How the energy rate depends on the pedal.
    fn rate_form(&self) -> RateForm;

    /// Whether zero pedal gives the acceleration of the brake branch at zero brake (true unless the
    /// model jumps between its pedal and fuel-cut branches at P = 0).
    fn zero_pedal_is_cut(&self) -> bool;

    /// The pedal at which the drive glides at `v_mps` in forward `gear` for less than at zero pedal
    /// (a battery-electric truck's machines drawing no electric power, against their drag while
    /// switched off); None where zero pedal is the glide.
    fn glide_pedal(&self, _v_mps: f64, _gear: usize) -> Option<f64> {
        None
    }

    /// Whether the drive has a glide pedal ([`Powertrain::glide_pedal`]) at some speeds.
    fn glides(&self) -> bool {
        false
    }

    /// The energy per unit of ½v² [m²/s²] the powertrain adds in forward `gear`, where that price
    /// is the same at every speed and load (a closed form); None where it must be found numerically.
    fn kinetic_energy_price(&self, _gear: usize) -> Option<f64> {
        None
    }

    /// Whether the brake changes the energy rate (a truck that recovers braking energy); false:
    /// braking draws what zero pedal draws, and the DP's brake arcs charge nothing for it.
    fn brake_draws_energy(&self) -> bool {
        false
    }

    /// The store the energy rate draws on.
    fn store(&self) -> EnergyStore;

    /// The thermal limits of a drive that derates when it overheats (a battery-electric truck's
    /// machines, [`crate::powertrain::thermal`]); None: it never does.
    fn thermal(&self) -> Option<Thermal> {
        None
    }

    /// For the plant, the energy rate of control `u` at `v_mps` and where power is lost:
    /// [energy rate ([`Powertrain::energy_rate`]), power heating a drive that derates (its
    /// machines' loss while they carry current) [W], loss in the machines (their drag while off
    /// included) [W], loss in the battery [W]]; the losses are zero for a powertrain without them.
    fn rates_with_losses(&self, v_mps: f64, u: Control) -> [f64; 4] {
        [self.energy_rate(v_mps, u), 0.0, 0.0, 0.0]
    }

    /// The machines' torque [Nm] under `u` at `v_mps` (a battery-electric truck's; NaN for
    /// other powertrains).
    fn machine_torque_nm(&self, _v_mps: f64, _u: Control) -> f64 {
        f64::NAN
    }

    /// This powertrain derated to its continuous rating; None where it never derates.
    fn derated(&self) -> Option<Self>
    where
        Self: Sized,
    {
        None
    }
}

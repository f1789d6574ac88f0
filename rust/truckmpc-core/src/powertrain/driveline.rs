//! From the engine to the road: gear and axle ratios with their efficiencies, and the tyre's
//! dynamic radius.

use super::RPM_PER_RAD_S;
use crate::{CoreError, CoreResult};

/// Gearbox, axle and wheels. Gears are numbered 1..=n. The losses, as torque at the gearbox's input,
/// are affine in the torque passed on: a drag torque (churning, bearings) plus a share of the
/// torque (tooth friction), the form VECTO's loss maps take at a given speed.
#[derive(Debug, Clone, PartialEq)]
pub struct Driveline {
    gear_ratios: Vec<f64>,
    axle_ratio: f64,
    gear_efficiency: f64,
    axle_efficiency: f64,
    loss_torque_nm: f64,
    wheel_radius_m: f64,
}

impl Driveline {
    /// A driveline from its gear ratios (first gear first, decreasing), axle ratio, the
    /// efficiencies of gearbox and axle (0, 1], the drag torque [Nm] (≥ 0, at the gearbox input)
    /// and the tyres' dynamic radius [m].
    pub fn new(
        (gear_ratios, axle_ratio): (&[f64], f64),
        (gear_efficiency, axle_efficiency, loss_torque_nm): (f64, f64, f64),
        wheel_radius_m: f64,
    ) -> CoreResult<Self> {
        if gear_ratios.is_empty() {
            return Err(CoreError::invalid("gear_ratios", "at least one gear"));
        }
        for (i, &r) in gear_ratios.iter().enumerate() {
            if !(r.is_finite() && r > 0.0) {
                return Err(CoreError::invalid("gear_ratios", format!("a ratio > 0 for gear {}", i + 1)).got(r));
            }
            if i > 0 && r >= gear_ratios[i - 1] {
                return Err(CoreError::invalid("gear_ratios", format!("gear {} below gear {}", i + 1, i))
                    .got(format!("{r} after {}", gear_ratios[i - 1])));
            }
        }
        for (key, value, lo) in [("axle_ratio", axle_ratio, 0.0), ("wheel_radius_m", wheel_radius_m, 0.0)] {
            if !(value.is_finite() && value > lo) {
                return Err(CoreError::invalid(key, "a number > 0").got(value));
            }
        }
        for (key, value) in [("gear_efficiency", gear_efficiency), ("axle_efficiency", axle_efficiency)] {
            if !(value.is_finite() && value > 0.0 && value <= 1.0) {
                return Err(CoreError::invalid(key, "a number in (0, 1]").got(value));
            }
        }
        if !(loss_torque_nm.is_finite() && loss_torque_nm >= 0.0) {
            return Err(CoreError::invalid("loss_torque_nm", "a number >= 0").got(loss_torque_nm));
        }
        let gear_ratios = gear_ratios.to_vec();
        Ok(Driveline { gear_ratios, axle_ratio, gear_efficiency, axle_efficiency, loss_torque_nm, wheel_radius_m })
    }

    /// Number of forward gears.
    pub fn gears(&self) -> usize {
        self.gear_ratios.len()
    }

    /// The gear ratios, first gear first.
    pub fn gear_ratios(&self) -> &[f64] {
        &self.gear_ratios
    }

    /// The axle ratio.
    pub fn axle_ratio(&self) -> f64 {
        self.axle_ratio
    }

    /// The tyres' dynamic radius [m].
    pub fn wheel_radius_m(&self) -> f64 {
        self.wheel_radius_m
    }

    /// The driveline's efficiency, gearbox times axle.
    pub fn efficiency(&self) -> f64 {
        self.gear_efficiency * self.axle_efficiency
    }

    /// Total ratio, engine speed over wheel speed, in `gear` (1..=n).
    ///
    /// # Panics
    /// If `gear` is not a forward gear of this driveline.
    pub fn ratio(&self, gear: usize) -> f64 {
        self.gear_ratios[gear - 1] * self.axle_ratio
    }

    /// Engine speed [rpm] at road speed `v_mps` in `gear`.
    pub fn engine_speed_rpm(&self, v_mps: f64, gear: usize) -> f64 {
        v_mps / self.wheel_radius_m * self.ratio(gear) * RPM_PER_RAD_S
    }

    /// Drag torque of the driveline [Nm] at the gearbox input, lost whatever the load.
    pub fn loss_torque_nm(&self) -> f64 {
        self.loss_torque_nm
    }

    /// Wheel torque [Nm] that `engine_torque_nm` gives in `gear`: the inverse of
    /// [`Driveline::engine_torque_nm`].
    pub fn wheel_torque_nm(&self, engine_torque_nm: f64, gear: usize) -> f64 {
        let passed = engine_torque_nm - self.loss_torque_nm;
        let ideal = if passed >= 0.0 { passed * self.efficiency() } else { passed / self.efficiency() };
        ideal * self.ratio(gear)
    }

    /// Engine torque [Nm] that gives `wheel_torque_nm` at the wheels in `gear`: the share lost is
    /// taken from the engine's side when it drives, from the wheels' side when they drive, and the
    /// drag torque always.
    pub fn engine_torque_nm(&self, wheel_torque_nm: f64, gear: usize) -> f64 {
        let ideal = wheel_torque_nm / self.ratio(gear);
        let passed = if ideal >= 0.0 { ideal / self.efficiency() } else { ideal * self.efficiency() };
        passed + self.loss_torque_nm
    }
}

//! From the engine to the road: gear and axle ratios with their losses, and the tyre's dynamic
//! radius.
//!
//! Each stage (the gearbox in a gear, then the axle) loses torque at its input. Where VECTO's loss
//! map of the stage is given it says how much ([`LossMap`]); otherwise the loss is affine in the
//! torque passed on: a drag torque (churning, bearings; the gearbox's only) plus a share of the
//! torque (tooth friction), taken from the engine's side when it drives and from the wheels' side
//! when they drive.

use super::loss_map::LossPoints;
use super::{LossMap, RPM_PER_RAD_S};
use crate::{CoreError, CoreResult};

/// Gearbox, axle and wheels. Gears are numbered 1..=n.
#[derive(Debug, Clone)]
pub struct Driveline {
    gear_ratios: Vec<f64>,
    axle_ratio: f64,
    gear_efficiency: f64,
    axle_efficiency: f64,
    loss_torque_nm: f64,
    wheel_radius_m: f64,
    /// VECTO's loss map of each gear (all or none), replacing the gear efficiency and drag torque.
    gear_maps: Option<Vec<LossMap>>,
    /// VECTO's loss map of the axle, replacing the axle efficiency.
    axle_map: Option<LossMap>,
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
        Ok(Driveline {
            gear_ratios,
            axle_ratio,
            gear_efficiency,
            axle_efficiency,
            loss_torque_nm,
            wheel_radius_m,
            gear_maps: None,
            axle_map: None,
        })
    }

    /// The same driveline with VECTO's loss maps: one per gear (first gear first; or none), and
    /// the axle's (or none). Each map's points are (input speed [rpm], input torque [Nm], torque
    /// loss [Nm]).
    pub fn with_loss_maps(
        mut self,
        gears: Option<&[LossPoints]>,
        axle: Option<&[(f64, f64, f64)]>,
    ) -> CoreResult<Self> {
        if let Some(maps) = gears {
            if maps.len() != self.gears() {
                let expected = format!("one loss map per gear ({})", self.gears());
                return Err(CoreError::invalid("gear_loss_maps", expected).got(maps.len()));
            }
            let built: CoreResult<Vec<LossMap>> =
                maps.iter().enumerate().map(|(i, m)| LossMap::new(&format!("gear_loss_maps[{}]", i + 1), m)).collect();
            self.gear_maps = Some(built?);
        }
        if let Some(points) = axle {
            self.axle_map = Some(LossMap::new("axle_loss_map", points)?);
        }
        Ok(self)
    }

    /// Whether VECTO's loss maps give the gearbox's and the axle's losses: (gears, axle).
    pub fn has_loss_maps(&self) -> (bool, bool) {
        (self.gear_maps.is_some(), self.axle_map.is_some())
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

    /// The driveline's efficiency without loss maps, gearbox times axle.
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

    /// Drag torque of the gearbox [Nm] at its input without loss maps, lost whatever the load.
    pub fn loss_torque_nm(&self) -> f64 {
        self.loss_torque_nm
    }

    /// Wheel torque [Nm] that `engine_torque_nm` at the gearbox input gives in `gear` at engine
    /// speed `n_rpm`: the inverse of [`Driveline::engine_torque_nm`].
    pub fn wheel_torque_nm(&self, engine_torque_nm: f64, gear: usize, n_rpm: f64) -> f64 {
        let gearbox_out = match &self.gear_maps {
            Some(maps) => maps[gear - 1].passed_nm(n_rpm, engine_torque_nm),
            None => passed(engine_torque_nm - self.loss_torque_nm, self.gear_efficiency),
        } * self.gear_ratios[gear - 1];
        let axle_out = match &self.axle_map {
            Some(map) => map.passed_nm(n_rpm / self.gear_ratios[gear - 1], gearbox_out),
            None => passed(gearbox_out, self.axle_efficiency),
        };
        axle_out * self.axle_ratio
    }

    /// Engine torque [Nm] at the gearbox input that gives `wheel_torque_nm` at the wheels in
    /// `gear` at engine speed `n_rpm`.
    pub fn engine_torque_nm(&self, wheel_torque_nm: f64, gear: usize, n_rpm: f64) -> f64 {
        let axle_passed = wheel_torque_nm / self.axle_ratio;
        let axle_in = match &self.axle_map {
            Some(map) => map.input_nm(n_rpm / self.gear_ratios[gear - 1], axle_passed),
            None => input(axle_passed, self.axle_efficiency),
        };
        let gear_passed = axle_in / self.gear_ratios[gear - 1];
        match &self.gear_maps {
            Some(maps) => maps[gear - 1].input_nm(n_rpm, gear_passed),
            None => input(gear_passed, self.gear_efficiency) + self.loss_torque_nm,
        }
    }
}

/// Torque passed on by a stage of efficiency `eta` from `torque_nm` at its input: the share lost
/// is taken from the input when it drives (positive), from the output when it is driven.
#[inline]
fn passed(torque_nm: f64, eta: f64) -> f64 {
    if torque_nm >= 0.0 {
        torque_nm * eta
    } else {
        torque_nm / eta
    }
}

/// Input torque of a stage of efficiency `eta` that passes `torque_nm` on: the inverse of [`passed`].
#[inline]
fn input(torque_nm: f64, eta: f64) -> f64 {
    if torque_nm >= 0.0 {
        torque_nm / eta
    } else {
        torque_nm * eta
    }
}

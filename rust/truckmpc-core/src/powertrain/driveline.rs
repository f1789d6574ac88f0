//! From the engine to the road: gear and axle ratios with their losses, and the tyre's dynamic
//! radius.
//!
//! Each stage (the gearbox in a gear, then the axle) loses torque at its input. Where VECTO's loss
//! map of the stage is given it says how much ([`LossMap`]); otherwise the loss is affine in the
//! torque passed on: a drag torque (churning, bearings; the gearbox's only) plus a share of the
//! torque (tooth friction), taken from the engine's side when it drives and from the wheels' side
//! when they drive. A retarder, where there is one, drags on the gearbox's input or output shaft
//! ([`Retarder`]).

use super::loss_map::LossPoints;
use super::retarder::{Retarder, RetarderPosition};
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
    /// The retarder's drag, where there is one.
    retarder: Option<Retarder>,
}

/// The powers [W] a driveline loses in a gear, each stage's torque loss times its input speed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StageLosses {
    /// The gearbox's.
    pub gearbox_w: f64,
    /// The retarder's drag (0 without one).
    pub retarder_w: f64,
    /// The axle's.
    pub axle_w: f64,
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
            retarder: None,
        })
    }

    /// The same driveline with a retarder dragging on its shaft.
    pub fn with_retarder(mut self, retarder: Retarder) -> Self {
        self.retarder = Some(retarder);
        self
    }

    /// The retarder, if there is one.
    pub fn retarder(&self) -> Option<&Retarder> {
        self.retarder.as_ref()
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

    /// The retarder's drag [Nm] on its shaft where it sits at `position`, the shaft turning at
    /// `shaft_rpm` (0 without a retarder there).
    #[inline]
    fn retarder_nm(&self, position: RetarderPosition, shaft_rpm: f64) -> f64 {
        match &self.retarder {
            Some(r) if r.position() == position => r.loss_nm(shaft_rpm),
            _ => 0.0,
        }
    }

    /// Wheel torque [Nm] that `engine_torque_nm` at the gearbox input gives in `gear` at engine
    /// speed `n_rpm`: the inverse of [`Driveline::engine_torque_nm`].
    pub fn wheel_torque_nm(&self, engine_torque_nm: f64, gear: usize, n_rpm: f64) -> f64 {
        let ratio = self.gear_ratios[gear - 1];
        let gearbox_in = match self.retarder {
            None => engine_torque_nm,
            Some(_) => engine_torque_nm - self.retarder_nm(RetarderPosition::GearboxInput, n_rpm),
        };
        let gearbox_out = self.gearbox_passed_nm(gearbox_in, gear, n_rpm) * ratio;
        let axle_in = match self.retarder {
            None => gearbox_out,
            Some(_) => gearbox_out - self.retarder_nm(RetarderPosition::GearboxOutput, n_rpm / ratio),
        };
        self.axle_passed_nm(axle_in, n_rpm / ratio) * self.axle_ratio
    }

    /// Engine torque [Nm] at the gearbox input that gives `wheel_torque_nm` at the wheels in
    /// `gear` at engine speed `n_rpm`.
    pub fn engine_torque_nm(&self, wheel_torque_nm: f64, gear: usize, n_rpm: f64) -> f64 {
        let ratio = self.gear_ratios[gear - 1];
        let axle_passed = wheel_torque_nm / self.axle_ratio;
        let axle_in = match &self.axle_map {
            Some(map) => map.input_nm(n_rpm / ratio, axle_passed),
            None => input(axle_passed, self.axle_efficiency),
        };
        let gearbox_out = match self.retarder {
            None => axle_in,
            Some(_) => axle_in + self.retarder_nm(RetarderPosition::GearboxOutput, n_rpm / ratio),
        };
        let gear_passed = gearbox_out / ratio;
        let gearbox_in = match &self.gear_maps {
            Some(maps) => maps[gear - 1].input_nm(n_rpm, gear_passed),
            None => input(gear_passed, self.gear_efficiency) + self.loss_torque_nm,
        };
        match self.retarder {
            None => gearbox_in,
            Some(_) => gearbox_in + self.retarder_nm(RetarderPosition::GearboxInput, n_rpm),
        }
    }

    /// Wheel torque [Nm] in neutral at road speed `v_mps` (≤ 0: a drag): the gearbox's output
    /// shaft passes no torque, so the wheels turn the axle and a retarder on that shaft. Zero
    /// without an axle loss map or such a retarder.
    pub fn neutral_wheel_torque_nm(&self, v_mps: f64) -> f64 {
        let shaft_rpm = v_mps / self.wheel_radius_m * self.axle_ratio * RPM_PER_RAD_S;
        let axle_in = -self.retarder_nm(RetarderPosition::GearboxOutput, shaft_rpm);
        self.axle_passed_nm(axle_in, shaft_rpm) * self.axle_ratio
    }

    /// The powers [W] each stage loses in `gear` at engine speed `n_rpm` with `input_torque_nm`
    /// at the gearbox input (before an input retarder).
    pub fn stage_losses_w(&self, input_torque_nm: f64, gear: usize, n_rpm: f64) -> StageLosses {
        let ratio = self.gear_ratios[gear - 1];
        let (omega_in, omega_out) = (n_rpm / RPM_PER_RAD_S, n_rpm / ratio / RPM_PER_RAD_S);
        let input_drag = self.retarder_nm(RetarderPosition::GearboxInput, n_rpm);
        let gearbox_in = input_torque_nm - input_drag;
        let gearbox_out = self.gearbox_passed_nm(gearbox_in, gear, n_rpm) * ratio;
        let output_drag = self.retarder_nm(RetarderPosition::GearboxOutput, n_rpm / ratio);
        let axle_in = gearbox_out - output_drag;
        let axle_out = self.axle_passed_nm(axle_in, n_rpm / ratio) * self.axle_ratio;
        StageLosses {
            gearbox_w: gearbox_in * omega_in - gearbox_out * omega_out,
            retarder_w: input_drag * omega_in + output_drag * omega_out,
            axle_w: axle_in * omega_out - axle_out * omega_out / self.axle_ratio,
        }
    }

    /// Torque [Nm] the gearbox passes on (output torque / ratio) from `input_nm` in `gear` at `n_rpm`.
    #[inline]
    fn gearbox_passed_nm(&self, input_nm: f64, gear: usize, n_rpm: f64) -> f64 {
        match &self.gear_maps {
            Some(maps) => maps[gear - 1].passed_nm(n_rpm, input_nm),
            None => passed(input_nm - self.loss_torque_nm, self.gear_efficiency),
        }
    }

    /// Torque [Nm] the axle passes on (wheel torque / axle ratio) from `input_nm` at its input
    /// speed `n_in_rpm`.
    #[inline]
    fn axle_passed_nm(&self, input_nm: f64, n_in_rpm: f64) -> f64 {
        match &self.axle_map {
            Some(map) => map.passed_nm(n_in_rpm, input_nm),
            None => passed(input_nm, self.axle_efficiency),
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

//! A battery-electric truck's component data as a file reader gives it, and the truck built from
//! it: machines at the axle, the reduction between them and the wheels, the battery, the body.

use super::battery::{Battery, BatteryData};
use super::machine::{Machines, VoltageLevel};
use crate::powertrain::parts::Rows;
use crate::powertrain::thermal::{OverloadRating, Thermal};
use crate::powertrain::{Body, Curve, LossMap, MapTruck};
use crate::{CoreError, CoreResult};

/// One machine's data at one voltage.
#[derive(Debug, Clone, PartialEq)]
pub struct LevelData {
    /// The voltage it was measured at [V].
    pub voltage_v: f64,
    /// (speed [rpm], most driving torque [Nm], most braking torque [Nm] ≤ 0).
    pub torque_limits: Rows,
    /// (speed [rpm], torque [Nm], electric power [W]).
    pub power_map: Rows,
    /// Its continuous and overload rating; none: it never derates.
    pub rating: Option<OverloadRating>,
}

/// The machines' data: the file's one machine and how many there are.
#[derive(Debug, Clone, PartialEq)]
pub struct MachineData {
    /// How many alike machines drive the shaft.
    pub count: usize,
    /// One machine's rotor inertia [kg m²].
    pub inertia_kgm2: f64,
    /// One machine at each voltage, voltage rising.
    pub levels: Vec<LevelData>,
    /// (speed [rpm], one machine's drag torque [Nm] ≤ 0).
    pub drag_curve: Vec<(f64, f64)>,
}

/// The reduction between the machines and the wheels, and the tyres.
#[derive(Debug, Clone, PartialEq)]
pub struct ReductionData {
    /// Machine speed per wheel speed [-].
    pub ratio: f64,
    /// (input speed [rpm], input torque [Nm], torque loss [Nm]); none: lossless.
    pub loss_map: Option<Rows>,
    /// Dynamic tyre radius [m].
    pub wheel_radius_m: f64,
}

/// A battery-electric truck's parts, and the state of charge its run starts from.
#[derive(Debug, Clone, PartialEq)]
pub struct ElectricParts {
    /// The machines.
    pub machine: MachineData,
    /// The reduction and the tyres.
    pub reduction: ReductionData,
    /// The battery.
    pub battery: BatteryData,
    /// Mass, inertia, air and rolling resistance; `aux_power_w` is the auxiliaries' electric power.
    pub body: Body,
    /// Electric power of the machines' conditioning while they carry current [W].
    pub conditioning_w: f64,
    /// Cd·A over speed `(speed [m/s], Cd·A [m²])`, or none for the body's constant `cda_m2`.
    pub cda_curve: Option<Vec<(f64, f64)>>,
    /// State of charge at the start [%]; none: the middle of the usable window, as declaration
    /// mode starts a run.
    pub soc_start_pct: Option<f64>,
}

/// A battery-electric truck, its battery held at the start's state of charge.
#[derive(Debug, Clone)]
pub struct ElectricTruck {
    machines: Machines,
    ratio: f64,
    loss: Option<LossMap>,
    wheel_radius_m: f64,
    battery: Battery,
    body: Body,
    conditioning_w: f64,
    /// Cd·A [m²] over speed [m/s] (VECTO's cross-wind correction); none: the body's constant.
    cda_curve: Option<Curve>,
}

impl ElectricParts {
    /// The truck these parts make; the error names the first value its part refuses.
    pub fn build(&self) -> CoreResult<ElectricTruck> {
        let soc_pct = self.soc_start_pct.unwrap_or_else(|| self.battery.declared_start_pct());
        let battery = self.battery.at(soc_pct / 100.0)?;
        let m = &self.machine;
        let mut levels = Vec::with_capacity(m.levels.len());
        for (i, level) in m.levels.iter().enumerate() {
            let key = format!("machine.levels[{i}]");
            let read = VoltageLevel::new(&key, level.voltage_v, &level.torque_limits, &level.power_map)?;
            levels.push(match level.rating {
                Some(rating) => read.with_rating(&key, rating)?,
                None => read,
            });
        }
        let machines = Machines::new(m.count, m.inertia_kgm2, levels, &m.drag_curve, battery.ocv_v)?;
        let r = &self.reduction;
        if !(r.ratio.is_finite() && r.ratio > 0.0) {
            return Err(CoreError::invalid("reduction.ratio", "a ratio > 0").got(r.ratio));
        }
        if !(r.wheel_radius_m.is_finite() && r.wheel_radius_m > 0.0) {
            return Err(CoreError::invalid("reduction.wheel_radius_m", "a radius > 0 [m]").got(r.wheel_radius_m));
        }
        let loss = r.loss_map.as_deref().map(|points| LossMap::new("reduction.loss_map", points)).transpose()?;
        let cda_curve = checked_cda(&self.body, self.cda_curve.as_deref())?;
        let (ratio, wheel_radius_m, body) = (r.ratio, r.wheel_radius_m, self.body);
        let conditioning_w = self.conditioning_w;
        if !(conditioning_w.is_finite() && conditioning_w >= 0.0) {
            return Err(CoreError::invalid("conditioning_w", "a power >= 0 [W]").got(conditioning_w));
        }
        Ok(ElectricTruck { machines, ratio, loss, wheel_radius_m, battery, body, conditioning_w, cda_curve })
    }
}

/// The body checked as a map-based truck's (the same keys), and its drag-area curve.
fn checked_cda(body: &Body, curve: Option<&[(f64, f64)]>) -> CoreResult<Option<Curve>> {
    crate::powertrain::truck::check_body(body)?;
    match curve {
        Some(points) => {
            MapTruck::check_cda_points(points)?;
            Ok(Some(Curve::new("cda_curve", points)?))
        }
        None => Ok(None),
    }
}

impl ElectricTruck {
    /// The machines.
    pub fn machines(&self) -> &Machines {
        &self.machines
    }

    /// The battery at the start's state of charge.
    pub fn battery(&self) -> &Battery {
        &self.battery
    }

    /// The body.
    pub fn body(&self) -> &Body {
        &self.body
    }

    /// Electric power of the machines' conditioning while they carry current [W].
    pub fn conditioning_w(&self) -> f64 {
        self.conditioning_w
    }

    /// The reduction's ratio [-].
    pub fn ratio(&self) -> f64 {
        self.ratio
    }

    /// Dynamic tyre radius [m].
    pub fn wheel_radius_m(&self) -> f64 {
        self.wheel_radius_m
    }

    /// The drag area Cd·A [m²] at `v_mps`.
    pub fn cda_m2(&self, v_mps: f64) -> f64 {
        self.cda_curve.as_ref().map_or(self.body.cda_m2, |c| c.at(v_mps))
    }

    /// Machine speed [rpm] at `v_mps`.
    pub fn machine_rpm(&self, v_mps: f64) -> f64 {
        v_mps / self.wheel_radius_m * self.ratio * crate::powertrain::RPM_PER_RAD_S
    }

    /// Machine torque [Nm] that gives the wheels `wheel_nm` at machine speed `n_rpm`: through the
    /// reduction's loss map looked up from the wheels' side, as VECTO does.
    #[inline]
    pub fn machine_nm(&self, n_rpm: f64, wheel_nm: f64) -> f64 {
        let passed = wheel_nm / self.ratio;
        self.loss.as_ref().map_or(passed, |map| map.input_nm(n_rpm, passed))
    }

    /// Wheel torque [Nm] from machine torque `machine_nm` at `n_rpm`: the inverse of
    /// [`ElectricTruck::machine_nm`].
    #[inline]
    pub fn wheel_nm(&self, n_rpm: f64, machine_nm: f64) -> f64 {
        self.ratio * self.loss.as_ref().map_or(machine_nm, |map| map.passed_nm(n_rpm, machine_nm))
    }

    /// The machines' thermal limits (none: they never derate).
    pub fn thermal(&self) -> Option<Thermal> {
        self.machines.thermal()
    }

    /// The same truck with its machines derated to their continuous torque; none where they are
    /// not rated.
    pub fn derated(&self) -> Option<Self> {
        let thermal = self.thermal()?;
        Some(ElectricTruck { machines: self.machines.derated(thermal.continuous_nm), ..self.clone() })
    }

    /// The same truck at another total mass [kg], checked as the body is.
    pub fn with_mass_kg(&self, mass_kg: f64) -> CoreResult<Self> {
        let body = Body { mass_kg, ..self.body };
        crate::powertrain::truck::check_body(&body)?;
        Ok(ElectricTruck { body, ..self.clone() })
    }
}

//! The truck the plant, the DP and the controllers drive: one of the built-in powertrains behind
//! the [`Powertrain`] interface, with its gears' constants and the parameters it was built from.
//!
//! Dispatch is a `match` over [`Model`], inlined, so the DP's per-transition calls stay static.

use std::sync::Arc;

use crate::error::CoreResult;
pub use crate::params::VehicleParams;
pub use crate::powertrain::interface::NEUTRAL;
use crate::powertrain::interface::{AffineAccel, Control, EnergyStore, Powertrain, RateForm};
pub use crate::powertrain::thesis::GearConstants;
use crate::powertrain::{ElectricModel, MapModel, Thermal, ThesisModel, G_MPS2};

/// The built-in powertrains.
#[derive(Debug, Clone)]
#[allow(clippy::large_enum_variant)] // inline, so the thesis's hot path takes no extra pointer
pub enum Model {
    /// The thesis's model (chapter 2, appendix B.1).
    Thesis(ThesisModel),
    /// A truck from component data (see [`crate::powertrain::dynamics`] for what its pedal means).
    Map(Arc<MapModel>),
    /// A battery-electric truck (see [`crate::powertrain::electric::model`] for its pedal).
    Electric(Arc<ElectricModel>),
}

/// Calls `$call` on the model inside `$vehicle`, whichever it is.
macro_rules! dispatch {
    ($vehicle:expr, $m:ident => $call:expr) => {
        match &$vehicle.model {
            Model::Thesis(model) => {
                let $m: &ThesisModel = model;
                $call
            }
            Model::Map(model) => {
                let $m: &MapModel = model;
                $call
            }
            Model::Electric(model) => {
                let $m: &ElectricModel = model;
                $call
            }
        }
    };
}

/// A validated vehicle: its powertrain, the (B.1) constants of its gears, and its parameters.
#[derive(Debug, Clone)]
pub struct Vehicle {
    params: VehicleParams,
    model: Model,
    gears: Vec<GearConstants>,
}

impl Vehicle {
    /// The thesis's truck: validate the parameters and precompute the model constants.
    pub fn new(params: VehicleParams) -> CoreResult<Self> {
        let thesis = ThesisModel::new(params.clone())?;
        let gears = thesis.gears().to_vec();
        Ok(Vehicle { params, model: Model::Thesis(thesis), gears })
    }

    /// A truck from component data. `base` gives what the components do not: the service brakes'
    /// torque (`brake_torque_max_nm`); the other keys of [`Vehicle::params`] are set from the
    /// truck (mass, inertias, idle speed, ratios, the driveline's efficiency in every gear, tyre
    /// radius, rolling resistance, air density, g), so code that reads them sees this truck.
    pub fn from_map(model: Arc<MapModel>, base: &VehicleParams) -> CoreResult<Self> {
        let truck = model.truck();
        let (engine, driveline, body) = (truck.engine(), truck.driveline(), truck.body());
        let gears = driveline.gears();
        let params = VehicleParams {
            mass_kg: body.mass_kg,
            engine_inertia_kgm2: engine.inertia_kgm2(),
            idle_speed_rpm: engine.idle_rpm(),
            final_drive_ratio: driveline.axle_ratio(),
            final_drive_efficiency: 1.0,
            wheel_inertia_kgm2: body.wheels_inertia_kgm2,
            rolling_resistance: body.rolling_resistance,
            gravity_mps2: G_MPS2,
            air_density_kgpm3: body.air_density_kgpm3,
            wheel_radius_m: driveline.wheel_radius_m(),
            brake_torque_max_nm: base.brake_torque_max_nm,
            gear_ratios: driveline.gear_ratios().to_vec(),
            gear_efficiencies: vec![driveline.efficiency(); gears],
            ..base.clone()
        };
        // Validates the keys set from the truck as the thesis's truck would be validated.
        ThesisModel::new(params.clone())?;
        let mut gear_constants = vec![GearConstants { c1: model.c1(0), c3: 0.0, c4: 0.0 }];
        for g in 1..=gears {
            let c3 = driveline.efficiency() * driveline.ratio(g);
            gear_constants.push(GearConstants { c1: model.c1(g), c3, c4: model.rpm_per_mps(g) });
        }
        Ok(Vehicle { params, model: Model::Map(model), gears: gear_constants })
    }

    /// A battery-electric truck, as [`Vehicle::from_map`] with the machines for the engine: one
    /// gear of the reduction's ratio, the machines' inertia, and the speed below which a cruise
    /// has stopped as the idle speed (so the stall speed is that speed).
    pub fn from_electric(model: Arc<ElectricModel>, base: &VehicleParams) -> CoreResult<Self> {
        let truck = model.truck();
        let body = truck.body();
        let params = VehicleParams {
            mass_kg: body.mass_kg,
            engine_inertia_kgm2: truck.machines().inertia_kgm2(),
            idle_speed_rpm: Powertrain::stall_speed_mps(model.as_ref()) * model.rpm_per_mps(),
            final_drive_ratio: 1.0,
            final_drive_efficiency: 1.0,
            wheel_inertia_kgm2: body.wheels_inertia_kgm2,
            rolling_resistance: body.rolling_resistance,
            gravity_mps2: G_MPS2,
            air_density_kgpm3: body.air_density_kgpm3,
            wheel_radius_m: truck.wheel_radius_m(),
            brake_torque_max_nm: base.brake_torque_max_nm,
            gear_ratios: vec![truck.ratio()],
            gear_efficiencies: vec![1.0],
            ..base.clone()
        };
        ThesisModel::new(params.clone())?;
        let c1 = model.c1();
        let gears = vec![
            GearConstants { c1, c3: 0.0, c4: 0.0 },
            GearConstants { c1, c3: truck.ratio(), c4: model.rpm_per_mps() },
        ];
        Ok(Vehicle { params, model: Model::Electric(model), gears })
    }

    /// Whether the truck draws on a battery.
    pub fn is_electric(&self) -> bool {
        matches!(self.model, Model::Electric(_))
    }

    /// The powertrain.
    #[inline]
    pub fn model(&self) -> &Model {
        &self.model
    }

    /// How long a gear shift interrupts traction [s]: 0 for the thesis's truck (instant shifts).
    pub fn traction_interruption_s(&self) -> f64 {
        dispatch!(self, m => Powertrain::traction_interruption_s(m))
    }

    /// The parameters this vehicle was built from.
    pub fn params(&self) -> &VehicleParams {
        &self.params
    }

    /// Number of forward gears (gear numbers 1..=n; 0 is neutral).
    pub fn forward_gears(&self) -> usize {
        self.gears.len() - 1
    }

    /// The (B.1) constants of a gear (0 = neutral). Panics on a gear number above `forward_gears()`.
    #[inline]
    pub fn gear(&self, gear: usize) -> GearConstants {
        self.gears[gear]
    }

    /// Gravity and rolling-resistance torque at the wheel on a slope [Nm].
    #[inline]
    pub fn slope_torque_nm(&self, slope: f64) -> f64 {
        dispatch!(self, m => Powertrain::slope_torque_nm(m, slope))
    }

    /// Engine speed [rpm]: c4·v in gear, idle speed in neutral.
    #[inline]
    pub fn engine_speed_rpm(&self, v_mps: f64, gear: usize) -> f64 {
        if let Model::Electric(m) = &self.model {
            return m.rpm_per_mps() * v_mps;
        }
        if gear == NEUTRAL {
            self.params.idle_speed_rpm
        } else {
            self.gears[gear].c4 * v_mps
        }
    }

    /// Engine torque [Nm] at engine speed `n_rpm` with `pedal` in `gear`, zero in neutral.
    #[inline]
    pub fn engine_torque_nm(&self, n_rpm: f64, pedal: f64, gear: usize) -> f64 {
        match &self.model {
            Model::Thesis(t) => t.engine_torque_nm(n_rpm, pedal, gear),
            Model::Map(_) if gear == NEUTRAL => 0.0,
            Model::Map(m) => m.engine_torque_nm(n_rpm / self.gears[gear].c4, pedal, gear),
            Model::Electric(m) => {
                let u = Control { pedal, brake: 0.0, gear };
                Powertrain::machine_torque_nm(m.as_ref(), n_rpm / m.rpm_per_mps(), u)
            }
        }
    }

    /// Acceleration dv/dt (B.1) [m/s²] at speed v, pedal P ∈ [0,1], brake B ∈ [0,1], gear, slope.
    #[inline]
    pub fn accel_mps2(&self, v_mps: f64, pedal: f64, brake: f64, gear: usize, slope: f64) -> f64 {
        self.accel_on(v_mps, pedal, brake, gear, self.slope_torque_nm(slope))
    }

    /// [`Vehicle::accel_mps2`] with the slope given as its wheel torque [Nm], for callers that
    /// evaluate one slope many times.
    #[inline]
    pub fn accel_on(&self, v_mps: f64, pedal: f64, brake: f64, gear: usize, slope_torque_nm: f64) -> f64 {
        dispatch!(self, m => Powertrain::accel_on(m, v_mps, pedal, brake, gear, slope_torque_nm))
    }

    /// Fuel mass flow [g/s]: the energy rate with the brake off.
    #[inline]
    pub fn fuel_rate_gps(&self, v_mps: f64, pedal: f64, gear: usize) -> f64 {
        dispatch!(self, m => Powertrain::energy_rate(m, v_mps, Control { pedal, brake: 0.0, gear }))
    }

    /// Brake force at the wheel contact [N] for brake level B.
    #[inline]
    pub fn brake_force_n(&self, brake: f64) -> f64 {
        self.params.brake_torque_max_nm * brake / self.params.wheel_radius_m
    }

    /// Highest engine speed [rpm] at which fuel can still be injected (infinite if unbounded).
    pub fn max_engine_speed_rpm(&self) -> f64 {
        match &self.model {
            Model::Thesis(t) => t.max_engine_speed_rpm(),
            Model::Map(m) => m.truck().engine().speed_range_rpm().1,
            Model::Electric(m) => m.truck().machines().top_rpm(),
        }
    }

    /// Lowest speed [m/s] at which the lowest gear still turns the engine at idle speed. Below it the
    /// model (no clutch slip) does not apply and a truck that slows down further has stalled.
    pub fn stall_speed_mps(&self) -> f64 {
        self.params.idle_speed_rpm / self.gears[1].c4
    }

    /// ∂(dv/dt)/∂v [1/s] at (v, P, brake off, gear) on a flat road.
    pub fn accel_derivative_per_s(&self, v_mps: f64, pedal: f64, gear: usize) -> f64 {
        dispatch!(self, m => Powertrain::accel_derivative_per_s(m, v_mps, pedal, gear))
    }
}

impl Powertrain for Vehicle {
    #[inline]
    fn forward_gears(&self) -> usize {
        Vehicle::forward_gears(self)
    }

    #[inline]
    fn engine_speed_rpm(&self, v_mps: f64, gear: usize) -> f64 {
        Vehicle::engine_speed_rpm(self, v_mps, gear)
    }

    fn stall_speed_mps(&self) -> f64 {
        Vehicle::stall_speed_mps(self)
    }

    #[inline]
    fn traction_interruption_s(&self) -> f64 {
        Vehicle::traction_interruption_s(self)
    }

    #[inline]
    fn interrupted_energy_rate(&self, v_mps: f64) -> f64 {
        dispatch!(self, m => Powertrain::interrupted_energy_rate(m, v_mps))
    }

    #[inline]
    fn slope_torque_nm(&self, grade: f64) -> f64 {
        Vehicle::slope_torque_nm(self, grade)
    }

    #[inline]
    fn pedal_affine(&self, v_mps: f64, gear: usize, slope_torque_nm: f64) -> AffineAccel {
        dispatch!(self, m => Powertrain::pedal_affine(m, v_mps, gear, slope_torque_nm))
    }

    #[inline]
    fn brake_affine(&self, v_mps: f64, gear: usize, slope_torque_nm: f64) -> AffineAccel {
        dispatch!(self, m => Powertrain::brake_affine(m, v_mps, gear, slope_torque_nm))
    }

    #[inline]
    fn accel_on(&self, v_mps: f64, pedal: f64, brake: f64, gear: usize, slope_torque_nm: f64) -> f64 {
        Vehicle::accel_on(self, v_mps, pedal, brake, gear, slope_torque_nm)
    }

    fn accel_derivative_per_s(&self, v_mps: f64, pedal: f64, gear: usize) -> f64 {
        Vehicle::accel_derivative_per_s(self, v_mps, pedal, gear)
    }

    #[inline]
    fn energy_rate(&self, v_mps: f64, u: Control) -> f64 {
        dispatch!(self, m => Powertrain::energy_rate(m, v_mps, u))
    }

    #[inline]
    fn friction_brake_force_n(&self, v_mps: f64, u: Control) -> f64 {
        dispatch!(self, m => Powertrain::friction_brake_force_n(m, v_mps, u))
    }

    #[inline]
    fn rate_form(&self) -> RateForm {
        dispatch!(self, m => Powertrain::rate_form(m))
    }

    #[inline]
    fn zero_pedal_is_cut(&self) -> bool {
        dispatch!(self, m => Powertrain::zero_pedal_is_cut(m))
    }

    fn glide_pedal(&self, v_mps: f64, gear: usize) -> Option<f64> {
        dispatch!(self, m => Powertrain::glide_pedal(m, v_mps, gear))
    }

    fn glides(&self) -> bool {
        dispatch!(self, m => Powertrain::glides(m))
    }

    fn kinetic_energy_price(&self, gear: usize) -> Option<f64> {
        dispatch!(self, m => Powertrain::kinetic_energy_price(m, gear))
    }

    #[inline]
    fn brake_draws_energy(&self) -> bool {
        dispatch!(self, m => Powertrain::brake_draws_energy(m))
    }

    fn store(&self) -> EnergyStore {
        dispatch!(self, m => Powertrain::store(m))
    }

    fn thermal(&self) -> Option<Thermal> {
        dispatch!(self, m => Powertrain::thermal(m))
    }

    #[inline]
    fn rates_with_losses(&self, v_mps: f64, u: Control) -> [f64; 4] {
        dispatch!(self, m => Powertrain::rates_with_losses(m, v_mps, u))
    }

    fn machine_torque_nm(&self, v_mps: f64, u: Control) -> f64 {
        dispatch!(self, m => Powertrain::machine_torque_nm(m, v_mps, u))
    }

    /// The same vehicle with its drive derated (a battery-electric truck's machines).
    fn derated(&self) -> Option<Self> {
        match &self.model {
            Model::Electric(m) => {
                m.derated().map(|derated| Vehicle { model: Model::Electric(Arc::new(derated)), ..self.clone() })
            }
            _ => None,
        }
    }
}

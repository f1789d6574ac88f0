//! The model of one run, built in one place: the validated settings, the truck as the plant drives
//! it and as the controllers model it (the thesis's model or one from component data), every check
//! where the settings meet the truck, the built-in controllers by name, and a changed copy for the
//! runs a study derives from this one (legs, convergence checks, equal-time searches).

pub mod controllers;
mod drivable;
mod resolved;
mod truck;

use std::sync::Arc;

pub use controllers::{ControllerKind, CONTROLLERS};
pub use drivable::{check_drivable, speed_limits, v_ref_range_kmh, SpeedLimits};
pub use truck::ComponentTruck;

use crate::band::SpeedBand;
use crate::control::{Controller, GearLogic};
use crate::dp::{fuel_time, DpSettings};
use crate::error::{CoreError, CoreResult};
use crate::params::{RunSettings, Value};
use crate::road::Road;
use crate::sim::{self, RunOutput};
use crate::vehicle::Vehicle;

/// One run's settings and truck, checked against each other.
#[derive(Debug, Clone)]
pub struct Scenario {
    settings: Arc<RunSettings>,
    truck: Option<Arc<ComponentTruck>>,
    vehicle: Arc<Vehicle>,
    /// The vehicle the controllers model (the truck's unless `controller_mass_kg` is set).
    controller_vehicle: Arc<Vehicle>,
}

impl Scenario {
    /// The run of `settings` (validated here) with `truck`, or the thesis's truck of the settings'
    /// vehicle keys when None. Refuses, naming the key: a VECTO truck's key set without one, a set speed the truck cannot drive, a
    /// fuel_time cost whose β cannot be derived, a set speed where kinetic energy has no price.
    pub fn new(settings: RunSettings, truck: Option<Arc<ComponentTruck>>) -> CoreResult<Self> {
        settings.validate()?;
        if truck.is_none() {
            truck::check_no_truck_keys(&settings)?;
        }
        let mut settings = settings;
        let vehicle = Arc::new(vehicle_of(&settings, truck.as_deref(), None)?);
        if vehicle.is_electric() {
            truck::electric_settings(&mut settings, &vehicle)?;
        } else {
            truck::check_no_electric_keys(&settings)?;
        }
        check_drivable(&settings, &vehicle)?;
        let controller_vehicle = match settings.sim.controller_mass_kg {
            Some(mass_kg) => Arc::new(vehicle_of(&settings, truck.as_deref(), Some(mass_kg))?),
            None => vehicle.clone(),
        };
        DpSettings::new(&settings.mpc, &settings.cruise)?.check_vehicle(&controller_vehicle)?;
        check_kinetic_price(&settings, &vehicle)?;
        Ok(Scenario { settings: Arc::new(settings), truck, vehicle, controller_vehicle })
    }

    /// The declared defaults overridden by `values` (key, user value), with `truck`.
    pub fn from_values<'a>(
        values: impl IntoIterator<Item = (&'a str, &'a Value)>,
        truck: Option<Arc<ComponentTruck>>,
    ) -> CoreResult<Self> {
        Scenario::new(RunSettings::from_values(values)?, truck)
    }

    /// This run with `changes` (key, user value) made, the same truck, checked as [`Scenario::new`].
    pub fn with_values<'a>(&self, changes: impl IntoIterator<Item = (&'a str, &'a Value)>) -> CoreResult<Self> {
        let mut settings = (*self.settings).clone();
        for (key, value) in changes {
            settings.set(key, value)?;
        }
        if self.truck.is_some() {
            truck::check_same_truck_keys(&self.settings, &settings)?;
        }
        Scenario::new(settings, self.truck.clone())
    }

    /// The validated settings.
    pub fn settings(&self) -> &RunSettings {
        &self.settings
    }

    /// The truck the plant drives.
    pub fn vehicle(&self) -> &Arc<Vehicle> {
        &self.vehicle
    }

    /// The truck the controllers model.
    pub fn controller_vehicle(&self) -> &Arc<Vehicle> {
        &self.controller_vehicle
    }

    /// A new built-in controller by name ([`CONTROLLERS`]), modelling the controllers' truck.
    pub fn controller(&self, name: &str) -> CoreResult<Box<dyn Controller + Send>> {
        controllers::build(name, &self.controller_vehicle, &self.settings)
    }

    /// The start speed [km/h] on `road`: `start_speed_kmh`, or when it is null the set speed at the
    /// road's start (v_ref, or the band's on a road with target speeds).
    pub fn start_speed_kmh(&self, road: &Road) -> f64 {
        let settings = &self.settings;
        settings
            .sim
            .start_speed_kmh
            .unwrap_or_else(|| SpeedBand::new(road, &settings.cruise).at(road.start_m(), &mut 0).v_ref_kmh)
    }

    /// Drive `road` with `controller`, planning on `map` (the road itself when None), from the
    /// start speed to the road's end or a stall. The output of a built-in controller that solves
    /// the DP carries [`Scenario::dp_settings`].
    pub fn run(
        &self,
        road: &Arc<Road>,
        map: Option<&Road>,
        altitude_m: &[f64],
        controller: &mut dyn Controller,
    ) -> CoreResult<RunOutput> {
        let start_kmh = self.start_speed_kmh(road);
        let map = map.unwrap_or(road);
        let mut output =
            sim::run_on_map(&self.vehicle, road, map, altitude_m, controller, &self.settings.sim, start_kmh)?;
        if CONTROLLERS.iter().any(|kind| kind.name == output.controller && kind.solves_dp) {
            output.settings = Some(self.dp_settings()?);
        }
        Ok(output)
    }

    /// The set speeds v_ref [km/h] whose band the truck can drive, (lowest, highest).
    pub fn v_ref_range_kmh(&self) -> (f64, f64) {
        v_ref_range_kmh(&self.settings, &self.vehicle)
    }

    /// The gear the PI's gear logic settles in at constant `v_mps` [m/s].
    pub fn steady_gear(&self, v_mps: f64) -> CoreResult<usize> {
        Ok(GearLogic::new(&self.vehicle, &self.settings.pi)?.steady_gear(v_mps))
    }

    /// Grams of fuel per unit of ½v² [m²/s²] the engine adds in the gear the PI settles in at
    /// v_ref: kinetic energy priced in fuel, for the end-speed correction.
    pub fn kinetic_fuel_g_per_half_v2(&self) -> CoreResult<f64> {
        kinetic_price_g(&self.settings, &self.vehicle).map(|(price, _)| price)
    }
}

/// The truck of `settings` (the thesis's model, or `truck`'s), at `mass_kg` when given.
fn vehicle_of(settings: &RunSettings, truck: Option<&ComponentTruck>, mass_kg: Option<f64>) -> CoreResult<Vehicle> {
    match (truck, mass_kg) {
        (None, None) => Vehicle::new(settings.vehicle.clone()),
        (None, Some(_)) => Vehicle::new(settings.controller_vehicle_params()),
        (Some(t), None) => t.vehicle(&settings.vehicle),
        (Some(t), Some(m)) => t.vehicle_at_mass(m, &settings.vehicle),
    }
}

/// Kinetic energy's price [g per unit of ½v²] in the gear the PI settles in at v_ref, and that gear.
fn kinetic_price_g(settings: &RunSettings, vehicle: &Vehicle) -> CoreResult<(f64, usize)> {
    let v_ref_mps = settings.cruise.v_ref_kmh / crate::KMH_PER_MPS;
    let gear = GearLogic::new(vehicle, &settings.pi)?.steady_gear(v_ref_mps);
    Ok((fuel_time::kinetic_fuel_g(vehicle, v_ref_mps, gear), gear))
}

/// The end-speed correction prices kinetic energy where the PI settles at v_ref on a flat road; a
/// map-based truck that cannot hold v_ref there has no price: refused, naming v_ref_kmh.
fn check_kinetic_price(settings: &RunSettings, vehicle: &Vehicle) -> CoreResult<()> {
    let (price, gear) = kinetic_price_g(settings, vehicle)?;
    if price.is_finite() {
        return Ok(());
    }
    let expected = format!(
        "a set speed the truck holds on a flat road in gear {gear}, where the PI settles (kinetic energy is priced there)"
    );
    Err(CoreError::invalid("v_ref_kmh", expected).got(settings.cruise.v_ref_kmh))
}

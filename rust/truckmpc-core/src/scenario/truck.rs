//! A truck from component data as a run takes it (an engine-driven truck with how long its gearbox
//! interrupts traction at a shift, or a battery-electric truck), and the models built from it, kept so that the runs of a study (each with
//! its own settings) build each model once.

use std::sync::{Arc, Mutex};

use crate::error::{CoreError, CoreResult};
use crate::params::{
    ParamSet, ParamValue, RunSettings, Value, VectoParams, VehicleParams, TRACTION_INTERRUPTION_RANGE_S,
};
use crate::powertrain::{ElectricModel, ElectricTruck, MapModel, MapTruck};
use crate::vehicle::{Model, Vehicle};

/// A truck from component data and the models built from it, by brake torque.
#[derive(Debug)]
pub struct ComponentTruck {
    kind: Kind,
    /// The models built for this truck, by brake torque [Nm] (bits): building one resamples the
    /// maps, which every run's settings would otherwise repeat.
    models: Mutex<Vec<(u64, Model)>>,
}

/// The kinds of truck from component data (built once a study, so their size does not matter).
#[derive(Debug)]
#[allow(clippy::large_enum_variant)]
enum Kind {
    /// An engine and a gearbox whose shifts interrupt traction for `traction_interruption_s` [s].
    Map { truck: MapTruck, traction_interruption_s: f64 },
    /// Electric machines and a battery.
    Electric(ElectricTruck),
}

impl ComponentTruck {
    /// `truck`, whose gearbox interrupts traction for `traction_interruption_s` [s] at a shift;
    /// the error names `traction_interruption_s` outside its declared range.
    pub fn new(truck: MapTruck, traction_interruption_s: f64) -> CoreResult<Self> {
        let value = Value::Float(traction_interruption_s);
        f64::from_value("traction_interruption_s", &value, &TRACTION_INTERRUPTION_RANGE_S)?;
        Ok(ComponentTruck { kind: Kind::Map { truck, traction_interruption_s }, models: Mutex::new(Vec::new()) })
    }

    /// A battery-electric truck.
    pub fn electric(truck: ElectricTruck) -> Self {
        ComponentTruck { kind: Kind::Electric(truck), models: Mutex::new(Vec::new()) }
    }

    /// The engine-driven truck's components (None for a battery-electric truck).
    pub fn truck(&self) -> Option<&MapTruck> {
        match &self.kind {
            Kind::Map { truck, .. } => Some(truck),
            Kind::Electric(_) => None,
        }
    }

    /// The battery-electric truck's components (None for an engine-driven truck).
    pub fn electric_truck(&self) -> Option<&ElectricTruck> {
        match &self.kind {
            Kind::Electric(truck) => Some(truck),
            Kind::Map { .. } => None,
        }
    }

    /// How long a gear shift interrupts traction [s] (0 for a battery-electric truck: one gear).
    pub fn traction_interruption_s(&self) -> f64 {
        match &self.kind {
            Kind::Map { traction_interruption_s, .. } => *traction_interruption_s,
            Kind::Electric(_) => 0.0,
        }
    }

    /// The vehicle of this truck with the service brakes of `base` (its `brake_torque_max_nm`),
    /// whose model is built once per brake torque.
    pub fn vehicle(&self, base: &VehicleParams) -> CoreResult<Vehicle> {
        let mut models = self.models.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
        let key = base.brake_torque_max_nm.to_bits();
        let model = match models.iter().find(|(k, _)| *k == key) {
            Some((_, model)) => model.clone(),
            None => {
                let model = self.model_of(&self.kind, base.brake_torque_max_nm);
                models.push((key, model.clone()));
                model
            }
        };
        drop(models);
        vehicle_from(model, base)
    }

    /// The vehicle of this truck at another mass `mass_kg` [kg] (not kept: a controller's model of
    /// a truck it misjudges).
    pub fn vehicle_at_mass(&self, mass_kg: f64, base: &VehicleParams) -> CoreResult<Vehicle> {
        let kind = match &self.kind {
            Kind::Map { truck, traction_interruption_s } => {
                Kind::Map { truck: truck.with_mass_kg(mass_kg)?, traction_interruption_s: *traction_interruption_s }
            }
            Kind::Electric(truck) => Kind::Electric(truck.with_mass_kg(mass_kg)?),
        };
        vehicle_from(self.model_of(&kind, base.brake_torque_max_nm), base)
    }

    /// The model of `kind` with `brake_torque_max_nm` [Nm] at full brake.
    fn model_of(&self, kind: &Kind, brake_torque_max_nm: f64) -> Model {
        match kind {
            Kind::Map { truck, traction_interruption_s } => {
                Model::Map(Arc::new(MapModel::new(truck.clone(), brake_torque_max_nm, *traction_interruption_s)))
            }
            Kind::Electric(truck) => Model::Electric(Arc::new(ElectricModel::new(truck.clone(), brake_torque_max_nm))),
        }
    }
}

/// The vehicle of a model from component data, with `base`'s service brakes.
fn vehicle_from(model: Model, base: &VehicleParams) -> CoreResult<Vehicle> {
    match model {
        Model::Map(model) => Vehicle::from_map(model, base),
        Model::Electric(model) => Vehicle::from_electric(model, base),
        Model::Thesis(_) => unreachable!("a truck from component data"),
    }
}

/// The keys a truck from VECTO's files is built from: its own section and the air density.
fn truck_keys(settings: &RunSettings) -> impl Iterator<Item = (&'static str, Value)> + '_ {
    let names = VectoParams::specs().into_iter().map(|spec| spec.name).chain(["air_density_kgpm3"]);
    names.map(|name| (name, settings.get(name).expect("declared")))
}

/// With an engine-driven truck, a battery's keys keep their defaults (set, they would be ignored).
pub(super) fn check_no_electric_keys(settings: &RunSettings) -> CoreResult<()> {
    let defaults = VectoParams::default();
    for key in ELECTRIC_KEYS {
        let value = settings.vecto.get(key).expect("declared");
        if defaults.get(key).as_ref() != Some(&value) {
            let expected = "no value with an engine-driven truck (a key of a battery-electric truck)";
            return Err(CoreError::invalid(key, expected).got(value));
        }
    }
    Ok(())
}

/// Without a truck from VECTO's files, its keys keep their defaults (set, they would be ignored).
pub(super) fn check_no_truck_keys(settings: &RunSettings) -> CoreResult<()> {
    let defaults = VectoParams::default();
    for spec in VectoParams::specs() {
        let value = settings.vecto.get(spec.name).expect("declared");
        if defaults.get(spec.name).as_ref() != Some(&value) {
            let expected = "no value with the thesis's truck (a key of a truck from VECTO's files)";
            return Err(CoreError::invalid(spec.name, expected).got(value));
        }
    }
    Ok(())
}

/// A run derived from one with a truck keeps the keys the truck was built from (another value is
/// another truck, built anew).
pub(super) fn check_same_truck_keys(built: &RunSettings, changed: &RunSettings) -> CoreResult<()> {
    for ((key, was), (_, now)) in truck_keys(built).zip(truck_keys(changed)) {
        if was != now {
            let expected = format!("{was}, the value the truck was built with (another value builds another truck)");
            return Err(CoreError::invalid(key, expected).got(now));
        }
    }
    Ok(())
}

/// The keys of a truck from VECTO's files that describe a diesel driveline: a battery-electric
/// truck keeps their defaults (set, they would be ignored).
const DIESEL_KEYS: [&str; 5] =
    ["gear_efficiency", "axle_efficiency", "loss_torque_nm", "use_loss_maps", "traction_interruption_s"];

/// The keys of a truck from VECTO's files that only a battery-electric truck takes.
const ELECTRIC_KEYS: [&str; 1] = ["soc_start_pct"];

/// With a battery-electric truck the DP's usable speeds are its machines': `n_min_rpm` and
/// `n_max_rpm` (an engine's window) become the speed below which the cruise has stopped and the
/// machines' top speed; and the PCC has no eco-roll (`eco_roll` false, as VECTO's for such a
/// truck). Refused, naming the key: either speed set to another value, or a diesel driveline's
/// key set.
pub(super) fn electric_settings(settings: &mut RunSettings, vehicle: &Vehicle) -> CoreResult<()> {
    let defaults = VectoParams::default();
    for key in DIESEL_KEYS {
        let value = settings.vecto.get(key).expect("declared");
        if defaults.get(key).as_ref() != Some(&value) {
            let expected = "no value with a battery-electric truck (a key of a diesel driveline)";
            return Err(CoreError::invalid(key, expected).got(value));
        }
    }
    let window = (vehicle.params().idle_speed_rpm, vehicle.max_engine_speed_rpm());
    let mpc_defaults = crate::params::MpcParams::default();
    for (key, value, default, machines) in [
        ("n_min_rpm", settings.mpc.n_min_rpm, mpc_defaults.n_min_rpm, window.0),
        ("n_max_rpm", settings.mpc.n_max_rpm, mpc_defaults.n_max_rpm, window.1),
    ] {
        if value != default && value != machines {
            let expected =
                format!("no value with a battery-electric truck (its machines' speeds apply: {machines:.0} rpm)");
            return Err(CoreError::invalid(key, expected).got(value));
        }
    }
    (settings.mpc.n_min_rpm, settings.mpc.n_max_rpm) = window;
    // VECTO's predictive cruise control has no eco-roll for a battery-electric truck.
    settings.pcc.eco_roll = false;
    Ok(())
}

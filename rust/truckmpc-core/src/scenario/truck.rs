//! A truck from component data as a run takes it: the truck, how long its gearbox interrupts
//! traction at a shift, and the models built from it, kept so that the runs of a study (each with
//! its own settings) build each model once.

use std::sync::{Arc, Mutex};

use crate::error::{CoreError, CoreResult};
use crate::params::{ParamSet, ParamValue, RunSettings, Value, VectoParams, TRACTION_INTERRUPTION_RANGE_S};
use crate::powertrain::{MapModel, MapTruck};

/// A truck from component data and the models built from it, by brake torque.
#[derive(Debug)]
pub struct ComponentTruck {
    truck: MapTruck,
    traction_interruption_s: f64,
    /// The models built for this truck, by brake torque [Nm] (bits): building one resamples the
    /// maps, which every run's settings would otherwise repeat.
    models: Mutex<Vec<(u64, Arc<MapModel>)>>,
}

impl ComponentTruck {
    /// `truck`, whose gearbox interrupts traction for `traction_interruption_s` [s] at a shift;
    /// the error names `traction_interruption_s` outside its declared range.
    pub fn new(truck: MapTruck, traction_interruption_s: f64) -> CoreResult<Self> {
        let value = Value::Float(traction_interruption_s);
        f64::from_value("traction_interruption_s", &value, &TRACTION_INTERRUPTION_RANGE_S)?;
        Ok(ComponentTruck { truck, traction_interruption_s, models: Mutex::new(Vec::new()) })
    }

    /// The truck's components.
    pub fn truck(&self) -> &MapTruck {
        &self.truck
    }

    /// How long a gear shift interrupts traction [s].
    pub fn traction_interruption_s(&self) -> f64 {
        self.traction_interruption_s
    }

    /// The model of this truck with `brake_torque_max_nm` [Nm] at full brake, built once.
    pub fn model(&self, brake_torque_max_nm: f64) -> Arc<MapModel> {
        let mut models = self.models.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
        let key = brake_torque_max_nm.to_bits();
        if let Some((_, model)) = models.iter().find(|(k, _)| *k == key) {
            return model.clone();
        }
        let model = Arc::new(MapModel::new(self.truck.clone(), brake_torque_max_nm, self.traction_interruption_s));
        models.push((key, model.clone()));
        model
    }

    /// The model of this truck at another mass `mass_kg` [kg] (not kept: a controller's model of a
    /// truck it misjudges).
    pub fn model_at_mass(&self, mass_kg: f64, brake_torque_max_nm: f64) -> CoreResult<Arc<MapModel>> {
        let truck = self.truck.with_mass_kg(mass_kg)?;
        Ok(Arc::new(MapModel::new(truck, brake_torque_max_nm, self.traction_interruption_s)))
    }
}

/// The keys a truck from VECTO's files is built from: its own section and the air density.
fn truck_keys(settings: &RunSettings) -> impl Iterator<Item = (&'static str, Value)> + '_ {
    let names = VectoParams::specs().into_iter().map(|spec| spec.name).chain(["air_density_kgpm3"]);
    names.map(|name| (name, settings.get(name).expect("declared")))
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

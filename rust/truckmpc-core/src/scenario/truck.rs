//! A truck from component data as a run takes it: the truck, how long its gearbox interrupts
//! traction at a shift, and the models built from it, kept so that the runs of a study (each with
//! its own settings) build each model once.

use std::sync::{Arc, Mutex};

use crate::error::{CoreError, CoreResult};
use crate::powertrain::{MapModel, MapTruck};

/// Longest traction interruption a gearbox may have [s].
pub const TRACTION_INTERRUPTION_MAX_S: f64 = 10.0;

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
    /// the error names `traction_interruption_s` outside [0, 10] s.
    pub fn new(truck: MapTruck, traction_interruption_s: f64) -> CoreResult<Self> {
        if !(traction_interruption_s.is_finite()
            && (0.0..=TRACTION_INTERRUPTION_MAX_S).contains(&traction_interruption_s))
        {
            let expected = format!("a time in [0, {TRACTION_INTERRUPTION_MAX_S}] s");
            return Err(CoreError::invalid("traction_interruption_s", expected).got(traction_interruption_s));
        }
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

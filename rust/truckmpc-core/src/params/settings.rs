//! All the settings of a run, as one flat namespace of declared keys.

use super::{
    retired, Change, CruiseParams, MpcParams, ParamSet, ParamSpec, PccParams, PiParams, SimParams, Value, VectoParams,
    VehicleParams,
};
use crate::error::{CoreError, CoreResult};

/// The vehicle, the cruise band, the controllers, the simulation and a VECTO truck's keys.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RunSettings {
    /// The truck.
    pub vehicle: VehicleParams,
    /// Set speed and band.
    pub cruise: CruiseParams,
    /// The PI cruise controller.
    pub pi: PiParams,
    /// The look-ahead controller.
    pub mpc: MpcParams,
    /// The rule-based predictive cruise control.
    pub pcc: PccParams,
    /// The closed-loop simulation.
    pub sim: SimParams,
    /// A truck from VECTO's files (defaults with the thesis's truck).
    pub vecto: VectoParams,
}

impl RunSettings {
    /// The names of the sections, in order.
    pub const SECTIONS: [&'static str; 7] = [
        VehicleParams::SECTION,
        CruiseParams::SECTION,
        PiParams::SECTION,
        MpcParams::SECTION,
        PccParams::SECTION,
        SimParams::SECTION,
        VectoParams::SECTION,
    ];

    /// Every declared parameter, section by section.
    pub fn specs() -> Vec<ParamSpec> {
        let mut specs = VehicleParams::specs();
        specs.extend(CruiseParams::specs());
        specs.extend(PiParams::specs());
        specs.extend(MpcParams::specs());
        specs.extend(PccParams::specs());
        specs.extend(SimParams::specs());
        specs.extend(VectoParams::specs());
        specs
    }

    /// Set one key from a user value (type and range checked); an unknown key is an error.
    pub fn set(&mut self, key: &str, value: &Value) -> CoreResult<()> {
        let known = self.vehicle.set(key, value)?
            || self.cruise.set(key, value)?
            || self.pi.set(key, value)?
            || self.mpc.set(key, value)?
            || self.pcc.set(key, value)?
            || self.sim.set(key, value)?
            || self.vecto.set(key, value)?;
        if known {
            return Ok(());
        }
        match retired(key).map(|c| c.change) {
            Some(Change::Replaced { new, why }) => {
                Err(CoreError::invalid(key, format!("{new} instead {why}")).got("a replaced key"))
            }
            Some(Change::Renamed { new }) => {
                Err(CoreError::invalid(key, format!("{new} (its name now)")).got("a renamed key"))
            }
            _ => Err(CoreError::invalid(key, "a known parameter").got("an unknown key")),
        }
    }

    /// The value of a key as a user would write it.
    pub fn get(&self, key: &str) -> Option<Value> {
        self.vehicle
            .get(key)
            .or_else(|| self.cruise.get(key))
            .or_else(|| self.pi.get(key))
            .or_else(|| self.mpc.get(key))
            .or_else(|| self.pcc.get(key))
            .or_else(|| self.sim.get(key))
            .or_else(|| self.vecto.get(key))
    }

    /// Every key with its value as a user would write it, in declaration order.
    pub fn values(&self) -> Vec<(&'static str, Value)> {
        Self::specs().iter().map(|spec| (spec.name, self.get(spec.name).expect("a declared key has a value"))).collect()
    }

    /// Defaults overridden by `values`, validated.
    pub fn from_values<'a>(values: impl IntoIterator<Item = (&'a str, &'a Value)>) -> CoreResult<Self> {
        let mut settings = RunSettings::default();
        for (key, value) in values {
            settings.set(key, value)?;
        }
        settings.validate()?;
        Ok(settings)
    }

    /// Every range, then every check between keys (within and across sections).
    pub fn validate(&self) -> CoreResult<()> {
        self.vehicle.check_ranges()?;
        self.cruise.check_ranges()?;
        self.pi.check_ranges()?;
        self.mpc.check_ranges()?;
        self.pcc.check_ranges()?;
        self.sim.check_ranges()?;
        self.vecto.check_ranges()?;
        self.vehicle.check_gearbox()?;
        self.pi.check_thresholds()?;
        self.pi.check_gearbox(&self.vehicle.gear_ratios)?;
        self.mpc.check_with(&self.cruise)
    }

    /// The vehicle the controllers model: the truck's, with `controller_mass_kg` as its mass when
    /// that is set.
    pub fn controller_vehicle_params(&self) -> VehicleParams {
        match self.sim.controller_mass_kg {
            Some(mass_kg) => VehicleParams { mass_kg, ..self.vehicle.clone() },
            None => self.vehicle.clone(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::key_changes;
    use std::collections::HashSet;

    #[test]
    fn keys_are_unique_across_sections() {
        let specs = RunSettings::specs();
        let names: HashSet<&str> = specs.iter().map(|s| s.name).collect();
        assert_eq!(names.len(), specs.len());
    }

    #[test]
    fn defaults_pass_their_own_checks_and_round_trip() {
        let defaults = RunSettings::default();
        defaults.validate().unwrap();
        for spec in RunSettings::specs() {
            assert_eq!(defaults.get(spec.name), Some(spec.default.clone()), "{}", spec.name);
            let mut copy = defaults.clone();
            copy.set(spec.name, &spec.default).unwrap();
            assert_eq!(copy, defaults);
        }
    }

    #[test]
    fn errors_name_the_key_and_what_was_expected() {
        let err = RunSettings::from_values([("mass_kg", &Value::Int(-1))]).unwrap_err();
        assert_eq!(err.to_string(), "mass_kg: expected a number in (0, 1000000], got -1");
        let err = RunSettings::from_values([("plant_dt_s", &Value::Float(f64::NAN))]).unwrap_err();
        assert_eq!(err.to_string(), "plant_dt_s: expected a finite number in (0, 1], got NaN");
        let err = RunSettings::from_values([("grid", &Value::Text("loose".into()))]).unwrap_err();
        assert_eq!(err.to_string(), "grid: expected 'moving' or 'fixed', got 'loose'");
        let err = RunSettings::from_values([("k_lim", &Value::Float(2.5))]).unwrap_err();
        assert_eq!(err.to_string(), "k_lim: expected a whole number in [1, 1000000] or null, got 2.5");
        let err = RunSettings::from_values([("v_ref_kmh", &Value::Int(5))]).unwrap_err();
        let CoreError::Invalid { key, related, .. } = err;
        assert_eq!((key.as_str(), related), ("v_dec_kmh", vec!["v_ref_kmh".to_string()]));
    }

    #[test]
    fn a_replaced_key_names_its_replacement() {
        let replaced = key_changes().into_iter().filter_map(|c| match c.change {
            Change::Replaced { new, .. } | Change::Renamed { new } => Some((c.key, new)),
            Change::Added { .. } => None,
        });
        for (old, new) in replaced {
            let err = RunSettings::from_values([(old, &Value::Float(5.0))]).unwrap_err();
            assert_eq!(err.key(), old);
            assert!(err.to_string().starts_with(&format!("{old}: expected {new} ")), "{err}");
            assert!(RunSettings::specs().iter().all(|spec| spec.name != old));
        }
    }

    #[test]
    fn numeric_text_is_a_number_but_a_flag_is_not() {
        let settings = RunSettings::from_values([("brake_torque_max_nm", &Value::Text("1e5".into()))]).unwrap();
        assert_eq!(settings.vehicle.brake_torque_max_nm, 1e5);
        assert!(RunSettings::from_values([("mass_kg", &Value::Bool(true))]).is_err());
    }
}

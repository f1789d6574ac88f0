//! The declared parameters as Python sees them: their specs, and `Settings`, a validated set of
//! every section built from a flat mapping of user values.

use std::sync::Arc;

use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use truckmpc_core::control::pi::GearLogic;
use truckmpc_core::dp::{fuel_time, DpSettings};
use truckmpc_core::params::{Kind, ParamSpec, Value, REPLACED_KEYS};
use truckmpc_core::powertrain::MapModel;
use truckmpc_core::{RunSettings, Vehicle};

use crate::errors::to_py;
use crate::powertrain::PyMapTruck;
use crate::vehicle::PyVehicle;

/// A Python object as a user value. Other types become their repr, which no parameter accepts.
pub fn to_value(obj: &Bound<'_, PyAny>) -> PyResult<Value> {
    if obj.is_none() {
        Ok(Value::Null)
    } else if obj.is_instance_of::<PyBool>() {
        Ok(Value::Bool(obj.extract()?))
    } else if obj.is_instance_of::<PyInt>() {
        Ok(obj.extract::<i64>().map(Value::Int).unwrap_or(Value::Float(obj.extract::<f64>().unwrap_or(f64::INFINITY))))
    } else if obj.is_instance_of::<PyFloat>() {
        Ok(Value::Float(obj.extract()?))
    } else if obj.is_instance_of::<PyString>() {
        Ok(Value::Text(obj.extract()?))
    } else if obj.is_instance_of::<PyList>() || obj.is_instance_of::<PyTuple>() {
        obj.try_iter()?.map(|item| to_value(&item?)).collect::<PyResult<Vec<_>>>().map(Value::List)
    } else {
        Ok(Value::Text(obj.repr()?.to_string()))
    }
}

/// A user value as a Python object (None, bool, int, float, str or list).
pub fn from_value<'py>(py: Python<'py>, value: &Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match value {
        Value::Null => py.None().into_bound(py),
        Value::Bool(b) => PyBool::new(py, *b).to_owned().into_any(),
        Value::Int(i) => i.into_pyobject(py)?.into_any(),
        Value::Float(x) => x.into_pyobject(py)?.into_any(),
        Value::Text(t) => t.into_pyobject(py)?.into_any(),
        Value::List(items) => {
            PyList::new(py, items.iter().map(|v| from_value(py, v)).collect::<PyResult<Vec<_>>>()?)?.into_any()
        }
    })
}

/// One declared parameter: name (unit in the name), section, kind, unit, doc, default, range.
#[pyclass(name = "ParamSpec", module = "truckmpc._core", frozen, get_all)]
pub struct PyParamSpec {
    /// Key as typed in YAML, `--set` and `--grid`.
    name: String,
    /// Section: vehicle, cruise, pi, mpc or sim.
    section: String,
    /// number, number_or_null, count, count_or_null, flag, choice, numbers or numbers_or_nulls.
    kind: String,
    /// Unit in words.
    unit: String,
    /// One-line description.
    doc: String,
    /// Default value.
    default: Py<PyAny>,
    /// Names a choice accepts; None for other kinds.
    choices: Option<Vec<String>>,
    /// What a value must be, in words (`"a number > 0"`).
    expected: String,
}

impl PyParamSpec {
    fn new(py: Python<'_>, spec: &ParamSpec) -> PyResult<Self> {
        let choices = match spec.kind {
            Kind::Choice(names) => Some(names.iter().map(|n| n.to_string()).collect()),
            _ => None,
        };
        Ok(PyParamSpec {
            name: spec.name.to_string(),
            section: spec.section.to_string(),
            kind: spec.kind.name().to_string(),
            unit: spec.unit.to_string(),
            doc: spec.doc.clone(),
            default: from_value(py, &spec.default)?.unbind(),
            choices,
            expected: spec.expected(),
        })
    }
}

#[pymethods]
impl PyParamSpec {
    fn __repr__(&self) -> String {
        format!("ParamSpec({} [{}], {})", self.name, self.unit, self.section)
    }
}

/// Every declared parameter, section by section (vehicle, cruise, pi, mpc, sim).
#[pyfunction]
pub fn parameter_specs(py: Python<'_>) -> PyResult<Vec<PyParamSpec>> {
    RunSettings::specs().iter().map(|spec| PyParamSpec::new(py, spec)).collect()
}

/// The keys that are no longer declared, each with the key that replaced it.
#[pyfunction]
pub fn replaced_keys() -> Vec<(&'static str, &'static str)> {
    REPLACED_KEYS.to_vec()
}

/// The end-speed correction prices kinetic energy where the PI settles at v_ref on a flat road;
/// a map-based truck that cannot hold v_ref there has no price: refused, naming v_ref_kmh.
fn check_kinetic_price(settings: &RunSettings, vehicle: &Vehicle) -> truckmpc_core::CoreResult<()> {
    let v_ref_mps = settings.cruise.v_ref_kmh / 3.6;
    let gear = GearLogic::new(vehicle, &settings.pi)?.steady_gear(v_ref_mps);
    let price = fuel_time::kinetic_fuel_g(vehicle, v_ref_mps, gear);
    if price.is_finite() {
        return Ok(());
    }
    let expected = format!(
        "a set speed the truck holds on a flat road in gear {gear}, where the PI settles (kinetic energy is priced there)"
    );
    Err(truckmpc_core::CoreError::invalid("v_ref_kmh", expected).got(settings.cruise.v_ref_kmh))
}

/// A validated set of every parameter of a run.
///
/// Args:
///     values: mapping of declared keys to user values (YAML-like: numbers, numeric text, bools,
///         None, names, lists); keys not given take their declared defaults.
///
/// Raises:
///     ParamError: a key is unknown, or a value is of the wrong type, out of its range, or
///         inconsistent with another (the error's `related` names the others).
#[pyclass(name = "Settings", module = "truckmpc._core", frozen)]
pub struct PySettings {
    pub inner: Arc<RunSettings>,
    pub vehicle: Arc<Vehicle>,
    /// The vehicle the controllers model (the truck's unless `controller_mass_kg` is set).
    pub controller_vehicle: Arc<Vehicle>,
}

#[pymethods]
impl PySettings {
    #[new]
    #[pyo3(signature = (values, truck=None))]
    fn new(values: &Bound<'_, PyDict>, truck: Option<PyRef<'_, PyMapTruck>>) -> PyResult<Self> {
        let mut pairs = Vec::with_capacity(values.len());
        for (key, value) in values.iter() {
            pairs.push((key.extract::<String>()?, to_value(&value)?));
        }
        let settings = RunSettings::from_values(pairs.iter().map(|(k, v)| (k.as_str(), v))).map_err(to_py)?;
        let build = |mass_kg: Option<f64>| match &truck {
            None => Vehicle::new(match mass_kg {
                Some(_) => settings.controller_vehicle_params(),
                None => settings.vehicle.clone(),
            }),
            Some(t) => {
                let brake_nm = settings.vehicle.brake_torque_max_nm;
                let model = match mass_kg {
                    None => t.model(brake_nm),
                    Some(m) => Arc::new(MapModel::new(t.inner.with_mass_kg(m)?, brake_nm, t.traction_interruption_s)),
                };
                Vehicle::from_map(model, &settings.vehicle)
            }
        };
        let vehicle = Arc::new(build(None).map_err(to_py)?);
        settings.check_drivable(&vehicle).map_err(to_py)?;
        let controller_vehicle = match settings.sim.controller_mass_kg {
            Some(mass_kg) => Arc::new(build(Some(mass_kg)).map_err(to_py)?),
            None => vehicle.clone(),
        };
        DpSettings::new(&settings.mpc, &settings.cruise)
            .and_then(|dp| dp.check_vehicle(&controller_vehicle))
            .map_err(to_py)?;
        check_kinetic_price(&settings, &vehicle).map_err(to_py)?;
        Ok(PySettings { inner: Arc::new(settings), vehicle, controller_vehicle })
    }

    /// Every key's value, in declaration order.
    fn values<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let out = PyDict::new(py);
        for spec in RunSettings::specs() {
            let value = self.inner.get(spec.name).expect("a declared key has a value");
            out.set_item(spec.name, from_value(py, &value)?)?;
        }
        Ok(out)
    }

    /// The value of one key.
    fn get<'py>(&self, py: Python<'py>, key: &str) -> PyResult<Bound<'py, PyAny>> {
        match self.inner.get(key) {
            Some(value) => from_value(py, &value),
            None => Err(pyo3::exceptions::PyKeyError::new_err(key.to_string())),
        }
    }

    /// The validated vehicle model.
    #[getter]
    fn vehicle(&self) -> PyVehicle {
        PyVehicle { inner: self.vehicle.clone() }
    }

    /// The set speeds v_ref [km/h] whose band the truck can drive, (lowest, highest): v_ref − v_dec
    /// at or above gear 1 at n_min_rpm, v_ref + v_inc at or below the top gear at n_max_rpm.
    #[getter]
    fn v_ref_range_kmh(&self) -> (f64, f64) {
        self.inner.v_ref_range_kmh(&self.vehicle)
    }

    /// k_lim [stages] with its default resolved (round(200 m / S), table 6.1).
    #[getter]
    fn k_lim_stages(&self) -> u32 {
        self.inner.mpc.k_lim_stages()
    }

    /// N, the stages of the MPC's horizon (round(horizon / S), at least 1).
    #[getter]
    fn horizon_stages(&self) -> usize {
        self.inner.mpc.stages()
    }

    /// Stages decided from one horizon solve (round(replan / S), at least 1: a solve every stage).
    #[getter]
    fn replan_stages(&self) -> usize {
        self.inner.mpc.replan_stages()
    }

    /// Q2 per stage, resolved (q_speed_below, else q_speed_below_per_km × S, else table 6.2).
    #[getter]
    fn q_speed_below_weight(&self) -> f64 {
        self.inner.mpc.q_speed_below_weight()
    }

    /// Q5 per stage, resolved (q_brake, else q_brake_per_km × S).
    #[getter]
    fn q_brake_weight(&self) -> f64 {
        self.inner.mpc.q_brake_weight()
    }

    /// β [g/s] of the fuel_time cost as the MPC uses it (beta_g_per_s, else the β that makes
    /// steady v_ref optimal on a flat road); None with the speed_penalty cost.
    #[getter]
    fn beta_g_per_s_resolved(&self) -> PyResult<Option<f64>> {
        let dp = DpSettings::new(&self.inner.mpc, &self.inner.cruise).map_err(to_py)?;
        Ok(dp.beta_for(&self.controller_vehicle))
    }

    /// Grams of fuel per unit of ½v² [m²/s²] the engine adds in the gear the PI's gear logic settles
    /// in at v_ref: kinetic energy priced in fuel, for the end-speed correction (it depends on the
    /// vehicle, the cruise and the PI settings only, not on the look-ahead controller's).
    #[getter]
    fn kinetic_fuel_g_per_half_v2(&self) -> PyResult<f64> {
        let logic = GearLogic::new(&self.vehicle, &self.inner.pi).map_err(to_py)?;
        let v_ref_mps = self.inner.cruise.v_ref_kmh / 3.6;
        let gear = logic.steady_gear(v_ref_mps);
        Ok(fuel_time::kinetic_fuel_g(&self.vehicle, v_ref_mps, gear))
    }
}

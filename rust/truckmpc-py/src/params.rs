//! The declared parameters as Python sees them: their specs, and `Settings`, a run's model
//! ([`Scenario`]) built from a flat mapping of user values.

use pyo3::prelude::*;
use pyo3::types::PyDict;
use truckmpc_core::params::{key_changes, Change, Kind, ParamSpec, Value};
use truckmpc_core::scenario::Scenario;
use truckmpc_core::RunSettings;

use crate::convert::{dict_of, from_value, pairs_of, to_value};
use crate::errors::to_py;
use crate::powertrain::PyMapTruck;
use crate::vehicle::PyVehicle;

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

/// A key renamed, replaced or added: the core's registry of key changes, one entry.
#[pyclass(name = "KeyChange", module = "truckmpc._core", frozen, get_all)]
pub struct PyKeyChange {
    /// The key as it was (renamed, replaced) or as it is (added).
    key: String,
    /// renamed, replaced or added.
    kind: String,
    /// The key's successor (renamed, replaced); None for an added key.
    new: Option<String>,
    /// Why it was replaced, in parentheses; None otherwise.
    why: Option<String>,
    /// The value a record made before an added key existed replays with; None otherwise.
    replays_with: Py<PyAny>,
    /// The version of truckmpc that changed it.
    version: String,
}

/// Every key renamed, replaced or added, oldest first.
#[pyfunction(name = "key_changes")]
pub fn key_changes_py(py: Python<'_>) -> PyResult<Vec<PyKeyChange>> {
    key_changes()
        .into_iter()
        .map(|c| {
            let (kind, new, why, replays_with) = match c.change {
                Change::Renamed { new } => ("renamed", Some(new), None, Value::Null),
                Change::Replaced { new, why } => ("replaced", Some(new), Some(why), Value::Null),
                Change::Added { replays_with } => ("added", None, None, replays_with),
            };
            Ok(PyKeyChange {
                key: c.key.to_string(),
                kind: kind.to_string(),
                new: new.map(str::to_string),
                why: why.map(str::to_string),
                replays_with: from_value(py, &replays_with)?.unbind(),
                version: c.version.to_string(),
            })
        })
        .collect()
}

/// The value of `key` as the core reads `value`: type and range checked against its declaration.
#[pyfunction]
pub fn parameter_value<'py>(py: Python<'py>, key: &str, value: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
    let mut settings = RunSettings::default();
    settings.set(key, &to_value(value)?).map_err(to_py)?;
    from_value(py, &settings.get(key).expect("set"))
}

/// A run's settings and truck, checked against each other: every parameter of a run.
///
/// Args:
///     values: mapping of declared keys to user values (YAML-like: numbers, numeric text, bools,
///         None, names, lists); keys not given take their declared defaults.
///     truck: a truck from component data, replacing the thesis's model of the vehicle keys.
///
/// Raises:
///     ParamError: a key is unknown, or a value is of the wrong type, out of its range, or
///         inconsistent with another or with the truck (the error's `related` names the others).
#[pyclass(name = "Settings", module = "truckmpc._core", frozen)]
pub struct PySettings {
    pub inner: Scenario,
}

#[pymethods]
impl PySettings {
    #[new]
    #[pyo3(signature = (values, truck=None))]
    fn new(values: &Bound<'_, PyDict>, truck: Option<PyRef<'_, PyMapTruck>>) -> PyResult<Self> {
        let pairs = pairs_of(values)?;
        let truck = truck.map(|t| t.inner.clone());
        let inner = Scenario::from_values(pairs.iter().map(|(k, v)| (k.as_str(), v)), truck).map_err(to_py)?;
        Ok(PySettings { inner })
    }

    /// These settings with `changes` (a mapping of keys to user values) made, the same truck.
    fn with_values(&self, changes: &Bound<'_, PyDict>) -> PyResult<Self> {
        let pairs = pairs_of(changes)?;
        let inner = self.inner.with_values(pairs.iter().map(|(k, v)| (k.as_str(), v))).map_err(to_py)?;
        Ok(PySettings { inner })
    }

    /// Every key's value, in declaration order.
    fn values<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let settings = self.inner.settings();
        let pairs: Vec<(&str, Value)> =
            RunSettings::specs().iter().map(|spec| (spec.name, settings.get(spec.name).expect("declared"))).collect();
        dict_of(py, &pairs)
    }

    /// The value of one key.
    fn get<'py>(&self, py: Python<'py>, key: &str) -> PyResult<Bound<'py, PyAny>> {
        match self.inner.settings().get(key) {
            Some(value) => from_value(py, &value),
            None => Err(pyo3::exceptions::PyKeyError::new_err(key.to_string())),
        }
    }

    /// The keys whose values the run resolves (`k_lim`, `q_speed_below`, `q_brake`,
    /// `beta_g_per_s`), with the values it uses.
    fn resolved<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        dict_of(py, &self.inner.resolved().map_err(to_py)?)
    }

    /// The validated vehicle model.
    #[getter]
    fn vehicle(&self) -> PyVehicle {
        PyVehicle { inner: self.inner.vehicle().clone() }
    }

    /// Figures derived from the settings and the truck: `horizon_stages`, `replan_stages`,
    /// `v_ref_range_kmh` (lowest, highest) and `kinetic_fuel_g_per_half_v2`.
    fn derived<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        dict_of(py, &self.inner.derived().map_err(to_py)?)
    }

    /// The gear the PI gear logic (table A.3) settles in at constant speed `v_mps` [m/s].
    fn steady_gear(&self, v_mps: f64) -> PyResult<usize> {
        self.inner.steady_gear(v_mps).map_err(to_py)
    }
}

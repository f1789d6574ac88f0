//! The core's declarations and parameters as Python sees them, and `Settings`, a run's model
//! ([`Scenario`]) built from a flat mapping of user values.

use pyo3::prelude::*;
use pyo3::types::PyDict;
use truckmpc_core::declarations::records;
use truckmpc_core::scenario::Scenario;
use truckmpc_core::RunSettings;

use crate::convert::{dict_of, from_value, pairs_of, to_value};
use crate::errors::to_py;
use crate::powertrain::PyMapTruck;
use crate::vehicle::PyVehicle;

/// The records of the core's declaration `name` ("parameters", "key_changes", "summary" or
/// "trace"), each a dict (`truckmpc_core::declarations::records`).
#[pyfunction]
pub fn declaration<'py>(py: Python<'py>, name: &str) -> PyResult<Vec<Bound<'py, PyDict>>> {
    records(name).map_err(to_py)?.iter().map(|record| dict_of(py, record)).collect()
}

/// The value of `key` as the core reads `value`: type and range checked against its declaration.
#[pyfunction]
pub fn parameter_value<'py>(py: Python<'py>, key: &str, value: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
    let mut settings = RunSettings::default();
    settings.set(key, &to_value(value)?).map_err(to_py)?;
    from_value(py, &settings.get(key).expect("set"))
}

/// A run's settings and truck, checked against each other (arguments: `_core.pyi`).
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
        dict_of(py, &self.inner.settings().values())
    }

    /// The value of one key.
    fn get<'py>(&self, py: Python<'py>, key: &str) -> PyResult<Bound<'py, PyAny>> {
        match self.inner.settings().get(key) {
            Some(value) => from_value(py, &value),
            None => Err(pyo3::exceptions::PyKeyError::new_err(key.to_string())),
        }
    }

    /// The validated vehicle model.
    #[getter]
    fn vehicle(&self) -> PyVehicle {
        PyVehicle { inner: self.inner.vehicle().clone() }
    }

    /// Figures derived from the settings and the truck (`Scenario::derived`), the resolved keys
    /// (`k_lim`, `q_speed_below`, `q_brake`, `beta_g_per_s` or a battery-electric truck's `beta_j_per_s`) among them.
    fn derived<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        dict_of(py, &self.inner.derived().map_err(to_py)?)
    }

    /// The gear the PI gear logic (table A.3) settles in at constant speed `v_mps` [m/s].
    fn steady_gear(&self, v_mps: f64) -> PyResult<usize> {
        self.inner.steady_gear(v_mps).map_err(to_py)
    }
}

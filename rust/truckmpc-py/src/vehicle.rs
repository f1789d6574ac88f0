//! The vehicle model as Python sees it.

use std::sync::Arc;

use pyo3::prelude::*;
use pyo3::types::PyDict;
use truckmpc_core::figures;
use truckmpc_core::Vehicle;

use crate::convert::dict_of;
use crate::errors::to_py;

/// A validated truck model (thesis chapter 2, appendix B.1, or one from component data), as a run's
/// `Settings.vehicle` gives it.
#[pyclass(name = "Vehicle", module = "truckmpc._core", frozen)]
pub struct PyVehicle {
    pub inner: Arc<Vehicle>,
}

#[pymethods]
impl PyVehicle {
    /// Number of forward gears (1..=n; 0 is neutral).
    #[getter]
    fn forward_gears(&self) -> usize {
        self.inner.forward_gears()
    }

    /// Engine speed (2.9) [rpm] at speed `v_mps` in `gear` (idle speed in neutral).
    fn engine_speed_rpm(&self, v_mps: f64, gear: usize) -> PyResult<f64> {
        figures::engine_speed_rpm(&self.inner, v_mps, gear).map_err(to_py)
    }

    /// Engine torque [Nm] at road speed `v_mps` with `pedal` in `gear` (`figures::engine_torque_nm`).
    fn engine_torque_nm(&self, v_mps: f64, pedal: f64, gear: usize) -> PyResult<f64> {
        figures::engine_torque_nm(&self.inner, v_mps, pedal, gear).map_err(to_py)
    }

    /// Levels holding `v_mps` on grade `slope` [-] in `gear` (`figures::stationary`).
    fn stationary<'py>(&self, py: Python<'py>, v_mps: f64, slope: f64, gear: usize) -> PyResult<Bound<'py, PyDict>> {
        dict_of(py, &figures::stationary(&self.inner, v_mps, slope, gear).map_err(to_py)?)
    }
}

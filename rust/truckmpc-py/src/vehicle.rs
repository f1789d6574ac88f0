//! The vehicle model as Python sees it.

use std::sync::Arc;

use pyo3::prelude::*;
use pyo3::types::PyDict;
use truckmpc_core::levels;
use truckmpc_core::params::ParamSet;
use truckmpc_core::{Vehicle, VehicleParams};

use crate::errors::{bad_argument, to_py};
use crate::params::to_value;

/// A validated truck model (thesis chapter 2, appendix B.1).
///
/// Args:
///     params: mapping of vehicle keys (see `parameter_specs()`, section "vehicle") to values;
///         keys not given take the thesis's 40 t values.
#[pyclass(name = "Vehicle", module = "truckmpc._core", frozen)]
pub struct PyVehicle {
    pub inner: Arc<Vehicle>,
}

#[pymethods]
impl PyVehicle {
    #[new]
    fn new(params: &Bound<'_, PyDict>) -> PyResult<Self> {
        let mut values = VehicleParams::default();
        for (key, value) in params.iter() {
            let key: String = key.extract()?;
            if !values.set(&key, &to_value(&value)?).map_err(to_py)? {
                return Err(to_py(
                    truckmpc_core::CoreError::invalid(&key, "a vehicle parameter").got("an unknown key"),
                ));
            }
        }
        let inner = Vehicle::new(values).map_err(to_py)?;
        Ok(PyVehicle { inner: Arc::new(inner) })
    }

    /// Number of forward gears (1..=n; 0 is neutral).
    #[getter]
    fn forward_gears(&self) -> usize {
        self.inner.forward_gears()
    }

    /// Speed [m/s] below which the lowest gear turns the engine slower than idle: a stall.
    #[getter]
    fn stall_speed_mps(&self) -> f64 {
        self.inner.stall_speed_mps()
    }

    /// Engine speed (2.9) [rpm] at speed `v_mps` in `gear` (idle speed in neutral).
    fn engine_speed_rpm(&self, v_mps: f64, gear: usize) -> PyResult<f64> {
        self.check_gear(gear)?;
        Ok(self.inner.engine_speed_rpm(v_mps, gear))
    }

    /// Engine torque [Nm] at road speed `v_mps` with `pedal` ∈ [0, 1] in `gear` (1..n): the
    /// model's torque map (thesis) or the torque giving the pedal's share of the wheel torque
    /// between fuel cut and full load (a truck from component data).
    fn engine_torque_nm(&self, v_mps: f64, pedal: f64, gear: usize) -> PyResult<f64> {
        self.check_gear(gear)?;
        if gear == 0 {
            return Err(bad_argument("gear", "a forward gear (1..n)", gear));
        }
        Ok(self.inner.engine_torque_nm(self.inner.engine_speed_rpm(v_mps, gear), pedal, gear))
    }

    /// Levels holding `v_mps` on grade `slope` in `gear`: dict with `pedal`, `brake`, `feasible`,
    /// `eigenvalue_per_m` (∂(dv/ds)/∂v [1/m], tables B.1/B.2), and the engine's operating point
    /// there: `engine_speed_rpm`, `engine_torque_nm`, `fuel_rate_g_per_h`.
    fn stationary<'py>(&self, py: Python<'py>, v_mps: f64, slope: f64, gear: usize) -> PyResult<Bound<'py, PyDict>> {
        self.check_gear(gear)?;
        if !(v_mps > 0.0) {
            return Err(bad_argument("speed", "> 0", v_mps));
        }
        let s = levels::stationary(&self.inner, v_mps, slope, gear);
        let out = PyDict::new(py);
        out.set_item("pedal", s.pedal)?;
        out.set_item("brake", s.brake)?;
        out.set_item("feasible", s.feasible)?;
        out.set_item("eigenvalue_per_m", s.eigenvalue_per_m)?;
        let n_rpm = self.inner.engine_speed_rpm(v_mps, gear);
        out.set_item("engine_speed_rpm", n_rpm)?;
        out.set_item("engine_torque_nm", self.inner.engine_torque_nm(n_rpm, s.pedal, gear))?;
        out.set_item("fuel_rate_g_per_h", self.inner.fuel_rate_gps(v_mps, s.pedal, gear) * 3600.0)?;
        Ok(out)
    }
}

impl PyVehicle {
    pub fn check_gear(&self, gear: usize) -> PyResult<()> {
        check_gear(&self.inner, gear)
    }
}

/// A gear number must be neutral (0) or a forward gear of `vehicle`.
pub fn check_gear(vehicle: &Vehicle, gear: usize) -> PyResult<()> {
    if gear > vehicle.forward_gears() {
        return Err(bad_argument("gear", &format!("0 (neutral) to {}", vehicle.forward_gears()), gear));
    }
    Ok(())
}

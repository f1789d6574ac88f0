//! The simulated truck, stepped from Python (the closed loop of controllers written in Python).

use pyo3::prelude::*;
use truckmpc_core as core;

use crate::errors::bad_argument;
use crate::road::PyRoad;
use crate::vehicle::{check_gear, PyVehicle};

/// The simulated truck on a road, integrated in time with RK4 at a fine step.
///
/// State tuples are `(s_m, v_mps, t_s, fuel_g, brake_energy_j, stalled)`, integrals cumulative.
#[pyclass(name = "Plant", module = "truckmpc._core")]
pub struct PyPlant {
    inner: core::Plant,
}

type StateTuple = (f64, f64, f64, f64, f64, bool);

fn state_tuple(s: core::PlantState) -> StateTuple {
    (s.s_m, s.v_mps, s.t_s, s.fuel_g, s.brake_energy_j, s.stalled)
}

#[pymethods]
impl PyPlant {
    #[new]
    fn new(vehicle: &PyVehicle, road: &PyRoad, s_m: f64, v_mps: f64) -> PyResult<Self> {
        if !(v_mps.is_finite() && v_mps > 0.0) {
            return Err(bad_argument("start speed", "> 0 m/s", v_mps));
        }
        Ok(PyPlant { inner: core::Plant::new(vehicle.inner.clone(), road.inner.clone(), s_m, v_mps) })
    }

    /// Current state tuple.
    fn state(&self) -> StateTuple {
        state_tuple(self.inner.state())
    }

    /// One RK4 step of at most `dt_s` seconds with constant inputs, shortened so as not to pass
    /// `s_limit_m`. Returns the new state tuple.
    fn step_until(&mut self, pedal: f64, brake: f64, gear: usize, dt_s: f64, s_limit_m: f64) -> PyResult<StateTuple> {
        let u = self.control(pedal, brake, gear)?;
        self.inner.step_until(u, dt_s, s_limit_m);
        Ok(state_tuple(self.inner.state()))
    }

    /// Integrate with constant inputs in steps of at most `dt_s` until `s_target_m` (or a stall).
    /// Returns the new state tuple.
    fn advance_to(&mut self, pedal: f64, brake: f64, gear: usize, dt_s: f64, s_target_m: f64) -> PyResult<StateTuple> {
        let u = self.control(pedal, brake, gear)?;
        if !(dt_s > 0.0) {
            return Err(bad_argument("dt_s", "> 0", dt_s));
        }
        self.inner.advance_to(u, dt_s, s_target_m);
        Ok(state_tuple(self.inner.state()))
    }
}

impl PyPlant {
    fn control(&self, pedal: f64, brake: f64, gear: usize) -> PyResult<core::Control> {
        check_gear(self.inner.vehicle(), gear)?;
        Ok(core::Control { pedal: pedal.clamp(0.0, 1.0), brake: brake.clamp(0.0, 1.0), gear })
    }
}

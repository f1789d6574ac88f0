//! The look-ahead DP as Python sees it, one solve at a time.

use std::sync::Arc;

use pyo3::prelude::*;
use truckmpc_core as core;
use truckmpc_core::dp;

use crate::errors::{bad_argument, to_py};
use crate::params::PySettings;
use crate::road::PyRoad;
use crate::vehicle::check_gear;

/// What one solve decided for the first stage, and its size.
#[pyclass(name = "Solution", module = "truckmpc._core", frozen, get_all)]
pub struct PySolution {
    /// Whether an admissible path exists; the controls are meaningless otherwise.
    feasible: bool,
    /// Pedal level of the first stage [0, 1].
    pedal: f64,
    /// Brake level of the first stage [0, 1].
    brake: f64,
    /// Gear of the first stage (0 = neutral).
    gear: usize,
    /// Optimal cost of the horizon.
    cost: f64,
    /// States of the search space.
    states: usize,
    /// Transitions evaluated.
    transitions: usize,
}

/// The look-ahead DP of chapter 5 on a road, with its reusable workspace.
///
/// Args:
///     settings: the run's settings; the MPC and cruise sections and the vehicle are used.
///     road: the road whose slopes it looks ahead at.
#[pyclass(name = "MpcSolver", module = "truckmpc._core")]
pub struct PyMpcSolver {
    vehicle: Arc<core::Vehicle>,
    road: Arc<core::Road>,
    solver: dp::Solver,
    slopes: Vec<f64>,
}

#[pymethods]
impl PyMpcSolver {
    #[new]
    fn new(settings: &PySettings, road: &PyRoad) -> PyResult<Self> {
        let params = dp::DpSettings::new(&settings.inner.mpc, &settings.inner.cruise).map_err(to_py)?;
        Ok(PyMpcSolver {
            vehicle: settings.vehicle.clone(),
            road: road.inner.clone(),
            solver: dp::Solver::new(params),
            slopes: Vec::new(),
        })
    }

    /// Speed [m/s] one stage ahead of `s_m` under the inputs being applied, by the controller's model.
    fn predict_speed(&self, s_m: f64, v_mps: f64, pedal: f64, brake: f64, gear: usize) -> PyResult<f64> {
        check_gear(&self.vehicle, gear)?;
        let u = core::Control { pedal, brake, gear };
        Ok(dp::horizon::predict_speed(&self.vehicle, &self.road, s_m, v_mps, u, self.solver.params().stage_m))
    }

    /// Solve the horizon starting at `s_m` from speed `v_mps` [m/s] in `gear` with
    /// `stages_since_shift` stages driven since the last shift. Releases the GIL.
    fn solve(
        &mut self,
        py: Python<'_>,
        s_m: f64,
        v_mps: f64,
        gear: usize,
        stages_since_shift: u32,
    ) -> PyResult<PySolution> {
        check_gear(&self.vehicle, gear)?;
        if !(v_mps.is_finite() && v_mps > 0.0) {
            return Err(bad_argument("speed", "> 0 m/s", v_mps));
        }
        let start = dp::InitialState { v_mps, gear, stages_since_shift };
        let (solver, slopes, vehicle, road) = (&mut self.solver, &mut self.slopes, &self.vehicle, &self.road);
        let s = py.detach(|| dp::horizon::solve_at(solver, vehicle, road, s_m, start, slopes));
        Ok(PySolution {
            feasible: s.feasible,
            pedal: s.pedal,
            brake: s.brake,
            gear: s.gear,
            cost: s.cost,
            states: s.states,
            transitions: s.transitions,
        })
    }
}

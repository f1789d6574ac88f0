//! Binding of the Rust closed loop: `run` drives a built-in controller over a road with the GIL
//! released, `run_python` a controller written in Python; both return the run's summary and trace.
//! `controllers` lists the built-in controllers.

use numpy::PyReadonlyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use truckmpc_core::control::{Controller, Decision};
use truckmpc_core::scenario::CONTROLLERS;
use truckmpc_core::sim::RunOutput;
use truckmpc_core::{Control, PlantState, Road};

use crate::convert::dict_of;
use crate::errors::to_py;
use crate::outputs::{summary_dict, trace_dict};
use crate::params::PySettings;
use crate::road::PyRoad;
use crate::signals;

/// The outcome of `run`: the summary figures (dict, keys as `truckmpc.sim.simulate` documents, plus
/// the DP controllers' `settings`) and the trace (dict of 1-D numpy arrays, float64 but `gear` int64).
type Output<'py> = (Bound<'py, PyDict>, Bound<'py, PyDict>);

/// Drive `road` with the built-in `controller`, the GIL released (arguments: `_core.pyi`).
#[pyfunction]
#[pyo3(signature = (settings, road, altitude_m, controller, controller_road=None))]
fn run<'py>(
    py: Python<'py>,
    settings: &PySettings,
    road: &PyRoad,
    altitude_m: PyReadonlyArray1<'_, f64>,
    controller: &str,
    controller_road: Option<&PyRoad>,
) -> PyResult<Output<'py>> {
    let scenario = &settings.inner;
    let mut ctrl = scenario.controller(controller).map_err(to_py)?;
    let altitude_m = altitude_m.as_array().to_vec();
    let map = controller_road.map(|r| r.inner.as_ref());
    let drive = || scenario.run(&road.inner, map, &altitude_m, ctrl.as_mut());
    let output = signals::watching(|| py.detach(drive))?.map_err(to_py)?;
    output_of(py, output)
}

/// The built-in controllers: (name, what it is, whether it solves the DP), in the order outputs
/// list them.
#[pyfunction]
fn controllers() -> Vec<(&'static str, &'static str, bool)> {
    CONTROLLERS.iter().map(|k| (k.name, k.doc, k.solves_dp)).collect()
}

fn output_of(py: Python<'_>, output: RunOutput) -> PyResult<Output<'_>> {
    let summary = summary_dict(py, &output.summary)?;
    if let Some(settings) = &output.settings {
        summary.set_item("settings", dict_of(py, settings)?)?;
    }
    Ok((summary, trace_dict(py, output.trace)?))
}

/// Add `run`, `run_python` and `controllers` to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(run, m)?)?;
    m.add_function(wrap_pyfunction!(run_python, m)?)?;
    m.add_function(wrap_pyfunction!(controllers, m)?)?;
    Ok(())
}

/// A controller written in Python (the `truckmpc.controller.Controller` protocol) driven by the
/// Rust closed loop, each call with the GIL held. The first exception it raises stops the loop and
/// is re-raised by `run_python`.
struct PyController {
    obj: Py<PyAny>,
    profile: Py<PyAny>,
    state_type: Py<PyAny>,
    error: Option<PyErr>,
}

impl PyController {
    fn state<'py>(&self, py: Python<'py>, s: &PlantState) -> PyResult<Bound<'py, PyAny>> {
        self.state_type.bind(py).call1((s.s_m, s.v_mps, s.t_s, s.fuel_g, s.brake_energy_j, s.stalled))
    }
}

impl Controller for PyController {
    fn name(&self) -> &'static str {
        "python"
    }

    fn start(&mut self, _road: &Road, s: &PlantState) {
        let started = Python::attach(|py| self.obj.call_method1(py, "start", (&self.profile, self.state(py, s)?)));
        self.error = started.err();
    }

    fn decide(&mut self, _road: &Road, s: &PlantState) -> Decision {
        let decided = Python::attach(|py| -> PyResult<Decision> {
            let answer = self.obj.call_method1(py, "decide", (self.state(py, s)?,))?;
            let ((pedal, brake, gear), until_m) = answer.extract(py)?;
            Ok(Decision { control: Control { pedal, brake, gear }, until_m })
        });
        decided.unwrap_or_else(|err| {
            self.error = Some(err);
            // Never applied: the loop stops on `aborted` before applying a decision.
            Decision { control: Control { pedal: 0.0, brake: 0.0, gear: 1 }, until_m: None }
        })
    }

    fn aborted(&self) -> bool {
        self.error.is_some()
    }
}

/// Drive `road` with a controller written in Python, in the same closed loop (arguments: `_core.pyi`).
#[pyfunction]
fn run_python<'py>(
    py: Python<'py>,
    settings: &PySettings,
    road: &PyRoad,
    altitude_m: PyReadonlyArray1<'_, f64>,
    controller: Py<PyAny>,
    profile: Py<PyAny>,
    state_type: Py<PyAny>,
) -> PyResult<Output<'py>> {
    let mut ctrl = PyController { obj: controller, profile, state_type, error: None };
    let altitude_m = altitude_m.as_array().to_vec();
    let output = settings.inner.run(&road.inner, None, &altitude_m, &mut ctrl).map_err(to_py)?;
    ctrl.error.map_or_else(|| output_of(py, output), Err)
}

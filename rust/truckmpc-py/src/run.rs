//! Binding of the Rust closed loop: `run` drives a built-in controller over a road with the GIL
//! released, `run_python` a controller written in Python; both return a `RunOutput`.
//! `steady_gear` is the PI gear logic's settled gear.

use numpy::PyReadonlyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use truckmpc_core::control::{
    Controller, Decision, GearLogic, PccController, PiController, RecedingController, VectoDriver,
};
use truckmpc_core::dp::DpSettings;
use truckmpc_core::sim;
use truckmpc_core::{Control, PlantState, Road};

use crate::errors::{bad_argument, to_py};
use crate::outputs::{summary_dict, trace_dict};
use crate::params::PySettings;
use crate::road::PyRoad;
use crate::signals::{self, Interruptible};

/// The outcome of `run`: the controller's name, the summary figures (dict, keys as
/// `truckmpc.sim.simulate` documents, plus the solver's for the MPC) and the trace (dict of 1-D
/// numpy arrays, float64 but `gear` int64).
#[pyclass(name = "RunOutput", module = "truckmpc._core", frozen)]
struct PyRunOutput {
    #[pyo3(get)]
    controller: String,
    #[pyo3(get)]
    summary: Py<PyDict>,
    #[pyo3(get)]
    trace: Py<PyDict>,
}

/// Drive `road` with the built-in controller `controller` ("pi", "mpc" or "optimal") from its start to its end
/// (or a stall), the closed loop in Rust with the GIL released.
///
/// Args:
///     settings: the run's settings (vehicle, cruise band, PI, MPC, simulation).
///     road: the road; `altitude_m` gives the trace's altitude at each of its profile points [m].
///     controller: "pi", "vecto_cc" (VECTO's cruise driver), "pcc", "mpc" or "optimal" (the whole-road optimum).
///     controller_road: the road the controller plans on, if not `road` (the plant drives `road`).
///
/// Returns:
///     RunOutput.
#[pyfunction]
#[pyo3(signature = (settings, road, altitude_m, controller, controller_road=None))]
fn run(
    py: Python<'_>,
    settings: &PySettings,
    road: &PyRoad,
    altitude_m: PyReadonlyArray1<'_, f64>,
    controller: &str,
    controller_road: Option<&PyRoad>,
) -> PyResult<PyRunOutput> {
    let s = &settings.inner;
    // The controllers model the truck they are told of; the plant is the truck.
    let vehicle = &settings.controller_vehicle;
    let mut ctrl: Box<dyn Controller + Send> = match controller {
        "pi" => Box::new(PiController::new(vehicle.clone(), &s.pi, &s.cruise).map_err(to_py)?),
        "mpc" | "optimal" => {
            let gears = GearLogic::new(vehicle, &s.pi).map_err(to_py)?;
            let dp = DpSettings::new(&s.mpc, &s.cruise).map_err(to_py)?;
            if controller == "optimal" {
                Box::new(RecedingController::whole_road(vehicle.clone(), dp, gears))
            } else {
                Box::new(RecedingController::new(vehicle.clone(), dp, gears))
            }
        }
        "pcc" => {
            Box::new(PccController::new(vehicle.clone(), &s.pi, &s.cruise, &s.pcc, s.sim.plant_dt_s).map_err(to_py)?)
        }
        "vecto_cc" => {
            Box::new(VectoDriver::new(vehicle.clone(), &s.pi, &s.cruise, &s.pcc, s.sim.plant_dt_s).map_err(to_py)?)
        }
        other => {
            let expected = "'pi', 'vecto_cc', 'pcc', 'mpc' or 'optimal'";
            return Err(bad_argument("controller", expected, format!("'{other}'")));
        }
    };
    let altitude_m = altitude_m.as_array().to_vec();
    let (road, start_kmh) = (&road.inner, s.start_speed_kmh(&road.inner));
    let map = controller_road.map_or(road, |r| &r.inner);
    let mut watched = Interruptible::new(ctrl.as_mut());
    let plant = &settings.vehicle;
    let run = || sim::run_on_map(plant, road, map, &altitude_m, &mut watched, &s.sim, start_kmh);
    let output = signals::watching(|| py.detach(run))?.map_err(to_py)?;
    Ok(PyRunOutput {
        controller: output.controller.to_string(),
        summary: summary_dict(py, &output.summary)?.unbind(),
        trace: trace_dict(py, output.trace)?.unbind(),
    })
}

/// The gear the PI gear logic (table A.3) settles in at constant speed `v_mps` [m/s].
#[pyfunction]
fn steady_gear(settings: &PySettings, v_mps: f64) -> PyResult<usize> {
    let logic = GearLogic::new(&settings.vehicle, &settings.inner.pi).map_err(to_py)?;
    Ok(logic.steady_gear(v_mps))
}

/// Add `run`, `run_python`, `steady_gear` and `RunOutput` to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyRunOutput>()?;
    m.add_function(wrap_pyfunction!(run, m)?)?;
    m.add_function(wrap_pyfunction!(run_python, m)?)?;
    m.add_function(wrap_pyfunction!(steady_gear, m)?)?;
    Ok(())
}

/// A controller written in Python (the `truckmpc.controller.Controller` protocol) driven by the
/// Rust closed loop: each decision calls its `decide(state)` with the GIL held. The first exception
/// it raises stops the loop and is re-raised by `run_python`.
struct PyController {
    obj: Py<PyAny>,
    profile: Py<PyAny>,
    state_type: Py<PyAny>,
    error: Option<PyErr>,
}

impl PyController {
    fn state(&self, py: Python<'_>, s: &PlantState) -> PyResult<Py<PyAny>> {
        let args = (s.s_m, s.v_mps, s.t_s, s.fuel_g, s.brake_energy_j, s.stalled);
        Ok(self.state_type.bind(py).call1(args)?.unbind())
    }

    fn call_decide(&self, py: Python<'_>, s: &PlantState) -> PyResult<Decision> {
        let answer = self.obj.bind(py).call_method1("decide", (self.state(py, s)?,))?;
        let (control, until_m): (Bound<'_, PyAny>, Option<f64>) = answer.extract()?;
        let (pedal, brake, gear): (f64, f64, usize) = control.extract()?;
        Ok(Decision { control: Control { pedal, brake, gear }, until_m })
    }
}

impl Controller for PyController {
    fn name(&self) -> &'static str {
        "python"
    }

    fn start(&mut self, _road: &Road, s: &PlantState) {
        let result = Python::attach(|py| -> PyResult<()> {
            self.obj.bind(py).call_method1("start", (self.profile.bind(py), self.state(py, s)?))?;
            Ok(())
        });
        self.error = result.err();
    }

    fn decide(&mut self, _road: &Road, s: &PlantState) -> Decision {
        let hold = Decision { control: Control { pedal: 0.0, brake: 0.0, gear: 1 }, until_m: None };
        if self.error.is_some() {
            return hold;
        }
        match Python::attach(|py| self.call_decide(py, s)) {
            Ok(decision) => decision,
            Err(err) => {
                self.error = Some(err);
                hold
            }
        }
    }

    fn aborted(&self) -> bool {
        self.error.is_some()
    }
}

/// Drive `road` with `controller`, an object of the `truckmpc.controller.Controller` protocol
/// written in Python, in the same Rust closed loop as the built-in controllers.
///
/// Args:
///     settings: the run's settings (vehicle, cruise band, simulation).
///     road: the road; `altitude_m` gives the trace's altitude at each of its profile points [m].
///     controller: the Python controller; `start(profile, state)` and `decide(state)` are called.
///     profile: the `RoadProfile` passed to `controller.start`.
///     state_type: the class of the states passed (`truckmpc.controller.PlantState`).
#[pyfunction]
fn run_python(
    py: Python<'_>,
    settings: &PySettings,
    road: &PyRoad,
    altitude_m: PyReadonlyArray1<'_, f64>,
    controller: Py<PyAny>,
    profile: Py<PyAny>,
    state_type: Py<PyAny>,
) -> PyResult<PyRunOutput> {
    let mut ctrl = PyController { obj: controller, profile, state_type, error: None };
    let s = &settings.inner;
    let altitude_m = altitude_m.as_array().to_vec();
    let output =
        sim::run(&settings.vehicle, &road.inner, &altitude_m, &mut ctrl, &s.sim, s.start_speed_kmh(&road.inner))
            .map_err(to_py)?;
    if let Some(err) = ctrl.error {
        return Err(err);
    }
    Ok(PyRunOutput {
        controller: output.controller.to_string(),
        summary: summary_dict(py, &output.summary)?.unbind(),
        trace: trace_dict(py, output.trace)?.unbind(),
    })
}

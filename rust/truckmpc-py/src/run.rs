//! Binding of the Rust closed loop: `run` drives a built-in controller over a road with the GIL
//! released and returns a `RunOutput`; `steady_gear` is the PI gear logic's settled gear.

use numpy::{IntoPyArray, PyReadonlyArray1};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use truckmpc_core::control::{Controller, GearLogic, PiController, PiParams, RecedingController, SimParams};
use truckmpc_core::sim::{self, RunSummary, Trace};

use super::{mpc_params_from_dict, to_py, PyRoad, PyVehicle};

const PI_NAMES: [&str; 10] = [
    "v_ref_kmh",
    "v_inc_kmh",
    "pedal_kp",
    "pedal_ki",
    "pedal_integrator_limit",
    "brake_kp",
    "brake_ki",
    "brake_integrator_limit",
    "gear_down_rpm",
    "gear_up_rpm",
];

const SIM_NAMES: [&str; 3] = ["plant_dt_s", "trace_step_m", "start_speed_kmh"];

/// Every key of `dict` is one of `names` and every name is there.
fn check_keys(dict: &Bound<'_, PyDict>, names: &[&str], what: &str) -> PyResult<()> {
    for key in dict.keys() {
        let key: String = key.extract()?;
        if !names.contains(&key.as_str()) {
            return Err(PyValueError::new_err(format!("{key}: unknown {what} parameter")));
        }
    }
    match names.iter().find(|name| !dict.contains(**name).unwrap_or(false)) {
        Some(name) => Err(PyValueError::new_err(format!("{name}: missing {what} parameter"))),
        None => Ok(()),
    }
}

fn item<'py, T: FromPyObjectOwned<'py>>(dict: &Bound<'py, PyDict>, key: &str, expected: &str) -> PyResult<T> {
    let value = dict.get_item(key)?.ok_or_else(|| PyValueError::new_err(format!("{key}: missing")))?;
    value.extract::<T>().map_err(|_| PyValueError::new_err(format!("{key}: expected {expected}")))
}

fn pi_params_from_dict(dict: &Bound<'_, PyDict>) -> PyResult<PiParams> {
    check_keys(dict, &PI_NAMES, "PI")?;
    let number = |key: &str| item::<f64>(dict, key, "a number");
    let thresholds = |key: &str| item::<Vec<Option<f64>>>(dict, key, "a list of numbers or None");
    Ok(PiParams {
        v_ref_kmh: number("v_ref_kmh")?,
        v_inc_kmh: number("v_inc_kmh")?,
        pedal_kp: number("pedal_kp")?,
        pedal_ki: number("pedal_ki")?,
        pedal_integrator_limit: number("pedal_integrator_limit")?,
        brake_kp: number("brake_kp")?,
        brake_ki: number("brake_ki")?,
        brake_integrator_limit: number("brake_integrator_limit")?,
        gear_down_rpm: thresholds("gear_down_rpm")?,
        gear_up_rpm: thresholds("gear_up_rpm")?,
    })
}

fn sim_params_from_dict(dict: &Bound<'_, PyDict>) -> PyResult<SimParams> {
    check_keys(dict, &SIM_NAMES, "simulation")?;
    Ok(SimParams {
        plant_dt_s: item(dict, "plant_dt_s", "a number")?,
        trace_step_m: item(dict, "trace_step_m", "a number")?,
        start_speed_kmh: item(dict, "start_speed_kmh", "a number or None")?,
    })
}

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

fn summary_dict<'py>(py: Python<'py>, s: &RunSummary) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    out.set_item("distance_m", s.distance_m)?;
    out.set_item("fuel_kg", s.fuel_kg)?;
    out.set_item("fuel_kg_per_100km", s.fuel_kg_per_100km)?;
    out.set_item("time_s", s.time_s)?;
    out.set_item("mean_speed_kmh", s.mean_speed_kmh)?;
    out.set_item("start_speed_kmh", s.start_speed_kmh)?;
    out.set_item("end_speed_kmh", s.end_speed_kmh)?;
    out.set_item("gear_shifts", s.gear_shifts)?;
    out.set_item("brake_energy_kj", s.brake_energy_kj)?;
    out.set_item("neutral_distance_m", s.neutral_distance_m)?;
    out.set_item("compute_time_s", s.compute_time_s)?;
    out.set_item("realtime_ratio", s.realtime_ratio)?;
    out.set_item("stalled", s.stalled)?;
    out.set_item("stall_distance_m", s.stall_distance_m)?;
    out.set_item("message", s.message.as_deref())?;
    out.set_item("plant_dt_s", s.plant_dt_s)?;
    if let Some(solver) = &s.solver {
        out.set_item("solves", solver.solves)?;
        out.set_item("infeasible_solves", solver.infeasible_solves)?;
        out.set_item("solve_ms_mean", solver.solve_ms_mean())?;
        out.set_item("solve_ms_max", solver.solve_ms_max())?;
        out.set_item("states_per_solve", solver.states_per_solve())?;
        out.set_item("transitions_per_solve", solver.transitions_per_solve())?;
    }
    Ok(out)
}

fn trace_dict(py: Python<'_>, t: Trace) -> PyResult<Bound<'_, PyDict>> {
    let out = PyDict::new(py);
    out.set_item("distance_m", t.distance_m.into_pyarray(py))?;
    out.set_item("time_s", t.time_s.into_pyarray(py))?;
    out.set_item("speed_kmh", t.speed_kmh.into_pyarray(py))?;
    out.set_item("gear", t.gear.into_pyarray(py))?;
    out.set_item("pedal", t.pedal.into_pyarray(py))?;
    out.set_item("brake", t.brake.into_pyarray(py))?;
    out.set_item("engine_speed_rpm", t.engine_speed_rpm.into_pyarray(py))?;
    out.set_item("slope", t.slope.into_pyarray(py))?;
    out.set_item("altitude_m", t.altitude_m.into_pyarray(py))?;
    out.set_item("fuel_g", t.fuel_g.into_pyarray(py))?;
    out.set_item("brake_energy_kj", t.brake_energy_kj.into_pyarray(py))?;
    Ok(out)
}

/// Drive `road` with the built-in controller `controller` ("pi" or "mpc") from its start to its end
/// (or a stall), the closed loop in Rust with the GIL released.
///
/// Args:
///     vehicle: the truck model.
///     road: the road; `altitude_m` gives the trace's altitude at each of its profile points [m].
///     controller: "pi" or "mpc".
///     pi: dict of PI parameters (table A.3/A.4 keys; the MPC takes its starting gear from the
///         gear thresholds, and both start at `v_ref_kmh` unless `sim` says otherwise).
///     sim: dict with `plant_dt_s` [s], `trace_step_m` [m], `start_speed_kmh` [km/h] or None.
///     mpc: dict of MPC parameters with k_lim resolved (required for "mpc").
///
/// Returns:
///     RunOutput.
#[pyfunction]
#[pyo3(signature = (vehicle, road, altitude_m, controller, pi, sim, mpc=None))]
fn run(
    py: Python<'_>,
    vehicle: &PyVehicle,
    road: &PyRoad,
    altitude_m: PyReadonlyArray1<'_, f64>,
    controller: &str,
    pi: &Bound<'_, PyDict>,
    sim: &Bound<'_, PyDict>,
    mpc: Option<&Bound<'_, PyDict>>,
) -> PyResult<PyRunOutput> {
    let pi = pi_params_from_dict(pi)?;
    let sim = sim_params_from_dict(sim)?;
    let mut ctrl: Box<dyn Controller + Send> = match (controller, mpc) {
        ("pi", _) => Box::new(PiController::new(vehicle.inner.clone(), &pi).map_err(to_py)?),
        ("mpc", Some(mpc)) => {
            let gears = GearLogic::new(&vehicle.inner, &pi.gear_down_rpm, &pi.gear_up_rpm).map_err(to_py)?;
            Box::new(RecedingController::new(vehicle.inner.clone(), mpc_params_from_dict(mpc)?, gears))
        }
        ("mpc", None) => return Err(PyValueError::new_err("mpc: the MPC controller needs its parameters")),
        (other, _) => return Err(PyValueError::new_err(format!("controller: expected 'pi' or 'mpc', got '{other}'"))),
    };
    let altitude_m = altitude_m.as_array().to_vec();
    let (vehicle, road) = (&vehicle.inner, &road.inner);
    let output =
        py.detach(|| sim::run(vehicle, road, &altitude_m, ctrl.as_mut(), &sim, pi.v_ref_kmh)).map_err(to_py)?;
    Ok(PyRunOutput {
        controller: output.controller.to_string(),
        summary: summary_dict(py, &output.summary)?.unbind(),
        trace: trace_dict(py, output.trace)?.unbind(),
    })
}

/// The gear the PI gear logic (table A.3) settles in at constant speed `v_mps` [m/s], given the
/// thresholds [rpm] per forward gear (None where there is no lower or higher gear).
#[pyfunction]
fn steady_gear(
    vehicle: &PyVehicle,
    v_mps: f64,
    gear_down_rpm: Vec<Option<f64>>,
    gear_up_rpm: Vec<Option<f64>>,
) -> PyResult<usize> {
    let logic = GearLogic::new(&vehicle.inner, &gear_down_rpm, &gear_up_rpm).map_err(to_py)?;
    Ok(logic.steady_gear(v_mps))
}

/// Add `run`, `steady_gear` and `RunOutput` to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyRunOutput>()?;
    m.add_function(wrap_pyfunction!(run, m)?)?;
    m.add_function(wrap_pyfunction!(steady_gear, m)?)?;
    Ok(())
}

//! Thin pyo3 binding of truckmpc-core, imported in Python as `truckmpc._core`.
//! No physics lives here: each method forwards to the core. Core errors become `ValueError`.

use std::sync::Arc;

use numpy::PyReadonlyArray1;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use truckmpc_core as core;
use truckmpc_core::dp;
use truckmpc_core::levels;

mod run;

/// Turn a core error into a Python `ValueError` carrying its one-line message.
fn to_py(err: core::CoreError) -> PyErr {
    PyValueError::new_err(err.to_string())
}

fn get_f64(dict: &Bound<'_, PyDict>, key: &str, default: f64) -> PyResult<f64> {
    match dict.get_item(key)? {
        Some(v) => v.extract::<f64>().map_err(|_| PyValueError::new_err(format!("{key}: expected a number"))),
        None => Ok(default),
    }
}

fn get_vec(dict: &Bound<'_, PyDict>, key: &str, default: &[f64]) -> PyResult<Vec<f64>> {
    match dict.get_item(key)? {
        Some(v) => {
            v.extract::<Vec<f64>>().map_err(|_| PyValueError::new_err(format!("{key}: expected a list of numbers")))
        }
        None => Ok(default.to_vec()),
    }
}

/// One of a few named values; the error lists them.
fn get_choice<T: Copy>(dict: &Bound<'_, PyDict>, key: &str, choices: &[(&str, T)], default: T) -> PyResult<T> {
    let Some(value) = dict.get_item(key)? else { return Ok(default) };
    let name = value.extract::<String>().ok();
    choices.iter().find(|(n, _)| Some(*n) == name.as_deref()).map(|&(_, v)| v).ok_or_else(|| {
        let names: Vec<String> = choices.iter().map(|(n, _)| format!("'{n}'")).collect();
        PyValueError::new_err(format!("{key}: expected {}", names.join(" or ")))
    })
}

/// Build core parameters from a dict whose keys are the field names of `VehicleParams`;
/// missing keys take the thesis's 40 t defaults, unknown keys are an error.
fn params_from_dict(dict: &Bound<'_, PyDict>) -> PyResult<core::VehicleParams> {
    let d = core::VehicleParams::default();
    let p = core::VehicleParams {
        mass_kg: get_f64(dict, "mass_kg", d.mass_kg)?,
        engine_inertia_kgm2: get_f64(dict, "engine_inertia_kgm2", d.engine_inertia_kgm2)?,
        cylinders: get_f64(dict, "cylinders", d.cylinders)?,
        revolutions_per_stroke: get_f64(dict, "revolutions_per_stroke", d.revolutions_per_stroke)?,
        torque_map_a_nm_per_rpm: get_f64(dict, "torque_map_a_nm_per_rpm", d.torque_map_a_nm_per_rpm)?,
        torque_map_b_nm_stroke_per_mg: get_f64(dict, "torque_map_b_nm_stroke_per_mg", d.torque_map_b_nm_stroke_per_mg)?,
        torque_map_c_nm: get_f64(dict, "torque_map_c_nm", d.torque_map_c_nm)?,
        fueling_max_a_mg_per_rpm2: get_f64(dict, "fueling_max_a_mg_per_rpm2", d.fueling_max_a_mg_per_rpm2)?,
        fueling_max_b_mg_per_rpm: get_f64(dict, "fueling_max_b_mg_per_rpm", d.fueling_max_b_mg_per_rpm)?,
        fueling_max_c_mg: get_f64(dict, "fueling_max_c_mg", d.fueling_max_c_mg)?,
        drag_torque_a_nm_per_rpm: get_f64(dict, "drag_torque_a_nm_per_rpm", d.drag_torque_a_nm_per_rpm)?,
        drag_torque_b_nm: get_f64(dict, "drag_torque_b_nm", d.drag_torque_b_nm)?,
        idle_speed_rpm: get_f64(dict, "idle_speed_rpm", d.idle_speed_rpm)?,
        idle_fueling_mg_per_stroke: get_f64(dict, "idle_fueling_mg_per_stroke", d.idle_fueling_mg_per_stroke)?,
        final_drive_ratio: get_f64(dict, "final_drive_ratio", d.final_drive_ratio)?,
        final_drive_efficiency: get_f64(dict, "final_drive_efficiency", d.final_drive_efficiency)?,
        wheel_inertia_kgm2: get_f64(dict, "wheel_inertia_kgm2", d.wheel_inertia_kgm2)?,
        rolling_resistance: get_f64(dict, "rolling_resistance", d.rolling_resistance)?,
        gravity_mps2: get_f64(dict, "gravity_mps2", d.gravity_mps2)?,
        air_drag_coefficient: get_f64(dict, "air_drag_coefficient", d.air_drag_coefficient)?,
        frontal_area_m2: get_f64(dict, "frontal_area_m2", d.frontal_area_m2)?,
        air_density_kgpm3: get_f64(dict, "air_density_kgpm3", d.air_density_kgpm3)?,
        wheel_radius_m: get_f64(dict, "wheel_radius_m", d.wheel_radius_m)?,
        brake_torque_max_nm: get_f64(dict, "brake_torque_max_nm", d.brake_torque_max_nm)?,
        gear_ratios: get_vec(dict, "gear_ratios", &d.gear_ratios)?,
        gear_efficiencies: get_vec(dict, "gear_efficiencies", &d.gear_efficiencies)?,
    };
    Ok(p)
}

/// The vehicle parameter names the core accepts, in declaration order.
const PARAM_NAMES: [&str; 26] = [
    "mass_kg",
    "engine_inertia_kgm2",
    "cylinders",
    "revolutions_per_stroke",
    "torque_map_a_nm_per_rpm",
    "torque_map_b_nm_stroke_per_mg",
    "torque_map_c_nm",
    "fueling_max_a_mg_per_rpm2",
    "fueling_max_b_mg_per_rpm",
    "fueling_max_c_mg",
    "drag_torque_a_nm_per_rpm",
    "drag_torque_b_nm",
    "idle_speed_rpm",
    "idle_fueling_mg_per_stroke",
    "final_drive_ratio",
    "final_drive_efficiency",
    "wheel_inertia_kgm2",
    "rolling_resistance",
    "gravity_mps2",
    "air_drag_coefficient",
    "frontal_area_m2",
    "air_density_kgpm3",
    "wheel_radius_m",
    "brake_torque_max_nm",
    "gear_ratios",
    "gear_efficiencies",
];

/// A validated truck model (thesis chapter 2, appendix B.1).
///
/// Args:
///     params: dict of vehicle parameters named with their units (see `parameter_names()`);
///         missing keys take the thesis's 40 t values.
#[pyclass(name = "Vehicle", module = "truckmpc._core", frozen)]
struct PyVehicle {
    inner: Arc<core::Vehicle>,
}

#[pymethods]
impl PyVehicle {
    #[new]
    fn new(params: &Bound<'_, PyDict>) -> PyResult<Self> {
        for key in params.keys() {
            let key: String = key.extract()?;
            if !PARAM_NAMES.contains(&key.as_str()) {
                return Err(PyValueError::new_err(format!("{key}: unknown vehicle parameter")));
            }
        }
        let inner = core::Vehicle::new(params_from_dict(params)?).map_err(to_py)?;
        Ok(PyVehicle { inner: Arc::new(inner) })
    }

    /// Names of the vehicle parameters, in declaration order.
    #[staticmethod]
    fn parameter_names() -> Vec<&'static str> {
        PARAM_NAMES.to_vec()
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

    /// Levels holding `v_mps` on grade `slope` in `gear`: dict with `pedal`, `brake`, `feasible`,
    /// `eigenvalue_per_m` (∂(dv/ds)/∂v [1/m], tables B.1/B.2).
    fn stationary<'py>(&self, py: Python<'py>, v_mps: f64, slope: f64, gear: usize) -> PyResult<Bound<'py, PyDict>> {
        self.check_gear(gear)?;
        if !(v_mps > 0.0) {
            return Err(PyValueError::new_err(format!("speed: expected > 0, got {v_mps}")));
        }
        let s = levels::stationary(&self.inner, v_mps, slope, gear);
        let out = PyDict::new(py);
        out.set_item("pedal", s.pedal)?;
        out.set_item("brake", s.brake)?;
        out.set_item("feasible", s.feasible)?;
        out.set_item("eigenvalue_per_m", s.eigenvalue_per_m)?;
        Ok(out)
    }
}

impl PyVehicle {
    fn check_gear(&self, gear: usize) -> PyResult<()> {
        if gear > self.inner.forward_gears() {
            return Err(PyValueError::new_err(format!(
                "gear: expected 0 (neutral) to {}, got {gear}",
                self.inner.forward_gears()
            )));
        }
        Ok(())
    }
}

/// A road profile: points `distance_m` [m] (strictly increasing) and the grade of each segment
/// between consecutive points (`len(slope) == len(distance_m) - 1`). Flat beyond its end.
#[pyclass(name = "Road", module = "truckmpc._core", frozen)]
struct PyRoad {
    inner: Arc<core::Road>,
}

#[pymethods]
impl PyRoad {
    #[new]
    fn new(distance_m: PyReadonlyArray1<'_, f64>, slope: PyReadonlyArray1<'_, f64>) -> PyResult<Self> {
        let road = core::Road::new(distance_m.as_array().to_vec(), slope.as_array().to_vec()).map_err(to_py)?;
        Ok(PyRoad { inner: Arc::new(road) })
    }

    /// Distance of the first point [m].
    #[getter]
    fn start_m(&self) -> f64 {
        self.inner.start_m()
    }

    /// Distance of the last point [m].
    #[getter]
    fn end_m(&self) -> f64 {
        self.inner.end_m()
    }

    /// Altitude at `s_m` relative to the first point [m].
    fn altitude_at(&self, s_m: f64) -> f64 {
        self.inner.altitude_at(s_m)
    }

    /// Mean grade over [s0_m, s1_m] [-].
    fn mean_slope(&self, s0_m: f64, s1_m: f64) -> f64 {
        self.inner.mean_slope(s0_m, s1_m)
    }
}

/// The simulated truck on a road, integrated in time with RK4 at a fine step.
///
/// State tuples are `(s_m, v_mps, t_s, fuel_g, brake_energy_j, stalled)`, integrals cumulative.
#[pyclass(name = "Plant", module = "truckmpc._core")]
struct PyPlant {
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
            return Err(PyValueError::new_err(format!("start speed: expected > 0 m/s, got {v_mps}")));
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
            return Err(PyValueError::new_err(format!("dt_s: expected > 0, got {dt_s}")));
        }
        self.inner.advance_to(u, dt_s, s_target_m);
        Ok(state_tuple(self.inner.state()))
    }
}

impl PyPlant {
    fn control(&self, pedal: f64, brake: f64, gear: usize) -> PyResult<core::Control> {
        if gear > self.inner.vehicle().forward_gears() {
            return Err(PyValueError::new_err(format!(
                "gear: expected 0..={}, got {gear}",
                self.inner.vehicle().forward_gears()
            )));
        }
        Ok(core::Control { pedal: pedal.clamp(0.0, 1.0), brake: brake.clamp(0.0, 1.0), gear })
    }
}

/// The MPC parameter names the core accepts (table 5.2 / 6.1 / 6.2).
const MPC_NAMES: [&str; 18] = [
    "stage_m",
    "horizon_m",
    "delta_kmh",
    "epsilon",
    "v_ref_kmh",
    "v_inc_kmh",
    "v_dec_kmh",
    "k_lim",
    "n_min_rpm",
    "n_max_rpm",
    "allow_neutral",
    "q_fuel",
    "q_speed_below",
    "q_speed_change",
    "q_gear_shift",
    "q_brake",
    "neutral_rule",
    "grid",
];

fn mpc_params_from_dict(dict: &Bound<'_, PyDict>) -> PyResult<dp::MpcParams> {
    for key in dict.keys() {
        let key: String = key.extract()?;
        if !MPC_NAMES.contains(&key.as_str()) {
            return Err(PyValueError::new_err(format!("{key}: unknown MPC parameter")));
        }
    }
    let d = dp::MpcParams::default();
    let k_lim = match dict.get_item("k_lim")? {
        Some(v) => v.extract::<u32>().map_err(|_| PyValueError::new_err("k_lim: expected a whole number >= 0"))?,
        None => d.k_lim,
    };
    let allow_neutral = match dict.get_item("allow_neutral")? {
        Some(v) => v.extract::<bool>().map_err(|_| PyValueError::new_err("allow_neutral: expected true or false"))?,
        None => d.allow_neutral,
    };
    let neutral_rule = get_choice(
        dict,
        "neutral_rule",
        &[("nearest", dp::NeutralRule::Nearest), ("interpolate", dp::NeutralRule::Interpolate)],
        d.neutral_rule,
    )?;
    let grid =
        get_choice(dict, "grid", &[("moving", dp::GridAnchor::Moving), ("fixed", dp::GridAnchor::Fixed)], d.grid)?;
    let params = dp::MpcParams {
        stage_m: get_f64(dict, "stage_m", d.stage_m)?,
        horizon_m: get_f64(dict, "horizon_m", d.horizon_m)?,
        delta_kmh: get_f64(dict, "delta_kmh", d.delta_kmh)?,
        epsilon: get_f64(dict, "epsilon", d.epsilon)?,
        v_ref_kmh: get_f64(dict, "v_ref_kmh", d.v_ref_kmh)?,
        v_inc_kmh: get_f64(dict, "v_inc_kmh", d.v_inc_kmh)?,
        v_dec_kmh: get_f64(dict, "v_dec_kmh", d.v_dec_kmh)?,
        k_lim,
        n_min_rpm: get_f64(dict, "n_min_rpm", d.n_min_rpm)?,
        n_max_rpm: get_f64(dict, "n_max_rpm", d.n_max_rpm)?,
        allow_neutral,
        q_fuel: get_f64(dict, "q_fuel", d.q_fuel)?,
        q_speed_below: get_f64(dict, "q_speed_below", d.q_speed_below)?,
        q_speed_change: get_f64(dict, "q_speed_change", d.q_speed_change)?,
        q_gear_shift: get_f64(dict, "q_gear_shift", d.q_gear_shift)?,
        q_brake: get_f64(dict, "q_brake", d.q_brake)?,
        neutral_rule,
        grid,
    };
    params.validate().map_err(to_py)?;
    Ok(params)
}

/// Validate a dict of MPC parameters (names as `MpcParams`'s fields, k_lim resolved); raises
/// ValueError("key: what was expected").
#[pyfunction]
fn check_mpc_params(params: &Bound<'_, PyDict>) -> PyResult<()> {
    mpc_params_from_dict(params).map(|_| ())
}

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyVehicle>()?;
    m.add_function(wrap_pyfunction!(check_mpc_params, m)?)?;
    m.add_class::<PyRoad>()?;
    m.add_class::<PyPlant>()?;
    run::register(m)?;
    Ok(())
}

//! The map-based truck (`truckmpc_core::powertrain`) as Python sees it: its engine, driveline and
//! body as typed objects, and the truck built from them.

use std::sync::Arc;

use pyo3::prelude::*;
use pyo3::types::PyDict;

use truckmpc_core::figures::{self, check_gear};
use truckmpc_core::powertrain::{Body, Driveline, Engine, MapTruck};
use truckmpc_core::scenario::ComponentTruck;

use crate::convert::dict_of;
use crate::errors::to_py;

/// Rows of (speed, torque, value) points of a map or curve.
type Rows = Vec<(f64, f64, f64)>;

/// An engine from its data, checked.
///
/// Args:
///     idle_speed_rpm: idle speed [rpm].
///     inertia_kgm2: inertia of the engine [kg m²].
///     full_load: rows of speed [rpm], full-load torque [Nm], drag torque [Nm].
///     fuel_map: rows of speed [rpm], torque [Nm], fuel [g/h].
#[pyclass(name = "Engine", module = "truckmpc._core", frozen)]
pub struct PyEngine {
    inner: Engine,
}

#[pymethods]
impl PyEngine {
    #[new]
    fn new(idle_speed_rpm: f64, inertia_kgm2: f64, full_load: Rows, fuel_map: Rows) -> PyResult<Self> {
        let inner = Engine::new(idle_speed_rpm, inertia_kgm2, &full_load, &fuel_map).map_err(to_py)?;
        Ok(PyEngine { inner })
    }
}

/// A gearbox and axle with their losses and the tyres' radius, checked.
///
/// Args:
///     gear_ratios: ratio of each gear, first gear first [-].
///     axle_ratio: the axle's ratio [-].
///     gear_efficiency, axle_efficiency: efficiencies where no loss map is given [-].
///     loss_torque_nm: drag at the gearbox input where no loss map is given [Nm].
///     wheel_radius_m: the driven tyres' dynamic radius [m].
///     gear_loss_maps: one list of (input speed [rpm], input torque [Nm], torque loss [Nm]) rows
///         per gear, replacing gear_efficiency and loss_torque_nm.
///     axle_loss_map: likewise for the axle, replacing axle_efficiency.
#[pyclass(name = "Driveline", module = "truckmpc._core", frozen)]
pub struct PyDriveline {
    inner: Driveline,
}

#[pymethods]
impl PyDriveline {
    #[new]
    #[pyo3(signature = (gear_ratios, axle_ratio, gear_efficiency, axle_efficiency, loss_torque_nm, wheel_radius_m,
        gear_loss_maps=None, axle_loss_map=None))]
    fn new(
        gear_ratios: Vec<f64>,
        axle_ratio: f64,
        gear_efficiency: f64,
        axle_efficiency: f64,
        loss_torque_nm: f64,
        wheel_radius_m: f64,
        gear_loss_maps: Option<Vec<Rows>>,
        axle_loss_map: Option<Rows>,
    ) -> PyResult<Self> {
        let losses = (gear_efficiency, axle_efficiency, loss_torque_nm);
        let inner = Driveline::new((&gear_ratios, axle_ratio), losses, wheel_radius_m)
            .and_then(|d| d.with_loss_maps(gear_loss_maps.as_deref(), axle_loss_map.as_deref()))
            .map_err(to_py)?;
        Ok(PyDriveline { inner })
    }
}

/// The truck's body and load (checked when the truck is built).
///
/// Args:
///     mass_kg: total mass [kg]; wheels_inertia_kgm2: every wheel's inertia [kg m²];
///     cda_m2: drag area Cd·A [m²]; air_density_kgpm3: [kg/m³]; rolling_resistance: [-];
///     aux_power_w: the auxiliaries' power [W];
///     cda_curve: rows of speed [m/s], Cd·A [m²], replacing cda_m2 by a drag area over speed.
#[pyclass(name = "Body", module = "truckmpc._core", frozen)]
pub struct PyBody {
    inner: Body,
    cda_curve: Option<Vec<(f64, f64)>>,
}

#[pymethods]
impl PyBody {
    #[new]
    #[pyo3(signature = (mass_kg, wheels_inertia_kgm2, cda_m2, air_density_kgpm3, rolling_resistance, aux_power_w,
        cda_curve=None))]
    fn new(
        mass_kg: f64,
        wheels_inertia_kgm2: f64,
        cda_m2: f64,
        air_density_kgpm3: f64,
        rolling_resistance: f64,
        aux_power_w: f64,
        cda_curve: Option<Vec<(f64, f64)>>,
    ) -> Self {
        let inner = Body { mass_kg, wheels_inertia_kgm2, cda_m2, air_density_kgpm3, rolling_resistance, aux_power_w };
        PyBody { inner, cda_curve }
    }
}

/// A truck from component data: engine, driveline and body, and how long a gear shift interrupts
/// traction [s].
#[pyclass(name = "MapTruck", module = "truckmpc._core", frozen)]
pub struct PyMapTruck {
    pub inner: Arc<ComponentTruck>,
}

#[pymethods]
impl PyMapTruck {
    #[new]
    #[pyo3(signature = (engine, driveline, body, traction_interruption_s=0.0))]
    fn new(engine: &PyEngine, driveline: &PyDriveline, body: &PyBody, traction_interruption_s: f64) -> PyResult<Self> {
        let mut truck = MapTruck::new(engine.inner.clone(), driveline.inner.clone(), body.inner).map_err(to_py)?;
        if let Some(curve) = &body.cda_curve {
            truck = truck.with_cda_curve(curve).map_err(to_py)?;
        }
        let inner = ComponentTruck::new(truck, traction_interruption_s).map_err(to_py)?;
        Ok(PyMapTruck { inner: Arc::new(inner) })
    }

    /// What the truck is (`truckmpc_core::figures::truck_facts`): gears, rated power and speed,
    /// the speeds and torques its maps cover, which losses loss maps give, the efficiency.
    #[getter]
    fn facts<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        dict_of(py, &figures::truck_facts(self.inner.truck()))
    }

    /// Drag area Cd·A [m²] at `v_mps`.
    fn cda_m2(&self, v_mps: f64) -> f64 {
        self.inner.truck().cda_m2(v_mps)
    }

    /// The engine at `speed_rpm` and `torque_nm`: dict with `max_torque_nm`, `drag_torque_nm`,
    /// `fuel_rate_g_per_h` (0 at or below the drag torque; the nearest boundary value outside the
    /// map) and `in_fuel_map`.
    fn engine_point<'py>(&self, py: Python<'py>, speed_rpm: f64, torque_nm: f64) -> PyResult<Bound<'py, PyDict>> {
        dict_of(py, &figures::engine_point(self.inner.truck(), speed_rpm, torque_nm).map_err(to_py)?)
    }

    /// Engine speed [rpm] at `v_mps` in `gear` (1..=gears).
    fn engine_speed_rpm(&self, v_mps: f64, gear: usize) -> PyResult<f64> {
        let driveline = self.inner.truck().driveline();
        check_gear(gear, 1, driveline.gears()).map_err(to_py)?;
        Ok(driveline.engine_speed_rpm(v_mps, gear))
    }

    /// Road loads [W] at `v_mps`, `acc_mps2` and `slope_rad`: dict with `air_w`, `rolling_w`,
    /// `slope_w`, `vehicle_inertia_w`, `wheels_inertia_w`, `wheel_w` (their sum).
    fn road_loads<'py>(
        &self,
        py: Python<'py>,
        v_mps: f64,
        acc_mps2: f64,
        slope_rad: f64,
    ) -> PyResult<Bound<'py, PyDict>> {
        dict_of(py, &figures::road_loads(self.inner.truck(), v_mps, acc_mps2, slope_rad))
    }

    /// The engine's operating point at `v_mps` (> 0), `acc_mps2`, `slope_rad` in `gear`: dict with
    /// `engine_speed_rpm`, `engine_torque_nm`, `engine_power_w`, `fuel_rate_g_per_h` (NaN beyond the
    /// full-load curve's speeds), `brake_power_w` (at the wheels, beyond the engine's drag),
    /// `feasible`.
    fn operating_point<'py>(
        &self,
        py: Python<'py>,
        v_mps: f64,
        acc_mps2: f64,
        slope_rad: f64,
        gear: usize,
    ) -> PyResult<Bound<'py, PyDict>> {
        let point = figures::operating_point(self.inner.truck(), v_mps, acc_mps2, slope_rad, gear).map_err(to_py)?;
        dict_of(py, &point)
    }
}

//! The map-based truck (`truckmpc_core::powertrain`) as Python sees it: built from an engine, a
//! driveline and a body read off typed Python objects, and asked for its figures.

use std::sync::Arc;

use pyo3::prelude::*;
use pyo3::types::PyDict;

use truckmpc_core::figures;
use truckmpc_core::powertrain::{Body, Driveline, Engine, MapTruck};
use truckmpc_core::scenario::ComponentTruck;

use crate::convert::dict_of;
use crate::errors::to_py;

/// Rows of (speed, torque, value) points of a map or curve.
type Rows = Vec<(f64, f64, f64)>;

/// An engine's data, read off the attributes of any object that has them (a VECTO `EngineData`).
#[derive(FromPyObject)]
struct EngineData {
    idle_speed_rpm: f64,
    inertia_kgm2: f64,
    full_load: Rows,
    fuel_map: Rows,
}

/// A gearbox and axle with their losses and the tyres' radius, read off an object's attributes.
#[derive(FromPyObject)]
struct DrivelineData {
    gear_ratios: Vec<f64>,
    axle_ratio: f64,
    gear_efficiency: f64,
    axle_efficiency: f64,
    loss_torque_nm: f64,
    wheel_radius_m: f64,
    gear_loss_maps: Option<Vec<Rows>>,
    axle_loss_map: Option<Rows>,
}

/// The body and load, read off an object's attributes.
#[derive(FromPyObject)]
struct BodyData {
    mass_kg: f64,
    wheels_inertia_kgm2: f64,
    cda_m2: f64,
    air_density_kgpm3: f64,
    rolling_resistance: f64,
    aux_power_w: f64,
    cda_curve: Option<Vec<(f64, f64)>>,
}

/// A truck from component data (engine, driveline, body), checked by the core, and how long a gear
/// shift interrupts traction [s].
#[pyclass(name = "MapTruck", module = "truckmpc._core", frozen)]
pub struct PyMapTruck {
    pub inner: Arc<ComponentTruck>,
}

#[pymethods]
impl PyMapTruck {
    #[new]
    #[pyo3(signature = (engine, driveline, body, traction_interruption_s=0.0))]
    fn new(
        engine: EngineData,
        driveline: DrivelineData,
        body: BodyData,
        traction_interruption_s: f64,
    ) -> PyResult<Self> {
        let e = engine;
        let engine = Engine::new(e.idle_speed_rpm, e.inertia_kgm2, &e.full_load, &e.fuel_map).map_err(to_py)?;
        let d = driveline;
        let losses = (d.gear_efficiency, d.axle_efficiency, d.loss_torque_nm);
        let driveline = Driveline::new((&d.gear_ratios, d.axle_ratio), losses, d.wheel_radius_m)
            .and_then(|built| built.with_loss_maps(d.gear_loss_maps.as_deref(), d.axle_loss_map.as_deref()))
            .map_err(to_py)?;
        let b = body;
        let (mass_kg, wheels_inertia_kgm2, cda_m2) = (b.mass_kg, b.wheels_inertia_kgm2, b.cda_m2);
        let (air_density_kgpm3, rolling_resistance, aux_power_w) =
            (b.air_density_kgpm3, b.rolling_resistance, b.aux_power_w);
        let body = Body { mass_kg, wheels_inertia_kgm2, cda_m2, air_density_kgpm3, rolling_resistance, aux_power_w };
        let mut truck = MapTruck::new(engine, driveline, body).map_err(to_py)?;
        if let Some(curve) = &b.cda_curve {
            truck = truck.with_cda_curve(curve).map_err(to_py)?;
        }
        let inner = ComponentTruck::new(truck, traction_interruption_s).map_err(to_py)?;
        Ok(PyMapTruck { inner: Arc::new(inner) })
    }

    /// What the truck is (`figures::truck_facts`).
    #[getter]
    fn facts<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        dict_of(py, &figures::truck_facts(self.inner.truck()))
    }

    /// Drag area Cd·A [m²] at `v_mps`.
    fn cda_m2(&self, v_mps: f64) -> f64 {
        self.inner.truck().cda_m2(v_mps)
    }

    /// The engine at `speed_rpm` and `torque_nm` (`figures::engine_point`).
    fn engine_point<'py>(&self, py: Python<'py>, speed_rpm: f64, torque_nm: f64) -> PyResult<Bound<'py, PyDict>> {
        dict_of(py, &figures::engine_point(self.inner.truck(), speed_rpm, torque_nm).map_err(to_py)?)
    }

    /// Engine speed [rpm] at `v_mps` in `gear` (1..=gears).
    fn engine_speed_rpm(&self, v_mps: f64, gear: usize) -> PyResult<f64> {
        figures::map_engine_speed_rpm(self.inner.truck(), v_mps, gear).map_err(to_py)
    }

    /// Road loads [W] at `v_mps`, `acc_mps2` and `slope_rad` (`figures::road_loads`).
    fn road_loads<'py>(
        &self,
        py: Python<'py>,
        v_mps: f64,
        acc_mps2: f64,
        slope_rad: f64,
    ) -> PyResult<Bound<'py, PyDict>> {
        dict_of(py, &figures::road_loads(self.inner.truck(), v_mps, acc_mps2, slope_rad))
    }

    /// The engine's operating point at `v_mps`, `acc_mps2`, `slope_rad` in `gear` (`figures::operating_point`).
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

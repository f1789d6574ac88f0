//! The map-based truck (`truckmpc_core::powertrain`) as Python sees it: built from an engine, a
//! driveline and a body read off the attributes of Python objects, and asked for its figures.

use std::sync::Arc;

use pyo3::prelude::*;
use pyo3::types::PyDict;

use truckmpc_core::figures;
use truckmpc_core::powertrain::{Body, DrivelineData, EngineData, TruckParts};
use truckmpc_core::scenario::ComponentTruck;

use crate::convert::{dict_of, read_attrs};
use crate::errors::to_py;

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
        engine: &Bound<'_, PyAny>,
        driveline: &Bound<'_, PyAny>,
        body: &Bound<'_, PyAny>,
        traction_interruption_s: f64,
    ) -> PyResult<Self> {
        let parts = TruckParts {
            engine: read_attrs!(engine, EngineData { idle_speed_rpm, inertia_kgm2, full_load, fuel_map }),
            driveline: read_attrs!(
                driveline,
                DrivelineData {
                    gear_ratios,
                    axle_ratio,
                    gear_efficiency,
                    axle_efficiency,
                    loss_torque_nm,
                    wheel_radius_m,
                    gear_loss_maps,
                    axle_loss_map,
                }
            ),
            body: read_attrs!(
                body,
                Body { mass_kg, wheels_inertia_kgm2, cda_m2, air_density_kgpm3, rolling_resistance, aux_power_w }
            ),
            cda_curve: body.getattr("cda_curve")?.extract()?,
        };
        let inner = ComponentTruck::new(parts.build().map_err(to_py)?, traction_interruption_s).map_err(to_py)?;
        Ok(PyMapTruck { inner: Arc::new(inner) })
    }

    /// What the truck is (`figures::truck_facts`).
    #[getter]
    fn facts<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        dict_of(py, &figures::truck_facts(self.inner.truck()))
    }

    /// The engine at `speed_rpm` and `torque_nm` (`figures::engine_point`).
    fn engine_point<'py>(&self, py: Python<'py>, speed_rpm: f64, torque_nm: f64) -> PyResult<Bound<'py, PyDict>> {
        dict_of(py, &figures::engine_point(self.inner.truck(), speed_rpm, torque_nm).map_err(to_py)?)
    }

    /// The truck at `v_mps`, `acc_mps2` and `slope_rad`, in `gear` if given (`figures::driving_state`).
    #[pyo3(signature = (v_mps, acc_mps2=0.0, slope_rad=0.0, gear=None))]
    fn at<'py>(
        &self,
        py: Python<'py>,
        v_mps: f64,
        acc_mps2: f64,
        slope_rad: f64,
        gear: Option<usize>,
    ) -> PyResult<Bound<'py, PyDict>> {
        dict_of(py, &figures::driving_state(self.inner.truck(), v_mps, acc_mps2, slope_rad, gear).map_err(to_py)?)
    }
}

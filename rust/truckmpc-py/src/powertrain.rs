//! The map-based truck (`truckmpc_core::powertrain`) as Python sees it: built from an engine, a
//! driveline and a body read off the attributes of Python objects, and asked for its figures.

use std::sync::Arc;

use numpy::{IntoPyArray, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use truckmpc_core::figures;
use truckmpc_core::powertrain::electric::{BatteryData, ElectricParts, LevelData, MachineData, ReductionData};
use truckmpc_core::powertrain::OverloadRating;
use truckmpc_core::powertrain::{Body, DrivelineData, ElectricTruck, EngineData, MapTruck, TruckParts};
use truckmpc_core::scenario::ComponentTruck;
use truckmpc_core::CoreError;

use crate::convert::{dict_of, read_attrs};
use crate::errors::to_py;

/// A truck from component data, checked by the core: an engine, a driveline and a body, with how
/// long a gear shift interrupts traction [s]; or (`MapTruck.electric`) electric machines, their
/// reduction, a battery and a body.
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
                    retarder_loss_map,
                    retarder_ratio,
                    retarder_position,
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

    /// A battery-electric truck from its machines, reduction, battery and body, its machines'
    /// conditioning power [W] and the state of charge it starts from [%] (None: the middle of the
    /// usable window).
    #[staticmethod]
    fn electric(
        machine: &Bound<'_, PyAny>,
        reduction: &Bound<'_, PyAny>,
        battery: &Bound<'_, PyAny>,
        body: &Bound<'_, PyAny>,
        conditioning_w: f64,
        soc_start_pct: Option<f64>,
    ) -> PyResult<Self> {
        let mut levels = Vec::new();
        for level in machine.getattr("levels")?.try_iter()? {
            let level = level?;
            let rating = read_attrs!(
                level,
                OverloadRating {
                    continuous_torque_nm,
                    continuous_speed_rpm,
                    overload_torque_nm,
                    overload_speed_rpm,
                    overload_duration_s
                }
            );
            levels.push(LevelData {
                voltage_v: level.getattr("voltage_v")?.extract()?,
                torque_limits: level.getattr("torque_limits")?.extract()?,
                power_map: level.getattr("power_map")?.extract()?,
                rating: Some(rating),
            });
        }
        let machine = MachineData {
            count: machine.getattr("count")?.extract()?,
            inertia_kgm2: machine.getattr("inertia_kgm2")?.extract()?,
            levels,
            drag_curve: machine.getattr("drag_curve")?.extract()?,
        };
        let parts = ElectricParts {
            machine,
            reduction: read_attrs!(reduction, ReductionData { ratio, loss_map, wheel_radius_m }),
            battery: read_attrs!(
                battery,
                BatteryData { capacity_ah, ocv, resistance_mohm, current_limits, soc_window_pct }
            ),
            body: read_attrs!(
                body,
                Body { mass_kg, wheels_inertia_kgm2, cda_m2, air_density_kgpm3, rolling_resistance, aux_power_w }
            ),
            conditioning_w,
            cda_curve: body.getattr("cda_curve")?.extract()?,
            soc_start_pct,
        };
        Ok(PyMapTruck { inner: Arc::new(ComponentTruck::electric(parts.build().map_err(to_py)?)) })
    }

    /// What the engine-driven truck is (`figures::truck_facts`).
    #[getter]
    fn facts<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        dict_of(py, &figures::truck_facts(self.map_truck()?))
    }

    /// What the battery-electric truck is (`figures::electric_facts`).
    #[getter]
    fn electric_facts<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        dict_of(py, &figures::electric_facts(self.electric_truck()?))
    }

    /// The machines at `speed_rpm` and `torque_nm` (`figures::machine_point`).
    fn machine_point<'py>(&self, py: Python<'py>, speed_rpm: f64, torque_nm: f64) -> PyResult<Bound<'py, PyDict>> {
        let truck = self.electric_truck()?;
        dict_of(py, &figures::machine_point(truck, speed_rpm, torque_nm).map_err(to_py)?)
    }

    /// The battery-electric truck holding `v_mps` on `slope_rad` (`figures::electric_state`).
    fn electric_state<'py>(
        &self,
        py: Python<'py>,
        v_mps: f64,
        slope_rad: f64,
        brake_torque_max_nm: f64,
    ) -> PyResult<Bound<'py, PyDict>> {
        let truck = self.electric_truck()?;
        dict_of(py, &figures::electric_state(truck, v_mps, slope_rad, brake_torque_max_nm).map_err(to_py)?)
    }

    /// Where the battery-electric truck's power goes under each control (`figures::electric_flows`):
    /// a dict of 1-D arrays [W].
    fn electric_flows<'py>(
        &self,
        py: Python<'py>,
        v_mps: PyReadonlyArray1<'_, f64>,
        pedal: PyReadonlyArray1<'_, f64>,
        brake: PyReadonlyArray1<'_, f64>,
        brake_torque_max_nm: f64,
    ) -> PyResult<Bound<'py, PyDict>> {
        let truck = self.electric_truck()?;
        let (v, p, b) = (v_mps.as_slice()?, pedal.as_slice()?, brake.as_slice()?);
        let columns = figures::electric_flows(truck, (v, p, b), brake_torque_max_nm).map_err(to_py)?;
        let out = PyDict::new(py);
        for (name, values) in columns {
            out.set_item(name, values.into_pyarray(py))?;
        }
        Ok(out)
    }

    /// Whether the truck is battery-electric.
    #[getter]
    fn is_electric(&self) -> bool {
        self.inner.electric_truck().is_some()
    }

    /// The engine at `speed_rpm` and `torque_nm` (`figures::engine_point`).
    fn engine_point<'py>(&self, py: Python<'py>, speed_rpm: f64, torque_nm: f64) -> PyResult<Bound<'py, PyDict>> {
        dict_of(py, &figures::engine_point(self.map_truck()?, speed_rpm, torque_nm).map_err(to_py)?)
    }

    /// The driveline in `gear` at `speed_rpm` with `torque_nm` at its input (`figures::driveline_point`).
    fn driveline_point<'py>(
        &self,
        py: Python<'py>,
        speed_rpm: f64,
        torque_nm: f64,
        gear: usize,
    ) -> PyResult<Bound<'py, PyDict>> {
        dict_of(py, &figures::driveline_point(self.map_truck()?, speed_rpm, torque_nm, gear).map_err(to_py)?)
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
        dict_of(py, &figures::driving_state(self.map_truck()?, v_mps, acc_mps2, slope_rad, gear).map_err(to_py)?)
    }
}

impl PyMapTruck {
    /// The engine-driven truck, or a `ParamError` for a battery-electric one.
    fn map_truck(&self) -> PyResult<&MapTruck> {
        self.inner
            .truck()
            .ok_or_else(|| to_py(CoreError::invalid("truck", "an engine-driven truck").got("a battery-electric truck")))
    }

    /// The battery-electric truck, or a `ParamError` for an engine-driven one.
    fn electric_truck(&self) -> PyResult<&ElectricTruck> {
        self.inner
            .electric_truck()
            .ok_or_else(|| to_py(CoreError::invalid("truck", "a battery-electric truck").got("an engine-driven truck")))
    }
}

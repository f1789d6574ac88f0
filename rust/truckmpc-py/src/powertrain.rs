//! The map-based truck (`truckmpc_core::powertrain`) as Python sees it.

use pyo3::exceptions::PyKeyError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::sync::{Arc, Mutex};

use truckmpc_core::powertrain::{Body, Driveline, Engine, MapModel, MapTruck, RPM_PER_RAD_S};

use crate::errors::{bad_argument, to_py};

/// A truck from component data: engine maps, driveline and body.
///
/// Args:
///     engine: `idle_speed_rpm`, `inertia_kgm2`, `full_load` (rows of speed [rpm], full-load
///         torque [Nm], drag torque [Nm]) and `fuel_map` (rows of speed [rpm], torque [Nm], fuel [g/h]).
///     driveline: `gear_ratios` (first gear first), `axle_ratio`, `gear_efficiency`,
///         `axle_efficiency`, `loss_torque_nm` (drag at the gearbox input), `wheel_radius_m`, and
///         optionally `traction_interruption_s` (how long a gear shift interrupts traction; 0),
///         `gear_loss_maps` (one list of (input speed [rpm], input torque [Nm], torque loss [Nm])
///         rows per gear, replacing `gear_efficiency` and `loss_torque_nm`) and `axle_loss_map`
///         (likewise for the axle, replacing `axle_efficiency`).
///     body: `mass_kg`, `wheels_inertia_kgm2`, `cda_m2`, `air_density_kg_m3`, `rolling_resistance`,
///         `aux_power_w`, and optionally `cda_curve` (rows of speed [m/s], Cd·A [m²]) replacing
///         `cda_m2` by a drag area that depends on speed.
#[pyclass(name = "MapTruck", module = "truckmpc._core", frozen)]
pub struct PyMapTruck {
    pub inner: MapTruck,
    /// How long a gear shift interrupts traction [s].
    pub traction_interruption_s: f64,
    /// The models built for this truck, by brake torque [Nm] (bits): building one resamples the
    /// maps (about 0.1 s), which every run's settings would otherwise repeat.
    models: Mutex<Vec<(u64, Arc<MapModel>)>>,
}

impl PyMapTruck {
    /// The model of this truck with `brake_torque_max_nm` at full brake, built once.
    pub fn model(&self, brake_torque_max_nm: f64) -> Arc<MapModel> {
        let mut models = self.models.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
        let key = brake_torque_max_nm.to_bits();
        if let Some((_, model)) = models.iter().find(|(k, _)| *k == key) {
            return model.clone();
        }
        let model = Arc::new(MapModel::new(self.inner.clone(), brake_torque_max_nm, self.traction_interruption_s));
        models.push((key, model.clone()));
        model
    }
}

fn item<'py, T: FromPyObjectOwned<'py>>(d: &Bound<'py, PyDict>, key: &str) -> PyResult<T> {
    let value = d.get_item(key)?.ok_or_else(|| PyKeyError::new_err(key.to_string()))?;
    value.extract::<T>().map_err(|_| {
        bad_argument(key, "a number (or rows of numbers)", value.repr().map_or_else(|_| "?".into(), |r| r.to_string()))
    })
}

/// The value of an optional key: None when absent or None.
fn optional<'py, T: FromPyObjectOwned<'py>>(d: &Bound<'py, PyDict>, key: &str) -> PyResult<Option<T>> {
    match d.get_item(key)? {
        Some(value) if !value.is_none() => item(d, key).map(Some),
        _ => Ok(None),
    }
}

#[pymethods]
impl PyMapTruck {
    #[new]
    fn new(engine: &Bound<'_, PyDict>, driveline: &Bound<'_, PyDict>, body: &Bound<'_, PyDict>) -> PyResult<Self> {
        let body_dict = body;
        let full_load: Vec<(f64, f64, f64)> = item(engine, "full_load")?;
        let fuel_map: Vec<(f64, f64, f64)> = item(engine, "fuel_map")?;
        let engine = Engine::new(item(engine, "idle_speed_rpm")?, item(engine, "inertia_kgm2")?, &full_load, &fuel_map)
            .map_err(to_py)?;
        let traction_interruption_s: f64 = if driveline.contains("traction_interruption_s")? {
            item(driveline, "traction_interruption_s")?
        } else {
            0.0
        };
        if !(traction_interruption_s.is_finite() && (0.0..=10.0).contains(&traction_interruption_s)) {
            return Err(to_py(
                truckmpc_core::CoreError::invalid("traction_interruption_s", "a time in [0, 10] s")
                    .got(traction_interruption_s),
            ));
        }
        let ratios: Vec<f64> = item(driveline, "gear_ratios")?;
        let gear_maps: Option<Vec<Vec<(f64, f64, f64)>>> = optional(driveline, "gear_loss_maps")?;
        let axle_map: Option<Vec<(f64, f64, f64)>> = optional(driveline, "axle_loss_map")?;
        let driveline = Driveline::new(
            (&ratios, item(driveline, "axle_ratio")?),
            (
                item(driveline, "gear_efficiency")?,
                item(driveline, "axle_efficiency")?,
                item(driveline, "loss_torque_nm")?,
            ),
            item(driveline, "wheel_radius_m")?,
        )
        .map_err(to_py)?
        .with_loss_maps(gear_maps.as_deref(), axle_map.as_deref())
        .map_err(to_py)?;
        let body = Body {
            mass_kg: item(body, "mass_kg")?,
            wheels_inertia_kgm2: item(body, "wheels_inertia_kgm2")?,
            cda_m2: item(body, "cda_m2")?,
            air_density_kg_m3: item(body, "air_density_kg_m3")?,
            rolling_resistance: item(body, "rolling_resistance")?,
            aux_power_w: item(body, "aux_power_w")?,
        };
        let mut inner = MapTruck::new(engine, driveline, body).map_err(to_py)?;
        if body_dict.contains("cda_curve")? {
            let curve: Vec<(f64, f64)> = item(body_dict, "cda_curve")?;
            inner = inner.with_cda_curve(&curve).map_err(to_py)?;
        }
        Ok(PyMapTruck { inner, traction_interruption_s, models: Mutex::new(Vec::new()) })
    }

    /// Number of forward gears.
    #[getter]
    fn gears(&self) -> usize {
        self.inner.driveline().gears()
    }

    /// Rated power [W]: the most the full-load curve gives.
    #[getter]
    fn rated_power_w(&self) -> f64 {
        self.inner.engine().rated_power().0
    }

    /// Engine speed [rpm] of the rated power.
    #[getter]
    fn rated_speed_rpm(&self) -> f64 {
        self.inner.engine().rated_power().1
    }

    /// Engine speeds [rpm] the full-load curve covers (first, last).
    #[getter]
    fn speed_range_rpm(&self) -> (f64, f64) {
        self.inner.engine().speed_range_rpm()
    }

    /// Engine speeds [rpm] the fuel map covers (lowest, highest).
    #[getter]
    fn fuel_map_speed_range_rpm(&self) -> (f64, f64) {
        self.inner.engine().fuel_map().speed_range_rpm()
    }

    /// Torques [Nm] the fuel map covers (lowest, highest).
    #[getter]
    fn fuel_map_torque_range_nm(&self) -> (f64, f64) {
        self.inner.engine().fuel_map().torque_range_nm()
    }

    /// Drag area Cd·A [m²] at `v_mps`.
    fn cda_m2(&self, v_mps: f64) -> f64 {
        self.inner.cda_m2(v_mps)
    }

    /// Whether VECTO's loss maps give the losses of the gears and of the axle: (gears, axle).
    #[getter]
    fn has_loss_maps(&self) -> (bool, bool) {
        self.inner.driveline().has_loss_maps()
    }

    /// Driveline efficiency without loss maps, gearbox times axle.
    #[getter]
    fn efficiency(&self) -> f64 {
        self.inner.driveline().efficiency()
    }

    /// Full-load torque [Nm] at `speed_rpm`.
    fn max_torque_nm(&self, speed_rpm: f64) -> f64 {
        self.inner.engine().max_torque_nm(speed_rpm)
    }

    /// Drag torque [Nm] (negative) at `speed_rpm`.
    fn drag_torque_nm(&self, speed_rpm: f64) -> f64 {
        self.inner.engine().drag_torque_nm(speed_rpm)
    }

    /// Fuel rate [g/h] at `speed_rpm` and `torque_nm` (0 at or below the drag torque; the nearest
    /// boundary value outside the map).
    fn fuel_rate_g_per_h(&self, speed_rpm: f64, torque_nm: f64) -> PyResult<f64> {
        finite(speed_rpm, torque_nm)?;
        Ok(self.inner.engine().fuel_rate_g_per_h(speed_rpm, torque_nm))
    }

    /// Whether (`speed_rpm`, `torque_nm`) lies inside the fuel map's convex hull.
    fn in_fuel_map(&self, speed_rpm: f64, torque_nm: f64) -> PyResult<bool> {
        finite(speed_rpm, torque_nm)?;
        Ok(self.inner.engine().fuel_map().interpolate(speed_rpm, torque_nm).is_some())
    }

    /// Engine speed [rpm] at `v_mps` in `gear` (1..=gears).
    fn engine_speed_rpm(&self, v_mps: f64, gear: usize) -> PyResult<f64> {
        self.check_gear(gear)?;
        Ok(self.inner.driveline().engine_speed_rpm(v_mps, gear))
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
        let l = self.inner.road_loads(v_mps, acc_mps2, slope_rad);
        let d = PyDict::new(py);
        for (k, v) in [
            ("air_w", l.air_w),
            ("rolling_w", l.rolling_w),
            ("slope_w", l.slope_w),
            ("vehicle_inertia_w", l.vehicle_inertia_w),
            ("wheels_inertia_w", l.wheels_inertia_w),
            ("wheel_w", l.wheel_w()),
        ] {
            d.set_item(k, v)?;
        }
        Ok(d)
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
        self.check_gear(gear)?;
        let op = self.inner.operating_point(v_mps, acc_mps2, slope_rad, gear).ok_or_else(|| {
            bad_argument(
                "v_mps, acc_mps2, slope_rad",
                "a finite speed > 0 and finite values",
                format!("{v_mps}, {acc_mps2}, {slope_rad}"),
            )
        })?;
        let d = PyDict::new(py);
        d.set_item("engine_speed_rpm", op.engine_speed_rpm)?;
        d.set_item("engine_torque_nm", op.engine_torque_nm)?;
        d.set_item("engine_power_w", op.engine_torque_nm * op.engine_speed_rpm / RPM_PER_RAD_S)?;
        d.set_item("fuel_rate_g_per_h", op.fuel_g_per_h)?;
        d.set_item("brake_power_w", op.brake_power_w)?;
        d.set_item("feasible", op.feasible)?;
        Ok(d)
    }
}

fn finite(speed_rpm: f64, torque_nm: f64) -> PyResult<()> {
    if speed_rpm.is_finite() && torque_nm.is_finite() {
        Ok(())
    } else {
        Err(bad_argument("speed_rpm, torque_nm", "finite numbers", format!("{speed_rpm}, {torque_nm}")))
    }
}

impl PyMapTruck {
    fn check_gear(&self, gear: usize) -> PyResult<()> {
        let n = self.inner.driveline().gears();
        if gear == 0 || gear > n {
            return Err(bad_argument("gear", &format!("1..={n}"), gear));
        }
        Ok(())
    }
}

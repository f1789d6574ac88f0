//! A road profile as Python sees it.

use std::sync::Arc;

use numpy::{IntoPyArray, PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;
use truckmpc_core::figures;
use truckmpc_core::{CruiseParams, Road};

use crate::convert::read_attrs;
use crate::errors::to_py;

/// A road profile: points `distance_m` [m] (strictly increasing), the grade of each segment
/// between consecutive points (`len(slope) == len(distance_m) - 1`) and, optionally, each
/// segment's target speed [km/h]. Flat beyond its end.
#[pyclass(name = "Road", module = "truckmpc._core", frozen)]
pub struct PyRoad {
    pub inner: Arc<Road>,
}

#[pymethods]
impl PyRoad {
    #[new]
    #[pyo3(signature = (distance_m, slope, target_speed_kmh=None))]
    fn new(
        distance_m: PyReadonlyArray1<'_, f64>,
        slope: PyReadonlyArray1<'_, f64>,
        target_speed_kmh: Option<PyReadonlyArray1<'_, f64>>,
    ) -> PyResult<Self> {
        let mut road = Road::new(distance_m.as_array().to_vec(), slope.as_array().to_vec()).map_err(to_py)?;
        if let Some(targets) = target_speed_kmh {
            road = road.with_target_speeds(targets.as_array().to_vec()).map_err(to_py)?;
        }
        Ok(PyRoad { inner: Arc::new(road) })
    }

    /// The speed band every controller works to on this road for one `cruise` setting [km/h], at
    /// each of `distance_m` [m] (increasing): the stretch's set speed, v_min and v_max.
    fn speed_band<'py>(
        &self,
        py: Python<'py>,
        distance_m: PyReadonlyArray1<'_, f64>,
        cruise: &Bound<'py, PyAny>,
    ) -> PyResult<SpeedBandArrays<'py>> {
        let cruise =
            read_attrs!(cruise, CruiseParams { v_ref_kmh, v_dec_kmh, v_inc_kmh, target_offset_kmh, target_decel_mps2 });
        let distance_m = distance_m.as_array().to_vec();
        let [set, low, high] = figures::speed_band(&self.inner, &cruise, &distance_m).map_err(to_py)?;
        Ok((set.into_pyarray(py), low.into_pyarray(py), high.into_pyarray(py)))
    }
}

/// The set speed, v_min and v_max along a road [km/h], as numpy arrays.
type SpeedBandArrays<'py> = (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>);

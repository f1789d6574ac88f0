//! A run's outputs as Python sees them, converted by walking the core's declaration
//! (`truckmpc_core::sim::schema`): the summary as a dict of its figures, the trace as a dict of
//! 1-D numpy arrays.

use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use truckmpc_core::params::Value;
use truckmpc_core::sim::schema::Column;
use truckmpc_core::sim::{RunSummary, Trace};

use crate::convert::dict_of;

/// The figures `s` carries, keyed by their declared names, in the declaration's order.
pub fn summary_dict<'py>(py: Python<'py>, s: &RunSummary) -> PyResult<Bound<'py, PyDict>> {
    let figures: Vec<(&str, Value)> = s.figures().map(|(spec, figure)| (spec.name, figure.value())).collect();
    dict_of(py, &figures)
}

/// The trace's columns as numpy arrays (float64, `gear` int64), in the declaration's order.
pub fn trace_dict(py: Python<'_>, t: Trace) -> PyResult<Bound<'_, PyDict>> {
    let out = PyDict::new(py);
    for (spec, column) in t.into_columns() {
        match column {
            Column::Number(values) => out.set_item(spec.name, values.into_pyarray(py))?,
            Column::Count(values) => out.set_item(spec.name, values.into_pyarray(py))?,
        }
    }
    Ok(out)
}

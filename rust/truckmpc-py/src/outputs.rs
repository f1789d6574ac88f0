//! A run's outputs as Python sees them, converted by walking the core's declaration
//! (`truckmpc_core::sim::schema`): the summary as a dict of its figures, the trace as a dict of
//! 1-D numpy arrays, and the declaration itself as dicts of each spec's record.

use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use truckmpc_core::params::Value;
use truckmpc_core::sim::schema::{Column, SUMMARY, TRACE};
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

/// Every figure of a controller's summary, in `summary.json`'s order, each a dict of its record
/// (`OutputSpec::record`).
#[pyfunction]
fn summary_specs(py: Python<'_>) -> PyResult<Vec<Bound<'_, PyDict>>> {
    SUMMARY.iter().map(|f| dict_of(py, &f.spec.record())).collect()
}

/// Every column of a run's trace, in the CSV's order, each a dict of its record.
#[pyfunction]
fn trace_specs(py: Python<'_>) -> PyResult<Vec<Bound<'_, PyDict>>> {
    TRACE.iter().map(|c| dict_of(py, &c.spec.record())).collect()
}

/// Add `summary_specs` and `trace_specs` to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(summary_specs, m)?)?;
    m.add_function(wrap_pyfunction!(trace_specs, m)?)?;
    Ok(())
}

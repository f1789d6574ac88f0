//! A run's outputs as Python sees them, converted by walking the core's declaration
//! (`truckmpc_core::sim::schema`): the summary as a dict of its figures, the trace as a dict of
//! 1-D numpy arrays, and the declaration itself as `OutputSpec`s.

use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use truckmpc_core::sim::schema::{Column, Figure, OutputSpec, Source, SUMMARY, TRACE};
use truckmpc_core::sim::{RunSummary, Trace};

/// The figures `s` carries, keyed by their declared names, in the declaration's order.
pub fn summary_dict<'py>(py: Python<'py>, s: &RunSummary) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    for (spec, value) in s.figures() {
        match value {
            Figure::Number(x) => out.set_item(spec.name, x)?,
            Figure::Count(n) => out.set_item(spec.name, n)?,
            Figure::Flag(b) => out.set_item(spec.name, b)?,
            Figure::Text(text) => out.set_item(spec.name, text)?,
            Figure::Null => out.set_item(spec.name, py.None())?,
        }
    }
    Ok(out)
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

/// One declared output: a figure of a controller's summary or a column of its trace.
#[pyclass(name = "OutputSpec", module = "truckmpc._core", frozen, get_all)]
pub struct PyOutputSpec {
    /// Key in the summary (column of the trace), its unit in the name.
    name: String,
    /// Unit ("-" for none).
    unit: String,
    /// Short label for tables.
    label: String,
    /// One-line meaning.
    doc: String,
    /// number, count, flag, text or record.
    kind: String,
    /// Which runs carry it: every, pcc, dp (mpc, optimal), optimal, or legs (a road with stops).
    runs: String,
    /// Where it is computed: core, or python (after the core's run).
    source: String,
    /// How a road driven as legs joins it: sum, sum_unless_stalled, max, first, last, any,
    /// mean_per_solve, per_100km, per_time_s, mean_speed, built; trace columns continued or joined.
    merge: String,
    /// The figure a recomputed one (per_100km, per_time_s) follows from; None otherwise.
    merge_of: Option<String>,
    /// Whose columns of sweep.csv carry it: all, look_ahead, mpc, or "" for none.
    sweep: String,
    /// Decimals the trace's CSV writes; None for summary figures and whole numbers.
    decimals: Option<u8>,
}

impl PyOutputSpec {
    fn new(spec: &OutputSpec) -> Self {
        let source = match spec.source {
            Source::Core => "core",
            Source::Python => "python",
        };
        PyOutputSpec {
            name: spec.name.to_string(),
            unit: spec.unit.to_string(),
            label: spec.label.to_string(),
            doc: spec.doc.to_string(),
            kind: spec.kind.name().to_string(),
            runs: spec.runs.name().to_string(),
            source: source.to_string(),
            merge: spec.merge.name().to_string(),
            merge_of: spec.merge.of().map(str::to_string),
            sweep: spec.sweep.name().to_string(),
            decimals: spec.decimals,
        }
    }
}

#[pymethods]
impl PyOutputSpec {
    fn __repr__(&self) -> String {
        format!("OutputSpec({:?}, unit={:?}, runs={:?}, merge={:?})", self.name, self.unit, self.runs, self.merge)
    }
}

/// Every figure of a controller's summary, in `summary.json`'s order.
#[pyfunction]
fn summary_specs() -> Vec<PyOutputSpec> {
    SUMMARY.iter().map(|f| PyOutputSpec::new(&f.spec)).collect()
}

/// Every column of a run's trace, in the CSV's order.
#[pyfunction]
fn trace_specs() -> Vec<PyOutputSpec> {
    TRACE.iter().map(|c| PyOutputSpec::new(&c.spec)).collect()
}

/// Add `OutputSpec`, `summary_specs` and `trace_specs` to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyOutputSpec>()?;
    m.add_function(wrap_pyfunction!(summary_specs, m)?)?;
    m.add_function(wrap_pyfunction!(trace_specs, m)?)?;
    Ok(())
}

//! Core errors cross into Python in one place: a `ParamError` (a `ValueError`) carrying the key, what
//! was expected, the value given and the related keys as attributes, so Python never parses text.

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use truckmpc_core::CoreError;

pyo3::create_exception!(
    _core,
    ParamError,
    PyValueError,
    "An invalid parameter: attributes `key`, `expected`, `got` (text or None) and `related` (keys the check involved)."
);

/// Turn a core error into a `ParamError` with its fields as attributes.
pub fn to_py(err: CoreError) -> PyErr {
    Python::attach(|py| {
        let message = err.to_string();
        let CoreError::Invalid { key, expected, got, related } = err;
        let py_err = ParamError::new_err(message);
        let value = py_err.value(py);
        let set = || -> PyResult<()> {
            value.setattr("key", key)?;
            value.setattr("expected", expected)?;
            value.setattr("got", got)?;
            value.setattr("related", related)?;
            Ok(())
        };
        set().err().unwrap_or(py_err)
    })
}

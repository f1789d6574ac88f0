//! Conversions between Python objects and the core's user values ([`Value`]).

use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use truckmpc_core::params::Value;

/// A Python object as a user value. Other types become their repr, which no parameter accepts.
pub fn to_value(obj: &Bound<'_, PyAny>) -> PyResult<Value> {
    if obj.is_none() {
        Ok(Value::Null)
    } else if obj.is_instance_of::<PyBool>() {
        Ok(Value::Bool(obj.extract()?))
    } else if obj.is_instance_of::<PyInt>() {
        Ok(obj.extract::<i64>().map(Value::Int).unwrap_or(Value::Float(obj.extract::<f64>().unwrap_or(f64::INFINITY))))
    } else if obj.is_instance_of::<PyFloat>() {
        Ok(Value::Float(obj.extract()?))
    } else if obj.is_instance_of::<PyString>() {
        Ok(Value::Text(obj.extract()?))
    } else if obj.is_instance_of::<PyList>() || obj.is_instance_of::<PyTuple>() {
        obj.try_iter()?.map(|item| to_value(&item?)).collect::<PyResult<Vec<_>>>().map(Value::List)
    } else {
        Ok(Value::Text(obj.repr()?.to_string()))
    }
}

/// A user value as a Python object (None, bool, int, float, str or list).
pub fn from_value<'py>(py: Python<'py>, value: &Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match value {
        Value::Null => py.None().into_bound(py),
        Value::Bool(b) => PyBool::new(py, *b).to_owned().into_any(),
        Value::Int(i) => i.into_pyobject(py)?.into_any(),
        Value::Float(x) => x.into_pyobject(py)?.into_any(),
        Value::Text(t) => t.into_pyobject(py)?.into_any(),
        Value::List(items) => {
            PyList::new(py, items.iter().map(|v| from_value(py, v)).collect::<PyResult<Vec<_>>>()?)?.into_any()
        }
    })
}

/// User values of a Python mapping, as (key, value) pairs.
pub fn pairs_of(values: &Bound<'_, PyDict>) -> PyResult<Vec<(String, Value)>> {
    values.iter().map(|(key, value)| Ok((key.extract::<String>()?, to_value(&value)?))).collect()
}

/// (key, value) pairs as a Python dict, in their order.
pub fn dict_of<'py>(py: Python<'py>, pairs: &[(&str, Value)]) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    for (key, value) in pairs {
        out.set_item(*key, from_value(py, value)?)?;
    }
    Ok(out)
}

/// A struct of the core's read off the same-named attributes of a Python object (a dataclass, a
/// reader's data): the core declares the fields once; the struct literal fails to compile if one is
/// left out. A missing attribute raises `AttributeError`, a value of the wrong type a `TypeError`
/// naming the field (`field_error`).
macro_rules! read_attrs {
    ($obj:expr, $kind:ident { $($field:ident),* $(,)? }) => {
        $kind { $($field: $obj.getattr(stringify!($field))?.extract().map_err(|err| {
            $crate::convert::field_error(stringify!($kind), stringify!($field), err)
        })?),* }
    };
}
pub(crate) use read_attrs;

/// A `TypeError` naming the field `kind.field` that could not be read, caused by `err`.
pub fn field_error(kind: &str, field: &str, err: impl Into<PyErr>) -> PyErr {
    Python::attach(|py| {
        let err = err.into();
        let named = PyTypeError::new_err(format!("failed to extract field {kind}.{field}: {}", err.value(py)));
        named.set_cause(py, Some(err));
        named
    })
}

//! Thin pyo3 binding of truckmpc-core, imported in Python as `truckmpc._core` and typed by
//! `python/truckmpc/_core.pyi`. No physics lives here: each call forwards to the core; core errors
//! become `ParamError` (a `ValueError`) with the key as an attribute (`errors.rs`).

mod convert;
mod errors;
mod outputs;
mod params;
mod powertrain;
mod road;
mod run;
mod signals;
mod vehicle;

use pyo3::prelude::*;

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("ParamError", m.py().get_type::<errors::ParamError>())?;
    m.add_function(wrap_pyfunction!(params::declaration, m)?)?;
    m.add_function(wrap_pyfunction!(params::parameter_value, m)?)?;
    m.add_class::<params::PySettings>()?;
    m.add_class::<vehicle::PyVehicle>()?;
    m.add_class::<road::PyRoad>()?;
    m.add_class::<powertrain::PyMapTruck>()?;
    m.add("G_MPS2", truckmpc_core::powertrain::G_MPS2)?;
    run::register(m)?;
    Ok(())
}

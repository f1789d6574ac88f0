//! Letting Python handle a signal (Ctrl-C, SIGTERM) while a run holds no GIL: the core asks
//! [`signalled`] now and then ([`truckmpc_core::stop`] says when), which takes the GIL back to run
//! the signal handlers; the first exception they raise stops the work and is returned.

use std::cell::Cell;

use pyo3::prelude::*;

thread_local! {
    /// The exception a signal handler raised during this thread's watched work.
    static RAISED: Cell<Option<PyErr>> = const { Cell::new(None) };
}

/// Run the signal handlers; whether one raised (its exception is kept for [`watching`]).
fn signalled() -> bool {
    let raised = Python::attach(|py| py.check_signals()).err();
    let stop = raised.is_some();
    RAISED.set(raised);
    stop
}

/// Run `work` (which releases the GIL) with signals watched; its result, or the exception a signal
/// handler raised.
pub fn watching<T>(work: impl FnOnce() -> T) -> PyResult<T> {
    RAISED.take();
    let out = truckmpc_core::stop::watched(signalled, work);
    RAISED.take().map_or(Ok(out), Err)
}

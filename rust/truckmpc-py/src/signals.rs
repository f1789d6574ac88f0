//! Letting Python handle a signal (Ctrl-C, SIGTERM) while a run holds no GIL: the run's thread
//! takes the GIL back at most every [`SIGNAL_CHECK_S`] to run the signal handlers, between
//! decisions of the closed loop and between stages of a DP solve (the core's
//! [`truckmpc_core::stop`] check), and the first exception they raise ends the run.

use std::cell::RefCell;
use std::time::Instant;

use pyo3::prelude::*;
use truckmpc_core::control::{Controller, Decision, RuleStats, SolverStats};
use truckmpc_core::{PlantState, Road};

/// How often a run with the GIL released looks for a signal to handle [s].
const SIGNAL_CHECK_S: f64 = 0.05;

/// One-step decisions (a plant step each, well under a microsecond) between two readings of the
/// clock: reading it at every step cost about a tenth of a PI run.
const STEPS_PER_CLOCK_READING: u32 = 64;

/// When this thread last ran the signal handlers, and the exception one raised.
struct Watch {
    checked: Instant,
    error: Option<PyErr>,
}

thread_local! {
    static WATCH: RefCell<Watch> = RefCell::new(Watch { checked: Instant::now(), error: None });
}

/// Run the signal handlers if [`SIGNAL_CHECK_S`] has passed since the last time; whether one
/// raised (now or before).
fn signalled() -> bool {
    WATCH.with(|watch| {
        let mut watch = watch.borrow_mut();
        if watch.error.is_none() && watch.checked.elapsed().as_secs_f64() > SIGNAL_CHECK_S {
            watch.checked = Instant::now();
            watch.error = Python::attach(|py| py.check_signals()).err();
        }
        watch.error.is_some()
    })
}

fn raised() -> bool {
    WATCH.with(|watch| watch.borrow().error.is_some())
}

/// Run `work` (which releases the GIL) with signals watched: the DP's stages ask [`signalled`]
/// too. Returns its result, or the exception a signal handler raised.
pub fn watching<T>(work: impl FnOnce() -> T) -> PyResult<T> {
    WATCH.with(|watch| *watch.borrow_mut() = Watch { checked: Instant::now(), error: None });
    let previous = truckmpc_core::stop::set_check(Some(signalled));
    let out = work();
    truckmpc_core::stop::set_check(previous);
    match WATCH.with(|watch| watch.borrow_mut().error.take()) {
        Some(err) => Err(err),
        None => Ok(out),
    }
}

/// A built-in controller whose run stops when a signal handler raised: the clock is read after
/// every held decision (a DP solve may have run) and every [`STEPS_PER_CLOCK_READING`] one-step
/// decisions.
pub struct Interruptible<'a> {
    pub inner: &'a mut (dyn Controller + Send),
    steps: u32,
}

impl<'a> Interruptible<'a> {
    pub fn new(inner: &'a mut (dyn Controller + Send)) -> Self {
        Interruptible { inner, steps: 0 }
    }
}

impl Controller for Interruptible<'_> {
    fn name(&self) -> &'static str {
        self.inner.name()
    }

    fn start(&mut self, road: &Road, state: &PlantState) {
        self.inner.start(road, state);
    }

    fn decide(&mut self, road: &Road, state: &PlantState) -> Decision {
        let decision = self.inner.decide(road, state);
        self.steps += 1;
        if decision.until_m.is_some() || self.steps >= STEPS_PER_CLOCK_READING {
            self.steps = 0;
            signalled();
        }
        decision
    }

    fn aborted(&self) -> bool {
        raised() || self.inner.aborted()
    }

    fn solver_stats(&self) -> Option<SolverStats> {
        self.inner.solver_stats()
    }

    fn rule_stats(&self) -> Option<RuleStats> {
        self.inner.rule_stats()
    }
}

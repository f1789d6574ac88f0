//! Closed-loop simulation of a cruise controller driving the truck over a road profile.
//!
//! The plant ([`crate::plant::Plant`]) integrates the vehicle model in time with RK4 at a fixed step
//! `plant_dt_s`; the last step is shortened so the run ends on the road's end. A controller
//! ([`crate::control::Controller`]) is asked for a decision whenever its previous one runs out:
//! after one plant step, or on reaching a distance. A truck whose speed falls below the stall speed
//! stops the run. The trace is sampled every `trace_step_m` metres of distance (and at the final
//! point) by linear interpolation between successive plant states; the inputs of a sample are those
//! applied over the step that crosses it.

pub mod run;
pub mod schema;
pub mod shifts;
pub mod summary;
pub mod trace;

pub use run::{run, run_on_map, RunOutput};
pub use schema::{OutputSpec, SUMMARY, TRACE};
pub use summary::RunSummary;
pub use trace::Trace;

pub use crate::KMH_PER_MPS;

/// A run (or a hold `until_m`) is complete within this distance of its target [m].
pub const ARRIVAL_TOLERANCE_M: f64 = 1e-6;

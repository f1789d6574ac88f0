//! The look-ahead controller's optimisation (thesis chapter 5): parameters, search space and the
//! backward dynamic program.

pub mod cache;
pub mod fuel_time;
pub mod horizon;
pub mod params;
pub mod rows;
pub mod shift;
pub mod simd;
pub mod solver;
pub mod space;
pub mod stage;
pub mod values;

pub use params::{CostKind, DpSettings, GridAnchor, NeutralRule, StageModel};
pub use solver::{InitialState, Solution, Solver, TrajectoryPoint};
pub use values::{StageValues, ValueTable};

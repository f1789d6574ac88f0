//! truckmpc-core: the physics and optimisation kernel of truckmpc, free of any Python dependency.
//!
//! - [`params`]: every parameter of a run, declared once (name with unit, type, default, range, doc);
//! - [`declarations`]: what the core declares (parameters, key changes, outputs), as records;
//! - [`vehicle`]: the built-in trucks behind one type, dispatched statically;
//! - [`figures`]: a model's answers as named figures, for the tools above the core;
//! - [`levels`]: pedal and brake levels joining two speeds (B.5, B.7) and stationary points (B.3);
//! - [`road`]: a road profile with piecewise-constant slope (and target speeds, if it has them);
//! - [`band`]: the speed band every cruise controller works to along a road;
//! - [`plant`]: the truck integrated in time at a fine step, for closed-loop simulation;
//! - [`powertrain`]: the interface every truck implements ([`powertrain::Powertrain`]), the thesis's
//!   model (chapter 2, appendix B.1) and a truck from component data (fuel map, full-load curve,
//!   driveline), as VECTO describes one;
//! - [`dp`]: the look-ahead controller's search space and backward dynamic program (chapter 5);
//! - [`control`]: the built-in cruise controllers, PI (section 2.5) and receding-horizon DP-MPC
//!   (section 5.6);
//! - [`sim`]: the closed loop driving the plant with a controller over a road, and its trace;
//! - [`scenario`]: the model of one run: settings and truck checked together, the controllers by
//!   name, and changed copies for the runs a study derives.

pub mod band;
pub mod control;
pub mod declarations;
pub mod dp;
pub mod error;
pub mod figures;
pub mod levels;
pub mod params;
pub mod plant;
pub mod powertrain;
pub mod road;
pub mod scenario;
pub mod sim;
pub mod stop;
pub mod vehicle;

pub use error::{CoreError, CoreResult};

/// Road speed conversion [km/h per m/s]: speeds are m/s inside the model, km/h at the interfaces.
pub const KMH_PER_MPS: f64 = 3.6;

pub use params::{CruiseParams, MpcParams, PiParams, RunSettings, SimParams};
pub use plant::{Control, Plant, PlantState};
pub use road::Road;
pub use vehicle::{Vehicle, VehicleParams, NEUTRAL};

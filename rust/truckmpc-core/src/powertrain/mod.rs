//! The trucks: the interface every kind of truck implements for the plant, the DP and the
//! controllers ([`interface`]), the thesis's model ([`thesis`]), whose torque and fuel are affine
//! in fueling, and a truck described by its component data, as VECTO (the EU's certification tool
//! for heavy trucks) describes it: an engine with a fuel map and full-load and drag curves, a
//! gearbox and axle with ratios and efficiencies, tyres, air drag, rolling resistance, mass and
//! auxiliary power, whose fuel rate is whatever the engine's map says at its speed and torque.
//!
//! - [`interface`]: the [`Powertrain`] trait, its control and its energy store;
//! - [`thesis`]: the thesis's model (chapter 2, appendix B.1);
//! - [`curve`]: a torque curve over engine speed (full load, drag), linear between its points;
//! - [`delaunay`]: a Delaunay triangulation built the way VECTO builds its maps;
//! - [`fuel_map`]: the fuel rate over engine speed and torque, linear on that triangulation;
//! - [`engine`]: the engine built from those;
//! - [`loss_map`]: a gear's or the axle's torque loss over speed and torque (VECTO's loss maps);
//! - [`driveline`]: gear and axle ratios, their losses, the tyre radius;
//! - [`retarder`]: a retarder's drag on the gearbox's input or output shaft;
//! - [`truck`]: the whole truck: road loads, engine operating points, the fuel to hold a speed;
//! - [`parts`]: a truck's component data as a file reader gives it, and the truck built from it;
//! - [`fuel_grid`]: the fuel map resampled on a regular grid, for fast evaluation;
//! - [`dynamics`]: the truck as the plant and the controllers drive it (pedal, brake, gear);
//! - [`electric`]: a battery-electric truck, its machines, reduction and battery.

pub mod curve;
pub mod delaunay;
pub mod driveline;
pub mod dynamics;
pub mod electric;
pub mod engine;
pub mod fuel_grid;
pub mod fuel_map;
pub mod interface;
pub mod loss_map;
pub mod parts;
pub mod retarder;
mod sampled;
pub mod thermal;
pub mod thesis;
pub mod truck;

#[cfg(test)]
mod dynamics_tests;
#[cfg(test)]
pub(crate) mod tests;

pub use curve::Curve;
pub use driveline::{Driveline, StageLosses};
pub use dynamics::MapModel;
pub use electric::{ElectricModel, ElectricParts, ElectricTruck};
pub use engine::Engine;
pub use fuel_grid::FuelGrid;
pub use fuel_map::FuelMap;
pub use interface::{AffineAccel, Control, EnergyStore, Powertrain, RateForm, NEUTRAL};
pub use loss_map::LossMap;
pub use parts::{DrivelineData, EngineData, TruckParts};
pub use retarder::{Retarder, RetarderPosition};
pub use thermal::{OverloadRating, Thermal, ThermalState};
pub use thesis::{GearConstants, ThesisModel};
pub use truck::{Body, MapTruck, OperatingPoint, RoadLoads, G_MPS2};

/// Engine speed [rpm] per angular speed [rad/s].
pub const RPM_PER_RAD_S: f64 = 60.0 / (2.0 * std::f64::consts::PI);

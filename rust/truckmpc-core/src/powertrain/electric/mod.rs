//! A battery-electric truck as VECTO declares it: electric machines at the axle (position E4)
//! through a reduction, a traction battery, electric auxiliaries.
//!
//! - [`machine`]: the machines' torque limits, drag and loss maps, blended at the battery's voltage;
//! - [`battery`]: the battery's voltage, resistance and current limits at a state of charge;
//! - [`truck`]: the component data as a reader gives it, and the truck built from it;
//! - [`model`]: the truck as the plant and the controllers drive it (pedal, brake, energy rate).

pub mod battery;
pub mod machine;
pub mod model;
pub mod truck;

#[cfg(test)]
mod tests;

pub use battery::{Battery, BatteryData};
pub use machine::{Machines, VoltageLevel};
pub use model::{ElectricModel, PowerFlows, RECUPERATION_MIN_MPS};
pub use truck::{ElectricParts, ElectricTruck, LevelData, MachineData, ReductionData};

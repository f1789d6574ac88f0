//! The built-in cruise controllers and the contract between them and the closed loop.
//!
//! A controller is asked for a decision at the current plant state and answers with the inputs to
//! apply and how long to hold them: `until_m: None` for one plant step (the PI of section 2.5, a
//! sampled controller running at the plant step), `Some(s)` until the truck reaches distance `s`
//! [m] or the road's end (the look-ahead controller of chapter 5, once per stage).

pub mod amt;
pub mod pcc;
pub mod pi;
pub mod receding;
pub mod rescue;
pub mod vecto_driver;

pub use pcc::{PccController, PccSegment, PccState};
pub use pi::{GearLogic, PiController};
pub use receding::{PlanStats, RecedingController, ShiftCounter, SolverStats};
pub use rescue::Rescue;
pub use vecto_driver::VectoDriver;

use crate::plant::{Control, PlantState};
use crate::road::Road;
use crate::vehicle::Vehicle;

/// Specific mechanical energy g·h + v²/2 [J/kg] of the truck at `s_m` [m] on `road` with speed
/// `v_mps` [m/s]: what the rule-based controllers compare to decide when to coast (the mass
/// cancels; h is relative to the road's first point).
pub fn specific_energy_j_per_kg(vehicle: &Vehicle, road: &Road, s_m: f64, v_mps: f64) -> f64 {
    vehicle.params().gravity_mps2 * road.altitude_at(s_m) + 0.5 * v_mps * v_mps
}

/// What the PCC did in a run: its use case 1 and 2 starts and its eco-roll engagements (each a
/// stretch in neutral with eco-roll fitted, counted apart from gear shifts).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct RuleStats {
    pub pcc_events: u64,
    pub eco_roll_entries: u64,
}

/// What [`Controller::decide`] returns: the inputs and until when to hold them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Decision {
    /// Pedal, brake and gear to apply (the plant clips the levels to [0, 1]).
    pub control: Control,
    /// Hold until this distance [m]; `None`: for one plant step.
    pub until_m: Option<f64>,
}

/// A cruise controller the closed loop ([`crate::sim::run`]) can drive.
pub trait Controller {
    /// Short name used in outputs (`"pi"`, `"mpc"`).
    fn name(&self) -> &'static str;

    /// Prepare for a run over `road` starting at `state` (resets any internal state).
    fn start(&mut self, road: &Road, state: &PlantState);

    /// Inputs to apply from `state` on, and until when.
    fn decide(&mut self, road: &Road, state: &PlantState) -> Decision;

    /// Whether the controller has failed (a controller written in another language whose code
    /// raised an error, say): the loop then stops without applying the decision just made, or
    /// asks for none after a failed `start`, and the caller reports the failure.
    fn aborted(&self) -> bool {
        false
    }

    /// Figures of an optimising controller's solves, for the run summary.
    fn solver_stats(&self) -> Option<SolverStats> {
        None
    }

    /// What a rule-based controller with look-ahead did, for the run summary.
    fn rule_stats(&self) -> Option<RuleStats> {
        None
    }
}

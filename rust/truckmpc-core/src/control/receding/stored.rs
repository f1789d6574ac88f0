//! Cost-to-go kept from one solve, with the grades and bands of its stages, and the short solves
//! that decide later stages from it: the whole-road optimum's plan, or a horizon solve whose next
//! stages are decided from it until the next horizon solve (`replan_m`).
//!
//! A DP's cost-to-go is a feedback law over its whole horizon: the control for the state the truck
//! actually reaches at a later stage comes from a solve against a later stage's stored values
//! (the next one, or the one where the shift limit lets the truck leave its gear), without solving
//! the rest of the horizon again.

use crate::dp::horizon::HorizonScratch;
use crate::dp::{InitialState, Solution, Solver, ValueTable};
use crate::vehicle::Vehicle;

/// One solve's cost-to-go and what its stages saw.
#[derive(Debug, Default)]
pub(super) struct Stored {
    /// Cost-to-go of every stage of the solve, stage 0 at its start.
    pub table: ValueTable,
    /// The grades of its stages and, on a road with target speeds, the bands at its boundaries
    /// (empty otherwise).
    pub ahead: HorizonScratch,
    /// The solve's first stage, counted from the run's origin.
    pub first: usize,
    /// How many stages from `first` on are decided from it.
    pub span: usize,
}

impl Stored {
    /// Values of a solve starting at stage `first` that decide `span` stages.
    pub fn starting(first: usize, span: usize) -> Self {
        Stored { first, span, ..Stored::default() }
    }

    /// The solve from `start` at the start of stage `k` (counted from the run's origin) against
    /// the stored values of a later stage; None where `k` is not among the stages decided from
    /// these values. It spans one stage, or while the shift limit keeps the truck in its gear
    /// beyond the next stage, every stage until the limit ends: the stored values are the best
    /// continuations of states regardless of the truck's last shift, and may shift sooner.
    pub fn decide(&self, solver: &mut Solver, vehicle: &Vehicle, k: usize, start: InitialState) -> Option<Solution> {
        let i = k.checked_sub(self.first).filter(|&i| i < self.span)?;
        let stages = solver.params().k_lim.saturating_sub(start.stages_since_shift).max(1) as usize;
        let next = self.table.stages.get(i + stages).filter(|next| next.count > 0)?;
        let slopes = self.ahead.slopes.get(i..i + stages)?;
        let bands = match self.ahead.bands.is_empty() {
            true => None,
            false => Some(self.ahead.bands.get(i..=i + stages)?),
        };
        Some(solver.solve_stages_to_values(vehicle, start, slopes, bands, next))
    }
}

//! Cost-to-go kept from one solve, with the grades and bands of its stages, and the one-stage
//! solves that decide later stages from it: the whole-road optimum's plan, or a horizon solve whose
//! next stages are decided from it until the next horizon solve (`replan_m`).
//!
//! A DP's cost-to-go is a feedback law over its whole horizon: the control for the state the truck
//! actually reaches at a later stage comes from a one-stage solve against the next stage's stored
//! values, without solving the rest of the horizon again.

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

    /// The one-stage solve from `start` at the start of stage `k` (counted from the run's origin)
    /// against the next stage's stored values; None where `k` is not among the stages decided
    /// from these values.
    pub fn decide(&self, solver: &mut Solver, vehicle: &Vehicle, k: usize, start: InitialState) -> Option<Solution> {
        let i = k.checked_sub(self.first).filter(|&i| i < self.span)?;
        let next = self.table.stages.get(i + 1)?;
        let slope = *self.ahead.slopes.get(i)?;
        let bands = self.ahead.bands.get(i..i + 2).map(|b| [b[0], b[1]]);
        Some(solver.solve_to_values(vehicle, start, slope, bands.as_ref(), next))
    }
}

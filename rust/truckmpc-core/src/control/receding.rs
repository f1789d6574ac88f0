//! The look-ahead cruise controller (thesis chapter 5) in the closed loop: the receding horizon of
//! section 5.6.
//!
//! Every S metres the controller predicts, with its own model (one Euler stage of (5.4)), the speed
//! at the start of the next stage under the inputs being applied now, solves the dynamic program
//! over the horizon from there, and keeps the first control of the optimum for that next stage.
//! Stage boundaries are counted from the road's start. When a solve finds no admissible path, the
//! controller keeps the inputs it is applying and counts the event.

use std::sync::Arc;
use std::time::Instant;

use super::pi::GearLogic;
use super::{Controller, Decision};
use crate::dp::{horizon, DpSettings, InitialState, Solver};
use crate::levels::stationary;
use crate::plant::{Control, PlantState};
use crate::road::Road;
use crate::vehicle::Vehicle;

/// Stages driven since the last gear shift, saturating at k_lim: the DP's shift constraint
/// (at least k_lim stages between shifts) carried from one solve to the next.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ShiftCounter {
    stages: u32,
    k_lim: u32,
}

impl ShiftCounter {
    /// A counter that allows a shift at once (k_lim stages since the last one).
    pub fn new(k_lim: u32) -> Self {
        ShiftCounter { stages: k_lim, k_lim }
    }

    /// Stages since the last shift (at most k_lim).
    pub fn stages(&self) -> u32 {
        self.stages
    }

    /// Count one more stage, driven in `gear` after `previous_gear`: a shift restarts the count at 1.
    pub fn record(&mut self, previous_gear: usize, gear: usize) {
        self.stages = if gear != previous_gear { 1 } else { (self.stages + 1).min(self.k_lim) };
    }
}

/// Figures of a run's DP solves.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SolverStats {
    /// Solves done.
    pub solves: u64,
    /// Solves that found no admissible path.
    pub infeasible_solves: u64,
    /// Wall time of all solves [s].
    pub solve_time_s: f64,
    /// Wall time of the longest solve [s].
    pub solve_time_max_s: f64,
    /// States over all solves.
    pub states: u64,
    /// Transitions over all solves.
    pub transitions: u64,
}

impl SolverStats {
    fn count(&self) -> f64 {
        self.solves.max(1) as f64
    }

    /// Mean wall time per solve [ms] (0 without solves).
    pub fn solve_ms_mean(&self) -> f64 {
        1e3 * self.solve_time_s / self.count()
    }

    /// Longest solve [ms].
    pub fn solve_ms_max(&self) -> f64 {
        1e3 * self.solve_time_max_s
    }

    /// Mean states per solve.
    pub fn states_per_solve(&self) -> f64 {
        self.states as f64 / self.count()
    }

    /// Mean transitions per solve.
    pub fn transitions_per_solve(&self) -> f64 {
        self.transitions as f64 / self.count()
    }
}

/// The DP-MPC as a [`Controller`]: decides once per stage, holding its inputs until the next stage
/// boundary.
#[derive(Debug)]
pub struct RecedingController {
    vehicle: Arc<Vehicle>,
    solver: Solver,
    /// The PI's gear logic, only for the gear the truck starts in.
    start_gears: GearLogic,
    slopes: Vec<f64>,
    origin_m: f64,
    shifts: ShiftCounter,
    gear: usize,
    pending: Control,
    stats: SolverStats,
}

impl RecedingController {
    /// A controller predicting with `vehicle`, solving with `params` (k_lim resolved) and starting
    /// in the gear `start_gears` settles in at the starting speed.
    pub fn new(vehicle: Arc<Vehicle>, params: DpSettings, start_gears: GearLogic) -> Self {
        let shifts = ShiftCounter::new(params.k_lim);
        RecedingController {
            vehicle,
            solver: Solver::new(params),
            start_gears,
            slopes: Vec::new(),
            origin_m: 0.0,
            shifts,
            gear: 0,
            pending: Control { pedal: 0.0, brake: 0.0, gear: 0 },
            stats: SolverStats::default(),
        }
    }

    /// Solve the horizon from `v_mps` [m/s] in `gear` at `s_m` [m]; the first control if feasible.
    fn solve(&mut self, road: &Road, s_m: f64, v_mps: f64, gear: usize) -> Option<Control> {
        let start = InitialState { v_mps, gear, stages_since_shift: self.shifts.stages() };
        let began = Instant::now();
        let solution = horizon::solve_at(&mut self.solver, &self.vehicle, road, s_m, start, &mut self.slopes);
        let elapsed_s = began.elapsed().as_secs_f64();
        let stats = &mut self.stats;
        stats.solves += 1;
        stats.solve_time_s += elapsed_s;
        stats.solve_time_max_s = stats.solve_time_max_s.max(elapsed_s);
        stats.states += solution.states as u64;
        stats.transitions += solution.transitions as u64;
        if !solution.feasible {
            stats.infeasible_solves += 1;
            return None;
        }
        Some(Control { pedal: solution.pedal, brake: solution.brake, gear: solution.gear })
    }

    /// Fallback before any feasible solve: the levels holding `v_mps` on a flat road in `gear`.
    fn holding(&self, v_mps: f64, gear: usize) -> Control {
        let level = stationary(&self.vehicle, v_mps, 0.0, gear);
        Control { pedal: level.pedal, brake: level.brake, gear }
    }
}

impl Controller for RecedingController {
    fn name(&self) -> &'static str {
        "mpc"
    }

    /// Solve the first stage from the starting state.
    fn start(&mut self, road: &Road, state: &PlantState) {
        self.origin_m = state.s_m;
        self.shifts = ShiftCounter::new(self.solver.params().k_lim);
        self.gear = self.start_gears.steady_gear(state.v_mps);
        self.stats = SolverStats::default();
        let first = self.solve(road, state.s_m, state.v_mps, self.gear);
        self.pending = first.unwrap_or_else(|| self.holding(state.v_mps, self.gear));
    }

    /// Apply the control chosen for this stage; solve the next stage from the predicted speed.
    fn decide(&mut self, road: &Road, state: &PlantState) -> Decision {
        let u = self.pending;
        self.shifts.record(self.gear, u.gear);
        self.gear = u.gear;
        let stage_m = self.solver.params().stage_m;
        let stage = ((state.s_m - self.origin_m) / stage_m).round_ties_even();
        let boundary_m = self.origin_m + (stage + 1.0) * stage_m;
        let v_next = horizon::predict_speed(&self.vehicle, road, state.s_m, state.v_mps, u, stage_m);
        let chosen = if v_next > 0.0 { self.solve(road, boundary_m, v_next, u.gear) } else { None };
        self.pending = chosen.unwrap_or(u);
        Decision { control: u, until_m: Some(boundary_m) }
    }

    fn solver_stats(&self) -> Option<SolverStats> {
        Some(self.stats)
    }
}

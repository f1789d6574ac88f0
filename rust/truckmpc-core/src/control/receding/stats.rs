//! What a look-ahead controller's run reports of its DP solves.

/// Figures of a run's DP solves.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SolverStats {
    /// Solves done, one per decision: a solve over the horizon or, between them (`replan_m`), a
    /// one-stage solve against the stored cost-to-go.
    pub solves: u64,
    /// Of the solves, those over the whole horizon.
    pub horizon_solves: u64,
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
    /// Relaxed solves (lower speed bound and shift limit relaxed) whose answer was driven.
    pub fallback_relaxed: u64,
    /// Times the controller fell back to the rescue policy (the PI's gear logic, full pedal).
    pub fallback_rescues: u64,
    /// Distance driven on the rescue policy [m].
    pub fallback_rescue_m: f64,
    /// The whole-road plan, for the whole-road optimum.
    pub plan: Option<PlanStats>,
}

/// What the whole-road optimum planned before driving: its prediction over the road by the DP's
/// own model and what the plan cost to compute.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PlanStats {
    /// Fuel of following the plan [kg] on the DP's own stage model, each stage decided from the
    /// state the model predicts as the controller decides from the plant's (NaN where the plan
    /// has no path, or the model's truck stops on the way).
    pub fuel_kg: f64,
    /// Trip time of following the plan [s], likewise.
    pub time_s: f64,
    /// Speed at the road's end of following the plan [m/s], likewise.
    pub end_v_mps: f64,
    /// The plan's optimal cost J_0.
    pub cost: f64,
    /// Wall time of the whole-road solve [s].
    pub solve_s: f64,
    /// Stages of the plan.
    pub stages: u64,
    /// Memory of its stored cost-to-go [bytes].
    pub table_bytes: u64,
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

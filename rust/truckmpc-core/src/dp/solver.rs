//! The backward dynamic program of section 5.6 over states (speed, gear) per stage, with the
//! shift counter of (5.6) and the cost (5.9).
//!
//! For a start speed and a target gear, the pedal level joining two speeds (B.5) is affine in the
//! end speed, so the end speeds reachable with P ∈ [−ε, 1 + ε] form one contiguous band of the next
//! grid: each state is joined only to that band (plus the brake points next to v_max and the one
//! neutral arc), not to every state of the next stage. The result is the same as the thesis's
//! all-pairs search, since every pair outside the band is infeasible there. The band's costs come
//! from [`super::rows`]; they are cached across solves ([`super::cache`]) while a stage's grids stay
//! the same, and what remains per solve is a min-plus pass over contiguous arrays.
//!
//! Shift limit: each state carries the number of stages until the next shift on its optimal
//! continuation (k_lim at the final stage). A shift into state j is allowed when that number is at
//! least k_lim, so the chosen path always keeps shifts k_lim stages apart. (The rule printed in 5.6,
//! 1 + c ≥ k_lim, would let them come k_lim − 1 stages apart, contradicting the forward counter of
//! (5.6).) Stages reached before the vehicle's own counter allows a shift keep the current gear.
//!
//! The solver's parts, one file each under `solver/`, in the order a solve runs them:
//! - `grids.rs`: each stage's speed grid and the gears that have states on it (the bounds of the
//!   search space);
//! - `ends.rs`: where a solve ends (the horizon's terminal cost, or stored values) and what it keeps;
//! - `first_pass.rs`: per stage and target gear, the best way from every speed into that gear;
//! - `arcs.rs`: the exact arcs (neutral, fuel-cut and full-pedal) and their joins to the next grid;
//! - `second_pass.rs`: per state, staying in its gear against the best shift;
//! - `choices.rs`: what the first pass leaves for the second, and the decisions kept per state;
//! - `trace.rs`: the traceback of the optimal path from the initial state.
//!
//! Units: speeds in m/s, costs in the dimensionless units of (5.9), stages counted from the
//! horizon's start.

mod arcs;
mod choices;
mod ends;
mod first_pass;
mod grids;
mod second_pass;
mod shifting;
#[cfg(test)]
mod tests;
mod trace;

use self::choices::{Choices, Decision};
use self::ends::Ends;
use self::grids::StageGrid;
use super::cache::{RecentRows, RowCache, RowScratch, StageKey, StageRows, PAD};
use super::params::DpSettings;
use super::rows::RowMemo;
use super::space::{self, Intervals};
use super::values::{StageValues, ValueTable};
use crate::band::BandAt;
use crate::vehicle::Vehicle;

const INF: f64 = f64::INFINITY;

/// Length of one gear's block of values for a grid of `count` points (margins included).
#[inline]
fn stride(count: usize) -> usize {
    count + 2 * PAD
}

/// Initial state of a solve: the speed predicted at the start of the horizon, the gear used on the
/// stage leading there, and the stages driven in that gear since the last shift.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InitialState {
    /// Speed [m/s].
    pub v_mps: f64,
    /// Gear (0 = neutral).
    pub gear: usize,
    /// Stages since the last gear shift (saturates at k_lim).
    pub stages_since_shift: u32,
}

/// One stage of the optimal predicted trajectory.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct TrajectoryPoint {
    /// Speed at the start of the stage [m/s]: on trapezoid stages the speed the decisions before
    /// give (off the grid after an arc), on Euler stages the grid speed.
    pub v_mps: f64,
    /// Grid speed of the stage's state in the plan [m/s].
    pub v_grid_mps: f64,
    /// Gear used over the stage.
    pub gear: usize,
    /// Pedal level over the stage.
    pub pedal: f64,
    /// Brake level over the stage.
    pub brake: f64,
}

/// What a solve returns.
#[derive(Debug, Clone, Default)]
pub struct Solution {
    /// Whether any admissible control sequence reaches the final stage.
    pub feasible: bool,
    /// Optimal cost J_0 (infinite when infeasible).
    pub cost: f64,
    /// First control: pedal level [0, 1].
    pub pedal: f64,
    /// First control: brake level [0, 1].
    pub brake: f64,
    /// First control: gear.
    pub gear: usize,
    /// Predicted optimal trajectory, one point per stage; the last point has the final speed and
    /// zero inputs.
    pub trajectory: Vec<TrajectoryPoint>,
    /// Number of (speed, gear) states in the search space.
    pub states: usize,
    /// Number of transitions whose cost entered the minimisation.
    pub transitions: usize,
}

/// A DP solver with its workspace; reuse one across solves so nothing is allocated per solve
/// once the buffers have grown (and so its row cache pays).
#[derive(Debug, Clone)]
pub struct Solver {
    params: DpSettings,
    caching: bool,
    intervals: Intervals,
    grids: Vec<StageGrid>,
    slope_torques: Vec<f64>,
    /// The speed band of each stage 0..=N of the solve under way.
    bands: Vec<BandAt>,
    /// Per stage and gear, the inclusive range of grid indices j where a state of that gear exists
    /// (empty when lo > hi). Indexed [stage * gears + gear].
    gear_ranges: Vec<(u32, u32)>,
    /// Per stage, the gears that have states there.
    active: Vec<Vec<usize>>,
    /// J_{k+1} per gear: a block of `stride(count)` values per gear, state j at
    /// [gear * stride + PAD + j], +∞ where a gear has no state (and in the margins).
    cost_next: Vec<f64>,
    /// cost_next where the state's continuation allows a shift into it, +∞ elsewhere.
    shift_next: Vec<f64>,
    /// Per gear, whether its block of shift_next equals cost_next bit for bit (every state's
    /// continuation allows a shift, or has no finite cost): one minimum then serves for both.
    shift_same_next: Vec<bool>,
    counter_next: Vec<u32>,
    cost_cur: Vec<f64>,
    shift_cur: Vec<f64>,
    shift_same_cur: Vec<bool>,
    counter_cur: Vec<u32>,
    /// Decisions per stage, flat; offsets[k] is the start of stage k, indexed [gear * count + i].
    decisions: Vec<Decision>,
    offsets: Vec<usize>,
    choices: Choices,
    scratch: RowScratch,
    /// What rows keep between calls: end-speed values, a map-based truck's pedal fuel table.
    row_memo: RowMemo,
    /// Rows of the stage being solved when they do not come from the cache.
    scratch_rows: StageRows,
    /// The memo of a shifting stage's rows (their length after the roll varies with the source).
    shift_memo: RowMemo,
    /// Where the first pass over shifting rows writes the choices it does not keep.
    shift_lanes: (Vec<f64>, Vec<u32>),
    /// The rolls of the stage under way's sources, for its shifting rows and arcs.
    rolls: shifting::StageRolls,
    cache: RowCache,
    /// Rows of the whole-road plan's stages (a recording solve off the cache's window), kept by key.
    recent: RecentRows,
    /// Whether the solve under way keeps its stages' rows in `recent`.
    keeps_rows_by_key: bool,
    /// Steps of the interval passes from earlier solves, by absolute stage.
    interval_memo: space::IntervalMemo,
    /// Whether the CPU has AVX2 (for the second pass), detected once.
    avx2: Option<Avx2Token>,
}

impl Solver {
    /// A solver for these parameters (built by [`DpSettings::new`], which validates). It caches
    /// transition costs across solves given their absolute stage, shared by the stages whose rows
    /// are the same (their slope, grids and band top).
    pub fn new(params: DpSettings) -> Self {
        Solver {
            params,
            caching: true,
            intervals: Intervals::default(),
            grids: Vec::new(),
            slope_torques: Vec::new(),
            bands: Vec::new(),
            gear_ranges: Vec::new(),
            active: Vec::new(),
            cost_next: Vec::new(),
            shift_next: Vec::new(),
            shift_same_next: Vec::new(),
            counter_next: Vec::new(),
            cost_cur: Vec::new(),
            shift_cur: Vec::new(),
            shift_same_cur: Vec::new(),
            counter_cur: Vec::new(),
            decisions: Vec::new(),
            offsets: Vec::new(),
            choices: Choices::default(),
            scratch: RowScratch::default(),
            row_memo: RowMemo::default(),
            scratch_rows: StageRows::default(),
            shift_memo: RowMemo::default(),
            shift_lanes: (Vec::new(), Vec::new()),
            rolls: shifting::StageRolls::default(),
            cache: RowCache::default(),
            recent: RecentRows::default(),
            keeps_rows_by_key: false,
            interval_memo: space::IntervalMemo::default(),
            avx2: Avx2Token::detect(),
        }
    }

    /// Turn the row cache off (or back on): the results are the same, only slower.
    pub fn set_caching(&mut self, on: bool) {
        self.caching = on;
    }

    /// Whether the row cache is on.
    pub fn caching(&self) -> bool {
        self.caching
    }

    /// The parameters.
    pub fn params(&self) -> &DpSettings {
        &self.params
    }

    /// Rows of transition costs computed so far by the cache (diagnostics).
    pub fn rows_computed(&self) -> u64 {
        self.cache.computed
    }

    /// Solve over the stages whose slopes are given (one grade per stage, N = slopes.len()).
    pub fn solve(&mut self, vehicle: &Vehicle, start: InitialState, slopes: &[f64]) -> Solution {
        self.solve_from_stage(vehicle, start, slopes, None)
    }

    /// As [`Solver::solve`], with the absolute index of the first stage on the road, which lets a
    /// fixed-grid solver reuse the transition costs of earlier solves.
    pub fn solve_from_stage(
        &mut self,
        vehicle: &Vehicle,
        start: InitialState,
        slopes: &[f64],
        first_stage: Option<u64>,
    ) -> Solution {
        self.solve_inner(vehicle, start, slopes, None, first_stage, Ends::Horizon)
    }

    /// As [`Solver::solve_from_stage`], with a speed band per stage 0..=N (`bands.len() ==
    /// slopes.len() + 1`) instead of the cruise band everywhere: a road with target speeds.
    pub fn solve_in_bands(
        &mut self,
        vehicle: &Vehicle,
        start: InitialState,
        slopes: &[f64],
        bands: &[BandAt],
        first_stage: Option<u64>,
    ) -> Solution {
        self.solve_inner(vehicle, start, slopes, Some(bands), first_stage, Ends::Horizon)
    }

    /// Solve over a whole road's stages at once (one grade per stage) and keep every stage's
    /// cost-to-go in `table` (stage k at index k), for one-stage solves against it later; `bands`
    /// as for [`Solver::solve_in_bands`] (None: the cruise band everywhere). The road's end is
    /// a horizon's end: with the fuel_time cost its speed is free and priced by the terminal cost,
    /// as the end-speed correction prices a run's.
    pub fn solve_recording(
        &mut self,
        vehicle: &Vehicle,
        start: InitialState,
        slopes: &[f64],
        bands: Option<&[BandAt]>,
        table: &mut ValueTable,
    ) -> Solution {
        table.stages.clear();
        table.stages.resize_with(slopes.len() + 1, StageValues::default);
        self.solve_inner(vehicle, start, slopes, bands, None, Ends::Recording(table))
    }

    /// As [`Solver::solve_from_stage`], keeping
    /// every stage's cost-to-go in `table` as [`Solver::solve_recording`] does: a horizon whose
    /// later stages are then decided by one-stage solves against it. `bands` as for
    /// [`Solver::solve_recording`].
    pub fn solve_horizon_recording(
        &mut self,
        vehicle: &Vehicle,
        start: InitialState,
        (slopes, bands): (&[f64], Option<&[BandAt]>),
        first_stage: Option<u64>,
        table: &mut ValueTable,
    ) -> Solution {
        table.stages.clear();
        table.stages.resize_with(slopes.len() + 1, StageValues::default);
        self.solve_inner(vehicle, start, slopes, bands, first_stage, Ends::Recording(table))
    }

    /// One stage on grade `slope` from `start`, ending on the states of `next` with their
    /// cost-to-go (a stage of a [`ValueTable`]) instead of the horizon's end; `bands`: the bands
    /// of the stage and the next (None: the cruise band).
    pub fn solve_to_values(
        &mut self,
        vehicle: &Vehicle,
        start: InitialState,
        slope: f64,
        bands: Option<&[BandAt; 2]>,
        next: &StageValues,
    ) -> Solution {
        self.solve_stages_to_values(vehicle, start, &[slope], bands.map(|b| &b[..]), next)
    }

    /// As [`Solver::solve_to_values`] over the stages whose grades are given, ending on the states
    /// of `next`; `bands` one per stage boundary 0..=N (None: the cruise band).
    pub fn solve_stages_to_values(
        &mut self,
        vehicle: &Vehicle,
        start: InitialState,
        slopes: &[f64],
        bands: Option<&[BandAt]>,
        next: &StageValues,
    ) -> Solution {
        self.solve_inner(vehicle, start, slopes, bands, None, Ends::Values(next))
    }

    fn solve_inner(
        &mut self,
        vehicle: &Vehicle,
        start: InitialState,
        slopes: &[f64],
        bands: Option<&[BandAt]>,
        first_stage: Option<u64>,
        mut ends: Ends,
    ) -> Solution {
        let n_stages = slopes.len();
        self.bands.clear();
        match bands {
            Some(given) => {
                assert_eq!(given.len(), n_stages + 1, "one band per stage 0..=N");
                self.bands.extend_from_slice(given);
            }
            None => self.bands.resize(n_stages + 1, self.params.band()),
        }
        let gears = vehicle.forward_gears() + 1;
        self.slope_torques.clear();
        self.slope_torques.extend(slopes.iter().map(|&a| vehicle.slope_torque_nm(a)));
        let terminal = match &ends {
            Ends::Values(next) => Some(*next),
            _ => None,
        };
        // Intervals, grids, gear ranges and active gears of every stage; the last stage's are those
        // of `terminal` when the solve ends on stored values.
        self.stage_grids(vehicle, start, slopes, first_stage, terminal);
        self.gear_states(vehicle, start, terminal);
        let cached_from = if self.caching { first_stage } else { None };
        self.keeps_rows_by_key = self.caching && first_stage.is_none() && matches!(ends, Ends::Recording(_));
        if let Some(stage) = cached_from {
            // Stage k of this solve (k ≥ 1 has grid states) is absolute stage `stage + k`.
            let keys = (1..n_stages).map(|k| StageKey {
                slope_torque_nm: self.slope_torques[k],
                origin_mps: self.grids[k].index.origin_mps,
                next_origin_mps: self.grids[k + 1].index.origin_mps,
                next_v_max_mps: self.bands[k + 1].v_max_mps(),
            });
            self.cache.prepare(stage + 1, keys);
        }
        let states = self.gear_ranges.iter().map(|&(lo, hi)| if hi >= lo { (hi - lo + 1) as usize } else { 0 }).sum();
        self.load_horizon_end(n_stages, gears, terminal);
        self.shift_same_cur.clear();
        self.shift_same_cur.resize(gears, true);
        if let Ends::Recording(table) = &mut ends {
            table.stages[n_stages] = self.stage_values(n_stages, gears, true);
        }

        let mut transitions = 0usize;
        for k in (0..n_stages).rev() {
            if crate::stop::requested() {
                // Asked to stop (a signal): no plan; the caller's loop ends at its next decision.
                return Solution { feasible: false, cost: f64::INFINITY, states, transitions, ..Solution::default() };
            }
            transitions += self.backward_stage(vehicle, k, cached_from.map(|s| s + k as u64), start.gear);
            if let (Ends::Recording(table), true) = (&mut ends, k > 0) {
                table.stages[k] = self.stage_values(k, gears, false);
            }
            std::mem::swap(&mut self.cost_cur, &mut self.cost_next);
            std::mem::swap(&mut self.shift_cur, &mut self.shift_next);
            std::mem::swap(&mut self.shift_same_cur, &mut self.shift_same_next);
            std::mem::swap(&mut self.counter_cur, &mut self.counter_next);
        }
        let cost = self.cost_next[start.gear * stride(1) + PAD];
        let mut solution = Solution { feasible: cost.is_finite(), cost, states, transitions, ..Solution::default() };
        if solution.feasible {
            self.trace(vehicle, start, &mut solution);
        }
        solution
    }

    /// J_k from J_{k+1} (in `cost_next`) into `cost_cur`. `abs_stage` is this stage's absolute
    /// index when rows may come from the cache. Returns the transitions evaluated.
    ///
    /// Two passes: first, per target gear, the best way from every velocity into that gear (the
    /// rows of one gear are contiguous, and so is the cost-to-go they are added to); then, per
    /// state, staying in its gear against the best shift.
    fn backward_stage(&mut self, vehicle: &Vehicle, k: usize, abs_stage: Option<u64>, start_gear: usize) -> usize {
        let gears = vehicle.forward_gears() + 1;
        let here = self.grids[k];
        // No clearing: the next stage reads only existing states (active gears, within their index
        // ranges), and every existing state is written below before that.
        let size = stride(here.count) * gears;
        if self.cost_cur.len() < size {
            self.cost_cur.resize(size, INF);
            self.shift_cur.resize(size, INF);
            self.counter_cur.resize(size, 0);
        }
        let active_here = std::mem::take(&mut self.active[k]);
        let active_next = std::mem::take(&mut self.active[k + 1]);
        // Velocities with at least one state here.
        let mut sources = (usize::MAX, 0usize);
        for &g in &active_here {
            let (lo, hi) = self.gear_ranges[k * gears + g];
            sources = (sources.0.min(lo as usize), sources.1.max(hi as usize));
        }
        let mut transitions = 0;
        if sources.0 <= sources.1 {
            self.choices.prepare(gears, here.first + sources.0 as i64, here.first + sources.1 as i64);
            transitions = self.best_per_target_gear(vehicle, k, abs_stage, sources, &active_next);
            self.stay_or_shift(vehicle, k, sources, &active_here, &active_next, (start_gear, gears));
        }
        self.active[k] = active_here;
        self.active[k + 1] = active_next;
        transitions
    }
}

/// Proof that the CPU has AVX2 (for the second pass).
#[derive(Debug, Clone, Copy)]
struct Avx2Token(());

impl Avx2Token {
    fn detect() -> Option<Self> {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            return Some(Avx2Token(()));
        }
        None
    }
}

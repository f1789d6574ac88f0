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

use super::cache::{Block, CoastArc, RowCache, RowScratch, StageKey, StageRows, LANES, PAD};
use super::params::{CostKind, DpSettings, GridAnchor, NeutralRule, StageModel};
use super::rows::{change_cost, forward_row, inputs, GridIndex};
#[cfg(target_arch = "x86_64")]
use super::simd::lanes::{self, pack, widen};
use super::simd::{self, LaneMins, LaneOut};
use super::space::{self, Grid, Intervals};
use super::stage::{self, Branch};
use super::values::{StageValues, ValueTable};
use crate::band::BandAt;
use crate::vehicle::{Vehicle, NEUTRAL};

const INF: f64 = f64::INFINITY;

/// Length of one gear's block of values for a grid of `count` points (margins included).
#[inline]
fn stride(count: usize) -> usize {
    count + 2 * PAD
}

/// Where a solve ends and what it keeps.
enum Ends<'a> {
    /// At the horizon's end, cost 0 on every final state.
    Horizon,
    /// At the horizon's end, keeping every stage's cost-to-go.
    Recording(&'a mut ValueTable),
    /// On stored states with their cost-to-go.
    Values(&'a StageValues),
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

/// What the first pass of a stage finds, per target gear and source slot [gear * width + slot]
/// (slot = source grid index − `base_key`, blocks of `LANES` aligned): the cheapest way into that
/// gear (fuel, speed change, brake and cost-to-go; +∞ when none) and the next-stage index it
/// reaches, and the same among targets that allow a shift now.
#[derive(Debug, Clone, Default)]
struct Choices {
    base_key: i64,
    width: usize,
    all_cost: Vec<f64>,
    all_j: Vec<u32>,
    shift_cost: Vec<f64>,
    shift_j: Vec<u32>,
    /// Per slot, the counter of the neutral choice (the interpolating rule takes the smaller of
    /// the two neighbours', so it is not the counter at all_j).
    neutral_counter: Vec<u32>,
    /// Per slot, the best and second-best shift targets over all gears: cost and gear.
    first_cost: Vec<f64>,
    first_gear: Vec<u32>,
    second_cost: Vec<f64>,
    second_gear: Vec<u32>,
    /// Per slot, the speed-deviation cost Q2·max(v_ref − v, 0)² of the source velocity.
    penalty: Vec<f64>,
    /// Per slot, the neutral state's best and second-best shifts when they differ from every
    /// other state's (only the highest usable gear, or leaving neutral free of Q4): cost and gear.
    exit_cost: Vec<f64>,
    exit_gear: Vec<u32>,
    exit2_cost: Vec<f64>,
    exit2_gear: Vec<u32>,
}

/// No gear (in the two best shifts).
const NO_GEAR: u32 = u32::MAX;

impl Choices {
    /// Room for `gears` target gears and source grid indices `key_lo..=key_hi`.
    fn prepare(&mut self, gears: usize, key_lo: i64, key_hi: i64) {
        let lanes = LANES as i64;
        self.base_key = key_lo.div_euclid(lanes) * lanes;
        self.width = (key_hi.div_euclid(lanes) * lanes + lanes - self.base_key) as usize;
        let size = gears * self.width;
        for v in [&mut self.all_cost, &mut self.shift_cost] {
            if v.len() < size {
                v.resize(size, INF);
            }
        }
        for v in [&mut self.all_j, &mut self.shift_j] {
            if v.len() < size {
                v.resize(size, 0);
            }
        }
        for v in [&mut self.first_cost, &mut self.second_cost, &mut self.exit_cost, &mut self.exit2_cost] {
            if v.len() < self.width {
                v.resize(self.width, INF);
            }
            v[..self.width].fill(INF);
        }
        for v in [&mut self.first_gear, &mut self.second_gear, &mut self.exit_gear, &mut self.exit2_gear] {
            if v.len() < self.width {
                v.resize(self.width, NO_GEAR);
            }
            v[..self.width].fill(NO_GEAR);
        }
        for v in [&mut self.neutral_counter] {
            if v.len() < self.width {
                v.resize(self.width, 0);
            }
        }
        if self.penalty.len() < self.width {
            self.penalty.resize(self.width, 0.0);
        }
    }
}

/// The decision stored for a state: the next state (grid index, gear) and whether the stage is
/// driven as a fuel-cut arc. `repr(C)`: the AVX2 second pass writes it as one u32, j in the low
/// half, the gear in the byte above and the top byte of the choice's index (its [`ARC`] flag) last.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
#[repr(C)]
struct Decision {
    j: u16,
    gear: u8,
    arc: u8,
}

impl Decision {
    /// The decision for a choice's next-grid index `j` (with its [`ARC`] flag) into `gear`.
    #[inline]
    fn new(j: u32, gear: u32) -> Self {
        Decision { j: j as u16, gear: gear as u8, arc: (j >> 24) as u8 }
    }
}

/// Flag on a choice's next-grid index (`all_j`, `shift_j`): the way into the target gear is its
/// fuel-cut arc, whose end speed is off the grid and whose control is zero pedal and brake; the
/// index is the grid point nearest to the arc's end. Grid indices stay below 2^16.
const ARC: u32 = 1 << 24;

/// Flag on a choice's next-grid index: the way into the target gear is its full-pedal arc (a
/// trapezoid stage's), whose end speed is off the grid and whose control is full pedal.
const FULL: u32 = 1 << 25;

/// Both flags of a choice's next-grid index.
const FLAGS: u32 = ARC | FULL;

/// One stage's grid: speeds of grid indices `first..first + count` of `index`.
#[derive(Debug, Clone, Copy)]
struct StageGrid {
    index: GridIndex,
    first: i64,
    count: usize,
}

impl StageGrid {
    #[inline]
    fn speed(&self, j: usize) -> f64 {
        self.index.speed(self.first + j as i64)
    }
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
    /// Rows of the stage being solved when they do not come from the cache.
    scratch_rows: StageRows,
    cache: RowCache,
    /// Steps of the interval passes from earlier solves, by absolute stage.
    interval_memo: space::IntervalMemo,
    /// Whether the CPU has AVX2 (for the second pass), detected once.
    avx2: Option<Avx2Token>,
}

impl Solver {
    /// A solver for these parameters (built by [`DpSettings::new`], which validates). It caches
    /// transition costs across solves given their absolute stage (while the stage's grids stay the
    /// same).
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
            scratch_rows: StageRows::default(),
            cache: RowCache::default(),
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
    /// as for [`Solver::solve_in_bands`] (None: the cruise band everywhere).
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
        self.solve_inner(vehicle, start, &[slope], bands.map(|b| &b[..]), None, Ends::Values(next))
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
        // A horizon of the fuel_time cost ends on its reachable speeds, priced by the terminal cost
        // (its kinetic energy in fuel): requiring v_ref there kept the truck from planning a coast
        // into a descent beyond the horizon. The whole road ends at v_ref, as every cost does.
        let raise_end = matches!(ends, Ends::Recording(_));
        self.build_space(vehicle, start, slopes, first_stage, terminal, raise_end);
        let cached_from = if self.caching { first_stage } else { None };
        if let Some(stage) = cached_from {
            // Stage k of this solve (k ≥ 1 has grid states) is absolute stage `stage + k`.
            let keys = (1..n_stages).map(|k| StageKey {
                slope_torque_nm: self.slope_torques[k],
                origin_mps: self.grids[k].index.origin_mps,
                next_origin_mps: self.grids[k + 1].index.origin_mps,
            });
            self.cache.prepare(stage + 1, keys);
        }
        let states = self.gear_ranges.iter().map(|&(lo, hi)| if hi >= lo { (hi - lo + 1) as usize } else { 0 }).sum();

        // Terminal cost 0 (fuel_time: the kinetic energy's); the counters of final states allow
        // any shift before them.
        let stride_last = stride(self.grids[n_stages].count);
        self.cost_next.clear();
        self.cost_next.resize(gears * stride_last, INF);
        self.counter_next.clear();
        self.counter_next.resize(gears * stride_last, self.params.k_lim);
        for g in 0..gears {
            let (lo, hi) = self.gear_ranges[n_stages * gears + g];
            if hi >= lo {
                let at = g * stride_last + PAD;
                let terminal = &mut self.cost_next[at + lo as usize..=at + hi as usize];
                terminal.fill(0.0);
                let weight = self.params.q_terminal_per_half_v2;
                let grid = self.grids[n_stages];
                if weight > 0.0 {
                    // The fuel_time cost values the speed left at the end: ½(v_ref² − v²) in fuel.
                    let v_ref = self.bands[n_stages].v_ref_mps();
                    for (cost, j) in terminal.iter_mut().zip(lo as usize..) {
                        let v = grid.speed(j);
                        *cost = weight * 0.5 * (v_ref * v_ref - v * v);
                    }
                }
                let q_time = self.params.q_time_per_s * self.params.stage_m;
                if q_time > 0.0 && self.params.stage_model == StageModel::Trapezoid {
                    // Each state is charged h/v (the stay_or_shift pass); the trapezoid's time along
                    // a path is that sum plus h/(2 v_N) at the end (less a constant h/(2 v_0)).
                    for (cost, j) in terminal.iter_mut().zip(lo as usize..) {
                        *cost += 0.5 * q_time / grid.speed(j);
                    }
                }
            }
        }
        self.shift_next.clone_from(&self.cost_next);
        self.shift_same_next.clear();
        self.shift_same_next.resize(gears, true);
        if let Some(next) = terminal {
            self.load_terminal(next, gears);
        }
        self.shift_same_cur.clear();
        self.shift_same_cur.resize(gears, true);
        if let Ends::Recording(table) = &mut ends {
            table.stages[n_stages] = self.stage_values(n_stages, gears, true);
        }

        let mut transitions = 0usize;
        for k in (0..n_stages).rev() {
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

    /// Stage `k`'s states and values: J_{k+1} in `cost_next` when `next` (the horizon's end,
    /// before the backward pass), else J_k just written to `cost_cur`.
    fn stage_values(&self, k: usize, gears: usize, next: bool) -> StageValues {
        let grid = self.grids[k];
        let ranges = &self.gear_ranges[k * gears..(k + 1) * gears];
        let mut values = StageValues::new(grid.index.origin_mps, grid.index.delta_mps, grid.first, grid.count, ranges);
        let (cost, counter) =
            if next { (&self.cost_next, &self.counter_next) } else { (&self.cost_cur, &self.counter_cur) };
        for (g, &(lo, hi)) in ranges.iter().enumerate() {
            if hi >= lo {
                let at = g * stride(grid.count) + PAD;
                let states = at + lo as usize..=at + hi as usize;
                values.set_gear(g, &cost[states.clone()], &counter[states]);
            }
        }
        values
    }

    /// The horizon's end on the states of `next`: their cost-to-go and counters, and the costs of
    /// those whose continuation allows a shift into them (+∞ elsewhere).
    fn load_terminal(&mut self, next: &StageValues, gears: usize) {
        let n = self.grids.len() - 1;
        let stride_last = stride(self.grids[n].count);
        for g in 0..gears {
            let (lo, hi) = self.gear_ranges[n * gears + g];
            for j in lo as usize..=hi as usize {
                let at = g * stride_last + PAD + j;
                let (cost, counter) = next.get(g, j).unwrap_or((INF, 0));
                (self.cost_next[at], self.counter_next[at]) = (cost, counter);
                self.shift_next[at] = if counter >= self.params.k_lim { cost } else { INF };
                if self.shift_next[at].to_bits() != cost.to_bits() {
                    self.shift_same_next[g] = false;
                }
            }
        }
    }

    /// Intervals, grids, gear ranges and active gears of every stage; the last stage's are those
    /// of `terminal` when the solve ends on stored values.
    fn build_space(
        &mut self,
        vehicle: &Vehicle,
        start: InitialState,
        slopes: &[f64],
        first_stage: Option<u64>,
        terminal: Option<&StageValues>,
        raise_end: bool,
    ) {
        // Absolute stages, when known, let the interval passes reuse steps of earlier solves.
        let p = &self.params;
        let memo = first_stage.filter(|_| self.caching).map(|stage| (stage, &mut self.interval_memo));
        let raise_end = raise_end || p.cost == CostKind::SpeedPenalty;
        space::intervals_from_stage(vehicle, p, start.v_mps, slopes, &self.bands, memo, raise_end, &mut self.intervals);
        let delta = p.delta_mps();
        self.grids.clear();
        self.grids.push(StageGrid {
            index: GridIndex { origin_mps: start.v_mps, delta_mps: delta },
            first: 0,
            count: 1,
        });
        for k in 1..=slopes.len() {
            let Grid { first_mps, count } = space::grid(p, self.intervals.lo[k], self.intervals.hi[k]);
            self.grids.push(match p.grid {
                GridAnchor::Moving => {
                    StageGrid { index: GridIndex { origin_mps: first_mps, delta_mps: delta }, first: 0, count }
                }
                GridAnchor::Fixed => StageGrid {
                    index: GridIndex { origin_mps: 0.0, delta_mps: delta },
                    first: (first_mps / delta).round() as i64,
                    count,
                },
            });
        }
        if let Some(next) = terminal {
            let index = GridIndex { origin_mps: next.origin_mps, delta_mps: next.delta_mps };
            *self.grids.last_mut().expect("a stage") = StageGrid { index, first: next.first, count: next.count };
        }
        let gears = vehicle.forward_gears() + 1;
        let last = self.grids.len() - 1;
        // Stages 1..=forced are reached before the shift limit lets the truck leave its gear.
        let forced = p.k_lim.saturating_sub(start.stages_since_shift) as usize;
        self.gear_ranges.clear();
        self.active.resize(self.grids.len(), Vec::new());
        // Per gear, the grid indices with engine speed in [n_min, n_max]: the same for every stage
        // of one grid index (all stages of a fixed grid), so computed only when the index changes.
        let (mut rpm_indices, mut rpm_of) = (vec![(0i64, -1i64); gears], None);
        for (k, grid) in self.grids.iter().enumerate() {
            let full = (0u32, grid.count as u32 - 1);
            self.active[k].clear();
            if rpm_of != Some(grid.index) {
                for (g, bounds) in rpm_indices.iter_mut().enumerate().filter(|&(g, _)| g != NEUTRAL) {
                    let c4 = vehicle.gear(g).c4;
                    *bounds = (grid.index.ceil(p.n_min_rpm / c4), grid.index.floor(p.n_max_rpm / c4));
                }
                rpm_of = Some(grid.index);
            }
            for (g, &(rpm_lo, rpm_hi)) in rpm_indices.iter().enumerate() {
                let stored = terminal.filter(|_| k == last).map(|next| next.ranges.get(g).copied().unwrap_or((1, 0)));
                let range = if (k == 0 || k <= forced) && g != start.gear {
                    (1, 0)
                } else if let Some(range) = stored {
                    range
                } else if k == 0 || k <= forced {
                    full
                } else if g == NEUTRAL {
                    if p.allow_neutral {
                        full
                    } else {
                        (1, 0)
                    }
                } else {
                    // Engine speed in [n_min, n_max]: an interval of speeds, so of grid indices.
                    let (lo, hi) = ((rpm_lo - grid.first).max(0), (rpm_hi - grid.first).min(full.1 as i64));
                    if hi >= lo {
                        (lo as u32, hi as u32)
                    } else {
                        (1, 0)
                    }
                };
                if range.1 >= range.0 {
                    self.active[k].push(g);
                }
                self.gear_ranges.push(range);
            }
        }
        self.offsets.clear();
        let mut total = 0;
        for grid in &self.grids {
            self.offsets.push(total);
            total += grid.count * gears;
        }
        // Every decision on a traced path is written before it is read: no need to clear.
        if self.decisions.len() < total {
            self.decisions.resize(total, Decision::default());
        }
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

    /// First pass of a stage: for every source velocity in `sources` and every target gear, the
    /// best next state and the best one that allows a shift now, into `choices`. Returns the
    /// transitions evaluated.
    fn best_per_target_gear(
        &mut self,
        vehicle: &Vehicle,
        k: usize,
        abs_stage: Option<u64>,
        (i_lo, i_hi): (usize, usize),
        active_next: &[usize],
    ) -> usize {
        let gears = vehicle.forward_gears() + 1;
        let (here, next) = (self.grids[k], self.grids[k + 1]);
        let p = &self.params;
        let v_max_next = self.bands[k + 1].v_max_mps();
        let mut uncounted = 0;
        let (stage, computed): (&mut StageRows, &mut u64) = match abs_stage {
            Some(stage) if k > 0 => self.cache.stage(stage),
            _ => {
                self.scratch_rows.reset(StageKey { slope_torque_nm: self.slope_torques[k], ..StageKey::default() });
                (&mut self.scratch_rows, &mut uncounted)
            }
        };
        let slope_torque = self.slope_torques[k];
        let (key_lo, key_hi) = (here.first + i_lo as i64, here.first + i_hi as i64);
        let ch = &mut self.choices;
        let mut transitions = 0;
        for &g in active_next {
            let (lo, hi) = self.gear_ranges[(k + 1) * gears + g];
            let out = g * ch.width;
            if g == NEUTRAL {
                let arcs = stage.arcs(NEUTRAL);
                arcs.fill(key_lo, key_hi, |key| coast_arc(p, vehicle, here.index.speed(key), NEUTRAL, slope_torque));
                let slot0 = (key_lo - ch.base_key) as usize;
                let join = ArcJoin::new(p, next, (lo, hi));
                let (cost_next, counter_next) = (&self.cost_next[PAD..], &self.counter_next[PAD..]);
                let arcs = arcs.get(key_lo, key_hi);
                let (slots, at) = (slot0..slot0 + arcs.len(), out + slot0..out + slot0 + arcs.len());
                let (all_cost, all_j) = (&mut ch.all_cost[at.clone()], &mut ch.all_j[at.clone()]);
                let (shift_cost, shift_j) = (&mut ch.shift_cost[at.clone()], &mut ch.shift_j[at]);
                let counters = &mut ch.neutral_counter[slots];
                let mut done = 0;
                #[cfg(target_arch = "x86_64")]
                if let (NeutralRule::Nearest, Some(_)) = (p.neutral_rule, self.avx2) {
                    let out = NeutralOut { all_cost, all_j, counters, shift_cost, shift_j };
                    // SAFETY: the token exists only where the CPU has AVX2.
                    done = unsafe { join_nearest_avx2(&join, arcs, (cost_next, counter_next), p.k_lim, out) };
                }
                for (s, arc) in arcs.iter().enumerate().skip(done) {
                    let (cost, j, counter) = join.join(arc, cost_next, counter_next);
                    (all_cost[s], all_j[s], counters[s]) = (cost, j, counter);
                    (shift_cost[s], shift_j[s]) = (if counter >= p.k_lim { cost } else { INF }, j);
                }
                // Shifting into neutral from a forward gear is an engagement: its price, in place of
                // Q4 (which the second pass adds to every shift) where Q4 prices forward shifts only.
                let engagement = p.q_neutral - if p.shift_price_neutral { 0.0 } else { p.q_gear_shift };
                if engagement != 0.0 {
                    shift_cost.iter_mut().for_each(|c| *c += engagement);
                }
                transitions += i_hi - i_lo + 1;
                continue;
            }
            let rows = stage.gear(g);
            *computed += rows.fill(key_lo, key_hi, &mut self.scratch, |key, buf| {
                forward_row(vehicle, p, here.index.speed(key), g, slope_torque, next.index, v_max_next, buf)
            });
            let values = g * stride(next.count)..(g + 1) * stride(next.count);
            let (blocks, first_key) = rows.get(key_lo, key_hi);
            debug_assert_eq!(first_key, ch.base_key);
            let pass = GearPass {
                blocks,
                costs: &rows.costs,
                next_first: next.first,
                lo,
                hi,
                to_go: &self.cost_next[values.clone()],
                shiftable: &self.shift_next[values],
                same: self.shift_same_next[g],
                first_key,
                key_lo,
                key_hi,
            };
            let span = out..out + blocks.len() * LANES;
            let choices = GearChoices {
                all_cost: &mut ch.all_cost[span.clone()],
                all_j: &mut ch.all_j[span.clone()],
                shift_cost: &mut ch.shift_cost[span.clone()],
                shift_j: &mut ch.shift_j[span],
            };
            transitions += gear_pass_dispatch(&pass, choices);
            // Fuel cut, and on trapezoid stages (whose rows stop at full pedal) full pedal too, as
            // exact arcs: (cache slot, input held, join, flag of the choice).
            let fuel_cut = p.fuel_cut_arcs.then(|| (g, (Branch::Brake, 0.0), ArcJoin::new(p, next, (lo, hi)), ARC));
            let full = (p.stage_model == StageModel::Trapezoid)
                .then(|| (gears + g, (Branch::Pedal, 1.0), ArcJoin::full_pedal(p, next, (lo, hi)), FULL));
            let block = g * stride(next.count) + PAD;
            let slot0 = out + (key_lo - ch.base_key) as usize;
            for (slot, input, join, flag) in fuel_cut.into_iter().chain(full) {
                let arcs = stage.arcs(slot);
                arcs.fill(key_lo, key_hi, |key| exact_arc(p, vehicle, here.index.speed(key), g, slope_torque, input));
                let (cost_next, counter_next) = (&self.cost_next[block..], &self.counter_next[block..]);
                for (at, arc) in (slot0..).zip(arcs.get(key_lo, key_hi)) {
                    // The counter of the grid point the path continues from, not the stencil's
                    // smallest (the neutral state's rule): this arc's state is a forward gear's.
                    let (cost, j, _) = join.join(arc, cost_next, counter_next);
                    better_by_arc(cost, j | flag, counter_next[j as usize] >= p.k_lim, ch, at);
                }
                transitions += (key_hi - key_lo + 1) as usize;
            }
        }
        transitions
    }

    /// Second pass of a stage: for every state, stay in its gear or take the best shift, plus the
    /// speed-deviation cost; writes J_k, the counters and the decisions.
    fn stay_or_shift(
        &mut self,
        vehicle: &Vehicle,
        k: usize,
        (i_lo, i_hi): (usize, usize),
        active_here: &[usize],
        active_next: &[usize],
        (start_gear, gears): (usize, usize),
    ) {
        let (here, next) = (self.grids[k], self.grids[k + 1]);
        let n = here.count;
        let v_ref = self.bands[k].v_ref_mps();
        let (q_speed_below, q4, k_lim) = (self.params.q_speed_below, self.params.q_gear_shift, self.params.k_lim);
        let ch = &mut self.choices;
        // Slot of source velocity i.
        let s0 = (here.first - ch.base_key) as usize;
        let sources = s0 + i_lo..s0 + i_hi + 1;
        // The two best shift targets per velocity, so that each state's best shift to another
        // gear is O(1). Gears are scanned in order, keeping the first of equal costs.
        for &g in active_next {
            let costs = &ch.shift_cost[g * ch.width + sources.start..g * ch.width + sources.end];
            let first_cost = &mut ch.first_cost[sources.clone()];
            let first_gear = &mut ch.first_gear[sources.clone()];
            let second_cost = &mut ch.second_cost[sources.clone()];
            let second_gear = &mut ch.second_gear[sources.clone()];
            let m = costs.len();
            assert!(first_cost.len() == m && first_gear.len() == m && second_cost.len() == m && second_gear.len() == m);
            let mut done = 0;
            #[cfg(target_arch = "x86_64")]
            if self.avx2.is_some() {
                // SAFETY: the token exists only where the CPU has AVX2; the lengths are checked above.
                done = unsafe { rank_avx2(costs, g as u32, (first_cost, first_gear), (second_cost, second_gear)) };
            }
            for t in done..m {
                let c = costs[t];
                if c < first_cost[t] {
                    (second_cost[t], second_gear[t]) = (first_cost[t], first_gear[t]);
                    (first_cost[t], first_gear[t]) = (c, g as u32);
                } else if c < second_cost[t] {
                    (second_cost[t], second_gear[t]) = (c, g as u32);
                }
            }
        }
        // The speed-deviation cost of each source velocity, once for all its gears (the same
        // operations as per state, so the same bits).
        for (slot, i) in ch.penalty[sources.clone()].iter_mut().zip(i_lo..) {
            let below = (v_ref - here.speed(i)).max(0.0);
            *slot = q_speed_below * below * below;
        }
        // The fuel_time cost's time: h / v_i per stage, exact to second order in S along a path
        // (the left sum differs from the trapezoid by the constant first term and half the last).
        let q_time = self.params.q_time_per_s * self.params.stage_m;
        if q_time > 0.0 {
            for (slot, i) in ch.penalty[sources.clone()].iter_mut().zip(i_lo..) {
                *slot += q_time / here.speed(i);
            }
        }
        let p = &self.params;
        let exit_own = active_here.contains(&NEUTRAL) && (p.neutral_exit_top_gear || !p.shift_price_neutral);
        if exit_own {
            // Leaving neutral is not charged Q4 where Q4 prices forward shifts only (the second
            // pass adds Q4 to every shift), and goes only into the highest usable gear where so set.
            let free = if p.shift_price_neutral { 0.0 } else { q4 };
            let (n_min, n_max) = (p.n_min_rpm, p.n_max_rpm);
            for (slot, i) in sources.clone().zip(i_lo..) {
                let (exit, second) = if p.neutral_exit_top_gear {
                    let top = space::usable_gears(vehicle, here.speed(i), n_min, n_max).map(|(_, hi)| hi);
                    let exit = match top {
                        Some(g) if active_next.contains(&g) => (ch.shift_cost[g * ch.width + slot], g as u32),
                        _ => (INF, NO_GEAR),
                    };
                    (exit, (INF, NO_GEAR))
                } else {
                    ((ch.first_cost[slot], ch.first_gear[slot]), (ch.second_cost[slot], ch.second_gear[slot]))
                };
                (ch.exit_cost[slot], ch.exit_gear[slot]) = (exit.0 - free, exit.1);
                (ch.exit2_cost[slot], ch.exit2_gear[slot]) = (second.0 - free, second.1);
            }
        }
        let stride_n = stride(next.count);
        for &g_i in active_here {
            let (lo, hi) = self.gear_ranges[k * gears + g_i];
            if (k == 0 && g_i != start_gear) || hi < lo {
                continue;
            }
            let stays = active_next.contains(&g_i);
            let (lo, hi) = (lo as usize, hi as usize);
            let slots = s0 + lo..s0 + hi + 1;
            let out = g_i * ch.width + slots.start..g_i * ch.width + slots.end;
            let values = g_i * stride(n) + PAD + lo..g_i * stride(n) + PAD + hi + 1;
            let decisions = self.offsets[k] + g_i * n + lo..self.offsets[k] + g_i * n + hi + 1;
            let state = StateOut {
                cost: &mut self.cost_cur[values.clone()],
                counter: &mut self.counter_cur[values.clone()],
                shift: &mut self.shift_cur[values],
                decision: &mut self.decisions[decisions],
            };
            let (ranked, ranked_gears) = if exit_own && g_i == NEUTRAL {
                ([&ch.exit_cost, &ch.exit2_cost], [&ch.exit_gear, &ch.exit2_gear])
            } else {
                ([&ch.first_cost, &ch.second_cost], [&ch.first_gear, &ch.second_gear])
            };
            let ranked = ranked.map(|costs| &costs[slots.clone()]);
            let ranked_gears = ranked_gears.map(|gears| &gears[slots.clone()]);
            let input = StateIn {
                gear: g_i as u32,
                slot0: slots.start,
                all_cost: &ch.all_cost[out.clone()],
                all_j: &ch.all_j[out],
                first_cost: ranked[0],
                first_gear: ranked_gears[0],
                second_cost: ranked[1],
                second_gear: ranked_gears[1],
                neutral_counter: &ch.neutral_counter[slots.clone()],
                penalty: &ch.penalty[slots],
                shift_j: &ch.shift_j,
                width: ch.width,
                counter_next: &self.counter_next[g_i * stride_n + PAD..(g_i + 1) * stride_n],
                q4,
                k_lim,
            };
            self.shift_same_cur[g_i] = match (stays, g_i == NEUTRAL) {
                (false, _) => decide_states::<false, false>(input, state, None),
                (true, false) => decide_states::<true, false>(input, state, self.avx2),
                (true, true) => decide_states::<true, true>(input, state, self.avx2),
            };
            // The rest of the gear's block (no state there) is +∞ for the min-plus pass.
            let block = g_i * stride(n)..(g_i + 1) * stride(n);
            for part in [block.start..block.start + PAD + lo, block.start + PAD + hi + 1..block.end] {
                self.cost_cur[part.clone()].fill(INF);
                self.shift_cur[part].fill(INF);
            }
        }
    }

    /// Follow the stored decisions from the initial state to fill the first control and the
    /// predicted trajectory; the inputs of each step are recomputed from its two speeds.
    fn trace(&self, vehicle: &Vehicle, start: InitialState, out: &mut Solution) {
        let (mut i, mut g) = (0usize, start.gear);
        let mut v = start.v_mps;
        // On trapezoid stages the trajectory follows the speeds the decisions give (an arc ends
        // off the grid, and the next stage's inputs aim at its planned grid speed from there), so
        // the plan's fuel and time are those of driving it; on Euler stages it runs on the grid.
        let exact = self.params.stage_model == StageModel::Trapezoid;
        out.trajectory.clear();
        for k in 0..self.grids.len() - 1 {
            let d = self.decisions[self.offsets[k] + g * self.grids[k].count + i];
            let (next_i, next_g) = (d.j as usize, d.gear as usize);
            let v_next = self.grids[k + 1].speed(next_i);
            let (pedal, brake) = if next_g == NEUTRAL || d.arc == (ARC >> 24) as u8 {
                (0.0, 0.0)
            } else if d.arc == (FULL >> 24) as u8 {
                (1.0, 0.0)
            } else {
                let v_max = self.bands[k + 1].v_max_mps();
                let torque = self.slope_torques[k];
                let planned = |from: f64| inputs(vehicle, &self.params, (from, v_next, v_max), next_g, torque);
                let u = planned(v)
                    .or_else(|| planned(self.grids[k].speed(i)))
                    .unwrap_or(super::rows::Inputs { pedal: 0.0, brake: 0.0 });
                (u.pedal, u.brake)
            };
            let v_grid_mps = self.grids[k].speed(i);
            out.trajectory.push(TrajectoryPoint { v_mps: v, v_grid_mps, gear: next_g, pedal, brake });
            v = if exact {
                let h = self.params.stage_m;
                let input = (pedal, brake, next_g);
                stage::end_speed_with(self.params.stage_model, vehicle, (v, h), input, self.slope_torques[k])
            } else {
                v_next
            };
            i = next_i;
            g = next_g;
        }
        let v_grid_mps = self.grids[self.grids.len() - 1].speed(i);
        out.trajectory.push(TrajectoryPoint { v_mps: v, v_grid_mps, gear: g, pedal: 0.0, brake: 0.0 });
        let first = out.trajectory[0];
        out.pedal = first.pedal;
        out.brake = first.brake;
        out.gear = first.gear;
    }
}

/// What the second pass reads for the states of one gear at one stage (slices over its states).
struct StateIn<'a> {
    gear: u32,
    /// Choice slot of the first state.
    slot0: usize,
    all_cost: &'a [f64],
    all_j: &'a [u32],
    first_cost: &'a [f64],
    first_gear: &'a [u32],
    second_cost: &'a [f64],
    second_gear: &'a [u32],
    neutral_counter: &'a [u32],
    penalty: &'a [f64],
    /// All gears' shift targets, [gear * width + slot].
    shift_j: &'a [u32],
    width: usize,
    /// The gear's counters at the next stage, from index 0.
    counter_next: &'a [u32],
    q4: f64,
    k_lim: u32,
}

/// What the second pass writes for the states of one gear at one stage.
struct StateOut<'a> {
    cost: &'a mut [f64],
    counter: &'a mut [u32],
    shift: &'a mut [f64],
    decision: &'a mut [Decision],
}

/// Stay in the gear or take the best shift to another, per state. `STAYS`: the gear has states at
/// the next stage; `NEUTRAL_STATE`: the gear is neutral (whose counter comes with its choice).
/// Returns whether every state's shiftable cost equals its cost bit for bit.
#[inline(always)]
fn decide_states<const STAYS: bool, const NEUTRAL_STATE: bool>(
    input: StateIn,
    mut out: StateOut,
    avx2: Option<Avx2Token>,
) -> bool {
    let m = out.cost.len();
    // Equal lengths, stated once: the loop below then needs no bounds checks on them.
    assert!(
        input.all_cost.len() == m
            && input.all_j.len() == m
            && input.first_cost.len() == m
            && input.first_gear.len() == m
            && input.second_cost.len() == m
            && input.second_gear.len() == m
            && input.neutral_counter.len() == m
            && input.penalty.len() == m
    );
    assert!(out.counter.len() == m && out.shift.len() == m && out.decision.len() == m);
    let (mut blocked, mut done) = (false, 0);
    #[cfg(target_arch = "x86_64")]
    if let (true, Some(_)) = (STAYS, avx2) {
        // SAFETY: the token exists only where the CPU has AVX2; the lengths are checked above.
        (done, blocked) = unsafe { decide_staying_avx2::<NEUTRAL_STATE>(&input, &mut out) };
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = avx2;
    for t in done..m {
        let stay_cost = if STAYS { input.all_cost[t] } else { INF };
        // The best shift to another gear. With none, its cost is +∞ and never beats staying.
        let own = input.first_gear[t] == input.gear;
        let shift_cost = (if own { input.second_cost[t] } else { input.first_cost[t] }) + input.q4;
        let (best_cost, decision, counter) = if shift_cost < stay_cost {
            let shift_gear = if own { input.second_gear[t] } else { input.first_gear[t] };
            let j = input.shift_j[shift_gear as usize * input.width + input.slot0 + t];
            (shift_cost, Decision::new(j, shift_gear), 1)
        } else {
            let j = if STAYS { input.all_j[t] } else { 0 };
            let carried = if !STAYS || !(stay_cost < INF) {
                0
            } else if NEUTRAL_STATE {
                input.neutral_counter[t]
            } else {
                input.counter_next[(j & !FLAGS) as usize]
            };
            (stay_cost, Decision::new(j, input.gear), carried.saturating_add(1).min(u32::MAX / 2))
        };
        let total = best_cost + input.penalty[t];
        out.cost[t] = total;
        out.counter[t] = counter;
        let shiftable = counter >= input.k_lim;
        // Not shiftable and not +∞: the shiftable cost (+∞) differs from the cost.
        blocked |= !shiftable & (total != INF);
        out.shift[t] = if shiftable { total } else { INF };
        out.decision[t] = decision;
    }
    // Otherwise each shiftable cost is its cost (or both are +∞): the same bits.
    !blocked
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

/// [`decide_states`] for a gear that stays, four states at a time in AVX2, as far as whole
/// groups of four go: returns the states done and whether one of them was blocked. Every value is
/// the scalar loop's: the same additions (shift + Q4, best + Q2 term), comparisons and selects,
/// and the counters' integer rules (saturating +1, at most u32::MAX / 2, ≥ k_lim). `NEUTRAL_STATE`:
/// the counter carried by staying is the neutral choice's own, not the target state's.
///
/// # Safety
/// The CPU must have AVX2, and the slices of `input` and `out` the lengths `decide_states` checks.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn decide_staying_avx2<const NEUTRAL_STATE: bool>(input: &StateIn, out: &mut StateOut) -> (usize, bool) {
    use std::arch::x86_64::*;
    let m = out.cost.len();
    if input.counter_next.is_empty() || input.shift_j.is_empty() {
        return (0, false);
    }
    let groups = m / 4 * 4;
    let inf = _mm256_set1_pd(INF);
    let q4 = _mm256_set1_pd(input.q4);
    let gear = _mm_set1_epi32(input.gear as i32);
    let one = _mm_set1_epi32(1);
    let below_max = _mm_set1_epi32((u32::MAX - 1) as i32);
    let half = _mm_set1_epi32((u32::MAX / 2) as i32);
    let k_lim = _mm_set1_epi32(input.k_lim as i32);
    let width = _mm_set1_epi32(input.width as i32);
    let lane_offsets = _mm_setr_epi32(0, 1, 2, 3);
    // A choice's index in the low half and its flag byte on top, the gear going in between.
    let index_and_flag = _mm_set1_epi32(0xff00_ffff_u32 as i32);
    let arc = _mm_set1_epi32(FLAGS as i32);
    let low8 = _mm_set1_epi32(0xff);
    // Lanes are loaded at indices clamped (as u32) into the slices, non-empty as checked above, and
    // kept only where the scalar loop reads.
    let last = |len: usize| _mm_set1_epi32((len - 1).min(u32::MAX as usize) as u32 as i32);
    let (last_counter, last_shift_j) = (last(input.counter_next.len()), last(input.shift_j.len()));
    let mut blocked = _mm256_setzero_pd();
    let mut t = 0;
    while t < groups {
        let stay = _mm256_loadu_pd(input.all_cost.as_ptr().add(t));
        let first_gear = _mm_loadu_si128(input.first_gear.as_ptr().add(t).cast());
        let second_gear = _mm_loadu_si128(input.second_gear.as_ptr().add(t).cast());
        let own = _mm_cmpeq_epi32(first_gear, gear);
        let shift_cost = _mm256_add_pd(
            _mm256_blendv_pd(
                _mm256_loadu_pd(input.first_cost.as_ptr().add(t)),
                _mm256_loadu_pd(input.second_cost.as_ptr().add(t)),
                widen(own),
            ),
            q4,
        );
        let take = _mm256_cmp_pd::<_CMP_LT_OQ>(shift_cost, stay);
        // Staying: the continuation's counter (0 when staying has no finite cost) + 1.
        let all_j = _mm_loadu_si128(input.all_j.as_ptr().add(t).cast());
        let carries = pack(_mm256_andnot_pd(take, _mm256_cmp_pd::<_CMP_LT_OQ>(stay, inf)));
        let carried = _mm_and_si128(
            if NEUTRAL_STATE {
                _mm_loadu_si128(input.neutral_counter.as_ptr().add(t).cast())
            } else {
                lanes::load_u32(input.counter_next, _mm_min_epu32(_mm_andnot_si128(arc, all_j), last_counter))
            },
            carries,
        );
        let stay_counter = _mm_min_epu32(_mm_add_epi32(_mm_min_epu32(carried, below_max), one), half);
        // Shifting: counter 1 and the target of the best other gear (looked up only when a lane
        // shifts, which most groups do not).
        let (counter, j, next_gear) = if _mm256_movemask_pd(take) == 0 {
            (stay_counter, all_j, gear)
        } else {
            let take32 = pack(take);
            let shift_gear = _mm_blendv_epi8(first_gear, second_gear, own);
            let slot = _mm_add_epi32(_mm_set1_epi32((input.slot0 + t) as i32), lane_offsets);
            let at = _mm_min_epu32(_mm_add_epi32(_mm_mullo_epi32(shift_gear, width), slot), last_shift_j);
            let shift_j = lanes::load_u32(input.shift_j, at);
            (
                _mm_blendv_epi8(stay_counter, one, take32),
                _mm_blendv_epi8(all_j, shift_j, take32),
                _mm_blendv_epi8(gear, shift_gear, take32),
            )
        };
        let total =
            _mm256_add_pd(_mm256_blendv_pd(stay, shift_cost, take), _mm256_loadu_pd(input.penalty.as_ptr().add(t)));
        let shiftable32 = _mm_cmpeq_epi32(_mm_max_epu32(counter, k_lim), counter);
        let shiftable = widen(shiftable32);
        _mm256_storeu_pd(out.cost.as_mut_ptr().add(t), total);
        _mm_storeu_si128(out.counter.as_mut_ptr().add(t).cast(), counter);
        _mm256_storeu_pd(out.shift.as_mut_ptr().add(t), _mm256_blendv_pd(inf, total, shiftable));
        blocked = _mm256_or_pd(blocked, _mm256_andnot_pd(shiftable, _mm256_cmp_pd::<_CMP_NEQ_UQ>(total, inf)));
        let decision =
            _mm_or_si128(_mm_and_si128(j, index_and_flag), _mm_slli_epi32::<16>(_mm_and_si128(next_gear, low8)));
        _mm_storeu_si128(out.decision.as_mut_ptr().add(t).cast(), decision);
        t += 4;
    }
    (groups, _mm256_movemask_pd(blocked) != 0)
}

/// The coasting arc from `v_i_mps` in `gear` on a stage: zero pedal and brake, the speed where the
/// physics ends it (engine drag braking in a forward gear, none in neutral), and its fuel (idle
/// fuel in neutral, none at fuel cut) and speed-change cost.
fn coast_arc(p: &DpSettings, vehicle: &Vehicle, v_i_mps: f64, gear: usize, slope_torque: f64) -> CoastArc {
    exact_arc(p, vehicle, v_i_mps, gear, slope_torque, (Branch::Brake, 0.0))
}

/// The exact arc from `v_i_mps` in `gear` with `input` held over a stage (fuel cut or coasting
/// with the brake branch at zero, full pedal with the pedal branch at one): its end speed, off the
/// grid, and its cost Q1·fuel + speed change.
fn exact_arc(
    p: &DpSettings,
    vehicle: &Vehicle,
    v_i_mps: f64,
    gear: usize,
    slope_torque: f64,
    input: (Branch, f64),
) -> CoastArc {
    let h = p.stage_m;
    let v_end_mps = stage::end_speed(p.stage_model, vehicle, (v_i_mps, h), gear, slope_torque, input);
    let pedal = if input.0 == Branch::Pedal { input.1 } else { 0.0 };
    let fuel = stage::fuel_g(p.stage_model, vehicle, (v_i_mps, v_end_mps), pedal, gear, h);
    let change = change_cost(p.q_speed_change, p.q_speed_change_sq, v_i_mps - v_end_mps);
    CoastArc { v_end_mps, cost: p.q_fuel * fuel + change }
}

/// Let an arc of cost `cost` (cost-to-go included) to grid point `j` (with its [`ARC`] or
/// [`FULL`] flag) take choice slot `at` where it is strictly cheaper, and the shift choice too
/// when its continuation allows a shift.
#[inline]
fn better_by_arc(cost: f64, j: u32, shiftable: bool, ch: &mut Choices, at: usize) {
    if cost < ch.all_cost[at] {
        (ch.all_cost[at], ch.all_j[at]) = (cost, j);
    }
    if shiftable && cost < ch.shift_cost[at] {
        (ch.shift_cost[at], ch.shift_j[at]) = (cost, j);
    }
}

/// Joins coasting arcs to the next grid by the configured rule (`neutral_rule`), within the target
/// gear's index range, with the stage's constants computed once.
struct ArcJoin {
    rule: NeutralRule,
    /// Whether an arc ending less than a grid step above the top state is joined to it, its
    /// cost-to-go extrapolated linearly from the two top states (full-pedal arcs: the top of the
    /// next stage is the grid speed full pedal reaches from the top of this one, so the arc from
    /// the top ends above it, and without this the top state could only stay at the top with a
    /// little less than full pedal, giving away power on every climb).
    extrapolate_top: bool,
    /// Speed of next-grid index 0 [m/s].
    origin_mps: f64,
    delta_mps: f64,
    lo: u32,
    hi: u32,
}

impl ArcJoin {
    fn new(p: &DpSettings, next: StageGrid, (lo, hi): (u32, u32)) -> Self {
        ArcJoin {
            rule: p.neutral_rule,
            extrapolate_top: false,
            origin_mps: next.speed(0),
            delta_mps: p.delta_mps(),
            lo,
            hi,
        }
    }

    /// The join of full-pedal arcs ([`ArcJoin::extrapolate_top`]).
    fn full_pedal(p: &DpSettings, next: StageGrid, range: (u32, u32)) -> Self {
        ArcJoin { extrapolate_top: true, ..Self::new(p, next, range) }
    }

    /// (cost with the cost-to-go, next-grid index, counter of the continuation); cost +∞ when
    /// the arc ends off the states.
    #[inline]
    fn join(&self, arc: &CoastArc, cost_next: &[f64], counter_next: &[u32]) -> (f64, u32, u32) {
        const NONE: (f64, u32, u32) = (INF, 0, 0);
        let (lo, hi) = (self.lo, self.hi);
        let x = (arc.v_end_mps - self.origin_mps) / self.delta_mps;
        if self.extrapolate_top && x > hi as f64 && x <= hi as f64 + 1.0 && hi > lo {
            let (top, below) = (cost_next[hi as usize], cost_next[hi as usize - 1]);
            if !(top.is_finite() && below.is_finite()) {
                return NONE;
            }
            let to_go = top + (x - hi as f64) * (top - below);
            return (arc.cost + to_go, hi, counter_next[hi as usize]);
        }
        // Grid indices are never negative; x below −0.5 is outside the grid either way.
        if x < lo as f64 - 0.5 || x > hi as f64 + 0.5 {
            return NONE;
        }
        let (to_go, j, counter) = match self.rule {
            NeutralRule::Nearest => {
                let j = (x + 0.5) as usize; // round half up without a libm call; x + 0.5 >= 0 here
                if j < lo as usize || j > hi as usize {
                    return NONE;
                }
                (cost_next[j], j, counter_next[j])
            }
            NeutralRule::Interpolate => {
                const TOL: f64 = 1e-9;
                if x < lo as f64 - TOL || x > hi as f64 + TOL {
                    return NONE;
                }
                let x = x.clamp(lo as f64, hi as f64);
                let j0 = x as usize;
                let w = x - j0 as f64;
                if w == 0.0 {
                    (cost_next[j0], j0, counter_next[j0])
                } else {
                    let to_go = (1.0 - w) * cost_next[j0] + w * cost_next[j0 + 1];
                    let nearest = if w < 0.5 { j0 } else { j0 + 1 };
                    (to_go, nearest, counter_next[j0].min(counter_next[j0 + 1]))
                }
            }
            NeutralRule::Quadratic => match quadratic_to_go(x, (lo, hi), cost_next, counter_next) {
                Some(found) => found,
                None => return NONE,
            },
        };
        if !to_go.is_finite() {
            return NONE;
        }
        (arc.cost + to_go, j as u32, counter)
    }
}

/// The cost-to-go at fractional grid index `x` (None outside the states `lo..=hi`)
/// through the three states around the nearest one, as (cost-to-go, nearest index, smallest
/// counter of the points used). At the ends of the states, or next to a state without a finite
/// cost, the stencil falls back to the two points bracketing `x`, then to the nearest alone when
/// `x` is within rounding of it; None when no finite cost brackets `x`.
#[inline]
fn quadratic_to_go(x: f64, (lo, hi): (u32, u32), cost: &[f64], counter: &[u32]) -> Option<(f64, usize, u32)> {
    const TOL: f64 = 1e-9;
    if x < lo as f64 - TOL || x > hi as f64 + TOL {
        return None;
    }
    let x = x.clamp(lo as f64, hi as f64);
    let j = (x + 0.5) as usize;
    let t = x - j as f64; // in [-0.5, 0.5]
    let (lo, hi) = (lo as usize, hi as usize);
    if j > lo && j < hi && cost[j - 1].is_finite() && cost[j].is_finite() && cost[j + 1].is_finite() {
        // Lagrange weights on (j - 1, j, j + 1) at offset t.
        let (wm, w0, wp) = (0.5 * t * (t - 1.0), 1.0 - t * t, 0.5 * t * (t + 1.0));
        let to_go = wm * cost[j - 1] + w0 * cost[j] + wp * cost[j + 1];
        let c = counter[j - 1].min(counter[j]).min(counter[j + 1]);
        return Some((to_go, j, c));
    }
    if t.abs() <= TOL {
        return cost[j].is_finite().then_some((cost[j], j, counter[j]));
    }
    let j0 = if t < 0.0 { j - 1 } else { j };
    if j0 < lo || j0 + 1 > hi || !cost[j0].is_finite() || !cost[j0 + 1].is_finite() {
        return None;
    }
    let w = x - j0 as f64;
    Some(((1.0 - w) * cost[j0] + w * cost[j0 + 1], j, counter[j0].min(counter[j0 + 1])))
}

/// What the first pass reads for one forward target gear.
struct GearPass<'a> {
    /// The blocks of the source keys, from `first_key` on.
    blocks: &'a [Block],
    costs: &'a [f64],
    /// Grid index of the next grid's state 0.
    next_first: i64,
    /// The target gear's states at the next stage.
    lo: u32,
    hi: u32,
    /// The target gear's blocks of cost_next and shift_next (margins included).
    to_go: &'a [f64],
    shiftable: &'a [f64],
    /// Whether `shiftable` equals `to_go` bit for bit.
    same: bool,
    first_key: i64,
    /// The source keys with states.
    key_lo: i64,
    key_hi: i64,
}

/// Where the first pass writes for one forward target gear: one value per block lane.
struct GearChoices<'a> {
    all_cost: &'a mut [f64],
    all_j: &'a mut [u32],
    shift_cost: &'a mut [f64],
    shift_j: &'a mut [u32],
}

/// [`gear_pass`] with the best kernels of the CPU. Returns the transitions evaluated.
fn gear_pass_dispatch(pass: &GearPass, out: GearChoices) -> usize {
    #[cfg(target_arch = "x86_64")]
    if let Some(kernels) = simd::Avx2::detect() {
        // SAFETY: `kernels` exists, so the CPU has AVX2.
        return unsafe { gear_pass_avx2(kernels, pass, out) };
    }
    gear_pass(simd::Portable, pass, out)
}

/// [`gear_pass`] compiled for AVX2, so that its kernels inline into the loop over blocks.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn gear_pass_avx2(kernels: simd::Avx2, pass: &GearPass, out: GearChoices) -> usize {
    gear_pass(kernels, pass, out)
}

/// The first pass towards one forward target gear: per block, the lanes' best ways into the gear
/// (and the best that allow a shift now), their next-grid indices, and the transitions counted.
#[inline(always)]
fn gear_pass<K: simd::Kernels>(kernels: K, pass: &GearPass, out: GearChoices) -> usize {
    let (lo, hi) = (pass.lo, pass.hi);
    let mut transitions = 0;
    let n = pass.blocks.len() * LANES;
    assert!(out.all_cost.len() == n && out.all_j.len() == n && out.shift_cost.len() == n && out.shift_j.len() == n);
    for (b, block) in pass.blocks.iter().enumerate() {
        let base = block.first as i64 - pass.next_first;
        let at = b * LANES..(b + 1) * LANES;
        let lanes = LaneOut {
            all: &mut out.all_cost[at.clone()],
            all_j: &mut out.all_j[at.clone()],
            shift: &mut out.shift_cost[at.clone()],
            shift_j: &mut out.shift_j[at],
        };
        block_mins(kernels, block, pass.costs, base, (lo, hi), (pass.to_go, pass.shiftable), pass.same, lanes);
        let key0 = pass.first_key + (b * LANES) as i64;
        let inside = base >= lo as i64 && base + block.steps as i64 + LANES as i64 - 2 <= hi as i64;
        if inside && key0 >= pass.key_lo && key0 + LANES as i64 - 1 <= pass.key_hi {
            // Every lane's targets are states and every lane a source: no clipping.
            transitions += block.reach as usize;
            continue;
        }
        for l in 0..LANES {
            let key = key0 + l as i64;
            let (first, len) = block.spans[l];
            let first = first as i64 - pass.next_first;
            let reached = ((first + len as i64 - 1).min(hi as i64) - first.max(lo as i64) + 1).max(0) as usize;
            transitions += if key >= pass.key_lo && key <= pass.key_hi { reached } else { 0 };
        }
    }
    transitions
}

/// Where the neutral arcs' choices go: one value per source, from the first.
#[cfg(target_arch = "x86_64")]
struct NeutralOut<'a> {
    all_cost: &'a mut [f64],
    all_j: &'a mut [u32],
    counters: &'a mut [u32],
    shift_cost: &'a mut [f64],
    shift_j: &'a mut [u32],
}

/// The ranking of one gear's shift costs into the two best per slot (the scalar loop of
/// `stay_or_shift`) four slots at a time in AVX2, as far as whole groups of four go: returns the
/// slots done. Selects on the same strict comparisons: a cost below the first moves the first to
/// second place, a cost between the two takes the second place.
///
/// # Safety
/// The CPU must have AVX2, and all slices the length of `costs`.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn rank_avx2(
    costs: &[f64],
    gear: u32,
    (first_cost, first_gear): (&mut [f64], &mut [u32]),
    (second_cost, second_gear): (&mut [f64], &mut [u32]),
) -> usize {
    use std::arch::x86_64::*;
    let groups = costs.len() / 4 * 4;
    let gear = _mm_set1_epi32(gear as i32);
    let mut t = 0;
    while t < groups {
        let c = _mm256_loadu_pd(costs.as_ptr().add(t));
        let (f, s) = (_mm256_loadu_pd(first_cost.as_ptr().add(t)), _mm256_loadu_pd(second_cost.as_ptr().add(t)));
        let fg = _mm_loadu_si128(first_gear.as_ptr().add(t).cast());
        let sg = _mm_loadu_si128(second_gear.as_ptr().add(t).cast());
        let below_first = _mm256_cmp_pd::<_CMP_LT_OQ>(c, f);
        let below_either = _mm256_or_pd(below_first, _mm256_cmp_pd::<_CMP_LT_OQ>(c, s));
        if _mm256_movemask_pd(below_either) == 0 {
            // Not among the two best anywhere in the group: nothing changes.
            t += 4;
            continue;
        }
        let (below_first32, below_either32) = (pack(below_first), pack(below_either));
        let s = _mm256_blendv_pd(s, _mm256_blendv_pd(c, f, below_first), below_either);
        let sg = _mm_blendv_epi8(sg, _mm_blendv_epi8(gear, fg, below_first32), below_either32);
        _mm256_storeu_pd(second_cost.as_mut_ptr().add(t), s);
        _mm_storeu_si128(second_gear.as_mut_ptr().add(t).cast(), sg);
        _mm256_storeu_pd(first_cost.as_mut_ptr().add(t), _mm256_blendv_pd(f, c, below_first));
        _mm_storeu_si128(first_gear.as_mut_ptr().add(t).cast(), _mm_blendv_epi8(fg, gear, below_first32));
        t += 4;
    }
    groups
}

/// [`ArcJoin::join`] with the nearest rule (and the shiftable cost), four arcs at a time in
/// AVX2, as far as whole groups of four go and no end speed is NaN: returns the arcs done. The
/// same operations as the scalar join: the division, the range tests, the truncation of x + 0.5
/// (exact: x + 0.5 is in [0, 2^31) where it is used), the cost-to-go and counter kept only where
/// the scalar join reads them (they are loaded at the nearest state within [lo, hi] for every
/// lane), and the finiteness test.
///
/// # Safety
/// The CPU must have AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn join_nearest_avx2(
    join: &ArcJoin,
    arcs: &[CoastArc],
    (cost_next, counter_next): (&[f64], &[u32]),
    k_lim: u32,
    out: NeutralOut,
) -> usize {
    use std::arch::x86_64::*;
    let n = arcs.len();
    assert!(
        out.all_cost.len() == n
            && out.all_j.len() == n
            && out.counters.len() == n
            && out.shift_cost.len() == n
            && out.shift_j.len() == n
    );
    // The loads below read indices within [lo, hi] only; the values must hold them.
    if join.lo > join.hi || (join.hi as usize) >= cost_next.len().min(counter_next.len()) || join.hi >= i32::MAX as u32
    {
        return 0;
    }
    let groups = n / 4 * 4;
    let (origin, delta) = (_mm256_set1_pd(join.origin_mps), _mm256_set1_pd(join.delta_mps));
    let (below, above) = (_mm256_set1_pd(join.lo as f64 - 0.5), _mm256_set1_pd(join.hi as f64 + 0.5));
    let half = _mm256_set1_pd(0.5);
    let inf = _mm256_set1_pd(INF);
    let sign = _mm256_set1_pd(-0.0);
    let (lo, hi) = (_mm_set1_epi32(join.lo as i32), _mm_set1_epi32(join.hi as i32));
    let k_lim = _mm_set1_epi32(k_lim as i32);
    let mut t = 0;
    while t < groups {
        // (v_end, cost) of arcs t..t + 4, as [v0 c0 v1 c1] [v2 c2 v3 c3].
        let a = _mm256_loadu_pd(arcs.as_ptr().add(t).cast());
        let b = _mm256_loadu_pd(arcs.as_ptr().add(t + 2).cast());
        let v_end = _mm256_permute4x64_pd::<0b11_01_10_00>(_mm256_unpacklo_pd(a, b));
        let arc_cost = _mm256_permute4x64_pd::<0b11_01_10_00>(_mm256_unpackhi_pd(a, b));
        let x = _mm256_div_pd(_mm256_sub_pd(v_end, origin), delta);
        if _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_UNORD_Q>(x, x)) != 0 {
            break;
        }
        let near = _mm256_and_pd(_mm256_cmp_pd::<_CMP_GE_OQ>(x, below), _mm256_cmp_pd::<_CMP_LE_OQ>(x, above));
        let j = _mm256_cvttpd_epi32(_mm256_add_pd(x, half));
        let in_states = _mm_andnot_si128(_mm_or_si128(_mm_cmpgt_epi32(lo, j), _mm_cmpgt_epi32(j, hi)), pack(near));
        // Loaded at the nearest state (clamped into [lo, hi]), kept only where it is a state.
        let state = _mm_min_epi32(_mm_max_epi32(j, lo), hi);
        let to_go = lanes::load_f64(cost_next, state);
        let finite = _mm256_cmp_pd::<_CMP_LT_OQ>(_mm256_andnot_pd(sign, to_go), inf);
        let ok = _mm_and_si128(in_states, pack(finite));
        let counter = _mm_and_si128(lanes::load_u32(counter_next, state), ok);
        let cost = _mm256_blendv_pd(inf, _mm256_add_pd(arc_cost, to_go), widen(ok));
        let j = _mm_and_si128(j, ok);
        let shiftable = widen(_mm_cmpeq_epi32(_mm_max_epu32(counter, k_lim), counter));
        _mm256_storeu_pd(out.all_cost.as_mut_ptr().add(t), cost);
        _mm_storeu_si128(out.all_j.as_mut_ptr().add(t).cast(), j);
        _mm_storeu_si128(out.counters.as_mut_ptr().add(t).cast(), counter);
        _mm256_storeu_pd(out.shift_cost.as_mut_ptr().add(t), _mm256_blendv_pd(inf, cost, shiftable));
        _mm_storeu_si128(out.shift_j.as_mut_ptr().add(t).cast(), j);
        t += 4;
    }
    t
}

/// The min-plus pass over one block of rows towards one forward target gear, into `out`: per
/// lane, the best of row cost + cost-to-go and the best among targets whose continuation allows a
/// shift now, with their next-grid indices (base + lane + step, as u32 like the i64 sum
/// truncated; meaningless where the cost is +∞). `base` is the next-grid index of lane 0 at step
/// 0; `values` the target gear's blocks of cost_next and shift_next (margins included, state j at
/// PAD + j); `same` when they are equal bit for bit.
#[inline(always)]
fn block_mins<K: simd::Kernels>(
    kernels: K,
    block: &Block,
    costs: &[f64],
    base: i64,
    (lo, hi): (u32, u32),
    (to_go, shiftable): (&[f64], &[f64]),
    same: bool,
    out: LaneOut,
) {
    let steps = block.steps as usize;
    let at = base + PAD as i64;
    let costs = &costs[block.offset as usize..];
    if steps > 0 && at >= 0 && at as usize + steps + LANES - 1 <= to_go.len() {
        // The values outside the target gear's states are +∞ (margins included): no clipping.
        let at = at as usize;
        let shiftable = if same { None } else { Some(&shiftable[at..]) };
        kernels.block_mins_to((costs, steps), &to_go[at..], shiftable, base as u32, out);
        return;
    }
    block_mins_clipped(costs, steps, base, (lo, hi), to_go, shiftable).write(base as u32, out);
}

/// [`block_mins`] for a block reaching beyond the margins: only targets that are states count.
#[cold]
fn block_mins_clipped(
    costs: &[f64],
    steps: usize,
    base: i64,
    (lo, hi): (u32, u32),
    to_go: &[f64],
    shiftable: &[f64],
) -> LaneMins {
    let mut out = LaneMins { all: [INF; LANES], all_step: [0; LANES], shift: [INF; LANES], shift_step: [0; LANES] };
    for d in 0..steps {
        for l in 0..LANES {
            let j = base + (l + d) as i64;
            if j < lo as i64 || j > hi as i64 {
                continue;
            }
            let c = costs[d * LANES + l];
            let (x, y) = (c + to_go[PAD + j as usize], c + shiftable[PAD + j as usize]);
            if x < out.all[l] {
                (out.all[l], out.all_step[l]) = (x, d as u32);
            }
            if y < out.shift[l] {
                (out.shift[l], out.shift_step[l]) = (y, d as u32);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::road::Road;
    use crate::vehicle::VehicleParams;

    /// A receding sequence of solves on a hilly road (with a model error, so that start speeds
    /// are off any grid), each solve's outputs as bits.
    fn receding(params: &DpSettings, caching: bool) -> Vec<(bool, u64, u64, u64, usize, usize, u64)> {
        let vehicle = Vehicle::new(VehicleParams::default()).unwrap();
        let n = 600;
        let distance: Vec<f64> = (0..=n).map(|i| 25.0 * i as f64).collect();
        let slopes: Vec<f64> =
            (0..n).map(|i| 0.04 * ((i as f64) * 0.021).sin() * ((i as f64) * 0.0037).cos()).collect();
        let road = Road::new(distance, slopes).unwrap();
        let mut solver = Solver::new(params.clone());
        solver.set_caching(caching);
        let mut scratch = super::super::horizon::HorizonScratch::default();
        let band = crate::band::SpeedBand::uniform(&params.cruise());
        let (mut v, mut gear, mut since) = (85.0 / 3.6, 12usize, params.k_lim);
        let mut out = Vec::new();
        for stage in 0..300 {
            let s = road.start_m() + stage as f64 * params.stage_m;
            let start = InitialState { v_mps: v, gear, stages_since_shift: since };
            let sol = super::super::horizon::solve_at(&mut solver, &vehicle, (&road, &band), s, start, &mut scratch);
            let next_v = sol.trajectory.get(1).map_or(0, |p| p.v_mps.to_bits());
            out.push((
                sol.feasible,
                sol.cost.to_bits(),
                sol.pedal.to_bits(),
                sol.brake.to_bits(),
                sol.gear,
                sol.transitions,
                next_v,
            ));
            if sol.feasible {
                since = if sol.gear != gear { 1 } else { (since + 1).min(params.k_lim) };
                gear = sol.gear;
                v = sol.trajectory[1].v_mps + if stage % 3 == 0 { 0.013 * ((stage as f64) * 0.7).sin() } else { 0.0 };
            }
        }
        out
    }

    #[test]
    fn second_pass_in_avx2_equals_the_scalar_loop() {
        let Some(avx2) = Avx2Token::detect() else { return };
        let mut seed = 13u64;
        let mut next = move |n: u64| {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 33) % n
        };
        let (width, gears) = (24usize, 6usize);
        for case in 0..400 {
            let m = 1 + next(21) as usize;
            let slot0 = next((width - m + 1) as u64) as usize;
            let gear = 1 + next(gears as u64 - 1) as u32;
            let k_lim = [0, 1, 3, 8, u32::MAX][case % 5];
            let mut cost = |inf_one_in: u64| if next(inf_one_in) == 0 { INF } else { next(7) as f64 * 0.5 };
            let all_cost: Vec<f64> = (0..m).map(|_| cost(4)).collect();
            let first_cost: Vec<f64> = (0..m).map(|_| cost(3)).collect();
            let second_cost: Vec<f64> = first_cost.iter().map(|&c| if c == INF { INF } else { c + cost(3) }).collect();
            // As the first pass leaves them: no gear exactly where the cost is +∞.
            let mut gear_of = |c: f64| if c == INF { NO_GEAR } else { next(gears as u64) as u32 };
            let first_gear: Vec<u32> = first_cost.iter().map(|&c| gear_of(c)).collect();
            let second_gear: Vec<u32> = second_cost.iter().map(|&c| gear_of(c)).collect();
            let counter_next: Vec<u32> =
                (0..40).map(|_| [0, 1, 2, 7, 8, 9, u32::MAX / 2, u32::MAX - 1, u32::MAX][next(9) as usize]).collect();
            // Some choices are fuel-cut arcs, flagged on their index.
            let mut index = |n: u64| next(n) as u32 | if next(3) == 0 { ARC } else { 0 };
            let all_j: Vec<u32> = (0..m).map(|_| index(40)).collect();
            let shift_j: Vec<u32> = (0..width * gears).map(|_| index(1000)).collect();
            let penalty: Vec<f64> = (0..m).map(|_| next(5) as f64 * 0.25).collect();
            // Even cases decide a forward gear's states; odd ones neutral's, whose staying
            // carries the counter of its own choice.
            let neutral = case % 2 == 1;
            let gear = if neutral { NEUTRAL as u32 } else { gear };
            let neutral_counter: Vec<u32> = if neutral {
                (0..m).map(|_| [0, 1, 7, 8, 9, u32::MAX / 2, u32::MAX - 1, u32::MAX][next(8) as usize]).collect()
            } else {
                vec![0; m]
            };
            let run = |avx2: Option<Avx2Token>| {
                let (mut c, mut n, mut sh, mut d) =
                    (vec![0.0; m], vec![0; m], vec![0.0; m], vec![Decision::default(); m]);
                let input = StateIn {
                    gear,
                    slot0,
                    all_cost: &all_cost,
                    all_j: &all_j,
                    first_cost: &first_cost,
                    first_gear: &first_gear,
                    second_cost: &second_cost,
                    second_gear: &second_gear,
                    neutral_counter: &neutral_counter,
                    penalty: &penalty,
                    shift_j: &shift_j,
                    width,
                    counter_next: &counter_next,
                    q4: 0.5,
                    k_lim,
                };
                let out = StateOut { cost: &mut c, counter: &mut n, shift: &mut sh, decision: &mut d };
                let same = if neutral {
                    decide_states::<true, true>(input, out, avx2)
                } else {
                    decide_states::<true, false>(input, out, avx2)
                };
                (
                    c.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
                    n,
                    sh.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
                    d,
                    same,
                )
            };
            assert_eq!(run(Some(avx2)), run(None), "case {case}");
        }
    }

    /// The quadratic rule is exact on a quadratic cost-to-go wherever three states surround the
    /// end speed; its error on a smooth cost-to-go is third order in the grid step (an eighth when
    /// it halves, where linear interpolation's, second order, is a quarter); at the ends and next
    /// to a state with no finite cost it interpolates between the two bracketing states; outside
    /// it finds none.
    #[test]
    fn quadratic_neutral_join_is_exact_on_quadratics_and_third_order() {
        let quad = |x: f64| 3.0 + 0.7 * x - 0.04 * x * x;
        let cost: Vec<f64> = (0..40).map(|j| quad(j as f64)).collect();
        let counter = vec![9u32; 40];
        for t in 0..=200 {
            let x = 2.0 + t as f64 * 0.17;
            let (to_go, j, _) = quadratic_to_go(x, (0, 39), &cost, &counter).unwrap();
            assert!((to_go - quad(x)).abs() < 1e-12, "x {x}: {to_go} vs {}", quad(x));
            assert_eq!(j, (x + 0.5) as usize);
        }
        // A smooth non-quadratic on grids of step h: error at mid-cells shrinks with h³.
        let error = |h: f64| {
            let f = |v: f64| (0.3 * v).sin() + 0.02 * v * v * v;
            let values: Vec<f64> = (0..400).map(|j| f(j as f64 * h)).collect();
            let x = 5.0 / h + 0.37; // the same speed region at every h
            (quadratic_to_go(x, (0, 399), &values, &vec![0; 400]).unwrap().0 - f(x * h)).abs()
        };
        let ratio = error(0.1) / error(0.05);
        assert!(ratio > 6.0 && ratio < 10.0, "error ratio at half the step: {ratio}");
        // Bracketing fallback: next to +∞, and at the ends of the states.
        let mut holes = cost.clone();
        holes[21] = INF;
        let (to_go, _, _) = quadratic_to_go(19.8, (0, 39), &holes, &counter).unwrap();
        assert!((to_go - (0.2 * cost[19] + 0.8 * cost[20])).abs() < 1e-12);
        let (to_go, _, _) = quadratic_to_go(0.3, (0, 39), &cost, &counter).unwrap();
        assert!((to_go - (0.7 * cost[0] + 0.3 * cost[1])).abs() < 1e-12);
        assert!(quadratic_to_go(20.6, (0, 39), &holes, &counter).is_none());
        assert!(quadratic_to_go(39.2, (0, 39), &cost, &counter).is_none());
        assert!(quadratic_to_go(-0.2, (0, 39), &cost, &counter).is_none());
        // The counter is the smallest among the points used.
        let mut counters = counter.clone();
        counters[11] = 2;
        assert_eq!(quadratic_to_go(10.2, (0, 39), &cost, &counters).unwrap().2, 2);
    }

    #[test]
    fn neutral_join_in_avx2_equals_the_scalar_join() {
        if Avx2Token::detect().is_none() {
            return;
        }
        let mut seed = 17u64;
        let mut next = move |n: u64| {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 33) % n
        };
        for case in 0..300 {
            let (lo, hi) = (next(6) as u32, 6 + next(20) as u32);
            let join = ArcJoin {
                extrapolate_top: false,
                rule: NeutralRule::Nearest,
                origin_mps: 20.0 + next(100) as f64 * 0.01,
                delta_mps: 0.1 / 3.6,
                lo,
                hi,
            };
            let n = next(23) as usize;
            let arcs: Vec<CoastArc> = (0..n)
                .map(|_| CoastArc {
                    // From well below to well above the states, with exact half steps.
                    v_end_mps: join.origin_mps
                        + (next(64) as f64 * 0.5 - 4.0) * join.delta_mps
                        + next(3) as f64 * 1e-12,
                    cost: next(9) as f64 * 0.25,
                })
                .collect();
            let cost_next: Vec<f64> = (0..40).map(|_| if next(4) == 0 { INF } else { next(11) as f64 }).collect();
            let counter_next: Vec<u32> = (0..40).map(|_| next(12) as u32).collect();
            let k_lim = [0, 4, 8, u32::MAX][case % 4];
            let scalar: Vec<_> = arcs
                .iter()
                .map(|arc| {
                    let (cost, j, counter) = join.join(arc, &cost_next, &counter_next);
                    (cost.to_bits(), j, counter, if counter >= k_lim { cost } else { INF }.to_bits(), j)
                })
                .collect();
            let (mut a, mut b, mut c, mut d, mut e) = (vec![0.0; n], vec![0; n], vec![0; n], vec![0.0; n], vec![0; n]);
            let out =
                NeutralOut { all_cost: &mut a, all_j: &mut b, counters: &mut c, shift_cost: &mut d, shift_j: &mut e };
            // SAFETY: AVX2 was detected above.
            let done = unsafe { join_nearest_avx2(&join, &arcs, (&cost_next, &counter_next), k_lim, out) };
            assert_eq!(done, n / 4 * 4);
            for t in 0..done {
                assert_eq!((a[t].to_bits(), b[t], c[t], d[t].to_bits(), e[t]), scalar[t], "case {case} arc {t}");
            }
        }
    }

    #[test]
    fn shift_ranking_in_avx2_equals_the_scalar_loop() {
        if Avx2Token::detect().is_none() {
            return;
        }
        let mut seed = 19u64;
        let mut next = move |n: u64| {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 33) % n
        };
        for case in 0..200 {
            let m = next(19) as usize;
            let (mut f, mut fg, mut s, mut sg) = (vec![INF; m], vec![NO_GEAR; m], vec![INF; m], vec![NO_GEAR; m]);
            let (mut f2, mut fg2, mut s2, mut sg2) = (f.clone(), fg.clone(), s.clone(), sg.clone());
            for g in 0..6u32 {
                // Few distinct values: many ties.
                let costs: Vec<f64> = (0..m).map(|_| if next(3) == 0 { INF } else { next(4) as f64 }).collect();
                for t in 0..m {
                    let c = costs[t];
                    if c < f[t] {
                        (s[t], sg[t]) = (f[t], fg[t]);
                        (f[t], fg[t]) = (c, g);
                    } else if c < s[t] {
                        (s[t], sg[t]) = (c, g);
                    }
                }
                // SAFETY: AVX2 was detected above; equal lengths.
                let done = unsafe { rank_avx2(&costs, g, (&mut f2, &mut fg2), (&mut s2, &mut sg2)) };
                for t in done..m {
                    let c = costs[t];
                    if c < f2[t] {
                        (s2[t], sg2[t]) = (f2[t], fg2[t]);
                        (f2[t], fg2[t]) = (c, g);
                    } else if c < s2[t] {
                        (s2[t], sg2[t]) = (c, g);
                    }
                }
            }
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!((bits(&f), fg, bits(&s), sg), (bits(&f2), fg2, bits(&s2), sg2), "case {case}");
        }
    }

    #[test]
    fn moving_grid_rows_from_the_cache_give_the_same_bits() {
        for rule in [NeutralRule::Nearest, NeutralRule::Interpolate, NeutralRule::Quadratic] {
            let params = DpSettings {
                grid: GridAnchor::Moving,
                neutral_rule: rule,
                horizon_m: 1500.0,
                delta_kmh: 0.2,
                ..DpSettings::thesis()
            };
            let with = receding(&params, true);
            let without = receding(&params, false);
            assert!(with.iter().filter(|s| s.0).count() > 200);
            for (k, (a, b)) in with.iter().zip(&without).enumerate() {
                assert_eq!(a, b, "solve {k} differs with the cache ({rule:?})");
            }
        }
    }

    /// Per lane, the first strict improvement over the targets that are states (`lo..=hi`).
    fn scalar_lane(
        costs: &[f64],
        steps: usize,
        base: i64,
        (lo, hi): (u32, u32),
        values: &[f64],
        l: usize,
    ) -> (f64, u32) {
        let mut best = (INF, 0);
        for d in 0..steps {
            let j = base + (l + d) as i64;
            if j >= lo as i64 && j <= hi as i64 {
                let x = costs[d * LANES + l] + values[PAD + j as usize];
                if x < best.0 {
                    best = (x, d as u32);
                }
            }
        }
        best
    }

    /// What [`block_mins`] with `kernels` writes: minima and next-grid indices of the four lanes.
    fn written<K: simd::Kernels>(
        kernels: K,
        block: &Block,
        costs: &[f64],
        base: i64,
        range: (u32, u32),
        values: (&[f64], &[f64]),
        same: bool,
    ) -> ([f64; LANES], [u32; LANES], [f64; LANES], [u32; LANES]) {
        let mut lanes = ([0.0; LANES], [0; LANES], [0.0; LANES], [0; LANES]);
        let (all, all_j, shift, shift_j) = (&mut lanes.0, &mut lanes.1, &mut lanes.2, &mut lanes.3);
        block_mins(kernels, block, costs, base, range, values, same, LaneOut { all, all_j, shift, shift_j });
        lanes
    }

    #[test]
    fn block_pass_inside_and_beyond_the_margins_matches_a_scalar_scan() {
        let (count, steps) = (30usize, 20usize);
        let (lo, hi) = (3u32, 25u32);
        let mut seed = 5u64;
        let mut next = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 35) % 9
        };
        for _ in 0..50 {
            let costs: Vec<f64> =
                (0..steps * LANES).map(|_| if next() == 0 { INF } else { next() as f64 * 0.5 }).collect();
            // Values as the solver keeps them: +∞ outside the states and in the margins.
            let mut to_go = vec![INF; stride(count)];
            let mut shiftable = vec![INF; stride(count)];
            for j in lo..=hi {
                to_go[PAD + j as usize] = next() as f64;
                shiftable[PAD + j as usize] = if next() < 3 { INF } else { to_go[PAD + j as usize] };
            }
            let block = Block { first: 0, steps: steps as u32, offset: 0, spans: [(0, 0); LANES], reach: 0 };
            // Inside the margins (packed pass) and reaching below them (clipped pass).
            for base in [-4i64, 10, -(PAD as i64) - 3, count as i64 - 5] {
                let (all, all_j, shift, shift_j) =
                    written(simd::Portable, &block, &costs, base, (lo, hi), (&to_go, &shiftable), false);
                // The AVX2 kernels (minima written from registers) write the same.
                #[cfg(target_arch = "x86_64")]
                if let Some(avx2) = simd::Avx2::detect() {
                    for same in [false, true] {
                        let values = (&to_go[..], if same { &to_go[..] } else { &shiftable[..] });
                        let got = written(avx2, &block, &costs, base, (lo, hi), values, same);
                        let want = written(simd::Portable, &block, &costs, base, (lo, hi), values, same);
                        let bits = |x: [f64; LANES]| x.map(f64::to_bits);
                        assert_eq!(
                            (bits(got.0), got.1, bits(got.2), got.3),
                            (bits(want.0), want.1, bits(want.2), want.3)
                        );
                    }
                }
                // The index of lane l at step d is base + l + d.
                let step = |j: u32, l: usize| (j as i64 - base - l as i64) as u32;
                for l in 0..LANES {
                    let want = scalar_lane(&costs, steps, base, (lo, hi), &to_go, l);
                    assert_eq!((all[l], step(all_j[l], l)), want, "base {base} lane {l}");
                    let want = scalar_lane(&costs, steps, base, (lo, hi), &shiftable, l);
                    assert_eq!((shift[l], step(shift_j[l], l)), want, "base {base} lane {l}");
                }
            }
        }
    }
}

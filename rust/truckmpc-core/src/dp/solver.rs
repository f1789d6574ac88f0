//! The backward dynamic program of section 5.6 over states (speed, gear) per stage, with the
//! shift counter of (5.6) and the cost (5.9).
//!
//! For a start speed and a target gear, the pedal level joining two speeds (B.5) is affine in the
//! end speed, so the end speeds reachable with P ∈ [−ε, 1 + ε] form one contiguous band of the next
//! grid: each state is joined only to that band (plus the brake points next to v_max and the one
//! neutral arc), not to every state of the next stage. The result is the same as the thesis's
//! all-pairs search, since every pair outside the band is infeasible there.
//!
//! Shift limit: each state carries the number of stages until the next shift on its optimal
//! continuation (k_lim at the final stage). A shift into state j is allowed when that number is at
//! least k_lim, so the chosen path always keeps shifts k_lim stages apart. (The rule printed in 5.6,
//! 1 + c ≥ k_lim, would let them come k_lim − 1 stages apart, contradicting the forward counter of
//! (5.6).) Stages reached before the vehicle's own counter allows a shift keep the current gear.

use super::params::{MpcParams, NeutralRule};
use super::space::{self, Grid, Intervals};
use crate::levels::{brake_accel_on, pedal_accel_on, stage_fuel_g};
use crate::vehicle::{Vehicle, NEUTRAL};

const INF: f64 = f64::INFINITY;

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
    /// Speed at the start of the stage [m/s].
    pub v_mps: f64,
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
    /// zero inputs. Speeds on later stages are grid speeds.
    pub trajectory: Vec<TrajectoryPoint>,
    /// Number of (speed, gear) states in the search space.
    pub states: usize,
    /// Number of transitions whose cost was evaluated.
    pub transitions: usize,
}

/// The best way out of a state towards one target gear.
#[derive(Debug, Clone, Copy)]
struct Choice {
    cost: f64,
    j: u32,
    counter: u32,
    pedal: f32,
    brake: f32,
}

const NO_CHOICE: Choice = Choice { cost: INF, j: 0, counter: 0, pedal: 0.0, brake: 0.0 };

/// The decision stored for a state: where it goes and with which inputs.
#[derive(Debug, Clone, Copy, Default)]
struct Decision {
    j: u32,
    gear: u8,
    pedal: f32,
    brake: f32,
}

/// A DP solver with its workspace; reuse one across solves so nothing is allocated per solve
/// once the buffers have grown.
#[derive(Debug, Clone)]
pub struct Solver {
    params: MpcParams,
    intervals: Intervals,
    grids: Vec<Grid>,
    /// Per stage and gear, the inclusive range of grid indices where a state of that gear exists
    /// (empty when lo > hi). Indexed [stage * gears + gear].
    gear_ranges: Vec<(u32, u32)>,
    cost_next: Vec<f64>,
    counter_next: Vec<u32>,
    cost_cur: Vec<f64>,
    counter_cur: Vec<u32>,
    /// Decisions per stage, flat; offsets[k] is the start of stage k, indexed [gear * n_k + i].
    decisions: Vec<Decision>,
    offsets: Vec<usize>,
    best_all: Vec<Choice>,
    best_shift: Vec<Choice>,
}

impl Solver {
    /// A solver for these parameters (validate them first with [`MpcParams::validate`]).
    pub fn new(params: MpcParams) -> Self {
        Solver {
            params,
            intervals: Intervals::default(),
            grids: Vec::new(),
            gear_ranges: Vec::new(),
            cost_next: Vec::new(),
            counter_next: Vec::new(),
            cost_cur: Vec::new(),
            counter_cur: Vec::new(),
            decisions: Vec::new(),
            offsets: Vec::new(),
            best_all: Vec::new(),
            best_shift: Vec::new(),
        }
    }

    /// The parameters.
    pub fn params(&self) -> &MpcParams {
        &self.params
    }

    /// Solve over the stages whose slopes are given (one grade per stage, N = slopes.len()).
    pub fn solve(&mut self, vehicle: &Vehicle, start: InitialState, slopes: &[f64]) -> Solution {
        let n_stages = slopes.len();
        let gears = vehicle.forward_gears() + 1;
        self.build_space(vehicle, start, slopes);
        let states = self.count_states(gears);

        // Terminal cost 0; the counters of final states allow any shift before them.
        let last = self.grids[n_stages].count;
        self.cost_next.clear();
        self.counter_next.clear();
        for g in 0..gears {
            let (lo, hi) = self.gear_ranges[n_stages * gears + g];
            for j in 0..last {
                let exists = (lo as usize) <= j && j <= hi as usize;
                self.cost_next.push(if exists { 0.0 } else { INF });
                self.counter_next.push(self.params.k_lim);
            }
        }
        self.best_all.resize(gears, NO_CHOICE);
        self.best_shift.resize(gears, NO_CHOICE);

        let mut transitions = 0usize;
        for k in (0..n_stages).rev() {
            let slope_torque = vehicle.slope_torque_nm(slopes[k]);
            transitions += self.backward_stage(vehicle, k, slope_torque, start.gear);
            std::mem::swap(&mut self.cost_cur, &mut self.cost_next);
            std::mem::swap(&mut self.counter_cur, &mut self.counter_next);
        }
        let cost = self.cost_next[start.gear];
        let mut solution = Solution { feasible: cost.is_finite(), cost, states, transitions, ..Solution::default() };
        if solution.feasible {
            self.trace(start, &mut solution);
        }
        solution
    }

    /// Intervals, grids and the gear ranges of every stage.
    fn build_space(&mut self, vehicle: &Vehicle, start: InitialState, slopes: &[f64]) {
        let p = &self.params;
        space::intervals(vehicle, p, start.v_mps, slopes, &mut self.intervals);
        self.grids.clear();
        self.grids.push(Grid { first_mps: start.v_mps, count: 1 });
        for k in 1..=slopes.len() {
            self.grids.push(space::grid(p, self.intervals.lo[k], self.intervals.hi[k]));
        }
        let gears = vehicle.forward_gears() + 1;
        let delta = p.delta_mps();
        // Stages 1..=forced are reached before the shift limit lets the truck leave its gear.
        let forced = p.k_lim.saturating_sub(start.stages_since_shift) as usize;
        self.gear_ranges.clear();
        for (k, grid) in self.grids.iter().enumerate() {
            let full = (0u32, grid.count as u32 - 1);
            for g in 0..gears {
                let range = if k == 0 || k <= forced {
                    if g == start.gear { full } else { (1, 0) }
                } else if g == NEUTRAL {
                    if p.allow_neutral { full } else { (1, 0) }
                } else {
                    // Engine speed in [n_min, n_max]: an interval of speeds, so of grid indices.
                    let c4 = vehicle.gear(g).c4;
                    let lo = ((p.n_min_rpm / c4 - grid.first_mps) / delta - 1e-9).ceil().max(0.0);
                    let hi = ((p.n_max_rpm / c4 - grid.first_mps) / delta + 1e-9).floor().min(full.1 as f64);
                    if hi >= lo { (lo as u32, hi as u32) } else { (1, 0) }
                };
                self.gear_ranges.push(range);
            }
        }
        self.offsets.clear();
        let mut total = 0;
        for grid in &self.grids {
            self.offsets.push(total);
            total += grid.count * gears;
        }
        self.decisions.clear();
        self.decisions.resize(total, Decision::default());
    }

    fn count_states(&self, gears: usize) -> usize {
        debug_assert_eq!(self.gear_ranges.len(), self.grids.len() * gears);
        self.gear_ranges.iter().map(|&(lo, hi)| if hi >= lo { (hi - lo + 1) as usize } else { 0 }).sum()
    }

    /// J_k from J_{k+1} (in `cost_next`) into `cost_cur`. Returns the transitions evaluated.
    fn backward_stage(&mut self, vehicle: &Vehicle, k: usize, slope_torque: f64, start_gear: usize) -> usize {
        let gears = vehicle.forward_gears() + 1;
        let (here, next) = (self.grids[k], self.grids[k + 1]);
        let delta = self.params.delta_mps();
        let v_ref = self.params.v_ref_mps();
        let v_max = self.params.v_max_mps();
        let q_speed_below = self.params.q_speed_below;
        let mut transitions = 0;
        self.cost_cur.clear();
        self.cost_cur.resize(here.count * gears, INF);
        self.counter_cur.clear();
        self.counter_cur.resize(here.count * gears, 0);

        for i in 0..here.count {
            let v_i = if k == 0 { here.first_mps } else { here.speed(i, delta) };
            if !self.state_exists_any(k, i, gears) {
                continue;
            }
            for g in 0..gears {
                let (lo, hi) = self.gear_ranges[(k + 1) * gears + g];
                let (all, shift, evaluated) = if hi < lo {
                    (NO_CHOICE, NO_CHOICE, 0)
                } else if g == NEUTRAL {
                    self.neutral_choice(vehicle, v_i, slope_torque, next, (lo, hi))
                } else {
                    self.gear_choice(vehicle, g, v_i, slope_torque, next, (lo, hi), v_max)
                };
                self.best_all[g] = all;
                self.best_shift[g] = shift;
                transitions += evaluated;
            }
            let below = (v_ref - v_i).max(0.0);
            let speed_cost = q_speed_below * below * below;
            for g_i in 0..gears {
                if !self.state_exists(k, i, g_i, gears, start_gear) {
                    continue;
                }
                self.settle_state(k, i, g_i, here.count, gears, speed_cost);
            }
        }
        transitions
    }

    #[inline]
    fn state_exists_any(&self, k: usize, i: usize, gears: usize) -> bool {
        (0..gears).any(|g| {
            let (lo, hi) = self.gear_ranges[k * gears + g];
            lo as usize <= i && i <= hi as usize
        })
    }

    #[inline]
    fn state_exists(&self, k: usize, i: usize, g: usize, gears: usize, start_gear: usize) -> bool {
        if k == 0 {
            return g == start_gear;
        }
        let (lo, hi) = self.gear_ranges[k * gears + g];
        lo as usize <= i && i <= hi as usize
    }

    /// J_k(i, g_i): the best of staying in g_i or shifting to another gear where the shift limit
    /// allows it, plus the speed-deviation cost of the state.
    fn settle_state(&mut self, k: usize, i: usize, g_i: usize, count: usize, gears: usize, speed_cost: f64) {
        let p = &self.params;
        let stay = self.best_all[g_i];
        let mut best = Decision { j: stay.j, gear: g_i as u8, pedal: stay.pedal, brake: stay.brake };
        let mut best_cost = stay.cost;
        let mut counter = stay.counter.saturating_add(1).min(u32::MAX / 2);
        for g in 0..gears {
            let c = self.best_shift[g];
            if g != g_i && c.cost + p.q_gear_shift < best_cost {
                best_cost = c.cost + p.q_gear_shift;
                best = Decision { j: c.j, gear: g as u8, pedal: c.pedal, brake: c.brake };
                counter = 1;
            }
        }
        let idx = g_i * count + i;
        self.cost_cur[idx] = best_cost + speed_cost;
        self.counter_cur[idx] = counter;
        self.decisions[self.offsets[k] + idx] = best;
    }

    /// Best transitions from speed v_i into the states of forward gear `g` at the next stage:
    /// over all reachable targets, and over those whose continuation allows a shift now.
    fn gear_choice(
        &self,
        vehicle: &Vehicle,
        g: usize,
        v_i: f64,
        slope_torque: f64,
        next: Grid,
        (lo, hi): (u32, u32),
        v_max: f64,
    ) -> (Choice, Choice, usize) {
        let p = &self.params;
        let h = p.stage_m;
        let delta = p.delta_mps();
        let map = pedal_accel_on(vehicle, v_i, g, slope_torque);
        let mut all = NO_CHOICE;
        let mut shift = NO_CHOICE;
        let mut evaluated = 0;
        let base = g * next.count;
        let k_lim = p.k_lim;
        let mut consider = |j: usize, cost: f64, pedal: f64, brake: f64, counter: u32| {
            let c = Choice { cost, j: j as u32, counter, pedal: pedal as f32, brake: brake as f32 };
            if cost < all.cost {
                all = c;
            }
            if counter >= k_lim && cost < shift.cost {
                shift = c;
            }
        };

        // The band of next-stage speeds reached with P in [−ε, 1 + ε].
        let (band_lo_v, band_hi_v) = if map.gain > 0.0 {
            (map.step(v_i, h, -p.epsilon), map.step(v_i, h, 1.0 + p.epsilon))
        } else {
            (INF, -INF)
        };
        let j_lo = ((band_lo_v - next.first_mps) / delta - 1e-9).ceil().max(lo as f64);
        let j_hi = ((band_hi_v - next.first_mps) / delta + 1e-9).floor().min(hi as f64);
        if j_hi >= j_lo {
            let (j_lo, j_hi) = (j_lo as usize, j_hi as usize);
            let full_fuel = stage_fuel_g(vehicle, v_i, 1.0, g, h);
            let dp_dj = v_i * delta / (h * map.gain);
            let mut pedal = map.input_for(v_i, next.speed(j_lo, delta), h);
            for j in j_lo..=j_hi {
                let v_j = next.speed(j, delta);
                let to_go = self.cost_next[base + j];
                if to_go < INF {
                    let clipped = pedal.clamp(0.0, 1.0);
                    let cost = p.q_fuel * full_fuel * clipped + p.q_speed_change * (v_i - v_j).abs() + to_go;
                    consider(j, cost, clipped, 0.0, self.counter_next[base + j]);
                }
                pedal += dp_dj;
            }
            evaluated += j_hi - j_lo + 1;
        }

        // Brakes: only for targets next to v_max that even fuel cut overshoots (P < −ε).
        let brake_map = brake_accel_on(vehicle, v_i, g, slope_torque);
        let first_brake = ((v_max - delta - next.first_mps) / delta).floor().max(lo as f64) as usize;
        let last_brake = ((v_max + delta - next.first_mps) / delta).ceil().min(hi as f64);
        if last_brake >= 0.0 {
            for j in first_brake..=(last_brake as usize) {
                let v_j = next.speed(j, delta);
                if (v_j - v_max).abs() >= delta || v_j >= band_lo_v - 1e-12 {
                    continue;
                }
                let brake = brake_map.input_for(v_i, v_j, h);
                let to_go = self.cost_next[base + j];
                evaluated += 1;
                if (0.0..=1.0).contains(&brake) && to_go < INF {
                    let cost = p.q_brake * brake + p.q_speed_change * (v_i - v_j).abs() + to_go;
                    consider(j, cost, 0.0, brake, self.counter_next[base + j]);
                }
            }
        }
        (all, shift, evaluated)
    }

    /// The single neutral arc from v_i: its end speed is set by the physics; join it to the next
    /// grid by the configured rule.
    fn neutral_choice(&self, vehicle: &Vehicle, v_i: f64, slope_torque: f64, next: Grid, (lo, hi): (u32, u32)) -> (Choice, Choice, usize) {
        let p = &self.params;
        let h = p.stage_m;
        let delta = p.delta_mps();
        let v_end = brake_accel_on(vehicle, v_i, NEUTRAL, slope_torque).step(v_i, h, 0.0);
        let x = (v_end - next.first_mps) / delta;
        let (to_go, j, counter) = match p.neutral_rule {
            NeutralRule::Nearest => {
                let j = x.round();
                if j < lo as f64 || j > hi as f64 {
                    return (NO_CHOICE, NO_CHOICE, 1);
                }
                let j = j as usize;
                (self.cost_next[j], j, self.counter_next[j])
            }
            NeutralRule::Interpolate => {
                const TOL: f64 = 1e-9;
                if x < lo as f64 - TOL || x > hi as f64 + TOL {
                    return (NO_CHOICE, NO_CHOICE, 1);
                }
                let x = x.clamp(lo as f64, hi as f64);
                let j0 = x.floor() as usize;
                let w = x - j0 as f64;
                let nearest = if w < 0.5 { j0 } else { j0 + 1 };
                let to_go = if w == 0.0 {
                    self.cost_next[j0]
                } else {
                    (1.0 - w) * self.cost_next[j0] + w * self.cost_next[j0 + 1]
                };
                let counter = if w == 0.0 { self.counter_next[j0] } else { self.counter_next[j0].min(self.counter_next[j0 + 1]) };
                (to_go, nearest, counter)
            }
        };
        if !to_go.is_finite() {
            return (NO_CHOICE, NO_CHOICE, 1);
        }
        let fuel = stage_fuel_g(vehicle, v_i, 0.0, NEUTRAL, h);
        let cost = p.q_fuel * fuel + p.q_speed_change * (v_i - v_end).abs() + to_go;
        let c = Choice { cost, j: j as u32, counter, pedal: 0.0, brake: 0.0 };
        let shift = if counter >= p.k_lim { c } else { NO_CHOICE };
        (c, shift, 1)
    }

    /// Follow the stored decisions from the initial state to fill the first control and the
    /// predicted trajectory.
    fn trace(&self, start: InitialState, out: &mut Solution) {
        let delta = self.params.delta_mps();
        let (mut i, mut g) = (0usize, start.gear);
        let mut v = start.v_mps;
        out.trajectory.clear();
        for k in 0..self.grids.len() - 1 {
            let d = self.decisions[self.offsets[k] + g * self.grids[k].count + i];
            out.trajectory.push(TrajectoryPoint { v_mps: v, gear: d.gear as usize, pedal: d.pedal as f64, brake: d.brake as f64 });
            i = d.j as usize;
            g = d.gear as usize;
            v = self.grids[k + 1].speed(i, delta);
        }
        out.trajectory.push(TrajectoryPoint { v_mps: v, gear: g, pedal: 0.0, brake: 0.0 });
        let first = out.trajectory[0];
        out.pedal = first.pedal;
        out.brake = first.brake;
        out.gear = first.gear;
    }
}

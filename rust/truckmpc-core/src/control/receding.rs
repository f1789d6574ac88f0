//! The look-ahead cruise controller (thesis chapter 5) in the closed loop: the receding horizon of
//! section 5.6.
//!
//! Every S metres the controller predicts, with its own stage model, the speed at the start of the
//! next stage under the inputs being applied now and chooses the control for that next stage from
//! the dynamic program over the horizon from there: a solve of the horizon every `replan_m` (every
//! stage when it is below 1.5 S), and in between a solve against the last one's stored cost-to-go
//! ([`stored`]). Stage boundaries are counted from the road's start. When a solve finds no
//! admissible path, the controller counts the event and, by `on_infeasible`, either keeps the inputs it is applying (the
//! thesis's rule) or rescues: a solve with the lower speed bound and the shift limit relaxed (on a
//! grid no finer than [`crate::dp::params::RELAXED_DELTA_MIN_KMH`]), and failing that the [`Rescue`]
//! policy until a later solve succeeds.

use std::sync::Arc;
use std::time::Instant;

use super::pi::GearLogic;
use super::rescue::Rescue;
use super::{Controller, Decision};
use crate::band::SpeedBand;
use crate::dp::{horizon, shift, stage, DpSettings, InitialState, Solver};
use crate::levels::stationary;
use crate::params::OnInfeasible;
use crate::plant::{Control, PlantState};
use crate::road::Road;
use crate::vehicle::{Vehicle, NEUTRAL};

mod stats;
mod stored;

pub use self::stats::{PlanStats, SolverStats};
use self::stored::Stored;

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

/// The DP-MPC as a [`Controller`]: decides once per stage, holding its inputs until the next stage
/// boundary; when a solve finds no admissible path it holds its inputs (`hold`, section 5.6) or
/// (`rescue`) solves again with the lower speed bound and the shift limit relaxed and, failing
/// that, drives the [`Rescue`] policy at every plant step until a solve succeeds in a later stage.
#[derive(Debug)]
pub struct RecedingController {
    vehicle: Arc<Vehicle>,
    solver: Solver,
    /// The relaxed solver ([`DpSettings::relaxed`], with a row cache of its own), built on the first
    /// need (rescue only).
    relaxed: Option<Solver>,
    rescue: Rescue,
    /// The PI's gear logic, for the gear the truck starts in.
    start_gears: GearLogic,
    scratch: horizon::HorizonScratch,
    /// The band along the road of the current run, for the solver and for the relaxed solver.
    band: SpeedBand,
    relaxed_band: SpeedBand,
    origin_m: f64,
    shifts: ShiftCounter,
    gear: usize,
    pending: Control,
    /// No solve gave the pending control: rescue from the next decision on.
    rescue_next: bool,
    /// Rescuing; the stage (counted from the road's start) of the last solve tried.
    rescuing: Option<i64>,
    rescue_from_m: f64,
    /// Position of the latest rescue decision [m].
    rescue_last_m: f64,
    /// Road segment of the rescue's last slope look-up.
    rescue_slope_hint: usize,
    /// The last stage the shift limit counted while rescuing (the rescue decides at every plant
    /// step, the limit counts stages).
    rescue_counted: i64,
    stats: SolverStats,
    /// Whether this is the whole-road optimum (one solve over the whole road).
    whole_road: bool,
    /// The cost-to-go the coming stages are decided from: the whole-road plan, or the latest
    /// horizon solve when stages are decided from it (`replan_m` above S).
    stored: Option<Stored>,
}

/// Lowest speed [km/h] the relaxed solve may plan with.
const RELAXED_V_MIN_KMH: f64 = 5.0;

impl RecedingController {
    /// A controller predicting with `vehicle`, solving with `params` (k_lim resolved) and starting
    /// in the gear `start_gears` settles in at the starting speed; it rescues with that gear logic
    /// below v_max.
    pub fn new(vehicle: Arc<Vehicle>, params: DpSettings, start_gears: GearLogic) -> Self {
        let params = params.for_vehicle(&vehicle);
        let shifts = ShiftCounter::new(params.k_lim);
        let band_params = params.clone();
        let rescue = Rescue::new(start_gears.clone());
        RecedingController {
            vehicle,
            solver: Solver::new(params),
            relaxed: None,
            rescue,
            start_gears,
            scratch: horizon::HorizonScratch::default(),
            band: SpeedBand::uniform(&band_params.cruise()),
            relaxed_band: SpeedBand::uniform(&band_params.relaxed(RELAXED_V_MIN_KMH).cruise()),
            origin_m: 0.0,
            shifts,
            gear: 0,
            pending: Control { pedal: 0.0, brake: 0.0, gear: 0 },
            rescue_next: false,
            rescuing: None,
            rescue_from_m: 0.0,
            rescue_last_m: 0.0,
            rescue_slope_hint: 0,
            rescue_counted: 0,
            stats: SolverStats::default(),
            whole_road: false,
            stored: None,
        }
    }

    /// The whole-road optimum: the same DP with the bound's prices ([`DpSettings::bound`]) solved
    /// once over the entire road from the start (no receding horizon; the speed at the road's end
    /// priced as at a horizon's end), its cost-to-go
    /// kept for every stage; each stage's control is then chosen from the truck's state predicted
    /// at the stage's start by a one-stage solve against the next stage's stored values. What it
    /// does when a one-stage solve finds no admissible path follows `on_infeasible`, as the MPC.
    pub fn whole_road(vehicle: Arc<Vehicle>, params: DpSettings, start_gears: GearLogic) -> Self {
        RecedingController { whole_road: true, ..Self::new(vehicle, params.bound(), start_gears) }
    }

    /// Plan the whole road from `start` at `s0_m`: the DP over every stage to the road's end.
    fn plan_road(&mut self, road: &Road, s0_m: f64, start: InitialState) {
        if !self.whole_road {
            return;
        }
        let h = self.solver.params().mpc.stage_m;
        let stages = (((road.end_m() - s0_m) / h) - 1e-9).ceil().max(1.0) as usize;
        let mut plan = Stored::starting(0, usize::MAX);
        horizon::stage_slopes(road, s0_m, h, stages, &mut plan.ahead.slopes);
        if self.band.varies() {
            horizon::stage_bands(&self.band, s0_m, h, stages, &mut plan.ahead.bands);
        }
        let bands = (!plan.ahead.bands.is_empty()).then_some(&plan.ahead.bands[..]);
        let began = Instant::now();
        let solution = self.solver.solve_recording(&self.vehicle, start, &plan.ahead.slopes, bands, &mut plan.table);
        let solve_s = began.elapsed().as_secs_f64();
        let table_bytes = plan.table.bytes() as u64;
        self.stored = Some(plan);
        let followed = solution.feasible.then(|| self.follow_plan(road, s0_m, start, stages)).flatten();
        let (fuel_g, time_s, end_v_mps) = followed.unwrap_or((f64::NAN, f64::NAN, f64::NAN));
        let (cost, stages, fuel_kg) = (solution.cost, stages as u64, fuel_g / 1000.0);
        self.stats.plan = Some(PlanStats { fuel_kg, time_s, end_v_mps, cost, solve_s, stages, table_bytes });
    }

    /// The fuel [g], time [s] and end speed [m/s] of driving the stored plan on the DP's own stage model: each
    /// stage's control from [`RecedingController::solve`] at the speed and gear the model predicts
    /// there, as the run decides from the plant's (the plan's grid path alone would restart from a
    /// grid speed after each arc); where no solve finds one, the control before is held (what
    /// `on_infeasible: hold` does; a run that rescues drives its rescue policy there instead).
    /// None where the model's truck stops. The run's counts are left as they were; its compute
    /// time includes this, about one more drive's worth of one-stage solves.
    fn follow_plan(&mut self, road: &Road, s0_m: f64, start: InitialState, stages: usize) -> Option<(f64, f64, f64)> {
        let kept = (self.stats, self.shifts);
        let h_m = self.solver.params().mpc.stage_m;
        let (mut v_mps, mut gear) = (start.v_mps, start.gear);
        let mut held = self.holding(v_mps, gear);
        let (mut fuel_g, mut time_s, mut stopped) = (0.0, 0.0, false);
        for k in 0..stages {
            let s_m = s0_m + k as f64 * h_m;
            let h = h_m.min(road.end_m() - s_m);
            let u = self.solve(road, s_m, v_mps, gear).unwrap_or(held);
            let (v_next, energy, time) = self.model_stage(road, (s_m, h), (v_mps, gear), u);
            if !(v_next > 0.0) {
                stopped = true;
                break;
            }
            fuel_g += energy;
            time_s += time;
            self.shifts.record(gear, u.gear);
            (v_mps, gear, held) = (v_next, u.gear, u);
        }
        (self.stats, self.shifts) = kept;
        (!stopped).then_some((fuel_g, time_s, v_mps))
    }

    /// A stage of `h_m` from `s_m` [m] at `v_mps` in `gear` under `u` on the DP's own stage model:
    /// (end speed [m/s], energy in the store's unit, time [s]), the roll of the interruption first
    /// where the plan models the change of gear. The end speed is 0 or below where the truck stops.
    fn model_stage(
        &self,
        road: &Road,
        (s_m, h_m): (f64, f64),
        (v_mps, gear): (f64, usize),
        u: Control,
    ) -> (f64, f64, f64) {
        let model = self.solver.params().mpc.stage_model;
        if shift::interrupts(self.solver.params(), &self.vehicle, gear, u.gear) {
            let torque = self.vehicle.slope_torque_nm(road.mean_slope(s_m, s_m + h_m));
            return shift::drive_stage((&self.vehicle, model), (v_mps, h_m), gear, u, torque);
        }
        let v_next = horizon::predict_speed((&self.vehicle, model), road, s_m, v_mps, u, h_m);
        let energy = stage::energy_of(model, &self.vehicle, (v_mps, v_next), u, h_m);
        (v_next, energy, stage::time_s(model, (v_mps, v_next), h_m))
    }

    /// The one-stage solve at the stage starting at `s_m` against the stored cost-to-go (None
    /// when `s_m` is no stage boundary among the stages decided from it: a horizon solve then).
    fn solve_against_stored(&mut self, s_m: f64, start: InitialState) -> Option<crate::dp::Solution> {
        let k = horizon::boundary_stage(self.origin_m, s_m, self.solver.params().mpc.stage_m)?;
        self.stored.as_ref()?.decide(&mut self.solver, &self.vehicle, k, start)
    }

    /// The horizon solve at `s_m`: with `replan_m` above S, on a stage boundary, over the horizon
    /// and the stages to be decided from it, its cost-to-go kept for them.
    fn solve_horizon(&mut self, road: &Road, s_m: f64, start: InitialState) -> crate::dp::Solution {
        let params = self.solver.params();
        let (span, stages) = (params.replan_stages(), params.stages());
        let boundary = horizon::boundary_stage(self.origin_m, s_m, params.mpc.stage_m);
        let (Some(k), false, true) = (boundary, self.whole_road, span > 1) else {
            let context = (road, &self.band);
            return horizon::solve_at(&mut self.solver, &self.vehicle, context, s_m, start, &mut self.scratch);
        };
        // The allocation of the values before is reused.
        let mut kept = self.stored.take().unwrap_or_default();
        (kept.first, kept.span) = (k, span);
        let (context, ahead) = ((road, &self.band), (s_m, stages + span - 1));
        let (table, scratch) = (&mut kept.table, &mut kept.ahead);
        let solution =
            horizon::solve_recording_at(&mut self.solver, &self.vehicle, context, ahead, start, scratch, table);
        self.stored = Some(kept);
        solution
    }

    fn rescues(&self) -> bool {
        self.solver.params().mpc.on_infeasible == OnInfeasible::Rescue
    }

    /// Solve the horizon from `v_mps` [m/s] in `gear` at `s_m` [m]; the first control if feasible.
    /// When rescuing, an infeasible solve from within the band is followed by a relaxed one; below
    /// the band the rescue policy drives instead, since a control held over a whole stage at low
    /// speed on a steep climb (where the one-step prediction is poor) can stall the truck.
    fn solve(&mut self, road: &Road, s_m: f64, v_mps: f64, gear: usize) -> Option<Control> {
        let start = InitialState { v_mps, gear, stages_since_shift: self.shifts.stages() };
        let found = self.timed_solve(road, s_m, start, false);

        if found.is_some() || !self.rescues() || v_mps < self.band.at(s_m, &mut 0).v_min_mps() {
            return found;
        }
        let relaxed = self.timed_solve(road, s_m, start, true);
        self.stats.fallback_relaxed += u64::from(relaxed.is_some());
        relaxed
    }

    fn timed_solve(&mut self, road: &Road, s_m: f64, start: InitialState, relaxed: bool) -> Option<Control> {
        let began = Instant::now();
        // A state the stored values do not reach (the plant a little slower than the plan on a
        // climb at full pedal) is solved over the horizon instead, as the MPC would.
        let planned = if relaxed { None } else { self.solve_against_stored(s_m, start) }.filter(|s| s.feasible);
        let from_stored = planned.is_some();
        let solution = match planned {
            Some(solution) => solution,
            None if relaxed => {
                // Its own row cache: relaxed solves come in runs (at a step of the target speed),
                // and on a grid no finer than 0.2 km/h over at most 1.5 km their rows down to
                // 5 km/h take tens of MB.
                let (params, caching) = (self.solver.params().relaxed(RELAXED_V_MIN_KMH), self.solver.caching());
                let solver = self.relaxed.get_or_insert_with(|| {
                    let mut solver = Solver::new(params);
                    solver.set_caching(caching);
                    solver
                });
                let context = (road, &self.relaxed_band);
                horizon::solve_at(solver, &self.vehicle, context, s_m, start, &mut self.scratch)
            }
            None => self.solve_horizon(road, s_m, start),
        };
        let elapsed_s = began.elapsed().as_secs_f64();
        let stats = &mut self.stats;
        stats.solve_time_s += elapsed_s;
        stats.solve_time_max_s = stats.solve_time_max_s.max(elapsed_s);
        if !relaxed {
            stats.solves += 1;
            stats.horizon_solves += u64::from(!from_stored);
            stats.states += solution.states as u64;
            stats.transitions += solution.transitions as u64;
            stats.infeasible_solves += u64::from(!solution.feasible);
        }
        solution.feasible.then_some(Control { pedal: solution.pedal, brake: solution.brake, gear: solution.gear })
    }

    /// Fallback before any feasible solve when holding: the levels holding `v_mps` on a flat road.
    fn holding(&self, v_mps: f64, gear: usize) -> Control {
        let level = stationary(&self.vehicle, v_mps, 0.0, gear);
        Control { pedal: level.pedal, brake: level.brake, gear }
    }

    /// Whether `u` would turn the engine below idle at `v_mps` in gear.
    fn below_idle(&self, u: Control, v_mps: f64) -> bool {
        u.gear != NEUTRAL && self.vehicle.engine_speed_rpm(v_mps, u.gear) < self.vehicle.params().idle_speed_rpm
    }

    /// Index of the stage containing `s_m`, counted from the road's start.
    fn stage_at(&self, s_m: f64) -> i64 {
        ((s_m - self.origin_m) / self.solver.params().mpc.stage_m + 1e-9).floor() as i64
    }

    /// Drive `u` until `boundary_m` and solve the stage after it from the speed predicted there
    /// over `h_m` metres.
    fn apply_and_plan(&mut self, road: &Road, state: &PlantState, u: Control, boundary_m: f64, h_m: f64) -> Decision {
        // The next stage is solved from where the model puts the truck, after the shift's roll
        // where the plan models it (from the speed before the roll it would plan from a state
        // the plant never reaches, off the stored plan's grid).
        let (v_next, _, _) = self.model_stage(road, (state.s_m, h_m), (state.v_mps, self.gear), u);
        self.shifts.record(self.gear, u.gear);
        self.gear = u.gear;
        let chosen = if v_next > 0.0 { self.solve(road, boundary_m, v_next, u.gear) } else { None };
        self.rescue_next = chosen.is_none() && self.rescues();
        self.pending = chosen.unwrap_or(u);
        Decision { control: u, until_m: Some(boundary_m) }
    }

    /// One plant step of the rescue policy; once per new stage with the truck back in its band, a
    /// solve from the actual state, which ends the rescue when it succeeds.
    fn rescue_step(&mut self, road: &Road, state: &PlantState) -> Decision {
        self.rescue_last_m = state.s_m;
        let stage = self.stage_at(state.s_m);
        let at = self.band.at(state.s_m, &mut 0);
        let in_band = state.v_mps >= at.v_min_mps() && state.v_mps <= at.v_max_mps();
        if in_band && self.rescuing.is_some_and(|tried| stage > tried) {
            self.rescuing = Some(stage);
            if let Some(u) = self.solve(road, state.s_m, state.v_mps, self.gear) {
                if !self.below_idle(u, state.v_mps) {
                    self.stats.fallback_rescue_m += state.s_m - self.rescue_from_m;
                    self.rescuing = None;
                    let boundary_m = self.origin_m + (stage + 1) as f64 * self.solver.params().mpc.stage_m;
                    return self.apply_and_plan(road, state, u, boundary_m, boundary_m - state.s_m);
                }
            }
        }
        let slope = road.slope_at(state.s_m, &mut self.rescue_slope_hint);
        let u = self.rescue.step(&self.vehicle, self.gear, (state.v_mps, slope), at.v_max_kmh);
        // A shift restarts the limit's count, a new stage adds one: counting plant steps would
        // free the look-ahead to shift back a few metres after the rescue's own shift.
        if u.gear != self.gear || stage > self.rescue_counted {
            self.shifts.record(self.gear, u.gear);
            self.rescue_counted = stage;
        }
        self.gear = u.gear;
        Decision { control: u, until_m: None }
    }

    fn enter_rescue(&mut self, road: &Road, state: &PlantState) -> Decision {
        self.rescue_next = false;
        self.rescuing = Some(self.stage_at(state.s_m));
        self.rescue_counted = self.stage_at(state.s_m) - 1;
        self.rescue_from_m = state.s_m;
        self.stats.fallback_rescues += 1;
        self.rescue_step(road, state)
    }
}

impl Controller for RecedingController {
    fn name(&self) -> &'static str {
        if self.whole_road {
            "optimal"
        } else {
            "mpc"
        }
    }

    /// Solve the first stage from the starting state.
    fn start(&mut self, road: &Road, state: &PlantState) {
        let params = self.solver.params().clone();
        self.band = SpeedBand::new(road, &params.cruise());
        self.relaxed_band = SpeedBand::new(road, &params.relaxed(RELAXED_V_MIN_KMH).cruise());
        // The row cache and interval memo hold stages of one road (of its slopes and bands): a new run
        // starts them afresh (a stage of another road, or of other target speeds, may differ).
        let caching = self.solver.caching();
        self.solver = Solver::new(params);
        self.solver.set_caching(caching);
        self.relaxed = None;
        self.origin_m = state.s_m;
        self.rescue_slope_hint = 0;
        self.shifts = ShiftCounter::new(self.solver.params().k_lim);
        self.gear = self.start_gears.steady_gear(state.v_mps);
        self.stats = SolverStats::default();
        self.rescuing = None;
        self.stored = None;
        let start = InitialState { v_mps: state.v_mps, gear: self.gear, stages_since_shift: self.shifts.stages() };
        self.plan_road(road, state.s_m, start);
        let first = self.solve(road, state.s_m, state.v_mps, self.gear);
        self.rescue_next = first.is_none() && self.rescues();
        self.pending = first.unwrap_or_else(|| self.holding(state.v_mps, self.gear));
    }

    /// Apply the control chosen for this stage; solve the next stage from the predicted speed.
    fn decide(&mut self, road: &Road, state: &PlantState) -> Decision {
        if self.rescuing.is_some() {
            return self.rescue_step(road, state);
        }
        if self.rescue_next || (self.rescues() && self.below_idle(self.pending, state.v_mps)) {
            return self.enter_rescue(road, state);
        }
        let u = self.pending;
        let stage_m = self.solver.params().mpc.stage_m;
        let stage = ((state.s_m - self.origin_m) / stage_m).round_ties_even();
        let boundary_m = self.origin_m + (stage + 1.0) * stage_m;
        self.apply_and_plan(road, state, u, boundary_m, stage_m)
    }

    fn solver_stats(&self) -> Option<SolverStats> {
        let mut stats = self.stats;
        if self.rescuing.is_some() {
            stats.fallback_rescue_m += self.rescue_last_m - self.rescue_from_m;
        }
        Some(stats)
    }
}

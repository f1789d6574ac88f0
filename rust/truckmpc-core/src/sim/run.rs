//! The closed loop: a controller driving the plant from the road's start to its end (or a stall).

use std::sync::Arc;
use std::time::Instant;

use super::shifts::GearCounts;
use super::summary::{LoopOutcome, RunSummary};
use super::trace::{Trace, TraceRecorder};
use super::{ARRIVAL_TOLERANCE_M, KMH_PER_MPS};
use crate::control::{Controller, Decision};
use crate::error::{CoreError, CoreResult};
use crate::params::{ParamSet, SimParams, Value};
use crate::plant::{Control, Plant, PlantState};
use crate::road::Road;
use crate::stop::DecisionWatch;
use crate::vehicle::Vehicle;

/// What a run returns.
#[derive(Debug, Clone, PartialEq)]
pub struct RunOutput {
    /// The controller's name (`"pi"`, `"mpc"`).
    pub controller: &'static str,
    pub summary: RunSummary,
    pub trace: Trace,
    /// The host's stop hook ([`crate::stop`]) ended the run before the road's end: the figures
    /// cover the distance driven.
    pub stopped: bool,
    /// The settings a controller that solves the DP ran with, as
    /// [`crate::scenario::Scenario::dp_settings`] gives them; None for other controllers and for
    /// runs outside a scenario.
    pub settings: Option<Vec<(&'static str, Value)>>,
}

/// Drive `road` with `controller` from its start at `start_speed_kmh` to its end, a stall, or
/// inputs that no longer move the truck. `altitude_m` gives the trace's altitude at each of the
/// road's profile points [m].
pub fn run(
    vehicle: &Arc<Vehicle>,
    road: &Arc<Road>,
    altitude_m: &[f64],
    controller: &mut dyn Controller,
    sim: &SimParams,
    start_speed_kmh: f64,
) -> CoreResult<RunOutput> {
    run_on_map(vehicle, road, road, altitude_m, controller, sim, start_speed_kmh)
}

/// As [`run`], with the controller planning on `map` while the plant drives `road`: a map that
/// is not the road (a noisy import of it, a grade bias). The map must span the road's distances to
/// within 2 % of its length (beyond its end the controller sees it flat, as on any road).
pub fn run_on_map(
    vehicle: &Arc<Vehicle>,
    road: &Arc<Road>,
    map: &Road,
    altitude_m: &[f64],
    controller: &mut dyn Controller,
    sim: &SimParams,
    start_speed_kmh: f64,
) -> CoreResult<RunOutput> {
    let wall = Instant::now();
    check_inputs(road, altitude_m, sim, start_speed_kmh)?;
    check_map(road, map)?;
    let mut closed = ClosedLoop::new(vehicle, road, sim, start_speed_kmh);
    controller.start(map, &closed.state);
    let last_u = closed.drive(map, controller);
    closed.recorder.finish(&closed.state, last_u);
    closed.outcome.thermal = closed.plant.thermal();
    closed.outcome.losses_j = closed.plant.losses_j();
    let compute_time_s = wall.elapsed().as_secs_f64();
    let summary = RunSummary::new(
        &closed.state,
        &closed.outcome,
        compute_time_s,
        controller.solver_stats(),
        controller.rule_stats(),
    );
    let trace = closed.recorder.into_trace(road, altitude_m, vehicle);
    let stopped = closed.outcome.stopped;
    Ok(RunOutput { controller: controller.name(), summary, trace, stopped, settings: None })
}

/// Share of the road's length by which the controller's map may differ at either end.
const MAP_SLACK: f64 = 0.02;

fn check_map(road: &Road, map: &Road) -> CoreResult<()> {
    let slack_m = MAP_SLACK * (road.end_m() - road.start_m());
    if (map.start_m() - road.start_m()).abs() > slack_m || (map.end_m() - road.end_m()).abs() > slack_m {
        let expected = format!("a map spanning the road's {:.0}..{:.0} m to within 2 %", road.start_m(), road.end_m());
        return Err(CoreError::invalid("controller_road", expected).got(format!(
            "{:.0}..{:.0} m",
            map.start_m(),
            map.end_m()
        )));
    }
    Ok(())
}

fn check_inputs(road: &Road, altitude_m: &[f64], sim: &SimParams, start_speed_kmh: f64) -> CoreResult<()> {
    sim.check_ranges()?;
    if !(start_speed_kmh.is_finite() && start_speed_kmh > 0.0) {
        return Err(CoreError::invalid("start_speed_kmh", "a number > 0").got(start_speed_kmh));
    }
    if altitude_m.len() != road.distance_m().len() {
        let expected = format!("one altitude per profile point ({})", road.distance_m().len());
        return Err(CoreError::invalid("altitude_m", expected).got(altitude_m.len()));
    }
    Ok(())
}

/// The plant, the trace and the running counts of one run.
struct ClosedLoop {
    plant: Plant,
    state: PlantState,
    recorder: TraceRecorder,
    outcome: LoopOutcome,
    /// Consecutive plant passes that did not move the truck.
    idle_passes: u32,
    watch: DecisionWatch,
}

impl ClosedLoop {
    fn new(vehicle: &Arc<Vehicle>, road: &Arc<Road>, sim: &SimParams, start_speed_kmh: f64) -> Self {
        let (start_m, end_m) = (road.start_m(), road.end_m());
        let plant = Plant::new(vehicle.clone(), road.clone(), start_m, start_speed_kmh / KMH_PER_MPS);
        let outcome = LoopOutcome {
            start_m,
            end_m,
            start_speed_kmh,
            gears: GearCounts::default(),
            neutral_distance_m: 0.0,
            stuck: false,
            stopped: false,
            stall_speed_mps: vehicle.stall_speed_mps(),
            plant_dt_s: sim.plant_dt_s,
            store: crate::powertrain::Powertrain::store(vehicle.as_ref()),
            thermal: None,
            losses_j: [0.0; 2],
        };
        ClosedLoop {
            state: plant.state(),
            plant,
            recorder: TraceRecorder::new(start_m, end_m, sim.trace_step_m),
            outcome,
            idle_passes: 0,
            watch: DecisionWatch::default(),
        }
    }

    /// Ask the controller and apply its decisions until the run ends (a failed controller or the
    /// host's stop ends it before a decision is applied; one that failed to start is not asked);
    /// the last inputs applied (gear 1 and no pedal when nothing was decided).
    fn drive(&mut self, road: &Road, controller: &mut dyn Controller) -> Control {
        let nothing_decided = Control { pedal: 0.0, brake: 0.0, gear: 1 };
        if controller.aborted() {
            return nothing_decided;
        }
        let end_m = self.outcome.end_m;
        let mut last: Option<Control> = None;
        while !self.outcome.stuck && !self.state.stalled && end_m - self.state.s_m > ARRIVAL_TOLERANCE_M {
            let decision = controller.decide(road, &self.state);
            if controller.aborted() {
                break;
            }
            if self.watch.requested_after(decision.until_m.is_some()) {
                self.outcome.stopped = true;
                break;
            }
            self.outcome.gears.apply(decision.control.gear);
            last = Some(decision.control);
            let begin_m = self.state.s_m;
            self.hold(decision);
            if decision.control.gear == 0 {
                self.outcome.neutral_distance_m += self.state.s_m - begin_m;
            }
        }
        last.unwrap_or(nothing_decided)
    }

    /// Apply one decision: one plant step, or steps up to `until_m` (capped at the road's end)
    /// stopping on each trace sample so samples are exact states.
    fn hold(&mut self, decision: Decision) {
        let Decision { control: u, until_m } = decision;
        let end_m = self.outcome.end_m;
        let target_m = match until_m {
            Some(s) if !(s > end_m) => s,
            _ => end_m,
        };
        let applied = Control { pedal: u.pedal.clamp(0.0, 1.0), brake: u.brake.clamp(0.0, 1.0), gear: u.gear };
        let dt_s = self.outcome.plant_dt_s;
        loop {
            let new = if until_m.is_none() {
                self.plant.step_until(applied, dt_s, target_m);
                self.plant.state()
            } else {
                let goal_m = target_m.min(self.recorder.next_s_m);
                if goal_m - self.state.s_m > ARRIVAL_TOLERANCE_M {
                    self.plant.advance_to(applied, dt_s, goal_m);
                    self.plant.state()
                } else {
                    self.state
                }
            };
            if new.s_m >= self.recorder.next_s_m - ARRIVAL_TOLERANCE_M {
                self.recorder.derated = self.plant.is_derated();
                self.recorder.cross(&self.state, &new, u);
            }
            self.idle_passes = if new.s_m <= self.state.s_m { self.idle_passes + 1 } else { 0 };
            self.state = new;
            // Nothing moves the truck any more: a stale hold, or rounding at the end.
            if self.idle_passes > 3 {
                self.outcome.stuck = true;
                return;
            }
            if until_m.is_none() || self.state.stalled || target_m - self.state.s_m <= ARRIVAL_TOLERANCE_M {
                return;
            }
        }
    }
}

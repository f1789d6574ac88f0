//! A host's stop hook ends the work it watches: the closed loop stops before applying the decision
//! after which the hook said stop, and a DP solve ends at the stage where it asks.

use std::cell::Cell;
use std::sync::Arc;
use std::thread::sleep;
use std::time::Duration;

use truckmpc_core::control::{Controller, Decision};
use truckmpc_core::dp::{DpSettings, InitialState, Solver};
use truckmpc_core::sim::{run, RunOutput};
use truckmpc_core::stop::{self, CHECK_INTERVAL_S, STEPS_PER_CLOCK_READING};
use truckmpc_core::{Control, PlantState, Road, SimParams, Vehicle, VehicleParams};

const SIM: SimParams =
    SimParams { plant_dt_s: 0.05, trace_step_m: 25.0, start_speed_kmh: None, controller_mass_kg: None };

thread_local! {
    static ASKED: Cell<u32> = const { Cell::new(0) };
}

fn stop_counting() -> bool {
    ASKED.set(ASKED.get() + 1);
    true
}

fn past_the_interval() {
    sleep(Duration::from_secs_f64(CHECK_INTERVAL_S * 1.2));
}

/// Half pedal in top gear, held for one plant step or `hold_m` metres; its first decision takes
/// longer than the hook's interval (as a DP solve may).
struct Slow {
    hold_m: Option<f64>,
    decisions: u32,
}

impl Controller for Slow {
    fn name(&self) -> &'static str {
        "slow"
    }

    fn start(&mut self, _road: &Road, _state: &PlantState) {}

    fn decide(&mut self, _road: &Road, state: &PlantState) -> Decision {
        if self.decisions == 0 {
            past_the_interval();
        }
        self.decisions += 1;
        let control = Control { pedal: 0.5, brake: 0.0, gear: 12 };
        Decision { control, until_m: self.hold_m.map(|h| state.s_m + h) }
    }
}

fn drive_flat(controller: &mut Slow) -> RunOutput {
    let vehicle = Arc::new(Vehicle::new(VehicleParams::default()).unwrap());
    let road = Arc::new(Road::new(vec![0.0, 10_000.0], vec![0.0]).unwrap());
    run(&vehicle, &road, &[0.0, 0.0], controller, &SIM, 85.0).unwrap()
}

/// One-step decisions: the hook is first asked at the STEPS_PER_CLOCK_READING-th, which is not
/// applied: the run ends after one plant step fewer, marked stopped.
#[test]
fn a_stop_after_single_steps_ends_the_run_within_a_clock_reading() {
    let mut slow = Slow { hold_m: None, decisions: 0 };
    let out = stop::watched(stop_counting, || drive_flat(&mut slow));
    assert!(out.stopped);
    assert_eq!(ASKED.get(), 1);
    assert_eq!(slow.decisions, STEPS_PER_CLOCK_READING);
    let steps = f64::from(STEPS_PER_CLOCK_READING - 1);
    assert!((out.summary.time_s - steps * SIM.plant_dt_s).abs() < 1e-9, "{}", out.summary.time_s);
    assert!(out.summary.distance_m > 0.0 && out.summary.distance_m < 100.0);
}

/// A held decision is followed by a question at once: the first one is not applied.
#[test]
fn a_stop_after_a_held_decision_ends_the_run_before_it_is_applied() {
    let mut slow = Slow { hold_m: Some(500.0), decisions: 0 };
    let out = stop::watched(stop_counting, || drive_flat(&mut slow));
    assert!(out.stopped);
    assert_eq!((ASKED.get(), slow.decisions), (1, 1));
    assert_eq!((out.summary.distance_m, out.summary.time_s), (0.0, 0.0));
}

/// Without a hook the same controller drives to the road's end.
#[test]
fn without_a_hook_the_run_is_not_stopped() {
    let out = drive_flat(&mut Slow { hold_m: Some(500.0), decisions: 0 });
    assert!(!out.stopped);
    assert!((out.summary.distance_m - 10_000.0).abs() < 1e-3);
}

/// A solve whose first stage finds the stop asked ends there: no plan, no transition evaluated;
/// the same solve without a hook is feasible.
#[test]
fn a_solve_ends_at_the_stage_where_it_asks() {
    let vehicle = Vehicle::new(VehicleParams::default()).unwrap();
    let params = DpSettings::thesis();
    let slopes = vec![0.0; params.stages()];
    let start = InitialState { v_mps: 85.0 / 3.6, gear: 12, stages_since_shift: params.k_lim };
    let mut solver = Solver::new(params);
    let stopped = stop::watched(stop_counting, || {
        past_the_interval();
        solver.solve(&vehicle, start, &slopes)
    });
    assert!(!stopped.feasible && stopped.transitions == 0);
    assert_eq!(ASKED.get(), 1);
    let solved = solver.solve(&vehicle, start, &slopes);
    assert!(solved.feasible && solved.transitions > 0);
}

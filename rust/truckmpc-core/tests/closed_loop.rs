//! The closed loop in Rust: runs over whole roads, the trace's samples, stalls.

mod common;

use std::sync::Arc;

use truckmpc_core::control::{GearLogic, PiController, RecedingController, ShiftCounter};
use truckmpc_core::dp::DpSettings;
use truckmpc_core::sim::{run, RunOutput};
use truckmpc_core::{CruiseParams, MpcParams, PiParams, SimParams};
use truckmpc_core::{Road, Vehicle, VehicleParams};

const SIM: SimParams =
    SimParams { plant_dt_s: 0.05, trace_step_m: 25.0, start_speed_kmh: None, controller_mass_kg: None };

/// Flat lead-in of 500 m, a 1000 m hill of `slope`, a flat run-out of 500 m; altitudes per point.
fn hill(slope: f64) -> (Arc<Road>, Vec<f64>) {
    let road = Road::new(vec![0.0, 500.0, 1500.0, 2000.0], vec![0.0, slope, 0.0]).unwrap();
    (Arc::new(road), vec![0.0, 0.0, 1000.0 * slope, 1000.0 * slope])
}

fn run_pi(slope: f64, sim: &SimParams) -> RunOutput {
    let vehicle = Arc::new(Vehicle::new(VehicleParams::default()).unwrap());
    let (road, altitude) = hill(slope);
    let mut pi = PiController::new(vehicle.clone(), &PiParams::default(), &CruiseParams::default()).unwrap();
    run(&vehicle, &road, &altitude, &mut pi, sim, sim.start_speed_kmh.unwrap_or(85.0)).unwrap()
}

#[test]
fn pi_drives_a_hill_to_the_end_sampling_every_step() {
    let out = run_pi(0.02, &SIM);
    let s = &out.summary;
    assert_eq!(out.controller, "pi");
    assert!(!s.stalled && s.message.is_none());
    assert!((s.distance_m - 2000.0).abs() < 1e-3);
    assert!(s.fuel_kg > 0.3 && s.fuel_kg < 1.5, "{}", s.fuel_kg);
    let t = &out.trace;
    assert_eq!(t.distance_m.len(), 81);
    assert!(t.distance_m.windows(2).all(|w| (w[1] - w[0] - 25.0).abs() < 1e-6));
    assert_eq!(t.slope[30], 0.02);
    assert!((t.altitude_m[40] - 10.0).abs() < 1e-9);
    assert_eq!(t.altitude_m[80], 20.0);
    assert!(s.realtime_ratio.unwrap() > 0.0 && s.solver.is_none());
}

#[test]
fn a_hill_too_steep_stalls_with_a_message() {
    let out = run_pi(0.3, &SIM);
    let s = &out.summary;
    assert!(s.stalled);
    let at = s.stall_distance_m.unwrap();
    assert!(at > 500.0 && at < 1500.0);
    assert!(s.message.as_deref().unwrap().starts_with("stalled at km 0."), "{:?}", s.message);
    assert_eq!(*out.trace.distance_m.last().unwrap(), at);
}

#[test]
fn a_start_below_the_stall_speed_ends_at_once() {
    let out = run_pi(0.0, &SimParams { start_speed_kmh: Some(1.0), ..SIM });
    assert!(out.summary.stalled);
    assert_eq!(out.trace.distance_m, vec![0.0]);
    assert_eq!(out.trace.gear, vec![1]);
}

#[test]
fn mpc_drives_a_hill_once_per_stage() {
    let vehicle = Arc::new(Vehicle::new(VehicleParams::default()).unwrap());
    let (road, altitude) = hill(0.03);
    let gears = GearLogic::new(&vehicle, &PiParams::default()).unwrap();
    let mpc = MpcParams { horizon_m: 1000.0, delta_kmh: 0.2, ..MpcParams::thesis() };
    let params = DpSettings::new(&mpc, &CruiseParams::default()).unwrap();
    let mut mpc = RecedingController::new(vehicle.clone(), params, gears);
    let out = run(&vehicle, &road, &altitude, &mut mpc, &SIM, 85.0).unwrap();
    let stats = out.summary.solver.unwrap();
    assert_eq!(out.controller, "mpc");
    assert_eq!(stats.solves, 2000 / 25 + 1, "one solve at the start and one per stage");
    assert_eq!(stats.infeasible_solves, 0);
    assert!((out.summary.distance_m - 2000.0).abs() < 1e-3);
    assert!(stats.transitions_per_solve() > 0.0);
}

#[test]
fn bad_settings_are_errors_naming_the_key() {
    let vehicle = Arc::new(Vehicle::new(VehicleParams::default()).unwrap());
    let (road, altitude) = hill(0.0);
    let mut pi = PiController::new(vehicle.clone(), &PiParams::default(), &CruiseParams::default()).unwrap();
    let bad = SimParams { plant_dt_s: 0.0, ..SIM };
    let err = run(&vehicle, &road, &altitude, &mut pi, &bad, 85.0).unwrap_err().to_string();
    assert!(err.starts_with("plant_dt_s: "), "{err}");
    let err = run(&vehicle, &road, &altitude[..2], &mut pi, &SIM, 85.0).unwrap_err().to_string();
    assert!(err.starts_with("altitude_m: "), "{err}");
}

#[test]
fn shift_counter_restarts_on_a_shift_and_saturates_at_k_lim() {
    let mut counter = ShiftCounter::new(3);
    assert_eq!(counter.stages(), 3, "a shift is allowed at the start");
    counter.record(12, 11);
    assert_eq!(counter.stages(), 1);
    counter.record(11, 11);
    counter.record(11, 11);
    counter.record(11, 11);
    assert_eq!(counter.stages(), 3);
    counter.record(11, 0);
    assert_eq!(counter.stages(), 1, "neutral counts as a shift");
}

/// The controller plans on its map while the plant drives the road: an MPC told of a 3 % hill on a
/// flat road speeds up before it and slows down on it (a different run from the one on the true
/// road, though the plant climbs nothing); its map must span the road.
#[test]
fn the_controller_plans_on_its_map_while_the_plant_drives_the_road() {
    use truckmpc_core::sim::run_on_map;
    let vehicle = Arc::new(Vehicle::new(VehicleParams::default()).unwrap());
    let (flat, altitude) = hill(0.0);
    let (map, _) = hill(0.03);
    let mpc = MpcParams { horizon_m: 1000.0, delta_kmh: 0.2, ..MpcParams::thesis() };
    let controller = || {
        let gears = GearLogic::new(&vehicle, &PiParams::default()).unwrap();
        RecedingController::new(vehicle.clone(), DpSettings::new(&mpc, &CruiseParams::default()).unwrap(), gears)
    };
    let truth = run(&vehicle, &flat, &altitude, &mut controller(), &SIM, 85.0).unwrap();
    let fooled = run_on_map(&vehicle, &flat, &map, &altitude, &mut controller(), &SIM, 85.0).unwrap();
    let top = |out: &RunOutput| out.trace.speed_kmh.iter().copied().fold(f64::MIN, f64::max);
    assert!(top(&truth) < 85.5, "on the true flat road the MPC holds v_ref: {}", top(&truth));
    assert!(top(&fooled) > 86.0, "told of a climb it gathers speed before it: {}", top(&fooled));
    assert!(fooled.trace.altitude_m.iter().all(|&h| h == 0.0));
    let short = Road::new(vec![0.0, 1000.0], vec![0.0]).unwrap();
    let err = run_on_map(&vehicle, &flat, &short, &altitude, &mut controller(), &SIM, 85.0).unwrap_err();
    assert!(err.to_string().contains("controller_road"), "{err}");
}

/// A controller that failed in `start` is never asked to decide; one that fails in `decide` stops
/// the loop before that decision is applied.
#[test]
fn a_failed_controller_ends_the_run_before_its_failed_decision() {
    use truckmpc_core::control::{Controller, Decision};
    use truckmpc_core::{Control, PlantState};
    struct Failing {
        fails_in_start: bool,
        decisions: u32,
    }
    impl Controller for Failing {
        fn name(&self) -> &'static str {
            "failing"
        }
        fn start(&mut self, _road: &Road, _state: &PlantState) {}
        fn decide(&mut self, _road: &Road, _state: &PlantState) -> Decision {
            self.decisions += 1;
            Decision { control: Control { pedal: 0.5, brake: 0.0, gear: 12 }, until_m: None }
        }
        fn aborted(&self) -> bool {
            self.fails_in_start || self.decisions >= 3
        }
    }
    let vehicle = Arc::new(Vehicle::new(VehicleParams::default()).unwrap());
    let (road, altitude) = hill(0.0);
    for (fails_in_start, decisions, steps) in [(true, 0, 0.0), (false, 3, 2.0)] {
        let mut failing = Failing { fails_in_start, decisions: 0 };
        let out = run(&vehicle, &road, &altitude, &mut failing, &SIM, 85.0).unwrap();
        assert_eq!(failing.decisions, decisions);
        assert!((out.summary.time_s - steps * SIM.plant_dt_s).abs() < 1e-12, "{}", out.summary.time_s);
        assert!(!out.stopped, "a failure is the controller's, not a stop the host asked");
    }
}

/// The whole-road optimum of a truck whose gearbox interrupts traction, on a long climb that it
/// drives with shifts: the plan models each shift's roll, every stage is decided from the stored
/// plan (no horizon solve after the first), and the plant burns what the plan predicts.
#[test]
fn the_whole_road_optimum_of_a_truck_that_interrupts_traction_drives_its_plan() {
    let vehicle = Arc::new(common::map_vehicle());
    let road = Road::new(vec![0.0, 500.0, 3500.0, 5000.0], vec![0.0, 0.045, 0.0]).unwrap();
    let altitude = vec![0.0, 0.0, 135.0, 135.0];
    let gears = GearLogic::new(&vehicle, &PiParams::default()).unwrap();
    let params = DpSettings::default();
    assert!(params.mpc.plan_interruption, "the plan models the interruption by default");
    let mut optimal = RecedingController::whole_road(vehicle.clone(), params, gears);
    let out = run(&vehicle, &Arc::new(road), &altitude, &mut optimal, &SIM, 85.0).unwrap();
    let stats = out.summary.solver.unwrap();
    let plan = stats.plan.unwrap();
    assert!(out.summary.gear_shifts >= 2, "the climb is driven with {} shifts", out.summary.gear_shifts);
    assert_eq!(stats.horizon_solves, 1, "stages decided off the stored plan");
    let gap = out.summary.fuel_kg / plan.fuel_kg - 1.0;
    assert!(gap.abs() < 5e-4, "plant {} kg against plan {} kg", out.summary.fuel_kg, plan.fuel_kg);
}

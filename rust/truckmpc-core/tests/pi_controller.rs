//! The PI cruise controller (section 2.5, table A.4) and its gear logic (table A.3).

use std::sync::Arc;

use truckmpc_core::control::{Controller, GearLogic, PiController};
use truckmpc_core::levels::stationary;
use truckmpc_core::{CruiseParams, PiParams};
use truckmpc_core::{PlantState, Road, Vehicle, VehicleParams};

const KMH: f64 = 3.6;

/// Table A.4's gains and table A.3's thresholds for the 12-gear truck.
fn table_params() -> PiParams {
    let mut down = vec![Some(1300.0); 12];
    down[0] = None;
    let mut up = vec![Some(1800.0); 12];
    up[10] = Some(1700.0);
    up[11] = None;
    PiParams {
        pedal_kp: 1.845,
        pedal_ki: 0.2,
        pedal_integrator_limit: 30.0,
        brake_kp: 0.3,
        brake_ki: 0.02,
        brake_integrator_limit: 30.0,
        gear_down_rpm: down,
        gear_up_rpm: up,
    }
}

fn vehicle() -> Arc<Vehicle> {
    Arc::new(Vehicle::new(VehicleParams::default()).unwrap())
}

fn state(v_kmh: f64, t_s: f64) -> PlantState {
    PlantState { s_m: 0.0, v_mps: v_kmh / KMH, t_s, fuel_g: 0.0, brake_energy_j: 0.0, returned: 0.0, stalled: false }
}

fn flat() -> Road {
    Road::new(vec![0.0, 1000.0], vec![0.0]).unwrap()
}

#[test]
fn pedal_integrator_saturates_on_a_steep_climb() {
    let mut pi = PiController::new(vehicle(), &table_params(), &CruiseParams::default()).unwrap();
    pi.reset(85.0 / KMH, 0.0, 0.0);
    let mut last = None;
    for k in 1..2000 {
        let decision = pi.decide(&flat(), &state(60.0, 0.05 * k as f64));
        assert_eq!(decision.until_m, None);
        last = Some(decision.control);
    }
    assert_eq!(pi.integrators().0, 30.0);
    let u = last.unwrap();
    assert_eq!((u.pedal, u.brake), (1.0, 0.0));
}

#[test]
fn start_holds_v_ref_without_transient() {
    let vehicle = vehicle();
    let mut pi = PiController::new(vehicle.clone(), &table_params(), &CruiseParams::default()).unwrap();
    for slope in [0.0, 0.01, -0.005] {
        pi.reset(85.0 / KMH, slope, 0.0);
        let u = pi.decide(&flat(), &state(85.0, 0.0)).control;
        let expected = stationary(&vehicle, 85.0 / KMH, slope, 12).pedal;
        assert!((u.pedal - expected).abs() <= 1e-9 * expected, "{slope}: {} vs {expected}", u.pedal);
        assert_eq!(pi.integrators().1, -30.0);
    }
}

#[test]
fn start_takes_the_first_grade_of_the_road() {
    let road = Road::new(vec![0.0, 500.0, 1000.0], vec![0.01, 0.0]).unwrap();
    let mut started = PiController::new(vehicle(), &table_params(), &CruiseParams::default()).unwrap();
    started.start(&road, &state(85.0, 0.0));
    let mut reset = PiController::new(vehicle(), &table_params(), &CruiseParams::default()).unwrap();
    reset.reset(85.0 / KMH, 0.01, 0.0);
    assert_eq!(started.integrators(), reset.integrators());
}

#[test]
fn brake_acts_on_speed_above_v_max() {
    let mut pi = PiController::new(vehicle(), &table_params(), &CruiseParams::default()).unwrap();
    pi.reset(85.0 / KMH, 0.0, 0.0);
    assert_eq!(pi.decide(&flat(), &state(89.5, 0.05)).control.brake, 0.0);
    let above = pi.decide(&flat(), &state(93.0, 0.10)).control; // K_B * 3 - I_B * 30 > 0
    assert!(above.brake > 0.0 && above.pedal == 0.0);
}

#[test]
fn gear_logic_hysteresis() {
    let vehicle = vehicle();
    let p = table_params();
    let logic = GearLogic::new(&vehicle, &p).unwrap();
    let rpm_per_mps = vehicle.engine_speed_rpm(1.0, 12);
    assert_eq!(logic.next_gear(12, 1299.0 / rpm_per_mps), 11);
    assert_eq!(logic.next_gear(12, 1301.0 / rpm_per_mps), 12);
    // Just after a downshift from 12 the engine turns ~1600 rpm in 11: below its 1700 rpm upshift.
    assert_eq!(logic.next_gear(11, 1299.0 / rpm_per_mps), 11);
    for g in 1..12 {
        let v_up = (p.gear_up_rpm[g - 1].unwrap() + 1.0) / vehicle.engine_speed_rpm(1.0, g);
        assert_eq!(logic.next_gear(g, v_up), g + 1);
        assert_eq!(logic.next_gear(g + 1, v_up), g + 1, "an upshift from {g} lands above the downshift");
    }
    assert_eq!(logic.steady_gear(85.0 / KMH), 12);
    assert_eq!(logic.next_gear(0, 85.0 / KMH), 12, "from neutral: the settled gear");
}

#[test]
fn gear_logic_rejects_bad_thresholds_naming_the_key() {
    let vehicle = vehicle();
    let p = table_params();
    let mut up = p.gear_up_rpm.clone();
    up[10] = Some(1400.0); // 11 -> 12 at 1400 rpm lands at 1138 rpm, below 12's 1300 rpm downshift
    let err = GearLogic::new(&vehicle, &PiParams { gear_up_rpm: up, ..p.clone() }).unwrap_err().to_string();
    assert!(err.starts_with("gear_up_rpm: ") && err.contains("hunt"), "{err}");
    let short = PiParams { gear_down_rpm: p.gear_down_rpm[..11].to_vec(), ..p.clone() };
    let err = GearLogic::new(&vehicle, &short).unwrap_err().to_string();
    assert!(err.starts_with("gear_up_rpm: ") && err.contains("one threshold per gear"), "{err}");
    let mut down = p.gear_down_rpm.clone();
    down[3] = Some(1900.0);
    let err = GearLogic::new(&vehicle, &PiParams { gear_down_rpm: down, ..p.clone() }).unwrap_err().to_string();
    assert!(
        err.starts_with("gear_down_rpm: expected gear 4's downshift speed below") && err.ends_with("got 1900"),
        "{err}"
    );
}

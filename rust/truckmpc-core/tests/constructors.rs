//! The core's constructors take anything a user can write: a value or an error that names a key and
//! says what was expected, never a panic, a NaN accepted, or an error about an undeclared key.

use std::sync::Arc;

use proptest::prelude::*;
use truckmpc_core::control::{GearLogic, PiController, RecedingController};
use truckmpc_core::dp::DpSettings;
use truckmpc_core::params::{RunSettings, Value};
use truckmpc_core::sim::run;
use truckmpc_core::{CoreError, Road, Vehicle};

fn value() -> impl Strategy<Value = Value> {
    let number = prop_oneof![
        any::<f64>(),
        -1e3..1e3f64,
        Just(0.0),
        Just(f64::NAN),
        Just(f64::INFINITY),
        Just(1e308),
        Just(1e-300),
    ];
    let leaf = prop_oneof![
        Just(Value::Null),
        any::<bool>().prop_map(Value::Bool),
        any::<i64>().prop_map(Value::Int),
        (-100i64..5000).prop_map(Value::Int),
        number.prop_map(Value::Float),
        "[a-z0-9.e+-]{0,8}".prop_map(Value::Text),
    ];
    leaf.prop_recursive(2, 16, 12, |inner| prop::collection::vec(inner, 0..14).prop_map(Value::List))
}

fn key() -> impl Strategy<Value = String> {
    let declared: Vec<String> = RunSettings::specs().iter().map(|s| s.name.to_string()).collect();
    prop_oneof![9 => prop::sample::select(declared), 1 => "[a-z_]{1,12}"]
}

fn is_declared(key: &str) -> bool {
    RunSettings::specs().iter().any(|s| s.name == key)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 3000, ..ProptestConfig::default() })]

    #[test]
    fn settings_are_valid_or_an_error_naming_a_key(pairs in prop::collection::vec((key(), value()), 0..6)) {
        match RunSettings::from_values(pairs.iter().map(|(k, v)| (k.as_str(), v))) {
            Ok(settings) => {
                settings.validate().unwrap();
                prop_assert!(Vehicle::new(settings.vehicle.clone()).is_ok());
                prop_assert!(DpSettings::new(&settings.mpc, &settings.cruise).is_ok());
            }
            Err(CoreError::Invalid { key, expected, related, .. }) => {
                prop_assert!(pairs.iter().any(|(k, _)| *k == key) || is_declared(&key), "{key}");
                prop_assert!(!expected.is_empty());
                prop_assert!(related.iter().all(|k| is_declared(k)));
            }
        }
    }

    #[test]
    fn roads_are_valid_or_an_error(
        distance in prop::collection::vec(prop_oneof![-1e4..1e6f64, Just(f64::NAN), Just(1e308)], 0..8),
        slope in prop::collection::vec(prop_oneof![-0.5..0.5f64, Just(f64::NAN)], 0..8),
    ) {
        match Road::new(distance.clone(), slope) {
            Ok(road) => prop_assert!(road.end_m() > road.start_m()),
            Err(err) => prop_assert!(["distance_m", "slope"].contains(&err.key())),
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

    /// Whatever valid settings the PI and the MPC are given on a short random road, a run ends:
    /// at the road's end, in a stall, or with the inputs no longer moving the truck.
    #[test]
    fn a_run_with_valid_settings_ends(
        pairs in prop::collection::vec((prop::sample::select(vec!["mass_kg", "v_ref_kmh", "start_speed_kmh",
            "stage_m", "horizon_m", "delta_kmh", "k_lim", "grid", "allow_neutral"]), value()), 0..4),
        slopes in prop::collection::vec(-0.12..0.12f64, 1..4),
    ) {
        let Ok(settings) = RunSettings::from_values(pairs.iter().map(|(k, v)| (*k, v))) else { return Ok(()) };
        prop_assume!(settings.mpc.stages() * ((settings.cruise.v_inc_kmh + settings.cruise.v_dec_kmh)
            / settings.mpc.delta_kmh) as usize <= 200_000);
        let distance: Vec<f64> = (0..=slopes.len()).map(|i| 300.0 * i as f64).collect();
        let mut altitude = vec![0.0];
        for (i, s) in slopes.iter().enumerate() {
            altitude.push(altitude[i] + 300.0 * s);
        }
        let road = Arc::new(Road::new(distance, slopes).unwrap());
        let vehicle = Arc::new(Vehicle::new(settings.vehicle.clone()).unwrap());
        let start = settings.sim.start_speed_kmh.unwrap_or(settings.cruise.v_ref_kmh);
        let mut pi = PiController::new(vehicle.clone(), &settings.pi, &settings.cruise).unwrap();
        let out = run(&vehicle, &road, &altitude, &mut pi, &settings.sim, start).unwrap();
        prop_assert!(out.summary.stalled || (out.summary.distance_m - road.end_m()).abs() < 1e-3 || out.summary.message.is_some());
        let gears = GearLogic::new(&vehicle, &settings.pi).unwrap();
        let dp = DpSettings::new(&settings.mpc, &settings.cruise).unwrap();
        let mut mpc = RecedingController::new(vehicle.clone(), dp, gears);
        let out = run(&vehicle, &road, &altitude, &mut mpc, &settings.sim, start).unwrap();
        prop_assert!(out.summary.fuel_kg.is_finite() && out.summary.time_s.is_finite());
    }
}

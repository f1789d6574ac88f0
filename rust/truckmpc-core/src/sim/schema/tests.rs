//! The outputs' declaration's tests: unique names, a trace's columns in order, and a spec's record
//! against the declaration.

use super::*;
use std::collections::HashSet;

#[test]
fn names_are_unique_and_recomputed_figures_name_declared_ones() {
    let names: HashSet<_> = SUMMARY.iter().map(|f| f.spec.name).collect();
    assert_eq!(names.len(), SUMMARY.len());
    assert_eq!(TRACE.iter().map(|c| c.spec.name).collect::<HashSet<_>>().len(), TRACE.len());
    for f in SUMMARY {
        if let Some(of) = f.spec.merge.of() {
            assert!(names.contains(of), "{} is recomputed from {of}", f.spec.name);
        }
        assert_eq!(f.read.is_some(), f.spec.source == Source::Core, "{}", f.spec.name);
    }
}

#[test]
fn a_trace_gives_every_column_once_in_order() {
    let two = vec![1.0, 2.0];
    let trace = Trace {
        distance_m: two.clone(),
        time_s: two.clone(),
        speed_kmh: two.clone(),
        gear: vec![3, 0],
        pedal: two.clone(),
        brake: two.clone(),
        engine_speed_rpm: two.clone(),
        slope: two.clone(),
        altitude_m: two.clone(),
        fuel_g: two.clone(),
        brake_energy_kj: two.clone(),
        ..Trace::default()
    };
    let columns: Vec<_> = trace.clone().into_columns().collect();
    let names: Vec<_> = columns.iter().map(|(spec, _)| spec.name).collect();
    let expected = ["distance_m", "time_s", "speed_kmh", "gear", "pedal", "brake", "engine_speed_rpm", "slope"];
    assert_eq!(names[..8], expected);
    assert_eq!(names[8..], ["altitude_m", "fuel_g", "brake_energy_kj"], "a fuel tank's run has no battery columns");
    assert_eq!(columns[3].1, Column::Count(vec![3, 0]));
    assert_eq!(columns[9].1, Column::Number(two.clone()));
    let battery = Trace {
        fuel_g: Vec::new(),
        battery_energy_kwh: two.clone(),
        soc_pct: two.clone(),
        battery_power_kw: two,
        ..trace
    };
    let names: Vec<_> = battery.into_columns().map(|(spec, _)| spec.name).collect();
    assert_eq!(names[8..], ["altitude_m", "brake_energy_kj", "battery_energy_kwh", "soc_pct", "battery_power_kw"]);
}

#[test]
fn a_record_has_every_field_of_the_spec() {
    let text = |s: &str| Value::Text(s.to_string());
    let per_100km = SUMMARY.iter().find(|f| f.spec.name == "gear_shifts_per_100km").expect("declared").spec;
    let expected = vec![
        ("name", text("gear_shifts_per_100km")),
        ("unit", text("1/100km")),
        ("label", text("gear shifts per 100 km")),
        ("doc", text("Gear shifts per 100 km; null when the truck did not move.")),
        ("kind", text("number")),
        ("runs", text("every")),
        ("source", text("core")),
        ("merge", text("per_100km")),
        ("merge_of", text("gear_shifts")),
        ("sweep", text("all")),
        ("decimals", Value::Null),
    ];
    assert_eq!(per_100km.record(), expected);
    let speed = TRACE.iter().find(|c| c.spec.name == "speed_kmh").expect("declared").spec.record();
    assert_eq!(speed[8..], [("merge_of", Value::Null), ("sweep", text("")), ("decimals", Value::Int(5))]);
}

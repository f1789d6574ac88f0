//! A model's answers as named figures, for the tools above the core (the binding hands them on as
//! they are): the levels holding a speed and the engine's operating point there, a map-based
//! truck at a driving state, the speed band along a road. Each checks its arguments
//! and names the one at fault.

use crate::band::SpeedBand;
use crate::error::{CoreError, CoreResult};
use crate::levels;
use crate::params::{CruiseParams, ParamSet, Value};
use crate::plant::Control;
use crate::powertrain::{ElectricModel, ElectricTruck, MapTruck, Powertrain, RPM_PER_RAD_S};
use crate::road::Road;
use crate::vehicle::{Vehicle, NEUTRAL};

/// Named figures, in the order a table shows them.
pub type Figures = Vec<(&'static str, Value)>;

/// Refuse a gear outside `lowest..=forward_gears`, naming `gear`.
pub fn check_gear(gear: usize, lowest: usize, forward_gears: usize) -> CoreResult<()> {
    if gear < lowest || gear > forward_gears {
        let what =
            if lowest == NEUTRAL { format!("0 (neutral) to {forward_gears}") } else { format!("1..={forward_gears}") };
        return Err(CoreError::invalid("gear", what).got(gear));
    }
    Ok(())
}

/// The levels holding `v_mps` (> 0) on grade `slope` [-] (Δh/ΔL, 0.01 = 1 %) in `gear` (tables B.1/B.2): `pedal`, `brake`,
/// `feasible`, `eigenvalue_per_m` [1/m], and the engine there: `engine_speed_rpm`,
/// `engine_torque_nm`, `fuel_rate_g_per_h`.
pub fn stationary(vehicle: &Vehicle, v_mps: f64, slope: f64, gear: usize) -> CoreResult<Figures> {
    check_gear(gear, NEUTRAL, vehicle.forward_gears())?;
    if !(v_mps > 0.0) {
        return Err(CoreError::invalid("speed", "> 0").got(v_mps));
    }
    let s = levels::stationary(vehicle, v_mps, slope, gear);
    let n_rpm = vehicle.engine_speed_rpm(v_mps, gear);
    Ok(vec![
        ("pedal", Value::Float(s.pedal)),
        ("brake", Value::Float(s.brake)),
        ("feasible", Value::Bool(s.feasible)),
        ("eigenvalue_per_m", Value::Float(s.eigenvalue_per_m)),
        ("engine_speed_rpm", Value::Float(n_rpm)),
        ("engine_torque_nm", Value::Float(vehicle.engine_torque_nm(n_rpm, s.pedal, gear))),
        ("fuel_rate_g_per_h", Value::Float(vehicle.fuel_rate_gps(v_mps, s.pedal, gear) * 3600.0)),
    ])
}

/// Engine speed (2.9) [rpm] of `vehicle` at `v_mps` in `gear` (0, neutral: the idle speed);
/// refuses a gear the truck does not have, naming `gear`.
pub fn engine_speed_rpm(vehicle: &Vehicle, v_mps: f64, gear: usize) -> CoreResult<f64> {
    check_gear(gear, NEUTRAL, vehicle.forward_gears())?;
    Ok(vehicle.engine_speed_rpm(v_mps, gear))
}

/// Engine torque [Nm] of `vehicle` at `v_mps` with `pedal` ∈ [0, 1] in `gear` (1..=n): the thesis
/// model's torque map, or the torque giving the pedal's share of the wheel torque between fuel cut
/// and full load (a map-based truck).
pub fn engine_torque_nm(vehicle: &Vehicle, v_mps: f64, pedal: f64, gear: usize) -> CoreResult<f64> {
    check_gear(gear, 1, vehicle.forward_gears())?;
    Ok(vehicle.engine_torque_nm(vehicle.engine_speed_rpm(v_mps, gear), pedal, gear))
}

/// A map-based `truck` at `v_mps` (> 0), `acc_mps2` and `slope_rad`: the drag area `cda_m2` [m²]
/// at that speed, the road loads [W] `air_w`, `rolling_w`, `slope_w`, `vehicle_inertia_w`,
/// `wheels_inertia_w` and `wheel_w` (their sum), `neutral_drag_w` (what the axle and an output
/// retarder take from the wheels in neutral), and, in a `gear` (1..=gears), the engine's
/// operating point: `engine_speed_rpm`, `engine_torque_nm`, `engine_power_w`, `fuel_rate_g_per_h`
/// (NaN beyond the full-load curve's speeds), `brake_power_w` (at the wheels, beyond the engine's
/// drag) and `feasible`.
pub fn driving_state(
    truck: &MapTruck,
    v_mps: f64,
    acc_mps2: f64,
    slope_rad: f64,
    gear: Option<usize>,
) -> CoreResult<Figures> {
    if !(v_mps > 0.0 && v_mps.is_finite() && acc_mps2.is_finite() && slope_rad.is_finite()) {
        let got = format!("{v_mps}, {acc_mps2}, {slope_rad}");
        return Err(CoreError::invalid("v_mps, acc_mps2, slope_rad", "a finite speed > 0 and finite values").got(got));
    }
    let l = truck.road_loads(v_mps, acc_mps2, slope_rad);
    let mut figures: Figures = [
        ("cda_m2", truck.cda_m2(v_mps)),
        ("air_w", l.air_w),
        ("rolling_w", l.rolling_w),
        ("slope_w", l.slope_w),
        ("vehicle_inertia_w", l.vehicle_inertia_w),
        ("wheels_inertia_w", l.wheels_inertia_w),
        ("wheel_w", l.wheel_w()),
        (
            "neutral_drag_w",
            -truck.driveline().neutral_wheel_torque_nm(v_mps) / truck.driveline().wheel_radius_m() * v_mps,
        ),
    ]
    .into_iter()
    .map(|(k, x)| (k, Value::Float(x)))
    .collect();
    if let Some(gear) = gear {
        check_gear(gear, 1, truck.driveline().gears())?;
        let op = truck.operating_point(v_mps, acc_mps2, slope_rad, gear).expect("finite arguments, speed > 0");
        figures.extend([
            ("engine_speed_rpm", Value::Float(op.engine_speed_rpm)),
            ("engine_torque_nm", Value::Float(op.engine_torque_nm)),
            ("engine_power_w", Value::Float(op.engine_torque_nm * op.engine_speed_rpm / RPM_PER_RAD_S)),
            ("fuel_rate_g_per_h", Value::Float(op.fuel_g_per_h)),
            ("brake_power_w", Value::Float(op.brake_power_w)),
            ("feasible", Value::Bool(op.feasible)),
        ]);
    }
    Ok(figures)
}

/// `truck`'s engine at `speed_rpm` and `torque_nm` (finite): `max_torque_nm` and `drag_torque_nm`
/// (negative) at that speed, `fuel_rate_g_per_h` (0 at or below the drag torque; the nearest
/// boundary value outside the map) and `in_fuel_map` (inside the fuel map's convex hull).
pub fn engine_point(truck: &MapTruck, speed_rpm: f64, torque_nm: f64) -> CoreResult<Figures> {
    if !(speed_rpm.is_finite() && torque_nm.is_finite()) {
        let got = format!("{speed_rpm}, {torque_nm}");
        return Err(CoreError::invalid("speed_rpm, torque_nm", "finite numbers").got(got));
    }
    let engine = truck.engine();
    let inside = engine.fuel_map().interpolate(speed_rpm, torque_nm).is_some();
    Ok(vec![
        ("max_torque_nm", Value::Float(engine.max_torque_nm(speed_rpm))),
        ("drag_torque_nm", Value::Float(engine.drag_torque_nm(speed_rpm))),
        ("fuel_rate_g_per_h", Value::Float(engine.fuel_rate_g_per_h(speed_rpm, torque_nm))),
        ("in_fuel_map", Value::Bool(inside)),
    ])
}

/// `truck`'s driveline in `gear` (1..=gears) at engine speed `speed_rpm` (> 0) with `torque_nm` at
/// the gearbox input: the powers [W] each stage loses, `gearbox_loss_w`, `retarder_loss_w` and
/// `axle_loss_w`, and the `wheel_torque_nm` it gives.
pub fn driveline_point(truck: &MapTruck, speed_rpm: f64, torque_nm: f64, gear: usize) -> CoreResult<Figures> {
    let driveline = truck.driveline();
    check_gear(gear, 1, driveline.gears())?;
    if !(speed_rpm > 0.0 && speed_rpm.is_finite() && torque_nm.is_finite()) {
        let got = format!("{speed_rpm}, {torque_nm}");
        return Err(CoreError::invalid("speed_rpm, torque_nm", "a finite speed > 0 and a finite torque").got(got));
    }
    let losses = driveline.stage_losses_w(torque_nm, gear, speed_rpm);
    Ok(vec![
        ("gearbox_loss_w", Value::Float(losses.gearbox_w)),
        ("retarder_loss_w", Value::Float(losses.retarder_w)),
        ("axle_loss_w", Value::Float(losses.axle_w)),
        ("wheel_torque_nm", Value::Float(driveline.wheel_torque_nm(torque_nm, gear, speed_rpm))),
    ])
}

/// What a map-based truck is, as a table of `truck info` shows it: `gears`, `rated_power_w` (the
/// most the full-load curve gives) at `rated_speed_rpm`, the speeds the full-load curve covers
/// (`full_load_speed_range_rpm`), the speeds and torques the fuel map covers
/// (`fuel_map_speed_range_rpm`, `fuel_map_torque_range_nm`), each as [lowest, highest], whether
/// loss maps give the gears' and the axle's losses (`gear_loss_maps`, `axle_loss_map`), and the
/// driveline's efficiency where none does (`efficiency`, gearbox times axle).
pub fn truck_facts(truck: &MapTruck) -> Figures {
    let (engine, driveline) = (truck.engine(), truck.driveline());
    let (rated_power_w, rated_speed_rpm) = engine.rated_power();
    let range = |(lo, hi): (f64, f64)| Value::List(vec![Value::Float(lo), Value::Float(hi)]);
    let (gear_maps, axle_map) = driveline.has_loss_maps();
    vec![
        ("gears", Value::Int(driveline.gears() as i64)),
        ("rated_power_w", Value::Float(rated_power_w)),
        ("rated_speed_rpm", Value::Float(rated_speed_rpm)),
        ("full_load_speed_range_rpm", range(engine.speed_range_rpm())),
        ("fuel_map_speed_range_rpm", range(engine.fuel_map().speed_range_rpm())),
        ("fuel_map_torque_range_nm", range(engine.fuel_map().torque_range_nm())),
        ("gear_loss_maps", Value::Bool(gear_maps)),
        ("axle_loss_map", Value::Bool(axle_map)),
        ("efficiency", Value::Float(driveline.efficiency())),
    ]
}

/// What a battery-electric truck is: its machines' torque and speed, the reduction, the battery
/// at the start's state of charge.
pub fn electric_facts(truck: &ElectricTruck) -> Figures {
    let (machines, battery, thermal) = (truck.machines(), truck.battery(), truck.thermal());
    let top = machines.top_rpm();
    let peak_w = (0..=200)
        .map(|k| top * k as f64 / 200.0)
        .map(|n| machines.max_drive_nm(n) * n / RPM_PER_RAD_S)
        .fold(0.0, f64::max);
    vec![
        ("gears", Value::Int(1)),
        ("max_torque_nm", Value::Float(machines.max_drive_nm(0.0))),
        ("peak_power_w", Value::Float(peak_w)),
        ("top_speed_rpm", Value::Float(top)),
        ("reduction_ratio", Value::Float(truck.ratio())),
        ("battery_ocv_v", Value::Float(battery.ocv_v)),
        ("battery_resistance_ohm", Value::Float(battery.resistance_ohm)),
        ("battery_max_discharge_w", Value::Float(battery.max_discharge_w())),
        ("battery_max_charge_w", Value::Float(battery.max_charge_w())),
        ("soc_start_pct", Value::Float(100.0 * battery.soc)),
        (
            "usable_window_pct",
            Value::List(vec![Value::Float(100.0 * battery.soc_window.0), Value::Float(100.0 * battery.soc_window.1)]),
        ),
        (
            "usable_energy_kwh",
            Value::Float(battery.energy_per_soc_j() * (battery.soc_window.1 - battery.soc_window.0) / 3.6e6),
        ),
        ("effective_mass_kg", Value::Float(effective_mass_kg(truck))),
        ("continuous_torque_nm", thermal.map_or(Value::Null, |t| Value::Float(t.continuous_nm))),
        ("continuous_loss_w", thermal.map_or(Value::Null, |t| Value::Float(t.continuous_loss_w))),
        ("overload_buffer_kj", thermal.map_or(Value::Null, |t| Value::Float(t.buffer_j / 1e3))),
    ]
}

/// The mass [kg] whose kinetic energy ½·m·v² the truck's moves: the body's, and the wheels' and
/// the machines' inertia seen at the wheels' rim.
fn effective_mass_kg(truck: &ElectricTruck) -> f64 {
    let (body, r) = (truck.body(), truck.wheel_radius_m());
    body.mass_kg + (body.wheels_inertia_kgm2 + truck.machines().inertia_kgm2() * truck.ratio().powi(2)) / (r * r)
}

/// Where a battery-electric truck's power goes under each control (`pedal`, `brake` at `v_mps`,
/// element by element; service brakes of `brake_torque_max_nm` [Nm]): the columns of
/// [`crate::powertrain::electric::PowerFlows`] [W], and the friction brakes' power [W].
pub fn electric_flows(
    truck: &ElectricTruck,
    (v_mps, pedal, brake): (&[f64], &[f64], &[f64]),
    brake_torque_max_nm: f64,
) -> CoreResult<Vec<(&'static str, Vec<f64>)>> {
    if pedal.len() != v_mps.len() || brake.len() != v_mps.len() {
        return Err(CoreError::invalid("pedal", "one pedal and one brake level per speed").got(pedal.len()));
    }
    let model = ElectricModel::new(truck.clone(), brake_torque_max_nm);
    let names =
        ["battery_w", "battery_loss_w", "aux_w", "machine_loss_w", "reduction_loss_w", "wheel_w", "friction_brake_w"];
    let mut columns: Vec<(&'static str, Vec<f64>)> =
        names.iter().map(|&n| (n, Vec::with_capacity(v_mps.len()))).collect();
    for ((&v, &p), &b) in v_mps.iter().zip(pedal).zip(brake) {
        let u = Control { pedal: p, brake: b, gear: 1 };
        let f = model.power_flows(v, u);
        let friction_w = model.friction_brake_force_n(v, u) * v;
        let values =
            [f.battery_w, f.battery_loss_w, f.aux_w, f.machine_loss_w, f.reduction_loss_w, f.wheel_w, friction_w];
        for ((_, column), value) in columns.iter_mut().zip(values) {
            column.push(value);
        }
    }
    Ok(columns)
}

/// The machines of a battery-electric truck at `speed_rpm` and `torque_nm` (all machines
/// together, at the shaft): their electric power and loss from the power map's triangulation, their
/// torque limits and drag there, and the battery's current and power for that electric power.
pub fn machine_point(truck: &ElectricTruck, speed_rpm: f64, torque_nm: f64) -> CoreResult<Figures> {
    if !(speed_rpm.is_finite() && speed_rpm >= 0.0 && torque_nm.is_finite()) {
        return Err(CoreError::invalid("speed_rpm", "a speed >= 0 and a finite torque")
            .got(format!("{speed_rpm} rpm, {torque_nm} Nm")));
    }
    let machines = truck.machines();
    let electric_w = machines.electric_power_w(speed_rpm, torque_nm);
    let battery = truck.battery();
    Ok(vec![
        ("electric_power_w", Value::Float(electric_w)),
        ("loss_w", Value::Float(machines.loss_w(speed_rpm, torque_nm))),
        ("max_drive_nm", Value::Float(machines.max_drive_nm(speed_rpm))),
        ("max_brake_nm", Value::Float(machines.max_brake_nm(speed_rpm))),
        ("drag_nm", Value::Float(machines.drag_nm(speed_rpm))),
        ("battery_current_a", Value::Float(battery.current_a(electric_w))),
        ("battery_internal_w", Value::Float(battery.internal_power_w(electric_w))),
    ])
}

/// A battery-electric truck holding `v_mps` (> 0) on `slope_rad` with service brakes of
/// `brake_torque_max_nm` [Nm]: the pedal or brake level that holds it (feasible when the machines
/// and the battery give the torque), the machines' speed and torque, and where the battery's power
/// goes (see [`PowerFlows`]); the friction brakes' power where braking needs more than the
/// machines take back.
pub fn electric_state(
    truck: &ElectricTruck,
    v_mps: f64,
    slope_rad: f64,
    brake_torque_max_nm: f64,
) -> CoreResult<Figures> {
    if !(v_mps.is_finite() && v_mps > 0.0) {
        return Err(CoreError::invalid("v_mps", "a speed > 0 [m/s]").got(v_mps));
    }
    if !slope_rad.is_finite() {
        return Err(CoreError::invalid("slope_rad", "a finite angle [rad]").got(slope_rad));
    }
    let model = ElectricModel::new(truck.clone(), brake_torque_max_nm);
    let need_nm = model.air_torque_nm(v_mps) + model.slope_torque_nm(slope_rad.tan());
    let (drag, full, _) = model.wheel_torques_nm(v_mps);
    let (pedal, brake) = if need_nm >= drag {
        ((need_nm - drag) / (full - drag), 0.0)
    } else {
        (0.0, (drag - need_nm) / brake_torque_max_nm)
    };
    let feasible = pedal <= 1.0 && brake <= 1.0;
    let u = Control { pedal: pedal.min(1.0), brake: brake.min(1.0), gear: 1 };
    let f = model.power_flows(v_mps, u);
    let friction_w = model.friction_brake_force_n(v_mps, u) * v_mps;
    Ok(vec![
        ("pedal", Value::Float(u.pedal)),
        ("brake", Value::Float(u.brake)),
        ("feasible", Value::Bool(feasible)),
        ("machine_speed_rpm", Value::Float(f.machine_rpm)),
        ("machine_torque_nm", Value::Float(f.machine_nm)),
        ("battery_power_w", Value::Float(f.battery_w)),
        ("battery_loss_w", Value::Float(f.battery_loss_w)),
        ("aux_power_w", Value::Float(f.aux_w)),
        ("machine_loss_w", Value::Float(f.machine_loss_w)),
        ("reduction_loss_w", Value::Float(f.reduction_loss_w)),
        ("wheel_power_w", Value::Float(f.wheel_w)),
        ("friction_brake_power_w", Value::Float(friction_w)),
    ])
}

/// The speed band of `cruise` along `road` at each of `distance_m` [m] (increasing) [km/h]: the
/// stretch's set speed, v_min and v_max.
pub fn speed_band(road: &Road, cruise: &CruiseParams, distance_m: &[f64]) -> CoreResult<[Vec<f64>; 3]> {
    cruise.check_ranges()?;
    let band = SpeedBand::new(road, cruise);
    let (mut hint, mut out) = (0, [Vec::new(), Vec::new(), Vec::new()]);
    for &s_m in distance_m {
        out[0].push(band.set_speed_kmh(s_m, &mut hint));
        let at = band.at(s_m, &mut hint);
        out[1].push(at.v_min_kmh);
        out[2].push(at.v_max_kmh);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::VehicleParams;

    /// The thesis's truck has 12 gears: neutral idles, gear 13 and (for a torque) neutral are
    /// refused naming `gear`; in gear the engine speed grows in proportion to the road speed.
    #[test]
    fn gear_queries_refuse_a_gear_the_truck_lacks() {
        let vehicle = Vehicle::new(VehicleParams::default()).unwrap();
        let idle = engine_speed_rpm(&vehicle, 20.0, NEUTRAL).unwrap();
        assert_eq!(idle, VehicleParams::default().idle_speed_rpm);
        let (at_10, at_20) =
            (engine_speed_rpm(&vehicle, 10.0, 12).unwrap(), engine_speed_rpm(&vehicle, 20.0, 12).unwrap());
        assert!((at_20 - 2.0 * at_10).abs() < 1e-9 && at_10 > 0.0);
        for refused in [engine_speed_rpm(&vehicle, 20.0, 13), engine_torque_nm(&vehicle, 20.0, 0.5, NEUTRAL)] {
            let CoreError::Invalid { key, .. } = refused.unwrap_err();
            assert_eq!(key, "gear");
        }
    }

    /// A map-based truck at a driving state: the drag area and the road loads at any speed, summing
    /// to the power at the wheels; in a gear the engine's power is its torque times its speed, the
    /// speed the driveline's; a gear the truck lacks, and a standstill, are refused by name.
    #[test]
    fn a_driving_state_gives_the_road_loads_and_in_a_gear_the_engine() {
        let truck = crate::powertrain::tests::truck();
        let figure = |figures: &Figures, key: &str| match figures.iter().find(|(k, _)| *k == key) {
            Some((_, Value::Float(x))) => *x,
            other => panic!("{key}: {other:?}"),
        };
        let (v, slope) = (22.0, 0.01_f64.atan());
        let loads = driving_state(&truck, v, 0.1, slope, None).unwrap();
        assert_eq!(loads.len(), 8, "no engine figures without a gear: {loads:?}");
        // The test truck's driveline has no loss map and no retarder: nothing drags in neutral.
        assert_eq!(figure(&loads, "neutral_drag_w"), 0.0);
        assert_eq!(figure(&loads, "cda_m2"), 6.0);
        let parts = ["air_w", "rolling_w", "slope_w", "vehicle_inertia_w", "wheels_inertia_w"];
        let sum: f64 = parts.iter().map(|k| figure(&loads, k)).sum();
        assert!((sum - figure(&loads, "wheel_w")).abs() < 1e-9 * sum);
        let in_gear = driving_state(&truck, v, 0.1, slope, Some(3)).unwrap();
        assert_eq!(in_gear[..8], loads[..]);
        let rpm = figure(&in_gear, "engine_speed_rpm");
        assert_eq!(rpm, truck.driveline().engine_speed_rpm(v, 3));
        let power = figure(&in_gear, "engine_torque_nm") * rpm / RPM_PER_RAD_S;
        assert!((figure(&in_gear, "engine_power_w") - power).abs() < 1e-9 * power);
        let CoreError::Invalid { key, .. } = driving_state(&truck, v, 0.0, slope, Some(4)).unwrap_err();
        assert_eq!(key, "gear");
        let CoreError::Invalid { key, .. } = driving_state(&truck, 0.0, 0.0, slope, None).unwrap_err();
        assert_eq!(key, "v_mps, acc_mps2, slope_rad");
    }
}

//! Trucks shared by the integration tests.

use truckmpc_core::{Vehicle, VehicleParams};

/// A truck from component data whose fuel map is curved (not affine in torque), with the thesis's
/// gearbox and body: the fuel of each pedal level is the map's, not full-pedal fuel × pedal. Its
/// gearbox interrupts traction for 1 s at a shift between forward gears.
pub fn map_vehicle() -> Vehicle {
    use truckmpc_core::powertrain::{Body, Driveline, Engine, MapModel, MapTruck};
    let full_load =
        [(500.0, 1000.0, -90.0), (1100.0, 2400.0, -140.0), (1800.0, 2300.0, -200.0), (2500.0, 1500.0, -260.0)];
    let fuel = |n: f64, t: f64| 1500.0 + 1.2 * n + 17.0 * t + 0.003 * t * t + 2e-3 * n * t;
    let mut map = Vec::new();
    for i in 0..11 {
        for j in 0..10 {
            let (n, t) = (500.0 + 200.0 * i as f64, -300.0 + 300.0 * j as f64);
            map.push((n, t, fuel(n, t).max(0.0)));
        }
    }
    let p = VehicleParams::default();
    let engine = Engine::new(600.0, 3.5, &full_load, &map).unwrap();
    let driveline =
        Driveline::new((&p.gear_ratios, p.final_drive_ratio), (0.95, 0.97, 15.0), p.wheel_radius_m).unwrap();
    let body = Body {
        mass_kg: 40_000.0,
        wheels_inertia_kgm2: 32.9,
        cda_m2: 5.5,
        air_density_kgpm3: 1.2,
        rolling_resistance: 0.006,
        aux_power_w: 4000.0,
    };
    let truck = MapTruck::new(engine, driveline, body).unwrap();
    Vehicle::from_map(std::sync::Arc::new(MapModel::new(truck, p.brake_torque_max_nm, 1.0)), &p).unwrap()
}

//! The fuel–time cost: fuel + β·trip time, and what kinetic energy is worth in fuel.
//!
//! **β from v_ref.** Holding a steady speed v on a flat road costs, per metre, F(v) + β/v, where
//! F(v) [g/m] is the fuel per metre that holds v in the cruise gear (the DP's own stage model:
//! fuel rate at the steady pedal, divided by v). That cost is stationary where F'(v) = β/v², so
//! the β that makes v_ref the best steady speed is β = v_ref²·F'(v_ref) (in terms of the fuel
//! rate ṁ = F·v: β = v·ṁ'(v) − ṁ(v), the fuel rate's marginal increase with speed less its
//! average). F' is taken by central differences: for the thesis's smooth engine at ±1 mm/s; for a
//! map-based truck at ±2 km/h ([`MAP_DV_MPS`]), because its map is linear on triangles, so F'
//! jumps wherever the steady operating point crosses a triangle's edge: the wider difference
//! prices time by the fuel of the speeds a cruise actually moves through.
//!
//! **Kinetic energy in fuel.** At a fixed engine speed both the engine torque (2.8) and the fuel
//! rate (B.2) are affine in the pedal, so every unit of ½v² [m²/s²] the engine adds in gear g
//! costs the same fuel at any speed and load: over a stage of length h, ½v² grows by h·a with
//! a = a0 + c1·c3·b·δ_max·P, while the fuel is (h/v)·c5·c4·v·P·δ_max, so the cost is
//! c5·c4 / (c1·c3·b) grams per unit of ½v² (b the torque map's fuelling coefficient; c1 carries
//! the vehicle's mass and the gear's rotating inertias). This prices a speed left at the end of a
//! horizon or of a run.

use crate::levels::{pedal_accel, stationary};
use crate::powertrain::{Powertrain, RateForm};
use crate::vehicle::{Vehicle, NEUTRAL};

/// Speed step of the central difference for F'(v) [m/s].
const DV_MPS: f64 = 1e-3;

/// Speed step of the central difference for F'(v) of a map-based truck [m/s]: 2 km/h.
pub const MAP_DV_MPS: f64 = 2.0 / 3.6;

/// Fuel per metre [g/m] holding `v_mps` on a flat road in `gear`; +∞ where the gear cannot hold it.
pub fn steady_fuel_g_per_m(vehicle: &Vehicle, v_mps: f64, gear: usize) -> f64 {
    let point = stationary(vehicle, v_mps, 0.0, gear);
    if !point.feasible {
        return f64::INFINITY;
    }
    vehicle.fuel_rate_gps(v_mps, point.pedal, gear) / v_mps
}

/// The forward gear that holds `v_mps` on a flat road with the least fuel, among those turning the
/// engine within [n_min, n_max] rpm (the top gear if none does).
pub fn cruise_gear(vehicle: &Vehicle, v_mps: f64, n_min_rpm: f64, n_max_rpm: f64) -> usize {
    (1..=vehicle.forward_gears())
        .filter(|&g| (n_min_rpm..=n_max_rpm).contains(&vehicle.engine_speed_rpm(v_mps, g)))
        .map(|g| (steady_fuel_g_per_m(vehicle, v_mps, g), g))
        .filter(|(fuel, _)| fuel.is_finite())
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map_or(vehicle.forward_gears(), |(_, g)| g)
}

/// β [g/s] for which steady `v_mps` in `gear` is the cheapest steady speed on a flat road under
/// fuel + β·time: v²·F'(v); NaN where the gear cannot hold the speeds around `v_mps`.
pub fn steady_beta_g_per_s(vehicle: &Vehicle, v_mps: f64, gear: usize) -> f64 {
    let dv = match vehicle.rate_form() {
        RateForm::ProportionalToPedal => DV_MPS,
        RateForm::Map => MAP_DV_MPS,
    };
    let slope =
        (steady_fuel_g_per_m(vehicle, v_mps + dv, gear) - steady_fuel_g_per_m(vehicle, v_mps - dv, gear)) / (2.0 * dv);
    let beta = v_mps * v_mps * slope;
    if beta.is_finite() {
        beta.max(0.0)
    } else {
        f64::NAN
    }
}

/// Fuel [g] per unit of ½v² [m²/s²] the engine adds in `gear` at `v_mps`: kinetic energy priced
/// in fuel. Where the powertrain has a closed form (the thesis's engine, whose torque and fuel are
/// both affine in fueling at a fixed engine speed: c5·c4 / (c1·c3·b_e) whatever the speed and
/// load), that; otherwise the marginal fuel of the pedal over its marginal acceleration,
/// (∂ṁ/∂P) / (v·∂a/∂P), where the truck holds `v_mps` on a flat road (a central difference, a
/// map's fuel being piecewise linear); NaN where it cannot hold that speed.
pub fn kinetic_fuel_g(vehicle: &Vehicle, v_mps: f64, gear: usize) -> f64 {
    debug_assert!(gear != NEUTRAL);
    if let Some(price) = vehicle.kinetic_energy_price(gear) {
        return price;
    }
    const DP: f64 = 0.02;
    let point = stationary(vehicle, v_mps, 0.0, gear);
    let gain = pedal_accel(vehicle, v_mps, gear, 0.0).gain;
    if !point.feasible || !(gain > 0.0) {
        return f64::NAN;
    }
    let (lo, hi) = ((point.pedal - DP).max(1e-9), (point.pedal + DP).min(1.0));
    let fuel = |pedal: f64| vehicle.fuel_rate_gps(v_mps, pedal, gear);
    (fuel(hi) - fuel(lo)) / (hi - lo) / (v_mps * gain)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::levels::stage_fuel_g;
    use crate::vehicle::VehicleParams;

    fn truck() -> Vehicle {
        Vehicle::new(VehicleParams::default()).unwrap()
    }

    /// Kinetic energy in fuel: the fuel of one stage at any pedal, divided by the ½v² it adds
    /// beyond the unfuelled engine, is the closed form, at several speeds, slopes and gears.
    #[test]
    fn kinetic_fuel_is_the_fuel_per_half_v2_added() {
        let vehicle = truck();
        for gear in [8, 10, 12] {
            for (v, slope, pedal) in [(15.0, 0.0, 0.3), (20.0, 0.02, 0.8), (23.6, -0.01, 0.5)] {
                let h = 25.0;
                let map = pedal_accel(&vehicle, v, gear, slope);
                if map.gain <= 0.0 {
                    continue;
                }
                // d(½v²)/ds = a, so a stage at pedal P adds h·gain·P to ½v² beyond the unfuelled engine.
                let added = h * map.gain * pedal;
                let fuel = stage_fuel_g(&vehicle, v, pedal, gear, h);
                let per_unit = fuel / added;
                assert!((per_unit / kinetic_fuel_g(&vehicle, v, gear) - 1.0).abs() < 1e-12, "{per_unit}");
            }
        }
    }

    /// With the derived β, v_ref is the cheapest steady speed on a flat road: fuel + β·time per
    /// metre is higher 1 km/h either side, and its brute-force minimum over a fine scan is v_ref.
    #[test]
    fn derived_beta_makes_v_ref_the_cheapest_steady_speed() {
        let vehicle = truck();
        for v_ref_kmh in [70.0, 80.0, 85.0] {
            let v_ref = v_ref_kmh / 3.6;
            let gear = cruise_gear(&vehicle, v_ref, 1000.0, 2000.0);
            let beta = steady_beta_g_per_s(&vehicle, v_ref, gear);
            assert!(beta > 0.0);
            let cost = |v: f64| steady_fuel_g_per_m(&vehicle, v, gear) + beta / v;
            let best = (-200..=200).map(|k| v_ref + k as f64 * 0.01).min_by(|a, b| cost(*a).total_cmp(&cost(*b)));
            assert!((best.unwrap() - v_ref).abs() <= 0.011, "{v_ref_kmh}: best {}", best.unwrap() * 3.6);
        }
    }
}

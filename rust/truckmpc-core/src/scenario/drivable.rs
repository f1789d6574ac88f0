//! Whether the truck can drive the set speed and its band at all: the check where the settings
//! meet the vehicle. A set speed beyond the truck's reach would otherwise run (the truck coasts down
//! to what it can do, or never reaches the band) and print a comparison of nothing.

use crate::error::{CoreError, CoreResult};
use crate::params::RunSettings;
use crate::vehicle::Vehicle;
use crate::KMH_PER_MPS;

/// The speeds the truck can drive [km/h]: from gear 1 at `n_min_rpm` to the top gear at `n_max_rpm`
/// (the look-ahead controller's usable engine speeds, section 5.7).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpeedLimits {
    /// Lowest usable speed: gear 1 at n_min_rpm [km/h].
    pub lowest_kmh: f64,
    /// Top speed: the top gear at n_max_rpm [km/h].
    pub top_kmh: f64,
}

/// The truck's usable speeds [km/h] with the settings' engine speed limits.
pub fn speed_limits(settings: &RunSettings, vehicle: &Vehicle) -> SpeedLimits {
    let top_gear = vehicle.forward_gears();
    SpeedLimits {
        lowest_kmh: settings.mpc.n_min_rpm / vehicle.gear(1).c4 * KMH_PER_MPS,
        top_kmh: settings.mpc.n_max_rpm / vehicle.gear(top_gear).c4 * KMH_PER_MPS,
    }
}

/// The set speeds v_ref [km/h] whose band the truck can drive: v_ref − v_dec at or above the
/// lowest usable speed, v_ref + v_inc at or below the top speed (lowest above highest when no set
/// speed fits the band).
pub fn v_ref_range_kmh(settings: &RunSettings, vehicle: &Vehicle) -> (f64, f64) {
    let limits = speed_limits(settings, vehicle);
    (limits.lowest_kmh + settings.cruise.v_dec_kmh, limits.top_kmh - settings.cruise.v_inc_kmh)
}

/// Refuse a set speed or band the truck cannot drive; the error names v_ref_kmh, the truck's limit
/// and the keys involved.
pub fn check_drivable(settings: &RunSettings, vehicle: &Vehicle) -> CoreResult<()> {
    let limits = speed_limits(settings, vehicle);
    let (v_ref, v_inc, v_dec) = (settings.cruise.v_ref_kmh, settings.cruise.v_inc_kmh, settings.cruise.v_dec_kmh);
    if v_ref + v_inc > limits.top_kmh {
        let expected = format!(
            "v_ref_kmh + v_inc_kmh ({v_inc}) at most the truck's top speed {:.2} km/h (gear {} at n_max_rpm {} rpm)",
            limits.top_kmh,
            vehicle.forward_gears(),
            settings.mpc.n_max_rpm
        );
        return Err(CoreError::invalid("v_ref_kmh", expected).got(v_ref).related(&["v_inc_kmh", "n_max_rpm"]));
    }
    if v_ref - v_dec < limits.lowest_kmh {
        let expected = format!(
                "v_ref_kmh - v_dec_kmh ({v_dec}) at least the truck's lowest usable speed {:.2} km/h (gear 1 at n_min_rpm {} rpm)",
                limits.lowest_kmh, settings.mpc.n_min_rpm
            );
        return Err(CoreError::invalid("v_ref_kmh", expected).got(v_ref).related(&["v_dec_kmh", "n_min_rpm"]));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn settings(v_ref_kmh: f64, v_inc_kmh: f64, v_dec_kmh: f64) -> RunSettings {
        let mut s = RunSettings::default();
        (s.cruise.v_ref_kmh, s.cruise.v_inc_kmh, s.cruise.v_dec_kmh) = (v_ref_kmh, v_inc_kmh, v_dec_kmh);
        s
    }

    #[test]
    fn limits_are_the_gearbox_at_the_usable_engine_speeds() {
        let s = RunSettings::default();
        let vehicle = Vehicle::new(s.vehicle.clone()).unwrap();
        let p = &s.vehicle;
        // Top gear ratio 1.0: v = n π r_w / (30 i_f).
        let top_kmh = 2000.0 * std::f64::consts::PI * p.wheel_radius_m / (30.0 * p.final_drive_ratio) * 3.6;
        let low_kmh = 1000.0 * std::f64::consts::PI * p.wheel_radius_m / (30.0 * 11.27 * p.final_drive_ratio) * 3.6;
        let limits = speed_limits(&s, &vehicle);
        assert!((limits.top_kmh - top_kmh).abs() < 1e-9 && (limits.top_kmh - 119.9).abs() < 0.05, "{limits:?}");
        assert!((limits.lowest_kmh - low_kmh).abs() < 1e-9, "{limits:?}");
        assert_eq!(v_ref_range_kmh(&s, &vehicle), (low_kmh + 8.0, top_kmh - 5.0));
    }

    #[test]
    fn a_band_beyond_the_truck_is_refused_naming_the_key_and_the_limit() {
        let vehicle = Vehicle::new(RunSettings::default().vehicle).unwrap();
        check_drivable(&settings(85.0, 5.0, 8.0), &vehicle).unwrap();
        check_drivable(&settings(114.8, 5.0, 8.0), &vehicle).unwrap();
        let err = check_drivable(&settings(200.0, 5.0, 8.0), &vehicle).unwrap_err();
        assert_eq!(
            err.to_string(),
            "v_ref_kmh: expected v_ref_kmh + v_inc_kmh (5) at most the truck's top speed 119.90 km/h \
             (gear 12 at n_max_rpm 2000 rpm), got 200"
        );
        let err = check_drivable(&settings(110.0, 10.0, 8.0), &vehicle).unwrap_err();
        let CoreError::Invalid { key, related, .. } = err;
        assert_eq!((key.as_str(), related), ("v_ref_kmh", vec!["v_inc_kmh".to_string(), "n_max_rpm".to_string()]));
        let err = check_drivable(&settings(12.0, 5.0, 8.0), &vehicle).unwrap_err();
        assert!(
            err.to_string().contains("lowest usable speed 5.32 km/h (gear 1 at n_min_rpm 1000 rpm), got 12"),
            "{err}"
        );
    }
}

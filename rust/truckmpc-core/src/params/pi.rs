//! The PI cruise controller's gains (table A.4) and gear-shift thresholds (table A.3).

use super::Range;
use crate::declare_params;
use crate::error::{CoreError, CoreResult};

declare_params! {
    /// The PI cruise controller. Its error signals are in km/h, so each integrator state is in
    /// km/h·s and is clamped to ±limit (the anti-windup).
    pub struct PiParams in "pi" {
        /// K_P, pedal proportional gain.
        pedal_kp: f64 = 1.845, unit "1/(km/h)", range Range::between(0.0, 1e3);
        /// I_P, pedal integral gain.
        pedal_ki: f64 = 0.2, unit "1/(km/h s)", range Range::between(0.0, 1e3);
        /// Clamp of the pedal integrator (the anti-windup's saturation value).
        pedal_integrator_limit: f64 = 30.0, unit "km/h s", range Range::positive_up_to(1e6);
        /// K_B, brake proportional gain; the brake acts on v - v_max.
        brake_kp: f64 = 0.3, unit "1/(km/h)", range Range::between(0.0, 1e3);
        /// I_B, brake integral gain.
        brake_ki: f64 = 0.02, unit "1/(km/h s)", range Range::between(0.0, 1e3);
        /// Clamp of the brake integrator.
        brake_integrator_limit: f64 = 30.0, unit "km/h s", range Range::positive_up_to(1e6);
        /// Engine speed below which each gear 1..n shifts down; null for gear 1.
        gear_down_rpm: Vec<Option<f64>> = down_thresholds(), unit "rpm", range Range::positive_up_to(1e4);
        /// Engine speed above which each gear 1..n shifts up; null for the top gear.
        gear_up_rpm: Vec<Option<f64>> = up_thresholds(), unit "rpm", range Range::positive_up_to(1e4);
    }
}

/// Table A.3's downshift speeds for 12 gears: none in gear 1, 1300 rpm in the others.
fn down_thresholds() -> Vec<Option<f64>> {
    let mut down = vec![Some(1300.0); 12];
    down[0] = None;
    down
}

/// Table A.3's upshift speeds for 12 gears: 1800 rpm, 1700 in gear 11, none in gear 12.
fn up_thresholds() -> Vec<Option<f64>> {
    let mut up = vec![Some(1800.0); 12];
    up[10] = Some(1700.0);
    up[11] = None;
    up
}

impl PiParams {
    /// Checks between the threshold lists: equal lengths, nulls exactly where a gear has no lower
    /// or higher gear, and each gear's downshift speed below its upshift speed.
    pub fn check_thresholds(&self) -> CoreResult<()> {
        let (down, up) = (&self.gear_down_rpm, &self.gear_up_rpm);
        if up.len() != down.len() {
            let expected =
                format!("one threshold per gear, as many as gear_down_rpm ({}), got {}", down.len(), up.len());
            return Err(CoreError::invalid("gear_up_rpm", expected).related(&["gear_down_rpm"]));
        }
        check_nulls("gear_down_rpm", down, 0, "gear 1 (there is no lower gear)")?;
        let n = up.len();
        check_nulls("gear_up_rpm", up, n - 1, &format!("gear {n} (there is no higher gear)"))?;
        for (i, (low, high)) in down.iter().zip(up).enumerate() {
            if let (Some(low), Some(high)) = (low, high) {
                if !(low < high) {
                    let expected = format!("gear {}'s downshift speed below its upshift speed {high} rpm", i + 1);
                    return Err(CoreError::invalid("gear_down_rpm", expected).got(low).related(&["gear_up_rpm"]));
                }
            }
        }
        Ok(())
    }

    /// Checks against the vehicle's gearbox (`ratios` of gears 1..n): one threshold per gear, and
    /// every upshift landing above the next gear's downshift speed, or the gearbox would hunt.
    pub fn check_gearbox(&self, ratios: &[f64]) -> CoreResult<()> {
        for (key, list) in [("gear_down_rpm", &self.gear_down_rpm), ("gear_up_rpm", &self.gear_up_rpm)] {
            if list.len() != ratios.len() {
                let expected = format!("{} thresholds (one per gear of the vehicle), got {}", ratios.len(), list.len());
                return Err(CoreError::invalid(key, expected).related(&["gear_ratios"]));
            }
        }
        for gear in 1..ratios.len() {
            let (Some(up), Some(next_down)) = (self.gear_up_rpm[gear - 1], self.gear_down_rpm[gear]) else {
                continue;
            };
            let landing = up * ratios[gear] / ratios[gear - 1];
            if !(landing > next_down) {
                let expected = format!(
                    "gear {gear}'s upshift speed to land above gear {}'s downshift speed {next_down} rpm \
                     (it lands at {landing:.0} rpm: the gearbox would hunt)",
                    gear + 1
                );
                return Err(CoreError::invalid("gear_up_rpm", expected)
                    .got(up)
                    .related(&["gear_down_rpm", "gear_ratios"]));
            }
        }
        Ok(())
    }
}

fn check_nulls(key: &str, speeds: &[Option<f64>], null_at: usize, what: &str) -> CoreResult<()> {
    for (i, speed) in speeds.iter().enumerate() {
        match (i == null_at, speed) {
            (true, Some(x)) => return Err(CoreError::invalid(key, format!("null for {what}")).got(x)),
            (false, None) => {
                return Err(CoreError::invalid(key, format!("an engine speed for gear {}", i + 1)).got("null"))
            }
            _ => {}
        }
    }
    Ok(())
}

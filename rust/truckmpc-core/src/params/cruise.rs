//! The set speed and the speed band every cruise controller works to.

use super::Range;
use crate::declare_params;

declare_params! {
    /// The driver's set speed and the band around it: the one speed band every controller works to
    /// (the PI's brake limit, the PCC's allowed underspeed and overspeed, the look-ahead bounds).
    pub struct CruiseParams in "cruise" {
        /// v_ref, the set speed.
        v_ref_kmh: f64 = 85.0, unit "km/h", range Range::positive_up_to(250.0);
        /// Allowed increase above v_ref: v_max = v_ref + v_inc is a hard limit (the PI and the PCC brake above it; the PCC's allowed overspeed on a descent, use case 3).
        v_inc_kmh: f64 = 5.0, unit "km/h", range Range::between(0.0, 100.0);
        /// Allowed decrease below v_ref (VECTO's declaration value): v_min = v_ref - v_dec, a soft limit of the look-ahead controller and the PCC's allowed underspeed (use case 1); the PI has none.
        v_dec_kmh: f64 = 8.0, unit "km/h", range Range::between(0.0, 250.0);
        /// On a road with target speeds: added to every stretch's set speed min(v_ref, target) (the equal-time search moves it there).
        target_offset_kmh: f64 = 0.0, unit "km/h", range Range::between(-50.0, 50.0);
        /// On a road with target speeds: the deceleration the band's top keeps to ahead of a lower target.
        target_decel_mps2: f64 = 0.5, unit "m/s^2", range Range::positive_up_to(5.0);
    }
}

impl CruiseParams {
    /// The thesis's band: v_ref 85 km/h, ±5 km/h (the `thesis` preset's).
    pub fn thesis() -> Self {
        CruiseParams { v_dec_kmh: 5.0, ..CruiseParams::default() }
    }

    /// v_ref [m/s].
    pub fn v_ref_mps(&self) -> f64 {
        self.v_ref_kmh / 3.6
    }

    /// v_max = v_ref + v_inc [km/h].
    pub fn v_max_kmh(&self) -> f64 {
        self.v_ref_kmh + self.v_inc_kmh
    }
}

//! Closed-loop simulation settings.

use super::Range;
use crate::declare_params;

declare_params! {
    /// How the closed loop is simulated and recorded.
    pub struct SimParams in "sim" {
        /// Time step of the plant's RK4 integration.
        plant_dt_s: f64 = 0.05, unit "s", range Range::FRACTION;
        /// Distance between samples of the recorded trace.
        trace_step_m: f64 = 25.0, unit "m", range Range::positive_up_to(1e5);
        /// Speed at the start of the road; null starts at v_ref.
        start_speed_kmh: Option<f64> = None, unit "km/h", range Range::positive_up_to(250.0);
        /// The mass the controllers assume, when it is not the truck's (a load the controller does not know); null: mass_kg.
        controller_mass_kg: Option<f64> = None, unit "kg", range Range::positive_up_to(1e6);
    }
}

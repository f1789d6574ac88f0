//! VECTO's driver (the EU's certification tool for heavy trucks): its plain cruise driver, its
//! rule-based predictive cruise control and eco-roll, with their declaration defaults. The
//! controllers are [`crate::control::VectoDriver`] (`vecto_cc`) and [`crate::control::PccController`].

use super::Range;
use crate::declare_params;

declare_params! {
    /// VECTO's driver: its cruise driver (`vecto_cc`), and the predictive cruise control (use cases
    /// 1–3) and eco-roll on top of it (`pcc`). The PCC's allowed underspeed and its overspeed with
    /// use case 3 are the cruise band's v_dec_kmh and v_inc_kmh.
    pub struct PccParams in "pcc" {
        /// VECTO's driver without use case 3: how far above the set speed it lets a descent take the truck before it brakes.
        vecto_overspeed_kmh: f64 = 2.5, unit "km/h", range Range::between(0.0, 100.0);
        /// VECTO's driver allows overspeed only where the set speed is above this.
        vecto_overspeed_min_speed_kmh: f64 = 50.0, unit "km/h", range Range::between(0.0, 250.0);
        /// VECTO's driver coasts ahead of a lower set speed only above this speed (below it, it brakes).
        vecto_coasting_min_speed_kmh: f64 = 50.0, unit "km/h", range Range::between(0.0, 250.0);
        /// PCC acts only where v_ref is at least this.
        pcc_enabling_speed_kmh: f64 = 80.0, unit "km/h", range Range::between(0.0, 250.0);
        /// Lowest speed at which use case 2 (regaining speed on a descent by gravity alone) starts.
        pcc_minimum_speed_kmh: f64 = 50.0, unit "km/h", range Range::between(0.0, 250.0);
        /// How far ahead of a descent use case 1 (crest coasting) may start.
        pcc_preview_m: f64 = 1500.0, unit "m", range Range::between(0.0, 1e5);
        /// How far ahead use case 2 looks for the end of the descent.
        pcc_preview_uc2_m: f64 = 1000.0, unit "m", range Range::between(0.0, 1e5);
        /// Whether use case 3 (dip coasting: the raised overspeed on a descent) is fitted.
        pcc_use_case_3: bool = true, unit "-", range Range::ANY;
        /// Eco-roll: coast in neutral (PCC events and gentle descents) instead of in gear at fuel cut.
        eco_roll: bool = true, unit "-", range Range::ANY;
        /// Lowest speed at which eco-roll engages.
        eco_roll_min_speed_kmh: f64 = 60.0, unit "km/h", range Range::between(0.0, 250.0);
        /// How long the conditions for eco-roll must hold before it engages.
        eco_roll_delay_s: f64 = 2.0, unit "s", range Range::between(0.0, 600.0);
        /// Eco-roll engages only where the truck rolling in neutral would accelerate by at least this (a descent).
        eco_roll_accel_min_mps2: f64 = 0.0, unit "m/s^2", range Range::between(-5.0, 5.0);
        /// Eco-roll engages only where the truck rolling in neutral would accelerate by at most this (a gentle descent).
        eco_roll_accel_max_mps2: f64 = 0.1, unit "m/s^2", range Range::between(-5.0, 5.0);
    }
}

//! The truck: tables A.1 (vehicle and engine) and A.2 (gearbox) of the thesis, 40 t.

use super::{ParamSet, Range, Value};
use crate::declare_params;
use crate::error::{CoreError, CoreResult};

declare_params! {
    /// Every parameter of the vehicle model. Defaults: the thesis's 40 t truck.
    pub struct VehicleParams in "vehicle" {
        /// m, total vehicle mass.
        mass_kg: f64 = 40_000.0, unit "kg", range Range::positive_up_to(1e6);
        /// J_e, engine (flywheel) inertia.
        engine_inertia_kgm2: f64 = 3.5, unit "kg m^2", range Range::positive_up_to(1e3);
        /// n_cyl, number of cylinders.
        cylinders: f64 = 6.0, unit "-", range Range::positive_up_to(64.0);
        /// n_r, crankshaft revolutions per stroke.
        revolutions_per_stroke: f64 = 2.0, unit "-", range Range::positive_up_to(8.0);
        /// a_e, engine map slope in engine speed (2.3).
        torque_map_a_nm_per_rpm: f64 = -3.30e-3, unit "Nm/rpm", range Range::between(-1e3, 1e3);
        /// b_e, engine map slope in fueling (2.3).
        torque_map_b_nm_stroke_per_mg: f64 = 9.16, unit "Nm stroke/mg", range Range::positive_up_to(1e3);
        /// c_e, engine map offset (2.3).
        torque_map_c_nm: f64 = -82.53, unit "Nm", range Range::between(-1e5, 1e5);
        /// a_δ, fueling limit, quadratic term (2.6).
        fueling_max_a_mg_per_rpm2: f64 = -1.59e-4, unit "mg/(rpm^2 stroke)", range Range::between(-1e3, 1e3);
        /// b_δ, fueling limit, linear term (2.6); the printed 0.42 is kept, though 0.422 fits tables B.1/B.2 better.
        fueling_max_b_mg_per_rpm: f64 = 0.42, unit "mg/(rpm stroke)", range Range::between(-1e3, 1e3);
        /// c_δ, fueling limit, offset (2.6).
        fueling_max_c_mg: f64 = -57.05, unit "mg/stroke", range Range::between(-1e5, 1e5);
        /// a_d, engine drag torque slope (2.4).
        drag_torque_a_nm_per_rpm: f64 = -8.80e-2, unit "Nm/rpm", range Range::between(-1e3, 1e3);
        /// b_d, engine drag torque offset (2.4).
        drag_torque_b_nm: f64 = -51.51, unit "Nm", range Range::between(-1e5, 1e5);
        /// N_idle, engine idle speed.
        idle_speed_rpm: f64 = 600.0, unit "rpm", range Range::positive_up_to(1e4);
        /// δ_idle, idle fueling.
        idle_fueling_mg_per_stroke: f64 = 10.44, unit "mg/stroke", range Range::between(0.0, 1e4);
        /// i_f, final drive ratio.
        final_drive_ratio: f64 = 3.27, unit "-", range Range::positive_up_to(100.0);
        /// η_f, final drive efficiency.
        final_drive_efficiency: f64 = 0.97, unit "-", range Range::FRACTION;
        /// J_w, wheel inertia.
        wheel_inertia_kgm2: f64 = 32.9, unit "kg m^2", range Range::between(0.0, 1e5);
        /// c_r, rolling resistance coefficient.
        rolling_resistance: f64 = 7e-3, unit "-", range Range::between(0.0, 1.0);
        /// g, gravitational acceleration.
        gravity_mps2: f64 = 9.81, unit "m/s^2", range Range::positive_up_to(100.0);
        /// c_w, air drag coefficient.
        air_drag_coefficient: f64 = 0.6, unit "-", range Range::between(0.0, 10.0);
        /// A_a, maximum cross-section area.
        frontal_area_m2: f64 = 10.0, unit "m^2", range Range::between(0.0, 100.0);
        /// ρ_a, air density; a truck from VECTO's files takes VECTO's 1.188 unless it is set.
        air_density_kgpm3: f64 = 1.29, unit "kg/m^3", range Range::positive_up_to(100.0);
        /// r_w, wheel radius.
        wheel_radius_m: f64 = 0.52, unit "m", range Range::positive_up_to(10.0);
        /// k_b, brake torque at full brake; table A.1 prints 20e3, a misprint: tables B.1/B.2 need 1e5.
        brake_torque_max_nm: f64 = 1.0e5, unit "Nm", range Range::positive_up_to(1e7);
        /// i_t, gearbox ratio of each gear 1..n, strictly decreasing (table A.2).
        gear_ratios: Vec<f64> = vec![11.27, 9.14, 7.17, 5.81, 4.62, 3.75, 3.01, 2.44, 1.91, 1.55, 1.23, 1.0],
            unit "-", range Range::positive_up_to(100.0);
        /// η_t, gearbox efficiency of each gear 1..n (table A.2).
        gear_efficiencies: Vec<f64> = vec![0.88, 0.89, 0.90, 0.91, 0.92, 0.93, 0.94, 0.95, 0.96, 0.97, 0.98, 0.99],
            unit "-", range Range::FRACTION;
    }
}

impl VehicleParams {
    /// The thesis's 40 t truck with `values` (key, user value) set; an unknown key is an error
    /// naming it.
    pub fn from_values<'a>(values: impl IntoIterator<Item = (&'a str, &'a Value)>) -> CoreResult<Self> {
        let mut params = VehicleParams::default();
        for (key, value) in values {
            if !params.set(key, value)? {
                return Err(CoreError::invalid(key, "a vehicle parameter").got("an unknown key"));
            }
        }
        Ok(params)
    }

    /// Checks between keys: at least one gear, one efficiency per ratio, ratios strictly decreasing.
    pub fn check_gearbox(&self) -> CoreResult<()> {
        if self.gear_ratios.is_empty() {
            return Err(CoreError::invalid("gear_ratios", "at least one forward gear"));
        }
        if self.gear_ratios.len() != self.gear_efficiencies.len() {
            let expected = format!("one efficiency per gear ratio ({})", self.gear_ratios.len());
            let err =
                CoreError::invalid("gear_efficiencies", expected).got(format!("{}", self.gear_efficiencies.len()));
            return Err(err.related(&["gear_ratios"]));
        }
        for (i, pair) in self.gear_ratios.windows(2).enumerate() {
            if !(pair[1] < pair[0]) {
                let expected = format!("strictly decreasing ratios, gear {} is not below gear {}", i + 2, i + 1);
                return Err(CoreError::invalid("gear_ratios", expected));
            }
        }
        Ok(())
    }
}

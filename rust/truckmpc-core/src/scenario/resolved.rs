//! The settings a run resolves from its declared keys (a null default made a number, a weight given
//! per kilometre made one per stage), reported under the keys' declared names.

use super::Scenario;
use crate::dp::DpSettings;
use crate::error::CoreResult;
use crate::figures::Figures;
use crate::params::{CruiseParams, MpcParams, ParamSet, Value};

impl Scenario {
    /// The keys whose values the run resolves, with what they resolve to: `k_lim` [stages] (null:
    /// round(200 m / S)), `q_speed_below` per stage (from its per-kilometre weight or the thesis's
    /// δ rule; the fuel_time cost, whose speed band is a hard bound, does not charge it),
    /// `q_brake` per stage, and `beta_g_per_s` [g/s] (`beta_j_per_s` [J/s] for a battery-electric
    /// truck; null with the speed_penalty cost; derived from v_ref when not given).
    pub fn resolved(&self) -> CoreResult<Vec<(&'static str, Value)>> {
        let mpc = &self.settings().mpc;
        let dp = DpSettings::new(mpc, &self.settings().cruise)?;
        let vehicle = self.controller_vehicle();
        let beta = dp.beta_for(vehicle).map_or(Value::Null, Value::Float);
        Ok(vec![
            ("k_lim", Value::Int(i64::from(mpc.k_lim_stages()))),
            ("q_speed_below", Value::Float(mpc.q_speed_below_weight())),
            ("q_brake", Value::Float(mpc.q_brake_weight())),
            (DpSettings::beta_key(vehicle), beta),
        ])
    }

    /// Figures derived from the settings and the truck: `horizon_stages` (N, round(horizon / S), at
    /// least 1), `replan_stages` (stages decided from one solve, round(replan / S), at least 1),
    /// `v_ref_range_kmh` ([lowest, highest] set speed whose band the truck can drive: v_ref − v_dec
    /// at or above gear 1 at n_min_rpm, v_ref + v_inc at or below the top gear at n_max_rpm) and
    /// `kinetic_fuel_g_per_half_v2` (grams of fuel per unit of ½v² [m²/s²] the engine adds in the
    /// gear the PI settles in at v_ref: kinetic energy's price for the end-speed correction),
    /// followed by [`Scenario::resolved`]'s keys and values.
    pub fn derived(&self) -> CoreResult<Figures> {
        let mpc = &self.settings().mpc;
        let (lowest_kmh, highest_kmh) = self.v_ref_range_kmh();
        let mut figures = vec![
            ("horizon_stages", Value::Int(mpc.stages() as i64)),
            ("replan_stages", Value::Int(mpc.replan_stages() as i64)),
            ("v_ref_range_kmh", Value::List(vec![Value::Float(lowest_kmh), Value::Float(highest_kmh)])),
            ("kinetic_fuel_g_per_half_v2", Value::Float(self.kinetic_fuel_g_per_half_v2()?)),
        ];
        figures.extend(self.resolved()?);
        Ok(figures)
    }

    /// The look-ahead controller's settings as it runs with them: its keys and the cruise keys,
    /// with [`Scenario::resolved`]'s values in place of the declared ones.
    pub fn dp_settings(&self) -> CoreResult<Vec<(&'static str, Value)>> {
        let settings = self.settings();
        let resolved = self.resolved()?;
        let keys = MpcParams::specs().into_iter().chain(CruiseParams::specs()).map(|spec| spec.name);
        Ok(keys
            .map(|key| match resolved.iter().find(|(name, _)| *name == key) {
                Some((_, value)) => (key, value.clone()),
                None => (key, settings.get(key).expect("a declared key has a value")),
            })
            .collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::RunSettings;

    #[test]
    fn resolved_values_follow_their_rules_and_replace_the_declared_ones() {
        let values = [("stage_m", Value::Float(50.0)), ("q_brake_per_km", Value::Float(2000.0))];
        let scenario = Scenario::from_values(values.iter().map(|(k, v)| (*k, v)), None).unwrap();
        let resolved = scenario.resolved().unwrap();
        // k_lim: 200 m of stages of 50 m; Q5 per stage: 2000 per km over 0.05 km.
        assert_eq!(resolved[0], ("k_lim", Value::Int(4)));
        assert_eq!(resolved[2], ("q_brake", Value::Float(100.0)));
        let Value::Float(beta) = resolved[3].1 else { panic!("β resolved: {:?}", resolved[3]) };
        assert!(beta > 0.0 && beta.is_finite());
        let dp = scenario.dp_settings().unwrap();
        assert_eq!(dp.len(), MpcParams::specs().len() + CruiseParams::specs().len());
        assert!(dp.contains(&("k_lim", Value::Int(4))) && dp.contains(&("v_ref_kmh", Value::Float(85.0))));
        assert_eq!(RunSettings::default().mpc.k_lim, None);
    }

    /// Stage counts from the horizon and replan distances; the set-speed range around the default.
    #[test]
    fn derived_figures_follow_the_settings() {
        let values =
            [("stage_m", Value::Float(50.0)), ("horizon_m", Value::Float(2600.0)), ("replan_m", Value::Float(120.0))];
        let scenario = Scenario::from_values(values.iter().map(|(k, v)| (*k, v)), None).unwrap();
        let derived = scenario.derived().unwrap();
        // 2600 m / 50 m = 52 stages; 120 m / 50 m = 2.4, rounded to 2.
        assert_eq!(derived[0], ("horizon_stages", Value::Int(52)));
        assert_eq!(derived[1], ("replan_stages", Value::Int(2)));
        let Value::List(range) = &derived[2].1 else { panic!("{:?}", derived[2]) };
        let [Value::Float(lo), Value::Float(hi)] = range.as_slice() else { panic!("{range:?}") };
        assert!(*lo < 85.0 && 85.0 < *hi, "the default 85 km/h lies inside [{lo}, {hi}]");
        let Value::Float(price) = derived[3].1 else { panic!("{:?}", derived[3]) };
        assert!(price > 0.0 && price.is_finite());
        let names: Vec<&str> = derived[4..].iter().map(|(name, _)| *name).collect();
        assert_eq!(names, ["k_lim", "q_speed_below", "q_brake", "beta_g_per_s"], "the resolved keys follow");
    }

    /// The output of a run whose controller solves the DP carries the settings it ran with; a
    /// rule-based controller's carries none.
    #[test]
    fn a_dp_run_returns_its_settings_with_its_output() {
        use crate::road::Road;
        use std::sync::Arc;
        let values = [("horizon_m", Value::Float(500.0)), ("delta_kmh", Value::Float(0.5))];
        let scenario = Scenario::from_values(values.iter().map(|(k, v)| (*k, v)), None).unwrap();
        let road = Arc::new(Road::new(vec![0.0, 300.0], vec![0.01]).unwrap());
        let drive = |name| scenario.run(&road, None, &[0.0, 3.0], scenario.controller(name).unwrap().as_mut()).unwrap();
        for kind in crate::scenario::CONTROLLERS {
            let out = drive(kind.name);
            let expected = kind.solves_dp.then(|| scenario.dp_settings().unwrap());
            assert_eq!(out.settings, expected, "{}", kind.name);
        }
        let mpc = drive("mpc").settings.unwrap();
        assert!(mpc.contains(&("horizon_m", Value::Float(500.0))) && mpc.contains(&("k_lim", Value::Int(8))));
    }
}

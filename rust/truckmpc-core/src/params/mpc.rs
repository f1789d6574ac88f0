//! The look-ahead controller's parameters (tables 5.2, 6.1 and 6.2). Its cost weighs fuel in grams
//! and speeds in m/s: with these units table 6.2's weights give chapter 6's behaviour.
//!
//! The defaults are the physical cost, fuel + β·trip time, on a stage model accurate to second
//! order (the trapezoid), with a closed-loop result that converges as δ and S shrink: a fixed grid,
//! fuel cut, full pedal and neutral as exact arcs joined by three-point interpolation, a 3 km
//! horizon, and a drivability price on gear shifts and neutral engagements (Q4, q_neutral) instead
//! of a price on speed changes. [`MpcParams::thesis`] (the `thesis` preset) is the controller as
//! printed: the speed-penalty cost (5.9) on Euler stages over 1.5 km.

use super::{CruiseParams, Range};
use crate::error::{CoreError, CoreResult};
use crate::{choice_enum, declare_params};

choice_enum! {
    /// How a neutral-gear arc, whose end speed is fixed by the physics and generally falls between
    /// two grid points, is joined to the next stage's grid (the thesis gives no rule).
    pub enum NeutralRule {
        /// Snap to the nearest grid point (the thesis's reading; biased with a moving grid).
        Nearest = "nearest",
        /// Interpolate the cost-to-go linearly between the two neighbouring grid points (unbiased).
        Interpolate = "interpolate",
        /// Interpolate the cost-to-go through the three grid points around the end speed: exact
        /// for a quadratic cost-to-go, so its error is third order in δ where linear
        /// interpolation's is second order and one-signed on a convex cost-to-go.
        Quadratic = "quadratic",
    }
}

choice_enum! {
    /// What the look-ahead controller minimises.
    pub enum CostKind {
        /// The thesis's criterion (5.1): Q1·fuel + Q2·(speed below v_ref)² + Q3·|speed change|
        /// + Q4·shifts + Q5·brake.
        SpeedPenalty = "speed_penalty",
        /// Q1·(fuel + β·trip time) + Q3·|speed change| + Q4·shifts + Q5·brake, the speed band a
        /// hard bound, the kinetic energy left at the horizon's end valued at the engine's
        /// marginal fuel cost, and the Euler stage's energy error charged back
        /// ([`crate::dp::DpSettings::q_speed_change_sq`]).
        FuelTime = "fuel_time",
    }
}

choice_enum! {
    /// How each stage's velocity grid is anchored.
    pub enum GridAnchor {
        /// The thesis's grid (5.8): v_low, v_low + δ, ..., anchored at each stage's own lower bound.
        Moving = "moving",
        /// Multiples of δ: one absolute grid shared by every stage and every solve.
        Fixed = "fixed",
    }
}

choice_enum! {
    /// The DP's model of one stage with constant inputs ([`crate::dp::stage`]).
    pub enum StageModel {
        /// The thesis's explicit Euler stage (5.4): first order in S; a path that speeds up and
        /// slows down in turn gains kinetic energy the plant does not give.
        Euler = "euler",
        /// Kinetic energy integrated by the trapezoid rule, fuel and time by the same rule: second
        /// order in S, and a closed speed cycle gains no energy.
        Trapezoid = "trapezoid",
    }
}

choice_enum! {
    /// What the controller does when a solve finds no admissible path.
    pub enum OnInfeasible {
        /// Solve again with the lower speed bound and the shift limit relaxed; failing that, drive
        /// with the PI's gear logic and full pedal (braking above v_max) until a solve succeeds.
        Rescue = "rescue",
        /// Keep the inputs being applied (section 5.6; a long climb can then stall the truck).
        Hold = "hold",
    }
}

/// Metres per kilometre, for the weights given per kilometre.
const M_PER_KM: f64 = 1000.0;

/// Stages of `stage_m` [m] in `length_m` [m]: round(length / S), at least 1.
pub fn stages_in(length_m: f64, stage_m: f64) -> usize {
    (length_m / stage_m).round().max(1.0) as usize
}

/// The most pedal levels (`pedal_levels`) a solver plans: the DP marks a level's arc in one byte.
pub const MAX_PEDAL_LEVELS: u32 = 240;

/// Table 6.1: the shift limit k_lim is chosen so that S · k_lim = 200 m.
pub const SHIFT_SPACING_M: f64 = 200.0;

declare_params! {
    /// The look-ahead DP-MPC.
    pub struct MpcParams in "mpc" {
        /// S, stage length: one decision per stage, its control held over the stage.
        stage_m: f64 = 25.0, unit "m", range Range::positive_up_to(1e4);
        /// Prediction horizon; N = round(horizon / S) stages.
        horizon_m: f64 = 3000.0, unit "m", range Range::positive_up_to(1e6);
        /// Distance between two solves of the horizon: each looks horizon_m + replan_m − S ahead and keeps its cost-to-go, which decides the stages until the next one at the truck's measured state (the look-ahead never falls below horizon_m); below 1.5 S: a solve every stage (section 5.6).
        replan_m: f64 = 750.0, unit "m", range Range::between(0.0, 1e5);
        /// δ, step of the DP's speed grid.
        delta_kmh: f64 = 0.05, unit "km/h", range Range::positive_up_to(100.0);
        /// ε, pedal tolerance: levels in [-ε, 1 + ε] are accepted and clipped to [0, 1]; null = half a grid step δ of speed change.
        epsilon: Option<f64> = None, unit "-", range Range::between(0.0, 1.0);
        /// Least number of stages between two gear shifts; null = 200 m / S (table 6.1).
        k_lim: Option<u32> = None, unit "stages", range Range::between(1.0, 1e6);
        /// Lowest engine speed of a usable gear (5.7).
        n_min_rpm: f64 = 1000.0, unit "rpm", range Range::between(0.0, 1e4);
        /// Highest engine speed of a usable gear (5.7).
        n_max_rpm: f64 = 2000.0, unit "rpm", range Range::positive_up_to(1e4);
        /// Whether the controller may coast in neutral (section 6.6).
        allow_neutral: bool = true, unit "-", range Range::ANY;
        /// Q1, weight per gram of fuel.
        q_fuel: f64 = 2.0, unit "1/g", range Range::between(0.0, 1e6);
        /// Q2 per stage, weight per (m/s)² below v_ref at each stage's start; null = q_speed_below_per_km × S, or without it 5 if δ < 0.15 km/h else 7 (table 6.2).
        q_speed_below: Option<f64> = None, unit "1/(m/s)^2", range Range::between(0.0, 1e6);
        /// Q2 per kilometre driven, so that S is a resolution of one cost (used when q_speed_below is null).
        q_speed_below_per_km: Option<f64> = Some(200.0), unit "1/((m/s)^2 km)", range Range::between(0.0, 1e9);
        /// Q3, weight per m/s of speed change over a stage.
        q_speed_change: f64 = 0.0, unit "1/(m/s)", range Range::between(0.0, 1e6);
        /// Q4, weight per gear shift.
        q_gear_shift: f64 = 60.0, unit "1/shift", range Range::between(0.0, 1e6);
        /// Price per engagement of neutral (a coasting episode; on top of Q4 where shift_price_neutral): a drivability price, not fuel.
        q_neutral: f64 = 30.0, unit "1/engagement", range Range::between(0.0, 1e6);
        /// Whether Q4 also prices each shift into and out of neutral (the thesis's cost); false: Q4 prices changes of forward gear only, and q_neutral each neutral engagement.
        shift_price_neutral: bool = false, unit "-", range Range::ANY;
        /// After coasting in neutral, engage only the highest gear usable at the speed (as an automated gearbox does); false: any usable gear.
        neutral_exit_top_gear: bool = true, unit "-", range Range::ANY;
        /// For a truck whose gearbox interrupts traction at a shift: plan each shift as the plant drives it (a roll in neutral for the interruption, then the new gear); false: the plan shifts instantly, as the thesis's truck does.
        plan_interruption: bool = true, unit "-", range Range::ANY;
        /// Q5 per stage, weight per unit brake level held over a stage; null = q_brake_per_km × S.
        q_brake: Option<f64> = None, unit "-", range Range::between(0.0, 1e6);
        /// Q5 per kilometre, weight per unit brake level held over a kilometre (used when q_brake is null).
        q_brake_per_km: Option<f64> = Some(4000.0), unit "1/km", range Range::between(0.0, 1e9);
        /// What the controller minimises: the thesis's speed_penalty criterion, or fuel_time (fuel + β·trip time, Q3·|Δv|, Q4 and Q5; q_speed_below unused).
        cost: CostKind = CostKind::FuelTime, unit "-", range Range::ANY;
        /// β of the fuel_time cost, the fuel worth one second of trip time; null = the β for which steady v_ref is optimal on a flat road.
        beta_g_per_s: Option<f64> = None, unit "g/s", range Range::between(0.0, 1e4);
        /// β of a battery-electric truck's fuel_time cost, the battery energy worth one second of trip time (about 1e5 for VECTO's generic tractor at 85 km/h); null = derived as beta_g_per_s is.
        beta_j_per_s: Option<f64> = None, unit "J/s", range Range::between(0.0, 1e7);
        /// The DP's stage model: euler (the thesis's, first order in S) or trapezoid (kinetic energy, fuel and time by the trapezoid rule, second order).
        stage_model: StageModel = StageModel::Trapezoid, unit "-", range Range::ANY;
        /// Fuel cut in a forward gear is also an exact arc: its end speed off the grid, joined to the next stage's grid by neutral_rule (otherwise only the grid point above fuel cut, at a small pedal, or below it within ε).
        fuel_cut_arcs: bool = true, unit "-", range Range::ANY;
        /// For a truck whose drive glides for less than at zero pedal (a battery-electric truck's machines drawing no electric power, against their drag while off), that glide is also an exact arc: its pedal at each start speed, its end speed off the grid, joined by neutral_rule.
        glide_arcs: bool = true, unit "-", range Range::ANY;
        /// Pedal levels planned off the grid: with K ≥ 2 every forward gear also drives the pedal levels 1/K, 2/K, …, (K−1)/K over a stage as exact arcs, each ending off the speed grid and joined to it by neutral_rule, so the pedal's resolution is 1/K whatever δ; 0 (or 1): only fuel cut, full pedal and the levels that land on grid speeds, about δ·v/(gain·S) apart. At most 120 with --check-convergence, which doubles it.
        pedal_levels: u32 = 0, unit "levels", range Range::between(0.0, MAX_PEDAL_LEVELS as f64);
        /// Neutral arcs end on the nearest grid point, or interpolate the cost-to-go linearly or through the three nearest points.
        neutral_rule: NeutralRule = NeutralRule::Quadratic, unit "-", range Range::ANY;
        /// Speed grid anchored at each stage's lower bound (moving, 5.8) or on multiples of δ (fixed).
        grid: GridAnchor = GridAnchor::Fixed, unit "-", range Range::ANY;
        /// No admissible path: rescue (relaxed solve, then the PI's gear logic at full pedal) or hold the inputs (5.6).
        on_infeasible: OnInfeasible = OnInfeasible::Rescue, unit "-", range Range::ANY;
    }
}

impl MpcParams {
    /// The thesis's controller as printed (chapter 5, tables 6.1 and 6.2; the `thesis` preset): the
    /// speed-penalty cost with Q3 = Q4 = 15 on Euler stages over a 1.5 km horizon, the moving grid
    /// at δ 0.2 km/h, ε = 0.1, neutral arcs on the nearest grid point, no fuel-cut arcs, Q2 and Q5
    /// per stage, and the inputs kept when a solve finds no admissible path.
    pub fn thesis() -> Self {
        MpcParams {
            delta_kmh: 0.2,
            epsilon: Some(0.1),
            fuel_cut_arcs: false,
            q_speed_below: None,
            q_speed_below_per_km: None,
            q_brake: Some(100.0),
            q_brake_per_km: None,
            neutral_rule: NeutralRule::Nearest,
            grid: GridAnchor::Moving,
            on_infeasible: OnInfeasible::Hold,
            stage_model: StageModel::Euler,
            cost: CostKind::SpeedPenalty,
            horizon_m: 1500.0,
            replan_m: 0.0,
            q_speed_change: 15.0,
            q_gear_shift: 15.0,
            q_neutral: 0.0,
            neutral_exit_top_gear: false,
            shift_price_neutral: true,
            ..MpcParams::default()
        }
    }

    /// k_lim with its default resolved: round(200 m / S), at least 1 (table 6.1).
    pub fn k_lim_stages(&self) -> u32 {
        self.k_lim.unwrap_or_else(|| (SHIFT_SPACING_M / self.stage_m).round_ties_even().max(1.0) as u32)
    }

    /// Q2 per stage with its default resolved: q_speed_below, else q_speed_below_per_km × S, else
    /// 5 below δ = 0.15 km/h and 7 above (table 6.2).
    pub fn q_speed_below_weight(&self) -> f64 {
        match (self.q_speed_below, self.q_speed_below_per_km) {
            (Some(per_stage), _) => per_stage,
            (None, Some(per_km)) => per_km * self.stage_m / M_PER_KM,
            (None, None) => {
                if self.delta_kmh < 0.15 {
                    5.0
                } else {
                    7.0
                }
            }
        }
    }

    /// Q5 per stage: q_brake, else q_brake_per_km × S (one of them is set, [`Self::check_with`]).
    pub fn q_brake_weight(&self) -> f64 {
        self.q_brake.unwrap_or_else(|| self.q_brake_per_km.unwrap_or(f64::NAN) * self.stage_m / M_PER_KM)
    }

    /// Number of stages N in the horizon.
    pub fn stages(&self) -> usize {
        stages_in(self.horizon_m, self.stage_m)
    }

    /// Stages decided from one horizon solve (a solve every stage when 1).
    pub fn replan_stages(&self) -> usize {
        stages_in(self.replan_m, self.stage_m)
    }

    /// Checks between keys, and against the speed band of `cruise`; the error names the key and
    /// the others the check involved.
    pub fn check_with(&self, cruise: &CruiseParams) -> CoreResult<()> {
        if self.q_brake.is_none() && self.q_brake_per_km.is_none() {
            return Err(CoreError::invalid("q_brake", "a number when q_brake_per_km is null")
                .got("null")
                .related(&["q_brake_per_km"]));
        }
        if self.horizon_m < self.stage_m {
            let expected = format!("at least one stage (horizon_m >= stage_m = {})", self.stage_m);
            return Err(CoreError::invalid("horizon_m", expected).got(self.horizon_m).related(&["stage_m"]));
        }
        if self.stages() > 100_000 {
            return Err(CoreError::invalid("horizon_m", "at most 100000 stages of stage_m")
                .got(self.horizon_m)
                .related(&["stage_m"]));
        }
        if self.n_min_rpm >= self.n_max_rpm {
            let expected = format!("n_min_rpm < n_max_rpm ({})", self.n_max_rpm);
            return Err(CoreError::invalid("n_min_rpm", expected).got(self.n_min_rpm).related(&["n_max_rpm"]));
        }
        if cruise.v_dec_kmh >= cruise.v_ref_kmh {
            let expected = format!("< v_ref_kmh ({})", cruise.v_ref_kmh);
            return Err(CoreError::invalid("v_dec_kmh", expected).got(cruise.v_dec_kmh).related(&["v_ref_kmh"]));
        }
        let band_kmh = cruise.v_inc_kmh + cruise.v_dec_kmh;
        if self.delta_kmh > band_kmh && band_kmh > 0.0 {
            let expected = format!("at most the speed band v_inc + v_dec = {band_kmh} km/h");
            return Err(CoreError::invalid("delta_kmh", expected)
                .got(self.delta_kmh)
                .related(&["v_inc_kmh", "v_dec_kmh"]));
        }
        // Grid indices are stored in 16 bits.
        if band_kmh / self.delta_kmh > 30_000.0 {
            let expected = "at most 30000 grid points in the speed band v_inc + v_dec";
            return Err(CoreError::invalid("delta_kmh", expected)
                .got(self.delta_kmh)
                .related(&["v_inc_kmh", "v_dec_kmh"]));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Weights given per kilometre are the same cost at every S: Q2 and Q5 per stage scale with S,
    /// and a stage's charge per metre stays the same. A weight given per stage wins over one per km.
    #[test]
    fn weights_per_km_scale_with_the_stage() {
        for stage_m in [10.0, 12.5, 25.0, 50.0] {
            let mpc = MpcParams {
                stage_m,
                q_speed_below_per_km: Some(200.0),
                q_brake: None,
                q_brake_per_km: Some(4000.0),
                ..MpcParams::default()
            };
            assert!((mpc.q_speed_below_weight() / stage_m - 0.2).abs() < 1e-12);
            assert!((mpc.q_brake_weight() / stage_m - 4.0).abs() < 1e-12);
            let per_stage = MpcParams { q_speed_below: Some(3.0), q_brake: Some(7.0), ..mpc };
            assert_eq!((per_stage.q_speed_below_weight(), per_stage.q_brake_weight()), (3.0, 7.0));
        }
        // Without either, Q2 follows table 6.2 (the thesis's rule) and Q5 is an error naming q_brake.
        let thesis = MpcParams { delta_kmh: 0.1, ..MpcParams::thesis() };
        assert_eq!(thesis.q_speed_below_weight(), 5.0);
        assert_eq!(MpcParams { delta_kmh: 0.2, ..thesis }.q_speed_below_weight(), 7.0);
        let neither = MpcParams { q_brake: None, q_brake_per_km: None, ..MpcParams::default() };
        let err = neither.check_with(&CruiseParams::default()).unwrap_err();
        assert!(err.to_string().contains("q_brake"), "{err}");
    }
}

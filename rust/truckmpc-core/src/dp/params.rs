//! Parameters of the look-ahead controller (tables 5.2, 6.1, 6.2), in the units a user types.
//! Internally the solver works in m/s; conversions happen in [`MpcParams::validate`] users.

use crate::error::{check_each, CoreError, CoreResult};

/// How a neutral-gear arc, whose end speed is fixed by the physics and generally falls between
/// two grid points, is joined to the next stage's grid (NOTES.md: the thesis gives no rule).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NeutralRule {
    /// Snap to the nearest grid point (thesis-faithful reading; biased with a moving grid).
    Nearest,
    /// Interpolate the cost-to-go linearly between the two neighbouring grid points (unbiased).
    Interpolate,
}

/// How each stage's velocity grid is anchored.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GridAnchor {
    /// The thesis's grid (5.8): v_low, v_low + δ, ..., anchored at each stage's own lower bound.
    Moving,
    /// Multiples of δ (an absolute grid shared by every stage and every solve).
    Fixed,
}

/// Controller parameters. Speeds in km/h as the user gives them; cost weights act on fuel in
/// grams and on speeds in m/s (NOTES.md: that is what makes table 6.2's weights behave).
#[derive(Debug, Clone, PartialEq)]
pub struct MpcParams {
    /// Stage length S [m]; the controller solves once per stage and holds its control over it.
    pub stage_m: f64,
    /// Prediction horizon [m]; the number of stages is round(horizon / S).
    pub horizon_m: f64,
    /// Velocity discretisation δ [km/h].
    pub delta_kmh: f64,
    /// Pedal tolerance ε: computed pedal levels in [−ε, 1 + ε] are accepted and clipped to [0, 1].
    pub epsilon: f64,
    /// Reference speed v_ref [km/h].
    pub v_ref_kmh: f64,
    /// Allowed increase above v_ref [km/h]; v_max = v_ref + v_inc is a hard limit.
    pub v_inc_kmh: f64,
    /// Allowed decrease below v_ref [km/h]; v_min = v_ref − v_dec is a soft limit.
    pub v_dec_kmh: f64,
    /// Minimum number of stages between two gear shifts.
    pub k_lim: u32,
    /// Lowest engine speed of a usable gear [rpm] (5.7).
    pub n_min_rpm: f64,
    /// Highest engine speed of a usable gear [rpm] (5.7).
    pub n_max_rpm: f64,
    /// Whether neutral gear may be chosen.
    pub allow_neutral: bool,
    /// Q1: weight per gram of fuel.
    pub q_fuel: f64,
    /// Q2: weight per (m/s)² of speed below v_ref.
    pub q_speed_below: f64,
    /// Q3: weight per m/s of speed change over a stage.
    pub q_speed_change: f64,
    /// Q4: weight per gear shift.
    pub q_gear_shift: f64,
    /// Q5: weight per unit brake level held over a stage.
    pub q_brake: f64,
    /// Rule joining neutral arcs to the grid.
    pub neutral_rule: NeutralRule,
    /// Anchoring of the velocity grid.
    pub grid: GridAnchor,
}

impl Default for MpcParams {
    /// Tables 6.1 and 6.2 at S = 25 m, δ = 0.2 km/h, 1000 m horizon.
    fn default() -> Self {
        MpcParams {
            stage_m: 25.0,
            horizon_m: 1000.0,
            delta_kmh: 0.2,
            epsilon: 0.1,
            v_ref_kmh: 85.0,
            v_inc_kmh: 5.0,
            v_dec_kmh: 5.0,
            k_lim: 8,
            n_min_rpm: 1000.0,
            n_max_rpm: 2000.0,
            allow_neutral: true,
            q_fuel: 2.0,
            q_speed_below: 7.0,
            q_speed_change: 15.0,
            q_gear_shift: 15.0,
            q_brake: 100.0,
            neutral_rule: NeutralRule::Nearest,
            grid: GridAnchor::Moving,
        }
    }
}

impl MpcParams {
    /// Check ranges; the error names the first offending key.
    pub fn validate(&self) -> CoreResult<()> {
        let positive = [
            ("stage_m", self.stage_m),
            ("horizon_m", self.horizon_m),
            ("delta_kmh", self.delta_kmh),
            ("v_ref_kmh", self.v_ref_kmh),
            ("n_max_rpm", self.n_max_rpm),
        ];
        check_each(&positive, |v| v > 0.0, "a number > 0")?;
        let non_negative = [
            ("epsilon", self.epsilon),
            ("v_inc_kmh", self.v_inc_kmh),
            ("v_dec_kmh", self.v_dec_kmh),
            ("n_min_rpm", self.n_min_rpm),
            ("q_fuel", self.q_fuel),
            ("q_speed_below", self.q_speed_below),
            ("q_speed_change", self.q_speed_change),
            ("q_gear_shift", self.q_gear_shift),
            ("q_brake", self.q_brake),
        ];
        check_each(&non_negative, |v| v >= 0.0, "a number >= 0")?;
        if self.horizon_m < self.stage_m {
            return Err(CoreError::invalid(
                "horizon_m",
                format!(
                    "expected at least one stage (horizon_m >= stage_m = {}), got {}",
                    self.stage_m, self.horizon_m
                ),
            ));
        }
        if self.n_min_rpm >= self.n_max_rpm {
            return Err(CoreError::invalid(
                "n_min_rpm",
                format!("expected n_min_rpm < n_max_rpm ({}), got {}", self.n_max_rpm, self.n_min_rpm),
            ));
        }
        if self.v_dec_kmh >= self.v_ref_kmh {
            return Err(CoreError::invalid(
                "v_dec_kmh",
                format!("expected < v_ref_kmh ({}), got {}", self.v_ref_kmh, self.v_dec_kmh),
            ));
        }
        if self.delta_kmh > self.v_inc_kmh + self.v_dec_kmh && self.v_inc_kmh + self.v_dec_kmh > 0.0 {
            return Err(CoreError::invalid(
                "delta_kmh",
                format!(
                    "expected at most the speed band v_inc + v_dec = {} km/h, got {}",
                    self.v_inc_kmh + self.v_dec_kmh,
                    self.delta_kmh
                ),
            ));
        }
        if self.stages() > 100_000 {
            return Err(CoreError::invalid("horizon_m", "expected at most 100000 stages"));
        }
        // Grid indices are stored in 16 bits.
        if (self.v_inc_kmh + self.v_dec_kmh) / self.delta_kmh > 30_000.0 {
            return Err(CoreError::invalid(
                "delta_kmh",
                "expected at most 30000 grid points in the speed band v_inc + v_dec",
            ));
        }
        Ok(())
    }

    /// Number of stages N in the horizon.
    pub fn stages(&self) -> usize {
        (self.horizon_m / self.stage_m).round().max(1.0) as usize
    }

    /// δ [m/s].
    pub fn delta_mps(&self) -> f64 {
        self.delta_kmh / 3.6
    }

    /// v_ref [m/s].
    pub fn v_ref_mps(&self) -> f64 {
        self.v_ref_kmh / 3.6
    }

    /// v_max = v_ref + v_inc [m/s].
    pub fn v_max_mps(&self) -> f64 {
        (self.v_ref_kmh + self.v_inc_kmh) / 3.6
    }

    /// v_min = v_ref − v_dec [m/s].
    pub fn v_min_mps(&self) -> f64 {
        (self.v_ref_kmh - self.v_dec_kmh) / 3.6
    }
}

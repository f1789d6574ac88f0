//! The settings the DP works with: the look-ahead controller's declared section ([`MpcParams`])
//! and the cruise band ([`CruiseParams`]) as they are, read in place, and beside them the values
//! they resolve to (k_lim, the per-stage weights, the fuel_time cost's weights). Units and meanings
//! are those of the declarations; the solver converts speeds to m/s through the methods below.

use crate::params::{stages_in, CruiseParams, MpcParams, ParamSet};
pub use crate::params::{CostKind, GridAnchor, NeutralRule, OnInfeasible, StageModel};

use super::fuel_time;
use crate::band::BandAt;
use crate::error::{CoreError, CoreResult};
use crate::vehicle::Vehicle;

/// Finest grid step [km/h] of the relaxed solve ([`DpSettings::relaxed`]): a finer δ of the
/// settings is raised to it.
pub const RELAXED_DELTA_MIN_KMH: f64 = 0.2;

/// Longest horizon [m] of the relaxed solve ([`DpSettings::relaxed`]): a longer one of the settings
/// is cut to it: the rescue needs only a way back into the band, which 1.5 km shows.
pub const RELAXED_HORIZON_MAX_M: f64 = 1500.0;

/// The DP's settings: the look-ahead controller's declared keys and the cruise band, as declared,
/// with the values they resolve to; build them with [`DpSettings::new`], which validates.
#[derive(Debug, Clone, PartialEq)]
pub struct DpSettings {
    /// The look-ahead controller's keys (S, horizon, δ, weights, stage model, grid, ...).
    pub mpc: MpcParams,
    /// Set speed and band.
    pub cruise: CruiseParams,
    /// k_lim [stages], resolved.
    pub k_lim: u32,
    /// Q2 per stage [1/(m/s)²], resolved; zero with the fuel_time cost.
    pub q_speed_below: f64,
    /// Q5 per stage [-], resolved.
    pub q_brake: f64,
    /// Q1·β [1/s], charged per second of each stage (h / v_i); 0 until [`DpSettings::for_vehicle`]
    /// resolves a fuel_time cost.
    pub q_time_per_s: f64,
    /// Q1 times the grams one unit of ½v² [m²/s²] costs in the cruise gear: the horizon's end is
    /// charged this times ½(v_ref² − v²); 0 until [`DpSettings::for_vehicle`] resolves a fuel_time cost.
    pub q_terminal_per_half_v2: f64,
    /// Weight per (m/s)² of speed change over a stage: 0, except with the fuel_time cost on Euler
    /// stages, where it is Q1 · (grams per unit of ½v²) · ½. The explicit Euler stage v_j = v_i + (h/v_i)·a
    /// adds h·a + ½(v_j − v_i)² to ½v², so a path that speeds up and slows down in turn would
    /// gain ½Δv² of kinetic energy a stage for nothing; this charges it back at the engine's
    /// marginal fuel cost (the speed_penalty cost leaves it out: its Q3·|Δv| is larger at any Δv a
    /// stage can make).
    pub q_speed_change_sq: f64,
}

impl Default for DpSettings {
    /// The declared defaults.
    fn default() -> Self {
        Self::resolve(&MpcParams::default(), &CruiseParams::default())
    }
}

impl DpSettings {
    /// The settings of the thesis's controller ([`MpcParams::thesis`]) in the thesis's band ±5 km/h.
    pub fn thesis() -> Self {
        Self::resolve(&MpcParams::thesis(), &CruiseParams::thesis())
    }

    /// Validate `mpc` and `cruise` (ranges and checks between keys) and resolve the defaults.
    pub fn new(mpc: &MpcParams, cruise: &CruiseParams) -> CoreResult<Self> {
        mpc.check_ranges()?;
        cruise.check_ranges()?;
        mpc.check_with(cruise)?;
        Ok(Self::resolve(mpc, cruise))
    }

    fn resolve(mpc: &MpcParams, cruise: &CruiseParams) -> Self {
        let fuel_time = mpc.cost == CostKind::FuelTime;
        DpSettings {
            mpc: mpc.clone(),
            cruise: cruise.clone(),
            k_lim: mpc.k_lim_stages(),
            q_speed_below: if fuel_time { 0.0 } else { mpc.q_speed_below_weight() },
            q_brake: mpc.q_brake_weight(),
            q_time_per_s: 0.0,
            q_terminal_per_half_v2: 0.0,
            q_speed_change_sq: 0.0,
        }
    }

    /// The settings with the fuel_time cost's weights resolved for `vehicle`: β (given, or the one
    /// that makes steady v_ref optimal on a flat road) and the value of kinetic energy at the
    /// horizon's end, both in the cruise gear at v_ref. The speed_penalty cost is returned as is.
    pub fn for_vehicle(self, vehicle: &Vehicle) -> Self {
        if self.mpc.cost != CostKind::FuelTime {
            return self;
        }
        let gear = fuel_time::cruise_gear(vehicle, self.v_ref_mps(), self.mpc.n_min_rpm, self.mpc.n_max_rpm);
        let beta = self.beta_for(vehicle).unwrap_or(0.0);
        let kinetic = self.mpc.q_fuel * fuel_time::kinetic_fuel_g(vehicle, self.v_ref_mps(), gear);
        DpSettings {
            q_time_per_s: self.mpc.q_fuel * beta,
            q_terminal_per_half_v2: kinetic,
            // The trapezoid stage conserves energy: nothing to charge back.
            q_speed_change_sq: if self.mpc.stage_model == StageModel::Euler { 0.5 * kinetic } else { 0.0 },
            ..self
        }
    }

    /// The settings of the whole-road bound: with the fuel_time cost, fuel + β·time alone (the
    /// prices of gear shifts, neutral engagements and braking at 0; the band and the shift limit
    /// kept), so that no controller within the same band and limit drives the road for less on the
    /// DP's model. A price the MPC pays for comfort would let the optimum trade fuel + β·time
    /// for fewer shifts or coasts, and lose to a run that paid them. The speed_penalty cost is
    /// returned as is: its prices are its objective.
    pub fn bound(self) -> Self {
        if self.mpc.cost != CostKind::FuelTime {
            return self;
        }
        let free = |m: &mut MpcParams| (m.q_gear_shift, m.q_neutral) = (0.0, 0.0);
        DpSettings { q_brake: 0.0, ..self.with_mpc(free) }
    }

    /// Whether `vehicle` can drive this cost: with fuel_time and no β given, the truck must hold
    /// v_ref on a flat road in a gear within [n_min, n_max] (β is derived there); the error names
    /// beta_g_per_s. β is given in the unit of the truck's store: `beta_j_per_s` for a battery,
    /// `beta_g_per_s` for fuel; the other key set is refused, naming it.
    pub fn check_vehicle(&self, vehicle: &Vehicle) -> CoreResult<()> {
        let battery = vehicle.is_electric();
        let (wrong, value, expected) = if battery {
            (
                "beta_g_per_s",
                self.mpc.beta_g_per_s,
                "no value with a battery-electric truck (its β is beta_j_per_s, in J/s)",
            )
        } else {
            (
                "beta_j_per_s",
                self.mpc.beta_j_per_s,
                "no value with a truck that burns fuel (its β is beta_g_per_s, in g/s)",
            )
        };
        if let Some(value) = value {
            return Err(CoreError::invalid(wrong, expected).got(value));
        }
        match self.beta_for(vehicle) {
            Some(beta) if !beta.is_finite() => Err(CoreError::invalid(
                if battery { "beta_j_per_s" } else { "beta_g_per_s" },
                "a value: the truck holds v_ref on a flat road in no gear within n_min_rpm..n_max_rpm, so β cannot be derived",
            )
            .got("null")
            .related(&["v_ref_kmh", "n_min_rpm", "n_max_rpm"])),
            _ => Ok(()),
        }
    }

    /// β of the fuel_time cost as used with `vehicle`, in its store's unit per second (g/s of fuel,
    /// J/s of battery energy; given or derived; NaN where it cannot be derived, see
    /// [`DpSettings::check_vehicle`]); None for the speed_penalty cost.
    pub fn beta_for(&self, vehicle: &Vehicle) -> Option<f64> {
        (self.mpc.cost == CostKind::FuelTime).then(|| {
            let v_ref = self.v_ref_mps();
            let gear = fuel_time::cruise_gear(vehicle, v_ref, self.mpc.n_min_rpm, self.mpc.n_max_rpm);
            let given = if vehicle.is_electric() { self.mpc.beta_j_per_s } else { self.mpc.beta_g_per_s };
            given.unwrap_or_else(|| fuel_time::steady_beta_g_per_s(vehicle, v_ref, gear))
        })
    }

    /// The key of β for `vehicle`: `beta_j_per_s` for a battery-electric truck, else `beta_g_per_s`.
    pub fn beta_key(vehicle: &Vehicle) -> &'static str {
        if vehicle.is_electric() {
            "beta_j_per_s"
        } else {
            "beta_g_per_s"
        }
    }

    /// The same settings with the lower speed bound at `v_min_kmh`, no shift limit, no neutral
    /// after the first stage and a grid step of at least [`RELAXED_DELTA_MIN_KMH`]: the rescue
    /// solve when these admit no path. (Its band reaches down to `v_min_kmh`, many times the cruise
    /// band's width, hence the coarser grid.)
    ///
    /// Without the shift limit a neutral engagement may last a single stage, and a change of gear
    /// routed through it would be priced q_neutral instead of Q4, cheaper when Q4 is the higher
    /// price. A rescue is the way back into the band, not a coast: it plans in gear.
    pub fn relaxed(&self, v_min_kmh: f64) -> Self {
        let (mpc, cruise) = (&self.mpc, &self.cruise);
        DpSettings {
            cruise: CruiseParams { v_dec_kmh: (cruise.v_ref_kmh - v_min_kmh).max(cruise.v_dec_kmh), ..cruise.clone() },
            mpc: MpcParams {
                allow_neutral: false,
                delta_kmh: mpc.delta_kmh.max(RELAXED_DELTA_MIN_KMH),
                horizon_m: mpc.horizon_m.min(RELAXED_HORIZON_MAX_M).max(mpc.stage_m),
                ..mpc.clone()
            },
            k_lim: 1,
            ..self.clone()
        }
    }

    /// These settings with the look-ahead controller's keys changed by `change`, the resolved
    /// values (k_lim, Q2, Q5, the fuel_time weights) kept as they are.
    pub fn with_mpc(mut self, change: impl FnOnce(&mut MpcParams)) -> Self {
        change(&mut self.mpc);
        self
    }

    /// Number of stages N in the horizon.
    pub fn stages(&self) -> usize {
        stages_in(self.mpc.horizon_m, self.mpc.stage_m)
    }

    /// Stages decided from one horizon solve (a solve every stage when 1).
    pub fn replan_stages(&self) -> usize {
        stages_in(self.mpc.replan_m, self.mpc.stage_m)
    }

    /// δ [m/s].
    pub fn delta_mps(&self) -> f64 {
        self.mpc.delta_kmh / 3.6
    }

    /// The pedal levels accepted (and clipped to [0, 1]) from `v_i_mps` when one unit of pedal
    /// changes the end speed of a stage by `gain_mps2 · S / v_i` [m/s]: [−ε, 1 + ε], where ε
    /// without a value is the pedal worth half a grid step δ, so that every stage reaches at least
    /// one grid point and the clipping error vanishes as δ shrinks.
    #[inline]
    pub fn pedal_band(&self, v_i_mps: f64, gain_mps2: f64) -> (f64, f64) {
        let e = match self.mpc.epsilon {
            Some(e) => e,
            None => 0.5 * self.delta_mps() * v_i_mps / (gain_mps2 * self.mpc.stage_m),
        };
        (-e, 1.0 + e)
    }

    /// The cruise band (the same at every stage on a road without target speeds).
    pub fn band(&self) -> BandAt {
        BandAt::uniform(&self.cruise())
    }

    /// The cruise parameters these settings were resolved from.
    pub fn cruise(&self) -> CruiseParams {
        self.cruise.clone()
    }

    /// v_ref [m/s].
    pub fn v_ref_mps(&self) -> f64 {
        self.cruise.v_ref_kmh / 3.6
    }

    /// v_max = v_ref + v_inc [m/s].
    pub fn v_max_mps(&self) -> f64 {
        (self.cruise.v_ref_kmh + self.cruise.v_inc_kmh) / 3.6
    }

    /// v_min = v_ref − v_dec [m/s].
    pub fn v_min_mps(&self) -> f64 {
        (self.cruise.v_ref_kmh - self.cruise.v_dec_kmh) / 3.6
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_relaxed_solve_lowers_v_min_drops_the_shift_limit_and_neutral_and_keeps_a_grid_of_at_least_0_2_kmh() {
        let fine = DpSettings::default();
        assert!(fine.mpc.delta_kmh < RELAXED_DELTA_MIN_KMH && fine.mpc.allow_neutral);
        let relaxed = fine.relaxed(5.0);
        assert_eq!((relaxed.v_min_mps() * 3.6, relaxed.k_lim, relaxed.mpc.allow_neutral), (5.0, 1, false));
        assert_eq!(relaxed.mpc.delta_kmh, RELAXED_DELTA_MIN_KMH);
        // A coarser grid is kept as it is.
        let coarse = DpSettings::thesis().with_mpc(|m| m.delta_kmh = 0.4).relaxed(5.0);
        assert_eq!(coarse.mpc.delta_kmh, 0.4);
        let mut expected = fine.with_mpc(|m| (m.allow_neutral, m.horizon_m) = (false, RELAXED_HORIZON_MAX_M));
        (expected.k_lim, expected.cruise.v_dec_kmh) = (1, relaxed.cruise.v_dec_kmh);
        assert_eq!(relaxed.with_mpc(|m| m.delta_kmh = 0.0), expected.with_mpc(|m| m.delta_kmh = 0.0));
    }

    #[test]
    fn the_bound_prices_fuel_and_time_alone_with_the_fuel_time_cost_and_keeps_the_speed_penalty_cost() {
        let fuel_time = DpSettings::default();
        assert!(fuel_time.mpc.q_gear_shift > 0.0 && fuel_time.mpc.q_neutral > 0.0 && fuel_time.q_brake > 0.0);
        let bound = fuel_time.clone().bound();
        assert_eq!((bound.mpc.q_gear_shift, bound.mpc.q_neutral, bound.q_brake), (0.0, 0.0, 0.0));
        // The band, the shift limit and the grid stay: the bound is over the same drives.
        assert_eq!(
            (bound.cruise.clone(), bound.k_lim, bound.mpc.delta_kmh),
            (fuel_time.cruise.clone(), fuel_time.k_lim, fuel_time.mpc.delta_kmh)
        );
        let thesis = DpSettings::thesis();
        assert_eq!(thesis.clone().bound(), thesis);
    }
}

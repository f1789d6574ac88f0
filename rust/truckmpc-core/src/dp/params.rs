//! The settings the DP works with: the look-ahead controller's declared parameters
//! ([`MpcParams`]) with their defaults resolved, and the cruise band ([`CruiseParams`]). Units and
//! meanings are those of the declarations; the solver converts speeds to m/s through the methods
//! below.

use crate::params::{CruiseParams, MpcParams, ParamSet};
pub use crate::params::{GridAnchor, NeutralRule, OnInfeasible};

use crate::error::CoreResult;

/// Resolved DP settings; build them with [`DpSettings::new`], which validates.
#[derive(Debug, Clone, PartialEq)]
pub struct DpSettings {
    /// S [m].
    pub stage_m: f64,
    /// Horizon [m].
    pub horizon_m: f64,
    /// δ [km/h].
    pub delta_kmh: f64,
    /// ε [-]; None: half a grid step δ of speed change, per row ([`DpSettings::pedal_band`]).
    pub epsilon: Option<f64>,
    /// v_ref [km/h].
    pub v_ref_kmh: f64,
    /// v_inc [km/h].
    pub v_inc_kmh: f64,
    /// v_dec [km/h].
    pub v_dec_kmh: f64,
    /// k_lim [stages], resolved.
    pub k_lim: u32,
    /// N_min [rpm].
    pub n_min_rpm: f64,
    /// N_max [rpm].
    pub n_max_rpm: f64,
    /// Neutral allowed.
    pub allow_neutral: bool,
    /// Fuel cut in a forward gear as an exact arc, joined like neutral arcs.
    pub fuel_cut_arcs: bool,
    /// Q1 [1/g].
    pub q_fuel: f64,
    /// Q2 per stage [1/(m/s)²], resolved.
    pub q_speed_below: f64,
    /// Q3 [1/(m/s)].
    pub q_speed_change: f64,
    /// Q4 [1/shift].
    pub q_gear_shift: f64,
    /// Q5 per stage [-], resolved.
    pub q_brake: f64,
    /// Neutral arcs' rule.
    pub neutral_rule: NeutralRule,
    /// Grid anchoring.
    pub grid: GridAnchor,
    /// The controller's answer to a solve without an admissible path (not used by the solver).
    pub on_infeasible: OnInfeasible,
}

impl Default for DpSettings {
    /// The declared defaults.
    fn default() -> Self {
        Self::resolve(&MpcParams::default(), &CruiseParams::default())
    }
}

impl DpSettings {
    /// The settings of the thesis's controller ([`MpcParams::thesis`]) in the default cruise band.
    pub fn thesis() -> Self {
        Self::resolve(&MpcParams::thesis(), &CruiseParams::default())
    }

    /// Validate `mpc` and `cruise` (ranges and checks between keys) and resolve the defaults.
    pub fn new(mpc: &MpcParams, cruise: &CruiseParams) -> CoreResult<Self> {
        mpc.check_ranges()?;
        cruise.check_ranges()?;
        mpc.check_with(cruise)?;
        Ok(Self::resolve(mpc, cruise))
    }

    fn resolve(mpc: &MpcParams, cruise: &CruiseParams) -> Self {
        DpSettings {
            stage_m: mpc.stage_m,
            horizon_m: mpc.horizon_m,
            delta_kmh: mpc.delta_kmh,
            epsilon: mpc.epsilon,
            v_ref_kmh: cruise.v_ref_kmh,
            v_inc_kmh: cruise.v_inc_kmh,
            v_dec_kmh: cruise.v_dec_kmh,
            k_lim: mpc.k_lim_stages(),
            n_min_rpm: mpc.n_min_rpm,
            n_max_rpm: mpc.n_max_rpm,
            allow_neutral: mpc.allow_neutral,
            fuel_cut_arcs: mpc.fuel_cut_arcs,
            q_fuel: mpc.q_fuel,
            q_speed_below: mpc.q_speed_below_weight(),
            q_speed_change: mpc.q_speed_change,
            q_gear_shift: mpc.q_gear_shift,
            q_brake: mpc.q_brake_weight(),
            neutral_rule: mpc.neutral_rule,
            grid: mpc.grid,
            on_infeasible: mpc.on_infeasible,
        }
    }

    /// The same settings with the lower speed bound at `v_min_kmh` and no shift limit: the
    /// rescue solve when these admit no path.
    pub fn relaxed(&self, v_min_kmh: f64) -> Self {
        DpSettings { v_dec_kmh: (self.v_ref_kmh - v_min_kmh).max(self.v_dec_kmh), k_lim: 1, ..self.clone() }
    }

    /// Number of stages N in the horizon.
    pub fn stages(&self) -> usize {
        (self.horizon_m / self.stage_m).round().max(1.0) as usize
    }

    /// δ [m/s].
    pub fn delta_mps(&self) -> f64 {
        self.delta_kmh / 3.6
    }

    /// The pedal levels accepted (and clipped to [0, 1]) from `v_i_mps` when one unit of pedal
    /// changes the end speed of a stage by `gain_mps2 · S / v_i` [m/s]: [−ε, 1 + ε], where ε
    /// without a value is the pedal worth half a grid step δ, so that every stage reaches at least
    /// one grid point and the clipping error vanishes as δ shrinks.
    #[inline]
    pub fn pedal_band(&self, v_i_mps: f64, gain_mps2: f64) -> (f64, f64) {
        let e = match self.epsilon {
            Some(e) => e,
            None => 0.5 * self.delta_mps() * v_i_mps / (gain_mps2 * self.stage_m),
        };
        (-e, 1.0 + e)
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

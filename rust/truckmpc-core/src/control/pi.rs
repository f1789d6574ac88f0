//! The PI cruise controller of thesis section 2.5 (table A.4) and its gear logic (table A.3).
//!
//! Two PI controllers share the speed measurement: the pedal drives the speed towards v_ref,
//! `P = sat(K_P e_P + I_P ∫e_P dt)` with `e_P = v_ref − v`; the brake holds it at
//! `v_max = v_ref + v_inc`, `B = sat(K_B e_B + I_B ∫e_B dt)` with `e_B = v − v_max`; `sat` clips to
//! [0, 1]. Errors are in km/h and the integrator states in km/h·s: table A.4's gains only make sense
//! so (in m/s the clamped brake integrator would keep the brakes off until about 7 km/h above
//! v_max). Each integrator state is clamped to ±limit (the table's "saturation value", the
//! anti-windup). The brake acts on v − v_max: (2.11) as printed would brake below v_max.
//!
//! The controller is sampled at every plant step; each decision integrates the current error over
//! the time since the previous decision (backward rectangle). A run starts with the pedal
//! integrator at the value that holds v_ref on the starting grade and the brake integrator at its
//! lower clamp, so it has no start transient.
//!
//! On a road with target speeds the set speed and the brake limit follow the band along the road
//! ([`SpeedBand`]), and the controller coasts ahead of a lower target as VECTO's driver model does
//! (look-ahead coasting): within a preview of 10 m per km/h of speed, it lifts the pedal once the
//! specific energy (g·h + v²/2) to lose before the lower stretch, per metre left, reaches the
//! coasting resistance (rolling, air and engine drag at fuel cut, per kg, at the mean of the two
//! speeds) times VECTO's decision factor DF = 2.5 − 1.5·DF_vel·DF_drop (DF_vel rises from 0 to 1
//! between targets of 48 and 52 km/h, DF_drop falls from 1 to 0 between drops of 9 and 11 km/h):
//! with DF = 1 the truck coasts just far enough to arrive at the lower set speed. While coasting
//! the integrators hold; when it ends (at the stretch, or below its set speed) the pedal
//! integrator is set to hold the new set speed, so the speed step causes no transient.

use std::sync::Arc;

use super::{specific_energy_j_per_kg, Controller, Decision};
use crate::band::SpeedBand;
use crate::error::CoreResult;
use crate::levels::stationary;
use crate::params::{CruiseParams, PiParams};
use crate::plant::{Control, PlantState};
use crate::road::Road;
use crate::vehicle::{Vehicle, NEUTRAL};
use crate::KMH_PER_MPS;

/// Engine-speed thresholds of table A.3 for a vehicle: above gear g's upshift threshold the next
/// higher gear is chosen, below its downshift threshold the next lower one. The PI never selects
/// neutral.
#[derive(Debug, Clone)]
pub struct GearLogic {
    forward_gears: usize,
    /// Engine speed per unit road speed [rpm/(m/s)] per gear, index 0 (neutral) unused.
    rpm_per_mps: Vec<f64>,
    /// Downshift thresholds [rpm] per gear (−∞ for gear 1), index 0 unused.
    down_rpm: Vec<f64>,
    /// Upshift thresholds [rpm] per gear (+∞ for the top gear), index 0 unused.
    up_rpm: Vec<f64>,
}

impl GearLogic {
    /// The thresholds of `params` for `vehicle`: checked first (one per gear, nulls only where a
    /// gear has no lower or higher gear, each downshift speed below its upshift speed, and every
    /// upshift landing above the next gear's downshift speed, or the gearbox would hunt).
    pub fn new(vehicle: &Vehicle, params: &PiParams) -> CoreResult<Self> {
        params.check_thresholds()?;
        params.check_gearbox(&vehicle.params().gear_ratios)?;
        let n = vehicle.forward_gears();
        // Engine speed is proportional to road speed in a forward gear (2.9).
        let rpm_per_mps = std::iter::once(0.0).chain((1..=n).map(|g| vehicle.engine_speed_rpm(1.0, g))).collect();
        let down = std::iter::once(f64::INFINITY)
            .chain(params.gear_down_rpm.iter().map(|x| x.unwrap_or(f64::NEG_INFINITY)))
            .collect();
        let up = std::iter::once(f64::INFINITY)
            .chain(params.gear_up_rpm.iter().map(|x| x.unwrap_or(f64::INFINITY)))
            .collect();
        Ok(GearLogic { forward_gears: n, rpm_per_mps, down_rpm: down, up_rpm: up })
    }

    /// Number of forward gears.
    pub fn forward_gears(&self) -> usize {
        self.forward_gears
    }

    /// Gear after one evaluation of the thresholds in `gear` at speed `v_mps` [m/s] (at most one
    /// shift). From neutral (handed over by another controller) the settled gear.
    pub fn next_gear(&self, gear: usize, v_mps: f64) -> usize {
        if gear == NEUTRAL {
            return self.steady_gear(v_mps);
        }
        let n_rpm = v_mps * self.rpm_per_mps[gear];
        if n_rpm > self.up_rpm[gear] {
            gear + 1
        } else if n_rpm < self.down_rpm[gear] {
            gear - 1
        } else {
            gear
        }
    }

    /// The gear after one evaluation in `gear` at `v_mps` [m/s] on `slope` [-] for `vehicle`:
    /// [`GearLogic::next_gear`], except that a truck whose shifts interrupt traction (a VECTO truck)
    /// shifts up only where the higher gear can still accelerate it by [`UPSHIFT_RESERVE_MPS2`] at
    /// full load on this slope: otherwise it would lose the interruption's speed and shift back,
    /// hunting up a long climb. The thesis's truck shifts by its thresholds alone (table A.3).
    pub fn shift(&self, vehicle: &Vehicle, gear: usize, v_mps: f64, slope: f64) -> usize {
        let next = self.next_gear(gear, v_mps);
        if next <= gear || gear == NEUTRAL || vehicle.traction_interruption_s() <= 0.0 {
            return next;
        }
        if vehicle.accel_mps2(v_mps, 1.0, 0.0, next, slope) >= UPSHIFT_RESERVE_MPS2 {
            next
        } else {
            gear
        }
    }

    /// The gear the logic settles in at constant speed `v_mps` [m/s] when reached by accelerating
    /// from gear 1.
    pub fn steady_gear(&self, v_mps: f64) -> usize {
        let mut gear = 1;
        // Validated thresholds settle within n shifts; the bound only guards the loop.
        for _ in 0..2 * self.forward_gears {
            let next = self.next_gear(gear, v_mps);
            if next == gear {
                return gear;
            }
            gear = next;
        }
        gear
    }
}

/// The PI cruise controller with its gear logic, sampled at every plant step.
#[derive(Debug, Clone)]
pub struct PiController {
    vehicle: Arc<Vehicle>,
    gears: GearLogic,
    cruise: CruiseParams,
    /// The band along the road of the current run, and the stretch of the last query.
    band: SpeedBand,
    band_hint: usize,
    /// Road segment of the last slope look-up (for the up-shift check of a map-based truck).
    slope_hint: usize,
    v_ref_kmh: f64,
    v_max_kmh: f64,
    /// A brake limit [km/h] set by a controller built on this one, instead of the band's.
    brake_limit_kmh: Option<f64>,
    /// Coasting ahead of a lower stretch (look-ahead coasting): its start [m] and set speed [m/s].
    coasting_to: Option<(f64, f64)>,
    pedal_kp: f64,
    pedal_ki: f64,
    brake_kp: f64,
    brake_ki: f64,
    pedal_limit: f64,
    brake_limit: f64,
    gear: usize,
    /// Pedal integrator state [km/h·s].
    pedal_integrator: f64,
    /// Brake integrator state [km/h·s].
    brake_integrator: f64,
    /// Time of the previous decision [s].
    t_last_s: f64,
}

impl PiController {
    /// A controller for `vehicle` (its gears and the starting pedal level) with `params`, working
    /// to the set speed and band of `cruise`.
    pub fn new(vehicle: Arc<Vehicle>, params: &PiParams, cruise: &CruiseParams) -> CoreResult<Self> {
        let gears = GearLogic::new(&vehicle, params)?;
        Ok(PiController {
            vehicle,
            gears,
            cruise: cruise.clone(),
            band: SpeedBand::uniform(cruise),
            band_hint: 0,
            slope_hint: 0,
            v_ref_kmh: cruise.v_ref_kmh,
            v_max_kmh: cruise.v_ref_kmh + cruise.v_inc_kmh,
            brake_limit_kmh: None,
            coasting_to: None,
            pedal_kp: params.pedal_kp,
            pedal_ki: params.pedal_ki,
            brake_kp: params.brake_kp,
            brake_ki: params.brake_ki,
            pedal_limit: params.pedal_integrator_limit,
            brake_limit: params.brake_integrator_limit,
            gear: NEUTRAL,
            pedal_integrator: 0.0,
            brake_integrator: 0.0,
            t_last_s: 0.0,
        })
    }

    /// The gear logic (table A.3).
    pub fn gear_logic(&self) -> &GearLogic {
        &self.gears
    }

    /// The gear the controller last chose (0 before its first decision).
    pub fn gear(&self) -> usize {
        self.gear
    }

    /// Set the speed above which the controller brakes [km/h] (the band's top unless set): a
    /// controller built on this one raises it on descents.
    pub fn set_brake_limit_kmh(&mut self, v_max_kmh: f64) {
        self.brake_limit_kmh = Some(v_max_kmh);
        self.v_max_kmh = v_max_kmh;
    }

    /// The speed band of the current run's road.
    pub fn band(&self) -> &SpeedBand {
        &self.band
    }

    /// Take over at `state` from another controller: the set speed and brake limit of the band at
    /// its position, no look-ahead coasting under way, then [`PiController::reset`].
    pub fn resume(&mut self, road: &Road, state: &PlantState) {
        self.follow_band(state.s_m);
        self.coasting_to = None;
        let mut hint = 0;
        self.reset(state.v_mps, road.slope_at(state.s_m, &mut hint), state.t_s);
    }

    /// Pedal and brake integrator states [km/h·s].
    pub fn integrators(&self) -> (f64, f64) {
        (self.pedal_integrator, self.brake_integrator)
    }

    /// Reset for speed `v_mps` [m/s] on grade `slope` [-] at time `t_s` [s]: the settled gear, the
    /// pedal integrator at the level holding v_ref on that grade, the brake integrator at its
    /// lower clamp.
    pub fn reset(&mut self, v_mps: f64, slope: f64, t_s: f64) {
        self.gear = self.gears.steady_gear(v_mps);
        self.hold_pedal_at(self.v_ref_kmh, slope);
        self.brake_integrator = -self.brake_limit;
        self.t_last_s = t_s;
    }
}

impl PiController {
    /// The gear after this step's evaluation of the gear logic ([`GearLogic::shift`]).
    fn next_gear(&mut self, road: &Road, state: &PlantState) -> usize {
        let slope = road.slope_at(state.s_m, &mut self.slope_hint);
        self.gears.shift(&self.vehicle, self.gear, state.v_mps, slope)
    }

    /// Take the set speed and the brake limit at `s_m` from the band.
    fn follow_band(&mut self, s_m: f64) {
        let at = self.band.at(s_m, &mut self.band_hint);
        self.v_ref_kmh = at.v_ref_kmh;
        self.v_max_kmh = self.brake_limit_kmh.unwrap_or(at.v_max_kmh);
    }

    /// Start or end look-ahead coasting (see the module's documentation).
    fn look_ahead_coasting(&mut self, road: &Road, state: &PlantState) {
        let (s, v) = (state.s_m, state.v_mps);
        if let Some((until_m, set_mps)) = self.coasting_to {
            if s < until_m && v > set_mps {
                return;
            }
            self.coasting_to = None;
            let mut hint = 0;
            let slope = road.slope_at(s, &mut hint);
            self.hold_pedal_at(self.v_ref_kmh, slope);
            return;
        }
        let preview_m = LAC_PREVIEW_M_PER_KMH * v * KMH_PER_MPS;
        let mut hint = self.band_hint;
        let here_kmh = self.band.set_speed_kmh(s, &mut hint);
        let Some((start_m, set_kmh)) = self.band.next_drop(s, preview_m, &mut hint) else { return };
        let v_c = set_kmh / KMH_PER_MPS;
        if v <= v_c {
            return;
        }
        let factor = lac_decision_factor(set_kmh, here_kmh - set_kmh);
        if time_to_coast(&self.vehicle, road, (s, v), (start_m, v_c), self.gear, factor) {
            self.coasting_to = Some((start_m, v_c));
        }
    }

    /// Set the pedal integrator to the level holding `v_ref_kmh` on `slope` in the settled gear.
    fn hold_pedal_at(&mut self, v_ref_kmh: f64, slope: f64) {
        let v_ref_mps = v_ref_kmh / KMH_PER_MPS;
        let hold = stationary(&self.vehicle, v_ref_mps, slope, self.gears.steady_gear(v_ref_mps));
        let pedal = clamp(hold.pedal, 0.0, 1.0);
        self.pedal_integrator =
            if self.pedal_ki > 0.0 { clamp(pedal / self.pedal_ki, -self.pedal_limit, self.pedal_limit) } else { 0.0 };
    }
}

/// Whether to start look-ahead coasting at `(s [m], v [m/s])` in `gear` towards a lower stretch
/// starting at `start_m` with speed `v_c_mps`: once the specific energy to lose per metre left
/// reaches the coasting resistance (per kg, at fuel cut, at the mean of the two speeds) times the
/// decision `factor`.
pub fn time_to_coast(
    vehicle: &Vehicle,
    road: &Road,
    (s_m, v_mps): (f64, f64),
    (start_m, v_c_mps): (f64, f64),
    gear: usize,
    factor: f64,
) -> bool {
    let surplus =
        specific_energy_j_per_kg(vehicle, road, s_m, v_mps) - specific_energy_j_per_kg(vehicle, road, start_m, v_c_mps);
    let needed_per_m = surplus / (start_m - s_m).max(1e-3);
    let resistance = -vehicle.accel_mps2(0.5 * (v_mps + v_c_mps), 0.0, 0.0, gear.max(1), 0.0);
    needed_per_m >= factor * resistance
}

/// Look-ahead coasting's preview: metres per km/h of speed (VECTO's declaration value).
pub const LAC_PREVIEW_M_PER_KMH: f64 = 10.0;

/// VECTO's decision factor for look-ahead coasting to a set speed `target_kmh` after a drop of
/// `drop_kmh` [km/h]: 2.5 − 1.5·DF_vel·DF_drop, DF_vel 0 below 48 km/h and 1 above 52, DF_drop 1
/// up to a 9 km/h drop and 0 above 11, linear between.
pub fn lac_decision_factor(target_kmh: f64, drop_kmh: f64) -> f64 {
    let vel = ((target_kmh - 48.0) / 4.0).clamp(0.0, 1.0);
    let drop = ((11.0 - drop_kmh) / 2.0).clamp(0.0, 1.0);
    2.5 - 1.5 * vel * drop
}

/// Acceleration [m/s²] a higher gear must still give at full load for a truck whose shifts
/// interrupt traction to shift up: about what a 1 s interruption loses on a 1 % grade.
pub const UPSHIFT_RESERVE_MPS2: f64 = 0.1;

/// `x` limited to [lo, hi] (NaN passes through).
fn clamp(x: f64, lo: f64, hi: f64) -> f64 {
    if x < lo {
        lo
    } else if x > hi {
        hi
    } else {
        x
    }
}

impl Controller for PiController {
    fn name(&self) -> &'static str {
        "pi"
    }

    fn start(&mut self, road: &Road, state: &PlantState) {
        self.band = SpeedBand::new(road, &self.cruise);
        self.band_hint = 0;
        self.coasting_to = None;
        self.follow_band(state.s_m);
        self.reset(state.v_mps, road.slopes()[0], state.t_s);
    }

    fn decide(&mut self, road: &Road, state: &PlantState) -> Decision {
        let dt_s = state.t_s - self.t_last_s;
        self.t_last_s = state.t_s;
        if self.band.varies() {
            self.follow_band(state.s_m);
            self.look_ahead_coasting(road, state);
        }
        let v_kmh = state.v_mps * KMH_PER_MPS;
        let pedal_error = self.v_ref_kmh - v_kmh;
        let brake_error = v_kmh - self.v_max_kmh;
        let coasting = self.coasting_to.is_some();
        if !coasting {
            self.pedal_integrator =
                clamp(self.pedal_integrator + pedal_error * dt_s, -self.pedal_limit, self.pedal_limit);
        }
        self.brake_integrator = clamp(self.brake_integrator + brake_error * dt_s, -self.brake_limit, self.brake_limit);
        let pedal = if coasting { 0.0 } else { self.pedal_kp * pedal_error + self.pedal_ki * self.pedal_integrator };
        let brake = self.brake_kp * brake_error + self.brake_ki * self.brake_integrator;
        self.gear = self.next_gear(road, state);
        let control = Control { pedal: clamp(pedal, 0.0, 1.0), brake: clamp(brake, 0.0, 1.0), gear: self.gear };
        Decision { control, until_m: None }
    }
}

//! VECTO's cruise driver (`vecto_cc`): what VECTO simulates for a truck without predictive
//! cruise control, and the driver the PCC ([`super::PccController`]) acts through.
//!
//! Each plant step the driver picks one of VECTO's driving actions:
//! - **accelerate** below the set speed: the pedal that reaches it by the end of the step, its
//!   acceleration at most the driver's limit (VECTO's declaration curve for trucks: 1 m/s² up to
//!   25 km/h, 0.5 m/s² from 60 km/h on, linear between its points), so at the set speed it holds it;
//! - **coast** at or above the set speed where overspeed is allowed (a set speed above
//!   `vecto_overspeed_min_speed_kmh`): no pedal, in gear at fuel cut, so a descent takes the truck up
//!   to the set speed plus the allowed overspeed; if coasting would bring it below the set speed
//!   within the step, it accelerates (holds the set speed) instead;
//! - **brake** where coasting would pass that limit: the brake that ends the step at the limit.
//!
//! On a road with target speeds the set speed is the band's (its top ramps down ahead of a lower
//! target at `target_decel_mps2`), and ahead of a lower set speed the driver lifts early and
//! coasts (look-ahead coasting) when the energy to lose per metre left reaches the coasting
//! resistance times VECTO's decision factor; the lower target counts with its overspeed, and
//! below `vecto_coasting_min_speed_kmh` the driver does not coast but brakes with the band.
//!
//! A truck from VECTO's files shifts as VECTO's automated manual gearbox does ([`super::amt`]: its
//! declaration-mode shift lines and classic AMT strategy); the thesis's truck by the PI's gear
//! logic (table A.3 thresholds).

use std::sync::Arc;

use super::amt::{AmtShifter, Request, LOOKAHEAD_M};
use super::pi::{lac_decision_factor, time_to_coast, GearLogic, LAC_PREVIEW_M_PER_KMH};
use super::{Controller, Decision};
use crate::band::SpeedBand;
use crate::error::CoreResult;
use crate::levels::{brake_accel, pedal_accel};
use crate::params::{CruiseParams, PccParams, PiParams};
use crate::plant::{Control, PlantState};
use crate::road::Road;
use crate::vehicle::{Model, Vehicle, NEUTRAL};
use crate::KMH_PER_MPS;

/// VECTO's declaration acceleration limits for trucks: speed [km/h], highest acceleration and
/// deceleration [m/s²].
const DRIVER_LIMITS: [(f64, f64, f64); 5] =
    [(0.0, 1.0, -1.0), (25.0, 1.0, -1.0), (50.0, 0.642857143, -1.0), (60.0, 0.5, -0.5), (120.0, 0.5, -0.5)];

/// The driver's highest acceleration and deceleration [m/s²] at `v_mps` (interpolated, held
/// beyond the table).
pub fn driver_limits_mps2(v_mps: f64) -> (f64, f64) {
    let v_kmh = v_mps * KMH_PER_MPS;
    let last = DRIVER_LIMITS[DRIVER_LIMITS.len() - 1];
    if v_kmh >= last.0 {
        return (last.1, last.2);
    }
    let i = DRIVER_LIMITS.iter().rposition(|row| row.0 <= v_kmh).unwrap_or(0);
    let (a, b) = (DRIVER_LIMITS[i], DRIVER_LIMITS[i + 1]);
    let w = (v_kmh - a.0) / (b.0 - a.0);
    (a.1 + w * (b.1 - a.1), a.2 + w * (b.2 - a.2))
}

/// VECTO's cruise driver; see the module's documentation.
#[derive(Debug, Clone)]
pub struct VectoDriver {
    vehicle: Arc<Vehicle>,
    gears: GearLogic,
    /// VECTO's AMT strategy, for a truck from VECTO's files (it then shifts instead of `gears`).
    amt: Option<AmtShifter>,
    /// The control of the last decision: what the driver asked of the gearbox.
    last: Control,
    cruise: CruiseParams,
    band: SpeedBand,
    band_hint: usize,
    slope_hint: usize,
    /// Allowed overspeed [km/h] (VECTO's 2.5 km/h; the band's v_inc with the PCC's use case 3).
    overspeed_kmh: f64,
    /// VECTO's overspeed without use case 3 [km/h].
    plain_overspeed_kmh: f64,
    overspeed_min_kmh: f64,
    coasting_min_kmh: f64,
    /// The plant's step [s]: the driver aims at the speed at its end.
    dt_s: f64,
    gear: usize,
    /// Look-ahead coasting under way: the lower stretch's start [m] and set speed [m/s].
    coasting_to: Option<(f64, f64)>,
}

impl VectoDriver {
    /// The driver of `vehicle` with the gear logic of `pi`, the set speed and band of `cruise`,
    /// VECTO's limits of `pcc`, deciding every plant step of `plant_dt_s` [s].
    pub fn new(
        vehicle: Arc<Vehicle>,
        pi: &PiParams,
        cruise: &CruiseParams,
        pcc: &PccParams,
        plant_dt_s: f64,
    ) -> CoreResult<Self> {
        let amt = match vehicle.model() {
            Model::Map(model) => Some(AmtShifter::new(model)),
            _ => None,
        };
        Ok(VectoDriver {
            gears: GearLogic::new(&vehicle, pi)?,
            amt,
            last: Control { pedal: 0.0, brake: 0.0, gear: NEUTRAL },
            vehicle,
            cruise: cruise.clone(),
            band: SpeedBand::uniform(cruise),
            band_hint: 0,
            slope_hint: 0,
            overspeed_kmh: pcc.vecto_overspeed_kmh,
            plain_overspeed_kmh: pcc.vecto_overspeed_kmh,
            overspeed_min_kmh: pcc.vecto_overspeed_min_speed_kmh,
            coasting_min_kmh: pcc.vecto_coasting_min_speed_kmh,
            dt_s: plant_dt_s,
            gear: NEUTRAL,
            coasting_to: None,
        })
    }

    /// Allow `kmh` of overspeed instead (the PCC's use case 3).
    pub fn set_overspeed_kmh(&mut self, kmh: f64) {
        self.overspeed_kmh = kmh;
    }

    /// The allowed overspeed [km/h].
    pub fn overspeed_kmh(&self) -> f64 {
        self.overspeed_kmh
    }

    /// The gear logic (table A.3).
    pub fn gear_logic(&self) -> &GearLogic {
        &self.gears
    }

    /// The gear the driver last chose (neutral before its first decision).
    pub fn gear(&self) -> usize {
        self.gear
    }

    /// Prepare for a run over `road`.
    pub fn start(&mut self, road: &Road) {
        self.band = SpeedBand::new(road, &self.cruise);
        self.band_hint = 0;
        self.slope_hint = 0;
        self.gear = NEUTRAL;
        self.coasting_to = None;
        self.last = Control { pedal: 0.0, brake: 0.0, gear: NEUTRAL };
        if let Some(amt) = self.amt.as_mut() {
            amt.reset();
        }
    }

    /// The gear to drive in at `state` on `slope`: VECTO's AMT strategy for a truck from VECTO's
    /// files, else the gear logic.
    fn shift(&mut self, road: &Road, state: &PlantState, slope: f64) -> usize {
        let (Some(amt), Model::Map(model)) = (self.amt.as_mut(), self.vehicle.model()) else {
            return self.gears.shift(&self.vehicle, self.gear, state.v_mps, slope);
        };
        let v = state.v_mps;
        // The torque the driver last asked of the wheels, at this speed: the road's load where it
        // coasted in neutral or has not driven yet.
        let wheel_torque_nm = if self.last.gear == NEUTRAL || self.gear == NEUTRAL {
            model.air_torque_nm(v) + model.slope_torque_nm(slope)
        } else {
            let (cut, full) = model.wheel_torque_range_nm(model.rpm_per_mps(self.gear) * v, self.gear);
            cut + self.last.pedal.max(0.0) * (full - cut)
        };
        let grade_ahead = (road.altitude_at(state.s_m + LOOKAHEAD_M) - road.altitude_at(state.s_m)) / LOOKAHEAD_M;
        let driving = self.last.pedal > 0.0;
        amt.gear(model, self.gear, &Request { t_s: state.t_s, v_mps: v, wheel_torque_nm, driving, grade_ahead })
    }

    /// The set speed at `s_m` [m/s]: the band's, which ramps down ahead of a lower target.
    pub fn target_mps(&mut self, s_m: f64) -> f64 {
        self.band.at(s_m, &mut self.band_hint).v_ref_mps()
    }

    /// The set speed of the stretch at `s_m` [m/s], without the band's ramp.
    pub fn stretch_target_mps(&mut self, s_m: f64) -> f64 {
        self.band.set_speed_kmh(s_m, &mut self.band_hint) / KMH_PER_MPS
    }

    /// [`VectoDriver::stretch_target_mps`] without a look-up hint, for look-ups out of order.
    pub fn stretch_target_at_mps(&self, s_m: f64) -> f64 {
        self.band.set_speed_kmh(s_m, &mut 0) / KMH_PER_MPS
    }

    /// Whether overspeed is allowed at set speed `target_mps`.
    fn overspeed_allowed(&self, target_mps: f64) -> bool {
        target_mps * KMH_PER_MPS > self.overspeed_min_kmh
    }

    /// The plain overspeed [m/s] at set speed `target_mps` (zero where overspeed is not allowed).
    fn plain_overspeed_mps(&self, target_mps: f64) -> f64 {
        if self.overspeed_allowed(target_mps) {
            self.plain_overspeed_kmh / KMH_PER_MPS
        } else {
            0.0
        }
    }

    /// The speed above which the driver brakes at set speed `target_mps` [m/s].
    pub fn limit_mps(&self, target_mps: f64) -> f64 {
        if self.overspeed_allowed(target_mps) {
            target_mps + self.overspeed_kmh / KMH_PER_MPS
        } else {
            target_mps
        }
    }

    /// One step of driving: accelerate to the set speed, coast in overspeed, brake at the limit.
    pub fn drive(&mut self, road: &Road, state: &PlantState) -> Control {
        self.last = self.drive_step(road, state);
        self.last
    }

    /// [`VectoDriver::drive`]'s decision.
    fn drive_step(&mut self, road: &Road, state: &PlantState) -> Control {
        let slope = road.slope_at(state.s_m, &mut self.slope_hint);
        self.gear = self.shift(road, state, slope);
        let target = self.target_mps(state.s_m);
        let limit = self.limit_mps(target);
        if self.band.varies() && self.look_ahead_coasting(road, state) {
            return self.coast_below(state.v_mps, limit, self.gear, slope);
        }
        let v = state.v_mps;
        let coast_next = v + self.dt_s * self.vehicle.accel_mps2(v, 0.0, 0.0, self.gear, slope);
        if v >= target && self.overspeed_allowed(target) {
            if coast_next > limit {
                return self.brake_to(v, limit, self.gear, slope);
            }
            if coast_next > target {
                return Control { pedal: 0.0, brake: 0.0, gear: self.gear };
            }
        }
        let control = self.pedal_to(v, target, slope);
        if control.pedal <= 0.0 && coast_next > limit {
            return self.brake_to(v, limit, self.gear, slope);
        }
        control
    }

    /// One step of coasting (a PCC event or eco-roll): no pedal, in neutral if `neutral`, else in
    /// the gear the logic picks; braking only to stay at the limit.
    pub fn coast(&mut self, road: &Road, state: &PlantState, neutral: bool) -> Control {
        let slope = road.slope_at(state.s_m, &mut self.slope_hint);
        self.gear = if neutral { NEUTRAL } else { self.shift(road, state, slope) };
        let target = self.target_mps(state.s_m);
        let limit = self.limit_mps(target);
        self.last = self.coast_below(state.v_mps, limit, self.gear, slope);
        self.last
    }

    /// No pedal in `gear`, the brake holding `limit_mps` if coasting would pass it.
    fn coast_below(&self, v_mps: f64, limit_mps: f64, gear: usize, slope: f64) -> Control {
        let next = v_mps + self.dt_s * self.vehicle.accel_mps2(v_mps, 0.0, 0.0, gear, slope);
        if next > limit_mps {
            return self.brake_to(v_mps, limit_mps, gear, slope);
        }
        Control { pedal: 0.0, brake: 0.0, gear }
    }

    /// The pedal that reaches `goal_mps` by the step's end, within the driver's acceleration limit.
    fn pedal_to(&self, v_mps: f64, goal_mps: f64, slope: f64) -> Control {
        let (accel_max, _) = driver_limits_mps2(v_mps);
        let wanted = ((goal_mps - v_mps) / self.dt_s).min(accel_max);
        let affine = pedal_accel(&self.vehicle, v_mps, self.gear, slope);
        let pedal = if affine.gain > 0.0 { (wanted - affine.accel_at_zero) / affine.gain } else { 0.0 };
        Control { pedal: pedal.clamp(0.0, 1.0), brake: 0.0, gear: self.gear }
    }

    /// The brake that ends the step at `goal_mps`, within the driver's deceleration limit.
    fn brake_to(&self, v_mps: f64, goal_mps: f64, gear: usize, slope: f64) -> Control {
        let (_, decel_max) = driver_limits_mps2(v_mps);
        let wanted = ((goal_mps - v_mps) / self.dt_s).max(decel_max);
        let affine = brake_accel(&self.vehicle, v_mps, gear, slope);
        let brake = if affine.gain < 0.0 { (wanted - affine.accel_at_zero) / affine.gain } else { 0.0 };
        Control { pedal: 0.0, brake: brake.clamp(0.0, 1.0), gear }
    }

    /// Start, continue or end look-ahead coasting; whether the driver coasts this step.
    fn look_ahead_coasting(&mut self, road: &Road, state: &PlantState) -> bool {
        let (s, v) = (state.s_m, state.v_mps);
        if let Some((until_m, set_mps)) = self.coasting_to {
            if s < until_m && v > set_mps {
                return true;
            }
            self.coasting_to = None;
            return false;
        }
        if v * KMH_PER_MPS <= self.coasting_min_kmh {
            return false;
        }
        // Every lower stretch within the preview counts (VECTO's GetNextDrivingAction): the driver
        // coasts once the earliest of their coasting starts is reached.
        let preview_m = LAC_PREVIEW_M_PER_KMH * v * KMH_PER_MPS;
        let mut hint = self.band_hint;
        let found = self.band.drops(s, preview_m, &mut hint).find_map(|(start_m, set_kmh)| {
            let set_mps = set_kmh / KMH_PER_MPS;
            let v_c = self.limit_mps(set_mps);
            // VECTO's coasting distance counts the lower target with the plain overspeed, even
            // where the PCC's use case 3 raised the driver's.
            let plain = set_mps + self.plain_overspeed_mps(set_mps);
            let factor = lac_decision_factor(plain * KMH_PER_MPS, (v - plain) * KMH_PER_MPS);
            let coast = v > v_c && time_to_coast(&self.vehicle, road, (s, v), (start_m, plain), self.gear, factor);
            coast.then_some((start_m, v_c))
        });
        if found.is_some() {
            self.coasting_to = found;
            return true;
        }
        false
    }
}

impl Controller for VectoDriver {
    fn name(&self) -> &'static str {
        "vecto_cc"
    }

    fn start(&mut self, road: &Road, _state: &PlantState) {
        VectoDriver::start(self, road);
    }

    fn decide(&mut self, road: &Road, state: &PlantState) -> Decision {
        Decision { control: self.drive(road, state), until_m: None }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The limits follow VECTO's truck curve: 1 m/s² to 25 km/h, 0.643 at 50, 0.5 from 60 on.
    #[test]
    fn driver_limits_follow_the_declaration_curve() {
        let at = |kmh: f64| driver_limits_mps2(kmh / KMH_PER_MPS);
        assert_eq!(at(10.0), (1.0, -1.0));
        assert!((at(55.0).0 - 0.5714285715).abs() < 1e-9);
        assert!((at(55.0).1 + 0.75).abs() < 1e-12);
        assert_eq!(at(85.0), (0.5, -0.5));
        assert_eq!(at(200.0), (0.5, -0.5));
    }
}

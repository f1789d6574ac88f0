//! VECTO's rule-based predictive cruise control (PCC) with eco-roll, rule for rule as VECTO's
//! driver has them, acting through VECTO's cruise driver ([`VectoDriver`]).
//!
//! **Segments.** Where the PCC may act is found once per run ([`segments`]): descents steeper than
//! the grade α* on which coasting at the set speed holds it, from a preview before them.
//!
//! **States**, updated every plant step (VECTO's `UpdatePCCState` and `HandlePCC`):
//! - *outside* a segment, or *within* one: the driver drives (and eco-roll may engage);
//! - from *within*, **use case 1** (crest coasting) starts before the descent's low point when the
//!   speed is at least the set speed less the underspeed and the truck's energy e = g·h + v²/2
//!   covers both the low point's (at the set speed less the underspeed) and the end's (at the set
//!   speed, at the preview's end or the segment's) plus the coasting losses there;
//! - from *within*, **use case 2** (accelerating without engine power) starts on the descent
//!   when the speed lies between max(set − underspeed, minimum speed) and the set speed less
//!   1 km/h and the energy covers the end's (use case 2's preview) plus the coasting losses;
//! - use case 1 is *interrupted* at the set speed less 1.05 × the underspeed (the driver drives)
//!   and resumes at the set speed less 0.95 × the underspeed; use cases 1 and 2 end above the set
//!   speed plus 1 km/h, use case 2 also below the minimum speed; each state ends at the segment's
//!   end, and a new check starts from *within*, so use cases may start again on one segment;
//! - during use cases 1 and 2 the truck coasts: no pedal, in neutral with eco-roll, else in gear;
//!   it brakes only at the overspeed limit.
//!
//! **Use case 3** (dip coasting) raises the driver's allowed overspeed from `vecto_overspeed_kmh`
//! to the band's v_inc_kmh wherever PCC is fitted (VECTO's highway sections: every road here).
//!
//! **Eco-roll** ([`eco_roll`]) is checked only outside the use cases.
//!
//! **Where the plant is not VECTO's powertrain**, what is done instead:
//! - the coasting losses per metre are the truck's deceleration on a flat road at the mean of the
//!   speed and the set speed, coasting as it would (in neutral with eco-roll, else in gear at fuel
//!   cut): VECTO sums air drag, rolling resistance and the driveline's present losses divided by
//!   the total mass; here the rotating masses and, in neutral, the driveline's losses are left out
//!   as the plant leaves them out;
//! - α* is found on the model at each set speed (in gear at fuel cut without eco-roll), where VECTO
//!   tabulates it per speed on a simplified powertrain and adds a mean engine drag;
//! - "pedal idle" (VECTO: the engine at its drag torque) is no pedal in a forward gear in the
//!   previous step, "brake active" any brake in the previous step;
//! - every road counts as highway (VECTO's cycles flag each stretch).

pub mod eco_roll;
pub mod segments;

use std::sync::Arc;

use self::eco_roll::{EcoRoll, EcoRollInputs, BELOW_OVERSPEED_KMH};
pub use self::segments::{pcc_segments, PccSegment, SegmentRules};
use super::vecto_driver::VectoDriver;
use super::{specific_energy_j_per_kg, Controller, Decision, RuleStats};
use crate::error::CoreResult;
use crate::params::{CruiseParams, PccParams, PiParams};
use crate::plant::{Control, PlantState};
use crate::road::Road;
use crate::vehicle::{Vehicle, NEUTRAL};
use crate::KMH_PER_MPS;

/// 1 km/h in m/s: the margin of VECTO's use case 2 entry and of both use cases' end.
const ONE_KMH_MPS: f64 = 1.0 / KMH_PER_MPS;
/// Use case 1 is interrupted below the set speed less this share of the underspeed.
const INTERRUPT_SHARE: f64 = 1.05;
/// An interrupted use case 1 resumes above the set speed less this share of the underspeed.
const RESUME_SHARE: f64 = 0.95;

/// The PCC's state in its segment.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PccState {
    OutsideSegment,
    WithinSegment,
    UseCase1,
    UseCase2,
    Interrupted,
}

/// The PCC controller; see the module's documentation.
#[derive(Debug, Clone)]
pub struct PccController {
    driver: VectoDriver,
    vehicle: Arc<Vehicle>,
    p: PccParams,
    underspeed_mps: f64,
    segments: Vec<PccSegment>,
    current: usize,
    state: PccState,
    eco: EcoRoll,
    /// The control of the previous step (eco-roll looks at its pedal and brake).
    last: Control,
    slope_hint: usize,
    /// Use case 1 and 2 starts, and eco-roll engagements, in the last run.
    events: u32,
    eco_rolls: u32,
}

impl PccController {
    /// PCC through VECTO's driver for `vehicle` (gear logic of `pi`), to `cruise`'s set speed and
    /// band, deciding every plant step of `plant_dt_s` [s].
    pub fn new(
        vehicle: Arc<Vehicle>,
        pi: &PiParams,
        cruise: &CruiseParams,
        pcc: &PccParams,
        plant_dt_s: f64,
    ) -> CoreResult<Self> {
        let mut driver = VectoDriver::new(vehicle.clone(), pi, cruise, pcc, plant_dt_s)?;
        if pcc.pcc_use_case_3 {
            driver.set_overspeed_kmh(cruise.v_inc_kmh);
        }
        Ok(PccController {
            driver,
            vehicle,
            p: pcc.clone(),
            underspeed_mps: cruise.v_dec_kmh / KMH_PER_MPS,
            segments: Vec::new(),
            current: 0,
            state: PccState::OutsideSegment,
            eco: EcoRoll::Off,
            last: Control { pedal: 0.0, brake: 0.0, gear: NEUTRAL },
            slope_hint: 0,
            events: 0,
            eco_rolls: 0,
        })
    }

    /// The segments found on the road of the last run.
    pub fn segments(&self) -> &[PccSegment] {
        &self.segments
    }

    /// Use case 1 and 2 starts in the last run (a resumed use case 1 not counted, nor one that
    /// ended in the step it started).
    pub fn events(&self) -> u32 {
        self.events
    }

    /// Eco-roll engagements in the last run.
    pub fn eco_rolls(&self) -> u32 {
        self.eco_rolls
    }

    /// The state after the last decision.
    pub fn state(&self) -> PccState {
        self.state
    }

    /// The gear the truck coasts in at set speed `v_mps` [m/s]: neutral with eco-roll, else the
    /// gear the logic settles in.
    fn coast_gear(&self, v_mps: f64) -> usize {
        if self.p.eco_roll {
            NEUTRAL
        } else {
            self.driver.gear_logic().steady_gear(v_mps)
        }
    }

    /// α*: the grade [-] on which the truck coasting at `v_mps` [m/s] keeps its speed (bisection).
    pub fn coasting_grade(&self, v_mps: f64) -> f64 {
        let gear = self.coast_gear(v_mps);
        let accel = |slope: f64| self.vehicle.accel_mps2(v_mps, 0.0, 0.0, gear, slope);
        let (mut steep, mut flat) = (-0.3, 0.0);
        if accel(flat) >= 0.0 {
            return flat;
        }
        for _ in 0..60 {
            let mid = 0.5 * (steep + flat);
            if accel(mid) >= 0.0 {
                steep = mid;
            } else {
                flat = mid;
            }
        }
        flat
    }

    /// Coasting losses per metre [J/(kg m)] from `v_mps` towards `target_mps` (see the module's
    /// documentation).
    fn coasting_loss(&self, v_mps: f64, target_mps: f64) -> f64 {
        let gear = if self.p.eco_roll { NEUTRAL } else { self.driver.gear().max(1) };
        -self.vehicle.accel_mps2(0.5 * (v_mps + target_mps), 0.0, 0.0, gear, 0.0)
    }

    /// The end of use case `preview_m`'s look [m] and the energy [J/kg] to arrive there with.
    fn end_of(&mut self, road: &Road, s_m: f64, preview_m: f64, segment: &PccSegment) -> (f64, f64) {
        let ahead_m = s_m + preview_m;
        if ahead_m <= segment.end_m {
            let target = self.driver.stretch_target_mps(ahead_m);
            return (ahead_m, specific_energy_j_per_kg(&self.vehicle, road, ahead_m, target));
        }
        (segment.end_m, segment.energy_end)
    }

    /// VECTO's `UpdatePCCState`: which segment, and whether a use case starts.
    fn update_state(&mut self, road: &Road, state: &PlantState, target: f64) {
        let (s, v) = (state.s_m, state.v_mps);
        // VECTO's CommitSimulationStep: past a segment's end the next one is checked afresh, even
        // where it overlaps the last (a use case running at the end does not carry over).
        while self.segments.get(self.current).is_some_and(|g| s > g.end_m) {
            self.current += 1;
            self.state = PccState::OutsideSegment;
        }
        let Some(segment) = self.segments.get(self.current).copied() else {
            self.state = PccState::OutsideSegment;
            return;
        };
        if s < segment.start_m {
            self.state = PccState::OutsideSegment;
            return;
        }
        if self.state == PccState::OutsideSegment {
            self.state = PccState::WithinSegment;
        }
        if self.state != PccState::WithinSegment {
            return;
        }
        let loss = self.coasting_loss(v, target);
        let energy = specific_energy_j_per_kg(&self.vehicle, road, s, v);
        let (end1, energy_end1) = self.end_of(road, s, self.p.pcc_preview_m, &segment);
        let use_case_1 = s < segment.x_low_m
            && v >= target - self.underspeed_mps
            && energy >= energy_end1 + loss * (end1 - s)
            && energy >= segment.energy_low + loss * (segment.x_low_m - s);
        if use_case_1 {
            self.state = PccState::UseCase1;
            return;
        }
        let (end2, energy_end2) = self.end_of(road, s, self.p.pcc_preview_uc2_m, &segment);
        let floor = (target - self.underspeed_mps).max(self.p.pcc_minimum_speed_kmh / KMH_PER_MPS);
        let use_case_2 = s >= segment.x_low_m
            && energy >= energy_end2 + loss * (end2 - s)
            && v >= floor
            && v <= target - ONE_KMH_MPS;
        if use_case_2 {
            self.state = PccState::UseCase2;
        }
    }

    /// VECTO's `HandlePCC`: a running use case ends, is interrupted or resumes.
    fn handle_state(&mut self, v_mps: f64, target_mps: f64) {
        let minimum = self.p.pcc_minimum_speed_kmh / KMH_PER_MPS;
        self.state = match self.state {
            PccState::UseCase1 if v_mps >= target_mps + ONE_KMH_MPS => PccState::WithinSegment,
            PccState::UseCase1 if v_mps <= target_mps - INTERRUPT_SHARE * self.underspeed_mps => PccState::Interrupted,
            PccState::UseCase2 if v_mps < minimum || v_mps > target_mps + ONE_KMH_MPS => PccState::WithinSegment,
            PccState::Interrupted if v_mps >= target_mps - RESUME_SHARE * self.underspeed_mps => PccState::UseCase1,
            unchanged => unchanged,
        };
    }

    /// VECTO's `HandleEcoRoll`: eco-roll's state after this step.
    fn handle_eco_roll(&mut self, road: &Road, state: &PlantState, target_mps: f64) {
        let v = state.v_mps;
        let slope = road.slope_at(state.s_m, &mut self.slope_hint);
        let top = target_mps + (self.driver.overspeed_kmh() - BELOW_OVERSPEED_KMH) / KMH_PER_MPS;
        let pedal_idle = self.last.gear != NEUTRAL && self.last.pedal <= 0.0;
        let braked = self.last.brake > 0.0;
        let conditions_met = v * KMH_PER_MPS >= self.p.eco_roll_min_speed_kmh
            && v <= top
            && slope < 0.0
            && pedal_idle
            && !braked
            // Rolling in neutral (the model's acceleration [m/s²]) last: it is the costly check.
            && (self.p.eco_roll_accel_min_mps2..=self.p.eco_roll_accel_max_mps2)
                .contains(&self.vehicle.accel_mps2(v, 0.0, 0.0, NEUTRAL, slope));
        let inputs = EcoRollInputs { conditions_met, below_target: v < target_mps, braked, t_s: state.t_s };
        let next = self.eco.next(&inputs, self.p.eco_roll_delay_s);
        if next == EcoRoll::On && self.eco != EcoRoll::On {
            self.eco_rolls += 1;
        }
        self.eco = next;
    }
}

impl Controller for PccController {
    fn name(&self) -> &'static str {
        "pcc"
    }

    fn start(&mut self, road: &Road, _state: &PlantState) {
        self.driver.start(road);
        let target_at = |s_m: f64| self.driver.stretch_target_at_mps(s_m);
        let grade = |v_mps: f64| self.coasting_grade(v_mps);
        let rules = SegmentRules {
            target_at: &target_at,
            coasting_grade: &grade,
            enabling_mps: self.p.pcc_enabling_speed_kmh / KMH_PER_MPS,
            preview_m: self.p.pcc_preview_m,
            underspeed_mps: self.underspeed_mps,
            gravity_mps2: self.vehicle.params().gravity_mps2,
        };
        self.segments = pcc_segments(road, &rules);
        self.current = 0;
        self.state = PccState::OutsideSegment;
        self.eco = EcoRoll::Off;
        self.last = Control { pedal: 0.0, brake: 0.0, gear: NEUTRAL };
        self.slope_hint = 0;
        self.events = 0;
        self.eco_rolls = 0;
    }

    fn decide(&mut self, road: &Road, state: &PlantState) -> Decision {
        let target = self.driver.stretch_target_mps(state.s_m);
        let coasting = |s: PccState| matches!(s, PccState::UseCase1 | PccState::UseCase2 | PccState::Interrupted);
        let was_coasting = coasting(self.state);
        self.update_state(road, state, target);
        self.handle_state(state.v_mps, target);
        if !was_coasting && coasting(self.state) {
            self.events += 1;
        }
        let outside_use_cases = matches!(self.state, PccState::OutsideSegment | PccState::WithinSegment);
        if self.p.eco_roll && outside_use_cases {
            self.handle_eco_roll(road, state, target);
        }
        let control = match self.state {
            PccState::UseCase1 | PccState::UseCase2 => self.driver.coast(road, state, self.p.eco_roll),
            _ if outside_use_cases && self.eco == EcoRoll::On => self.driver.coast(road, state, true),
            _ => self.driver.drive(road, state),
        };
        self.last = control;
        Decision { control, until_m: None }
    }

    fn rule_stats(&self) -> Option<RuleStats> {
        Some(RuleStats { pcc_events: self.events.into(), eco_roll_entries: self.eco_rolls.into() })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::vehicle::VehicleParams;

    fn controller() -> PccController {
        let vehicle = Arc::new(Vehicle::new(VehicleParams::default()).unwrap());
        let cruise = CruiseParams::default();
        PccController::new(vehicle, &PiParams::default(), &cruise, &PccParams::default(), 0.05).unwrap()
    }

    /// VECTO's `HandlePCC`: use case 1 is interrupted at the set speed less 1.05 × the underspeed,
    /// resumes at less 0.95 × and ends at the set speed + 1 km/h; use case 2 ends above the set
    /// speed + 1 km/h or below the minimum speed.
    #[test]
    fn use_cases_end_interrupt_and_resume_as_handle_pcc() {
        let (mut c, t, under) = (controller(), 85.0 / KMH_PER_MPS, 8.0 / KMH_PER_MPS);
        let mut after = |from: PccState, v_mps: f64| {
            c.state = from;
            c.handle_state(v_mps, t);
            c.state
        };
        assert_eq!(after(PccState::UseCase1, t - 1.04 * under), PccState::UseCase1);
        assert_eq!(after(PccState::UseCase1, t - 1.06 * under), PccState::Interrupted);
        assert_eq!(after(PccState::Interrupted, t - 0.96 * under), PccState::Interrupted);
        assert_eq!(after(PccState::Interrupted, t - 0.94 * under), PccState::UseCase1);
        assert_eq!(after(PccState::UseCase1, t + 0.99 * ONE_KMH_MPS), PccState::UseCase1);
        assert_eq!(after(PccState::UseCase1, t + 1.01 * ONE_KMH_MPS), PccState::WithinSegment);
        assert_eq!(after(PccState::UseCase2, t + 0.99 * ONE_KMH_MPS), PccState::UseCase2);
        assert_eq!(after(PccState::UseCase2, t + 1.01 * ONE_KMH_MPS), PccState::WithinSegment);
        assert_eq!(after(PccState::UseCase2, 49.9 / KMH_PER_MPS), PccState::WithinSegment);
    }

    /// VECTO's `CommitSimulationStep`: past a segment's end the next segment starts outside, so a
    /// use case still running there does not carry into an overlapping segment whose own entry
    /// conditions fail.
    #[test]
    fn a_use_case_does_not_carry_into_the_next_segment() {
        let mut c = controller();
        let road = Road::new(vec![0.0, 5000.0], vec![0.0]).unwrap();
        let t = 85.0 / KMH_PER_MPS;
        let at = |s_m: f64| PlantState {
            s_m,
            v_mps: t,
            t_s: 0.0,
            fuel_g: 0.0,
            brake_energy_j: 0.0,
            returned: 0.0,
            stalled: false,
        };
        c.start(&road, &at(0.0));
        let segment = |start_m, x_low_m, end_m| PccSegment {
            start_m,
            x_low_m,
            end_m,
            target_mps: t,
            energy_low: 1e9,
            energy_end: 1e9,
        };
        c.segments = vec![segment(0.0, 1000.0, 1500.0), segment(1200.0, 3000.0, 3500.0)];
        c.state = PccState::UseCase1;
        c.update_state(&road, &at(1600.0), t);
        assert_eq!((c.current, c.state), (1, PccState::WithinSegment));
    }

    /// α* in neutral at 85 km/h is the grade of table B.1 on which the 40 t truck holds 85 km/h in
    /// neutral (−1.25 %); in gear at fuel cut the engine's drag needs a steeper one.
    #[test]
    fn coasting_grade_is_where_coasting_holds_the_set_speed() {
        let v = 85.0 / KMH_PER_MPS;
        let neutral = controller().coasting_grade(v);
        assert!((neutral + 0.0125).abs() < 2e-4, "{neutral}");
        let vehicle = Arc::new(Vehicle::new(VehicleParams::default()).unwrap());
        let pcc = PccParams { eco_roll: false, ..PccParams::default() };
        let in_gear = PccController::new(vehicle, &PiParams::default(), &CruiseParams::default(), &pcc, 0.05)
            .unwrap()
            .coasting_grade(v);
        assert!(in_gear < neutral - 0.002, "{in_gear} {neutral}");
    }
}

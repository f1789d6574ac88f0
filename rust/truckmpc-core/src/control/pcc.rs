//! VECTO's rule-based predictive cruise control (PCC) with eco-roll, driving our plant on top of
//! the PI cruise control: the baseline trucks are sold with.
//!
//! **Descents.** At the start of a run the road is scanned for *descents*: stretches steeper
//! downhill than the slope α* at which the truck, coasting at v_ref (in neutral with eco-roll, else
//! in gear at fuel cut), holds its speed. A descent [x_low, x_end_max) is where the speed should
//! be lowest (its start) and by when it must be back at v_ref (its end).
//!
//! **Events.** Decisions compare specific energies e = g·h + v²/2 [J/kg] (VECTO compares m·g·h +
//! m·v²/2; the mass cancels), losing f = the coasting deceleration on a flat road at v_ref [m/s²,
//! J/(kg m)] per metre coasted:
//! - use case 1 (crest coasting), from x_low − preview to x_low: coast when coasting from here
//!   reaches x_low no slower than v_ref − underspeed (the band's v_dec) *and* reaches x_end = min(x + preview,
//!   x_end_max) with at least v_ref's energy;
//! - use case 2 (accelerating without engine power), on the descent below v_ref and above the
//!   minimum speed: coast when coasting reaches x_end (preview 1000 m) with v_ref's energy;
//! - use case 3 (dip coasting), on the descent: the brake limit is raised to v_ref + the allowed
//!   overspeed (the band's v_inc, so never below the band's top v_ref + v_inc).
//!
//! A use case 1 event ends when the speed falls below v_ref − underspeed; either event ends at
//! x_end, or when the speed passes the brake limit (the PI then brakes). The choices where VECTO's
//! text leaves the logic open: events do not start again on the same descent once ended; the PI
//! is reset to hold v_ref when an event or eco-roll ends (so its integrator has not wound up while
//! coasting); speeds and distances are compared once per plant step.
//!
//! **Eco-roll.** Outside events, with eco-roll fitted, at or above its minimum speed and at or
//! above v_ref: when the PI asks for no pedal and no brake for `eco_roll_delay_s`, the truck
//! declutches and coasts in neutral (idle fuel) until its speed falls below v_ref or passes the
//! brake limit.

use std::sync::Arc;

use super::pi::PiController;
use super::{specific_energy_j_per_kg, Controller, Decision};
use crate::error::CoreResult;
use crate::params::{CruiseParams, PccParams, PiParams};
use crate::plant::{Control, PlantState};
use crate::road::Road;
use crate::vehicle::{Vehicle, NEUTRAL};
use crate::KMH_PER_MPS;

/// A stretch of road steeper downhill than α*: the speed should be lowest at `x_low_m` and back at
/// v_ref by `x_end_max_m`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Descent {
    pub x_low_m: f64,
    pub x_end_max_m: f64,
}

/// What the controller is doing.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Mode {
    /// The PI drives.
    Cruise,
    /// Coasting through descent `descent` (use case 1 or 2) until `until_m`, or while the speed
    /// stays at or above `floor_mps`.
    Event { descent: usize, until_m: f64, floor_mps: f64 },
    /// Eco-roll in neutral.
    EcoRoll,
}

/// The PCC controller; see the module's documentation.
#[derive(Debug, Clone)]
pub struct PccController {
    pi: PiController,
    vehicle: Arc<Vehicle>,
    p: PccParams,
    /// Allowed underspeed of use case 1: the band's v_dec [km/h].
    underspeed_kmh: f64,
    /// Allowed overspeed of use case 3: the band's v_inc [km/h].
    overspeed_kmh: f64,
    /// The cruise set speed [m/s]: the coasting grade and loss are those at it.
    v_ref_mps: f64,
    /// The descents of the road, in order.
    descents: Vec<Descent>,
    /// Per descent, whether an event already ran there.
    used: Vec<bool>,
    mode: Mode,
    /// Since when [s] the PI has asked for neither pedal nor brake (eco-roll's delay), if it has.
    idle_since_s: Option<f64>,
    /// Number of use case 1 and 2 events started.
    events: u32,
}

impl PccController {
    /// PCC over the PI of `pi` working to `cruise`, for `vehicle`.
    pub fn new(vehicle: Arc<Vehicle>, pi: &PiParams, cruise: &CruiseParams, pcc: &PccParams) -> CoreResult<Self> {
        Ok(PccController {
            pi: PiController::new(vehicle.clone(), pi, cruise)?,
            vehicle,
            p: pcc.clone(),
            underspeed_kmh: cruise.v_dec_kmh,
            overspeed_kmh: cruise.v_inc_kmh,
            v_ref_mps: cruise.v_ref_mps(),
            descents: Vec::new(),
            used: Vec::new(),
            mode: Mode::Cruise,
            idle_since_s: None,
            events: 0,
        })
    }

    /// The descents found on the road of the last run.
    pub fn descents(&self) -> &[Descent] {
        &self.descents
    }

    /// Use case 1 and 2 events started in the last run.
    pub fn events(&self) -> u32 {
        self.events
    }

    /// The gear the truck coasts in: neutral with eco-roll, else the PI's top gear at v_ref.
    fn coast_gear(&self) -> usize {
        if self.p.eco_roll {
            NEUTRAL
        } else {
            self.pi.gear_logic().steady_gear(self.v_ref_mps)
        }
    }

    /// α*: the grade on which the truck coasting at v_ref keeps its speed (bisection) [-].
    pub fn coasting_grade(&self) -> f64 {
        let gear = self.coast_gear();
        let accel = |slope: f64| self.vehicle.accel_mps2(self.v_ref_mps, 0.0, 0.0, gear, slope);
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

    /// Coasting loss per metre on a flat road at v_ref [J/(kg m)].
    fn coast_loss(&self) -> f64 {
        -self.vehicle.accel_mps2(self.v_ref_mps, 0.0, 0.0, self.coast_gear(), 0.0)
    }

    /// The brake limit [m/s]: the band's top, raised on a descent by use case 3 to v_ref(s) plus
    /// the allowed overspeed.
    fn brake_limit_mps(&self, s_m: f64) -> f64 {
        let at = self.pi.band().at(s_m, &mut 0);
        let raised = (at.v_ref_mps() * KMH_PER_MPS + self.overspeed_kmh) / KMH_PER_MPS;
        if self.p.pcc_use_case_3 && self.descent_at(s_m).is_some() {
            at.v_max_mps().max(raised)
        } else {
            at.v_max_mps()
        }
    }

    /// The set speed at `s_m` [m/s] (the band's v_ref there).
    fn v_ref_at(&self, s_m: f64) -> f64 {
        self.pi.band().at(s_m, &mut 0).v_ref_mps()
    }

    fn descent_at(&self, s_m: f64) -> Option<usize> {
        self.descents.iter().position(|d| (d.x_low_m..d.x_end_max_m).contains(&s_m))
    }

    /// Specific energy at `s_m` with speed `v_mps` [J/kg].
    fn energy(&self, road: &Road, s_m: f64, v_mps: f64) -> f64 {
        specific_energy_j_per_kg(&self.vehicle, road, s_m, v_mps)
    }

    /// Whether coasting from `s_m` at `v_mps` arrives at `x_m` with at least the energy of `v_at`.
    fn coasts_to(&self, road: &Road, s_m: f64, v_mps: f64, x_m: f64, v_at: f64) -> bool {
        let left = self.energy(road, s_m, v_mps) - self.coast_loss() * (x_m - s_m);
        left >= self.energy(road, x_m, v_at)
    }

    /// A use case 1 or 2 event to start at `state`, if one should.
    fn event_to_start(&self, road: &Road, state: &PlantState) -> Option<Mode> {
        let (s, v) = (state.s_m, state.v_mps);
        for (k, d) in self.descents.iter().enumerate() {
            if self.used[k] || s >= d.x_end_max_m {
                continue;
            }
            if s < d.x_low_m - self.p.pcc_preview_m {
                continue;
            }
            let v_ref = self.v_ref_at(s.max(d.x_low_m));
            let v_low = (v_ref * KMH_PER_MPS - self.underspeed_kmh) / KMH_PER_MPS;
            if s < d.x_low_m {
                // Use case 1: before the descent, within the preview (checked above).
                if v < v_low {
                    continue;
                }
                let x_end = (s + self.p.pcc_preview_m).min(d.x_end_max_m);
                let v_end = self.v_ref_at(x_end);
                if self.coasts_to(road, s, v, d.x_low_m, v_low) && self.coasts_to(road, s, v, x_end, v_end) {
                    return Some(Mode::Event { descent: k, until_m: x_end, floor_mps: v_low });
                }
            } else if v < v_ref && v * KMH_PER_MPS >= self.p.pcc_minimum_speed_kmh {
                // Use case 2: on the descent, below v_ref.
                let x_end = (s + self.p.pcc_preview_uc2_m).min(d.x_end_max_m);
                let floor = self.p.pcc_minimum_speed_kmh / KMH_PER_MPS;
                if self.coasts_to(road, s, v, x_end, self.v_ref_at(x_end)) {
                    return Some(Mode::Event { descent: k, until_m: x_end, floor_mps: floor });
                }
            }
        }
        None
    }

    /// Hand back to the PI: reset it to hold v_ref from the present state.
    fn resume_cruise(&mut self, road: &Road, state: &PlantState) {
        self.pi.resume(road, state);
        self.mode = Mode::Cruise;
        self.idle_since_s = None;
    }

    fn coast(&self) -> Decision {
        Decision { control: Control { pedal: 0.0, brake: 0.0, gear: self.coasting_gear_now() }, until_m: None }
    }

    /// Neutral with eco-roll; else the gear the PI is in.
    fn coasting_gear_now(&self) -> usize {
        if self.p.eco_roll {
            NEUTRAL
        } else {
            self.pi.gear().max(1)
        }
    }
}

/// The descents of `road`: maximal runs of segments steeper downhill than `grade`.
pub fn descents(road: &Road, grade: f64) -> Vec<Descent> {
    let (x, slopes) = (road.distance_m(), road.slopes());
    let mut out = Vec::new();
    let mut start: Option<f64> = None;
    for (i, &slope) in slopes.iter().enumerate() {
        match (slope < grade, start) {
            (true, None) => start = Some(x[i]),
            (false, Some(a)) => {
                out.push(Descent { x_low_m: a, x_end_max_m: x[i] });
                start = None;
            }
            _ => {}
        }
    }
    if let Some(a) = start {
        out.push(Descent { x_low_m: a, x_end_max_m: road.end_m() });
    }
    out
}

impl Controller for PccController {
    fn name(&self) -> &'static str {
        "pcc"
    }

    fn start(&mut self, road: &Road, state: &PlantState) {
        self.pi.start(road, state);
        let mut found = descents(road, self.coasting_grade());
        // PCC acts only where the set speed is at least the enabling speed.
        found.retain(|d| self.v_ref_at(d.x_low_m) * KMH_PER_MPS >= self.p.pcc_enabling_speed_kmh);
        self.descents = found;
        self.used = vec![false; self.descents.len()];
        self.mode = Mode::Cruise;
        self.idle_since_s = None;
        self.events = 0;
    }

    fn decide(&mut self, road: &Road, state: &PlantState) -> Decision {
        let limit = self.brake_limit_mps(state.s_m);
        self.pi.set_brake_limit_kmh(limit * KMH_PER_MPS);
        match self.mode {
            Mode::Event { until_m, floor_mps, .. } => {
                if state.s_m < until_m && state.v_mps >= floor_mps && state.v_mps <= limit {
                    return self.coast();
                }
                self.resume_cruise(road, state);
            }
            Mode::EcoRoll => {
                if state.v_mps >= self.v_ref_at(state.s_m) && state.v_mps <= limit {
                    return self.coast();
                }
                self.resume_cruise(road, state);
            }
            Mode::Cruise => {}
        }
        if let Some(event) = self.event_to_start(road, state) {
            if let Mode::Event { descent, .. } = event {
                self.used[descent] = true;
            }
            self.events += 1;
            self.mode = event;
            return self.coast();
        }
        let decision = self.pi.decide(road, state);
        let idle = decision.control.pedal <= 0.0 && decision.control.brake <= 0.0;
        let eco_speed =
            state.v_mps * KMH_PER_MPS >= self.p.eco_roll_min_speed_kmh && state.v_mps >= self.v_ref_at(state.s_m);
        self.idle_since_s = if idle && eco_speed { self.idle_since_s.or(Some(state.t_s)) } else { None };
        if self.p.eco_roll && self.idle_since_s.is_some_and(|since| state.t_s - since >= self.p.eco_roll_delay_s) {
            self.mode = Mode::EcoRoll;
            return self.coast();
        }
        decision
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::vehicle::VehicleParams;

    fn controller(eco_roll: bool) -> PccController {
        let vehicle = Arc::new(Vehicle::new(VehicleParams::default()).unwrap());
        let pcc = PccParams { eco_roll, ..PccParams::default() };
        PccController::new(vehicle, &PiParams::default(), &CruiseParams::default(), &pcc).unwrap()
    }

    /// α* in neutral at 85 km/h is the grade of table B.1 on which the 40 t truck holds 85 km/h in
    /// neutral (−1.25 %); in gear at fuel cut the engine's drag needs a steeper one (−1.52 %).
    #[test]
    fn coasting_grade_is_where_coasting_holds_v_ref() {
        let neutral = controller(true).coasting_grade();
        assert!((neutral + 0.0125).abs() < 2e-4, "{neutral}");
        let in_gear = controller(false).coasting_grade();
        assert!(in_gear < neutral - 0.002, "{in_gear} {neutral}");
    }

    /// Descents are the maximal runs of segments steeper than the grade, to the road's end.
    #[test]
    fn descents_are_maximal_runs_of_steep_segments() {
        let x = vec![0.0, 100.0, 200.0, 300.0, 400.0, 500.0, 600.0];
        let slopes = vec![0.0, -0.02, -0.03, -0.005, -0.02, 0.0];
        let road = Road::new(x, slopes).unwrap();
        let found = descents(&road, -0.0125);
        let expected = [Descent { x_low_m: 100.0, x_end_max_m: 300.0 }, Descent { x_low_m: 400.0, x_end_max_m: 500.0 }];
        assert_eq!(found, expected);
        let last = Road::new(vec![0.0, 100.0, 200.0], vec![0.0, -0.03]).unwrap();
        assert_eq!(descents(&last, -0.0125), [Descent { x_low_m: 100.0, x_end_max_m: 200.0 }]);
    }
}

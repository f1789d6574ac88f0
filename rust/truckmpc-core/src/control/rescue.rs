//! What the look-ahead controller drives with while its DP finds no admissible path (a climb too
//! long for the speed band and the shift limit, a start above v_max): the PI's gear logic, full
//! pedal below v_max and a brake proportional to the excess above it, decided at every plant step.
//! It is always feasible in the sense that matters: the engine stays in its speed range wherever
//! the PI's would, and the truck climbs wherever the PI climbs.

use super::pi::GearLogic;
use crate::plant::Control;
use crate::vehicle::Vehicle;
use crate::KMH_PER_MPS;

/// Brake level per km/h above v_max, and the offset [km/h] that keeps braking just below v_max so
/// the speed ends up inside the band rather than creeping down towards its top.
const BRAKE_PER_KMH: f64 = 0.2;
const BRAKE_OFFSET_KMH: f64 = 1.0;

/// The rescue policy.
#[derive(Debug, Clone)]
pub struct Rescue {
    gears: GearLogic,
}

impl Rescue {
    /// Rescue with the PI's gear logic.
    pub fn new(gears: GearLogic) -> Self {
        Rescue { gears }
    }

    /// The inputs for one plant step of `vehicle` from `gear` at `v_mps` [m/s] on `slope` below
    /// the band's top `v_max_kmh` [km/h] there. A truck whose shifts interrupt traction shifts up
    /// only into a gear that still accelerates it at full load ([`GearLogic::shift`]): a shift
    /// costs it the interruption's speed, and an upshift the truck cannot hold would be followed by
    /// a downshift.
    pub fn step(&self, vehicle: &Vehicle, gear: usize, (v_mps, slope): (f64, f64), v_max_kmh: f64) -> Control {
        let gear = self.gears.shift(vehicle, gear, v_mps, slope);
        let over_kmh = v_mps * KMH_PER_MPS - v_max_kmh;
        if over_kmh > -BRAKE_OFFSET_KMH {
            let brake = ((over_kmh + BRAKE_OFFSET_KMH) * BRAKE_PER_KMH).clamp(0.0, 1.0);
            Control { pedal: 0.0, brake, gear }
        } else {
            Control { pedal: 1.0, brake: 0.0, gear }
        }
    }
}

//! VECTO's classic AMT shift strategy (`AMTShiftStrategy`, shift lines) in declaration mode, for
//! the rule-based drivers of a truck from VECTO's files. Each method names the VECTO function it
//! follows. The operating point VECTO tests is the gearbox input's: the torque the driver asks of
//! the gearbox (here the wheel torque of the driver's last control, at the current speed) seen at
//! the input in each gear, without the auxiliaries.
//!
//! Declaration mode's constants: at least 1.5 s between shifts, no downshift within 10 s of an
//! upshift nor upshift within 10 s of a downshift, an upshift only where the new gear can still
//! accelerate at 0.1 m/s² at full load on the mean grade of the next 100 m, and a torque reserve of
//! 20 % for an early upshift.

use super::geometry::{is_above, is_below, torque_on, Pt};
use super::polygon::{ShiftLineInputs, ShiftPolygon};
use crate::powertrain::{MapModel, RPM_PER_RAD_S};

/// VECTO's `MinTimeBetweenGearshifts` [s].
const SHIFT_TIME_S: f64 = 1.5;
/// VECTO's `DownshiftAfterUpshiftDelay` and `UpshiftAfterDownshiftDelay` [s].
const REVERSE_DELAY_S: f64 = 10.0;
/// VECTO's `UpshiftMinAcceleration` [m/s²].
const UPSHIFT_MIN_ACCEL_MPS2: f64 = 0.1;
/// VECTO's `TorqueReserve` and `TorqueReserveStart` [-].
const TORQUE_RESERVE: f64 = 0.2;
/// VECTO's `ClutchClosingSpeedNorm` [-].
const CLUTCH_CLOSING_SPEED_NORM: f64 = 0.065;
/// VECTO's `GearboxLookaheadForAccelerationEstimation` [m].
pub const LOOKAHEAD_M: f64 = 100.0;

/// What the driver asks of the gearbox at one decision.
#[derive(Debug, Clone, Copy)]
pub struct Request {
    /// Time [s].
    pub t_s: f64,
    /// Road speed [m/s].
    pub v_mps: f64,
    /// Torque asked at the wheels [Nm].
    pub wheel_torque_nm: f64,
    /// Whether the driver accelerates or holds the speed (VECTO's Accelerating or Driving), not
    /// coasting or braking.
    pub driving: bool,
    /// Mean grade (Δh/ΔL) over the next [`LOOKAHEAD_M`].
    pub grade_ahead: f64,
}

/// The strategy's state: its shift lines and when it last shifted.
#[derive(Debug, Clone)]
pub struct AmtShifter {
    polygons: Vec<ShiftPolygon>,
    lines: ShiftLineInputs,
    n95h_rad_s: f64,
    rated_rad_s: f64,
    last_shift_s: f64,
    last_up_s: f64,
    last_down_s: f64,
    /// The gear engaged before the gearbox went to neutral (VECTO's `_nextGear`).
    next_gear: usize,
}

impl AmtShifter {
    /// The strategy for `model`'s engine and gearbox.
    pub fn new(model: &MapModel) -> Self {
        let (engine, driveline) = (model.truck().engine(), model.truck().driveline());
        let ((full, drag), _) = engine.curves();
        let lines = ShiftLineInputs {
            full_load: full.points().map(|(n, t)| (n / RPM_PER_RAD_S, t)).collect(),
            min_drag_nm: drag.points().map(|p| p.1).fold(0.0, f64::min),
            idle_rad_s: engine.idle_rpm() / RPM_PER_RAD_S,
            gear_ratios: driveline.gear_ratios().to_vec(),
            axle_ratio: driveline.axle_ratio(),
            wheel_radius_m: driveline.wheel_radius_m(),
        };
        let polygons = (1..=driveline.gears()).map(|g| lines.polygon(g)).collect();
        let (n95h_rad_s, rated_rad_s) = (lines.n95h_rad_s(), lines.rated().0);
        let never = f64::NEG_INFINITY;
        AmtShifter {
            polygons,
            lines,
            n95h_rad_s,
            rated_rad_s,
            last_shift_s: never,
            last_up_s: never,
            last_down_s: never,
            next_gear: 0,
        }
    }

    /// Forgets the shifts of a previous run.
    pub fn reset(&mut self) {
        let never = f64::NEG_INFINITY;
        (self.last_shift_s, self.last_up_s, self.last_down_s, self.next_gear) = (never, never, never, 0);
    }

    /// What the shift lines are computed from.
    pub fn lines(&self) -> &ShiftLineInputs {
        &self.lines
    }

    /// Drive in `gear` from now on, as after an engagement.
    #[cfg(test)]
    pub(crate) fn force_gear(&mut self, gear: usize) {
        self.next_gear = gear;
    }

    /// Record a shift at `t_s`, up or down.
    #[cfg(test)]
    pub(crate) fn mark_shift(&mut self, t_s: f64, up: bool) {
        self.last_shift_s = t_s;
        if up {
            self.last_up_s = t_s;
        } else {
            self.last_down_s = t_s;
        }
    }

    /// The shift lines of `gear` (1..=n).
    pub fn polygon(&self, gear: usize) -> &ShiftPolygon {
        &self.polygons[gear - 1]
    }

    /// The gear to drive `r` in, coming from `gear` (0: neutral, from a stop, a start or a coast).
    pub fn gear(&mut self, model: &MapModel, gear: usize, r: &Request) -> usize {
        let next = if gear == 0 {
            if self.next_gear == 0 {
                self.init_gear(model, r)
            } else {
                self.engage(model, self.next_gear, r.v_mps)
            }
        } else {
            self.shift_required(model, gear, r)
        };
        if gear != 0 && next != gear {
            self.last_shift_s = r.t_s;
            if next > gear {
                self.last_up_s = r.t_s;
            } else {
                self.last_down_s = r.t_s;
            }
        }
        self.next_gear = next;
        next
    }

    /// Gearbox input (speed [rad/s], torque [Nm]) in `gear` for the request.
    fn input(&self, model: &MapModel, gear: usize, r: &Request) -> Pt {
        let n_rpm = model.rpm_per_mps(gear) * r.v_mps;
        let torque = model.truck().driveline().engine_torque_nm(r.wheel_torque_nm, gear, n_rpm);
        Pt { x: n_rpm / RPM_PER_RAD_S, y: torque }
    }

    /// (power asked of the engine, its full-load power) [W] at input point `p`: the auxiliaries'
    /// power included.
    fn powers(&self, model: &MapModel, p: Pt) -> (f64, f64) {
        let aux_w = model.truck().body().aux_power_w;
        (p.y * p.x + aux_w, self.lines.full_load_nm(p.x) * p.x)
    }

    /// VECTO's `SpeedTooLowForEngine`.
    fn too_low(&self, model: &MapModel, gear: usize, v_mps: f64) -> bool {
        model.rpm_per_mps(gear) * v_mps / RPM_PER_RAD_S < self.lines.idle_rad_s
    }

    /// VECTO's `SpeedTooHighForEngine`, without the gears' own input speed limits (VECTO's
    /// `MaxInputSpeed`; the files are read without them, and VECTO's generic gearbox has none).
    fn too_high(&self, model: &MapModel, gear: usize, v_mps: f64) -> bool {
        model.rpm_per_mps(gear) * v_mps / RPM_PER_RAD_S >= self.n95h_rad_s
    }

    /// VECTO's `Engage`: the gear before neutral, lowered while the engine would turn below idle
    /// and raised while at or above n95h.
    fn engage(&self, model: &MapModel, mut gear: usize, v_mps: f64) -> usize {
        let top = self.polygons.len();
        while gear > 1 && self.too_low(model, gear, v_mps) {
            gear -= 1;
        }
        while gear < top && self.too_high(model, gear, v_mps) {
            gear += 1;
        }
        gear
    }

    /// VECTO's `InitGear` at a speed above zero: from the top gear down, the first whose point lies
    /// between its shift lines with the starting torque reserve (one lower if the engine would turn
    /// within 6.5 % of idle towards rated), or the one above a gear whose upshift line it is
    /// beyond; else gear 1.
    fn init_gear(&self, model: &MapModel, r: &Request) -> usize {
        for gear in (2..=self.polygons.len()).rev() {
            let p = self.input(model, gear, r);
            let (asked, full) = self.powers(model, p);
            let reserve = 1.0 - asked / full;
            let poly = self.polygon(gear);
            let above_up = is_above(&poly.up, p);
            if !is_below(&poly.down, p) && !above_up && reserve >= TORQUE_RESERVE {
                let norm = (p.x - self.lines.idle_rad_s) / (self.rated_rad_s - self.lines.idle_rad_s);
                return if norm < CLUTCH_CLOSING_SPEED_NORM { gear - 1 } else { gear };
            }
            if above_up && gear < self.polygons.len() {
                return gear + 1;
            }
        }
        1
    }

    /// VECTO's `ShiftRequired` in `gear`: the engine's speed limits at once, then (1.5 s after the
    /// last shift) a downshift, else an upshift.
    fn shift_required(&self, model: &MapModel, gear: usize, r: &Request) -> usize {
        let engaged = self.engage(model, gear, r.v_mps);
        if engaged != gear {
            return engaged;
        }
        if self.last_shift_s + SHIFT_TIME_S > r.t_s {
            return gear;
        }
        let down = self.check_downshift(model, gear, r);
        if down != gear {
            return down;
        }
        self.check_upshift(model, gear, r)
    }

    /// VECTO's `CheckDownshift`/`DoCheckDownshift`: one gear down below the downshift line, not
    /// within 10 s of an upshift.
    fn check_downshift(&self, model: &MapModel, gear: usize, r: &Request) -> usize {
        if r.t_s - self.last_up_s < REVERSE_DELAY_S {
            return gear;
        }
        if is_below(&self.polygon(gear).down, self.input(model, gear, r)) {
            gear - 1
        } else {
            gear
        }
    }

    /// VECTO's `CheckUpshift`: only while driving and not within 10 s of a downshift; the gear of
    /// [`AmtShifter::do_check_upshift`] if it can accelerate at 0.1 m/s², else one gear up if that
    /// one can, else none.
    fn check_upshift(&self, model: &MapModel, gear: usize, r: &Request) -> usize {
        if !r.driving || r.t_s - self.last_down_s < REVERSE_DELAY_S {
            return gear;
        }
        let next = self.do_check_upshift(model, gear, r);
        if next == gear || self.acceleration(model, (gear, next), r) >= UPSHIFT_MIN_ACCEL_MPS2 {
            return next;
        }
        if next - gear == 1 || self.acceleration(model, (gear, gear + 1), r) < UPSHIFT_MIN_ACCEL_MPS2 {
            return gear;
        }
        gear + 1
    }

    /// VECTO's `DoCheckUpshift`: beyond the upshift line one gear up, and further while the gear
    /// above keeps a torque reserve and stays above its downshift line (skipping gears); then an
    /// early upshift ([`AmtShifter::early_upshift`]).
    fn do_check_upshift(&self, model: &MapModel, mut gear: usize, r: &Request) -> usize {
        let top = self.polygons.len();
        let now = self.input(model, gear, r);
        if is_above(&self.polygon(gear).up, now) {
            gear += 1;
            while gear < top {
                gear += 1;
                let p = self.input(model, gear, r);
                let full_w = self.lines.full_load_nm(p.x) * p.x;
                let max_torque = (full_w / ((now.x + p.x) / 2.0)).min(torque_on(&self.polygon(gear).down, p.x));
                if 1.0 - p.y / max_torque >= 0.0 && is_above(&self.polygon(gear).down, p) {
                    continue;
                }
                gear -= 1;
                break;
            }
        }
        if gear < top {
            gear = self.early_upshift(model, gear, r);
        }
        gear
    }

    /// VECTO's `CheckEarlyUpshift`: one gear up where that gear's point is not below its downshift
    /// line and leaves the engine a 20 % power reserve.
    fn early_upshift(&self, model: &MapModel, gear: usize, r: &Request) -> usize {
        let p = self.input(model, gear + 1, r);
        if is_below(&self.polygon(gear + 1).down, p) {
            return gear;
        }
        let (asked, full) = self.powers(model, p);
        if 1.0 - asked / full >= TORQUE_RESERVE {
            gear + 1
        } else {
            gear
        }
    }

    /// VECTO's `EstimateAccelerationForGear` [m/s²] in `gear`, driving in `now`: the engine's
    /// full-load power in `gear` less the gearbox's loss there, the axle's loss now, and the air,
    /// rolling and grade resistance on the mean grade ahead (which VECTO takes as the angle in
    /// radians), over the speed and the mass with the wheels' inertia.
    fn acceleration(&self, model: &MapModel, (now_gear, gear): (usize, usize), r: &Request) -> f64 {
        let truck = model.truck();
        let n_rpm = model.rpm_per_mps(gear) * r.v_mps;
        let full_nm = self.lines.full_load_nm(n_rpm / RPM_PER_RAD_S);
        let driveline = truck.driveline();
        let gearbox_w = driveline.stage_losses_w(full_nm, gear, n_rpm).gearbox_w;
        let now = self.input(model, now_gear, r);
        let axle_w = driveline.stage_losses_w(now.y, now_gear, now.x * RPM_PER_RAD_S).axle_w;
        let loads = truck.road_loads(r.v_mps, 0.0, r.grade_ahead);
        let power =
            full_nm * n_rpm / RPM_PER_RAD_S - gearbox_w - axle_w - loads.air_w - loads.rolling_w - loads.slope_w;
        let r_m = driveline.wheel_radius_m();
        let body = truck.body();
        power / r.v_mps / (body.mass_kg + body.wheels_inertia_kgm2 / (r_m * r_m))
    }
}

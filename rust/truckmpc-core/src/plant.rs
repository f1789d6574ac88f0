//! The simulated truck: (B.1) and (B.2) integrated in time with classic fourth-order Runge–Kutta at a
//! fine step, the slope looked up at each evaluation's position and steps split at the road's
//! profile points. Integrating in time (not distance)
//! keeps dv/dt finite at any speed; a truck that drops below the stall speed stops the run.
//!
//! The plant drives any [`Powertrain`] (the built-in trucks through [`Vehicle`]). A shift whose
//! powertrain interrupts traction ([`Powertrain::shift_interruption_s`]; a map-based truck with an
//! automated manual gearbox) rolls the truck in neutral at the powertrain's interrupted energy
//! rate for that time; the thesis's truck shifts instantly. The energy rate is integrated as drawn
//! from the powertrain's store (fuel for a diesel), the friction brakes' share of the braking as
//! brake energy; once the store is empty the truck no longer moves. A drive that derates when it
//! overheats (a battery-electric truck's machines, [`crate::powertrain::thermal`]) fills its
//! thermal buffer with its heating at each step and, once derated, drives as its derated self.

use std::sync::Arc;

pub use crate::powertrain::Control;
use crate::powertrain::{EnergyStore, Powertrain, ThermalState};
use crate::road::Road;
use crate::vehicle::{Vehicle, NEUTRAL};

/// State of the simulated truck; the integrals are cumulative since the start of the run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlantState {
    /// Position along the road [m].
    pub s_m: f64,
    /// Speed [m/s].
    pub v_mps: f64,
    /// Elapsed time [s].
    pub t_s: f64,
    /// Fuel used [g]: the energy drawn from the powertrain's store, in its unit (grams of fuel for
    /// a fuel tank).
    pub fuel_g: f64,
    /// Energy dissipated in the service (friction) brakes [J].
    pub brake_energy_j: f64,
    /// Energy returned to the store while the rate was negative, in the rate's unit (for a
    /// battery, joules recovered while braking beyond what the truck drew meanwhile; zero for a
    /// fuel tank).
    pub returned: f64,
    /// Set once the speed fell below the stall speed or the energy store ran empty; the plant then
    /// no longer moves.
    pub stalled: bool,
}

/// Derivatives of (s, v, fuel, brake energy, energy returned, heat, machine loss, battery loss)
/// with respect to time.
type Rates = [f64; 8];

/// The truck on a road, integrated in time.
#[derive(Debug, Clone)]
pub struct Plant<P = Vehicle> {
    vehicle: Arc<P>,
    road: Arc<Road>,
    state: PlantState,
    segment_hint: usize,
    stall_speed_mps: f64,
    /// The gear last applied (None before the first step).
    engaged_gear: Option<usize>,
    /// Time left of the traction interruption of the last shift [s].
    interruption_left_s: f64,
    /// The store the energy is drawn from.
    store: EnergyStore,
    /// The drive's thermal buffer, for one that derates (none: it never does).
    thermal: Option<ThermalState>,
    /// The drive derated, built when it first derates.
    derated: Option<Arc<P>>,
    /// Energy lost in the machines and in the battery so far [J] (a battery's store only).
    losses_j: [f64; 2],
}

impl<P: Powertrain> Plant<P> {
    /// A truck at `s_m` with speed `v_mps`, nothing used yet.
    pub fn new(vehicle: Arc<P>, road: Arc<Road>, s_m: f64, v_mps: f64) -> Self {
        let stall_speed_mps = vehicle.stall_speed_mps();
        let store = vehicle.store();
        let stalled = v_mps < stall_speed_mps || store.is_empty(0.0);
        let state = PlantState { s_m, v_mps, t_s: 0.0, fuel_g: 0.0, brake_energy_j: 0.0, returned: 0.0, stalled };
        let (engaged_gear, interruption_left_s) = (None, 0.0);
        let thermal = vehicle.thermal().map(ThermalState::new);
        Plant {
            vehicle,
            road,
            state,
            segment_hint: 0,
            stall_speed_mps,
            engaged_gear,
            interruption_left_s,
            store,
            thermal,
            derated: None,
            losses_j: [0.0; 2],
        }
    }

    /// Energy lost in the machines and in the battery since the start [J] (zero but for a
    /// battery-electric truck).
    pub fn losses_j(&self) -> [f64; 2] {
        self.losses_j
    }

    /// The drive's thermal buffer now (none for a drive that never derates).
    pub fn thermal(&self) -> Option<ThermalState> {
        self.thermal
    }

    /// Whether the drive is derated now.
    pub fn is_derated(&self) -> bool {
        self.thermal.is_some_and(|t| t.derated)
    }

    /// The drive as it drives now and the control it takes for `u` at `v_mps`: the derated drive
    /// ([`derated_control`]) while its thermal buffer says so.
    #[inline]
    fn active(&self, v_mps: f64, u: Control) -> (&P, Control) {
        match (&self.thermal, &self.derated) {
            (Some(t), Some(derated)) if t.derated => {
                (derated, derated_control(self.vehicle.as_ref(), derated.as_ref(), v_mps, u).0)
            }
            _ => (&self.vehicle, u),
        }
    }

    /// Current state.
    pub fn state(&self) -> PlantState {
        self.state
    }

    /// The vehicle being simulated.
    pub fn vehicle(&self) -> &P {
        &self.vehicle
    }

    /// The energy store's state of charge [0–1] now (None for a fuel tank).
    pub fn state_of_charge(&self) -> Option<f64> {
        self.store.state_of_charge(self.state.fuel_g)
    }

    /// Time derivatives at speed `v_mps` on a slope given by its wheel torque [Nm].
    #[inline]
    fn rates(&self, slope_torque_nm: f64, v_mps: f64, u: Control) -> Rates {
        let (vehicle, u) = self.active(v_mps, u);
        let accel = vehicle.accel_on(v_mps, u.pedal, u.brake, u.gear, slope_torque_nm);
        let [energy, heat, machine_loss, battery_loss] = if self.interruption_left_s > 0.0 {
            [vehicle.interrupted_energy_rate(v_mps), 0.0, 0.0, 0.0]
        } else {
            vehicle.rates_with_losses(v_mps, u)
        };
        let brake_power = vehicle.friction_brake_force_n(v_mps, u) * v_mps;
        [v_mps, accel, energy, brake_power, (-energy).max(0.0), heat, machine_loss, battery_loss]
    }

    /// Advance by `dt_s` with constant inputs. No-op once stalled. The step is split at the road's
    /// profile points and each part uses the one slope of its segment, so no RK4 stage sees a slope
    /// the step does not drive on (which would cost accuracy at every slope jump); the time
    /// advanced is `dt_s` all the same.
    pub fn step(&mut self, u: Control, dt_s: f64) {
        if let Some(previous) = self.engaged_gear {
            let interruption_s = self.vehicle.shift_interruption_s(previous, u.gear);
            if interruption_s > 0.0 {
                self.interruption_left_s = interruption_s;
            }
        }
        self.engaged_gear = Some(u.gear);
        let mut remaining = dt_s;
        if self.interruption_left_s > 0.0 {
            let dt = self.interruption_left_s.min(remaining);
            self.step_engaged(Control { pedal: 0.0, brake: u.brake, gear: NEUTRAL }, dt);
            remaining -= dt;
            // Exactly zero once used up, so the rest of the step is fuelled.
            self.interruption_left_s = if dt < self.interruption_left_s { self.interruption_left_s - dt } else { 0.0 };
        }
        self.step_engaged(u, remaining);
    }

    /// [`Plant::step`] with the inputs applied as given (no shift to start).
    fn step_engaged(&mut self, u: Control, dt_s: f64) {
        // A split lands within a second-order error of the point; a few more are never needed.
        const MAX_SPLITS: usize = 4;
        // A point closer than this ahead counts as passed (the split's landing error).
        const PASSED_M: f64 = 1e-6;
        let mut remaining = dt_s;
        for split in 0..=MAX_SPLITS {
            if self.state.stalled || remaining <= 0.0 {
                return;
            }
            let x = self.state;
            let ahead = x.s_m + PASSED_M;
            let slope_torque = self.vehicle.slope_torque_nm(self.road.slope_at(ahead, &mut self.segment_hint));
            let k1 = self.rates(slope_torque, x.v_mps, u);
            let to_point = self.road.next_point_after(ahead, &mut self.segment_hint) - x.s_m;
            // Distance covered in `remaining` at the current acceleration, with a margin.
            let reach = 1.1 * (x.v_mps * remaining + 0.5 * k1[1].abs() * remaining * remaining);
            let dt = if to_point < reach && split < MAX_SPLITS {
                (to_point / x.v_mps.max(self.stall_speed_mps)).min(remaining)
            } else {
                remaining
            };
            self.rk4(u, dt, slope_torque, k1);
            remaining -= dt;
        }
    }

    /// One classic RK4 step of `dt_s` on one slope with constant inputs, given the rates `k1` at
    /// its start.
    fn rk4(&mut self, u: Control, dt_s: f64, slope_torque_nm: f64, k1: Rates) {
        if self.state.stalled || dt_s <= 0.0 {
            return;
        }
        let x = self.state;
        let k2 = self.rates(slope_torque_nm, x.v_mps + 0.5 * dt_s * k1[1], u);
        let k3 = self.rates(slope_torque_nm, x.v_mps + 0.5 * dt_s * k2[1], u);
        let k4 = self.rates(slope_torque_nm, x.v_mps + dt_s * k3[1], u);
        let d = |i: usize| dt_s / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        self.state.s_m += d(0);
        self.state.v_mps += d(1);
        self.state.fuel_g += d(2);
        self.state.brake_energy_j += d(3);
        self.state.returned += d(4);
        self.state.t_s += dt_s;
        self.losses_j[0] += d(6);
        self.losses_j[1] += d(7);
        let binds = self.derating_binds(x.v_mps, u);
        if let Some(thermal) = self.thermal.as_mut() {
            thermal.commit(d(5), dt_s, binds);
            if thermal.derated && self.derated.is_none() {
                self.derated = self.vehicle.derated().map(Arc::new);
            }
        }
        if !(self.state.v_mps >= self.stall_speed_mps) || self.store.is_empty(self.state.fuel_g) {
            self.state.stalled = true;
        }
    }

    /// Whether the drive runs derated at `v_mps` in `u`'s gear with limits below its rated ones
    /// (its most driving or most recovering torque lower).
    fn derating_binds(&self, v_mps: f64, u: Control) -> bool {
        match (&self.thermal, &self.derated) {
            (Some(t), Some(derated)) if t.derated => {
                derated_control(self.vehicle.as_ref(), derated.as_ref(), v_mps, u).1
            }
            _ => false,
        }
    }

    /// Advance by at most `dt_s` but stop at `s_limit_m`: the last step is shortened so the truck
    /// ends on the limit (to a second-order error in the step, under a millimetre; [`Plant::advance_to`]
    /// closes the rest). Returns the time step taken [s].
    pub fn step_until(&mut self, u: Control, dt_s: f64, s_limit_m: f64) -> f64
    where
        P: Clone,
    {
        // A shortened step that passes the limit by more than this is taken again, shorter (a
        // very light truck's acceleration makes the first-order guess overshoot by millimetres).
        const OVERSHOOT_M: f64 = 1e-3;
        let remaining = s_limit_m - self.state.s_m;
        if remaining <= 0.0 || self.state.stalled {
            return 0.0;
        }
        let v = self.state.v_mps.max(self.stall_speed_mps);
        // Distance covered in dt with a first-order guess; shorten when it would pass the limit.
        if v * dt_s < remaining {
            self.step(u, dt_s);
            return dt_s;
        }
        let dt = remaining / v;
        let before = self.clone();
        self.step(u, dt);
        let over = self.state.s_m - s_limit_m;
        if over <= OVERSHOOT_M {
            return dt;
        }
        *self = before;
        let shorter = dt * remaining / (remaining + over);
        self.step(u, shorter);
        shorter
    }

    /// Advance with constant inputs until `s_target_m` (or a stall), in steps of at most `dt_s`.
    pub fn advance_to(&mut self, u: Control, dt_s: f64, s_target_m: f64)
    where
        P: Clone,
    {
        // The shortened last step lands within a second-order error of the target; a few more
        // tiny steps close the gap. The bound guards against a truck that can no longer move.
        const TOLERANCE_M: f64 = 1e-6;
        let mut guard = 0usize;
        while s_target_m - self.state.s_m > TOLERANCE_M && !self.state.stalled {
            self.step_until(u, dt_s, s_target_m);
            guard += 1;
            if guard > 100_000_000 {
                break;
            }
        }
    }
}

/// The control the `derated` drive takes for `u` at `v_mps`, and whether de-rating binds there.
/// De-rating caps the machines' torque; below the cap the pedal gives the rated drive's torque:
/// the pedal is rescaled by the ratio of the two drives' full-pedal gains and held to full pedal
/// of the derated drive. It binds where the rated torque asked for is above the cap, or where the
/// derated drive leaves the friction brakes more of the brake's force than the rated one.
pub fn derated_control<P: Powertrain>(rated: &P, derated: &P, v_mps: f64, u: Control) -> (Control, bool) {
    if u.gear == NEUTRAL {
        return (u, false);
    }
    let gain = |p: &P| p.pedal_affine(v_mps, u.gear, 0.0).gain;
    let (rated_gain, derated_gain) = (gain(rated), gain(derated));
    let asked = u.pedal * rated_gain;
    let pedal = if derated_gain > 0.0 { (asked / derated_gain).min(1.0) } else { u.pedal };
    let braked = |p: &P| p.friction_brake_force_n(v_mps, u);
    let binds = (u.pedal > 0.0 && asked > derated_gain) || (u.brake > 0.0 && braked(derated) > braked(rated));
    (Control { pedal, ..u }, binds)
}

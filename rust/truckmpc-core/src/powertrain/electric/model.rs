//! A battery-electric truck in the form the plant and the controllers drive it.
//!
//! **The pedal.** At a given speed the pedal P ∈ [0, 1] sets the wheel torque between what the
//! machines give turning without current (their drag, through the reduction) and their most
//! driving torque, W(P) = W_drag + P·(W_full − W_drag), so the acceleration is affine in the pedal
//! as with the other trucks. The most driving torque is the machines' limit or, where lower, the
//! torque whose electric power and the auxiliaries' take the battery's most power.
//!
//! **Coasting** (P = 0, brake off) switches the machines off: they turn against their drag and
//! draw nothing. The truck has one gear; gear 0 (neutral) is the same as coasting in it, since
//! the machines at the axle cannot be declutched.
//!
//! **Braking** with brake level B asks for B times the service brakes' torque at the wheels.
//! Above 10 km/h the machines take what they can of it as generators (down to their most braking
//! torque, and to the torque whose returned power the battery's charging current takes); the
//! friction brakes take the rest. The acceleration does not depend on the split.
//!
//! **Energy.** The rate is the power drawn from the battery's store [W]: U·I for the current I
//! that gives the terminals the machines' electric power and the auxiliaries'; negative while the
//! machines return more than the auxiliaries take. The auxiliaries draw a constant power, and the
//! machines' conditioning (cooling) a constant power more while they carry current.

use super::battery::Battery;
use super::truck::ElectricTruck;
use crate::powertrain::interface::{AffineAccel, Control, EnergyStore, Powertrain, RateForm, NEUTRAL};
use crate::powertrain::sampled::Sampled;
use crate::powertrain::thermal::Thermal;
use crate::powertrain::{FuelGrid, G_MPS2, RPM_PER_RAD_S};

/// Lowest speed at which braking recovers energy [m/s] (VECTO's 10 km/h).
pub const RECUPERATION_MIN_MPS: f64 = 10.0 / 3.6;

/// Below this speed [m/s] a run counts as stopped: the cruise has ended in a standstill.
const STOP_SPEED_MPS: f64 = 0.5;

/// Nodes along each axis of the machines' resampled loss.
const LOSS_NODES: usize = 401;

/// Bisection steps that find a battery-limited torque (to about 1e-9 of the machines' range).
const BISECTION_STEPS: usize = 40;

/// The truck's equations of motion and battery power, from its component data.
#[derive(Debug, Clone)]
pub struct ElectricModel {
    truck: ElectricTruck,
    brake_torque_max_nm: f64,
    /// Machine speed per road speed [rpm/(m/s)].
    rpm_per_mps: f64,
    /// r / (I_wheels + m r² + I_machines·ratio²) [1/(kg m)].
    c1: f64,
    /// m g r [Nm].
    weight_torque_nm: f64,
    /// Wheel torque [Nm] over machine speed: turning without current, at the most driving torque,
    /// at the most braking torque (zero recovery below 10 km/h: the drag).
    wheel_drag: Sampled,
    wheel_full: Sampled,
    wheel_regen: Sampled,
    /// Wheel torque [Nm] over machine speed at the glide, where the machines draw no electric
    /// power (NaN where there is no such torque).
    wheel_glide: Sampled,
    /// The machines' loss [W] over (speed, torque), resampled.
    loss: FuelGrid,
}

/// Where one control's power goes [W]: a breakdown of the battery's rate for energy balances.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PowerFlows {
    /// Power drawn from the battery's store (the energy rate).
    pub battery_w: f64,
    /// Lost in the battery's internal resistance.
    pub battery_loss_w: f64,
    /// Taken by the auxiliaries.
    pub aux_w: f64,
    /// Lost in the machines: electric power less mechanical power (their drag's while off).
    pub machine_loss_w: f64,
    /// Lost in the reduction.
    pub reduction_loss_w: f64,
    /// Mechanical power the machines give the wheels (negative: taken from them).
    pub wheel_w: f64,
    /// Machine speed [rpm] and torque [Nm] (the drag while off).
    pub machine_rpm: f64,
    pub machine_nm: f64,
    /// Whether the machines carry current (false: off, turning against their drag).
    pub running: bool,
}

impl ElectricModel {
    /// The model of `truck`, whose service brakes give at most `brake_torque_max_nm` at the wheels.
    pub fn new(truck: ElectricTruck, brake_torque_max_nm: f64) -> Self {
        let r = truck.wheel_radius_m();
        let body = *truck.body();
        let machines = truck.machines();
        let rpm_per_mps = truck.machine_rpm(1.0);
        let c1 =
            r / (body.wheels_inertia_kgm2 + body.mass_kg * r * r + machines.inertia_kgm2() * truck.ratio().powi(2));
        let (speed_rpm, torque_nm) = machines.map_range();
        let loss = FuelGrid::from_fn(speed_rpm, torque_nm, LOSS_NODES, |n, t| machines.loss_w(n, t));
        let range = (0.0, machines.top_rpm().max(speed_rpm.1) + 1.0);
        let wheel = |f: &dyn Fn(f64) -> f64| Sampled::from_fn(range, |n| truck.wheel_nm(n, f(n)));
        let (electric_max_w, electric_min_w) =
            electric_limits(truck.battery(), body.aux_power_w + truck.conditioning_w());
        let full = |n: f64| {
            let (drag, top) = (machines.drag_nm(n), machines.max_drive_nm(n).max(machines.drag_nm(n)));
            limit_torque(|t| machines.electric_power_w(n, t) <= electric_max_w, drag, top)
        };
        let regen_rpm = RECUPERATION_MIN_MPS * rpm_per_mps;
        let regen = |n: f64| {
            let drag = machines.drag_nm(n);
            if n < regen_rpm {
                return drag;
            }
            limit_torque(
                |t| machines.electric_power_w(n, t) >= electric_min_w,
                drag,
                machines.max_brake_nm(n).min(drag),
            )
        };
        // The glide: the torque between the drag and zero at which the machines draw no electric
        // power, as the model's loss grid gives it (none below 10 km/h, or where there is none).
        let glide = |n: f64| {
            let (drag, omega) = (machines.drag_nm(n), n / RPM_PER_RAD_S);
            let electric = |t: f64| t * omega + loss.at(n, t);
            if n < regen_rpm || !(electric(drag) < 0.0 && electric(0.0) > 0.0) {
                return f64::NAN;
            }
            limit_torque(|t| electric(t) <= 0.0, drag, 0.0)
        };
        let (wheel_drag, wheel_full, wheel_regen) = (wheel(&|n| machines.drag_nm(n)), wheel(&full), wheel(&regen));
        let wheel_glide = wheel(&glide);
        let weight_torque_nm = body.mass_kg * G_MPS2 * r;
        ElectricModel {
            truck,
            brake_torque_max_nm,
            rpm_per_mps,
            c1,
            weight_torque_nm,
            wheel_drag,
            wheel_full,
            wheel_regen,
            wheel_glide,
            loss,
        }
    }

    /// The truck this model drives.
    pub fn truck(&self) -> &ElectricTruck {
        &self.truck
    }

    /// Brake torque at the wheels at full brake [Nm].
    pub fn brake_torque_max_nm(&self) -> f64 {
        self.brake_torque_max_nm
    }

    /// r / effective inertia [1/(kg m)]: acceleration per wheel torque.
    pub fn c1(&self) -> f64 {
        self.c1
    }

    /// Machine speed per road speed [rpm/(m/s)].
    pub fn rpm_per_mps(&self) -> f64 {
        self.rpm_per_mps
    }

    /// Air drag torque at the wheel at `v_mps` [Nm]: ½ρ·CdA(v)·v²·r.
    #[inline]
    pub fn air_torque_nm(&self, v_mps: f64) -> f64 {
        let body = self.truck.body();
        0.5 * body.air_density_kgpm3 * self.truck.cda_m2(v_mps) * v_mps * v_mps * self.truck.wheel_radius_m()
    }

    /// Wheel torques [Nm] at `v_mps`: (machines off, most driving, most recovering).
    #[inline]
    pub fn wheel_torques_nm(&self, v_mps: f64) -> (f64, f64, f64) {
        let n = self.rpm_per_mps * v_mps;
        (self.wheel_drag.at(n), self.wheel_full.at(n), self.wheel_regen.at(n))
    }

    /// The wheel torque [Nm] the machines give under control `u` at `v_mps`, and whether they
    /// run (carry current): the pedal's torque, or the drag less what the brake recovers.
    #[inline]
    fn machine_wheel_nm(&self, v_mps: f64, u: Control) -> (f64, bool) {
        let (drag, full, regen) = self.wheel_torques_nm(v_mps);
        if u.gear != NEUTRAL && u.pedal > 0.0 {
            return (drag + u.pedal * (full - drag), true);
        }
        let recovered = (u.brake * self.brake_torque_max_nm).min(drag - regen);
        (drag - recovered, recovered > 0.0)
    }

    /// Where the power of control `u` at `v_mps` goes.
    pub fn power_flows(&self, v_mps: f64, u: Control) -> PowerFlows {
        let n = self.rpm_per_mps * v_mps;
        let omega = n / RPM_PER_RAD_S;
        let (wheel_nm, running) = self.machine_wheel_nm(v_mps, u);
        let (machine_nm, electric_w) = self.machines_at(n, wheel_nm, running);
        let aux_w = self.aux_power_w(running);
        let battery = self.truck.battery();
        let battery_w = battery.internal_power_w(electric_w + aux_w);
        let wheel_w = wheel_nm * v_mps / self.truck.wheel_radius_m();
        PowerFlows {
            battery_w,
            battery_loss_w: battery_w - electric_w - aux_w,
            aux_w,
            machine_loss_w: electric_w - machine_nm * omega,
            reduction_loss_w: machine_nm * omega - wheel_w,
            wheel_w,
            machine_rpm: n,
            machine_nm,
            running,
        }
    }

    /// Power drawn from the battery's store [W] under control `u` at `v_mps`.
    #[inline]
    pub fn battery_power_w(&self, v_mps: f64, u: Control) -> f64 {
        let (wheel_nm, running) = self.machine_wheel_nm(v_mps, u);
        let (_, electric_w) = self.machines_at(self.rpm_per_mps * v_mps, wheel_nm, running);
        self.truck.battery().internal_power_w(electric_w + self.aux_power_w(running))
    }

    /// The machines' torque [Nm] and electric power [W] at `n_rpm` giving the wheels `wheel_nm`
    /// (their drag's torque and no power while they are off).
    #[inline]
    fn machines_at(&self, n_rpm: f64, wheel_nm: f64, running: bool) -> (f64, f64) {
        let machine_nm = self.truck.machine_nm(n_rpm, wheel_nm);
        let electric_w =
            if running { machine_nm * n_rpm / RPM_PER_RAD_S + self.loss.at(n_rpm, machine_nm) } else { 0.0 };
        (machine_nm, electric_w)
    }

    /// The auxiliaries' electric power [W], with the machines' conditioning while they run.
    #[inline]
    fn aux_power_w(&self, running: bool) -> f64 {
        self.truck.body().aux_power_w + if running { self.truck.conditioning_w() } else { 0.0 }
    }
}

/// The machines' electric power's bounds [W] (most drawn, most returned ≤ 0) that keep the battery
/// within its current limits with the auxiliaries' `aux_w` on (conditioning included).
fn electric_limits(battery: &Battery, aux_w: f64) -> (f64, f64) {
    (battery.max_discharge_w() - aux_w, -battery.max_charge_w() - aux_w)
}

/// The torque nearest `limit` from `start` for which `ok` holds (`ok(start)` assumed), by
/// bisection: `limit` itself where it is ok.
fn limit_torque(ok: impl Fn(f64) -> bool, start: f64, limit: f64) -> f64 {
    if ok(limit) {
        return limit;
    }
    let (mut good, mut bad) = (start, limit);
    for _ in 0..BISECTION_STEPS {
        let mid = 0.5 * (good + bad);
        if ok(mid) {
            good = mid;
        } else {
            bad = mid;
        }
    }
    good
}

impl Powertrain for ElectricModel {
    fn forward_gears(&self) -> usize {
        1
    }

    /// The machines' speed: they turn with the wheels in either gear.
    #[inline]
    fn engine_speed_rpm(&self, v_mps: f64, _gear: usize) -> f64 {
        self.rpm_per_mps * v_mps
    }

    /// The machines drive from standstill; below half a metre per second the cruise has stopped.
    fn stall_speed_mps(&self) -> f64 {
        STOP_SPEED_MPS
    }

    fn traction_interruption_s(&self) -> f64 {
        0.0
    }

    /// Never interrupted (one gear); the auxiliaries' draw.
    fn interrupted_energy_rate(&self, v_mps: f64) -> f64 {
        self.battery_power_w(v_mps, Control { pedal: 0.0, brake: 0.0, gear: NEUTRAL })
    }

    /// m·g·r·(sin α + c_r cos α), α = arctan(grade), as for the map-based truck.
    #[inline]
    fn slope_torque_nm(&self, grade: f64) -> f64 {
        let alpha = grade.atan();
        self.weight_torque_nm * (alpha.sin() + self.truck.body().rolling_resistance * alpha.cos())
    }

    #[inline]
    fn pedal_affine(&self, v_mps: f64, _gear: usize, slope_torque_nm: f64) -> AffineAccel {
        let (drag, full, _) = self.wheel_torques_nm(v_mps);
        let load = self.air_torque_nm(v_mps) + slope_torque_nm;
        AffineAccel { accel_at_zero: self.c1 * (drag - load), gain: self.c1 * (full - drag) }
    }

    #[inline]
    fn brake_affine(&self, v_mps: f64, _gear: usize, slope_torque_nm: f64) -> AffineAccel {
        let (drag, _, _) = self.wheel_torques_nm(v_mps);
        let load = self.air_torque_nm(v_mps) + slope_torque_nm;
        AffineAccel { accel_at_zero: self.c1 * (drag - load), gain: -self.c1 * self.brake_torque_max_nm }
    }

    #[inline]
    fn accel_on(&self, v_mps: f64, pedal: f64, brake: f64, gear: usize, slope_torque_nm: f64) -> f64 {
        let (drag, full, _) = self.wheel_torques_nm(v_mps);
        let drive = if gear == NEUTRAL { drag } else { drag + pedal.max(0.0) * (full - drag) };
        let resist = self.brake_torque_max_nm * brake + self.air_torque_nm(v_mps) + slope_torque_nm;
        self.c1 * (drive - resist)
    }

    /// A central difference over ±0.1 mm/s (the wheel-torque tables are piecewise linear).
    fn accel_derivative_per_s(&self, v_mps: f64, pedal: f64, gear: usize) -> f64 {
        const DV_MPS: f64 = 1e-4;
        let at = |v: f64| self.accel_on(v, pedal, 0.0, gear, 0.0);
        (at(v_mps + DV_MPS) - at(v_mps - DV_MPS)) / (2.0 * DV_MPS)
    }

    /// Battery power [W]; negative while braking returns more than the auxiliaries take.
    #[inline]
    fn energy_rate(&self, v_mps: f64, u: Control) -> f64 {
        self.battery_power_w(v_mps, u)
    }

    /// What the machines do not take of the brake's force [N].
    #[inline]
    fn friction_brake_force_n(&self, v_mps: f64, u: Control) -> f64 {
        let (drag, _) = self.machine_wheel_nm(v_mps, Control { pedal: 0.0, ..u });
        let recovered = self.wheel_drag.at(self.rpm_per_mps * v_mps) - drag;
        (self.brake_torque_max_nm * u.brake - recovered).max(0.0) / self.truck.wheel_radius_m()
    }

    fn rate_form(&self) -> RateForm {
        RateForm::Map
    }

    /// Where the machines draw no electric power: they brake the truck less than their drag does
    /// while switched off, for no more than the conditioning. Between the drag and zero torque they
    /// generate what their losses take (above 10 km/h, where they recover).
    fn glide_pedal(&self, v_mps: f64, _gear: usize) -> Option<f64> {
        let glide = self.wheel_glide.at(self.rpm_per_mps * v_mps);
        let (drag, full, _) = self.wheel_torques_nm(v_mps);
        let pedal = (glide - drag) / (full - drag);
        (pedal > 0.0 && pedal < 1.0).then_some(pedal)
    }

    fn glides(&self) -> bool {
        true
    }

    /// At zero pedal the machines are off, as in the brake branch at zero brake.
    fn zero_pedal_is_cut(&self) -> bool {
        true
    }

    /// Braking returns energy to the battery.
    fn brake_draws_energy(&self) -> bool {
        true
    }

    fn thermal(&self) -> Option<Thermal> {
        self.truck.thermal()
    }

    /// One evaluation of the power flows: the battery's power (as [`Powertrain::energy_rate`]
    /// computes it, to the bit), the machines' loss while they run (VECTO heats the thermal buffer
    /// with nothing while they are off), the machines' and the battery's losses.
    fn rates_with_losses(&self, v_mps: f64, u: Control) -> [f64; 4] {
        let flows = self.power_flows(v_mps, u);
        let heating = if flows.running { flows.machine_loss_w } else { 0.0 };
        [flows.battery_w, heating, flows.machine_loss_w, flows.battery_loss_w]
    }

    /// The machines' torque: the pedal's, their drag at zero pedal or in neutral, less what the
    /// brake recovers.
    fn machine_torque_nm(&self, v_mps: f64, u: Control) -> f64 {
        let (wheel_nm, _) = self.machine_wheel_nm(v_mps, u);
        self.truck.machine_nm(self.rpm_per_mps * v_mps, wheel_nm)
    }

    /// The truck with its machines held to their continuous torque, both ways.
    fn derated(&self) -> Option<Self> {
        self.truck.derated().map(|truck| ElectricModel::new(truck, self.brake_torque_max_nm))
    }

    fn store(&self) -> EnergyStore {
        let battery = self.truck.battery();
        EnergyStore::Battery {
            capacity_j: battery.energy_per_soc_j(),
            soc_start: battery.soc,
            soc_min: battery.soc_window.0,
        }
    }
}

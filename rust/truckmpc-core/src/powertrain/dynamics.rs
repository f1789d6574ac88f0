//! A map-based truck in the form the plant and the controllers drive it: acceleration and fuel rate
//! over speed, pedal, brake, gear and slope, with the same units and conventions as the thesis's
//! model ([`super::thesis`]).
//!
//! **The pedal.** At a given engine speed the pedal P ∈ [0, 1] sets the torque at the wheels
//! between what the engine gives at fuel cut (its drag torque, less the auxiliaries, through the
//! driveline) and at full load: W(P) = W_cut + P·(W_full − W_cut). The acceleration is then affine
//! in the pedal at a fixed speed, as with the thesis's engine, so the controllers' pedal levels
//! from end speeds carry over unchanged; the fuel rate is the map's at the engine torque that
//! gives W(P), which is not affine in the pedal. Above the full-load curve's highest speed the
//! engine gives no more than its drag (the governor cuts fuel).
//!
//! **Inertia.** The engine's inertia is counted in the truck's effective mass in each gear (as the
//! thesis's model counts it), seen through the ratio without the driveline's losses.
//!
//! **Slope.** The road's grade Δh/ΔL is turned into the angle α = arctan(grade), as VECTO does.

use super::interface::{AffineAccel, Control, EnergyStore, Powertrain, RateForm, NEUTRAL};
use super::retarder::RetarderPosition;
use super::sampled::Sampled;
use super::{FuelGrid, MapTruck, G_MPS2, RPM_PER_RAD_S};

/// The truck's equations of motion and fuel rate, from its component data.
#[derive(Debug, Clone)]
pub struct MapModel {
    truck: MapTruck,
    brake_torque_max_nm: f64,
    traction_interruption_s: f64,
    grid: FuelGrid,
    /// Drag torque [Nm] over engine speed, resampled.
    drag: Sampled,
    /// Lowest engine speed the tables cover [rpm] (idle, or the curve's first point if lower).
    low_rpm: f64,
    /// Highest engine speed of the full-load curve [rpm].
    top_rpm: f64,
    /// Wheel torque [Nm] at fuel cut and at full load over engine speed, per gear (index 0 unused).
    wheel_range: Vec<(Sampled, Sampled)>,
    /// r / (I_wheels + m r² + I_engine·ratio²) per gear [1/(kg m)], index 0 neutral (no engine).
    c1: Vec<f64>,
    /// Engine speed per road speed [rpm/(m/s)] per gear, index 0 unused (0).
    rpm_per_mps: Vec<f64>,
    /// m g r [Nm]: gravity's torque at the wheel per unit sin α.
    weight_torque_nm: f64,
    /// Fuel rate [g/s] with the engine idling in neutral and driving the auxiliaries.
    idle_fuel_gps: f64,
    /// Wheel torque [Nm] in neutral over the gearbox output shaft's speed [rpm] and that speed per
    /// road speed [rpm/(m/s)]: the axle's and an output retarder's drag, where a loss map gives
    /// one (none: no drag in neutral).
    neutral: Option<(Sampled, f64)>,
}

impl MapModel {
    /// The model of `truck`, whose service brakes give at most `brake_torque_max_nm` at the wheels
    /// and whose gearbox interrupts traction for `traction_interruption_s` at each shift.
    pub fn new(truck: MapTruck, brake_torque_max_nm: f64, traction_interruption_s: f64) -> Self {
        let (engine, driveline, body) = (truck.engine(), truck.driveline(), truck.body());
        let r = driveline.wheel_radius_m();
        let base = body.wheels_inertia_kgm2 + body.mass_kg * r * r;
        let mut c1 = vec![r / base];
        let mut rpm_per_mps = vec![0.0];
        for gear in 1..=driveline.gears() {
            c1.push(r / (base + engine.inertia_kgm2() * driveline.ratio(gear).powi(2)));
            rpm_per_mps.push(driveline.engine_speed_rpm(1.0, gear));
        }
        let (lo, hi) = engine.speed_range_rpm();
        let (n_lo, n_hi) = (lo.min(engine.idle_rpm()), hi);
        let t_lo = engine.drag_torque_nm(n_lo).min(engine.drag_torque_nm(n_hi)).min(0.0);
        let t_hi = (0..=100).map(|k| engine.max_torque_nm(n_lo + (n_hi - n_lo) * k as f64 / 100.0)).fold(0.0, f64::max);
        let grid = FuelGrid::new(engine.fuel_map(), (n_lo, n_hi), (t_lo, t_hi));
        let idle = engine.idle_rpm();
        let idle_torque = body.aux_power_w / (idle / RPM_PER_RAD_S);
        let idle_fuel_gps = engine.fuel_rate_g_per_h(idle, idle_torque) / 3600.0;
        let weight_torque_nm = body.mass_kg * G_MPS2 * r;
        let (curves, speeds) = engine.curves();
        debug_assert!(curves.0.x_range() == speeds);
        let wheel_range = wheel_ranges(&truck, (n_lo, n_hi));
        let neutral = neutral_drag(&truck, hi / driveline.gear_ratios()[driveline.gears() - 1]);
        MapModel {
            neutral,
            drag: Sampled::new(curves.1, speeds),
            low_rpm: n_lo,
            top_rpm: hi,
            wheel_range,
            truck,
            brake_torque_max_nm,
            traction_interruption_s,
            grid,
            c1,
            rpm_per_mps,
            weight_torque_nm,
            idle_fuel_gps,
        }
    }

    /// The truck this model drives.
    pub fn truck(&self) -> &MapTruck {
        &self.truck
    }

    /// Brake torque at the wheels at full brake [Nm].
    pub fn brake_torque_max_nm(&self) -> f64 {
        self.brake_torque_max_nm
    }

    /// How long a gear shift interrupts traction [s].
    pub fn traction_interruption_s(&self) -> f64 {
        self.traction_interruption_s
    }

    /// r / effective inertia in `gear` (0 = neutral) [1/(kg m)]: acceleration per wheel torque.
    #[inline]
    pub fn c1(&self, gear: usize) -> f64 {
        self.c1[gear]
    }

    /// Engine speed per road speed in forward `gear` [rpm/(m/s)].
    #[inline]
    pub fn rpm_per_mps(&self, gear: usize) -> f64 {
        self.rpm_per_mps[gear]
    }

    /// Air drag torque at the wheel at `v_mps` [Nm]: ½ρ·CdA(v)·v²·r.
    #[inline]
    pub fn air_torque_nm(&self, v_mps: f64) -> f64 {
        let body = self.truck.body();
        0.5 * body.air_density_kgpm3
            * self.truck.cda_m2(v_mps)
            * v_mps
            * v_mps
            * self.truck.driveline().wheel_radius_m()
    }

    /// Gravity and rolling resistance at the wheel on grade `grade` (Δh/ΔL) [Nm]:
    /// m·g·r·(sin α + c_r cos α), α = arctan(grade).
    #[inline]
    pub fn slope_torque_nm(&self, grade: f64) -> f64 {
        let alpha = grade.atan();
        self.weight_torque_nm * (alpha.sin() + self.truck.body().rolling_resistance * alpha.cos())
    }

    /// Torque of the auxiliaries at the engine [Nm] at `n_rpm`, held below the tables' lowest
    /// speed as the wheel-torque tables are (so fuel cut stays at the drag torque there).
    #[inline]
    fn aux_torque_nm(&self, n_rpm: f64) -> f64 {
        self.truck.body().aux_power_w / (n_rpm.max(self.low_rpm) / RPM_PER_RAD_S)
    }

    /// Wheel torques [Nm] at fuel cut and at full load in forward `gear` at engine speed `n_rpm`:
    /// the engine's drag and full-load torque less the auxiliaries', through the driveline.
    #[inline]
    pub fn wheel_torque_range_nm(&self, n_rpm: f64, gear: usize) -> (f64, f64) {
        let (cut, full) = &self.wheel_range[gear];
        let cut = cut.at(n_rpm);
        if n_rpm > self.top_rpm {
            return (cut, cut);
        }
        (cut, full.at(n_rpm).max(cut))
    }

    /// Wheel torque [Nm] in neutral at `v_mps` (≤ 0): the drag of what turns with the wheels, the
    /// axle and a retarder on the gearbox's output shaft (0 where neither has a loss map).
    #[inline]
    pub fn neutral_wheel_torque_nm(&self, v_mps: f64) -> f64 {
        match &self.neutral {
            Some((drag, rpm_per_mps)) => drag.at(rpm_per_mps * v_mps),
            None => 0.0,
        }
    }

    /// Acceleration [m/s²] at `v_mps` with pedal, brake and gear (0 = neutral), on a slope given
    /// by its wheel torque [Nm].
    #[inline]
    pub fn accel_on(&self, v_mps: f64, pedal: f64, brake: f64, gear: usize, slope_torque_nm: f64) -> f64 {
        let resist = self.brake_torque_max_nm * brake + self.air_torque_nm(v_mps) + slope_torque_nm;
        if gear == 0 {
            return match &self.neutral {
                None => -self.c1[0] * resist,
                Some(_) => self.c1[0] * (self.neutral_wheel_torque_nm(v_mps) - resist),
            };
        }
        let (cut, full) = self.wheel_torque_range_nm(self.rpm_per_mps[gear] * v_mps, gear);
        self.c1[gear] * (cut + pedal.max(0.0) * (full - cut) - resist)
    }

    /// The acceleration [m/s²] as an affine function of the pedal at `v_mps` in forward `gear`
    /// (brake off), on a slope given by its wheel torque [Nm]: (acceleration at fuel cut, gain per
    /// unit of pedal), the form [`MapModel::accel_on`] evaluates.
    #[inline]
    pub fn pedal_affine(&self, v_mps: f64, gear: usize, slope_torque_nm: f64) -> (f64, f64) {
        let (cut, full) = self.wheel_torque_range_nm(self.rpm_per_mps[gear] * v_mps, gear);
        let load = self.air_torque_nm(v_mps) + slope_torque_nm;
        (self.c1[gear] * (cut - load), self.c1[gear] * (full - cut))
    }

    /// The acceleration [m/s²] as an affine function of the brake at fuel cut (or in neutral,
    /// `gear` 0): (acceleration without brake, gain per unit of brake).
    #[inline]
    pub fn brake_affine(&self, v_mps: f64, gear: usize, slope_torque_nm: f64) -> (f64, f64) {
        let cut = if gear == 0 {
            self.neutral_wheel_torque_nm(v_mps)
        } else {
            self.wheel_torque_range_nm(self.rpm_per_mps[gear] * v_mps, gear).0
        };
        let load = self.air_torque_nm(v_mps) + slope_torque_nm;
        (self.c1[gear] * (cut - load), -self.c1[gear] * self.brake_torque_max_nm)
    }

    /// Engine torque [Nm] at `v_mps` with `pedal` in forward `gear`: the one that gives the wheels
    /// W(P), with the auxiliaries' share.
    #[inline]
    pub fn engine_torque_nm(&self, v_mps: f64, pedal: f64, gear: usize) -> f64 {
        self.engine_torque_at(self.rpm_per_mps[gear] * v_mps, pedal, gear)
    }

    /// [`MapModel::engine_torque_nm`] at engine speed `n_rpm`.
    #[inline]
    fn engine_torque_at(&self, n_rpm: f64, pedal: f64, gear: usize) -> f64 {
        let (cut, full) = self.wheel_torque_range_nm(n_rpm, gear);
        let wheel = cut + pedal.max(0.0) * (full - cut);
        self.truck.driveline().engine_torque_nm(wheel, gear, n_rpm) + self.aux_torque_nm(n_rpm)
    }

    /// Fuel rate [g/s]: idling in neutral; zero at fuel cut (pedal ≤ 0); else the map's at the
    /// engine speed and torque.
    #[inline]
    pub fn fuel_rate_gps(&self, v_mps: f64, pedal: f64, gear: usize) -> f64 {
        if gear == 0 {
            return self.idle_fuel_gps;
        }
        if pedal <= 0.0 {
            return 0.0;
        }
        let n = self.rpm_per_mps[gear] * v_mps;
        if n > self.top_rpm {
            return 0.0; // above its full-load curve the engine only drags (the governor cuts fuel)
        }
        let torque = self.engine_torque_at(n, pedal, gear);
        if torque <= self.drag.at(n) {
            return 0.0;
        }
        self.grid.at(n, torque) / 3600.0
    }

    /// Fuel rate [g/h] from the resampled map at `n_rpm` and `torque_nm` (no cut at the drag curve).
    pub fn grid_fuel_g_per_h(&self, n_rpm: f64, torque_nm: f64) -> f64 {
        self.grid.at(n_rpm, torque_nm)
    }
}

impl Powertrain for MapModel {
    fn forward_gears(&self) -> usize {
        self.rpm_per_mps.len() - 1
    }

    #[inline]
    fn engine_speed_rpm(&self, v_mps: f64, gear: usize) -> f64 {
        if gear == NEUTRAL {
            self.truck.engine().idle_rpm()
        } else {
            self.rpm_per_mps[gear] * v_mps
        }
    }

    /// The speed at which the lowest gear turns the engine at idle (no clutch slip is modelled).
    fn stall_speed_mps(&self) -> f64 {
        self.truck.engine().idle_rpm() / self.rpm_per_mps[1]
    }

    #[inline]
    fn traction_interruption_s(&self) -> f64 {
        self.traction_interruption_s
    }

    /// Zero: the engine is at fuel cut while the gearbox shifts.
    #[inline]
    fn interrupted_energy_rate(&self, _v_mps: f64) -> f64 {
        0.0
    }

    #[inline]
    fn slope_torque_nm(&self, grade: f64) -> f64 {
        MapModel::slope_torque_nm(self, grade)
    }

    #[inline]
    fn pedal_affine(&self, v_mps: f64, gear: usize, slope_torque_nm: f64) -> AffineAccel {
        let (accel_at_zero, gain) = MapModel::pedal_affine(self, v_mps, gear, slope_torque_nm);
        AffineAccel { accel_at_zero, gain }
    }

    #[inline]
    fn brake_affine(&self, v_mps: f64, gear: usize, slope_torque_nm: f64) -> AffineAccel {
        let (accel_at_zero, gain) = MapModel::brake_affine(self, v_mps, gear, slope_torque_nm);
        AffineAccel { accel_at_zero, gain }
    }

    #[inline]
    fn accel_on(&self, v_mps: f64, pedal: f64, brake: f64, gear: usize, slope_torque_nm: f64) -> f64 {
        MapModel::accel_on(self, v_mps, pedal, brake, gear, slope_torque_nm)
    }

    /// A central difference over ±0.1 mm/s (the wheel-torque tables are piecewise linear).
    fn accel_derivative_per_s(&self, v_mps: f64, pedal: f64, gear: usize) -> f64 {
        const DV_MPS: f64 = 1e-4;
        let at = |v: f64| MapModel::accel_on(self, v, pedal, 0.0, gear, 0.0);
        (at(v_mps + DV_MPS) - at(v_mps - DV_MPS)) / (2.0 * DV_MPS)
    }

    /// Fuel [g/s]; the brakes take nothing back.
    #[inline]
    fn energy_rate(&self, v_mps: f64, u: Control) -> f64 {
        self.fuel_rate_gps(v_mps, u.pedal, u.gear)
    }

    #[inline]
    fn friction_brake_force_n(&self, _v_mps: f64, u: Control) -> f64 {
        self.brake_torque_max_nm * u.brake / self.truck.driveline().wheel_radius_m()
    }

    fn rate_form(&self) -> RateForm {
        RateForm::Map
    }

    /// At zero pedal the engine gives its drag, as at fuel cut.
    fn zero_pedal_is_cut(&self) -> bool {
        true
    }

    fn store(&self) -> EnergyStore {
        EnergyStore::FuelTank
    }
}

/// The wheel torque [Nm] in neutral over the gearbox output shaft's speed up to `top_rpm`, and
/// that speed per road speed [rpm/(m/s)]; none where nothing turning with the wheels drags (no
/// axle loss map and no retarder on the gearbox's output).
fn neutral_drag(truck: &MapTruck, top_rpm: f64) -> Option<(Sampled, f64)> {
    let driveline = truck.driveline();
    let output_retarder = driveline.retarder().is_some_and(|r| r.position() == RetarderPosition::GearboxOutput);
    if !(driveline.has_loss_maps().1 || output_retarder) {
        return None;
    }
    let rpm_per_mps = driveline.axle_ratio() / driveline.wheel_radius_m() * RPM_PER_RAD_S;
    let drag = Sampled::from_fn((0.0, top_rpm), |n| driveline.neutral_wheel_torque_nm(n / rpm_per_mps));
    Some((drag, rpm_per_mps))
}

/// Per gear (index 0 unused), the wheel torque [Nm] over engine speed in `range_rpm` at fuel cut
/// and at full load: the engine's drag and full-load torque less the auxiliaries', through the
/// driveline (whose loss maps would otherwise be inverted at every look-up).
fn wheel_ranges(truck: &MapTruck, range_rpm: (f64, f64)) -> Vec<(Sampled, Sampled)> {
    let (engine, driveline, aux_w) = (truck.engine(), truck.driveline(), truck.body().aux_power_w);
    let wheel = |torque: &dyn Fn(f64) -> f64, gear: usize| {
        Sampled::from_fn(range_rpm, |n| driveline.wheel_torque_nm(torque(n) - aux_w / (n / RPM_PER_RAD_S), gear, n))
    };
    let mut out = vec![(Sampled::zero(), Sampled::zero())];
    for gear in 1..=driveline.gears() {
        out.push((wheel(&|n| engine.drag_torque_nm(n), gear), wheel(&|n| engine.max_torque_nm(n), gear)));
    }
    out
}

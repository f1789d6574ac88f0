//! The electric machines at the axle (VECTO's position E4), as VECTO models them from a
//! declaration: `count` alike machines on one shaft, each measured at one or more voltages.
//!
//! - **Count.** The file describes one machine; torques, electric powers and inertia scale with
//!   the count, speeds do not (VECTO's data adapter multiplies them when it reads the file).
//! - **Voltage levels.** The torque limits and the power map are interpolated linearly between
//!   the two levels around the battery's voltage, and held at the nearer level outside them.
//! - **Power map.** VECTO turns each measured point into a loss torque, (electric power less
//!   mechanical power) / angular speed, triangulates the points (Delaunay, as for an engine's fuel
//!   map) and interpolates the loss torque linearly on the triangles; the electric power is then
//!   ω·(torque + loss torque). A point at standstill has no loss torque and is left out; below the
//!   lowest measured speed the loss torque is held at its nearest measured value.
//! - **Drag.** A machine turning without current takes its drag torque (≤ 0), linear in speed.
//!
//! Torques are at the machines' shaft [Nm], positive driving the truck; speeds in rpm; powers in
//! W, the electric power positive when the machines draw from the battery.

use crate::powertrain::thermal::{OverloadRating, Thermal};
use crate::powertrain::{Curve, FuelMap, RPM_PER_RAD_S};
use crate::{CoreError, CoreResult};

/// One machine measured at one voltage.
#[derive(Debug, Clone)]
pub struct VoltageLevel {
    voltage_v: f64,
    /// Most driving torque [Nm] over speed.
    drive: Curve,
    /// Most braking torque [Nm] (≤ 0) over speed.
    brake: Curve,
    /// Loss torque [Nm] (electric power less mechanical power, over ω) over (speed, torque).
    loss: FuelMap,
    /// The continuous and overload rating; none: the machine never derates.
    rating: Option<OverloadRating>,
}

impl VoltageLevel {
    /// The level at `voltage_v` from `torque_limits` (speed [rpm], most driving torque [Nm], most
    /// braking torque [Nm] ≤ 0) and `power_map` (speed [rpm], torque [Nm], electric power [W]);
    /// `key` names the level in errors.
    pub fn new(
        key: &str,
        voltage_v: f64,
        torque_limits: &[(f64, f64, f64)],
        power_map: &[(f64, f64, f64)],
    ) -> CoreResult<Self> {
        if !(voltage_v.is_finite() && voltage_v > 0.0) {
            return Err(CoreError::invalid(&format!("{key}.voltage_v"), "a voltage > 0 [V]").got(voltage_v));
        }
        if let Some(&(n, d, b)) = torque_limits.iter().find(|&&(_, d, b)| !(d >= 0.0 && b <= 0.0)) {
            let expected = "a driving torque >= 0 and a braking torque <= 0 at every speed";
            return Err(
                CoreError::invalid(&format!("{key}.torque_limits"), expected).got(format!("{d}, {b} Nm at {n} rpm"))
            );
        }
        let column = |f: fn(&(f64, f64, f64)) -> f64| torque_limits.iter().map(|p| (p.0, f(p))).collect::<Vec<_>>();
        let drive = Curve::new(&format!("{key}.torque_limits"), &column(|p| p.1))?;
        let brake = Curve::new(&format!("{key}.torque_limits"), &column(|p| p.2))?;
        let moving = power_map.iter().filter(|p| p.0 > 0.0);
        let loss_points: Vec<_> = moving.map(|&(n, t, p)| (n, t, p * RPM_PER_RAD_S / n - t)).collect();
        let loss = FuelMap::signed(&format!("{key}.power_map"), &loss_points)?;
        Ok(VoltageLevel { voltage_v, drive, brake, loss, rating: None })
    }

    /// This level rated `rating`, checked: torques and speeds > 0, a time >= 0 (a zero time: no
    /// buffer), the overload torque at least the continuous one (`key` names it).
    pub fn with_rating(self, key: &str, rating: OverloadRating) -> CoreResult<Self> {
        let r = rating;
        let positive = [r.continuous_torque_nm, r.continuous_speed_rpm, r.overload_torque_nm, r.overload_speed_rpm];
        let key = format!("{key}.rating");
        if let Some(bad) = positive.into_iter().find(|v| !(v.is_finite() && *v > 0.0)) {
            return Err(CoreError::invalid(&key, "torques and speeds > 0").got(bad));
        }
        if !(r.overload_duration_s.is_finite() && r.overload_duration_s >= 0.0) {
            return Err(CoreError::invalid(&key, "an overload duration >= 0 [s]").got(r.overload_duration_s));
        }
        if r.overload_torque_nm < r.continuous_torque_nm {
            let expected = format!("an overload torque >= the continuous torque ({} Nm)", r.continuous_torque_nm);
            return Err(CoreError::invalid(&key, &expected).got(r.overload_torque_nm));
        }
        Ok(VoltageLevel { rating: Some(rating), ..self })
    }

    /// One machine's loss [W] at `n_rpm` with `torque_nm`, on this level's map.
    fn loss_w(&self, n_rpm: f64, torque_nm: f64) -> f64 {
        n_rpm / RPM_PER_RAD_S * self.loss.extrapolate(n_rpm, torque_nm)
    }
}

/// `count` alike machines on one shaft, their levels blended at one battery voltage.
#[derive(Debug, Clone)]
pub struct Machines {
    count: f64,
    inertia_kgm2: f64,
    /// The levels around the voltage and the weight of the upper one: (lower, upper, weight).
    levels: (VoltageLevel, VoltageLevel, f64),
    drag: Curve,
    top_rpm: f64,
    /// Torque both ways held to this [Nm] (derated); none: the limits as rated.
    cap_nm: Option<f64>,
}

impl Machines {
    /// `count` machines of `inertia_kgm2` each, with `levels` (voltage rising) and `drag` (speed
    /// [rpm], drag torque [Nm] ≤ 0), run at battery voltage `voltage_v`.
    pub fn new(
        count: usize,
        inertia_kgm2: f64,
        levels: Vec<VoltageLevel>,
        drag: &[(f64, f64)],
        voltage_v: f64,
    ) -> CoreResult<Self> {
        if count == 0 {
            return Err(CoreError::invalid("machine.count", "at least one machine").got(count));
        }
        if !(inertia_kgm2.is_finite() && inertia_kgm2 >= 0.0) {
            return Err(CoreError::invalid("machine.inertia_kgm2", "a number >= 0").got(inertia_kgm2));
        }
        if let Some(&(n, t)) = drag.iter().find(|p| !(p.1 <= 0.0)) {
            return Err(CoreError::invalid("machine.drag_curve", "a drag torque <= 0 at every speed")
                .got(format!("{t} Nm at {n} rpm")));
        }
        let drag = Curve::new("machine.drag_curve", drag)?;
        let levels = blend(levels, voltage_v)?;
        let top_rpm = levels.0.drive.x_range().1.min(levels.1.drive.x_range().1);
        Ok(Machines { count: count as f64, inertia_kgm2, levels, drag, top_rpm, cap_nm: None })
    }

    /// The machines' thermal limits at the battery's voltage ([`Thermal`], blended as the maps
    /// are); none unless both levels are rated.
    pub fn thermal(&self) -> Option<Thermal> {
        let (lower, upper, _) = &self.levels;
        let of = |level: &VoltageLevel| {
            level.rating.map(|rating| Thermal::of(&rating, self.count, |n, t| level.loss_w(n, t)))
        };
        let (low, high) = (of(lower)?, of(upper)?);
        let field = |f: fn(&Thermal) -> f64| self.blended(f(&low), f(&high));
        Some(Thermal {
            buffer_j: field(|t| t.buffer_j),
            continuous_loss_w: field(|t| t.continuous_loss_w),
            continuous_nm: field(|t| t.continuous_nm),
        })
    }

    /// These machines with their driving and braking torque held to `cap_nm` [Nm, all machines].
    pub fn derated(&self, cap_nm: f64) -> Self {
        Machines { cap_nm: Some(cap_nm), ..self.clone() }
    }

    /// Rotor inertia of all the machines [kg m²].
    pub fn inertia_kgm2(&self) -> f64 {
        self.count * self.inertia_kgm2
    }

    /// Highest speed the torque limits cover [rpm]: above it the machines give no driving torque.
    pub fn top_rpm(&self) -> f64 {
        self.top_rpm
    }

    /// Most driving torque of all the machines at `n_rpm` [Nm]; none above the top speed.
    pub fn max_drive_nm(&self, n_rpm: f64) -> f64 {
        if n_rpm > self.top_rpm {
            return 0.0;
        }
        let rated = self.count * self.mix(|l| l.drive.at(n_rpm));
        self.cap_nm.map_or(rated, |cap| rated.min(cap))
    }

    /// Most braking torque of all the machines at `n_rpm` [Nm, ≤ 0].
    pub fn max_brake_nm(&self, n_rpm: f64) -> f64 {
        let rated = self.count * self.mix(|l| l.brake.at(n_rpm));
        self.cap_nm.map_or(rated, |cap| rated.max(-cap))
    }

    /// Drag torque of all the machines turning without current at `n_rpm` [Nm, ≤ 0].
    pub fn drag_nm(&self, n_rpm: f64) -> f64 {
        self.count * self.drag.at(n_rpm)
    }

    /// Loss of all the machines [W] at `n_rpm` with `torque_nm` between them, from the maps'
    /// triangulation (at the nearest boundary point outside it).
    pub fn loss_w(&self, n_rpm: f64, torque_nm: f64) -> f64 {
        let per_machine = torque_nm / self.count;
        self.count * n_rpm / RPM_PER_RAD_S * self.mix(|l| l.loss.extrapolate(n_rpm, per_machine))
    }

    /// Electric power all the machines draw [W] at `n_rpm` with `torque_nm` (negative: returned).
    pub fn electric_power_w(&self, n_rpm: f64, torque_nm: f64) -> f64 {
        torque_nm * n_rpm / RPM_PER_RAD_S + self.loss_w(n_rpm, torque_nm)
    }

    /// The speed and torque ranges of the power maps, for resampling: ((lowest, highest) rpm,
    /// (lowest, highest) Nm of all the machines).
    pub fn map_range(&self) -> ((f64, f64), (f64, f64)) {
        let (a, b) = (&self.levels.0.loss, &self.levels.1.loss);
        let speed =
            (a.speed_range_rpm().0.min(b.speed_range_rpm().0), a.speed_range_rpm().1.max(b.speed_range_rpm().1));
        let torque =
            (a.torque_range_nm().0.min(b.torque_range_nm().0), a.torque_range_nm().1.max(b.torque_range_nm().1));
        (speed, (self.count * torque.0, self.count * torque.1))
    }

    /// `f` of the two levels, blended by the voltage's weight.
    #[inline]
    fn mix(&self, f: impl Fn(&VoltageLevel) -> f64) -> f64 {
        let (lower, upper, w) = &self.levels;
        if *w == 0.0 {
            return f(lower);
        }
        self.blended(f(lower), f(upper))
    }

    /// A figure of the lower and of the upper level, blended by the voltage's weight.
    #[inline]
    fn blended(&self, lower: f64, upper: f64) -> f64 {
        let w = self.levels.2;
        if w == 0.0 {
            return lower;
        }
        (1.0 - w) * lower + w * upper
    }
}

/// The two levels around `voltage_v` and the upper one's weight, held at the nearer level outside
/// them (one level: itself twice, weight 0).
fn blend(mut levels: Vec<VoltageLevel>, voltage_v: f64) -> CoreResult<(VoltageLevel, VoltageLevel, f64)> {
    if levels.is_empty() {
        return Err(CoreError::invalid("machine.voltage_levels", "at least one voltage level").got(0));
    }
    if levels.windows(2).any(|w| w[1].voltage_v <= w[0].voltage_v) {
        return Err(CoreError::invalid("machine.voltage_levels", "voltages strictly rising").got(levels.len()));
    }
    let above =
        levels.iter().position(|l| l.voltage_v >= voltage_v).unwrap_or(levels.len() - 1).max(1).min(levels.len() - 1);
    if levels.len() == 1 {
        let only = levels.remove(0);
        return Ok((only.clone(), only, 0.0));
    }
    let upper = levels.remove(above);
    let lower = levels.remove(above - 1);
    let w = ((voltage_v - lower.voltage_v) / (upper.voltage_v - lower.voltage_v)).clamp(0.0, 1.0);
    Ok((lower, upper, w))
}

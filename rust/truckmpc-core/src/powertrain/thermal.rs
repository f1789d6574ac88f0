//! Thermal de-rating, as VECTO models it for electric machines: the machines may run above their
//! continuous rating until the extra heat fills a buffer, then hold their continuous torque until
//! it has cooled to 90 % of the buffer.
//!
//! A declaration rates each machine at each voltage with a continuous torque at a speed and an
//! overload torque held for a time at a speed. VECTO (`ElectricMotor` and its data adapter's
//! overload data) turns these into:
//!
//! - the **continuous loss** [W]: the machines' loss driving at the continuous torque and speed;
//! - the **buffer** [J]: (loss at the overload torque and speed − continuous loss) × the overload
//!   time;
//!
//! each computed at both voltage levels around the battery's voltage and blended as the maps are
//! (`Machines::thermal`).
//! While it drives, a run adds (loss − continuous loss)·dt to the buffer's content (never below
//! zero; zero loss while the machines are off). Once the content exceeds the buffer the machines
//! derate: their driving and their braking torque are held to the continuous torque, until the
//! content falls to 90 % of the buffer.

/// Share of the buffer the content must fall to before the machines leave de-rating (VECTO's
/// overload recovery factor).
pub const RECOVERY: f64 = 0.9;

/// One machine's thermal rating at one voltage, as the declaration gives it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OverloadRating {
    /// Torque held indefinitely [Nm], measured at `continuous_speed_rpm`.
    pub continuous_torque_nm: f64,
    pub continuous_speed_rpm: f64,
    /// Torque held for `overload_duration_s` [Nm], measured at `overload_speed_rpm`.
    pub overload_torque_nm: f64,
    pub overload_speed_rpm: f64,
    pub overload_duration_s: f64,
}

/// A drive's thermal limits, all its machines together.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Thermal {
    /// Heat the machines may store above their continuous loss before they derate [J].
    pub buffer_j: f64,
    /// Loss at the continuous rating [W].
    pub continuous_loss_w: f64,
    /// Torque the machines hold while derated [Nm].
    pub continuous_nm: f64,
}

impl Thermal {
    /// The limits of `count` machines rated `rating`, whose loss [W] at (speed [rpm], one
    /// machine's torque [Nm]) is `loss_w` for one machine.
    pub fn of(rating: &OverloadRating, count: f64, loss_w: impl Fn(f64, f64) -> f64) -> Self {
        let continuous_loss_w = count * loss_w(rating.continuous_speed_rpm, rating.continuous_torque_nm);
        let peak_loss_w = count * loss_w(rating.overload_speed_rpm, rating.overload_torque_nm);
        Thermal {
            buffer_j: (peak_loss_w - continuous_loss_w) * rating.overload_duration_s,
            continuous_loss_w,
            continuous_nm: count * rating.continuous_torque_nm,
        }
    }
}

/// The buffer's content over a run and whether the machines are derated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThermalState {
    pub limits: Thermal,
    /// Heat stored above the continuous loss [J].
    pub content_j: f64,
    pub derated: bool,
    /// Time spent derated where the continuous torque is below the rated limits [s] (above the
    /// speed where the machines' rated torque falls below it, de-rating changes nothing).
    pub derated_s: f64,
}

impl ThermalState {
    /// A cool start: nothing stored.
    pub fn new(limits: Thermal) -> Self {
        ThermalState { limits, content_j: 0.0, derated: false, derated_s: 0.0 }
    }

    /// After `dt_s` in which the machines lost `loss_j` [J]: the content, the time derated where
    /// that `binds` (in the state the step ran in), and the switch into or out of de-rating as
    /// VECTO commits a step.
    pub fn commit(&mut self, loss_j: f64, dt_s: f64, binds: bool) {
        let limits = self.limits;
        if self.derated && binds {
            self.derated_s += dt_s;
        }
        self.content_j = (self.content_j + loss_j - limits.continuous_loss_w * dt_s).max(0.0);
        self.derated =
            if self.derated { self.content_j > limits.buffer_j * RECOVERY } else { self.content_j > limits.buffer_j };
    }
}

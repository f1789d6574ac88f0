//! The traction battery as VECTO models it from a declaration, at one state of charge.
//!
//! - **Open-circuit voltage** U over the state of charge, linear between the file's points.
//! - **Internal resistance** R over the state of charge, given in mΩ for current pulses of 2, 10
//!   and 20 s. A cruise draws current one way for far longer than 20 s, so the 20 s value applies.
//! - **Power.** Drawing current I (positive discharging) gives the terminals P = U·I − R·I²; the
//!   battery's own energy changes by U·I and R·I² is its loss. Charging is the same with I < 0.
//! - **Current limits** over the state of charge bound the current both ways, and so the power.
//! - **Usable window.** Declaration mode keeps the declared SOCmin–SOCmax within 5–95 % and then
//!   narrows it by 5 % of its width for ageing, half at each end (8–92 % becomes 10.1–89.9 %). A
//!   declaration run starts in the middle of that window.
//! - **State of charge.** VECTO holds it for a declaration run (it computes the range afterwards
//!   from the usable energy); the model does the same for its voltage, resistance and limits, and
//!   the plant integrates the charge drawn to report the state of charge and end a trip the usable
//!   charge cannot finish.
//!
//! States of charge are fractions [0–1]; voltages in V, currents in A, powers in W.

use crate::powertrain::Curve;
use crate::{CoreError, CoreResult};

/// The generic window a declared one is kept within [%] (VECTO's generic limits for a
/// battery-electric truck).
pub const GENERIC_SOC_WINDOW_PCT: (f64, f64) = (5.0, 95.0);

/// The share of the window's width declaration mode takes off for ageing, half at each end.
pub const DETERIORATION: f64 = 0.05;

/// A battery's data, as a file gives it.
#[derive(Debug, Clone, PartialEq)]
pub struct BatteryData {
    /// Rated capacity [Ah].
    pub capacity_ah: f64,
    /// (state of charge [%], open-circuit voltage [V]) rows.
    pub ocv: Vec<(f64, f64)>,
    /// (state of charge [%], internal resistance for a 20 s pulse [mΩ]) rows.
    pub resistance_mohm: Vec<(f64, f64)>,
    /// (state of charge [%], most charging current [A], most discharging current [A]) rows.
    pub current_limits: Vec<(f64, f64, f64)>,
    /// The declared usable window's ends, SOCmin and SOCmax [%].
    pub soc_window_pct: (f64, f64),
}

/// The battery at one state of charge.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Battery {
    /// Rated capacity [C].
    pub capacity_c: f64,
    /// Open-circuit voltage [V].
    pub ocv_v: f64,
    /// Internal resistance [Ω].
    pub resistance_ohm: f64,
    /// Most charging current [A, > 0].
    pub charge_current_a: f64,
    /// Most discharging current [A, > 0].
    pub discharge_current_a: f64,
    /// The usable window as declaration mode applies it [0–1].
    pub soc_window: (f64, f64),
    /// The state of charge it is held at [0–1].
    pub soc: f64,
}

impl BatteryData {
    /// The usable window as declaration mode applies it [%]: the declared one kept within
    /// [`GENERIC_SOC_WINDOW_PCT`] and narrowed by [`DETERIORATION`] of its width.
    pub fn usable_window_pct(&self) -> (f64, f64) {
        let (lo, hi) = self.soc_window_pct;
        let lo = if lo > GENERIC_SOC_WINDOW_PCT.0 { lo } else { GENERIC_SOC_WINDOW_PCT.0 };
        let hi = if hi < GENERIC_SOC_WINDOW_PCT.1 && hi > lo { hi } else { GENERIC_SOC_WINDOW_PCT.1 };
        let margin = 0.5 * DETERIORATION * (hi - lo);
        (lo + margin, hi - margin)
    }

    /// The state of charge a declaration run starts from [%]: the middle of the usable window.
    pub fn declared_start_pct(&self) -> f64 {
        let (lo, hi) = self.usable_window_pct();
        0.5 * (lo + hi)
    }

    /// The battery held at state of charge `soc` [0–1], which must lie in the usable window;
    /// errors name the key at fault.
    pub fn at(&self, soc: f64) -> CoreResult<Battery> {
        let (lo, hi) = self.soc_window_pct;
        if !(0.0 <= lo && lo < hi && hi <= 100.0) {
            return Err(
                CoreError::invalid("battery.soc_window_pct", "0 <= SOCmin < SOCmax <= 100").got(format!("{lo}–{hi} %"))
            );
        }
        if !(self.capacity_ah.is_finite() && self.capacity_ah > 0.0) {
            return Err(CoreError::invalid("battery.capacity_ah", "a capacity > 0 [Ah]").got(self.capacity_ah));
        }
        let (lo, hi) = self.usable_window_pct();
        let window = (lo / 100.0, hi / 100.0);
        if !(window.0..=window.1).contains(&soc) {
            let expected = format!("a state of charge in the usable window {lo:.1}–{hi:.1} %");
            return Err(CoreError::invalid("soc_start_pct", expected).got(100.0 * soc));
        }
        let pct = 100.0 * soc;
        let positive = |key: &str, points: &[(f64, f64)]| -> CoreResult<f64> {
            let value = Curve::new(key, points)?.at(pct);
            if !(value.is_finite() && value > 0.0) {
                return Err(CoreError::invalid(key, format!("a value > 0 at {pct:.1} %")).got(value));
            }
            Ok(value)
        };
        let limits =
            |f: fn(&(f64, f64, f64)) -> f64| self.current_limits.iter().map(|p| (p.0, f(p).abs())).collect::<Vec<_>>();
        Ok(Battery {
            capacity_c: self.capacity_ah * 3600.0,
            ocv_v: positive("battery.ocv", &self.ocv)?,
            resistance_ohm: positive("battery.resistance_mohm", &self.resistance_mohm)? / 1000.0,
            charge_current_a: positive("battery.current_limits", &limits(|p| p.1))?,
            discharge_current_a: positive("battery.current_limits", &limits(|p| p.2))?,
            soc_window: window,
            soc,
        })
    }
}

impl Battery {
    /// The current [A] that gives `terminal_w` at the terminals (positive discharging): the root
    /// of R·I² − U·I + P = 0 nearer zero. NaN beyond the most the battery can give.
    #[inline]
    pub fn current_a(&self, terminal_w: f64) -> f64 {
        let (u, r) = (self.ocv_v, self.resistance_ohm);
        let disc = u * u - 4.0 * r * terminal_w;
        // (U − √D)/(2R) loses digits for a small P; the product of the roots gives it exactly.
        2.0 * terminal_w / (u + disc.sqrt())
    }

    /// Power drawn from the battery's store [W] to give `terminal_w` at the terminals: U·I.
    #[inline]
    pub fn internal_power_w(&self, terminal_w: f64) -> f64 {
        self.ocv_v * self.current_a(terminal_w)
    }

    /// Most power the terminals give [W] at the discharging current limit (or where the
    /// terminal power peaks, at I = U/2R, if that is lower).
    pub fn max_discharge_w(&self) -> f64 {
        let i = self.discharge_current_a.min(self.ocv_v / (2.0 * self.resistance_ohm));
        self.ocv_v * i - self.resistance_ohm * i * i
    }

    /// Most power the terminals take [W, > 0] at the charging current limit.
    pub fn max_charge_w(&self) -> f64 {
        let i = self.charge_current_a;
        self.ocv_v * i + self.resistance_ohm * i * i
    }

    /// The energy [J] the store holds per unit of state of charge at the held voltage.
    pub fn energy_per_soc_j(&self) -> f64 {
        self.capacity_c * self.ocv_v
    }
}

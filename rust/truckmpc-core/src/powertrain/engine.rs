//! An engine described by its maps: full-load and drag (motoring) torque over engine speed, and the
//! fuel rate over engine speed and torque.

use super::{Curve, FuelMap, RPM_PER_RAD_S};
use crate::{CoreError, CoreResult};

/// A map-based combustion engine.
#[derive(Debug, Clone)]
pub struct Engine {
    idle_rpm: f64,
    inertia_kgm2: f64,
    full_load: Curve,
    drag: Curve,
    fuel: FuelMap,
}

impl Engine {
    /// An engine from its idle speed [rpm], rotating inertia [kg m²], full-load curve as
    /// `(speed [rpm], full-load torque [Nm], drag torque [Nm])` points and fuel map as
    /// `(speed [rpm], torque [Nm], fuel [g/h])` points.
    pub fn new(
        idle_rpm: f64,
        inertia_kgm2: f64,
        full_load: &[(f64, f64, f64)],
        fuel_map: &[(f64, f64, f64)],
    ) -> CoreResult<Self> {
        if !(idle_rpm.is_finite() && idle_rpm > 0.0) {
            return Err(CoreError::invalid("idle_speed_rpm", "a number > 0").got(idle_rpm));
        }
        if !(inertia_kgm2.is_finite() && inertia_kgm2 >= 0.0) {
            return Err(CoreError::invalid("engine_inertia_kgm2", "a number >= 0").got(inertia_kgm2));
        }
        let max: Vec<(f64, f64)> = full_load.iter().map(|&(n, t, _)| (n, t)).collect();
        let drag: Vec<(f64, f64)> = full_load.iter().map(|&(n, _, d)| (n, d)).collect();
        let full_load_curve = Curve::new("full_load_curve", &max)?;
        if let Some((i, &(n, t, d))) = full_load.iter().enumerate().find(|(_, p)| p.2 > p.1) {
            return Err(CoreError::invalid(
                "full_load_curve",
                format!("drag torque <= full-load torque at point {}", i + 1),
            )
            .got(format!("{d} > {t} Nm at {n} rpm")));
        }
        Ok(Engine {
            idle_rpm,
            inertia_kgm2,
            full_load: full_load_curve,
            drag: Curve::new("full_load_curve", &drag)?,
            fuel: FuelMap::new("fuel_map", fuel_map)?,
        })
    }

    /// Idle speed [rpm].
    pub fn idle_rpm(&self) -> f64 {
        self.idle_rpm
    }

    /// Rotating inertia of the engine [kg m²].
    pub fn inertia_kgm2(&self) -> f64 {
        self.inertia_kgm2
    }

    /// Full-load (maximum) torque [Nm] at `speed_rpm`.
    pub fn max_torque_nm(&self, speed_rpm: f64) -> f64 {
        self.full_load.at(speed_rpm)
    }

    /// Drag (motoring) torque [Nm] at `speed_rpm`: negative, the torque the engine absorbs at fuel cut.
    pub fn drag_torque_nm(&self, speed_rpm: f64) -> f64 {
        self.drag.at(speed_rpm)
    }

    /// Fuel rate [g/h] at `speed_rpm` delivering `torque_nm`: zero at or below the drag torque
    /// (fuel cut), else the fuel map's value (extrapolated to its boundary outside it).
    pub fn fuel_rate_g_per_h(&self, speed_rpm: f64, torque_nm: f64) -> f64 {
        if torque_nm <= self.drag_torque_nm(speed_rpm) {
            return 0.0;
        }
        self.fuel.extrapolate(speed_rpm, torque_nm).max(0.0)
    }

    /// The fuel map itself (for callers that must know whether a point lies inside it).
    pub fn fuel_map(&self) -> &FuelMap {
        &self.fuel
    }

    /// The full-load and drag curves, and the speeds [rpm] they cover.
    pub fn curves(&self) -> ((&Curve, &Curve), (f64, f64)) {
        ((&self.full_load, &self.drag), self.full_load.x_range())
    }

    /// Engine speeds [rpm] the full-load curve covers: the speeds the engine may run at.
    pub fn speed_range_rpm(&self) -> (f64, f64) {
        self.full_load.x_range()
    }

    /// Rated power [W] and the speed [rpm] it is reached at: the maximum of torque × speed over the
    /// full-load curve's points.
    pub fn rated_power(&self) -> (f64, f64) {
        self.full_load.points().map(|(n, t)| (t * n / RPM_PER_RAD_S, n)).fold((f64::NEG_INFINITY, 0.0), |best, p| {
            if p.0 > best.0 {
                p
            } else {
                best
            }
        })
    }
}

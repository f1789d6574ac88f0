//! A transmission's torque loss over its input speed and torque, as VECTO's gearbox and axle loss
//! maps give it (`.vtlm` files, or the `TorqueLossMap` of a declaration XML).
//!
//! VECTO triangulates the map's points over (input speed, input torque − loss), the torque that
//! reaches the output seen at the input, and looks the loss up there: from the output side
//! (wheels towards the engine) the input torque is then output torque / ratio + loss, without
//! iterating. This does the same, on the triangulation the fuel map uses (extrapolated at the
//! boundary outside it), resampled on a regular grid for speed.

use super::{FuelGrid, FuelMap};
use crate::CoreResult;

/// Nodes along each axis of a loss map's grid: loss maps are nearly linear in torque, so a coarser
/// grid than the fuel map's keeps the error below half a newton-metre on VECTO's generic maps.
const NODES: usize = 321;

/// Fixed-point steps that turn an input torque into the output torque (each step shrinks the
/// error by the map's torque slope, a few percent).
const FORWARD_STEPS: usize = 6;

/// A loss map's points: (input speed [rpm], input torque [Nm], torque loss [Nm]).
pub type LossPoints = Vec<(f64, f64, f64)>;

/// A loss map, ready to look up in either direction.
#[derive(Debug, Clone)]
pub struct LossMap {
    grid: FuelGrid,
}

impl LossMap {
    /// A map from `(input speed [rpm], input torque [Nm], torque loss [Nm])` points; `key` names
    /// it in errors (losses ≥ 0, each (speed, torque) once, not all on one line).
    pub fn new(key: &str, points: &[(f64, f64, f64)]) -> CoreResult<Self> {
        let shifted: Vec<(f64, f64, f64)> = points.iter().map(|&(n, t, loss)| (n, t - loss, loss)).collect();
        let map = FuelMap::new(key, &shifted)?;
        let grid = FuelGrid::with_nodes(&map, map.speed_range_rpm(), map.torque_range_nm(), NODES);
        Ok(LossMap { grid })
    }

    /// Torque loss [Nm] at input speed `n_rpm` when `passed_nm` (output torque / ratio) leaves.
    #[inline]
    pub fn loss_nm(&self, n_rpm: f64, passed_nm: f64) -> f64 {
        self.grid.at(n_rpm, passed_nm)
    }

    /// Input torque [Nm] that passes `passed_nm` (output torque / ratio) at `n_rpm`.
    #[inline]
    pub fn input_nm(&self, n_rpm: f64, passed_nm: f64) -> f64 {
        passed_nm + self.loss_nm(n_rpm, passed_nm)
    }

    /// Torque [Nm] passed on (output torque / ratio) from `input_nm` at `n_rpm`: the inverse of
    /// [`LossMap::input_nm`].
    #[inline]
    pub fn passed_nm(&self, n_rpm: f64, input_nm: f64) -> f64 {
        let mut passed = input_nm - self.loss_nm(n_rpm, input_nm);
        for _ in 0..FORWARD_STEPS {
            passed = input_nm - self.loss_nm(n_rpm, passed);
        }
        passed
    }
}

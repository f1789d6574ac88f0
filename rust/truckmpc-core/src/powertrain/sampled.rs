//! A curve over engine (or machine) speed resampled at a fixed step, for the models' hot paths.

use super::Curve;

/// Speed step of the resampled torque curves [rpm].
const CURVE_STEP_RPM: f64 = 0.5;

/// A curve over speed resampled every [`CURVE_STEP_RPM`]: one multiply and one lerp per look-up
/// instead of a search. Outside its range it holds the end values, as [`Curve`] does.
#[derive(Debug, Clone)]
pub(crate) struct Sampled {
    lo_rpm: f64,
    values: Vec<f64>,
}

impl Sampled {
    /// `curve` resampled over `range_rpm` (lowest, highest).
    pub(crate) fn new(curve: &Curve, range_rpm: (f64, f64)) -> Self {
        Self::from_fn(range_rpm, |n| curve.at(n))
    }

    /// Any function of speed [rpm] resampled over `range_rpm` (lowest, highest).
    pub(crate) fn from_fn((lo_rpm, hi_rpm): (f64, f64), f: impl Fn(f64) -> f64) -> Self {
        let nodes = ((hi_rpm - lo_rpm) / CURVE_STEP_RPM).ceil() as usize + 2;
        Sampled { lo_rpm, values: (0..nodes).map(|i| f(lo_rpm + i as f64 * CURVE_STEP_RPM)).collect() }
    }

    /// Zero at every speed.
    pub(crate) fn zero() -> Self {
        Sampled { lo_rpm: 0.0, values: vec![0.0, 0.0] }
    }

    /// The value at `n_rpm`, linear between the samples.
    #[inline]
    pub(crate) fn at(&self, n_rpm: f64) -> f64 {
        let last = (self.values.len() - 2) as f64;
        let t = ((n_rpm - self.lo_rpm) / CURVE_STEP_RPM).clamp(0.0, last);
        let i = t as usize;
        let f = t - i as f64;
        self.values[i] + f * (self.values[i + 1] - self.values[i])
    }
}

//! A curve y(x) given at points with strictly increasing x, linear between them: the engine's
//! full-load and drag torque over engine speed.

use crate::{CoreError, CoreResult};

/// A piecewise-linear curve. Beyond its first and last points it holds their values (an engine
/// curve extrapolated far past its last point turns into nonsense); [`Curve::covers`] says whether
/// x is inside.
#[derive(Debug, Clone, PartialEq)]
pub struct Curve {
    x: Vec<f64>,
    y: Vec<f64>,
}

impl Curve {
    /// A curve through `(x, y)` points; `key` names it in errors. At least two points, x finite and
    /// strictly increasing, y finite.
    pub fn new(key: &str, points: &[(f64, f64)]) -> CoreResult<Self> {
        if points.len() < 2 {
            return Err(CoreError::invalid(key, "at least two points").got(points.len()));
        }
        for (i, &(x, y)) in points.iter().enumerate() {
            if !x.is_finite() || !y.is_finite() {
                return Err(
                    CoreError::invalid(key, format!("finite numbers at point {}", i + 1)).got(format!("{x}, {y}"))
                );
            }
            if i > 0 && x <= points[i - 1].0 {
                return Err(CoreError::invalid(key, format!("increasing x at point {}", i + 1)).got(format!(
                    "{} after {}",
                    x,
                    points[i - 1].0
                )));
            }
        }
        Ok(Curve { x: points.iter().map(|p| p.0).collect(), y: points.iter().map(|p| p.1).collect() })
    }

    /// y at `x`, linear between the neighbouring points, the end values outside.
    pub fn at(&self, x: f64) -> f64 {
        let n = self.x.len();
        let x = x.clamp(self.x[0], self.x[n - 1]);
        let i = self.x.partition_point(|&xi| xi <= x).clamp(1, n - 1);
        let (x0, x1, y0, y1) = (self.x[i - 1], self.x[i], self.y[i - 1], self.y[i]);
        y0 + (y1 - y0) * (x - x0) / (x1 - x0)
    }

    /// Whether `x` lies within the curve's first and last points.
    pub fn covers(&self, x: f64) -> bool {
        x >= self.x[0] && x <= self.x[self.x.len() - 1]
    }

    /// The first and last x.
    pub fn x_range(&self) -> (f64, f64) {
        (self.x[0], self.x[self.x.len() - 1])
    }

    /// The curve's points.
    pub fn points(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.x.iter().copied().zip(self.y.iter().copied())
    }
}

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
    /// Buckets of equal width over x: where the search for a point in each may start.
    lookup: Lookup,
}

/// Equal-width buckets over a curve's x range, each holding an index at or below that of the first
/// point beyond any x in it, so a look-up steps forward from there instead of searching.
#[derive(Debug, Clone, PartialEq)]
struct Lookup {
    x0: f64,
    per_x: f64,
    starts: Vec<u32>,
}

/// At most this many buckets (a curve with points much closer than its mean spacing steps past
/// a few of them per look-up).
const MAX_BUCKETS: usize = 4096;

impl Lookup {
    fn new(x: &[f64]) -> Self {
        let (x0, span) = (x[0], x[x.len() - 1] - x[0]);
        let narrowest = x.windows(2).map(|w| w[1] - w[0]).fold(f64::INFINITY, f64::min);
        let count = ((span / narrowest).ceil() as usize).clamp(1, MAX_BUCKETS);
        let width = span / count as f64;
        // A bucket's start less a whole width: a lower bound whatever the rounding of x's bucket.
        let starts = (0..=count).map(|b| x.partition_point(|&xi| xi < x0 + (b as f64 - 1.0) * width) as u32).collect();
        Lookup { x0, per_x: count as f64 / span, starts }
    }

    /// The index of the first point beyond `x` (x within the curve's range), as
    /// `x.partition_point(|xi| xi <= x)` gives it.
    #[inline]
    fn first_beyond(&self, xs: &[f64], x: f64) -> usize {
        let b = (((x - self.x0) * self.per_x) as usize).min(self.starts.len() - 1);
        let mut i = self.starts[b] as usize;
        while i < xs.len() && xs[i] <= x {
            i += 1;
        }
        i
    }
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
        let x: Vec<f64> = points.iter().map(|p| p.0).collect();
        let lookup = Lookup::new(&x);
        Ok(Curve { x, y: points.iter().map(|p| p.1).collect(), lookup })
    }

    /// y at `x`, linear between the neighbouring points, the end values outside.
    pub fn at(&self, x: f64) -> f64 {
        let n = self.x.len();
        let x = x.clamp(self.x[0], self.x[n - 1]);
        let i = self.lookup.first_beyond(&self.x, x).clamp(1, n - 1);
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

//! A road profile as the plant and the controller see it: a piecewise-linear altitude over
//! distance, i.e. a constant slope on each segment between two profile points.
//! Beyond its last point the road is taken to continue flat (the look-ahead needs slopes past the end).
//! A road may carry a target speed per segment (a driving cycle's, or the speed limits), which
//! holds from the segment's first point to the next; beyond the end the last one holds.

use crate::error::{CoreError, CoreResult};

/// Road profile: segment boundaries [m] and the grade of each segment [-].
#[derive(Debug, Clone, PartialEq)]
pub struct Road {
    distance_m: Vec<f64>,
    altitude_m: Vec<f64>,
    slope: Vec<f64>,
    /// Target speed of each segment [km/h], if the road has them.
    target_kmh: Option<Vec<f64>>,
}

/// Highest accepted target speed [km/h].
pub const MAX_TARGET_KMH: f64 = 250.0;

impl Road {
    /// Build from profile points `distance_m` (strictly increasing, ≥ 2 points) and the grade of each
    /// segment [i, i+1) (`slope.len() == distance_m.len() - 1`). Altitude starts at 0 m.
    pub fn new(distance_m: Vec<f64>, slope: Vec<f64>) -> CoreResult<Self> {
        if distance_m.len() < 2 {
            return Err(CoreError::invalid("distance_m", "at least two profile points"));
        }
        if slope.len() + 1 != distance_m.len() {
            return Err(
                CoreError::invalid("slope", format!("{} segment slopes", distance_m.len() - 1)).got(slope.len())
            );
        }
        if let Some(i) = distance_m.windows(2).position(|w| !(w[1] > w[0]) || !w[1].is_finite()) {
            return Err(CoreError::invalid("distance_m", format!("strictly increasing distances at point {}", i + 1)));
        }
        if let Some(i) = slope.iter().position(|s| !s.is_finite()) {
            return Err(CoreError::invalid("slope", format!("a finite slope on segment {i}")));
        }
        let mut altitude_m = Vec::with_capacity(distance_m.len());
        altitude_m.push(0.0);
        for (i, s) in slope.iter().enumerate() {
            altitude_m.push(altitude_m[i] + s * (distance_m[i + 1] - distance_m[i]));
        }
        Ok(Road { distance_m, altitude_m, slope, target_kmh: None })
    }

    /// The same road with a target speed per segment `target_kmh` [km/h] (one per segment, each
    /// in (0, 250]).
    pub fn with_target_speeds(mut self, target_kmh: Vec<f64>) -> CoreResult<Self> {
        if target_kmh.len() != self.slope.len() {
            let expected = format!("{} segment target speeds", self.slope.len());
            return Err(CoreError::invalid("target_speed_kmh", expected).got(target_kmh.len()));
        }
        if let Some(i) = target_kmh.iter().position(|v| !(*v > 0.0 && *v <= MAX_TARGET_KMH)) {
            let expected = format!("a target speed in (0, {MAX_TARGET_KMH}] km/h on segment {i}");
            return Err(CoreError::invalid("target_speed_kmh", expected).got(target_kmh[i]));
        }
        self.target_kmh = Some(target_kmh);
        Ok(self)
    }

    /// The target speed of each segment [km/h], if the road has them.
    pub fn target_speeds_kmh(&self) -> Option<&[f64]> {
        self.target_kmh.as_deref()
    }

    /// Distance of the first profile point [m].
    pub fn start_m(&self) -> f64 {
        self.distance_m[0]
    }

    /// Distance of the last profile point [m].
    pub fn end_m(&self) -> f64 {
        *self.distance_m.last().unwrap()
    }

    /// The profile points [m].
    pub fn distance_m(&self) -> &[f64] {
        &self.distance_m
    }

    /// The grade of each segment between consecutive profile points [-].
    pub fn slopes(&self) -> &[f64] {
        &self.slope
    }

    /// Index of the segment containing `s_m`, searching forward from `hint` (the last answer)
    /// for the common case of a vehicle moving forward; clamps outside the road.
    #[inline]
    pub fn segment(&self, s_m: f64, hint: usize) -> usize {
        let last = self.slope.len() - 1;
        let mut i = hint.min(last);
        if s_m < self.distance_m[i] {
            // Moving backwards (rare): binary search.
            return self.distance_m.partition_point(|&d| d <= s_m).saturating_sub(1).min(last);
        }
        while i < last && s_m >= self.distance_m[i + 1] {
            i += 1;
        }
        i
    }

    /// Grade at `s_m` [-]: the segment's slope, 0 beyond the end. `hint` as for [`Road::segment`].
    #[inline]
    pub fn slope_at(&self, s_m: f64, hint: &mut usize) -> f64 {
        if s_m >= self.end_m() {
            return 0.0;
        }
        *hint = self.segment(s_m, *hint);
        self.slope[*hint]
    }

    /// The first profile point strictly beyond `s_m` (where the slope may jump) [m]; infinite
    /// past the end. `hint` as for [`Road::segment`].
    #[inline]
    pub fn next_point_after(&self, s_m: f64, hint: &mut usize) -> f64 {
        if s_m >= self.end_m() {
            return f64::INFINITY;
        }
        if s_m < self.start_m() {
            return self.start_m();
        }
        *hint = self.segment(s_m, *hint);
        self.distance_m[*hint + 1]
    }

    /// Altitude at `s_m` [m] relative to the first point, flat beyond the end.
    pub fn altitude_at(&self, s_m: f64) -> f64 {
        // A hint past the end makes `segment` search the whole profile.
        let mut anywhere = usize::MAX;
        self.altitude_from(s_m, &mut anywhere)
    }

    /// [`Road::altitude_at`], searching forward from `hint` as [`Road::segment`] does (the same
    /// value whatever the hint).
    #[inline]
    pub fn altitude_from(&self, s_m: f64, hint: &mut usize) -> f64 {
        if s_m >= self.end_m() {
            return *self.altitude_m.last().unwrap();
        }
        if s_m <= self.start_m() {
            return self.slope[0] * (s_m - self.start_m());
        }
        *hint = self.segment(s_m, *hint);
        self.altitude_m[*hint] + self.slope[*hint] * (s_m - self.distance_m[*hint])
    }

    /// Mean grade over [s0, s1] [-]: altitude difference over length, the slope a DP stage sees.
    pub fn mean_slope(&self, s0_m: f64, s1_m: f64) -> f64 {
        let mut anywhere = usize::MAX;
        self.mean_slope_from(s0_m, s1_m, &mut anywhere)
    }

    /// [`Road::mean_slope`] with a search hint, for positions visited in increasing order.
    #[inline]
    pub fn mean_slope_from(&self, s0_m: f64, s1_m: f64, hint: &mut usize) -> f64 {
        let h0 = self.altitude_from(s0_m, hint);
        (self.altitude_from(s1_m, hint) - h0) / (s1_m - s0_m)
    }
}

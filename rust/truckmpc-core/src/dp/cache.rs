//! Transition costs of one stage, kept across solves on a fixed (absolute) velocity grid.
//!
//! Successive receding-horizon solves share all but one of their stages: a stage at absolute road
//! position k is solved N times, from N different start positions. With a fixed grid a row of
//! costs depends only on (absolute stage, velocity index, target gear), so it is computed once and
//! reused; stages behind the vehicle are dropped. A solve without the cache (moving grid, or the
//! first stage, whose start speed is off the grid) fills a scratch [`StageRows`] the same way.
//!
//! Layout: per target gear, the rows of consecutive source velocities are side by side, because
//! the DP's first pass walks one target gear at a time over all source velocities.

use std::collections::VecDeque;

use super::rows::RowSpan;

/// Values for a contiguous range of source keys (grid indices), grown at either end on demand.
#[derive(Debug, Clone)]
pub struct Keyed<T> {
    key_lo: i64,
    values: Vec<T>,
}

impl<T> Default for Keyed<T> {
    fn default() -> Self {
        Keyed { key_lo: 0, values: Vec::new() }
    }
}

impl<T: Copy> Keyed<T> {
    fn clear(&mut self) {
        self.values.clear();
    }

    /// Make sure keys `lo..=hi` have values, computing the missing ones with `make` (a request
    /// that leaves a gap to the present range fills the gap too, so the range stays contiguous).
    /// Returns how many values were computed.
    pub fn fill(&mut self, lo: i64, hi: i64, mut make: impl FnMut(i64) -> T) -> u64 {
        if self.values.is_empty() {
            self.key_lo = lo;
            self.values.extend((lo..=hi).map(&mut make));
            return self.values.len() as u64;
        }
        let present_hi = self.key_lo + self.values.len() as i64 - 1;
        let mut computed = 0;
        if lo < self.key_lo {
            let mut front: Vec<T> = (lo..self.key_lo).map(&mut make).collect();
            computed += front.len() as u64;
            front.extend_from_slice(&self.values);
            self.values = front;
            self.key_lo = lo;
        }
        if hi > present_hi {
            self.values.extend((present_hi + 1..=hi).map(&mut make));
            computed += (hi - present_hi) as u64;
        }
        computed
    }

    /// The values of keys `lo..=hi` (which must have been filled).
    #[inline]
    pub fn get(&self, lo: i64, hi: i64) -> &[T] {
        &self.values[(lo - self.key_lo) as usize..=(hi - self.key_lo) as usize]
    }
}

/// Where one row lives in its gear's cost buffer.
#[derive(Debug, Clone, Copy, Default)]
pub struct RowMeta {
    /// Next-stage grid index of the row's first cost.
    pub first: i32,
    /// Start of the row in the cost buffer.
    pub offset: u32,
    /// Number of costs (0: no admissible target).
    pub len: u32,
}

impl RowMeta {
    /// The span the row covers on the next grid.
    #[inline]
    pub fn span(&self) -> RowSpan {
        RowSpan { first: self.first as i64, len: self.len as usize }
    }
}

/// The rows of one stage towards one forward target gear, keyed by source grid index.
#[derive(Debug, Clone, Default)]
pub struct GearRows {
    pub meta: Keyed<RowMeta>,
    pub costs: Vec<f64>,
}

impl GearRows {
    /// Make sure the rows of keys `lo..=hi` exist; `row(key, out)` writes one row's costs into
    /// `out` and returns its span. Returns the rows computed.
    pub fn fill(&mut self, lo: i64, hi: i64, scratch: &mut Vec<f64>, mut row: impl FnMut(i64, &mut Vec<f64>) -> RowSpan) -> u64 {
        let costs = &mut self.costs;
        self.meta.fill(lo, hi, |key| {
            let span = row(key, scratch);
            let meta = RowMeta { first: span.first as i32, offset: costs.len() as u32, len: span.len as u32 };
            costs.extend_from_slice(&scratch[..span.len]);
            meta
        })
    }
}

/// A neutral arc from one source speed: where it ends and the part of its cost that does not
/// depend on the cost-to-go (fuel and speed change).
#[derive(Debug, Clone, Copy, Default)]
pub struct NeutralArc {
    /// End speed after the stage [m/s].
    pub v_end_mps: f64,
    /// Q1·fuel + Q3·|Δv|.
    pub cost: f64,
}

/// Everything one stage keeps: its slope, its rows per target gear and its neutral arcs.
#[derive(Debug, Clone, Default)]
pub struct StageRows {
    slope_torque_nm: f64,
    /// Indexed by gear; entry 0 (neutral) is unused.
    gears: Vec<GearRows>,
    pub neutral: Keyed<NeutralArc>,
}

impl StageRows {
    /// Empty the stage for a slope (as wheel torque [Nm]).
    pub fn reset(&mut self, slope_torque_nm: f64) {
        self.slope_torque_nm = slope_torque_nm;
        for rows in &mut self.gears {
            rows.meta.clear();
            rows.costs.clear();
        }
        self.neutral.clear();
    }

    /// The rows towards forward `gear`.
    #[inline]
    pub fn gear(&mut self, gear: usize) -> &mut GearRows {
        if self.gears.len() <= gear {
            self.gears.resize_with(gear + 1, GearRows::default);
        }
        &mut self.gears[gear]
    }
}

/// Cached stages for a window of absolute stages.
#[derive(Debug, Clone, Default)]
pub struct RowCache {
    first_stage: u64,
    stages: VecDeque<StageRows>,
    spare: Vec<StageRows>,
    /// Rows computed (cache misses) since creation, for diagnostics.
    pub computed: u64,
}

impl RowCache {
    /// Drop the stages before `stage` and make sure `stage..stage + count` exist with these slopes.
    /// A stage whose slope changed (another road) is emptied.
    pub fn prepare(&mut self, stage: u64, slope_torques_nm: &[f64]) {
        while self.first_stage < stage && !self.stages.is_empty() {
            self.spare.push(self.stages.pop_front().unwrap());
            self.first_stage += 1;
        }
        if self.stages.is_empty() || self.first_stage > stage {
            self.spare.extend(self.stages.drain(..));
            self.first_stage = stage;
        }
        for (k, &torque) in slope_torques_nm.iter().enumerate() {
            let at = (stage - self.first_stage) as usize + k;
            if at == self.stages.len() {
                let mut rows = self.spare.pop().unwrap_or_default();
                rows.reset(torque);
                self.stages.push_back(rows);
            } else if self.stages[at].slope_torque_nm != torque {
                self.stages[at].reset(torque);
            }
        }
    }

    /// The rows of absolute `stage` (`prepare` must have covered it) and the miss counter.
    #[inline]
    pub fn stage(&mut self, stage: u64) -> (&mut StageRows, &mut u64) {
        (&mut self.stages[(stage - self.first_stage) as usize], &mut self.computed)
    }
}

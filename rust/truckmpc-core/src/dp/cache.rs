//! Rows of transition costs kept across solves, for a fixed (absolute) velocity grid.
//!
//! Successive receding-horizon solves share all but one of their stages: a stage at absolute road
//! position k is solved N times, from N different start positions. With a fixed grid a row depends
//! only on (absolute stage, velocity index, gear), so it is computed once and reused; stages behind
//! the vehicle are dropped. Rows are filled lazily, only for the states a solve visits.

use std::collections::VecDeque;

use super::params::MpcParams;
use super::rows::{forward_row, GridIndex, RowSpan};
use crate::vehicle::Vehicle;

/// Where one row lives in its stage's cost buffer (12 bytes: the lookups are memory-bound).
#[derive(Debug, Clone, Copy)]
struct RowMeta {
    /// Grid index of the row's first cost.
    first: i32,
    offset: u32,
    /// Number of costs; `UNFILLED` until the row is computed.
    len: u32,
}

const UNFILLED: u32 = u32::MAX;

impl Default for RowMeta {
    fn default() -> Self {
        RowMeta { first: 0, offset: 0, len: UNFILLED }
    }
}

/// The rows of one absolute stage.
#[derive(Debug, Clone, Default)]
struct StageRows {
    slope_torque_nm: f64,
    /// Velocity index of the first row block; rows are indexed [(i − i_lo)·gears + g].
    i_lo: i64,
    blocks: usize,
    meta: Vec<RowMeta>,
    costs: Vec<f64>,
}

impl StageRows {
    fn reset(&mut self, slope_torque_nm: f64) {
        self.slope_torque_nm = slope_torque_nm;
        self.i_lo = 0;
        self.blocks = 0;
        self.meta.clear();
        self.costs.clear();
    }

    /// Make room for velocity index `i` (with some margin, so growth is rare).
    fn cover(&mut self, i: i64, gears: usize) {
        const MARGIN: i64 = 32;
        if self.blocks > 0 && i >= self.i_lo && i < self.i_lo + self.blocks as i64 {
            return;
        }
        let (lo, hi) = if self.blocks == 0 {
            (i - MARGIN, i + MARGIN)
        } else {
            ((self.i_lo).min(i - MARGIN), (self.i_lo + self.blocks as i64 - 1).max(i + MARGIN))
        };
        let blocks = (hi - lo + 1) as usize;
        let mut meta = vec![RowMeta::default(); blocks * gears];
        for b in 0..self.blocks {
            let to = (self.i_lo + b as i64 - lo) as usize;
            meta[to * gears..(to + 1) * gears].copy_from_slice(&self.meta[b * gears..(b + 1) * gears]);
        }
        self.meta = meta;
        self.i_lo = lo;
        self.blocks = blocks;
    }
}

/// Cached rows for a window of absolute stages.
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

    /// The rows of absolute `stage`, covering velocity indices `i_lo..=i_hi`. `prepare` must have
    /// covered the stage.
    pub fn stage(&mut self, stage: u64, i_lo: i64, i_hi: i64, gears: usize) -> StageView<'_> {
        let rows = &mut self.stages[(stage - self.first_stage) as usize];
        rows.cover(i_lo, gears);
        rows.cover(i_hi, gears);
        StageView { rows, gears, computed: &mut self.computed }
    }
}

/// One stage's rows, ready for lookups by (velocity index, gear).
pub struct StageView<'a> {
    rows: &'a mut StageRows,
    gears: usize,
    computed: &'a mut u64,
}

impl StageView<'_> {
    /// The row of velocity index `i` (speed `v_i`) in forward `gear`, computed on first use.
    #[inline]
    pub fn row(&mut self, vehicle: &Vehicle, p: &MpcParams, i: i64, v_i: f64, gear: usize, grid: GridIndex, scratch: &mut Vec<f64>) -> (RowSpan, &[f64]) {
        let rows = &mut *self.rows;
        let at = (i - rows.i_lo) as usize * self.gears + gear;
        let m = rows.meta[at];
        let m = if m.len != UNFILLED {
            m
        } else {
            let span = forward_row(vehicle, p, v_i, gear, rows.slope_torque_nm, grid, scratch);
            let m = RowMeta { first: span.first as i32, offset: rows.costs.len() as u32, len: span.len as u32 };
            rows.meta[at] = m;
            rows.costs.extend_from_slice(scratch);
            *self.computed += 1;
            m
        };
        (RowSpan { first: m.first as i64, len: m.len as usize }, &rows.costs[m.offset as usize..(m.offset + m.len) as usize])
    }
}

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
    /// Velocity index of the first row block; rows are indexed [(i − i_lo)·gear_count + g − g_lo]
    /// (only the gears this stage has seen: the lookups are memory-bound).
    i_lo: i64,
    blocks: usize,
    g_lo: usize,
    gear_count: usize,
    meta: Vec<RowMeta>,
    costs: Vec<f64>,
}

impl StageRows {
    fn reset(&mut self, slope_torque_nm: f64) {
        self.slope_torque_nm = slope_torque_nm;
        self.i_lo = 0;
        self.blocks = 0;
        self.g_lo = 0;
        self.gear_count = 0;
        self.meta.clear();
        self.costs.clear();
    }

    /// Make room for velocity indices `i_lo..=i_hi` and gears `g_lo..=g_hi` (with some margin on
    /// the velocities, so that growth is rare).
    fn cover(&mut self, i_lo: i64, i_hi: i64, g_lo: usize, g_hi: usize) {
        const MARGIN: i64 = 32;
        let i_end = self.i_lo + self.blocks as i64;
        let g_end = self.g_lo + self.gear_count;
        let fits = self.blocks > 0 && i_lo >= self.i_lo && i_hi < i_end && g_lo >= self.g_lo && g_hi < g_end;
        if fits {
            return;
        }
        let (new_i_lo, new_i_hi, new_g_lo, new_g_hi) = if self.blocks == 0 {
            (i_lo - MARGIN, i_hi + MARGIN, g_lo, g_hi)
        } else {
            (
                self.i_lo.min(i_lo - MARGIN),
                (i_end - 1).max(i_hi + MARGIN),
                self.g_lo.min(g_lo),
                (g_end - 1).max(g_hi),
            )
        };
        let blocks = (new_i_hi - new_i_lo + 1) as usize;
        let gear_count = new_g_hi - new_g_lo + 1;
        let mut meta = vec![RowMeta::default(); blocks * gear_count];
        for b in 0..self.blocks {
            for g in 0..self.gear_count {
                let to = (self.i_lo + b as i64 - new_i_lo) as usize * gear_count + (self.g_lo + g - new_g_lo);
                meta[to] = self.meta[b * self.gear_count + g];
            }
        }
        self.meta = meta;
        self.i_lo = new_i_lo;
        self.blocks = blocks;
        self.g_lo = new_g_lo;
        self.gear_count = gear_count;
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

    /// The rows of absolute `stage`, covering velocity indices `i_lo..=i_hi` and forward gears
    /// `g_lo..=g_hi`. `prepare` must have covered the stage.
    pub fn stage(&mut self, stage: u64, (i_lo, i_hi): (i64, i64), (g_lo, g_hi): (usize, usize)) -> StageView<'_> {
        let rows = &mut self.stages[(stage - self.first_stage) as usize];
        rows.cover(i_lo, i_hi, g_lo, g_hi);
        StageView { rows, computed: &mut self.computed }
    }
}

/// One stage's rows, ready for lookups by (velocity index, gear).
pub struct StageView<'a> {
    rows: &'a mut StageRows,
    computed: &'a mut u64,
}

impl StageView<'_> {
    /// The row of velocity index `i` (speed `v_i`) in forward `gear` (both within what `stage`
    /// covered), computed on first use.
    #[inline]
    pub fn row(&mut self, vehicle: &Vehicle, p: &MpcParams, i: i64, v_i: f64, gear: usize, grid: GridIndex, scratch: &mut Vec<f64>) -> (RowSpan, &[f64]) {
        let rows = &mut *self.rows;
        let at = (i - rows.i_lo) as usize * rows.gear_count + gear - rows.g_lo;
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

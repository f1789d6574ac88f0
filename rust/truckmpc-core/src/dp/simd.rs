//! The DP's innermost loop: for a block of `LANES` source velocities towards one target gear,
//! per lane the smallest row cost + cost-to-go and its first index, against both the cost-to-go
//! and the cost-to-go of targets that allow a shift.
//!
//! Lanes are source velocities, not row entries: rows are short (about 8 to 17 admissible targets)
//! and a horizontal minimum per row costs a reduction and a data-dependent branch, while one step
//! across lanes needs neither. On x86-64 with AVX2 (detected at run time) a step is a handful of
//! 4-wide instructions; elsewhere the portable loop, which the compiler vectorises as it can. Only
//! additions, comparisons and selects are used, so every path gives the same bits as a scalar
//! scan of each row keeping the first strict improvement ([`argmin_sum_scalar`], which the tests
//! compare against).
//!
//! This file holds the portable kernels, the dispatch and the [`Kernels`] interface; the AVX2
//! kernels are in `simd/avx2.rs`, the lane helpers of the solver's AVX2 passes in `simd/lanes.rs`.

#[cfg(target_arch = "x86_64")]
mod avx2;
#[cfg(target_arch = "x86_64")]
pub mod lanes;
#[cfg(test)]
mod tests;

#[cfg(target_arch = "x86_64")]
pub use avx2::Avx2;

use super::cache::LANES;

const INF: f64 = f64::INFINITY;

/// The reference for one lane: a scan of `row[t] + to_go[t]` keeping the first strict improvement
/// (+∞ and 0 when every sum is +∞).
#[inline]
pub fn argmin_sum_scalar(row: &[f64], to_go: &[f64]) -> (f64, usize) {
    let to_go = &to_go[..row.len()];
    let (mut best, mut best_t) = (INF, 0usize);
    for t in 0..row.len() {
        let c = row[t] + to_go[t];
        if c < best {
            best = c;
            best_t = t;
        }
    }
    (best, best_t)
}

/// Per lane of a block: the smallest cost + to-go and the first step reaching it, and the same
/// against the shiftable to-go (cost +∞ and step 0 when none is finite).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LaneMins {
    pub all: [f64; LANES],
    pub all_step: [u32; LANES],
    pub shift: [f64; LANES],
    pub shift_step: [u32; LANES],
}

/// Where a block's lane minima go: the minima and their next-grid indices, `LANES` of each.
pub struct LaneOut<'a> {
    pub all: &'a mut [f64],
    pub all_j: &'a mut [u32],
    pub shift: &'a mut [f64],
    pub shift_j: &'a mut [u32],
}

impl LaneMins {
    /// The minima into `out`, with lane l's index `base` + l + its step (wrapping, as u32).
    #[inline(always)]
    pub fn write(&self, base: u32, out: LaneOut) {
        out.all[..LANES].copy_from_slice(&self.all);
        out.shift[..LANES].copy_from_slice(&self.shift);
        for l in 0..LANES {
            out.all_j[l] = base.wrapping_add(l as u32).wrapping_add(self.all_step[l]);
            out.shift_j[l] = base.wrapping_add(l as u32).wrapping_add(self.shift_step[l]);
        }
    }
}

/// The min-plus pass over one block of rows (see [`crate::dp::cache::Block`]): `costs` holds
/// `steps × LANES` costs, step-major; lane l at step d adds `to_go[l + d]` (and
/// `shiftable[l + d]`). Both value slices hold at least `steps + LANES − 1` values. Scanning the
/// steps in order and keeping strict improvements gives each lane the first index of its minimum,
/// as a scalar scan of its row would.
#[inline]
pub fn block_mins(costs: &[f64], steps: usize, to_go: &[f64], shiftable: &[f64]) -> LaneMins {
    let costs = &costs[..steps * LANES];
    let (to_go, shiftable) = (&to_go[..steps + LANES - 1], &shiftable[..steps + LANES - 1]);
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU has AVX2 (checked just above).
            return unsafe { avx2::block_mins_avx2(costs, steps, to_go, shiftable) };
        }
    }
    block_mins_portable(costs, steps, to_go, shiftable)
}

/// [`block_mins`] when the shiftable to-go is the to-go itself (bit for bit): one minimum per
/// lane, returned as both.
#[inline]
pub fn block_mins_same(costs: &[f64], steps: usize, to_go: &[f64]) -> LaneMins {
    let costs = &costs[..steps * LANES];
    let to_go = &to_go[..steps + LANES - 1];
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU has AVX2 (checked just above).
            return unsafe { avx2::block_mins_same_avx2(costs, steps, to_go) };
        }
    }
    block_mins_portable(costs, steps, to_go, to_go)
}

/// The min-plus kernels of one instruction set, for callers that run many blocks in a loop: a
/// loop generic over `Kernels` and instantiated inside a function compiled for AVX2 (see
/// [`Avx2::detect`]) inlines the AVX2 kernels, with no call, feature check or result in memory
/// per block.
pub trait Kernels: Copy {
    /// The min-plus pass of [`block_mins`] (of [`block_mins_same`] without `shiftable`) over
    /// `steps` steps (`block`: the costs and the steps), written into `out` as
    /// [`LaneMins::write`] does.
    fn block_mins_to(self, block: (&[f64], usize), to_go: &[f64], shiftable: Option<&[f64]>, base: u32, out: LaneOut);
}

/// A block's costs and value slices cut to the lengths the kernels read: `steps × LANES` costs and
/// `steps + LANES − 1` values (panics if a slice is shorter).
#[inline(always)]
fn block_slices<'a>(
    costs: &'a [f64],
    steps: usize,
    to_go: &'a [f64],
    shiftable: Option<&'a [f64]>,
) -> (&'a [f64], &'a [f64], Option<&'a [f64]>) {
    let values = steps + LANES - 1;
    (&costs[..steps * LANES], &to_go[..values], shiftable.map(|shiftable| &shiftable[..values]))
}

/// The portable kernels.
#[derive(Debug, Clone, Copy)]
pub struct Portable;

impl Kernels for Portable {
    #[inline(always)]
    fn block_mins_to(
        self,
        (costs, steps): (&[f64], usize),
        to_go: &[f64],
        shiftable: Option<&[f64]>,
        base: u32,
        out: LaneOut,
    ) {
        let (costs, to_go, shiftable) = block_slices(costs, steps, to_go, shiftable);
        block_mins_portable(costs, steps, to_go, shiftable.unwrap_or(to_go)).write(base, out);
    }
}

#[inline(always)]
fn block_mins_portable(costs: &[f64], steps: usize, to_go: &[f64], shiftable: &[f64]) -> LaneMins {
    let mut out = LaneMins { all: [INF; LANES], all_step: [0; LANES], shift: [INF; LANES], shift_step: [0; LANES] };
    for d in 0..steps {
        let c: &[f64; LANES] = costs[d * LANES..d * LANES + LANES].try_into().unwrap();
        let a: &[f64; LANES] = to_go[d..d + LANES].try_into().unwrap();
        let b: &[f64; LANES] = shiftable[d..d + LANES].try_into().unwrap();
        for l in 0..LANES {
            let x = c[l] + a[l];
            let better = x < out.all[l];
            out.all[l] = if better { x } else { out.all[l] };
            out.all_step[l] = if better { d as u32 } else { out.all_step[l] };
            let y = c[l] + b[l];
            let better = y < out.shift[l];
            out.shift[l] = if better { y } else { out.shift[l] };
            out.shift_step[l] = if better { d as u32 } else { out.shift_step[l] };
        }
    }
    out
}

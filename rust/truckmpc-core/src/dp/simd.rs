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
            return unsafe { block_mins_avx2(costs, steps, to_go, shiftable) };
        }
    }
    block_mins_portable(costs, steps, to_go, shiftable)
}

/// [`block_mins`] in AVX2: one 4-wide step per d. Only additions, comparisons, minima and
/// blends, so the results are those of the portable version bit for bit.
///
/// Each running minimum is a chain of compare and blend from one step to the next, whose latency
/// (not the instruction count) bounds the loop. So even and odd steps keep separate minima, two
/// chains that run side by side, merged at the end: the smaller value, and of equal values the
/// earlier step, which is what one scan keeping the first strict improvement finds.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn block_mins_avx2(costs: &[f64], steps: usize, to_go: &[f64], shiftable: &[f64]) -> LaneMins {
    block_mins_avx2_regs(costs, steps, to_go, shiftable).lane_mins()
}

/// A block's lane minima in AVX2 registers: values, and steps as f64 lanes.
#[cfg(target_arch = "x86_64")]
#[derive(Clone, Copy)]
struct MinsAvx2 {
    all: std::arch::x86_64::__m256d,
    all_step: std::arch::x86_64::__m256d,
    shift: std::arch::x86_64::__m256d,
    shift_step: std::arch::x86_64::__m256d,
}

#[cfg(target_arch = "x86_64")]
impl MinsAvx2 {
    /// As a [`LaneMins`].
    #[target_feature(enable = "avx2")]
    #[inline]
    unsafe fn lane_mins(self) -> LaneMins {
        use std::arch::x86_64::*;
        let mut out = LaneMins { all: [0.0; LANES], all_step: [0; LANES], shift: [0.0; LANES], shift_step: [0; LANES] };
        _mm256_storeu_pd(out.all.as_mut_ptr(), self.all);
        _mm256_storeu_pd(out.shift.as_mut_ptr(), self.shift);
        // Steps are small non-negative integers: exact as i32.
        _mm_storeu_si128(out.all_step.as_mut_ptr().cast(), _mm256_cvttpd_epi32(self.all_step));
        _mm_storeu_si128(out.shift_step.as_mut_ptr().cast(), _mm256_cvttpd_epi32(self.shift_step));
        out
    }

    /// As [`LaneMins::write`], from the registers.
    #[target_feature(enable = "avx2")]
    #[inline]
    unsafe fn write(self, base: u32, out: LaneOut) {
        use std::arch::x86_64::*;
        assert!(out.all.len() >= LANES && out.shift.len() >= LANES);
        assert!(out.all_j.len() >= LANES && out.shift_j.len() >= LANES);
        let first = _mm_add_epi32(_mm_set1_epi32(base as i32), _mm_setr_epi32(0, 1, 2, 3));
        _mm256_storeu_pd(out.all.as_mut_ptr(), self.all);
        _mm256_storeu_pd(out.shift.as_mut_ptr(), self.shift);
        let all_j = _mm_add_epi32(first, _mm256_cvttpd_epi32(self.all_step));
        let shift_j = _mm_add_epi32(first, _mm256_cvttpd_epi32(self.shift_step));
        _mm_storeu_si128(out.all_j.as_mut_ptr().cast(), all_j);
        _mm_storeu_si128(out.shift_j.as_mut_ptr().cast(), shift_j);
    }
}

/// [`block_mins_avx2`], left in registers.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn block_mins_avx2_regs(costs: &[f64], steps: usize, to_go: &[f64], shiftable: &[f64]) -> MinsAvx2 {
    use std::arch::x86_64::*;
    const _: () = assert!(LANES == 4);
    let (c, a, b) = (costs.as_ptr(), to_go.as_ptr(), shiftable.as_ptr());
    // Per parity: (all, all_step, shift, shift_step); steps as f64 lanes, so that they blend like
    // the costs; exact for any realistic count.
    let inf = _mm256_set1_pd(INF);
    let zero = _mm256_setzero_pd();
    let mut even = [inf, zero, inf, zero];
    let mut odd = [inf, zero, inf, zero];
    #[inline(always)]
    unsafe fn step_into(acc: &mut [__m256d; 4], cost: __m256d, to_go: __m256d, shiftable: __m256d, step: __m256d) {
        let x = _mm256_add_pd(cost, to_go);
        let better = _mm256_cmp_pd::<_CMP_LT_OQ>(x, acc[0]);
        acc[0] = _mm256_blendv_pd(acc[0], x, better);
        acc[1] = _mm256_blendv_pd(acc[1], step, better);
        let y = _mm256_add_pd(cost, shiftable);
        let better = _mm256_cmp_pd::<_CMP_LT_OQ>(y, acc[2]);
        acc[2] = _mm256_blendv_pd(acc[2], y, better);
        acc[3] = _mm256_blendv_pd(acc[3], step, better);
    }
    let two = _mm256_set1_pd(2.0);
    let (mut step_even, mut step_odd) = (zero, _mm256_set1_pd(1.0));
    let mut d = 0;
    while d + 1 < steps {
        // SAFETY: the caller checked costs.len() = steps·LANES and to_go, shiftable ≥ steps + LANES − 1.
        step_into(
            &mut even,
            _mm256_loadu_pd(c.add(d * LANES)),
            _mm256_loadu_pd(a.add(d)),
            _mm256_loadu_pd(b.add(d)),
            step_even,
        );
        step_into(
            &mut odd,
            _mm256_loadu_pd(c.add((d + 1) * LANES)),
            _mm256_loadu_pd(a.add(d + 1)),
            _mm256_loadu_pd(b.add(d + 1)),
            step_odd,
        );
        step_even = _mm256_add_pd(step_even, two);
        step_odd = _mm256_add_pd(step_odd, two);
        d += 2;
    }
    if d < steps {
        step_into(
            &mut even,
            _mm256_loadu_pd(c.add(d * LANES)),
            _mm256_loadu_pd(a.add(d)),
            _mm256_loadu_pd(b.add(d)),
            step_even,
        );
    }
    // The odd minimum wins when smaller, or equal at an earlier step.
    let merge = |value: usize| {
        let smaller = _mm256_cmp_pd::<_CMP_LT_OQ>(odd[value], even[value]);
        let equal = _mm256_cmp_pd::<_CMP_EQ_OQ>(odd[value], even[value]);
        let earlier = _mm256_cmp_pd::<_CMP_LT_OQ>(odd[value + 1], even[value + 1]);
        let take = _mm256_or_pd(smaller, _mm256_and_pd(equal, earlier));
        (_mm256_blendv_pd(even[value], odd[value], take), _mm256_blendv_pd(even[value + 1], odd[value + 1], take))
    };
    let ((all, all_step), (shift, shift_step)) = (merge(0), merge(2));
    MinsAvx2 { all, all_step, shift, shift_step }
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
            return unsafe { block_mins_same_avx2(costs, steps, to_go) };
        }
    }
    block_mins_portable(costs, steps, to_go, to_go)
}

/// [`block_mins_same`] in AVX2, with the two chains of [`block_mins_avx2`].
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn block_mins_same_avx2(costs: &[f64], steps: usize, to_go: &[f64]) -> LaneMins {
    block_mins_same_avx2_regs(costs, steps, to_go).lane_mins()
}

/// [`block_mins_same_avx2`], left in registers.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn block_mins_same_avx2_regs(costs: &[f64], steps: usize, to_go: &[f64]) -> MinsAvx2 {
    use std::arch::x86_64::*;
    const _: () = assert!(LANES == 4);
    let (c, a) = (costs.as_ptr(), to_go.as_ptr());
    let inf = _mm256_set1_pd(INF);
    let zero = _mm256_setzero_pd();
    let mut even = [inf, zero];
    let mut odd = [inf, zero];
    #[inline(always)]
    unsafe fn step_into(acc: &mut [__m256d; 2], cost: __m256d, to_go: __m256d, step: __m256d) {
        let x = _mm256_add_pd(cost, to_go);
        let better = _mm256_cmp_pd::<_CMP_LT_OQ>(x, acc[0]);
        acc[0] = _mm256_blendv_pd(acc[0], x, better);
        acc[1] = _mm256_blendv_pd(acc[1], step, better);
    }
    let two = _mm256_set1_pd(2.0);
    let (mut step_even, mut step_odd) = (zero, _mm256_set1_pd(1.0));
    let mut d = 0;
    while d + 1 < steps {
        // SAFETY: the caller checked costs.len() = steps·LANES and to_go ≥ steps + LANES − 1.
        step_into(&mut even, _mm256_loadu_pd(c.add(d * LANES)), _mm256_loadu_pd(a.add(d)), step_even);
        step_into(&mut odd, _mm256_loadu_pd(c.add((d + 1) * LANES)), _mm256_loadu_pd(a.add(d + 1)), step_odd);
        step_even = _mm256_add_pd(step_even, two);
        step_odd = _mm256_add_pd(step_odd, two);
        d += 2;
    }
    if d < steps {
        step_into(&mut even, _mm256_loadu_pd(c.add(d * LANES)), _mm256_loadu_pd(a.add(d)), step_even);
    }
    let smaller = _mm256_cmp_pd::<_CMP_LT_OQ>(odd[0], even[0]);
    let equal = _mm256_cmp_pd::<_CMP_EQ_OQ>(odd[0], even[0]);
    let earlier = _mm256_cmp_pd::<_CMP_LT_OQ>(odd[1], even[1]);
    let take = _mm256_or_pd(smaller, _mm256_and_pd(equal, earlier));
    let (all, all_step) = (_mm256_blendv_pd(even[0], odd[0], take), _mm256_blendv_pd(even[1], odd[1], take));
    MinsAvx2 { all, all_step, shift: all, shift_step: all_step }
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

/// The AVX2 kernels; a value exists only where the CPU has AVX2.
#[cfg(target_arch = "x86_64")]
#[derive(Debug, Clone, Copy)]
pub struct Avx2(());

#[cfg(target_arch = "x86_64")]
impl Avx2 {
    /// The AVX2 kernels if the CPU has AVX2.
    #[inline]
    pub fn detect() -> Option<Avx2> {
        std::arch::is_x86_feature_detected!("avx2").then_some(Avx2(()))
    }
}

#[cfg(target_arch = "x86_64")]
impl Kernels for Avx2 {
    /// The minima go from registers to `out`, with no [`LaneMins`] in memory between.
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
        // SAFETY: an `Avx2` exists only where the CPU has AVX2; the lengths are checked by
        // `block_slices`.
        unsafe {
            match shiftable {
                Some(shiftable) => block_mins_avx2_regs(costs, steps, to_go, shiftable),
                None => block_mins_same_avx2_regs(costs, steps, to_go),
            }
            .write(base, out)
        }
    }
}

/// Lane helpers for the AVX2 passes of the solver (x86-64 only).
///
/// Gathers are replaced by four scalar loads: on the AMD cores this project is measured on (Zen 2
/// and earlier) a gather is microcoded and several times slower than the loads it stands for.
#[cfg(target_arch = "x86_64")]
pub mod lanes {
    use std::arch::x86_64::*;

    /// The 32-bit halves of four 64-bit lane masks (each all ones or all zeros), in lane order.
    ///
    /// # Safety
    /// The CPU must have AVX2.
    #[target_feature(enable = "avx2")]
    #[inline]
    pub unsafe fn pack(mask: __m256d) -> __m128i {
        let m = _mm256_castpd_ps(mask);
        _mm_castps_si128(_mm_shuffle_ps::<0b10_00_10_00>(_mm256_castps256_ps128(m), _mm256_extractf128_ps::<1>(m)))
    }

    /// Four 32-bit lane masks widened to 64-bit lanes.
    ///
    /// # Safety
    /// The CPU must have AVX2.
    #[target_feature(enable = "avx2")]
    #[inline]
    pub unsafe fn widen(mask: __m128i) -> __m256d {
        _mm256_castsi256_pd(_mm256_cvtepi32_epi64(mask))
    }

    /// The four lanes of `index` as indices.
    #[target_feature(enable = "avx2")]
    #[inline]
    unsafe fn indices(index: __m128i) -> [usize; 4] {
        let mut at = [0u32; 4];
        _mm_storeu_si128(at.as_mut_ptr().cast(), index);
        at.map(|i| i as usize)
    }

    /// `values[index]` per lane.
    ///
    /// # Safety
    /// The CPU must have AVX2, and every lane of `index` (as u32) must be within `values`.
    #[target_feature(enable = "avx2")]
    #[inline]
    pub unsafe fn load_u32(values: &[u32], index: __m128i) -> __m128i {
        let [a, b, c, d] = indices(index);
        debug_assert!([a, b, c, d].iter().all(|&i| i < values.len()), "lane index out of bounds");
        let v = values.as_ptr();
        _mm_setr_epi32(*v.add(a) as i32, *v.add(b) as i32, *v.add(c) as i32, *v.add(d) as i32)
    }

    /// `values[index]` per lane.
    ///
    /// # Safety
    /// The CPU must have AVX2, and every lane of `index` (as u32) must be within `values`.
    #[target_feature(enable = "avx2")]
    #[inline]
    pub unsafe fn load_f64(values: &[f64], index: __m128i) -> __m256d {
        let [a, b, c, d] = indices(index);
        debug_assert!([a, b, c, d].iter().all(|&i| i < values.len()), "lane index out of bounds");
        let v = values.as_ptr();
        _mm256_setr_pd(*v.add(a), *v.add(b), *v.add(c), *v.add(d))
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Deterministic pseudo-random costs with ties and +∞ (a small LCG: no dependency).
    fn costs(seed: &mut u64, n: usize) -> Vec<f64> {
        (0..n)
            .map(|_| {
                *seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
                match (*seed >> 33) % 7 {
                    0 => INF,
                    1 => 1.5,
                    k => (k as f64) * 0.25 + ((*seed >> 40) % 5) as f64 * 1e-3,
                }
            })
            .collect()
    }

    #[test]
    fn block_mins_equal_per_lane_scalar_scans() {
        let mut seed = 3;
        for steps in 0..40 {
            for _ in 0..20 {
                let costs = costs(&mut seed, steps * LANES);
                let (to_go, shiftable) =
                    (costs_of(&mut seed, steps + LANES - 1), costs_of(&mut seed, steps + LANES - 1));
                let got = block_mins(&costs, steps, &to_go, &shiftable);
                assert_eq!(
                    got,
                    block_mins_portable(
                        &costs[..steps * LANES],
                        steps,
                        &to_go[..steps + LANES - 1],
                        &shiftable[..steps + LANES - 1]
                    )
                );
                for l in 0..LANES {
                    let row: Vec<f64> = (0..steps).map(|d| costs[d * LANES + l]).collect();
                    let (a, t) = argmin_sum_scalar(&row, &to_go[l..]);
                    let (b, u) = argmin_sum_scalar(&row, &shiftable[l..]);
                    assert_eq!(
                        (got.all[l].to_bits(), got.all_step[l] as usize),
                        (a.to_bits(), t),
                        "steps {steps} lane {l}"
                    );
                    assert_eq!(
                        (got.shift[l].to_bits(), got.shift_step[l] as usize),
                        (b.to_bits(), u),
                        "steps {steps} lane {l}"
                    );
                }
            }
        }
    }

    #[test]
    fn one_minimum_when_both_to_go_are_the_same() {
        let mut seed = 7;
        for steps in 0..40 {
            for _ in 0..20 {
                let costs = costs(&mut seed, steps * LANES);
                let to_go = costs_of(&mut seed, steps + LANES - 1);
                assert_eq!(
                    block_mins_same(&costs, steps, &to_go),
                    block_mins(&costs, steps, &to_go, &to_go),
                    "steps {steps}"
                );
            }
        }
    }

    /// The outputs of `block_mins_to` for `kernels`: minima and next-grid indices, as bits.
    fn written<K: Kernels>(
        kernels: K,
        costs: &[f64],
        steps: usize,
        values: (&[f64], Option<&[f64]>),
        base: u32,
    ) -> Vec<u64> {
        let (mut all, mut all_j, mut shift, mut shift_j) = ([0.0; LANES], [0; LANES], [0.0; LANES], [0; LANES]);
        let out = LaneOut { all: &mut all, all_j: &mut all_j, shift: &mut shift, shift_j: &mut shift_j };
        kernels.block_mins_to((costs, steps), values.0, values.1, base, out);
        let floats = all.iter().chain(&shift).map(|x| x.to_bits());
        floats.chain(all_j.iter().chain(&shift_j).map(|&j| j as u64)).collect()
    }

    #[cfg(target_arch = "x86_64")]
    #[test]
    fn avx2_writes_what_the_portable_kernels_write() {
        let Some(avx2) = Avx2::detect() else { return };
        let mut seed = 11;
        for steps in 0..30 {
            for (i, base) in [0u32, 7, u32::MAX - 2].into_iter().enumerate() {
                let costs = costs(&mut seed, steps * LANES);
                let (to_go, shiftable) =
                    (costs_of(&mut seed, steps + LANES - 1), costs_of(&mut seed, steps + LANES - 1));
                let shiftable = (i != 1).then_some(&shiftable[..]);
                assert_eq!(
                    written(avx2, &costs, steps, (&to_go, shiftable), base),
                    written(Portable, &costs, steps, (&to_go, shiftable), base),
                    "steps {steps} base {base}"
                );
            }
        }
    }

    /// `costs` of at least one value (a block's value slices are never empty).
    fn costs_of(seed: &mut u64, n: usize) -> Vec<f64> {
        costs(seed, n.max(LANES - 1))
    }

    #[test]
    fn all_infinite_lanes_give_infinity_at_step_zero() {
        let got = block_mins(&[INF; 3 * LANES], 3, &[1.0; 3 + LANES - 1], &[INF; 3 + LANES - 1]);
        assert_eq!(
            got,
            LaneMins { all: [INF; LANES], all_step: [0; LANES], shift: [INF; LANES], shift_step: [0; LANES] }
        );
    }
}

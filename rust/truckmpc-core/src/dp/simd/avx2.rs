//! The AVX2 kernels of the min-plus pass (x86-64 only, used where the CPU has AVX2): the same
//! additions, comparisons and selects as the portable kernels of [`super`], four lanes at a time,
//! so the same bits. Costs are a stage's transition costs plus cost-to-go (units of (5.9)); steps
//! are offsets on the next stage's grid.

use super::{block_slices, Kernels, LaneMins, LaneOut, INF};
use crate::dp::cache::LANES;

/// [`block_mins`](super::block_mins) in AVX2: one 4-wide step per d. Only additions, comparisons,
/// minima and blends, so the results are those of the portable version bit for bit.
///
/// Each running minimum is a chain of compare and blend from one step to the next, whose latency
/// (not the instruction count) bounds the loop. So even and odd steps keep separate minima, two
/// chains that run side by side, merged at the end: the smaller value, and of equal values the
/// earlier step, which is what one scan keeping the first strict improvement finds.
#[target_feature(enable = "avx2")]
#[inline]
pub(super) unsafe fn block_mins_avx2(costs: &[f64], steps: usize, to_go: &[f64], shiftable: &[f64]) -> LaneMins {
    block_mins_avx2_regs(costs, steps, to_go, shiftable).lane_mins()
}

/// A block's lane minima in AVX2 registers: values, and steps as f64 lanes.
#[derive(Clone, Copy)]
struct MinsAvx2 {
    all: std::arch::x86_64::__m256d,
    all_step: std::arch::x86_64::__m256d,
    shift: std::arch::x86_64::__m256d,
    shift_step: std::arch::x86_64::__m256d,
}

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

/// [`block_mins_same`](super::block_mins_same) in AVX2, with the two chains of [`block_mins_avx2`].
#[target_feature(enable = "avx2")]
#[inline]
pub(super) unsafe fn block_mins_same_avx2(costs: &[f64], steps: usize, to_go: &[f64]) -> LaneMins {
    block_mins_same_avx2_regs(costs, steps, to_go).lane_mins()
}

/// [`block_mins_same_avx2`], left in registers.
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

/// The AVX2 kernels; a value exists only where the CPU has AVX2.
#[derive(Debug, Clone, Copy)]
pub struct Avx2(());

impl Avx2 {
    /// The AVX2 kernels if the CPU has AVX2.
    #[inline]
    pub fn detect() -> Option<Avx2> {
        std::arch::is_x86_feature_detected!("avx2").then_some(Avx2(()))
    }
}

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

//! Lane helpers for the AVX2 passes of the solver (x86-64 only).
//!
//! Gathers are replaced by four scalar loads: on AMD cores up to Zen 2 a gather is microcoded and
//! slower than the loads it stands for.

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

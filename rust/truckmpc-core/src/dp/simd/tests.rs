//! The kernels against per-lane scalar scans, and the AVX2 kernels against the portable ones.

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
            let (to_go, shiftable) = (costs_of(&mut seed, steps + LANES - 1), costs_of(&mut seed, steps + LANES - 1));
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
            let (to_go, shiftable) = (costs_of(&mut seed, steps + LANES - 1), costs_of(&mut seed, steps + LANES - 1));
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
    assert_eq!(got, LaneMins { all: [INF; LANES], all_step: [0; LANES], shift: [INF; LANES], shift_step: [0; LANES] });
}

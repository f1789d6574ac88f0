//! The exact arcs and their joins: over a stage with an input held (neutral coasting, fuel cut at
//! zero pedal, full pedal on trapezoid stages, or a pedal level of `pedal_levels`) the end speed
//! [m/s] falls off the grid, so each arc is joined to the next grid by a rule (nearest point, linear
//! or quadratic interpolation of the cost-to-go) within the target gear's states. Costs in the
//! units of (5.9).

use super::choices::Choices;
use super::grids::StageGrid;
use super::{Avx2Token, INF};
use crate::dp::cache::{CoastArc, Keyed};
use crate::dp::params::{DpSettings, NeutralRule};
use crate::dp::rows::change_cost;
#[cfg(target_arch = "x86_64")]
use crate::dp::simd::lanes::{self, pack, widen};
use crate::dp::stage::{self, Branch};
use crate::vehicle::{Vehicle, NEUTRAL};

/// The coasting arc from `v_i_mps` in `gear` on a stage: zero pedal and brake, the speed where the
/// physics ends it (engine drag braking in a forward gear, none in neutral), and its fuel (idle
/// fuel in neutral, none at fuel cut) and speed-change cost.
pub(super) fn coast_arc(p: &DpSettings, vehicle: &Vehicle, v_i_mps: f64, gear: usize, slope_torque: f64) -> CoastArc {
    exact_arc(p, vehicle, v_i_mps, gear, slope_torque, (Branch::Brake, 0.0))
}

/// The exact arc from `v_i_mps` in `gear` with `input` held over a stage (fuel cut or coasting
/// with the brake branch at zero, full pedal with the pedal branch at one): its end speed, off the
/// grid, and its cost Q1·fuel + speed change.
pub(super) fn exact_arc(
    p: &DpSettings,
    vehicle: &Vehicle,
    v_i_mps: f64,
    gear: usize,
    slope_torque: f64,
    input: (Branch, f64),
) -> CoastArc {
    let h = p.mpc.stage_m;
    let v_end_mps = stage::end_speed(p.mpc.stage_model, vehicle, (v_i_mps, h), gear, slope_torque, input);
    let pedal = if input.0 == Branch::Pedal { input.1 } else { 0.0 };
    let fuel = stage::fuel_g(p.mpc.stage_model, vehicle, (v_i_mps, v_end_mps), pedal, gear, h);
    let change = change_cost(p.mpc.q_speed_change, p.q_speed_change_sq, v_i_mps - v_end_mps);
    CoastArc { v_end_mps, cost: p.mpc.q_fuel * fuel + change }
}

/// The first pass into neutral: every source's coasting arc (keys `key_lo..=key_hi` of the stage
/// grid `here`, filled into `arcs` where missing) joined to neutral's states `lo..=hi` of the next
/// grid by the neutral rule, against neutral's cost-to-go and counters (`values`, from state 0);
/// into neutral's choices, the shift choices with the price of an engagement.
pub(super) fn neutral_choices(
    p: &DpSettings,
    vehicle: &Vehicle,
    arcs: &mut Keyed<CoastArc>,
    (here, next): (StageGrid, StageGrid),
    slope_torque: f64,
    (key_lo, key_hi): (i64, i64),
    (lo, hi): (u32, u32),
    (cost_next, counter_next): (&[f64], &[u32]),
    avx2: Option<Avx2Token>,
    ch: &mut Choices,
) {
    let out = NEUTRAL * ch.width;
    arcs.fill(key_lo, key_hi, |key| coast_arc(p, vehicle, here.index.speed(key), NEUTRAL, slope_torque));
    let slot0 = (key_lo - ch.base_key) as usize;
    let join = ArcJoin::new(p, next, (lo, hi));
    let arcs = arcs.get(key_lo, key_hi);
    let (slots, at) = (slot0..slot0 + arcs.len(), out + slot0..out + slot0 + arcs.len());
    let (all_cost, all_j) = (&mut ch.all_cost[at.clone()], &mut ch.all_j[at.clone()]);
    let (shift_cost, shift_j) = (&mut ch.shift_cost[at.clone()], &mut ch.shift_j[at]);
    let counters = &mut ch.neutral_counter[slots];
    let mut done = 0;
    #[cfg(target_arch = "x86_64")]
    if let (NeutralRule::Nearest, Some(_)) = (p.mpc.neutral_rule, avx2) {
        let out = NeutralOut { all_cost, all_j, counters, shift_cost, shift_j };
        // SAFETY: the token exists only where the CPU has AVX2.
        done = unsafe { join_nearest_avx2(&join, arcs, (cost_next, counter_next), p.k_lim, out) };
    }
    for (s, arc) in arcs.iter().enumerate().skip(done) {
        let (cost, j, counter) = join.join(arc, cost_next, counter_next);
        (all_cost[s], all_j[s], counters[s]) = (cost, j, counter);
        (shift_cost[s], shift_j[s]) = (if counter >= p.k_lim { cost } else { INF }, j);
    }
    // Shifting into neutral from a forward gear is an engagement: its price, in place of
    // Q4 (which the second pass adds to every shift) where Q4 prices forward shifts only.
    let engagement = p.mpc.q_neutral - if p.mpc.shift_price_neutral { 0.0 } else { p.mpc.q_gear_shift };
    if engagement != 0.0 {
        shift_cost.iter_mut().for_each(|c| *c += engagement);
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = avx2;
}

/// Let an arc of cost `cost` (cost-to-go included) to grid point `j` (with its
/// [`ARC`](super::choices::ARC) or [`FULL`](super::choices::FULL) flag) take choice slot `at` where
/// it is strictly cheaper, and the shift choice too when its continuation allows a shift.
#[inline]
pub(super) fn better_by_arc(cost: f64, j: u32, shiftable: bool, ch: &mut Choices, at: usize) {
    if cost < ch.all_cost[at] {
        (ch.all_cost[at], ch.all_j[at]) = (cost, j);
    }
    if shiftable && cost < ch.shift_cost[at] {
        (ch.shift_cost[at], ch.shift_j[at]) = (cost, j);
    }
}

/// Joins coasting arcs to the next grid by the configured rule (`neutral_rule`), within the target
/// gear's index range, with the stage's constants computed once.
pub(super) struct ArcJoin {
    pub(super) rule: NeutralRule,
    /// Whether an arc ending less than a grid step above the top state is joined to it, its
    /// cost-to-go extrapolated linearly from the two top states (full-pedal arcs: the top of the
    /// next stage is the grid speed full pedal reaches from the top of this one, so the arc from
    /// the top ends above it, and without this the top state could only stay at the top with a
    /// little less than full pedal, giving away power on every climb).
    pub(super) extrapolate_top: bool,
    /// Speed of next-grid index 0 [m/s].
    pub(super) origin_mps: f64,
    pub(super) delta_mps: f64,
    pub(super) lo: u32,
    pub(super) hi: u32,
}

impl ArcJoin {
    pub(super) fn new(p: &DpSettings, next: StageGrid, (lo, hi): (u32, u32)) -> Self {
        ArcJoin {
            rule: p.mpc.neutral_rule,
            extrapolate_top: false,
            origin_mps: next.speed(0),
            delta_mps: p.delta_mps(),
            lo,
            hi,
        }
    }

    /// The join of full-pedal arcs ([`ArcJoin::extrapolate_top`]).
    pub(super) fn full_pedal(p: &DpSettings, next: StageGrid, range: (u32, u32)) -> Self {
        ArcJoin { extrapolate_top: true, ..Self::new(p, next, range) }
    }

    /// (cost with the cost-to-go, next-grid index, counter of the continuation); cost +∞ when
    /// the arc ends off the states.
    #[inline]
    pub(super) fn join(&self, arc: &CoastArc, cost_next: &[f64], counter_next: &[u32]) -> (f64, u32, u32) {
        const NONE: (f64, u32, u32) = (INF, 0, 0);
        let (lo, hi) = (self.lo, self.hi);
        let x = (arc.v_end_mps - self.origin_mps) / self.delta_mps;
        if self.extrapolate_top && x > hi as f64 && x <= hi as f64 + 1.0 && hi > lo {
            let (top, below) = (cost_next[hi as usize], cost_next[hi as usize - 1]);
            if !(top.is_finite() && below.is_finite()) {
                return NONE;
            }
            let to_go = top + (x - hi as f64) * (top - below);
            return (arc.cost + to_go, hi, counter_next[hi as usize]);
        }
        // Grid indices are never negative; x below −0.5 is outside the grid either way.
        if x < lo as f64 - 0.5 || x > hi as f64 + 0.5 {
            return NONE;
        }
        let (to_go, j, counter) = match self.rule {
            NeutralRule::Nearest => {
                let j = (x + 0.5) as usize; // round half up without a libm call; x + 0.5 >= 0 here
                if j < lo as usize || j > hi as usize {
                    return NONE;
                }
                (cost_next[j], j, counter_next[j])
            }
            NeutralRule::Interpolate => {
                const TOL: f64 = 1e-9;
                if x < lo as f64 - TOL || x > hi as f64 + TOL {
                    return NONE;
                }
                let x = x.clamp(lo as f64, hi as f64);
                let j0 = x as usize;
                let w = x - j0 as f64;
                if w == 0.0 {
                    (cost_next[j0], j0, counter_next[j0])
                } else {
                    let to_go = (1.0 - w) * cost_next[j0] + w * cost_next[j0 + 1];
                    let nearest = if w < 0.5 { j0 } else { j0 + 1 };
                    (to_go, nearest, counter_next[j0].min(counter_next[j0 + 1]))
                }
            }
            NeutralRule::Quadratic => match quadratic_to_go(x, (lo, hi), cost_next, counter_next) {
                Some(found) => found,
                None => return NONE,
            },
        };
        if !to_go.is_finite() {
            return NONE;
        }
        (arc.cost + to_go, j as u32, counter)
    }
}

/// The cost-to-go at fractional grid index `x` (None outside the states `lo..=hi`)
/// through the three states around the nearest one, as (cost-to-go, nearest index, smallest
/// counter of the points used). At the ends of the states, or next to a state without a finite
/// cost, the stencil falls back to the two points bracketing `x`, then to the nearest alone when
/// `x` is within rounding of it; None when no finite cost brackets `x`.
#[inline]
pub(super) fn quadratic_to_go(
    x: f64,
    (lo, hi): (u32, u32),
    cost: &[f64],
    counter: &[u32],
) -> Option<(f64, usize, u32)> {
    const TOL: f64 = 1e-9;
    if x < lo as f64 - TOL || x > hi as f64 + TOL {
        return None;
    }
    let x = x.clamp(lo as f64, hi as f64);
    let j = (x + 0.5) as usize;
    let t = x - j as f64; // in [-0.5, 0.5]
    let (lo, hi) = (lo as usize, hi as usize);
    if j > lo && j < hi && cost[j - 1].is_finite() && cost[j].is_finite() && cost[j + 1].is_finite() {
        // Lagrange weights on (j - 1, j, j + 1) at offset t.
        let (wm, w0, wp) = (0.5 * t * (t - 1.0), 1.0 - t * t, 0.5 * t * (t + 1.0));
        let to_go = wm * cost[j - 1] + w0 * cost[j] + wp * cost[j + 1];
        let c = counter[j - 1].min(counter[j]).min(counter[j + 1]);
        return Some((to_go, j, c));
    }
    if t.abs() <= TOL {
        return cost[j].is_finite().then_some((cost[j], j, counter[j]));
    }
    let j0 = if t < 0.0 { j - 1 } else { j };
    if j0 < lo || j0 + 1 > hi || !cost[j0].is_finite() || !cost[j0 + 1].is_finite() {
        return None;
    }
    let w = x - j0 as f64;
    Some(((1.0 - w) * cost[j0] + w * cost[j0 + 1], j, counter[j0].min(counter[j0 + 1])))
}

/// Where the neutral arcs' choices go: one value per source, from the first.
#[cfg(target_arch = "x86_64")]
pub(super) struct NeutralOut<'a> {
    pub(super) all_cost: &'a mut [f64],
    pub(super) all_j: &'a mut [u32],
    pub(super) counters: &'a mut [u32],
    pub(super) shift_cost: &'a mut [f64],
    pub(super) shift_j: &'a mut [u32],
}

/// [`ArcJoin::join`] with the nearest rule (and the shiftable cost), four arcs at a time in
/// AVX2, as far as whole groups of four go and no end speed is NaN: returns the arcs done. The
/// same operations as the scalar join: the division, the range tests, the truncation of x + 0.5
/// (exact: x + 0.5 is in [0, 2^31) where it is used), the cost-to-go and counter kept only where
/// the scalar join reads them (they are loaded at the nearest state within [lo, hi] for every
/// lane), and the finiteness test.
///
/// # Safety
/// The CPU must have AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
pub(super) unsafe fn join_nearest_avx2(
    join: &ArcJoin,
    arcs: &[CoastArc],
    (cost_next, counter_next): (&[f64], &[u32]),
    k_lim: u32,
    out: NeutralOut,
) -> usize {
    use std::arch::x86_64::*;
    let n = arcs.len();
    assert!(
        out.all_cost.len() == n
            && out.all_j.len() == n
            && out.counters.len() == n
            && out.shift_cost.len() == n
            && out.shift_j.len() == n
    );
    // The loads below read indices within [lo, hi] only; the values must hold them.
    if join.lo > join.hi || (join.hi as usize) >= cost_next.len().min(counter_next.len()) || join.hi >= i32::MAX as u32
    {
        return 0;
    }
    let groups = n / 4 * 4;
    let (origin, delta) = (_mm256_set1_pd(join.origin_mps), _mm256_set1_pd(join.delta_mps));
    let (below, above) = (_mm256_set1_pd(join.lo as f64 - 0.5), _mm256_set1_pd(join.hi as f64 + 0.5));
    let half = _mm256_set1_pd(0.5);
    let inf = _mm256_set1_pd(INF);
    let sign = _mm256_set1_pd(-0.0);
    let (lo, hi) = (_mm_set1_epi32(join.lo as i32), _mm_set1_epi32(join.hi as i32));
    let k_lim = _mm_set1_epi32(k_lim as i32);
    let mut t = 0;
    while t < groups {
        // (v_end, cost) of arcs t..t + 4, as [v0 c0 v1 c1] [v2 c2 v3 c3].
        let a = _mm256_loadu_pd(arcs.as_ptr().add(t).cast());
        let b = _mm256_loadu_pd(arcs.as_ptr().add(t + 2).cast());
        let v_end = _mm256_permute4x64_pd::<0b11_01_10_00>(_mm256_unpacklo_pd(a, b));
        let arc_cost = _mm256_permute4x64_pd::<0b11_01_10_00>(_mm256_unpackhi_pd(a, b));
        let x = _mm256_div_pd(_mm256_sub_pd(v_end, origin), delta);
        if _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_UNORD_Q>(x, x)) != 0 {
            break;
        }
        let near = _mm256_and_pd(_mm256_cmp_pd::<_CMP_GE_OQ>(x, below), _mm256_cmp_pd::<_CMP_LE_OQ>(x, above));
        let j = _mm256_cvttpd_epi32(_mm256_add_pd(x, half));
        let in_states = _mm_andnot_si128(_mm_or_si128(_mm_cmpgt_epi32(lo, j), _mm_cmpgt_epi32(j, hi)), pack(near));
        // Loaded at the nearest state (clamped into [lo, hi]), kept only where it is a state.
        let state = _mm_min_epi32(_mm_max_epi32(j, lo), hi);
        let to_go = lanes::load_f64(cost_next, state);
        let finite = _mm256_cmp_pd::<_CMP_LT_OQ>(_mm256_andnot_pd(sign, to_go), inf);
        let ok = _mm_and_si128(in_states, pack(finite));
        let counter = _mm_and_si128(lanes::load_u32(counter_next, state), ok);
        let cost = _mm256_blendv_pd(inf, _mm256_add_pd(arc_cost, to_go), widen(ok));
        let j = _mm_and_si128(j, ok);
        let shiftable = widen(_mm_cmpeq_epi32(_mm_max_epu32(counter, k_lim), counter));
        _mm256_storeu_pd(out.all_cost.as_mut_ptr().add(t), cost);
        _mm_storeu_si128(out.all_j.as_mut_ptr().add(t).cast(), j);
        _mm_storeu_si128(out.counters.as_mut_ptr().add(t).cast(), counter);
        _mm256_storeu_pd(out.shift_cost.as_mut_ptr().add(t), _mm256_blendv_pd(inf, cost, shiftable));
        _mm_storeu_si128(out.shift_j.as_mut_ptr().add(t).cast(), j);
        t += 4;
    }
    t
}

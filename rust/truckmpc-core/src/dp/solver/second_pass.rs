//! The second pass of a stage (stay or shift): for every state, staying in its gear against the
//! best shift into another (plus Q4), plus the speed-deviation cost Q2 (and with the fuel_time
//! cost the stage's time); writes J_k, the shift counters [stages] and the decisions. The AVX2
//! versions give the scalar loops' bits.

use super::choices::{Decision, FLAGS, NO_GEAR};
use super::grids::StageGrid;
use super::{stride, Avx2Token, Solver, INF};
use crate::dp::cache::PAD;
#[cfg(target_arch = "x86_64")]
use crate::dp::simd::lanes::{self, pack, widen};
use crate::dp::space;
use crate::vehicle::{Vehicle, NEUTRAL};
use std::ops::Range;

impl Solver {
    /// Second pass of a stage: for every state, stay in its gear or take the best shift, plus the
    /// speed-deviation cost; writes J_k, the counters and the decisions.
    pub(super) fn stay_or_shift(
        &mut self,
        vehicle: &Vehicle,
        k: usize,
        (i_lo, i_hi): (usize, usize),
        active_here: &[usize],
        active_next: &[usize],
        (start_gear, gears): (usize, usize),
    ) {
        let (here, next) = (self.grids[k], self.grids[k + 1]);
        let n = here.count;
        let (q4, k_lim) = (self.params.mpc.q_gear_shift, self.params.k_lim);
        // Slot of source velocity i.
        let s0 = (here.first - self.choices.base_key) as usize;
        let sources = s0 + i_lo..s0 + i_hi + 1;
        // A shift between forward gears that interrupts traction has its own ways (the stage
        // starts with the roll); leaving neutral does not, so neutral ranks its exits itself.
        let interrupting = crate::dp::shift::planned(&self.params, vehicle);
        self.rank_shifts(sources.clone(), active_next, interrupting);
        self.source_penalties(k, sources.clone(), i_lo);
        let p = &self.params;
        let exit_own = active_here.contains(&NEUTRAL)
            && (interrupting || p.mpc.neutral_exit_top_gear || !p.mpc.shift_price_neutral);
        if exit_own {
            self.neutral_exits(vehicle, here, sources, (i_lo, interrupting), active_next);
        }
        let ch = &self.choices;
        let stride_n = stride(next.count);
        for &g_i in active_here {
            let (lo, hi) = self.gear_ranges[k * gears + g_i];
            if (k == 0 && g_i != start_gear) || hi < lo {
                continue;
            }
            let stays = active_next.contains(&g_i);
            let (lo, hi) = (lo as usize, hi as usize);
            let slots = s0 + lo..s0 + hi + 1;
            let out = g_i * ch.width + slots.start..g_i * ch.width + slots.end;
            let values = g_i * stride(n) + PAD + lo..g_i * stride(n) + PAD + hi + 1;
            let decisions = self.offsets[k] + g_i * n + lo..self.offsets[k] + g_i * n + hi + 1;
            let state = StateOut {
                cost: &mut self.cost_cur[values.clone()],
                counter: &mut self.counter_cur[values.clone()],
                shift: &mut self.shift_cur[values],
                decision: &mut self.decisions[decisions],
            };
            let (ranked, ranked_gears) = if exit_own && g_i == NEUTRAL {
                ([&ch.exit_cost, &ch.exit2_cost], [&ch.exit_gear, &ch.exit2_gear])
            } else {
                ([&ch.first_cost, &ch.second_cost], [&ch.first_gear, &ch.second_gear])
            };
            let ranked = ranked.map(|costs| &costs[slots.clone()]);
            let ranked_gears = ranked_gears.map(|gears| &gears[slots.clone()]);
            let input = StateIn {
                gear: g_i as u32,
                slot0: slots.start,
                all_cost: &ch.all_cost[out.clone()],
                all_j: &ch.all_j[out],
                first_cost: ranked[0],
                first_gear: ranked_gears[0],
                second_cost: ranked[1],
                second_gear: ranked_gears[1],
                neutral_counter: &ch.neutral_counter[slots.clone()],
                penalty: &ch.penalty[slots],
                shift_j: if interrupting && g_i != NEUTRAL { &ch.ishift_j } else { &ch.shift_j },
                width: ch.width,
                counter_next: &self.counter_next[g_i * stride_n + PAD..(g_i + 1) * stride_n],
                q4,
                k_lim,
            };
            self.shift_same_cur[g_i] = match (stays, g_i == NEUTRAL) {
                (false, _) => decide_states::<false, false>(input, state, None),
                (true, false) => decide_states::<true, false>(input, state, self.avx2),
                (true, true) => decide_states::<true, true>(input, state, self.avx2),
            };
            // The rest of the gear's block (no state there) is +∞ for the min-plus pass.
            let block = g_i * stride(n)..(g_i + 1) * stride(n);
            for part in [block.start..block.start + PAD + lo, block.start + PAD + hi + 1..block.end] {
                self.cost_cur[part.clone()].fill(INF);
                self.shift_cur[part].fill(INF);
            }
        }
    }

    /// The two best shift targets per velocity (choice slots `sources`), so that each state's best
    /// shift to another gear is O(1): among the ways that start with a shift's interruption where
    /// `interrupting`. Gears are scanned in order, keeping the first of equal costs.
    fn rank_shifts(&mut self, sources: Range<usize>, active_next: &[usize], interrupting: bool) {
        let ch = &mut self.choices;
        for &g in active_next {
            let all = if interrupting { &ch.ishift_cost } else { &ch.shift_cost };
            let costs = &all[g * ch.width + sources.start..g * ch.width + sources.end];
            let first_cost = &mut ch.first_cost[sources.clone()];
            let first_gear = &mut ch.first_gear[sources.clone()];
            let second_cost = &mut ch.second_cost[sources.clone()];
            let second_gear = &mut ch.second_gear[sources.clone()];
            let m = costs.len();
            assert!(first_cost.len() == m && first_gear.len() == m && second_cost.len() == m && second_gear.len() == m);
            let mut done = 0;
            #[cfg(target_arch = "x86_64")]
            if self.avx2.is_some() {
                // SAFETY: the token exists only where the CPU has AVX2; the lengths are checked above.
                done = unsafe { rank_avx2(costs, g as u32, (first_cost, first_gear), (second_cost, second_gear)) };
            }
            for t in done..m {
                let c = costs[t];
                if c < first_cost[t] {
                    (second_cost[t], second_gear[t]) = (first_cost[t], first_gear[t]);
                    (first_cost[t], first_gear[t]) = (c, g as u32);
                } else if c < second_cost[t] {
                    (second_cost[t], second_gear[t]) = (c, g as u32);
                }
            }
        }
    }

    /// The speed-deviation cost of each source velocity of stage `k` (choice slots `sources`, the
    /// first of velocity `i_lo`), once for all its gears (the same operations as per state, so the
    /// same bits).
    fn source_penalties(&mut self, k: usize, sources: Range<usize>, i_lo: usize) {
        let here = self.grids[k];
        let v_ref = self.bands[k].v_ref_mps();
        let q_speed_below = self.params.q_speed_below;
        let ch = &mut self.choices;
        for (slot, i) in ch.penalty[sources.clone()].iter_mut().zip(i_lo..) {
            let below = (v_ref - here.speed(i)).max(0.0);
            *slot = q_speed_below * below * below;
        }
        // The fuel_time cost's time: h / v_i per stage, exact to second order in S along a path
        // (the left sum differs from the trapezoid by the constant first term and half the last).
        let q_time = self.params.q_time_per_s * self.params.mpc.stage_m;
        if q_time > 0.0 {
            for (slot, i) in ch.penalty[sources].iter_mut().zip(i_lo..) {
                *slot += q_time / here.speed(i);
            }
        }
    }

    /// The neutral state's own two best shifts per velocity (`exit_cost`, `exit2_cost`) where they
    /// differ from every other state's (choice slots `sources`, the first of velocity `i_lo`; with
    /// `interrupting`, ranked here among the ways without an interruption).
    fn neutral_exits(
        &mut self,
        vehicle: &Vehicle,
        here: StageGrid,
        sources: Range<usize>,
        (i_lo, interrupting): (usize, bool),
        active_next: &[usize],
    ) {
        let p = &self.params;
        let q4 = p.mpc.q_gear_shift;
        let ch = &mut self.choices;
        // Leaving neutral is not charged Q4 where Q4 prices forward shifts only (the second
        // pass adds Q4 to every shift), and goes only into the highest usable gear where so set.
        let free = if p.mpc.shift_price_neutral { 0.0 } else { q4 };
        let (n_min, n_max) = (p.mpc.n_min_rpm, p.mpc.n_max_rpm);
        for (slot, i) in sources.zip(i_lo..) {
            let (exit, second) = if p.mpc.neutral_exit_top_gear {
                let top = space::usable_gears(vehicle, here.speed(i), n_min, n_max).map(|(_, hi)| hi);
                let exit = match top {
                    Some(g) if active_next.contains(&g) => (ch.shift_cost[g * ch.width + slot], g as u32),
                    _ => (INF, NO_GEAR),
                };
                (exit, (INF, NO_GEAR))
            } else if interrupting {
                best_two(&ch.shift_cost, ch.width, slot, active_next)
            } else {
                ((ch.first_cost[slot], ch.first_gear[slot]), (ch.second_cost[slot], ch.second_gear[slot]))
            };
            (ch.exit_cost[slot], ch.exit_gear[slot]) = (exit.0 - free, exit.1);
            (ch.exit2_cost[slot], ch.exit2_gear[slot]) = (second.0 - free, second.1);
        }
    }
}

/// The two cheapest of `costs` [gear * width + slot] over the gears `active`, the first of equal
/// costs kept (as [`Solver::rank_shifts`] ranks): ((cost, gear), (cost, gear)).
fn best_two(costs: &[f64], width: usize, slot: usize, active: &[usize]) -> ((f64, u32), (f64, u32)) {
    let (mut first, mut second) = ((INF, NO_GEAR), (INF, NO_GEAR));
    for &g in active {
        let c = costs[g * width + slot];
        if c < first.0 {
            (second, first) = (first, (c, g as u32));
        } else if c < second.0 {
            second = (c, g as u32);
        }
    }
    (first, second)
}

/// What the second pass reads for the states of one gear at one stage (slices over its states).
pub(super) struct StateIn<'a> {
    pub(super) gear: u32,
    /// Choice slot of the first state.
    pub(super) slot0: usize,
    pub(super) all_cost: &'a [f64],
    pub(super) all_j: &'a [u32],
    pub(super) first_cost: &'a [f64],
    pub(super) first_gear: &'a [u32],
    pub(super) second_cost: &'a [f64],
    pub(super) second_gear: &'a [u32],
    pub(super) neutral_counter: &'a [u32],
    pub(super) penalty: &'a [f64],
    /// All gears' shift targets, [gear * width + slot].
    pub(super) shift_j: &'a [u32],
    pub(super) width: usize,
    /// The gear's counters at the next stage, from index 0.
    pub(super) counter_next: &'a [u32],
    pub(super) q4: f64,
    pub(super) k_lim: u32,
}

/// What the second pass writes for the states of one gear at one stage.
pub(super) struct StateOut<'a> {
    pub(super) cost: &'a mut [f64],
    pub(super) counter: &'a mut [u32],
    pub(super) shift: &'a mut [f64],
    pub(super) decision: &'a mut [Decision],
}

/// Stay in the gear or take the best shift to another, per state. `STAYS`: the gear has states at
/// the next stage; `NEUTRAL_STATE`: the gear is neutral (whose counter comes with its choice).
/// Returns whether every state's shiftable cost equals its cost bit for bit.
#[inline(always)]
pub(super) fn decide_states<const STAYS: bool, const NEUTRAL_STATE: bool>(
    input: StateIn,
    mut out: StateOut,
    avx2: Option<Avx2Token>,
) -> bool {
    let m = out.cost.len();
    // Equal lengths, stated once: the loop below then needs no bounds checks on them.
    assert!(
        input.all_cost.len() == m
            && input.all_j.len() == m
            && input.first_cost.len() == m
            && input.first_gear.len() == m
            && input.second_cost.len() == m
            && input.second_gear.len() == m
            && input.neutral_counter.len() == m
            && input.penalty.len() == m
    );
    assert!(out.counter.len() == m && out.shift.len() == m && out.decision.len() == m);
    let (mut blocked, mut done) = (false, 0);
    #[cfg(target_arch = "x86_64")]
    if let (true, Some(_)) = (STAYS, avx2) {
        // SAFETY: the token exists only where the CPU has AVX2; the lengths are checked above.
        (done, blocked) = unsafe { decide_staying_avx2::<NEUTRAL_STATE>(&input, &mut out) };
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = avx2;
    for t in done..m {
        let stay_cost = if STAYS { input.all_cost[t] } else { INF };
        // The best shift to another gear. With none, its cost is +∞ and never beats staying.
        let own = input.first_gear[t] == input.gear;
        let shift_cost = (if own { input.second_cost[t] } else { input.first_cost[t] }) + input.q4;
        let (best_cost, decision, counter) = if shift_cost < stay_cost {
            let shift_gear = if own { input.second_gear[t] } else { input.first_gear[t] };
            let j = input.shift_j[shift_gear as usize * input.width + input.slot0 + t];
            (shift_cost, Decision::new(j, shift_gear), 1)
        } else {
            let j = if STAYS { input.all_j[t] } else { 0 };
            let carried = if !STAYS || !(stay_cost < INF) {
                0
            } else if NEUTRAL_STATE {
                input.neutral_counter[t]
            } else {
                input.counter_next[(j & !FLAGS) as usize]
            };
            (stay_cost, Decision::new(j, input.gear), carried.saturating_add(1).min(u32::MAX / 2))
        };
        let total = best_cost + input.penalty[t];
        out.cost[t] = total;
        out.counter[t] = counter;
        let shiftable = counter >= input.k_lim;
        // Not shiftable and not +∞: the shiftable cost (+∞) differs from the cost.
        blocked |= !shiftable & (total != INF);
        out.shift[t] = if shiftable { total } else { INF };
        out.decision[t] = decision;
    }
    // Otherwise each shiftable cost is its cost (or both are +∞): the same bits.
    !blocked
}

/// [`decide_states`] for a gear that stays, four states at a time in AVX2, as far as whole
/// groups of four go: returns the states done and whether one of them was blocked. Every value is
/// the scalar loop's: the same additions (shift + Q4, best + Q2 term), comparisons and selects,
/// and the counters' integer rules (saturating +1, at most u32::MAX / 2, ≥ k_lim). `NEUTRAL_STATE`:
/// the counter carried by staying is the neutral choice's own, not the target state's.
///
/// # Safety
/// The CPU must have AVX2, and the slices of `input` and `out` the lengths `decide_states` checks.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn decide_staying_avx2<const NEUTRAL_STATE: bool>(input: &StateIn, out: &mut StateOut) -> (usize, bool) {
    use std::arch::x86_64::*;
    let m = out.cost.len();
    if input.counter_next.is_empty() || input.shift_j.is_empty() {
        return (0, false);
    }
    let groups = m / 4 * 4;
    let inf = _mm256_set1_pd(INF);
    let q4 = _mm256_set1_pd(input.q4);
    let gear = _mm_set1_epi32(input.gear as i32);
    let one = _mm_set1_epi32(1);
    let below_max = _mm_set1_epi32((u32::MAX - 1) as i32);
    let half = _mm_set1_epi32((u32::MAX / 2) as i32);
    let k_lim = _mm_set1_epi32(input.k_lim as i32);
    let width = _mm_set1_epi32(input.width as i32);
    let lane_offsets = _mm_setr_epi32(0, 1, 2, 3);
    // A choice's index in the low half and its flag byte on top, the gear going in between.
    let index_and_flag = _mm_set1_epi32(0xff00_ffff_u32 as i32);
    let arc = _mm_set1_epi32(FLAGS as i32);
    let low8 = _mm_set1_epi32(0xff);
    // Lanes are loaded at indices clamped (as u32) into the slices, non-empty as checked above, and
    // kept only where the scalar loop reads.
    let last = |len: usize| _mm_set1_epi32((len - 1).min(u32::MAX as usize) as u32 as i32);
    let (last_counter, last_shift_j) = (last(input.counter_next.len()), last(input.shift_j.len()));
    let mut blocked = _mm256_setzero_pd();
    let mut t = 0;
    while t < groups {
        let stay = _mm256_loadu_pd(input.all_cost.as_ptr().add(t));
        let first_gear = _mm_loadu_si128(input.first_gear.as_ptr().add(t).cast());
        let second_gear = _mm_loadu_si128(input.second_gear.as_ptr().add(t).cast());
        let own = _mm_cmpeq_epi32(first_gear, gear);
        let shift_cost = _mm256_add_pd(
            _mm256_blendv_pd(
                _mm256_loadu_pd(input.first_cost.as_ptr().add(t)),
                _mm256_loadu_pd(input.second_cost.as_ptr().add(t)),
                widen(own),
            ),
            q4,
        );
        let take = _mm256_cmp_pd::<_CMP_LT_OQ>(shift_cost, stay);
        // Staying: the continuation's counter (0 when staying has no finite cost) + 1.
        let all_j = _mm_loadu_si128(input.all_j.as_ptr().add(t).cast());
        let carries = pack(_mm256_andnot_pd(take, _mm256_cmp_pd::<_CMP_LT_OQ>(stay, inf)));
        let carried = _mm_and_si128(
            if NEUTRAL_STATE {
                _mm_loadu_si128(input.neutral_counter.as_ptr().add(t).cast())
            } else {
                lanes::load_u32(input.counter_next, _mm_min_epu32(_mm_andnot_si128(arc, all_j), last_counter))
            },
            carries,
        );
        let stay_counter = _mm_min_epu32(_mm_add_epi32(_mm_min_epu32(carried, below_max), one), half);
        // Shifting: counter 1 and the target of the best other gear (looked up only when a lane
        // shifts, which most groups do not).
        let (counter, j, next_gear) = if _mm256_movemask_pd(take) == 0 {
            (stay_counter, all_j, gear)
        } else {
            let take32 = pack(take);
            let shift_gear = _mm_blendv_epi8(first_gear, second_gear, own);
            let slot = _mm_add_epi32(_mm_set1_epi32((input.slot0 + t) as i32), lane_offsets);
            let at = _mm_min_epu32(_mm_add_epi32(_mm_mullo_epi32(shift_gear, width), slot), last_shift_j);
            let shift_j = lanes::load_u32(input.shift_j, at);
            (
                _mm_blendv_epi8(stay_counter, one, take32),
                _mm_blendv_epi8(all_j, shift_j, take32),
                _mm_blendv_epi8(gear, shift_gear, take32),
            )
        };
        let total =
            _mm256_add_pd(_mm256_blendv_pd(stay, shift_cost, take), _mm256_loadu_pd(input.penalty.as_ptr().add(t)));
        let shiftable32 = _mm_cmpeq_epi32(_mm_max_epu32(counter, k_lim), counter);
        let shiftable = widen(shiftable32);
        _mm256_storeu_pd(out.cost.as_mut_ptr().add(t), total);
        _mm_storeu_si128(out.counter.as_mut_ptr().add(t).cast(), counter);
        _mm256_storeu_pd(out.shift.as_mut_ptr().add(t), _mm256_blendv_pd(inf, total, shiftable));
        blocked = _mm256_or_pd(blocked, _mm256_andnot_pd(shiftable, _mm256_cmp_pd::<_CMP_NEQ_UQ>(total, inf)));
        let decision =
            _mm_or_si128(_mm_and_si128(j, index_and_flag), _mm_slli_epi32::<16>(_mm_and_si128(next_gear, low8)));
        _mm_storeu_si128(out.decision.as_mut_ptr().add(t).cast(), decision);
        t += 4;
    }
    (groups, _mm256_movemask_pd(blocked) != 0)
}

/// The ranking of one gear's shift costs into the two best per slot (the scalar loop of
/// `stay_or_shift`) four slots at a time in AVX2, as far as whole groups of four go: returns the
/// slots done. Selects on the same strict comparisons: a cost below the first moves the first to
/// second place, a cost between the two takes the second place.
///
/// # Safety
/// The CPU must have AVX2, and all slices the length of `costs`.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
pub(super) unsafe fn rank_avx2(
    costs: &[f64],
    gear: u32,
    (first_cost, first_gear): (&mut [f64], &mut [u32]),
    (second_cost, second_gear): (&mut [f64], &mut [u32]),
) -> usize {
    use std::arch::x86_64::*;
    let groups = costs.len() / 4 * 4;
    let gear = _mm_set1_epi32(gear as i32);
    let mut t = 0;
    while t < groups {
        let c = _mm256_loadu_pd(costs.as_ptr().add(t));
        let (f, s) = (_mm256_loadu_pd(first_cost.as_ptr().add(t)), _mm256_loadu_pd(second_cost.as_ptr().add(t)));
        let fg = _mm_loadu_si128(first_gear.as_ptr().add(t).cast());
        let sg = _mm_loadu_si128(second_gear.as_ptr().add(t).cast());
        let below_first = _mm256_cmp_pd::<_CMP_LT_OQ>(c, f);
        let below_either = _mm256_or_pd(below_first, _mm256_cmp_pd::<_CMP_LT_OQ>(c, s));
        if _mm256_movemask_pd(below_either) == 0 {
            // Not among the two best anywhere in the group: nothing changes.
            t += 4;
            continue;
        }
        let (below_first32, below_either32) = (pack(below_first), pack(below_either));
        let s = _mm256_blendv_pd(s, _mm256_blendv_pd(c, f, below_first), below_either);
        let sg = _mm_blendv_epi8(sg, _mm_blendv_epi8(gear, fg, below_first32), below_either32);
        _mm256_storeu_pd(second_cost.as_mut_ptr().add(t), s);
        _mm_storeu_si128(second_gear.as_mut_ptr().add(t).cast(), sg);
        _mm256_storeu_pd(first_cost.as_mut_ptr().add(t), _mm256_blendv_pd(f, c, below_first));
        _mm_storeu_si128(first_gear.as_mut_ptr().add(t).cast(), _mm_blendv_epi8(fg, gear, below_first32));
        t += 4;
    }
    groups
}

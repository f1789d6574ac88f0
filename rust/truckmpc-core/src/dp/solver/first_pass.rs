//! The first pass of a stage (per target gear): for every source speed, the cheapest way into each
//! gear of the next stage (row cost + cost-to-go) and the cheapest that allows a shift now. Forward
//! gears take the min-plus pass over their cached rows ([`crate::dp::simd`]); neutral, fuel-cut,
//! full-pedal and pedal-level ways are exact arcs ([`super::arcs`]). Costs in the units of (5.9).

use super::arcs::{better_by_arc, exact_arc, neutral_choices, ArcJoin};
use super::choices::{level_flag, Choices, ARC, FULL, GLIDE};
use super::grids::StageGrid;
use super::shifting::{fill_shifting_arcs, shift_slot_offset, shifting_row};
use super::{stride, Solver, INF};
use crate::dp::cache::{Block, CoastArc, GearBlocks, StageKey, StageRows, LANES, PAD};
use crate::dp::params::{DpSettings, StageModel};
use crate::dp::rows::forward_row;
use crate::dp::simd::{self, LaneMins, LaneOut};
use crate::dp::stage::Branch;
use crate::powertrain::Powertrain;
use crate::vehicle::{Vehicle, NEUTRAL};

impl Solver {
    /// First pass of a stage: for every source velocity in `sources` and every target gear, the
    /// best next state and the best one that allows a shift now, into `choices`. Returns the
    /// transitions evaluated.
    pub(super) fn best_per_target_gear(
        &mut self,
        vehicle: &Vehicle,
        k: usize,
        abs_stage: Option<u64>,
        (i_lo, i_hi): (usize, usize),
        active_next: &[usize],
    ) -> usize {
        let gears = vehicle.forward_gears() + 1;
        let (here, next) = (self.grids[k], self.grids[k + 1]);
        let p = &self.params;
        let v_max_next = self.bands[k + 1].v_max_mps();
        let mut uncounted = 0;
        let key = StageKey {
            slope_torque_nm: self.slope_torques[k],
            origin_mps: here.index.origin_mps,
            next_origin_mps: next.index.origin_mps,
            next_v_max_mps: v_max_next,
        };
        let (stage, computed): (&mut StageRows, &mut u64) = match abs_stage {
            Some(stage) if k > 0 => self.cache.stage(stage),
            None if k > 0 && self.keeps_rows_by_key => (self.recent.rows(key), &mut self.cache.computed),
            _ => {
                self.scratch_rows.reset(key);
                (&mut self.scratch_rows, &mut uncounted)
            }
        };
        let slope_torque = self.slope_torques[k];
        let (key_lo, key_hi) = (here.first + i_lo as i64, here.first + i_hi as i64);
        let ch = &mut self.choices;
        // A row's band ends where the fuel-cut and full-pedal arcs end, when those are its inputs:
        // full pedal on trapezoid stages, and fuel cut for a map truck, whose engine at fuel cut
        // gives the same wheel torque as its map at zero pedal.
        let reuse = [p.mpc.fuel_cut_arcs && vehicle.zero_pedal_is_cut(), p.mpc.stage_model == StageModel::Trapezoid];
        let mut transitions = 0;
        let interrupting = crate::dp::shift::planned(p, vehicle);
        let rolls = &mut self.rolls;
        if interrupting {
            rolls.reset((key_lo, key_hi));
        }
        for &g in active_next {
            let (lo, hi) = self.gear_ranges[(k + 1) * gears + g];
            let out = g * ch.width;
            if g == NEUTRAL {
                let values = (&self.cost_next[PAD..], &self.counter_next[PAD..]);
                let arcs = stage.arcs(NEUTRAL);
                let keys = (key_lo, key_hi);
                neutral_choices(p, vehicle, arcs, (here, next), slope_torque, keys, (lo, hi), values, self.avx2, ch);
                if interrupting {
                    // Into neutral a forward gear disengages without an interruption.
                    let span = out..out + ch.width;
                    ch.ishift_cost[span.clone()].copy_from_slice(&ch.shift_cost[span.clone()]);
                    ch.ishift_j[span.clone()].copy_from_slice(&ch.shift_j[span]);
                }
                transitions += i_hi - i_lo + 1;
                continue;
            }
            let to = ArcTarget { gear: g, gears, next, lo, hi, glides: vehicle.glides() };
            fill_arcs(p, vehicle, stage, (here, slope_torque), (key_lo, key_hi), &to);
            let (rows, ends) = stage.gear_with_arcs(g, end_slots(gears, g));
            let memo = &mut self.row_memo;
            *computed += rows.fill(key_lo, key_hi, &mut self.scratch, |key, buf| {
                let known = [0, 1].map(|e| ends[e].at(key).filter(|_| reuse[e]).map(|arc| arc.v_end_mps));
                let from = (here.index.speed(key), known);
                forward_row(vehicle, p, from, g, slope_torque, next.index, v_max_next, (buf, &mut *memo))
            });
            let values = g * stride(next.count)..(g + 1) * stride(next.count);
            let targets = (&self.cost_next[values.clone()], &self.shift_next[values], self.shift_same_next[g]);
            let pass = GearPass::over(rows, (key_lo, key_hi), (next, lo, hi), targets);
            debug_assert_eq!(pass.first_key, ch.base_key);
            let span = out..out + pass.blocks.len() * LANES;
            let choices = GearChoices {
                all_cost: &mut ch.all_cost[span.clone()],
                all_j: &mut ch.all_j[span.clone()],
                shift_cost: &mut ch.shift_cost[span.clone()],
                shift_j: &mut ch.shift_j[span],
            };
            transitions += gear_pass_dispatch(&pass, choices);
            let block = g * stride(next.count) + PAD;
            let values = (&self.cost_next[block..], &self.counter_next[block..]);
            transitions += join_arcs(p, stage, (key_lo, key_hi), &to, values, ch, false);
            if !interrupting {
                continue;
            }
            // The same ways with the shift's interruption first, for a shift from a forward gear.
            fill_shifting_arcs((vehicle, p), stage, (here, slope_torque), (key_lo, key_hi), (&to, &mut *rolls));
            let shift_memo = &mut self.shift_memo;
            let rows = stage.gear(gears + g);
            *computed += rows.fill(key_lo, key_hi, &mut self.scratch, |key, buf| {
                let to_next = (next, v_max_next);
                shifting_row((vehicle, p), here, key, g, slope_torque, to_next, (buf, &mut *shift_memo, &mut *rolls))
            });
            let values = g * stride(next.count)..(g + 1) * stride(next.count);
            let targets = (&self.cost_next[values.clone()], &self.shift_next[values], self.shift_same_next[g]);
            let pass = GearPass::over(rows, (key_lo, key_hi), (next, lo, hi), targets);
            let lanes = pass.blocks.len() * LANES;
            let (unkept_cost, unkept_j) = &mut self.shift_lanes;
            unkept_cost.resize(lanes.max(unkept_cost.len()), INF);
            unkept_j.resize(lanes.max(unkept_j.len()), 0);
            let span = out..out + lanes;
            let choices = GearChoices {
                all_cost: &mut unkept_cost[..lanes],
                all_j: &mut unkept_j[..lanes],
                shift_cost: &mut ch.ishift_cost[span.clone()],
                shift_j: &mut ch.ishift_j[span],
            };
            transitions += gear_pass_dispatch(&pass, choices);
            let values = (&self.cost_next[block..], &self.counter_next[block..]);
            transitions += join_arcs(p, stage, (key_lo, key_hi), &to, values, ch, true);
        }
        transitions
    }
}

/// A forward target gear of the exact arcs: its number (of `gears`, neutral included), the next
/// stage's grid and the gear's states `lo..=hi` on it.
pub(super) struct ArcTarget {
    pub(super) gear: usize,
    pub(super) gears: usize,
    pub(super) next: StageGrid,
    pub(super) lo: u32,
    pub(super) hi: u32,
    /// Whether the truck has a glide pedal ([`Powertrain::glides`]).
    pub(super) glides: bool,
}

/// The input an exact arc holds over its stage: a fixed one, or the glide pedal at its start speed.
#[derive(Debug, Clone, Copy)]
pub(super) enum ArcInput {
    Held((Branch, f64)),
    Glide,
}

/// The exact arcs into a forward gear: fuel cut, full pedal on trapezoid stages (whose rows stop
/// there), the pedal levels l/K between them (`pedal_levels`) and, for a truck that glides, its
/// glide (`glide_arcs`), as (cache slot, input, join, flag of the choice).
pub(super) fn arc_kinds<'a>(
    p: &'a DpSettings,
    to: &ArcTarget,
) -> impl Iterator<Item = (usize, ArcInput, ArcJoin, u32)> + 'a {
    let (g, gears, next, range) = (to.gear, to.gears, to.next, (to.lo, to.hi));
    let [cut_slot, full_slot] = end_slots(gears, g);
    let held = |branch, input| ArcInput::Held((branch, input));
    let fuel_cut = p.mpc.fuel_cut_arcs.then(|| (cut_slot, held(Branch::Brake, 0.0), ArcJoin::new(p, next, range), ARC));
    let full = (p.mpc.stage_model == StageModel::Trapezoid)
        .then(|| (full_slot, held(Branch::Pedal, 1.0), ArcJoin::full_pedal(p, next, range), FULL));
    let k_levels = p.mpc.pedal_levels;
    let levels = (1..k_levels.max(1)).map(move |l| {
        let input = held(Branch::Pedal, l as f64 / k_levels as f64);
        (level_slot(l, gears, g), input, ArcJoin::new(p, next, range), level_flag(l))
    });
    let glide = (to.glides && p.mpc.glide_arcs)
        .then(|| (level_slot(k_levels.max(1), gears, g), ArcInput::Glide, ArcJoin::new(p, next, range), GLIDE));
    fuel_cut.into_iter().chain(full).chain(levels).chain(glide)
}

/// Fill the exact arcs ([`arc_kinds`]) into a forward gear from the sources `key_lo..=key_hi` of
/// the grid `here` on a stage of wheel torque `slope_torque` [Nm], where missing.
fn fill_arcs(
    p: &DpSettings,
    vehicle: &Vehicle,
    stage: &mut StageRows,
    (here, slope_torque): (StageGrid, f64),
    (key_lo, key_hi): (i64, i64),
    to: &ArcTarget,
) {
    for (slot, input, _, _) in arc_kinds(p, to) {
        let g = to.gear;
        stage.arcs(slot).fill(key_lo, key_hi, |key| {
            let v_mps = here.index.speed(key);
            match input {
                ArcInput::Held(held) => exact_arc(p, vehicle, v_mps, g, slope_torque, held),
                ArcInput::Glide => match vehicle.glide_pedal(v_mps, g) {
                    Some(pedal) => exact_arc(p, vehicle, v_mps, g, slope_torque, (Branch::Pedal, pedal)),
                    None => CoastArc { v_end_mps: v_mps, cost: INF },
                },
            }
        });
    }
}

/// The exact arcs into a forward gear from the sources `key_lo..=key_hi` (filled by
/// [`fill_arcs`], or with `shifting` by [`fill_shifting_arcs`]) joined to the gear's states against
/// their cost-to-go and counters (`values`, from state 0), each taking a source's choice where
/// cheaper (with `shifting`, its shift choice after an interruption only). Returns the transitions
/// evaluated.
fn join_arcs(
    p: &DpSettings,
    stage: &mut StageRows,
    (key_lo, key_hi): (i64, i64),
    to: &ArcTarget,
    (cost_next, counter_next): (&[f64], &[u32]),
    ch: &mut Choices,
    shifting: bool,
) -> usize {
    let slot0 = to.gear * ch.width + (key_lo - ch.base_key) as usize;
    let offset = if shifting { shift_slot_offset(p, to.gears) } else { 0 };
    let mut transitions = 0;
    for (slot, _, join, flag) in arc_kinds(p, to) {
        for (at, arc) in (slot0..).zip(stage.arcs(slot + offset).get(key_lo, key_hi)) {
            // The counter of the grid point the path continues from, not the stencil's
            // smallest (the neutral state's rule): this arc's state is a forward gear's.
            let (cost, j, _) = join.join(arc, cost_next, counter_next);
            if !shifting {
                better_by_arc(cost, j | flag, counter_next[j as usize] >= p.k_lim, ch, at);
            } else if cost < ch.ishift_cost[at] && counter_next[j as usize] >= p.k_lim {
                (ch.ishift_cost[at], ch.ishift_j[at]) = (cost, j | flag);
            }
        }
        transitions += (key_hi - key_lo + 1) as usize;
    }
    transitions
}

/// The cache slots of the fuel-cut and full-pedal arcs into forward gear `g` (of `gears`, neutral
/// included), after neutral's (slot 0).
#[inline]
fn end_slots(gears: usize, g: usize) -> [usize; 2] {
    [g, gears + g]
}

/// The cache slot of the arcs of pedal level `l` into forward gear `g` (of `gears`, neutral
/// included): after neutral's and the [`end_slots`].
#[inline]
fn level_slot(l: u32, gears: usize, g: usize) -> usize {
    (l as usize + 1) * gears + g
}

/// What the first pass reads for one forward target gear.
struct GearPass<'a> {
    /// The blocks of the source keys, from `first_key` on.
    blocks: &'a [Block],
    costs: &'a [f64],
    /// Grid index of the next grid's state 0.
    next_first: i64,
    /// The target gear's states at the next stage.
    lo: u32,
    hi: u32,
    /// The target gear's blocks of cost_next and shift_next (margins included).
    to_go: &'a [f64],
    shiftable: &'a [f64],
    /// Whether `shiftable` equals `to_go` bit for bit.
    same: bool,
    first_key: i64,
    /// The source keys with states.
    key_lo: i64,
    key_hi: i64,
}

impl<'a> GearPass<'a> {
    /// The pass over the blocks of `rows` holding the sources `key_lo..=key_hi`, towards the target
    /// gear's states `lo..=hi` of `next`, against its cost-to-go, its shiftable values and whether
    /// the two are equal bit for bit.
    fn over(
        rows: &'a GearBlocks,
        (key_lo, key_hi): (i64, i64),
        (next, lo, hi): (StageGrid, u32, u32),
        (to_go, shiftable, same): (&'a [f64], &'a [f64], bool),
    ) -> Self {
        let (blocks, first_key) = rows.get(key_lo, key_hi);
        GearPass {
            blocks,
            costs: &rows.costs,
            next_first: next.first,
            lo,
            hi,
            to_go,
            shiftable,
            same,
            first_key,
            key_lo,
            key_hi,
        }
    }
}

/// Where the first pass writes for one forward target gear: one value per block lane.
struct GearChoices<'a> {
    all_cost: &'a mut [f64],
    all_j: &'a mut [u32],
    shift_cost: &'a mut [f64],
    shift_j: &'a mut [u32],
}

/// [`gear_pass`] with the best kernels of the CPU. Returns the transitions evaluated.
fn gear_pass_dispatch(pass: &GearPass, out: GearChoices) -> usize {
    #[cfg(target_arch = "x86_64")]
    if let Some(kernels) = simd::Avx2::detect() {
        // SAFETY: `kernels` exists, so the CPU has AVX2.
        return unsafe { gear_pass_avx2(kernels, pass, out) };
    }
    gear_pass(simd::Portable, pass, out)
}

/// [`gear_pass`] compiled for AVX2, so that its kernels inline into the loop over blocks.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn gear_pass_avx2(kernels: simd::Avx2, pass: &GearPass, out: GearChoices) -> usize {
    gear_pass(kernels, pass, out)
}

/// The first pass towards one forward target gear: per block, the lanes' best ways into the gear
/// (and the best that allow a shift now), their next-grid indices, and the transitions counted.
#[inline(always)]
fn gear_pass<K: simd::Kernels>(kernels: K, pass: &GearPass, out: GearChoices) -> usize {
    let (lo, hi) = (pass.lo, pass.hi);
    let mut transitions = 0;
    let n = pass.blocks.len() * LANES;
    assert!(out.all_cost.len() == n && out.all_j.len() == n && out.shift_cost.len() == n && out.shift_j.len() == n);
    for (b, block) in pass.blocks.iter().enumerate() {
        let base = block.first as i64 - pass.next_first;
        let at = b * LANES..(b + 1) * LANES;
        let lanes = LaneOut {
            all: &mut out.all_cost[at.clone()],
            all_j: &mut out.all_j[at.clone()],
            shift: &mut out.shift_cost[at.clone()],
            shift_j: &mut out.shift_j[at],
        };
        block_mins(kernels, block, pass.costs, base, (lo, hi), (pass.to_go, pass.shiftable), pass.same, lanes);
        let key0 = pass.first_key + (b * LANES) as i64;
        let inside = base >= lo as i64 && base + block.steps as i64 + LANES as i64 - 2 <= hi as i64;
        if inside && key0 >= pass.key_lo && key0 + LANES as i64 - 1 <= pass.key_hi {
            // Every lane's targets are states and every lane a source: no clipping.
            transitions += block.reach as usize;
            continue;
        }
        for l in 0..LANES {
            let key = key0 + l as i64;
            let (first, len) = block.spans[l];
            let first = first as i64 - pass.next_first;
            let reached = ((first + len as i64 - 1).min(hi as i64) - first.max(lo as i64) + 1).max(0) as usize;
            transitions += if key >= pass.key_lo && key <= pass.key_hi { reached } else { 0 };
        }
    }
    transitions
}

/// The min-plus pass over one block of rows towards one forward target gear, into `out`: per
/// lane, the best of row cost + cost-to-go and the best among targets whose continuation allows a
/// shift now, with their next-grid indices (base + lane + step, as u32 like the i64 sum
/// truncated; meaningless where the cost is +∞). `base` is the next-grid index of lane 0 at step
/// 0; `values` the target gear's blocks of cost_next and shift_next (margins included, state j at
/// PAD + j); `same` when they are equal bit for bit.
#[inline(always)]
pub(super) fn block_mins<K: simd::Kernels>(
    kernels: K,
    block: &Block,
    costs: &[f64],
    base: i64,
    (lo, hi): (u32, u32),
    (to_go, shiftable): (&[f64], &[f64]),
    same: bool,
    out: LaneOut,
) {
    let steps = block.steps as usize;
    let at = base + PAD as i64;
    let costs = &costs[block.offset as usize..];
    if steps > 0 && at >= 0 && at as usize + steps + LANES - 1 <= to_go.len() {
        // The values outside the target gear's states are +∞ (margins included): no clipping.
        let at = at as usize;
        let shiftable = if same { None } else { Some(&shiftable[at..]) };
        kernels.block_mins_to((costs, steps), &to_go[at..], shiftable, base as u32, out);
        return;
    }
    block_mins_clipped(costs, steps, base, (lo, hi), to_go, shiftable).write(base as u32, out);
}

/// [`block_mins`] for a block reaching beyond the margins: only targets that are states count.
#[cold]
fn block_mins_clipped(
    costs: &[f64],
    steps: usize,
    base: i64,
    (lo, hi): (u32, u32),
    to_go: &[f64],
    shiftable: &[f64],
) -> LaneMins {
    let mut out = LaneMins { all: [INF; LANES], all_step: [0; LANES], shift: [INF; LANES], shift_step: [0; LANES] };
    for d in 0..steps {
        for l in 0..LANES {
            let j = base + (l + d) as i64;
            if j < lo as i64 || j > hi as i64 {
                continue;
            }
            let c = costs[d * LANES + l];
            let (x, y) = (c + to_go[PAD + j as usize], c + shiftable[PAD + j as usize]);
            if x < out.all[l] {
                (out.all[l], out.all_step[l]) = (x, d as u32);
            }
            if y < out.shift[l] {
                (out.shift[l], out.shift_step[l]) = (y, d as u32);
            }
        }
    }
    out
}

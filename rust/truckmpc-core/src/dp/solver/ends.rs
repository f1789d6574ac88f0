//! Where a solve ends and what it keeps: the horizon's end (terminal cost 0, or with the fuel_time
//! cost the kinetic energy left, in the cost's units per state), or the stored cost-to-go of a
//! [`ValueTable`]'s stage; and each stage's values when a solve records them.

use super::{stride, Solver, INF};
use crate::dp::cache::PAD;
use crate::dp::params::StageModel;
use crate::dp::values::{StageValues, ValueTable};

/// Where a solve ends and what it keeps.
pub(super) enum Ends<'a> {
    /// At the horizon's end, cost 0 on every final state.
    Horizon,
    /// At the horizon's end (a whole road's end, too), keeping every stage's cost-to-go.
    Recording(&'a mut ValueTable),
    /// On stored states with their cost-to-go.
    Values(&'a StageValues),
}

impl Solver {
    /// J_N and the counters at the horizon's end (stage `n_stages`) into `cost_next`,
    /// `counter_next` and `shift_next`: the terminal cost, or the states of `terminal` when the
    /// solve ends on stored values.
    pub(super) fn load_horizon_end(&mut self, n_stages: usize, gears: usize, terminal: Option<&StageValues>) {
        // Terminal cost 0 (fuel_time: the kinetic energy's); the counters of final states allow
        // any shift before them.
        let stride_last = stride(self.grids[n_stages].count);
        self.cost_next.clear();
        self.cost_next.resize(gears * stride_last, INF);
        self.counter_next.clear();
        self.counter_next.resize(gears * stride_last, self.params.k_lim);
        for g in 0..gears {
            let (lo, hi) = self.gear_ranges[n_stages * gears + g];
            if hi >= lo {
                let at = g * stride_last + PAD;
                let terminal = &mut self.cost_next[at + lo as usize..=at + hi as usize];
                terminal.fill(0.0);
                let weight = self.params.q_terminal_per_half_v2;
                let grid = self.grids[n_stages];
                if weight > 0.0 {
                    // The fuel_time cost values the speed left at the end: ½(v_ref² − v²) in fuel.
                    let v_ref = self.bands[n_stages].v_ref_mps();
                    for (cost, j) in terminal.iter_mut().zip(lo as usize..) {
                        let v = grid.speed(j);
                        *cost = weight * 0.5 * (v_ref * v_ref - v * v);
                    }
                }
                let q_time = self.params.q_time_per_s * self.params.mpc.stage_m;
                if q_time > 0.0 && self.params.mpc.stage_model == StageModel::Trapezoid {
                    // Each state is charged h/v (the stay_or_shift pass); the trapezoid's time along
                    // a path is that sum plus h/(2 v_N) at the end (less a constant h/(2 v_0)).
                    for (cost, j) in terminal.iter_mut().zip(lo as usize..) {
                        *cost += 0.5 * q_time / grid.speed(j);
                    }
                }
            }
        }
        self.shift_next.clone_from(&self.cost_next);
        self.shift_same_next.clear();
        self.shift_same_next.resize(gears, true);
        if let Some(next) = terminal {
            self.load_terminal(next, gears);
        }
    }

    /// Stage `k`'s states and values: J_{k+1} in `cost_next` when `next` (the horizon's end,
    /// before the backward pass), else J_k just written to `cost_cur`.
    pub(super) fn stage_values(&self, k: usize, gears: usize, next: bool) -> StageValues {
        let grid = self.grids[k];
        let ranges = &self.gear_ranges[k * gears..(k + 1) * gears];
        let mut values = StageValues::new(grid.index.origin_mps, grid.index.delta_mps, grid.first, grid.count, ranges);
        let (cost, counter) =
            if next { (&self.cost_next, &self.counter_next) } else { (&self.cost_cur, &self.counter_cur) };
        for (g, &(lo, hi)) in ranges.iter().enumerate() {
            if hi >= lo {
                let at = g * stride(grid.count) + PAD;
                let states = at + lo as usize..=at + hi as usize;
                values.set_gear(g, &cost[states.clone()], &counter[states]);
            }
        }
        values
    }

    /// The horizon's end on the states of `next`: their cost-to-go and counters, and the costs of
    /// those whose continuation allows a shift into them (+∞ elsewhere).
    pub(super) fn load_terminal(&mut self, next: &StageValues, gears: usize) {
        let n = self.grids.len() - 1;
        let stride_last = stride(self.grids[n].count);
        for g in 0..gears {
            let (lo, hi) = self.gear_ranges[n * gears + g];
            for j in lo as usize..=hi as usize {
                let at = g * stride_last + PAD + j;
                let (cost, counter) = next.get(g, j).unwrap_or((INF, 0));
                (self.cost_next[at], self.counter_next[at]) = (cost, counter);
                self.shift_next[at] = if counter >= self.params.k_lim { cost } else { INF };
                if self.shift_next[at].to_bits() != cost.to_bits() {
                    self.shift_same_next[g] = false;
                }
            }
        }
    }
}

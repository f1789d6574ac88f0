//! Stage grids and bounds: each stage's speed grid [m/s] (moving or fixed, from the bounds of the
//! interval passes in [`crate::dp::space`]) and, per gear, the grid indices where a state exists
//! (engine speed within [N_min, N_max] rpm, neutral if allowed, the start gear until a shift is
//! allowed).

use super::choices::Decision;
use super::{InitialState, Solver};
use crate::dp::params::{CostKind, GridAnchor};
use crate::dp::rows::GridIndex;
use crate::dp::space::{self, Grid};
use crate::dp::values::StageValues;
use crate::vehicle::{Vehicle, NEUTRAL};

/// One stage's grid: speeds of grid indices `first..first + count` of `index`.
#[derive(Debug, Clone, Copy)]
pub(super) struct StageGrid {
    pub(super) index: GridIndex,
    pub(super) first: i64,
    pub(super) count: usize,
}

impl StageGrid {
    #[inline]
    pub(super) fn speed(&self, j: usize) -> f64 {
        self.index.speed(self.first + j as i64)
    }
}

impl Solver {
    /// The speed bounds of every stage (the interval passes) and the grid on them; the start
    /// stage's grid is the start speed alone, the last stage's that of `terminal` if given.
    pub(super) fn stage_grids(
        &mut self,
        vehicle: &Vehicle,
        start: InitialState,
        slopes: &[f64],
        first_stage: Option<u64>,
        terminal: Option<&StageValues>,
    ) {
        // Absolute stages, when known, let the interval passes reuse steps of earlier solves.
        let p = &self.params;
        let memo = first_stage.filter(|_| self.caching).map(|stage| (stage, &mut self.interval_memo));
        // The speed_penalty cost has no price for the speed left at the end: it ends at v_ref or
        // above. The fuel_time cost ends on its reachable speeds, priced by the terminal cost (its
        // kinetic energy in fuel): requiring v_ref there kept the truck from planning a coast into
        // a descent beyond a horizon, and made the whole road's optimum pay for an end speed the
        // end-speed correction would have priced lower (a run it then no longer bounded).
        let raise_end = p.mpc.cost == CostKind::SpeedPenalty;
        space::intervals_from_stage(vehicle, p, start.v_mps, slopes, &self.bands, memo, raise_end, &mut self.intervals);
        let delta = p.delta_mps();
        self.grids.clear();
        self.grids.push(StageGrid {
            index: GridIndex { origin_mps: start.v_mps, delta_mps: delta },
            first: 0,
            count: 1,
        });
        for k in 1..=slopes.len() {
            let Grid { first_mps, count } = space::grid(p, self.intervals.lo[k], self.intervals.hi[k]);
            self.grids.push(match p.mpc.grid {
                GridAnchor::Moving => {
                    StageGrid { index: GridIndex { origin_mps: first_mps, delta_mps: delta }, first: 0, count }
                }
                GridAnchor::Fixed => StageGrid {
                    index: GridIndex { origin_mps: 0.0, delta_mps: delta },
                    first: (first_mps / delta).round() as i64,
                    count,
                },
            });
        }
        if let Some(next) = terminal {
            let index = GridIndex { origin_mps: next.origin_mps, delta_mps: next.delta_mps };
            *self.grids.last_mut().expect("a stage") = StageGrid { index, first: next.first, count: next.count };
        }
    }

    /// Per stage and gear, the grid indices with a state (`gear_ranges`) and the gears with any
    /// (`active`); room for the decisions of every state.
    pub(super) fn gear_states(&mut self, vehicle: &Vehicle, start: InitialState, terminal: Option<&StageValues>) {
        let p = &self.params;
        let gears = vehicle.forward_gears() + 1;
        let last = self.grids.len() - 1;
        // Stages 1..=forced are reached before the shift limit lets the truck leave its gear.
        let forced = p.k_lim.saturating_sub(start.stages_since_shift) as usize;
        self.gear_ranges.clear();
        self.active.resize(self.grids.len(), Vec::new());
        // Per gear, the grid indices with engine speed in [n_min, n_max]: the same for every stage
        // of one grid index (all stages of a fixed grid), so computed only when the index changes.
        let (mut rpm_indices, mut rpm_of) = (vec![(0i64, -1i64); gears], None);
        for (k, grid) in self.grids.iter().enumerate() {
            let full = (0u32, grid.count as u32 - 1);
            self.active[k].clear();
            if rpm_of != Some(grid.index) {
                for (g, bounds) in rpm_indices.iter_mut().enumerate().filter(|&(g, _)| g != NEUTRAL) {
                    let c4 = vehicle.gear(g).c4;
                    *bounds = (grid.index.ceil(p.mpc.n_min_rpm / c4), grid.index.floor(p.mpc.n_max_rpm / c4));
                }
                rpm_of = Some(grid.index);
            }
            for (g, &(rpm_lo, rpm_hi)) in rpm_indices.iter().enumerate() {
                let stored = terminal.filter(|_| k == last).map(|next| next.ranges.get(g).copied().unwrap_or((1, 0)));
                let range = if (k == 0 || k <= forced) && g != start.gear {
                    (1, 0)
                } else if let Some(range) = stored {
                    range
                } else if k == 0 || k <= forced {
                    full
                } else if g == NEUTRAL {
                    if p.mpc.allow_neutral {
                        full
                    } else {
                        (1, 0)
                    }
                } else {
                    // Engine speed in [n_min, n_max]: an interval of speeds, so of grid indices.
                    let (lo, hi) = ((rpm_lo - grid.first).max(0), (rpm_hi - grid.first).min(full.1 as i64));
                    if hi >= lo {
                        (lo as u32, hi as u32)
                    } else {
                        (1, 0)
                    }
                };
                if range.1 >= range.0 {
                    self.active[k].push(g);
                }
                self.gear_ranges.push(range);
            }
        }
        self.offsets.clear();
        let mut total = 0;
        for grid in &self.grids {
            self.offsets.push(total);
            total += grid.count * gears;
        }
        // Every decision on a traced path is written before it is read: no need to clear.
        if self.decisions.len() < total {
            self.decisions.resize(total, Decision::default());
        }
    }
}

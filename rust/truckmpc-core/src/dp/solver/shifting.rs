//! The first pass's shifting ways into a forward gear, for a truck whose gearbox interrupts
//! traction: each source speed's stage starts with the interruption's roll in neutral, then drives
//! the target gear over the rest of the stage from the speed the roll ends at
//! ([`crate::dp::shift`]). Its rows and exact arcs are kept beside the ordinary ones (rows in the
//! target gear's slot plus the gear count, arcs in their slot plus [`shift_slot_offset`]); the first
//! pass joins them into the shift choices of a forward source (`ishift_cost`, `ishift_j`).

use super::arcs::exact_arc;
use super::first_pass::{arc_kinds, ArcInput, ArcTarget};
use super::grids::StageGrid;
use crate::dp::cache::{CoastArc, StageRows};
use crate::dp::params::DpSettings;
use crate::dp::rows::{forward_row, RowMemo, RowSpan};
use crate::dp::shift::{after, extra_cost, interruption, Interruption};
use crate::vehicle::Vehicle;

use super::INF;

/// The rolls of one stage's sources, each found once: a source's roll depends on its speed, the
/// stage's grade and length only, and every target gear's row and arcs start with it.
#[derive(Debug, Clone, Default)]
pub(super) struct StageRolls {
    first_key: i64,
    /// Per source key from `first_key`: None until found, then the roll (None where no shift starts).
    rolls: Vec<Option<Option<Interruption>>>,
}

impl StageRolls {
    /// Forget the rolls of the stage before: sources `key_lo..=key_hi` of a new stage.
    pub(super) fn reset(&mut self, (key_lo, key_hi): (i64, i64)) {
        self.first_key = key_lo;
        self.rolls.clear();
        self.rolls.resize((key_hi - key_lo + 1).max(0) as usize, None);
    }

    /// The roll of source `key` of `here`, found on first use (a key outside the sources, which a
    /// block of rows may reach past their last, is found each time).
    fn of(
        &mut self,
        (vehicle, p): (&Vehicle, &DpSettings),
        here: StageGrid,
        key: i64,
        slope_torque: f64,
    ) -> Option<Interruption> {
        let find = || interruption(vehicle, here.index.speed(key), slope_torque, p.mpc.stage_m);
        match usize::try_from(key - self.first_key).ok().and_then(|i| self.rolls.get_mut(i)) {
            Some(slot) => *slot.get_or_insert_with(find),
            None => find(),
        }
    }
}

/// Where a shifting way's arcs are kept: after every ordinary slot (neutral's, the fuel-cut and
/// full-pedal arcs', each pedal level's and the glide's).
#[inline]
pub(super) fn shift_slot_offset(p: &DpSettings, gears: usize) -> usize {
    (p.mpc.pedal_levels.max(1) as usize + 2) * gears
}

/// The row of a shifting stage from source `key` of `here` into forward gear `g`: the roll, then
/// the ordinary row from its end speed over the rest of the stage, each cost with the roll's
/// extra ([`extra_cost`]). Appends to `out` as [`forward_row`] does; empty where no shift can
/// start at that speed.
#[allow(clippy::too_many_arguments)]
pub(super) fn shifting_row(
    (vehicle, p): (&Vehicle, &DpSettings),
    here: StageGrid,
    key: i64,
    g: usize,
    slope_torque: f64,
    (next, v_max_next): (StageGrid, f64),
    (out, memo, rolls): (&mut Vec<f64>, &mut RowMemo, &mut StageRolls),
) -> (RowSpan, usize) {
    let v_i = here.index.speed(key);
    let Some(roll) = rolls.of((vehicle, p), here, key, slope_torque) else {
        // The roll outlasts the stage (a short stage, a fast truck) or would stop the truck: the
        // shift is planned as an ordinary stage, as the model then drives it (`drive_stage`).
        return forward_row(vehicle, p, (v_i, [None, None]), g, slope_torque, next.index, v_max_next, (out, memo));
    };
    let rest = after(p, &roll);
    let from = (roll.v_mps, [None, None]);
    let (span, at) = forward_row(vehicle, &rest, from, g, slope_torque, next.index, v_max_next, (out, memo));
    for (index, cost) in (span.first..).zip(&mut out[at..at + span.len]) {
        if cost.is_finite() {
            *cost += extra_cost(p, &roll, (v_i, next.index.speed(index)));
        }
    }
    (span, at)
}

/// Fill the shifting stages' exact arcs into forward gear `to.gear` from the sources
/// `key_lo..=key_hi` of `here`, where missing: each of [`arc_kinds`]' inputs held after the roll,
/// its cost with the roll's extra. None where no shift starts (a truck that glides has no
/// interruption).
pub(super) fn fill_shifting_arcs(
    (vehicle, p): (&Vehicle, &DpSettings),
    stage: &mut StageRows,
    (here, slope_torque): (StageGrid, f64),
    (key_lo, key_hi): (i64, i64),
    (to, rolls): (&ArcTarget, &mut StageRolls),
) {
    let offset = shift_slot_offset(p, to.gears);
    for (slot, input, _, _) in arc_kinds(p, to) {
        stage.arcs(slot + offset).fill(key_lo, key_hi, |key| {
            let v_i = here.index.speed(key);
            let none = CoastArc { v_end_mps: v_i, cost: INF };
            let ArcInput::Held(held) = input else {
                return none;
            };
            let Some(roll) = rolls.of((vehicle, p), here, key, slope_torque) else {
                // As an ordinary stage, as the row does.
                return exact_arc(p, vehicle, v_i, to.gear, slope_torque, held);
            };
            let mut arc = exact_arc(&after(p, &roll), vehicle, roll.v_mps, to.gear, slope_torque, held);
            if arc.v_end_mps > 0.0 && arc.cost.is_finite() {
                arc.cost += extra_cost(p, &roll, (v_i, arc.v_end_mps));
            }
            arc
        });
    }
}

//! The traceback: the stored decisions followed from the initial state, giving the first control
//! and the predicted trajectory (speeds [m/s], gears, pedal and brake levels [0, 1]).

use super::choices::{level_of, ARC, FULL, GLIDE};
use super::{InitialState, Solution, Solver, TrajectoryPoint};
use crate::dp::params::StageModel;
use crate::dp::rows::{inputs, Inputs};
use crate::dp::{shift, stage};
use crate::plant::Control;
use crate::powertrain::Powertrain;
use crate::vehicle::{Vehicle, NEUTRAL};

impl Solver {
    /// Follow the stored decisions from the initial state to fill the first control and the
    /// predicted trajectory; the inputs of each step are recomputed from its two speeds.
    pub(super) fn trace(&self, vehicle: &Vehicle, start: InitialState, out: &mut Solution) {
        let (mut i, mut g) = (0usize, start.gear);
        let mut v = start.v_mps;
        // On trapezoid stages the trajectory follows the speeds the decisions give (an arc ends
        // off the grid, and the next stage's inputs aim at its planned grid speed from there), so
        // the plan's fuel and time are those of driving it; on Euler stages it runs on the grid.
        let exact = self.params.mpc.stage_model == StageModel::Trapezoid;
        out.trajectory.clear();
        for k in 0..self.grids.len() - 1 {
            let d = self.decisions[self.offsets[k] + g * self.grids[k].count + i];
            let (next_i, next_g) = (d.j as usize, d.gear as usize);
            let v_next = self.grids[k + 1].speed(next_i);
            let (pedal, brake) = if next_g == NEUTRAL || d.arc == (ARC >> 24) as u8 {
                (0.0, 0.0)
            } else if d.arc == (FULL >> 24) as u8 {
                (1.0, 0.0)
            } else if d.arc == (GLIDE >> 24) as u8 {
                // The glide pedal at the speed its arc started from (the grid's, as when filled).
                (vehicle.glide_pedal(self.grids[k].speed(i), next_g).unwrap_or(0.0), 0.0)
            } else if let Some(l) = level_of(d.arc) {
                debug_assert!(l < self.params.mpc.pedal_levels, "level {l} of {} levels", self.params.mpc.pedal_levels);
                (l as f64 / self.params.mpc.pedal_levels as f64, 0.0)
            } else {
                let v_max = self.bands[k + 1].v_max_mps();
                let torque = self.slope_torques[k];
                let planned = |from: f64| self.stage_inputs(vehicle, (from, v_next, v_max), (g, next_g), torque);
                let u =
                    planned(v).or_else(|| planned(self.grids[k].speed(i))).unwrap_or(Inputs { pedal: 0.0, brake: 0.0 });
                (u.pedal, u.brake)
            };
            let v_grid_mps = self.grids[k].speed(i);
            out.trajectory.push(TrajectoryPoint { v_mps: v, v_grid_mps, gear: next_g, pedal, brake });
            v = if !exact {
                v_next
            } else if shift::interrupts(&self.params, vehicle, g, next_g) {
                let u = Control { pedal, brake, gear: next_g };
                let at = (vehicle, self.params.mpc.stage_model);
                shift::drive_stage(at, (v, self.params.mpc.stage_m), g, u, self.slope_torques[k]).0
            } else {
                let h = self.params.mpc.stage_m;
                let input = (pedal, brake, next_g);
                stage::end_speed_with(self.params.mpc.stage_model, vehicle, (v, h), input, self.slope_torques[k])
            };
            i = next_i;
            g = next_g;
        }
        let v_grid_mps = self.grids[self.grids.len() - 1].speed(i);
        out.trajectory.push(TrajectoryPoint { v_mps: v, v_grid_mps, gear: g, pedal: 0.0, brake: 0.0 });
        let first = out.trajectory[0];
        out.pedal = first.pedal;
        out.brake = first.brake;
        out.gear = first.gear;
    }

    /// The inputs of a row's stage from `v_i` to `v_j` [m/s] (`v_max` the next band's top) from
    /// gear `from` into `to`: after the shift's roll where the change interrupts traction.
    fn stage_inputs(
        &self,
        vehicle: &Vehicle,
        (v_i, v_j, v_max): (f64, f64, f64),
        (from, to): (usize, usize),
        torque: f64,
    ) -> Option<Inputs> {
        if !shift::interrupts(&self.params, vehicle, from, to) {
            return inputs(vehicle, &self.params, (v_i, v_j, v_max), to, torque);
        }
        let roll = shift::interruption(vehicle, v_i, torque, self.params.mpc.stage_m)?;
        inputs(vehicle, &shift::after(&self.params, &roll), (roll.v_mps, v_j, v_max), to, torque)
    }
}

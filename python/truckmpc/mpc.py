"""The look-ahead cruise controller (thesis chapter 5) in the closed loop.

Every S metres the controller predicts, with its own model, the speed at the start of the next
stage under the inputs being applied now, solves the dynamic program (Rust kernel) over the slopes
of the horizon from there, and keeps the first control of the optimum for that next stage
(receding horizon, section 5.6). Stage boundaries are anchored at the road's start. When a solve
finds no admissible path, the controller keeps the inputs it is applying and counts the event.

Units: the cost weights act on fuel in grams and on speeds in m/s (NOTES.md); speeds in the config
(v_ref, v_inc, v_dec, delta) are in km/h.
"""

from __future__ import annotations

import time
from typing import TYPE_CHECKING, Any

from truckmpc import _core
from truckmpc.controller import Control, Decision, PlantState
from truckmpc.pi import steady_gear

if TYPE_CHECKING:
    from truckmpc.config import RunConfig
    from truckmpc.road import RoadProfile


class MpcController:
    """The DP-MPC as a :class:`truckmpc.controller.Controller`: decides once per stage."""

    name = "mpc"

    def __init__(self, vehicle: _core.Vehicle, config: RunConfig):
        self._vehicle = vehicle
        self._config = config
        self._params = {
            **config.mpc,
            **config.cruise,
            "k_lim": config.settings.k_lim_stages,
            "q_speed_below": config.settings.q_speed_below_weight,
        }
        self._pi = config.pi  # only its gear thresholds: the gear the truck starts in
        self._stage_m = float(config.mpc.stage_m)

    def start(self, road: RoadProfile, state: PlantState) -> None:
        """Build the solver for ``road`` and solve the first stage from the starting state."""
        self._solver = _core.MpcSolver(self._config.settings, road.core())
        self._origin_m = state.s_m
        self._k_lim = int(self._params["k_lim"])
        self._since_shift = self._k_lim
        self._gear = steady_gear(self._vehicle, state.v_mps, self._pi)
        self._solve_times_s: list[float] = []
        self._states = 0
        self._transitions = 0
        self._infeasible = 0
        first = self._solve(state.s_m, state.v_mps, self._gear)
        self._pending = first if first is not None else self._holding(state.v_mps, self._gear)

    def decide(self, state: PlantState) -> Decision:
        """Apply the control chosen for this stage; solve the next stage from the predicted speed."""
        u = self._pending
        self._since_shift = 1 if u.gear != self._gear else min(self._since_shift + 1, self._k_lim)
        self._gear = u.gear
        stage = round((state.s_m - self._origin_m) / self._stage_m)
        boundary_m = self._origin_m + (stage + 1) * self._stage_m
        v_next = self._solver.predict_speed(state.s_m, state.v_mps, u.pedal, u.brake, u.gear)
        chosen = self._solve(boundary_m, v_next, u.gear) if v_next > 0 else None
        self._pending = chosen if chosen is not None else u
        return u, boundary_m

    def summary(self) -> dict[str, Any]:
        """Solver figures for the run summary: solves, infeasible solves, time and size per solve."""
        times = self._solve_times_s
        count = max(len(times), 1)
        return {
            "solves": len(times),
            "infeasible_solves": self._infeasible,
            "solve_ms_mean": 1e3 * sum(times) / count,
            "solve_ms_max": 1e3 * max(times, default=0.0),
            "states_per_solve": self._states / count,
            "transitions_per_solve": self._transitions / count,
            "settings": dict(self._params),
        }

    def _solve(self, s_m: float, v_mps: float, gear: int) -> Control | None:
        began = time.perf_counter()
        solution = self._solver.solve(s_m, v_mps, gear, self._since_shift)
        feasible, pedal, brake, next_gear = solution.feasible, solution.pedal, solution.brake, solution.gear
        states, transitions = solution.states, solution.transitions
        self._solve_times_s.append(time.perf_counter() - began)
        self._states += states
        self._transitions += transitions
        if not feasible:
            self._infeasible += 1
            return None
        return Control(pedal, brake, next_gear)

    def _holding(self, v_mps: float, gear: int) -> Control:
        """Fallback before any feasible solve: the level holding the speed on a flat road."""
        level = self._vehicle.stationary(v_mps, 0.0, gear)
        return Control(level["pedal"], level["brake"], gear)

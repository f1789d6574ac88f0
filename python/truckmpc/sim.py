"""Closed-loop simulation of a cruise controller driving the truck over a road profile.

The plant (``truckmpc._core.Plant``) integrates the vehicle model (B.1) and the fuel flow (B.2) in
**time** with classic RK4 at a fixed step ``plant_dt_s`` (default 0.05 s, about 1.2 m at 85 km/h);
integrating in time keeps dv/dt finite at any speed. The last step is shortened so the run ends on the
road's end. At the default step, halving it changes trip fuel and time on the bundled test track by far
less than the 0.05 % / 0.01 % the project requires (``tests/test_sim.py`` checks it).

The built-in controllers (``"pi"``, ``"mpc"``) run in the Rust closed loop (``truckmpc._core.run``),
with the GIL released; a :class:`truckmpc.controller.Controller` written in Python runs in the loop
below, which steps the same plant the same way. A controller is asked for a decision whenever its
previous one runs out: after one plant step (PI, section 2.5) or on reaching a distance (a look-ahead
controller that holds its inputs over a stage). A truck whose speed falls below the stall speed (gear 1 turning the
engine slower than idle) stops the run: the result says ``stalled`` and where.

The trace is sampled every ``trace_step_m`` metres of distance (and at the final point) by linear
interpolation between successive plant states; the inputs of a sample are those applied over the
step that crosses it.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from truckmpc import _core
from truckmpc.controller import Control, Controller, PlantState
from truckmpc.errors import ConfigError

if TYPE_CHECKING:
    from truckmpc.config import RunConfig
    from truckmpc.road import RoadProfile

KMH_PER_MPS = 3.6
PI_KEYS = (
    "v_ref_kmh",
    "v_inc_kmh",
    "pedal_kp",
    "pedal_ki",
    "pedal_integrator_limit",
    "brake_kp",
    "brake_ki",
    "brake_integrator_limit",
    "gear_down_rpm",
    "gear_up_rpm",
)
"""The PI settings the Rust closed loop takes (the PI's gains and gear thresholds; its v_ref is the
start speed of every run unless ``start_speed_kmh`` is set)."""
SIM_KEYS = ("plant_dt_s", "trace_step_m", "start_speed_kmh")
ARRIVAL_TOLERANCE_M = 1e-6
"""A run (or a hold ``until_m``) is complete within this distance of its target [m]."""

TRACE_COLUMNS = (
    "distance_m",
    "time_s",
    "speed_kmh",
    "gear",
    "pedal",
    "brake",
    "engine_speed_rpm",
    "slope",
    "altitude_m",
    "fuel_g",
    "brake_energy_kj",
)
"""Trace columns, in CSV order. ``fuel_g`` and ``brake_energy_kj`` are cumulative."""

CONTROLLERS: tuple[str, ...] = ("pi", "mpc")
"""Built-in controllers selectable by name (``truckmpc simulate --controller``): the PI of section 2.5
and the DP-MPC of chapter 5, both run by the Rust closed loop."""


@dataclass(frozen=True)
class RunResult:
    """Outcome of one closed-loop run.

    Attributes
    ----------
    name
        Controller name (``"pi"``); the key of its summary in ``summary.json``.
    road
        Name of the road profile driven.
    summary
        Scalar figures (see :func:`simulate`), JSON-serialisable.
    trace
        Column name -> 1-D array, sampled every ``trace_step_m`` metres plus the final point
        (columns :data:`TRACE_COLUMNS`).
    """

    name: str
    road: str
    summary: dict[str, Any]
    trace: dict[str, np.ndarray] = field(repr=False)

    @property
    def stalled(self) -> bool:
        return bool(self.summary["stalled"])

    @property
    def message(self) -> str | None:
        """One-line note on an abnormal end (``"stalled at km 1.23 ..."``), else None."""
        return self.summary.get("message")


class _TraceRecorder:
    """Collects states at the trace's sample distances by interpolating across each plant step."""

    def __init__(self, start_m: float, end_m: float, step_m: float):
        n = int(np.floor((end_m - start_m) / step_m + 1e-9)) + 1
        self._samples = start_m + step_m * np.arange(n)
        self._samples = self._samples[self._samples <= end_m]
        self._next = 0
        self.next_s = float(self._samples[0]) if len(self._samples) else float("inf")
        self.rows: list[tuple[float, ...]] = []

    def cross(self, a: PlantState, b: PlantState, u: Control) -> None:
        """Record every sample in (a.s, b.s] (a.s included for the first one)."""
        ds = b.s_m - a.s_m
        while self.next_s <= b.s_m + ARRIVAL_TOLERANCE_M:
            f = 1.0 if ds <= 0.0 else min(1.0, max(0.0, (self.next_s - a.s_m) / ds))
            self.rows.append(
                (
                    self.next_s if f < 1.0 else b.s_m,
                    a.t_s + f * (b.t_s - a.t_s),
                    a.v_mps + f * (b.v_mps - a.v_mps),
                    a.fuel_g + f * (b.fuel_g - a.fuel_g),
                    a.brake_energy_j + f * (b.brake_energy_j - a.brake_energy_j),
                    u.pedal,
                    u.brake,
                    u.gear,
                )
            )
            self._next += 1
            self.next_s = float(self._samples[self._next]) if self._next < len(self._samples) else float("inf")

    def finish(self, last: PlantState, u: Control) -> None:
        """Always end the trace on the final state."""
        if not self.rows or last.s_m - self.rows[-1][0] > ARRIVAL_TOLERANCE_M:
            self.rows.append((last.s_m, last.t_s, last.v_mps, last.fuel_g, last.brake_energy_j, *u))


def simulate(road: RoadProfile, config: RunConfig, controller: str | Controller = "pi") -> RunResult:
    """Drive ``road`` with ``controller`` from its start to its end (or a stall).

    Parameters
    ----------
    road
        The road profile.
    config
        Vehicle, PI controller and simulation settings (plant step, trace spacing, start speed).
    controller
        A name from :data:`CONTROLLERS` or a :class:`~truckmpc.controller.Controller` instance.

    Returns
    -------
    RunResult
        Summary keys: ``fuel_kg``, ``fuel_kg_per_100km``, ``time_s``, ``distance_m``,
        ``mean_speed_kmh``, ``start_speed_kmh``, ``end_speed_kmh``, ``gear_shifts``,
        ``brake_energy_kj``, ``neutral_distance_m``, ``compute_time_s`` (wall time of the run),
        ``realtime_ratio`` (compute time / simulated time), ``stalled``, ``stall_distance_m``
        (None unless stalled), ``message`` (None unless stalled), ``plant_dt_s``. The MPC adds
        ``solves``, ``infeasible_solves``, ``solve_ms_mean``, ``solve_ms_max``, ``states_per_solve``,
        ``transitions_per_solve`` and ``settings`` (its parameters as the kernel took them); a Python
        controller with a ``summary()`` method adds its entries.
    """
    if isinstance(controller, str):
        return _run_built_in(road, config, controller)
    return _run_python_loop(road, config, controller)


def _run_built_in(road: RoadProfile, config: RunConfig, name: str) -> RunResult:
    """Run a built-in controller in the Rust closed loop."""
    if name not in CONTROLLERS:
        raise ConfigError(f"controller: expected one of {', '.join(CONTROLLERS)}, got {name!r}")
    pi = {key: getattr(config.pi, key) for key in PI_KEYS}
    sim = {key: getattr(config.sim, key) for key in SIM_KEYS}
    mpc = config.mpc.core_params() if name == "mpc" else None
    altitude_m = np.ascontiguousarray(road.altitude_m, dtype=float)
    out = _core.run(config.vehicle.core(), road.core(), altitude_m, name, pi, sim, mpc)
    summary = dict(out.summary)
    if mpc is not None:
        summary["settings"] = dict(mpc)
    return RunResult(name=out.controller, road=road.name, summary=summary, trace=dict(out.trace))


def _run_python_loop(road: RoadProfile, config: RunConfig, ctrl: Controller) -> RunResult:
    """Run a controller written in Python, stepping the Rust plant once per decision or trace sample."""
    wall_start = time.perf_counter()
    sim = config.sim
    vehicle = config.vehicle.core()
    core_road = road.core()
    start_m, end_m = core_road.start_m, core_road.end_m
    v0_kmh = config.pi.v_ref_kmh if sim.start_speed_kmh is None else sim.start_speed_kmh
    plant = _core.Plant(vehicle, core_road, start_m, v0_kmh / KMH_PER_MPS)
    dt = float(sim.plant_dt_s)

    state = PlantState(*plant.state())
    ctrl.start(road, state)
    recorder = _TraceRecorder(start_m, end_m, float(sim.trace_step_m))
    make_state = PlantState._make
    step_until, advance_to = plant.step_until, plant.advance_to

    shifts = 0
    neutral_m = 0.0
    u: Control | None = None
    stuck = False
    idle_passes = 0  # consecutive passes that did not move the truck
    while not stuck and not state.stalled and end_m - state.s_m > ARRIVAL_TOLERANCE_M:
        new_u, until_m = ctrl.decide(state)
        if u is not None and new_u.gear != u.gear:
            shifts += 1
        u = new_u
        target = end_m if until_m is None or until_m > end_m else until_m
        begin = state
        while True:
            if until_m is None:
                new = make_state(step_until(u.pedal, u.brake, u.gear, dt, target))
            else:  # hold over a stage, stopping on each trace sample so samples are exact states
                goal = min(target, recorder.next_s)
                if goal - state.s_m > ARRIVAL_TOLERANCE_M:
                    new = make_state(advance_to(u.pedal, u.brake, u.gear, dt, goal))
                else:
                    new = state
            if new.s_m >= recorder.next_s - ARRIVAL_TOLERANCE_M:
                recorder.cross(state, new, u)
            idle_passes = idle_passes + 1 if new.s_m <= state.s_m else 0
            state = new
            if idle_passes > 3:  # nothing moves the truck any more (a stale hold, or rounding at the end)
                stuck = True
                break
            if until_m is None or state.stalled or target - state.s_m <= ARRIVAL_TOLERANCE_M:
                break
        if u.gear == 0:
            neutral_m += state.s_m - begin.s_m
    if u is None:  # stalled at the start: nothing was decided
        u = Control(0.0, 0.0, 1)
    recorder.finish(state, u)
    compute_s = time.perf_counter() - wall_start

    trace = _trace_arrays(recorder.rows, road, vehicle)
    distance_m = state.s_m - start_m
    summary: dict[str, Any] = {
        "distance_m": distance_m,
        "fuel_kg": state.fuel_g / 1000.0,
        "fuel_kg_per_100km": state.fuel_g / 1000.0 / (distance_m / 1e5) if distance_m > 0 else None,
        "time_s": state.t_s,
        "mean_speed_kmh": distance_m / state.t_s * KMH_PER_MPS if state.t_s > 0 else v0_kmh,
        "start_speed_kmh": v0_kmh,
        "end_speed_kmh": state.v_mps * KMH_PER_MPS,
        "gear_shifts": shifts,
        "brake_energy_kj": state.brake_energy_j / 1000.0,
        "neutral_distance_m": neutral_m,
        "compute_time_s": compute_s,
        "realtime_ratio": compute_s / state.t_s if state.t_s > 0 else None,
        "stalled": bool(state.stalled),
        "stall_distance_m": state.s_m if state.stalled else None,
        "message": None,
        "plant_dt_s": dt,
        **(ctrl.summary() if hasattr(ctrl, "summary") else {}),
    }
    if stuck and end_m - state.s_m > 1e-3:
        summary["message"] = f"stopped at km {state.s_m / 1000:.2f}: the controller's inputs no longer move the truck"
    if state.stalled:
        summary["message"] = (
            f"stalled at km {state.s_m / 1000:.2f}: the speed fell below "
            f"{vehicle.stall_speed_mps * KMH_PER_MPS:.1f} km/h, where gear 1 turns the engine at idle"
        )
    return RunResult(name=ctrl.name, road=road.name, summary=summary, trace=trace)


def _trace_arrays(rows: list[tuple[float, ...]], road: RoadProfile, vehicle: _core.Vehicle) -> dict[str, np.ndarray]:
    data = np.array(rows, dtype=float).reshape(-1, 8)
    s, t, v, fuel, brake_j, pedal, brake, gear_f = data.T
    gear = gear_f.astype(np.int64)
    distance = np.asarray(road.distance_m, dtype=float)
    slope_seg = np.asarray(road.slope, dtype=float)
    seg = np.clip(np.searchsorted(distance, s, side="right") - 1, 0, len(slope_seg) - 1)
    slope = slope_seg[seg]  # the grade of the segment ahead; the last segment's at the end point
    engine = np.array([vehicle.engine_speed_rpm(vi, int(g)) for vi, g in zip(v, gear)])
    return {
        "distance_m": s,
        "time_s": t,
        "speed_kmh": v * KMH_PER_MPS,
        "gear": gear,
        "pedal": pedal,
        "brake": brake,
        "engine_speed_rpm": engine,
        "slope": slope,
        "altitude_m": np.interp(s, distance, np.asarray(road.altitude_m, dtype=float)),
        "fuel_g": fuel,
        "brake_energy_kj": brake_j / 1000.0,
    }

"""Closed-loop simulation of a cruise controller driving the truck over a road profile.

The loop is in Rust (`truckmpc._core.run`): the plant integrates the vehicle model (B.1) and the
fuel flow (B.2) in **time** with classic RK4 at a fixed step `plant_dt_s` (default 0.05 s, about
1.2 m at 85 km/h), which keeps dv/dt finite at any speed; the last step is shortened so the run ends
on the road's end. At the default step, halving it changes trip fuel and time on the bundled test
track by far less than the 0.05 % / 0.01 % the project requires (`tests/test_sim.py` checks it).

The built-in controllers (`"pi"`, `"mpc"`, `"optimal"`) run with the GIL released. A
:class:`truckmpc.controller.Controller` written in Python runs in the same loop, which calls its
`decide(state)` whenever its previous decision runs out: after one plant step, or on reaching a
distance (a look-ahead controller holding its inputs over a stage). A truck whose speed falls below
the stall speed (gear 1 turning the engine slower than idle) stops the run: the result says
`stalled` and where.

The trace is sampled every `trace_step_m` metres of distance (and at the final point) by linear
interpolation between successive plant states; the inputs of a sample are those applied over the
step that crosses it.

A road with stops (a driving cycle's) is driven as its stop-free legs, each from its entry target
speed, and reported as one run (:mod:`truckmpc.legs`): the stops themselves are not simulated, and
the summary says so.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from truckmpc import _core
from truckmpc.consumption import consumption_of
from truckmpc.controller import Controller, PlantState
from truckmpc.errors import ConfigError
from truckmpc.fuel import beta_per_s, corrected, plan_gap_pct
from truckmpc.legs import drive_legs
from truckmpc.schema import TRACE_COLUMNS

__all__ = ["CONTROLLERS", "DP_CONTROLLERS", "TRACE_COLUMNS", "RunResult", "simulate"]

if TYPE_CHECKING:
    from truckmpc.config import RunConfig
    from truckmpc.roads import RoadProfile

CONTROLLERS: tuple[str, ...] = tuple(name for name, _, _ in _core.controllers())
"""Built-in controllers selectable by name (`truckmpc simulate --controller`), from the core's
registry (`_core.controllers()` says what each is): `pi`, `vecto_cc`, `pcc`, `mpc`, `optimal`."""

DP_CONTROLLERS = frozenset(name for name, _, solves_dp in _core.controllers() if solves_dp)
"""The built-in controllers that solve the DP (their summaries carry its settings and solves)."""


@dataclass(frozen=True)
class RunResult:
    """Outcome of one closed-loop run.

    Attributes
    ----------
    name
        Controller name (`"pi"`); the key of its summary in `summary.json`.
    road
        Name of the road profile driven.
    summary
        Scalar figures (see :func:`simulate`), JSON-serialisable.
    trace
        Column name -> 1-D array, sampled every `trace_step_m` metres plus the final point
        (columns :data:`TRACE_COLUMNS`; `gear` int64, the others float64).
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
        """One-line note on an abnormal end (`"stalled at km 1.23 ..."`), else None."""
        message = self.summary.get("message")
        return None if message is None else str(message)


def simulate(road: RoadProfile, config: RunConfig, controller: str | Controller = "pi") -> RunResult:
    """Drive `road` with `controller` from its start to its end (or a stall).

    Parameters
    ----------
    road
        The road profile (the controllers plan on its `controller_map` if it has one).
    config
        The run's settings (vehicle, cruise band, controllers, simulation).
    controller
        A name from :data:`CONTROLLERS` or a :class:`~truckmpc.controller.Controller` instance.

    Returns
    -------
    RunResult
        Its summary holds the figures declared for its runs in the core
        (:data:`truckmpc.schema.SUMMARY_SPECS`: name with unit, meaning, which runs carry it, how
        legs join it; the outputs reference page lists them): every run's, the PCC's, the DP
        controllers' (with their `settings`) and the whole-road optimum's plan, `fuel_corrected_kg`
        (the fuel with the end speed brought back to the start speed, :func:`truckmpc.fuel.corrected`;
        None if stalled; `energy_corrected_kwh` for a battery-electric truck) and, on a road with
        stops, `legs` and `stops_not_simulated` (:func:`truckmpc.legs.merge_legs`). A Python controller with a
        `summary()` method adds its entries. Its trace has the columns :data:`TRACE_COLUMNS`.
    """
    if road.stops:
        return drive_legs(road, config, lambda leg, leg_config: _drive(leg, leg_config, controller))
    return _drive(road, config, controller)


def _drive(road: RoadProfile, config: RunConfig, controller: str | Controller) -> RunResult:
    """One closed-loop run over a road without stops (see :func:`simulate`)."""
    altitude_m = np.ascontiguousarray(road.altitude_m, dtype=float)
    if isinstance(controller, str):
        if controller not in CONTROLLERS:
            raise ConfigError(f"controller: expected one of {', '.join(CONTROLLERS)}, got {controller!r}")
        told = None if road.controller_map is None else road.controller_map.core()
        figures, trace = _core.run(config.settings, road.core(), altitude_m, controller, told)
        name, extra = controller, {}
    else:
        if config.settings.get("controller_mass_kg") is not None:
            raise ConfigError(
                f"controller_mass_kg: expected null with the Python controller {controller.name!r} "
                "(it is given the truck's state, not a model), got a mass"
            )
        if road.controller_map is not None:
            raise ConfigError(
                f"controller_road: expected a built-in controller, got the Python controller {controller.name!r}"
            )
        figures, trace = _core.run_python(config.settings, road.core(), altitude_m, controller, road, PlantState)
        summary_of = getattr(controller, "summary", None)
        name, extra = controller.name, dict(summary_of()) if callable(summary_of) else {}
    summary = {**figures, **extra}
    # Kinetic energy's price in the core's store unit (grams of fuel, joules of battery energy).
    derived = config.settings.derived()
    per_half_v2 = derived["kinetic_fuel_g_per_half_v2"]
    key = consumption_of(summary).corrected_key
    summary[key] = None if summary["stalled"] else corrected(summary, per_half_v2)
    if "plan_time_s" in summary:
        summary["plan_gap_pct"] = plan_gap_pct(summary, per_half_v2, beta_per_s(derived))
    return RunResult(name=name, road=road.name, summary=summary, trace=dict(trace))

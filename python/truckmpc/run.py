"""What ``truckmpc simulate`` drives, as library calls: several controllers over one road, each
look-ahead run against the PI (and against the PCC, when it ran) re-tuned to its trip time, and the
MPC at half δ, half S (and twice its pedal levels) when asked (:mod:`truckmpc.convergence`)::

    from truckmpc import default_test_track, load_run_config, write_outputs
    from truckmpc.run import run_controllers

    road, config = default_test_track(), load_run_config()
    runs = run_controllers(road, config, ("pi", "mpc"))
    write_outputs("out/test-track", road, runs.results, extra=runs.extra, equal_times=runs.equal_times)
"""

from __future__ import annotations

import contextlib
from collections.abc import Callable, Mapping, Sequence
from contextlib import AbstractContextManager
from dataclasses import dataclass
from typing import Any

from truckmpc.compare import headline
from truckmpc.config import RunConfig
from truckmpc.consumption import consumption_of
from truckmpc.convergence import convergence_document, run_halves
from truckmpc.equal_time import BASELINES, EqualTime, compared_with, equal_time_baselines
from truckmpc.roads import RoadProfile
from truckmpc.sim import RunResult, simulate
from truckmpc.workload import EQUAL_TIME_RUNS, check_runs, duration

__all__ = ["ControllerRuns", "Status", "check_work", "planned_runs", "run_controllers"]

Status = Callable[[str], AbstractContextManager[object]]
"""Shows a text while a block runs, e.g. :func:`truckmpc.status.status_line` (a spinner on stderr)."""


@dataclass(frozen=True)
class ControllerRuns:
    """What :func:`run_controllers` drove: one result per controller, the equal-time baselines
    (keyed by look-ahead controller against the PI; ``<name>_vs_<baseline>`` against VECTO's cruise
    driver and the PCC) and the extra objects of ``summary.json`` (``convergence``, with halved
    configurations)."""

    results: dict[str, RunResult]
    equal_times: dict[str, EqualTime]
    extra: dict[str, Any]


def planned_runs(controllers: Sequence[str]) -> list[str]:
    """The runs :func:`run_controllers` makes, for the work estimate: the controllers and, for each
    baseline among them, a typical equal-time search's runs of it per controller compared with it."""
    retuned = [
        baseline
        for baseline in BASELINES
        if baseline in controllers
        for name in controllers
        if name in compared_with(baseline)
        for _ in range(EQUAL_TIME_RUNS)
    ]
    return [*controllers, *retuned]


def check_work(
    road: RoadProfile,
    config: RunConfig,
    controllers: Sequence[str],
    *,
    force: bool = False,
    halves: Mapping[str, RunConfig] | None = None,
) -> float:
    """The estimated seconds [s] of :func:`run_controllers`; refuses too much work or memory as
    :func:`truckmpc.workload.check_runs` does (a :class:`~truckmpc.workload.WorkError`)."""
    return check_runs(road, config, planned_runs(controllers), force=force, extra=(halves or {}).values())


def _silent(text: str) -> AbstractContextManager[object]:
    return contextlib.nullcontext()


def run_controllers(
    road: RoadProfile,
    config: RunConfig,
    controllers: Sequence[str],
    halves: Mapping[str, RunConfig] | None = None,
    *,
    status: Status = _silent,
    estimate_s: float | None = None,
) -> ControllerRuns:
    """Drive each of `controllers` (names of :data:`truckmpc.sim.CONTROLLERS`) over `road`, then the
    equal-time baselines; with `halves` (:func:`truckmpc.convergence.halved_configs`, which needs
    the PI and the MPC among the controllers) the MPC at each halved configuration too.

    `status` shows what is being driven; `estimate_s` [s], the estimate of all of it, is shown with
    each controller's run.
    """
    told = "" if estimate_s is None else f" (estimate for all: {duration(estimate_s)})"
    results = {}
    for name in controllers:
        with status(f"{name}: driving {road.name}{told}"):
            results[name] = simulate(road, config, name)
    equal_times: dict[str, EqualTime] = {}
    for baseline in (name for name in BASELINES if name in results):
        with status(f"{baseline} re-tuned to each look-ahead run's trip time: driving {road.name}"):
            found = equal_time_baselines(road, config, results, baseline=baseline)
        suffix = "" if baseline == "pi" else f"_vs_{baseline}"
        equal_times.update({f"{name}{suffix}": value for name, value in found.items()})
    extra = {}
    if halves:
        with status(f"mpc at half delta_kmh, half stage_m (and twice pedal_levels): driving {road.name}"):
            halved = run_halves(road, halves)
        with status(f"pi re-tuned to each halved run's trip time: driving {road.name}"):
            runs = {"mpc": results["mpc"], **halved}
            searched = {half: _equal_time_of(road, config, results["pi"], run) for half, run in halved.items()}
            equal = {"mpc": equal_times.get("mpc"), **searched}
            pct = {name: _equal_time_pct(runs[name], equal[name]) for name in runs}
            quoted = {name: _headline_pct(runs[name], equal[name]) for name in runs}
        extra["convergence"] = convergence_document(results, halved, halves, pct, quoted)
    return ControllerRuns(results, equal_times, extra)


def _equal_time_of(road: RoadProfile, config: RunConfig, pi: RunResult, mpc: RunResult) -> EqualTime | None:
    """The PI over `road` re-tuned to the trip time of the MPC run `mpc` (None if it stalled)."""
    return equal_time_baselines(road, config, {"pi": pi, "mpc": mpc}).get("mpc")


def _headline_pct(run: RunResult, found: EqualTime | None) -> float | None:
    """The headline [%] of `run` against the PI driven to its trip time, both end speeds corrected;
    None where the search missed it."""
    if found is None or not found.reached:
        return None
    return headline(run.summary.get(consumption_of(run.summary).corrected_key), found.consumed_corrected).pct


def _equal_time_pct(run: RunResult, found: EqualTime | None) -> float | None:
    """Δfuel [%] of `run` against the PI driven to its trip time; None where the search missed it."""
    return None if found is None else found.delta_pct_of(float(run.summary[consumption_of(run.summary).key]))

"""One run of a sweep or Pareto study, as a worker (a Dask worker process, or this process) runs it:
a PI, PCC or MPC run over one road with one vehicle and its overrides, with the look-ahead runs'
equal-time baselines and convergence moves. A run that raises comes back as its error, one line,
so that the other runs go on."""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from typing import Any, NamedTuple

from truckmpc import sim
from truckmpc.config import RunConfig, load_run_config
from truckmpc.consumption import consumption_of
from truckmpc.convergence import convergence_document, halved_configs, run_halves
from truckmpc.equal_time import equal_time_baselines
from truckmpc.errors import RoadError, TruckmpcError
from truckmpc.roads import RoadProfile
from truckmpc.sim import RunResult, simulate
from truckmpc.sweep.columns import ERROR_COLUMN, convergence_fields, runs_of
from truckmpc.sweep.compared import equal_time_fields

ERROR = ERROR_COLUMN
"""The key of a failed run's one-line error in its figures (which hold nothing else): the name of
the column it goes to."""


class Task(NamedTuple):
    """One run: ``controller`` over road number ``road`` with vehicle number ``vehicle`` and
    ``overrides``, for plan row ``row`` (for a shared run: one of the rows whose run of
    ``controller`` has this ``key``). A look-ahead run is also compared at equal trip time with each
    of ``baselines`` unless ``plain``, and an MPC run driven again at half δ and half S with
    ``convergence``."""

    controller: str
    road: int
    overrides: tuple[str, ...]
    row: int
    key: str
    plain: bool = False
    convergence: bool = False
    baselines: tuple[str, ...] = ("pi",)
    vehicle: int = 0


class RunBase(NamedTuple):
    """What every run of a study starts from: the vehicle files (one per ``Task.vehicle``; None:
    the packaged truck) and the ``--config`` overlays, as absolute paths where a worker reads them."""

    vehicles: tuple[str | None, ...]
    config_paths: tuple[str, ...]


class BrokenRoad(NamedTuple):
    """A road file of a fleet (found in a directory or by a glob) that could not be read: its rows
    are planned, and each of their runs fails with ``message``."""

    name: str
    source: str
    message: str

    def sha256(self) -> None:
        """No content to identify the road by."""
        return None


Road = RoadProfile | BrokenRoad
"""A road of a sweep: a profile, or a fleet's file that could not be read."""


def run_task(road: Road, base: RunBase, task: Task) -> dict[str, Any]:
    """The figures of `task` over `road` by field name, or ``{"error": one line}`` if it raised."""
    try:
        if isinstance(road, BrokenRoad):
            raise RoadError(road.message)
        config = load_run_config(base.vehicles[task.vehicle], base.config_paths, task.overrides)
        return _figures(road, config, task)
    except Exception as err:  # a failed run is reported in its rows, not raised
        return {ERROR: error_line(err)}


def error_line(err: BaseException) -> str:
    """A run's error as one line: a user-facing error's message, else the exception's type and text."""
    text = str(err) if isinstance(err, TruckmpcError) else f"{type(err).__name__}: {err}"
    return " ".join(text.split())


def _figures(profile: RoadProfile, config: RunConfig, task: Task) -> dict[str, Any]:
    """Run one controller (``pi``, ``pcc``, ``mpc``) over `profile`; its figures by field name (a
    look-ahead run's with each of the task's baselines re-tuned to its trip time, unless plain, and
    an MPC run's convergence moves when asked)."""
    result = simulate(profile, config, task.controller)
    consumption = consumption_of(result.summary)
    figures = {name: result.summary.get(name) for name in runs_of(consumption)[task.controller].fields}
    if task.controller == "pi" or task.plain:
        return figures
    # The baselines at v_ref again, in this worker: each equal-time search starts from its baseline's
    # run and the convergence moves are measured against the PI's (not the sweep's shared runs).
    bases = {name: sim.simulate(profile, config, name) for name in task.baselines}
    for base in bases.values():
        figures.update(_equal_time_figures(profile, config, base, result))
    if task.convergence:
        halves = halved_configs(config)
        moves = convergence_document({"pi": bases["pi"], "mpc": result}, run_halves(profile, halves), halves)
        figures.update({field: moves.get(field) for field in convergence_fields(consumption)})
    return figures


def _equal_time_figures(profile: RoadProfile, config: RunConfig, base: RunResult, run: RunResult) -> dict[str, Any]:
    """`base`'s controller re-tuned to `run`'s trip time, starting from `base` (its run at v_ref):
    ``equal_time_<base>_*`` (:func:`~truckmpc.sweep.compared.equal_time_fields`), None each where the
    time was not reached."""
    fields = equal_time_fields(base.name, consumption_of(run.summary))
    figures: dict[str, Any] = dict.fromkeys(fields)
    if run.stalled:
        return figures
    found = equal_time_baselines(profile, config, {base.name: base, run.name: run}, base.name).get(run.name)
    if found is not None and found.reached:
        figures.update(zip(fields, (found.v_ref_kmh, found.consumed, found.consumed_corrected), strict=True))
    return figures


def run_all(roads: Sequence[Road], base: RunBase, tasks: Sequence[Task]) -> Iterator[tuple[Task, dict[str, Any]]]:
    """Each task's ``(task, figures)`` in this process, in order (one job, or a single run)."""
    for task in tasks:
        yield task, run_task(roads[task.road], base, task)

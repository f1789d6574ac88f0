"""Running a sweep's PI, PCC and MPC runs: in this process (one job) or in a pool of spawned processes."""

from __future__ import annotations

import multiprocessing
import signal
from collections.abc import Iterator, Sequence
from concurrent.futures import ProcessPoolExecutor, as_completed
from concurrent.futures.process import BrokenProcessPool
from typing import Any, NamedTuple

from truckmpc import sim
from truckmpc.config import RunConfig, load_run_config
from truckmpc.convergence import convergence_document, halved_configs, run_halves
from truckmpc.equal_time import equal_time_baselines
from truckmpc.road import RoadProfile
from truckmpc.signals import received_signal
from truckmpc.sim import RunResult, simulate
from truckmpc.sweep.columns import CONVERGENCE_COLUMNS, RUNS, equal_time_fields
from truckmpc.sweep.errors import SweepWorkerDied


class Task(NamedTuple):
    """One run: ``controller`` over road number ``road`` with ``overrides``, for plan row ``row``
    (for a shared run: one of the rows whose run of ``controller`` has this ``key``). A look-ahead
    run is also compared at equal trip time with each of ``baselines`` unless ``plain``, and an MPC
    run driven again at half δ and half S with ``convergence``."""

    controller: str
    road: int
    overrides: tuple[str, ...]
    row: int
    key: str
    plain: bool = False
    convergence: bool = False
    baselines: tuple[str, ...] = ("pi",)


_WORKER: dict[str, Any] = {}


def _init_worker(roads: Sequence[RoadProfile], base: tuple[str | None, tuple[str, ...]], ignore_sigint: bool) -> None:
    """Per process: the roads (sent once) and the base files; workers leave Ctrl-C to the parent."""
    if ignore_sigint:
        signal.signal(signal.SIGINT, signal.SIG_IGN)
    _WORKER.update(roads=list(roads), base=base)


def run_one(
    controller: str,
    road: int,
    overrides: Sequence[str],
    plain: bool = False,
    convergence: bool = False,
    baselines: Sequence[str] = ("pi",),
) -> dict[str, Any]:
    """Run one controller (``pi``, ``pcc``, ``mpc``) over one road of the current worker's sweep;
    its figures by field name (a look-ahead run's with each of `baselines` re-tuned to its trip
    time, unless ``plain``, and an MPC run's convergence moves with ``convergence``)."""
    vehicle_path, config_paths = _WORKER["base"]
    config = load_run_config(vehicle_path, config_paths, overrides)
    profile = _WORKER["roads"][road]
    result = simulate(profile, config, controller)
    figures = {name: result.summary.get(name) for name in RUNS[controller].fields}
    if controller == "pi" or plain:
        return figures
    # The baselines at v_ref again, in this worker: each equal-time search starts from its baseline's
    # run and the convergence moves are measured against the PI's (not the sweep's shared runs).
    bases = {name: sim.simulate(profile, config, name) for name in baselines}
    for base in bases.values():
        figures.update(_equal_time_figures(profile, config, base, result))
    if convergence:
        halves = halved_configs(config)
        moves = convergence_document({"pi": bases["pi"], "mpc": result}, run_halves(profile, halves), halves)
        figures.update({column: moves[column] for column in CONVERGENCE_COLUMNS})
    return figures


def _equal_time_figures(profile: RoadProfile, config: RunConfig, base: RunResult, run: RunResult) -> dict[str, Any]:
    """`base`'s controller re-tuned to `run`'s trip time, starting from `base` (its run at v_ref):
    ``equal_time_<base>_*`` (:func:`~truckmpc.sweep.columns.equal_time_fields`), None each where the
    time was not reached."""
    fields = equal_time_fields(base.name)
    figures: dict[str, Any] = dict.fromkeys(fields)
    if run.stalled:
        return figures
    found = equal_time_baselines(profile, config, {base.name: base, run.name: run}, base.name).get(run.name)
    if found is not None and found.reached:
        figures.update(zip(fields, (found.v_ref_kmh, found.fuel_kg, found.fuel_corrected_kg), strict=True))
    return figures


class Runner:
    """Runs tasks in this process (jobs=1) or in a pool of spawned processes, yielding
    ``(task, figures)`` as they finish. Leaving the block early (an error, Ctrl-C) stops the workers
    at once, mid-run."""

    def __init__(self, roads: Sequence[RoadProfile], base: tuple[str | None, tuple[str, ...]], jobs: int) -> None:
        self.roads, self.base, self.jobs = roads, base, jobs
        self._pool: ProcessPoolExecutor | None = None

    def __enter__(self) -> Runner:
        return self

    def __exit__(self, exc_type: object, *exc: object) -> None:
        pool, self._pool = self._pool, None
        if pool is None:
            return
        if exc_type is not None:  # don't wait for runs nobody will read
            if hasattr(pool, "terminate_workers"):  # Python >= 3.14
                pool.terminate_workers()
            else:
                for process in list(getattr(pool, "_processes", {}).values()):
                    process.terminate()
        pool.shutdown(wait=True, cancel_futures=True)

    def results(self, tasks: Sequence[Task]) -> Iterator[tuple[Task, dict[str, Any]]]:
        if self.jobs <= 1 or len(tasks) <= 1:
            _init_worker(self.roads, self.base, ignore_sigint=False)
            for task in tasks:
                yield task, run_one(*_arguments(task))
            return
        # Workers are spawned (not forked: this process may run threads) while submitting; they
        # inherit an ignored SIGINT through exec, so Ctrl-C reaches only this process.
        previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
        try:
            self._pool = ProcessPoolExecutor(
                min(self.jobs, len(tasks)),
                multiprocessing.get_context("spawn"),
                _init_worker,
                (self.roads, self.base, True),
            )
            futures = {self._pool.submit(run_one, *_arguments(t)): t for t in tasks}
        finally:
            signal.signal(signal.SIGINT, previous)
        try:
            for future in as_completed(futures):
                yield futures[future], future.result()
        except BrokenProcessPool:
            if received_signal() is not None:  # the signal reached the workers too (sent to the process group)
                raise KeyboardInterrupt from None
            raise SweepWorkerDied(
                "a sweep worker process died (killed? out of memory?); run the same command again to resume"
            ) from None


def _arguments(task: Task) -> tuple[Any, ...]:
    """The arguments of :func:`run_one` for `task`."""
    return task.controller, task.road, task.overrides, task.plain, task.convergence, task.baselines

"""Running a sweep's PI and MPC runs: in this process (one job) or in a pool of spawned processes."""

from __future__ import annotations

import multiprocessing
import signal
from collections.abc import Iterator, Sequence
from concurrent.futures import ProcessPoolExecutor, as_completed
from concurrent.futures.process import BrokenProcessPool
from typing import Any, NamedTuple

from truckmpc.config import load_run_config
from truckmpc.road import RoadProfile
from truckmpc.signals import received_signal
from truckmpc.sim import simulate
from truckmpc.sweep.columns import MPC_FIELDS, PI_FIELDS
from truckmpc.sweep.errors import SweepWorkerDied


class Task(NamedTuple):
    """One run: ``controller`` over road number ``road`` with ``overrides``, for plan row ``row``
    (for a PI run: one of the rows sharing ``pi_key``)."""

    controller: str
    road: int
    overrides: tuple[str, ...]
    row: int
    pi_key: str


_WORKER: dict[str, Any] = {}


def _init_worker(roads: Sequence[RoadProfile], base: tuple[str | None, tuple[str, ...]], ignore_sigint: bool) -> None:
    """Per process: the roads (sent once) and the base files; workers leave Ctrl-C to the parent."""
    if ignore_sigint:
        signal.signal(signal.SIGINT, signal.SIG_IGN)
    _WORKER.update(roads=list(roads), base=base)


def run_one(controller: str, road: int, overrides: Sequence[str]) -> dict[str, Any]:
    """Run one controller over one road of the current worker's sweep; its figures by field name."""
    vehicle_path, config_paths = _WORKER["base"]
    config = load_run_config(vehicle_path, config_paths, overrides)
    summary = simulate(_WORKER["roads"][road], config, controller).summary
    fields = PI_FIELDS if controller == "pi" else MPC_FIELDS
    return {name: summary.get(name) for name in fields}


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
                yield task, run_one(task.controller, task.road, task.overrides)
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
            futures = {self._pool.submit(run_one, t.controller, t.road, t.overrides): t for t in tasks}
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

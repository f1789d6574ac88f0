"""Running a study's tasks: in this process (one job, or a single run on the embedded cluster), or
on a Dask cluster (:mod:`truckmpc.sweep.cluster`), yielding each run's figures as it finishes.

On a cluster each road is a small task of its own, which every run over it depends on: a worker
fetches it once, and if the worker holding it dies, the scheduler makes it again from the task. A
run whose worker dies is run again on another one (Dask's own rescheduling); a run that kills
:data:`ALLOWED_FAILURES` workers comes back as its error, like a run that raises.
"""

from __future__ import annotations

import os
import uuid
from collections.abc import Callable, Iterator, Sequence
from typing import Any

from truckmpc.signals import received_signal
from truckmpc.sweep.cluster import Cluster, scheduler_address
from truckmpc.sweep.errors import SweepWorkerDied
from truckmpc.sweep.task import ERROR, Road, RunBase, Task, run_all, run_task

Notice = Callable[[str], None]

ProgressHook = Callable[[int, int], None]
"""``hook(done_runs, total_runs)`` of the runs this call makes, called at the start and after each run."""

ALLOWED_FAILURES = 3
"""Workers a run may kill before it is given up (Dask's ``distributed.scheduler.allowed-failures``)."""


class Runner:
    """Runs tasks in this process or on a Dask cluster, yielding ``(task, figures)`` as they finish
    (figures ``{"error": line}`` for a run that failed). A context manager: leaving the block early
    (an error, Ctrl-C) stops the embedded cluster's workers at once, mid-run, and cancels the runs
    sent to a running cluster."""

    def __init__(
        self,
        roads: Sequence[Road],
        base: RunBase,
        jobs: int | None,
        scheduler: str | None = None,
        notice: Notice | None = None,
    ) -> None:
        """`jobs`: worker processes of the embedded cluster (1: this process; None: one per core);
        `scheduler` (default ``$TRUCKMPC_SCHEDULER``): the address of a running cluster's scheduler
        instead (connected to at once)."""
        self.roads, self.base, self.scheduler = roads, base, scheduler_address(scheduler)
        self._jobs, self._notice = max(1, jobs or os.cpu_count() or 1), notice
        self._cluster: Cluster | None = None if self.scheduler is None else Cluster(self.scheduler, 0)

    @property
    def jobs(self) -> int:
        """Runs at once: the embedded cluster's workers, or a running cluster's threads now."""
        return self._jobs if self._cluster is None else self._cluster.workers

    def __enter__(self) -> Runner:
        return self

    def __exit__(self, exc_type: object, *exc: object) -> None:
        cluster, self._cluster = self._cluster, None
        if cluster is not None:
            cluster.close(failed=exc_type is not None)

    def results(
        self, tasks: Sequence[Task], progress: ProgressHook | None = None
    ) -> Iterator[tuple[Task, dict[str, Any]]]:
        """``(task, figures)`` of each task as it finishes, the longest first where there is a choice;
        `progress` hears of each once the caller has taken it."""
        if progress:
            progress(0, len(tasks))
        for finished, result in enumerate(self._finishing(tasks), start=1):
            yield result
            if progress:
                progress(finished, len(tasks))

    def _finishing(self, tasks: Sequence[Task]) -> Iterator[tuple[Task, dict[str, Any]]]:
        if not tasks:
            return
        if self._cluster is None and (self._jobs <= 1 or len(tasks) <= 1):
            yield from run_all(self.roads, self.base, tasks)
            return
        if self._cluster is None:
            self._cluster = Cluster(None, min(self._jobs, len(tasks)))
        yield from self._on_cluster(self._cluster, tasks)

    def _on_cluster(self, cluster: Cluster, tasks: Sequence[Task]) -> Iterator[tuple[Task, dict[str, Any]]]:
        # distributed is loaded only when runs go to workers (start-up time)
        from distributed import as_completed

        client, prefix = cluster.client, f"truckmpc-{uuid.uuid4().hex[:12]}"
        self._say_where(cluster, len(tasks))
        first = len(tasks) + 1  # priorities: the roads, then the runs in the order given
        roads = {r: client.submit(_road, self.roads[r], key=f"road-{prefix}-{r}", priority=first) for r in _used(tasks)}
        futures = {}
        for i, task in enumerate(tasks):
            key = f"run-{prefix}-{i}"
            futures[client.submit(run_task, roads[task.road], self.base, task, key=key, priority=first - 1 - i)] = task
        for future in as_completed(futures):
            yield futures.pop(future), _outcome(future, cluster)

    def _say_where(self, cluster: Cluster, runs: int) -> None:
        """One line on where the runs go (a running cluster) and one with the dashboard's link."""
        if self._notice is None:
            return
        if cluster.address is not None:
            self._notice(f"{runs} runs on the Dask cluster at {cluster.address} ({cluster.workers} workers now)")
        dashboard = cluster.dashboard  # each read asks the scheduler
        if dashboard is not None:
            self._notice(f"Dask dashboard: {dashboard}")


def _used(tasks: Sequence[Task]) -> list[int]:
    """The roads `tasks` drive."""
    return sorted({task.road for task in tasks})


def _road(road: Road) -> Road:
    """A road as a task's result, so that the scheduler can make it again if its worker dies."""
    return road


def _outcome(future: Any, cluster: Cluster) -> dict[str, Any]:
    """A finished future's figures; a run that killed its workers as its error; a lost cluster as
    :class:`SweepWorkerDied`."""
    # distributed is loaded only when runs go to workers (start-up time)
    from distributed import KilledWorker

    try:
        figures: dict[str, Any] = future.result()
    except KilledWorker:
        return {ERROR: f"the run killed {ALLOWED_FAILURES} Dask workers (out of memory?)"}
    except Exception as err:
        if received_signal() is not None:  # the signal reached the workers too (sent to the process group)
            raise KeyboardInterrupt from None
        where = "the embedded Dask cluster" if cluster.address is None else f"the Dask cluster at {cluster.address}"
        raise SweepWorkerDied(f"lost {where} ({type(err).__name__}); run the same command again to resume") from None
    return figures

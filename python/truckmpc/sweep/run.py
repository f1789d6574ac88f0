"""Running (or resuming) a sweep into a directory: the rows already there are kept, the missing
ones run, and ``sweep.csv`` is written when all are done."""

from __future__ import annotations

import sys
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from truckmpc.roads import RoadProfile
from truckmpc.roads.profile import PathLike
from truckmpc.sweep.columns import DEFAULT_CONTROLLERS
from truckmpc.sweep.errors import SweepInterrupted
from truckmpc.sweep.files import (
    PARTIAL_NAME,
    PartialFile,
    check_out_dir,
    csv_line,
    finished_rows,
    write_final,
    write_settings,
)
from truckmpc.sweep.grid import Axis
from truckmpc.sweep.plan import SHARED_SECTIONS, Row, SweepPlan, plan_sweep
from truckmpc.sweep.renamed import ADDED_COLUMNS, RENAMED_COLUMNS
from truckmpc.sweep.runner import ProgressHook, Runner
from truckmpc.sweep.task import RunBase, Task
from truckmpc.sweep.waiting import Run, Waiting
from truckmpc.workload import EQUAL_TIME_RUNS, MAX_WORK_S, Work, WorkError, memory_limit_bytes, too_big, too_long


@dataclass(frozen=True)
class SweepResult:
    """A finished sweep: its CSV, its rows (column -> cell text, grid order) and what ran (runs by
    controller, this time)."""

    csv_path: Path
    columns: tuple[str, ...]
    rows: list[dict[str, str]]
    runs: Mapping[str, int]
    resumed_rows: int

    @property
    def pi_runs(self) -> int:
        return self.runs.get("pi", 0)

    @property
    def mpc_runs(self) -> int:
        return self.runs.get("mpc", 0)


def run_sweep(
    roads: Sequence[RoadProfile | PathLike],
    grid: Sequence[Axis | str] | Mapping[str, Sequence[Any]],
    out: PathLike,
    *,
    reverse: bool | str = False,
    vehicle_path: PathLike | Sequence[PathLike] | None = None,
    config_paths: Sequence[PathLike] = (),
    overrides: Sequence[str] = (),
    jobs: int | None = None,
    progress: ProgressHook | None = None,
    force: bool = False,
    check_convergence: bool = False,
    controllers: Sequence[str] = DEFAULT_CONTROLLERS,
    scheduler: str | None = None,
) -> SweepResult:
    """Run (or resume) a sweep into directory ``out``: the PI and `controllers` (``pcc``, ``mpc``)
    on every road for every combination of ``grid`` (``["horizon_m=250:3000:250",
    "delta_kmh=0.1,0.2"]`` or ``{"horizon_m": [250, 500]}``), each road reversed or both ways
    (``reverse="both"``), with one vehicle file or several; see :mod:`truckmpc.sweep`,
    :func:`~truckmpc.sweep.plan.plan_sweep` and :func:`run_plan`.

    Every combination is validated before anything runs or ``out`` is created.
    """
    plan = plan_sweep(
        roads,
        grid,
        reverse=reverse,
        vehicle_path=vehicle_path,
        config_paths=config_paths,
        overrides=overrides,
        check_convergence=check_convergence,
        controllers=controllers,
    )
    return run_plan(plan, out, jobs=jobs, progress=progress, force=force, scheduler=scheduler)


def run_plan(
    plan: SweepPlan,
    out: PathLike,
    *,
    jobs: int | None = None,
    progress: ProgressHook | None = None,
    force: bool = False,
    notice: Callable[[str], None] | None = None,
    scheduler: str | None = None,
) -> SweepResult:
    """Run (or resume) a planned sweep into directory ``out``; see :mod:`truckmpc.sweep`.

    ``jobs``: worker processes of the embedded Dask cluster (default ``os.cpu_count()``); 1 runs in
    this process. ``scheduler``: the address of a running Dask cluster's scheduler to send the runs
    to instead. ``mpc_realtime_ratio`` of each row is measured under whatever load the other jobs make.
    Raises :class:`SweepError` if ``out`` holds a different sweep,
    :class:`~truckmpc.workload.WorkError` if the runs left would take more than an hour (unless
    ``force``); damaged rows resumed from ``out`` are dropped, to run again, and ``notice`` (default:
    a line on stderr) is told; so are rows whose runs failed. A run that fails (raises, or kills its
    workers) leaves its error in its rows' ``error`` column and the other runs go on. On
    ``KeyboardInterrupt`` the workers are stopped, the finished rows stay in ``sweep.partial.csv``
    and :class:`SweepInterrupted` (a ``KeyboardInterrupt``) says how many.
    """
    out, notice = Path(out), notice or _to_stderr
    check_out_dir(out, plan.settings, renames=RENAMED_COLUMNS, added=ADDED_COLUMNS)
    done = _resumed_rows(plan, out, notice)
    resumed = len(done)
    pending = [row for row in plan.rows if row.index not in done]
    known = _resumed_runs(plan, done)
    tasks = _tasks(plan, pending, known)
    base = run_base(plan.vehicle_paths, plan.config_paths)
    header = csv_line(plan.columns)
    try:
        with Runner(plan.roads, base, jobs, scheduler, notice) as runner:
            _check_work(plan, tasks, runner.jobs, force)
            out.mkdir(parents=True, exist_ok=True)
            write_settings(out, plan.settings, runner.jobs)
            partial = PartialFile(out / PARTIAL_NAME, header, [csv_line(cells) for _, cells in sorted(done.items())])
            try:
                _run_rows(plan, pending, runner, tasks, known, done, partial, progress)
            finally:
                partial.close()
    except KeyboardInterrupt:
        # A signal during the runs, or while the workers shut down after it (a second interrupt
        # from a worker's failed run): the finished rows are in the partial file either way.
        if not (out / PARTIAL_NAME).exists():
            raise
        raise SweepInterrupted(len(done), len(plan.rows), out / PARTIAL_NAME) from None
    ordered = [done[row.index] for row in plan.rows]
    return SweepResult(
        write_final(out, header, ordered),
        plan.columns,
        [dict(zip(plan.columns, cells, strict=True)) for cells in ordered],
        runs={name: sum(task.controller == name for task in tasks) for name in plan.layout.runs},
        resumed_rows=resumed,
    )


def _run_rows(
    plan: SweepPlan,
    pending: Sequence[Row],
    runner: Runner,
    tasks: Sequence[Task],
    known: Mapping[Run, dict[str, Any]],
    done: dict[int, list[str]],
    partial: PartialFile,
    progress: ProgressHook | None,
) -> None:
    """Run `tasks`, putting each pending row into `done` and `partial` as soon as its runs are in."""
    for index, cells in _rows_as_they_finish(plan, pending, runner.results(tasks, progress), known):
        done[index] = cells
        partial.append(csv_line(cells))


def run_base(vehicles: Sequence[str | None], config_paths: Sequence[str]) -> RunBase:
    """The files every run reads, as absolute paths (a worker may run elsewhere, on a shared file
    system); a packaged preset's name, or None for the packaged truck, as it is."""
    return RunBase(tuple(None if v is None else _absolute(v) for v in vehicles), tuple(map(_absolute, config_paths)))


def _absolute(path: str) -> str:
    return str(Path(path).resolve()) if Path(path).exists() else path


def _to_stderr(text: str) -> None:
    print(text, file=sys.stderr)


def _check_work(plan: SweepPlan, tasks: Sequence[Task], jobs: int, force: bool) -> None:
    """Refuse, unless ``force``, tasks whose estimated wall time on ``jobs`` processes is beyond the
    limit, or whose largest dynamic programs, ``jobs`` of them at once, would hold more memory than
    the limit."""
    if force or not tasks:
        return
    works = [(plan.rows[t.row].work, t.controller) for t in tasks]
    costs = [_cost(plan.rows[t.row].work, t) for t in tasks]
    at_once = max(1, min(jobs, len(tasks)))
    where = "--grid" if plan.axes else "sweep"
    runs = f"for {len(tasks)} runs on {jobs} process{'es' if jobs > 1 else ''}"
    largest = sorted((work.dp_bytes for work, controller in works if controller == "mpc"), reverse=True)
    dp_bytes, limit_bytes = sum(largest[:at_once]), memory_limit_bytes()
    if dp_bytes > limit_bytes:
        raise WorkError(f"{where}: {too_big(dp_bytes, limit_bytes, runs)}")
    wall_s = max(sum(costs) / at_once, max(costs))
    if wall_s > MAX_WORK_S:
        raise WorkError(f"{where}: {too_long(wall_s, runs)}")


def _cost(work: Work, task: Task) -> float:
    """Estimated seconds of a task [s] from its row's look-ahead `work`: a PI run the plant's; a PCC
    run the plant's, an MPC run its DP's too, each with some EQUAL_TIME_RUNS runs of the plant per
    baseline re-tuned to its trip time."""
    if task.controller == "pi":
        return work.plant_s
    own_s = work.plant_s if task.controller == "pcc" else work.total_s
    return own_s + len(task.baselines) * EQUAL_TIME_RUNS * work.plant_s


def _resumed_rows(plan: SweepPlan, out: Path, notice: Callable[[str], None]) -> dict[int, list[str]]:
    """Row index -> cells of the plan's rows already in ``out`` (the first copy of each). A damaged
    row (a cell that is not what the sweep writes there, a wrong number of cells, axis values not in
    this sweep) is dropped, to run again, and ``notice`` is told in one line; so is a row whose runs
    failed (its error may have passed: a worker out of memory)."""
    by_key = {plan.row_key(row): row for row in plan.rows}
    first_result = len(plan.key_columns)
    done: dict[int, list[str]] = {}
    dropped: list[str] = []
    failed: set[int] = set()
    for where, cells in finished_rows(out, plan.columns, renames=RENAMED_COLUMNS, added=ADDED_COLUMNS):
        row = by_key.get(tuple(cells[:first_result]))
        if row is not None and plan.layout.failed(cells[first_result:]):
            failed.add(row.index)
            continue
        damage = None if row is None else plan.layout.damaged(cells[first_result:])
        problem = "not a row of this sweep" if row is None else damage
        if problem is not None or row is None:
            dropped.append(f"{where}: {problem}")
        else:  # an earlier version's row gets its headline from its own figures
            done.setdefault(row.index, [*cells[:first_result], *plan.layout.completed(cells[first_result:])])
    if dropped:
        rows = "1 damaged row" if len(dropped) == 1 else f"{len(dropped)} damaged rows"
        notice(f"dropped {rows}, to run again ({dropped[0]}{'; ...' if len(dropped) > 1 else ''})")
    if failed - done.keys():
        notice(f"running again {_rows_text(len(failed - done.keys()))} whose runs failed")
    return done


def _rows_text(count: int) -> str:
    return "1 row" if count == 1 else f"{count} rows"


def _resumed_runs(plan: SweepPlan, done: Mapping[int, Sequence[str]]) -> dict[Run, dict[str, Any]]:
    """The shared runs' figures read back from finished rows, so that those runs are not repeated."""
    first_result = len(plan.key_columns)
    known: dict[Run, dict[str, Any]] = {}
    for index, cells in done.items():
        for name, key in plan.rows[index].keys.items():
            if name in SHARED_SECTIONS and (name, key) not in known:
                known[name, key] = plan.layout.figures(name, cells[first_result:])
    return known


def _tasks(plan: SweepPlan, pending: Sequence[Row], known: Mapping[Run, Any]) -> list[Task]:
    """The runs the pending rows need and `known` lacks: the shared runs first (the PI's, then the
    PCC's; rows wait for them), once per key, then the rows' own runs longest first, so that the
    cluster does not end on one long run while the other workers idle (the runner keeps this order)."""
    by_cost = sorted(pending, key=lambda r: -r.cost)
    tasks: dict[Run, Task] = {}
    for name in plan.layout.runs:
        baselines = plan.layout.baselines(name)
        convergence = plan.check_convergence and name == "mpc"
        for row in pending if name in SHARED_SECTIONS else by_cost:
            run = (name, row.keys[name])
            if run not in known and run not in tasks:
                own = (False, convergence, baselines, row.vehicle)
                tasks[run] = Task(name, row.road, row.overrides, row.index, run[1], *own)
    return list(tasks.values())


def _rows_as_they_finish(
    plan: SweepPlan,
    pending: Sequence[Row],
    results: Iterable[tuple[Task, dict[str, Any]]],
    known: Mapping[Run, dict[str, Any]],
) -> Iterator[tuple[int, list[str]]]:
    """``(row index, cells)`` of each pending row as soon as all its runs are done (at once for a
    row whose runs all are `known`)."""
    waiting = Waiting(pending, known)
    for index in waiting.ready():
        yield index, _row_cells(plan, index, waiting)
    for task, figures in results:
        for index in waiting.finished((task.controller, task.key), figures):
            yield index, _row_cells(plan, index, waiting)


def _row_cells(plan: SweepPlan, index: int, waiting: Waiting) -> list[str]:
    """The cells of row `index`, whose runs are all done."""
    return [*plan.row_key(plan.rows[index]), *plan.layout.cells(waiting.take(index))]

"""Running (or resuming) a Pareto study into a directory, through the sweep's runner (a Dask
cluster, or this process) and files: ``pareto.json`` (which study), ``pareto.partial.csv`` (points as they finish) and
``pareto.csv`` (every point in plan order, written at the end)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from truckmpc.consumption import FUEL, Consumption
from truckmpc.pareto.plan import ParetoPlan, Point, consumption_of_pareto
from truckmpc.roads.profile import PathLike
from truckmpc.sweep.cells import cell, parse_cell
from truckmpc.sweep.errors import SweepInterrupted
from truckmpc.sweep.files import (
    PartialFile,
    check_out_dir,
    csv_line,
    file_names,
    finished_rows,
    write_final,
    write_settings,
)
from truckmpc.sweep.run import run_base
from truckmpc.sweep.runner import ProgressHook, Runner
from truckmpc.sweep.task import ERROR, Task
from truckmpc.workload import MAX_WORK_S, WorkError, too_long

STEM = "pareto"


def figures_of(consumption: Consumption) -> tuple[str, ...]:
    """The run's figures that go to ``pareto.csv``: what it consumed, raw and end speed corrected
    (fuel [kg] or battery energy [kWh]), its trip time, end speed and whether it stalled."""
    return (consumption.key, consumption.corrected_key, "time_s", "end_speed_kmh", "stalled")


@dataclass(frozen=True)
class ParetoResult:
    """A finished study: its CSV and its rows (column -> cell text, plan order)."""

    csv_path: Path
    rows: list[dict[str, str]]
    runs: int
    resumed: int


def run_pareto(
    plan: ParetoPlan,
    out: PathLike,
    *,
    jobs: int | None = None,
    progress: ProgressHook | None = None,
    force: bool = False,
    notice: Callable[[str], None] | None = None,
    scheduler: str | None = None,
) -> ParetoResult:
    """Run the points of `plan` not yet in `out` (or whose run failed), longest first, on `jobs`
    worker processes of an embedded Dask cluster (default: all cores; 1: this process) or on the
    running cluster at `scheduler`; append each to ``pareto.partial.csv`` as it finishes and write
    ``pareto.csv`` at the end. A run that fails leaves its error in its row. Rerunning the same
    study into `out` resumes it; a different one is refused."""
    out = Path(out)
    check_out_dir(out, plan.settings, STEM)
    done = _resumed(plan, out, notice)
    pending = sorted((p for p in plan.points if p.index not in done), key=lambda p: -p.work.total_s)
    tasks = [Task(p.controller, p.road, p.overrides, p.index, "", plain=True) for p in pending]
    base = run_base((plan.vehicle_path,), plan.config_paths)
    partial_path = out / file_names(STEM)[1]
    with Runner(plan.roads, base, jobs, scheduler, notice) as runner:
        _check_work(pending, runner.jobs, force)
        out.mkdir(parents=True, exist_ok=True)
        write_settings(out, plan.settings, runner.jobs, STEM)
        header = csv_line(plan.columns)
        partial = PartialFile(partial_path, header, [csv_line(cells) for _, cells in sorted(done.items())])
        try:
            for task, figures in runner.results(tasks, progress):
                cells = _cells(plan, plan.points[task.row], figures)
                done[task.row] = cells
                partial.append(csv_line(cells))
        except KeyboardInterrupt:
            raise SweepInterrupted(len(done), len(plan.points), partial_path) from None
        finally:
            partial.close()
    ordered = [done[p.index] for p in plan.points]
    rows = [dict(zip(plan.columns, cells, strict=True)) for cells in ordered]
    return ParetoResult(write_final(out, header, ordered, STEM), rows, len(tasks), len(plan.points) - len(tasks))


def _cells(plan: ParetoPlan, point: Point, figures: dict[str, Any]) -> list[str]:
    """A point's cells: its key, set speed and β, the run's figures (blank if it failed) and error."""
    own = [cell(point.v_ref_kmh), cell(point.beta_per_s)]
    named = (cell(figures.get(name)) for name in figures_of(plan.consumption))
    return [*plan.point_key(point), *own, *named, cell(figures.get(ERROR))]


def _resumed(plan: ParetoPlan, out: Path, notice: Callable[[str], None] | None) -> dict[int, list[str]]:
    """Point index -> cells of the points already in `out`; a damaged line is dropped, to run again."""
    by_key = {plan.point_key(p): p for p in plan.points}
    done: dict[int, list[str]] = {}
    dropped = []
    for where, cells in finished_rows(out, plan.columns, STEM):
        point = by_key.get(tuple(cells[:5]))
        problem = "not a point of this study" if point is None else damaged_row(cells, plan.columns)
        if point is None or problem is not None:
            dropped.append(f"{where}: {problem}")
        elif not cells[plan.columns.index(ERROR)].strip():  # a point whose run failed runs again
            done.setdefault(point.index, cells)
    if dropped and notice is not None:
        notice(f"dropped {len(dropped)} damaged row(s), to run again ({dropped[0]})")
    return done


def damaged_row(cells: list[str], columns: tuple[str, ...]) -> str | None:
    """What is wrong with a row read back from a ``pareto.csv`` of `columns` (a study's), or None:
    the study's number of cells, true or false in ``stalled``, numbers in the figures (all of them
    when the run finished); a failed run's row is its error and blank figures."""
    if len(cells) != len(columns):
        return f"expected {len(columns)} cells, got {len(cells)}"
    consumption = consumption_of_pareto(columns) or FUEL
    figures = figures_of(consumption)
    named = dict(zip(columns, cells, strict=True))
    if named[ERROR].strip():
        filled = [name for name in figures if named[name].strip()]
        return f"column {filled[0]!r}: expected blank in a failed run's row" if filled else None
    stalled = parse_cell(named["stalled"])
    if not isinstance(stalled, bool):
        return f"column 'stalled': expected true or false, got {named['stalled']!r}"
    for column in ("value", "v_ref_kmh", consumption.beta_key, *figures[:-1]):
        value = parse_cell(named[column])
        required = column != consumption.beta_key and not (stalled and column in figures)
        if (value is None and required) or isinstance(value, (bool, str)):
            return f"column {column!r}: expected a number, got {named[column]!r}"
    return None


def _check_work(pending: list[Point], jobs: int, force: bool) -> None:
    """Refuse, unless `force`, points whose estimated wall time on `jobs` processes is beyond the limit."""
    if force or not pending:
        return
    costs = [p.work.total_s for p in pending]
    wall_s = max(sum(costs) / max(1, min(jobs, len(costs))), max(costs))
    if wall_s > MAX_WORK_S:
        raise WorkError(f"pareto: {too_long(wall_s, f'for {len(costs)} runs on {jobs} processes')}")

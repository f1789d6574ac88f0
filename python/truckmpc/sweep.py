"""Parameter sweeps: PI and MPC over every combination of a grid of config values (thesis chapter 6).

A sweep is a list of roads (all driven forward, or all reversed) and a list of *axes*, each a config
key with the values it takes (``horizon_m=250:3000:250``, ``delta_kmh=0.1,0.2``). Every combination
is applied as ``key=value`` overrides on top of the base configuration (vehicle file, ``--config``
overlays, ``--set``) and validated before anything runs. For each (road, combination) the PI and the
MPC drive the same road with the same vehicle; one row per pair goes to ``DIR/sweep.csv``.

The PI run depends only on the road, the vehicle, the PI and the simulation settings, so it is keyed
by those *resolved values* and computed once per distinct key: an axis over an MPC key reuses one PI
run per road, an axis over ``v_ref_kmh`` or ``mass_kg`` reruns it per value.

Resuming: ``DIR/sweep.json`` identifies the sweep (roads by name, content hash and direction; axes;
the resolved base configuration). Rows are appended to ``DIR/sweep.partial.csv`` one complete line
at a time as they finish; when all are done ``DIR/sweep.csv`` is written atomically in grid order and
the partial file removed. Running the same sweep again into the same directory skips the rows already
there (and reuses their PI figures); a different sweep into it is refused.
"""

from __future__ import annotations

import contextlib
import csv
import dataclasses
import decimal
import hashlib
import io
import itertools
import json
import math
import multiprocessing
import os
import re
import signal
from collections.abc import Callable, Iterator, Mapping, Sequence
from concurrent.futures import ProcessPoolExecutor, as_completed
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import yaml

from truckmpc.atomic import atomic_write_text
from truckmpc.config import RunConfig, load_run_config
from truckmpc.errors import ConfigError, TruckmpcError
from truckmpc.road import RoadProfile, load_road
from truckmpc.sim import simulate

__all__ = [
    "SWEEP_COLUMNS",
    "Axis",
    "SweepError",
    "SweepInterrupted",
    "SweepPlan",
    "SweepResult",
    "SweepWorkerDied",
    "expand_grid",
    "parse_axis",
    "plan_sweep",
    "progress_bar",
    "run_plan",
    "run_sweep",
]

PathLike = str | os.PathLike[str]
CSV_NAME, PARTIAL_NAME, SETTINGS_NAME = "sweep.csv", "sweep.partial.csv", "sweep.json"
MAX_AXIS_VALUES = 10_000
"""More values than this on one axis is taken to be a typo in a range's step."""

# Result columns after road, direction and the axes: PI figures, MPC figures (the solver's without
# a prefix), then the comparison (blank when either run stalled: its fuel is not that of the road).
_PI_FIELDS = ("fuel_kg", "time_s", "end_speed_kmh", "brake_energy_kj", "gear_shifts", "stalled")
_MPC_FIELDS = (
    *_PI_FIELDS,
    "neutral_distance_m",
    "realtime_ratio",
    "solve_ms_mean",
    "solve_ms_max",
    "infeasible_solves",
    "transitions_per_solve",
)
_MPC_ONLY = frozenset(_MPC_FIELDS) - frozenset(_PI_FIELDS)
_RESULT_SOURCES: tuple[tuple[str, str, str], ...] = (
    *(("pi", name, f"pi_{name}") for name in _PI_FIELDS),
    *(("mpc", name, name if name in _MPC_ONLY else f"mpc_{name}") for name in _MPC_FIELDS),
)
SWEEP_COLUMNS: tuple[str, ...] = (*(column for _, _, column in _RESULT_SOURCES), "delta_fuel_pct", "delta_time_pct")
"""Columns of ``sweep.csv`` after ``road``, ``direction`` and one column per axis."""


class SweepError(TruckmpcError):
    """A bad ``--grid`` axis, or an output directory that holds a different sweep."""


class SweepWorkerDied(RuntimeError):
    """A worker process of a parallel sweep died (killed, out of memory); finished rows are kept."""


class SweepInterrupted(KeyboardInterrupt):
    """Ctrl-C during a sweep: ``done`` of ``total`` rows are kept in ``partial_path``."""

    def __init__(self, done: int, total: int, partial_path: Path) -> None:
        super().__init__(f"{done} of {total} rows kept in {partial_path}")
        self.done, self.total, self.partial_path = done, total, partial_path


# ---------------------------------------------------------------------------------------------
# Axes and the grid.


@dataclass(frozen=True)
class Axis:
    """One grid axis: a config key and its values, in order (``spec`` is the text it came from)."""

    key: str
    values: tuple[Any, ...]
    spec: str = ""


def parse_axis(text: str) -> Axis:
    """``KEY=SPEC``: SPEC is ``start:stop:step`` (an inclusive range, computed in decimal so
    ``0.1:0.3:0.1`` gives exactly 0.1, 0.2, 0.3; integers if all three are) or a comma list of
    YAML scalars (``0.1,0.2``, ``true,false``, ``nearest,interpolate``)."""
    key, sep, spec = text.partition("=")
    key, spec = key.strip(), spec.strip()
    where = f"--grid {key}" if key else f"--grid {text!r}"
    if not sep or not key or not spec:
        raise SweepError(f"--grid {text!r}: expected KEY=SPEC (SPEC start:stop:step or a comma list)")
    values = _range(where, spec) if ":" in spec else _list(where, spec)
    for a, b in itertools.combinations(values, 2):
        if type(a) is type(b) and a == b:
            raise SweepError(f"{where}: value {cell(a)} is given twice")
    return Axis(key, tuple(values), spec)


def _range(where: str, spec: str) -> list[Any]:
    parts = [part.strip() for part in spec.split(":")]
    try:
        if len(parts) != 3:
            raise decimal.InvalidOperation
        start, stop, step = (decimal.Decimal(part) for part in parts)
    except decimal.InvalidOperation:
        raise SweepError(f"{where}: expected start:stop:step numbers, got {spec!r}") from None
    if not all(x.is_finite() for x in (start, stop, step)) or step <= 0 or stop < start:
        raise SweepError(f"{where}: expected start <= stop and step > 0 in start:stop:step, got {spec!r}")
    count = int((stop - start) / step) + 1
    if count > MAX_AXIS_VALUES:
        raise SweepError(f"{where}: {spec!r} gives {count} values, expected at most {MAX_AXIS_VALUES}")
    whole = all("." not in part and "e" not in part.lower() for part in parts)
    return [int(start + i * step) if whole else float(start + i * step) for i in range(count)]


def _list(where: str, spec: str) -> list[Any]:
    values = []
    for item in spec.split(","):
        try:
            value = yaml.safe_load(item)
        except yaml.YAMLError:
            raise SweepError(f"{where}: value {item.strip()!r} is not a YAML scalar") from None
        if item.strip() == "" or isinstance(value, (list, dict)):
            raise SweepError(f"{where}: expected a comma list of scalar values, got {spec!r}")
        values.append(value)
    return values


def expand_grid(axes: Sequence[Axis]) -> list[tuple[Any, ...]]:
    """Every combination of the axes' values, the last axis varying fastest (one empty combination
    for no axes)."""
    return list(itertools.product(*(axis.values for axis in axes)))


def cell(value: Any) -> str:
    """A value as written in the CSV (and as a YAML ``--set`` value): true/false, repr of floats
    (exact round trip), blank for None."""
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value) if math.isfinite(value) else ""
    return str(value)


def _yaml_text(value: Any) -> str:
    return json.dumps(value) if isinstance(value, str) else ("null" if value is None else cell(value))


def _parse_cell(text: str) -> Any:
    if text == "":
        return None
    if text in ("true", "false"):
        return text == "true"
    try:
        return int(text)
    except ValueError:
        return float(text)


# ---------------------------------------------------------------------------------------------
# The plan: roads, rows and their configs, all validated before anything runs.


@dataclass(frozen=True)
class Row:
    """One (road, combination) of a sweep: its place in grid order, its overrides, its PI key and
    a rough relative cost of its MPC run (for scheduling only)."""

    index: int
    road: int
    values: tuple[Any, ...]
    overrides: tuple[str, ...]
    pi_key: str
    cost: float = 0.0


@dataclass(frozen=True)
class SweepPlan:
    roads: tuple[RoadProfile, ...]
    direction: str
    axes: tuple[Axis, ...]
    vehicle_path: str | None
    config_paths: tuple[str, ...]
    overrides: tuple[str, ...]
    rows: tuple[Row, ...]
    settings: dict[str, Any]

    @property
    def columns(self) -> tuple[str, ...]:
        return ("road", "direction", *(axis.key for axis in self.axes), *SWEEP_COLUMNS)

    def row_key(self, row: Row) -> tuple[str, ...]:
        return (self.roads[row.road].name, self.direction, *(cell(v) for v in row.values))


def _pi_key(road: int, config: RunConfig) -> str:
    """Everything the PI run depends on: road, vehicle, PI and simulation values (not the MPC's)."""
    parts = [road, *(dict(config.section(name)) for name in ("vehicle", "cruise", "pi", "sim"))]
    return json.dumps(parts, sort_keys=True)


def _mpc_cost(profile: RoadProfile, config: RunConfig) -> float:
    """Relative work of an MPC run: solves (length / S) times stages per solve (horizon / S) times
    grid points per stage (1 / delta)."""
    mpc = config.mpc
    return profile.length_m / mpc.stage_m * (mpc.horizon_m / mpc.stage_m) / mpc.delta_kmh


def _road_digest(profile: RoadProfile) -> str:
    digest = hashlib.sha256(profile.distance_m.tobytes())
    digest.update(profile.altitude_m.tobytes())
    return digest.hexdigest()


def plan_sweep(
    roads: Sequence[RoadProfile | PathLike],
    axes: Sequence[Axis | str] | Mapping[str, Sequence[Any]] = (),
    *,
    reverse: bool = False,
    vehicle_path: PathLike | None = None,
    config_paths: Sequence[PathLike] = (),
    overrides: Sequence[str] = (),
) -> SweepPlan:
    """Load the roads and validate the configuration of every combination; raise a one-line
    :class:`~truckmpc.errors.TruckmpcError` naming the road, the ``--set`` or the ``--grid`` axis."""
    if isinstance(axes, Mapping):
        axes = [Axis(key, tuple(values), ",".join(cell(v) for v in values)) for key, values in axes.items()]
    axes = tuple(parse_axis(a) if isinstance(a, str) else a for a in axes)
    keys = [axis.key for axis in axes]
    set_keys = {text.partition("=")[0].strip() for text in overrides}
    for axis in axes:
        if keys.count(axis.key) > 1:
            raise SweepError(f"--grid {axis.key}: axis given twice")
        if axis.key in set_keys:
            raise SweepError(f"--grid {axis.key}: also set with --set {axis.key}; give it once")
        if not axis.values:
            raise SweepError(f"--grid {axis.key}: expected at least one value")
    profiles = [load_road(road) if not isinstance(road, RoadProfile) else road for road in roads]
    if not profiles:
        raise SweepError("--road: expected at least one road")
    names = [p.name for p in profiles]
    for name in names:
        if names.count(name) > 1:
            raise SweepError(f"--road: two roads are named {name!r} (rows are keyed by road name)")
    if reverse:
        profiles = [p.reversed() for p in profiles]
        profiles = [dataclasses.replace(p, name=n) for p, n in zip(profiles, names, strict=True)]
    base = dict(
        vehicle_path=None if vehicle_path is None else str(vehicle_path),
        config_paths=tuple(str(p) for p in config_paths),
        overrides=tuple(overrides),
    )
    base_config = load_run_config(**base)  # errors in the base name their file or --set
    combos = []
    for values in expand_grid(axes):
        texts = tuple(f"{key}={_yaml_text(v)}" for key, v in zip(keys, values, strict=True))
        combos.append((values, texts, _combination_config(base, axes, values, texts)))
    rows = [
        Row(len(combos) * r + i, r, values, texts, _pi_key(r, config), _mpc_cost(profile, config))
        for r, profile in enumerate(profiles)
        for i, (values, texts, config) in enumerate(combos)
    ]
    direction = "reverse" if reverse else "forward"
    config_doc = base_config.as_dict()
    config_doc.pop("sources")
    settings = {
        "version": 1,
        "roads": [
            {"name": p.name, "direction": direction, "sha256": _road_digest(p), "path": p.source} for p in profiles
        ],
        "grid": [{"key": a.key, "spec": a.spec, "values": list(a.values)} for a in axes],
        "base_config": config_doc,
        "vehicle": base["vehicle_path"],
        "configs": list(base["config_paths"]),
        "overrides": list(base["overrides"]),
        "columns": ["road", "direction", *keys, *SWEEP_COLUMNS],
    }
    return SweepPlan(
        tuple(profiles),
        direction,
        axes,
        base["vehicle_path"],
        base["config_paths"],
        base["overrides"],
        tuple(rows),
        json.loads(json.dumps(settings)),
    )


def _combination_config(
    base: dict[str, Any], axes: Sequence[Axis], values: tuple[Any, ...], texts: tuple[str, ...]
) -> RunConfig:
    try:
        return load_run_config(base["vehicle_path"], base["config_paths"], (*base["overrides"], *texts))
    except ConfigError as err:
        message = str(err)
        named = [axis.key for axis in axes if re.search(rf"--set {re.escape(axis.key)}\b", message)]
        for key in named:
            message = re.sub(rf"--set {re.escape(key)}\b", f"--grid {key}", message)
        if not named:  # a check across keys that blamed a base setting: say which combination
            combo = " ".join(f"{axis.key}={cell(v)}" for axis, v in zip(axes, values, strict=True))
            message = f"--grid combination {combo}: {message}"
        raise SweepError(message) from None


# Settings that identify a sweep: a directory holding another sweep is not resumed into.
_IDENTITY = ("version", "roads", "grid", "base_config", "columns")


def _identity(settings: Mapping[str, Any]) -> dict[str, Any]:
    doc = {k: settings.get(k) for k in _IDENTITY}
    doc["roads"] = [{k: r.get(k) for k in ("name", "direction", "sha256")} for r in doc["roads"] or []]
    return doc


# ---------------------------------------------------------------------------------------------
# Running: one unit of work, and the pool that runs them.

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
    fields = _PI_FIELDS if controller == "pi" else _MPC_FIELDS
    return {name: summary.get(name) for name in fields}


class _Runner:
    """Runs tasks ``(id, controller, road, overrides)`` in this process (jobs=1) or in a pool of
    spawned processes, yielding ``(id, figures)`` as they finish. Leaving the block early (an error,
    Ctrl-C) stops the workers at once, mid-run."""

    def __init__(self, plan: SweepPlan, jobs: int) -> None:
        self.plan, self.jobs = plan, jobs
        self._pool: ProcessPoolExecutor | None = None

    def __enter__(self) -> _Runner:
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

    def results(self, tasks: Sequence[tuple[Any, str, int, tuple[str, ...]]]) -> Iterator[tuple[Any, dict[str, Any]]]:
        args = (self.plan.roads, (self.plan.vehicle_path, self.plan.config_paths))
        if self.jobs <= 1 or len(tasks) <= 1:
            _init_worker(*args, ignore_sigint=False)
            for task_id, *task in tasks:
                yield task_id, run_one(*task)
            return
        # Workers are spawned (not forked: this process may run threads) while submitting; they
        # inherit an ignored SIGINT through exec, so Ctrl-C reaches only this process.
        previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
        try:
            self._pool = ProcessPoolExecutor(
                min(self.jobs, len(tasks)), multiprocessing.get_context("spawn"), _init_worker, (*args, True)
            )
            futures = {self._pool.submit(run_one, *task): task_id for task_id, *task in tasks}
        finally:
            signal.signal(signal.SIGINT, previous)
        try:
            for future in as_completed(futures):
                yield futures[future], future.result()
        except BrokenProcessPool:
            raise SweepWorkerDied(
                "a sweep worker process died (killed? out of memory?); run the same command again to resume"
            ) from None


# ---------------------------------------------------------------------------------------------
# Rows, the partial file and resuming.


def _row_cells(plan: SweepPlan, row: Row, pi: Mapping[str, Any], mpc: Mapping[str, Any]) -> list[str]:
    runs = {"pi": pi, "mpc": mpc}
    values = {column: runs[run][name] for run, name, column in _RESULT_SOURCES}
    ok = not (pi["stalled"] or mpc["stalled"])
    for name, field in (("delta_fuel_pct", "fuel_kg"), ("delta_time_pct", "time_s")):
        values[name] = 100.0 * (mpc[field] - pi[field]) / pi[field] if ok and pi[field] else None
    return [*plan.row_key(row), *(cell(values[c]) for c in SWEEP_COLUMNS)]


def _csv_line(cells: Sequence[str]) -> str:
    buffer = io.StringIO()
    csv.writer(buffer, lineterminator="\n").writerow(cells)
    return buffer.getvalue()


def _read_rows(path: Path, columns: Sequence[str]) -> list[list[str]]:
    """Complete rows of a sweep CSV (a last line cut short by an interruption is ignored)."""
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        return []
    lines = text.splitlines(keepends=True)
    if not lines:
        return []
    if next(csv.reader([lines[0]])) != list(columns):
        raise SweepError(f"{path}: its columns are not this sweep's; remove it or use another --out")
    rows = []
    for line in lines[1:]:
        if not line.endswith("\n"):
            break
        cells = next(csv.reader([line]), [])
        if len(cells) == len(columns):
            rows.append(cells)
    return rows


def _check_out_dir(out: Path, plan: SweepPlan) -> None:
    """Refuse to mix sweeps: an existing ``sweep.json`` must describe this one."""
    path = out / SETTINGS_NAME
    try:
        old = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        if (out / PARTIAL_NAME).exists() or (out / CSV_NAME).exists():
            raise SweepError(
                f"{out}: holds sweep results without {SETTINGS_NAME}; use another --out or remove them"
            ) from None
        return
    except (json.JSONDecodeError, UnicodeDecodeError):
        raise SweepError(f"{path}: not a sweep settings file; use another --out or remove it") from None
    mine, theirs = _identity(plan.settings), _identity(old if isinstance(old, dict) else {})
    differ = [key for key in _IDENTITY if mine[key] != theirs[key]]
    if differ:
        raise SweepError(
            f"{out} holds a different sweep (not the same: {', '.join(differ)}); use another --out or remove it"
        )


class _PartialFile:
    """Rows appended one complete line per write(2) and flushed to the OS as they finish."""

    def __init__(self, path: Path, header: str, rows: Sequence[str]) -> None:
        atomic_write_text(path, header + "".join(rows))  # drop a cut-short line before appending
        self._fd = os.open(path, os.O_WRONLY | os.O_APPEND)

    def append(self, line: str) -> None:
        data = line.encode("utf-8")
        while data:
            data = data[os.write(self._fd, data) :]

    def close(self) -> None:
        os.close(self._fd)


@dataclass(frozen=True)
class SweepResult:
    """A finished sweep: its CSV, its rows (column -> cell text, grid order) and what ran."""

    csv_path: Path
    columns: tuple[str, ...]
    rows: list[dict[str, str]]
    pi_runs: int
    mpc_runs: int
    resumed_rows: int


ProgressHook = Callable[[int, int], None]
"""``hook(done_rows, total_rows)``, called at the start and after each row."""


def run_sweep(
    roads: Sequence[RoadProfile | PathLike],
    grid: Sequence[Axis | str] | Mapping[str, Sequence[Any]],
    out: PathLike,
    *,
    reverse: bool = False,
    vehicle_path: PathLike | None = None,
    config_paths: Sequence[PathLike] = (),
    overrides: Sequence[str] = (),
    jobs: int | None = None,
    progress: ProgressHook | None = None,
) -> SweepResult:
    """Run (or resume) a sweep into directory ``out``: PI and MPC on every road for every
    combination of ``grid`` (``["horizon_m=250:3000:250", "delta_kmh=0.1,0.2"]`` or
    ``{"horizon_m": [250, 500]}``); see the module doc and :func:`run_plan`.

    Every combination is validated before anything runs or ``out`` is created.
    """
    plan = plan_sweep(
        roads, grid, reverse=reverse, vehicle_path=vehicle_path, config_paths=config_paths, overrides=overrides
    )
    return run_plan(plan, out, jobs=jobs, progress=progress)


def run_plan(
    plan: SweepPlan,
    out: PathLike,
    *,
    jobs: int | None = None,
    progress: ProgressHook | None = None,
) -> SweepResult:
    """Run (or resume) a planned sweep into directory ``out``; see the module doc.

    ``jobs``: processes (default ``os.cpu_count()``); 1 runs in this process. ``realtime_ratio`` of
    each row is measured under whatever load the other jobs make.
    Raises :class:`SweepError` if ``out`` holds a different sweep; on ``KeyboardInterrupt`` the
    workers are stopped, the finished rows stay in ``sweep.partial.csv`` and
    :class:`SweepInterrupted` (a ``KeyboardInterrupt``) says how many.
    """
    out = Path(out)
    jobs = max(1, jobs or os.cpu_count() or 1)
    _check_out_dir(out, plan)
    columns = plan.columns
    by_key = {plan.row_key(row): row for row in plan.rows}
    done: dict[int, list[str]] = {}
    for cells in [*_read_rows(out / CSV_NAME, columns), *_read_rows(out / PARTIAL_NAME, columns)]:
        row = by_key.get(tuple(cells[: 2 + len(plan.axes)]))
        if row is not None:
            done.setdefault(row.index, cells)
    resumed = len(done)
    pending = [row for row in plan.rows if row.index not in done]
    pi_cache: dict[str, dict[str, Any]] = {}
    first_pi = len(plan.axes) + 2
    for index, cells in done.items():  # reuse the PI figures of finished rows
        pi_cache.setdefault(
            plan.rows[index].pi_key, {k: _parse_cell(c) for k, c in zip(_PI_FIELDS, cells[first_pi:], strict=False)}
        )
    out.mkdir(parents=True, exist_ok=True)
    atomic_write_text(out / SETTINGS_NAME, json.dumps({**plan.settings, "jobs": jobs}, indent=2) + "\n")
    pi_tasks = {row.pi_key: row for row in pending if row.pi_key not in pi_cache}
    tasks = [(("pi", key), "pi", row.road, row.overrides) for key, row in pi_tasks.items()]
    # The PI runs first (every row needs one), then the MPC runs longest first, so that a pool does
    # not end on one long run while the other workers idle.
    tasks += [(("mpc", row.index), "mpc", row.road, row.overrides) for row in sorted(pending, key=lambda r: -r.cost)]
    header = _csv_line(columns)
    partial = _PartialFile(out / PARTIAL_NAME, header, [_csv_line(cells) for _, cells in sorted(done.items())])
    waiting: dict[int, dict[str, Any]] = {}
    if progress:
        progress(len(done), len(plan.rows))
    try:
        with _Runner(plan, jobs) as runner:
            for (kind, ident), figures in runner.results(tasks):
                if kind == "pi":
                    pi_cache[ident] = figures
                    ready = [i for i in waiting if plan.rows[i].pi_key == ident]
                else:
                    waiting[ident] = figures
                    ready = [ident] if plan.rows[ident].pi_key in pi_cache else []
                for index in ready:
                    row = plan.rows[index]
                    done[index] = _row_cells(plan, row, pi_cache[row.pi_key], waiting.pop(index))
                    partial.append(_csv_line(done[index]))
                    if progress:
                        progress(len(done), len(plan.rows))
    except KeyboardInterrupt:
        raise SweepInterrupted(len(done), len(plan.rows), out / PARTIAL_NAME) from None
    finally:
        partial.close()
    ordered = [done[row.index] for row in plan.rows]
    atomic_write_text(out / CSV_NAME, header + "".join(_csv_line(cells) for cells in ordered))
    with contextlib.suppress(FileNotFoundError):
        os.unlink(out / PARTIAL_NAME)
    return SweepResult(
        out / CSV_NAME,
        columns,
        [dict(zip(columns, cells, strict=True)) for cells in ordered],
        pi_runs=len(pi_tasks),
        mpc_runs=len(pending),
        resumed_rows=resumed,
    )


@contextlib.contextmanager
def progress_bar(enabled: bool = True) -> Iterator[ProgressHook | None]:
    """A progress bar with an ETA on stderr (``rich.progress``, which typer installs), as a
    :data:`ProgressHook`; None (no bar) when not ``enabled``, stderr is not a terminal or rich is
    missing."""
    try:
        from rich.console import Console
        from rich.progress import (
            BarColumn,
            MofNCompleteColumn,
            Progress,
            TextColumn,
            TimeElapsedColumn,
            TimeRemainingColumn,
        )
    except ImportError:
        enabled = False
    if not enabled:
        yield None
        return
    console = Console(stderr=True)
    if not console.is_terminal:
        yield None
        return
    columns = (
        TextColumn("sweep"),
        BarColumn(),
        MofNCompleteColumn(),
        TextColumn("rows"),
        TimeElapsedColumn(),
        TextColumn("ETA"),
        TimeRemainingColumn(),
    )
    with Progress(*columns, console=console, transient=False) as bar:
        task = bar.add_task("sweep", total=None)
        started = False

        def hook(done: int, total: int) -> None:
            nonlocal started
            if not started:  # rows resumed from an earlier run must not count towards the speed
                bar.reset(task, total=total, completed=done)
                started = True
            bar.update(task, completed=done, total=total)

        yield hook

"""Pictures of runs and sweeps (``truckmpc plot``), in the look of the thesis's chapter 6.

- A **run directory** (``summary.json`` and ``trace-pi.csv`` and/or ``trace-mpc.csv``, as written by
  ``truckmpc simulate``) gives ``run.png``: stacked panels over distance [km] — altitude, speed of
  PI and MPC with v_ref and the allowed band v_ref − v_dec … v_ref + v_inc, gear (neutral, gear 0 in
  the trace, ticked "N" just below the lowest gear used and shaded), pedal and brake levels — as
  figures 6.3–6.14. Lines longer than :data:`MAX_POINTS` are reduced by :func:`decimate`.
- A **sweep directory** (``sweep.csv``, as written by ``truckmpc sweep``) gives ``sweep.png``: Δfuel
  and Δtime [%] against the prediction horizon, one line per (S, δ), one column per road and
  direction (figures 6.16–6.18; ``allow_neutral = false`` dashed), and ``realtime.png``: the real-time
  ratio q against the horizon on a log scale (figure 6.19).

matplotlib is an optional dependency (``pip install 'truckmpc[plot]'``). It is imported only when a
picture is drawn, and only through its object-oriented API (``matplotlib.figure.Figure``), so no GUI
backend is ever selected and the global pyplot state is left alone.
"""

from __future__ import annotations

import csv
import json
import math
import os
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from truckmpc.atomic import OutputDir
from truckmpc.config import SECTIONS, VEHICLE_KEYS
from truckmpc.errors import TruckmpcError
from truckmpc.units import M_PER_KM

__all__ = ["MAX_POINTS", "PlotError", "decimate", "plot_dir", "plot_run", "plot_sweep"]

MAX_POINTS = 20_000
"""Most points drawn per line of a run picture; longer traces are reduced to per-bucket min/max."""

MISSING_MATPLOTLIB = "plotting needs matplotlib: pip install 'truckmpc[plot]'"

CONTROLLER_STYLE = {"pi": ("PI", "tab:blue"), "mpc": ("MPC", "tab:red")}
"""Label and colour per controller, the same in every panel."""

RESULT_COLUMNS = frozenset(
    {
        "road",
        "direction",
        "pi_fuel_kg",
        "pi_time_s",
        "mpc_fuel_kg",
        "mpc_time_s",
        "delta_fuel_pct",
        "delta_time_pct",
        "realtime_ratio",
        "solve_ms_mean",
        "solve_ms_max",
        "infeasible_solves",
    }
)
CONFIG_KEYS = frozenset(VEHICLE_KEYS) | {key for section in SECTIONS.values() for key in section.parsers}
"""Column names of sweep.csv that can be grid axes: any vehicle, controller or simulation key."""

_DPI = 150


class PlotError(TruckmpcError):
    """A directory that cannot be plotted (nothing recognisable in it, unreadable files), or no matplotlib."""


def _figure_class() -> Any:
    try:
        from matplotlib.figure import Figure
    except ImportError as err:
        raise PlotError(MISSING_MATPLOTLIB) from err
    return Figure


# ---------------------------------------------------------------------------------------------
# Entry point: run or sweep directory.


def plot_dir(
    directory: str | os.PathLike[str], *, out: str | os.PathLike[str] | None = None, svg: bool = False
) -> list[Path]:
    """Plot a run or a sweep directory; return the files written.

    ``out`` is a directory (default: ``directory``) or, for one kind of input, a file name whose
    suffix (``.png`` or ``.svg``) sets the format; a sweep's second picture then goes to
    ``<stem>-realtime<suffix>``. ``svg`` also writes an SVG beside every PNG. ``directory`` may
    also name the ``summary.json`` or ``sweep.csv`` itself.
    """
    source = Path(directory)
    if source.is_file() and source.name in ("summary.json", "sweep.csv"):
        source = source.parent
    if not source.is_dir():
        raise PlotError(f"{source}: not a directory (expected a run directory or a sweep directory)")
    is_run = (source / "summary.json").is_file()
    is_sweep = (source / "sweep.csv").is_file()
    if not (is_run or is_sweep):
        raise PlotError(
            f"{source}: neither a run directory (summary.json, trace-*.csv) nor a sweep directory (sweep.csv)"
        )
    target = source if out is None else Path(out)
    as_file = target.suffix.lower() in (".png", ".svg")
    if as_file and is_run and is_sweep:
        raise PlotError(f"--out {target}: {source} holds both a run and a sweep; give a directory")
    written: list[Path] = []
    if is_run:
        written += plot_run(source, target if as_file else target / "run.png", svg=svg)
    if is_sweep:
        written += plot_sweep(source, target if as_file else target / "sweep.png", svg=svg)
    return written


def _save(figures: Sequence[tuple[Any, Path]], svg: bool) -> list[Path]:
    """Write every (figure, path) pair, plus an SVG beside each PNG if asked, all or nothing."""
    written: list[Path] = []
    by_dir: dict[Path, list[tuple[Any, Path]]] = {}
    for fig, path in figures:
        by_dir.setdefault(path.parent, []).append((fig, path))
    for out_dir, items in by_dir.items():
        with OutputDir(out_dir) as staging:
            for fig, path in items:
                paths = [path]
                if svg and path.suffix.lower() == ".png":
                    paths.append(path.with_suffix(".svg"))
                for p in paths:
                    fig.savefig(staging / p.name, dpi=_DPI)
                    written.append(p)
    return written


# ---------------------------------------------------------------------------------------------
# Run directory.


def _read_json(path: Path) -> dict[str, Any]:
    try:
        doc = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError) as err:
        raise PlotError(f"{path}: expected a JSON document ({err})") from err
    if not isinstance(doc, dict):
        raise PlotError(f"{path}: expected a JSON object")
    return doc


def _read_trace(path: Path) -> dict[str, np.ndarray]:
    """A ``trace-<controller>.csv`` as column -> float array."""
    try:
        with path.open(newline="", encoding="utf-8") as handle:
            rows = list(csv.reader(handle))
    except OSError as err:
        raise PlotError(f"{path}: {err.strerror or err}") from err
    if len(rows) < 2:
        raise PlotError(f"{path}: expected a header and at least one row")
    header = [h.strip() for h in rows[0]]
    for needed in ("distance_m", "speed_kmh"):
        if needed not in header:
            raise PlotError(f"{path}: no '{needed}' column")
    try:
        table = np.array([[float(x) for x in row] for row in rows[1:] if row], dtype=float)
    except ValueError as err:
        raise PlotError(f"{path}: expected numbers ({err})") from err
    if table.ndim != 2 or table.shape[1] != len(header):
        raise PlotError(f"{path}: expected {len(header)} values per row")
    return {name: table[:, i] for i, name in enumerate(header)}


def decimate(x: np.ndarray, *ys: np.ndarray, max_points: int = MAX_POINTS) -> tuple[np.ndarray, ...]:
    """At most ``max_points`` samples of (x, *ys): per bucket, the samples where any y is at its
    min or max, in order, so short brake pulses and speed dips survive the reduction."""
    n = len(x)
    if n <= max_points:
        return (x, *ys)
    buckets = max(1, max_points // (2 * max(1, len(ys))))
    edges = np.linspace(0, n, buckets + 1).astype(int)
    keep = [0, n - 1]
    for lo, hi in zip(edges[:-1], edges[1:], strict=True):
        if hi <= lo:
            continue
        for y in ys:
            part = y[lo:hi]
            keep += [lo + int(np.argmin(part)), lo + int(np.argmax(part))]
    index = np.unique(keep)
    return (x[index], *(y[index] for y in ys))


def _settings(summary: Mapping[str, Any]) -> dict[str, Any]:
    """The controller settings a run recorded (the MPC's, which hold v_ref and the band), if any."""
    for name in ("mpc", "pi"):
        block = summary.get(name)
        if isinstance(block, dict) and isinstance(block.get("settings"), dict):
            return block["settings"]
    return {}


def _fmt_pct(value: Any) -> str:
    if not isinstance(value, (int, float)) or not math.isfinite(value):
        return "–"
    return "0.00 %" if round(value, 2) == 0 else f"{value:+.2f} %".replace("-", "−")


def _title(summary: Mapping[str, Any], names: Sequence[str]) -> str:
    road = summary.get("road", "?")
    length = summary.get("length_m")
    head = f"{road}" + (f", {length / M_PER_KM:.1f} km" if isinstance(length, (int, float)) else "")
    reason = summary.get("not_comparable")
    if reason is None and any(isinstance(summary.get(n), dict) and summary[n].get("stalled") for n in names):
        reason = "not comparable: a run stalled"  # a summary written before not_comparable existed
    if "delta_fuel_pct" in summary and reason is not None:
        head += f" — MPC vs PI: {reason}"
    elif "delta_fuel_pct" in summary:
        head += (
            f" — MPC vs PI: Δfuel {_fmt_pct(summary['delta_fuel_pct'])}, Δtime {_fmt_pct(summary['delta_time_pct'])}"
        )
    else:
        head += " — " + " and ".join(CONTROLLER_STYLE.get(n, (n,))[0] for n in names) + " only"
    s = _settings(summary)
    if "mpc" in names and s:
        parts = []
        if "stage_m" in s:
            parts.append(f"S {s['stage_m']:g} m")
        if "delta_kmh" in s:
            parts.append(f"δ {s['delta_kmh']:g} km/h")
        if "horizon_m" in s:
            parts.append(f"horizon {s['horizon_m']:g} m")
        if "allow_neutral" in s:
            parts.append("neutral allowed" if s["allow_neutral"] else "no neutral")
        head += "\nMPC: " + ", ".join(parts)
    return head


def _run_traces(directory: Path) -> dict[str, dict[str, np.ndarray]]:
    traces: dict[str, dict[str, np.ndarray]] = {}
    known = [n for n in CONTROLLER_STYLE if (directory / f"trace-{n}.csv").is_file()]
    others = sorted(p.name[len("trace-") : -len(".csv")] for p in directory.glob("trace-*.csv"))
    for name in known + [n for n in others if n not in known]:
        traces[name] = _read_trace(directory / f"trace-{name}.csv")
    if not traces:
        raise PlotError(f"{directory}: summary.json but no trace-<controller>.csv to plot")
    return traces


def plot_run(directory: str | os.PathLike[str], out: str | os.PathLike[str], *, svg: bool = False) -> list[Path]:
    """Draw one run (altitude, speed with v_ref and band, gear, pedal, brake over distance) to ``out``."""
    directory = Path(directory)
    summary = _read_json(directory / "summary.json")
    traces = _run_traces(directory)
    figure = _run_figure(_figure_class(), summary, traces)
    return _save([(figure, Path(out))], svg)


def _run_figure(Figure: Any, summary: Mapping[str, Any], traces: Mapping[str, Mapping[str, np.ndarray]]) -> Any:
    fig = Figure(figsize=(11, 10), layout="constrained")
    axes = fig.subplots(5, 1, sharex=True, height_ratios=[1.0, 2.2, 1.3, 1.1, 1.1])
    ax_alt, ax_v, ax_gear, ax_pedal, ax_brake = axes
    longest = max(traces.values(), key=lambda t: t["distance_m"][-1])
    n_max = max(len(t["distance_m"]) for t in traces.values())
    lw = 1.0 if n_max <= 5000 else 0.6
    lines: list[Any] = []
    references: list[Any] = []

    if "altitude_m" in longest:
        x, alt = decimate(longest["distance_m"] / M_PER_KM, longest["altitude_m"])
        ax_alt.fill_between(x, alt, alt.min(), color="0.85", lw=0)
        ax_alt.plot(x, alt, color="0.3", lw=lw)
        pad = max(1.0, 0.05 * (alt.max() - alt.min()))
        ax_alt.set_ylim(alt.min() - pad, alt.max() + pad)
    ax_alt.set_ylabel("altitude [m]")

    s = _settings(summary)
    if "v_ref_kmh" in s:
        v_ref = float(s["v_ref_kmh"])
        lo, hi = v_ref - float(s.get("v_dec_kmh", 0.0)), v_ref + float(s.get("v_inc_kmh", 0.0))
        references.append(ax_v.axhline(v_ref, color="k", ls="--", lw=1.0, label=f"v_ref {v_ref:g} km/h"))
        references.append(ax_v.axhspan(lo, hi, color="0.6", alpha=0.2, lw=0, label=f"allowed band {lo:g}–{hi:g} km/h"))

    gears = [t["gear"] for t in traces.values() if "gear" in t]
    neutral_spans = any(np.any(g == 0) for g in gears)
    neutral_y = _neutral_y(gears)
    for name, t in traces.items():
        label, color = CONTROLLER_STYLE.get(name, (name, None))
        block = summary.get(name) if isinstance(summary.get(name), dict) else {}
        if block.get("stalled"):
            label += f" (stalled at km {t['distance_m'][-1] / M_PER_KM:.2f})"
        km = t["distance_m"] / M_PER_KM
        lines += ax_v.plot(*decimate(km, t["speed_kmh"]), color=color, lw=lw, label=label)
        if block.get("stalled"):
            ax_v.plot(km[-1], t["speed_kmh"][-1], "x", color=color, ms=8, mew=2)
        if "gear" in t:
            gear = np.where(t["gear"] == 0, neutral_y, t["gear"])
            ax_gear.plot(*decimate(km, gear), color=color, lw=lw, drawstyle="steps-post")
            if np.any(t["gear"] == 0):
                ax_gear.fill_between(
                    km,
                    0,
                    1,
                    where=t["gear"] == 0,
                    step="post",
                    color=color,
                    alpha=0.18,
                    lw=0,
                    transform=ax_gear.get_xaxis_transform(),
                )
        if "pedal" in t:
            ax_pedal.plot(*decimate(km, t["pedal"]), color=color, lw=lw)
        if "brake" in t:
            ax_brake.plot(*decimate(km, t["brake"]), color=color, lw=lw)

    ax_v.set_ylabel("speed [km/h]")
    _gear_axis(ax_gear, gears, neutral_y if neutral_spans else None)
    ax_pedal.set_ylabel("pedal [-]")
    ax_pedal.set_ylim(-0.03, 1.03)
    ax_brake.set_ylabel("brake [-]")
    ax_brake.set_ylim(bottom=-0.02 * max(ax_brake.get_ylim()[1], 0.05))
    ax_brake.set_xlabel("distance [km]")
    length_m = summary.get("length_m")
    end_m = length_m if isinstance(length_m, (int, float)) and length_m > 0 else longest["distance_m"][-1]
    ax_brake.set_xlim(0, max(end_m, longest["distance_m"][-1]) / M_PER_KM)  # a stalled run still shows the whole road
    for ax in axes:
        ax.grid(True, color="0.9", lw=0.6)
        ax.label_outer()
    handles = lines + references
    if neutral_spans:
        from matplotlib.patches import Patch

        handles.append(Patch(color="0.5", alpha=0.3, label="neutral gear (N), shaded"))
    fig.legend(handles=handles, loc="outside lower center", ncol=len(handles), fontsize="small", frameon=False)
    fig.suptitle(_title(summary, list(traces)), fontsize="medium")
    return fig


def _forward_gears(gears: Iterable[np.ndarray]) -> list[int]:
    return sorted({int(g) for arr in gears for g in np.unique(arr)} - {0})


def _neutral_y(gears: Sequence[np.ndarray]) -> float:
    """Where neutral (gear 0) is drawn: 1.5 below the lowest forward gear used, so a truck that only
    uses gears 10-12 and neutral keeps its shifts readable. The axis tick says "N"."""
    forward = _forward_gears(gears)
    return (forward[0] if forward else 1) - 1.5


def _gear_axis(ax: Any, gears: Sequence[np.ndarray], neutral_y: float | None) -> None:
    """Integer ticks for the gears used; neutral (``neutral_y`` given) ticked "N" below a dotted break."""
    forward = _forward_gears(gears) or [1]
    span = list(range(forward[0], forward[-1] + 1))
    step = max(1, math.ceil(len(span) / 6))
    ticks: list[float] = list(span[::-1][::step][::-1])
    labels = [str(g) for g in ticks]
    if neutral_y is not None:
        ticks.insert(0, neutral_y)
        labels.insert(0, "N")
        ax.axhline(neutral_y + 0.75, color="0.5", ls=":", lw=0.8)  # the axis is not linear below here
    ax.set_yticks(ticks, labels)
    ax.set_ylim((neutral_y if neutral_y is not None else forward[0]) - 0.6, forward[-1] + 0.6)
    ax.set_ylabel("gear")


# ---------------------------------------------------------------------------------------------
# Sweep directory.


def _parse_cell(text: str) -> Any:
    value = text.strip()
    lower = value.lower()
    if lower in ("true", "false"):
        return lower == "true"
    try:
        return float(value)
    except ValueError:
        return value


def _read_sweep(directory: Path) -> tuple[list[str], list[dict[str, Any]]]:
    path = directory / "sweep.csv"
    try:
        with path.open(newline="", encoding="utf-8") as handle:
            reader = csv.DictReader(handle)
            header = list(reader.fieldnames or [])
            rows = [{k: _parse_cell(v or "") for k, v in row.items() if k is not None} for row in reader]
    except OSError as err:
        raise PlotError(f"{path}: {err.strerror or err}") from err
    for needed in ("delta_fuel_pct", "delta_time_pct"):
        if needed not in header:
            raise PlotError(f"{path}: no '{needed}' column")
    if not rows:
        raise PlotError(f"{path}: no rows to plot")
    return header, rows


def _grid_axes(directory: Path, header: Sequence[str]) -> list[str]:
    """The grid-axis columns: config keys, and whatever ``sweep.json`` names as its grid."""
    named: set[str] = set()
    meta = directory / "sweep.json"
    if meta.is_file():
        try:
            doc = json.loads(meta.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            doc = {}
        grid = doc.get("grid") if isinstance(doc, dict) else None
        if isinstance(grid, dict):
            named = set(grid)
        elif isinstance(grid, list):
            named = {
                g if isinstance(g, str) else g.get("key", g.get("name")) for g in grid if isinstance(g, (str, dict))
            }
    return [c for c in header if c not in RESULT_COLUMNS and (c in CONFIG_KEYS or c in named)]


def _varying(rows: Sequence[Mapping[str, Any]], column: str) -> list[Any]:
    values: list[Any] = []
    for row in rows:
        v = row.get(column)
        if v not in values and v != "":
            values.append(v)
    return values


_AXIS_LABELS = {
    "horizon_m": "prediction horizon [m]",
    "stage_m": "S",
    "delta_kmh": "δ",
}
_UNITS = (("_kmh", "km/h"), ("_rpm", "rpm"), ("_kg", "kg"), ("_pct", "%"), ("_m", "m"), ("_s", "s"))


def _unit(column: str) -> str:
    for suffix, unit in _UNITS:
        if column.endswith(suffix):
            return unit
    return ""


def _axis_label(column: str) -> str:
    if column == "horizon_m":
        return _AXIS_LABELS[column]
    unit = _unit(column)
    return f"{column} [{unit}]" if unit else column


def _line_label(column: str, value: Any) -> str:
    if isinstance(value, float) and value.is_integer():
        shown = f"{value:.0f}"
    else:
        shown = f"{value:g}" if isinstance(value, float) else str(value)
    name = _AXIS_LABELS.get(column)
    if name is not None:
        return f"{name} {shown} {_unit(column)}"
    if column == "allow_neutral":
        return "neutral allowed" if value else "no neutral"
    unit = _unit(column)
    return f"{column} {shown}" + (f" {unit}" if unit else "")


def _x_axis(rows: Sequence[Mapping[str, Any]], axes: Sequence[str], path: Path) -> str:
    numeric = [a for a in axes if all(isinstance(v, float) for v in _varying(rows, a)) and len(_varying(rows, a)) > 1]
    if "horizon_m" in numeric:
        return "horizon_m"
    if numeric:
        return max(numeric, key=lambda a: len(_varying(rows, a)))
    raise PlotError(f"{path}: no numeric grid axis varies (expected e.g. a horizon_m column); nothing to plot against")


def plot_sweep(directory: str | os.PathLike[str], out: str | os.PathLike[str], *, svg: bool = False) -> list[Path]:
    """Draw a sweep: Δfuel and Δtime against the horizon to ``out``, q against the horizon beside it."""
    directory = Path(directory)
    out = Path(out)
    header, rows = _read_sweep(directory)
    axes = _grid_axes(directory, header)
    x_axis = _x_axis(rows, axes, directory / "sweep.csv")
    line_axes = [a for a in axes if a != x_axis and a != "allow_neutral" and len(_varying(rows, a)) > 1]
    neutral_axis = "allow_neutral" in axes and len(_varying(rows, "allow_neutral")) > 1
    panels = (
        [(r, d) for r in _varying(rows, "road") for d in _varying(rows, "direction")]
        if "direction" in header
        else [(r, None) for r in _varying(rows, "road")]
        if "road" in header
        else [(None, None)]
    )
    panels = [p for p in panels if any(_in_panel(row, p) for row in rows)]
    fixed = [_line_label(a, _varying(rows, a)[0]) for a in axes if len(_varying(rows, a)) == 1]
    note = f" ({', '.join(fixed)})" if fixed else ""
    Figure = _figure_class()
    figures = [
        (
            _sweep_figure(
                Figure,
                rows,
                panels,
                x_axis,
                line_axes,
                neutral_axis,
                [("delta_fuel_pct", "Δfuel [%]"), ("delta_time_pct", "Δtime [%]")],
                log=False,
                title=f"MPC against PI: (MPC − PI) / PI{note}",
            ),
            out,
        )
    ]
    if "realtime_ratio" in header:
        figures.append(
            (
                _sweep_figure(
                    Figure,
                    rows,
                    panels,
                    x_axis,
                    line_axes,
                    neutral_axis,
                    [("realtime_ratio", "real-time ratio q [-]\n(compute time / driven time)")],
                    log=True,
                    title=f"MPC closed-loop real-time ratio{note}",
                ),
                out.with_name(f"{out.stem}-realtime{out.suffix}" if out.name != "sweep.png" else "realtime.png"),
            )
        )
    return _save(figures, svg)


def _in_panel(row: Mapping[str, Any], panel: tuple[Any, Any]) -> bool:
    road, direction = panel
    return (road is None or row.get("road") == road) and (direction is None or row.get("direction") == direction)


def _panel_title(panel: tuple[Any, Any]) -> str:
    road, direction = panel
    text = "" if road is None else str(road)
    if direction not in (None, ""):
        text += f" ({direction})"
    return text


def _sweep_figure(
    Figure: Any,
    rows: Sequence[Mapping[str, Any]],
    panels: Sequence[tuple[Any, Any]],
    x_axis: str,
    line_axes: Sequence[str],
    neutral_axis: bool,
    metrics: Sequence[tuple[str, str]],
    *,
    log: bool,
    title: str,
) -> Any:
    from matplotlib.lines import Line2D

    ncols = len(panels)
    fig = Figure(figsize=(max(6.5, 4.6 * ncols), 1.0 + 3.0 * len(metrics)), layout="constrained")
    grid = fig.subplots(len(metrics), ncols, sharex="col", sharey="row", squeeze=False)
    combos = _combos(rows, line_axes)
    colors = [f"C{i % 10}" for i in range(len(combos))]
    neutral_values = _varying(rows, "allow_neutral") if neutral_axis else [None]
    handles: dict[str, Any] = {}
    for col, panel in enumerate(panels):
        in_panel = [r for r in rows if _in_panel(r, panel)]
        for row_i, (metric, ylabel) in enumerate(metrics):
            ax = grid[row_i][col]
            for combo, color in zip(combos, colors, strict=True):
                for neutral in neutral_values:
                    points = sorted(
                        (r[x_axis], r[metric])
                        for r in in_panel
                        if all(r.get(a) == v for a, v in combo)
                        and (neutral is None or r.get("allow_neutral") == neutral)
                        and isinstance(r.get(x_axis), float)
                        and isinstance(r.get(metric), float)
                        and math.isfinite(r[metric])
                        and (r[metric] > 0 or not log)
                    )
                    if not points:
                        continue
                    xs, ys = zip(*points, strict=True)
                    label = ", ".join(_line_label(a, v) for a, v in combo) or "MPC"
                    (line,) = ax.plot(
                        xs, ys, color=color, ls="-" if neutral in (None, True) else "--", marker="o", ms=3, lw=1.2
                    )
                    handles.setdefault(label, Line2D([], [], color=color, marker="o", ms=3, lw=1.2, label=label))
            if log:
                ax.set_yscale("log")
            else:
                ax.axhline(0.0, color="0.4", lw=0.8)
            ax.grid(True, which="major", color="0.88", lw=0.6)
            if col == 0:
                ax.set_ylabel(ylabel)
            if row_i == 0:
                ax.set_title(_panel_title(panel), fontsize="medium")
            if row_i == len(metrics) - 1:
                ax.set_xlabel(_axis_label(x_axis))
    if log:
        for ax in grid[0]:
            lo, hi = ax.get_ylim()
            if lo <= 1.0 <= hi:
                ax.axhline(1.0, color="k", ls=":", lw=1.0)
                ax.annotate(
                    "real time (q = 1)", (0.01, 1.0), xycoords=("axes fraction", "data"), va="bottom", fontsize="small"
                )
    fig.suptitle(title, fontsize="medium")
    entries = list(handles.values())
    if neutral_axis:  # colour says (S, δ), the line style says whether neutral was allowed
        entries += [
            Line2D([], [], color="0.2", lw=1.2, label="neutral allowed"),
            Line2D([], [], color="0.2", lw=1.2, ls="--", label="no neutral"),
        ]
    if entries:
        fits = max(1, int(fig.get_figwidth() / 2.1))
        fig.legend(
            handles=entries, loc="outside lower center", fontsize="small", frameon=False, ncol=min(len(entries), fits)
        )
    return fig


def _combos(rows: Sequence[Mapping[str, Any]], line_axes: Sequence[str]) -> list[tuple[tuple[str, Any], ...]]:
    """Every combination of the line axes' values present in the rows, in first-seen order, sorted."""
    seen: list[tuple[tuple[str, Any], ...]] = []
    for row in rows:
        combo = tuple((a, row.get(a)) for a in line_axes)
        if combo not in seen:
            seen.append(combo)
    try:
        seen.sort(key=lambda c: tuple(v for _, v in c))
    except TypeError:
        pass
    return seen

"""The picture of one run (``run.png``): stacked panels over distance [km] — altitude, speed of
every controller with the set speed, the allowed band and the stops
(:mod:`~truckmpc.plot.run_speed`), gear (neutral, gear 0 in the trace, ticked "N" just below the
lowest gear used and shaded), pedal and brake levels — as figures 6.3–6.14 of the thesis.
Lines longer than :data:`MAX_POINTS` are reduced by :func:`decimate`.
"""

from __future__ import annotations

import csv
import itertools
import json
import math
import os
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from truckmpc.plot.figures import PlotError, figure_class, save
from truckmpc.plot.run_speed import speed_references
from truckmpc.plot.run_title import CONTROLLER_STYLE, run_title
from truckmpc.units import M_PER_KM

MAX_POINTS = 20_000
"""Most points drawn per line of a run picture; longer traces are reduced to per-bucket min/max."""

_LEGEND_COLUMNS = 4
"""Columns of the legend when its labels would not fit on one line."""


def _read_json(path: Path) -> dict[str, Any]:
    try:
        doc = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError) as err:
        raise PlotError(f"{path}: expected a JSON document ({err})") from err
    if not isinstance(doc, dict):
        raise PlotError(f"{path}: expected a JSON object")
    return doc


def read_trace(path: Path) -> dict[str, np.ndarray]:
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
    for lo, hi in itertools.pairwise(edges):
        if hi <= lo:
            continue
        for y in ys:
            part = y[lo:hi]
            keep += [lo + int(np.argmin(part)), lo + int(np.argmax(part))]
    index = np.unique(keep)
    return (x[index], *(y[index] for y in ys))


def _block(summary: Mapping[str, Any], name: str) -> Mapping[str, Any]:
    """The summary of controller ``name`` (empty if the file has none)."""
    block = summary.get(name)
    return block if isinstance(block, dict) else {}


def _run_traces(directory: Path) -> dict[str, dict[str, np.ndarray]]:
    traces: dict[str, dict[str, np.ndarray]] = {}
    known = [n for n in CONTROLLER_STYLE if (directory / f"trace-{n}.csv").is_file()]
    others = sorted(p.name[len("trace-") : -len(".csv")] for p in directory.glob("trace-*.csv"))
    for name in known + [n for n in others if n not in known]:
        traces[name] = read_trace(directory / f"trace-{name}.csv")
    if not traces:
        raise PlotError(f"{directory}: summary.json but no trace-<controller>.csv to plot")
    return traces


def plot_run(directory: str | os.PathLike[str], out: str | os.PathLike[str], *, svg: bool = False) -> list[Path]:
    """Draw one run (altitude, speed with v_ref and band, gear, pedal, brake over distance) to ``out``."""
    return save([(run_figure(directory), Path(out))], svg)


def run_figure(directory: str | os.PathLike[str]) -> Any:
    """The matplotlib Figure of the run in ``directory`` (``summary.json`` and its traces)."""
    directory = Path(directory)
    summary = _read_json(directory / "summary.json")
    return _run_figure(figure_class(), summary, _run_traces(directory))


def _run_figure(Figure: Any, summary: Mapping[str, Any], traces: Mapping[str, Mapping[str, np.ndarray]]) -> Any:
    """The five stacked panels of a run, its legend and its title."""
    fig = Figure(figsize=(11, 10), layout="constrained")
    axes = fig.subplots(5, 1, sharex=True, height_ratios=[1.0, 2.2, 1.3, 1.1, 1.1])
    ax_alt, ax_v, ax_gear, ax_pedal, ax_brake = axes
    longest = max(traces.values(), key=lambda t: t["distance_m"][-1])
    n_max = max(len(t["distance_m"]) for t in traces.values())
    lw = 1.0 if n_max <= 5000 else 0.6
    lines: list[Any] = []
    _altitude_panel(ax_alt, longest, lw)
    end_m = _end_m(summary, longest)
    references = speed_references(ax_v, summary, end_m)
    gears = [t["gear"] for t in traces.values() if "gear" in t]
    neutral_spans = any(np.any(g == 0) for g in gears)
    neutral_y = _neutral_y(gears)
    for name, t in traces.items():
        label, color = CONTROLLER_STYLE.get(name, (name, None))
        block = _block(summary, name)
        if block.get("stalled"):
            label += f" (stalled at km {t['distance_m'][-1] / M_PER_KM:.2f})"
        km = t["distance_m"] / M_PER_KM
        lines += ax_v.plot(*decimate(km, t["speed_kmh"]), color=color, lw=lw, label=label)
        if block.get("stalled"):
            ax_v.plot(km[-1], t["speed_kmh"][-1], "x", color=color, ms=8, mew=2)
        if "gear" in t:
            _gear_line(ax_gear, km, t["gear"], neutral_y, color, lw)
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
    ax_brake.set_xlim(0, end_m / M_PER_KM)  # a stalled run still shows the whole road
    for ax in axes:
        ax.grid(True, color="0.9", lw=0.6)
        ax.label_outer()
    handles = lines + references
    if neutral_spans:
        # matplotlib is optional, loaded only to draw (see truckmpc.plot)
        from matplotlib.patches import Patch

        handles.append(Patch(color="0.5", alpha=0.3, label="neutral gear (N), shaded"))
    ncol = min(len(handles), _LEGEND_COLUMNS) if sum(len(h.get_label()) for h in handles) > 150 else len(handles)
    fig.legend(handles=handles, loc="outside lower center", ncol=ncol, fontsize="small", frameon=False)
    fig.suptitle(run_title(summary, list(traces)), fontsize="medium")
    return fig


def _end_m(summary: Mapping[str, Any], longest: Mapping[str, np.ndarray]) -> float:
    """Where the distance axis ends [m]: the road's end, or the longest trace's if further."""
    length_m = summary.get("length_m")
    end_m = length_m if isinstance(length_m, (int, float)) and length_m > 0 else longest["distance_m"][-1]
    return float(max(end_m, longest["distance_m"][-1]))


def _altitude_panel(ax: Any, trace: Mapping[str, np.ndarray], lw: float) -> None:
    """The road's altitude [m] over distance [km], shaded below."""
    if "altitude_m" in trace:
        x, alt = decimate(trace["distance_m"] / M_PER_KM, trace["altitude_m"])
        ax.fill_between(x, alt, alt.min(), color="0.85", lw=0)
        ax.plot(x, alt, color="0.3", lw=lw)
        pad = max(1.0, 0.05 * (alt.max() - alt.min()))
        ax.set_ylim(alt.min() - pad, alt.max() + pad)
    ax.set_ylabel("altitude [m]")


def _gear_line(ax: Any, km: np.ndarray, gear: np.ndarray, neutral_y: float, color: Any, lw: float) -> None:
    """One controller's gear over distance [km], neutral drawn at ``neutral_y`` and shaded."""
    shown = np.where(gear == 0, neutral_y, gear)
    ax.plot(*decimate(km, shown), color=color, lw=lw, drawstyle="steps-post")
    if np.any(gear == 0):
        ax.fill_between(
            km, 0, 1, where=gear == 0, step="post", color=color, alpha=0.18, lw=0, transform=ax.get_xaxis_transform()
        )


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

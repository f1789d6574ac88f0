"""The pictures of a sweep: ``sweep.png``, Δfuel (raw, and at equal trip time: against the PI
re-tuned to the run's trip time) and Δtime [%] of each look-ahead controller the sweep ran (MPC,
PCC) against the PI, against the prediction horizon, one line per (S, δ), one column
per road and direction (figures 6.16–6.18 of the thesis; ``allow_neutral = false`` dashed),
``realtime.png``, the MPC's real-time ratio q against the horizon on a log scale (figure 6.19), and
``headline.png``, the headline per road and truck (:mod:`truckmpc.plot.headline`). Without a horizon
axis the numeric axis that varies most is used; without one that varies (a fleet study) only the
headline is drawn.
"""

from __future__ import annotations

import contextlib
import math
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from truckmpc.consumption import ENERGY, FUEL
from truckmpc.plot.figures import PlotError, figure_class, save
from truckmpc.plot.headline import headline_comparisons, headline_figure
from truckmpc.plot.sweep_csv import COMPARED, compared_controllers, delta_metrics, grid_axes, read_sweep
from truckmpc.sweep.columns import RUNS, consumption_of_columns, delta_column

Row = Mapping[str, Any]
Panel = tuple[Any, Any]
"""(road, direction) of one column of panels; None where the CSV has no such column."""

REALTIME_COLUMN = RUNS["mpc"].column("realtime_ratio")
"""The column of the MPC's real-time ratio q [-] (compute time / driven time)."""

_REALTIME = ((REALTIME_COLUMN, "real-time ratio q [-]\n(compute time / driven time)"),)
_AXIS_LABELS = {"horizon_m": "prediction horizon [m]", "stage_m": "S", "delta_kmh": "δ"}
_UNITS = (("_kmh", "km/h"), ("_rpm", "rpm"), ("_kg", "kg"), ("_pct", "%"), ("_m", "m"), ("_s", "s"))


@dataclass(frozen=True)
class _Layout:
    """How a sweep is drawn: its rows, one column of panels per (road, direction), the x axis, the
    axes that make one line each, and whether ``allow_neutral`` varies (dashed lines)."""

    rows: Sequence[Row]
    panels: Sequence[Panel]
    x_axis: str
    line_axes: Sequence[str]
    neutral_axis: bool


def plot_sweep(directory: str | os.PathLike[str], out: str | os.PathLike[str], *, svg: bool = False) -> list[Path]:
    """Draw a sweep: Δfuel (raw and at equal trip time) and Δtime against the horizon to ``out``,
    q against the horizon and the headline per road and truck beside it."""
    return save(sweep_figures(directory, out), svg)


def sweep_figures(directory: str | os.PathLike[str], out: str | os.PathLike[str]) -> list[tuple[Any, Path]]:
    """The matplotlib Figures of the sweep in ``directory``, each with the file it goes to: the Δ
    picture at ``out``, the real-time picture beside it when the sweep has a q column, and the
    headline beside them when it has the headline columns (alone when no numeric axis varies)."""
    directory = Path(directory)
    out = Path(out)
    header, rows = read_sweep(directory)
    axes = grid_axes(directory, header)
    headline = []
    if headline_comparisons(header):
        path = out.with_name("headline.png" if out.name == "sweep.png" else f"{out.stem}-headline{out.suffix}")
        headline.append((headline_figure(figure_class(), header, rows, axes), path))
    try:
        x_axis = _x_axis(rows, axes, directory / "sweep.csv")
    except PlotError:
        if headline:
            return headline
        raise
    return [*_delta_figures(out, header, rows, axes, x_axis), *headline]


def _delta_figures(
    out: Path, header: Sequence[str], rows: Sequence[Row], axes: Sequence[str], x_axis: str
) -> list[tuple[Any, Path]]:
    """The Δ picture at `out` and the real-time picture beside it when the sweep has a q column."""
    compared = compared_controllers(header)
    subject = " and ".join(label for _, label in compared)
    layout = _Layout(
        rows,
        _panels(rows, header),
        x_axis,
        [a for a in axes if a != x_axis and a != "allow_neutral" and len(_varying(rows, a)) > 1],
        "allow_neutral" in axes and len(_varying(rows, "allow_neutral")) > 1,
    )
    fixed = [_line_label(a, _varying(rows, a)[0]) for a in axes if len(_varying(rows, a)) == 1]
    note = f" ({', '.join(fixed)})" if fixed else ""
    look_ahead = compared[0][1] if len(compared) == 1 else "look-ahead"
    title = f"{subject} against PI: ({look_ahead} − PI) / PI{note}"
    metrics = delta_metrics(compared, header)
    consumption = consumption_of_columns(header)
    equal_time = {delta_column(name, "fuel_equal_time", consumption=consumption) for name, _ in compared}
    if any(column in equal_time for column, _ in metrics):
        title += f"\nat equal trip time: against the PI re-tuned to the {look_ahead} run's trip time"
    pictures: list[tuple[Sequence[tuple[str, str]], bool, str, Path]] = [(metrics, False, title, out)]
    if REALTIME_COLUMN in header:
        realtime = out.with_name(f"{out.stem}-realtime{out.suffix}" if out.name != "sweep.png" else "realtime.png")
        pictures.append((_REALTIME, True, f"MPC closed-loop real-time ratio{note}", realtime))
    Figure = figure_class()
    return [(_sweep_figure(Figure, layout, m, log=log, title=t), path) for m, log, t, path in pictures]


def _is_number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _varying(rows: Sequence[Row], column: str) -> list[Any]:
    """The distinct non-blank values of ``column``, in first-seen order."""
    values: list[Any] = []
    for row in rows:
        v = row.get(column)
        if v not in values and v is not None:
            values.append(v)
    return values


def _panels(rows: Sequence[Row], header: Sequence[str]) -> list[Panel]:
    """One panel per (road, direction) that has rows."""
    if "direction" in header:
        panels = [(r, d) for r in _varying(rows, "road") for d in _varying(rows, "direction")]
    elif "road" in header:
        panels = [(r, None) for r in _varying(rows, "road")]
    else:
        panels = [(None, None)]
    return [p for p in panels if any(_in_panel(row, p) for row in rows)]


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


def _x_axis(rows: Sequence[Row], axes: Sequence[str], path: Path) -> str:
    """``horizon_m`` if it varies, else the numeric axis with the most values."""
    numeric = [a for a in axes if all(_is_number(v) for v in _varying(rows, a)) and len(_varying(rows, a)) > 1]
    if "horizon_m" in numeric:
        return "horizon_m"
    if numeric:
        return max(numeric, key=lambda a: len(_varying(rows, a)))
    raise PlotError(f"{path}: no numeric grid axis varies (expected e.g. a horizon_m column); nothing to plot against")


def _in_panel(row: Row, panel: Panel) -> bool:
    road, direction = panel
    return (road is None or row.get("road") == road) and (direction is None or row.get("direction") == direction)


def _panel_title(panel: Panel) -> str:
    road, direction = panel
    text = "" if road is None else str(road)
    if direction not in (None, ""):
        text += f" ({direction})"
    return text


def _sweep_figure(Figure: Any, layout: _Layout, metrics: Sequence[tuple[str, str]], *, log: bool, title: str) -> Any:
    """One row of panels per metric, one column per (road, direction), one line per combination."""
    # matplotlib is optional, loaded only to draw (see truckmpc.plot)
    from matplotlib.lines import Line2D

    ncols = len(layout.panels)
    row_in = 3.0 if len(metrics) <= 3 else 2.3  # two controllers' six rows stay on a screen or a page
    fig = Figure(figsize=(max(6.5, 4.6 * ncols), 1.0 + row_in * len(metrics)), layout="constrained")
    grid = fig.subplots(len(metrics), ncols, sharex="col", sharey="row", squeeze=False)
    handles: dict[str, Any] = {}
    for col, panel in enumerate(layout.panels):
        in_panel = [r for r in layout.rows if _in_panel(r, panel)]
        for row_i, (metric, ylabel) in enumerate(metrics):
            ax = grid[row_i][col]
            _draw_lines(ax, layout, in_panel, metric, log, handles)
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
                ax.set_xlabel(_axis_label(layout.x_axis))
    if log:
        _mark_real_time(grid[0])
    else:
        _share_fuel_limits(grid, metrics)
    fig.suptitle(title, fontsize="medium")
    entries = list(handles.values())
    if layout.neutral_axis:  # colour says (S, δ), the line style says whether neutral was allowed
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


def _share_fuel_limits(grid: Any, metrics: Sequence[tuple[str, str]]) -> None:
    """One y range for each controller's raw and equal-time Δfuel rows, so the two read side by side."""
    for name, _ in COMPARED:
        rows = [i for i, (column, _) in enumerate(metrics) if column in _fuel_columns(name)]
        if len(rows) < 2:
            continue
        limits = [grid[i][0].get_ylim() for i in rows]
        lo, hi = min(lim[0] for lim in limits), max(lim[1] for lim in limits)
        for i in rows:
            grid[i][0].set_ylim(lo, hi)


def _fuel_columns(name: str) -> tuple[str, ...]:
    """`name`'s raw and equal-time Δ columns of fuel and of battery energy."""
    kinds = ("fuel", "fuel_equal_time")
    return tuple(delta_column(name, kind, consumption=c) for c in (FUEL, ENERGY) for kind in kinds)


def _draw_lines(ax: Any, layout: _Layout, rows: Sequence[Row], metric: str, log: bool, handles: dict[str, Any]) -> None:
    """One line of ``metric`` against the x axis per combination (and per ``allow_neutral``); adds a
    legend handle per combination to ``handles``."""
    # matplotlib is optional, loaded only to draw (see truckmpc.plot)
    from matplotlib.lines import Line2D

    combos = _combos(layout.rows, layout.line_axes)
    colors = [f"C{i % 10}" for i in range(len(combos))]
    neutral_values = _varying(layout.rows, "allow_neutral") if layout.neutral_axis else [None]
    for combo, color in zip(combos, colors, strict=True):
        for neutral in neutral_values:
            points = sorted(
                (r[layout.x_axis], r[metric])
                for r in rows
                if all(r.get(a) == v for a, v in combo)
                and (neutral is None or r.get("allow_neutral") == neutral)
                and _is_number(r.get(layout.x_axis))
                and _is_number(r.get(metric))
                and math.isfinite(r[metric])
                and (r[metric] > 0 or not log)
            )
            if not points:
                continue
            xs, ys = zip(*points, strict=True)
            ax.plot(xs, ys, color=color, ls="-" if neutral in (None, True) else "--", marker="o", ms=3, lw=1.2)
            if combo:  # a lone line needs no legend: the y label and the title say what it is
                label = ", ".join(_line_label(a, v) for a, v in combo)
                handles.setdefault(label, Line2D([], [], color=color, marker="o", ms=3, lw=1.2, label=label))


def _mark_real_time(axes: Sequence[Any]) -> None:
    """A dotted line at q = 1 on the panels whose range includes it."""
    for ax in axes:
        lo, hi = ax.get_ylim()
        if lo <= 1.0 <= hi:
            ax.axhline(1.0, color="k", ls=":", lw=1.0)
            ax.annotate(
                "real time (q = 1)", (0.01, 1.0), xycoords=("axes fraction", "data"), va="bottom", fontsize="small"
            )


def _combos(rows: Sequence[Row], line_axes: Sequence[str]) -> list[tuple[tuple[str, Any], ...]]:
    """Every combination of the line axes' values present in the rows, in first-seen order, sorted."""
    seen: list[tuple[tuple[str, Any], ...]] = []
    for row in rows:
        combo = tuple((a, row.get(a)) for a in line_axes)
        if combo not in seen:
            seen.append(combo)
    with contextlib.suppress(TypeError):  # values that do not compare stay in first-seen order
        seen.sort(key=lambda c: tuple(v for _, v in c))
    return seen

"""The headline of a sweep, ``headline.png``: each look-ahead controller's Δfuel [%] against the PCC
and against the PI at equal trip time and equal end speed (the sweep's headline columns), one panel
per comparison, one group of bars per road and direction, one bar per truck (and combination of
the grid's values), each bar labelled with the fuel it saves [kg] (battery energy and kWh for
battery-electric trucks). A fleet study without a grid has no other picture."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

from truckmpc.sweep.columns import consumption_of_columns, headline_column

Row = Mapping[str, Any]

COMPARISONS = (("mpc", "pcc"), ("mpc", "pi"), ("pcc", "pi"))
"""(controller, baseline) of each panel, in order, where the sweep has its headline."""


def headline_comparisons(header: Sequence[str]) -> list[tuple[str, str]]:
    """The comparisons of :data:`COMPARISONS` whose headline columns the sweep has."""
    return [(run, base) for run, base in COMPARISONS if headline_column(run, base, "headline") in header]


def headline_figure(Figure: Any, header: Sequence[str], rows: Sequence[Row], axes: Sequence[str]) -> Any:
    """The picture: a panel per comparison with a headline, grouped bars per road (and direction)
    and per truck and grid combination (the `axes` whose values vary)."""
    comparisons = headline_comparisons(header)
    consumption = consumption_of_columns(header)
    word, unit = consumption.word, consumption.unit
    roads = list(dict.fromkeys(_road(row) for row in rows))
    series = list(dict.fromkeys(_series(row, header, axes, rows) for row in rows))
    width_in = min(16.0, max(6.5, 1.0 + len(roads) * (0.8 + 0.45 * len(series))))
    fig = Figure(figsize=(width_in, 1.2 + 2.8 * len(comparisons)), layout="constrained")
    panels = fig.subplots(len(comparisons), 1, squeeze=False, sharex=True)
    bar = 0.8 / len(series)
    for k, ((run, base), (ax,)) in enumerate(zip(comparisons, panels, strict=True)):
        for i, name in enumerate(series):
            chosen = {_road(r): r for r in rows if _series(r, header, axes, rows) == name}
            pct = [_number(chosen.get(road), headline_column(run, base, "headline")) for road in roads]
            kg = [_number(chosen.get(road), headline_column(run, base, "saved", consumption)) for road in roads]
            xs = [j - 0.4 + bar * (i + 0.5) for j in range(len(roads))]
            bars = ax.bar(xs, pct, bar, label=name if name and k == 0 else None, color=f"C{i % 10}")
            ax.bar_label(bars, labels=[_saved_label(v, unit) for v in kg], fontsize="x-small", padding=2)
        ax.axhline(0.0, color="0.4", lw=0.8)
        ax.set_ylabel(f"{run.upper()} against the {base.upper()}\nΔ{word} [%]")
        ax.set_xticks(range(len(roads)), roads, rotation=15, ha="right", fontsize="small")
        ax.margins(y=0.2)
        ax.grid(True, axis="y", color="0.88", lw=0.6)
    fig.suptitle(
        f"The headline: Δ{word} at equal trip time and equal end speed (below 0 saves {word})\n"
        f"each bar labelled with the {word} it saves [{unit}]",
        fontsize="medium",
    )
    if any(series):
        fig.legend(loc="outside lower center", fontsize="small", frameon=False, ncol=min(len(series), 4))
    return fig


def _road(row: Row) -> str:
    direction = row.get("direction")
    return f"{row.get('road')}" + (f" ({direction})" if direction not in (None, "", "forward") else "")


def _series(row: Row, header: Sequence[str], axes: Sequence[str], rows: Sequence[Row]) -> str:
    """The row's truck and the values of the grid's axes that vary: what tells its bar from the others'."""
    keys = [key for key in ("vehicle", *axes) if key in header and len({r.get(key) for r in rows}) > 1]
    return ", ".join(f"{row.get(key)}" if key == "vehicle" else f"{key} {row.get(key)}" for key in keys)


def _number(row: Row | None, column: str) -> float:
    value = None if row is None else row.get(column)
    return float(value) if isinstance(value, (int, float)) and not isinstance(value, bool) else math.nan


def _saved_label(saved: float, unit: str) -> str:
    return "" if math.isnan(saved) else f"{saved:.3f} {unit}"

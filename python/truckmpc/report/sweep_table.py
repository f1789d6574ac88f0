"""A sweep's table: one row per row of ``sweep.csv`` (road, direction, vehicle, the grid's values),
with each controller's fuel and trip time and each comparison's Δfuel and Δtrip time as driven and
Δfuel at equal trip time, the headline columns of the sweep."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from truckmpc.report.html import escape, scalar_text
from truckmpc.sweep.columns import ERROR_COLUMN, RUNS, VERSUS

__all__ = ["Column", "shared_keys", "sweep_columns", "sweep_table_html"]

_FIGURES = (("fuel_kg", "fuel [kg]", ".3f"), ("time_s", "trip time [s]", ".1f"))
_DELTAS = (
    ("fuel_equal_time", "Δfuel, equal time [%]"),
    ("fuel", "Δfuel [%]"),
    ("time", "Δtime [%]"),
)
_SHARED = ("road", "direction", "vehicle")
"""Row keys shown once, above the table, when every row has the same value."""


@dataclass(frozen=True)
class Column:
    """One column of the sweep's table: its group (a controller, a comparison, or "" for the row's
    keys), its heading, the sweep.csv column it shows, and how numbers are formatted."""

    group: str
    heading: str
    source: str
    spec: str = ""


def shared_keys(header: Sequence[str], rows: Sequence[Mapping[str, Any]]) -> dict[str, Any]:
    """The row keys (road, direction, vehicle) that are the same in every row, with their value."""
    return {
        name: rows[0].get(name)
        for name in _SHARED
        if name in header and rows and all(row.get(name) == rows[0].get(name) for row in rows)
    }


def sweep_columns(header: Sequence[str], axes: Sequence[str], shared: Sequence[str] = ()) -> list[Column]:
    """The columns of the table for a sweep.csv with `header` and grid `axes`, without the `shared`
    keys (said once above the table)."""
    names = [name for name in _SHARED if name not in shared]
    keys = [Column("", name, name) for name in (*names, *axes) if name in header]
    figures = [
        Column(name, heading, run.column(field), spec)
        for name, run in RUNS.items()
        for field, heading, spec in _FIGURES
        if run.column(field) in header
    ]
    deltas = [
        Column(f"{v.run} vs {v.base}", heading, column, "+.2f")
        for v in VERSUS
        for kind, heading in _DELTAS
        for column in [dict(v.columns).get(kind)]
        if column is not None and column in header
    ]
    return keys + figures + deltas


def sweep_table_html(rows: Sequence[Mapping[str, Any]], columns: Sequence[Column], caption: str = "") -> str:
    """The table, with a row of group headings over the columns, and each row's error under it."""
    groups: list[tuple[str, int]] = []
    for column in columns:
        if groups and groups[-1][0] == column.group:
            groups[-1] = (column.group, groups[-1][1] + 1)
        else:
            groups.append((column.group, 1))
    top = "".join(f'<th colspan="{n}" scope="colgroup" class="group">{escape(group)}</th>' for group, n in groups)
    names = "".join(f'<th scope="col">{escape(c.heading)}</th>' for c in columns)
    body = []
    for row in rows:
        cells = "".join(f"<td>{escape(_cell(row.get(c.source), c.spec))}</td>" for c in columns)
        body.append(f"<tr>{cells}</tr>\n")
        error = row.get(ERROR_COLUMN)
        if error:
            body.append(f'<tr><td colspan="{len(columns)}" class="note">error: {escape(str(error))}</td></tr>\n')
    return (
        f'<div class="wide"><table class="numbers sweep" id="sweep-table"><caption>{escape(caption)}</caption>'
        f"<thead><tr>{top}</tr>"
        f"<tr>{names}</tr></thead>\n<tbody>\n{''.join(body)}</tbody></table></div>\n"
    )


def _cell(value: Any, spec: str) -> str:
    if value is None:
        return ""
    if spec and isinstance(value, (int, float)) and not isinstance(value, bool):
        return format(value, spec)
    return scalar_text(value)

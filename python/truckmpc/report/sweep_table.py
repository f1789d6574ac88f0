"""A sweep's tables, one row per row of ``sweep.csv`` (road, direction, vehicle, the grid's values):
the summary, each comparison's headline first (Δfuel at equal trip time and equal end speed [%] and
the fuel saved [kg]), then Δfuel and Δtrip time as driven against the PI [%]; and each run's fuel
[kg] and trip time [s] (battery energy and kWh for battery-electric trucks). Both fit the page's
width: cells wrap rather than scroll sideways."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from truckmpc.consumption import Consumption
from truckmpc.report.html import escape, scalar_text
from truckmpc.sweep.columns import ERROR_COLUMN, VERSUS, consumption_of_columns, headline_column, runs_of

__all__ = ["Column", "run_columns", "shared_keys", "sweep_columns", "sweep_table_html"]

_FIGURES = (("fuel_kg", "fuel [kg]", ".3f"), ("time_s", "trip time [s]", ".1f"))
_HEADLINE = (("headline", "Δfuel [%]", "+.2f"), ("saved", "saved [kg]", ".3f"))
"""A sweep of battery-electric trucks shows battery energy: :meth:`~truckmpc.consumption.Consumption.worded`."""
_HEADLINES = (("mpc", "pcc"), ("mpc", "pi"), ("pcc", "pi"))
"""The comparisons whose headline the table shows, in order: the MPC against the PCC first."""
_DELTAS = (("fuel", "Δfuel [%]"), ("time", "Δtime [%]"))
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


def _keys(header: Sequence[str], axes: Sequence[str], shared: Sequence[str]) -> list[Column]:
    names = [name for name in _SHARED if name not in shared]
    return [Column("", name, name) for name in (*names, *axes) if name in header]


def sweep_columns(header: Sequence[str], axes: Sequence[str], shared: Sequence[str] = ()) -> list[Column]:
    """The columns of the summary table for a sweep.csv with `header` and grid `axes`, without the
    `shared` keys (said once above the table): each comparison's headline, then as driven."""
    consumption = consumption_of_columns(header)
    headlines = [
        Column(f"{run} vs {base}, equal time and end speed", consumption.worded(heading), column, spec)
        for run, base in _HEADLINES
        for kind, heading, spec in _HEADLINE
        if (column := headline_column(run, base, kind, consumption)) in header
    ]
    deltas = [
        Column(f"{v.run} vs {v.base}, as driven", consumption.worded(heading), column, "+.2f")
        for v in VERSUS
        if v.base == "pi"
        for (kind, heading), (_, column) in zip(_DELTAS, _delta_columns(v, consumption), strict=True)
        if column in header
    ]
    return _keys(header, axes, shared) + headlines + deltas


def _delta_columns(versus: Any, consumption: Consumption) -> list[tuple[str, str]]:
    """The (kind, column) of `versus`'s raw Δ of consumption and of time, in :data:`_DELTAS` order."""
    columns = dict(zip(versus.kinds, versus.columns_of(consumption), strict=True))
    return [columns[kind] for kind, _ in _DELTAS]


def run_columns(header: Sequence[str], axes: Sequence[str], shared: Sequence[str] = ()) -> list[Column]:
    """The columns of the runs' table: each controller's fuel and trip time."""
    consumption = consumption_of_columns(header)
    fields = ((consumption.key if field == "fuel_kg" else field, heading, spec) for field, heading, spec in _FIGURES)
    named = [(field, consumption.worded(heading), spec) for field, heading, spec in fields]
    figures = [
        Column(name, heading, run.column(field), spec)
        for name, run in runs_of(consumption).items()
        for field, heading, spec in named
        if run.column(field) in header
    ]
    return _keys(header, axes, shared) + figures


def sweep_table_html(
    rows: Sequence[Mapping[str, Any]], columns: Sequence[Column], caption: str = "", ident: str = "sweep-table"
) -> str:
    """The table, with a row of group headings over the columns, and each row's error under it; as
    wide as the page, its cells wrapping (the page's ``table.sweep`` style)."""
    groups: list[tuple[str, int]] = []
    for column in columns:
        if groups and groups[-1][0] == column.group:
            groups[-1] = (column.group, groups[-1][1] + 1)
        else:
            groups.append((column.group, 1))
    top = "".join(f'<th colspan="{n}" scope="colgroup" class="group">{escape(group)}</th>' for group, n in groups)
    names = "".join(f'<th scope="col"{_key_class(c)}>{escape(c.heading)}</th>' for c in columns)
    body = []
    for row in rows:
        cells = "".join(f"<td{_key_class(c)}>{_wrappable(_cell(row.get(c.source), c.spec))}</td>" for c in columns)
        body.append(f"<tr>{cells}</tr>\n")
        error = row.get(ERROR_COLUMN)
        if error:
            body.append(f'<tr><td colspan="{len(columns)}" class="note">error: {escape(str(error))}</td></tr>\n')
    return (
        f'<table class="numbers sweep" id="{escape(ident)}"><caption>{escape(caption)}</caption>'
        f"<thead><tr>{top}</tr>"
        f"<tr>{names}</tr></thead>\n<tbody>\n{''.join(body)}</tbody></table>\n"
    )


def _key_class(column: Column) -> str:
    """The class of the road's, direction's and vehicle's cells: text, set left (a grid axis's
    values are numbers more often than not and stay right)."""
    return ' class="key"' if not column.group and column.source in _SHARED else ""


def _wrappable(text: str) -> str:
    """`text` escaped, with a break opportunity after each underscore: a road's name wraps between
    its words, not anywhere, in a column as narrow as the page's width leaves it."""
    return escape(text).replace("_", "_<wbr>")


def _cell(value: Any, spec: str) -> str:
    if value is None:
        return ""
    if spec and isinstance(value, (int, float)) and not isinstance(value, bool):
        return format(value, spec)
    return scalar_text(value)

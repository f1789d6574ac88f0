"""Reading a sweep directory for its pictures: the rows of ``sweep.csv``, its grid axes and the
look-ahead controllers it compared with the PI."""

from __future__ import annotations

import csv
import json
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from truckmpc.config import KEYS
from truckmpc.consumption import ENERGY
from truckmpc.plot.figures import PlotError
from truckmpc.sweep.cells import parse_cell
from truckmpc.sweep.columns import ALL_COLUMNS, LOOK_AHEAD, Layout, consumption_of_columns, delta_column
from truckmpc.sweep.renamed import current_name

RESULT_COLUMNS = frozenset({"road", "direction", *ALL_COLUMNS, *Layout(LOOK_AHEAD, True, ENERGY).columns})
"""Column names of sweep.csv that are not grid axes (of trucks that burn fuel or draw on a battery)."""

CONFIG_KEYS = frozenset(KEYS)
"""Column names of sweep.csv that can be grid axes: any vehicle, controller or simulation key."""

COMPARED = (("mpc", "MPC"), ("pcc", "PCC"))
"""The look-ahead controllers a sweep may compare with the PI, in the order their Δ are drawn."""


def read_sweep(directory: Path) -> tuple[list[str], list[dict[str, Any]]]:
    """The header and the rows (column -> value) of ``sweep.csv``, its columns by today's names."""
    path = directory / "sweep.csv"
    try:
        with path.open(newline="", encoding="utf-8") as handle:
            reader = csv.DictReader(handle)
            header = [current_name(name) for name in reader.fieldnames or []]
            rows = [{current_name(k): parse_cell(v or "") for k, v in row.items() if k is not None} for row in reader]
    except OSError as err:
        raise PlotError(f"{path}: {err.strerror or err}") from err
    if not compared_controllers(header):
        needed = " or ".join(f"'{delta_column(name, 'fuel')}'" for name, _ in COMPARED)
        raise PlotError(f"{path}: no {needed} column")
    if not rows:
        raise PlotError(f"{path}: no rows to plot")
    return header, rows


def compared_controllers(header: Sequence[str]) -> list[tuple[str, str]]:
    """(controller, label) of each look-ahead controller whose Δfuel and Δtime against the PI are
    columns of the sweep."""
    consumption = consumption_of_columns(header)
    return [
        (name, label)
        for name, label in COMPARED
        if all(delta_column(name, kind, consumption=consumption) in header for kind in ("fuel", "time"))
    ]


DELTA_KINDS = (("fuel", "Δfuel [%]"), ("fuel_equal_time", "Δfuel at equal\ntrip time [%]"), ("time", "Δtime [%]"))
"""The kinds of Δ a sweep figure draws, one row of panels each (a sweep's columns name them through
:func:`truckmpc.sweep.columns.delta_column`), with their y labels: the raw Δfuel, the Δfuel against
the PI re-tuned to the run's trip time, and the Δtime (Δenergy for battery-electric trucks)."""


def delta_metrics(compared: Sequence[tuple[str, str]], header: Sequence[str]) -> list[tuple[str, str]]:
    """(column, y label) of each Δ panel row: each controller's Δfuel, its Δfuel at equal trip
    time where the sweep has that column, and its Δtime (the controller named when several)."""
    named, consumption = len(compared) > 1, consumption_of_columns(header)
    return [
        (column, f"{label + ' ' if named else ''}{text.replace('Δfuel', 'Δ' + consumption.word)}")
        for name, label in compared
        for kind, text in DELTA_KINDS
        if (column := delta_column(name, kind, consumption=consumption)) in header
    ]


def grid_axes(directory: Path, header: Sequence[str]) -> list[str]:
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
            named = {axis_name(g) for g in grid if isinstance(g, (str, dict))}
    return [c for c in header if c not in RESULT_COLUMNS and (c in CONFIG_KEYS or c in named)]


def axis_name(entry: str | Mapping[str, Any]) -> str:
    """The key of one ``grid`` entry of ``sweep.json`` (``{"key": ...}``, older ``{"name": ...}``)."""
    return entry if isinstance(entry, str) else str(entry.get("key", entry.get("name")))

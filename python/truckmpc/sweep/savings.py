"""A fleet's headline over its roads: for a group of ``sweep.csv`` rows, one look-ahead controller's
saving against one baseline at equal trip time and equal end speed (the headline columns,
:func:`truckmpc.sweep.columns.headline_column`), as its mean and distance-weighted mean [%], its mean
and total fuel saved [kg], and its best and worst road."""

from __future__ import annotations

import statistics
from collections.abc import Mapping, Sequence

from truckmpc.consumption import FUEL, Consumption
from truckmpc.sweep.columns import headline_column

__all__ = ["SAVINGS_FIGURES", "savings", "savings_column"]

SAVINGS_FIGURES = (
    "compared",
    "mean_pct",
    "weighted_pct",
    "mean_saved_kg",
    "total_saved_kg",
    "best_road",
    "best_pct",
    "best_saved_kg",
    "worst_road",
    "worst_pct",
    "worst_saved_kg",
)
"""The figures of :func:`savings`, each in the summary column :func:`savings_column`: the rows with
a headline; its mean over them and its mean weighted by each row's road length [%] (negative is
saved); the mean and total fuel saved [kg] (positive is saved); the road (``name (direction,
vehicle)``) with the largest saving and the one with the least, each with its headline [%] and fuel
saved [kg]."""


def savings_column(base: str, figure: str) -> str:
    """The summary column of `figure` (:data:`SAVINGS_FIGURES`) against `base`:
    ``headline_vs_<base>_<figure>``."""
    return f"headline_vs_{base}_{figure}"


def savings(
    rows: Sequence[Mapping[str, str]],
    controller: str,
    base: str,
    lengths_m: Mapping[str, float],
    consumption: Consumption = FUEL,
) -> dict[str, str]:
    """The summary cells (by :func:`savings_column`) of `controller`'s headline against `base` over
    `rows` (cell text), each row weighted by its road's length [m] in `lengths_m` (by road name);
    blank where no row has one. The ``*_kg`` figures hold kWh for battery-electric trucks
    (`consumption`); ``summary.csv`` names them so."""
    pct_column = headline_column(controller, base, "headline", consumption)
    kg_column = headline_column(controller, base, "saved", consumption)
    found = [row for row in rows if row.get(pct_column) and row.get(kg_column)]
    cells = dict.fromkeys((savings_column(base, figure) for figure in SAVINGS_FIGURES), "")
    cells[savings_column(base, "compared")] = str(len(found))
    if not found:
        return cells
    pct = [float(row[pct_column]) for row in found]
    kg = [float(row[kg_column]) for row in found]
    weights = [lengths_m[row["road"]] for row in found]
    best, worst = min(range(len(found)), key=pct.__getitem__), max(range(len(found)), key=pct.__getitem__)
    figures = {
        "mean_pct": _number(statistics.fmean(pct)),
        "weighted_pct": _number(sum(w * p for w, p in zip(weights, pct, strict=True)) / sum(weights)),
        "mean_saved_kg": _number(statistics.fmean(kg)),
        "total_saved_kg": _number(sum(kg)),
        "best_road": _road(found[best]),
        "best_pct": _number(pct[best]),
        "best_saved_kg": _number(kg[best]),
        "worst_road": _road(found[worst]),
        "worst_pct": _number(pct[worst]),
        "worst_saved_kg": _number(kg[worst]),
    }
    cells.update({savings_column(base, figure): text for figure, text in figures.items()})
    return cells


def _road(row: Mapping[str, str]) -> str:
    """A row's road as a reader names it: ``name (direction, vehicle)``."""
    where = ", ".join(value for value in (row.get("direction", ""), row.get("vehicle", "")) if value)
    return f"{row['road']} ({where})" if where else row["road"]


def _number(value: float) -> str:
    return f"{value:.6g}"

"""The result columns of ``sweep.csv`` and how a row's figures fill them (the text of a cell is
:mod:`truckmpc.sweep.cells`'s).

After ``road``, ``direction``, ``vehicle`` (when a sweep has several) and one column per axis
come ``error`` (blank unless a run of the row failed), the PI figures, then those of each
look-ahead controller the sweep runs (``--controller``), then the comparisons of :data:`VERSUS`
whose two controllers ran: blank when either run stalled or the baseline is zero
(:func:`truckmpc.compare.compare`), and the equal-time ones also where the baseline could not be
re-tuned to the other's trip time.

Every column but ``error`` belongs to one controller and follows one pattern,
``<controller>_<figure>`` (:func:`run_column`): ``pi_fuel_kg``, ``mpc_neutral_distance_m``,
``pcc_equal_time_pi_fuel_kg``; a comparison is the figure ``delta_<kind>_pct`` of the controller
compared, against the PI, or ``delta_<kind>_vs_<base>_pct`` against another baseline
(:func:`versus_column`): ``mpc_delta_fuel_pct``, ``mpc_delta_fuel_vs_pcc_pct``. Right after ``error``
come the headline columns (:func:`headline_column`): each look-ahead controller's saving at equal
trip time and equal end speed against the PI and against the PCC, in % (``mpc_headline_pct``,
``mpc_headline_vs_pcc_pct``, negative is saved) and in kg (``mpc_saved_kg``,
``mpc_saved_vs_pcc_kg``, positive is saved). Names written by earlier versions are read through
:mod:`truckmpc.sweep.renamed`.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from truckmpc.compare import compare
from truckmpc.consumption import FUEL, Consumption
from truckmpc.sweep.cells import cell, error_text, parse_cell
from truckmpc.sweep.compared import HEADLINE_KINDS, deltas, equal_time_fields, headline_unit
from truckmpc.sweep.run_columns import (
    BASELINE,
    CONVERGENCE_COLUMNS,
    CONVERGENCE_FIELDS,
    DEFAULT_CONTROLLERS,
    EQUAL_TIME_FIELDS,
    ERROR_COLUMN,
    LOOK_AHEAD,
    MPC_FIELDS,
    PCC_FIELDS,
    PI_FIELDS,
    RUNS,
    WALL_TIME_COLUMNS,
    RunColumns,
    check_controllers,
    consumption_of_columns,
    convergence_fields,
    run_column,
    runs_of,
    swept_figures,
)

__all__ = [
    "ALL_COLUMNS",
    "BASELINE",
    "CONVERGENCE_COLUMNS",
    "CONVERGENCE_FIELDS",
    "DEFAULT_CONTROLLERS",
    "EQUAL_TIME_FIELDS",
    "ERROR_COLUMN",
    "LOOK_AHEAD",
    "MPC_FIELDS",
    "PCC_FIELDS",
    "PI_FIELDS",
    "RUNS",
    "SWEEP_COLUMNS",
    "VERSUS",
    "WALL_TIME_COLUMNS",
    "Layout",
    "RunColumns",
    "Versus",
    "check_controllers",
    "consumption_of_columns",
    "convergence_fields",
    "delta_column",
    "headline_column",
    "result_cells",
    "run_column",
    "runs_of",
    "swept_figures",
    "versus_column",
]


def versus_column(run: str, base: str, kind: str) -> str:
    """The column of `run`'s Δ [%] of `kind` (``fuel``, ``time``, ...) against `base`:
    ``<run>_delta_<kind>_pct`` against the PI, ``<run>_delta_<kind>_vs_<base>_pct`` otherwise."""
    against = "" if base == BASELINE else f"_vs_{base}"
    return f"{run}_delta_{kind}{against}_pct"


def headline_column(run: str, base: str, kind: str, consumption: Consumption = FUEL) -> str:
    """The column of `run`'s headline figure `kind` (``headline`` [%], ``saved`` [kg or kWh]) against
    `base`: ``<run>_<kind>_<unit>`` against the PI, ``<run>_<kind>_vs_<base>_<unit>`` otherwise."""
    against = "" if base == BASELINE else f"_vs_{base}"
    return f"{run}_{kind}{against}_{headline_unit(kind, consumption)}"


@dataclass(frozen=True)
class Versus:
    """One comparison of a row: `run` against `base`, each kind of Δ [%] (see :func:`deltas`) in
    its column (:func:`versus_column`)."""

    run: str
    base: str
    kinds: tuple[str, ...]

    @property
    def columns(self) -> tuple[tuple[str, str], ...]:
        """(kind, column) of each Δ."""
        return self.columns_of(FUEL)

    def columns_of(self, consumption: Consumption) -> tuple[tuple[str, str], ...]:
        """(kind, column) of each Δ of a sweep of trucks that consume `consumption`: ``energy`` for
        ``fuel`` in each kind of a battery-electric truck's."""
        kinds = (consumption.worded(kind) for kind in self.kinds)
        return tuple((kind, versus_column(self.run, self.base, kind)) for kind in kinds)

    @property
    def headline_columns(self) -> tuple[tuple[str, str], ...]:
        """(kind, column) of the headline's figures, % and kg (:func:`headline_column`)."""
        return self.headline_columns_of(FUEL)

    def headline_columns_of(self, consumption: Consumption) -> tuple[tuple[str, str], ...]:
        """(kind, column) of the headline's figures, % and kg or kWh."""
        return tuple((kind, headline_column(self.run, self.base, kind, consumption)) for kind in HEADLINE_KINDS)

    @property
    def equal_time(self) -> bool:
        """Whether `base` is re-tuned to `run`'s trip time for it (in `run`'s worker)."""
        return any(kind.startswith("fuel_equal_time") for kind in self.kinds)


VERSUS = (
    Versus("mpc", "pi", ("fuel", "time", "fuel_corrected", "fuel_equal_time", "fuel_equal_time_corrected")),
    Versus("pcc", "pi", ("fuel", "time", "fuel_equal_time")),
    Versus("mpc", "pcc", ("fuel", "fuel_equal_time")),
)
"""The comparisons of a row, in column order; each is there when both its controllers ran."""


def delta_column(run: str, kind: str, base: str = "pi", consumption: Consumption = FUEL) -> str:
    """The column of `run`'s Δ of `kind` (``fuel``, ``time``, ...) against `base`, in a sweep of
    trucks that consume `consumption` (``fuel_equal_time`` is ``energy_equal_time`` for a battery)."""
    versus = next(v for v in VERSUS if (v.run, v.base) == (run, base))
    if kind not in versus.kinds:
        raise KeyError(f"no {kind} delta of {run} against {base}")
    return versus_column(run, base, consumption.worded(kind))


@dataclass(frozen=True)
class Layout:
    """The result columns of a sweep of the PI and `controllers` (:data:`LOOK_AHEAD`, in that
    order), with or without the convergence columns (which need the MPC)."""

    controllers: tuple[str, ...] = DEFAULT_CONTROLLERS
    check_convergence: bool = False
    consumption: Consumption = FUEL
    """What the sweep's trucks consume: fuel, or battery energy (battery-electric trucks), which
    names their figures and comparisons (``pi_energy_kwh``, ``mpc_delta_energy_pct``, ``mpc_saved_kwh``)."""

    @functools.cached_property
    def runs(self) -> tuple[str, ...]:
        """The controllers of each row, the PI first."""
        return ("pi", *self.controllers)

    @functools.cached_property
    def versus(self) -> tuple[Versus, ...]:
        return tuple(v for v in VERSUS if v.run in self.runs and v.base in self.runs)

    def fields(self, controller: str) -> tuple[str, ...]:
        """`controller`'s figures in the CSV: its own, with each baseline other than the PI re-tuned
        to its trip time (:func:`equal_time_fields`), which its headline against that baseline needs."""
        bases = (base for base in self.baselines(controller) if base != BASELINE)
        others = (field for base in bases for field in equal_time_fields(base, self.consumption))
        return (*runs_of(self.consumption)[controller].fields, *others)

    @functools.cached_property
    def sources(self) -> tuple[tuple[str, str, str], ...]:
        """(controller, figure, column) of every figure column."""
        runs = runs_of(self.consumption)
        return tuple((name, field, runs[name].column(field)) for name in self.runs for field in self.fields(name))

    @functools.cached_property
    def convergence(self) -> tuple[tuple[str, str], ...]:
        """(figure, column) of the MPC's convergence moves, when checked."""
        if not self.check_convergence:
            return ()
        return tuple((field, RUNS["mpc"].column(field)) for field in convergence_fields(self.consumption))

    @functools.cached_property
    def headlines(self) -> tuple[str, ...]:
        """The headline columns, each comparison's % then kg: the MPC's against the PCC first."""
        ordered = sorted(self.versus, key=lambda v: (-LOOK_AHEAD.index(v.run), v.base == BASELINE))
        return tuple(column for v in ordered for _, column in v.headline_columns_of(self.consumption))

    @functools.cached_property
    def columns(self) -> tuple[str, ...]:
        """The result columns (after ``road``, ``direction`` and the axes)."""
        figures = tuple(column for _, _, column in self.sources)
        compared = tuple(column for v in self.versus for _, column in v.columns_of(self.consumption))
        convergence = tuple(column for _, column in self.convergence)
        return (ERROR_COLUMN, *self.headlines, *figures, *compared, *convergence)

    def baselines(self, controller: str) -> tuple[str, ...]:
        """The controllers re-tuned to `controller`'s trip time in its worker (its equal-time deltas)."""
        return tuple(v.base for v in self.versus if v.run == controller and v.equal_time)

    def cells(self, runs: Mapping[str, Mapping[str, Any]]) -> list[str]:
        """The result cells of one row from each controller's figures (the MPC's with its
        convergence moves when checked); a failed run (figures ``{"error": line}``) leaves its
        figures and comparisons blank and its error in the ``error`` column."""
        failed = {name: str(figures[ERROR_COLUMN]) for name, figures in runs.items() if ERROR_COLUMN in figures}
        values: dict[str, Any] = {
            column: None if name in failed else runs[name][field] for name, field, column in self.sources
        }
        for v in self.versus:
            by_kind = {} if {v.base, v.run} & set(failed) else deltas(runs[v.base], runs[v.run], v.base, v.run)
            named = (*v.columns_of(self.consumption), *v.headline_columns_of(self.consumption))
            values.update({column: by_kind.get(kind) for kind, column in named})
        if self.check_convergence:  # the moves of the MPC's deltas against the PI
            comparable = not {"pi", "mpc"} & set(failed) and compare(runs["pi"], runs["mpc"]).not_comparable is None
            values.update({c: runs["mpc"].get(f) if comparable else None for f, c in self.convergence})
        values[ERROR_COLUMN] = error_text(failed)
        return [cell(values[c]) for c in self.columns]

    def figures(self, controller: str, cells: Sequence[str]) -> dict[str, Any]:
        """`controller`'s figures read back from a row's result cells."""
        named = dict(zip(self.columns, cells, strict=False))
        column = runs_of(self.consumption)[controller].column
        return {field: parse_cell(named[column(field)]) for field in self.fields(controller)}

    def completed(self, cells: Sequence[str]) -> list[str]:
        """A row's result cells read back with its blank headline cells filled from its own figures
        where they hold them (a row an earlier version wrote, which had no headline columns)."""
        if self.failed(cells) or len(cells) != len(self.columns):
            return list(cells)
        named = dict(zip(self.columns, cells, strict=True))
        runs = {name: self.figures(name, cells) for name in self.runs}
        for v in self.versus:
            by_kind = deltas(runs[v.base], runs[v.run], v.base, v.run)
            for kind, column in v.headline_columns_of(self.consumption):
                named[column] = named[column] or cell(by_kind.get(kind))
        return [named[column] for column in self.columns]

    def failed(self, cells: Sequence[str]) -> bool:
        """Whether a row read back has an error (it is run again on resume)."""
        return len(cells) == len(self.columns) and cells[self.columns.index(ERROR_COLUMN)].strip() != ""

    def damaged(self, cells: Sequence[str]) -> str | None:
        """What is wrong with the result cells of a row read back, or None when each is what
        :func:`cell` writes there: true or false for ``*stalled``, else a finite number or blank."""
        if len(cells) != len(self.columns):
            return f"expected {len(self.columns)} result cells, got {len(cells)}"
        for column, text in zip(self.columns, cells, strict=True):
            if column == ERROR_COLUMN:
                continue
            value = parse_cell(text)
            if column.endswith("stalled"):
                if not isinstance(value, bool):
                    return f"column {column!r}: expected true or false, got {text!r}"
            elif value is not None and (isinstance(value, (bool, str)) or not math.isfinite(value)):
                return f"column {column!r}: expected a number or blank, got {text!r}"
        return None


SWEEP_COLUMNS: tuple[str, ...] = Layout().columns
"""Result columns of the default sweep (PI and MPC)."""

ALL_COLUMNS: tuple[str, ...] = Layout(LOOK_AHEAD, check_convergence=True).columns
"""Every result column a sweep may have."""


def result_cells(pi: Mapping[str, Any], mpc: Mapping[str, Any], check_convergence: bool = False) -> list[str]:
    """The result cells of a PI and MPC row (:data:`SWEEP_COLUMNS`) from the two runs' figures."""
    return Layout(DEFAULT_CONTROLLERS, check_convergence).cells({"pi": pi, "mpc": mpc})

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
from truckmpc.schema import SUMMARY_SPECS
from truckmpc.sweep.cells import cell, error_text, parse_cell
from truckmpc.sweep.compared import HEADLINE_KINDS, deltas, equal_time_fields

SWEPT = {"pi": ("all",), "pcc": ("all", "look_ahead"), "mpc": ("all", "look_ahead", "mpc")}
"""Which of the declared figures (:mod:`truckmpc.schema`, a spec's ``sweep``) go to each
controller's columns: every controller's, the look-ahead controllers', the MPC's."""


def swept_figures(controller: str) -> tuple[str, ...]:
    """The summary figures of `controller` (``pi``, ``pcc`` or ``mpc``) that go to the CSV, in
    column order: those declared for every controller's columns, then the look-ahead controllers',
    then the MPC's, each group in the declaration's order."""
    return tuple(spec.name for group in SWEPT[controller] for spec in SUMMARY_SPECS if spec.sweep == group)


PI_FIELDS = swept_figures("pi")
"""Figures of a run's summary that go to the CSV for every controller (gear shifts between forward
gears and entries into neutral apart, each also per 100 km)."""


EQUAL_TIME_FIELDS = equal_time_fields("pi")
"""The PI re-tuned to a look-ahead run's trip time."""

MPC_FIELDS = (*swept_figures("mpc"), *EQUAL_TIME_FIELDS)
"""Figures of the MPC run's summary that go to the CSV (with its equal-time baseline's)."""

PCC_FIELDS = (*swept_figures("pcc"), *EQUAL_TIME_FIELDS)
"""Figures of the PCC run's summary that go to the CSV (with its equal-time baseline's)."""


@dataclass(frozen=True)
class RunColumns:
    """How one controller's run goes to the CSV: its figures, each in the column ``<name>_<figure>``."""

    name: str
    fields: tuple[str, ...]

    def column(self, field: str) -> str:
        return f"{self.name}_{field}"


RUNS = {
    "pi": RunColumns("pi", PI_FIELDS),
    "pcc": RunColumns("pcc", PCC_FIELDS),
    "mpc": RunColumns("mpc", MPC_FIELDS),
}
"""Every controller a sweep can run, in column order."""


def run_column(controller: str, field: str) -> str:
    """The column of `controller`'s figure `field` (``run_column("mpc", "realtime_ratio")``)."""
    return RUNS[controller].column(field)


BASELINE = "pi"
"""The controller every row runs, that the others are compared with first."""

LOOK_AHEAD = ("pcc", "mpc")
"""The controllers ``sweep --controller`` takes (the PI always runs, as the baseline)."""

DEFAULT_CONTROLLERS = ("mpc",)
"""``sweep --controller`` when not given."""


def versus_column(run: str, base: str, kind: str) -> str:
    """The column of `run`'s Δ [%] of `kind` (``fuel``, ``time``, ...) against `base`:
    ``<run>_delta_<kind>_pct`` against the PI, ``<run>_delta_<kind>_vs_<base>_pct`` otherwise."""
    against = "" if base == BASELINE else f"_vs_{base}"
    return f"{run}_delta_{kind}{against}_pct"


def headline_column(run: str, base: str, kind: str) -> str:
    """The column of `run`'s headline figure `kind` (``headline`` [%], ``saved`` [kg]) against
    `base`: ``<run>_<kind>_<unit>`` against the PI, ``<run>_<kind>_vs_<base>_<unit>`` otherwise."""
    against = "" if base == BASELINE else f"_vs_{base}"
    return f"{run}_{kind}{against}_{dict(HEADLINE_KINDS)[kind]}"


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
        return tuple((kind, versus_column(self.run, self.base, kind)) for kind in self.kinds)

    @property
    def headline_columns(self) -> tuple[tuple[str, str], ...]:
        """(kind, column) of the headline's figures, % and kg (:func:`headline_column`)."""
        return tuple((kind, headline_column(self.run, self.base, kind)) for kind, _ in HEADLINE_KINDS)

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


def delta_column(run: str, kind: str, base: str = "pi") -> str:
    """The column of `run`'s Δ of `kind` (``fuel``, ``time``, ...) against `base`."""
    versus = next(v for v in VERSUS if (v.run, v.base) == (run, base))
    if kind not in versus.kinds:
        raise KeyError(f"no {kind} delta of {run} against {base}")
    return versus_column(run, base, kind)


ERROR_COLUMN = "error"
"""The first result column: why a row's runs failed (``pi: ...; mpc: ...``), blank when they did
not; the failed runs' figures and their comparisons are blank."""

WALL_TIME_COLUMNS = frozenset(
    RUNS["mpc"].column(field) for field in ("realtime_ratio", "solve_ms_mean", "solve_ms_max")
)
"""The columns that are measured wall times: they differ between two runs of the same row."""

CONVERGENCE_FIELDS = (
    *(f"delta_{figure}_pct_half_{half}" for figure in ("fuel", "time", "cost") for half in ("delta", "stage")),
    *(f"delta_{figure}_pct_half_pedal" for figure in ("fuel", "time", "cost")),
)
"""The MPC's figures of :mod:`truckmpc.convergence`."""

CONVERGENCE_COLUMNS = tuple(RUNS["mpc"].column(field) for field in CONVERGENCE_FIELDS)
"""With ``--check-convergence``: how far Δfuel, Δtime and (with the fuel_time cost) fuel + β·time move
[points] with the MPC at half δ, at half S and at twice its pedal levels (:mod:`truckmpc.convergence`);
blank where a halved run is not comparable, and the last three where the row plans no pedal levels."""


def check_controllers(names: Sequence[str]) -> tuple[str, ...]:
    """The look-ahead controllers of a sweep in column order; ValueError (the reason) unless each
    is one of :data:`LOOK_AHEAD`, once."""
    given = [name.strip() for name in names]
    if not given or any(name not in LOOK_AHEAD for name in given) or len(set(given)) < len(given):
        raise ValueError(
            f"expected a comma list of {', '.join(LOOK_AHEAD)}, each once (the pi always runs, as the "
            f"baseline), got {','.join(given)!r}"
        )
    return tuple(name for name in LOOK_AHEAD if name in given)


@dataclass(frozen=True)
class Layout:
    """The result columns of a sweep of the PI and `controllers` (:data:`LOOK_AHEAD`, in that
    order), with or without the convergence columns (which need the MPC)."""

    controllers: tuple[str, ...] = DEFAULT_CONTROLLERS
    check_convergence: bool = False

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
        others = (field for base in self.baselines(controller) if base != BASELINE for field in equal_time_fields(base))
        return (*RUNS[controller].fields, *others)

    @functools.cached_property
    def sources(self) -> tuple[tuple[str, str, str], ...]:
        """(controller, figure, column) of every figure column."""
        return tuple((name, field, RUNS[name].column(field)) for name in self.runs for field in self.fields(name))

    @functools.cached_property
    def headlines(self) -> tuple[str, ...]:
        """The headline columns, each comparison's % then kg: the MPC's against the PCC first."""
        ordered = sorted(self.versus, key=lambda v: (-LOOK_AHEAD.index(v.run), v.base == BASELINE))
        return tuple(column for v in ordered for _, column in v.headline_columns)

    @functools.cached_property
    def columns(self) -> tuple[str, ...]:
        """The result columns (after ``road``, ``direction`` and the axes)."""
        figures = tuple(column for _, _, column in self.sources)
        compared = tuple(column for v in self.versus for _, column in v.columns)
        convergence = CONVERGENCE_COLUMNS if self.check_convergence else ()
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
            values.update({column: by_kind.get(kind) for kind, column in (*v.columns, *v.headline_columns)})
        if self.check_convergence:  # the moves of the MPC's deltas against the PI
            comparable = not {"pi", "mpc"} & set(failed) and compare(runs["pi"], runs["mpc"]).not_comparable is None
            moves = zip(CONVERGENCE_COLUMNS, CONVERGENCE_FIELDS, strict=True)
            values.update({c: runs["mpc"].get(f) if comparable else None for c, f in moves})
        values[ERROR_COLUMN] = error_text(failed)
        return [cell(values[c]) for c in self.columns]

    def figures(self, controller: str, cells: Sequence[str]) -> dict[str, Any]:
        """`controller`'s figures read back from a row's result cells."""
        named = dict(zip(self.columns, cells, strict=False))
        return {field: parse_cell(named[RUNS[controller].column(field)]) for field in self.fields(controller)}

    def completed(self, cells: Sequence[str]) -> list[str]:
        """A row's result cells read back with its blank headline cells filled from its own figures
        where they hold them (a row an earlier version wrote, which had no headline columns)."""
        if self.failed(cells) or len(cells) != len(self.columns):
            return list(cells)
        named = dict(zip(self.columns, cells, strict=True))
        runs = {name: self.figures(name, cells) for name in self.runs}
        for v in self.versus:
            by_kind = deltas(runs[v.base], runs[v.run], v.base, v.run)
            for kind, column in v.headline_columns:
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

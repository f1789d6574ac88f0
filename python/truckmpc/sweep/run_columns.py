"""The figure columns of ``sweep.csv``: each controller's own figures (``<controller>_<figure>``),
which of the declared summary figures go there for trucks that burn fuel or draw on a battery, the
controllers a sweep runs, the ``error`` column and the MPC's convergence moves. The comparisons
and the whole row's layout are :mod:`truckmpc.sweep.columns`'s."""

from __future__ import annotations

import functools
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

from truckmpc.consumption import ENERGY, FUEL, Consumption
from truckmpc.schema import SUMMARY_SPECS, OutputSpec
from truckmpc.sweep.compared import equal_time_fields

SWEPT = {"pi": ("all",), "pcc": ("all", "look_ahead"), "mpc": ("all", "look_ahead", "mpc")}
"""Which of the declared figures (:mod:`truckmpc.schema`, a spec's ``sweep``) go to each
controller's columns: every controller's, the look-ahead controllers', the MPC's."""


def swept_figures(controller: str, consumption: Consumption = FUEL) -> tuple[str, ...]:
    """The summary figures of `controller` (``pi``, ``pcc`` or ``mpc``) that go to the CSV, in
    column order: those declared for every controller's columns, then the look-ahead controllers',
    then the MPC's, each group in the declaration's order; of a sweep of trucks that consume
    `consumption` (fuel, or a battery-electric truck's battery energy), the figures such a run has."""
    return tuple(
        spec.name
        for group in SWEPT[controller]
        for spec in SUMMARY_SPECS
        if spec.sweep == group and _carried(spec, consumption)
    )


def _carried(spec: OutputSpec, consumption: Consumption) -> bool:
    """Whether a run consuming `consumption` has the figure `spec`: a diesel truck's have no battery
    figures, a battery-electric truck's no fuel."""
    if consumption is ENERGY:
        return spec.name not in (FUEL.key, FUEL.corrected_key)
    return spec.runs != "electric"


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
"""Every controller a sweep can run, in column order (a sweep of trucks that consume fuel)."""


@functools.cache
def runs_of(consumption: Consumption) -> dict[str, RunColumns]:
    """Every controller's columns of a sweep of trucks that consume `consumption`."""
    if consumption is FUEL:
        return RUNS
    equal_time = equal_time_fields("pi", consumption)
    return {
        "pi": RunColumns("pi", swept_figures("pi", consumption)),
        "pcc": RunColumns("pcc", (*swept_figures("pcc", consumption), *equal_time)),
        "mpc": RunColumns("mpc", (*swept_figures("mpc", consumption), *equal_time)),
    }


def run_column(controller: str, field: str) -> str:
    """The column of `controller`'s figure `field` (``run_column("mpc", "realtime_ratio")``)."""
    return RUNS[controller].column(field)


BASELINE = "pi"
"""The controller every row runs, that the others are compared with first."""

LOOK_AHEAD = ("pcc", "mpc")
"""The controllers ``sweep --controller`` takes (the PI always runs, as the baseline)."""

DEFAULT_CONTROLLERS = ("mpc",)
"""``sweep --controller`` when not given."""


def consumption_of_columns(columns: Iterable[str]) -> Consumption:
    """What the trucks of a ``sweep.csv`` with `columns` consume: battery energy where the PI's
    column of it is there, else fuel."""
    return ENERGY if run_column(BASELINE, ENERGY.key) in set(columns) else FUEL


ERROR_COLUMN = "error"
"""The first result column: why a row's runs failed (``pi: ...; mpc: ...``), blank when they did
not; the failed runs' figures and their comparisons are blank."""

WALL_TIME_COLUMNS = frozenset(
    RUNS["mpc"].column(field) for field in ("realtime_ratio", "solve_ms_mean", "solve_ms_max")
)
"""The columns that are measured wall times: they differ between two runs of the same row."""


def convergence_fields(consumption: Consumption = FUEL) -> tuple[str, ...]:
    """The MPC's figures of :mod:`truckmpc.convergence` of a truck that consumes `consumption`."""
    figures = (consumption.word, "time", "cost")
    return (
        *(f"delta_{figure}_pct_half_{half}" for figure in figures for half in ("delta", "stage")),
        *(f"delta_{figure}_pct_half_pedal" for figure in figures),
    )


CONVERGENCE_FIELDS = convergence_fields()
"""The MPC's figures of :mod:`truckmpc.convergence` (a truck that consumes fuel)."""

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

"""The result columns of ``sweep.csv`` and the text of its cells.

After ``road``, ``direction`` and one column per axis come the PI figures, the MPC figures (the
solver's and the equal-time baseline's without a prefix), then the comparisons: blank when either
run stalled or the baseline is zero (:func:`truckmpc.compare.compare`), and the equal-time ones
also where the PI could not be re-tuned to the MPC's trip time.
"""

from __future__ import annotations

import contextlib
import json
import math
from collections.abc import Mapping, Sequence
from typing import Any

from truckmpc.compare import compare, delta_pct

PI_FIELDS = ("fuel_kg", "fuel_corrected_kg", "time_s", "end_speed_kmh", "brake_energy_kj", "gear_shifts", "stalled")
"""Figures of a run's summary that go to the CSV for both controllers."""

EQUAL_TIME_FIELDS = ("equal_time_pi_v_ref_kmh", "equal_time_pi_fuel_kg", "equal_time_pi_fuel_corrected_kg")
"""The PI re-tuned to the MPC's trip time (:mod:`truckmpc.equal_time`): blank where it could not be."""

MPC_FIELDS = (
    *PI_FIELDS,
    "neutral_distance_m",
    "realtime_ratio",
    "solve_ms_mean",
    "solve_ms_max",
    "infeasible_solves",
    "transitions_per_solve",
    *EQUAL_TIME_FIELDS,
)
"""Figures of the MPC run's summary that go to the CSV (with its equal-time baseline's)."""

_MPC_ONLY = frozenset(MPC_FIELDS) - frozenset(PI_FIELDS)
_RESULT_SOURCES: tuple[tuple[str, str, str], ...] = (
    *(("pi", name, f"pi_{name}") for name in PI_FIELDS),
    *(("mpc", name, name if name in _MPC_ONLY else f"mpc_{name}") for name in MPC_FIELDS),
)
DELTA_COLUMNS = (
    "delta_fuel_pct",
    "delta_time_pct",
    "delta_fuel_corrected_pct",
    "delta_fuel_equal_time_pct",
    "delta_fuel_equal_time_corrected_pct",
)
"""The comparisons, as in ``summary.json``."""

SWEEP_COLUMNS: tuple[str, ...] = (*(column for _, _, column in _RESULT_SOURCES), *DELTA_COLUMNS)

CONVERGENCE_COLUMNS = (
    "delta_fuel_pct_half_delta",
    "delta_fuel_pct_half_stage",
    "delta_time_pct_half_delta",
    "delta_time_pct_half_stage",
)
"""With ``--check-convergence``: how far Δfuel and Δtime move [points] with the MPC at half δ and at
half S (:mod:`truckmpc.convergence`); blank where a halved run is not comparable."""


def result_columns(check_convergence: bool) -> tuple[str, ...]:
    """The result columns of a sweep, with or without the convergence columns."""
    return (*SWEEP_COLUMNS, *CONVERGENCE_COLUMNS) if check_convergence else SWEEP_COLUMNS


"""Columns of ``sweep.csv`` after ``road``, ``direction`` and one column per axis."""


def cell(value: Any) -> str:
    """A value as written in the CSV (and as a YAML ``--set`` value): true/false, repr of floats
    (exact round trip), blank for None."""
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value) if math.isfinite(value) else ""
    return str(value)


def yaml_text(value: Any) -> str:
    """A value as the YAML text of a ``key=value`` override (strings quoted)."""
    return json.dumps(value) if isinstance(value, str) else ("null" if value is None else cell(value))


def result_cells(pi: Mapping[str, Any], mpc: Mapping[str, Any], check_convergence: bool = False) -> list[str]:
    """The result cells of one row (:func:`result_columns`) from the two runs' figures (the MPC's
    with its convergence moves when checked)."""
    runs = {"pi": pi, "mpc": mpc}
    values = {column: runs[run][name] for run, name, column in _RESULT_SOURCES}
    comparison = compare(pi, mpc)
    values["delta_fuel_pct"], values["delta_time_pct"] = comparison.delta_fuel_pct, comparison.delta_time_pct
    values.update(dict.fromkeys(DELTA_COLUMNS[2:]))
    if comparison.not_comparable is None:
        values["delta_fuel_corrected_pct"] = _delta(mpc["fuel_corrected_kg"], pi["fuel_corrected_kg"])
        values["delta_fuel_equal_time_pct"] = _delta(mpc["fuel_kg"], mpc["equal_time_pi_fuel_kg"])
        corrected = (mpc["fuel_corrected_kg"], mpc["equal_time_pi_fuel_corrected_kg"])
        values["delta_fuel_equal_time_corrected_pct"] = _delta(*corrected)
    for column in CONVERGENCE_COLUMNS:
        values[column] = mpc.get(column) if comparison.not_comparable is None else None
    return [cell(values[c]) for c in result_columns(check_convergence)]


def _delta(value: float | None, base: float | None) -> float | None:
    return None if value is None or base is None else delta_pct(value, base)


def parse_cell(text: str) -> Any:
    """The value a cell's text stands for (the inverse of :func:`cell`, also for ``truckmpc plot``):
    None for blank, a bool for true/false (any case), an int, a float, else the text itself (road
    names, string axis values)."""
    text = text.strip()
    if text == "":
        return None
    if text.lower() in ("true", "false"):
        return text.lower() == "true"
    for number in (int, float):
        with contextlib.suppress(ValueError):
            return number(text)
    return text


def damaged_cell(cells: Sequence[str], check_convergence: bool = False) -> str | None:
    """What is wrong with the result cells (:data:`SWEEP_COLUMNS`) of a row read back, or None when
    each is what :func:`cell` writes there: true or false for ``*stalled``, else a finite number or
    blank."""
    columns = result_columns(check_convergence)
    if len(cells) != len(columns):
        return f"expected {len(columns)} result cells, got {len(cells)}"
    for column, text in zip(columns, cells, strict=True):
        value = parse_cell(text)
        if column.endswith("stalled"):
            if not isinstance(value, bool):
                return f"column {column!r}: expected true or false, got {text!r}"
        elif value is not None and (isinstance(value, (bool, str)) or not math.isfinite(value)):
            return f"column {column!r}: expected a number or blank, got {text!r}"
    return None

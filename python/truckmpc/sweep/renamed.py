"""The result columns of ``sweep.csv`` under the names earlier versions wrote, each with its name
now, so that a sweep directory written by them still resumes and plots.

Earlier versions wrote the MPC's solver figures, its equal-time baseline's, its Δ against the PI and
its convergence moves without the ``mpc_`` prefix (``neutral_distance_m``, ``delta_fuel_pct``), and
its Δ against the PCC as ``delta_<kind>_mpc_vs_pcc_pct``. Readers map a header through
:func:`current_names` before comparing it with :mod:`truckmpc.sweep.columns`'s names.

Earlier versions wrote neither the headline columns nor the MPC's PCC re-tuned to its trip time
(:data:`ADDED_COLUMNS`): a header without them is this sweep's, its rows' cells there are blank,
and a resume fills the headline where the row's own figures give it.
"""

from __future__ import annotations

from collections.abc import Iterable

from truckmpc.sweep.columns import LOOK_AHEAD, RUNS, Layout, versus_column
from truckmpc.sweep.compared import equal_time_fields

__all__ = ["ADDED_COLUMNS", "RENAMED_COLUMNS", "current_name", "current_names"]

_UNPREFIXED_MPC = (
    "neutral_distance_m",
    "realtime_ratio",
    "solve_ms_mean",
    "solve_ms_max",
    "infeasible_solves",
    "transitions_per_solve",
    "equal_time_pi_v_ref_kmh",
    "equal_time_pi_fuel_kg",
    "equal_time_pi_fuel_corrected_kg",
    "delta_fuel_pct",
    "delta_time_pct",
    "delta_fuel_corrected_pct",
    "delta_fuel_equal_time_pct",
    "delta_fuel_equal_time_corrected_pct",
    "delta_fuel_pct_half_delta",
    "delta_fuel_pct_half_stage",
    "delta_time_pct_half_delta",
    "delta_time_pct_half_stage",
)
"""The MPC's columns earlier versions wrote without its prefix."""

RENAMED_COLUMNS: dict[str, str] = {
    **{old: RUNS["mpc"].column(old) for old in _UNPREFIXED_MPC},
    "delta_fuel_mpc_vs_pcc_pct": versus_column("mpc", "pcc", "fuel"),
    "delta_fuel_equal_time_mpc_vs_pcc_pct": versus_column("mpc", "pcc", "fuel_equal_time"),
}
"""Old column name -> the name the sweep writes now."""


ADDED_COLUMNS: frozenset[str] = frozenset(
    (*Layout(LOOK_AHEAD).headlines, *(RUNS["mpc"].column(field) for field in equal_time_fields("pcc")))
)
"""The columns added since earlier versions: blank in the rows those wrote."""


def current_name(name: str) -> str:
    """The name a sweep writes now for column `name` (itself unless it is an old name)."""
    return RENAMED_COLUMNS.get(name, name)


def current_names(header: Iterable[str]) -> list[str]:
    """A ``sweep.csv`` header with its old names replaced by today's."""
    return [current_name(name) for name in header]

"""A run against the baseline: Δ = (x − x_base) / x_base × 100 [%] (thesis section 6.1).

A stalled run did not drive the whole road, so its fuel and time are not those of the road: when
either run stalled there is no delta, and the reason says which run stalled and where. A baseline of
zero (no fuel used on a descent, say) gives no delta either.

:func:`headline` is the figure every output quotes: a look-ahead run's fuel against a baseline's at
equal trip time and equal end speed, in % and in kilograms saved.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from truckmpc.consumption import consumption_of
from truckmpc.units import M_PER_KM, PCT_PER_FRACTION


@dataclass(frozen=True)
class Comparison:
    """Δ of what the run consumed (fuel, or battery energy for a battery-electric truck) and Δtime
    [%] of a run against the baseline; None where not comparable, with the reason in
    ``not_comparable`` (``"not comparable: mpc stalled at km 0.98"``)."""

    delta_consumed_pct: float | None
    delta_time_pct: float | None
    not_comparable: str | None = None


def compare(
    base: Mapping[str, Any], run: Mapping[str, Any], base_name: str = "pi", run_name: str = "mpc"
) -> Comparison:
    """Compare two run summaries (``fuel_kg`` or ``energy_kwh``, ``time_s``, ``stalled`` and, if
    known, ``stall_distance_m`` [m])."""
    stalls = [_stall(name, summary) for name, summary in ((base_name, base), (run_name, run)) if summary["stalled"]]
    if stalls:
        return Comparison(None, None, "not comparable: " + " and ".join(stalls))
    compared = (("consumed", consumption_of(run).key), ("time", "time_s"))
    deltas = {name: delta_pct(run[field], base[field]) for name, field in compared}
    zero = [f"{base_name} {field} is 0" for name, field in compared if deltas[name] is None]
    reason = "not comparable: " + ", ".join(zero) if zero else None
    return Comparison(deltas["consumed"], deltas["time"], reason)


def delta_pct(value: float, base: float) -> float | None:
    """(value − base) / base [%]; None for a zero or non-finite base. A negative base (a
    battery-electric truck that took back more than it drew, or a corrected fuel on a long descent)
    flips the sign's meaning: read such a Δ with the figures beside it."""
    if not base or not math.isfinite(base):
        return None
    return PCT_PER_FRACTION * (value - base) / base


HEADLINE_BASELINES = ("pcc", "pi")
"""The baselines a look-ahead controller's headline is quoted against, in the order outputs give
it: the PCC (what trucks drive today), then the PI."""


@dataclass(frozen=True)
class Headline:
    """A run's saving against a baseline at equal trip time and equal end speed: Δ [%] of what it
    consumes (negative is saved) and what it saved, in the consumption's unit (kg of fuel, kWh of
    battery energy; positive is saved); None each where there is no comparison (a run stalled, the
    baseline did not reach the run's trip time)."""

    pct: float | None
    saved: float | None


def headline(corrected: float | None, baseline_corrected: float | None) -> Headline:
    """The headline of a run whose end-speed-corrected consumption is `corrected` (kg of fuel, kWh
    of battery energy) against its baseline re-run at the run's trip time, whose end-speed-corrected
    consumption is `baseline_corrected` (``summary.json``'s ``headline_pct`` and ``saved_kg`` or
    ``saved_kwh``, and what every table, CSV and page quotes, read through this one function)."""
    if corrected is None or baseline_corrected is None:
        return Headline(None, None)
    pct = delta_pct(corrected, baseline_corrected)
    return Headline(pct, None if pct is None else baseline_corrected - corrected)


def _stall(name: str, summary: Mapping[str, Any]) -> str:
    where_m = summary.get("stall_distance_m")
    what = "'s battery emptied" if summary.get("battery_empty") else " stalled"
    return f"{name}{what}" + (f" at km {where_m / M_PER_KM:.2f}" if isinstance(where_m, (int, float)) else "")

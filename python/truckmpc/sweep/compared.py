"""The comparisons of a ``sweep.csv`` row, from its runs' figures: each kind of Δ [%] of a
look-ahead run against a baseline, and the headline, its saving at equal trip time and equal end
speed (:func:`truckmpc.compare.headline`) in % and in kilograms. Which columns they go to is
:mod:`truckmpc.sweep.columns`'s."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from truckmpc.compare import compare, delta_pct, headline

__all__ = ["HEADLINE_KINDS", "deltas", "equal_time_fields"]

HEADLINE_KINDS = (("headline", "pct"), ("saved", "kg"))
"""The headline's two figures, each with its unit: Δfuel [%] at equal trip time and end speed
(negative is saved) and the fuel saved [kg] (positive is saved)."""


def equal_time_fields(baseline: str) -> tuple[str, ...]:
    """The figures of `baseline` re-tuned to a run's trip time (:mod:`truckmpc.equal_time`): its
    set speed [km/h], fuel and end-speed-corrected fuel [kg]; blank where it could not be."""
    return tuple(f"equal_time_{baseline}_{name}" for name in ("v_ref_kmh", "fuel_kg", "fuel_corrected_kg"))


def deltas(base: Mapping[str, Any], run: Mapping[str, Any], base_name: str, run_name: str) -> dict[str, Any]:
    """Δ [%] of `run` against `base` by kind: ``fuel`` and ``time`` (:func:`compare`); where those
    are comparable also ``fuel_corrected`` (both end speeds corrected) and ``fuel_equal_time`` (raw
    and ``_corrected``) against `base` re-tuned to `run`'s trip time (the ``equal_time_<base>_*``
    figures of `run`), and the headline's ``headline`` [%] and ``saved`` [kg]; None where there is
    none."""
    comparison = compare(base, run, base_name, run_name)
    out: dict[str, Any] = {"fuel": comparison.delta_consumed_pct, "time": comparison.delta_time_pct}
    if comparison.not_comparable is not None:
        return out
    _, equal_fuel, equal_corrected = equal_time_fields(base_name)
    out["fuel_corrected"] = _delta(run["fuel_corrected_kg"], base.get("fuel_corrected_kg"))
    out["fuel_equal_time"] = _delta(run["fuel_kg"], run.get(equal_fuel))
    out["fuel_equal_time_corrected"] = _delta(run["fuel_corrected_kg"], run.get(equal_corrected))
    quoted = headline(run.get("fuel_corrected_kg"), run.get(equal_corrected))
    out.update(headline=quoted.pct, saved=quoted.saved)
    return out


def _delta(value: float | None, base: float | None) -> float | None:
    return None if value is None or base is None else delta_pct(value, base)

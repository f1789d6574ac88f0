"""The comparisons of a ``sweep.csv`` row, from its runs' figures: each kind of Δ [%] of a
look-ahead run against a baseline, and the headline, its saving at equal trip time and equal end
speed (:func:`truckmpc.compare.headline`) in % and in kilograms (kWh for a battery-electric truck,
whose kinds say ``energy`` where a diesel truck's say ``fuel``). Which columns they go to is
:mod:`truckmpc.sweep.columns`'s."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from truckmpc.compare import compare, delta_pct, headline
from truckmpc.consumption import FUEL, Consumption, consumption_of

__all__ = ["HEADLINE_KINDS", "deltas", "equal_time_fields", "headline_unit"]

HEADLINE_KINDS = ("headline", "saved")
"""The headline's two figures: Δfuel [%] at equal trip time and end speed (negative is saved) and
the fuel saved (positive is saved), in kg, or battery energy in kWh (:func:`headline_unit`)."""


def headline_unit(kind: str, consumption: Consumption = FUEL) -> str:
    """The unit in the column name of the headline's figure `kind`: ``pct``, or the consumption's
    (``kg``, ``kwh``) for what is saved."""
    return "pct" if kind == "headline" else consumption.unit.lower()


def equal_time_fields(baseline: str, consumption: Consumption = FUEL) -> tuple[str, ...]:
    """The figures of `baseline` re-tuned to a run's trip time (:mod:`truckmpc.equal_time`): its
    set speed [km/h], fuel and end-speed-corrected fuel [kg] (battery energy [kWh]); blank where it
    could not be."""
    names = ("v_ref_kmh", consumption.key, consumption.corrected_key)
    return tuple(f"equal_time_{baseline}_{name}" for name in names)


def deltas(base: Mapping[str, Any], run: Mapping[str, Any], base_name: str, run_name: str) -> dict[str, Any]:
    """Δ [%] of `run` against `base` by kind: ``fuel`` and ``time`` (:func:`compare`); where those
    are comparable also ``fuel_corrected`` (both end speeds corrected) and ``fuel_equal_time`` (raw
    and ``_corrected``) against `base` re-tuned to `run`'s trip time (the ``equal_time_<base>_*``
    figures of `run`), and the headline's ``headline`` [%] and ``saved`` [kg]; None where there is
    none. A battery-electric truck's kinds say ``energy`` (``energy_equal_time``), in kWh."""
    consumption = consumption_of(run)
    word, key, corrected_key = consumption.word, consumption.key, consumption.corrected_key
    comparison = compare(base, run, base_name, run_name)
    out: dict[str, Any] = {word: comparison.delta_consumed_pct, "time": comparison.delta_time_pct}
    if comparison.not_comparable is not None:
        return out
    _, equal_used, equal_corrected = equal_time_fields(base_name, consumption)
    out[f"{word}_corrected"] = _delta(run[corrected_key], base.get(corrected_key))
    out[f"{word}_equal_time"] = _delta(run[key], run.get(equal_used))
    out[f"{word}_equal_time_corrected"] = _delta(run[corrected_key], run.get(equal_corrected))
    quoted = headline(run.get(corrected_key), run.get(equal_corrected))
    out.update(headline=quoted.pct, saved=quoted.saved)
    return out


def _delta(value: float | None, base: float | None) -> float | None:
    return None if value is None or base is None else delta_pct(value, base)

"""The content of a run's ``summary.json``: each controller's summary and the comparisons.

``summary.json``::

    {"road": <name>, "length_m": <m>,
     "pi": {<summary of the PI run>},
     "mpc": {...}, "delta_fuel_pct": ..., "delta_time_pct": ...,   # when both ran
     "delta_fuel_corrected_pct": ...,            # both runs' end speeds brought back to their start speeds
     "delta_fuel_equal_time_pct": ...,           # against the pi re-tuned to the mpc's trip time
     "delta_fuel_equal_time_corrected_pct": ...,
     "equal_time": {"pi_v_ref_kmh", "pi_time_s", "pi_fuel_kg", "pi_fuel_corrected_kg", "target_time_s",
                    "time_error_pct", "pi_runs", "not_comparable" (only when the time was not reached)},
     "not_comparable": "not comparable: mpc stalled at km 0.98"}   # only when a delta is null

With several look-ahead controllers (``--controller all``) each delta and ``equal_time`` key ends in
``_<controller>``. ``"comparisons"`` lists the same per controller against the PI, then each
look-ahead controller against VECTO's cruise driver (``vecto_cc``) and each optimising one against
the PCC, when they ran (their ``equal_time_<controller>_vs_<baseline>`` objects beside):
``[{"controller", "baseline", "delta_fuel_pct", "delta_time_pct", "delta_fuel_corrected_pct",
"delta_fuel_equal_time_pct", "delta_fuel_equal_time_corrected_pct", "headline_pct", "saved_kg",
"not_comparable"?}, ...]``: ``headline_pct`` (:data:`HEADLINE`) is the figure to quote, ``saved_kg``
(:data:`SAVED`) the same in kilograms. A battery-electric truck's runs compare battery energy under
keys named for it (:mod:`truckmpc.consumption`): ``delta_energy_pct``, ``delta_energy_corrected_pct``,
``delta_energy_equal_time_pct``, ``delta_energy_equal_time_corrected_pct``, ``saved_kwh``, and in
``equal_time`` ``pi_energy_kwh`` and ``pi_energy_corrected_kwh``.
The end-speed correction is :mod:`truckmpc.fuel`'s, the equal-time search :mod:`truckmpc.equal_time`'s.

The deltas follow the thesis (section 6.1): (x_mpc − x_pi) / x_pi in percent; they are null when a
run stalled or the baseline is zero (:func:`truckmpc.compare.compare`).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

from truckmpc.compare import compare, delta_pct, headline
from truckmpc.consumption import consumption_of
from truckmpc.equal_time import BASELINES, EqualTime, compared_with
from truckmpc.sim import RunResult

if TYPE_CHECKING:
    from truckmpc.roads import RoadProfile

__all__ = ["BASELINE", "HEADLINE", "SAVED", "summary_document"]

BASELINE = "pi"
"""The controller every other one is compared against."""

HEADLINE = "headline_pct"
"""The comparison to quote: Δfuel [%] against the baseline at equal trip time and equal end speed
(the baseline re-run to the controller's trip time, both runs' end speeds brought back to their
start speeds); negative is fuel saved. Null where not comparable."""

SAVED = "saved_kg"
"""The same comparison in kilograms: the baseline's fuel minus the controller's [kg], at equal trip
time and end speed (positive is fuel saved); unlike a percentage it does not shrink when flat road
is added."""


def summary_document(
    road: RoadProfile,
    results: Mapping[str, RunResult],
    run: Mapping[str, Any] | None = None,
    equal_times: Mapping[str, EqualTime] | None = None,
) -> dict[str, Any]:
    """The ``summary.json`` content for runs of several controllers over ``road``; ``run`` is the
    record of what was run (:func:`truckmpc.record.run_record`), kept under ``"run"``;
    ``equal_times`` the baseline driven to each look-ahead run's trip time."""
    doc: dict[str, Any] = {"road": road.name, "length_m": float(road.length_m)}
    for name, result in results.items():
        doc[name] = dict(result.summary)
    base = results.get(BASELINE)
    comparisons = []
    for name, result in results.items():
        if base is None or name == BASELINE:
            continue
        entry = _comparison(base, result, (equal_times or {}).get(name))
        suffix = "" if len(results) == 2 else f"_{name}"
        doc.update({f"{key}{suffix}": value for key, value in entry.items() if key not in ("controller", "baseline")})
        comparisons.append({key: value for key, value in entry.items() if key != "equal_time"})
    for baseline in (name for name in BASELINES if name != BASELINE and name in results):
        for name in (name for name in compared_with(baseline) if name in results):
            key = f"{name}_vs_{baseline}"
            entry = _comparison(results[baseline], results[name], (equal_times or {}).get(key))
            comparisons.append({key: value for key, value in entry.items() if key != "equal_time"})
            doc[f"equal_time_{key}"] = entry.get("equal_time")
    if comparisons:
        doc["comparisons"] = comparisons
    if "mpc" in results and "optimal" in results:
        doc["gap_to_optimal_pct"] = _gap_to_optimal(results["mpc"].summary, results["optimal"].summary)
    if run is not None:
        doc["run"] = dict(run)
    return doc


def _comparison(base: RunResult, run: RunResult, equal: EqualTime | None) -> dict[str, Any]:
    """One entry of ``comparisons``: `run` against `base`, raw, end-speed corrected and at equal
    trip time (`base` re-tuned to `run`'s time), with the equal-time search's figures."""
    comparison = compare(base.summary, run.summary, base.name, run.name)
    entry: dict[str, Any] = {
        "controller": run.name,
        "baseline": base.name,
        consumption_of(run.summary).delta_key(): comparison.delta_consumed_pct,
        "delta_time_pct": comparison.delta_time_pct,
    }
    if comparison.not_comparable is not None:
        entry["not_comparable"] = comparison.not_comparable
        return entry
    entry.update(_time_fair_deltas(base.summary, run.summary, equal, base.name))
    if "not_comparable" in entry.get("equal_time", {}):
        entry["not_comparable"] = entry["equal_time"]["not_comparable"]
    return entry


def _time_fair_deltas(
    base: Mapping[str, Any], run: Mapping[str, Any], equal: EqualTime | None, baseline: str
) -> dict[str, Any]:
    """Δ [%] of what the runs consumed (fuel, or battery energy: :mod:`truckmpc.consumption` names
    the keys) with both runs' end speeds corrected, and against the baseline at equal trip time
    (raw and corrected), with the ``equal_time`` object; null where the baseline did not reach the
    time."""
    doc: dict[str, Any] = {}
    c = consumption_of(run)
    if base.get(c.corrected_key) is not None and run.get(c.corrected_key) is not None:
        doc[c.delta_key("_corrected")] = delta_pct(run[c.corrected_key], base[c.corrected_key])
    if equal is None:
        return doc
    raw, corrected = equal.consumed, equal.consumed_corrected
    reached = equal.reached and raw is not None and corrected is not None
    own = run.get(c.corrected_key)
    doc[c.delta_key("_equal_time")] = delta_pct(run[c.key], raw) if reached and raw else None
    quoted = headline(own, corrected if reached else None)
    doc[c.delta_key("_equal_time_corrected")] = quoted.pct
    doc[HEADLINE], doc[c.saved_key] = quoted.pct, quoted.saved
    doc["equal_time"] = equal.document(baseline)
    return doc


def _gap_to_optimal(mpc: Mapping[str, Any], optimal: Mapping[str, Any]) -> float | None:
    """How much more fuel the MPC burns than the whole-road optimum, in % of the optimum's fuel
    (None when either stalled)."""
    comparison = compare(optimal, mpc, "optimal", "mpc")
    return comparison.delta_consumed_pct

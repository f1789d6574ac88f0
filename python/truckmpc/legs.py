"""A road with stops, driven as its stop-free legs and reported as one run.

The vehicle model cannot launch from standstill (below the stall speed gear 1 turns the engine
slower than idle) and the cruise controllers do not brake to a standstill, so a driving cycle's stops
(:class:`truckmpc.roads.profile.Stop`) are not simulated: the road is cut at every stop inside it into
legs (:mod:`truckmpc.roads.stops`), each leg is driven on its own from its entry target speed (the set
speed at its start; with `start_speed_kmh` configured, the first leg starts at that), and the legs'
results are joined into one :class:`~truckmpc.sim.RunResult`. The summary says so
(`stops_not_simulated`) and lists the legs (`legs`: each one's start and end [m], entry and exit
speed [km/h], fuel [kg] and time [s]); the trace runs on across the legs, with two samples at each
stop (the end of one leg and the start of the next) and the cumulative columns continued.

A battery-electric truck's battery carries over the stops: each leg after the first starts at the
state of charge the one before ended at (what the auxiliaries draw while the truck stands is not
simulated, as the diesel truck's idling is not), and a battery that empties ends the run there.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from truckmpc.errors import RoadError
from truckmpc.roads.profile import RoadProfile
from truckmpc.roads.stops import MIN_LEG_M, STOPS_NOTE, leg_bounds, leg_road
from truckmpc.schema import SUMMARY_SPECS, TRACE_SPECS
from truckmpc.units import KMH_PER_MPS, M_PER_KM

if TYPE_CHECKING:
    from truckmpc.config import RunConfig
    from truckmpc.sim import RunResult

__all__ = ["drive_legs", "merge_legs", "stops_document", "stops_line", "stops_text"]

CUMULATIVE = tuple(spec.name for spec in TRACE_SPECS if spec.merge == "continued")
"""Trace columns counted from the start of the run, continued across the legs."""

Drive = Callable[[RoadProfile, "RunConfig"], "RunResult"]
"""Drive one stop-free road with a configuration."""


def stops_document(road: RoadProfile) -> dict[str, Any]:
    """The summary's `stops_not_simulated`: how many stops `road` has, their total duration [s], why."""
    total_s = road.stop_time_s
    return {"count": len(road.stops), "total_stop_s": total_s, "note": STOPS_NOTE, "legs": len(leg_bounds(road))}


def stops_line(road: RoadProfile) -> str:
    """One line for the CLI on how a road's stops are driven (`road.stops` must not be empty)."""
    return stops_text(len(road.stops), road.stop_time_s, len(leg_bounds(road)))


def stops_text(count: int, total_s: float, legs: int) -> str:
    """The line of :func:`stops_line` from `count` stops lasting `total_s` [s], driven as `legs` legs."""
    return (
        f"stops not simulated: {count} stops ({total_s:g} s); driven as {legs} stop-free legs, "
        "each from its entry target speed (no launch, no braking to standstill)"
    )


def drive_legs(road: RoadProfile, config: RunConfig, drive: Drive) -> RunResult:
    """Drive each stop-free leg of `road` with `drive` and join the results (:func:`merge_legs`);
    after a leg that stalls (or ends short of its end) the later legs are not driven."""
    bounds = leg_bounds(road)
    if not bounds:
        raise RoadError(f"{road.source or road.name}: no stop-free leg of at least {MIN_LEG_M:g} m between its stops")
    results: list[RunResult] = []
    for number, (start_m, end_m) in enumerate(bounds, start=1):
        previous = results[-1].summary if results else None
        result = drive(leg_road(road, start_m, end_m, number), _leg_config(config, number, previous))
        results.append(result)
        if result.message is not None:
            break
    return merge_legs(road, results, bounds)


def _leg_config(config: RunConfig, number: int, previous: Mapping[str, Any] | None) -> RunConfig:
    """The configuration of leg `number` (from 1), after the leg whose summary is `previous`: a
    configured start speed is the first leg's, the others start at their entry set speed; a
    battery-electric truck starts at the state of charge the previous leg ended at."""
    where = f"leg {number}"
    if number > 1 and config.settings.get("start_speed_kmh") is not None:
        config = config.with_values({"start_speed_kmh": None}, where)
    if previous is not None and config.is_electric:
        config = config.with_truck_values({"soc_start_pct": previous["soc_end_pct"]}, where)
    return config


def merge_legs(road: RoadProfile, results: Sequence[RunResult], bounds: Sequence[tuple[float, float]]) -> RunResult:
    """One result for `road` from the results of its first legs (`bounds`: every leg's (start, end)
    [m]; fewer results than legs when one stalled)."""
    summary = _merged_summary([result.summary for result in results])
    summary["legs"] = [
        {
            "start_m": start_m,
            "end_m": end_m,
            "entry_speed_kmh": result.summary["start_speed_kmh"],
            "exit_speed_kmh": result.summary["end_speed_kmh"],
            **{key: result.summary[key] for key in ("fuel_kg", "energy_kwh") if key in result.summary},
            "time_s": result.summary["time_s"],
        }
        for (start_m, end_m), result in zip(bounds, results, strict=False)
    ]
    summary["stops_not_simulated"] = stops_document(road)
    if len(results) < len(bounds):
        skipped, next_m = len(bounds) - len(results), bounds[len(results)][0]
        legs = "the later leg" if skipped == 1 else f"the {skipped} later legs"
        summary["message"] = (
            f"{summary['message']}; {legs} (from km {next_m / M_PER_KM:.2f}) {'was' if skipped == 1 else 'were'} "
            "not driven"
        )
    trace = _merged_trace([result.trace for result in results])
    return dataclasses.replace(results[0], road=road.name, summary=summary, trace=trace)


def _merged_summary(legs: Sequence[Mapping[str, Any]]) -> dict[str, Any]:
    """The legs' summaries as one, each figure joined by its declared rule (:mod:`truckmpc.schema`):
    sums, maxima, solve-weighted means, the first leg's start speed, the last leg's end speed and
    any other entry, then the figures recomputed from the joined ones (per 100 km, per trip time)."""
    merged = {**legs[0], **legs[-1]}
    stalled = any(leg["stalled"] for leg in legs)
    for spec in SUMMARY_SPECS:
        if spec.merge in _JOINED:
            _JOINED[spec.merge](merged, spec.name, legs, stalled)
    for spec in SUMMARY_SPECS:
        if spec.merge in _RECOMPUTED and spec.merge_of in (None, *merged):
            _RECOMPUTED[spec.merge](merged, spec.name, spec.merge_of or "")
    return merged


Legs = Sequence[Mapping[str, Any]]


def _first(merged: dict[str, Any], key: str, legs: Legs, stalled: bool) -> None:
    if key in legs[0]:
        merged[key] = legs[0][key]


def _sum(merged: dict[str, Any], key: str, legs: Legs, stalled: bool) -> None:
    """The legs' sum when every leg has a value; else the last leg's stays."""
    values = [leg.get(key) for leg in legs]
    if all(value is not None for value in values):
        merged[key] = sum(values)


def _sum_unless_stalled(merged: dict[str, Any], key: str, legs: Legs, stalled: bool) -> None:
    if key not in legs[0]:
        return
    _sum(merged, key, legs, stalled)
    merged[key] = None if stalled else merged.get(key)


def _max(merged: dict[str, Any], key: str, legs: Legs, stalled: bool) -> None:
    if key in merged:  # legs without a value (a plan with no path) are left out
        merged[key] = max((leg[key] for leg in legs if leg.get(key) is not None), default=None)


def _any(merged: dict[str, Any], key: str, legs: Legs, stalled: bool) -> None:
    if key in merged:
        merged[key] = any(leg[key] for leg in legs)


def _mean_per_solve(merged: dict[str, Any], key: str, legs: Legs, stalled: bool) -> None:
    solves = sum(leg.get("solves") or 0 for leg in legs)
    if key in merged and solves:
        merged[key] = sum(leg[key] * leg["solves"] for leg in legs) / solves


_JOINED = {
    "first": _first,
    "sum": _sum,
    "sum_unless_stalled": _sum_unless_stalled,
    "max": _max,
    "any": _any,
    "mean_per_solve": _mean_per_solve,
}
"""How each rule of :mod:`truckmpc.schema` joins a figure from the legs (``last``: the merged
dict holds the last leg's already; ``built``: :func:`merge_legs` makes it)."""


def _per_100km(merged: dict[str, Any], key: str, of: str) -> None:
    distance_m = merged["distance_m"]
    merged[key] = merged[of] / (distance_m / (100.0 * M_PER_KM)) if distance_m > 0 else None


def _per_time_s(merged: dict[str, Any], key: str, of: str) -> None:
    time_s = merged["time_s"]
    merged[key] = merged[of] / time_s if time_s > 0 else None


def _mean_speed(merged: dict[str, Any], key: str, of: str) -> None:
    distance_m, time_s = merged["distance_m"], merged["time_s"]
    merged[key] = distance_m / time_s * KMH_PER_MPS if time_s > 0 else merged["start_speed_kmh"]


_RECOMPUTED = {"per_100km": _per_100km, "per_time_s": _per_time_s, "mean_speed": _mean_speed}
"""The rules that recompute a figure from joined ones (after every other is joined)."""


def _merged_trace(traces: Sequence[Mapping[str, np.ndarray]]) -> dict[str, np.ndarray]:
    """The legs' traces one after the other (distances are the road's already), the cumulative
    columns of each leg counted on from where the previous leg's ended."""
    offsets = dict.fromkeys(CUMULATIVE, 0.0)
    parts: dict[str, list[np.ndarray]] = {name: [] for name in traces[0]}
    for trace in traces:
        for name in parts:
            column = np.asarray(trace[name])
            parts[name].append(column + offsets[name] if name in offsets else column)
        offsets = {name: float(parts[name][-1][-1]) for name in CUMULATIVE if name in parts}
    return {name: np.concatenate(columns) for name, columns in parts.items()}

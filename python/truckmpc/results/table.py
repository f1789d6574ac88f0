"""The short table of a run's figures the CLI prints (``truckmpc simulate``)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

from truckmpc.convergence import convergence_lines
from truckmpc.equal_time import EqualTime
from truckmpc.legs import stops_line
from truckmpc.results.summary import BASELINE, summary_document
from truckmpc.sim import RunResult
from truckmpc.table import figure_lines, label_width
from truckmpc.units import M_PER_KM

if TYPE_CHECKING:
    from truckmpc.config import RunConfig
    from truckmpc.roads import RoadProfile

__all__ = ["format_table"]

_FIGURES = (
    ("fuel", "fuel_kg", "kg", ".3f"),
    ("fuel per 100 km", "fuel_kg_per_100km", "kg", ".2f"),
    ("trip time", "time_s", "s", ".1f"),
    ("mean speed", "mean_speed_kmh", "km/h", ".2f"),
    ("end speed", "end_speed_kmh", "km/h", ".2f"),
    ("gear shifts", "gear_shifts", "", "d"),
    ("gear shifts per 100 km", "gear_shifts_per_100km", "", ".1f"),
    ("neutral engagements", "neutral_engagements", "", "d"),
    ("neutral engagements per 100 km", "neutral_engagements_per_100km", "", ".1f"),
    ("brake energy", "brake_energy_kj", "kJ", ".1f"),
    ("neutral distance", "neutral_distance_m", "m", ".0f"),
    ("compute time", "compute_time_s", "s", ".2f"),
    ("realtime ratio", "realtime_ratio", "", ".2e"),
    ("horizon solves", "horizon_solves", "", "d"),
    ("infeasible solves", "infeasible_solves", "", "d"),
    ("relaxed solves driven", "fallback_relaxed", "", "d"),
    ("rescues", "fallback_rescues", "", "d"),
    ("rescue distance", "fallback_rescue_m", "m", ".0f"),
    ("solve time mean", "solve_ms_mean", "ms", ".3f"),
    ("solve time max", "solve_ms_max", "ms", ".3f"),
    ("plan fuel", "plan_fuel_kg", "kg", ".3f"),
    ("plan trip time", "plan_time_s", "s", ".1f"),
    ("plan solve time", "plan_solve_s", "s", ".2f"),
)


def format_table(
    road: RoadProfile,
    results: Mapping[str, RunResult],
    config: RunConfig | None = None,
    convergence: Mapping[str, Any] | None = None,
    equal_times: Mapping[str, EqualTime] | None = None,
) -> str:
    """A short plain-text table of the runs' main figures, one column per controller; with the
    configuration, its first line names the truck's mass, v_ref and the speed band; with a
    ``convergence`` object, how far the deltas move at half δ and half S."""
    names = list(results)
    doc = summary_document(road, results, equal_times=equal_times)
    lines = [f"road {road.name}: {road.length_m / M_PER_KM:.2f} km" + ("" if config is None else _setup(config))]
    lines += [stops_line(road)] if road.stops else []
    deltas = [
        (key.replace("_pct", " [%]").replace("_", " "), value)
        for key, value in doc.items()
        if key.startswith(("delta_", "gap_to_optimal_pct")) and isinstance(value, float)
    ]
    for entry in doc.get("comparisons", []):
        if entry["baseline"] != BASELINE:
            who = f"{entry['controller']} vs {entry['baseline']}"
            deltas += [
                (f"{key.replace('_pct', ' [%]').replace('_', ' ')} {who}", value)
                for key, value in entry.items()
                if key.startswith("delta_") and isinstance(value, float)
            ]
    width = max([label_width(_FIGURES), *(len(label) + 2 for label, _ in deltas)])
    lines.append(" " * width + "".join(f"{name:>14}" for name in names))
    lines += figure_lines(_FIGURES, [results[name].summary for name in names], 14, width)
    lines += [f"{label:<{width}}{value:>+14.2f}" for label, value in deltas]
    for key, value in doc.items():
        if key.startswith("equal_time") and isinstance(value, dict):
            lines.append(_equal_time_line(key, value, width))
    lines += [text for key, text in doc.items() if key.startswith("not_comparable")]
    if convergence is not None:
        lines += convergence_lines(convergence, width)
    for name in names:
        if results[name].message:
            lines.append(f"{name}: {results[name].message}")
    return "\n".join(lines)


def _equal_time_line(key: str, equal: Mapping[str, Any], width: int) -> str:
    """`equal time pi v_ref [km/h]   84.41  (4789.3 s, 6 runs)` (on a road with target speeds
    `equal time pi target offset [km/h]   +1.20 ...`), or why the time was not reached."""
    name, _, against = key.partition("_vs_")
    baseline = against or "pi"
    moved = "target_offset_kmh" if f"{baseline}_target_offset_kmh" in equal else "v_ref_kmh"
    what, spec = ("target offset", "+14.2f") if moved == "target_offset_kmh" else ("v_ref", "14.2f")
    label = f"{name.replace('_', ' ')} {baseline} {what} [km/h]"
    if "not_comparable" in equal:
        return f"{label}: {equal['not_comparable']}"
    value, time_s, runs = (equal[f"{baseline}_{k}"] for k in (moved, "time_s", "runs"))
    return f"{label:<{width}}{value:{spec}}  ({time_s:.1f} s, {runs} runs)"


def _setup(config: RunConfig) -> str:
    """`; truck 40000 kg; v_ref 85 km/h, band 80-90 km/h`."""
    cruise = config.cruise
    v_min, v_max = cruise.v_ref_kmh - cruise.v_dec_kmh, cruise.v_ref_kmh + cruise.v_inc_kmh
    truck = (
        f"{config.vehicle.mass_kg:.0f} kg"
        if config.truck is None
        else f"{config.truck.mass_kg:.0f} kg (VECTO {config.truck.job.path.name})"
    )
    return f"; truck {truck}; v_ref {cruise.v_ref_kmh:g} km/h, band {v_min:g}-{v_max:g} km/h"

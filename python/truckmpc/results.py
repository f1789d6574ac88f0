"""Run outputs: ``summary.json``, ``trace-<controller>.csv`` and the short table the CLI prints.

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
``_<controller>``. ``"comparisons"`` lists the same per look-ahead controller:
``[{"controller", "baseline", "delta_fuel_pct", "delta_time_pct", "delta_fuel_corrected_pct",
"delta_fuel_equal_time_pct", "delta_fuel_equal_time_corrected_pct", "not_comparable"?}, ...]``.
The end-speed correction and the equal-time search are :mod:`truckmpc.equal_time`'s.

The deltas follow the thesis (section 6.1): (x_mpc − x_pi) / x_pi in percent; they are null when a
run stalled or the baseline is zero (:func:`truckmpc.compare.compare`). All files of a run are
written through :class:`truckmpc.atomic.OutputDir`, so a failed run leaves nothing half-written.
"""

from __future__ import annotations

import io
import json
import math
import os
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from truckmpc.atomic import OutputDir
from truckmpc.compare import compare, delta_pct
from truckmpc.convergence import convergence_lines
from truckmpc.equal_time import EqualTime
from truckmpc.errors import ConfigError
from truckmpc.legs import stops_line
from truckmpc.sim import TRACE_COLUMNS, RunResult
from truckmpc.table import figure_lines, label_width
from truckmpc.units import M_PER_KM

if TYPE_CHECKING:
    from truckmpc.config import RunConfig
    from truckmpc.roads import RoadProfile

BASELINE = "pi"
"""The controller every other one is compared against."""

_CSV_FORMATS = {
    "distance_m": "%.3f",
    "time_s": "%.4f",
    "speed_kmh": "%.5f",
    "gear": "%d",
    "pedal": "%.6f",
    "brake": "%.6f",
    "engine_speed_rpm": "%.2f",
    "slope": "%.6f",
    "altitude_m": "%.4f",
    "fuel_g": "%.4f",
    "brake_energy_kj": "%.4f",
}


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
    pcc = results.get("pcc")
    for name in ("mpc", "optimal"):
        if pcc is not None and name in results:
            entry = _comparison(pcc, results[name], (equal_times or {}).get(f"{name}_vs_pcc"))
            comparisons.append({key: value for key, value in entry.items() if key != "equal_time"})
            doc[f"equal_time_{name}_vs_pcc"] = entry.get("equal_time")
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
        "delta_fuel_pct": comparison.delta_fuel_pct,
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
    """Δfuel [%] with both runs' end speeds corrected, and against the baseline at equal trip time
    (raw and corrected), with the ``equal_time`` object; null where the baseline did not reach the
    time."""
    doc: dict[str, Any] = {}
    if base.get("fuel_corrected_kg") is not None and run.get("fuel_corrected_kg") is not None:
        doc["delta_fuel_corrected_pct"] = delta_pct(run["fuel_corrected_kg"], base["fuel_corrected_kg"])
    if equal is None:
        return doc
    raw, corrected = equal.fuel_kg, equal.fuel_corrected_kg
    reached = equal.reached and raw is not None and corrected is not None
    own = run.get("fuel_corrected_kg")
    doc["delta_fuel_equal_time_pct"] = delta_pct(run["fuel_kg"], raw) if reached and raw else None
    doc["delta_fuel_equal_time_corrected_pct"] = (
        delta_pct(own, corrected) if reached and corrected and own is not None else None
    )
    doc["equal_time"] = equal.document(baseline)
    return doc


def _gap_to_optimal(mpc: Mapping[str, Any], optimal: Mapping[str, Any]) -> float | None:
    """How much more fuel the MPC burns than the whole-road optimum, in % of the optimum's fuel
    (None when either stalled)."""
    comparison = compare(optimal, mpc, "optimal", "mpc")
    return comparison.delta_fuel_pct


def trace_csv(result: RunResult) -> str:
    """The trace of one run as CSV text (header line, then one row per sample)."""
    columns = [c for c in TRACE_COLUMNS if c in result.trace] + [c for c in result.trace if c not in TRACE_COLUMNS]
    table = np.column_stack([np.asarray(result.trace[c], dtype=float) for c in columns])
    buffer = io.StringIO()
    np.savetxt(
        buffer,
        table,
        fmt=[_CSV_FORMATS.get(c, "%.6g") for c in columns],
        delimiter=",",
        header=",".join(columns),
        comments="",
    )
    return buffer.getvalue()


def _json_default(value: Any) -> Any:
    if isinstance(value, np.generic):
        return value.item()
    raise TypeError(f"not JSON-serialisable: {type(value).__name__}")


def _clean(value: Any) -> Any:
    """NaN and infinities are not JSON; write them as null."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {k: _clean(v) for k, v in value.items()}
    return value


RUN_FILES = ("summary.json", "trace-*.csv", "run.png", "run.svg")
"""What a run directory holds (its outputs and its plots); a new run replaces them all."""


def check_run_dir(out_dir: str | os.PathLike[str]) -> None:
    """Refuse an output directory that holds anything but an earlier run's files (which the new run
    replaces whole): it is someone's other data."""
    out = Path(out_dir)
    if out.exists() and not out.is_dir():
        raise ConfigError(f"{out}: expected a directory for the run's outputs, got a file")
    if not out.is_dir():
        return
    foreign = sorted(p.name for p in out.iterdir() if not any(p.match(pattern) for pattern in RUN_FILES))
    if foreign:
        shown = ", ".join(foreign[:3]) + (", ..." if len(foreign) > 3 else "")
        raise ConfigError(f"{out}: holds files that are not a truckmpc run's ({shown}); choose another --out")


def write_outputs(
    out_dir: str | os.PathLike[str],
    road: RoadProfile,
    results: Mapping[str, RunResult],
    run: Mapping[str, Any] | None = None,
    extra: Mapping[str, Any] | None = None,
    equal_times: Mapping[str, EqualTime] | None = None,
) -> list[Path]:
    """Write ``summary.json`` and one ``trace-<controller>.csv`` per run into ``out_dir``, all or
    nothing, replacing any earlier run there whole (see :func:`check_run_dir`). `extra` adds
    top-level objects to the summary (``convergence``).

    Returns the paths written.
    """
    out = Path(out_dir)
    check_run_dir(out)
    names = ["summary.json"] + [f"trace-{name}.csv" for name in results]
    with OutputDir(out, replace=True) as staging:
        doc = {**summary_document(road, results, run, equal_times), **(extra or {})}
        text = json.dumps(_clean(doc), indent=2, default=_json_default)
        (staging / "summary.json").write_text(text + "\n", encoding="utf-8")
        for name, result in results.items():
            (staging / f"trace-{name}.csv").write_text(trace_csv(result), encoding="utf-8")
    return [out / name for name in names]


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
    baseline = "pcc" if key.endswith("_vs_pcc") else "pi"
    moved = "target_offset_kmh" if f"{baseline}_target_offset_kmh" in equal else "v_ref_kmh"
    what, spec = ("target offset", "+14.2f") if moved == "target_offset_kmh" else ("v_ref", "14.2f")
    label = f"{key.replace('_vs_pcc', '').replace('_', ' ')} {baseline} {what} [km/h]"
    if "not_comparable" in equal:
        return f"{label}: {equal['not_comparable']}"
    value, time_s, runs = (equal[f"{baseline}_{k}"] for k in (moved, "time_s", "runs"))
    return f"{label:<{width}}{value:{spec}}  ({time_s:.1f} s, {runs} runs)"


def _setup(config: RunConfig) -> str:
    """`; truck 40000 kg; v_ref 85 km/h, band 80-90 km/h`."""
    cruise = config.cruise
    v_min, v_max = cruise.v_ref_kmh - cruise.v_dec_kmh, cruise.v_ref_kmh + cruise.v_inc_kmh
    return f"; truck {config.vehicle.mass_kg:.0f} kg; v_ref {cruise.v_ref_kmh:g} km/h, band {v_min:g}-{v_max:g} km/h"

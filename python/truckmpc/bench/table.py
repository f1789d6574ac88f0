"""The benchmark's result as a plain-text table, one column per run."""

from __future__ import annotations

from typing import Any

from truckmpc.bench.runs import BenchResult
from truckmpc.table import figure_lines, label_width
from truckmpc.units import M_PER_KM

__all__ = ["format_bench"]

_FIGURES = (
    ("realtime ratio", "realtime_ratio", "", ".2e"),
    ("solve time mean", "solve_ms_mean", "ms", ".3f"),
    ("solve time max", "solve_ms_max", "ms", ".3f"),
    ("solves", "solves", "", "d"),
    ("horizon solves", "horizon_solves", "", "d"),
    ("infeasible solves", "infeasible_solves", "", "d"),
    ("states per solve", "states_per_solve", "", ".0f"),
    ("transitions per solve", "transitions_per_solve", "", ".0f"),
    ("time per transition", "ns_per_transition", "ns", ".2f"),
    ("compute time", "compute_time_s", "s", ".2f"),
    ("simulated time", "time_s", "s", ".1f"),
    ("fuel", "fuel_kg", "kg", ".3f"),
    ("peak memory", "peak_rss_mb", "MB", ".1f"),
)


def _replan(run: dict[str, Any]) -> str:
    """How often the run solved its horizon: every stage, or every ``replan_m`` metres."""
    every_stage = run.get("replan_stages", 1) <= 1
    return "solve every stage" if every_stage else f"solve every {run['replan_m']:g} m"


def format_bench(result: BenchResult) -> str:
    """A plain-text table of :func:`run_bench`'s result, one column per case, its road's file (or
    the bundled test track) named first."""
    runs = result.runs
    lines = []
    roads = {(r["road"], r["path"]): r for r in runs}
    for (name, path), r in roads.items():
        where = f"{path or 'bundled'}" + ("; ../shared/roads not found" if r["fallback"] else "")
        lines.append(f"road {name}: {r['length_m'] / M_PER_KM:.2f} km, {where}")
    heads = [f"{r['case']}, {r['label']}" for r in runs]
    settings = [f"S {r['stage_m']:g} m, δ {r['delta_kmh']:g} km/h, {r['horizon_m']:g} m" for r in runs]
    settings = [f"{s}, {_replan(r)}" for s, r in zip(settings, runs, strict=True)]
    extra = [f"neutral {'allowed' if r['allow_neutral'] else 'off'}, {r['grid']} grid" for r in runs]
    cell = max(len(h) for h in [*heads, *settings, *extra]) + 3
    width = label_width(_FIGURES)
    for row in (heads, settings, extra):
        lines.append(" " * width + "".join(f"{h:>{cell}}" for h in row))
    lines += figure_lines(_FIGURES, runs, cell)
    for r in runs:
        if r.get("stalled"):
            lines.append(f"{r['case']} on {r['road']}: the truck stalled; figures cover the road up to there")
    return "\n".join(lines)

"""The real-time benchmark: closed-loop MPC runs on fixed, named roads at fixed settings.

Each case (:data:`CASES`) drives a whole road with the MPC (:func:`truckmpc.sim.simulate`) in a fresh
Python process, so its peak resident memory is its own:

- the default controller at its own settings on the EU VECTO long-haul road (108 km) and on the
  Swedish E6/E20 motorway (294 km): what users run;
- the thesis's worst case, S 25 m, δ 0.1 km/h, 3000 m horizon, neutral allowed, fixed grid, on the
  VECTO road.

The roads are ``../shared/roads/`` beside the repository checkout (or the working directory), else
the bundled test track; ``--road`` drives every case on one road instead, and ``--quick`` keeps the
first 10 km of each. Figures per run (from the run's summary, but for the last two):

- ``realtime_ratio``: wall time of the run / simulated trip time;
- ``solve_ms_mean``, ``solve_ms_max``, ``solves`` (one per stage), ``horizon_solves`` (those over the
  whole horizon; the others decide a stage from the last one's stored cost-to-go),
  ``states_per_solve``, ``transitions_per_solve``;
- ``ns_per_transition``: mean solve time / transitions per solve;
- ``peak_rss_mb``: the run's process peak resident set [MB], Python and numpy included.

Nothing here asserts a time: the figures are printed for people and CI to read.

Usage: ``truckmpc bench [--json] [--road FILE] [--quick] [--set key=value ...]``.
"""

from __future__ import annotations

import json
import resource
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from truckmpc.config import load_run_config
from truckmpc.errors import TruckmpcError
from truckmpc.roads import RoadProfile, default_test_track, load_road
from truckmpc.sim import simulate
from truckmpc.table import figure_lines, label_width
from truckmpc.units import M_PER_KM

__all__ = [
    "CASES",
    "SETTINGS",
    "BenchError",
    "BenchResult",
    "format_bench",
    "run_bench",
    "shared_road_path",
]

SETTINGS: dict[str, Any] = {
    "stage_m": 25.0,
    "delta_kmh": 0.1,
    "horizon_m": 3000.0,
    "replan_m": 0.0,
    "allow_neutral": True,
    "grid": "fixed",
}
"""The thesis's worst case: the settings its row fixes (every other key keeps its configured value)."""

SHARED_ROADS = Path("..") / "shared" / "roads"
"""Where the benchmark's roads are, relative to the repository root (or the working directory)."""

CASES: tuple[dict[str, Any], ...] = (
    {"case": "default", "road": "eu_vecto_longhaul_2015_108km.csv", "label": "VECTO 108 km", "settings": {}},
    {"case": "default", "road": "se_E6_E20_goteborg_malmo_volvo_chalmers.csv", "label": "SE E6/E20", "settings": {}},
    {
        "case": "thesis worst case",
        "road": "eu_vecto_longhaul_2015_108km.csv",
        "label": "VECTO 108 km",
        "settings": SETTINGS,
    },
)
"""The benchmark's runs, in order: the default controller at its own settings on two roads, then the
thesis's worst case."""

QUICK_M = 10_000.0
"""``--quick`` drives the first this many metres of the road [m]."""


class BenchError(TruckmpcError):
    """A benchmark run failed (its process ended with an error)."""


def shared_road_path(name: str) -> Path | None:
    """The road `name` of ``../shared/roads/`` beside the repository checkout of this package, or
    beside the working directory; None when neither exists."""
    checkout = Path(__file__).resolve().parents[2]
    roots = [checkout] if (checkout / "pyproject.toml").is_file() else []
    roots.append(Path.cwd())
    for root in roots:
        path = (root / SHARED_ROADS / name).resolve()
        if path.is_file():
            return path
    return None


def _first(profile: RoadProfile, length_m: float) -> RoadProfile:
    """The first ``length_m`` metres of a road (all of it if shorter), named ``<name>-first<N>km``."""
    start = float(profile.distance_m[0])
    if profile.length_m <= length_m:
        return profile
    end = start + length_m
    keep = profile.distance_m < end
    distance = np.append(profile.distance_m[keep], end)
    altitude = np.append(profile.altitude_m[keep], np.interp(end, profile.distance_m, profile.altitude_m))
    return RoadProfile(f"{profile.name}-first{length_m / M_PER_KM:g}km", distance, altitude, profile.source)


def _road(path: str | None, quick: bool) -> RoadProfile:
    profile = default_test_track() if path is None else load_road(path)
    return _first(profile, QUICK_M) if quick else profile


def _overrides(setting: dict[str, Any], extra: tuple[str, ...]) -> list[str]:
    fixed = [
        f"{key}={'true' if value is True else 'false' if value is False else value}" for key, value in setting.items()
    ]
    return [*extra, *fixed]


def _peak_rss_mb() -> float:
    """This process's peak resident set [MB = 1e6 bytes] (ru_maxrss is KiB on Linux, bytes on macOS)."""
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return (peak if sys.platform == "darwin" else peak * 1024) / 1e6


def run_one(road_path: str | None, quick: bool, setting: dict[str, Any], extra: tuple[str, ...] = ()) -> dict[str, Any]:
    """One closed-loop MPC run in this process; the figures of :func:`run_bench`'s runs, with the
    settings the run resolved to (a default row's are the configured ones)."""
    config = load_run_config(overrides=_overrides(setting, extra))
    profile = _road(road_path, quick)
    summary = simulate(profile, config, "mpc").summary
    transitions = summary["transitions_per_solve"]
    mpc = config.mpc
    return {
        "road": profile.name,
        "length_m": profile.length_m,
        "stage_m": mpc.stage_m,
        "delta_kmh": mpc.delta_kmh,
        "horizon_m": mpc.horizon_m,
        "replan_m": mpc.replan_m,
        "replan_stages": config.settings.replan_stages,
        "allow_neutral": mpc.allow_neutral,
        "grid": mpc.grid,
        "neutral_rule": config.mpc.neutral_rule,
        "realtime_ratio": summary["realtime_ratio"],
        "solve_ms_mean": summary["solve_ms_mean"],
        "solve_ms_max": summary["solve_ms_max"],
        "solves": summary["solves"],
        "horizon_solves": summary["horizon_solves"],
        "infeasible_solves": summary["infeasible_solves"],
        "states_per_solve": summary["states_per_solve"],
        "transitions_per_solve": transitions,
        "ns_per_transition": summary["solve_ms_mean"] * 1e6 / transitions if transitions else None,
        "compute_time_s": summary["compute_time_s"],
        "time_s": summary["time_s"],
        "distance_m": summary["distance_m"],
        "fuel_kg": summary["fuel_kg"],
        "stalled": summary["stalled"],
        "peak_rss_mb": _peak_rss_mb(),
    }


def _spawn(road_path: str | None, quick: bool, setting: dict[str, Any], extra: tuple[str, ...]) -> dict[str, Any]:
    """:func:`run_one` in a fresh interpreter (``python -m truckmpc.bench --one SPEC``)."""
    spec = json.dumps({"road": road_path, "quick": quick, "setting": setting, "set": list(extra)})
    done = subprocess.run(
        [sys.executable, "-m", "truckmpc.bench", "--one", spec], capture_output=True, text=True, check=False
    )
    if done.returncode != 0:
        lines = [line for line in done.stderr.splitlines() if line.strip()]
        why = lines[-1].removeprefix("error: ") if lines else f"exit code {done.returncode}"
        raise BenchError(f"benchmark run {setting}: {why}")
    figures: dict[str, Any] = json.loads(done.stdout.splitlines()[-1])
    return figures


@dataclass(frozen=True)
class BenchResult:
    """What :func:`run_bench` measured: one figures dict per case, each with its ``case``
    (``default`` or ``thesis worst case``), its ``road`` (name, with ``-first10km`` under
    ``--quick``) and ``label`` (short, for tables), ``path`` (None for the bundled test track) and
    ``fallback`` (True when the case's road was not found and the test track was driven)."""

    runs: list[dict[str, Any]]

    def document(self) -> dict[str, Any]:
        """The ``--json`` document: ``{"runs": [...]}``."""
        return {"runs": self.runs}


def run_bench(road: str | Path | None = None, quick: bool = False, overrides: tuple[str, ...] = ()) -> BenchResult:
    """Run every case of :data:`CASES`, each in its own process.

    Parameters
    ----------
    road
        Road CSV for every case; None: each case's road of ``../shared/roads/`` if found
        (:func:`shared_road_path`), else the bundled test track.
    quick
        Drive only the first 10 km of each road.
    overrides
        Further ``key=value`` settings (e.g. ``neutral_rule=interpolate``), for every case; the
        keys the worst case fixes (:data:`SETTINGS`) are refused.
    """
    for text in overrides:
        key = text.partition("=")[0].strip()
        if key in SETTINGS:
            raise BenchError(f"--set {key}: the benchmark fixes {', '.join(sorted(SETTINGS))}; set other keys only")
    load_run_config(overrides=overrides)  # report a bad --set once, here, rather than from a child
    runs = []
    for case in CASES:
        found = shared_road_path(case["road"]) if road is None else Path(road)
        path = None if found is None else str(found)
        figures = _spawn(path, quick, case["settings"], tuple(overrides))
        label = case["label"] if road is None and found is not None else figures["road"]
        label += " (first 10 km)" if quick and label == case["label"] else ""
        runs.append(
            {"case": case["case"], "label": label, "path": path, "fallback": road is None and found is None, **figures}
        )
    return BenchResult(runs)


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


def _child(argv: list[str]) -> int:
    """``python -m truckmpc.bench --one SPEC``: one run, its figures as one JSON line on stdout."""
    if len(argv) != 2 or argv[0] != "--one":
        print("usage: python -m truckmpc.bench --one SPEC  (internal; use `truckmpc bench`)", file=sys.stderr)
        return 2
    spec = json.loads(argv[1])
    try:
        figures = run_one(spec["road"], spec["quick"], spec["setting"], tuple(spec["set"]))
    except TruckmpcError as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    print(json.dumps(figures))
    return 0


if __name__ == "__main__":
    sys.exit(_child(sys.argv[1:]))

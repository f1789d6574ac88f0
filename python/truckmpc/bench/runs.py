"""The benchmark's cases and runs: each case drives a whole road with the MPC in a fresh Python
process (``python -m truckmpc.bench --one SPEC``), so its peak resident memory is its own."""

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
from truckmpc.units import M_PER_KM

__all__ = [
    "CASES",
    "SETTINGS",
    "BenchError",
    "BenchResult",
    "cases_to_run",
    "run_bench",
    "run_one",
    "shared_path",
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

SHARED = Path("..") / "shared"
"""Where the benchmark's roads and trucks are, relative to the repository root (or the working
directory): ``roads/`` and ``vehicles/`` in it."""

TRACTOR = "vehicles/vecto-generic-class5-tractor/Class5_Tractor_DECL.xml"
"""VECTO's generic long-haul tractor (its declaration XML, with its loss maps and retarder), within
:data:`SHARED`."""

VECTO_108 = "roads/eu_vecto_longhaul_2015_108km.csv"
SE = "roads/se_E6_E20_goteborg_malmo_volvo_chalmers.csv"

CASES: tuple[dict[str, Any], ...] = (
    {"case": "default", "road": VECTO_108, "label": "VECTO 108 km", "settings": {}},
    {"case": "default", "road": SE, "label": "SE E6/E20", "settings": {}},
    {"case": "thesis worst case", "road": VECTO_108, "label": "VECTO 108 km", "settings": SETTINGS},
    {"case": "default, VECTO tractor", "road": VECTO_108, "label": "VECTO 108 km", "settings": {}, "vehicle": TRACTOR},
)
"""The benchmark's runs, in order: the default controller at its own settings on two roads, the
thesis's worst case, and the default with VECTO's generic tractor (run only where its files are
found: a map-based truck evaluates its maps where the thesis's truck has closed forms)."""

QUICK_M = 10_000.0
"""``--quick`` drives the first this many metres of the road [m]."""


class BenchError(TruckmpcError):
    """A benchmark run failed (its process ended with an error)."""


def shared_path(name: str) -> Path | None:
    """The file `name` (``roads/…`` or ``vehicles/…``) of ``../shared/`` beside the repository
    checkout of this package, or beside the working directory; None when neither exists."""
    checkout = Path(__file__).resolve().parents[3]
    roots = [checkout] if (checkout / "pyproject.toml").is_file() else []
    roots.append(Path.cwd())
    for root in roots:
        path = (root / SHARED / name).resolve()
        if path.is_file():
            return path
    return None


def cases_to_run() -> list[dict[str, Any]]:
    """The cases :func:`run_bench` runs: those of :data:`CASES` whose truck is found (the packaged
    truck always is)."""
    return [case for case in CASES if "vehicle" not in case or shared_path(case["vehicle"]) is not None]


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


def run_one(
    road_path: str | None,
    quick: bool,
    setting: dict[str, Any],
    extra: tuple[str, ...] = (),
    vehicle_path: str | None = None,
) -> dict[str, Any]:
    """One closed-loop MPC run in this process (the packaged truck, or the VECTO job or vehicle
    file `vehicle_path`); the figures of :func:`run_bench`'s runs, with the settings the run
    resolved to (a default row's are the configured ones)."""
    config = load_run_config(vehicle_path, overrides=_overrides(setting, extra))
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
        "replan_stages": config.settings.derived()["replan_stages"],
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


def _spawn(
    road_path: str | None, quick: bool, setting: dict[str, Any], extra: tuple[str, ...], vehicle: str | None
) -> dict[str, Any]:
    """:func:`run_one` in a fresh interpreter (``python -m truckmpc.bench --one SPEC``)."""
    spec = json.dumps({"road": road_path, "quick": quick, "setting": setting, "set": list(extra), "vehicle": vehicle})
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
    (``default``, ``thesis worst case`` or ``default, VECTO tractor``), its ``road`` (name, with ``-first10km`` under
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
        (:func:`shared_path`), else the bundled test track.
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
    for case in cases_to_run():
        vehicle = shared_path(case["vehicle"]) if "vehicle" in case else None
        found = shared_path(case["road"]) if road is None else Path(road)
        path = None if found is None else str(found)
        figures = _spawn(path, quick, case["settings"], tuple(overrides), None if vehicle is None else str(vehicle))
        label = case["label"] if road is None and found is not None else figures["road"]
        label += " (first 10 km)" if quick and label == case["label"] else ""
        runs.append(
            {"case": case["case"], "label": label, "path": path, "fallback": road is None and found is None, **figures}
        )
    return BenchResult(runs)

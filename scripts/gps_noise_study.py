"""The GPS noise study (issue 15, item 3): per road, altitude noise and smoothing, the grade RMS error
of the imported road against the true one [percentage points] and the error of the MPC's Δfuel
(against the PI) on the imported road [points], over several seeded tracks (truckmpc.geo.study).

    python scripts/gps_noise_study.py [--road FILE ...] [--km A-B] [--sigmas 0,2,5]
        [--methods spline,savgol] [--noise-m 2] [--seeds 3] [--kind markov] [--set key=value ...]

Default roads: the VECTO long-haul 100 km and the US EPA 20 km profiles from ../shared/roads (or
$TRUCKMPC_SHARED_ROADS). Prints a Markdown table: mean and range over the seeds.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from study_roads import default_road_paths, road_part

from truckmpc.config import load_run_config
from truckmpc.geo.study import StudyRow, study_rows
from truckmpc.geo.synthetic import NOISE_KINDS
from truckmpc.roads import load_road
from truckmpc.roads.gps.smooth import Smoothing


def _arguments() -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--road", type=Path, action="append", help="road CSV with the true altitude; repeatable")
    parser.add_argument("--km", default=None, help="only the part A-B [km] of each road, e.g. 0-10")
    parser.add_argument("--sigmas", default="0,2,5", help="altitude noise std values [m], comma-separated")
    parser.add_argument("--methods", default="spline,savgol", help="smoothing methods, comma-separated")
    parser.add_argument("--noise-m", type=float, default=2.0, help="noise std the import assumes [m] (--noise-m)")
    parser.add_argument("--smooth-m", type=float, default=None, help="smoothing length [m] instead (--smooth-m)")
    parser.add_argument("--seeds", type=int, default=3, help="tracks per noise level (seeds 1..N)")
    parser.add_argument("--kind", choices=sorted(NOISE_KINDS), default="markov", help="altitude noise process")
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="configuration override")
    return parser.parse_args()


def _range(values: tuple[float | None, ...]) -> str:
    known = [v for v in values if v is not None]
    if not known:
        return "stalled"
    return f"{sum(known) / len(known):+.2f} ({min(known):+.2f} to {max(known):+.2f})"


def _line(row: StudyRow) -> str:
    grades = f"{sum(row.grade_rms_pct) / len(row.grade_rms_pct):.2f} (max {max(row.grade_rms_pct):.2f})"
    smoothing = f"{row.smoothing.method} {row.smoothing.length_m:g} m"
    return f"| {row.road} | {row.sigma_m:g} | {smoothing} | {grades} | {_range(row.delta_fuel_error_pct)} |"


def main() -> None:
    args = _arguments()
    config = load_run_config(overrides=tuple(args.set))
    sigmas_m = [float(x) for x in args.sigmas.split(",")]
    methods = args.methods.split(",")
    smoothings = [
        Smoothing.for_noise(m, args.noise_m) if args.smooth_m is None else Smoothing(m, args.smooth_m) for m in methods
    ]
    print(f"noise: {args.kind}, correlation 100 m, jitter 2 m per axis (none at sigma 0); seeds 1..{args.seeds}")
    print("| road | sigma [m] | smoothing | grade RMS error [pp] | delta-fuel error [points] |")
    print("|---|---|---|---|---|")
    for path in args.road or default_road_paths():
        road = road_part(load_road(path), args.km)
        rows = study_rows(road, config, sigmas_m, smoothings, range(1, args.seeds + 1), args.kind)
        for i, row in enumerate(rows):
            if i == 0:
                clean = "stalled" if row.clean_delta_fuel_pct is None else f"{row.clean_delta_fuel_pct:+.2f} %"
                print(f"| {road.name} | true road | | | delta-fuel MPC vs PI: {clean} |")
            print(_line(row), flush=True)


if __name__ == "__main__":
    main()

"""Write the noise test's GPS tracks: a road's altitude laid along a synthetic path, with GPS-like
noise (truckmpc.geo.synthetic), as GPX files. Deterministic for a given seed.

    python scripts/make_gps_fixtures.py ROAD.csv OUT_DIR [--sigmas 0,2,5] [--seed 1] [--km A-B] [--kind markov]

The tests make the same tracks in temporary directories (nothing is kept in the repository).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from study_roads import road_part

from truckmpc.geo.synthetic import NOISE_KINDS, write_fixtures
from truckmpc.roads import load_road


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("road", type=Path, help="road CSV with the true altitude (e.g. ../shared/roads/...)")
    parser.add_argument("out_dir", type=Path, help="directory for the GPX files")
    parser.add_argument("--sigmas", default="0,2,5", help="altitude noise std values [m], comma-separated")
    parser.add_argument("--seed", type=int, default=1, help="random seed")
    parser.add_argument("--km", default=None, help="only the part A-B [km] of the road, e.g. 0-10")
    parser.add_argument("--kind", choices=sorted(NOISE_KINDS), default="markov", help="altitude noise process")
    args = parser.parse_args()
    road = road_part(load_road(args.road), args.km)
    sigmas_m = [float(x) for x in args.sigmas.split(",")]
    for path in write_fixtures(road, args.out_dir, sigmas_m, args.seed, args.kind):
        print(f"wrote {path}")


if __name__ == "__main__":
    main()

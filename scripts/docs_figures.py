"""Draw the figures of the README and the documentation site (docs/images/*.png) from real runs.

    python scripts/docs_figures.py [--out docs/images]

Each figure is a `truckmpc simulate` run followed by `truckmpc plot`, run as a user would type them,
so a figure always shows what the commands draw today. Needs matplotlib (pip install '.[plot]').

- vecto108-pi-pcc-mpc.png (README, getting started): the PI, VECTO's PCC and the default MPC on
  the EU VECTO long-haul road (108 km, ../shared/roads beside the checkout), the 40 t truck.
- thesis-fig6-*.png (docs/validation/thesis.md): the `thesis` preset at the settings of the
  thesis's detail study (table 6.1: 1000 m horizon, S 25 m, δ 0.2 km/h, 40 t, 85 km/h) against the
  PI on the thesis's artificial sections in roads/, one figure per section of chapter 6.
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
SHARED_ROADS = REPO.parent / "shared" / "roads"
DETAIL = ["--config", "thesis", "--set", "horizon_m=1000"]
NEAREST = ["--set", "neutral_rule=nearest"]
# image name, road file, options
FIGURES: list[tuple[str, Path, list[str]]] = [
    ("vecto108-pi-pcc-mpc.png", SHARED_ROADS / "eu_vecto_longhaul_2015_108km.csv", ["--controller", "pi,pcc,mpc"]),
    ("thesis-fig6-3-ascent.png", REPO / "roads" / "hill_L500_A3.5.csv", DETAIL),
    ("thesis-fig6-5-short-descent.png", REPO / "roads" / "hill_L300_A-3.csv", DETAIL + NEAREST),
    ("thesis-fig6-6-descent.png", REPO / "roads" / "hill_L500_A-3.csv", DETAIL),
    ("thesis-fig6-9-crest.png", REPO / "roads" / "crest_L1500_A2.csv", DETAIL + NEAREST),
    ("thesis-fig6-10-depression.png", REPO / "roads" / "depression_L1500_A2.csv", DETAIL + NEAREST),
]


def draw(image: Path, road: Path, options: list[str]) -> None:
    """Simulate on `road` with `options` and keep the run's figure as `image`."""
    if not road.is_file():
        sys.exit(f"{road}: not found (the shared roads belong at ../shared/roads beside the checkout)")
    with tempfile.TemporaryDirectory() as run:
        subprocess.run(
            ["truckmpc", "simulate", "--road", str(road), *options, "--out", run], check=True, stdout=subprocess.DEVNULL
        )
        subprocess.run(["truckmpc", "plot", run], check=True, stdout=subprocess.DEVNULL)
        shutil.copyfile(Path(run) / "run.png", image)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", type=Path, default=REPO / "docs" / "images", help="directory of the images")
    out = parser.parse_args().out
    out.mkdir(parents=True, exist_ok=True)
    for name, road, options in FIGURES:
        draw(out / name, road, options)
        print(out / name)


if __name__ == "__main__":
    main()

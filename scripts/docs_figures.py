"""Draw the figures of the validation pages (docs/images/*.png) with `truckmpc simulate` and `truckmpc plot`.

    python scripts/docs_figures.py [--out docs/images]

The thesis reproduction (docs/validation/thesis.md): the `thesis` preset at the settings of the
thesis's detail study (table 6.1: 1000 m horizon, S 25 m, δ 0.2 km/h, 40 t, 85 km/h) against the PI
on the thesis's artificial sections in roads/, one figure per section of chapter 6.
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import tempfile
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
DETAIL = ["--config", "thesis", "--set", "horizon_m=1000"]
NEAREST = ["--set", "neutral_rule=nearest"]
# image name, road under roads/, options beyond the detail study's
FIGURES: list[tuple[str, str, list[str]]] = [
    ("thesis-fig6-3-ascent.png", "hill_L500_A3.5.csv", []),
    ("thesis-fig6-5-short-descent.png", "hill_L300_A-3.csv", NEAREST),
    ("thesis-fig6-6-descent.png", "hill_L500_A-3.csv", []),
    ("thesis-fig6-9-crest.png", "crest_L1500_A2.csv", NEAREST),
    ("thesis-fig6-10-depression.png", "depression_L1500_A2.csv", NEAREST),
]


def draw(image: Path, road: str, options: list[str]) -> None:
    """Drive PI and MPC on one road and keep the run's figure as `image`."""
    with tempfile.TemporaryDirectory() as run:
        subprocess.run(
            ["truckmpc", "simulate", "--road", str(REPO / "roads" / road), *DETAIL, *options, "--out", run],
            check=True,
            stdout=subprocess.DEVNULL,
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

"""Make the figures of the README and the documentation site (docs/images/), from real runs.

Usage: python scripts/docs_figures.py [OUT_DIR]
(default: docs/images). Needs the shared roads at ../shared/roads (beside the checkout) and
matplotlib (pip install '.[plot]').

Each figure is a `truckmpc simulate` run followed by `truckmpc plot`, driven through the command
line exactly as a user would type it, so a figure always shows what the commands draw today:

- vecto108-pi-pcc-mpc.png: the PI, VECTO's PCC and the look-ahead MPC on the EU VECTO long-haul
  road (108 km), the 40 t truck at the defaults.
"""

from __future__ import annotations

import shutil
import sys
import tempfile
from pathlib import Path

from truckmpc.cli import app

REPO = Path(__file__).resolve().parents[1]
SHARED_ROADS = REPO.parent / "shared" / "roads"

# figure name -> (road file under ../shared/roads, controllers)
FIGURES = {
    "vecto108-pi-pcc-mpc.png": ("eu_vecto_longhaul_2015_108km.csv", "pi,pcc,mpc"),
}


def truckmpc(*args: str) -> None:
    """Run one `truckmpc` command in this process; stop the script if it fails."""
    print("truckmpc", " ".join(args), flush=True)
    try:
        app(list(args), prog_name="truckmpc")
    except SystemExit as done:
        if done.code not in (0, None):
            sys.exit(f"truckmpc {args[0]} failed (exit {done.code})")


def make_figure(name: str, road_file: str, controllers: str, out_dir: Path) -> Path:
    """Simulate `controllers` on a shared road and plot the run to out_dir/name."""
    road = SHARED_ROADS / road_file
    if not road.is_file():
        sys.exit(f"{road}: not found (the shared roads belong at ../shared/roads beside the checkout)")
    with tempfile.TemporaryDirectory() as tmp:
        run_dir = Path(tmp) / "run"
        truckmpc("simulate", "--road", str(road), "--controller", controllers, "--out", str(run_dir))
        truckmpc("plot", str(run_dir), "--out", str(Path(tmp) / name))
        target = out_dir / name
        shutil.copyfile(Path(tmp) / name, target)
    return target


def main() -> None:
    out_dir = Path(sys.argv[1]) if len(sys.argv) > 1 else REPO / "docs" / "images"
    out_dir.mkdir(parents=True, exist_ok=True)
    for name, (road_file, controllers) in FIGURES.items():
        print("wrote", make_figure(name, road_file, controllers, out_dir))


if __name__ == "__main__":
    main()

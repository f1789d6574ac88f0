"""``truckmpc plot``: :func:`truckmpc.plot.plot_dir` on a run or sweep directory."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from truckmpc.plot import plot_dir

__all__ = ["plot_cmd"]


def plot_cmd(
    directory: Annotated[
        Path,
        typer.Argument(
            metavar="DIR",
            help="A run directory (summary.json, trace-*.csv), a sweep directory (sweep.csv) or a Pareto directory "
            "(pareto.csv).",
        ),
    ],
    svg: Annotated[bool, typer.Option("--svg", help="Also write an SVG beside every PNG.")] = False,
    out: Annotated[
        Path | None,
        typer.Option("--out", metavar="PATH", help="Output directory, or a .png/.svg file name (default: DIR)."),
    ] = None,
) -> None:
    """Plot a run (DIR/run.png: altitude, speed, gear, pedal, brake over distance), a sweep
    (DIR/sweep.png: delta fuel, raw and at equal trip time, and delta time against the swept
    parameter; DIR/realtime.png) or a Pareto study (DIR/pareto.png). Needs matplotlib."""
    written = plot_dir(directory, out=out, svg=svg)
    typer.echo("wrote " + ", ".join(str(p) for p in written))

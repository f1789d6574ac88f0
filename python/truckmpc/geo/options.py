"""Command-line options of ``truckmpc road import|info|plot``, kept free of heavy imports (scipy,
pyproj, gpxpy) so that the ``truckmpc`` command starts fast; the import's defaults are
:mod:`truckmpc.roads.gps`'s, named here too for the command line."""

from __future__ import annotations

import enum
from pathlib import Path
from typing import Annotated

import typer

from truckmpc.roads.gps import DEFAULT_GRADE_LIMIT_PCT, DEFAULT_NOISE_M

__all__ = [
    "DEFAULT_GRADE_LIMIT_PCT",
    "DEFAULT_NOISE_M",
    "GradeLimitOpt",
    "Method",
    "MethodOpt",
    "NoiseOpt",
    "OutputOpt",
    "RoadFileArg",
    "SmoothOpt",
    "StepOpt",
    "TrackArg",
]


class Method(enum.StrEnum):
    """Elevation smoothing methods (:mod:`truckmpc.roads.gps.smooth`)."""

    spline = "spline"
    savgol = "savgol"
    none = "none"


TrackArg = Annotated[Path, typer.Argument(metavar="FILE", help="The track file.")]
OutputOpt = Annotated[Path, typer.Option("-o", "--output", help="Road CSV to write.")]
MethodOpt = Annotated[Method, typer.Option("--method", help="Elevation smoothing: spline (default), savgol or none.")]
NoiseOpt = Annotated[
    float,
    typer.Option(
        "--noise-m", min=0.0, help="Expected std of the elevations [m]; sets the smoothing length (0: no smoothing)."
    ),
]
SmoothOpt = Annotated[
    float | None,
    typer.Option(
        "--smooth-m", min=0.0, help="Smoothing length [m] (spline bandwidth, savgol window); overrides --noise-m."
    ),
]
StepOpt = Annotated[
    float | None,
    typer.Option(
        "--step-m", help="Resampling step [m], no finer than the track's point spacing (default: that spacing)."
    ),
]
GradeLimitOpt = Annotated[
    float, typer.Option("--grade-limit-pct", min=0.0, help="Report grades steeper than this [%] (never clipped).")
]
RoadFileArg = Annotated[Path, typer.Argument(metavar="FILE", help="A road CSV or a GPX track.")]

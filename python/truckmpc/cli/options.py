"""The options several ``truckmpc`` commands share, declared once: their names, metavars and help
texts, and the configuration they make together (``--vehicle``, ``--config``, ``--set``)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from truckmpc.config import RunConfig, load_run_config
from truckmpc.config.keys import preset_names
from truckmpc.geo.options import Method

__all__ = [
    "CONFIG_HELP",
    "ConfigOpt",
    "ForceOpt",
    "GradeLimitOpt",
    "JobsOpt",
    "MethodOpt",
    "NoiseOpt",
    "QuietOpt",
    "ReverseAllOpt",
    "RoadFileArg",
    "RoadOutputOpt",
    "RoadsOpt",
    "SchedulerOpt",
    "SetOpt",
    "SmoothOpt",
    "StepOpt",
    "TrackArg",
    "VehicleOpt",
    "run_config_from",
]

VehicleOpt = Annotated[
    Path | None,
    typer.Option(
        "--vehicle",
        metavar="FILE",
        help="Vehicle: a YAML file (default: the packaged 40 t truck, truck-40t.yaml), a VECTO job (.vecto) or "
        "a VECTO declaration (.xml).",
    ),
]
CONFIG_HELP = (
    "Controller/simulation YAML overlay, or a packaged preset by name: "
    f"{', '.join(preset_names())}; repeatable, later ones win."
)
"""The help of ``--config``, naming the packaged presets (configs/presets/*.yaml)."""
ConfigOpt = Annotated[list[Path] | None, typer.Option("--config", metavar="FILE|PRESET", help=CONFIG_HELP)]
SetOpt = Annotated[
    list[str] | None,
    typer.Option(
        "--set",
        metavar="KEY=VALUE",
        help="Override any vehicle, controller or simulation key (listed with their units by truckmpc config "
        "keys), the value in the key's unit; repeatable.",
    ),
]
ForceOpt = Annotated[
    bool, typer.Option("--force", help="Run even when the estimated work is beyond an hour (refused otherwise).")
]

# Studies over many roads (sweep, pareto).
RoadsOpt = Annotated[
    list[Path],
    typer.Option(
        "--road",
        metavar="FILE",
        help="Road profile CSV, VECTO .vdri cycle or GPS track (.gpx), a directory of them, or a glob (quoted); "
        "repeatable.",
    ),
]
ReverseAllOpt = Annotated[bool, typer.Option("--reverse", help="Drive every road in the opposite direction.")]
JobsOpt = Annotated[
    int | None,
    typer.Option(
        "--jobs",
        min=1,
        metavar="N",
        help="Worker processes of the embedded Dask cluster (default: all cores); 1 runs in-process.",
    ),
]
SchedulerOpt = Annotated[
    str | None,
    typer.Option(
        "--scheduler",
        metavar="ADDRESS",
        envvar="TRUCKMPC_SCHEDULER",
        help="Send the runs to the running Dask cluster whose scheduler is at ADDRESS (tcp://host:8786) "
        "instead of starting one here.",
    ),
]
QuietOpt = Annotated[bool, typer.Option("--quiet", help="No progress bar.")]

# Road files (road import, info, plot); the defaults are truckmpc.geo.options's.
TrackArg = Annotated[Path, typer.Argument(metavar="FILE", help="The track file to import.")]
RoadOutputOpt = Annotated[Path, typer.Option("-o", "--output", metavar="FILE", help="Road CSV to write.")]
MethodOpt = Annotated[Method, typer.Option("--method", help=f"Elevation smoothing: {', '.join(Method)}.")]
NoiseOpt = Annotated[
    float,
    typer.Option(
        "--noise-m",
        min=0.0,
        metavar="M",
        help="Expected std of the elevations [m]; sets the smoothing length (0: no smoothing).",
    ),
]
SmoothOpt = Annotated[
    float | None,
    typer.Option(
        "--smooth-m",
        min=0.0,
        metavar="M",
        help="Smoothing length [m] (spline bandwidth, savgol window); overrides --noise-m (default: from it).",
    ),
]
StepOpt = Annotated[
    float | None,
    typer.Option(
        "--step-m",
        metavar="M",
        help="Resampling step [m], no finer than the track's point spacing (default: that spacing).",
    ),
]
GradeLimitOpt = Annotated[
    float,
    typer.Option(
        "--grade-limit-pct", min=0.0, metavar="PCT", help="Report grades steeper than this [%] (never clipped)."
    ),
]
RoadFileArg = Annotated[Path, typer.Argument(metavar="FILE", help="A road CSV or a GPX track.")]


def run_config_from(vehicle: Path | None, config: list[Path] | None, set_: list[str] | None) -> RunConfig:
    """The configuration from ``--vehicle``, ``--config`` and ``--set``."""
    return load_run_config(vehicle_path=vehicle, config_paths=tuple(config or ()), overrides=tuple(set_ or ()))

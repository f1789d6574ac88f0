"""``truckmpc robustness``: :func:`truckmpc.robustness.study` on one road, printed as a table and
optionally written as JSON."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer

from truckmpc import robustness
from truckmpc.atomic import atomic_write_text
from truckmpc.cli.options import ConfigOpt, SetOpt, VehicleOpt, run_config_from
from truckmpc.roads import load_road
from truckmpc.signals import stopping_on_signals
from truckmpc.status import status_line

__all__ = ["STUDIED", "robustness_cmd"]

STUDIED = ("mpc", "optimal", "pcc")
"""The look-ahead controllers ``robustness --controller`` takes."""


def robustness_cmd(
    road: Annotated[
        Path,
        typer.Option(
            "--road", metavar="FILE", help="Road profile CSV, VECTO .vdri cycle or GPS track (.gpx) the truck drives."
        ),
    ],
    controller: Annotated[
        str,
        typer.Option("--controller", metavar="NAME", help=f"The look-ahead controller studied: {', '.join(STUDIED)}."),
    ] = STUDIED[0],
    seeds: Annotated[
        int, typer.Option("--seeds", min=1, metavar="N", help="Noisy maps (random seeds) per grade-noise level.")
    ] = 2,
    vehicle: VehicleOpt = None,
    config: ConfigOpt = None,
    set_: SetOpt = None,
    out: Annotated[
        Path | None, typer.Option("--out", metavar="FILE", help="Also write the rows to this JSON file.")
    ] = None,
) -> None:
    """How much of the controller's saving survives a mass it does not know (+-25 %) and a map with
    grade noise (sigma 0.2, 0.5, 1 %): each case against the PI on the true truck and road.

    A VECTO truck's other masses are its payload changed (no lighter than empty); a battery-electric
    truck's table is of battery energy.
    """
    if controller not in STUDIED:
        raise typer.BadParameter(
            f"expected one of {', '.join(STUDIED)}, got {controller!r}", param_hint="'--controller'"
        )
    run_config = run_config_from(vehicle, config, set_)
    profile = load_road(road)
    with stopping_on_signals(), status_line(f"robustness of {controller}: driving {profile.name}"):
        rows = robustness.study(profile, run_config, controller, tuple(range(1, seeds + 1)))
    typer.echo(robustness.format_study(rows, controller))
    if out is not None:
        atomic_write_text(out, json.dumps({"road": profile.name, "controller": controller, "rows": rows}, indent=2))
        typer.echo(f"wrote {out}")

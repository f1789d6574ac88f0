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

__all__ = ["robustness_cmd"]


def robustness_cmd(
    road: Annotated[Path, typer.Option("--road", metavar="FILE", help="Road profile the truck drives.")],
    controller: Annotated[
        str, typer.Option("--controller", help="The look-ahead controller studied: mpc, optimal or pcc.")
    ] = "mpc",
    seeds: Annotated[int, typer.Option("--seeds", min=1, help="Noisy maps per grade-noise level.")] = 2,
    vehicle: VehicleOpt = None,
    config: ConfigOpt = None,
    set_: SetOpt = None,
    out: Annotated[Path | None, typer.Option("--out", metavar="JSON", help="Also write the rows as JSON.")] = None,
) -> None:
    """How much of the controller's saving survives a mass it does not know (+-25 %) and a map with
    grade noise (sigma 0.2, 0.5, 1 %): each case against the PI on the true truck and road."""
    if controller not in ("mpc", "optimal", "pcc"):
        raise typer.BadParameter(f"expected mpc, optimal or pcc, got {controller!r}", param_hint="'--controller'")
    run_config = run_config_from(vehicle, config, set_)
    profile = load_road(road)
    with stopping_on_signals(), status_line(f"robustness of {controller}: driving {profile.name}"):
        rows = robustness.study(profile, run_config, controller, tuple(range(1, seeds + 1)))
    typer.echo(robustness.format_study(rows, controller))
    if out is not None:
        atomic_write_text(out, json.dumps({"road": profile.name, "controller": controller, "rows": rows}, indent=2))
        typer.echo(f"wrote {out}")

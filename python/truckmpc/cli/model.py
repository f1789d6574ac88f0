"""``truckmpc model``: queries of the vehicle model (``model stationary``:
:func:`truckmpc.stationary.stationary_point`, printed)."""

from __future__ import annotations

import json
from typing import Annotated

import typer

from truckmpc.cli.options import ConfigOpt, SetOpt, VehicleOpt, run_config_from
from truckmpc.stationary import stationary_point

__all__ = ["model_app"]

model_app = typer.Typer(help="Query the vehicle model.", no_args_is_help=True, rich_markup_mode=None)


def _parse_gear(text: str | None, forward_gears: int) -> int | None:
    if text is None:
        return None
    if text.strip().lower() in ("n", "neutral"):
        return 0
    try:
        gear = int(text)
    except ValueError:
        gear = -1
    if not 0 <= gear <= forward_gears:
        raise typer.BadParameter(f"expected 1..{forward_gears} or 'neutral', got {text!r}", param_hint="'--gear'")
    return gear


@model_app.command("stationary")
def stationary_cmd(
    speed_kmh: Annotated[float, typer.Option("--speed-kmh", help="Speed to hold [km/h].")],
    slope_pct: Annotated[float, typer.Option("--slope-pct", help="Road grade [%], negative downhill.")],
    gear: Annotated[
        str | None,
        typer.Option("--gear", help="Gear 1..12 or 'neutral' (default: the PI gear logic's gear at this speed)."),
    ] = None,
    vehicle: VehicleOpt = None,
    config: ConfigOpt = None,
    set_: SetOpt = None,
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON instead of text.")] = False,
) -> None:
    """Pedal or brake level holding a speed on a grade, its feasibility and eigenvalue λ = ∂(dv/ds)/∂v [1/m]."""
    if not speed_kmh > 0:
        raise typer.BadParameter(f"expected a speed > 0 km/h, got {speed_kmh:g}", param_hint="'--speed-kmh'")
    run_config = run_config_from(vehicle, config, set_)
    doc = stationary_point(run_config, speed_kmh, slope_pct, _parse_gear(gear, run_config.core_vehicle.forward_gears))
    if as_json:
        typer.echo(json.dumps(doc))
        return
    gear_text = "neutral" if doc["gear"] == 0 else str(doc["gear"])
    typer.echo(f"speed {speed_kmh:g} km/h on {slope_pct:g} % in gear {gear_text}")
    typer.echo(f"  pedal       {doc['pedal']:.4f}")
    typer.echo(f"  brake       {doc['brake']:.4f}")
    typer.echo(f"  feasible    {'yes' if doc['feasible'] else 'no (levels clipped to [0, 1])'}")
    typer.echo(f"  eigenvalue  {doc['eigenvalue_per_m'] * 1e3:.4f}e-3 1/m")

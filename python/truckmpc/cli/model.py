"""``truckmpc model``: queries of the vehicle model (``model stationary``:
:func:`truckmpc.stationary.stationary_point`, printed)."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Annotated, Any

import typer

from truckmpc.cli.options import ConfigOpt, SetOpt, VehicleOpt, run_config_from
from truckmpc.config import load_run_config
from truckmpc.config.vecto_truck import diesel_truck_from_overrides, truck_from_overrides
from truckmpc.errors import VehicleError
from truckmpc.stationary import electric_stationary_point, map_truck_stationary_point, stationary_point
from truckmpc.vecto.electric_truck import ElectricVectoTruck

__all__ = ["model_app"]

model_app = typer.Typer(
    help="Query the vehicle model: what the engine does holding a speed on a grade.",
    short_help="Query the vehicle model.",
    no_args_is_help=True,
    rich_markup_mode=None,
)


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


@model_app.command("stationary", short_help="Engine speed, torque and fuel holding a speed on a grade.")
def stationary_cmd(
    speed_kmh: Annotated[float, typer.Option("--speed-kmh", metavar="KMH", help="Speed to hold [km/h].")],
    slope_pct: Annotated[float, typer.Option("--slope-pct", metavar="PCT", help="Road grade [%], negative downhill.")],
    gear: Annotated[
        str | None,
        typer.Option(
            "--gear",
            metavar="GEAR",
            help="A forward gear, 1 to the truck's top gear (12 for the packaged truck), or 'neutral' (default: "
            "the PI gear logic's gear at this speed).",
        ),
    ] = None,
    vehicle: VehicleOpt = None,
    config: ConfigOpt = None,
    set_: SetOpt = None,
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON instead of text.")] = False,
) -> None:
    """The engine's speed, torque and fuel rate holding a speed on a grade; for the thesis's truck also
    the pedal or brake level, its feasibility and the eigenvalue λ = ∂(dv/ds)/∂v [1/m]. --vehicle may
    be a VECTO job (.vecto) or declaration XML (.xml)."""
    if not (speed_kmh > 0 and math.isfinite(speed_kmh)):
        raise typer.BadParameter(f"expected a speed > 0 km/h, got {speed_kmh:g}", param_hint="'--speed-kmh'")
    if not math.isfinite(slope_pct):
        raise typer.BadParameter(f"expected a finite grade, got {slope_pct:g}", param_hint="'--slope-pct'")
    if vehicle is not None and vehicle.suffix.lower() in (".vecto", ".xml"):
        _map_truck_point(vehicle, speed_kmh, slope_pct, gear, config, set_, as_json)
        return
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
    _echo_engine(doc)


def _echo_engine(doc: dict[str, float]) -> None:
    typer.echo(f"  engine      {doc['engine_speed_rpm']:.0f} rpm, {doc['engine_torque_nm']:.0f} Nm")
    typer.echo(f"  fuel rate   {doc['fuel_rate_g_per_h']:.0f} g/h")


def _map_truck_point(
    job: Path,
    speed_kmh: float,
    slope_pct: float,
    gear: str | None,
    config: list[Path] | None,
    set_: list[str] | None,
    as_json: bool,
) -> None:
    if config:
        raise VehicleError(f"--config: expected none with a VECTO truck ({job.name}): its keys are set with --set")
    any_truck = truck_from_overrides(job, set_ or ())
    if isinstance(any_truck, ElectricVectoTruck):
        if gear is not None and gear != "1":
            raise typer.BadParameter(f"expected 1 for a battery-electric truck, got {gear!r}", param_hint="'--gear'")
        brakes_nm = float(load_run_config(job, overrides=set_ or ()).settings.get("brake_torque_max_nm"))
        _echo_electric(electric_stationary_point(any_truck, speed_kmh, slope_pct, brakes_nm), as_json)
        return
    truck = diesel_truck_from_overrides(job, set_ or (), "model stationary")
    gears = truck.core.facts["gears"]
    parsed = _parse_gear(gear, gears)
    if parsed == 0:
        raise typer.BadParameter(f"expected 1..{gears} for a VECTO truck, got {gear!r}", param_hint="'--gear'")
    doc = map_truck_stationary_point(truck, speed_kmh, slope_pct, parsed)
    if as_json:
        typer.echo(json.dumps(doc))
        return
    typer.echo(f"speed {speed_kmh:g} km/h on {slope_pct:g} % in gear {doc['gear']}")
    if doc["fuel_rate_g_per_h"] is None:
        typer.echo(f"  not feasible: {doc['not_feasible']}")
        return
    _echo_engine(doc)
    typer.echo(f"  brakes      {doc['brake_power_w'] / 1e3:.1f} kW at the wheels, beyond the engine's drag")
    typer.echo("  feasible    yes")


def _echo_electric(doc: dict[str, Any], as_json: bool) -> None:
    """A battery-electric truck's stationary point: levels, machines, and the battery's power."""
    if as_json:
        typer.echo(json.dumps(doc))
        return
    typer.echo(f"speed {doc['speed_kmh']:g} km/h on {doc['slope_pct']:g} %")
    level = f"pedal {doc['pedal']:.4f}" if doc["brake"] == 0.0 else f"brake {doc['brake']:.4f}"
    typer.echo(f"  level       {level}" + ("" if doc["feasible"] else " (clipped: the truck cannot hold the speed)"))
    typer.echo(f"  machines    {doc['machine_speed_rpm']:.0f} rpm, {doc['machine_torque_nm']:.0f} Nm")
    typer.echo(f"  battery     {doc['battery_power_w'] / 1e3:.2f} kW drawn (negative: taken back)")
    losses = (doc[k] / 1e3 for k in ("machine_loss_w", "reduction_loss_w", "battery_loss_w", "aux_power_w"))
    typer.echo("  of which    machines {:.2f}, reduction {:.2f}, battery {:.2f}, auxiliaries {:.2f} kW".format(*losses))
    typer.echo(
        f"  brakes      {doc['friction_brake_power_w'] / 1e3:.1f} kW at the wheels, beyond what the machines take"
    )

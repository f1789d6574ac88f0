"""``truckmpc vehicle``: what truckmpc reads of a truck's component files (``vehicle info``:
:func:`truckmpc.vecto.info.truck_info`, printed)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated, Any

import typer

from truckmpc.cli.options import SetOpt
from truckmpc.config import load_run_config
from truckmpc.config.keys import RENAMED_KEYS
from truckmpc.config.vecto_truck import diesel_truck_from_overrides, electric_truck_keys
from truckmpc.errors import VehicleError
from truckmpc.vecto.electric import ElectricTruckJob
from truckmpc.vecto.electric_info import electric_truck_info
from truckmpc.vecto.info import truck_info
from truckmpc.vecto.truck import VectoTruck
from truckmpc.vecto.xml_file import read_declaration_xml

__all__ = ["vehicle_app"]

vehicle_app = typer.Typer(
    help="Read a truck's component files (VECTO .vecto jobs or declaration .xml files).",
    short_help="Read a VECTO truck's component files.",
    no_args_is_help=True,
    rich_markup_mode=None,
)


@vehicle_app.command("info", short_help="Print a VECTO truck's masses, ratios, drag and maps.")
def info_cmd(
    job: Annotated[
        Path,
        typer.Argument(
            metavar="FILE", help="A VECTO job (.vecto) naming its component files, or a VECTO declaration XML (.xml)."
        ),
    ],
    set_: SetOpt = None,
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON instead of text.")] = False,
) -> None:
    """Masses, ratios, air drag, rolling resistance, rated power and the maps' ranges, as simulated
    (VECTO's declaration-mode trailer, load and auxiliaries included; --set payload_kg=… and so on).
    A battery-electric truck's declaration XML: its machines, reduction, batteries and vehicle as read."""
    electric = _electric(job)
    if electric is not None:
        doc = electric_truck_info(electric, electric_truck_keys(job, set_ or ()))
    else:
        doc = truck_info(diesel_truck_from_overrides(job, set_ or (), "vehicle info"))
    if as_json:
        typer.echo(json.dumps(doc, indent=2))
        return
    typer.echo("\n".join(_electric_text(doc) if electric is not None else _text(doc)))


def _plot_electric(job: ElectricTruckJob, out: Path | None, svg: bool, given: str | None) -> None:
    """Draw a battery-electric truck's machine map; ``given`` names an option it cannot take."""
    if given:
        raise VehicleError(
            f"{given}: expected none for a battery-electric truck (its plot is the file's machine map), got one"
        )
    from truckmpc.plot.electric import plot_machine_map  # lazy: matplotlib

    written = plot_machine_map(job, out or Path(f"{job.path.stem}-machine-map.png"), svg=svg)
    typer.echo("wrote " + ", ".join(str(p) for p in written))


def _electric(path: Path) -> ElectricTruckJob | None:
    """The battery-electric truck a declaration XML declares, or None for any other truck file."""
    if path.suffix.lower() != ".xml" or not path.is_file():
        return None
    job = read_declaration_xml(path)
    return job if isinstance(job, ElectricTruckJob) else None


@vehicle_app.command("plot", short_help="Draw a VECTO truck's fuel map and a run's points.")
def plot_cmd(
    job: Annotated[Path, typer.Argument(metavar="FILE", help="A VECTO job (.vecto) or declaration XML (.xml).")],
    out: Annotated[
        Path | None,
        typer.Option(
            "-o", "--out", metavar="FILE", help="A .png or .svg file (default: <job name>-fuel-map.png here)."
        ),
    ] = None,
    svg: Annotated[bool, typer.Option("--svg", help="Also write an SVG beside the PNG.")] = False,
    run: Annotated[
        Path | None,
        typer.Option(
            "--run", metavar="DIR", help="A simulate output directory of this truck: draw where each controller ran it."
        ),
    ] = None,
    set_: SetOpt = None,
) -> None:
    """Draw the engine's fuel map (specific consumption [g/kWh] over speed and torque) with its
    full-load and drag curves, and with --run the operating points of each controller's run. For a
    battery-electric truck's declaration: one machine's efficiency map at each voltage level with its
    torque limits and drag curve. Needs matplotlib."""
    electric = _electric(job)
    if electric is not None:
        given = "--run" if run is not None else "--set" if set_ else None
        _plot_electric(electric, out, svg, given)
        return
    from truckmpc.plot.vehicle import plot_fuel_map, run_operating_points  # lazy: matplotlib

    overrides = tuple(set_ or ()) if run is None else _run_keys(run, job, set_)
    config = load_run_config(job, overrides=overrides)
    truck = config.truck
    assert isinstance(truck, VectoTruck), "a declaration of a battery-electric truck returned above"
    points = None if run is None else run_operating_points(run, config.core_vehicle)
    written = plot_fuel_map(truck, out or Path(f"{job.stem}-fuel-map.png"), svg=svg, runs=points)
    typer.echo("wrote " + ", ".join(str(p) for p in written))


def _run_keys(run: Path, job: Path, set_: list[str] | None) -> tuple[str, ...]:
    """The truck keys a run of ``job`` in ``run`` was made with, as ``--set`` items; a run of another
    truck, or ``--set`` beside ``--run``, is refused."""
    where = run / "summary.json"
    try:
        record = json.loads(where.read_text(encoding="utf-8"))["run"].get("vehicle")
    except (OSError, ValueError, KeyError, TypeError, AttributeError):
        raise VehicleError(f"{where}: expected a summary.json written by truckmpc simulate") from None
    if set_:
        raise VehicleError(f"--set {set_[0]}: expected no --set with --run (the run's own truck keys are used)")
    recorded = record.get("vecto_job") if isinstance(record, dict) else None
    if recorded != str(job.resolve()):
        raise VehicleError(
            f"{where}: run.vehicle: expected a run of {job.resolve()}, got a run of {recorded or 'the thesis truck'}"
        )
    keys = record.get("keys", {})
    return tuple(f"{RENAMED_KEYS.get(k, k)}={json.dumps(v)}" for k, v in keys.items() if isinstance(keys, dict))


def _text(d: dict[str, Any]) -> list[str]:
    ratios = ", ".join(f"{r:g}" for r in d["gear_ratios"])
    (n_lo, n_hi), (m_lo, m_hi) = d["full_load_speed_range_rpm"], d["fuel_map_speed_range_rpm"]
    t_lo, t_hi = d["fuel_map_torque_range_nm"]
    covers = "" if d["fuel_map_covers_full_load_curve"] else " (short of the full-load curve: nearest map value beyond)"
    masses = f"vehicle {d['curb_mass_kg']:.0f} + trailer {d['trailer_mass_kg']:.0f} + load {d['payload_kg']:.0f}"
    power = f"{d['rated_power_w'] / 1e3:.0f} kW at {d['rated_speed_rpm']:.0f} rpm"
    cda = f"{d['cda_declared_m2']:g} m² declared, {d['cda_at_80_kmh_m2']:.3f} m² at 80 km/h"
    return [
        f"{d['job']}: {d['group']}",
        f"  mass            {d['mass_kg']:.0f} kg = {masses}",
        f"  engine          {power}, idle {d['idle_speed_rpm']:.0f} rpm",
        f"  full-load curve {n_lo:.0f}-{n_hi:.0f} rpm",
        f"  fuel map        {m_lo:.0f}-{m_hi:.0f} rpm, {t_lo:.0f} to {t_hi:.0f} Nm{covers}",
        f"  gearbox         {d['gearbox']}: {len(d['gear_ratios'])} gears ({ratios}), axle {d['axle_ratio']:g}",
        f"  tyres           dynamic radius {d['wheel_radius_m']:.4f} m",
        f"  air drag        Cd·A {cda} ({d['cross_wind']} cross-wind correction)",
        f"  rolling         RRC {d['rolling_resistance']:.5f} (the whole combination at this mass)",
        f"  auxiliaries     {d['aux_power_w'] / 1e3:.2f} kW",
        f"  shifts          traction interrupted {d['traction_interruption_s']:g} s",
        f"  note            {d['driveline_losses']}",
    ]


def _electric_text(d: dict[str, Any]) -> list[str]:
    m = d["machines"]
    levels = " and ".join(f"{v:g}" for v in m["voltage_levels_v"])
    machines = (
        f"{m['count']} × {m['type']} at {m['position']}, {m['rated_power_w'] / 1e3:.0f} kW rated each, "
        f"{m['max_torque_nm']:.0f} Nm up to {m['top_speed_rpm']:.0f} rpm "
        f"(continuous {m['continuous_torque_nm']:.0f} Nm, "
        f"{m['overload_torque_nm']:.0f} Nm for {m['overload_duration_s']:g} s)"
    )
    lines = [
        f"{d['job']}: battery-electric, {d['group']} ({d['architecture']})",
        f"  mass            {d['mass_kg']:.0f} kg = vehicle {d['corrected_actual_mass_kg']:.0f} (corrected actual) "
        f"+ trailer {d['trailer_mass_kg']:.0f} + load {d['payload_kg']:.0f}",
        f"  machines        {machines}",
        f"  power maps      {m['power_map_size'][0]} speeds × {m['power_map_size'][1]} torques at {levels} V",
        f"  reduction       ratio {d['reduction_ratio']:g}, loss map of {d['reduction_loss_map_points']} points",
    ]
    for b in d["batteries"]:
        lo, hi = b["soc_window_pct"]
        lines.append(
            f"  battery {b['string_id']}       {b['type']} {b['rated_capacity_ah']:g} Ah, "
            f"OCV {b['ocv_range_v'][0]:.0f}-{b['ocv_range_v'][1]:.0f} V, usable {lo:g}-{hi:g} %: "
            f"{b['usable_energy_kwh']:.0f} kWh"
        )
    lines += [
        f"  tyres           dynamic radius {d['wheel_radius_m']:.4f} m",
        f"  air drag        Cd·A {d['cda_declared_m2']:g} m² declared, {d['cda_at_80_kmh_m2']:.3f} m² at 80 km/h "
        f"({d['cross_wind']} cross-wind correction)",
        f"  rolling         RRC {d['rolling_resistance']:.5f} (the whole combination at this mass)",
        f"  auxiliaries     {'; '.join(d['auxiliaries'])}",
        f"  as driven       usable {d['usable_window_pct'][0]:.1f}-{d['usable_window_pct'][1]:.1f} % "
        f"(declaration mode: narrowed for ageing), {d['usable_energy_kwh']:.0f} kWh at the start's voltage; "
        f"starts at {d['soc_start_pct']:.1f} %",
    ]
    if d["machines_continuous_torque_nm"] is not None:
        lines.append(
            f"  derating        held to {d['machines_continuous_torque_nm']:.0f} Nm once their losses above "
            f"{d['machines_continuous_loss_w'] / 1e3:.1f} kW fill {d['machines_overload_buffer_kj']:.0f} kJ "
            "(VECTO's overload buffer)"
        )
    return lines

"""``truckmpc pareto``: :func:`truckmpc.pareto.plan_pareto` and :func:`truckmpc.pareto.run_pareto`,
each controller's headline at the PCC's and the PI's trip time (and equal end speed) printed, and
the figure drawn."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated

import typer

from truckmpc.cli.options import (
    ConfigOpt,
    ForceOpt,
    JobsOpt,
    QuietOpt,
    ReverseAllOpt,
    RoadsOpt,
    SchedulerOpt,
    SetOpt,
    VehicleOpt,
)
from truckmpc.cli.study import notice, pooled_study, stop_notes, study_inputs
from truckmpc.consumption import FUEL, consumption_of
from truckmpc.errors import TruckmpcError
from truckmpc.pareto import equal_time_savings, plan_pareto, run_pareto
from truckmpc.pareto.fronts import BASELINES
from truckmpc.pareto.plan import CURVE_CONTROLLERS
from truckmpc.plot.pareto import plot_pareto
from truckmpc.sweep import SweepError, parse_axis, progress_bar

__all__ = ["pareto_cmd"]

OutOpt = Annotated[
    Path, typer.Option("--out", metavar="DIR", help="Output directory: pareto.csv, pareto.json, pareto.png.")
]
SpeedsOpt = Annotated[
    str | None,
    typer.Option(
        "--speeds",
        metavar="SPEC",
        help="Set speeds [km/h], start:stop:step or v1,v2,... (default: v_ref -8 to +4 in steps of 2).",
    ),
]
BetasOpt = Annotated[
    str | None,
    typer.Option(
        "--betas",
        metavar="SPEC",
        help="beta values [g/s] ([J/s] for a battery-electric truck) for the fuel_time curve at the configured "
        "v_ref (default: the set speeds, beta derived from each).",
    ),
]
CurvesOpt = Annotated[
    str,
    typer.Option(
        "--curves",
        metavar="LIST",
        help=f"Curves to run, a comma list of {', '.join(CURVE_CONTROLLERS)} (fuel_time: the MPC with the "
        "fuel-time cost, battery energy + beta·time for a battery-electric truck, over beta).",
    ),
]


def pareto_cmd(
    road: RoadsOpt,
    out: OutOpt,
    speeds: SpeedsOpt = None,
    betas: BetasOpt = None,
    curves: CurvesOpt = "pi,mpc,fuel_time",
    reverse: ReverseAllOpt = False,
    jobs: JobsOpt = None,
    scheduler: SchedulerOpt = None,
    vehicle: VehicleOpt = None,
    config: ConfigOpt = None,
    set_: SetOpt = None,
    quiet: QuietOpt = False,
    force: ForceOpt = False,
) -> None:
    """Fuel (battery energy for a battery-electric truck) against trip time: the PI over set speeds,
    the PCC and the MPC over set speeds and the fuel-time MPC over set speeds or beta;
    DIR/pareto.csv, and DIR/pareto.png with the saving at equal trip time.

    Rerun the same command with the same --out to resume an interrupted study.
    """
    with pooled_study("points"):
        plan = plan_pareto(
            road,
            speeds_kmh=_numbers("--speeds", "v_ref_kmh", speeds),
            betas=_numbers("--betas", "beta_g_per_s", betas),
            curves=[c.strip() for c in curves.split(",") if c.strip()],
            **study_inputs(reverse, vehicle, config, set_),
        )
        stop_notes(plan.roads)
        with progress_bar(not quiet) as hook:
            result = run_pareto(plan, out, jobs=jobs, progress=hook, force=force, notice=notice, scheduler=scheduler)
    written = [result.csv_path]
    for line in _saving_lines(result.rows, plan.base_v_ref_kmh):
        typer.echo(line)
    try:
        written += plot_pareto(out, out / "pareto.png", plan.base_v_ref_kmh)
    except TruckmpcError as err:  # no matplotlib: the CSV stands on its own
        typer.echo(f"no figure: {err}", err=True)
    typer.echo(f"wrote {', '.join(map(str, written))} ({result.runs} runs, {result.resumed} resumed)")


def _saving_lines(rows: list[dict[str, str]], v_ref_kmh: float) -> list[str]:
    """Each look-ahead curve's headline on each road against the PCC (when its curve ran) and the PI:
    at the baseline's trip time at v_ref and equal end speed, in % and kg (kWh) saved, or why there is none."""
    ran = {row["controller"] for row in rows}
    consumption = consumption_of(rows[0]) if rows else FUEL
    lines = []
    for base in (base for base in BASELINES if base in ran):
        for road_name, by_controller in equal_time_savings(rows, v_ref_kmh, base).items():
            for name, saving in by_controller.items():
                text = (
                    saving.reason
                    if saving.pct is None
                    else f"Δ{consumption.word} {saving.pct:+.2f} % ({saving.saved:.3f} {consumption.unit} saved)"
                )
                lines.append(
                    f"{road_name}: {name} against the {base.upper()} at equal trip time and end speed (the "
                    f"{base.upper()}'s trip time at v_ref {v_ref_kmh:g} km/h): {text}"
                )
    return lines


def _numbers(option: str, key: str, spec: str | None) -> list[float] | None:
    """The values of a --speeds or --betas SPEC (start:stop:step or v1,v2,...), all numbers."""
    if spec is None:
        return None
    try:
        values = parse_axis(f"{key}={spec}").values
    except SweepError as err:  # it speaks of the --grid axis it parsed
        raise SweepError(str(err).replace(f"--grid {key}", option)) from None
    numbers = [_number(v) for v in values]
    if None in numbers or not numbers:
        raise typer.BadParameter(f"expected numbers, got {spec!r}", param_hint=f"'{option}'")
    return [float(v) for v in numbers if v is not None]


def _number(value: object) -> float | None:
    """A finite number of a SPEC, or None (text, true or false, .nan, .inf)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        return None
    return float(value)

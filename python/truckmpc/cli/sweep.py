"""``truckmpc sweep``: :func:`truckmpc.sweep.plan_sweep` and :func:`truckmpc.sweep.run_plan` over
roads, a grid and a fleet, one line printed per row."""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Annotated

import typer

from truckmpc.cli.invocation import typed_command
from truckmpc.cli.options import ConfigOpt, ForceOpt, JobsOpt, QuietOpt, ReverseAllOpt, RoadsOpt, SchedulerOpt, SetOpt
from truckmpc.cli.study import notice, pooled_study, stop_notes, study_inputs
from truckmpc.compare import HEADLINE_BASELINES
from truckmpc.consumption import FUEL, Consumption
from truckmpc.record import program_record
from truckmpc.status import status_line
from truckmpc.sweep import plan_sweep, progress_bar, run_plan
from truckmpc.sweep.columns import DEFAULT_CONTROLLERS, LOOK_AHEAD, check_controllers, delta_column, headline_column
from truckmpc.sweep.summary import check_parquet, fleet_outputs

__all__ = ["sweep_cmd"]

DEFAULT_CONTROLLER = ",".join(DEFAULT_CONTROLLERS)
"""``sweep --controller`` when not given."""

OutOpt = Annotated[
    Path,
    typer.Option(
        "--out",
        metavar="DIR",
        help="Output directory: sweep.csv (a row per road and combination, the headline first, each look-ahead "
        "controller's saving at equal trip time and end speed: mpc_headline_vs_pcc_pct, mpc_saved_kg; then each "
        "figure in a column <controller>_<figure>: pi_fuel_kg, mpc_delta_fuel_pct; energy_kwh, delta_energy, "
        "saved_kwh for battery-electric trucks), sweep.json (and sweep.partial.csv while running; summary.csv "
        "for a fleet, sweep.parquet with --parquet).",
    ),
]
GridOpt = Annotated[
    list[str] | None,
    typer.Option(
        "--grid",
        metavar="KEY=SPEC",
        help="An axis: KEY=start:stop:step or KEY=v1,v2,... over any config key (listed with their units by "
        "truckmpc config keys), the values in the key's unit; repeatable.",
    ),
]
ControllerOpt = Annotated[
    str,
    typer.Option(
        "--controller",
        metavar="LIST",
        help=f"Look-ahead controllers to run on each row, a comma list of {', '.join(LOOK_AHEAD)}; the pi always "
        "runs, as the baseline.",
    ),
]
BothWaysOpt = Annotated[bool, typer.Option("--both-ways", help="Drive every road in both directions (a row for each).")]
FleetOpt = Annotated[
    list[Path] | None,
    typer.Option(
        "--vehicle",
        metavar="FILE",
        help="Vehicle: a YAML file (default: the packaged 40 t truck, truck-40t.yaml), a VECTO job (.vecto) or "
        "a VECTO declaration (.xml); repeatable, for a fleet (a vehicle column).",
    ),
]
ParquetOpt = Annotated[
    bool, typer.Option("--parquet", help="Also write DIR/sweep.parquet (needs pyarrow: truckmpc[parquet]).")
]
CheckConvergenceOpt = Annotated[
    bool,
    typer.Option(
        "--check-convergence",
        help="Also drive each MPC row at half the speed step and at half the stage length; add how far "
        "delta fuel and delta time move as columns.",
    ),
]


def sweep_cmd(
    road: RoadsOpt,
    out: OutOpt,
    grid: GridOpt = None,
    controller: ControllerOpt = DEFAULT_CONTROLLER,
    reverse: ReverseAllOpt = False,
    both_ways: BothWaysOpt = False,
    jobs: JobsOpt = None,
    scheduler: SchedulerOpt = None,
    vehicle: FleetOpt = None,
    config: ConfigOpt = None,
    set_: SetOpt = None,
    quiet: QuietOpt = False,
    force: ForceOpt = False,
    parquet: ParquetOpt = False,
    check_convergence: CheckConvergenceOpt = False,
) -> None:
    """Run the PI and the --controller list (default: the MPC) on every road for every combination of the
    --grid axes; one row each in DIR/sweep.csv.

    Rerun the same command with the same --out to resume an interrupted sweep.
    """
    controllers = _sweep_controllers(controller)
    if parquet:
        check_parquet()
    with pooled_study("rows"):
        with status_line("checking every combination of the grid"):
            plan = plan_sweep(
                road,
                tuple(grid or ()),
                **study_inputs(_directions(reverse, both_ways), _vehicles(vehicle), config, set_),
                check_convergence=check_convergence,
                controllers=controllers,
            )
        # recorded in sweep.json; not part of the sweep's identity, so a resume may be typed differently
        plan = dataclasses.replace(
            plan, settings={**plan.settings, "command": typed_command(), "program": program_record()}
        )
        stop_notes(plan.roads)
        with progress_bar(not quiet) as hook:
            result = run_plan(plan, out, jobs=jobs, progress=hook, force=force, notice=notice, scheduler=scheduler)
    axes = [axis.key for axis in plan.axes]
    for row in result.rows:
        figures = " ".join(f"{key}={row[key]}" for key in ("vehicle", *axes) if key in row)
        deltas = _sweep_deltas(row, plan.controllers, plan.consumption)
        typer.echo(f"{row['road']} {row['direction']} {figures}: {deltas}")
    runs = [f"{result.runs[name]} {name.upper()}" for name in (*plan.controllers, "pi")]
    lines, files = fleet_outputs(out, plan, result, parquet)
    for line in lines:
        typer.echo(line)
    written = [result.csv_path, *files]
    typer.echo(
        f"wrote {', '.join(map(str, written))} ({len(result.rows)} rows: {', '.join(runs[:-1])} and {runs[-1]} "
        f"runs, {result.resumed_rows} rows resumed)"
    )


def _vehicles(given: list[Path] | None) -> Path | tuple[Path, ...] | None:
    """``plan_sweep``'s `vehicle_path` from the --vehicle options: one file, several, or None."""
    if not given:
        return None
    return given[0] if len(given) == 1 else tuple(given)


def _directions(reverse: bool, both_ways: bool) -> bool | str:
    """``plan_sweep``'s `reverse`: True, False or ``"both"``; not --reverse with --both-ways."""
    if reverse and both_ways:
        raise typer.BadParameter("expected --reverse or --both-ways, not both", param_hint="'--both-ways'")
    return "both" if both_ways else reverse


def _sweep_controllers(text: str) -> tuple[str, ...]:
    """The look-ahead controllers of ``sweep --controller`` (``pcc``, ``mpc``), in column order."""
    try:
        return check_controllers(text.split(","))
    except ValueError as err:
        raise typer.BadParameter(str(err), param_hint="'--controller'") from None


def _sweep_deltas(row: Mapping[str, str], controllers: Sequence[str], consumption: Consumption = FUEL) -> str:
    """Each look-ahead controller's headline against the PCC (when it ran) and the PI, `Δfuel -2.31 %
    (0.123 kg saved)` (`Δenergy … kWh` for battery-electric trucks), then its Δfuel and Δtrip time as
    driven against the PI; `-` where blank."""
    parts = []
    for name in controllers:
        bases = [base for base in HEADLINE_BASELINES if base != name and (base == "pi" or base in controllers)]
        quoted = ", ".join(f"against the {base.upper()} {_headline(row, name, base, consumption)}" for base in bases)
        columns = (delta_column(name, kind, consumption=consumption) for kind in ("fuel", "time"))
        shown = [f"{float(v):+.2f}" if v else "-" for v in (row[column] for column in columns)]
        parts.append(
            f"{name} at equal trip time and end speed {quoted}; as driven Δ{consumption.word} vs PI {shown[0]} %, "
            f"Δtrip time {shown[1]} %"
        )
    return "; ".join(parts)


def _headline(row: Mapping[str, str], name: str, base: str, consumption: Consumption) -> str:
    """`Δfuel -2.31 % (0.123 kg saved)` of `name` against `base`, `-` where the row has none."""
    pct, saved = (row.get(headline_column(name, base, kind, consumption), "") for kind in ("headline", "saved"))
    if not (pct and saved):
        return "-"
    return f"Δ{consumption.word} {float(pct):+.2f} % ({float(saved):.3f} {consumption.unit} saved)"

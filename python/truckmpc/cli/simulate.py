"""``truckmpc simulate``: controllers over one road (or a run replayed from its summary.json), the
short table printed and the run directory written; the runs are :func:`truckmpc.run.run_controllers`'s."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer

from truckmpc.cli.invocation import typed_command
from truckmpc.cli.options import ConfigOpt, ForceOpt, SetOpt, VehicleOpt, run_config_from
from truckmpc.config import RunConfig
from truckmpc.convergence import halved_configs
from truckmpc.record import RunRequest, load_replay, run_record, with_controller_road
from truckmpc.results import check_run_dir, free_run_dir, write_outputs
from truckmpc.results.run_table import render_text, run_table
from truckmpc.roads import RoadProfile, default_test_track, load_road
from truckmpc.run import check_work, run_controllers
from truckmpc.signals import Stopped, received_signal, stopping_on_signals
from truckmpc.sim import CONTROLLERS
from truckmpc.status import status_line

__all__ = ["BOTH", "GROUPS", "controller_names", "simulate_cmd"]

BOTH = "both"
"""``--controller both``: PI and MPC on the same road and vehicle, with Δfuel and Δtime."""

GROUPS = {BOTH: ("pi", "mpc"), "all": tuple(CONTROLLERS)}
"""``--controller`` values that run several controllers: ``both`` (PI and MPC) and ``all`` (every
controller of :data:`truckmpc.sim.CONTROLLERS`: each look-ahead controller against each baseline,
and the MPC's gap to the whole-road optimum)."""


def controller_names(text: str) -> tuple[str, ...]:
    """The controllers of a ``--controller`` value: a group (``both``, ``all``) or a comma list of
    controllers from :data:`truckmpc.sim.CONTROLLERS` (``pi,mpc,optimal``), each once, in that order."""
    if text in GROUPS:
        return GROUPS[text]
    names = tuple(name.strip() for name in text.split(","))
    known = [*CONTROLLERS, *GROUPS]
    bad = [name for name in names if name not in CONTROLLERS]
    if bad or len(set(names)) < len(names):
        raise typer.BadParameter(
            f"expected one of {', '.join(known)}, or a comma list of {', '.join(CONTROLLERS)} each once, got {text!r}",
            param_hint="'--controller'",
        )
    return names


RoadOpt = Annotated[
    Path | None,
    typer.Option(
        "--road",
        metavar="FILE",
        help="Road profile CSV, VECTO .vdri cycle or GPS track (.gpx, imported with the defaults of road import "
        "gpx) (default: the bundled test track). A road with stops is driven as its stop-free legs.",
    ),
]
CONTROLLER_HELP = (
    f"Controllers to run: a comma list of {', '.join(CONTROLLERS)} (e.g. pi,pcc,mpc), or "
    + ", ".join(f"{group} = {','.join(names)}" for group, names in GROUPS.items())
    + f" (default: {BOTH}). pi is the thesis's PI cruise control, vecto_cc VECTO's cruise driver, pcc VECTO's "
    "predictive cruise control, mpc the look-ahead controller, optimal its whole-road optimum. Each look-ahead "
    "controller (pcc, mpc, optimal) is compared with every baseline that ran (pi, vecto_cc) and the mpc and "
    "optimal with the pcc."
)
"""The help of ``simulate --controller``, its lists built from :data:`~truckmpc.sim.CONTROLLERS` and
:data:`GROUPS`."""
ControllerOpt = Annotated[str | None, typer.Option("--controller", metavar="LIST", help=CONTROLLER_HELP)]
OutOpt = Annotated[
    Path | None,
    typer.Option(
        "--out",
        metavar="DIR",
        help="Output directory (default: out/<road name>, or out/<road name>-2, -3, ... when it holds an earlier "
        "run). A DIR holding an earlier run is refused unless --replace is given.",
    ),
]
ReplaceOpt = Annotated[
    bool, typer.Option("--replace", help="Replace the earlier run the --out directory holds (refused otherwise).")
]
ReverseOpt = Annotated[bool, typer.Option("--reverse", help="Drive the road in the opposite direction.")]
ReplayOpt = Annotated[
    Path | None,
    typer.Option("--replay", metavar="SUMMARY", help="Rerun exactly what a summary.json records (road, settings)."),
]
ControllerRoadOpt = Annotated[
    Path | None,
    typer.Option(
        "--controller-road",
        metavar="FILE",
        help="A road the controllers plan on while the truck drives --road (a noisy import, a grade bias).",
    ),
]
CheckConvergenceOpt = Annotated[
    bool,
    typer.Option(
        "--check-convergence",
        help="Also run the MPC at half the speed step, at half the stage length and (with pedal_levels) at "
        "twice the pedal levels, and report how far delta fuel (battery energy), delta time and fuel + "
        "beta*time move (flagged beyond 0.3 points).",
    ),
]
VerboseOpt = Annotated[
    bool,
    typer.Option(
        "--verbose",
        "-v",
        help="Also print the solver statistics (horizon solves, infeasible, relaxed and rescued solves, solve "
        "times [ms]), the optimum's plan, compute times and what each equal-time search found.",
    ),
]


def simulate_cmd(
    road: RoadOpt = None,
    controller: ControllerOpt = None,
    vehicle: VehicleOpt = None,
    config: ConfigOpt = None,
    set_: SetOpt = None,
    out: OutOpt = None,
    reverse: ReverseOpt = False,
    replay: ReplayOpt = None,
    force: ForceOpt = False,
    controller_road: ControllerRoadOpt = None,
    check_convergence: CheckConvergenceOpt = False,
    verbose: VerboseOpt = False,
    replace: ReplaceOpt = False,
) -> None:
    """Run controllers over a road; print a short table, write DIR/summary.json and DIR/trace-<controller>.csv.

    By default (--controller both) the PI and the MPC run. The table has a column per controller: its
    fuel and trip time, then its delta fuel against each baseline, (controller - baseline) /
    baseline in % (negative: fuel saved), at equal trip time (the baseline re-run at the set speed
    that matches the controller's trip time) and as driven. A run never replaces another unless
    asked (--replace).
    """
    options = (road, controller, vehicle, config, set_, reverse, check_convergence, controller_road)
    if replay is not None:
        given = [name for name, value in _run_options(*options) if value]
        if given:
            raise typer.BadParameter(
                f"takes the whole run from {replay}; drop {', '.join(given)}", param_hint="'--replay'"
            )
        request, profile, run_config = load_replay(replay)
    else:
        request, profile, run_config = _requested(*options)
    halves = _halved_configs(request, run_config)
    estimate_s = check_work(profile, run_config, request.controllers, force=force, halves=halves)
    out_dir = _out_dir(out, profile.name, replace)
    with stopping_on_signals():
        try:
            runs = run_controllers(
                profile, run_config, request.controllers, halves, status=status_line, estimate_s=estimate_s
            )
            record = run_record(request, profile, run_config)
            written = write_outputs(out_dir, profile, runs.results, record, runs.extra, runs.equal_times)
        except KeyboardInterrupt:
            raise Stopped("nothing written", received_signal()) from None
    # The table is read from the summary.json just written: what it shows is what the file holds.
    summary = json.loads(written[0].read_text(encoding="utf-8"))
    typer.echo(render_text(run_table(summary, verbose=verbose)))
    typer.echo("wrote " + ", ".join(str(p) for p in written))


def _out_dir(out: Path | None, road_name: str, replace: bool) -> Path:
    """The directory the run writes: `out` (refused if it holds an earlier run, unless `replace`), or
    by default out/<road name>, the next free out/<road name>-N when that holds one (said)."""
    if out is not None or replace:
        out_dir = Path("out") / road_name if out is None else out
        check_run_dir(out_dir, replace=replace)
        return out_dir
    default = Path("out") / road_name
    out_dir = free_run_dir(default)
    check_run_dir(out_dir, replace=False)
    if out_dir != default:
        typer.echo(f"{default} holds an earlier run: this one goes to {out_dir} (--replace replaces it)")
    return out_dir


def _requested(
    road: Path | None,
    controller: str | None,
    vehicle: Path | None,
    config: list[Path] | None,
    set_: list[str] | None,
    reverse: bool,
    check_convergence: bool,
    controller_road: Path | None,
) -> tuple[RunRequest, RoadProfile, RunConfig]:
    """The run the simulate options ask for: its request (as recorded), road and configuration."""
    run_config = run_config_from(vehicle, config, set_)
    profile = default_test_track() if road is None else load_road(road)
    profile = with_controller_road(profile.reversed() if reverse else profile, controller_road, reverse)
    names = controller_names(BOTH if controller is None else controller)
    inputs = (_text(vehicle), tuple(map(str, config or ())), tuple(set_ or ()))
    told = _text(controller_road)
    request = RunRequest(
        _text(road), reverse, names, *inputs, check_convergence, controller_road_path=told, command=typed_command()
    )
    return request, profile, run_config


def _halved_configs(request: RunRequest, config: RunConfig) -> dict[str, RunConfig]:
    """The configurations of `--check-convergence` (none without it); it needs the MPC and its baseline."""
    if not request.check_convergence:
        return {}
    if not {"pi", "mpc"} <= set(request.controllers):
        raise typer.BadParameter(
            f"expected --controller both (the mpc against the pi), got {','.join(request.controllers)}",
            param_hint="'--check-convergence'",
        )
    return halved_configs(config)


def _run_options(*values: object) -> list[tuple[str, object]]:
    """The simulate options that --replay replaces, with the values given."""
    names = (
        "--road",
        "--controller",
        "--vehicle",
        "--config",
        "--set",
        "--reverse",
        "--check-convergence",
        "--controller-road",
    )
    return list(zip(names, values, strict=True))


def _text(path: Path | None) -> str | None:
    return None if path is None else str(path)

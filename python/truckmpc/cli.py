"""The ``truckmpc`` command line.

Commands::

    truckmpc simulate [--road FILE] [--controller pi] [--vehicle FILE] [--config FILE ...]
                      [--set key=value ...] [--out DIR] [--reverse]
    truckmpc sweep --road FILE|DIR|GLOB [--road ...] [--grid KEY=SPEC ...] [--reverse|--both-ways]
                   [--jobs N | --scheduler ADDRESS] [--vehicle FILE ...] [--config FILE ...]
                   [--set key=value ...] [--quiet] [--check-convergence] [--parquet] --out DIR
    truckmpc pareto --road FILE|DIR|GLOB [--road ...] [--speeds SPEC] [--betas SPEC] [--curves LIST]
                    [--reverse] [--jobs N | --scheduler ADDRESS] [--vehicle FILE] [--config FILE ...]
                    [--set key=value ...] [--quiet] --out DIR
    truckmpc model stationary --speed-kmh V --slope-pct A [--gear G|neutral] [--vehicle FILE] [--json]
    truckmpc road make {flat,hill,crest,depression} --length-m L [--slope-pct A] [--lead-m X]
                       [--tail-m Y] -o FILE
    truckmpc road regenerate [--dir roads]
    truckmpc road import vdri FILE -o FILE
    truckmpc road import {gpx,csv} FILE -o ROAD.csv [--method spline|savgol|none] [--noise-m S]
                         [--smooth-m L] [--step-m D] [--grade-limit-pct G]
    truckmpc road info FILE
    truckmpc road plot FILE [-o OUT.png] [--svg]
    truckmpc bench [--json] [--road FILE] [--quick] [--set key=value ...]
    truckmpc plot DIR [--svg] [--out FILE_OR_DIR]

Every input problem (a :class:`~truckmpc.errors.TruckmpcError`, a usage error, an unreadable or
unwritable file) ends the command with exactly one line ``error: ...`` on stderr and exit code 2, no
traceback and no output files.
"""

from __future__ import annotations

import contextlib
import enum
import importlib
import json
import sys
from collections.abc import Callable, Iterator, Mapping, Sequence
from pathlib import Path
from typing import Annotated, Any, NoReturn

import typer
from typer.core import TyperGroup

from truckmpc import robustness
from truckmpc.atomic import atomic_write_text
from truckmpc.bench import BENCH_HELP, bench_cmd
from truckmpc.config import RunConfig, load_run_config
from truckmpc.convergence import halved_configs
from truckmpc.errors import TruckmpcError
from truckmpc.geo import options as geo
from truckmpc.legs import stops_line
from truckmpc.record import RunRequest, load_replay, run_record, with_controller_road
from truckmpc.results import check_run_dir, format_table, write_outputs
from truckmpc.road import (
    COLUMNS_COMMENT,
    RoadProfile,
    default_test_track,
    load_road,
    make_section,
    write_road,
    write_shipped_roads,
)
from truckmpc.run import check_work, run_controllers
from truckmpc.signals import Stopped, received_signal, stopping_on_signals
from truckmpc.sim import CONTROLLERS
from truckmpc.stationary import stationary_point
from truckmpc.status import status_line
from truckmpc.units import M_PER_KM
from truckmpc.vdri import cycle_summary, import_comments, read_vdri

USAGE_EXIT_CODE = 2


def _usage_error_types() -> tuple[type[Exception], ...]:
    """Usage-error base classes: Typer >= 0.20 vendors click (``typer.TyperException``); older
    versions raise ``click.ClickException``."""
    types: list[type[Exception]] = []
    if hasattr(typer, "TyperException"):
        types.append(typer.TyperException)
    try:
        click = importlib.import_module("click")  # not a static import: typer >= 0.20 does not install it
    except ImportError:
        pass
    else:
        types.append(click.ClickException)
    return tuple(types)


_USAGE_ERRORS = _usage_error_types()


def _fail(message: str, code: int = USAGE_EXIT_CODE) -> NoReturn:
    text = " ".join(str(message).split())
    typer.echo(f"error: {text}", err=True)
    sys.exit(code)


class _OneLineErrors(TyperGroup):
    """Root command group that turns every user-facing error into one ``error:`` line and exit code 2.

    Living in the group (not only in :func:`main`) means Typer's ``CliRunner`` sees the same behaviour
    as the installed command.
    """

    def main(
        self,
        args: Sequence[str] | None = None,
        prog_name: str | None = None,
        complete_var: str | None = None,
        standalone_mode: bool = True,
        windows_expand_args: bool = True,
        **extra: Any,
    ) -> Any:
        try:
            rv = super().main(
                args=args,
                prog_name=prog_name,
                complete_var=complete_var,
                standalone_mode=False,
                windows_expand_args=windows_expand_args,
                **extra,
            )
        except _USAGE_ERRORS as err:  # usage errors, bad parameter values
            message = err.format_message() if hasattr(err, "format_message") else str(err)
            _fail(message or "missing command or arguments (usage above; --help for more)")
        except TruckmpcError as err:
            _fail(str(err))
        except OSError as err:  # e.g. an output directory that cannot be written
            where = f"{err.filename}: " if err.filename else ""
            _fail(f"{where}{err.strerror or err}")
        except typer.Abort:
            _fail("aborted", 1)
        except Stopped as stop:  # SIGINT or SIGTERM: one line, exit 130 or 143
            typer.echo(str(stop), err=True)
            sys.exit(stop.exit_code)
        if not standalone_mode:
            return rv
        sys.exit(rv if isinstance(rv, int) else 0)


app = typer.Typer(
    cls=_OneLineErrors,
    help="Look-ahead cruise control for heavy trucks: simulate a PI cruise controller and a look-ahead DP-MPC "
    "over road profiles and compare their fuel and trip time.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    # Plain help: rich markup would take the units in brackets ([km/h], [m]) for style tags and drop them.
    rich_markup_mode=None,
)
model_app = typer.Typer(help="Query the vehicle model.", no_args_is_help=True, rich_markup_mode=None)
road_app = typer.Typer(help="Make, import, inspect and plot roads.", no_args_is_help=True, rich_markup_mode=None)
config_app = typer.Typer(
    help="The parameters: key tables and the packaged default files.", no_args_is_help=True, rich_markup_mode=None
)
road_import_app = typer.Typer(
    help="Make a road CSV from a GPS track, a track drawn on a map or a VECTO driving cycle.",
    no_args_is_help=True,
    rich_markup_mode=None,
)
road_app.add_typer(road_import_app, name="import")
app.add_typer(model_app, name="model")
app.add_typer(road_app, name="road")
app.add_typer(config_app, name="config")
app.command("bench", help=BENCH_HELP)(bench_cmd)

BOTH = "both"
"""``--controller both``: PI and MPC on the same road and vehicle, with Δfuel and Δtime."""

GROUPS = {BOTH: ("pi", "mpc"), "all": ("pi", "mpc", "optimal")}
"""``--controller`` values that run several controllers: ``both`` (PI and MPC) and ``all`` (PI, MPC
and the whole-road optimum, with the MPC's gap to it)."""


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


class SectionKind(enum.StrEnum):
    flat = "flat"
    hill = "hill"
    crest = "crest"
    depression = "depression"


VehicleOpt = Annotated[
    Path | None, typer.Option("--vehicle", metavar="FILE", help="Vehicle YAML file (default: packaged truck-40t.yaml).")
]
ConfigOpt = Annotated[
    list[Path] | None, typer.Option("--config", metavar="FILE", help="Controller/simulation YAML overlay; repeatable.")
]
SetOpt = Annotated[
    list[str] | None,
    typer.Option(
        "--set", metavar="KEY=VALUE", help="Override any vehicle, controller or simulation key: key=value; repeatable."
    ),
]
RoadsOpt = Annotated[
    list[Path],
    typer.Option(
        "--road",
        metavar="FILE",
        help="Road profile CSV or VECTO .vdri cycle, a directory of them, or a glob (quoted); repeatable.",
    ),
]
ReverseAllOpt = Annotated[bool, typer.Option("--reverse", help="Drive every road in the opposite direction.")]
JobsOpt = Annotated[
    int | None,
    typer.Option(
        "--jobs", min=1, help="Worker processes of the embedded Dask cluster (default: all cores); 1 runs in-process."
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
ForceOpt = Annotated[
    bool, typer.Option("--force", help="Run even when the estimated work is beyond an hour (refused otherwise).")
]


def _run_config(vehicle: Path | None, config: list[Path] | None, set_: list[str] | None) -> RunConfig:
    """The configuration from ``--vehicle``, ``--config`` and ``--set``."""
    return load_run_config(vehicle_path=vehicle, config_paths=tuple(config or ()), overrides=tuple(set_ or ()))


@app.command("simulate")
def simulate_cmd(
    road: Annotated[
        Path | None,
        typer.Option(
            "--road",
            metavar="FILE",
            help="Road profile CSV or VECTO .vdri cycle (default: the bundled test track). A road with stops is "
            "driven as its stop-free legs.",
        ),
    ] = None,
    controller: Annotated[
        str | None,
        typer.Option(
            "--controller",
            help="Controllers to run: a comma list of pi, mpc, optimal (pi,mpc,optimal), or both = pi,mpc "
            "(default), all = pi,mpc,optimal. Each look-ahead controller is compared with the pi.",
        ),
    ] = None,
    vehicle: VehicleOpt = None,
    config: ConfigOpt = None,
    set_: SetOpt = None,
    out: Annotated[Path | None, typer.Option("--out", help="Output directory (default: out/<road name>).")] = None,
    reverse: Annotated[bool, typer.Option("--reverse", help="Drive the road in the opposite direction.")] = False,
    replay: Annotated[
        Path | None,
        typer.Option("--replay", metavar="SUMMARY", help="Rerun exactly what a summary.json records (road, settings)."),
    ] = None,
    force: ForceOpt = False,
    controller_road: Annotated[
        Path | None,
        typer.Option(
            "--controller-road",
            metavar="FILE",
            help="A road the controllers plan on while the truck drives --road (a noisy import, a grade bias).",
        ),
    ] = None,
    check_convergence: Annotated[
        bool,
        typer.Option(
            "--check-convergence",
            help="Also run the MPC at half the speed step and at half the stage length, and report how far "
            "delta fuel and delta time move (flagged beyond 0.3 points).",
        ),
    ] = False,
) -> None:
    """Run controllers over a road; print a short table, write DIR/summary.json and DIR/trace-<controller>.csv.

    The default, both, runs PI and MPC and reports delta fuel and delta time, (MPC - PI) / PI in %.
    A directory holding an earlier run is replaced whole.
    """
    if replay is not None:
        options = (road, controller, vehicle, config, set_, reverse, check_convergence, controller_road)
        given = [name for name, value in _run_options(*options) if value]
        if given:
            raise typer.BadParameter(
                f"takes the whole run from {replay}; drop {', '.join(given)}", param_hint="'--replay'"
            )
        request, profile, run_config = load_replay(replay)
    else:
        run_config = _run_config(vehicle, config, set_)
        profile = default_test_track() if road is None else load_road(road)
        profile = with_controller_road(profile.reversed() if reverse else profile, controller_road, reverse)
        names = controller_names(BOTH if controller is None else controller)
        inputs = (_text(vehicle), tuple(map(str, config or ())), tuple(set_ or ()))
        told = _text(controller_road)
        request = RunRequest(_text(road), reverse, names, *inputs, check_convergence, controller_road_path=told)
    halves = _halved_configs(request, run_config)
    estimate_s = check_work(profile, run_config, request.controllers, force=force, halves=halves)
    out_dir = Path("out") / profile.name if out is None else out
    check_run_dir(out_dir)
    with stopping_on_signals():
        try:
            runs = run_controllers(
                profile, run_config, request.controllers, halves, status=status_line, estimate_s=estimate_s
            )
            record = run_record(request, profile, run_config)
            written = write_outputs(out_dir, profile, runs.results, record, runs.extra, runs.equal_times)
        except KeyboardInterrupt:
            raise Stopped("nothing written", received_signal()) from None
    typer.echo(format_table(profile, runs.results, run_config, runs.extra.get("convergence"), runs.equal_times))
    typer.echo("wrote " + ", ".join(str(p) for p in written))


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


@app.command("robustness")
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
    run_config = _run_config(vehicle, config, set_)
    profile = load_road(road)
    with stopping_on_signals(), status_line(f"robustness of {controller}: driving {profile.name}"):
        rows = robustness.study(profile, run_config, controller, tuple(range(1, seeds + 1)))
    typer.echo(robustness.format_study(rows, controller))
    if out is not None:
        atomic_write_text(out, json.dumps({"road": profile.name, "controller": controller, "rows": rows}, indent=2))
        typer.echo(f"wrote {out}")


@app.command("sweep")
def sweep_cmd(
    road: RoadsOpt,
    out: Annotated[
        Path,
        typer.Option("--out", help="Output directory: sweep.csv, sweep.json (and sweep.partial.csv while running)."),
    ],
    grid: Annotated[
        list[str] | None,
        typer.Option(
            "--grid", metavar="KEY=SPEC", help="Axis KEY=start:stop:step or KEY=v1,v2,...; any config key; repeatable."
        ),
    ] = None,
    controller: Annotated[
        str,
        typer.Option(
            "--controller",
            help="Look-ahead controllers to run on each row, a comma list of pcc, mpc; the pi always runs, "
            "as the baseline.",
        ),
    ] = "mpc",
    reverse: ReverseAllOpt = False,
    both_ways: Annotated[
        bool, typer.Option("--both-ways", help="Drive every road in both directions (a row for each).")
    ] = False,
    jobs: JobsOpt = None,
    scheduler: SchedulerOpt = None,
    vehicle: Annotated[
        list[Path] | None,
        typer.Option(
            "--vehicle",
            metavar="FILE",
            help="Vehicle YAML file (default: packaged truck-40t.yaml); repeatable, for a fleet (a vehicle column).",
        ),
    ] = None,
    config: ConfigOpt = None,
    set_: SetOpt = None,
    quiet: QuietOpt = False,
    force: ForceOpt = False,
    parquet: Annotated[
        bool, typer.Option("--parquet", help="Also write DIR/sweep.parquet (needs pyarrow: truckmpc[parquet]).")
    ] = False,
    check_convergence: Annotated[
        bool,
        typer.Option(
            "--check-convergence",
            help="Also drive each MPC row at half the speed step and at half the stage length; add how far "
            "delta fuel and delta time move as columns.",
        ),
    ] = False,
) -> None:
    """Run the PI and the --controller list (default: the MPC) on every road for every combination of the
    --grid axes; one row each in DIR/sweep.csv.

    Rerun the same command with the same --out to resume an interrupted sweep.
    """
    from truckmpc.sweep import plan_sweep, progress_bar, run_plan
    from truckmpc.sweep.summary import check_parquet, fleet_outputs

    controllers = _sweep_controllers(controller)
    if parquet:
        check_parquet()
    with _pooled_study("rows"):
        with status_line("checking every combination of the grid"):
            plan = plan_sweep(
                road,
                tuple(grid or ()),
                **_study_inputs(_directions(reverse, both_ways), _vehicles(vehicle), config, set_),
                check_convergence=check_convergence,
                controllers=controllers,
            )
        _stop_notes(plan.roads)
        with progress_bar(not quiet) as hook:
            result = run_plan(plan, out, jobs=jobs, progress=hook, force=force, notice=_notice, scheduler=scheduler)
    axes = [axis.key for axis in plan.axes]
    for row in result.rows:
        figures = " ".join(f"{key}={row[key]}" for key in ("vehicle", *axes) if key in row)
        typer.echo(f"{row['road']} {row['direction']} {figures}: {_sweep_deltas(row, plan.controllers)}")
    runs = [f"{result.runs[name]} {name.upper()}" for name in (*plan.controllers, "pi")]
    lines, files = fleet_outputs(out, plan, result, parquet)
    for line in lines:
        typer.echo(line)
    written = [result.csv_path, *files]
    typer.echo(
        f"wrote {', '.join(map(str, written))} ({len(result.rows)} rows: {', '.join(runs[:-1])} and {runs[-1]} "
        f"runs, {result.resumed_rows} rows resumed)"
    )


def _directions(reverse: bool, both_ways: bool) -> bool | str:
    """``plan_sweep``'s `reverse`: True, False or ``"both"``; not --reverse with --both-ways."""
    if reverse and both_ways:
        raise typer.BadParameter("expected --reverse or --both-ways, not both", param_hint="'--both-ways'")
    return "both" if both_ways else reverse


def _sweep_controllers(text: str) -> tuple[str, ...]:
    """The look-ahead controllers of ``sweep --controller`` (``pcc``, ``mpc``), in column order."""
    from truckmpc.sweep.columns import check_controllers

    try:
        return check_controllers(text.split(","))
    except ValueError as err:
        raise typer.BadParameter(str(err), param_hint="'--controller'") from None


def _sweep_deltas(row: Mapping[str, str], controllers: Sequence[str]) -> str:
    """`delta fuel -1.23 %, delta time +0.45 %` of each look-ahead controller against the PI (named
    when there are several), `-` where blank."""
    from truckmpc.sweep.columns import delta_column

    parts = []
    for name in controllers:
        shown = [f"{float(v):+.2f}" if v else "-" for v in (row[delta_column(name, k)] for k in ("fuel", "time"))]
        named = f"{name} " if len(controllers) > 1 else ""
        parts.append(f"{named}delta fuel {shown[0]} %, delta time {shown[1]} %")
    return "; ".join(parts)


@app.command("pareto")
def pareto_cmd(
    road: RoadsOpt,
    out: Annotated[
        Path,
        typer.Option("--out", help="Output directory: pareto.csv, pareto.json, pareto.png."),
    ],
    speeds: Annotated[
        str | None,
        typer.Option(
            "--speeds",
            metavar="SPEC",
            help="Set speeds [km/h], start:stop:step or v1,v2,... (default: v_ref -8 to +4 in steps of 2).",
        ),
    ] = None,
    betas: Annotated[
        str | None,
        typer.Option(
            "--betas",
            metavar="SPEC",
            help="beta values [g/s] for the fuel_time curve at the configured v_ref (default: the set speeds, "
            "beta derived from each).",
        ),
    ] = None,
    curves: Annotated[
        str, typer.Option("--curves", help="Curves to run, comma-separated: pi, pcc, mpc, fuel_time.")
    ] = "pi,mpc,fuel_time",
    reverse: ReverseAllOpt = False,
    jobs: JobsOpt = None,
    scheduler: SchedulerOpt = None,
    vehicle: VehicleOpt = None,
    config: ConfigOpt = None,
    set_: SetOpt = None,
    quiet: QuietOpt = False,
    force: ForceOpt = False,
) -> None:
    """Fuel against trip time: the PI over set speeds, the PCC and the MPC over set speeds and the
    fuel-time MPC over set speeds or beta; DIR/pareto.csv, and DIR/pareto.png with the saving at equal
    trip time.

    Rerun the same command with the same --out to resume an interrupted study.
    """
    from truckmpc.pareto import equal_time_savings, plan_pareto, run_pareto
    from truckmpc.sweep import progress_bar

    with _pooled_study("points"):
        plan = plan_pareto(
            road,
            speeds_kmh=_numbers("--speeds", "v_ref_kmh", speeds),
            betas_g_per_s=_numbers("--betas", "beta_g_per_s", betas),
            curves=[c.strip() for c in curves.split(",") if c.strip()],
            **_study_inputs(reverse, vehicle, config, set_),
        )
        _stop_notes(plan.roads)
        with progress_bar(not quiet) as hook:
            result = run_pareto(plan, out, jobs=jobs, progress=hook, force=force, notice=_notice, scheduler=scheduler)
    written = [result.csv_path]
    savings = equal_time_savings(result.rows, plan.base_v_ref_kmh)
    for road_name, by_controller in savings.items():
        for name, saving in by_controller.items():
            text = saving.reason if saving.pct is None else f"{saving.pct:+.2f} %"
            typer.echo(f"{road_name}: {name} at the PI's trip time at v_ref {plan.base_v_ref_kmh:g} km/h: {text}")
    try:
        from truckmpc.plot.pareto import plot_pareto

        written += plot_pareto(out, out / "pareto.png", plan.base_v_ref_kmh)
    except TruckmpcError as err:  # no matplotlib: the CSV stands on its own
        typer.echo(f"no figure: {err}", err=True)
    typer.echo(f"wrote {', '.join(map(str, written))} ({result.runs} runs, {result.resumed} resumed)")


def _vehicles(given: list[Path] | None) -> Path | tuple[Path, ...] | None:
    """``plan_sweep``'s `vehicle_path` from the --vehicle options: one file, several, or None."""
    if not given:
        return None
    return given[0] if len(given) == 1 else tuple(given)


def _study_inputs(
    reverse: bool | str,
    vehicle: Path | tuple[Path, ...] | None,
    config: list[Path] | None,
    set_: list[str] | None,
) -> dict[str, Any]:
    """The base inputs of a sweep or Pareto study, as ``plan_sweep`` and ``plan_pareto`` take them."""
    return {
        "reverse": reverse,
        "vehicle_path": vehicle,
        "config_paths": tuple(config or ()),
        "overrides": tuple(set_ or ()),
    }


@contextlib.contextmanager
def _pooled_study(kept_what: str) -> Iterator[None]:
    """A sweep or Pareto study's stops as one line each: Ctrl-C or SIGTERM says how many finished
    `kept_what` (rows, points) stay for a resume; a lost Dask cluster exits 1."""
    from truckmpc.sweep import SweepInterrupted, SweepWorkerDied

    try:
        with stopping_on_signals():
            yield
    except SweepInterrupted as stop:
        kept = f"{stop.done} of {stop.total} {kept_what} kept in {stop.partial_path}"
        raise Stopped(f"{kept}; run the same command again to resume", received_signal()) from None
    except KeyboardInterrupt:
        raise Stopped("before any run started", received_signal()) from None
    except SweepWorkerDied as err:
        _fail(str(err), 1)


def _numbers(option: str, key: str, spec: str | None) -> list[float] | None:
    """The values of a --speeds or --betas SPEC (start:stop:step or v1,v2,...), all numbers."""
    from truckmpc.sweep import SweepError, parse_axis

    if spec is None:
        return None
    try:
        values = parse_axis(f"{key}={spec}").values
    except SweepError as err:  # it speaks of the --grid axis it parsed
        raise SweepError(str(err).replace(f"--grid {key}", option)) from None
    bad = [v for v in values if isinstance(v, bool) or not isinstance(v, (int, float))]
    if bad or not values:
        raise typer.BadParameter(f"expected numbers, got {spec!r}", param_hint=f"'{option}'")
    return [float(v) for v in values]


def _notice(text: str) -> None:
    typer.echo(text, err=True)


def _stop_notes(roads: Sequence[object]) -> None:
    """One line per road with stops: they are not simulated, the road is driven as its legs."""
    for road in roads:
        if isinstance(road, RoadProfile) and road.stops:
            typer.echo(f"{road.name}: {stops_line(road)}")


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
    run_config = _run_config(vehicle, config, set_)
    doc = stationary_point(run_config, speed_kmh, slope_pct, _parse_gear(gear, run_config.core_vehicle.forward_gears))
    chosen = doc["gear"]
    if as_json:
        typer.echo(json.dumps(doc))
        return
    gear_text = "neutral" if chosen == 0 else str(chosen)
    typer.echo(f"speed {speed_kmh:g} km/h on {slope_pct:g} % in gear {gear_text}")
    typer.echo(f"  pedal       {doc['pedal']:.4f}")
    typer.echo(f"  brake       {doc['brake']:.4f}")
    typer.echo(f"  feasible    {'yes' if doc['feasible'] else 'no (levels clipped to [0, 1])'}")
    typer.echo(f"  eigenvalue  {doc['eigenvalue_per_m'] * 1e3:.4f}e-3 1/m")


@road_app.command("make")
def road_make_cmd(
    kind: Annotated[SectionKind, typer.Argument(help="Section shape.")],
    length_m: Annotated[float, typer.Option("--length-m", help="Length of the hill (or crest/depression) [m].")],
    output: Annotated[Path, typer.Option("-o", "--output", help="CSV file to write.")],
    slope_pct: Annotated[
        float | None, typer.Option("--slope-pct", help="Grade [%] (negative for a descent); not for flat.")
    ] = None,
    lead_m: Annotated[float | None, typer.Option("--lead-m", help="Flat lead-in [m] (default: the thesis's).")] = None,
    tail_m: Annotated[float | None, typer.Option("--tail-m", help="Flat run-out [m] (default: the thesis's).")] = None,
) -> None:
    """Write an artificial road section (thesis sections 1.2, 6.2, 6.3) as a road CSV."""
    profile = make_section(kind.value, length_m, slope_pct, lead_m=lead_m, tail_m=tail_m)
    command = f"truckmpc road make {kind.value} --length-m {length_m:g}"
    for flag, value in (("--slope-pct", slope_pct), ("--lead-m", lead_m), ("--tail-m", tail_m)):
        command += "" if value is None else f" {flag} {value:g}"
    write_road(profile, output, comments=(f"Generated by: {command}", COLUMNS_COMMENT))
    typer.echo(f"wrote {output} ({profile.name}, {profile.length_m / M_PER_KM:.2f} km)")


@road_app.command("regenerate")
def road_regenerate_cmd(
    directory: Annotated[Path, typer.Option("--dir", help="Directory of the shipped roads.")] = Path("roads"),
) -> None:
    """Rewrite the shipped example sections and the test track from their definitions."""
    written = write_shipped_roads(directory)
    typer.echo(f"wrote {len(written)} road files to {directory}")


@road_import_app.command("vdri")
def road_import_vdri_cmd(
    cycle: Annotated[Path, typer.Argument(metavar="FILE", help="VECTO distance-based driving cycle (.vdri).")],
    output: Annotated[Path, typer.Option("-o", "--output", help="Road CSV to write.")],
) -> None:
    """Convert a VECTO driving cycle into a road CSV: distance, altitude integrated from the grade,
    target speed and stops (the stop_s column); prints its length, legs, stops and target speeds."""
    profile = read_vdri(cycle)
    write_road(profile, output, comments=import_comments(profile, f"truckmpc road import vdri {cycle} -o {output}"))
    typer.echo(f"wrote {output} ({cycle_summary(profile)})")


def _import(kind: str, file: Path, output: Path, *options: Any) -> None:
    from truckmpc.geo.commands import ImportOptions, import_road

    for line in import_road(kind, file, output, ImportOptions(*options)):
        typer.echo(line)


def _track_import_command(kind: str, doc: str) -> Callable[..., None]:
    """The `road import KIND` command for a track format (`gpx`, `csv`): the same options for both."""

    def command(
        file: geo.TrackArg,
        output: geo.OutputOpt,
        method: geo.MethodOpt = geo.Method.spline,
        noise_m: geo.NoiseOpt = geo.DEFAULT_NOISE_M,
        smooth_m: geo.SmoothOpt = None,
        step_m: geo.StepOpt = None,
        grade_limit_pct: geo.GradeLimitOpt = geo.DEFAULT_GRADE_LIMIT_PCT,
    ) -> None:
        _import(kind, file, output, method, noise_m, smooth_m, step_m, grade_limit_pct)

    command.__doc__ = doc
    return command


road_import_app.command("gpx")(
    _track_import_command(
        "gpx",
        """Make a road CSV from a GPX file's track points (else its route points): geodesic distance,
    elevation resampled and smoothed, steep grades reported (README: Roads from GPS tracks).""",
    )
)
road_import_app.command("csv")(
    _track_import_command(
        "csv",
        """Make a road CSV from a plain lat,lon,ele table (degrees, metres; one point per row in travel
    order), as road import gpx does.""",
    )
)


@road_app.command("info")
def road_info_cmd(file: geo.RoadFileArg) -> None:
    """Print a road's length, climb and descent, grade histogram, steepest stretches and, for an
    imported road, how it was made (smoothing included)."""
    from truckmpc.geo.commands import info_lines

    for line in info_lines(file):
        typer.echo(line)


@road_app.command("plot")
def road_plot_cmd(
    file: geo.RoadFileArg,
    out: Annotated[Path | None, typer.Option("-o", "--out", help="Picture to write (default: FILE.png).")] = None,
    svg: Annotated[bool, typer.Option("--svg", help="Also write an SVG beside the PNG.")] = False,
) -> None:
    """Draw a road's altitude and grade over distance; for an imported road, the raw elevation under
    the smoothed one. Needs matplotlib."""
    from truckmpc.geo.commands import plot_road_file

    written = plot_road_file(file, out, svg)
    typer.echo("wrote " + ", ".join(str(p) for p in written))


@app.command("plot")
def plot_cmd(
    directory: Annotated[
        Path,
        typer.Argument(
            metavar="DIR", help="A run directory (summary.json, trace-*.csv) or a sweep directory (sweep.csv)."
        ),
    ],
    svg: Annotated[bool, typer.Option("--svg", help="Also write an SVG beside every PNG.")] = False,
    out: Annotated[
        Path | None, typer.Option("--out", help="Output directory, or a .png/.svg file name (default: DIR).")
    ] = None,
) -> None:
    """Plot a run (DIR/run.png: altitude, speed, gear, pedal, brake over distance) or a sweep
    (DIR/sweep.png: delta fuel and delta time against the horizon; DIR/realtime.png). Needs matplotlib."""
    from truckmpc.plot import plot_dir

    written = plot_dir(directory, out=out, svg=svg)
    typer.echo("wrote " + ", ".join(str(p) for p in written))


@config_app.command("keys")
def config_keys_cmd(
    section: Annotated[
        str | None, typer.Option("--section", help="vehicle, cruise, pi, mpc or sim (default: all).")
    ] = None,
    write: Annotated[
        Path | None,
        typer.Option(
            "--write", metavar="FILE", help="Rewrite the tables between <!-- keys:SECTION --> markers in FILE."
        ),
    ] = None,
) -> None:
    """Print the Markdown table of every key (unit, default, allowed values, meaning), per section."""
    from truckmpc.config import SECTION_NAMES, key_table, rewrite_key_tables

    if section is not None and section not in SECTION_NAMES:
        raise typer.BadParameter(
            f"expected one of {', '.join(SECTION_NAMES)}, got {section!r}", param_hint="'--section'"
        )
    if write is not None:
        rewritten = rewrite_key_tables(write)
        typer.echo(f"rewrote {len(rewritten)} key tables in {write}: {', '.join(rewritten)}")
        return
    for name in SECTION_NAMES if section is None else (section,):
        typer.echo(f"<!-- keys:{name} -->\n{key_table(name)}\n<!-- /keys:{name} -->")


@config_app.command("defaults")
def config_defaults_cmd(
    directory: Annotated[
        Path | None, typer.Option("--dir", help="Directory to write (default: the packaged configs).")
    ] = None,
) -> None:
    """Write the default YAML files (trucks, cruise, pi, mpc, simulation) from the parameter declarations."""
    from truckmpc.config import write_packaged_defaults
    from truckmpc.config.keys import CONFIG_DIR

    target = CONFIG_DIR if directory is None else directory
    target.mkdir(parents=True, exist_ok=True)
    written = write_packaged_defaults(target)
    typer.echo(f"wrote {len(written)} files to {target}")


def main(argv: list[str] | None = None) -> None:
    """Entry point of the ``truckmpc`` command."""
    app(args=argv, prog_name="truckmpc")

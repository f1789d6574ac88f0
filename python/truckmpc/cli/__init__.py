"""The ``truckmpc`` command line: a thin layer over the library, one module per command group.

Commands::

    truckmpc --version
    truckmpc simulate [--road FILE] [--controller pi] [--vehicle FILE] [--config FILE ...]
                      [--set key=value ...] [--out DIR] [--reverse] [--controller-road FILE]
                      [--check-convergence] [--force] | --replay SUMMARY [--out DIR]
    truckmpc robustness --road FILE [--controller mpc|optimal|pcc] [--seeds N] [--vehicle FILE]
                        [--config FILE ...] [--set key=value ...] [--out JSON]
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
    truckmpc vehicle info JOB.vecto|DECL.xml [--set key=value ...] [--json]
    truckmpc vehicle plot JOB.vecto|DECL.xml [-o OUT.png] [--svg] [--run DIR]
    truckmpc config keys [--section SECTION] [--write FILE]
    truckmpc config defaults [--dir DIR]
    truckmpc bench [--json] [--road FILE] [--quick] [--set key=value ...]
    truckmpc plot DIR [--svg] [--out FILE_OR_DIR]
    truckmpc report DIR [--out FILE]

Modules: :mod:`~truckmpc.cli.simulate` (simulate, its --replay), :mod:`~truckmpc.cli.robustness`,
:mod:`~truckmpc.cli.sweep`, :mod:`~truckmpc.cli.pareto` (and :mod:`~truckmpc.cli.study`, what those
two share), :mod:`~truckmpc.cli.model`, :mod:`~truckmpc.cli.road`, :mod:`~truckmpc.cli.vehicle`,
:mod:`~truckmpc.cli.config`,
:mod:`~truckmpc.cli.bench`, :mod:`~truckmpc.cli.plot`, :mod:`~truckmpc.cli.report`;
:mod:`~truckmpc.cli.options` (the options several commands share), :mod:`~truckmpc.cli.errors`
(one-line errors) and :mod:`~truckmpc.cli.invocation` (the command line, as recorded). The library
never imports this package.

Every input problem (a :class:`~truckmpc.errors.TruckmpcError`, a usage error, an unreadable or
unwritable file) ends the command with exactly one line ``error: ...`` on stderr and exit code 2, no
traceback and no output files.
"""

from __future__ import annotations

from typing import Annotated

import typer

from truckmpc.cli.bench import BENCH_HELP, bench_cmd
from truckmpc.cli.config import config_app
from truckmpc.cli.errors import OneLineErrors
from truckmpc.cli.model import model_app
from truckmpc.cli.pareto import pareto_cmd
from truckmpc.cli.plot import plot_cmd
from truckmpc.cli.report import report_cmd
from truckmpc.cli.road import road_app
from truckmpc.cli.robustness import robustness_cmd
from truckmpc.cli.simulate import simulate_cmd
from truckmpc.cli.sweep import sweep_cmd
from truckmpc.cli.vehicle import vehicle_app
from truckmpc.record import program_version

__all__ = ["app", "main"]

app = typer.Typer(
    cls=OneLineErrors,
    help="Look-ahead cruise control for heavy trucks: simulate a PI cruise controller, VECTO's predictive "
    "cruise control and a look-ahead DP-MPC over road profiles and compare their fuel and trip time.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    # Plain help: rich markup would take the units in brackets ([km/h], [m]) for style tags and drop them.
    rich_markup_mode=None,
)


def _print_version(asked: bool) -> None:
    if asked:
        typer.echo(f"truckmpc {program_version()}")
        raise typer.Exit()


@app.callback()
def _options(
    version: Annotated[
        bool,
        typer.Option("--version", is_eager=True, callback=_print_version, help="Print the version and exit."),
    ] = False,
) -> None:
    """The options of ``truckmpc`` itself, before a command (the app's help is the text above)."""


# The order here is the order of `truckmpc --help`; each summary fits on its line there.
app.command("bench", help=BENCH_HELP, short_help="Time the MPC's closed-loop runs on long roads.")(bench_cmd)
app.command("simulate", short_help="Run controllers over a road; compare fuel and trip time.")(simulate_cmd)
app.command("robustness", short_help="How much saving survives a wrong mass or a noisy map.")(robustness_cmd)
app.command("sweep", short_help="Run the controllers over a grid of settings and roads.")(sweep_cmd)
app.command("pareto", short_help="Fuel against trip time over set speeds and beta.")(pareto_cmd)
app.command("plot", short_help="Draw the figures of a run or a sweep directory.")(plot_cmd)
app.command("report", short_help="Write an HTML page of a run or a sweep to hand on.")(report_cmd)
app.add_typer(model_app, name="model")
app.add_typer(road_app, name="road")
app.add_typer(vehicle_app, name="vehicle")
app.add_typer(config_app, name="config")


def main(argv: list[str] | None = None) -> None:
    """Entry point of the ``truckmpc`` command."""
    app(args=argv, prog_name="truckmpc")

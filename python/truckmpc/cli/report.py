"""``truckmpc report``: :func:`truckmpc.report.write_report` on a run or sweep directory."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from truckmpc.report import write_report

__all__ = ["report_cmd"]


def report_cmd(
    directory: Annotated[
        Path,
        typer.Argument(
            metavar="DIR",
            help="A run directory (summary.json, trace-*.csv, from simulate --out DIR) or a sweep directory "
            "(sweep.json, sweep.csv, from sweep --out DIR).",
        ),
    ],
    out: Annotated[
        Path | None,
        typer.Option("--out", metavar="FILE", help="Where to write the page (default: DIR/report.html)."),
    ] = None,
) -> None:
    """Write an HTML report of a run or a sweep.

    One self-contained page (DIR/report.html) to hand on: the summary table, the figures, the command
    that repeats the run, its provenance and every parameter with its unit. Figures need matplotlib.
    """
    report = write_report(directory, out)
    if report.missing_figures is not None:
        typer.echo(f"note: no figures in the report: {report.missing_figures}", err=True)
    typer.echo(f"wrote {report.path}")

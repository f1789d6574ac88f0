"""``truckmpc report``: one self-contained HTML page for a run or a sweep directory, to hand on.

The page holds the summary table (for a run, the model of the ``simulate`` table,
:func:`truckmpc.results.run_table.run_table`; for a sweep, one row per row of ``sweep.csv`` with
the headline, each look-ahead controller's saving at equal trip time and equal end speed, first),
the figures of ``truckmpc plot`` embedded as PNG ``data:`` URIs, the
command that repeats the run or sweep, its provenance (program version, roads with their SHA-256,
the truck, the inputs as given) and every resolved parameter with its unit and meaning. Nothing
in it is fetched from elsewhere: the file alone is the report.

Modules: :mod:`~truckmpc.report.inputs` (reading and checking the directory),
:mod:`~truckmpc.report.run_page` and :mod:`~truckmpc.report.sweep_page` (the two kinds of page),
:mod:`~truckmpc.report.run_table` and :mod:`~truckmpc.report.sweep_table` (their tables),
:mod:`~truckmpc.report.figures`, :mod:`~truckmpc.report.settings` (the configuration),
:mod:`~truckmpc.report.replay` (the commands), :mod:`~truckmpc.report.html` (the page's pieces).
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

from truckmpc.atomic import atomic_write_text
from truckmpc.report.figures import draw_figures
from truckmpc.report.html import page
from truckmpc.report.inputs import ReportError, RunDir, SweepDir, read_dir
from truckmpc.report.run_page import run_body, run_title
from truckmpc.report.sweep_page import sweep_body, sweep_title

__all__ = ["REPORT_NAME", "Report", "ReportError", "report_html", "write_report"]

REPORT_NAME = "report.html"
"""The report's file name in the directory it reports on, unless told otherwise."""


@dataclass(frozen=True)
class Report:
    """A written report: where it went, and why it has no figures if it has none."""

    path: Path
    missing_figures: str | None


def report_html(directory: str | os.PathLike[str]) -> tuple[str, str | None]:
    """The page for the run or sweep in `directory`, and why it has no figures (None if it has);
    :class:`ReportError` for a directory that holds neither."""
    source: RunDir | SweepDir = read_dir(directory)
    figures, missing = draw_figures(source.path)
    if isinstance(source, RunDir):
        return page(run_title(source), run_body(source, figures, missing)), missing
    return page(sweep_title(source), sweep_body(source, figures, missing)), missing


def write_report(directory: str | os.PathLike[str], out: str | os.PathLike[str] | None = None) -> Report:
    """Write the page for `directory` to `out` (default ``directory/report.html``) in one step;
    nothing is written if the directory cannot be reported on."""
    text, missing = report_html(directory)
    path = Path(directory) / REPORT_NAME if out is None else Path(out)
    atomic_write_text(path, text)
    return Report(path, missing)

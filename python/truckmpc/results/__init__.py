"""Run outputs: ``summary.json`` (:mod:`~truckmpc.results.summary`), ``trace-<controller>.csv``
and the writing of both (:mod:`~truckmpc.results.files`), and the run's table read from a
summary alone (:mod:`~truckmpc.results.run_table`: the CLI prints it, the HTML report lays it out)."""

from truckmpc.results.files import RUN_FILES, check_run_dir, free_run_dir, trace_csv, write_outputs
from truckmpc.results.summary import BASELINE, summary_document
from truckmpc.results.table import format_table

__all__ = [
    "BASELINE",
    "RUN_FILES",
    "check_run_dir",
    "format_table",
    "free_run_dir",
    "summary_document",
    "trace_csv",
    "write_outputs",
]

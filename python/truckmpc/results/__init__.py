"""Run outputs: ``summary.json`` (:mod:`~truckmpc.results.summary`), ``trace-<controller>.csv``
and the writing of both (:mod:`~truckmpc.results.files`), and the short table the CLI prints
(:mod:`~truckmpc.results.table`)."""

from truckmpc.results.files import RUN_FILES, check_run_dir, trace_csv, write_outputs
from truckmpc.results.summary import BASELINE, summary_document
from truckmpc.results.table import format_table

__all__ = [
    "BASELINE",
    "RUN_FILES",
    "check_run_dir",
    "format_table",
    "summary_document",
    "trace_csv",
    "write_outputs",
]

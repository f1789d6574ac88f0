"""A run's files: ``summary.json`` (:mod:`~truckmpc.results.summary`) and one
``trace-<controller>.csv`` per controller, written all or nothing through
:class:`truckmpc.atomic.OutputDir`, so a failed run leaves nothing half-written."""

from __future__ import annotations

import io
import itertools
import json
import math
import os
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from truckmpc.atomic import OutputDir
from truckmpc.equal_time import EqualTime
from truckmpc.errors import ConfigError
from truckmpc.results.summary import summary_document
from truckmpc.schema import TRACE_SPECS
from truckmpc.sim import TRACE_COLUMNS, RunResult

if TYPE_CHECKING:
    from truckmpc.roads import RoadProfile

__all__ = ["RUN_FILES", "check_run_dir", "free_run_dir", "holds_run", "summary_json", "trace_csv", "write_outputs"]

_CSV_FORMATS = {spec.name: "%d" if spec.decimals is None else f"%.{spec.decimals}f" for spec in TRACE_SPECS}
"""How the trace's CSV writes each declared column (others ``%.6g``)."""


def trace_csv(result: RunResult) -> str:
    """The trace of one run as CSV text (header line, then one row per sample)."""
    columns = [c for c in TRACE_COLUMNS if c in result.trace] + [c for c in result.trace if c not in TRACE_COLUMNS]
    table = np.column_stack([np.asarray(result.trace[c], dtype=float) for c in columns])
    buffer = io.StringIO()
    np.savetxt(
        buffer,
        table,
        fmt=[_CSV_FORMATS.get(c, "%.6g") for c in columns],
        delimiter=",",
        header=",".join(columns),
        comments="",
    )
    return buffer.getvalue()


def _json_default(value: Any) -> Any:
    if isinstance(value, np.generic):
        return value.item()
    raise TypeError(f"not JSON-serialisable: {type(value).__name__}")


def _clean(value: Any) -> Any:
    """NaN and infinities are not JSON; write them as null."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {k: _clean(v) for k, v in value.items()}
    return value


RUN_FILES = ("summary.json", "trace-*.csv", "run.png", "run.svg", "report.html")
"""What a run directory holds (its outputs, its plots and its report); a new run replaces them all."""


def holds_run(out_dir: str | os.PathLike[str]) -> bool:
    """Whether `out_dir` holds any of an earlier run's files (:data:`RUN_FILES`)."""
    out = Path(out_dir)
    return out.is_dir() and any(p.match(pattern) for p in out.iterdir() for pattern in RUN_FILES)


def free_run_dir(out_dir: str | os.PathLike[str]) -> Path:
    """`out_dir` if it holds no run, else the first of `out_dir`-2, -3, ... that holds none."""
    out = Path(out_dir)
    candidates = itertools.chain([out], (out.with_name(f"{out.name}-{n}") for n in itertools.count(2)))
    return next(c for c in candidates if not holds_run(c))


def check_run_dir(out_dir: str | os.PathLike[str], replace: bool = True) -> None:
    """Refuse an output directory that holds anything but an earlier run's files: it is someone's
    other data. Without `replace`, refuse one that holds an earlier run too (the new run would
    replace it whole)."""
    out = Path(out_dir)
    if out.exists() and not out.is_dir():
        raise ConfigError(f"{out}: expected a directory for the run's outputs, got a file")
    if not out.is_dir():
        return
    foreign = sorted(p.name for p in out.iterdir() if not any(p.match(pattern) for pattern in RUN_FILES))
    if foreign:
        shown = ", ".join(foreign[:3]) + (", ..." if len(foreign) > 3 else "")
        raise ConfigError(f"{out}: holds files that are not a truckmpc run's ({shown}); choose another --out")
    if not replace and holds_run(out):
        raise ConfigError(f"{out}: holds an earlier run; add --replace to replace it, or choose another --out")


def summary_json(doc: Mapping[str, Any]) -> str:
    """A summary document as ``summary.json`` holds it (JSON text; non-finite numbers as null)."""
    return json.dumps(_clean(doc), indent=2, default=_json_default)


def write_outputs(
    out_dir: str | os.PathLike[str],
    road: RoadProfile,
    results: Mapping[str, RunResult],
    run: Mapping[str, Any] | None = None,
    extra: Mapping[str, Any] | None = None,
    equal_times: Mapping[str, EqualTime] | None = None,
) -> list[Path]:
    """Write ``summary.json`` and one ``trace-<controller>.csv`` per run into ``out_dir``, all or
    nothing, replacing any earlier run there whole (see :func:`check_run_dir`). `extra` adds
    top-level objects to the summary (``convergence``).

    Returns the paths written.
    """
    out = Path(out_dir)
    check_run_dir(out)
    names = ["summary.json"] + [f"trace-{name}.csv" for name in results]
    with OutputDir(out, replace=True) as staging:
        doc = {**summary_document(road, results, run, equal_times), **(extra or {})}
        (staging / "summary.json").write_text(summary_json(doc) + "\n", encoding="utf-8")
        for name, result in results.items():
            (staging / f"trace-{name}.csv").write_text(trace_csv(result), encoding="utf-8")
    return [out / name for name in names]

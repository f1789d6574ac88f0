"""What a report is made from: a run directory (``summary.json`` and ``trace-<controller>.csv``, as
``truckmpc simulate --out DIR`` writes it) or a sweep directory (``sweep.json`` and ``sweep.csv``, as
``truckmpc sweep --out DIR`` writes it), read and checked before anything is drawn or written."""

from __future__ import annotations

import csv
import json
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from truckmpc.errors import TruckmpcError
from truckmpc.sweep.cells import parse_cell

__all__ = ["ReportError", "RunDir", "SweepDir", "read_dir"]

_EXPECTED = "a run directory (summary.json, from truckmpc simulate --out DIR) or a sweep directory (sweep.csv)"


class ReportError(TruckmpcError):
    """A directory a report cannot be made of: missing, or without a readable summary.json or sweep."""


@dataclass(frozen=True)
class RunDir:
    """A run directory: its ``summary.json`` as a dict and the controllers it ran, in run order."""

    path: Path
    summary: dict[str, Any]
    controllers: tuple[str, ...]


@dataclass(frozen=True)
class SweepDir:
    """A sweep directory: ``sweep.json`` (the sweep's settings) and the rows of ``sweep.csv``."""

    path: Path
    settings: dict[str, Any]
    header: tuple[str, ...]
    rows: tuple[dict[str, Any], ...]


def read_dir(directory: str | os.PathLike[str]) -> RunDir | SweepDir:
    """The run or sweep in `directory`; :class:`ReportError` naming the file and what was expected."""
    path = Path(directory)
    if not path.is_dir():
        raise ReportError(f"{path}: no such directory; expected {_EXPECTED}")
    if (path / "summary.json").is_file():
        return _read_run(path)
    if (path / "sweep.csv").is_file():
        return _read_sweep(path)
    raise ReportError(f"{path}: no summary.json (nor sweep.csv); expected {_EXPECTED}")


def _read_run(path: Path) -> RunDir:
    doc = _json_object(path / "summary.json", "a summary.json written by truckmpc simulate")
    where = path / "summary.json"
    run = doc.get("run")
    if not isinstance(run, dict) or not isinstance(run.get("settings"), dict):
        raise ReportError(f"{where}: expected a 'run' object with 'settings' (written by truckmpc simulate)")
    controllers = run.get("controllers")
    if not isinstance(controllers, list) or not controllers:
        raise ReportError(f"{where}: run.controllers: expected a list of the controllers run, got {controllers!r}")
    missing = [name for name in controllers if not isinstance(doc.get(name), dict)]
    if missing:
        raise ReportError(f"{where}: expected an object of figures for each controller run, none for {missing}")
    return RunDir(path, doc, tuple(controllers))


def _read_sweep(path: Path) -> SweepDir:
    settings = _json_object(path / "sweep.json", "the sweep.json that truckmpc sweep writes beside sweep.csv")
    where = path / "sweep.csv"
    try:
        with where.open(newline="", encoding="utf-8") as handle:
            reader = csv.DictReader(handle)
            header = tuple(reader.fieldnames or ())
            rows = tuple({k: parse_cell(v or "") for k, v in row.items() if k is not None} for row in reader)
    except (OSError, UnicodeDecodeError, csv.Error) as err:
        raise ReportError(f"{where}: expected a sweep CSV, could not read it ({err})") from None
    if "road" not in header or not rows:
        raise ReportError(f"{where}: expected a header with a 'road' column and at least one row")
    return SweepDir(path, settings, header, rows)


def _json_object(path: Path, expected: str) -> dict[str, Any]:
    """The JSON object in `path`; :class:`ReportError` if it is missing, unreadable or not an object."""
    try:
        doc = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise ReportError(f"{path}: missing; expected {expected}") from None
    except json.JSONDecodeError as err:
        raise ReportError(f"{path}:{err.lineno}: expected {expected}, got invalid JSON ({err.msg})") from None
    except (OSError, UnicodeDecodeError) as err:
        raise ReportError(f"{path}: expected {expected}, could not read it ({err})") from None
    if not isinstance(doc, dict):
        raise ReportError(f"{path}: expected {expected} (a JSON object), got a {type(doc).__name__}")
    return doc

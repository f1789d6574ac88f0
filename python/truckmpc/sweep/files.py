"""The files of a sweep directory: ``sweep.json`` (which sweep it holds), ``sweep.partial.csv``
(rows appended as they finish) and ``sweep.csv`` (all rows in grid order, written at the end). A
Pareto study keeps the same three files under the stem ``pareto``.

``sweep.json`` identifies the sweep by its roads (name, content hash, direction), its axes, its
resolved base configuration and its columns; a directory holding another sweep is not resumed into.
"""

from __future__ import annotations

import contextlib
import csv
import io
import json
import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from truckmpc.atomic import atomic_write_text
from truckmpc.config.keys import SPEC_BY_KEY, current_sections
from truckmpc.config.yamlfile import parse_assignment
from truckmpc.errors import ConfigError
from truckmpc.sweep.errors import SweepError

CSV_NAME, PARTIAL_NAME, SETTINGS_NAME = "sweep.csv", "sweep.partial.csv", "sweep.json"


def file_names(stem: str = "sweep") -> tuple[str, str, str]:
    """The final CSV, the partial CSV and the settings file of a study named `stem` (``sweep``,
    ``pareto``): they share this module's resume logic."""
    return f"{stem}.csv", f"{stem}.partial.csv", f"{stem}.json"


_IDENTITY = ("version", "roads", "grid", "base_config", "columns")
"""Settings that identify a sweep."""


def _identity(settings: Mapping[str, Any]) -> dict[str, Any]:
    doc = {k: settings.get(k) for k in _IDENTITY}
    doc["roads"] = [{k: r.get(k) for k in ("name", "direction", "sha256")} for r in doc["roads"] or []]
    return doc


def check_out_dir(
    out: Path,
    settings: Mapping[str, Any],
    stem: str = "sweep",
    renames: Mapping[str, str] | None = None,
    added: frozenset[str] = frozenset(),
) -> None:
    """Refuse to mix studies: an existing ``<stem>.json`` in ``out`` must describe this one, its
    ``columns`` read through `renames` (old name -> new name) and lacking at most the columns
    `added` since."""
    csv_name, partial_name, settings_name = file_names(stem)
    path = out / settings_name
    try:
        old = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        if (out / partial_name).exists() or (out / csv_name).exists():
            raise SweepError(
                f"{out}: holds {stem} results without {settings_name}; use another --out or remove them"
            ) from None
        return
    except (json.JSONDecodeError, UnicodeDecodeError):
        raise SweepError(f"{path}: not a {stem} settings file; use another --out or remove it") from None
    theirs = _identity(old if isinstance(old, dict) else {})
    theirs["base_config"] = _current_config(theirs["base_config"], _set_keys(old))
    if renames and isinstance(theirs["columns"], list):
        theirs["columns"] = _renamed(theirs["columns"], renames)
    mine = _identity(settings)
    if isinstance(theirs["columns"], list) and _positions(theirs["columns"], mine["columns"] or [], added):
        theirs["columns"] = mine["columns"]
    differ = [key for key in _IDENTITY if mine[key] != theirs[key]]
    if differ:
        raise SweepError(
            f"{out} holds a different {stem} (not the same: {', '.join(differ)}); use another --out or remove it"
        )


def _current_config(doc: Any, set_keys: Mapping[str, Any]) -> Any:
    """A recorded base configuration (one, or a fleet's by name) with its keys as today's, through
    the registry of renamed and added keys: a sweep written before a key existed still resumes.
    A key added since that the sweep's own ``--set`` gave (a VECTO truck's, which its configuration
    did not record then) takes the value set, not the registry's."""

    def current(one: Any) -> Any:
        if not isinstance(one, dict):
            return one
        out = current_sections(one)
        for key, value in set_keys.items():
            section = SPEC_BY_KEY[key].section
            if section not in one and isinstance(out.get(section), dict):
                out[section][key] = value
        return out

    if not isinstance(doc, dict):
        return doc
    return current(doc) if "vehicle" in doc else {name: current(one) for name, one in doc.items()}


def _set_keys(doc: Any) -> dict[str, Any]:
    """The declared keys a recorded sweep's ``--set`` overrides gave, with their values."""
    overrides = doc.get("overrides") if isinstance(doc, dict) else None
    out: dict[str, Any] = {}
    for text in overrides if isinstance(overrides, list) else ():
        with contextlib.suppress(ConfigError, TypeError):
            key, value = parse_assignment(str(text))
            if key in SPEC_BY_KEY:
                out[key] = value
    return out


def write_settings(out: Path, settings: Mapping[str, Any], jobs: int, stem: str = "sweep") -> None:
    """Write ``<stem>.json``: the plan's settings and the number of processes of this run."""
    atomic_write_text(out / file_names(stem)[2], json.dumps({**settings, "jobs": jobs}, indent=2) + "\n")


def csv_line(cells: Sequence[str]) -> str:
    """One CSV line, ending in a newline."""
    buffer = io.StringIO()
    csv.writer(buffer, lineterminator="\n").writerow(cells)
    return buffer.getvalue()


def read_rows(
    path: Path, columns: Sequence[str], renames: Mapping[str, str] | None = None, added: frozenset[str] = frozenset()
) -> list[tuple[int, list[str]]]:
    """(line number, cells) of each complete line of a sweep CSV after its header (whose names are
    read through `renames`, old name -> new name; a header without some of the columns `added`
    since gives those cells blank), whatever its number of cells (a last line cut
    short by an interruption is ignored; bytes that are not UTF-8 are read as U+FFFD, so a damaged
    line is still a line)."""
    try:
        text = path.read_bytes().decode("utf-8", errors="replace")
    except FileNotFoundError:
        return []
    # Only "\n" ends a line the sweep writes: splitlines() would also split a damaged line at a form
    # feed or a U+2028 and stop reading there.
    lines = [line + "\n" for line in text.split("\n")]
    lines[-1] = lines[-1][:-1]  # what follows the last newline: a line cut short, or nothing
    if not lines[0]:
        return []
    positions = _positions(_renamed(next(csv.reader([lines[0]]), []), renames or {}), columns, added)
    if positions is None:
        raise SweepError(f"{path}: its columns are not this sweep's; remove it or use another --out")
    rows = []
    for number, line in enumerate(lines[1:], start=2):
        if not line.endswith("\n"):
            break  # cut short by an interruption
        try:
            cells = next(csv.reader([line]), [])
        except csv.Error:  # e.g. a NUL byte
            cells = []
        rows.append((number, _placed(cells, positions)))
    return rows


def finished_rows(
    out: Path,
    columns: Sequence[str],
    stem: str = "sweep",
    renames: Mapping[str, str] | None = None,
    added: frozenset[str] = frozenset(),
) -> list[tuple[str, list[str]]]:
    """The rows already in ``<stem>.csv`` and ``<stem>.partial.csv`` (possibly repeated), each with
    where it was read (``DIR/sweep.partial.csv:7``); see :func:`read_rows` for `renames` and `added`."""
    return [
        (f"{out / name}:{number}", cells)
        for name in file_names(stem)[:2]
        for number, cells in read_rows(out / name, columns, renames, added)
    ]


def _positions(header: Sequence[Any], columns: Sequence[str], added: frozenset[str]) -> list[int | None] | None:
    """Where each of `columns` is in `header` (None: a column added since, absent); None if
    `header` is not `columns` less some of the `added` ones, in order."""
    if list(header) != [c for c in columns if c in header or c not in added]:
        return None
    return [header.index(c) if c in header else None for c in columns]


def _placed(cells: list[str], positions: Sequence[int | None]) -> list[str]:
    """A row's `cells` under this sweep's columns (blank where its header lacked one); as read when
    their number is not the header's (a damaged row, dropped later)."""
    if len(cells) != sum(p is not None for p in positions):
        return cells
    return [cells[p] if p is not None else "" for p in positions]


def _renamed(names: Sequence[Any], renames: Mapping[str, str]) -> list[Any]:
    """`names` with each old name in `renames` replaced by its new one."""
    return [renames.get(name, name) if isinstance(name, str) else name for name in names]


class PartialFile:
    """``sweep.partial.csv``: rows appended one complete line per write(2), flushed to the OS as
    they finish."""

    def __init__(self, path: Path, header: str, rows: Sequence[str]) -> None:
        atomic_write_text(path, header + "".join(rows))  # drop a cut-short line before appending
        self._fd = os.open(path, os.O_WRONLY | os.O_APPEND)

    def append(self, line: str) -> None:
        data = line.encode("utf-8")
        while data:
            data = data[os.write(self._fd, data) :]

    def close(self) -> None:
        os.close(self._fd)


def write_final(out: Path, header: str, rows: Sequence[Sequence[str]], stem: str = "sweep") -> Path:
    """Write ``<stem>.csv`` in one step and remove the partial file; return the CSV's path."""
    csv_name, partial_name, _ = file_names(stem)
    atomic_write_text(out / csv_name, header + "".join(csv_line(cells) for cells in rows))
    with contextlib.suppress(FileNotFoundError):
        os.unlink(out / partial_name)
    return out / csv_name

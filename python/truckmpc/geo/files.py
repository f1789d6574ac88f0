"""Road files made from tracks: writing an import, and reading back what it recorded.

An imported road is an ordinary road CSV (``load_road`` reads it) with two additions:

- ``#`` comment lines ``key: value`` recording how it was made (:data:`~truckmpc.roads.gps.importer.NOTE_KEYS`:
  source, length, positions, resample, smoothing, grade limit, raw grade), after a line naming the
  command that wrote it;
- a fourth column ``raw_altitude_m`` [m], the resampled elevation before smoothing, on the same
  points and relative to the same start (``road plot`` overlays it; ``load_road`` ignores it).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from truckmpc.atomic import atomic_write_text
from truckmpc.errors import RoadError, read_user_text
from truckmpc.roads.csvfile import COLUMNS_COMMENT, data_lines, fixed_cell, header_cells
from truckmpc.roads.gps.importer import NOTE_KEYS, ImportedRoad, import_track
from truckmpc.roads.gpx import read_gpx
from truckmpc.roads.loader import load_road
from truckmpc.roads.profile import PathLike, RoadProfile

__all__ = ["RAW_COLUMN", "RoadWithNotes", "read_road_with_notes", "write_imported"]

RAW_COLUMN = "raw_altitude_m"
"""The extra column of an imported road: the elevation before smoothing [m]."""


@dataclass(frozen=True)
class RoadWithNotes:
    """A road with what its file says of its making: `notes` (``key: value`` lines, empty for a road
    not imported) and `raw_altitude_m` [m] (None when the file has no raw elevation)."""

    profile: RoadProfile
    raw_altitude_m: np.ndarray | None
    notes: tuple[str, ...]


def write_imported(imported: ImportedRoad, path: PathLike, command: str) -> None:
    """Write `imported` atomically as a road CSV with its notes and the raw column (module doc)."""
    profile = imported.profile
    grade = np.append(profile.slope, profile.slope[-1])
    lines = [f"# Imported by: {command}", *(f"# {note}" for note in imported.notes)]
    lines.append(f"# {COLUMNS_COMMENT}; {RAW_COLUMN} [m], the resampled elevation before smoothing")
    lines.append(f"distance_m,altitude_m,grade,{RAW_COLUMN}")
    rows = zip(profile.distance_m, profile.altitude_m, grade, imported.raw_altitude_m, strict=True)
    lines += [f"{d:.3f},{fixed_cell(h)},{fixed_cell(g)},{raw:.3f}" for d, h, g, raw in rows]
    atomic_write_text(path, "\n".join(lines) + "\n")


def read_road_with_notes(path: PathLike) -> RoadWithNotes:
    """A road file (CSV, or GPX imported with the defaults) with its notes and raw elevation."""
    path = Path(path)
    if path.suffix.lower() == ".gpx":
        imported = import_track(read_gpx(path))
        return RoadWithNotes(imported.profile, imported.raw_altitude_m, imported.notes)
    profile = load_road(path)
    text = read_user_text(path, str(path), "a CSV file", RoadError, encoding="utf-8-sig")
    comments = [line.strip()[1:].strip() for line in text.splitlines() if line.strip().startswith("#")]
    notes = tuple(line for line in comments if line.split(":", 1)[0] in NOTE_KEYS)
    return RoadWithNotes(profile, _raw_column(path, text, profile), notes)


def _raw_column(path: Path, text: str, profile: RoadProfile) -> np.ndarray | None:
    """The `raw_altitude_m` column of a road CSV, or None if it has none or a cell is not a number."""
    rows = [line for _, line in data_lines(text)]
    header = header_cells(rows[0])
    if RAW_COLUMN not in header:
        return None
    column = header.index(RAW_COLUMN)
    try:
        raw = np.array([float(row.split(",")[column]) for row in rows[1:]])
    except (ValueError, IndexError):
        raise RoadError(f"{path}: column {RAW_COLUMN!r}: expected a number on every row") from None
    if raw.shape != profile.altitude_m.shape or not all(math.isfinite(v) for v in raw):
        raise RoadError(f"{path}: column {RAW_COLUMN!r}: expected a finite number on every row")
    return raw

"""Read a plain ``lat,lon,ele`` table (a track exported from a map or a terrain model) as a track.

Format: `#` comment lines and blank lines ignored; a header naming the latitude (``lat`` or
``latitude``) [deg], longitude (``lon``, ``lng`` or ``longitude``) [deg] and elevation (``ele``,
``elevation``, ``alt`` or ``altitude``, optionally with an ``_m`` suffix) [m] columns in any order,
other columns ignored; then one point per row, in travel order. Cells are numbers; an empty
elevation cell is a missing elevation (refused, like a GPX point without ``<ele>``).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from truckmpc.errors import RoadError, read_user_text
from truckmpc.roads.csvfile import data_lines, header_cells, number_cell
from truckmpc.roads.gps.track import Track

__all__ = ["read_latlon_csv"]

_NAMES = {
    "lat": ("lat", "latitude"),
    "lon": ("lon", "lng", "longitude"),
    "ele": ("ele", "elevation", "alt", "altitude", "ele_m", "elevation_m", "alt_m", "altitude_m"),
}


def read_latlon_csv(path: Path) -> Track:
    """The points of a ``lat,lon,ele`` CSV table (format in the module doc)."""
    where = str(path)
    text = read_user_text(path, where, "a CSV file", RoadError, encoding="utf-8-sig")
    rows = data_lines(text)
    if not rows:
        raise RoadError(f"{where}: expected a header with columns lat, lon and ele, got an empty file")
    index = _header(where, *rows[0])
    width = len(rows[0][1].split(","))
    values: dict[str, list[float]] = {name: [] for name in _NAMES}
    for number, line in rows[1:]:
        cells = line.split(",")
        if len(cells) != width:
            raise RoadError(f"{where}:{number}: expected {width} columns, got {len(cells)}")
        for name, column in index.items():
            values[name].append(_cell(where, number, name, cells[column].strip()))
    return Track(
        where=where,
        kind="table rows",
        lat_deg=np.array(values["lat"], dtype=np.float64),
        lon_deg=np.array(values["lon"], dtype=np.float64),
        ele_m=np.array(values["ele"], dtype=np.float64),
        time_s=np.full(len(rows) - 1, np.nan),
        line=np.array([number for number, _ in rows[1:]], dtype=np.int64),
    )


def _header(where: str, number: int, line: str) -> dict[str, int]:
    """Column index of lat, lon and ele in the header line."""
    columns = [cell.lower() for cell in header_cells(line)]
    index = {}
    for name, aliases in _NAMES.items():
        found = [i for i, column in enumerate(columns) if column in aliases]
        if len(found) != 1:
            raise RoadError(
                f"{where}:{number}: expected a header with one column each of lat, lon and ele, got {line[:80]!r}"
            )
        index[name] = found[0]
    return index


def _cell(where: str, number: int, name: str, text: str) -> float:
    """The number in a cell; an empty elevation is NaN (a missing elevation, refused later)."""
    if name == "ele" and not text:
        return math.nan
    return number_cell(where, number, repr(name), text)

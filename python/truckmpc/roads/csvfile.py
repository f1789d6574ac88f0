"""Road profile CSV files: reading and writing (:func:`truckmpc.roads.loader.load_road` and
:func:`~truckmpc.roads.loader.write_road` call these), and the CSV text helpers the other table
formats share (:mod:`~truckmpc.roads.vdri`, :mod:`~truckmpc.roads.latlon`).

Format: `#` comment lines, blank lines ignored; a header naming `distance_m` and `altitude_m` and/or
`grade`, optionally `target_speed_kmh` and `stop_s`; other columns are ignored. With only `grade`,
the grade on a row is that of the segment starting at the row, and the altitude is its integral.
With both, the altitude is used. A row's `target_speed_kmh` is the target speed [km/h] from that
row to the next; its `stop_s` the duration [s] of a stop at the row (0: none), as a VECTO driving
cycle has them (:mod:`truckmpc.roads.vdri`).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from truckmpc.atomic import atomic_write_text
from truckmpc.errors import RoadError, read_user_text
from truckmpc.roads.profile import (
    GRADE_CHECK,
    MAX_ABS_DISTANCE_M,
    MAX_GRADE,
    MAX_LENGTH_M,
    MAX_TARGET_KMH,
    PathLike,
    RoadProfile,
    Stop,
    altitude_from_grade,
)

__all__ = ["COLUMNS_COMMENT", "OPTIONAL_COLUMNS_COMMENT", "read_road_csv", "write_road_csv"]

COLUMNS_COMMENT = "distance_m [m]; altitude_m [m], relative; grade [-] of the segment starting at the row (0.01 = 1 %)"
"""The comment line naming the columns of a written road CSV, with their units."""

OPTIONAL_COLUMNS_COMMENT = {
    "target_speed_kmh": "target_speed_kmh [km/h] from the row to the next",
    "stop_s": "stop_s [s], a stop of that duration at the row (0 = none)",
}
"""The comment the writer adds for each optional column it writes."""

_KNOWN = ("distance_m", "altitude_m", "grade", "target_speed_kmh", "stop_s")


def read_road_csv(path: PathLike) -> RoadProfile:
    """Read a road profile CSV (format in the module doc); errors name the file and line."""
    path = Path(path)
    where = str(path)
    text = read_user_text(path, where, "a CSV file", RoadError, encoding="utf-8-sig")
    lines = data_lines(text)
    if not lines:
        raise RoadError(f"{where}: no header line (expected columns distance_m and altitude_m and/or grade)")
    columns = _header(where, *lines[0])
    data = _rows(where, columns, lines[1:])
    distance = np.array(data["distance_m"])
    if "altitude_m" in data:
        altitude = np.array(data["altitude_m"])
    else:
        altitude = altitude_from_grade(distance, np.array(data["grade"]))
    targets = np.array(data["target_speed_kmh"]) if "target_speed_kmh" in data else None
    stops = tuple(Stop(d, t) for d, t in zip(data["distance_m"], data.get("stop_s", ()), strict=False) if t > 0)
    return RoadProfile(path.stem, distance, altitude, where, targets, stops)


def _header(where: str, number: int, line: str) -> list[str]:
    columns = header_cells(line)
    if "distance_m" not in columns or not {"altitude_m", "grade"} & set(columns):
        raise RoadError(
            f"{where}:{number}: expected a header with columns distance_m and altitude_m and/or grade, "
            f"got {line[:80]!r}"
        )
    return columns


def _rows(where: str, columns: list[str], lines: list[tuple[int, str]]) -> dict[str, list[float]]:
    """The values of each known column present, checked row by row."""
    wanted = [name for name in _KNOWN if name in columns]
    index = {name: columns.index(name) for name in wanted}
    data: dict[str, list[float]] = {name: [] for name in wanted}
    for number, line in lines:
        cells = line.split(",")
        if len(cells) != len(columns):
            raise RoadError(f"{where}:{number}: expected {len(columns)} columns, got {len(cells)}")
        for name in wanted:
            data[name].append(_cell(where, number, name, cells[index[name]]))
        _check_row(where, number, data)
    if len(data["distance_m"]) < 2:
        raise RoadError(f"{where}: expected at least two data rows, got {len(data['distance_m'])}")
    return data


def data_lines(text: str) -> list[tuple[int, str]]:
    """The (1-based line number, stripped line) of each line of a CSV text that is neither blank
    nor a ``#`` comment."""
    lines = [(number, line.strip()) for number, line in enumerate(text.splitlines(), start=1)]
    return [(number, line) for number, line in lines if line and not line.startswith("#")]


def header_cells(line: str) -> list[str]:
    """The names in a CSV header line, spaces and double quotes around each taken off."""
    return [cell.strip().strip('"').strip() for cell in line.split(",")]


def number_cell(where: str, number: int, column: str, text: str) -> float:
    """The finite number in cell `text` of line `number`; errors name the file, line and `column`."""
    text = text.strip()
    try:
        value = float(text)
    except ValueError:
        raise RoadError(f"{where}:{number}: column {column}: expected a number, got {text!r}") from None
    if not math.isfinite(value):
        raise RoadError(f"{where}:{number}: column {column}: expected a finite number, got {text!r}")
    return value


def _cell(where: str, number: int, name: str, text: str) -> float:
    value = number_cell(where, number, repr(name), text)
    if name == "distance_m" and abs(value) > MAX_ABS_DISTANCE_M:
        raise RoadError(f"{where}:{number}: column {name!r}: expected at most {MAX_ABS_DISTANCE_M:g} m, got {text!r}")
    if name == "target_speed_kmh" and not 0 < value <= MAX_TARGET_KMH:
        raise RoadError(
            f"{where}:{number}: column {name!r}: expected a speed in (0, {MAX_TARGET_KMH:g}] km/h, got {text!r}"
        )
    if name == "stop_s" and value < 0:
        raise RoadError(f"{where}:{number}: column {name!r}: expected a duration >= 0 s (0: no stop), got {text!r}")
    return value


def _check_row(where: str, number: int, data: dict[str, list[float]]) -> None:
    """Checks of the newest row against the previous one: increasing distance, |slope| <= 30 %."""
    distance = data["distance_m"]
    uses_grade = "altitude_m" not in data
    if uses_grade and abs(data["grade"][-1]) > GRADE_CHECK:
        raise RoadError(
            f"{where}:{number}: column 'grade': expected |grade| <= {MAX_GRADE:g}, got {data['grade'][-1]:g}"
        )
    if len(distance) < 2:
        return
    if distance[-1] - distance[0] > MAX_LENGTH_M:
        raise RoadError(
            f"{where}:{number}: column 'distance_m': expected a road of at most {MAX_LENGTH_M:g} m from the first "
            f"row's {distance[0]:g}, got {distance[-1]:g}"
        )
    if not distance[-1] > distance[-2]:
        raise RoadError(
            f"{where}:{number}: column 'distance_m': expected more than the previous row's {distance[-2]:g}, "
            f"got {distance[-1]:g}"
        )
    if not uses_grade:
        slope = (data["altitude_m"][-1] - data["altitude_m"][-2]) / (distance[-1] - distance[-2])
        if abs(slope) > GRADE_CHECK:
            raise RoadError(
                f"{where}:{number}: column 'altitude_m': slope from the previous row is {slope:.4g}, "
                f"expected |slope| <= {MAX_GRADE:g}"
            )


def write_road_csv(profile: RoadProfile, path: PathLike, comments: Sequence[str] = ()) -> None:
    """Write `profile` atomically as CSV: `# comment` lines, then `distance_m,altitude_m,grade`
    rows (%.3f m, %.6f m, %.6f), plus `target_speed_kmh` (%.6g) if the road has target speeds and
    `stop_s` (%.6g; 0 = no stop) if it has stops, each with a comment line saying what it holds; a
    row's grade is that of the segment starting there, the last row repeats the previous one."""
    distance = [f"{d:.3f}" for d in profile.distance_m]
    if any(float(b) <= float(a) for a, b in itertools.pairwise(distance)):
        raise RoadError(f"{path}: points closer than 1 mm cannot be written with 1 mm resolution")
    grade = np.append(profile.slope, profile.slope[-1])
    lines = [f"# {line}".rstrip() for comment in comments for line in str(comment).splitlines() or [""]]
    header = ["distance_m", "altitude_m", "grade"]
    rows = [f"{d},{fixed_cell(h)},{fixed_cell(g)}" for d, h, g in zip(distance, profile.altitude_m, grade, strict=True)]
    for name, values in _optional_columns(profile).items():
        lines.append(f"# {OPTIONAL_COLUMNS_COMMENT[name]}")
        header.append(name)
        rows = [f"{row},{value:.6g}" for row, value in zip(rows, values, strict=True)]
    lines.append(",".join(header))
    atomic_write_text(path, "\n".join(lines + rows) + "\n")


def _optional_columns(profile: RoadProfile) -> dict[str, np.ndarray]:
    """The optional columns `profile` needs: its target speeds [km/h], its stops' durations [s] per row."""
    columns = {}
    if profile.target_speed_kmh is not None:
        columns["target_speed_kmh"] = profile.target_speed_kmh
    if profile.stops:
        stop_s = np.zeros(profile.distance_m.size)
        for stop in profile.stops:
            stop_s[np.searchsorted(profile.distance_m, stop.distance_m)] = stop.duration_s
        columns["stop_s"] = stop_s
    return columns


def fixed_cell(value: float) -> str:
    """`value` with 6 decimals, without a minus sign on zero."""
    text = f"{value:.6f}"
    return "0.000000" if text == "-0.000000" else text

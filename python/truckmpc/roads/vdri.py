"""VECTO distance-based driving cycles (`.vdri`) read as road profiles with target speeds and stops.

A cycle is a CSV file: `#` comments (whole lines, or the rest of a line) and blank lines are
ignored; the header names the columns `<s>` (distance), `<v>` (target speed), `<grad>` (grade in %)
and `<stop>` (stop duration), each optionally followed by its unit in brackets (`<v> [km/h]`);
other columns are ignored. Units taken: `<s>` in m or km, `<v>` in km/h or m/s, `<grad>` in %,
`<stop>` in s (a column without a unit is in the first of these). `<s>` and `<v>` are required;
without `<grad>` the road is flat, without `<stop>` it has no stops.

A row's target speed and grade hold from that row to the next; the altitude [m] is the integral of
the grade. A row with a stop time > 0 is a stop there (whatever its `<v>`). The truck cannot launch
from standstill or brake to it in this model, so the target speed 0 of a launch (the segments after
a stop) or an approach (before one) becomes the next non-zero target speed of its stop-free leg (the
previous one at the leg's end); a target of 0 with no stop, between non-zero targets of one leg, is
an error (a standstill the cycle gives no duration for). How the legs are driven: :mod:`truckmpc.legs`.
"""

from __future__ import annotations

import itertools
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from truckmpc.errors import RoadError, read_user_text
from truckmpc.roads.csvfile import COLUMNS_COMMENT, header_cells, number_cell
from truckmpc.roads.profile import (
    GRADE_CHECK,
    MAX_ABS_DISTANCE_M,
    MAX_GRADE,
    MAX_TARGET_KMH,
    PathLike,
    RoadProfile,
    Stop,
    altitude_from_grade,
)
from truckmpc.roads.stops import STOPS_NOTE, leg_bounds
from truckmpc.units import KMH_PER_MPS, M_PER_KM, PCT_PER_FRACTION

__all__ = ["SUFFIX", "UNITS", "cycle_summary", "import_comments", "read_vdri"]

SUFFIX = ".vdri"
"""The file name ending of a VECTO driving cycle."""

UNITS: dict[str, dict[str, float]] = {
    "s": {"m": 1.0, "km": M_PER_KM},
    "v": {"km/h": 1.0, "m/s": KMH_PER_MPS},
    "grad": {"%": 1.0 / PCT_PER_FRACTION},
    "stop": {"s": 1.0},
}
"""Per column, the units taken and the factor to the road's unit (m, km/h, grade fraction, s); the
first is the column's unit when none is given."""

_REQUIRED = ("s", "v")
_CELL = re.compile(r"^<?\s*([A-Za-z_][\w-]*)\s*>?\s*(?:\[([^\]]*)\])?$")


@dataclass(frozen=True)
class _Column:
    """A column of the cycle: its index in the row and the factor to the road's unit."""

    index: int
    factor: float


@dataclass
class _Cycle:
    """The rows of a cycle in the road's units, with their line numbers."""

    line: list[int]
    s_m: list[float]
    v_kmh: list[float]
    grade: list[float]
    stop_s: list[float]


def read_vdri(path: PathLike) -> RoadProfile:
    """The road of a VECTO distance-based cycle (format in the module doc), named after the file;
    errors are one line naming the file and line."""
    path = Path(path)
    where = str(path)
    text = read_user_text(path, where, "a VECTO driving cycle (.vdri)", RoadError, encoding="utf-8-sig")
    lines = [(n, line.split("#", 1)[0].strip()) for n, line in enumerate(text.splitlines(), start=1)]
    lines = [(n, line) for n, line in lines if line]
    if not lines:
        raise RoadError(f"{where}: no header line (expected columns <s>, <v>, <grad>, <stop>)")
    columns = _header(where, *lines[0])
    cycle = _rows(where, columns, lines[1:])
    distance_m = np.array(cycle.s_m)
    altitude_m = altitude_from_grade(distance_m, np.array(cycle.grade))
    stops = tuple(Stop(s, t) for s, t in zip(cycle.s_m, cycle.stop_s, strict=True) if t > 0)
    targets = _filled_targets(where, cycle, [i for i, t in enumerate(cycle.stop_s) if t > 0])
    return RoadProfile(path.stem, distance_m, altitude_m, where, targets, stops)


def _header(where: str, number: int, line: str) -> dict[str, _Column]:
    """The known columns of the header line, with their units checked."""
    columns: dict[str, _Column] = {}
    for index, cell in enumerate(header_cells(line)):
        match = _CELL.match(cell)
        if match is None:
            continue
        name, unit = match.group(1).lower(), (match.group(2) or "").strip()
        if name not in UNITS:
            continue
        if name in columns:
            raise RoadError(f"{where}:{number}: column <{name}>: expected it once in the header, got it twice")
        columns[name] = _Column(index, _factor(where, number, name, unit))
    missing = [f"<{name}>" for name in _REQUIRED if name not in columns]
    if missing:
        raise RoadError(
            f"{where}:{number}: expected a distance-based cycle's header with columns <s>, <v> (and <grad>, <stop>), "
            f"missing {', '.join(missing)} in {line[:80]!r}"
        )
    return columns


def _factor(where: str, number: int, name: str, unit: str) -> float:
    """The factor from `unit` to the road's unit for column `name`; the default unit when empty."""
    units = UNITS[name]
    if not unit:
        return next(iter(units.values()))
    for known, factor in units.items():
        if unit.lower() == known:
            return factor
    expected = " or ".join(f"[{known}]" for known in units)
    raise RoadError(f"{where}:{number}: column <{name}>: expected the unit {expected}, got [{unit}]")


def _rows(where: str, columns: dict[str, _Column], lines: list[tuple[int, str]]) -> _Cycle:
    """The rows, converted and checked one by one."""
    width = 1 + max(column.index for column in columns.values())
    cycle = _Cycle([], [], [], [], [])
    for number, line in lines:
        cells = line.split(",")
        if len(cells) < width:
            raise RoadError(f"{where}:{number}: expected at least {width} columns, got {len(cells)}")
        values = {name: _cell(where, number, name, cells[c.index]) * c.factor for name, c in columns.items()}
        _check_row(where, number, values, cycle.s_m[-1] if cycle.s_m else None)
        cycle.line.append(number)
        cycle.s_m.append(values["s"])
        cycle.v_kmh.append(values["v"])
        cycle.grade.append(values.get("grad", 0.0))
        cycle.stop_s.append(values.get("stop", 0.0))
    if len(cycle.s_m) < 2:
        raise RoadError(f"{where}: expected at least two data rows, got {len(cycle.s_m)}")
    return cycle


def _cell(where: str, number: int, name: str, text: str) -> float:
    return number_cell(where, number, f"<{name}>", text)


def _check_row(where: str, number: int, values: dict[str, float], previous_m: float | None) -> None:
    """A row's values in the road's units: distance increasing and in range, target speed in
    [0, MAX_TARGET_KMH] km/h, |grade| <= MAX_GRADE, stop time >= 0 s."""
    s_m, v_kmh = values["s"], values["v"]
    if abs(s_m) > MAX_ABS_DISTANCE_M:
        raise RoadError(f"{where}:{number}: column <s>: expected at most {MAX_ABS_DISTANCE_M:g} m, got {s_m:g} m")
    if previous_m is not None and not s_m > previous_m:
        raise RoadError(
            f"{where}:{number}: column <s>: expected more than the previous row's {previous_m:g} m, got {s_m:g} m"
        )
    if not 0 <= v_kmh <= MAX_TARGET_KMH:
        raise RoadError(
            f"{where}:{number}: column <v>: expected a speed in [0, {MAX_TARGET_KMH:g}] km/h, got {v_kmh:g}"
        )
    grade = values.get("grad", 0.0)
    if abs(grade) > GRADE_CHECK:
        limit_pct = MAX_GRADE * PCT_PER_FRACTION
        raise RoadError(
            f"{where}:{number}: column <grad>: expected |grade| <= {limit_pct:g} %, got {grade * PCT_PER_FRACTION:g} %"
        )
    if values.get("stop", 0.0) < 0:
        raise RoadError(f"{where}:{number}: column <stop>: expected a stop time >= 0 s, got {values['stop']:g} s")


def _filled_targets(where: str, cycle: _Cycle, stop_rows: list[int]) -> np.ndarray:
    """The target speed [km/h] per point, the zeros of each stop-free leg's launch and approach
    filled with the leg's next (at its end: previous) non-zero target; the last point's is the last
    segment's."""
    v_kmh = np.array(cycle.v_kmh)
    bounds = sorted({0, len(v_kmh) - 1, *stop_rows})
    for first, end in itertools.pairwise(bounds):
        v_kmh[first:end] = _filled_leg(where, cycle, first, v_kmh[first:end])
    v_kmh[-1] = v_kmh[-2]
    return v_kmh


def _filled_leg(where: str, cycle: _Cycle, first: int, v_kmh: np.ndarray) -> np.ndarray:
    """The targets of one leg's segments (rows `first`, ...) with the leading and trailing zeros filled."""
    moving = np.flatnonzero(v_kmh > 0)
    if moving.size == 0:
        end_m = cycle.s_m[first + v_kmh.size]
        raise RoadError(
            f"{where}:{cycle.line[first]}: column <v>: expected a target speed > 0 somewhere between the stops "
            f"at {cycle.s_m[first]:g} m and {end_m:g} m, got only 0"
        )
    inner = np.flatnonzero(v_kmh[moving[0] : moving[-1]] == 0)
    if inner.size:
        row = first + int(moving[0] + inner[0])
        raise RoadError(
            f"{where}:{cycle.line[row]}: column <v>: expected a target speed > 0 or a stop time > 0 (a stop), "
            f"got 0 with no stop between non-zero targets"
        )
    filled = v_kmh.copy()
    filled[: moving[0]] = v_kmh[moving[0]]
    filled[moving[-1] + 1 :] = v_kmh[moving[-1]]
    return filled


def import_comments(profile: RoadProfile, command: str) -> list[str]:
    """The comment lines of a road CSV imported from a cycle by `command`: where it came from, how
    the cycle was read, its stops [m: s] and stop-free legs [m]."""
    stops = ", ".join(f"{stop.distance_m:g}: {stop.duration_s:g}" for stop in profile.stops) or "none"
    legs = ", ".join(f"{start_m:g}-{end_m:g}" for start_m, end_m in leg_bounds(profile))
    return [
        f"Imported from the VECTO driving cycle {profile.source} by: {command}",
        "Altitude integrated from <grad>; a zero <v> (a launch or an approach) takes the next non-zero target "
        "speed of its stop-free leg (the previous one at the leg's end).",
        f"Stops [m: s]: {stops}. Stop-free legs [m]: {legs}.",
        f"When simulated: {STOPS_NOTE}.",
        COLUMNS_COMMENT,
    ]


def cycle_summary(profile: RoadProfile) -> str:
    """One line on an imported cycle: length, legs, stops, the target speeds found."""
    total_s = profile.stop_time_s
    targets = profile.target_speed_kmh
    speeds = "none" if targets is None else ", ".join(f"{v:g}" for v in np.unique(targets)) + " km/h"
    return (
        f"{profile.name}: {profile.length_m / M_PER_KM:.2f} km, {len(leg_bounds(profile))} stop-free legs, "
        f"{len(profile.stops)} stops ({total_s:g} s, not simulated), target speeds {speeds}"
    )

"""Generated roads: the thesis's artificial sections (sections 1.2, 6.2, 6.3), roads joined from
parts, and the bundled test track."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from truckmpc.errors import RoadError
from truckmpc.roads.profile import MAX_GRADE, MAX_LENGTH_M, RoadProfile, Stop, step_grid
from truckmpc.units import PCT_PER_FRACTION

__all__ = ["SECTION_KINDS", "concatenate", "default_test_track", "make_section"]

SECTION_KINDS: dict[str, tuple[float, float]] = {
    "flat": (0.0, 0.0),
    "hill": (500.0, 1500.0),
    "crest": (500.0, 1000.0),
    "depression": (500.0, 1000.0),
}
"""Section kinds and their default flat lead-in and run-out lengths [m] (thesis sections 6.2, 6.3)."""


def make_section(
    kind: str,
    length_m: float,
    slope_pct: float | None = None,
    lead_m: float | None = None,
    tail_m: float | None = None,
    step_m: float = 25.0,
) -> RoadProfile:
    """An artificial road section: `lead_m` flat, the feature over `length_m`, `tail_m` flat.

    Kinds: `flat` (no slope); `hill`, constant slope `slope_pct` [%] (negative: a descent);
    `crest`, slope falling linearly from +|slope_pct| to -|slope_pct|; `depression`, rising from
    -|slope_pct| to +|slope_pct|. Lead and tail default to the thesis's (`SECTION_KINDS`).
    Points every `step_m` metres plus the feature's ends (and a crest's top, a depression's bottom);
    altitudes are the exact integral of the slope law, so each segment's differenced slope is the
    mean slope over it.
    """
    where = f"section {kind!r}"
    if kind not in SECTION_KINDS:
        raise RoadError(f"{where}: unknown kind (expected one of {', '.join(SECTION_KINDS)})")
    default_lead, default_tail = SECTION_KINDS[kind]
    lead = default_lead if lead_m is None else lead_m
    tail = default_tail if tail_m is None else tail_m
    _check_positive(where, "length_m", length_m)
    _check_positive(where, "step_m", step_m)
    for name, value in (("lead_m", lead), ("tail_m", tail)):
        if not (math.isfinite(value) and value >= 0):
            raise RoadError(f"{where}: {name}: expected a number >= 0, got {value!r}")
    if length_m + lead + tail > MAX_LENGTH_M:
        raise RoadError(
            f"{where}: length_m: expected lead_m + length_m + tail_m of at most {MAX_LENGTH_M:g} m, "
            f"got {length_m + lead + tail:g} m"
        )
    start_grade, end_grade = _slope_law(where, kind, slope_pct)
    # The feature's ends and, for a crest or depression, its top or bottom are always points.
    middle = [lead + length_m / 2] if start_grade != end_grade else []
    breaks = np.array([0.0, lead, *middle, lead + length_m, lead + length_m + tail])
    grid = step_grid(0.0, float(breaks[-1]), step_m)
    keep = np.min(np.abs(grid[:, None] - breaks[None, :]), axis=1) > 1e-3
    distance = np.unique(np.concatenate([grid[keep], breaks]))
    x = np.clip(distance - lead, 0.0, length_m)
    altitude = start_grade * x + (end_grade - start_grade) * x**2 / (2.0 * length_m)
    return RoadProfile(_section_name(kind, length_m, slope_pct, lead, tail), distance, altitude, None)


def _check_positive(where: str, name: str, value: float) -> None:
    if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
        raise RoadError(f"{where}: {name}: expected a number > 0, got {value!r}")


def _slope_law(where: str, kind: str, slope_pct: float | None) -> tuple[float, float]:
    """Grades [-] at the start and end of the feature."""
    if kind == "flat":
        if slope_pct not in (None, 0, 0.0):
            raise RoadError(f"{where}: slope_pct: expected none for a flat section, got {slope_pct!r}")
        return 0.0, 0.0
    limit_pct = PCT_PER_FRACTION * MAX_GRADE
    if slope_pct is None or not math.isfinite(slope_pct) or not 0 < abs(slope_pct) <= limit_pct:
        raise RoadError(f"{where}: slope_pct: expected a non-zero slope within +-{limit_pct:g} %, got {slope_pct!r}")
    grade = slope_pct / PCT_PER_FRACTION
    return {"hill": (grade, grade), "crest": (abs(grade), -abs(grade)), "depression": (-abs(grade), abs(grade))}[kind]


def _section_name(kind: str, length_m: float, slope_pct: float | None, lead_m: float, tail_m: float) -> str:
    """E.g. `hill_L500_A3.5`, `hill_L300_A-3` (a descent), `crest_L1500_A2`, `flat_L1000`;
    a non-default lead or tail is appended as `_lead200`, `_tail800`."""
    name = f"{kind}_L{length_m:g}"
    if kind != "flat" and slope_pct is not None:
        name += f"_A{(slope_pct if kind == 'hill' else abs(slope_pct)):g}"
    default_lead, default_tail = SECTION_KINDS[kind]
    name += f"_lead{lead_m:g}" if lead_m != default_lead else ""
    name += f"_tail{tail_m:g}" if tail_m != default_tail else ""
    return name


def concatenate(parts: Sequence[RoadProfile], name: str) -> RoadProfile:
    """One road made of `parts` driven in order, each continuing where the previous one ends
    (distance and altitude shifted to join; stops move with their parts, and two stops meeting at a
    join become one stop of their summed duration)."""
    if not parts:
        raise RoadError(f"{name}: expected at least one part to concatenate")
    with_targets = [part.target_speed_kmh is not None for part in parts]
    if any(with_targets) and not all(with_targets):
        raise RoadError(f"{name}: expected target speeds on every part or on none")
    distance, altitude = [parts[0].distance_m], [parts[0].altitude_m]
    targets = [part.target_speed_kmh[:-1] for part in parts if part.target_speed_kmh is not None]
    stops = list(parts[0].stops)
    for part in parts[1:]:
        join_m = float(distance[-1][-1])
        shift_m = join_m - part.distance_m[0]
        lift_m = altitude[-1][-1] - part.altitude_m[0]
        distance.append(part.distance_m[1:] + shift_m)
        altitude.append(part.altitude_m[1:] + lift_m)
        stops = _joined_stops(stops, part.stops, join_m, float(part.distance_m[0]), shift_m)
    joined = np.concatenate([*targets, targets[-1][-1:]]) if targets else None
    return RoadProfile(name, np.concatenate(distance), np.concatenate(altitude), None, joined, tuple(stops))


def _joined_stops(
    stops: list[Stop], more: Sequence[Stop], join_m: float, part_start_m: float, shift_m: float
) -> list[Stop]:
    """`stops` followed by a part's `more`, shifted by `shift_m` [m]; a stop at the part's start
    lands exactly on the join `join_m` [m] and merges with a stop already there."""
    for stop in more:
        at_m = join_m if stop.distance_m == part_start_m else float(stop.distance_m + shift_m)
        if stops and stops[-1].distance_m == at_m:
            stops[-1] = Stop(at_m, stops[-1].duration_s + stop.duration_s)
        else:
            stops.append(Stop(at_m, stop.duration_s))
    return stops


def default_test_track() -> RoadProfile:
    """The bundled 8.5 km test track: the thesis's features separated by 1000 m of flat road
    (500 m flat, 500 m at +3.5 %, 500 m at -3 %, a 1500 m crest and a 1500 m depression at 2 %)."""
    flat = make_section("flat", 1000)
    parts = [
        make_section("flat", 500),
        make_section("hill", 500, 3.5, lead_m=0, tail_m=0),
        flat,
        make_section("hill", 500, -3.0, lead_m=0, tail_m=0),
        flat,
        make_section("crest", 1500, 2.0, lead_m=0, tail_m=0),
        flat,
        make_section("depression", 1500, 2.0, lead_m=0, tail_m=0),
        flat,
    ]
    return concatenate(parts, "test-track")

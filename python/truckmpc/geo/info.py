"""Figures of a road for ``truckmpc road info``: length, climb and descent, a grade histogram, the
steepest stretches, and the smoothing its import applied."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from truckmpc.roads.profile import RoadProfile
from truckmpc.units import M_PER_KM, PCT_PER_FRACTION

__all__ = ["HISTOGRAM_EDGES_PCT", "STRETCH_M", "RoadInfo", "format_info", "road_info", "steepest_stretches"]

HISTOGRAM_EDGES_PCT = (-6.0, -4.0, -3.0, -2.0, -1.0, 1.0, 2.0, 3.0, 4.0, 6.0)
"""Inner bin edges of the grade histogram [%]; the outer bins are open."""

STRETCH_M = 500.0
"""Length [m] of the stretches over which the steepest climbs and descents are found."""

_STRETCH_STEP_M = 10.0


@dataclass(frozen=True)
class RoadInfo:
    """What ``road info`` prints. Lengths [m], grades [-]; `histogram` is (lower [%] or None, upper [%]
    or None, share of the length [-]) per bin; `climbs`, `descents` are (start [m], end [m], mean
    grade [-]) of the steepest stretches, steepest first."""

    name: str
    length_m: float
    points: int
    climb_m: float
    descent_m: float
    min_grade: float
    max_grade: float
    histogram: tuple[tuple[float | None, float | None, float], ...]
    climbs: tuple[tuple[float, float, float], ...]
    descents: tuple[tuple[float, float, float], ...]
    notes: tuple[str, ...]


def road_info(profile: RoadProfile, notes: tuple[str, ...] = (), stretches: int = 3) -> RoadInfo:
    """The figures of `profile`; `notes` are the import's ``key: value`` lines, if any."""
    rise_m = np.diff(profile.altitude_m)
    return RoadInfo(
        name=profile.name,
        length_m=profile.length_m,
        points=int(profile.distance_m.size),
        climb_m=float(np.sum(rise_m[rise_m > 0])),
        descent_m=float(-np.sum(rise_m[rise_m < 0])),
        min_grade=float(np.min(profile.slope)),
        max_grade=float(np.max(profile.slope)),
        histogram=_histogram(profile),
        climbs=tuple(steepest_stretches(profile, stretches, uphill=True)),
        descents=tuple(steepest_stretches(profile, stretches, uphill=False)),
        notes=notes,
    )


def _histogram(profile: RoadProfile) -> tuple[tuple[float | None, float | None, float], ...]:
    """Share of the length in each grade bin (edges :data:`HISTOGRAM_EDGES_PCT`)."""
    edges = np.array(HISTOGRAM_EDGES_PCT) / PCT_PER_FRACTION
    bins = np.searchsorted(edges, profile.slope, side="right")
    weights = np.bincount(bins, weights=np.diff(profile.distance_m), minlength=edges.size + 1)
    lower: list[float | None] = [None, *HISTOGRAM_EDGES_PCT]
    upper: list[float | None] = [*HISTOGRAM_EDGES_PCT, None]
    return tuple((a, b, float(w / profile.length_m)) for a, b, w in zip(lower, upper, weights, strict=True))


def steepest_stretches(profile: RoadProfile, count: int, uphill: bool) -> list[tuple[float, float, float]]:
    """The `count` steepest non-overlapping climbs (or descents) of :data:`STRETCH_M` (the whole road
    if shorter), starting every 10 m, as (start [m], end [m], mean grade [-]), steepest first; only
    those that do climb (or descend)."""
    window_m = min(STRETCH_M, profile.length_m)
    start_m = np.arange(profile.distance_m[0], profile.distance_m[-1] - window_m + 1e-9, _STRETCH_STEP_M)
    rise_m = np.interp(start_m + window_m, profile.distance_m, profile.altitude_m) - np.interp(
        start_m, profile.distance_m, profile.altitude_m
    )
    grade = (rise_m if uphill else -rise_m) / window_m
    found: list[tuple[float, float, float]] = []
    # Steepest first; equal grades (to 1e-9) in road order, so a long even climb is cut from its start.
    for i in np.lexsort((start_m, -np.round(grade, 9))):
        if len(found) == count or grade[i] <= 0:
            break
        if all(abs(start_m[i] - a) >= window_m for a, _, _ in found):
            found.append((float(start_m[i]), float(start_m[i] + window_m), float(rise_m[i] / window_m)))
    return found


def format_info(info: RoadInfo) -> list[str]:
    """The lines ``road info`` prints."""
    lines = [
        f"road {info.name}: {info.length_m / M_PER_KM:.3f} km, {info.points} points",
        f"climb {info.climb_m:.1f} m, descent {info.descent_m:.1f} m",
        f"grade {PCT_PER_FRACTION * info.min_grade:+.2f} % to {PCT_PER_FRACTION * info.max_grade:+.2f} %",
        "grade histogram (share of the length):",
    ]
    for lower, upper, share in info.histogram:
        label = (
            f"< {upper:g} %" if lower is None else f">= {lower:g} %" if upper is None else f"{lower:g} to {upper:g} %"
        )
        lines.append(f"  {label:>12} {PCT_PER_FRACTION * share:6.1f} %  {'#' * round(50 * share)}")
    for what, found in (("climbs", info.climbs), ("descents", info.descents)):
        text = ", ".join(f"km {a / M_PER_KM:.2f}-{b / M_PER_KM:.2f} {PCT_PER_FRACTION * g:+.2f} %" for a, b, g in found)
        lines.append(f"steepest {what} over {STRETCH_M:g} m: {text or 'none'}")
    lines.append("import:" if info.notes else "import: none recorded (not made by truckmpc road import)")
    lines += [f"  {note}" for note in info.notes]
    return lines

"""From a track (GPX or ``lat,lon,ele`` table) to a road profile.

1. The points are checked (:func:`~truckmpc.roads.gps.track.checked`): a one-line error names the
   first bad point.
2. Logged positions (GPX track points) are smoothed (a spline of 40 m bandwidth) to take out GPS
   jitter, which would otherwise lengthen the road (:func:`~truckmpc.roads.gps.track.smoothed_positions`);
   route points and table rows, drawn on a map, are kept as they are.
3. Distance along the track is geodesic on WGS84
   (:func:`~truckmpc.roads.gps.track.cumulative_distance_m`).
4. The elevation is interpolated onto a uniform grid no finer than the source: the step is the
   median distance between the points (or a coarser `step_m`), stretched slightly so that a whole
   number of steps spans the track.
5. The altitude on that grid is smoothed (:mod:`truckmpc.roads.gps.smooth`; default: the cubic smoothing
   spline for an elevation noise of 2 m).
6. Grades beyond `grade_limit` are reported (sections and the steepest value), never clipped.

The result keeps the raw resampled altitude beside the smoothed one, and ``key: value`` notes of how
it was made (:data:`NOTE_KEYS`), which ``road import`` writes as the CSV's ``#`` comments.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from truckmpc.errors import RoadError
from truckmpc.roads.gps import DEFAULT_GRADE_LIMIT_PCT, DEFAULT_NOISE_M
from truckmpc.roads.gps.smooth import Smoothing
from truckmpc.roads.gps.track import POSITION_BANDWIDTH_M, Track, checked, cumulative_distance_m, smoothed_positions
from truckmpc.roads.profile import RoadProfile
from truckmpc.units import M_PER_KM, PCT_PER_FRACTION

__all__ = [
    "DEFAULT_GRADE_LIMIT",
    "DEFAULT_NOISE_M",
    "NOTE_KEYS",
    "ImportedRoad",
    "default_smoothing",
    "import_track",
    "steep_sections",
]

DEFAULT_GRADE_LIMIT = DEFAULT_GRADE_LIMIT_PCT / PCT_PER_FRACTION
"""|grade| [-] beyond which an imported road's grade is reported
(:data:`~truckmpc.roads.gps.DEFAULT_GRADE_LIMIT_PCT`)."""

NOTE_KEYS = ("source", "length", "positions", "resample", "smoothing", "grade limit", "raw grade")
"""The keys of an import's notes, in order."""


def default_smoothing() -> Smoothing:
    """The smoothing applied unless another is asked for: the spline for :data:`DEFAULT_NOISE_M`."""
    return Smoothing.for_noise("spline", DEFAULT_NOISE_M)


@dataclass(frozen=True)
class ImportedRoad:
    """A road made from a track: `profile` (smoothed, altitude relative to its start),
    `raw_altitude_m` [m] on the same points (resampled, unsmoothed, same reference), and `notes`,
    ``key: value`` lines recording how it was made (keys :data:`NOTE_KEYS`)."""

    profile: RoadProfile
    raw_altitude_m: np.ndarray
    notes: tuple[str, ...]


def import_track(
    track: Track,
    smoothing: Smoothing | None = None,
    step_m: float | None = None,
    grade_limit: float = DEFAULT_GRADE_LIMIT,
    position_bandwidth_m: float | None = None,
) -> ImportedRoad:
    """The road along `track` (see the module doc). `smoothing` defaults to
    :func:`default_smoothing`; `step_m` [m] must be no finer than the median point spacing (None:
    that spacing); `position_bandwidth_m` [m] (None: 40 m for track points, 0 otherwise)."""
    track = checked(track)
    smoothing = default_smoothing() if smoothing is None else smoothing
    if position_bandwidth_m is None:
        position_bandwidth_m = POSITION_BANDWIDTH_M if track.kind == "track points" else 0.0
    distance_m = cumulative_distance_m(*smoothed_positions(track.lat_deg, track.lon_deg, position_bandwidth_m))
    spacing_m = float(np.median(np.diff(distance_m)))
    grid_m = _grid_m(track, float(distance_m[-1]), spacing_m, step_m)
    grid_step_m = float(grid_m[1] - grid_m[0])
    raw_m = np.interp(grid_m, distance_m, track.ele_m)
    smooth_m = smoothing.apply(grid_step_m, raw_m)
    profile = RoadProfile(Path(track.where).stem, grid_m, smooth_m - smooth_m[0], track.where)
    positions = f"smoothing spline of bandwidth {position_bandwidth_m:g} m" if position_bandwidth_m > 0 else "as given"
    notes = (
        f"source: {track.where} ({track.size} {track.kind})",
        f"length: {distance_m[-1]:.1f} m, geodesic on the WGS84 ellipsoid (pyproj.Geod)",
        f"positions: {positions}",
        f"resample: {grid_step_m:.3f} m uniform steps (median point spacing {spacing_m:.2f} m)",
        f"smoothing: {smoothing.describe(grid_step_m)}",
        f"grade limit: {_limit_note(profile, grade_limit)}",
        f"raw grade: {_extent_pct(np.diff(raw_m) / grid_step_m)} before smoothing",
    )
    return ImportedRoad(profile, raw_m - smooth_m[0], notes)


def _grid_m(track: Track, length_m: float, spacing_m: float, step_m: float | None) -> np.ndarray:
    """Uniform points over [0, `length_m`], at least `spacing_m` (and `step_m`) apart."""
    if step_m is not None and not (math.isfinite(step_m) and step_m >= spacing_m):
        raise RoadError(
            f"{track.where}: step: expected at least the median point spacing {spacing_m:.2f} m "
            f"(no finer than the source), got {step_m!r}"
        )
    target_m = spacing_m if step_m is None else step_m
    steps = max(1, math.floor(length_m / target_m))
    return np.linspace(0.0, length_m, steps + 1)


def steep_sections(profile: RoadProfile, grade_limit: float) -> list[tuple[float, float, float]]:
    """(start [m], end [m], steepest grade [-]) of every run of segments with |grade| > `grade_limit`."""
    beyond = np.abs(profile.slope) > grade_limit
    edges = np.flatnonzero(np.diff(np.concatenate([[0], beyond.astype(np.int8), [0]])))
    sections = []
    for first, stop in zip(edges[::2], edges[1::2], strict=True):
        grades = profile.slope[first:stop]
        steepest = float(grades[np.argmax(np.abs(grades))])
        sections.append((float(profile.distance_m[first]), float(profile.distance_m[stop]), steepest))
    return sections


def _limit_note(profile: RoadProfile, grade_limit: float) -> str:
    sections = steep_sections(profile, grade_limit)
    head = f"|grade| <= {PCT_PER_FRACTION * grade_limit:g} % expected"
    if not sections:
        return f"{head}; none beyond"
    shown = ", ".join(
        f"km {a / M_PER_KM:.2f}-{b / M_PER_KM:.2f} ({PCT_PER_FRACTION * g:+.1f} %)" for a, b, g in sections[:5]
    )
    more = f" and {len(sections) - 5} more" if len(sections) > 5 else ""
    return f"{head}; {len(sections)} sections beyond, kept as they are: {shown}{more}"


def _extent_pct(grade: np.ndarray) -> str:
    low_pct, high_pct = PCT_PER_FRACTION * float(np.min(grade)), PCT_PER_FRACTION * float(np.max(grade))
    return f"{low_pct:+.1f} % to {high_pct:+.1f} %"

"""A GPS track as read from a file, its checks, and its length along the WGS84 ellipsoid.

A :class:`Track` is what every reader (:mod:`~truckmpc.roads.gpx`, :mod:`~truckmpc.roads.latlon`) hands
on: latitude [deg], longitude [deg] and elevation [m] per point, with the optional time [s] and the
line of the file each point came from, so that every complaint is one line ``FILE:LINE: ...``.

Distances are geodesic: :func:`segment_lengths_m` solves the inverse geodesic problem on the WGS84
ellipsoid (``pyproj.Geod``, Karney's algorithm, accurate to nanometres) between consecutive points,
not a flat-earth or spherical approximation (a sphere is off by up to 0.5 % along a meridian).
"""

from __future__ import annotations

import datetime as dt
from dataclasses import dataclass

import numpy as np
from pyproj import Geod
from scipy.interpolate import make_smoothing_spline

from truckmpc.errors import RoadError

__all__ = [
    "MIN_SEGMENT_M",
    "POSITION_BANDWIDTH_M",
    "WGS84",
    "Track",
    "checked",
    "cumulative_distance_m",
    "segment_lengths_m",
    "smoothed_positions",
]

WGS84 = Geod(ellps="WGS84")
"""The WGS84 ellipsoid, on which GPS positions are given."""

MIN_SEGMENT_M = 1e-3
"""Shortest accepted distance between consecutive points [m] (the 1 mm a road file resolves);
a shorter one is a repeated point, a zero-length segment."""


@dataclass(frozen=True)
class Track:
    """Points of a track in file order.

    `lat_deg`, `lon_deg` [deg]; `ele_m` [m] (NaN where the file has no elevation); `time_s` [s]
    since the epoch (NaN where a point has no time); `line` the file's line of each point (0 where
    not known); `where` the file name; `kind` what the points are ("track points", "route points",
    "table rows"), for messages and the record of an import.
    """

    where: str
    kind: str
    lat_deg: np.ndarray
    lon_deg: np.ndarray
    ele_m: np.ndarray
    time_s: np.ndarray
    line: np.ndarray

    @property
    def size(self) -> int:
        return int(self.lat_deg.size)

    def at(self, index: int) -> str:
        """``FILE:LINE`` of point `index` if its line is known, else ``FILE: point N`` (1-based)."""
        line = int(self.line[index])
        return f"{self.where}:{line}" if line > 0 else f"{self.where}: point {index + 1}"


def segment_lengths_m(lat_deg: np.ndarray, lon_deg: np.ndarray) -> np.ndarray:
    """Geodesic length [m] on WGS84 of each segment between consecutive points (n-1 values)."""
    _, _, length_m = WGS84.inv(lon_deg[:-1], lat_deg[:-1], lon_deg[1:], lat_deg[1:])
    return np.asarray(length_m, dtype=np.float64)


def cumulative_distance_m(lat_deg: np.ndarray, lon_deg: np.ndarray) -> np.ndarray:
    """Geodesic distance [m] of every point from the first, along the track."""
    return np.concatenate([[0.0], np.cumsum(segment_lengths_m(lat_deg, lon_deg))])


POSITION_BANDWIDTH_M = 40.0
"""Default bandwidth [m] of the smoothing spline applied to logged positions before measuring
lengths (:func:`smoothed_positions`)."""


def smoothed_positions(
    lat_deg: np.ndarray, lon_deg: np.ndarray, bandwidth_m: float = POSITION_BANDWIDTH_M
) -> tuple[np.ndarray, np.ndarray]:
    """Latitude and longitude [deg] with the point-to-point jitter of GPS taken out.

    Jitter of σ [m] across the track lengthens every segment of length d by about σ²/d: 0.8 % of
    the length at σ = 2 m and 1 Hz at 80 km/h, which shifts every feature of a long road by
    hundreds of metres. Latitude and longitude are each smoothed as functions of the distance along
    the raw track by a cubic smoothing spline of bandwidth `bandwidth_m` (as in
    :mod:`truckmpc.roads.gps.smooth`; 0: none). The default takes out nearly all of that lengthening
    while motorway curves keep their radius; a junction's tight turn is cut short by a few metres."""
    if lat_deg.size < 5 or bandwidth_m <= 0:
        return lat_deg, lon_deg
    along_m = cumulative_distance_m(lat_deg, lon_deg)
    lam = bandwidth_m**4 / float(np.median(np.diff(along_m)))
    lat = make_smoothing_spline(along_m, lat_deg, lam=lam)(along_m)
    # Unwrapped, so that a track across the antimeridian is smoothed as the line it is.
    lon = make_smoothing_spline(along_m, np.unwrap(lon_deg, period=360.0), lam=lam)(along_m)
    return np.asarray(lat), (np.asarray(lon) + 180.0) % 360.0 - 180.0


def checked(track: Track) -> Track:
    """`track` if it can become a road: at least two points, valid positions, an elevation on every
    point, times (where given) increasing, no zero-length segment; else a one-line RoadError naming
    the first offending point."""
    if track.size < 2:
        raise RoadError(f"{track.where}: expected at least two {track.kind}, got {track.size}")
    _check_positions(track)
    missing = np.flatnonzero(~np.isfinite(track.ele_m))
    if missing.size:
        i = int(missing[0])
        raise RoadError(
            f"{track.at(i)}: expected an elevation on every point, got none on point {i + 1} "
            f"({missing.size} of {track.size} {track.kind} lack one)"
        )
    _check_times(track)
    short = np.flatnonzero(segment_lengths_m(track.lat_deg, track.lon_deg) < MIN_SEGMENT_M)
    if short.size:
        i = int(short[0]) + 1
        raise RoadError(
            f"{track.at(i)}: expected point {i + 1} apart from the previous one, got the same position "
            f"(a zero-length segment; {short.size} in all)"
        )
    return track


def _check_positions(track: Track) -> None:
    for name, values, limit in (("latitude", track.lat_deg, 90.0), ("longitude", track.lon_deg, 180.0)):
        bad = np.flatnonzero(~(np.abs(values) <= limit))
        if bad.size:
            i = int(bad[0])
            raise RoadError(f"{track.at(i)}: expected a {name} within +-{limit:g} deg, got {values[i]:g}")


def _check_times(track: Track) -> None:
    """Times, where both neighbours have one, must increase: a repeated time is a duplicated point."""
    time_s = track.time_s
    both = np.isfinite(time_s[1:]) & np.isfinite(time_s[:-1])
    bad = np.flatnonzero(both & ~(time_s[1:] > time_s[:-1]))
    if bad.size:
        i = int(bad[0]) + 1
        what = "the same time" if time_s[i] == time_s[i - 1] else f"an earlier time {_iso(time_s[i])}"
        raise RoadError(
            f"{track.at(i)}: expected point {i + 1} later than the previous one ({_iso(time_s[i - 1])}), got {what}"
        )


def _iso(time_s: float) -> str:
    return dt.datetime.fromtimestamp(time_s, tz=dt.UTC).isoformat().replace("+00:00", "Z")

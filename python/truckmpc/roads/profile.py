"""Road profiles: altitude along the road, as data and geometry (no files here).

A profile is a list of points (distance [m], altitude [m]); the road between two points has the
constant slope Δh/ΔL (thesis section 1.2), so the slope of segment i is the difference of the
altitudes over the difference of the distances. Slopes are grades: 0.01 = 1 %, positive uphill.

A profile may also carry a target speed [km/h] per segment (a driving cycle's, or the speed limit):
the cruise controllers' set speed and band then follow it along the road; and stops (a driving
cycle's standstills, each at a point of the road with its duration [s]), which the simulation does
not drive through: it drives the stop-free legs between them (:mod:`truckmpc.roads.stops`,
:mod:`truckmpc.legs`).

This is the bottom of :mod:`truckmpc.roads`: generated roads are :mod:`~truckmpc.roads.sections`'s,
the file formats build profiles in their own modules and :func:`truckmpc.roads.loader.load_road`
picks one by the file's suffix.
"""

from __future__ import annotations

import dataclasses
import hashlib
import math
import os
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from truckmpc import _core
from truckmpc.errors import RoadError

__all__ = [
    "GRADE_CHECK",
    "MAX_ABS_DISTANCE_M",
    "MAX_GRADE",
    "MAX_LENGTH_M",
    "MAX_TARGET_KMH",
    "PathLike",
    "RoadProfile",
    "Stop",
    "altitude_from_grade",
    "step_grid",
]

PathLike = str | os.PathLike[str]
"""A file name: a string or a path."""

MAX_TARGET_KMH = 250.0
"""Highest accepted target speed [km/h]."""
MAX_GRADE = 0.30
"""Largest accepted |grade| [-] (30 %); steeper roads are taken to be input errors."""

GRADE_CHECK = MAX_GRADE + 1e-3
"""The |grade| [-] a profile is checked against: MAX_GRADE with slack, so that a profile at the limit
survives being written (altitudes rounded to 1 um) and read back."""

MAX_LENGTH_M = 1e7
"""Longest accepted road [m] (10 000 km): longer than any drive a truck makes without stopping
(the long-haul cycle is 108 km), and far beyond it a run's plant steps and trace stop fitting in
memory and time; a longer road is taken to be an input error (a distance in mm, a typo)."""

MAX_ABS_DISTANCE_M = 1e9
"""Largest accepted |distance| of a road point [m]: below it float64 resolves distances to 0.2 um,
far finer than the 1 mm a road file is written with, so a road may start at any chainage up to it."""
_REVERSED = "-reversed"


@dataclass(frozen=True)
class Stop:
    """A standstill of a driving cycle: at `distance_m` [m] (a point of the road), for `duration_s` [s] > 0."""

    distance_m: float
    duration_s: float


@dataclass(frozen=True, eq=False)
class RoadProfile:
    """A road: points `distance_m` [m] (strictly increasing, from wherever the road starts) with
    their `altitude_m` [m] (relative) and, optionally, `target_speed_kmh` [km/h], the target speed
    from each point to the next (the last point's is that beyond the end), and `stops`, in order of
    distance, each at a point of the road. Arrays are float64 and read-only. `controller_map`, if
    given, is the road the controllers are told of (they plan on it while the truck drives this
    one): a noisy import of it, a grade bias."""

    name: str
    distance_m: np.ndarray
    altitude_m: np.ndarray
    source: str | None = None
    target_speed_kmh: np.ndarray | None = None
    stops: tuple[Stop, ...] = ()
    controller_map: RoadProfile | None = None
    _road: _core.Road | None = field(default=None, init=False, repr=False)

    def __post_init__(self) -> None:
        distance = _frozen_array(self.distance_m)
        altitude = _frozen_array(self.altitude_m)
        object.__setattr__(self, "distance_m", distance)
        object.__setattr__(self, "altitude_m", altitude)
        where = self.source or self.name
        self._check_points(where, distance, altitude)
        if self.target_speed_kmh is not None:
            targets = _checked_targets(where, _frozen_array(self.target_speed_kmh), distance)
            object.__setattr__(self, "target_speed_kmh", targets)
        object.__setattr__(self, "stops", _checked_stops(where, tuple(self.stops), distance))

    def _check_points(self, where: str, distance: np.ndarray, altitude: np.ndarray) -> None:
        """Raise RoadError unless the points make a road: 1-D, finite, increasing, within the limits."""
        if distance.ndim != 1 or altitude.shape != distance.shape:
            raise RoadError(f"{where}: expected 1-D distance and altitude arrays of equal length")
        if distance.size < 2:
            raise RoadError(f"{where}: expected at least two points, got {distance.size}")
        if not (np.all(np.isfinite(distance)) and np.all(np.isfinite(altitude))):
            raise RoadError(f"{where}: expected finite distances and altitudes")
        if np.max(np.abs(distance)) > MAX_ABS_DISTANCE_M:
            raise RoadError(f"{where}: expected distances within +-{MAX_ABS_DISTANCE_M:g} m")
        if distance[-1] - distance[0] > MAX_LENGTH_M:
            length = distance[-1] - distance[0]
            raise RoadError(f"{where}: expected a road of at most {MAX_LENGTH_M:g} m, got {length:g} m")
        step = np.diff(distance)
        if not np.all(step > 0):
            raise RoadError(f"{where}: expected strictly increasing distances (point {int(np.argmin(step > 0)) + 1})")
        steep = np.flatnonzero(np.abs(self.slope) > GRADE_CHECK)
        if steep.size:
            i = int(steep[0])
            raise RoadError(f"{where}: slope {self.slope[i]:.4g} at {distance[i]:g} m exceeds |grade| <= {MAX_GRADE:g}")

    @property
    def slope(self) -> np.ndarray:
        """Grade of each segment between consecutive points [-] (length n-1): Δaltitude/Δdistance."""
        return np.diff(self.altitude_m) / np.diff(self.distance_m)

    @property
    def stop_time_s(self) -> float:
        """Total duration of the road's stops [s] (0 without stops)."""
        return float(sum(stop.duration_s for stop in self.stops))

    @property
    def length_m(self) -> float:
        """Road length from the first to the last point [m]."""
        return float(self.distance_m[-1] - self.distance_m[0])

    def __getstate__(self) -> dict[str, Any]:
        """The profile for pickling (a Dask worker sends it to another): without the core road
        built from it, which cannot be pickled and is built again where it is needed."""
        return {**self.__dict__, "_road": None}

    def core(self) -> _core.Road:
        """The road for the Rust core (`_core.Road(distance_m, slope)`), built once."""
        road = self._road
        if road is None:
            targets = None if self.target_speed_kmh is None else np.ascontiguousarray(self.target_speed_kmh[:-1])
            road = _core.Road(np.ascontiguousarray(self.distance_m), np.ascontiguousarray(self.slope), targets)
            object.__setattr__(self, "_road", road)
        return road

    def sha256(self) -> str:
        """Hex SHA-256 of the profile's points (distances, then altitudes, then the target speeds if
        it has them, then the stops' (distance, duration) pairs if it has any, as float64): the road's
        identity in result files, whatever file or generator it came from."""
        digest = hashlib.sha256(self.distance_m.tobytes())
        digest.update(self.altitude_m.tobytes())
        if self.target_speed_kmh is not None:
            digest.update(self.target_speed_kmh.tobytes())
        if self.stops:
            digest.update(np.array([(stop.distance_m, stop.duration_s) for stop in self.stops], np.float64).tobytes())
        return digest.hexdigest()

    def reversed(self) -> RoadProfile:
        """The same road driven the other way: distances measured from the far end (over the same
        range), altitudes unchanged; uphill becomes downhill."""
        start, end = self.distance_m[0], self.distance_m[-1]
        name = self.name.removesuffix(_REVERSED) if self.name.endswith(_REVERSED) else self.name + _REVERSED
        targets = None
        if self.target_speed_kmh is not None:
            # Segment i of the reversed road is segment n - 1 - i of this one.
            segments = self.target_speed_kmh[:-1][::-1]
            targets = np.append(segments, segments[-1])
        stops = tuple(Stop((start + end) - stop.distance_m, stop.duration_s) for stop in self.stops[::-1])
        mirrored = None if self.controller_map is None else self.controller_map.mirrored(start + end)
        distance = (start + end) - self.distance_m[::-1]
        return RoadProfile(name, distance, self.altitude_m[::-1], self.source, targets, stops, mirrored)

    def mirrored(self, ends_sum_m: float) -> RoadProfile:
        """This road driven the other way, distances mirrored as `ends_sum_m` − d [m]: with the sum of
        another road's ends, this road as a map of that one reversed (its points then stay where
        they were along the other road, whatever its own ends)."""
        back = self.reversed()
        shift_m = ends_sum_m - (self.distance_m[0] + self.distance_m[-1])
        stops = tuple(Stop(stop.distance_m + shift_m, stop.duration_s) for stop in back.stops)
        return dataclasses.replace(back, distance_m=back.distance_m + shift_m, stops=stops)

    def resampled(self, step_m: float) -> RoadProfile:
        """The altitude linearly interpolated onto points every `step_m` metres from the start,
        plus the end point (so the length is kept); stops stay points, and keep their places."""
        if not (math.isfinite(step_m) and step_m > 0):
            raise RoadError(f"{self.source or self.name}: resampling step: expected a number > 0 m, got {step_m!r}")
        grid = step_grid(float(self.distance_m[0]), float(self.distance_m[-1]), step_m)
        grid = np.union1d(grid, [stop.distance_m for stop in self.stops])
        targets = None
        if self.target_speed_kmh is not None:
            # Every change of target speed stays a point, so the targets keep their positions.
            changes = self.distance_m[1:-1][np.diff(self.target_speed_kmh[:-1]) != 0]
            grid = np.union1d(grid, changes)
            targets = self.target_speed_at(grid)
        altitude = np.interp(grid, self.distance_m, self.altitude_m)
        return RoadProfile(self.name, grid, altitude, self.source, targets, self.stops, self.controller_map)

    def between(self, start_m: float, end_m: float, margin_m: float = 0.0) -> RoadProfile:
        """The road from `start_m` to `end_m` [m] (positions on this road): its points more than
        `margin_m` [m] inside, and both ends interpolated (altitude, and target speed where the road
        has them); no stops and no map."""
        distance = self.distance_m
        inside = distance[(distance > start_m + margin_m) & (distance < end_m - margin_m)]
        grid = np.concatenate([[start_m], inside, [end_m]])
        altitude = np.interp(grid, distance, self.altitude_m)
        targets = None if self.target_speed_kmh is None else self.target_speed_at(grid)
        return RoadProfile(self.name, grid, altitude, self.source, targets)

    def target_speed_at(self, s_m: np.ndarray) -> np.ndarray:
        """The target speed [km/h] at distances `s_m` [m] (that of the segment containing each; the
        first segment's before the start, the last one's beyond the end)."""
        if self.target_speed_kmh is None:
            raise RoadError(f"{self.source or self.name}: the road has no target speeds")
        segment = np.searchsorted(self.distance_m, s_m, side="right") - 1
        return self.target_speed_kmh[:-1][np.clip(segment, 0, self.distance_m.size - 2)]


def _checked_targets(where: str, targets: np.ndarray, distance: np.ndarray) -> np.ndarray:
    """`targets` if it holds one target speed in (0, MAX_TARGET_KMH] km/h per point."""
    if targets.shape != distance.shape:
        raise RoadError(f"{where}: expected one target speed per point ({distance.size}), got {targets.size}")
    bad = np.flatnonzero(~((targets > 0) & (targets <= MAX_TARGET_KMH)))
    if bad.size:
        i = int(bad[0])
        raise RoadError(
            f"{where}: target_speed_kmh at {distance[i]:g} m: expected a speed in (0, {MAX_TARGET_KMH:g}] km/h, "
            f"got {targets[i]:g}"
        )
    return targets


def _checked_stops(where: str, stops: tuple[Stop, ...], distance: np.ndarray) -> tuple[Stop, ...]:
    """`stops` if each is a Stop at a point of the road with a duration > 0 s, in increasing distance."""
    previous_m = -math.inf
    for stop in stops:
        if not isinstance(stop, Stop):
            raise RoadError(f"{where}: stops: expected Stop(distance_m, duration_s) entries, got {stop!r}")
        if not (math.isfinite(stop.duration_s) and stop.duration_s > 0):
            raise RoadError(
                f"{where}: stop at {stop.distance_m:g} m: expected a duration > 0 s, got {stop.duration_s!r}"
            )
        if not np.any(distance == stop.distance_m):
            raise RoadError(f"{where}: stop at {stop.distance_m!r} m: expected it at a point of the road")
        if not stop.distance_m > previous_m:
            raise RoadError(f"{where}: stop at {stop.distance_m:g} m: expected stops in increasing distance")
        previous_m = stop.distance_m
    return stops


def altitude_from_grade(distance_m: np.ndarray, grade: np.ndarray) -> np.ndarray:
    """Altitudes [m] from 0 at the first point, integrating each point's `grade` [-] (that of the
    segment starting there; the last one is unused) over the distances `distance_m` [m]."""
    return np.concatenate([[0.0], np.cumsum(np.asarray(grade)[:-1] * np.diff(distance_m))])


def _frozen_array(values: Any) -> np.ndarray:
    array = np.array(values, dtype=np.float64, copy=True)
    array.flags.writeable = False
    return array


def step_grid(start_m: float, end_m: float, step_m: float) -> np.ndarray:
    """Points start, start+step, ... and end; a grid point within 1 mm of the end is dropped."""
    count = math.floor((end_m - start_m) / step_m + 1e-9) + 1
    grid = start_m + step_m * np.arange(count, dtype=np.float64)
    grid = grid[grid < end_m - 1e-3]
    return np.append(grid, end_m)

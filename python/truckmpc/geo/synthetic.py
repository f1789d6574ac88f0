"""GPS tracks with known truth, for the noise test: a road's altitude profile laid along a curving
path, then sampled as a GPS logger would, with altitude noise and horizontal jitter added.

The path starts on the Swedish west coast (57.70 N, 11.97 E, as the Göteborg–Malmö road) heading
south, its heading a sum of two slow sines (radius of curvature never below about 1.1 km, as on a
motorway); points are logged once a second at a speed varying between 75 and 85 km/h (22 m apart),
each one a geodesic step from the last (``pyproj.Geod.fwd``), so the clean track's geodesic length is
the road's length. A point's true elevation is the road's altitude at its distance (linear between
the road's points) plus a base of 100 m.

GPS-like noise, seeded and so reproducible: the altitude error wanders along the distance with std
`sigma_m` and a correlation length `corr_m` (~100 m), as a receiver's vertical error does rather than
jumping point to point: by default a first-order Gauss–Markov process (correlation e^(−Δs/`corr_m`),
the usual model of GPS errors, rough at short range), or a Gaussian-correlated one (correlation
e^(−(Δs/`corr_m`)²), smooth); the horizontal error is white, `jitter_m` [m] per axis. The tracks
are written as GPX 1.1 with gpxpy (elevations to 1 cm, positions to 1e-7 deg).
"""

from __future__ import annotations

import datetime as dt
import math
from collections.abc import Sequence
from pathlib import Path

import gpxpy.gpx
import numpy as np
from scipy.signal import fftconvolve

from truckmpc.atomic import atomic_write_text
from truckmpc.errors import RoadError
from truckmpc.gauss_markov import gauss_markov
from truckmpc.roads.gps.track import WGS84
from truckmpc.roads.profile import RoadProfile
from truckmpc.units import KMH_PER_MPS, M_PER_KM

__all__ = [
    "NOISE_KINDS",
    "START",
    "noisy_track_gpx",
    "path_points",
    "road_piece",
    "write_fixtures",
]

START = (57.70, 11.97)
"""First point of the synthetic path (latitude, longitude) [deg]."""
_START_TIME = dt.datetime(2024, 5, 6, 8, 0, 0, tzinfo=dt.UTC)
_BASE_ALTITUDE_M = 100.0


def path_points(length_m: float, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Distance [m], latitude and longitude [deg] of points logged at 1 Hz along the curving path
    over `length_m` (the last point exactly at its end)."""
    speed_mps = 80.0 / KMH_PER_MPS + (5.0 / KMH_PER_MPS) * np.sin(
        np.arange(int(length_m / 20.0) + 2) / 97.0 + rng.uniform(0, 6.3)
    )
    distance_m = np.concatenate([[0.0], np.cumsum(speed_mps)])
    distance_m = np.append(distance_m[distance_m < length_m - 1.0], length_m)
    phase = rng.uniform(0.0, 2 * math.pi, size=2)
    heading_deg = (
        np.degrees(
            0.5 * np.sin(2 * math.pi * distance_m / 8000.0 + phase[0])
            + 0.2 * np.sin(2 * math.pi * distance_m / 2500.0 + phase[1])
        )
        + 180.0
    )
    lat, lon = [START[0]], [START[1]]
    for step_m, azimuth_deg in zip(np.diff(distance_m), heading_deg[:-1], strict=True):
        next_lon, next_lat, _ = WGS84.fwd(lon[-1], lat[-1], azimuth_deg, step_m)
        lat.append(next_lat)
        lon.append(next_lon)
    return distance_m, np.array(lat), np.array(lon)


def _gauss_markov(distance_m: np.ndarray, sigma_m: float, corr_m: float, rng: np.random.Generator) -> np.ndarray:
    """A stationary first-order Gauss–Markov sequence at `distance_m`: std `sigma_m`, correlation
    exp(−Δs / `corr_m`) between points Δs apart."""
    first = rng.standard_normal()
    rho = np.exp(-np.diff(distance_m) / corr_m)
    return gauss_markov(rho, sigma_m, np.concatenate([[first], rng.standard_normal(rho.size)]))


def _gaussian_correlated(distance_m: np.ndarray, sigma_m: float, corr_m: float, rng: np.random.Generator) -> np.ndarray:
    """A stationary sequence at `distance_m` with std `sigma_m` and Gaussian correlation
    exp(−(Δs / `corr_m`)²): white noise on a 1 m grid convolved with a Gaussian of std `corr_m` / √2."""
    grid_m = np.arange(0.0, distance_m[-1] + 1.0)
    width_m = corr_m / math.sqrt(2.0)
    offsets_m = np.arange(-math.ceil(4 * width_m), math.ceil(4 * width_m) + 1, dtype=np.float64)
    kernel = np.exp(-0.5 * (offsets_m / width_m) ** 2)
    smooth = np.asarray(fftconvolve(rng.standard_normal(grid_m.size + kernel.size - 1), kernel, mode="valid"))
    return np.asarray(np.interp(distance_m, grid_m, smooth * sigma_m / np.sqrt(np.sum(kernel**2))))


NOISE_KINDS = {"markov": _gauss_markov, "gauss": _gaussian_correlated}
"""Altitude noise processes by name: first-order Gauss–Markov (exponential correlation, the usual
model of a GPS receiver's error; rough at short range) and Gaussian-correlated (smooth)."""


def noisy_track_gpx(
    road: RoadProfile,
    sigma_m: float,
    seed: int,
    *,
    corr_m: float = 100.0,
    jitter_m: float = 2.0,
    kind: str = "markov",
) -> gpxpy.gpx.GPX:
    """`road` laid along the synthetic path as a GPX track, with altitude noise of std `sigma_m` [m]
    correlated over `corr_m` [m] (process `kind`, a key of :data:`NOISE_KINDS`) and horizontal
    jitter of `jitter_m` [m] per axis (0 and 0: a clean track)."""
    rng = np.random.default_rng(seed)
    distance_m, lat, lon = path_points(road.length_m, rng)
    altitude_m = _BASE_ALTITUDE_M + np.interp(distance_m + road.distance_m[0], road.distance_m, road.altitude_m)
    if sigma_m > 0:
        altitude_m += NOISE_KINDS[kind](distance_m, sigma_m, corr_m, rng)
    if jitter_m > 0:
        east_m, north_m = jitter_m * rng.standard_normal((2, distance_m.size))
        lon, lat, _ = WGS84.fwd(lon, lat, np.degrees(np.arctan2(east_m, north_m)), np.hypot(east_m, north_m))
    segment = gpxpy.gpx.GPXTrackSegment()
    for i in range(distance_m.size):
        point = gpxpy.gpx.GPXTrackPoint(
            round(float(lat[i]), 7),
            round(float(lon[i]), 7),
            elevation=round(float(altitude_m[i]), 2),
            time=_START_TIME + dt.timedelta(seconds=i),
        )
        segment.points.append(point)
    track = gpxpy.gpx.GPXTrack(name=f"{road.name} sigma {sigma_m:g} m seed {seed}")
    track.segments.append(segment)
    document = gpxpy.gpx.GPX()
    document.creator = "truckmpc.geo.synthetic"
    document.tracks.append(track)
    return document


def road_piece(road: RoadProfile, start_m: float, end_m: float) -> RoadProfile:
    """The part of `road` between `start_m` and `end_m` [m] from its start (its points there, the
    ends interpolated), distances from 0, altitudes from 0, named ``NAME-kmA-B``."""
    first_m = road.distance_m[0] + start_m
    last_m = min(road.distance_m[0] + end_m, road.distance_m[-1])
    if not (start_m >= 0 and last_m > first_m):
        raise RoadError(
            f"{road.source or road.name}: expected a part within the road's {road.length_m:g} m, "
            f"got {start_m:g} m to {end_m:g} m"
        )
    part = road.between(first_m, last_m, margin_m=1e-3)
    name = f"{road.name}-km{start_m / M_PER_KM:g}-{end_m / M_PER_KM:g}"
    return RoadProfile(name, part.distance_m - first_m, part.altitude_m - part.altitude_m[0], road.source)


def write_fixtures(
    road: RoadProfile, out_dir: Path, sigmas_m: Sequence[float], seed: int, kind: str = "markov"
) -> list[Path]:
    """The noise test's tracks of `road`: one GPX per altitude noise std in `sigmas_m` [m] (0: a
    clean track, without jitter either), named ``NAME-sigmaS-seedN.gpx``, written to `out_dir`."""
    out_dir.mkdir(parents=True, exist_ok=True)
    written = []
    for sigma_m in sigmas_m:
        path = out_dir / f"{road.name}-sigma{sigma_m:g}-seed{seed}.gpx"
        jitter_m = 2.0 if sigma_m > 0 else 0.0
        document = noisy_track_gpx(road, sigma_m, seed, jitter_m=jitter_m, kind=kind)
        atomic_write_text(path, document.to_xml(version="1.1"))
        written.append(path)
    return written

"""The noise study: how far an imported road is from the truth, in grade and in the MPC's fuel saving.

For a road with known altitude (a shared road), noisy GPS tracks are made along a synthetic path
(:mod:`truckmpc.geo.synthetic`), written as GPX, imported as a user's track would be, and compared
with the road itself:

- grade RMS error [percentage points]: the RMS over the imported road's segments of its grade minus
  the true road's grade over the same segment (the true altitude interpolated at the segment's ends);
- Δfuel error [points]: Δfuel of the MPC against the PI on the imported road minus the same on the
  true road, Δfuel = (fuel_MPC − fuel_PI) / fuel_PI × 100 (:func:`truckmpc.compare.compare`).
"""

from __future__ import annotations

import tempfile
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from truckmpc.compare import compare
from truckmpc.config import RunConfig
from truckmpc.errors import RoadError
from truckmpc.geo.synthetic import write_fixtures
from truckmpc.roads.gps.importer import import_track
from truckmpc.roads.gps.smooth import Smoothing
from truckmpc.roads.gpx import read_gpx
from truckmpc.roads.profile import RoadProfile
from truckmpc.sim import simulate
from truckmpc.units import PCT_PER_FRACTION

__all__ = ["StudyRow", "delta_fuel_pct", "grade_rms_error_pct", "noisy_imports", "study_rows"]


@dataclass(frozen=True)
class StudyRow:
    """One road, noise level and smoothing, over several seeds: grade RMS errors [pp] and Δfuel
    errors [points] per seed (None where a run stalled), and the true road's Δfuel [%]."""

    road: str
    sigma_m: float
    smoothing: Smoothing
    grade_rms_pct: tuple[float, ...]
    delta_fuel_error_pct: tuple[float | None, ...]
    clean_delta_fuel_pct: float | None


def grade_rms_error_pct(imported: RoadProfile, truth: RoadProfile) -> float:
    """RMS [pp] of the imported road's segment grades minus the true grades over the same segments,
    both measured from their starts (segments beyond the true road's end left out)."""
    distance_m = imported.distance_m[imported.distance_m <= truth.length_m + 1e-6]
    if distance_m.size < 2:
        raise RoadError(f"{imported.name}: expected at least one segment within the true road")
    true_m = np.interp(distance_m, truth.distance_m - truth.distance_m[0], truth.altitude_m)
    error = np.diff(imported.altitude_m[: distance_m.size] - true_m) / np.diff(distance_m)
    return float(PCT_PER_FRACTION * np.sqrt(np.mean(error**2)))


def delta_fuel_pct(road: RoadProfile, config: RunConfig) -> float | None:
    """Δfuel [%] of the MPC against the PI on `road` (None if either stalled)."""
    comparison = compare(simulate(road, config, "pi").summary, simulate(road, config, "mpc").summary)
    return comparison.delta_consumed_pct


def noisy_imports(
    road: RoadProfile, sigma_m: float, seeds: Sequence[int], smoothing: Smoothing, kind: str = "markov"
) -> Iterator[RoadProfile]:
    """`road` as imported from a noisy GPX track (:func:`~truckmpc.geo.synthetic.write_fixtures`,
    noise process `kind`) for each seed, written to a temporary file and read back as a user's
    file would be."""
    with tempfile.TemporaryDirectory(prefix="truckmpc-gps-") as directory:
        for seed in seeds:
            (path,) = write_fixtures(road, Path(directory), [sigma_m], seed, kind)
            yield import_track(read_gpx(path), smoothing).profile


def study_rows(
    road: RoadProfile,
    config: RunConfig,
    sigmas_m: Sequence[float],
    smoothings: Sequence[Smoothing],
    seeds: Sequence[int],
    kind: str = "markov",
) -> Iterator[StudyRow]:
    """A :class:`StudyRow` per noise level and smoothing on `road` (Δfuel against the true road's)."""
    clean = delta_fuel_pct(road, config)
    for sigma_m in sigmas_m:
        for smoothing in smoothings:
            grades, fuels = [], []
            for imported in noisy_imports(road, sigma_m, seeds, smoothing, kind):
                grades.append(grade_rms_error_pct(imported, road))
                fuel = delta_fuel_pct(imported, config)
                fuels.append(None if fuel is None or clean is None else fuel - clean)
            yield StudyRow(road.name, sigma_m, smoothing, tuple(grades), tuple(fuels), clean)

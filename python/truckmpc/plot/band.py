"""The speed band a run's controllers worked to, along the road, for the speed panel of ``run.png``.

On a road without target speeds the band is the cruise band everywhere: the set speed v_ref and
v_ref − v_dec … v_ref + v_inc [km/h]. On a road with target speeds (a VECTO ``.vdri`` cycle, a road
CSV with a ``target_speed_kmh`` column) each stretch's set speed is min(v_ref, target) +
target_offset and the band follows it; ahead of a lower set speed its top falls no faster than the
deceleration ``target_decel_mps2``. The band is the simulation core's own (``Road.speed_band``), so
the picture shows what the controllers were asked to do.

The road is read again from the file the run recorded (``run.road`` in ``summary.json``) and must
still hash to the recorded SHA-256; the cruise settings come from the run's recorded configuration
(``run.settings.cruise``), or, in an older summary, from the MPC's settings.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from truckmpc.errors import TruckmpcError
from truckmpc.roads import RoadProfile, default_test_track, load_road

SAMPLE_STEP_M = 25.0
"""Finest spacing [m] of the points the band is evaluated at (besides the road's own points)."""

MAX_SAMPLES = 20_000
"""Most regular points the band is evaluated at on a long road."""


@dataclass(frozen=True)
class Cruise:
    """The cruise settings that shape the band: set speed, band below and above it [km/h], the
    offset added to every target [km/h] and the deceleration the top falls at [m/s²]."""

    v_ref_kmh: float
    v_dec_kmh: float
    v_inc_kmh: float
    target_offset_kmh: float = 0.0
    target_decel_mps2: float = 0.5


@dataclass(frozen=True)
class Band:
    """The band at distances `distance_m` [m]: the stretch's set speed `set_kmh` (without the
    falling top), and the allowed band `low_kmh` … `high_kmh` [km/h]; `from_targets` says whether
    it follows the road's target speeds."""

    distance_m: np.ndarray
    set_kmh: np.ndarray
    low_kmh: np.ndarray
    high_kmh: np.ndarray
    from_targets: bool


def run_cruise(summary: Mapping[str, Any]) -> Cruise | None:
    """The cruise settings recorded in a ``summary.json``; None when it records none."""
    run = summary.get("run")
    settings = run.get("settings") if isinstance(run, dict) else None
    cruise = settings.get("cruise") if isinstance(settings, dict) else None
    if not isinstance(cruise, dict):  # a summary written before the run was recorded
        mpc = summary.get("mpc")
        cruise = mpc.get("settings") if isinstance(mpc, dict) else None
    if not isinstance(cruise, dict) or not isinstance(cruise.get("v_ref_kmh"), (int, float)):
        return None
    number = {k: float(v) for k, v in cruise.items() if isinstance(v, (int, float)) and not isinstance(v, bool)}
    return Cruise(
        number["v_ref_kmh"],
        number.get("v_dec_kmh", 0.0),
        number.get("v_inc_kmh", 0.0),
        number.get("target_offset_kmh", 0.0),
        number.get("target_decel_mps2", 0.5),
    )


def run_road(summary: Mapping[str, Any]) -> RoadProfile | str:
    """The road a run drove, read again from the file ``summary.json`` names (in the direction it
    was driven); why not, as a short phrase, when the file is gone, unreadable or changed."""
    run = summary.get("run")
    record = run.get("road") if isinstance(run, dict) else None
    if not isinstance(record, dict):
        return "the summary does not record the road"
    path = record.get("path")
    try:
        road = default_test_track() if path is None else load_road(str(path))
    except (TruckmpcError, OSError) as err:
        return f"road file not readable ({err})"
    if record.get("reverse") is True:
        road = road.reversed()
    if record.get("sha256") not in (None, road.sha256()):
        return f"road file {path} changed since the run"
    return road


def band_along(road: RoadProfile | None, cruise: Cruise, end_m: float) -> Band:
    """The band along `road` (uniform without one, or without target speeds) at the road's points
    and every :data:`SAMPLE_STEP_M` metres (coarser on long roads) up to `end_m` [m]."""
    start_m = 0.0 if road is None else float(road.distance_m[0])
    stop_m = max(end_m, start_m) if road is None else float(road.distance_m[-1])
    step_m = max(SAMPLE_STEP_M, (stop_m - start_m) / MAX_SAMPLES)
    x_m = np.arange(start_m, stop_m, step_m)
    if road is not None:
        x_m = np.union1d(x_m, road.distance_m)
    x_m = np.union1d(x_m, [stop_m])
    if road is None or road.target_speed_kmh is None:
        v_ref = np.full_like(x_m, cruise.v_ref_kmh)
        return Band(x_m, v_ref, v_ref - cruise.v_dec_kmh, v_ref + cruise.v_inc_kmh, from_targets=False)
    set_kmh, low_kmh, high_kmh = road.core().speed_band(np.ascontiguousarray(x_m), cruise)
    return Band(x_m, set_kmh, low_kmh, high_kmh, from_targets=True)

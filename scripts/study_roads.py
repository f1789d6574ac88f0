"""What the noise-study scripts share: where the shared roads are, the two roads they study by
default, and a part of a road given on the command line as ``A-B`` [km]."""

from __future__ import annotations

import os
from pathlib import Path

from truckmpc.geo.synthetic import road_piece
from truckmpc.roads import RoadProfile
from truckmpc.units import M_PER_KM

SHARED_ROADS = Path(
    os.environ.get("TRUCKMPC_SHARED_ROADS", Path(__file__).resolve().parents[1] / ".." / "shared" / "roads")
)
"""The shared road profiles (``../shared/roads`` beside the checkout, or $TRUCKMPC_SHARED_ROADS)."""

DEFAULT_ROADS = ("eu_vecto_longhaul_100km.csv", "us_epa_gem_ph2_grade_20km.csv")
"""The roads of the noise study: the VECTO long-haul 100 km and the US EPA 20 km profiles."""


def default_road_paths() -> list[Path]:
    """The paths of :data:`DEFAULT_ROADS`."""
    return [SHARED_ROADS / name for name in DEFAULT_ROADS]


def road_part(road: RoadProfile, km: str | None) -> RoadProfile:
    """`road`, or its part ``A-B`` [km from its start] when `km` is given."""
    if km is None:
        return road
    start_km, end_km = (float(x) for x in km.split("-"))
    return road_piece(road, M_PER_KM * start_km, M_PER_KM * end_km)

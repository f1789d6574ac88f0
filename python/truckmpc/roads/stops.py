"""A road's stops and the stop-free legs between them.

The vehicle model cannot launch from standstill and the cruise controllers do not brake to a
standstill, so a road with stops (a driving cycle's, :class:`~truckmpc.roads.profile.Stop`) is cut
at every stop inside it into legs, each driven on its own (:mod:`truckmpc.legs` drives them and
joins their results).
"""

from __future__ import annotations

import itertools

import numpy as np

from truckmpc.roads.profile import RoadProfile

__all__ = ["MIN_LEG_M", "STOPS_NOTE", "leg_bounds", "leg_road"]

MIN_LEG_M = 1.0
"""Legs shorter than this [m] (two stops about at one place) are not driven."""

STOPS_NOTE = (
    "launches from standstill, braking to standstill and the stops themselves are not simulated; "
    "each leg starts at its entry target speed"
)
"""What `stops_not_simulated.note` says."""


def leg_bounds(road: RoadProfile) -> list[tuple[float, float]]:
    """(start, end) [m] of each stop-free leg of `road`: cut at its stops, those shorter than
    :data:`MIN_LEG_M` left out."""
    start_m, end_m = float(road.distance_m[0]), float(road.distance_m[-1])
    cuts = [start_m, *(stop.distance_m for stop in road.stops if start_m < stop.distance_m < end_m), end_m]
    return [(a, b) for a, b in itertools.pairwise(cuts) if b - a >= MIN_LEG_M]


def leg_road(road: RoadProfile, start_m: float, end_m: float, number: int) -> RoadProfile:
    """The part of `road` from `start_m` to `end_m` [m] (points of the road, as stops are), without
    stops, named `<road>-leg<number>`; its last point's target speed is its last segment's."""
    keep = (road.distance_m >= start_m) & (road.distance_m <= end_m)
    targets = None
    if road.target_speed_kmh is not None:
        segments = road.target_speed_kmh[keep][:-1]
        targets = np.append(segments, segments[-1])
    name = f"{road.name}-leg{number}"
    told = None if road.controller_map is None else road.controller_map.between(start_m, end_m)
    return RoadProfile(name, road.distance_m[keep], road.altitude_m[keep], road.source, targets, (), told)

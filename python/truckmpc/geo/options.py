"""Defaults and smoothing methods of a road import (``truckmpc road import gpx|csv``), kept free of
heavy imports (scipy, pyproj, gpxpy) so that the ``truckmpc`` command, whose options
(:mod:`truckmpc.cli.options`) show them, starts fast."""

from __future__ import annotations

import enum

from truckmpc.roads.gps import DEFAULT_GRADE_LIMIT_PCT, DEFAULT_NOISE_M

__all__ = [
    "DEFAULT_GRADE_LIMIT_PCT",
    "DEFAULT_NOISE_M",
    "Method",
]


class Method(enum.StrEnum):
    """Elevation smoothing methods (:mod:`truckmpc.roads.gps.smooth`)."""

    spline = "spline"
    savgol = "savgol"
    none = "none"

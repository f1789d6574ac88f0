"""Defaults and smoothing methods of a road import (``truckmpc road import gpx|csv``), kept free of
heavy imports (scipy, pyproj, gpxpy) so that the ``truckmpc`` command, whose options
(:mod:`truckmpc.cli.options`) show them, starts fast."""

from __future__ import annotations

import enum

__all__ = [
    "DEFAULT_GRADE_LIMIT_PCT",
    "DEFAULT_NOISE_M",
    "Method",
]

DEFAULT_NOISE_M = 2.0
"""Elevation noise std [m] assumed unless told: a consumer GPS receiver's, or a terrain model's."""

DEFAULT_GRADE_LIMIT_PCT = 8.0
"""|grade| [%] beyond which an imported road's grade is reported as implausible for a truck route
(motorways are built to at most 6–7 %)."""


class Method(enum.StrEnum):
    """Elevation smoothing methods (:mod:`truckmpc.geo.smooth`)."""

    spline = "spline"
    savgol = "savgol"
    none = "none"

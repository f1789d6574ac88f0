"""From a GPS track (or a ``lat,lon,ele`` table from a map) to a road profile.

Modules: :mod:`~truckmpc.roads.gps.track` (the points, their checks, position jitter, geodesic
distance), :mod:`~truckmpc.roads.gps.smooth` (elevation smoothing), :mod:`~truckmpc.roads.gps.importer`
(track to road). The file formats that hand on a track are :mod:`truckmpc.roads.gpx` and
:mod:`truckmpc.roads.latlon`.

Only the import's defaults are defined here, and nothing is imported, so that the command line can
show them without loading scipy, pyproj or gpxpy.
"""

__all__ = ["DEFAULT_GRADE_LIMIT_PCT", "DEFAULT_NOISE_M"]

DEFAULT_NOISE_M = 2.0
"""Elevation noise std [m] assumed unless told: a consumer GPS receiver's, or a terrain model's."""

DEFAULT_GRADE_LIMIT_PCT = 8.0
"""|grade| [%] beyond which an imported road's grade is reported as implausible for a truck route
(motorways are built to at most 6–7 %)."""

"""Roads: profiles, the roads generated from the thesis's sections, and road files of every format.

Layers, each importing only from those below it (``pyproject.toml``'s import-linter contract
checks it):

1. :mod:`~truckmpc.roads.loader`: :func:`load_road` picks a format by the file's suffix;
   :mod:`~truckmpc.roads.shipped`: the roads shipped in ``roads/``.
2. The formats, one module each: :mod:`~truckmpc.roads.gpx` (GPX tracks), :mod:`~truckmpc.roads.latlon`
   (``lat,lon,ele`` tables), :mod:`~truckmpc.roads.vdri` (VECTO driving cycles),
   :mod:`~truckmpc.roads.csvfile` (the road CSV, and the CSV text helpers the others share).
3. :mod:`~truckmpc.roads.gps`: from a track to a road (geodesic distance, smoothing).
4. :mod:`~truckmpc.roads.sections` (generated roads) and :mod:`~truckmpc.roads.stops` (the stop-free
   legs of a road with stops).
5. :mod:`~truckmpc.roads.profile`: :class:`RoadProfile` and :class:`Stop`, data and geometry.

What is named here is the profile and the files a user reads and writes; the GPS-track formats and
:mod:`~truckmpc.roads.gps` are not imported here, as they load gpxpy, pyproj and scipy.
"""

from truckmpc.roads.csvfile import COLUMNS_COMMENT
from truckmpc.roads.loader import load_road, write_road
from truckmpc.roads.profile import MAX_ABS_DISTANCE_M, MAX_GRADE, MAX_LENGTH_M, RoadProfile, Stop
from truckmpc.roads.sections import SECTION_KINDS, concatenate, default_test_track, make_section
from truckmpc.roads.shipped import shipped_roads, write_shipped_roads

__all__ = [
    "COLUMNS_COMMENT",
    "MAX_ABS_DISTANCE_M",
    "MAX_GRADE",
    "MAX_LENGTH_M",
    "SECTION_KINDS",
    "RoadProfile",
    "Stop",
    "concatenate",
    "default_test_track",
    "load_road",
    "make_section",
    "shipped_roads",
    "write_road",
    "write_shipped_roads",
]

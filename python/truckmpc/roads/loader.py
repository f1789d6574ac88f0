"""Road files by name: :func:`load_road` picks the format by the file's suffix; :func:`write_road`
writes the road CSV.

Formats: a VECTO driving cycle (``.vdri``, :mod:`truckmpc.roads.vdri`), a GPX track imported with
the defaults of ``truckmpc road import gpx`` (``.gpx``, :mod:`truckmpc.roads.gpx`), else a road CSV
(:mod:`truckmpc.roads.csvfile`). This is the top of :mod:`truckmpc.roads`: it imports every format,
and none imports it.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from truckmpc.roads import vdri
from truckmpc.roads.csvfile import read_road_csv, write_road_csv
from truckmpc.roads.profile import PathLike, RoadProfile

__all__ = ["load_road", "write_road"]

GPX_SUFFIX = ".gpx"
"""The file name ending of a GPX track."""


def load_road(path: PathLike) -> RoadProfile:
    """Read a road file: a VECTO driving cycle if the name ends in `.vdri`
    (:func:`truckmpc.roads.vdri.read_vdri`), a `.gpx` track imported with the defaults of
    `truckmpc road import gpx` (:func:`truckmpc.roads.gpx.gpx_road`), else a road CSV
    (:func:`truckmpc.roads.csvfile.read_road_csv`); errors name the file and line."""
    suffix = Path(path).suffix.lower()
    if suffix == GPX_SUFFIX:
        # Deferred for start-up time only (no cycle: the GPX format is below this module): it loads
        # gpxpy, pyproj and scipy, which every command reading a road CSV would otherwise wait for.
        from truckmpc.roads.gpx import gpx_road

        return gpx_road(Path(path))
    if suffix == vdri.SUFFIX:
        return vdri.read_vdri(path)
    return read_road_csv(path)


def write_road(profile: RoadProfile, path: PathLike, comments: Sequence[str] = ()) -> None:
    """Write `profile` atomically as a road CSV with `# comment` lines
    (:func:`truckmpc.roads.csvfile.write_road_csv`)."""
    write_road_csv(profile, path, comments)

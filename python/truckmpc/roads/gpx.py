"""GPX files: their points (track points, else route points) read with gpxpy, and the road along
them imported with the defaults (:mod:`truckmpc.roads.gps.importer`).

gpxpy (Apache-2.0, maintained since 2011, pure Python) parses GPX 1.0 and 1.1 with the standard
library's XML parser. It accepts any XML and keeps no line numbers, so this module adds what a user
needs to fix a file: the root element must be ``<gpx>``, XML syntax errors keep the parser's line,
and each point's line is found by counting ``<trkpt``/``<rtept`` tags in the text.
"""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET
from pathlib import Path

import gpxpy
import gpxpy.gpx
import numpy as np

from truckmpc.errors import RoadError, read_user_text
from truckmpc.roads.gps.importer import import_track
from truckmpc.roads.gps.track import Track
from truckmpc.roads.profile import PathLike, RoadProfile

__all__ = ["gpx_road", "read_gpx"]


def gpx_road(path: PathLike) -> RoadProfile:
    """The road of GPX file `path`, imported with the defaults of ``truckmpc road import gpx``
    (what :func:`~truckmpc.roads.loader.load_road` does for ``.gpx``)."""
    return import_track(read_gpx(Path(path))).profile


def read_gpx(path: Path) -> Track:
    """The track points of every track and segment of GPX file `path` in file order or, in a file
    without track points, its route points; errors are one line naming the file (and line)."""
    where = str(path)
    text = read_user_text(path, where, "a GPX file", RoadError, encoding="utf-8-sig")
    document = _parse(where, text)
    tracks = [p for track in document.tracks for segment in track.segments for p in segment.points]
    routes = [p for route in document.routes for p in route.points]
    points, tag, kind = (tracks, "trkpt", "track points") if tracks else (routes, "rtept", "route points")
    if not points:
        raise RoadError(f"{where}: expected track points (<trkpt>) or route points (<rtept>), got none")
    lines = _tag_lines(text, tag)
    line = np.array(lines if len(lines) == len(points) else [0] * len(points), dtype=np.int64)
    return Track(
        where=where,
        kind=kind,
        lat_deg=np.array([p.latitude for p in points], dtype=np.float64),
        lon_deg=np.array([p.longitude for p in points], dtype=np.float64),
        ele_m=np.array([np.nan if p.elevation is None else p.elevation for p in points], dtype=np.float64),
        time_s=np.array([np.nan if p.time is None else p.time.timestamp() for p in points], dtype=np.float64),
        line=line,
    )


def _parse(where: str, text: str) -> gpxpy.gpx.GPX:
    """The parsed document; XML errors keep their line, a root other than ``<gpx>`` is refused."""
    try:
        root = ET.fromstring(text)
    except ET.ParseError as err:
        line, column = err.position
        message = re.sub(r": line \d+, column \d+$", "", str(err))
        raise RoadError(f"{where}:{line}: expected well-formed XML, got {message} (column {column + 1})") from None
    name = str(root.tag).rsplit("}", 1)[-1]
    if name != "gpx":
        raise RoadError(f"{where}: expected a GPX file (root element <gpx>), got <{name}>")
    try:
        return gpxpy.parse(text)
    except gpxpy.gpx.GPXException as err:
        raise RoadError(f"{where}: expected valid GPX, got {err}") from None


def _tag_lines(text: str, tag: str) -> list[int]:
    """1-based line of every opening `tag` element (with or without a namespace prefix)."""
    lines, line, done = [], 1, 0
    for match in re.finditer(rf"<(?:[\w.-]+:)?{tag}\b", text):
        line += text.count("\n", done, match.start())
        done = match.start()
        lines.append(line)
    return lines

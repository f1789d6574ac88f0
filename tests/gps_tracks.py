"""Helpers of the GPS-track tests: GPX text from point lists, and where the shared roads are."""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
SHARED_ROADS = Path(os.environ.get("TRUCKMPC_SHARED_ROADS", REPO / ".." / "shared" / "roads"))
"""The shared road profiles: ../shared/roads beside the repository, or $TRUCKMPC_SHARED_ROADS (a
work tree elsewhere)."""

needs_shared = pytest.mark.skipif(
    not SHARED_ROADS.is_dir(), reason="shared road profiles (../shared/roads) not present"
)


def point_xml(tag: str, lat: float, lon: float, ele: float | None = None, time: str | None = None) -> str:
    """One `<trkpt>` or `<rtept>` element on one line."""
    inner = "" if ele is None else f"<ele>{ele:.3f}</ele>"
    inner += "" if time is None else f"<time>{time}</time>"
    return f'<{tag} lat="{lat:.8f}" lon="{lon:.8f}">{inner}</{tag}>'


def gpx_text(points: Sequence[str], route: bool = False) -> str:
    """A GPX 1.1 document holding `points` (from :func:`point_xml`), one per line, in one track
    segment (or one route); the first point is on line 5."""
    open_tags, close_tags = ("<rte>", "</rte>") if route else ("<trk><trkseg>", "</trkseg></trk>")
    return "\n".join(
        [
            '<?xml version="1.0" encoding="UTF-8"?>',
            '<gpx version="1.1" creator="tests" xmlns="http://www.topografix.com/GPX/1/1">',
            "<!-- made by tests/gps_tracks.py -->",
            open_tags,
            *points,
            close_tags,
            "</gpx>",
        ]
    )


def meridian_points(lat_from: float, lat_to: float, count: int, lon: float = 11.0, ele: float = 50.0) -> list[str]:
    """`count` track points evenly spaced in latitude along a meridian, with a constant elevation."""
    step = (lat_to - lat_from) / (count - 1)
    return [point_xml("trkpt", lat_from + i * step, lon, ele) for i in range(count)]

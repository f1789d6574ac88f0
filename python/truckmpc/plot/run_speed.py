"""What the speed panel of ``run.png`` draws behind the speeds: the set speed and the allowed band
along the road (:mod:`truckmpc.plot.band`), and the road's stops."""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

from truckmpc.plot.band import Band, Cruise, band_along, run_cruise, run_road
from truckmpc.roads import RoadProfile
from truckmpc.units import M_PER_KM

MAX_STOP_LABELS = 12
"""Most stops whose duration is written beside their mark; more would overlap."""

_STOP_COLOR = "tab:brown"


def speed_references(ax: Any, summary: Mapping[str, Any], end_m: float) -> list[Any]:
    """Draw the set speed (dashed, gid ``set-speed``), the allowed band (shaded, gid ``band``) and
    the stops (vertical lines, gid ``stop``) on `ax` [km, km/h]; return their legend handles."""
    cruise = run_cruise(summary)
    road = run_road(summary)
    handles: list[Any] = []
    if cruise is not None:
        known = road if isinstance(road, RoadProfile) else None
        band = band_along(known, cruise, end_m)
        set_label, band_label = _band_labels(band, cruise, None if known is not None else str(road))
        km = band.distance_m / M_PER_KM
        handles.append(
            ax.plot(
                km, band.set_kmh, color="k", ls="--", lw=1.0, drawstyle="steps-post", label=set_label, gid="set-speed"
            )[0]
        )
        handles.append(
            ax.fill_between(km, band.low_kmh, band.high_kmh, color="0.6", alpha=0.2, lw=0, label=band_label, gid="band")
        )
    if isinstance(road, RoadProfile) and road.stops:
        handles.append(_draw_stops(ax, road))
    return handles


def _band_labels(band: Band, cruise: Cruise, missing_road: str | None) -> tuple[str, str]:
    """Legend labels of the set speed and the band."""
    if not band.from_targets:
        lo, hi = cruise.v_ref_kmh - cruise.v_dec_kmh, cruise.v_ref_kmh + cruise.v_inc_kmh
        note = f" ({missing_road}: target speeds, if any, not drawn)" if missing_road else ""
        return f"v_ref {cruise.v_ref_kmh:g} km/h{note}", f"allowed band {lo:g}–{hi:g} km/h"
    offset = f" {cruise.target_offset_kmh:+g} km/h" if cruise.target_offset_kmh else ""
    set_label = f"set speed: road's target (at most v_ref {cruise.v_ref_kmh:g} km/h){offset}"
    band_label = f"allowed band: set speed −{cruise.v_dec_kmh:g} … +{cruise.v_inc_kmh:g} km/h"
    return set_label, band_label


def _draw_stops(ax: Any, road: RoadProfile) -> Any:
    """A vertical line at each stop, its duration beside it when there are few; the legend handle."""
    handle = None
    labelled_km = -math.inf
    min_gap_km = road.length_m / M_PER_KM / 150  # about a label's width: closer labels would overlap
    for stop in road.stops:
        km = stop.distance_m / M_PER_KM
        line = ax.axvline(km, color=_STOP_COLOR, ls="-.", lw=1.0, gid="stop", label="stop (standstill not simulated)")
        handle = handle or line
        if len(road.stops) <= MAX_STOP_LABELS and km - labelled_km >= min_gap_km:
            labelled_km = km
            ax.annotate(
                f"stop {stop.duration_s:g} s",
                (km, 0.02),
                xycoords=("data", "axes fraction"),
                xytext=(2, 0),
                textcoords="offset points",
                rotation=90,
                va="bottom",
                fontsize="x-small",
                color=_STOP_COLOR,
            )
    return handle

"""The picture of a road (``truckmpc road plot``): altitude [m] and grade [%] over distance [km],
and for a driving cycle its target speeds [km/h] and stops;
for a road made by ``truckmpc road import``, the raw resampled elevation and its grade drawn under
the smoothed ones, so the smoothing can be judged by eye."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from truckmpc.plot.figures import figure_class, save
from truckmpc.plot.run import decimate
from truckmpc.roads import RoadProfile
from truckmpc.units import M_PER_KM, PCT_PER_FRACTION

__all__ = ["plot_road", "road_figure"]


def plot_road(
    profile: RoadProfile, out: Path, raw_altitude_m: np.ndarray | None = None, svg: bool = False
) -> list[Path]:
    """Draw `profile` (and `raw_altitude_m` [m] on its points, if given) to `out` (.png or .svg);
    returns the files written."""
    fig = road_figure(profile, raw_altitude_m)
    return save([(fig, out)], svg=svg)


def road_figure(profile: RoadProfile, raw_altitude_m: np.ndarray | None = None) -> Any:
    """The matplotlib Figure of `profile`: altitude and grade, and its target speeds [km/h] and
    stops when it has them (a driving cycle)."""
    targets = profile.target_speed_kmh is not None
    fig = figure_class()(figsize=(10, 8 if targets else 6), layout="constrained")
    axes = fig.subplots(3 if targets else 2, 1, sharex=True)
    altitude_ax, grade_ax = axes[0], axes[1]
    km = profile.distance_m / M_PER_KM
    middle_km = (km[:-1] + km[1:]) / 2
    if raw_altitude_m is not None:
        raw_grade_pct = PCT_PER_FRACTION * np.diff(raw_altitude_m) / np.diff(profile.distance_m)
        altitude_ax.plot(*decimate(km, raw_altitude_m), color="0.6", lw=0.8, label="raw (resampled)")
        grade_ax.plot(*decimate(middle_km, raw_grade_pct), color="0.6", lw=0.6, label="raw (resampled)")
    label = "smoothed" if raw_altitude_m is not None else profile.name
    altitude_ax.plot(*decimate(km, profile.altitude_m), color="tab:blue", lw=1.2, label=label)
    grade_ax.plot(*decimate(middle_km, PCT_PER_FRACTION * profile.slope), color="tab:blue", lw=1.0, label=label)
    altitude_ax.set_ylabel("altitude [m]")
    grade_ax.set_ylabel("grade [%]")
    axes[-1].set_xlabel("distance [km]")
    grade_ax.axhline(0.0, color="black", lw=0.5)
    altitude_ax.set_title(f"{profile.name}: {profile.length_m / M_PER_KM:.2f} km")
    if targets:
        _target_panel(axes[2], profile)
    for ax in axes:
        for stop in profile.stops:
            ax.axvline(stop.distance_m / M_PER_KM, color="tab:brown", ls="-.", lw=0.8, gid="stop")
        ax.grid(True, alpha=0.3)
        ax.legend(loc="best", fontsize="small")
    return fig


def _target_panel(ax: Any, profile: RoadProfile) -> None:
    """The road's target speed [km/h] over distance [km], each from its point to the next; its
    stops in the legend."""
    assert profile.target_speed_kmh is not None
    km = profile.distance_m / M_PER_KM
    ax.plot(km, profile.target_speed_kmh, color="k", lw=1.0, drawstyle="steps-post", label="target speed", gid="target")
    if profile.stops:
        total_s = profile.stop_time_s
        ax.plot([], [], color="tab:brown", ls="-.", lw=0.8, label=f"{len(profile.stops)} stops ({total_s:g} s)")
    ax.set_ylabel("target speed [km/h]")
    ax.set_ylim(bottom=0)

"""The picture of a road (``truckmpc road plot``): altitude [m] and grade [%] over distance [km];
for a road made by ``truckmpc road import``, the raw resampled elevation and its grade drawn under
the smoothed ones, so the smoothing can be judged by eye."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from truckmpc.plot.figures import figure_class, save
from truckmpc.plot.run import decimate
from truckmpc.roads import RoadProfile
from truckmpc.units import M_PER_KM, PCT_PER_FRACTION

__all__ = ["plot_road"]


def plot_road(
    profile: RoadProfile, out: Path, raw_altitude_m: np.ndarray | None = None, svg: bool = False
) -> list[Path]:
    """Draw `profile` (and `raw_altitude_m` [m] on its points, if given) to `out` (.png or .svg);
    returns the files written."""
    fig = figure_class()(figsize=(10, 6), layout="constrained")
    altitude_ax, grade_ax = fig.subplots(2, 1, sharex=True)
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
    grade_ax.set_xlabel("distance [km]")
    grade_ax.axhline(0.0, color="black", lw=0.5)
    altitude_ax.set_title(f"{profile.name}: {profile.length_m / M_PER_KM:.2f} km")
    for ax in (altitude_ax, grade_ax):
        ax.grid(True, alpha=0.3)
        ax.legend(loc="best", fontsize="small")
    return save([(fig, out)], svg=svg)

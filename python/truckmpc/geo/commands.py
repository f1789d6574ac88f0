"""The work of ``truckmpc road import gpx|csv``, ``road info`` and ``road plot`` (the Typer
declarations are in :mod:`truckmpc.cli.road`)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from truckmpc.geo.files import read_road_with_notes, write_imported
from truckmpc.geo.info import format_info, road_info
from truckmpc.geo.options import Method
from truckmpc.plot.road import plot_road
from truckmpc.roads.gps import DEFAULT_GRADE_LIMIT_PCT, DEFAULT_NOISE_M
from truckmpc.roads.gps.importer import import_track
from truckmpc.roads.gps.smooth import Smoothing
from truckmpc.roads.gps.track import Track
from truckmpc.roads.gpx import read_gpx
from truckmpc.roads.latlon import read_latlon_csv
from truckmpc.units import M_PER_KM, PCT_PER_FRACTION

__all__ = ["ImportOptions", "import_road", "info_lines", "plot_road_file"]


@dataclass(frozen=True)
class ImportOptions:
    """What ``road import`` was told: smoothing `method`, elevation noise `noise_m` [m], smoothing
    length `smooth_m` [m] (None: from the noise), resampling `step_m` [m] (None: the point spacing),
    grade report limit `grade_limit_pct` [%]."""

    method: Method = Method.spline
    noise_m: float = DEFAULT_NOISE_M
    smooth_m: float | None = None
    step_m: float | None = None
    grade_limit_pct: float = DEFAULT_GRADE_LIMIT_PCT

    def smoothing(self) -> Smoothing:
        if self.smooth_m is None or self.method == Method.none:
            return Smoothing.for_noise(self.method.value, self.noise_m)
        return Smoothing(self.method.value, self.smooth_m)

    def flags(self) -> str:
        """The options as command-line flags (those not at their defaults)."""
        given = (
            ("--method", self.method.value, Method.spline.value),
            ("--noise-m", self.noise_m, DEFAULT_NOISE_M),
            ("--smooth-m", self.smooth_m, None),
            ("--step-m", self.step_m, None),
            ("--grade-limit-pct", self.grade_limit_pct, DEFAULT_GRADE_LIMIT_PCT),
        )
        return "".join(
            f" {flag} {value:g}" if isinstance(value, float) else f" {flag} {value}"
            for flag, value, default in given
            if value != default
        )


READERS: dict[str, Callable[[Path], Track]] = {"gpx": read_gpx, "csv": read_latlon_csv}
"""Track readers of ``road import``, by sub-command."""


def import_road(kind: str, file: Path, output: Path, options: ImportOptions) -> list[str]:
    """Import track `file` of `kind` (a key of :data:`READERS`) into road CSV `output`; returns the
    lines to print (what was written and how it was made, steep sections included)."""
    imported = import_track(
        READERS[kind](file), options.smoothing(), options.step_m, options.grade_limit_pct / PCT_PER_FRACTION
    )
    command = f"truckmpc road import {kind} {file} -o {output}{options.flags()}"
    write_imported(imported, output, command)
    profile = imported.profile
    head = f"wrote {output} ({profile.name}, {profile.length_m / M_PER_KM:.3f} km, {profile.distance_m.size} points)"
    return [head, *(f"  {note}" for note in imported.notes)]


def info_lines(file: Path) -> list[str]:
    """The lines of ``road info FILE``."""
    road = read_road_with_notes(file)
    return format_info(road_info(road.profile, road.notes))


def plot_road_file(file: Path, out: Path, svg: bool) -> list[Path]:
    """Draw road `file` to `out` (a .png; with `svg` an .svg beside it); returns the files written."""
    road = read_road_with_notes(file)
    return plot_road(road.profile, out, road.raw_altitude_m, svg=svg)

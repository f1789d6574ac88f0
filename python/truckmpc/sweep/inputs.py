"""The inputs of a sweep, checked before anything runs: its roads, its axes and the validated
configuration of each combination of the axes' values."""

from __future__ import annotations

import dataclasses
import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import yaml

from truckmpc import _core
from truckmpc.config import VEHICLE_KEYS, Origin, RunConfig, load_run_config
from truckmpc.config.vecto_truck import STILL_APPLIES
from truckmpc.config.yamlfile import load_value
from truckmpc.consumption import ENERGY, FUEL, Consumption
from truckmpc.errors import ConfigError
from truckmpc.roads import RoadProfile, load_road
from truckmpc.roads.profile import PathLike
from truckmpc.sweep.cells import cell
from truckmpc.sweep.errors import SweepError
from truckmpc.sweep.fleet import check_unique, road_files
from truckmpc.sweep.grid import Axis, parse_axis

MAX_SWEEP_ROWS = 1_000_000
"""Most rows (roads × combinations) a sweep may have: its CSV is then about 0.4 GB, and planning
it takes about a minute; more is taken to be a typo in a range."""


@dataclass(frozen=True)
class Base:
    """The base configuration every combination is applied on top of."""

    vehicle_path: str | None
    config_paths: tuple[str, ...]
    overrides: tuple[str, ...]

    def config(self, extra: Sequence[str] = ()) -> RunConfig:
        return load_run_config(self.vehicle_path, self.config_paths, (*self.overrides, *extra))


def checked_axes(
    axes: Sequence[Axis | str] | Mapping[str, Sequence[Any]], overrides: Sequence[str]
) -> tuple[Axis, ...]:
    """The axes, parsed; each key once, not also a ``--set``, with at least one value."""
    if isinstance(axes, Mapping):
        axes = [Axis(key, tuple(values), ",".join(cell(v) for v in values)) for key, values in axes.items()]
    parsed = tuple(parse_axis(a) if isinstance(a, str) else a for a in axes)
    keys = [axis.key for axis in parsed]
    set_keys = {text.partition("=")[0].strip() for text in overrides}
    for axis in parsed:
        if keys.count(axis.key) > 1:
            raise SweepError(f"--grid {axis.key}: axis given twice")
        if axis.key in set_keys:
            raise SweepError(f"--grid {axis.key}: also set with --set {axis.key}; give it once")
        if not axis.values:
            raise SweepError(f"--grid {axis.key}: expected at least one value")
    return parsed


def load_profiles(roads: Sequence[RoadProfile | PathLike], reverse: bool) -> list[RoadProfile]:
    """The roads loaded (directories and globs expanded, every file readable), uniquely named,
    reversed if asked (keeping their names: rows are keyed by them)."""
    profiles = [road if isinstance(road, RoadProfile) else load_road(road) for road, _ in road_files(roads)]
    if not profiles:
        raise SweepError("--road: expected at least one road")
    names = [p.name for p in profiles]
    check_unique(names, "--road", "roads")
    if reverse:
        profiles = [p.reversed() for p in profiles]
        profiles = [dataclasses.replace(p, name=n) for p, n in zip(profiles, names, strict=True)]
    return profiles


def check_size(axes: Sequence[Axis], roads: int) -> None:
    """Refuse more than :data:`MAX_SWEEP_ROWS` rows before expanding the grid."""
    combinations = math.prod(len(axis.values) for axis in axes)
    if combinations * roads > MAX_SWEEP_ROWS:
        raise SweepError(
            f"--grid: expected at most {MAX_SWEEP_ROWS} rows (combinations × roads), got {combinations} "
            f"combinations × {roads} road{'s' if roads > 1 else ''}"
        )


class Combinations:
    """The configurations of a grid's combinations: the base's resolved values with the axis values
    put in, validated by the core. Reading the files again per combination would be most of a
    sweep's planning; only a combination the core refuses is loaded again through the files, so
    that its error names where each value came from exactly as ``load_run_config`` does."""

    def __init__(self, base: Base, base_config: RunConfig, axes: Sequence[Axis]) -> None:
        _check_truck_axes(base_config, axes)
        self._base, self._axes = base, axes
        self._settings = base_config.settings
        self._truck = base_config.truck
        self._origins = dict(base_config.origins)
        self._rank = max((origin.rank for origin in self._origins.values()), default=0) + 1
        self._parsed: dict[str, Any] = {}

    def config(self, values: tuple[Any, ...], texts: tuple[str, ...]) -> RunConfig:
        """The validated configuration of one combination (``texts``: its ``key=value`` overrides)."""
        changes, origins = {}, dict(self._origins)
        try:
            for i, text in enumerate(texts):
                key, _, raw = text.partition("=")
                changes[key] = self._parse(raw)
                origins[key] = Origin(f"--set {key}", self._rank + i)
            settings = self._settings.with_values(changes)
        except (yaml.YAMLError, _core.ParamError):
            return _combination_config(self._base, self._axes, values, texts)
        return RunConfig(settings=settings, origins=origins, truck=self._truck)

    def _parse(self, raw: str) -> Any:
        if raw not in self._parsed:
            self._parsed[raw] = load_value(raw)
        return self._parsed[raw]


def _combination_config(base: Base, axes: Sequence[Axis], values: tuple[Any, ...], texts: tuple[str, ...]) -> RunConfig:
    """The configuration of one combination; its errors blame the ``--grid`` axis, not a ``--set``."""
    try:
        return base.config(texts)
    except ConfigError as err:
        message = str(err)
        named = [axis.key for axis in axes if re.search(rf"--set {re.escape(axis.key)}\b", message)]
        for key in named:
            message = re.sub(rf"--set {re.escape(key)}\b", f"--grid {key}", message)
        if not named:  # a check across keys that blamed a base setting: say which combination
            combo = " ".join(f"{axis.key}={cell(v)}" for axis, v in zip(axes, values, strict=True))
            message = f"--grid combination {combo}: {message}"
        raise SweepError(message) from None


def _check_truck_axes(config: RunConfig, axes: Sequence[Axis]) -> None:
    """A VECTO truck replaces the thesis's vehicle keys: an axis over one of them would change nothing."""
    if config.truck is None:
        return
    replaced = [a.key for a in axes if a.key in VEHICLE_KEYS and a.key not in STILL_APPLIES]
    if replaced:
        raise SweepError(
            f"--grid {replaced[0]}: expected a key a VECTO truck uses, got a key of the thesis's truck, which "
            f"{config.truck.job.path.name} replaces (vary its load with one job per load instead)"
        )


def consumed_by(configs: Sequence[RunConfig], names: Sequence[str]) -> Consumption:
    """What the trucks of a sweep consume (their columns are named for it): fuel, or battery energy
    when every truck is battery-electric; a one-line :class:`SweepError` for a fleet of both, whose
    rows could not share their columns."""
    electric = [config.is_electric for config in configs]
    if all(electric):
        return ENERGY
    if any(electric):
        diesel, battery = (next(n for n, e in zip(names, electric, strict=True) if e is kind) for kind in (False, True))
        raise SweepError(
            f"--vehicle: expected trucks that all burn fuel or all draw on a battery (a sweep compares one "
            f"of them; run each kind as a sweep of its own), got {diesel} (fuel) and {battery} (battery)"
        )
    return FUEL

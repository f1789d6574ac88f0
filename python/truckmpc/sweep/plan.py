"""The plan of a sweep: its roads and rows, each row's overrides and PI key, all validated before
anything runs.

The PI run depends only on the road, the vehicle, the PI and the simulation settings, so each row
carries a key made of those *resolved values*: rows with the same key share one PI run (an axis over
an MPC key needs one PI run per road, an axis over ``v_ref_kmh`` or ``mass_kg`` one per value).
"""

from __future__ import annotations

import dataclasses
import json
import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import yaml

from truckmpc import _core
from truckmpc.config import SPEC_BY_KEY, Origin, RunConfig, load_run_config
from truckmpc.config.yamlfile import load_value
from truckmpc.convergence import halved_configs
from truckmpc.errors import ConfigError
from truckmpc.road import PathLike, RoadProfile, load_road
from truckmpc.sweep.columns import cell, result_columns, yaml_text
from truckmpc.sweep.errors import SweepError
from truckmpc.sweep.grid import Axis, expand_grid, parse_axis
from truckmpc.workload import Work, check_trace, run_work

MAX_SWEEP_ROWS = 1_000_000
"""Most rows (roads × combinations) a sweep may have: its CSV is then about 0.4 GB, and planning
it takes about a minute; more is taken to be a typo in a range."""


@dataclass(frozen=True)
class Row:
    """One (road, combination) of a sweep: its place in grid order, its overrides, its PI key and
    the estimated work of its MPC run (:mod:`truckmpc.workload`; its PI run's is the plant part)."""

    index: int
    road: int
    values: tuple[Any, ...]
    overrides: tuple[str, ...]
    pi_key: str
    work: Work

    @property
    def cost(self) -> float:
        """Estimated seconds of the row's MPC run [s] (the longest are scheduled first)."""
        return self.work.total_s


@dataclass(frozen=True)
class SweepPlan:
    """A validated sweep: roads (already reversed when ``direction`` is reverse), axes, the base
    configuration files and overrides, the rows in grid order and the ``sweep.json`` settings."""

    roads: tuple[RoadProfile, ...]
    direction: str
    axes: tuple[Axis, ...]
    vehicle_path: str | None
    config_paths: tuple[str, ...]
    overrides: tuple[str, ...]
    rows: tuple[Row, ...]
    settings: dict[str, Any]
    check_convergence: bool = False

    @property
    def columns(self) -> tuple[str, ...]:
        return ("road", "direction", *(axis.key for axis in self.axes), *result_columns(self.check_convergence))

    def row_key(self, row: Row) -> tuple[str, ...]:
        """The cells that identify a row in the CSV: road, direction and the axis values."""
        return (self.roads[row.road].name, self.direction, *(cell(v) for v in row.values))


@dataclass(frozen=True)
class _Base:
    """The base configuration every combination is applied on top of."""

    vehicle_path: str | None
    config_paths: tuple[str, ...]
    overrides: tuple[str, ...]

    def config(self, extra: Sequence[str] = ()) -> RunConfig:
        return load_run_config(self.vehicle_path, self.config_paths, (*self.overrides, *extra))


def plan_sweep(
    roads: Sequence[RoadProfile | PathLike],
    axes: Sequence[Axis | str] | Mapping[str, Sequence[Any]] = (),
    *,
    reverse: bool = False,
    vehicle_path: PathLike | None = None,
    config_paths: Sequence[PathLike] = (),
    overrides: Sequence[str] = (),
    check_convergence: bool = False,
) -> SweepPlan:
    """Load the roads and validate the configuration of every combination; raise a one-line
    :class:`~truckmpc.errors.TruckmpcError` naming the road, the ``--set`` or the ``--grid`` axis.
    With `check_convergence` every MPC row is also driven at half δ and half S (its work counts
    them) and gets the convergence columns."""
    checked = _checked_axes(axes, overrides)
    profiles = load_profiles(roads, reverse)
    base = _Base(
        None if vehicle_path is None else str(vehicle_path), tuple(str(p) for p in config_paths), tuple(overrides)
    )
    _check_size(checked, len(profiles))
    base_config = base.config()  # errors in the base name their file or --set
    keys = [axis.key for axis in checked]
    combinations = _Combinations(base, base_config, checked)
    combos = []
    for values in expand_grid(checked):
        texts = tuple(f"{key}={yaml_text(v)}" for key, v in zip(keys, values, strict=True))
        config = combinations.config(values, texts)
        for profile in profiles:
            check_trace(profile, config)
        combos.append((values, texts, config, _section_values(config)))
    rows = [
        Row(len(combos) * r + i, r, values, texts, _pi_key(r, sections), _mpc_work(profile, config, check_convergence))
        for r, profile in enumerate(profiles)
        for i, (values, texts, config, sections) in enumerate(combos)
    ]
    direction = "reverse" if reverse else "forward"
    settings = _settings(profiles, direction, checked, base, base_config, check_convergence)
    return SweepPlan(
        tuple(profiles),
        direction,
        checked,
        base.vehicle_path,
        base.config_paths,
        base.overrides,
        tuple(rows),
        settings,
        check_convergence,
    )


def _mpc_work(profile: RoadProfile, config: RunConfig, check_convergence: bool) -> Work:
    """The estimated work of a row's MPC run, with its runs at half δ and half S when checked."""
    configs = [config, *(halved_configs(config).values() if check_convergence else ())]
    works = [run_work(profile, c, "mpc") for c in configs]
    return Work(sum(w.plant_s for w in works), sum(w.dp_s for w in works), max(w.dp_bytes for w in works))


def _checked_axes(
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
    """The roads loaded, uniquely named, reversed if asked (keeping their names: rows are keyed by them)."""
    profiles = [load_road(road) if not isinstance(road, RoadProfile) else road for road in roads]
    if not profiles:
        raise SweepError("--road: expected at least one road")
    names = [p.name for p in profiles]
    for name in names:
        if names.count(name) > 1:
            raise SweepError(f"--road: two roads are named {name!r} (rows are keyed by road name)")
    if reverse:
        profiles = [p.reversed() for p in profiles]
        profiles = [dataclasses.replace(p, name=n) for p, n in zip(profiles, names, strict=True)]
    return profiles


def _check_size(axes: Sequence[Axis], roads: int) -> None:
    """Refuse more than :data:`MAX_SWEEP_ROWS` rows before expanding the grid."""
    combinations = math.prod(len(axis.values) for axis in axes)
    if combinations * roads > MAX_SWEEP_ROWS:
        raise SweepError(
            f"--grid: expected at most {MAX_SWEEP_ROWS} rows (combinations × roads), got {combinations} "
            f"combinations × {roads} road{'s' if roads > 1 else ''}"
        )


class _Combinations:
    """The configurations of a grid's combinations: the base's resolved values with the axis values
    put in, validated by the core. Reading the files again per combination took 6.7 ms, most of a
    sweep's planning; only a combination the core refuses is loaded again through the files, so
    that its error names where each value came from exactly as ``load_run_config`` does."""

    def __init__(self, base: _Base, base_config: RunConfig, axes: Sequence[Axis]) -> None:
        self._base, self._axes = base, axes
        self._values = base_config.settings.values()
        self._origins = dict(base_config.origins)
        self._rank = max((origin.rank for origin in self._origins.values()), default=0) + 1
        self._parsed: dict[str, Any] = {}

    def config(self, values: tuple[Any, ...], texts: tuple[str, ...]) -> RunConfig:
        """The validated configuration of one combination (``texts``: its ``key=value`` overrides)."""
        merged, origins = dict(self._values), dict(self._origins)
        try:
            for i, text in enumerate(texts):
                key, _, raw = text.partition("=")
                merged[key] = self._parse(raw)
                origins[key] = Origin(f"--set {key}", self._rank + i)
            settings = _core.Settings(merged)
        except (yaml.YAMLError, _core.ParamError):
            return _combination_config(self._base, self._axes, values, texts)
        return RunConfig(settings=settings, origins=origins)

    def _parse(self, raw: str) -> Any:
        if raw not in self._parsed:
            self._parsed[raw] = load_value(raw)
        return self._parsed[raw]


def _combination_config(
    base: _Base, axes: Sequence[Axis], values: tuple[Any, ...], texts: tuple[str, ...]
) -> RunConfig:
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


_PI_SECTIONS = ("vehicle", "cruise", "pi", "sim")


def _section_values(config: RunConfig) -> dict[str, dict[str, Any]]:
    """The values of the sections a PI run depends on, by section."""
    sections: dict[str, dict[str, Any]] = {name: {} for name in _PI_SECTIONS}
    for key, value in config.settings.values().items():
        section = SPEC_BY_KEY[key].section
        if section in sections:
            sections[section][key] = value
    return sections


def _pi_key(road: int, sections: Mapping[str, Mapping[str, Any]]) -> str:
    """Everything the PI run depends on: road, vehicle, PI and simulation values (not the MPC's)."""
    return json.dumps([road, *(sections[name] for name in _PI_SECTIONS)], sort_keys=True)


def _settings(
    profiles: Sequence[RoadProfile],
    direction: str,
    axes: Sequence[Axis],
    base: _Base,
    base_config: RunConfig,
    check_convergence: bool,
) -> dict[str, Any]:
    """The ``sweep.json`` document (without ``jobs``), as plain JSON values."""
    grid = [{"key": a.key, "spec": a.spec, "values": list(a.values)} for a in axes]
    columns = ["road", "direction", *(a.key for a in axes), *result_columns(check_convergence)]
    return study_settings(profiles, direction, grid, base_config, base, columns)


def study_settings(
    profiles: Sequence[RoadProfile],
    direction: str,
    grid: Any,
    base_config: RunConfig,
    base: Any,
    columns: Sequence[str],
) -> dict[str, Any]:
    """The settings file of a sweep or Pareto study (without ``jobs``), as plain JSON values: what
    identifies it (roads, `grid`, the resolved base configuration, columns) and the inputs as given
    (`base`: ``vehicle_path``, ``config_paths``, ``overrides``)."""
    config_doc = base_config.as_dict()
    config_doc.pop("sources")
    settings = {
        "version": 1,
        "roads": [{"name": p.name, "direction": direction, "sha256": p.sha256(), "path": p.source} for p in profiles],
        "grid": grid,
        "base_config": config_doc,
        "vehicle": base.vehicle_path,
        "configs": list(base.config_paths),
        "overrides": list(base.overrides),
        "columns": list(columns),
    }
    doc: dict[str, Any] = json.loads(json.dumps(settings))
    return doc

"""The plan of a sweep: its roads and rows, each row's overrides and PI key, all validated before
anything runs.

The PI run depends only on the road, the vehicle, the PI and the simulation settings, so each row
carries a key made of those *resolved values*: rows with the same key share one PI run (an axis over
an MPC key needs one PI run per road, an axis over ``v_ref_kmh`` or ``mass_kg`` one per value).
"""

from __future__ import annotations

import dataclasses
import json
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from truckmpc.config import RunConfig, load_run_config
from truckmpc.errors import ConfigError
from truckmpc.road import PathLike, RoadProfile, load_road
from truckmpc.sweep.columns import SWEEP_COLUMNS, cell, yaml_text
from truckmpc.sweep.errors import SweepError
from truckmpc.sweep.grid import Axis, expand_grid, parse_axis


@dataclass(frozen=True)
class Row:
    """One (road, combination) of a sweep: its place in grid order, its overrides, its PI key and
    a rough relative cost of its MPC run (for scheduling only)."""

    index: int
    road: int
    values: tuple[Any, ...]
    overrides: tuple[str, ...]
    pi_key: str
    cost: float = 0.0


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

    @property
    def columns(self) -> tuple[str, ...]:
        return ("road", "direction", *(axis.key for axis in self.axes), *SWEEP_COLUMNS)

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
) -> SweepPlan:
    """Load the roads and validate the configuration of every combination; raise a one-line
    :class:`~truckmpc.errors.TruckmpcError` naming the road, the ``--set`` or the ``--grid`` axis."""
    checked = _checked_axes(axes, overrides)
    profiles = _profiles(roads, reverse)
    base = _Base(
        None if vehicle_path is None else str(vehicle_path), tuple(str(p) for p in config_paths), tuple(overrides)
    )
    base_config = base.config()  # errors in the base name their file or --set
    keys = [axis.key for axis in checked]
    combos = []
    for values in expand_grid(checked):
        texts = tuple(f"{key}={yaml_text(v)}" for key, v in zip(keys, values, strict=True))
        combos.append((values, texts, _combination_config(base, checked, values, texts)))
    rows = [
        Row(len(combos) * r + i, r, values, texts, _pi_key(r, config), _mpc_cost(profile, config))
        for r, profile in enumerate(profiles)
        for i, (values, texts, config) in enumerate(combos)
    ]
    direction = "reverse" if reverse else "forward"
    settings = _settings(profiles, direction, checked, base, base_config)
    return SweepPlan(
        tuple(profiles),
        direction,
        checked,
        base.vehicle_path,
        base.config_paths,
        base.overrides,
        tuple(rows),
        settings,
    )


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


def _profiles(roads: Sequence[RoadProfile | PathLike], reverse: bool) -> list[RoadProfile]:
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


def _pi_key(road: int, config: RunConfig) -> str:
    """Everything the PI run depends on: road, vehicle, PI and simulation values (not the MPC's)."""
    parts = [road, *(dict(config.section(name)) for name in ("vehicle", "cruise", "pi", "sim"))]
    return json.dumps(parts, sort_keys=True)


def _mpc_cost(profile: RoadProfile, config: RunConfig) -> float:
    """Relative work of an MPC run: solves (length / S) times stages per solve (horizon / S) times
    grid points per stage (1 / delta)."""
    stage_m, horizon_m, delta_kmh = (float(config.mpc[key]) for key in ("stage_m", "horizon_m", "delta_kmh"))
    return profile.length_m / stage_m * (horizon_m / stage_m) / delta_kmh


def _settings(
    profiles: Sequence[RoadProfile], direction: str, axes: Sequence[Axis], base: _Base, base_config: RunConfig
) -> dict[str, Any]:
    """The ``sweep.json`` document (without ``jobs``), as plain JSON values."""
    config_doc = base_config.as_dict()
    config_doc.pop("sources")
    settings = {
        "version": 1,
        "roads": [{"name": p.name, "direction": direction, "sha256": p.sha256(), "path": p.source} for p in profiles],
        "grid": [{"key": a.key, "spec": a.spec, "values": list(a.values)} for a in axes],
        "base_config": config_doc,
        "vehicle": base.vehicle_path,
        "configs": list(base.config_paths),
        "overrides": list(base.overrides),
        "columns": ["road", "direction", *(a.key for a in axes), *SWEEP_COLUMNS],
    }
    doc: dict[str, Any] = json.loads(json.dumps(settings))
    return doc

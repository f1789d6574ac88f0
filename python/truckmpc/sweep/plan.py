"""The plan of a sweep: its roads and rows, each row's overrides and run keys, all validated
before anything runs.

The PI run depends only on the road, the vehicle, the PI and the simulation settings, and the PCC's
on those and the ``pcc`` section, so each row carries, per controller, a key made of those *resolved
values*: rows with the same key share one run (an axis over an MPC key needs one PI run and one PCC
run per road, an axis over ``v_ref_kmh`` or ``mass_kg`` one per value). Each MPC run is its row's own.
"""

from __future__ import annotations

import dataclasses
import functools
import json
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from truckmpc.config import SPEC_BY_KEY, RunConfig
from truckmpc.consumption import FUEL, Consumption
from truckmpc.convergence import halved_configs
from truckmpc.roads import RoadProfile
from truckmpc.roads.profile import PathLike
from truckmpc.sweep.cells import cell, yaml_text
from truckmpc.sweep.columns import DEFAULT_CONTROLLERS, Layout, check_controllers
from truckmpc.sweep.errors import SweepError
from truckmpc.sweep.fleet import load_fleet, vehicle_names, vehicle_paths
from truckmpc.sweep.grid import Axis, expand_grid
from truckmpc.sweep.inputs import Base, Combinations, check_size, checked_axes, consumed_by
from truckmpc.sweep.task import Road
from truckmpc.workload import Work, check_trace, run_work


@dataclass(frozen=True)
class Row:
    """One (road and direction, vehicle, combination) of a sweep: its place in grid order, its
    overrides, the key of each of its runs (controller -> key; rows with the same key share the run)
    and the estimated work of its look-ahead run (:mod:`truckmpc.workload`: the MPC's if it runs,
    else the PCC's; a PI or PCC run's is the plant part)."""

    index: int
    road: int
    values: tuple[Any, ...]
    overrides: tuple[str, ...]
    keys: Mapping[str, str]
    work: Work
    vehicle: int = 0

    @property
    def cost(self) -> float:
        """Estimated seconds of the row's look-ahead run [s] (the longest are scheduled first)."""
        return self.work.total_s


@dataclass(frozen=True)
class SweepPlan:
    """A validated sweep: roads (each as driven in its direction of ``directions``: already reversed
    for ``reverse``), axes, the vehicle files (None: the packaged truck) and their names, the base
    configuration files and overrides, the rows in grid order and the ``sweep.json`` settings."""

    roads: tuple[Road, ...]
    directions: tuple[str, ...]
    axes: tuple[Axis, ...]
    vehicle_paths: tuple[str | None, ...]
    config_paths: tuple[str, ...]
    overrides: tuple[str, ...]
    rows: tuple[Row, ...]
    settings: dict[str, Any]
    check_convergence: bool = False
    controllers: tuple[str, ...] = DEFAULT_CONTROLLERS
    vehicle_names: tuple[str, ...] = ("truck-40t",)
    consumption: Consumption = FUEL

    @functools.cached_property
    def layout(self) -> Layout:
        """The result columns and how a row's runs fill them."""
        return Layout(self.controllers, self.check_convergence, self.consumption)

    @property
    def vehicle_path(self) -> str | None:
        """The vehicle file of a sweep of one vehicle (the first one's of a fleet)."""
        return self.vehicle_paths[0]

    @property
    def key_columns(self) -> tuple[str, ...]:
        """The columns that identify a row: road, direction, vehicle (when there are several) and the axes."""
        return key_columns(self.axes, len(self.vehicle_paths) > 1)

    @property
    def columns(self) -> tuple[str, ...]:
        return (*self.key_columns, *self.layout.columns)

    def row_key(self, row: Row) -> tuple[str, ...]:
        """The cells that identify a row in the CSV: road, direction, vehicle and the axis values."""
        vehicle = (self.vehicle_names[row.vehicle],) if len(self.vehicle_paths) > 1 else ()
        return (self.roads[row.road].name, self.directions[row.road], *vehicle, *(cell(v) for v in row.values))


def key_columns(axes: Sequence[Axis], several_vehicles: bool) -> tuple[str, ...]:
    """The columns that identify a row: road, direction, vehicle (with `several_vehicles`) and the axes."""
    return ("road", "direction", *(("vehicle",) if several_vehicles else ()), *(axis.key for axis in axes))


def plan_sweep(
    roads: Sequence[RoadProfile | PathLike],
    axes: Sequence[Axis | str] | Mapping[str, Sequence[Any]] = (),
    *,
    reverse: bool | str = False,
    vehicle_path: PathLike | Sequence[PathLike] | None = None,
    config_paths: Sequence[PathLike] = (),
    overrides: Sequence[str] = (),
    check_convergence: bool = False,
    controllers: Sequence[str] = DEFAULT_CONTROLLERS,
) -> SweepPlan:
    """Load the roads (files, directories, globs: :mod:`~truckmpc.sweep.fleet`) and validate the
    configuration of every combination with every vehicle (`vehicle_path`: one file, several, or
    None for the packaged truck); raise a one-line :class:`~truckmpc.errors.TruckmpcError` naming
    the road, the ``--set``, the ``--grid`` axis or the ``--controller``. `reverse`: drive the roads
    reversed, or ``"both"`` ways. Each row runs the PI and `controllers` (``pcc``, ``mpc``). With
    `check_convergence` every MPC row is also driven at half δ and half S, and at twice its pedal
    levels (its work counts them), and gets the convergence columns."""
    layout = _checked_layout(controllers, check_convergence)
    checked = checked_axes(axes, overrides)
    profiles, directions = load_fleet(roads, reverse)
    vehicles = vehicle_paths(vehicle_path)
    names = vehicle_names(vehicles)
    bases = [Base(v, tuple(str(p) for p in config_paths), tuple(overrides)) for v in vehicles]
    check_size(checked, len(profiles) * len(bases))
    base_configs = [base.config() for base in bases]  # errors in the base name their file or --set
    layout = dataclasses.replace(layout, consumption=consumed_by(base_configs, names))
    fleet = [_combos(base, config, checked, profiles) for base, config in zip(bases, base_configs, strict=True)]
    rows = _rows(profiles, fleet, layout)
    settings = _settings(profiles, directions, checked, bases, base_configs, layout, names)
    return SweepPlan(
        tuple(profiles),
        tuple(directions),
        checked,
        vehicles,
        bases[0].config_paths,
        bases[0].overrides,
        tuple(rows),
        settings,
        check_convergence,
        layout.controllers,
        names,
        layout.consumption,
    )


Combo = tuple[tuple[Any, ...], tuple[str, ...], RunConfig, Mapping[str, Any]]
"""A combination's axis values, overrides, configuration and the values of its shared sections."""


def _combos(base: Base, base_config: RunConfig, axes: Sequence[Axis], profiles: Sequence[Road]) -> list[Combo]:
    """Every combination of `axes` on top of one vehicle's base, validated, each checked on every road."""
    keys = [axis.key for axis in axes]
    combinations = Combinations(base, base_config, axes)
    combos: list[Combo] = []
    for values in expand_grid(axes):
        texts = tuple(f"{key}={yaml_text(v)}" for key, v in zip(keys, values, strict=True))
        config = combinations.config(values, texts)
        for profile in profiles:
            if isinstance(profile, RoadProfile):
                check_trace(profile, config)
        combos.append((values, texts, config, _section_values(config)))
    return combos


def _rows(profiles: Sequence[Road], fleet: Sequence[Sequence[Combo]], layout: Layout) -> list[Row]:
    """The rows in grid order, road by road and vehicle by vehicle: each combination of each vehicle
    (`fleet`: a vehicle's combinations) on each road."""
    rows: list[Row] = []
    for r, profile in enumerate(profiles):
        for v, combos in enumerate(fleet):
            for values, texts, config, sections in combos:
                index = len(rows)
                keys = _run_keys(r, index, sections, layout)
                work = _look_ahead_work(profile, config, layout) if isinstance(profile, RoadProfile) else Work(0, 0, 0)
                rows.append(Row(index, r, values, texts, keys, work, v))
    return rows


def _checked_layout(controllers: Sequence[str], check_convergence: bool) -> Layout:
    """The columns of a sweep of `controllers`; a one-line :class:`SweepError` for a controller
    that is not ``pcc`` or ``mpc``, or ``--check-convergence`` without the MPC."""
    try:
        names = check_controllers(controllers)
    except ValueError as err:
        raise SweepError(f"--controller: {err}") from None
    if check_convergence and "mpc" not in names:
        raise SweepError(
            f"--check-convergence: expected mpc in --controller (it drives the MPC at half δ and half S), "
            f"got {','.join(names)}"
        )
    return Layout(names, check_convergence)


def _look_ahead_work(profile: RoadProfile, config: RunConfig, layout: Layout) -> Work:
    """The estimated work of a row's MPC run, with its runs at half δ, half S and twice its pedal levels when checked; a
    PCC run's (the plant's) without the MPC."""
    if "mpc" not in layout.controllers:
        return run_work(profile, config, "pcc")
    configs = [config, *(halved_configs(config).values() if layout.check_convergence else ())]
    works = [run_work(profile, c, "mpc") for c in configs]
    return Work(sum(w.plant_s for w in works), sum(w.dp_s for w in works), max(w.dp_bytes for w in works))


SHARED_SECTIONS = {
    "pi": ("vehicle", "vecto", "cruise", "pi", "sim"),
    "pcc": ("vehicle", "vecto", "cruise", "pi", "pcc", "sim"),
}
"""The controllers whose runs rows share, and the config sections such a run depends on (the PCC is
VECTO's rules on VECTO's driver, which shifts by the PI's gear logic: the PI's sections and its own)."""

_SHARED = tuple(dict.fromkeys(section for sections in SHARED_SECTIONS.values() for section in sections))


def _section_values(config: RunConfig) -> dict[str, dict[str, Any]]:
    """The values of the sections a shared run depends on, by section."""
    sections: dict[str, dict[str, Any]] = {name: {} for name in _SHARED}
    for key, value in config.settings.values().items():
        section = SPEC_BY_KEY[key].section
        if section in sections:
            sections[section][key] = value
    return sections


def _run_keys(road: int, index: int, sections: Mapping[str, Mapping[str, Any]], layout: Layout) -> dict[str, str]:
    """Controller -> the key of the row's run of it: for a shared run everything it depends on (the
    road and its sections' values, not the MPC's), for the MPC the row itself."""
    return {
        name: json.dumps([road, *(sections[s] for s in SHARED_SECTIONS[name])], sort_keys=True)
        if name in SHARED_SECTIONS
        else f"row {index}"
        for name in layout.runs
    }


def _settings(
    profiles: Sequence[Road],
    directions: Sequence[str],
    axes: Sequence[Axis],
    bases: Sequence[Base],
    base_configs: Sequence[RunConfig],
    layout: Layout,
    names: Sequence[str],
) -> dict[str, Any]:
    """The ``sweep.json`` document (without ``jobs``), as plain JSON values; with several vehicles
    ``vehicle`` lists their files and ``base_config`` maps each one's name to its configuration."""
    grid = [{"key": a.key, "spec": a.spec, "values": list(a.values)} for a in axes]
    columns = [*key_columns(axes, len(bases) > 1), *layout.columns]
    settings = study_settings(profiles, directions, grid, base_configs[0], bases[0], columns)
    if len(bases) > 1:
        settings["vehicle"] = [base.vehicle_path for base in bases]
        configs = {name: _config_doc(config) for name, config in zip(names, base_configs, strict=True)}
        settings["base_config"] = json.loads(json.dumps(configs))
    return settings


def study_settings(
    profiles: Sequence[Road],
    direction: str | Sequence[str],
    grid: Any,
    base_config: RunConfig,
    base: Any,
    columns: Sequence[str],
) -> dict[str, Any]:
    """The settings file of a sweep or Pareto study (without ``jobs``), as plain JSON values: what
    identifies it (roads and their directions — one for all, or one each —, `grid`, the resolved base
    configuration, columns) and the inputs as given (`base`: ``vehicle_path``, ``config_paths``,
    ``overrides``)."""
    directions = [direction] * len(profiles) if isinstance(direction, str) else list(direction)
    roads = [
        {"name": p.name, "direction": d, "sha256": p.sha256(), "path": p.source}
        for p, d in zip(profiles, directions, strict=True)
    ]
    settings = {
        "version": 1,
        "roads": roads,
        "grid": grid,
        "base_config": _config_doc(base_config),
        "vehicle": base.vehicle_path,
        "configs": list(base.config_paths),
        "overrides": list(base.overrides),
        "columns": list(columns),
    }
    doc: dict[str, Any] = json.loads(json.dumps(settings))
    return doc


def _config_doc(config: RunConfig) -> dict[str, Any]:
    """A resolved configuration as a document, without where each value came from."""
    doc = config.as_dict()
    doc.pop("sources")
    return doc

"""The plan of a sweep: its roads and rows, each row's overrides and run keys, all validated
before anything runs.

The PI run depends only on the road, the vehicle, the PI and the simulation settings, and the PCC's
on those and the ``pcc`` section, so each row carries, per controller, a key made of those *resolved
values*: rows with the same key share one run (an axis over an MPC key needs one PI run and one PCC
run per road, an axis over ``v_ref_kmh`` or ``mass_kg`` one per value). Each MPC run is its row's own.
"""

from __future__ import annotations

import functools
import json
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from truckmpc.config import SPEC_BY_KEY, RunConfig
from truckmpc.convergence import halved_configs
from truckmpc.road import PathLike, RoadProfile
from truckmpc.sweep.columns import DEFAULT_CONTROLLERS, Layout, cell, check_controllers, yaml_text
from truckmpc.sweep.errors import SweepError
from truckmpc.sweep.grid import Axis, expand_grid
from truckmpc.sweep.inputs import Base, Combinations, check_size, checked_axes, load_profiles
from truckmpc.workload import Work, check_trace, run_work


@dataclass(frozen=True)
class Row:
    """One (road, combination) of a sweep: its place in grid order, its overrides, the key of each
    of its runs (controller -> key; rows with the same key share the run) and the estimated work of
    its look-ahead run (:mod:`truckmpc.workload`: the MPC's if it runs, else the PCC's; a PI or PCC
    run's is the plant part)."""

    index: int
    road: int
    values: tuple[Any, ...]
    overrides: tuple[str, ...]
    keys: Mapping[str, str]
    work: Work

    @property
    def pi_key(self) -> str:
        return self.keys["pi"]

    @property
    def cost(self) -> float:
        """Estimated seconds of the row's look-ahead run [s] (the longest are scheduled first)."""
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
    controllers: tuple[str, ...] = DEFAULT_CONTROLLERS

    @functools.cached_property
    def layout(self) -> Layout:
        """The result columns and how a row's runs fill them."""
        return Layout(self.controllers, self.check_convergence)

    @property
    def columns(self) -> tuple[str, ...]:
        return ("road", "direction", *(axis.key for axis in self.axes), *self.layout.columns)

    def row_key(self, row: Row) -> tuple[str, ...]:
        """The cells that identify a row in the CSV: road, direction and the axis values."""
        return (self.roads[row.road].name, self.direction, *(cell(v) for v in row.values))


def plan_sweep(
    roads: Sequence[RoadProfile | PathLike],
    axes: Sequence[Axis | str] | Mapping[str, Sequence[Any]] = (),
    *,
    reverse: bool = False,
    vehicle_path: PathLike | None = None,
    config_paths: Sequence[PathLike] = (),
    overrides: Sequence[str] = (),
    check_convergence: bool = False,
    controllers: Sequence[str] = DEFAULT_CONTROLLERS,
) -> SweepPlan:
    """Load the roads and validate the configuration of every combination; raise a one-line
    :class:`~truckmpc.errors.TruckmpcError` naming the road, the ``--set``, the ``--grid`` axis or
    the ``--controller``. Each row runs the PI and `controllers` (``pcc``, ``mpc``). With
    `check_convergence` every MPC row is also driven at half δ and half S (its work counts them) and
    gets the convergence columns."""
    layout = _checked_layout(controllers, check_convergence)
    checked = checked_axes(axes, overrides)
    profiles = load_profiles(roads, reverse)
    base = Base(
        None if vehicle_path is None else str(vehicle_path), tuple(str(p) for p in config_paths), tuple(overrides)
    )
    check_size(checked, len(profiles))
    base_config = base.config()  # errors in the base name their file or --set
    keys = [axis.key for axis in checked]
    combinations = Combinations(base, base_config, checked)
    combos = []
    for values in expand_grid(checked):
        texts = tuple(f"{key}={yaml_text(v)}" for key, v in zip(keys, values, strict=True))
        config = combinations.config(values, texts)
        for profile in profiles:
            check_trace(profile, config)
        combos.append((values, texts, config, _section_values(config)))
    rows = _rows(profiles, combos, layout)
    direction = "reverse" if reverse else "forward"
    settings = _settings(profiles, direction, checked, base, base_config, layout)
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
        layout.controllers,
    )


def _rows(
    profiles: Sequence[RoadProfile],
    combos: Sequence[tuple[tuple[Any, ...], tuple[str, ...], RunConfig, Mapping[str, Any]]],
    layout: Layout,
) -> list[Row]:
    """The rows in grid order, road by road: each combination's (values, overrides, configuration,
    section values) on each road."""
    rows: list[Row] = []
    for r, profile in enumerate(profiles):
        for values, texts, config, sections in combos:
            index = len(rows)
            keys = _run_keys(r, index, sections, layout)
            rows.append(Row(index, r, values, texts, keys, _look_ahead_work(profile, config, layout)))
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
    """The estimated work of a row's MPC run, with its runs at half δ and half S when checked; a
    PCC run's (the plant's) without the MPC."""
    if "mpc" not in layout.controllers:
        return run_work(profile, config, "pcc")
    configs = [config, *(halved_configs(config).values() if layout.check_convergence else ())]
    works = [run_work(profile, c, "mpc") for c in configs]
    return Work(sum(w.plant_s for w in works), sum(w.dp_s for w in works), max(w.dp_bytes for w in works))


SHARED_SECTIONS = {"pi": ("vehicle", "cruise", "pi", "sim"), "pcc": ("vehicle", "cruise", "pi", "pcc", "sim")}
"""The controllers whose runs rows share, and the config sections such a run depends on (the PCC is
VECTO's rules on the PI: the PI's sections and its own)."""

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
    profiles: Sequence[RoadProfile],
    direction: str,
    axes: Sequence[Axis],
    base: Base,
    base_config: RunConfig,
    layout: Layout,
) -> dict[str, Any]:
    """The ``sweep.json`` document (without ``jobs``), as plain JSON values."""
    grid = [{"key": a.key, "spec": a.spec, "values": list(a.values)} for a in axes]
    columns = ["road", "direction", *(a.key for a in axes), *layout.columns]
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

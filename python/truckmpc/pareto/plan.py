"""The points of a fuel–time (battery energy–time) Pareto study: which controller runs with which
set speed or β on which road, each configuration validated before anything runs.

Curves:

- ``pi``: the baseline over the set speeds;
- ``pcc``: VECTO's rule-based predictive cruise control (on VECTO's cruise driver) over the set speeds;
- ``mpc``: the configured look-ahead controller (the thesis's cost by default) over the set speeds;
- ``fuel_time``: the look-ahead controller with the ``fuel_time`` preset, over the set speeds with β
  derived from each, or over ``betas`` at the configured v_ref.

A battery-electric truck's study is of battery energy: its columns are ``energy_kwh``,
``energy_corrected_kwh`` and ``beta_j_per_s`` (β in J/s) where a diesel truck's are ``fuel_kg``,
``fuel_corrected_kg`` and ``beta_g_per_s``; the curve is still named ``fuel_time``, as the preset it
runs (its cost is the battery energy + β·time).

The speed band moves with each set speed (``v_inc_kmh``/``v_dec_kmh`` are offsets); every run starts
at the configured start speed clipped into its band, and its end-speed-corrected fuel brings it
back to that start speed. The ``fuel_time`` preset's keys come first, the user's ``--set`` over
them, then each point's set speed or β.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from truckmpc.config import RunConfig, load_run_config
from truckmpc.config.keys import PRESET_DIR
from truckmpc.config.yamlfile import read_mapping
from truckmpc.consumption import ENERGY, FUEL, Consumption
from truckmpc.errors import ConfigError
from truckmpc.fuel import beta_per_s
from truckmpc.roads import RoadProfile
from truckmpc.roads.profile import PathLike
from truckmpc.sweep.cells import cell, yaml_text
from truckmpc.sweep.errors import SweepError
from truckmpc.sweep.inputs import load_profiles
from truckmpc.sweep.plan import study_settings
from truckmpc.workload import Work, check_trace, run_work

CURVES = ("pi", "pcc", "mpc", "fuel_time")
"""The curves of a Pareto study, in the order they are drawn."""

DEFAULT_CURVES = ("pi", "mpc", "fuel_time")
"""The curves run when none are named."""

CURVE_CONTROLLERS = {"pi": "pi", "pcc": "pcc", "mpc": "mpc", "fuel_time": "mpc"}
"""The built-in controller that drives each curve."""

SPEED_OFFSETS_KMH = (-8.0, -6.0, -4.0, -2.0, 0.0, 2.0, 4.0)
"""Default set speeds: these offsets from the configured v_ref [km/h]."""

PARETO_COLUMNS = (
    "road",
    "direction",
    "controller",
    "parameter",
    "value",
    "v_ref_kmh",
    "beta_g_per_s",
    "fuel_kg",
    "fuel_corrected_kg",
    "time_s",
    "end_speed_kmh",
    "stalled",
    "error",
)
"""Columns of a diesel truck's ``pareto.csv``; ``parameter`` names what the curve varies
(``v_ref_kmh`` or ``beta_g_per_s``) and ``value`` its value; ``error`` why the run failed (its
figures and ``stalled`` blank), blank when it did not."""


def pareto_columns(consumption: Consumption) -> tuple[str, ...]:
    """The columns of ``pareto.csv`` for trucks that consume `consumption` (:data:`PARETO_COLUMNS`
    named for battery energy and β in J/s for a battery-electric truck)."""
    return tuple(consumption.worded(column) for column in PARETO_COLUMNS)


def consumption_of_pareto(header: Sequence[str]) -> Consumption | None:
    """What the study whose ``pareto.csv`` has `header` compares, or None if it is no study's."""
    return next((c for c in (FUEL, ENERGY) if tuple(header) == pareto_columns(c)), None)


@dataclass(frozen=True)
class Point:
    """One run of a Pareto study: curve ``curve`` on road number ``road`` at ``parameter`` =
    ``value`` (with its set speed and β), its ``key=value`` overrides and estimated work."""

    index: int
    road: int
    curve: str
    parameter: str
    value: float
    v_ref_kmh: float
    beta_per_s: float | None
    """β of a look-ahead point, in its truck's unit (g/s, or J/s for a battery-electric truck)."""
    overrides: tuple[str, ...]
    work: Work

    @property
    def controller(self) -> str:
        """The built-in controller that drives the point."""
        return CURVE_CONTROLLERS[self.curve]


@dataclass(frozen=True)
class ParetoPlan:
    """A validated Pareto study: roads (reversed when ``direction`` is reverse), the base files and
    overrides, the points, the ``pareto.json`` settings and what its trucks consume."""

    roads: tuple[RoadProfile, ...]
    direction: str
    vehicle_path: str | None
    config_paths: tuple[str, ...]
    base_v_ref_kmh: float
    points: tuple[Point, ...]
    settings: dict[str, Any]
    consumption: Consumption = FUEL

    @property
    def columns(self) -> tuple[str, ...]:
        """The columns of its ``pareto.csv``."""
        return pareto_columns(self.consumption)

    def point_key(self, point: Point) -> tuple[str, ...]:
        """The cells that identify a point in the CSV."""
        return (self.roads[point.road].name, self.direction, point.curve, point.parameter, cell(point.value))


def plan_pareto(
    roads: Sequence[RoadProfile | PathLike],
    *,
    speeds_kmh: Sequence[float] | None = None,
    betas: Sequence[float] | None = None,
    curves: Sequence[str] = DEFAULT_CURVES,
    reverse: bool = False,
    vehicle_path: PathLike | None = None,
    config_paths: Sequence[PathLike] = (),
    overrides: Sequence[str] = (),
) -> ParetoPlan:
    """Load the roads and validate every point's configuration; errors are one line naming the key.
    `betas` are in the truck's unit of β: g/s, or J/s for a battery-electric truck."""
    _check_choices(curves, speeds_kmh, betas)
    profiles = load_profiles(roads, reverse)
    vehicle = None if vehicle_path is None else str(vehicle_path)
    configs = tuple(str(p) for p in config_paths)
    base = load_run_config(vehicle, configs, tuple(overrides))
    consumption = ENERGY if base.is_electric else FUEL
    v_ref = float(base.cruise.v_ref_kmh)
    speeds = [v_ref + d for d in SPEED_OFFSETS_KMH] if speeds_kmh is None else list(speeds_kmh)
    specs = _specs(curves, speeds, betas, v_ref, consumption.beta_key)
    points: list[Point] = []
    for r, profile in enumerate(profiles):
        for curve, parameter, value, v in specs:
            # The curve's preset first, the user's --set over it, then the point's own values.
            preset = _preset_overrides("fuel_time") if curve == "fuel_time" else ()
            own = (f"{parameter}={yaml_text(value)}", f"start_speed_kmh={yaml_text(_start_kmh(base, v))}")
            extra = (*preset, *overrides, *own)
            config = _point_config(vehicle, configs, extra, curve, parameter, value)
            check_trace(profile, config)
            controller = CURVE_CONTROLLERS[curve]
            beta = beta_per_s(config.settings.derived()) if controller == "mpc" else None
            work = run_work(profile, config, controller)
            points.append(Point(len(points), r, curve, parameter, float(value), v, beta, extra, work))
    direction = "reverse" if reverse else "forward"
    betas_key = consumption.beta_key.replace("beta", "betas", 1)
    grid = {"curves": list(curves), "speeds_kmh": speeds, betas_key: betas and list(betas)}
    inputs = _Inputs(vehicle, configs, tuple(overrides))
    settings = study_settings(profiles, direction, grid, base, inputs, pareto_columns(consumption))
    return ParetoPlan(tuple(profiles), direction, vehicle, configs, v_ref, tuple(points), settings, consumption)


def _check_choices(curves: Sequence[str], speeds: Sequence[float] | None, betas: Sequence[float] | None) -> None:
    """Curves known and each given once, values each given once, --betas only with the fuel_time curve."""
    unknown = [c for c in curves if c not in CURVES]
    if unknown or not curves or len(set(curves)) < len(curves):
        raise SweepError(f"--curves: expected some of {', '.join(CURVES)}, each once, got {','.join(curves) or 'none'}")
    for option, values in (("--speeds", speeds), ("--betas", betas)):
        twice = [v for i, v in enumerate(values or ()) if v in list(values or ())[:i]]
        if twice:
            raise SweepError(f"{option}: expected each value once, got {cell(float(twice[0]))} twice")
    if betas is not None and "fuel_time" not in curves:
        raise SweepError("--betas: expected the fuel_time curve in --curves (β is its parameter)")


def _specs(
    curves: Sequence[str], speeds: Sequence[float], betas: Sequence[float] | None, v_ref: float, beta_key: str
) -> list[tuple[str, str, float, float]]:
    """(curve, parameter, value, set speed) of every point on one road; β is the key `beta_key`."""
    specs: list[tuple[str, str, float, float]] = []
    for curve in curves:
        if curve == "fuel_time" and betas is not None:
            specs += [(curve, beta_key, float(b), v_ref) for b in betas]
        else:
            specs += [(curve, "v_ref_kmh", float(v), float(v)) for v in speeds]
    return specs


def _start_kmh(base: RunConfig, v_ref_kmh: float) -> float:
    """The start speed of a point driven at `v_ref_kmh`: the configured one (or v_ref) clipped into
    that set speed's band, so that no run begins by braking away what it was given."""
    cruise, start = base.cruise, base.sim.start_speed_kmh
    start = cruise.v_ref_kmh if start is None else start
    return float(min(max(start, v_ref_kmh - cruise.v_dec_kmh), v_ref_kmh + cruise.v_inc_kmh))


def _preset_overrides(name: str) -> tuple[str, ...]:
    """A packaged preset's keys as ``key=value`` overrides."""
    mapping, _where, _lines = read_mapping(PRESET_DIR / f"{name}.yaml")
    return tuple(f"{key}={yaml_text(value)}" for key, value in mapping.items())


def _point_config(
    vehicle: str | None, configs: tuple[str, ...], overrides: tuple[str, ...], curve: str, parameter: str, value: float
) -> RunConfig:
    """The configuration of one point; its errors say which curve and parameter value."""
    try:
        return load_run_config(vehicle, configs, overrides)
    except ConfigError as err:
        raise SweepError(f"{curve} at {parameter}={cell(value)}: {err}") from None


@dataclass(frozen=True)
class _Inputs:
    """The base inputs as given, for ``pareto.json``."""

    vehicle_path: str | None
    config_paths: tuple[str, ...]
    overrides: tuple[str, ...]

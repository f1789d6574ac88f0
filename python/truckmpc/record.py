"""What was run, recorded in `summary.json` so that the run can be repeated exactly.

The record names the program and its version, the road (name, file, length, SHA-256 of its points,
direction), the map the controllers planned on if it was another road, the controllers, the inputs
as the user gave them (vehicle file, overlay files, `--set` overrides), every resolved parameter and
the command line that asked for the run (with its working directory).
`truckmpc simulate --replay summary.json` rebuilds the run from the resolved parameters and the
road file, checking that the road is still the one that was run.
"""

from __future__ import annotations

import dataclasses
import json
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from truckmpc.config import RunConfig, config_from_values
from truckmpc.config.keys import current_values
from truckmpc.errors import ConfigError, RoadError, read_user_text
from truckmpc.roads import RoadProfile, default_test_track, load_road
from truckmpc.sim import CONTROLLERS
from truckmpc.units import PCT_PER_FRACTION
from truckmpc.vecto.replay import check_read_files, recorded_job, truck_record

MAP_SLACK = 0.02
"""Share of the road's length by which the controllers' map may differ at either end: the core's
MAP_SLACK (rust/truckmpc-core/src/sim/run.rs), checked here first for an error naming the file."""

WALL_CLOCK_FIELDS = frozenset({"compute_time_s", "realtime_ratio", "solve_ms_mean", "solve_ms_max"})
"""Summary fields that measure the computer, not the truck: a replay reproduces every other field."""


@dataclass(frozen=True)
class RunRequest:
    """A `simulate` command's inputs as the user gave them."""

    road_path: str | None
    """The road file; None for the bundled test track."""
    reverse: bool
    controllers: tuple[str, ...]
    vehicle_path: str | None = None
    config_paths: tuple[str, ...] = ()
    overrides: tuple[str, ...] = ()
    check_convergence: bool = False
    """Whether the MPC also ran at half δ and half S (`--check-convergence`)."""
    controller_road_path: str | None = None
    """The road the controllers planned on, if not the road driven (`--controller-road`)."""
    command: Mapping[str, Any] | None = None
    """The command line that asked for the run, ``{"argv": [...], "cwd": DIR}``; None from the Python API."""


def program_version() -> str:
    """The installed truckmpc's version."""
    # Imported here: importlib.metadata brings email, zipfile and socket, about 20 ms that every
    # `import truckmpc` would pay for a figure only a run's record and --version print.
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("truckmpc")
    except PackageNotFoundError:  # running from a source tree that was never installed
        return "unknown"


def program_record() -> dict[str, str]:
    """The program that ran: ``{"name": "truckmpc", "version": ...}``."""
    return {"name": "truckmpc", "version": program_version()}


def run_record(request: RunRequest, profile: RoadProfile, config: RunConfig) -> dict[str, Any]:
    """The `run` object of `summary.json`."""
    road_path = None if request.road_path is None else str(Path(request.road_path).resolve())
    settings = config.as_dict()
    settings.pop("sources")
    return {
        "program": program_record(),
        "road": {
            "name": profile.name,
            "path": road_path,
            "length_m": profile.length_m,
            "sha256": profile.sha256(),
            "reverse": request.reverse,
            "target_speeds": profile.target_speed_kmh is not None,
        },
        "controllers": list(request.controllers),
        "controller_road": _controller_road(request, profile),
        "check_convergence": request.check_convergence,
        "inputs": {
            "vehicle": request.vehicle_path,
            "configs": list(request.config_paths),
            "overrides": list(request.overrides),
        },
        "settings": settings,
        "vehicle": None if config.truck is None else truck_record(config.truck),
        "command": None if request.command is None else dict(request.command),
    }


def _controller_road(request: RunRequest, profile: RoadProfile) -> dict[str, Any] | None:
    """The `controller_road` record: the map the controllers planned on, or None."""
    told = profile.controller_map
    if told is None or request.controller_road_path is None:
        return None
    return {"path": str(Path(request.controller_road_path).resolve()), "sha256": told.sha256()}


def with_controller_road(profile: RoadProfile, path: str | os.PathLike[str] | None, reverse: bool) -> RoadProfile:
    """`profile` with the road read from `path` (driven the same way) as the controllers' map."""
    if path is None:
        return profile
    told = load_road(path)
    slack_m = MAP_SLACK * profile.length_m
    ends = (told.distance_m[0] - profile.distance_m[0], told.distance_m[-1] - profile.distance_m[-1])
    if max(abs(end) for end in ends) > slack_m:
        slack_pct = PCT_PER_FRACTION * MAP_SLACK
        raise RoadError(
            f"{path}: --controller-road: expected a road spanning the road driven "
            f"({profile.distance_m[0]:.0f}..{profile.distance_m[-1]:.0f} m) to within {slack_pct:g} %, "
            f"got {told.distance_m[0]:.0f}..{told.distance_m[-1]:.0f} m"
        )
    if reverse:
        told = told.mirrored(profile.distance_m[0] + profile.distance_m[-1])
    return dataclasses.replace(profile, controller_map=map_with_targets_of(profile, told))


def map_with_targets_of(profile: RoadProfile, told: RoadProfile) -> RoadProfile:
    """The map `told` with the target speeds of the road driven (a map tells the grades; the
    targets are the run's): without them the controllers would plan in the uniform band while the
    truck follows the road's."""
    targets = None if profile.target_speed_kmh is None else profile.target_speed_at(told.distance_m)
    return dataclasses.replace(told, target_speed_kmh=targets, stops=())


def load_replay(path: Path) -> tuple[RunRequest, RoadProfile, RunConfig]:
    """The request, road and configuration recorded in a `summary.json`; the road must still hash
    to the recorded SHA-256, and the controllers be some of :data:`truckmpc.sim.CONTROLLERS`."""
    where = str(path)
    try:
        doc = json.loads(read_user_text(path, where, "a summary.json file", ConfigError))
    except json.JSONDecodeError as err:
        raise ConfigError(f"{where}:{err.lineno}: invalid JSON: {err.msg}") from None
    run = _field(doc, "run", dict, where)
    road = _field(run, "road", dict, f"{where}: run")
    settings = _field(run, "settings", dict, f"{where}: run")
    values = {
        key: value for section in settings.values() if isinstance(section, dict) for key, value in section.items()
    }
    recorded = recorded_job(run.get("vehicle"), where)
    # A record made before the truck's keys were settings holds those set in run.vehicle.keys.
    job, truck_keys = (None, {}) if recorded is None else recorded
    config = config_from_values(current_values({**truck_keys, **values}), f"{where}: run.settings", job)
    if config.truck is not None:
        check_read_files(config.truck, run["vehicle"], where)
    road_path = _field(road, "path", (str, type(None)), f"{where}: run.road")
    reverse = _field(road, "reverse", bool, f"{where}: run.road")
    profile = default_test_track() if road_path is None else load_road(road_path)
    profile = profile.reversed() if reverse else profile
    told = run.get("controller_road")
    told_path = _field(told, "path", str, f"{where}: run.controller_road") if told is not None else None
    profile = with_controller_road(profile, told_path, reverse)
    if told is not None and profile.controller_map is not None:
        _check_hash(where, "run.controller_road", told, profile.controller_map, told_path)
    _check_hash(where, "run.road", road, profile, road_path or "the bundled test track")
    controllers = tuple(_field(run, "controllers", list, f"{where}: run"))
    inputs = _field(run, "inputs", dict, f"{where}: run")
    given = (inputs.get("vehicle"), tuple(inputs.get("configs", ())), tuple(inputs.get("overrides", ())))
    check = run.get("check_convergence", False)
    if not isinstance(check, bool):
        raise ConfigError(f"{where}: run: key 'check_convergence': expected bool, got {type(check).__name__}")
    unknown = [name for name in controllers if name not in CONTROLLERS]
    if unknown or not controllers:
        raise ConfigError(f"{where}: run.controllers: expected some of {', '.join(CONTROLLERS)}, got {unknown}")
    command = run.get("command")  # a replay is the run its summary's command asked for
    request = RunRequest(
        road_path,
        reverse,
        controllers,
        *given,
        check_convergence=check,
        controller_road_path=told_path,
        command=command if isinstance(command, dict) else None,
    )
    return request, profile, config


def _check_hash(where: str, key: str, record: Mapping[str, Any], profile: RoadProfile, path: str | None) -> None:
    recorded = _field(record, "sha256", str, f"{where}: {key}")
    if profile.sha256() != recorded:
        raise ConfigError(
            f"{where}: {key}.sha256: expected the road that was run ({recorded[:12]}...), "
            f"got {profile.sha256()[:12]}... from {path}"
        )


def _field(doc: Mapping[str, Any], key: str, kind: type | tuple[type, ...], where: str) -> Any:
    if not isinstance(doc, Mapping) or key not in doc:
        raise ConfigError(f"{where}: missing key {key!r} (not a summary.json written by truckmpc simulate)")
    value = doc[key]
    if not isinstance(value, kind):
        raise ConfigError(f"{where}: key {key!r}: expected {_kind_text(kind)}, got {type(value).__name__}")
    return value


def _kind_text(kind: type | tuple[type, ...]) -> str:
    kinds: Sequence[type] = kind if isinstance(kind, tuple) else (kind,)
    return " or ".join("null" if k is type(None) else k.__name__ for k in kinds)

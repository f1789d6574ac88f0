"""A VECTO job as a run's vehicle: the truck's own keys (load, trailer, air drag, losses) split from
the run's overrides, and the PI shift speeds that suit its engine.

The run's other vehicle keys describe the thesis's truck; with a VECTO job only
``brake_torque_max_nm`` (the service brakes, which VECTO's files do not give) still applies, so
setting any other is refused rather than ignored.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import fields
from pathlib import Path
from typing import Any

import yaml

from truckmpc import _core
from truckmpc.config.keys import VEHICLE_KEYS
from truckmpc.config.yamlfile import load_value
from truckmpc.errors import ConfigError
from truckmpc.vecto.truck import TruckKeys, VectoTruck, load_vecto_truck, pi_shift_speeds_rpm

__all__ = ["TRUCK_KEYS", "is_vecto_job", "truck_layer", "vecto_truck"]

TRUCK_KEYS = tuple(f.name for f in fields(TruckKeys))
"""Keys of a VECTO truck a user may set with ``--set`` (see :class:`truckmpc.vecto.TruckKeys`)."""

_STILL_APPLIES = ("brake_torque_max_nm",)


def is_vecto_job(path: object) -> bool:
    """Whether a vehicle path names a VECTO truck: a job (``.vecto``) or a declaration XML."""
    return str(path).lower().endswith((".vecto", ".xml"))


def vecto_truck(path: Path, overrides: Sequence[str]) -> tuple[VectoTruck, tuple[str, ...]]:
    """The truck of the job at ``path`` with the truck's keys among ``overrides`` applied, and the
    overrides left for the run's settings."""
    values: dict[str, Any] = {}
    rest: list[str] = []
    for text in overrides:
        key, sep, raw = text.partition("=")
        key = key.strip()
        if sep and key in TRUCK_KEYS:
            try:
                values[key] = load_value(raw)
            except yaml.YAMLError:
                raise ConfigError(f"--set {key}: expected a YAML value, got {raw.strip()!r}") from None
            continue
        if sep and key in VEHICLE_KEYS and key not in _STILL_APPLIES:
            raise ConfigError(
                f"--set {key}: expected a key of the VECTO truck ({', '.join(TRUCK_KEYS)}) or "
                f"{', '.join(_STILL_APPLIES)}, got a key of the thesis's truck, which {path.name} replaces"
            )
        rest.append(text)
    return load_vecto_truck(path, values), tuple(rest)


def truck_layer(truck: VectoTruck) -> dict[str, Any]:
    """The run's keys the truck sets: the vehicle keys its components give (so that the settings a
    run records, and the checks between keys, describe this truck) and the PI's shift speeds for
    its engine (``gear_down_rpm``, ``gear_up_rpm``)."""
    job, keys, gears = truck.job, truck.keys, len(truck.job.gearbox.gear_ratios)
    down, up = pi_shift_speeds_rpm(truck)
    return {
        "mass_kg": truck.mass_kg,
        "engine_inertia_kgm2": job.engine.inertia_kgm2,
        "idle_speed_rpm": job.engine.idle_speed_rpm,
        "final_drive_ratio": job.gearbox.axle_ratio,
        "final_drive_efficiency": keys.axle_efficiency,
        "wheel_radius_m": truck.wheel_radius_m,
        "rolling_resistance": truck.rolling_resistance,
        "gravity_mps2": _core.G_MPS2,
        "air_density_kgpm3": keys.air_density_kg_m3,
        "gear_ratios": list(job.gearbox.gear_ratios),
        "gear_efficiencies": [keys.gear_efficiency] * gears,
        "gear_down_rpm": down,
        "gear_up_rpm": up,
    }

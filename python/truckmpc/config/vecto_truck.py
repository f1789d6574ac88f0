"""A VECTO job as a run's vehicle: the truck built from its keys' values in the run's layers (each
checked by the core against its declaration), the vehicle keys and PI shift speeds it gives the run.

The run's other vehicle keys describe the thesis's truck; with a VECTO job only
``brake_torque_max_nm`` (the service brakes, which VECTO's files do not give) and
``air_density_kgpm3`` (VECTO's 1.188 unless set) still apply, so setting any other is refused
rather than ignored.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

from truckmpc import _core
from truckmpc.config.keys import KEYS, VEHICLE_KEYS
from truckmpc.config.layers import Layers
from truckmpc.config.yamlfile import parse_assignment
from truckmpc.errors import ConfigError, VehicleError
from truckmpc.vecto import declaration as decl
from truckmpc.vecto.electric_truck import ElectricVectoTruck
from truckmpc.vecto.truck import (
    TRUCK_KEYS,
    AnyVectoTruck,
    VectoTruck,
    load_vecto_truck,
    pi_shift_speeds_rpm,
    truck_values,
)

__all__ = [
    "ELECTRIC_KEYS",
    "STILL_APPLIES",
    "VECTO_VALUES",
    "build_truck",
    "diesel_truck_from_overrides",
    "electric_truck_keys",
    "is_vecto_job",
    "refuse_thesis_key",
    "truck_from_overrides",
    "truck_layer",
]

STILL_APPLIES = ("brake_torque_max_nm", "air_density_kgpm3")
"""The thesis's vehicle keys a VECTO truck still uses."""
VECTO_VALUES: dict[str, Any] = {"air_density_kgpm3": decl.AIR_DENSITY_KG_M3}
"""VECTO's values of keys the thesis's truck gives otherwise: the layer under a user's own."""


def is_vecto_job(path: object) -> bool:
    """Whether a vehicle path names a VECTO truck: a job (``.vecto``) or a declaration XML."""
    return str(path).lower().endswith((".vecto", ".xml"))


def refuse_thesis_key(key: str, job: Path) -> None:
    """A `--set` of a key of the thesis's truck that the VECTO job replaces: refused, not ignored."""
    if key in VEHICLE_KEYS and key not in STILL_APPLIES:
        raise ConfigError(
            f"--set {key}: expected a key of the VECTO truck ({', '.join(TRUCK_KEYS)}) or "
            f"{', '.join(k for k in STILL_APPLIES if k not in TRUCK_KEYS)}, got a key of the thesis's truck, "
            f"which {job.name} replaces"
        )


def build_truck(job: Path, layers: Layers) -> AnyVectoTruck:
    """The truck of `job` from the layers' values of its keys; a bad value is blamed on its origin."""
    try:
        return load_vecto_truck(job, {key: layers.values[key] for key in TRUCK_KEYS if key in layers.values})
    except _core.ParamError as err:
        raise layers.blame(err) from None


def truck_from_overrides(job: Path, overrides: Sequence[str]) -> AnyVectoTruck:
    """The truck of `job` with `--set key=value` overrides of its keys (``truckmpc vehicle info``)."""
    return build_truck(job, _override_layers(job, overrides))


def diesel_truck_from_overrides(job: Path, overrides: Sequence[str], command: str) -> VectoTruck:
    """:func:`truck_from_overrides` for a command that needs an engine-driven truck; a
    battery-electric one is refused in one line naming `command`."""
    truck = truck_from_overrides(job, overrides)
    if isinstance(truck, ElectricVectoTruck):
        raise VehicleError(
            f"{job}: expected a diesel truck for '{command}' (not built for a battery-electric truck yet), "
            f"got a battery-electric truck ({truck.job.architecture})"
        )
    return truck


ELECTRIC_KEYS = ("mission", "payload_kg", "trailer_mass_kg", "cross_wind", "aux_power_w", "soc_start_pct")
"""The VECTO truck's keys that apply to a battery-electric truck: its declaration-mode combination's,
the auxiliaries' power and the state of charge at the start (the others describe a diesel driveline)."""


def electric_truck_keys(job: Path, overrides: Sequence[str]) -> dict[str, Any]:
    """The VECTO truck's keys with `--set key=value` overrides of :data:`ELECTRIC_KEYS`, as the core
    reads them (a battery-electric truck, which ``vehicle info`` shows); any other key is refused."""
    for text in overrides:
        key = parse_assignment(text)[0]
        if key not in ELECTRIC_KEYS:
            raise ConfigError(
                f"--set {key}: expected a key a battery-electric truck takes ({', '.join(ELECTRIC_KEYS)}), got another"
            )
    layers = _override_layers(job, overrides)
    try:
        return truck_values({key: layers.values[key] for key in TRUCK_KEYS if key in layers.values})
    except _core.ParamError as err:
        raise layers.blame(err) from None


def _override_layers(job: Path, overrides: Sequence[str]) -> Layers:
    """`--set key=value` overrides of the VECTO truck's keys, each refused unless it is one."""
    layers = Layers()
    for text in overrides:
        key, value = parse_assignment(text)
        refuse_thesis_key(key, job)
        if key in KEYS and key not in TRUCK_KEYS:
            raise ConfigError(
                f"--set {key}: expected a key of the VECTO truck ({', '.join(TRUCK_KEYS)}), got a run's key"
            )
        layers.override(key, value, TRUCK_KEYS)
    return layers


def truck_layer(truck: AnyVectoTruck) -> dict[str, Any]:
    """The run's keys the truck sets: the vehicle keys its components give (so that the settings a
    run records, and the checks between keys, describe this truck) and the PI's shift speeds for
    its engine (``gear_down_rpm``, ``gear_up_rpm``)."""
    if isinstance(truck, ElectricVectoTruck):
        return _electric_layer(truck)
    job, keys, gears = truck.job, truck.keys, len(truck.job.gearbox.gear_ratios)
    down, up = pi_shift_speeds_rpm(truck)
    return {
        "mass_kg": truck.mass_kg,
        "engine_inertia_kgm2": job.engine.inertia_kgm2,
        "idle_speed_rpm": job.engine.idle_speed_rpm,
        "final_drive_ratio": job.gearbox.axle_ratio,
        "final_drive_efficiency": keys["axle_efficiency"],
        "wheel_radius_m": truck.wheel_radius_m,
        "rolling_resistance": truck.rolling_resistance,
        "gravity_mps2": _core.G_MPS2,
        "gear_ratios": list(job.gearbox.gear_ratios),
        "gear_efficiencies": [keys["gear_efficiency"]] * gears,
        "gear_down_rpm": down,
        "gear_up_rpm": up,
    }


def _electric_layer(truck: ElectricVectoTruck) -> dict[str, Any]:
    """A battery-electric truck's vehicle keys: one gear of the reduction's ratio, the machines'
    inertia, no shift speeds (the core sets the same from the truck; these describe it in a run's
    record)."""
    machine = truck.job.machine
    return {
        "mass_kg": truck.mass_kg,
        "engine_inertia_kgm2": machine.count * machine.inertia_kgm2,
        "final_drive_ratio": 1.0,
        "final_drive_efficiency": 1.0,
        "wheel_radius_m": truck.wheel_radius_m,
        "rolling_resistance": truck.rolling_resistance,
        "gravity_mps2": _core.G_MPS2,
        "gear_ratios": [truck.job.reduction.ratio],
        "gear_efficiencies": [1.0],
        "gear_down_rpm": [None],
        "gear_up_rpm": [None],
    }

"""A VECTO job made into a truck the core simulates: the components as read, plus what declaration
mode adds (trailer, load, the combination's air drag and rolling resistance, auxiliaries), each a
key a user can see and override.
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from truckmpc import _core
from truckmpc.errors import VehicleError
from truckmpc.vecto import declaration as decl
from truckmpc.vecto.combination import declared_combination
from truckmpc.vecto.components import VectoJob, read_job
from truckmpc.vecto.electric import ElectricTruckJob
from truckmpc.vecto.electric_truck import ElectricVectoTruck, load_electric_truck
from truckmpc.vecto.parts import Body, Driveline
from truckmpc.vecto.xml_file import read_declaration_xml

__all__ = [
    "DRIVELINE_LOSS_NOTE",
    "TRUCK_KEYS",
    "AnyVectoTruck",
    "VectoTruck",
    "driveline_losses",
    "load_vecto_truck",
    "pi_shift_speeds_rpm",
    "truck_values",
]

DRIVELINE_LOSS_NOTE = (
    "without loss maps, the gearbox and axle lose a torque affine in the torque: the defaults "
    "(gear_efficiency 0.9546, loss_torque_nm 107, axle_efficiency 1) are fitted on VECTO's generic "
    "tractor's full-load climb in gear 11 and used in every gear"
)
_VECTO_SPECS = [record for record in _core.declaration("parameters") if record["section"] == "vecto"]
"""The core's records of its ``vecto`` section (``truckmpc.config.keys.ParamSpec`` types them, a
layer above)."""
TRUCK_KEYS: tuple[str, ...] = (*(record["name"] for record in _VECTO_SPECS), "air_density_kgpm3")
"""The keys a VECTO truck is built from: the core's ``vecto`` section and the air density."""
_DEFAULTS: dict[str, Any] = {
    **{record["name"]: record["default"] for record in _VECTO_SPECS},
    "air_density_kgpm3": decl.AIR_DENSITY_KG_M3,
}
"""A VECTO truck's keys unset: the declared defaults, and VECTO's air density."""


def truck_values(values: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """The truck's keys (:data:`TRUCK_KEYS`) with ``values`` set, each read by the core (type and
    range as declared); raises ``_core.ParamError`` naming a bad value's key."""
    given = dict(values or {})
    unknown = [key for key in given if key not in TRUCK_KEYS]
    if unknown:
        raise VehicleError(f"{unknown[0]}: expected a key of the VECTO truck ({', '.join(TRUCK_KEYS)}), got another")
    return {key: _core.parameter_value(key, given.get(key, _DEFAULTS[key])) for key in TRUCK_KEYS}


@dataclass(frozen=True)
class VectoTruck:
    """A VECTO truck ready to simulate: the job, the resolved values, and the core's model."""

    job: VectoJob
    segment: decl.Segment
    mass_kg: float
    payload_kg: float
    trailer_mass_kg: float
    wheel_radius_m: float
    rolling_resistance: float
    cda_curve: tuple[tuple[float, float], ...]
    aux_power_w: float
    keys: Mapping[str, Any]
    """The truck's keys (:data:`TRUCK_KEYS`) as the core read them."""
    core: _core.MapTruck


def load_vecto_truck(path: Path, values: Mapping[str, Any] | None = None) -> AnyVectoTruck:
    """Read a ``.vecto`` job or a declaration XML and build its truck with declaration mode's
    additions (``values`` set among :data:`TRUCK_KEYS`, checked by :func:`truck_values`): a diesel
    truck, or a battery-electric one from its declaration."""
    keys = truck_values(values)
    job = read_declaration_xml(path) if path.suffix.lower() == ".xml" else read_job(path)
    if isinstance(job, ElectricTruckJob):
        return load_electric_truck(job, keys)
    c = declared_combination(job.vehicle, keys, job.path, job.declaration_mode)
    aux = keys["aux_power_w"]
    aux = decl.auxiliary_power_w(job.auxiliaries, str(job.path)) if aux is None else aux
    body = Body(
        c.mass_kg, c.wheels_inertia_kgm2, c.cda_m2, keys["air_density_kgpm3"], c.rolling_resistance, aux, c.cda_curve
    )
    loss_maps = _loss_maps(job, keys)
    _refuse_replaced_loss_keys(path, loss_maps, keys)
    interruption_s = keys["traction_interruption_s"]
    interruption_s = job.gearbox.traction_interruption_s if interruption_s is None else interruption_s
    core = _core_truck(job, keys, c.wheel_radius_m, loss_maps, body, interruption_s)
    return VectoTruck(
        job,
        c.segment,
        c.mass_kg,
        c.payload_kg,
        c.trailer_mass_kg,
        c.wheel_radius_m,
        c.rolling_resistance,
        c.cda_curve,
        aux,
        keys,
        core,
    )


AnyVectoTruck = VectoTruck | ElectricVectoTruck
"""A truck from VECTO's files: diesel, or battery-electric."""


def _loss_maps(job: VectoJob, keys: Mapping[str, Any]) -> dict[str, Any]:
    """VECTO's loss maps where the job gives one for every gear (gears) and for the axle, unless
    ``use_loss_maps`` is off; the affine losses (``gear_efficiency`` and so on) stand in for the others."""
    gearbox = job.gearbox
    if not keys["use_loss_maps"]:
        return {}
    gears = gearbox.gear_loss_maps
    out: dict[str, Any] = {}
    if gears and all(m is not None for m in gears):
        out["gear_loss_maps"] = tuple(m for m in gears if m is not None)
    if gearbox.axle_loss_map is not None:
        out["axle_loss_map"] = gearbox.axle_loss_map
    retarder = job.retarder
    if retarder is not None and retarder.loss_map is not None:
        out |= {"retarder_loss_map": retarder.loss_map, "retarder_ratio": retarder.ratio}
        out["retarder_position"] = retarder.position
    return out


def _refuse_replaced_loss_keys(path: Path, loss_maps: dict[str, Any], values: Mapping[str, Any]) -> None:
    """The affine losses' keys do nothing where loss maps replace them: set to other than their
    defaults, refused, not ignored."""
    replaced = {"gear_loss_maps": ("gear_efficiency", "loss_torque_nm"), "axle_loss_map": ("axle_efficiency",)}
    for maps, keys in replaced.items():
        given = [k for k in keys if values[k] != _DEFAULTS[k]]
        if maps in loss_maps and given:
            raise VehicleError(
                f"{path}: {given[0]}: expected no value where the job's loss maps give the losses "
                f"(set use_loss_maps=false to use it), got {values[given[0]]!r}"
            )


def driveline_losses(truck: VectoTruck) -> str:
    """How the truck's driveline losses are modelled, in a sentence."""
    facts = truck.core.facts
    gears, axle = facts["gear_loss_maps"], facts["axle_loss_map"]
    retarder = truck.job.retarder
    missing = truck.job.gearbox.missing_loss_maps
    if retarder is not None and retarder.loss_map is None and retarder.file:
        missing += (retarder.file,)
    named = f"; loss maps named but not found: {', '.join(missing)}" if missing else ""
    if retarder is not None and retarder.loss_map is not None and truck.keys["use_loss_maps"]:
        named = f", and the drag of a retarder on the gearbox's {retarder.position}" + named
    if gears and axle:
        return "VECTO's loss maps of every gear and of the axle" + named
    parts = ["the gears' loss maps" if gears else "", "the axle's loss map" if axle else ""]
    used = " and ".join(p for p in parts if p)
    return (f"{used}; otherwise: " if used else "") + DRIVELINE_LOSS_NOTE + named


def _core_truck(
    job: VectoJob,
    keys: Mapping[str, Any],
    radius_m: float,
    loss_maps: dict[str, Any],
    body: Body,
    interruption_s: float,
) -> _core.MapTruck:
    """The core's truck; its checks' errors name the file the offending data came from."""
    engine, gearbox = job.engine, job.gearbox
    fld, fmap = engine.files if len(engine.files) == 2 else (engine.path, engine.path)
    files = {"fuel_map": fmap, "full_load_curve": fld, "idle_speed_rpm": engine.path, "axle_loss_map": gearbox.path}
    files |= {"engine_inertia_kgm2": engine.path, "gear_ratios": gearbox.path, "axle_ratio": gearbox.path}
    try:
        driveline = Driveline(
            tuple(gearbox.gear_ratios),
            gearbox.axle_ratio,
            keys["gear_efficiency"],
            keys["axle_efficiency"],
            keys["loss_torque_nm"],
            radius_m,
            **loss_maps,
        )
        return _core.MapTruck(engine, driveline, body, interruption_s)
    except _core.ParamError as e:
        raise VehicleError(f"{_blamed_file(job, e.key, files)}: {e}") from None


def _blamed_file(job: VectoJob, key: str, files: dict[str, Path]) -> Path:
    """The file the data behind a core error's ``key`` came from: a loss map's own file where it has
    one (``gear_loss_maps[i]`` is gear i's, ``axle_loss_map`` the axle's), else ``files``' entry."""
    map_files = job.gearbox.loss_map_files
    index = 0 if key == "axle_loss_map" else None
    if key.startswith("gear_loss_maps[") and key.endswith("]"):
        index = int(key[len("gear_loss_maps[") : -1])
    found = map_files[index] if index is not None and index < len(map_files) else None
    if found is not None:
        return found
    return job.gearbox.path if index is not None else files.get(key, job.path)


# The PI's shift speeds for a VECTO truck, as shares of the engine's rated speed, chosen to keep
# VECTO's tractor in top gear at cruise (the figures: docs/explanation/controllers.md, the PI).
DOWNSHIFT_SHARE = 0.63
UPSHIFT_SHARE = 0.86
_LANDING_MARGIN = 0.95  # a downshift speed at most this share of where the upshift below lands


def pi_shift_speeds_rpm(truck: VectoTruck) -> tuple[list[float | None], list[float | None]]:
    """Default PI shift speeds [rpm] per gear for a VECTO truck (``gear_down_rpm``, ``gear_up_rpm``):
    :data:`UPSHIFT_SHARE` of the rated speed up, :data:`DOWNSHIFT_SHARE` down, lowered where a
    gearbox's wide steps would land an up-shift below it (the gearbox would hunt); none below gear 1
    or above the top gear."""
    rated = truck.core.facts["rated_speed_rpm"]
    ratios = truck.job.gearbox.gear_ratios
    up_rpm = round(UPSHIFT_SHARE * rated)
    down: list[float | None] = [None]
    for lower, higher in itertools.pairwise(ratios):
        landing = up_rpm * higher / lower
        down.append(float(round(min(DOWNSHIFT_SHARE * rated, _LANDING_MARGIN * landing))))
    up: list[float | None] = [float(up_rpm)] * (len(ratios) - 1) + [None]
    return down, up

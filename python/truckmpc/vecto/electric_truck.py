"""A battery-electric VECTO declaration made into a truck the core simulates: the machines,
reduction and battery as read, plus what declaration mode adds (trailer, load, the combination's
air drag and rolling resistance, the electric auxiliaries, the state of charge a run starts from).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from truckmpc import _core
from truckmpc.errors import VehicleError
from truckmpc.vecto import declaration as decl
from truckmpc.vecto.combination import declared_combination
from truckmpc.vecto.components import LossPoints
from truckmpc.vecto.electric import BatteryData, ElectricMachineData, ElectricTruckJob, VoltageLevel
from truckmpc.vecto.parts import Body

__all__ = ["CONDITIONING_W", "ElectricVectoTruck", "electric_auxiliary_power_w", "load_electric_truck"]

_AUX_LONG_HAUL_EL_W = {  # VECTO's VAUX tables as electric power drawn from the battery, Long Haul
    # 600 W × 1.2 (mission) × 0.857 (electric pump) as mechanical power, × 0.7 as VECTO converts it.
    "SteeringPump": {"Electric driven pump": 720.0 * 0.857 * 0.7},  # one steered axle
    "ElectricSystem": {"Standard technology": 1200.0},  # no alternator between it and the battery
    "PneumaticSystem": {"Medium Supply 2-stage + elec. driven": 875.0},  # the table's electric column
    "HVAC": {"Default": 350.0 / 0.8},  # over VECTO's electric HVAC efficiency factor
}
CONDITIONING_W = 600.0
"""The machines' and battery's conditioning [W], drawn while the machines carry current (VECTO's
Cond table for a truck on Long Haul)."""


def electric_auxiliary_power_w(auxiliaries: tuple[tuple[str, str], ...], where: str) -> float:
    """The summed electric power [W] of a battery-electric truck's auxiliaries on Long Haul, each
    (auxiliary, technology), drawn at every moment (conditioning aside)."""
    total = 0.0
    for name, technology in auxiliaries:
        table = _AUX_LONG_HAUL_EL_W.get(name, {})
        if technology not in table:
            raise VehicleError(
                f"{where}: Auxiliaries/{name}: expected a technology truckmpc carries "
                f"({', '.join(table) or 'none for this auxiliary'}), got {technology!r}; set aux_power_w instead"
            )
        total += table[technology]
    return total


@dataclass(frozen=True)
class _Machine:
    count: int
    inertia_kgm2: float
    levels: tuple[VoltageLevel, ...]
    drag_curve: tuple[tuple[float, float], ...]


@dataclass(frozen=True)
class _Reduction:
    ratio: float
    loss_map: LossPoints | None
    wheel_radius_m: float


@dataclass(frozen=True)
class _Battery:
    capacity_ah: float
    ocv: tuple[tuple[float, float], ...]
    resistance_mohm: tuple[tuple[float, float], ...]
    current_limits: tuple[tuple[float, float, float], ...]
    soc_window_pct: tuple[float, float]


@dataclass(frozen=True)
class ElectricVectoTruck:
    """A battery-electric VECTO truck ready to simulate: the declaration, the resolved values, and
    the core's model."""

    job: ElectricTruckJob
    segment: decl.Segment
    mass_kg: float
    payload_kg: float
    trailer_mass_kg: float
    wheel_radius_m: float
    rolling_resistance: float
    cda_curve: tuple[tuple[float, float], ...]
    aux_power_w: float
    """The auxiliaries' electric power [W], conditioning aside."""
    keys: Mapping[str, Any]
    core: _core.MapTruck


def load_electric_truck(job: ElectricTruckJob, keys: Mapping[str, Any]) -> ElectricVectoTruck:
    """The truck of a battery-electric declaration with the VECTO truck's ``keys`` as the core read
    them (``truck_values``)."""
    where = str(job.path)
    if len(job.batteries) != 1:
        raise VehicleError(f"{where}: REESS: expected one battery string, got {len(job.batteries)}")
    c = declared_combination(job.vehicle, keys, job.path)
    aux = keys["aux_power_w"]
    aux = electric_auxiliary_power_w(job.auxiliaries, where) if aux is None else aux
    body = Body(
        c.mass_kg, c.wheels_inertia_kgm2, c.cda_m2, keys["air_density_kgpm3"], c.rolling_resistance, aux, c.cda_curve
    )
    reduction = _Reduction(job.reduction.ratio, job.reduction.loss_map or None, c.wheel_radius_m)
    soc = keys["soc_start_pct"]
    core = _core.MapTruck.electric(
        _machine(job.machine), reduction, _battery(job.batteries[0]), body, CONDITIONING_W, soc
    )
    return ElectricVectoTruck(
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


def _machine(m: ElectricMachineData) -> _Machine:
    return _Machine(m.count, m.inertia_kgm2, m.voltage_levels, m.drag_curve)


def _battery(b: BatteryData) -> _Battery:
    """The battery as the core reads it; a cruise draws current one way for longer than 20 s, so
    the 20 s pulse's resistance applies."""
    resistance = tuple((soc, r_20) for soc, _, _, r_20 in b.resistance)
    return _Battery(b.rated_capacity_ah, b.ocv, resistance, b.current_limits, (b.soc_min_pct, b.soc_max_pct))

"""VECTO's declaration XML of a battery-electric truck (``Vehicle_PEV_…`` vehicles, schema v2.x
definitions): its electric machines, the reduction at the axle, its batteries, the vehicle and its
auxiliaries, read into an :class:`~truckmpc.vecto.electric.ElectricTruckJob`.

Only machines at position E4 (at the axle, through the ADC reduction) are read today; a file with a
gearbox (E2) or an axle gear (E3) is refused naming the element. Every problem is a one-line
:class:`~truckmpc.errors.VehicleError` naming the file, the line, the element and what was expected.
"""

from __future__ import annotations

from collections.abc import Sequence
from itertools import pairwise
from pathlib import Path

from truckmpc.errors import VehicleError
from truckmpc.vecto.checks import check_once
from truckmpc.vecto.electric import BatteryData, ElectricMachineData, ElectricTruckJob, ReductionData, VoltageLevel
from truckmpc.vecto.xml_job import loss_map_of, vehicle_of
from truckmpc.vecto.xml_tree import Element, boolean, child, entries, located, number, opt, table, text

__all__ = ["is_electric", "read_electric_xml"]

_MACHINE_TYPES = ("ASM", "PSM", "ESM", "RM")
_AUXILIARIES = ("SteeringPump", "ElectricSystem", "PneumaticSystem", "HVAC")
_V2_VEHICLE = ("ChassisConfiguration", "CorrectedActualMass", "TechnicalPermissibleMaximumLadenMass")
"""The elements of the vehicle's category, mass [kg] and permissible maximum laden mass in schema v2.x."""


def is_electric(vehicle: Element) -> bool:
    """Whether a declaration's ``Vehicle`` element is a battery-electric one (VECTO's ``PEV`` types)."""
    return "PEV" in vehicle.attrs.get("type", "")


def read_electric_xml(path: Path, vehicle: Element) -> ElectricTruckJob:
    """The battery-electric truck of ``vehicle``, the ``Vehicle`` element of the file ``path``."""
    architecture_el = child(vehicle, "ArchitectureID")
    architecture = text(architecture_el)
    components = child(vehicle, "Components")
    for other in ("Gearbox", "Axlegear"):
        found = opt(components, other)
        if found is not None:
            raise VehicleError(
                f"{found.where}: expected no <{other}> (truckmpc reads battery-electric trucks with their "
                f"machines at the axle, E4, only), got one"
            )
    machine_el = child(components, "ElectricMachine")
    machine = _machine(machine_el)
    if machine.position != architecture:
        raise VehicleError(
            f"{architecture_el.where}: expected {machine.position}, the machines' position, got {architecture!r}"
        )
    aux = child(components, "Auxiliaries", "Data")
    return ElectricTruckJob(
        path=path,
        architecture=architecture,
        vehicle=vehicle_of(vehicle, components, _V2_VEHICLE),
        machine=machine,
        reduction=_reduction(child(machine_el, "ADC", "Data")),
        batteries=tuple(_battery(b) for b in _children(child(components, "ElectricEnergyStorage"), "Battery")),
        auxiliaries=tuple((name, text(child(aux, name, "Technology"))) for name in _AUXILIARIES if opt(aux, name)),
    )


def _children(el: Element, name: str) -> list[Element]:
    found = [c for c in el.children if c.name == name]
    if not found:
        raise VehicleError(f"{el.where}: expected at least one <{name}> element, got none")
    return found


def _machine(el: Element) -> ElectricMachineData:
    """The machines of one ``ElectricMachine`` element."""
    position_el = child(el, "PowertrainPosition")
    if text(position_el) != "4":
        raise VehicleError(f"{position_el.where}: expected 4 (E4: machines at the axle), got {text(position_el)!r}")
    count_el = child(el, "Count")
    count = number(count_el, positive=True)
    if count != int(count):
        raise VehicleError(f"{count_el.where}: expected a whole number, got {text(count_el)!r}")
    data = child(el, "ElectricMachineSystem", "Data")
    kind_el = child(data, "ElectricMachineType")
    if text(kind_el) not in _MACHINE_TYPES:
        raise VehicleError(f"{kind_el.where}: expected one of {', '.join(_MACHINE_TYPES)}, got {text(kind_el)!r}")
    levels = sorted((_voltage_level(v) for v in _children(data, "VoltageLevel")), key=lambda v: v.voltage_v)
    for low, high in pairwise(levels):
        if low.voltage_v == high.voltage_v:
            raise VehicleError(f"{data.where}/VoltageLevel: expected each voltage once, got {high.voltage_v:g} V twice")
    drag = entries(child(data, "DragCurve"), (("outShaftSpeed", 0.0), ("dragTorque", None)), 2)
    _rising(drag, "speeds")
    for e, (_, torque) in drag:
        if torque > 0:
            raise VehicleError(f"{e.where}: expected a drag torque <= 0, got {torque:g}")
    return ElectricMachineData(
        position="E4",
        count=int(count),
        machine_type=text(kind_el),
        rated_power_w=number(child(data, "R85RatedPower"), positive=True),
        inertia_kgm2=number(child(data, "RotationalInertia"), minimum=0.0),
        dc_dc_converter_included=boolean(child(data, "DcDcConverterIncluded")),
        voltage_levels=tuple(levels),
        drag_curve=tuple((n, t) for _, (n, t) in drag),
    )


def _voltage_level(el: Element) -> VoltageLevel:
    """One ``VoltageLevel``: its torque limits and power map."""
    limits = table(child(el, "MaxTorqueCurve"), (("outShaftSpeed", 0.0), ("maxTorque", 0.0), ("minTorque", None)), 2)
    _rising(limits, "speeds")
    for e, (_, _, braking) in limits:
        if braking > 0:
            raise VehicleError(f"{e.where}: expected a minTorque <= 0 (the most braking torque), got {braking:g}")
    power = table(child(el, "PowerMap"), (("outShaftSpeed", 0.0), ("torque", None), ("electricPower", None)), 4)
    check_once(located(power), "(speed, torque)")
    continuous_nm = number(child(el, "ContinuousTorque"), positive=True)
    overload = child(el, "OverloadTorque")
    overload_nm = number(overload, positive=True)
    if overload_nm < continuous_nm:
        raise VehicleError(
            f"{overload.where}: expected an OverloadTorque >= the ContinuousTorque ({continuous_nm:g} Nm; the "
            f"machine's thermal buffer is the overload's loss above the continuous one), got {overload_nm:g}"
        )
    return VoltageLevel(
        voltage_v=number(child(el, "Voltage"), positive=True),
        continuous_torque_nm=continuous_nm,
        continuous_speed_rpm=number(child(el, "TestSpeedContinuousTorque"), positive=True),
        overload_torque_nm=overload_nm,
        overload_speed_rpm=number(child(el, "TestSpeedOverloadTorque"), positive=True),
        overload_duration_s=number(child(el, "OverloadDuration"), minimum=0.0),
        torque_limits=tuple(v for _, v in limits),
        power_map=tuple(v for _, v in power),
    )


def _rising(rows: Sequence[tuple[Element, tuple[float, ...]]], what: str) -> None:
    """Rows whose first number rises strictly, ``what`` naming it."""
    for (_, (x_prev, *_)), (e, (x, *_)) in pairwise(rows):
        if x <= x_prev:
            raise VehicleError(f"{e.where}: expected {what} that increase, got {x:g} after {x_prev:g}")


def _reduction(data: Element) -> ReductionData:
    """The ADC (inside the ``ElectricMachine`` element): its ratio and its torque loss map."""
    return ReductionData(
        ratio=number(child(data, "Ratio"), positive=True), loss_map=loss_map_of(child(data, "TorqueLossMap"))
    )


def _battery(el: Element) -> BatteryData:
    """One ``Battery`` string: its REESS data and usable window."""
    data = child(el, "REESS", "Data")
    soc = (("SoC", 0.0),)
    ocv = entries(child(data, "OCV"), (*soc, ("OCV", 0.0)), 2)
    resistance = entries(child(data, "InternalResistance"), (*soc, ("R_2", 0.0), ("R_10", 0.0), ("R_20", 0.0)), 1)
    limits = entries(
        child(data, "CurrentLimits"), (*soc, ("maxChargingCurrent", 0.0), ("maxDischargingCurrent", 0.0)), 1
    )
    for rows in (ocv, resistance, limits):
        _rising(rows, "states of charge")
        for e, (pct, *_) in rows:
            if pct > 100:
                raise VehicleError(f"{e.where}/@SoC: expected a state of charge in [0, 100] %, got {pct:g}")
    soc_min_el, soc_max_el = child(el, "SOCmin"), child(el, "SOCmax")
    soc_min, soc_max = number(soc_min_el, minimum=0.0), number(soc_max_el, minimum=0.0)
    if not soc_min < soc_max <= 100:
        raise VehicleError(
            f"{soc_max_el.where}: expected a value above SOCmin ({soc_min:g}) and at most 100, got {soc_max:g}"
        )
    string_el = child(el, "StringID")
    string_id = number(string_el, minimum=0.0)
    if string_id != int(string_id):
        raise VehicleError(f"{string_el.where}: expected a whole number, got {text(string_el)!r}")
    return BatteryData(
        string_id=int(string_id),
        battery_type=text(child(data, "BatteryType")),
        rated_capacity_ah=number(child(data, "RatedCapacity"), positive=True),
        ocv=tuple((pct, volts) for _, (pct, volts) in ocv),
        resistance=tuple((pct, r2, r10, r20) for _, (pct, r2, r10, r20) in resistance),
        current_limits=tuple((pct, charge, discharge) for _, (pct, charge, discharge) in limits),
        soc_min_pct=soc_min,
        soc_max_pct=soc_max,
    )

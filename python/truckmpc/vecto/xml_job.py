"""VECTO's declaration-mode XML vehicle file (``VectoInputDeclaration``, schema v1.0): the vehicle
and every component in one file, read into the same :class:`~truckmpc.vecto.components.VectoJob` as a
``.vecto`` job, with what declaration mode adds to it: the engine's inertia and the traction
interruption of a gear shift (by gearbox type), and the wheels' inertia (by tyre size).

Elements are matched by their local names (``xml_tree``), so later schema versions read where their
names agree. ``Signature`` elements are ignored. Of a steering pump's technologies (one per
steered axle) the first is taken. The retarder is read by :mod:`truckmpc.vecto.retarder`. Every
problem is a one-line :class:`~truckmpc.errors.VehicleError` naming the file, the line, the element
and what was expected.
"""

from __future__ import annotations

from pathlib import Path

from truckmpc.errors import VehicleError
from truckmpc.vecto import declaration as decl
from truckmpc.vecto.checks import check_full_load, check_once
from truckmpc.vecto.components import Axle, EngineData, GearboxData, LossPoints, VectoJob, VehicleData
from truckmpc.vecto.retarder import retarder_of_xml
from truckmpc.vecto.xml_tree import (
    Element,
    boolean,
    child,
    located,
    number,
    numbered,
    opt,
    parse,
    table,
    text,
)

__all__ = ["axles_of", "declared_vehicle", "job_of", "loss_map_of", "read_xml_job", "vehicle_of"]

# VECTO's declaration rules for a gearbox with a clutch. Engine inertia [kg m²]: clutch 1.3
# (a torque converter's would be 1.2) + engine base 0.41 + 0.27 kg m² per litre of displacement.
# Traction interruption of a shift [s]: 1 for an AMT, 2 for a manual (SMT) gearbox.
_CLUTCH_INERTIA_KGM2 = 1.3
_ENGINE_BASE_INERTIA_KGM2 = 0.41
_DISPLACEMENT_INERTIA_KGM2_PER_L = 0.27
_TRACTION_INTERRUPTION_S = {"AMT": 1.0, "SMT": 2.0}
# Auxiliaries: the XML element and the id a ``.vecto`` job gives it, in the job's order.
_AUXILIARIES = {"Fan": "FAN", "SteeringPump": "STP", "HVAC": "AC", "ElectricSystem": "ES", "PneumaticSystem": "PS"}


def read_xml_job(path: Path) -> VectoJob:
    """Read a VECTO declaration XML file into a declaration-mode job (every component's path is the
    file's, and no other files are read)."""
    return job_of(path, declared_vehicle(path))


def declared_vehicle(path: Path) -> Element:
    """The ``Vehicle`` element of a VECTO declaration XML file."""
    root = parse(path)
    if root.name != "VectoInputDeclaration":
        raise VehicleError(
            f"{path}:{root.line}: expected a VECTO declaration (root element VectoInputDeclaration), got <{root.name}>"
        )
    return child(root, "Vehicle")


def job_of(path: Path, vehicle: Element) -> VectoJob:
    """The diesel truck of a declaration's ``Vehicle`` element."""
    components = child(vehicle, "Components")
    gearbox = _gearbox(child(components, "Gearbox", "Data"), child(components, "Axlegear", "Data"))
    idle = opt(vehicle, "IdlingSpeed")
    engine = _engine(child(components, "Engine", "Data"), number(idle, positive=True) if idle else 0.0)
    aux = child(components, "Auxiliaries", "Data")
    return VectoJob(
        path=path,
        declaration_mode=True,
        vehicle=vehicle_of(vehicle, components),
        engine=engine,
        gearbox=gearbox,
        auxiliaries=tuple((aux_id, text(child(aux, name, "Technology"))) for name, aux_id in _AUXILIARIES.items()),
        retarder=retarder_of_xml(vehicle, components),
    )


def _engine(data: Element, vehicle_idle_rpm: float) -> EngineData:
    """The engine; VECTO idles it at the higher of its own and the vehicle's idling speed [rpm], and
    gives it the inertia [kg m²] of an engine with a clutch of its displacement [cm³]."""
    displacement = number(child(data, "Displacement"), positive=True)
    inertia = _CLUTCH_INERTIA_KGM2 + _ENGINE_BASE_INERTIA_KGM2 + _DISPLACEMENT_INERTIA_KGM2_PER_L * displacement / 1000
    return EngineData(
        path=data.file,
        model=text(child(data, "Model")),
        idle_speed_rpm=max(number(child(data, "IdlingSpeed"), positive=True), vehicle_idle_rpm),
        inertia_kgm2=inertia,
        displacement_cm3=displacement,
        full_load=_full_load(child(data, "FullLoadAndDragCurve")),
        fuel_map=_fuel_map(child(data, "FuelConsumptionMap")),
        files=(),
    )


def _full_load(el: Element) -> tuple[tuple[float, float, float], ...]:
    """(engine speed [rpm], full-load torque [Nm], drag torque [Nm]) rows."""
    rows = table(el, (("engineSpeed", None), ("maxTorque", None), ("dragTorque", None)), 2)
    check_full_load(located(rows))
    return tuple(v for _, v in rows)


def _fuel_map(el: Element) -> tuple[tuple[float, float, float], ...]:
    """(engine speed [rpm], torque [Nm], fuel rate [g/h]) points."""
    rows = table(el, (("engineSpeed", None), ("torque", None), ("fuelConsumption", 0.0)), 4)
    check_once(located(rows), "(engine speed, torque)")
    return tuple(v for _, v in rows)


def loss_map_of(el: Element) -> LossPoints:
    """(input speed [rpm], input torque [Nm], torque loss [Nm]) points."""
    rows = table(el, (("inputSpeed", 0.0), ("inputTorque", None), ("torqueLoss", 0.0)), 4)
    check_once(located(rows), "(input speed, input torque)")
    return tuple(v for _, v in rows)


def _gearbox(data: Element, axlegear: Element) -> GearboxData:
    """The gearbox with its gears' ratios and loss maps, the axle's, and VECTO's traction
    interruption [s] for its type."""
    kind_el = child(data, "TransmissionType")
    kind = text(kind_el)
    if kind not in _TRACTION_INTERRUPTION_S:
        raise VehicleError(
            f"{kind_el.where}: expected AMT or SMT (truckmpc models gearboxes with a clutch, "
            f"no torque converter), got {kind!r}"
        )
    gears = numbered(child(data, "Gears"), "Gear")
    ratios: list[float] = []
    for k, gear in enumerate(gears, start=1):
        ratio_el = child(gear, "Ratio")
        ratio = number(ratio_el, positive=True)
        if ratios and ratio >= ratios[-1]:
            raise VehicleError(f"{ratio_el.where}: expected a ratio below gear {k - 1}'s {ratios[-1]:g}, got {ratio:g}")
        ratios.append(ratio)
    return GearboxData(
        path=data.file,
        model=text(child(data, "Model")),
        gearbox_type=kind,
        axle_ratio=number(child(axlegear, "Ratio"), positive=True),
        gear_ratios=tuple(ratios),
        traction_interruption_s=_TRACTION_INTERRUPTION_S[kind],
        gear_loss_maps=tuple(loss_map_of(child(g, "TorqueLossMap")) for g in gears),
        axle_loss_map=loss_map_of(child(axlegear, "TorqueLossMap")),
    )


_V1_VEHICLE = ("VehicleCategory", "CurbMassChassis", "GrossVehicleMass")
"""The elements of schema v1.0's vehicle category, curb mass and gross mass."""


def vehicle_of(vehicle: Element, components: Element, names: tuple[str, str, str] = _V1_VEHICLE) -> VehicleData:
    """The vehicle: its category, mass [kg] and gross mass [t] from the elements ``names`` (schema
    v1.0's by default), declared air drag Cd·A [m²], axles in axle-number order."""
    category, mass, gross = names
    return VehicleData(
        path=vehicle.file,
        category=text(child(vehicle, category)),
        axle_config=text(child(vehicle, "AxleConfiguration")),
        curb_mass_kg=number(child(vehicle, mass), positive=True),
        cda_m2=number(child(components, "AirDrag", "Data", "DeclaredCdxA"), positive=True),
        gross_mass_t=number(child(vehicle, gross), positive=True) / 1000.0,
        axles=axles_of(components),
    )


def axles_of(components: Element) -> tuple[Axle, ...]:
    """The vehicle's axles, in axle-number order."""
    return tuple(_axle(a) for a in numbered(child(components, "AxleWheels", "Data", "Axles"), "Axle"))


def _axle(axle: Element) -> Axle:
    """An axle; one wheel's inertia [kg m²] from VECTO's Wheels table for its tyre size."""
    kind_el = child(axle, "AxleType")
    kind = text(kind_el)
    if kind not in ("VehicleDriven", "VehicleNonDriven"):
        raise VehicleError(f"{kind_el.where}: expected VehicleDriven or VehicleNonDriven, got {kind!r}")
    tyre = child(axle, "Tyre", "Data")
    dimension_el = child(tyre, "Dimension")
    dimension = text(dimension_el)
    return Axle(
        tyre=dimension,
        rolling_resistance=number(child(tyre, "RRCDeclared"), minimum=0.0),
        tyre_test_load_n=number(child(tyre, "FzISO"), positive=True),
        twin_tyres=boolean(child(axle, "TwinTyres")),
        wheel_inertia_kgm2=decl.wheel_inertia_kgm2(dimension, dimension_el.where),
        driven=kind == "VehicleDriven",
    )

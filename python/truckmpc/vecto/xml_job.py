"""VECTO's declaration-mode XML vehicle file (``VectoInputDeclaration``, schema v1.0): the vehicle
and every component in one file, read into the same :class:`~truckmpc.vecto.components.VectoJob` as a
``.vecto`` job, with what declaration mode adds to it: the engine's inertia and the traction
interruption of a gear shift (by gearbox type), and the wheels' inertia (by tyre size).

Elements are matched by their local names, whatever their namespace, so later schema versions read
where their names agree. ``Signature`` elements are ignored; so is the retarder (its losses are not
modelled). Of a steering pump's technologies (one per steered axle) the first is taken. Every
problem is a one-line :class:`~truckmpc.errors.VehicleError` naming the file, the line, the element
and what was expected.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from xml.parsers import expat

from truckmpc.errors import VehicleError, read_user_text
from truckmpc.vecto import declaration as decl
from truckmpc.vecto.checks import Located, check_full_load, check_once
from truckmpc.vecto.components import Axle, EngineData, GearboxData, LossPoints, VectoJob, VehicleData

__all__ = ["read_xml_job"]

# VECTO's declaration rules for a gearbox with a clutch. Engine inertia [kg m²]: clutch 1.3
# (a torque converter's would be 1.2) + engine base 0.41 + 0.27 kg m² per litre of displacement.
# Traction interruption of a shift [s]: 1 for an AMT, 2 for a manual (SMT) gearbox.
_CLUTCH_INERTIA_KGM2 = 1.3
_ENGINE_BASE_INERTIA_KGM2 = 0.41
_DISPLACEMENT_INERTIA_KGM2_PER_L = 0.27
_TRACTION_INTERRUPTION_S = {"AMT": 1.0, "SMT": 2.0}
# Auxiliaries: the XML element and the id a ``.vecto`` job gives it, in the job's order.
_AUXILIARIES = {"Fan": "FAN", "SteeringPump": "STP", "HVAC": "AC", "ElectricSystem": "ES", "PneumaticSystem": "PS"}
_KEYS = {"Gear": "number", "Axle": "axleNumber"}  # the attribute that tells repeated elements apart


@dataclass
class _Element:
    """An XML element: local name, start line, path from below the root, attributes (local names)."""

    file: Path
    name: str
    line: int
    path: str
    attrs: dict[str, str]
    children: list[_Element] = field(default_factory=list)
    texts: list[str] = field(default_factory=list)

    @property
    def text(self) -> str:
        return "".join(self.texts).strip()

    @property
    def where(self) -> str:
        return f"{self.file}:{self.line}: {self.path}"


_Row = tuple[_Element, tuple[float, float, float]]
"""An ``Entry`` element and its three numbers."""


def read_xml_job(path: Path) -> VectoJob:
    """Read a VECTO declaration XML file into a declaration-mode job (every component's path is the
    file's, and no other files are read)."""
    root = _parse(path)
    if root.name != "VectoInputDeclaration":
        raise VehicleError(
            f"{path}:{root.line}: expected a VECTO declaration (root element VectoInputDeclaration), got <{root.name}>"
        )
    vehicle = _child(root, "Vehicle")
    components = _child(vehicle, "Components")
    gearbox = _gearbox(_child(components, "Gearbox", "Data"), _child(components, "Axlegear", "Data"))
    idle = _opt(vehicle, "IdlingSpeed")
    engine = _engine(_child(components, "Engine", "Data"), _number(idle, positive=True) if idle else 0.0)
    aux = _child(components, "Auxiliaries", "Data")
    return VectoJob(
        path=path,
        declaration_mode=True,
        vehicle=_vehicle(vehicle, components),
        engine=engine,
        gearbox=gearbox,
        auxiliaries=tuple((aux_id, _text(_child(aux, name, "Technology"))) for name, aux_id in _AUXILIARIES.items()),
    )


def _parse(path: Path) -> _Element:
    """The file's element tree, each element with its start line."""
    try:
        raw = read_user_text(path, str(path), "a VECTO declaration XML file", VehicleError, encoding="utf-8-sig")
    except OSError as e:  # permission denied and the like
        raise VehicleError(f"{path}: cannot be read ({e.strerror or type(e).__name__})") from None
    parser = expat.ParserCreate(namespace_separator=" ")
    stack: list[_Element] = []
    top: list[_Element] = []

    def start(tag: str, attrs: dict[str, str]) -> None:
        name = _local(tag)
        key = _KEYS.get(name)
        label = f'{name}[@{key}="{attrs[key]}"]' if key in attrs else name
        el_path = f"{stack[-1].path}/{label}" if len(stack) > 1 else label
        el = _Element(path, name, parser.CurrentLineNumber, el_path, {_local(k): v for k, v in attrs.items()})
        (stack[-1].children if stack else top).append(el)
        stack.append(el)

    def doctype(*_: object) -> None:
        raise VehicleError(
            f"{path}:{parser.CurrentLineNumber}: expected a VECTO declaration without a DOCTYPE, got one"
        )

    parser.StartElementHandler = start
    parser.EndElementHandler = lambda _tag: stack.pop()
    parser.CharacterDataHandler = lambda data: stack[-1].texts.append(data) if stack else None
    parser.StartDoctypeDeclHandler = doctype
    try:
        parser.Parse(raw, True)
    except expat.ExpatError as e:
        got = f"{expat.ErrorString(e.code)} (column {e.offset + 1})"
        raise VehicleError(f"{path}:{e.lineno}: expected well-formed XML, got {got}") from None
    return top[0]


def _local(name: str) -> str:
    """A name without its namespace (expat gives ``namespace local``)."""
    return name.rsplit(" ", 1)[-1]


def _opt(el: _Element, name: str) -> _Element | None:
    return next((c for c in el.children if c.name == name), None)


def _child(el: _Element, *names: str) -> _Element:
    """The first child of that name, its first child of the next name, and so on."""
    for name in names:
        found = _opt(el, name)
        if found is None:
            raise VehicleError(f"{el.where}: expected a <{name}> element, got none")
        el = found
    return el


def _text(el: _Element) -> str:
    if not el.text:
        raise VehicleError(f"{el.where}: expected a text, got nothing")
    return el.text


def _number(el: _Element, *, positive: bool = False, minimum: float | None = None) -> float:
    """The element's text as a finite number."""
    return _checked(el.where, el.text, positive, minimum)


def _attr(el: _Element, name: str, minimum: float | None = None) -> float:
    """An attribute as a finite number."""
    where = f"{el.file}:{el.line}: {el.path}/@{name}"
    if name not in el.attrs:
        raise VehicleError(f"{where}: expected a number, got nothing (the attribute is missing)")
    return _checked(where, el.attrs[name], False, minimum)


def _checked(where: str, raw: str, positive: bool, minimum: float | None) -> float:
    try:
        x = float(raw)
    except ValueError:
        raise VehicleError(f"{where}: expected a number, got {raw!r}") from None
    if not math.isfinite(x) or (positive and x <= 0) or (minimum is not None and x < minimum):
        bound = "> 0" if positive else f">= {minimum:g}" if minimum is not None else "finite"
        raise VehicleError(f"{where}: expected a number {bound}, got {raw!r}")
    return x


def _bool(el: _Element) -> bool:
    value = el.text
    if value not in ("true", "false", "1", "0"):
        raise VehicleError(f"{el.where}: expected true or false, got {value!r}")
    return value in ("true", "1")


def _numbered(parent: _Element, name: str) -> list[_Element]:
    """The ``name`` children ordered by their number attribute, which must run 1..n."""
    key = _KEYS[name]
    items = [c for c in parent.children if c.name == name]
    if not items:
        raise VehicleError(f"{parent.where}: expected at least one <{name}> element, got none")
    numbered = []
    for c in items:
        try:
            numbered.append((int(c.attrs.get(key, "")), c))
        except ValueError:
            raise VehicleError(f"{c.where}/@{key}: expected a whole number, got {c.attrs.get(key)!r}") from None
    numbered.sort(key=lambda pair: pair[0])
    for i, (n, c) in enumerate(numbered, start=1):
        if n != i:
            raise VehicleError(f"{c.where}/@{key}: expected {name} numbers 1 to {len(items)}, each once, got {n}")
    return [c for _, c in numbered]


def _table(el: _Element, columns: tuple[tuple[str, float | None], ...], fewest: int) -> list[_Row]:
    """The ``Entry`` children of ``el`` as numbers, one per (attribute, lowest value) column."""
    (a, low_a), (b, low_b), (c, low_c) = columns
    rows = [(e, (_attr(e, a, low_a), _attr(e, b, low_b), _attr(e, c, low_c))) for e in el.children if e.name == "Entry"]
    if len(rows) < fewest:
        raise VehicleError(f"{el.where}: expected at least {fewest} <Entry> elements, got {len(rows)}")
    return rows


def _located(rows: list[_Row]) -> list[Located]:
    """The rows with where each element was read, for the checks the file formats share."""
    return [(e.where, e.line, values) for e, values in rows]


def _engine(data: _Element, vehicle_idle_rpm: float) -> EngineData:
    """The engine; VECTO idles it at the higher of its own and the vehicle's idling speed [rpm], and
    gives it the inertia [kg m²] of an engine with a clutch of its displacement [cm³]."""
    displacement = _number(_child(data, "Displacement"), positive=True)
    inertia = _CLUTCH_INERTIA_KGM2 + _ENGINE_BASE_INERTIA_KGM2 + _DISPLACEMENT_INERTIA_KGM2_PER_L * displacement / 1000
    return EngineData(
        path=data.file,
        model=_text(_child(data, "Model")),
        idle_speed_rpm=max(_number(_child(data, "IdlingSpeed"), positive=True), vehicle_idle_rpm),
        inertia_kgm2=inertia,
        displacement_cm3=displacement,
        full_load=_full_load(_child(data, "FullLoadAndDragCurve")),
        fuel_map=_fuel_map(_child(data, "FuelConsumptionMap")),
        files=(),
    )


def _full_load(el: _Element) -> tuple[tuple[float, float, float], ...]:
    """(engine speed [rpm], full-load torque [Nm], drag torque [Nm]) rows."""
    rows = _table(el, (("engineSpeed", None), ("maxTorque", None), ("dragTorque", None)), 2)
    check_full_load(_located(rows))
    return tuple(v for _, v in rows)


def _fuel_map(el: _Element) -> tuple[tuple[float, float, float], ...]:
    """(engine speed [rpm], torque [Nm], fuel rate [g/h]) points."""
    rows = _table(el, (("engineSpeed", None), ("torque", None), ("fuelConsumption", 0.0)), 4)
    check_once(_located(rows), "(engine speed, torque)")
    return tuple(v for _, v in rows)


def _loss_map(el: _Element) -> LossPoints:
    """(input speed [rpm], input torque [Nm], torque loss [Nm]) points."""
    rows = _table(el, (("inputSpeed", 0.0), ("inputTorque", None), ("torqueLoss", 0.0)), 4)
    check_once(_located(rows), "(input speed, input torque)")
    return tuple(v for _, v in rows)


def _gearbox(data: _Element, axlegear: _Element) -> GearboxData:
    """The gearbox with its gears' ratios and loss maps, the axle's, and VECTO's traction
    interruption [s] for its type."""
    kind_el = _child(data, "TransmissionType")
    kind = _text(kind_el)
    if kind not in _TRACTION_INTERRUPTION_S:
        raise VehicleError(
            f"{kind_el.where}: expected AMT or SMT (truckmpc models gearboxes with a clutch, "
            f"no torque converter), got {kind!r}"
        )
    gears = _numbered(_child(data, "Gears"), "Gear")
    ratios: list[float] = []
    for k, gear in enumerate(gears, start=1):
        ratio_el = _child(gear, "Ratio")
        ratio = _number(ratio_el, positive=True)
        if ratios and ratio >= ratios[-1]:
            raise VehicleError(f"{ratio_el.where}: expected a ratio below gear {k - 1}'s {ratios[-1]:g}, got {ratio:g}")
        ratios.append(ratio)
    return GearboxData(
        path=data.file,
        model=_text(_child(data, "Model")),
        gearbox_type=kind,
        axle_ratio=_number(_child(axlegear, "Ratio"), positive=True),
        gear_ratios=tuple(ratios),
        traction_interruption_s=_TRACTION_INTERRUPTION_S[kind],
        gear_loss_maps=tuple(_loss_map(_child(g, "TorqueLossMap")) for g in gears),
        axle_loss_map=_loss_map(_child(axlegear, "TorqueLossMap")),
    )


def _vehicle(vehicle: _Element, components: _Element) -> VehicleData:
    """The vehicle: masses [kg; gross in t], declared air drag Cd·A [m²], axles in axle-number order."""
    axles = _numbered(_child(components, "AxleWheels", "Data", "Axles"), "Axle")
    return VehicleData(
        path=vehicle.file,
        category=_text(_child(vehicle, "VehicleCategory")),
        axle_config=_text(_child(vehicle, "AxleConfiguration")),
        curb_mass_kg=_number(_child(vehicle, "CurbMassChassis"), positive=True),
        cda_m2=_number(_child(components, "AirDrag", "Data", "DeclaredCdxA"), positive=True),
        gross_mass_t=_number(_child(vehicle, "GrossVehicleMass"), positive=True) / 1000.0,
        axles=tuple(_axle(a) for a in axles),
    )


def _axle(axle: _Element) -> Axle:
    """An axle; one wheel's inertia [kg m²] from VECTO's Wheels table for its tyre size."""
    kind_el = _child(axle, "AxleType")
    kind = _text(kind_el)
    if kind not in ("VehicleDriven", "VehicleNonDriven"):
        raise VehicleError(f"{kind_el.where}: expected VehicleDriven or VehicleNonDriven, got {kind!r}")
    tyre = _child(axle, "Tyre", "Data")
    dimension_el = _child(tyre, "Dimension")
    dimension = _text(dimension_el)
    return Axle(
        tyre=dimension,
        rolling_resistance=_number(_child(tyre, "RRCDeclared"), minimum=0.0),
        tyre_test_load_n=_number(_child(tyre, "FzISO"), positive=True),
        twin_tyres=_bool(_child(axle, "TwinTyres")),
        wheel_inertia_kgm2=decl.wheel_inertia_kgm2(dimension, dimension_el.where),
        driven=kind == "VehicleDriven",
    )

"""A VECTO job and the component files it names, read and checked: the engine (with its full-load
curve and fuel map), the gearbox (with the axle ratio) and the vehicle (masses, air drag, axles).

Paths inside a file are relative to that file's folder, as VECTO resolves them.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

from truckmpc.errors import VehicleError
from truckmpc.vecto.checks import Located, check_full_load, check_once
from truckmpc.vecto.files import json_body, number, numbers_table, text
from truckmpc.vecto.retarder import RetarderData, retarder_of_vveh

__all__ = ["Axle", "EngineData", "GearboxData", "LossPoints", "VectoJob", "VehicleData", "read_job"]


@dataclass(frozen=True)
class EngineData:
    """An engine: its ``.veng`` file and the full-load curve and fuel map it names."""

    path: Path
    model: str
    idle_speed_rpm: float
    inertia_kgm2: float
    displacement_cm3: float
    full_load: tuple[tuple[float, float, float], ...]
    """(engine speed [rpm], full-load torque [Nm], drag torque [Nm]) rows."""
    fuel_map: tuple[tuple[float, float, float], ...]
    """(engine speed [rpm], torque [Nm], fuel rate [g/h]) points."""
    files: tuple[Path, ...]


LossPoints = tuple[tuple[float, float, float], ...]
"""A transmission loss map: (input speed [rpm], input torque [Nm], torque loss [Nm]) points."""


@dataclass(frozen=True)
class GearboxData:
    """A gearbox (``.vgbx``): its ratios, the axle ratio (VECTO's first entry), its type, and the
    loss maps of its gears and of the axle where the files give them."""

    path: Path
    model: str
    gearbox_type: str
    axle_ratio: float
    gear_ratios: tuple[float, ...]
    traction_interruption_s: float
    gear_loss_maps: tuple[LossPoints | None, ...] = ()
    """One per gear, first gear first; None where no loss map was given (or its file is missing)."""
    axle_loss_map: LossPoints | None = None
    missing_loss_maps: tuple[str, ...] = ()
    """Loss map files the gearbox names that are not beside it."""
    files: tuple[Path, ...] = ()
    """The loss map files read."""
    loss_map_files: tuple[Path | None, ...] = ()
    """The file of each loss map read: the axle's first, then each gear's (None: not from a file)."""


@dataclass(frozen=True)
class Axle:
    """One axle of the vehicle (``.vveh``)."""

    tyre: str
    rolling_resistance: float
    tyre_test_load_n: float
    twin_tyres: bool
    wheel_inertia_kgm2: float
    driven: bool


@dataclass(frozen=True)
class VehicleData:
    """The vehicle (``.vveh``): category, masses, air drag and axles."""

    path: Path
    category: str
    axle_config: str
    curb_mass_kg: float
    cda_m2: float
    gross_mass_t: float
    axles: tuple[Axle, ...]


@dataclass(frozen=True)
class VectoJob:
    """A VECTO job (``.vecto``) with its components."""

    path: Path
    declaration_mode: bool
    vehicle: VehicleData
    engine: EngineData
    gearbox: GearboxData
    auxiliaries: tuple[tuple[str, str], ...]
    """(id, technology) of each auxiliary."""
    retarder: RetarderData | None = None
    """The retarder whose drag counts, if any."""

    @property
    def files(self) -> tuple[Path, ...]:
        """Every file the job was read from, the job first."""
        paths = (
            self.path,
            self.vehicle.path,
            self.engine.path,
            *self.engine.files,
            self.gearbox.path,
            *self.gearbox.files,
        )
        return tuple(dict.fromkeys(paths))


def read_job(path: Path) -> VectoJob:
    """Read a ``.vecto`` job and every component file it names."""
    body = json_body(path)
    aux = []
    entries = body.get("Aux") or []
    if not isinstance(entries, list):
        raise VehicleError(f"{path}: Aux: expected a list of auxiliaries, got a {type(entries).__name__}")
    for i, entry in enumerate(entries):
        techs = entry.get("Technology") if isinstance(entry, dict) else None
        if not isinstance(entry, dict) or not isinstance(techs, list) or not techs:
            raise VehicleError(f"{path}: Aux[{i}]: expected an object with an ID and a Technology list, got {entry!r}")
        aux.append((str(entry.get("ID", "")), str(techs[0])))
    vehicle_file = _component(body, "VehicleFile", path)
    return VectoJob(
        path=path,
        declaration_mode=bool(body.get("SavedInDeclMode", False)),
        vehicle=read_vehicle(vehicle_file),
        engine=read_engine(_component(body, "EngineFile", path)),
        gearbox=read_gearbox(_component(body, "GearboxFile", path)),
        auxiliaries=tuple(aux),
        retarder=retarder_of_vveh(json_body(vehicle_file), vehicle_file),
    )


def _component(body: dict[str, Any], key: str, path: Path) -> Path:
    target = path.parent / text(body, key, path)
    if not target.is_file():
        raise VehicleError(f"{path}: {key}: expected a file beside the job, got {target.name!r} (not found)")
    return target


def read_engine(path: Path) -> EngineData:
    """Read a ``.veng`` engine and its ``.vfld`` and ``.vmap``."""
    body = json_body(path)
    fld = path.parent / text(body, "FullLoadCurve", path)
    fmap = path.parent / text(body, "FuelMap", path)
    for key, file in (("FullLoadCurve", fld), ("FuelMap", fmap)):
        if not file.is_file():
            raise VehicleError(f"{path}: {key}: expected a file beside the engine, got {file.name!r} (not found)")
    return EngineData(
        path=path,
        model=str(body.get("ModelName", "")),
        idle_speed_rpm=number(body, "IdlingSpeed", path, positive=True),
        inertia_kgm2=number(body, "Inertia", path, minimum=0.0),
        displacement_cm3=number(body, "Displacement", path, minimum=0.0),
        full_load=_full_load(fld),
        fuel_map=_fuel_map(fmap),
        files=(fld, fmap),
    )


def _located(path: Path, columns: int, what: str) -> list[Located]:
    """The rows of a numeric CSV table, each with ``path:line``."""
    return [(f"{path}:{line}", line, (r[0], r[1], r[2])) for line, r in numbers_table(path, columns, what)]


def _full_load(path: Path) -> tuple[tuple[float, float, float], ...]:
    rows = _located(path, 3, "a full-load curve (engine speed, full-load torque, drag torque)")
    check_full_load(rows)
    return tuple(values for _, _, values in rows)


def _fuel_map(path: Path) -> tuple[tuple[float, float, float], ...]:
    rows = _located(path, 3, "a fuel map (engine speed, torque, fuel rate)")
    for where, _, (_, _, fuel) in rows:
        if fuel < 0:
            raise VehicleError(f"{where}: expected a fuel rate >= 0 [g/h], got {fuel:g}")
    check_once(rows, "(engine speed, torque)")
    return tuple(values for _, _, values in rows)


def read_gearbox(path: Path) -> GearboxData:
    """Read a ``.vgbx`` gearbox: VECTO lists the axle first, then the gears from first to top."""
    body = json_body(path)
    gears = body.get("Gears")
    if not isinstance(gears, list) or len(gears) < 2:
        raise VehicleError(f"{path}: Gears: expected the axle and at least one gear, got {gears!r}")
    ratios = []
    for i, gear in enumerate(gears):
        if not isinstance(gear, dict):
            raise VehicleError(f"{path}: Gears[{i}]: expected an object with a Ratio, got {gear!r}")
        ratios.append(number(gear, "Ratio", f"{path}: Gears[{i}]", positive=True))
    for i, r in enumerate(ratios[2:], start=2):
        if r >= ratios[i - 1]:
            raise VehicleError(
                f"{path}: Gears[{i}].Ratio: expected a ratio below gear {i - 1}'s {ratios[i - 1]:g}, got {r:g}"
            )
    maps: list[LossPoints | None] = []
    map_files: list[Path | None] = []
    files: list[Path] = []
    missing: list[str] = []
    for gear in gears:
        name = str(gear.get("LossMap") or "").strip()
        file = path.parent / name
        if name and file.is_file():
            maps.append(loss_map(file))
            files.append(file)
            map_files.append(file)
        else:
            maps.append(None)
            map_files.append(None)
            if name:
                missing.append(name)
    return GearboxData(
        path=path,
        model=str(body.get("ModelName", "")),
        gearbox_type=str(body.get("GearboxType", "")),
        axle_ratio=ratios[0],
        gear_ratios=tuple(ratios[1:]),
        traction_interruption_s=number(body, "TracInt", path, minimum=0.0) if "TracInt" in body else 0.0,
        gear_loss_maps=tuple(maps[1:]),
        axle_loss_map=maps[0],
        missing_loss_maps=tuple(dict.fromkeys(missing)),
        files=tuple(dict.fromkeys(files)),
        loss_map_files=tuple(map_files),
    )


def loss_map(path: Path) -> LossPoints:
    """Read a ``.vtlm`` transmission loss map: (input speed [rpm], input torque [Nm], torque loss
    [Nm]) rows, each (speed, torque) once, losses >= 0."""
    rows = _located(path, 3, "a loss map (input speed, input torque, torque loss)")
    for where, _, (n, _, loss) in rows:
        if loss < 0:
            raise VehicleError(f"{where}: expected a torque loss >= 0 [Nm], got {loss:g}")
        if n < 0:
            raise VehicleError(f"{where}: expected an input speed >= 0 [rpm], got {n:g}")
    check_once(rows, "(input speed, input torque)")
    return tuple(values for _, _, values in rows)


def read_vehicle(path: Path) -> VehicleData:
    """Read a ``.vveh`` vehicle."""
    body = json_body(path)
    config = body.get("AxleConfig")
    axles_raw = config.get("Axles") if isinstance(config, dict) else None
    if not isinstance(axles_raw, list) or not axles_raw:
        raise VehicleError(f"{path}: AxleConfig.Axles: expected a list of axles, got {axles_raw!r}")
    axles = tuple(_axle(a, i, path) for i, a in enumerate(axles_raw))
    return VehicleData(
        path=path,
        category=str(body.get("VehCat", "")),
        axle_config=str(config.get("Type", "")) if isinstance(config, dict) else "",
        curb_mass_kg=number(body, "CurbWeight", path, positive=True),
        cda_m2=number(body, "CdA", path, positive=True),
        gross_mass_t=number(body, "MassMax", path, positive=True),
        axles=axles,
    )


def _axle(raw: Any, i: int, path: Path) -> Axle:
    if not isinstance(raw, dict):
        raise VehicleError(f"{path}: AxleConfig.Axles[{i}]: expected an object, got {raw!r}")
    where = f"{path}: AxleConfig.Axles[{i}]"
    return Axle(
        tyre=text(raw, "Wheels", where),
        rolling_resistance=number(raw, "RRCISO", where, minimum=0.0),
        tyre_test_load_n=number(raw, "FzISO", where, positive=True),
        twin_tyres=bool(raw.get("TwinTyres", False)),
        wheel_inertia_kgm2=number(raw, "Inertia", where, minimum=0.0),
        driven=str(raw.get("Type", "")) == "VehicleDriven",
    )

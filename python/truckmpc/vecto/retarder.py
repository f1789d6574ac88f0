"""A VECTO truck's retarder: where it sits, its ratio and its loss map (``.vrlm``, or the
``RetarderLossMap`` of a declaration XML), whose drag VECTO charges whenever its shaft turns.

A retarder on the gearbox's input shaft turns with the engine; one on its output (or on the axle's
input, the same shaft without an angle drive) turns with the wheels, in neutral too. An engine
retarder, one whose losses the gearbox's loss maps include, or none, adds no loss.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

from truckmpc.errors import VehicleError
from truckmpc.vecto.files import number, numbers_table
from truckmpc.vecto.xml_tree import Element, attr, child, text
from truckmpc.vecto.xml_tree import number as xml_number

__all__ = ["RetarderData", "retarder_of_vveh", "retarder_of_xml"]

# Retarder types as VECTO's files name them (XML, and the .vveh's older names), lower case: the
# gearbox shaft each turns with, or None where VECTO charges no retarder loss.
_POSITIONS: dict[str, str | None] = {
    "none": None,
    "losses included in gearbox": None,
    "engine retarder": None,
    "transmission input retarder": "input",
    "primary": "input",
    "transmission output retarder": "output",
    "secondary": "output",
    "axlegear input retarder": "output",
}


@dataclass(frozen=True)
class RetarderData:
    """A retarder whose drag counts: the gearbox shaft it turns with, its ratio and loss map."""

    position: str
    """"input" or "output" (of the gearbox)."""
    ratio: float
    """Retarder speed per speed of its shaft [-]."""
    loss_map: tuple[tuple[float, float], ...] | None
    """(retarder speed [rpm], torque loss [Nm]) rows; None where the named file is missing."""
    file: str
    """The loss map's file as the job names it ("" for a declaration XML)."""


_BY_KEY = {name.replace(" ", ""): position for name, position in _POSITIONS.items()} | {
    "losses included in transmission".replace(" ", ""): None,
}
"""The types by their name lower-cased without spaces: VECTO's files write them with spaces (XML)
or as its enum's names (``TransmissionOutputRetarder``, ``LossesIncludedInTransmission``)."""


def _position(kind: str, where: str) -> str | None:
    """The shaft of a retarder type, refusing a type VECTO does not know."""
    key = kind.strip().lower().replace(" ", "")
    if key not in _BY_KEY:
        names = ", ".join(sorted(_POSITIONS))
        raise VehicleError(f"{where}: expected a retarder type ({names}), got {kind!r}")
    return _BY_KEY[key]


def retarder_of_xml(vehicle: Element, components: Element) -> RetarderData | None:
    """The retarder a declaration's ``Vehicle`` declares (``RetarderType``, ``RetarderRatio``) with
    the loss map of its ``Retarder`` component; None where none adds a loss."""
    kind_el = child(vehicle, "RetarderType")
    position = _position(text(kind_el), kind_el.where)
    if position is None:
        return None
    ratio = xml_number(child(vehicle, "RetarderRatio"), positive=True)
    entries = [e for e in child(components, "Retarder", "Data", "RetarderLossMap").children if e.name == "Entry"]
    if len(entries) < 2:
        raise VehicleError(f"{kind_el.file}: RetarderLossMap: expected at least 2 <Entry> elements, got {len(entries)}")
    rows = tuple((attr(e, "retarderSpeed", 0.0), attr(e, "torqueLoss", 0.0)) for e in entries)
    _check_speeds(rows, [f"{e.file}:{e.line}: {e.path}" for e in entries])
    return RetarderData(position, ratio, rows, "")


def retarder_of_vveh(body: dict[str, Any], path: Path) -> RetarderData | None:
    """The retarder of a ``.vveh`` vehicle (its ``Retarder`` object) with its ``.vrlm`` loss map
    where the file is beside the vehicle; None where none adds a loss."""
    raw = body.get("Retarder")
    if not isinstance(raw, dict):
        return None
    where = f"{path}: Retarder"
    position = _position(str(raw.get("Type", "None")), f"{where}.Type")
    if position is None:
        return None
    ratio = number(raw, "Ratio", where, positive=True)
    name = str(raw.get("File") or "").strip()
    file = path.parent / name
    if not (name and file.is_file()):
        return RetarderData(position, ratio, None, name)
    rows = numbers_table(file, 2, "a retarder loss map (retarder speed, torque loss)")
    for line, (n, loss) in rows:
        if n < 0 or loss < 0:
            raise VehicleError(f"{file}:{line}: expected a speed and a torque loss >= 0, got {n:g}, {loss:g}")
    _check_speeds(tuple((n, loss) for _, (n, loss) in rows), [f"{file}:{line}" for line, _ in rows])
    return RetarderData(position, ratio, tuple((n, loss) for _, (n, loss) in rows), name)


def _check_speeds(rows: tuple[tuple[float, float], ...], wheres: list[str]) -> None:
    """Refuses retarder speeds that do not increase, naming the row."""
    for i in range(1, len(rows)):
        if rows[i][0] <= rows[i - 1][0]:
            raise VehicleError(
                f"{wheres[i]}: expected a retarder speed above {rows[i - 1][0]:g} rpm, got {rows[i][0]:g}"
            )

"""What VECTO's declaration mode adds to a vehicle, whatever drives it: its group on the mission,
the standard trailer and reference load, the combination's rolling resistance and wheels' inertia,
the tyres' dynamic radius and the air drag with the trailer and the cross-wind correction."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from truckmpc.errors import VehicleError
from truckmpc.vecto import declaration as decl
from truckmpc.vecto.components import VehicleData

__all__ = ["Combination", "declared_combination"]

_MIN_GROSS_MASS_T = 16.0  # group 5 is a 4x2 tractor above 16 t


@dataclass(frozen=True)
class Combination:
    """A vehicle with its declaration-mode trailer and load."""

    segment: decl.Segment
    payload_kg: float
    trailer_mass_kg: float
    mass_kg: float
    """Vehicle + trailer + load [kg]."""
    wheel_radius_m: float
    """The driven axles' mean dynamic tyre radius [m]."""
    rolling_resistance: float
    """The combination's rolling resistance coefficient at :attr:`mass_kg` [-]."""
    wheels_inertia_kgm2: float
    cda_m2: float
    """Cd·A [m²] of the vehicle with the trailer, before the cross-wind correction."""
    cda_curve: tuple[tuple[float, float], ...]
    """(speed [m/s], Cd·A [m²]) with the cross-wind correction."""


def declared_combination(
    vehicle: VehicleData, keys: Mapping[str, Any], path: Path, declaration_mode: bool = True
) -> Combination:
    """``vehicle`` (read from ``path``) as declaration mode completes it, with the truck's ``keys``
    (``mission``, ``payload_kg``, ``trailer_mass_kg``, ``cross_wind``)."""
    segment = _segment(vehicle, keys, path, declaration_mode)
    payload = segment.reference_load_kg if keys["payload_kg"] is None else keys["payload_kg"]
    trailer = segment.trailer_mass_kg if keys["trailer_mass_kg"] is None else keys["trailer_mass_kg"]
    mass = vehicle.curb_mass_kg + trailer + payload
    where = f"{vehicle.path}: AxleConfig.Axles"
    driven = [a for a in vehicle.axles if a.driven] or list(vehicle.axles)
    radius = sum(decl.dynamic_radius_m(a.tyre, where) for a in driven) / len(driven)
    rrc, wheels_inertia = _wheels(vehicle, segment, mass)
    cda0 = vehicle.cda_m2 + segment.trailer_delta_cda_m2
    curve = decl.cross_wind_cda_curve(cda0, keys["cross_wind"], segment.cross_wind_parameters, segment.height_m)
    return Combination(segment, payload, trailer, mass, radius, rrc, wheels_inertia, cda0, tuple(curve))


def _segment(vehicle: VehicleData, keys: Mapping[str, Any], path: Path, declaration_mode: bool) -> decl.Segment:
    """VECTO's group of a declaration-mode vehicle on the mission."""
    if not declaration_mode:
        raise VehicleError(
            f"{path}: SavedInDeclMode: expected a declaration-mode job (truckmpc adds declaration mode's "
            "trailer, load and air drag; an engineering-mode job's own are not read yet), got false"
        )
    mission = keys["mission"]
    segment = decl.SEGMENTS.get((vehicle.category, vehicle.axle_config, mission))
    if segment is None or vehicle.gross_mass_t <= _MIN_GROSS_MASS_T:
        carried = "; ".join(s.name for s in decl.SEGMENTS.values())
        raise VehicleError(
            f"{vehicle.path}: VehCat/AxleConfig/MassMax: expected a group truckmpc carries ({carried}), "
            f"got {vehicle.category} {vehicle.axle_config} of {vehicle.gross_mass_t:g} t on {mission}"
        )
    if len(segment.vehicle_axle_shares) != len(vehicle.axles):
        raise VehicleError(
            f"{vehicle.path}: AxleConfig.Axles: "
            f"expected {len(segment.vehicle_axle_shares)} axles, got {len(vehicle.axles)}"
        )
    return segment


def _wheels(vehicle: VehicleData, segment: decl.Segment, mass_kg: float) -> tuple[float, float]:
    """The combination's rolling resistance coefficient and its wheels' inertia [kg m²], the
    vehicle's axles and the standard trailer's."""
    ta = segment.trailer_axles
    share = segment.trailer_axle_share / ta.count
    axles = [
        (s, a.rolling_resistance, a.tyre_test_load_n, 4 if a.twin_tyres else 2)
        for s, a in zip(segment.vehicle_axle_shares, vehicle.axles, strict=True)
    ]
    axles += [(share, ta.rolling_resistance, ta.tyre_test_load_n, 2)] * ta.count
    inertia = sum((4 if a.twin_tyres else 2) * a.wheel_inertia_kgm2 for a in vehicle.axles)
    inertia += 2 * ta.count * decl.wheel_inertia_kgm2(ta.tyre, "the standard trailer")
    return decl.combination_rolling_resistance(axles, mass_kg), inertia

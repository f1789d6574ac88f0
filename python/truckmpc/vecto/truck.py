"""A VECTO job made into a truck the core simulates: the components as read, plus what declaration
mode adds (trailer, load, the combination's air drag and rolling resistance, auxiliaries), each a
key a user can see and override.
"""

from __future__ import annotations

from dataclasses import dataclass, fields, replace
from pathlib import Path
from typing import Any

from truckmpc import _core
from truckmpc.errors import VehicleError
from truckmpc.vecto import declaration as decl
from truckmpc.vecto.components import VectoJob, read_job

__all__ = ["DRIVELINE_LOSS_NOTE", "TruckKeys", "VectoTruck", "load_vecto_truck"]

DRIVELINE_LOSS_NOTE = (
    "gearbox and axle losses: VECTO's loss maps are not read yet; the defaults are a loss affine in "
    "torque fitted on VECTO's generic tractor's full-load climb in gear 11 (4.5 % of the torque plus "
    "102 Nm of drag at the gearbox input)"
)


@dataclass(frozen=True)
class TruckKeys:
    """What declaration mode adds to a VECTO vehicle, with VECTO's values for its group as defaults;
    ``None`` means "VECTO's value for this truck"."""

    mission: str = "LongHaul"
    payload_kg: float | None = None
    """Load [kg]; default: the group's reference load on the mission."""
    trailer_mass_kg: float | None = None
    """Mass of the standard trailer [kg]."""
    cross_wind: str = "vecto3"
    """Cross-wind correction of the drag area: vecto3, height_profile or none."""
    air_density_kg_m3: float = decl.AIR_DENSITY_KG_M3
    aux_power_w: float | None = None
    """Auxiliary power [W]; default: VECTO's for the job's technologies."""
    gear_efficiency: float = 1.0 - 0.04541
    axle_efficiency: float = 1.0
    loss_torque_nm: float = 102.33 / (1.0 - 0.04541)
    """Driveline drag torque at the gearbox input [Nm] (see :data:`DRIVELINE_LOSS_NOTE`)."""

    def with_values(self, values: dict[str, Any], where: str) -> TruckKeys:
        """These keys with ``values`` set; an unknown key or a bad value is a one-line error."""
        known = {f.name: f for f in fields(self)}
        out: dict[str, Any] = {}
        for key, value in values.items():
            if key not in known:
                raise VehicleError(f"{where}: {key}: expected one of {', '.join(known)}, got an unknown key")
            if key in ("mission", "cross_wind"):
                out[key] = str(value)
                continue
            try:
                out[key] = float(value)
            except (TypeError, ValueError):
                raise VehicleError(f"{where}: {key}: expected a number, got {value!r}") from None
        keys = replace(self, **out)
        if keys.cross_wind not in decl.CROSS_WIND:
            raise VehicleError(
                f"{where}: cross_wind: expected one of {', '.join(decl.CROSS_WIND)}, got {keys.cross_wind!r}"
            )
        return keys


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
    keys: TruckKeys
    core: _core.MapTruck


def load_vecto_truck(path: Path, values: dict[str, Any] | None = None) -> VectoTruck:
    """Read a ``.vecto`` job and build its truck with declaration mode's additions (``values``
    override :class:`TruckKeys`)."""
    job = read_job(path)
    keys = TruckKeys().with_values(values or {}, str(path))
    vehicle = job.vehicle
    axle_config = "4x2" if len(vehicle.axles) == 2 else f"{len(vehicle.axles)} axles"
    segment = decl.SEGMENTS.get((vehicle.category, axle_config, keys.mission))
    if segment is None:
        carried = "; ".join(s.name for s in decl.SEGMENTS.values())
        raise VehicleError(
            f"{vehicle.path}: VehCat/AxleConfig: expected a group truckmpc carries ({carried}), "
            f"got {vehicle.category} {axle_config} on {keys.mission}"
        )
    if len(segment.vehicle_axle_shares) != len(vehicle.axles):
        raise VehicleError(
            f"{vehicle.path}: AxleConfig.Axles: "
            f"expected {len(segment.vehicle_axle_shares)} axles, got {len(vehicle.axles)}"
        )
    payload = segment.reference_load_kg if keys.payload_kg is None else keys.payload_kg
    trailer = segment.trailer_mass_kg if keys.trailer_mass_kg is None else keys.trailer_mass_kg
    mass = vehicle.curb_mass_kg + trailer + payload
    where = f"{vehicle.path}: AxleConfig.Axles"
    driven = [a for a in vehicle.axles if a.driven] or list(vehicle.axles)
    radius = sum(decl.dynamic_radius_m(a.tyre, where) for a in driven) / len(driven)
    ta = segment.trailer_axles
    share = segment.trailer_axle_share / ta.count
    axles = [
        (s, a.rolling_resistance, a.tyre_test_load_n, 4 if a.twin_tyres else 2)
        for s, a in zip(segment.vehicle_axle_shares, vehicle.axles, strict=True)
    ]
    axles += [(share, ta.rolling_resistance, ta.tyre_test_load_n, 2)] * ta.count
    rrc = decl.combination_rolling_resistance(axles, mass)
    wheels_inertia = sum((4 if a.twin_tyres else 2) * a.wheel_inertia_kgm2 for a in vehicle.axles)
    wheels_inertia += 2 * ta.count * decl.wheel_inertia_kgm2(ta.tyre, "the standard trailer")
    cda0 = vehicle.cda_m2 + segment.trailer_delta_cda_m2
    curve = decl.cross_wind_cda_curve(cda0, keys.cross_wind, segment.cross_wind_parameters, segment.height_m)
    aux = decl.auxiliary_power_w(job.auxiliaries, str(job.path)) if keys.aux_power_w is None else keys.aux_power_w
    engine = job.engine
    core = _core.MapTruck(
        {
            "idle_speed_rpm": engine.idle_speed_rpm,
            "inertia_kgm2": engine.inertia_kgm2,
            "full_load": list(engine.full_load),
            "fuel_map": list(engine.fuel_map),
        },
        {
            "gear_ratios": list(job.gearbox.gear_ratios),
            "axle_ratio": job.gearbox.axle_ratio,
            "gear_efficiency": keys.gear_efficiency,
            "axle_efficiency": keys.axle_efficiency,
            "loss_torque_nm": keys.loss_torque_nm,
            "wheel_radius_m": radius,
        },
        {
            "mass_kg": mass,
            "wheels_inertia_kgm2": wheels_inertia,
            "cda_m2": cda0,
            "cda_curve": curve,
            "air_density_kg_m3": keys.air_density_kg_m3,
            "rolling_resistance": rrc,
            "aux_power_w": aux,
        },
    )
    return VectoTruck(job, segment, mass, payload, trailer, radius, rrc, tuple(curve), aux, keys, core)

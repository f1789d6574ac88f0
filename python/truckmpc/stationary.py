"""The truck held at a constant speed on a constant grade (``truckmpc model stationary``): for the
thesis's truck the pedal or brake level that holds it, whether the levels reach, and the eigenvalue
of the speed dynamics there; for any truck the engine's speed, torque and fuel rate."""

from __future__ import annotations

import math
from typing import Any

from truckmpc.config import RunConfig
from truckmpc.units import KMH_PER_MPS, PCT_PER_FRACTION
from truckmpc.vecto import VectoTruck
from truckmpc.vecto.electric_truck import ElectricVectoTruck

__all__ = ["electric_stationary_point", "map_truck_stationary_point", "stationary_point"]


def stationary_point(config: RunConfig, speed_kmh: float, slope_pct: float, gear: int | None = None) -> dict[str, Any]:
    """The stationary point of `config`'s truck at `speed_kmh` [km/h] on `slope_pct` [%, negative
    downhill] in `gear` (0: neutral; None: the gear the PI gear logic settles in at that speed).

    Returns ``speed_kmh``, ``slope_pct``, ``gear``, ``pedal`` and ``brake`` (levels 0..1),
    ``feasible`` (False when the levels were clipped to [0, 1]), ``eigenvalue_per_m``,
    λ = ∂(dv/ds)/∂v [1/m], and the engine's ``engine_speed_rpm``, ``engine_torque_nm`` and
    ``fuel_rate_g_per_h`` there.
    """
    v_mps = speed_kmh / KMH_PER_MPS
    chosen = config.settings.steady_gear(v_mps) if gear is None else gear
    point = config.core_vehicle.stationary(v_mps, slope_pct / PCT_PER_FRACTION, chosen)
    return {
        "speed_kmh": speed_kmh,
        "slope_pct": slope_pct,
        "gear": chosen,
        "pedal": point["pedal"],
        "brake": point["brake"],
        "feasible": bool(point["feasible"]),
        "eigenvalue_per_m": point["eigenvalue_per_m"],
        "engine_speed_rpm": point["engine_speed_rpm"],
        "engine_torque_nm": point["engine_torque_nm"],
        "fuel_rate_g_per_h": point["fuel_rate_g_per_h"],
    }


def map_truck_stationary_point(
    truck: VectoTruck, speed_kmh: float, slope_pct: float, gear: int | None = None
) -> dict[str, Any]:
    """The operating point of a truck from component data holding `speed_kmh` on `slope_pct` in
    `gear` (None: the highest gear that holds it within the engine's full-load curve; where none
    does, the lowest gear whose engine speed the curve covers, else the one nearest its range).

    Returns ``speed_kmh``, ``slope_pct``, ``gear``, ``engine_speed_rpm``, ``engine_torque_nm`` (the
    drag torque when the grade needs braking), ``fuel_rate_g_per_h``, ``brake_power_w`` (what the
    wheel brakes take beyond the engine's drag), ``feasible`` (the engine can deliver the torque at
    that speed) and ``not_feasible`` (why not, or None). Where it is not feasible the fuel rate and
    brake power are None: the truck cannot hold that speed there.
    """
    core = truck.core
    v_mps, slope_rad = speed_kmh / KMH_PER_MPS, math.atan(slope_pct / PCT_PER_FRACTION)
    lo, hi = core.facts["full_load_speed_range_rpm"]
    gears = range(1, core.facts["gears"] + 1) if gear is None else [gear]
    points = {g: core.at(v_mps, 0.0, slope_rad, g) for g in gears}
    if gear is None:
        feasible = [g for g, p in points.items() if p["feasible"]]
        outside = {g: max(lo - p["engine_speed_rpm"], p["engine_speed_rpm"] - hi, 0.0) for g, p in points.items()}
        gear = max(feasible) if feasible else min(outside, key=lambda g: (outside[g], g))
    op = points[gear]
    n_rpm, torque_nm = op["engine_speed_rpm"], op["engine_torque_nm"]
    reason = None
    if not lo <= n_rpm <= hi:
        reason = f"gear {gear} turns the engine at {n_rpm:.0f} rpm, outside its full-load curve ({lo:.0f}-{hi:.0f} rpm)"
    elif not op["feasible"]:
        most_nm = core.engine_point(n_rpm, 0.0)["max_torque_nm"]
        reason = f"the engine gives at most {most_nm:.0f} Nm at {n_rpm:.0f} rpm, {torque_nm:.0f} Nm needed"
    return {
        "speed_kmh": speed_kmh,
        "slope_pct": slope_pct,
        "gear": gear,
        "engine_speed_rpm": n_rpm,
        "engine_torque_nm": max(torque_nm, core.engine_point(n_rpm, 0.0)["drag_torque_nm"]),
        "fuel_rate_g_per_h": op["fuel_rate_g_per_h"] if reason is None else None,
        "brake_power_w": op["brake_power_w"] if reason is None else None,
        "feasible": bool(op["feasible"]),
        "not_feasible": reason,
    }


def electric_stationary_point(
    truck: ElectricVectoTruck, speed_kmh: float, slope_pct: float, brake_torque_max_nm: float
) -> dict[str, Any]:
    """A battery-electric truck holding `speed_kmh` on `slope_pct` (service brakes of
    `brake_torque_max_nm` [Nm] at the wheels): the pedal or brake level, ``feasible`` (the machines
    and the battery give the torque), the machines' ``machine_speed_rpm`` and ``machine_torque_nm``,
    and where the battery's power goes [W]: ``battery_power_w`` (negative where braking returns
    energy), ``battery_loss_w``, ``aux_power_w``, ``machine_loss_w``, ``reduction_loss_w``,
    ``wheel_power_w`` and ``friction_brake_power_w``."""
    v_mps, slope_rad = speed_kmh / KMH_PER_MPS, math.atan(slope_pct / PCT_PER_FRACTION)
    state = truck.core.electric_state(v_mps, slope_rad, brake_torque_max_nm)
    return {"speed_kmh": speed_kmh, "slope_pct": slope_pct, **state}

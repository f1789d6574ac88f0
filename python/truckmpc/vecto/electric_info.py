"""What was read of a battery-electric truck's declaration, as a document (``truckmpc vehicle
info``): its machines, reduction, batteries and vehicle, each figure with its unit in its key."""

from __future__ import annotations

import hashlib
from collections.abc import Mapping
from typing import Any

import numpy as np

from truckmpc.units import KMH_PER_MPS
from truckmpc.vecto.combination import declared_combination
from truckmpc.vecto.electric import BatteryData, ElectricMachineData, ElectricTruckJob
from truckmpc.vecto.electric_truck import load_electric_truck

_REFERENCE_KMH = 80.0

__all__ = ["electric_truck_info", "usable_energy_kwh"]


def electric_truck_info(job: ElectricTruckJob, keys: Mapping[str, Any]) -> dict[str, Any]:
    """The truck's components as read, with the figures a reader checks first, and the vehicle as
    declaration mode completes it with the VECTO truck's ``keys`` (``truck_values``)."""
    vehicle = job.vehicle
    c = declared_combination(vehicle, keys, job.path)
    curve = np.array(c.cda_curve)
    cda_at_80 = float(np.interp(_REFERENCE_KMH / KMH_PER_MPS, curve[:, 0], curve[:, 1]))
    return {
        "job": str(job.path),
        "files": {str(job.path): hashlib.sha256(job.path.read_bytes()).hexdigest()},
        "architecture": job.architecture,
        "group": c.segment.name,
        "category": vehicle.category,
        "axle_config": vehicle.axle_config,
        "corrected_actual_mass_kg": vehicle.curb_mass_kg,
        "trailer_mass_kg": c.trailer_mass_kg,
        "payload_kg": c.payload_kg,
        "mass_kg": c.mass_kg,
        "gross_mass_kg": vehicle.gross_mass_t * 1000.0,
        "wheel_radius_m": c.wheel_radius_m,
        "cda_declared_m2": vehicle.cda_m2,
        "cda_at_80_kmh_m2": cda_at_80,
        "cross_wind": keys["cross_wind"],
        "rolling_resistance": c.rolling_resistance,
        "machines": _machines(job.machine),
        "reduction_ratio": job.reduction.ratio,
        "reduction_loss_map_points": len(job.reduction.loss_map),
        "batteries": [_battery(b) for b in job.batteries],
        "auxiliaries": [f"{name}: {technology}" for name, technology in job.auxiliaries],
        **_as_driven(job, keys),
    }


def _as_driven(job: ElectricTruckJob, keys: Mapping[str, Any]) -> dict[str, Any]:
    """What a run takes of the truck: the battery's usable window, start and energy; the machines'
    continuous torque (all of them), their loss there and the thermal buffer above it, at the
    battery's voltage (their derating)."""
    facts = load_electric_truck(job, keys).core.electric_facts
    battery = {key: facts[key] for key in ("usable_window_pct", "soc_start_pct", "usable_energy_kwh")}
    return {
        **battery,
        "machines_continuous_torque_nm": facts["continuous_torque_nm"],
        "machines_continuous_loss_w": facts["continuous_loss_w"],
        "machines_overload_buffer_kj": facts["overload_buffer_kj"],
    }


def _machines(m: ElectricMachineData) -> dict[str, Any]:
    """Each machine's figures as the file gives them (per machine), and how many there are."""
    low = m.voltage_levels[0]
    speeds = sorted({n for n, _, _ in low.power_map})
    torques = sorted({t for _, t, _ in low.power_map})
    return {
        "position": m.position,
        "count": m.count,
        "type": m.machine_type,
        "rated_power_w": m.rated_power_w,
        "inertia_kgm2": m.inertia_kgm2,
        "voltage_levels_v": [v.voltage_v for v in m.voltage_levels],
        "continuous_torque_nm": low.continuous_torque_nm,
        "overload_torque_nm": low.overload_torque_nm,
        "overload_duration_s": low.overload_duration_s,
        "max_torque_nm": max(t for _, t, _ in low.torque_limits),
        "top_speed_rpm": low.torque_limits[-1][0],
        "power_map_size": [len(speeds), len(torques)],
        "drag_torque_range_nm": [min(t for _, t in m.drag_curve), max(t for _, t in m.drag_curve)],
    }


def _battery(b: BatteryData) -> dict[str, Any]:
    volts = [v for _, v in b.ocv]
    return {
        "string_id": b.string_id,
        "type": b.battery_type,
        "rated_capacity_ah": b.rated_capacity_ah,
        "ocv_range_v": [min(volts), max(volts)],
        "soc_window_pct": [b.soc_min_pct, b.soc_max_pct],
        "usable_capacity_ah": b.usable_capacity_ah,
        "usable_energy_kwh": usable_energy_kwh(b),
        "internal_resistance_mohm": sorted({r for _, *rs in b.resistance for r in rs}),
        "charging_current_limit_range_a": [
            min(c for _, c, _ in b.current_limits),
            max(c for _, c, _ in b.current_limits),
        ],
        "discharging_current_limit_range_a": [
            min(d for _, _, d in b.current_limits),
            max(d for _, _, d in b.current_limits),
        ],
    }


def usable_energy_kwh(b: BatteryData) -> float:
    """The energy [kWh] the battery holds between SOCmin and SOCmax at its open-circuit voltage
    (linear between the file's points): capacity × ∫ OCV d(SoC), no losses."""
    soc_pct = np.array([p for p, _ in b.ocv])
    ocv_v = np.array([v for _, v in b.ocv])
    inside = (soc_pct > b.soc_min_pct) & (soc_pct < b.soc_max_pct)
    grid = np.concatenate(([b.soc_min_pct], soc_pct[inside], [b.soc_max_pct]))
    volts = np.interp(grid, soc_pct, ocv_v)
    mean_v = float(np.trapezoid(volts, grid)) / (b.soc_max_pct - b.soc_min_pct)
    return b.usable_capacity_ah * mean_v / 1000.0

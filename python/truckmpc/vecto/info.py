"""What was read of a VECTO truck, as a document: masses, ratios, air drag, rolling resistance,
the engine's rated power and the ranges of its maps (``truckmpc vehicle info``)."""

from __future__ import annotations

import hashlib
from typing import Any

from truckmpc.units import KMH_PER_MPS
from truckmpc.vecto.truck import VectoTruck, driveline_losses

__all__ = ["truck_info"]

_REFERENCE_KMH = 80.0


def truck_info(truck: VectoTruck) -> dict[str, Any]:
    """The truck's resolved values with their units in the key names, and the files with SHA-256."""
    job, core = truck.job, truck.core
    facts = core.facts
    map_speeds, curve_speeds = facts["fuel_map_speed_range_rpm"], facts["full_load_speed_range_rpm"]
    return {
        "job": str(job.path),
        "group": truck.segment.name,
        "files": {str(p): hashlib.sha256(p.read_bytes()).hexdigest() for p in job.files},
        "curb_mass_kg": job.vehicle.curb_mass_kg,
        "trailer_mass_kg": truck.trailer_mass_kg,
        "payload_kg": truck.payload_kg,
        "mass_kg": truck.mass_kg,
        "gearbox": f"{job.gearbox.gearbox_type} {job.gearbox.model}".strip(),
        "gear_ratios": list(job.gearbox.gear_ratios),
        "axle_ratio": job.gearbox.axle_ratio,
        "wheel_radius_m": truck.wheel_radius_m,
        "cda_declared_m2": job.vehicle.cda_m2,
        "cda_at_80_kmh_m2": core.at(_REFERENCE_KMH / KMH_PER_MPS)["cda_m2"],
        "cross_wind": truck.keys["cross_wind"],
        "rolling_resistance": truck.rolling_resistance,
        "aux_power_w": truck.aux_power_w,
        "rated_power_w": facts["rated_power_w"],
        "rated_speed_rpm": facts["rated_speed_rpm"],
        "idle_speed_rpm": job.engine.idle_speed_rpm,
        "full_load_speed_range_rpm": list(curve_speeds),
        "fuel_map_speed_range_rpm": list(map_speeds),
        "fuel_map_torque_range_nm": facts["fuel_map_torque_range_nm"],
        "fuel_map_covers_full_load_curve": map_speeds[0] <= curve_speeds[0] and map_speeds[1] >= curve_speeds[1],
        "traction_interruption_s": job.gearbox.traction_interruption_s,
        "driveline_losses": driveline_losses(truck),
    }

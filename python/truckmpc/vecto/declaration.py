"""What VECTO adds to a vehicle in declaration mode, for the group it certifies it in: the standard
trailer, the loads, the whole combination's air drag (with VECTO's cross-wind correction) and
rolling resistance, the tyres' dynamic radius, and the auxiliaries' power.

The values are VECTO's declaration tables and constants (VECTO is published by the European
Commission under the EUPL; tables in its ``Declaration/`` resources, github.com/tanawadeatharva/BharatVECTO).
Only the groups listed in :data:`SEGMENTS` are carried; for another truck, set the keys by hand.
"""

from __future__ import annotations

import csv
import functools
import math
from dataclasses import dataclass
from importlib import resources

from truckmpc import _core
from truckmpc.errors import VehicleError
from truckmpc.units import KMH_PER_MPS

__all__ = [
    "AIR_DENSITY_KG_M3",
    "CROSS_WIND",
    "SEGMENTS",
    "Segment",
    "auxiliary_power_w",
    "combination_rolling_resistance",
    "cross_wind_cda_curve",
    "dynamic_radius_m",
    "wheel_inertia_kgm2",
]

AIR_DENSITY_KG_M3 = 1.188
"""VECTO's air density [kg/m³]."""
GRAVITY_MPS2 = _core.G_MPS2
"""Gravitational acceleration [m/s²], the core's for the map-based truck."""
ROLL_RESISTANCE_EXPONENT = 0.9
"""β of VECTO's load dependence of a tyre's rolling resistance, c_r·(F_z/F_z,ISO)^(β−1)."""


@dataclass(frozen=True)
class TrailerAxles:
    """The standard trailer's axles, as VECTO declares them."""

    count: int
    tyre: str
    rolling_resistance: float
    tyre_test_load_n: float


@dataclass(frozen=True)
class Segment:
    """A vehicle group on a mission: VECTO's segment table row and its standard trailer."""

    name: str
    trailer_mass_kg: float
    reference_load_kg: float
    vehicle_axle_shares: tuple[float, ...]
    trailer_axle_share: float
    trailer_axles: TrailerAxles
    trailer_delta_cda_m2: float
    height_m: float
    cross_wind_parameters: str


SEGMENTS = {
    # Group 5: tractor 4x2 above 16 t with semitrailer ST1, Long Haul (SegmentTable.csv,
    # Body_Trailers_Weights.csv; the trailer tyres' RRC 0.00555 is VECTO 3's, 0.0055 since).
    ("Tractor", "4x2", "LongHaul"): Segment(
        name="group 5 (tractor 4x2 > 16 t), Long Haul",
        trailer_mass_kg=7500.0,
        reference_load_kg=19300.0,
        vehicle_axle_shares=(0.20, 0.25),
        trailer_axle_share=0.55,
        trailer_axles=TrailerAxles(count=3, tyre="385/65 R22.5", rolling_resistance=0.00555, tyre_test_load_n=37500.0),
        trailer_delta_cda_m2=0.0,
        height_m=4.0,
        cross_wind_parameters="TractorSemitrailer",
    ),
}

CROSS_WIND = ("vecto3", "height_profile", "none")
"""VECTO's speed-dependent cross-wind correction of the drag area: ``vecto3``, a 3 m/s wind from
every direction with VECTO 3's parameters (the method behind the results of VECTO 3, 2017);
``height_profile``, the wind growing with height over the vehicle's height with today's parameters
(VECTO since about 2019); ``none``, the declared Cd·A at every speed."""

_CROSS_WIND_PARAMETERS = {  # (a1, a2, a3) of ΔCdA = a1·β + a2·β² + a3·β³, β in degrees
    "vecto3": {"TractorSemitrailer": (0.034767, 0.039367, -0.001897)},
    "height_profile": {
        "TractorSemitrailer": (0.030042, 0.040817, -0.00213),
        "RigidSolo": (0.013526, 0.017746, -0.000666),
        "RigidTrailer": (0.017125, 0.072275, -0.004148),
    },
}


def cross_wind_cda_curve(cda_m2: float, method: str, parameters: str, height_m: float) -> list[tuple[float, float]]:
    """The effective drag area [m²] over speed [m/s], VECTO's way: at 60, 65 … 130 km/h, Cd·A(β)
    weighted by (v_air/v)² and averaged over wind directions 0–180° (10° steps, the ends half
    weighted) and, for ``height_profile``, over heights 5–95 % of ``height_m``; below 60 km/h the
    60 km/h value."""
    if method == "none":
        return [(0.0, cda_m2), (130.0 / KMH_PER_MPS, cda_m2)]
    a1, a2, a3 = _CROSS_WIND_PARAMETERS[method][parameters]
    winds = (
        [(1.0, 3.0)]
        if method == "vecto3"
        else [(0.1, 3.0 * (p / 100 * height_m / 4.0) ** 0.2) for p in range(5, 100, 10)]
    )
    points = []
    for kmh in range(60, 131, 5):
        v = kmh / KMH_PER_MPS
        total = 0.0
        for weight, wind in winds:
            for alpha in range(0, 181, 10):
                vx, vy = v + wind * math.cos(math.radians(alpha)), wind * math.sin(math.radians(alpha))
                beta = math.degrees(math.atan(vy / vx))
                share = (5.0 if alpha in (0, 180) else 10.0) / 180.0
                total += (
                    weight * share * (cda_m2 + a1 * beta + a2 * beta**2 + a3 * beta**3) * (vx * vx + vy * vy) / (v * v)
                )
        points.append((v, total))
    return [(0.0, points[0][1]), *points]


@functools.cache
def _wheels() -> dict[str, tuple[float, float, float]]:
    text = resources.files("truckmpc.vecto").joinpath("data/wheels.csv").read_text(encoding="utf-8")
    rows = csv.DictReader(line for line in text.splitlines() if not line.startswith("#"))
    return {r["tyre"].replace(" ", ""): (float(r["d_mm"]), float(r["inertia_kgm2"]), float(r["F"])) for r in rows}


def _wheel(tyre: str, where: str) -> tuple[float, float, float]:
    table = _wheels()
    key = tyre.replace(" ", "")
    if key not in table:
        raise VehicleError(f"{where}: expected a tyre size of VECTO's Wheels table (e.g. 315/70 R22.5), got {tyre!r}")
    return table[key]


def dynamic_radius_m(tyre: str, where: str) -> float:
    """A tyre's dynamic radius [m], VECTO's d·F/(2π)."""
    d_mm, _, factor = _wheel(tyre, where)
    return d_mm / 1000.0 * factor / (2.0 * math.pi)


def wheel_inertia_kgm2(tyre: str, where: str) -> float:
    """One wheel's rotating inertia [kg m²] from VECTO's Wheels table."""
    return _wheel(tyre, where)[1]


def combination_rolling_resistance(axles: list[tuple[float, float, float, int]], mass_kg: float) -> float:
    """VECTO's rolling resistance coefficient of the whole combination from its axles, each
    (share of the mass, tyre RRC, tyre test load F_z,ISO [N], number of tyres): the sum of
    share·RRC·(share·m·g / (F_z,ISO·tyres))^(β−1)."""
    total = 0.0
    for share, rrc, fz_iso_n, tyres in axles:
        total += share * rrc * (share * mass_kg * GRAVITY_MPS2 / fz_iso_n / tyres) ** (ROLL_RESISTANCE_EXPONENT - 1)
    return total


_AUX_LONG_HAUL_W = {  # VECTO's VAUX tables, Long Haul column, for the technologies carried here
    "Fan": {"Belt driven or driven via transm. - Electronically controlled visco clutch": 989.0},
    "Steering pump": {"Fixed displacement with elec. control": 690.0},  # one steered axle
    "HVAC": {"Default": 350.0},
    "Pneumatic system": {"Medium Supply 2-stage + ESS + AMS": 700.0},
    "Electric system": {"Standard technology": 1200.0 / 0.7},  # electric demand over the alternator's efficiency
}
_AUX_IDS = {"FAN": "Fan", "STP": "Steering pump", "AC": "HVAC", "PS": "Pneumatic system", "ES": "Electric system"}


def auxiliary_power_w(auxiliaries: tuple[tuple[str, str], ...], where: str) -> float:
    """The summed power [W] of a job's auxiliaries on Long Haul, each (id, technology)."""
    total = 0.0
    for aux_id, tech in auxiliaries:
        kind = _AUX_IDS.get(aux_id)
        table = _AUX_LONG_HAUL_W.get(kind or "", {})
        if tech not in table:
            raise VehicleError(
                f"{where}: Aux {aux_id}: expected a technology truckmpc carries "
                f"({', '.join(table) or 'none for this id'}), "
                f"got {tech!r}; set the vehicle key aux_power_w instead"
            )
        total += table[tech]
    return total

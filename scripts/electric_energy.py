"""Drive VECTO's generic battery-electric tractor with a controller over a road and check that its
battery energy balances: the net energy drawn from the battery against air drag, rolling
resistance, the machines', reduction's and battery's losses, the auxiliaries, the friction brakes
and the change of kinetic and potential energy.

Usage: python scripts/electric_energy.py [ROAD [CONTROLLER]]
(default: ../shared/roads/eu_vecto_longhaul_2015_108km.csv and the MPC).

The run is traced every metre. Air drag ½ρ·CdA(v)·v³, rolling resistance m·g·c_r·cos α·v and the
powertrain's losses (the core's, at each sample's speed and the inputs that drove up to it) are
summed over the trace by the trapezoid rule in time; the potential energy is m·g·sin α summed over
the road's segments, the kinetic energy ½·m_eff·v² with the wheels' and machines' inertia.
Prints each term [kWh] and the balance's residual in % of the battery energy.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path
from typing import Any

import numpy as np

from truckmpc.config import load_run_config
from truckmpc.roads import load_road
from truckmpc.sim import simulate
from truckmpc.units import KMH_PER_MPS

SHARED = Path(__file__).resolve().parents[1] / ".." / "shared"
BEV = SHARED / "vehicles" / "vecto-generic-class5-bev" / "Group5_PEV_E4.xml"
J_PER_KWH = 3.6e6
G_MPS2 = 9.80665
LOSSES = ("machine_loss_w", "reduction_loss_w", "battery_loss_w", "aux_w")


def energy_balance(road_path: Path, controller: str) -> dict[str, float]:
    """The terms of the battery's energy balance [kWh] of `controller` over the road, and
    ``residual_pct``: (drawn − the sum of the terms) / drawn [%]."""
    config = load_run_config(BEV, overrides=["trace_step_m=1"])
    road = load_road(road_path)
    result = simulate(road, config, controller)
    if result.summary.get("battery_empty") or result.summary["stalled"]:
        raise SystemExit(f"{controller} did not drive the road: {result.message}")
    truck = config.truck
    assert truck is not None
    trace = {key: np.asarray(values, dtype=float) for key, values in result.trace.items()}
    v = trace["speed_kmh"] / KMH_PER_MPS
    brakes_nm = float(config.settings.get("brake_torque_max_nm"))
    flows = truck.core.electric_flows(v, trace["pedal"], trace["brake"], brakes_nm)
    terms = {name: _integral(flows[name], trace) for name in LOSSES}
    terms["air_drag"] = _integral(_air_w(truck, config, v), trace)
    terms["rolling"] = _integral(_rolling_w(truck, trace, v), trace)
    terms["friction_brakes"] = result.summary["brake_energy_kj"] * 1e3 / J_PER_KWH
    terms["kinetic"] = 0.5 * truck.core.electric_facts["effective_mass_kg"] * (v[-1] ** 2 - v[0] ** 2) / J_PER_KWH
    terms["potential"] = truck.mass_kg * G_MPS2 * _height_m(road, trace["distance_m"][0], trace["distance_m"][-1])
    terms["potential"] /= J_PER_KWH
    drawn = result.summary["energy_kwh"]
    return {"drawn": drawn, **terms, "residual_pct": 100 * (drawn - sum(terms.values())) / drawn}


def _integral(power_w: np.ndarray, trace: dict[str, np.ndarray]) -> float:
    """∫ power dt [kWh] over the trace, by the trapezoid rule between its samples."""
    dt = np.diff(trace["time_s"])
    return float(np.sum(0.5 * (power_w[:-1] + power_w[1:]) * dt)) / J_PER_KWH


def _air_w(truck: Any, config: Any, v: np.ndarray) -> np.ndarray:
    speeds, areas = zip(*truck.cda_curve, strict=True)
    rho = float(config.settings.get("air_density_kgpm3"))
    return np.asarray(0.5 * rho * np.interp(v, speeds, areas) * v**3, dtype=float)


def _rolling_w(truck: Any, trace: dict[str, np.ndarray], v: np.ndarray) -> np.ndarray:
    alpha = np.arctan(trace["slope"])
    return np.asarray(truck.mass_kg * G_MPS2 * truck.rolling_resistance * np.cos(alpha) * v, dtype=float)


def _height_m(road: Any, start_m: float, end_m: float) -> float:
    """Σ sin α · length over the road's segments between `start_m` and `end_m` [m]."""
    d, slopes = np.asarray(road.distance_m), np.diff(road.altitude_m) / np.diff(road.distance_m)
    lo, hi = np.clip(d[:-1], start_m, end_m), np.clip(d[1:], start_m, end_m)
    return float(np.sum(np.sin(np.arctan(slopes)) * (hi - lo)))


def main() -> None:
    road = Path(sys.argv[1]) if len(sys.argv) > 1 else SHARED / "roads" / "eu_vecto_longhaul_2015_108km.csv"
    controller = sys.argv[2] if len(sys.argv) > 2 else "mpc"
    terms = energy_balance(road, controller)
    for name, value in terms.items():
        unit = "%" if name == "residual_pct" else "kWh"
        print(f"{name:18s} {value:12.4f} {unit}")
    if not math.isfinite(terms["residual_pct"]):
        raise SystemExit("the balance is not a number")


if __name__ == "__main__":
    main()

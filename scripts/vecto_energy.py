"""Drive a VECTO truck with a controller over a road and print where its energy went, next to
VECTO's own balance for the same truck on its Long Haul cycle (the ``.vsum`` row at the load).

Usage: python scripts/vecto_energy.py [ROAD [CONTROLLER]]
(default: ../shared/roads/eu_vecto_longhaul_100km.csv and the PI, with VECTO's generic group-5
tractor at its reference load).

The run is traced every 5 m; the terms are summed over the trace (air drag ½ρ·CdA(v)·v², rolling
m·g·c_r·cos α and gravity m·g·sin α per metre, the auxiliaries' power over time, the engine's work
above and below zero torque), the brakes' energy is the run's own, and the driveline's losses are
what the engine's work leaves after the others and the change of kinetic energy.
"""

from __future__ import annotations

import csv
import math
import sys
from pathlib import Path

import numpy as np

from truckmpc.config import load_run_config
from truckmpc.roads import load_road
from truckmpc.sim import simulate
from truckmpc.units import KMH_PER_MPS

SHARED = Path(__file__).resolve().parents[1] / ".." / "shared"
TRACTOR = SHARED / "vehicles" / "vecto-generic-class5-tractor"
J_PER_KWH = 3.6e6
G_MPS2 = 9.80665
VSUM_TERMS = {
    "air drag": "E_air [kWh]",
    "rolling": "E_roll [kWh]",
    "gravity": "E_grad [kWh]",
    "brakes": "E_brake [kWh]",
    "driveline losses": "E_gbx_axl_loss [kWh]",
    "retarder losses": "E_ret_loss [kWh]",
    "auxiliaries": "E_aux_sum [kWh]",
    "engine work > 0": "E_fcmap_pos [kWh]",
}


def vsum_row(load_kg: float) -> dict[str, str]:
    """VECTO's summary row for the Long Haul cycle at ``load_kg``."""
    with (TRACTOR / "Class5_Tractor_DECL.vsum").open() as f:
        for row in csv.DictReader(f):
            if "LongHaul" in row["Cycle [-]"] and abs(float(row["Loading [kg]"]) - load_kg) < 1.0:
                return row
    raise SystemExit(f"no Long Haul row at {load_kg:g} kg in the .vsum")


def ledger(road_path: Path, controller: str) -> tuple[dict[str, float], dict[str, float]]:
    """The run's energy terms [kWh] and its figures (fuel g/km, time s, mean speed km/h)."""
    config = load_run_config(TRACTOR / "Class5_Tractor_DECL.vecto", overrides=["trace_step_m=5"])
    truck = config.truck
    assert truck is not None
    result = simulate(load_road(road_path), config, controller)
    t = result.trace
    s, v = np.asarray(t["distance_m"]), np.asarray(t["speed_kmh"]) / KMH_PER_MPS
    ds, dt = np.diff(s), np.diff(np.asarray(t["time_s"]))
    v_mid = 0.5 * (v[1:] + v[:-1])
    alpha = np.arctan(np.asarray(t["slope"])[:-1])
    mass, core = truck.mass_kg, truck.core
    air = sum(
        0.5 * truck.keys["air_density_kgpm3"] * core.at(u)["cda_m2"] * u * u * d for u, d in zip(v_mid, ds, strict=True)
    )
    vehicle = config.core_vehicle
    work_pos = work_neg = 0.0
    for u, pedal, gear, step in zip(v_mid, t["pedal"][:-1], t["gear"][:-1], dt, strict=True):
        if gear > 0:
            omega = vehicle.engine_speed_rpm(u, int(gear)) * math.pi / 30
            power = vehicle.engine_torque_nm(u, pedal, int(gear)) * omega
            work_pos, work_neg = work_pos + max(power, 0.0) * step, work_neg + min(power, 0.0) * step
    terms = {
        "air drag": air,
        "rolling": float(np.sum(mass * G_MPS2 * truck.rolling_resistance * np.cos(alpha) * ds)),
        "gravity": float(np.sum(mass * G_MPS2 * np.sin(alpha) * ds)),
        "brakes": result.summary["brake_energy_kj"] * 1e3,
        "auxiliaries": truck.aux_power_w * result.summary["time_s"],
        "engine work > 0": work_pos,
        "engine work < 0 (drag)": work_neg,
        "kinetic energy gained": 0.5 * mass * (v[-1] ** 2 - v[0] ** 2),
    }
    spent = sum(terms[k] for k in ("air drag", "rolling", "gravity", "brakes", "auxiliaries", "kinetic energy gained"))
    terms["driveline losses"] = work_pos + work_neg - spent
    summary = result.summary
    figures = {
        "fuel [g/km]": summary["fuel_kg"] * 1e6 / summary["distance_m"],
        "trip time [s]": summary["time_s"],
        "mean speed [km/h]": summary["mean_speed_kmh"],
        "fuel per engine work [g/kWh]": summary["fuel_kg"] * 1e3 / (work_pos / J_PER_KWH),
    }
    return {k: val / J_PER_KWH for k, val in terms.items()}, figures


def main() -> None:
    road = Path(sys.argv[1]) if len(sys.argv) > 1 else SHARED / "roads" / "eu_vecto_longhaul_100km.csv"
    controller = sys.argv[2] if len(sys.argv) > 2 else "pi"
    terms, figures = ledger(road, controller)
    vecto = vsum_row(19300.0)
    km = float(vecto["distance [km]"])
    vecto_fuel_g = float(vecto["FC-Final [g/km]"]) * km
    vecto_figures = {
        "fuel [g/km]": float(vecto["FC-Final [g/km]"]),
        "trip time [s]": float(vecto["time [s]"]),
        "mean speed [km/h]": float(vecto["speed [km/h]"]),
        "fuel per engine work [g/kWh]": vecto_fuel_g / float(vecto["E_fcmap_pos [kWh]"]),
    }
    print(f"{controller} on {road.name} | VECTO's Long Haul cycle ({km:g} km), reference load")
    for name, ours in figures.items():
        print(f"  {name:32s} {ours:10.1f}   {vecto_figures[name]:10.1f}")
    print("  energy [kWh]")
    for name, ours in terms.items():
        theirs = f"{float(vecto[VSUM_TERMS[name]]):10.2f}" if name in VSUM_TERMS else " " * 10
        print(f"  {name:32s} {ours:10.2f}   {theirs}")
    print(f"  {'retarder losses':32s} {'-':>10s}   {float(vecto['E_ret_loss [kWh]']):10.2f}")


if __name__ == "__main__":
    main()

"""Drive a VECTO truck with a controller over a road and print where its energy went, term by term,
next to VECTO's own balance for the same truck on its Long Haul cycle (the ``.vsum`` row at the
reference load).

Usage: python scripts/vecto_energy.py [ROAD [CONTROLLER [TRUCK]]]
(default: ../shared/roads/eu_vecto_longhaul_100km.csv, ``vecto_cc``, and VECTO's generic group-5
tractor from its declaration XML at its reference load).

Three columns: the run at the configured set speed; the same run at the set speed that gives
VECTO's driving time (its trip time less its time standing: the CSV road has VECTO's grades but not
its stops and speed limits); VECTO's. The share of each difference that the speed explains is the
first column's difference from the second over its difference from VECTO's.

The run is traced every 5 m and the terms are summed over the trace: air drag ½ρ·CdA(v)·v²,
rolling m·g·c_r·cos α and gravity m·g·sin α per metre, the kinetic energy gained, the brakes'
energy (the run's own), the auxiliaries' power over time, the engine's positive work at the fuel
map (the auxiliaries' share included, idling in neutral too, as VECTO's E_fcmap_pos) and its
negative work at the clutch (as E_clutch_neg), and the gearbox's, the retarder's and the axle's
losses at each sample's engine speed and gearbox input torque. What the engine's work leaves after
all of them is printed as the residual (the trace's sampling, and in neutral the axle's and
retarder's drag).
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
    "kinetic energy gained": "E_inertia [kWh]",
    "brakes": "E_brake [kWh]",
    "gearbox and axle": "E_gbx_axl_loss [kWh]",
    "retarder": "E_ret_loss [kWh]",
    "auxiliaries": "E_aux_sum [kWh]",
    "engine work > 0": "E_fcmap_pos [kWh]",
    "clutch work < 0 (drag)": "E_clutch_neg [kWh]",
}
SPENT = ("air drag", "rolling", "gravity", "kinetic energy gained", "brakes", "gearbox and axle", "retarder")


def vsum_row(load_kg: float) -> dict[str, str]:
    """VECTO's summary row for the Long Haul cycle at ``load_kg``."""
    with (TRACTOR / "Class5_Tractor_DECL.vsum").open() as f:
        for row in csv.DictReader(f):
            if "LongHaul" in row["Cycle [-]"] and abs(float(row["Loading [kg]"]) - load_kg) < 1.0:
                return row
    raise SystemExit(f"no Long Haul row at {load_kg:g} kg in the .vsum")


def ledger(road_path: Path, controller: str, truck_path: Path, v_ref_kmh: float | None) -> tuple[dict, dict]:
    """The run's energy terms [kWh] and its figures (fuel, time, speed, g/kWh)."""
    overrides = ["trace_step_m=5"] + ([f"v_ref_kmh={v_ref_kmh}"] if v_ref_kmh is not None else [])
    config = load_run_config(truck_path, overrides=overrides)
    truck = config.truck
    assert truck is not None
    result = simulate(load_road(road_path), config, controller)
    t = result.trace
    s, v = np.asarray(t["distance_m"]), np.asarray(t["speed_kmh"]) / KMH_PER_MPS
    ds, dt = np.diff(s), np.diff(np.asarray(t["time_s"]))
    v_mid = 0.5 * (v[1:] + v[:-1])
    alpha = np.arctan(np.asarray(t["slope"])[:-1])
    mass, core, vehicle = truck.mass_kg, truck.core, config.core_vehicle
    air = sum(
        0.5 * truck.keys["air_density_kgpm3"] * core.at(u)["cda_m2"] * u * u * d for u, d in zip(v_mid, ds, strict=True)
    )
    work_pos = map_neg = clutch_neg = gearbox_axle = retarder = 0.0
    for u, pedal, gear, step in zip(v_mid, t["pedal"][:-1], t["gear"][:-1], dt, strict=True):
        if gear == 0:
            work_pos += truck.aux_power_w * step  # idling, driving the auxiliaries
            continue
        n_rpm = vehicle.engine_speed_rpm(u, int(gear))
        omega = n_rpm * math.pi / 30
        torque = vehicle.engine_torque_nm(u, pedal, int(gear))
        clutch_nm = torque - truck.aux_power_w / omega
        work_pos += max(torque * omega, 0.0) * step
        map_neg += min(torque * omega, 0.0) * step
        clutch_neg += min(clutch_nm * omega, 0.0) * step
        losses = core.driveline_point(n_rpm, clutch_nm, int(gear))
        gearbox_axle += (losses["gearbox_loss_w"] + losses["axle_loss_w"]) * step
        retarder += losses["retarder_loss_w"] * step
    summary = result.summary
    terms = {
        "air drag": air,
        "rolling": float(np.sum(mass * G_MPS2 * truck.rolling_resistance * np.cos(alpha) * ds)),
        "gravity": float(np.sum(mass * G_MPS2 * np.sin(alpha) * ds)),
        "kinetic energy gained": 0.5 * mass * (v[-1] ** 2 - v[0] ** 2),
        "brakes": summary["brake_energy_kj"] * 1e3,
        "gearbox and axle": gearbox_axle,
        "retarder": retarder,
        "auxiliaries": truck.aux_power_w * summary["time_s"],
        "engine work > 0": work_pos,
        "clutch work < 0 (drag)": clutch_neg,
    }
    terms["residual"] = work_pos + map_neg - terms["auxiliaries"] - sum(terms[k] for k in SPENT)
    figures = {
        "fuel [g/km]": summary["fuel_kg"] * 1e6 / summary["distance_m"],
        "driving time [s]": summary["time_s"],
        "mean speed [km/h]": summary["mean_speed_kmh"],
        "fuel per engine work > 0 [g/kWh]": summary["fuel_kg"] * 1e3 / (work_pos / J_PER_KWH),
    }
    return {k: val / J_PER_KWH for k, val in terms.items()}, figures


def matched_set_speed(road: Path, controller: str, truck_path: Path, time_s: float) -> float:
    """The set speed [km/h] at which the run takes ``time_s``, by bisection to 0.01 km/h."""
    lo, hi = 60.0, 90.0
    while hi - lo > 0.01:
        mid = 0.5 * (lo + hi)
        _, figures = ledger(road, controller, truck_path, mid)
        lo, hi = (mid, hi) if figures["driving time [s]"] > time_s else (lo, mid)
    return 0.5 * (lo + hi)


def main() -> None:
    road = Path(sys.argv[1]) if len(sys.argv) > 1 else SHARED / "roads" / "eu_vecto_longhaul_100km.csv"
    controller = sys.argv[2] if len(sys.argv) > 2 else "vecto_cc"
    truck_path = Path(sys.argv[3]) if len(sys.argv) > 3 else TRACTOR / "Class5_Tractor_DECL.xml"
    vecto = vsum_row(19300.0)
    km = float(vecto["distance [km]"])
    moving_s = float(vecto["time [s]"]) * (1 - float(vecto["StopTimeShare [%]"]) / 100)
    vecto_figures = {
        "fuel [g/km]": float(vecto["FC-Final [g/km]"]),
        "driving time [s]": moving_s,
        "mean speed [km/h]": km / (moving_s / 3600),
        "fuel per engine work > 0 [g/kWh]": float(vecto["FC-Final [g/km]"]) * km / float(vecto["E_fcmap_pos [kWh]"]),
    }
    terms, figures = ledger(road, controller, truck_path, None)
    v_match = matched_set_speed(road, controller, truck_path, moving_s)
    matched_terms, matched_figures = ledger(road, controller, truck_path, v_match)
    print(f"{controller} on {road.name} with {truck_path.name} | VECTO's Long Haul cycle ({km:g} km), reference load")
    print(f"  {'':34s} {'set speed':>10s} {f'{v_match:.2f} km/h':>12s} {'VECTO':>10s} {'speed explains':>15s}")
    for name, ours in figures.items():
        print(_row(name, ours, matched_figures[name], vecto_figures[name], 1))
    print("  energy [kWh]")
    for name, ours in terms.items():
        theirs = float(vecto[VSUM_TERMS[name]]) if name in VSUM_TERMS else math.nan
        print(_row(name, ours, matched_terms[name], theirs, 2))


def _row(name: str, ours: float, matched: float, vecto: float, digits: int) -> str:
    """A table row: the two runs, VECTO's, and the share of the difference the speed explains."""
    share = (ours - matched) / (ours - vecto) if math.isfinite(vecto) and abs(ours - vecto) > 1e-9 else math.nan
    vecto_text = f"{vecto:10.{digits}f}" if math.isfinite(vecto) else f"{'-':>10s}"
    share_text = f"{100 * share:14.0f}%" if math.isfinite(share) else f"{'':15s}"
    return f"  {name:34s} {ours:10.{digits}f} {matched:12.{digits}f} {vecto_text} {share_text}"


if __name__ == "__main__":
    main()

"""Print how closely truckmpc's model of a VECTO truck reproduces VECTO's second-by-second output.

Usage: python scripts/vecto_validation.py [JOB.xml|JOB.vecto [EXCERPT.vmod]]
(default: VECTO's generic group-5 tractor from its declaration XML, and its Long Haul excerpt, in
../shared/vehicles/).

For every row in gear it compares engine speed, the air-drag, rolling, slope and inertia powers,
the fuel map at VECTO's engine speed and torque, and the power the gearbox, the retarder and the
axle lose with VECTO's gearbox input (its speed and P_gbx_in); for the rows in neutral (a shift's
traction interruption), the axle's and the retarder's drag; for the rows at steady speed, the
engine torque and fuel rate the model needs to hold that speed on that grade in VECTO's gear.
Prints the worst relative error of each with its criterion.
"""

from __future__ import annotations

import csv
import math
import sys
from pathlib import Path

from truckmpc.units import KMH_PER_MPS
from truckmpc.vecto import load_vecto_truck

HERE = Path(__file__).resolve().parents[1] / ".." / "shared" / "vehicles" / "vecto-generic-class5-tractor"
LOADS = {
    "air drag power": ("air_w", "P_air [kW]", 0.01),
    "rolling power": ("rolling_w", "P_roll [kW]", 0.01),
    "slope power": ("slope_w", "P_slope [kW]", 0.01),
    "vehicle inertia power": ("vehicle_inertia_w", "P_veh_inertia [kW]", None),
}
STAGES = {
    "gearbox loss power": ("gearbox_loss_w", "P_gbx_loss [kW]"),
    "retarder loss power": ("retarder_loss_w", "P_ret_loss [kW]"),
    "axle loss power": ("axle_loss_w", "P_axle_loss [kW]"),
}
RAD_S_PER_RPM = 2 * math.pi / 60


def main() -> None:
    job = Path(sys.argv[1]) if len(sys.argv) > 1 else HERE / "Class5_Tractor_DECL.xml"
    vmod = Path(sys.argv[2]) if len(sys.argv) > 2 else HERE / "Class5_Tractor_DECL_LongHaulReferenceLoad.excerpt.vmod"
    truck = load_vecto_truck(job).core
    with vmod.open() as f:
        rows = [{k: float(v) if v else math.nan for k, v in r.items()} for r in csv.DictReader(f)]
    in_gear = [r for r in rows if r["Gear [-]"] > 0]
    neutral = [r for r in rows if r["Gear [-]"] == 0 and r["v_act [km/h]"] > 0]
    worst: dict[str, list[float]] = {}

    def note(name: str, ours: float, vecto: float) -> None:
        if abs(vecto) > 1e-6:
            worst.setdefault(name, []).append(ours / vecto - 1)

    for r in in_gear:
        v_mps, gear, slope = r["v_act [km/h]"] / KMH_PER_MPS, int(r["Gear [-]"]), math.atan(r["grad [%]"] / 100)
        note("engine speed", truck.at(v_mps, gear=gear)["engine_speed_rpm"], r["n_eng_avg [1/min]"])
        loads = truck.at(v_mps, r["acc [m/s^2]"], slope)
        for name, (key, column, _) in LOADS.items():
            note(name, loads[key] / 1e3, r[column])
        note(
            "fuel map at VECTO's speed and torque",
            truck.engine_point(r["n_eng_avg [1/min]"], r["T_eng_fcmap [Nm]"])["fuel_rate_g_per_h"],
            r["FC-Map [g/h]"],
        )
        gearbox_in_nm = r["P_gbx_in [kW]"] * 1e3 / (r["n_eng_avg [1/min]"] * RAD_S_PER_RPM)
        losses = truck.driveline_point(r["n_eng_avg [1/min]"], gearbox_in_nm, gear)
        for name, (key, column) in STAGES.items():
            note(name, losses[key] / 1e3, r[column])
        note(
            "driveline loss power, all stages",
            sum(losses[key] for key, _ in STAGES.values()) / 1e3,
            sum(r[column] for _, column in STAGES.values()),
        )
        if r["acc [m/s^2]"] == 0.0:
            op = truck.at(v_mps, 0.0, slope, gear)
            note("engine torque to hold a steady speed", op["engine_torque_nm"], r["T_eng_fcmap [Nm]"])
            note("fuel to hold a steady speed", op["fuel_rate_g_per_h"], r["FC-Map [g/h]"])
    for r in neutral:
        drag_w = truck.at(r["v_act [km/h]"] / KMH_PER_MPS)["neutral_drag_w"]
        note("drag in neutral (axle and retarder)", drag_w / 1e3, r["P_ret_loss [kW]"] + r["P_axle_loss [kW]"])
    criteria = {
        "engine speed": 0.005,
        "fuel map at VECTO's speed and torque": 0.01,
        "engine torque to hold a steady speed": 0.003,
        "fuel to hold a steady speed": 0.005,
    }
    criteria.update(dict.fromkeys([*STAGES, "drag in neutral (axle and retarder)"], 0.02))
    criteria.update({name: tol for name, (_, _, tol) in LOADS.items() if tol})
    print(f"{job.name} against {vmod.name}: {len(in_gear)} rows in gear")
    for name, errors in worst.items():
        top = max(errors, key=abs)
        goal = f"(criterion {100 * criteria[name]:g} %)" if name in criteria else ""
        print(f"  {name:38s} worst {100 * top:+.4f} % over {len(errors)} rows {goal}")


if __name__ == "__main__":
    main()

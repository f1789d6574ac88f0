"""Helpers of the VECTO-truck tests: a small VECTO job written from scratch (so the error tests do
not need the shared files), and where VECTO's generic tractor is."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
SHARED_TRACTOR = (
    Path(os.environ.get("TRUCKMPC_SHARED_VEHICLES", REPO / ".." / "shared" / "vehicles"))
    / "vecto-generic-class5-tractor"
)
TRACTOR_JOB = SHARED_TRACTOR / "Class5_Tractor_DECL.vecto"
needs_tractor = pytest.mark.skipif(
    not TRACTOR_JOB.is_file(), reason="VECTO's generic tractor (../shared/vehicles) not present"
)

AUX = [
    {
        "ID": "FAN",
        "Type": "Fan",
        "Technology": ["Belt driven or driven via transm. - Electronically controlled visco clutch"],
    },
    {"ID": "STP", "Type": "Steering pump", "Technology": ["Fixed displacement with elec. control"]},
    {"ID": "AC", "Type": "HVAC", "Technology": ["Default"]},
    {"ID": "ES", "Type": "Electric System", "Technology": ["Standard technology"]},
    {"ID": "PS", "Type": "Pneumatic System", "Technology": ["Medium Supply 2-stage + ESS + AMS"]},
]


def _json(path: Path, body: dict) -> None:
    path.write_text(json.dumps({"Header": {"FileVersion": 1}, "Body": body}, indent=2))


def write_job(folder: Path, loss_maps: bool = False) -> Path:
    """A complete small VECTO job in ``folder``: a 4x2 tractor, an engine whose fuel map is the plane
    fuel = 2·speed + 10·torque + 5000 [g/h] over 600–2000 rpm and −200–2000 Nm, a 3-speed gearbox.
    With ``loss_maps``, ``.vtlm`` loss maps for each gear and the axle with the law of the XML job
    of :mod:`vecto_xml` (loss = base + 2 % of |input torque|); without, the gearbox names an axle
    loss map that is not there. Returns the job's path. Line 2 of each CSV is its first row of numbers."""
    folder.mkdir(parents=True, exist_ok=True)
    fld = ["engine speed [1/min], full load torque [Nm], motoring torque [Nm]"]
    fld += [f"{n},{1800 + (n - 600) * 0.1:g},{-150 - (n - 600) * 0.02:g}" for n in range(600, 2001, 200)]
    (folder / "e.vfld").write_text("\n".join(fld) + "\n")
    vmap = ["engine speed [rpm],torque [Nm],fuel consumption [g/h]"]
    vmap += [f"{n},{t},{2 * n + 10 * t + 5000:g}" for n in range(600, 2001, 200) for t in range(-200, 2001, 200)]
    (folder / "e.vmap").write_text("\n".join(vmap) + "\n")
    _json(
        folder / "e.veng",
        {
            "ModelName": "test",
            "Displacement": "12000",
            "IdlingSpeed": 600.0,
            "Inertia": 4.0,
            "FullLoadCurve": "e.vfld",
            "FuelMap": "e.vmap",
        },
    )
    gears = [{"Ratio": 2.5, "LossMap": "axle.vtlm"}] + [{"Ratio": r, "LossMap": ""} for r in (4.0, 2.0, 1.0)]
    if loss_maps:
        from vecto_xml import AXLE_LOSS_BASE_NM, GEAR_LOSS_BASE_NM, LOSS_SPEEDS_RPM, LOSS_TORQUES_NM, loss_nm

        for name, base in [("axle.vtlm", AXLE_LOSS_BASE_NM)] + [
            (f"gear{k}.vtlm", b) for k, b in enumerate(GEAR_LOSS_BASE_NM, start=1)
        ]:
            rows = ["Input Speed [rpm],Input Torque [Nm],Torque Loss [Nm]"]
            rows += [f"{n},{t},{loss_nm(base, t):g}" for n in LOSS_SPEEDS_RPM for t in LOSS_TORQUES_NM]
            (folder / name).write_text("\n".join(rows) + "\n")
        for k, gear in enumerate(gears[1:], start=1):
            gear["LossMap"] = f"gear{k}.vtlm"
    _json(folder / "g.vgbx", {"ModelName": "g3", "GearboxType": "AMT", "TracInt": 1.0, "Gears": gears})
    axle = {"Inertia": 14.9, "Wheels": "315/70 R22.5", "RRCISO": 0.006, "FzISO": 33350.0}
    axles = [
        {**axle, "TwinTyres": False, "Type": "VehicleNonDriven"},
        {**axle, "TwinTyres": True, "Type": "VehicleDriven"},
    ]
    _json(
        folder / "v.vveh",
        {
            "VehCat": "Tractor",
            "CurbWeight": 8000.0,
            "MassMax": 18.0,
            "CdA": 5.5,
            "AxleConfig": {"Type": "4x2", "Axles": axles},
        },
    )
    job = folder / "t.vecto"
    _json(
        job,
        {"SavedInDeclMode": True, "VehicleFile": "v.vveh", "EngineFile": "e.veng", "GearboxFile": "g.vgbx", "Aux": AUX},
    )
    return job

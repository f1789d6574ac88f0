"""A truck from VECTO's files, checked against VECTO: its second-by-second output for the generic
tractor (engine speed, the road's loads, the fuel map, the fuel to hold a speed), VECTO's own
unit-test values for the cross-wind correction, and truths constructed by hand."""

from __future__ import annotations

import csv
import json
import math
from types import SimpleNamespace

import pytest

from truckmpc import _core
from truckmpc.vecto import load_vecto_truck
from truckmpc.vecto.declaration import combination_rolling_resistance, cross_wind_cda_curve
from truckmpc.vecto.truck import truck_values
from vecto_files import SHARED_TRACTOR, TRACTOR_JOB, needs_tractor, write_job

KMH_PER_MPS = 3.6


def excerpt_rows() -> list[dict[str, float]]:
    path = SHARED_TRACTOR / "Class5_Tractor_DECL_LongHaulReferenceLoad.excerpt.vmod"
    with path.open() as f:
        return [{k: float(v) if v else math.nan for k, v in row.items()} for row in csv.DictReader(f)]


def in_gear(rows: list[dict[str, float]]) -> list[dict[str, float]]:
    return [r for r in rows if r["Gear [-]"] > 0]


@needs_tractor
def test_engine_speed_road_loads_and_fuel_map_match_vecto_at_every_row_in_gear() -> None:
    truck = load_vecto_truck(TRACTOR_JOB).core
    rows = in_gear(excerpt_rows())
    assert len(rows) == 38
    for r in rows:
        v_mps, gear = r["v_act [km/h]"] / KMH_PER_MPS, int(r["Gear [-]"])
        # Issue 27 asks for 0.5 % (speed) and 1 % (powers, fuel map); the model is as VECTO's to the
        # excerpt's rounding, so the checks are tight enough to catch g = 9.81 or a trailer tyre's
        # RRC off by 1 %.
        assert truck.at(v_mps, gear=gear)["engine_speed_rpm"] == pytest.approx(r["n_eng_avg [1/min]"], rel=1e-5)
        loads = truck.at(v_mps, r["acc [m/s^2]"], math.atan(r["grad [%]"] / 100))
        for key, column in (("air_w", "P_air [kW]"), ("rolling_w", "P_roll [kW]"), ("slope_w", "P_slope [kW]")):
            assert loads[key] / 1e3 == pytest.approx(r[column], rel=2e-4), column
        fuel = truck.engine_point(r["n_eng_avg [1/min]"], r["T_eng_fcmap [Nm]"])["fuel_rate_g_per_h"]
        assert fuel == pytest.approx(r["FC-Map [g/h]"], rel=1e-5)


@needs_tractor
def test_driveline_losses_fitted_on_the_full_load_rows_give_the_steady_rows_fuel_within_2_percent() -> None:
    rows = in_gear(excerpt_rows())
    full = [r for r in rows if abs(r["P_eng_fcmap [kW]"] - r["P_eng_full [kW]"]) < 1e-3]
    steady = [r for r in rows if r["acc [m/s^2]"] == 0.0]
    assert len(full) == 35 and len(steady) == 2
    # Loss torque at the gearbox input (gearbox, retarder, axle) against the input torque: a line.
    pts = []
    for r in full:
        omega = r["n_eng_avg [1/min]"] * math.pi / 30
        loss_kw = r["P_gbx_loss [kW]"] + r["P_ret_loss [kW]"] + r["P_axle_loss [kW]"]
        pts.append((r["P_gbx_in [kW]"] * 1e3 / omega, loss_kw * 1e3 / omega))
    mx, my = (sum(p[i] for p in pts) / len(pts) for i in (0, 1))
    slope = sum((x - mx) * (y - my) for x, y in pts) / sum((x - mx) ** 2 for x, _ in pts)
    drag_nm = my - slope * mx
    keys = {"gear_efficiency": 1 - slope, "axle_efficiency": 1.0, "loss_torque_nm": drag_nm / (1 - slope)}
    # The defaults are this fit (rounded), so a VECTO truck without loss maps gets these losses.
    defaults = truck_values()
    assert defaults["gear_efficiency"] == pytest.approx(keys["gear_efficiency"], abs=1e-4)
    assert defaults["loss_torque_nm"] == pytest.approx(keys["loss_torque_nm"], rel=1e-3)
    truck = load_vecto_truck(TRACTOR_JOB, keys).core
    for r in steady:
        op = truck.at(r["v_act [km/h]"] / KMH_PER_MPS, 0.0, math.atan(r["grad [%]"] / 100), int(r["Gear [-]"]))
        assert op["feasible"]
        assert op["engine_speed_rpm"] == pytest.approx(r["n_eng_avg [1/min]"], rel=0.005)
        assert op["fuel_rate_g_per_h"] == pytest.approx(r["FC-Map [g/h]"], rel=0.02)


@needs_tractor
def test_the_generic_tractor_has_vectos_masses_and_auxiliary_power() -> None:
    truck = load_vecto_truck(TRACTOR_JOB)
    assert truck.mass_kg == 35029.0  # VECTO's summary: 15 729 kg before the 19 300 kg reference load
    assert truck.aux_power_w == pytest.approx(4443.3, abs=0.05)  # the excerpt's P_aux
    assert load_vecto_truck(TRACTOR_JOB, {"payload_kg": 0}).mass_kg == 15729.0


@pytest.mark.parametrize(
    ("method", "kmh", "height_m", "expected_m2", "tol"),
    [
        # VECTO's own unit tests (TractorSemitrailer, Cd·A 6.46 m²): today's method ...
        ("height_profile", 60, 4.0, 7.71712257, 1e-6),
        ("height_profile", 75, 3.75, 7.35129203, 1e-6),
        ("height_profile", 100, 4.0, 7.03986404, 1e-6),
        # ... and VECTO 3's, which has no height.
        ("vecto3", 60, 4.0, 8.12204, 1e-4),
        ("vecto3", 75, 4.0, 7.67058, 1e-4),
        ("vecto3", 100, 4.0, 7.23735, 1e-4),
    ],
)
def test_the_cross_wind_correction_gives_vectos_unit_test_values(method, kmh, height_m, expected_m2, tol) -> None:
    curve = dict(cross_wind_cda_curve(6.46, method, "TractorSemitrailer", height_m))
    assert curve[kmh / KMH_PER_MPS] == pytest.approx(expected_m2, abs=tol)


def test_a_tyre_loaded_at_its_test_load_rolls_with_its_own_coefficient() -> None:
    # One axle carrying everything, two tyres each at exactly F_z,ISO: the load correction is 1.
    mass_kg = 2 * 30_000.0 / 9.80665
    assert combination_rolling_resistance([(1.0, 0.006, 30_000.0, 2)], mass_kg) == pytest.approx(0.006, rel=1e-12)
    # At twice the load the coefficient falls by 2^(0.9-1).
    assert combination_rolling_resistance([(1.0, 0.006, 30_000.0, 2)], 2 * mass_kg) == pytest.approx(0.006 * 2**-0.1)


def test_a_written_job_reads_back_its_plane_fuel_map_and_its_masses(tmp_path) -> None:
    truck = load_vecto_truck(write_job(tmp_path), {"payload_kg": 10_000})
    assert truck.mass_kg == 8000 + 7500 + 10_000
    for n, t in [(700.0, 100.0), (1234.0, 1555.0), (1999.0, -150.0)]:
        assert truck.core.engine_point(n, t)["fuel_rate_g_per_h"] == pytest.approx(2 * n + 10 * t + 5000, rel=1e-9)
    assert truck.core.facts["gears"] == 3


@needs_tractor
def test_model_stationary_gives_vectos_steady_fuel_rate_in_vectos_gear() -> None:
    from typer.testing import CliRunner

    from truckmpc.cli import app

    row = next(r for r in in_gear(excerpt_rows()) if r["acc [m/s^2]"] == 0.0)
    args = ["model", "stationary", "--vehicle", str(TRACTOR_JOB), "--speed-kmh", "85", "--gear", "11", "--json"]
    result = CliRunner().invoke(app, [*args, "--slope-pct", str(row["grad [%]"])])
    assert result.exit_code == 0, result.output
    doc = json.loads(result.stdout)
    assert doc["engine_speed_rpm"] == pytest.approx(row["n_eng_avg [1/min]"], rel=0.005)
    assert doc["fuel_rate_g_per_h"] == pytest.approx(row["FC-Map [g/h]"], rel=0.02)
    assert doc["feasible"] and doc["brake_power_w"] == 0.0


def test_on_a_steep_descent_the_written_truck_cuts_fuel_and_brakes(tmp_path) -> None:
    from truckmpc.stationary import map_truck_stationary_point

    truck = load_vecto_truck(write_job(tmp_path))
    down = map_truck_stationary_point(truck, 80.0, -6.0)
    assert down["fuel_rate_g_per_h"] == 0.0 and down["brake_power_w"] > 0.0
    drag_nm = truck.core.engine_point(down["engine_speed_rpm"], 0.0)["drag_torque_nm"]
    assert down["engine_torque_nm"] == pytest.approx(drag_nm)
    up = map_truck_stationary_point(truck, 80.0, 1.0)
    assert up["feasible"] and up["brake_power_w"] == 0.0 and up["gear"] == 3
    # Its fuel is the plane's at its operating point (the map is that plane).
    n, t = up["engine_speed_rpm"], up["engine_torque_nm"]
    assert up["fuel_rate_g_per_h"] == pytest.approx(2 * n + 10 * t + 5000, rel=1e-9)


@needs_tractor
def test_a_speed_the_truck_cannot_hold_gives_no_fuel_rate_but_says_why() -> None:
    from truckmpc.stationary import map_truck_stationary_point

    truck = load_vecto_truck(TRACTOR_JOB)
    over = map_truck_stationary_point(truck, 85.0, 0.0, gear=1)
    assert over["fuel_rate_g_per_h"] is None and "outside its full-load curve" in over["not_feasible"]
    steep = map_truck_stationary_point(truck, 85.0, 8.0)
    assert steep["fuel_rate_g_per_h"] is None and "Nm needed" in steep["not_feasible"]
    # A descent VECTO's tractor brakes on: no fuel; the brakes take power at the wheels.
    down = map_truck_stationary_point(truck, 80.0, -3.0)
    assert down["feasible"] and down["fuel_rate_g_per_h"] == 0.0 and down["brake_power_w"] > 50e3


def test_a_part_of_the_wrong_type_or_missing_an_attribute_is_named() -> None:
    """The binding reads a truck's parts off attributes: a value of the wrong type is a TypeError
    naming the part's field, a missing attribute an AttributeError naming it."""
    engine = {"idle_speed_rpm": 600.0, "inertia_kgm2": 4.0, "full_load": [], "fuel_map": []}
    with pytest.raises(TypeError, match=r"failed to extract field EngineData\.idle_speed_rpm"):
        _core.MapTruck(SimpleNamespace(**{**engine, "idle_speed_rpm": "600"}), None, None)  # type: ignore[arg-type]
    del engine["fuel_map"]
    with pytest.raises(AttributeError, match="fuel_map"):
        _core.MapTruck(SimpleNamespace(**engine), None, None)  # type: ignore[arg-type]


@needs_tractor
def test_the_xmls_gearbox_retarder_and_axle_lose_what_vecto_charges_at_every_row_in_gear() -> None:
    """At VECTO's gearbox input (its speed and P_gbx_in) each stage of the declaration XML's
    driveline loses VECTO's power within 0.2 % (issue 46 asks for 2 %; the maps are VECTO's, so
    the check is tighter), and on the steady rows the engine torque and fuel to hold the speed are
    VECTO's within 0.3 % and 0.5 %."""
    truck = load_vecto_truck(SHARED_TRACTOR / "Class5_Tractor_DECL.xml").core
    stages = {
        "gearbox_loss_w": "P_gbx_loss [kW]",
        "retarder_loss_w": "P_ret_loss [kW]",
        "axle_loss_w": "P_axle_loss [kW]",
    }
    for r in in_gear(excerpt_rows()):
        n_rpm = r["n_eng_avg [1/min]"]
        losses = truck.driveline_point(n_rpm, r["P_gbx_in [kW]"] * 1e3 / (n_rpm * math.pi / 30), int(r["Gear [-]"]))
        for key, column in stages.items():
            assert losses[key] / 1e3 == pytest.approx(r[column], rel=2e-3), column
    for r in (r for r in in_gear(excerpt_rows()) if r["acc [m/s^2]"] == 0.0):
        op = truck.at(r["v_act [km/h]"] / KMH_PER_MPS, 0.0, math.atan(r["grad [%]"] / 100), int(r["Gear [-]"]))
        assert op["engine_torque_nm"] == pytest.approx(r["T_eng_fcmap [Nm]"], rel=3e-3)
        assert op["fuel_rate_g_per_h"] == pytest.approx(r["FC-Map [g/h]"], rel=5e-3)


@needs_tractor
def test_in_neutral_the_axle_and_the_retarder_drag_as_vectos_do() -> None:
    """VECTO's excerpt has two rows in neutral (a shift's traction interruption): its disengaged
    gearbox passes no torque, and the wheels still turn the axle and the output retarder."""
    truck = load_vecto_truck(SHARED_TRACTOR / "Class5_Tractor_DECL.xml").core
    neutral = [r for r in excerpt_rows() if r["Gear [-]"] == 0]
    assert len(neutral) == 2
    for r in neutral:
        drag_kw = truck.at(r["v_act [km/h]"] / KMH_PER_MPS)["neutral_drag_w"] / 1e3
        assert drag_kw == pytest.approx(r["P_ret_loss [kW]"] + r["P_axle_loss [kW]"], rel=0.02)
    # The .vecto job, without its loss map files, has no such drag.
    assert load_vecto_truck(TRACTOR_JOB).core.at(23.0)["neutral_drag_w"] == 0.0

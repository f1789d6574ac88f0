"""VECTO's generic battery-electric tractor driven: its machines and battery as VECTO's method makes
them of the declaration (points worked by hand from the file's own rows), declaration mode's usable
window and start, and runs of every controller reporting battery energy, not fuel."""

from __future__ import annotations

import importlib.util
import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from typer.testing import CliRunner

from truckmpc import _core
from truckmpc.cli import app
from truckmpc.stationary import electric_stationary_point
from truckmpc.vecto.electric import ElectricTruckJob
from truckmpc.vecto.electric_truck import load_electric_truck
from truckmpc.vecto.truck import truck_values
from truckmpc.vecto.xml_file import read_declaration_xml
from vecto_files import SHARED_TRACTOR

BEV_XML = SHARED_TRACTOR.parent / "vecto-generic-class5-bev" / "Group5_PEV_E4.xml"
needs_bev = pytest.mark.skipif(not BEV_XML.is_file(), reason="VECTO's generic electric tractor (../shared) not present")
runner = CliRunner()
RAD_S_PER_RPM = math.pi / 30.0


def _job() -> ElectricTruckJob:
    job = read_declaration_xml(BEV_XML)
    assert isinstance(job, ElectricTruckJob)
    return job


def _truck(**keys: object) -> _core.MapTruck:
    return load_electric_truck(_job(), truck_values(keys)).core


@needs_bev
def test_a_measured_point_of_the_map_is_reproduced_for_both_machines() -> None:
    """VECTO's `ElectricMotorMapReader.Create` scales torque and power by `Count`, and its
    `EfficiencyMapNew.LookupElectricPower` is exact at a measured point: the file's last row, one
    machine at 8276.06 rpm and 750 Nm drawing 739.46 kW, is 1500 Nm drawing 1478.92 kW for two."""
    point = _truck().machine_point(8276.06, 1500.0)
    assert point["electric_power_w"] == pytest.approx(2 * 739_460.0, rel=1e-9)
    assert point["loss_w"] == pytest.approx(2 * 739_460.0 - 1500.0 * 8276.06 * RAD_S_PER_RPM, rel=1e-9)


@needs_bev
def test_between_two_measured_points_the_loss_torque_is_interpolated_linearly() -> None:
    """Halfway along a grid edge of the map (2069.01 rpm, 300 and 337.5 Nm per machine) VECTO's
    Delaunay lookup interpolates the loss torque (P_el/ω − T) linearly, whatever diagonal the cells
    take: worked by hand from the file's two rows."""
    level = _job().machine.voltage_levels[0]
    rows = {(n, t): p for n, t, p in level.power_map}
    n = 2069.01
    omega = n * RAD_S_PER_RPM
    loss_torque = [rows[(n, t)] / omega - t for t in (300.0, 337.5)]
    expected_w = 2 * omega * (318.75 + 0.5 * sum(loss_torque))
    assert _truck().machine_point(n, 2 * 318.75)["electric_power_w"] == pytest.approx(expected_w, rel=1e-9)


@needs_bev
def test_torque_limits_drag_and_the_battery_follow_the_file_and_declaration_mode() -> None:
    """Limits and drag ×2 (`ElectricMotorFullLoadCurveReader`, `DragCurveReader` scaled by the
    count); the usable window 8-92 % narrowed by 5 % of its width for ageing and the run started in
    its middle (VECTO's `CreateBatteryData`); the current solving P = U·I − R·I² at 40 mΩ."""
    truck = _truck()
    at_low = truck.machine_point(1000.0, 0.0)
    assert (at_low["max_drive_nm"], at_low["max_brake_nm"]) == (1500.0, -1500.0)
    # The drag curve's row at 2069.01 rpm: -6.5 Nm per machine.
    assert truck.machine_point(2069.01, 0.0)["drag_nm"] == pytest.approx(-13.0)
    facts = truck.electric_facts
    assert facts["usable_window_pct"] == pytest.approx([10.1, 89.9])
    assert facts["soc_start_pct"] == pytest.approx(50.0)
    assert facts["battery_ocv_v"] == pytest.approx(778.61)  # the file's OCV at 50 %
    u, r, p = 778.61, 0.040, 200_000.0
    current = (u - math.sqrt(u * u - 4 * r * p)) / (2 * r)
    point = truck.machine_point(4000.0, p / (4000.0 * RAD_S_PER_RPM))
    assert point["battery_current_a"] == pytest.approx(current * point["electric_power_w"] / p, rel=0.05)
    assert point["battery_internal_w"] == pytest.approx(u * point["battery_current_a"], rel=1e-12)
    assert _truck(soc_start_pct=30.0).electric_facts["battery_ocv_v"] == pytest.approx(771.85)


@needs_bev
def test_every_controller_drives_it_and_reports_battery_energy_not_fuel(tmp_path: Path) -> None:
    out = tmp_path / "o"
    args = ["simulate", "--vehicle", str(BEV_XML), "--controller", "pi,vecto_cc,pcc,mpc", "--out", str(out)]
    result = runner.invoke(app, args)
    assert result.exit_code == 0, result.output
    assert "battery energy [kWh]" in result.output and "fuel [kg]" not in result.output
    doc = json.loads((out / "summary.json").read_text())
    for name in ("pi", "vecto_cc", "pcc", "mpc"):
        run = doc[name]
        assert "fuel_kg" not in run and not run["stalled"], name
        # A 37 t tractor at 85 km/h on the test track: between 90 and 180 kWh per 100 km.
        assert 90.0 < run["energy_kwh_per_100km"] < 180.0, (name, run["energy_kwh_per_100km"])
        used_pct = run["soc_start_pct"] - run["soc_end_pct"]
        # The state of charge falls by the energy over what the battery holds at its held voltage.
        assert used_pct == pytest.approx(100 * run["energy_kwh"] / (1555.5 * 778.61 / 1000), rel=1e-9)
    assert doc["mpc"]["energy_kwh"] < doc["pi"]["energy_kwh"]
    # The comparisons are of battery energy, under keys named for it.
    against_pcc = next(c for c in doc["comparisons"] if (c["controller"], c["baseline"]) == ("mpc", "pcc"))
    assert "delta_fuel_pct" not in against_pcc and "saved_kg" not in against_pcc
    raw = 100 * (doc["mpc"]["energy_kwh"] - doc["pcc"]["energy_kwh"]) / doc["pcc"]["energy_kwh"]
    assert against_pcc["delta_energy_pct"] == pytest.approx(raw, rel=1e-9)
    re_run = doc["equal_time_mpc_vs_pcc"]
    own, base = doc["mpc"]["energy_corrected_kwh"], re_run["pcc_energy_corrected_kwh"]
    assert against_pcc["headline_pct"] == pytest.approx(100 * (own - base) / base, rel=1e-9)
    assert against_pcc["saved_kwh"] == pytest.approx(base - own, rel=1e-9)
    assert "Δenergy at equal trip time and end speed vs PCC [%]" in result.output


@needs_bev
def test_a_trip_the_battery_cannot_finish_ends_where_the_usable_charge_ends(tmp_path: Path) -> None:
    out = tmp_path / "o"
    args = ["simulate", "--vehicle", str(BEV_XML), "--controller", "pi", "--set", "soc_start_pct=10.2", "--out"]
    result = runner.invoke(app, [*args, str(out)])
    assert result.exit_code == 0, result.output
    run = json.loads((out / "summary.json").read_text())["pi"]
    assert run["stalled"] and run["battery_empty"] and run["soc_end_pct"] == pytest.approx(10.1, abs=0.01)
    # The table gives no figure for the trip, only the line naming where it ended.
    assert "battery energy" not in result.output and "trip time" not in result.output, result.output
    assert "pi: battery empty at km " in result.output
    assert run["message"].startswith("battery empty at km ")
    # 0.1 % of 1211 kWh is 1.2 kWh: under 1 km of the 8.5 km track at about 1.4 kWh/km.
    assert 0.5e3 < run["stall_distance_m"] < 1.2e3, run["stall_distance_m"]
    refused = runner.invoke(app, [*args[:-2], "--set", "soc_start_pct=5", "--out", str(tmp_path / "p")])
    assert refused.exit_code == 2 and "soc_start_pct" in refused.output, refused.output
    assert len(refused.output.strip().splitlines()) == 1, refused.output


VECTO_108 = BEV_XML.parents[2] / "roads" / "eu_vecto_longhaul_2015_108km.csv"


@pytest.mark.slow
@needs_bev
def test_the_whole_road_plan_knows_what_braking_returns(tmp_path: Path) -> None:
    """On VECTO's 108 km long-haul road the optimum's plan, driven on the DP's own stage model, uses
    within 0.1 % of the battery energy the plant draws: its brake arcs charge the energy braking
    returns (without it the plan was 8 % off), its coasting arcs the auxiliaries'."""
    out = tmp_path / "o"
    args = ["simulate", "--vehicle", str(BEV_XML), "--road", str(VECTO_108), "--controller", "optimal", "--out"]
    result = runner.invoke(app, [*args, str(out)])
    assert result.exit_code == 0, result.output
    run = json.loads((out / "summary.json").read_text())["optimal"]
    assert run["recovered_kwh"] > 0.05 * run["energy_kwh"]
    assert run["plan_energy_kwh"] == pytest.approx(run["energy_kwh"], rel=1e-3)
    assert "plan_fuel_kg" not in run


@needs_bev
def test_the_optimum_pulses_and_glides_and_its_plan_predicts_the_plant(tmp_path: Path) -> None:
    """On the test track the optimum pulses and glides: the machines run far better near half their
    torque than at the 100 kW a steady 85 km/h takes. With its glide arc (an exact arc at the pedal
    where the machines draw no electric power) the plant uses what the plan predicts to 0.1 %.
    Without it (`glide_arcs=false`) the glides are the pedals that land on grid speeds, and the
    optimum is flat and coarse: from the plant's speeds between the grid's the closed loop times its
    pulses otherwise than the plan (1.2 % less energy for 2.4 s more and a 1 km/h lower end speed);
    only brought to the plan's trip time (at β) and end speed is it within 0.1 % of the plan."""
    runs = {}
    for name, extra in (("glides", []), ("grid", ["--set", "glide_arcs=false"])):
        out = tmp_path / name
        args = ["simulate", "--vehicle", str(BEV_XML), "--controller", "optimal", *extra, "--out", str(out)]
        result = runner.invoke(app, args)
        assert result.exit_code == 0, result.output
        runs[name] = json.loads((out / "summary.json").read_text())["optimal"]
        pedal = np.loadtxt(out / "trace-optimal.csv", delimiter=",", skiprows=1, usecols=4)
        assert np.mean(pedal > 0.5) > 0.2 and np.mean((pedal > 0) & (pedal < 0.06)) > 0.3, name
        assert runs[name]["plan_gap_pct"] < 0.1, name
    glides, grid = runs["glides"], runs["grid"]
    assert glides["settings"]["glide_arcs"] and not grid["settings"]["glide_arcs"]
    assert glides["energy_kwh"] == pytest.approx(glides["plan_energy_kwh"], rel=1e-3)
    assert abs(grid["energy_kwh"] / grid["plan_energy_kwh"] - 1) > 5e-3


@needs_bev
def test_holding_a_speed_on_a_grade_the_wheels_get_the_road_load_and_the_battery_its_losses_more() -> None:
    """`model stationary`: at 80 km/h on 1 % the machines give the wheels the road load worked by
    hand from the declared combination (mass, rolling resistance, drag area at the speed, VECTO's air
    density), and the battery gives that plus the losses; downhill at -4 % the brake is the machines',
    who return energy."""
    truck = load_electric_truck(_job(), truck_values())
    v = 80 / 3.6
    for slope_pct in (1.0, -4.0):
        alpha = math.atan(slope_pct / 100)
        cda = float(np.interp(v, *zip(*truck.cda_curve, strict=True)))
        load_n = truck.mass_kg * 9.80665 * (math.sin(alpha) + truck.rolling_resistance * math.cos(alpha))
        load_n += 0.5 * 1.188 * cda * v * v
        state = electric_stationary_point(truck, 80.0, slope_pct, 80_000.0)
        assert state["feasible"]
        assert state["wheel_power_w"] - state["friction_brake_power_w"] == pytest.approx(load_n * v, rel=1e-6)
        losses = sum(state[k] for k in ("machine_loss_w", "reduction_loss_w", "battery_loss_w", "aux_power_w"))
        assert state["battery_power_w"] == pytest.approx(state["wheel_power_w"] + losses, rel=1e-9)
    assert state["brake"] > 0.0 and state["battery_power_w"] < 0.0 and state["friction_brake_power_w"] == 0.0


def _energy_script() -> Any:
    path = Path(__file__).resolve().parents[1] / "scripts" / "electric_energy.py"
    spec = importlib.util.spec_from_file_location("electric_energy", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.slow
@needs_bev
@pytest.mark.parametrize("controller", ["pi", "pcc", "mpc"])
def test_the_battery_energy_balances_on_vecto_108_km(controller: str) -> None:
    """scripts/electric_energy.py: the net battery energy equals air drag, rolling resistance, the
    machines', reduction's and battery's losses, the auxiliaries, the friction brakes and the change
    of kinetic and potential energy, each summed independently of the plant over a 1 m trace, to
    0.1 % of the battery energy."""
    terms = _energy_script().energy_balance(VECTO_108, controller)
    assert abs(terms["residual_pct"]) < 0.1, terms
    assert terms["machine_loss_w"] > 0.1 * terms["drawn"] and terms["air_drag"] > 0.3 * terms["drawn"]


@needs_bev
def test_beta_is_given_in_the_unit_of_the_trucks_store(tmp_path: Path) -> None:
    """β is battery energy per second for a battery-electric truck (`beta_j_per_s`), fuel per second
    for a diesel one (`beta_g_per_s`): each key is refused in one line on the other kind of truck.
    A β of twice the derived one buys time: the MPC drives faster and draws more."""
    runs = {}
    for name, extra in (("derived", []), ("double", ["--set", "beta_j_per_s=204619"])):
        out = tmp_path / name
        result = runner.invoke(
            app, ["simulate", "--vehicle", str(BEV_XML), "--controller", "mpc", *extra, "--out", str(out)]
        )
        assert result.exit_code == 0, result.output
        runs[name] = json.loads((out / "summary.json").read_text())["mpc"]
    derived = runs["derived"]["settings"]["beta_j_per_s"]
    assert 0.9e5 < derived < 1.2e5 and runs["derived"]["settings"]["beta_g_per_s"] is None
    assert runs["double"]["time_s"] < runs["derived"]["time_s"]
    assert runs["double"]["energy_kwh"] > runs["derived"]["energy_kwh"]
    for args, key in (
        ([f"--vehicle={BEV_XML}", "--set", "beta_g_per_s=5"], "beta_g_per_s"),
        (["--set", "beta_j_per_s=1e5"], "beta_j_per_s"),
    ):
        refused = runner.invoke(app, ["simulate", *args, "--controller", "pi", "--out", str(tmp_path / "r")])
        assert refused.exit_code == 2 and key in refused.output, refused.output
        assert len(refused.output.strip().splitlines()) == 1, refused.output


@needs_bev
def test_the_convergence_check_moves_battery_energy_under_keys_named_for_it(tmp_path: Path) -> None:
    """`--check-convergence` with the electric truck: the MPC again at δ/2 and S/2, its moves of
    Δenergy, Δtime, Δenergy at equal trip time and energy + β·time, none named for fuel."""
    out = tmp_path / "c"
    args = ["simulate", "--vehicle", str(BEV_XML), "--controller", "pi,mpc", "--check-convergence", "--out"]
    result = runner.invoke(app, [*args, str(out)])
    assert result.exit_code == 0, result.output
    doc = json.loads((out / "summary.json").read_text())["convergence"]
    for half in ("half_delta", "half_stage"):
        for name in ("energy", "time", "energy_equal_time", "headline", "cost"):
            assert isinstance(doc[f"delta_{name}_pct_{half}"], float), (name, half, doc)
        assert doc[half]["energy_kwh"] > 0 and "fuel_kg" not in doc[half]
    assert not any("fuel" in key for key in doc), doc
    assert "Δenergy at equal trip time vs PI δ/2 [pts]" in result.output
    assert "energy + β·time vs PI S/2 [pts]" in result.output


def test_the_cost_move_of_a_battery_is_in_joules_worked_by_hand() -> None:
    """From a run at 9.0 kWh (end speed corrected) and 100 s to a half at 9.1 kWh and 99 s with
    β = 100 kJ/s: 0.1 kWh = 360 kJ less 100 kJ for the second saved, over the PI's 10 kWh (36 MJ):
    +0.7222 %."""
    from truckmpc.convergence import cost_move_pct

    base = {"energy_kwh": 10.0, "energy_corrected_kwh": 10.0, "time_s": 95.0}
    run = {"energy_kwh": 9.0, "energy_corrected_kwh": 9.0, "time_s": 100.0}
    half = {"energy_kwh": 9.1, "energy_corrected_kwh": 9.1, "time_s": 99.0}
    assert cost_move_pct(base, run, half, 1e5) == pytest.approx(100 * 260e3 / 36e6, rel=1e-12)


@needs_bev
def test_the_plot_title_and_the_report_quote_battery_energy(tmp_path: Path) -> None:
    """The figures' title and the report's lead read the comparisons under their energy keys."""
    from truckmpc.plot.run_title import run_title
    from truckmpc.report.run_page import comparison_headline

    out = tmp_path / "o"
    result = runner.invoke(app, ["simulate", "--vehicle", str(BEV_XML), "--controller", "pcc,mpc", "--out", str(out)])
    assert result.exit_code == 0, result.output
    doc = json.loads((out / "summary.json").read_text())
    title = run_title(doc, ["pcc", "mpc"])
    assert "Δenergy at equal trip time" in title and "no Δ recorded" not in title, title
    against_pcc = next(c for c in doc["comparisons"] if (c["controller"], c["baseline"]) == ("mpc", "pcc"))
    pct, saved_kwh = comparison_headline(doc, against_pcc) or (None, None)
    assert pct == pytest.approx(against_pcc["headline_pct"]) and saved_kwh == pytest.approx(against_pcc["saved_kwh"])

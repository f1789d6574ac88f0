"""The outputs' declaration (:mod:`truckmpc.schema`, declared in the core): it covers exactly the
figures each controller's run gives and the trace's columns in CSV order; a road driven as legs
joins the legs' figures as figured by hand; the sweep's columns and the reference page follow it."""

from __future__ import annotations

import importlib.util
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from truckmpc.config import load_run_config
from truckmpc.legs import merge_legs
from truckmpc.results.files import trace_csv
from truckmpc.roads import RoadProfile, Stop, make_section
from truckmpc.roads.stops import leg_bounds
from truckmpc.schema import SUMMARY, SUMMARY_SPECS, TRACE_COLUMNS, TRACE_SPECS, OutputSpec
from truckmpc.sim import RunResult, simulate
from truckmpc.sweep.columns import MPC_FIELDS, PCC_FIELDS, PI_FIELDS

CARRIED = {
    "pi": {"every"},
    "vecto_cc": {"every"},
    "pcc": {"every", "pcc"},
    "mpc": {"every", "dp"},
    "optimal": {"every", "dp", "optimal"},
}
"""Which declared groups of figures each controller's run carries (the PCC reports its rules, the
DP controllers their solves, the whole-road optimum its plan)."""


BATTERY_ONLY = {"energy_kwh", "energy_kwh_per_100km", "energy_corrected_kwh", "plan_energy_kwh"}
"""A battery-electric truck's figures; its runs carry them in place of the fuel's."""
FUEL_ONLY = {"fuel_kg", "fuel_kg_per_100km", "fuel_corrected_kg", "plan_fuel_kg"}


def declared(controller: str, legs: bool = False, electric: bool = False) -> set[str]:
    runs = CARRIED[controller] | ({"legs"} if legs else set()) | ({"electric"} if electric else set())
    names = {spec.name for spec in SUMMARY_SPECS if spec.runs in runs}
    return names - (FUEL_ONLY if electric else BATTERY_ONLY)


def declared_columns(electric: bool = False) -> list[str]:
    runs = {"every", "electric"} if electric else {"every"}
    return [spec.name for spec in TRACE_SPECS if spec.runs in runs and not (electric and spec.name == "fuel_g")]


@pytest.fixture(scope="module")
def config():
    return load_run_config()


@pytest.mark.parametrize("controller", list(CARRIED))
def test_a_run_gives_exactly_the_declared_figures_and_columns(config, controller: str) -> None:
    result = simulate(make_section("hill", 1500, 2.0), config, controller)
    assert set(result.summary) == declared(controller)
    assert list(result.trace) == declared_columns()
    assert trace_csv(result).splitlines()[0] == ",".join(declared_columns())


def test_a_road_with_a_stop_gives_the_legs_figures_too(config) -> None:
    road = RoadProfile("stop", [0, 1000, 2000], [0, 5, 5], target_speed_kmh=[70] * 3, stops=(Stop(1000.0, 30.0),))
    assert set(simulate(road, config, "pcc").summary) == declared("pcc", legs=True)


def test_a_spec_reads_as_the_core_declares_it() -> None:
    """Two entries of sim/schema.rs, every field: a recomputed summary figure and a trace column."""
    figure = OutputSpec(
        name="fuel_kg_per_100km",
        unit="kg/100km",
        label="fuel per 100 km",
        doc="Fuel per 100 km driven; null when the truck did not move.",
        kind="number",
        runs="every",
        source="core",
        merge="per_100km",
        merge_of="fuel_kg",
        sweep="",
        decimals=None,
    )
    assert SUMMARY["fuel_kg_per_100km"] == figure
    doc = "Gear engaged, 0 = neutral."
    gear = OutputSpec("gear", "-", "gear", doc, "count", "every", "core", "joined", None, "", None)
    assert TRACE_SPECS[TRACE_COLUMNS.index("gear")] == gear
    assert SUMMARY["fuel_corrected_kg"].source == "python" and TRACE_SPECS[2].decimals == 5


def test_the_trace_columns_are_the_csv_files_columns_in_order() -> None:
    expected = "distance_m time_s speed_kmh gear pedal brake engine_speed_rpm slope altitude_m fuel_g brake_energy_kj"
    battery = "battery_energy_kwh soc_pct battery_power_kw machine_torque_nm"
    assert tuple(expected.split()) == TRACE_COLUMNS
    assert [spec.name for spec in TRACE_SPECS] == [*expected.split(), *battery.split()]
    continued = [spec.name for spec in TRACE_SPECS if spec.merge == "continued"]
    assert continued == ["time_s", "fuel_g", "brake_energy_kj", "battery_energy_kwh"]


def test_the_sweeps_figure_columns_keep_their_order() -> None:
    """sweep.csv's columns are what an unfinished sweep resumes by: the declaration's order must
    keep them as earlier versions wrote them."""
    pi = [
        "fuel_kg",
        "fuel_corrected_kg",
        "time_s",
        "end_speed_kmh",
        "brake_energy_kj",
        "gear_shifts",
        "gear_shifts_per_100km",
        "neutral_engagements",
        "neutral_engagements_per_100km",
        "stalled",
    ]
    equal_time = ["equal_time_pi_v_ref_kmh", "equal_time_pi_fuel_kg", "equal_time_pi_fuel_corrected_kg"]
    solver = ["realtime_ratio", "solve_ms_mean", "solve_ms_max", "infeasible_solves", "transitions_per_solve"]
    assert list(PI_FIELDS) == pi
    assert list(PCC_FIELDS) == [*pi, "neutral_distance_m", *equal_time]
    assert list(MPC_FIELDS) == [*pi, "neutral_distance_m", *solver, *equal_time]


def leg(**figures: Any) -> RunResult:
    summary = {
        "distance_m": 1000.0,
        "fuel_kg": 0.3,
        "fuel_corrected_kg": 0.31,
        "time_s": 50.0,
        "start_speed_kmh": 70.0,
        "end_speed_kmh": 72.0,
        "gear_shifts": 2,
        "neutral_engagements": 1,
        "eco_roll_entries": 1,
        "stalled": False,
        "stall_distance_m": None,
        "message": None,
        "compute_time_s": 0.5,
        "plant_dt_s": 0.05,
        **figures,
    }
    trace = {name: np.zeros(2) for name in TRACE_COLUMNS}
    return RunResult("pcc", "leg", summary, trace)


def two_legs(one: RunResult, two: RunResult) -> dict[str, Any]:
    road = RoadProfile("two", [0, 1000, 4000], [0, 0, 0], target_speed_kmh=[70] * 3, stops=(Stop(1000.0, 20.0),))
    return merge_legs(road, [one, two], leg_bounds(road)).summary


def test_legs_add_up_and_per_distance_figures_are_weighed_by_each_legs_distance() -> None:
    one = leg(fuel_kg_per_100km=30.0, gear_shifts_per_100km=200.0)
    two = leg(
        distance_m=3000.0,
        fuel_kg=0.6,
        fuel_corrected_kg=0.62,
        time_s=100.0,
        gear_shifts=1,
        end_speed_kmh=80.0,
        start_speed_kmh=75.0,
        fuel_kg_per_100km=20.0,
        gear_shifts_per_100km=1 / 0.03,
    )
    summary = two_legs(one, two)
    assert summary["fuel_kg"] == pytest.approx(0.9)
    assert summary["fuel_corrected_kg"] == pytest.approx(0.93)
    assert summary["distance_m"] == 4000.0 and summary["time_s"] == 150.0 and summary["gear_shifts"] == 3
    # A figure per 100 km of the road is the legs' figures weighed by their distances.
    assert summary["fuel_kg_per_100km"] == pytest.approx((30.0 * 1000 + 20.0 * 3000) / 4000)
    assert summary["gear_shifts_per_100km"] == pytest.approx((200.0 * 1000 + 100 / 3 * 3000) / 4000)
    assert summary["eco_roll_entries_per_100km"] == pytest.approx(2 / 0.04)
    # The mean speed is the legs' mean speeds weighed by their times.
    mean_kmh = (1000 / 50 * 3.6 * 50 + 3000 / 100 * 3.6 * 100) / 150
    assert summary["mean_speed_kmh"] == pytest.approx(mean_kmh)
    assert summary["realtime_ratio"] == pytest.approx(1.0 / 150)
    assert (summary["start_speed_kmh"], summary["end_speed_kmh"]) == (70.0, 80.0)
    assert summary["stalled"] is False


def test_a_stalled_leg_stalls_the_road_and_leaves_no_corrected_fuel() -> None:
    stalled = leg(stalled=True, fuel_corrected_kg=None, stall_distance_m=1500.0, message="stalled at km 1.50")
    summary = two_legs(leg(), stalled)
    assert summary["stalled"] is True and summary["fuel_corrected_kg"] is None
    assert summary["stall_distance_m"] == 1500.0 and summary["fuel_kg"] == pytest.approx(0.6)


def test_the_reference_page_lists_every_declared_output() -> None:
    path = Path(__file__).resolve().parents[1] / "docs" / "hooks" / "output_reference.py"
    spec = importlib.util.spec_from_file_location("docs_hook_output_reference", path)
    assert spec is not None and spec.loader is not None
    hook = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(hook)
    source = (path.parents[1] / "reference" / "outputs.md").read_text(encoding="utf-8")
    page = hook.outputs_page(source)
    for output in (*SUMMARY_SPECS, *TRACE_SPECS):
        assert f"| `{output.name}` | " in page, output.name
    with pytest.raises(Exception, match="outputs:NAME"):
        hook.outputs_page(source.replace("<!-- outputs:trace -->", ""))


BEV_XML = Path(__file__).resolve().parents[2] / "shared/vehicles/vecto-generic-class5-bev/Group5_PEV_E4.xml"


@pytest.mark.skipif(not BEV_XML.is_file(), reason="VECTO's generic electric tractor (../shared) not present")
@pytest.mark.parametrize("controller", list(CARRIED))
def test_a_battery_electric_truck_s_run_gives_battery_figures_in_place_of_fuel(controller: str) -> None:
    result = simulate(make_section("hill", 1500, 2.0), load_run_config(BEV_XML), controller)
    assert set(result.summary) == declared(controller, electric=True)
    assert list(result.trace) == declared_columns(electric=True)
    trace = result.trace
    # The trace's last sample is the run's end: the summary's energy and state of charge.
    assert trace["battery_energy_kwh"][-1] == pytest.approx(result.summary["energy_kwh"], rel=1e-12)
    assert trace["soc_pct"][-1] == pytest.approx(result.summary["soc_end_pct"], rel=1e-12)

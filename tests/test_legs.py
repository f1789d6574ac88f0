"""A road with stops driven as its stop-free legs: the joined result against the legs driven on
their own, the trace across a stop, stalls, and VECTO's long-haul cycle."""

from __future__ import annotations

import itertools
from pathlib import Path

import numpy as np
import pytest

from truckmpc import _core, load_road, load_run_config, simulate
from truckmpc.legs import merge_legs
from truckmpc.roads import RoadProfile, Stop, concatenate, make_section
from truckmpc.roads.stops import STOPS_NOTE, leg_bounds
from truckmpc.sim import RunResult

REPO = Path(__file__).resolve().parents[1]
LONG_HAUL = REPO / ".." / "shared" / "roads" / "raw" / "vecto-longhaul-2015.vdri"

JOIN_M = 2000.0


def first_leg() -> RoadProfile:
    """2 km: flat, a 2 % climb over 1 km, flat; target 70 km/h."""
    return RoadProfile("first", [0, 500, 1500, 2000], [0, 0, 20, 20], target_speed_kmh=[70] * 4)


def second_leg() -> RoadProfile:
    """3 km from 2 km: flat, then down 15 m over 2 km; target 80 km/h."""
    return RoadProfile("second", [2000, 3000, 5000], [20, 20, 5], target_speed_kmh=[80] * 3)


def whole_road() -> RoadProfile:
    """Both legs as one road with a 45 s stop between them."""
    distance = [0, 500, 1500, 2000, 3000, 5000]
    altitude = [0, 0, 20, 20, 20, 5]
    targets = [70, 70, 70, 80, 80, 80]
    return RoadProfile("whole", distance, altitude, target_speed_kmh=targets, stops=(Stop(JOIN_M, 45.0),))


@pytest.mark.slow
@pytest.mark.parametrize("controller", ["pi", "pcc", "mpc"])
def test_a_road_with_a_stop_adds_up_its_legs_driven_alone(controller: str) -> None:
    config = load_run_config()
    whole = simulate(whole_road(), config, controller)
    legs = [simulate(leg, config, controller) for leg in (first_leg(), second_leg())]
    summary, one, two = whole.summary, legs[0].summary, legs[1].summary
    for key in ("fuel_kg", "time_s", "distance_m", "brake_energy_kj", "neutral_distance_m", "fuel_corrected_kg"):
        assert summary[key] == pytest.approx(one[key] + two[key], rel=1e-12), key
    assert summary["gear_shifts"] == one["gear_shifts"] + two["gear_shifts"]
    assert summary["start_speed_kmh"] == one["start_speed_kmh"] == 70.0  # each leg starts at its target
    assert summary["end_speed_kmh"] == two["end_speed_kmh"]
    distance_m, time_s = one["distance_m"] + two["distance_m"], one["time_s"] + two["time_s"]
    assert summary["mean_speed_kmh"] == pytest.approx(distance_m / time_s * 3.6)
    assert summary["fuel_kg_per_100km"] == pytest.approx((one["fuel_kg"] + two["fuel_kg"]) / distance_m * 1e5)
    assert [(leg["start_m"], leg["end_m"], leg["entry_speed_kmh"]) for leg in summary["legs"]] == [
        (0.0, JOIN_M, 70.0),
        (JOIN_M, 5000.0, 80.0),
    ]
    assert [leg["fuel_kg"] for leg in summary["legs"]] == [one["fuel_kg"], two["fuel_kg"]]
    assert summary["stops_not_simulated"] == {"count": 1, "total_stop_s": 45.0, "note": STOPS_NOTE, "legs": 2}
    if controller == "pcc":
        for key in ("pcc_events", "eco_roll_entries"):
            assert summary[key] == one[key] + two[key], key
    if controller == "mpc":
        assert summary["solves"] == one["solves"] + two["solves"]
        assert summary["states_per_solve"] == pytest.approx(
            (one["states_per_solve"] * one["solves"] + two["states_per_solve"] * two["solves"]) / summary["solves"]
        )


def test_timings_add_up_take_the_largest_and_weigh_means_by_solves() -> None:
    """The wall-clock figures of two made-up legs: compute time adds up, the realtime ratio is
    recomputed from the sums, the worst solve is the worse leg's, the mean solve is per solve."""
    road = whole_road()
    one = {"compute_time_s": 2.0, "time_s": 100.0, "solves": 10, "solve_ms_mean": 1.0, "solve_ms_max": 5.0}
    two = {"compute_time_s": 1.0, "time_s": 300.0, "solves": 30, "solve_ms_mean": 3.0, "solve_ms_max": 4.0}
    results = [made_up_result(leg) for leg in (one, two)]
    summary = merge_legs(road, results, leg_bounds(road)).summary
    assert summary["compute_time_s"] == 3.0 and summary["realtime_ratio"] == 3.0 / 400.0
    assert summary["solve_ms_max"] == 5.0
    assert summary["solve_ms_mean"] == (10 * 1.0 + 30 * 3.0) / 40


def made_up_result(figures: dict[str, float]) -> RunResult:
    """A run result of a leg with `figures` and otherwise plausible entries (2 km at 72 km/h)."""
    summary = {
        "distance_m": 2000.0,
        "fuel_kg": 1.0,
        "start_speed_kmh": 70.0,
        "end_speed_kmh": 70.0,
        "stalled": False,
        "stall_distance_m": None,
        "message": None,
        "fuel_corrected_kg": 1.0,
        **figures,
    }
    trace = {name: np.zeros(2) for name in ("distance_m", "time_s", "fuel_g", "brake_energy_kj")}
    return RunResult("mpc", "leg", summary, trace)


def test_the_trace_runs_on_across_the_stop() -> None:
    """The legs' traces one after the other: both samples at the stop, the cumulative columns
    continued from the first leg's end, the second leg starting at its target speed."""
    config = load_run_config()
    trace = simulate(whole_road(), config, "pi").trace
    one, two = (simulate(leg, config, "pi").trace for leg in (first_leg(), second_leg()))
    k = one["distance_m"].size
    assert trace["distance_m"].size == k + two["distance_m"].size
    assert trace["distance_m"][k - 1] == pytest.approx(JOIN_M, abs=1e-3) and trace["distance_m"][k] == JOIN_M
    assert trace["speed_kmh"][k] == pytest.approx(80.0)
    for name in ("time_s", "fuel_g", "brake_energy_kj"):
        assert trace[name][k] == trace[name][k - 1] == one[name][-1]
        np.testing.assert_allclose(trace[name][k:], two[name] + one[name][-1])
        assert np.all(np.diff(trace[name]) >= 0)
    np.testing.assert_array_equal(trace["gear"], np.concatenate([one["gear"], two["gear"]]))
    assert trace["gear"].dtype == np.int64


def test_a_road_without_stops_is_driven_as_before() -> None:
    """No stop: the result is the core's run unchanged, without leg entries."""
    config = load_run_config()
    road = whole_road()
    plain = RoadProfile("plain", road.distance_m, road.altitude_m, target_speed_kmh=road.target_speed_kmh)
    result = simulate(plain, config, "pi")
    out_summary, out_trace = _core.run(config.settings, plain.core(), np.ascontiguousarray(plain.altitude_m), "pi")
    timing = ("compute_time_s", "realtime_ratio")
    assert {k: v for k, v in result.summary.items() if k not in (*timing, "fuel_corrected_kg")} == {
        k: v for k, v in out_summary.items() if k not in timing
    }
    for name, column in out_trace.items():
        np.testing.assert_array_equal(result.trace[name], column)


def test_stops_at_the_ends_only_drive_the_whole_road_as_one_leg() -> None:
    config = load_run_config()
    road = second_leg()
    stopped = RoadProfile(
        "stopped",
        road.distance_m,
        road.altitude_m,
        None,
        road.target_speed_kmh,
        (Stop(2000.0, 10.0), Stop(5000.0, 20.0)),
    )
    plain, legs = simulate(road, config, "pi"), simulate(stopped, config, "pi")
    assert legs.summary["fuel_kg"] == plain.summary["fuel_kg"] and legs.summary["time_s"] == plain.summary["time_s"]
    assert len(legs.summary["legs"]) == 1
    assert legs.summary["stops_not_simulated"]["count"] == 2
    assert legs.summary["stops_not_simulated"]["total_stop_s"] == 30.0


def test_a_configured_start_speed_is_the_first_legs_only() -> None:
    result = simulate(whole_road(), load_run_config(overrides=["start_speed_kmh=75"]), "pi")
    assert [leg["entry_speed_kmh"] for leg in result.summary["legs"]] == [75.0, 80.0]


def test_a_stall_ends_the_run_and_says_the_later_legs_were_not_driven() -> None:
    """A 60 t truck stalls on 25 % (tests/test_sim.py); the leg after the stop is not driven."""
    hill, flat = make_section("hill", 2000, 25.0), make_section("flat", 1000)
    joined = concatenate([hill, flat], "hill-then-flat")
    road = RoadProfile(joined.name, joined.distance_m, joined.altitude_m, stops=(Stop(hill.length_m, 60.0),))
    result = simulate(road, load_run_config(overrides=["mass_kg=60000"]), "pi")
    assert result.stalled and result.summary["fuel_corrected_kg"] is None
    assert result.summary["stall_distance_m"] < hill.length_m
    assert "stalled at km" in result.message and "not driven" in result.message
    assert f"from km {hill.length_m / 1000:.2f}" in result.message
    assert len(result.summary["legs"]) == 1
    assert result.trace["distance_m"][-1] == pytest.approx(result.summary["stall_distance_m"])


@pytest.mark.skipif(not LONG_HAUL.is_file(), reason="../shared/roads/raw/vecto-longhaul-2015.vdri absent")
def test_the_long_haul_cycle_is_driven_as_five_legs_and_never_through_a_stop() -> None:
    road = load_road(LONG_HAUL)
    bounds = [(0.0, 899.0), (899.0, 2249.0), (2249.0, 105941.0), (105941.0, 107291.0), (107291.0, 108191.0)]
    assert leg_bounds(road) == bounds
    result: RunResult = simulate(road, load_run_config(), "pi")
    summary, trace = result.summary, result.trace
    assert not result.stalled and result.message is None
    assert [(leg["start_m"], leg["end_m"]) for leg in summary["legs"]] == bounds
    assert summary["distance_m"] == pytest.approx(road.length_m, abs=0.01)
    assert summary["time_s"] == pytest.approx(sum(leg["time_s"] for leg in summary["legs"]))
    for leg in summary["legs"]:  # each leg enters at its target speed (all at most v_ref)
        assert leg["entry_speed_kmh"] == road.target_speed_at(np.array([leg["start_m"]]))[0]
    inside = [stop.distance_m for stop in road.stops][1:-1]
    assert not any(start < at < end for start, end in bounds for at in inside)
    # At each stop the trace goes from the leg before it, at its exit speed, to the leg after it at
    # its entry speed, with no time between them.
    for before, after in itertools.pairwise(summary["legs"]):
        k = int(np.flatnonzero(trace["distance_m"] == after["start_m"])[-1])
        assert trace["speed_kmh"][k] == pytest.approx(after["entry_speed_kmh"])
        assert trace["speed_kmh"][k - 1] == pytest.approx(before["exit_speed_kmh"], abs=0.01)
        assert trace["time_s"][k] == trace["time_s"][k - 1]
    assert summary["stops_not_simulated"]["count"] == 6 and summary["stops_not_simulated"]["total_stop_s"] == 244.0

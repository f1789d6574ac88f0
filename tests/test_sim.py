"""Closed-loop simulation: step convergence, energy sanity, stalls, the trace, the controller protocol."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from truckmpc import _core
from truckmpc.config import load_run_config
from truckmpc.controller import Control, PlantState
from truckmpc.errors import ConfigError
from truckmpc.roads import RoadProfile, default_test_track, load_road, make_section
from truckmpc.sim import TRACE_COLUMNS, simulate

SHARED_ROADS = Path(__file__).resolve().parents[1] / ".." / "shared" / "roads"
VECTO_108 = SHARED_ROADS / "eu_vecto_longhaul_2015_108km.csv"


@pytest.fixture(scope="module")
def config():
    return load_run_config()


def test_halving_the_plant_step_changes_fuel_and_time_very_little(config):
    road = default_test_track()
    dt = config.sim.plant_dt_s
    coarse = simulate(road, config).summary
    fine = simulate(road, load_run_config(overrides=[f"plant_dt_s={dt / 2}"])).summary
    assert abs(fine["fuel_kg"] / coarse["fuel_kg"] - 1) < 0.05e-2
    assert abs(fine["time_s"] / coarse["time_s"] - 1) < 0.01e-2


def test_flat_road_uses_fuel_and_no_brakes(config):
    summary = simulate(make_section("flat", 10_000), config).summary
    assert summary["fuel_kg"] > 0
    assert summary["brake_energy_kj"] == 0.0
    # A 40 t truck at 85 km/h: about 30 kg/100 km (about 35 l/100 km of diesel).
    assert 25 < summary["fuel_kg_per_100km"] < 35
    assert summary["time_s"] == pytest.approx(10_000 / (85 / 3.6), rel=1e-6)
    assert summary["neutral_distance_m"] == 0.0
    assert not summary["stalled"] and summary["stall_distance_m"] is None and summary["message"] is None


def test_descent_energy_goes_into_the_brakes(config):
    summary = simulate(make_section("hill", 3000, -4.0), config).summary
    assert summary["brake_energy_kj"] > 0
    # Brake energy cannot exceed the potential energy released (m g h) on the descent.
    mgh_kj = config.vehicle.mass_kg * 9.81 * 3000 * 0.04 / 1000
    assert summary["brake_energy_kj"] < mgh_kj


def test_a_hill_too_steep_to_climb_stalls_with_a_clear_result():
    # A 60 t truck cannot climb 25 % in gear 1 (a 40 t one just manages up to about 29 %).
    config = load_run_config(overrides=["mass_kg=60000"])
    result = simulate(make_section("hill", 2000, 25.0), config)
    summary = result.summary
    assert result.stalled and summary["stalled"] is True
    assert 500 < summary["stall_distance_m"] < 2500
    assert result.message.startswith(f"stalled at km {summary['stall_distance_m'] / 1000:.2f}")
    assert summary["distance_m"] < 2500
    for key in ("fuel_kg", "time_s", "mean_speed_kmh", "end_speed_kmh", "realtime_ratio"):
        assert math.isfinite(summary[key])
    trace = result.trace
    assert trace["distance_m"][-1] == pytest.approx(summary["stall_distance_m"])
    assert np.all(np.isfinite(np.column_stack([trace[c] for c in TRACE_COLUMNS])))


def test_forty_tonne_truck_stalls_on_thirty_percent():
    result = simulate(make_section("hill", 2000, 30.0), load_run_config())
    assert result.stalled
    assert "stalled at km" in result.message


def test_trace_is_sampled_every_step_and_ends_on_the_road_end(config):
    road = default_test_track()
    result = simulate(road, config)
    trace = result.trace
    assert list(trace) == list(TRACE_COLUMNS)
    s = trace["distance_m"]
    assert s[0] == road.distance_m[0]
    assert s[-1] == pytest.approx(road.distance_m[-1], abs=1e-6)
    assert np.allclose(np.diff(s)[:-1], config.sim.trace_step_m)
    assert np.all(np.diff(trace["time_s"]) > 0)
    assert np.all(np.diff(trace["fuel_g"]) >= 0)
    assert trace["fuel_g"][-1] == pytest.approx(result.summary["fuel_kg"] * 1000)
    assert trace["altitude_m"][-1] == pytest.approx(road.altitude_m[-1])
    assert set(np.unique(trace["slope"])) <= set(np.round(road.slope, 12)) | set(road.slope)
    assert result.summary["time_s"] > 0
    assert result.summary["compute_time_s"] > 0
    assert result.summary["realtime_ratio"] == pytest.approx(
        result.summary["compute_time_s"] / result.summary["time_s"]
    )


class HoldStationary:
    """A stage controller: every 100 m it applies the pedal that holds 85 km/h on a flat road."""

    name = "hold"

    def __init__(self, gear: int = 12, stage_m: float = 100.0) -> None:
        self.gear, self.stage_m, self.decisions = gear, stage_m, 0

    def start(self, road: RoadProfile, state: PlantState) -> None:
        self.decisions = 0

    def decide(self, state: PlantState) -> tuple[Control, float]:
        self.decisions += 1
        return Control(0.4487034812584876, 0.0, self.gear), state.s_m + self.stage_m


def test_stage_controllers_run_in_the_same_loop(config):
    controller = HoldStationary()
    result = simulate(make_section("flat", 2000), config, controller)
    assert result.name == "hold"
    assert controller.decisions == 20
    assert np.all(np.abs(result.trace["speed_kmh"] - 85.0) < 1e-3)
    pi = simulate(make_section("flat", 2000), config).summary
    assert result.summary["fuel_kg"] == pytest.approx(pi["fuel_kg"], rel=1e-6)
    assert np.allclose(np.diff(result.trace["distance_m"]), config.sim.trace_step_m)


def test_neutral_distance_counts_coasting(config):
    result = simulate(make_section("hill", 1000, -1.25, lead_m=0, tail_m=0), config, HoldCoast())
    assert result.summary["neutral_distance_m"] == pytest.approx(1000.0, abs=1e-3)
    assert result.summary["gear_shifts"] == 0


class HoldCoast:
    """Neutral gear, no pedal, no brake: -1.25 % holds 85 km/h in neutral (table B.1, row 3)."""

    name = "coast"

    def start(self, road: RoadProfile, state: PlantState) -> None:
        pass

    def decide(self, state: PlantState) -> tuple[Control, float]:
        return Control(0.0, 0.0, 0), state.s_m + 250.0


def test_reversed_road_swaps_climbs_and_descents(config):
    road = make_section("hill", 500, 3.5)
    up = simulate(road, config).summary
    down = simulate(road.reversed(), config).summary
    assert down["fuel_kg"] < up["fuel_kg"]


@pytest.mark.slow
@pytest.mark.skipif(not VECTO_108.is_file(), reason="../shared/roads not present")
def test_pi_completes_the_108_km_vecto_long_haul_road(config):
    road = load_road(VECTO_108)
    result = simulate(road, config)
    summary = result.summary
    assert not summary["stalled"]
    assert summary["distance_m"] == pytest.approx(road.length_m, abs=1e-3)
    assert 20 < summary["fuel_kg_per_100km"] < 45
    assert summary["realtime_ratio"] < 0.05  # far faster than real time


class StaleHold:
    """A faulty stage controller whose hold always ends behind the truck."""

    name = "stale"

    def start(self, road: RoadProfile, state: PlantState) -> None:
        pass

    def decide(self, state: PlantState) -> tuple[Control, float]:
        return Control(0.5, 0.0, 12), state.s_m - 10.0


def test_a_controller_that_never_moves_the_truck_ends_the_run(config):
    result = simulate(make_section("flat", 1000), config, StaleHold())
    assert "stopped at km 0.00" in result.message


def test_the_rust_loop_rejects_what_it_cannot_run(config):
    road = make_section("flat", 1000)
    args = (config.settings, road.core())
    with pytest.raises(ValueError, match=r"^controller: "):
        _core.run(*args, np.asarray(road.altitude_m, dtype=float), "pid")
    with pytest.raises(ValueError, match=r"^altitude_m: "):
        _core.run(*args, np.asarray(road.altitude_m[:1], dtype=float), "pi")
    with pytest.raises(ConfigError, match=r"^controller: "):
        simulate(road, config, "pid")


class Failing:
    """A Python controller whose decision raises after 100 m."""

    name = "failing"

    def start(self, road: object, state: PlantState) -> None:
        pass

    def decide(self, state: PlantState) -> tuple[Control, None]:
        if state.s_m > 100.0:
            raise RuntimeError("the controller's own bug")
        return Control(0.5, 0.0, 12), None


def test_an_error_in_a_python_controller_stops_the_loop_and_surfaces(config):
    with pytest.raises(RuntimeError, match="the controller's own bug"):
        simulate(make_section("flat", 1000), config, Failing())


class FailingToStart(Failing):
    """A Python controller whose start raises; it counts the decisions asked of it."""

    def __init__(self) -> None:
        self.decisions = 0

    def start(self, road: object, state: PlantState) -> None:
        raise RuntimeError("no start")

    def decide(self, state: PlantState) -> tuple[Control, None]:
        self.decisions += 1
        return super().decide(state)


def test_a_python_controller_that_fails_to_start_is_asked_for_no_decision(config):
    controller = FailingToStart()
    with pytest.raises(RuntimeError, match="no start"):
        simulate(make_section("flat", 1000), config, controller)
    assert controller.decisions == 0


def test_the_rust_loop_returns_the_trace_columns_as_arrays(config):
    result = simulate(make_section("flat", 1000), config, "mpc")
    assert list(result.trace) == list(TRACE_COLUMNS)
    assert result.trace["gear"].dtype == np.int64
    assert all(result.trace[c].dtype == np.float64 for c in TRACE_COLUMNS if c != "gear")
    assert result.summary["solves"] == 1000 / config.mpc.stage_m + 1
    settings = result.summary["settings"]
    # 200 m / S; Q2 and Q5 per stage from their per-kilometre defaults at S 25 m.
    assert (settings["k_lim"], settings["q_speed_below"], settings["q_brake"]) == (8, 5.0, 100.0)
    assert settings["horizon_m"] == config.mpc.horizon_m and settings["v_ref_kmh"] == config.cruise.v_ref_kmh


class GearsByDistance:
    """Coasting at fuel cut (no pedal) on a -1.25 % road in a gear set per 250 m stretch: a known
    sequence of gears, neutral between some of them."""

    name = "gears"

    def __init__(self, gears: list[int]) -> None:
        self.gears = gears

    def start(self, road: RoadProfile, state: PlantState) -> None:
        pass

    def decide(self, state: PlantState) -> tuple[Control, float]:
        k = min(int(state.s_m // 250.0 + 1e-9), len(self.gears) - 1)
        return Control(0.0, 0.0, self.gears[k]), (k + 1) * 250.0


def test_shifts_and_neutral_engagements_are_counted_apart(config):
    """Gears 12, N, 12, 11, N, N, 10, 12 over eight 250 m stretches (2 km): declutching and
    re-engaging 12 is one engagement and no shift; 11 -> N -> 10 is one engagement and one shift;
    12 -> 11 and 10 -> 12 are one shift each: 3 shifts, 2 engagements, 150 and 100 per 100 km."""
    gears = [12, 0, 12, 11, 0, 0, 10, 12]
    road = make_section("hill", 2000.0, -1.25, lead_m=0, tail_m=0)
    summary = simulate(road, config, GearsByDistance(gears)).summary
    assert (summary["gear_shifts"], summary["neutral_engagements"]) == (3, 2)
    km = summary["distance_m"] / 1000.0
    assert km == pytest.approx(2.0, abs=1e-3)
    assert summary["gear_shifts_per_100km"] == pytest.approx(3 / km * 100.0, rel=1e-12)
    assert summary["neutral_engagements_per_100km"] == pytest.approx(2 / km * 100.0, rel=1e-12)
    assert summary["neutral_distance_m"] == pytest.approx(750.0, abs=1e-3)

"""PI cruise controller (thesis section 2.5, tables A.3/A.4): closed-loop behaviour and gear logic."""

from __future__ import annotations

import numpy as np
import pytest

from truckmpc.config import load_run_config
from truckmpc.controller import PlantState
from truckmpc.errors import ConfigError
from truckmpc.pi import GearLogic, PiController, steady_gear
from truckmpc.road import make_section
from truckmpc.sim import simulate

KMH = 3.6


@pytest.fixture(scope="module")
def config():
    return load_run_config()


def state(v_kmh: float, t_s: float, s_m: float = 0.0) -> PlantState:
    return PlantState(s_m, v_kmh / KMH, t_s, 0.0, 0.0, False)


def test_flat_road_from_85_holds_85(config):
    result = simulate(make_section("flat", 5000), config)
    speed = result.trace["speed_kmh"]
    assert np.all(np.abs(speed - 85.0) < 0.1)
    assert result.summary["gear_shifts"] == 0


def test_flat_road_settles_on_85_after_a_start_below_it():
    config = load_run_config(overrides=["start_speed_kmh=80"])
    trace = simulate(make_section("flat", 8000), config).trace
    settled = trace["distance_m"] > 4000
    assert np.all(np.abs(trace["speed_kmh"][settled] - 85.0) < 0.1)
    assert trace["speed_kmh"].max() < 90.0  # the overshoot of the pedal integrator stays below v_max


def test_long_descent_brakes_and_holds_v_max(config):
    # 500 m flat, 3000 m at -4 %, 1500 m flat.
    trace = simulate(make_section("hill", 3000, -4.0), config).trace
    v_max = config.v_max_kmh
    s = trace["distance_m"]
    on_descent = (s >= 500) & (s <= 3500)
    assert trace["brake"][on_descent].max() > 0.0
    # The brake integrator starts at its lower clamp (-30 km/h*s, i.e. -0.6 of brake), so the speed
    # rises about 2 km/h above v_max before the brake takes hold; from 500 m into the descent on it
    # stays within 1 km/h of v_max.
    assert trace["speed_kmh"][on_descent].max() < v_max + 2.5
    held = (s >= 1000) & (s <= 3500)
    assert np.all(np.abs(trace["speed_kmh"][held] - v_max) < 1.0)
    # Steady braking on -4 % at 90 km/h needs B = 0.0490 (table B.1, row 2).
    assert trace["brake"][(s > 3000) & (s <= 3500)].mean() == pytest.approx(0.0490, rel=0.02)


def test_no_braking_below_v_max(config):
    # A -1 % descent speeds the truck up less than 5 km/h: brake error v - v_max stays negative.
    result = simulate(make_section("hill", 2000, -1.0), config)
    assert result.trace["speed_kmh"].max() < config.v_max_kmh
    assert result.summary["brake_energy_kj"] == 0.0


def test_ascent_downshifts_and_upshifts_after(config):
    trace = simulate(make_section("hill", 2000, 4.0), config).trace
    gear = trace["gear"]
    assert gear[0] == 12
    assert gear.min() < 12
    assert gear[-1] == 12
    # Gears change one step at a time and never hunt: every shift is +-1.
    assert set(np.unique(np.diff(gear))) <= {-1, 0, 1}


def test_pedal_integrator_saturates_on_a_steep_climb(config):
    vehicle = config.core_vehicle
    pi = PiController(vehicle, config)
    pi.reset(85 / KMH, 0.0)
    for k in range(1, 2000):
        control, until = pi.decide(state(60.0, 0.05 * k))
        assert until is None
    assert pi.pedal_integrator == config.pi.pedal_integrator_limit
    assert control.pedal == 1.0 and control.brake == 0.0


def test_start_holds_v_ref_without_transient(config):
    vehicle = config.core_vehicle
    pi = PiController(vehicle, config)
    for slope in (0.0, 0.01, -0.005):
        pi.reset(85 / KMH, slope)
        control, _ = pi.decide(state(85.0, 0.0))
        expected = vehicle.stationary(85 / KMH, slope, 12)["pedal"]
        assert control.pedal == pytest.approx(expected, rel=1e-9)
        assert pi.brake_integrator == -config.pi.brake_integrator_limit


def test_brake_acts_on_speed_above_v_max(config):
    pi = PiController(config.core_vehicle, config)
    pi.reset(85 / KMH, 0.0)
    below, _ = pi.decide(state(config.v_max_kmh - 0.5, 0.05))
    assert below.brake == 0.0
    above, _ = pi.decide(state(config.v_max_kmh + 3.0, 0.10))  # K_B * 3 - I_B * 30 > 0
    assert above.brake > 0.0 and above.pedal == 0.0


def test_steady_gear_follows_table_a3(config):
    vehicle = config.core_vehicle
    assert steady_gear(vehicle, 85 / KMH, config.pi) == 12
    for v_kmh in np.arange(5.0, 120.0, 2.5):
        gear = steady_gear(vehicle, v_kmh / KMH, config.pi)
        rpm = vehicle.engine_speed_rpm(v_kmh / KMH, gear)
        assert gear == 12 or rpm <= config.pi.gear_up_rpm[gear - 1]
        assert gear == 1 or rpm >= config.pi.gear_down_rpm[gear - 1]


def test_gear_logic_hysteresis(config):
    vehicle = config.core_vehicle
    logic = GearLogic(vehicle, config.pi.gear_down_rpm, config.pi.gear_up_rpm)
    rpm_per_mps = vehicle.engine_speed_rpm(1.0, 12)
    assert logic.next_gear(12, 1299 / rpm_per_mps) == 11
    assert logic.next_gear(12, 1301 / rpm_per_mps) == 12
    # Just after a downshift from 12 the engine turns ~1600 rpm in 11: below its 1700 rpm upshift.
    v = 1299 / rpm_per_mps
    assert logic.next_gear(11, v) == 11
    # Every upshift lands above the next gear's downshift threshold.
    for g in range(1, 12):
        v_up = (config.pi.gear_up_rpm[g - 1] + 1) / vehicle.engine_speed_rpm(1.0, g)
        assert logic.next_gear(g, v_up) == g + 1
        assert logic.next_gear(g + 1, v_up) == g + 1


def test_gear_logic_rejects_hunting_thresholds(config):
    vehicle = config.core_vehicle
    up = list(config.pi.gear_up_rpm)
    up[10] = 1400.0  # 11 -> 12 at 1400 rpm lands at 1138 rpm, below 12's 1300 rpm downshift
    with pytest.raises(ConfigError, match="hunt"):
        GearLogic(vehicle, config.pi.gear_down_rpm, up)
    with pytest.raises(ConfigError, match="one per forward gear"):
        GearLogic(vehicle, config.pi.gear_down_rpm[:-1], up[:-1])


def test_twenty_tonne_truck_climbs_faster(config):
    light = load_run_config(vehicle_path=None, overrides=["mass_kg=20000"])
    road = make_section("hill", 1000, 3.0)
    heavy_run = simulate(road, config).summary
    light_run = simulate(road, light).summary
    assert light_run["time_s"] < heavy_run["time_s"]
    assert light_run["fuel_kg"] < heavy_run["fuel_kg"]

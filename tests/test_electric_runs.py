"""Runs of VECTO's generic battery-electric tractor against truths built independently: a road
with a stop against its legs driven alone, each from where the battery was left; the summary's
machine and battery losses against the core's power flows summed over a fine trace."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from test_electric_truck import BEV_XML, needs_bev
from truckmpc import load_run_config, simulate
from truckmpc.roads import RoadProfile, Stop, load_road
from truckmpc.roads.stops import leg_road


@needs_bev
@pytest.mark.parametrize("controller", ["pi", "mpc"])
def test_over_a_stop_the_battery_carries_on(controller: str) -> None:
    """A road with a stop is driven as two legs and the battery carries over: the second leg is the
    same truck started, on its own, at the state of charge the first ended at; the run's energy,
    recovered energy and time are the legs' sums, its state of charge ends where the second's does."""
    road = RoadProfile(
        "stop", [0, 1000, 2000, 3000, 4000], [0, 25, 25, 0, 0], target_speed_kmh=[80] * 5, stops=(Stop(2000.0, 30.0),)
    )
    config = load_run_config(BEV_XML)
    whole = simulate(road, config, controller).summary
    first = simulate(leg_road(road, 0.0, 2000.0, 1), config, controller).summary
    carried = load_run_config(BEV_XML, overrides=(f"soc_start_pct={first['soc_end_pct']!r}",))
    second = simulate(leg_road(road, 2000.0, 4000.0, 2), carried, controller).summary
    assert first["soc_end_pct"] < 50.0 and whole["soc_start_pct"] == 50.0
    assert whole["soc_end_pct"] == second["soc_end_pct"]
    for key in ("energy_kwh", "recovered_kwh", "time_s", "energy_corrected_kwh"):
        assert whole[key] == pytest.approx(first[key] + second[key], rel=1e-12), key
    assert [leg["energy_kwh"] for leg in whole["legs"]] == [first["energy_kwh"], second["energy_kwh"]]


@needs_bev
def test_the_summary_sums_the_machines_and_the_batterys_losses_and_the_trace_gives_the_torque() -> None:
    """The summary's machine and battery losses are the trace's loss powers (the core's power
    flows at each 1 m sample) summed by the trapezoid rule in time, to 0.5 %; the trace's machine
    torque times the machines' speed is the mechanical power the wheels and the reduction take."""
    road = Path(__file__).resolve().parents[1] / "roads" / "hill_L500_A3.5.csv"
    config = load_run_config(BEV_XML, overrides=("trace_step_m=1",))
    result = simulate(load_road(road), config, "mpc")
    trace = {key: np.asarray(values, dtype=float) for key, values in result.trace.items()}
    v = trace["speed_kmh"] / 3.6
    brakes_nm = float(config.settings.get("brake_torque_max_nm"))
    flows = config.truck.core.electric_flows(v, trace["pedal"], trace["brake"], brakes_nm)
    dt = np.diff(trace["time_s"])
    for key, power in (("machine_loss_kwh", "machine_loss_w"), ("battery_loss_kwh", "battery_loss_w")):
        summed = float(np.sum(0.5 * (flows[power][:-1] + flows[power][1:]) * dt)) / 3.6e6
        assert result.summary[key] == pytest.approx(summed, rel=5e-3), key
    omega = trace["engine_speed_rpm"] * math.pi / 30.0
    mechanical_w = trace["machine_torque_nm"] * omega
    assert np.allclose(mechanical_w, flows["wheel_w"] + flows["reduction_loss_w"], rtol=1e-9, atol=1e-6)

"""The whole-road optimum (`--controller optimal`): one DP over the whole road, driven from the
measured state stage by stage against its stored cost-to-go. Checked against the receding MPC's
closed-loop trajectory priced by the same cost function, computed here from the MPC's trace."""

from __future__ import annotations

import json

import numpy as np
import pytest
from typer.testing import CliRunner

from table_text import parse_table
from truckmpc import load_run_config, simulate
from truckmpc.cli import app
from truckmpc.fuel import plan_gap_pct
from truckmpc.roads import default_test_track, make_section
from truckmpc.sim import CONTROLLERS
from truckmpc.units import KMH_PER_MPS

runner = CliRunner()

# The thesis's speed-penalty cost (with the converged grid and arcs), which `trajectory_cost` prices:
# Q4 on every gear change, neutral included, Euler stages, the thesis's ±5 km/h band.
SPEED_PENALTY = [
    "cost=speed_penalty",
    "stage_model=euler",
    "q_speed_change=15",
    "q_gear_shift=15",
    "q_neutral=0",
    "shift_price_neutral=true",
    "neutral_exit_top_gear=false",
    "horizon_m=1500",
    "delta_kmh=0.025",
    "v_dec_kmh=5",
]


def trajectory_cost(result, config) -> float:
    """The DP's cost (Q1 fuel, Q2 speed deficit at each stage start, Q3 speed change, Q4 shifts,
    Q5 brake level per stage) of a closed-loop run, from its trace sampled at the stage boundaries."""
    s = config.settings
    stage_m = float(config.mpc.stage_m)
    trace = result.trace
    at = np.isclose(np.mod(trace["distance_m"] + 1e-6, stage_m), 1e-6, atol=1e-3)
    v = trace["speed_kmh"][at] / KMH_PER_MPS
    fuel_g = np.diff(trace["fuel_g"][at])
    v_ref = float(config.cruise.v_ref_kmh) / KMH_PER_MPS
    deficit = np.maximum(v_ref - v[:-1], 0.0)
    shifts = np.count_nonzero(np.diff(trace["gear"][at]))
    mpc = config.mpc
    return float(
        mpc.q_fuel * fuel_g.sum()
        + s.derived()["q_speed_below"] * (deficit**2).sum()
        + mpc.q_speed_change * np.abs(np.diff(v)).sum()
        + mpc.q_gear_shift * shifts
        + s.derived()["q_brake"] * trace["brake"][at][:-1].sum()
    )


@pytest.mark.parametrize(
    "road", [default_test_track(), make_section("crest", 1500, 4.0)], ids=["test-track", "crest 4 %"]
)
def test_the_whole_road_plan_is_never_costlier_than_the_mpcs_closed_loop_trajectory(road):
    config = load_run_config(overrides=SPEED_PENALTY)
    optimal = simulate(road, config, "optimal").summary
    mpc = simulate(road, config, "mpc")
    assert np.isfinite(optimal["plan_cost"]) and optimal["infeasible_solves"] == 0
    # Within the grid's resolution and the plant's difference from the DP's one-step model.
    assert optimal["plan_cost"] <= trajectory_cost(mpc, config) * 1.002


def fuel_time_cost_g(summary, config) -> float:
    """A run's fuel + β·time [g] with its end speed brought back to its start speed, kinetic energy
    priced as the end-speed correction prices it: c·½(v_end² − v_start²) off the fuel."""
    price = config.settings.derived()["kinetic_fuel_g_per_half_v2"]
    beta = config.settings.derived()["beta_g_per_s"]
    v0, v1 = (summary[key] / KMH_PER_MPS for key in ("start_speed_kmh", "end_speed_kmh"))
    return 1000 * summary["fuel_kg"] - price * 0.5 * (v1**2 - v0**2) + beta * summary["time_s"]


@pytest.mark.parametrize(
    "road",
    [make_section("crest", 1500, 2.0, tail_m=0.0), make_section("hill", 1000, 2.0, tail_m=500.0)],
    ids=["ending on a crest", "ending after a climb"],
)
def test_with_the_fuel_time_cost_the_optimum_bounds_the_mpcs_fuel_and_time_whatever_its_end_speed(road):
    """Roads that end where the MPC, pricing its end speed, leaves it off v_ref: the optimum (free end
    speed priced alike, no comfort prices) costs no more fuel + β·time, end speed corrected. Raised to
    v_ref at the end, or paying for its shifts and coasts, it cost up to 9 g more here."""
    config = load_run_config()
    optimal = simulate(road, config, "optimal").summary
    mpc = simulate(road, config, "mpc").summary
    assert fuel_time_cost_g(optimal, config) <= fuel_time_cost_g(mpc, config)


def test_the_optimum_drives_close_to_its_plan_and_beats_the_pi():
    config = load_run_config()
    road = default_test_track()
    optimal = simulate(road, config, "optimal").summary
    pi = simulate(road, config, "pi").summary
    assert optimal["fuel_kg"] == pytest.approx(optimal["plan_fuel_kg"], rel=0.01)
    assert optimal["time_s"] == pytest.approx(optimal["plan_time_s"], rel=0.005)
    assert optimal["plan_gap_pct"] < 0.1
    assert optimal["fuel_kg"] < pi["fuel_kg"]
    assert optimal["plan_stages"] == 8500 / 25 and optimal["plan_table_mb"] > 0


def test_controller_all_reports_the_mpcs_gap_to_the_optimum(tmp_path):
    result = runner.invoke(app, ["simulate", "--controller", "all", "--out", str(tmp_path / "out"), "--verbose"])
    assert result.exit_code == 0, result.stderr
    doc = json.loads((tmp_path / "out" / "summary.json").read_text())
    mpc, optimal = doc["mpc"]["fuel_kg"], doc["optimal"]["fuel_kg"]
    assert doc["gap_to_optimal_pct"] == pytest.approx((mpc - optimal) / optimal * 100, abs=1e-12)
    for name in ("mpc", "optimal"):
        assert f"delta_fuel_pct_{name}" in doc
    table = parse_table(result.stdout)
    # `all` is every controller, the PCC and VECTO's cruise driver included.
    blank = dict.fromkeys(CONTROLLERS, "")
    assert table.row("Δfuel vs optimum [%]") == blank | {"mpc": f"{doc['gap_to_optimal_pct']:+.2f}"}
    assert table.row("plan fuel [kg]") == blank | {"optimal": f"{doc['optimal']['plan_fuel_kg']:.3f}"}
    assert all((tmp_path / "out" / f"trace-{name}.csv").is_file() for name in CONTROLLERS)


def test_the_plan_gap_brings_the_run_to_the_plans_end_speed_and_trip_time():
    """Worked by hand: a run 2 s slower than its plan and 1 m/s slower at the end, 5 g/s for time
    and 2 g per m²/s² of ½v²: 20 kg + (2·½(21² − 20²) + 5·2) g = 20.051 kg against a 20.1 kg plan."""
    summary = {
        "fuel_kg": 20.0,
        "time_s": 1002.0,
        "end_speed_kmh": 20.0 * 3.6,
        "stalled": False,
        "plan_fuel_kg": 20.1,
        "plan_time_s": 1000.0,
        "plan_end_speed_kmh": 21.0 * 3.6,
    }
    assert plan_gap_pct(summary, 2.0, 5.0) == pytest.approx(100 * (1 - 20.051 / 20.1), rel=1e-9)
    assert plan_gap_pct({**summary, "plan_fuel_kg": float("nan")}, 2.0, 5.0) is None
    assert plan_gap_pct({**summary, "stalled": True}, 2.0, 5.0) is None

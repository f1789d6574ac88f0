"""The thesis's look-ahead controller (the `thesis` preset) on the thesis's artificial sections
(chapter 6), against PI.

Settings are the thesis's detail-study ones (table 6.1: 1000 m horizon, S = 25 m, delta = 0.2 km/h,
40 t, 85 km/h); each test states the behaviour of the figure it mirrors.
"""

from __future__ import annotations

import numpy as np
import pytest

from truckmpc.config import load_run_config
from truckmpc.roads import default_test_track, make_section
from truckmpc.sim import simulate

DETAIL = ["horizon_m=1000"]


def run_both(road, *overrides):
    config = load_run_config(config_paths=["thesis"], overrides=[*DETAIL, *overrides])
    return simulate(road, config, "pi"), simulate(road, config, "mpc")


def speed_at(result, distance_m: float) -> float:
    """Speed [km/h] at a distance, from the trace."""
    return float(np.interp(distance_m, result.trace["distance_m"], result.trace["speed_kmh"]))


def neutral_m(result) -> float:
    return float(result.summary["neutral_distance_m"])


@pytest.fixture(scope="module")
def ascent():
    return run_both(make_section("hill", 500, 3.5))


def test_accelerates_before_a_steep_ascent(ascent):
    """Fig. 6.3: faster at the foot of a 500 m 3.5 % ascent, and a shorter trip."""
    pi, mpc = ascent
    foot_m = 500.0
    assert speed_at(mpc, foot_m) > speed_at(pi, foot_m) + 1.0
    assert mpc.summary["time_s"] < pi.summary["time_s"]


@pytest.mark.parametrize("length_m", [300, 500])
def test_slows_before_a_descent_and_saves_fuel_and_brakes(length_m):
    """Figs. 6.5/6.6: below v_ref before a -3 % descent; less fuel and less brake energy than PI."""
    pi, mpc = run_both(make_section("hill", length_m, -3.0))
    top_m = 500.0
    assert speed_at(mpc, top_m) < speed_at(pi, top_m) - 1.0
    assert mpc.summary["fuel_kg"] < pi.summary["fuel_kg"]
    assert mpc.summary["brake_energy_kj"] <= pi.summary["brake_energy_kj"]
    if length_m == 500:  # long enough that PI reaches v_max and brakes
        assert pi.summary["brake_energy_kj"] > 0
        assert mpc.summary["brake_energy_kj"] < 0.8 * pi.summary["brake_energy_kj"]


def test_coasts_in_neutral_on_the_short_descent():
    """Fig. 6.5: neutral gear around a 300 m -3 % descent (neutral_rule nearest)."""
    _, mpc = run_both(make_section("hill", 300, -3.0), "neutral_rule=nearest")
    assert neutral_m(mpc) > 100.0


@pytest.mark.parametrize("kind", ["crest", "depression"])
def test_coasts_in_neutral_on_gentle_crests_and_depressions(kind):
    """Figs. 6.9/6.10: neutral gear on 1500 m crests and depressions of 2 %."""
    pi, mpc = run_both(make_section(kind, 1500, 2.0), "neutral_rule=nearest")
    assert neutral_m(mpc) > 100.0
    assert neutral_m(pi) == 0.0
    assert mpc.summary["fuel_kg"] < pi.summary["fuel_kg"]


@pytest.mark.parametrize("kind", ["crest", "depression"])
def test_forbidding_neutral_removes_it(kind):
    """Section 6.6: with neutral disallowed the controller never selects it."""
    _, mpc = run_both(make_section(kind, 1500, 2.0), "allow_neutral=false")
    assert neutral_m(mpc) == 0.0
    assert not np.any(mpc.trace["gear"] == 0)


def test_holds_the_reference_on_a_flat_road():
    """On a flat road there is nothing to anticipate: the MPC cruises at v_ref like PI."""
    pi, mpc = run_both(make_section("flat", 3000))
    assert abs(mpc.summary["end_speed_kmh"] - 85.0) < 0.5
    assert abs(mpc.summary["fuel_kg"] / pi.summary["fuel_kg"] - 1.0) < 0.01  # same job, same fuel
    assert mpc.summary["infeasible_solves"] == 0


def test_never_exceeds_v_max_by_more_than_the_model_error():
    """v_max is a hard limit of the DP; the plant may pass it only by the prediction error."""
    _, mpc = run_both(make_section("hill", 1500, -4.0))
    assert mpc.trace["speed_kmh"].max() < 90.0 + 0.5


def test_interpolated_neutral_rule_runs_and_saves_fuel():
    """The unbiased neutral rule is a valid controller too (its effect is reported, not asserted)."""
    pi, mpc = run_both(make_section("crest", 1500, 2.0), "neutral_rule=interpolate")
    assert mpc.summary["fuel_kg"] < pi.summary["fuel_kg"]


def test_mpc_on_the_test_track_keeps_the_figures_of_the_python_loop():
    # Recorded with the Python closed loop driving the Rust solver (before the receding horizon moved
    # to Rust): `truckmpc simulate --controller mpc` on the bundled test track, summary.json.
    summary = simulate(default_test_track(), load_run_config(config_paths=["thesis"]), "mpc").summary
    assert summary["distance_m"] == 8499.999999903843
    assert summary["fuel_kg"] == 2.5809409833255024
    assert summary["time_s"] == 361.5022925247021
    assert summary["end_speed_kmh"] == 84.83494177440996
    # The loop recorded 6 gear changes: 2 between forward gears and 2 stretches in neutral, each in
    # and out (issue 25 counts shifts and neutral engagements apart).
    assert (summary["gear_shifts"], summary["neutral_engagements"]) == (2, 2)
    assert summary["brake_energy_kj"] == 585.8429539050907
    assert summary["neutral_distance_m"] == 1224.9999999863294
    assert (summary["solves"], summary["infeasible_solves"]) == (341, 0)
    assert summary["states_per_solve"] == 7245.152492668622
    assert summary["transitions_per_solve"] == 35284.645161290326

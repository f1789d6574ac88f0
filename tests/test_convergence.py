"""`truckmpc simulate --check-convergence`: the MPC again at half δ and half S, and how far the
deltas move, checked against runs made independently with the same settings through `--set`."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from truckmpc import load_road, load_run_config, simulate
from truckmpc.cli import app
from truckmpc.convergence import (
    convergence_document,
    convergence_lines,
    cost_move_pct,
    halved_configs,
    run_halves,
)

runner = CliRunner()
HILL = Path(__file__).resolve().parents[1] / "roads" / "hill_L500_A-3.csv"


def run(*args: str):
    return runner.invoke(app, [str(a) for a in args])


@pytest.fixture(scope="module")
def checked(tmp_path_factory):
    """A --check-convergence run of the thesis's controller on the 500 m −3 % descent at δ 0.4 km/h,
    S 50 m."""
    out = tmp_path_factory.mktemp("checked")
    args = ["--road", HILL, "--config", "thesis", "--set", "delta_kmh=0.4", "--set", "stage_m=50"]
    args += ["--set", "horizon_m=1000"]
    result = run("simulate", *args, "--check-convergence", "--out", out)
    assert result.exit_code == 0, result.stderr
    return json.loads((out / "summary.json").read_text()), result.stdout, out


def pct(value: float, base: float) -> float:
    return (value - base) / base * 100


def test_the_halved_runs_are_the_mpc_at_half_delta_and_half_stage_with_q2_and_the_shift_spacing_held(checked):
    doc, _, _ = checked
    road = load_road(HILL)
    # δ 0.4 km/h resolves Q2 to 7 (table 6.2); the halved runs keep it, and k_lim keeps 200 m.
    common = ["stage_m=50", "horizon_m=1000", "q_speed_below=7"]
    expected = {
        "half_delta": [*common, "delta_kmh=0.2"],
        "half_stage": ["delta_kmh=0.4", "stage_m=25", "horizon_m=1000", "q_speed_below=7", "k_lim=8"],
    }
    for half, overrides in expected.items():
        alone = simulate(road, load_run_config(config_paths=["thesis"], overrides=overrides), "mpc").summary
        assert doc["convergence"][half]["fuel_kg"] == alone["fuel_kg"]
        assert doc["convergence"][half]["time_s"] == alone["time_s"]
    assert doc["convergence"]["half_delta"]["delta_kmh"] == 0.2
    assert (doc["convergence"]["half_stage"]["stage_m"], doc["convergence"]["half_stage"]["k_lim"]) == (25.0, 8)


def test_weights_given_per_kilometre_keep_their_value_per_kilometre_at_half_the_stage():
    config = load_run_config(overrides=["stage_m=50"])
    halves = halved_configs(config)
    assert halves["half_stage"].settings.derived()["q_speed_below"] == config.settings.derived()["q_speed_below"] / 2
    assert halves["half_stage"].settings.derived()["q_brake"] == config.settings.derived()["q_brake"] / 2
    assert halves["half_delta"].settings.derived()["q_speed_below"] == config.settings.derived()["q_speed_below"]
    assert halves["half_delta"].mpc.delta_kmh == config.mpc.delta_kmh / 2


def test_each_move_is_the_halved_delta_minus_the_runs_delta_in_points(checked):
    doc, _, _ = checked
    conv = doc["convergence"]
    fuel_pi, time_pi = doc["pi"]["fuel_kg"], doc["pi"]["time_s"]
    for half in ("half_delta", "half_stage"):
        fuel_move = pct(conv[half]["fuel_kg"], fuel_pi) - pct(doc["mpc"]["fuel_kg"], fuel_pi)
        time_move = pct(conv[half]["time_s"], time_pi) - pct(doc["mpc"]["time_s"], time_pi)
        assert conv[f"delta_fuel_pct_{half}"] == pytest.approx(fuel_move, abs=1e-9)
        assert conv[f"delta_time_pct_{half}"] == pytest.approx(time_move, abs=1e-9)
        # at equal trip time: each against the PI re-tuned to its own trip time
        equal_move = conv[half]["delta_fuel_equal_time_pct"] - doc["delta_fuel_equal_time_pct"]
        assert conv[f"delta_fuel_equal_time_pct_{half}"] == pytest.approx(equal_move, abs=1e-9)
        # the headline: at equal trip time and end speed, as summary.json quotes it
        assert conv[f"delta_headline_pct_{half}"] == pytest.approx(conv[half]["headline_pct"] - doc["headline_pct"])
    moves = {k: v for k, v in conv.items() if k.startswith("delta_") and v is not None}
    assert len(moves) == 8
    assert conv["flagged"] == [k for k, v in moves.items() if abs(v) > 0.3]
    # The thesis's cost is not fuel + β·time: no move of that cost.
    assert "delta_cost_pct_half_delta" not in conv and "delta_cost_pct_half_stage" not in conv


def test_the_fuel_time_costs_move_is_corrected_fuel_plus_beta_time_over_the_pis_fuel():
    """With the default cost the check also reports how far fuel (end speed corrected) + β·time
    moves, in points of the PI's fuel, computed here from the runs' own figures."""
    road = load_road(HILL)
    config = load_run_config()
    results = {name: simulate(road, config, name) for name in ("pi", "mpc")}
    halves = halved_configs(config)
    halved = run_halves(road, halves)
    doc = convergence_document(results, halved, halves)
    beta = config.settings.derived()["beta_g_per_s"]
    run, pi_g = results["mpc"].summary, 1000 * results["pi"].summary["fuel_kg"]
    for half, result in halved.items():
        at = result.summary
        moved_g = 1000 * (at["fuel_corrected_kg"] - run["fuel_corrected_kg"]) + beta * (at["time_s"] - run["time_s"])
        assert doc[f"delta_cost_pct_{half}"] == pytest.approx(100 * moved_g / pi_g, abs=1e-9)
    lines = convergence_lines(doc, 40)
    assert sum(line.startswith("fuel + β·time vs PI") for line in lines) == 2
    moves = {k: v for k, v in doc.items() if k.startswith("delta_") and v is not None}
    assert doc["flagged"] == [k for k, v in moves.items() if abs(v) > 0.3]


def test_the_cost_move_on_figures_made_by_hand():
    """10 kg of PI fuel; the half burns 20 g less (end speed corrected) and takes 1 s more at β 5 g/s:
    fuel + β·time moves by −15 g, −0.15 points. No figure without β or a corrected fuel (a stall)."""
    base = {"fuel_kg": 10.0}
    run_summary = {"fuel_corrected_kg": 9.0, "time_s": 1000.0}
    half = {"fuel_corrected_kg": 8.98, "time_s": 1001.0}
    assert cost_move_pct(base, run_summary, half, 5.0) == pytest.approx(-0.15, abs=1e-12)
    assert cost_move_pct(base, run_summary, {**half, "time_s": 1004.0}, 5.0) == pytest.approx(0.0, abs=1e-12)
    assert cost_move_pct(base, run_summary, half, None) is None
    assert cost_move_pct(base, run_summary, {**half, "fuel_corrected_kg": None}, 5.0) is None


def test_the_table_prints_each_move_and_flags_those_beyond_a_third_of_a_point(checked):
    doc, stdout, _ = checked
    conv = doc["convergence"]
    # At δ 0.4 km/h and S 50 m this descent is far from converged: the coarse grid cannot coast.
    assert abs(conv["delta_fuel_pct_half_delta"]) > 0.3
    for label, key in (
        ("Δfuel vs PI δ/2 [pts]", "delta_fuel_pct_half_delta"),
        ("Δtrip time vs PI S/2", "delta_time_pct_half_stage"),
    ):
        line = next(line for line in stdout.splitlines() if line.startswith(label))
        assert f"{conv[key]:+.2f}" in line
        assert ("not converged" in line) == (key in conv["flagged"])


def test_with_pedal_levels_the_check_also_doubles_them_and_reports_that_move(tmp_path):
    """A run planning 4 pedal levels off the grid is checked at 8 levels too (its control resolution
    halved, δ and S kept); the halved run is the MPC run alone with `pedal_levels=8`."""
    out = tmp_path / "levels"
    args = ["--road", HILL, "--set", "pedal_levels=4", "--check-convergence", "--out", out]
    result = run("simulate", *args)
    assert result.exit_code == 0, result.stderr
    conv = json.loads((out / "summary.json").read_text())["convergence"]
    assert (conv["half_pedal"]["pedal_levels"], conv["half_pedal"]["delta_kmh"]) == (8, 0.05)
    assert conv["half_pedal"]["stage_m"] == 25.0
    alone = simulate(load_road(HILL), load_run_config(overrides=["pedal_levels=8"]), "mpc").summary
    assert conv["half_pedal"]["fuel_kg"] == alone["fuel_kg"]
    line = next(line for line in result.stdout.splitlines() if line.startswith("Δfuel vs PI 2×levels [pts]"))
    assert f"{conv['delta_fuel_pct_half_pedal']:+.2f}" in line
    # Without pedal levels there is no such run; past the levels' range, the check says why.
    assert "half_pedal" not in halved_configs(load_run_config())
    too_many = run("simulate", "--road", HILL, "--set", "pedal_levels=121", "--check-convergence", "--out", out / "x")
    assert too_many.exit_code == 2 and too_many.stderr.count("\n") == 1
    assert "pedal_levels" in too_many.stderr and "twice pedal_levels = 121" in too_many.stderr


def test_replay_runs_the_check_again(checked, tmp_path):
    doc, _, out = checked
    result = run("simulate", "--replay", out / "summary.json", "--out", tmp_path / "again")
    assert result.exit_code == 0, result.stderr
    again = json.loads((tmp_path / "again" / "summary.json").read_text())
    assert again["run"]["check_convergence"] is True
    assert again["convergence"]["half_stage"]["fuel_kg"] == doc["convergence"]["half_stage"]["fuel_kg"]


def test_the_check_needs_both_controllers(tmp_path):
    result = run("simulate", "--road", HILL, "--controller", "mpc", "--check-convergence", "--out", tmp_path / "x")
    assert result.exit_code == 2
    assert result.stderr.strip().count("\n") == 0 and "--check-convergence" in result.stderr
    assert "expected --controller both" in result.stderr
    assert not (tmp_path / "x").exists()


# ---------------------------------------------------------------------------------------------
# The default controller converges; the thesis's does not.

ROADS = Path(__file__).resolve().parents[1] / "roads"
SHARED_ROADS = Path(__file__).resolve().parents[1] / ".." / "shared" / "roads"
TOLERANCE_POINTS = 0.15
"""Issue 12's bar: Δfuel within 0.15 points of its value at half δ and at half S."""


def fuel_moves(road_path: Path, *configs: str) -> tuple[float, float]:
    """How far Δfuel moves at δ/2 and at S/2 [points] for the MPC with these --config overlays."""
    road = load_road(road_path)
    config = load_run_config(config_paths=configs)
    results = {name: simulate(road, config, name) for name in ("pi", "mpc")}
    halves = halved_configs(config)
    doc = convergence_document(results, run_halves(road, halves), halves)
    return doc["delta_fuel_pct_half_delta"], doc["delta_fuel_pct_half_stage"]


# Not reached by the fuel + β·time default (issue 25, item 5): that cost is nearly flat along the
# trade of fuel for time, so a finer grid or stage moves the plan along it. On the 500 m 2 % climb
# δ 0.05 km/h slows down before the climb (−1.58 % fuel, +2.8 % time) where δ 0.025 km/h holds v_ref,
# two plans whose costs (fuel + β·time) differ by 0.1 %. On the 500 m 3 % descent, at q_neutral 30,
# S/2 moves +0.16 points (the coast into the descent starts a stage apart).
NOT_CONVERGED = pytest.mark.xfail(
    reason=f"the fuel_time default's raw Δfuel moves more than {TOLERANCE_POINTS} points at δ/2 or S/2 (issue 25)",
    strict=True,
)


@pytest.mark.parametrize("section", ["hill_L500_A-3", "hill_L500_A2"])
def test_the_thesis_preset_does_not_converge_on_a_descent_and_a_climb(section):
    thesis = fuel_moves(ROADS / f"{section}.csv", "thesis")
    assert max(abs(move) for move in thesis) > 0.3, thesis


@pytest.mark.slow
@pytest.mark.parametrize(
    "section", [pytest.param("hill_L500_A-3", marks=NOT_CONVERGED), pytest.param("hill_L500_A2", marks=NOT_CONVERGED)]
)
def test_the_default_converges_on_a_descent_and_a_climb(section):
    default = fuel_moves(ROADS / f"{section}.csv")
    assert all(abs(move) <= TOLERANCE_POINTS for move in default), default


@pytest.mark.slow
@pytest.mark.skipif(not SHARED_ROADS.is_dir(), reason="shared road profiles (../shared/roads) not present")
@pytest.mark.parametrize("road", ["eu_vecto_longhaul_2015_108km", "eu_vecto_longhaul_100km"])
def test_the_default_converges_on_the_vecto_long_haul_cycles(road):
    # Solving the horizon every stage, the 100 km cycle moved +0.17 points at S/2. Re-planning every
    # 750 m at q_neutral 30 and Q4 60, the 108 km cycle moves −0.13 at δ/2 and +0.04 at S/2, the
    # 100 km one +0.10 and +0.11 (docs/validation/convergence.md).
    moves = fuel_moves(SHARED_ROADS / f"{road}.csv")
    assert all(abs(move) <= TOLERANCE_POINTS for move in moves), moves

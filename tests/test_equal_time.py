"""Comparisons at equal trip time and end speed: the PI re-tuned to a target trip time, the
end-speed correction, and the fuel–time cost's derived β holding v_ref on a flat road."""

from __future__ import annotations

import json
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from typer.testing import CliRunner

from table_text import parse_table
from truckmpc import load_road, load_run_config, simulate
from truckmpc.cli import app
from truckmpc.equal_time import TIME_TOLERANCE, EqualTime, baseline_runner, equal_time
from truckmpc.fuel import kinetic_correction
from truckmpc.roads import RoadProfile, make_section

runner = CliRunner()
SHARED_ROADS = Path(__file__).resolve().parents[1] / ".." / "shared" / "roads"
EPA = SHARED_ROADS / "us_epa_gem_ph2_grade_20km.csv"


def fake_run(length_m: float, offset_s: float = 0.0):
    """A stand-in for a baseline run whose trip time is length / v_ref + offset: the root is known."""

    def run_at(v_ref_kmh: float):
        time_s = length_m / (v_ref_kmh / 3.6) + offset_s
        summary = {"time_s": time_s, "fuel_kg": v_ref_kmh / 100, "start_speed_kmh": 85.0, "end_speed_kmh": v_ref_kmh}
        return SimpleNamespace(stalled=False, message=None, summary=summary)

    return run_at


@pytest.mark.parametrize("true_v_kmh", [71.3, 84.2, 85.0001, 88.77, 99.0])
def test_search_finds_a_known_set_speed(true_v_kmh: float) -> None:
    """Against a trip time made by a known set speed (time = L / v + a fixed stop), the search ends
    within the tolerance, at that set speed, in a handful of runs."""
    run_at = fake_run(50_000.0, offset_s=120.0)
    target_s = run_at(true_v_kmh).summary["time_s"]
    found = equal_time(run_at, 85.0, 6.0, run_at(85.0), target_s, 2.0)
    assert found.reached, found.reason
    assert abs(found.time_s - target_s) <= TIME_TOLERANCE * target_s
    assert found.v_ref_kmh == pytest.approx(true_v_kmh, abs=0.01)
    assert found.runs <= 6


def test_search_says_when_the_time_is_out_of_reach() -> None:
    """A trip time that would need v_ref beyond the search range is not reached, and says why; no
    number stands in for it."""
    run_at = fake_run(50_000.0)
    target_s = 50_000.0 / (120.0 / 3.6)  # 120 km/h: 35 above v_ref
    found = equal_time(run_at, 85.0, 6.0, run_at(85.0), target_s, 2.0)
    assert not found.reached
    assert "cannot reach the trip time" in found.reason and "100.0 km/h" in found.reason
    assert found.document()["not_comparable"] == found.reason


@pytest.mark.skipif(not EPA.is_file(), reason="shared road profiles (../shared/roads) not present")
def test_equal_time_pi_hits_a_time_made_by_another_set_speed() -> None:
    """On a shared road (US EPA 20 km), the PI re-tuned to the trip time of the PI at 83.4 km/h
    reaches it within 0.01 % and lands within 0.05 km/h of 83.4."""
    road = load_road(EPA)
    config = load_run_config()
    run_at = baseline_runner(road, config)
    target_s = run_at(83.4).summary["time_s"]
    found = equal_time(run_at, 85.0, 6.0, simulate(road, config, "pi"), target_s, 2.0)
    assert found.reached, found.reason
    assert abs(found.time_s - target_s) <= TIME_TOLERANCE * target_s
    assert found.v_ref_kmh == pytest.approx(83.4, abs=0.05)


@pytest.mark.slow
@pytest.mark.skipif(not EPA.is_file(), reason="shared road profiles (../shared/roads) not present")
def test_simulate_reports_the_mpc_at_equal_time(tmp_path: Path) -> None:
    """`truckmpc simulate` compares the MPC with the PI driven to the MPC's trip time: the PI's time
    is within 0.01 % of the MPC's, and the equal-time delta is the fuel against that PI."""
    result = runner.invoke(app, ["simulate", "--road", str(EPA), "--out", str(tmp_path / "run"), "--verbose"])
    assert result.exit_code == 0, result.output
    doc = json.loads((tmp_path / "run" / "summary.json").read_text())
    equal = doc["equal_time"]
    assert abs(equal["pi_time_s"] / doc["mpc"]["time_s"] - 1) <= TIME_TOLERANCE
    assert doc["delta_fuel_equal_time_pct"] == pytest.approx(100 * (doc["mpc"]["fuel_kg"] / equal["pi_fuel_kg"] - 1))
    expected = 100 * (doc["mpc"]["fuel_corrected_kg"] / equal["pi_fuel_corrected_kg"] - 1)
    assert doc["delta_fuel_equal_time_corrected_pct"] == pytest.approx(expected)
    assert parse_table(result.stdout).row("PI re-run: v_ref [km/h]")["mpc"] == f"{equal['pi_v_ref_kmh']:.2f}"


def test_end_speed_correction_prices_the_kinetic_energy_of_a_speed_up() -> None:
    """A PI run that starts at 75 km/h and speeds up to 85 burns more fuel than one started at 85;
    the difference is the kinetic energy gained, priced at the engine's marginal cost, within 10 %
    (the rest is the drag saved while slower), and the corrected fuels agree to 0.3 %."""
    road = make_section("flat", 6000.0, None)
    slow = simulate(road, load_run_config(overrides=["start_speed_kmh=75"]), "pi")
    steady = simulate(road, load_run_config(), "pi")
    c = load_run_config().settings.derived()["kinetic_fuel_g_per_half_v2"]
    extra_kg = slow.summary["fuel_kg"] - steady.summary["fuel_kg"]
    priced_kg = kinetic_correction(slow.summary, c)
    assert priced_kg == pytest.approx(c * 0.5 * ((85 / 3.6) ** 2 - (75 / 3.6) ** 2) / 1000, rel=1e-3)
    assert extra_kg == pytest.approx(priced_kg, rel=0.10)
    assert slow.summary["fuel_corrected_kg"] == pytest.approx(steady.summary["fuel_corrected_kg"], rel=3e-3)


def test_fuel_time_cost_with_the_derived_beta_holds_v_ref_on_a_flat_road() -> None:
    """With β derived from v_ref, the fuel–time controller holds v_ref on a flat road (within
    0.05 km/h, in one gear) at every set speed tried, once it has left the gear the PI's gear logic
    starts it in (at 75 km/h gear 11, where the controller cruises in 12: one change, made by a
    coast, in the first kilometre)."""
    road = make_section("flat", 4000.0, None)
    for v_ref in (75.0, 85.0):
        config = load_run_config(config_paths=["fuel_time"], overrides=[f"v_ref_kmh={v_ref}"])
        result = simulate(road, config, "mpc")
        steady = result.trace["distance_m"] > 1500.0
        speed, gear = result.trace["speed_kmh"][steady], result.trace["gear"][steady]
        assert np.max(np.abs(speed - v_ref)) < 0.05, (v_ref, speed.min(), speed.max())
        assert np.all(gear == gear[0]) and result.summary["gear_shifts"] <= 1
        assert result.summary["settings"]["beta_g_per_s"] > 0


def test_a_larger_beta_buys_time_with_fuel() -> None:
    """On a hilly section, raising β makes the fuel–time controller faster and thirstier: trip time
    falls and fuel rises monotonically over β = 2, 5.6, 12 g/s."""
    road = make_section("hill", 1500.0, 3.0)
    runs = []
    for beta in (2.0, 5.6, 12.0):
        config = load_run_config(config_paths=["fuel_time"], overrides=[f"beta_g_per_s={beta}"])
        runs.append(simulate(road, config, "mpc").summary)
    times = [r["time_s"] for r in runs]
    fuels = [r["fuel_corrected_kg"] for r in runs]
    assert times[0] > times[1] > times[2], times
    assert fuels[0] < fuels[1] < fuels[2], fuels


def test_controller_list_and_comparisons(tmp_path: Path) -> None:
    """`--controller pi,optimal` runs those two; `comparisons` lists each look-ahead controller
    against the PI with the same figures as the top-level deltas; a bad list is one line, exit 2."""
    result = runner.invoke(app, ["simulate", "--controller", "pi,optimal", "--out", str(tmp_path / "run")])
    assert result.exit_code == 0, result.output
    doc = json.loads((tmp_path / "run" / "summary.json").read_text())
    assert {"pi", "optimal"} <= set(doc) and "mpc" not in doc
    [entry] = doc["comparisons"]
    assert entry["controller"] == "optimal" and entry["baseline"] == "pi"
    for key in ("delta_fuel_pct", "delta_time_pct", "delta_fuel_equal_time_pct", "delta_fuel_corrected_pct"):
        assert entry[key] == doc[key]
    for bad in ("pi,bogus", "pi,pi", "mpc,both"):
        failed = runner.invoke(app, ["simulate", "--controller", bad, "--out", str(tmp_path / "bad")])
        assert failed.exit_code == 2 and failed.output.count("\n") == 1 and "--controller" in failed.output
        assert not (tmp_path / "bad").exists()


def test_on_a_road_with_target_speeds_the_search_moves_the_target_offset() -> None:
    """On a road whose target (70 km/h) is below v_ref (85), v_ref only caps it: the equal-time
    baseline moves target_offset_kmh instead (x = v_ref + offset). A trip time made at offset +1.3
    is found there, and the document reports v_ref kept and the offset."""
    road = RoadProfile("target-70", [0.0, 3000.0, 6000.0], [0.0, 0.0, 0.0], target_speed_kmh=[70.0] * 3)
    config = load_run_config()
    run_at = baseline_runner(road, config)
    base = run_at(85.0)
    assert base.summary["mean_speed_kmh"] == pytest.approx(70.0, abs=0.5)
    assert run_at(87.0).summary["mean_speed_kmh"] == pytest.approx(72.0, abs=0.5)
    target_s = run_at(86.3).summary["time_s"]
    c = config.settings.derived()["kinetic_fuel_g_per_half_v2"]
    found = equal_time(run_at, 85.0, 35.0, base, target_s, c, offset_from_kmh=85.0)
    assert found.reached, found.reason
    doc = found.document()
    assert doc["pi_v_ref_kmh"] == 85.0
    assert doc["pi_target_offset_kmh"] == pytest.approx(1.3, abs=0.05)
    assert "pi_target_offset_kmh" not in equal_time(run_at, 85.0, 35.0, base, target_s, c).document()


def test_on_a_road_with_targets_the_v_ref_is_the_kept_one_and_the_offset_the_setting_minus_it():
    """The search variable there is v_ref + target offset: what the result reports as v_ref (in the
    summary and the sweep's columns alike) is the v_ref kept, the offset the difference."""
    found = EqualTime(100.0, setting_kmh=86.5, time_s=100.0, offset_from_kmh=85.0)
    assert (found.v_ref_kmh, found.target_offset_kmh) == (85.0, 1.5)
    doc = found.document()
    assert (doc["pi_v_ref_kmh"], doc["pi_target_offset_kmh"]) == (85.0, 1.5)
    plain = EqualTime(100.0, setting_kmh=83.0, time_s=100.0)
    assert (plain.v_ref_kmh, plain.target_offset_kmh) == (83.0, None)


def test_search_stays_below_the_ceiling_of_drivable_set_speeds() -> None:
    """A time that needs a set speed above the highest the truck can drive (its band's top beyond
    the top speed) is not comparable, and no run is asked for beyond that ceiling."""
    run_at = fake_run(50_000.0)
    asked: list[float] = []

    def counted(v_ref_kmh: float):
        asked.append(v_ref_kmh)
        return run_at(v_ref_kmh)

    target_s = 50_000.0 / (120.0 / 3.6)
    found = equal_time(counted, 110.0, 6.0, run_at(110.0), target_s, 2.0, v_ceiling_kmh=114.5)
    assert not found.reached and "v_ref in 95.0-114.5 km/h" in found.reason
    assert asked and max(asked) <= 114.5


def test_equal_time_near_the_top_speed_clips_the_search_instead_of_failing() -> None:
    """At v_ref 112 km/h (the band's top 117, the truck's top speed 119.90 km/h) a look-ahead run
    5 % faster than the PI would need the PI at some 118 km/h, beyond what the core accepts: the
    search clips to the highest drivable v_ref and reports the comparison as not comparable."""
    from truckmpc.equal_time import equal_time_baselines

    road = make_section("flat", 2000.0, 0.0)
    config = load_run_config(overrides=["v_ref_kmh=112"])
    pi = simulate(road, config, "pi")
    faster = SimpleNamespace(stalled=False, summary={**pi.summary, "time_s": pi.summary["time_s"] * 0.95})
    found = equal_time_baselines(road, config, {"pi": pi, "pcc": faster})["pcc"]
    highest = config.settings.derived()["v_ref_range_kmh"][1]
    assert not found.reached and "cannot reach the trip time" in found.reason
    assert f"{highest:.1f} km/h" in found.reason
    assert max(v for v, _ in found.tried) <= highest

"""A controller told a wrong world: a mass it does not know, a map that is not the road.

Truths constructed here: a map equal to the road (or a mass equal to the truck's) changes nothing
bit for bit; the grade noise has the standard deviation and correlation length asked for; the plant
drives the true road whatever the controller is told; `--controller-road` is recorded and replayed.
"""

from __future__ import annotations

import dataclasses
import json
import math

import numpy as np
from typer.testing import CliRunner

from truckmpc import load_run_config, simulate
from truckmpc import robustness as rb
from truckmpc.cli import app
from truckmpc.equal_time import equal_time_baselines
from truckmpc.roads import RoadProfile, concatenate, make_section, write_road
from vecto_files import write_job

COARSE = ("delta_kmh=0.2", "stage_m=50", "horizon_m=1000")
runner = CliRunner()


def _road() -> RoadProfile:
    parts = [make_section("hill", 600, 3.0, lead_m=300, tail_m=300), make_section("hill", 600, -3.0, lead_m=0)]
    return concatenate(parts, "up-down")


def test_grade_noise_has_the_asked_spread_and_correlation():
    flat = make_section("flat", 200_000)
    told = rb.noisy_map(flat, 0.5, seed=3)
    grade_pct = 100 * np.diff(told.altitude_m) / np.diff(told.distance_m)
    assert abs(np.std(grade_pct) - 0.5) < 0.05
    lag = round(rb.CORRELATION_M / rb.NOISE_STEP_M)
    corr = np.corrcoef(grade_pct[:-lag], grade_pct[lag:])[0, 1]
    assert abs(corr - math.exp(-1.0)) < 0.05
    assert told.length_m == flat.length_m
    assert np.array_equal(told.altitude_m, rb.noisy_map(flat, 0.5, seed=3).altitude_m)
    assert not np.array_equal(told.altitude_m, rb.noisy_map(flat, 0.5, seed=4).altitude_m)


def test_a_map_equal_to_the_road_and_the_true_mass_change_nothing():
    road = _road()
    config = load_run_config(overrides=COARSE)
    plain = simulate(road, config, "mpc")
    copy = RoadProfile("copy", road.distance_m, road.altitude_m)
    told = simulate(dataclasses.replace(road, controller_map=copy), config, "mpc")
    same_mass = simulate(road, load_run_config(overrides=(*COARSE, "controller_mass_kg=40000")), "mpc")
    for other in (told, same_mass):
        assert other.summary["fuel_kg"] == plain.summary["fuel_kg"]
        assert np.array_equal(other.trace["speed_kmh"], plain.trace["speed_kmh"])


def test_the_plant_drives_the_true_road_whatever_the_map_says():
    road = _road()
    config = load_run_config(overrides=COARSE)
    biased = RoadProfile("biased", road.distance_m, road.altitude_m + 0.01 * (road.distance_m - road.distance_m[0]))
    fooled = simulate(dataclasses.replace(road, controller_map=biased), config, "mpc")
    truth = simulate(road, config, "mpc")
    assert np.allclose(fooled.trace["altitude_m"], truth.trace["altitude_m"])
    assert fooled.summary["fuel_kg"] != truth.summary["fuel_kg"]
    # Told of a 1 % climb everywhere, the controller expects to need more power than it does.
    assert not np.array_equal(fooled.trace["pedal"], truth.trace["pedal"])


def test_a_lighter_truck_than_assumed_is_a_different_run():
    road = _road()
    light = ("mass_kg=30000", *COARSE)
    told = simulate(road, load_run_config(overrides=light), "mpc")
    untold = simulate(road, load_run_config(overrides=(*light, "controller_mass_kg=40000")), "mpc")
    assert told.summary["fuel_kg"] != untold.summary["fuel_kg"]


def test_the_study_has_every_case_and_its_references(tmp_path):
    road = _road()
    config = load_run_config(overrides=COARSE)
    rows = rb.study(road, config, "mpc", seeds=(1,))
    assert len(rows) == 1 + 2 * len(rb.MASS_ERRORS) + len(rb.GRADE_SIGMAS_PCT)
    exact = rows[0]
    assert exact["kept_pct"] == 100.0
    pi = simulate(road, config, "pi").summary["fuel_kg"]
    mpc = simulate(road, config, "mpc").summary["fuel_kg"]
    assert math.isclose(exact["delta_fuel_pct"], 100 * (mpc - pi) / pi)
    light = next(row for row in rows if row["mass_kg"] == 30000 and row["controller_mass_kg"] == 30000)
    heavy_config = load_run_config(overrides=(*COARSE, "mass_kg=30000"))
    pi_light = simulate(road, heavy_config, "pi").summary["fuel_kg"]
    mpc_light = simulate(road, heavy_config, "mpc").summary["fuel_kg"]
    assert math.isclose(light["delta_fuel_pct"], 100 * (mpc_light - pi_light) / pi_light)
    text = rb.format_study(rows, "mpc")
    assert text.count("\n") == len(rows) + 1 and "map grade noise 1 %" in text
    assert text.startswith("mpc against the PI on the true truck and road, at equal trip time and end speed")


def test_the_study_quotes_the_headline_from_the_corrected_fuels_at_equal_time():
    """The exact case's headline is the MPC's corrected fuel against the PI re-run at its trip time."""
    road = _road()
    config = load_run_config(overrides=COARSE)
    row = rb.run_case(road, config, rb.Case("exact", 40000.0, 40000.0))
    runs = {"pi": simulate(road, config, "pi"), "mpc": simulate(road, config, "mpc")}
    pi_at_mpc_time = equal_time_baselines(road, config, runs)["mpc"].consumed_corrected
    own = runs["mpc"].summary["fuel_corrected_kg"]
    assert math.isclose(row["headline_pct"], 100 * (own - pi_at_mpc_time) / pi_at_mpc_time)
    assert math.isclose(row["saved_kg"], pi_at_mpc_time - own)


def test_controller_road_is_recorded_and_replayed(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    road = _road()
    write_road(road, tmp_path / "road.csv")
    told = rb.noisy_map(road, 1.0, seed=1)
    write_road(told, tmp_path / "map.csv")
    args = ["simulate", "--road", "road.csv", "--controller-road", "map.csv", "--out", "a", *_sets()]
    first = runner.invoke(app, args)
    assert first.exit_code == 0, first.output
    doc = json.loads((tmp_path / "a" / "summary.json").read_text())
    assert doc["run"]["controller_road"]["path"].endswith("map.csv")
    assert (
        first.stdout.splitlines()[0].startswith("road road: ")
        and "(the controllers planned on map.csv)" in (first.stdout.splitlines()[0])
    )
    again = runner.invoke(app, ["simulate", "--replay", "a/summary.json", "--out", "b"])
    assert again.exit_code == 0, again.output
    replayed = json.loads((tmp_path / "b" / "summary.json").read_text())
    assert replayed["mpc"]["fuel_kg"] == doc["mpc"]["fuel_kg"]
    plain = runner.invoke(app, ["simulate", "--road", "road.csv", "--out", "c", *_sets()])
    assert plain.exit_code == 0, plain.output
    assert "planned on" not in plain.stdout.splitlines()[0]
    assert json.loads((tmp_path / "c" / "summary.json").read_text())["mpc"]["fuel_kg"] != doc["mpc"]["fuel_kg"]


def test_a_map_that_does_not_span_the_road_is_one_line_exit_2(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    write_road(_road(), tmp_path / "road.csv")
    write_road(make_section("flat", 500), tmp_path / "short.csv")
    result = runner.invoke(app, ["simulate", "--road", "road.csv", "--controller-road", "short.csv", *_sets()])
    assert result.exit_code == 2
    lines = result.output.strip().splitlines()
    assert len(lines) == 1 and "--controller-road" in lines[0] and "short.csv" in lines[0]


def _sets() -> list[str]:
    return [arg for setting in COARSE for arg in ("--set", setting)]


def test_a_reversed_map_keeps_its_points_along_the_road_and_takes_the_roads_targets(tmp_path):
    road = RoadProfile("r", np.array([0.0, 1000.0, 2000.0]), np.zeros(3), None, np.array([85.0, 60.0, 60.0]))
    # A map 1 % longer than the road, with a bump at 500 m along it.
    told = RoadProfile("m", np.array([0.0, 500.0, 2020.0]), np.array([0.0, 5.0, 0.0]))
    write_road(told, tmp_path / "map.csv")
    from truckmpc.record import with_controller_road

    back = with_controller_road(road.reversed(), tmp_path / "map.csv", reverse=True)
    assert back.controller_map is not None
    # The bump at 500 m along the road is at 2000 - 500 = 1500 m driving back.
    assert np.interp(1500.0, back.controller_map.distance_m, back.controller_map.altitude_m) == 5.0
    assert back.controller_map.target_speed_kmh is not None
    assert back.controller_map.target_speed_at(np.array([1500.0]))[0] == 85.0


def test_a_vecto_trucks_other_mass_is_the_same_truck_at_another_load(tmp_path):
    """The robustness study's truck of another mass, for a VECTO truck: its payload changed by the
    difference, so the truck and the run's recorded mass are that mass and nothing else moves;
    the controller told the declared mass models the truck at it; a key the user set over what the
    truck sets (the PI's upshift speeds) stays the user's."""
    job = write_job(tmp_path / "truck")
    shifted = [None if n is None else n + 50.0 for n in load_run_config(job).settings.get("gear_up_rpm")]
    own = f"gear_up_rpm={shifted}".replace("None", "null")
    config = load_run_config(job, overrides=(own,))
    declared_kg = config.truck.mass_kg
    truth = rb._truth(config, declared_kg - 5000.0, "truck 5 t lighter")
    assert truth.truck.mass_kg == declared_kg - 5000.0 == truth.settings.get("mass_kg")
    assert truth.truck.payload_kg == config.truck.payload_kg - 5000.0
    # The same as the truck loaded so from its file (its tyres' rolling resistance follows the load).
    loaded = load_run_config(job, overrides=(f"payload_kg={truth.truck.payload_kg}", own))
    assert truth.settings.values() == {**loaded.settings.values(), "controller_mass_kg": None}
    assert list(truth.settings.get("gear_up_rpm")) == shifted
    road = make_section("hill", 600, 3.0, lead_m=300, tail_m=300)
    told = truth.with_values({"controller_mass_kg": declared_kg}, "told")
    # The PI holds its set speed whatever it weighs: the lighter truck burns less.
    assert simulate(road, truth, "pi").summary["fuel_kg"] < simulate(road, config, "pi").summary["fuel_kg"]
    assert simulate(road, told, "mpc").summary["fuel_kg"] != simulate(road, truth, "mpc").summary["fuel_kg"]


def test_a_vecto_truck_is_made_no_lighter_than_empty(tmp_path, monkeypatch):
    """At a payload below a quarter of the truck's mass, the lighter truck is the empty truck."""
    job = write_job(tmp_path / "truck")
    config = load_run_config(job, overrides=("payload_kg=2600",))
    seen = []
    monkeypatch.setattr(rb, "run_case", lambda road, config, case, controller: seen.append(case) or _row(case))
    rb.study(_road(), config, "mpc", seeds=(1,))
    masses = sorted({case.mass_kg for case in seen})
    empty_kg = config.truck.mass_kg - 2600.0
    assert masses == [empty_kg, config.truck.mass_kg, 1.25 * config.truck.mass_kg]
    assert any(case.label == f"truck {empty_kg / 1000:.3g} t, told it (reference)" for case in seen)


def _row(case: rb.Case) -> dict:
    return {
        "mass_kg": case.mass_kg,
        "controller_mass_kg": case.controller_mass_kg,
        "grade_sigma_pct": 0.0,
        "headline_pct": None,
    }

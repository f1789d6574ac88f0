"""Work estimates: settings that would run for hours are refused up front (unless --force), and a
sweep's many combinations are validated quickly."""

from __future__ import annotations

import time
from pathlib import Path

import pytest
from typer.testing import CliRunner

import truckmpc.sweep.run as sweep_run
import truckmpc.workload as workload
from truckmpc import default_test_track, load_road, load_run_config, simulate
from truckmpc.cli import app
from truckmpc.sweep import expand_grid, parse_axis
from truckmpc.sweep.cells import yaml_text
from truckmpc.sweep.inputs import Base, Combinations

runner = CliRunner()
REPO = Path(__file__).resolve().parents[1]
TEST_TRACK = REPO / "roads" / "test-track.csv"


def run(*args: object):
    return runner.invoke(app, [str(a) for a in args])


@pytest.fixture(autouse=True)
def in_tmp(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "short.csv").write_text("distance_m,altitude_m\n0,0\n150,1.5\n300,0\n")
    return tmp_path


def assert_refused(result, where: str) -> None:
    assert result.exit_code == 2, result.output
    assert result.stderr.count("\n") == 1 and "Traceback" not in result.output
    assert result.stderr.startswith(f"error: {where}: about "), result.stderr
    assert "of work at this setting (limit 1 h); pass --force to run it anyway" in result.stderr


def hours_in(message: str) -> float:
    figure, unit = message.split("about ", 1)[1].split()[:2]
    return float(figure) * {"h": 1.0, "days": 24.0}[unit]


def test_a_tiny_plant_step_is_refused_with_its_estimate(in_tmp):
    result = run("simulate", "--controller", "pi", "--set", "plant_dt_s=1e-9", "--out", "res")
    assert_refused(result, "--set plant_dt_s")
    # The 8.5 km test track at 85 km/h in steps of 1e-9 s: 3.6e11 steps; the Rust loop takes about
    # 1e-7 s a step, so hours, not minutes nor years.
    assert 1 < hours_in(result.stderr) < 100
    assert not (in_tmp / "res").exists()


def test_a_fine_speed_grid_is_refused_naming_where_it_was_set(in_tmp):
    # Solving the horizon every stage (replan_m 0), δ 0.001 km/h is hours of work.
    fine = ("--set", "replan_m=0", "--set", "delta_kmh=0.001")
    assert_refused(run("simulate", *fine, "--out", "res"), "--set delta_kmh")
    (in_tmp / "fine.yaml").write_text("# overlay\nreplan_m: 0\ndelta_kmh: 0.001\n")
    assert_refused(run("simulate", "--config", "fine.yaml", "--out", "res"), "fine.yaml:3: key 'delta_kmh'")
    assert not (in_tmp / "res").exists()


def test_pedal_levels_whose_arcs_alone_take_hours_are_refused_naming_the_key(in_tmp):
    # 10 000 km of flat road: at the defaults minutes of DP; 120 pedal levels add about
    # 400 000 stages × 261 grid points × 120 levels arcs of a few tenths of a microsecond each.
    (in_tmp / "long.csv").write_text("distance_m,altitude_m\n0,0\n10000000,0\n")
    long_road = ("--road", "long.csv", "--controller", "mpc", "--out", "res")
    assert_refused(run("simulate", *long_road, "--set", "pedal_levels=120"), "--set pedal_levels")
    config = load_run_config()
    assert workload.run_work(load_road(in_tmp / "long.csv"), config, "mpc").total_s < workload.MAX_WORK_S
    assert not (in_tmp / "res").exists()


def test_a_grid_too_large_for_memory_is_refused_naming_its_size(in_tmp, monkeypatch):
    # delta 0.01 km/h over a 10 km/h band (v_dec 5) and 79 stages a solve (a 1500 m horizon and the
    # 19 stages decided from each solve of it, replan_m 500): 1001² × 79 units of 2.5 bytes, 198 MB.
    monkeypatch.setattr(workload, "memory_limit_bytes", lambda: 100e6)
    result = run(
        "simulate",
        "--road",
        "short.csv",
        "--set",
        "v_dec_kmh=5",
        "--set",
        "horizon_m=1500",
        "--set",
        "replan_m=500",
        "--set",
        "delta_kmh=0.01",
        "--out",
        "res",
    )
    assert result.exit_code == 2 and result.stderr.count("\n") == 1, result.output
    assert result.stderr.startswith("error: --set delta_kmh: about 0.198 GB of memory for the dynamic program")
    assert "(limit 0.1 GB, half this machine's); pass --force" in result.stderr
    assert not (in_tmp / "res").exists()
    assert run("simulate", "--road", "short.csv", "--set", "delta_kmh=0.2", "--out", "res").exit_code == 0


def test_force_runs_what_the_estimate_refuses(in_tmp, monkeypatch):
    monkeypatch.setattr(workload, "MAX_WORK_S", 1e-6)
    args = ["simulate", "--road", "short.csv", "--controller", "pi", "--out", "res"]
    assert run(*args).exit_code == 2 and not (in_tmp / "res").exists()
    forced = run(*args, "--force")
    assert forced.exit_code == 0, forced.output
    assert (in_tmp / "res" / "summary.json").exists()


def test_force_runs_a_sweep_the_estimate_refuses(in_tmp, monkeypatch):
    monkeypatch.setattr(sweep_run, "MAX_WORK_S", 1e-6)
    args = ["sweep", "--road", "short.csv", "--grid", "horizon_m=250,500", "--jobs", "1", "--out", "sw"]
    refused = run(*args)
    assert refused.exit_code == 2 and refused.stderr.startswith("error: --grid: about ")
    assert "pass --force" in refused.stderr and not (in_tmp / "sw").exists()
    forced = run(*args, "--force")
    assert forced.exit_code == 0, forced.output
    assert len((in_tmp / "sw" / "sweep.csv").read_text().splitlines()) == 3


@pytest.mark.slow
def test_a_sweep_counts_the_memory_of_the_runs_it_holds_at_once(in_tmp, monkeypatch):
    # Over a 10 km/h band (v_dec 5), DPs of 150.3 MB (δ 0.01 km/h) and 124.2 MB (δ 0.011): either fits
    # in 200 MB, both at once do not; the PI holds none, and a δ 0.2 DP (0.4 MB) beside the 150 MB one fits.
    monkeypatch.setattr(sweep_run, "memory_limit_bytes", lambda: 200e6)
    band = ("--set", "v_dec_kmh=5", "--set", "horizon_m=1500", "--set", "replan_m=0")  # 60 stages a solve
    fits = run("sweep", "--road", "short.csv", *band, "--grid", "delta_kmh=0.01,0.2", "--jobs", "2", "--out", "ok")
    assert fits.exit_code == 0, fits.output
    args = ["sweep", "--road", "short.csv", *band, "--grid", "delta_kmh=0.01,0.011", "--out", "sw"]
    refused = run(*args, "--jobs", "2")
    assert refused.exit_code == 2, refused.output
    assert refused.stderr.startswith("error: --grid: about 0.275 GB of memory for the dynamic program for 3 runs on 2")
    assert "(limit 0.2 GB, half this machine's)" in refused.stderr
    assert not (in_tmp / "sw").exists()
    single = run(*args, "--jobs", "1")
    assert single.exit_code == 0, single.output


def test_the_estimate_is_within_a_factor_of_ten_of_a_measured_run():
    road = default_test_track()
    for overrides in ((), ("delta_kmh=0.1", "horizon_m=2000"), ("pedal_levels=16",)):
        config = load_run_config(overrides=overrides)
        for controller in ("pi", "mpc"):
            started = time.perf_counter()
            simulate(road, config, controller)
            measured_s = time.perf_counter() - started
            estimate_s = workload.run_work(road, config, controller).total_s
            assert measured_s / 10 < estimate_s < measured_s * 10, (overrides, controller, measured_s, estimate_s)


@pytest.mark.slow
def test_a_sweep_of_many_combinations_is_validated_quickly_and_refused_with_its_estimate(in_tmp):
    # 30 000 combinations of MPC runs of about a second each (δ 0.05 km/h over the test track, solving
    # every stage): hours on 2 processes. Validating them through the files took 6.7 ms each (over
    # three minutes) before anything was said.
    started = time.perf_counter()
    result = run(
        "sweep",
        "--road",
        TEST_TRACK,
        "--grid",
        "q_fuel=1:300:1",
        "--grid",
        "q_brake=1:100:1",
        "--set",
        "delta_kmh=0.05",
        "--set",
        "replan_m=0",
        "--jobs",
        "2",
        "--out",
        "sw",
    )
    elapsed_s = time.perf_counter() - started
    assert result.exit_code == 2, result.output
    assert result.stderr.startswith("error: --grid: about ") and "for 30001 runs on 2 processes" in result.stderr
    assert 1 < hours_in(result.stderr) < 100
    assert elapsed_s < 30 and not (in_tmp / "sw").exists()


@pytest.mark.parametrize(
    "grid",
    [
        ["mass_kg=20000,40000", "allow_neutral=true,false", "neutral_rule=nearest,interpolate"],
        ["v_ref_kmh=70:90:10", "k_lim=null,4", "delta_kmh=0.1,0.5", "start_speed_kmh=null,60.5"],
    ],
)
def test_each_combination_has_the_configuration_load_run_config_gives(grid):
    axes = [parse_axis(text) for text in grid]
    base = Base(None, (), ("v_inc_kmh=6",))
    combinations = Combinations(base, base.config(), axes)
    for values in expand_grid(axes):
        texts = tuple(f"{axis.key}={yaml_text(v)}" for axis, v in zip(axes, values, strict=True))
        expected = load_run_config(overrides=("v_inc_kmh=6", *texts)).settings.values()
        assert combinations.config(values, texts).settings.values() == expected

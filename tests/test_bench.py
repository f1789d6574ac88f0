"""`truckmpc bench`: the documented figures, sane values, the road it names, bad input. No timing
thresholds: the figures depend on the machine and are for people (and CI's gross bound) to read."""

from __future__ import annotations

import json

import numpy as np
import pytest
from typer.testing import CliRunner

from truckmpc.bench import SETTINGS, BenchResult, _first, format_bench
from truckmpc.cli import app
from truckmpc.roads import default_test_track, make_section, write_road

runner = CliRunner()

RUN_KEYS = (
    "stage_m",
    "delta_kmh",
    "horizon_m",
    "allow_neutral",
    "grid",
    "neutral_rule",
    "realtime_ratio",
    "solve_ms_mean",
    "solve_ms_max",
    "solves",
    "infeasible_solves",
    "states_per_solve",
    "transitions_per_solve",
    "ns_per_transition",
    "compute_time_s",
    "time_s",
    "distance_m",
    "fuel_kg",
    "stalled",
    "peak_rss_mb",
)


def _check_runs(runs: list[dict], length_m: float) -> None:
    assert len(runs) == len(SETTINGS)
    assert [{key: run[key] for key in setting} for run, setting in zip(runs, SETTINGS, strict=True)] == list(SETTINGS)
    for run in runs:
        assert set(RUN_KEYS) <= set(run)
        assert not run["stalled"]
        assert run["distance_m"] == pytest.approx(length_m, abs=1e-3)
        for key in (
            "realtime_ratio",
            "solve_ms_mean",
            "solve_ms_max",
            "compute_time_s",
            "time_s",
            "states_per_solve",
            "transitions_per_solve",
            "ns_per_transition",
            "peak_rss_mb",
            "fuel_kg",
        ):
            assert run[key] > 0, key
        assert run["solve_ms_max"] >= run["solve_ms_mean"]
        assert run["transitions_per_solve"] > run["states_per_solve"]  # several ways out of each state
        # one solve per stage, plus the first solve at the start
        assert run["solves"] == pytest.approx(length_m / run["stage_m"] + 1, abs=1)
        assert run["ns_per_transition"] == pytest.approx(run["solve_ms_mean"] * 1e6 / run["transitions_per_solve"])
        assert run["realtime_ratio"] == pytest.approx(run["compute_time_s"] / run["time_s"])
        assert 1 < run["peak_rss_mb"] < 10_000  # MB, not KiB or bytes


@pytest.mark.slow
def test_quick_json_gives_the_documented_figures_per_setting():
    result = runner.invoke(app, ["bench", "--quick", "--json"])
    assert result.exit_code == 0, result.output
    doc = json.loads(result.stdout)
    assert set(doc) == {"road", "runs"}
    # the VECTO road's first 10 km when ../shared is there, else the bundled test track
    assert doc["road"] in ("eu_vecto_longhaul_2015_108km-first10km", "test-track")
    length_m = 10_000.0 if doc["road"].endswith("first10km") else default_test_track().length_m
    _check_runs(doc["runs"], length_m)
    # the worst case searches a bigger space than the other setting, on either grid
    worst_fixed, worst_moving, other_fixed, other_moving = doc["runs"]
    for worst, other in ((worst_fixed, other_fixed), (worst_moving, other_moving)):
        assert worst["states_per_solve"] > other["states_per_solve"]
        assert worst["transitions_per_solve"] > other["transitions_per_solve"]


def test_table_on_a_given_road_names_it_and_each_setting(tmp_path):
    road = tmp_path / "hill.csv"
    write_road(make_section("hill", 300, 2.0, lead_m=200, tail_m=200), road)
    result = runner.invoke(app, ["bench", "--road", str(road), "--set", "neutral_rule=interpolate"])
    assert result.exit_code == 0, result.output
    lines = result.stdout.splitlines()
    assert lines[0].startswith("road hill") and "0.70 km" in lines[0] and str(road) in lines[0]
    assert "S 25 m, δ 0.1 km/h, 3000 m" in lines[1] and "S 50 m, δ 0.2 km/h, 2000 m" in lines[1]
    assert lines[2].count("neutral allowed, fixed grid") == 2 and lines[2].count("neutral allowed, moving grid") == 2
    for label in (
        "realtime ratio",
        "solve time mean [ms]",
        "transitions per solve",
        "time per transition [ns]",
        "peak memory [MB]",
    ):
        assert any(line.startswith(label) for line in lines), label


def test_format_bench_marks_the_fallback_road_and_missing_figures():
    run = (
        dict.fromkeys(RUN_KEYS, 1.0)
        | dict(SETTINGS[0])
        | {"grid": "moving", "solves": 3, "infeasible_solves": 0, "ns_per_transition": None}
    )
    text = format_bench(BenchResult("test-track", None, 8500.0, True, [run]))
    lines = text.splitlines()
    assert lines[0] == "road test-track: 8.50 km, bundled; ../shared/roads/eu_vecto_longhaul_2015_108km.csv not found"
    assert next(line for line in lines if line.startswith("time per transition")).endswith(" -")


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--set", "stage_m=50"], "--set stage_m: the benchmark fixes"),
        (["--set", "no_such_key=1"], "no_such_key"),
        (["--road", "missing.csv"], "missing.csv"),
    ],
)
def test_bad_input_is_one_error_line(args, message, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    result = runner.invoke(app, ["bench", "--quick", *args])
    assert result.exit_code == 2
    assert result.stderr.startswith("error: ") and message in result.stderr
    assert len(result.stderr.strip().splitlines()) == 1


def test_first_keeps_the_start_of_a_road_and_interpolates_its_end():
    road = make_section("hill", 500, 3.0, lead_m=500, tail_m=500)
    first = _first(road, 750.0)
    assert first.name == f"{road.name}-first0.75km"
    assert first.length_m == pytest.approx(750.0)
    assert first.altitude_m[-1] == pytest.approx(np.interp(750.0, road.distance_m, road.altitude_m))
    assert _first(road, 10_000.0) is road

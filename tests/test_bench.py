"""`truckmpc bench`: the documented figures, sane values, the road it names, bad input. No timing
thresholds: the figures depend on the machine and are for people (and CI's gross bound) to read."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from truckmpc.bench import SETTINGS, BenchResult, cases_to_run, format_bench
from truckmpc.bench.runs import _first
from truckmpc.cli import app
from truckmpc.config import load_run_config
from truckmpc.roads import default_test_track, make_section, write_road

runner = CliRunner()

RUN_KEYS = (
    "case",
    "label",
    "road",
    "path",
    "fallback",
    "length_m",
    "stage_m",
    "delta_kmh",
    "horizon_m",
    "replan_m",
    "allow_neutral",
    "grid",
    "neutral_rule",
    "realtime_ratio",
    "solve_ms_mean",
    "solve_ms_max",
    "solves",
    "horizon_solves",
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
    """Each case's run, at its settings: the default's configured ones, the worst case's fixed ones."""
    cases = cases_to_run()
    assert [run["case"] for run in runs] == [case["case"] for case in cases]
    own = load_run_config().mpc
    for run, case in zip(runs, cases, strict=True):
        expected = case["settings"] or {key: getattr(own, key) for key in SETTINGS}
        assert {key: run[key] for key in SETTINGS} == expected
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
def test_quick_json_gives_the_documented_figures_per_case():
    result = runner.invoke(app, ["bench", "--quick", "--json"])
    assert result.exit_code == 0, result.output
    doc = json.loads(result.stdout)
    assert set(doc) == {"runs"}
    runs = doc["runs"]
    # each case's shared road's first 10 km when ../shared is there, else the bundled test track
    shared = not runs[0]["fallback"]
    names = [run["road"] for run in runs]
    if shared:
        assert names == [Path(case["road"]).stem + "-first10km" for case in cases_to_run()]
    else:
        assert set(names) == {"test-track"}
    _check_runs(runs, 10_000.0 if shared else default_test_track().length_m)
    # the default solves its horizon every replan_m and decides the stages between from that solve's
    # cost-to-go; the thesis's worst case solves its horizon every stage
    default, _, worst, *tractor = runs
    assert worst["horizon_solves"] == worst["solves"]
    assert default["horizon_solves"] < default["solves"] / 10
    # VECTO's tractor where its files are found, on the same road as the first default run
    assert [run["label"] for run in tractor] == [default["label"]] * len(tractor)


def test_table_on_a_given_road_names_it_and_each_case(tmp_path):
    road = tmp_path / "hill.csv"
    write_road(make_section("hill", 300, 2.0, lead_m=200, tail_m=200), road)
    result = runner.invoke(app, ["bench", "--road", str(road), "--set", "neutral_rule=interpolate"])
    assert result.exit_code == 0, result.output
    lines = result.stdout.splitlines()
    assert lines[0].startswith("road hill") and "0.70 km" in lines[0] and str(road) in lines[0]
    assert lines[1].count("default, hill") == 2 and lines[1].count("thesis worst case, hill") == 1
    own = load_run_config().mpc
    assert f"S {own.stage_m:g} m, δ {own.delta_kmh:g} km/h, {own.horizon_m:g} m" in lines[2]
    assert "S 25 m, δ 0.1 km/h, 3000 m" in lines[2]
    assert "neutral allowed, fixed grid" in lines[3]
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
        | dict(SETTINGS)
        | {"case": "default", "label": "test-track", "road": "test-track", "path": None, "fallback": True}
        | {"length_m": 8500.0, "solves": 3, "horizon_solves": 3, "infeasible_solves": 0, "ns_per_transition": None}
    )
    text = format_bench(BenchResult([run]))
    lines = text.splitlines()
    assert lines[0] == "road test-track: 8.50 km, bundled; ../shared/roads not found"
    assert "default, test-track" in lines[1]
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

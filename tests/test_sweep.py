"""`truckmpc sweep`: grid parsing, rows, PI reuse, resume, parallel runs, bad axes, --reverse."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

import truckmpc.sweep.task as sweep_task
from truckmpc import load_road, load_run_config, make_section, run_sweep, simulate, write_road
from truckmpc.cli import app
from truckmpc.sweep import (
    PARTIAL_NAME,
    SWEEP_COLUMNS,
    Axis,
    SweepError,
    expand_grid,
    parse_axis,
    plan_sweep,
)
from truckmpc.sweep.cells import cell, parse_cell
from truckmpc.sweep.columns import MPC_FIELDS, PI_FIELDS, WALL_TIME_COLUMNS, result_cells

runner = CliRunner()


@pytest.fixture(scope="module")
def descent(tmp_path_factory) -> Path:
    """A short road: 100 m flat, 300 m at -3 %, 100 m flat (a PI run brakes, the MPC coasts)."""
    path = tmp_path_factory.mktemp("roads") / "descent.csv"
    write_road(make_section("hill", 300, -3.0, lead_m=100, tail_m=100), path)
    return path


@pytest.fixture(scope="module")
def flat(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("roads") / "flat.csv"
    write_road(make_section("flat", 400), path)
    return path


@pytest.fixture
def count_runs(monkeypatch):
    """Count the simulate() calls per controller of in-process (--jobs 1) sweeps."""
    counts = {"pi": 0, "mpc": 0}

    def counted(road, config, controller="pi"):
        counts[controller] += 1
        return simulate(road, config, controller)

    monkeypatch.setattr(sweep_task, "simulate", counted)
    return counts


def read_csv(path: Path) -> list[dict[str, str]]:
    with path.open(newline="", encoding="utf-8") as handle:
        return list(csv.DictReader(handle))


def untimed(rows: list[dict[str, str]]) -> list[dict[str, str]]:
    return [{k: v for k, v in row.items() if k not in WALL_TIME_COLUMNS} for row in rows]


# ---------------------------------------------------------------------------------------------
# Axes and the grid


@pytest.mark.parametrize(
    ("text", "values"),
    [
        ("horizon_m=250:3000:250", tuple(range(250, 3001, 250))),
        ("delta_kmh=0.1:0.3:0.1", (0.1, 0.2, 0.3)),  # exactly these floats: no 0.30000000000000004
        ("horizon_m=0.25:1:0.25", (0.25, 0.5, 0.75, 1.0)),
        ("horizon_m=100:350:100", (100, 200, 300)),  # stop is included only when it is on the grid
        ("delta_kmh=0.1,0.2", (0.1, 0.2)),
        ("allow_neutral=true,false", (True, False)),
        ("neutral_rule=nearest,interpolate", ("nearest", "interpolate")),
        ("k_lim=null,8", (None, 8)),
        ("stage_m = 25, 50", (25, 50)),
    ],
)
def test_parse_axis(text, values):
    axis = parse_axis(text)
    assert axis.key == text.partition("=")[0].strip()
    assert axis.values == values
    assert [type(v) for v in axis.values] == [type(v) for v in values]


@pytest.mark.parametrize(
    "text",
    [
        "horizon_m",
        "=1,2",
        "horizon_m=",
        "horizon_m=1:2",
        "horizon_m=3:1:1",
        "horizon_m=1:3:0",
        "horizon_m=a:b:c",
        "horizon_m=1,,2",
        "horizon_m=1,1",
        "horizon_m=0:1e9:1",
    ],
)
def test_parse_axis_rejects(text):
    with pytest.raises(SweepError, match=r"^--grid "):
        parse_axis(text)


def test_expand_grid_last_axis_fastest():
    axes = [Axis("horizon_m", (250, 500, 750)), Axis("delta_kmh", (0.1, 0.2)), Axis("stage_m", (25, 50))]
    grid = expand_grid(axes)
    assert len(grid) == 12
    assert grid[:3] == [(250, 0.1, 25), (250, 0.1, 50), (250, 0.2, 25)]
    assert expand_grid([]) == [()]


# ---------------------------------------------------------------------------------------------
# Rows


def test_rows_columns_and_deltas(descent, tmp_path, count_runs):
    result = run_sweep([descent], ["horizon_m=250,500", "delta_kmh=0.1,0.2"], tmp_path / "out", jobs=1)
    rows = read_csv(tmp_path / "out" / "sweep.csv")
    header = list(rows[0])
    assert header == ["road", "direction", "horizon_m", "delta_kmh", *SWEEP_COLUMNS]
    for column in (
        "pi_fuel_kg",
        "pi_time_s",
        "pi_end_speed_kmh",
        "mpc_fuel_kg",
        "mpc_time_s",
        "mpc_end_speed_kmh",
        "mpc_delta_fuel_pct",
        "mpc_delta_time_pct",
        "mpc_realtime_ratio",
        "mpc_solve_ms_mean",
        "mpc_solve_ms_max",
        "mpc_infeasible_solves",
        "mpc_neutral_distance_m",
        "pi_brake_energy_kj",
        "mpc_brake_energy_kj",
        "pi_stalled",
        "mpc_stalled",
    ):
        assert column in header
    assert [(r["horizon_m"], r["delta_kmh"]) for r in rows] == [
        ("250", "0.1"),
        ("250", "0.2"),
        ("500", "0.1"),
        ("500", "0.2"),
    ]
    assert {r["road"] for r in rows} == {"descent"} and {r["direction"] for r in rows} == {"forward"}
    for row in rows:
        pi_fuel, mpc_fuel = float(row["pi_fuel_kg"]), float(row["mpc_fuel_kg"])
        pi_time, mpc_time = float(row["pi_time_s"]), float(row["mpc_time_s"])
        assert float(row["mpc_delta_fuel_pct"]) == pytest.approx(100 * (mpc_fuel - pi_fuel) / pi_fuel, rel=1e-12)
        assert float(row["mpc_delta_time_pct"]) == pytest.approx(100 * (mpc_time - pi_time) / pi_time, rel=1e-12)
        assert row["pi_stalled"] == row["mpc_stalled"] == "false"
        assert float(row["mpc_realtime_ratio"]) > 0
        equal_fuel = float(row["mpc_equal_time_pi_fuel_kg"])
        assert float(row["mpc_delta_fuel_equal_time_pct"]) == pytest.approx(
            100 * (mpc_fuel / equal_fuel - 1), rel=1e-12
        )
        corrected = float(row["mpc_fuel_corrected_kg"]) / float(row["mpc_equal_time_pi_fuel_corrected_kg"])
        assert float(row["mpc_delta_fuel_equal_time_corrected_pct"]) == pytest.approx(100 * (corrected - 1), rel=1e-12)
    assert untimed(result.rows) == untimed(rows)
    assert count_runs == {"pi": 1, "mpc": 4} and (result.pi_runs, result.mpc_runs) == (1, 4)
    # The same figures as simulate itself gives for one of the rows.
    config = load_run_config(overrides=("horizon_m=500", "delta_kmh=0.2"))
    road = load_road(descent)
    assert float(rows[3]["mpc_fuel_kg"]) == simulate(road, config, "mpc").summary["fuel_kg"]
    assert float(rows[3]["pi_fuel_kg"]) == simulate(road, config, "pi").summary["fuel_kg"]
    settings = json.loads((tmp_path / "out" / "sweep.json").read_text())
    assert [a["key"] for a in settings["grid"]] == ["horizon_m", "delta_kmh"]
    assert settings["roads"][0]["name"] == "descent" and settings["columns"] == header
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == ["sweep.csv", "sweep.json"]


def test_deltas_blank_when_a_run_stalled():
    pi = dict.fromkeys(PI_FIELDS, 1.0) | {"stalled": False}
    mpc = dict.fromkeys(MPC_FIELDS, 1.0) | {"stalled": True}
    cells = dict(zip(SWEEP_COLUMNS, result_cells(pi, mpc), strict=True))
    assert cells["mpc_stalled"] == "true" and cells["mpc_delta_fuel_pct"] == cells["mpc_delta_time_pct"] == ""


@pytest.mark.parametrize(
    ("grid", "pi_runs"),
    [
        (["horizon_m=250,500", "allow_neutral=true,false"], 1),  # MPC keys only: one PI run per road
        (["horizon_m=250,500", "v_ref_kmh=80,85"], 2),  # v_ref is also the PI's
        (["mass_kg=30000,40000", "delta_kmh=0.1,0.2"], 2),  # the vehicle
        (["plant_dt_s=0.05,0.1"], 2),  # the simulation
    ],
)
def test_pi_run_once_per_distinct_pi_setting(descent, flat, tmp_path, count_runs, grid, pi_runs):
    result = run_sweep([descent, flat], grid, tmp_path / "out", jobs=1)
    combos = len(expand_grid([parse_axis(g) for g in grid]))
    assert count_runs == {"pi": 2 * pi_runs, "mpc": 2 * combos}
    assert result.pi_runs == 2 * pi_runs and len(result.rows) == 2 * combos
    by_road = {}
    for row in result.rows:  # rows sharing a PI setting share its figures
        by_road.setdefault(row["road"], set()).add(row["pi_fuel_kg"])
    assert all(len(fuels) == pi_runs for fuels in by_road.values())


def test_reverse_drives_the_road_the_other_way(descent, tmp_path):
    result = run_sweep([descent], ["horizon_m=250"], tmp_path / "out", reverse=True, jobs=1)
    (row,) = result.rows
    assert (row["road"], row["direction"]) == ("descent", "reverse")
    reversed_road = load_road(descent).reversed()
    config = load_run_config(overrides=("horizon_m=250",))
    assert float(row["pi_fuel_kg"]) == simulate(reversed_road, config, "pi").summary["fuel_kg"]
    forward = run_sweep([descent], ["horizon_m=250"], tmp_path / "fwd", jobs=1).rows[0]
    assert float(row["pi_fuel_kg"]) > 3 * float(forward["pi_fuel_kg"])  # the descent became a climb


# ---------------------------------------------------------------------------------------------
# Resume


def test_resume_runs_only_the_missing_rows(descent, tmp_path, count_runs):
    out = tmp_path / "out"
    grid = ["horizon_m=250,500", "delta_kmh=0.1,0.2"]
    full = read_csv(run_sweep([descent], grid, out, jobs=1).csv_path)
    # An interrupted state: two finished rows and a third cut off mid-line, no sweep.csv.
    lines = (out / "sweep.csv").read_text().splitlines(keepends=True)
    (out / "sweep.csv").unlink()
    (out / PARTIAL_NAME).write_text(lines[0] + lines[3] + lines[1] + lines[2][:40])
    count_runs.update(pi=0, mpc=0)
    result = run_sweep([descent], grid, out, jobs=1)
    assert count_runs == {"pi": 0, "mpc": 2}  # the PI figures come from the finished rows
    assert (result.mpc_runs, result.pi_runs, result.resumed_rows) == (2, 0, 2)
    assert untimed(read_csv(out / "sweep.csv")) == untimed(full)  # complete, in grid order
    assert read_csv(out / "sweep.csv")[2] == full[2]  # a resumed row is kept as it was
    assert not (out / PARTIAL_NAME).exists()
    count_runs.update(pi=0, mpc=0)
    assert run_sweep([descent], grid, out, jobs=1).resumed_rows == 4 and count_runs == {"pi": 0, "mpc": 0}


def test_resume_refuses_a_different_sweep(descent, flat, tmp_path):
    out = tmp_path / "out"
    run_sweep([descent], ["horizon_m=250"], out, jobs=1)
    before = (out / "sweep.csv").read_text()
    for roads, grid, overrides in (
        ([descent], ["horizon_m=500"], ()),
        ([flat], ["horizon_m=250"], ()),
        ([descent], ["horizon_m=250"], ("mass_kg=30000",)),
    ):
        result = runner.invoke(
            app,
            [
                "sweep",
                *(f"--road={r}" for r in roads),
                *(f"--grid={g}" for g in grid),
                *(f"--set={s}" for s in overrides),
                "--jobs",
                "1",
                "--out",
                str(out),
            ],
        )
        assert result.exit_code == 2
        assert result.stderr.startswith(f"error: {out} holds a different sweep") and result.stderr.count("\n") == 1
    assert (out / "sweep.csv").read_text() == before


def test_ctrl_c_keeps_finished_rows_and_says_how_to_resume(descent, tmp_path, monkeypatch):
    calls = []

    def interrupted(road, config, controller="pi"):
        calls.append(controller)
        if len(calls) == 4:  # PI, two MPC runs, then Ctrl-C
            raise KeyboardInterrupt
        return simulate(road, config, controller)

    monkeypatch.setattr(sweep_task, "simulate", interrupted)
    out = tmp_path / "out"
    result = runner.invoke(
        app, ["sweep", "--road", str(descent), "--grid", "horizon_m=250,500,750", "--jobs", "1", "--out", str(out)]
    )
    assert result.exit_code == 130
    assert (
        result.stderr
        == f"interrupted: 2 of 3 rows kept in {out / PARTIAL_NAME}; run the same command again to resume\n"
    )
    assert len(read_csv(out / PARTIAL_NAME)) == 2 and not (out / "sweep.csv").exists()


# ---------------------------------------------------------------------------------------------
# The command


def test_cli_parallel_matches_in_process(descent, tmp_path):
    args = ["sweep", "--road", str(descent), "--grid", "horizon_m=250,500", "--grid", "allow_neutral=true,false"]
    one = runner.invoke(app, [*args, "--jobs", "1", "--out", str(tmp_path / "one")])
    two = runner.invoke(app, [*args, "--jobs", "2", "--out", str(tmp_path / "two")])
    assert one.exit_code == 0 and two.exit_code == 0, (one.stderr, two.stderr)
    assert "4 rows: 4 MPC and 1 PI runs" in two.stdout and "Δfuel vs PI" in two.stdout
    assert untimed(read_csv(tmp_path / "one" / "sweep.csv")) == untimed(read_csv(tmp_path / "two" / "sweep.csv"))
    assert two.stderr == ""  # no progress bar when stderr is not a terminal


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--grid", "horizon_m=-250,500"], "error: --grid horizon_m: expected a number in (0, 1000000], got -250"),
        (["--grid", "horizonm=250"], "error: --grid horizonm: unknown key (did you mean 'horizon_m'?)"),
        (["--grid", "allow_neutral=true,maybe"], "error: --grid allow_neutral: expected true or false, got 'maybe'"),
        (["--grid", "horizon_m=250:1000"], "error: --grid horizon_m: expected start:stop:step numbers"),
        (
            ["--grid", "horizon_m=25,250", "--grid", "stage_m=25,50"],
            "error: --grid stage_m: horizon_m: expected at least one stage",
        ),
        (
            ["--grid", "horizon_m=250", "--set", "horizon_m=500"],
            "error: --grid horizon_m: also set with --set horizon_m",
        ),
        (["--grid", "horizon_m=250", "--grid", "horizon_m=500"], "error: --grid horizon_m: axis given twice"),
        (["--grid", "mass_kg=40000,-1"], "error: --grid mass_kg: expected a number in (0, 1000000], got -1"),
    ],
)
def test_cli_bad_axis_is_one_line_and_writes_nothing(descent, tmp_path, args, message):
    out = tmp_path / "out"
    result = runner.invoke(app, ["sweep", "--road", str(descent), *args, "--out", str(out)])
    assert result.exit_code == 2
    assert result.stderr.startswith(message) and result.stderr.count("\n") == 1, result.stderr
    assert not out.exists()


def test_longer_mpc_runs_are_scheduled_first(descent):
    plan = plan_sweep([descent], ["horizon_m=250,500", "delta_kmh=0.1,0.2"])
    costs = {(row.values): row.cost for row in plan.rows}
    assert costs[(500, 0.1)] > costs[(250, 0.1)] and costs[(500, 0.1)] > costs[(500, 0.2)]


@pytest.mark.parametrize("value", [None, True, False, 0, 250, -3, 0.1, 0.30000000000000004, 1e-300, "nearest"])
def test_a_cell_reads_back_as_the_value_written(value):
    text = cell(value)
    back = parse_cell(text)
    assert back == value and type(back) is type(value)


def test_cells_read_by_the_plot_too_tolerate_spaces_and_case():
    assert [parse_cell(t) for t in (" 12 ", "TRUE", "False", "  ", "road-1")] == [12, True, False, None, "road-1"]


def test_check_convergence_adds_the_moves_as_columns(descent, tmp_path):
    """`sweep --check-convergence` drives each MPC row again at half δ and half S; its four columns
    are the moves `simulate --check-convergence` reports for the same settings."""
    out = tmp_path / "conv"
    result = CliRunner().invoke(
        app,
        [
            "sweep",
            "--road",
            str(descent),
            "--grid",
            "delta_kmh=0.2",
            "--check-convergence",
            "--jobs",
            "1",
            "--out",
            str(out),
        ],
    )
    assert result.exit_code == 0, result.output
    [row] = read_csv(out / "sweep.csv")
    run = CliRunner().invoke(
        app,
        [
            "simulate",
            "--road",
            str(descent),
            "--set",
            "delta_kmh=0.2",
            "--check-convergence",
            "--out",
            str(tmp_path / "s"),
        ],
    )
    assert run.exit_code == 0, run.output
    convergence = json.loads((tmp_path / "s" / "summary.json").read_text())["convergence"]
    for key in (
        "delta_fuel_pct_half_delta",
        "delta_fuel_pct_half_stage",
        "delta_time_pct_half_delta",
        "delta_time_pct_half_stage",
    ):
        assert float(row[f"mpc_{key}"]) == pytest.approx(convergence[key], abs=1e-9), key
    # Without the flag the columns are not there, and the two sweeps are not mixed in one directory.
    again = CliRunner().invoke(app, ["sweep", "--road", str(descent), "--grid", "delta_kmh=0.2", "--out", str(out)])
    assert again.exit_code == 2 and "different sweep" in again.output

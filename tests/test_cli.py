"""The `truckmpc` command line: simulate, model stationary, road make/regenerate, and bad input."""

from __future__ import annotations

import importlib.metadata
import json
import re
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest
from typer.testing import CliRunner

from table_text import parse_table
from truckmpc.cli import app
from truckmpc.config import default_config_path

REPO = Path(__file__).resolve().parents[1]
runner = CliRunner()


def run(*args: str):
    return runner.invoke(app, [str(a) for a in args])


@pytest.fixture(autouse=True)
def in_tmp(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    return tmp_path


# ---------------------------------------------------------------------------------------------
# simulate


def test_simulate_without_road_runs_the_bundled_test_track(in_tmp):
    result = run("simulate")
    assert result.exit_code == 0, result.stderr
    assert "test-track" in result.stdout and "fuel [kg]" in result.stdout
    out = in_tmp / "out" / "test-track"
    summary = json.loads((out / "summary.json").read_text())
    assert summary["road"] == "test-track" and summary["length_m"] == pytest.approx(8500.0)
    for name in ("pi", "mpc"):  # the default runs both and compares them
        for key in (
            "fuel_kg",
            "time_s",
            "mean_speed_kmh",
            "end_speed_kmh",
            "gear_shifts",
            "brake_energy_kj",
            "neutral_distance_m",
            "compute_time_s",
            "realtime_ratio",
            "stalled",
        ):
            assert key in summary[name]
        header = (out / f"trace-{name}.csv").read_text().splitlines()[0].split(",")
        for column in (
            "distance_m",
            "time_s",
            "speed_kmh",
            "gear",
            "pedal",
            "brake",
            "engine_speed_rpm",
            "slope",
            "fuel_g",
        ):
            assert column in header
    for key in ("infeasible_solves", "solve_ms_mean", "solve_ms_max"):
        assert key in summary["mpc"]
    pi, mpc = summary["pi"], summary["mpc"]
    assert summary["delta_fuel_pct"] == pytest.approx(100 * (mpc["fuel_kg"] - pi["fuel_kg"]) / pi["fuel_kg"])
    assert summary["delta_time_pct"] == pytest.approx(100 * (mpc["time_s"] - pi["time_s"]) / pi["time_s"])
    assert "Δfuel vs PI [%]" in result.stdout
    assert sorted(p.name for p in out.iterdir()) == ["summary.json", "trace-mpc.csv", "trace-pi.csv"]


def test_simulate_a_road_file_reversed_with_overrides(in_tmp):
    assert run("road", "make", "hill", "--length-m", "500", "--slope-pct", "3.5", "-o", "hill.csv").exit_code == 0
    result = run(
        "simulate",
        "--road",
        "hill.csv",
        "--reverse",
        "--set",
        "mass_kg=20000",
        "--set",
        "v_ref_kmh=80",
        "--out",
        "res",
        "--controller",
        "pi",
    )
    assert result.exit_code == 0, result.stderr
    summary = json.loads((in_tmp / "res" / "summary.json").read_text())
    assert summary["road"] == "hill-reversed"  # the file name, reversed
    assert summary["pi"]["start_speed_kmh"] == 80.0


def test_simulate_reports_a_stall(in_tmp):
    assert run("road", "make", "hill", "--length-m", "2000", "--slope-pct", "25", "-o", "wall.csv").exit_code == 0
    result = run("simulate", "--road", "wall.csv", "--set", "mass_kg=60000", "--out", "res")
    assert result.exit_code == 0
    assert re.search(r"stalled at km \d+\.\d\d", result.stdout)
    assert json.loads((in_tmp / "res" / "summary.json").read_text())["pi"]["stalled"] is True


def test_simulate_gives_no_delta_when_the_mpc_stalls(in_tmp):
    # The thesis preset holds the inputs when no path exists (section 5.6): it stalls on this climb.
    assert run("road", "make", "hill", "--length-m", "1000", "--slope-pct", "20", "-o", "steep.csv").exit_code == 0
    result = run("simulate", "--road", "steep.csv", "--config", "thesis", "--out", "res")
    assert result.exit_code == 0, result.stderr
    summary = json.loads((in_tmp / "res" / "summary.json").read_text())
    assert summary["mpc"]["stalled"] is True and summary["pi"]["stalled"] is False
    assert summary["delta_fuel_pct"] is None and summary["delta_time_pct"] is None
    km = summary["mpc"]["stall_distance_m"] / 1000
    assert summary["not_comparable"] == f"not comparable: mpc stalled at km {km:.2f}"
    assert f"mpc vs pi: {summary['not_comparable']}" in result.stdout.splitlines()
    assert not any(line.startswith("Δ") for line in result.stdout.splitlines())


def test_the_table_counts_the_fallbacks_of_a_steep_climb(in_tmp):
    # 6 % over 1 km: the DP finds no admissible path from about 200 m on; the rescue climbs.
    assert run("road", "make", "hill", "--length-m", "1000", "--slope-pct", "6", "-o", "h6.csv").exit_code == 0
    result = run("simulate", "--road", "h6.csv", "--out", "res", "--verbose")
    assert result.exit_code == 0, result.stderr
    mpc = json.loads((in_tmp / "res" / "summary.json").read_text())["mpc"]
    assert mpc["fallback_relaxed"] + mpc["fallback_rescues"] > 0
    table = parse_table(result.stdout)
    assert table.row("relaxed solves driven")["mpc"] == str(mpc["fallback_relaxed"])
    assert table.row("rescues")["mpc"] == str(mpc["fallback_rescues"])
    assert table.row("rescue distance [m]")["mpc"] == f"{mpc['fallback_rescue_m']:.0f}"


# ---------------------------------------------------------------------------------------------
# model stationary: tables B.1 (40 t) and B.2 (20 t) of the thesis, within 2 %.

TABLES_B1_B2 = [
    # vehicle, speed [km/h], slope [%], gear option, pedal, brake, lambda [1/m]
    ("truck-40t.yaml", 85, 0.0, None, 0.443, 0.0, -0.238e-3),
    ("truck-40t.yaml", 90, -4.0, None, 0.0, 0.0490, -0.224e-3),
    ("truck-40t.yaml", 85, -1.25, "neutral", 0.0, 0.0, -0.192e-3),
    ("truck-20t.yaml", 85, 0.0, None, 0.331, 0.0, -0.451e-3),
    ("truck-20t.yaml", 90, -4.0, None, 0.0, 0.0153, -0.445e-3),
    ("truck-20t.yaml", 85, -1.80, "neutral", 0.0, 0.0, -0.382e-3),
]


@pytest.mark.parametrize(("vehicle", "speed", "slope", "gear", "pedal", "brake", "eigenvalue"), TABLES_B1_B2)
def test_model_stationary_reproduces_tables_b1_b2(vehicle, speed, slope, gear, pedal, brake, eigenvalue):
    args = [
        "model",
        "stationary",
        "--speed-kmh",
        speed,
        "--slope-pct",
        slope,
        "--vehicle",
        default_config_path(vehicle),
        "--json",
    ]
    if gear is not None:
        args += ["--gear", gear]
    result = run(*args)
    assert result.exit_code == 0, result.stderr
    doc = json.loads(result.stdout)
    assert {"pedal", "brake", "gear", "feasible", "eigenvalue_per_m"} <= set(doc)
    assert doc["gear"] == (0 if gear == "neutral" else 12)
    assert doc["feasible"] is True
    # The neutral rows have P = B = 0 by construction (the thesis solved for the slope): the level
    # needed there is zero up to the slope's printed rounding.
    for key, expected in (("pedal", pedal), ("brake", brake)):
        assert doc[key] == pytest.approx(expected, rel=0.02, abs=1e-3 if expected == 0 else 0)
    assert doc["eigenvalue_per_m"] == pytest.approx(eigenvalue, rel=0.02)


def test_model_stationary_text_output_and_infeasible_point():
    result = run("model", "stationary", "--speed-kmh", "85", "--slope-pct", "6", "--gear", "12")
    assert result.exit_code == 0
    assert "gear 12" in result.stdout and "feasible    no" in result.stdout


# ---------------------------------------------------------------------------------------------
# road make / regenerate


def test_road_make_writes_a_loadable_section(in_tmp):
    result = run(
        "road",
        "make",
        "crest",
        "--length-m",
        "1500",
        "--slope-pct",
        "2",
        "--lead-m",
        "200",
        "--tail-m",
        "300",
        "-o",
        "crest.csv",
    )
    assert result.exit_code == 0, result.stderr
    text = (in_tmp / "crest.csv").read_text()
    assert text.startswith("# Generated by: truckmpc road make crest --length-m 1500 --slope-pct 2")
    from truckmpc.roads import load_road

    assert load_road(in_tmp / "crest.csv").length_m == pytest.approx(2000.0)


def test_road_regenerate_reproduces_the_shipped_roads(in_tmp):
    result = run("road", "regenerate", "--dir", "roads")
    assert result.exit_code == 0, result.stderr
    shipped = sorted((REPO / "roads").glob("*.csv"))
    assert shipped
    for path in shipped:
        assert (in_tmp / "roads" / path.name).read_text() == path.read_text(), path.name
    assert sorted(p.name for p in (in_tmp / "roads").iterdir()) == [p.name for p in shipped]


# ---------------------------------------------------------------------------------------------
# Bad input: one `error:` line naming the place, exit code 2, no output directory.

VEHICLE_40T = default_config_path("truck-40t.yaml").read_text()

BAD_FILES = {
    "nan.csv": "distance_m,altitude_m\n0,0\n25,nan\n50,1\n",
    "text.csv": "# a comment\ndistance_m,altitude_m\n0,0\n25,abc\n50,1\n",
    "backwards.csv": "distance_m,altitude_m\n0,0\n25,0\n25,1\n",
    "single.csv": "distance_m,altitude_m\n0,0\n",
    "steep.csv": "distance_m,grade\n0,0.01\n25,0.35\n50,0\n",
    "unknown.yaml": "v_ref_kmh: 85\nbogus_key: 1\n",
    "wrongtype.yaml": "v_ref_kmh: fast\n",
    "mass0.yaml": re.sub(r"(?m)^mass_kg:.*$", "mass_kg: 0", VEHICLE_40T),
    "vehicle-unknown.yaml": VEHICLE_40T + "wings_m2: 3\n",
    "mpc-typo.yaml": "horizon_m: 1500\nhorizn_m: 2000\n",
    "mpc-delta.yaml": "delta_kmh: 0\n",
}

BAD_INPUTS = [
    # args, words the message must contain
    (["--road", "missing.csv"], ["missing.csv"]),
    (["--road", "nan.csv"], ["nan.csv:3"]),
    (["--road", "text.csv"], ["text.csv:4", "abc"]),
    (["--road", "backwards.csv"], ["backwards.csv:4"]),
    (["--road", "single.csv"], ["single.csv", "two"]),
    (["--road", "steep.csv"], ["steep.csv"]),
    (["--config", "unknown.yaml"], ["unknown.yaml", "bogus_key"]),
    (["--config", "wrongtype.yaml"], ["wrongtype.yaml", "v_ref_kmh"]),
    (["--vehicle", "mass0.yaml"], ["mass0.yaml", "mass_kg"]),
    (["--vehicle", "vehicle-unknown.yaml"], ["vehicle-unknown.yaml", "wings_m2"]),
    (["--set", "mass_kg=0"], ["--set mass_kg"]),
    (["--set", "mass_kg=-5"], ["--set mass_kg"]),
    (["--set", "v_inc_kmh=-1"], ["--set v_inc_kmh"]),
    (["--set", "top_speed=3"], ["--set top_speed", "unknown"]),
    # A set speed the truck cannot drive, and the PCC's band keys that the one band replaced (issue 25).
    (["--set", "v_ref_kmh=200"], ["--set v_ref_kmh", "top speed 119.90 km/h", "got 200"]),
    (["--set", "v_ref_kmh=10"], ["--set v_ref_kmh", "lowest usable speed 5.32 km/h"]),
    (["--set", "pcc_underspeed_kmh=6"], ["--set pcc_underspeed_kmh", "replaced by 'v_dec_kmh'"]),
    (["--set", "pcc_overspeed_kmh=6"], ["--set pcc_overspeed_kmh", "replaced by 'v_inc_kmh'"]),
    (["--set", "mass_kg"], ["--set", "key=value"]),
    (["--controller", "fuzzy"], ["--controller"]),
    # MPC configuration (issue 3): each names the key and what was expected.
    (["--set", "delta_kmh=0"], ["--set delta_kmh", "in (0, 100]"]),
    (["--set", "delta_kmh=-0.1"], ["--set delta_kmh"]),
    (["--set", "n_min_rpm=2000"], ["--set n_min_rpm", "n_max_rpm"]),
    (["--set", "n_max_rpm=900"], ["n_max_rpm"]),
    (["--set", "epsilon=-0.1"], ["--set epsilon", "in [0, 1]"]),
    (["--set", "horizon_m=10"], ["--set horizon_m", "stage"]),
    (["--set", "k_lim=0"], ["--set k_lim"]),
    (["--set", "neutral_rule=closest"], ["--set neutral_rule", "nearest"]),
    (["--set", "allow_neutral=maybe"], ["--set allow_neutral", "true or false"]),
    (["--config", "mpc-typo.yaml"], ["mpc-typo.yaml", "horizn_m", "horizon_m"]),
    (["--config", "mpc-delta.yaml"], ["mpc-delta.yaml", "delta_kmh"]),
    (["--no-such-option"], ["--no-such-option"]),
]


@pytest.mark.parametrize(("args", "words"), BAD_INPUTS, ids=[" ".join(a) for a, _ in BAD_INPUTS])
def test_bad_input_gives_one_error_line_exit_2_and_no_output(in_tmp, args, words):
    for name, text in BAD_FILES.items():
        (in_tmp / name).write_text(text)
    result = run("simulate", *args, "--out", "results")
    assert result.exit_code == 2
    lines = result.stderr.splitlines()
    assert len(lines) == 1, result.stderr
    assert lines[0].startswith("error: ")
    for word in words:
        assert word in lines[0]
    assert "Traceback" not in result.stdout + result.stderr
    assert not (in_tmp / "results").exists()
    assert not (in_tmp / "out").exists()


@pytest.mark.parametrize(
    "args",
    [
        ["model", "stationary", "--speed-kmh", "85"],
        ["model", "stationary", "--speed-kmh", "0", "--slope-pct", "0"],
        ["model", "stationary", "--speed-kmh", "85", "--slope-pct", "0", "--gear", "13"],
        ["road", "make", "hill", "--length-m", "500", "-o", "x.csv"],
        ["road", "make", "hill", "--length-m", "-1", "--slope-pct", "2", "-o", "x.csv"],
        ["road", "make", "spiral", "--length-m", "500", "-o", "x.csv"],
        ["no-such-command"],
        [],
    ],
)
def test_other_commands_fail_with_one_line(in_tmp, args):
    result = run(*args)
    assert result.exit_code == 2
    assert len(result.stderr.splitlines()) == 1 and result.stderr.startswith("error: ")
    assert not (in_tmp / "x.csv").exists()


def test_installed_command_fails_with_one_line_in_a_real_process(in_tmp):
    proc = subprocess.run(
        [
            sys.executable,
            "-c",
            "from truckmpc.cli import main; main()",
            "simulate",
            "--road",
            "missing.csv",
            "--out",
            "results",
        ],
        capture_output=True,
        text=True,
        cwd=in_tmp,
        check=False,
    )
    assert proc.returncode == 2
    assert proc.stderr.splitlines() == ["error: missing.csv: no such file"]
    assert proc.stdout == ""
    assert not (in_tmp / "results").exists()


def test_help_exits_zero():
    result = run("--help")
    assert result.exit_code == 0
    assert "simulate" in result.stdout


def test_version_prints_the_installed_packages_version():
    """`truckmpc --version` names the version pip installed (the one summary.json records)."""
    result = run("--version")
    assert result.exit_code == 0, result.stderr
    assert result.stdout.strip() == f"truckmpc {importlib.metadata.version('truckmpc')}"


def test_ci_runs_exactly_the_readme_test_command():
    readme = (REPO / "README.md").read_text()
    commands = re.findall(r"```sh\n(.+?)\n```", readme)
    test_command = next(c for c in commands if "pytest" in c)
    ci_lines = (REPO / ".ci" / "run").read_text().splitlines()
    assert test_command in ci_lines
    assert "set -euo pipefail" in ci_lines[: ci_lines.index(test_command)]
    # set -e ignores a failure inside an && list except at its last command (a failing `cargo test`
    # once let CI go on, green): the line after the command must check its status.
    following = ci_lines[ci_lines.index(test_command) + 1 : ci_lines.index(test_command) + 4]
    assert "test_status=$?" in following and any('exit "$test_status"' in line for line in following)
    # every test: the default run leaves the slow tier out, so the command must run it too
    addopts = tomllib.loads((REPO / "pyproject.toml").read_text())["tool"]["pytest"]["ini_options"]["addopts"]
    assert addopts[-2:] == ["-m", "not slow"]
    assert "python -m pytest -q && python -m pytest -q -m slow" in test_command


@pytest.mark.parametrize(
    ("command", "units"),
    [(["model", "stationary"], ["[km/h]", "[%]"]), (["road", "make"], ["[m]", "[%]"]), (["simulate"], [])],
)
def test_help_keeps_units_and_shows_flags_as_flags(command: list[str], units: list[str]) -> None:
    result = runner.invoke(app, [*command, "--help"], env={"COLUMNS": "120"})
    assert result.exit_code == 0
    for unit in units:
        assert unit in result.stdout, (unit, result.stdout)
    assert "<bool>" not in result.stdout and "list[" not in result.stdout
    assert "next" not in runner.invoke(app, ["--help"]).stdout  # the DP-MPC is here


def test_model_stationary_names_the_engine_operating_point():
    def point(slope: str) -> dict:
        result = run("model", "stationary", "--speed-kmh", "80", "--slope-pct", slope, "--gear", "12", "--json")
        assert result.exit_code == 0, result.output
        return json.loads(result.stdout)

    up, down = point("1"), point("-6")
    # Climbing: fuel flows and the engine drives; a steep descent needs the brake: fuel cut, drag torque.
    assert up["fuel_rate_g_per_h"] > 0 and up["engine_torque_nm"] > 0 and up["brake"] == 0
    assert down["brake"] > 0 and down["fuel_rate_g_per_h"] == 0 and down["engine_torque_nm"] < 0
    # In one gear the engine speed is proportional to road speed.
    slower = json.loads(
        run("model", "stationary", "--speed-kmh", "60", "--slope-pct", "1", "--gear", "12", "--json").stdout
    )
    assert slower["engine_speed_rpm"] / 60 == pytest.approx(up["engine_speed_rpm"] / 80)

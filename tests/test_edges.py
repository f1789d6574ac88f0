"""Inputs at the edges that used to end in a traceback, a MemoryError or a hang: each is now one
`error:` line, exit 2 and no output (and a damaged resumed sweep row is run again)."""

from __future__ import annotations

import csv
import time
from pathlib import Path

import pytest
from typer.testing import CliRunner

from truckmpc import make_section, write_road
from truckmpc.cli import app
from truckmpc.sweep import PARTIAL_NAME
from truckmpc.sweep.columns import WALL_TIME_COLUMNS

runner = CliRunner()


def run(*args: object):
    return runner.invoke(app, [str(a) for a in args])


def assert_one_error_line(result, *words: str) -> None:
    assert result.exit_code == 2, result.output
    assert result.stderr.count("\n") == 1 and result.stderr.startswith("error: "), result.stderr
    assert "Traceback" not in result.output
    for word in words:
        assert word in result.stderr, result.stderr


@pytest.fixture(autouse=True)
def in_tmp(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    return tmp_path


@pytest.fixture
def short_road(in_tmp) -> Path:
    path = in_tmp / "short.csv"
    path.write_text("distance_m,altitude_m\n0,0\n150,1.5\n300,0\n")
    return path


@pytest.mark.parametrize(
    ("rows", "words"),
    [
        ("0,0\n1e308,0\n", ["road.csv:3", "'distance_m'", "1e308"]),  # beyond any position
        ("0,0\n100,0\n2e7,0\n", ["road.csv:4", "'distance_m'", "at most 1e+07 m"]),  # 20 000 km long
        ("-1e300,0\n0,0\n", ["road.csv:2", "'distance_m'"]),
    ],
)
def test_a_non_physical_road_distance_is_refused_by_line(in_tmp, rows, words):
    (in_tmp / "road.csv").write_text("distance_m,altitude_m\n" + rows)
    result = run("simulate", "--road", "road.csv", "--controller", "pi", "--out", "res")
    assert_one_error_line(result, *words)
    assert not (in_tmp / "res").exists()


def test_a_trace_too_long_for_memory_is_refused(in_tmp, short_road):
    # 300 m every 1 um: 3e8 rows, 63 GiB of trace.
    result = run("simulate", "--road", short_road, "--controller", "pi", "--set", "trace_step_m=1e-6", "--out", "res")
    assert_one_error_line(result, "--set trace_step_m", "trace rows")
    assert not (in_tmp / "res").exists()
    fine = run("simulate", "--road", short_road, "--controller", "pi", "--set", "trace_step_m=0.5", "--out", "res")
    assert fine.exit_code == 0, fine.output
    assert len((in_tmp / "res" / "trace-pi.csv").read_text().splitlines()) == 1 + 300 / 0.5 + 1


def test_road_make_refuses_a_road_longer_than_the_limit_at_once(in_tmp):
    started = time.perf_counter()
    result = run("road", "make", "hill", "--length-m", "1e12", "--slope-pct", "3", "-o", "h.csv")
    assert_one_error_line(result, "length_m", "1e+12")
    assert time.perf_counter() - started < 5 and not (in_tmp / "h.csv").exists()


def billion_laughs(levels: int = 9) -> str:
    """A YAML value of 10**levels ones made of nested aliases, in a few hundred bytes."""
    text = "[&a0 [1, 1, 1, 1, 1, 1, 1, 1, 1, 1]"
    for level in range(1, levels):
        text += f", &a{level} [" + ", ".join([f"*a{level - 1}"] * 10) + "]"
    return text + "]"


def test_a_yaml_alias_bomb_in_a_config_file_is_refused_at_once(in_tmp, short_road):
    (in_tmp / "bomb.yaml").write_text(f"# overlay\nq_brake: {billion_laughs()}\n")
    started = time.perf_counter()
    result = run("simulate", "--road", short_road, "--controller", "pi", "--config", "bomb.yaml", "--out", "res")
    assert_one_error_line(result, "bomb.yaml:2", "alias")
    assert time.perf_counter() - started < 5 and not (in_tmp / "res").exists()


def test_even_a_harmless_alias_is_refused_in_a_config_file(in_tmp, short_road):
    (in_tmp / "alias.yaml").write_text("q_fuel: &w 2.0\nq_brake: *w\n")
    result = run("simulate", "--road", short_road, "--controller", "pi", "--config", "alias.yaml", "--out", "res")
    assert_one_error_line(result, "alias.yaml:2", "*w")


def test_a_grid_of_1e8_combinations_is_refused_before_it_is_expanded(in_tmp, short_road):
    started = time.perf_counter()
    result = run(
        "sweep", "--road", short_road, "--grid", "q_fuel=1:10000:1", "--grid", "q_brake=1:10000:1", "--out", "sw"
    )
    assert_one_error_line(result, "--grid", "100000000 combinations")
    assert time.perf_counter() - started < 5 and not (in_tmp / "sw").exists()


def read_rows(path: Path) -> list[dict[str, str]]:
    with path.open(newline="", encoding="utf-8") as handle:
        return [{k: v for k, v in row.items() if k not in WALL_TIME_COLUMNS} for row in csv.DictReader(handle)]


@pytest.mark.parametrize(
    "damage",
    [
        lambda line: line.replace(",false,", ",fals3,", 1),  # a stalled flag
        lambda line: line.replace(".", "x", 3),  # numbers
        lambda line: line[:30] + "\x00" + line[31:],  # a NUL byte
        lambda line: line[:30] + "\x0c" + line[31:],  # a form feed: a line break to str.splitlines
        lambda line: line[:30] + "\u2028" + line[31:],  # so is the Unicode line separator
    ],
    ids=["flag", "number", "nul", "form-feed", "line-separator"],
)
def test_a_damaged_row_of_an_interrupted_sweep_is_dropped_and_run_again(in_tmp, damage):
    write_road(make_section("hill", 200, -3.0, lead_m=100, tail_m=100), in_tmp / "descent.csv")
    args = ["sweep", "--road", "descent.csv", "--grid", "horizon_m=250,500,750", "--jobs", "1", "--out", "sw"]
    first = run(*args)
    assert first.exit_code == 0, first.output
    complete = read_rows(in_tmp / "sw" / "sweep.csv")
    # An interrupted state: the three rows in the partial file, the middle one damaged, no sweep.csv.
    header, *rows = (in_tmp / "sw" / "sweep.csv").read_text().splitlines(keepends=True)
    assert damage(rows[1]) != rows[1]
    (in_tmp / "sw" / "sweep.csv").unlink()
    (in_tmp / "sw" / PARTIAL_NAME).write_text(header + rows[0] + damage(rows[1]) + rows[2])
    again = run(*args)
    assert again.exit_code == 0, again.output
    assert again.stderr.count("\n") == 1 and "dropped 1 damaged row" in again.stderr
    assert f"{PARTIAL_NAME}:3" in again.stderr
    assert "(3 rows: 1 MPC and 0 PI runs, 2 rows resumed)" in again.stdout
    assert read_rows(in_tmp / "sw" / "sweep.csv") == complete


DEEP = "[" * 5000  # PyYAML composes nested collections recursively: a RecursionError, not a YAMLError


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (["simulate", "--set", f"horizon_m={DEEP}"], ["--set horizon_m", "nested too deeply"]),
        (["simulate", "--config", "deep.yaml"], ["deep.yaml", "nested too deeply"]),
        (["sweep", "--road", "short.csv", "--grid", f"horizon_m={DEEP}", "--out", "sw"], ["--grid horizon_m"]),
    ],
    ids=["set", "config", "grid"],
)
def test_yaml_nested_too_deeply_is_one_error_line(in_tmp, short_road, args, words):
    (in_tmp / "deep.yaml").write_text(f"horizon_m: {DEEP}\n")
    result = run(*args, *(["--out", "res"] if args[0] == "simulate" else []))
    assert_one_error_line(result, *words)
    assert not (in_tmp / "res").exists() and not (in_tmp / "sw").exists()


@pytest.mark.parametrize(
    ("text", "code"),
    [("Null\n", 0), ("just text\n", 2), ("\x1f\n", 2)],
    ids=["null-document", "scalar-document", "control-character"],
)
def test_a_config_file_that_is_not_a_mapping_is_an_empty_overlay_or_one_error_line(in_tmp, short_road, text, code):
    # Found by tests/test_cli_property.py: both ended in a traceback.
    (in_tmp / "odd.yaml").write_text(text)
    result = run("simulate", "--road", short_road, "--controller", "pi", "--config", "odd.yaml", "--out", "res")
    assert result.exit_code == code, result.output
    if code == 2:
        assert_one_error_line(result, "odd.yaml")
        assert not (in_tmp / "res").exists()


def test_a_pedal_gain_that_would_reach_absurd_speeds_does_not_exhaust_memory(tmp_path) -> None:
    # fueling_max_a_mg_per_rpm2 = 2 makes the fueling limit 2·N² mg/stroke (4.5e6 at 1500 rpm): full
    # pedal would end a stage at astronomic speeds, and the DP's rows once spanned every grid point
    # up to there (a request for 9e12 bytes aborted the process). Rows now stop one grid step
    # beyond the band.
    from typer.testing import CliRunner

    from truckmpc.cli import app

    road = tmp_path / "road.csv"
    road.write_text("distance_m,altitude_m\n-50.0,0.0\n-12.228856309009458,-2.8775886299627715\n")
    out = tmp_path / "out"
    args = ["simulate", "--road", str(road), "--controller", "mpc", "--set", "fueling_max_a_mg_per_rpm2=2"]
    result = CliRunner().invoke(app, [*args, "--out", str(out)])
    assert result.exit_code == 0, result.output
    assert (out / "trace-mpc.csv").is_file()

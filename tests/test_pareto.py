"""Fuel–time Pareto studies (`truckmpc pareto`): curves, the saving at equal trip time, resume."""

from __future__ import annotations

import csv
from pathlib import Path

import pytest
from typer.testing import CliRunner

from truckmpc import load_run_config, make_section, simulate
from truckmpc.cli import app
from truckmpc.consumption import FUEL
from truckmpc.pareto import below, curves, equal_time_savings, plan_pareto, run_pareto
from truckmpc.pareto.run import figures_of
from truckmpc.roads import default_test_track, write_road
from truckmpc.sweep.cells import parse_cell

runner = CliRunner()


@pytest.fixture(scope="module")
def study(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, list[dict[str, str]]]:
    """The three curves on the bundled test track (hilly: grades up to ±4 %) at four set speeds."""
    out = tmp_path_factory.mktemp("pareto")
    result = runner.invoke(
        app, ["pareto", "--road", "roads/test-track.csv", "--speeds", "79,82,85,88", "--jobs", "2", "--out", str(out)]
    )
    assert result.exit_code == 0, result.output
    with (out / "pareto.csv").open(newline="") as handle:
        return out, list(csv.DictReader(handle))


@pytest.mark.slow
def test_every_look_ahead_curve_lies_below_the_pi_on_a_hilly_road(study) -> None:
    """At every trip time both the PI and a look-ahead controller reach, the look-ahead controller
    uses less fuel (end speed corrected), by at least 0.5 % of the PI's."""
    _, rows = study
    by_controller = curves(rows)["test-track"]
    pi = by_controller["pi"]
    for name in ("mpc", "fuel_time"):
        under, margin_kg = below(by_controller[name], pi)
        assert under, (name, margin_kg)
        assert margin_kg > 0.005 * pi.consumed.min(), (name, margin_kg)


def test_csv_figure_and_equal_time_saving(study) -> None:
    """One row per (curve, set speed), β given for the fuel_time curve and rising with the set
    speed; the printed saving at equal time is the curve's fuel interpolated at the PI's time."""
    out, rows = study
    assert (out / "pareto.png").stat().st_size > 0
    assert [(r["controller"], float(r["value"])) for r in rows] == [
        (c, v) for c in ("pi", "mpc", "fuel_time") for v in (79.0, 82.0, 85.0, 88.0)
    ]
    betas = [float(r["beta_g_per_s"]) for r in rows if r["controller"] == "fuel_time"]
    assert betas == sorted(betas) and betas[0] > 0
    # The default look-ahead cost is fuel + β·time too, so the mpc curve has its derived β; the PI none.
    assert all(r["beta_g_per_s"] == "" for r in rows if r["controller"] == "pi")
    assert all(float(r["beta_g_per_s"]) > 0 for r in rows if r["controller"] == "mpc")
    savings = {name: saving.pct for name, saving in equal_time_savings(rows, 85.0)["test-track"].items()}
    pi85 = next(r for r in rows if r["controller"] == "pi" and float(r["value"]) == 85.0)
    mpc = curves(rows)["test-track"]["mpc"]
    expected = 100 * (mpc.consumed_at(float(pi85["time_s"])) / float(pi85["fuel_corrected_kg"]) - 1)
    assert savings["mpc"] == pytest.approx(expected)
    assert savings["mpc"] < 0 and savings["fuel_time"] < 0


def test_rerun_resumes_and_a_different_study_is_refused(tmp_path: Path) -> None:
    """Running the same study again into its directory runs nothing; points lost from the end of
    the partial file run again; another study into it is refused with one line, exit 2."""
    plan = plan_pareto([default_test_track()], speeds_kmh=[84.0, 86.0], curves=["pi"])
    first = run_pareto(plan, tmp_path, jobs=1)
    assert (first.runs, first.resumed) == (2, 0)
    again = run_pareto(plan, tmp_path, jobs=1)
    assert (again.runs, again.resumed) == (0, 2) and again.rows == first.rows
    # An interrupted study: the CSV gone, one finished point in the partial file.
    lines = (tmp_path / "pareto.csv").read_text().splitlines(keepends=True)
    (tmp_path / "pareto.csv").unlink()
    (tmp_path / "pareto.partial.csv").write_text(lines[0] + lines[2])
    resumed = run_pareto(plan, tmp_path, jobs=1)
    assert (resumed.runs, resumed.resumed) == (1, 1) and resumed.rows == first.rows
    other = runner.invoke(
        app, ["pareto", "--road", "roads/test-track.csv", "--speeds", "80", "--curves", "pi", "--out", str(tmp_path)]
    )
    assert other.exit_code == 2 and other.output.count("\n") == 1 and "different pareto" in other.output


@pytest.mark.parametrize(
    ("args", "expected"),
    [
        (["--curves", "pi,bogus"], "--curves: expected some of pi, pcc, mpc, fuel_time, each once, got pi,bogus"),
        (["--curves", "pi,pi"], "each once, got pi,pi"),
        (["--speeds", "80,80.0"], "--speeds: expected each value once, got 80.0 twice"),
        (["--speeds", "90:80:2"], "--speeds"),
        (["--betas", "3,4", "--curves", "pi,mpc"], "--betas: expected the fuel_time curve"),
        (["--speeds", "abc"], "--speeds': expected numbers, got 'abc'"),
        (["--set", "v_dec_kmh=90"], "v_dec_kmh"),
    ],
)
def test_bad_input_is_one_line_and_exit_2(tmp_path: Path, args: list[str], expected: str) -> None:
    result = runner.invoke(app, ["pareto", "--road", "roads/test-track.csv", "--out", str(tmp_path / "p"), *args])
    assert result.exit_code == 2, result.output
    assert result.output.startswith("error: ") and result.output.count("\n") == 1 and expected in result.output
    assert "--grid" not in result.output
    assert not (tmp_path / "p").exists()


def test_a_stall_or_a_missing_reference_gives_no_saving(study) -> None:
    """A look-ahead curve with a stalled run, or a study without the PI at the reference set speed,
    gets a reason instead of a saving."""
    _, rows = study
    stalled = [dict(r) for r in rows]
    for row in stalled:
        if row["controller"] == "mpc" and row["value"] == "82.0":
            row.update(stalled="true", time_s="", fuel_kg="", fuel_corrected_kg="")
    savings = equal_time_savings(stalled, 85.0)["test-track"]
    assert savings["mpc"].pct is None and "mpc stalled at 82.0" in savings["mpc"].reason
    assert savings["fuel_time"].pct is not None
    missing = equal_time_savings(rows, 86.0)["test-track"]
    assert all(s.pct is None and "no pi run at v_ref 86" in s.reason for s in missing.values())


def test_plot_refuses_a_damaged_pareto_csv(study, tmp_path: Path) -> None:
    """A pareto.csv whose finished run lacks its trip time is refused with one line naming the line."""
    out, _ = study
    lines = (out / "pareto.csv").read_text().splitlines(keepends=True)
    broken = lines[2].split(",")
    broken[9] = ""  # time_s
    (tmp_path / "pareto.csv").write_text(lines[0] + lines[1] + ",".join(broken))
    (tmp_path / "pareto.json").write_text((out / "pareto.json").read_text())
    result = runner.invoke(app, ["plot", str(tmp_path)])
    assert result.exit_code == 2 and result.output.count("\n") == 1
    assert f"{tmp_path / 'pareto.csv'}:3: column 'time_s': expected a number" in result.output


def test_the_pcc_curve_is_simulates_pcc_at_each_set_speed(tmp_path: Path) -> None:
    """`--curves pi,pcc`: one PCC point per set speed, each the figures of simulate(road, config,
    "pcc") at that v_ref, starting at the configured v_ref (85 km/h, inside both bands); the figure
    draws it and the command prints its saving."""
    road = make_section("hill", 300, -3.0, lead_m=100, tail_m=100)
    path = tmp_path / "descent.csv"
    write_road(road, path)
    out = tmp_path / "p"
    args = ["pareto", "--road", str(path), "--speeds", "82,86", "--curves", "pi,pcc", "--jobs", "1", "--out", str(out)]
    result = runner.invoke(app, args)
    assert result.exit_code == 0, result.output
    assert (
        "descent: pcc against the PI at equal trip time and end speed" in result.output
        and (out / "pareto.png").stat().st_size > 0
    )
    with (out / "pareto.csv").open(newline="") as handle:
        rows = [r for r in csv.DictReader(handle) if r["controller"] == "pcc"]
    assert [float(r["v_ref_kmh"]) for r in rows] == [82.0, 86.0]
    for row in rows:
        config = load_run_config(overrides=(f"v_ref_kmh={row['v_ref_kmh']}", "start_speed_kmh=85"))
        expected = simulate(road, config, "pcc").summary
        for name in figures_of(FUEL):
            assert parse_cell(row[name]) == expected[name], name

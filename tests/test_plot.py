"""`truckmpc plot`: run and sweep directories to PNG/SVG, PI-only runs, bad directories, no matplotlib."""

from __future__ import annotations

import csv
import itertools
import json
import math
import sys
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from truckmpc.cli import app
from truckmpc.plot import MAX_POINTS, MISSING_MATPLOTLIB, decimate
from truckmpc.plot.sweep import sweep_figures
from truckmpc.sweep.columns import RUNS, delta_column

runner = CliRunner()
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def run(*args: object):
    return runner.invoke(app, [str(a) for a in args])


def assert_png(path: Path) -> None:
    data = path.read_bytes()
    assert data.startswith(PNG_MAGIC) and len(data) > 10_000, path  # a drawn figure, not an empty canvas


def assert_one_line_error(result, *fragments: str) -> None:
    assert result.exit_code == 2
    assert len(result.stderr.splitlines()) == 1 and result.stderr.startswith("error: "), result.stderr
    for fragment in fragments:
        assert fragment in result.stderr


@pytest.fixture(autouse=True)
def in_tmp(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    return tmp_path


@pytest.fixture(scope="module")
def run_dirs(tmp_path_factory):
    """The bundled test track driven by PI and MPC, and by PI alone."""
    base = tmp_path_factory.mktemp("runs")
    both, pi_only = base / "both", base / "pi"
    assert run("simulate", "--out", both).exit_code == 0
    assert run("simulate", "--controller", "pi", "--out", pi_only).exit_code == 0
    return both, pi_only


def write_sweep(
    directory: Path,
    *,
    stages=(25, 50),
    deltas=(0.1, 0.2),
    neutral=(True, False),
    horizons=range(250, 3001, 250),
    directions=("forward", "reverse"),
    realtime=True,
    equal_time=True,
) -> Path:
    """A synthetic sweep.csv in the layout `truckmpc sweep` writes (road, direction, axes, results)."""
    directory.mkdir(parents=True, exist_ok=True)
    axes = ["horizon_m"] + ["stage_m"] * bool(stages) + ["delta_kmh"] * bool(deltas) + ["allow_neutral"] * bool(neutral)
    mpc = RUNS["mpc"].column
    results = ["pi_fuel_kg", "pi_time_s", mpc("fuel_kg"), mpc("time_s"), mpc("neutral_distance_m")]
    results += [mpc("realtime_ratio"), mpc("solve_ms_mean"), mpc("solve_ms_max"), mpc("infeasible_solves")] * realtime
    results += [delta_column("mpc", "fuel"), delta_column("mpc", "time")]
    results += [delta_column("mpc", "fuel_equal_time")] * equal_time
    with (directory / "sweep.csv").open("w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(["road", "direction", *axes, *results])
        for direction, h, s, d, n in itertools.product(
            directions, horizons, stages or [25], deltas or [0.2], neutral or [True]
        ):
            saving = -3.5 * (1 - math.exp(-h / 600)) * (1.0 if n else 0.7) + (0.1 if s == 50 else 0.0)
            dtime = 0.3 * math.exp(-h / 400) - 0.2
            q = 1e-4 * h / s * (0.2 / d) ** 2
            cells = {
                "horizon_m": h,
                "stage_m": s,
                "delta_kmh": d,
                "allow_neutral": str(n).lower(),
                "pi_fuel_kg": 35.6,
                "pi_time_s": 4761.2,
                mpc("fuel_kg"): 35.6 * (1 + saving / 100),
                mpc("time_s"): 4761.2 * (1 + dtime / 100),
                mpc("neutral_distance_m"): 1200.0 * n,
                mpc("realtime_ratio"): q,
                mpc("solve_ms_mean"): q * 1e3,
                mpc("solve_ms_max"): q * 2e3,
                mpc("infeasible_solves"): 0,
                delta_column("mpc", "fuel"): saving,
                delta_column("mpc", "time"): dtime,
                delta_column("mpc", "fuel_equal_time"): saving + 0.4 * dtime,
            }
            writer.writerow(["test-track", direction, *(cells[c] for c in axes + results)])
    grid = [{"key": a, "values": []} for a in axes]
    (directory / "sweep.json").write_text(json.dumps({"version": 1, "grid": grid}))
    return directory


# ---------------------------------------------------------------------------------------------
# run directories


def test_a_run_dir_gives_run_png_and_svg(run_dirs):
    both, _ = run_dirs
    result = run("plot", both, "--svg")
    assert result.exit_code == 0, result.stderr
    assert_png(both / "run.png")
    assert b"<svg" in (both / "run.svg").read_bytes()[:2000]
    assert "run.png" in result.stdout and "run.svg" in result.stdout


def test_a_pi_only_run_dir_is_plotted(run_dirs, in_tmp):
    _, pi_only = run_dirs
    result = run("plot", pi_only, "--out", in_tmp / "pics")
    assert result.exit_code == 0, result.stderr
    assert_png(in_tmp / "pics" / "run.png")
    assert not (pi_only / "run.png").exists()  # --out, not the run directory


def test_out_may_name_the_file(run_dirs, in_tmp):
    both, _ = run_dirs
    assert run("plot", both / "summary.json", "--out", in_tmp / "fig.png").exit_code == 0
    assert_png(in_tmp / "fig.png")


def test_a_long_stalled_run_renders_with_decimated_lines(in_tmp):
    """300 km at a 10 m trace step: 30001 samples per line, reduced to MAX_POINTS; a stall is marked."""
    d = np.arange(0.0, 300_000.0 + 1, 10.0)
    trace = {
        "distance_m": d,
        "time_s": d / 23.6,
        "speed_kmh": 85 + 5 * np.sin(d / 3000),
        "gear": np.where(d % 40_000 < 2000, 0, 12),
        "pedal": 0.5 + 0.5 * np.sin(d / 700),
        "brake": np.where(d % 20_000 < 100, 0.05, 0.0),
        "altitude_m": 100 * np.sin(d / 20_000),
    }
    out = in_tmp / "long"
    out.mkdir()
    for name, cut in (("pi", len(d)), ("mpc", len(d) // 2)):
        header = ",".join(trace)
        np.savetxt(
            out / f"trace-{name}.csv",
            np.column_stack([v[:cut] for v in trace.values()]),
            delimiter=",",
            header=header,
            comments="",
            fmt="%.6g",
        )
    summary = {
        "road": "long",
        "length_m": 300_000.0,
        "pi": {"stalled": False},
        "mpc": {
            "stalled": True,
            "settings": {
                "v_ref_kmh": 85.0,
                "v_inc_kmh": 5.0,
                "v_dec_kmh": 5.0,
                "stage_m": 25.0,
                "delta_kmh": 0.2,
                "horizon_m": 1500.0,
                "allow_neutral": True,
            },
        },
        "mpc_delta_fuel_pct": -3.0,
        "mpc_delta_time_pct": 0.1,
    }
    (out / "summary.json").write_text(json.dumps(summary))
    result = run("plot", out)
    assert result.exit_code == 0, result.stderr
    assert_png(out / "run.png")


def test_decimate_keeps_the_extremes_and_the_ends():
    x = np.arange(100_000.0)
    y = np.zeros_like(x)
    y[54_321] = 1.0  # a one-sample brake pulse
    xs, ys = decimate(x, y)
    assert len(xs) <= MAX_POINTS
    assert ys.max() == 1.0 and xs[0] == 0.0 and xs[-1] == x[-1] and np.all(np.diff(xs) > 0)
    short = np.arange(10.0)
    assert decimate(short, short)[0] is short  # short lines are drawn as they are


# ---------------------------------------------------------------------------------------------
# sweep directories


def test_a_sweep_dir_gives_sweep_and_realtime_pngs_and_svgs(in_tmp):
    sweep = write_sweep(in_tmp / "sweep")
    result = run("plot", sweep, "--svg")
    assert result.exit_code == 0, result.stderr
    for name in ("sweep", "realtime"):
        assert_png(sweep / f"{name}.png")
        assert b"<svg" in (sweep / f"{name}.svg").read_bytes()[:2000]


def test_a_sweep_without_stage_or_neutral_axes_or_realtime_column(in_tmp):
    sweep = write_sweep(in_tmp / "sweep", stages=(), neutral=(), directions=("forward",), realtime=False)
    result = run("plot", sweep, "--out", in_tmp / "s.png")
    assert result.exit_code == 0, result.stderr
    assert_png(in_tmp / "s.png")
    assert not (in_tmp / "s-realtime.png").exists()


def test_a_sweep_without_the_equal_time_column_draws_the_raw_deltas_only(in_tmp):
    sweep = write_sweep(in_tmp / "sweep", equal_time=False, realtime=False)
    ((fig, _),) = sweep_figures(sweep, sweep / "sweep.png")
    labels = [ax.get_ylabel() for ax in fig.axes if ax.get_ylabel()]
    assert labels == ["Δfuel [%]", "Δtime [%]"]


def test_a_sweep_without_a_horizon_axis_plots_against_the_axis_that_varies(in_tmp):
    sweep = write_sweep(in_tmp / "sweep", horizons=[1500], deltas=(0.1, 0.15, 0.2, 0.25), neutral=())
    assert run("plot", sweep).exit_code == 0
    assert_png(sweep / "sweep.png")


def test_a_sweep_with_no_varying_numeric_axis_fails_in_one_line(in_tmp):
    sweep = write_sweep(in_tmp / "sweep", horizons=[1500], stages=(25,), deltas=(0.2,))
    assert_one_line_error(run("plot", sweep), "no numeric grid axis varies")


# ---------------------------------------------------------------------------------------------
# errors


def test_an_empty_or_missing_dir_fails_in_one_line(in_tmp):
    (in_tmp / "empty").mkdir()
    assert_one_line_error(run("plot", in_tmp / "empty"), "neither a run directory", "nor a sweep directory")
    assert_one_line_error(run("plot", in_tmp / "missing"), "not a directory")
    assert list((in_tmp / "empty").iterdir()) == []


def test_without_matplotlib_plot_says_how_to_install_it(run_dirs, monkeypatch):
    for name in [m for m in sys.modules if m == "matplotlib" or m.startswith("matplotlib.")]:
        monkeypatch.setitem(sys.modules, name, None)
    monkeypatch.setitem(sys.modules, "matplotlib", None)  # `import matplotlib...` now raises ImportError
    both, _ = run_dirs
    result = run("plot", both, "--out", "pics")
    assert_one_line_error(result)
    assert result.stderr == f"error: {MISSING_MATPLOTLIB}\n"
    assert MISSING_MATPLOTLIB == "plotting needs matplotlib: pip install 'truckmpc[plot]'"
    assert not Path("pics").exists()

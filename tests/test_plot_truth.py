"""The pictures say what the run did: titles carry every controller and its headline Δ as
``summary.json`` has it, the set speed and band follow the road's targets and the run's band
settings, stops are marked, and the sweep figure has the Δfuel at equal trip time beside the raw one.

Each test inspects the matplotlib Figure the command would save, against truths read independently
(the summary's own numbers, the road file written or parsed here, the sweep's CSV)."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from truckmpc.cli import app
from truckmpc.plot.road import road_figure
from truckmpc.plot.run import run_figure
from truckmpc.plot.sweep import sweep_figures
from truckmpc.roads import load_road
from truckmpc.sweep.columns import delta_column

runner = CliRunner()
VDRI = Path("../shared/roads/raw/vecto-longhaul-2015.vdri")
LABELS = {"pi": "PI", "pcc": "PCC", "mpc": "MPC", "optimal": "optimum"}
LINE_START = {"pcc": "PCC (VECTO): ", "mpc": "MPC: ", "optimal": "whole-road optimum: "}


def simulate(out: Path, *args: object) -> dict:
    result = runner.invoke(app, ["simulate", "--out", str(out), *(str(a) for a in args)])
    assert result.exit_code == 0, result.stderr
    return json.loads((out / "summary.json").read_text())


def pct(value: float) -> str:
    """A Δ as a person reads it in the title: signed, two decimals, a real minus sign."""
    return f"{value:+.2f} %".replace("-", "−")


def title(fig) -> str:
    return fig._suptitle.get_text()


def speed_axes(fig):
    return next(ax for ax in fig.axes if ax.get_ylabel() == "speed [km/h]")


def by_gid(ax, gid: str) -> list:
    return [a for a in [*ax.lines, *ax.collections] if a.get_gid() == gid]


# ---------------------------------------------------------------------------------------------
# titles


@pytest.mark.parametrize("controllers", ["pi,pcc,mpc", "pi,optimal", "pi,pcc", "pi,pcc,mpc,optimal"])
def test_the_title_names_every_controller_with_its_delta_from_the_summary(tmp_path, controllers):
    summary = simulate(tmp_path, "--controller", controllers)
    text = title(run_figure(tmp_path))
    names = controllers.split(",")
    first = text.splitlines()[0]
    assert all(("optimum" if n == "optimal" else LABELS[n]) in first for n in names), text
    for entry in summary["comparisons"]:
        if entry["baseline"] not in ("pi", "pcc"):
            continue
        line = next(ln for ln in text.splitlines() if ln.startswith(LINE_START[entry["controller"]]))
        base = LABELS[entry["baseline"]]
        equal = entry.get("delta_fuel_equal_time_pct")
        if equal is not None:
            assert f"{pct(equal)} vs {base}" in line and "equal trip time" in line, (entry, text)
        else:
            assert f"Δfuel {pct(entry['delta_fuel_pct'])}, Δtime {pct(entry['delta_time_pct'])} vs {base}" in line
    assert "only" not in text


def test_a_pi_only_title_names_the_pi_and_no_delta(tmp_path):
    simulate(tmp_path, "--controller", "pi")
    text = title(run_figure(tmp_path))
    assert "PI" in text and "Δ" not in text and "only" not in text


def test_an_old_summary_without_comparisons_still_gives_each_controllers_delta(tmp_path):
    """Top-level keys suffixed with the controller's name (several look-ahead controllers), no
    equal-time figure for the PCC: its raw Δ is shown instead."""
    summary = simulate(tmp_path, "--controller", "pi,pcc,mpc")
    old = {k: v for k, v in summary.items() if k != "comparisons"}
    del old["delta_fuel_equal_time_pct_pcc"]
    (tmp_path / "summary.json").write_text(json.dumps(old))
    text = title(run_figure(tmp_path))
    pcc_line = next(ln for ln in text.splitlines() if ln.startswith("PCC"))
    mpc_line = next(ln for ln in text.splitlines() if ln.startswith("MPC:"))
    assert pct(summary["delta_fuel_pct_pcc"]) in pcc_line and pct(summary["delta_time_pct_pcc"]) in pcc_line
    assert "raw" in pcc_line
    assert pct(summary["delta_fuel_equal_time_pct_mpc"]) in mpc_line and "equal trip time" in mpc_line


# ---------------------------------------------------------------------------------------------
# set speed, band and stops


def write_target_road(path: Path) -> tuple[list[tuple[float, float, float]], float]:
    """A flat 8 km road CSV: 80 km/h, then 60, 30 and 80 km/h stretches of 2 km, and a 30 s stop at
    5 km. Returns the stretches (from [m], to [m], target [km/h]) and the stop's place [m]."""
    stretches = [(0.0, 2000.0, 80.0), (2000.0, 4000.0, 60.0), (4000.0, 6000.0, 30.0), (6000.0, 8000.0, 80.0)]
    stop_m = 5000.0
    rows = ["distance_m,altitude_m,target_speed_kmh,stop_s"]
    for d in np.arange(0.0, 8001.0, 100.0):
        target = next((v for lo, hi, v in stretches if lo <= d < hi), 80.0)
        rows.append(f"{d:g},0,{target:g},{30 if d == stop_m else 0}")
    path.write_text("\n".join(rows) + "\n")
    return stretches, stop_m


def test_set_speed_band_and_stops_follow_a_road_csvs_targets(tmp_path):
    stretches, stop_m = write_target_road(tmp_path / "targets.csv")
    summary = simulate(
        tmp_path / "run", "--road", tmp_path / "targets.csv", "--controller", "pi", "--set", "v_dec_kmh=6"
    )
    cruise = summary["run"]["settings"]["cruise"]
    ax = speed_axes(run_figure(tmp_path / "run"))
    (set_line,) = by_gid(ax, "set-speed")
    km, kmh = np.asarray(set_line.get_xdata()), np.asarray(set_line.get_ydata())
    for lo, hi, target in stretches:
        inside = (km * 1000 >= lo) & (km * 1000 < hi)
        assert inside.any() and np.allclose(kmh[inside], min(target, cruise["v_ref_kmh"]))
    (band,) = by_gid(ax, "band")
    vertices = band.get_paths()[0].vertices
    for lo, hi, target in stretches:  # the band of a stretch's first half, away from the falling top
        near = np.abs(vertices[:, 0] * 1000 - (lo + 0.25 * (hi - lo))) < 30
        set_kmh = min(target, cruise["v_ref_kmh"])
        assert vertices[near, 1].min() == pytest.approx(max(set_kmh - cruise["v_dec_kmh"], 5.0))
        assert vertices[near, 1].max() == pytest.approx(set_kmh + cruise["v_inc_kmh"])
    stops = by_gid(ax, "stop")
    assert [line.get_xdata()[0] * 1000 for line in stops] == [pytest.approx(stop_m)]


def test_without_targets_the_band_is_the_runs_own(tmp_path):
    summary = simulate(tmp_path, "--controller", "pi", "--set", "v_ref_kmh=70", "--set", "v_dec_kmh=3")
    cruise = summary["run"]["settings"]["cruise"]
    ax = speed_axes(run_figure(tmp_path))
    (set_line,) = by_gid(ax, "set-speed")
    assert np.all(np.asarray(set_line.get_ydata()) == cruise["v_ref_kmh"])
    y = by_gid(ax, "band")[0].get_paths()[0].vertices[:, 1]
    assert (y.min(), y.max()) == (pytest.approx(67.0), pytest.approx(70.0 + cruise["v_inc_kmh"]))
    assert by_gid(ax, "stop") == []


def read_vdri(path: Path) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The cycle's <s> [m], <v> [km/h] and <stop> [s] columns, parsed here."""
    with path.open() as handle:
        rows = [r for r in csv.reader(handle) if r and not r[0].startswith("#")]
    table = np.array([[float(x) for x in r[:4]] for r in rows[1:]])
    return table[:, 0], table[:, 1], table[:, 3]


def test_the_vdri_cycles_targets_and_stops_are_drawn(tmp_path):
    summary = simulate(tmp_path, "--road", VDRI, "--controller", "pi")
    v_ref = summary["run"]["settings"]["cruise"]["v_ref_kmh"]
    s_m, v_kmh, stop_s = read_vdri(VDRI)
    ax = speed_axes(run_figure(tmp_path))
    (set_line,) = by_gid(ax, "set-speed")
    x_m, y = np.asarray(set_line.get_xdata()) * 1000, np.asarray(set_line.get_ydata())
    row = np.searchsorted(s_m, x_m, side="right") - 1  # the cycle's row whose target holds at x
    moving = (row < len(s_m) - 1) & (v_kmh[np.clip(row, 0, None)] > 0)
    assert moving.sum() > 100
    assert np.allclose(y[moving], np.minimum(v_kmh[row[moving]], v_ref))
    assert {60.0, 30.0} <= set(np.round(y, 6))  # the cycle's slow stretches, not a fixed v_ref
    stops = sorted(line.get_xdata()[0] * 1000 for line in by_gid(ax, "stop"))
    assert stops == pytest.approx(sorted(s_m[stop_s > 0]))


def test_a_moved_road_file_leaves_the_band_uniform_and_says_so(tmp_path):
    write_target_road(tmp_path / "targets.csv")
    simulate(tmp_path / "run", "--road", tmp_path / "targets.csv", "--controller", "pi")
    (tmp_path / "targets.csv").unlink()
    ax = speed_axes(run_figure(tmp_path / "run"))
    (set_line,) = by_gid(ax, "set-speed")
    assert "not drawn" in set_line.get_label()


# ---------------------------------------------------------------------------------------------
# sweeps


def test_the_sweep_figure_has_the_equal_time_delta_beside_the_raw_one(tmp_path):
    out = tmp_path / "sweep"
    result = runner.invoke(
        app,
        ["sweep", "--road", "../shared/roads/us_epa_gem_ph2_grade_20km.csv", "--grid", "horizon_m=500,1500",
         "--controller", "pcc,mpc", "--jobs", "1", "--quiet", "--out", str(out)],
    )  # fmt: skip
    assert result.exit_code == 0, result.stderr
    with (out / "sweep.csv").open() as handle:
        rows = list(csv.DictReader(handle))
    (fig, _), *_ = sweep_figures(out, out / "sweep.png")
    for name, label in (("mpc", "MPC"), ("pcc", "PCC")):
        for kind in ("fuel", "fuel_equal_time"):
            column = delta_column(name, kind)
            ax = next(
                a
                for a in fig.axes
                if a.get_ylabel().startswith(f"{label} Δfuel") and ("equal" in a.get_ylabel()) == (kind != "fuel")
            )
            (line,) = [ln for ln in ax.lines if ln.get_marker() == "o"]  # the data, not the zero line
            expected = sorted((float(r["horizon_m"]), float(r[column])) for r in rows)
            assert np.allclose(np.column_stack([line.get_xdata(), line.get_ydata()]), expected)
    # one line per panel, named by its y label: no legend calling every line "MPC and PCC"
    assert fig.legends == []


def test_the_road_figure_draws_a_cycles_targets_and_stops(tmp_path):
    stretches, stop_m = write_target_road(tmp_path / "targets.csv")
    fig = road_figure(load_road(tmp_path / "targets.csv"))
    ax = next(a for a in fig.axes if a.get_ylabel() == "target speed [km/h]")
    (line,) = by_gid(ax, "target")
    km, kmh = np.asarray(line.get_xdata()), np.asarray(line.get_ydata())
    for lo, hi, target in stretches:
        inside = (km * 1000 >= lo) & (km * 1000 < hi)
        assert inside.any() and np.all(kmh[inside] == target)
    for panel in fig.axes:
        assert [s.get_xdata()[0] * 1000 for s in by_gid(panel, "stop")] == [pytest.approx(stop_m)]

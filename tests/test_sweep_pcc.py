"""`truckmpc sweep --controller`: the rule-based PCC in sweeps, alone or with the MPC, against the PI;
its columns, comparisons, resume, errors and plot."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

import truckmpc.sweep.task as sweep_task
from truckmpc import _core, load_road, load_run_config, make_section, run_sweep, simulate, write_road
from truckmpc.cli import app
from truckmpc.sweep import PARTIAL_NAME, SWEEP_COLUMNS
from truckmpc.sweep.cells import parse_cell
from truckmpc.sweep.columns import PCC_FIELDS, PI_FIELDS, WALL_TIME_COLUMNS

runner = CliRunner()
PCC_DELTAS = ("pcc_delta_fuel_pct", "pcc_delta_time_pct", "pcc_delta_fuel_equal_time_pct")
SUMMARY_KEYS = (
    (("mpc", "pi"), "delta_fuel_pct", "mpc_delta_fuel_pct"),
    (("mpc", "pi"), "delta_time_pct", "mpc_delta_time_pct"),
    (("mpc", "pi"), "delta_fuel_equal_time_pct", "mpc_delta_fuel_equal_time_pct"),
    (("pcc", "pi"), "delta_fuel_pct", "pcc_delta_fuel_pct"),
    (("pcc", "pi"), "delta_time_pct", "pcc_delta_time_pct"),
    (("pcc", "pi"), "delta_fuel_equal_time_pct", "pcc_delta_fuel_equal_time_pct"),
    (("mpc", "pcc"), "delta_fuel_pct", "mpc_delta_fuel_vs_pcc_pct"),
    (("mpc", "pcc"), "delta_fuel_equal_time_pct", "mpc_delta_fuel_equal_time_vs_pcc_pct"),
)
"""(controller, baseline) of an entry of summary.json's comparisons, its key, and the sweep's column."""


@pytest.fixture(scope="module")
def descent(tmp_path_factory) -> Path:
    """A short road: 600 m flat, 300 m at -3 %, 100 m flat (the PCC coasts where the PI brakes). The
    flat lead lets the PCC's trip time follow its set speed: with 100 m the PCC coasts from the start
    at any set speed and no PCC run matches a faster trip time."""
    path = tmp_path_factory.mktemp("roads") / "descent.csv"
    write_road(make_section("hill", 300, -3.0, lead_m=600, tail_m=100), path)
    return path


@pytest.fixture
def core_runs(monkeypatch) -> list[str]:
    """Every controller the core drives in this process (sweep runs, baselines and equal-time searches)."""
    driven: list[str] = []
    real = _core.run

    def recorded(settings, road, altitude, controller, controller_road=None):
        driven.append(controller)
        return real(settings, road, altitude, controller, controller_road)

    monkeypatch.setattr(_core, "run", recorded)
    return driven


def untimed(rows: list[dict[str, str]]) -> list[dict[str, str]]:
    return [{k: v for k, v in row.items() if k not in WALL_TIME_COLUMNS} for row in rows]


def read_csv(path: Path) -> list[dict[str, str]]:
    with path.open(newline="", encoding="utf-8") as handle:
        return list(csv.DictReader(handle))


def sweep(args: list[str]):
    result = runner.invoke(app, ["sweep", *args])
    assert result.exit_code == 0, result.output
    return result


def test_a_pcc_sweep_gives_simulates_figures_and_runs_no_mpc(descent, tmp_path, core_runs):
    """`--controller pcc` over a PCC key: PI and PCC columns only, each row's PCC figures those of
    simulate(road, config, "pcc") with the row's value, the deltas those of its fuel and time columns,
    one PI run shared by both rows, and no MPC anywhere."""
    out = tmp_path / "pcc"
    grid = ["--grid", "pcc_enabling_speed_kmh=80,100"]
    result = sweep(["--road", str(descent), "--controller", "pcc", *grid, "--jobs", "1", "--out", str(out)])
    assert "mpc" not in core_runs and "pcc" in core_runs
    assert "2 PCC and 1 PI runs" in result.stdout
    rows = read_csv(out / "sweep.csv")
    header = list(rows[0])
    assert not any(column.startswith("mpc_") for column in header)
    assert {f"pcc_{name}" for name in PCC_FIELDS} | set(PCC_DELTAS) <= set(header)
    road = load_road(descent)
    for row in rows:
        config = load_run_config(overrides=(f"pcc_enabling_speed_kmh={row['pcc_enabling_speed_kmh']}",))
        expected = simulate(road, config, "pcc").summary
        for name in (*PI_FIELDS, "neutral_distance_m"):
            assert parse_cell(row[f"pcc_{name}"]) == expected[name], name
        check_deltas_against_pi(row)
    assert rows[0]["pcc_fuel_kg"] != rows[1]["pcc_fuel_kg"]  # the axis reaches the PCC
    assert rows[0]["pi_fuel_kg"] == rows[1]["pi_fuel_kg"]


def check_deltas_against_pi(row: dict[str, str]) -> None:
    """The PCC's Δ columns are (PCC − PI) / PI of its fuel and time columns, and of its fuel against
    the PI re-tuned to its trip time."""
    pcc_fuel, pi_fuel = float(row["pcc_fuel_kg"]), float(row["pi_fuel_kg"])
    assert float(row["pcc_delta_fuel_pct"]) == pytest.approx(100 * (pcc_fuel / pi_fuel - 1), rel=1e-12)
    time_ratio = float(row["pcc_time_s"]) / float(row["pi_time_s"])
    assert float(row["pcc_delta_time_pct"]) == pytest.approx(100 * (time_ratio - 1), rel=1e-12)
    equal_fuel = float(row["pcc_equal_time_pi_fuel_kg"])
    assert float(row["pcc_delta_fuel_equal_time_pct"]) == pytest.approx(100 * (pcc_fuel / equal_fuel - 1), rel=1e-12)


def test_pcc_and_mpc_sweep_gives_simulates_comparisons(descent, tmp_path):
    """`--controller mpc,pcc`: the MPC's columns as without the PCC, the PCC's beside them, and every
    comparison (each against the PI, the MPC against the PCC, raw and at equal trip time) equal to
    the `comparisons` of `simulate --controller pi,pcc,mpc` at the same settings."""
    out = tmp_path / "both"
    sweep(["--road", str(descent), "--controller", "mpc,pcc", "--grid", "horizon_m=250", "--out", str(out)])
    (row,) = read_csv(out / "sweep.csv")
    assert set(SWEEP_COLUMNS) <= set(row)
    args = ["--road", str(descent), "--controller", "pi,pcc,mpc", "--set", "horizon_m=250"]
    run = runner.invoke(app, ["simulate", *args, "--out", str(tmp_path / "s")])
    assert run.exit_code == 0, run.output
    summary = json.loads((tmp_path / "s" / "summary.json").read_text())
    comparisons = {(c["controller"], c["baseline"]): c for c in summary["comparisons"]}
    for pair, key, column in SUMMARY_KEYS:
        assert float(row[column]) == pytest.approx(comparisons[pair][key], rel=1e-12), column
    mpc_fuel, pcc_fuel = float(row["mpc_fuel_kg"]), float(row["pcc_fuel_kg"])
    assert float(row["mpc_delta_fuel_vs_pcc_pct"]) == pytest.approx(100 * (mpc_fuel / pcc_fuel - 1), rel=1e-12)
    assert float(row["pcc_fuel_kg"]) == summary["pcc"]["fuel_kg"]
    check_deltas_against_pi(row)


def test_resume_reuses_the_pcc_runs_of_finished_rows(descent, tmp_path, monkeypatch):
    """An axis over an MPC key shares one PI and one PCC run; resuming with one row finished runs
    only the missing MPC run (PI and PCC figures read back from the finished row) and gives the same
    CSV."""
    counts: dict[str, int] = {}

    def counted(road, config, controller="pi"):
        counts[controller] = counts.get(controller, 0) + 1
        return simulate(road, config, controller)

    monkeypatch.setattr(sweep_task, "simulate", counted)
    out, grid = tmp_path / "out", ["horizon_m=250,500"]
    full = run_sweep([descent], grid, out, jobs=1, controllers=["pcc", "mpc"])
    assert counts == {"pi": 1, "pcc": 1, "mpc": 2} and dict(full.runs) == counts
    lines = (out / "sweep.csv").read_text().splitlines(keepends=True)
    (out / "sweep.csv").unlink()
    (out / PARTIAL_NAME).write_text(lines[0] + lines[2])
    counts.clear()
    resumed = run_sweep([descent], grid, out, jobs=1, controllers=["pcc", "mpc"])
    assert counts == {"mpc": 1} and resumed.resumed_rows == 1
    assert untimed(resumed.rows) == untimed(full.rows)


@pytest.mark.parametrize(
    ("args", "expected"),
    [
        (["--controller", "bogus"], "error: Invalid value for '--controller': expected a comma list of pcc, mpc"),
        (["--controller", "pi,mpc"], "the pi always runs, as the baseline), got 'pi,mpc'"),
        (["--controller", "pcc,pcc"], "each once"),
        (["--controller", ""], "'--controller'"),
        (["--controller", "pcc", "--check-convergence"], "error: --check-convergence: expected mpc in --controller"),
    ],
)
def test_a_bad_controller_is_one_line_exit_2_and_writes_nothing(descent, tmp_path, args, expected):
    out = tmp_path / "out"
    result = runner.invoke(app, ["sweep", "--road", str(descent), *args, "--out", str(out)])
    assert result.exit_code == 2
    assert result.stderr.startswith("error: ") and result.stderr.count("\n") == 1, result.stderr
    assert expected in result.stderr
    assert not out.exists()


def test_the_sweep_plot_draws_the_pcc_deltas(descent, tmp_path, monkeypatch):
    """A PCC-only sweep plots without the MPC's real-time picture; the plot of a PCC and MPC sweep has
    a PCC Δfuel panel whose line is the CSV's pcc_delta_fuel_pct against the horizon."""
    pytest.importorskip("matplotlib")
    import truckmpc.plot.sweep as plot_sweep

    grid = ["--grid", "horizon_m=250,500"]
    alone = tmp_path / "alone"
    sweep(["--road", str(descent), "--controller", "pcc", *grid, "--jobs", "1", "--out", str(alone)])
    result = runner.invoke(app, ["plot", str(alone)])
    assert result.exit_code == 0, result.output
    assert sorted(p.name for p in alone.glob("*.png")) == ["headline.png", "sweep.png"]
    both = tmp_path / "both"
    sweep(["--road", str(descent), "--controller", "pcc,mpc", *grid, "--jobs", "1", "--out", str(both)])
    drawn = []

    def kept(figures, svg):
        drawn.extend(figures)
        return [path for _, path in figures]

    monkeypatch.setattr(plot_sweep, "save", kept)
    plot_sweep.plot_sweep(both, both / "sweep.png")
    axes = {ax.get_ylabel(): ax for ax in drawn[0][0].axes}
    assert {"MPC Δfuel [%]", "MPC Δtime [%]", "PCC Δfuel [%]", "PCC Δtime [%]"} <= set(axes)
    (line,) = [line for line in axes["PCC Δfuel [%]"].get_lines() if list(line.get_xdata()) == [250, 500]]
    assert list(line.get_ydata()) == [float(row["pcc_delta_fuel_pct"]) for row in read_csv(both / "sweep.csv")]


def test_the_default_sweep_keeps_its_columns():
    """Without --controller the columns are the error column (blank unless a run of the row failed),
    the MPC's headline against the PI (% and kg, issue 44), the PI's and the MPC's figures, every
    controller's gear shifts and neutral engagements apart, each also per 100 km (issue 25), then the
    MPC's Δ against the PI: each prefixed by its controller."""
    gears = ["gear_shifts", "gear_shifts_per_100km", "neutral_engagements", "neutral_engagements_per_100km"]
    figures = ["fuel_kg", "fuel_corrected_kg", "time_s", "end_speed_kmh", "brake_energy_kj", *gears, "stalled"]
    mpc_own = ["neutral_distance_m", "realtime_ratio", "solve_ms_mean", "solve_ms_max", "infeasible_solves"]
    equal_time = ["equal_time_pi_v_ref_kmh", "equal_time_pi_fuel_kg", "equal_time_pi_fuel_corrected_kg"]
    deltas = ["fuel", "time", "fuel_corrected", "fuel_equal_time", "fuel_equal_time_corrected"]
    assert list(SWEEP_COLUMNS) == [
        "error",
        "mpc_headline_pct",
        "mpc_saved_kg",
        *(f"pi_{name}" for name in figures),
        *(f"mpc_{name}" for name in figures),
        *(f"mpc_{name}" for name in mpc_own),
        "mpc_transitions_per_solve",
        *(f"mpc_{name}" for name in equal_time),
        *(f"mpc_delta_{name}_pct" for name in deltas),
    ]

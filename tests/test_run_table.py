"""The table `truckmpc simulate` prints, read back from its text and checked against the numbers
of the summary.json it wrote (read independently): each Δ in its own controller's column, the
headline first, no empty row, the details only under --verbose, no "vs PCC" row without a PCC,
and the same table built from the summary.json alone (as `truckmpc report` has only the files)."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from typer.testing import CliRunner

from table_text import PrintedTable, parse_table
from truckmpc import TRACE_COLUMNS, RunResult, format_table, make_section
from truckmpc.cli import app
from truckmpc.results.run_rows import LEGEND_PCC
from truckmpc.results.run_table import render_text, run_table

runner = CliRunner()

MEASURES = {  # the summary's Δ key in each comparison, and the row that prints it
    "headline_pct": "Δfuel at equal trip time and end speed vs {} [%]",
    "delta_fuel_equal_time_pct": "Δfuel at equal trip time vs {} [%]",
    "delta_fuel_pct": "Δfuel vs {} [%]",
    "delta_time_pct": "Δtrip time vs {} [%]",
    "delta_fuel_corrected_pct": "Δfuel, end speeds corrected vs {} [%]",
}
SOLVER_ROWS = ("horizon solves", "infeasible solves", "solve time mean [ms]", "solve time max [ms]")


def simulate(out: Path, *args: str) -> tuple[PrintedTable, dict[str, Any], str]:
    """Run `truckmpc simulate` into `out`: the printed table, the summary.json, the output."""
    result = runner.invoke(app, ["simulate", "--out", str(out), *args])
    assert result.exit_code == 0, result.output
    return parse_table(result.stdout), json.loads((out / "summary.json").read_text()), result.stdout


@pytest.fixture(scope="module")
def three(tmp_path_factory: pytest.TempPathFactory) -> tuple[PrintedTable, dict[str, Any], str]:
    """PI, PCC and MPC on the bundled test track, printed plainly."""
    return simulate(tmp_path_factory.mktemp("three"), "--controller", "pi,pcc,mpc")


@pytest.fixture(scope="module")
def three_verbose(three: tuple[PrintedTable, dict[str, Any], str]) -> PrintedTable:
    """The same run's table with --verbose, built from its summary.json."""
    return parse_table(render_text(run_table(three[1], verbose=True)))


def test_each_delta_stands_in_its_own_controllers_column(three):
    table, summary, _ = three
    assert table.columns == ["pi", "pcc", "mpc"]
    checked = 0
    for entry in summary["comparisons"]:
        baseline = {"pi": "PI", "pcc": "PCC"}[entry["baseline"]]
        for key, label in MEASURES.items():
            cells = table.row(label.format(baseline))
            assert cells[entry["controller"]] == f"{entry[key]:+.2f}", (label, entry)
            assert cells[entry["baseline"]] == ""  # the baseline's own cell is blank
            checked += 1
    assert checked == 3 * len(MEASURES)  # pcc and mpc vs pi, mpc vs pcc
    # No Δ sits under the PI (the old table put every controller's Δ there), nor the PCC's vs itself.
    for label, cells in table.rows:
        if label.startswith("Δ"):
            assert cells["pi"] == "", label
            assert not (label.endswith("vs PCC [%]") and cells["pcc"]), label


def test_the_headline_comes_first_with_the_summarys_numbers(three):
    table, summary, _ = three
    assert table.labels()[:6] == [
        "fuel [kg]",
        "trip time [s]",
        "Δfuel at equal trip time and end speed vs PI [%]",
        "Δfuel at equal trip time and end speed vs PCC [%]",
        "Δfuel at equal trip time vs PI [%]",
        "Δfuel at equal trip time vs PCC [%]",
    ]
    assert table.heading.startswith("road test-track: 8.50 km; truck 40000 kg; v_ref 85 km/h, band 77-90 km/h")
    for name in table.columns:
        assert table.row("fuel [kg]")[name] == f"{summary[name]['fuel_kg']:.3f}"
        assert table.row("trip time [s]")[name] == f"{summary[name]['time_s']:.1f}"
    assert summary["delta_fuel_equal_time_pct_mpc"] is not None
    assert table.row("Δfuel at equal trip time vs PI [%]")["mpc"] == f"{summary['delta_fuel_equal_time_pct_mpc']:+.2f}"
    # The headline: the PCC's fuel at the MPC's trip time and both end speeds priced, read from the
    # re-run's figures rather than from the comparison's own Δ.
    pcc = summary["equal_time_mpc_vs_pcc"]
    fair = 100 * (summary["mpc"]["fuel_corrected_kg"] / pcc["pcc_fuel_corrected_kg"] - 1)
    assert table.row("Δfuel at equal trip time and end speed vs PCC [%]")["mpc"] == f"{fair:+.2f}"


def test_driving_figures_count_neutral_and_eco_roll_apart_from_gear_shifts(three):
    table, summary, _ = three
    for label, key, scale, spec in (
        ("gear shifts per 100 km", "gear_shifts_per_100km", 1, ".1f"),
        ("neutral coasting: entries per 100 km", "neutral_engagements_per_100km", 1, ".1f"),
        ("neutral coasting: distance [km]", "neutral_distance_m", 1e-3, ".1f"),
        ("brake energy [MJ]", "brake_energy_kj", 1e-3, ".1f"),
        ("end speed [km/h]", "end_speed_kmh", 1, ".2f"),
    ):
        assert table.row(label) == {n: format(summary[n][key] * scale, spec) for n in table.columns}, label
    # Eco-roll is the PCC's rule: its row has the PCC's count and nothing under the others.
    eco = summary["pcc"]["eco_roll_entries_per_100km"]
    assert table.row("PCC eco-roll entries per 100 km") == {"pi": "", "pcc": f"{eco:.1f}", "mpc": ""}


def test_no_printed_row_is_empty(three, three_verbose):
    for table in (three[0], three_verbose):
        assert table.rows
        for label, cells in table.rows:
            assert any(cells.values()), label


def test_the_legend_tells_how_to_read_the_deltas(three):
    table, _, _ = three
    legend = [line for line in table.after if line.startswith(("Δ [%] =", "At equal trip time:"))]
    assert len(legend) == 2 and "negative = less than the baseline" in legend[0]
    assert "equal trip time" in legend[1]


def test_verbose_adds_the_solver_rows_and_the_search_plain_output_does_not(three, three_verbose, tmp_path):
    plain, summary, _ = three
    for label in (*SOLVER_ROWS, "compute time [s]", "PI re-run: v_ref [km/h]"):
        assert label not in plain.labels()
    assert three_verbose.row("horizon solves") == {"pi": "", "pcc": "", "mpc": str(summary["mpc"]["horizon_solves"])}
    equal = summary["equal_time_mpc_vs_pcc"]
    assert three_verbose.row("PCC re-run: v_ref [km/h]")["mpc"] == f"{equal['pcc_v_ref_kmh']:.2f}"
    assert three_verbose.row("PCC re-run: search runs")["mpc"] == str(equal["pcc_runs"])
    # The option itself: `simulate --verbose` prints the solver rows.
    table, summary, _ = simulate(tmp_path / "v", "--verbose")
    assert table.row("horizon solves")["mpc"] == str(summary["mpc"]["horizon_solves"])
    assert table.row("solve time max [ms]")["mpc"] == f"{summary['mpc']['solve_ms_max']:.3f}"


def test_no_vs_pcc_row_without_a_pcc(tmp_path):
    table, summary, output = simulate(tmp_path / "both")
    assert table.columns == ["pi", "mpc"]
    assert not any("PCC" in label for label in table.labels())
    assert table.row("Δfuel at equal trip time vs PI [%]") == {
        "pi": "",
        "mpc": f"{summary['delta_fuel_equal_time_pct']:+.2f}",
    }
    assert "PCC" not in output.replace("PCC eco-roll", "")


def test_a_lone_pi_prints_no_delta_and_no_legend(tmp_path):
    table, _, _ = simulate(tmp_path / "pi", "--controller", "pi")
    assert table.columns == ["pi"]
    assert not any(label.startswith("Δ") for label in table.labels())
    assert not any(line.startswith("Δ") for line in table.after)


def test_the_table_is_built_from_summary_json_alone(three):
    _, summary, output = three
    text = render_text(run_table(summary))
    assert text in output  # the printed table is the one the file gives
    assert json.loads(json.dumps(summary)) == summary


ROAD_CSV = "distance_m,altitude_m,target_speed_kmh,stop_s\n" + "".join(
    f"{d},{20 * math.sin(d / 900):.3f},{80 if d < 3000 else 60},{20 if d == 3000 else 0}\n" for d in range(0, 6001, 100)
)


def test_a_road_with_target_speeds_and_stops(tmp_path):
    """A road with target speeds: the heading names them, the stops line stays, and the equal-time
    search's target offset is what --verbose shows (not a v_ref)."""
    road = tmp_path / "targets.csv"
    road.write_text(ROAD_CSV)
    table, summary, _ = simulate(tmp_path / "t", "--road", str(road), "--controller", "pi,mpc", "--verbose")
    assert "the road's targets up to v_ref 85 km/h, band -8/+5 km/h" in table.heading
    stops = summary["mpc"]["stops_not_simulated"]
    assert stops["legs"] == 2
    assert any(line.startswith(f"stops not simulated: {stops['count']} stops") for line in table.after)
    offset = summary["equal_time"]["pi_target_offset_kmh"]
    assert table.row("PI re-run: target offset [km/h]") == {"pi": "", "mpc": f"{offset:+.2f}"}
    assert "PI re-run: v_ref [km/h]" not in table.labels()


def _run(name: str, fuel_kg: float, time_s: float, stall_m: float | None = None) -> RunResult:
    """A run with only the figures the comparison reads (a stall at `stall_m` [m] if given)."""
    summary = {
        "fuel_kg": fuel_kg,
        "time_s": time_s,
        "stalled": stall_m is not None,
        "stall_distance_m": stall_m,
        "message": None if stall_m is None else f"stalled at km {stall_m / 1000:.2f}",
    }
    trace = {column: np.zeros(2) for column in TRACE_COLUMNS}
    return RunResult(name=name, road="flat", summary=summary, trace=trace)


def test_a_stalled_run_leaves_its_delta_cells_blank_and_says_why_once():
    runs = {"pi": _run("pi", 20.0, 400.0), "pcc": _run("pcc", 19.0, 402.0), "mpc": _run("mpc", 1.0, 40.0, 980.0)}
    table = parse_table(format_table(make_section("flat", 2000), runs))
    assert table.row("Δfuel vs PI [%]") == {"pi": "", "pcc": "-5.00", "mpc": ""}
    assert "Δfuel vs PCC [%]" not in table.labels()  # the only one against the PCC stalled
    assert table.after.count("mpc vs pi, pcc: not comparable: mpc stalled at km 0.98") == 1
    assert "mpc: stalled at km 0.98" in table.after


def test_the_pccs_neutral_entries_beside_its_eco_roll_entries_are_explained(three, tmp_path):
    """On the test track the PCC declutches about 35 times per 100 km and never by eco-roll: the
    line under the table says its coasting use cases make the difference. Without the PCC no line."""
    _, summary, printed = three
    pcc = summary["pcc"]
    assert pcc["neutral_engagements_per_100km"] > pcc["eco_roll_entries_per_100km"]
    assert LEGEND_PCC in printed.splitlines()
    _, _, without = simulate(tmp_path / "pi-mpc", "--controller", "pi,mpc")
    assert LEGEND_PCC not in without


def _ending(end_kmh: float) -> dict[str, Any]:
    return {"fuel_kg": 5.0, "time_s": 800.0, "end_speed_kmh": end_kmh}


@pytest.mark.parametrize(("raw", "fair", "said"), [(-5.54, -4.59, True), (-5.0, -4.6, False), (-4.0, -4.51, True)])
def test_a_run_whose_end_speeds_move_the_equal_time_delta_by_over_half_a_point_says_so_once(raw, fair, said):
    """A constructed summary: the note names the pair and both figures only when the raw and the
    corrected Δ at equal trip time lie more than 0.5 points apart (either way)."""
    entry = {"controller": "mpc", "baseline": "pi", "delta_fuel_equal_time_pct": raw, "headline_pct": fair}
    summary = {"pi": _ending(84.8), "mpc": _ending(79.6), "comparisons": [entry]}
    lines = render_text(run_table(summary)).splitlines()
    notes = [line for line in lines if line.startswith("end speeds:")]
    assert len(notes) == int(said)
    if said:
        assert f"mpc vs PI {raw:+.2f} → {fair:+.2f} %" in notes[0] and "mpc ends at 79.6 km/h" in notes[0]

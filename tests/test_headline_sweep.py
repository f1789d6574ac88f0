"""Issue 44: the headline (a look-ahead controller's saving at equal trip time and equal end speed)
in the sweep's rows, in a resumed sweep an earlier version wrote, in the fleet summary and in the
sweep's console lines. Each figure is recomputed here from the row's own fuels."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest

from truckmpc import make_section, run_sweep, write_road
from truckmpc.cli.sweep import _sweep_deltas
from truckmpc.compare import headline
from truckmpc.sweep import PARTIAL_NAME
from truckmpc.sweep.renamed import ADDED_COLUMNS
from truckmpc.sweep.savings import savings, savings_column
from truckmpc.sweep.summary import summarise, summary_lines


@pytest.fixture(scope="module")
def descent(tmp_path_factory) -> Path:
    """A short road: 100 m flat, 300 m at -3 %, 100 m flat."""
    path = tmp_path_factory.mktemp("roads") / "descent.csv"
    write_road(make_section("hill", 300, -3.0, lead_m=100, tail_m=100), path)
    return path


def read_csv(path: Path) -> tuple[list[str], list[list[str]]]:
    with path.open(newline="", encoding="utf-8") as handle:
        header, *rows = list(csv.reader(handle))
    return header, rows


def test_the_headline_is_the_corrected_fuel_against_the_baseline_at_equal_time() -> None:
    quoted = headline(9.5, 10.0)
    assert quoted.pct == pytest.approx(-5.0) and quoted.saved == pytest.approx(0.5)
    assert headline(None, 10.0).pct is None and headline(9.5, None).saved is None


def test_sweep_rows_carry_each_look_ahead_headline_against_the_pcc_and_the_pi(descent, tmp_path) -> None:
    run_sweep([descent], ["horizon_m=250,500"], tmp_path, jobs=1, controllers=("pcc", "mpc"))
    with (tmp_path / "sweep.csv").open(newline="", encoding="utf-8") as handle:
        rows = list(csv.DictReader(handle))
    assert list(rows[0])[3:9] == [
        "error",
        "mpc_headline_vs_pcc_pct",
        "mpc_saved_vs_pcc_kg",
        "mpc_headline_pct",
        "mpc_saved_kg",
        "pcc_headline_pct",
    ]
    for row in rows:
        for run, base, equal in (("mpc", "pi", "pi"), ("pcc", "pi", "pi"), ("mpc", "pcc", "pcc")):
            against = "" if base == "pi" else f"_vs_{base}"
            own, baseline = (
                float(row[f"{run}_fuel_corrected_kg"]),
                float(row[f"{run}_equal_time_{equal}_fuel_corrected_kg"]),
            )
            assert float(row[f"{run}_headline{against}_pct"]) == pytest.approx(100 * (own - baseline) / baseline)
            assert float(row[f"{run}_saved{against}_kg"]) == pytest.approx(baseline - own)


def test_a_sweep_an_earlier_version_wrote_resumes_and_gets_its_headline(descent, tmp_path) -> None:
    """A directory without the headline columns (in sweep.json and in its partial CSV) resumes: its
    row is kept, gets the headline from its own fuels, and only the missing row runs."""
    grid = ["horizon_m=250,500"]
    run_sweep([descent], grid, tmp_path, jobs=1)
    header, rows = read_csv(tmp_path / "sweep.csv")
    kept = [i for i, name in enumerate(header) if name not in ADDED_COLUMNS]
    assert len(kept) == len(header) - 2
    old_header = [header[i] for i in kept]
    (tmp_path / "sweep.csv").unlink()
    with (tmp_path / PARTIAL_NAME).open("w", newline="", encoding="utf-8") as handle:
        csv.writer(handle, lineterminator="\n").writerows([old_header, [rows[0][i] for i in kept]])
    settings = json.loads((tmp_path / "sweep.json").read_text(encoding="utf-8"))
    (tmp_path / "sweep.json").write_text(json.dumps({**settings, "columns": old_header}), encoding="utf-8")
    result = run_sweep([descent], grid, tmp_path, jobs=1)
    assert result.resumed_rows == 1 and result.runs["mpc"] == 1
    row = result.rows[0]
    own, baseline = float(row["mpc_fuel_corrected_kg"]), float(row["mpc_equal_time_pi_fuel_corrected_kg"])
    assert float(row["mpc_headline_pct"]) == pytest.approx(100 * (own - baseline) / baseline)
    assert float(row["mpc_saved_kg"]) == pytest.approx(baseline - own)
    assert read_csv(tmp_path / "sweep.csv")[0] == header


def fleet_row(road: str, vehicle: str, pct: float, kg: float) -> dict[str, str]:
    """A sweep row of the MPC against the PCC (and as driven against the PI) with a given headline."""
    return {
        "road": road,
        "direction": "forward",
        "vehicle": vehicle,
        "error": "",
        "mpc_headline_vs_pcc_pct": str(pct),
        "mpc_saved_vs_pcc_kg": str(kg),
        "mpc_headline_pct": "",
        "mpc_saved_kg": "",
        "mpc_delta_fuel_pct": "-1.0",
        "mpc_delta_time_pct": "0.5",
        **dict.fromkeys(("pcc_headline_pct", "pcc_saved_kg", "pcc_delta_fuel_pct", "pcc_delta_time_pct"), ""),
    }


FLEET = [
    fleet_row("short", "truck-40t", -2.0, 0.1),
    fleet_row("long", "truck-40t", -6.0, 1.2),
    fleet_row("short", "truck-20t", -1.0, 0.05),
    fleet_row("long", "truck-20t", -3.0, 0.4),
]
LENGTHS_M = {"short": 1000.0, "long": 3000.0}


def test_the_fleet_headline_per_truck_is_mean_distance_weighted_best_and_worst() -> None:
    cells = savings(FLEET[:2], "mpc", "pcc", LENGTHS_M)

    def cell(figure: str) -> str:
        return cells[savings_column("pcc", figure)]

    assert float(cell("mean_pct")) == pytest.approx(-4.0)
    assert float(cell("weighted_pct")) == pytest.approx((1000 * -2.0 + 3000 * -6.0) / 4000)  # -5.0
    assert float(cell("mean_saved_kg")) == pytest.approx(0.65) and float(cell("total_saved_kg")) == pytest.approx(1.3)
    assert (cell("best_road"), float(cell("best_pct"))) == ("long (forward, truck-40t)", -6.0)
    assert (cell("worst_road"), float(cell("worst_saved_kg"))) == ("short (forward, truck-40t)", 0.1)
    assert cell("compared") == "2"


def test_the_fleet_summary_gives_each_truck_its_headline_against_the_pcc() -> None:
    summary = summarise(FLEET, [], ["pcc", "mpc"], LENGTHS_M)
    by_truck = {(row["axis"], row["value"], row["controller"]): row for row in summary}
    light = by_truck["vehicle", "truck-20t", "mpc"]
    assert float(light[savings_column("pcc", "weighted_pct")]) == pytest.approx((1000 * -1.0 + 3000 * -3.0) / 4000)
    assert light[savings_column("pi", "compared")] == "0"  # no headline against the PI in these rows
    assert by_truck["vehicle", "truck-20t", "pcc"][savings_column("pcc", "mean_pct")] == ""  # not against itself
    lines = summary_lines(summary)
    (line,) = [line for line in lines if line.startswith("vehicle truck-20t, mpc against the PCC")]
    assert "at equal trip time and end speed: Δfuel -2.00 % on average (-2.50 % weighted by distance)" in line
    assert "0.450 kg in all" in line and "best long (forward, truck-20t) -3.00 %" in line


def test_a_sweep_line_quotes_the_headline_against_the_pcc_and_the_pi() -> None:
    row = {
        "mpc_headline_vs_pcc_pct": "-2.5",
        "mpc_saved_vs_pcc_kg": "0.25",
        "mpc_headline_pct": "-4.0",
        "mpc_saved_kg": "0.4",
        "mpc_delta_fuel_pct": "-3.08",
        "mpc_delta_time_pct": "0.1",
        "pcc_headline_pct": "",
        "pcc_saved_kg": "",
        "pcc_delta_fuel_pct": "-1.0",
        "pcc_delta_time_pct": "0.2",
    }
    line = _sweep_deltas(row, ("pcc", "mpc"))
    assert (
        "mpc at equal trip time and end speed against the PCC Δfuel -2.50 % (0.250 kg saved), against the PI " in line
    )
    assert "Δfuel -4.00 % (0.400 kg saved); as driven Δfuel vs PI -3.08 %" in line
    assert line.startswith("pcc at equal trip time and end speed against the PI -;")

"""Studies of VECTO's generic battery-electric tractor: a fleet sweep names every figure and
comparison for battery energy, gives each row what `truckmpc simulate` gives that road, and sums
its rows into the fleet summary; a Pareto study draws battery energy against trip time with β in
J/s; a fleet of both kinds of truck, and β in grams per second, are refused in one line."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from test_electric_truck import BEV_XML, needs_bev
from truckmpc import load_run_config, simulate
from truckmpc.cli import app
from truckmpc.config.keys import CONFIG_DIR
from truckmpc.consumption import ENERGY
from truckmpc.pareto import below, curves
from truckmpc.pareto.plan import pareto_columns
from truckmpc.roads import load_road

REPO = Path(__file__).resolve().parents[1]
ROADS = [REPO / "roads" / "hill_L500_A3.5.csv", REPO / "roads" / "crest_L1500_A2.csv"]
runner = CliRunner()


def _read(path: Path) -> list[dict[str, str]]:
    with path.open(newline="", encoding="utf-8") as handle:
        return list(csv.DictReader(handle))


@pytest.fixture(scope="module")
def swept(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, str]:
    out = tmp_path_factory.mktemp("bev-fleet")
    args = ["sweep", "--vehicle", str(BEV_XML), *(f"--road={road}" for road in ROADS), "--controller", "pcc,mpc"]
    result = runner.invoke(app, [*args, "--grid", "v_ref_kmh=80,85", "--jobs", "1", "--out", str(out)])
    assert result.exit_code == 0, result.output
    return out, result.output


@needs_bev
def test_a_sweep_of_a_battery_electric_truck_names_everything_for_battery_energy(swept) -> None:
    out, printed = swept
    rows = _read(out / "sweep.csv")
    header = list(rows[0])
    assert not [column for column in header if "fuel" in column or column.endswith("_kg")], header
    for column in ("pi_energy_kwh", "mpc_energy_corrected_kwh", "mpc_recovered_kwh", "mpc_soc_end_pct"):
        assert column in header
    for column in ("mpc_headline_pct", "mpc_saved_kwh", "mpc_headline_vs_pcc_pct", "mpc_saved_vs_pcc_kwh"):
        assert all(row[column] for row in rows), column
    assert "mpc_delta_energy_equal_time_pct" in header and "mpc_equal_time_pi_energy_kwh" in header
    summary = _read(out / "summary.csv")
    assert "mean_delta_energy_pct" in summary[0] and "headline_vs_pi_total_saved_kwh" in summary[0]
    assert "Δenergy" in printed and "kWh saved" in printed and "Δfuel" not in printed


@needs_bev
def test_each_row_is_what_simulate_gives_its_road(swept, tmp_path: Path) -> None:
    """The second road at 85 km/h driven by `truckmpc simulate`: the same battery energies, and the
    same headline against the PI and the PCC."""
    out, _ = swept
    row = next(r for r in _read(out / "sweep.csv") if r["road"] == ROADS[1].stem and r["v_ref_kmh"] == "85")
    args = ["simulate", "--vehicle", str(BEV_XML), "--road", str(ROADS[1]), "--controller", "pi,pcc,mpc"]
    result = runner.invoke(app, [*args, "--set", "v_ref_kmh=85", "--out", str(tmp_path / "s")])
    assert result.exit_code == 0, result.output
    doc = json.loads((tmp_path / "s" / "summary.json").read_text())
    for name in ("pi", "pcc", "mpc"):
        assert float(row[f"{name}_energy_kwh"]) == pytest.approx(doc[name]["energy_kwh"], rel=1e-12)
    compared = {(c["controller"], c["baseline"]): c for c in doc["comparisons"]}
    assert float(row["mpc_headline_pct"]) == pytest.approx(compared["mpc", "pi"]["headline_pct"], abs=1e-9)
    assert float(row["mpc_saved_vs_pcc_kwh"]) == pytest.approx(compared["mpc", "pcc"]["saved_kwh"], rel=1e-9)


@needs_bev
def test_the_fleet_summary_adds_the_rows_kwh(swept) -> None:
    out, _ = swept
    rows = _read(out / "sweep.csv")
    summary = next(s for s in _read(out / "summary.csv") if s["axis"] == "all" and s["controller"] == "mpc")
    total = sum(float(row["mpc_saved_vs_pcc_kwh"]) for row in rows)
    assert float(summary["headline_vs_pcc_total_saved_kwh"]) == pytest.approx(total, rel=1e-5)
    worst = max(float(row["mpc_delta_energy_pct"]) for row in rows)
    assert float(summary["worst_delta_energy_pct"]) == pytest.approx(worst, rel=1e-9)


@needs_bev
@pytest.mark.parametrize(
    ("args", "expected"),
    [
        (["sweep", f"--vehicle={CONFIG_DIR / 'truck-40t.yaml'}", f"--vehicle={BEV_XML}"], "all burn fuel or all"),
        (["pareto", "--vehicle", str(BEV_XML), "--set", "beta_g_per_s=2"], "its β is beta_j_per_s, in J/s"),
    ],
    ids=["a fleet of both kinds", "a Pareto study's β in g/s"],
)
def test_what_a_battery_electric_truck_cannot_join_is_refused_in_one_line(
    tmp_path: Path, args: list[str], expected: str
) -> None:
    refused = runner.invoke(app, [*args, "--road", str(ROADS[0]), "--out", str(tmp_path / "o")])
    assert refused.exit_code == 2, refused.output
    assert len(refused.output.strip().splitlines()) == 1 and expected in refused.output, refused.output
    assert not (tmp_path / "o").exists()


@needs_bev
def test_the_sweep_resumes_and_its_report_speaks_of_battery_energy(swept) -> None:
    out, _ = swept
    args = ["sweep", "--vehicle", str(BEV_XML), *(f"--road={road}" for road in ROADS), "--controller", "pcc,mpc"]
    again = runner.invoke(app, [*args, "--grid", "v_ref_kmh=80,85", "--jobs", "1", "--out", str(out)])
    assert again.exit_code == 0, again.output
    assert "4 rows resumed" in again.output
    report = runner.invoke(app, ["report", str(out)])
    assert report.exit_code == 0, report.output
    page = (out / "report.html").read_text(encoding="utf-8")
    assert "Δenergy [%]" in page and "saved [kWh]" in page and "battery energy saved [kWh]" in page
    assert "Δfuel [%]" not in page.split("<figure>")[0]


@pytest.fixture(scope="module")
def pareto_study(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, str]:
    out = tmp_path_factory.mktemp("bev-pareto")
    args = ["pareto", "--vehicle", str(BEV_XML), "--road", str(ROADS[0]), "--speeds", "82,85,88", "--jobs", "1"]
    result = runner.invoke(app, [*args, "--curves", "pi,fuel_time", "--out", str(out)])
    assert result.exit_code == 0, result.output
    return out, result.output


@needs_bev
def test_a_pareto_study_of_a_battery_electric_truck_is_of_battery_energy(pareto_study) -> None:
    """The columns are named for battery energy and β in J/s; each PI point is what `simulate`
    gives at its set speed; the look-ahead curve lies below the PI's at every common trip time, and
    the printed headline is its energy interpolated at the PI's trip time at 85 km/h."""
    out, printed = pareto_study
    rows = _read(out / "pareto.csv")
    assert tuple(rows[0]) == pareto_columns(ENERGY)
    assert "beta_j_per_s" in rows[0] and not [c for c in rows[0] if c.endswith("_kg") or "g_per_s" in c]
    road = load_road(ROADS[0])
    for row in (r for r in rows if r["controller"] == "pi"):
        config = load_run_config(str(BEV_XML), overrides=(f"v_ref_kmh={row['v_ref_kmh']}", "start_speed_kmh=85"))
        expected = simulate(road, config, "pi").summary
        assert float(row["energy_corrected_kwh"]) == pytest.approx(expected["energy_corrected_kwh"], rel=1e-12)
    betas = [float(r["beta_j_per_s"]) for r in rows if r["controller"] == "fuel_time"]
    assert betas == sorted(betas) and betas[0] > 5e4  # β of the order of the cruising power, in W
    by_controller = curves(rows)[ROADS[0].stem]
    under, margin_kwh = below(by_controller["fuel_time"], by_controller["pi"])
    assert under and margin_kwh > 0, margin_kwh
    pi85 = next(r for r in rows if r["controller"] == "pi" and float(r["value"]) == 85.0)
    energy = by_controller["fuel_time"].consumed_at(float(pi85["time_s"]))
    expected_pct = 100 * (energy / float(pi85["energy_corrected_kwh"]) - 1)
    assert f"Δenergy {expected_pct:+.2f} %" in printed and "kWh saved" in printed and "Δfuel" not in printed
    assert (out / "pareto.png").stat().st_size > 0


@needs_bev
def test_a_battery_electric_pareto_study_sweeps_beta_in_joules_per_second(tmp_path: Path) -> None:
    """`--betas` in J/s: each point runs at the β it names, and a higher price of time drives faster."""
    args = ["pareto", "--vehicle", str(BEV_XML), "--road", str(ROADS[0]), "--speeds", "85", "--jobs", "1"]
    result = runner.invoke(app, [*args, "--curves", "pi,fuel_time", "--betas", "6e4,2e5", "--out", str(tmp_path)])
    assert result.exit_code == 0, result.output
    rows = [r for r in _read(tmp_path / "pareto.csv") if r["controller"] == "fuel_time"]
    assert [(r["parameter"], float(r["beta_j_per_s"])) for r in rows] == [("beta_j_per_s", 6e4), ("beta_j_per_s", 2e5)]
    assert float(rows[0]["time_s"]) > float(rows[1]["time_s"])


@needs_bev
def test_the_robustness_study_of_a_battery_electric_truck_speaks_of_battery_energy(tmp_path: Path) -> None:
    """The exact case's headline is the one `truckmpc simulate` compares (the MPC's corrected
    battery energy against the PI re-run at its trip time), its keys and table named for energy."""
    from truckmpc import robustness as rb

    config = load_run_config(str(BEV_XML))
    mass_kg = float(config.settings.get("mass_kg"))
    row = rb.run_case(load_road(ROADS[1]), config, rb.Case("exact", mass_kg, mass_kg))
    assert {"delta_energy_pct", "delta_energy_equal_time_pct", "saved_kwh"} <= set(row)
    assert not [key for key in row if "fuel" in key or key.endswith("saved_kg")]
    args = ["simulate", "--vehicle", str(BEV_XML), "--road", str(ROADS[1]), "--controller", "pi,mpc"]
    result = runner.invoke(app, [*args, "--out", str(tmp_path / "s")])
    assert result.exit_code == 0, result.output
    compared = json.loads((tmp_path / "s" / "summary.json").read_text())["comparisons"][0]
    assert row["headline_pct"] == pytest.approx(compared["headline_pct"], abs=1e-9)
    assert row["saved_kwh"] == pytest.approx(compared["saved_kwh"], rel=1e-9)
    table = rb.format_study(rb.kept_shares([row]), "mpc")
    assert "Δenergy %" in table and "saved kWh" in table and "fuel" not in table

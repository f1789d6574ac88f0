"""Fleet studies on the embedded Dask cluster: roads from a directory and a glob, two vehicles, both
directions; a broken road file among them fails in its rows only; summary.csv, Parquet, resume."""

from __future__ import annotations

import csv
import shutil
import statistics
from pathlib import Path

import pytest
from typer.testing import CliRunner

import truckmpc.sweep.cluster as sweep_cluster
from truckmpc.cli import app
from truckmpc.config.keys import CONFIG_DIR
from truckmpc.sweep.summary import SUMMARY_COLUMNS

REPO = Path(__file__).resolve().parents[1]
TRUCKS = [str(CONFIG_DIR / "truck-20t.yaml"), str(CONFIG_DIR / "truck-40t.yaml")]
runner = CliRunner()


def read_csv(path: Path) -> list[dict[str, str]]:
    with path.open(newline="", encoding="utf-8") as handle:
        return list(csv.DictReader(handle))


@pytest.fixture(scope="module")
def fleet(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, list[str]]:
    """A directory of two roads and a file that is not a road, and a glob of one more road; the
    sweep's arguments over them with both trucks, both ways, two horizons, on two workers."""
    roads = tmp_path_factory.mktemp("roads")
    for name in ("hill_L500_A3.5.csv", "crest_L1500_A2.csv"):
        shutil.copy(REPO / "roads" / name, roads / name)
    (roads / "broken.csv").write_text("not,a,road\n")
    (roads / "notes.txt").write_text("not a road file: not read\n")
    args = ["sweep", "--road", str(roads), "--road", str(REPO / "roads" / "hill_L300_*.csv")]
    args += [*(f"--vehicle={truck}" for truck in TRUCKS), "--grid", "horizon_m=500,1000", "--both-ways"]
    return roads, [*args, "--jobs", "2", "--parquet"]


@pytest.fixture(scope="module")
def swept(fleet, tmp_path_factory: pytest.TempPathFactory):
    _, args = fleet
    out = tmp_path_factory.mktemp("fleet")
    result = runner.invoke(app, [*args, "--out", str(out)])
    assert result.exit_code == 0, result.output
    return out, result, read_csv(out / "sweep.csv")


@pytest.mark.slow
def test_one_row_per_road_direction_vehicle_and_combination(swept) -> None:
    _, _, rows = swept
    assert list(rows[0])[:5] == ["road", "direction", "vehicle", "horizon_m", "error"]
    keys = [(r["road"], r["direction"], r["vehicle"], r["horizon_m"]) for r in rows]
    roads = ["broken", "crest_L1500_A2", "hill_L500_A3.5", "hill_L300_A-3"]
    expected = [(road, d, v) for road in roads for d in ("forward", "reverse") for v in ("truck-20t", "truck-40t")]
    assert keys == [(*key, h) for key in expected for h in ("500", "1000")]
    # The 20 t truck uses less fuel than the 40 t one on the same road, direction and horizon.
    good = [r for r in rows if not r["error"]]
    by_key = {(r["road"], r["direction"], r["horizon_m"], r["vehicle"]): float(r["pi_fuel_kg"]) for r in good}
    for (road, direction, horizon, vehicle), fuel in by_key.items():
        if vehicle == "truck-20t":
            assert fuel < by_key[road, direction, horizon, "truck-40t"]


def test_a_broken_road_fails_in_its_rows_only(swept) -> None:
    _, result, rows = swept
    broken = [r for r in rows if r["road"] == "broken"]
    assert len(broken) == 8 and all(r["error"].startswith("pi, mpc: ") for r in broken)
    assert all("broken.csv:1: expected a header" in r["error"] for r in broken)
    assert all(r["pi_fuel_kg"] == r["mpc_delta_fuel_pct"] == r["mpc_stalled"] == "" for r in broken)
    others = [r for r in rows if r["road"] != "broken"]
    assert all(r["error"] == "" and r["mpc_delta_fuel_pct"] != "" for r in others)
    assert all(r["mpc_headline_pct"] == r["mpc_saved_kg"] == "" for r in broken)
    assert "all rows, mpc as driven against the PI: Δfuel " in result.stdout
    assert "; 8 failed, on broken" in result.stdout
    assert "all rows, mpc against the PI at equal trip time and end speed: Δfuel " in result.stdout


def test_the_summary_gives_mean_spread_and_worst_road_per_axis_value(swept) -> None:
    out, result, rows = swept
    summary = read_csv(out / "summary.csv")
    assert tuple(summary[0]) == SUMMARY_COLUMNS
    groups = [(s["axis"], s["value"]) for s in summary]
    assert groups == [
        ("all", ""),
        ("vehicle", "truck-20t"),
        ("vehicle", "truck-40t"),
        ("direction", "forward"),
        ("direction", "reverse"),
        ("horizon_m", "500"),
        ("horizon_m", "1000"),
    ]
    for entry in summary:
        members = [r for r in rows if entry["axis"] == "all" or r[entry["axis"]] == entry["value"]]
        fuel = [float(r["mpc_delta_fuel_pct"]) for r in members if r["mpc_delta_fuel_pct"]]
        failed = sum(bool(r["error"]) for r in members)
        assert (int(entry["rows"]), int(entry["compared"]), int(entry["failed"])) == (len(members), len(fuel), failed)
        assert float(entry["mean_delta_fuel_pct"]) == pytest.approx(statistics.fmean(fuel), rel=1e-5)
        assert float(entry["std_delta_fuel_pct"]) == pytest.approx(statistics.stdev(fuel), rel=1e-5)
        quoted = [float(r["mpc_headline_pct"]) for r in members if r["mpc_headline_pct"]]
        assert float(entry["headline_vs_pi_mean_pct"]) == pytest.approx(statistics.fmean(quoted), rel=1e-5)
        worst = max((r for r in members if r["mpc_delta_fuel_pct"]), key=lambda r: float(r["mpc_delta_fuel_pct"]))
        assert (entry["worst_road"], entry["worst_direction"], entry["worst_vehicle"]) == (
            worst["road"],
            worst["direction"],
            worst["vehicle"],
        )
        assert entry["failed_roads"] == "broken" and "broken.csv" in entry["first_error"]
    assert f"wrote {out / 'sweep.csv'}, {out / 'summary.csv'}, {out / 'sweep.parquet'} (32 rows" in result.stdout


def test_the_parquet_table_holds_the_csv_values_typed(swept) -> None:
    pq = pytest.importorskip("pyarrow.parquet")
    out, _, rows = swept
    table = pq.read_table(out / "sweep.parquet").to_pylist()
    assert len(table) == len(rows) and list(table[0]) == list(rows[0])
    for row, typed in zip(rows, table, strict=True):
        assert typed["horizon_m"] == int(row["horizon_m"]) and typed["error"] == (row["error"] or None)
        assert typed["mpc_fuel_kg"] == (float(row["mpc_fuel_kg"]) if row["mpc_fuel_kg"] else None)
        assert typed["mpc_stalled"] == {"true": True, "false": False, "": None}[row["mpc_stalled"]]


def test_a_rerun_runs_only_the_failed_rows_again(swept, fleet, tmp_path: Path) -> None:
    """Into a copy of the finished directory: the 24 good rows are kept, the 8 failed ones run
    again (and fail again), and the notice says so."""
    out, _, rows = swept
    _, args = fleet
    again_dir = tmp_path / "again"
    shutil.copytree(out, again_dir)
    again = runner.invoke(app, [*args, "--out", str(again_dir)])
    assert again.exit_code == 0, again.output
    assert "running again 8 rows whose runs failed" in again.stderr
    assert "(32 rows: 8 MPC and 4 PI runs, 24 rows resumed)" in again.stdout
    assert read_csv(again_dir / "sweep.csv") == rows


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--road", "{empty}"], "error: --road {empty}: no road file (.csv, .vdri, .gpx)"),
        (["--road", "{empty}/*.csv"], "error: --road {empty}/*.csv: no file matches"),
        (["--road", "{empty}/missing.csv"], "error: {empty}/missing.csv"),
        (
            ["--road", "roads/hill_L300_A-3.csv", "--reverse", "--both-ways"],
            "error: Invalid value for '--both-ways': expected --reverse or --both-ways",
        ),
    ],
)
def test_bad_fleet_input_is_one_line_and_writes_nothing(tmp_path: Path, args: list[str], message: str) -> None:
    empty = tmp_path / "empty"
    empty.mkdir()
    filled = [arg.replace("{empty}", str(empty)) for arg in args]
    result = runner.invoke(app, ["sweep", *filled, "--out", str(tmp_path / "out")])
    assert result.exit_code == 2, result.output
    assert result.stderr.startswith(message.replace("{empty}", str(empty))) and result.stderr.count("\n") == 1
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("given", ["option", "environment"])
def test_an_unreachable_scheduler_is_one_line_and_writes_nothing(tmp_path: Path, monkeypatch, given: str) -> None:
    """--scheduler, or TRUCKMPC_SCHEDULER without it, names a scheduler nothing listens at."""
    monkeypatch.setattr(sweep_cluster, "CONNECT_TIMEOUT_S", 1.0)
    args = ["sweep", "--road", "roads/hill_L300_A-3.csv", "--out", str(tmp_path)]
    if given == "option":
        args += ["--scheduler", "tcp://127.0.0.1:1"]
    else:
        monkeypatch.setenv("TRUCKMPC_SCHEDULER", "tcp://127.0.0.1:1")
    result = runner.invoke(app, args)
    assert result.exit_code == 2, result.output
    assert result.stderr.startswith("error: --scheduler tcp://127.0.0.1:1: cannot reach a Dask scheduler there (")
    assert result.stderr.count("\n") == 1 and not list(tmp_path.iterdir())

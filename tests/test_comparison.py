"""`truckmpc.compare_controllers`: the comparison `truckmpc simulate` prints, as one library call."""

from __future__ import annotations

from pathlib import Path

import pytest
from typer.testing import CliRunner

from truckmpc import compare_controllers, load_road, load_run_config
from truckmpc.cli import app

ROAD = Path(__file__).resolve().parent.parent / "roads" / "hill_L500_A2.csv"


@pytest.fixture(scope="module")
def comparison():
    return compare_controllers(load_road(ROAD), load_run_config(), ("pi", "pcc", "mpc"))


def test_the_headline_is_the_fuel_at_equal_trip_time_and_end_speed(comparison) -> None:
    """Recomputed from the runs: the MPC's end-speed-corrected fuel against the PCC's, the PCC re-run
    to the MPC's trip time (which it drove within its tolerance)."""
    doc = comparison.summary
    equal = doc["equal_time_mpc_vs_pcc"]
    assert equal["pcc_time_s"] == pytest.approx(doc["mpc"]["time_s"], rel=1e-3)
    own, baseline = doc["mpc"]["fuel_corrected_kg"], equal["pcc_fuel_corrected_kg"]
    assert comparison.headline("mpc", "pcc") == pytest.approx((own - baseline) / baseline * 100, rel=1e-12)
    assert comparison.saved_kg("mpc", "pcc") == pytest.approx(baseline - own, rel=1e-12)
    assert comparison.not_comparable("mpc", "pcc") is None
    with pytest.raises(KeyError, match="pi vs mpc: not compared"):
        comparison.headline("pi", "mpc")


def test_its_table_is_what_simulate_prints(comparison, tmp_path: Path) -> None:
    printed = CliRunner().invoke(
        app, ["simulate", "--road", str(ROAD), "--controller", "pi,pcc,mpc", "--out", str(tmp_path / "run")]
    )
    assert printed.exit_code == 0, printed.output

    def timeless(lines: list[str]) -> list[str]:  # a wall-clock row differs from run to run
        return [line for line in lines if not line.startswith("realtime ratio")]

    table = printed.stdout.splitlines()[:-1]  # all but the line naming the files written
    assert timeless(comparison.text().splitlines()) == timeless(table)
    written = comparison.write(tmp_path / "again")
    assert [p.name for p in written] == ["summary.json", "trace-pi.csv", "trace-pcc.csv", "trace-mpc.csv"]

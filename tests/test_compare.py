"""Δfuel and Δtime against the PI: one rule for summary.json, the printed table and sweep.csv."""

from __future__ import annotations

import json

import numpy as np
import pytest

from truckmpc import TRACE_COLUMNS, RunResult, format_table, make_section, summary_document, write_outputs
from truckmpc.compare import compare
from truckmpc.sweep import SWEEP_COLUMNS
from truckmpc.sweep.columns import MPC_FIELDS, PI_FIELDS, result_cells

ROAD = make_section("flat", 2000)


def summary(fuel_kg: float, time_s: float, stall_m: float | None = None) -> dict[str, object]:
    """A run summary as sim.simulate writes it, with the fields the comparison and the table read."""
    figures = dict.fromkeys(MPC_FIELDS, 1)
    return figures | {
        "fuel_kg": fuel_kg,
        "time_s": time_s,
        "stalled": stall_m is not None,
        "stall_distance_m": stall_m,
        "message": None if stall_m is None else f"stalled at km {stall_m / 1000:.2f}",
    }


def result(name: str, doc: dict[str, object]) -> RunResult:
    trace = {column: np.zeros(2) for column in TRACE_COLUMNS}
    trace["distance_m"] = np.array([0.0, 1.0])
    return RunResult(name=name, road=ROAD.name, summary=doc, trace=trace)


def test_delta_is_mpc_minus_pi_over_pi_in_percent():
    comparison = compare(summary(20.0, 400.0), summary(19.0, 410.0))
    assert comparison.delta_consumed_pct == pytest.approx(-5.0, rel=1e-12)
    assert comparison.delta_time_pct == pytest.approx(2.5, rel=1e-12)
    assert comparison.not_comparable is None


@pytest.mark.parametrize(
    ("pi_stall_m", "mpc_stall_m", "reason"),
    [
        (None, 980.0, "not comparable: mpc stalled at km 0.98"),
        (1234.0, None, "not comparable: pi stalled at km 1.23"),
        (500.0, 640.0, "not comparable: pi stalled at km 0.50 and mpc stalled at km 0.64"),
    ],
)
def test_no_delta_when_a_run_stalled(pi_stall_m, mpc_stall_m, reason):
    comparison = compare(summary(20.0, 400.0, pi_stall_m), summary(1.0, 40.0, mpc_stall_m))
    assert (comparison.delta_consumed_pct, comparison.delta_time_pct) == (None, None)
    assert comparison.not_comparable == reason


def test_no_fuel_delta_against_a_zero_baseline():
    comparison = compare(summary(0.0, 400.0), summary(0.5, 380.0))
    assert comparison.delta_consumed_pct is None
    assert comparison.delta_time_pct == pytest.approx(-5.0, rel=1e-12)
    assert comparison.not_comparable == "not comparable: pi fuel_kg is 0"


def test_summary_json_has_null_deltas_and_the_reason_when_the_mpc_stalled(tmp_path):
    runs = {"pi": result("pi", summary(20.0, 400.0)), "mpc": result("mpc", summary(1.0, 40.0, 980.0))}
    write_outputs(tmp_path, ROAD, runs)
    doc = json.loads((tmp_path / "summary.json").read_text())
    assert doc["delta_fuel_pct"] is None and doc["delta_time_pct"] is None
    assert doc["not_comparable"] == "not comparable: mpc stalled at km 0.98"


def test_summary_json_has_no_reason_when_comparable():
    runs = {"pi": result("pi", summary(20.0, 400.0)), "mpc": result("mpc", summary(19.0, 410.0))}
    doc = summary_document(ROAD, runs)
    assert doc["delta_fuel_pct"] == pytest.approx(-5.0) and "not_comparable" not in doc


def test_table_prints_the_reason_instead_of_a_delta():
    runs = {"pi": result("pi", summary(20.0, 400.0)), "mpc": result("mpc", summary(1.0, 40.0, 980.0))}
    lines = format_table(ROAD, runs).splitlines()
    assert "mpc vs pi: not comparable: mpc stalled at km 0.98" in lines
    assert not any(line.startswith("Δ") for line in lines)
    comparable = format_table(
        ROAD, {"pi": result("pi", summary(20.0, 400.0)), "mpc": result("mpc", summary(19.0, 410.0))}
    )
    assert "Δfuel vs PI [%]" in comparable and "not comparable" not in comparable


@pytest.mark.parametrize(
    ("pi", "mpc"),
    [
        (summary(20.0, 400.0), summary(19.0, 410.0)),
        (summary(20.0, 400.0), summary(1.0, 40.0, 980.0)),
        (summary(0.0, 400.0), summary(0.5, 380.0)),
    ],
)
def test_sweep_row_and_summary_json_give_the_same_deltas(pi, mpc):
    doc = summary_document(ROAD, {"pi": result("pi", pi), "mpc": result("mpc", mpc)})
    cells = dict(zip(SWEEP_COLUMNS, result_cells({k: pi[k] for k in PI_FIELDS}, mpc), strict=True))
    for key in ("delta_fuel_pct", "delta_time_pct"):
        assert cells[f"mpc_{key}"] == ("" if doc[key] is None else repr(doc[key]))

"""Issue 44: the headline (a look-ahead controller's saving at equal trip time and equal end speed)
in the console lines of ``pareto`` and ``robustness``, recomputed here from the runs' fuels."""

from __future__ import annotations

import pytest

from truckmpc.cli.pareto import _saving_lines
from truckmpc.pareto import equal_time_savings


def point(controller: str, v_ref_kmh: float, time_s: float, fuel_kg: float) -> dict[str, str]:
    """A finished pareto.csv row (end-speed-corrected fuel `fuel_kg`)."""
    return {
        "road": "hill",
        "direction": "forward",
        "controller": controller,
        "parameter": "v_ref_kmh",
        "value": str(v_ref_kmh),
        "v_ref_kmh": str(v_ref_kmh),
        "beta_g_per_s": "",
        "fuel_kg": str(fuel_kg),
        "fuel_corrected_kg": str(fuel_kg),
        "time_s": str(time_s),
        "end_speed_kmh": "85",
        "stalled": "false",
        "error": "",
    }


# The MPC's curve is a line from (990 s, 9.9 kg) to (1030 s, 9.5 kg): 9.8 kg at the PI's 1000 s,
# 9.7 kg at the PCC's 1010 s.
PARETO = [
    point("pi", 85.0, 1000.0, 10.0),
    point("pcc", 85.0, 1010.0, 9.8),
    point("mpc", 86.0, 990.0, 9.9),
    point("mpc", 84.0, 1030.0, 9.5),
]


def test_pareto_reads_each_curve_against_the_pcc_at_its_trip_time() -> None:
    against_pcc = equal_time_savings(PARETO, 85.0, "pcc")["hill"]
    assert list(against_pcc) == ["mpc"]
    assert against_pcc["mpc"].pct == pytest.approx(100 * (9.7 - 9.8) / 9.8)
    assert against_pcc["mpc"].saved == pytest.approx(0.1)
    against_pi = equal_time_savings(PARETO, 85.0)["hill"]
    assert against_pi["mpc"].pct == pytest.approx(-2.0) and against_pi["mpc"].saved == pytest.approx(0.2)


def test_pareto_prints_the_headline_against_the_pcc_then_the_pi() -> None:
    lines = _saving_lines(PARETO, 85.0)
    assert lines[0] == (
        "hill: mpc against the PCC at equal trip time and end speed (the PCC's trip time at v_ref 85 km/h): "
        "Δfuel -1.02 % (0.100 kg saved)"
    )
    assert "hill: mpc against the PI at equal trip time and end speed" in lines[2]
    assert lines[2].endswith("Δfuel -2.00 % (0.200 kg saved)")

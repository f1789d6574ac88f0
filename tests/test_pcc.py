"""VECTO's rule-based predictive cruise control (`--controller pcc`) and its cruise driver
(`--controller vecto_cc`), rule by rule on constructed roads: each test names the function of
VECTO's driver (`DefaultDriverStrategy`) whose rule it checks. Each would fail for the PCC before
it followed VECTO's code, which coasted from anywhere between 50 km/h and v_ref, eco-rolled
wherever the PI let go of the pedal at or above v_ref, and kept a use case running to its end."""

from __future__ import annotations

import dataclasses

import numpy as np

from truckmpc import load_run_config, simulate
from truckmpc.roads import make_section

NO_PCC = "pcc_enabling_speed_kmh=200"
"""No PCC segment anywhere: eco-roll alone."""


def run(road, controller: str = "pcc", *overrides: str):
    return simulate(road, load_run_config(overrides=list(overrides)), controller)


def between(trace, lo_m: float, hi_m: float) -> np.ndarray:
    return (trace["distance_m"] >= lo_m) & (trace["distance_m"] < hi_m)


def test_use_case_1_slows_before_a_descent_by_at_most_the_underspeed() -> None:
    """`UpdatePCCState`, use case 1: before a 500 m descent at −3 % (500 m of flat before it) the
    PCC lifts and coasts in neutral, the speed falling below v_ref − 4 but not below v_ref − 8 (the
    allowed underspeed), and on the descent it needs no brake where the PI brakes."""
    road = make_section("hill", 500.0, -3.0)
    pcc, pi = run(road), run(road, "pi")
    before = between(pcc.trace, 100.0, 500.0)
    assert np.all(pcc.trace["pedal"][before] == 0) and np.all(pcc.trace["gear"][before] == 0)
    v_before = pcc.trace["speed_kmh"][between(pcc.trace, 0.0, 500.0)]
    assert 85 - 8 - 0.3 <= v_before.min() < 85 - 4
    assert pcc.summary["brake_energy_kj"] < 0.1 * pi.summary["brake_energy_kj"]
    assert pcc.summary["fuel_kg"] < pi.summary["fuel_kg"]


def test_use_case_1_ends_one_kmh_above_the_set_speed() -> None:
    """`HandlePCC`: use case 1 ends once the speed reaches v_ref + 1 km/h, and the driver engages a
    gear (the −3 % descent is too steep for eco-roll): the truck is never in neutral above 86 km/h,
    though the descent takes it on to 90 km/h."""
    road = make_section("hill", 500.0, -3.0)
    pcc = run(road)
    neutral = pcc.trace["gear"] == 0
    assert neutral.any()
    assert pcc.trace["speed_kmh"][neutral].max() <= 86.0 + 0.05
    assert pcc.trace["speed_kmh"].max() > 89.0


def test_use_case_2_starts_only_between_the_underspeed_and_one_kmh_below_the_set_speed() -> None:
    """`UpdatePCCState`, use case 2: on a 1500 m descent at −3 % entered at 80 km/h (between
    max(50, v_ref − 8) = 77 and v_ref − 1 = 84 km/h) the PCC coasts and gravity brings the speed
    back; entered at 70 km/h, below that window, the driver accelerates with the engine until the
    speed reaches 77 km/h."""
    road = make_section("hill", 1500.0, -3.0, lead_m=50.0)
    inside = run(road, "pcc", "start_speed_kmh=80")
    early = between(inside.trace, 100.0, 400.0)
    assert np.all(inside.trace["pedal"][early] == 0)
    assert np.all(np.diff(inside.trace["speed_kmh"][early]) > 0)
    below = run(road, "pcc", "start_speed_kmh=70")
    slow = between(below.trace, 60.0, 400.0) & (below.trace["speed_kmh"] < 76.5)
    assert slow.any() and np.all(below.trace["pedal"][slow] > 0) and np.all(below.trace["gear"][slow] > 0)


def test_use_case_3_and_the_plain_driver_brake_at_their_overspeed() -> None:
    """`GetOverspeed` and the driver's braking action: on a long −4 % descent the PCC with use case 3
    brakes at v_ref + v_inc (90 km/h), without it and VECTO's plain cruise driver at v_ref + 2.5 km/h;
    each holds its limit where the PI's brake loop overshoots v_ref + v_inc by about 2 km/h."""
    road = make_section("hill", 2500.0, -4.0)
    top = {name: run(road, name).trace["speed_kmh"].max() for name in ("pcc", "vecto_cc", "pi")}
    without = run(road, "pcc", "pcc_use_case_3=false").trace["speed_kmh"].max()
    assert 89.9 < top["pcc"] <= 90.01
    assert 87.4 < top["vecto_cc"] <= 87.51 and 87.4 < without <= 87.51
    assert top["pi"] > 91.0


def test_eco_roll_waits_for_a_gentle_descent() -> None:
    """`HandleEcoRoll`: with no PCC segment, eco-roll engages on a 3 km descent at −1.6 % (where
    the truck in neutral accelerates by 0 to 0.1 m/s²) and declutches there only; on a −3 % descent
    (steeper than that) the truck stays in gear at fuel cut, and on the flat after a braking descent
    it never declutches (the road must fall)."""
    gentle = make_section("hill", 3000.0, -1.6, lead_m=500.0, tail_m=500.0)
    rolled = run(gentle, "pcc", NO_PCC)
    assert rolled.summary["eco_roll_entries"] == 1 == rolled.summary["neutral_engagements"]
    assert np.all(rolled.trace["gear"][~between(rolled.trace, 500.0, 3525.0)] > 0)
    steep = run(make_section("hill", 3000.0, -3.0, lead_m=500.0, tail_m=500.0), "pcc", NO_PCC)
    assert steep.summary["eco_roll_entries"] == 0 and np.all(steep.trace["gear"] > 0)
    flat_after = run(make_section("hill", 1500.0, -4.0, lead_m=500.0, tail_m=2000.0))
    assert np.all(flat_after.trace["gear"][between(flat_after.trace, 2100.0, 4000.0)] > 0)


def test_eco_roll_engages_no_faster_than_three_kmh_above_the_set_speed() -> None:
    """`HandleEcoRoll`: the speed must be at most the overspeed limit less 2 km/h (v_ref + 3 with
    use case 3): a truck entering the gentle descent at 89.5 km/h rolls on in gear."""
    road = make_section("hill", 2000.0, -1.6, lead_m=50.0, tail_m=500.0)
    fast = run(road, "pcc", NO_PCC, "start_speed_kmh=89.5")
    assert fast.summary["eco_roll_entries"] == 0 and np.all(fast.trace["gear"] > 0)


def test_below_the_enabling_speed_no_event_starts() -> None:
    """PCC segments need a set speed of at least the enabling speed (80 km/h): at v_ref 70 km/h no
    use case slows the truck before the descent, which drives as VECTO's plain driver does."""
    road = make_section("hill", 500.0, -3.0)
    pcc, plain = run(road, "pcc", "v_ref_kmh=70"), run(road, "vecto_cc", "v_ref_kmh=70")
    lead = between(pcc.trace, 0.0, 450.0)
    assert pcc.summary["pcc_events"] == 0
    assert np.allclose(pcc.trace["speed_kmh"][lead], plain.trace["speed_kmh"][lead], atol=0.05)


def test_eco_roll_is_a_neutral_engagement_not_a_gear_shift() -> None:
    """Through the use case 1 test's descent the PCC declutches once (the coast before the descent)
    and re-engages: one neutral engagement, counted as a PCC event, and no more gear shifts than the
    PI, which never declutches. Without eco-roll it coasts in gear: no engagement."""
    road = make_section("hill", 500.0, -3.0)
    pcc, pi = run(road), run(road, "pi")
    gears = pcc.trace["gear"]
    entries = int(np.sum((gears[1:] == 0) & (gears[:-1] != 0)))
    assert pcc.summary["neutral_engagements"] == entries == pcc.summary["pcc_events"] == 1
    assert pi.summary["neutral_engagements"] == 0
    assert pcc.summary["gear_shifts"] <= pi.summary["gear_shifts"]
    in_gear = run(road, "pcc", "eco_roll=false")
    assert in_gear.summary["neutral_engagements"] == 0


def test_the_plain_driver_holds_the_set_speed_and_coasts_down_to_a_lower_target() -> None:
    """VECTO's cruise driver (`DriverModeDrive`): on the flat it holds v_ref to 0.05 km/h; ahead of
    a lower target speed (85 to 60 km/h) it lifts early and coasts (look-ahead coasting), reaching
    the lower stretch with the pedal idle for the last stretch before it."""
    flat = run(make_section("flat", 2000.0), "vecto_cc")
    assert np.all(np.abs(flat.trace["speed_kmh"] - 85.0) < 0.05)
    road = make_section("flat", 3000.0)
    targets = np.where(road.distance_m < 2000.0, 85.0, 60.0)
    lowered = run(dataclasses.replace(road, target_speed_kmh=targets), "vecto_cc")
    ahead = between(lowered.trace, 1700.0, 2000.0)
    assert np.all(lowered.trace["pedal"][ahead] == 0)
    assert np.all(lowered.trace["speed_kmh"][between(lowered.trace, 2100.0, 3000.0)] < 60.0 + 2.5 + 0.1)

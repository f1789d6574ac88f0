"""VECTO's rule-based predictive cruise control (`--controller pcc`): its three use cases and
eco-roll on artificial sections, against the PI on the same plant."""

from __future__ import annotations

import numpy as np

from truckmpc import load_run_config, simulate
from truckmpc.roads import make_section


def run(road, *overrides: str):
    config = load_run_config(overrides=list(overrides))
    return simulate(road, config, "pcc"), simulate(road, config, "pi")


def between(trace, lo_m: float, hi_m: float) -> np.ndarray:
    return (trace["distance_m"] >= lo_m) & (trace["distance_m"] < hi_m)


def test_use_case_1_slows_before_a_descent_by_at_most_the_underspeed() -> None:
    """Before a 500 m descent at −3 % (500 m of flat before it) the PCC lifts and coasts in neutral:
    no pedal from 100 m to the descent, the speed falls below v_ref − 4 but never below v_ref − 8
    (the allowed underspeed), and on the descent it needs no brake where the PI brakes."""
    road = make_section("hill", 500.0, -3.0)
    pcc, pi = run(road)
    before = between(pcc.trace, 100.0, 500.0)
    assert np.all(pcc.trace["pedal"][before] == 0) and np.all(pcc.trace["gear"][before] == 0)
    v_before = pcc.trace["speed_kmh"][between(pcc.trace, 0.0, 500.0)]
    assert 85 - 8 - 0.3 <= v_before.min() < 85 - 4
    assert pcc.summary["brake_energy_kj"] < 0.1 * pi.summary["brake_energy_kj"]
    assert pcc.summary["fuel_kg"] < pi.summary["fuel_kg"]


def test_use_case_2_regains_speed_by_gravity_on_a_descent_entered_slowly() -> None:
    """Entering a 1500 m descent at −3 % at 65 km/h, the PCC coasts (no pedal) while gravity brings
    the speed back towards v_ref; the PI drives the same stretch with pedal."""
    road = make_section("hill", 1500.0, -3.0, lead_m=50.0)
    pcc, pi = run(road, "start_speed_kmh=65")
    early = between(pcc.trace, 100.0, 400.0)
    assert np.all(pcc.trace["pedal"][early] == 0)
    assert np.all(np.diff(pcc.trace["speed_kmh"][early]) > 0)
    assert pi.trace["pedal"][early].max() > 0.1
    assert pcc.summary["fuel_kg"] < pi.summary["fuel_kg"]


def test_the_underspeed_is_the_bands_v_dec() -> None:
    """The PCC's allowed underspeed is the one band's v_dec_kmh: with v_dec 4 km/h the coast before
    the descent of the use case 1 test ends by v_ref − 4, where with the default 8 it goes below."""
    road = make_section("hill", 500.0, -3.0)
    narrow, _ = run(road, "v_dec_kmh=4")
    wide, _ = run(road)
    lead_in = between(narrow.trace, 0.0, 500.0)
    assert narrow.trace["speed_kmh"][lead_in].min() >= 85 - 4 - 0.3
    assert wide.trace["speed_kmh"][lead_in].min() < 85 - 4 - 0.3


def test_use_case_3_runs_to_the_bands_top_on_a_braking_descent() -> None:
    """Use case 3's allowed overspeed is the band's v_inc_kmh, the PI's brake limit too: on a long
    −4 % descent both brake from v_ref + v_inc on, so their top speeds agree (the PI's brake loop
    overshoots by about 2 km/h), and a band 2.5 km/h wider on top moves the PCC's top by 2.5 km/h."""
    road = make_section("hill", 2000.0, -4.0)
    pcc, pi = run(road, "v_inc_kmh=2.5")
    wide, _ = run(road, "v_inc_kmh=5")
    pi_top, pcc_top = pi.trace["speed_kmh"].max(), pcc.trace["speed_kmh"].max()
    assert 87.5 < pi_top < 90.0
    assert abs(pcc_top - pi_top) < 0.5, (pi_top, pcc_top)
    assert abs((wide.trace["speed_kmh"].max() - pcc_top) - 2.5) < 0.5


def test_below_the_enabling_speed_no_event_starts() -> None:
    """At v_ref 70 km/h (below the 80 km/h enabling speed) no PCC event slows the truck before a
    descent: over the flat lead-in it drives as the PI does."""
    road = make_section("hill", 500.0, -3.0)
    pcc, pi = run(road, "v_ref_kmh=70")
    lead = between(pcc.trace, 0.0, 450.0)
    assert np.allclose(pcc.trace["speed_kmh"][lead], pi.trace["speed_kmh"][lead], atol=0.05)


def test_eco_roll_is_a_neutral_engagement_not_a_gear_shift() -> None:
    """Through the use case 1 test's descent the PCC declutches once (the coast before the descent)
    and re-engages: one neutral engagement, and no more gear shifts than the PI, which never
    declutches. Without eco-roll it coasts in gear: no engagement."""
    road = make_section("hill", 500.0, -3.0)
    pcc, pi = run(road)
    gears = pcc.trace["gear"]
    entries = int(np.sum((gears[1:] == 0) & (gears[:-1] != 0)))
    assert pcc.summary["neutral_engagements"] == entries >= 1
    assert pi.summary["neutral_engagements"] == 0
    assert pcc.summary["gear_shifts"] <= pi.summary["gear_shifts"] + entries
    in_gear, _ = run(road, "eco_roll=false")
    assert in_gear.summary["neutral_engagements"] == 0

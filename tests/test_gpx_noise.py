"""The noise test (issue 15, item 3): GPS tracks made from the shared roads' altitude along a
synthetic path, with altitude noise of σ = 2 m correlated over 100 m and 2 m of horizontal jitter
(truckmpc.geo.synthetic), imported with the defaults and compared with the true road. The full study,
with its numbers, is scripts/gps_noise_study.py (docs/validation/gps.md)."""

from __future__ import annotations

import numpy as np
import pytest

from gps_tracks import SHARED_ROADS, needs_shared
from truckmpc.config import load_run_config
from truckmpc.geo.study import delta_fuel_pct, grade_rms_error_pct, noisy_imports
from truckmpc.geo.synthetic import road_piece
from truckmpc.roads import RoadProfile, load_road
from truckmpc.roads.gps.importer import default_smoothing
from truckmpc.roads.gps.smooth import Smoothing

SEEDS = (1, 2, 3)
PIECES = {
    "epa-20km": ("us_epa_gem_ph2_grade_20km.csv", 0.0, 20e3),
    "vecto-km0-25": ("eu_vecto_longhaul_100km.csv", 0.0, 25e3),
}
COARSE_MPC = ("delta_kmh=0.2", "stage_m=50", "horizon_m=1000")


def piece(name: str) -> RoadProfile:
    file, start_m, end_m = PIECES[name]
    return road_piece(load_road(SHARED_ROADS / file), start_m, end_m)


def raw_grade_rms_error_pct(truth: RoadProfile) -> float:
    """The grade RMS error [pp] of the first seed's track imported without smoothing."""
    (raw,) = noisy_imports(truth, 2.0, SEEDS[:1], Smoothing("none"))
    return grade_rms_error_pct(raw, truth)


@needs_shared
@pytest.mark.parametrize("name", list(PIECES))
def test_sigma_2m_gives_a_grade_within_half_a_point(name):
    truth = piece(name)
    errors = [grade_rms_error_pct(road, truth) for road in noisy_imports(truth, 2.0, SEEDS, default_smoothing())]
    assert max(errors) <= 0.5, errors
    # differentiated as it comes, the same elevation is several points of grade off
    assert raw_grade_rms_error_pct(truth) >= 4 * max(errors)


@needs_shared
@pytest.mark.xfail(
    reason="0.3 points at sigma 2 m is below the oracle Wiener bound, 0.33-0.39 points "
    "(scripts/smoothing_bound.py, docs/validation/gps.md): no linear shift-invariant smoother reaches it on average",
)
@pytest.mark.parametrize("name", list(PIECES))
def test_sigma_2m_gives_a_grade_within_the_aim_of_0_3_points(name):
    truth = piece(name)
    errors = [grade_rms_error_pct(road, truth) for road in noisy_imports(truth, 2.0, SEEDS, default_smoothing())]
    assert np.mean(errors) <= 0.3, errors


@needs_shared
@pytest.mark.slow
def test_the_mpc_saving_on_an_imported_road_stays_near_the_true_one():
    """Δfuel (MPC against PI) on 10 km of the VECTO road, imported from a σ = 2 m track, against
    the true road's; coarse MPC settings to keep it short."""
    config = load_run_config(overrides=COARSE_MPC)
    truth = road_piece(load_road(SHARED_ROADS / "eu_vecto_longhaul_100km.csv"), 0.0, 10e3)
    clean = delta_fuel_pct(truth, config)
    assert clean is not None and clean < -0.5  # the MPC does save on this piece
    for road in noisy_imports(truth, 2.0, SEEDS[:2], default_smoothing()):
        imported = delta_fuel_pct(road, config)
        assert imported is not None
        assert abs(imported - clean) <= 1.0

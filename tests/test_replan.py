"""Solving the horizon every `replan_m` metres and deciding the stages between from its stored
cost-to-go: a receding horizon whose look-ahead is never shorter than `horizon_m`, at a fraction
of the solves.

The references are the receding horizon that solves every stage (`replan_m: 0`) and the whole-road
optimum, on the same road. (That each decision between solves is the one a fresh solve of the
stages left would take is checked in the core, `rust/truckmpc-core/tests/dp_replan.rs`.)
"""

from __future__ import annotations

import math

import pytest

from truckmpc.config import load_run_config
from truckmpc.roads import default_test_track
from truckmpc.sim import simulate

ROAD = default_test_track()


@pytest.fixture(scope="module")
def runs():
    """The PI, the whole-road optimum, and the MPC solving every stage and every `replan_m` (the
    default), on the test track."""
    every = load_run_config(overrides=["replan_m=0"])
    default = load_run_config()
    return {
        "pi": simulate(ROAD, default, "pi").summary,
        "optimal": simulate(ROAD, default, "optimal").summary,
        "every stage": simulate(ROAD, every, "mpc").summary,
        "replanned": simulate(ROAD, default, "mpc").summary,
    }


def test_the_default_solves_its_horizon_every_replan_m_and_decides_the_stages_between(runs):
    replanned, every = runs["replanned"], runs["every stage"]
    stages = math.ceil(ROAD.length_m / 25.0)
    assert every["horizon_solves"] == every["solves"] == pytest.approx(stages + 1, abs=1)
    assert replanned["solves"] == every["solves"]
    # one horizon solve per replan_m, plus one wherever the truck left the stored states
    replan_m = load_run_config().mpc.replan_m
    assert replan_m >= 250.0
    assert ROAD.length_m / replan_m <= replanned["horizon_solves"] <= 1.5 * ROAD.length_m / replan_m


def test_replanning_leaves_no_more_of_the_whole_road_optimum_than_solving_every_stage(runs):
    """Replanning looks 3000-3725 m ahead where solving every stage looks 3000 m: on the test
    track's hills it leaves no more of the whole-road optimum's saving than solving every stage.
    (The optimum prices no shifts or coasts, so both leave it some points: no bound on that gap.)"""
    pi = runs["pi"]

    def saving_pct(run: dict) -> float:
        return 100.0 * (1.0 - run["fuel_kg"] / pi["fuel_kg"])

    best = saving_pct(runs["optimal"])
    left = {name: best - saving_pct(runs[name]) for name in ("every stage", "replanned")}
    assert left["replanned"] <= left["every stage"] + 0.05, left
    assert runs["replanned"]["time_s"] == pytest.approx(runs["every stage"]["time_s"], rel=0.005)


def test_the_thesis_preset_solves_every_stage():
    summary = simulate(ROAD, load_run_config(config_paths=["thesis"]), "mpc").summary
    assert summary["horizon_solves"] == summary["solves"]

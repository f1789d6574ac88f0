"""The baselines driven to each look-ahead run's trip time (:mod:`truckmpc.equal_time.search`), by
simulation."""

from __future__ import annotations

import math
from collections.abc import Mapping

from truckmpc.config import RunConfig
from truckmpc.equal_time.search import TARGET_OFFSET_LIMIT_KMH, EqualTime, RunAt, equal_time
from truckmpc.roads.profile import RoadProfile
from truckmpc.sim import RunResult, simulate

__all__ = ["BASELINES", "LOOK_AHEAD", "OPTIMISERS", "baseline_runner", "compared_with", "equal_time_baselines"]

LOOK_AHEAD = ("pcc", "mpc", "optimal")
"""The controllers compared with the baselines without look-ahead at equal trip time."""

OPTIMISERS = ("mpc", "optimal")
"""The controllers also compared with the rule-based PCC (when it ran) at equal trip time."""

BASELINES = ("pi", "vecto_cc", "pcc")
"""The controllers others are compared with, when they ran: the thesis's PI, VECTO's cruise driver
(what VECTO simulates for a truck without predictive cruise control) and VECTO's PCC."""


def compared_with(baseline: str) -> tuple[str, ...]:
    """The controllers compared with `baseline` at equal trip time: the look-ahead ones with the
    baselines without look-ahead, the optimising ones with the PCC."""
    return OPTIMISERS if baseline == "pcc" else LOOK_AHEAD


def baseline_runner(road: RoadProfile, config: RunConfig, controller: str = "pi") -> RunAt:
    """A function driving `controller` over `road` at another v_ref, the band moving with it and
    the start speed kept at the run's (clipped into the moved band: a truck starting above v_max
    would only brake the difference away). On a road with target speeds it takes x = v_ref +
    target_offset_kmh and moves the offset (x − v_ref), v_ref and the start speed kept as configured."""
    settings, where = config.settings, "equal-time baseline"
    v_ref_kmh = settings.get("v_ref_kmh")
    if road.target_speed_kmh is not None:

        def run_offset(x_kmh: float) -> RunResult:
            return simulate(road, config.with_values({"target_offset_kmh": x_kmh - v_ref_kmh}, where), controller)

        return run_offset
    start_kmh = settings.get("start_speed_kmh")
    start_kmh = v_ref_kmh if start_kmh is None else start_kmh
    v_dec_kmh, v_inc_kmh = settings.get("v_dec_kmh"), settings.get("v_inc_kmh")

    def run_at(v_ref_kmh: float) -> RunResult:
        band = (v_ref_kmh - v_dec_kmh, v_ref_kmh + v_inc_kmh)
        changed = {"v_ref_kmh": v_ref_kmh, "start_speed_kmh": min(max(start_kmh, band[0]), band[1])}
        return simulate(road, config.with_values(changed, where), controller)

    return run_at


def equal_time_baselines(
    road: RoadProfile, config: RunConfig, results: Mapping[str, RunResult], baseline: str = "pi"
) -> dict[str, EqualTime]:
    """For every run in `results` compared with `baseline` (:func:`compared_with`) that did not
    stall, the baseline driven to its trip time (the baseline's run at the configured v_ref is
    `results[baseline]`)."""
    base = results.get(baseline)
    if base is None:
        return {}
    run_at = baseline_runner(road, config, baseline)
    cruise = config.cruise
    # The band needs v_ref > v_dec (its lower end above zero): keep 1 km/h clear of it, and inside
    # the set speeds whose band the truck can drive.
    lowest_kmh, ceiling_kmh = config.settings.derived()["v_ref_range_kmh"]
    floor_kmh, start_kmh, offset_from_kmh = max(cruise.v_dec_kmh + 1.0, lowest_kmh), cruise.v_ref_kmh, None
    if road.target_speed_kmh is not None:
        # x = v_ref + target offset; the core keeps every stretch's set speed at 1 km/h or more.
        offset_from_kmh = cruise.v_ref_kmh
        start_kmh = cruise.v_ref_kmh + cruise.target_offset_kmh
        floor_kmh, ceiling_kmh = cruise.v_ref_kmh - TARGET_OFFSET_LIMIT_KMH, math.inf
    out = {}
    for name in compared_with(baseline):
        result = results.get(name)
        if result is None or result.stalled:
            continue
        if base.stalled:
            out[name] = EqualTime(float(result.summary["time_s"]), reason=f"not comparable: {base.message}")
            continue
        target_s = float(result.summary["time_s"])
        g_per_half_v2 = config.settings.derived()["kinetic_fuel_g_per_half_v2"]
        out[name] = equal_time(
            run_at, start_kmh, floor_kmh, base, target_s, g_per_half_v2, offset_from_kmh, v_ceiling_kmh=ceiling_kmh
        )
    return out

"""The table of a run's figures the CLI prints (``truckmpc simulate``), from the runs in memory:
their summary document laid out by :mod:`truckmpc.results.run_table`."""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

from truckmpc.equal_time import EqualTime
from truckmpc.results.run_table import render_text, run_table
from truckmpc.results.summary import summary_document
from truckmpc.sim import RunResult

if TYPE_CHECKING:
    from truckmpc.config import RunConfig
    from truckmpc.roads import RoadProfile

__all__ = ["format_table"]


def format_table(
    road: RoadProfile,
    results: Mapping[str, RunResult],
    config: RunConfig | None = None,
    convergence: Mapping[str, Any] | None = None,
    equal_times: Mapping[str, EqualTime] | None = None,
    *,
    verbose: bool = False,
) -> str:
    """The plain-text table of the runs, one column per controller (see
    :func:`truckmpc.results.run_table.run_table`); with the configuration, its first line names the
    truck's mass, v_ref and the speed band; with a ``convergence`` object, how far the deltas move
    at half δ and half S; ``verbose`` adds the solver statistics and the equal-time search."""
    doc = summary_document(road, results, _setup(road, results, config), equal_times)
    if convergence is not None:
        doc["convergence"] = convergence
    return render_text(run_table(doc, verbose=verbose))


def _setup(road: RoadProfile, results: Mapping[str, RunResult], config: RunConfig | None) -> dict[str, Any]:
    """The parts of the summary's ``run`` record the table's heading reads: the controllers, whether
    the road has target speeds, the truck's mass [kg] and the cruise band."""
    run: dict[str, Any] = {
        "road": {"target_speeds": road.target_speed_kmh is not None},
        "controllers": list(results),
    }
    if config is None:
        return run
    run["settings"] = {"vehicle": {"mass_kg": config.vehicle.mass_kg}, "cruise": config.as_dict()["cruise"]}
    if config.truck is not None:
        run["vehicle"] = {"mass_kg": config.truck.mass_kg, "vecto_job": str(config.truck.job.path)}
    return run

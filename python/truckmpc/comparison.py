"""A comparison of controllers over one road, as ``truckmpc simulate`` makes and prints it, in one
library call: the runs, each look-ahead run against each baseline at equal trip time and end speed
(the baseline re-run to the run's trip time, both end speeds corrected), the ``summary.json``
document and its table::

    from truckmpc import compare_controllers, default_test_track, load_run_config

    comparison = compare_controllers(default_test_track(), load_run_config(), ("pi", "pcc", "mpc"))
    comparison.headline("mpc", "pcc")  # Δfuel [%] at equal trip time and end speed; negative = saved
    comparison.saved_kg("mpc", "pcc")  # the same in kg of fuel; positive = saved
    print(comparison.text())
"""

from __future__ import annotations

import json
import os
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from truckmpc.config import RunConfig
from truckmpc.record import RunRequest, run_record
from truckmpc.results import summary_document, write_outputs
from truckmpc.results.files import summary_json
from truckmpc.results.run_table import RunTable, render_text, run_table
from truckmpc.results.summary import HEADLINE, SAVED
from truckmpc.roads import RoadProfile
from truckmpc.run import ControllerRuns, run_controllers

__all__ = ["Comparison", "compare_controllers"]


@dataclass(frozen=True)
class Comparison:
    """Controllers driven over one road and compared: the runs (:class:`~truckmpc.run.ControllerRuns`)
    and the ``summary.json`` document made of them, as the file holds it (``comparisons`` holds each
    look-ahead run against each baseline)."""

    road: RoadProfile
    runs: ControllerRuns
    summary: dict[str, Any]

    def _entry(self, controller: str, baseline: str) -> dict[str, Any]:
        for entry in self.summary.get("comparisons", ()):
            if (entry["controller"], entry["baseline"]) == (controller, baseline):
                return dict(entry)
        compared = [f"{e['controller']} vs {e['baseline']}" for e in self.summary.get("comparisons", ())]
        raise KeyError(f"{controller} vs {baseline}: not compared (compared: {', '.join(compared) or 'none'})")

    def headline(self, controller: str, baseline: str) -> float | None:
        """Δfuel [%] of `controller` against `baseline` at equal trip time and end speed (negative:
        fuel saved); None where not comparable (a stall, a trip time the baseline cannot drive)."""
        return self._entry(controller, baseline).get(HEADLINE)

    def saved_kg(self, controller: str, baseline: str) -> float | None:
        """Fuel [kg] `controller` saves against `baseline` at equal trip time and end speed."""
        return self._entry(controller, baseline).get(SAVED)

    def not_comparable(self, controller: str, baseline: str) -> str | None:
        """Why the comparison has no figure, or None when it has one."""
        return self._entry(controller, baseline).get("not_comparable")

    def table(self, *, verbose: bool = False) -> RunTable:
        """The table ``truckmpc simulate`` prints for these runs."""
        return run_table(self.summary, verbose=verbose)

    def text(self, *, verbose: bool = False) -> str:
        """:meth:`table` as plain text."""
        return render_text(self.table(verbose=verbose))

    def write(self, out_dir: str | os.PathLike[str]) -> list[Path]:
        """Write ``summary.json`` and the traces into `out_dir` (refused if it holds other files;
        an earlier run there is replaced); returns the paths written."""
        runs = self.runs
        record = self.summary.get("run")
        return write_outputs(out_dir, self.road, runs.results, record, runs.extra, runs.equal_times)


def compare_controllers(
    road: RoadProfile, config: RunConfig, controllers: Sequence[str] = ("pi", "pcc", "mpc")
) -> Comparison:
    """Drive `controllers` (names of :data:`truckmpc.sim.CONTROLLERS`) over `road` with `config`,
    re-run each baseline among them (``pi``, ``vecto_cc``, ``pcc``) to each look-ahead run's trip
    time, and compare them as ``truckmpc simulate`` does."""
    runs = run_controllers(road, config, tuple(controllers))
    record = run_record(RunRequest(None, False, tuple(controllers)), road, config)
    doc = summary_document(road, runs.results, record, runs.equal_times) | runs.extra
    return Comparison(road, runs, json.loads(summary_json(doc)))

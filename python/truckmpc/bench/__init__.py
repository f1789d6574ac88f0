"""The real-time benchmark: closed-loop MPC runs on fixed, named roads at fixed settings.

Each case (:data:`CASES`) drives a whole road with the MPC (:func:`truckmpc.sim.simulate`) in a fresh
Python process, so its peak resident memory is its own:

- the default controller at its own settings on the EU VECTO long-haul road (108 km) and on the
  Swedish E6/E20 motorway (294 km): what users run;
- the thesis's worst case, S 25 m, δ 0.1 km/h, 3000 m horizon, neutral allowed, fixed grid, on the
  VECTO road;
- the default controller with VECTO's generic long-haul tractor on the VECTO road (where its files,
  ``../shared/vehicles/``, are found; the case is left out otherwise).

The roads are ``../shared/roads/`` beside the repository checkout (or the working directory), else
the bundled test track; ``--road`` drives every case on one road instead, and ``--quick`` keeps the
first 10 km of each. Figures per run (from the run's summary, but for the last two):

- ``realtime_ratio``: wall time of the run / simulated trip time;
- ``solve_ms_mean``, ``solve_ms_max``, ``solves`` (one per stage), ``horizon_solves`` (those over the
  whole horizon; the others decide a stage from the last one's stored cost-to-go),
  ``states_per_solve``, ``transitions_per_solve``;
- ``ns_per_transition``: mean solve time / transitions per solve;
- ``peak_rss_mb``: the run's process peak resident set [MB], Python and numpy included.

Nothing here asserts a time: the figures are printed for people and CI to read.

Usage: ``truckmpc bench [--json] [--road FILE] [--quick] [--set key=value ...]``.
"""

from truckmpc.bench.runs import CASES, SETTINGS, BenchError, BenchResult, cases_to_run, run_bench, shared_path
from truckmpc.bench.table import format_bench

__all__ = [
    "CASES",
    "SETTINGS",
    "BenchError",
    "BenchResult",
    "cases_to_run",
    "format_bench",
    "run_bench",
    "shared_path",
]

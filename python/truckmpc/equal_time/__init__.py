"""Comparisons that do not depend on trip time: the baseline re-tuned to a look-ahead run's trip time.

:mod:`~truckmpc.equal_time.search` finds the set speed (a search over a function that drives the
baseline); :mod:`~truckmpc.equal_time.baselines` drives it by simulation for every look-ahead run.
Comparisons that do not depend on end speed, the end-speed correction, are :mod:`truckmpc.fuel`'s.
"""

from truckmpc.equal_time.baselines import (
    BASELINES,
    LOOK_AHEAD,
    OPTIMISERS,
    baseline_runner,
    compared_with,
    equal_time_baselines,
)
from truckmpc.equal_time.search import (
    MAX_RUNS,
    SEARCH_KMH,
    TARGET_OFFSET_LIMIT_KMH,
    TIME_TOLERANCE,
    EqualTime,
    RunAt,
    equal_time,
)

__all__ = [
    "BASELINES",
    "LOOK_AHEAD",
    "MAX_RUNS",
    "OPTIMISERS",
    "SEARCH_KMH",
    "TARGET_OFFSET_LIMIT_KMH",
    "TIME_TOLERANCE",
    "EqualTime",
    "RunAt",
    "baseline_runner",
    "compared_with",
    "equal_time",
    "equal_time_baselines",
]

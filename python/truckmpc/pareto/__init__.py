"""Fuel–time Pareto studies (``truckmpc pareto``): the baseline over a range of set speeds and each
look-ahead controller over a range of set speeds or β, on one or more roads, through the sweep's
process pool with progress, resume and ``--jobs``; ``pareto.csv`` and ``pareto.png``.

Modules: :mod:`~truckmpc.pareto.plan` (the points, validated), :mod:`~truckmpc.pareto.run` (running
and resuming), :mod:`~truckmpc.pareto.fronts` (curves and the saving at equal trip time).
"""

from truckmpc.pareto.fronts import Curve, Saving, below, curves, equal_time_savings
from truckmpc.pareto.plan import CURVES, PARETO_COLUMNS, ParetoPlan, plan_pareto
from truckmpc.pareto.run import ParetoResult, run_pareto

__all__ = [
    "CURVES",
    "PARETO_COLUMNS",
    "Curve",
    "ParetoPlan",
    "ParetoResult",
    "Saving",
    "below",
    "curves",
    "equal_time_savings",
    "plan_pareto",
    "run_pareto",
]

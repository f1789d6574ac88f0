"""truckmpc: look-ahead cruise control for heavy trucks, compared against a PI baseline.

Public API::

    from truckmpc import load_run_config, load_road, default_test_track, simulate
    result = simulate(default_test_track(), load_run_config())
    result.summary["fuel_kg"], result.trace["speed_kmh"]
"""

from truckmpc.comparison import Comparison, compare_controllers
from truckmpc.config import RunConfig, load_run_config
from truckmpc.controller import Control, Controller, PlantState
from truckmpc.errors import ConfigError, RoadError, TruckmpcError
from truckmpc.results import format_table, summary_document, trace_csv, write_outputs
from truckmpc.roads import RoadProfile, Stop, default_test_track, load_road, make_section, shipped_roads, write_road
from truckmpc.sim import CONTROLLERS, TRACE_COLUMNS, RunResult, simulate
from truckmpc.sweep import SweepError, SweepResult, run_sweep

__all__ = [
    "CONTROLLERS",
    "TRACE_COLUMNS",
    "Comparison",
    "ConfigError",
    "Control",
    "Controller",
    "PlantState",
    "RoadError",
    "RoadProfile",
    "RunConfig",
    "RunResult",
    "Stop",
    "SweepError",
    "SweepResult",
    "TruckmpcError",
    "compare_controllers",
    "default_test_track",
    "format_table",
    "load_road",
    "load_run_config",
    "make_section",
    "run_sweep",
    "shipped_roads",
    "simulate",
    "summary_document",
    "trace_csv",
    "write_outputs",
    "write_road",
]

"""Parameter sweeps: the PI and look-ahead controllers over every combination of a grid of config
values (thesis chapter 6).

A sweep is a list of roads (all driven forward, or all reversed) and a list of *axes*, each a config
key with the values it takes (``horizon_m=250:3000:250``, ``delta_kmh=0.1,0.2``). Every combination
is applied as ``key=value`` overrides on top of the base configuration (vehicle file, ``--config``
overlays, ``--set``) and validated before anything runs. For each (road, vehicle, combination) the PI and each
controller of ``--controller`` (``pcc``, ``mpc``; default the MPC) drive the same road with the same
vehicle; one row per pair goes to ``DIR/sweep.csv``.

The PI run depends only on the road, the vehicle, the PI and the simulation settings (the PCC's on
those and the ``pcc`` section), so it is keyed by those *resolved values* and computed once per
distinct key: an axis over an MPC key reuses one PI run per road, an axis over ``v_ref_kmh`` or
``mass_kg`` reruns it per value.

Resuming: ``DIR/sweep.json`` identifies the sweep (roads by name, content hash and direction; axes;
the resolved base configuration). Rows are appended to ``DIR/sweep.partial.csv`` one complete line
at a time as they finish; when all are done ``DIR/sweep.csv`` is written atomically in grid order and
the partial file removed. Running the same sweep again into the same directory skips the rows already
there (and reuses their PI and PCC figures); a different sweep into it is refused.

Runs go to a Dask cluster (:mod:`~truckmpc.sweep.cluster`): by default an embedded one of ``--jobs``
worker processes on this machine, or a running one given by its scheduler's address. A run that
fails leaves its error in its rows' ``error`` column; the others go on.

Fleets (:mod:`~truckmpc.sweep.fleet`): ``--road`` takes directories and globs too, ``--vehicle``
may be repeated (a ``vehicle`` column), the roads may be driven both ways; the rows are summarised
per axis value (:mod:`~truckmpc.sweep.summary`: ``summary.csv``), led by each truck's headline over
the roads (:mod:`~truckmpc.sweep.savings`).

The columns (:mod:`~truckmpc.sweep.columns`, each controller's figures in
:mod:`~truckmpc.sweep.run_columns`) are named for what the sweep's trucks consume: fuel, or battery
energy when they are all battery-electric.

Modules: :mod:`~truckmpc.sweep.grid` (axes), :mod:`~truckmpc.sweep.inputs` (axes and each
combination's configuration, checked), :mod:`~truckmpc.sweep.fleet` (roads, directions,
vehicles), :mod:`~truckmpc.sweep.plan` (rows, run keys), :mod:`~truckmpc.sweep.columns` (CSV columns
and cells), :mod:`~truckmpc.sweep.compared` (a row's comparisons and headline),
:mod:`~truckmpc.sweep.files` (the directory's files), :mod:`~truckmpc.sweep.task` (one run, in a
worker), :mod:`~truckmpc.sweep.cluster` and :mod:`~truckmpc.sweep.runner` (the Dask
cluster and the runs on it), :mod:`~truckmpc.sweep.run` (running and resuming),
:mod:`~truckmpc.sweep.waiting` (rows waiting for their runs), :mod:`~truckmpc.sweep.summary` (the
summary per axis value, Parquet), :mod:`~truckmpc.sweep.savings` (a group's headline over its
roads), :mod:`~truckmpc.sweep.progress` (the progress bar).
"""

from truckmpc.sweep.cells import cell
from truckmpc.sweep.columns import SWEEP_COLUMNS
from truckmpc.sweep.errors import SweepError, SweepInterrupted, SweepWorkerDied
from truckmpc.sweep.files import CSV_NAME, PARTIAL_NAME, SETTINGS_NAME
from truckmpc.sweep.grid import MAX_AXIS_VALUES, Axis, expand_grid, parse_axis
from truckmpc.sweep.plan import Row, SweepPlan, plan_sweep
from truckmpc.sweep.progress import progress_bar
from truckmpc.sweep.run import SweepResult, run_plan, run_sweep
from truckmpc.sweep.runner import ProgressHook
from truckmpc.sweep.task import run_task

__all__ = [
    "CSV_NAME",
    "MAX_AXIS_VALUES",
    "PARTIAL_NAME",
    "SETTINGS_NAME",
    "SWEEP_COLUMNS",
    "Axis",
    "ProgressHook",
    "Row",
    "SweepError",
    "SweepInterrupted",
    "SweepPlan",
    "SweepResult",
    "SweepWorkerDied",
    "cell",
    "expand_grid",
    "parse_axis",
    "plan_sweep",
    "progress_bar",
    "run_plan",
    "run_sweep",
    "run_task",
]

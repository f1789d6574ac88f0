"""Pictures of runs and sweeps (``truckmpc plot``), in the look of the thesis's chapter 6.

- A **run directory** (``summary.json`` and ``trace-<controller>.csv``, as written by
  ``truckmpc simulate``) gives ``run.png``: stacked panels over distance [km] — altitude, speed of
  every controller with the set speed and the allowed band (set speed − v_dec … + v_inc, following
  the road's target speeds where it has them) and the road's stops, gear (neutral, gear 0 in the
  trace, ticked "N" just below the lowest gear used and shaded), pedal and brake levels — as
  figures 6.3–6.14. The title names every controller and each look-ahead one's Δfuel at equal trip
  time against the PI and the PCC. Lines longer than :data:`MAX_POINTS` are reduced by :func:`decimate`.
- A **sweep directory** (``sweep.csv``, as written by ``truckmpc sweep``) gives ``sweep.png``: Δfuel
  (raw and at equal trip time) and Δtime [%] against the prediction horizon, one line per (S, δ),
  one column per road and direction (figures 6.16–6.18; ``allow_neutral = false`` dashed), and
  ``realtime.png``: the real-time ratio q against the horizon on a log scale (figure 6.19), and
  ``headline.png``: each look-ahead controller's saving against the PCC and the PI at equal trip
  time and equal end speed per road and truck (the only picture of a fleet without a numeric axis).
- A **Pareto directory** (``pareto.csv``, as written by ``truckmpc pareto``) gives ``pareto.png``:
  end-speed-corrected fuel against trip time, one curve per controller, the saving at the PI's trip
  time at the reference set speed annotated.

Modules: :mod:`~truckmpc.plot.run` (run pictures; their title :mod:`~truckmpc.plot.run_title`,
their set speed, band and stops :mod:`~truckmpc.plot.run_speed` and :mod:`~truckmpc.plot.band`),
:mod:`~truckmpc.plot.sweep` (sweep pictures; their headline :mod:`~truckmpc.plot.headline`),
:mod:`~truckmpc.plot.figures` (matplotlib and saving).

matplotlib is an optional dependency (``pip install 'truckmpc[plot]'``). It is imported only when a
picture is drawn, and only through its object-oriented API (``matplotlib.figure.Figure``), so no GUI
backend is ever selected and the global pyplot state is left alone.
"""

from __future__ import annotations

import os
from pathlib import Path

from truckmpc.plot.figures import MISSING_MATPLOTLIB, PlotError
from truckmpc.plot.pareto import pareto_v_ref_kmh, plot_pareto
from truckmpc.plot.run import MAX_POINTS, decimate, plot_run
from truckmpc.plot.sweep import plot_sweep

__all__ = ["MAX_POINTS", "MISSING_MATPLOTLIB", "PlotError", "decimate", "plot_dir", "plot_run", "plot_sweep"]


def plot_dir(
    directory: str | os.PathLike[str], *, out: str | os.PathLike[str] | None = None, svg: bool = False
) -> list[Path]:
    """Plot a run or a sweep directory; return the files written.

    ``out`` is a directory (default: ``directory``) or, for one kind of input, a file name whose
    suffix (``.png`` or ``.svg``) sets the format; a sweep's second picture then goes to
    ``<stem>-realtime<suffix>``. ``svg`` also writes an SVG beside every PNG. ``directory`` may
    also name the ``summary.json`` or ``sweep.csv`` itself.
    """
    source = Path(directory)
    named = source.name if source.is_file() else None
    if named in ("summary.json", "sweep.csv", "pareto.csv"):
        source = source.parent
    if not source.is_dir():
        raise PlotError(f"{source}: not a directory (expected a run directory or a sweep directory)")
    if named == "pareto.csv" or (named is None and (source / "pareto.csv").is_file()):
        target = source / "pareto.png" if out is None else Path(out)
        target = target / "pareto.png" if target.is_dir() else target
        return plot_pareto(source, target, pareto_v_ref_kmh(source), svg=svg)
    is_run = (source / "summary.json").is_file()
    is_sweep = (source / "sweep.csv").is_file()
    if not (is_run or is_sweep):
        raise PlotError(
            f"{source}: neither a run directory (summary.json, trace-*.csv) nor a sweep directory (sweep.csv)"
        )
    target = source if out is None else Path(out)
    as_file = target.suffix.lower() in (".png", ".svg")
    if target.suffix and not as_file and not target.is_dir():
        raise PlotError(f"--out {target}: expected a directory or a .png or .svg file name, got {target.suffix!r}")
    if as_file and is_run and is_sweep:
        raise PlotError(f"--out {target}: {source} holds both a run and a sweep; give a directory")
    written: list[Path] = []
    if is_run:
        written += plot_run(source, target if as_file else target / "run.png", svg=svg)
    if is_sweep:
        written += plot_sweep(source, target if as_file else target / "sweep.png", svg=svg)
    return written

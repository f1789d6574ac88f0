"""The picture of a battery-electric truck's machine (``truckmpc vehicle plot`` on its declaration):
the efficiency of one machine over its speed [rpm] and torque [Nm] at each voltage level, read off
its power map, with its driving and braking torque limits and its drag curve."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.tri import Triangulation

from truckmpc.plot.figures import figure_class, save
from truckmpc.units import RPM_PER_RAD_S
from truckmpc.vecto.electric import ElectricTruckJob, VoltageLevel

__all__ = ["machine_efficiency_pct", "plot_machine_map"]

_LEVELS_PCT = [60, 70, 75, 80, 84, 87, 89, 91, 93, 94, 95, 96, 97, 98]


def machine_efficiency_pct(power_map: tuple[tuple[float, float, float], ...]) -> np.ndarray:
    """The efficiency [%] at each (speed [rpm], torque [Nm], electric power [W]) point of a power
    map: mechanical over electric power where the machine drives, electric over mechanical where it
    brakes; NaN where either power is zero or they have opposite signs (the machine draws power while
    braking, or the point is at standstill)."""
    points = np.array(power_map, dtype=float)
    mech_w = points[:, 1] * points[:, 0] / RPM_PER_RAD_S
    el_w = points[:, 2]
    valid = mech_w * el_w > 0.0
    ratio = np.divide(mech_w, el_w, out=np.full_like(el_w, np.nan), where=valid)
    efficiency: np.ndarray = 100.0 * np.where(mech_w > 0.0, ratio, 1.0 / ratio)
    return efficiency


def plot_machine_map(job: ElectricTruckJob, out: Path, svg: bool = False) -> list[Path]:
    """Draw one machine's efficiency map at each voltage level of ``job`` to ``out`` (.png or .svg);
    returns the files written."""
    machine = job.machine
    levels = machine.voltage_levels
    fig = figure_class()(figsize=(7 * len(levels), 6), layout="constrained")
    axes = np.atleast_1d(fig.subplots(1, len(levels), sharey=True))
    filled = None
    for ax, level in zip(axes, levels, strict=True):
        filled = _panel(ax, level, machine.drag_curve)
        ax.set_title(f"at {level.voltage_v:g} V")
    fig.colorbar(filled, ax=list(axes), label="efficiency [%]")
    fig.suptitle(
        f"{job.path.stem}: one of {machine.count} × {machine.machine_type} at {machine.position}, "
        f"{machine.rated_power_w / 1e3:.0f} kW rated each"
    )
    axes[0].set_ylabel("machine torque [Nm] (negative: braking)")
    axes[0].legend(loc="lower left", fontsize="small")
    return save([(fig, out)], svg=svg)


def _panel(ax, level: VoltageLevel, drag_curve: tuple[tuple[float, float], ...]):  # type: ignore[no-untyped-def]
    """One voltage level's efficiency contours, limits and drag curve on ``ax``; the filled contours."""
    points = np.array(level.power_map, dtype=float)
    efficiency = machine_efficiency_pct(level.power_map)
    limits = np.array(level.torque_limits, dtype=float)
    valid = np.isfinite(efficiency)
    grid = Triangulation(points[valid, 0], points[valid, 1])
    # Triangles whose centre lies beyond the torque limits are left blank: the map is measured there,
    # but the machine cannot reach it.
    n_mid, t_mid = (points[valid][grid.triangles, k].mean(axis=1) for k in (0, 1))
    top, bottom = (np.interp(n_mid, limits[:, 0], limits[:, k]) for k in (1, 2))
    grid.set_mask((t_mid > top) | (t_mid < bottom))
    shown = np.clip(efficiency[valid], _LEVELS_PCT[0], 100.0)
    filled = ax.tricontourf(grid, shown, levels=_LEVELS_PCT, cmap="viridis", extend="min")
    lines = ax.tricontour(grid, shown, levels=_LEVELS_PCT[4:], colors="white", linewidths=0.5)
    ax.clabel(lines, fmt="%d", fontsize="x-small")
    ax.plot(limits[:, 0], limits[:, 1], color="black", lw=1.5, label="most driving torque")
    ax.plot(limits[:, 0], limits[:, 2], color="black", lw=1.5, ls="-.", label="most braking torque")
    drag = np.array(drag_curve, dtype=float)
    ax.plot(drag[:, 0], drag[:, 1], color="tab:red", lw=1.0, ls="--", label="drag (no current)")
    ax.plot(points[:, 0], points[:, 1], ".", color="0.4", ms=2, label="power map points")
    ax.axhline(0.0, color="black", lw=0.4)
    ax.set_xlabel("machine speed [rpm]")
    ax.grid(True, alpha=0.3)
    return filled

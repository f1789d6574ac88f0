"""The picture of a truck's engine (``truckmpc vehicle plot``): the fuel map as specific fuel
consumption [g/kWh] over engine speed [rpm] and torque [Nm], the full-load and drag curves, the
map's measured points and, given a run directory, where each controller ran the engine."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from truckmpc import _core
from truckmpc.plot.figures import figure_class, save
from truckmpc.plot.run import read_trace
from truckmpc.plot.run_title import CONTROLLER_STYLE
from truckmpc.units import KMH_PER_MPS, RPM_PER_RAD_S, W_PER_KW
from truckmpc.vecto import VectoTruck

__all__ = ["operating_points", "plot_fuel_map", "run_operating_points"]

_BSFC_LEVELS_G_PER_KWH = [180, 185, 190, 195, 200, 205, 210, 220, 230, 250, 280, 320, 400]


def operating_points(vehicle: _core.Vehicle, trace: dict[str, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """Engine speed [rpm] and torque [Nm] at each sample of a run's trace in gear (neutral samples,
    where the engine idles off the driveline, are left out)."""
    in_gear = trace["gear"] > 0
    v_mps = trace["speed_kmh"][in_gear] / KMH_PER_MPS
    pedal, gear = trace["pedal"][in_gear], trace["gear"][in_gear].astype(int)
    torque = np.array([vehicle.engine_torque_nm(v, p, g) for v, p, g in zip(v_mps, pedal, gear, strict=True)])
    return trace["engine_speed_rpm"][in_gear], torque


def plot_fuel_map(
    truck: VectoTruck,
    out: Path,
    svg: bool = False,
    runs: dict[str, tuple[np.ndarray, np.ndarray]] | None = None,
) -> list[Path]:
    """Draw `truck`'s fuel map to `out` (.png or .svg), with each run's operating points (engine
    speed [rpm], torque [Nm] per controller, :func:`operating_points`); returns the files written."""
    core, engine = truck.core, truck.job.engine
    facts = core.facts
    n_lo, n_hi = facts["full_load_speed_range_rpm"]
    speeds = np.linspace(n_lo, n_hi, 161)
    at_speeds = [core.engine_point(n, 0.0) for n in speeds]
    full = np.array([p["max_torque_nm"] for p in at_speeds])
    drag = np.array([p["drag_torque_nm"] for p in at_speeds])
    torques = np.linspace(1.0, float(full.max()), 141)
    n_grid, t_grid = np.meshgrid(speeds, torques)
    fuel = np.vectorize(lambda n, t: core.engine_point(n, t)["fuel_rate_g_per_h"])(n_grid, t_grid)
    power_kw = t_grid * n_grid / RPM_PER_RAD_S / W_PER_KW
    bsfc = np.where(t_grid <= np.interp(n_grid, speeds, full), fuel / power_kw, np.nan)
    fig = figure_class()(figsize=(9, 6), layout="constrained")
    ax = fig.subplots()
    filled = ax.contourf(n_grid, t_grid, bsfc, levels=_BSFC_LEVELS_G_PER_KWH, cmap="viridis_r", extend="both")
    lines = ax.contour(n_grid, t_grid, bsfc, levels=_BSFC_LEVELS_G_PER_KWH[:9], colors="white", linewidths=0.5)
    ax.clabel(lines, fmt="%d", fontsize="x-small")
    fig.colorbar(filled, ax=ax, label="specific fuel consumption [g/kWh]")
    ax.plot(speeds, full, color="black", lw=1.5, label="full load")
    ax.plot(speeds, drag, color="black", lw=1.0, ls="--", label="drag (fuel cut)")
    points = np.array(engine.fuel_map)
    ax.plot(points[:, 0], points[:, 1], ".", color="0.4", ms=2.5, label="fuel map points")
    for name, (speed_rpm, torque_nm) in (runs or {}).items():
        label, colour = CONTROLLER_STYLE.get(name, (name, "tab:gray"))
        ax.plot(speed_rpm, torque_nm, "o", color=colour, ms=3, alpha=0.35, mec="none", label=f"{label} (trace samples)")
    power_kw_rated = facts["rated_power_w"] / 1e3
    ax.set_title(f"{engine.model or engine.path.stem}: {power_kw_rated:.0f} kW at {facts['rated_speed_rpm']:.0f} rpm")
    ax.set_xlabel("engine speed [rpm]")
    ax.set_ylabel("engine torque [Nm]")
    ax.axhline(0.0, color="black", lw=0.4)
    ax.grid(True, alpha=0.3)
    ax.legend(loc="lower right", fontsize="small")
    return save([(fig, out)], svg=svg)


def run_operating_points(directory: Path, vehicle: _core.Vehicle) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """The operating points of every controller whose trace a run directory holds."""
    traces = sorted(directory.glob("trace-*.csv"))
    return {p.stem.removeprefix("trace-"): operating_points(vehicle, read_trace(p)) for p in traces}

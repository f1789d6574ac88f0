"""The picture of a Pareto study: ``pareto.png``, one panel per road, trip time [min] on x and
end-speed-corrected fuel [kg] (battery energy [kWh] for a battery-electric truck) on y, one curve
per controller with its points labelled by set speed (or β), the baseline's point at the reference
set speed marked, and each look-ahead curve's saving at that trip time annotated."""

from __future__ import annotations

import csv
import json
import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from truckmpc.consumption import Consumption, consumption_of
from truckmpc.pareto.fronts import Curve, curves, equal_time_savings, reference_point
from truckmpc.pareto.plan import PARETO_COLUMNS, consumption_of_pareto
from truckmpc.pareto.run import damaged_row
from truckmpc.plot.figures import PlotError, figure_class, save

_STYLES = {"pi": ("tab:gray", "o"), "pcc": ("tab:green", "D"), "mpc": ("tab:blue", "s"), "fuel_time": ("tab:red", "^")}
_LABELS = {
    "pi": "PI (set speed)",
    "pcc": "PCC, VECTO rules (set speed)",
    "mpc": "MPC as configured (set speed)",
    "fuel_time": "MPC, fuel + β·time",
}
_S_PER_MIN = 60.0


def read_rows(path: Path) -> list[dict[str, str]]:
    """The rows of ``pareto.csv``, each checked: a study's columns (a diesel or a battery-electric
    truck's), numbers where a run finished."""
    try:
        with path.open(newline="", encoding="utf-8") as handle:
            reader = csv.DictReader(handle)
            rows = list(reader)
            header = list(reader.fieldnames or ())
    except (OSError, UnicodeDecodeError, csv.Error) as err:
        raise PlotError(f"{path}: cannot read it ({err})") from None
    if consumption_of_pareto(header) is None:
        expected = ",".join(PARETO_COLUMNS)
        raise PlotError(f"{path}:1: expected the columns {expected} (or named for energy), got {','.join(header)}")
    columns = tuple(header)
    for line, row in enumerate(rows, start=2):
        problem = damaged_row([row.get(c) or "" for c in columns], columns)
        if problem is not None:
            raise PlotError(f"{path}:{line}: {problem}")
    return rows


def pareto_v_ref_kmh(directory: Path) -> float:
    """The reference set speed of the study in `directory` (its base configuration's v_ref)."""
    path = directory / "pareto.json"
    try:
        return float(json.loads(path.read_text(encoding="utf-8"))["base_config"]["cruise"]["v_ref_kmh"])
    except (OSError, ValueError, KeyError, TypeError) as err:
        raise PlotError(f"{path}: cannot read the study's v_ref ({err})") from None


def plot_pareto(
    directory: str | os.PathLike[str], out: str | os.PathLike[str], v_ref_kmh: float, *, svg: bool = False
) -> list[Path]:
    """Draw the fronts of ``directory/pareto.csv`` to `out`, the saving annotated at `v_ref_kmh`."""
    rows = read_rows(Path(directory) / "pareto.csv")
    by_road = curves(rows)
    if not by_road:
        raise PlotError(f"{directory}/pareto.csv: no run that finished the road")
    consumption = consumption_of(rows[0])
    savings = {
        road: {c: saving.pct for c, saving in by.items()} for road, by in equal_time_savings(rows, v_ref_kmh).items()
    }
    figure = figure_class()(figsize=(7.0, 4.8 * len(by_road)), layout="constrained")
    for i, (road, by_controller) in enumerate(by_road.items()):
        ax = figure.add_subplot(len(by_road), 1, i + 1)
        _draw_road(ax, road, by_controller, rows, v_ref_kmh, savings.get(road, {}), consumption)
    return save([(figure, Path(out))], svg)


def _draw_road(
    ax: Any,
    road: str,
    by_controller: Mapping[str, Curve],
    rows: Sequence[Mapping[str, str]],
    v_ref_kmh: float,
    savings: Mapping[str, float | None],
    consumption: Consumption,
) -> None:
    for name, curve in by_controller.items():
        color, marker = _STYLES.get(name, ("black", "x"))
        minutes = curve.time_s / _S_PER_MIN
        saving = savings.get(name)
        label = _LABELS.get(name, name).replace("fuel +", f"{consumption.label} +")
        if saving is not None and name != "pi":
            label += f": Δ{consumption.word} {saving:+.2f} % vs the PI at its trip time".replace("-", "−")
        ax.plot(minutes, curve.consumed, color=color, marker=marker, label=label)
        for x, y, value in zip(minutes, curve.consumed, curve.values, strict=True):
            ax.annotate(f"{value:g}", (x, y), textcoords="offset points", xytext=(4, 3), fontsize=7, color=color)
    reference = reference_point(rows, road, v_ref_kmh)
    if not isinstance(reference, str):
        time_s, consumed = reference
        ax.axvline(time_s / _S_PER_MIN, color="black", linewidth=0.8, linestyle=":")
        ax.annotate(
            f"PI at v_ref {v_ref_kmh:g} km/h",
            (time_s / _S_PER_MIN, consumed),
            textcoords="offset points",
            xytext=(6, -12),
            fontsize=8,
        )
    ax.set_title(f"{road}: {consumption.label} against trip time")
    ax.set_xlabel("trip time [min]")
    ax.set_ylabel(f"{consumption.label}, end speed corrected [{consumption.unit}]")
    ax.grid(True, linewidth=0.4)
    ax.legend(fontsize=8)

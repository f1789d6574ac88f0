"""A fleet study's summary: for each axis value (and each vehicle, each direction, and all rows
together), each look-ahead controller's headline over the roads — its saving against the PCC and
against the PI at equal trip time and equal end speed: mean and distance-weighted mean [%], mean and
total fuel saved [kg], best and worst road (:mod:`truckmpc.sweep.savings`) — then its Δfuel and
Δtime as driven against the PI [%] (mean, standard deviation, the worst road) and how many rows
failed; ``summary.csv``.
And the result table as Parquet (``--parquet``, with pyarrow), since fleet tables outgrow CSV.
"""

from __future__ import annotations

import importlib.util
import statistics
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from truckmpc.atomic import atomic_write_text
from truckmpc.compare import HEADLINE_BASELINES
from truckmpc.consumption import FUEL, Consumption
from truckmpc.roads import RoadProfile
from truckmpc.sweep.cells import parse_cell
from truckmpc.sweep.columns import ERROR_COLUMN, Layout, delta_column
from truckmpc.sweep.errors import SweepError
from truckmpc.sweep.files import csv_line
from truckmpc.sweep.savings import SAVINGS_FIGURES, savings, savings_column

if TYPE_CHECKING:
    from truckmpc.sweep.plan import SweepPlan
    from truckmpc.sweep.run import SweepResult

SUMMARY_NAME = "summary.csv"

SUMMARY_COLUMNS = (
    "axis",
    "value",
    "controller",
    "rows",
    "compared",
    "failed",
    *(savings_column(base, figure) for base in HEADLINE_BASELINES for figure in SAVINGS_FIGURES),
    "mean_delta_fuel_pct",
    "std_delta_fuel_pct",
    "mean_delta_time_pct",
    "std_delta_time_pct",
    "worst_road",
    "worst_direction",
    "worst_vehicle",
    "worst_delta_fuel_pct",
    "failed_roads",
    "first_error",
)
"""Columns of ``summary.csv``: ``rows`` of the axis value, ``compared`` those with both Δs as driven
(not stalled, not failed), ``failed`` those with an error; the headline against the PCC and the PI
(``headline_vs_<baseline>_*``, :data:`~truckmpc.sweep.savings.SAVINGS_FIGURES`; blank against a
baseline the sweep did not run); the standard deviation is the sample's (0 for
one row); the worst road is the compared row with the largest Δfuel; ``failed_roads`` names the
roads of the failed rows, ``first_error`` the first one's error. A sweep of battery-electric trucks
names them for battery energy (:func:`summary_columns`)."""


def summary_columns(consumption: Consumption = FUEL) -> tuple[str, ...]:
    """The columns of ``summary.csv`` of a sweep of trucks that consume `consumption`: each named
    for fuel says ``energy`` and ``kwh`` for battery energy (``mean_delta_energy_pct``,
    ``headline_vs_pi_total_saved_kwh``)."""
    return tuple(consumption.worded(column) for column in SUMMARY_COLUMNS)


Rows = Sequence[Mapping[str, str]]


def summary_groups(rows: Rows, axes: Sequence[str]) -> list[tuple[str, str, list[Mapping[str, str]]]]:
    """(axis, value, rows) of every group summarised: all rows (axis ``all``), then each value of
    the vehicle and direction (when they vary) and of each axis, in the order met."""
    groups: list[tuple[str, str, list[Mapping[str, str]]]] = [("all", "", list(rows))]
    keys = [key for key in ("vehicle", "direction") if len({row.get(key, "") for row in rows}) > 1]
    for key in (*keys, *axes):
        for value in dict.fromkeys(row[key] for row in rows):
            groups.append((key, value, [row for row in rows if row[key] == value]))
    return groups


def summarise(
    rows: Rows,
    axes: Sequence[str],
    controllers: Sequence[str],
    lengths_m: Mapping[str, float],
    consumption: Consumption = FUEL,
) -> list[dict[str, str]]:
    """The summary rows (:data:`SUMMARY_COLUMNS`, as cell text) of a sweep's result rows, each road
    weighted by its length [m] in `lengths_m` (by road name) in the distance-weighted means; the
    figures of battery-electric trucks (`consumption`) are of battery energy, under the same keys."""
    versus = Layout(tuple(controllers)).versus
    out = []
    for axis, value, members in summary_groups(rows, axes):
        for controller in controllers:
            figures = _figures(members, controller, consumption)
            summary = {"axis": axis, "value": value, "controller": controller, **figures}
            for base in HEADLINE_BASELINES:
                ran = any((v.run, v.base) == (controller, base) for v in versus)
                summary.update(savings(members if ran else [], controller, base, lengths_m, consumption))
            out.append(summary)
    return out


def _figures(members: Rows, controller: str, consumption: Consumption) -> dict[str, str]:
    """The summary cells of one group's rows for one controller."""
    fuel_column = delta_column(controller, "fuel", consumption=consumption)
    time_column = delta_column(controller, "time")
    compared = [row for row in members if row[fuel_column] and row[time_column]]
    failed = [row for row in members if row.get(ERROR_COLUMN)]
    fuel = [float(row[fuel_column]) for row in compared]
    time = [float(row[time_column]) for row in compared]
    worst = max(compared, key=lambda row: float(row[fuel_column]), default=None)
    return {
        "rows": str(len(members)),
        "compared": str(len(compared)),
        "failed": str(len(failed)),
        "mean_delta_fuel_pct": _number(statistics.fmean(fuel) if fuel else None),
        "std_delta_fuel_pct": _number(_std(fuel)),
        "mean_delta_time_pct": _number(statistics.fmean(time) if time else None),
        "std_delta_time_pct": _number(_std(time)),
        "worst_road": worst["road"] if worst else "",
        "worst_direction": worst["direction"] if worst else "",
        "worst_vehicle": worst.get("vehicle", "") if worst else "",
        "worst_delta_fuel_pct": worst[fuel_column] if worst else "",
        "failed_roads": " ".join(dict.fromkeys(row["road"] for row in failed)),
        "first_error": failed[0][ERROR_COLUMN] if failed else "",
    }


def _std(values: Sequence[float]) -> float | None:
    """The sample standard deviation; 0 for one value, None for none."""
    if not values:
        return None
    return statistics.stdev(values) if len(values) > 1 else 0.0


def _number(value: float | None) -> str:
    return "" if value is None else f"{value:.6g}"


def write_summary(out: Path, summary: Sequence[Mapping[str, str]], consumption: Consumption = FUEL) -> Path:
    """Write ``summary.csv`` into `out` in one step, its columns named for `consumption`; its path."""
    rows = (csv_line([row[c] for c in SUMMARY_COLUMNS]) for row in summary)
    lines = [csv_line(summary_columns(consumption)), *rows]
    atomic_write_text(out / SUMMARY_NAME, "".join(lines))
    return out / SUMMARY_NAME


def summary_lines(summary: Sequence[Mapping[str, str]], consumption: Consumption = FUEL) -> list[str]:
    """The lines of each summary row: its headline against each baseline that ran (mean, distance-
    weighted mean, fuel saved, best and worst road), then Δfuel and Δtrip time as driven against the
    PI with the worst road, and the failed rows (Δenergy and kWh for battery-electric trucks)."""
    lines = []
    word = consumption.word
    for row in summary:
        group = "all rows" if row["axis"] == "all" else f"{row['axis']} {row['value']}"
        who = f"{group}, {row['controller']}"
        for base in HEADLINE_BASELINES:
            if row[savings_column(base, "compared")] not in ("", "0"):
                saving = _saving(row, base, consumption)
                lines.append(f"{who} against the {base.upper()} at equal trip time and end speed: {saving}")
        if row["mean_delta_fuel_pct"]:
            worst = ", ".join(v for v in (row["worst_direction"], row["worst_vehicle"]) if v)
            text = (
                f"Δ{word} {float(row['mean_delta_fuel_pct']):+.2f} % ± {float(row['std_delta_fuel_pct']):.2f}, "
                f"Δtrip time {float(row['mean_delta_time_pct']):+.2f} % over {row['compared']} rows; worst "
                f"{row['worst_road']} ({worst}) {float(row['worst_delta_fuel_pct']):+.2f} %"
            )
        else:
            text = "no comparable row"
        failed = f"; {row['failed']} failed, on {row['failed_roads']}" if row["failed"] != "0" else ""
        lines.append(f"{who} as driven against the PI: {text}{failed}")
    return lines


def _saving(row: Mapping[str, str], base: str, consumption: Consumption) -> str:
    """One baseline's headline figures of a summary row, in words."""

    def figure(name: str) -> float:
        return float(row[savings_column(base, name)])

    word, unit = consumption.word, consumption.unit
    return (
        f"Δ{word} {figure('mean_pct'):+.2f} % on average ({figure('weighted_pct'):+.2f} % weighted by distance), "
        f"{figure('mean_saved_kg'):.3f} {unit} saved per road, {figure('total_saved_kg'):.3f} {unit} in all, over "
        f"{row[savings_column(base, 'compared')]} rows; best {row[savings_column(base, 'best_road')]} "
        f"{figure('best_pct'):+.2f} % ({figure('best_saved_kg'):.3f} {unit}), worst "
        f"{row[savings_column(base, 'worst_road')]} {figure('worst_pct'):+.2f} % "
        f"({figure('worst_saved_kg'):.3f} {unit})"
    )


def check_parquet() -> None:
    """A one-line :class:`SweepError` unless pyarrow, which writes Parquet, is installed."""
    if importlib.util.find_spec("pyarrow") is None:
        raise SweepError("--parquet: needs pyarrow; install it with: pip install 'truckmpc[parquet]'")


def write_parquet(path: Path, columns: Sequence[str], rows: Sequence[Sequence[str]]) -> Path:
    """Write the rows (cell text) as a Parquet file at `path`, each column typed as its cells read
    (numbers, booleans, text; blank as null): one call of pyarrow."""
    # pyarrow is optional (the parquet extra), loaded only to write Parquet
    import pyarrow as pa
    import pyarrow.parquet as pq

    arrays = [_array(pa, [parse_cell(row[i]) for row in rows]) for i in range(len(columns))]
    pq.write_table(pa.table(dict(zip(columns, arrays, strict=True))), path)
    return path


def _array(pa: Any, values: list[Any]) -> Any:
    """A pyarrow array of `values`; as text if they do not share a type (``nearest`` and 4)."""
    try:
        return pa.array(values)
    except (pa.ArrowInvalid, pa.ArrowTypeError):
        return pa.array([None if v is None else str(v) for v in values], type=pa.string())


def fleet_outputs(out: Path, plan: SweepPlan, result: SweepResult, parquet: bool) -> tuple[list[str], list[Path]]:
    """The summary lines to print and the files written besides ``sweep.csv``: ``summary.csv`` for
    a fleet (several roads, directions or vehicles) or a sweep with failed rows, ``sweep.parquet``
    when `parquet`."""
    lines: list[str] = []
    files: list[Path] = []
    failed = any(row[ERROR_COLUMN] for row in result.rows)
    if len(plan.roads) > 1 or len(plan.vehicle_paths) > 1 or failed:
        lengths_m = {road.name: road.length_m for road in plan.roads if isinstance(road, RoadProfile)}
        axes, consumption = [axis.key for axis in plan.axes], plan.consumption
        summary = summarise(result.rows, axes, plan.controllers, lengths_m, consumption)
        lines += summary_lines(summary, consumption)
        files.append(write_summary(out, summary, consumption))
    if parquet:
        cells = [[row[column] for column in result.columns] for row in result.rows]
        files.append(write_parquet(out / "sweep.parquet", result.columns, cells))
    return lines, files

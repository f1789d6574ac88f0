"""The names of the sweep's columns: every per-controller column is ``<controller>_<figure>``, and a
sweep directory written with the names of earlier versions still resumes and plots."""

from __future__ import annotations

import csv
import itertools
import json
import re
from pathlib import Path

import pytest

import truckmpc.sweep.task as sweep_task
from truckmpc import make_section, run_sweep, simulate, write_road
from truckmpc.consumption import ENERGY, FUEL
from truckmpc.sweep import PARTIAL_NAME
from truckmpc.sweep.columns import ERROR_COLUMN, LOOK_AHEAD, Layout

OLD_TO_NEW = {
    "neutral_distance_m": "mpc_neutral_distance_m",
    "realtime_ratio": "mpc_realtime_ratio",
    "solve_ms_mean": "mpc_solve_ms_mean",
    "solve_ms_max": "mpc_solve_ms_max",
    "infeasible_solves": "mpc_infeasible_solves",
    "transitions_per_solve": "mpc_transitions_per_solve",
    "equal_time_pi_v_ref_kmh": "mpc_equal_time_pi_v_ref_kmh",
    "equal_time_pi_fuel_kg": "mpc_equal_time_pi_fuel_kg",
    "equal_time_pi_fuel_corrected_kg": "mpc_equal_time_pi_fuel_corrected_kg",
    "delta_fuel_pct": "mpc_delta_fuel_pct",
    "delta_time_pct": "mpc_delta_time_pct",
    "delta_fuel_corrected_pct": "mpc_delta_fuel_corrected_pct",
    "delta_fuel_equal_time_pct": "mpc_delta_fuel_equal_time_pct",
    "delta_fuel_equal_time_corrected_pct": "mpc_delta_fuel_equal_time_corrected_pct",
}
"""The default sweep's columns as earlier versions named them (their README's list), and now."""


@pytest.fixture(scope="module")
def descent(tmp_path_factory) -> Path:
    """A short road: 100 m flat, 300 m at -3 %, 100 m flat."""
    path = tmp_path_factory.mktemp("roads") / "descent.csv"
    write_road(make_section("hill", 300, -3.0, lead_m=100, tail_m=100), path)
    return path


def layouts() -> list[Layout]:
    """Every selection of look-ahead controllers, with and without the convergence columns."""
    picks = [c for n in range(1, len(LOOK_AHEAD) + 1) for c in itertools.combinations(LOOK_AHEAD, n)]
    return [Layout(pick, check) for pick in picks for check in (False, True) if not check or "mpc" in pick]


@pytest.mark.parametrize("layout", layouts(), ids=lambda layout: f"{'+'.join(layout.runs)}-{layout.check_convergence}")
def test_every_result_column_is_a_controller_that_ran_then_its_figure(layout: Layout) -> None:
    pattern = re.compile(r"^(pi|pcc|mpc)_[a-z0-9]+(_[a-z0-9]+)*$")
    for column in layout.columns:
        if column == ERROR_COLUMN:
            continue
        match = pattern.match(column)
        assert match, column
        assert match.group(1) in layout.runs, (column, layout.runs)
    comparisons = [c for c in layout.columns if "_delta_" in c]
    named = r"(pcc|mpc)_delta_[a-z_]+?(_vs_(pcc))?_pct(_half_(delta|stage|pedal))?"
    assert all(re.fullmatch(named, c) for c in comparisons)


def test_the_pcc_and_mpc_columns_share_their_figures_names() -> None:
    """The figures both look-ahead controllers report have the same name after the prefix."""
    columns = Layout(LOOK_AHEAD).columns
    pcc = {c.removeprefix("pcc_") for c in columns if c.startswith("pcc_")}
    mpc = {c.removeprefix("mpc_") for c in columns if c.startswith("mpc_")}
    assert {"neutral_distance_m", "equal_time_pi_fuel_kg", "delta_fuel_pct", "delta_fuel_equal_time_pct"} <= pcc & mpc


REPO = Path(__file__).resolve().parent.parent
# A sweep column as the pages quote it: a look-ahead controller's Δ or its equal-time baseline.
QUOTED_COLUMN = re.compile(r"`((?:pcc|mpc)_(?:delta|equal_time)_[a-z_]+)`")


def test_every_sweep_column_the_pages_quote_is_one_a_sweep_writes() -> None:
    pages = [REPO / "README.md", *sorted((REPO / "docs").rglob("*.md"))]
    quoted = {name: page.name for page in pages for name in QUOTED_COLUMN.findall(page.read_text(encoding="utf-8"))}
    kinds = (FUEL, ENERGY)
    written = {column for c in kinds for column in Layout(LOOK_AHEAD, check_convergence=True, consumption=c).columns}
    assert quoted, "no page quotes a sweep column"
    assert {name: page for name, page in quoted.items() if name not in written} == {}


def read_csv(path: Path) -> tuple[list[str], list[list[str]]]:
    with path.open(newline="", encoding="utf-8") as handle:
        header, *rows = list(csv.reader(handle))
    return header, rows


def write_old_style(out: Path, interrupted: bool) -> list[list[str]]:
    """Turn a finished default sweep in `out` into one an earlier version wrote: its columns by
    their old names in sweep.json and in sweep.csv, or (`interrupted`) in the partial CSV without
    the last row. Returns the rows it keeps."""
    header, rows = read_csv(out / "sweep.csv")
    old = {new: old for old, new in OLD_TO_NEW.items()}
    old_header = [old.get(name, name) for name in header]
    assert "neutral_distance_m" in old_header and "mpc_neutral_distance_m" not in old_header
    rows = rows[:-1] if interrupted else rows
    (out / "sweep.csv").unlink()
    with (out / (PARTIAL_NAME if interrupted else "sweep.csv")).open("w", newline="", encoding="utf-8") as handle:
        csv.writer(handle, lineterminator="\n").writerows([old_header, *rows])
    settings = json.loads((out / "sweep.json").read_text(encoding="utf-8"))
    settings["columns"] = old_header
    (out / "sweep.json").write_text(json.dumps(settings), encoding="utf-8")
    return rows


def test_an_old_style_directory_resumes_with_its_rows_and_writes_the_new_names(descent, tmp_path, monkeypatch):
    out = tmp_path / "old"
    grid = ["horizon_m=250,500"]
    run_sweep([descent], grid, out, jobs=1)
    new_header, _ = read_csv(out / "sweep.csv")
    kept = write_old_style(out, interrupted=True)
    runs = {"pi": 0, "mpc": 0}

    def counted(road, config, controller="pi"):
        runs[controller] += 1
        return simulate(road, config, controller)

    monkeypatch.setattr(sweep_task, "simulate", counted)
    result = run_sweep([descent], grid, out, jobs=1)
    assert result.resumed_rows == 1 and runs == {"pi": 0, "mpc": 1}  # only the missing row ran
    header, rows = read_csv(out / "sweep.csv")
    assert header == new_header and not (out / PARTIAL_NAME).exists()
    assert rows[0] == kept[0]  # the old row's cells, under the new names
    settings = json.loads((out / "sweep.json").read_text(encoding="utf-8"))
    assert settings["columns"] == new_header


def test_an_old_style_directory_plots_its_old_columns(descent, tmp_path, monkeypatch):
    pytest.importorskip("matplotlib")
    import truckmpc.plot.sweep as plot_sweep

    out = tmp_path / "old"
    run_sweep([descent], ["horizon_m=250,500"], out, jobs=1)
    kept = write_old_style(out, interrupted=False)
    drawn = []

    def kept_figures(figures, svg):
        drawn.extend(figures)
        return [path for _, path in figures]

    monkeypatch.setattr(plot_sweep, "save", kept_figures)
    plot_sweep.plot_sweep(out, out / "sweep.png")
    assert [path.name for _, path in drawn] == ["sweep.png", "realtime.png", "headline.png"]
    header, _ = read_csv(out / "sweep.csv")
    fuel = header.index("delta_fuel_pct")
    axes = {ax.get_ylabel(): ax for ax in drawn[0][0].axes}
    (line,) = [line for line in axes["Δfuel [%]"].get_lines() if list(line.get_xdata()) == [250, 500]]
    assert list(line.get_ydata()) == [float(row[fuel]) for row in kept]

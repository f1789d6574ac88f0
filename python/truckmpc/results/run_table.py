"""The table of a run read at a glance, built from its ``summary.json`` document alone.

One column per controller, in run order. The headline comes first (fuel, trip time, Δfuel at
equal trip time and end speed against each baseline that ran, then the same at equal trip time
alone), then the Δ as driven, the driving figures and
the realtime ratio; ``verbose`` adds the solver statistics, the optimum's plan and the equal-time
search. A row that has no value in any column is left out. Each Δ stands in its own controller's
column; the baseline's own cell is blank. :func:`render_text` prints it (``truckmpc simulate``);
the HTML report lays out the same :class:`RunTable`.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from truckmpc.consumption import FUEL, Consumption, consumption_of
from truckmpc.convergence import convergence_lines
from truckmpc.results.run_rows import (
    Figure,
    comparison_rows,
    driving_rows,
    equal_time_rows,
    figure_rows,
    heading,
    notes,
    optimum_rows,
)
from truckmpc.results.summary import HEADLINE
from truckmpc.results.table_model import Row, RunTable, Section

__all__ = ["Row", "RunTable", "Section", "render_text", "run_table"]


_HEADLINE = (Figure("fuel_kg", ".3f"), Figure("energy_kwh", ".2f"), Figure("time_s", ".1f"))


def _equal_time(c: Consumption) -> tuple[tuple[str, str], ...]:
    """The headline rows: Δ at equal trip time and end speed, and at equal trip time alone."""
    return (
        (HEADLINE, f"Δ{c.word} at equal trip time and end speed"),
        (c.delta_key("_equal_time"), f"Δ{c.word} at equal trip time"),
    )


_SOLVER = (
    Figure("horizon_solves", "d"),
    Figure("infeasible_solves", "d"),
    Figure("fallback_relaxed", "d"),
    Figure("fallback_rescues", "d"),
    Figure("fallback_rescue_m", ".0f"),
    Figure("solve_ms_mean", ".3f"),
    Figure("solve_ms_max", ".3f"),
    Figure("pcc_events", "d"),
    Figure("compute_time_s", ".2f"),
)
_PLAN = (
    Figure("plan_fuel_kg", ".3f"),
    Figure("plan_energy_kwh", ".2f"),
    Figure("plan_time_s", ".1f"),
    Figure("plan_gap_pct", ".3f"),
    Figure("plan_solve_s", ".2f"),
)
_COMPUTE = (Figure("realtime_ratio", ".2e"),)


def run_table(summary: Mapping[str, Any], *, verbose: bool = False) -> RunTable:
    """The table of the run a ``summary.json`` document records (as :func:`json.load` returns it);
    ``verbose`` adds the solver statistics, the optimum's plan and the equal-time search."""
    columns = _columns(summary)
    # A run whose battery emptied did not drive the road: its message says where, no figure shows.
    runs = [{} if summary[name].get("battery_empty") else summary[name] for name in columns]
    c = consumption_of(summary[columns[0]]) if columns else FUEL
    sections = [
        Section("", figure_rows(_HEADLINE, runs) + comparison_rows(summary, columns, _equal_time(c))),
        Section("as driven", comparison_rows(summary, columns, _as_driven(c)) + optimum_rows(summary, columns)),
        Section("driving", driving_rows(runs)),
        Section("compute", figure_rows(_SOLVER if verbose else (), runs) + figure_rows(_COMPUTE, runs)),
    ]
    if verbose:
        sections.append(Section("the optimum's plan", figure_rows(_PLAN, runs)))
        sections.append(Section("equal trip time: the baseline re-run", equal_time_rows(summary, columns)))
    shown = tuple(Section(s.title, tuple(r for r in s.rows if any(r.cells))) for s in sections)
    legend = any(row.label.startswith("Δ") for section in shown for row in section.rows)
    lines = list(notes(summary, columns, legend))
    if isinstance(summary.get("convergence"), Mapping):
        lines += [_CONVERGENCE, *convergence_lines(summary["convergence"], _label_width(shown))]
    return RunTable(heading(summary), columns, tuple(s for s in shown if s.rows), tuple(lines))


_CONVERGENCE = (
    "convergence: how far the MPC's Δ vs PI moves at half the speed step δ and at half the stage S "
    "(and at twice pedal_levels)"
)


def _as_driven(c: Consumption) -> tuple[tuple[str, str], ...]:
    """The rows of the runs as driven: Δ of what they consumed, Δtrip time, Δ end speeds corrected."""
    return (
        (c.delta_key(), f"Δ{c.word}"),
        ("delta_time_pct", "Δtrip time"),
        (c.delta_key("_corrected"), f"Δ{c.word}, end speeds corrected"),
    )


def render_text(table: RunTable) -> str:
    """The table as plain text: the heading line, a header of the controllers, each section (its
    title on a line of its own after a blank line), then the notes."""
    width = _label_width(table.sections)
    cell = max([10, *(len(c) + 2 for c in table.columns)])
    cell = max([cell, *(len(v) + 2 for s in table.sections for r in s.rows for v in r.cells)])
    lines = [table.heading, " " * width + "".join(f"{name:>{cell}}" for name in table.columns)]
    for section in table.sections:
        if section.title:
            lines += ["", section.title]
        for row in section.rows:
            line = f"{_head(row):<{width}}" + "".join(f"{value:>{cell}}" for value in row.cells)
            lines.append(line.rstrip())
    return "\n".join([*lines, *table.notes])


def _head(row: Row) -> str:
    return f"{row.label} [{row.unit}]" if row.unit else row.label


def _label_width(sections: tuple[Section, ...]) -> int:
    """The label column: the longest ``label [unit]`` and two spaces."""
    return max((len(_head(row)) + 2 for section in sections for row in section.rows), default=30)


def _columns(summary: Mapping[str, Any]) -> tuple[str, ...]:
    """The controllers that ran, in run order (the run record's; else the summary's own order)."""
    recorded = (summary.get("run") or {}).get("controllers")
    if recorded:
        return tuple(name for name in recorded if isinstance(summary.get(name), Mapping))
    return tuple(k for k, v in summary.items() if isinstance(v, Mapping) and ("fuel_kg" in v or "energy_kwh" in v))

"""The outputs of a run, declared once in the core (``truckmpc._core.declaration("summary")``
and ``("trace")``): every figure of a controller's summary and every column of its trace, each with
its name (unit in the name), unit, label, meaning, which runs carry it, where it is computed, how a
road driven as legs joins it (:mod:`truckmpc.legs`) and whose ``sweep.csv`` columns carry it
(:mod:`truckmpc.sweep.columns`). The outputs reference page's tables are made from it
(:func:`summary_table`, :func:`trace_table`).

A spec's ``runs`` is ``every``, ``pcc`` (VECTO's rule-based predictive cruise control), ``dp`` (the
controllers that solve the DP: ``mpc``, ``optimal``), ``optimal`` (the whole-road optimum), ``legs``
(a road with stops, driven as its legs) or ``electric`` (a battery-electric truck's runs); its
``source`` is ``core`` or ``python`` (added after the core's run).
"""

from __future__ import annotations

from dataclasses import dataclass

from truckmpc import _core

__all__ = [
    "SUMMARY",
    "SUMMARY_SPECS",
    "TRACE_COLUMNS",
    "TRACE_SPECS",
    "OutputSpec",
    "summary_table",
    "trace_table",
]


@dataclass(frozen=True)
class OutputSpec:
    """One declared output: a figure of a controller's summary or a column of its trace."""

    name: str
    """Key in the summary (column of the trace), its unit in the name."""
    unit: str
    """Unit (``"-"`` for none)."""
    label: str
    """Short label for tables."""
    doc: str
    """One-line meaning."""
    kind: str
    """number, count, flag, text or record."""
    runs: str
    """Which runs carry it: every, pcc, dp (mpc, optimal), optimal, legs (a road with stops), or
    electric (a battery-electric truck's)."""
    source: str
    """Where it is computed: core, or python (after the core's run)."""
    merge: str
    """How a road driven as legs joins it: sum, sum_unless_stalled, max, first, last, any,
    mean_per_solve, per_100km, per_time_s, mean_speed, built; trace columns continued or joined."""
    merge_of: str | None
    """The figure a recomputed one (per_100km, per_time_s) follows from; None otherwise."""
    sweep: str
    """Whose columns of sweep.csv carry it: all, look_ahead, mpc, or ``""`` for none."""
    decimals: int | None
    """Decimals the trace's CSV writes; None for summary figures and whole numbers."""


SUMMARY_SPECS: tuple[OutputSpec, ...] = tuple(OutputSpec(**record) for record in _core.declaration("summary"))
"""Every figure of a controller's summary, in ``summary.json``'s order."""

SUMMARY: dict[str, OutputSpec] = {spec.name: spec for spec in SUMMARY_SPECS}
"""The summary's figures by name."""

TRACE_SPECS: tuple[OutputSpec, ...] = tuple(OutputSpec(**record) for record in _core.declaration("trace"))
"""Every column of a run's trace, in the CSV's order."""

TRACE_COLUMNS: tuple[str, ...] = tuple(spec.name for spec in TRACE_SPECS if spec.runs == "every")
"""The trace's columns every run carries, in the CSV's order (``gear`` int64, the others float64); a
battery-electric truck's runs carry its battery's columns in place of ``fuel_g``."""

_RUNS = {
    "every": "every run",
    "pcc": "`pcc`",
    "dp": "`mpc`, `optimal`",
    "optimal": "`optimal`",
    "legs": "a road with stops",
    "electric": "a battery-electric truck's",
}
"""Which runs carry a figure, in the reference page's words."""

_MERGES = {
    "sum": "sum",
    "sum_unless_stalled": "sum (null if a leg stalled)",
    "max": "largest",
    "first": "first leg's",
    "last": "last leg's",
    "any": "true if any leg's",
    "mean_per_solve": "mean weighted by solves",
    "per_100km": "recomputed: `{of}` per 100 km",
    "per_time_s": "recomputed: `{of}` / `time_s`",
    "mean_speed": "recomputed: `distance_m` / `time_s`",
    "built": "made from the legs",
    "continued": "continued from the previous leg's end",
    "joined": "one leg after another",
}
"""How the legs join a figure, in the reference page's words."""


def merge_text(spec: OutputSpec) -> str:
    """How a road driven as legs joins `spec`, in words."""
    return _MERGES[spec.merge].format(of=spec.merge_of)


def summary_table() -> str:
    """A Markdown table of the summary's figures: key, unit, which runs carry it, how legs join
    it, meaning (those added in Python marked so)."""
    lines = ["| key | unit | runs | legs | meaning |", "|---|---|---|---|---|"]
    for spec in SUMMARY_SPECS:
        doc = spec.doc + (" Added in Python." if spec.source == "python" else "")
        cells = [f"`{spec.name}`", _unit(spec.unit), _RUNS[spec.runs], merge_text(spec), _cell(doc)]
        lines.append(f"| {' | '.join(cells)} |")
    return "\n".join(lines)


def trace_table() -> str:
    """A Markdown table of the trace's columns: column, unit, how legs join it, meaning."""
    lines = ["| column | unit | legs | meaning |", "|---|---|---|---|"]
    for spec in TRACE_SPECS:
        cells = [f"`{spec.name}`", _unit(spec.unit), merge_text(spec), _cell(spec.doc)]
        lines.append(f"| {' | '.join(cells)} |")
    return "\n".join(lines)


def _unit(unit: str) -> str:
    return "–" if unit == "-" else unit


def _cell(text: str) -> str:
    """Text for a Markdown table cell: a bare `|` would end the cell."""
    return text.replace("|", "\\|")

"""Plain-text tables the CLI prints: one line per figure, one column per run.

A figure is ``(label, key, unit, spec)``: the line reads ``label [unit]`` and each column the run's
value of ``key`` formatted with ``spec`` (``".3f"``), or ``-`` when it has none.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

Figure = tuple[str, str, str, str]


def label_width(figures: Sequence[Figure]) -> int:
    """Width of the label column: the longest ``label [unit]`` and two spaces."""
    return max(len(label) + len(unit) + 3 for label, _, unit, _ in figures)


def format_value(value: Any, spec: str) -> str:
    """``value`` formatted with ``spec``; ``-`` for None, NaN or an infinity."""
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "-"
    return format(value, spec)


def figure_lines(
    figures: Sequence[Figure], runs: Sequence[Mapping[str, Any]], cell_width: int, width: int | None = None
) -> list[str]:
    """One line per figure: its label (in ``width``, default :func:`label_width`), then the value of
    each run right-aligned in ``cell_width``."""
    width = label_width(figures) if width is None else width
    lines = []
    for label, key, unit, spec in figures:
        head = f"{label} [{unit}]" if unit else label
        lines.append(f"{head:<{width}}" + "".join(f"{format_value(run.get(key), spec):>{cell_width}}" for run in runs))
    return lines

"""The text of a ``sweep.csv`` cell: a value as written (:func:`cell`, also a YAML ``--set`` value)
and read back (:func:`parse_cell`, also for ``truckmpc plot`` and ``pareto``), and a row's ``error``
cell (:func:`error_text`)."""

from __future__ import annotations

import contextlib
import json
import math
from collections.abc import Mapping
from typing import Any

__all__ = ["cell", "error_text", "parse_cell", "yaml_text"]


def cell(value: Any) -> str:
    """A value as written in the CSV (and as a YAML ``--set`` value): true/false, repr of floats
    (exact round trip), blank for None."""
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value) if math.isfinite(value) else ""
    return str(value)


def yaml_text(value: Any) -> str:
    """A value as the YAML text of a ``key=value`` override (strings quoted)."""
    return json.dumps(value) if isinstance(value, str) else ("null" if value is None else cell(value))


def parse_cell(text: str) -> Any:
    """The value a cell's text stands for (the inverse of :func:`cell`, also for ``truckmpc plot``):
    None for blank, a bool for true/false (any case), an int, a float, else the text itself (road
    names, string axis values)."""
    text = text.strip()
    if text == "":
        return None
    if text.lower() in ("true", "false"):
        return text.lower() == "true"
    for number in (int, float):
        with contextlib.suppress(ValueError):
            return number(text)
    return text


def error_text(failed: Mapping[str, str]) -> str | None:
    """The ``error`` cell of a row from each failed run's error (``pi, mpc: line`` when they say
    the same); None when none failed."""
    by_line: dict[str, list[str]] = {}
    for name, line in failed.items():
        by_line.setdefault(line, []).append(name)
    return "; ".join(f"{', '.join(names)}: {line}" for line, names in by_line.items()) or None

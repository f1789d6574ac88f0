"""Grid axes: ``KEY=SPEC`` parsed into values (decimal ranges or YAML lists) and their combinations."""

from __future__ import annotations

import decimal
import itertools
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import yaml

from truckmpc.config.yamlfile import load_value
from truckmpc.sweep.cells import cell
from truckmpc.sweep.errors import SweepError

MAX_AXIS_VALUES = 10_000
"""More values than this on one axis is taken to be a typo in a range's step."""


@dataclass(frozen=True)
class Axis:
    """One grid axis: a config key and its values, in order (``spec`` is the text it came from)."""

    key: str
    values: tuple[Any, ...]
    spec: str = ""


def parse_axis(text: str) -> Axis:
    """``KEY=SPEC``: SPEC is ``start:stop:step`` (an inclusive range, computed in decimal so
    ``0.1:0.3:0.1`` gives exactly 0.1, 0.2, 0.3; integers if all three are) or a comma list of
    YAML scalars (``0.1,0.2``, ``true,false``, ``nearest,interpolate``)."""
    key, sep, spec = text.partition("=")
    key, spec = key.strip(), spec.strip()
    where = f"--grid {key}" if key else f"--grid {text!r}"
    if not sep or not key or not spec:
        raise SweepError(f"--grid {text!r}: expected KEY=SPEC (SPEC start:stop:step or a comma list)")
    values = _range(where, spec) if ":" in spec else _list(where, spec)
    seen: set[tuple[type, Any]] = set()
    for value in values:  # a set, not all pairs: a range of 10 000 values took seconds
        if (type(value), value) in seen:
            raise SweepError(f"{where}: value {cell(value)} is given twice")
        seen.add((type(value), value))
    return Axis(key, tuple(values), spec)


def _range(where: str, spec: str) -> list[Any]:
    parts = [part.strip() for part in spec.split(":")]
    try:
        if len(parts) != 3:
            raise decimal.InvalidOperation
        start, stop, step = (decimal.Decimal(part) for part in parts)
    except decimal.InvalidOperation:
        raise SweepError(f"{where}: expected start:stop:step numbers, got {spec!r}") from None
    if not all(x.is_finite() for x in (start, stop, step)) or step <= 0 or stop < start:
        raise SweepError(f"{where}: expected start <= stop and step > 0 in start:stop:step, got {spec!r}")
    count = int((stop - start) / step) + 1
    if count > MAX_AXIS_VALUES:
        raise SweepError(f"{where}: {spec!r} gives {count} values, expected at most {MAX_AXIS_VALUES}")
    whole = all("." not in part and "e" not in part.lower() for part in parts)
    return [int(start + i * step) if whole else float(start + i * step) for i in range(count)]


def _list(where: str, spec: str) -> list[Any]:
    values = []
    for item in spec.split(","):
        try:
            value = load_value(item)
        except yaml.YAMLError:
            raise SweepError(f"{where}: value {item.strip()!r} is not a YAML scalar") from None
        if item.strip() == "" or isinstance(value, (list, dict)):
            raise SweepError(f"{where}: expected a comma list of scalar values, got {spec!r}")
        values.append(value)
    return values


def expand_grid(axes: Sequence[Axis]) -> list[tuple[Any, ...]]:
    """Every combination of the axes' values, the last axis varying fastest (one empty combination
    for no axes)."""
    return list(itertools.product(*(axis.values for axis in axes)))

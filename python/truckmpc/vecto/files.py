"""Reading VECTO's file formats: the JSON component files (``.vecto`` job, ``.vveh`` vehicle, ``.veng``
engine, ``.vgbx`` gearbox), whose data sit under a ``Body`` key, and the CSV tables (``.vfld``
full-load curve, ``.vmap`` fuel map): one header line, then rows of numbers, ``#`` starting a comment.

Every problem is a :class:`~truckmpc.errors.VehicleError` naming the file and the line or key.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

from truckmpc.errors import VehicleError, read_user_text

__all__ = ["json_body", "number", "numbers_table", "text"]


def json_body(path: Path) -> dict[str, Any]:
    """The ``Body`` object of a VECTO JSON component file."""
    raw = read_user_text(path, str(path), "a VECTO JSON file", VehicleError, encoding="utf-8-sig")
    try:
        doc = json.loads(raw)
    except json.JSONDecodeError as e:
        raise VehicleError(f"{path}:{e.lineno}: expected JSON, got a syntax error ({e.msg})") from None
    except (RecursionError, ValueError) as e:  # nested too deeply; an integer too long to convert
        raise VehicleError(
            f"{path}: expected a VECTO JSON file, got JSON Python cannot read ({type(e).__name__})"
        ) from None
    if not isinstance(doc, dict):
        raise VehicleError(f"{path}: expected a JSON object with a 'Body' object, got a {type(doc).__name__}")
    body = doc.get("Body")
    if not isinstance(body, dict):
        raise VehicleError(
            f"{path}: Body: expected an object, got {'nothing' if body is None else type(body).__name__}"
        )
    return body


def number(
    body: dict[str, Any], key: str, where: str | Path, *, minimum: float | None = None, positive: bool = False
) -> float:
    """The finite number under ``key`` of a JSON body (VECTO writes some numbers as strings); ``where``
    (the file, and the object within it) starts the error message."""
    if key not in body:
        raise VehicleError(f"{where}: {key}: expected a number, got nothing (the key is missing)")
    value = body[key]
    if isinstance(value, bool):
        raise VehicleError(f"{where}: {key}: expected a number, got {value!r}")
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise VehicleError(f"{where}: {key}: expected a number, got {value!r}") from None
    if not math.isfinite(x) or (positive and x <= 0) or (minimum is not None and x < minimum):
        bound = "> 0" if positive else f">= {minimum:g}" if minimum is not None else "finite"
        raise VehicleError(f"{where}: {key}: expected a number {bound}, got {value!r}")
    return x


def text(body: dict[str, Any], key: str, where: str | Path) -> str:
    """The non-empty string under ``key`` of a JSON body."""
    value = body.get(key)
    if not isinstance(value, str) or not value.strip():
        raise VehicleError(f"{where}: {key}: expected a text, got {value!r}")
    return value.strip()


def numbers_table(path: Path, columns: int, what: str) -> list[tuple[int, tuple[float, ...]]]:
    """The rows of a VECTO CSV table of ``columns`` numbers each, after its header line, as (line
    number, numbers); blank and ``#`` lines skipped. ``what`` names the table in errors ("a
    full-load curve")."""
    raw = read_user_text(path, str(path), what, VehicleError, encoding="utf-8-sig")
    rows: list[tuple[int, tuple[float, ...]]] = []
    header_seen = False
    for lineno, line in enumerate(raw.splitlines(), start=1):
        content = line.split("#", 1)[0].strip()
        if not content:
            continue
        if not header_seen:
            header_seen = True
            if _is_numeric_row(content):
                raise VehicleError(f"{path}:{lineno}: expected a header line naming the columns, got numbers")
            continue
        cells = [c.strip() for c in content.split(",")]
        if len(cells) < columns:
            raise VehicleError(f"{path}:{lineno}: expected {columns} comma-separated numbers, got {len(cells)} fields")
        try:
            values = tuple(float(c) for c in cells[:columns])
        except ValueError:
            raise VehicleError(f"{path}:{lineno}: expected {columns} numbers, got {content!r}") from None
        if not all(math.isfinite(v) for v in values):
            raise VehicleError(f"{path}:{lineno}: expected finite numbers, got {content!r}")
        rows.append((lineno, values))
    if len(rows) < 2:
        raise VehicleError(f"{path}: expected {what} with at least two rows, got {len(rows)}")
    return rows


def _is_numeric_row(content: str) -> bool:
    try:
        [float(c) for c in content.split(",")]
    except ValueError:
        return False
    return True

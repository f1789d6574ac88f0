"""A VECTO XML file as a tree of elements, each with the line it starts on and its path, and the
readers of its values: every problem is a one-line :class:`~truckmpc.errors.VehicleError` naming
the file, the line, the element and what was expected.

Elements are matched by their local names, whatever their namespace, so a reader follows VECTO's
schema versions where their names agree.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from xml.parsers import expat

from truckmpc.errors import VehicleError, read_user_text
from truckmpc.vecto.checks import Located

__all__ = [
    "Element",
    "Row",
    "attr",
    "boolean",
    "child",
    "entries",
    "located",
    "number",
    "numbered",
    "opt",
    "parse",
    "table",
    "text",
]

_KEYS = {"Gear": "number", "Axle": "axleNumber"}  # the attribute that tells repeated elements apart


@dataclass
class Element:
    """An XML element: local name, start line, path from below the root, attributes (local names)."""

    file: Path
    name: str
    line: int
    path: str
    attrs: dict[str, str]
    children: list[Element] = field(default_factory=list)
    texts: list[str] = field(default_factory=list)

    @property
    def text(self) -> str:
        return "".join(self.texts).strip()

    @property
    def where(self) -> str:
        return f"{self.file}:{self.line}: {self.path}"


Row = tuple[Element, tuple[float, float, float]]
"""An ``Entry`` element and its three numbers."""


def parse(path: Path) -> Element:
    """The file's element tree, each element with its start line."""
    try:
        raw = read_user_text(path, str(path), "a VECTO declaration XML file", VehicleError, encoding="utf-8-sig")
    except OSError as e:  # permission denied and the like
        raise VehicleError(f"{path}: cannot be read ({e.strerror or type(e).__name__})") from None
    parser = expat.ParserCreate(namespace_separator=" ")
    stack: list[Element] = []
    top: list[Element] = []

    def start(tag: str, attrs: dict[str, str]) -> None:
        name = _local(tag)
        key = _KEYS.get(name)
        label = f'{name}[@{key}="{attrs[key]}"]' if key in attrs else name
        el_path = f"{stack[-1].path}/{label}" if len(stack) > 1 else label
        el = Element(path, name, parser.CurrentLineNumber, el_path, {_local(k): v for k, v in attrs.items()})
        (stack[-1].children if stack else top).append(el)
        stack.append(el)

    def doctype(*_: object) -> None:
        raise VehicleError(
            f"{path}:{parser.CurrentLineNumber}: expected a VECTO declaration without a DOCTYPE, got one"
        )

    parser.StartElementHandler = start
    parser.EndElementHandler = lambda _tag: stack.pop()
    parser.CharacterDataHandler = lambda data: stack[-1].texts.append(data) if stack else None
    parser.StartDoctypeDeclHandler = doctype
    try:
        parser.Parse(raw, True)
    except expat.ExpatError as e:
        got = f"{expat.ErrorString(e.code)} (column {e.offset + 1})"
        raise VehicleError(f"{path}:{e.lineno}: expected well-formed XML, got {got}") from None
    return top[0]


def _local(name: str) -> str:
    """A name without its namespace (expat gives ``namespace local``)."""
    return name.rsplit(" ", 1)[-1]


def opt(el: Element, name: str) -> Element | None:
    return next((c for c in el.children if c.name == name), None)


def child(el: Element, *names: str) -> Element:
    """The first child of that name, its first child of the next name, and so on."""
    for name in names:
        found = opt(el, name)
        if found is None:
            raise VehicleError(f"{el.where}: expected a <{name}> element, got none")
        el = found
    return el


def text(el: Element) -> str:
    if not el.text:
        raise VehicleError(f"{el.where}: expected a text, got nothing")
    return el.text


def number(el: Element, *, positive: bool = False, minimum: float | None = None) -> float:
    """The element's text as a finite number."""
    return _checked(el.where, el.text, positive, minimum)


def attr(el: Element, name: str, minimum: float | None = None) -> float:
    """An attribute as a finite number."""
    where = f"{el.file}:{el.line}: {el.path}/@{name}"
    if name not in el.attrs:
        raise VehicleError(f"{where}: expected a number, got nothing (the attribute is missing)")
    return _checked(where, el.attrs[name], False, minimum)


def _checked(where: str, raw: str, positive: bool, minimum: float | None) -> float:
    try:
        x = float(raw)
    except ValueError:
        raise VehicleError(f"{where}: expected a number, got {raw!r}") from None
    if not math.isfinite(x) or (positive and x <= 0) or (minimum is not None and x < minimum):
        bound = "> 0" if positive else f">= {minimum:g}" if minimum is not None else "finite"
        raise VehicleError(f"{where}: expected a number {bound}, got {raw!r}")
    return x


def boolean(el: Element) -> bool:
    value = el.text
    if value not in ("true", "false", "1", "0"):
        raise VehicleError(f"{el.where}: expected true or false, got {value!r}")
    return value in ("true", "1")


def numbered(parent: Element, name: str) -> list[Element]:
    """The ``name`` children ordered by their number attribute, which must run 1..n."""
    key = _KEYS[name]
    items = [c for c in parent.children if c.name == name]
    if not items:
        raise VehicleError(f"{parent.where}: expected at least one <{name}> element, got none")
    numbered = []
    for c in items:
        try:
            numbered.append((int(c.attrs.get(key, "")), c))
        except ValueError:
            raise VehicleError(f"{c.where}/@{key}: expected a whole number, got {c.attrs.get(key)!r}") from None
    numbered.sort(key=lambda pair: pair[0])
    for i, (n, c) in enumerate(numbered, start=1):
        if n != i:
            raise VehicleError(f"{c.where}/@{key}: expected {name} numbers 1 to {len(items)}, each once, got {n}")
    return [c for _, c in numbered]


def entries(
    el: Element, columns: tuple[tuple[str, float | None], ...], fewest: int
) -> list[tuple[Element, tuple[float, ...]]]:
    """The ``Entry`` children of ``el`` as numbers, one per (attribute, lowest value) column."""
    rows = [(e, tuple(attr(e, name, low) for name, low in columns)) for e in el.children if e.name == "Entry"]
    if len(rows) < fewest:
        raise VehicleError(f"{el.where}: expected at least {fewest} <Entry> elements, got {len(rows)}")
    return rows


def table(el: Element, columns: tuple[tuple[str, float | None], ...], fewest: int) -> list[Row]:
    """:func:`entries` of three columns."""
    return [(e, (a, b, c)) for e, (a, b, c) in entries(el, columns, fewest)]


def located(rows: list[Row]) -> list[Located]:
    """The rows with where each element was read, for the checks the file formats share."""
    return [(e.where, e.line, values) for e, values in rows]

"""The pieces of the page: escaped text, tables, definition lists and the page itself (one file,
its style inline, nothing fetched from elsewhere). Every function returns HTML text; every value
given to one is plain text and escaped here."""

from __future__ import annotations

import html
import math
from collections.abc import Mapping, Sequence
from string import Template
from typing import Any

__all__ = ["code_block", "definitions", "escape", "page", "scalar_text", "section", "table"]

escape = html.escape


def scalar_text(value: Any) -> str:
    """A value as a reader wants it: ``–`` for none, ``yes``/``no``, floats without trailing noise
    (up to 6 significant digits), lists joined by commas."""
    if value is None:
        return "–"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, float):
        return "–" if not math.isfinite(value) else f"{value:.6g}"
    if isinstance(value, (list, tuple)) and all(not isinstance(v, (dict, list)) for v in value):
        return ", ".join(scalar_text(v) for v in value) if value else "none"
    return str(value)


def table(head: Sequence[str], rows: Sequence[Sequence[str]], *, caption: str = "", css: str = "") -> str:
    """A table of plain-text cells; a first cell of each row is its row heading."""
    cap = f"<caption>{escape(caption)}</caption>" if caption else ""
    head_html = "".join(f'<th scope="col">{escape(h)}</th>' for h in head)
    body = "".join("<tr>" + "".join(_cell(c, first=i == 0) for i, c in enumerate(row)) + "</tr>\n" for row in rows)
    cls = f' class="{escape(css)}"' if css else ""
    return f"<table{cls}>{cap}<thead><tr>{head_html}</tr></thead>\n<tbody>\n{body}</tbody></table>\n"


def _cell(text: str, *, first: bool) -> str:
    if first:
        return f'<th scope="row">{escape(text)}</th>'
    return f"<td>{escape(text)}</td>"


def definitions(items: Mapping[str, Any]) -> str:
    """A definition list of `items`; a mapping value nests another list, a list of mappings one each."""
    parts = []
    for key, value in items.items():
        parts.append(f"<dt>{escape(str(key))}</dt><dd>{_value_html(value)}</dd>")
    return '<dl class="defs">' + "".join(parts) + "</dl>\n"


def _value_html(value: Any) -> str:
    if isinstance(value, Mapping):
        return definitions(value) if value else "none"
    if isinstance(value, (list, tuple)) and any(isinstance(v, (Mapping, list)) for v in value):
        return "".join(_value_html(v) for v in value)
    return escape(scalar_text(value))


def code_block(text: str, *, ident: str = "") -> str:
    """Text to copy (a command), in a block of its own, wrapped where it is long."""
    attr = f' id="{escape(ident)}"' if ident else ""
    # each word unbroken, so a line wraps only between words (not after the "-" of an option)
    words = " ".join(f'<span class="word">{escape(word)}</span>' for word in text.split(" "))
    return f'<pre class="command"><code{attr}>{words}</code></pre>\n'


def section(ident: str, title: str, body: str) -> str:
    """One titled part of the page, linked from its contents by `ident`."""
    return f'<section id="{escape(ident)}">\n<h2>{escape(title)}</h2>\n{body}</section>\n'


_PAGE = Template("""<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<meta name="generator" content="truckmpc report">
<title>$title</title>
<style>
body { font-family: system-ui, -apple-system, "Segoe UI", Roboto, sans-serif; color: #1d232a;
       max-width: 1180px; margin: 0 auto; padding: 1.5rem 2rem 4rem; line-height: 1.45; }
h1 { font-size: 1.7rem; margin-bottom: 0.2rem; }
h2 { font-size: 1.3rem; border-bottom: 2px solid #d7dde3; padding-bottom: 0.2rem; margin-top: 2.2rem; }
h3 { font-size: 1.05rem; margin: 1.4rem 0 0.4rem; }
.subtitle { color: #56616c; margin-top: 0; }
.lead { font-size: 1.05rem; background: #f2f6fa; border-left: 4px solid #2f6fa7; padding: 0.5rem 1rem; }
.lead p { margin: 0.3rem 0; }
nav { font-size: 0.95rem; margin: 0.9rem 0; } nav a { margin-right: 1.1rem; }
table { border-collapse: collapse; margin: 0.6rem 0 1rem; font-size: 0.92rem; }
caption { text-align: left; font-weight: 600; padding-bottom: 0.3rem; }
th, td { padding: 0.28rem 0.7rem; border-bottom: 1px solid #e3e7eb; vertical-align: top; }
thead th { background: #eef2f5; text-align: left; border-bottom: 2px solid #c9d1d9; }
table.numbers td { text-align: right; font-variant-numeric: tabular-nums; }
table.numbers thead th { text-align: right; } table.numbers thead th:first-child { text-align: left; }
tbody th { text-align: left; font-weight: normal; }
table.numbers thead th.group { text-align: center; border-bottom: 1px solid #c9d1d9; }
table.sweep { font-size: 0.86rem; width: 100%; table-layout: fixed; }
table.sweep th, table.sweep td { padding: 0.25rem 0.45rem; overflow-wrap: anywhere; }
table.numbers .key { text-align: left; }
table.roads td { overflow-wrap: anywhere; }
tr.group th { background: #f7f9fb; font-weight: 600; padding-top: 0.6rem; }
tr.headline th, tr.headline td { font-weight: 600; }
td.changed { background: #fff5d6; }
.note { color: #56616c; font-size: 0.9rem; }
.wide { overflow-x: auto; }
figure { margin: 1rem 0 2rem; } figure img { max-width: 100%; height: auto; border: 1px solid #e3e7eb; }
figcaption { color: #56616c; font-size: 0.9rem; }
pre { background: #f4f5f7; padding: 0.7rem 1rem; overflow-x: auto; border-radius: 4px; }
pre.command { white-space: pre-wrap; } pre.command .word { white-space: nowrap; }
table.settings { width: 100%; table-layout: fixed; }
table.settings col.key { width: 24%; } table.settings col.value { width: 18%; }
table.settings col.unit { width: 11%; }
code { font-family: ui-monospace, "DejaVu Sans Mono", Menlo, monospace; font-size: 0.88rem; }
dl.defs { display: grid; grid-template-columns: max-content 1fr; gap: 0.15rem 1.2rem; margin: 0.3rem 0; }
dl.defs dt { font-weight: 600; } dl.defs dd { margin: 0; overflow-wrap: anywhere; }
dl.defs dl.defs { border-left: 2px solid #e3e7eb; padding-left: 0.8rem; }
details summary { cursor: pointer; color: #2f6fa7; }
</style>
</head>
<body>
$body
</body>
</html>
""")


def page(title: str, body: str) -> str:
    """The whole HTML document: `title` (plain text) and `body` (HTML)."""
    return _PAGE.substitute(title=escape(title), body=body)

"""The outputs reference's tables, generated when the site is built from the core's declaration of
a run's outputs (read through :mod:`truckmpc.schema`): every figure of a controller's summary and
every column of its trace, with its unit, which runs carry it, how a road driven as legs joins it
and its meaning. The page reference/outputs.md holds the lines ``<!-- outputs:summary -->`` and
``<!-- outputs:trace -->``; this MkDocs hook puts each table under its line.
"""

from __future__ import annotations

import re
from typing import Any

from mkdocs.exceptions import PluginError

from truckmpc.schema import summary_table, trace_table

PAGE = "reference/outputs.md"
_TABLES = {"summary": summary_table, "trace": trace_table}
_MARKER = re.compile(r"^<!-- outputs:(\w+) -->$", re.M)
_TABLE = '<div class="reference-table" markdown>\n\n{}\n\n</div>'
"""A table in the reference pages' style (docs/stylesheets/reference.css)."""


def outputs_page(markdown: str) -> str:
    """The page with each declared table under its marker; each table must have exactly one marker
    and each marker must name a table."""
    found = _MARKER.findall(markdown)
    if sorted(found) != sorted(_TABLES):
        raise PluginError(
            f"{PAGE}: expected one line <!-- outputs:NAME --> for each of {', '.join(_TABLES)}, "
            f"got {', '.join(found) or 'none'}"
        )
    return _MARKER.sub(lambda m: f"{m.group(0)}\n\n{_TABLE.format(_TABLES[m.group(1)]())}\n", markdown)


def on_page_markdown(markdown: str, page: Any, **_: Any) -> str:
    """MkDocs hook: fill the outputs reference page's markers."""
    return outputs_page(markdown) if page.file.src_uri == PAGE else markdown

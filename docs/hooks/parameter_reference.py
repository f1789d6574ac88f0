"""The parameter reference, generated when the site is built from the parameter declarations (the
Rust core's, read through :mod:`truckmpc.config`): every key of every section with its unit,
default, allowed values and meaning. The page reference/parameters.md holds a hand-written
introduction per section and, where the section's table goes, the line ``<!-- keys:SECTION -->``;
this MkDocs hook puts the table (:func:`truckmpc.config.key_table`, which ``truckmpc config keys --markdown``
prints too) under that line.
"""

from __future__ import annotations

import re
from typing import Any

from mkdocs.exceptions import PluginError

from truckmpc.config import SECTION_NAMES, key_table

PAGE = "reference/parameters.md"
_MARKER = re.compile(r"^<!-- keys:(\w+) -->$", re.M)
_TABLE = '<div class="reference-table" markdown>\n\n{}\n\n</div>'
"""A table in the reference pages' style (docs/stylesheets/reference.css)."""


def parameters_page(markdown: str) -> str:
    """The page with every section's key table under its marker. Every declared section must have
    exactly one marker, and every marker must name a declared section."""
    found = _MARKER.findall(markdown)
    unknown = sorted(set(found) - set(SECTION_NAMES))
    missing = [s for s in SECTION_NAMES if s not in found]
    twice = sorted({s for s in found if found.count(s) > 1})
    if unknown or missing or twice:
        problems = [
            f"{what}: {', '.join(names)}"
            for what, names in (("no such section", unknown), ("no marker", missing), ("two markers", twice))
            if names
        ]
        raise PluginError(
            f"{PAGE}: expected one line <!-- keys:SECTION --> for each of {', '.join(SECTION_NAMES)}; "
            + "; ".join(problems)
        )
    return _MARKER.sub(lambda m: f"{m.group(0)}\n\n{_TABLE.format(key_table(m.group(1)))}\n", markdown)


def on_page_markdown(markdown: str, page: Any, **_: Any) -> str:
    """MkDocs hook: fill the parameter reference page's markers."""
    return parameters_page(markdown) if page.file.src_uri == PAGE else markdown

"""Docstrings written for Sphinx, read on the Python API page (reference/python-api.md): the package's
docstrings name other objects with Sphinx roles (``:func:`~truckmpc.sim.simulate```) and end a
paragraph before a literal block with ``::``, which Markdown leaves as they are. This MkDocs hook
shows a role as its code (``simulate``; with ``~``, the last part of the name) and ``::`` as ``:``.
"""

from __future__ import annotations

import re
from typing import Any

PAGE = "reference/python-api.md"
_ROLE = re.compile(r":(?:func|class|meth|mod|attr|data|exc|obj):<code>(~?)([\w.]+)</code>")
_LITERAL_BLOCK_LEAD = re.compile(r"::(</p>)")


def plain_roles(html: str) -> str:
    """The page's HTML with every Sphinx role shown as the code it names."""
    html = _ROLE.sub(lambda m: f"<code>{m.group(2).rsplit('.', 1)[-1] if m.group(1) else m.group(2)}</code>", html)
    return _LITERAL_BLOCK_LEAD.sub(r":\1", html)


def on_page_content(html: str, page: Any, **_: Any) -> str:
    """MkDocs hook: clean up the Python API page's docstrings."""
    return plain_roles(html) if page.file.src_uri == PAGE else html

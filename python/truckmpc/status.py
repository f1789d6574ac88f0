"""A transient status line with a spinner on stderr, for work that may take more than a moment."""

from __future__ import annotations

import contextlib
from collections.abc import Iterator


@contextlib.contextmanager
def status_line(text: str) -> Iterator[None]:
    """Show `text` with a spinner on stderr while the block runs, only when stderr is a terminal
    (``rich``, which typer installs; nothing without it)."""
    try:
        from rich.console import Console
    except ImportError:
        yield
        return
    console = Console(stderr=True)
    if not console.is_terminal:
        yield
        return
    with console.status(text):
        yield

"""The sweep's progress bar on stderr."""

from __future__ import annotations

import contextlib
from collections.abc import Iterator

from truckmpc.sweep.runner import ProgressHook


@contextlib.contextmanager
def progress_bar(enabled: bool = True) -> Iterator[ProgressHook | None]:
    """A progress bar with an ETA on stderr (``rich.progress``, which typer installs), as a
    :data:`ProgressHook`; None (no bar) when not ``enabled``, stderr is not a terminal or rich is
    missing."""
    try:
        from rich.console import Console
        from rich.progress import (
            BarColumn,
            MofNCompleteColumn,
            Progress,
            TextColumn,
            TimeElapsedColumn,
            TimeRemainingColumn,
        )
    except ImportError:
        enabled = False
    if not enabled:
        yield None
        return
    console = Console(stderr=True)
    if not console.is_terminal:
        yield None
        return
    columns = (
        TextColumn("sweep"),
        BarColumn(),
        MofNCompleteColumn(),
        TextColumn("runs"),
        TimeElapsedColumn(),
        TextColumn("ETA"),
        TimeRemainingColumn(),
    )
    with Progress(*columns, console=console, transient=False) as bar:
        task = bar.add_task("sweep", total=None)
        started = False

        def hook(done: int, total: int) -> None:
            nonlocal started
            if not started:  # the first call sets the total (rows resumed from an earlier run make no runs)
                bar.reset(task, total=total, completed=done)
                started = True
            bar.update(task, completed=done, total=total)

        yield hook

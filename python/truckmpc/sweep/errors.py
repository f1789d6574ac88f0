"""What a sweep raises: a bad grid or output directory, a dead worker, an interruption."""

from __future__ import annotations

from pathlib import Path

from truckmpc.errors import TruckmpcError


class SweepError(TruckmpcError):
    """A bad ``--grid`` axis, or an output directory that holds a different sweep."""


class SweepWorkerDied(RuntimeError):
    """A worker process of a parallel sweep died (killed, out of memory); finished rows are kept."""


class SweepInterrupted(KeyboardInterrupt):
    """Ctrl-C during a sweep: ``done`` of ``total`` rows are kept in ``partial_path``."""

    def __init__(self, done: int, total: int, partial_path: Path) -> None:
        super().__init__(f"{done} of {total} rows kept in {partial_path}")
        self.done, self.total, self.partial_path = done, total, partial_path

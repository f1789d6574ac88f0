"""The rows of a sweep waiting for their runs: which rows a finished run completes, and each run's
figures kept until the last row needing it is written."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from truckmpc.sweep.plan import Row

Run = tuple[str, str]
"""A run of a sweep: (controller, key), as in :attr:`~truckmpc.sweep.plan.Row.keys`."""


class Waiting:
    """The pending rows and the figures of the runs they need: how many runs each row still waits
    for, and each run's figures until the last row needing it is out."""

    def __init__(self, pending: Sequence[Row], known: Mapping[Run, dict[str, Any]]) -> None:
        self._rows = {row.index: row for row in pending}
        self._figures = dict(known)
        self._missing = dict.fromkeys(self._rows, 0)
        self._waiting: dict[Run, list[int]] = {}  # run -> the rows waiting for it
        self._users: dict[Run, int] = {}  # run -> how many pending rows need it
        for row in pending:
            for run in row.keys.items():
                self._users[run] = self._users.get(run, 0) + 1
                if run not in self._figures:
                    self._waiting.setdefault(run, []).append(row.index)
                    self._missing[row.index] += 1

    def ready(self) -> list[int]:
        """The rows that wait for no run."""
        return [index for index, missing in self._missing.items() if missing == 0]

    def finished(self, run: Run, figures: dict[str, Any]) -> list[int]:
        """Note `run`'s figures; the rows it was the last one missing of."""
        self._figures[run] = figures
        ready = []
        for index in self._waiting.pop(run, []):
            self._missing[index] -= 1
            if self._missing[index] == 0:
                ready.append(index)
        return ready

    def take(self, index: int) -> dict[str, dict[str, Any]]:
        """Controller -> figures of row `index`'s runs; runs no other pending row needs are let go."""
        row = self._rows.pop(index)
        del self._missing[index]
        runs = {name: self._figures[name, key] for name, key in row.keys.items()}
        for run in row.keys.items():
            self._users[run] -= 1
            if not self._users[run]:
                del self._users[run]
                self._figures.pop(run, None)
        return runs

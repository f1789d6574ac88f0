"""Helpers of the tests that drive `truckmpc` in another process and watch its files."""

from __future__ import annotations

import time
from collections.abc import Callable
from pathlib import Path


def wait_for(condition: Callable[[], bool], timeout_s: float) -> bool:
    """Poll `condition` every 50 ms for up to `timeout_s` seconds; whether it came true."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        if condition():
            return True
        time.sleep(0.05)
    return condition()


def data_rows(path: Path) -> int:
    """Rows after the header of the CSV at `path` (0 if it does not exist yet)."""
    try:
        return max(0, len(path.read_text().splitlines()) - 1)
    except FileNotFoundError:
        return 0

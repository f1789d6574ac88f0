"""Stopping a command on SIGINT (Ctrl-C) or SIGTERM: the same cleanup for both (the sweep's workers
stopped, its finished rows kept), then one line on stderr and exit code 128 + the signal's number
(130 for SIGINT, 143 for SIGTERM), as a shell reports a process killed by it."""

from __future__ import annotations

import contextlib
import signal
import threading
from collections.abc import Iterator
from types import FrameType

__all__ = ["Stopped", "received_signal", "stopping_on_signals"]

_received: int | None = None


class Stopped(Exception):
    """A command stopped by a signal: ``str()`` is its one line (``terminated: ...`` for SIGTERM,
    ``interrupted: ...`` for SIGINT), ``exit_code`` is 128 + the signal's number."""

    def __init__(self, detail: str, signum: int | None = None) -> None:
        self.signum = signal.SIGINT if signum is None else signum
        verb = "terminated" if self.signum == signal.SIGTERM else "interrupted"
        super().__init__(f"{verb}: {detail}")
        self.exit_code = 128 + int(self.signum)


def received_signal() -> int | None:
    """The signal that stopped the current :func:`stopping_on_signals` block, if one came."""
    return _received


def _raise_interrupt(signum: int, frame: FrameType | None) -> None:
    global _received
    if _received is not None:  # a second signal while the first one's cleanup runs: let it finish
        return
    _received = signum
    raise KeyboardInterrupt


@contextlib.contextmanager
def stopping_on_signals() -> Iterator[None]:
    """Within the block SIGINT and SIGTERM raise ``KeyboardInterrupt`` in the main thread (SIGTERM
    would otherwise kill this process at once, leaving the sweep's workers running), and
    :func:`received_signal` tells which came. Outside the main thread the handlers stay as they are."""
    global _received
    _received = None
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = {signum: signal.signal(signum, _raise_interrupt) for signum in (signal.SIGINT, signal.SIGTERM)}
    try:
        yield
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, handler)

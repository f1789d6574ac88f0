"""Where a sweep's runs go: a Dask cluster, either embedded (a ``LocalCluster`` of worker processes
on this machine, started for the sweep and stopped after it) or running already, reached by its
scheduler's address (``--scheduler``, ``TRUCKMPC_SCHEDULER``: ``dask scheduler`` and ``dask worker``
by hand, or dask-jobqueue on a batch system).

Workers are processes with one thread each: the Rust core releases the GIL, but the Python around
it does not. The embedded cluster's workers ignore Ctrl-C (it reaches the whole process group): the
sweep, in this process, stops them.
"""

from __future__ import annotations

import contextlib
import importlib.util
import logging
import os
import signal
import threading
from collections.abc import Iterator
from typing import TYPE_CHECKING

from truckmpc.sweep.errors import SweepError

if TYPE_CHECKING:
    from distributed import Client, LocalCluster

SCHEDULER_ENV = "TRUCKMPC_SCHEDULER"
"""The environment variable that gives ``--scheduler``'s default."""

CONNECT_TIMEOUT_S = 10.0
"""How long to try to reach a scheduler [s] before saying it cannot be reached."""


def scheduler_address(given: str | None) -> str | None:
    """The scheduler to send runs to: `given`, else ``$TRUCKMPC_SCHEDULER``; None (or blank) for the
    embedded local cluster."""
    address = given if given is not None else os.environ.get(SCHEDULER_ENV)
    return address.strip() or None if address is not None else None


class Cluster:
    """A Dask client and, for the embedded cluster, the cluster itself; a context manager. The
    distributed library is imported only here, when runs go to workers."""

    def __init__(self, address: str | None, workers: int) -> None:
        """Connect to the scheduler at `address`, or start `workers` local worker processes."""
        from distributed import Client

        self.address, self.local = address, None
        # Dask's own log lines (a worker lost and its runs rescheduled, a slow connection), and those
        # of the event loop under it (a cancelled call when a signal stops the sweep mid-gather),
        # are kept off stderr: the sweep says in one line what matters to its user.
        # The event loop's stays silenced after the sweep: its callbacks may still run once the
        # client is closed.
        self._loggers = [logging.getLogger("distributed")]
        self._levels = [logger.level for logger in self._loggers]
        for logger in [*self._loggers, logging.getLogger("tornado.application")]:
            logger.setLevel(logging.CRITICAL)
        try:
            if address is None:
                self.local = _local_cluster(workers)
                self.client: Client = Client(self.local)
            else:
                self.client = _connect(address)
        except BaseException:
            self.close(failed=True)
            raise

    @property
    def workers(self) -> int:
        """The threads the cluster runs tasks on now (at least 1: more may join later)."""
        return max(1, int(sum(self.client.nthreads().values())))

    @property
    def dashboard(self) -> str | None:
        """The link to the scheduler's dashboard, when it serves one: a running cluster's if it says
        so; the embedded one's if bokeh, which draws it, is installed."""
        if self.local is not None and importlib.util.find_spec("bokeh") is None:
            return None
        services = self.client.scheduler_info().get("services", {})
        return str(self.client.dashboard_link) if "dashboard" in services else None

    def close(self, failed: bool = False) -> None:
        """Disconnect; stop the embedded cluster (its workers at once, mid-run, when `failed`)."""
        client, local = getattr(self, "client", None), self.local
        self.local = None
        try:
            if failed and local is not None:
                _terminate_workers(local)
            if client is not None:
                client.close()
            if local is not None:
                local.close(timeout=10)
        finally:
            for logger, level in zip(self._loggers, self._levels, strict=True):
                logger.setLevel(level)

    def __enter__(self) -> Cluster:
        return self

    def __exit__(self, exc_type: object, *exc: object) -> None:
        self.close(failed=exc_type is not None)


def _local_cluster(workers: int) -> LocalCluster:
    """`workers` worker processes of one thread on this machine, ignoring SIGINT; the scheduler's
    HTTP server (the dashboard, if bokeh is installed) on a free port, not on 8787, which another
    cluster may hold."""
    # distributed is loaded only when runs go to workers (start-up time)
    from distributed import LocalCluster

    with _sigint_ignored():  # the spawned workers inherit it through exec
        return LocalCluster(
            n_workers=workers,
            threads_per_worker=1,
            processes=True,
            dashboard_address=":0",
            silence_logs=logging.ERROR,
        )


def _connect(address: str) -> Client:
    """A client of the scheduler at `address`; a one-line :class:`SweepError` if it cannot be reached."""
    # distributed is loaded only when runs go to workers (start-up time)
    from distributed import Client

    try:
        return Client(address, timeout=CONNECT_TIMEOUT_S)
    except (OSError, TimeoutError, ValueError, TypeError) as err:
        reason = " ".join(str(err).split()) or type(err).__name__
        raise SweepError(f"--scheduler {address}: cannot reach a Dask scheduler there ({reason})") from None


def _terminate_workers(local: LocalCluster) -> None:
    """Stop the embedded cluster's worker processes at once, whatever they are running."""
    for nanny in list(local.workers.values()):
        process = getattr(getattr(nanny, "process", None), "process", None)
        if process is not None:
            with contextlib.suppress(Exception):
                process.terminate()


@contextlib.contextmanager
def _sigint_ignored() -> Iterator[None]:
    """SIGINT ignored within the block (in the main thread only: elsewhere it cannot be set)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)

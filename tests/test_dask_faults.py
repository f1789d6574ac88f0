"""Faults of a sweep on Dask, with real processes on 127.0.0.1: a worker killed mid-sweep (its runs
go to the other worker), the client killed mid-sweep (the same command resumes). Either way every
row is there exactly once, with the numbers of an uninterrupted run."""

from __future__ import annotations

import csv
import json
import os
import signal
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

from truckmpc import run_sweep
from truckmpc.sweep.columns import WALL_TIME_COLUMNS
from waiting import data_rows, wait_for

REPO = Path(__file__).resolve().parents[1]
ROAD = REPO / "roads" / "test-track.csv"  # 8.5 km of hills: each run below takes about a second
SWEEP = ["--road", str(ROAD), "--grid", "horizon_m=1500:3000:500", "--grid", "allow_neutral=true,false"]
SETTINGS = ["--set", "delta_kmh=0.04"]
ROWS = 8
COMMAND = [sys.executable, "-c", "from truckmpc.cli import main; main()"]
"""Columns that are measured wall times: they differ between two runs of the same row."""

pytestmark = pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="needs Linux /proc")


def untimed(path: Path) -> list[dict[str, str]]:
    with path.open(newline="", encoding="utf-8") as handle:
        return [{k: v for k, v in row.items() if k not in WALL_TIME_COLUMNS} for row in csv.DictReader(handle)]


def stop(proc: subprocess.Popen[str]) -> None:
    """End a process this test started (and its group), whatever state it is in."""
    if proc.poll() is None:
        os.killpg(proc.pid, signal.SIGKILL)
    proc.communicate(timeout=10)  # closes its pipes


@pytest.fixture(scope="module")
def reference(tmp_path_factory: pytest.TempPathFactory) -> list[dict[str, str]]:
    """The sweep run without interruption, in this process."""
    out = tmp_path_factory.mktemp("reference")
    grid = [SWEEP[3], SWEEP[5]]
    return untimed(run_sweep([ROAD], grid, out, overrides=[SETTINGS[1]], jobs=1).csv_path)


class Cluster:
    """A Dask scheduler and two worker processes (no nanny: a killed worker stays dead) on 127.0.0.1."""

    def __init__(self, where: Path) -> None:
        self.where, self.procs, self.logs = where, [], []
        self.scheduler_file = where / "scheduler.json"
        self._start("scheduler", "distributed.cli.dask_scheduler", "--host", "127.0.0.1", "--port", "0")
        if not wait_for(lambda: self.scheduler_file.exists() or self.procs[0].poll() is not None, 30):
            pytest.skip("the Dask scheduler did not start within 30 s")
        if self.procs[0].poll() is not None:
            pytest.skip(f"the Dask scheduler could not start on 127.0.0.1: {self.log('scheduler')[-300:]}")
        self.address = json.loads(self.scheduler_file.read_text())["address"]
        self.workers = [self._start(f"worker{i}", "distributed.cli.dask_worker", *self._worker_args()) for i in (0, 1)]
        registered = lambda: all("Registered to" in self.log(f"worker{i}") for i in (0, 1))  # noqa: E731
        if not wait_for(registered, 30):
            pytest.skip(f"the Dask workers did not register within 30 s: {self.log('worker0')[-300:]}")

    def _worker_args(self) -> list[str]:
        return [
            self.address,
            *("--nthreads", "1", "--no-nanny", "--host", "127.0.0.1", "--no-dashboard"),
            *("--memory-limit", "0"),
        ]

    def _start(self, name: str, module: str, *args: str) -> subprocess.Popen[str]:
        extra = ["--scheduler-file", str(self.scheduler_file), "--dashboard-address", "127.0.0.1:0"]
        extra = extra if name == "scheduler" else []
        log = (self.where / f"{name}.log").open("w")
        self.logs.append(log)
        proc = subprocess.Popen(
            [sys.executable, "-m", module, *args, *extra],
            stdout=log,
            stderr=subprocess.STDOUT,
            text=True,
            start_new_session=True,
            cwd=self.where,
        )
        self.procs.append(proc)
        return proc

    def log(self, name: str) -> str:
        return (self.where / f"{name}.log").read_text(errors="replace")

    def close(self) -> None:
        for proc in reversed(self.procs):
            stop(proc)
        for log in self.logs:
            log.close()


@pytest.fixture
def cluster(tmp_path: Path) -> Iterator[Cluster]:
    started = Cluster.__new__(Cluster)
    started.procs, started.logs = [], []
    try:
        started.__init__(tmp_path)  # type: ignore[misc]
        yield started
    finally:
        started.close()


@pytest.mark.slow
def test_a_worker_killed_mid_sweep_loses_no_row(cluster: Cluster, tmp_path: Path, reference) -> None:
    """SIGKILL one of the two workers once the first row is in: the sweep finishes on the other one,
    every row once, the same numbers as without the kill."""
    out = tmp_path / "sweep"
    args = [*COMMAND, "sweep", *SWEEP, *SETTINGS, "--scheduler", cluster.address, "--quiet", "--out", str(out)]
    proc = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
    try:
        assert wait_for(lambda: data_rows(out / "sweep.partial.csv") >= 1 or proc.poll() is not None, 60)
        assert proc.poll() is None and data_rows(out / "sweep.partial.csv") < ROWS, "finished before the kill"
        cluster.workers[0].kill()
        stdout, stderr = proc.communicate(timeout=90)
    finally:
        stop(proc)
    assert proc.returncode == 0, stderr
    assert cluster.workers[0].wait(timeout=10) == -signal.SIGKILL and cluster.workers[1].poll() is None
    said = (
        f"{ROWS + 1} runs on the Dask cluster at {cluster.address} (2 workers now)\nDask dashboard: http://127.0.0.1:"
    )
    assert stderr.startswith(said), stderr  # the MPC runs and the PI run they share
    rows = untimed(out / "sweep.csv")
    assert len(rows) == ROWS and len({(r["horizon_m"], r["allow_neutral"]) for r in rows}) == ROWS
    assert rows == reference and f"({ROWS} rows: {ROWS} MPC and 1 PI runs, 0 rows resumed)" in stdout


@pytest.mark.slow
def test_the_client_killed_mid_sweep_is_resumed(tmp_path: Path, reference) -> None:
    """SIGKILL the command and its embedded cluster once the first row is in: the same command
    again keeps the finished rows, runs the others, and gives the uninterrupted run's numbers."""
    out = tmp_path / "sweep"
    args = [*COMMAND, "sweep", *SWEEP, *SETTINGS, "--jobs", "2", "--quiet", "--out", str(out)]
    proc = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
    try:
        assert wait_for(lambda: data_rows(out / "sweep.partial.csv") >= 1 or proc.poll() is not None, 60)
        assert proc.poll() is None, "the sweep ended before it could be killed"
        os.killpg(proc.pid, signal.SIGKILL)
    finally:
        stop(proc)
    kept = data_rows(out / "sweep.partial.csv")
    assert 1 <= kept < ROWS and not (out / "sweep.csv").exists()
    again = subprocess.run(args, capture_output=True, text=True, timeout=90)
    assert again.returncode == 0, again.stderr
    # The kept rows are not run again, nor the PI run they share with the others.
    assert f"({ROWS} rows: {ROWS - kept} MPC and 0 PI runs, {kept} rows resumed)" in again.stdout
    assert untimed(out / "sweep.csv") == reference and not (out / "sweep.partial.csv").exists()

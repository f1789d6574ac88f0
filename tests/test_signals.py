"""SIGINT and SIGTERM end a command cleanly: every process it started ends, the sweep keeps its
finished rows, one line on stderr, exit 128 + the signal's number (130, 143) as a shell reports it.

Real processes: the command runs in a new session, so every process it starts shares its process
group, which is looked up in /proc after it ends.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from waiting import data_rows, wait_for

REPO = Path(__file__).resolve().parents[1]
HILL = REPO / "roads" / "hill_L500_A3.5.csv"  # 2.5 km
COMMAND = [sys.executable, "-c", "from truckmpc.cli import main; main()"]

pytestmark = pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="needs Linux /proc")


def group_members(pgid: int) -> list[int]:
    """PIDs of the live (not zombie) processes in process group `pgid`."""
    members = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            stat = (entry / "stat").read_text()
        except OSError:
            continue
        fields = stat.rsplit(")", 1)[1].split()  # after "pid (comm)": state, ppid, pgrp, ...
        if int(fields[2]) == pgid and fields[0] != "Z":
            members.append(int(entry.name))
    return members


@pytest.mark.slow
@pytest.mark.parametrize(
    ("signum", "to_group"),
    [(signal.SIGTERM, False), (signal.SIGTERM, True), (signal.SIGINT, True)],
    ids=["sigterm-to-parent", "sigterm-to-group", "sigint-to-group (Ctrl-C)"],
)
def test_a_signal_ends_the_sweep_and_its_workers_and_keeps_its_rows(tmp_path, signum, to_group):
    out = tmp_path / "sweep"
    # δ 0.005 km/h, solving every stage, makes each MPC run take seconds, so the sweep is still
    # running when the first row is in.
    grid = ["--grid", "horizon_m=1000:3000:250", "--set", "delta_kmh=0.005", "--set", "replan_m=0"]
    args = ["sweep", "--road", str(HILL), *grid]
    proc = subprocess.Popen(
        [*COMMAND, *args, "--jobs", "2", "--quiet", "--out", str(out)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
    )
    try:
        assert wait_for(lambda: data_rows(out / "sweep.partial.csv") >= 1 or proc.poll() is not None, 60)
        assert proc.poll() is None, "the sweep ended before it could be interrupted"
        assert len(group_members(proc.pid)) >= 3  # the command and its two workers
        if to_group:
            os.killpg(proc.pid, signum)
        else:
            proc.send_signal(signum)
        stdout, stderr = proc.communicate(timeout=30)  # returns once nothing holds the pipes open
        assert stdout == ""
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    assert proc.returncode == 128 + signum
    verb = "terminated" if signum == signal.SIGTERM else "interrupted"
    assert stderr.splitlines() == [stderr.strip()] and stderr.startswith(f"{verb}: ")
    assert "rows kept in" in stderr and "Traceback" not in stderr
    assert wait_for(lambda: not group_members(proc.pid), 5), "a process the sweep started survived it"
    kept = data_rows(out / "sweep.partial.csv")
    assert 1 <= kept < 9 and not (out / "sweep.csv").exists()
    assert f" {kept} of 9 rows kept" in stderr


@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGINT])
def test_a_signal_ends_simulate_with_one_line_and_no_output(tmp_path, signum):
    out = tmp_path / "run"
    proc = subprocess.Popen(
        [
            *COMMAND,
            "simulate",
            "--road",
            str(HILL),
            "--set",
            "delta_kmh=0.01",
            "--set",
            "horizon_m=3000",
            "--set",
            "replan_m=0",
            "--out",
            str(out),
        ],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
    )
    try:
        time.sleep(1.5)  # well into the runs (the MPC at δ 0.01 km/h and 3000 m, solving every stage, takes seconds)
        assert proc.poll() is None
        proc.send_signal(signum)
        stdout, stderr = proc.communicate(timeout=30)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    assert proc.returncode == 128 + signum
    verb = "terminated" if signum == signal.SIGTERM else "interrupted"
    assert stderr == f"{verb}: nothing written\n"
    assert stdout == "" and not out.exists()


@pytest.mark.slow
def test_a_signal_ends_a_whole_road_plan_within_a_stage(tmp_path):
    """The whole-road optimum's single DP solve over a 400 km road takes several seconds; a SIGTERM
    sent while it runs ends the command within a few DP stages (the solver asks between stages),
    not when the solve is done."""
    road = tmp_path / "rolling-400km.csv"
    distance = np.arange(0.0, 400_001.0, 100.0)
    altitude = 30.0 * np.sin(distance / 3000.0)
    road.write_text(
        "distance_m,altitude_m\n" + "".join(f"{d:.0f},{a:.3f}\n" for d, a in zip(distance, altitude, strict=True))
    )
    args = ["simulate", "--road", str(road), "--controller", "optimal", "--force", "--out", str(tmp_path / "run")]
    proc = subprocess.Popen(
        [*COMMAND, *args], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True
    )
    try:
        time.sleep(3.0)  # imports, the road and the work estimate take about a second; then the plan
        assert proc.poll() is None, "the plan ended before it could be interrupted"
        proc.send_signal(signal.SIGTERM)
        stdout, stderr = proc.communicate(timeout=3)  # the plan alone takes well over that
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    assert proc.returncode == 128 + signal.SIGTERM
    assert stderr == "terminated: nothing written\n" and stdout == ""

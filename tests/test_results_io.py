"""What a run writes and records: one run per output directory, file names never internal, and a
summary.json that reruns the run exactly (`simulate --replay`)."""

from __future__ import annotations

import errno
import json
import os
from pathlib import Path

import pytest
from typer.testing import CliRunner

from truckmpc.atomic import OutputDir, atomic_write_text
from truckmpc.cli import app
from truckmpc.record import WALL_CLOCK_FIELDS

ROADS = Path(__file__).resolve().parent.parent / "roads"
runner = CliRunner()


def simulate(*args: str) -> tuple[int, str, str]:
    result = runner.invoke(app, ["simulate", *args])
    return result.exit_code, result.stdout, result.stderr


def without_wall_clock(doc: dict) -> dict:
    return {
        k: without_wall_clock(v) if isinstance(v, dict) else v for k, v in doc.items() if k not in WALL_CLOCK_FIELDS
    }


def test_replay_reproduces_the_run_bit_for_bit(tmp_path: Path) -> None:
    road = str(ROADS / "crest_L1500_A4.csv")
    first, second = tmp_path / "first", tmp_path / "second"
    code, _, err = simulate(
        "--road", road, "--reverse", "--set", "mass_kg=31000", "--set", "horizon_m=800", "--out", str(first)
    )
    assert code == 0, err
    code, _, err = simulate("--replay", str(first / "summary.json"), "--out", str(second))
    assert code == 0, err
    a, b = (json.loads((d / "summary.json").read_text()) for d in (first, second))
    assert without_wall_clock(a) == without_wall_clock(b)
    assert a["run"]["settings"]["vehicle"]["mass_kg"] == 31000.0 and a["run"]["road"]["reverse"] is True
    assert a["run"]["inputs"]["overrides"] == ["mass_kg=31000", "horizon_m=800"]
    assert len(a["run"]["road"]["sha256"]) == 64 and a["run"]["program"]["name"] == "truckmpc"
    for name in ("trace-pi.csv", "trace-mpc.csv"):
        assert (first / name).read_bytes() == (second / name).read_bytes()


def test_a_summary_recorded_before_a_key_existed_replays_with_the_value_that_drove_it(tmp_path: Path) -> None:
    """`pedal_levels` came later; a summary.json without it replays as it ran, with none."""
    first, second = tmp_path / "first", tmp_path / "second"
    code, _, err = simulate("--road", str(ROADS / "hill_L500_A2.csv"), "--out", str(first))
    assert code == 0, err
    doc = json.loads((first / "summary.json").read_text())
    assert doc["run"]["settings"]["mpc"].pop("pedal_levels") == 0
    (first / "summary.json").write_text(json.dumps(doc))
    code, _, err = simulate("--replay", str(first / "summary.json"), "--out", str(second))
    assert code == 0, err
    again = json.loads((second / "summary.json").read_text())
    assert again["mpc"]["fuel_kg"] == doc["mpc"]["fuel_kg"] and again["run"]["settings"]["mpc"]["pedal_levels"] == 0


def test_replay_refuses_a_changed_road_and_extra_options(tmp_path: Path) -> None:
    road = tmp_path / "hill.csv"
    road.write_text((ROADS / "hill_L500_A2.csv").read_text())
    assert simulate("--road", str(road), "--controller", "pi", "--out", str(tmp_path / "a"))[0] == 0
    summary = str(tmp_path / "a" / "summary.json")
    code, _, err = simulate("--replay", summary, "--set", "mass_kg=1", "--out", str(tmp_path / "b"))
    assert code == 2 and "--replay" in err and "--set" in err
    lines = road.read_text().splitlines()
    distance, altitude, grade = lines[-1].split(",")
    lines[-1] = f"{distance},{float(altitude) + 0.5},{grade}"  # the last point 0.5 m higher
    road.write_text("\n".join(lines) + "\n")
    code, _, err = simulate("--replay", summary, "--out", str(tmp_path / "b"))
    assert code == 2 and err.startswith("error: ") and "sha256" in err and not (tmp_path / "b").exists()


def test_table_names_mass_set_speed_and_band(tmp_path: Path) -> None:
    code, out, _ = simulate(
        "--controller", "pi", "--set", "mass_kg=20000", "--set", "v_dec_kmh=3", "--out", str(tmp_path / "o")
    )
    assert code == 0
    assert "truck 20000 kg; v_ref 85 km/h, band 82-90 km/h" in out.splitlines()[0]


def test_an_output_directory_holds_one_run(tmp_path: Path) -> None:
    out = tmp_path / "run"
    assert simulate("--controller", "mpc", "--out", str(out))[0] == 0
    (out / "run.png").write_bytes(b"an old plot")
    assert simulate("--controller", "pi", "--out", str(out))[0] == 2  # not without --replace
    assert simulate("--controller", "pi", "--out", str(out), "--replace")[0] == 0
    assert sorted(p.name for p in out.iterdir()) == ["summary.json", "trace-pi.csv"]


def test_a_directory_with_other_files_is_refused(tmp_path: Path) -> None:
    out = tmp_path / "mine"
    out.mkdir()
    (out / "notes.txt").write_text("keep me")
    code, _, err = simulate("--controller", "pi", "--out", str(out))
    assert code == 2 and "notes.txt" in err and err.count("\n") == 1
    assert sorted(p.name for p in out.iterdir()) == ["notes.txt"]


def test_write_errors_name_the_output_not_the_staging_directory(tmp_path: Path) -> None:
    out = tmp_path / "out"
    with pytest.raises(OSError) as info, OutputDir(out, replace=True) as staging:
        raise OSError(errno.ENOSPC, "No space left on device", str(staging / "trace-pi.csv"))
    assert info.value.filename == str(out / "trace-pi.csv")
    assert [p.name for p in tmp_path.iterdir()] == []


def test_atomic_write_errors_name_the_file_not_its_temporary(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    def refuse(source: str, target: object) -> None:
        raise OSError(errno.EACCES, "Permission denied", source)

    monkeypatch.setattr(os, "replace", refuse)
    with pytest.raises(OSError) as info:
        atomic_write_text(tmp_path / "sweep.csv", "a\n")
    assert info.value.filename == str(tmp_path / "sweep.csv")


def test_plot_refuses_an_unknown_picture_format(tmp_path: Path) -> None:
    assert simulate("--controller", "pi", "--out", str(tmp_path / "run"))[0] == 0
    result = runner.invoke(app, ["plot", str(tmp_path / "run"), "--out", str(tmp_path / "x.jpg")])
    assert result.exit_code == 2 and "'.jpg'" in result.stderr and not (tmp_path / "x.jpg").exists()

"""Atomic file writing: a reader sees the old file or the new one, never a mix or a fragment."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from truckmpc.atomic import OutputDir, atomic_write_text


def _leftovers(directory: Path) -> list[str]:
    return sorted(p.name for p in directory.iterdir() if p.name.startswith("."))


def test_atomic_write_creates_and_replaces(tmp_path: Path) -> None:
    target = tmp_path / "out.csv"
    atomic_write_text(target, "a\r\nb\n")
    assert target.read_bytes() == b"a\r\nb\n"  # line endings written exactly as given
    atomic_write_text(target, "new\n")
    assert target.read_text() == "new\n"
    assert _leftovers(tmp_path) == []


def test_atomic_write_gives_normal_permissions(tmp_path: Path) -> None:
    target = tmp_path / "out.txt"
    atomic_write_text(target, "x")
    umask = os.umask(0o022)
    os.umask(umask)
    assert target.stat().st_mode & 0o777 == 0o666 & ~umask


def test_atomic_write_failure_keeps_old_file(tmp_path: Path) -> None:
    target = tmp_path / "out.txt"
    target.write_text("old")
    with pytest.raises(UnicodeEncodeError):
        atomic_write_text(target, "bad \udc80", encoding="utf-8")
    assert target.read_text() == "old"
    assert _leftovers(tmp_path) == []


def test_output_dir_publishes_on_success(tmp_path: Path) -> None:
    out = tmp_path / "results" / "run1"
    with OutputDir(out) as staging:
        assert not out.exists()
        assert staging.parent == out.parent
        (staging / "summary.json").write_text("{}")
        (staging / "plots").mkdir()
        (staging / "plots" / "speed.svg").write_text("<svg/>")
    assert (out / "summary.json").read_text() == "{}"
    assert (out / "plots" / "speed.svg").read_text() == "<svg/>"
    assert not staging.exists()
    assert _leftovers(out.parent) == []


def test_output_dir_replaces_same_names_and_keeps_others(tmp_path: Path) -> None:
    out = tmp_path / "run"
    out.mkdir()
    (out / "summary.json").write_text("old")
    (out / "notes.txt").write_text("mine")
    with OutputDir(out) as staging:
        (staging / "summary.json").write_text("new")
    assert (out / "summary.json").read_text() == "new"
    assert (out / "notes.txt").read_text() == "mine"


def test_output_dir_discards_everything_on_exception(tmp_path: Path) -> None:
    out = tmp_path / "run"
    with pytest.raises(RuntimeError, match="boom"), OutputDir(out) as staging:
        (staging / "summary.json").write_text("partial")
        raise RuntimeError("boom")
    assert not out.exists()
    assert not staging.exists()
    assert list(tmp_path.iterdir()) == []


def test_output_dir_exception_leaves_existing_results_untouched(tmp_path: Path) -> None:
    out = tmp_path / "run"
    out.mkdir()
    (out / "summary.json").write_text("previous")
    with pytest.raises(KeyboardInterrupt), OutputDir(out) as staging:
        (staging / "summary.json").write_text("partial")
        raise KeyboardInterrupt
    assert (out / "summary.json").read_text() == "previous"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run"]

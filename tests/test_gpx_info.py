"""`truckmpc road info` and `road plot`: the figures of a constructed road, and an imported road's
record of its smoothing and its raw elevation."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from truckmpc.cli import app
from truckmpc.geo.info import road_info
from truckmpc.geo.synthetic import write_fixtures
from truckmpc.roads import RoadProfile, write_road

runner = CliRunner()


@pytest.fixture(autouse=True)
def in_tmp(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    return tmp_path


def run(*args: object):
    result = runner.invoke(app, [str(a) for a in args])
    assert result.exit_code == 0, result.stderr
    return result.stdout


# 1000 m at +2 %, 1000 m flat, 1000 m at -1.5 %, 500 m flat.
LEGS_M = ((1000.0, 0.02), (1000.0, 0.0), (1000.0, -0.015), (500.0, 0.0))


def legs_road() -> RoadProfile:
    distance_m = np.concatenate([[0.0], np.cumsum([length for length, _ in LEGS_M])])
    altitude_m = np.concatenate([[0.0], np.cumsum([length * grade for length, grade in LEGS_M])])
    return RoadProfile("legs", distance_m, altitude_m)


def test_the_figures_of_a_constructed_road():
    info = road_info(legs_road())
    length_m = sum(length for length, _ in LEGS_M)
    assert info.length_m == length_m
    assert info.climb_m == pytest.approx(sum(a * g for a, g in LEGS_M if g > 0))
    assert info.descent_m == pytest.approx(-sum(a * g for a, g in LEGS_M if g < 0))
    shares = {(lower, upper): share for lower, upper, share in info.histogram}
    assert shares[(2.0, 3.0)] == pytest.approx(1000.0 / length_m)
    assert shares[(-1.0, 1.0)] == pytest.approx(1500.0 / length_m)
    assert shares[(-2.0, -1.0)] == pytest.approx(1000.0 / length_m)
    assert sum(shares.values()) == pytest.approx(1.0)
    # two 500 m stretches at +2 % fill the climb; any other would overlap them or climb nothing
    assert [(a, b) for a, b, _ in info.climbs] == [(0.0, 500.0), (500.0, 1000.0)]
    assert [g for _, _, g in info.climbs] == pytest.approx([0.02, 0.02])
    assert info.descents[0][2] == pytest.approx(-0.015)
    assert 2000.0 <= info.descents[0][0] <= 2500.0


def test_road_info_prints_them(in_tmp):
    write_road(legs_road(), in_tmp / "legs.csv")
    lines = run("road", "info", "legs.csv").splitlines()
    assert lines[0] == "road legs: 3.500 km, 5 points"
    assert lines[1] == "climb 20.0 m, descent 15.0 m"
    assert lines[2] == "grade -1.50 % to +2.00 %"
    assert any(line.split() == ["2", "to", "3", "%", f"{100 * 1000 / 3500:.1f}", "%", "#" * 14] for line in lines)
    assert "steepest climbs over 500 m: km 0.00-0.50 +2.00 %, km 0.50-1.00 +2.00 %" in "\n".join(lines)
    assert lines[-1] == "import: none recorded (not made by truckmpc road import)"


def test_an_imported_road_tells_its_smoothing(in_tmp):
    (track,) = write_fixtures(legs_road(), in_tmp, [2.0], seed=5)
    printed = run("road", "import", "gpx", track, "-o", "road.csv").splitlines()
    notes = [line.strip() for line in printed[1:]]
    assert any(note.startswith("smoothing: spline, cubic smoothing spline of bandwidth") for note in notes)
    info = run("road", "info", "road.csv").splitlines()
    assert [line.strip() for line in info[info.index("import:") + 1 :]] == notes
    direct = run("road", "info", track).splitlines()  # a GPX file directly: imported with the defaults
    assert [line.strip() for line in direct[direct.index("import:") + 1 :]] == notes


@pytest.mark.parametrize("source", ["road.csv", "track.gpx", "plain.csv"])
def test_road_plot_writes_a_png(in_tmp, source):
    (track,) = write_fixtures(legs_road(), in_tmp, [2.0], seed=5)
    track.rename(in_tmp / "track.gpx")
    run("road", "import", "gpx", "track.gpx", "-o", "road.csv")
    write_road(legs_road(), in_tmp / "plain.csv")
    printed = run("road", "plot", source, "-o", "picture.png")
    assert printed.strip() == "wrote picture.png"
    png = (in_tmp / "picture.png").read_bytes()
    assert png.startswith(b"\x89PNG") and len(png) > 10_000


def test_road_plot_writes_into_out_by_default_never_beside_the_road(in_tmp):
    (in_tmp / "roads").mkdir()
    write_road(legs_road(), in_tmp / "roads" / "plain.csv")
    printed = run("road", "plot", "roads/plain.csv", "--svg")
    assert printed.strip() == f"wrote {Path('out/plain.png')}, {Path('out/plain.svg')}"
    assert (in_tmp / "out" / "plain.png").stat().st_size > 0 and (in_tmp / "out" / "plain.svg").stat().st_size > 0
    assert sorted(p.name for p in (in_tmp / "roads").iterdir()) == ["plain.csv"]

"""Malformed tracks: every one ends `truckmpc road import` (and any command reading a road) with one
line `error: FILE:LINE: ...` (or the file and point), exit code 2, no traceback and no output file."""

from __future__ import annotations

import pytest
from typer.testing import CliRunner

from gps_tracks import gpx_text, meridian_points, point_xml
from truckmpc.cli import app

runner = CliRunner()
T0, T1, T2 = "2024-05-06T08:00:00Z", "2024-05-06T08:00:01Z", "2024-05-06T08:00:02Z"


@pytest.fixture(autouse=True)
def in_tmp(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    return tmp_path


def trkpts(*points: tuple[float, float, float | None, str | None]) -> str:
    return gpx_text([point_xml("trkpt", *p) for p in points])


# The first point of gpx_text() is on line 5.
BAD_GPX = {
    "missing elevation": (
        trkpts((57.0, 11.0, 10.0, None), (57.001, 11.0, 11.0, None), (57.002, 11.0, None, None)),
        ["bad.gpx:7:", "expected an elevation on every point", "point 3", "1 of 3 track points"],
    ),
    "single point": (trkpts((57.0, 11.0, 10.0, None)), ["bad.gpx:", "at least two track points, got 1"]),
    "duplicate timestamps": (
        trkpts((57.0, 11.0, 10.0, T0), (57.001, 11.0, 10.0, T1), (57.002, 11.0, 10.0, T1), (57.003, 11.0, 10.0, T2)),
        ["bad.gpx:7:", "later than the previous one (2024-05-06T08:00:01Z)", "got the same time"],
    ),
    "time going back": (
        trkpts((57.0, 11.0, 10.0, T1), (57.001, 11.0, 10.0, T0)),
        ["bad.gpx:6:", "got an earlier time 2024-05-06T08:00:00Z"],
    ),
    "zero-length segment": (
        trkpts((57.0, 11.0, 10.0, None), (57.001, 11.0, 10.0, None), (57.001, 11.0, 10.5, None)),
        ["bad.gpx:7:", "got the same position", "zero-length segment"],
    ),
    "latitude out of range": (
        trkpts((57.0, 11.0, 10.0, None), (95.0, 11.0, 10.0, None)),
        ["bad.gpx:6:", "latitude within +-90 deg, got 95"],
    ),
    "not GPX": (
        '<?xml version="1.0"?>\n<kml xmlns="http://www.opengis.net/kml/2.2"><Document/></kml>\n',
        ["bad.gpx:", "expected a GPX file (root element <gpx>), got <kml>"],
    ),
    "not XML": ("lat,lon,ele\n57,11,10\n", ["bad.gpx:1:", "expected well-formed XML"]),
    "broken XML": (
        gpx_text(meridian_points(57.0, 57.01, 3)).replace("</trkpt>", "", 1),
        ["bad.gpx:8:", "expected well-formed XML, got mismatched tag"],  # where the parser notices
    ),
    "no points": (
        '<gpx version="1.1"><wpt lat="57" lon="11"><ele>3</ele></wpt></gpx>',
        ["bad.gpx:", "expected track points (<trkpt>) or route points (<rtept>), got none"],
    ),
    "bad coordinate": (
        gpx_text(['<trkpt lat="fifty" lon="11"><ele>1</ele></trkpt>']),
        ["bad.gpx:", "expected valid GPX", "fifty"],
    ),
}

BAD_CSV = {
    "missing elevation": ("lat,lon,ele\n57.0,11.0,10\n57.001,11.0,\n", ["bad.csv:3:", "expected an elevation"]),
    "no header": ("57.0,11.0,10\n57.001,11.0,11\n", ["bad.csv:1:", "one column each of lat, lon and ele"]),
    "not a number": ("lat,lon,ele\n57.0,11.0,10\n57.001,east,11\n", ["bad.csv:3:", "column 'lon'", "'east'"]),
    "short row": ("lat,lon,ele\n57.0,11.0,10\n57.001,11.0\n", ["bad.csv:3:", "expected 3 columns, got 2"]),
    "single row": ("lat,lon,ele\n57.0,11.0,10\n", ["bad.csv:", "at least two table rows, got 1"]),
    "empty": ("# nothing\n", ["bad.csv:", "expected a header"]),
}


def assert_one_line_error(result, words: list[str]) -> None:
    assert result.exit_code == 2, result.stdout
    lines = result.stderr.splitlines()
    assert len(lines) == 1, result.stderr
    assert lines[0].startswith("error: ")
    for word in words:
        assert word in lines[0], lines[0]
    assert "Traceback" not in result.stdout + result.stderr


@pytest.mark.parametrize("case", list(BAD_GPX))
def test_a_malformed_gpx_gives_one_error_line(in_tmp, case):
    text, words = BAD_GPX[case]
    (in_tmp / "bad.gpx").write_text(text)
    assert_one_line_error(runner.invoke(app, ["road", "import", "gpx", "bad.gpx", "-o", "road.csv"]), words)
    assert not (in_tmp / "road.csv").exists()


@pytest.mark.parametrize("case", list(BAD_CSV))
def test_a_malformed_table_gives_one_error_line(in_tmp, case):
    text, words = BAD_CSV[case]
    (in_tmp / "bad.csv").write_text(text)
    assert_one_line_error(runner.invoke(app, ["road", "import", "csv", "bad.csv", "-o", "road.csv"]), words)
    assert not (in_tmp / "road.csv").exists()


@pytest.mark.parametrize("command", [["road", "info"], ["road", "plot"], ["simulate", "--controller", "pi", "--road"]])
def test_commands_reading_a_road_give_the_same_error_for_a_gpx(in_tmp, command):
    text, words = BAD_GPX["missing elevation"]
    (in_tmp / "bad.gpx").write_text(text)
    assert_one_line_error(runner.invoke(app, [*command, "bad.gpx"]), words)


def test_a_step_finer_than_the_track_is_refused(in_tmp):
    (in_tmp / "track.gpx").write_text(gpx_text(meridian_points(57.0, 57.01, 51)))  # 22 m apart
    result = runner.invoke(app, ["road", "import", "gpx", "track.gpx", "-o", "road.csv", "--step-m", "5"])
    assert_one_line_error(result, ["track.gpx: step: expected at least the median point spacing 22.2", "got 5"])


def test_a_missing_file_gives_one_error_line(in_tmp):
    assert_one_line_error(runner.invoke(app, ["road", "import", "gpx", "none.gpx", "-o", "x.csv"]), ["none.gpx"])

"""VECTO driving cycles (.vdri): units, comments, altitude from grade, target speeds, stops, the
`road import vdri` command and its one-line errors."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from truckmpc.cli import app
from truckmpc.errors import RoadError
from truckmpc.roads import Stop, load_road
from truckmpc.roads.vdri import read_vdri

REPO = Path(__file__).resolve().parents[1]
LONG_HAUL = REPO / ".." / "shared" / "roads" / "raw" / "vecto-longhaul-2015.vdri"
needs_long_haul = pytest.mark.skipif(
    not LONG_HAUL.is_file(), reason="../shared/roads/raw/vecto-longhaul-2015.vdri absent"
)
runner = CliRunner()

# Distances in km, speeds in m/s (20 m/s = 72 km/h, 15 m/s = 54 km/h), an auxiliary column to ignore;
# a stop at the start and one at 0.5 km, each followed by a launch row (v = 0), and an approach row
# (v = 0, no stop) at 0.45 km.
CYCLE = """# a generated test cycle
<s> [km], <v> [m/s], <grad> [%], <stop> [s], <Aux_fan> [kW]

0,0,1.0,3,5      # the start: a stop, then the launch
0.1,20,2.0,0,5
0.4,20,-1.5,0,5
0.45,0,-3.0,0,5  # approach
# a comment line between rows
0.5,0,0.5,30,5
0.55,15,0,0,5
0.9,15,0,0,5
"""
DISTANCE_M = [0.0, 100.0, 400.0, 450.0, 500.0, 550.0, 900.0]
# The integral of the grades: +1 % over 100 m, +2 % over 300 m, -1.5 %, -3 % and +0.5 % over 50 m each, flat.
ALTITUDE_M = [0.0, 1.0, 7.0, 6.25, 4.75, 5.0, 5.0]
# Launch and approach take the leg's next (at its end: previous) non-zero target; the last point the last segment's.
TARGETS_KMH = [72.0, 72.0, 72.0, 72.0, 54.0, 54.0, 54.0]
STOPS = (Stop(0.0, 3.0), Stop(500.0, 30.0))


@pytest.fixture
def cycle(tmp_path: Path) -> Path:
    path = tmp_path / "cycle.vdri"
    path.write_text(CYCLE)
    return path


def test_a_cycle_reads_into_distance_altitude_targets_and_stops(cycle: Path) -> None:
    road = read_vdri(cycle)
    assert road.name == "cycle" and road.source == str(cycle)
    np.testing.assert_allclose(road.distance_m, DISTANCE_M)
    np.testing.assert_allclose(road.altitude_m, ALTITUDE_M, atol=1e-12)
    np.testing.assert_allclose(road.target_speed_kmh, TARGETS_KMH)
    assert road.stops == STOPS


def test_load_road_reads_a_vdri_by_its_suffix(cycle: Path) -> None:
    road = load_road(cycle)
    assert road.stops == STOPS and road.sha256() == read_vdri(cycle).sha256()


def test_units_default_when_not_given(tmp_path: Path) -> None:
    """Without brackets <s> is in m, <v> in km/h; without <grad> and <stop> the road is flat and has no stops."""
    path = tmp_path / "plain.vdri"
    path.write_text("<s>,<v>\n0,80\n250,60\n500,60\n")
    road = read_vdri(path)
    np.testing.assert_array_equal(road.distance_m, [0, 250, 500])
    np.testing.assert_array_equal(road.altitude_m, [0, 0, 0])
    np.testing.assert_array_equal(road.target_speed_kmh, [80, 60, 60])
    assert road.stops == ()


def test_import_writes_a_csv_that_reads_back_as_the_cycle(cycle: Path, tmp_path: Path) -> None:
    out = tmp_path / "cycle.csv"
    result = runner.invoke(app, ["road", "import", "vdri", str(cycle), "-o", str(out)])
    assert result.exit_code == 0, result.stderr
    lines = result.stdout.splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"wrote {out} ")
    for words in ("0.90 km", "2 stop-free legs", "2 stops (33 s", "54, 72 km/h"):
        assert words in lines[0], lines[0]
    text = out.read_text()
    assert str(cycle) in text and "# stop_s [s]" in text and "# target_speed_kmh [km/h]" in text
    back, original = load_road(out), read_vdri(cycle)
    np.testing.assert_allclose(back.distance_m, original.distance_m)
    np.testing.assert_allclose(back.altitude_m, original.altitude_m, atol=1e-6)
    np.testing.assert_array_equal(back.target_speed_kmh, original.target_speed_kmh)
    assert back.stops == original.stops


HEADER = "<s> [m],<v> [km/h],<grad> [%],<stop> [s]\n"


@pytest.mark.parametrize(
    ("text", "line", "words"),
    [
        ("# cycle\ndistance,speed\n0,60\n100,60\n", 2, ["<s>", "<v>", "missing"]),
        (HEADER + "0,60,0,0\n100,abc,0,0\n", 3, ["column <v>", "expected a number", "'abc'"]),
        ("<s> [m],<v> [mph],<grad> [%],<stop> [s]\n0,60,0,0\n100,60,0,0\n", 1, ["<v>", "[km/h] or [m/s]", "[mph]"]),
        ("<s> [m],<v>,<grad> [deg],<stop>\n0,60,0,0\n100,60,0,0\n", 1, ["<grad>", "[%]", "[deg]"]),
        (HEADER + "0,60,0,0\n100,60,0,0\n# back\n50,60,0,0\n", 5, ["column <s>", "more than", "100 m", "50 m"]),
        (HEADER + "0,60,0,0\n100,0,0,0\n200,60,0,0\n300,60,0,0\n", 3, ["<v>", "stop time > 0", "got 0"]),
        (HEADER + "0,60,40,0\n100,60,0,0\n", 2, ["<grad>", "30 %", "40 %"]),
        (HEADER + "0,60,0,-1\n100,60,0,0\n", 2, ["<stop>", ">= 0 s"]),
    ],
    ids=["header", "not-a-number", "speed-unit", "grade-unit", "decreasing", "zero-without-stop", "steep", "stop"],
)
def test_a_malformed_cycle_is_one_error_line_naming_file_and_line(
    tmp_path: Path, text: str, line: int, words: list[str]
) -> None:
    path = tmp_path / "bad.vdri"
    path.write_text(text)
    with pytest.raises(RoadError) as info:
        read_vdri(path)
    message = str(info.value)
    assert message.startswith(f"{path}:{line}: ") and "\n" not in message
    for word in words:
        assert word in message, message
    result = runner.invoke(app, ["road", "import", "vdri", str(path), "-o", str(tmp_path / "out.csv")])
    assert result.exit_code == 2
    assert result.stderr.splitlines() == [f"error: {message}"]
    assert "Traceback" not in result.stdout + result.stderr
    assert not (tmp_path / "out.csv").exists()


def test_a_missing_cycle_is_one_error_line(tmp_path: Path) -> None:
    result = runner.invoke(app, ["simulate", "--road", str(tmp_path / "none.vdri"), "--controller", "pi"])
    assert result.exit_code == 2
    assert result.stderr.splitlines() == [f"error: {tmp_path / 'none.vdri'}: no such file"]


def test_simulate_a_cycle_says_its_stops_are_not_simulated(cycle: Path, tmp_path: Path) -> None:
    out = tmp_path / "run"
    result = runner.invoke(app, ["simulate", "--road", str(cycle), "--controller", "pi,pcc", "--out", str(out)])
    assert result.exit_code == 0, result.stderr
    notes = [line for line in result.stdout.splitlines() if line.startswith("stops not simulated")]
    assert len(notes) == 1 and "2 stops (33 s)" in notes[0] and "2 stop-free legs" in notes[0]
    doc = json.loads((out / "summary.json").read_text())
    assert [len(doc[name]["legs"]) for name in ("pi", "pcc")] == [2, 2]
    assert doc["pi"]["stops_not_simulated"]["count"] == 2
    assert "pi_target_offset_kmh" in doc["equal_time"]  # the equal-time pi moved its target offset


@needs_long_haul
def test_the_long_haul_cycle_has_its_six_stops_and_no_zero_target() -> None:
    """The stops of VECTO's long-haul cycle (2 s at both ends, 60 s at four places between); the
    launch after the stop at 899 m (target 0 in the file up to 1029 m) takes the 60 km/h after it."""
    road = load_road(LONG_HAUL)
    assert road.length_m == 108191.0
    assert [(stop.distance_m, stop.duration_s) for stop in road.stops] == [
        (0.0, 2.0),
        (899.0, 60.0),
        (2249.0, 60.0),
        (105941.0, 60.0),
        (107291.0, 60.0),
        (108191.0, 2.0),
    ]
    assert road.target_speed_kmh is not None and np.all(road.target_speed_kmh > 0)
    assert road.target_speed_at(np.array([900.0]))[0] == 60.0

"""Road profiles: CSV reading and writing, the shared measured roads, generated sections."""

from __future__ import annotations

import hashlib
import re
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from truckmpc import load_run_config, simulate
from truckmpc.errors import RoadError
from truckmpc.roads import (
    RoadProfile,
    Stop,
    concatenate,
    default_test_track,
    load_road,
    make_section,
    shipped_roads,
    write_road,
    write_shipped_roads,
)

REPO = Path(__file__).resolve().parents[1]
SHARED_ROADS = REPO / ".." / "shared" / "roads"
needs_shared = pytest.mark.skipif(
    not SHARED_ROADS.is_dir(), reason="shared road profiles (../shared/roads) not present"
)


def write(tmp_path: Path, text: str, name: str = "road.csv") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def road_error(path: Path, *parts: str) -> str:
    with pytest.raises(RoadError) as info:
        load_road(path)
    message = str(info.value)
    assert "\n" not in message
    assert message.startswith(str(path))
    for part in parts:
        assert part in message, message
    return message


# --- reading --------------------------------------------------------------------------------


def test_altitude_file_slopes_are_differenced(tmp_path: Path) -> None:
    path = write(
        tmp_path, "# a comment\n\ndistance_m,altitude_m,note\n100,10,a\n# mid-file comment\n200,12,b\n\n400,11,c\n"
    )
    road = load_road(path)
    assert road.name == "road" and road.source == str(path)
    np.testing.assert_array_equal(road.distance_m, [100, 200, 400])  # starts where the file starts
    np.testing.assert_allclose(road.slope, [0.02, -0.005])
    assert road.length_m == 300


def test_grade_file_is_integrated(tmp_path: Path) -> None:
    road = load_road(write(tmp_path, "distance_m,grade\n0,0.01\n100,-0.02\n150,0.05\n"))
    np.testing.assert_allclose(road.altitude_m, [0.0, 1.0, 0.0])  # the last row's grade is unused...
    np.testing.assert_allclose(road.slope, [0.01, -0.02])


def test_altitude_wins_over_grade(tmp_path: Path) -> None:
    road = load_road(write(tmp_path, "grade,distance_m,altitude_m\n0.5,0,0\n0.5,100,1\n"))
    np.testing.assert_allclose(road.slope, [0.01])


def test_the_core_drives_the_profile_it_was_given(tmp_path: Path) -> None:
    """A closed-loop run over the core's copy of the road covers the profile's 300 m, and its
    altitude ends where the profile's does (2 m up, then 4 m down)."""
    road = load_road(write(tmp_path, "distance_m,altitude_m\n0,0\n100,2\n300,-2\n"))
    trace = simulate(road, load_run_config(), "pi").trace
    assert trace["distance_m"][-1] == pytest.approx(300.0, abs=1.0)
    assert trace["altitude_m"][-1] == pytest.approx(-2.0, abs=0.05)


BAD_FILES = [
    ("", ["no header line"]),
    ("# only comments\n", ["no header line"]),
    ("distance,altitude_m\n0,0\n1,0\n", [":1:", "distance_m"]),
    ("distance_m,height\n0,0\n1,0\n", [":1:", "altitude_m and/or grade"]),
    ("0,0\n1,0\n", [":1:", "expected a header"]),
    ("distance_m,grade\n0,0\n25,0\n50,abc\n", [":4: column 'grade': expected a number, got 'abc'"]),
    ("distance_m,altitude_m\n0,0\n25,nan\n", [":3: column 'altitude_m': expected a finite number"]),
    ("distance_m,altitude_m\n0,0\ninf,1\n", [":3: column 'distance_m'", "finite"]),
    ("distance_m,altitude_m\n0,0\n25\n", [":3: expected 2 columns, got 1"]),
    ("distance_m,altitude_m\n0,0\n25,0,1\n", [":3: expected 2 columns, got 3"]),
    ("distance_m,altitude_m\n0,0\n25,0\n25,1\n", [":4: column 'distance_m'", "more than the previous row's 25"]),
    ("distance_m,altitude_m\n0,0\n25,0\n20,1\n", [":4:", "distance_m"]),
    ("distance_m,altitude_m\n0,0\n", ["at least two data rows, got 1"]),
    ("distance_m,grade\n0,0\n25,0.31\n50,0\n", [":3: column 'grade': expected |grade| <= 0.3"]),
    ("distance_m,altitude_m\n0,0\n25,0\n50,-10\n", [":4: column 'altitude_m'", "-0.4", "<= 0.3"]),
]


@pytest.mark.parametrize(("text", "parts"), BAD_FILES)
def test_bad_file(tmp_path: Path, text: str, parts: list[str]) -> None:
    road_error(write(tmp_path, text), *parts)


def test_missing_file(tmp_path: Path) -> None:
    road_error(tmp_path / "nope.csv", "no such file")


@needs_shared
@pytest.mark.parametrize("path", sorted(SHARED_ROADS.glob("*.csv")), ids=lambda p: p.name)
def test_shared_roads_load(path: Path) -> None:
    road = load_road(path)
    readme = (SHARED_ROADS / "README.md").read_text()
    row = next(line for line in readme.splitlines() if f"`{path.name}`" in line)
    length_km = float(re.search(r"\|\s*([\d.]+) km\s*\|", row).group(1))  # type: ignore[union-attr]
    assert road.length_m / 1000 == pytest.approx(length_km, rel=0.01)
    assert 0.01 < np.max(np.abs(road.slope)) < 0.10  # real roads: some grade, nothing absurd
    road.core()


@needs_shared
@pytest.mark.parametrize("path", sorted(SHARED_ROADS.glob("*.csv")), ids=lambda p: p.name)
def test_shared_roads_grade_is_the_segment_slope(path: Path) -> None:
    """The shared files carry both columns; their grade is the slope of the segment starting at the
    row, which integrates to the altitude column (to its 1 mm rounding, accumulated)."""
    rows = [line.split(",") for line in path.read_text().splitlines() if line and not line.startswith("#")][1:]
    grade = np.array([float(row[2]) for row in rows])
    road = load_road(path)
    integrated = np.concatenate([[0.0], np.cumsum(grade[:-1] * np.diff(road.distance_m))])
    assert np.max(np.abs(integrated - road.altitude_m)) < 0.05


# --- transformations ------------------------------------------------------------------------


def test_reversed_twice_is_original() -> None:
    road = make_section("hill", 500, 3.5)
    back = road.reversed()
    assert back.name == "hill_L500_A3.5-reversed"
    np.testing.assert_allclose(back.slope, -road.slope[::-1], atol=1e-12)  # the ascent becomes a descent
    again = back.reversed()
    assert again.name == road.name
    np.testing.assert_allclose(again.distance_m, road.distance_m, atol=1e-9)
    np.testing.assert_array_equal(again.altitude_m, road.altitude_m)


def test_reversed_keeps_the_distance_range() -> None:
    road = RoadProfile("r", np.array([100.0, 150.0, 400.0]), np.array([0.0, 1.0, 3.0]))
    back = road.reversed()
    np.testing.assert_allclose(back.distance_m, [100.0, 350.0, 400.0])
    np.testing.assert_allclose(back.altitude_m, [3.0, 1.0, 0.0])


def test_resampled_keeps_altitude_at_common_points() -> None:
    road = make_section("crest", 1500, 4.0)  # points every 25 m
    fine = road.resampled(5.0)
    assert fine.distance_m[0] == road.distance_m[0] and fine.distance_m[-1] == road.distance_m[-1]
    common = np.intersect1d(fine.distance_m, road.distance_m)
    assert common.size == road.distance_m.size
    np.testing.assert_allclose(
        np.interp(common, fine.distance_m, fine.altitude_m), np.interp(common, road.distance_m, road.altitude_m)
    )
    coarse = road.resampled(40.0)
    assert np.all(np.diff(coarse.distance_m) <= 40.0 + 1e-9) and coarse.length_m == road.length_m
    with pytest.raises(RoadError, match="resampling step"):
        road.resampled(0.0)


def test_profile_arrays_are_read_only() -> None:
    road = make_section("flat", 100)
    with pytest.raises(ValueError):
        road.altitude_m[0] = 1.0


@pytest.mark.parametrize(
    ("distance", "altitude", "match"),
    [
        ([0.0], [0.0], "at least two points"),
        ([0.0, 0.0], [0.0, 0.0], "strictly increasing"),
        ([0.0, 1.0], [0.0, 0.5], "exceeds"),
    ],
)
def test_profile_checks_its_points(distance: list[float], altitude: list[float], match: str) -> None:
    with pytest.raises(RoadError, match=match):
        RoadProfile("bad", np.array(distance), np.array(altitude))


# --- writing --------------------------------------------------------------------------------


def test_write_format(tmp_path: Path) -> None:
    road = RoadProfile("r", np.array([0.0, 10.0, 30.0]), np.array([0.0, 0.1, -0.1]))
    path = tmp_path / "r.csv"
    write_road(road, path, comments=["made by a test", "second\nthird"])
    assert path.read_text() == (
        "# made by a test\n# second\n# third\n"
        "distance_m,altitude_m,grade\n"
        "0.000,0.000000,0.010000\n10.000,0.100000,-0.010000\n30.000,-0.100000,-0.010000\n"
    )


def test_write_refuses_points_closer_than_resolution(tmp_path: Path) -> None:
    road = RoadProfile("r", np.array([0.0, 1.0, 1.0001]), np.array([0.0, 0.0, 0.0]))
    with pytest.raises(RoadError, match="closer than 1 mm"):
        write_road(road, tmp_path / "r.csv")


@settings(max_examples=60, deadline=None)
@given(
    start=st.floats(-1e4, 1e4),
    steps=st.lists(st.floats(0.01, 500.0), min_size=1, max_size=60),
    grades=st.data(),
)
def test_write_then_load_round_trips(
    tmp_path_factory: pytest.TempPathFactory, start: float, steps: list[float], grades: st.DataObject
) -> None:
    slope = grades.draw(st.lists(st.floats(-0.3, 0.3), min_size=len(steps), max_size=len(steps)))
    distance = np.round(start + np.concatenate([[0.0], np.cumsum(steps)]), 3)
    altitude = np.concatenate([[0.0], np.cumsum(np.array(slope) * np.diff(distance))])
    road = RoadProfile("r", distance, altitude)
    path = tmp_path_factory.mktemp("roundtrip") / "r.csv"
    write_road(road, path)
    back = load_road(path)
    np.testing.assert_allclose(back.distance_m, road.distance_m, atol=5e-4)
    np.testing.assert_allclose(back.altitude_m, road.altitude_m, atol=5e-7)


# --- stops ----------------------------------------------------------------------------------


def stopped_road() -> RoadProfile:
    """600 m with targets and stops at 200 m (30 s) and at the end (5 s)."""
    return RoadProfile(
        "stopped",
        [0.0, 200.0, 450.0, 600.0],
        [0.0, 2.0, 1.0, 1.0],
        None,
        [60.0, 80.0, 70.0, 70.0],
        (Stop(200.0, 30.0), Stop(600.0, 5.0)),
    )


@pytest.mark.parametrize(
    ("stops", "match"),
    [
        ((Stop(150.0, 30.0),), "expected it at a point"),
        ((Stop(200.0, 0.0),), "duration > 0"),
        ((Stop(450.0, 1.0), Stop(200.0, 1.0)), "increasing distance"),
        (((200.0, 30.0),), "expected Stop"),
    ],
)
def test_profile_checks_its_stops(stops: tuple, match: str) -> None:
    with pytest.raises(RoadError, match=match):
        RoadProfile("r", [0.0, 200.0, 450.0], [0.0, 0.0, 0.0], stops=stops)


def test_stops_enter_the_hash_only_when_there_are_some() -> None:
    road = stopped_road()
    plain = RoadProfile("plain", road.distance_m, road.altitude_m, target_speed_kmh=road.target_speed_kmh)
    digest = hashlib.sha256(road.distance_m.tobytes())
    digest.update(road.altitude_m.tobytes())
    digest.update(road.target_speed_kmh.tobytes())
    assert plain.sha256() == digest.hexdigest()
    assert road.sha256() != plain.sha256()


def test_reversed_and_resampled_keep_the_stops() -> None:
    road = stopped_road()
    assert road.reversed().stops == (Stop(0.0, 5.0), Stop(400.0, 30.0))
    assert road.reversed().reversed().stops == road.stops
    resampled = road.resampled(75.0)
    assert resampled.stops == road.stops
    assert 200.0 in resampled.distance_m


def test_concatenate_moves_stops_and_merges_those_meeting_at_a_join() -> None:
    road = stopped_road()
    twice = concatenate([road, road], "twice")
    assert twice.stops == (Stop(200.0, 30.0), Stop(600.0, 5.0), Stop(800.0, 30.0), Stop(1200.0, 5.0))
    starts = RoadProfile("starts", [0.0, 100.0], [0.0, 0.0], None, [50.0, 50.0], (Stop(0.0, 7.0),))
    assert concatenate([road, starts], "joined").stops == (Stop(200.0, 30.0), Stop(600.0, 12.0))


def test_stops_round_trip_through_the_csv(tmp_path: Path) -> None:
    road = stopped_road()
    write_road(road, tmp_path / "stopped.csv")
    text = (tmp_path / "stopped.csv").read_text()
    assert (
        "distance_m,altitude_m,grade,target_speed_kmh,stop_s\n" in text
        and "\n200.000,2.000000,-0.004000,80,30\n" in text
    )
    back = load_road(tmp_path / "stopped.csv")
    assert back.stops == road.stops and back.sha256() == road.sha256()


def test_a_negative_stop_time_in_a_csv_is_an_error(tmp_path: Path) -> None:
    path = write(tmp_path, "distance_m,altitude_m,stop_s\n0,0,0\n100,0,-3\n")
    road_error(path, ":3:", "stop_s", ">= 0 s")


# --- generated sections ---------------------------------------------------------------------


@pytest.mark.parametrize(("length_m", "slope_pct"), [(500, 3.5), (300, -3.0), (1000, 2.0), (730, 1.3)])
def test_hill_geometry(length_m: float, slope_pct: float) -> None:
    road = make_section("hill", length_m, slope_pct)
    assert road.length_m == pytest.approx(500 + length_m + 1500)  # thesis: 500 m before, 1500 m after
    assert road.altitude_m[-1] == pytest.approx(length_m * slope_pct / 100)
    hill = (road.distance_m[:-1] >= 500) & (road.distance_m[:-1] < 500 + length_m)
    np.testing.assert_allclose(road.slope[hill], slope_pct / 100)
    np.testing.assert_allclose(road.slope[~hill], 0.0, atol=1e-12)
    assert np.all(np.diff(road.distance_m) <= 25.0 + 1e-9)


@pytest.mark.parametrize("slope_pct", [2.0, 4.0, 1.3])
@pytest.mark.parametrize("length_m", [1500.0, 500.0, 1010.0])
def test_crest_and_depression_geometry(length_m: float, slope_pct: float) -> None:
    a = slope_pct / 100
    crest = make_section("crest", length_m, slope_pct)
    depression = make_section("depression", length_m, -slope_pct)  # the sign is given by the kind
    for road in (crest, depression):
        assert road.length_m == pytest.approx(500 + length_m + 1000)
        assert road.altitude_m[-1] == pytest.approx(0.0, abs=1e-9)  # back to the start altitude
    assert np.max(crest.altitude_m) == pytest.approx(a * length_m / 4)
    assert np.min(depression.altitude_m) == pytest.approx(-a * length_m / 4)
    # Cells are short against the feature: the differenced slope is the mean slope over each cell,
    # so at a cell's midpoint it equals the linear law exactly.
    mid = (crest.distance_m[:-1] + crest.distance_m[1:]) / 2
    law = np.where((mid > 500) & (mid < 500 + length_m), a - 2 * a * (mid - 500) / length_m, 0.0)
    np.testing.assert_allclose(crest.slope, law, atol=1e-12)


def test_section_lead_tail_step_and_name() -> None:
    road = make_section("hill", 510, -3, lead_m=0, tail_m=90, step_m=100)
    np.testing.assert_allclose(road.distance_m, [0, 100, 200, 300, 400, 500, 510, 600])
    assert road.name == "hill_L510_A-3_lead0_tail90"
    assert make_section("crest", 1500, 2).name == "crest_L1500_A2"
    assert make_section("flat", 1000).name == "flat_L1000"
    assert make_section("flat", 1000).length_m == 1000


@pytest.mark.parametrize(
    ("args", "kwargs", "match"),
    [
        (("bump", 100, 1), {}, "unknown kind"),
        (("hill", 0, 1), {}, "length_m: expected a number > 0"),
        (("hill", 100, 31), {}, "within"),
        (("hill", 100), {}, "slope_pct"),
        (("hill", 100, 0), {}, "non-zero"),
        (("flat", 100, 2), {}, "slope_pct"),
        (("crest", 100, 2), {"lead_m": -1}, "lead_m: expected a number >= 0"),
        (("crest", 100, 2), {"tail_m": float("nan")}, "tail_m"),
        (("crest", 100, 2), {"step_m": 0}, "step_m"),
    ],
)
def test_bad_section_arguments(args: tuple, kwargs: dict, match: str) -> None:
    with pytest.raises(RoadError, match=match) as info:
        make_section(*args, **kwargs)
    assert "\n" not in str(info.value)


def test_default_test_track() -> None:
    track = default_test_track()
    assert track.name == "test-track" and track.length_m == 8500
    assert np.max(track.slope) == pytest.approx(0.035) and np.min(track.slope) == pytest.approx(-0.03)
    assert track.altitude_m[-1] == pytest.approx(17.5 - 15.0)


def test_shipped_roads_are_up_to_date(tmp_path: Path) -> None:
    """roads/ holds exactly what the generator writes; regenerate with `truckmpc road regenerate`."""
    written = write_shipped_roads(tmp_path)
    assert sorted(p.name for p in written) == sorted(shipped_roads())
    assert sorted(p.name for p in (REPO / "roads").glob("*.csv")) == sorted(shipped_roads())
    for path in written:
        assert (REPO / "roads" / path.name).read_bytes() == path.read_bytes(), path.name
        assert load_road(path).length_m == shipped_roads()[path.name].length_m
    assert set(shipped_roads()) >= {
        "hill_L500_A3.5.csv",
        "hill_L300_A-3.csv",
        "crest_L1500_A4.csv",
        "depression_L1500_A2.csv",
        "test-track.csv",
    }

"""Roads from GPS tracks: geodesic length, the clean round trip, GPX routes and segments, the
lat,lon,ele table, grades beyond the limit, and the fixtures' determinism."""

from __future__ import annotations

import math

import numpy as np
import pytest
from typer.testing import CliRunner

from gps_tracks import gpx_text, meridian_points, point_xml
from truckmpc.cli import app
from truckmpc.geo.study import grade_rms_error_pct
from truckmpc.geo.synthetic import path_points, write_fixtures
from truckmpc.roads import RoadProfile, concatenate, load_road, make_section

runner = CliRunner()
WGS84_A_M = 6378137.0
WGS84_F = 1 / 298.257223563


@pytest.fixture(autouse=True)
def in_tmp(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    return tmp_path


def run(*args: object):
    return runner.invoke(app, [str(a) for a in args])


def meridian_arc_m(lat_from_deg: float, lat_to_deg: float) -> float:
    """Length [m] of the WGS84 meridian between two latitudes: ∫ a(1−e²)/(1−e² sin²φ)^(3/2) dφ by
    Simpson's rule (independent of pyproj)."""
    e2 = WGS84_F * (2 - WGS84_F)
    phi = np.radians(np.linspace(lat_from_deg, lat_to_deg, 2001))
    radius = WGS84_A_M * (1 - e2) / (1 - e2 * np.sin(phi) ** 2) ** 1.5
    h = phi[1] - phi[0]
    return float(h / 3 * (radius[0] + radius[-1] + 4 * radius[1:-1:2].sum() + 2 * radius[2:-1:2].sum()))


def smooth_road() -> RoadProfile:
    """A road whose grade never jumps: 6 km of 15 m high waves 3 km long (grades within ±3.1 %)."""
    distance_m = np.arange(0.0, 6000.0 + 1, 25.0)
    return RoadProfile("waves", distance_m, 15.0 * np.sin(2 * np.pi * distance_m / 3000.0))


def test_one_degree_along_a_meridian_is_the_ellipsoid_arc(in_tmp):
    (in_tmp / "meridian.gpx").write_text(gpx_text(meridian_points(57.0, 58.0, 201)))
    truth_m = meridian_arc_m(57.0, 58.0)
    assert 110_600 < truth_m < 111_700
    # a sphere of the mean radius gives 111 195 m, 0.16 % short: the check tells geodesic from flat or round
    assert load_road(in_tmp / "meridian.gpx").length_m == pytest.approx(truth_m, rel=1e-6)


def test_one_degree_along_the_equator_is_a_times_the_angle(in_tmp):
    points = [point_xml("trkpt", 0.0, i / 100, 10.0) for i in range(101)]
    (in_tmp / "equator.gpx").write_text(gpx_text(points))
    assert load_road(in_tmp / "equator.gpx").length_m == pytest.approx(WGS84_A_M * math.pi / 180, rel=1e-9)


def test_a_clean_track_comes_back_as_its_road(in_tmp):
    truth = smooth_road()
    (track,) = write_fixtures(truth, in_tmp, [0.0], seed=3)
    result = run("road", "import", "gpx", track, "-o", "road.csv", "--noise-m", "0")
    assert result.exit_code == 0, result.stderr
    road = load_road("road.csv")
    assert road.length_m == pytest.approx(truth.length_m, rel=1e-4)
    assert grade_rms_error_pct(road, truth) < 0.03
    # The default smoothing (a spline for 2 m of noise) flattens waves of 3 km by 2 % (0.04 pp of
    # grade); within 350 m of either end its one-sided fit is up to 0.5 pp off.
    assert run("road", "import", "gpx", track, "-o", "smoothed.csv").exit_code == 0
    assert grade_rms_error_pct(load_road("smoothed.csv"), truth) < 0.15


def test_the_path_is_logged_at_about_one_hertz_at_80_kmh():
    distance_m, lat, lon = path_points(5000.0, np.random.default_rng(0))
    spacing_m = np.diff(distance_m)
    assert distance_m[-1] == 5000.0
    assert spacing_m[:-1].min() > 75 / 3.6 - 1e-9 and spacing_m.max() < 85 / 3.6 + 1e-9
    assert np.all(np.abs(lat - 57.7) < 0.1) and np.all(np.abs(lon - 11.97) < 0.1)


def test_fixtures_are_deterministic(in_tmp):
    road = make_section("hill", 1000, 3.0)
    first = write_fixtures(road, in_tmp / "a", [0.0, 2.0, 5.0], seed=7)
    second = write_fixtures(road, in_tmp / "b", [0.0, 2.0, 5.0], seed=7)
    other = write_fixtures(road, in_tmp / "c", [2.0], seed=8)
    assert [p.read_bytes() for p in first] == [p.read_bytes() for p in second]
    assert first[1].read_bytes() != other[0].read_bytes()


def test_route_points_are_used_when_there_is_no_track(in_tmp):
    points = [point_xml("rtept", 57.0 + i / 1000, 11.0, 10.0 + i) for i in range(20)]
    (in_tmp / "route.gpx").write_text(gpx_text(points, route=True))
    result = run("road", "import", "gpx", "route.gpx", "-o", "road.csv", "--noise-m", "0")
    assert result.exit_code == 0, result.stderr
    assert "20 route points" in result.stdout
    road = load_road("road.csv")
    rise_m = 19.0
    assert road.altitude_m[-1] - road.altitude_m[0] == pytest.approx(rise_m)


def test_track_segments_are_joined_in_file_order(in_tmp):
    first = meridian_points(57.00, 57.01, 11)
    second = meridian_points(57.011, 57.02, 10)
    text = gpx_text([*first, "</trkseg><trkseg>", *second])
    (in_tmp / "two.gpx").write_text(text)
    assert load_road("two.gpx").length_m == pytest.approx(meridian_arc_m(57.0, 57.02), rel=1e-6)


def test_a_lat_lon_ele_table_gives_the_road_of_the_same_route(in_tmp):
    lat = 57.0 + np.arange(50) / 2000
    lon = 11.0 + np.sin(np.arange(50) / 10) / 2000
    ele = 30.0 + 5 * np.sin(np.arange(50) / 8)
    rows = "\n".join(f"{a:.8f},{b:.8f},{c:.3f}" for a, b, c in zip(lat, lon, ele, strict=True))
    (in_tmp / "table.csv").write_text(f"# from a map\nlatitude,longitude,elevation\n{rows}\n")
    points = [point_xml("rtept", a, b, c) for a, b, c in zip(lat, lon, ele, strict=True)]
    (in_tmp / "route.gpx").write_text(gpx_text(points, route=True))
    assert run("road", "import", "csv", "table.csv", "-o", "a.csv").exit_code == 0
    assert run("road", "import", "gpx", "route.gpx", "-o", "b.csv").exit_code == 0
    a, b = load_road("a.csv"), load_road("b.csv")
    np.testing.assert_allclose(a.distance_m, b.distance_m, atol=1e-3)
    np.testing.assert_allclose(a.altitude_m, b.altitude_m, atol=1e-5)


def test_grades_beyond_the_limit_are_reported_not_clipped(in_tmp):
    steep = concatenate(
        [make_section("flat", 1000), make_section("hill", 400, 10.0, lead_m=0, tail_m=0), make_section("flat", 600)],
        "steep",
    )
    (track,) = write_fixtures(steep, in_tmp, [0.0], seed=1)
    result = run("road", "import", "gpx", track, "-o", "road.csv", "--noise-m", "0", "--grade-limit-pct", "8")
    assert result.exit_code == 0, result.stderr
    assert "1 sections beyond, kept as they are: km 1.0" in result.stdout
    road = load_road("road.csv")
    assert road.slope.max() == pytest.approx(0.10, abs=1e-3)
    assert "1 sections beyond" in (in_tmp / "road.csv").read_text()


def test_a_gpx_road_drives_like_any_road(in_tmp):
    (in_tmp / "hill.gpx").write_text(gpx_text(meridian_points(57.0, 57.02, 101)))
    result = run("simulate", "--road", "hill.gpx", "--controller", "pi", "--out", "out")
    assert result.exit_code == 0, result.stderr
    assert "hill" in result.stdout and (in_tmp / "out" / "summary.json").is_file()

"""Configuration files: packaged defaults equal the thesis's tables, layering works, and every bad
input gives one line naming its file (or --set key) and what was expected."""

from __future__ import annotations

from pathlib import Path

import pytest
import truckmpc._core as core
import yaml

from truckmpc import config
from truckmpc.config import (
    ConfigError,
    PiConfig,
    Section,
    default_config_path,
    load_pi,
    load_run_config,
    load_sections,
    load_sim,
    load_vehicle,
)

# Tables A.1 and A.2, with k_b = 1e5 Nm, not the printed 20e3: table B.1's brake level holding 90 km/h
# on -4 % (B = 0.0490) needs 1e5; 20e3 would need B = 0.245.
THESIS_40T = {
    "mass_kg": 40000.0,
    "engine_inertia_kgm2": 3.5,
    "cylinders": 6.0,
    "revolutions_per_stroke": 2.0,
    "torque_map_a_nm_per_rpm": -3.30e-3,
    "torque_map_b_nm_stroke_per_mg": 9.16,
    "torque_map_c_nm": -82.53,
    "fueling_max_a_mg_per_rpm2": -1.59e-4,
    "fueling_max_b_mg_per_rpm": 0.42,
    "fueling_max_c_mg": -57.05,
    "drag_torque_a_nm_per_rpm": -8.80e-2,
    "drag_torque_b_nm": -51.51,
    "idle_speed_rpm": 600.0,
    "idle_fueling_mg_per_stroke": 10.44,
    "final_drive_ratio": 3.27,
    "final_drive_efficiency": 0.97,
    "wheel_inertia_kgm2": 32.9,
    "rolling_resistance": 7e-3,
    "gravity_mps2": 9.81,
    "air_drag_coefficient": 0.6,
    "frontal_area_m2": 10.0,
    "air_density_kgpm3": 1.29,
    "wheel_radius_m": 0.52,
    "brake_torque_max_nm": 1.0e5,
    "gear_ratios": [11.27, 9.14, 7.17, 5.81, 4.62, 3.75, 3.01, 2.44, 1.91, 1.55, 1.23, 1.0],
    "gear_efficiencies": [0.88, 0.89, 0.90, 0.91, 0.92, 0.93, 0.94, 0.95, 0.96, 0.97, 0.98, 0.99],
}


def write(directory: Path, name: str, text: str) -> Path:
    path = directory / name
    path.write_text(text)
    return path


def one_line_error(match: list[str], **kwargs: object) -> str:
    """Run load_run_config expecting a ConfigError; check it is one line containing `match`."""
    with pytest.raises(ConfigError) as info:
        load_run_config(**kwargs)  # type: ignore[arg-type]
    message = str(info.value)
    assert "\n" not in message
    for part in match:
        assert part in message, message
    return message


# --- defaults -------------------------------------------------------------------------------


def test_default_vehicle_is_table_a1_a2() -> None:
    vehicle = load_vehicle()
    assert vehicle.params == THESIS_40T
    assert list(vehicle.params) == core.Vehicle.parameter_names()
    assert vehicle.source.endswith("truck-40t.yaml")
    assert vehicle.core().forward_gears == 12


def test_20t_truck_differs_only_in_mass() -> None:
    light = load_vehicle(default_config_path("truck-20t.yaml")).params
    assert light["mass_kg"] == 20000.0
    assert {k: v for k, v in light.items() if k != "mass_kg"} == {k: v for k, v in THESIS_40T.items() if k != "mass_kg"}


def test_default_pi_is_table_a3_a4() -> None:
    pi = load_pi()
    assert (pi.v_ref_kmh, pi.v_inc_kmh, pi.v_max_kmh) == (85.0, 5.0, 90.0)
    assert (pi.pedal_kp, pi.pedal_ki, pi.pedal_integrator_limit) == (1.845, 0.2, 30.0)
    assert (pi.brake_kp, pi.brake_ki, pi.brake_integrator_limit) == (0.3, 0.02, 30.0)
    assert pi.gear_down_rpm == (None,) + (1300.0,) * 11
    assert pi.gear_up_rpm == (1800.0,) * 10 + (1700.0, None)


def test_default_simulation() -> None:
    sim = load_sim()
    assert (sim.plant_dt_s, sim.trace_step_m, sim.start_speed_kmh) == (0.05, 25.0, None)


def test_run_config_defaults_and_plain_dict() -> None:
    run = load_run_config()
    assert run.pi == load_pi() and run.sim == load_sim()
    assert run.vehicle.params == THESIS_40T
    data = yaml.safe_load(yaml.safe_dump(run.as_dict()))
    assert data["pi"]["gear_up_rpm"][-1] is None
    assert data["vehicle"]["mass_kg"] == 40000.0
    assert set(data["sources"]) == {"vehicle", "pi", "mpc", "sim"}
    assert data["mpc"]["k_lim"] is None  # resolved to 200 m / S only when the kernel gets it


def test_configs_are_frozen() -> None:
    with pytest.raises(AttributeError):
        load_pi().pedal_kp = 2.0  # type: ignore[misc]


def test_unknown_packaged_config() -> None:
    with pytest.raises(ConfigError, match=r"no packaged config named 'nope\.yaml'"):
        default_config_path("nope.yaml")


# --- layering -------------------------------------------------------------------------------


def test_overlay_then_set_override(tmp_path: Path) -> None:
    first = write(tmp_path, "a.yaml", "v_ref_kmh: 80\npedal_kp: 1.0\ntrace_step_m: 10\n")
    second = write(tmp_path, "b.yaml", "pedal_kp: 1.5\n")
    run = load_run_config(config_paths=[first, second], overrides=["pedal_kp=2.5", "mass_kg=1e4"])
    assert run.pi.v_ref_kmh == 80.0 and run.pi.v_max_kmh == 85.0
    assert run.pi.pedal_kp == 2.5  # --set wins over both files
    assert load_run_config(config_paths=[first, second]).pi.pedal_kp == 1.5  # the later file wins
    assert run.sim.trace_step_m == 10.0
    assert run.vehicle.params["mass_kg"] == 1e4
    assert "--set mass_kg" in run.vehicle.source
    assert "a.yaml" in run.pi.source and "--set pedal_kp" in run.pi.source


def test_set_parses_yaml_values() -> None:
    run = load_run_config(
        overrides=[
            "start_speed_kmh=70",
            "gear_down_rpm=[null, 1200, 1200, 1200, 1200, 1200, 1200, 1200, 1200, 1200, 1200, 1200]",
        ]
    )
    assert run.sim.start_speed_kmh == 70.0
    assert run.pi.gear_down_rpm[1] == 1200.0
    assert load_run_config(overrides=["start_speed_kmh=null"]).sim.start_speed_kmh is None


@pytest.fixture
def demo_section(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    """A third section sharing v_ref_kmh with the PI controller, as the MPC section will."""
    # An absolute default_file stands in for a packaged file (pathlib joins it as itself).
    defaults = write(tmp_path, "demo.yaml", "v_ref_kmh: 85\nhorizon_m: 2000\n")
    parsers = {"v_ref_kmh": config._number(0, above=True), "horizon_m": config._number(0, above=True)}
    monkeypatch.setitem(config.SECTIONS, "demo", Section(str(defaults), parsers, lambda values, source: dict(values)))


@pytest.mark.usefixtures("demo_section")
def test_shared_key_is_set_in_every_section(tmp_path: Path) -> None:
    overlay = write(tmp_path, "o.yaml", "v_ref_kmh: 70\nhorizon_m: 500\n")
    _, sections = load_sections(config_paths=[overlay])
    assert sections["pi"].v_ref_kmh == 70.0 and sections["demo"] == {"v_ref_kmh": 70.0, "horizon_m": 500.0}
    _, sections = load_sections(overrides=["v_ref_kmh=60"])
    assert sections["pi"].v_ref_kmh == 60.0 and sections["demo"]["v_ref_kmh"] == 60.0
    assert isinstance(load_run_config(overrides=["v_ref_kmh=60"]).pi, PiConfig)


# --- bad input ------------------------------------------------------------------------------

BAD_OVERLAYS = [
    ("pedal_kp: abc\n", ["key 'pedal_kp'", "expected a number", "got 'abc'"]),
    ("pedal_kp: true\n", ["key 'pedal_kp'", "expected a number", "got true"]),
    ("pedal_ki: .nan\n", ["key 'pedal_ki'", "finite"]),
    ("plant_dt_s: .inf\n", ["key 'plant_dt_s'", "finite"]),
    ("pedal_kp: -1\n", ["key 'pedal_kp'", ">= 0"]),
    ("brake_integrator_limit: 0\n", ["key 'brake_integrator_limit'", "> 0"]),
    ("v_ref_kmh: 0\n", ["key 'v_ref_kmh'", "> 0"]),
    ("v_inc_kmh: -1\n", ["key 'v_inc_kmh'", "expected a number >= 0 (v_max = v_ref + v_inc must not be below v_ref)"]),
    ("plant_dt_s: 1.5\n", ["key 'plant_dt_s'", "(0, 1]"]),
    ("plant_dt_s: 0\n", ["key 'plant_dt_s'", "(0, 1]"]),
    ("trace_step_m: 0\n", ["key 'trace_step_m'", "> 0"]),
    ("start_speed_kmh: -5\n", ["key 'start_speed_kmh'", "> 0"]),
    ("pedal_kpp: 1\n", ["unknown key 'pedal_kpp'", "did you mean 'pedal_kp'"]),
    ("mass_kg: 1\n", ["key 'mass_kg' is a vehicle parameter"]),
    ("gear_up_rpm: [1800, 1800]\n", ["key 'gear_up_rpm'", "(12), got 2"]),
    ("gear_up_rpm: 1800\n", ["key 'gear_up_rpm'", "expected a list of engine speeds"]),
    (
        "gear_down_rpm: [1000, 1300, 1300, 1300, 1300, 1300, 1300, 1300, 1300, 1300, 1300, 1300]\n",
        ["key 'gear_down_rpm'", "null for gear 1"],
    ),
    (
        "gear_down_rpm: [null, 1900, 1300, 1300, 1300, 1300, 1300, 1300, 1300, 1300, 1300, 1300]\n",
        ["key 'gear_down_rpm'", "gear 2", "below its upshift"],
    ),
    (
        "gear_up_rpm: [1400, 1800, 1800, 1800, 1800, 1800, 1800, 1800, 1800, 1800, 1700, null]\n",
        ["key 'gear_up_rpm'", "hunt"],
    ),
    ("pedal_kp: 1\npedal_kp: 2\n", [":2:", "'pedal_kp' given twice"]),
    ("pedal_kp: [1,\n", [":2:", "invalid YAML"]),
    ("- pedal_kp\n", ["expected a mapping"]),
]


@pytest.mark.parametrize(("text", "match"), BAD_OVERLAYS)
def test_bad_overlay(tmp_path: Path, text: str, match: list[str]) -> None:
    path = write(tmp_path, "my.yaml", text)
    message = one_line_error(match, config_paths=[path])
    assert message.split(":")[0].endswith(path.name)  # names the file first


BAD_SETS = [
    ("pedal_kp=abc", ["--set pedal_kp: expected a number", "got 'abc'"]),
    ("masss_kg=3", ["--set masss_kg: unknown key", "did you mean 'mass_kg'"]),
    ("mass_kg=-1", ["--set mass_kg: expected a number > 0, got -1"]),
    ("mass_kg=yes", ["--set mass_kg: expected a number, got true"]),
    ("gear_ratios=[3, 2, 1]", ["gear_efficiencies", "(after --set gear_ratios)"]),
    ("v_inc_kmh=-2", ["--set v_inc_kmh", "must not be below v_ref"]),
    ("pedal_kp", ["--set 'pedal_kp': expected key=value"]),
    ("=3", ["expected key=value"]),
    ("pedal_kp=[1,", ["--set pedal_kp", "not valid YAML"]),
]


@pytest.mark.parametrize(("text", "match"), BAD_SETS)
def test_bad_set(text: str, match: list[str]) -> None:
    one_line_error(match, overrides=[text])


def test_missing_files() -> None:
    one_line_error(["nope.yaml: no such file"], config_paths=["nope.yaml"])
    one_line_error(["truck.yaml: no such file"], vehicle_path="truck.yaml")


def vehicle_text(**changes: object) -> str:
    params = {**THESIS_40T, **changes}
    return yaml.safe_dump({k: v for k, v in params.items() if v is not None})


BAD_VEHICLES = [
    (vehicle_text(mass_kg=-1), ["key 'mass_kg': expected a number > 0, got -1"]),
    (vehicle_text(final_drive_efficiency=1.5), ["key 'final_drive_efficiency'", "(0, 1]"]),
    (vehicle_text(gear_efficiencies=[0.9] * 11), ["key 'gear_efficiencies'", "12"]),
    (vehicle_text(gear_ratios=[1.0, 2.0]), ["key 'gear_"]),
    (vehicle_text(mass_kg="heavy"), ["key 'mass_kg': expected a number, got 'heavy'"]),
    (vehicle_text(mass_kg=True), ["key 'mass_kg': expected a number, got true"]),
    (vehicle_text(mass_kg=float("nan")), ["key 'mass_kg'", "finite"]),
    (vehicle_text(gear_ratios="fast"), ["key 'gear_ratios': expected a list of numbers"]),
    (vehicle_text(wheel_radius_m=None), ["missing key 'wheel_radius_m'", "every parameter"]),
    (vehicle_text() + "masss_kg: 3\n", ["unknown key 'masss_kg' (did you mean 'mass_kg'?)"]),
    ("", ["missing 26 keys"]),
]


@pytest.mark.parametrize(("text", "match"), BAD_VEHICLES)
def test_bad_vehicle_file(tmp_path: Path, text: str, match: list[str]) -> None:
    path = write(tmp_path, "truck.yaml", text)
    message = one_line_error(match, vehicle_path=path)
    assert message.split(":")[0].endswith(path.name)  # names the file first
    with pytest.raises(ConfigError):
        load_vehicle(path)


def test_controller_file_must_be_complete(tmp_path: Path) -> None:
    path = write(tmp_path, "pi.yaml", "pedal_kp: 1\n")
    with pytest.raises(ConfigError, match=r"pi\.yaml: missing 9 keys"):
        load_pi(path)
    with pytest.raises(ConfigError, match="unknown key 'pedal_kp'"):
        load_sim(path)


def test_config_error_is_value_error() -> None:
    with pytest.raises(ValueError):
        load_run_config(overrides=["pedal_kp=x"])

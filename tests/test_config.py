"""Configuration: the declarations carry the thesis's tables, the packaged files follow from them
(the docs site's key tables: tests/test_docs_reference.py), layering works, and every bad input
gives one line naming its file (and line) or --set key, what was expected, and the culprit the
user set last."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
import yaml

from truckmpc import _core
from truckmpc.config import (
    KEYS,
    SPECS,
    ConfigError,
    default_config_path,
    load_run_config,
    packaged_defaults,
    section_keys,
)

# Tables A.1 and A.2, with k_b = 1e5 Nm (the printed 20e3 is a misprint: tables B.1/B.2 need 1e5).
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
    run = load_run_config()
    assert dict(run.vehicle) == {k: tuple(v) if isinstance(v, list) else v for k, v in THESIS_40T.items()}
    assert list(run.vehicle) == list(THESIS_40T) == list(section_keys("vehicle"))
    assert run.core_vehicle.forward_gears == 12


def test_20t_truck_differs_only_in_mass() -> None:
    light = load_run_config(vehicle_path=default_config_path("truck-20t.yaml")).vehicle
    heavy = load_run_config().vehicle
    assert light["mass_kg"] == 20000.0
    assert {k: v for k, v in light.items() if k != "mass_kg"} == {k: v for k, v in heavy.items() if k != "mass_kg"}


def test_default_pi_and_cruise_are_table_a3_a4() -> None:
    run = load_run_config()
    assert (run.cruise.v_ref_kmh, run.cruise.v_inc_kmh, run.v_max_kmh) == (85.0, 5.0, 90.0)
    pi = run.pi
    assert (pi.pedal_kp, pi.pedal_ki, pi.pedal_integrator_limit) == (1.845, 0.2, 30.0)
    assert (pi.brake_kp, pi.brake_ki, pi.brake_integrator_limit) == (0.3, 0.02, 30.0)
    assert pi.gear_down_rpm == (None,) + (1300.0,) * 11
    assert pi.gear_up_rpm == (1800.0,) * 10 + (1700.0, None)


def test_thesis_preset_is_tables_6_1_6_2_and_simulation() -> None:
    run = load_run_config(config_paths=["thesis"])
    mpc = run.mpc
    assert (mpc.stage_m, mpc.horizon_m, mpc.delta_kmh, mpc.epsilon) == (25.0, 1500.0, 0.2, 0.1)
    assert (mpc.q_fuel, mpc.q_speed_change, mpc.q_gear_shift, mpc.q_brake) == (2.0, 15.0, 15.0, 100.0)
    assert (mpc.grid, mpc.neutral_rule, mpc.fuel_cut_arcs, mpc.on_infeasible) == ("moving", "nearest", False, "hold")
    assert (mpc.k_lim, mpc.q_speed_below, mpc.q_speed_below_per_km, mpc.q_brake_per_km) == (None, None, None, None)
    assert (run.settings.derived()["k_lim"], run.settings.derived()["q_speed_below"]) == (
        8,
        7.0,
    )  # S k_lim = 200 m; delta 0.2
    fine = load_run_config(config_paths=["thesis"], overrides=["stage_m=50", "delta_kmh=0.1"]).settings
    assert (fine.derived()["k_lim"], fine.derived()["q_speed_below"], fine.derived()["q_brake"]) == (4, 5.0, 100.0)
    assert (run.sim.plant_dt_s, run.sim.trace_step_m, run.sim.start_speed_kmh) == (0.05, 25.0, None)


def test_default_mpc_weighs_per_kilometre_what_the_thesis_weighs_per_25_m_stage() -> None:
    run = load_run_config()
    mpc = run.mpc
    assert (mpc.grid, mpc.neutral_rule, mpc.fuel_cut_arcs, mpc.epsilon) == ("fixed", "quadratic", True, None)
    assert (run.settings.derived()["q_speed_below"], run.settings.derived()["q_brake"]) == (5.0, 100.0)  # at S 25 m
    for stage_m in (12.5, 50.0):
        other = load_run_config(overrides=[f"stage_m={stage_m}"]).settings
        assert other.derived()["q_speed_below"] == pytest.approx(5.0 * stage_m / 25.0)
        assert other.derived()["q_brake"] == pytest.approx(100.0 * stage_m / 25.0)
    # A weight given per stage is used as given.
    assert load_run_config(overrides=["q_brake=7"]).settings.derived()["q_brake"] == 7.0


def test_a_brake_weight_is_needed_per_stage_or_per_kilometre() -> None:
    with pytest.raises(ConfigError, match=r"q_brake.*expected a number when q_brake_per_km is null"):
        load_run_config(overrides=["q_brake_per_km=null"])


def test_run_config_plain_dict_and_sources() -> None:
    run = load_run_config(overrides=["pedal_kp=2"])
    data = yaml.safe_load(yaml.safe_dump(run.as_dict()))
    assert data["pi"]["gear_up_rpm"][-1] is None
    assert data["vehicle"]["mass_kg"] == 40000.0
    assert data["mpc"]["k_lim"] is None  # resolved to 200 m / S only when the kernel gets it
    assert set(data) == {"vehicle", "cruise", "pi", "mpc", "pcc", "sim", "vecto", "sources"}
    assert data["sources"][0].endswith("truck-40t.yaml") and data["sources"][-1] == "--set pedal_kp"


def test_configs_are_frozen() -> None:
    with pytest.raises(AttributeError):
        load_run_config().pi.pedal_kp = 2.0


def test_unknown_packaged_config() -> None:
    with pytest.raises(ConfigError, match=r"no packaged config named 'nope\.yaml'"):
        default_config_path("nope.yaml")


# --- one declaration ------------------------------------------------------------------------


def test_packaged_files_are_the_declared_defaults() -> None:
    """Regenerate with `truckmpc config defaults` after changing a declaration."""
    for name, text in packaged_defaults().items():
        assert default_config_path(name).read_text(encoding="utf-8") == text, name


def test_every_key_has_unit_doc_and_default_within_range() -> None:
    assert len(KEYS) == len(set(KEYS)) == len(SPECS)
    for spec in SPECS:
        assert spec.unit and spec.doc and spec.expected, spec.name
        load_run_config(overrides=[f"{spec.name}={yaml.safe_dump(spec.default, default_flow_style=True).strip()}"])
    assert _core.Settings({}).values() == {spec.name: spec.default for spec in SPECS}


# --- layering -------------------------------------------------------------------------------


def test_overlay_then_set_override(tmp_path: Path) -> None:
    first = write(tmp_path, "a.yaml", "v_ref_kmh: 80\npedal_kp: 1.0\ntrace_step_m: 10\n")
    second = write(tmp_path, "b.yaml", "pedal_kp: 1.5\n")
    run = load_run_config(config_paths=[first, second], overrides=["pedal_kp=2.5", "mass_kg=1e4"])
    assert run.cruise.v_ref_kmh == 80.0 and run.v_max_kmh == 85.0
    assert run.pi.pedal_kp == 2.5  # --set wins over both files
    assert load_run_config(config_paths=[first, second]).pi.pedal_kp == 1.5  # the later file wins
    assert run.sim.trace_step_m == 10.0
    assert run.vehicle["mass_kg"] == 1e4
    assert run.origins["mass_kg"].text == "--set mass_kg"
    assert run.origins["v_ref_kmh"].text.endswith("a.yaml:1") and run.origins["pedal_kp"].text == "--set pedal_kp"


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


# --- the culprit ----------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("override", "start"),
    [
        ("v_ref_kmh=5", "--set v_ref_kmh: v_dec_kmh: expected < v_ref_kmh (5)"),
        ("stage_m=0.001", "--set stage_m: horizon_m: expected at most 100000 stages"),
        ("gear_down_rpm=[null,1300]", "--set gear_down_rpm: gear_up_rpm: expected one threshold per gear"),
        ("gear_ratios=[3, 2, 1]", "--set gear_ratios: gear_efficiencies: expected one efficiency per gear ratio (3)"),
        ("n_max_rpm=900", "--set n_max_rpm: n_min_rpm: expected n_min_rpm < n_max_rpm (900)"),
    ],
)
def test_a_cross_key_error_blames_the_key_set_last(override: str, start: str) -> None:
    message = one_line_error([start], overrides=[override])
    assert message.startswith(start) and "configs/" not in message


@pytest.mark.parametrize(("old", "new"), [("pcc_underspeed_kmh", "v_dec_kmh"), ("pcc_overspeed_kmh", "v_inc_kmh")])
def test_a_replaced_key_names_its_replacement(tmp_path: Path, old: str, new: str) -> None:
    """The PCC's own band keys are gone: a file or --set naming one says which key replaced it."""
    path = write(tmp_path, "old.yaml", f"# comment\n{old}: 6.0\n")
    message = one_line_error([f"{path.name}:2: key {old!r} was replaced by {new!r}"], config_paths=[path])
    assert "one speed band for every controller" in message and "did you mean" not in message
    one_line_error([f"--set {old}: key was replaced by {new!r}"], overrides=[f"{old}=6"])
    with pytest.raises(_core.ParamError) as info:
        _core.Settings({old: 6.0})
    assert info.value.key == old and new in info.value.expected


def test_the_band_is_vectos_and_the_thesis_keeps_its_own() -> None:
    """One band for every controller: VECTO's 8 km/h under and 5 over by default; the thesis preset
    keeps the thesis's ±5."""
    assert (load_run_config().cruise.v_dec_kmh, load_run_config().cruise.v_inc_kmh) == (8.0, 5.0)
    thesis = load_run_config(config_paths=["thesis"]).cruise
    assert (thesis.v_dec_kmh, thesis.v_inc_kmh) == (5.0, 5.0)


@pytest.mark.parametrize(
    ("override", "words"),
    [
        ("v_ref_kmh=200", ["--set v_ref_kmh", "top speed 119.90 km/h", "n_max_rpm 2000 rpm", "got 200"]),
        ("v_ref_kmh=115", ["--set v_ref_kmh", "top speed 119.90 km/h"]),
        ("v_ref_kmh=13", ["--set v_ref_kmh", "lowest usable speed 5.32 km/h", "n_min_rpm 1000 rpm", "got 13"]),
        ("v_inc_kmh=40", ["--set v_inc_kmh: v_ref_kmh: expected v_ref_kmh + v_inc_kmh (40)", "119.90 km/h"]),
        ("n_max_rpm=1400", ["--set n_max_rpm: v_ref_kmh:", "top speed 83.93 km/h"]),
    ],
)
def test_a_band_the_truck_cannot_drive_is_refused(override: str, words: list[str]) -> None:
    """Top gear at n_max_rpm (2000 rpm: 119.90 km/h for the default truck) caps v_ref + v_inc, gear 1
    at n_min_rpm (5.32 km/h) floors v_ref − v_dec; the key set last is blamed."""
    one_line_error(words, overrides=[override])


def test_the_drivable_set_speeds_follow_the_gearbox() -> None:
    """The range of drivable set speeds is the gearbox's speeds at the usable engine speeds, less
    the band: v = n · π r_w / (30 i_t i_f)."""
    config = load_run_config()
    r_w, i_f = config.vehicle.wheel_radius_m, config.vehicle.final_drive_ratio
    ratios = config.vehicle.gear_ratios
    speed_kmh = lambda n_rpm, i_t: n_rpm * math.pi * r_w / (30 * i_t * i_f) * 3.6  # noqa: E731
    lowest, highest = config.settings.derived()["v_ref_range_kmh"]
    assert lowest == pytest.approx(speed_kmh(1000, ratios[0]) + 8.0, rel=1e-12)
    assert highest == pytest.approx(speed_kmh(2000, ratios[-1]) - 5.0, rel=1e-12)
    load_run_config(overrides=[f"v_ref_kmh={highest - 1e-6}"])


def test_a_file_error_names_its_line(tmp_path: Path) -> None:
    path = write(tmp_path, "my.yaml", "# comment\npedal_kp: 1\n\nhorizon_m: 10\n")
    one_line_error([f"{path.name}:4: key 'horizon_m': expected at least one stage"], config_paths=[path])


# --- bad input ------------------------------------------------------------------------------

BAD_OVERLAYS = [
    ("pedal_kp: abc\n", ["key 'pedal_kp'", "expected a number", "got 'abc'"]),
    ("pedal_kp: true\n", ["key 'pedal_kp'", "expected a number", "got true"]),
    ("pedal_ki: .nan\n", ["key 'pedal_ki'", "finite"]),
    ("plant_dt_s: .inf\n", ["key 'plant_dt_s'", "finite"]),
    ("pedal_kp: -1\n", ["key 'pedal_kp'", "in [0, 1000]"]),
    ("brake_integrator_limit: 0\n", ["key 'brake_integrator_limit'", "in (0, 1000000]"]),
    ("v_ref_kmh: 0\n", ["key 'v_ref_kmh'", "in (0, 250]"]),
    ("v_inc_kmh: -1\n", ["key 'v_inc_kmh'", "expected a number in [0, 100], got -1"]),
    ("plant_dt_s: 1.5\n", ["key 'plant_dt_s'", "(0, 1]"]),
    ("plant_dt_s: 0\n", ["key 'plant_dt_s'", "(0, 1]"]),
    ("trace_step_m: 0\n", ["key 'trace_step_m'", "in (0, 100000]"]),
    ("start_speed_kmh: -5\n", ["key 'start_speed_kmh'", "in (0, 250]"]),
    ("pedal_kpp: 1\n", ["unknown key 'pedal_kpp'", "did you mean 'pedal_kp'"]),
    ("mass_kg: 1\n", ["key 'mass_kg' is a vehicle parameter"]),
    ("gear_up_rpm: [1800, 1800]\n", ["key 'gear_up_rpm'", "(12), got 2"]),
    ("gear_up_rpm: 1800\n", ["key 'gear_up_rpm'", "expected a list of numbers in (0, 10000]"]),
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
    ("mass_kg=-1", ["--set mass_kg: expected a number in (0, 1000000], got -1"]),
    ("mass_kg=yes", ["--set mass_kg: expected a number in (0, 1000000], got true"]),
    ("gear_ratios=[3, 2, 1]", ["--set gear_ratios", "gear_efficiencies"]),
    ("v_inc_kmh=-2", ["--set v_inc_kmh: expected a number in [0, 100], got -2"]),
    ("pedal_kp", ["--set 'pedal_kp': expected key=value"]),
    ("=3", ["expected key=value"]),
    ("pedal_kp=[1,", ["--set pedal_kp", "not valid YAML"]),
    ("pedal_kp=[&a [1, 1], *a, *a]", ["--set pedal_kp", "aliases are not accepted"]),
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
    (vehicle_text(mass_kg=-1), ["key 'mass_kg': expected a number in (0, 1000000], got -1"]),
    (vehicle_text(final_drive_efficiency=1.5), ["key 'final_drive_efficiency'", "(0, 1]"]),
    (vehicle_text(gear_efficiencies=[0.9] * 11), ["key 'gear_efficiencies'", "12"]),
    (vehicle_text(gear_ratios=[1.0, 2.0]), ["key 'gear_"]),
    (vehicle_text(mass_kg="heavy"), ["key 'mass_kg': expected a number in (0, 1000000], got 'heavy'"]),
    (vehicle_text(mass_kg=True), ["key 'mass_kg': expected a number in (0, 1000000], got true"]),
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


def test_config_error_is_value_error() -> None:
    with pytest.raises(ValueError):
        load_run_config(overrides=["pedal_kp=x"])


def test_the_thesis_preset_is_an_overlay_by_name(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    assert load_run_config().mpc.on_infeasible == "rescue"
    assert load_run_config(config_paths=["thesis"]).mpc.on_infeasible == "hold"
    monkeypatch.chdir(tmp_path)
    (tmp_path / "thesis").write_text("pedal_kp: 1.5\n")  # a file of that name wins over the preset
    run = load_run_config(config_paths=["thesis"])
    assert (run.pi.pedal_kp, run.mpc.on_infeasible) == (1.5, "rescue")

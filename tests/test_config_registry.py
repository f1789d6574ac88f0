"""One parameter system: the VECTO truck's keys are declared in the core like every other (its
ranges refuse, `config keys` lists them, `--set` takes every listed key), and the core's registry
of renamed, replaced and added keys drives the unknown-key errors, `--replay` and sweep resume."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from truckmpc.cli import app
from truckmpc.config import ConfigError, load_run_config
from truckmpc.config.docs import yaml_value
from truckmpc.config.keys import KEY_CHANGES, SPEC_BY_KEY, VECTO_KEYS, KeyChange, ParamSpec, current_values
from truckmpc.config.vecto_truck import STILL_APPLIES
from truckmpc.roads import default_test_track
from truckmpc.sweep.files import check_out_dir
from truckmpc.sweep.plan import plan_sweep
from vecto_files import write_job

runner = CliRunner()


def _error(**kwargs) -> str:
    with pytest.raises(ConfigError) as caught:
        load_run_config(**kwargs)
    message = str(caught.value)
    assert len(message.splitlines()) == 1, message
    return message


def test_the_declared_range_refuses_a_bad_payload_naming_the_set(tmp_path: Path) -> None:
    expected = SPEC_BY_KEY["payload_kg"].expected  # the declaration's words, not a second table's
    message = _error(vehicle_path=write_job(tmp_path), overrides=["payload_kg=-5"])
    assert message == f"--set payload_kg: expected {expected}, got -5"
    assert expected == "a number in [0, 1000000] or null"


def test_a_vecto_key_with_the_thesis_truck_is_refused_naming_it() -> None:
    message = _error(overrides=["payload_kg=5000"])
    assert message.startswith("--set payload_kg: expected no value with the thesis's truck")


def test_a_thesis_vehicle_key_with_a_vecto_truck_stays_refused(tmp_path: Path) -> None:
    message = _error(vehicle_path=write_job(tmp_path), overrides=["mass_kg=30000"])
    assert message.startswith("--set mass_kg: expected a key of the VECTO truck") and "replaces" in message


def _listed_keys() -> list[str]:
    result = runner.invoke(app, ["config", "keys", "--markdown"])
    assert result.exit_code == 0, result.output
    return [line.split("`")[1] for line in result.stdout.splitlines() if line.startswith("| `")]


def test_config_keys_prints_a_terminal_table_of_every_key_within_the_width() -> None:
    """No Markdown in a terminal: boxed tables wrapped to the terminal's width, every key whole."""
    result = runner.invoke(app, ["config", "keys"], env={"COLUMNS": "100"})
    assert result.exit_code == 0, result.output
    lines = result.stdout.splitlines()
    assert "<!--" not in result.stdout and not any(line.startswith("| `") for line in lines)
    assert max(len(line) for line in lines) <= 100
    cells = {cell.strip() for line in lines for cell in line.split("│")}
    assert set(SPEC_BY_KEY) <= cells  # each key whole in its cell, never wrapped
    (row,) = [line.split("│") for line in lines if "│ payload_kg " in line]
    assert [cell.strip() for cell in row[2:4]] == ["kg", "null"]  # its unit and default beside it


def test_config_keys_lists_the_vecto_trucks_keys_with_units() -> None:
    listed = _listed_keys()
    assert set(VECTO_KEYS) <= set(listed) and len(listed) == len(set(listed)) == len(SPEC_BY_KEY)
    assert SPEC_BY_KEY["payload_kg"].unit == "kg" and SPEC_BY_KEY["aux_power_w"].unit == "W"


def test_set_accepts_every_key_config_keys_lists(tmp_path: Path) -> None:
    job = write_job(tmp_path)
    for key in _listed_keys():
        text = f"{key}={yaml_value(SPEC_BY_KEY[key].default)}"
        assert load_run_config(overrides=[text]).settings.get(key) == SPEC_BY_KEY[key].default, key
        if key in VECTO_KEYS or key in STILL_APPLIES:
            assert load_run_config(job, overrides=[text]).truck is not None, key


def test_a_vecto_key_set_reaches_the_truck_and_the_settings(tmp_path: Path) -> None:
    config = load_run_config(write_job(tmp_path), overrides=["payload_kg=10000", "air_density_kgpm3=1.2"])
    assert config.truck is not None and config.truck.payload_kg == 10000.0
    assert config.settings.get("payload_kg") == 10000.0 and config.truck.keys["air_density_kgpm3"] == 1.2
    assert config.settings.get("air_density_kgpm3") == 1.2
    # Without the override the VECTO truck takes VECTO's air density, not the thesis's.
    assert load_run_config(write_job(tmp_path)).settings.get("air_density_kgpm3") == 1.188


def test_the_cores_records_read_as_the_declarations_give_them() -> None:
    """delta_kmh and grid as params/mpc.rs declares them, the air density's rename as
    params/changes.rs registers it; each typed and frozen."""
    doc = "δ, step of the DP's speed grid."
    delta = ParamSpec("delta_kmh", "mpc", "number", "km/h", doc, 0.05, None, "a number in (0, 100]")
    assert SPEC_BY_KEY["delta_kmh"] == delta
    grid = SPEC_BY_KEY["grid"]
    assert grid.kind == "choice" and grid.default == "fixed" and grid.choices == ["moving", "fixed"]
    assert grid.expected == "'moving' or 'fixed'"
    renamed = next(c for c in KEY_CHANGES if c.key == "air_density_kg_m3")
    assert renamed == KeyChange("air_density_kg_m3", "renamed", "air_density_kgpm3", None, None, "0.1.0")
    with pytest.raises(dataclasses.FrozenInstanceError):
        renamed.new = "air_density"  # type: ignore[misc]


def test_the_registry_drives_the_unknown_key_errors() -> None:
    for change in KEY_CHANGES:
        if change.kind == "added":
            continue
        message = _error(overrides=[f"{change.key}=1"])
        assert message.startswith(f"--set {change.key}: key ") and repr(change.new) in message, message


def test_the_registry_fills_and_renames_recorded_values() -> None:
    added = {c.key: c.replays_with for c in KEY_CHANGES if c.kind == "added"}
    assert added["pedal_levels"] == 0 and added["payload_kg"] is None and added["mission"] == "LongHaul"
    assert current_values({"air_density_kg_m3": 1.2, "payload_kg": 9000}) == {
        **added,
        "air_density_kgpm3": 1.2,
        "payload_kg": 9000,
    }


def test_an_old_vecto_summary_without_the_truck_keys_replays_as_it_ran(tmp_path: Path) -> None:
    job, road = write_job(tmp_path), tmp_path / "flat.csv"
    road.write_text("distance_m,altitude_m\n0,0\n2000,0\n")
    first, second = tmp_path / "first", tmp_path / "second"
    sets = ["--set", "payload_kg=10000", "--set", "air_density_kgpm3=1.2"]
    args = ["simulate", "--vehicle", str(job), "--road", str(road), "--controller", "pi", *sets]
    assert runner.invoke(app, [*args, "--out", str(first)]).exit_code == 0
    doc = json.loads((first / "summary.json").read_text())
    settings = doc["run"]["settings"]
    # As a record made before the truck's keys were settings: no vecto section, the keys set in
    # run.vehicle.keys under their old names.
    assert settings.pop("vecto")["payload_kg"] == 10000.0
    keys = doc["run"]["vehicle"]["keys"]
    keys["air_density_kg_m3"] = keys.pop("air_density_kgpm3")
    (first / "summary.json").write_text(json.dumps(doc))
    result = runner.invoke(app, ["simulate", "--replay", str(first / "summary.json"), "--out", str(second)])
    assert result.exit_code == 0, result.output
    again = json.loads((second / "summary.json").read_text())
    assert again["pi"]["fuel_kg"] == doc["pi"]["fuel_kg"]
    assert again["run"]["settings"]["vecto"]["payload_kg"] == 10000.0
    assert again["run"]["settings"]["vehicle"] == settings["vehicle"]


def test_a_sweep_directory_written_before_the_vecto_keys_still_resumes(tmp_path: Path) -> None:
    config = load_run_config().as_dict()
    config.pop("sources")
    mine = {"version": 1, "roads": [], "grid": {}, "base_config": config, "columns": ["a"]}
    old_config = {section: dict(values) for section, values in config.items() if section != "vecto"}
    old_config["vehicle"]["air_density_kg_m3"] = old_config["vehicle"].pop("air_density_kgpm3")
    (tmp_path / "sweep.json").write_text(json.dumps({**mine, "base_config": old_config}))
    check_out_dir(tmp_path, mine)  # the same sweep: no error
    old_config["vehicle"]["air_density_kg_m3"] = 1.0
    (tmp_path / "sweep.json").write_text(json.dumps({**mine, "base_config": old_config}))
    with pytest.raises(Exception, match="base_config"):
        check_out_dir(tmp_path, mine)


def test_an_old_vecto_sweep_that_set_a_truck_key_resumes_with_the_value_it_set(tmp_path: Path) -> None:
    """Before the VECTO keys were declared a sweep recorded a truck key only among its overrides."""
    job = write_job(tmp_path)
    config = load_run_config(job, overrides=["payload_kg=10000"]).as_dict()
    config.pop("sources")
    mine = {"version": 1, "roads": [], "grid": {}, "base_config": config, "columns": ["a"]}
    mine["overrides"] = ["payload_kg=10000"]
    old_config = {section: dict(values) for section, values in config.items() if section != "vecto"}
    (tmp_path / "sweep.json").write_text(json.dumps({**mine, "base_config": old_config}))
    check_out_dir(tmp_path, mine)  # the same sweep: no error
    (tmp_path / "sweep.json").write_text(json.dumps({**mine, "base_config": old_config, "overrides": []}))
    with pytest.raises(Exception, match="base_config"):
        check_out_dir(tmp_path, mine)


def test_the_declared_choices_are_the_names_the_declaration_data_carries() -> None:
    from truckmpc.vecto import declaration as decl

    assert SPEC_BY_KEY["cross_wind"].choices == list(decl.CROSS_WIND)
    assert SPEC_BY_KEY["mission"].choices == sorted({mission for _, _, mission in decl.SEGMENTS})


def test_sweep_rows_differing_only_in_a_vecto_key_do_not_share_their_baselines(tmp_path: Path) -> None:
    """The auxiliaries' power changes what the PI and the PCC burn: rows that differ in it alone must
    each drive their own baselines (a shared PI would compare the 20 kW row with a 0 kW PI)."""
    plan = plan_sweep([default_test_track()], ["aux_power_w=0,20000"], vehicle_path=write_job(tmp_path))
    pi_keys = {row.keys["pi"] for row in plan.rows}
    assert len(plan.rows) == 2 and len(pi_keys) == 2


@pytest.mark.parametrize(
    "overrides",
    [["mass_kg=999999"], ["v_ref_kmh=60", "mass_kg=999999"], ["mass_kg=999999", "v_ref_kmh=60", "delta_kmh=0.1"]],
)
def test_an_error_on_a_derived_value_names_the_users_key_never_a_packaged_file(overrides: list[str]) -> None:
    """β is derived from the truck: a 1000 t truck holds v_ref in no gear, so β has no value. The
    fault is the mass the user set (with its packaged default, 40 t, every other value passes), not
    the packaged file that leaves β to be derived, nor another key set beside it."""
    message = _error(overrides=overrides)
    assert message.startswith("--set mass_kg: beta_g_per_s: expected a value"), message
    assert "configs" not in message and ".yaml" not in message

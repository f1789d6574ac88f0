"""Bad VECTO files get one line naming the file and the line or key, exit 2, from ``vehicle info``; what
``vehicle info`` and ``vehicle plot`` write for a good one."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from truckmpc.cli import app
from vecto_files import write_job

runner = CliRunner()


def _edit_json(path: Path, edit) -> None:
    doc = json.loads(path.read_text())
    edit(doc["Body"])
    path.write_text(json.dumps(doc))


def _replace_line(path: Path, line: int, text: str) -> None:
    lines = path.read_text().splitlines()
    lines[line - 1] = text
    path.write_text("\n".join(lines) + "\n")


def _gears_not_falling(body):
    body["Gears"][3]["Ratio"] = 2.5


CASES = {
    "an unreadable number in the fuel map": (
        lambda d: _replace_line(d / "e.vmap", 5, "600,400,abc"),
        ["e.vmap:5", "expected 3 numbers"],
    ),
    "a fuel rate below zero": (lambda d: _replace_line(d / "e.vmap", 3, "600,0,-5"), ["e.vmap:3", "fuel rate >= 0"]),
    "a fuel map point twice": (lambda d: _replace_line(d / "e.vmap", 3, "600,-200,5"), ["e.vmap:3", "once"]),
    "engine speeds that do not increase": (
        lambda d: _replace_line(d / "e.vfld", 3, "600,1800,-150"),
        ["e.vfld:3", "increase"],
    ),
    "drag above full load": (
        lambda d: _replace_line(d / "e.vfld", 2, "600,-300,-200"),
        ["e.vfld:2", "drag torque <= the full-load"],
    ),
    "gear ratios that do not fall": (
        lambda d: _edit_json(d / "g.vgbx", _gears_not_falling),
        ["g.vgbx", "Gears[3].Ratio"],
    ),
    "a negative mass": (
        lambda d: _edit_json(d / "v.vveh", lambda b: b.update(CurbWeight=-1)),
        ["v.vveh", "CurbWeight", "> 0"],
    ),
    "a missing component file": (lambda d: (d / "e.veng").unlink(), ["t.vecto", "EngineFile", "not found"]),
    "a JSON syntax error": (
        lambda d: (d / "v.vveh").write_text('{"Body": {\n  "CdA": ,\n}}'),
        ["v.vveh:2", "expected JSON"],
    ),
    "a fuel map at one speed": (
        lambda d: (d / "e.vmap").write_text("n,T,fc\n" + "".join(f"600,{t},{t + 500}\n" for t in range(0, 900, 100))),
        ["e.vmap", "fuel_map", "range of engine speeds"],
    ),
    "a positive drag torque": (
        lambda d: _replace_line(d / "e.vfld", 2, "600,1800,50"),
        ["e.vfld:2", "drag (motoring) torque <= 0"],
    ),
    "an engineering-mode job": (
        lambda d: _edit_json(d / "t.vecto", lambda b: b.update(SavedInDeclMode=False)),
        ["t.vecto", "SavedInDeclMode"],
    ),
    "a 4x4 tractor": (
        lambda d: _edit_json(d / "v.vveh", lambda b: b["AxleConfig"].update(Type="4x4")),
        ["v.vveh", "Tractor 4x4"],
    ),
    "a tractor of 16 t": (
        lambda d: _edit_json(d / "v.vveh", lambda b: b.update(MassMax=16.0)),
        ["v.vveh", "MassMax", "of 16 t"],
    ),
    "a gear ratio of true": (
        lambda d: _edit_json(d / "g.vgbx", lambda b: b["Gears"][1].update(Ratio=True)),
        ["g.vgbx", "Gears[1]", "Ratio"],
    ),
    "a JSON list": (lambda d: (d / "v.vveh").write_text("[1, 2]"), ["v.vveh", "got a list"]),
    "Aux as a string": (
        lambda d: _edit_json(d / "t.vecto", lambda b: b.update(Aux="FAN")),
        ["t.vecto", "Aux", "got a str"],
    ),
    "an unknown tyre": (
        lambda d: _edit_json(d / "v.vveh", lambda b: b["AxleConfig"]["Axles"][1].update(Wheels="999/99 R99")),
        ["v.vveh", "Axles", "999/99 R99"],
    ),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_a_bad_file_is_one_line_naming_it_and_exit_2(tmp_path: Path, case: str) -> None:
    job = write_job(tmp_path)
    damage, expected = CASES[case]
    damage(tmp_path)
    result = runner.invoke(app, ["vehicle", "info", str(job)])
    assert result.exit_code == 2, result.output
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), result.stderr
    for part in expected:
        assert part in lines[0], lines[0]
    assert result.stdout == ""


@pytest.mark.parametrize(
    ("setting", "expected"),
    [
        # The declared ranges refuse, in the declaration's words.
        ("payload_kg=-5", "--set payload_kg: expected a number in [0, 1000000] or null, got -5"),
        ("payload_kg=nan", "--set payload_kg: expected a finite number in [0, 1000000] or null, got 'nan'"),
        ("gear_efficiency=2", "--set gear_efficiency: expected a number in (0, 1], got 2"),
        ("air_density_kgpm3=0", "--set air_density_kgpm3: expected a number in (0, 100], got 0"),
        ("air_density_kg_m3=1", "--set air_density_kg_m3: key is now 'air_density_kgpm3'"),
        ("cross_wind=foo", "--set cross_wind: expected 'vecto3' or 'height_profile' or 'none', got 'foo'"),
        ("traction_interruption_s=11", "--set traction_interruption_s: expected a number in [0, 10] or null, got 11"),
        ("=5", "--set '=5': expected key=value"),
    ],
)
def test_a_bad_setting_is_one_line(tmp_path: Path, setting: str, expected: str) -> None:
    result = runner.invoke(app, ["vehicle", "info", str(write_job(tmp_path)), "--set", setting])
    assert result.exit_code == 2, result.output
    assert len(result.stderr.strip().splitlines()) == 1 and expected in result.stderr, result.stderr


def test_an_unknown_key_is_one_line(tmp_path: Path) -> None:
    result = runner.invoke(app, ["vehicle", "info", str(write_job(tmp_path)), "--set", "cda=7"])
    assert result.exit_code == 2
    assert "--set cda: unknown key" in result.stderr


def test_info_prints_the_truck_and_json_names_units(tmp_path: Path) -> None:
    job = write_job(tmp_path)
    text = runner.invoke(app, ["vehicle", "info", str(job)])
    assert text.exit_code == 0, text.output
    assert "vehicle 8000 + trailer 7500 + load 19300" in text.stdout
    doc = json.loads(runner.invoke(app, ["vehicle", "info", str(job), "--json"]).stdout)
    assert doc["mass_kg"] == 8000 + 7500 + 19300
    assert doc["gear_ratios"] == [4.0, 2.0, 1.0]
    assert set(doc["files"]) == {
        str(tmp_path / f) for f in ("t.vecto", "v.vveh", "e.veng", "e.vfld", "e.vmap", "g.vgbx")
    }


def test_plot_draws_the_fuel_map_to_the_file_named(tmp_path: Path) -> None:
    job = write_job(tmp_path / "job")
    out = tmp_path / "map.png"
    result = runner.invoke(app, ["vehicle", "plot", str(job), "-o", str(out), "--svg"])
    assert result.exit_code == 0, result.output
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert out.with_suffix(".svg").read_text().lstrip().startswith("<?xml")

"""VECTO's declaration XML vehicle file: read into the same job as the JSON files of the same truck,
with its loss maps, VECTO's declaration rules for what the file leaves out, and one-line errors that
name the file, the line and the element."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import pytest

from truckmpc.errors import VehicleError
from truckmpc.vecto.components import read_job
from truckmpc.vecto.declaration import auxiliary_power_w
from truckmpc.vecto.xml_job import read_xml_job
from vecto_files import SHARED_TRACTOR, TRACTOR_JOB, write_job
from vecto_xml import (
    AXLE_LOSS_BASE_NM,
    GEAR_LOSS_BASE_NM,
    LOSS_SPEEDS_RPM,
    LOSS_TORQUES_NM,
    loss_nm,
    write_xml_job,
)

TRACTOR_XML = SHARED_TRACTOR / "Class5_Tractor_DECL.xml"


def _line_of(path: Path, text: str) -> int:
    """The number of the first line of ``path`` holding ``text``."""
    return next(i for i, line in enumerate(path.read_text().splitlines(), start=1) if text in line)


def _edit(path: Path, old: str, new: str) -> int:
    """Replace ``old`` by ``new`` on the first line holding it; that line's number."""
    line = _line_of(path, old)
    lines = path.read_text().splitlines()
    lines[line - 1] = lines[line - 1].replace(old, new, 1)
    path.write_text("\n".join(lines) + "\n")
    return line


def test_the_xml_file_reads_into_the_json_jobs_vehicle_engine_ratios_and_auxiliaries(tmp_path: Path) -> None:
    path = write_xml_job(tmp_path / "xml")
    xml, json = read_xml_job(path), read_job(write_job(tmp_path / "json"))
    for name in ("category", "axle_config", "curb_mass_kg", "cda_m2", "gross_mass_t", "axles"):
        assert getattr(xml.vehicle, name) == getattr(json.vehicle, name), name
    for name in ("model", "idle_speed_rpm", "displacement_cm3", "full_load", "fuel_map"):
        assert getattr(xml.engine, name) == getattr(json.engine, name), name
    for name in ("model", "gearbox_type", "axle_ratio", "gear_ratios", "traction_interruption_s"):
        assert getattr(xml.gearbox, name) == getattr(json.gearbox, name), name
    assert xml.auxiliaries == json.auxiliaries
    # The numbers written into both fixtures, and what declaration mode makes of them.
    assert (xml.vehicle.curb_mass_kg, xml.vehicle.gross_mass_t, xml.vehicle.cda_m2) == (8000.0, 18.0, 5.5)
    assert (xml.gearbox.gear_ratios, xml.gearbox.axle_ratio) == ((4.0, 2.0, 1.0), 2.5)
    assert [(a.driven, a.twin_tyres, a.wheel_inertia_kgm2) for a in xml.vehicle.axles] == [
        (False, False, 14.9),  # VECTO's Wheels table: 315/70 R22.5, 14.9 kg m²
        (True, True, 14.9),
    ]
    assert xml.engine.fuel_map[1] == (600.0, 0.0, 2 * 600 + 10 * 0 + 5000)
    assert auxiliary_power_w(xml.auxiliaries, str(path)) == pytest.approx(989 + 690 + 350 + 700 + 1200 / 0.7)
    assert xml.declaration_mode
    assert xml.path == xml.vehicle.path == xml.engine.path == xml.gearbox.path == path
    assert xml.engine.files == () and xml.gearbox.files == () and xml.gearbox.missing_loss_maps == ()


def test_each_gear_and_the_axle_have_their_own_loss_map_with_every_point(tmp_path: Path) -> None:
    gearbox = read_xml_job(write_xml_job(tmp_path)).gearbox
    grid = [(float(n), float(t)) for n in LOSS_SPEEDS_RPM for t in LOSS_TORQUES_NM]
    maps = [*gearbox.gear_loss_maps, gearbox.axle_loss_map]
    assert len(gearbox.gear_loss_maps) == 3
    for points, base in zip(maps, [*GEAR_LOSS_BASE_NM, AXLE_LOSS_BASE_NM], strict=True):
        assert points is not None
        assert [(n, t) for n, t, _ in points] == grid
        assert [loss for _, _, loss in points] == pytest.approx([loss_nm(base, t) for _, t in grid])
    # By hand: gear 2 at 1000 rpm and −2500 Nm loses 21 + 0.02·2500 = 71 Nm; the axle at 3000 rpm
    # and 5000 Nm, 30 + 100 = 130 Nm.
    assert (1000.0, -2500.0, 71.0) in gearbox.gear_loss_maps[1]
    assert gearbox.axle_loss_map is not None and gearbox.axle_loss_map[-1] == (3000.0, 5000.0, 130.0)


@pytest.mark.parametrize(("transmission", "interruption_s"), [("AMT", 1.0), ("SMT", 2.0)])
def test_engine_inertia_and_traction_interruption_follow_vectos_declaration_rules(
    tmp_path: Path, transmission: str, interruption_s: float
) -> None:
    path = write_xml_job(tmp_path)
    _edit(path, "<TransmissionType>AMT<", f"<TransmissionType>{transmission}<")
    job = read_xml_job(path)
    # Clutch 1.3 + engine 0.41 + 0.27 kg m² per litre of the 12 l engine.
    assert job.engine.inertia_kgm2 == pytest.approx(4.95)
    assert job.gearbox.traction_interruption_s == interruption_s
    assert job.gearbox.gearbox_type == transmission


def test_the_inertia_of_vectos_12_74_l_engine_is_its_veng_files(tmp_path: Path) -> None:
    path = write_xml_job(tmp_path)
    _edit(path, "<Displacement>12000<", "<Displacement>12740<")
    assert read_xml_job(path).engine.inertia_kgm2 == pytest.approx(5.1498, abs=1e-9)


def test_the_engine_idles_at_the_vehicles_idling_speed_where_that_is_higher(tmp_path: Path) -> None:
    path = write_xml_job(tmp_path)
    assert read_xml_job(path).engine.idle_speed_rpm == 600.0  # both 600 rpm
    line = _edit(path, "<IdlingSpeed>600<", "<IdlingSpeed>700<")
    assert line < _line_of(path, "<Components>")  # the vehicle's, not the engine's
    assert read_xml_job(path).engine.idle_speed_rpm == 700.0
    _edit(path, "<IdlingSpeed>700<", "<IdlingSpeed>500<")
    assert read_xml_job(path).engine.idle_speed_rpm == 600.0  # the engine's


def _missing_gears(path: Path) -> tuple[int, list[str]]:
    text = path.read_text()
    start, end = text.index("<Gears>"), text.index("</Gears>") + len("</Gears>")
    path.write_text(text[:start] + text[end:])
    return _line_of(path, '<Data id="GBX-g3">'), ["Vehicle/Components/Gearbox/Data:", "expected a <Gears>", "none"]


def _duplicate_fuel_point(path: Path) -> tuple[int, list[str]]:
    edited = _edit(path, 'engineSpeed="800.00" torque="-200.00"', 'engineSpeed="800.00" torque="0.00"')
    return edited + 1, ["FuelConsumptionMap/Entry", "each (engine speed, torque) once", f"(line {edited})"]


def _not_a_declaration(path: Path) -> tuple[int, list[str]]:
    path.write_text('<?xml version="1.0"?>\n<VectoComponent xmlns="urn:x"/>\n')
    return 2, ["expected a VECTO declaration", "VectoInputDeclaration", "got <VectoComponent>"]


CASES: dict[str, Callable[[Path], tuple[int, list[str]]]] = {
    "an unreadable number in a fuel map entry": lambda p: (
        _edit(p, 'engineSpeed="800.00" torque="400.00"', 'engineSpeed="800.00" torque="4OO"'),
        ["Vehicle/Components/Engine/Data/FuelConsumptionMap/Entry/@torque:", "expected a number, got '4OO'"],
    ),
    "no <Gears>": _missing_gears,
    "gear ratios that do not fall": lambda p: (
        _edit(p, "<Ratio>2.000</Ratio>", "<Ratio>4.500</Ratio>"),
        ['Gearbox/Data/Gears/Gear[@number="2"]/Ratio:', "expected a ratio below gear 1's 4, got 4.5"],
    ),
    "a negative mass": lambda p: (
        _edit(p, "<CurbMassChassis>8000<", "<CurbMassChassis>-1<"),
        ["Vehicle/CurbMassChassis:", "expected a number > 0, got '-1'"],
    ),
    "malformed XML": lambda p: (
        _edit(p, "<Model>test</Model>", "<Model>test</Modell>"),
        ["expected well-formed XML, got mismatched tag"],
    ),
    "gear numbers with a gap": lambda p: (
        _edit(p, '<Gear number="3">', '<Gear number="4">'),
        ['Gear[@number="4"]/@number:', "expected Gear numbers 1 to 3, each once, got 4"],
    ),
    "a negative torque loss": lambda p: (
        _edit(p, 'torqueLoss="130.00"', 'torqueLoss="-1.00"'),  # the axle's first entry
        ["Axlegear/Data/TorqueLossMap/Entry/@torqueLoss:", "expected a number >= 0, got '-1.00'"],
    ),
    "a fuel map point twice": _duplicate_fuel_point,
    "a positive drag torque": lambda p: (
        _edit(p, 'dragTorque="-150.00"', 'dragTorque="50.00"'),
        ["FullLoadAndDragCurve/Entry:", "drag (motoring) torque <= 0, got 50"],
    ),
    "a tyre size VECTO does not know": lambda p: (
        _edit(p, "<Dimension>315/70 R22.5<", "<Dimension>999/99 R99<"),
        ['Axle[@axleNumber="1"]/Tyre/Data/Dimension:', "Wheels table", "got '999/99 R99'"],
    ),
    "an automatic gearbox with a torque converter": lambda p: (
        _edit(p, "<TransmissionType>AMT<", "<TransmissionType>APT-S<"),
        ["Gearbox/Data/TransmissionType:", "expected AMT or SMT", "got 'APT-S'"],
    ),
    "twin tyres neither true nor false": lambda p: (
        _edit(p, "<TwinTyres>true<", "<TwinTyres>yes<"),
        ['Axle[@axleNumber="2"]/TwinTyres:', "expected true or false, got 'yes'"],
    ),
    "a retarder type VECTO does not know": lambda p: (
        _edit(p, "<RetarderType>Transmission Output Retarder<", "<RetarderType>Exhaust brake<"),
        ["Vehicle/RetarderType:", "expected a retarder type", "got 'Exhaust brake'"],
    ),
    "retarder speeds that do not increase": lambda p: (
        _edit(p, 'retarderSpeed="2000.00"', 'retarderSpeed="500.00"'),
        ["Retarder/Data/RetarderLossMap/Entry:", "expected a retarder speed above 1000 rpm, got 500"],
    ),
    "a negative retarder loss": lambda p: (
        _edit(p, 'retarderSpeed="1000.00" torqueLoss="20.00"', 'retarderSpeed="1000.00" torqueLoss="-2.00"'),
        ["RetarderLossMap/Entry/@torqueLoss:", "expected a number >= 0, got '-2.00'"],
    ),
    "another root element": _not_a_declaration,
    "a DOCTYPE (which could declare entities)": lambda p: (
        _edit(p, "?>", '?><!DOCTYPE VectoInputDeclaration [<!ENTITY e "x">]>'),
        ["expected a VECTO declaration without a DOCTYPE"],
    ),
}


@pytest.mark.parametrize("case", CASES)
def test_bad_input_is_one_line_naming_the_file_the_line_and_the_element(tmp_path: Path, case: str) -> None:
    path = write_xml_job(tmp_path)
    line, fragments = CASES[case](path)
    with pytest.raises(VehicleError) as err:
        read_xml_job(path)
    message = str(err.value)
    assert "\n" not in message
    assert message.startswith(f"{path}:{line}: "), message
    for fragment in fragments:
        assert fragment in message, message


def test_a_missing_file_is_one_line(tmp_path: Path) -> None:
    with pytest.raises(VehicleError, match=r"t\.xml: no such file$"):
        read_xml_job(tmp_path / "t.xml")


@pytest.mark.skipif(not TRACTOR_XML.is_file(), reason="VECTO's generic tractor's XML (../shared/vehicles) not present")
def test_vectos_generic_tractor_reads_as_its_json_job() -> None:
    job = read_xml_job(TRACTOR_XML)
    # The numbers of VECTO's Class5_Tractor_DECL.xml, and its .veng's inertia 5.1498 kg m² for 12.74 l.
    assert (job.vehicle.curb_mass_kg, job.vehicle.gross_mass_t, job.vehicle.cda_m2) == (8229.0, 18.0, 5.3)
    assert job.engine.inertia_kgm2 == pytest.approx(5.1498, abs=1e-9)
    assert (job.gearbox.gearbox_type, job.gearbox.traction_interruption_s) == ("AMT", 1.0)
    assert (len(job.gearbox.gear_ratios), job.gearbox.gear_ratios[0], job.gearbox.axle_ratio) == (12, 14.93, 2.64)
    assert [a.rolling_resistance for a in job.vehicle.axles] == [0.0055, 0.0065]
    if TRACTOR_JOB.is_file():
        json = read_job(TRACTOR_JOB)
        assert job.vehicle.axles == json.vehicle.axles
        assert job.gearbox.gear_ratios == json.gearbox.gear_ratios
        assert job.engine.inertia_kgm2 == pytest.approx(json.engine.inertia_kgm2, abs=1e-9)
        assert job.auxiliaries == json.auxiliaries


def test_the_retarder_reads_with_its_shaft_ratio_and_loss_map(tmp_path: Path) -> None:
    path = write_xml_job(tmp_path)
    retarder = read_xml_job(path).retarder
    assert retarder is not None
    assert (retarder.position, retarder.ratio) == ("output", 1.0)
    assert retarder.loss_map == ((0.0, 10.0), (1000.0, 20.0), (2000.0, 30.0))
    _edit(path, "<RetarderType>Transmission Output Retarder<", "<RetarderType>Transmission Input Retarder<")
    _edit(path, "<RetarderRatio>1.000<", "<RetarderRatio>2.000<")
    retarder = read_xml_job(path).retarder
    assert retarder is not None and (retarder.position, retarder.ratio) == ("input", 2.0)


@pytest.mark.parametrize(
    "kind", ["None", "Losses included in Gearbox", "Engine Retarder", "LossesIncludedInTransmission"]
)
def test_a_retarder_whose_losses_vecto_does_not_charge_adds_none(tmp_path: Path, kind: str) -> None:
    path = write_xml_job(tmp_path)
    _edit(path, "<RetarderType>Transmission Output Retarder<", f"<RetarderType>{kind}<")
    assert read_xml_job(path).retarder is None


def test_a_retarder_type_reads_by_vectos_enum_name_too(tmp_path: Path) -> None:
    path = write_xml_job(tmp_path)
    _edit(path, "<RetarderType>Transmission Output Retarder<", "<RetarderType>TransmissionInputRetarder<")
    retarder = read_xml_job(path).retarder
    assert retarder is not None and retarder.position == "input"

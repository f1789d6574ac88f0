"""VECTO's declaration XML of a battery-electric truck: its machines, reduction, batteries and
vehicle read as the file writes them (checked against the file's own text), the usable energy
against a battery built by hand, one-line errors naming the file, line and element for each defect,
and what ``vehicle info`` shows of such a truck."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from truckmpc import load_run_config
from truckmpc.cli import app
from truckmpc.errors import VehicleError
from truckmpc.vecto.electric import BatteryData, ElectricTruckJob
from truckmpc.vecto.electric_info import usable_energy_kwh
from truckmpc.vecto.xml_file import read_declaration_xml
from vecto_files import SHARED_TRACTOR

BEV_XML = SHARED_TRACTOR.parent / "vecto-generic-class5-bev" / "Group5_PEV_E4.xml"
needs_bev = pytest.mark.skipif(not BEV_XML.is_file(), reason="VECTO's generic electric tractor (../shared) not present")
runner = CliRunner()


def _read(path: Path) -> ElectricTruckJob:
    job = read_declaration_xml(path)
    assert isinstance(job, ElectricTruckJob)
    return job


@needs_bev
def test_the_generic_electric_tractor_reads_as_its_file_writes_it() -> None:
    job = _read(BEV_XML)
    m = job.machine
    assert (job.architecture, m.position, m.count, m.machine_type) == ("E4", "E4", 2, "ASM")
    assert (m.rated_power_w, m.inertia_kgm2, m.dc_dc_converter_included) == (325_000.0, 0.23, True)
    assert [v.voltage_v for v in m.voltage_levels] == [100.0, 1000.0]
    low = m.voltage_levels[0]
    assert (low.continuous_torque_nm, low.overload_torque_nm, low.overload_duration_s) == (700.0, 750.0, 120.0)
    assert low.torque_limits[0] == (0.0, 750.0, -750.0) and low.torque_limits[-1] == (8276.0, 187.5, -187.5)
    # A grid of 22 speeds and 42 torques, the last point 739.46 kW at 8276.06 rpm and 750 Nm.
    assert len(low.power_map) == 22 * 42 and low.power_map[-1] == (8276.06, 750.0, 739_460.0)
    assert (m.drag_curve[0], m.drag_curve[-1], len(m.drag_curve)) == ((0.0, -1.77), (8276.06, -20.69), 22)
    assert (job.reduction.ratio, len(job.reduction.loss_map)) == (12.72, 10)
    assert job.reduction.loss_map[0] == (0.0, -50_000.0, 1500.0)
    (battery,) = job.batteries
    assert (battery.rated_capacity_ah, battery.soc_min_pct, battery.soc_max_pct) == (1555.5, 8.0, 92.0)
    assert (battery.ocv[0], battery.ocv[-1], len(battery.ocv)) == ((0.0, 718.42), (100.0, 800.21), 11)
    assert battery.resistance == ((0.0, 40.0, 40.0, 40.0), (100.0, 40.0, 40.0, 40.0))
    assert battery.current_limits == ((0.0, 1500.0, 1500.0), (100.0, 1500.0, 1500.0))
    v = job.vehicle
    assert (v.category, v.axle_config, v.curb_mass_kg, v.gross_mass_t, v.cda_m2) == (
        "Tractor",
        "4x2",
        10143.0,
        18.0,
        4.31,
    )
    assert [(a.driven, a.twin_tyres, a.rolling_resistance) for a in v.axles] == [
        (False, False, 0.0034),
        (True, True, 0.004),
    ]


def test_the_usable_energy_integrates_the_open_circuit_voltage_over_the_usable_window() -> None:
    # OCV linear from 700 V (empty) to 800 V (full): over 10-90 % its mean is 750 V, and 100 Ah of
    # which 80 % is usable hold 80 Ah × 750 V = 60 kWh.
    battery = BatteryData(0, "HPBS", 100.0, ((0.0, 700.0), (100.0, 800.0)), (), (), 10.0, 90.0)
    assert usable_energy_kwh(battery) == pytest.approx(60.0, rel=1e-12)
    # A kink at 50 %: 700 V to 720 V up to 50 %, then to 800 V. Over 0-100 %: mean (710 + 760) / 2 = 735 V.
    kinked = BatteryData(0, "HPBS", 10.0, ((0.0, 700.0), (50.0, 720.0), (100.0, 800.0)), (), (), 0.0, 100.0)
    assert usable_energy_kwh(kinked) == pytest.approx(7.35, rel=1e-12)


def _edited(tmp_path: Path, old: str, new: str) -> tuple[Path, int]:
    """A copy of the shared file with ``old`` replaced by ``new`` on the first line holding it."""
    lines = BEV_XML.read_text(encoding="utf-8-sig").splitlines()
    line = next(i for i, text in enumerate(lines, start=1) if old in text)
    lines[line - 1] = lines[line - 1].replace(old, new, 1)
    path = tmp_path / "bev.xml"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path, line


@needs_bev
@pytest.mark.parametrize(
    ("old", "new", "element", "expected"),
    [
        ("<PowertrainPosition>4<", "<PowertrainPosition>2<", "PowertrainPosition", "expected 4"),
        ("<Count>2<", "<Count>1.5<", "Count", "expected a whole number"),
        ("<ElectricMachineType>ASM<", "<ElectricMachineType>DC<", "ElectricMachineType", "expected one of"),
        ('dragTorque="-6.50"', 'dragTorque="6.50"', "DragCurve/Entry", "expected a drag torque <= 0"),
        ('outShaftSpeed="41.00" maxTorque', 'outShaftSpeed="0.00" maxTorque', "MaxTorqueCurve/Entry", "increase"),
        ('minTorque="-750.00"', 'minTorque="750.00"', "MaxTorqueCurve/Entry", "expected a minTorque <= 0"),
        ('torque="-712.50" electricPower="0.00"', 'torque="-750.00" electricPower="0.00"', "PowerMap/Entry", "once"),
        ("<Ratio>12.720<", "<Ratio>-1<", "ADC/Data/Ratio", "expected a number > 0"),
        ('SoC="100" OCV="800.21"', 'SoC="120" OCV="800.21"', "OCV/Entry", "[0, 100]"),
        ("<SOCmax>92.0<", "<SOCmax>5.0<", "SOCmax", "above SOCmin"),
        (">1555.50</v2.3:RatedCapacity>", ">lots</v2.3:RatedCapacity>", "RatedCapacity", "expected a number"),
        ("<OverloadTorque>750.00<", "<OverloadTorque>600.00<", "OverloadTorque", "expected an OverloadTorque >="),
    ],
)
def test_a_defect_is_one_line_naming_the_file_line_and_element(
    tmp_path: Path, old: str, new: str, element: str, expected: str
) -> None:
    path, line = _edited(tmp_path, old, new)
    with pytest.raises(VehicleError) as caught:
        read_declaration_xml(path)
    message = str(caught.value)
    assert "\n" not in message
    assert message.startswith(f"{path}:"), message
    assert element in message and expected in message, message
    assert f"{path}:{line}:" in message, message


@needs_bev
def test_a_gearbox_in_an_electric_truck_is_refused_naming_it(tmp_path: Path) -> None:
    path, _ = _edited(tmp_path, "<ElectricEnergyStorage>", "<Gearbox/><ElectricEnergyStorage>")
    with pytest.raises(VehicleError, match=r"Components/Gearbox: expected no <Gearbox>"):
        read_declaration_xml(path)


@needs_bev
def test_vehicle_info_shows_the_electric_truck_and_refuses_a_diesel_key_in_one_line() -> None:
    shown = runner.invoke(app, ["vehicle", "info", str(BEV_XML)])
    assert shown.exit_code == 0, shown.output
    assert "2 × ASM at E4, 325 kW rated each" in shown.output
    assert "22 speeds × 42 torques at 100 and 1000 V" in shown.output
    doc = json.loads(runner.invoke(app, ["vehicle", "info", str(BEV_XML), "--json"]).output)
    assert doc["machines"]["count"] == 2 and doc["batteries"][0]["soc_window_pct"] == [8.0, 92.0]
    # 1555.5 Ah × 84 % × the OCV's mean over 8-92 % (between 739 and 791 V): about 1 MWh.
    assert 1555.5 * 0.84 * 0.739 < doc["batteries"][0]["usable_energy_kwh"] < 1555.5 * 0.84 * 0.792
    # Declaration mode's group-5 long-haul trailer (7 500 kg) and reference load (19 300 kg).
    assert (doc["group"], doc["mass_kg"]) == ("group 5 (tractor 4x2 > 16 t), Long Haul", 10143.0 + 7500.0 + 19300.0)
    lighter = runner.invoke(app, ["vehicle", "info", str(BEV_XML), "--json", "--set", "payload_kg=1000"])
    assert json.loads(lighter.output)["mass_kg"] == 10143.0 + 7500.0 + 1000.0
    assert "usable 10.1-89.9 % (declaration mode: narrowed for ageing)" in shown.output
    refused_keys = (["--set", "v_ref_kmh=80"], ["--set", "gear_efficiency=0.5"], ["--set", "use_loss_maps=false"])
    for args in (["vehicle", "info", str(BEV_XML), *key] for key in refused_keys):
        refused = runner.invoke(app, args)
        assert refused.exit_code == 2, refused.output
        assert "Traceback" not in refused.output and len(refused.output.strip().splitlines()) == 1, refused.output


def test_the_machine_efficiency_is_mechanical_over_electric_power_driving_and_the_inverse_braking() -> None:
    from truckmpc.plot.electric import machine_efficiency_pct

    # The file's last point: 750 Nm at 8276.06 rpm is 650.0 kW at the shaft for 739.46 kW drawn.
    mech_w = 750.0 * 8276.06 * 2 * math.pi / 60
    points = ((8276.06, 750.0, 739_460.0), (1000.0, -300.0, -28_000.0), (0.0, 500.0, 9_000.0), (900.0, -10.0, 400.0))
    efficiency = machine_efficiency_pct(points)
    assert efficiency[0] == pytest.approx(100 * mech_w / 739_460.0, rel=1e-12)
    # Braking: 300 Nm at 1000 rpm is 31.4 kW taken in, 28 kW returned.
    assert efficiency[1] == pytest.approx(100 * 28_000.0 / (300.0 * 1000.0 * 2 * math.pi / 60), rel=1e-12)
    # At standstill, and braking while drawing power: no efficiency.
    assert np.isnan(efficiency[2]) and np.isnan(efficiency[3])


@needs_bev
def test_vehicle_plot_draws_the_machine_map_and_refuses_a_run(tmp_path: Path) -> None:
    out = tmp_path / "map.png"
    drawn = runner.invoke(app, ["vehicle", "plot", str(BEV_XML), "-o", str(out)])
    assert drawn.exit_code == 0, drawn.output
    assert out.stat().st_size > 10_000
    refused = runner.invoke(app, ["vehicle", "plot", str(BEV_XML), "--run", str(tmp_path)])
    assert refused.exit_code == 2 and "--run: expected none" in refused.output


@needs_bev
def test_a_zero_overload_duration_is_a_machine_without_a_thermal_buffer(tmp_path: Path) -> None:
    """OverloadDuration 0 at both voltage levels: no buffer, so the machines derate as soon as
    their loss exceeds the continuous loss; the file still drives, and vehicle info says so."""
    path, _ = _edited(tmp_path, "<OverloadDuration>120.00<", "<OverloadDuration>0<")
    path.write_text(path.read_text().replace("<OverloadDuration>120.00<", "<OverloadDuration>0<"))
    facts = load_run_config(path).truck.core.electric_facts
    assert facts["overload_buffer_kj"] == 0.0 and facts["continuous_torque_nm"] == 1400.0
    shown = runner.invoke(app, ["vehicle", "info", str(path)])
    assert shown.exit_code == 0 and "fill 0 kJ" in shown.output, shown.output

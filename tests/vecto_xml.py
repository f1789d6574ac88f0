"""A small VECTO declaration XML file written from scratch, laid out as VECTO's (schema v1.0, with
its namespaces and signatures): the same truck as the JSON job of :func:`vecto_files.write_job`, plus
a loss map for each gear and for the axle. One element (or ``Entry``) a line, so a test can find the
line it edits."""

from __future__ import annotations

from pathlib import Path

from vecto_files import AUX

NS_DEFINITIONS = "urn:tugraz:ivt:VectoAPI:DeclarationDefinitions:v1.0"
NS_INPUT = "urn:tugraz:ivt:VectoAPI:DeclarationInput:v1.0"
NS_SIGNATURE = "http://www.w3.org/2000/09/xmldsig#"

GEAR_RATIOS = (4.0, 2.0, 1.0)
AXLE_RATIO = 2.5
DISPLACEMENT_CM3 = 12000
LOSS_SPEEDS_RPM = (0, 1000, 2000, 3000)
LOSS_TORQUES_NM = (-5000, -2500, 0, 2500, 5000)
GEAR_LOSS_BASE_NM = (20.0, 21.0, 22.0)
"""Each gear's loss at zero torque; the loss map of gear k is base_k + 2 % of |input torque|."""
AXLE_LOSS_BASE_NM = 30.0
_AUX_ELEMENTS = {"FAN": "Fan", "STP": "SteeringPump", "AC": "HVAC", "ES": "ElectricSystem", "PS": "PneumaticSystem"}


def loss_nm(base_nm: float, torque_nm: float) -> float:
    """The fixture's torque loss [Nm] at an input torque [Nm]."""
    return base_nm + 0.02 * abs(torque_nm)


def _signature(ref: str) -> list[str]:
    return [
        "<Signature>",
        f'  <Reference URI="#{ref}" xmlns="{NS_SIGNATURE}">',
        "    <Transforms>",
        '      <Transform Algorithm="urn:vecto:xml:2017:canonicalization" />',
        "    </Transforms>",
        '    <DigestMethod Algorithm="http://www.w3.org/2001/04/xmlenc#sha256" />',
        "    <DigestValue></DigestValue>",
        "  </Reference>",
        "</Signature>",
    ]


def _indent(lines: list[str], depth: int) -> list[str]:
    return ["  " * depth + line for line in lines]


def _component(name: str, ident: str, data: list[str]) -> list[str]:
    """A signed component: its ``Data`` and ``Signature``."""
    return [
        f"<{name}>",
        f'  <Data id="{ident}">',
        *_indent(data, 2),
        "  </Data>",
        *_indent(_signature(ident), 1),
        f"</{name}>",
    ]


def _head(ident: str, model: str) -> list[str]:
    return [
        "<Manufacturer>truckmpc tests</Manufacturer>",
        f"<Model>{model}</Model>",
        f"<CertificationNumber>{ident}</CertificationNumber>",
        "<Date>2017-09-20T12:56:09.2147847Z</Date>",
        "<AppVersion>VectoCore</AppVersion>",
    ]


def _loss_map(base_nm: float) -> list[str]:
    rows = [
        f'  <Entry inputSpeed="{n:.2f}" inputTorque="{t:.2f}" torqueLoss="{loss_nm(base_nm, t):.2f}" />'
        for n in LOSS_SPEEDS_RPM
        for t in LOSS_TORQUES_NM
    ]
    return ["<TorqueLossMap>", *rows, "</TorqueLossMap>"]


def _engine() -> list[str]:
    fuel = [
        f'  <Entry engineSpeed="{n:.2f}" torque="{t:.2f}" fuelConsumption="{2 * n + 10 * t + 5000:.2f}" />'
        for n in range(600, 2001, 200)
        for t in range(-200, 2001, 200)
    ]
    fld = [
        f'  <Entry engineSpeed="{n:.2f}" maxTorque="{1800 + (n - 600) * 0.1:.2f}" '
        f'dragTorque="{-150 - (n - 600) * 0.02:.2f}" />'
        for n in range(600, 2001, 200)
    ]
    data = [
        *_head("ENG-test", "test"),
        f"<Displacement>{DISPLACEMENT_CM3}</Displacement>",
        "<IdlingSpeed>600</IdlingSpeed>",
        "<RatedSpeed>1800</RatedSpeed>",
        "<RatedPower>330000</RatedPower>",
        "<MaxEngineTorque>1920</MaxEngineTorque>",
        *[f"<{k}>1.0000</{k}>" for k in ("WHTCUrban", "WHTCRural", "WHTCMotorway", "BFColdHot", "CFRegPer", "CFNCV")],
        "<FuelType>Diesel CI</FuelType>",
        "<FuelConsumptionMap>",
        *fuel,
        "</FuelConsumptionMap>",
        "<FullLoadAndDragCurve>",
        *fld,
        "</FullLoadAndDragCurve>",
    ]
    return _component("Engine", "ENG-test", data)


def _gearbox() -> list[str]:
    gears = []
    for k, (ratio, base) in enumerate(zip(GEAR_RATIOS, GEAR_LOSS_BASE_NM, strict=True), start=1):
        gears += [f'<Gear number="{k}">', f"  <Ratio>{ratio:.3f}</Ratio>", *_indent(_loss_map(base), 1), "</Gear>"]
    data = [
        *_head("GBX-g3", "g3"),
        "<TransmissionType>AMT</TransmissionType>",
        "<MainCertificationMethod>Standard values</MainCertificationMethod>",
        "<Gears>",
        *_indent(gears, 1),
        "</Gears>",
    ]
    return _component("Gearbox", "GBX-g3", data)


def _retarder() -> list[str]:
    data = [
        *_head("RET-test", "retarder"),
        "<CertificationMethod>Standard values</CertificationMethod>",
        "<RetarderLossMap>",
        *[f'  <Entry retarderSpeed="{n:.2f}" torqueLoss="{10 + n / 100:.2f}" />' for n in (0, 1000, 2000)],
        "</RetarderLossMap>",
    ]
    return _component("Retarder", "RET-test", data)


def _axlegear() -> list[str]:
    data = [
        *_head("AXL-2.5", "axle"),
        "<LineType>Single portal axle</LineType>",
        f"<Ratio>{AXLE_RATIO:.3f}</Ratio>",
        "<CertificationMethod>Standard values</CertificationMethod>",
        *_loss_map(AXLE_LOSS_BASE_NM),
    ]
    return _component("Axlegear", "AXL-2.5", data)


def _axle(number: int, kind: str, twin: bool, steered: bool) -> list[str]:
    tyre = [
        *_head("TYRE-315_70R22.5", "315/70 R22.5"),
        "<Dimension>315/70 R22.5</Dimension>",
        "<RRCDeclared>0.0060</RRCDeclared>",
        "<FzISO>33350</FzISO>",
    ]
    return [
        f'<Axle axleNumber="{number}">',
        f"  <AxleType>{kind}</AxleType>",
        f"  <TwinTyres>{str(twin).lower()}</TwinTyres>",
        f"  <Steered>{str(steered).lower()}</Steered>",
        "  <Tyre>",
        '    <Data id="TYRE-315_70R22.5">',
        *_indent(tyre, 3),
        "    </Data>",
        *_indent(_signature("TYRE-315_70R22.5"), 2),
        "  </Tyre>",
        "</Axle>",
    ]


def _rest() -> list[str]:
    axles = _axle(1, "VehicleNonDriven", False, True) + _axle(2, "VehicleDriven", True, False)
    aux = []
    for entry in AUX:
        element = _AUX_ELEMENTS[entry["ID"]]
        aux += [f"<{element}>", f"  <Technology>{entry['Technology'][0]}</Technology>", f"</{element}>"]
    air = [*_head("AIR-test", "test"), *[f"<{k}>5.50</{k}>" for k in ("CdxA_0", "TransferredCdxA", "DeclaredCdxA")]]
    return [
        "<AxleWheels>",
        "  <Data>",
        "    <Axles>",
        *_indent(axles, 3),
        "    </Axles>",
        "  </Data>",
        "</AxleWheels>",
        "<Auxiliaries>",
        "  <Data>",
        *_indent(aux, 2),
        "  </Data>",
        "</Auxiliaries>",
        "<AirDrag>",
        '  <Data id="AIR-test">',
        *_indent(air, 2),
        "  </Data>",
        *_indent(_signature("AIR-test"), 1),
        "</AirDrag>",
    ]


def write_xml_job(folder: Path) -> Path:
    """A complete small VECTO declaration XML file ``t.xml`` in ``folder``: a 4x2 tractor of 8000 kg
    (18 t gross), Cd·A 5.5 m², the engine of :func:`vecto_files.write_job` (12 l, its full-load curve
    and plane fuel map), an AMT with ratios 4, 2, 1 and the axle's 2.5, each with a loss map over
    :data:`LOSS_SPEEDS_RPM` × :data:`LOSS_TORQUES_NM`, a retarder, and the JSON job's auxiliaries.
    Returns the file's path."""
    folder.mkdir(parents=True, exist_ok=True)
    components = _engine() + _gearbox() + _retarder() + _axlegear() + _rest()
    vehicle = [
        "<Manufacturer>truckmpc tests</Manufacturer>",
        "<ManufacturerAddress>N.A.</ManufacturerAddress>",
        "<Model>N.A.</Model>",
        "<VIN>N.A.</VIN>",
        "<Date>2017-09-20T12:56:08.9227555Z</Date>",
        "<LegislativeClass>N3</LegislativeClass>",
        "<VehicleCategory>Tractor</VehicleCategory>",
        "<AxleConfiguration>4x2</AxleConfiguration>",
        "<CurbMassChassis>8000</CurbMassChassis>",
        "<GrossVehicleMass>18000</GrossVehicleMass>",
        "<IdlingSpeed>600</IdlingSpeed>",
        "<RetarderType>Transmission Output Retarder</RetarderType>",
        "<RetarderRatio>1.000</RetarderRatio>",
        "<AngledriveType>None</AngledriveType>",
        "<PTO>",
        "  <PTOShaftsGearWheels>none</PTOShaftsGearWheels>",
        "  <PTOOtherElements>none</PTOOtherElements>",
        "</PTO>",
        "<Components>",
        *_indent(components, 1),
        "</Components>",
    ]
    lines = [
        '<?xml version="1.0" encoding="utf-8"?>',
        f'<tns:VectoInputDeclaration schemaVersion="1.0" xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance" '
        f'xmlns="{NS_DEFINITIONS}" xmlns:tns="{NS_INPUT}">',
        '  <Vehicle id="VEH-test">',
        *_indent(vehicle, 2),
        "  </Vehicle>",
        "</tns:VectoInputDeclaration>",
    ]
    path = folder / "t.xml"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path

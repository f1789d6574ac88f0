"""A VECTO declaration XML file, whichever truck it declares: a diesel truck
(:mod:`truckmpc.vecto.xml_job`) or a battery-electric one (:mod:`truckmpc.vecto.electric_xml`)."""

from __future__ import annotations

from pathlib import Path

from truckmpc.vecto.components import VectoJob
from truckmpc.vecto.electric import ElectricTruckJob
from truckmpc.vecto.electric_xml import is_electric, read_electric_xml
from truckmpc.vecto.xml_job import declared_vehicle, job_of

__all__ = ["read_declaration_xml"]


def read_declaration_xml(path: Path) -> VectoJob | ElectricTruckJob:
    """The truck a VECTO declaration XML file declares."""
    vehicle = declared_vehicle(path)
    return read_electric_xml(path, vehicle) if is_electric(vehicle) else job_of(path, vehicle)

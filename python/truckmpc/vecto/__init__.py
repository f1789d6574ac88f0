"""Trucks from VECTO's component files: a ``.vecto`` job with the vehicle, engine (full-load curve,
fuel map) and gearbox files it names, made into a truck the core simulates with what VECTO's
declaration mode adds (trailer, load, cross-wind corrected air drag, the combination's rolling
resistance, auxiliaries).

Modules, bottom up: :mod:`~truckmpc.vecto.files` (VECTO's JSON and CSV formats),
:mod:`~truckmpc.vecto.components` (the job and its components, checked),
:mod:`~truckmpc.vecto.declaration` (VECTO's declaration tables and formulas),
:mod:`~truckmpc.vecto.truck` (the truck, with keys a user can override).
"""

from truckmpc.vecto.components import VectoJob, read_job
from truckmpc.vecto.truck import TruckKeys, VectoTruck, load_vecto_truck

__all__ = ["TruckKeys", "VectoJob", "VectoTruck", "load_vecto_truck", "read_job"]

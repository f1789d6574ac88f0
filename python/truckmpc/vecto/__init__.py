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
from truckmpc.vecto.truck import TRUCK_KEYS, VectoTruck, load_vecto_truck, truck_values

__all__ = ["TRUCK_KEYS", "VectoJob", "VectoTruck", "load_vecto_truck", "read_job", "truck_values"]

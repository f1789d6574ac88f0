"""A VECTO truck in a run's record (``summary.json``): every component file with its SHA-256 and
the truck's keys set to other than their defaults, so that ``--replay`` rebuilds the same truck or
refuses a file that changed.
"""

from __future__ import annotations

import hashlib
from pathlib import Path
from typing import Any

from truckmpc.errors import ConfigError
from truckmpc.vecto.truck import AnyVectoTruck, truck_values

__all__ = ["check_read_files", "recorded_job", "truck_record"]

_DEFAULTS = truck_values()


def truck_record(truck: AnyVectoTruck) -> dict[str, Any]:
    """The ``run.vehicle`` record of a run driving ``truck``: the job, each file it read with its
    SHA-256, the keys set to other than their defaults, and the masses they resolved to [kg]."""
    job = truck.job
    return {
        "vecto_job": str(Path(job.path).resolve()),
        "files": {str(Path(p).resolve()): _sha256(Path(p)) for p in job.files},
        "keys": {k: v for k, v in truck.keys.items() if v != _DEFAULTS[k]},
        "mass_kg": truck.mass_kg,
        "payload_kg": truck.payload_kg,
        "trailer_mass_kg": truck.trailer_mass_kg,
    }


def recorded_job(record: Any, where: str) -> tuple[Path, dict[str, Any]] | None:
    """The job a ``run.vehicle`` record names and the truck's keys it records (None for a run of
    the thesis's truck); every file must still hash as recorded."""
    if record is None:
        return None
    key = f"{where}: run.vehicle"
    if not isinstance(record, dict) or not isinstance(record.get("files"), dict):
        raise ConfigError(f"{key}: expected a record with 'vecto_job', 'files' and 'keys', got {record!r:.60}")
    for name, recorded in record["files"].items():
        path = Path(name)
        got = _sha256(path) if path.is_file() else "a missing file"
        if got != recorded:
            shown = got if got == "a missing file" else got[:12] + "..."
            raise ConfigError(f"{key}.files: expected {name} as it was run ({str(recorded)[:12]}...), got {shown}")
    job, keys = record.get("vecto_job"), record.get("keys", {})
    if not isinstance(job, str) or not isinstance(keys, dict):
        raise ConfigError(f"{key}: expected 'vecto_job' a path and 'keys' a mapping, got {job!r}, {keys!r}")
    return Path(job), keys


def check_read_files(truck: AnyVectoTruck, record: dict[str, Any], where: str) -> None:
    """A file the job names that was missing then (a loss map) and is there now changes the truck."""
    added = sorted({str(Path(p).resolve()) for p in truck.job.files} - set(record["files"]))
    if added:
        raise ConfigError(
            f"{where}: run.vehicle.files: expected the files the run read, got {added[0]} too (not there when it ran)"
        )


def _sha256(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()

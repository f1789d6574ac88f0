"""A run's configuration, layered from files and overrides and validated once, by the Rust core.

Layers, each overriding the previous:

1. a vehicle file (default: the packaged `truck-40t.yaml`), which must give every vehicle key;
   with a VECTO job (`.vecto`, `.xml`) as the vehicle, the packaged truck's file;
2. the packaged defaults of the other sections (`cruise.yaml`, `pi.yaml`, `mpc.yaml`,
   `pcc.yaml`, `simulation.yaml`, `vecto.yaml`, generated from the declarations);
3. with a VECTO job, the truck's: VECTO's air density, and once the truck is built from the layers'
   values of its keys, the vehicle keys its components give and the PI's shift speeds for its engine;
4. overlay files (`config_paths`): flat YAML mappings of any non-vehicle keys; a name without a
   path that is no file names a packaged preset (`thesis`: the thesis's controller as printed);
5. `key=value` overrides (the CLI's `--set`), for any key; the value is YAML.

Every value remembers where it came from (`file:line` or `--set key`), so an error from the core,
which names the key (and the other keys a cross-key check involved) as data, is reported against
the origin the user set last: `--set v_ref_kmh=5` is blamed, not the packaged `v_dec_kmh`.
"""

from __future__ import annotations

import os
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from truckmpc import _core
from truckmpc.config.keys import (
    KEYS,
    SECTION_FILES,
    SPEC_BY_KEY,
    VEHICLE_KEYS,
    default_config_path,
    overlay_path,
    section_keys,
    unknown_key,
)
from truckmpc.config.layers import Layers, Origin, problem
from truckmpc.config.vecto_truck import VECTO_VALUES, build_truck, is_vecto_job, refuse_thesis_key, truck_layer
from truckmpc.config.yamlfile import parse_assignment
from truckmpc.errors import ConfigError
from truckmpc.vecto.truck import AnyVectoTruck

PathLike = str | os.PathLike[str]
__all__ = ["Origin", "RunConfig", "Section", "config_from_values", "load_run_config"]


class Section(Mapping[str, Any]):
    """The resolved values of one section, read-only; keys are also attributes (`mpc.stage_m`).
    Lists are tuples."""

    def __init__(self, name: str, values: Mapping[str, Any]) -> None:
        self._name = name
        self._values = {k: tuple(v) if isinstance(v, list) else v for k, v in values.items()}

    def __getattr__(self, key: str) -> Any:
        try:
            return self.__dict__["_values"][key]
        except KeyError:
            raise AttributeError(f"section {self.__dict__.get('_name')!r} has no key {key!r}") from None

    def __setattr__(self, key: str, value: Any) -> None:
        if key.startswith("_"):
            object.__setattr__(self, key, value)
        else:
            raise AttributeError(f"settings are read-only: {key}")

    def __getitem__(self, key: str) -> Any:
        return self._values[key]

    def __iter__(self) -> Iterator[str]:
        return iter(self._values)

    def __len__(self) -> int:
        return len(self._values)

    def __repr__(self) -> str:
        return f"Section({self._name!r}, {self._values!r})"


@dataclass(frozen=True)
class RunConfig:
    """Every setting of a run: the validated core settings and where each value came from."""

    settings: _core.Settings
    origins: Mapping[str, Origin] = field(repr=False)
    truck: AnyVectoTruck | None = field(default=None, repr=False)
    """The VECTO truck the run drives, when the vehicle is a VECTO job (None: the thesis's model)."""

    def section(self, name: str) -> Section:
        """The values of one section (`vehicle`, `cruise`, `pi`, `mpc`, `sim`)."""
        return Section(name, {key: self.settings.get(key) for key in section_keys(name)})

    @property
    def vehicle(self) -> Section:
        return self.section("vehicle")

    @property
    def cruise(self) -> Section:
        return self.section("cruise")

    @property
    def pi(self) -> Section:
        return self.section("pi")

    @property
    def mpc(self) -> Section:
        return self.section("mpc")

    @property
    def sim(self) -> Section:
        return self.section("sim")

    @property
    def core_vehicle(self) -> _core.Vehicle:
        """The validated Rust vehicle model."""
        return self.settings.vehicle

    @property
    def v_max_kmh(self) -> float:
        """v_max = v_ref + v_inc [km/h], above which the PI brakes."""
        return float(self.cruise.v_ref_kmh + self.cruise.v_inc_kmh)

    @property
    def is_electric(self) -> bool:
        """Whether the truck is battery-electric (its runs draw battery energy, not fuel)."""
        return self.truck is not None and self.truck.core.is_electric

    def with_values(self, changes: Mapping[str, Any], where: str) -> RunConfig:
        """This configuration with `changes` (key: user value) made and checked by the core, the same
        truck: the runs a study derives from this one. An error names `where` and the key."""
        try:
            settings = self.settings.with_values(dict(changes))
        except _core.ParamError as err:
            raise ConfigError(f"{Origin(where, 0).where(err.key)}: {problem(err)}") from None
        rank = max((origin.rank for origin in self.origins.values()), default=0) + 1
        origins = {**self.origins, **{key: Origin(where, rank) for key in changes}}
        return RunConfig(settings=settings, origins=origins, truck=self.truck)

    def with_truck_values(self, changes: Mapping[str, Any], where: str) -> RunConfig:
        """This configuration's VECTO truck built again with `changes` to its keys (``payload_kg``:
        the same truck at another load), the run's keys the truck sets (its mass among them)
        following it; every other key as it is. An error names `where` and the key."""
        if self.truck is None:
            raise ConfigError(f"{where}: expected a VECTO truck, got the thesis's truck (its keys are run keys)")
        job = self.truck.job.path
        layers = Layers()
        layers.rank = max((origin.rank for origin in self.origins.values()), default=0) + 1
        for key, value in self.settings.values().items():
            origin = self.origins.get(key, Origin(where, 0))
            layers.put_under(key, value, origin.text, origin.rank)
        for key, value in changes.items():
            layers.put(key, value, where)
        truck = build_truck(job, layers)
        # What the old truck set follows the new one; what a user set over it stays.
        for key, value in truck_layer(truck).items():
            set_by = layers.origins.get(key)
            if set_by is None or set_by.text == str(job):
                layers.put_under(key, value, str(job), set_by.rank if set_by else 0)
        return _build(layers, truck)

    def sources(self) -> list[str]:
        """The files and overrides the values came from, in layer order, each once."""
        ordered = sorted(self.origins.values(), key=lambda origin: origin.rank)
        return list(dict.fromkeys(origin.text.split(":")[0] for origin in ordered))

    def as_dict(self) -> dict[str, Any]:
        """Plain data (YAML/JSON-ready): every section's values, and the sources."""
        data: dict[str, Any] = {}
        for key, value in self.settings.values().items():
            data.setdefault(SPEC_BY_KEY[key].section, {})[key] = value
        data["sources"] = self.sources()
        return data


def load_run_config(
    vehicle_path: PathLike | None = None,
    config_paths: Sequence[PathLike] = (),
    overrides: Sequence[str] = (),
) -> RunConfig:
    """Load a run's configuration: vehicle file (default: packaged 40 t truck), the packaged
    defaults of the other sections, overlay files in order, then `key=value` overrides."""
    layers = Layers()
    vehicle_file = default_config_path("truck-40t.yaml") if vehicle_path is None else vehicle_path
    # A VECTO job replaces the thesis's truck; its file of defaults still gives the brakes.
    job = Path(vehicle_file) if is_vecto_job(vehicle_file) else None
    layers.read_file(default_config_path("truck-40t.yaml") if job else vehicle_file, VEHICLE_KEYS, True, False)
    others = [key for key in KEYS if key not in VEHICLE_KEYS]
    for section, name in SECTION_FILES.items():
        allowed = [k for k in others if SPEC_BY_KEY[k].section == section]
        layers.read_file(default_config_path(name), allowed, complete=True, refuse_vehicle=False)
    truck_rank = layers.rank + 1
    if job is not None:
        layers.next_layer()
        for key, value in VECTO_VALUES.items():
            layers.put(key, value, str(job))
    for path in config_paths:
        layers.read_file(overlay_path(path), others, complete=False, refuse_vehicle=True)
    for text in overrides:
        key, value = parse_assignment(text)
        if job is not None:
            refuse_thesis_key(key, job)
        layers.override(key, value, KEYS)
    truck = None if job is None else build_truck(job, layers)
    if truck is not None:
        for key, value in truck_layer(truck).items():
            layers.put_under(key, value, str(truck.job.path), truck_rank)
    return _build(layers, truck)


def config_from_values(values: Mapping[str, Any], where: str, job: Path | None = None) -> RunConfig:
    """A configuration from a complete flat mapping of keys to values (a recorded run's settings),
    driving the VECTO truck of `job` (built from the values) when given; errors name `where` and
    the key."""
    layers = Layers()
    layers.next_layer()
    for key, raw in values.items():
        if key not in KEYS:
            raise unknown_key(where, key, KEYS)
        layers.put(key, raw, where)
    missing = [key for key in KEYS if key not in values]
    if missing:
        raise ConfigError(f"{where}: missing key {missing[0]!r} (a recorded run gives every parameter)")
    return _build(layers, None if job is None else build_truck(job, layers))


def _build(layers: Layers, truck: AnyVectoTruck | None) -> RunConfig:
    """The run's settings, built once by the core with `truck`; an error names the value's origin."""
    core_truck = None if truck is None else truck.core

    def fails(values: dict[str, Any]) -> bool:
        try:
            _core.Settings(values, core_truck)
        except _core.ParamError:
            return True
        return False

    try:
        settings = _core.Settings(layers.values, core_truck)
    except _core.ParamError as err:
        raise layers.blame(err, fails) from None
    return RunConfig(settings=settings, origins=dict(layers.origins), truck=truck)

"""A run's configuration, layered from files and overrides and validated once, by the Rust core.

Layers, each overriding the previous:

1. a vehicle file (default: the packaged `truck-40t.yaml`), which must give every vehicle key;
2. the packaged defaults of the other sections (`cruise.yaml`, `pi.yaml`, `mpc.yaml`,
   `simulation.yaml`, generated from the declarations);
3. overlay files (`config_paths`): flat YAML mappings of any non-vehicle keys; a name without a
   path that is no file names a packaged preset (`thesis`: the thesis's controller as printed);
4. `key=value` overrides (the CLI's `--set`), for any key; the value is YAML.

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

import yaml

from truckmpc import _core
from truckmpc.config.keys import (
    KEYS,
    SECTION_FILES,
    SPEC_BY_KEY,
    VEHICLE_KEYS,
    default_config_path,
    overlay_path,
    unknown_key,
)
from truckmpc.config.vecto_truck import is_vecto_job, truck_layer, vecto_truck
from truckmpc.config.yamlfile import load_value, read_mapping, show_value
from truckmpc.errors import ConfigError
from truckmpc.vecto.truck import VectoTruck

PathLike = str | os.PathLike[str]


@dataclass(frozen=True)
class Origin:
    """Where a value came from: a file (and line), or a `--set` override; `rank` orders the layers
    (every key of one file has the same rank)."""

    text: str
    rank: int

    def where(self, key: str) -> str:
        """Prefix of a message about `key` from here: `file:line: key 'k'`, or `--set k`."""
        return self.text if self.text.startswith("--set ") else f"{self.text}: key {key!r}"


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
    truck: VectoTruck | None = field(default=None, repr=False)
    """The VECTO truck the run drives, when the vehicle is a VECTO job (None: the thesis's model)."""

    def section(self, name: str) -> Section:
        """The values of one section (`vehicle`, `cruise`, `pi`, `mpc`, `sim`)."""
        values = self.settings.values()
        return Section(name, {k: v for k, v in values.items() if SPEC_BY_KEY[k].section == name})

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

    def with_values(self, changes: Mapping[str, Any], where: str) -> RunConfig:
        """This configuration with `changes` (key: user value) made and checked by the core, the same
        truck: the runs a study derives from this one. An error names `where` and the key."""
        try:
            settings = self.settings.with_values(dict(changes))
        except _core.ParamError as err:
            got = "" if err.got is None else f", got {err.got}"
            raise ConfigError(f"{where}: key {err.key!r}: expected {err.expected}{got}") from None
        rank = max((origin.rank for origin in self.origins.values()), default=0) + 1
        origins = {**self.origins, **{key: Origin(where, rank) for key in changes}}
        return RunConfig(settings=settings, origins=origins, truck=self.truck)

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


class _Layers:
    """Raw values by key, each with its origin, in the order the layers set them."""

    def __init__(self) -> None:
        self.values: dict[str, Any] = {}
        self.origins: dict[str, Origin] = {}
        self._rank = 0

    def put(self, key: str, raw: Any, origin_text: str) -> None:
        """Set `key` in the current layer (call `next_layer` between files and overrides)."""
        self.values[key] = raw
        self.origins[key] = Origin(origin_text, self._rank)

    def next_layer(self) -> None:
        self._rank += 1

    def read_file(self, path: PathLike, allowed: Sequence[str], complete: bool, refuse_vehicle: bool) -> None:
        data, where, lines = read_mapping(path)
        self.next_layer()
        for key, raw in data.items():
            if refuse_vehicle and key in VEHICLE_KEYS:
                raise ConfigError(
                    f"{where}: key {key!r} is a vehicle parameter: set it in the vehicle file or with --set {key}=..."
                )
            at = f"{where}:{lines[key]}" if key in lines else where
            if key not in allowed:
                raise unknown_key(at, key, allowed)
            self.put(key, raw, at)
        missing = [key for key in allowed if key not in data]
        if complete and missing:
            shown = ", ".join(repr(key) for key in missing[:4])
            what = f"missing key {shown}" if len(missing) == 1 else f"missing {len(missing)} keys: {shown}"
            more = ", ..." if len(missing) > 4 else ""
            raise ConfigError(f"{where}: {what}{more} (a file of defaults must give every parameter)")

    def override(self, text: str) -> None:
        key, sep, raw_text = text.partition("=")
        key = key.strip()
        if not sep or not key:
            raise ConfigError(f"--set {text!r}: expected key=value")
        origin = f"--set {key}"
        if key not in KEYS:
            raise unknown_key(origin, key, KEYS)
        try:
            raw = load_value(raw_text)
        except yaml.YAMLError as err:
            problem = getattr(err, "problem", None) or str(err) or "syntax error"
            shown = show_value(raw_text.strip())
            raise ConfigError(f"{origin}: value {shown} is not valid YAML ({problem})") from None
        self.next_layer()
        self.put(key, raw, origin)

    def build(self, truck: VectoTruck | None = None) -> RunConfig:
        try:
            settings = _core.Settings(self.values, None if truck is None else truck.core)
        except _core.ParamError as err:
            raise self._blame(err) from None
        return RunConfig(settings=settings, origins=dict(self.origins), truck=truck)

    def _blame(self, err: _core.ParamError) -> ConfigError:
        """The error against the origin of the key the user set last among those the check involved
        (the key itself when several were set in the same layer)."""
        involved = [k for k in (err.key, *err.related) if k in self.origins]
        if not involved:
            return ConfigError(str(err))
        culprit = max(involved, key=lambda k: self.origins[k].rank)
        detail = f"expected {err.expected}" + ("" if err.got is None else f", got {err.got}")
        if culprit == err.key:
            return ConfigError(f"{self.origins[err.key].where(err.key)}: {detail}")
        return ConfigError(f"{self.origins[culprit].where(culprit)}: {err.key}: {detail}")


def load_run_config(
    vehicle_path: PathLike | None = None,
    config_paths: Sequence[PathLike] = (),
    overrides: Sequence[str] = (),
) -> RunConfig:
    """Load a run's configuration: vehicle file (default: packaged 40 t truck), the packaged
    defaults of the other sections, overlay files in order, then `key=value` overrides."""
    layers = _Layers()
    vehicle_file = default_config_path("truck-40t.yaml") if vehicle_path is None else vehicle_path
    truck = None
    if is_vecto_job(vehicle_file):
        # The VECTO job replaces the thesis's truck; its file of defaults still gives the brakes.
        truck, overrides = vecto_truck(Path(vehicle_file), overrides)
        vehicle_file = default_config_path("truck-40t.yaml")
    layers.read_file(vehicle_file, VEHICLE_KEYS, complete=True, refuse_vehicle=False)
    others = [key for key in KEYS if key not in VEHICLE_KEYS]
    for section, name in SECTION_FILES.items():
        allowed = [k for k in others if SPEC_BY_KEY[k].section == section]
        layers.read_file(default_config_path(name), allowed, complete=True, refuse_vehicle=False)
    if truck is not None:
        layers.next_layer()
        for key, value in truck_layer(truck).items():
            layers.put(key, value, str(truck.job.path))
    for path in config_paths:
        layers.read_file(overlay_path(path), others, complete=False, refuse_vehicle=True)
    for text in overrides:
        layers.override(text)
    return layers.build(truck)


def config_from_values(values: Mapping[str, Any], where: str, truck: VectoTruck | None = None) -> RunConfig:
    """A configuration from a complete flat mapping of keys to values (a recorded run's settings),
    driving `truck` when given (a configuration's own, to keep it); errors name `where` and the key."""
    layers = _Layers()
    layers.next_layer()
    for key, raw in values.items():
        if key not in KEYS:
            raise unknown_key(where, key, KEYS)
        layers.put(key, raw, where)
    missing = [key for key in KEYS if key not in values]
    if missing:
        raise ConfigError(f"{where}: missing key {missing[0]!r} (a recorded run gives every parameter)")
    return layers.build(truck)

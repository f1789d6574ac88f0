"""Configuration: the vehicle, the controllers and the simulation, read from YAML files.

A run is configured in three layers, each overriding the previous:

1. the packaged defaults (`configs/*.yaml`: truck-40t, pi, simulation), or a vehicle file;
2. overlay files (`config_paths`): flat YAML mappings whose keys may be any controller or
   simulation key; a key that several sections share (e.g. `v_ref_kmh`) is set in all of them;
3. `key=value` overrides (the CLI's `--set`), for any vehicle, controller or simulation key.

Every value is checked where it enters, so an error names the file (or `--set key`) it came from.
Vehicle ranges are checked by the Rust core (`truckmpc._core.Vehicle`), not here.

Controller and simulation settings are *sections* in a registry (`SECTIONS`); a new section (e.g.
the MPC's) is a frozen dataclass, a table of key parsers, a build function and one `Section(...)`.
"""

from __future__ import annotations

import dataclasses
import difflib
import math
import os
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml

from . import _core
from .errors import ConfigError, read_user_text

__all__ = [
    "SECTIONS",
    "PiConfig",
    "RunConfig",
    "Section",
    "SimConfig",
    "VehicleConfig",
    "default_config_path",
    "load_pi",
    "load_run_config",
    "load_sections",
    "load_sim",
    "load_vehicle",
]

PathLike = str | os.PathLike[str]
_CONFIG_DIR = Path(__file__).resolve().parent / "configs"
VEHICLE_KEYS: tuple[str, ...] = tuple(_core.Vehicle.parameter_names())
_VEHICLE_LIST_KEYS = frozenset({"gear_ratios", "gear_efficiencies"})


def default_config_path(name: str) -> Path:
    """Path of a packaged default configuration file, e.g. `"pi.yaml"` or `"truck-20t.yaml"`."""
    path = _CONFIG_DIR / name
    if not path.is_file():
        available = ", ".join(sorted(p.name for p in _CONFIG_DIR.glob("*.yaml")))
        raise ConfigError(f"no packaged config named {name!r} (available: {available})")
    return path


# ---------------------------------------------------------------------------------------------
# Value parsing. A parser turns a raw YAML value into a checked Python value or raises _Invalid
# with what was expected; the caller adds where the value came from.


class _Invalid(Exception):
    """A value (or, from a build function, the value of `key`) is not what was expected."""

    def __init__(self, expected: str, got: Any = None, key: str | None = None, show_got: bool = True) -> None:
        super().__init__(expected)
        self.expected, self.got, self.key, self.show_got = expected, got, key, show_got

    def text(self) -> str:
        return f"expected {self.expected}, got {_show(self.got)}" if self.show_got else f"expected {self.expected}"


Parser = Callable[[Any], Any]


def _show(value: Any) -> str:
    """A value as the user wrote it, briefly."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if value is None:
        return "null"
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def _to_float(value: Any, what: str = "a number") -> float:
    """A finite float from an int, float or numeric string (PyYAML reads `1e5` as a string)."""
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        raise _Invalid(what, value)
    try:
        number = float(value)
    except ValueError:
        raise _Invalid(what, value) from None
    if not math.isfinite(number):
        raise _Invalid(f"a finite number{what.removeprefix('a number')}", value)
    return number


def _number(
    minimum: float | None = None, *, above: bool = False, maximum: float | None = None, why: str = ""
) -> Parser:
    """Parser of a finite number, optionally bounded: > or >= `minimum`, <= `maximum`."""
    if minimum is not None and maximum is not None:
        expected = f"a number in {'(' if above else '['}{minimum:g}, {maximum:g}]"
    elif minimum is not None:
        expected = f"a number {'>' if above else '>='} {minimum:g}"
    else:
        expected = "a number"
    expected += f" ({why})" if why else ""

    def parse(value: Any) -> float:
        number = _to_float(value, expected)
        too_low = minimum is not None and (number <= minimum if above else number < minimum)
        if too_low or (maximum is not None and number > maximum):
            raise _Invalid(expected, value)
        return number

    return parse


def _optional(parser: Parser) -> Parser:
    """Parser that also accepts null (None)."""
    return lambda value: None if value is None else parser(value)


def _rpm_list(value: Any) -> tuple[float | None, ...]:
    """A list of engine speeds [rpm] > 0, null where a gear has no threshold."""
    expected = "a list of engine speeds in rpm (numbers > 0, or null)"
    if not isinstance(value, list) or not value:
        raise _Invalid(expected, value)
    result = []
    for item in value:
        if item is None:
            result.append(None)
            continue
        speed = _to_float(item, expected)
        if speed <= 0:
            raise _Invalid(expected, value)
        result.append(speed)
    return tuple(result)


def _number_list(value: Any) -> list[float]:
    if not isinstance(value, list):
        raise _Invalid("a list of numbers", value)
    return [_to_float(item, "a list of numbers") for item in value]


# ---------------------------------------------------------------------------------------------
# Reading YAML.


class _StrictLoader(yaml.SafeLoader):
    """Safe loader that rejects a key given twice in one mapping (PyYAML keeps the last silently)."""


def _construct_mapping(loader: _StrictLoader, node: yaml.MappingNode, deep: bool = False) -> dict[Any, Any]:
    seen: set[Any] = set()
    for key_node, _ in node.value:
        key = loader.construct_object(key_node, deep=deep)
        if not isinstance(key, str):
            continue
        if key in seen:
            raise yaml.constructor.ConstructorError(None, None, f"key {key!r} given twice", key_node.start_mark)
        seen.add(key)
    return loader.construct_mapping(node, deep=deep)


_StrictLoader.add_constructor(yaml.resolver.BaseResolver.DEFAULT_MAPPING_TAG, _construct_mapping)


def _display(path: Path) -> str:
    """How a file is named in messages: relative to the working directory when it is below it."""
    try:
        return str(path.resolve().relative_to(Path.cwd().resolve()))
    except ValueError:
        return str(path)


def _read_mapping(path: PathLike) -> tuple[dict[str, Any], str]:
    """The top-level mapping of a YAML file and the file's display name."""
    path = Path(path)
    where = _display(path)
    text = read_user_text(path, where, "a YAML file", ConfigError)
    try:
        data = yaml.load(text, Loader=_StrictLoader)
    except yaml.MarkedYAMLError as err:
        line = f":{err.problem_mark.line + 1}" if err.problem_mark is not None else ""
        raise ConfigError(f"{where}{line}: invalid YAML: {err.problem or err.context}") from None
    except yaml.YAMLError as err:
        raise ConfigError(f"{where}: invalid YAML: {err}") from None
    if data is None:
        data = {}
    if not isinstance(data, dict):
        raise ConfigError(f"{where}: expected a mapping of key: value at the top level, got {type(data).__name__}")
    for key in data:
        if not isinstance(key, str):
            raise ConfigError(f"{where}: key {_show(key)}: expected a text key")
    return data, where


def _where(origin: str, key: str) -> str:
    """Prefix naming a value's origin: `file: key 'k'`, or `--set k` for an override."""
    return origin if origin.startswith("--set ") else f"{origin}: key {key!r}"


def _missing_text(missing: Sequence[str]) -> str:
    shown = ", ".join(repr(key) for key in missing[:4])
    if len(missing) == 1:
        return f"missing key {shown}"
    return f"missing {len(missing)} keys: {shown}{', ...' if len(missing) > 4 else ''}"


def _unknown_key(origin: str, key: str, known: Sequence[str]) -> ConfigError:
    close = difflib.get_close_matches(key, list(known), n=1)
    hint = f" (did you mean {close[0]!r}?)" if close else ""
    if origin.startswith("--set "):
        return ConfigError(f"{origin}: unknown key{hint}")
    return ConfigError(f"{origin}: unknown key {key!r}{hint}")


@dataclass
class _Value:
    """A parsed value and where it came from (file name or `--set key`)."""

    value: Any
    origin: str


def _parse_into(target: dict[str, _Value], key: str, raw: Any, parser: Parser, origin: str) -> None:
    try:
        target[key] = _Value(parser(raw), origin)
    except _Invalid as err:
        raise ConfigError(f"{_where(origin, key)}: {err.text()}") from None


# ---------------------------------------------------------------------------------------------
# The vehicle.


@dataclass(frozen=True)
class VehicleConfig:
    """Vehicle parameters (keys and units as `truckmpc._core.Vehicle.parameter_names()`).

    `params` maps each key to a float, or to a list of floats for `gear_ratios` and
    `gear_efficiencies`; treat it as read-only. `source` names where the values came from.
    """

    params: dict[str, Any]
    source: str
    _vehicle: Any = field(default=None, init=False, repr=False, compare=False)

    def core(self) -> _core.Vehicle:
        """The validated Rust vehicle model, built once."""
        if self._vehicle is None:
            vehicle = _build_vehicle({k: _Value(v, self.source) for k, v in self.params.items()})
            object.__setattr__(self, "_vehicle", vehicle)
        return self._vehicle

    @property
    def mass_kg(self) -> float:
        """Total vehicle mass [kg]."""
        return float(self.params["mass_kg"])


def _vehicle_parser(key: str) -> Parser:
    return _number_list if key in _VEHICLE_LIST_KEYS else _to_float


def _build_vehicle(values: Mapping[str, _Value]) -> _core.Vehicle:
    """Construct the core vehicle; its range errors are reported against the key's origin."""
    try:
        return _core.Vehicle({key: item.value for key, item in values.items()})
    except ValueError as err:
        key, _, message = str(err).partition(": ")
        origins = list(dict.fromkeys(item.origin for item in values.values()))
        if key not in values:
            raise ConfigError(f"{origins[0]}: {err}") from None
        overrides = [origin for origin in origins if origin.startswith("--set ") and origin != values[key].origin]
        after = f" (after {', '.join(overrides)})" if overrides else ""
        raise ConfigError(f"{_where(values[key].origin, key)}: {message}{after}") from None


def _read_vehicle_file(path: PathLike | None) -> tuple[dict[str, _Value], str]:
    data, where = _read_mapping(default_config_path("truck-40t.yaml") if path is None else path)
    values: dict[str, _Value] = {}
    for key, raw in data.items():
        if key not in VEHICLE_KEYS:
            raise _unknown_key(where, key, VEHICLE_KEYS)
        _parse_into(values, key, raw, _vehicle_parser(key), where)
    missing = [key for key in VEHICLE_KEYS if key not in values]
    if missing:
        raise ConfigError(f"{where}: {_missing_text(missing)} (a vehicle file must give every parameter)")
    return values, where


def _vehicle_config(values: Mapping[str, _Value], source: str) -> VehicleConfig:
    config = VehicleConfig(params={key: values[key].value for key in VEHICLE_KEYS}, source=source)
    object.__setattr__(config, "_vehicle", _build_vehicle(values))
    return config


def load_vehicle(path: PathLike | None = None) -> VehicleConfig:
    """Load and validate a complete vehicle file; `None` loads the packaged `truck-40t.yaml`."""
    values, where = _read_vehicle_file(path)
    return _vehicle_config(values, where)


# ---------------------------------------------------------------------------------------------
# Controller and simulation sections.


@dataclass(frozen=True)
class Section:
    """One group of controller or simulation settings.

    `parsers` maps each key to the parser of its value; `build(values, source)` makes the config
    object from a complete set of parsed values and raises `_Invalid(..., key=k)` for a check that
    involves several keys; `check_vehicle(config, vehicle)`, if given, checks it against the vehicle.
    """

    default_file: str
    parsers: Mapping[str, Parser]
    build: Callable[[dict[str, Any], str], Any]
    check_vehicle: Callable[[Any, VehicleConfig], None] | None = None


@dataclass(frozen=True)
class PiConfig:
    """The PI cruise controller (thesis section 2.5, tables A.3 and A.4).

    The controller works on speeds in km/h: gains are per km/h, integrator states in km/h*s are
    clamped to +-limit (the anti-windup). The pedal acts on v_ref - v, the brake on v - v_max.
    Gear thresholds [rpm] are per gear 1..n; None where a gear has no lower/higher gear.
    """

    v_ref_kmh: float
    v_inc_kmh: float
    pedal_kp: float
    pedal_ki: float
    pedal_integrator_limit: float
    brake_kp: float
    brake_ki: float
    brake_integrator_limit: float
    gear_down_rpm: tuple[float | None, ...]
    gear_up_rpm: tuple[float | None, ...]
    source: str

    @property
    def v_max_kmh(self) -> float:
        """Speed above which the brake controller acts, v_ref + v_inc [km/h]."""
        return self.v_ref_kmh + self.v_inc_kmh


@dataclass(frozen=True)
class SimConfig:
    """Closed-loop simulation settings: plant RK4 step [s], trace sampling distance [m], start speed
    [km/h] (None: start at the controller's v_ref)."""

    plant_dt_s: float
    trace_step_m: float
    start_speed_kmh: float | None
    source: str


_V_INC_WHY = "v_max = v_ref + v_inc must not be below v_ref"

_PI_PARSERS: dict[str, Parser] = {
    "v_ref_kmh": _number(0, above=True),
    "v_inc_kmh": _number(0, why=_V_INC_WHY),
    "pedal_kp": _number(0),
    "pedal_ki": _number(0),
    "pedal_integrator_limit": _number(0, above=True),
    "brake_kp": _number(0),
    "brake_ki": _number(0),
    "brake_integrator_limit": _number(0, above=True),
    "gear_down_rpm": _rpm_list,
    "gear_up_rpm": _rpm_list,
}


def _build_pi(values: dict[str, Any], source: str) -> PiConfig:
    down, up = values["gear_down_rpm"], values["gear_up_rpm"]
    if len(up) != len(down):
        raise _Invalid(
            f"one threshold per gear, as many as gear_down_rpm ({len(down)}), got {len(up)}",
            key="gear_up_rpm",
            show_got=False,
        )
    _check_thresholds("gear_down_rpm", down, none_at=0, what="gear 1 (there is no lower gear)")
    _check_thresholds("gear_up_rpm", up, none_at=len(up) - 1, what=f"gear {len(up)} (there is no higher gear)")
    for gear, (low, high) in enumerate(zip(down, up, strict=True), start=1):
        if low is not None and high is not None and not low < high:
            raise _Invalid(
                f"gear {gear}'s downshift speed below its upshift speed {high:g} rpm", low, key="gear_down_rpm"
            )
    return PiConfig(**values, source=source)


def _check_thresholds(key: str, speeds: tuple[float | None, ...], none_at: int, what: str) -> None:
    for index, speed in enumerate(speeds):
        if index == none_at and speed is not None:
            raise _Invalid(f"null for {what}", speed, key=key)
        if index != none_at and speed is None:
            raise _Invalid(f"an engine speed for gear {index + 1}", None, key=key)


def _check_pi_gears(pi: PiConfig, vehicle: VehicleConfig) -> None:
    """Threshold lists must cover the vehicle's gears, and an upshift must land above the next
    gear's downshift speed, or the gearbox would hunt between the two."""
    ratios = vehicle.params["gear_ratios"]
    for key in ("gear_down_rpm", "gear_up_rpm"):
        count = len(getattr(pi, key))
        if count != len(ratios):
            raise _Invalid(
                f"{len(ratios)} thresholds (one per gear of the vehicle), got {count}", key=key, show_got=False
            )
    for gear in range(1, len(ratios)):
        up, next_down = pi.gear_up_rpm[gear - 1], pi.gear_down_rpm[gear]
        landing = up * ratios[gear] / ratios[gear - 1]
        if not landing > next_down:
            raise _Invalid(
                f"gear {gear}'s upshift speed to land above gear {gear + 1}'s downshift speed {next_down:g} rpm "
                f"(it lands at {landing:.0f} rpm: the gearbox would hunt)",
                up,
                key="gear_up_rpm",
            )


_SIM_PARSERS: dict[str, Parser] = {
    "plant_dt_s": _number(0, above=True, maximum=1),
    "trace_step_m": _number(0, above=True),
    "start_speed_kmh": _optional(_number(0, above=True)),
}

SHIFT_SPACING_M = 200.0
"""Table 6.1: the shift limit k_lim is chosen so that S * k_lim = 200 m."""


@dataclass(frozen=True)
class MpcConfig:
    """The look-ahead controller (chapter 5; tables 5.2, 6.1, 6.2); see `configs/mpc.yaml`.

    Speeds in km/h. The cost weighs fuel in grams and speeds in m/s (NOTES.md). `k_lim` None means
    200 m / S (table 6.1); `q_speed_below` None means table 6.2's rule: 5 at delta = 0.1 km/h and
    7 at 0.2 km/h (5 below 0.15 km/h, else 7).
    """

    stage_m: float
    horizon_m: float
    delta_kmh: float
    epsilon: float
    v_ref_kmh: float
    v_inc_kmh: float
    v_dec_kmh: float
    k_lim: int | None
    n_min_rpm: float
    n_max_rpm: float
    allow_neutral: bool
    q_fuel: float
    q_speed_below: float | None
    q_speed_change: float
    q_gear_shift: float
    q_brake: float
    neutral_rule: str
    grid: str
    source: str

    def core_params(self) -> dict[str, Any]:
        """The parameters as the Rust kernel takes them, with the table 6.1/6.2 defaults resolved."""
        params = dataclasses.asdict(self)
        params.pop("source")
        if params["k_lim"] is None:
            params["k_lim"] = max(1, round(SHIFT_SPACING_M / self.stage_m))
        if params["q_speed_below"] is None:
            params["q_speed_below"] = 5.0 if self.delta_kmh < 0.15 else 7.0
        return params


def _flag(value: Any) -> bool:
    if not isinstance(value, bool):
        raise _Invalid("true or false", value)
    return value


def _whole(value: Any) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or value < 1:
        raise _Invalid("a whole number >= 1", value)
    return value


def _one_of(*choices: str) -> Parser:
    def parse(value: Any) -> str:
        if value not in choices:
            raise _Invalid(" or ".join(repr(c) for c in choices), value)
        return value

    return parse


_MPC_PARSERS: dict[str, Parser] = {
    "stage_m": _number(0, above=True),
    "horizon_m": _number(0, above=True),
    "delta_kmh": _number(0, above=True),
    "epsilon": _number(0),
    "v_ref_kmh": _number(0, above=True),
    "v_inc_kmh": _number(0, why=_V_INC_WHY),
    "v_dec_kmh": _number(0),
    "k_lim": _optional(_whole),
    "n_min_rpm": _number(0),
    "n_max_rpm": _number(0, above=True),
    "allow_neutral": _flag,
    "q_fuel": _number(0),
    "q_speed_below": _optional(_number(0)),
    "q_speed_change": _number(0),
    "q_gear_shift": _number(0),
    "q_brake": _number(0),
    "neutral_rule": _one_of("nearest", "interpolate"),
    "grid": _one_of("moving", "fixed"),
}


def _build_mpc(values: dict[str, Any], source: str) -> MpcConfig:
    """Ranges that involve several keys are the kernel's to judge (one source of truth)."""
    config = MpcConfig(**values, source=source)
    try:
        _core.check_mpc_params(config.core_params())
    except ValueError as err:
        key, _, text = str(err).partition(": ")
        raise _Invalid(text.removeprefix("expected "), key=key if key in values else None, show_got=False) from None
    return config


SECTIONS: dict[str, Section] = {
    "pi": Section("pi.yaml", _PI_PARSERS, _build_pi, _check_pi_gears),
    "mpc": Section("mpc.yaml", _MPC_PARSERS, _build_mpc),
    "sim": Section("simulation.yaml", _SIM_PARSERS, lambda values, source: SimConfig(**values, source=source)),
}
"""Registry of controller/simulation sections, keyed by their `RunConfig` field name."""


@dataclass(frozen=True)
class RunConfig:
    """Everything a simulation run needs: vehicle, PI and MPC controllers, simulation settings."""

    vehicle: VehicleConfig
    pi: PiConfig
    mpc: MpcConfig
    sim: SimConfig

    def as_dict(self) -> dict[str, Any]:
        """Plain data (YAML/JSON-ready) of every setting and where it came from, for result files."""
        data: dict[str, Any] = {"vehicle": dict(self.vehicle.params)}
        sources = {"vehicle": self.vehicle.source}
        for item in dataclasses.fields(self):
            if item.name == "vehicle":
                continue
            values = dataclasses.asdict(getattr(self, item.name))
            sources[item.name] = values.pop("source")
            data[item.name] = {k: list(v) if isinstance(v, tuple) else v for k, v in values.items()}
        data["sources"] = sources
        return data


# ---------------------------------------------------------------------------------------------
# Loading.


def _section_keys() -> list[str]:
    return sorted({key for section in SECTIONS.values() for key in section.parsers})


def _read_section_file(section: Section, path: PathLike) -> dict[str, _Value]:
    """Parsed values of a complete section file."""
    data, where = _read_mapping(path)
    values: dict[str, _Value] = {}
    for key, raw in data.items():
        if key not in section.parsers:
            raise _unknown_key(where, key, list(section.parsers))
        _parse_into(values, key, raw, section.parsers[key], where)
    missing = [key for key in section.parsers if key not in values]
    if missing:
        raise ConfigError(f"{where}: {_missing_text(missing)}")
    return values


def _build_section(section: Section, values: dict[str, _Value], vehicle: VehicleConfig | None) -> Any:
    origins = list(dict.fromkeys(item.origin for item in values.values()))
    try:
        config = section.build({key: item.value for key, item in values.items()}, " + ".join(origins))
        if vehicle is not None and section.check_vehicle is not None:
            section.check_vehicle(config, vehicle)
    except _Invalid as err:
        key = err.key or next(iter(values))
        raise ConfigError(f"{_where(values[key].origin, key)}: {err.text()}") from None
    return config


def load_pi(path: PathLike | None = None) -> PiConfig:
    """Load a complete PI controller file; `None` loads the packaged `pi.yaml`."""
    section = SECTIONS["pi"]
    return _build_section(section, _read_section_file(section, path or default_config_path(section.default_file)), None)


def load_sim(path: PathLike | None = None) -> SimConfig:
    """Load a complete simulation file; `None` loads the packaged `simulation.yaml`."""
    section = SECTIONS["sim"]
    return _build_section(section, _read_section_file(section, path or default_config_path(section.default_file)), None)


def _apply_overlay(state: dict[str, dict[str, _Value]], path: PathLike) -> None:
    """Set every key of an overlay file in each section that has it."""
    data, where = _read_mapping(path)
    for key, raw in data.items():
        owners = [name for name, section in SECTIONS.items() if key in section.parsers]
        if not owners and key in VEHICLE_KEYS:
            raise ConfigError(
                f"{where}: key {key!r} is a vehicle parameter: set it in the vehicle file or with --set {key}=..."
            )
        if not owners:
            raise _unknown_key(where, key, [*_section_keys(), *VEHICLE_KEYS])
        for name in owners:
            _parse_into(state[name], key, raw, SECTIONS[name].parsers[key], where)


def _apply_override(vehicle: dict[str, _Value], state: dict[str, dict[str, _Value]], text: str) -> None:
    """Apply one `key=value` override (value in YAML syntax) to the vehicle and/or sections."""
    key, sep, raw_text = text.partition("=")
    key = key.strip()
    if not sep or not key:
        raise ConfigError(f"--set {text!r}: expected key=value")
    origin = f"--set {key}"
    try:
        raw = yaml.safe_load(raw_text)
    except yaml.YAMLError as err:
        problem = getattr(err, "problem", None) or "syntax error"
        raise ConfigError(f"{origin}: value {raw_text.strip()!r} is not valid YAML ({problem})") from None
    owners = [name for name, section in SECTIONS.items() if key in section.parsers]
    if key not in VEHICLE_KEYS and not owners:
        raise _unknown_key(origin, key, [*VEHICLE_KEYS, *_section_keys()])
    if key in VEHICLE_KEYS:
        _parse_into(vehicle, key, raw, _vehicle_parser(key), origin)
    for name in owners:
        _parse_into(state[name], key, raw, SECTIONS[name].parsers[key], origin)


def load_sections(
    vehicle_path: PathLike | None = None,
    config_paths: Sequence[PathLike] = (),
    overrides: Sequence[str] = (),
) -> tuple[VehicleConfig, dict[str, Any]]:
    """The vehicle and every registered section's config, layered as described in the module doc.

    Returns the vehicle config and a dict from section name (a key of `SECTIONS`) to its config.
    """
    vehicle_values, vehicle_where = _read_vehicle_file(vehicle_path)
    state = {
        name: _read_section_file(section, default_config_path(section.default_file))
        for name, section in SECTIONS.items()
    }
    for path in config_paths:
        _apply_overlay(state, path)
    for text in overrides:
        _apply_override(vehicle_values, state, text)
    set_keys = sorted({item.origin for item in vehicle_values.values()} - {vehicle_where})
    vehicle = _vehicle_config(vehicle_values, " + ".join([vehicle_where, *set_keys]))
    return vehicle, {name: _build_section(section, state[name], vehicle) for name, section in SECTIONS.items()}


def load_run_config(
    vehicle_path: PathLike | None = None,
    config_paths: Sequence[PathLike] = (),
    overrides: Sequence[str] = (),
) -> RunConfig:
    """Load a run's configuration: vehicle file (default: packaged 40 t truck), then the packaged
    controller/simulation defaults, overlay files in order, then `key=value` overrides."""
    vehicle, sections = load_sections(vehicle_path, config_paths, overrides)
    names = [item.name for item in dataclasses.fields(RunConfig) if item.name != "vehicle"]
    return RunConfig(vehicle=vehicle, **{name: sections[name] for name in names})

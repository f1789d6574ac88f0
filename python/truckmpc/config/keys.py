"""The declared parameters (from the Rust core's declarations) and the packaged default files.

Every key is declared once in the core with its unit, type, default, range and doc; this module
only reads those declarations. Keys are unique across sections, so settings are one namespace.
"""

from __future__ import annotations

import difflib
import os
from collections.abc import Sequence
from pathlib import Path

from truckmpc import _core
from truckmpc.errors import ConfigError

CONFIG_DIR = Path(__file__).resolve().parent.parent / "configs"
SPECS: tuple[_core.ParamSpec, ...] = tuple(_core.parameter_specs())
SPEC_BY_KEY: dict[str, _core.ParamSpec] = {spec.name: spec for spec in SPECS}
SECTION_NAMES: tuple[str, ...] = tuple(dict.fromkeys(spec.section for spec in SPECS))
KEYS: tuple[str, ...] = tuple(SPEC_BY_KEY)
"""Every key, section by section in declaration order."""
REPLACED_KEYS: dict[str, str] = dict(_core.replaced_keys())
"""Keys no longer declared, each with the key that replaced it."""

SECTION_FILES: dict[str, str] = {
    "cruise": "cruise.yaml",
    "pi": "pi.yaml",
    "mpc": "mpc.yaml",
    "pcc": "pcc.yaml",
    "sim": "simulation.yaml",
}
"""The packaged file holding each section's defaults (the vehicle's is a truck file)."""

VEHICLE_FILES: dict[str, dict[str, float]] = {"truck-40t.yaml": {}, "truck-20t.yaml": {"mass_kg": 20000.0}}
"""Packaged vehicles: the declared defaults (the thesis's 40 t truck) with these changes."""


def section_keys(section: str) -> tuple[str, ...]:
    """The keys of one section, in declaration order."""
    return tuple(spec.name for spec in SPECS if spec.section == section)


VEHICLE_KEYS: tuple[str, ...] = section_keys("vehicle")


def default_config_path(name: str) -> Path:
    """Path of a packaged configuration file, e.g. `"pi.yaml"` or `"truck-20t.yaml"`."""
    path = CONFIG_DIR / name
    if not path.is_file():
        available = ", ".join(sorted(p.name for p in CONFIG_DIR.glob("*.yaml")))
        raise ConfigError(f"no packaged config named {name!r} (available: {available})")
    return path


PRESET_DIR = CONFIG_DIR / "presets"


def overlay_path(path: str | os.PathLike[str]) -> Path:
    """An overlay file, or a packaged preset named without a path (`thesis` for `presets/thesis.yaml`)
    when no such file exists."""
    given = Path(path)
    preset = PRESET_DIR / f"{given.name}.yaml"
    if not given.exists() and given.name == str(path) and given.suffix == "" and preset.is_file():
        return preset
    return given


def preset_names() -> list[str]:
    """The packaged presets' names."""
    return sorted(p.stem for p in PRESET_DIR.glob("*.yaml"))


def unknown_key(where: str, key: str, known: Sequence[str]) -> ConfigError:
    """The error for a key that is not declared: the key that replaced it, or the closest known key
    as a hint."""
    if key in REPLACED_KEYS:
        what = "key" if where.startswith("--") else f"key {key!r}"
        return ConfigError(
            f"{where}: {what} was replaced by {REPLACED_KEYS[key]!r} "
            "(one speed band for every controller: v_dec_kmh below v_ref, v_inc_kmh above)"
        )
    close = difflib.get_close_matches(key, list(known), n=1)
    hint = f" (did you mean {close[0]!r}?)" if close else ""
    if where.startswith("--"):
        return ConfigError(f"{where}: unknown key{hint}")
    return ConfigError(f"{where}: unknown key {key!r}{hint}")

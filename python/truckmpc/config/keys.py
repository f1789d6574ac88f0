"""The declared parameters (from the Rust core's declarations) and the packaged default files.

Every key is declared once in the core with its unit, type, default, range and doc; this module
only reads those declarations. Keys are unique across sections, so settings are one namespace.
"""

from __future__ import annotations

import difflib
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from truckmpc import _core
from truckmpc.errors import ConfigError


@dataclass(frozen=True)
class ParamSpec:
    """One declared parameter: name (unit in the name), section, kind, unit, doc, default, range."""

    name: str
    """Key as typed in YAML, ``--set`` and ``--grid``."""
    section: str
    """Section: vehicle, cruise, pi, mpc, pcc, sim or vecto."""
    kind: str
    """number, number_or_null, count, count_or_null, flag, choice, numbers or numbers_or_nulls."""
    unit: str
    """Unit in words."""
    doc: str
    """One-line description."""
    default: Any
    """Default value."""
    choices: list[str] | None
    """Names a choice accepts; None for other kinds."""
    expected: str
    """What a value must be, in words (``"a number > 0"``)."""


@dataclass(frozen=True)
class KeyChange:
    """A key renamed, replaced or added: the core's registry of key changes, one entry."""

    key: str
    """The key as it was (renamed, replaced) or as it is (added)."""
    kind: str
    """renamed, replaced or added."""
    new: str | None
    """The key's successor (renamed, replaced); None for an added key."""
    why: str | None
    """Why it was replaced, in parentheses; None otherwise."""
    replays_with: Any
    """The value a record made before an added key existed replays with; None otherwise."""
    version: str
    """The version of truckmpc that changed it."""


CONFIG_DIR = Path(__file__).resolve().parent.parent / "configs"
SPECS: tuple[ParamSpec, ...] = tuple(ParamSpec(**record) for record in _core.declaration("parameters"))
"""Every declared parameter, section by section in declaration order."""
SPEC_BY_KEY: dict[str, ParamSpec] = {spec.name: spec for spec in SPECS}
SECTION_NAMES: tuple[str, ...] = tuple(dict.fromkeys(spec.section for spec in SPECS))
KEYS: tuple[str, ...] = tuple(SPEC_BY_KEY)
"""Every key, section by section in declaration order."""
KEY_CHANGES: tuple[KeyChange, ...] = tuple(KeyChange(**record) for record in _core.declaration("key_changes"))
"""Keys renamed, replaced or added, oldest first (the core's registry)."""
RETIRED_KEYS: dict[str, KeyChange] = {c.key: c for c in KEY_CHANGES if c.kind != "added"}
"""Keys no longer declared (renamed or replaced), each with its change."""
RENAMED_KEYS: dict[str, str] = {c.key: c.new for c in KEY_CHANGES if c.kind == "renamed" and c.new is not None}
"""Old name -> name now, for keys renamed with their meaning kept."""
ADDED_KEYS: dict[str, Any] = {c.key: c.replays_with for c in KEY_CHANGES if c.kind == "added"}
"""Keys declared after runs were recorded, each with the value those runs replay with."""

SECTION_FILES: dict[str, str] = {
    "cruise": "cruise.yaml",
    "pi": "pi.yaml",
    "mpc": "mpc.yaml",
    "pcc": "pcc.yaml",
    "sim": "simulation.yaml",
    "vecto": "vecto.yaml",
}
"""The packaged file holding each section's defaults (the vehicle's is a truck file)."""

VEHICLE_FILES: dict[str, dict[str, float]] = {"truck-40t.yaml": {}, "truck-20t.yaml": {"mass_kg": 20000.0}}
"""Packaged vehicles: the declared defaults (the thesis's 40 t truck) with these changes."""


def section_keys(section: str) -> tuple[str, ...]:
    """The keys of one section, in declaration order."""
    return tuple(spec.name for spec in SPECS if spec.section == section)


VEHICLE_KEYS: tuple[str, ...] = section_keys("vehicle")
VECTO_KEYS: tuple[str, ...] = section_keys("vecto")
"""The keys of a truck from VECTO's files (refused with the thesis's truck)."""


def current_values(values: Mapping[str, Any]) -> dict[str, Any]:
    """Recorded values as today's keys: renamed keys under their names now, and each added key the
    record lacks with the value that drove it (:data:`ADDED_KEYS`)."""
    return {**ADDED_KEYS, **{RENAMED_KEYS.get(key, key): value for key, value in values.items()}}


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
    change = RETIRED_KEYS.get(key)
    if change is not None:
        what = "key" if where.startswith("--") else f"key {key!r}"
        how = f"was replaced by {change.new!r} {change.why}" if change.kind == "replaced" else f"is now {change.new!r}"
        return ConfigError(f"{where}: {what} {how}")
    close = difflib.get_close_matches(key, list(known), n=1)
    hint = f" (did you mean {close[0]!r}?)" if close else ""
    if where.startswith("--"):
        return ConfigError(f"{where}: unknown key{hint}")
    return ConfigError(f"{where}: unknown key {key!r}{hint}")


def current_sections(doc: Mapping[str, Any]) -> dict[str, Any]:
    """A recorded configuration by section (as a sweep's ``base_config`` holds it) as today's
    sections (:func:`current_values`); a document with a key this version does not know is left as it is."""
    flat = {key: value for section in doc.values() if isinstance(section, dict) for key, value in section.items()}
    out: dict[str, dict[str, Any]] = {name: {} for name in SECTION_NAMES}
    for key, value in current_values(flat).items():
        if key not in SPEC_BY_KEY:
            return dict(doc)
        out[SPEC_BY_KEY[key].section][key] = value
    return out

"""The layers of a run's configuration: raw values by key, each with where it came from, and the
one shape of a message about a value (``file:line: key 'k': expected ..., got ...``, or
``--set k: expected ..., got ...``)."""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from truckmpc import _core
from truckmpc.config.keys import CONFIG_DIR, SPEC_BY_KEY, VEHICLE_KEYS, unknown_key
from truckmpc.config.yamlfile import read_mapping
from truckmpc.errors import ConfigError

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

    @property
    def packaged(self) -> bool:
        """Whether the value is one of truckmpc's packaged defaults (a file of its configs folder)."""
        if self.text.startswith("--set "):
            return False
        path, _, line = self.text.rpartition(":")
        return Path(path if line.isdigit() else self.text).resolve().parent == CONFIG_DIR


def problem(err: _core.ParamError) -> str:
    """What the core found wrong with a value: `expected ..., got ...`."""
    return f"expected {err.expected}" + ("" if err.got is None else f", got {err.got}")


class Layers:
    """Raw values by key, each with its origin, in the order the layers set them."""

    def __init__(self) -> None:
        self.values: dict[str, Any] = {}
        self.origins: dict[str, Origin] = {}
        self.rank = 0

    def put(self, key: str, raw: Any, origin_text: str) -> None:
        """Set `key` in the current layer (call `next_layer` between files and overrides)."""
        self.values[key] = raw
        self.origins[key] = Origin(origin_text, self.rank)

    def put_under(self, key: str, raw: Any, origin_text: str, rank: int) -> None:
        """Set `key` in the earlier layer `rank`, unless a later layer set it."""
        if key not in self.origins or self.origins[key].rank <= rank:
            self.values[key] = raw
            self.origins[key] = Origin(origin_text, rank)

    def next_layer(self) -> None:
        self.rank += 1

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

    def override(self, key: str, raw: Any, known: Sequence[str]) -> None:
        """A `--set key=value` (parsed), in a layer of its own."""
        origin = f"--set {key}"
        if key not in known:
            raise unknown_key(origin, key, known)
        self.next_layer()
        self.put(key, raw, origin)

    def blame(self, err: _core.ParamError, fails: Callable[[dict[str, Any]], bool] | None = None) -> ConfigError:
        """The error against the origin of the key the user set last among those the check involved
        (the key itself when several were set in the same layer). An error on a packaged default
        (a derived quantity such as β, or a key checked against the user's) is the user's doing:
        with `fails` (whether values still fail), the user's key whose declared default clears it;
        else, when every key involved is packaged, the user's key set last."""
        involved = [k for k in (err.key, *err.related) if k in self.origins]
        if not involved:
            return ConfigError(str(err))
        culprit = max(involved, key=lambda k: self.origins[k].rank)
        if self.origins[err.key].packaged:
            users = sorted((k for k, o in self.origins.items() if not o.packaged), key=lambda k: -self.origins[k].rank)
            clears = [k for k in users if fails is not None and not fails({**self.values, k: SPEC_BY_KEY[k].default})]
            if clears or (users and self.origins[culprit].packaged):
                culprit = (clears or users)[0]
        if culprit == err.key:
            return ConfigError(f"{self.origins[err.key].where(err.key)}: {problem(err)}")
        return ConfigError(f"{self.origins[culprit].where(culprit)}: {err.key}: {problem(err)}")

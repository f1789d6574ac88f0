"""The roads, directions and vehicles of a fleet study.

``--road`` takes a file, a directory (its road files: :data:`ROAD_SUFFIXES`, not its subdirectories)
or a glob (an argument with ``*``, ``?`` or ``[``, expanded here, so that a quoted pattern works
too). A file named on its own must be readable (else a one-line error before anything runs); a file
found in a directory or by a glob that cannot be read is kept as a :class:`BrokenRoad`, whose runs
fail with its error in their rows, so that one bad file does not stop a fleet. ``--vehicle`` may
be repeated: each vehicle's rows carry its name (the file's stem) in a ``vehicle`` column.
"""

from __future__ import annotations

import dataclasses
import glob
import os
from collections import Counter
from collections.abc import Sequence
from pathlib import Path

from truckmpc.errors import TruckmpcError
from truckmpc.roads import RoadProfile, load_road
from truckmpc.roads.profile import PathLike
from truckmpc.sweep.errors import SweepError
from truckmpc.sweep.task import BrokenRoad, Road

ROAD_SUFFIXES = (".csv", ".vdri", ".gpx")
"""The files of a road directory that are taken as roads (a format ``load_road`` cannot read yet is
a broken road of the fleet)."""

GLOB_CHARACTERS = frozenset("*?[")
"""An argument of ``--road`` with one of these is a glob."""

DIRECTIONS = {False: ("forward",), True: ("reverse",), "both": ("forward", "reverse")}
"""The directions a sweep drives its roads in, by ``reverse`` (``"both"``: each road both ways)."""


def road_files(arguments: Sequence[RoadProfile | PathLike]) -> list[tuple[RoadProfile | Path, bool]]:
    """Each road of `arguments` with whether it was found in a directory or by a glob (a fleet
    member, whose load error is kept, not raised); a directory or glob without road files is a
    one-line :class:`SweepError`."""
    found: list[tuple[RoadProfile | Path, bool]] = []
    for argument in arguments:
        if isinstance(argument, RoadProfile):
            found.append((argument, False))
            continue
        path, text = Path(argument), str(argument)
        if GLOB_CHARACTERS & set(text):
            matches = [Path(m) for m in sorted(glob.glob(text)) if Path(m).is_file()]
        elif path.is_dir():
            matches = sorted(p for p in path.iterdir() if p.is_file() and p.suffix.lower() in ROAD_SUFFIXES)
        else:
            found.append((path, False))
            continue
        if not matches:
            what = "no file matches" if GLOB_CHARACTERS & set(text) else f"no road file ({', '.join(ROAD_SUFFIXES)})"
            raise SweepError(f"--road {text}: {what}")
        found += [(match, True) for match in matches]
    return found


def load_fleet(arguments: Sequence[RoadProfile | PathLike], reverse: bool | str) -> tuple[list[Road], list[str]]:
    """The roads of a sweep, each in each direction of `reverse` (a road's directions next to each
    other), and their directions; reversed roads keep their names (rows are keyed by name and
    direction). Names must be unique."""
    roads = [_load(item, member) for item, member in road_files(arguments)]
    if not roads:
        raise SweepError("--road: expected at least one road")
    check_unique([road.name for road in roads], "--road", "roads")
    directions = DIRECTIONS[reverse]
    out = [_driven(road, direction) for road in roads for direction in directions]
    return out, [direction for _ in roads for direction in directions]


def _load(item: RoadProfile | Path, member: bool) -> Road:
    """A road loaded; a fleet member that cannot be read as a :class:`BrokenRoad`."""
    if isinstance(item, RoadProfile):
        return item
    if not member:
        return load_road(item)
    try:
        return load_road(item)
    except (TruckmpcError, OSError) as err:
        return BrokenRoad(item.stem, str(item), " ".join(str(err).split()))


def _driven(road: Road, direction: str) -> Road:
    """`road` as driven in `direction`, under its own name."""
    if direction == "forward" or isinstance(road, BrokenRoad):
        return road
    return dataclasses.replace(road.reversed(), name=road.name)


def vehicle_names(paths: Sequence[str | None]) -> tuple[str, ...]:
    """The name of each vehicle (its file's stem; ``truck-40t`` for the packaged default), unique."""
    names = tuple("truck-40t" if path is None else Path(path).stem for path in paths)
    check_unique(names, "--vehicle", "vehicles")
    return names


def check_unique(names: Sequence[str], option: str, what: str) -> None:
    """A one-line SweepError naming `option` if two of `what` (``roads``, ``vehicles``) share a
    name: rows are keyed by names."""
    repeated = [name for name, count in Counter(names).items() if count > 1]
    if repeated:
        key = what.removesuffix("s")
        raise SweepError(f"{option}: two {what} are named {repeated[0]!r} (rows are keyed by {key} name)")


def vehicle_paths(given: PathLike | Sequence[PathLike] | None) -> tuple[str | None, ...]:
    """The vehicle files of a sweep: one, several (at least one), or None (the packaged truck)."""
    if given is None or isinstance(given, (str, os.PathLike)):
        return (None if given is None else str(given),)
    if not given:
        raise SweepError("--vehicle: expected at least one vehicle file")
    return tuple(str(path) for path in given)

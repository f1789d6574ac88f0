"""What ``truckmpc sweep`` and ``truckmpc pareto`` share: their base inputs, their stops as one line
each, and the notes they print."""

from __future__ import annotations

import contextlib
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any

import typer

from truckmpc.cli.errors import fail
from truckmpc.legs import stops_line
from truckmpc.roads import RoadProfile
from truckmpc.signals import Stopped, received_signal, stopping_on_signals
from truckmpc.sweep import SweepInterrupted, SweepWorkerDied

__all__ = ["notice", "pooled_study", "stop_notes", "study_inputs"]


def study_inputs(
    reverse: bool | str,
    vehicle: Path | tuple[Path, ...] | None,
    config: list[Path] | None,
    set_: list[str] | None,
) -> dict[str, Any]:
    """The base inputs of a sweep or Pareto study, as ``plan_sweep`` and ``plan_pareto`` take them."""
    return {
        "reverse": reverse,
        "vehicle_path": vehicle,
        "config_paths": tuple(config or ()),
        "overrides": tuple(set_ or ()),
    }


@contextlib.contextmanager
def pooled_study(kept_what: str) -> Iterator[None]:
    """A sweep or Pareto study's stops as one line each: Ctrl-C or SIGTERM says how many finished
    `kept_what` (rows, points) stay for a resume; a lost Dask cluster exits 1."""
    try:
        with stopping_on_signals():
            yield
    except SweepInterrupted as stop:
        kept = f"{stop.done} of {stop.total} {kept_what} kept in {stop.partial_path}"
        raise Stopped(f"{kept}; run the same command again to resume", received_signal()) from None
    except KeyboardInterrupt:
        raise Stopped("before any run started", received_signal()) from None
    except SweepWorkerDied as err:
        fail(str(err), 1)


def notice(text: str) -> None:
    """Print one of a study's notices (damaged rows dropped, the Dask cluster's address) on stderr."""
    typer.echo(text, err=True)


def stop_notes(roads: Sequence[object]) -> None:
    """One line per road with stops: they are not simulated, the road is driven as its legs."""
    for road in roads:
        if isinstance(road, RoadProfile) and road.stops:
            typer.echo(f"{road.name}: {stops_line(road)}")

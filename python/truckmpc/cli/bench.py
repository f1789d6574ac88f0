"""``truckmpc bench``: :func:`truckmpc.bench.run_bench`, printed as a table or JSON."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer

from truckmpc.bench import format_bench, run_bench

__all__ = ["BENCH_HELP", "bench_cmd"]

BENCH_HELP = (
    "Time closed-loop MPC runs, each in its own process: the default controller at its own settings on the "
    "VECTO long-haul road (108 km) and the Swedish E6/E20 (294 km), then the thesis's worst case (S 25 m, "
    "δ 0.1 km/h, 3000 m, neutral allowed, fixed grid) on the VECTO road, then the default with VECTO's generic "
    "tractor on the VECTO road (where ../shared/vehicles has it).\n\n"
    "Reports the realtime ratio (compute time / simulated time), the time per DP solve, the states and "
    "transitions per solve, the time per transition and the peak memory of each run."
)
"""The help text of ``truckmpc bench``."""


def bench_cmd(
    road: Annotated[
        Path | None,
        typer.Option(
            "--road",
            metavar="FILE",
            help="Road profile CSV for every run (default: each run's road of ../shared/roads, "
            "else the bundled test track).",
        ),
    ] = None,
    quick: Annotated[bool, typer.Option("--quick", help="Only the first 10 km of each road (for CI).")] = False,
    set_: Annotated[
        list[str] | None,
        typer.Option(
            "--set",
            metavar="KEY=VALUE",
            help="Any other key=value (e.g. neutral_rule=interpolate); "
            "for every run; stage_m, delta_kmh, horizon_m, allow_neutral and grid are fixed.",
        ),
    ] = None,
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON instead of a table.")] = False,
) -> None:
    """``truckmpc bench``: :func:`truckmpc.bench.run_bench`, printed (its help: :data:`BENCH_HELP`)."""
    result = run_bench(road, quick=quick, overrides=tuple(set_ or ()))
    typer.echo(json.dumps(result.document()) if as_json else format_bench(result))

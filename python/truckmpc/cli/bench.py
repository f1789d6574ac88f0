"""``truckmpc bench``: :func:`truckmpc.bench.run_bench`, printed as a table or JSON."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer

from truckmpc.bench import format_bench, run_bench

__all__ = ["BENCH_HELP", "bench_cmd"]

BENCH_HELP = (
    "Time closed-loop MPC runs at (S 25 m, δ 0.1 km/h, 3000 m) and (S 50 m, δ 0.2 km/h, 2000 m), "
    "on the fixed and the moving grid, each in its own process.\n\n"
    "Reports the realtime ratio (compute time / simulated time), the time per DP solve, the states and "
    "transitions per solve, the time per transition and the peak memory of each run."
)
"""The help text of ``truckmpc bench``."""


def bench_cmd(
    road: Annotated[
        Path | None,
        typer.Option(
            "--road",
            help="Road profile CSV (default: the 108 km VECTO long-haul road of ../shared/roads, "
            "else the bundled test track).",
        ),
    ] = None,
    quick: Annotated[bool, typer.Option("--quick", help="Only the first 10 km of the road (for CI).")] = False,
    set_: Annotated[
        list[str] | None,
        typer.Option(
            "--set",
            help="Any other key=value (e.g. neutral_rule=interpolate); "
            "stage_m, delta_kmh, horizon_m, allow_neutral and grid are fixed.",
        ),
    ] = None,
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON instead of a table.")] = False,
) -> None:
    """``truckmpc bench``: :func:`truckmpc.bench.run_bench`, printed (its help: :data:`BENCH_HELP`)."""
    result = run_bench(road, quick=quick, overrides=tuple(set_ or ()))
    typer.echo(json.dumps(result.document()) if as_json else format_bench(result))

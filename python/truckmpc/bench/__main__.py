"""``python -m truckmpc.bench --one SPEC``: one benchmark run (internal; ``truckmpc bench`` spawns
it), its figures as one JSON line on stdout."""

from __future__ import annotations

import json
import sys

from truckmpc.bench.runs import run_one
from truckmpc.errors import TruckmpcError


def _child(argv: list[str]) -> int:
    """One run of the JSON spec in ``argv`` (``--one SPEC``); exit status 2 on bad input."""
    if len(argv) != 2 or argv[0] != "--one":
        print("usage: python -m truckmpc.bench --one SPEC  (internal; use `truckmpc bench`)", file=sys.stderr)
        return 2
    spec = json.loads(argv[1])
    try:
        figures = run_one(spec["road"], spec["quick"], spec["setting"], tuple(spec["set"]), spec.get("vehicle"))
    except TruckmpcError as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    print(json.dumps(figures))
    return 0


sys.exit(_child(sys.argv[1:]))

"""The commands that repeat a run or a sweep, as shell lines: ``simulate --replay`` of the run's
``summary.json`` (every resolved parameter, the road checked against its hash), and the command as it
was typed, in the directory it was typed in, where the outputs recorded it."""

from __future__ import annotations

import shlex
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

__all__ = ["replay_run", "typed_line"]


def replay_run(directory: Path) -> str:
    """``truckmpc simulate --replay DIR/summary.json --out DIR-replay``, with absolute paths."""
    run_dir = directory.resolve()
    out = run_dir.with_name(run_dir.name + "-replay")
    return shlex.join(["truckmpc", "simulate", "--replay", str(run_dir / "summary.json"), "--out", str(out)])


def typed_line(record: Any, *, new_out: Path | None = None) -> str | None:
    """The recorded command (``{"argv": [...], "cwd": DIR}``) as ``cd DIR && truckmpc ...``, its
    ``--out`` replaced by `new_out` if given; None if nothing usable was recorded."""
    if not isinstance(record, Mapping):
        return None
    argv, cwd = record.get("argv"), record.get("cwd")
    if not isinstance(argv, list) or not argv or not all(isinstance(a, str) for a in argv):
        return None
    if new_out is not None:
        argv = _with_out(argv, str(new_out))
    line = shlex.join(argv)
    return f"cd {shlex.quote(cwd)} && {line}" if isinstance(cwd, str) else line


def _with_out(argv: Sequence[str], out: str) -> list[str]:
    """`argv` writing to `out`: the value of its ``--out`` replaced, or ``--out`` added."""
    result, replaced, skip = [], False, False
    for i, arg in enumerate(argv):
        if skip:
            skip = False
            continue
        if arg == "--out" and i + 1 < len(argv):
            result += ["--out", out]
            replaced, skip = True, True
        elif arg.startswith("--out="):
            result.append(f"--out={out}")
            replaced = True
        else:
            result.append(arg)
    return result if replaced else [*result, "--out", out]

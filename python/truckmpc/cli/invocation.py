"""The command line a ``truckmpc`` command was given, kept so that its outputs can record it
(``run.command`` in ``summary.json``, ``command`` in ``sweep.json``): what a report shows as the
command that repeats the run."""

from __future__ import annotations

import os
import sys
from collections.abc import Sequence
from typing import Any

__all__ = ["remember_arguments", "typed_command"]

_arguments: list[str] | None = None


def remember_arguments(args: Sequence[str] | None) -> None:
    """Keep the arguments of this invocation (None: the process's own, ``sys.argv[1:]``)."""
    global _arguments
    _arguments = list(sys.argv[1:] if args is None else args)


def typed_command() -> dict[str, Any] | None:
    """``{"argv": ["truckmpc", ...], "cwd": DIR}``: the command as given and the directory it ran
    in (relative paths in it are relative to that); None outside the ``truckmpc`` command."""
    if _arguments is None:
        return None
    return {"argv": ["truckmpc", *_arguments], "cwd": os.getcwd()}

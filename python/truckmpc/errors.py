"""Errors a user can act on: bad configuration files, bad road profiles, bad arguments.

Every error is a `ValueError`, so callers that already catch `ValueError` keep working, and its
message is a single line naming where the problem is (file and line, file and key, or `--set key`)
and what was expected, ready to print after "error: ".
"""

from __future__ import annotations

import re
from pathlib import Path

__all__ = ["ConfigError", "RoadError", "TruckmpcError", "VehicleError", "read_user_text"]


class TruckmpcError(ValueError):
    """A user-facing input problem; `str(e)` is one line naming the file (and line or key) and what
    was expected."""

    def __init__(self, message: str) -> None:
        # Messages quote user input, which may itself contain line breaks; keep the one-line promise.
        super().__init__(re.sub(r"\s*[\r\n]+\s*", " ", str(message)).strip())


class ConfigError(TruckmpcError):
    """A configuration file, key or `--set key=value` override is missing or invalid."""


class RoadError(TruckmpcError):
    """A road profile (CSV file or generated section) is missing or invalid."""


class VehicleError(TruckmpcError):
    """A vehicle's component files (VECTO job, engine, gearbox, maps) are missing, malformed or
    inconsistent."""


def read_user_text(path: Path, where: str, expected: str, error: type[TruckmpcError], encoding: str = "utf-8") -> str:
    """The text of a user's input file; a missing, directory or non-text file raises `error` with a
    one-line message starting with `where` and naming what was `expected` ("a YAML file")."""
    try:
        return path.read_text(encoding=encoding)
    except FileNotFoundError:
        raise error(f"{where}: no such file") from None
    except IsADirectoryError:
        raise error(f"{where}: is a directory, expected {expected}") from None
    except UnicodeDecodeError:
        raise error(f"{where}: not a UTF-8 text file") from None

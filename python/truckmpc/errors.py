"""Errors a user can act on: bad configuration files, bad road profiles, bad arguments.

Every error is a `ValueError`, so callers that already catch `ValueError` keep working, and its
message is a single line naming where the problem is (file and line, file and key, or `--set key`)
and what was expected, ready to print after "error: ".
"""

from __future__ import annotations

import re

__all__ = ["ConfigError", "RoadError", "TruckmpcError"]


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

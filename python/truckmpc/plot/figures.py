"""What every picture shares: matplotlib, imported only when drawing, and all-or-nothing saving."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

from truckmpc.atomic import OutputDir
from truckmpc.errors import TruckmpcError

MISSING_MATPLOTLIB = "plotting needs matplotlib: pip install 'truckmpc[plot]'"

_DPI = 150


class PlotError(TruckmpcError):
    """A directory that cannot be plotted (nothing recognisable in it, unreadable files), or no matplotlib."""


def figure_class() -> Any:
    """``matplotlib.figure.Figure`` (no pyplot, so no GUI backend); :class:`PlotError` without matplotlib."""
    try:
        from matplotlib.figure import Figure
    except ImportError as err:
        raise PlotError(MISSING_MATPLOTLIB) from err
    return Figure


def save(figures: Sequence[tuple[Any, Path]], svg: bool) -> list[Path]:
    """Write every (figure, path) pair, plus an SVG beside each PNG if asked, all or nothing."""
    written: list[Path] = []
    by_dir: dict[Path, list[tuple[Any, Path]]] = {}
    for fig, path in figures:
        by_dir.setdefault(path.parent, []).append((fig, path))
    for out_dir, items in by_dir.items():
        with OutputDir(out_dir) as staging:
            for fig, path in items:
                paths = [path]
                if svg and path.suffix.lower() == ".png":
                    paths.append(path.with_suffix(".svg"))
                for p in paths:
                    fig.savefig(staging / p.name, dpi=_DPI)
                    written.append(p)
    return written

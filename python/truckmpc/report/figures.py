"""The figures of a run or sweep, drawn by :func:`truckmpc.plot.plot_dir` (the pictures of
``truckmpc plot``) and embedded in the page as PNG ``data:`` URIs, so the page needs no other file."""

from __future__ import annotations

import base64
import tempfile
from dataclasses import dataclass
from pathlib import Path

from truckmpc.plot import PlotError, plot_dir
from truckmpc.report.html import escape

__all__ = ["Figure", "draw_figures", "figures_html"]

CAPTIONS = {
    "run.png": "Over the road: altitude, speed of each controller with the set speed and the allowed band, "
    "gear (N: neutral), pedal and brake.",
    "sweep.png": "Δfuel (battery energy for battery-electric trucks) and Δtime of each look-ahead controller "
    "against the PI, over the sweep's axis.",
    "headline.png": "The figure to quote: each look-ahead controller's Δfuel (battery energy for battery-electric "
    "trucks) against the PCC and against the PI at equal trip time and equal end speed, per road and truck "
    "(below 0 saves), each bar labelled with what it saves.",
    "realtime.png": "The MPC's real-time ratio (compute time / driven time) over the sweep's axis; below 1 is "
    "faster than real time.",
}
"""What each of the plot package's pictures shows, under it on the page."""


@dataclass(frozen=True)
class Figure:
    """One picture: its file name as ``truckmpc plot`` would write it, and its PNG bytes."""

    name: str
    png: bytes


def draw_figures(directory: Path) -> tuple[list[Figure], str | None]:
    """The pictures of `directory`, drawn in a scratch directory (`directory` is left alone), and
    why there are none if none could be drawn (no matplotlib, an unreadable trace)."""
    with tempfile.TemporaryDirectory(prefix="truckmpc-report-") as scratch:
        try:
            written = plot_dir(directory, out=Path(scratch))
        except PlotError as err:
            return [], str(err)
        return [Figure(path.name, path.read_bytes()) for path in written if path.suffix == ".png"], None


def figures_html(figures: list[Figure], missing: str | None) -> str:
    """The figures as ``<figure>`` elements with embedded PNGs, or a note saying why there are none."""
    if not figures:
        return f'<p class="note">No figures: {escape(missing or "nothing to draw")}.</p>\n'
    parts = []
    for fig in figures:
        data = base64.b64encode(fig.png).decode("ascii")
        caption = CAPTIONS.get(fig.name, "")
        parts.append(
            f'<figure><img src="data:image/png;base64,{data}" alt="{escape(fig.name)}">'
            f'<figcaption>{escape(caption)} <span class="note">({escape(fig.name)})</span></figcaption></figure>\n'
        )
    return "".join(parts)

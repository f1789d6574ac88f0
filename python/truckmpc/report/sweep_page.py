"""The page of a sweep: its table, its figures, how to repeat it, where it came from (roads, grid,
inputs) and the base configuration every row starts from."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from truckmpc.plot.sweep_csv import axis_name
from truckmpc.report.figures import Figure, figures_html
from truckmpc.report.html import code_block, definitions, escape, section, table
from truckmpc.report.inputs import SweepDir
from truckmpc.report.replay import typed_line
from truckmpc.report.settings import is_sections, settings_html
from truckmpc.report.sweep_table import run_columns, shared_keys, sweep_columns, sweep_table_html
from truckmpc.sweep.columns import consumption_of_columns

__all__ = ["sweep_body", "sweep_title"]

_CONTENTS = (
    ("summary", "Summary"),
    ("figures", "Figures"),
    ("replay", "Repeat the sweep"),
    ("provenance", "Provenance"),
    ("configuration", "Configuration"),
)


def sweep_title(sweep: SweepDir) -> str:
    """The page's title: the roads and the grid's axes."""
    roads = sorted({str(row.get("road")) for row in sweep.rows})
    shown = ", ".join(roads[:3]) + (f" and {len(roads) - 3} more" if len(roads) > 3 else "")
    axes = ", ".join(_axes(sweep))
    return f"truckmpc sweep: {shown}" + (f" over {axes}" if axes else "")


def sweep_body(sweep: SweepDir, figures: list[Figure], missing: str | None) -> str:
    """The body of a sweep's page."""
    nav = " ".join(f'<a href="#{ident}">{escape(title)}</a>' for ident, title in _CONTENTS)
    shared = shared_keys(sweep.header, sweep.rows)
    columns = sweep_columns(sweep.header, _axes(sweep), tuple(shared))
    runs = run_columns(sweep.header, _axes(sweep), tuple(shared))
    caption = ", ".join(f"{key} {value}" for key, value in shared.items())
    used = consumption_of_columns(sweep.header)
    word = used.label
    lead = (
        f"{len(sweep.rows)} rows, one per road, direction, truck and combination of the grid. The figure to quote "
        f"is each look-ahead controller's saving at equal trip time and equal end speed: Δ{used.word} [%] = "
        "(controller − baseline) / baseline with the baseline re-run at the set speed that matches the controller's "
        f"trip time and both runs' end speeds corrected (negative means less {word} than the baseline), and the "
        f"{word} saved [{used.unit}]. As driven, the runs are compared as they ended."
    )
    base = sweep.settings.get("base_config")
    parts = [
        f"<h1>{escape(sweep_title(sweep))}</h1>\n",
        f'<p class="lead">{escape(lead)}</p>\n',
        f"<nav>{nav}</nav>\n",
        section(
            "summary",
            "Summary",
            sweep_table_html(sweep.rows, columns, caption)
            + sweep_table_html(sweep.rows, runs, f"{word.capitalize()} and trip time of each run", ident="runs-table"),
        ),
        section("figures", "Figures", figures_html(figures, missing)),
        section("replay", "Repeat the sweep", _replay_html(sweep)),
        section("provenance", "Provenance", _provenance_html(sweep.settings)),
        section("configuration", "Configuration", _configuration_html(base)),
    ]
    return "".join(parts)


def _axes(sweep: SweepDir) -> list[str]:
    grid = sweep.settings.get("grid")
    entries = grid if isinstance(grid, list) else []
    return [axis_name(g) for g in entries if isinstance(g, (str, Mapping))]


def _replay_html(sweep: SweepDir) -> str:
    out = sweep.path.resolve()
    typed = typed_line(sweep.settings.get("command"), new_out=out.with_name(out.name + "-replay"))
    if typed is None:
        return '<p class="note">This sweep did not record its command; its inputs are under Provenance.</p>\n'
    return (
        "<p>The command as it was given, in the directory it was given in, writing to a new directory "
        "(the same --out resumes the sweep there instead):</p>\n" + code_block(typed, ident="replay-command")
    )


def _provenance_html(settings: Mapping[str, Any]) -> str:
    roads = settings.get("roads") or []
    rows = [
        [
            str(r.get("name")),
            str(r.get("direction")),
            str(r.get("path") or "the bundled test track"),
            str(r.get("sha256")),
        ]
        for r in roads
        if isinstance(r, Mapping)
    ]
    grid = settings.get("grid") or []
    program = settings.get("program") or {}
    facts = {
        "program": f"{program.get('name', 'truckmpc')} {program.get('version', '')}".strip() or "not recorded",
        "grid": {axis_name(g): g.get("spec", g.get("values")) for g in grid if isinstance(g, Mapping)} or "none",
        "vehicle files": settings.get("vehicle") or "none (the packaged 40 t truck)",
        "configuration files": settings.get("configs") or "none",
        "--set overrides": settings.get("overrides") or "none",
        "worker processes": settings.get("jobs"),
    }
    roads_table = table(["road", "direction", "file", "SHA-256"], rows, caption="Roads", css="roads")
    return f'<div class="wide">{roads_table}</div>' + definitions(facts)


def _configuration_html(base: Any) -> str:
    """The base configuration (every row's, before its grid values), one per vehicle in a fleet."""
    intro = "<p>The base configuration every row starts from; each row then sets its grid values.</p>\n"
    if is_sections(base):
        return intro + settings_html(base)
    if isinstance(base, Mapping):
        return intro + "".join(
            f"<h3>vehicle {escape(str(name))}</h3>\n" + settings_html(doc)
            for name, doc in base.items()
            if isinstance(doc, Mapping)
        )
    return '<p class="note">sweep.json records no base configuration.</p>\n'

"""The page of a run: the table, the figures, how to repeat the run, where it came from, and every
parameter it ran with."""

from __future__ import annotations

import base64
import json
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from truckmpc.compare import headline
from truckmpc.consumption import consumption_of
from truckmpc.report.figures import Figure, figures_html
from truckmpc.report.html import code_block, definitions, escape, section
from truckmpc.report.inputs import RunDir
from truckmpc.report.replay import replay_run, typed_line
from truckmpc.report.run_table import run_table_html
from truckmpc.report.settings import settings_html
from truckmpc.results.run_rows import NAMES, equal_time_of
from truckmpc.results.run_table import run_table

__all__ = ["run_body", "run_title"]

_CONTENTS = (
    ("summary", "Summary"),
    ("figures", "Figures"),
    ("replay", "Repeat the run"),
    ("provenance", "Provenance"),
    ("configuration", "Configuration"),
)


def run_title(run: RunDir) -> str:
    """The page's title: the road and the controllers."""
    return f"truckmpc run: {run.summary.get('road', run.path.name)} ({', '.join(run.controllers)})"


def run_body(run: RunDir, figures: list[Figure], missing: str | None) -> str:
    """The body of a run's page."""
    summary = run.summary
    model = run_table(summary)
    details = run_table(summary, verbose=True)
    nav = " ".join(f'<a href="#{ident}">{escape(title)}</a>' for ident, title in _CONTENTS)
    parts = [
        f"<h1>{escape(run_title(run))}</h1>\n",
        f'<p class="subtitle">{escape(model.heading)}</p>\n',
        _lead(_headline(summary)),
        f"<nav>{nav}</nav>\n",
        section(
            "summary",
            "Summary",
            run_table_html(model, ident="run-table")
            + "<details><summary>Solver statistics and the equal-time search</summary>\n"
            + run_table_html(details)
            + "</details>\n",
        ),
        section("figures", "Figures", figures_html(figures, missing)),
        section("replay", "Repeat the run", _replay_html(run)),
        section("provenance", "Provenance", definitions(_provenance(summary["run"], run.path))),
        section("configuration", "Configuration", settings_html(summary["run"]["settings"]) + _download(summary)),
    ]
    return "".join(parts)


def _lead(lines: list[str]) -> str:
    """The headline sentences in one box at the top of the page."""
    if not lines:
        return ""
    return '<div class="lead">' + "".join(f"<p>{escape(line)}</p>" for line in lines) + "</div>\n"


def _headline(summary: Mapping[str, Any]) -> list[str]:
    """One sentence per comparison, those against the PCC first, then the MPC's: how much less (or
    more) fuel at equal trip time and equal end speed (the headline, with the kilograms saved), else
    as driven."""
    comparisons = [c for c in summary.get("comparisons") or () if isinstance(c, Mapping)]
    comparisons.sort(key=lambda c: (c.get("baseline") != "pcc", c.get("controller") != "mpc"))
    lines = []
    for comparison in comparisons:
        run, base = (NAMES.get(str(comparison.get(k)), str(comparison.get(k))) for k in ("controller", "baseline"))
        quoted = comparison_headline(summary, comparison)
        c = consumption_of(summary.get(str(comparison.get("controller"))) or {})
        what = c.label
        if quoted is not None:
            pct, amount = quoted
            word = "less" if pct < 0 else "more"
            saved = f"{amount:.3f} {c.unit} saved" if amount >= 0 else f"{-amount:.3f} {c.unit} more"
            lines.append(
                f"The {run} uses {abs(pct):.2f} % {word} {what} than the {base} at equal trip time and equal end "
                f"speed ({saved})."
            )
        elif isinstance(delta := comparison.get(c.delta_key()), (int, float)):
            word = "less" if delta < 0 else "more"
            lines.append(f"The {run} uses {abs(delta):.2f} % {word} {what} than the {base} as driven.")
    return lines


def comparison_headline(summary: Mapping[str, Any], comparison: Mapping[str, Any]) -> tuple[float, float] | None:
    """A comparison's headline, (Δfuel [%], fuel saved [kg]; battery energy and kWh for a
    battery-electric truck), from the summary's figures: its
    controller's end-speed-corrected fuel and its baseline's re-run at the controller's trip time
    (its ``equal_time`` object), through :func:`truckmpc.compare.headline`; None where there is none."""
    run, base = str(comparison.get("controller")), str(comparison.get("baseline"))
    equal, own = equal_time_of(summary, run, base), summary.get(run)
    c = consumption_of(own if isinstance(own, Mapping) else {})
    quoted = headline(
        own.get(c.corrected_key) if isinstance(own, Mapping) else None, equal.get(f"{base}_{c.corrected_key}")
    )
    if comparison.get("not_comparable") or quoted.pct is None or quoted.saved is None:
        return None
    return quoted.pct, quoted.saved


def _replay_html(run: RunDir) -> str:
    parts = [
        "<p>Every resolved parameter, from this run's summary.json (the road file must still be the one that "
        "was run: its SHA-256 is checked):</p>\n",
        code_block(replay_run(run.path), ident="replay-command"),
    ]
    typed = typed_line(run.summary["run"].get("command"))
    if typed is not None:
        parts += [
            "<p>The command as it was given, in the directory it was given in:</p>\n",
            code_block(typed, ident="typed-command"),
        ]
    return "".join(parts)


def _provenance(record: Mapping[str, Any], directory: Path) -> dict[str, Any]:
    """What the run record says about where the run came from, in the words of a reader."""
    road = record.get("road") or {}
    inputs = record.get("inputs") or {}
    program = record.get("program") or {}
    told = record.get("controller_road")
    return {
        "run directory": str(directory.resolve()),
        "program": f"{program.get('name', 'truckmpc')} {program.get('version', '')}".strip(),
        "road": road.get("name"),
        "road file": road.get("path") or "the bundled test track",
        "road SHA-256": road.get("sha256"),
        "road length [km]": road["length_m"] / 1000 if isinstance(road.get("length_m"), (int, float)) else None,
        "direction": "reversed" if road.get("reverse") else "as in the file",
        "map the controllers planned on": told if told else "the road driven",
        "controllers": ", ".join(map(str, record.get("controllers") or ())),
        "convergence check": record.get("check_convergence"),
        "vehicle file": inputs.get("vehicle") or "none (the packaged 40 t truck)",
        "configuration files": inputs.get("configs") or "none",
        "--set overrides": inputs.get("overrides") or "none",
        "VECTO truck": record.get("vehicle") or "none",
    }


def _download(summary: Mapping[str, Any]) -> str:
    """The whole summary.json, to read here or save (and replay with ``simulate --replay``)."""
    text = json.dumps(summary, indent=2)
    data = base64.b64encode(text.encode("utf-8")).decode("ascii")
    return (
        f'<p><a download="summary.json" href="data:application/json;base64,{data}">Save summary.json</a> '
        "(every figure and parameter of the run, as written by truckmpc simulate).</p>\n"
        f"<details><summary>summary.json</summary><pre><code>{escape(text)}</code></pre></details>\n"
    )

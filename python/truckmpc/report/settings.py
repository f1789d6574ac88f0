"""The resolved configuration on the page: one table per section (vehicle, cruise, pi, mpc, pcc,
sim), each parameter with its value, unit and meaning from the declarations, and its default beside
it where the run's value differs."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from truckmpc.config import SPEC_BY_KEY
from truckmpc.config.docs import SECTION_TITLES
from truckmpc.report.html import escape, scalar_text

__all__ = ["is_sections", "settings_html"]


def is_sections(doc: Any) -> bool:
    """Whether `doc` is one resolved configuration (section -> key -> value), not one per vehicle."""
    return isinstance(doc, Mapping) and all(
        isinstance(v, Mapping) and all(k in SPEC_BY_KEY for k in v) for v in doc.values()
    )


def settings_html(settings: Mapping[str, Any]) -> str:
    """Every section of a resolved configuration as a table; values that are not the declared
    default are marked and show the default."""
    parts = []
    for section, values in settings.items():
        if not isinstance(values, Mapping):
            continue
        title = " ".join(SECTION_TITLES.get(section, "").replace("\n#", " ").split())
        parts.append(f'<h3 id="settings-{escape(section)}">{escape(section)}</h3>\n')
        if title:
            parts.append(f'<p class="note">{escape(title)}</p>\n')
        parts.append(_section_table(values))
    return "".join(parts)


def _section_table(values: Mapping[str, Any]) -> str:
    rows = []
    for key, value in values.items():
        spec = SPEC_BY_KEY.get(key)
        unit = spec.unit if spec is not None else ""
        doc = spec.doc if spec is not None else ""
        changed = spec is not None and not _same(value, spec.default)
        shown = escape(scalar_text(value))
        if changed and spec is not None:
            shown += f' <span class="note">(default {escape(scalar_text(spec.default))})</span>'
        cls = ' class="changed"' if changed else ""
        rows.append(
            f'<tr><th scope="row"><code>{escape(key)}</code></th><td{cls}>{shown}</td>'
            f"<td>{escape(unit)}</td><td>{escape(doc)}</td></tr>\n"
        )
    head = "<thead><tr><th>parameter</th><th>value</th><th>unit</th><th>meaning</th></tr></thead>"
    cols = '<colgroup><col class="key"><col class="value"><col class="unit"><col></colgroup>'
    return f'<table class="settings">{cols}{head}<tbody>\n{"".join(rows)}</tbody></table>\n'


def _same(value: Any, default: Any) -> bool:
    """Whether a recorded value is the declared default (numbers compared as numbers)."""
    if isinstance(value, (list, tuple)) and isinstance(default, (list, tuple)):
        return len(value) == len(default) and all(_same(a, b) for a, b in zip(value, default, strict=True))
    numbers = (int, float)
    if isinstance(value, numbers) and isinstance(default, numbers) and not isinstance(value, bool):
        return float(value) == float(default)
    return bool(value == default)

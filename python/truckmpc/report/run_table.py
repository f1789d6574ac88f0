"""A run's table (:func:`truckmpc.results.run_table.run_table`, the model the ``simulate`` table is
printed from) as an HTML table: one column per controller, its sections as titled row groups, the
headline section first and in bold, its notes under it."""

from __future__ import annotations

from truckmpc.report.html import escape
from truckmpc.results.run_table import RunTable

__all__ = ["run_table_html"]


def run_table_html(model: RunTable, *, ident: str = "") -> str:
    """`model` as a ``<table>`` and its notes as paragraphs under it."""
    head = '<th scope="col"></th>' + "".join(f'<th scope="col">{escape(name)}</th>' for name in model.columns)
    span = len(model.columns) + 1
    body = []
    for section in model.sections:
        if section.title:
            body.append(f'<tr class="group"><th colspan="{span}">{escape(section.title)}</th></tr>\n')
        css = "" if section.title else ' class="headline"'
        for row in section.rows:
            label = f"{row.label} [{row.unit}]" if row.unit else row.label
            cells = "".join(f"<td>{escape(cell)}</td>" for cell in row.cells)
            body.append(f'<tr{css}><th scope="row">{escape(label)}</th>{cells}</tr>\n')
    attr = f' id="{escape(ident)}"' if ident else ""
    notes = "".join(f'<p class="note">{escape(note)}</p>\n' for note in model.notes)
    return (
        f'<div class="wide"><table class="numbers"{attr}><thead><tr>{head}</tr></thead>\n'
        f"<tbody>\n{''.join(body)}</tbody></table></div>\n{notes}"
    )
